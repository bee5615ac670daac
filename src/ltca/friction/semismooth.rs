//! The globalised semismooth Newton polish of an increment: the
//! increment's conditions (module doc of [`super`]) as one nonsmooth
//! system F(P_n, P_t, θ) = 0, solved by Newton's method on a generalized
//! Jacobian with a backtracking line search on the merit ½‖F‖².
//!
//! # The equations
//!
//! With κ = P₀/δ₀ (the same weight as in the residual of `residual.rs`),
//! bᵢ = μᵢ max(P_n,i, 0) and yᵢ = P_t,i + κΔσᵢ, per point i
//!
//! ```text
//!   F_n,i = min(P_n,i, κ gᵢ)                         (natural map of g ≥ 0 ⟂ P_n ≥ 0)
//!   F_t,i = P_t,i − proj_[−bᵢ, bᵢ](yᵢ)                (Coulomb: the projection on the segment)
//! ```
//!
//! and the equilibrium F_eq = Σ r_n P_n + r_t P_t − T_k. F = 0 exactly when
//! every residual of `residual.rs` is zero: F_t is its Coulomb natural map,
//! and min(P_n, κg) = 0 is P_n ≥ 0, g ≥ 0, P_n g = 0. This is the
//! augmented-Lagrangian form of frictional contact of Alart & Curnier
//! (Comput. Methods Appl. Mech. Engrg. 92, 1991), with the friction bound
//! taken at P_n itself rather than at the augmented normal multiplier (both
//! agree at a solution), and the natural-map reformulation of a
//! complementarity problem (Facchinei & Pang, *Finite-Dimensional
//! Variational Inequalities and Complementarity Problems*, 2003, §1.5 and
//! ch. 7–8). Christensen, Klarbring, Pang & Strömberg (Int. J. Numer.
//! Meth. Engng 42, 1998) solve the same kind of system by a semismooth
//! Newton method with a line search; F is piecewise linear here (the
//! increment is linear in its unknowns for fixed states), so it is
//! strongly semismooth.
//!
//! # The method
//!
//! Scaled unknowns x = (P_n/P₀, P_t/P₀, (θ − θ_{k−1})/θ_s), scaled
//! equations (F_n, F_t over P₀, F_eq over r₀P₀). Per iteration one
//! element J of the B-subdifferential: the branch of each min and
//! projection taken where its argument lies (at a kink, the branch of the
//! closed, sticking point; every choice is an element), so that J is the
//! matrix of the state system of the states the iterate implies
//! (`polish.rs`) — the primal–dual active-set method is this Newton
//! method with full steps (Hintermüller, Ito & Kunisch, SIAM J. Optim. 13,
//! 2002), and that is what cycles on points at the cone's edge. Here:
//!
//! 1. d from J d = −F (LU with full pivoting, one refinement step);
//! 2. Armijo backtracking on ψ = ½‖F‖²: the largest α = 2⁻ʲ
//!    (j < [`MAX_BACKTRACKS`]) with ψ(x + αd) ≤ (1 − 2σα) ψ(x), σ = 10⁻⁴
//!    (the Newton direction's directional derivative of ψ is −2ψ);
//! 3. if J is singular, d is not finite, or no α is accepted: the
//!    Levenberg–Marquardt direction (JᵀJ + λI) d = −JᵀF, λ = ‖F‖ (plus a
//!    floor), a descent direction of ψ that always exists, with the
//!    Armijo test on its directional derivative −(JᵀF)ᵀd;
//! 4. if neither direction decreases ψ the iteration stops (it has
//!    reached round-off, or a point where J is useless), with the best
//!    iterate.
//!
//! It stops when ‖F‖∞ (scaled) is at most [`STOP`] (round-off), stalls, or
//! reaches its iteration limit, and says which. It is used from a nearby
//! start (the Tresca answer of the fixed point), where the local
//! superlinear convergence of semismooth Newton applies when every
//! element of the B-subdifferential at the answer is regular
//! (BD-regularity; Qi & Sun, Math. Program. 58, 1993).

use nalgebra::{DMatrix, DVector};

use super::residual::{gaps, slips, Previous};
use super::Prepared;

/// Armijo constant σ.
const ARMIJO: f64 = 1e-4;

/// Halvings of the step before the direction is given up.
pub const MAX_BACKTRACKS: usize = 40;

/// ‖F‖∞ of the scaled system at which the iteration stops (round-off of
/// O(1) scaled quantities).
pub const STOP: f64 = 1e-15;

/// How the Newton iteration ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum NewtonEnd {
    /// ‖F‖∞ ≤ [`STOP`].
    Converged,
    /// Neither the Newton nor the Levenberg–Marquardt direction decreased
    /// the merit (round-off floor or a useless Jacobian).
    Stalled,
    /// The iteration limit was reached.
    Limit,
}

