//! Hypoid pitch cones, ISO 23509:2016 clause 6, methods 1–3 (formulae
//! (8)–(109)), each as the standard's chain of formulae with its iteration:
//!
//! * method 1 (Gleason): the desired pinion spiral angle β_Δ1 fixes the
//!   hypoid dimension factor K1; the wheel offset angle η in the axial plane
//!   is iterated until the lengthwise curvature radius of the tooth at the
//!   mean point ρ_mβ (r_c0 for face milling, the extended epicycloid's for
//!   face hobbing, formulae (34)–(39)) equals Wildhaber's limit curvature
//!   radius ρ_lim (formula (33)). The mean point is not at mid face width
//!   (r_mpt2 from an approximate pitch angle, formula (12)), hence c_be2.
//! * method 2 (Oerlikon, face hobbing): approximations (42)–(56) give a
//!   start value of the improved wheel pitch angle δ2imp; formulae (57)–(78)
//!   give the cones; the check (79)–(82) asks that the pinion's mean cone
//!   distance R_m1 equal R_mcheck, the side of the pitch-plane triangle
//!   (wheel apex, P, pinion apex) whose angle at the wheel apex is the angle
//!   φ6 of the cutter centre seen from the crown-gear centre (law of sines:
//!   R_mcheck = R_m2 sin φ6 / sin(180° − ζ_mp − φ6)).
//! * method 3 (Klingelnberg): fixed-point passes over formulae (88)–(108),
//!   with the check R_mint = R_m1 (formula (106)); ν = 0 for face milling
//!   (no z0; this is this code's reading: a single-indexing cutter has no
//!   lead angle).
//!
//! **Stopping rule.** The standard iterates from its start value until the
//! method's check passes (method 1: |ρ_mβ/ρ_lim − 1| ≤ 0.01; method 2:
//! |R_m1/R_mcheck − 1| ≤ 0.01; method 3: |R_mint − R_m1| ≤ 10⁻⁴ R_m1). Its
//! sample F4 prints the *first* trial (its check is 0.3 % there, the root
//! of the check lies degrees away), so a trial that passes is returned as
//! is. When the start value fails, methods 1 and 2 go on to the root of
//! the check (bracketed scan and bisection, bounded); how the standard
//! picks its next trial is not known here. Method 3 repeats its passes
//! (the standard's own update, formulae (107), (108)) until the check
//! passes.

use super::pitch_cone::{asin_checked, limit_pressure_angle, missing, Clause6, ConeInputs};
use crate::error::{FlankError, Result};

use std::f64::consts::{FRAC_PI_2, PI};

/// Bound of every loop here.
pub const MAX_ITERATIONS: usize = 200;

fn fail(method: u8, why: impl std::fmt::Display) -> FlankError {
    FlankError::Model(format!("blank design, method {method} pitch cones: {why}"))
}

/// Root of `f` nearest to `x0`: two walkers step outwards by `step` (at most
/// `n` steps each) to the first sign change between finite values, then
/// bisection. Returns the root and the number of evaluations, or None.
fn root_near(f: &dyn Fn(f64) -> Option<f64>, x0: f64, step: f64, n: usize) -> Option<(f64, usize)> {
    let mut evals = 1;
    let f0 = f(x0)?;
    let mut walkers = [(x0, f0, 1.0, true), (x0, f0, -1.0, true)];
    for _ in 0..n {
        for w in walkers.iter_mut().filter(|w| w.3) {
            let xb = w.0 + w.2 * step;
            evals += 1;
            let Some(fb) = f(xb) else {
                w.3 = false;
                continue;
            };
            if w.1 * fb <= 0.0 {
                let (mut lo, mut hi, mut f_lo) = (w.0, xb, w.1);
                for _ in 0..MAX_ITERATIONS {
                    let mid = 0.5 * (lo + hi);
                    evals += 1;
                    let fm = f(mid)?;
                    if f_lo * fm <= 0.0 {
                        hi = mid;
                    } else {
                        lo = mid;
                        f_lo = fm;
                    }
                    if (hi - lo).abs() < 1e-15 * (1.0 + mid.abs()) {
                        break;
                    }
                }
                return Some((0.5 * (lo + hi), evals));
            }
            w.0 = xb;
            w.1 = fb;
        }
    }
    None
}

