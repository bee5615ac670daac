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
//! routine ([`kkt`]), and [`QpSolution::within_tolerance`] says whether
//! its largest component is at most [`QpOptions::kkt_tolerance`]. An answer
//! above tolerance is returned (it may still be useful) but never silently:
//! the caller must check the flag.

use std::fmt;
use std::str::FromStr;

use nalgebra::{DMatrix, DVector, SymmetricEigen};

use crate::error::FlankError;

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

/// The solver of the contact QP.
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    serde::Serialize,
    serde::Deserialize,
    clap::ValueEnum,
)]
#[serde(rename_all = "kebab-case")]
pub enum QpSolver {
    /// Dedicated primal active-set method (exact at termination, fast).
    #[default]
    ActiveSet,
    /// clarabel interior point, then polished on its loaded set.
    Clarabel,
}

impl QpSolver {
    /// All solvers, for sweeps and CLI help.
    pub const ALL: [QpSolver; 2] = [QpSolver::ActiveSet, QpSolver::Clarabel];

    /// The name used in scenes, the CLI and reports.
    pub fn name(self) -> &'static str {
        match self {
            QpSolver::ActiveSet => "active-set",
            QpSolver::Clarabel => "clarabel",
        }
    }
}

impl fmt::Display for QpSolver {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for QpSolver {
    type Err = FlankError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        QpSolver::ALL
            .into_iter()
            .find(|v| v.name() == s)
            .ok_or_else(|| {
                FlankError::Model(format!(
                    "unknown contact QP solver '{s}' (expected active-set or clarabel)"
                ))
            })
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

/// The KKT residuals from F p (the shared part of [`kkt`] and the solvers).
fn residuals(fp: &[f64], w: &[f64], r: &[f64], t: f64, load: &[f64], rotation: f64) -> Kkt {
    let n = w.len();
    let rmin = r.iter().fold(f64::INFINITY, |a, &v| a.min(v));
    let rmax = r.iter().fold(0.0f64, |a, &v| a.max(v));
    let mut p0 = if t > 0.0 {
        t / rmin
    } else {
        load.iter().fold(0.0f64, |a, v| a.max(v.abs()))
    };
    if !(p0 > 0.0) {
        p0 = 1.0;
    }
    let mut d0 = w
        .iter()
        .chain(fp)
        .fold(0.0f64, |a, v| a.max(v.abs()))
        .max(rotation.abs() * rmax);
    if !(d0 > 0.0) {
        d0 = 1.0;
    }
    let mut k = Kkt::default();
    let mut rp = 0.0;
    let mut rp_abs = 0.0;
    let mut finite = rotation.is_finite();
    for i in 0..n {
        let g = fp[i] + w[i] - rotation * r[i];
        let p = load[i];
        rp += r[i] * p;
        rp_abs += (r[i] * p).abs();
        if p > 0.0 {
            k.stationarity = k.stationarity.max(g.abs() / d0);
        }
        k.primal_feasibility = k.primal_feasibility.max(-p / p0);
        k.dual_feasibility = k.dual_feasibility.max(-g / d0);
        k.complementarity = k.complementarity.max((p.max(0.0) / p0).min(g.abs() / d0));
        finite &= g.is_finite() && p.is_finite();
    }
    let escale = if t > 0.0 {
        t
    } else {
        rp_abs.max(f64::MIN_POSITIVE)
    };
    k.equilibrium = (rp - t).abs() / escale;
    if !finite {
        // f64::max drops NaN: mark non-finite input explicitly
        k.stationarity = f64::NAN;
    }
    let parts = [
        k.stationarity,
        k.equilibrium,
        k.primal_feasibility,
        k.dual_feasibility,
        k.complementarity,
    ];
    k.max = if parts.iter().any(|v| v.is_nan()) {
        f64::NAN
    } else {
        parts.iter().fold(0.0f64, |a, &v| a.max(v))
    };
    k
}

/// Relative KKT residuals of loads `load` and rotation `rotation` for the
/// problem `qp` (scales in [`Kkt`]). Uses the symmetric part of F. Lengths
/// that do not match the problem give NaN residuals.
pub fn kkt(qp: &ContactQp, load: &[f64], rotation: f64) -> Kkt {
    let n = qp.separation.len();
    if qp.moment_arm.len() != n || qp.compliance.len() != n * n || load.len() != n {
        return Kkt {
            stationarity: f64::NAN,
            equilibrium: f64::NAN,
            primal_feasibility: f64::NAN,
            dual_feasibility: f64::NAN,
            complementarity: f64::NAN,
            max: f64::NAN,
        };
    }
    let fp: Vec<f64> = (0..n)
        .map(|i| {
            (0..n)
                .map(|j| 0.5 * (qp.compliance[i * n + j] + qp.compliance[j * n + i]) * load[j])
                .sum()
        })
        .collect();
    residuals(&fp, qp.separation, qp.moment_arm, qp.torque, load, rotation)
}

/// 2-norm condition number κ(F) = λ_max/λ_min of the symmetric part of F
/// (n × n row-major) from its eigenvalues, for reports. ∞ if λ_min ≤ 0
/// (semi-definite or indefinite), NaN for a wrong length or non-finite
/// entries.
pub fn condition_number(compliance: &[f64], n: usize) -> f64 {
    if compliance.len() != n * n || n == 0 || compliance.iter().any(|v| !v.is_finite()) {
        return f64::NAN;
    }
    let f = DMatrix::from_fn(n, n, |i, j| {
        0.5 * (compliance[i * n + j] + compliance[j * n + i])
    });
    let eig = SymmetricEigen::new(f).eigenvalues;
    let lmax = eig.iter().fold(f64::NEG_INFINITY, |a, &v| a.max(v));
    let lmin = eig.iter().fold(f64::INFINITY, |a, &v| a.min(v));
    if !(lmin > 0.0) {
        f64::INFINITY
    } else {
        lmax / lmin
    }
}

/// The solution of the equality-constrained problem on a loaded set.
struct Eqp {
    /// p_S, in the order of the set.
    load: Vec<f64>,
    rotation: f64,
    /// Diagonal shift used (absolute, mm/N).
    shift: f64,
}

/// Solves [F_SS −r_S; r_Sᵀ 0][p_S; θ] = [−w_S; T] on `set` (Cholesky of
/// F_SS, Schur complement r_Sᵀ F_SS⁻¹ r_S, one refinement step against the
/// unshifted F_SS).
fn solve_eqp(prob: &Prepared, set: &[usize]) -> Result<Eqp, FlankError> {
    let m = set.len();
    let a = DMatrix::from_fn(m, m, |i, j| prob.f[(set[i], set[j])]);
    let ws = DVector::from_iterator(m, set.iter().map(|&i| prob.w[i]));
    let rs = DVector::from_iterator(m, set.iter().map(|&i| prob.r[i]));
    let dmax = (0..m).fold(0.0f64, |acc, i| acc.max(a[(i, i)]));
    let mut shift = 0.0;
    let chol = loop {
        let mut shifted = a.clone();
        for i in 0..m {
            shifted[(i, i)] += shift;
        }
        if let Some(c) = shifted.clone().cholesky() {
            let l = c.l_dirty();
            let ratio = (0..m).fold(f64::INFINITY, |acc, i| {
                acc.min(l[(i, i)] * l[(i, i)] / shifted[(i, i)])
            });
            if ratio >= PIVOT_RATIO_MIN {
                break c;
            }
        }
        shift = if shift == 0.0 {
            REGULARIZATION_START * dmax
        } else {
            shift * 100.0
        };
        if shift > REGULARIZATION_MAX * dmax {
            return Err(FlankError::Solver(format!(
                "LTCA contact QP: the compliance of the {m} loaded points is not positive definite even with a diagonal shift of {:.1e} of its diagonal (points {:?}…)",
                REGULARIZATION_MAX,
                &set[..m.min(8)]
            )));
        }
    };
    let b = chol.solve(&rs);
    let c = chol.solve(&ws);
    let rb = rs.dot(&b);
    let mut theta = (prob.t + rs.dot(&c)) / rb;
    let mut q = &b * theta - &c;
    // residuals (compatibility on S relative to its scale; equilibrium)
    let residual = |q: &DVector<f64>, theta: f64| {
        let e = &a * q + &ws - &rs * theta;
        let tau = prob.t - rs.dot(q);
        let scale = ws.amax().max((&a * q).amax()).max(theta.abs() * rs.amax());
        let size = e.amax() / scale.max(f64::MIN_POSITIVE) + tau.abs() / prob.t;
        (e, tau, size)
    };
    let (e, tau, size) = residual(&q, theta);
    let fe = chol.solve(&e);
    let dtheta = (tau + rs.dot(&fe)) / rb;
    let q2 = &q + &b * dtheta - fe;
    let theta2 = theta + dtheta;
    let (_, _, size2) = residual(&q2, theta2);
    if size2 <= size {
        q = q2;
        theta = theta2;
    }
    if !(theta.is_finite() && q.iter().all(|v| v.is_finite())) {
        return Err(FlankError::Solver(format!(
            "LTCA contact QP: the equality-constrained solve on {m} loaded points gave non-finite values"
        )));
    }
    Ok(Eqp {
        load: q.iter().copied().collect(),
        rotation: theta,
        shift,
    })
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

/// The primal active-set method (module doc), cold start. T > 0.
fn active_set(prob: &Prepared, options: &QpOptions) -> Result<Raw, FlankError> {
    let (w, r) = (prob.w, prob.r);
    // start: the first point to close under a rigid rotation takes all
    // (the exact minimizer on that one-point set)
    let k = (0..prob.n)
        .min_by(|&a, &b| (w[a] / r[a]).total_cmp(&(w[b] / r[b])).then(a.cmp(&b)))
        .expect("n > 0");
    let mut load = vec![0.0; prob.n];
    load[k] = prob.t / r[k];
    let rotation = (prob.f[(k, k)] * load[k] + w[k]) / r[k];
    iterate(prob, options, vec![k], load, rotation, 1)
}

/// Active-set iterations from a feasible start: loads ≥ 0, zero outside
/// `free`, rᵀp = T. If `done` > 0 the start is the equality-constrained
/// minimizer on `free` (with multiplier `rotation`) and counts as `done`
/// solves; if 0 that minimizer is sought first. Returns the answer with the
/// number of equality-constrained solves (including `done`).
fn iterate(
    prob: &Prepared,
    options: &QpOptions,
    mut free: Vec<usize>,
    mut p: Vec<f64>,
    mut theta: f64,
    done: usize,
) -> Result<Raw, FlankError> {
    let n = prob.n;
    let (w, r, t) = (prob.w, prob.r, prob.t);
    let pscale = t / r.iter().fold(f64::INFINITY, |a, &v| a.min(v));
    let rmax = r.iter().fold(0.0f64, |a, &v| a.max(v));
    let wmax = w.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let add_tol = (1e-3 * options.kkt_tolerance).max(1e-14);
    let mut in_free = vec![false; n];
    for &i in &free {
        in_free[i] = true;
    }
    let mut iterations = done;
    let mut shift = 0.0f64;
    let mut single = false;
    // points that entered alone and were dropped at once (round-off or a
    // singular F_SS): not re-entered until the iterate moves
    let mut refused = vec![false; n];
    let mut entered_alone: Option<usize> = None;
    let mut need_solve = done == 0;
    loop {
        // minimize on the loaded set, cutting steps at zero loads
        if need_solve {
            loop {
                if iterations >= options.max_iterations {
                    return Err(FlankError::Solver(format!(
                    "LTCA active set: iteration limit {} (QpOptions::max_iterations) reached with {} of {n} points loaded",
                    options.max_iterations,
                    free.len()
                )));
                }
                iterations += 1;
                let eqp = solve_eqp(prob, &free)?;
                shift = shift.max(eqp.shift);
                if eqp.load.iter().all(|&v| v >= 0.0) {
                    for (a, &i) in free.iter().enumerate() {
                        p[i] = eqp.load[a];
                    }
                    theta = eqp.rotation;
                    refused.iter_mut().for_each(|v| *v = false);
                    break;
                }
                // ratio test: the largest step keeping every load ≥ 0
                let mut alpha = 1.0f64;
                for (a, &i) in free.iter().enumerate() {
                    let q = eqp.load[a];
                    if q < 0.0 {
                        alpha = alpha.min(p[i] / (p[i] - q));
                    }
                }
                for (a, &i) in free.iter().enumerate() {
                    p[i] += alpha * (eqp.load[a] - p[i]);
                }
                // the blocking points (and ties within round-off) leave
                let mut dropped = Vec::new();
                for (a, &i) in free.iter().enumerate() {
                    if eqp.load[a] < 0.0 && p[i] <= 1e-14 * pscale {
                        dropped.push(i);
                    }
                }
                for &i in &dropped {
                    p[i] = 0.0;
                    in_free[i] = false;
                }
                free.retain(|&i| in_free[i]);
                if alpha > 0.0 {
                    refused.iter_mut().for_each(|v| *v = false);
                } else {
                    single = true;
                    if let Some(j) = entered_alone {
                        if dropped.contains(&j) {
                            refused[j] = true;
                        }
                    }
                }
                if free.is_empty() {
                    return Err(FlankError::Solver(
                    "LTCA active set: every point was dropped from the loaded set (round-off in the ratio test)".into(),
                ));
                }
            }
        }
        // gaps from the loaded columns
        let mut fp = vec![0.0; n];
        for &j in &free {
            if p[j] != 0.0 {
                for (v, &fij) in fp.iter_mut().zip(prob.f.column(j).iter()) {
                    *v += fij * p[j];
                }
            }
        }
        let fpmax = fp.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let d0 = wmax.max(fpmax).max(theta.abs() * rmax);
        let threshold = add_tol * d0;
        let mut viol: Vec<(f64, usize)> = (0..n)
            .filter(|&i| !in_free[i] && !refused[i])
            .map(|i| (fp[i] + w[i] - theta * r[i], i))
            .filter(|&(g, _)| g < -threshold)
            .collect();
        if viol.is_empty() {
            break;
        }
        viol.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        if single {
            viol.truncate(1);
        } else {
            let worst = viol[0].0;
            viol.retain(|v| v.0 <= ADDITION_FRACTION * worst);
        }
        entered_alone = if viol.len() == 1 {
            Some(viol[0].1)
        } else {
            None
        };
        for &(_, i) in &viol {
            free.push(i);
            in_free[i] = true;
        }
        single = false;
        need_solve = true;
    }
    Ok(Raw {
        load: p,
        rotation: theta,
        iterations,
        shift,
        polished: false,
        polish_iterations: 0,
        raw_kkt: None,
    })
}

/// clarabel on the scaled QP, then the polish (module doc). T > 0.
///
/// Scaling: with r₀ = max rᵢ, f₀ = max Fᵢᵢ, P₀ = T/r₀ and δ₀ = P₀f₀,
/// p = P₀p̂, F = f₀F̂, r = r₀r̂, w = δ₀ŵ, and the objective divided by
/// P₀δ₀, clarabel solves
///
/// ```text
///   min ½ p̂ᵀF̂p̂ + ŵᵀp̂   s.t.  r̂ᵀp̂ + s₀ = 1, s₀ = 0 (zero cone),
///                             −p̂ + s = 0,  s ≥ 0 (non-negative cone),
/// ```
///
/// whose entries are O(1) (F ~ 1e-5 mm/N and T ~ 1e5 N·mm unscaled would
/// span 10 decades). clarabel's optimality conditions are
/// P x + q + Aᵀz = 0, i.e. F̂p̂ + ŵ + z₀r̂ − z₁..ₙ = 0: the bound multipliers
/// are the scaled gaps ĝ = z₁..ₙ and the rotation is θ̂ = −z₀, θ = θ̂δ₀/r₀
/// (sign checked against the active set in the tests).
fn solve_clarabel(prob: &Prepared, options: &QpOptions) -> Result<Raw, FlankError> {
    let n = prob.n;
    let ClarabelRaw {
        load: raw_load,
        rotation: raw_rotation,
        loaded: set,
        iterations,
    } = clarabel_raw(prob, options)?;
    let fp = prob.apply(&raw_load);
    let raw_kkt = residuals(&fp, prob.w, prob.r, prob.t, &raw_load, raw_rotation);
    // polish: active-set iterations from the loaded set read off the
    // answer, loads rescaled to rᵀp = T (usually one equality solve)
    let rp: f64 = set.iter().map(|&i| prob.r[i] * raw_load[i]).sum();
    if !set.is_empty() && rp > 0.0 {
        let mut start = vec![0.0; n];
        for &i in &set {
            start[i] = raw_load[i] * prob.t / rp;
        }
        if let Ok(polish) = iterate(prob, options, set, start, raw_rotation, 0) {
            let fp = prob.apply(&polish.load);
            let kkt = residuals(&fp, prob.w, prob.r, prob.t, &polish.load, polish.rotation);
            if !(kkt.max > raw_kkt.max) {
                return Ok(Raw {
                    iterations,
                    polished: true,
                    polish_iterations: polish.iterations,
                    raw_kkt: Some(raw_kkt),
                    ..polish
                });
            }
        }
    }
    Ok(Raw {
        load: raw_load,
        rotation: raw_rotation,
        iterations,
        shift: 0.0,
        polished: false,
        polish_iterations: 0,
        raw_kkt: Some(raw_kkt),
    })
}

/// clarabel's unpolished answer.
struct ClarabelRaw {
    load: Vec<f64>,
    rotation: f64,
    /// Points with p̂ᵢ > ĝᵢ (scaled load above scaled gap).
    loaded: Vec<usize>,
    iterations: usize,
}

/// Builds the scaled problem (see `solve_clarabel`), runs clarabel, maps
/// its status and unscales its answer.
fn clarabel_raw(prob: &Prepared, options: &QpOptions) -> Result<ClarabelRaw, FlankError> {
    use clarabel::algebra::CscMatrix;
    use clarabel::solver::{
        DefaultSettings, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
    };
    let n = prob.n;
    let r0 = prob.r.iter().fold(0.0f64, |a, &v| a.max(v));
    let f0 = prob.max_diag;
    let p0 = prob.t / r0;
    let d0 = p0 * f0;
    // P: upper triangle of F̂, CSC
    let mut colptr = Vec::with_capacity(n + 1);
    let mut rowval = Vec::with_capacity(n * (n + 1) / 2);
    let mut nzval = Vec::with_capacity(n * (n + 1) / 2);
    colptr.push(0);
    for j in 0..n {
        for i in 0..=j {
            let v = prob.f[(i, j)] / f0;
            if v != 0.0 || i == j {
                rowval.push(i);
                nzval.push(v);
            }
        }
        colptr.push(rowval.len());
    }
    let pm = CscMatrix::new(n, n, colptr, rowval, nzval);
    let q: Vec<f64> = prob.w.iter().map(|v| v / d0).collect();
    // A: row 0 = r̂ᵀ, rows 1..=n = −I
    let mut colptr = Vec::with_capacity(n + 1);
    let mut rowval = Vec::with_capacity(2 * n);
    let mut nzval = Vec::with_capacity(2 * n);
    colptr.push(0);
    for j in 0..n {
        rowval.push(0);
        nzval.push(prob.r[j] / r0);
        rowval.push(1 + j);
        nzval.push(-1.0);
        colptr.push(rowval.len());
    }
    let am = CscMatrix::new(n + 1, n, colptr, rowval, nzval);
    let mut b = vec![0.0; n + 1];
    b[0] = 1.0;
    let cones = [
        SupportedConeT::ZeroConeT(1),
        SupportedConeT::NonnegativeConeT(n),
    ];
    let settings = DefaultSettings {
        verbose: false,
        max_iter: options.max_iterations.min(u32::MAX as usize) as u32,
        tol_gap_abs: 1e-10,
        tol_gap_rel: 1e-10,
        tol_feas: 1e-10,
        ..DefaultSettings::default()
    };
    let mut solver = DefaultSolver::new(&pm, &q, &am, &b, &cones, settings)
        .map_err(|e| FlankError::Solver(format!("LTCA clarabel setup: {e}")))?;
    solver.solve();
    let sol = &solver.solution;
    match sol.status {
        SolverStatus::Solved | SolverStatus::AlmostSolved | SolverStatus::InsufficientProgress => {}
        SolverStatus::PrimalInfeasible
        | SolverStatus::AlmostPrimalInfeasible
        | SolverStatus::DualInfeasible
        | SolverStatus::AlmostDualInfeasible => {
            return Err(FlankError::Solver(format!(
                "LTCA clarabel: status {} after {} iterations; the problem is feasible and bounded for r > 0 and T ≥ 0, so this is a numerical failure (condition of F?)",
                sol.status, sol.iterations
            )));
        }
        SolverStatus::MaxIterations => {
            return Err(FlankError::Solver(format!(
                "LTCA clarabel: iteration limit {} (QpOptions::max_iterations) reached",
                options.max_iterations
            )));
        }
        other => {
            return Err(FlankError::Solver(format!(
                "LTCA clarabel: status {other} after {} iterations",
                sol.iterations
            )));
        }
    }
    let iterations = sol.iterations as usize;
    let x = &sol.x;
    let z = &sol.z;
    if x.len() != n || z.len() != n + 1 || x.iter().chain(z).any(|v| !v.is_finite()) {
        return Err(FlankError::Solver(format!(
            "LTCA clarabel: status {} but a non-finite or mis-sized answer",
            sol.status
        )));
    }
    Ok(ClarabelRaw {
        load: x.iter().map(|v| v * p0).collect(),
        rotation: -z[0] * d0 / r0,
        loaded: (0..n).filter(|&i| x[i] > z[1 + i] && x[i] > 0.0).collect(),
        iterations,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Instant;

    /// Knuth's MMIX LCG, top 53 bits: a reproducible uniform [0, 1).
    struct Lcg(u64);
    impl Lcg {
        fn next(&mut self) -> f64 {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (self.0 >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    struct Problem {
        f: Vec<f64>,
        w: Vec<f64>,
        r: Vec<f64>,
        t: f64,
    }

    impl Problem {
        fn qp(&self) -> ContactQp<'_> {
            ContactQp {
                compliance: &self.f,
                separation: &self.w,
                moment_arm: &self.r,
                torque: self.t,
            }
        }
    }

    fn options(solver: QpSolver) -> QpOptions {
        QpOptions {
            solver,
            ..QpOptions::default()
        }
    }

    fn solve(pb: &Problem, solver: QpSolver) -> QpSolution {
        solve_contact_qp(&pb.qp(), &options(solver)).unwrap()
    }

    /// Laplace-kernel compliance c·exp(−|xᵢ − xⱼ|/λ) + d·δᵢⱼ at points
    /// `x` (SPD for distinct points: the kernel is positive definite).
    fn kernel(x: &[[f64; 2]], c: f64, lambda: f64, d: f64) -> Vec<f64> {
        let n = x.len();
        let mut f = vec![0.0; n * n];
        for i in 0..n {
            for j in 0..n {
                let dist = ((x[i][0] - x[j][0]).powi(2) + (x[i][1] - x[j][1]).powi(2)).sqrt();
                f[i * n + j] = c * (-dist / lambda).exp() + if i == j { d } else { 0.0 };
            }
        }
        f
    }

    /// A flank-like random problem: points on a 10 × 3 mm patch, Laplace
    /// kernel (or, `generic`, F = c·BBᵀ/n + d·I with a random B),
    /// separations a·(u − 0.2) (both signs), arms 30…60 mm, T = 1e5 N·mm.
    fn random_problem(n: usize, seed: u64, generic: bool) -> Problem {
        let mut rng = Lcg(seed);
        let x: Vec<[f64; 2]> = (0..n)
            .map(|_| [10.0 * rng.next(), 3.0 * rng.next()])
            .collect();
        let f = if generic {
            let b: Vec<f64> = (0..n * n).map(|_| rng.next() - 0.5).collect();
            let mut f = vec![0.0; n * n];
            for i in 0..n {
                for j in 0..n {
                    let s: f64 = (0..n).map(|k| b[i * n + k] * b[j * n + k]).sum();
                    f[i * n + j] = 2e-5 * s / n as f64 + if i == j { 2e-6 } else { 0.0 };
                }
            }
            f
        } else {
            kernel(&x, 8e-6, 1.5, 4e-6)
        };
        let w = (0..n).map(|_| 2e-2 * (rng.next() - 0.2)).collect();
        let r = (0..n).map(|_| 30.0 + 30.0 * rng.next()).collect();
        Problem { f, w, r, t: 1e5 }
    }

    fn rel_load_diff(a: &[f64], b: &[f64]) -> f64 {
        let pmax = a.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        a.iter()
            .zip(b)
            .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
            / pmax
    }

    fn check_basic(pb: &Problem, s: &QpSolution) {
        assert!(s.rotation.is_finite());
        assert!(s.load.iter().all(|v| v.is_finite() && *v >= 0.0));
        let rp: f64 = s.load.iter().zip(&pb.r).map(|(p, r)| p * r).sum();
        assert!(
            (rp - pb.t).abs() <= 1e-10 * pb.t,
            "rᵀp = {rp} vs T = {}",
            pb.t
        );
        // the public residual routine gives the same figures
        let k = kkt(&pb.qp(), &s.load, s.rotation);
        assert!((k.max - s.kkt.max).abs() <= 1e-12, "{k:?} vs {:?}", s.kkt);
    }

    /// Both solvers; active set within tolerance; agreement.
    fn agree(pb: &Problem, p_tol: f64, theta_tol: f64) -> (QpSolution, QpSolution) {
        let a = solve(pb, QpSolver::ActiveSet);
        let c = solve(pb, QpSolver::Clarabel);
        check_basic(pb, &a);
        check_basic(pb, &c);
        assert!(a.within_tolerance, "active set KKT {:?}", a.kkt);
        assert!(c.within_tolerance, "clarabel KKT {:?}", c.kkt);
        let dp = rel_load_diff(&a.load, &c.load);
        let dt = (a.rotation - c.rotation).abs() / a.rotation.abs();
        assert!(dp <= p_tol, "loads differ by {dp:.3e}");
        assert!(
            dt <= theta_tol,
            "rotations {} vs {} ({dt:.3e})",
            a.rotation,
            c.rotation
        );
        (a, c)
    }

    #[test]
    fn one_point() {
        let pb = Problem {
            f: vec![1.2e-5],
            w: vec![-3e-3],
            r: vec![45.0],
            t: 2e5,
        };
        for solver in QpSolver::ALL {
            let s = solve(&pb, solver);
            let p = 2e5 / 45.0;
            assert!((s.load[0] - p).abs() <= 1e-12 * p);
            let theta = (1.2e-5 * p - 3e-3) / 45.0;
            assert!(
                (s.rotation - theta).abs() <= 1e-12 * theta.abs(),
                "{solver}"
            );
            assert!(s.within_tolerance && s.active[0]);
        }
    }

    #[test]
    fn two_springs() {
        // both in contact: θ = (T + Σ rᵢwᵢ/cᵢ) / Σ rᵢ²/cᵢ, pᵢ = (θrᵢ − wᵢ)/cᵢ
        let (c1, c2, r1, r2, t) = (1e-5, 2e-5, 40.0, 50.0, 1e5);
        let pb = Problem {
            f: vec![c1, 0.0, 0.0, c2],
            w: vec![0.0, 1e-3],
            r: vec![r1, r2],
            t,
        };
        let theta = (t + r2 * 1e-3 / c2) / (r1 * r1 / c1 + r2 * r2 / c2);
        let p = [theta * r1 / c1, (theta * r2 - 1e-3) / c2];
        for solver in QpSolver::ALL {
            let s = solve(&pb, solver);
            assert!(
                (s.rotation - theta).abs() <= 1e-12 * theta,
                "{solver}: {}",
                s.rotation
            );
            assert!(
                rel_load_diff(&p, &s.load) <= 1e-12,
                "{solver}: {:?}",
                s.load
            );
            assert!(s.within_tolerance && s.active == [true, true]);
        }
        // second spring open: θ = (c₁T/r₁ + w₁)/r₁, g₂ = w₂ − θr₂ > 0
        let pb = Problem {
            w: vec![0.0, 5e-2],
            ..pb
        };
        let theta = c1 * t / r1 / r1;
        for solver in QpSolver::ALL {
            let s = solve(&pb, solver);
            assert!((s.rotation - theta).abs() <= 1e-12 * theta, "{solver}");
            assert_eq!(s.load[1], 0.0, "{solver}");
            assert!((s.gap[1] - (5e-2 - theta * r2)).abs() <= 1e-15);
            assert!(s.within_tolerance && s.active == [true, false]);
        }
    }

    #[test]
    fn uniform_line_is_symmetric() {
        let n = 41;
        let x: Vec<[f64; 2]> = (0..n).map(|i| [0.5 * i as f64, 0.0]).collect();
        let pb = Problem {
            f: kernel(&x, 5e-6, 2.0, 5e-6),
            w: vec![0.0; n],
            r: vec![40.0; n],
            t: 1e5,
        };
        let (a, _) = agree(&pb, 1e-6, 1e-8);
        let pmax = a.load.iter().fold(0.0f64, |m, &v| m.max(v));
        for i in 0..n {
            assert!((a.load[i] - a.load[n - 1 - i]).abs() <= 1e-10 * pmax);
        }
        assert!(a.active.iter().all(|&v| v), "all points carry load");
        // the ends of a line carry more than the middle (kernel edge effect)
        assert!(a.load[0] > a.load[n / 2]);
    }

    #[test]
    fn random_problems_agree() {
        for (k, &n) in [5usize, 10, 20, 50, 100, 200].iter().enumerate() {
            for generic in [false, true] {
                let pb = random_problem(n, 17 + k as u64, generic);
                let t0 = Instant::now();
                let a = solve(&pb, QpSolver::ActiveSet);
                let ta = t0.elapsed().as_secs_f64();
                let t0 = Instant::now();
                let c = solve(&pb, QpSolver::Clarabel);
                let tc = t0.elapsed().as_secs_f64();
                let (a2, _) = agree(&pb, 1e-6, 1e-8);
                assert_eq!(a.load, a2.load, "deterministic");
                assert!(a.kkt.max <= 1e-9);
                let loaded = a.active.iter().filter(|&&v| v).count();
                assert!(
                    loaded > 0 && (n < 10 || loaded < n),
                    "a mix of open and loaded points"
                );
                // clarabel's raw interior point, before the polish
                let raw = clarabel_raw(
                    &Prepared::new(&pb.qp()).unwrap(),
                    &options(QpSolver::Clarabel),
                )
                .unwrap();
                let dp_raw = rel_load_diff(&a.load, &raw.load);
                let dt_raw = (a.rotation - raw.rotation).abs() / a.rotation.abs();
                eprintln!(
                    "n {n:3} {}: {loaded:3} loaded; active set {} it {:.2e} s KKT {:.1e}; clarabel {} it {:.2e} s raw KKT {:.1e} Δp {dp_raw:.1e} Δθ {dt_raw:.1e}, polished KKT {:.1e} ({} solves); θ {:.3e} Δp {:.1e} Δθ {:.1e}",
                    if generic { "BBᵀ   " } else { "kernel" },
                    a.iterations,
                    ta,
                    a.kkt.max,
                    c.iterations,
                    tc,
                    c.raw_kkt.unwrap().max,
                    c.kkt.max,
                    c.polish_iterations,
                    a.rotation,
                    rel_load_diff(&a.load, &c.load),
                    (a.rotation - c.rotation).abs() / a.rotation.abs()
                );
                assert!(c.polished);
                assert!(
                    dp_raw <= 1e-6 && dt_raw <= 1e-8,
                    "raw clarabel: Δp {dp_raw:.1e} Δθ {dt_raw:.1e}"
                );
            }
        }
    }

    #[test]
    fn clarabel_raw_rotation_sign() {
        // θ = −z₀δ₀/r₀ from clarabel's raw duals (no polish) matches the
        // active set: the sign convention of the equality's multiplier
        let pb = random_problem(30, 5, false);
        let prob = Prepared::new(&pb.qp()).unwrap();
        let a = solve(&pb, QpSolver::ActiveSet);
        let raw_theta = clarabel_raw(&prob, &QpOptions::default()).unwrap().rotation;
        assert!(
            (raw_theta - a.rotation).abs() <= 1e-6 * a.rotation,
            "raw θ {raw_theta} vs {}",
            a.rotation
        );
    }

    #[test]
    fn zero_torque() {
        let pb = Problem {
            t: 0.0,
            ..random_problem(12, 3, false)
        };
        let theta = (0..12)
            .map(|i| pb.w[i] / pb.r[i])
            .fold(f64::INFINITY, f64::min);
        for solver in QpSolver::ALL {
            let s = solve(&pb, solver);
            assert!(s.load.iter().all(|&v| v == 0.0));
            assert_eq!(s.rotation, theta);
            assert!(s.gap.iter().all(|&g| g >= -1e-18));
            assert!(s.within_tolerance && s.iterations == 0);
        }
    }

    /// A named problem and the indices of its twin points (if duplicated).
    type Case = (String, Problem, Option<(usize, usize)>);

    #[test]
    fn extreme_cases() {
        let n = 60;
        let mut cases: Vec<(&str, Problem)> = Vec::new();
        for (name, s) in [("F×1e-3", 1e-3), ("F×1e3", 1e3)] {
            let mut pb = random_problem(n, 99, false);
            pb.f.iter_mut().for_each(|v| *v *= s);
            pb.w.iter_mut().for_each(|v| *v *= s);
            cases.push((name, pb));
        }
        for (name, s) in [("T×1e-3", 1e-3), ("T×10", 10.0)] {
            let mut pb = random_problem(n, 99, false);
            pb.t *= s;
            cases.push((name, pb));
        }
        // two bodies: the second half 100× stiffer, no coupling
        let mut pb = random_problem(n, 99, false);
        for i in 0..n {
            for j in 0..n {
                if (i < n / 2) != (j < n / 2) {
                    pb.f[i * n + j] = 0.0;
                } else if i >= n / 2 {
                    pb.f[i * n + j] *= 1e-2;
                }
            }
        }
        cases.push(("two bodies 100×", pb));
        // zero backlash: all separations equal
        let mut pb = random_problem(n, 99, false);
        pb.w.iter_mut().for_each(|v| *v = 1e-3);
        cases.push(("all w equal", pb));
        // heavy crowning along a line: w from 0 to 1 mm
        let x: Vec<[f64; 2]> = (0..n)
            .map(|i| [20.0 * i as f64 / (n - 1) as f64, 0.0])
            .collect();
        cases.push((
            "crowning 0…1 mm",
            Problem {
                f: kernel(&x, 8e-6, 1.5, 4e-6),
                w: x.iter().map(|p| ((p[0] - 6.0) / 14.0).powi(2)).collect(),
                r: vec![40.0; n],
                t: 1e5,
            },
        ));
        let mut all: Vec<Case> = cases
            .into_iter()
            .map(|(a, b)| (a.to_string(), b, None))
            .collect();
        // nearly duplicated points: a copy of the first point to close
        // (exact, and with its diagonal compliance 1e-9 larger)
        for (name, eps, flat) in [
            ("duplicate", 0.0, false),
            ("near duplicate", 1e-9, false),
            ("duplicate, w = 0", 0.0, true),
        ] {
            let mut pb = random_problem(n, 99, false);
            if flat {
                // both twins enter the loaded set together: F_SS singular
                pb.w.iter_mut().for_each(|v| *v = 0.0);
            }
            let k = (0..n)
                .min_by(|&a, &b| (pb.w[a] / pb.r[a]).total_cmp(&(pb.w[b] / pb.r[b])))
                .unwrap();
            // (w = 0: a pair away from the start point, 0)
            let (src, dst) = if flat {
                (n / 2, n / 2 + 1)
            } else {
                (k, if k == 0 { 1 } else { 0 })
            };
            for j in 0..n {
                pb.f[dst * n + j] = pb.f[src * n + j];
            }
            for i in 0..n {
                pb.f[i * n + dst] = pb.f[i * n + src];
            }
            pb.f[dst * n + dst] = pb.f[src * n + src] * (1.0 + eps);
            pb.w[dst] = pb.w[src];
            pb.r[dst] = pb.r[src];
            all.push((name.to_string(), pb, Some((src, dst))));
        }
        for (name, pb, twins) in &all {
            let a = solve(pb, QpSolver::ActiveSet);
            let c = solve(pb, QpSolver::Clarabel);
            check_basic(pb, &a);
            check_basic(pb, &c);
            let loaded = a.active.iter().filter(|&&v| v).count();
            eprintln!(
                "{name:16}: {loaded:2} loaded, κ(F) {:.1e}; active set {} it KKT {:.1e} reg {:.0e}; clarabel {} it KKT {:.1e} polished {} ({} solves) reg {:.0e}; Δp {:.1e} Δθ {:.1e}",
                condition_number(&pb.f, n),
                a.iterations,
                a.kkt.max,
                a.regularization,
                c.iterations,
                c.kkt.max,
                c.polished,
                c.polish_iterations,
                c.regularization,
                rel_load_diff(&a.load, &c.load),
                (a.rotation - c.rotation).abs() / a.rotation.abs()
            );
            assert!(a.within_tolerance, "{name}: active set {:?}", a.kkt);
            if name.contains("w = 0") {
                assert!(a.regularization > 0.0, "both twins entered together");
            }
            assert!(c.within_tolerance, "{name}: clarabel {:?}", c.kkt);
            assert!(
                (a.rotation - c.rotation).abs() <= 1e-8 * a.rotation.abs(),
                "{name}"
            );
            if let Some((i, j)) = *twins {
                // the split between the twins is not determined (exact
                // copy) or ill-determined (κ ~ 1e10): their sum and every
                // other load are
                let sum = |s: &QpSolution| {
                    let mut l = s.load.clone();
                    l[i] += l[j];
                    l[j] = 0.0;
                    l
                };
                assert!(rel_load_diff(&sum(&a), &sum(&c)) <= 1e-6, "{name}");
            } else {
                assert!(rel_load_diff(&a.load, &c.load) <= 1e-6, "{name}");
            }
        }
    }

    #[test]
    fn bad_input() {
        let pb = random_problem(4, 1, false);
        let opts = QpOptions::default();
        let err = |qp: ContactQp| solve_contact_qp(&qp, &opts).unwrap_err().to_string();
        let empty: [f64; 0] = [];
        assert!(err(ContactQp {
            compliance: &empty,
            separation: &empty,
            moment_arm: &empty,
            torque: 1.0
        })
        .contains("no candidate"));
        assert!(err(ContactQp {
            moment_arm: &pb.r[..3],
            ..pb.qp()
        })
        .contains("moment arms"));
        assert!(err(ContactQp {
            compliance: &pb.f[..15],
            ..pb.qp()
        })
        .contains("compliance entries"));
        assert!(err(ContactQp {
            torque: -1.0,
            ..pb.qp()
        })
        .contains("torque"));
        assert!(err(ContactQp {
            torque: f64::NAN,
            ..pb.qp()
        })
        .contains("torque"));
        let mut w = pb.w.clone();
        w[2] = f64::INFINITY;
        assert!(err(ContactQp {
            separation: &w,
            ..pb.qp()
        })
        .contains("separation of point 2"));
        let mut r = pb.r.clone();
        r[1] = 0.0;
        assert!(err(ContactQp {
            moment_arm: &r,
            ..pb.qp()
        })
        .contains("moment arm of point 1"));
        let mut f = pb.f.clone();
        f[1] *= 2.0;
        assert!(err(ContactQp {
            compliance: &f,
            ..pb.qp()
        })
        .contains("not symmetric"));
        let mut f = pb.f.clone();
        f[5] = -1e-6;
        assert!(err(ContactQp {
            compliance: &f,
            ..pb.qp()
        })
        .contains("diagonal"));
        let mut f = pb.f.clone();
        f[7] = f64::NAN;
        assert!(err(ContactQp {
            compliance: &f,
            ..pb.qp()
        })
        .contains("compliance entry (1, 3)"));
        // iteration limits are errors naming the limit
        let big = random_problem(50, 7, false);
        for solver in QpSolver::ALL {
            let opts = QpOptions {
                solver,
                max_iterations: 2,
                ..QpOptions::default()
            };
            let e = solve_contact_qp(&big.qp(), &opts).unwrap_err().to_string();
            assert!(e.contains("iteration limit 2"), "{e}");
        }
        assert!("simplex".parse::<QpSolver>().is_err());
        assert_eq!("clarabel".parse::<QpSolver>().unwrap(), QpSolver::Clarabel);
        assert_eq!(
            "active-set".parse::<QpSolver>().unwrap(),
            QpSolver::ActiveSet
        );
        assert_eq!(
            serde_json::to_string(&QpSolver::ActiveSet).unwrap(),
            "\"active-set\""
        );
        // the public residual on wrong lengths is NaN (never within tolerance)
        assert!(kkt(&pb.qp(), &[1.0], 0.0).max.is_nan());
        assert!(kkt(&pb.qp(), &[1.0, f64::NAN, 0.0, 0.0], 0.0).max.is_nan());
        assert!(kkt(&pb.qp(), &[1.0; 4], f64::INFINITY).max.is_nan());
    }

    #[test]
    fn condition_numbers() {
        assert!((condition_number(&[1.0, 0.0, 0.0, 4.0], 2) - 4.0).abs() < 1e-12);
        assert_eq!(condition_number(&[1.0, 1.0, 1.0, 1.0], 2), f64::INFINITY);
        assert!(condition_number(&[1.0], 2).is_nan());
    }
}