/// The answer of [`newton`]: the last accepted iterate (the merit
/// decreases monotonically, so also the best). `fallbacks`, `start_norm`
/// and `norm` are diagnostics read by the unit tests.
#[cfg_attr(not(test), allow(dead_code))]
pub(crate) struct NewtonAnswer {
    pub(crate) pn: Vec<f64>,
    pub(crate) pt: Vec<f64>,
    pub(crate) theta: f64,
    /// Newton iterations (Jacobians formed).
    pub(crate) iterations: usize,
    /// Iterations that fell back to the Levenberg–Marquardt direction.
    pub(crate) fallbacks: usize,
    /// ‖F‖∞ (scaled) at the start and at the answer.
    pub(crate) start_norm: f64,
    pub(crate) norm: f64,
    pub(crate) end: NewtonEnd,
}

/// The scaled residual F at x, and the branch data for the Jacobian.
struct Eval {
    f: DVector<f64>,
    /// Per point: the normal branch is closed (F_n = κg).
    closed: Vec<bool>,
    /// Per point: 0 stick (F_t = −κΔσ), +1 / −1 the projection at ±b.
    slip: Vec<i8>,
}

/// Totals from scaled x.
fn unscale(prob: &Prepared, prev: &Previous, x: &DVector<f64>) -> (Vec<f64>, Vec<f64>, f64) {
    let m = prob.m;
    let pn = (0..m).map(|i| x[i] * prob.p0).collect();
    let pt = (0..m).map(|i| x[m + i] * prob.p0).collect();
    (pn, pt, prev.theta + x[2 * m] * prob.theta_scale())
}

fn evaluate(prob: &Prepared, prev: &Previous, torque: f64, x: &DVector<f64>) -> Eval {
    let m = prob.m;
    let (p0, d0) = (prob.p0, prob.d0);
    let kappa = p0 / d0;
    let (pn, pt, theta) = unscale(prob, prev, x);
    let gap = gaps(prob, &pn, &pt, theta);
    let slip = slips(prob, prev, &pn, &pt, theta);
    let mut f = DVector::zeros(2 * m + 1);
    let mut closed = vec![false; m];
    let mut state = vec![0i8; m];
    let mut moment = 0.0;
    for i in 0..m {
        // min(P_n, κg): the closed branch at a tie
        closed[i] = kappa * gap[i] <= pn[i];
        f[i] = if closed[i] { gap[i] / d0 } else { pn[i] / p0 };
        let b = prob.mu[i] * pn[i].max(0.0);
        let y = pt[i] + kappa * slip[i];
        // the stick branch at a tie (and for b = 0 the projection onto {0})
        state[i] = if b > 0.0 && y.abs() <= b {
            0
        } else if y >= 0.0 {
            1
        } else {
            -1
        };
        f[m + i] = match state[i] {
            0 => -slip[i] / d0,
            s => (pt[i] - f64::from(s) * b) / p0,
        };
        moment += prob.r_n[i] * pn[i] + prob.r_t[i] * pt[i];
    }
    f[2 * m] = (moment - torque) / (prob.r0 * p0);
    Eval {
        f,
        closed,
        slip: state,
    }
}

/// The element of the B-subdifferential of the branches in `e` at x.
fn jacobian(prob: &Prepared, x: &DVector<f64>, e: &Eval) -> DMatrix<f64> {
    let m = prob.m;
    let n = 2 * m + 1;
    let k = prob.p0 / prob.d0;
    let r0 = prob.r0;
    let mut j = DMatrix::zeros(n, n);
    for i in 0..m {
        if e.closed[i] {
            for c in 0..m {
                j[(i, c)] = k * prob.c_nn[(i, c)];
                j[(i, m + c)] = k * prob.c_nt[(i, c)];
            }
            j[(i, n - 1)] = -prob.r_n[i] / r0;
        } else {
            j[(i, i)] = 1.0;
        }
        let row = m + i;
        match e.slip[i] {
            0 => {
                for c in 0..m {
                    j[(row, c)] = k * prob.c_tn[(i, c)];
                    j[(row, m + c)] = k * prob.c_tt[(i, c)];
                }
                j[(row, n - 1)] = -prob.rho[i] / r0;
            }
            s => {
                j[(row, m + i)] = 1.0;
                if x[i] > 0.0 {
                    j[(row, i)] = -f64::from(s) * prob.mu[i];
                }
            }
        }
        j[(n - 1, i)] = prob.r_n[i] / r0;
        j[(n - 1, m + i)] = prob.r_t[i] / r0;
    }
    j
}

fn merit(f: &DVector<f64>) -> f64 {
    0.5 * f.norm_squared()
}

fn inf_norm(f: &DVector<f64>) -> f64 {
    f.iter().fold(0.0f64, |a, v| a.max(v.abs()))
}

