//! The `flank` command line: parses, calls the library, prints. One module
//! per subcommand in `cli/`.

mod cli;

use anyhow::Result;
use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "flank",
    // with the git commit: campaign job identities carry it
    version = flank::campaign::variants::flank_version_static(),
    about = "Finite-element-first gear tooth contact: native 3D elasticity, FE contact, LTCA"
)]
struct Cli {
    /// Memory limit (MB) for this flank process and the processes it
    /// starts, below what the machine has: a factorization, Schur
    /// complement or compliance tensor that would need more is refused with
    /// the figures instead of being killed (same as FLANK_MEMORY_LIMIT_MB).
    #[arg(long, global = true, value_name = "MB")]
    memory_limit_mb: Option<f64>,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Solve a CalculiX/Abaqus linear static deck (C3D20, C3D20R, C3D15).
    Solve(cli::solve::Args),
    /// Read a gear-pair scene, check the pair (shifts vs centre distance,
    /// undercut, pointed tips, clearance, interference, contact ratio) and
    /// print the pair report (ε_α, ε_β, working pressure angle, W_k, …) as JSON.
    Check(cli::check::Args),
    /// Mesh both bodies of a gear-pair scene (sector of N teeth, hex20 or
    /// wedge15, flank micro-geometry applied): writes pinion.inp and
    /// gear.inp (bore clamped, nominal single-pair
    /// normal force T/r_b1 at the working pitch point of the middle tooth),
    /// .vtu files, <body>_flank_uv.csv (flank node parameters) and
    /// mesh_report.json.
    Mesh(cli::mesh::Args),
    /// Convert a gmsh mesh (.msh 4.1 ASCII; 20-node hexahedra and 15-node
    /// prisms, i.e. exported with Mesh.SecondOrderIncomplete = 1) into a
    /// CalculiX deck: physical groups of dimension 0–2 become node sets,
    /// volume groups element sets; one linear-elastic material, no boundary
    /// conditions or loads.
    Import(cli::import::Args),
    /// Nodal compliance tensors of a scene's gear bodies (bore clamped; the
    /// loaded flank FLANK_R<k> of every tooth by default) from one
    /// factorization each: writes <body>.inp (as `flank mesh`),
    /// <body>.compliance.h5 (built with --features hdf5) or
    /// <body>.compliance.bin, <body>_cnn.svg/.png (normal self-compliance over
    /// the middle tooth's flank) and summary.json.
    Compliance(cli::compliance::Args),
    /// Compliance-matrix LTCA over a mesh cycle (the scene's [analyses.ltca]):
    /// both bodies' compliance tensors (computed once, cached beside the
    /// decks in --out), then per roll angle the unloaded TCA, the normal
    /// compliance of the candidate points and the contact QP. Writes
    /// ltca_cycle.csv (spur/helical) or ltca_positions.csv (bevel/hypoid),
    /// ltca_points.csv, summary.json and plots (docs/outputs.md).
    Ltca(cli::ltca::Args),
    /// LTCA against FE contact at the same roll angles: LTCA at several K,
    /// FE contact at several flank element sizes (the finest is the
    /// reference). Writes compare.json, compare.md and error_vs_time plots.
    Compare(cli::compare::Args),
    /// FE contact over a mesh cycle (the scene's [analyses.contact]): both
    /// sectors meshed and placed in mesh, pinion hub coupled to a reference
    /// node loaded by the torque, gear hub clamped, one contact solve per
    /// roll angle with the stiffness factorized once. Writes, for a
    /// spur/helical pair, mesh_cycle.csv, summary.json (contact_ratio,
    /// single_pair_force_n, positions, time_per_position_s, nodes, ...),
    /// force_per_tooth and transmission_error plots (SVG, PNG) and
    /// roll_<angle>deg.vtu; for a bevel/hypoid pair positions.csv,
    /// contact_pattern.csv, summary.json and plots (docs/outputs.md).
    Run(cli::run::Args),
    /// Write the benchmark cantilever as a CalculiX deck: a box L × 10 × 10 mm
    /// (L = 10·nx/ny mm … so elements are cubes), clamped at x = 0, 1 kN tip
    /// load in −y spread over the tip face nodes.
    Cantilever(cli::cantilever::Args),
    /// ISO 23509 blank design of a spiral bevel or hypoid pair (methods
    /// 0–3) from a JSON input set with the Annex F key names; prints the
    /// outputs (mm, degrees) as JSON.
    Blank(cli::blank::Args),
    /// One flank of a scene's member as the measuring machine's grid (points
    /// and unit normals on FACE × PROFILE points over the active flank, CSV,
    /// `deviation_um` column to fill in): the file a measured deviation grid
    /// is read back from.
    Grid(cli::grid::Args),
    /// Unloaded tooth contact analysis over the mesh cycle. Spiral bevel and
    /// hypoid scenes: point contact with and without edge contact (seed
    /// 000): per position and tooth pair the contact point in flank
    /// projection, TE, contact ellipse at the approach δ (curvatures and
    /// numerical search), edge flags, velocities (tca_*.csv), the system
    /// transitions, summary.json (contact_ratio, te_peak_to_peak_arcsec
    /// under with_edges/without_edges) and TE / bearing-pattern plots.
    Tca(cli::tca::Args),
    /// Campaigns: a scene's variants (grid over scene keys, seeded Monte
    /// Carlo sample) × analyses, resumable, run locally (`run`) or as a
    /// Slurm job array (`submit`, `status`), collected into one table with
    /// convergence (GCI) and distribution summaries (`collect`).
    Campaign(cli::campaign::Args),
}

