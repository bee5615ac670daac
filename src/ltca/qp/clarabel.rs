//! The clarabel path of the contact QP: the scaled problem handed to the
//! interior-point solver clarabel, its status and answer unscaled, then
//! the polish by active-set iterations from its loaded set (module doc of
//! [`super`]).

use super::active_set::iterate;
use super::kkt::residuals;
use super::problem::{Prepared, QpOptions, Raw};
use crate::error::FlankError;

/// clarabel on the scaled QP, then the polish (module doc). T > 0.
///
/// Scaling: with r₀ = max rᵢ, f₀ = max Fᵢᵢ, P₀ = T/r₀ and δ₀ = P₀f₀,
/// p = P₀p̂, F = f₀F̂, r = r₀r̂, w = δ₀ŵ, and the objective divided by
/// P₀δ₀, clarabel solves
///
/// ```text
///   min ½ p̂ᵀF̂p̂ + ŵᵀp̂   s.t.  r̂ᵀp̂ + s₀ = 1, s₀ = 0 (zero cone),
///                             −p̂ + s = 0,  s ≥ 0 (non-negative cone),
/// ```
///
/// whose entries are O(1) (F ~ 1e-5 mm/N and T ~ 1e5 N·mm unscaled would
/// span 10 decades). clarabel's optimality conditions are
/// P x + q + Aᵀz = 0, i.e. F̂p̂ + ŵ + z₀r̂ − z₁..ₙ = 0: the bound multipliers
/// are the scaled gaps ĝ = z₁..ₙ and the rotation is θ̂ = −z₀, θ = θ̂δ₀/r₀
/// (sign checked against the active set in the tests).
pub(super) fn solve_clarabel(prob: &Prepared, options: &QpOptions) -> Result<Raw, FlankError> {
    let n = prob.n;
    let ClarabelRaw {
        load: raw_load,
        rotation: raw_rotation,
        loaded: set,
        iterations,
    } = clarabel_raw(prob, options)?;
    let fp = prob.apply(&raw_load);
    let raw_kkt = residuals(&fp, prob.w, prob.r, prob.t, &raw_load, raw_rotation);
    // polish: active-set iterations from the loaded set read off the
    // answer, loads rescaled to rᵀp = T (usually one equality solve)
    let rp: f64 = set.iter().map(|&i| prob.r[i] * raw_load[i]).sum();
    if !set.is_empty() && rp > 0.0 {
        let mut start = vec![0.0; n];
        for &i in &set {
            start[i] = raw_load[i] * prob.t / rp;
        }
        if let Ok(polish) = iterate(prob, options, set, start, raw_rotation, 0) {
            let fp = prob.apply(&polish.load);
            let kkt = residuals(&fp, prob.w, prob.r, prob.t, &polish.load, polish.rotation);
            if !(kkt.max > raw_kkt.max) {
                return Ok(Raw {
                    iterations,
                    polished: true,
                    polish_iterations: polish.iterations,
                    raw_kkt: Some(raw_kkt),
                    ..polish
                });
            }
        }
    }
    Ok(Raw {
        load: raw_load,
        rotation: raw_rotation,
        iterations,
        shift: 0.0,
        polished: false,
        polish_iterations: 0,
        raw_kkt: Some(raw_kkt),
    })
}

/// clarabel's unpolished answer.
pub(super) struct ClarabelRaw {
    pub(super) load: Vec<f64>,
    pub(super) rotation: f64,
    /// Points with p̂ᵢ > ĝᵢ (scaled load above scaled gap).
    pub(super) loaded: Vec<usize>,
    pub(super) iterations: usize,
}

