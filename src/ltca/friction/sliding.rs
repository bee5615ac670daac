//! Fully developed sliding friction: the running mesh.
//!
//! In a gear mesh running at a steady torque the flanks slide past each
//! other at the kinematic sliding velocity v_s, and the elastic
//! displacements change only as the load moves along the flank: their rate
//! is two orders below v_s except within a few hundredths of a degree of
//! the pitch point. The friction force at every loaded point is then
//! μ P_n against the kinematic sliding (the friction model of gear
//! efficiency and load-distribution studies, e.g. Xu, Kahraman, Anderson
//! & Maddock, J. Mech. Des. 129 (2007) 58–68), with no stick state:
//!
//! ```text
//!   P_t = μ S P_n,   S = diag(sign v_s)          (P_t resists slip along +t)
//!   g   = g⁰ + C_nn P_n + C_nt P_t − r_n θ ≥ 0,  P_n ≥ 0,  gᵢ P_n,i = 0
//!   Σ r_n P_n + r_t P_t = T
//! ```
//!
//! The matrix C_nn + μ C_nt S is not symmetric, so this is not a QP. It is
//! solved by a fixed point on the friction forces: for given P_t the
//! problem is the frictionless QP of [`crate::ltca::qp`] with separations
//! g⁰ + C_nt P_t and torque T − r_tᵀP_t; then P_t ← μ S P_n. The map
//! contracts at a rate of about μ‖C_nt‖/‖C_nn‖ (≈ 0.01 for steel gears at
//! μ = 0.05), so a handful of iterations reach round-off; the loop is
//! bounded and reports when it hits its bound.
//!
//! Where the map does not contract (a strong C_nt coupling, e.g. a loaded
//! tip corner: seed 002 at 0.42° with 1 mm cells), the change stops
//! shrinking: the step is then relaxed (halved, down to 1/64), and if the
//! bound is still hit a primal–dual active set on the sliding law itself
//! takes over from the last loaded set (bounded, reported).
//!
//! A fixed-point answer is checked by an independent route: the linear
//! system of the loaded set (rows gᵢ = 0 with the non-symmetric matrix,
//! and the equilibrium row), solved directly by LU;
//! [`SlidingAnswer::direct_difference`] is the largest difference of the
//! loads, relative to the largest load (NaN for an active-set answer,
//! which is that solve).

use nalgebra::{DMatrix, DVector};

use super::problem::FrictionProblem;
use crate::error::FlankError;
use crate::ltca::qp::{solve_contact_qp, ContactQp, QpOptions};

/// Largest number of fixed-point iterations.
pub const MAX_SLIDING_ITERATIONS: usize = 400;

/// Relative change of the friction forces that ends the fixed point.
pub const SLIDING_TOLERANCE: f64 = 1e-12;

/// Below this relative change, a change that no longer halves is the
/// round-off floor of the QP solves (the map contracts by ≈ 0.01 per
/// iteration): the fixed point has converged as far as it can.
pub const SLIDING_FLOOR: f64 = 1e-9;

/// The answer of [`solve_sliding`].
#[derive(Clone, Debug)]
pub struct SlidingAnswer {
    /// P_n (N), P_t (N, resisting slip along +t), θ (rad), the loaded gaps
    /// (mm).
    pub normal: Vec<f64>,
    pub tangential: Vec<f64>,
    pub rotation: f64,
    pub gap: Vec<f64>,
    /// Fixed-point iterations (frictionless QPs solved) and whether the
    /// bound [`MAX_SLIDING_ITERATIONS`] was hit before the tolerance
    /// [`SLIDING_TOLERANCE`] or the round-off floor (`SLIDING_FLOOR`).
    pub iterations: usize,
    pub limit_hit: bool,
    /// Primal–dual active-set iterations after a fixed point that did not
    /// converge (0: not needed).
    pub active_set_iterations: usize,
    /// Last relative change of P_t.
    pub change: f64,
    /// KKT residual of the last QP (relative, as [`crate::ltca::qp`]).
    pub kkt: f64,
    /// Largest residual of the sliding law itself: equilibrium (relative
    /// to T), complementarity and penetration (relative to the largest
    /// g⁰ or C P), the friction law (relative to the largest μ P_n).
    pub residual: f64,
    /// Largest difference from the direct solve on the loaded set,
    /// relative to the largest load.
    pub direct_difference: f64,
    /// The QP met its KKT tolerance and the fixed point converged.
    pub within_tolerance: bool,
}

