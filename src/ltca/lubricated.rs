//! The wet–dry loop of seed 002 through the frictional LTCA of any pair
//! kind (`flank ltca` on a scene with `[lubricant]` and
//! `[analyses.lubrication]`): the dry pass is the LTCA cycle at μ₀ =
//! `initial_mu`; per loaded tooth pair and position the operating point
//! goes through the EHL model of [`crate::lubrication`]; the wet passes
//! solve every position again with that μ per tooth pair
//! ([`LtcaSettings::pair_mu`], μ per candidate point in
//! [`crate::ltca::friction::FrictionProblem::point_mu`]).
//!
//! The operating point of pair p at a position:
//! * W: the LTCA's normal force of the pair (Σ over its points);
//! * R_x, R_y, u, v_s of a **line contact** (spur, helical): the closed-form
//!   involute contact at the pair's kinematic path position
//!   ([`crate::lubrication::involute_contact`]), as the FE variant
//!   ([`crate::mesh_cycle::lubricated`]); Hertz: a line of the face width
//!   over cos β_b;
//! * of a **point contact** (bevel, hypoid): the point TCA's contact of the
//!   pair at the grid position ([`PointCandidates::grid_position`]). Its
//!   curvature ellipse at approach δ has semi-axes a = √(2δ/λ_min),
//!   b = √(2δ/λ_max) (λ the principal relative curvatures,
//!   [`crate::geometry::contact_curvature`]), so λ_max = 2δ/b²,
//!   λ_min = 2δ/a². The entrainment u = |v_t1 + v_t2|/2 runs at θ to the
//!   minor axis; R_x and R_y are the effective radii along and across it,
//!   1/R_x = λ_max cos²θ + λ_min sin²θ, 1/R_y = λ_max sin²θ + λ_min cos²θ
//!   (Chittenden, Dowson, Dunn & Taylor 1985, entrainment at an angle to the
//!   ellipse's axes; the default film fit is theirs), v_s = |v_t1 − v_t2|,
//!   the TCA's speeds scaled to the scene's `load.speed_rpm`. Hertz: the
//!   exact elliptical contact of W on the principal radii
//!   ([`crate::ltca::hertz_elliptic`]). A pair in edge contact (no
//!   ellipse) has no operating point: its μ stays μ₀ (counted in the
//!   summary's notes);
//! * A (for `mean_pressure = "contact_area"`): Σ 2aᵢ wᵢ over the pair's
//!   loaded points, aᵢ the Hertz half-width of the point's load per length
//!   on its TCA radius (the LTCA's own local model) and wᵢ the length it
//!   represents; at a tip-corner point (edge radius 0, no Hertz width of
//!   its own) aᵢ is the Hertz half-width of its load per length on the
//!   operating point's R_x (the path end's, flagged `OutsidePath`, which
//!   the film and traction use too). On a uniformly loaded line this is
//!   the Hertz area 2bL, so the two P̄ options differ by the load's
//!   variation along the line and by corner loads (both are in
//!   `lubrication.csv`).
//!
//! The friction model defaults to `sliding` (P_t = μ P_n against the
//! kinematic sliding: the traction of a sliding EHL contact, and what the
//! power loss μ W |v_s| assumes); `--friction-model` or `[analyses.ltca]
//! friction_model` choose another. Outputs: [`crate::report::lubrication`].

use std::path::Path;
use std::time::Instant;

use crate::error::FlankError;
use crate::geometry::cylindrical::MeshKinematics;
use crate::geometry::gear_pair::LineContactPair;
use crate::geometry::tangency::ContactSystem;
use crate::geometry::vec3::{cross, dot, unit};
use crate::load_sharing::LOADED_FRACTION;
use crate::ltca::cycle::{LtcaCycle, LtcaOptions};
use crate::ltca::hertz_elliptic::hertz_elliptic;
use crate::ltca::local::hertz_line;
use crate::ltca::model::PositionResult;
use crate::ltca::solve_settings::LtcaSettings;
use crate::lubrication::{
    involute_contact, reduced_modulus, wet_dry_loop, ContactKinematics, HertzContact, LoopResult,
    LoopSettings, OperatingPoint,
};
use crate::report::lubrication::{LtcaLoopFigures, LubricationSummary};
use crate::scene::{Gears, Scene};
use crate::settings::FrictionModel;
use crate::tca::point_candidates::PointCandidates;
use crate::tca::point_contact::PairContact;

