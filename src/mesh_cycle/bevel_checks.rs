//! Checks of a bevel/hypoid FE contact run made before its stiffness is
//! factorized, and the cycle built after them ([`checked_cycle`]): a
//! torque that loads no pair
//! ([`crate::mesh_cycle::pair_model::check_torque`]), a sector too small to
//! hold the pairs in mesh, bodies that interpenetrate in the unloaded
//! assembly. Each error names the scene key to change, at its line.
//!
//! **Interpenetration: noise against a real one.** The FE sees the unloaded
//! geometry through its candidates' initial gaps g₀: a pinion flank node
//! (exactly on the generated surface, corner and midside nodes alike)
//! against the gear's quadratic flank faces, which leave the surface by the
//! mesh's flank-edge deviation (third order in the element size:
//! 3.5e-3 mm at 1 mm, about 0.03 mm at 2 mm, `verification/bevel_sector_mesh`).
//! So g₀ carries discretisation noise of that size, which grows fast on
//! the coarse meshes that are allowed (up to half the whole depth). The
//! check therefore does not judge g₀: at the deepest FE candidates of each
//! pair and position it measures the pinion node's signed distance to the
//! exact gear flank (closest point on the generated surface), which has
//! no mesh in it, and judges that ([`exact_depths`]); g₀ is reported
//! beside it, so the noise can be read off.
//!
//! **Threshold.** In the nominal (kinematic) placement a pair's flanks
//! interpenetrate legitimately by its unloaded TE times the gear's moment
//! arm: the pinion's rigid turn resolves that before load, and the loaded
//! TE contains it. What is not legitimate is flanks that cross: a pair
//! whose cut does not mesh with the gear, so that a neighbouring pair
//! stops the gear far from where the TCA says (seed 003's milled pinion:
//! 0.65–0.87 mm; the middle pair then never carries load). The threshold
//! is [`GROSS_INTERPENETRATION_MODULE`] × the mean normal module m_mn
//! (0.194 mm on seed 003, m_mn = 3.89 mm; m_mn-relative so that a scaled
//! pair is judged alike). Measured on the exact surfaces (test
//! `unloaded_interpenetration_of_the_seed_scenes`, 20 positions over a
//! cycle, all three pairs, 2 and 1 mm meshes): the designed seed 003 pairs
//! (eased, synthesised) reach at most 0.55 µm; the milled pinions 0.82 mm
//! (seed 003) and 0.72 mm (seed 001). 0.05 m_mn lies 350 times above the
//! first and 3.6 times below the second. It is an unloaded TE of
//! 0.194 mm / 94 mm ≈ 425″ at seed 003's gear mean radius, many times any
//! TE a gear set is built with. The FE gap at the same nodes differed
//! from the exact depth by at most 0.33 µm (2 mm mesh) and 0.04 µm (1 mm).

use std::collections::BTreeSet;
use std::time::Instant;

use crate::contact::pairing::{build_pair_placed, PairingOptions};
use crate::contact::placement::Placement;
use crate::error::FlankError;
use crate::geometry::gear_pair::{Flank, GearPair};
use crate::mesh::bevel_sector::BevelSectorOptions;
use crate::mesh_cycle::cycle::{MeshCycle, RunSettings};
use crate::mesh_cycle::pair_model::{bevel_pair_model, PairModel};
use crate::scene::Scene;
use crate::tca::point_contact::{point_tca, PointTcaSettings};

/// Gross unloaded interpenetration, in mean normal modules (module docs).
pub const GROSS_INTERPENETRATION_MODULE: f64 = 0.05;

/// Deepest FE candidates per pair and position whose exact depth is
/// measured.
const EXACT_CANDIDATES: usize = 8;

/// Positions of the default bevel run over one mesh cycle.
pub const DEFAULT_POSITIONS: usize = 20;

