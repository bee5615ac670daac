//! `flank compare SCENE`: the fast path against the reference, error
//! against run time (DESIGN.md, verification rung 5).
//!
//! The LTCA (at several K, the compliance tensors computed once and then
//! cached) and FE contact (at several flank element sizes, one
//! factorization per size) are run at the same roll angles. The reference
//! is FE contact extrapolated to h → 0 from the three finest meshes when
//! three or more are given ([`reference`](mod@reference): Richardson per position and
//! pair, with the GCI as its uncertainty), else the finest mesh. Errors,
//! over the positions:
//!
//! * load sharing: max |s_L − s_F| over positions and pairs, s the pair's
//!   share of the total normal force (a share is already relative to the
//!   total load, so this is the error relative to the total);
//! * TE: max |θ_L − θ_F| / |θ_F| over positions;
//! * p_max: max |p_L − p_F| / p_F over the *flank-contact* positions, where
//!   every loaded pair's kinematic contact lies inside its path of contact
//!   (at a tip corner the pressure of a sharp edge is not a mesh-independent
//!   quantity in either method: FE gives a mesh-dependent nodal value, the
//!   LTCA's Hertz formula none);
//! * with friction (`--friction-mu` μ > 0, both methods at that μ): the
//!   tangential force, max |P_t,L − P_t,F| / Σ P_n,F over positions and
//!   pairs, relative to the reference's total normal force like the shares
//!   (the reference's P_t is the finest run's, not extrapolated);
//!
//! and the run time of a cycle: LTCA = Σ position solves with the tensors
//! in memory (`ltca_cycle_s`); FE = Σ position solves (`fe_cycle_s`) plus
//! the one factorization (`fe_setup_s`).

use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::compliance::body::BodyMeshOptions;
use crate::error::FlankError;
use crate::ltca::cycle::{LtcaCycle, LtcaOptions};
use crate::ltca::model::PositionResult;
use crate::mesh_cycle::run::{settings, RunOptions};
use crate::scene::Scene;
use crate::settings::SlaveBody;

pub mod bevel;
pub mod method_run;
pub mod plot;
pub mod pmax_reference;
pub mod reference;
pub mod run;
pub mod summary;

use crate::mesh_cycle::cycle::{MeshCycle, StepResult};
use method_run::shares;
pub use method_run::MethodRun;
use reference::{extrapolate, ExtrapolatedReference};
use summary::PositionError;

/// Options of [`run::compare`] (any pair kind).
#[derive(Clone, Debug)]
pub struct CompareOptions {
    pub out: PathBuf,
    /// K values of the LTCA runs.
    pub points_per_line: Vec<usize>,
    /// Flank element sizes (mm) of the FE-contact runs; the smallest is the reference.
    pub fe_flank_sizes: Vec<f64>,
    /// Base element size of the FE-contact runs (mm); default the scene's.
    pub fe_base_size: Option<f64>,
    /// Roll angles (deg); default: the middle pair's engagement ± 2 steps.
    pub roll_angles_deg: Option<Vec<f64>>,
    pub roll_step_deg: f64,
    /// LTCA compliance mesh and settings.
    pub ltca: LtcaOptions,
    pub threads: usize,
    pub quiet: bool,
    /// Coulomb friction coefficient of both methods' flanks (`--friction-mu`;
    /// `None`: each method's scene setting, 0 without one). With μ > 0 the
    /// tangential force per pair is compared too.
    pub friction_mu: Option<f64>,
    /// Contact-band FE runs (`contact_band.json` files or their
    /// directories) as the p_max reference ([`pmax_reference`]); empty: p_max
    /// against the finest uniform FE run only.
    pub pmax_reference: Vec<PathBuf>,
}

