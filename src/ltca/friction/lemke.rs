//! The independent second method: each increment as a linear
//! complementarity problem, solved by Lemke's complementary pivoting
//! (Lemke 1965; Cottle, Pang & Stone, *The Linear Complementarity
//! Problem*, 1992, §4.4 (the method) and §4.9 (lexicographic degeneracy
//! resolution); Murty, *Linear Complementarity, Linear and Nonlinear
//! Programming*, 1988, ch. 2).
//!
//! # The LCP of increment k
//!
//! Unknowns z ≥ 0, scaled: p = P_n/P₀; the friction split
//! P_t = P₀(β⁺ − β⁻); the slip magnitude λ (in δ₀); θ′ with
//! θ = θ_{k−1} + θ_s(θ′ − c) (θ_s = δ₀/r₀, c a shift that lets the
//! rotation decrease: c = 1 first, ×10 on a retry). With
//! Δσ̂ = Δσ/δ₀ = ρ̂(θ′ − c) − K[C_tn(p − p_{k−1}) + C_tt(β⁺ − β⁻ − p_{t,k−1})],
//! K = P₀/δ₀, r̂ = r/r₀, ρ̂ = ρ/r₀, the complementary pairs are
//!
//! ```text
//!   g/δ₀ = (g⁰ − r_n θ_{k−1})/δ₀ + K C_nn p + K C_nt (β⁺ − β⁻) − r̂_n(θ′ − c) ≥ 0  ⟂ p ≥ 0
//!   λ − Δσ̂ ≥ 0                                                                ⟂ β⁺ ≥ 0
//!   λ + Δσ̂ ≥ 0                                                                ⟂ β⁻ ≥ 0
//!   μ p − β⁺ − β⁻ ≥ 0                                                         ⟂ λ ≥ 0
//!   r̂_nᵀp + r̂_tᵀ(β⁺ − β⁻) − T_k/(r₀P₀) ≥ 0                                    ⟂ θ′ ≥ 0
//! ```
//!
//! The second to fourth rows are Coulomb's law in 2D (Klarbring 1986):
//! slip Δσ > 0 forces λ = Δσ, β⁻ = 0 and β⁺ = μp; no slip allows any
//! force in the cone. The last row is the equilibrium: at any solution
//! θ′ > 0 (a rotation c·θ_s below θ_{k−1} opens every point and cannot
//! carry T_k), so it holds with equality; a solution with θ′ = 0 and the
//! row slack means c was too small, and the LCP is rebuilt with 10 c (at
//! most [`SHIFT_RETRIES`] times). With μ = 0 only p and θ′ remain (the
//! frictionless LCP).
//!
//! # Lemke's method
//!
//! w = q + A z + d z₀ with the covering vector d = 1. Start: z₀ enters
//! at the row of the most negative qᵢ; then the complement of the variable
//! that left enters, each time by the minimum-ratio test, ties broken
//! lexicographically on the rows of B⁻¹ (divided by the pivot column),
//! which excludes cycling; z₀ leaves as soon as it is among the tied rows.
//! Termination: z₀ leaves (a solution), no blocking row (a secondary ray:
//! an error), or the pivot limit (an error). The dense tableau B⁻¹[I, −A,
//! −d | q] is updated by Gauss–Jordan pivots; at the end the basic
//! variables are recomputed from the original data (LU of the basis
//! columns, one refinement step), so the answer carries the round-off of
//! one factorization, not of all pivots.

use nalgebra::{DMatrix, DVector};

use super::problem::{FrictionOptions, Prepared, StepAnswer};
use super::residual::Previous;
use crate::error::FlankError;

/// Rebuilds of the LCP with a wider rotation shift before giving up.
pub const SHIFT_RETRIES: usize = 6;

/// Pivot-column entries at most this fraction of the column's largest
/// are not eligible pivots.
const PIVOT_TOLERANCE: f64 = 1e-11;

/// Ratios within this distance of the minimum, relative to max(1, the
/// minimum), are ties (the scaled variables are O(1), so a degenerate
/// zero ratio and a round-off ratio of 1e-17 tie).
const TIE_TOLERANCE: f64 = 1e-10;

/// Lemke's answer of w = q + A z.
pub(crate) struct LemkeAnswer {
    pub(crate) z: Vec<f64>,
    pub(crate) w: Vec<f64>,
    pub(crate) pivots: usize,
}

