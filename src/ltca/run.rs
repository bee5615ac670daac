//! The `flank ltca` run of a scene: for a bevel/hypoid pair
//! [`crate::ltca::point_run`]; for a spur/helical pair the cycle of
//! [`crate::ltca::cycle::LtcaCycle`] over the scene's roll angles (extended
//! while the middle pair is loaded at an end), the wet–dry loop when the
//! scene asks for it ([`crate::ltca::lubricated`]), and the outputs:
//! `ltca_cycle.csv` and `ltca_positions.csv` (the files of every pair kind,
//! [`crate::ltca::outputs`]), `ltca_points.csv` (load distribution along
//! every contact line), `summary.json` (the serialization of
//! [`crate::ltca::summary::LtcaResult`]) and plots of the force per tooth
//! pair and the TE (SVG, PNG).
//!
//! Pairs are numbered as in FE contact ([`crate::mesh_cycle`]): pair p is
//! pinion tooth p + 1 with its mate, so the two runs compare column by
//! column.

use crate::error::FlankError;
use crate::fem::static_analysis::peak_memory_mb;
use crate::load_sharing::LOADED_FRACTION;
use crate::ltca::cycle::{roll_angles, LtcaCycle, LtcaOptions};
use crate::ltca::lubricated::LubricatedSettings;
use crate::ltca::model::PositionResult;
use crate::ltca::outputs::{
    friction_summary, iteration_limits, write_cycle_csv, write_points_csv, write_positions_csv,
};
use crate::ltca::point_run::run_point;
use crate::ltca::summary::peak_to_peak;
use crate::ltca::summary::{
    CylindricalLtcaSummary, KindSummary, LtcaFiles, LtcaResult, LtcaStep, LtcaSummary,
};
use crate::scene::{read_scene, Scene};
use std::path::Path;
use std::time::Instant;

/// `flank ltca SCENE`: reads the scene and runs [`run`].
pub fn run_scene(path: &Path, options: &LtcaOptions) -> Result<LtcaResult, FlankError> {
    let scene = read_scene(path)?;
    run(&scene, options)
}

/// The LTCA over the scene's mesh cycle, for any pair kind; writes the
/// outputs into `options.out` and returns the summary. Every option is
/// taken from `options`, else the scene's `[analyses.ltca]`, else its
/// default ([`LtcaCycle::new`]); a bevel/hypoid scene runs
/// [`crate::ltca::point_run::run_point`]. On `options.threads` threads (0:
/// rayon's global pool); the answer is the same on any number (fixed
/// summation orders).
pub fn run(scene: &Scene, options: &LtcaOptions) -> Result<LtcaResult, FlankError> {
    // the wet–dry loop (seed 002): the cycle is its dry pass at μ₀
    let lubricated = crate::ltca::lubricated::loop_settings(scene, options)?;
    // the map's torques checked before anything is computed
    if let Some(t) = crate::ltca::outputs::map_torques(scene, options) {
        crate::ltca::torque_map::check_torques(&t, "--torques").map_err(FlankError::Model)?;
        if lubricated.is_some() {
            return Err(FlankError::Model(
                "torques_nm (the map over torque) runs the dry LTCA: it is refused with [analyses.lubrication], whose wet–dry loop sets μ at the scene's torque".into(),
            ));
        }
    }
    let dry_options;
    let options = match &lubricated {
        Some(l) => {
            dry_options = l.dry_options(options);
            &dry_options
        }
        None => options,
    };
    crate::fem::solver::with_threads(options.threads, || {
        if scene.is_bevel() {
            run_point(scene, options, lubricated.as_ref())
        } else {
            run_line(scene, options, lubricated.as_ref())
        }
    })
}

