//! `flank compliance`: nodal compliance tensors of a scene's gear bodies.

use std::path::PathBuf;

use anyhow::{Context, Result};

use crate::cli::common::SectorArgs;

#[derive(clap::Args)]
pub struct Args {
    /// The scene file (.toml).
    scene: PathBuf,
    /// Output directory.
    #[arg(long, default_value = "out")]
    out: PathBuf,
    #[command(flatten)]
    sizes: SectorArgs,
    /// Bodies, comma-separated.
    #[arg(long, value_delimiter = ',', default_values_t = ["pinion".to_string(), "gear".to_string()])]
    bodies: Vec<String>,
    /// Method (schur: flank DOFs ordered last, fastest; blocked:
    /// unit right-hand sides); overrides [analyses.compliance].
    #[arg(long, value_enum)]
    method: Option<flank::settings::Method>,
    /// Flanks carrying tensors; overrides [analyses.compliance].
    #[arg(long, value_enum)]
    flanks: Option<flank::settings::FlankSelection>,
    /// Part of each flank carrying tensors: full (involute and root
    /// fillet) or active (spur/helical: from the start of active profile,
    /// which the mating tip sets, to the tip, plus a margin of 2 flank
    /// elements + 1 mm down the profile); overrides
    /// [analyses.compliance] flank_region, default full.
    #[arg(long, value_enum)]
    flank_region: Option<flank::settings::FlankRegion>,
    /// Clamp the sector cut faces CUT_A and CUT_B as well as the bore.
    #[arg(long)]
    clamp_cuts: bool,
    /// Threads (0 = all cores).
    #[arg(long, default_value_t = 0)]
    threads: usize,
    /// Memory for the blocked method's right-hand sides (MB).
    #[arg(long)]
    memory_budget_mb: Option<f64>,
    /// Right-hand sides per block (blocked method; 0 = from the budget).
    #[arg(long, default_value_t = 0)]
    block_size: usize,
    /// Campaign cache directory: tensors kept by key and reused.
    #[arg(long)]
    cache: Option<PathBuf>,
    /// File format (default: hdf5 with the feature, else native).
    #[arg(long, value_enum)]
    format: Option<flank::compliance::FileFormat>,
    /// Skip the condition-number estimate of C.
    #[arg(long)]
    no_condition: bool,
    /// Write the decks without the nominal load (as `flank mesh --no-load`).
    #[arg(long)]
    no_load: bool,
    /// Print nothing but errors.
    #[arg(long, short)]
    quiet: bool,
}

pub fn run(args: Args) -> Result<()> {
    use flank::compliance::run::{run_scene, RunOptions};
    let Args {
        scene,
        out,
        sizes,
        bodies,
        method,
        flanks,
        flank_region,
        clamp_cuts,
        threads,
        memory_budget_mb,
        block_size,
        cache,
        format,
        no_condition,
        no_load,
        quiet,
    } = args;
    let options = RunOptions {
        out: out.clone(),
        mesh: sizes.body_options(!no_load),
        bodies,
        method,
        flanks,
        clamp_cuts,
        threads,
        memory_budget_mb,
        block_size,
        cache,
        format,
        condition: !no_condition,
        region: flank_region,
    };
    let summary = run_scene(&scene, &options)
        .with_context(|| format!("compliance of {}", scene.display()))?;
    if !quiet {
        use flank::compliance::summary::MeanContact;
        for (name, b) in &summary.bodies {
            let (n, source, file) = (b.matrix_dim, b.source.name(), &b.file);
            let Some(s) = &b.stats else {
                println!(
                    "{name}: {} flank nodes, C {n}×{n} reused ({source}, same cache key): {file}",
                    b.flank_nodes
                );
                continue;
            };
            let line = match &b.contact_line {
                Some(c) => format!(", C_nn on the pitch line κ = {:.3e}", c.condition),
                None => String::new(),
            };
            let kappa = s.condition.as_ref().map_or(f64::NAN, |c| c.kappa);
            println!(
                "{name}: {} flank nodes, C {n}×{n} ({source}); factorization {:.2} s, solve {:.2} s ({:.2}× its own factorization), κ(C) ≈ {kappa:.3e}{line}; {file}",
                b.flank_nodes, s.factorization_s, s.solve_s, s.time_vs_factorization
            );
        }
        for (name, b) in &summary.bodies {
            match &b.mean_contact {
                None => {}
                Some(MeanContact::Missing { error }) => {
                    println!("{name}: no directional compliances at the mean contact: {error}")
                }
                Some(MeanContact::Probed(m)) => {
                    let r = &m.report;
                    println!(
                        "{name}: mean contact (roll 0, {} points on the major axis, a = {:.3} mm): c_nn {:.4e}, c_tt {:.4e}, c_nt {:.4e}, c_tn {:.4e} mm/N; C_nn κ = {:.3e}, reciprocity {:.1e}",
                        r.points, m.semi_major_mm, r.c_nn, r.c_tt, r.c_nt, r.c_tn, r.condition, r.reciprocity
                    );
                }
            }
        }
        println!("wrote {}", out.display());
    }
    Ok(())
}