/// The loop's settings and the friction model it runs the LTCA with.
#[derive(Clone, Debug)]
pub struct LubricatedSettings {
    pub settings: LoopSettings,
    pub model: FrictionModel,
}

impl LubricatedSettings {
    /// The options of the dry pass: friction at μ₀ with the loop's model.
    pub fn dry_options(&self, o: &LtcaOptions) -> LtcaOptions {
        LtcaOptions {
            friction_mu: Some(self.settings.initial_mu),
            friction_model: Some(self.model),
            ..o.clone()
        }
    }
}

/// The loop of the scene's `[analyses.lubrication]` for the LTCA (`None`
/// without it), checked against the LTCA's friction options: the loop sets
/// μ itself, so `--friction-mu` is refused, and an `[analyses.ltca]
/// friction_mu` must be > 0 and equal `initial_mu` if both are given
/// (without `initial_mu` it is μ₀, else 0.05 as seed 002).
pub fn loop_settings(
    scene: &Scene,
    o: &LtcaOptions,
) -> Result<Option<LubricatedSettings>, FlankError> {
    let Some(l) = &scene.analyses.lubrication else {
        return Ok(None);
    };
    if scene.lubricant.is_none() {
        return Err(FlankError::Model(
            "[analyses.lubrication] needs a [lubricant] table".into(),
        ));
    }
    if let Some(mu) = o.friction_mu {
        return Err(FlankError::Model(format!(
            "--friction-mu {mu}: not with [analyses.lubrication] in {}: the wet–dry loop sets μ itself (the dry pass at `initial_mu`, then μ per position and tooth pair from the EHL model); give the dry pass's μ as [analyses.lubrication] initial_mu",
            scene.source.display()
        )));
    }
    let a = scene.analyses.ltca.clone().unwrap_or_default();
    let initial_mu = match (a.friction_mu, l.initial_mu) {
        (Some(m), _) if !(m > 0.0) => {
            return Err(FlankError::Model(format!(
                "{}: [analyses.ltca] friction_mu = {m} (frictionless) contradicts [analyses.lubrication] (a lubricated, frictional loop); remove one",
                scene.source.display()
            )))
        }
        (Some(m), Some(i)) if m != i => {
            return Err(FlankError::Model(format!(
                "{}: [analyses.ltca] friction_mu = {m} and [analyses.lubrication] initial_mu = {i} both set the dry pass's μ; give one",
                scene.source.display()
            )))
        }
        (_, Some(i)) => i,
        (Some(m), None) => m,
        (None, None) => 0.05,
    };
    let settings = LoopSettings {
        film: l.film.unwrap_or_default(),
        tolerance: l.tolerance.unwrap_or(0.005),
        max_iterations: l.max_iterations.unwrap_or(10),
        initial_mu,
        composite_roughness_mm: l.composite_roughness_um.map(|r| r * 1e-3),
        mean_pressure: l.mean_pressure.unwrap_or_default(),
    };
    crate::lubrication::wet_dry::check_settings(&settings)?;
    Ok(Some(LubricatedSettings {
        settings,
        model: o
            .friction_model
            .or(a.friction_model)
            .unwrap_or(FrictionModel::Sliding),
    }))
}

/// The loop's answer: the final pass's positions and the summary object.
pub struct LubricatedLtca {
    pub results: Vec<PositionResult>,
    pub result: LoopResult,
    pub summary: LubricationSummary,
}

/// Σ 2aᵢ wᵢ (mm²) over the loaded points of pinion tooth `k`; a point
/// without a Hertz width of its own (a tip corner) takes that of its load
/// per length on `radius_x` (mm) with contact modulus `e_star` (MPa)
/// (module doc).
pub fn loaded_area(r: &PositionResult, k: usize, radius_x: f64, e_star: f64) -> f64 {
    r.points
        .iter()
        .filter(|p| p.force_n > 0.0 && p.load_per_length > 0.0 && r.lines[p.line].0 == k)
        .map(|p| {
            let a = if p.half_width_mm > 0.0 {
                p.half_width_mm
            } else {
                hertz_line(p.load_per_length, radius_x, e_star).0
            };
            2.0 * a * p.force_n / p.load_per_length
        })
        .sum()
}

