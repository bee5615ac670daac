//! Scene files (TOML): which gear pair to analyse, with which materials,
//! under which load, and which analyses to run.
//!
//! The scene file is the unit boundary of flank: its keys carry their unit in
//! the name where it is not an internal one (`torque_nm`, `speed_rpm`,
//! `normal_pressure_angle_deg`, `tip_relief_um`, …) and everything is
//! converted here to mm, N, N·mm, MPa and rad. Nothing downstream converts.
//!
//! ```toml
//! [pair]
//! kind = "spur"                       # or "helical"
//! centre_distance_mm = 90.0
//!
//! [pinion]
//! teeth = 13
//! normal_module_mm = 3.8
//! normal_pressure_angle_deg = 20.0
//! helix_angle_deg = 0.0               # helical: 0 < β < 45; spur: 0 or absent
//! # hand = "right"                    # helical only; pinion and gear opposite
//! face_width_mm = 13.3
//! profile_shift = 0.3                 # optional, default 0
//! rack = { addendum = 1.25, dedendum = 1.0, tip_radius = 0.38 }  # optional (ISO 53, ×m_n; tip_radius follows α_n)
//! tip_diameter_mm = 59.0              # optional; default d + 2 m_n (h_aP* + x)
//! bore_diameter_mm = 20.0
//! material = "steel"                  # a [materials.<name>] table
//!
//! [pinion.micro]                      # optional; parsed and validated only
//! tip_relief_um = 10.0
//! tip_relief_length_mm = 1.0
//! tip_relief_shape = "linear"         # or "parabolic"
//!
//! [gear]                              # the same keys as [pinion]
//! # …
//!
//! [materials.steel]
//! young_modulus_mpa = 206000.0
//! poisson_ratio = 0.3
//!
//! [load]
//! torque_nm = 312.0                   # on the pinion
//! speed_rpm = 11758.0                 # of the pinion
//!
//! [analyses]                          # optional: the analyses asked for
//! mesh = {}
//!
//! [mesh]                              # optional meshing options
//! teeth_in_sector = 3
//! element = "wedge15"                 # or "hex20"
//! flank_size_mm = 0.1
//! base_size_mm = 1.0
//! ```
//!
//! `[<gear>.micro]` keys (all optional): `tip_relief_um`/`_length_mm`/`_shape`,
//! `root_relief_um`/`_length_mm`/`_shape`, `end_relief_um`/`_length_mm`/`_shape`
//! (amount and length go together; shape `linear` by default),
//! `profile_crowning_um`, `lead_crowning_um` (≥ 0), `helix_slope_deviation_um`
//! (signed), `measured_profile_csv` (relative to the scene file; must exist).
//!
//! Every table rejects unknown keys; every error is a
//! [`FlankError::Parse`] with the file, the 1-based line and a message that
//! names the key. Beyond types and ranges (5 ≤ z ≤ 1000, m_n > 0,
//! 0 < α_n < 45°, spur β = 0 and no hand, helical 0 < β < 45° with opposite
//! hands, b > 0, |x| ≤ 2, E > 0, −1 < ν < 0.5, torque and speed ≥ 0) the
//! checks are geometric: both gears share m_n, α_n and β; the rack tooth tip
//! fits its fillets (a rack without `tip_radius` takes ISO 53's 0.38 where it
//! fits, otherwise 0.99 × the full root radius:
//! [`crate::geometry::involute::default_rack_tip_radius`]); the tip lies above
//! the base and root circles and below the pointed-tooth diameter; the gear is
//! not undercut and its tip not pointed ([`crate::geometry::involute::GearGeometry`],
//! reported at the shift or tip diameter); the bore is inside the root circle; the centre
//! distance exceeds r_b1 + r_b2 and is not too small for x1 + x2 (no
//! interference); no tip reaches into the mating root circle. Last, the pair
//! goes through [`crate::geometry::pair::check_pair`] (zero backlash: Σx within
//! 1e-6 of what the centre distance needs; clearances; interference with the
//! root fillet; ε_α ≥ 1), whose message is reported at the centre-distance line.

mod analyses;
mod bevel;
mod bevel_cutting;
pub mod check;
mod gear;
mod involute;
mod load;
mod location;
mod lubricant;
mod materials;
mod mesh;
pub mod overrides;
mod pair;
#[cfg(test)]
mod test_support;
mod validated;

use std::collections::BTreeMap;
use std::path::Path;

use serde::Deserialize;

use crate::error::FlankError;
use analyses::RawAnalyses;
use gear::RawGear;
use load::RawLoad;
use location::{Cx, Res};
use materials::RawMaterial;
use mesh::RawMesh;
use pair::RawPair;

