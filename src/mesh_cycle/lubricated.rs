//! The wet–dry loop of seed 002 on the FE mesh cycle (`flank run` with
//! `[analyses.lubrication]`): the dry pass is the run's own cycle at
//! μ₀ = `friction_mu`; per loaded tooth pair and position the operating
//! point (closed-form involute R_x, R_y, u, v_s; W and P̄ from the FE
//! contact forces and patch area, seed 002 eqs. 10–11) goes through the EHL
//! model ([`crate::lubrication`]); the wet passes solve every position again
//! with that μ per tooth pair ([`MeshCycle::solve_with_mu`]).
//!
//! Outputs, the same as the LTCA variant's: [`crate::report::lubrication`].

use std::path::Path;

use crate::error::FlankError;
use crate::geometry::cylindrical::MeshKinematics;
use crate::lubrication::{
    involute_contact, reduced_modulus, wet_dry_loop, HertzContact, LoopResult, LoopSettings,
    OperatingPoint,
};
use crate::mesh_cycle::cycle::{MeshCycle, StepResult};

use crate::scene::Scene;

/// The loop of the scene's `[analyses.lubrication]` for `flank run` (`None`
/// without it). The loop sets μ itself: `--friction-mu` (`cli_mu`) is
/// refused, as in `flank ltca`; the dry pass runs at `initial_mu`, else at
/// a positive `[analyses.contact] friction_mu`, else at 0.05 (seed 002).
pub fn loop_settings(
    scene: &Scene,
    cli_mu: Option<f64>,
) -> Result<Option<LoopSettings>, FlankError> {
    let Some(l) = &scene.analyses.lubrication else {
        return Ok(None);
    };
    if scene.lubricant.is_none() {
        return Err(FlankError::Model(
            "[analyses.lubrication] needs a [lubricant] table".into(),
        ));
    }
    if let Some(mu) = cli_mu {
        return Err(FlankError::Model(format!(
            "--friction-mu {mu}: not with [analyses.lubrication] in {}: the wet–dry loop sets μ itself (the dry pass at `initial_mu`, then μ per position and tooth pair from the EHL model); give the dry pass's μ as [analyses.lubrication] initial_mu",
            scene.source.display()
        )));
    }
    let scene_mu = scene
        .analyses
        .contact
        .as_ref()
        .and_then(|c| c.friction_mu)
        .filter(|&m| m > 0.0);
    let s = LoopSettings {
        film: l.film.unwrap_or_default(),
        tolerance: l.tolerance.unwrap_or(0.005),
        max_iterations: l.max_iterations.unwrap_or(10),
        initial_mu: l.initial_mu.or(scene_mu).unwrap_or(0.05),
        composite_roughness_mm: l.composite_roughness_um.map(|r| r * 1e-3),
        mean_pressure: l.mean_pressure.unwrap_or_default(),
    };
    crate::lubrication::wet_dry::check_settings(&s)?;
    Ok(Some(s))
}

/// The figures of the loop for summary.json, and the final pass's steps.
pub struct LubricatedCycle {
    pub steps: Vec<StepResult>,
    pub result: LoopResult,
    pub summary: crate::report::lubrication::LubricationSummary,
}

/// Runs the loop from the dry pass `dry` (solved at μ₀) and writes its files to `out`.
pub fn lubricated_cycle(
    cycle: &MeshCycle,
    scene: &Scene,
    settings: &LoopSettings,
    dry: Vec<StepResult>,
    out: &Path,
) -> Result<LubricatedCycle, FlankError> {
    let cyl = scene.cylindrical("the spur/helical FE mesh cycle")?;
    let lub = scene.lubricant.as_ref().ok_or_else(|| {
        FlankError::Model("the lubricated mesh cycle needs a [lubricant] table".into())
    })?;
    if (cycle.settings.friction_mu - settings.initial_mu).abs() > 0.0 {
        return Err(FlankError::Model(format!(
            "the dry pass ran at μ = {} but the loop's μ₀ is {}",
            cycle.settings.friction_mu, settings.initial_mu
        )));
    }
    let kin = MeshKinematics::new(&cyl.pair, cycle.pair.teeth.len())?;
    let crowning = [0, 1].map(|i| cyl.micro[i].as_ref().map_or(0.0, |m| m.lead_crowning));
    let e_prime = reduced_modulus(
        [scene.pinion_material.young, scene.gear_material.young],
        [scene.pinion_material.poisson, scene.gear_material.poisson],
    );
    let length = kin.face_width[0].min(kin.face_width[1]) / kin.base_helix_angle.cos();
    let speed = scene.load.speed_rpm;
    let angles: Vec<f64> = dry.iter().map(|s| s.roll_deg).collect();
    let np = cycle.pair.teeth.len();
    let mut current = dry;
    let mut pass_forces: Vec<Vec<Vec<f64>>> = Vec::new();
    let result = wet_dry_loop(lub, settings, angles.len(), np, |pass, mu| {
        if pass > 0 {
            current = angles
                .iter()
                .zip(mu)
                .map(|(&a, m)| cycle.solve_with_mu(a, Some(m)).map(|s| s.step))
                .collect::<Result<_, _>>()?;
        }
        pass_forces.push(current.iter().map(|s| s.pair_force_n.clone()).collect());
        current
            .iter()
            .map(|st| {
                (0..np)
                    .map(|p| {
                        if !cycle.loaded(st, p) || !(st.patch[p].area_mm2 > 0.0) {
                            return Ok(None);
                        }
                        let c =
                            involute_contact(&kin, st.kinematic_position_mm[p], speed, crowning)?;
                        OperatingPoint::new(
                            &c.kinematics(),
                            st.pair_force_n[p],
                            st.patch[p].area_mm2,
                            HertzContact::line(st.pair_force_n[p], c.radius_x_mm, length, e_prime),
                            length,
                            e_prime,
                            settings.mean_pressure,
                        )
                        .map(Some)
                    })
                    .collect::<Result<Vec<_>, FlankError>>()
            })
            .collect()
    })?;
    let teeth = cycle.pair.teeth.clone();
    let summary =
        crate::report::lubrication::write_loop_outputs(&crate::report::lubrication::LoopOutputs {
            out,
            angles: &angles,
            result: &result,
            pass_forces: &pass_forces,
            teeth: &teeth,
            settings,
            lubricant: lub,
            pitch_deg: cycle.gear_pair.pinion().angular_pitch().to_degrees(),
            speed_rpm: speed,
            torque_nmm: scene.load.torque_nmm,
            poisson: 0.5 * (scene.pinion_material.poisson + scene.gear_material.poisson),
            reduced_modulus_mpa: e_prime,
            contact_length_mm: Some(length),
            point_contact: false,
        })?;
    Ok(LubricatedCycle {
        steps: current,
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

    /// `--friction-mu` is refused with the loop (it used to become μ₀
    /// silently); without it the dry pass runs at the scene's μ₀.
    #[test]
    fn the_loop_refuses_a_command_line_mu() {
        let s = scene();
        let e = loop_settings(&s, Some(0.08)).unwrap_err().to_string();
        assert!(
            e.contains("--friction-mu 0.08") && e.contains("[analyses.lubrication]"),
            "{e}"
        );
        assert!(e.contains("initial_mu"), "{e}");
        let l = loop_settings(&s, None).unwrap().unwrap();
        assert_eq!(l.initial_mu, 0.05);
        let mut dry = s.clone();
        dry.analyses.lubrication = None;
        assert!(loop_settings(&dry, Some(0.08)).unwrap().is_none());
    }
}