/// Where the loop takes each kind's contact geometry and kinematics from.
enum LoopContacts<'a> {
    /// Closed-form involute contacts along the path.
    Line {
        pair: &'a dyn LineContactPair,
        kinematics: Box<MeshKinematics>,
        lead_crowning_mm: [f64; 2],
        length_mm: f64,
    },
    /// The point TCA's contacts; its speeds times `speed_scale`.
    Point {
        candidates: &'a PointCandidates,
        speed_scale: f64,
    },
}

/// What [`point_contact_kinematics`] finds of one point contact.
#[derive(Clone, Copy, Debug)]
pub struct PointOperatingContact {
    pub kinematics: ContactKinematics,
    pub hertz: HertzContact,
    /// The Hertz ellipse's long axis 2a (mm): the length of a line fit.
    pub long_axis_mm: f64,
    /// Angle θ of the entrainment to the minor axis (deg).
    pub entrainment_angle_deg: f64,
}

/// The EHL kinematics and the Hertz contact of load `load_n` (N) of a point
/// contact `c` of the TCA at approach `approach_mm` (module doc), speeds
/// times `speed_scale`, reduced modulus E′ (MPa); `None` without a finite
/// curvature ellipse (edge or line contact).
pub fn point_contact_kinematics(
    c: &PairContact,
    approach_mm: f64,
    speed_scale: f64,
    load_n: f64,
    reduced_modulus_mpa: f64,
) -> Result<Option<PointOperatingContact>, FlankError> {
    let Some(e) = c
        .ellipse
        .filter(|e| c.system == ContactSystem::Flank && !e.line_contact)
    else {
        return Ok(None);
    };
    let Some(a) = e.semi_major_mm else {
        return Ok(None);
    };
    let (lmax, lmin) = (
        2.0 * approach_mm / (e.semi_minor_mm * e.semi_minor_mm),
        2.0 * approach_mm / (a * a),
    );
    // θ: entrainment against the minor axis (the direction of λ_max)
    let minor = unit(cross(c.normal, e.major_direction));
    let cos = dot(c.rolling_direction, minor).abs().min(1.0);
    let (c2, s2) = (cos * cos, 1.0 - cos * cos);
    let kin = ContactKinematics {
        radius_x_mm: 1.0 / (lmax * c2 + lmin * s2),
        radius_y_mm: 1.0 / (lmax * s2 + lmin * c2),
        entraining_speed_mm_s: 1e3 * c.rolling_velocity * speed_scale,
        sliding_speed_mm_s: 1e3 * c.sliding_velocity * speed_scale,
        outside_path: false,
    };
    // gap coefficients A = λ/2 on the principal radii
    let h = hertz_elliptic(load_n, 0.5 * lmax, 0.5 * lmin, 0.5 * reduced_modulus_mpa)?;
    let area = std::f64::consts::PI * h.semi_x * h.semi_y;
    let hertz = HertzContact {
        area_mm2: area,
        mean_mpa: load_n / area,
        peak_mpa: h.p0,
    };
    Ok(Some(PointOperatingContact {
        kinematics: kin,
        hertz,
        long_axis_mm: 2.0 * h.semi_x.max(h.semi_y),
        entrainment_angle_deg: cos.acos().to_degrees(),
    }))
}

