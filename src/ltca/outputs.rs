//! What both LTCA drivers (spur/helical [`crate::ltca::run`], bevel/hypoid
//! [`crate::ltca::point_run`]) write and summarise of their positions: the
//! per-position CSVs (`ltca_cycle.csv`, `ltca_positions.csv`), the
//! per-point CSV, the friction summary and the positions' bounded loops;
//! the TE harmonics, mesh stiffness and the map over torque of a cycle
//! ([`cycle_spectra`]).

use std::path::Path;

use crate::error::FlankError;
use crate::iteration_limits::IterationLimits;
use crate::ltca::cycle::{LtcaCycle, LtcaOptions};
use crate::ltca::friction_report::FrictionReport;
use crate::ltca::harmonics::{te_harmonics, TeHarmonics};
use crate::ltca::mesh_stiffness::{mesh_stiffness, write_mesh_stiffness_csv, MeshStiffness};
use crate::ltca::model::PositionResult;
use crate::ltca::solve_settings::LtcaFriction;
use crate::ltca::summary::{FrictionSummary, LtcaStep};
use crate::ltca::torque_map::{map_rolls, torque_map, TorqueMap};
use crate::scene::Scene;
use crate::summary::Measured;

/// The bounded loops of every position together (the summary's
/// `iteration_limits`).
pub fn iteration_limits(results: &[PositionResult]) -> IterationLimits {
    let mut all = IterationLimits::new();
    for r in results {
        all.merge(&r.iteration_limits);
    }
    all
}

/// The frictional LTCA over the cycle (seeds 001/003): the Coulomb
/// solve's worst residual and, if run, the largest difference from Lemke's
/// method; the tangential-to-normal force ratio; the friction power loss
/// Σ |P_t v_s| (W) and the mesh efficiency 1 − P_loss/(T ω₁), mean over the
/// positions (seed 001 eq. for P_loss; η as Xu & Kahraman's
/// instantaneous mesh efficiency).
pub fn friction_summary(
    results: &[PositionResult],
    friction: &LtcaFriction,
    torque_nmm: f64,
) -> FrictionSummary {
    let max = |figure: fn(&FrictionReport) -> f64| {
        results
            .iter()
            .filter_map(|r| r.friction.as_ref().map(figure))
            .fold(0.0f64, f64::max)
    };
    let (pt, pn): (f64, f64) = results
        .iter()
        .flat_map(|r| &r.points)
        .fold((0.0, 0.0), |(a, b), p| {
            (a + p.friction_n.abs(), b + p.force_n)
        });
    let n = results.len().max(1) as f64;
    let power: Vec<f64> = results.iter().map(|r| r.friction_power_w).collect();
    let mean_power = power.iter().sum::<f64>() / n;
    let input_w = torque_nmm * 1e-3 * friction.pinion_speed_rad_s;
    FrictionSummary {
        mu: friction.mu,
        increments: friction.options.increments,
        max_residual: max(FrictionReport::max_residual),
        max_coupling: max(FrictionReport::coupling),
        within_tolerance: results.iter().all(|r| r.kkt_within_tolerance),
        cross_check_max_load_difference: friction
            .cross_check
            .then(|| max(|f| f.cross_check_load_difference().unwrap_or(0.0))),
        cross_check_max_rotation_difference: friction
            .cross_check
            .then(|| max(|f| f.cross_check_rotation_difference().unwrap_or(0.0))),
        tangential_to_normal: if pn > 0.0 { pt / pn } else { 0.0 },
        power_loss_w: power,
        mean_power_loss_w: mean_power,
        input_power_w: input_w,
        mesh_efficiency: if input_w > 0.0 {
            1.0 - mean_power / input_w
        } else {
            f64::NAN
        },
    }
}

