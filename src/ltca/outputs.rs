//! What both LTCA drivers (spur/helical [`crate::ltca::run`], bevel/hypoid
//! [`crate::ltca::bevel`]) write and summarise of their positions: the
//! per-point CSV, the friction summary and the positions' bounded loops.

use std::path::Path;

use crate::error::FlankError;
use crate::iteration_limits::IterationLimits;
use crate::ltca::model::PositionResult;
use crate::ltca::solve_settings::LtcaFriction;

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
) -> serde_json::Value {
    let num = |r: &PositionResult, k: &str| -> f64 {
        r.friction
            .as_ref()
            .and_then(|f| f.pointer(k))
            .and_then(serde_json::Value::as_f64)
            .unwrap_or(0.0)
    };
    let max = |k: &str| results.iter().map(|r| num(r, k)).fold(0.0f64, f64::max);
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
    let within = results.iter().all(|r| r.kkt_within_tolerance);
    serde_json::json!({
        "mu": friction.mu,
        "increments": friction.options.increments,
        "max_residual": max("/max_residual/max"),
        "max_coupling": max("/coupling"),
        "within_tolerance": within,
        "cross_check_max_load_difference": friction.cross_check.then(|| max("/cross_check/load_difference")),
        "cross_check_max_rotation_difference": friction.cross_check.then(|| max("/cross_check/rotation_difference")),
        "tangential_to_normal": if pn > 0.0 { pt / pn } else { 0.0 },
        "power_loss_w": power,
        "mean_power_loss_w": mean_power,
        "input_power_w": input_w,
        "mesh_efficiency": if input_w > 0.0 { 1.0 - mean_power / input_w } else { f64::NAN },
    })
}

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