fn main() -> std::process::ExitCode {
    // Rust ignores SIGPIPE, so printing into a closed pipe (`flank check … |
    // head`) would panic; restore the default action: the process ends quietly,
    // as Unix tools do.
    #[cfg(unix)]
    // SAFETY: called first in main, before any thread exists; SIG_DFL is a
    // valid disposition for SIGPIPE.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    match run(Cli::parse()) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            // the whole context chain, no backtrace: the message says what and where
            eprintln!("error: {e:#}");
            // stopped by SIGINT at a safe point: the shell's code for SIGINT
            if let Some(flank::FlankError::Interrupted(_)) = e.downcast_ref::<flank::FlankError>() {
                return std::process::ExitCode::from(130);
            }
            std::process::ExitCode::FAILURE
        }
    }
}

/// `flank ARGV…` parsed (the program name added).
fn parse_argv(argv: &[String]) -> std::result::Result<Cli, String> {
    Cli::try_parse_from(std::iter::once("flank".to_string()).chain(argv.iter().cloned()))
        .map_err(|e| e.to_string())
}

/// The command line handed to campaigns: their analyses are flank
/// commands, checked and (in `run-task`) run in this process.
const COMMAND_LINE: cli::campaign::CommandLine = cli::campaign::CommandLine {
    check: |argv| parse_argv(argv).map(|_| ()),
    run: |argv| run(parse_argv(argv)?).map_err(|e| format!("{e:#}")),
};

fn run(cli: Cli) -> Result<()> {
    if let Some(mb) = cli.memory_limit_mb {
        anyhow::ensure!(
            mb > 0.0 && mb.is_finite(),
            "--memory-limit-mb {mb}: expected a positive number of megabytes"
        );
        flank::resources::set_memory_limit_mb(Some(mb));
        // campaign jobs are child processes: they inherit the limit
        std::env::set_var(flank::resources::LIMIT_VAR, mb.to_string());
    }
    match cli.command {
        Command::Solve(args) => cli::solve::run(args),
        Command::Check(args) => cli::check::run(args),
        Command::Mesh(args) => cli::mesh::run(args),
        Command::Import(args) => cli::import::run(args),
        Command::Compliance(args) => cli::compliance::run(args),
        Command::Ltca(args) => cli::ltca::run(args),
        Command::Compare(args) => cli::compare::run(args),
        Command::Run(args) => cli::run::run(args),
        Command::Cantilever(args) => cli::cantilever::run(args),
        Command::Blank(args) => cli::blank::run(args),
        Command::Grid(args) => cli::grid::run(args),
        Command::Tca(args) => cli::tca::run(args),
        Command::Campaign(args) => cli::campaign::run(args, &COMMAND_LINE),
    }
}
