//! The frictional contact problem at one roll position, its options and
//! its answer ([`FrictionProblem`], [`FrictionOptions`],
//! [`FrictionSolution`]), and the checked data every solver works on
//! ([`Prepared`]); the solvers are the sibling modules (module docs of
//! [`crate::ltca::friction`]).

use nalgebra::DMatrix;

use crate::error::FlankError;

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

/// Options of [`solve_friction`](super::solve_friction).
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

/// The answer of [`solve_friction`](super::solve_friction).
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

/// What a per-increment solver returns: the totals and its counters.
pub(crate) struct StepAnswer {
    pub(crate) pn: Vec<f64>,
    pub(crate) pt: Vec<f64>,
    pub(crate) theta: f64,
    pub(crate) iterations: usize,
    pub(crate) inner_iterations: usize,
    pub(crate) polish_iterations: usize,
    pub(crate) polished: bool,
    pub(crate) newton_iterations: usize,
    pub(crate) newton: bool,
    pub(crate) limit_hit: bool,
}
/// The state of a candidate point at the end of an increment.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum PointState {
    /// Open: P_n = P_t = 0.
    Separated,
    /// Closed, no slip over the increment, |P_t| ≤ μP_n.
    Stick,
    /// Closed, slipping along +t; P_t = +μP_n resists it.
    SlipPositive,
    /// Closed, slipping along −t; P_t = −μP_n.
    SlipNegative,
}

/// Relative residuals of an answer (P_n, P_t, θ) of increment k. Scales:
/// loads P₀ = T / min r_n, lengths δ₀ (see `Prepared`), κ = P₀/δ₀.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct Residuals {
    /// |Σ r_n P_n + r_t P_t − T_k| / T_k.
    pub equilibrium: f64,
    /// No penetration: max(0, −min g) / δ₀.
    pub gap: f64,
    /// No tension: max(0, −min P_n) / P₀.
    pub load: f64,
    /// Normal complementarity, threshold-free: maxᵢ min(P_n,i⁺/P₀, |gᵢ|/δ₀).
    pub complementarity: f64,
    /// Friction cone: max(0, max(|P_t| − μP_n)) / P₀.
    pub cone: f64,
    /// Coulomb law (stick/slip/direction) as the natural map:
    /// maxᵢ |P_t − proj_[−μP_n⁺, μP_n⁺](P_t + κΔσ)| / P₀; zero iff stick
    /// (Δσ = 0) or slip with P_t = μP_n sign Δσ, given the cone.
    pub coulomb: f64,
    /// The largest of the above.
    pub max: f64,
    /// min g (mm), unscaled.
    pub min_gap: f64,
    /// min P_n (N), unscaled.
    pub min_load: f64,
}

impl Residuals {
    /// Componentwise maximum (min_gap, min_load: minimum).
    pub fn worst(&self, o: &Residuals) -> Residuals {
        Residuals {
            equilibrium: self.equilibrium.max(o.equilibrium),
            gap: self.gap.max(o.gap),
            load: self.load.max(o.load),
            complementarity: self.complementarity.max(o.complementarity),
            cone: self.cone.max(o.cone),
            coulomb: self.coulomb.max(o.coulomb),
            max: if self.max.is_nan() || o.max.is_nan() {
                f64::NAN
            } else {
                self.max.max(o.max)
            },
            min_gap: self.min_gap.min(o.min_gap),
            min_load: self.min_load.min(o.min_load),
        }
    }
}
