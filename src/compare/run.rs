//! `flank compare` over a scene of any pair kind: one LTCA cycle
//! ([`LtcaCycle`], the tensors once, then each K) and one FE mesh cycle per
//! flank size ([`crate::mesh_cycle::cycle::MeshCycle`]) at the same roll
//! angles, the errors against the (extrapolated) FE reference, the tables,
//! plots and the typed summary. What differs by kind is small and named
//! here: where the roll angles come from (spur/helical: the middle pair's
//! engagement; bevel/hypoid: the point TCA's grid, so both methods see the
//! same angles), how an FE cycle is built (spur/helical: the slave rule
//! `auto`, cached runs; bevel/hypoid: after `flank run`'s input checks,
//! [`super::bevel`]), which positions have flank contact (spur/helical:
//! every loaded pair inside its path of contact; bevel/hypoid: all), the
//! contact-band p_max reference (spur/helical only) and the targets.

use std::path::Path;
use std::time::Instant;

use super::bevel::{bevel_fe_run, bevel_kind};
use super::summary::{
    CompareFiles, CompareKind, CompareSummary, CompareTargets, CylindricalCompare, PmaxContactBand,
};
use super::{
    best_ltca, errors, fe_run_cached, friction_table, ltca_run, markdown, plot, pmax_reference,
    position_errors, position_table, CompareOptions,
};
use crate::error::FlankError;
use crate::ltca::cycle::{LtcaCycle, LtcaOptions};
use crate::mesh_cycle::cycle::default_roll_angles;
use crate::mesh_cycle::run::{settings, RunOptions};
use crate::scene::{read_scene, Scene};
use crate::settings::EdgeVariants;

/// `flank compare SCENE`: reads the scene and runs [`compare`].
pub fn compare_scene(path: &Path, options: &CompareOptions) -> Result<CompareSummary, FlankError> {
    compare(&read_scene(path)?, options)
}

/// The LTCA's options of a comparison: `options.ltca` (merged with the
/// scene's `[analyses.ltca]` as `flank ltca` merges them,
/// [`LtcaCycle::new`]) with the command line's μ, its first K, the tensors
/// in `out/ltca_bodies`; a bevel/hypoid TCA without edges (FE contact is
/// the reference of flank contact here).
pub fn ltca_options(scene: &Scene, options: &CompareOptions) -> LtcaOptions {
    let mut lo = options.ltca.clone();
    lo.out = options.out.join("ltca_bodies");
    lo.points_per_line = Some(options.points_per_line[0]);
    lo.friction_mu = options.friction_mu.or(lo.friction_mu);
    if scene.is_bevel() {
        lo.edges = Some(EdgeVariants::Without);
    }
    lo
}

