//! The frictional LTCA contact problem at one roll position (seeds 001,
//! 003), solved in load increments by two independent methods.
//!
//! # The problem
//!
//! M candidate points on the contact-ellipse major axes of the pairs in
//! mesh. Per point i: the unit normal n (positive into the loaded member's
//! flank) and the unit tangent t along the sliding direction (seeds 001,
//! 003: "positive in the direction of relative sliding"). Data:
//!
//! * the pair's directional compliances C_nn, C_nt, C_tn, C_tt (M × M,
//!   mm/N; C = C_pinion + C_gear projected on n and t as in seed 001,
//!   c^{kl}_{nt} = nᵏᵀ C^{kl} tˡ);
//! * g⁰, the initial separations of the rigidly rolled flanks (mm,
//!   negative = overlap);
//! * r_n, r_t (mm/rad): the normal approach and the tangential relative
//!   displacement of point i per unit rotation θ of the loaded member
//!   (the other held); by virtual work also the torque of a unit normal /
//!   tangential force, so the equilibrium is T = Σ r_n P_n + r_t P_t;
//! * s, the sliding coefficient of seeds 001/003: the kinematic sliding
//!   distance of the flanks (along +t) per unit normal approach while the
//!   load is taken up, from the TCA velocities;
//! * μ ≥ 0 and the torque T ≥ 0 (N·mm), applied in increments.
//!
//! Unknowns: normal loads P_n ≥ 0 (N), friction forces P_t (N, positive
//! when it resists a slip along +t, i.e. it is the force on the loaded
//! member's flank along −t), and the loaded rotation θ (rad, the loaded
//! transmission error).
//!
//! # Conditions of increment k (torque T_{k−1} → T_k)
//!
//! With the totals P_n, P_t, θ at the end of the increment and
//! ΔX = X − X_{k−1}:
//!
//! ```text
//!   equilibrium   Σᵢ r_n,i P_n,i + r_t,i P_t,i = T_k
//!   normal gap    g  = g⁰ + C_nn P_n + C_nt P_t − r_n θ          (total: elastic)
//!   slip          Δσ = ρ Δθ − (C_tn ΔP_n + C_tt ΔP_t),  ρ = r_t + s ∘ r_n
//!   contact       g ≥ 0,  P_n ≥ 0,  gᵢ P_n,i = 0
//!   Coulomb       |P_t| ≤ μ P_n;  |P_t,i| < μ P_n,i ⇒ Δσᵢ = 0        (stick)
//!                 Δσᵢ ≠ 0 ⇒ P_t,i = μ P_n,i sign(Δσᵢ)                (slip, force opposing it)
//! ```
//!
//! Three states per point: separation (P_n = P_t = 0, g ≥ 0), stick
//! (g = 0, Δσ = 0, |P_t| ≤ μP_n), slip (g = 0, P_t = ±μP_n against Δσ).
//! The seeds' compatibility Δu_n = C_nn ΔP_n + C_nt ΔP_t,
//! Δu_t = C_tn ΔP_n + C_tt ΔP_t is the elastic part of g and Δσ. Their
//! transcription leaves the kinematics loose; here it is made explicit:
//! the relative tangential motion of a point over an increment is the
//! rigid part r_t Δθ (the virtual-work partner of the torque arm r_t), the
//! kinematic sliding s r_n Δθ (s times the point's rigid normal approach
//! r_n Δθ, the seeds' definition of s), less the elastic tangential
//! deformation. The slip direction is that of ρ = r_t + s r_n only where
//! ρ Δθ outweighs the elastic tangential motion C_tn ΔP_n + C_tt ΔP_t:
//! on seed 002's spur pair the elastic part is about 0.4 of the normal
//! approach, and r_t, s r_n are 8 and 0.6 mm/rad one degree past the pitch
//! point, so there the points slip against ρ's direction or stick over
//! about ±2° of roll. This is the load taken up at a standing position
//! (the caller may set s = 0: the mate held, what one static FE contact
//! step models). In the running mesh the friction follows the kinematic
//! sliding: `sliding.rs` ([`solve_sliding`]).
//! The normal part is total (elastic, path independent), the tangential
//! part incremental (the Coulomb law is a rate law: backward Euler over the
//! increment), so the answer depends on the load path when a point changes
//! state inside the loading, and not at all while the states are constant
//! (every increment is then the same linear map of ΔT).
//!
//! Reciprocity (Maxwell–Betti) makes the full compliance symmetric:
//! C_tn = C_ntᵀ (seed 001's c^{kl}_{nt} ≠ c^{kl}_{tn} is the statement for
//! one pair k, l, not for the transposed block), C_nn and C_tt symmetric;
//! asymmetry above [`SYMMETRY_TOLERANCE`] is an input error. No self-locking:
//! r_n,i > μ|r_t,i| for every point, otherwise a friction force could
//! carry the torque at no normal load.
//!
//! The start (T = 0) is the rigid contact: P = 0, θ₀ = minᵢ g⁰ᵢ / r_n,i.
//!
//! # Two solvers per increment
//!
//! * [`FrictionSolver::Clarabel`] (`clarabel.rs`): the seeds' "LP with
//!   complementarity" enforces complementarity by restricted basis entry in
//!   a simplex method (Conry & Seireg), which an interior-point solver
//!   cannot do. Instead, for given friction bounds S (Tresca) and a given
//!   kinematic slip s r_n Δθ̃, the increment's conditions are exactly the
//!   KKT conditions of the convex QP
//!
//!   ```text
//!     min ½ ΔPᵀ C ΔP + [g_{k−1}; −s∘r_n Δθ̃]ᵀ ΔP
//!     s.t. P_n ≥ 0,  −S ≤ P_t ≤ S,  r_nᵀΔP_n + r_tᵀΔP_t = ΔT
//!   ```
//!
//!   (ΔP = (ΔP_n, ΔP_t), C the full symmetric compliance; Δθ the
//!   multiplier of the equality, g and Δσ those of the bounds); clarabel
//!   solves it, then S ← μP_n and Δθ̃ ← Δθ until both settle (the
//!   Tresca-to-Coulomb fixed point: Panagiotopoulos 1985; Haslinger,
//!   Dostál & Kučera 2002; as in [`crate::contact::friction`]). The
//!   states read off the answer start the polish (`polish.rs`): the linear
//!   system of the increment with the states fixed, solved exactly, the
//!   states updated by the primal–dual active-set rule until they repeat
//!   (Hüeber, Stadler & Wohlmuth 2008). Where that cycles (points at the
//!   cone's edge) or settles above the tolerance, a globalised semismooth
//!   Newton method on the natural-map / Alart–Curnier form of the
//!   conditions polishes the Tresca answer instead (`semismooth.rs`).
//!   With μ = 0 it is the frictionless QP of [`crate::ltca::qp`].
//! * [`FrictionSolver::Lemke`] (`lemke.rs`): the increment as a linear
//!   complementarity problem w = q + A z, w, z ≥ 0, wᵀz = 0 in the loads,
//!   the friction split P_t = β⁺ − β⁻ and the slip magnitude λ (the
//!   standard 2D Coulomb LCP: Klarbring 1986; Cottle, Pang & Stone, *The
//!   Linear Complementarity Problem*, 1992), solved by Lemke's
//!   complementary pivoting with the lexicographic ratio test. It shares
//!   no code with the first path except the problem data and the residual.
//!
//! Every answer gets the residuals of [`Residuals`]; the cross-check
//! ([`cross_check`]) runs both and reports their largest difference.
//!
//! # Files
//!
//! | file | holds |
//! | --- | --- |
//! | `mod.rs` | problem, options and answer types, validation, entries |
//! | `incremental.rs` | the load schedule and the increment loop |
//! | `clarabel.rs` | the Tresca QP per increment and the fixed point |
//! | `problem.rs` | the problem, its options and answer, the checked data |
//! | `polish.rs` | the state-fixed linear system and active-set updates |
//! | `semismooth.rs` | the globalised semismooth Newton polish |
//! | `lemke.rs` | the increment's LCP and Lemke's method |
//! | `residual.rs` | gaps, slips, states and residuals of an answer |
//! | `sliding.rs` | fully developed sliding (the running mesh, no stick) |
//! | `tests.rs` | unit tests (references stated in each) |

