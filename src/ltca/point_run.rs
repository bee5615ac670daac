//! The `flank ltca` run of a bevel/hypoid scene: the cycle of
//! [`LtcaCycle`] over one pitch of the point TCA's grid (positions where no
//! tooth pair of the sector is in contact are gaps, listed), for each
//! edge-contact variant the scene asks for, and the figures only a
//! point-contact pair has: the functional contact ratio and load-sharing
//! zones over the pitch, seed 003's quadratic TE fit, the torque balance,
//! loaded axis ends and flank edges, pairs beyond the sector.
//!
//! Outputs (`out`): the files of every pair kind's LTCA
//! ([`crate::ltca::outputs`]: `ltca_cycle.csv` per position,
//! `ltca_positions.csv` per position and tooth pair, `ltca_points.csv` the
//! load along every axis), `summary.json` (the serialization of
//! [`LtcaResult`]); with `edges = both` the CSVs of each variant in
//! `out/with_edges/` and `out/without_edges/`, and summary.json with one
//! object per variant under `with_edges` and `without_edges`.

use std::time::Instant;

use crate::error::FlankError;
use crate::fem::static_analysis::peak_memory_mb;
use crate::geometry::gear_pair::GearPair;
use crate::ltca::cycle::{LtcaCycle, LtcaOptions};
use crate::ltca::lubricated::LubricatedSettings;
use crate::ltca::model::PositionResult;
use crate::ltca::outputs::{write_cycle_csv, write_points_csv, write_positions_csv};
use crate::ltca::summary::{
    peak_to_peak, shares, BevelLtcaSummary, EdgeVariantRatios, EdgeVariantSummaries, KindSummary,
    LtcaResult, LtcaStep, LtcaSummary,
};
use crate::scene::Scene;
use crate::tca::point_candidates::PointCandidates;

/// `flank ltca` on a bevel/hypoid scene: the cycle's positions, the files
/// of the module docs, for each variant of [`LtcaOptions::edges`] (else
/// the scene's), with the wet–dry loop's settings if it runs (`options`
/// are then its dry pass's); returns the summary.
pub fn run_point(
    scene: &Scene,
    options: &LtcaOptions,
    lubricated: Option<&LubricatedSettings>,
) -> Result<LtcaResult, FlankError> {
    let t_total = Instant::now();
    let first = LtcaCycle::new(scene, options)?;
    let out = &options.out;
    std::fs::create_dir_all(out).map_err(|e| FlankError::io(out, e))?;
    let a = scene.analyses.ltca.clone().unwrap_or_default();
    let runs = options
        .edges
        .or(a.edges)
        .unwrap_or(crate::settings::EdgeVariants::Without)
        .runs();
    let compliance_s = first.setup.compliance_s;
    if runs.len() == 1 {
        let mut s = run_variant(
            scene,
            &first,
            options,
            lubricated,
            out,
            runs[0].1,
            compliance_s,
        )?;
        s.total_s = t_total.elapsed().as_secs_f64();
        let result = LtcaResult::Cycle(Box::new(s));
        result.write(out)?;
        return Ok(result);
    }
    let mut variants = Vec::new();
    for (edges, name) in runs {
        let other;
        // the other variant's tensors cost nothing more
        let (cycle, setup_s) = if edges == first.point()?.edges {
            (&first, compliance_s)
        } else {
            other = first.with_edges(edges, scene.load.speed_rpm)?;
            (&other, 0.0)
        };
        let dir = out.join(name);
        std::fs::create_dir_all(&dir).map_err(|e| FlankError::io(&dir, e))?;
        variants.push(run_variant(
            scene, cycle, options, lubricated, &dir, name, setup_s,
        )?);
    }
    let (Some(without_edges), Some(with_edges)) = (variants.pop(), variants.pop()) else {
        return Err(FlankError::Model(
            "LTCA: --edges both ran fewer than two variants".into(),
        ));
    };
    let ratio = |s: &LtcaSummary| match &s.kind {
        KindSummary::Bevel(b) => b.functional_contact_ratio,
        KindSummary::Cylindrical(_) => None,
    };
    let result = LtcaResult::EdgeVariants(Box::new(EdgeVariantSummaries {
        header: scene.summary_header(),
        analysis: "ltca_bevel_cycle",
        edges: "both",
        compliance_s,
        flank_nodes: first.setup.flank_nodes,
        functional_contact_ratio: EdgeVariantRatios {
            with_edges: ratio(&with_edges),
            without_edges: ratio(&without_edges),
        },
        with_edges,
        without_edges,
        total_s: t_total.elapsed().as_secs_f64(),
        peak_memory_mb: peak_memory_mb(),
    }));
    result.write(out)?;
    Ok(result)
}

