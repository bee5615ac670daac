//! The dedicated primal active-set solver of the contact QP (see the
//! module doc of [`super`]): the equality-constrained solve on a loaded
//! set (Cholesky of F_SS with regularization, Schur complement), the cold
//! start and the iterations (additions of penetrating points, ratio test).

use nalgebra::{DMatrix, DVector};

use super::problem::{
    Prepared, QpOptions, Raw, ADDITION_FRACTION, PIVOT_RATIO_MIN, REGULARIZATION_MAX,
    REGULARIZATION_START,
};
use crate::error::FlankError;

/// The solution of the equality-constrained problem on a loaded set.
struct Eqp {
    /// p_S, in the order of the set.
    load: Vec<f64>,
    rotation: f64,
    /// Diagonal shift used (absolute, mm/N).
    shift: f64,
}

/// Solves [F_SS −r_S; r_Sᵀ 0][p_S; θ] = [−w_S; T] on `set` (Cholesky of
/// F_SS, Schur complement r_Sᵀ F_SS⁻¹ r_S, one refinement step against the
/// unshifted F_SS).
fn solve_eqp(prob: &Prepared, set: &[usize]) -> Result<Eqp, FlankError> {
    let m = set.len();
    let a = DMatrix::from_fn(m, m, |i, j| prob.f[(set[i], set[j])]);
    let ws = DVector::from_iterator(m, set.iter().map(|&i| prob.w[i]));
    let rs = DVector::from_iterator(m, set.iter().map(|&i| prob.r[i]));
    let dmax = (0..m).fold(0.0f64, |acc, i| acc.max(a[(i, i)]));
    let mut shift = 0.0;
    let chol = loop {
        let mut shifted = a.clone();
        for i in 0..m {
            shifted[(i, i)] += shift;
        }
        if let Some(c) = shifted.clone().cholesky() {
            let l = c.l_dirty();
            let ratio = (0..m).fold(f64::INFINITY, |acc, i| {
                acc.min(l[(i, i)] * l[(i, i)] / shifted[(i, i)])
            });
            if ratio >= PIVOT_RATIO_MIN {
                break c;
            }
        }
        shift = if shift == 0.0 {
            REGULARIZATION_START * dmax
        } else {
            shift * 100.0
        };
        if shift > REGULARIZATION_MAX * dmax {
            return Err(FlankError::Solver(format!(
                "LTCA contact QP: the compliance of the {m} loaded points is not positive definite even with a diagonal shift of {:.1e} of its diagonal (points {:?}…)",
                REGULARIZATION_MAX,
                &set[..m.min(8)]
            )));
        }
    };
    let b = chol.solve(&rs);
    let c = chol.solve(&ws);
    let rb = rs.dot(&b);
    let mut theta = (prob.t + rs.dot(&c)) / rb;
    let mut q = &b * theta - &c;
    // residuals (compatibility on S relative to its scale; equilibrium)
    let residual = |q: &DVector<f64>, theta: f64| {
        let e = &a * q + &ws - &rs * theta;
        let tau = prob.t - rs.dot(q);
        let scale = ws.amax().max((&a * q).amax()).max(theta.abs() * rs.amax());
        let size = e.amax() / scale.max(f64::MIN_POSITIVE) + tau.abs() / prob.t;
        (e, tau, size)
    };
    let (e, tau, size) = residual(&q, theta);
    let fe = chol.solve(&e);
    let dtheta = (tau + rs.dot(&fe)) / rb;
    let q2 = &q + &b * dtheta - fe;
    let theta2 = theta + dtheta;
    let (_, _, size2) = residual(&q2, theta2);
    if size2 <= size {
        q = q2;
        theta = theta2;
    }
    if !(theta.is_finite() && q.iter().all(|v| v.is_finite())) {
        return Err(FlankError::Solver(format!(
            "LTCA contact QP: the equality-constrained solve on {m} loaded points gave non-finite values"
        )));
    }
    Ok(Eqp {
        load: q.iter().copied().collect(),
        rotation: theta,
        shift,
    })
}

/// The primal active-set method (module doc), cold start. T > 0.
pub(super) fn active_set(prob: &Prepared, options: &QpOptions) -> Result<Raw, FlankError> {
    let (w, r) = (prob.w, prob.r);
    // start: the first point to close under a rigid rotation takes all
    // (the exact minimizer on that one-point set)
    let k = (0..prob.n)
        .min_by(|&a, &b| (w[a] / r[a]).total_cmp(&(w[b] / r[b])).then(a.cmp(&b)))
        .expect("n > 0");
    let mut load = vec![0.0; prob.n];
    load[k] = prob.t / r[k];
    let rotation = (prob.f[(k, k)] * load[k] + w[k]) / r[k];
    iterate(prob, options, vec![k], load, rotation, 1)
}

/// max(0, −min gᵢ) with g = F p + w − θ r (mm): how far the iterate
/// (p, θ) leaves a point inside its mate; its residual when the iteration
/// limit stops it.
fn largest_penetration(prob: &Prepared, p: &[f64], theta: f64) -> f64 {
    (0..prob.n)
        .map(|i| {
            let fp: f64 = (0..prob.n).map(|j| prob.f[(i, j)] * p[j]).sum();
            -(fp + prob.w[i] - theta * prob.r[i])
        })
        .fold(0.0f64, f64::max)
}

