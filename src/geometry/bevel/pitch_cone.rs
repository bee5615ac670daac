//! Pitch-cone parameters, ISO 23509:2016 clause 6, and the basic data of
//! clause 7.2 derived from them.
//!
//! Every method ends in the seven quantities that Annex A.2 of the standard
//! names as clause 6's common result: R_m1, R_m2, δ1, δ2, β_m1, β_m2 and the
//! face width factor c_be2 ([`Clause6`]). Clause 7.2 then derives, the same
//! way for all methods, d_m1, d_m2, the offset angles ζ_m (pinion axial
//! plane) and ζ_mp (pitch plane), the offset in the pitch plane a_p, the
//! mean normal module m_mn, the limit pressure angle α_lim and R_e2
//! ([`finish`], formulae (110)–(117), (122)).
//!
//! * Method 0 (bevel gears, formulae (1)–(7)): tan δ1 = sin Σ / (cos Σ + u),
//!   δ2 = Σ − δ1, R_e = d_e2 / (2 sin δ2), R_m1 = R_m2 = R_e − b2/2,
//!   β_m1 = β_m2, c_be2 = 1/2 (given d_m2 instead: R_m = d_m2 / (2 sin δ2)).
//! * Methods 1–3 (hypoid gears): see [`super::hypoid_methods`]. A zero
//!   offset gives the method-0 cones for every method (the clean branch in
//!   `pitch_cones` of [`super::blank_design`]: method 1's chain divides 0
//!   by 0 there).
//!
//! Formula numbers are those of ISO 23509:2016 as transcribed in a public
//! C# implementation of the standard (namespace `ISO23509Calc`, found with
//! the code search of this project; see `verification/iso23509_blank/
//! README.md`); the formulae were re-derived or checked where said.

use crate::error::{FlankError, Result};

/// The pitch cones of a pair with the clause 7.2 basic data (mm, rad).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PitchCones {
    /// Gear ratio u = z2 / z1.
    pub u: f64,
    /// Pitch angles δ1, δ2.
    pub delta1: f64,
    pub delta2: f64,
    /// Mean cone distances R_m1, R_m2 (equal for a = 0).
    pub rm1: f64,
    pub rm2: f64,
    /// Outer cone distance of the wheel R_e2 = R_m2 + c_be2 b2 (formula 122).
    pub re2: f64,
    /// Face width factor c_be2 = (R_e2 − R_m2) / b2 (1/2 except method 1).
    pub c_be2: f64,
    /// Mean pitch diameters d_m1, d_m2 (formulae 110, 111).
    pub dm1: f64,
    pub dm2: f64,
    /// Mean spiral angles β_m1, β_m2.
    pub beta_m1: f64,
    pub beta_m2: f64,
    /// Pinion offset angle in the axial plane ζ_m (formula 113; 0 for a = 0).
    pub zeta_m: f64,
    /// Offset angle in the pitch plane ζ_mp (formula 114; 0 for a = 0).
    pub zeta_mp: f64,
    /// Offset in the pitch plane a_p = R_m2 sin ζ_mp (formula 115).
    pub ap: f64,
    /// Mean normal module m_mn = 2 R_m2 sin δ2 cos β_m2 / z2 (formula 116).
    pub m_mn: f64,
    /// Limit pressure angle α_lim (formula 117; 0 for a = 0).
    pub alpha_lim: f64,
    /// The method's closing check at the returned trial (method 1:
    /// ρ_mβ/ρ_lim − 1, method 2: R_m1/R_mcheck − 1, method 3:
    /// (R_mint − R_m1)/R_m1; 0 for method 0 and a = 0) and the number of
    /// trials the iteration took (1: the standard's start value passed).
    pub check: f64,
    pub trials: usize,
}