/// Solves the sliding-friction problem of the module doc. `direction` is
/// the sign of the kinematic slip of each point along +t (−1, 0 or +1;
/// 0: no friction there). `pb.sliding` is not used.
pub fn solve_sliding(
    pb: &FrictionProblem,
    direction: &[f64],
    qp: &QpOptions,
) -> Result<SlidingAnswer, FlankError> {
    let m = pb.points();
    if direction.len() != m || direction.iter().any(|d| !matches!(*d, -1.0 | 0.0 | 1.0)) {
        return Err(FlankError::Model(format!(
            "sliding friction: {} slip directions of −1, 0 or +1 are needed for {m} points",
            direction.len()
        )));
    }
    for (name, v) in [("C_nn", pb.c_nn), ("C_nt", pb.c_nt)] {
        if v.len() != m * m || v.iter().any(|x| !x.is_finite()) {
            return Err(FlankError::Model(format!(
                "sliding friction: {name} must be {m} × {m} finite numbers"
            )));
        }
    }
    pb.check_mu("sliding friction")?;
    // the effective torque arm r_n + μ S r_t must stay positive: otherwise
    // friction alone could carry the torque (self-locking)
    if let Some(i) = (0..m)
        .find(|&i| !(pb.arm_normal[i] + pb.mu_at(i) * direction[i] * pb.arm_tangential[i] > 0.0))
    {
        return Err(FlankError::Model(format!(
            "sliding friction: point {i} locks (r_n {:.4} + μ r_t {:.4} ≤ 0)",
            pb.arm_normal[i],
            pb.mu_at(i) * direction[i] * pb.arm_tangential[i]
        )));
    }
    let cnt = |i: usize, pt: &[f64]| (0..m).map(|j| pb.c_nt[i * m + j] * pt[j]).sum::<f64>();
    let mut pt = vec![0.0; m];
    let mut iterations = 0;
    let mut change = f64::INFINITY;
    let mut converged = false;
    let mut relax: f64 = 1.0;
    let mut first_load = Vec::new();
    let mut last = None;
    while iterations < MAX_SLIDING_ITERATIONS {
        iterations += 1;
        let separation: Vec<f64> = (0..m).map(|i| pb.separation[i] + cnt(i, &pt)).collect();
        let torque = pb.torque - (0..m).map(|i| pb.arm_tangential[i] * pt[i]).sum::<f64>();
        if !(torque > 0.0) {
            return Err(FlankError::Model(format!(
                "sliding friction: the friction moments ({:.1} N·mm) carry all of the torque {:.1} N·mm",
                pb.torque - torque,
                pb.torque
            )));
        }
        let s = solve_contact_qp(
            &ContactQp {
                compliance: pb.c_nn,
                separation: &separation,
                moment_arm: pb.arm_normal,
                torque,
            },
            qp,
        )?;
        let next: Vec<f64> = (0..m)
            .map(|i| pb.mu_at(i) * direction[i] * s.load[i])
            .collect();
        if first_load.is_empty() {
            first_load = s.load.clone();
        }
        let scale = next.iter().fold(0.0f64, |a, x| a.max(x.abs())).max(1e-300);
        let previous = change;
        change = (0..m)
            .map(|i| (next[i] - pt[i]).abs())
            .fold(0.0f64, f64::max)
            / scale;
        converged = change <= SLIDING_TOLERANCE
            || pb.mu_max() == 0.0
            || (change <= SLIDING_FLOOR && change >= 0.5 * previous);
        last = Some(s);
        if converged {
            pt = next;
            break;
        }
        // relaxed update; a change that does not shrink above the floor
        // means the map does not contract here: halve the step (to 1/64)
        if iterations >= 3 && change > SLIDING_FLOOR && change > 0.9 * previous {
            relax = (0.5 * relax).max(1.0 / 64.0);
        }
        for i in 0..m {
            pt[i] += relax * (next[i] - pt[i]);
        }
    }
    let s = last.expect("at least one iteration");
    let (mut normal, mut rotation) = (s.load.clone(), s.rotation);
    let mut limit_hit = !converged;
    let mut active_set_iterations = 0;
    if limit_hit {
        // the fixed point does not contract (strong C_nt coupling, e.g. at
        // a tip corner): the primal–dual active set on the sliding law
        // itself, from the last loaded set, else from the frictionless one
        let tried = match active_set(pb, direction, &normal)? {
            Some(x) => Some(x),
            None => active_set(pb, direction, &first_load)?,
        };
        if let Some((p, th, k)) = tried {
            normal = p;
            rotation = th;
            pt = (0..m)
                .map(|i| pb.mu_at(i) * direction[i] * normal[i])
                .collect();
            limit_hit = false;
            active_set_iterations = k;
        }
    }
    // gaps with the final friction forces (the QP's used the previous ones)
    let gap: Vec<f64> = (0..m)
        .map(|i| {
            pb.separation[i]
                + (0..m).map(|j| pb.c_nn[i * m + j] * normal[j]).sum::<f64>()
                + cnt(i, &pt)
                - pb.arm_normal[i] * rotation
        })
        .collect();
    let residual = sliding_residual(pb, direction, &normal, &pt, &gap);
    let direct_difference = if active_set_iterations > 0 {
        // the active set's answer is the direct solve: no second opinion
        f64::NAN
    } else {
        direct_check(pb, direction, &normal)?
    };
    Ok(SlidingAnswer {
        normal,
        tangential: pt,
        rotation,
        gap,
        iterations,
        active_set_iterations,
        limit_hit,
        change,
        kkt: s.kkt.max,
        residual,
        direct_difference,
        within_tolerance: s.within_tolerance && !limit_hit && residual <= 1e-9,
    })
}

