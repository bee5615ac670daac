//! The frictionless LTCA contact problem at one roll position, and its
//! solvers.
//!
//! # The problem (seed 000)
//!
//! n candidate contact points; F (n × n, mm/N) the normal compliance of the
//! pair at those points (symmetric positive (semi)definite), w (mm) the
//! initial separations of the unloaded, rigidly rolled flanks (negative =
//! overlap), r (mm/rad, all > 0) the moment arms (normal approach of point i
//! per unit pinion rotation), T ≥ 0 (N·mm) the pinion torque. Unknowns: the
//! normal point loads p (N) and the loaded pinion rotation θ (rad, the loaded
//! transmission error). With the gaps
//!
//! ```text
//!   g = F p + w − θ r
//! ```
//!
//! the contact conditions are compatibility g ≥ 0, p ≥ 0, complementarity
//! pᵢgᵢ = 0 and equilibrium rᵀp = T. They are the KKT conditions of the
//! convex QP
//!
//! ```text
//!   min ½ pᵀF p + wᵀp   subject to  p ≥ 0,  rᵀp = T,
//! ```
//!
//! θ being the multiplier of the equality and g the multipliers of the
//! bounds. Since r > 0 the feasible set is a non-empty compact simplex for
//! every T ≥ 0, so a solution always exists; it is unique in p when F is
//! definite, and then θ is unique too. F is used through its symmetric part
//! ½(F + Fᵀ) (compliances computed column by column are symmetric only to
//! round-off); an asymmetry above [`SYMMETRY_TOLERANCE`] is an input error.
//!
//! # Solvers
//!
//! * [`QpSolver::ActiveSet`] (default): a primal active-set method
//!   (Nocedal & Wright, *Numerical Optimization*, 2nd ed., §16.5, in the
//!   Lawson–Hanson form). It starts from the point that closes first under
//!   a rigid rotation (smallest wᵢ/rᵢ) carrying the whole torque, which is
//!   feasible and the exact minimizer on that one-point set. Each outer
//!   iteration adds the penetrating points (gᵢ < 0; all of them within
//!   [`ADDITION_FRACTION`] of the worst, or only the worst after a
//!   degenerate step) to the loaded set S and solves the equality-constrained
//!   problem on S,
//!
//!   ```text
//!     [F_SS  −r_S] [p_S]   [−w_S]
//!     [r_Sᵀ    0 ] [ θ ] = [  T ]
//!   ```
//!
//!   by a dense Cholesky factorization of F_SS and the Schur complement
//!   r_Sᵀ F_SS⁻¹ r_S (one step of iterative refinement). If that minimizer
//!   has a negative load the step from the current (feasible) loads is cut
//!   where the first load reaches zero and that point leaves S (the ratio
//!   test), so every iterate is feasible and the objective never increases.
//!   It decreases strictly at every non-zero step; after a zero
//!   (degenerate) step only the single most penetrating point enters, and
//!   for definite F_SS that point gets a positive load (Lawson–Hanson), so
//!   the method cannot cycle. Should round-off drop such a point at once
//!   it is not offered again until the iterate moves (its penetration then
//!   shows in the KKT residual). An iteration limit guards it anyway
//!   ([`QpOptions::max_iterations`], counted in equality-constrained
//!   solves; hitting it is an error naming it). A point counts as
//!   penetrating when gᵢ < −10⁻³·kkt_tolerance·δ₀ (δ₀ the gap scale of
//!   [`Kkt`]). At termination the loads are the exact (to round-off)
//!   equality-constrained solution on S and zero elsewhere. Each solve
//!   refactorizes F_SS (O(|S|³), no updating): fine for a few hundred
//!   loaded points. When F_SS is singular or nearly so (duplicated points: the
//!   Cholesky pivot ratio min Lᵢᵢ²/Aᵢᵢ falls below [`PIVOT_RATIO_MIN`]) the
//!   diagonal of F_SS is shifted by [`REGULARIZATION_START`]·max diag F_SS
//!   (×100 until it factorizes); the largest shift used, relative to max
//!   diag F, is reported in [`QpSolution::regularization`], and the KKT
//!   residual is always computed with the unshifted F.
//! * [`QpSolver::Clarabel`]: the same QP handed to the interior-point
//!   solver clarabel (see `solve_clarabel` for the scaling and the sign
//!   of θ), then *polished*: the loaded set is read off clarabel's answer
//!   (pᵢ larger than its bound multiplier gᵢ, both scaled), the loads there
//!   are rescaled to rᵀp = T (a feasible start) and the active-set
//!   iterations above run from it: one equality-constrained solve when the
//!   set was right, a few ratio-test drops when clarabel left load on a
//!   degenerate point (nearly duplicated points, where the interior point
//!   splits the load). The polished answer is kept if its KKT residual is
//!   not larger than that of clarabel's raw answer (interior points carry
//!   loads of ~1e-9 at open points, which the stationarity measure below
//!   counts); otherwise, or if the polish fails, the raw answer is returned
//!   with its residual and `polished = false`.
//!
//! # Checking
//!
//! Every answer, of either solver, gets its [`Kkt`] residual from the same
//! routine ([`kkt()`]), and [`QpSolution::within_tolerance`] says whether
//! its largest component is at most [`QpOptions::kkt_tolerance`]. An answer
//! above tolerance is returned (it may still be useful) but never silently:
//! the caller must check the flag.
//!
//! # Files
//!
//! | file | holds |
//! | --- | --- |
//! | `mod.rs` (this file) | the problem and answer types ([`ContactQp`], [`QpSolver`], [`QpOptions`], [`Kkt`], [`QpSolution`]), the validated input `Prepared` and the entry [`solve_contact_qp`] |
//! | `kkt.rs` | the KKT residuals of an answer ([`kkt()`]) and [`condition_number`] |
//! | `active_set.rs` | the primal active-set method: equality-constrained solve on a loaded set, cold start, iterations |
//! | `clarabel.rs` | the clarabel interior-point path: scaling, status mapping, polish |
//! | `tests.rs` | unit tests of both solvers against each other and the residuals |