/// Inputs of the pitch-cone calculation in internal units.
#[derive(Clone, Copy, Debug)]
pub struct ConeInputs {
    pub method: u8,
    pub sigma: f64,
    pub a: f64,
    pub z1: f64,
    pub z2: f64,
    pub de2: Option<f64>,
    pub dm2: Option<f64>,
    pub b2: f64,
    /// Wheel mean spiral angle (methods 0, 2, 3; method 1 computes it).
    pub beta_m2: Option<f64>,
    /// Desired pinion mean spiral angle β_Δ1 (method 1).
    pub beta_m1_desired: Option<f64>,
    pub rc0: f64,
    /// Blade groups of a face-hobbing cutter (None: face milling).
    pub z0: Option<f64>,
}

/// Clause 6's common result (Annex A.2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Clause6 {
    pub delta1: f64,
    pub delta2: f64,
    pub rm1: f64,
    pub rm2: f64,
    pub beta_m1: f64,
    pub beta_m2: f64,
    pub c_be2: f64,
    pub check: f64,
    pub trials: usize,
}

pub(super) fn missing(key: &str, why: &str) -> FlankError {
    FlankError::Model(format!("blank input `{key}`: missing ({why})"))
}

/// Method 0, formulae (1)–(7); `beta` is the common spiral angle.
pub fn method0(c: &ConeInputs, beta: f64) -> Result<Clause6> {
    let u = c.z2 / c.z1;
    let delta1 = c.sigma.sin().atan2(c.sigma.cos() + u);
    let delta2 = c.sigma - delta1;
    let rm = match (c.de2, c.dm2) {
        (Some(de2), _) => de2 / (2.0 * delta2.sin()) - c.b2 / 2.0,
        (None, Some(dm2)) => dm2 / (2.0 * delta2.sin()),
        (None, None) => return Err(missing("de2_mm", "give de2_mm or dm2_mm")),
    };
    if rm <= 0.0 {
        return Err(FlankError::Model(
            "blank input `b2_mm`: face width not smaller than twice the outer cone distance".into(),
        ));
    }
    Ok(Clause6 {
        delta1,
        delta2,
        rm1: rm,
        rm2: rm,
        beta_m1: beta,
        beta_m2: beta,
        c_be2: 0.5,
        check: 0.0,
        trials: 1,
    })
}

/// `asin` that refuses an argument outside [−1, 1] with a message.
pub(super) fn asin_checked(x: f64, what: &str) -> Result<f64> {
    if x.is_finite() && x.abs() <= 1.0 {
        Ok(x.asin())
    } else {
        Err(FlankError::Model(format!(
            "blank design: {what} has no solution (sine {x:.6})"
        )))
    }
}

/// Limit pressure angle, formula (117) (and (32) inside method 1):
/// tan α_lim = −(tan δ1 tan δ2 / cos ζ_mp) (R_m1 sin β_m1 − R_m2 sin β_m2)
/// / (R_m1 tan δ1 + R_m2 tan δ2).
pub fn limit_pressure_angle(s: &Clause6, zeta_mp: f64) -> f64 {
    let (t1, t2) = (s.delta1.tan(), s.delta2.tan());
    (-(t1 * t2 / zeta_mp.cos()) * (s.rm1 * s.beta_m1.sin() - s.rm2 * s.beta_m2.sin())
        / (s.rm1 * t1 + s.rm2 * t2))
        .atan()
}