/// Largest number of primal–dual active-set iterations.
pub const MAX_ACTIVE_SET_ITERATIONS: usize = 200;

/// The loaded set's system (rows gᵢ = 0 with C_nn + μ C_nt S, the
/// equilibrium row) solved for the set `loaded`: loads (zero elsewhere)
/// and θ.
fn solve_loaded_set(
    pb: &FrictionProblem,
    direction: &[f64],
    loaded: &[usize],
) -> Option<(Vec<f64>, f64)> {
    let m = direction.len();
    let k = loaded.len();
    let mut a = DMatrix::<f64>::zeros(k + 1, k + 1);
    let mut b = DVector::<f64>::zeros(k + 1);
    for (r, &i) in loaded.iter().enumerate() {
        for (c, &j) in loaded.iter().enumerate() {
            a[(r, c)] = pb.c_nn[i * m + j] + pb.mu_at(j) * pb.c_nt[i * m + j] * direction[j];
        }
        a[(r, k)] = -pb.arm_normal[i];
        b[r] = -pb.separation[i];
        a[(k, r)] = pb.arm_normal[i] + pb.mu_at(i) * direction[i] * pb.arm_tangential[i];
    }
    b[k] = pb.torque;
    let x = a.lu().solve(&b)?;
    let mut p = vec![0.0; m];
    for (r, &i) in loaded.iter().enumerate() {
        p[i] = x[r];
    }
    Some((p, x[k]))
}

/// Primal–dual active set on the sliding law (Hintermüller, Ito &
/// Kunisch, SIAM J. Optim. 13 (2003) 865–888): solve on the loaded set,
/// drop points with P_n < 0, add points with g < 0, until the set
/// repeats; `None` if it does not settle within
/// [`MAX_ACTIVE_SET_ITERATIONS`] or a system is singular.
fn active_set(
    pb: &FrictionProblem,
    direction: &[f64],
    start: &[f64],
) -> Result<Option<(Vec<f64>, f64, usize)>, FlankError> {
    let m = direction.len();
    let pmax = start.iter().fold(0.0f64, |a, &x| a.max(x));
    let mut loaded: Vec<bool> = start.iter().map(|&p| p > 1e-12 * pmax).collect();
    for k in 1..=MAX_ACTIVE_SET_ITERATIONS {
        let set: Vec<usize> = (0..m).filter(|&i| loaded[i]).collect();
        if set.is_empty() {
            return Ok(None);
        }
        let Some((p, th)) = solve_loaded_set(pb, direction, &set) else {
            return Ok(None);
        };
        let pt: Vec<f64> = (0..m).map(|i| pb.mu_at(i) * direction[i] * p[i]).collect();
        let scale = pb.c_nn.iter().fold(0.0f64, |a, &x| a.max(x.abs()))
            * p.iter().fold(0.0f64, |a, &x| a.max(x.abs()));
        let next: Vec<bool> = (0..m)
            .map(|i| {
                if loaded[i] {
                    p[i] >= 0.0
                } else {
                    let g = pb.separation[i]
                        + (0..m)
                            .map(|j| pb.c_nn[i * m + j] * p[j] + pb.c_nt[i * m + j] * pt[j])
                            .sum::<f64>()
                        - pb.arm_normal[i] * th;
                    g < -1e-14 * scale
                }
            })
            .collect();
        if next == loaded {
            return Ok(Some((p, th, k)));
        }
        loaded = next;
    }
    Ok(None)
}

