//! The clarabel path of an increment: Tresca QPs (fixed friction bounds
//! and kinematic slip) by the interior-point solver clarabel, the fixed
//! point on the bounds, then the polish (module doc of [`super`]).

use super::polish::polish;
use super::problem::{FrictionOptions, Prepared, StepAnswer};
use super::residual::{gaps, residuals, slips, states, Previous};
use super::semismooth::{newton, NewtonEnd};
use crate::error::FlankError;

/// A friction bound below this fraction of P₀ is treated as zero: the
/// point carries no friction force in that QP (a box of width ~0 has no
/// interior for clarabel).
const BOUND_MIN: f64 = 1e-12;

/// One Tresca QP's answer (totals).
struct Tresca {
    pn: Vec<f64>,
    pt: Vec<f64>,
    dtheta: f64,
    iterations: usize,
}

/// The Tresca QP of the increment for bounds `bound` and kinematic slip
/// s r_n Δθ̃ (`dtheta_kin` = Δθ̃), scaled: x = ΔP/P₀, objective over
/// P₀δ₀, equality over r₀P₀. Points with a zero bound keep P_t = 0.
/// clarabel's conditions P x + q + Aᵀz = 0 give g = δ₀ z_n (normal
/// bounds), Δσ = δ₀ (z_upper − z_lower) and Δθ = −z₀ δ₀/r₀.
fn tresca(
    prob: &Prepared,
    prev: &Previous,
    g_prev: &[f64],
    dtorque: f64,
    bound: &[f64],
    dtheta_kin: f64,
    options: &FrictionOptions,
) -> Result<Tresca, FlankError> {
    use clarabel::algebra::CscMatrix;
    use clarabel::solver::{
        DefaultSettings, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
    };
    let m = prob.m;
    let (p0, d0, r0) = (prob.p0, prob.d0, prob.r0);
    let free: Vec<usize> = (0..m).filter(|&i| bound[i] > BOUND_MIN * p0).collect();
    let fixed: Vec<usize> = (0..m).filter(|&i| !(bound[i] > BOUND_MIN * p0)).collect();
    let f = free.len();
    let nv = m + f;
    // the full compliance entry of variables a, b (0..m normal, m.. free tangential)
    let entry = |a: usize, b: usize| -> f64 {
        match (a < m, b < m) {
            (true, true) => prob.c_nn[(a, b)],
            (true, false) => prob.c_nt[(a, free[b - m])],
            (false, true) => prob.c_tn[(free[a - m], b)],
            (false, false) => prob.c_tt[(free[a - m], free[b - m])],
        }
    };
    let k = p0 / d0;
    let mut colptr = Vec::with_capacity(nv + 1);
    let mut rowval = Vec::new();
    let mut nzval = Vec::new();
    colptr.push(0);
    for j in 0..nv {
        for i in 0..=j {
            let v = k * entry(i, j);
            if v != 0.0 || i == j {
                rowval.push(i);
                nzval.push(v);
            }
        }
        colptr.push(rowval.len());
    }
    let pm = CscMatrix::new(nv, nv, colptr, rowval, nzval);
    // fixed tangential increments ΔP_t = −P_t,prev (to zero)
    let mut q = vec![0.0; nv];
    for i in 0..m {
        let mut v = g_prev[i];
        for &j in &fixed {
            v -= prob.c_nt[(i, j)] * prev.pt[j];
        }
        q[i] = v / d0;
    }
    for (a, &i) in free.iter().enumerate() {
        let mut v = -(prob.rho[i] - prob.r_t[i]) * dtheta_kin;
        for &j in &fixed {
            v -= prob.c_tt[(i, j)] * prev.pt[j];
        }
        q[m + a] = v / d0;
    }
    // rows: 0 equilibrium; 1..=m normal bounds; then upper/lower per free point
    let nrows = 1 + m + 2 * f;
    let mut colptr = Vec::with_capacity(nv + 1);
    let mut rowval = Vec::new();
    let mut nzval = Vec::new();
    colptr.push(0);
    for j in 0..m {
        rowval.extend([0, 1 + j]);
        nzval.extend([prob.r_n[j] / r0, -1.0]);
        colptr.push(rowval.len());
    }
    for (a, &i) in free.iter().enumerate() {
        rowval.extend([0, 1 + m + 2 * a, 2 + m + 2 * a]);
        nzval.extend([prob.r_t[i] / r0, 1.0, -1.0]);
        colptr.push(rowval.len());
    }
    let am = CscMatrix::new(nrows, nv, colptr, rowval, nzval);
    let mut b = vec![0.0; nrows];
    let fixed_moment: f64 = fixed.iter().map(|&j| prob.r_t[j] * prev.pt[j]).sum();
    b[0] = (dtorque + fixed_moment) / (r0 * p0);
    for i in 0..m {
        b[1 + i] = prev.pn[i] / p0;
    }
    for (a, &i) in free.iter().enumerate() {
        b[1 + m + 2 * a] = (bound[i] - prev.pt[i]) / p0;
        b[2 + m + 2 * a] = (bound[i] + prev.pt[i]) / p0;
    }
    let cones = [
        SupportedConeT::ZeroConeT(1),
        SupportedConeT::NonnegativeConeT(m + 2 * f),
    ];
    let settings = DefaultSettings {
        verbose: false,
        max_iter: options.max_qp_iterations.min(u32::MAX as usize) as u32,
        tol_gap_abs: 1e-11,
        tol_gap_rel: 1e-11,
        tol_feas: 1e-11,
        ..DefaultSettings::default()
    };
    let mut solver = DefaultSolver::new(&pm, &q, &am, &b, &cones, settings)
        .map_err(|e| FlankError::Solver(format!("friction LTCA clarabel setup: {e}")))?;
    solver.solve();
    let sol = &solver.solution;
    match sol.status {
        SolverStatus::Solved | SolverStatus::AlmostSolved | SolverStatus::InsufficientProgress => {}
        SolverStatus::MaxIterations => {
            return Err(FlankError::Solver(format!(
                "friction LTCA clarabel: iteration limit {} (FrictionOptions::max_qp_iterations) reached",
                options.max_qp_iterations
            )))
        }
        other => {
            return Err(FlankError::Solver(format!(
                "friction LTCA clarabel: status {other} after {} iterations (the Tresca QP is feasible and bounded for r_n > μ|r_t|, so this is numerical)",
                sol.iterations
            )))
        }
    }
    if sol.x.len() != nv
        || sol.z.len() != nrows
        || sol.x.iter().chain(&sol.z).any(|v| !v.is_finite())
    {
        return Err(FlankError::Solver(
            "friction LTCA clarabel: a non-finite or mis-sized answer".into(),
        ));
    }
    let mut pn = prev.pn.to_vec();
    let mut pt = vec![0.0; m];
    for i in 0..m {
        pn[i] += sol.x[i] * p0;
    }
    for (a, &i) in free.iter().enumerate() {
        pt[i] = prev.pt[i] + sol.x[m + a] * p0;
    }
    Ok(Tresca {
        pn,
        pt,
        dtheta: -sol.z[0] * d0 / r0,
        iterations: sol.iterations as usize,
    })
}

