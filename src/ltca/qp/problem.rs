//! The contact QP at one roll position, its options and its answer
//! ([`ContactQp`], [`QpOptions`], [`QpSolution`], [`Kkt`]), and the checked
//! data the solvers work on ([`Prepared`]); the solvers and the KKT check
//! are the sibling modules (module docs of [`crate::ltca::qp`]).

use nalgebra::DMatrix;

use crate::error::FlankError;
use crate::settings::QpSolver;

/// Largest accepted asymmetry of F, max |Fᵢⱼ − Fⱼᵢ| / max |Fᵢⱼ|; below it
/// the symmetric part is used.
pub const SYMMETRY_TOLERANCE: f64 = 1e-6;

/// Cholesky pivot ratio min Lᵢᵢ²/Aᵢᵢ of F_SS below which the loaded set's
/// compliance is treated as singular and regularized.
pub const PIVOT_RATIO_MIN: f64 = 1e-13;

/// First diagonal shift of a singular F_SS, relative to its largest
/// diagonal entry (then ×100 up to [`REGULARIZATION_MAX`]).
pub const REGULARIZATION_START: f64 = 1e-11;

/// Largest diagonal shift tried before giving up.
pub const REGULARIZATION_MAX: f64 = 1e-5;

/// Penetrating points enter the loaded set together if their gap is at most
/// this fraction of the most negative one (1 = one level at a time, 0 = all
/// penetrating points at once).
pub const ADDITION_FRACTION: f64 = 0.5;

/// The contact problem at one roll position (see the module doc).
#[derive(Clone, Copy, Debug)]
pub struct ContactQp<'a> {
    /// F, n × n row-major (mm/N).
    pub compliance: &'a [f64],
    /// w, initial separations (mm); negative = initial overlap.
    pub separation: &'a [f64],
    /// r, moment arms (mm/rad): normal approach per unit pinion rotation, > 0.
    pub moment_arm: &'a [f64],
    /// T, pinion torque (N·mm), ≥ 0.
    pub torque: f64,
}

impl ContactQp<'_> {
    /// Number of candidate points n.
    pub fn points(&self) -> usize {
        self.separation.len()
    }
}

/// Options of [`solve_contact_qp`](super::solve_contact_qp).
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct QpOptions {
    pub solver: QpSolver,
    /// Active set: limit on equality-constrained solves; clarabel: its
    /// interior-point iteration limit. Reaching it is an error.
    pub max_iterations: usize,
    /// Largest accepted [`Kkt::max`] (relative): sets
    /// [`QpSolution::within_tolerance`]; also scales the active set's
    /// threshold for a penetration (10⁻³ of it, at least 10⁻¹⁴).
    pub kkt_tolerance: f64,
}

impl Default for QpOptions {
    fn default() -> Self {
        QpOptions {
            solver: QpSolver::ActiveSet,
            max_iterations: 500,
            kkt_tolerance: 1e-9,
        }
    }
}

/// Relative KKT residuals of an answer (p, θ).
///
/// Scales: loads by P₀ = T / min rᵢ (the largest load a single point can
/// carry; max |pᵢ| if T = 0, 1 N if that is 0 too); gaps by
/// δ₀ = max(max |wᵢ|, max |(F p)ᵢ|, |θ| max rᵢ) (1 mm if all are 0);
/// equilibrium by T. With g = F p + w − θ r:
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Kkt {
    /// Stationarity on the free variables: max over loaded points (pᵢ > 0)
    /// of |gᵢ| / δ₀ (a loaded point must touch). Exact zeros are needed for
    /// open points: an interior-point answer with pᵢ ≈ 1e-9 at an open
    /// point scores its whole gap here.
    pub stationarity: f64,
    /// |rᵀp − T| / T.
    pub equilibrium: f64,
    /// Primal feasibility of the bounds: max(0, −min pᵢ) / P₀.
    pub primal_feasibility: f64,
    /// Dual feasibility (no penetration): max(0, −min gᵢ) / δ₀.
    pub dual_feasibility: f64,
    /// max over points of min(max(pᵢ, 0)/P₀, |gᵢ|/δ₀): no point both
    /// carries load and is open (the natural residual, threshold-free).
    pub complementarity: f64,
    /// The largest of the above (NaN if any is NaN).
    pub max: f64,
}

