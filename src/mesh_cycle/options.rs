//! The options of `flank run` and their one merge for every pair kind
//! (command line > the scene's `[analyses.contact]` > defaults,
//! [`settings`]): what the cycle solves and at which roll angles.

use std::path::PathBuf;

use crate::compliance::body::BodyMeshOptions;
use crate::error::FlankError;
use crate::geometry::gear_pair::{GearPair, LineContactPair};
use crate::mesh_cycle::bevel_checks::DEFAULT_POSITIONS;
use crate::mesh_cycle::cycle::{default_roll_angles, RunSettings};
use crate::scene::{ContactAnalysis, Scene};
use crate::settings::{ContactLaw, SlaveBody};

/// Options of [`crate::mesh_cycle::run::run_scene`]; `None` falls back to the scene's
/// `[analyses.contact]`, then to the defaults.
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    pub out: PathBuf,
    pub mesh: BodyMeshOptions,
    pub threads: usize,
    /// Roll angles (deg, flank's convention); overrides the scene's.
    pub roll_angles_deg: Option<Vec<f64>>,
    /// Roll angles in the scene's reference convention
    /// (`reference_single_contact_start_deg`); overrides the scene's.
    pub reference_angles_deg: Option<Vec<f64>>,
    pub law: Option<ContactLaw>,
    pub penalty_factor: Option<f64>,
    pub slave: Option<SlaveBody>,
    /// Coulomb friction coefficient; overrides the scene's `friction_mu`.
    pub friction_mu: Option<f64>,
    /// Write a VTU file per position.
    pub vtu: Option<bool>,
    /// Write a CalculiX deck per position (the pair model moved to its
    /// placed coordinates, `roll_…deg.inp`), to run the same contact problem
    /// in ccx.
    pub decks: bool,
    /// Bisect the middle pair's first and last loaded roll angles.
    pub refine_contact_limits: Option<bool>,
    pub quiet: bool,
    /// Take the positions of `out/checkpoint.json` left by an interrupted
    /// run of the same scene and options ([`super::checkpoint`]).
    pub resume: bool,
}

