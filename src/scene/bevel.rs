//! Scenes of spiral bevel and hypoid pairs (`[pair] kind = "spiral_bevel"`
//! or `"hypoid"`): the pair's blank is an ISO 23509 input set, in a `[blank]`
//! table with the key names `flank blank` reads (those of the standard's
//! Annex F samples in `../shared/reference/iso23509_annexF.json`), and the
//! blank design ([`crate::geometry::bevel::blank_design`]) is run when the
//! scene is read, so a scene whose blank does not work is refused at load.
//!
//! ```toml
//! [pair]
//! kind = "hypoid"                   # or "spiral_bevel" (blank method 0, a = 0)
//! pinion_hand = "left"              # hand of the pinion's spiral; the gear's is opposite
//!
//! [blank]                           # ISO 23509 inputs (see `flank blank`)
//! method = 3
//! Sigma_deg = 90.0
//! a_mm = 30.0
//! # …
//!
//! [pinion]
//! bore_diameter_mm = 30.0
//! shank_length_mm = 40.0            # optional: the stem with its bearing seats
//! shank_diameter_mm = 26.0          # (either key models it; `pinion_shank`)
//! material = "steel"
//! process = "generated"             # or "formate", "conjugate" (+ [pinion.ease_off]),
//!                                   # "synthesised" (+ [pinion.synthesis])
//!
//! [gear]
//! bore_diameter_mm = 120.0
//! material = "steel"
//! process = "generated"             # or "formate"; [gear.cutter], [gear.machine] optional
//!
//! [materials.steel]                 # as for cylindrical pairs
//! [load]                            # torque_nm on the pinion, speed_rpm of the pinion
//! [analyses]                        # optional
//! [mesh]                            # optional; element = "hex20" or "wedge15" as for cylindrical pairs
//! ```
//!
//! The cutting keys (process, cutter, explicit machine settings, ease-off)
//! are described in `scene/bevel_cutting.rs`; both members are cut when the
//! scene is read ([`crate::geometry::bevel::cutting`]).
//!
//! Errors are [`FlankError::Parse`] at the line of the key at fault; an
//! error of the blank design names its `[blank]` key and points at it (or at
//! the `[blank]` header when the key is absent).

use std::collections::BTreeMap;
use std::sync::Arc;

use serde::Deserialize;
use toml::Spanned;

use super::analyses::{self, RawAnalyses};
use super::bevel_cutting::{
    self, CutterTilt, Process, RawCutter, RawEaseOff, RawMachine, RawMemberCutting, RawSynthesis,
};
use super::load::{self, RawLoad};
use super::location::{Cx, Res};
use super::materials::{self, RawMaterial};
use super::mesh::{self, RawMesh};
use super::validated::{BevelGears, BevelKeyLines, Gears, PairKind, Scene};
use crate::error::FlankError;
use crate::geometry::bevel::cutting::{self};
use crate::geometry::bevel::pair::BevelPair;
use crate::geometry::bevel::{blank_design, BlankInputs};
use crate::geometry::Hand;

/// `[pair] kind` of a bevel pair as read (the scene's [`PairKind`] once
/// read).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub(super) enum BevelKind {
    /// Intersecting axes (ISO 23509 method 0).
    SpiralBevel,
    /// Offset axes (methods 1–3).
    Hypoid,
}

impl From<BevelKind> for PairKind {
    fn from(k: BevelKind) -> Self {
        match k {
            BevelKind::SpiralBevel => PairKind::SpiralBevel,
            BevelKind::Hypoid => PairKind::Hypoid,
        }
    }
}

/// Longest shank, in face widths: a longer stem is a shaft (a beam), not
/// part of the gear blank.
const MAX_SHANK_FACE_WIDTHS: f64 = 10.0;

