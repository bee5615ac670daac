//! KKT residuals of an answer (p, θ) of the contact QP, shared by both
//! solvers and the callers, and the condition number of F for reports.

use nalgebra::{DMatrix, SymmetricEigen};

use super::problem::{ContactQp, Kkt};

/// The KKT residuals from F p (the shared part of [`kkt`] and the solvers).
pub(super) fn residuals(
    fp: &[f64],
    w: &[f64],
    r: &[f64],
    t: f64,
    load: &[f64],
    rotation: f64,
) -> Kkt {
    let n = w.len();
    let rmin = r.iter().fold(f64::INFINITY, |a, &v| a.min(v));
    let rmax = r.iter().fold(0.0f64, |a, &v| a.max(v));
    let mut p0 = if t > 0.0 {
        t / rmin
    } else {
        load.iter().fold(0.0f64, |a, v| a.max(v.abs()))
    };
    if !(p0 > 0.0) {
        p0 = 1.0;
    }
    let mut d0 = w
        .iter()
        .chain(fp)
        .fold(0.0f64, |a, v| a.max(v.abs()))
        .max(rotation.abs() * rmax);
    if !(d0 > 0.0) {
        d0 = 1.0;
    }
    let mut k = Kkt::default();
    let mut rp = 0.0;
    let mut rp_abs = 0.0;
    let mut finite = rotation.is_finite();
    for i in 0..n {
        let g = fp[i] + w[i] - rotation * r[i];
        let p = load[i];
        rp += r[i] * p;
        rp_abs += (r[i] * p).abs();
        if p > 0.0 {
            k.stationarity = k.stationarity.max(g.abs() / d0);
        }
        k.primal_feasibility = k.primal_feasibility.max(-p / p0);
        k.dual_feasibility = k.dual_feasibility.max(-g / d0);
        k.complementarity = k.complementarity.max((p.max(0.0) / p0).min(g.abs() / d0));
        finite &= g.is_finite() && p.is_finite();
    }
    let escale = if t > 0.0 {
        t
    } else {
        rp_abs.max(f64::MIN_POSITIVE)
    };
    k.equilibrium = (rp - t).abs() / escale;
    if !finite {
        // f64::max drops NaN: mark non-finite input explicitly
        k.stationarity = f64::NAN;
    }
    let parts = [
        k.stationarity,
        k.equilibrium,
        k.primal_feasibility,
        k.dual_feasibility,
        k.complementarity,
    ];
    k.max = if parts.iter().any(|v| v.is_nan()) {
        f64::NAN
    } else {
        parts.iter().fold(0.0f64, |a, &v| a.max(v))
    };
    k
}

/// Relative KKT residuals of loads `load` and rotation `rotation` for the
/// problem `qp` (scales in [`Kkt`]). Uses the symmetric part of F. Lengths
/// that do not match the problem give NaN residuals.
pub fn kkt(qp: &ContactQp, load: &[f64], rotation: f64) -> Kkt {
    let n = qp.separation.len();
    if qp.moment_arm.len() != n || qp.compliance.len() != n * n || load.len() != n {
        return Kkt {
            stationarity: f64::NAN,
            equilibrium: f64::NAN,
            primal_feasibility: f64::NAN,
            dual_feasibility: f64::NAN,
            complementarity: f64::NAN,
            max: f64::NAN,
        };
    }
    let fp: Vec<f64> = (0..n)
        .map(|i| {
            (0..n)
                .map(|j| 0.5 * (qp.compliance[i * n + j] + qp.compliance[j * n + i]) * load[j])
                .sum()
        })
        .collect();
    residuals(&fp, qp.separation, qp.moment_arm, qp.torque, load, rotation)
}

/// 2-norm condition number κ(F) = λ_max/λ_min of the symmetric part of F
/// (n × n row-major) from its eigenvalues, for reports. ∞ if λ_min ≤ 0
/// (semi-definite or indefinite), NaN for a wrong length or non-finite
/// entries.
pub fn condition_number(compliance: &[f64], n: usize) -> f64 {
    if compliance.len() != n * n || n == 0 || compliance.iter().any(|v| !v.is_finite()) {
        return f64::NAN;
    }
    let f = DMatrix::from_fn(n, n, |i, j| {
        0.5 * (compliance[i * n + j] + compliance[j * n + i])
    });
    let eig = SymmetricEigen::new(f).eigenvalues;
    let lmax = eig.iter().fold(f64::NEG_INFINITY, |a, &v| a.max(v));
    let lmin = eig.iter().fold(f64::INFINITY, |a, &v| a.min(v));
    if !(lmin > 0.0) {
        f64::INFINITY
    } else {
        lmax / lmin
    }
}

/// Relative pivot below which [`singular_on`] calls a block singular
/// (κ₂ of the order of its inverse or above).
pub const SINGULAR_PIVOT: f64 = 1e-12;

/// Whether the principal block of F (n × n row-major, symmetric part) on
/// the points `on` is numerically singular: a Cholesky factorization of it
/// meets a pivot ≤ `SINGULAR_PIVOT` × its largest diagonal entry. A
/// singular block on the loaded points means the loads there are not
/// unique (any null vector with rᵀv = 0 can be added), although the gaps
/// and θ are. O(m³/3) for m points.
pub fn singular_on(compliance: &[f64], n: usize, on: &[usize]) -> bool {
    let m = on.len();
    if m == 0 {
        return false;
    }
    let mut a = vec![0.0; m * m];
    for (x, &i) in on.iter().enumerate() {
        for (y, &j) in on.iter().enumerate() {
            a[x * m + y] = 0.5 * (compliance[i * n + j] + compliance[j * n + i]);
        }
    }
    let dmax = (0..m).map(|k| a[k * m + k]).fold(0.0f64, f64::max);
    if !(dmax > 0.0) {
        return true;
    }
    // right-looking Cholesky on the lower triangle
    for k in 0..m {
        let d = a[k * m + k];
        if !(d > SINGULAR_PIVOT * dmax) {
            return true;
        }
        let l = d.sqrt();
        for i in k + 1..m {
            a[i * m + k] /= l;
        }
        for j in k + 1..m {
            let ljk = a[j * m + k];
            for i in j..m {
                a[i * m + j] -= a[i * m + k] * ljk;
            }
        }
    }
    false
}
