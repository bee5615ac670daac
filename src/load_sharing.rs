//! When a tooth pair carries load: the threshold that FE contact
//! ([`crate::mesh_cycle`]) and the LTCA ([`crate::ltca`]) share, so that
//! their contact ratios from load sharing (the roll-angle span in which the
//! middle pair is loaded, per angular pitch) are measured the same way.
//!
//! [`cycle`]: load sharing over one mesh cycle and the functional contact
//! ratio, from either method's forces per position and pair.

pub mod cycle;
pub use cycle::{cycle_sharing, CycleSharing};

/// Fraction of the nominal single-pair force T / r (r the pair's
/// [`crate::geometry::gear_pair::LineContactPair::nominal_moment_arm`], r_b1 cos β_b
/// for a cylindrical pair) above which a tooth pair counts as carrying load
/// (contact ratio, single contact).
pub const LOADED_FRACTION: f64 = 1e-3;

/// A loaded pinion rotation beyond the kinematic one (|TE|, rad) above
/// which both analyses warn that the answer is outside the small-
/// displacement model they solve (1.1°: the tooth rotates by that order and
/// the contact moves by a sizeable part of the tooth; the seed 002 pair
/// turns 0.005 rad at its nominal 312 N·m).
pub const LARGE_ROTATION_RAD: f64 = 0.02;

/// The warning of [`LARGE_ROTATION_RAD`] for a loaded TE (µrad), if due.
pub fn large_rotation_warning(te_urad: f64) -> Option<String> {
    (te_urad.abs() * 1e-6 > LARGE_ROTATION_RAD).then(|| {
        format!(
            "the loaded TE {:.4} rad is above {LARGE_ROTATION_RAD} rad: the teeth deflect beyond what the small-displacement (linear) model represents; the answer satisfies its equations but not the physics (lower the torque or stiffen the bodies)",
            te_urad * 1e-6
        )
    })
}

/// The error for a loaded TE (µrad) of a whole angular pitch
/// `pitch_rad` (2π/z₁) or more: the pinion would turn its next tooth into
/// the place of this one, so the tooth pairs the model holds are not the
/// ones in contact and its answer has no meaning at all (a linear model
/// of small displacements is far past its range long before).
pub fn beyond_pitch_error(te_urad: f64, pitch_rad: f64) -> Option<String> {
    let pitch = pitch_rad.abs();
    (te_urad.abs() * 1e-6 >= pitch).then(|| {
        format!(
            "the loaded TE {:.4} rad reaches the angular pitch {pitch:.4} rad: the pinion would turn by a whole tooth under this load, so the linear model's tooth pairs are not the ones in contact and no answer is given (lower the torque or stiffen the bodies; the small-displacement model holds to about {LARGE_ROTATION_RAD} rad)",
            te_urad * 1e-6
        )
    })
}

/// Arc seconds per radian (180 · 3600 / π; the point TCA's
/// `crate::tca::point_contact::ARCSEC_PER_RAD`, a module of the same layer).
const ARCSEC_PER_RAD: f64 = 180.0 * 3600.0 / std::f64::consts::PI;

/// The loaded TE at the gear (arcsec) from the loaded TE at the pinion
/// (µrad): Δθ₂ = −θ₁ · z₁/z₂. Every output of the LTCA and of FE contact
/// gives both forms (`te_urad`, pinion, > 0 under a driving torque;
/// `te_arcsec`, gear, the sign of the point TCA's Δφ₂ = φ₂ − (z₁/z₂) φ₁,
/// `src/tca/point_contact.rs`), whatever the pair kind. `ratio` = z₁/z₂.
pub fn te_arcsec_at_gear(te_urad: f64, ratio: f64) -> f64 {
    -te_urad * 1e-6 * ratio * ARCSEC_PER_RAD
}

/// The inverse of [`te_arcsec_at_gear`]: the pinion TE (µrad) from the gear
/// TE (arcsec).
pub fn te_urad_at_pinion(te_arcsec: f64, ratio: f64) -> f64 {
    -te_arcsec / (ratio * ARCSEC_PER_RAD) * 1e6
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn te_forms_convert_both_ways() {
        // 100 µrad at the pinion of a 13:39 pair: −100e-6 · (1/3) · 206 264.8″
        let a = te_arcsec_at_gear(100.0, 13.0 / 39.0);
        assert!((a + 6.875_493).abs() < 1e-6, "{a}");
        assert!((te_urad_at_pinion(a, 13.0 / 39.0) - 100.0).abs() < 1e-9);
    }

    #[test]
    fn beyond_pitch_error_from_one_pitch_on() {
        let pitch = 2.0 * std::f64::consts::PI / 13.0;
        assert!(beyond_pitch_error(423_557.0, pitch).is_none());
        assert!(beyond_pitch_error(-423_557.0, -pitch).is_none());
        let e = beyond_pitch_error(8_055_759.0, pitch).unwrap();
        assert!(e.contains("8.0558 rad") && e.contains("0.4833 rad"), "{e}");
        assert!(beyond_pitch_error(-500_000.0, pitch).is_some());
    }

    #[test]
    fn large_rotation_warning_above_the_threshold_only() {
        assert!(large_rotation_warning(4935.0).is_none());
        assert!(large_rotation_warning(-19_999.0).is_none());
        let w = large_rotation_warning(104_940.0).unwrap();
        assert!(
            w.contains("0.1049 rad") && w.contains("small-displacement"),
            "{w}"
        );
        assert!(large_rotation_warning(-25_000.0).is_some());
    }
}