/// The pinion's shank from `[pinion]`: modelled when either key is given
/// (it changes the pinion's compliance, so it is not on by default). A
/// missing key takes flank's proportion (no standard gives one; the seeds
/// give none):
/// * diameter d_s = d_f,e − 2 h_m: the root-cone diameter at the heel less
///   one mean whole depth on each side, a shoulder one whole depth high
///   (the proportion the ring gear's rim below the teeth gets,
///   `mesh::bevel_sector`); seed 000: 78.12 − 2 × 8.53 = 61.06 mm,
///   seed 003: 54.72 mm;
/// * length L = b₁, one face width of bearing seat beyond the heel face.
///
/// Range: bore < d_s < d_f,e (the mesher also needs d_s below the rim's top
/// at the heel and reports that bound), 0 < L ≤ 10 b₁.
fn pinion_shank(
    cx: &Cx,
    raw: &RawBevelGear,
    bore: f64,
    cut: &crate::geometry::bevel::MemberBlank,
    face_width: f64,
    whole_depth: f64,
) -> Res<Option<crate::mesh::bevel_sector::Shank>> {
    if raw.shank_length_mm.is_none() && raw.shank_diameter_mm.is_none() {
        return Ok(None);
    }
    let root_heel = 2.0 * cut.axial_point(-cut.dedendum(cut.re), cut.re).1;
    let diameter = match &raw.shank_diameter_mm {
        Some(v) => {
            let d = cx.positive(v, "pinion.shank_diameter_mm")?;
            if !(d > bore && d < root_heel) {
                return Err(cx.err(
                    v.span(),
                    format!(
                        "`pinion.shank_diameter_mm` = {d}: the shank must be wider than the bore ({bore} mm) and narrower than the root cone at the heel ({root_heel:.3} mm)"
                    ),
                ));
            }
            d
        }
        None => root_heel - 2.0 * whole_depth,
    };
    let length = match &raw.shank_length_mm {
        Some(v) => {
            let l = cx.positive(v, "pinion.shank_length_mm")?;
            let max = MAX_SHANK_FACE_WIDTHS * face_width;
            if l > max {
                return Err(cx.err(
                    v.span(),
                    format!(
                        "`pinion.shank_length_mm` = {l}: at most {MAX_SHANK_FACE_WIDTHS} face widths ({max:.3} mm); a longer stem is a shaft, not part of the blank"
                    ),
                ));
            }
            l
        }
        None => face_width,
    };
    if !(diameter > bore) {
        return Err(cx.err(
            raw.shank_length_mm
                .as_ref()
                .map_or(0..0, |v| v.span()),
            format!(
                "`pinion.shank_length_mm` given without `pinion.shank_diameter_mm`: the default diameter {diameter:.3} mm (root cone at the heel less a whole depth each side) is not wider than the bore ({bore} mm); give the diameter"
            ),
        ));
    }
    Ok(Some(crate::mesh::bevel_sector::Shank { length, diameter }))
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawBevelPair {
    kind: Spanned<BevelKind>,
    pinion_hand: Spanned<Hand>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawBevelGear {
    bore_diameter_mm: Spanned<f64>,
    material: Spanned<String>,
    shank_length_mm: Option<Spanned<f64>>,
    shank_diameter_mm: Option<Spanned<f64>>,
    process: Option<Spanned<Process>>,
    cutter: Option<Spanned<RawCutter>>,
    machine: Option<Spanned<RawMachine>>,
    ease_off: Option<Spanned<RawEaseOff>>,
    synthesis: Option<Spanned<RawSynthesis>>,
    cutter_tilt: Option<Spanned<CutterTilt>>,
}

impl RawBevelGear {
    /// The cutting keys (taken out of the section).
    fn cutting(&mut self) -> RawMemberCutting {
        RawMemberCutting {
            process: self.process.take(),
            cutter: self.cutter.take(),
            machine: self.machine.take(),
            ease_off: self.ease_off.take(),
            synthesis: self.synthesis.take(),
            cutter_tilt: self.cutter_tilt.take(),
        }
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawBevelScene {
    pair: RawBevelPair,
    blank: Spanned<BTreeMap<String, Spanned<toml::Value>>>,
    pinion: Spanned<RawBevelGear>,
    gear: Spanned<RawBevelGear>,
    #[serde(default)]
    materials: BTreeMap<String, RawMaterial>,
    load: RawLoad,
    analyses: Option<RawAnalyses>,
    mesh: Option<RawMesh>,
    lubricant: Option<super::lubricant::RawLubricant>,
}

/// TOML value → JSON value (the blank inputs are read by their JSON reader).
fn json(v: &toml::Value) -> serde_json::Value {
    match v {
        toml::Value::String(s) => serde_json::Value::from(s.clone()),
        toml::Value::Integer(i) => serde_json::Value::from(*i),
        toml::Value::Float(f) => serde_json::Value::from(*f),
        toml::Value::Boolean(b) => serde_json::Value::from(*b),
        toml::Value::Datetime(d) => serde_json::Value::from(d.to_string()),
        toml::Value::Array(a) => serde_json::Value::Array(a.iter().map(json).collect()),
        toml::Value::Table(t) => {
            serde_json::Value::Object(t.iter().map(|(k, v)| (k.clone(), json(v))).collect())
        }
    }
}

/// A blank-design error at the line of the `[blank]` key it names.
fn blank_error(
    cx: &Cx,
    blank: &Spanned<BTreeMap<String, Spanned<toml::Value>>>,
    e: FlankError,
) -> FlankError {
    let message = e.to_string();
    // Messages name the key in backticks (`blank input `key`: …`) or, from
    // serde, as "unknown field `key`".
    let key = message
        .split('`')
        .nth(1)
        .filter(|k| blank.get_ref().contains_key(*k));
    let span = match key {
        Some(k) => blank.get_ref()[k].span(),
        None => blank.span(),
    };
    cx.err(span, format!("[blank]: {message}"))
}

pub(super) fn build(cx: &Cx, mut raw: RawBevelScene) -> Res<Scene> {
    let kind = *raw.pair.kind.get_ref();
    // JSON has no NaN or infinity (they would become null): refuse them here, at their key
    for (k, v) in raw.blank.get_ref() {
        if let toml::Value::Float(f) = v.get_ref() {
            if !f.is_finite() {
                return Err(cx.err(
                    v.span(),
                    format!("`blank.{k}` = {f}: must be a finite number"),
                ));
            }
        }
    }
    let object: serde_json::Map<String, serde_json::Value> = raw
        .blank
        .get_ref()
        .iter()
        .map(|(k, v)| (k.clone(), json(v.get_ref())))
        .collect();
    let inputs = BlankInputs::from_value(serde_json::Value::Object(object))
        .map_err(|e| blank_error(cx, &raw.blank, e))?;
    let method_ok = match kind {
        BevelKind::SpiralBevel => inputs.method == 0,
        BevelKind::Hypoid => inputs.method > 0,
    };
    if !method_ok {
        return Err(cx.err(
            raw.pair.kind.span(),
            format!(
                "`pair.kind` = {kind:?} does not fit `blank.method` = {} (spiral_bevel: method 0, zero offset; hypoid: methods 1–3)",
                inputs.method
            ),
        ));
    }
    let blank = blank_design(&inputs).map_err(|e| blank_error(cx, &raw.blank, e))?;

    let mut bore_diameter = [0.0; 2];
    for (k, (g, name)) in [
        (raw.pinion.get_ref(), "pinion"),
        (raw.gear.get_ref(), "gear"),
    ]
    .into_iter()
    .enumerate()
    {
        let key = format!("{name}.bore_diameter_mm");
        let d = cx.positive(&g.bore_diameter_mm, &key)?;
        // The bore must stay inside the root cone at the toe (inner end).
        let cut = blank.cutting_blank();
        let m = if k == 0 { &cut.pinion } else { &cut.wheel };
        let inner_root_diameter = 2.0 * m.axial_point(-m.dedendum(m.ri), m.ri).1;
        if !(d < inner_root_diameter) {
            return Err(cx.err(
                g.bore_diameter_mm.span(),
                format!(
                    "`{key}` = {d}: the bore must be smaller than the root cone's diameter at the toe, {inner_root_diameter:.3} mm"
                ),
            ));
        }
        bore_diameter[k] = d;
    }
    let pinion_material =
        materials::material(cx, &raw.materials, &raw.pinion.get_ref().material, "pinion")?;
    let gear_material =
        materials::material(cx, &raw.materials, &raw.gear.get_ref().material, "gear")?;
    let load = load::load(cx, &raw.load)?;
    let analyses = analyses::analyses(cx, raw.analyses.as_ref())?;
    if let (Some(l), Some(span)) = (&analyses.ltca, analyses.ltca_span.clone()) {
        if let Some(key) = spur_only_ltca_key(l) {
            return Err(cx.err(span, format!("`analyses.ltca.{key}`: {}", SPUR_ONLY_LTCA)));
        }
    }
    let lubricant =
        super::lubricant::scene_lubricant(cx, raw.lubricant.as_ref(), &analyses, &load)?;
    let mesh = mesh::mesh_options(cx, raw.mesh.as_ref(), inputs.z1, blank.cones.m_mn)?;
    let [teeth_in_sector, flank_size, base_size] = mesh::key_lines(cx, raw.mesh.as_ref());
    let lines = BevelKeyLines {
        pinion: cx.line(raw.pinion.span().start),
        torque: load::torque_line(cx, &raw.load),
        teeth_in_sector,
        flank_size,
        base_size,
        lubrication: analyses.lubrication_span.clone().map(|s| cx.line(s.start)),
    };

    // how each member is cut, and the members
    let pinion_hand = *raw.pair.pinion_hand.get_ref();
    let gear_hand = pinion_hand.opposite();
    let (raw_pinion, raw_gear) = (
        &raw.pinion.get_mut().cutting(),
        &raw.gear.get_mut().cutting(),
    );
    let gear_cut = bevel_cutting::gear_cut(cx, raw_gear, &blank)?;
    let pinion_cut = bevel_cutting::pinion_cut(cx, raw_pinion, &blank)?;
    let gear_error = |e| bevel_cutting::cutting_error(cx, "gear", raw_gear, raw.gear.span(), e);
    let pinion_error =
        |e| bevel_cutting::cutting_error(cx, "pinion", raw_pinion, raw.pinion.span(), e);
    let gear_flanks = cutting::cut_gear(&blank, gear_hand, &gear_cut).map_err(gear_error)?;
    let pinion_flanks = cutting::cut_pinion(
        &inputs,
        &blank,
        pinion_hand,
        &pinion_cut,
        &gear_cut,
        &gear_flanks,
    )
    .map_err(pinion_error)?;
    let n = mesh.teeth_in_sector as usize;
    let pinion_body = cutting::member_body(&blank, true, &pinion_flanks, 0.5 * bore_diameter[0], n)
        .map_err(pinion_error)?;
    let gear_body = cutting::member_body(&blank, false, &gear_flanks, 0.5 * bore_diameter[1], n)
        .map_err(gear_error)?;
    let bodies = [Arc::new(pinion_body), Arc::new(gear_body)];
    mesh::check_bevel_sizes(cx, raw.mesh.as_ref(), &bodies)?;
    let g = raw.gear.get_ref();
    if let Some(v) = g.shank_length_mm.as_ref().or(g.shank_diameter_mm.as_ref()) {
        return Err(cx.err(
            v.span(),
            "[gear]: a shank is the pinion's (`[pinion] shank_length_mm`, `shank_diameter_mm`); the ring gear is held by its mounting plane".into(),
        ));
    }
    let pinion_shank = {
        let c = bodies[0].cones();
        pinion_shank(
            cx,
            raw.pinion.get_ref(),
            bore_diameter[0],
            &blank.cutting_blank().pinion,
            c.b,
            c.ham + c.hfm,
        )?
    };
    let pair = cutting::assembly_for(&inputs, &blank, gear_hand)
        .and_then(|assembly| BevelPair::new(bodies.clone(), assembly))
        .map_err(|e| cx.err(raw.pair.pinion_hand.span(), format!("`[pair]`: {e}")))?;
    let gears = BevelGears {
        pinion_hand,
        blank_inputs: inputs,
        blank,
        bore_diameter,
        gear_cut,
        pinion_cut,
        bodies,
        pair: Arc::new(pair),
        pinion_eased: pinion_flanks.eased.clone(),
        cutting_report: [pinion_flanks.report, gear_flanks.report],
        lines,
        pinion_shank,
    };
    Ok(Scene {
        kind: kind.into(),
        gears: Gears::Bevel(Box::new(gears)),
        pinion_material,
        gear_material,
        load,
        analyses,
        mesh,
        lubricant,
        source: cx.file.to_path_buf(),
        kind_line: cx.line(raw.pair.kind.span().start),
    })
}

/// Why a spur/helical `[analyses.ltca]` key is refused on a hypoid scene.
const SPUR_ONLY_LTCA: &str = "a key of the spur/helical LTCA; a hypoid LTCA takes `roll_angles_deg` or `positions` (default one mesh cycle of 20 positions), `points_per_line` (K on each major axis), `solver`, `local`, `fe_cell_factor`, `local_iterations`, `friction_mu`, `increments`, `friction_model` and `edges` from the scene, its compliance mesh from `--flank-size`/`--base-size` and the candidate span from `--span-approach-mm`; it has no misalignment (the hypoid TCA takes it, `flank tca --offset-error-mm` …)";

/// The first key of `l` that only the spur/helical LTCA reads, if any.
fn spur_only_ltca_key(l: &analyses::LtcaAnalysis) -> Option<&'static str> {
    [
        ("roll_start_deg", l.roll_start_deg.is_some()),
        ("roll_end_deg", l.roll_end_deg.is_some()),
        ("roll_step_deg", l.roll_step_deg.is_some()),
        ("misalignment_urad", l.misalignment_urad.is_some()),
        (
            "centre_distance_error_um",
            l.centre_distance_error_um.is_some(),
        ),
        ("extension_mm", l.extension_mm.is_some()),
        ("flank_size_mm", l.flank_size_mm.is_some()),
        ("base_size_mm", l.base_size_mm.is_some()),
        ("flank_region", l.flank_region.is_some()),
        ("compression", l.compression.is_some()),
    ]
    .into_iter()
    .find(|(_, given)| *given)
    .map(|(key, _)| key)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::test_support::{expect_err, line_of};
    use crate::scene::{parse_scene, BevelGears};
    use std::path::Path;

    const SCENE: &str = r#"[pair]
kind = "hypoid"
pinion_hand = "left"

[blank]
method = 3
Sigma_deg = 90.0
a_mm = 30.0
z1 = 12
z2 = 41
de2_mm = 213.2
b2_mm = 32.0
beta_m2_deg = 32.0
rc0_mm = 100.0
z0 = 5
data_type = "I"
alpha_dD_deg = 20.0
alpha_dC_deg = 20.0
f_alim = 0.0
k_hap = 1.0
k_hfp = 1.25
x_hm1 = 0.53
x_smn = 0.0

[pinion]
bore_diameter_mm = 20.0
material = "steel"

[gear]
bore_diameter_mm = 130.0
material = "steel"

[materials.steel]
young_modulus_mpa = 206000.0
poisson_ratio = 0.3

[load]
torque_nm = 117.07
speed_rpm = 1000.0
"#;

    fn parse(text: &str) -> Result<Scene, FlankError> {
        parse_scene(text, Path::new("s.toml"))
    }

    fn bevel(text: &str) -> BevelGears {
        *match parse(text).unwrap().gears {
            Gears::Bevel(b) => b,
            Gears::Cylindrical(_) => panic!("not a bevel scene"),
        }
    }

    #[test]
    fn a_hypoid_scene_reads_and_runs_its_blank_design() {
        let scene = parse(SCENE).unwrap();
        assert_eq!(scene.kind, PairKind::Hypoid);
        let s = scene.bevel("this test").unwrap();
        assert_eq!(s.pinion_hand, Hand::Left);
        assert_eq!(s.blank.method, 3);
        assert_eq!(s.blank_inputs.z2, 41);
        // The blank's wheel outer pitch diameter is the input d_e2.
        let c = &s.blank.cones;
        assert!((2.0 * c.re2 * c.delta2.sin() - 213.2).abs() < 1e-9);
        assert_eq!(s.bore_diameter, [20.0, 130.0]);
        // An analysis of spur/helical pairs only refuses it at its kind.
        let e = scene
            .cylindrical("the contact-band study")
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("s.toml:2:") && e.contains("spur and helical"),
            "{e}"
        );
    }

    #[test]
    fn bad_bevel_scenes_point_at_the_key() {
        let edit = |from: &str, to: &str| SCENE.replacen(from, to, 1);
        let t = edit("z1 = 12", "z1 = 0");
        expect_err(&t, line_of(&t, "z1 = 0"), &["z1", "positive"]);
        let t = edit("x_smn = 0.0\n", "");
        expect_err(&t, line_of(&t, "[blank]"), &["x_smn", "missing"]);
        let t = edit("z0 = 5", "z0 = 5\nfoo = 1");
        expect_err(&t, line_of(&t, "foo = 1"), &["foo"]);
        let t = edit("kind = \"hypoid\"", "kind = \"spiral_bevel\"");
        expect_err(&t, 2, &["pair.kind", "blank.method"]);
        let t = edit("bore_diameter_mm = 130.0", "bore_diameter_mm = 190.0");
        expect_err(
            &t,
            line_of(&t, "190.0"),
            &["gear.bore_diameter_mm", "root cone"],
        );
        let t = edit("pinion_hand = \"left\"", "pinion_hand = \"up\"");
        expect_err(&t, 3, &["pinion_hand"]);
        let t = edit("material = \"steel\"", "material = \"brass\"");
        expect_err(&t, line_of(&t, "\"brass\""), &["materials.brass"]);
        // nan/inf became JSON null ("invalid type: null" at [blank]): now at the key
        for bad in ["nan", "inf", "-inf"] {
            let t = edit("a_mm = 30.0", &format!("a_mm = {bad}"));
            expect_err(&t, line_of(&t, "a_mm ="), &["blank.a_mm", "finite"]);
        }
    }

    /// `[pinion] shank_length_mm` / `shank_diameter_mm`: none given, no
    /// shank; one given, the other from the proportions of
    /// [`pinion_shank`] (d_s = d_f,e − 2 h_m, L = b₁); out of range at the
    /// key's line; on the gear refused. The key lines the FE checks point
    /// at are the scene's.
    #[test]
    fn pinion_shank_keys_default_and_range() {
        let s = bevel(SCENE);
        assert_eq!(s.pinion_shank, None);
        assert_eq!(s.lines.pinion, line_of(SCENE, "[pinion]"));
        assert_eq!(s.lines.torque, line_of(SCENE, "torque_nm"));
        let edit = |from: &str, to: &str| SCENE.replacen(from, to, 1);
        let pin = "bore_diameter_mm = 20.0";
        let t = edit(pin, "bore_diameter_mm = 20.0\nshank_length_mm = 50.0");
        let sh = bevel(&t).pinion_shank.unwrap();
        let c = s.bodies[0].cones();
        let m = s.blank.cutting_blank().pinion;
        let root_heel = 2.0 * m.axial_point(-m.dedendum(m.re), m.re).1;
        println!(
            "seed 000 pinion: d_f,e = {root_heel:.3} mm, h_m = {:.3} mm, b = {:.3} mm: default shank diameter {:.3} mm",
            c.ham + c.hfm,
            c.b,
            sh.diameter
        );
        assert_eq!(sh.length, 50.0);
        assert!((sh.diameter - (root_heel - 2.0 * (c.ham + c.hfm))).abs() < 1e-12);
        let t = edit(pin, "bore_diameter_mm = 20.0\nshank_diameter_mm = 30.0");
        let sh = bevel(&t).pinion_shank.unwrap();
        assert_eq!((sh.length, sh.diameter), (c.b, 30.0));
        for (bad, words) in [
            (
                "shank_diameter_mm = 15.0",
                &["pinion.shank_diameter_mm", "bore"][..],
            ),
            (
                "shank_diameter_mm = 500.0",
                &["pinion.shank_diameter_mm", "root cone at the heel"],
            ),
            (
                "shank_length_mm = -1.0",
                &["pinion.shank_length_mm", "positive"],
            ),
            (
                "shank_length_mm = 1e4",
                &["pinion.shank_length_mm", "face widths"],
            ),
        ] {
            let t = edit(pin, &format!("bore_diameter_mm = 20.0\n{bad}"));
            expect_err(&t, line_of(&t, bad), words);
        }
        let t = edit(
            "bore_diameter_mm = 130.0",
            "bore_diameter_mm = 130.0\nshank_length_mm = 50.0",
        );
        expect_err(&t, line_of(&t, "shank_length_mm"), &["[gear]", "pinion's"]);
    }
}
