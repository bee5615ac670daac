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
mod residual;
mod semismooth;
mod sliding;

#[cfg(test)]
mod tests;

use nalgebra::DMatrix;

use crate::error::FlankError;

pub use residual::{PointState, Residuals};
pub use sliding::{
    friction_coupling, solve_sliding, SlidingAnswer, MAX_ACTIVE_SET_ITERATIONS,
    MAX_SLIDING_ITERATIONS, SLIDING_TOLERANCE,
};

/// Largest accepted asymmetry of the compliance (C_nn, C_tt symmetric,
/// C_tn = C_ntᵀ), relative to max |C|; below it the symmetric part is used.
pub const SYMMETRY_TOLERANCE: f64 = 1e-6;

/// Largest number of load increments accepted.
pub const MAX_INCREMENTS: usize = 100_000;

/// The frictional contact problem at one roll position (module doc).
/// Matrices are M × M row-major.
#[derive(Clone, Copy, Debug)]
pub struct FrictionProblem<'a> {
    /// C_nn (mm/N): normal displacement at i from a unit normal force at j.
    pub c_nn: &'a [f64],
    /// C_nt (mm/N): normal displacement at i from a unit tangential force at j.
    pub c_nt: &'a [f64],
    /// C_tn (mm/N) = C_ntᵀ.
    pub c_tn: &'a [f64],
    /// C_tt (mm/N).
    pub c_tt: &'a [f64],
    /// g⁰, initial separations (mm); negative = overlap.
    pub separation: &'a [f64],
    /// r_n (mm/rad), > 0: normal approach per unit rotation, torque arm.
    pub arm_normal: &'a [f64],
    /// r_t (mm/rad): tangential relative motion per unit rotation, torque arm.
    pub arm_tangential: &'a [f64],
    /// s: kinematic sliding along +t per unit normal approach.
    pub sliding: &'a [f64],
    /// μ ≥ 0, the same at every point unless `point_mu` is given.
    pub mu: f64,
    /// μᵢ ≥ 0 per point (M entries), replacing `mu`: the lubricated LTCA
    /// gives each tooth pair its own traction coefficient
    /// ([`crate::ltca::lubricated`]). Every condition of the module doc
    /// holds pointwise with μᵢ.
    pub point_mu: Option<&'a [f64]>,
    /// T ≥ 0 (N·mm), on the loaded member.
    pub torque: f64,
}

impl FrictionProblem<'_> {
    /// Number of candidate points M.
    pub fn points(&self) -> usize {
        self.separation.len()
    }

    /// μ of point i.
    pub fn mu_at(&self, i: usize) -> f64 {
        self.point_mu.map_or(self.mu, |v| v[i])
    }

    /// The largest μ over the points (μ itself without `point_mu`).
    pub fn mu_max(&self) -> f64 {
        self.point_mu
            .map_or(self.mu, |v| v.iter().fold(0.0f64, |a, &b| a.max(b)))
    }

    /// μ (or every μᵢ, M of them) finite and ≥ 0.
    pub(crate) fn check_mu(&self, what: &str) -> Result<(), FlankError> {
        if !(self.mu >= 0.0 && self.mu.is_finite()) {
            return Err(FlankError::Model(format!(
                "{what}: μ = {} must be finite and ≥ 0",
                self.mu
            )));
        }
        if let Some(v) = self.point_mu {
            if v.len() != self.points() {
                return Err(FlankError::Model(format!(
                    "{what}: μ per point has {} entries for {} points",
                    v.len(),
                    self.points()
                )));
            }
            if let Some(i) = v.iter().position(|x| !(*x >= 0.0 && x.is_finite())) {
                return Err(FlankError::Model(format!(
                    "{what}: μ[{i}] = {} must be finite and ≥ 0",
                    v[i]
                )));
            }
        }
        Ok(())
    }
}

/// How the torque is applied (the scene's increment count or size).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Increments {
    /// N equal increments T/N.
    Count(usize),
    /// Increments of this size (N·mm); the last one takes the remainder.
    Size(f64),
}

/// The method that solves each increment.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum FrictionSolver {
    /// Tresca QPs by clarabel, fixed point on the bounds, polished.
    #[default]
    Clarabel,
    /// Lemke's complementary pivoting on the increment's LCP.
    Lemke,
}

