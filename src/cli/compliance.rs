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
        if let Some(bodies) = summary["bodies"].as_object() {
            for (name, b) in bodies {
                let s = &b["stats"];
                if s.is_null() {
                    println!(
                        "{name}: {} flank nodes, C {}×{} reused ({}, same cache key): {}",
                        b["flank_nodes"],
                        b["matrix_dim"],
                        b["matrix_dim"],
                        b["source"].as_str().unwrap_or(""),
                        b["file"].as_str().unwrap_or("")
                    );
                    continue;
                }
                let line = match b["contact_line"]["condition"].as_f64() {
                    Some(k) => format!(", C_nn on the pitch line κ = {k:.3e}"),
                    None => String::new(),
                };
                println!(
                    "{name}: {} flank nodes, C {}×{} ({}); factorization {:.2} s, solve {:.2} s ({:.2}× its own factorization), κ(C) ≈ {:.3e}{line}; {}",
                    b["flank_nodes"],
                    b["matrix_dim"],
                    b["matrix_dim"],
                    b["source"].as_str().unwrap_or(""),
                    s["factorization_s"].as_f64().unwrap_or(0.0),
                    s["solve_s"].as_f64().unwrap_or(0.0),
                    s["time_vs_factorization"].as_f64().unwrap_or(0.0),
                    s["condition"]["kappa"].as_f64().unwrap_or(f64::NAN),
                    b["file"].as_str().unwrap_or("")
                );
            }
            for (name, b) in bodies {
                let m = &b["mean_contact"];
                if m.is_null() {
                    continue;
                }
                if let Some(why) = m["error"].as_str() {
                    println!("{name}: no directional compliances at the mean contact: {why}");
                    continue;
                }
                let r = &m["report"];
                let f = |k: &str| r[k].as_f64().unwrap_or(f64::NAN);
                println!(
                    "{name}: mean contact (roll 0, {} points on the major axis, a = {:.3} mm): c_nn {:.4e}, c_tt {:.4e}, c_nt {:.4e}, c_tn {:.4e} mm/N; C_nn κ = {:.3e}, reciprocity {:.1e}",
                    r["points"],
                    m["semi_major_mm"].as_f64().unwrap_or(f64::NAN),
                    f("c_nn"),
                    f("c_tt"),
                    f("c_nt"),
                    f("c_tn"),
                    f("condition"),
                    f("reciprocity")
                );
            }
        }
        println!("wrote {}", out.display());
    }
    Ok(())
}