/// Lemke's method with the lexicographic ratio test (module doc).
pub(crate) fn lemke(
    a: &DMatrix<f64>,
    q: &[f64],
    max_pivots: usize,
) -> Result<LemkeAnswer, FlankError> {
    let n = q.len();
    if q.iter().all(|&v| v >= 0.0) {
        return Ok(LemkeAnswer {
            z: vec![0.0; n],
            w: q.to_vec(),
            pivots: 0,
        });
    }
    // variables: 0..n w, n..2n z, 2n z₀; tableau row-major n × (2n + 1)
    let cols = 2 * n + 1;
    let z0 = 2 * n;
    let mut tab = vec![0.0; n * cols];
    for i in 0..n {
        tab[i * cols + i] = 1.0;
        for j in 0..n {
            tab[i * cols + n + j] = -a[(i, j)];
        }
        tab[i * cols + z0] = -1.0;
    }
    let mut rhs = q.to_vec();
    let mut basis: Vec<usize> = (0..n).collect();
    let pivot = |tab: &mut [f64], rhs: &mut [f64], r: usize, c: usize| {
        let pv = tab[r * cols + c];
        for v in &mut tab[r * cols..(r + 1) * cols] {
            *v /= pv;
        }
        rhs[r] /= pv;
        let (row_r, rr) = (tab[r * cols..(r + 1) * cols].to_vec(), rhs[r]);
        for i in 0..n {
            if i == r {
                continue;
            }
            let f = tab[i * cols + c];
            if f != 0.0 {
                for (v, &p) in tab[i * cols..(i + 1) * cols].iter_mut().zip(&row_r) {
                    *v -= f * p;
                }
                rhs[i] -= f * rr;
                tab[i * cols + c] = 0.0;
            }
        }
    };
    // first pivot: z₀ in, the most negative q out (ties: lexicographic on
    // the rows of B⁻¹ = I divided by the column entry −1: the largest index)
    let qmin = q.iter().fold(f64::INFINITY, |a, &v| a.min(v));
    let r = (0..n).rev().find(|&i| q[i] == qmin).unwrap_or(0);
    pivot(&mut tab, &mut rhs, r, z0);
    let mut entering = n + basis[r]; // complement of w_r
    basis[r] = z0;
    let mut pivots = 1;
    loop {
        if pivots >= max_pivots {
            // the artificial variable z₀ still in the basis measures how far
            // the almost-complementary point is from a solution (0 there)
            let z0_value = (0..n).find(|&i| basis[i] == z0).map_or(0.0, |i| rhs[i]);
            return Err(FlankError::Solver(format!(
                "friction LTCA Lemke: pivot limit {max_pivots} (FrictionOptions::max_pivots) reached with the artificial variable z₀ = {z0_value:.3e} (0 at a solution)"
            )));
        }
        let c = entering;
        let colmax = (0..n).fold(0.0f64, |m, i| m.max(tab[i * cols + c].abs()));
        let eligible: Vec<usize> = (0..n)
            .filter(|&i| tab[i * cols + c] > PIVOT_TOLERANCE * colmax)
            .collect();
        if eligible.is_empty() {
            return Err(FlankError::Solver(format!(
                "friction LTCA Lemke: secondary ray after {pivots} pivots (no solution found; friction too large for the method?)"
            )));
        }
        let ratio = |i: usize| rhs[i].max(0.0) / tab[i * cols + c];
        let rmin = eligible.iter().fold(f64::INFINITY, |m, &i| m.min(ratio(i)));
        let mut ties: Vec<usize> = eligible
            .into_iter()
            .filter(|&i| ratio(i) <= rmin + TIE_TOLERANCE * rmin.abs().max(1.0))
            .collect();
        let leave_row = if let Some(&i) = ties.iter().find(|&&i| basis[i] == z0) {
            i
        } else {
            // lexicographic: compare (B⁻¹)_{i,·} / column entry, column by column
            let mut j = 0;
            while ties.len() > 1 && j < n {
                let val = |i: usize| tab[i * cols + j] / tab[i * cols + c];
                let vmin = ties.iter().fold(f64::INFINITY, |m, &i| m.min(val(i)));
                let vmax = ties.iter().fold(f64::NEG_INFINITY, |m, &i| m.max(val(i)));
                let tol = TIE_TOLERANCE * vmin.abs().max(vmax.abs()).max(1e-300);
                ties.retain(|&i| val(i) <= vmin + tol);
                j += 1;
            }
            ties[0]
        };
        pivot(&mut tab, &mut rhs, leave_row, c);
        pivots += 1;
        let left = basis[leave_row];
        basis[leave_row] = c;
        if left == z0 {
            break;
        }
        entering = if left < n { left + n } else { left - n };
    }
    // the basic variables from the original data
    let mut b = DMatrix::zeros(n, n);
    for (k, &v) in basis.iter().enumerate() {
        for i in 0..n {
            b[(i, k)] = if v < n {
                if i == v {
                    1.0
                } else {
                    0.0
                }
            } else if v < 2 * n {
                -a[(i, v - n)]
            } else {
                -1.0
            };
        }
    }
    let qv = DVector::from_column_slice(q);
    let lu = b.clone().lu();
    let x = match lu.solve(&qv) {
        Some(mut x) => {
            let res = &qv - &b * &x;
            if let Some(dx) = lu.solve(&res) {
                x += dx;
            }
            x
        }
        None => DVector::from_column_slice(&rhs),
    };
    let mut val = vec![0.0; 2 * n + 1];
    for (k, &v) in basis.iter().enumerate() {
        val[v] = x[k];
    }
    Ok(LemkeAnswer {
        w: val[..n].to_vec(),
        z: val[n..2 * n].to_vec(),
        pivots,
    })
}

