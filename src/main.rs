//! The `flank` command line: parses, calls the library, prints.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::{Parser, Subcommand};

use flank::fem::ordering::OrderingMethod;
use flank::fem::solver::Precision;
use flank::fem::static_analysis::{solve_static, SolveOptions};

#[derive(Parser)]
#[command(
    name = "flank",
    version,
    about = "Finite-element-first gear tooth contact: native 3D elasticity, FE contact, LTCA"
)]
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
        /// Arithmetic of the factorization: double, or mixed (f32 factor,
        /// f64 iterative refinement, automatic fallback to double).
        #[arg(long, value_enum, default_value_t = Precision::Double)]
        precision: Precision,
        /// Skip stress recovery and reactions.
        #[arg(long)]
        no_stress: bool,
        /// No progress display.
        #[arg(long, short)]
        quiet: bool,
    },
    /// Read a gear-pair scene, check the pair (shifts vs centre distance,
    /// undercut, pointed tips, clearance, interference, contact ratio) and
    /// print the pair report (ε_α, ε_β, working pressure angle, W_k, …) as JSON.
    Check {
        /// The scene file (.toml).
        scene: PathBuf,
    },
    /// Write the benchmark cantilever as a CalculiX deck: a box L × 10 × 10 mm
    /// (L = 10·nx/ny mm … so elements are cubes), clamped at x = 0, 1 kN tip
    /// load in −y spread over the tip face nodes.
    Cantilever {
        /// Elements along x, y, z.
        #[arg(long, value_delimiter = ',', default_values_t = [100, 10, 10])]
        cells: Vec<usize>,
        /// Element type.
        #[arg(long, value_enum, default_value_t = DeckElement::C3d20)]
        element: DeckElement,
        /// Output deck.
        #[arg(long, default_value = "cantilever.inp")]
        out: PathBuf,
    },
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum DeckElement {
    C3d20,
    C3d20r,
    C3d15,
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
            precision,
            no_stress,
            quiet,
        } => {
            let parsed = flank::mesh::inp::read_deck(&deck)?;
            for w in &parsed.warnings {
                eprintln!("warning: {}:{}: {}", deck.display(), w.line, w.message);
            }
            let options = SolveOptions {
                ordering,
                threads,
                recover_stress: !no_stress,
                progress: !quiet,
                precision,
            };
            let sol = solve_static(&parsed.model, &options)
                .with_context(|| format!("solving {}", deck.display()))?;
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
        Command::Check { scene } => {
            let scene = flank::scene::read_scene(&scene)?;
            let report = flank::geometry::pair::check_pair(&scene.pair)?;
            println!("{}", serde_json::to_string_pretty(&report)?);
        }
        Command::Cantilever {
            cells,
            element,
            out,
        } => {
            let kind = match element {
                DeckElement::C3d20 => flank::mesh::structured::BoxElement::Hex20,
                DeckElement::C3d20r => flank::mesh::structured::BoxElement::Hex20R,
                DeckElement::C3d15 => flank::mesh::structured::BoxElement::Wedge15,
            };
            if cells.len() != 3 || cells.contains(&0) {
                anyhow::bail!("--cells needs three positive counts, e.g. --cells 100,10,10");
            }
            let model = flank::mesh::structured::cantilever_model(
                [cells[0], cells[1], cells[2]],
                kind,
                1000.0,
            )?;
            flank::mesh::inp::write_deck(&model, &out)?;
            println!(
                "wrote {} ({} nodes, {} elements)",
                out.display(),
                model.mesh.node_count(),
                model.mesh.elements.len()
            );
        }
    }
    Ok(())
}
