//! Gaps, slips, states and residuals of an increment's answer: one routine
//! for both solvers, so that neither grades itself.

use super::problem::{PointState, Prepared, Residuals};

/// The previous totals of an increment.
pub(crate) struct Previous<'a> {
    pub(crate) pn: &'a [f64],
    pub(crate) pt: &'a [f64],
    pub(crate) theta: f64,
}

/// g = g⁰ + C_nn P_n + C_nt P_t − r_n θ.
pub(crate) fn gaps(prob: &Prepared, pn: &[f64], pt: &[f64], theta: f64) -> Vec<f64> {
    (0..prob.m)
        .map(|i| {
            let mut g = prob.g0[i] - prob.r_n[i] * theta;
            for j in 0..prob.m {
                g += prob.c_nn[(i, j)] * pn[j] + prob.c_nt[(i, j)] * pt[j];
            }
            g
        })
        .collect()
}

/// Δσ = ρ Δθ − (C_tn ΔP_n + C_tt ΔP_t).
pub(crate) fn slips(
    prob: &Prepared,
    prev: &Previous,
    pn: &[f64],
    pt: &[f64],
    theta: f64,
) -> Vec<f64> {
    let dth = theta - prev.theta;
    (0..prob.m)
        .map(|i| {
            let mut s = prob.rho[i] * dth;
            for j in 0..prob.m {
                s -= prob.c_tn[(i, j)] * (pn[j] - prev.pn[j])
                    + prob.c_tt[(i, j)] * (pt[j] - prev.pt[j]);
            }
            s
        })
        .collect()
}

/// The state of each point read off an answer: closed when the scaled
/// load exceeds the scaled gap; then slipping when the scaled slip exceeds
/// the scaled slack μP_n − |P_t| of the cone, in the direction of the slip.
pub(crate) fn states(
    prob: &Prepared,
    pn: &[f64],
    pt: &[f64],
    gap: &[f64],
    slip: &[f64],
) -> Vec<PointState> {
    (0..prob.m)
        .map(|i| {
            if !(pn[i] / prob.p0 > gap[i] / prob.d0) {
                PointState::Separated
            } else if prob.mu_max > 0.0
                && slip[i].abs() / prob.d0 > (prob.mu[i] * pn[i] - pt[i].abs()) / prob.p0
            {
                if slip[i] > 0.0 {
                    PointState::SlipPositive
                } else {
                    PointState::SlipNegative
                }
            } else {
                PointState::Stick
            }
        })
        .collect()
}

/// The residuals of (P_n, P_t, θ) at torque T_k (T_k > 0).
pub(crate) fn residuals(
    prob: &Prepared,
    torque: f64,
    pn: &[f64],
    pt: &[f64],
    gap: &[f64],
    slip: &[f64],
) -> Residuals {
    let (p0, d0) = (prob.p0, prob.d0);
    let kappa = p0 / d0;
    let moment: f64 = (0..prob.m)
        .map(|i| prob.r_n[i] * pn[i] + prob.r_t[i] * pt[i])
        .sum();
    let mut r = Residuals {
        equilibrium: (moment - torque).abs() / torque,
        min_gap: f64::INFINITY,
        min_load: f64::INFINITY,
        ..Residuals::default()
    };
    for i in 0..prob.m {
        let bound = prob.mu[i] * pn[i].max(0.0);
        r.min_gap = r.min_gap.min(gap[i]);
        r.min_load = r.min_load.min(pn[i]);
        r.gap = r.gap.max(-gap[i] / d0);
        r.load = r.load.max(-pn[i] / p0);
        r.complementarity = r
            .complementarity
            .max((pn[i].max(0.0) / p0).min(gap[i].abs() / d0));
        r.cone = r.cone.max((pt[i].abs() - prob.mu[i] * pn[i]) / p0);
        let y = (pt[i] + kappa * slip[i]).clamp(-bound, bound);
        r.coulomb = r.coulomb.max((pt[i] - y).abs() / p0);
    }
    // any NaN makes max NaN (f64::max would drop it)
    let parts = [
        r.equilibrium,
        r.gap,
        r.load,
        r.complementarity,
        r.cone,
        r.coulomb,
    ];
    r.max = if parts.iter().any(|v| v.is_nan()) || pn.iter().chain(pt).any(|v| !v.is_finite()) {
        f64::NAN
    } else {
        parts.iter().fold(0.0f64, |a, &v| a.max(v))
    };
    r
}