/// `flank compare`'s defaults: K = 5, 10, 20, 40; FE flank elements of
/// 1.0 and 0.5 mm; roll step 1°; output `out`.
impl Default for CompareOptions {
    fn default() -> Self {
        CompareOptions {
            out: PathBuf::from("out"),
            points_per_line: vec![5, 10, 20, 40],
            fe_flank_sizes: vec![1.0, 0.5],
            fe_base_size: None,
            roll_angles_deg: None,
            roll_step_deg: 1.0,
            ltca: LtcaOptions::default(),
            threads: 0,
            quiet: false,
            friction_mu: None,
            pmax_reference: Vec::new(),
        }
    }
}

impl CompareOptions {
    /// Checks the run lists and the step before anything runs.
    pub fn validate(&self) -> Result<(), FlankError> {
        if self.points_per_line.is_empty() || self.fe_flank_sizes.is_empty() {
            return Err(FlankError::Model(
                "compare needs at least one K (--points-per-line) and one FE flank size (--fe-flank-sizes)"
                    .into(),
            ));
        }
        if let Some(&k) = self
            .points_per_line
            .iter()
            .find(|&&k| !(2..=2000).contains(&k))
        {
            return Err(FlankError::Model(format!(
                "--points-per-line: points per line must be in 2 … 2000, got {k}"
            )));
        }
        if let Some(&h) = self
            .fe_flank_sizes
            .iter()
            .find(|&&h| !(h > 0.0 && h.is_finite()))
        {
            return Err(FlankError::Model(format!(
                "--fe-flank-sizes: FE flank sizes must be > 0, got {h}"
            )));
        }
        if let Some(mu) = self.friction_mu {
            if !(mu.is_finite() && (0.0..=1.0).contains(&mu)) {
                return Err(FlankError::Model(format!(
                    "--friction-mu {mu}: a coefficient in [0, 1] is needed"
                )));
            }
        }
        if !(self.roll_step_deg > 0.0 && self.roll_step_deg.is_finite()) {
            return Err(FlankError::Model(format!(
                "--roll-step: the roll step must be > 0, got {}",
                self.roll_step_deg
            )));
        }
        Ok(())
    }
}

/// An FE step's friction force per pair, padded with zeros to its
/// `pairs` (a frictionless step has none).
pub(crate) fn per_pair(friction_n: &[f64], pairs: usize) -> Vec<f64> {
    let mut t = friction_n.to_vec();
    t.resize(pairs, 0.0);
    t
}

/// The LTCA run with the smallest worst relative error (load sharing or
/// TE); the first of equals.
pub(crate) fn best_ltca(runs: &[MethodRun]) -> MethodRun {
    runs.iter()
        .min_by(|a, b| {
            let ea = a.load_sharing_err.max(a.te_rel_err);
            let eb = b.load_sharing_err.max(b.te_rel_err);
            ea.total_cmp(&eb)
        })
        .cloned()
        .expect("one K")
}

/// The reference of a comparison: FE contact extrapolated to h → 0 from
/// the three finest runs when `fe` (coarse to fine) holds three or more
/// ([`reference`]), else the finest run.
pub(crate) fn reference_of(fe: &[MethodRun]) -> (MethodRun, Option<ExtrapolatedReference>) {
    match extrapolate(fe) {
        Some(x) => (x.run.clone(), Some(x)),
        None => (fe.last().cloned().expect("one FE size"), None),
    }
}