/// A factorized bevel cycle after the input checks ([`checked_cycle`]).
pub struct CheckedCycle {
    pub cycle: MeshCycle,
    /// The unloaded pairs' exact depths at the roll angles checked.
    pub unloaded: Vec<UnloadedPair>,
    /// What the checks could not establish (shank with a partial sector;
    /// the point TCA did not run).
    pub warnings: Vec<String>,
    /// Time of the checks, and of the system's setup (assembly, ordering,
    /// factorization, condition estimates) (s).
    pub checks_s: f64,
    pub setup_s: f64,
}

/// The FE cycle of a bevel/hypoid `scene` for the roll angles `rolls`
/// (deg), built only after the checks that refuse bad inputs before the
/// factorization: the torque, the members meshed with `mesh` (the more
/// basic error first), a sector that holds every pair in mesh at these
/// angles, no gross unloaded interpenetration. Every FE contact cycle of a
/// bevel pair in a run goes through it (`flank run`, `flank compare`).
pub fn checked_cycle(
    scene: &Scene,
    mesh: &BevelSectorOptions,
    settings: RunSettings,
    threads: usize,
    rolls: &[f64],
) -> Result<CheckedCycle, FlankError> {
    let bevel = scene.bevel("the bevel/hypoid FE mesh cycle")?;
    let mut warnings = Vec::new();
    let t_check = Instant::now();
    // meshing first (it checks the torque): a member that cannot be
    // meshed is the more basic error
    let model = bevel_pair_model(scene, mesh)?;
    if mesh.shank.is_some() && scene.mesh.teeth_in_sector < bevel.blank_inputs.z1 {
        warnings.push(crate::mesh::bevel_sector::SHANK_SECTOR_WARNING.to_string());
    }
    if check_sector(scene, rolls)?.is_none() {
        warnings.push(
            "the point TCA did not run: whether the sector holds every pair in mesh is not checked"
                .to_string(),
        );
    }
    let pairing = PairingOptions {
        search_distance: Some(settings.search_distance_mm),
        max_initial_penetration: None,
    };
    let unloaded = exact_depths(&model, bevel.pair.as_ref(), rolls, &pairing)?;
    check_interpenetration(scene, &model, &unloaded)?;
    let checks_s = t_check.elapsed().as_secs_f64();
    let t0 = Instant::now();
    let cycle = MeshCycle::of_pair(scene, model, settings, threads)?;
    Ok(CheckedCycle {
        cycle,
        unloaded,
        warnings,
        checks_s,
        setup_s: t0.elapsed().as_secs_f64(),
    })
}

/// The sector must hold every pair that is in mesh at the run's roll
/// angles: the point TCA (exact surfaces, edges on, δ = 0.00635 mm) says
/// which pairs lie within δ of contact at the grid rolls bracketing each
/// roll; a pair among them that the sector does not model is an error
/// naming `mesh.teeth_in_sector` and the count needed. Returns the
/// smallest sufficient sector, or `None` when the TCA does not run (a
/// warning is then the caller's).
pub fn check_sector(scene: &Scene, rolls_deg: &[f64]) -> Result<Option<usize>, FlankError> {
    let bevel = scene.bevel("the bevel/hypoid FE mesh cycle")?;
    let pair = bevel.pair.as_ref();
    let settings = PointTcaSettings {
        search_directions: 0,
        ..Default::default()
    };
    let Ok(tca) = point_tca(pair, &settings) else {
        return Ok(None);
    };
    let h = tca.pitch_rad / settings.positions_per_pitch as f64;
    let mut needed = BTreeSet::new();
    let mut missing: Option<(f64, i64)> = None;
    for &r in rolls_deg {
        let r = r.to_radians();
        for p in tca.positions.iter().filter(|p| (p.roll_rad - r).abs() < h) {
            for c in p
                .pairs
                .iter()
                .filter(|c| c.separation_mm <= settings.approach_mm)
            {
                needed.insert(c.offset);
                if c.teeth.is_none() && missing.is_none() {
                    missing = Some((r.to_degrees(), c.offset));
                }
            }
        }
    }
    let (lo, hi) = (
        needed.first().copied().unwrap_or(0),
        needed.last().copied().unwrap_or(0),
    );
    // the smallest sector whose middle tooth ⌈n/2⌉ has the needed pairs on both sides
    let z1 = bevel.blank_inputs.z1 as usize;
    let enough =
        Some(crate::geometry::gear_pair::sector_teeth_holding(lo, hi)).filter(|&n| n <= z1);
    if let Some((roll, offset)) = missing {
        let n = pair.sector_teeth();
        let key = match bevel.lines.teeth_in_sector {
            Some(l) => format!("{} `mesh.teeth_in_sector` = {n}", scene.at(l)),
            None => format!(
                "`mesh.teeth_in_sector` (default {n}, in [mesh] of {})",
                scene.source.display()
            ),
        };
        return Err(FlankError::Model(format!(
            "{key}: the sector is too small to hold the pairs in mesh: at roll {roll:.3}° the pair {offset:+} pitch(es) from the middle one is within δ = {} mm of contact (point TCA) but not modelled; {} teeth are needed",
            settings.approach_mm,
            enough.map_or_else(|| "more".to_string(), |n| n.to_string())
        )));
    }
    Ok(enough)
}

