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

use super::problem::Prepared;
use super::residual::{gaps, slips, Previous};

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

/// ‖F‖∞, infinite if any entry is not finite (f64::max would drop a NaN).
fn inf_norm(f: &DVector<f64>) -> f64 {
    if f.iter().any(|v| !v.is_finite()) {
        return f64::INFINITY;
    }
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
        // a non-finite start (or F not finite there): nothing to improve
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

#[cfg(test)]
mod tests {
    //! The Newton polish on small problems with known answers (one point
    //! slipping or sticking: the hand formulas of `tests.rs`, check (c)),
    //! at the cone's edge (stick with |P_t| = μP_n exactly, a kink of F),
    //! and degenerate: duplicated points (singular Jacobian, a continuum
    //! of answers), a non-finite start, and its iteration limit.

    use super::*;
    use crate::ltca::friction::residual::residuals;
    use crate::ltca::friction::FrictionProblem;

    /// Owned data of a problem with a block-diagonal compliance (no
    /// coupling between points): per point c_nn, c_nt = c_tn, c_tt.
    struct Points {
        c_nn: Vec<f64>,
        c_nt: Vec<f64>,
        c_tt: Vec<f64>,
        g0: Vec<f64>,
        r_n: Vec<f64>,
        r_t: Vec<f64>,
        s: Vec<f64>,
        mu: f64,
        t: f64,
    }

    impl Points {
        fn prepared(&self, full: Option<(&[f64], &[f64], &[f64])>) -> Prepared {
            let m = self.g0.len();
            let diag = |v: &[f64]| {
                let mut c = vec![0.0; m * m];
                for i in 0..m {
                    c[i * m + i] = v[i];
                }
                c
            };
            let (c_nn, c_nt, c_tt) = match full {
                Some((a, b, c)) => (a.to_vec(), b.to_vec(), c.to_vec()),
                None => (diag(&self.c_nn), diag(&self.c_nt), diag(&self.c_tt)),
            };
            let c_tn: Vec<f64> = (0..m * m).map(|k| c_nt[(k % m) * m + k / m]).collect();
            Prepared::new(&FrictionProblem {
                c_nn: &c_nn,
                c_nt: &c_nt,
                c_tn: &c_tn,
                c_tt: &c_tt,
                separation: &self.g0,
                arm_normal: &self.r_n,
                arm_tangential: &self.r_t,
                sliding: &self.s,
                mu: self.mu,
                point_mu: None,
                torque: self.t,
            })
            .unwrap()
        }
    }

    /// The residuals of a Newton answer for the first increment (from the
    /// rigid start, no load) to the whole torque.
    fn graded(prob: &Prepared, prev: &Previous, n: &NewtonAnswer) -> f64 {
        let gap = gaps(prob, &n.pn, &n.pt, n.theta);
        let slip = slips(prob, prev, &n.pn, &n.pt, n.theta);
        residuals(prob, prob.torque, &n.pn, &n.pt, &gap, &slip).max
    }

    fn one_point(s: f64) -> Points {
        Points {
            c_nn: vec![2e-5],
            c_nt: vec![1e-6],
            c_tt: vec![1.5e-5],
            g0: vec![1e-3],
            r_n: vec![40.0],
            r_t: vec![12.0],
            s: vec![s],
            mu: 0.1,
            t: 5e4,
        }
    }

    // One point, slipping forward (s = 5): P_n = T/(r_n + μr_t),
    // P_t = μP_n, θ = (g⁰ + (c_nn + μc_nt)P_n)/r_n; sticking (ρ = 0):
    // P_t = −(c_tn/c_tt)P_n, P_n = T/(r_n − r_t c_tn/c_tt),
    // θ = (g⁰ + (c_nn − c_nt c_tn/c_tt)P_n)/r_n. From a start 20 % off
    // (and from the unloaded start), to 1e-12.
    #[test]
    fn one_point_known_answers() {
        let (c, b, e, g0, rn, rt, mu, t) = (2e-5, 1e-6, 1.5e-5, 1e-3, 40.0, 12.0, 0.1, 5e4);
        let slip_pn = t / (rn + mu * rt);
        let stick_pn = t / (rn - rt * b / e);
        let cases = [
            (
                5.0,
                slip_pn,
                mu * slip_pn,
                (g0 + (c + mu * b) * slip_pn) / rn,
            ),
            (
                -rt / rn,
                stick_pn,
                -b / e * stick_pn,
                (g0 + (c - b * b / e) * stick_pn) / rn,
            ),
        ];
        for (s, pn, pt, th) in cases {
            let d = one_point(s);
            let prob = d.prepared(None);
            let zero = [0.0];
            let prev = Previous {
                pn: &zero,
                pt: &zero,
                theta: prob.start_rotation(),
            };
            for (p, q, r) in [(1.2 * pn, 0.8 * pt, 1.1 * th), (0.0, 0.0, prev.theta)] {
                let n = newton(&prob, &prev, t, &[p], &[q], r, 50);
                assert_eq!(n.end, NewtonEnd::Converged, "s = {s}: {:?}", n.norm);
                assert!(n.iterations <= 10, "s = {s}: {} iterations", n.iterations);
                assert!((n.pn[0] - pn).abs() <= 1e-12 * pn, "{} vs {pn}", n.pn[0]);
                assert!((n.pt[0] - pt).abs() <= 1e-12 * pn, "{} vs {pt}", n.pt[0]);
                assert!((n.theta - th).abs() <= 1e-12 * th, "{} vs {th}", n.theta);
                assert!(graded(&prob, &prev, &n) <= 1e-12);
            }
        }
    }

    // Three points at the cone's edge and one open: ρ = 0 and
    // c_tn/c_tt = −μ, so sticking (Δσ = 0) gives P_t = μP_n exactly, a
    // point where the stick and slip branches of F meet (both are valid
    // Jacobians). Known answer: P_n,i = (r_n,i θ − g⁰ᵢ)/(c_nn + μc_nt) on
    // the closed points, θ from Σ(r_n + μr_t)P_n = T. Starts on either
    // side of the edge converge to it.
    #[test]
    fn cone_edge() {
        let (c, e, mu) = (2e-5, 1.5e-5, 0.1);
        let b = -mu * e;
        let r_n = vec![40.0, 42.0, 44.0, 46.0];
        let r_t = vec![6.0, -4.0, 2.0, 8.0];
        let d = Points {
            c_nn: vec![c; 4],
            c_nt: vec![b; 4],
            c_tt: vec![e; 4],
            g0: vec![0.0, 1e-4, 2e-4, 1.0],
            s: (0..4).map(|i| -r_t[i] / r_n[i]).collect(),
            r_n: r_n.clone(),
            r_t: r_t.clone(),
            mu,
            t: 1e5,
        };
        let prob = d.prepared(None);
        let k = c + mu * b;
        // θ with points 0..3 closed
        let (num, den) = (0..3).fold((d.t, 0.0), |(a, w), i| {
            let f = (r_n[i] + mu * r_t[i]) / k;
            (a + f * d.g0[i], w + f * r_n[i])
        });
        let th = num / den;
        let pn: Vec<f64> = (0..4)
            .map(|i| {
                if i < 3 {
                    (r_n[i] * th - d.g0[i]) / k
                } else {
                    0.0
                }
            })
            .collect();
        assert!(pn.iter().take(3).all(|&p| p > 0.0));
        assert!(r_n[3] * th < d.g0[3]);
        let zero = [0.0; 4];
        let prev = Previous {
            pn: &zero,
            pt: &zero,
            theta: prob.start_rotation(),
        };
        for (fn_, ft) in [(1.1, 0.9), (0.9, 1.1), (1.0, 1.0 + 1e-9), (1.0, 1.0 - 1e-9)] {
            let p: Vec<f64> = pn.iter().map(|v| fn_ * v).collect();
            let q: Vec<f64> = pn.iter().map(|v| ft * mu * v).collect();
            let n = newton(&prob, &prev, d.t, &p, &q, th * fn_, 50);
            assert_eq!(n.end, NewtonEnd::Converged, "{fn_} {ft}: {:?}", n.norm);
            for i in 0..4 {
                assert!((n.pn[i] - pn[i]).abs() <= 1e-12 * pn[0], "{i}: {:?}", n.pn);
                assert!(
                    (n.pt[i] - mu * pn[i]).abs() <= 1e-12 * pn[0],
                    "{i}: {:?}",
                    n.pt
                );
            }
            assert!((n.theta - th).abs() <= 1e-12 * th.abs());
            assert!(graded(&prob, &prev, &n) <= 1e-12);
        }
    }

    // Two copies of one sticking point: the compliance is singular, the
    // Jacobian has two equal rows wherever both are closed and stick, and
    // any split of the loads with each force in its cone is an answer. The
    // Newton polish must not panic or give NaN; it gets to an answer
    // (residual ≤ 1e-12) through the Levenberg–Marquardt direction.
    // Further: a NaN start stops at once (`Stalled`), and one iteration
    // from far away reports its limit.
    #[test]
    fn singular_and_degenerate_starts() {
        let one = one_point(-12.0 / 40.0);
        let d = Points {
            c_nn: vec![],
            c_nt: vec![],
            c_tt: vec![],
            g0: vec![one.g0[0]; 2],
            r_n: vec![one.r_n[0]; 2],
            r_t: vec![one.r_t[0]; 2],
            s: vec![one.s[0]; 2],
            mu: one.mu,
            t: one.t,
        };
        let prob = d.prepared(Some((
            &[one.c_nn[0]; 4],
            &[one.c_nt[0]; 4],
            &[one.c_tt[0]; 4],
        )));
        let zero = [0.0; 2];
        let prev = Previous {
            pn: &zero,
            pt: &zero,
            theta: prob.start_rotation(),
        };
        let (b, e) = (one.c_nt[0], one.c_tt[0]);
        let total = one.t / (one.r_n[0] - one.r_t[0] * b / e);
        let n = newton(
            &prob,
            &prev,
            d.t,
            &[0.7 * total, 0.4 * total],
            &[0.0, -0.01 * total],
            1e-3,
            50,
        );
        assert!(n.pn.iter().chain(&n.pt).all(|v| v.is_finite()) && n.theta.is_finite());
        assert!(n.norm.is_finite() && n.norm <= n.start_norm);
        let r = graded(&prob, &prev, &n);
        println!(
            "duplicated point: {:?} after {} iterations ({} Levenberg–Marquardt), residual {r:.1e}",
            n.end, n.iterations, n.fallbacks
        );
        assert!(r <= 1e-12, "{r:.2e} after {} ({:?})", n.iterations, n.end);
        assert!(n.fallbacks >= 1, "the singular Jacobian went unnoticed");
        assert!(((n.pn[0] + n.pn[1]) - total).abs() <= 1e-12 * total);
        assert!(((n.pt[0] + n.pt[1]) + b / e * total).abs() <= 1e-12 * total);

        let n = newton(&prob, &prev, d.t, &[f64::NAN, 0.0], &[0.0; 2], 1e-3, 50);
        assert_eq!((n.end, n.iterations), (NewtonEnd::Stalled, 0));

        let n = newton(&prob, &prev, d.t, &[0.0; 2], &[0.0; 2], prev.theta, 1);
        assert_eq!((n.end, n.iterations), (NewtonEnd::Limit, 1));
        assert!(n.norm < n.start_norm);
    }
}
