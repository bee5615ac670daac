//! Face widths of both members, ISO 23509:2016 clause 7.2 (formulae
//! (123), (127), (128)) and clause 7.5 (formulae (154)–(173)).
//!
//! The wheel spans R_i2 = R_e2 − b2 … R_e2 with b_e2 = R_e2 − R_m2 outside
//! and b_i2 = R_m2 − R_i2 inside the mean point. The pinion of a hypoid pair
//! must be wider to cover the wheel's face: in the pitch plane the wheel's
//! heel and toe circles cut the pinion generator, which is offset by a_p,
//! b_p1 = √(R_e2² − a_p²) − √(R_i2² − a_p²), b_1A = √(R_m2² − a_p²) −
//! √(R_i2² − a_p²); then per method:
//!
//! * method 0: b1 = b2, b_e1 = c_be2 b1;
//! * method 1 (Gleason): the face width projected along the pinion axis,
//!   with the face cone and the wheel's root line, formulae (159)–(166);
//! * method 2 (Oerlikon): b1 = b2 (1 + tan² ζ_mp), b_e1 = c_be2 b1;
//! * method 3 (Klingelnberg): b1 = ⌊b_p1 + 3 m_mn |tan ζ_mp| + 1⌋ (whole
//!   millimetres, as the standard writes it), spread so that the
//!   additional width (b1 − b_p1)/2 lies on each side.

use super::face_angles::FaceAngles;
use super::pitch_cone::PitchCones;
use super::tooth_depth::ToothDepth;
use crate::error::{FlankError, Result};

/// Face widths (mm): along the pitch cones, from the mean point outwards
/// (`be`) and inwards (`bi`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FaceWidths {
    pub b1: f64,
    pub be1: f64,
    pub bi1: f64,
    pub b2: f64,
    pub be2: f64,
    pub bi2: f64,
    /// Pinion face width in the pitch plane b_p1 and its part inside the
    /// mean point b_1A.
    pub bp1: f64,
    pub b1a: f64,
}

/// Clause 7.5 for `method`.
pub fn face_widths(
    method: u8,
    c: &PitchCones,
    b2: f64,
    f: &FaceAngles,
    d: &ToothDepth,
) -> Result<FaceWidths> {
    let ri2 = c.re2 - b2;
    let ap2 = c.ap * c.ap;
    if ri2 * ri2 <= ap2 {
        return Err(FlankError::Model(format!(
            "blank input `b2_mm`: the wheel's inner end (R_i2 = {ri2:.3} mm) does not reach past the \
             offset in the pitch plane a_p = {:.3} mm (face width too large for the offset)",
            c.ap
        )));
    }
    let bp1 = (c.re2 * c.re2 - ap2).sqrt() - (ri2 * ri2 - ap2).sqrt();
    let b1a = (c.rm2 * c.rm2 - ap2).sqrt() - (ri2 * ri2 - ap2).sqrt();
    let (b1, be1, bi1) = match method {
        0 => (b2, c.c_be2 * b2, (1.0 - c.c_be2) * b2),
        1 => {
            let (d1, d2, zmp) = (c.delta1, c.delta2, c.zeta_mp);
            let lam = (zmp.sin() * d2.cos() / (c.u * d1.cos() + d2.cos() * zmp.cos())).atan();
            let b_reri1 = b2 * lam.cos() / (zmp - lam).cos();
            let dbx1 = d.hmw * f.zeta_r.sin() * (1.0 - 1.0 / c.u);
            let da1 = d1 + f.theta_a1;
            let along = da1.cos() / f.theta_a1.cos();
            let dgxe = c.c_be2 * b_reri1 * along + dbx1 - (d.hfm2 - d.c) * d1.sin();
            let dgxi = (1.0 - c.c_be2) * b_reri1 * along + dbx1 + (d.hfm2 - d.c) * d1.sin();
            let be1 = (dgxe + d.ham1 * d1.sin()) / along;
            let bi1 = (dgxi - d.ham1 * d1.sin()) / (d1.cos() - f.theta_a1.tan() * d1.sin());
            (be1 + bi1, be1, bi1)
        }
        2 => {
            let b1 = b2 * (1.0 + c.zeta_mp.tan().powi(2));
            (b1, c.c_be2 * b1, (1.0 - c.c_be2) * b1)
        }
        _ => {
            let b1 = (bp1 + 3.0 * c.m_mn * c.zeta_mp.tan().abs() + 1.0).floor();
            let bi1 = b1a + (b1 - bp1) / 2.0;
            (b1, b1 - bi1, bi1)
        }
    };
    Ok(FaceWidths {
        b1,
        be1,
        bi1,
        b2,
        be2: c.re2 - c.rm2,
        bi2: c.rm2 - ri2,
        bp1,
        b1a,
    })
}