mod active_set;
mod clarabel;
mod kkt;

#[cfg(test)]
mod tests;

use nalgebra::DMatrix;

use crate::error::FlankError;

use crate::settings::QpSolver;
use active_set::active_set;
use clarabel::solve_clarabel;
use kkt::residuals;
pub use kkt::{condition_number, kkt, singular_on};

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

/// Options of [`solve_contact_qp`].
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

/// The answer of [`solve_contact_qp`].
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
struct Prepared<'a> {
    n: usize,
    /// ½(F + Fᵀ), column-major (= row-major, it is symmetric).
    f: DMatrix<f64>,
    w: &'a [f64],
    r: &'a [f64],
    t: f64,
    /// max diag F.
    max_diag: f64,
}

impl<'a> Prepared<'a> {
    fn new(qp: &ContactQp<'a>) -> Result<Self, FlankError> {
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
    fn apply(&self, load: &[f64]) -> Vec<f64> {
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
struct Raw {
    load: Vec<f64>,
    rotation: f64,
    iterations: usize,
    /// Absolute diagonal shift (mm/N).
    shift: f64,
    polished: bool,
    polish_iterations: usize,
    raw_kkt: Option<Kkt>,
}

/// Solves the contact QP with the chosen solver and checks the answer
/// (module doc). Errors: invalid input ([`FlankError::Model`]: n = 0,
/// mismatched lengths, non-finite entries, T < 0, rᵢ ≤ 0, Fᵢᵢ ≤ 0,
/// asymmetric F) and solver failures ([`FlankError::Solver`]: iteration
/// limit, clarabel status, F_SS not factorizable even regularized). With
/// T = 0 the answer is p = 0, θ = minᵢ wᵢ/rᵢ (the rigid rotation that
/// closes the first point) for either solver, without iterations.
pub fn solve_contact_qp(qp: &ContactQp, options: &QpOptions) -> Result<QpSolution, FlankError> {
    let prob = Prepared::new(qp)?;
    if !(options.kkt_tolerance >= 0.0) {
        return Err(FlankError::Model(format!(
            "contact QP: KKT tolerance {} must be ≥ 0",
            options.kkt_tolerance
        )));
    }
    if options.max_iterations == 0 {
        return Err(FlankError::Model(
            "contact QP: the iteration limit must be ≥ 1".into(),
        ));
    }
    let raw = if prob.t == 0.0 {
        let rotation = (0..prob.n)
            .map(|i| prob.w[i] / prob.r[i])
            .fold(f64::INFINITY, f64::min);
        Raw {
            load: vec![0.0; prob.n],
            rotation,
            iterations: 0,
            shift: 0.0,
            polished: false,
            polish_iterations: 0,
            raw_kkt: None,
        }
    } else {
        match options.solver {
            QpSolver::ActiveSet => active_set(&prob, options)?,
            QpSolver::Clarabel => solve_clarabel(&prob, options)?,
        }
    };
    let fp = prob.apply(&raw.load);
    let kkt = residuals(&fp, prob.w, prob.r, prob.t, &raw.load, raw.rotation);
    let gap: Vec<f64> = (0..prob.n)
        .map(|i| fp[i] + prob.w[i] - raw.rotation * prob.r[i])
        .collect();
    Ok(QpSolution {
        active: raw.load.iter().map(|&v| v > 0.0).collect(),
        load: raw.load,
        rotation: raw.rotation,
        gap,
        kkt,
        iterations: raw.iterations,
        solver: options.solver,
        within_tolerance: kkt.max <= options.kkt_tolerance,
        regularization: raw.shift / prob.max_diag,
        polished: raw.polished,
        polish_iterations: raw.polish_iterations,
        raw_kkt: raw.raw_kkt,
    })
}