impl FrictionSolver {
    /// The name used in reports.
    pub fn name(self) -> &'static str {
        match self {
            FrictionSolver::Clarabel => "clarabel",
            FrictionSolver::Lemke => "lemke",
        }
    }
}

/// Options of [`solve_friction`].
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct FrictionOptions {
    pub increments: Increments,
    pub solver: FrictionSolver,
    /// Clarabel path: limit on Tresca QPs per increment (reaching it is
    /// reported in [`Increment::limit_hit`]).
    pub max_fixed_point: usize,
    /// Clarabel path: the fixed point stops when the bounds and Δθ̃ change
    /// by at most this (relative to μP₀ and the rotation scale); usually a
    /// polish ends it earlier (see `clarabel.rs`). Not below clarabel's own
    /// accuracy (~1e-10): the iterates stall there.
    pub fixed_point_tolerance: f64,
    /// Clarabel's own interior-point iteration limit per QP (an error).
    pub max_qp_iterations: usize,
    /// Polish: limit on state updates (reaching it is reported).
    pub max_polish: usize,
    /// Clarabel path: limit on the iterations of the semismooth Newton
    /// polish (`semismooth.rs`), tried where the active-set polish does not
    /// reach the tolerance; 0 switches it off. Reaching it is reported.
    #[serde(default = "default_max_newton")]
    pub max_newton: usize,
    /// Lemke: pivot limit per LCP (an error).
    pub max_pivots: usize,
    /// Largest accepted [`Residuals::max`]: sets `within_tolerance`.
    pub tolerance: f64,
}

impl Default for FrictionOptions {
    fn default() -> Self {
        FrictionOptions {
            increments: Increments::Count(10),
            solver: FrictionSolver::Clarabel,
            max_fixed_point: 200,
            fixed_point_tolerance: 1e-8,
            max_qp_iterations: 200,
            max_polish: 50,
            max_newton: DEFAULT_MAX_NEWTON,
            max_pivots: 20_000,
            tolerance: 1e-9,
        }
    }
}

/// Default of [`FrictionOptions::max_newton`].
pub const DEFAULT_MAX_NEWTON: usize = 50;

fn default_max_newton() -> usize {
    DEFAULT_MAX_NEWTON
}

/// The state at the end of one increment.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Increment {
    /// T_k (N·mm).
    pub torque: f64,
    /// P_n (N), totals.
    pub normal: Vec<f64>,
    /// P_t (N), totals (positive resists slip along +t).
    pub tangential: Vec<f64>,
    /// θ (rad), total loaded rotation.
    pub rotation: f64,
    /// g (mm) at the end of the increment.
    pub gap: Vec<f64>,
    /// Δσ (mm), the slip over the increment.
    pub slip: Vec<f64>,
    pub state: Vec<PointState>,
    pub residual: Residuals,
    /// Clarabel: Tresca QPs (fixed-point iterations); Lemke: pivots.
    pub iterations: usize,
    /// Clarabel: interior-point iterations summed over the QPs; Lemke:
    /// restarts with a wider rotation shift.
    pub inner_iterations: usize,
    /// Clarabel: state updates of the polish (0 if not polished).
    pub polish_iterations: usize,
    /// Clarabel: the answer is the polished (exact) one.
    pub polished: bool,
    /// Clarabel: iterations of the semismooth Newton polish, summed over
    /// its attempts in the increment (0 if not tried).
    pub newton_iterations: usize,
    /// Clarabel: the answer is the semismooth Newton polish's (then
    /// `polished` is true as well).
    pub newton: bool,
    /// A bounded loop (the fixed point, or a polish attempt) reached its
    /// limit. For a polished answer this is information only: the answer is
    /// the exact one of its states, graded by its residuals.
    pub limit_hit: bool,
}

/// The answer of [`solve_friction`].
#[derive(Clone, Debug, serde::Serialize)]
pub struct FrictionSolution {
    pub solver: FrictionSolver,
    /// θ₀ = min g⁰/r_n, the rigid start (rad).
    pub start_rotation: f64,
    /// One entry per increment; the last is the final state (empty for T = 0).
    pub increments: Vec<Increment>,
    /// Componentwise largest residual over all increments.
    pub max_residual: Residuals,
    /// max_residual.max ≤ options.tolerance, and no unpolished answer came
    /// from a loop that hit its limit.
    pub within_tolerance: bool,
}

impl FrictionSolution {
    /// Final normal loads (zeros for T = 0).
    pub fn normal(&self) -> Vec<f64> {
        match self.increments.last() {
            Some(k) => k.normal.clone(),
            None => Vec::new(),
        }
    }

