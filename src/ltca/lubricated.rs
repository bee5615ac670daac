//! The wet–dry loop of seed 002 through the frictional spur/helical LTCA
//! (`flank ltca` on a scene with `[lubricant]` and `[analyses.lubrication]`):
//! the dry pass is the LTCA cycle at μ₀ = `initial_mu`; per loaded tooth
//! pair and position the operating point goes through the EHL model of
//! [`crate::lubrication`]; the wet passes solve every position again with
//! that μ per tooth pair ([`LtcaSettings::pair_mu`], μ per candidate point
//! in [`crate::ltca::friction::FrictionProblem::point_mu`]).
//!
//! The operating point of pair p at a position:
//! * W: the LTCA's normal force of the pair (Σ over its points);
//! * R_x, R_y, u, v_s: the closed-form involute contact at the pair's
//!   kinematic path position ([`crate::lubrication::involute_contact`]), as
//!   the FE variant ([`crate::mesh_cycle::lubricated`]);
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
use crate::load_sharing::LOADED_FRACTION;
use crate::ltca::cycle::{LtcaCycle, LtcaOptions};
use crate::ltca::local::hertz_line;
use crate::ltca::model::PositionResult;
use crate::ltca::solve_settings::LtcaSettings;
use crate::lubrication::{
    involute_contact, reduced_modulus, wet_dry_loop, LoopResult, LoopSettings, OperatingPoint,
};
use crate::report::lubrication::{LtcaLoopFigures, LubricationSummary};
use crate::scene::Scene;
use crate::settings::FrictionModel;

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
    let cyl = scene.cylindrical("the spur/helical LTCA")?;
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
    let line_pair = cycle.line_pair()?;
    let kin = MeshKinematics::new(&cyl.pair, np)?;
    let crowning = [0, 1].map(|i| cyl.micro[i].as_ref().map_or(0.0, |m| m.lead_crowning));
    let e_prime = reduced_modulus(
        [scene.pinion_material.young, scene.gear_material.young],
        [scene.pinion_material.poisson, scene.gear_material.poisson],
    );
    let length = kin.face_width[0].min(kin.face_width[1]) / kin.base_helix_angle.cos();
    let speed = scene.load.speed_rpm;
    let nominal = cycle.nominal_force();
    let e_star = cycle.bodies.contact_modulus;
    let mut current = dry;
    let mut pass_forces: Vec<Vec<Vec<f64>>> = Vec::new();
    let mut pass_s: Vec<f64> = Vec::new();
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
                (0..np)
                    .map(|p| {
                        if !(f[p] > LOADED_FRACTION * nominal) {
                            return Ok(None);
                        }
                        let s = line_pair.path_position(p + 1, r.roll_deg.to_radians());
                        let c = involute_contact(&kin, s, speed, crowning)?;
                        let area = loaded_area(r, p + 1, c.radius_x_mm, e_star);
                        OperatingPoint::new(&c, f[p], area, length, e_prime, settings.mean_pressure)
                            .map(Some)
                    })
                    .collect::<Result<Vec<_>, FlankError>>()
            })
            .collect();
        pass_forces.push(forces);
        points
    })?;
    let teeth: Vec<(usize, usize)> = (1..=np).map(|k| (k, cycle.pair.mate(k))).collect();
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
            contact_length_mm: length,
        })?;
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
