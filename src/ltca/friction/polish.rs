//! The increment with its point states fixed: one linear system, solved
//! exactly; and the primal–dual active-set update of the states from its
//! answer (Hüeber, Stadler & Wohlmuth, SIAM J. Sci. Comput. 30, 2008,
//! for Coulomb friction), used to polish the clarabel answer.

use nalgebra::{DMatrix, DVector};

use super::problem::{PointState, Prepared};
use super::residual::{gaps, slips, Previous};
use crate::error::FlankError;

/// Relative tolerance of the state updates (a state changes only when its
/// condition is violated by more than this, in P₀ or δ₀).
const STATE_TOLERANCE: f64 = 1e-12;

/// The totals of an increment for fixed states. Unknowns: P_n on the
/// closed points, P_t on the sticking points (μ > 0), θ; slipping points
/// have P_t = ±μP_n, open points P_n = P_t = 0. Equations: gᵢ = 0 on the
/// closed points, Δσᵢ = 0 on the sticking ones, equilibrium. Scaled
/// (loads by P₀, θ by θ_s, rows by δ₀ and r₀P₀), LU with full pivoting,
/// one step of iterative refinement.
pub(crate) fn solve_states(
    prob: &Prepared,
    prev: &Previous,
    torque: f64,
    state: &[PointState],
) -> Result<(Vec<f64>, Vec<f64>, f64), FlankError> {
    let m = prob.m;
    let mu = &prob.mu;
    let closed: Vec<usize> = (0..m)
        .filter(|&i| state[i] != PointState::Separated)
        .collect();
    let stick: Vec<usize> = if prob.mu_max > 0.0 {
        (0..m).filter(|&i| state[i] == PointState::Stick).collect()
    } else {
        Vec::new()
    };
    // σ for the P_n columns: the slip sign (P_t = σμP_n), 0 for stick
    let sigma = |j: usize| match state[j] {
        PointState::SlipPositive => mu[j],
        PointState::SlipNegative => -mu[j],
        _ => 0.0,
    };
    let (nc, ns) = (closed.len(), stick.len());
    let n = nc + ns + 1;
    let k = prob.p0 / prob.d0;
    let ts = prob.theta_scale();
    let mut a = DMatrix::zeros(n, n);
    let mut b = DVector::zeros(n);
    for (row, &i) in closed.iter().enumerate() {
        for (col, &j) in closed.iter().enumerate() {
            a[(row, col)] = k * (prob.c_nn[(i, j)] + sigma(j) * prob.c_nt[(i, j)]);
        }
        for (col, &j) in stick.iter().enumerate() {
            a[(row, nc + col)] = k * prob.c_nt[(i, j)];
        }
        a[(row, n - 1)] = -prob.r_n[i] * ts / prob.d0;
        b[row] = -prob.g0[i] / prob.d0;
    }
    for (srow, &i) in stick.iter().enumerate() {
        let row = nc + srow;
        // Δσ = ρ(θ − θ_p) − C_tn(P_n − P_n,p) − C_tt(P_t − P_t,p) = 0
        for (col, &j) in closed.iter().enumerate() {
            a[(row, col)] = -k * (prob.c_tn[(i, j)] + sigma(j) * prob.c_tt[(i, j)]);
        }
        for (col, &j) in stick.iter().enumerate() {
            a[(row, nc + col)] = -k * prob.c_tt[(i, j)];
        }
        a[(row, n - 1)] = prob.rho[i] * ts / prob.d0;
        let mut c = prob.rho[i] * prev.theta;
        for j in 0..m {
            c -= prob.c_tn[(i, j)] * prev.pn[j] + prob.c_tt[(i, j)] * prev.pt[j];
        }
        b[row] = c / prob.d0;
    }
    let scale = prob.r0 * prob.p0;
    for (col, &j) in closed.iter().enumerate() {
        a[(n - 1, col)] = (prob.r_n[j] + sigma(j) * prob.r_t[j]) * prob.p0 / scale;
    }
    for (col, &j) in stick.iter().enumerate() {
        a[(n - 1, nc + col)] = prob.r_t[j] * prob.p0 / scale;
    }
    b[n - 1] = torque / scale;
    let lu = a.clone().full_piv_lu();
    let mut x = lu.solve(&b).ok_or_else(|| {
        FlankError::Solver(
            "friction LTCA: the state system of an increment is singular (duplicated points?)"
                .into(),
        )
    })?;
    let res = &b - &a * &x;
    if let Some(dx) = lu.solve(&res) {
        x += dx;
    }
    if x.iter().any(|v| !v.is_finite()) {
        return Err(FlankError::Solver(
            "friction LTCA: non-finite answer of the state system".into(),
        ));
    }
    let mut pn = vec![0.0; m];
    let mut pt = vec![0.0; m];
    for (col, &j) in closed.iter().enumerate() {
        pn[j] = x[col] * prob.p0;
        pt[j] = sigma(j) * pn[j];
    }
    for (col, &j) in stick.iter().enumerate() {
        pt[j] = x[nc + col] * prob.p0;
    }
    Ok((pn, pt, x[n - 1] * ts))
}