    /// Final rotation.
    pub fn rotation(&self) -> f64 {
        self.increments
            .last()
            .map_or(self.start_rotation, |k| k.rotation)
    }
}

/// The input after validation: symmetric parts, scales.
pub(crate) struct Prepared {
    pub(crate) m: usize,
    pub(crate) c_nn: DMatrix<f64>,
    pub(crate) c_nt: DMatrix<f64>,
    /// = c_ntᵀ (symmetrized).
    pub(crate) c_tn: DMatrix<f64>,
    pub(crate) c_tt: DMatrix<f64>,
    pub(crate) g0: Vec<f64>,
    pub(crate) r_n: Vec<f64>,
    pub(crate) r_t: Vec<f64>,
    /// ρ = r_t + s r_n.
    pub(crate) rho: Vec<f64>,
    /// μᵢ per point and their largest value.
    pub(crate) mu: Vec<f64>,
    pub(crate) mu_max: f64,
    pub(crate) torque: f64,
    /// P₀ = T / min r_n (1 N if T = 0).
    pub(crate) p0: f64,
    /// δ₀ = max(P₀ max diag C_nn, max |g⁰|) (1 mm if 0).
    pub(crate) d0: f64,
    /// r₀ = max r_n.
    pub(crate) r0: f64,
}

fn check_len(name: &str, v: &[f64], n: usize) -> Result<(), FlankError> {
    if v.len() != n {
        return Err(FlankError::Model(format!(
            "friction LTCA: {name} has {} entries, expected {n}",
            v.len()
        )));
    }
    if let Some(i) = v.iter().position(|x| !x.is_finite()) {
        return Err(FlankError::Model(format!(
            "friction LTCA: {name}[{i}] is {}",
            v[i]
        )));
    }
    Ok(())
}