mod clarabel;
mod incremental;
mod lemke;
mod polish;
mod problem;
mod residual;
mod semismooth;
mod sliding;

#[cfg(test)]
mod tests;

use crate::error::FlankError;

pub(crate) use problem::Prepared;
pub use problem::{
    FrictionOptions, FrictionProblem, FrictionSolution, FrictionSolver, Increment, Increments,
    PointState, Residuals, DEFAULT_MAX_NEWTON, MAX_INCREMENTS, SYMMETRY_TOLERANCE,
};
pub use sliding::{
    friction_coupling, solve_sliding, SlidingAnswer, MAX_ACTIVE_SET_ITERATIONS,
    MAX_SLIDING_ITERATIONS, SLIDING_TOLERANCE,
};

/// Solves the frictional problem in increments with the chosen solver
/// (module doc). Errors: invalid input or options ([`FlankError::Model`]),
/// solver failures ([`FlankError::Solver`]: clarabel status, Lemke ray
/// termination or pivot limit, singular state system). An answer above
/// tolerance is returned with `within_tolerance = false`.
pub fn solve_friction(
    pb: &FrictionProblem,
    options: &FrictionOptions,
) -> Result<FrictionSolution, FlankError> {
    let prob = Prepared::new(pb)?;
    incremental::run(&prob, options)
}