/// Runs the loop from the dry pass `dry` (solved at μ₀, roll `angles` in
/// deg) and writes its files to `out`.
pub fn lubricated_cycle(
    cycle: &LtcaCycle,
    scene: &Scene,
    ls: &LubricatedSettings,
    dry: Vec<PositionResult>,
    angles: &[f64],
    out: &Path,
) -> Result<LubricatedLtca, FlankError> {
    let t0 = Instant::now();
    let settings = &ls.settings;
    let lub = scene
        .lubricant
        .as_ref()
        .ok_or_else(|| FlankError::Model("the lubricated LTCA needs a [lubricant] table".into()))?;
    match &cycle.settings.friction {
        Some(f) if f.mu == settings.initial_mu => {}
        f => {
            return Err(FlankError::Model(format!(
                "the lubricated LTCA's dry pass must run with friction at μ₀ = {} (got {:?})",
                settings.initial_mu,
                f.as_ref().map(|f| f.mu)
            )))
        }
    }
    if dry.len() != angles.len() {
        return Err(FlankError::Model(format!(
            "lubricated LTCA: {} dry positions for {} roll angles",
            dry.len(),
            angles.len()
        )));
    }
    let np = cycle.pair.sector_teeth();
    let speed = scene.load.speed_rpm;
    let contacts = match &scene.gears {
        Gears::Cylindrical(cyl) => {
            let kinematics = Box::new(MeshKinematics::new(&cyl.pair, np)?);
            let length_mm = kinematics.face_width[0].min(kinematics.face_width[1])
                / kinematics.base_helix_angle.cos();
            LoopContacts::Line {
                pair: cycle.line_pair()?.as_ref(),
                lead_crowning_mm: [0, 1]
                    .map(|i| cyl.micro[i].as_ref().map_or(0.0, |m| m.lead_crowning)),
                kinematics,
                length_mm,
            }
        }
        Gears::Bevel(_) => {
            let candidates = cycle.point()?;
            let tca_speed = candidates.tca.settings.speed_rpm;
            if !(tca_speed > 0.0) {
                return Err(FlankError::Model(format!(
                    "the lubricated LTCA needs the point TCA's velocities: its speed is {tca_speed} rpm"
                )));
            }
            LoopContacts::Point {
                candidates,
                speed_scale: speed / tca_speed,
            }
        }
    };
    let e_prime = reduced_modulus(
        [scene.pinion_material.young, scene.gear_material.young],
        [scene.pinion_material.poisson, scene.gear_material.poisson],
    );
    let nominal = cycle.nominal_force();
    let e_star = cycle.bodies.contact_modulus;
    let mut current = dry;
    let mut pass_forces: Vec<Vec<Vec<f64>>> = Vec::new();
    let mut pass_s: Vec<f64> = Vec::new();
    // point contacts: loaded pairs without an ellipse, largest entrainment angle
    let mut without_ellipse = std::collections::BTreeSet::new();
    let mut largest_angle = 0.0f64;
    let result = wet_dry_loop(lub, settings, angles.len(), np, |pass, mu| {
        if pass > 0 {
            let t = Instant::now();
            current = angles
                .iter()
                .zip(mu)
                .map(|(&a, m)| {
                    let s = LtcaSettings {
                        pair_mu: Some(m.clone()),
                        ..cycle.settings.clone()
                    };
                    cycle.solve_with(a, &s)
                })
                .collect::<Result<_, _>>()?;
            pass_s.push(t.elapsed().as_secs_f64());
        }
        let forces: Vec<Vec<f64>> = current.iter().map(|r| cycle.pair_forces(r)).collect();
        let points = current
            .iter()
            .zip(&forces)
            .map(|(r, f)| {
                let grid = match &contacts {
                    LoopContacts::Point { candidates, .. } => candidates.grid_position(r.roll_deg),
                    LoopContacts::Line { .. } => None,
                };
                (0..np)
                    .map(|p| {
                        if !(f[p] > LOADED_FRACTION * nominal) {
                            return Ok(None);
                        }
                        let (kin, hertz, length) = match &contacts {
                            LoopContacts::Line {
                                pair,
                                kinematics,
                                lead_crowning_mm,
                                length_mm,
                            } => {
                                let s = pair.path_position(p + 1, r.roll_deg.to_radians());
                                let c = involute_contact(kinematics, s, speed, *lead_crowning_mm)?;
                                let hertz =
                                    HertzContact::line(f[p], c.radius_x_mm, *length_mm, e_prime);
                                (c.kinematics(), hertz, *length_mm)
                            }
                            LoopContacts::Point {
                                candidates,
                                speed_scale,
                            } => {
                                let c = grid.as_ref().and_then(|g| {
                                    g.pairs
                                        .iter()
                                        .find(|c| c.teeth.map(|t| t[0]) == Some(p + 1))
                                });
                                let found = match c {
                                    Some(c) => point_contact_kinematics(
                                        c,
                                        candidates.tca.settings.approach_mm,
                                        *speed_scale,
                                        f[p],
                                        e_prime,
                                    )?,
                                    None => None,
                                };
                                let Some(o) = found else {
                                    without_ellipse.insert(format!(
                                        "{:.3}° pair {}",
                                        r.roll_deg,
                                        p + 1
                                    ));
                                    return Ok(None);
                                };
                                largest_angle = largest_angle.max(o.entrainment_angle_deg);
                                (o.kinematics, o.hertz, o.long_axis_mm)
                            }
                        };
                        let area = loaded_area(r, p + 1, kin.radius_x_mm, e_star);
                        OperatingPoint::new(
                            &kin,
                            f[p],
                            area,
                            hertz,
                            length,
                            e_prime,
                            settings.mean_pressure,
                        )
                        .map(Some)
                    })
                    .collect::<Result<Vec<_>, FlankError>>()
            })
            .collect();
        pass_forces.push(forces);
        points
    })?;
    let teeth: Vec<(usize, usize)> = (1..=np).map(|k| (k, cycle.pair.mate(k))).collect();
    let (point_contact, contact_length_mm) = match &contacts {
        LoopContacts::Line { length_mm, .. } => (false, Some(*length_mm)),
        LoopContacts::Point { .. } => (true, None),
    };
    let mut summary =
        crate::report::lubrication::write_loop_outputs(&crate::report::lubrication::LoopOutputs {
            out,
            angles,
            result: &result,
            pass_forces: &pass_forces,
            teeth: &teeth,
            settings,
            lubricant: lub,
            pitch_deg: cycle.pair.pinion().angular_pitch().to_degrees(),
            speed_rpm: speed,
            torque_nmm: scene.load.torque_nmm,
            poisson: 0.5 * (scene.pinion_material.poisson + scene.gear_material.poisson),
            reduced_modulus_mpa: e_prime,
            contact_length_mm,
            point_contact,
        })?;
    if point_contact {
        summary.notes.push(format!(
            "point contacts: R_x, R_y are the effective radii along and across the entrainment, which runs at up to {largest_angle:.1}° to the contact ellipse's minor axis (Chittenden et al. 1985)"
        ));
    }
    if !without_ellipse.is_empty() {
        summary.notes.push(format!(
            "{} loaded pair position(s) without a contact ellipse (edge contact) have no EHL operating point and keep μ₀ = {}: {}",
            without_ellipse.len(),
            settings.initial_mu,
            without_ellipse.into_iter().collect::<Vec<_>>().join(", ")
        ));
    }
    let flagged: Vec<String> = current
        .iter()
        .filter(|r| !r.kkt_within_tolerance)
        .map(|r| format!("{}°", r.roll_deg))
        .collect();
    summary.ltca = Some(LtcaLoopFigures {
        solver: "ltca",
        friction_model: ls.model,
        contact_area: "Σ 2aᵢwᵢ over the pair's loaded LTCA points: Hertz half-width of each point's load per length on its TCA radius (tip corners: on the operating point's R_x), times the length it represents",
        wet_pass_s: pass_s,
        loop_s: t0.elapsed().as_secs_f64(),
        final_pass_flagged: flagged,
    });
    Ok(LubricatedLtca {
        results: current,
        result,
        summary,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene() -> Scene {
        crate::scene::read_scene(
            &Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("papers/seed002-spur/scene_lubricated.toml"),
        )
        .unwrap()
    }

    fn with_ltca_mu(mu: f64) -> Scene {
        let mut s = scene();
        s.analyses.ltca = Some(crate::scene::LtcaAnalysis {
            friction_mu: Some(mu),
            ..Default::default()
        });
        s
    }

    /// The point-contact operating point against the closed form: the
    /// point TCA of seed 002's spur pair with 20 µm lead crowning on the
    /// pinion (a point contact with R_y = b²/(8 C_β)), at every position
    /// and pair in flank contact, against [`involute_contact`] at the
    /// pair's path position. Bands set from the TCA's accuracy before the
    /// run: curvatures from second derivatives of the surfaces (R_x, R_y
    /// within 0.5 %), speeds from the exact rigid-body motion (u within
    /// 1e-6 relative, |v_s| within 1e-6 u); entrainment along the minor
    /// axis of a spur contact (θ < 0.5°).
    #[test]
    fn point_contact_operating_point_matches_the_involute_closed_form() {
        use crate::geometry::gear_pair::GearPair;
        use crate::tca::point_contact::{point_tca, PointTcaSettings};
        let dir = std::env::temp_dir().join(format!("flank-lub-point-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let text = std::fs::read_to_string(
            Path::new(env!("CARGO_MANIFEST_DIR")).join("papers/seed002-spur/scene.toml"),
        )
        .unwrap()
            + "\n[pinion.micro]\nlead_crowning_um = 20.0\n";
        let path = dir.join("scene.toml");
        std::fs::write(&path, text).unwrap();
        let scene = crate::scene::read_scene(&path).unwrap();
        let speed = scene.load.speed_rpm;
        let line = scene.gear_pair().unwrap();
        let cyl = scene.cylindrical("this test").unwrap();
        let kin = MeshKinematics::new(&cyl.pair, scene.mesh.teeth_in_sector as usize).unwrap();
        let settings = PointTcaSettings {
            edges: false,
            search_directions: 0,
            speed_rpm: speed,
            ..Default::default()
        };
        let pair: &dyn GearPair = line.as_ref();
        let tca = point_tca(pair, &settings).unwrap();
        let e_prime = reduced_modulus([206_000.0; 2], [0.3; 2]);
        let (mut checked, mut worst) = (0, [0.0f64; 5]);
        for pos in &tca.positions {
            for c in pos
                .pairs
                .iter()
                .filter(|c| c.system == ContactSystem::Flank)
            {
                let Some([k, _]) = c.teeth else { continue };
                let s = line.path_position(k, pos.roll_rad);
                let exact = involute_contact(&kin, s, speed, [0.02, 0.0]).unwrap();
                if exact.outside_path {
                    continue;
                }
                let Some(o) =
                    point_contact_kinematics(c, settings.approach_mm, 1.0, 1000.0, e_prime)
                        .unwrap()
                else {
                    continue;
                };
                let k = o.kinematics;
                let rel = |a: f64, b: f64| (a - b).abs() / b.abs();
                let d = [
                    rel(k.radius_x_mm, exact.radius_x_mm),
                    rel(k.radius_y_mm, exact.radius_y_mm),
                    rel(k.entraining_speed_mm_s, exact.entraining_speed_mm_s),
                    (k.sliding_speed_mm_s - exact.sliding_speed_mm_s.abs()).abs()
                        / exact.entraining_speed_mm_s,
                    o.entrainment_angle_deg,
                ];
                for (w, x) in worst.iter_mut().zip(d) {
                    *w = w.max(x);
                }
                checked += 1;
            }
        }
        println!(
            "VERIFY point-contact operating point vs involute closed form ({checked} contacts): R_x {:.2e}, R_y {:.2e}, u {:.2e}, v_s {:.2e} (of u), entrainment angle {:.3}°",
            worst[0], worst[1], worst[2], worst[3], worst[4]
        );
        assert!(checked >= 20, "{checked} contacts checked");
        assert!(worst[0] <= 5e-3 && worst[1] <= 5e-3, "{worst:?}");
        assert!(worst[2] <= 1e-6 && worst[3] <= 1e-6, "{worst:?}");
        assert!(worst[4] < 0.5, "{worst:?}");
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn settings_and_contradictions() {
        let o = LtcaOptions::default();
        let l = loop_settings(&scene(), &o).unwrap().unwrap();
        assert_eq!(l.settings.initial_mu, 0.05);
        assert_eq!(l.model, FrictionModel::Sliding);
        let dry = l.dry_options(&o);
        assert_eq!(
            (dry.friction_mu, dry.friction_model),
            (Some(0.05), Some(FrictionModel::Sliding))
        );
        // the model may be chosen
        let o2 = LtcaOptions {
            friction_model: Some(FrictionModel::Standstill),
            ..Default::default()
        };
        assert_eq!(
            loop_settings(&scene(), &o2).unwrap().unwrap().model,
            FrictionModel::Standstill
        );
        // the same μ₀ twice is no contradiction; without initial_mu the
        // LTCA's friction_mu is μ₀
        assert!(loop_settings(&with_ltca_mu(0.05), &o).is_ok());
        let mut s = with_ltca_mu(0.07);
        s.analyses.lubrication.as_mut().unwrap().initial_mu = None;
        assert_eq!(
            loop_settings(&s, &o).unwrap().unwrap().settings.initial_mu,
            0.07
        );
        // contradictions name their keys and options
        let cases: [(Scene, LtcaOptions, &[&str]); 3] = [
            (
                scene(),
                LtcaOptions {
                    friction_mu: Some(0.05),
                    ..Default::default()
                },
                &["--friction-mu", "[analyses.lubrication]", "initial_mu"],
            ),
            (
                with_ltca_mu(0.0),
                o.clone(),
                &["friction_mu = 0", "frictionless"],
            ),
            (
                with_ltca_mu(0.03),
                o.clone(),
                &["friction_mu = 0.03", "initial_mu = 0.05"],
            ),
        ];
        for (s, o, words) in cases {
            let e = loop_settings(&s, &o).unwrap_err().to_string();
            for w in words {
                assert!(e.contains(w), "{e} lacks {w}");
            }
        }
        // no loop without [analyses.lubrication]
        let mut s = scene();
        s.analyses.lubrication = None;
        assert!(loop_settings(&s, &o).unwrap().is_none());
    }
}
