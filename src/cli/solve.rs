//! `flank solve`: a CalculiX/Abaqus deck, linear static or with contact pairs.

use std::path::PathBuf;

use anyhow::{Context, Result};

use flank::fem::ordering::OrderingMethod;
use flank::fem::solver::Precision;
use flank::fem::static_analysis::{solve_static, SolveOptions};
use flank::fem::substructuring::Substructure;

#[derive(clap::Args)]
pub struct Args {
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
    /// Arithmetic of the factorization: mixed (default: f32 factor, f64
    /// refinement to a backward error of f64 round-off, automatic fallback
    /// to double), or double (forces the f64 factor).
    /// Contact decks always factorize in double.
    #[arg(long, value_enum)]
    precision: Option<Precision>,
    /// Two-domain factorization of the static solve (a vertex separator
    /// splits the model in two halves factorized concurrently): auto
    /// (default: with 2 or more threads and at least 50 000 DOFs in mixed
    /// precision), off, or on (whenever mixed, any size).
    #[arg(long, value_enum, default_value_t = Substructure::Auto)]
    substructure: Substructure,
    /// Skip stress recovery and reactions.
    #[arg(long)]
    no_stress: bool,
    /// No progress display.
    #[arg(long, short)]
    quiet: bool,
}

pub fn run(args: Args) -> Result<()> {
    let Args {
        deck,
        out,
        ordering,
        threads,
        precision,
        substructure,
        no_stress,
        quiet,
    } = args;
    let parsed = flank::deck::read_deck(&deck)?;
    for w in &parsed.warnings {
        eprintln!("warning: {}:{}: {}", deck.display(), w.line, w.message);
    }
    if !parsed.model.contact.is_empty() {
        return solve_contact_deck(
            &deck, &out, &parsed, ordering, threads, !no_stress, quiet, precision,
        );
    }
    let options = SolveOptions {
        ordering,
        threads,
        recover_stress: !no_stress,
        progress: !quiet,
        precision: precision.unwrap_or_default(),
        substructure,
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
            "{} nodes, {} elements, {} DOFs; nnz(L) = {} ({}); assembly {:.3} s, ordering {:.3} s, factorization {:.3} s ({:.1} GFLOP/s), solve {:.3} s; residual {:.1e}; peak memory {:.0} MB (estimated {:.0} MB)",
            s.nodes, s.elements, s.dofs, s.nnz_factor, s.ordering, s.assembly_s, s.ordering_s, s.factorization_s, s.factorization_gflops, s.solve_s, s.relative_residual, s.peak_memory_mb, s.estimated_peak_mb
        );
        println!("results in {}", out.display());
    }
    Ok(())
}

/// `flank solve` on a deck with contact pairs: the contact solve, then the
/// usual outputs plus contact.csv, contact fields in result.vtu and the
/// contact figures in summary.json.
#[allow(clippy::too_many_arguments)]
fn solve_contact_deck(
    deck: &std::path::Path,
    out: &std::path::Path,
    parsed: &flank::deck::Deck,
    ordering: OrderingMethod,
    threads: usize,
    recover_stress: bool,
    quiet: bool,
    precision: Option<Precision>,
) -> Result<()> {
    // the contact solve reuses one factor for many Delassus columns (no
    // refinement per column): it always factorizes in double
    if precision == Some(Precision::Mixed) {
        eprintln!("warning: contact solves factorize in double precision (--precision ignored)");
    }
    let options = flank::contact::ContactOptions {
        ordering,
        threads,
        recover_stress,
        ..Default::default()
    };
    let sol = flank::contact::solve_contact(&parsed.model, &options)
        .with_context(|| format!("solving {}", deck.display()))?;
    for w in &sol.summary.warnings {
        eprintln!("warning: {w}");
    }
    let extra = serde_json::json!({
        "deck": deck.display().to_string(),
        "warnings": parsed.warnings.len() + sol.summary.warnings.len(),
    });
    flank::report::solution::write_contact_solution(out, &parsed.model, &sol, extra)?;
    if !quiet {
        let s = &sol.solution.stats;
        let a = &sol.summary.active_set;
        println!(
            "{} nodes, {} elements, {} DOFs; factorization {:.3} s; contact: {} active-set iterations, {} closed, {} solves; law violation {:.1e} mm, complementarity {:.1e} N·mm; residual {:.1e}",
            s.nodes, s.elements, s.dofs, s.factorization_s, a.iterations, a.active, a.columns, a.max_violation, a.complementarity, s.relative_residual
        );
        for p in &sol.summary.pairs {
            let law = match p.law {
                flank::contact::pairing::NormalLaw::Hard => "hard".to_string(),
                flank::contact::pairing::NormalLaw::Penalty { slope, automatic } => format!(
                    "penalty {slope:.4e} MPa/mm{}",
                    if automatic { " (automatic)" } else { "" }
                ),
            };
            println!(
                "pair {} / {} ({law}): {} of {} candidates closed, total normal force {:.6e} N, max pressure {:.6e} MPa",
                p.slave, p.master, p.closed, p.candidates, p.total_normal_force, p.max_pressure
            );
            if let Some(f) = &p.friction {
                println!(
                    "  friction μ = {}{}: {} stick, {} slip; tangential force {:.6e} N ({:.6e}, {:.6e}, {:.6e}); max slip {:.3e} mm",
                    f.mu,
                    f.stick_slope
                        .map_or(" (hard stick)".to_string(), |k| format!(", stick slope {k:.4e} MPa/mm")),
                    f.stick,
                    f.slip,
                    f.total_tangential_force,
                    f.tangential_resultant[0],
                    f.tangential_resultant[1],
                    f.tangential_resultant[2],
                    f.max_slip
                );
            }
        }
        if let Some(f) = &sol.summary.friction {
            println!(
                "friction: {} fixed-point iterations ({}), polish {}; Coulomb residual {:.1e} N, stick/slip complementarity {:.1e} N·mm; {} stiffness solves",
                f.iterations,
                if f.converged { "converged" } else { "ITERATION LIMIT" },
                if f.polished { "exact" } else { "not applied" },
                f.coulomb_residual,
                f.stick_slip_complementarity,
                f.columns
            );
        }
        println!("results in {}", out.display());
    }
    Ok(())
}