/// The answer of [`solve_contact_qp`](super::solve_contact_qp).
#[derive(Clone, Debug, serde::Serialize)]
pub struct QpSolution {
    /// p, normal point loads (N).
    pub load: Vec<f64>,
    /// θ, loaded pinion rotation (rad): the loaded transmission error.
    pub rotation: f64,
    /// g = F p + w − θ r (mm), the loaded gaps.
    pub gap: Vec<f64>,
    /// pᵢ > 0: the point carries load.
    pub active: Vec<bool>,
    pub kkt: Kkt,
    /// Active set: equality-constrained solves; clarabel: interior-point
    /// iterations (the polish is one more solve, not counted).
    pub iterations: usize,
    pub solver: QpSolver,
    /// kkt.max ≤ options.kkt_tolerance. An answer with `false` is not a
    /// solution to that tolerance: the caller must flag or reject it.
    pub within_tolerance: bool,
    /// Largest diagonal shift applied to a singular F_SS (relative to
    /// max diag F); 0 when F_SS was always definite enough.
    pub regularization: f64,
    /// Clarabel only: the answer is the polished one (active-set
    /// iterations from clarabel's loaded set), not clarabel's raw iterate.
    pub polished: bool,
    /// Clarabel only: equality-constrained solves of the polish (1 when
    /// clarabel's loaded set was right).
    pub polish_iterations: usize,
    /// Clarabel only: the KKT residual of its raw (unpolished) answer.
    pub raw_kkt: Option<Kkt>,
}

/// The input after validation, with the symmetric part of F.
pub(super) struct Prepared<'a> {
    pub(super) n: usize,
    /// ½(F + Fᵀ), column-major (= row-major, it is symmetric).
    pub(super) f: DMatrix<f64>,
    pub(super) w: &'a [f64],
    pub(super) r: &'a [f64],
    pub(super) t: f64,
    /// max diag F.
    pub(super) max_diag: f64,
}

impl<'a> Prepared<'a> {
    pub(super) fn new(qp: &ContactQp<'a>) -> Result<Self, FlankError> {
        let n = qp.separation.len();
        if n == 0 {
            return Err(FlankError::Model(
                "contact QP: no candidate contact points".into(),
            ));
        }
        if qp.moment_arm.len() != n || qp.compliance.len() != n * n {
            return Err(FlankError::Model(format!(
                "contact QP: {n} separations but {} moment arms and {} compliance entries (expected {n} and {})",
                qp.moment_arm.len(),
                qp.compliance.len(),
                n * n
            )));
        }
        if !qp.torque.is_finite() || qp.torque < 0.0 {
            return Err(FlankError::Model(format!(
                "contact QP: torque {} N·mm must be finite and ≥ 0 (load the pinion flank that drives)",
                qp.torque
            )));
        }
        if let Some(i) = qp.separation.iter().position(|v| !v.is_finite()) {
            return Err(FlankError::Model(format!(
                "contact QP: separation of point {i} is {}",
                qp.separation[i]
            )));
        }
        if let Some(i) = qp
            .moment_arm
            .iter()
            .position(|&v| !(v > 0.0 && v.is_finite()))
        {
            return Err(FlankError::Model(format!(
                "contact QP: moment arm of point {i} is {} mm/rad (must be finite and > 0: the point must close under the driving rotation)",
                qp.moment_arm[i]
            )));
        }
        if let Some(k) = qp.compliance.iter().position(|v| !v.is_finite()) {
            return Err(FlankError::Model(format!(
                "contact QP: compliance entry ({}, {}) is {}",
                k / n,
                k % n,
                qp.compliance[k]
            )));
        }
        let fmax = qp.compliance.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let mut asym = 0.0f64;
        for i in 0..n {
            for j in 0..i {
                asym = asym.max((qp.compliance[i * n + j] - qp.compliance[j * n + i]).abs());
            }
        }
        if asym > SYMMETRY_TOLERANCE * fmax {
            return Err(FlankError::Model(format!(
                "contact QP: compliance is not symmetric (max |Fij − Fji| = {asym:.3e} of max |F| = {fmax:.3e}); wrong layout?"
            )));
        }
        if let Some(i) = (0..n).find(|&i| !(qp.compliance[i * n + i] > 0.0)) {
            return Err(FlankError::Model(format!(
                "contact QP: compliance diagonal F[{i}][{i}] = {} mm/N must be > 0",
                qp.compliance[i * n + i]
            )));
        }
        let f = DMatrix::from_fn(n, n, |i, j| {
            0.5 * (qp.compliance[i * n + j] + qp.compliance[j * n + i])
        });
        let max_diag = (0..n).fold(0.0f64, |a, i| a.max(f[(i, i)]));
        Ok(Prepared {
            n,
            f,
            w: qp.separation,
            r: qp.moment_arm,
            t: qp.torque,
            max_diag,
        })
    }

    /// F p, using only the non-zero loads.
    pub(super) fn apply(&self, load: &[f64]) -> Vec<f64> {
        let mut fp = vec![0.0; self.n];
        for (j, &pj) in load.iter().enumerate() {
            if pj != 0.0 {
                for (v, &fij) in fp.iter_mut().zip(self.f.column(j).iter()) {
                    *v += fij * pj;
                }
            }
        }
        fp
    }
}

/// What a solver returns before the common checks.
pub(super) struct Raw {
    pub(super) load: Vec<f64>,
    pub(super) rotation: f64,
    pub(super) iterations: usize,
    /// Absolute diagonal shift (mm/N).
    pub(super) shift: f64,
    pub(super) polished: bool,
    pub(super) polish_iterations: usize,
    pub(super) raw_kkt: Option<Kkt>,
}