/// The run of a spur/helical scene (module docs), with the wet–dry loop's
/// settings if it runs (`options` are then its dry pass's).
fn run_line(
    scene: &Scene,
    options: &LtcaOptions,
    lubricated: Option<&LubricatedSettings>,
) -> Result<LtcaResult, FlankError> {
    let t_total = Instant::now();
    let out = &options.out;
    std::fs::create_dir_all(out).map_err(|e| FlankError::io(out, e))?;
    let cycle = LtcaCycle::new(scene, options)?;
    let line_pair = cycle.line_pair()?;
    let (mut angles, default_range) = roll_angles(scene, line_pair.as_ref(), options);
    let mid = cycle.pair.middle() - 1;
    let t_cycle = Instant::now();
    let mut results = cycle.solve_cycle(&angles)?;
    let cycle_s = t_cycle.elapsed().as_secs_f64();
    let positions_solved = results.len();
    let mut extended = 0;
    if default_range {
        let step = scene
            .analyses
            .ltca
            .as_ref()
            .and_then(|a| a.roll_step_deg)
            .unwrap_or(1.0);
        let limit = (cycle.pair.pinion().angular_pitch().to_degrees() / step).ceil() as usize;
        for _ in 0..limit {
            if !cycle.loaded(&results[0], mid) {
                break;
            }
            let a = angles[0] - step;
            results.insert(0, cycle.solve(a)?);
            angles.insert(0, a);
            extended += 1;
        }
        for _ in 0..limit {
            if !cycle.loaded(&results[results.len() - 1], mid) {
                break;
            }
            let a = angles[angles.len() - 1] + step;
            results.push(cycle.solve(a)?);
            angles.push(a);
            extended += 1;
        }
    }
    let mut notes = scene.material_warnings();
    notes.extend(scene.sector_warning(&angles));
    let limits = cycle.loaded_limits(&angles, &results)?;
    if limits.is_none() {
        notes.push("contact ratio not measured: the roll angles do not cover the middle pair's whole engagement with an unloaded position before and after".to_string());
    }
    let mut lubrication = None;
    if let Some(l) = lubricated {
        let dry = std::mem::take(&mut results);
        let lc = crate::ltca::lubricated::lubricated_cycle(&cycle, scene, l, dry, &angles, out)?;
        results = lc.results;
        notes.push(format!(
            "lubricated: the contact-limit bisection ran at the dry pass's μ₀ = {}; the positions, and the forces and power of `friction` (whose `mu` is μ₀; its power is the mean over all positions, the `lubrication` one over one pitch), are the last wet pass's, solved with μ per tooth pair (lubrication_passes.csv)",
            l.settings.initial_mu
        ));
        lubrication = Some(lc.summary);
    }
    let pitch_deg = cycle.pair.pinion().angular_pitch().to_degrees();
    let contact_ratio = limits.map(|(s, e)| (e - s) / pitch_deg);
    let nominal = cycle.nominal_force();
    let np = cycle.pair.sector_teeth();
    let forces: Vec<Vec<f64>> = results.iter().map(|r| cycle.pair_forces(r)).collect();
    let single: Vec<usize> = (0..results.len())
        .filter(|&i| (0..np).all(|p| (p == mid) == (forces[i][p] > LOADED_FRACTION * nominal)))
        .collect();
    let single_pair_force_n = (!single.is_empty())
        .then(|| single.iter().map(|&i| forces[i][mid]).sum::<f64>() / single.len() as f64);
    let flagged: Vec<String> = results
        .iter()
        .filter(|r| !r.kkt_within_tolerance)
        .map(|r| {
            format!(
                "{}°: KKT residual {:.2e} above tolerance",
                r.roll_deg, r.kkt_max
            )
        })
        .collect();
    let ratio = cycle.pair.ratio();
    let steps: Vec<LtcaStep> = results
        .iter()
        .map(|r| LtcaStep::new(r.clone(), np, ratio))
        .collect();
    let mates: Vec<usize> = (1..=np).map(|k| cycle.pair.mate(k)).collect();
    write_cycle_csv(&out.join("ltca_cycle.csv"), &steps, np)?;
    write_positions_csv(&out.join("ltca_positions.csv"), &steps, &mates)?;
    write_points_csv(&out.join("ltca_points.csv"), &results)?;
    let teeth: Vec<(usize, usize)> = (1..=np).map(|k| (k, cycle.pair.mate(k))).collect();
    let series: Vec<Vec<f64>> = (0..np)
        .map(|p| forces.iter().map(|f| f[p]).collect())
        .collect();
    let te: Vec<f64> = results.iter().map(|r| r.te_urad).collect();
    let plots = crate::report::cycle_plot::plot_cycle(
        out,
        "ltca_",
        &angles,
        &series,
        &te,
        &teeth,
        nominal,
        line_pair.transmission_error_radius(),
    )
    .unwrap_or_else(|e| {
        notes.push(format!("plots not written: {e}"));
        Vec::new()
    });
    let pattern = crate::ltca::pattern::plot_contact_pattern(out, &results, cycle.pair.middle(), {
        let (z0, z1) = cycle.pair.pinion().blank().axial_range;
        z1 - z0
    })
    .unwrap_or_else(|e| {
        notes.push(format!("contact pattern not plotted: {e}"));
        Vec::new()
    });
    let spectra = crate::ltca::outputs::cycle_spectra(&cycle, scene, options, &results, &[], out)?;
    let loops = iteration_limits(&results);
    notes.extend(loops.warnings());
    // the positions run side by side: the wall time of the cycle over them
    // (the extension and the bisection after it, one position at a time,
    // are not in it)
    let time_per_position_s = cycle_s / positions_solved.max(1) as f64;
    let worst = |f: fn(&PositionResult) -> f64| results.iter().map(f).fold(0.0f64, f64::max);
    let te_arcsec: Vec<f64> = steps.iter().map(|s| s.te_arcsec).collect();
    let summary = LtcaSummary {
        header: scene.summary_header(),
        analysis: "ltca_mesh_cycle",
        positions: results.len(),
        tooth_pairs: teeth,
        te_peak_to_peak_urad: peak_to_peak(&te),
        te_peak_to_peak_arcsec: peak_to_peak(&te_arcsec),
        max_pressure_mpa: worst(|r| r.max_pressure_mpa),
        te_harmonics: spectra.te_harmonics,
        mesh_stiffness: spectra.mesh_stiffness,
        torque_map: spectra.torque_map,
        max_kkt: worst(|r| r.kkt_max),
        iteration_limits: loops,
        friction: cycle
            .settings
            .friction
            .as_ref()
            .map(|f| friction_summary(&results, f, cycle.torque)),
        lubrication,
        settings: cycle.settings.clone(),
        cycle_s,
        time_per_position_s,
        total_s: t_total.elapsed().as_secs_f64(),
        peak_memory_mb: peak_memory_mb(),
        notes,
        kind: KindSummary::Cylindrical(Box::new(CylindricalLtcaSummary {
            contact_ratio,
            contact_ratio_kinematic: line_pair.kinematic_contact_ratio(),
            middle_pair_loaded_deg: limits.map(|(s, e)| [s, e]),
            single_pair_force_n,
            nominal_force_n: nominal,
            single_pair_force_error: single_pair_force_n.map(|f| f / nominal - 1.0),
            extension_positions: extended,
            points_per_line: cycle.points_per_line,
            setup: cycle.setup.clone(),
            max_condition: results.iter().filter_map(|r| r.condition).reduce(f64::max),
            max_condition_loaded: results
                .iter()
                .filter_map(|r| r.condition_loaded)
                .reduce(f64::max),
            tensor_backward_error: cycle.setup.backward_error,
            warnings: results
                .iter()
                .flat_map(|r| {
                    r.warnings
                        .iter()
                        .map(move |w| format!("{:.4}°: {w}", r.roll_deg))
                })
                .collect(),
            kkt_flagged: flagged,
            files: LtcaFiles {
                csv: ["ltca_cycle.csv", "ltca_positions.csv", "ltca_points.csv"]
                    .map(String::from)
                    .into_iter()
                    .chain(spectra.files)
                    .collect(),
                plots,
                contact_pattern: pattern,
            },
        })),
        steps,
    };
    let result = LtcaResult::Cycle(Box::new(summary));
    result.write(out)?;
    Ok(result)
}
