//! `flank run`: FE contact over a mesh cycle.

use std::path::PathBuf;

use anyhow::{Context, Result};

use flank::mesh_cycle::summary::{BevelRun, CylindricalRun, RunKind, RunSummary};

use crate::cli::common::{contact_ratio_line, print_wet_dry_loop, SectorArgs};

#[derive(clap::Args)]
pub struct Args {
    /// The scene file (.toml).
    scene: PathBuf,
    /// Output directory.
    #[arg(long, default_value = "out")]
    out: PathBuf,
    #[command(flatten)]
    sizes: SectorArgs,
    /// Roll angles (deg, flank's convention: 0 = middle pair at the pitch
    /// point), comma-separated; overrides the scene's.
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    roll_angles: Option<Vec<f64>>,
    /// Roll angles in the scene's reference convention
    /// (reference_single_contact_start_deg, e.g. the paper's angles).
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    reference_angles: Option<Vec<f64>>,
    /// Normal contact law; overrides the scene's.
    #[arg(long, value_enum)]
    law: Option<flank::settings::ContactLaw>,
    /// Penalty slope as a multiple of the automatic default.
    #[arg(long)]
    penalty_factor: Option<f64>,
    /// Body carrying the slave nodes (auto: the body whose tip edge can touch,
    /// per tooth pair and position); overrides the scene's.
    #[arg(long, value_enum)]
    slave: Option<flank::settings::SlaveBody>,
    /// Coulomb friction coefficient of the flanks (0…1); overrides the
    /// scene's friction_mu.
    #[arg(long)]
    friction_mu: Option<f64>,
    /// Write no VTU files.
    #[arg(long)]
    no_vtu: bool,
    /// Also write a CalculiX deck per position (roll_<angle>deg.inp):
    /// the pair model at its placed coordinates, for ccx.
    #[arg(long)]
    decks: bool,
    /// Do not bisect the middle pair's contact limits.
    #[arg(long)]
    no_refine: bool,
    /// Threads (0 = all cores).
    #[arg(long, default_value_t = 0)]
    threads: usize,
    /// Print nothing but errors.
    #[arg(long, short)]
    quiet: bool,
    /// Contact band (mm): per roll angle (--roll-angles, required), mesh
    /// both bodies with involute rows of this size around that position's
    /// kinematic contact points (± --band-half-width Hertz half-widths),
    /// solve, and report p_max against Hertz p₀ and the elements across 2b
    /// (OUT/contact_band.json). Spur pairs, frictionless hard contact.
    #[arg(long)]
    contact_band: Option<f64>,
    /// Band half-width as a multiple of the nominal Hertz half-width b.
    #[arg(long, default_value_t = 2.5)]
    band_half_width: f64,
    /// Resume an interrupted run: take the positions kept in
    /// OUT/checkpoint.json (same scene and options) and solve only the
    /// others. Ctrl-C (SIGINT) stops a run at the next position boundary
    /// and keeps what is solved; a second Ctrl-C ends it at once.
    #[arg(long)]
    resume: bool,
}