/// μ ‖C_nn⁻¹ C_nt‖₂ over the loaded points: the Lipschitz constant of the
/// map P_t ↦ μ S P_n on a fixed loaded set. Below 1 the sliding fixed
/// point contracts and the frictional problem's answer is unique for that
/// set (the classical small-μ condition of discrete Coulomb friction:
/// Klarbring, Ing.-Arch. 60 (1990) 529–541); near or above 1 answers may
/// be many, and the solvers may disagree. `None` if no point is loaded or
/// C_nn is singular there.
pub fn friction_coupling(pb: &FrictionProblem, normal: &[f64]) -> Option<f64> {
    let m = normal.len();
    let pmax = normal.iter().fold(0.0f64, |a, &x| a.max(x));
    let loaded: Vec<usize> = (0..m).filter(|&i| normal[i] > 1e-12 * pmax).collect();
    let k = loaded.len();
    if k == 0 {
        return None;
    }
    let a = DMatrix::from_fn(k, k, |r, c| pb.c_nn[loaded[r] * m + loaded[c]]);
    let b = DMatrix::from_fn(k, k, |r, c| pb.c_nt[loaded[r] * m + loaded[c]]);
    let x = a.lu().solve(&b)?;
    match pb.point_mu {
        None => Some(pb.mu * x.singular_values().max()),
        // μ per point: the map is C_nn⁻¹ C_nt diag(μ)
        Some(mu) => {
            let scaled = DMatrix::from_fn(k, k, |r, c| x[(r, c)] * mu[loaded[c]]);
            Some(scaled.singular_values().max())
        }
    }
}

/// Largest relative residual of the sliding law (see [`SlidingAnswer`]).
fn sliding_residual(
    pb: &FrictionProblem,
    direction: &[f64],
    pn: &[f64],
    pt: &[f64],
    gap: &[f64],
) -> f64 {
    let m = pn.len();
    let moment: f64 = (0..m)
        .map(|i| pb.arm_normal[i] * pn[i] + pb.arm_tangential[i] * pt[i])
        .sum();
    let equilibrium = (moment - pb.torque).abs() / pb.torque.max(1e-300);
    let pmax = pn.iter().fold(0.0f64, |a, &x| a.max(x)).max(1e-300);
    let cmax = pb.c_nn.iter().fold(0.0f64, |a, &x| a.max(x.abs()));
    let gscale = pb
        .separation
        .iter()
        .fold(cmax * pmax, |a, &x| a.max(x.abs()))
        .max(1e-300);
    let mut r = equilibrium;
    for i in 0..m {
        r = r.max((-gap[i]).max(0.0) / gscale);
        r = r.max((gap[i] * pn[i]).abs() / (gscale * pmax));
        r = r.max((-pn[i]).max(0.0) / pmax);
        r = r.max(
            (pt[i] - pb.mu_at(i) * direction[i] * pn[i]).abs() / (pb.mu_max() * pmax).max(1e-300),
        );
    }
    r
}