/// Lengthwise curvature radius of the tooth at the mean point, formulae
/// (34)–(40): face milling r_c0; face hobbing the extended epicycloid's,
/// ρ_mβ = R_m2 cos β_m2 (tan β_m2 + tan η1 / (1 + tan ν (tan β_m2 + tan η1)))
/// with z_p = z2 / sin δ2, sin ν = R_m2 z0 cos β_m2 / (r_c0 z_p),
/// λ = 90° − β_m2 + ν, ρ_P0² = R_m2² + r_c0² − 2 R_m2 r_c0 cos λ and
/// cos η1 = R_m2 cos β_m2 (z_p + z0) / (ρ_P0 z_p). (Checked in the tests
/// against the curvature of the blade point's path in the crown gear.)
pub fn lengthwise_curvature_radius(
    rm2: f64,
    beta_m2: f64,
    delta2: f64,
    z2: f64,
    rc0: f64,
    z0: Option<f64>,
) -> Result<f64> {
    let Some(z0) = z0 else {
        return Ok(rc0);
    };
    let zp = z2 / delta2.sin();
    let nu = asin_checked(
        rm2 * z0 * beta_m2.cos() / (rc0 * zp),
        "the cutter lead angle ν (`rc0_mm` too small for `z0`)",
    )?;
    let lambda = FRAC_PI_2 - beta_m2 + nu;
    let rho_p0 = (rm2 * rm2 + rc0 * rc0 - 2.0 * rm2 * rc0 * lambda.cos()).sqrt();
    let c = rm2 * beta_m2.cos() * (zp + z0) / (rho_p0 * zp);
    if !(c.abs() <= 1.0) {
        return Err(FlankError::Model(format!(
            "blank design: the epicycloid of `rc0_mm` = {rc0}, `z0` = {z0} does not pass the mean point"
        )));
    }
    let (tb, te) = (beta_m2.tan(), c.acos().tan());
    Ok(rm2 * beta_m2.cos() * (tb + te / (1.0 + nu.tan() * (tb + te))))
}

/// Wildhaber's limit curvature radius, formula (33): ρ_lim = sec α_lim
/// (tan β_m1 − tan β_m2) / (−tan α_lim (tan β_m1 / (R_m1 tan δ1) + tan β_m2 /
/// (R_m2 tan δ2)) + 1/(R_m1 cos β_m1) − 1/(R_m2 cos β_m2)); returned as its
/// inverse (no pole where the denominator vanishes).
pub fn limit_curvature(s: &Clause6, alpha_lim: f64) -> f64 {
    let ta = alpha_lim.tan();
    let den = -ta
        * (s.beta_m1.tan() / (s.rm1 * s.delta1.tan()) + s.beta_m2.tan() / (s.rm2 * s.delta2.tan()))
        + 1.0 / (s.rm1 * s.beta_m1.cos())
        - 1.0 / (s.rm2 * s.beta_m2.cos());
    alpha_lim.cos() * den / (s.beta_m1.tan() - s.beta_m2.tan())
}