pub use analyses::{
    Analyses, ComplianceAnalysis, ContactAnalysis, LtcaAnalysis, LubricationAnalysis, MeshAnalysis,
};
pub use load::Load;
pub use mesh::{ElementKind, MeshOptions};
pub use validated::{
    BevelGears, BevelKeyLines, CylindricalGears, Gears, PairKind, RackTipRadiusSource, Scene,
};

/// Flank modifications: defined in [`crate::geometry::micro`], re-exported here
/// because a scene is where they are read.
pub use crate::geometry::micro::{MicroGeometry, Relief, ReliefShape};

/// Reads and validates a scene file of any pair kind.
pub fn read_scene(path: &Path) -> Result<Scene, FlankError> {
    let text = crate::text_file::read_utf8(path)?;
    parse_scene(&text, path)
}

/// Parses and validates scene text of any pair kind (`[pair] kind`); `path`
/// names the file in errors and anchors relative paths (measured
/// profiles).
pub fn parse_scene(text: &str, path: &Path) -> Result<Scene, FlankError> {
    let cx = Cx { text, file: path };
    if bevel_kind(&cx)?.is_some() {
        let raw: bevel::RawBevelScene = toml::from_str(text).map_err(|e| cx.toml_error(&e))?;
        return bevel::build(&cx, raw);
    }
    let raw: RawScene = toml::from_str(text).map_err(|e| cx.toml_error(&e))?;
    build(&cx, raw)
}

