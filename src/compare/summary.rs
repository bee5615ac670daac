//! The typed result of `flank compare` for every pair kind: `compare.json`
//! is the serialization of [`CompareSummary`] (docs/outputs.md lists every
//! key). The errors of the best LTCA run against the FE reference, the
//! times, every run, the per-position errors, and, flattened beside them,
//! what only one pair kind reports ([`CompareKind`]).

use std::path::Path;

use serde::Serialize;

use crate::compare::method_run::MethodRun;
use crate::compare::pmax_reference::{PmaxReferencePair, PmaxRun};
use crate::compare::reference::ExtrapolatedReference;
use crate::error::FlankError;
use crate::ltca::bodies::Setup;
use crate::ltca::solve_settings::LtcaSettings;

/// `compare.json`.
#[derive(Clone, Debug, Serialize)]
pub struct CompareSummary {
    /// Schema version, scene file and pair kind.
    #[serde(flatten)]
    pub header: crate::summary::Header,
    pub positions: usize,
    pub roll_angles_deg: Vec<f64>,
    /// Label of the FE reference run and, with three FE sizes, its
    /// Richardson extrapolation.
    pub reference: String,
    pub reference_extrapolated: Option<ExtrapolatedReference>,
    /// Label of the LTCA run with the smallest max(load sharing, TE error).
    pub best_ltca: String,
    /// The best run's errors: the largest absolute load-share difference
    /// (a fraction 0–1), the relative TE and p_max errors and the
    /// tangential force error (of the total normal force).
    pub load_sharing_rel_err: f64,
    pub te_rel_err: f64,
    pub pmax_rel_err: f64,
    /// What p_max is compared against.
    pub pmax_reference: String,
    pub tangential_force_rel_err: f64,
    /// The LTCA's μ.
    pub friction_mu: f64,
    /// The best LTCA's cycle (s), the FE reference's cycle and setup (s),
    /// their ratio.
    pub ltca_cycle_s: f64,
    pub fe_cycle_s: f64,
    pub fe_setup_s: f64,
    pub speedup: f64,
    pub targets: CompareTargets,
    pub ltca_settings: LtcaSettings,
    /// Every FE run, then every LTCA run.
    pub runs: Vec<MethodRun>,
    pub best_ltca_per_position: Vec<PositionError>,
    pub files: CompareFiles,
    #[serde(flatten)]
    pub kind: CompareKind,
}

impl CompareSummary {
    /// The summary as JSON (what `compare.json` holds).
    pub fn to_json(&self) -> serde_json::Value {
        serde_json::to_value(self).unwrap_or(serde_json::Value::Null)
    }

    /// Writes `dir/compare.json`.
    pub fn write(&self, dir: &Path) -> Result<(), FlankError> {
        let text =
            serde_json::to_string_pretty(self).map_err(|e| FlankError::Model(e.to_string()))?;
        crate::atomic_file::write(&dir.join("compare.json"), text + "\n")
    }
}

/// The targets the errors and times are read against (DESIGN.md).
#[derive(Clone, Debug, Serialize)]
pub struct CompareTargets {
    pub load_sharing_rel_err: f64,
    pub te_rel_err: f64,
    pub pmax_rel_err: f64,
    pub ltca_cycle_s: f64,
    /// Spur/helical only.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub speedup: Option<f64>,
}

/// The files `flank compare` wrote beside `compare.json`.
#[derive(Clone, Debug, Serialize)]
pub struct CompareFiles {
    pub markdown: String,
    pub plots: Vec<String>,
}

/// What only one pair kind's comparison reports.
#[derive(Clone, Debug, Serialize)]
#[serde(untagged)]
pub enum CompareKind {
    Cylindrical(Box<CylindricalCompare>),
    Bevel(Box<BevelCompare>),
}

/// A spur/helical comparison's own keys.
#[derive(Clone, Debug, Serialize)]
pub struct CylindricalCompare {
    /// Positions where every loaded pair lies inside its path of contact
    /// (where p_max is compared).
    pub flank_contact_positions: usize,
    pub pmax_uniform_fe_rel_err: f64,
    /// With `--pmax-reference`: the contact-band reference and the LTCA's
    /// p_max against it.
    pub pmax_contact_band: Option<PmaxContactBand>,
    /// FE contact's μ.
    pub fe_friction_mu: f64,
    /// The LTCA setup (as `flank ltca`'s `setup`).
    pub ltca_compliance: Setup,
}

/// The contact-band p_max reference and the LTCA runs against it.
#[derive(Clone, Debug, Serialize)]
pub struct PmaxContactBand {
    pub reference: Vec<PmaxReferencePair>,
    pub ltca: Vec<PmaxRun>,
}

/// A bevel/hypoid comparison's own keys.
#[derive(Clone, Debug, Serialize)]
pub struct BevelCompare {
    /// `"hypoid"` for every bevel pair (kept for scripts; `pair_kind`
    /// tells spiral bevel from hypoid).
    pub pair: &'static str,
    /// The LTCA's friction model and load increments (with friction).
    pub ltca_friction_model: Option<crate::settings::FrictionModel>,
    pub ltca_increments: Option<usize>,
    /// The candidate axis span (mm).
    pub ltca_span_approach_mm: f64,
}

/// One position of the best LTCA against the reference: the errors the
/// table's maxima are taken over, beside the reference's uncertainty.
#[derive(Clone, Debug, serde::Serialize)]
pub struct PositionError {
    pub roll_deg: f64,
    /// The reference's load shares per pair.
    pub reference_shares: Vec<f64>,
    /// The reference's TE (µrad).
    pub reference_te_urad: f64,
    /// Largest |share difference| over the pairs.
    pub share_err: f64,
    /// Relative TE difference (signed: < 0 the LTCA's TE is lower).
    pub te_rel_err: f64,
    /// The reference's largest share uncertainty over the pairs and its
    /// relative TE uncertainty (NaN without an extrapolated reference).
    pub share_uncertainty: f64,
    pub te_uncertainty: f64,
}