/// The unloaded geometry of one tooth pair at one position.
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct UnloadedPair {
    pub roll_deg: f64,
    /// Tooth pair index (0-based) of the pair model.
    pub pair: usize,
    /// Smallest FE initial gap g₀ of its candidates (mm).
    pub fe_gap_mm: f64,
    /// Largest depth of a candidate's pinion node inside the exact gear
    /// flank (mm, ≥ 0; 0: none inside), and that node's FE gap.
    pub exact_depth_mm: f64,
    pub fe_gap_there_mm: f64,
}

/// Per roll angle and tooth pair, in the nominal placement: the smallest
/// FE gap and the deepest exact interpenetration of the
/// `EXACT_CANDIDATES` deepest candidates (module docs).
pub fn exact_depths(
    model: &PairModel,
    pair: &dyn GearPair,
    rolls_deg: &[f64],
    pairing: &PairingOptions,
) -> Result<Vec<UnloadedPair>, FlankError> {
    let mut out = Vec::new();
    for &roll in rolls_deg {
        let frames = pair.nominal_frames(roll.to_radians());
        let placement = Placement {
            body_of: model.body_of.clone(),
            frames: frames.to_vec(),
        };
        for (p, (&(kp, kg), ids)) in model.teeth.iter().zip(&model.pairings).enumerate() {
            let Some(id) = ids[0] else { continue };
            let g = build_pair_placed(&model.model, &placement, id, pairing)?;
            let mut order: Vec<usize> = (0..g.constraints.len()).collect();
            order.sort_by(|&a, &b| g.constraints[a].g0.total_cmp(&g.constraints[b].g0));
            let (Some(pf), Some(gf)) = (
                pair.pinion().flank(Flank::Right, kp),
                pair.gear().flank(Flank::Right, kg),
            ) else {
                continue;
            };
            let (gv0, gv1) = gf.v_range();
            let mut row = UnloadedPair {
                roll_deg: roll,
                pair: p,
                fe_gap_mm: order
                    .first()
                    .map_or(f64::INFINITY, |&i| g.constraints[i].g0),
                exact_depth_mm: 0.0,
                fe_gap_there_mm: f64::INFINITY,
            };
            for &i in order.iter().take(EXACT_CANDIDATES) {
                let c = &g.constraints[i];
                let Some(&(u, v)) = model.flank_uv.get(&c.slave) else {
                    continue;
                };
                let x = frames[0].place(pf.point(u, v));
                let o = frames[1].translation;
                let xg = frames[1].rotate_back([x[0] - o[0], x[1] - o[1], x[2] - o[2]]);
                let (gu, gvv, d) = gf.closest_point_from(xg, 0.0, 0.5 * (gv0 + gv1));
                // a closest point on the domain's edge has no meaningful sign
                let inside = gu > gf.u_root(gvv) + 1e-9
                    && gu < gf.u_tip(gvv) - 1e-9
                    && gvv > gv0 + 1e-9
                    && gvv < gv1 - 1e-9;
                if inside && d.is_finite() && -d > row.exact_depth_mm {
                    row.exact_depth_mm = -d;
                    row.fe_gap_there_mm = c.g0;
                }
            }
            out.push(row);
        }
    }
    Ok(out)
}

