//! `flank run` on a bevel/hypoid scene ([`run_bevel`]): the checked and
//! factorized [`MeshCycle`](crate::mesh_cycle::cycle::MeshCycle) ([`checked_cycle`]) over the roll angles with
//! checkpoints, and its files: `mesh_cycle.csv` and `positions.csv` with the columns of every
//! pair kind ([`crate::mesh_cycle::outputs`]), `contact_pattern.csv`, the
//! pattern plots and summary.json ([`RunSummary`]).

use crate::error::FlankError;
use crate::geometry::gear_pair::GearPair;
use crate::mesh_cycle::bevel_checks::{self as checks, checked_cycle, CheckedCycle};
use crate::mesh_cycle::checkpoint;
use crate::mesh_cycle::cycle::{iteration_limits, RunSettings, StepResult};
use crate::mesh_cycle::options::RunOptions;
use crate::mesh_cycle::outputs::{self, position_records};
use crate::mesh_cycle::positions::{PositionFiles, Positions};
use crate::mesh_cycle::summary::{peak_to_peak, BevelRun, RunFiles, RunKind, RunLaw, RunSummary};
use crate::report::fe_pattern::{plot_fe_pattern, PatternNode};
use crate::scene::Scene;
use crate::settings::SlaveBody;

/// `flank run` on a bevel/hypoid scene with the merged `settings`
/// ([`crate::mesh_cycle::run::settings`]; `options` gives the mesh,
/// threads, output folder, decks and resume): the pair factorized once
/// after its input checks, then the settings' roll angles (by default
/// [`checks::DEFAULT_POSITIONS`] positions over one mesh cycle centred on
/// roll 0, the middle pair at the mean point); writes `mesh_cycle.csv`
/// (per position), `positions.csv` (per position and tooth pair),
/// `contact_pattern.csv`, the pattern plots and `summary.json` into
/// `options.out` and returns the summary.
pub fn run_bevel(
    scene: &Scene,
    settings: RunSettings,
    options: &RunOptions,
) -> Result<RunSummary, FlankError> {
    let bevel = scene.bevel("the bevel/hypoid FE mesh cycle")?;
    use std::io::Write;
    crate::mesh_cycle::pair_model::check_torque(scene)?;
    let out = options.out.as_path();
    let pitch = bevel.pair.tooth_roll_step().abs().to_degrees();
    // the functional contact ratio needs the default cycle (positions
    // spread evenly over one pitch)
    let default_cycle = options.roll_angles_deg.is_none()
        && scene
            .analyses
            .contact
            .as_ref()
            .is_none_or(|a| a.roll_angles_deg.is_none());
    let rolls = settings.roll_angles_deg.clone();
    let mesh = crate::compliance::body::bevel_sector_options(scene, &options.mesh)?;
    let threads = if options.threads == 0 {
        std::thread::available_parallelism().map_or(1, |n| n.get())
    } else {
        options.threads
    };
    let CheckedCycle {
        cycle,
        unloaded,
        warnings: run_warnings,
        checks_s,
        setup_s,
    } = checked_cycle(scene, &mesh, settings, threads, &rolls)?;
    std::fs::create_dir_all(out).map_err(|e| FlankError::io(out, e))?;
    crate::atomic_file::remove_stale_temps(out);
    // every position is kept in checkpoint.json as it is solved; SIGINT is
    // polled between positions
    let key = checkpoint::run_key(&scene.source, &mesh, &cycle.settings)?;
    let files = PositionFiles {
        vtu: false,
        decks: options.decks,
    };
    let mut positions = Positions::open(&cycle, out, key, options.resume, files)?;
    let mut steps: Vec<StepResult> = Vec::with_capacity(rolls.len());
    let progress = crate::progress::Counter::start("fe positions", rolls.len());
    for &r in &rolls {
        steps.push(positions.solve(r)?);
        progress.step();
        if let Some(e) = positions.stop_requested(&steps) {
            return Err(e);
        }
    }
    let resumed = positions.reused();
    let records = position_records(&cycle, &steps);
    let np = cycle.pair.teeth.len();
    outputs::write_mesh_cycle_csv(&out.join("mesh_cycle.csv"), np, &records)?;
    outputs::write_positions_csv(&out.join("positions.csv"), &records)?;
    // the contact pattern: every loaded node of every position
    let path = out.join("contact_pattern.csv");
    let mut w = crate::atomic_file::AtomicWriter::create(&path)?;
    let io = |e| FlankError::io(&path, e);
    writeln!(
        w,
        "roll_deg,pair,pinion_along_face_mm,pinion_height_mm,gear_along_face_mm,gear_height_mm,pressure_mpa"
    )
    .map_err(io)?;
    for st in &steps {
        for n in &st.pattern {
            let [p, g] = n.projection_mm;
            writeln!(
                w,
                "{},{},{:e},{:e},{:e},{:e},{:e}",
                st.roll_deg, n.pair, p[0], p[1], g[0], g[1], n.pressure_mpa
            )
            .map_err(io)?;
        }
    }
    w.commit()?;
    let pattern: Vec<PatternNode> = steps.iter().flat_map(|s| s.pattern.clone()).collect();
    let plots = plot_fe_pattern(out, cycle.gear_pair.as_ref(), &pattern)?;
    let interference = steps
        .iter()
        .flat_map(|s| s.min_initial_gap_mm.iter().flatten())
        .cloned()
        .fold(f64::INFINITY, f64::min);
    let loops = iteration_limits(&steps, cycle.contact.max_iterations);
    // the LTCA's measure ([`crate::load_sharing::cycle`]): pairs above 1 %
    // of the position's normal force, over one pitch
    let sharing = default_cycle
        .then(|| {
            let forces: Vec<Vec<f64>> = steps.iter().map(|s| s.pair_force_n.clone()).collect();
            crate::load_sharing::cycle_sharing(&forces, pitch)
        })
        .flatten();
    let torque = cycle.torque_nmm();
    let stats = &cycle.system.stats;
    let nodes = cycle.pair.model.mesh.node_count();
    let kind = BevelRun {
        functional_contact_ratio: sharing.as_ref().map(|s| s.functional_contact_ratio),
        load_sharing: sharing,
        input_checks_s: checks_s,
        largest_exact_unloaded_interpenetration_mm: unloaded
            .iter()
            .map(|u| u.exact_depth_mm)
            .fold(0.0, f64::max),
        gross_interpenetration_limit_mm: checks::GROSS_INTERPENETRATION_MODULE
            * bevel.blank.cones.m_mn,
        largest_unloaded_interpenetration_mm: (-interference).max(0.0),
        mesh_cycle_deg: pitch,
        torque_nm: torque / 1000.0,
        max_pressure_mpa: steps
            .iter()
            .flat_map(|s| s.max_pressure_mpa.iter())
            .cloned()
            .fold(0.0, f64::max),
        max_moment_balance: steps
            .iter()
            .filter_map(|s| s.moment_balance.map(f64::abs))
            .fold(0.0, f64::max),
        plots: plots.clone(),
        slave: SlaveBody::Pinion,
        friction_mu: cycle.settings.friction_mu,
        max_coulomb_residual: steps.iter().map(|s| s.coulomb_residual).fold(0.0, f64::max),
        friction_not_converged: steps
            .iter()
            .filter(|s| s.friction_converged == Some(false))
            .count(),
        steps: steps.clone(),
    };
    let summary = RunSummary {
        header: scene.summary_header(),
        positions: steps.len(),
        resumed_positions: resumed,
        nodes,
        nodes_per_body: cycle.pair.nodes,
        elements_per_body: cycle.pair.elements,
        dofs: stats.dofs,
        nnz_factor: stats.nnz_factor,
        factorization_flops: stats.flops,
        factorization_s: stats.factorization_s,
        setup_s,
        factorization_gflop_per_s: stats.flops / stats.factorization_s.max(1e-9) / 1e9,
        time_per_position_s: steps.iter().map(|s| s.time_s).sum::<f64>()
            / steps.len().max(1) as f64,
        peak_memory_mb: crate::fem::static_analysis::peak_memory_mb(),
        te_peak_to_peak_urad: peak_to_peak(records.iter().map(|r| r.te_urad)),
        te_peak_to_peak_arcsec: peak_to_peak(steps.iter().map(|s| s.te_arcsec)),
        law: RunLaw::of(&cycle),
        iteration_limits: loops,
        tooth_pairs: cycle.pair.teeth.clone(),
        kinematics: cycle.gear_pair.describe(),
        files: RunFiles {
            csv: "mesh_cycle.csv",
            positions_csv: "positions.csv",
            plots,
            vtu: "",
        },
        notes: Vec::new(),
        warnings: run_warnings,
        kind: RunKind::Bevel(Box::new(kind)),
    };
    crate::atomic_file::write(&out.join("summary.json"), summary.to_json_text()? + "\n")?;
    positions.finish()?;
    Ok(summary)
}
