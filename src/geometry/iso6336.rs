//! Tooth stiffness of ISO 6336-1 (method B): the plausibility band against
//! which FE single-tooth and mesh stiffnesses are compared.
//!
//! q′ = C1 + C2/z_n1 + C3/z_n2 + C4·x1 + C5·x1/z_n1 + C6·x2 + C7·x2/z_n2
//!      + C8·x1² + C9·x2² (mm·µm/N), c′_th = 1/q′,
//! c′ = c′_th·C_M·C_R·C_B·cos β, c_γα = c′(0.75 ε_α + 0.25)
//! (ISO 6336-1:2006, 9.3; C_M = 0.8, C_R = 1 for solid blanks,
//! C_B = [1 + 0.5(1.2 − h_fP/m_n)][1 − 0.02(20° − α_n)]; z_n = z/(cos²β_b cos β)).
//! For an internal use of the band, x and z are those of the pair's pinion
//! (1) and wheel (2); ISO limits the formula to external gears,
//! −0.5 ≤ x1 + x2 ≤ 2, and so does this function.

use crate::error::FlankError;
use crate::geometry::involute::base_helix_angle;
use crate::geometry::PairSpec;

/// ISO 6336-1 method B coefficients C1…C9 (mm·µm/N).
const C: [f64; 9] = [
    0.04723, 0.15551, 0.25791, -0.00635, -0.11654, -0.00193, -0.24188, 0.00529, 0.00182,
];

/// Stiffness figures of ISO 6336-1 for a pair (N/(mm·µm)).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct ToothStiffness {
    /// Virtual numbers of teeth z_n1, z_n2.
    pub virtual_teeth: [f64; 2],
    /// Minimum flexibility q′ (mm·µm/N).
    pub flexibility: f64,
    /// Theoretical single stiffness c′_th = 1/q′.
    pub single_theoretical: f64,
    /// Basic rack factor C_B.
    pub basic_rack_factor: f64,
    /// Single stiffness c′ = c′_th C_M C_R C_B cos β (C_M = 0.8, C_R = 1).
    pub single: f64,
    /// Mesh stiffness c_γα = c′(0.75 ε_α + 0.25).
    pub mesh: f64,
}

/// c′ and c_γα of a pair with transverse contact ratio `contact_ratio`.
pub fn tooth_stiffness(pair: &PairSpec, contact_ratio: f64) -> Result<ToothStiffness, FlankError> {
    let (g1, g2) = (&pair.pinion, &pair.gear);
    let beta = g1.helix_angle.abs();
    let beta_b = base_helix_angle(g1).abs();
    let zn = |z: u32| z as f64 / (beta_b.cos().powi(2) * beta.cos());
    let (zn1, zn2) = (zn(g1.teeth), zn(g2.teeth));
    let (x1, x2) = (g1.profile_shift, g2.profile_shift);
    if !(-0.5..=2.0).contains(&(x1 + x2)) {
        return Err(FlankError::Model(format!(
            "ISO 6336-1 stiffness: x1 + x2 = {:.4} outside the formula's range [−0.5, 2]",
            x1 + x2
        )));
    }
    let q = C[0]
        + C[1] / zn1
        + C[2] / zn2
        + C[3] * x1
        + C[4] * x1 / zn1
        + C[5] * x2
        + C[6] * x2 / zn2
        + C[7] * x1 * x1
        + C[8] * x2 * x2;
    if !(q > 0.0) {
        return Err(FlankError::Model(format!(
            "ISO 6336-1 stiffness: non-positive flexibility q′ = {q}"
        )));
    }
    // the gear's dedendum is the rack's addendum h_fP = rack.addendum·m_n
    let hfp = g1.rack.addendum;
    let alpha_deg = g1.normal_pressure_angle.to_degrees();
    let cb = (1.0 + 0.5 * (1.2 - hfp)) * (1.0 - 0.02 * (20.0 - alpha_deg));
    let cth = 1.0 / q;
    let single = cth * 0.8 * 1.0 * cb * beta.cos();
    Ok(ToothStiffness {
        virtual_teeth: [zn1, zn2],
        flexibility: q,
        single_theoretical: cth,
        basic_rack_factor: cb,
        single,
        mesh: single * (0.75 * contact_ratio + 0.25),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{GearSpec, Hand, RackProfile};

    fn gear(z: u32, x: f64, beta_deg: f64, hand: Hand) -> GearSpec {
        GearSpec {
            teeth: z,
            normal_module: 4.0,
            normal_pressure_angle: 20f64.to_radians(),
            helix_angle: beta_deg.to_radians(),
            hand,
            face_width: 20.0,
            profile_shift: x,
            rack: RackProfile::default(),
            tip_diameter: None,
            bore_diameter: 20.0,
        }
    }

    /// Spur 20/40, x = 0, ISO 53 rack: q′ = 0.04723 + 0.15551/20 + 0.25791/40
    /// = 0.0614530 mm·µm/N, c′_th = 16.2726, C_B = 0.975,
    /// c′ = 16.2726·0.8·0.975 = 12.6926 N/(mm·µm) (the familiar ≈ 14 N/(mm·µm)
    /// order of magnitude of ISO's simplified value for steel spur gears).
    #[test]
    fn spur_example_by_hand() {
        let pair = PairSpec {
            pinion: gear(20, 0.0, 0.0, Hand::Right),
            gear: gear(40, 0.0, 0.0, Hand::Left),
            centre_distance: 120.0,
        };
        let s = tooth_stiffness(&pair, 1.6).unwrap();
        let q = 0.04723 + 0.15551 / 20.0 + 0.25791 / 40.0;
        assert!((s.flexibility - q).abs() < 1e-15);
        assert!((s.basic_rack_factor - 0.975).abs() < 1e-15);
        assert!((s.single - 0.8 * 0.975 / q).abs() < 1e-12);
        assert!((s.mesh - s.single * (0.75 * 1.6 + 0.25)).abs() < 1e-12);
        assert!((s.single - 12.6926).abs() < 1e-4, "{}", s.single);
    }

    /// Helical gears use virtual teeth and cos β.
    #[test]
    fn helical_uses_virtual_teeth() {
        let pair = PairSpec {
            pinion: gear(21, 0.0, 20.0, Hand::Right),
            gear: gear(37, 0.0, 20.0, Hand::Left),
            centre_distance: 0.0,
        };
        let s = tooth_stiffness(&pair, 1.5).unwrap();
        let bb = (20f64.to_radians().sin() * 20f64.to_radians().cos()).asin();
        let zn1 = 21.0 / (bb.cos().powi(2) * 20f64.to_radians().cos());
        assert!((s.virtual_teeth[0] - zn1).abs() < 1e-12);
        assert!(s.single < s.single_theoretical * 0.8);
    }

    #[test]
    fn out_of_range_shifts_are_an_error() {
        let pair = PairSpec {
            pinion: gear(20, -0.4, 0.0, Hand::Right),
            gear: gear(40, -0.4, 0.0, Hand::Left),
            centre_distance: 0.0,
        };
        assert!(tooth_stiffness(&pair, 1.5).is_err());
    }
}