/// Active-set iterations from a feasible start: loads ≥ 0, zero outside
/// `free`, rᵀp = T. If `done` > 0 the start is the equality-constrained
/// minimizer on `free` (with multiplier `rotation`) and counts as `done`
/// solves; if 0 that minimizer is sought first. Returns the answer with the
/// number of equality-constrained solves (including `done`).
pub(super) fn iterate(
    prob: &Prepared,
    options: &QpOptions,
    mut free: Vec<usize>,
    mut p: Vec<f64>,
    mut theta: f64,
    done: usize,
) -> Result<Raw, FlankError> {
    let n = prob.n;
    let (w, r, t) = (prob.w, prob.r, prob.t);
    let pscale = t / r.iter().fold(f64::INFINITY, |a, &v| a.min(v));
    let rmax = r.iter().fold(0.0f64, |a, &v| a.max(v));
    let wmax = w.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let add_tol = (1e-3 * options.kkt_tolerance).max(1e-14);
    let mut in_free = vec![false; n];
    for &i in &free {
        in_free[i] = true;
    }
    let mut iterations = done;
    let mut shift = 0.0f64;
    let mut single = false;
    // points that entered alone and were dropped at once (round-off or a
    // singular F_SS): not re-entered until the iterate moves
    let mut refused = vec![false; n];
    let mut entered_alone: Option<usize> = None;
    let mut need_solve = done == 0;
    loop {
        // minimize on the loaded set, cutting steps at zero loads
        if need_solve {
            loop {
                if iterations >= options.max_iterations {
                    return Err(FlankError::Solver(format!(
                    "LTCA active set: iteration limit {} (QpOptions::max_iterations) reached with {} of {n} points loaded and the largest penetration of a point {:.3e} mm (the feasible iterate's residual)",
                    options.max_iterations,
                    free.len(),
                    largest_penetration(prob, &p, theta)
                )));
                }
                iterations += 1;
                let eqp = solve_eqp(prob, &free)?;
                shift = shift.max(eqp.shift);
                if eqp.load.iter().all(|&v| v >= 0.0) {
                    for (a, &i) in free.iter().enumerate() {
                        p[i] = eqp.load[a];
                    }
                    theta = eqp.rotation;
                    refused.iter_mut().for_each(|v| *v = false);
                    break;
                }
                // ratio test: the largest step keeping every load ≥ 0
                let mut alpha = 1.0f64;
                for (a, &i) in free.iter().enumerate() {
                    let q = eqp.load[a];
                    if q < 0.0 {
                        alpha = alpha.min(p[i] / (p[i] - q));
                    }
                }
                for (a, &i) in free.iter().enumerate() {
                    p[i] += alpha * (eqp.load[a] - p[i]);
                }
                // the blocking points (and ties within round-off) leave
                let mut dropped = Vec::new();
                for (a, &i) in free.iter().enumerate() {
                    if eqp.load[a] < 0.0 && p[i] <= 1e-14 * pscale {
                        dropped.push(i);
                    }
                }
                for &i in &dropped {
                    p[i] = 0.0;
                    in_free[i] = false;
                }
                free.retain(|&i| in_free[i]);
                if alpha > 0.0 {
                    refused.iter_mut().for_each(|v| *v = false);
                } else {
                    single = true;
                    if let Some(j) = entered_alone {
                        if dropped.contains(&j) {
                            refused[j] = true;
                        }
                    }
                }
                if free.is_empty() {
                    return Err(FlankError::Solver(
                    "LTCA active set: every point was dropped from the loaded set (round-off in the ratio test)".into(),
                ));
                }
            }
        }
        // gaps from the loaded columns
        let mut fp = vec![0.0; n];
        for &j in &free {
            if p[j] != 0.0 {
                for (v, &fij) in fp.iter_mut().zip(prob.f.column(j).iter()) {
                    *v += fij * p[j];
                }
            }
        }
        let fpmax = fp.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let d0 = wmax.max(fpmax).max(theta.abs() * rmax);
        let threshold = add_tol * d0;
        let mut viol: Vec<(f64, usize)> = (0..n)
            .filter(|&i| !in_free[i] && !refused[i])
            .map(|i| (fp[i] + w[i] - theta * r[i], i))
            .filter(|&(g, _)| g < -threshold)
            .collect();
        if viol.is_empty() {
            break;
        }
        viol.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        if single {
            viol.truncate(1);
        } else {
            let worst = viol[0].0;
            viol.retain(|v| v.0 <= ADDITION_FRACTION * worst);
        }
        entered_alone = if viol.len() == 1 {
            Some(viol[0].1)
        } else {
            None
        };
        for &(_, i) in &viol {
            free.push(i);
            in_free[i] = true;
        }
        single = false;
        need_solve = true;
    }
    Ok(Raw {
        load: p,
        rotation: theta,
        iterations,
        shift,
        polished: false,
        polish_iterations: 0,
        raw_kkt: None,
    })
}
