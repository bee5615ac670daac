//! `flank run` over a scene of any pair kind: the options merged (command
//! line > scene's `[analyses.contact]` > defaults, [`settings`]), the
//! cycle of [`crate::mesh_cycle::cycle::MeshCycle`] over the roll angles
//! ([`crate::mesh_cycle::positions`]: checkpoints, SIGINT), and what a gear
//! engineer reads from it. Here the line-contact part: the default range
//! extended while the middle pair is loaded, the wet–dry loop, contact
//! ratio and single-pair force, VTU and plots; a bevel/hypoid scene goes
//! to [`crate::mesh_cycle::bevel_run`]. Both write the same CSVs and
//! [`RunSummary`].

use std::path::Path;
use std::time::Instant;

use crate::error::FlankError;
use crate::fem::static_analysis::peak_memory_mb;

use crate::load_sharing::{te_arcsec_at_gear, LOADED_FRACTION};
use crate::mesh_cycle::bevel_run::run_bevel;
use crate::mesh_cycle::checkpoint;
use crate::mesh_cycle::cycle::{iteration_limits, MeshCycle, StepResult, ILL_CONDITIONED};
use crate::mesh_cycle::outputs::{self, position_records};
use crate::mesh_cycle::positions::{PositionFiles, Positions};
use crate::mesh_cycle::summary::{
    peak_to_peak, CylindricalRun, RunFiles, RunKind, RunLaw, RunSummary,
};
use crate::scene::{read_scene, Scene};

pub use crate::mesh_cycle::options::{settings, RunOptions};

/// `flank run SCENE`: the FE contact mesh cycle of the scene, written to
/// `options.out`. Returns the summary (also written as summary.json).
pub fn run_scene(path: &Path, options: &RunOptions) -> Result<RunSummary, FlankError> {
    let scene = read_scene(path)?;
    asks_for_contact(&scene)?;
    run(&scene, options)
}

/// Refuses a spur/helical scene without `[analyses] contact`: `flank run`
/// (and the library's FE mesh cycle) would otherwise run on defaults the
/// scene never asked for. Bevel/hypoid scenes run on the defaults.
pub fn asks_for_contact(scene: &Scene) -> Result<(), FlankError> {
    if !scene.is_bevel() && scene.analyses.contact.is_none() {
        return Err(FlankError::Model(format!(
            "{}: the scene asks for no analysis `flank run` performs; add `contact = {{}}` under [analyses] for the FE contact mesh cycle",
            scene.source.display()
        )));
    }
    Ok(())
}

