//! Axial positions of the mean point and the face and root angles of both
//! members, ISO 23509:2016 clause 7.2 (formulae (129)–(131)) and clause 7.4
//! (formulae (140)–(149)).
//!
//! The wheel's face and root cones are δ_a2 = δ2 + θ_a2, δ_f2 = δ2 − θ_f2
//! (θ = 0 for uniform depth). The pinion's face cone is made parallel to the
//! wheel's root cone and its root cone to the wheel's face cone (uniform
//! clearance): with the wheel's pitch apex at t_z2 beyond the crossing point
//! along its axis, the auxiliary angles
//! tan φ_R = a tan ΔΣ cos δ_f2 / (R_m2 cos θ_f2 − t_z2 cos δ_f2),
//! ζ_R = asin(a cos φ_R sin δ_f2 / (R_m2 cos θ_f2 − t_z2 cos δ_f2)) − φ_R
//! (and φ_o, ζ_o with the face cone) give
//! sin δ_a1 = sin ΔΣ sin δ_f2 + cos ΔΣ cos δ_f2 cos ζ_R,
//! sin δ_f1 = sin ΔΣ sin δ_a2 + cos ΔΣ cos δ_a2 cos ζ_o, ΔΣ = Σ − 90°.
//! For a = 0 this is θ_a1 = θ_f2, θ_f1 = θ_a2; for a hypoid of uniform depth
//! the pinion's face angle still differs slightly from its pitch angle.

use super::pitch_cone::{asin_checked, PitchCones};
use crate::error::Result;

/// Clause 7.2 axial positions and clause 7.4 angles (mm, rad).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FaceAngles {
    /// Crossing point to the mean point along the wheel / pinion axis.
    pub tzm1: f64,
    pub tzm2: f64,
    /// Pitch apex beyond the crossing point along the pinion / wheel axis.
    pub tz1: f64,
    pub tz2: f64,
    /// Pinion offset angles in the root and face planes ζ_R, ζ_o.
    pub zeta_r: f64,
    pub zeta_o: f64,
    pub theta_a1: f64,
    pub theta_f1: f64,
    pub theta_a2: f64,
    pub theta_f2: f64,
}

/// Formulae (129)–(131), (140)–(149); `theta` = (θ_a2, θ_f2).
pub fn face_angles(c: &PitchCones, sigma: f64, a: f64, theta: (f64, f64)) -> Result<FaceAngles> {
    let ds = sigma - std::f64::consts::FRAC_PI_2;
    let (d1, d2) = (c.delta1, c.delta2);
    let k = c.dm2 + c.dm1 * d2.cos() / d1.cos();
    let tzm2 = c.dm1 * d2.sin() / (2.0 * d1.cos()) - 0.5 * c.zeta_m.cos() * ds.tan() * k;
    let tzm1 = c.dm2 / 2.0 * c.zeta_m.cos() * ds.cos() - tzm2 * ds.sin();
    let tz1 = c.rm1 * d1.cos() - tzm1;
    let tz2 = c.rm2 * d2.cos() - tzm2;
    let (theta_a2, theta_f2) = theta;
    let (da2, df2) = (d2 + theta_a2, d2 - theta_f2);
    // ζ for a cone of the wheel with angle δ and depth angle θ (142)–(145).
    let zeta = |delta: f64, th: f64, what: &str| -> Result<f64> {
        let den = c.rm2 * th.cos() - tz2 * delta.cos();
        let phi = (a * ds.tan() * delta.cos() / den).atan();
        Ok(asin_checked(a * phi.cos() * delta.sin() / den, what)? - phi)
    };
    let zeta_r = zeta(df2, theta_f2, "ζ_R (formula 144)")?;
    let zeta_o = zeta(da2, theta_a2, "ζ_o (formula 145)")?;
    let da1 = asin_checked(
        ds.sin() * df2.sin() + ds.cos() * df2.cos() * zeta_r.cos(),
        "δ_a1 (formula 146)",
    )?;
    let df1 = asin_checked(
        ds.sin() * da2.sin() + ds.cos() * da2.cos() * zeta_o.cos(),
        "δ_f1 (formula 147)",
    )?;
    Ok(FaceAngles {
        tzm1,
        tzm2,
        tz1,
        tz2,
        zeta_r,
        zeta_o,
        theta_a1: da1 - d1,
        theta_f1: d1 - df1,
        theta_a2,
        theta_f2,
    })
}
