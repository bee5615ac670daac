//! The `[pinion]` and `[gear]` sections (one gear each: teeth, module,
//! angles, face width, shift, rack, tip and bore) and their micro-geometry
//! `[<gear>.micro]`.

use std::f64::consts::PI;
use std::path::Path;

use serde::Deserialize;
use toml::Spanned;

use super::involute::{base_diameter, root_diameter, tip_diameter, tip_thickness};
use super::location::{Cx, Res};
use super::pair::{CylindricalKind, GearSpans};
use super::validated::RackTipRadiusSource;
use crate::error::FlankError;
use crate::geometry::involute::{
    default_rack_tip_radius, rack_tip_radius_limit, undercut_limit, GearGeometry, ISO53_TIP_RADIUS,
};
use crate::geometry::micro::{MicroGeometry, Relief, ReliefShape};
use crate::geometry::{GearSpec, Hand, RackProfile};

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawGear {
    teeth: Spanned<i64>,
    normal_module_mm: Spanned<f64>,
    normal_pressure_angle_deg: Spanned<f64>,
    helix_angle_deg: Option<Spanned<f64>>,
    hand: Option<Spanned<Hand>>,
    face_width_mm: Spanned<f64>,
    profile_shift: Option<Spanned<f64>>,
    rack: Option<RawRack>,
    tip_diameter_mm: Option<Spanned<f64>>,
    bore_diameter_mm: Spanned<f64>,
    material: Spanned<String>,
    pub(super) micro: Option<RawMicro>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawRack {
    addendum: Option<Spanned<f64>>,
    dedendum: Option<Spanned<f64>>,
    tip_radius: Option<Spanned<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawMicro {
    tip_relief_um: Option<Spanned<f64>>,
    tip_relief_length_mm: Option<Spanned<f64>>,
    tip_relief_shape: Option<Spanned<ReliefShape>>,
    root_relief_um: Option<Spanned<f64>>,
    root_relief_length_mm: Option<Spanned<f64>>,
    root_relief_shape: Option<Spanned<ReliefShape>>,
    profile_crowning_um: Option<Spanned<f64>>,
    lead_crowning_um: Option<Spanned<f64>>,
    helix_slope_deviation_um: Option<Spanned<f64>>,
    end_relief_um: Option<Spanned<f64>>,
    end_relief_length_mm: Option<Spanned<f64>>,
    end_relief_shape: Option<Spanned<ReliefShape>>,
    measured_profile_csv: Option<Spanned<String>>,
}

impl RawMicro {
    /// The span of the table's first key (where an error about the
    /// modification as a whole is reported).
    pub(super) fn first_span(&self) -> std::ops::Range<usize> {
        let spans = [
            self.tip_relief_um.as_ref().map(Spanned::span),
            self.tip_relief_length_mm.as_ref().map(Spanned::span),
            self.tip_relief_shape.as_ref().map(Spanned::span),
            self.root_relief_um.as_ref().map(Spanned::span),
            self.root_relief_length_mm.as_ref().map(Spanned::span),
            self.root_relief_shape.as_ref().map(Spanned::span),
            self.profile_crowning_um.as_ref().map(Spanned::span),
            self.lead_crowning_um.as_ref().map(Spanned::span),
            self.helix_slope_deviation_um.as_ref().map(Spanned::span),
            self.end_relief_um.as_ref().map(Spanned::span),
            self.end_relief_length_mm.as_ref().map(Spanned::span),
            self.end_relief_shape.as_ref().map(Spanned::span),
            self.measured_profile_csv.as_ref().map(Spanned::span),
        ];
        spans
            .into_iter()
            .flatten()
            .min_by_key(|s| s.start)
            .unwrap_or(0..0)
    }
}

pub(super) fn gear(
    cx: &Cx,
    g: &RawGear,
    name: &str,
    kind: CylindricalKind,
) -> Res<(GearSpec, GearSpans, RackTipRadiusSource)> {
    let key = |k: &str| format!("{name}.{k}");

    let z = *g.teeth.get_ref();
    if !(5..=1000).contains(&z) {
        return Err(cx.err(
            g.teeth.span(),
            format!("`{}` = {z}: must lie in 5..=1000", key("teeth")),
        ));
    }
    let teeth = z as u32;

    let m = cx.positive(&g.normal_module_mm, &key("normal_module_mm"))?;

    let alpha_deg = cx.finite(
        &g.normal_pressure_angle_deg,
        &key("normal_pressure_angle_deg"),
    )?;
    if !(alpha_deg > 0.0 && alpha_deg < 45.0) {
        return Err(cx.err(
            g.normal_pressure_angle_deg.span(),
            format!(
                "`{}` = {alpha_deg}: must lie in (0, 45) degrees",
                key("normal_pressure_angle_deg")
            ),
        ));
    }

    let (beta_deg, helix_span) = match (&g.helix_angle_deg, kind) {
        (None, CylindricalKind::Spur) => (0.0, g.teeth.span()),
        (Some(b), CylindricalKind::Spur) => {
            let beta = cx.finite(b, &key("helix_angle_deg"))?;
            if beta != 0.0 {
                return Err(cx.err(
                    b.span(),
                    format!(
                        "`{}` = {beta}: a spur pair has no helix angle (0 or absent); use kind = \"helical\"",
                        key("helix_angle_deg")
                    ),
                ));
            }
            (0.0, b.span())
        }
        (None, CylindricalKind::Helical) => {
            return Err(cx.err(
                g.teeth.span(),
                format!("[{name}]: missing field `helix_angle_deg` (required for a helical pair)"),
            ))
        }
        (Some(b), CylindricalKind::Helical) => {
            let beta = cx.finite(b, &key("helix_angle_deg"))?;
            if !(beta > 0.0 && beta < 45.0) {
                return Err(cx.err(
                    b.span(),
                    format!(
                        "`{}` = {beta}: a helical gear needs 0 < β < 45 degrees (the direction is given by `hand`)",
                        key("helix_angle_deg")
                    ),
                ));
            }
            (beta, b.span())
        }
    };

    let hand = match (&g.hand, kind) {
        (None, CylindricalKind::Spur) => Hand::Right,
        (Some(h), CylindricalKind::Spur) => {
            return Err(cx.err(
                h.span(),
                format!("`{}`: a spur gear has no hand (helical only)", key("hand")),
            ))
        }
        (None, CylindricalKind::Helical) => {
            return Err(cx.err(
                g.teeth.span(),
                format!("[{name}]: missing field `hand` (\"left\" or \"right\", required for a helical pair)"),
            ))
        }
        (Some(h), CylindricalKind::Helical) => *h.get_ref(),
    };

    let b = cx.positive(&g.face_width_mm, &key("face_width_mm"))?;

    let x = match &g.profile_shift {
        Some(v) => {
            let x = cx.finite(v, &key("profile_shift"))?;
            if !(x.abs() <= 2.0) {
                return Err(cx.err(
                    v.span(),
                    format!("`{}` = {x}: must lie in [-2, 2]", key("profile_shift")),
                ));
            }
            x
        }
        None => 0.0,
    };

    // the generating rack: ISO 53's depths, and a tip radius that follows α_n
    // where the scene gives none (`geometry::involute::default_rack_tip_radius`)
    let alpha = alpha_deg.to_radians();
    let raw_rack = g.rack.as_ref();
    let mut rack = RackProfile::default();
    let addendum_span = raw_rack.and_then(|r| r.addendum.as_ref()).map(|v| v.span());
    if let Some(v) = raw_rack.and_then(|r| r.addendum.as_ref()) {
        rack.addendum = cx.positive(v, &key("rack.addendum"))?;
    }
    if let Some(v) = raw_rack.and_then(|r| r.dedendum.as_ref()) {
        rack.dedendum = cx.positive(v, &key("rack.dedendum"))?;
    }
    // the generating rack's tooth tip must be wide enough for both fillets
    let rho_max = rack_tip_radius_limit(rack.addendum, alpha);
    if !(PI / 4.0 - rack.addendum * alpha.tan() > 0.0) {
        let (span, given) = match addendum_span {
            Some(s) => (s, String::new()),
            None => (
                g.normal_pressure_angle_deg.span(),
                format!(
                    " (the default ISO 53 depth at α_n = {alpha_deg}°; a rack of addendum below {:.4} is needed: set `{}`)",
                    PI / 4.0 / alpha.tan(),
                    key("rack")
                ),
            ),
        };
        return Err(cx.err(
            span,
            format!(
                "`{}` = {}: the generating rack's tooth is pointed (addendum × tan α_n ≥ π/4){given}",
                key("rack.addendum"),
                rack.addendum
            ),
        ));
    }
    let tip_radius_source = match raw_rack.and_then(|r| r.tip_radius.as_ref()) {
        Some(v) => {
            rack.tip_radius = cx.non_negative(v, &key("rack.tip_radius"))?;
            if rack.tip_radius > rho_max {
                return Err(cx.err(
                    v.span(),
                    format!(
                        "`{}` = {}: larger than the {:.4} the rack tooth tip allows at addendum {} and α_n = {alpha_deg}°",
                        key("rack.tip_radius"),
                        rack.tip_radius,
                        rho_max,
                        rack.addendum
                    ),
                ));
            }
            RackTipRadiusSource::Scene
        }
        None => {
            rack.tip_radius = default_rack_tip_radius(rack.addendum, alpha);
            if rack.tip_radius == ISO53_TIP_RADIUS {
                RackTipRadiusSource::DefaultIso53
            } else {
                RackTipRadiusSource::DefaultNearFullRadius
            }
        }
    };

    let mut spec = GearSpec {
        teeth,
        normal_module: m,
        normal_pressure_angle: alpha_deg.to_radians(),
        helix_angle: beta_deg.to_radians(),
        hand,
        face_width: b,
        profile_shift: x,
        rack,
        tip_diameter: None,
        bore_diameter: 0.0,
    };

    let df = root_diameter(&spec);
    let db = base_diameter(&spec);
    let tip_span = match &g.tip_diameter_mm {
        Some(v) => {
            let da = cx.positive(v, &key("tip_diameter_mm"))?;
            if !(da > df) || !(da > db) {
                return Err(cx.err(
                    v.span(),
                    format!(
                        "`{}` = {da}: must exceed the root diameter {df:.4} mm and the base diameter {db:.4} mm",
                        key("tip_diameter_mm")
                    ),
                ));
            }
            spec.tip_diameter = Some(da);
            v.span()
        }
        None => g.teeth.span(),
    };
    let da = tip_diameter(&spec);
    if da > db {
        let s = tip_thickness(&spec, da);
        if !(s > 0.0) {
            let span = tip_span.clone();
            return Err(cx.err(
                span,
                format!(
                    "{name}: the tooth is pointed below the tip diameter {da:.4} mm \
                     (tooth thickness there {s:.4} mm); reduce `{}` or `{}`",
                    key("tip_diameter_mm"),
                    key("profile_shift")
                ),
            ));
        }
    } else {
        return Err(cx.err(
            tip_span,
            format!(
                "{name}: tip diameter {da:.4} mm does not exceed the base diameter {db:.4} mm (no involute flank)"
            ),
        ));
    }

    let bore = cx.positive(&g.bore_diameter_mm, &key("bore_diameter_mm"))?;
    if !(bore < df) || !(bore < da) {
        return Err(cx.err(
            g.bore_diameter_mm.span(),
            format!(
                "`{}` = {bore}: must be smaller than the root diameter {df:.4} mm (tip diameter {da:.4} mm)",
                key("bore_diameter_mm")
            ),
        ));
    }
    spec.bore_diameter = bore;

    // the gear's own checks (undercut by the rack, pointed tip, no involute
    // left), at the key that changes them rather than at the centre distance
    if let Err(e) = GearGeometry::new(&spec, name) {
        let m = match e {
            FlankError::Model(m) => m,
            other => other.to_string(),
        };
        let shift_span = g.profile_shift.as_ref().map(|v| v.span());
        let (span, k) = if spec.profile_shift < undercut_limit(&spec) {
            (shift_span.unwrap_or(g.teeth.span()), key("profile_shift"))
        } else if let Some(v) = &g.tip_diameter_mm {
            (v.span(), key("tip_diameter_mm"))
        } else {
            (shift_span.unwrap_or(g.teeth.span()), key("profile_shift"))
        };
        return Err(cx.err(span, format!("{m} (`{k}`)")));
    }

    Ok((
        spec,
        GearSpans {
            module: g.normal_module_mm.span(),
            alpha: g.normal_pressure_angle_deg.span(),
            helix: helix_span,
            hand: g.hand.as_ref().map(|h| h.span()),
            tip: tip_span,
            material: g.material.clone(),
        },
        tip_radius_source,
    ))
}

pub(super) fn micro_geometry(
    cx: &Cx,
    m: &RawMicro,
    name: &str,
    face_width: f64,
) -> Res<MicroGeometry> {
    let key = |k: &str| format!("{name}.micro.{k}");
    let um = |v: &Option<Spanned<f64>>, k: &str| -> Res<f64> {
        match v {
            Some(v) => Ok(cx.non_negative(v, &key(k))? * 1e-3),
            None => Ok(0.0),
        }
    };
    let relief = |amount: &Option<Spanned<f64>>,
                  length: &Option<Spanned<f64>>,
                  shape: &Option<Spanned<ReliefShape>>,
                  stem: &str|
     -> Res<Option<Relief>> {
        let a_key = format!("{stem}_um");
        let l_key = format!("{stem}_length_mm");
        let s_key = format!("{stem}_shape");
        match (amount, length) {
            (None, None) => {
                if let Some(s) = shape {
                    return Err(cx.err(
                        s.span(),
                        format!("`{}` given without `{}`", key(&s_key), key(&a_key)),
                    ));
                }
                Ok(None)
            }
            (Some(a), None) => Err(cx.err(
                a.span(),
                format!("`{}` needs `{}`", key(&a_key), key(&l_key)),
            )),
            (None, Some(l)) => Err(cx.err(
                l.span(),
                format!("`{}` needs `{}`", key(&l_key), key(&a_key)),
            )),
            (Some(a), Some(l)) => {
                let amount = cx.non_negative(a, &key(&a_key))? * 1e-3;
                let length = cx.positive(l, &key(&l_key))?;
                Ok(Some(Relief {
                    amount,
                    length,
                    shape: shape.as_ref().map_or(ReliefShape::Linear, |s| *s.get_ref()),
                }))
            }
        }
    };

    let tip_relief = relief(
        &m.tip_relief_um,
        &m.tip_relief_length_mm,
        &m.tip_relief_shape,
        "tip_relief",
    )?;
    let root_relief = relief(
        &m.root_relief_um,
        &m.root_relief_length_mm,
        &m.root_relief_shape,
        "root_relief",
    )?;
    let end_relief = relief(
        &m.end_relief_um,
        &m.end_relief_length_mm,
        &m.end_relief_shape,
        "end_relief",
    )?;
    if let (Some(r), Some(l)) = (&end_relief, &m.end_relief_length_mm) {
        if r.length > 0.5 * face_width {
            return Err(cx.err(
                l.span(),
                format!(
                    "`{}` = {}: end reliefs at both ends must fit the face width {face_width} mm (≤ b/2)",
                    key("end_relief_length_mm"),
                    r.length
                ),
            ));
        }
    }
    let helix_slope_deviation = match &m.helix_slope_deviation_um {
        Some(v) => cx.finite(v, &key("helix_slope_deviation_um"))? * 1e-3,
        None => 0.0,
    };
    let measured_profile = match &m.measured_profile_csv {
        Some(p) => {
            let rel = Path::new(p.get_ref());
            let base = cx.file.parent().unwrap_or(Path::new(""));
            let full = base.join(rel);
            if !full.is_file() {
                return Err(cx.err(
                    p.span(),
                    format!(
                        "`{}`: measured profile file not found: {}",
                        key("measured_profile_csv"),
                        full.display()
                    ),
                ));
            }
            Some(full)
        }
        None => None,
    };
    Ok(MicroGeometry {
        tip_relief,
        root_relief,
        profile_crowning: um(&m.profile_crowning_um, "profile_crowning_um")?,
        lead_crowning: um(&m.lead_crowning_um, "lead_crowning_um")?,
        helix_slope_deviation,
        end_relief,
        measured_profile,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::involute::FULL_ROOT_RADIUS_SHARE;
    use crate::scene::parse_scene;
    use crate::scene::test_support::*;

    /// A spur pair of ordinary proportions at α_n = `alpha_deg` with the
    /// racks left to their defaults: z 24/60, m_n 4, x ±0.4 (a = a_0 = 168 mm).
    fn spur_at(alpha_deg: f64, pinion_rack: &str) -> String {
        format!(
            r#"
[pair]
kind = "spur"
centre_distance_mm = 168.0

[pinion]
teeth = 24
normal_module_mm = 4.0
normal_pressure_angle_deg = {alpha_deg}
face_width_mm = 40.0
profile_shift = 0.4
{pinion_rack}
bore_diameter_mm = 30.0
material = "steel"

[gear]
teeth = 60
normal_module_mm = 4.0
normal_pressure_angle_deg = {alpha_deg}
face_width_mm = 40.0
profile_shift = -0.4
bore_diameter_mm = 80.0
material = "steel"

[materials.steel]
young_modulus_mpa = 206000.0
poisson_ratio = 0.3

[load]
torque_nm = 500.0
speed_rpm = 1500.0
"#
        )
    }

    /// Issue 56: the default rack tip radius follows α_n, so every ordinary
    /// pressure angle checks without a `rack`; above 23.04° the 20° value 0.38
    /// would not fit (and was refused), there the default is 0.99 × the limit.
    #[test]
    fn default_rack_checks_at_every_ordinary_pressure_angle() {
        for alpha_deg in [14.5, 17.5, 20.0, 22.5, 25.0, 28.0, 30.0] {
            let t = spur_at(alpha_deg, "");
            let scene = parse(&t).unwrap_or_else(|e| panic!("α_n = {alpha_deg}°: {e}"));
            let c = scene.cylindrical("this test").unwrap();
            let limit = rack_tip_radius_limit(1.25, f64::to_radians(alpha_deg));
            for (g, source) in [
                (&c.pair.pinion, c.rack_tip_radius_source[0]),
                (&c.pair.gear, c.rack_tip_radius_source[1]),
            ] {
                let rho = g.rack.tip_radius;
                assert!(
                    rho > 0.0 && rho < limit,
                    "α_n = {alpha_deg}°: ρ = {rho}, limit {limit}"
                );
                if ISO53_TIP_RADIUS < FULL_ROOT_RADIUS_SHARE * limit {
                    assert_eq!(rho, ISO53_TIP_RADIUS, "α_n = {alpha_deg}°");
                    assert_eq!(source, RackTipRadiusSource::DefaultIso53);
                } else {
                    assert!((rho - FULL_ROOT_RADIUS_SHARE * limit).abs() < 1e-15);
                    assert_eq!(source, RackTipRadiusSource::DefaultNearFullRadius);
                }
            }
            // the 20° value does not fit from 25° on: these angles were refused
            assert_eq!(
                ISO53_TIP_RADIUS > limit,
                alpha_deg >= 25.0,
                "α_n = {alpha_deg}°"
            );
            let report = crate::scene::check::check(&scene)
                .unwrap_or_else(|e| panic!("α_n = {alpha_deg}°: {e}"));
            let crate::scene::check::PairCheck::Cylindrical(r) = report else {
                panic!("a spur pair checks as cylindrical")
            };
            assert!(r.report.contact_ratio > 1.0);
            assert_eq!(r.racks.pinion.tip_radius, c.pair.pinion.rack.tip_radius);
        }
    }

    /// At 20° nothing moves: 0.38 by default and as given, the scene's value
    /// reported as the scene's.
    #[test]
    fn twenty_degree_rack_unchanged() {
        let given = parse(SPUR).unwrap();
        let defaulted = parse(&edit(
            SPUR,
            "rack = { addendum = 1.25, dedendum = 1.0, tip_radius = 0.38 }\n",
            "",
        ))
        .unwrap();
        let (g, d) = (
            given.cylindrical("this test").unwrap(),
            defaulted.cylindrical("this test").unwrap(),
        );
        assert_eq!(g.pair, d.pair);
        assert_eq!(d.pair.pinion.rack, RackProfile::default());
        assert_eq!(d.pair.pinion.rack.tip_radius, 0.38);
        assert_eq!(g.rack_tip_radius_source[0], RackTipRadiusSource::Scene);
        assert_eq!(
            d.rack_tip_radius_source[0],
            RackTipRadiusSource::DefaultIso53
        );
        assert_eq!(
            g.rack_tip_radius_source[1],
            RackTipRadiusSource::DefaultIso53
        );
    }

    /// An explicit tip radius that does not fit is refused at its own line
    /// (not at the centre distance), with the limit; one that fits is kept.
    #[test]
    fn explicit_rack_tip_radius_is_checked_at_its_key() {
        let t = spur_at(25.0, "rack = { tip_radius = 0.36 }");
        expect_err(
            &t,
            line_of(&t, "rack = "),
            &["`pinion.rack.tip_radius` = 0.36", "0.3179", "α_n = 25°"],
        );
        let t = spur_at(25.0, "rack = { tip_radius = 0.2 }");
        let s = parse(&t).unwrap();
        let c = s.cylindrical("this test").unwrap();
        assert_eq!(c.pair.pinion.rack.tip_radius, 0.2);
        assert_eq!(c.rack_tip_radius_source[0], RackTipRadiusSource::Scene);
        // a deeper rack's default follows its addendum
        let t = spur_at(25.0, "rack = { addendum = 1.3 }");
        let s = parse(&t).unwrap();
        let rho = s
            .cylindrical("this test")
            .unwrap()
            .pair
            .pinion
            .rack
            .tip_radius;
        let want = FULL_ROOT_RADIUS_SHARE * rack_tip_radius_limit(1.3, 25f64.to_radians());
        assert!((rho - want).abs() < 1e-15, "{rho} vs {want}");
    }

    /// The ISO depth leaves no rack tooth tip above 32.14°: refused at the
    /// pressure angle (no rack given) or at the rack (addendum given).
    #[test]
    fn pointed_rack_is_refused_at_its_cause() {
        let t = spur_at(35.0, "");
        expect_err(
            &t,
            line_of(&t, "normal_pressure_angle_deg"),
            &["pointed", "`pinion.rack`", "1.1217"],
        );
        let t = spur_at(20.0, "rack = { addendum = 2.2 }");
        expect_err(
            &t,
            line_of(&t, "rack = "),
            &["pointed", "`pinion.rack.addendum` = 2.2"],
        );
    }

    /// Undercut and pointed-tip refusals name the shift or the tip diameter at
    /// its line (they were reported at `pair.centre_distance_mm`).
    #[test]
    fn gear_checks_at_the_key_that_changes_them() {
        // x_min of 24 teeth at 14.5° is 0.212: x = 0.1 undercuts
        let t = edit(
            &spur_at(14.5, ""),
            "profile_shift = 0.4",
            "profile_shift = 0.1",
        );
        let t = edit(&t, "profile_shift = -0.4", "profile_shift = -0.1");
        expect_err(
            &t,
            line_of(&t, "profile_shift = 0.1"),
            &["undercut", "`pinion.profile_shift`"],
        );
        // no shift given: at the tooth count
        let t = edit(&spur_at(14.5, ""), "profile_shift = 0.4\n", "");
        let t = edit(&t, "profile_shift = -0.4\n", "");
        expect_err(
            &t,
            line_of(&t, "teeth = 24"),
            &["undercut", "`pinion.profile_shift`"],
        );
    }

    #[test]
    fn unknown_key_in_pinion() {
        let t = edit(SPUR, "teeth = 13\n", "teeth = 13\ntooth_count = 13\n");
        expect_err(&t, line_of(&t, "tooth_count"), &["tooth_count"]);
    }

    #[test]
    fn unknown_key_in_rack() {
        let t = edit(
            SPUR,
            "tip_radius = 0.38 }",
            "tip_radius = 0.38, root_radius = 0.2 }",
        );
        expect_err(&t, line_of(&t, "rack = "), &["root_radius"]);
    }

    #[test]
    fn unknown_key_in_micro() {
        let t = edit(
            SPUR,
            "lead_crowning_um = 5.0\n",
            "lead_crowning_um = 5.0\nbarrelling_um = 2\n",
        );
        expect_err(&t, line_of(&t, "barrelling_um"), &["barrelling_um"]);
    }

    /// A key given twice named only the line ("duplicate key"); now the key.
    #[test]
    fn duplicated_key_is_named() {
        let t = edit(SPUR, "teeth = 13\n", "teeth = 13\nteeth = 14\n");
        expect_err(
            &t,
            line_of(&t, "teeth = 14"),
            &["`pinion.teeth`: duplicate key"],
        );
    }

    #[test]
    fn too_few_teeth() {
        let t = edit(SPUR, "teeth = 13", "teeth = 3");
        expect_err(&t, line_of(&t, "teeth = 3"), &["pinion.teeth", "3"]);
        let t = edit(SPUR, "teeth = 13", "teeth = -13");
        expect_err(&t, line_of(&t, "teeth = -13"), &["pinion.teeth"]);
    }

    #[test]
    fn spur_with_helix_angle() {
        let t = edit(SPUR, "helix_angle_deg = 0.0", "helix_angle_deg = 15.0");
        expect_err(
            &t,
            line_of(&t, "helix_angle_deg"),
            &["pinion.helix_angle_deg", "spur"],
        );
        let t = edit(SPUR, "helix_angle_deg = 0.0", "hand = \"left\"");
        expect_err(&t, line_of(&t, "hand ="), &["pinion.hand", "spur"]);
    }

    #[test]
    fn negative_module() {
        let t = edit(
            SPUR,
            "normal_module_mm = 3.8\nnormal_pressure_angle_deg = 20.0\nhelix",
            "normal_module_mm = -3.8\nnormal_pressure_angle_deg = 20.0\nhelix",
        );
        expect_err(
            &t,
            line_of(&t, "-3.8"),
            &["pinion.normal_module_mm", "positive"],
        );
    }

    #[test]
    fn missing_measured_profile() {
        let t = edit(
            SPUR,
            "end_relief_length_mm = 2.0\n",
            "end_relief_length_mm = 2.0\nmeasured_profile_csv = \"cmm/pinion.csv\"\n",
        );
        expect_err(
            &t,
            line_of(&t, "measured_profile_csv"),
            &["measured_profile_csv", "/nonexistent/cmm/pinion.csv"],
        );
    }

    #[test]
    fn measured_profile_relative_to_scene() {
        let dir = std::env::temp_dir().join(format!("flank-scene-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("cmm")).unwrap();
        // a real profile of this pinion: the scene binds it when it is read
        let example = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("papers/seed002-spur/measured_profile_example.csv");
        std::fs::copy(example, dir.join("cmm/pinion.csv")).unwrap();
        let t = edit(
            SPUR,
            "end_relief_length_mm = 2.0\n",
            "end_relief_length_mm = 2.0\nmeasured_profile_csv = \"cmm/pinion.csv\"\n",
        );
        let s = parse_scene(&t, &dir.join("scene.toml")).unwrap();
        let m = s.cylindrical("this test").unwrap().micro[0]
            .as_ref()
            .unwrap();
        assert_eq!(
            m.measured_profile.as_deref(),
            Some(dir.join("cmm/pinion.csv").as_path())
        );
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// A relief longer than the active profile was reported only when the
    /// modification was bound (`flank mesh`), without file or line; now
    /// when the scene is read, at the `[pinion.micro]` table's first key.
    #[test]
    fn micro_that_does_not_fit_its_gear_is_located() {
        let t = edit(
            SPUR,
            "tip_relief_length_mm = 1.0",
            "tip_relief_length_mm = 50.0",
        );
        let first = t[t.find("[pinion.micro]").unwrap()..]
            .lines()
            .nth(1)
            .unwrap()
            .to_string();
        expect_err(
            &t,
            line_of(&t, &first),
            &["pinion.micro", "tip relief length 50 mm exceeds"],
        );
    }

    #[test]
    fn micro_values_checked() {
        let t = edit(SPUR, "tip_relief_um = 10.0", "tip_relief_um = -10.0");
        expect_err(
            &t,
            line_of(&t, "tip_relief_um"),
            &["pinion.micro.tip_relief_um"],
        );
        let t = edit(SPUR, "lead_crowning_um = 5.0", "lead_crowning_um = nan");
        expect_err(
            &t,
            line_of(&t, "lead_crowning_um"),
            &["pinion.micro.lead_crowning_um", "finite"],
        );
        let t = edit(SPUR, "tip_relief_length_mm = 1.0\n", "");
        expect_err(&t, line_of(&t, "tip_relief_um"), &["tip_relief_length_mm"]);
        let t = edit(
            SPUR,
            "end_relief_length_mm = 2.0",
            "end_relief_length_mm = 7.0",
        );
        expect_err(
            &t,
            line_of(&t, "end_relief_length_mm"),
            &["end_relief_length_mm"],
        );
        let t = edit(
            SPUR,
            "tip_relief_shape = \"parabolic\"",
            "tip_relief_shape = \"cubic\"",
        );
        expect_err(&t, line_of(&t, "tip_relief_shape"), &["cubic"]);
    }
}
