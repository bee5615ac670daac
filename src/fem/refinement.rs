//! Mixed-precision refinement of a static solve: conjugate gradients on the
//! f64 stiffness, preconditioned by one application of a single-precision
//! factorization (the plain f32 Cholesky, or the two-domain block
//! elimination of [`crate::fem::substructuring`]), iterated to a normwise
//! backward error of f64 round-off ([`crate::fem::residual`]). Not reaching
//! [`MIXED_TOLERANCE`] within [`MAX_REFINEMENT`] steps makes the static
//! solve ([`crate::fem::static_analysis`]) fall back to the f64 factor.

use crate::fem::residual::residual_norms;

/// Backward error at which mixed-precision CG stops (that of a double-
/// precision direct solve is ~1e-16); not reaching it within
/// [`MAX_REFINEMENT`] steps makes the solve fall back to double.
const MIXED_TOLERANCE: f64 = 1e-14;
/// Backward error at which mixed-precision CG stops early: a few units of
/// f64 round-off, as good as a double-precision direct solve.
const MIXED_TARGET: f64 = 2e-16;
/// Maximum iterative-refinement steps.
const MAX_REFINEMENT: usize = 20;

/// Residual b − K q, its relative 2-norm ‖r‖/‖b‖, and the normwise backward
/// error ‖r‖∞ / (‖K‖∞‖q‖∞ + ‖b‖∞) (Higham, *Accuracy and Stability of
/// Numerical Algorithms*, §7.1), with `k_norm` = ‖K‖∞.
fn residual(
    matvec: &dyn Fn(&[f64]) -> Vec<f64>,
    k_norm: f64,
    q: &[f64],
    b: &[f64],
) -> (Vec<f64>, f64, f64) {
    let kq = matvec(q);
    let r: Vec<f64> = b.iter().zip(&kq).map(|(b, k)| b - k).collect();
    let (rel, eta) = residual_norms(&r, k_norm, q, b);
    (r, rel, eta)
}

/// Solves K q = b with `solve` (one application of a factorization; `exact`
/// for a double-precision one). With a single-precision factor the f32
/// Cholesky serves as preconditioner of conjugate gradients on the f64
/// matrix (mixed-precision refinement, cf. Buttari et al., ACM TOMS 34, 2008;
/// CG converges in a few steps where plain iterative refinement would need
/// κ·ε₃₂-limited ones). Returns q, its true relative residual and backward
/// error, or `None` if the backward error did not reach [`MIXED_TOLERANCE`]
/// (the caller falls back to double); `steps` is set to the CG steps taken
/// (0 for an `exact` solve: a fallback to double reports its own solve, not the failed one's steps).
pub(crate) fn solve_refined(
    solve: &dyn Fn(&mut [f64]),
    exact: bool,
    matvec: &dyn Fn(&[f64]) -> Vec<f64>,
    k_norm: f64,
    b: &[f64],
    steps: &mut usize,
) -> Option<(Vec<f64>, f64, f64)> {
    *steps = 0;
    let mut q = b.to_vec();
    solve(&mut q);
    let (mut r, rel0, eta0) = residual(matvec, k_norm, &q, b);
    if exact {
        return Some((q, rel0, eta0));
    }
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let mut z = r.clone();
    solve(&mut z);
    let mut p = z.clone();
    let mut rz = dot(&r, &z);
    let mut eta = eta0;
    // iterate to f64 round-off (MIXED_TARGET) while the backward error still
    // falls; accept the result if it reached MIXED_TOLERANCE
    let mut best = eta;
    let mut stalled = 0;
    while *steps < MAX_REFINEMENT && eta > MIXED_TARGET && stalled < 3 {
        let kp = matvec(&p);
        let pkp = dot(&p, &kp);
        if !(pkp > 0.0) || !rz.is_finite() {
            break;
        }
        let alpha = rz / pkp;
        for i in 0..q.len() {
            q[i] += alpha * p[i];
            r[i] -= alpha * kp[i];
        }
        *steps += 1;
        eta = residual_norms(&r, k_norm, &q, b).1;
        if eta < 0.5 * best {
            best = eta;
            stalled = 0;
        } else {
            stalled += 1;
        }
        if eta <= MIXED_TARGET {
            break;
        }
        z.copy_from_slice(&r);
        solve(&mut z);
        let rz_new = dot(&r, &z);
        let beta = rz_new / rz;
        rz = rz_new;
        for i in 0..p.len() {
            p[i] = z[i] + beta * p[i];
        }
    }
    if !(eta <= MIXED_TOLERANCE) {
        return None;
    }
    let (_, rel, eta) = residual(matvec, k_norm, &q, b);
    Some((q, rel, eta))
}