/// `[pair] kind` if it names a bevel pair.
fn bevel_kind(cx: &Cx) -> Result<Option<toml::Spanned<String>>, FlankError> {
    #[derive(Deserialize)]
    struct Peek {
        pair: Option<PeekPair>,
    }
    #[derive(Deserialize)]
    struct PeekPair {
        kind: Option<toml::Spanned<String>>,
    }
    let peek: Peek = toml::from_str(cx.text).map_err(|e| cx.toml_error(&e))?;
    Ok(peek
        .pair
        .and_then(|p| p.kind)
        .filter(|k| matches!(k.get_ref().as_str(), "spiral_bevel" | "hypoid")))
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawScene {
    pair: RawPair,
    pinion: RawGear,
    gear: RawGear,
    #[serde(default)]
    materials: BTreeMap<String, RawMaterial>,
    load: RawLoad,
    analyses: Option<RawAnalyses>,
    mesh: Option<RawMesh>,
    lubricant: Option<lubricant::RawLubricant>,
}

fn build(cx: &Cx, raw: RawScene) -> Res<Scene> {
    let kind = *raw.pair.kind.get_ref();
    let (pinion, ps, pinion_rack) = gear::gear(cx, &raw.pinion, "pinion", kind)?;
    let (gear_spec, gs, gear_rack) = gear::gear(cx, &raw.gear, "gear", kind)?;
    let pair = pair::pair_spec(cx, &raw.pair, kind, pinion, &ps, gear_spec, &gs)?;

    // materials
    let pinion_material = materials::material(cx, &raw.materials, &ps.material, "pinion")?;
    let gear_material = materials::material(cx, &raw.materials, &gs.material, "gear")?;

    // load
    let load = load::load(cx, &raw.load)?;

    // micro-geometry
    let micro = [
        match &raw.pinion.micro {
            Some(m) => Some(gear::micro_geometry(
                cx,
                m,
                "pinion",
                pair.pinion.face_width,
            )?),
            None => None,
        },
        match &raw.gear.micro {
            Some(m) => Some(gear::micro_geometry(cx, m, "gear", pair.gear.face_width)?),
            None => None,
        },
    ];

    let analyses = analyses::analyses(cx, raw.analyses.as_ref())?;
    if let (Some(span), Some(why)) = (
        analyses.ltca_span.clone(),
        analyses.ltca.as_ref().and_then(bevel_only_ltca_key),
    ) {
        return Err(cx.err(span, format!("`analyses.ltca`: {why}")));
    }
    let lubricant = lubricant::scene_lubricant(cx, raw.lubricant.as_ref(), &analyses, &load)?;
    let min_teeth = pair.pinion.teeth.min(pair.gear.teeth);
    let min_module = pair.pinion.normal_module.min(pair.gear.normal_module);
    let mut mesh = mesh::mesh_options(cx, raw.mesh.as_ref(), min_teeth, min_module)?;
    let [teeth_line, ..] = mesh::key_lines(cx, raw.mesh.as_ref());
    // the sector that holds every pair in mesh under the load (a pair the
    // analyses would refuse is refused by them, with its reason)
    let (e1, e2) = (pinion_material.young, gear_material.young);
    let sector_in_mesh = crate::geometry::cylindrical::sector_size::sector_in_mesh(
        &pair,
        load.torque_nmm / 1e3,
        2.0 * e1 * e2 / (e1 + e2),
    )
    .ok();
    if let (None, Some(s)) = (teeth_line, &sector_in_mesh) {
        mesh.teeth_in_sector = s.teeth as u32;
    }

    let gears = CylindricalGears {
        pair,
        micro,
        rack_tip_radius_source: [pinion_rack, gear_rack],
        sector_in_mesh,
        teeth_in_sector_line: teeth_line,
    };
    // bind the modifications to their gears now (a relief longer than the
    // active profile, a measured profile that does not fit): the error names
    // the `[<gear>.micro]` table instead of surfacing later without a line
    for (i, name, raw_micro) in [
        (0, "pinion", &raw.pinion.micro),
        (1, "gear", &raw.gear.micro),
    ] {
        if let Some(m) = raw_micro {
            gears.flank_modification(i).map_err(|e| match e {
                FlankError::Model(msg) => cx.err(m.first_span(), format!("`{name}.micro`: {msg}")),
                e => e,
            })?;
        }
    }
    let scene = Scene {
        kind: kind.into(),
        gears: Gears::Cylindrical(gears),
        pinion_material,
        gear_material,
        load,
        analyses,
        mesh,
        lubricant,
        source: cx.file.to_path_buf(),
        kind_line: cx.line(raw.pair.kind.span().start),
    };
    Ok(scene)
}

/// Why the first `[analyses.ltca]` key that only a bevel/hypoid LTCA reads
/// is refused on a spur/helical scene, if one is given (the mirror of the
/// bevel reader's spur-only keys).
fn bevel_only_ltca_key(l: &analyses::LtcaAnalysis) -> Option<String> {
    if let Some(e) = l.edges {
        return Some(format!(
            "edges = \"{}\" is for bevel and hypoid pairs (their TCA's edge contacts); a spur/helical LTCA always takes its tip corners as candidates",
            serde_json::to_value(e).ok().and_then(|v| v.as_str().map(String::from)).unwrap_or_default()
        ));
    }
    l.positions.map(|n| format!(
        "positions = {n} is for bevel and hypoid pairs (positions over one mesh cycle); a spur/helical LTCA takes roll_start_deg, roll_end_deg and roll_step_deg, or roll_angles_deg"
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fem::material::Material;
    use crate::geometry::{Hand, RackProfile};
    use crate::scene::involute::{
        reference_diameter, shift_sum_for_centre_distance, transverse_contact_ratio,
    };
    use crate::scene::test_support::*;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-12 * a.abs().max(b.abs()).max(1.0)
    }

    #[test]
    fn spur_scene_in_internal_units() {
        let s = parse(SPUR).unwrap();
        assert_eq!(s.kind, PairKind::Spur);
        let p = &s.cylindrical("this test").unwrap().pair.pinion;
        let g = &s.cylindrical("this test").unwrap().pair.gear;
        assert_eq!((p.teeth, g.teeth), (13, 35));
        assert!(close(p.normal_module, 3.8));
        assert!(close(p.normal_pressure_angle, 20f64.to_radians()));
        assert_eq!(p.helix_angle, 0.0);
        assert_eq!(g.helix_angle, 0.0);
        assert!(close(p.face_width, 13.3));
        assert!(close(p.profile_shift, 0.3));
        assert!(close(g.profile_shift, -0.59931744));
        assert_eq!(p.rack, RackProfile::default());
        assert_eq!(p.tip_diameter, Some(58.7));
        assert_eq!(g.tip_diameter, Some(135.5));
        assert!(close(p.bore_diameter, 20.0));
        assert!(close(
            s.cylindrical("this test").unwrap().pair.centre_distance,
            90.0
        ));
        assert_eq!(
            s.pinion_material,
            Material::new("steel", 206000.0, 0.3).unwrap()
        );
        assert_eq!(s.gear_material, s.pinion_material);
        // N·m → N·mm
        assert!(close(s.load.torque_nmm, 312_000.0));
        assert!(close(s.load.speed_rpm, 11758.0));
        // µm → mm
        let m = s.cylindrical("this test").unwrap().micro[0]
            .as_ref()
            .unwrap();
        let tip = m.tip_relief.unwrap();
        assert!(close(tip.amount, 0.010));
        assert!(close(tip.length, 1.0));
        assert_eq!(tip.shape, ReliefShape::Parabolic);
        assert!(m.root_relief.is_none());
        assert!(close(m.lead_crowning, 0.005));
        assert!(close(m.helix_slope_deviation, -0.003));
        assert_eq!(m.profile_crowning, 0.0);
        let end = m.end_relief.unwrap();
        assert!(close(end.amount, 0.020));
        assert_eq!(end.shape, ReliefShape::Linear);
        assert!(s.cylindrical("this test").unwrap().micro[1].is_none());
        assert_eq!(s.analyses.mesh, Some(MeshAnalysis {}));
        assert_eq!(
            s.mesh,
            MeshOptions {
                teeth_in_sector: 3,
                element: ElementKind::Wedge15,
                flank_size: Some(0.1),
                base_size: Some(1.0),
            }
        );
        assert_eq!(s.source, Path::new("/nonexistent/scene.toml"));
        // a = 90 mm with x1 + x2 = -0.2993 is backlash-free to 1e-4
        let xs = shift_sum_for_centre_distance(p, g, 90.0);
        assert!((xs - (-0.29932)).abs() < 1e-5, "{xs}");
    }

    #[test]
    fn helical_scene_in_internal_units() {
        let s = parse(HELICAL).unwrap();
        assert_eq!(s.kind, PairKind::Helical);
        let p = &s.cylindrical("this test").unwrap().pair.pinion;
        let g = &s.cylindrical("this test").unwrap().pair.gear;
        assert!(close(p.normal_module, 15.0)); // integer in the file
        assert!(close(p.helix_angle, 20f64.to_radians()));
        assert!(close(g.helix_angle, 20f64.to_radians()));
        assert_eq!((p.hand, g.hand), (Hand::Right, Hand::Left));
        assert_eq!(p.profile_shift, 0.0);
        assert_eq!(p.tip_diameter, None);
        assert_eq!(p.rack, RackProfile::default());
        assert_eq!(s.pinion_material.name, "a");
        assert_eq!(s.gear_material, Material::new("b", 210000.0, 0.29).unwrap());
        assert!(close(s.load.torque_nmm, 5.0e6));
        assert_eq!(s.cylindrical("this test").unwrap().micro, [None, None]);
        assert_eq!(s.analyses, Analyses::default());
        // no sector stated: the default is the sector that holds every pair in mesh
        let held = s
            .cylindrical("this test")
            .unwrap()
            .sector_in_mesh
            .as_ref()
            .unwrap()
            .teeth;
        assert!(held >= 3, "{held}");
        assert_eq!(s.mesh.teeth_in_sector as usize, held);
        let stated = MeshOptions {
            teeth_in_sector: held as u32,
            ..MeshOptions::default()
        };
        assert_eq!(s.mesh, stated);
        // reference centre distance: (21 + 37) 15 / (2 cos 20°) = 462.9173 mm
        let a_ref = reference_diameter(p) / 2.0 + reference_diameter(g) / 2.0;
        assert!((a_ref - 462.9173).abs() < 1e-4, "{a_ref}");
    }

    #[test]
    fn unknown_key_top_level() {
        let t = edit(SPUR, "[load]\n", "[loads]\ntorque = 1\n\n[load]\n");
        expect_err(&t, line_of(&t, "[loads]"), &["loads"]);
    }

    #[test]
    fn missing_required_key() {
        let t = edit(
            SPUR,
            "face_width_mm = 13.3\nprofile_shift = 0.3\n",
            "profile_shift = 0.3\n",
        );
        expect_err(
            &t,
            line_of(&t, "[pinion]"),
            &["[pinion]", "missing field `face_width_mm`"],
        );
        let t = edit(SPUR, "[load]\ntorque_nm = 312.0\n", "[load]\n");
        expect_err(&t, line_of(&t, "[load]"), &["[load]", "torque_nm"]);
        // a missing file is an I/O error naming the path
        let e = read_scene(Path::new("/nonexistent/scene.toml")).unwrap_err();
        assert!(matches!(e, FlankError::Io { .. }), "{e}");
        // helical-only keys are required for a helical pair
        let t = edit(HELICAL, "hand = \"left\"\n", "");
        expect_err(&t, line_of(&t, "teeth = 37"), &["hand", "gear"]);
        let t = edit(
            HELICAL,
            "helix_angle_deg = 20.0\nhand = \"right\"",
            "hand = \"right\"",
        );
        expect_err(
            &t,
            line_of(&t, "teeth = 21"),
            &["helix_angle_deg", "pinion"],
        );
    }

    #[test]
    fn no_panic_on_odd_input() {
        for text in [
            "",
            "[pair]",
            "\u{0}\u{ff}",
            "pair = 3",
            "[pair]\nkind = 7",
            "a = [",
            "[[pinion]]\nteeth = 1",
        ] {
            assert!(parse(text).is_err(), "{text:?}");
        }
        for (from, to) in [
            ("teeth = 13", "teeth = 99999999999999"),
            (
                "normal_module_mm = 3.8\nnormal_pressure_angle_deg = 20.0\nhelix",
                "normal_module_mm = inf\nnormal_pressure_angle_deg = 20.0\nhelix",
            ),
            ("centre_distance_mm = 90.0", "centre_distance_mm = nan"),
            ("torque_nm = 312.0", "torque_nm = \"lots\""),
            ("profile_shift = 0.3", "profile_shift = 1e308"),
        ] {
            assert!(parse(&edit(SPUR, from, to)).is_err(), "{to}");
        }
    }

    #[test]
    fn paper_scenes_parse() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("papers");
        let s2 = read_scene(&root.join("seed002-spur/scene.toml")).unwrap();
        assert_eq!(s2.kind, PairKind::Spur);
        assert_eq!(
            (
                s2.cylindrical("this test").unwrap().pair.pinion.teeth,
                s2.cylindrical("this test").unwrap().pair.gear.teeth
            ),
            (13, 35)
        );
        assert!(close(
            s2.cylindrical("this test").unwrap().pair.centre_distance,
            90.0
        ));
        assert!(close(s2.load.torque_nmm, 312_000.0));
        assert!(close(s2.pinion_material.young, 206_000.0));
        let eps2 = transverse_contact_ratio(&s2.cylindrical("this test").unwrap().pair);
        assert!((1.45..=1.51).contains(&eps2), "seed 002 eps_alpha {eps2}");
        assert!((eps2 - 1.4844).abs() < 1e-4, "README value {eps2}");

        let s4 = read_scene(&root.join("seed004-helical/scene.toml")).unwrap();
        assert_eq!(s4.kind, PairKind::Helical);
        assert_eq!(
            (
                s4.cylindrical("this test").unwrap().pair.pinion.teeth,
                s4.cylindrical("this test").unwrap().pair.gear.teeth
            ),
            (21, 37)
        );
        assert!(close(
            s4.cylindrical("this test").unwrap().pair.pinion.helix_angle,
            20f64.to_radians()
        ));
        assert!(close(s4.load.torque_nmm, 5.0e6));
        assert!(close(s4.gear_material.young, 207_000.0));
        let eps4 = transverse_contact_ratio(&s4.cylindrical("this test").unwrap().pair);
        assert!((eps4 - 1.5029).abs() < 1e-4, "README value {eps4}");

        // the geometry module's pair check accepts both and agrees on ε_α
        let r2 =
            crate::geometry::pair::check_pair(&s2.cylindrical("this test").unwrap().pair).unwrap();
        assert!(
            (r2.contact_ratio - eps2).abs() < 1e-9,
            "{}",
            r2.contact_ratio
        );
        let r4 =
            crate::geometry::pair::check_pair(&s4.cylindrical("this test").unwrap().pair).unwrap();
        assert!(
            (r4.contact_ratio - eps4).abs() < 1e-9,
            "{}",
            r4.contact_ratio
        );
        assert!(
            (r4.overlap_ratio - 1.3064).abs() < 1e-4,
            "{}",
            r4.overlap_ratio
        );
    }

    #[test]
    fn no_panic_on_mutated_scenes() {
        // deterministic mutations of a valid scene: every one parses or errors, none panics
        let base: Vec<char> = SPUR.chars().collect();
        let alphabet: Vec<char> = "=[]{}\"'.,-+0123456789eainf_\n #é".chars().collect();
        let mut state: u64 = 0x9e37_79b9_7f4a_7c15;
        let mut next = |n: usize| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state % n as u64) as usize
        };
        for _ in 0..3000 {
            let mut t = base.clone();
            for _ in 0..1 + next(3) {
                let at = next(t.len());
                match next(3) {
                    0 => {
                        t.remove(at);
                    }
                    1 => t.insert(at, alphabet[next(alphabet.len())]),
                    _ => t[at] = alphabet[next(alphabet.len())],
                }
            }
            let text: String = t.into_iter().collect();
            if let Err(e) = parse(&text) {
                assert!(matches!(e, FlankError::Parse { .. }), "{e}");
            }
        }
    }
}
