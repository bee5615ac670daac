//! `flank compare` on a bevel/hypoid scene (issue 19 point 5): the hypoid
//! LTCA ([`crate::ltca::cycle`], at several K on the tensors of one
//! compliance mesh) against FE contact of the hypoid pair
//! ([`crate::mesh_cycle::cycle::MeshCycle`], hard contact, at several flank sizes) at
//! the same roll angles, the finest FE the reference; the errors, times and
//! files of the spur/helical comparison ([`super`]), with the TE as the
//! pinion's loaded rotation (µrad; its relative error is the same at the
//! gear).
//!
//! p_max is compared at every position; FE contact's p_max of a hypoid
//! contact converges only when the elements resolve the loaded ellipse's
//! width (≈ 1 mm here: `papers/seed003-hypoid/README.md`), so its error
//! says how far the reference is from resolving it as much as how far the
//! LTCA is off.
//!
//! With friction (μ > 0, `--friction-mu`) both methods use the same μ: the
//! LTCA's frictional solve in load increments (its friction model, default
//! `incremental`: friction against the kinematic sliding), FE contact's
//! static Coulomb law (friction against the slip of the loading step); the
//! tangential force per pair is compared besides the normal forces
//! (`super::errors`).

use std::time::Instant;

use crate::error::FlankError;
use crate::ltca::cycle::{LtcaCycle, LtcaOptions};
use crate::mesh::bevel_sector::BevelSectorOptions;
use crate::mesh_cycle::bevel_checks::checked_cycle;
use crate::mesh_cycle::cycle::RunSettings;
use crate::scene::Scene;
use crate::settings::EdgeVariants;

use super::summary::{BevelCompare, CompareFiles, CompareKind, CompareSummary, CompareTargets};
use super::{best_ltca, errors, markdown, per_pair, plot, CompareOptions, MethodRun};

/// The hypoid LTCA's options of a comparison: `options.ltca` (merged with
/// the scene's `[analyses.ltca]` as `flank ltca` merges them,
/// [`LtcaCycle::new`]) with the command line's μ, and the TCA without
/// edges (K is swept, [`CompareOptions::points_per_line`]).
pub fn ltca_options(options: &CompareOptions) -> LtcaOptions {
    let mut lo = options.ltca.clone();
    lo.out = options.out.join("ltca_bodies");
    lo.friction_mu = options.friction_mu.or(lo.friction_mu);
    lo.edges = Some(EdgeVariants::Without);
    lo
}

