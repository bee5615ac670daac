//! What the frictional solve of one LTCA position reports
//! ([`crate::ltca::model::PositionResult::friction`]): the incremental
//! Coulomb solve (Clarabel or Lemke, seed 001) or the sliding fixed point
//! (P_t = μ P_n against the kinematic sliding), with its residuals and,
//! where asked, its cross-check.

use serde::Serialize;

use crate::ltca::friction::Residuals;
use crate::settings::FrictionModel;

/// The friction report of one position.
#[derive(Clone, Debug, Serialize)]
#[serde(untagged)]
pub enum FrictionReport {
    /// Load increments of the Coulomb problem.
    Incremental(IncrementalReport),
    /// The sliding model's fixed point.
    Sliding(SlidingReport),
}

/// The incremental Coulomb solve's figures.
#[derive(Clone, Debug, Serialize)]
pub struct IncrementalReport {
    /// μ and the friction model.
    pub mu: f64,
    pub model: FrictionModel,
    /// Largest tangential-normal coupling of the loaded points
    /// ([`crate::ltca::friction::sliding::friction_coupling`]).
    pub coupling: Option<f64>,
    /// `clarabel` or `lemke`.
    pub solver: &'static str,
    /// Load increments solved.
    pub increments: usize,
    /// Worst residuals over the increments.
    pub max_residual: Residuals,
    pub within_tolerance: bool,
    /// Some increment hit its iteration bound.
    pub limit_hit: bool,
    /// Lemke against Clarabel, if asked.
    pub cross_check: Option<LemkeCrossCheck>,
}

/// [`crate::ltca::friction::cross_check`] in short.
#[derive(Clone, Debug, Serialize)]
pub struct LemkeCrossCheck {
    pub load_difference: f64,
    pub rotation_difference: f64,
    pub state_differences: usize,
    pub lemke_within_tolerance: bool,
}

/// The sliding fixed point's figures.
#[derive(Clone, Debug, Serialize)]
pub struct SlidingReport {
    /// μ and the friction model.
    pub mu: f64,
    pub model: FrictionModel,
    /// As [`IncrementalReport::coupling`].
    pub coupling: Option<f64>,
    /// `sliding fixed point`.
    pub solver: &'static str,
    /// Fixed-point and active-set iterations.
    pub iterations: usize,
    pub active_set_iterations: usize,
    /// The fixed point hit its bound (the active set took over).
    pub limit_hit: bool,
    /// Last relative change of P_t.
    pub change: f64,
    pub max_residual: SlidingResidual,
    pub within_tolerance: bool,
    /// The direct solve on the loaded set, when the fixed point settled.
    pub cross_check: Option<DirectCheck>,
}

/// Residuals of the sliding answer.
#[derive(Clone, Debug, Serialize)]
pub struct SlidingResidual {
    /// The larger of the two.
    pub max: f64,
    /// Of the sliding law, and the QP's KKT residual.
    pub sliding_law: f64,
    pub qp_kkt: f64,
}

/// The fixed point against a direct solve on its loaded set.
#[derive(Clone, Debug, Serialize)]
pub struct DirectCheck {
    /// `direct solve on the loaded set`.
    pub method: &'static str,
    pub load_difference: f64,
}

impl FrictionReport {
    /// Largest residual of the solve.
    pub fn max_residual(&self) -> f64 {
        match self {
            FrictionReport::Incremental(r) => r.max_residual.max,
            FrictionReport::Sliding(r) => r.max_residual.max,
        }
    }

    /// Largest tangential-normal coupling (0 if none was computed).
    pub fn coupling(&self) -> f64 {
        match self {
            FrictionReport::Incremental(r) => r.coupling,
            FrictionReport::Sliding(r) => r.coupling,
        }
        .unwrap_or(0.0)
    }

    /// The cross-check's load difference (`None` without one).
    pub fn cross_check_load_difference(&self) -> Option<f64> {
        match self {
            FrictionReport::Incremental(r) => r.cross_check.as_ref().map(|c| c.load_difference),
            FrictionReport::Sliding(r) => r.cross_check.as_ref().map(|c| c.load_difference),
        }
    }

    /// The cross-check's rotation difference (`None` without one, and for
    /// the sliding model, whose direct check compares loads only).
    pub fn cross_check_rotation_difference(&self) -> Option<f64> {
        match self {
            FrictionReport::Incremental(r) => r.cross_check.as_ref().map(|c| c.rotation_difference),
            FrictionReport::Sliding(_) => None,
        }
    }
}
