//! The `[pair]` section (kind, centre distance) and the checks of the two
//! converted gears as a pair: same m_n, α_n and β, opposite hands, centre
//! distance against the base circles and the profile shifts, tip-to-root
//! clearance, then [`crate::geometry::pair::check_pair`].

use std::ops::Range;

use serde::Deserialize;
use toml::Spanned;

use super::involute::{base_diameter, root_diameter, shift_sum_for_centre_distance, tip_diameter};
use super::location::{Cx, Res};
use crate::error::FlankError;
use crate::geometry::{GearSpec, Hand, PairSpec};

/// `[pair] kind` of a cylindrical pair as read (the scene's
/// [`super::validated::PairKind`] once read).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub(super) enum CylindricalKind {
    Spur,
    Helical,
}

impl From<CylindricalKind> for super::validated::PairKind {
    fn from(k: CylindricalKind) -> Self {
        match k {
            CylindricalKind::Spur => super::validated::PairKind::Spur,
            CylindricalKind::Helical => super::validated::PairKind::Helical,
        }
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawPair {
    pub(super) kind: Spanned<CylindricalKind>,
    centre_distance_mm: Spanned<f64>,
}

/// What a converted gear still needs for the pair checks.
pub(super) struct GearSpans {
    pub(super) module: Range<usize>,
    pub(super) alpha: Range<usize>,
    pub(super) helix: Range<usize>,
    pub(super) hand: Option<Range<usize>>,
    pub(super) tip: Range<usize>,
    pub(super) material: Spanned<String>,
}

/// The pair of the two converted gears at the `[pair]` centre distance,
/// checked (errors at the key of the gear or centre distance at fault).
pub(super) fn pair_spec(
    cx: &Cx,
    raw: &RawPair,
    kind: CylindricalKind,
    pinion: GearSpec,
    ps: &GearSpans,
    gear_spec: GearSpec,
    gs: &GearSpans,
) -> Res<PairSpec> {
    // the two gears must mesh: same normal module, pressure angle and helix angle
    let same = |a: f64, b: f64| (a - b).abs() <= 1e-9 * a.abs().max(b.abs()).max(1.0);
    if !same(pinion.normal_module, gear_spec.normal_module) {
        return Err(cx.err(
            gs.module.clone(),
            format!(
                "`gear.normal_module_mm` = {}: must equal `pinion.normal_module_mm` = {} (the gears must mesh)",
                gear_spec.normal_module, pinion.normal_module
            ),
        ));
    }
    if !same(
        pinion.normal_pressure_angle,
        gear_spec.normal_pressure_angle,
    ) {
        return Err(cx.err(
            gs.alpha.clone(),
            format!(
                "`gear.normal_pressure_angle_deg` = {}: must equal `pinion.normal_pressure_angle_deg` = {}",
                gear_spec.normal_pressure_angle.to_degrees(),
                pinion.normal_pressure_angle.to_degrees()
            ),
        ));
    }
    if !same(pinion.helix_angle, gear_spec.helix_angle) {
        return Err(cx.err(
            gs.helix.clone(),
            format!(
                "`gear.helix_angle_deg` = {}: must equal `pinion.helix_angle_deg` = {} (parallel axes)",
                gear_spec.helix_angle.to_degrees(),
                pinion.helix_angle.to_degrees()
            ),
        ));
    }
    if kind == CylindricalKind::Helical && pinion.hand == gear_spec.hand {
        return Err(cx.err(
            gs.hand.clone().unwrap_or(gs.helix.clone()),
            format!(
                "`gear.hand` = \"{}\": an external helical pair needs opposite hands (pinion is \"{}\")",
                hand_name(gear_spec.hand),
                hand_name(pinion.hand)
            ),
        ));
    }
    // centre distance against the involutes
    let a_span = raw.centre_distance_mm.span();
    let a = cx.positive(&raw.centre_distance_mm, "pair.centre_distance_mm")?;
    let rb1 = base_diameter(&pinion) / 2.0;
    let rb2 = base_diameter(&gear_spec) / 2.0;
    if !(a > rb1 + rb2) {
        return Err(cx.err(
            a_span,
            format!(
                "`pair.centre_distance_mm` = {a}: must exceed the sum of the base radii {:.4} mm",
                rb1 + rb2
            ),
        ));
    }
    let x_sum_a = shift_sum_for_centre_distance(&pinion, &gear_spec, a);
    let x_sum = pinion.profile_shift + gear_spec.profile_shift;
    if x_sum > x_sum_a + 1e-4 {
        return Err(cx.err(
            a_span,
            format!(
                "`pair.centre_distance_mm` = {a}: too small for the profile shifts x1 + x2 = {x_sum:.4}; \
                 backlash-free meshing at this centre distance needs x1 + x2 = {x_sum_a:.4} (the teeth would interfere)"
            ),
        ));
    }
    for (g, s, name, other, other_name) in [
        (&pinion, ps, "pinion", &gear_spec, "gear"),
        (&gear_spec, gs, "gear", &pinion, "pinion"),
    ] {
        let clearance = a - tip_diameter(g) / 2.0 - root_diameter(other) / 2.0;
        if clearance < 0.0 {
            return Err(cx.err(
                s.tip.clone(),
                format!(
                    "{name} tip diameter {:.4} mm reaches {:.4} mm into the {other_name}'s root circle \
                     at centre distance {a} mm (reduce `{name}.tip_diameter_mm`)",
                    tip_diameter(g),
                    -clearance
                ),
            ));
        }
    }

    let pair = PairSpec {
        pinion,
        gear: gear_spec,
        centre_distance: a,
    };
    // the geometry module's pair check: zero backlash (Σx within 1e-6 of what
    // a needs), clearances, interference, ε_α ≥ 1
    crate::geometry::pair::check_pair(&pair).map_err(|e| {
        let m = match e {
            FlankError::Model(m) => m,
            other => other.to_string(),
        };
        cx.err(
            a_span.clone(),
            format!("`pair.centre_distance_mm` = {a}: {m}"),
        )
    })?;

    Ok(pair)
}

fn hand_name(h: Hand) -> &'static str {
    match h {
        Hand::Left => "left",
        Hand::Right => "right",
    }
}

#[cfg(test)]
mod tests {
    use crate::scene::test_support::*;