/// The hypoid comparison; writes `compare.json`, `compare.md` and
/// `error_vs_time.{svg,png}` into `options.out`.
pub fn compare_bevel(
    scene: &Scene,
    options: &CompareOptions,
) -> Result<CompareSummary, FlankError> {
    let bevel = scene.bevel("the bevel/hypoid comparison")?;
    options.validate()?;
    if !options.pmax_reference.is_empty() {
        return Err(FlankError::Model(
            "--pmax-reference: contact-band runs exist for spur pairs only, not for bevel/hypoid scenes".into(),
        ));
    }
    let mut lo = ltca_options(options);
    lo.points_per_line = Some(options.points_per_line[0]);
    let out = &options.out;
    std::fs::create_dir_all(out).map_err(|e| FlankError::io(out, e))?;
    let say = |m: String| {
        if !options.quiet {
            eprintln!("{m}");
        }
    };
    // LTCA first (its TCA grid fixes the roll angles): tensors once
    say("LTCA: compliance tensors and TCA …".into());
    let t = Instant::now();
    let base = LtcaCycle::new(scene, &lo)?;
    let setup = t.elapsed().as_secs_f64();
    let friction = base.settings.friction.clone();
    let mu = friction.as_ref().map_or(0.0, |f| f.mu);
    // the TCA grid's own angles, so both methods see the same ones
    let want = options.roll_angles_deg.clone().unwrap_or_else(|| {
        base.point()
            .map(|p| p.cycle_rolls_deg())
            .unwrap_or_default()
    });
    let angles: Vec<f64> = want
        .iter()
        .map(|&a| base.solve(a).map(|r| r.roll_deg))
        .collect::<Result<_, _>>()?;
    let mut runs = Vec::new();
    for &k in &options.points_per_line {
        let l = base.with_points_per_line(k)?;
        let t = Instant::now();
        let results = l.solve_cycle(&angles)?;
        let cycle_s = t.elapsed().as_secs_f64();
        runs.push(MethodRun {
            method: "ltca".into(),
            label: format!("LTCA K = {k}"),
            points_per_line: Some(k),
            flank_size_mm: options.ltca.mesh.flank_size,
            nodes: None,
            pair_force_n: results.iter().map(|r| l.pair_forces(r)).collect(),
            pair_tangential_n: results
                .iter()
                .map(|r| l.pair_friction(r).iter().map(|t| t.abs()).collect())
                .collect(),
            te_urad: results.iter().map(|r| r.te_urad).collect(),
            pmax_mpa: results.iter().map(|r| r.max_pressure_mpa).collect(),
            cycle_s,
            setup_s: setup,
            slave: Vec::new(),
            load_sharing_err: f64::NAN,
            te_rel_err: f64::NAN,
            pmax_rel_err: f64::NAN,
            pmax_uniform_fe_rel_err: f64::NAN,
            tangential_force_err: f64::NAN,
        });
    }
    // FE contact, finest last
    let mut sizes = options.fe_flank_sizes.clone();
    sizes.sort_by(|a, b| b.total_cmp(a));
    sizes.dedup();
    let mut fe = Vec::new();
    for &h in &sizes {
        say(format!(
            "FE contact, flank {h} mm, {} positions …",
            angles.len()
        ));
        let t = Instant::now();
        // the inputs `flank run` refuses are refused here too (a sector too
        // small for the pairs in mesh at these angles, interpenetrating
        // unloaded bodies): FE numbers of such a model are not a reference
        let mesh = BevelSectorOptions {
            flank_size: h,
            base_size: options
                .fe_base_size
                .or(scene.mesh.base_size)
                .unwrap_or(bevel.blank.cones.m_mn / 2.0)
                .max(h),
            ..Default::default()
        };
        let settings = RunSettings {
            friction_mu: mu,
            roll_angles_deg: angles.clone(),
            ..RunSettings::default_for(scene)
        };
        let cycle = checked_cycle(scene, &mesh, settings, options.threads.max(1), &angles)?.cycle;
        let setup_s = t.elapsed().as_secs_f64();
        let t = Instant::now();
        let steps: Vec<_> = angles
            .iter()
            .map(|&a| cycle.solve(a).map(|s| s.step))
            .collect::<Result<_, _>>()?;
        let cycle_s = t.elapsed().as_secs_f64();
        fe.push(MethodRun {
            method: "fe_contact".into(),
            label: format!("FE flank {h} mm"),
            points_per_line: None,
            flank_size_mm: Some(h),
            nodes: Some(cycle.pair.model.mesh.node_count()),
            pair_force_n: steps.iter().map(|s| s.pair_force_n.clone()).collect(),
            pair_tangential_n: steps
                .iter()
                .map(|s| per_pair(&s.friction_force_n, s.pair_force_n.len()))
                .collect(),
            te_urad: steps.iter().map(|s| s.te_urad).collect(),
            pmax_mpa: steps
                .iter()
                .map(|s| s.max_pressure_mpa.iter().copied().fold(0.0, f64::max))
                .collect(),
            cycle_s,
            setup_s,
            slave: Vec::new(),
            load_sharing_err: f64::NAN,
            te_rel_err: f64::NAN,
            pmax_rel_err: f64::NAN,
            pmax_uniform_fe_rel_err: f64::NAN,
            tangential_force_err: f64::NAN,
        });
    }
    let (reference, extrapolated) = super::reference_of(&fe);
    let every = vec![true; angles.len()];
    for r in fe.iter_mut().chain(runs.iter_mut()) {
        errors(r, &reference, &every);
    }
    let best = best_ltca(&runs);
    let plots = plot::plot_error_vs_time(out, &fe, &runs, &reference.label).unwrap_or_else(|e| {
        say(format!("plots not written: {e}"));
        Vec::new()
    });
    let mut md = markdown(
        &scene.source,
        &angles,
        &fe,
        &runs,
        &reference,
        &every,
        extrapolated.as_ref(),
        false,
    );
    if mu > 0.0 {
        super::friction_table(&mut md, mu, fe.iter().chain(&runs), &reference);
    }
    let per_position = super::position_errors(&angles, &best, &reference, extrapolated.as_ref());
    super::position_table(&mut md, &best.label, &per_position, [0.02, 0.03]);
    let p = out.join("compare.md");
    crate::atomic_file::write(&p, &md)?;
    let summary = CompareSummary {
        schema_version: crate::summary::SCHEMA_VERSION,
        scene: scene.source.display().to_string(),
        pair_kind: scene.kind.name(),
        positions: angles.len(),
        roll_angles_deg: angles,
        reference: reference.label.clone(),
        reference_extrapolated: extrapolated,
        best_ltca: best.label.clone(),
        load_sharing_rel_err: best.load_sharing_err,
        te_rel_err: best.te_rel_err,
        pmax_rel_err: best.pmax_rel_err,
        pmax_reference: format!(
            "{} (the finest run's p_max)",
            fe.last().map_or("FE", |r| r.label.as_str())
        ),
        tangential_force_rel_err: best.tangential_force_err,
        friction_mu: mu,
        ltca_cycle_s: best.cycle_s,
        fe_cycle_s: reference.cycle_s,
        fe_setup_s: reference.setup_s,
        speedup: reference.cycle_s / best.cycle_s,
        targets: CompareTargets {
            load_sharing_rel_err: 0.02,
            te_rel_err: 0.03,
            pmax_rel_err: 0.05,
            ltca_cycle_s: 1.0,
            speedup: None,
        },
        ltca_settings: base.settings.clone(),
        runs: fe.iter().chain(runs.iter()).cloned().collect(),
        best_ltca_per_position: per_position,
        files: CompareFiles {
            markdown: "compare.md".into(),
            plots,
        },
        kind: CompareKind::Bevel(Box::new(BevelCompare {
            pair: "hypoid",
            ltca_friction_model: friction.as_ref().map(|f| f.model),
            ltca_increments: friction.as_ref().and_then(|f| f.increment_count()),
            ltca_span_approach_mm: base.point()?.span_approach_mm,
        })),
    };
    summary.write(out)?;
    Ok(summary)
}
