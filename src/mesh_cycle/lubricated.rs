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
    involute_contact, reduced_modulus, wet_dry_loop, LoopResult, LoopSettings, OperatingPoint,
};
use crate::mesh_cycle::run::{MeshCycle, StepResult};
use crate::scene::Scene;

/// The figures of the loop for summary.json, and the final pass's steps.
pub struct LubricatedCycle {
    pub steps: Vec<StepResult>,
    pub result: LoopResult,
    pub summary: serde_json::Value,
}

/// Runs the loop from the dry pass `dry` (solved at μ₀) and writes its files to `out`.
pub fn lubricated_cycle(
    cycle: &MeshCycle,
    scene: &Scene,
    settings: &LoopSettings,
    dry: Vec<StepResult>,
    out: &Path,
) -> Result<LubricatedCycle, FlankError> {
    let lub = scene.lubricant.as_ref().ok_or_else(|| {
        FlankError::Model("the lubricated mesh cycle needs a [lubricant] table".into())
    })?;
    if (cycle.settings.friction_mu - settings.initial_mu).abs() > 0.0 {
        return Err(FlankError::Model(format!(
            "the dry pass ran at μ = {} but the loop's μ₀ is {}",
            cycle.settings.friction_mu, settings.initial_mu
        )));
    }
    let kin = MeshKinematics::new(&scene.pair, cycle.pair.teeth.len())?;
    let crowning = [0, 1].map(|i| scene.micro[i].as_ref().map_or(0.0, |m| m.lead_crowning));
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
                            &c,
                            st.pair_force_n[p],
                            st.patch[p].area_mm2,
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
            contact_length_mm: length,
        })?;
    Ok(LubricatedCycle {
        steps: current,
        result,
        summary,
    })
}
