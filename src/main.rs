//! The `flank` command line: parses, calls the library, prints.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::{Parser, Subcommand};

use flank::fem::ordering::OrderingMethod;
use flank::fem::static_analysis::{solve_static, SolveOptions};

#[derive(Parser)]
#[command(name = "flank", version, about = "Finite-element-first gear tooth contact: native 3D elasticity, FE contact, LTCA")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Solve a CalculiX/Abaqus linear static deck (C3D20, C3D20R, C3D15).
    Solve {
        /// The input deck (.inp).
        deck: PathBuf,
        /// Output directory (displacements.csv, stresses.csv, reactions.csv, result.vtu, summary.json).
        #[arg(long, default_value = "out")]
        out: PathBuf,
        /// Fill-reducing ordering for the Cholesky factorization.
        #[arg(long, value_enum, default_value_t = OrderingMethod::Metis)]
        ordering: OrderingMethod,
        /// Threads (0 = all cores).
        #[arg(long, default_value_t = 0)]
        threads: usize,
        /// Skip stress recovery and reactions.
        #[arg(long)]
        no_stress: bool,
        /// No progress display.
        #[arg(long, short)]
        quiet: bool,
    },
}

fn main() -> std::process::ExitCode {
    match run(Cli::parse()) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            // the whole context chain, no backtrace: the message says what and where
            eprintln!("error: {e:#}");
            std::process::ExitCode::FAILURE
        }
    }
}

fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Solve {
            deck,
            out,
            ordering,
            threads,
            no_stress,
            quiet,
        } => {
            if threads > 0 {
                rayon::ThreadPoolBuilder::new().num_threads(threads).build_global().ok();
            }
            let parsed = flank::mesh::inp::read_deck(&deck)?;
            for w in &parsed.warnings {
                eprintln!("warning: {}:{}: {}", deck.display(), w.line, w.message);
            }
            let options = SolveOptions {
                ordering,
                threads,
                recover_stress: !no_stress,
                progress: !quiet,
            };
            let sol = solve_static(&parsed.model, &options).with_context(|| format!("solving {}", deck.display()))?;
            let extra = serde_json::json!({
                "deck": deck.display().to_string(),
                "warnings": parsed.warnings.len(),
            });
            flank::report::solution::write_solution(&out, &parsed.model, &sol, extra)?;
            let s = &sol.stats;
            if !quiet {
                println!(
                    "{} nodes, {} elements, {} DOFs; nnz(L) = {} ({}); assembly {:.3} s, ordering {:.3} s, factorization {:.3} s ({:.1} GFLOP/s), solve {:.3} s; residual {:.1e}; peak memory {:.0} MB",
                    s.nodes, s.elements, s.dofs, s.nnz_factor, s.ordering, s.assembly_s, s.ordering_s, s.factorization_s, s.factorization_gflops, s.solve_s, s.relative_residual, s.peak_memory_mb
                );
                println!("results in {}", out.display());
            }
        }
    }
    Ok(())
}