pub fn run(args: Args) -> Result<()> {
    use flank::mesh_cycle::run::{run, run_scene, RunOptions};
    let Args {
        scene,
        out,
        sizes,
        roll_angles,
        reference_angles,
        law,
        penalty_factor,
        slave,
        friction_mu,
        no_vtu,
        decks,
        no_refine,
        threads,
        quiet,
        resume,
        contact_band,
        band_half_width,
    } = args;
    if let Some(size) = contact_band {
        let rolls = roll_angles.ok_or_else(|| {
            anyhow::anyhow!("--contact-band needs --roll-angles (the bands follow each position's contact points)")
        })?;
        let sc = flank::scene::read_scene(&scene)?;
        let options = flank::mesh_cycle::contact_band::BandOptions {
            size_mm: Some(size),
            half_width_b: band_half_width,
            mesh: sizes.body_options(false),
            face_layers: 0,
            threads,
        };
        let res = flank::mesh_cycle::contact_band::run_contact_band(&sc, &rolls, &options)
            .with_context(|| format!("contact-band FE contact of {}", scene.display()))?;
        std::fs::create_dir_all(&out)?;
        std::fs::write(
            out.join("contact_band.json"),
            serde_json::to_string_pretty(&res)?,
        )?;
        if !quiet {
            for r in &res {
                println!(
                    "{:.3}°: {} DOFs, min scaled J {:.3}, max aspect {:.1}, setup {:.1} s, solve {:.1} s, peak {:.0} MB, TE {:.2} µrad",
                    r.roll_deg, r.dofs, r.min_scaled_jacobian, r.max_aspect_ratio, r.setup_s, r.solve_s, r.peak_memory_mb, r.te_urad
                );
                for p in r.pairs.iter().filter(|p| p.force_n > 0.0) {
                    println!(
                        "  pair {}: F {:.1} N (share {:.4}), p_max {:.1} MPa (mid face {:.1}), Hertz p0 {} MPa, elements across 2b {}",
                        p.pinion_tooth,
                        p.force_n,
                        p.load_share,
                        p.p_max_mpa,
                        p.p_max_mid_face_mpa,
                        p.hertz_p0_mpa.map_or("-".into(), |v| format!("{v:.1}")),
                        p.elements_across_2b.map_or("-".into(), |v| format!("{v:.1}"))
                    );
                }
            }
            println!("wrote {}", out.join("contact_band.json").display());
        }
        return Ok(());
    }
    let options = RunOptions {
        out: out.clone(),
        mesh: sizes.body_options(false),
        threads,
        roll_angles_deg: roll_angles,
        reference_angles_deg: reference_angles,
        law,
        penalty_factor,
        slave,
        friction_mu,
        vtu: no_vtu.then_some(false),
        decks,
        refine_contact_limits: no_refine.then_some(false),
        quiet,
        resume,
    };
    // the first Ctrl-C stops at the next position boundary
    flank::interrupt::install_sigint_handler()?;
    let read = flank::scene::read_scene(&scene)?;
    if read.is_bevel() {
        let s = run(&read, &options)
            .with_context(|| format!("FE contact of the hypoid pair of {}", scene.display()))?;
        if !quiet {
            if let RunKind::Bevel(b) = &s.kind {
                print_bevel(&s, b);
            }
            println!("wrote {}", out.display());
        }
        return Ok(());
    }
    let s = run_scene(&scene, &options)
        .with_context(|| format!("FE contact mesh cycle of {}", scene.display()))?;
    if !quiet {
        if let RunKind::Cylindrical(c) = &s.kind {
            print_cylindrical(&s, c);
        }
        println!("wrote {}", out.display());
    }
    Ok(())
}

/// A figure as the printed summary shows it: NaN where summary.json has
/// null (a figure not measured, or not finite).
fn shown(v: f64) -> f64 {
    if v.is_finite() {
        v
    } else {
        f64::NAN
    }
}

/// What `flank run` prints of a spur/helical run's summary.
fn print_cylindrical(s: &RunSummary, c: &CylindricalRun) {
    println!(
        "{} positions, {} nodes, {} DOFs; factorization {:.2} s once, {:.2} s per position; peak {:.0} MB",
        s.positions,
        s.nodes,
        s.dofs,
        shown(s.factorization_s),
        shown(s.time_per_position_s),
        shown(s.peak_memory_mb)
    );
    println!(
        "{}; TE peak-to-peak {:.2} µrad",
        contact_ratio_line(
            c.contact_ratio,
            shown(c.contact_ratio_kinematic),
            c.single_pair_force_n,
            shown(c.nominal_force_n),
            c.single_pair_force_error,
        ),
        shown(s.te_peak_to_peak_urad)
    );
    // the law as summary.json writes it
    println!(
        "contact law: {}",
        serde_json::to_value(s.law).unwrap_or_default()
    );
    if let Some(l) = &c.lubrication {
        print_wet_dry_loop(l);
    }
    for n in &s.notes {
        println!("note: {n}");
    }
    let w = s.warnings.len();
    if w > 0 {
        println!("{w} warning(s) in summary.json");
    }
}

/// What `flank run` prints of a bevel/hypoid run's summary.
fn print_bevel(s: &RunSummary, b: &BevelRun) {
    println!(
        "{} positions, {} nodes, {} DOFs; factorization {:.2} s once, {:.2} s per position",
        s.positions,
        s.nodes,
        s.dofs,
        shown(s.factorization_s),
        shown(s.time_per_position_s)
    );
    println!(
        "TE peak-to-peak {:.2} arcsec; largest contact pressure {:.0} MPa; moment balance {:.1e}",
        shown(s.te_peak_to_peak_arcsec),
        shown(b.max_pressure_mpa),
        shown(b.max_moment_balance)
    );
    for w in &s.warnings {
        println!("warning: {w}");
    }
    let pen = shown(b.largest_unloaded_interpenetration_mm);
    if pen > 1e-3 {
        println!(
            "warning: the unloaded flanks interpenetrate by up to {pen:.4} mm in the nominal placement (positions.csv: min_initial_gap_mm); the loaded TE contains the unloaded TE this resolves"
        );
    }
}