/// One variant's cycle: its CSVs in `out`, its summary returned
/// (`compliance_s`: what its tensors cost).
fn run_variant(
    scene: &Scene,
    cycle: &LtcaCycle,
    options: &LtcaOptions,
    lubricated: Option<&LubricatedSettings>,
    out: &std::path::Path,
    variant: &'static str,
    compliance_s: f64,
) -> Result<LtcaSummary, FlankError> {
    let t_variant = Instant::now();
    let point = cycle.point()?;
    let pitch = point.cycle_deg();
    let requested = options.roll_angles_deg.clone().or(scene
        .analyses
        .ltca
        .as_ref()
        .and_then(|a| a.roll_angles_deg.clone()));
    let default_cycle = requested.is_none();
    let rolls = requested.unwrap_or_else(|| point.cycle_rolls_deg());
    let t_cycle = Instant::now();
    let solved = cycle.solve_cycle_gaps(&rolls)?;
    let cycle_s = t_cycle.elapsed().as_secs_f64();
    let gaps: Vec<f64> = rolls
        .iter()
        .zip(&solved)
        .filter(|(_, r)| r.is_none())
        .map(|(&x, _)| x)
        .collect();
    let mut results: Vec<PositionResult> = solved.iter().flatten().cloned().collect();
    let np = cycle.pair.sector_teeth();
    let mut lubrication = None;
    if let Some(l) = lubricated {
        if !gaps.is_empty() {
            return Err(FlankError::Model(format!(
                "[analyses.lubrication]: no tooth pair of the sector is in contact at {} of the {} roll angles ({:?}°): the wet–dry loop needs a contact at every position",
                gaps.len(),
                rolls.len(),
                gaps
            )));
        }
        let dry = std::mem::take(&mut results);
        let lc = crate::ltca::lubricated::lubricated_cycle(cycle, scene, l, dry, &rolls, out)?;
        results = lc.results;
        lubrication = Some(lc.summary);
    }
    let ratio = cycle.pair.ratio();
    let steps: Vec<LtcaStep> = results
        .iter()
        .map(|r| LtcaStep::new(r.clone(), np, ratio))
        .collect();
    let mut notes = Vec::new();
    let te: Vec<f64> = steps.iter().map(|s| s.te_arcsec).collect();
    let te_urad: Vec<f64> = results.iter().map(|r| r.te_urad).collect();
    let mut edge_loaded = 0usize;
    let mut beyond = 0usize;
    let mut beyond_rolls = Vec::new();
    for r in &results {
        // a loaded end point: where the axis kept all K points the span is
        // too short; where the flank's edge clipped it the contact reaches
        // that edge (counted)
        for (li, line) in r.lines.iter().enumerate() {
            let loads: Vec<f64> = r
                .points
                .iter()
                .filter(|q| q.line == li)
                .map(|q| q.force_n)
                .collect();
            let end_loaded = loads.len() > 2
                && [loads.first(), loads.last()]
                    .iter()
                    .any(|e| e.is_some_and(|&x| x > 0.0));
            if !end_loaded {
                continue;
            }
            if loads.len() == point.points_per_pair {
                notes.push(format!(
                    "{:.3}°: pinion tooth {} carries load at an end of its candidate axis: raise --span-approach-mm",
                    r.roll_deg, line.0
                ));
            } else {
                edge_loaded += 1;
            }
        }
        notes.extend(
            r.warnings
                .iter()
                .map(|w| format!("{:.3}°: {w}", r.roll_deg)),
        );
        for (offset, sep) in point.beyond_sector(r.roll_deg, r.loaded_approach_mm) {
            beyond += 1;
            beyond_rolls.push(format!(
                "{:.3}° (pair {offset}: {:.1} µm < {:.1} µm)",
                r.roll_deg,
                1e3 * sep,
                1e3 * r.loaded_approach_mm
            ));
        }
        if !r.kkt_within_tolerance {
            notes.push(format!(
                "{:.3}°: {} residual {:.2e} above tolerance",
                r.roll_deg,
                if r.friction.is_some() {
                    "friction"
                } else {
                    "KKT"
                },
                r.kkt_max
            ));
        }
    }
    if !beyond_rolls.is_empty() {
        notes.push(format!(
            "a pair outside the {np}-tooth sector (not modelled; pitches from the middle pair) lies within the loaded approach at {} of {} positions: {} (its unloaded separation < the loaded approach (θ − θ₀) r): raise [mesh] teeth_in_sector",
            beyond_rolls.len(),
            results.len(),
            beyond_rolls.join(", ")
        ));
    }
    let loops = crate::ltca::outputs::iteration_limits(&results);
    notes.extend(loops.warnings());
    let mates: Vec<usize> = (1..=np).map(|k| cycle.pair.mate(k)).collect();
    write_cycle_csv(&out.join("ltca_cycle.csv"), &steps, np)?;
    write_positions_csv(&out.join("ltca_positions.csv"), &steps, &mates)?;
    write_points_csv(&out.join("ltca_points.csv"), &results)?;
    let plots = plot_variant(cycle, out, &results)?;
    let spectra = crate::ltca::outputs::cycle_spectra(cycle, scene, options, &results, &gaps, out)?;
    let worst = |f: fn(&PositionResult) -> f64| results.iter().map(f).fold(0.0f64, f64::max);
    // the functional contact ratio needs the default cycle (positions
    // spread evenly over one pitch)
    // (a position without contact counts with no loaded pair)
    let sharing = default_cycle
        .then(|| {
            let forces: Vec<Vec<f64>> = solved
                .iter()
                .map(|r| match r {
                    Some(r) => cycle.pair_forces(r),
                    None => vec![0.0; np],
                })
                .collect();
            crate::load_sharing::cycle_sharing(&forces, pitch)
        })
        .flatten();
    if !gaps.is_empty() {
        notes.push(format!(
            "no tooth pair of the sector is in contact at {} of {} positions ({}°): the pair cannot carry the torque there{}",
            gaps.len(),
            rolls.len(),
            gaps.iter().map(|g| format!("{g:.3}")).collect::<Vec<_>>().join(", "),
            if point.edges { "" } else { " without edge contact" }
        ));
    }
    let edge_points: usize = results
        .iter()
        .map(|r| {
            r.points
                .iter()
                .filter(|q| r.lines[q.line].2 != "Flank")
                .count()
        })
        .sum();
    let edge_force: f64 = results
        .iter()
        .map(|r| {
            r.line_force_n
                .iter()
                .zip(&r.lines)
                .filter(|(_, l)| l.2 != "Flank")
                .map(|(f, _)| f)
                .sum::<f64>()
        })
        .fold(0.0, f64::max);
    // frictionless: Σ P r = T (with friction the tangential forces take
    // part of the torque)
    let torque_balance = cycle.settings.friction.is_none().then(|| {
        results
            .iter()
            .map(|r| {
                let m: f64 = r.points.iter().map(|q| q.force_n * q.moment_arm_mm).sum();
                (m - cycle.torque).abs() / cycle.torque
            })
            .fold(0.0f64, f64::max)
    });
    Ok(LtcaSummary {
        header: scene.summary_header(),
        analysis: "ltca_bevel_cycle",
        positions: results.len(),
        tooth_pairs: (1..=np).map(|k| (k, cycle.pair.mate(k))).collect(),
        te_peak_to_peak_urad: peak_to_peak(&te_urad),
        te_peak_to_peak_arcsec: peak_to_peak(&te),
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
            .map(|f| crate::ltca::outputs::friction_summary(&results, f, cycle.torque)),
        lubrication,
        settings: cycle.settings.clone(),
        cycle_s,
        time_per_position_s: cycle_s / results.len().max(1) as f64,
        total_s: t_variant.elapsed().as_secs_f64(),
        peak_memory_mb: peak_memory_mb(),
        notes,
        kind: KindSummary::Bevel(Box::new(BevelLtcaSummary {
            edges: variant,
            edge_contact: point.edges,
            mesh_cycle_deg: pitch,
            torque_nm: cycle.torque / 1000.0,
            points_per_pair: point.points_per_pair,
            span_approach_mm: point.span_approach_mm,
            approach_mm: point.tca.settings.approach_mm,
            friction_mu: cycle.settings.friction.as_ref().map_or(0.0, |f| f.mu),
            increments: cycle
                .settings
                .friction
                .as_ref()
                .and_then(|f| f.increment_count()),
            flank_nodes: cycle.setup.flank_nodes,
            // seed 003's Δθ(φ) = a₀ + a₁φ + a₂φ² (φ pinion roll in °, Δθ at
            // the gear in ″)
            te_quadratic_fit: crate::ltca::te_fit::quadratic_te_fit(
                &results.iter().map(|r| r.roll_deg).collect::<Vec<_>>(),
                &te,
            ),
            max_torque_balance_error: torque_balance,
            pairs_loaded_at_a_flank_edge: edge_loaded,
            pairs_beyond_sector_within_approach: beyond,
            positions_without_contact_deg: gaps,
            edge_candidate_points: edge_points,
            max_edge_force_n: edge_force,
            functional_contact_ratio: sharing.as_ref().map(|s| s.functional_contact_ratio),
            load_sharing: sharing,
            tca_contact_ratio: point.tca.contact_ratio,
            tca_transitions: point.tca.transitions.clone(),
            compliance_s,
            tca_s: point.trace_s,
            plots,
        })),
        steps,
    })
}