/// `ltca_cycle.csv`, one row per position (every pair kind): per pair k
/// its force, share and friction; the loaded TE at the pinion (µrad) and
/// times the TE radius (µm; r_b1 of a cylindrical pair, the middle pair's
/// moment arm at roll 0 of a bevel pair); the unloaded TE; the secant mesh
/// stiffness (an empty cell where it is not defined); solver counts; and, last, both TEs at the gear (arcsec).
pub fn write_cycle_csv(path: &Path, steps: &[LtcaStep], teeth: usize) -> Result<(), FlankError> {
    use std::fmt::Write;
    let mut s = String::from("roll_deg");
    for p in 1..=teeth {
        let _ = write!(s, ",force_pair{p}_n,share_pair{p}");
    }
    for p in 1..=teeth {
        let _ = write!(s, ",friction_pair{p}_n");
    }
    s.push_str(",te_urad,te_um,unloaded_te_urad,mesh_stiffness_n_per_um,max_pressure_mpa,friction_power_w,candidates,qp_iterations,local_iterations,kkt,condition,time_s,te_arcsec,unloaded_te_arcsec\n");
    for step in steps {
        let r = &step.position;
        let _ = write!(s, "{}", r.roll_deg);
        for (f, share) in step.pair_force_n.iter().zip(&step.load_share) {
            let _ = write!(s, ",{f},{share}");
        }
        for x in &step.pair_friction_n {
            let _ = write!(s, ",{x}");
        }
        let _ = writeln!(
            s,
            ",{},{},{},{},{},{},{},{},{},{:e},{},{},{},{}",
            r.te_urad,
            r.te_um,
            r.unloaded_te_urad,
            // empty where not defined (no deflection), as the torque-map CSVs
            Some(r.mesh_stiffness_n_per_um)
                .filter(|k| k.is_finite())
                .map_or(String::new(), |k| k.to_string()),
            r.max_pressure_mpa,
            r.friction_power_w,
            r.candidates,
            r.qp_iterations,
            r.local_iterations,
            r.kkt_max,
            r.condition.map_or(String::new(), |c| format!("{c:e}")),
            r.time_s,
            step.te_arcsec,
            step.unloaded_te_arcsec
        );
    }
    crate::atomic_file::write(path, s)
}

/// `ltca_positions.csv`, one row per position and pair k of the sector
/// (every pair kind): its teeth, force, share, largest pressure, friction
/// force and the position's loaded TE at the gear (arcsec) and, last, at
/// the pinion (µrad). `mates[k − 1]` is the gear tooth of pinion tooth k.
pub fn write_positions_csv(
    path: &Path,
    steps: &[LtcaStep],
    mates: &[usize],
) -> Result<(), FlankError> {
    use std::fmt::Write;
    let mut s = String::from(
        "roll_deg,pair,pinion_tooth,gear_tooth,force_n,load_share,max_pressure_mpa,te_arcsec,friction_n,te_urad\n",
    );
    for step in steps {
        let r = &step.position;
        for (p, (&f, &mate)) in step.pair_force_n.iter().zip(mates).enumerate() {
            let _ = writeln!(
                s,
                "{},{},{},{},{:e},{:e},{:e},{:e},{:e},{:e}",
                r.roll_deg,
                p + 1,
                p + 1,
                mate,
                f,
                step.load_share[p],
                step.pair_max_pressure_mpa(p + 1),
                step.te_arcsec,
                step.pair_friction_n[p],
                r.te_urad
            );
        }
    }
    crate::atomic_file::write(path, s)
}

/// `ltca_points.csv`, one row per candidate point of every position.
pub fn write_points_csv(path: &Path, results: &[PositionResult]) -> Result<(), FlankError> {
    use std::fmt::Write;
    let mut s = String::from("roll_deg,pinion_tooth,gear_tooth,kind,along_mm,x_mm,y_mm,z_mm,separation_um,force_n,load_per_length_n_per_mm,pressure_mpa,half_width_mm,gap_um,friction_n,state,sliding_velocity_m_s\n");
    for r in results {
        for p in &r.points {
            let (k, m, kind) = &r.lines[p.line];
            let _ = writeln!(
                s,
                "{},{k},{m},{kind},{},{},{},{},{},{},{},{},{},{},{},{},{}",
                r.roll_deg,
                p.along_mm,
                p.position[0],
                p.position[1],
                p.position[2],
                p.separation_mm * 1e3,
                p.force_n,
                p.load_per_length,
                p.pressure_mpa,
                p.half_width_mm,
                p.gap_mm * 1e3,
                p.friction_n,
                p.state,
                p.sliding_velocity_m_s
            );
        }
    }
    crate::atomic_file::write(path, s)
}