    #[test]
    fn helical_with_same_hands() {
        let t = edit(HELICAL, "hand = \"left\"", "hand = \"right\"");
        expect_err(
            &t,
            line_of(
                &t,
                "hand = \"right\"\nface_width_mm = 180.0\nbore_diameter_mm = 400",
            ),
            &["gear.hand", "opposite"],
        );
    }

    #[test]
    fn helical_angles_must_match_and_be_in_range() {
        let t = edit(
            HELICAL,
            "helix_angle_deg = 20.0\nhand = \"left\"",
            "helix_angle_deg = 21.0\nhand = \"left\"",
        );
        expect_err(
            &t,
            line_of(&t, "helix_angle_deg = 21.0"),
            &["gear.helix_angle_deg"],
        );
        let t = edit(
            HELICAL,
            "helix_angle_deg = 20.0\nhand = \"left\"",
            "helix_angle_deg = 45.0\nhand = \"left\"",
        );
        expect_err(
            &t,
            line_of(&t, "helix_angle_deg = 45.0"),
            &["gear.helix_angle_deg"],
        );
    }

    #[test]
    fn pair_geometry_checked() {
        // bore at the root
        let t = edit(SPUR, "bore_diameter_mm = 20.0", "bore_diameter_mm = 50.0");
        expect_err(
            &t,
            line_of(&t, "bore_diameter_mm = 50"),
            &["pinion.bore_diameter_mm"],
        );
        // centre distance too small for the shifts
        let t = edit(
            SPUR,
            "centre_distance_mm = 90.0",
            "centre_distance_mm = 89.0",
        );
        expect_err(
            &t,
            line_of(&t, "centre_distance_mm"),
            &["pair.centre_distance_mm", "interfere"],
        );
        // pressure angle out of range, and different modules
        let t = edit(
            SPUR,
            "normal_pressure_angle_deg = 20.0\nhelix",
            "normal_pressure_angle_deg = 45.0\nhelix",
        );
        expect_err(
            &t,
            line_of(&t, "= 45.0"),
            &["pinion.normal_pressure_angle_deg"],
        );
        let t = edit(
            SPUR,
            "normal_module_mm = 3.8\nnormal_pressure_angle_deg = 20.0\nface",
            "normal_module_mm = 4.0\nnormal_pressure_angle_deg = 20.0\nface",
        );
        expect_err(&t, line_of(&t, "= 4.0"), &["gear.normal_module_mm"]);
        // negative speed, face width
        let t = edit(SPUR, "speed_rpm = 11758.0", "speed_rpm = -1.0");
        expect_err(&t, line_of(&t, "speed_rpm"), &["load.speed_rpm"]);
        let t = edit(
            SPUR,
            "face_width_mm = 13.3\nprofile_shift = 0.3",
            "face_width_mm = 0\nprofile_shift = 0.3",
        );
        expect_err(
            &t,
            line_of(&t, "face_width_mm = 0"),
            &["pinion.face_width_mm"],
        );
        // backlash: the centre distance does not match the shifts
        let t = edit(
            SPUR,
            "centre_distance_mm = 90.0",
            "centre_distance_mm = 90.1",
        );
        expect_err(
            &t,
            line_of(&t, "centre_distance_mm"),
            &["pair.centre_distance_mm", "profile shifts"],
        );
        // pointed pinion tooth
        let t = edit(SPUR, "tip_diameter_mm = 58.7", "tip_diameter_mm = 62.0");
        assert!(parse(&t).is_err());
    }
}
