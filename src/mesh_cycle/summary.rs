//! The summary of `flank run` as a typed struct ([`RunSummary`]):
//! summary.json is its serialization, whatever the pair kind. The figures
//! both kinds have are its own fields; what only a cylindrical or only a
//! bevel/hypoid run has is the flattened [`RunKind`], so that each kind
//! keeps every key it had.

use serde::ser::SerializeStruct;
use serde::Serialize;

use crate::contact::PressureOverclosure;
use crate::iteration_limits::IterationLimits;
use crate::load_sharing::CycleSharing;
use crate::mesh_cycle::cycle::{MeshCycle, RunSettings, StepResult};
use crate::settings::SlaveBody;

pub use crate::summary::{peak_to_peak, SCHEMA_VERSION};

/// summary.json of `flank run`.
#[derive(Clone, Debug, Serialize)]
pub struct RunSummary {
    /// Schema version, scene file and pair kind.
    #[serde(flatten)]
    pub header: crate::summary::Header,
    /// Rows of `mesh_cycle.csv`, and positions taken from a checkpoint.
    pub positions: usize,
    pub resumed_positions: usize,
    pub nodes: usize,
    pub nodes_per_body: [usize; 2],
    pub elements_per_body: [usize; 2],
    /// The free DOFs of the pair's system.
    pub dofs: usize,
    pub nnz_factor: usize,
    pub factorization_flops: f64,
    /// The numeric factorization (s).
    pub factorization_s: f64,
    /// The system's setup: assembly, ordering, factorization and condition
    /// estimates, with the meshing for cylindrical pairs (a bevel pair's
    /// meshing is part of its `input_checks_s`) (s).
    pub setup_s: f64,
    pub factorization_gflop_per_s: f64,
    pub time_per_position_s: f64,
    pub peak_memory_mb: f64,
    /// Peak-to-peak loaded TE, at the pinion (µrad) and at the gear
    /// (arcsec), over the positions of the TE statistics (cylindrical: the
    /// middle pair loaded; bevel: all).
    pub te_peak_to_peak_urad: f64,
    pub te_peak_to_peak_arcsec: f64,
    /// The normal contact law.
    pub law: RunLaw,
    pub iteration_limits: IterationLimits,
    /// (pinion tooth, gear tooth) of each pair k.
    pub tooth_pairs: Vec<(usize, usize)>,
    /// The pair's description (as `flank tca`'s `pair`).
    pub kinematics: serde_json::Value,
    /// The files written.
    pub files: RunFiles,
    pub notes: Vec<String>,
    pub warnings: Vec<String>,
    #[serde(flatten)]
    pub kind: RunKind,
}

impl RunSummary {
    /// The summary as a JSON value (summary.json), for callers that read it
    /// by key.
    pub fn to_json(&self) -> serde_json::Value {
        serde_json::to_value(self).unwrap_or(serde_json::Value::Null)
    }

    /// summary.json's text.
    pub fn to_json_text(&self) -> Result<String, crate::error::FlankError> {
        serde_json::to_string_pretty(self)
            .map_err(|e| crate::error::FlankError::Model(format!("summary: {e}")))
    }
}

/// The files of a run (relative to its output directory).
#[derive(Clone, Debug, Serialize)]
pub struct RunFiles {
    /// `mesh_cycle.csv`, one row per roll angle.
    pub csv: &'static str,
    /// `positions.csv`, one row per roll angle and tooth pair.
    pub positions_csv: &'static str,
    pub plots: Vec<String>,
    /// The VTU name pattern, empty when none are written.
    pub vtu: &'static str,
}

/// What only one pair kind reports.
#[derive(Clone, Debug, Serialize)]
#[serde(untagged)]
pub enum RunKind {
    Cylindrical(Box<CylindricalRun>),
    Bevel(Box<BevelRun>),
}