/// Both solvers on the same problem and their largest differences.
#[derive(Clone, Debug, serde::Serialize)]
pub struct CrossCheck {
    pub clarabel: FrictionSolution,
    pub lemke: FrictionSolution,
    /// max over increments and points of |ΔP| / max |P_n| (normal and
    /// tangential forces).
    pub load_difference: f64,
    /// max over increments of |Δθ| / max(|θ − θ₀|, θ-scale of the loads).
    pub rotation_difference: f64,
    /// Points whose reported state differs, summed over increments.
    pub state_differences: usize,
}

/// Runs [`solve_friction`] with both solvers (other options as given) and
/// compares them increment by increment.
pub fn cross_check(
    pb: &FrictionProblem,
    options: &FrictionOptions,
) -> Result<CrossCheck, FlankError> {
    let prob = Prepared::new(pb)?;
    let a = incremental::run(
        &prob,
        &FrictionOptions {
            solver: FrictionSolver::Clarabel,
            ..options.clone()
        },
    )?;
    let b = incremental::run(
        &prob,
        &FrictionOptions {
            solver: FrictionSolver::Lemke,
            ..options.clone()
        },
    )?;
    let mut load_difference = 0.0f64;
    let mut rotation_difference = 0.0f64;
    let mut state_differences = 0;
    for (x, y) in a.increments.iter().zip(&b.increments) {
        let pmax = x.normal.iter().fold(0.0f64, |s, v| s.max(v.abs()));
        let pmax = if pmax > 0.0 { pmax } else { 1.0 };
        for i in 0..prob.m {
            load_difference = load_difference
                .max((x.normal[i] - y.normal[i]).abs() / pmax)
                .max((x.tangential[i] - y.tangential[i]).abs() / pmax);
        }
        let scale = (x.rotation - a.start_rotation)
            .abs()
            .max(pmax * prob.c_nn.diagonal().max() / prob.r0);
        rotation_difference = rotation_difference.max((x.rotation - y.rotation).abs() / scale);
        state_differences += x.state.iter().zip(&y.state).filter(|(p, q)| p != q).count();
    }
    Ok(CrossCheck {
        clarabel: a,
        lemke: b,
        load_difference,
        rotation_difference,
        state_differences,
    })
}