/// Fills the errors of `run` against `reference` (positions where the
/// reference's pressure counts are flagged in `flank_positions`).
pub(crate) fn errors(run: &mut MethodRun, reference: &MethodRun, flank_positions: &[bool]) {
    let mut ls: f64 = 0.0;
    let mut te: f64 = 0.0;
    let mut pm: f64 = 0.0;
    let mut pt: f64 = 0.0;
    let frictional = !reference.pair_tangential_n.is_empty()
        && reference
            .pair_tangential_n
            .iter()
            .flatten()
            .any(|&t| t > 0.0);
    for i in 0..reference.te_urad.len() {
        let (a, b) = (
            shares(&run.pair_force_n[i]),
            shares(&reference.pair_force_n[i]),
        );
        for (x, y) in a.iter().zip(&b) {
            ls = ls.max((x - y).abs());
        }
        te = te.max((run.te_urad[i] - reference.te_urad[i]).abs() / reference.te_urad[i].abs());
        if flank_positions[i] && reference.pmax_mpa[i] > 0.0 {
            pm = pm.max((run.pmax_mpa[i] - reference.pmax_mpa[i]).abs() / reference.pmax_mpa[i]);
        }
        if frictional {
            let total: f64 = reference.pair_force_n[i].iter().sum();
            let zero = Vec::new();
            let a = run.pair_tangential_n.get(i).unwrap_or(&zero);
            for (p, y) in reference.pair_tangential_n[i].iter().enumerate() {
                let x = a.get(p).copied().unwrap_or(0.0);
                if total > 0.0 {
                    pt = pt.max((x - y).abs() / total);
                }
            }
        }
    }
    run.load_sharing_err = ls;
    run.te_rel_err = te;
    run.pmax_rel_err = pm;
    run.pmax_uniform_fe_rel_err = pm;
    run.tangential_force_err = if frictional { pt } else { f64::NAN };
}

/// One LTCA run over `angles` as `flank ltca` runs a cycle (the
/// positions side by side), `setup_s` the time of its tensors and TCA.
pub(crate) fn ltca_run(
    cycle: &LtcaCycle,
    angles: &[f64],
    setup_s: f64,
) -> Result<MethodRun, FlankError> {
    let t = Instant::now();
    let results: Vec<PositionResult> = cycle.solve_cycle(angles)?;
    let cycle_s = t.elapsed().as_secs_f64();
    Ok(MethodRun {
        method: "ltca".into(),
        label: format!("LTCA K = {}", cycle.points_per_line),
        points_per_line: Some(cycle.points_per_line),
        flank_size_mm: Some(cycle.setup.flank_size_mm).filter(|h| h.is_finite()),
        nodes: None,
        pair_force_n: results.iter().map(|r| cycle.pair_forces(r)).collect(),
        pair_tangential_n: results
            .iter()
            .map(|r| cycle.pair_friction(r).iter().map(|t| t.abs()).collect())
            .collect(),
        te_urad: results.iter().map(|r| r.te_urad).collect(),
        pmax_mpa: results.iter().map(|r| r.max_pressure_mpa).collect(),
        cycle_s,
        setup_s,
        slave: Vec::new(),
        load_sharing_err: f64::NAN,
        te_rel_err: f64::NAN,
        pmax_rel_err: f64::NAN,
        pmax_uniform_fe_rel_err: f64::NAN,
        tangential_force_err: f64::NAN,
    })
}

/// An FE contact run of flank size `size`: the factorized `cycle` (built in
/// `setup_s`) solved at `angles`, timed, with the forces, friction, TE
/// (µrad, pinion), p_max and slave bodies per position.
pub(crate) fn fe_method_run(
    size: f64,
    cycle: &MeshCycle,
    angles: &[f64],
    setup_s: f64,
) -> Result<MethodRun, FlankError> {
    let t = Instant::now();
    let steps: Vec<StepResult> = angles
        .iter()
        .map(|&a| cycle.solve(a).map(|s| s.step))
        .collect::<Result<_, _>>()?;
    let cycle_s = t.elapsed().as_secs_f64();
    let slave = steps
        .iter()
        .map(|s| {
            s.slave
                .iter()
                .map(|b| match b {
                    SlaveBody::Gear => "gear",
                    _ => "pinion",
                })
                .collect::<Vec<_>>()
                .join("/")
        })
        .collect();
    Ok(MethodRun {
        method: "fe_contact".into(),
        label: format!("FE flank {size} mm"),
        points_per_line: None,
        flank_size_mm: Some(size),
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
        slave,
        load_sharing_err: f64::NAN,
        te_rel_err: f64::NAN,
        pmax_rel_err: f64::NAN,
        pmax_uniform_fe_rel_err: f64::NAN,
        tangential_force_err: f64::NAN,
    })
}

