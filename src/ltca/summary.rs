//! The typed result of `flank ltca` for every pair kind: `summary.json` is
//! the serialization of [`LtcaResult`] (docs/outputs.md lists every key).
//!
//! One [`LtcaSummary`] per cycle: the figures every pair kind has (the
//! positions, both forms of the loaded TE, the largest pressure, the KKT
//! residual, the loops' tally, friction, times, the positions themselves
//! as [`LtcaStep`]s) and, flattened beside them, what only one kind has
//! ([`KindSummary`]: a cylindrical pair's contact ratio from the middle
//! pair's loaded span, a bevel pair's functional contact ratio over one
//! pitch, its TCA and edge counts). A bevel/hypoid LTCA run with and
//! without edge contact (`--edges both`) returns both cycles in
//! [`EdgeVariantSummaries`].

use std::path::Path;

use serde::Serialize;

use crate::error::FlankError;
use crate::iteration_limits::IterationLimits;
use crate::load_sharing::CycleSharing;
use crate::ltca::bodies::Setup;
use crate::ltca::harmonics::TeHarmonics;
use crate::ltca::mesh_stiffness::MeshStiffness;
use crate::ltca::model::PositionResult;
use crate::ltca::solve_settings::LtcaSettings;
use crate::ltca::te_fit::QuadraticTeFit;
use crate::ltca::torque_map::TorqueMap;
use crate::summary::Measured;
use crate::tca::point_contact::Transition;

pub use crate::summary::SCHEMA_VERSION;

/// What `flank ltca` returns and writes to `summary.json`.
#[derive(Clone, Debug, Serialize)]
#[serde(untagged)]
pub enum LtcaResult {
    /// One cycle (every spur/helical LTCA; a bevel/hypoid one with or
    /// without edge contact).
    Cycle(Box<LtcaSummary>),
    /// A bevel/hypoid LTCA with and without edge contact.
    EdgeVariants(Box<EdgeVariantSummaries>),
}

impl LtcaResult {
    /// The cycles with their variant name (`None` for a single cycle).
    pub fn cycles(&self) -> Vec<(Option<&'static str>, &LtcaSummary)> {
        match self {
            LtcaResult::Cycle(s) => vec![(None, s.as_ref())],
            LtcaResult::EdgeVariants(v) => vec![
                (Some("with_edges"), &v.with_edges),
                (Some("without_edges"), &v.without_edges),
            ],
        }
    }

    /// The first cycle (the only one, or the variant with edges).
    pub fn first(&self) -> &LtcaSummary {
        match self {
            LtcaResult::Cycle(s) => s,
            LtcaResult::EdgeVariants(v) => &v.with_edges,
        }
    }

    /// The summary as JSON (what `summary.json` holds).
    pub fn to_json(&self) -> serde_json::Value {
        serde_json::to_value(self).unwrap_or(serde_json::Value::Null)
    }

    /// Writes `dir/summary.json`.
    pub fn write(&self, dir: &Path) -> Result<(), FlankError> {
        let text = serde_json::to_string_pretty(self)
            .map_err(|e| FlankError::Model(format!("summary: {e}")))?;
        crate::atomic_file::write(&dir.join("summary.json"), text + "\n")
    }
}

/// One LTCA cycle of any pair kind.
#[derive(Clone, Debug, Serialize)]
pub struct LtcaSummary {
    /// Schema version, scene file and pair kind.
    #[serde(flatten)]
    pub header: crate::summary::Header,
    /// `"ltca_mesh_cycle"` (spur, helical) or `"ltca_bevel_cycle"` (bevel,
    /// hypoid).
    pub analysis: &'static str,
    /// Positions solved.
    pub positions: usize,
    /// (pinion tooth, gear tooth) of each pair k = 1 … n.
    pub tooth_pairs: Vec<(usize, usize)>,
    /// Loaded TE peak-to-peak over the positions: pinion (µrad) and gear
    /// (arcsec; [`crate::load_sharing::te_arcsec_at_gear`]).
    pub te_peak_to_peak_urad: f64,
    pub te_peak_to_peak_arcsec: f64,
    /// Largest Hertz peak pressure over the cycle (MPa).
    pub max_pressure_mpa: f64,
    /// The loaded TE's mesh orders 1 … 5 over the cycle's positions,
    /// measured where they are equal steps over whole pitches
    /// ([`crate::ltca::harmonics`]), else why not.
    pub te_harmonics: Measured<TeHarmonics>,
    /// Mean and variation of the mesh stiffness over the same positions
    /// ([`crate::ltca::mesh_stiffness`]), else why not.
    pub mesh_stiffness: Measured<MeshStiffness>,
    /// The map over torque (`torques_nm`; [`crate::ltca::torque_map`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub torque_map: Option<TorqueMap>,
    /// Largest KKT (or friction) residual over the positions.
    pub max_kkt: f64,
    /// How the bounded loops of every position ended.
    pub iteration_limits: IterationLimits,
    /// The frictional LTCA's figures (`None` frictionless).
    pub friction: Option<FrictionSummary>,
    /// The wet–dry loop's summary (`[analyses.lubrication]` only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lubrication: Option<crate::report::lubrication::LubricationSummary>,
    pub settings: LtcaSettings,
    /// Wall time of the cycle, per position, and of the whole run (s).
    pub cycle_s: f64,
    pub time_per_position_s: f64,
    pub total_s: f64,
    pub peak_memory_mb: f64,
    pub notes: Vec<String>,
    /// What only this pair kind reports.
    #[serde(flatten)]
    pub kind: KindSummary,
    /// The positions, in roll order.
    pub steps: Vec<LtcaStep>,
}