/// The Newton direction J d = −F, if J is regular and d finite.
fn newton_direction(j: &DMatrix<f64>, f: &DVector<f64>) -> Option<DVector<f64>> {
    let lu = j.clone().full_piv_lu();
    let rhs = -f;
    let mut d = lu.solve(&rhs)?;
    let res = &rhs - j * &d;
    if let Some(dd) = lu.solve(&res) {
        d += dd;
    }
    d.iter().all(|v| v.is_finite()).then_some(d)
}

/// The Levenberg–Marquardt direction (JᵀJ + λI) d = −JᵀF with λ = ‖F‖ +
/// 10⁻¹² max(1, max diag JᵀJ) (positive definite, so it exists).
fn lm_direction(j: &DMatrix<f64>, f: &DVector<f64>) -> Option<DVector<f64>> {
    let mut a = j.transpose() * j;
    let g = j.transpose() * f;
    let dmax = a.diagonal().iter().fold(1.0f64, |s, v| s.max(*v));
    let lambda = f.norm() + 1e-12 * dmax;
    for i in 0..a.nrows() {
        a[(i, i)] += lambda;
    }
    let d = a.cholesky()?.solve(&(-g));
    d.iter().all(|v| v.is_finite()).then_some(d)
}

/// Backtracking from x along d: the accepted point and its evaluation,
/// for a directional derivative `slope` of ψ (negative).
fn line_search(
    prob: &Prepared,
    prev: &Previous,
    torque: f64,
    x: &DVector<f64>,
    psi: f64,
    d: &DVector<f64>,
    slope: f64,
) -> Option<(DVector<f64>, Eval)> {
    if !(slope < 0.0) {
        return None;
    }
    let mut alpha = 1.0;
    for _ in 0..MAX_BACKTRACKS {
        let xn = x + alpha * d;
        let e = evaluate(prob, prev, torque, &xn);
        let pn = merit(&e.f);
        if pn.is_finite() && pn <= psi + ARMIJO * alpha * slope {
            return Some((xn, e));
        }
        alpha *= 0.5;
    }
    None
}

/// The globalised semismooth Newton method (module doc) from the totals
/// (P_n, P_t, θ) of a nearby answer, at most `max_iterations` Jacobians.
/// Never fails: a non-finite start or a singular Jacobian ends in the
/// fallback or `Stalled`; the caller grades the answer by its residuals.
pub(crate) fn newton(
    prob: &Prepared,
    prev: &Previous,
    torque: f64,
    pn: &[f64],
    pt: &[f64],
    theta: f64,
    max_iterations: usize,
) -> NewtonAnswer {
    let m = prob.m;
    let mut x = DVector::zeros(2 * m + 1);
    for i in 0..m {
        x[i] = pn[i] / prob.p0;
        x[m + i] = pt[i] / prob.p0;
    }
    x[2 * m] = (theta - prev.theta) / prob.theta_scale();
    let mut e = evaluate(prob, prev, torque, &x);
    let start_norm = inf_norm(&e.f);
    let answer = |x: &DVector<f64>, e: &Eval, iterations, fallbacks, end| {
        let (pn, pt, theta) = unscale(prob, prev, x);
        NewtonAnswer {
            pn,
            pt,
            theta,
            iterations,
            fallbacks,
            start_norm,
            norm: inf_norm(&e.f),
            end,
        }
    };
    if !start_norm.is_finite() {
        return answer(&x, &e, 0, 0, NewtonEnd::Stalled);
    }
    let mut fallbacks = 0;
    for it in 0..max_iterations {
        if inf_norm(&e.f) <= STOP {
            return answer(&x, &e, it, fallbacks, NewtonEnd::Converged);
        }
        let psi = merit(&e.f);
        let j = jacobian(prob, &x, &e);
        // the Newton direction: ψ'(x; d) = Fᵀ J d = −2ψ
        let step = newton_direction(&j, &e.f)
            .and_then(|d| line_search(prob, prev, torque, &x, psi, &d, -2.0 * psi));
        let step = match step {
            Some(s) => Some(s),
            None => {
                fallbacks += 1;
                lm_direction(&j, &e.f).and_then(|d| {
                    let slope = (j.transpose() * &e.f).dot(&d);
                    line_search(prob, prev, torque, &x, psi, &d, slope)
                })
            }
        };
        match step {
            Some((xn, en)) => {
                x = xn;
                e = en;
            }
            None => return answer(&x, &e, it + 1, fallbacks, NewtonEnd::Stalled),
        }
    }
    let end = if inf_norm(&e.f) <= STOP {
        NewtonEnd::Converged
    } else {
        NewtonEnd::Limit
    };
    answer(&x, &e, max_iterations, fallbacks, end)
}