/// The next states from an answer of [`solve_states`] (the active-set
/// rule, with a tolerance in favour of the current state): a closed point
/// opens when its load is negative, an open one closes when it
/// penetrates; a sticking point slips when its force leaves the cone (in
/// the force's direction); a slipping point keeps its state while it slips
/// the way its force resists, else sticks, or slips back if the reverse
/// slip exceeds the cone's width (2μP_n/κ); a newly closed point slips
/// with its slip, or sticks if it does not slip.
pub(crate) fn update_states(
    prob: &Prepared,
    state: &[PointState],
    pn: &[f64],
    pt: &[f64],
    gap: &[f64],
    slip: &[f64],
) -> Vec<PointState> {
    let (p0, d0) = (prob.p0, prob.d0);
    let kappa = p0 / d0;
    let eps = STATE_TOLERANCE;
    let sign_state = |v: f64| {
        if v > 0.0 {
            PointState::SlipPositive
        } else {
            PointState::SlipNegative
        }
    };
    (0..prob.m)
        .map(|i| {
            let was_closed = state[i] != PointState::Separated;
            let closed = if was_closed {
                pn[i] >= -eps * p0
            } else {
                gap[i] < -eps * d0
            };
            if !closed {
                return PointState::Separated;
            }
            if prob.mu_max == 0.0 {
                return PointState::Stick;
            }
            let bound = prob.mu[i] * pn[i].max(0.0);
            match state[i] {
                PointState::Stick => {
                    if pt[i].abs() <= bound + eps * p0 {
                        PointState::Stick
                    } else {
                        sign_state(pt[i])
                    }
                }
                PointState::SlipPositive | PointState::SlipNegative => {
                    let s = if state[i] == PointState::SlipPositive {
                        1.0
                    } else {
                        -1.0
                    };
                    if s * slip[i] >= -eps * d0 {
                        state[i]
                    } else if kappa * slip[i].abs() <= 2.0 * bound {
                        PointState::Stick
                    } else {
                        sign_state(slip[i])
                    }
                }
                PointState::Separated => {
                    if slip[i].abs() <= eps * d0 {
                        PointState::Stick
                    } else {
                        sign_state(slip[i])
                    }
                }
            }
        })
        .collect()
}

/// The polished answer.
pub(crate) struct Polished {
    pub(crate) pn: Vec<f64>,
    pub(crate) pt: Vec<f64>,
    pub(crate) theta: f64,
    /// State systems solved.
    pub(crate) iterations: usize,
    /// The states repeated (false: the limit was reached).
    pub(crate) settled: bool,
}

/// Active-set iterations from `start` until the states repeat, at most
/// `max_iterations` state systems.
pub(crate) fn polish(
    prob: &Prepared,
    prev: &Previous,
    torque: f64,
    start: Vec<PointState>,
    max_iterations: usize,
) -> Result<Polished, FlankError> {
    let mut state = start;
    let mut last = None;
    for it in 1..=max_iterations {
        let (pn, pt, theta) = solve_states(prob, prev, torque, &state)?;
        let gap = gaps(prob, &pn, &pt, theta);
        let slip = slips(prob, prev, &pn, &pt, theta);
        let next = update_states(prob, &state, &pn, &pt, &gap, &slip);
        if next == state {
            return Ok(Polished {
                pn,
                pt,
                theta,
                iterations: it,
                settled: true,
            });
        }
        state = next;
        last = Some((pn, pt, theta));
    }
    let (pn, pt, theta) = last.ok_or_else(|| {
        FlankError::Model("friction LTCA: the polish needs at least one iteration".into())
    })?;
    Ok(Polished {
        pn,
        pt,
        theta,
        iterations: max_iterations,
        settled: false,
    })
}
