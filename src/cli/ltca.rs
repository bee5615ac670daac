//! `flank ltca`: compliance-matrix LTCA over a mesh cycle.

use std::path::PathBuf;

use anyhow::{Context, Result};

use crate::cli::common::{contact_ratio_line, print_wet_dry_loop, SectorArgs};
use flank::ltca::summary::{KindSummary, LtcaSummary};

#[derive(clap::Args)]
pub struct Args {
    /// The scene file (.toml).
    scene: PathBuf,
    /// Output directory.
    #[arg(long, default_value = "out")]
    out: PathBuf,
    /// Compliance mesh (default m_n/8 flank, m_n/2 base).
    #[command(flatten)]
    sizes: SectorArgs,
    /// Roll angles (deg, flank's convention), comma-separated.
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    roll_angles: Option<Vec<f64>>,
    /// K: candidate points per contact line.
    #[arg(long)]
    points_per_line: Option<usize>,
    /// QP solver: active-set or clarabel.
    #[arg(long)]
    solver: Option<String>,
    /// Local contact deformation model.
    #[arg(long, value_enum)]
    local: Option<flank::settings::LocalModel>,
    /// FE cell half-width across the line in flank element sizes.
    #[arg(long)]
    fe_cell_factor: Option<f64>,
    /// A campaign cache of compliance tensors (directory).
    #[arg(long)]
    cache: Option<PathBuf>,
    /// Skip the condition number of F at every position (reported by
    /// default; not part of the timed solve).
    #[arg(long)]
    no_condition: bool,
    /// Threads (0 = all cores).
    #[arg(long, default_value_t = 0)]
    threads: usize,
    /// Bevel/hypoid pairs: the candidate axis runs out to this unloaded
    /// separation (mm; default 0.04).
    #[arg(long)]
    span_approach_mm: Option<f64>,
    /// Coulomb friction coefficient of the flanks (seeds 001/003; 0 =
    /// frictionless; default the scene's `[analyses.ltca] friction_mu`;
    /// refused with `[analyses.lubrication]`, whose loop sets μ).
    #[arg(long)]
    friction_mu: Option<f64>,
    /// Load increments of the frictional solve (default 10).
    #[arg(long)]
    increments: Option<usize>,
    /// Also solve every position by Lemke's method and report the largest
    /// difference from the clarabel path.
    #[arg(long)]
    cross_check: bool,
    /// What the friction resists: incremental (seeds 001/003, default),
    /// standstill (the mate held, as one static FE contact step) or
    /// sliding (the running mesh: μP_n against the kinematic sliding;
    /// the default of the lubricated loop).
    #[arg(long, value_enum)]
    friction_model: Option<flank::settings::FrictionModel>,
    /// Bevel/hypoid pairs: LTCA with the TCA's edge contacts as candidates,
    /// without them, or both (seed 000; default the scene's
    /// `[analyses.ltca] edges`, else without).
    #[arg(long, value_enum)]
    edges: Option<flank::settings::EdgeVariants>,
    /// Spur/helical pairs: the flank nodes the compliance tensors cover:
    /// active (default: from the start of active profile, which the
    /// mating tip sets, to the tip, plus a margin of 2 flank elements +
    /// 1 mm down the profile; the fillet below is left out) or full
    /// (involute and root fillet); default the scene's
    /// `[analyses.ltca] flank_region`, else active.
    #[arg(long, value_enum)]
    flank_region: Option<flank::settings::FlankRegion>,
    /// Spur/helical, frictionless: `none` (dense tensors) or a relative
    /// accuracy ε in (0, 1), e.g. 1e-6, to build the tensors in block
    /// low-rank form (each block within ε of its Frobenius norm) panel by
    /// panel from the body's factor, without the dense tensor, and read
    /// the LTCA's page pairs from it; default the scene's
    /// `[analyses.ltca] compression`, else none.
    #[arg(long)]
    compression: Option<String>,
    /// Pinion torques (N·m, comma-separated) of the map over torque: the
    /// LTCA over one mesh pitch at each, TE peak-to-peak, mesh-order
    /// harmonics and mesh stiffness (`ltca_torque_map.csv`, `.svg`);
    /// default the scene's `[analyses.ltca] torques_nm`, else no map.
    #[arg(long, value_delimiter = ',')]
    torques: Option<Vec<f64>>,
    /// Print nothing but errors.
    #[arg(long, short)]
    quiet: bool,
}

pub fn run(args: Args) -> Result<()> {
    use flank::ltca::cycle::LtcaOptions;
    use flank::ltca::run::run;
    let Args {
        scene,
        out,
        sizes,
        roll_angles,
        points_per_line,
        solver,
        local,
        fe_cell_factor,
        cache,
        no_condition,
        threads,
        span_approach_mm,
        friction_mu,
        increments,
        cross_check,
        friction_model,
        edges,
        flank_region,
        compression,
        torques,
        quiet,
    } = args;
    let compression = match compression {
        Some(c) => Some(
            c.parse::<flank::settings::Compression>()
                .map_err(|e| anyhow::anyhow!("--compression: {e}"))?,
        ),
        None => None,
    };
    let solver = match solver {
        Some(s) => Some(
            s.parse::<flank::settings::QpSolver>()
                .map_err(|e| anyhow::anyhow!("--solver: {e}"))?,
        ),
        None => None,
    };
    let options = LtcaOptions {
        out: out.clone(),
        mesh: sizes.body_options(false),
        roll_angles_deg: roll_angles,
        points_per_line,
        solver,
        local,
        fe_cell_factor,
        cache,
        condition: !no_condition,
        threads,
        quiet,
        friction_mu,
        increments,
        cross_check,
        friction_model,
        flank_region,
        compression,
        span_approach_mm,
        edges,
        // a bevel pair's grid: the scene's `[analyses.ltca] positions`
        positions: None,
        torques_nm: torques,
    };
    let read = flank::scene::read_scene(&scene)?;
    let result =
        run(&read, &options).with_context(|| format!("LTCA mesh cycle of {}", scene.display()))?;
    if quiet {
        return Ok(());
    }
    for (name, s) in result.cycles() {
        if let Some(name) = name {
            println!("{name}:");
        }
        print_cycle(s);
    }
    println!("wrote {}", out.display());
    Ok(())
}