/// The loaded set's linear system solved directly: rows i ∈ A
/// (C_nn + μ C_nt S)_{AA} P_A − r_A θ = −g⁰_A and Σ (r_n + μ S r_t)_A P_A = T;
/// returns max |P_direct − P| / max P.
fn direct_check(pb: &FrictionProblem, direction: &[f64], pn: &[f64]) -> Result<f64, FlankError> {
    let pmax = pn.iter().fold(0.0f64, |a, &x| a.max(x));
    if !(pmax > 0.0) {
        return Ok(0.0);
    }
    let loaded: Vec<usize> = (0..pn.len()).filter(|&i| pn[i] > 1e-12 * pmax).collect();
    let (x, _) = solve_loaded_set(pb, direction, &loaded).ok_or_else(|| {
        FlankError::Solver("sliding friction: the loaded set's system is singular".into())
    })?;
    Ok(loaded
        .iter()
        .map(|&i| (x[i] - pn[i]).abs())
        .fold(0.0f64, f64::max)
        / pmax)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One point: P_n = T / (r_n + μ s r_t) in closed form (equilibrium
    /// with P_t = μ s P_n), and the loaded rotation from the gap.
    #[test]
    fn one_point_closed_form() {
        let (c, rn, rt, mu, t) = (2e-5, 23.0, 9.0, 0.05, 3e5);
        for dir in [-1.0, 1.0] {
            let pb = FrictionProblem {
                c_nn: &[c],
                c_nt: &[4e-6],
                c_tn: &[4e-6],
                c_tt: &[1.5e-5],
                separation: &[0.0],
                arm_normal: &[rn],
                arm_tangential: &[rt],
                sliding: &[0.0],
                mu,
                point_mu: None,
                torque: t,
            };
            let a = solve_sliding(&pb, &[dir], &QpOptions::default()).unwrap();
            let pn = t / (rn + mu * dir * rt);
            assert!(
                (a.normal[0] / pn - 1.0).abs() < 1e-13,
                "{} vs {pn}",
                a.normal[0]
            );
            assert!((a.tangential[0] - mu * dir * pn).abs() < 1e-9 * pn);
            let theta = (c * pn + 4e-6 * mu * dir * pn) / rn;
            assert!((a.rotation / theta - 1.0).abs() < 1e-12);
            assert!(a.residual < 1e-12 && a.direct_difference < 1e-12 && !a.limit_hit);
        }
    }

    /// A crowned line of 21 points, sliding through zero at mid-line (a
    /// pitch point): the fixed point agrees with the direct solve on its
    /// loaded set to round-off; μ = 0 gives the frictionless QP exactly.
    #[test]
    fn crowned_line_against_direct_solve() {
        let m = 21;
        let x: Vec<f64> = (0..m)
            .map(|i| -1.0 + 2.0 * i as f64 / (m - 1) as f64)
            .collect();
        let mut c_nn = vec![0.0; m * m];
        let mut c_nt = vec![0.0; m * m];
        for i in 0..m {
            for j in 0..m {
                let d = (x[i] - x[j]).abs();
                c_nn[i * m + j] = 1e-5 * (-d / 0.4).exp() + if i == j { 1e-5 } else { 0.0 };
                c_nt[i * m + j] = 2e-6 * (-d / 0.4).exp();
            }
        }
        let g0: Vec<f64> = x.iter().map(|&v| 4e-3 * v * v).collect();
        let rn = vec![20.0; m];
        let rt: Vec<f64> = x.iter().map(|&v| 8.0 + 2.0 * v).collect();
        let dir: Vec<f64> = x
            .iter()
            .map(|&v| if v.abs() < 1e-12 { 0.0 } else { v.signum() })
            .collect();
        let pb = |mu: f64| FrictionProblem {
            c_nn: &c_nn,
            c_nt: &c_nt,
            c_tn: &c_nt,
            c_tt: &c_nn,
            separation: &g0,
            arm_normal: &rn,
            arm_tangential: &rt,
            sliding: &x,
            mu,
            point_mu: None,
            torque: 2e5,
        };
        let a = solve_sliding(&pb(0.08), &dir, &QpOptions::default()).unwrap();
        eprintln!(
            "sliding line: {} iterations, change {:.1e}, residual {:.1e}, direct {:.1e}",
            a.iterations, a.change, a.residual, a.direct_difference
        );
        assert!(a.direct_difference < 1e-10 && a.residual < 1e-10 && a.within_tolerance);
        let f = solve_sliding(&pb(0.0), &dir, &QpOptions::default()).unwrap();
        let q = solve_contact_qp(
            &ContactQp {
                compliance: &c_nn,
                separation: &g0,
                moment_arm: &rn,
                torque: 2e5,
            },
            &QpOptions::default(),
        )
        .unwrap();
        let d = f
            .normal
            .iter()
            .zip(&q.load)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0f64, f64::max);
        assert!(d == 0.0, "μ = 0 is the frictionless QP: {d}");
    }

    #[test]
    fn bad_directions_and_self_locking_are_errors() {
        let pb = FrictionProblem {
            c_nn: &[1e-5],
            c_nt: &[0.0],
            c_tn: &[0.0],
            c_tt: &[1e-5],
            separation: &[0.0],
            arm_normal: &[10.0],
            arm_tangential: &[-30.0],
            sliding: &[0.0],
            mu: 0.5,
            point_mu: None,
            torque: 1e3,
        };
        let e = solve_sliding(&pb, &[0.5], &QpOptions::default()).unwrap_err();
        assert!(e.to_string().contains("−1, 0 or +1"), "{e}");
        let e = solve_sliding(&pb, &[1.0], &QpOptions::default()).unwrap_err();
        assert!(e.to_string().contains("locks"), "{e}");
    }
}