impl Prepared {
    pub(crate) fn new(pb: &FrictionProblem) -> Result<Self, FlankError> {
        let m = pb.separation.len();
        if m == 0 {
            return Err(FlankError::Model(
                "friction LTCA: no candidate contact points".into(),
            ));
        }
        check_len("separation", pb.separation, m)?;
        check_len("normal arm r_n", pb.arm_normal, m)?;
        check_len("tangential arm r_t", pb.arm_tangential, m)?;
        check_len("sliding coefficient s", pb.sliding, m)?;
        for (name, c) in [
            ("C_nn", pb.c_nn),
            ("C_nt", pb.c_nt),
            ("C_tn", pb.c_tn),
            ("C_tt", pb.c_tt),
        ] {
            check_len(name, c, m * m)?;
        }
        pb.check_mu("friction LTCA")?;
        let mu: Vec<f64> = (0..m).map(|i| pb.mu_at(i)).collect();
        let mu_max = pb.mu_max();
        if !(pb.torque >= 0.0 && pb.torque.is_finite()) {
            return Err(FlankError::Model(format!(
                "friction LTCA: torque {} N·mm must be finite and ≥ 0",
                pb.torque
            )));
        }
        if let Some(i) = pb.arm_normal.iter().position(|&v| !(v > 0.0)) {
            return Err(FlankError::Model(format!(
                "friction LTCA: normal arm r_n[{i}] = {} mm/rad must be > 0 (the point must close under the loaded rotation)",
                pb.arm_normal[i]
            )));
        }
        if let Some(i) = (0..m).find(|&i| !(pb.arm_normal[i] > mu[i] * pb.arm_tangential[i].abs()))
        {
            return Err(FlankError::Model(format!(
                "friction LTCA: self-locking at point {i}: r_n = {} ≤ μ|r_t| = {} (friction alone could carry the torque)",
                pb.arm_normal[i],
                mu[i] * pb.arm_tangential[i].abs()
            )));
        }
        let cmax = [pb.c_nn, pb.c_nt, pb.c_tn, pb.c_tt]
            .iter()
            .flat_map(|c| c.iter())
            .fold(0.0f64, |a, v| a.max(v.abs()));
        let mut asym = [0.0f64; 3];
        for i in 0..m {
            for j in 0..m {
                asym[0] = asym[0].max((pb.c_nn[i * m + j] - pb.c_nn[j * m + i]).abs());
                asym[1] = asym[1].max((pb.c_tt[i * m + j] - pb.c_tt[j * m + i]).abs());
                asym[2] = asym[2].max((pb.c_tn[i * m + j] - pb.c_nt[j * m + i]).abs());
            }
        }
        for (name, a) in ["C_nn − C_nnᵀ", "C_tt − C_ttᵀ", "C_tn − C_ntᵀ"]
            .iter()
            .zip(asym)
        {
            if a > SYMMETRY_TOLERANCE * cmax {
                return Err(FlankError::Model(format!(
                    "friction LTCA: compliance not reciprocal: max |{name}| = {a:.3e} of max |C| = {cmax:.3e} (wrong layout or directions?)"
                )));
            }
        }
        if let Some(i) = (0..m).find(|&i| !(pb.c_nn[i * m + i] > 0.0)) {
            return Err(FlankError::Model(format!(
                "friction LTCA: C_nn[{i}][{i}] = {} mm/N must be > 0",
                pb.c_nn[i * m + i]
            )));
        }
        if mu_max > 0.0 {
            if let Some(i) = (0..m).find(|&i| !(pb.c_tt[i * m + i] > 0.0)) {
                return Err(FlankError::Model(format!(
                    "friction LTCA: C_tt[{i}][{i}] = {} mm/N must be > 0",
                    pb.c_tt[i * m + i]
                )));
            }
        }
        let sym = |c: &[f64], i: usize, j: usize| 0.5 * (c[i * m + j] + c[j * m + i]);
        let c_nn = DMatrix::from_fn(m, m, |i, j| sym(pb.c_nn, i, j));
        let c_tt = DMatrix::from_fn(m, m, |i, j| sym(pb.c_tt, i, j));
        let c_nt = DMatrix::from_fn(m, m, |i, j| 0.5 * (pb.c_nt[i * m + j] + pb.c_tn[j * m + i]));
        let c_tn = c_nt.transpose();
        let max_diag = (0..m).fold(0.0f64, |a, i| a.max(c_nn[(i, i)]));
        if mu_max > 0.0 {
            // the full compliance must be positive semidefinite (clarabel's
            // QP is convex only then); a shift of 1e-12 max diag forgives round-off
            let mut full = DMatrix::zeros(2 * m, 2 * m);
            full.view_mut((0, 0), (m, m)).copy_from(&c_nn);
            full.view_mut((0, m), (m, m)).copy_from(&c_nt);
            full.view_mut((m, 0), (m, m)).copy_from(&c_tn);
            full.view_mut((m, m), (m, m)).copy_from(&c_tt);
            let dmax = (0..2 * m).fold(0.0f64, |a, i| a.max(full[(i, i)]));
            for i in 0..2 * m {
                full[(i, i)] += 1e-12 * dmax;
            }
            if full.cholesky().is_none() {
                return Err(FlankError::Model(
                    "friction LTCA: the compliance [C_nn C_nt; C_tn C_tt] is not positive semidefinite".into(),
                ));
            }
        }
        let r0 = pb.arm_normal.iter().fold(0.0f64, |a, &v| a.max(v));
        let rmin = pb.arm_normal.iter().fold(f64::INFINITY, |a, &v| a.min(v));
        let p0 = if pb.torque > 0.0 {
            pb.torque / rmin
        } else {
            1.0
        };
        let gmax = pb.separation.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let mut d0 = (p0 * max_diag).max(gmax);
        if !(d0 > 0.0 && d0.is_finite()) {
            d0 = 1.0;
        }
        Ok(Prepared {
            m,
            c_nn,
            c_nt,
            c_tn,
            c_tt,
            g0: pb.separation.to_vec(),
            r_n: pb.arm_normal.to_vec(),
            r_t: pb.arm_tangential.to_vec(),
            rho: (0..m)
                .map(|i| pb.arm_tangential[i] + pb.sliding[i] * pb.arm_normal[i])
                .collect(),
            mu,
            mu_max,
            torque: pb.torque,
            p0,
            d0,
            r0,
        })
    }

    /// Rotation scale θ_s = δ₀ / r₀ (rad).
    pub(crate) fn theta_scale(&self) -> f64 {
        self.d0 / self.r0
    }

    /// The rigid start θ₀ = min g⁰ᵢ / r_n,i.
    pub(crate) fn start_rotation(&self) -> f64 {
        (0..self.m)
            .map(|i| self.g0[i] / self.r_n[i])
            .fold(f64::INFINITY, f64::min)
    }
}

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
