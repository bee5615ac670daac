//! Spiral angles at the outer and inner ends of both members, ISO
//! 23509:2016 clause 7.6 (formulae (174)–(194)).
//!
//! The tooth trace lies in the wheel's crown gear (pitch plane). At the
//! crown-gear radius R:
//!
//! * face milling (circular arc of radius r_c0 whose centre is at the same
//!   distance from the crown-gear centre for every R):
//!   sin β(R) = (2 R_m2 r_c0 sin β_m2 − R_m2² + R²) / (2 R r_c0);
//! * face hobbing (extended epicycloid): with the cutter centre at ρ_P0 and
//!   the base radius ρ_b ([`super::pitch_cone::hobbing`]), the angle φ at the
//!   crown-gear centre between the point and the cutter centre,
//!   cos φ = (R² + ρ_P0² − r_c0²) / (2 R ρ_P0), and the instantaneous centre
//!   of the rolling circles at ρ_b along that line give
//!   tan β(R) = (R − ρ_b cos φ) / (ρ_b sin φ).
//!
//! The wheel's angles are at R_e2 and R_i2; the pinion's boundary points
//! lie on the pinion generator at b_e1 and b_i1 from the mean point, i.e. at
//! crown-gear radii R_e21, R_i21 (law of cosines with ζ_mp), where the
//! pinion's spiral angle is the wheel's plus the local offset angle
//! asin(a_p / R).

use super::face_width::FaceWidths;
use super::pitch_cone::{Hobbing, PitchCones};
use crate::error::{FlankError, Result};

/// Spiral angles at the ends (rad).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EndSpiralAngles {
    pub beta_e1: f64,
    pub beta_i1: f64,
    pub beta_e2: f64,
    pub beta_i2: f64,
}

/// Wheel spiral angle at crown-gear radius `r` (see the module docs).
pub fn wheel_spiral_angle(c: &PitchCones, rc0: f64, hob: Option<&Hobbing>, r: f64) -> Result<f64> {
    let incompatible = |what: &str| {
        FlankError::Model(format!(
            "blank input `rc0_mm`: the cutter radius {rc0} mm cannot cut the face width with \
             `beta_m2_deg` = {:.3}° ({what} at R = {r:.3} mm)",
            c.beta_m2.to_degrees()
        ))
    };
    match hob {
        None => {
            let s = (2.0 * c.rm2 * rc0 * c.beta_m2.sin() - c.rm2 * c.rm2 + r * r) / (2.0 * r * rc0);
            if s.abs() <= 1.0 {
                Ok(s.asin())
            } else {
                Err(incompatible("no spiral angle"))
            }
        }
        Some(h) => {
            let cphi = (r * r + h.rho_p0 * h.rho_p0 - rc0 * rc0) / (2.0 * r * h.rho_p0);
            if !(cphi.abs() <= 1.0) {
                return Err(incompatible("the epicycloid does not reach"));
            }
            let phi = cphi.acos();
            Ok(((r - h.rho_b * phi.cos()) / (h.rho_b * phi.sin())).atan())
        }
    }
}

/// Formulae (174)–(194).
pub fn end_spiral_angles(
    c: &PitchCones,
    w: &FaceWidths,
    rc0: f64,
    hob: Option<&Hobbing>,
) -> Result<EndSpiralAngles> {
    let zc = c.zeta_mp.cos();
    let re21 = (c.rm2 * c.rm2 + w.be1 * w.be1 + 2.0 * c.rm2 * w.be1 * zc).sqrt();
    let ri21 = (c.rm2 * c.rm2 + w.bi1 * w.bi1 - 2.0 * c.rm2 * w.bi1 * zc).sqrt();
    let pinion = |r: f64| -> Result<f64> {
        Ok(wheel_spiral_angle(c, rc0, hob, r)? + (c.ap / r).clamp(-1.0, 1.0).asin())
    };
    Ok(EndSpiralAngles {
        beta_e1: pinion(re21)?,
        beta_i1: pinion(ri21)?,
        beta_e2: wheel_spiral_angle(c, rc0, hob, c.re2)?,
        beta_i2: wheel_spiral_angle(c, rc0, hob, c.re2 - w.b2)?,
    })
}
