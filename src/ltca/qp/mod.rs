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
mod problem;

#[cfg(test)]
mod tests;

use crate::error::FlankError;

use crate::settings::QpSolver;
use active_set::active_set;
use clarabel::solve_clarabel;
use kkt::residuals;
pub use kkt::{condition_number, kkt, singular_on};
pub use problem::{
    ContactQp, Kkt, QpOptions, QpSolution, ADDITION_FRACTION, PIVOT_RATIO_MIN, REGULARIZATION_MAX,
    REGULARIZATION_START, SYMMETRY_TOLERANCE,
};
use problem::{Prepared, Raw};
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