/// Clause 7.2 basic data, formulae (110)–(117) and (122).
pub fn finish(c: &ConeInputs, s: &Clause6) -> Result<PitchCones> {
    let dm1 = 2.0 * s.rm1 * s.delta1.sin();
    let dm2 = 2.0 * s.rm2 * s.delta2.sin();
    let zeta_m = asin_checked(
        2.0 * c.a / (dm2 + dm1 * s.delta2.cos() / s.delta1.cos()),
        "the pinion offset angle ζ_m (offset `a_mm` too large for the pitch diameters)",
    )?;
    let zeta_mp = asin_checked(
        zeta_m.sin() * c.sigma.sin() / s.delta1.cos(),
        "the offset angle in the pitch plane ζ_mp (offset `a_mm` too large)",
    )?;
    Ok(PitchCones {
        u: c.z2 / c.z1,
        delta1: s.delta1,
        delta2: s.delta2,
        rm1: s.rm1,
        rm2: s.rm2,
        re2: s.rm2 + s.c_be2 * c.b2,
        c_be2: s.c_be2,
        dm1,
        dm2,
        beta_m1: s.beta_m1,
        beta_m2: s.beta_m2,
        zeta_m,
        zeta_mp,
        ap: s.rm2 * zeta_mp.sin(),
        m_mn: dm2 * s.beta_m2.cos() / c.z2,
        alpha_lim: limit_pressure_angle(s, zeta_mp),
        check: s.check,
        trials: s.trials,
    })
}

/// Face-hobbing quantities of the wheel (clause 7.6.1, formulae (176)–(178),
/// and (42)–(43)): the cutter lead angle ν, sin ν = z0 m_mn / (2 r_c0); the
/// angle at P between the generator and the cutter radius λ = 90° − β_m2 + ν;
/// the distance ρ_P0 of the cutter centre from the crown-gear centre
/// (triangle crown centre, P, cutter centre: ρ_P0² = R_m2² + r_c0² −
/// 2 R_m2 r_c0 cos λ); the base radius of the epicycloid ρ_b = ρ_P0 /
/// (1 + z0 sin δ2 / z2) (rolling circles in the ratio z0 : z_p, z_p = z2 /
/// sin δ2 the crown gear's teeth).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hobbing {
    pub nu: f64,
    pub lambda: f64,
    pub rho_p0: f64,
    pub rho_b: f64,
}

pub fn hobbing(z0: f64, z2: f64, rc0: f64, cones: &PitchCones) -> Result<Hobbing> {
    let s = z0 * cones.m_mn / (2.0 * rc0);
    if !(s.abs() < 1.0) {
        return Err(FlankError::Model(format!(
            "blank input `rc0_mm`: cutter radius {rc0} too small for z0 = {z0} blade groups"
        )));
    }
    let nu = s.asin();
    let lambda = std::f64::consts::FRAC_PI_2 - cones.beta_m2 + nu;
    let rm2 = cones.rm2;
    let rho_p0 = (rm2 * rm2 + rc0 * rc0 - 2.0 * rm2 * rc0 * lambda.cos()).sqrt();
    Ok(Hobbing {
        nu,
        lambda,
        rho_p0,
        rho_b: rho_p0 / (1.0 + z0 / z2 * cones.delta2.sin()),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    pub(crate) fn inputs(sigma_deg: f64) -> ConeInputs {
        ConeInputs {
            method: 0,
            sigma: sigma_deg.to_radians(),
            a: 0.0,
            z1: 13.0,
            z2: 41.0,
            de2: Some(200.0),
            dm2: None,
            b2: 30.0,
            beta_m2: Some(30f64.to_radians()),
            beta_m1_desired: None,
            rc0: 100.0,
            z0: None,
        }
    }

    #[test]
    fn method0_pitch_angles_follow_the_shaft_angle() {
        for sigma in [60.0, 90.0, 110.0] {
            let c = inputs(sigma);
            let p = finish(&c, &method0(&c, c.beta_m2.unwrap()).unwrap()).unwrap();
            let u = 41.0 / 13.0;
            let s = c.sigma;
            assert!((p.delta1.tan() - s.sin() / (s.cos() + u)).abs() < 1e-12);
            assert!((p.delta1 + p.delta2 - s).abs() < 1e-12);
            // Both members share the mean cone distance and the normal module.
            assert!((p.dm1 / p.delta1.sin() - p.dm2 / p.delta2.sin()).abs() < 1e-9);
            assert!((p.dm1 * p.beta_m1.cos() / 13.0 - p.m_mn).abs() < 1e-12);
            assert!(p.zeta_m == 0.0 && p.alpha_lim == 0.0);
        }
    }
}