/// Builds the scaled problem (see `solve_clarabel`), runs clarabel, maps
/// its status and unscales its answer.
pub(super) fn clarabel_raw(
    prob: &Prepared,
    options: &QpOptions,
) -> Result<ClarabelRaw, FlankError> {
    use clarabel::algebra::CscMatrix;
    use clarabel::solver::{
        DefaultSettings, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
    };
    let n = prob.n;
    let r0 = prob.r.iter().fold(0.0f64, |a, &v| a.max(v));
    let f0 = prob.max_diag;
    let p0 = prob.t / r0;
    let d0 = p0 * f0;
    // P: upper triangle of F̂, CSC
    let mut colptr = Vec::with_capacity(n + 1);
    let mut rowval = Vec::with_capacity(n * (n + 1) / 2);
    let mut nzval = Vec::with_capacity(n * (n + 1) / 2);
    colptr.push(0);
    for j in 0..n {
        for i in 0..=j {
            let v = prob.f[(i, j)] / f0;
            if v != 0.0 || i == j {
                rowval.push(i);
                nzval.push(v);
            }
        }
        colptr.push(rowval.len());
    }
    let pm = CscMatrix::new(n, n, colptr, rowval, nzval);
    let q: Vec<f64> = prob.w.iter().map(|v| v / d0).collect();
    // A: row 0 = r̂ᵀ, rows 1..=n = −I
    let mut colptr = Vec::with_capacity(n + 1);
    let mut rowval = Vec::with_capacity(2 * n);
    let mut nzval = Vec::with_capacity(2 * n);
    colptr.push(0);
    for j in 0..n {
        rowval.push(0);
        nzval.push(prob.r[j] / r0);
        rowval.push(1 + j);
        nzval.push(-1.0);
        colptr.push(rowval.len());
    }
    let am = CscMatrix::new(n + 1, n, colptr, rowval, nzval);
    let mut b = vec![0.0; n + 1];
    b[0] = 1.0;
    let cones = [
        SupportedConeT::ZeroConeT(1),
        SupportedConeT::NonnegativeConeT(n),
    ];
    let settings = DefaultSettings {
        verbose: false,
        max_iter: options.max_iterations.min(u32::MAX as usize) as u32,
        tol_gap_abs: 1e-10,
        tol_gap_rel: 1e-10,
        tol_feas: 1e-10,
        ..DefaultSettings::default()
    };
    let mut solver = DefaultSolver::new(&pm, &q, &am, &b, &cones, settings)
        .map_err(|e| FlankError::Solver(format!("LTCA clarabel setup: {e}")))?;
    solver.solve();
    let sol = &solver.solution;
    match sol.status {
        SolverStatus::Solved | SolverStatus::AlmostSolved | SolverStatus::InsufficientProgress => {}
        SolverStatus::PrimalInfeasible
        | SolverStatus::AlmostPrimalInfeasible
        | SolverStatus::DualInfeasible
        | SolverStatus::AlmostDualInfeasible => {
            return Err(FlankError::Solver(format!(
                "LTCA clarabel: status {} after {} iterations; the problem is feasible and bounded for r > 0 and T ≥ 0, so this is a numerical failure (condition of F?)",
                sol.status, sol.iterations
            )));
        }
        SolverStatus::MaxIterations => {
            return Err(FlankError::Solver(format!(
                "LTCA clarabel: iteration limit {} (QpOptions::max_iterations) reached with primal and dual residuals {:.3e} and {:.3e}",
                options.max_iterations, sol.r_prim, sol.r_dual
            )));
        }
        other => {
            return Err(FlankError::Solver(format!(
                "LTCA clarabel: status {other} after {} iterations",
                sol.iterations
            )));
        }
    }
    let iterations = sol.iterations as usize;
    let x = &sol.x;
    let z = &sol.z;
    if x.len() != n || z.len() != n + 1 || x.iter().chain(z).any(|v| !v.is_finite()) {
        return Err(FlankError::Solver(format!(
            "LTCA clarabel: status {} but a non-finite or mis-sized answer",
            sol.status
        )));
    }
    Ok(ClarabelRaw {
        load: x.iter().map(|v| v * p0).collect(),
        rotation: -z[0] * d0 / r0,
        loaded: (0..n).filter(|&i| x[i] > z[1 + i] && x[i] > 0.0).collect(),
        iterations,
    })
}