/// FE contact at flank size `size` over `angles`, with the FE driver's
/// slave rule `auto` ([`SlaveBody::Auto`]): node-to-surface contact is
/// one-sided (slave nodes slip past a master corner, FE-contact README), so
/// each tooth pair's slave is the body whose tip edge is in play, the gear
/// before the pair's kinematic start and the pinion from then on, with the
/// driver's retry when pinion nodes are cut just after the start. The
/// slave of every pair at every position is recorded.
fn fe_run(
    scene: &Scene,
    (size, base): (f64, Option<f64>),
    angles: &[f64],
    threads: usize,
    friction_mu: Option<f64>,
) -> Result<MethodRun, FlankError> {
    let o = RunOptions {
        roll_angles_deg: Some(angles.to_vec()),
        friction_mu,
        vtu: Some(false),
        refine_contact_limits: Some(false),
        slave: Some(SlaveBody::Auto),
        threads,
        quiet: true,
        ..Default::default()
    };
    let s = settings(scene, &o)?;
    let mesh = BodyMeshOptions {
        flank_size: Some(size),
        base_size: base,
        ..Default::default()
    };
    let t = Instant::now();
    let cycle = MeshCycle::new(scene, &mesh, s, threads)?;
    fe_method_run(size, &cycle, angles, t.elapsed().as_secs_f64())
}

/// [`fe_run`] through a file cache in `dir`: a run is reused when the
/// scene text, the flank size, the roll angles and the slave rule are the
/// same (so the LTCA side of a comparison can be redone without the FE
/// runs; runs cached under an older slave rule are not reused).
pub(crate) fn fe_run_cached(
    scene: &Scene,
    (size, base): (f64, Option<f64>),
    angles: &[f64],
    threads: usize,
    friction_mu: Option<f64>,
    dir: &Path,
) -> Result<(MethodRun, bool), FlankError> {
    let text = std::fs::read_to_string(&scene.source).unwrap_or_default();
    let base_key = base.map(|b| format!("\nbase {b}")).unwrap_or_default();
    // μ from the command line is part of the key (none: the scene's, in `text`)
    let mu_key = friction_mu.map(|m| format!("\nmu {m}")).unwrap_or_default();
    let key = format!(
        "{text}\n{size}\n{angles:?}\n{}{base_key}{mu_key}\nslave auto",
        env!("CARGO_PKG_VERSION")
    );
    let mut h = crate::compliance::Fnv128::new();
    h.bytes(key.as_bytes());
    let file = dir.join(format!("fe_flank_{size}_{}.json", h.hex()));
    if let Ok(t) = std::fs::read_to_string(&file) {
        if let Ok(r) = serde_json::from_str::<MethodRun>(&t) {
            return Ok((r, true));
        }
    }
    let r = fe_run(scene, (size, base), angles, threads, friction_mu)?;
    std::fs::create_dir_all(dir).map_err(|e| FlankError::io(dir, e))?;
    let t = serde_json::to_string(&r).map_err(|e| FlankError::Model(e.to_string()))?;
    crate::atomic_file::write(&file, t)?;
    Ok((r, false))
}