/// One position of a cycle: the solve's [`PositionResult`] and its
/// figures per tooth pair and at the gear.
#[derive(Clone, Debug, Serialize)]
pub struct LtcaStep {
    #[serde(flatten)]
    pub position: PositionResult,
    /// Normal force (N), share of the position's total (0–1) and friction
    /// force (N) of each pair k = 1 … n.
    pub pair_force_n: Vec<f64>,
    pub load_share: Vec<f64>,
    pub pair_friction_n: Vec<f64>,
    /// Loaded and unloaded TE at the gear (arcsec).
    pub te_arcsec: f64,
    pub unloaded_te_arcsec: f64,
}

impl LtcaStep {
    /// The step of `position` in a sector of `teeth` pinion teeth and a
    /// pair of speed ratio `ratio` = z₁/z₂.
    pub fn new(position: PositionResult, teeth: usize, ratio: f64) -> Self {
        let pair_force_n = position.per_pair(&position.line_force_n, teeth);
        let pair_friction_n = position.per_pair(&position.line_friction_n, teeth);
        LtcaStep {
            load_share: shares(&pair_force_n),
            pair_force_n,
            pair_friction_n,
            te_arcsec: crate::load_sharing::te_arcsec_at_gear(position.te_urad, ratio),
            unloaded_te_arcsec: crate::load_sharing::te_arcsec_at_gear(
                position.unloaded_te_urad,
                ratio,
            ),
            position,
        }
    }

    /// Largest Hertz pressure over the points of pair k (1-based; MPa).
    pub fn pair_max_pressure_mpa(&self, k: usize) -> f64 {
        let r = &self.position;
        r.points
            .iter()
            .filter(|q| r.lines[q.line].0 == k)
            .map(|q| q.pressure_mpa)
            .fold(0.0f64, f64::max)
    }
}

/// Each force's share of their sum (0 where the sum is 0).
pub fn shares(forces: &[f64]) -> Vec<f64> {
    let total: f64 = forces.iter().sum();
    forces
        .iter()
        .map(|&f| if total > 0.0 { f / total } else { 0.0 })
        .collect()
}

/// max − min of `values` (−∞ for none;
/// [`crate::summary::peak_to_peak`]).
pub fn peak_to_peak(values: &[f64]) -> f64 {
    crate::summary::peak_to_peak(values.iter().copied())
}

/// The figures only one pair kind has.
#[derive(Clone, Debug, Serialize)]
#[serde(untagged)]
pub enum KindSummary {
    Cylindrical(Box<CylindricalLtcaSummary>),
    Bevel(Box<BevelLtcaSummary>),
}

/// A spur/helical cycle's own figures: contact ratio and single-pair force
/// from the middle pair's loaded span, the compliance setup, conditioning.
#[derive(Clone, Debug, Serialize)]
pub struct CylindricalLtcaSummary {
    /// The middle pair's loaded roll span / angular pitch; `None` when the
    /// roll angles do not cover its engagement.
    pub contact_ratio: Option<f64>,
    /// ε_α (kinematic).
    pub contact_ratio_kinematic: f64,
    /// [start, end] of the middle pair's loaded span (deg).
    pub middle_pair_loaded_deg: Option<[f64; 2]>,
    /// Mean force of the middle pair where it alone is loaded (N), the
    /// nominal T/(r_b1 cos β_b) (N) and their relative difference.
    pub single_pair_force_n: Option<f64>,
    pub nominal_force_n: f64,
    pub single_pair_force_error: Option<f64>,
    /// Positions added at the ends while the middle pair was loaded.
    pub extension_positions: usize,
    /// K, candidate points per contact line.
    pub points_per_line: usize,
    pub setup: Setup,
    /// Largest κ₂(F) over every candidate and over the loaded points.
    pub max_condition: Option<f64>,
    pub max_condition_loaded: Option<f64>,
    /// The tensors' probe backward errors [pinion, gear].
    pub tensor_backward_error: [Option<f64>; 2],
    /// Per-position warnings (`"<roll>°: …"`).
    pub warnings: Vec<String>,
    /// Positions whose KKT residual is above the tolerance.
    pub kkt_flagged: Vec<String>,
    pub files: LtcaFiles,
}

