//! `flank run` on a bevel/hypoid scene ([`run_bevel`]): the checked and
//! factorized [`BevelCycle`] over the roll angles with checkpoints, and its
//! files: `mesh_cycle.csv` and `positions.csv` with the columns of every
//! pair kind ([`crate::mesh_cycle::outputs`]), `contact_pattern.csv`, the
//! pattern plots and summary.json ([`RunSummary`]).

use crate::contact::PressureOverclosure;
use crate::error::FlankError;
use crate::geometry::gear_pair::GearPair;
use crate::iteration_limits::IterationLimits;
use crate::load_sharing::te_urad_at_pinion;
use crate::mesh_cycle::bevel::{
    BevelCycle, BevelRunOptions, BevelStep, CheckedCycle, DEFAULT_POSITIONS,
};
use crate::mesh_cycle::bevel_checks as checks;
use crate::mesh_cycle::checkpoint::{self, Checkpoint, Position};
use crate::mesh_cycle::outputs::{self, PairRecord, PositionRecord};
use crate::mesh_cycle::summary::{
    peak_to_peak, BevelLaw, BevelRun, BevelRunStep, RunFiles, RunKind, RunSummary, SCHEMA_VERSION,
};
use crate::report::fe_pattern::{plot_fe_pattern, PatternNode};
use crate::scene::Scene;
use crate::settings::SlaveBody;

/// A position as the checkpoint keeps it: the step with its contact
/// pattern (which summary.json leaves out).
#[derive(Clone, serde::Serialize, serde::Deserialize)]
struct KeptStep {
    step: BevelStep,
    pattern: Vec<PatternNode>,
}

impl Position for KeptStep {
    fn roll_deg(&self) -> f64 {
        self.step.roll_deg
    }
}