/// Resolves the run's settings, for any pair kind: each from `o` (the
/// command line), else the scene's `[analyses.contact]`, else the default
/// ([`RunSettings::default_for`]; a run writes VTU files and bisects the
/// contact limits unless told not to). Roll angles: given (`o`, then the
/// scene), else the default range (cylindrical: the middle pair's
/// engagement in `roll_step_deg` steps, extended while it is loaded at an
/// end; bevel/hypoid: [`DEFAULT_POSITIONS`] positions over one mesh cycle
/// centred on roll 0). What a bevel/hypoid run does not have is refused:
/// reference angles (the seeds' convention is that of cylindrical pairs),
/// roll ranges (its default cycle is one pitch), the gear as slave; its
/// positions write no VTU and have no contact limits to bisect.
pub fn settings(scene: &Scene, o: &RunOptions) -> Result<RunSettings, FlankError> {
    let a = scene.analyses.contact.clone().unwrap_or_default();
    let base = RunSettings::default_for(scene);
    let law = o.law.or(a.law).unwrap_or(base.law);
    let penalty_factor = o
        .penalty_factor
        .or(a.penalty_factor)
        .unwrap_or(base.penalty_factor);
    let mut friction_mu = o.friction_mu.or(a.friction_mu).unwrap_or(base.friction_mu);
    let lubrication = crate::mesh_cycle::lubricated::loop_settings(scene, o.friction_mu)?;
    if let Some(s) = &lubrication {
        friction_mu = s.initial_mu;
    }
    // a bad value is named where it was given: the command line's option
    // (the scene's keys are range-checked when it is read)
    let given = |cli: Option<f64>, option: &str, key: &str, v: f64| match cli {
        Some(_) => format!("{option} {v}"),
        None => format!("[analyses.contact] {key} = {v}"),
    };
    if !(0.0..=1.0).contains(&friction_mu) {
        return Err(FlankError::Model(format!(
            "{}: a friction coefficient must be in 0…1",
            given(o.friction_mu, "--friction-mu", "friction_mu", friction_mu)
        )));
    }
    if !(penalty_factor > 0.0 && penalty_factor.is_finite()) {
        return Err(FlankError::Model(format!(
            "{}: the penalty factor must be positive and finite",
            given(
                o.penalty_factor,
                "--penalty-factor",
                "penalty_factor",
                penalty_factor
            )
        )));
    }
    let search_distance_mm = a.search_distance_mm.unwrap_or(base.search_distance_mm);
    if scene.is_bevel() {
        let refused = [
            (o.reference_angles_deg.is_some(), "--reference-angles"),
            (
                a.reference_angles_deg.is_some(),
                "[analyses.contact] reference_angles_deg",
            ),
            (
                a.roll_start_deg.is_some() || a.roll_end_deg.is_some() || a.roll_step_deg.is_some(),
                "[analyses.contact] roll_start_deg / roll_end_deg / roll_step_deg",
            ),
            (
                o.slave.or(a.slave).is_some_and(|b| b != SlaveBody::Pinion),
                "--slave / [analyses.contact] slave",
            ),
        ];
        if let Some((_, name)) = refused.iter().find(|(given, _)| *given) {
            return Err(FlankError::Model(format!(
                "{name}: not available for bevel and hypoid scenes yet (their FE contact has the pinion as slave and runs over one mesh cycle, `roll_angles_deg` or --roll-angles)"
            )));
        }
        if lubrication.is_some() {
            let at = match scene.bevel("")?.lines.lubrication {
                Some(l) => scene.at(l),
                None => scene.source.display().to_string(),
            };
            return Err(FlankError::Model(format!(
                "{at}: `analyses.lubrication` with `flank run`: the FE wet–dry loop takes its operating points from the involute closed form of spur and helical pairs; for bevel and hypoid pairs the loop runs in `flank ltca` (operating points from the point TCA)"
            )));
        }
        let bevel = scene.bevel("the bevel/hypoid FE mesh cycle")?;
        let pitch = bevel.pair.tooth_roll_step().abs().to_degrees();
        let roll_angles_deg = match o.roll_angles_deg.as_ref().or(a.roll_angles_deg.as_ref()) {
            Some(v) => v.clone(),
            None => (0..DEFAULT_POSITIONS)
                .map(|i| -0.5 * pitch + pitch * i as f64 / DEFAULT_POSITIONS as f64)
                .collect(),
        };
        if let Some(r) = roll_angles_deg.iter().find(|r| !r.is_finite()) {
            return Err(FlankError::Model(format!("roll angle {r} is not a number")));
        }
        if roll_angles_deg.is_empty() {
            return Err(FlankError::Model(
                "at least one roll angle is needed".into(),
            ));
        }
        return Ok(RunSettings {
            law,
            penalty_factor,
            friction_mu,
            search_distance_mm,
            roll_angles_deg,
            lubrication,
            ..base
        });
    }
    let pair = scene.gear_pair()?;
    let pair = pair.as_ref();
    let default_range = o.roll_angles_deg.is_none()
        && o.reference_angles_deg.is_none()
        && a.roll_angles_deg.is_none()
        && a.reference_angles_deg.is_none()
        && a.roll_start_deg.is_none();
    let roll_angles_deg = match (&o.roll_angles_deg, &o.reference_angles_deg) {
        (Some(_), Some(_)) => {
            return Err(FlankError::Model(
                "give roll angles or reference angles, not both".into(),
            ))
        }
        (Some(v), None) => v.clone(),
        (None, Some(v)) => {
            let r = a.reference_single_contact_start_deg.ok_or_else(|| {
                FlankError::Model(
                    "reference angles need reference_single_contact_start_deg in the scene's [analyses.contact]".into(),
                )
            })?;
            reference_to_roll(pair, r, v)
        }
        (None, None) => scene_roll_angles(&a, pair)?,
    };
    if roll_angles_deg.is_empty() || roll_angles_deg.iter().any(|v| !v.is_finite()) {
        return Err(FlankError::Model(
            "the roll angles must be finite and at least one".into(),
        ));
    }
    Ok(RunSettings {
        law,
        penalty_factor,
        friction_mu,
        slave: o.slave.or(a.slave).unwrap_or(base.slave),
        search_distance_mm,
        roll_angles_deg,
        vtu: o.vtu.or(a.vtu).unwrap_or(true),
        refine_contact_limits: o
            .refine_contact_limits
            .or(a.refine_contact_limits)
            .unwrap_or(true),
        reference_single_contact_start_deg: a.reference_single_contact_start_deg,
        extend_step_deg: default_range.then(|| a.roll_step_deg.unwrap_or(1.0)),
        lubrication,
    })
}

/// Roll angles (deg) of angles given in a reference convention whose
/// value `start` marks the kinematic start of single contact.
fn reference_to_roll(pair: &dyn LineContactPair, start: f64, angles: &[f64]) -> Vec<f64> {
    let lpstc = pair.single_contact().0.to_degrees();
    angles.iter().map(|x| x - start + lpstc).collect()
}

fn scene_roll_angles(
    a: &ContactAnalysis,
    pair: &dyn LineContactPair,
) -> Result<Vec<f64>, FlankError> {
    if let Some(v) = &a.roll_angles_deg {
        return Ok(v.clone());
    }
    if let Some(v) = &a.reference_angles_deg {
        let r = a.reference_single_contact_start_deg.ok_or_else(|| {
            FlankError::Model(
                "reference_angles_deg needs reference_single_contact_start_deg".into(),
            )
        })?;
        return Ok(reference_to_roll(pair, r, v));
    }
    let step = a.roll_step_deg.unwrap_or(1.0);
    match (a.roll_start_deg, a.roll_end_deg) {
        (Some(s), Some(e)) => {
            let n = ((e - s) / step + 1e-9).floor() as i64;
            Ok((0..=n).map(|i| s + i as f64 * step).collect())
        }
        (None, None) => Ok(default_roll_angles(pair, step)),
        _ => Err(FlankError::Model(
            "[analyses.contact]: give both roll_start_deg and roll_end_deg, or neither".into(),
        )),
    }
}