/// What a cycle reports of its TE spectrum and mesh stiffness
/// ([`cycle_spectra`]).
pub struct CycleSpectra {
    pub te_harmonics: Measured<TeHarmonics>,
    pub mesh_stiffness: Measured<MeshStiffness>,
    pub torque_map: Option<TorqueMap>,
    /// Files written (`ltca_mesh_stiffness.csv`, the map's).
    pub files: Vec<String>,
}

/// The pinion torques of the map: the options', else the scene's
/// `[analyses.ltca] torques_nm` (`None`: no map).
pub fn map_torques(scene: &Scene, options: &LtcaOptions) -> Option<Vec<f64>> {
    options.torques_nm.clone().or_else(|| {
        scene
            .analyses
            .ltca
            .as_ref()
            .and_then(|a| a.torques_nm.clone())
    })
}

/// The face width a cylindrical pair's mesh stiffness is divided by: the
/// smaller of the two (mm); `None` for a bevel/hypoid pair.
pub fn stiffness_face_width(scene: &Scene) -> Option<f64> {
    scene
        .cylindrical("the mesh stiffness per unit face width")
        .ok()
        .map(|c| c.pair.pinion.face_width.min(c.pair.gear.face_width))
}

/// Of a solved cycle (`results` at `rolls`, `gaps` the rolls without any
/// contact): the TE harmonics and the mesh stiffness's mean and variation
/// where the rolls are equal steps over whole pitches (else the reason),
/// `ltca_mesh_stiffness.csv` (every position) and, if torques are asked,
/// the map over torque; every file in `out`.
pub fn cycle_spectra(
    cycle: &LtcaCycle,
    scene: &Scene,
    options: &LtcaOptions,
    results: &[PositionResult],
    gaps: &[f64],
    out: &Path,
) -> Result<CycleSpectra, FlankError> {
    let pitch = cycle.pair.pinion().angular_pitch().to_degrees();
    let face = stiffness_face_width(scene);
    let mut sorted: Vec<&PositionResult> = results.iter().collect();
    sorted.sort_by(|a, b| a.roll_deg.total_cmp(&b.roll_deg));
    let rolls: Vec<f64> = sorted.iter().map(|r| r.roll_deg).collect();
    let te: Vec<f64> = sorted.iter().map(|r| r.te_urad).collect();
    let harmonics = if gaps.is_empty() {
        te_harmonics(
            &rolls,
            &te,
            pitch,
            cycle.bodies.te_radius_mm,
            cycle.pair.ratio(),
        )
    } else {
        Err(format!(
            "no tooth pair of the sector is in contact at {} positions: the pitch is not sampled whole",
            gaps.len()
        ))
    };
    let stiffness = match &harmonics {
        Ok(h) => {
            let sample: Vec<PositionResult> =
                sorted[..h.positions].iter().map(|r| (*r).clone()).collect();
            mesh_stiffness(&sample, face, cycle.bodies.nominal_moment_arm_mm)
        }
        Err(e) => Err(format!("needs the positions of the harmonics: {e}")),
    };
    let owned: Vec<PositionResult> = sorted.iter().map(|r| (*r).clone()).collect();
    write_mesh_stiffness_csv(&out.join("ltca_mesh_stiffness.csv"), &owned, pitch, face)?;
    let mut files = vec!["ltca_mesh_stiffness.csv".to_string()];
    let torque_map = match map_torques(scene, options) {
        Some(t) => {
            let rolls = map_rolls(cycle)?;
            let m = torque_map(cycle, &t, &rolls, face, out)?;
            files.extend(m.files.iter().cloned());
            Some(m)
        }
        None => None,
    };
    Ok(CycleSpectra {
        te_harmonics: Measured::from_result(harmonics),
        mesh_stiffness: Measured::from_result(stiffness),
        torque_map,
        files,
    })
}