/// A spur/helical run's own figures.
#[derive(Clone, Debug, Serialize)]
pub struct CylindricalRun {
    /// `"fe_contact_mesh_cycle"`.
    pub analysis: &'static str,
    /// The middle pair's loaded interval / angular pitch.
    pub contact_ratio: Option<f64>,
    pub contact_ratio_kinematic: f64,
    /// Mean middle-pair force over the single-contact positions (N), the
    /// nominal T/(r_b1 cos β_b) and their ratio − 1.
    pub single_pair_force_n: Option<f64>,
    pub nominal_force_n: f64,
    pub single_pair_force_error: Option<f64>,
    pub single_contact_positions: usize,
    pub middle_pair_loaded_deg: Option<[f64; 2]>,
    pub middle_pair_kinematic_deg: [f64; 2],
    pub kinematic_single_contact_deg: [f64; 2],
    pub angular_pitch_deg: f64,
    pub loaded_threshold_fraction: f64,
    pub refinement_positions: usize,
    pub extension_positions: usize,
    pub total_s: f64,
    /// The wet–dry loop's figures, with `[analyses.lubrication]`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lubrication: Option<crate::report::lubrication::LubricationSummary>,
    pub ordering: String,
    pub assembly_s: f64,
    pub condition_estimate: f64,
    pub scaled_condition_estimate: f64,
    pub condition_estimate_s: f64,
    pub threads: usize,
    pub estimated_peak_memory_mb: f64,
    /// The TE statistics' positions (middle pair loaded).
    pub te_positions: usize,
    pub te_mean_urad: f64,
    pub te_peak_to_peak_um: f64,
    pub max_violation_mm: f64,
    pub max_complementarity: f64,
    pub max_equilibrium: f64,
    pub max_backward_error: f64,
    pub settings: RunSettings,
    pub steps: Vec<StepResult>,
}

/// A bevel/hypoid run's own figures.
#[derive(Clone, Debug, Serialize)]
pub struct BevelRun {
    /// As in the hypoid LTCA (default cycle only).
    pub functional_contact_ratio: Option<f64>,
    pub load_sharing: Option<CycleSharing>,
    /// The bad-input checks before the factorization (s).
    pub input_checks_s: f64,
    pub largest_exact_unloaded_interpenetration_mm: f64,
    pub gross_interpenetration_limit_mm: f64,
    pub largest_unloaded_interpenetration_mm: f64,
    pub mesh_cycle_deg: f64,
    pub torque_nm: f64,
    pub max_pressure_mpa: f64,
    pub max_moment_balance: f64,
    pub plots: Vec<String>,
    pub slave: SlaveBody,
    pub friction_mu: f64,
    pub max_coulomb_residual: f64,
    pub friction_not_converged: usize,
    pub steps: Vec<StepResult>,
}

/// The normal law of a run as its summary gives it: `"hard"`, or
/// `{"penalty_slope_mpa_per_mm": …, "factor": …}` (factor 1: the automatic
/// slope).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RunLaw {
    Hard,
    Penalty { slope_mpa_per_mm: f64, factor: f64 },
}

impl RunLaw {
    /// The law `cycle` solves with.
    pub fn of(cycle: &MeshCycle) -> Self {
        match cycle.pair.model.contact.interactions[0].behavior {
            Some(PressureOverclosure::Linear { slope: Some(s), .. }) => RunLaw::Penalty {
                slope_mpa_per_mm: s,
                factor: cycle.settings.penalty_factor,
            },
            _ => RunLaw::Hard,
        }
    }
}

impl Serialize for RunLaw {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match *self {
            RunLaw::Hard => s.serialize_str("hard"),
            RunLaw::Penalty {
                slope_mpa_per_mm,
                factor,
            } => {
                let mut m = s.serialize_struct("RunLaw", 2)?;
                m.serialize_field("penalty_slope_mpa_per_mm", &slope_mpa_per_mm)?;
                m.serialize_field("factor", &factor)?;
                m.end()
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn law_keeps_its_keys() {
        assert_eq!(serde_json::to_value(RunLaw::Hard).unwrap(), "hard");
        let v = serde_json::to_value(RunLaw::Penalty {
            slope_mpa_per_mm: 2.0,
            factor: 1.0,
        })
        .unwrap();
        assert_eq!(
            v,
            serde_json::json!({"penalty_slope_mpa_per_mm": 2.0, "factor": 1.0})
        );
    }
}