/// The mesh cycle of a parsed scene of any pair kind (see [`run_scene`]):
/// the settings of [`settings`]; a bevel/hypoid scene runs
/// [`crate::mesh_cycle::bevel_run::run_bevel`] with them.
pub fn run(scene: &Scene, options: &RunOptions) -> Result<RunSummary, FlankError> {
    let settings = settings(scene, options)?;
    if scene.is_bevel() {
        return run_bevel(scene, settings, options);
    }
    let t_total = Instant::now();
    let out = &options.out;
    std::fs::create_dir_all(out).map_err(|e| FlankError::io(out, e))?;
    // what a killed earlier run left half-written (never a result file)
    crate::atomic_file::remove_stale_temps(out);
    let t = Instant::now();
    let cycle = MeshCycle::new(scene, &options.mesh, settings, options.threads)?;
    let setup_s = t.elapsed().as_secs_f64();
    let line = cycle.line_pair()?.clone();
    let nominal = cycle.nominal_force()?;
    let np = cycle.pair.teeth.len();
    let mid = line.middle() - 1;
    let angles = cycle.settings.roll_angles_deg.clone();
    let progress = crate::progress::Counter::start("fe positions", angles.len());
    // an embedding program that observes progress draws its own bar
    let bar = if options.quiet || crate::progress::observed() {
        indicatif::ProgressBar::hidden()
    } else {
        let b = indicatif::ProgressBar::new(angles.len() as u64);
        b.set_style(
            indicatif::ProgressStyle::with_template(
                "{msg} [{bar:30}] {pos}/{len} positions, {elapsed} (eta {eta})",
            )
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        b.set_message("mesh cycle");
        b
    };
    let mut steps = Vec::with_capacity(angles.len());
    let key = checkpoint::run_key(&scene.source, &options.mesh, &cycle.settings)?;
    let files = PositionFiles {
        vtu: cycle.settings.vtu,
        decks: options.decks,
    };
    let mut positions = Positions::open(&cycle, out, key, options.resume, files)?;
    // SIGINT is polled between positions: what is solved is kept
    let stop = |positions: &Positions, steps: &[StepResult]| -> Result<(), FlankError> {
        match positions.stop_requested(steps) {
            Some(e) => {
                bar.abandon();
                Err(e)
            }
            None => Ok(()),
        }
    };
    for &a in &angles {
        steps.push(positions.solve(a)?);
        bar.inc(1);
        progress.step();
        stop(&positions, &steps)?;
    }
    // a default range grows while the middle pair is loaded at an end
    let mut extended = 0;
    if let Some(step) = cycle.settings.extend_step_deg {
        let limit = (line.pinion().angular_pitch().to_degrees() / step).ceil() as usize;
        for _ in 0..limit {
            if !cycle.loaded(&steps[0], mid) {
                break;
            }
            bar.inc_length(1);
            progress.grow(1);
            steps.insert(0, positions.solve(steps[0].roll_deg - step)?);
            bar.inc(1);
            progress.step();
            extended += 1;
            stop(&positions, &steps)?;
        }
        for _ in 0..limit {
            let last = steps.len() - 1;
            if !cycle.loaded(&steps[last], mid) {
                break;
            }
            bar.inc_length(1);
            progress.grow(1);
            steps.push(positions.solve(steps[last].roll_deg + step)?);
            bar.inc(1);
            progress.step();
            extended += 1;
            stop(&positions, &steps)?;
        }
    }
    bar.finish_and_clear();
    let reused = positions.reused();
    let mut notes: Vec<String> = scene.material_warnings();
    let rolls: Vec<f64> = steps.iter().map(|s| s.roll_deg).collect();
    notes.extend(scene.sector_warning(&rolls));
    // the wet–dry loop: the positions solved so far are its dry pass
    let mut lubrication = None;
    if let Some(ls) = cycle.settings.lubrication.clone() {
        let dry = std::mem::take(&mut steps);
        let lc = crate::mesh_cycle::lubricated::lubricated_cycle(&cycle, scene, &ls, dry, out)?;
        steps = lc.steps;
        if cycle.settings.refine_contact_limits {
            notes.push(format!(
                "the contact-limit bisection runs at the dry pass's μ₀ = {}",
                ls.initial_mu
            ));
        }
        lubrication = Some(lc.summary);
    }
    let time_per_position_s =
        steps.iter().map(|s| s.time_s).sum::<f64>() / steps.len().max(1) as f64;

    // contact ratio from the middle pair's loaded interval
    let mut refine_solves = 0;
    let mut limits: Option<(f64, f64)> = None;
    let loaded: Vec<bool> = steps.iter().map(|s| cycle.loaded(s, mid)).collect();
    let first = loaded.iter().position(|&l| l);
    let last = loaded.iter().rposition(|&l| l);
    match (first, last) {
        (Some(f), Some(l)) if f > 0 && l + 1 < steps.len() => {
            let (mut start, mut end) = (
                0.5 * (steps[f - 1].roll_deg + steps[f].roll_deg),
                0.5 * (steps[l].roll_deg + steps[l + 1].roll_deg),
            );
            if cycle.settings.refine_contact_limits {
                let (s, n1) = cycle.bisect(mid, steps[f - 1].roll_deg, steps[f].roll_deg, 0.01)?;
                let (e, n2) = cycle.bisect(mid, steps[l + 1].roll_deg, steps[l].roll_deg, 0.01)?;
                start = s;
                end = e;
                refine_solves = n1 + n2;
            }
            limits = Some((start, end));
        }
        _ => notes.push(
            "contact ratio not measured: the roll angles do not cover the middle pair's whole engagement with an unloaded position before and after"
                .into(),
        ),
    }
    let pitch_deg = line.pinion().angular_pitch().to_degrees();
    let contact_ratio = limits.map(|(s, e)| (e - s) / pitch_deg);
    // single contact: only the middle pair loaded
    let single: Vec<&StepResult> = steps
        .iter()
        .filter(|s| (0..np).all(|p| (p == mid) == cycle.loaded(s, p)))
        .collect();
    let single_pair_force_n = if single.is_empty() {
        notes.push("no position with a single loaded pair".into());
        None
    } else {
        Some(single.iter().map(|s| s.pair_force_n[mid]).sum::<f64>() / single.len() as f64)
    };
    let worst = |f: fn(&StepResult) -> f64| steps.iter().map(f).fold(0.0f64, f64::max);
    let warnings: Vec<String> = steps
        .iter()
        .flat_map(|s| {
            s.warnings
                .iter()
                .map(move |w| format!("{}°: {w}", s.roll_deg))
        })
        .collect();
    let loops = iteration_limits(&steps, cycle.contact.max_iterations);
    notes.extend(loops.warnings());
    let records = position_records(&cycle, &steps);
    outputs::write_mesh_cycle_csv(&out.join("mesh_cycle.csv"), np, &records)?;
    outputs::write_positions_csv(&out.join("positions.csv"), &records)?;
    let (lpstc, hpstc) = line.single_contact();
    let (eng_a, eng_e) = line.engagement(line.middle());
    // TE over the positions where the middle pair carries load (1.5
    // pitches: a whole mesh cycle away from the sector's outer teeth)
    let te: Vec<f64> = steps
        .iter()
        .filter(|s| cycle.loaded(s, mid))
        .map(|s| s.te_urad)
        .collect();
    let te_mean = te.iter().sum::<f64>() / te.len().max(1) as f64;
    let te_pp = te.iter().fold(f64::NEG_INFINITY, |a, &v| a.max(v))
        - te.iter().fold(f64::INFINITY, |a, &v| a.min(v));
    let roll_deg: Vec<f64> = steps.iter().map(|s| s.roll_deg).collect();
    let pair_forces: Vec<Vec<f64>> = (0..cycle.pair.teeth.len())
        .map(|p| steps.iter().map(|s| s.pair_force_n[p]).collect())
        .collect();
    let te_series: Vec<f64> = steps.iter().map(|s| s.te_urad).collect();
    let plot_files = crate::report::cycle_plot::plot_cycle(
        out,
        "",
        &roll_deg,
        &pair_forces,
        &te_series,
        &cycle.pair.teeth,
        nominal,
        line.transmission_error_radius(),
    )
    .unwrap_or_else(|e| {
        notes.push(format!("plots not written: {e}"));
        Vec::new()
    });
    let stats = &cycle.system.stats;
    if !(stats.scaled_condition_estimate <= ILL_CONDITIONED) {
        notes.push(format!(
            "the pinned stiffness is ill-conditioned: κ₁ estimate of the diagonally scaled stiffness, which Cholesky's accuracy depends on, {:.2e} (above {ILL_CONDITIONED:.0e}: a solve may lose more than 12 of 16 digits; the backward error per position says whether the solves themselves were stable; unscaled κ₁ {:.2e})",
            stats.scaled_condition_estimate, stats.condition_estimate
        ));
    }
    let ratio = line.ratio();
    let te_arcsec: Vec<f64> = te.iter().map(|&t| te_arcsec_at_gear(t, ratio)).collect();
    let kind = CylindricalRun {
        analysis: "fe_contact_mesh_cycle",
        contact_ratio,
        contact_ratio_kinematic: line.kinematic_contact_ratio(),
        single_pair_force_n,
        nominal_force_n: nominal,
        single_pair_force_error: single_pair_force_n.map(|f| f / nominal - 1.0),
        single_contact_positions: single.len(),
        middle_pair_loaded_deg: limits.map(|(s, e)| [s, e]),
        middle_pair_kinematic_deg: [eng_a.to_degrees(), eng_e.to_degrees()],
        kinematic_single_contact_deg: [lpstc.to_degrees(), hpstc.to_degrees()],
        angular_pitch_deg: pitch_deg,
        loaded_threshold_fraction: LOADED_FRACTION,
        refinement_positions: refine_solves,
        extension_positions: extended,
        total_s: t_total.elapsed().as_secs_f64(),
        lubrication,
        ordering: stats.ordering.clone(),
        assembly_s: stats.assembly_s,
        condition_estimate: stats.condition_estimate,
        scaled_condition_estimate: stats.scaled_condition_estimate,
        condition_estimate_s: stats.condition_s,
        threads: crate::fem::solver::parallelism(options.threads).degree(),
        estimated_peak_memory_mb: stats.estimated_peak_mb,
        te_positions: te.len(),
        te_mean_urad: te_mean,
        te_peak_to_peak_um: te_pp * line.transmission_error_radius() * 1e-3,
        max_violation_mm: worst(|s| s.max_violation_mm),
        max_complementarity: worst(|s| s.complementarity),
        max_equilibrium: worst(|s| s.equilibrium),
        max_backward_error: worst(|s| s.backward_error),
        settings: cycle.settings.clone(),
        steps: steps.clone(),
    };
    let summary = RunSummary {
        header: scene.summary_header(),
        positions: steps.len(),
        resumed_positions: reused,
        nodes: cycle.pair.model.mesh.node_count(),
        nodes_per_body: cycle.pair.nodes,
        elements_per_body: cycle.pair.elements,
        dofs: stats.dofs,
        nnz_factor: stats.nnz_factor,
        factorization_flops: stats.flops,
        factorization_s: stats.factorization_s,
        setup_s,
        factorization_gflop_per_s: stats.flops / stats.factorization_s.max(1e-9) / 1e9,
        time_per_position_s,
        peak_memory_mb: peak_memory_mb(),
        te_peak_to_peak_urad: te_pp,
        te_peak_to_peak_arcsec: peak_to_peak(te_arcsec.iter().copied()),
        law: RunLaw::of(&cycle),
        iteration_limits: loops,
        tooth_pairs: cycle.pair.teeth.clone(),
        kinematics: line.describe(),
        files: RunFiles {
            csv: "mesh_cycle.csv",
            positions_csv: "positions.csv",
            plots: plot_files,
            vtu: if cycle.settings.vtu {
                "roll_<angle>deg.vtu"
            } else {
                ""
            },
        },
        notes,
        warnings,
        kind: RunKind::Cylindrical(Box::new(kind)),
    };
    let text = summary.to_json_text()?;
    let p = out.join("summary.json");
    crate::atomic_file::write(&p, text)?;
    // complete: summary.json holds every position
    positions.finish()?;
    Ok(summary)
}