/// The LCP of the increment (module doc) for shift `c`.
fn build(prob: &Prepared, prev: &Previous, torque: f64, c: f64) -> (DMatrix<f64>, Vec<f64>) {
    let m = prob.m;
    let f = if prob.mu_max > 0.0 { m } else { 0 };
    let n = m + 3 * f + 1;
    let (bp, bm, lam, th) = (m, m + f, m + 2 * f, m + 3 * f);
    let k = prob.p0 / prob.d0;
    let r0 = prob.r0;
    let mut a = DMatrix::zeros(n, n);
    let mut q = vec![0.0; n];
    let pnp: Vec<f64> = prev.pn.iter().map(|v| v / prob.p0).collect();
    let ptp: Vec<f64> = prev.pt.iter().map(|v| v / prob.p0).collect();
    for i in 0..m {
        q[i] = (prob.g0[i] - prob.r_n[i] * prev.theta) / prob.d0 + prob.r_n[i] / r0 * c;
        for j in 0..m {
            a[(i, j)] = k * prob.c_nn[(i, j)];
        }
        a[(i, th)] = -prob.r_n[i] / r0;
    }
    for i in 0..f {
        let rho = prob.rho[i] / r0;
        let mut cst = 0.0;
        for j in 0..m {
            cst += k * (prob.c_tn[(i, j)] * pnp[j] + prob.c_tt[(i, j)] * ptp[j]);
        }
        // λ − Δσ̂: Δσ̂ = ρ̂(θ′ − c) − K C_tn p − K C_tt(β⁺ − β⁻) + cst
        q[bp + i] = rho * c - cst;
        q[bm + i] = -rho * c + cst;
        for j in 0..m {
            a[(i, bp + j)] = k * prob.c_nt[(i, j)];
            a[(i, bm + j)] = -k * prob.c_nt[(i, j)];
            a[(bp + i, j)] = k * prob.c_tn[(i, j)];
            a[(bp + i, bp + j)] = k * prob.c_tt[(i, j)];
            a[(bp + i, bm + j)] = -k * prob.c_tt[(i, j)];
            a[(bm + i, j)] = -k * prob.c_tn[(i, j)];
            a[(bm + i, bp + j)] = -k * prob.c_tt[(i, j)];
            a[(bm + i, bm + j)] = k * prob.c_tt[(i, j)];
        }
        a[(bp + i, lam + i)] = 1.0;
        a[(bm + i, lam + i)] = 1.0;
        a[(bp + i, th)] = -rho;
        a[(bm + i, th)] = rho;
        a[(lam + i, i)] = prob.mu[i];
        a[(lam + i, bp + i)] = -1.0;
        a[(lam + i, bm + i)] = -1.0;
        a[(th, bp + i)] = prob.r_t[i] / r0;
        a[(th, bm + i)] = -prob.r_t[i] / r0;
    }
    for j in 0..m {
        a[(th, j)] = prob.r_n[j] / r0;
    }
    q[th] = -torque / (r0 * prob.p0);
    (a, q)
}

/// Increment k by Lemke's method (module doc).
pub(crate) fn step(
    prob: &Prepared,
    prev: &Previous,
    torque: f64,
    options: &FrictionOptions,
) -> Result<StepAnswer, FlankError> {
    let m = prob.m;
    let f = if prob.mu_max > 0.0 { m } else { 0 };
    let th = m + 3 * f;
    let mut c = 1.0;
    for retry in 0..=SHIFT_RETRIES {
        let (a, q) = build(prob, prev, torque, c);
        let ans = lemke(&a, &q, options.max_pivots)?;
        // θ′ = 0 with the equilibrium row slack: the shift was too small
        if ans.z[th] <= 0.0 && ans.w[th] > 1e-9 {
            c *= 10.0;
            continue;
        }
        let pn: Vec<f64> = ans.z[..m].iter().map(|v| v * prob.p0).collect();
        let pt: Vec<f64> = (0..m)
            .map(|i| {
                if f > 0 {
                    (ans.z[m + i] - ans.z[m + f + i]) * prob.p0
                } else {
                    0.0
                }
            })
            .collect();
        let theta = prev.theta + prob.theta_scale() * (ans.z[th] - c);
        return Ok(StepAnswer {
            pn,
            pt,
            theta,
            iterations: ans.pivots,
            inner_iterations: retry,
            polish_iterations: 0,
            polished: false,
            newton_iterations: 0,
            newton: false,
            limit_hit: false,
        });
    }
    Err(FlankError::Solver(format!(
        "friction LTCA Lemke: the rotation shift reached {c:.1e} rotation scales without an equilibrium answer"
    )))
}