/// Method 1, formulae (8)–(41).
pub fn method1(c: &ConeInputs) -> Result<Clause6> {
    let de2 = c
        .de2
        .ok_or_else(|| missing("de2_mm", "method 1 starts from the outer pitch diameter"))?;
    let beta_d1 = c
        .beta_m1_desired
        .ok_or_else(|| missing("beta_m1_desired_deg", "method 1 needs it"))?;
    let (a, u) = (c.a, c.z2 / c.z1);
    let ds = c.sigma - FRAC_PI_2;
    // (11)–(16): approximate wheel pitch angle (Gleason's factor 1.2 for the
    // larger hypoid pinion), mean pitch radius, offset angle, hypoid
    // dimension factor K1, pinion mean radius, start value of η.
    let d_int2 = (u * ds.cos()).atan2(1.2 * (1.0 - u * ds.sin()));
    let r_mpt2 = (de2 - c.b2 * d_int2.sin()) / 2.0;
    let eps_i = asin_checked(
        a * d_int2.sin() / r_mpt2,
        "the approximate pinion offset angle (offset `a_mm` too large)",
    )?;
    let k1 = beta_d1.tan() * eps_i.sin() + eps_i.cos();
    let r_mn1 = r_mpt2 * k1 / u;
    let eta0 = (a / (r_mpt2 * (d_int2.tan() * ds.cos() - ds.sin()) + r_mn1)).atan();
    // (17)–(40) for one η: the cones and the check ρ_mβ/ρ_lim − 1.
    let trial = |eta: f64| -> Result<(Clause6, f64)> {
        let eps2 = asin_checked((a - r_mn1 * eta.sin()) / r_mpt2, "ε2 (formula 17)")?;
        let d_int1 = (eta.sin() / (eps2.tan() * ds.cos()) + ds.tan() * eta.cos()).atan();
        let eps2p = asin_checked(eps2.sin() * ds.cos() / d_int1.cos(), "ε2' (formula 19)")?;
        let beta_int1 = ((k1 - eps2p.cos()) / eps2p.sin()).atan();
        let dk = eps2p.sin() * (beta_d1.tan() - beta_int1.tan());
        let dr1 = r_mpt2 * dk / u;
        let eps1 = asin_checked(eps2.sin() - dr1 / r_mpt2 * eta.sin(), "ε1 (formula 23)")?;
        let delta1 = (eta.sin() / (eps1.tan() * ds.cos()) + ds.tan() * eta.cos()).atan();
        let eps1p = asin_checked(eps1.sin() * ds.cos() / delta1.cos(), "ε1' (formula 25)")?;
        let beta_m1 = ((k1 + dk - eps1p.cos()) / eps1p.sin()).atan();
        let beta_m2 = beta_m1 - eps1p;
        let delta2 = (eps1.sin() / (eta.tan() * ds.cos()) + eps1.cos() * ds.tan()).atan();
        let s = Clause6 {
            delta1,
            delta2,
            rm1: (r_mn1 + dr1) / delta1.sin(),
            rm2: r_mpt2 / delta2.sin(),
            beta_m1,
            beta_m2,
            c_be2: 0.5,
            check: 0.0,
            trials: 0,
        };
        let alpha_lim = limit_pressure_angle(&s, eps1p);
        let rho = lengthwise_curvature_radius(s.rm2, beta_m2, delta2, c.z2, c.rc0, c.z0)?;
        let r = rho * limit_curvature(&s, alpha_lim) - 1.0;
        if !(r.is_finite() && s.rm1 > 0.0 && s.rm2 > 0.0) {
            return Err(fail(
                1,
                format!("no valid cones at η = {:.4}°", eta.to_degrees()),
            ));
        }
        Ok((s, r))
    };
    let (mut s, mut r) = trial(eta0)?;
    let mut trials = 1;
    if r.abs() > 0.01 {
        let f = |eta: f64| trial(eta).ok().map(|t| t.1);
        let (eta, evals) = root_near(&f, eta0, 0.1f64.to_radians(), 200).ok_or_else(|| {
            fail(
                1,
                format!(
                    "ρ_mβ = ρ_lim has no root within ±20° of the start value of η (check {r:.4} there): \
                     cutter radius `rc0_mm` incompatible with `beta_m1_desired_deg` and the offset"
                ),
            )
        })?;
        (s, r) = trial(eta)?;
        trials = evals;
    }
    // (41): the mean point is not at mid face width.
    let c_be2 = (de2 / (2.0 * s.delta2.sin()) - s.rm2) / c.b2;
    if !(0.0..1.0).contains(&c_be2) {
        return Err(fail(
            1,
            format!(
                "the mean point leaves the face width (c_be2 = {c_be2:.4}; `b2_mm` or `de2_mm`)"
            ),
        ));
    }
    Ok(Clause6 {
        c_be2,
        check: r,
        trials,
        ..s
    })
}