/// The files a spur/helical cycle wrote.
#[derive(Clone, Debug, Serialize)]
pub struct LtcaFiles {
    pub csv: Vec<String>,
    pub plots: Vec<String>,
    pub contact_pattern: Vec<String>,
}

/// A bevel/hypoid cycle's own figures: the point TCA it stands on, load
/// sharing over one pitch, edges, the candidate axis.
#[derive(Clone, Debug, Serialize)]
pub struct BevelLtcaSummary {
    /// `with_edges` or `without_edges`.
    pub edges: &'static str,
    /// This variant's TCA traced edge contacts.
    pub edge_contact: bool,
    /// One angular pitch of the pinion (deg).
    pub mesh_cycle_deg: f64,
    pub torque_nm: f64,
    /// K, candidate points per major axis.
    pub points_per_pair: usize,
    /// Separation out to which the candidate axis runs (mm) and the TCA's
    /// approach δ (mm).
    pub span_approach_mm: f64,
    pub approach_mm: f64,
    /// μ (0: frictionless) and the load increments (`None` frictionless).
    pub friction_mu: f64,
    pub increments: Option<usize>,
    /// Flank nodes [pinion, gear].
    pub flank_nodes: [usize; 2],
    /// Δθ(φ) = a₀ + a₁φ + a₂φ² (seed 003; φ pinion roll, deg; Δθ gear,
    /// arcsec).
    pub te_quadratic_fit: Option<QuadraticTeFit>,
    /// max |Σ P r − T| / T (frictionless only).
    pub max_torque_balance_error: Option<f64>,
    /// Pair contacts whose loaded axis reaches a flank edge.
    pub pairs_loaded_at_a_flank_edge: usize,
    /// Pair-positions outside the sector within the loaded approach.
    pub pairs_beyond_sector_within_approach: usize,
    /// Positions where no pair of the sector touches (deg).
    pub positions_without_contact_deg: Vec<f64>,
    pub edge_candidate_points: usize,
    /// Largest edge-contact force of a position (N).
    pub max_edge_force_n: f64,
    /// Roll span over which a pair carries > 1 % of the force, in pitches
    /// (the default cycle only).
    pub functional_contact_ratio: Option<f64>,
    pub load_sharing: Option<CycleSharing>,
    /// The point TCA's contact ratio at δ and its changes of contact
    /// system (roll in rad).
    pub tca_contact_ratio: f64,
    pub tca_transitions: Vec<Transition>,
    /// Wall time of the tensors and of the TCA (s).
    pub compliance_s: f64,
    pub tca_s: f64,
    pub plots: Vec<String>,
}

/// A bevel/hypoid LTCA with and without edge contact (`--edges both`).
#[derive(Clone, Debug, Serialize)]
pub struct EdgeVariantSummaries {
    /// Schema version, scene file and pair kind.
    #[serde(flatten)]
    pub header: crate::summary::Header,
    pub analysis: &'static str,
    /// `"both"`.
    pub edges: &'static str,
    pub compliance_s: f64,
    pub flank_nodes: [usize; 2],
    pub with_edges: LtcaSummary,
    pub without_edges: LtcaSummary,
    pub functional_contact_ratio: EdgeVariantRatios,
    pub total_s: f64,
    pub peak_memory_mb: f64,
}

/// The functional contact ratio of each edge variant.
#[derive(Clone, Debug, Serialize)]
pub struct EdgeVariantRatios {
    pub with_edges: Option<f64>,
    pub without_edges: Option<f64>,
}

/// The frictional LTCA over a cycle (seeds 001/003): the Coulomb solve's
/// worst residual and, if run, the largest difference from Lemke's method;
/// the tangential-to-normal force ratio; the friction power loss
/// Σ |P_t v_s| (W) and the mesh efficiency 1 − P_loss/(T ω₁), mean over the
/// positions (seed 001 eq. for P_loss; η as Xu & Kahraman's instantaneous
/// mesh efficiency).
#[derive(Clone, Debug, Serialize)]
pub struct FrictionSummary {
    pub mu: f64,
    pub increments: crate::ltca::friction::Increments,
    pub max_residual: f64,
    pub max_coupling: f64,
    pub within_tolerance: bool,
    pub cross_check_max_load_difference: Option<f64>,
    pub cross_check_max_rotation_difference: Option<f64>,
    pub tangential_to_normal: f64,
    /// Per position (W).
    pub power_loss_w: Vec<f64>,
    pub mean_power_loss_w: f64,
    pub input_power_w: f64,
    pub mesh_efficiency: f64,
}
