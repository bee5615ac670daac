//! The typed result of `flank compliance`: `summary.json` is the
//! serialization of [`ComplianceSummary`] (docs/outputs.md lists every
//! key).

use std::collections::BTreeMap;
use std::path::Path;

use serde::Serialize;

use crate::compliance::cache::FileFormat;
use crate::compliance::contact_probe::ProbeReport;
use crate::compliance::plot::PlotInfo;
use crate::compliance::tensor_cache::CacheOutcome;
use crate::compliance::ComplianceStats;
use crate::error::FlankError;
use crate::settings::{FlankRegion, FlankSelection, Method};

pub use crate::summary::SCHEMA_VERSION;

/// A contact line across the face width: the nodes of the full profile row
/// (nodes of equal u spanning the face width) nearest to a roll angle, and
/// their normal compliance matrix.
#[derive(Clone, Debug, serde::Serialize)]
pub struct ContactLine {
    pub set: String,
    /// Flank parameter u of the row (involute roll angle).
    pub u: f64,
    pub points: usize,
    /// Eigenvalues of C_nn (mm/N).
    pub lambda_min: f64,
    pub lambda_max: f64,
    /// λ_max / λ_min (2-norm condition number).
    pub condition: f64,
    pub positive_definite: bool,
    /// C_nn diagonal at the first and the middle point (mm/N).
    pub c_nn_first: f64,
    pub c_nn_middle: f64,
}

/// What `flank compliance` returns and writes to `summary.json`.
#[derive(Clone, Debug, Serialize)]
pub struct ComplianceSummary {
    /// Schema version, scene file and pair kind.
    #[serde(flatten)]
    pub header: crate::summary::Header,
    /// How the tensors were computed (`schur` / `blocked`).
    pub method: Method,
    /// Which flanks the tensors cover.
    pub flanks: FlankSelection,
    /// `full` or `active` flank region.
    pub flank_region: FlankRegion,
    /// The cut faces were clamped.
    pub clamp_cuts: bool,
    /// Threads of the solves (0: all cores).
    pub threads: usize,
    /// Per body (`pinion`, `gear`), by name.
    pub bodies: BTreeMap<String, BodySummary>,
    /// Wall time of the whole command (s).
    pub total_s: f64,
    /// Peak resident set of the process (MB).
    pub peak_memory_mb: f64,
}

/// One body's tensor: its files, what it was built from, its size and
/// symmetry, and its probes.
#[derive(Clone, Debug, Serialize)]
pub struct BodySummary {
    /// The body's CalculiX deck in the output folder.
    pub deck: String,
    /// The tensor file (`.compliance.h5` or `.compliance.bin`).
    pub file: String,
    /// Its format.
    pub format: FileFormat,
    /// Computed here, or reused from a file or the cache.
    pub source: CacheOutcome,
    /// The cache key (model, mesh, flank nodes, region).
    pub cache_key: String,
    /// Hash of the body mesh.
    pub mesh_hash: String,
    /// Node sets held fixed.
    pub clamped_sets: Vec<String>,
    /// Flank node sets the tensor covers.
    pub flank_sets: Vec<String>,
    /// Lowest profile parameter u kept per flank set (rad), with
    /// `flank_region = "active"`.
    pub region_u_min: Option<Vec<f64>>,
    /// N, the flank nodes.
    pub flank_nodes: usize,
    /// 3N, the dimension of C.
    pub matrix_dim: usize,
    /// ‖C − Cᵀ‖_F / ‖C‖_F.
    pub asymmetry: f64,
    /// The c_nn plot files.
    pub plot: PlotInfo,
    /// C_nn on the pitch-line profile row (spur/helical bodies).
    pub contact_line: Option<ContactLine>,
    /// Wall time of this body (s).
    pub body_s: f64,
    /// Directional compliances on the middle pair's major axis at roll 0
    /// (bevel/hypoid bodies).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mean_contact: Option<MeanContact>,
    /// Figures of the computation (absent when the tensor was reused).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stats: Option<ComplianceStats>,
}

/// The probe of a bevel/hypoid body at its mean contact, or why there is
/// none.
#[derive(Clone, Debug, Serialize)]
#[serde(untagged)]
pub enum MeanContact {
    /// C_nn, C_nt, C_tn, C_tt on the major axis.
    Probed(Box<MeanContactProbe>),
    /// Why the probe could not be made.
    Missing {
        /// The reason.
        error: String,
    },
}

/// What [`MeanContact::Probed`] holds.
#[derive(Clone, Debug, Serialize)]
pub struct MeanContactProbe {
    /// Semi-major axis of the contact ellipse (mm).
    pub semi_major_mm: f64,
    /// The flank set probed.
    pub set: String,
    /// (u, v) of the middle probe point (mm).
    pub uv_mm: [f64; 2],
    /// Points on the major axis asked for.
    pub axis_points: usize,
    /// Of them, off the active flank.
    pub off_the_active_flank: usize,
    /// Of them, off the meshed flank.
    pub off_the_meshed_flank: usize,
    /// The directional compliances (mm/N), condition and reciprocity.
    pub report: ProbeReport,
}

impl ComplianceSummary {
    /// Writes `dir/summary.json`.
    pub fn write(&self, dir: &Path) -> Result<(), FlankError> {
        let text = serde_json::to_string_pretty(self)
            .map_err(|e| FlankError::Model(format!("summary: {e}")))?;
        crate::atomic_file::write(&dir.join("summary.json"), text + "\n")
    }
}