/// Gross interpenetration (module docs) is an error naming the pinion's
/// cut, the deepest pair and position, and both depths.
pub fn check_interpenetration(
    scene: &Scene,
    model: &PairModel,
    found: &[UnloadedPair],
) -> Result<(), FlankError> {
    let bevel = scene.bevel("the bevel/hypoid FE mesh cycle")?;
    let limit = GROSS_INTERPENETRATION_MODULE * bevel.blank.cones.m_mn;
    let Some(w) = found
        .iter()
        .filter(|w| w.exact_depth_mm > limit)
        .max_by(|a, b| a.exact_depth_mm.total_cmp(&b.exact_depth_mm))
    else {
        return Ok(());
    };
    let (kp, kg) = model.teeth[w.pair];
    Err(FlankError::Model(format!(
        "{} [pinion]: the unloaded bodies interpenetrate: at roll {:.3}° pinion tooth {kp} lies {:.4} mm inside gear tooth {kg} (exact surfaces; FE gap {:.4} mm), more than {GROSS_INTERPENETRATION_MODULE} m_mn = {limit:.4} mm (an unloaded TE cannot explain it: the flanks cross and another pair stops the gear): the pinion's cut does not mesh with the gear; change its machine settings ([pinion.machine]), or cut it conjugate with an ease-off (`pinion.process` = \"conjugate\", [pinion.ease_off]) or synthesised (\"synthesised\", [pinion.synthesis]); `flank tca` reports the crossing",
        scene.at(bevel.lines.pinion),
        w.roll_deg,
        w.exact_depth_mm,
        w.fe_gap_there_mm,
    )))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::bevel_body::bevel_body_model;
    use crate::mesh::bevel_sector::BevelSectorOptions;
    use crate::mesh_cycle::pair_model::{combine, PairBody};
    use crate::scene::read_scene;
    use crate::settings::SlaveBody;

    /// The bevel gears of a scene this test reads.
    fn gears(s: &Scene) -> &crate::scene::BevelGears {
        s.bevel("this test").unwrap()
    }

    fn scene(rel: &str) -> Scene {
        let path = format!("{}/papers/{rel}", env!("CARGO_MANIFEST_DIR"));
        let s = read_scene(std::path::Path::new(&path)).unwrap();
        s
    }

    fn model(s: &Scene, flank: f64) -> PairModel {
        let bevel = gears(s);
        let opts = BevelSectorOptions {
            flank_size: flank,
            base_size: 4.0 * flank,
            ..Default::default()
        };
        let p =
            bevel_body_model(&bevel.bodies[0], "pinion", &s.pinion_material, &opts, None).unwrap();
        let g = bevel_body_model(&bevel.bodies[1], "gear", &s.gear_material, &opts, None).unwrap();
        combine(
            bevel.pair.as_ref(),
            [
                PairBody::of("pinion", &p.model, &p.sector.flank_uv),
                PairBody::of("gear", &g.model, &g.sector.flank_uv),
            ],
            s.load.torque_nmm,
            crate::contact::PressureOverclosure::Hard,
            SlaveBody::Pinion,
        )
        .unwrap()
    }

    /// The figures of the module docs' threshold: the exact unloaded
    /// interpenetration over 20 positions of the designed seed 003 pairs
    /// stays below 1 % of the threshold, the milled pinions of seeds 003
    /// and 001 exceed it (the check refuses them, naming `[pinion]`), and
    /// the FE gap's noise (g₀ − exact at the deepest node) is printed per
    /// flank size.
    #[test]
    fn unloaded_interpenetration_of_the_seed_scenes() {
        let pairing = PairingOptions {
            search_distance: Some(0.1),
            max_initial_penetration: None,
        };
        for (rel, designed) in [
            ("seed003-hypoid/scene_eased.toml", true),
            ("seed003-hypoid/scene_synthesised.toml", true),
            ("seed003-hypoid/scene.toml", false),
            ("seed001-hypoid/scene.toml", false),
        ] {
            let s = scene(rel);
            let limit = GROSS_INTERPENETRATION_MODULE * gears(&s).blank.cones.m_mn;
            let pitch = gears(&s).pair.tooth_roll_step().abs().to_degrees();
            let rolls: Vec<f64> = (0..20)
                .map(|i| -0.5 * pitch + pitch * i as f64 / 20.0)
                .collect();
            for flank in [2.0, 1.0] {
                let m = model(&s, flank);
                let found = exact_depths(&m, gears(&s).pair.as_ref(), &rolls, &pairing).unwrap();
                let deepest = found
                    .iter()
                    .max_by(|a, b| a.exact_depth_mm.total_cmp(&b.exact_depth_mm))
                    .unwrap();
                let noise = found
                    .iter()
                    .filter(|w| w.exact_depth_mm > 0.0)
                    .map(|w| (w.fe_gap_there_mm + w.exact_depth_mm).abs())
                    .fold(0.0, f64::max);
                let fe = found
                    .iter()
                    .map(|w| w.fe_gap_mm)
                    .fold(f64::INFINITY, f64::min);
                println!(
                    "{rel} flank {flank} mm: deepest exact {:.5} mm (roll {:.2}°, pair {}), smallest FE g0 {fe:.5} mm, |g0 + depth| ≤ {noise:.5} mm; threshold {limit:.4} mm",
                    deepest.exact_depth_mm, deepest.roll_deg, deepest.pair
                );
                let verdict = check_interpenetration(&s, &m, &found);
                if designed {
                    assert!(deepest.exact_depth_mm < 0.01 * limit, "{deepest:?}");
                    assert!(verdict.is_ok());
                } else {
                    let e = verdict.unwrap_err().to_string();
                    assert!(
                        e.contains("[pinion]") && e.contains("interpenetrate"),
                        "{e}"
                    );
                }
            }
        }
    }

    /// A one-tooth sector of the eased seed 003 pair (contact ratio 1.4)
    /// cannot hold the pairs in mesh over a cycle: refused with the count
    /// needed; the default three-tooth sector passes. Over the cycle
    /// centred on roll 0 the pairs within δ are the middle one and the one
    /// after it, so two teeth (middle tooth 1) would do.
    #[test]
    fn a_one_tooth_sector_is_refused() {
        let s = scene("seed003-hypoid/scene_eased.toml");
        let pitch = gears(&s).pair.tooth_roll_step().abs().to_degrees();
        let rolls: Vec<f64> = (0..20)
            .map(|i| -0.5 * pitch + pitch * i as f64 / 20.0)
            .collect();
        assert_eq!(check_sector(&s, &rolls).unwrap(), Some(2));
        let path = format!(
            "{}/papers/seed003-hypoid/scene_eased.toml",
            env!("CARGO_MANIFEST_DIR")
        );
        let text = std::fs::read_to_string(&path).unwrap() + "\n[mesh]\nteeth_in_sector = 1\n";
        let one = crate::scene::parse_scene(&text, std::path::Path::new("one.toml")).unwrap();
        let e = check_sector(&one, &rolls).unwrap_err().to_string();
        println!("{e}");
        assert!(
            e.contains("one.toml:") && e.contains("too small") && e.contains("2 teeth are needed"),
            "{e}"
        );
    }
}