/// The lines `flank ltca` prints of one cycle.
fn print_cycle(s: &LtcaSummary) {
    match &s.kind {
        KindSummary::Bevel(b) => {
            println!(
                "{} positions, K = {} per major axis: {:.3} s for the cycle ({:.1} ms per position); tensors {:.1} s, TCA {:.2} s",
                s.positions,
                b.points_per_pair,
                s.cycle_s,
                1e3 * s.time_per_position_s,
                b.compliance_s,
                b.tca_s
            );
            println!(
                "loaded TE {:.2} arcsec peak-to-peak (gear; {:.1} µrad at the pinion); largest contact pressure {:.0} MPa; max KKT residual {:.1e}",
                s.te_peak_to_peak_arcsec, s.te_peak_to_peak_urad, s.max_pressure_mpa, s.max_kkt
            );
            if let Some(sharing) = &b.load_sharing {
                println!(
                    "functional contact ratio {:.3} (pairs loaded above {} % of the force: {}…{}; single-pair zone {:.2}° of roll)",
                    sharing.functional_contact_ratio,
                    100.0 * sharing.loaded_share_threshold,
                    sharing.min_loaded_pairs,
                    sharing.max_loaded_pairs,
                    sharing.single_pair_span_deg
                );
            }
        }
        KindSummary::Cylindrical(c) => {
            println!(
                "{} positions, K = {}: {:.4} s for the cycle ({:.2} ms per position); compliance {:.1} s",
                s.positions,
                c.points_per_line,
                s.cycle_s,
                1e3 * s.time_per_position_s,
                c.setup.compliance_s
            );
            println!(
                "{}; max KKT residual {:.1e}",
                contact_ratio_line(
                    c.contact_ratio,
                    c.contact_ratio_kinematic,
                    c.single_pair_force_n,
                    c.nominal_force_n,
                    c.single_pair_force_error,
                ),
                s.max_kkt
            );
        }
    }
    print_spectra(s);
    if let Some(fr) = &s.friction {
        println!(
                "friction μ = {}: P_t/P_n {:.4}, mean friction power {:.1} W, mesh efficiency {:.4}; largest Coulomb residual {:.1e}{}",
                fr.mu,
                fr.tangential_to_normal,
                fr.mean_power_loss_w,
                fr.mesh_efficiency,
                fr.max_residual,
                match fr.cross_check_max_load_difference {
                    Some(d) => format!(", Lemke cross-check {d:.1e}"),
                    None => String::new(),
                }
            );
    }
    if let Some(l) = &s.lubrication {
        print_wet_dry_loop(l);
    }
    for n in &s.notes {
        println!("note: {n}");
    }
    if let KindSummary::Cylindrical(c) = &s.kind {
        for n in &c.kkt_flagged {
            println!("flagged: {n}");
        }
    }
}

/// The TE harmonics, mesh stiffness and the map over torque of a cycle.
fn print_spectra(s: &LtcaSummary) {
    use flank::summary::Measured;
    match &s.te_harmonics {
        Measured::Figures(h) => println!(
            "loaded TE mesh orders 1-5 over {} positions ({} pitch): {} µrad",
            h.positions,
            h.pitches,
            h.harmonics
                .iter()
                .map(|x| format!("{:.3}", x.amplitude_urad))
                .collect::<Vec<_>>()
                .join(" / ")
        ),
        Measured::NotMeasured { not_measured } => {
            println!("TE harmonics of the cycle not measured: {not_measured}")
        }
    }
    if let Measured::Figures(k) = &s.mesh_stiffness {
        println!(
            "mesh stiffness {:.1} N/µm mean ({:.1} … {:.1}){}",
            k.mean_n_per_um,
            k.min_n_per_um,
            k.max_n_per_um,
            k.mean_n_per_mm_um
                .map(|x| format!(", {x:.2} N/(mm·µm)"))
                .unwrap_or_default()
        );
    }
    if let Some(m) = &s.torque_map {
        println!(
            "map over torque ({} positions per torque, {:.1} s):",
            m.roll_deg.len(),
            m.time_s
        );
        for p in &m.torques {
            let first = p
                .harmonics
                .figures()
                .map(|h| format!("{:.3} µm", h.harmonics[0].amplitude_um))
                .unwrap_or_else(|| "not measured".into());
            let k = p
                .mesh_stiffness
                .figures()
                .map(|k| format!("{:.1} N/µm", k.mean_n_per_um))
                .unwrap_or_else(|| "not measured".into());
            println!(
                "  {} N·m: TE p-p {:.3} µm ({:.2} µrad), first order {first}, mean mesh stiffness {k}",
                p.torque_nm, p.te_peak_to_peak_um, p.te_peak_to_peak_urad
            );
        }
    }
}