/// Increment k by the clarabel path: Tresca QPs with S ← μP_n,
/// Δθ̃ ← Δθ until both change by at most the fixed-point tolerance (or
/// the limit). From the first iterate
/// whose change is below [`POLISH_TRIGGER`] (or that stagnates below
/// [`STALL_TRIGGER`]) on, the polish is tried from its states; the first
/// polished answer that settles within the residual tolerance ends the
/// increment (the exact answer does not need a tighter fixed point, and
/// the fixed point cannot settle below clarabel's own accuracy). Where
/// the active-set polish does not get there (it cycles, or settles above
/// the tolerance), the semismooth Newton polish (`semismooth.rs`) is
/// tried from the same Tresca answer. Without such a polish the last
/// Tresca answer is kept.
pub(crate) fn step(
    prob: &Prepared,
    prev: &Previous,
    dtorque: f64,
    torque: f64,
    options: &FrictionOptions,
) -> Result<StepAnswer, FlankError> {
    let m = prob.m;
    let g_prev = gaps(prob, prev.pn, prev.pt, prev.theta);
    let mut bound: Vec<f64> = (0..m).map(|i| prob.mu[i] * prev.pn[i].max(0.0)).collect();
    let mut dtheta_kin = 0.0;
    let mut inner = 0;
    let mut iterations = 0;
    let mut counters = PolishCounters::default();
    let mut converged = false;
    let mut last = None;
    let (mut best, mut stalled) = (f64::INFINITY, 0);
    let ts = prob.theta_scale();
    while iterations < options.max_fixed_point {
        iterations += 1;
        let t = tresca(prob, prev, &g_prev, dtorque, &bound, dtheta_kin, options)?;
        inner += t.iterations;
        let new_bound: Vec<f64> = (0..m).map(|i| prob.mu[i] * t.pn[i].max(0.0)).collect();
        let db = (0..m).fold(0.0f64, |a, i| a.max((new_bound[i] - bound[i]).abs()));
        let change = if prob.mu_max == 0.0 {
            0.0
        } else {
            (db / (prob.mu_max * prob.p0)).max((t.dtheta - dtheta_kin).abs() / ts)
        };
        bound = new_bound;
        dtheta_kin = t.dtheta;
        // stagnation: the change no longer halves (clarabel's own accuracy,
        // about 1e-6 relative on stiff problems, is the floor)
        if change < 0.5 * best {
            best = change;
            stalled = 0;
        } else {
            stalled += 1;
        }
        let stagnant = stalled >= STALL_ITERATIONS && change <= STALL_TRIGGER;
        if change <= POLISH_TRIGGER || stagnant {
            if let Some(p) = try_polish(prob, prev, torque, &t, options, &mut counters)? {
                return Ok(StepAnswer {
                    iterations,
                    inner_iterations: inner,
                    ..p
                });
            }
        }
        last = Some(t);
        if change <= options.fixed_point_tolerance {
            converged = true;
            break;
        }
        if stagnant {
            // polished without success: a slow approach may still get
            // there; the next try after another window
            stalled = 0;
        }
    }
    let t = last.ok_or_else(|| {
        FlankError::Model("friction LTCA: the fixed point needs at least one iteration".into())
    })?;
    let theta = prev.theta + t.dtheta;
    if converged && options.fixed_point_tolerance > POLISH_TRIGGER {
        // (with a tolerance ≤ the trigger this iterate was tried already)
        if let Some(p) = try_polish(prob, prev, torque, &t, options, &mut counters)? {
            return Ok(StepAnswer {
                iterations,
                inner_iterations: inner,
                ..p
            });
        }
    }
    Ok(StepAnswer {
        pn: t.pn,
        pt: t.pt,
        theta,
        iterations,
        inner_iterations: inner,
        polish_iterations: counters.polish_iterations,
        polished: false,
        newton_iterations: counters.newton_iterations,
        newton: false,
        limit_hit: !converged || counters.limit_hit,
    })
}