/// Method 2, formulae (42)–(83).
pub fn method2(c: &ConeInputs) -> Result<Clause6> {
    let dm2 = c
        .dm2
        .ok_or_else(|| missing("dm2_mm", "method 2 starts from the mean pitch diameter"))?;
    let b2 = c
        .beta_m2
        .ok_or_else(|| missing("beta_m2_deg", "method 2 needs it"))?;
    let z0 =
        c.z0.ok_or_else(|| missing("z0", "method 2 is face hobbing"))?;
    let (a, u, sg, rc0) = (c.a, c.z2 / c.z1, c.sigma, c.rc0);
    // (42)–(56): start value.
    let nu = asin_checked(
        z0 * dm2 * b2.cos() / (2.0 * c.z2 * rc0),
        "the cutter lead angle ν (`rc0_mm` too small for `z0`)",
    )?;
    let lambda = FRAC_PI_2 - b2 + nu;
    let d1_app = sg.sin().atan2(u + sg.cos());
    let d2_app = sg - d1_app;
    let zm_app = asin_checked(
        (2.0 * a / dm2) / (1.0 + d2_app.cos() / (u * d1_app.cos())),
        "the approximate pinion offset angle (offset `a_mm` too large for `dm2_mm`)",
    )?;
    let f_app = b2.cos() / (b2 + zm_app).cos();
    let dm1_app = f_app * dm2 / u;
    let phi2 = (u * zm_app.cos()).atan2(u / d2_app.tan() + (f_app - 1.0) * sg.sin());
    let rm_app = dm2 / (2.0 * phi2.sin());
    let eta1 = ((rc0 * nu.cos() - rm_app * b2.sin()) / (rc0 * nu.sin() + rm_app * b2.cos())).atan();
    let phi3 = ((b2 + eta1).tan() / phi2.sin()).atan();
    let d1pp = (dm1_app * sg.sin())
        .atan2(dm2 * zm_app.cos() + dm1_app * sg.cos() - 2.0 * a / (phi3 + zm_app).tan());
    let d2pp = sg - d1pp;
    let d2imp0 = (d2pp.tan() * zm_app.cos()).atan();
    // (57)–(82) for one δ2imp: the cones and the check R_m1/R_mcheck − 1.
    let trial = |d2imp: f64| -> Result<(Clause6, f64)> {
        let eta_p = (zm_app.sin() * d2imp.cos() / (sg - d2imp).cos()).atan();
        let eta_app = (2.0 * a
            / (dm2 * d2imp.tan() + dm1_app * eta_p.cos() * (b2 + eta1).sin() / (sg - d2imp).cos()))
        .atan();
        let zm_imp = asin_checked(
            2.0 * a / dm2
                - f_app * eta_app.tan() * d2imp.sin() * eta_p.cos() / (u * (sg - d2imp).cos()),
            "ζ_m,imp (formula 59)",
        )?;
        let zmp_imp = (zm_imp.tan() * sg.sin() / (sg - d2imp).cos()).atan();
        let f = b2.cos() / (b2 + zmp_imp).cos();
        let dm1 = f * dm2 / u;
        let phi4 = (lambda.sin() * sg.sin()).atan2(dm2 / (2.0 * rc0) - lambda.cos() * d2imp.sin());
        let d1pp_imp = (dm1 * sg.sin()).atan2(
            dm2 * zm_imp.cos() + dm1 * sg.cos() * eta_p.cos() - 2.0 * a / (phi4 + zm_imp).tan(),
        );
        let delta2 = ((sg - d1pp_imp).tan() * zmp_imp.cos()).atan();
        let phi5 = (delta2.tan() / zm_imp.cos()).atan();
        let eta_pimp = (eta_app.tan() * phi5.sin() / (sg - phi5).cos()).atan();
        let eta = (2.0 * a
            / (dm2 * delta2.tan() + dm1 * eta_pimp.cos() * phi5.sin() / (sg - phi5).cos()))
        .atan();
        let zeta_m = asin_checked(delta2.tan() * eta.tan(), "ζ_m (formula 70)")?;
        let zeta_mp = (zeta_m.tan() * sg.sin() / (sg - delta2).cos()).atan();
        let beta_m1 = b2 + zeta_mp;
        let dm1 = dm2 * b2.cos() / (u * beta_m1.cos());
        // (74)/(75): ξ = arctan(tan Σ cos ζ_m) − δ2, written with atan2 so
        // that Σ = 90° (formula 75: ξ = 90° − δ2) is the same branch.
        let xi = (sg.sin() * zeta_m.cos()).atan2(sg.cos()) - delta2;
        let delta1 = (xi.tan() * zeta_mp.cos()).atan();
        let rm1 = dm1 / (2.0 * delta1.sin());
        let rm2 = dm2 / (2.0 * delta2.sin());
        let rho_p0 = (rc0 * rc0 + rm2 * rm2 - 2.0 * rc0 * rm2 * lambda.cos()).sqrt();
        let phi6 = asin_checked(rc0 * lambda.sin() / rho_p0, "φ6 (formula 80)")?;
        let rm_check = rm2 * phi6.sin() / (PI - zeta_mp - phi6).sin();
        let r = rm1 / rm_check - 1.0;
        if !(r.is_finite() && rm1 > 0.0 && rm2 > 0.0 && delta1 > 0.0 && delta2 > 0.0) {
            return Err(fail(
                2,
                format!("no valid cones at δ2imp = {:.4}°", d2imp.to_degrees()),
            ));
        }
        let s = Clause6 {
            delta1,
            delta2,
            rm1,
            rm2,
            beta_m1,
            beta_m2: b2,
            c_be2: 0.5,
            check: r,
            trials: 0,
        };
        Ok((s, r))
    };
    let (mut s, mut r) = trial(d2imp0)?;
    let mut trials = 1;
    if r.abs() > 0.01 {
        let f = |x: f64| trial(x).ok().map(|t| t.1);
        let (x, evals) = root_near(&f, d2imp0, 0.1f64.to_radians(), 200).ok_or_else(|| {
            fail(
                2,
                format!(
                    "R_m1 = R_mcheck has no root within ±20° of the start value (check {r:.4} there): \
                     cutter radius `rc0_mm` / `z0` incompatible with the offset and `beta_m2_deg`"
                ),
            )
        })?;
        (s, r) = trial(x)?;
        trials = evals;
    }
    Ok(Clause6 {
        check: r,
        trials,
        ..s
    })
}