/// `flank run` on a bevel/hypoid scene: the pair factorized once, then
/// `roll_angles_deg` (default: [`DEFAULT_POSITIONS`] positions over one
/// mesh cycle centred on roll 0, the middle pair at the mean point);
/// writes `mesh_cycle.csv` (per position), `positions.csv` (per position
/// and tooth pair), `contact_pattern.csv`, the pattern plots and
/// `summary.json` into `out` and returns the summary.
pub fn run_bevel(
    scene: &Scene,
    options: &BevelRunOptions,
    roll_angles_deg: Option<Vec<f64>>,
    out: &std::path::Path,
) -> Result<RunSummary, FlankError> {
    let bevel = scene.bevel("the bevel/hypoid FE mesh cycle")?;
    use std::io::Write;
    checks::check_torque(scene)?;
    let pitch = bevel.pair.tooth_roll_step().abs().to_degrees();
    // the functional contact ratio needs the default cycle (positions
    // spread evenly over one pitch)
    let default_cycle = roll_angles_deg.is_none();
    let rolls = roll_angles_deg.unwrap_or_else(|| {
        (0..DEFAULT_POSITIONS)
            .map(|i| -0.5 * pitch + pitch * i as f64 / DEFAULT_POSITIONS as f64)
            .collect()
    });
    if let Some(r) = rolls.iter().find(|r| !r.is_finite()) {
        return Err(FlankError::Model(format!("roll angle {r} is not a number")));
    }
    let CheckedCycle {
        cycle,
        unloaded,
        warnings: run_warnings,
        checks_s,
        factorization_s,
    } = BevelCycle::checked(scene, options, &rolls)?;
    std::fs::create_dir_all(out).map_err(|e| FlankError::io(out, e))?;
    // every position is kept in checkpoint.json as it is solved; SIGINT is
    // polled between positions (the spur cycle's protocol)
    let settings = format!(
        "{:?}",
        (
            options.search_distance_mm,
            &options.law,
            options.penalty_factor,
            options.friction_mu
        )
    );
    let key = checkpoint::key(&scene.source, &options.mesh, &settings);
    let mut kept: Checkpoint<KeptStep> = Checkpoint::open(out, key, options.resume)?;
    let mut steps: Vec<BevelStep> = Vec::with_capacity(rolls.len());
    for &r in &rolls {
        let step = match kept.take(r)? {
            Some(k) => BevelStep {
                pattern: k.pattern,
                ..k.step
            },
            None => {
                let step = cycle.solve(r)?;
                kept.record(&KeptStep {
                    pattern: step.pattern.clone(),
                    step: step.clone(),
                })?;
                step
            }
        };
        steps.push(step);
        if crate::interrupt::requested() {
            return Err(FlankError::Interrupted(format!(
                "stopped at a position boundary after {} solved position(s); they are kept in {}; \
                 resume with the same command and options plus --resume (`flank run SCENE --out {} ... --resume`): \
                 only the remaining positions are solved",
                steps.len(),
                kept.path().display(),
                out.display()
            )));
        }
    }
    let resumed = kept.reused();
    if options.decks {
        for &r in &rolls {
            let name = crate::report::vtu::vtu_name(r).replace(".vtu", ".inp");
            cycle.write_deck(r, &out.join(name))?;
        }
    }
    let ratio = cycle.pair.ratio();
    let records: Vec<PositionRecord> = steps
        .iter()
        .map(|st| position_record(st, &cycle.model.teeth, ratio))
        .collect();
    let np = cycle.model.teeth.len();
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
    let plots = plot_fe_pattern(out, cycle.pair.as_ref(), &pattern)?;
    let interference = steps
        .iter()
        .flat_map(|s| s.min_initial_gap_mm.iter())
        .cloned()
        .fold(f64::INFINITY, f64::min);
    let mut loops = IterationLimits::new();
    for s in &steps {
        crate::mesh_cycle::cycle::record_active_set(
            &mut loops,
            s.active_set_iterations,
            cycle.contact.max_iterations,
            s.max_violation_mm,
        );
        if let Some(converged) = s.friction_converged {
            crate::mesh_cycle::cycle::record_friction(
                &mut loops,
                converged,
                s.friction_iterations,
                s.friction_rounds,
                s.friction_bound_change,
            );
        }
    }
    // the LTCA's measure ([`crate::load_sharing::cycle`]): pairs above 1 %
    // of the position's normal force, over one pitch
    let sharing = default_cycle
        .then(|| {
            let forces: Vec<Vec<f64>> = steps.iter().map(|s| s.pair_force_n.clone()).collect();
            crate::load_sharing::cycle_sharing(&forces, pitch)
        })
        .flatten();
    let torque = cycle.torque;
    let stats = &cycle.system.stats;
    let nodes = cycle.model.model.mesh.node_count();
    let law = match cycle.model.model.contact.interactions[0].behavior {
        Some(PressureOverclosure::Linear { slope: Some(s), .. }) => BevelLaw::Penalty {
            slope_mpa_per_mm: s,
            factor: options.penalty_factor,
        },
        _ => BevelLaw::Hard,
    };
    let kind = BevelRun {
        functional_contact_ratio: sharing.as_ref().map(|s| s.functional_contact_ratio),
        load_sharing: sharing,
        // the numeric factorization alone (factorization_s also holds
        // assembly, ordering and the condition estimates)
        numeric_factorization_s: stats.factorization_s,
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
            .map(|s| s.moment_balance.abs())
            .fold(0.0, f64::max),
        plots: plots.clone(),
        law,
        slave: SlaveBody::Pinion,
        friction_mu: options.friction_mu,
        max_coulomb_residual: steps.iter().map(|s| s.coulomb_residual).fold(0.0, f64::max),
        friction_not_converged: steps
            .iter()
            .filter(|s| s.friction_converged == Some(false))
            .count(),
        steps: steps
            .iter()
            .zip(&records)
            .map(|(s, r)| BevelRunStep {
                step: s.clone(),
                te_urad: r.te_urad,
            })
            .collect(),
    };
    let summary = RunSummary {
        schema_version: SCHEMA_VERSION,
        pair_kind: scene.kind.name(),
        scene: scene.source.display().to_string(),
        positions: steps.len(),
        resumed_positions: resumed,
        nodes,
        nodes_per_body: cycle.model.nodes,
        elements_per_body: cycle.model.elements,
        dofs: 3 * nodes,
        nnz_factor: stats.nnz_factor,
        factorization_flops: stats.flops,
        factorization_s,
        factorization_gflop_per_s: stats.flops / stats.factorization_s.max(1e-9) / 1e9,
        time_per_position_s: steps.iter().map(|s| s.time_s).sum::<f64>()
            / steps.len().max(1) as f64,
        peak_memory_mb: crate::fem::static_analysis::peak_memory_mb(),
        te_peak_to_peak_urad: peak_to_peak(records.iter().map(|r| r.te_urad)),
        te_peak_to_peak_arcsec: peak_to_peak(steps.iter().map(|s| s.te_arcsec)),
        iteration_limits: loops,
        tooth_pairs: cycle.model.teeth.clone(),
        kinematics: cycle.pair.describe(),
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
    kept.remove()?;
    Ok(summary)
}

/// A solved bevel position as the files of both pair kinds hold it: the
/// figures only cylindrical pairs have (kinematic position on the line of
/// action, TE along it, Delassus columns, equilibrium residual, reference
/// roll) are left out; the slave is always the pinion.
fn position_record(st: &BevelStep, teeth: &[(usize, usize)], ratio: f64) -> PositionRecord {
    PositionRecord {
        roll_deg: st.roll_deg,
        reference_deg: None,
        pairs: (0..st.pair_force_n.len())
            .map(|p| PairRecord {
                pinion_tooth: teeth[p].0,
                gear_tooth: teeth[p].1,
                force_n: st.pair_force_n[p],
                load_share: st.load_share[p],
                position_mm: None,
                max_pressure_mpa: st.max_pressure_mpa[p],
                closed_nodes: st.closed_nodes[p],
                slave: SlaveBody::Pinion,
                friction_n: st.friction_force_n.get(p).copied().unwrap_or(0.0),
                pinion_tip_edge: Some(st.pinion_tip_edge[p]),
                min_initial_gap_mm: Some(st.min_initial_gap_mm[p]),
            })
            .collect(),
        te_urad: te_urad_at_pinion(st.te_arcsec, ratio),
        te_arcsec: st.te_arcsec,
        te_um: None,
        candidates: st.candidates,
        iterations: st.active_set_iterations,
        columns: None,
        max_violation_mm: st.max_violation_mm,
        complementarity: st.complementarity,
        equilibrium: None,
        moment_balance: Some(st.moment_balance),
        time_s: st.time_s,
    }
}