/// Relative change of the fixed point below which the polish is tried.
pub const POLISH_TRIGGER: f64 = 1e-6;

/// Rounds without the change halving after which the fixed point counts
/// as stagnant: seed 001 at flank 1 mm stalls at a change of 1.34e-6,
/// just above [`POLISH_TRIGGER`], for all its 200 rounds (clarabel's
/// accuracy is the floor). A stagnant iterate below [`STALL_TRIGGER`] is
/// polished; if that does not settle, the rounds go on (a slow approach
/// may still converge) and the next window tries again.
pub const STALL_ITERATIONS: usize = 5;
/// Largest change at which a stagnant fixed point is polished.
pub const STALL_TRIGGER: f64 = 1e-3;

/// The polish attempts of one increment, summed.
#[derive(Default)]
struct PolishCounters {
    /// Successful active-set polish: its state systems.
    polish_iterations: usize,
    /// Semismooth Newton iterations over all attempts.
    newton_iterations: usize,
    /// A polish (active-set or Newton) reached its limit.
    limit_hit: bool,
}

/// The polish from a Tresca answer; `Some` when it reaches the residual
/// tolerance and not above the Tresca answer's residual. First the
/// active-set polish from the answer's states (exact: the answer of a
/// state system); where it cycles, fails or settles above the tolerance,
/// the semismooth Newton polish from the Tresca answer itself (if
/// `max_newton` > 0).
fn try_polish(
    prob: &Prepared,
    prev: &Previous,
    torque: f64,
    t: &Tresca,
    options: &FrictionOptions,
    counters: &mut PolishCounters,
) -> Result<Option<StepAnswer>, FlankError> {
    let theta = prev.theta + t.dtheta;
    let gap = gaps(prob, &t.pn, &t.pt, theta);
    let slip = slips(prob, prev, &t.pn, &t.pt, theta);
    let raw = residuals(prob, torque, &t.pn, &t.pt, &gap, &slip);
    let accept = |pn: &[f64], pt: &[f64], theta: f64| {
        let gap = gaps(prob, pn, pt, theta);
        let slip = slips(prob, prev, pn, pt, theta);
        let res = residuals(prob, torque, pn, pt, &gap, &slip);
        res.max <= options.tolerance && res.max <= raw.max.max(options.tolerance)
    };
    let start = states(prob, &t.pn, &t.pt, &gap, &slip);
    match polish(prob, prev, torque, start, options.max_polish) {
        Ok(p) if p.settled => {
            if accept(&p.pn, &p.pt, p.theta) {
                return Ok(Some(StepAnswer {
                    pn: p.pn,
                    pt: p.pt,
                    theta: p.theta,
                    iterations: 0,
                    inner_iterations: 0,
                    polish_iterations: counters.polish_iterations + p.iterations,
                    polished: true,
                    newton_iterations: counters.newton_iterations,
                    newton: false,
                    limit_hit: counters.limit_hit,
                }));
            }
        }
        Ok(_) => counters.limit_hit = true,
        Err(_) => {}
    }
    if options.max_newton == 0 {
        return Ok(None);
    }
    let n = newton(prob, prev, torque, &t.pn, &t.pt, theta, options.max_newton);
    counters.newton_iterations += n.iterations;
    if n.end == NewtonEnd::Limit {
        counters.limit_hit = true;
    }
    if !accept(&n.pn, &n.pt, n.theta) {
        return Ok(None);
    }
    Ok(Some(StepAnswer {
        pn: n.pn,
        pt: n.pt,
        theta: n.theta,
        iterations: 0,
        inner_iterations: 0,
        polish_iterations: counters.polish_iterations,
        polished: true,
        newton_iterations: counters.newton_iterations,
        newton: true,
        limit_hit: counters.limit_hit,
    }))
}