/// `load_sharing.{svg,png}` (share of each pinion tooth against roll),
/// `transmission_error.{svg,png}` (loaded and unloaded TE, gear arcsec),
/// the loaded contact pattern on both drive flanks
/// (`contact_pattern_{pinion,gear}.{svg,png}`: every loaded candidate
/// point of the cycle at its place in the axial projection, coloured by
/// its Hertz pressure, as the FE cycle draws its nodes) and, with friction,
/// `friction_power.{svg,png}` (Σ |P_t v_s| per position) in `out`; returns
/// the file names.
fn plot_variant(
    cycle: &LtcaCycle,
    out: &std::path::Path,
    results: &[PositionResult],
) -> Result<Vec<String>, FlankError> {
    use crate::report::cycle_plot::plot_series;
    let point = cycle.point()?;
    let np = cycle.pair.sector_teeth();
    let shares: Vec<Vec<f64>> = results
        .iter()
        .map(|r| shares(&cycle.pair_forces(r)))
        .collect();
    let curves: Vec<(String, Vec<(f64, f64)>)> = (0..np)
        .filter(|&p| shares.iter().any(|s| s[p] > 0.0))
        .map(|p| {
            (
                format!(
                    "pinion tooth {} / gear tooth {}",
                    p + 1,
                    cycle.pair.mate(p + 1)
                ),
                results
                    .iter()
                    .zip(&shares)
                    .map(|(r, s)| (r.roll_deg, s[p]))
                    .collect(),
            )
        })
        .collect();
    let variant = if point.edges {
        "with edge contact"
    } else {
        "without edge contact"
    };
    let mut files = plot_series(
        out,
        "load_sharing",
        &format!("Load share per tooth pair, {variant}"),
        "pinion roll angle (deg)",
        "share of the normal force",
        &curves,
    )?;
    let arcsec = |x: f64| crate::load_sharing::te_arcsec_at_gear(x, cycle.pair.ratio());
    files.extend(plot_series(
        out,
        "transmission_error",
        &format!("Transmission error at the gear, {variant}"),
        "pinion roll angle (deg)",
        "TE (arcsec)",
        &[
            (
                "loaded".into(),
                results
                    .iter()
                    .map(|r| (r.roll_deg, arcsec(r.te_urad)))
                    .collect(),
            ),
            (
                "unloaded".into(),
                results
                    .iter()
                    .map(|r| (r.roll_deg, arcsec(r.unloaded_te_urad)))
                    .collect(),
            ),
        ],
    )?);
    files.extend(crate::report::fe_pattern::plot_pattern(
        out,
        point.pair.as_ref(),
        &pattern_points(point, results),
        "LTCA",
    )?);
    if cycle.settings.friction.is_some() {
        files.extend(plot_series(
            out,
            "friction_power",
            &format!("Friction power loss Σ |P_t v_s|, {variant}"),
            "pinion roll angle (deg)",
            "power loss (W)",
            &[(
                "all tooth pairs".into(),
                results
                    .iter()
                    .map(|r| (r.roll_deg, r.friction_power_w))
                    .collect(),
            )],
        )?);
    }
    Ok(files)
}

/// The loaded candidate points of the cycle in each member's axial
/// projection (the FE pattern's coordinates,
/// [`crate::tca::point_contact::projection`]): the global point taken back
/// into each member's own frame at its position.
fn pattern_points(
    point: &PointCandidates,
    results: &[PositionResult],
) -> Vec<crate::report::fe_pattern::PatternNode> {
    use crate::tca::point_contact::projection;
    let own = |f: &crate::geometry::frame::Frame, x: [f64; 3]| {
        f.rotate_back([
            x[0] - f.translation[0],
            x[1] - f.translation[1],
            x[2] - f.translation[2],
        ])
    };
    results
        .iter()
        .flat_map(|r| {
            let frames = point.pair.frames(r.roll_deg.to_radians());
            r.points
                .iter()
                .filter(|q| q.force_n > 0.0)
                .map(|q| crate::report::fe_pattern::PatternNode {
                    pair: r.lines[q.line].0,
                    projection_mm: [
                        projection(point.pair.pinion(), own(&frames[0], q.position)),
                        projection(point.pair.gear(), own(&frames[1], q.position)),
                    ],
                    pressure_mpa: q.pressure_mpa,
                })
                .collect::<Vec<_>>()
        })
        .collect()
}