#[allow(clippy::too_many_arguments)]
pub(crate) fn markdown(
    source: &Path,
    angles: &[f64],
    fe: &[MethodRun],
    ltca: &[MethodRun],
    reference: &MethodRun,
    flank_positions: &[bool],
    extrapolated: Option<&ExtrapolatedReference>,
    pmax_bands: bool,
) -> String {
    use std::fmt::Write;
    let mut s = String::new();
    let _ = writeln!(s, "# LTCA against FE contact: {}\n", source.display());
    let _ = writeln!(
        s,
        "{} roll angles from {:.2}° to {:.2}°; reference: {} ({} positions with flank contact only, where p_max is compared).\n",
        angles.len(),
        angles.first().copied().unwrap_or(f64::NAN),
        angles.last().copied().unwrap_or(f64::NAN),
        reference.label,
        flank_positions.iter().filter(|&&b| b).count()
    );
    let finest = fe.last().map_or(String::new(), |r| r.label.clone());
    if pmax_bands {
        let _ = writeln!(s, "| run | load sharing err | TE rel err | p_max rel err (contact bands) | p_max rel err vs uniform {finest} | cycle (s) | per position (s) | setup (s) |");
        let _ = writeln!(s, "|---|---:|---:|---:|---:|---:|---:|---:|");
    } else {
        let _ = writeln!(s, "| run | load sharing err | TE rel err | p_max rel err | cycle (s) | per position (s) | setup (s) |");
        let _ = writeln!(s, "|---|---:|---:|---:|---:|---:|---:|");
    }
    for r in fe.iter().chain(ltca) {
        let pmax = match (pmax_bands, r.method.as_str()) {
            (false, _) => format!("{:.4}", r.pmax_rel_err),
            (true, "ltca") => format!("{:.4} | {:.4}", r.pmax_rel_err, r.pmax_uniform_fe_rel_err),
            (true, _) => format!("— | {:.4}", r.pmax_uniform_fe_rel_err),
        };
        let _ = writeln!(
            s,
            "| {} | {:.4} | {:.4} | {pmax} | {:.4} | {:.5} | {:.1} |",
            r.label,
            r.load_sharing_err,
            r.te_rel_err,
            r.cycle_s,
            r.cycle_s / angles.len().max(1) as f64,
            r.setup_s
        );
    }
    if pmax_bands {
        let _ = writeln!(s, "\np_max: the LTCA rows' p_max error is against the contact-band FE reference at its own roll angles (section \"p_max against the contact-band FE reference\" below); the column \"vs uniform {finest}\" is against the finest uniform FE run's p_max at the flank-contact positions of the roll grid, a mesh that does not resolve the Hertz width (kept for the record, not an LTCA error).");
    }
    let pmax_uniform = if pmax_bands {
        "p_max against uniform FE (its column)"
    } else {
        "p_max"
    };
    match extrapolated {
        None => {
            let _ = writeln!(s, "\nErrors are against {}; its own row is zero by definition. Load sharing: max |share difference| (fraction of the total normal force); TE: max relative difference; {pmax_uniform}: max relative difference over the flank-contact positions.", reference.label);
        }
        Some(x) => {
            let _ = writeln!(s, "\nErrors are against {}: per position and pair the Richardson-extrapolated load share, and the extrapolated TE (Celik et al. 2008); every FE row, the finest included, is measured against it. {pmax_uniform} is not extrapolated: its reference is the finest run's. Load sharing: max |share difference| (fraction of the total normal force); TE: max relative difference; {pmax_uniform}: max relative difference over the flank-contact positions.", reference.label);
            let _ = writeln!(
                s,
                "\nUncertainty of the reference (GCI_fine, F_s = 1.25): load share ≤ {:.4}, TE ≤ {:.3} %; {} of the figures gave no trusted estimate (no order, or one outside 0.5–4) and keep the finest value with 3 × the spread of the three grids as uncertainty ({} of them did not change between the grids: a pair out of mesh). An LTCA error below the uncertainty is not resolved by this reference.",
                x.max_share_uncertainty,
                100.0 * x.max_te_uncertainty,
                x.fallbacks,
                x.unchanged
            );
        }
    }
    s
}

/// Per position, `run` against `reference` ([`PositionError`]).
pub(crate) fn position_errors(
    angles: &[f64],
    run: &MethodRun,
    reference: &MethodRun,
    extrapolated: Option<&ExtrapolatedReference>,
) -> Vec<PositionError> {
    (0..reference.te_urad.len())
        .map(|i| {
            let (a, b) = (
                shares(&run.pair_force_n[i]),
                shares(&reference.pair_force_n[i]),
            );
            let share_err = a
                .iter()
                .zip(&b)
                .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
            let (su, tu) = extrapolated.map_or((f64::NAN, f64::NAN), |x| {
                (
                    x.share_uncertainty[i].iter().copied().fold(0.0, f64::max),
                    x.te_uncertainty[i],
                )
            });
            PositionError {
                roll_deg: angles.get(i).copied().unwrap_or(f64::NAN),
                reference_shares: b,
                reference_te_urad: reference.te_urad[i],
                share_err,
                te_rel_err: (run.te_urad[i] - reference.te_urad[i]) / reference.te_urad[i].abs(),
                share_uncertainty: su,
                te_uncertainty: tu,
            }
        })
        .collect()
}