/// LTCA against FE contact at the same positions, for any pair kind;
/// writes `compare.json`, `compare.md` and `error_vs_time.{svg,png}` into
/// `options.out` and returns the summary.
pub fn compare(scene: &Scene, options: &CompareOptions) -> Result<CompareSummary, FlankError> {
    options.validate()?;
    let bevel = scene.is_bevel();
    if bevel && !options.pmax_reference.is_empty() {
        return Err(FlankError::Model(
            "--pmax-reference: contact-band runs exist for spur pairs only, not for bevel/hypoid scenes".into(),
        ));
    }
    // the contact-band p_max reference, read before anything runs
    let pmax_ref = if options.pmax_reference.is_empty() {
        None
    } else {
        Some(pmax_reference::load(&options.pmax_reference, scene)?)
    };
    let out = &options.out;
    std::fs::create_dir_all(out).map_err(|e| FlankError::io(out, e))?;
    let say = |m: String| {
        if !options.quiet {
            eprintln!("{m}");
        }
    };
    // LTCA first: its tensors once, and on a bevel pair its TCA grid
    say("LTCA: compliance tensors and TCA …".into());
    let t = Instant::now();
    let base = LtcaCycle::new(scene, &ltca_options(scene, options))?;
    let ltca_setup_s = t.elapsed().as_secs_f64();
    let ltca_mu = base.settings.friction.as_ref().map_or(0.0, |f| f.mu);
    let line = if bevel {
        None
    } else {
        Some(base.line_pair()?.clone())
    };
    let angles: Vec<f64> = match &line {
        Some(pair) => options
            .roll_angles_deg
            .clone()
            .unwrap_or_else(|| default_roll_angles(pair.as_ref(), options.roll_step_deg)),
        // the TCA grid's own angles, so both methods see the same ones
        None => {
            let want = options.roll_angles_deg.clone().unwrap_or_else(|| {
                base.point()
                    .map(|p| p.cycle_rolls_deg())
                    .unwrap_or_default()
            });
            want.iter()
                .map(|&a| base.solve(a).map(|r| r.roll_deg))
                .collect::<Result<_, _>>()?
        }
    };
    // FE contact, finest last; its μ: the command line's, else the scene's
    // `[analyses.contact]` (spur/helical) or the LTCA's (bevel/hypoid)
    let fe_mu = if bevel {
        ltca_mu
    } else {
        settings(
            scene,
            &RunOptions {
                roll_angles_deg: Some(angles.clone()),
                friction_mu: options.friction_mu,
                ..Default::default()
            },
        )?
        .friction_mu
    };
    let mut sizes = options.fe_flank_sizes.clone();
    sizes.sort_by(|a, b| b.total_cmp(a));
    sizes.dedup();
    let mut fe = Vec::new();
    for &h in &sizes {
        say(format!(
            "FE contact, flank {h} mm, {} positions …",
            angles.len()
        ));
        let r = if bevel {
            bevel_fe_run(scene, options, h, &angles, fe_mu)?
        } else {
            let (r, cached) = fe_run_cached(
                scene,
                (h, options.fe_base_size),
                &angles,
                options.threads,
                options.friction_mu,
                &out.join("fe_runs"),
            )?;
            if cached {
                say(format!("  reused {}", r.label));
            }
            r
        };
        fe.push(r);
    }
    // the LTCA at each K on the same tensors
    let mut ltca = Vec::new();
    let mut pmax_runs = Vec::new();
    for &k in &options.points_per_line {
        let c = base.with_points_per_line(k)?;
        // one warm-up pass (page faults, thread pool), then the timed cycle
        let _ = c.solve(angles[angles.len() / 2])?;
        let run = ltca_run(&c, &angles, ltca_setup_s)?;
        // the extra positions of the p_max reference, untimed
        if let Some(x) = &pmax_ref {
            let rolls = x.roll_angles();
            let results: Vec<_> = c
                .solve_cycle(&rolls)?
                .into_iter()
                .zip(rolls)
                .map(|(r, a)| {
                    let f = c.pair_forces(&r);
                    (a, r, f)
                })
                .collect();
            pmax_runs.push(pmax_reference::ltca_against(x, &run.label, &results));
        }
        ltca.push(run);
    }
    let (reference, extrapolated) = super::reference_of(&fe);
    // flank-contact positions: on a line-contact pair every loaded pair
    // inside its path of contact; a point-contact pair's every position
    let flank_positions: Vec<bool> = match &line {
        Some(pair) => {
            let nominal = base.nominal_force();
            angles
                .iter()
                .enumerate()
                .map(|(i, &a)| {
                    reference.pair_force_n[i]
                        .iter()
                        .enumerate()
                        .filter(|(_, &f)| f > 1e-3 * nominal)
                        .all(|(p, _)| {
                            let s = pair.path_position(p + 1, a.to_radians());
                            s > 0.0 && s < pair.path_length()
                        })
                })
                .collect()
        }
        None => vec![true; angles.len()],
    };
    for r in fe.iter_mut().chain(ltca.iter_mut()) {
        errors(r, &reference, &flank_positions);
    }
    for (r, p) in ltca.iter_mut().zip(&pmax_runs) {
        r.pmax_rel_err = p.max_rel_err;
    }
    let pmax_against = match &pmax_ref {
        Some(_) => "FE with contact bands (extrapolated, over the flank)".to_string(),
        None => format!(
            "{} (uniform FE mesh, the finest run's p_max)",
            fe.last().map_or("FE", |r| r.label.as_str())
        ),
    };
    // the issue targets: spur/helical seed 002's, bevel/hypoid seed 003's
    let targets = if bevel {
        CompareTargets {
            load_sharing_rel_err: 0.02,
            te_rel_err: 0.03,
            pmax_rel_err: 0.05,
            ltca_cycle_s: 1.0,
            speedup: None,
        }
    } else {
        CompareTargets {
            load_sharing_rel_err: 0.02,
            te_rel_err: 0.02,
            pmax_rel_err: 0.05,
            ltca_cycle_s: 0.1,
            speedup: Some(1000.0),
        }
    };
    let best = best_ltca(&ltca);
    let plots = plot::plot_error_vs_time(out, &fe, &ltca, &reference.label).unwrap_or_else(|e| {
        say(format!("plots not written: {e}"));
        Vec::new()
    });
    let mut md = markdown(
        &scene.source,
        &angles,
        &fe,
        &ltca,
        &reference,
        &flank_positions,
        extrapolated.as_ref(),
        pmax_ref.is_some(),
    );
    if ltca_mu.max(fe_mu) > 0.0 {
        friction_table(
            &mut md,
            ltca_mu.max(fe_mu),
            fe.iter().chain(&ltca),
            &reference,
        );
    }
    let per_position = position_errors(&angles, &best, &reference, extrapolated.as_ref());
    position_table(
        &mut md,
        &best.label,
        &per_position,
        [targets.load_sharing_rel_err, targets.te_rel_err],
    );
    if let Some(x) = &pmax_ref {
        pmax_reference::markdown(&mut md, x, &pmax_runs);
    }
    crate::atomic_file::write(&out.join("compare.md"), &md)?;
    let kind = if bevel {
        CompareKind::Bevel(Box::new(bevel_kind(&base)?))
    } else {
        CompareKind::Cylindrical(Box::new(CylindricalCompare {
            flank_contact_positions: flank_positions.iter().filter(|&&b| b).count(),
            pmax_uniform_fe_rel_err: best.pmax_uniform_fe_rel_err,
            pmax_contact_band: pmax_ref.map(|x| PmaxContactBand {
                reference: x.pairs,
                ltca: pmax_runs,
            }),
            fe_friction_mu: fe_mu,
            ltca_compliance: base.setup.clone(),
        }))
    };
    let summary = CompareSummary {
        header: scene.summary_header(),
        positions: angles.len(),
        roll_angles_deg: angles,
        reference: reference.label.clone(),
        reference_extrapolated: extrapolated,
        best_ltca: best.label.clone(),
        load_sharing_rel_err: best.load_sharing_err,
        te_rel_err: best.te_rel_err,
        pmax_rel_err: best.pmax_rel_err,
        pmax_reference: pmax_against,
        tangential_force_rel_err: best.tangential_force_err,
        friction_mu: ltca_mu,
        ltca_cycle_s: best.cycle_s,
        fe_cycle_s: reference.cycle_s,
        fe_setup_s: reference.setup_s,
        speedup: reference.cycle_s / best.cycle_s,
        targets,
        ltca_settings: base.settings.clone(),
        runs: fe.iter().chain(ltca.iter()).cloned().collect(),
        best_ltca_per_position: per_position,
        files: CompareFiles {
            markdown: "compare.md".into(),
            plots,
        },
        kind,
    };
    summary.write(out)?;
    Ok(summary)
}