/// Method 3, formulae (84)–(109).
pub fn method3(c: &ConeInputs) -> Result<Clause6> {
    // Formula (88) takes d_m2 from d_e2 at each pass; a given d_m2 is used
    // as it is (this code's extension: the mean point is then fixed).
    let wheel_dm2 = |delta2: f64| -> Result<f64> {
        match (c.de2, c.dm2) {
            (Some(de2), _) => Ok(de2 - c.b2 * delta2.sin()),
            (None, Some(dm2)) => Ok(dm2),
            _ => Err(missing(
                "de2_mm",
                "method 3 starts from the outer pitch diameter",
            )),
        }
    };
    let b2 = c
        .beta_m2
        .ok_or_else(|| missing("beta_m2_deg", "method 3 needs it"))?;
    let (a, u, sg, rc0) = (c.a, c.z2 / c.z1, c.sigma, c.rc0);
    // (85)–(87): start with F = 1 (the bevel-gear cones).
    let mut f = 1.0;
    let mut delta2 = sg.sin().atan2(f / u + sg.cos());
    let mut delta1 = sg - delta2;
    for pass in 1..=MAX_ITERATIONS {
        // (88)–(106).
        let dm2 = wheel_dm2(delta2)?;
        let zeta_m = asin_checked(
            2.0 * a / (dm2 * (1.0 + f * delta2.cos() / (u * delta1.cos()))),
            "ζ_m (formula 89; offset `a_mm` too large)",
        )?;
        let d1 = asin_checked(
            zeta_m.cos() * sg.sin() * delta2.cos() - sg.cos() * delta2.sin(),
            "δ1 (formula 90)",
        )?;
        let zeta_mp = asin_checked(zeta_m.sin() * sg.sin() / d1.cos(), "ζ_mp (formula 91)")?;
        let m_mn = b2.cos() * dm2 / c.z2;
        let beta_m1 = b2 + zeta_mp;
        let f_new = b2.cos() / beta_m1.cos();
        let dm1 = dm2 / u * f_new;
        let rm1 = dm1 / (2.0 * d1.sin());
        let rm2 = dm2 / (2.0 * delta2.sin());
        let nu = match c.z0 {
            Some(z0) => asin_checked(
                z0 * m_mn / (2.0 * rc0),
                "the cutter lead angle ν (`rc0_mm` too small for `z0`)",
            )?,
            None => 0.0,
        };
        let theta_m = (delta2.sin() * zeta_m.tan()).atan();
        let a3 = rc0 * (b2 - nu).cos().powi(2);
        let a4 = rm2 * (b2 + theta_m).cos() * b2.cos();
        let a5 = zeta_mp.sin() * theta_m.cos() * nu.cos();
        let a6 = rm2 * b2.cos() + rc0 * nu.sin();
        let a7 = beta_m1.cos() * (b2 + theta_m).cos()
            - (b2 + theta_m - nu).sin() * zeta_mp.sin() / (b2 - nu).cos();
        let rm_int = a3 * a4 / (a5 * a6 + a3 * a7);
        let r = (rm_int - rm1) / rm1;
        if !(r.is_finite() && rm_int > 0.0 && rm1 > 0.0) {
            return Err(fail(
                3,
                "no valid cones (cutter radius `rc0_mm` incompatible with the offset and `beta_m2_deg`)",
            ));
        }
        if r.abs() <= 1e-4 {
            return Ok(Clause6 {
                delta1: d1,
                delta2,
                rm1,
                rm2,
                beta_m1,
                beta_m2: b2,
                c_be2: 0.5,
                check: r,
                trials: pass,
            });
        }
        // (107), (108): improved pitch angles for the next pass.
        let d1i = asin_checked(dm1 / (2.0 * rm_int), "δ1' (formula 107)")?;
        let s2 = (sg.sin() * zeta_m.sin()).powi(2);
        let c2 = (d1i.sin() * zeta_m.cos() * sg.sin() + d1i.cos() * zeta_mp.cos() * sg.cos())
            / (1.0 - s2);
        if !(c2.abs() <= 1.0) {
            return Err(fail(3, "δ2' (formula 108) has no solution"));
        }
        delta1 = d1i;
        delta2 = c2.acos();
        f = f_new;
    }
    Err(fail(
        3,
        format!("the passes (88)–(108) did not meet |R_mint − R_m1| ≤ 1e-4 R_m1 in {MAX_ITERATIONS} passes"),
    ))
}

#[cfg(test)]
mod tests;