/// The per-position section of `compare.md` for `label` (the best LTCA),
/// with the count of positions within the targets `[share, te]` (absolute
/// load share, relative TE).
pub(crate) fn position_table(
    s: &mut String,
    label: &str,
    rows: &[PositionError],
    [share_target, te_target]: [f64; 2],
) {
    use std::fmt::Write;
    let within = rows
        .iter()
        .filter(|r| r.share_err <= share_target && r.te_rel_err.abs() <= te_target)
        .count();
    let _ = writeln!(
        s,
        "
## Per position: {label} against the reference
"
    );
    let _ = writeln!(
        s,
        "{within} of {} positions within both targets (load sharing {share_target}, TE {} %).\n",
        rows.len(),
        100.0 * te_target
    );
    let _ = writeln!(
        s,
        "| roll (°) | reference shares | share err | ref. share unc. | TE ref. (µrad) | TE err | ref. TE unc. |"
    );
    let _ = writeln!(s, "|---:|---|---:|---:|---:|---:|---:|");
    for r in rows {
        let shares: Vec<String> = r
            .reference_shares
            .iter()
            .map(|x| format!("{x:.3}"))
            .collect();
        let _ = writeln!(
            s,
            "| {:.2} | {} | {:.4} | {:.4} | {:.1} | {:+.2} % | {:.2} % |",
            r.roll_deg,
            shares.join(" / "),
            r.share_err,
            r.share_uncertainty,
            r.reference_te_urad,
            100.0 * r.te_rel_err,
            100.0 * r.te_uncertainty
        );
    }
}

/// The friction rows of `compare.md`: per run the total normal force, the
/// friction/normal ratio and the tangential force error against the
/// reference, with the caption that defines them.
pub(crate) fn friction_table<'a>(
    s: &mut String,
    mu: f64,
    runs: impl Iterator<Item = &'a MethodRun>,
    reference: &MethodRun,
) {
    use std::fmt::Write;
    let _ = writeln!(s, "\n## Friction (μ = {mu})\n");
    let _ = writeln!(
        s,
        "| run | Σ P_n mean (N) | Σ P_t / Σ P_n min … max | tangential force err |"
    );
    let _ = writeln!(s, "|---|---:|---:|---:|");
    for r in runs {
        let n: Vec<f64> = r.pair_force_n.iter().map(|f| f.iter().sum()).collect();
        let ratio: Vec<f64> = r
            .pair_tangential_n
            .iter()
            .zip(&n)
            .filter(|(_, &n)| n > 0.0)
            .map(|(t, &n)| t.iter().sum::<f64>() / n)
            .collect();
        let _ = writeln!(
            s,
            "| {} | {:.1} | {:.4} … {:.4} | {:.4} |",
            r.label,
            n.iter().sum::<f64>() / n.len().max(1) as f64,
            ratio.iter().copied().fold(f64::INFINITY, f64::min),
            ratio.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            r.tangential_force_err
        );
    }
    let _ = writeln!(
        s,
        "\nTangential force: per pair the LTCA's |Σ P_t| over its points (each P_t along its point's tangent, the sliding direction), FE contact's magnitude of the vector resultant of the friction forces on its slave nodes (a little below μ Σ P_n where the nodes' slip directions differ, or less where nodes stick); its error is max over positions and pairs of |P_t − P_t,ref| / Σ P_n,ref, the reference's total normal force at that position (the same scale as the load-sharing error). The reference's P_t is {} (not extrapolated).",
        if reference.method == "fe_extrapolated" {
            "the finest FE run's"
        } else {
            "its own"
        }
    );
}
