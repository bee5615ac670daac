//! Coulomb friction (stick and slip) on the condensed contact problem.
//!
//! Every candidate slave node i has three constraint rows: the normal gap
//! (row 3i) and the tangential relative displacements along the two master
//! tangents t₁, t₂ (rows 3i+1, 3i+2; [`crate::contact::pairing`]). Small
//! displacements, small sliding, one static step in total displacements:
//! the slip is the total tangential displacement of the slave node against
//! its master point. With λ = (λₙ, λₜ) per node, W = B K₀⁻¹ Bᵀ over all 3n
//! rows, q the gaps and slips under the external loads, C the penalty
//! compliances (normal 1/(kₙA); tangential 1/(kₜA) with the stick slope kₜ,
//! 0 for hard stick), D the floating modes' rows and r their loads,
//!
//! ```text
//!   g = q + (W + C)λ + Dα   (gₙ: normal gap + penalty term; gₜ: slip + λₜ/(kₜA))
//!   λₙ ≥ 0, gₙ ≥ 0, λₙgₙ = 0                         (normal contact)
//!   ‖λₜ‖ ≤ μλₙ;  ‖λₜ‖ < μλₙ ⇒ gₜ = 0 (stick);
//!                ‖λₜ‖ = μλₙ ⇒ gₜ = −ν λₜ, ν ≥ 0 (slip against the force)
//!   Dᵀλ = r                                            (floating bodies)
//! ```
//!
//! With elastic stick (kₜ given) the stick state is λₜ = −kₜA·slip, the
//! slip state the same with the friction force at its bound μλₙ.
//!
//! **Method** (fixed point on the slip bound, the classical reduction of
//! Coulomb friction to a sequence of Tresca problems: Panagiotopoulos,
//! *Inequality Problems in Mechanics and Applications*, 1985; Haslinger,
//! Dostál & Kučera, Comput. Methods Appl. Mech. Engrg. 2002): for given
//! bounds sᵢ the Tresca problem
//!
//! ```text
//!   min ½λᵀ(W + C)λ + qᵀλ   s.t.  λₙ ≥ 0,  ‖λₜ,ᵢ‖ ≤ sᵢ,  Dᵀλ = r
//! ```
//!
//! is a strictly convex second-order-cone program (its KKT conditions are
//! the law above with μλₙ replaced by sᵢ, α being the equality's
//! multiplier); clarabel solves it (non-negative, second-order and zero
//! cones; scaled to O(1) entries). Then sᵢ ← μλₙ,ᵢ, until the largest
//! change of the bounds is below `tolerance` × the largest bound, or the
//! iteration limit (reported, not an error); once the change is below
//! [`POLISH_TRIGGER`] the polish below is tried, and when it settles on an
//! exact Coulomb answer the iteration stops there. The start is the frictionless
//! solution from the active set ([`crate::contact::active_set`]) when it
//! exists (sᵢ = μλₙ,ᵢ of frictionless contact), else unbounded friction
//! (full stick) for the first iterate.
//!
//! **Polish.** clarabel's interior-point answer is accurate to its
//! tolerances (~1e-10 relative), not to round-off. Its states (open,
//! stick, slip with the direction of λₜ) start a primal–dual active-set
//! iteration on the Coulomb law itself: per closed node the normal row
//! gₙ = 0, per sticking node gₜ = 0, per slipping node λₜ = μλₙe with a
//! fixed direction e; one dense linear solve (with the equilibrium rows
//! Dᵀλ = r); then states and directions (e = −gₜ/‖gₜ‖) are updated, until
//! nothing changes. If it settles with every inequality satisfied its
//! answer replaces clarabel's (the `polished` flag); otherwise clarabel's
//! answer stands.
//!
//! **Working set.** Columns of W cost a stiffness solve each, three per
//! node, so the frictional problem is solved on the nodes that are closed
//! in the frictionless solution plus the open ones nearest to closing (as
//! many as half the closed ones, and four more); afterwards the normal gaps
//! of all candidates are checked, nodes outside the set that penetrate
//! are added, and the problem is solved again. Without a frictionless
//! solution (a body whose sliding only friction holds) the set is all
//! candidates.
//!
//! **No equilibrium.** A tangential load larger than what the friction
//! cones can carry (e.g. Q > μP on a body held only by contact) makes a
//! Tresca problem infeasible: clarabel reports it and the solve stops with
//! an error saying so.

use nalgebra::{DMatrix, DVector};

use crate::contact::active_set::{
    solve_active_set, ActiveSetOptions, ActiveSetSolution, Condensed, Delassus,
};
use crate::error::FlankError;

/// The frictional condensed problem (row layout in the module doc).
#[derive(Clone, Debug, Default)]
pub struct FrictionProblem {
    /// Normal part: gaps q, penalty compliances, floating-mode normal rows
    /// d and loads r (as for frictionless contact).
    pub normal: Condensed,
    /// Tangential slips (along t₁, t₂) under the external loads.
    pub qt: Vec<[f64; 2]>,
    /// Floating modes' tangential slips (one vector of n per mode).
    pub dt: Vec<Vec<[f64; 2]>>,
    /// Friction coefficient per candidate (0: no tangential force there).
    pub mu: Vec<f64>,
    /// 1/(kₜ A) per candidate; 0 for hard stick.
    pub stick_compliance: Vec<f64>,
    /// Tangential rows (index 3i+1, 3i+2) that no free DOF and no floating
    /// mode moves (e.g. a tangent along a symmetry plane's held direction):
    /// their W row and column vanish and their force is set to 0. Length
    /// 3n or empty (none).
    pub inert: Vec<bool>,
}

/// Options of the friction solve.
#[derive(Clone, Debug)]
pub struct FrictionOptions {
    /// Fixed-point iteration limit (Tresca problems per working set).
    pub max_iterations: usize,
    /// Convergence: largest change of the slip bounds ≤ tolerance × the
    /// largest bound.
    pub tolerance: f64,
    /// Options of the frictionless start (gap tolerance, iteration limit).
    pub active_set: ActiveSetOptions,
    /// Limit on the working-set enlargements.
    pub max_rounds: usize,
}

impl Default for FrictionOptions {
    fn default() -> Self {
        FrictionOptions {
            max_iterations: 50,
            tolerance: 1e-9,
            active_set: ActiveSetOptions::default(),
            max_rounds: 10,
        }
    }
}

/// State of a slave node.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum FrictionStatus {
    Open,
    Stick,
    Slip,
}

impl FrictionStatus {
    pub fn name(self) -> &'static str {
        match self {
            FrictionStatus::Open => "open",
            FrictionStatus::Stick => "stick",
            FrictionStatus::Slip => "slip",
        }
    }
}

/// Answer of the frictional problem with its residuals.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct FrictionSolution {
    /// Normal forces λₙ (N).
    #[serde(skip)]
    pub lambda_n: Vec<f64>,
    /// Tangential forces on the slave nodes along (t₁, t₂) (N).
    #[serde(skip)]
    pub lambda_t: Vec<[f64; 2]>,
    /// Normal gaps (mm) without the penalty term.
    #[serde(skip)]
    pub gap: Vec<f64>,
    /// Total tangential relative displacement (slip) along (t₁, t₂) (mm).
    #[serde(skip)]
    pub slip: Vec<[f64; 2]>,
    #[serde(skip)]
    pub status: Vec<FrictionStatus>,
    /// Floating-mode amplitudes.
    pub alpha: Vec<f64>,
    /// Fixed-point iterations (Tresca problems solved), all rounds.
    pub iterations: usize,
    /// Whether the answer satisfies the Coulomb law: the fixed point met
    /// its tolerance or the polish settled on an exact answer (false: the
    /// iteration limit was hit and the polish failed; see the warnings).
    pub converged: bool,
    /// Last relative change of the slip bounds.
    pub bound_change: f64,
    /// Interior-point iterations of clarabel, all Tresca problems.
    pub clarabel_iterations: usize,
    /// Whether the primal–dual active-set polish replaced clarabel's answer.
    pub polished: bool,
    pub polish_iterations: usize,
    /// Working-set rounds and final size (nodes).
    pub rounds: usize,
    pub working_set: usize,
    /// Columns of W computed (stiffness solves).
    pub columns: usize,
    /// Whether the frictionless active set gave the start (false: it had
    /// no answer, e.g. a sliding mode only friction holds).
    pub frictionless_start: bool,
    pub closed: usize,
    pub stick: usize,
    pub slipping: usize,
    /// max over nodes of max(0, ‖λₜ‖ − μλₙ) (N): Coulomb cone violation.
    pub coulomb_residual: f64,
    /// max over closed nodes of (μλₙ − ‖λₜ‖)‖w‖ + (‖λₜ‖‖w‖ + λₜ·w) with
    /// w = gₜ + λₜ/(kₜA) the slip beyond the elastic stick (N·mm): zero when
    /// sticking nodes do not slip and slipping ones are at the bound with
    /// the force opposite to the slip.
    pub stick_slip_complementarity: f64,
    /// Normal law: max(0, −(gₙ + cλₙ)) (mm) and max |λₙ(gₙ + cλₙ)| (N·mm).
    pub max_violation: f64,
    pub complementarity: f64,
    /// ‖Dᵀλ − r‖/‖r‖ (floating bodies' equilibrium), 0 without them.
    pub equilibrium: f64,
    pub warnings: Vec<String>,
}

/// Relative change of the slip bounds below which the polish is tried
/// before the fixed point meets its tolerance.
pub const POLISH_TRIGGER: f64 = 1e-4;

/// Cached columns of the 3n-row Delassus matrix.
struct Columns<'a> {
    w: &'a mut dyn Delassus,
    cols: Vec<Option<Vec<f64>>>,
    /// Rows (tangential rows of μ = 0 nodes) whose columns are zero.
    zero: Vec<bool>,
    computed: usize,
}

impl Columns<'_> {
    fn fetch(&mut self, idx: &[usize]) -> Result<(), FlankError> {
        let rows = self.cols.len();
        let mut need: Vec<usize> = Vec::new();
        for &j in idx {
            if self.cols[j].is_some() {
                continue;
            }
            if self.zero[j] {
                self.cols[j] = Some(vec![0.0; rows]);
            } else if !need.contains(&j) {
                need.push(j);
            }
        }
        if need.is_empty() {
            return Ok(());
        }
        let got = self.w.columns(&need)?;
        for (j, c) in need.into_iter().zip(got) {
            if c.len() != rows || c.iter().any(|v| !v.is_finite()) {
                return Err(FlankError::Solver(format!(
                    "friction: column {j} of the Delassus matrix is invalid"
                )));
            }
            self.cols[j] = Some(c);
            self.computed += 1;
        }
        Ok(())
    }

    fn col(&self, j: usize) -> &[f64] {
        self.cols[j].as_deref().expect("fetched")
    }
}

/// The normal rows of the 3n-row Delassus matrix, for the frictionless
/// start (shares the column cache).
struct NormalView<'a, 'b> {
    cols: &'a mut Columns<'b>,
}

impl Delassus for NormalView<'_, '_> {
    fn columns(&mut self, cols: &[usize]) -> Result<Vec<Vec<f64>>, FlankError> {
        let idx: Vec<usize> = cols.iter().map(|&j| 3 * j).collect();
        self.cols.fetch(&idx)?;
        let n = self.cols.cols.len() / 3;
        Ok(idx
            .iter()
            .map(|&j| {
                let c = self.cols.col(j);
                (0..n).map(|i| c[3 * i]).collect()
            })
            .collect())
    }

    fn block_size(&self) -> usize {
        self.cols.w.block_size()
    }
}

/// Row `row` (0..3n) of the floating-mode matrix, mode `c`.
fn d_entry(prob: &FrictionProblem, c: usize, row: usize) -> f64 {
    let (i, a) = (row / 3, row % 3);
    if a == 0 {
        prob.normal.d[c][i]
    } else {
        prob.dt[c][i][a - 1]
    }
}

fn q_entry(prob: &FrictionProblem, row: usize) -> f64 {
    let (i, a) = (row / 3, row % 3);
    if a == 0 {
        prob.normal.q[i]
    } else {
        prob.qt[i][a - 1]
    }
}

/// Diagonal compliance of row `row`.
fn c_entry(prob: &FrictionProblem, row: usize) -> f64 {
    let (i, a) = (row / 3, row % 3);
    if a == 0 {
        prob.normal.compliance[i]
    } else {
        prob.stick_compliance[i]
    }
}

/// g = q + W[:, S]λ_S + Dα over all 3n rows (without the compliance term).
fn all_gaps(
    prob: &FrictionProblem,
    cols: &Columns,
    set: &[usize],
    lambda: &[f64],
    alpha: &[f64],
) -> Vec<f64> {
    let rows = 3 * prob.normal.q.len();
    let mut g: Vec<f64> = (0..rows).map(|r| q_entry(prob, r)).collect();
    for &i in set {
        for a in 0..3 {
            let j = 3 * i + a;
            if lambda[j] != 0.0 {
                let c = cols.col(j);
                for (gr, cr) in g.iter_mut().zip(c) {
                    *gr += cr * lambda[j];
                }
            }
        }
    }
    for (c, &al) in alpha.iter().enumerate() {
        if al != 0.0 {
            for (r, gr) in g.iter_mut().enumerate() {
                *gr += d_entry(prob, c, r) * al;
            }
        }
    }
    g
}

/// One Tresca problem on the working set `set` with slip bounds `bound`
/// (None: unbounded) by clarabel. Returns λ (3n, zero outside the set),
/// α and clarabel's iterations.
fn tresca(
    prob: &FrictionProblem,
    cols: &Columns,
    set: &[usize],
    bound: &[Option<f64>],
) -> Result<(Vec<f64>, Vec<f64>, usize), FlankError> {
    use clarabel::algebra::CscMatrix;
    use clarabel::solver::{
        DefaultSettings, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
    };
    let n = prob.normal.q.len();
    let m = prob.normal.d.len();
    let k = 3 * set.len();
    let var = |a: usize| 3 * set[a / 3] + a % 3;
    // scales: W by its largest diagonal, forces by the load scale
    let w0 = (0..k)
        .map(|a| cols.col(var(a))[var(a)] + c_entry(prob, var(a)))
        .fold(0.0f64, f64::max);
    if !(w0 > 0.0) {
        return Err(FlankError::Solver(
            "friction: the Delassus matrix of the working set has no positive diagonal".into(),
        ));
    }
    let qmax = (0..k).fold(0.0f64, |a, v| a.max(q_entry(prob, var(v)).abs()));
    let rmax = prob.normal.r.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let mut f0 = (qmax / w0).max(rmax);
    if !(f0 > 0.0) {
        f0 = 1.0;
    }
    // P: upper triangle of (W + C)/w0
    let mut colptr = vec![0usize];
    let mut rowval = Vec::new();
    let mut nzval = Vec::new();
    for b in 0..k {
        let cb = cols.col(var(b));
        for a in 0..=b {
            let ca = cols.col(var(a));
            let mut v = 0.5 * (cb[var(a)] + ca[var(b)]) / w0;
            if a == b {
                v += c_entry(prob, var(b)) / w0;
            }
            if v != 0.0 || a == b {
                rowval.push(a);
                nzval.push(v);
            }
        }
        colptr.push(rowval.len());
    }
    let pm = CscMatrix::new(k, k, colptr, rowval, nzval);
    let qv: Vec<f64> = (0..k).map(|a| q_entry(prob, var(a)) / (f0 * w0)).collect();
    // constraint rows: [zero: Dᵀ (m), zero tangents (2 per zero-bound
    // node)], [non-negative: −λₙ], [SOC 3 per bounded node]
    // tangential variables held at zero: μ = 0, inert, or a zero bound
    let fixed: Vec<usize> = (0..k)
        .filter(|&a| {
            a % 3 != 0 && (cols.zero[var(a)] || bound[set[a / 3]].is_some_and(|s| s <= 0.0))
        })
        .collect();
    let soc_nodes: Vec<usize> = (0..set.len())
        .filter(|&a| bound[set[a]].is_some_and(|s| s > 0.0))
        .collect();
    let nz = m + fixed.len();
    let rows = nz + set.len() + 3 * soc_nodes.len();
    let mut a_rows: Vec<Vec<(usize, f64)>> = vec![Vec::new(); k]; // per column: (row, value)
    let mut b = vec![0.0; rows];
    for c in 0..m {
        for (a, col) in a_rows.iter_mut().enumerate() {
            let v = d_entry(prob, c, var(a));
            if v != 0.0 {
                col.push((c, v));
            }
        }
        b[c] = prob.normal.r[c] / f0;
    }
    for (z, &a) in fixed.iter().enumerate() {
        a_rows[a].push((m + z, 1.0));
    }
    for a in 0..set.len() {
        a_rows[3 * a].push((nz + a, -1.0));
    }
    let base = nz + set.len();
    for (s, &a) in soc_nodes.iter().enumerate() {
        b[base + 3 * s] = bound[set[a]].unwrap_or(0.0) / f0;
        a_rows[3 * a + 1].push((base + 3 * s + 1, -1.0));
        a_rows[3 * a + 2].push((base + 3 * s + 2, -1.0));
    }
    let mut colptr = vec![0usize];
    let mut rowval = Vec::new();
    let mut nzval = Vec::new();
    for col in &mut a_rows {
        col.sort_by_key(|e| e.0);
        for &(r, v) in col.iter() {
            rowval.push(r);
            nzval.push(v);
        }
        colptr.push(rowval.len());
    }
    let am = CscMatrix::new(rows, k, colptr, rowval, nzval);
    let mut cones = Vec::new();
    if nz > 0 {
        cones.push(SupportedConeT::ZeroConeT(nz));
    }
    cones.push(SupportedConeT::NonnegativeConeT(set.len()));
    for _ in &soc_nodes {
        cones.push(SupportedConeT::SecondOrderConeT(3));
    }
    let settings = DefaultSettings {
        verbose: false,
        max_iter: 200,
        tol_gap_abs: 1e-11,
        tol_gap_rel: 1e-11,
        tol_feas: 1e-11,
        tol_ktratio: 1e-9,
        ..DefaultSettings::default()
    };
    let mut solver = DefaultSolver::new(&pm, &qv, &am, &b, &cones, settings)
        .map_err(|e| FlankError::Solver(format!("friction: clarabel setup: {e}")))?;
    solver.solve();
    let sol = &solver.solution;
    match sol.status {
        SolverStatus::Solved | SolverStatus::AlmostSolved | SolverStatus::InsufficientProgress => {}
        SolverStatus::PrimalInfeasible | SolverStatus::AlmostPrimalInfeasible => {
            return Err(FlankError::Solver(format!(
                "frictional contact has no static equilibrium: the loads on the floating bodies cannot be balanced by contact forces inside the friction cones ‖λt‖ ≤ μλn ({n} candidate slave nodes, {} in the working set); a tangential load larger than μ × the normal load on a body held only by contact cannot be carried (clarabel: {})",
                set.len(),
                sol.status
            )));
        }
        other => {
            return Err(FlankError::Solver(format!(
                "friction: clarabel status {other} after {} iterations on the Tresca problem of {} nodes",
                sol.iterations,
                set.len()
            )));
        }
    }
    if sol.x.len() != k || sol.x.iter().chain(&sol.z).any(|v| !v.is_finite()) {
        return Err(FlankError::Solver(format!(
            "friction: clarabel status {} but a non-finite or mis-sized answer",
            sol.status
        )));
    }
    let mut lambda = vec![0.0; 3 * n];
    for a in 0..k {
        lambda[var(a)] = sol.x[a] * f0;
    }
    for a in 0..set.len() {
        // the non-negative cone's interior: exact zeros for open nodes are
        // set by the polish; keep λₙ ≥ 0 here
        let j = 3 * set[a];
        lambda[j] = lambda[j].max(0.0);
    }
    let alpha: Vec<f64> = (0..m).map(|c| sol.z[c] * f0 * w0).collect();
    Ok((lambda, alpha, sol.iterations as usize))
}

/// Primal–dual active-set polish on the Coulomb law (module doc), from the
/// states of `lambda`. Returns (λ, α, iterations) if it settles with the
/// law satisfied.
fn polish(
    prob: &FrictionProblem,
    cols: &Columns,
    set: &[usize],
    lambda: &[f64],
    tol: f64,
) -> Option<(Vec<f64>, Vec<f64>, usize)> {
    let m = prob.normal.d.len();
    let nn = prob.normal.q.len();
    let lmax = set.iter().fold(0.0f64, |a, &i| a.max(lambda[3 * i]));
    if !(lmax > 0.0) {
        return None;
    }
    #[derive(Clone, Copy, PartialEq)]
    enum St {
        Open,
        Stick,
        Slip([f64; 2]),
    }
    let mut st: Vec<St> = set
        .iter()
        .map(|&i| {
            let ln = lambda[3 * i];
            let lt = [lambda[3 * i + 1], lambda[3 * i + 2]];
            let nt = lt[0].hypot(lt[1]);
            if ln <= 1e-7 * lmax {
                St::Open
            } else if prob.mu[i] == 0.0 {
                St::Slip([1.0, 0.0])
            } else if nt < (1.0 - 1e-6) * prob.mu[i] * ln {
                St::Stick
            } else {
                St::Slip([lt[0] / nt, lt[1] / nt])
            }
        })
        .collect();
    for it in 1..=30 {
        let closed: Vec<usize> = (0..set.len()).filter(|&a| st[a] != St::Open).collect();
        let k = 3 * closed.len();
        let size = k + m;
        let mut mat = DMatrix::<f64>::zeros(size, size);
        let mut rhs = DVector::<f64>::zeros(size);
        let var = |b: usize| 3 * set[closed[b / 3]] + b % 3;
        for a in 0..k {
            let row = var(a);
            let node = set[closed[a / 3]];
            let comp = a % 3;
            match (st[closed[a / 3]], comp) {
                _ if comp > 0 && cols.zero[row] => {
                    mat[(a, a)] = 1.0;
                }
                (St::Slip(e), 1 | 2) => {
                    mat[(a, a)] = 1.0;
                    mat[(a, a - comp)] = -prob.mu[node] * e[comp - 1];
                }
                _ => {
                    for b in 0..k {
                        mat[(a, b)] = cols.col(var(b))[row];
                    }
                    mat[(a, a)] += c_entry(prob, row);
                    for c in 0..m {
                        mat[(a, k + c)] = d_entry(prob, c, row);
                    }
                    rhs[a] = -q_entry(prob, row);
                }
            }
        }
        for c in 0..m {
            for b in 0..k {
                mat[(k + c, b)] = d_entry(prob, c, var(b));
            }
            rhs[k + c] = prob.normal.r[c];
        }
        let x = mat.lu().solve(&rhs)?;
        if x.iter().any(|v| !v.is_finite()) {
            return None;
        }
        let mut lam = vec![0.0; 3 * nn];
        for b in 0..k {
            lam[var(b)] = x[b];
        }
        let alpha: Vec<f64> = (0..m).map(|c| x[k + c]).collect();
        let g = all_gaps(prob, cols, set, &lam, &alpha);
        let lmax = set.iter().fold(0.0f64, |a, &i| a.max(lam[3 * i]));
        let mut changed = false;
        let mut turn = 0.0f64;
        for (a, &i) in set.iter().enumerate() {
            let ln = lam[3 * i];
            let lt = [lam[3 * i + 1], lam[3 * i + 2]];
            let nt = lt[0].hypot(lt[1]);
            let ct = prob.stick_compliance[i];
            let w = [g[3 * i + 1] + ct * lt[0], g[3 * i + 2] + ct * lt[1]];
            let nw = w[0].hypot(w[1]);
            let new = match st[a] {
                St::Open => {
                    if g[3 * i] < -tol {
                        St::Stick
                    } else {
                        St::Open
                    }
                }
                _ if ln < 0.0 => St::Open,
                St::Stick => {
                    if nt > prob.mu[i] * ln * (1.0 + 1e-12) + 1e-14 * lmax {
                        St::Slip([lt[0] / nt, lt[1] / nt])
                    } else {
                        St::Stick
                    }
                }
                St::Slip(e) => {
                    if prob.mu[i] == 0.0 {
                        St::Slip(e)
                    } else if w[0] * e[0] + w[1] * e[1] > tol {
                        St::Stick
                    } else if nw > 0.0 {
                        // slip across the force direction beyond the
                        // tolerance turns it; below it the direction stands
                        // (the slip of a node at the stick/slip transition
                        // is tiny and its direction mere round-off)
                        let along = w[0] * e[0] + w[1] * e[1];
                        let across = (w[0] - along * e[0]).hypot(w[1] - along * e[1]);
                        if across > tol {
                            let e2 = [-w[0] / nw, -w[1] / nw];
                            turn = turn.max((e2[0] - e[0]).hypot(e2[1] - e[1]));
                            St::Slip(e2)
                        } else {
                            St::Slip(e)
                        }
                    } else {
                        St::Slip(e)
                    }
                }
            };
            let kind = |s: St| match s {
                St::Open => 0,
                St::Stick => 1,
                St::Slip(_) => 2,
            };
            if kind(new) != kind(st[a]) {
                changed = true;
            }
            st[a] = new;
        }
        if std::env::var_os("FLANK_DEBUG_FRICTION").is_some() {
            let c = |f: &dyn Fn(&St) -> bool| st.iter().filter(|s| f(s)).count();
            eprintln!(
                "polish {it}: open {} stick {} slip {} changed {changed} turn {turn:.3e} min λn {:.3e}",
                c(&|s| *s == St::Open),
                c(&|s| *s == St::Stick),
                c(&|s| matches!(s, St::Slip(_))),
                set.iter().map(|&i| lam[3 * i]).fold(f64::INFINITY, f64::min)
            );
        }
        if !changed && turn <= 1e-13 {
            return Some((lam, alpha, it));
        }
    }
    None
}

/// Solves the frictional contact problem: `w` supplies columns of the
/// Delassus matrix over the 3n rows (normal, t₁, t₂ per candidate).
pub fn solve_friction(
    w: &mut dyn Delassus,
    prob: &FrictionProblem,
    options: &FrictionOptions,
) -> Result<(FrictionSolution, ActiveSetSolution), FlankError> {
    let n = prob.normal.q.len();
    let m = prob.normal.d.len();
    if prob.qt.len() != n
        || prob.mu.len() != n
        || prob.stick_compliance.len() != n
        || prob.dt.len() != m
        || prob.dt.iter().any(|d| d.len() != n)
        || prob.normal.compliance.len() != n
        || prob.normal.r.len() != m
        || prob.normal.d.iter().any(|d| d.len() != n)
    {
        return Err(FlankError::Solver(
            "frictional contact problem: inconsistent dimensions".into(),
        ));
    }
    if prob
        .qt
        .iter()
        .flatten()
        .chain(prob.dt.iter().flatten().flatten())
        .chain(&prob.mu)
        .chain(&prob.stick_compliance)
        .any(|v| !v.is_finite())
    {
        return Err(FlankError::Solver(
            "frictional contact problem: non-finite slip, coefficient or compliance".into(),
        ));
    }
    let tol = options.active_set.gap_tolerance;
    if !prob.inert.is_empty() && prob.inert.len() != 3 * n {
        return Err(FlankError::Solver(
            "frictional contact problem: inconsistent dimensions".into(),
        ));
    }
    let mut zero = vec![false; 3 * n];
    for i in 0..n {
        for a in 1..3 {
            zero[3 * i + a] = prob.mu[i] == 0.0 || prob.inert.get(3 * i + a) == Some(&true);
        }
    }
    let mut cols = Columns {
        w,
        cols: vec![None; 3 * n],
        zero,
        computed: 0,
    };
    let mut out = FrictionSolution::default();
    if n == 0 {
        if m > 0 {
            return Err(FlankError::Solver(
                "a floating body has no candidate contact node to hold it".into(),
            ));
        }
        out.converged = true;
        return Ok((out, ActiveSetSolution::default()));
    }
    // frictionless start
    let start = {
        let mut view = NormalView { cols: &mut cols };
        solve_active_set(&mut view, &prob.normal, &options.active_set)
    };
    let mut bound: Vec<Option<f64>> = vec![None; n];
    let mut in_set = vec![false; n];
    let mut start_iterations = 0;
    match &start {
        Ok(s) => {
            out.frictionless_start = true;
            start_iterations = s.iterations;
            let closed: Vec<usize> = (0..n).filter(|&i| s.lambda[i] > 0.0).collect();
            let mut open: Vec<usize> = (0..n).filter(|&i| s.lambda[i] <= 0.0).collect();
            open.sort_by(|&a, &b| s.gap[a].total_cmp(&s.gap[b]));
            open.truncate(closed.len() / 2 + 4);
            for &i in closed.iter().chain(&open) {
                in_set[i] = true;
            }
            for i in 0..n {
                bound[i] = Some(prob.mu[i] * s.lambda[i]);
            }
        }
        Err(e) => {
            out.warnings.push(format!(
                "frictionless contact has no answer here ({e}); the friction solve starts from full stick on all {n} candidates"
            ));
            in_set = vec![true; n];
        }
    }
    let mut lambda;
    let mut alpha;
    loop {
        out.rounds += 1;
        let set: Vec<usize> = (0..n).filter(|&i| in_set[i]).collect();
        let idx: Vec<usize> = set
            .iter()
            .flat_map(|&i| [3 * i, 3 * i + 1, 3 * i + 2])
            .collect();
        cols.fetch(&idx)?;
        let mut round_iterations = 0;
        let mut polished = None;
        let mut last_try = f64::INFINITY;
        loop {
            let (l, a, it) = tresca(prob, &cols, &set, &bound)?;
            out.iterations += 1;
            round_iterations += 1;
            out.clarabel_iterations += it;
            lambda = l;
            alpha = a;
            let smax = set
                .iter()
                .fold(0.0f64, |acc, &i| acc.max(prob.mu[i] * lambda[3 * i]));
            let mut change = 0.0f64;
            for &i in &set {
                let s = prob.mu[i] * lambda[3 * i];
                change = change.max(match bound[i] {
                    Some(b) => (s - b).abs(),
                    None => f64::INFINITY,
                });
                bound[i] = Some(s);
            }
            out.bound_change = if smax > 0.0 { change / smax } else { change };
            if out.bound_change <= options.tolerance {
                out.converged = true;
                break;
            }
            // near the fixed point: the polish may already settle on the
            // exact Coulomb answer (tried again after 100× progress)
            if out.bound_change <= POLISH_TRIGGER && out.bound_change <= 1e-2 * last_try {
                last_try = out.bound_change;
                polished = polish(prob, &cols, &set, &lambda, tol);
                if polished.is_some() {
                    out.converged = true;
                    break;
                }
            }
            if round_iterations >= options.max_iterations {
                out.converged = false;
                break;
            }
        }
        if polished.is_none() {
            polished = polish(prob, &cols, &set, &lambda, tol);
        }
        if let Some((l, a, it)) = polished {
            lambda = l;
            alpha = a;
            out.polished = true;
            out.polish_iterations += it;
            out.converged = true;
        } else {
            out.polished = false;
        }
        if !out.converged {
            out.warnings.push(format!(
                "friction fixed point stopped at its iteration limit ({}) with a relative change of the slip bounds {:.3e} (tolerance {:.1e}), and the polish found no exact Coulomb answer from its states: the answer is the last Tresca iterate",
                options.max_iterations, out.bound_change, options.tolerance
            ));
        }
        let g = all_gaps(prob, &cols, &set, &lambda, &alpha);
        let entering: Vec<usize> = (0..n).filter(|&i| !in_set[i] && g[3 * i] < -tol).collect();
        if entering.is_empty() {
            break;
        }
        if out.rounds >= options.max_rounds {
            let deepest = entering.iter().map(|&i| -g[3 * i]).fold(0.0f64, f64::max);
            return Err(FlankError::Solver(format!(
                "friction: {} candidate(s) outside the working set still penetrate after {} enlargements (the limit), the deepest by {deepest:.3e} mm",
                entering.len(),
                out.rounds
            )));
        }
        for i in entering {
            in_set[i] = true;
            bound[i] = Some(0.0);
        }
        out.converged = false;
    }
    // answer and residuals
    let set: Vec<usize> = (0..n).filter(|&i| in_set[i]).collect();
    let g = all_gaps(prob, &cols, &set, &lambda, &alpha);
    out.working_set = set.len();
    out.columns = cols.computed;
    out.lambda_n = (0..n).map(|i| lambda[3 * i]).collect();
    out.lambda_t = (0..n)
        .map(|i| [lambda[3 * i + 1], lambda[3 * i + 2]])
        .collect();
    out.gap = (0..n).map(|i| g[3 * i]).collect();
    out.slip = (0..n).map(|i| [g[3 * i + 1], g[3 * i + 2]]).collect();
    for i in 0..n {
        let ln = out.lambda_n[i];
        let lt = out.lambda_t[i];
        let nt = lt[0].hypot(lt[1]);
        let cap = prob.mu[i] * ln.max(0.0);
        out.coulomb_residual = out.coulomb_residual.max(nt - cap);
        let cn = prob.normal.compliance[i];
        out.max_violation = out.max_violation.max(-(out.gap[i] + cn * ln));
        out.complementarity = out.complementarity.max((ln * (out.gap[i] + cn * ln)).abs());
        let status = if ln <= 0.0 {
            FrictionStatus::Open
        } else if nt < cap * (1.0 - 1e-9) {
            FrictionStatus::Stick
        } else {
            FrictionStatus::Slip
        };
        if ln > 0.0 {
            let ct = prob.stick_compliance[i];
            let wv = [out.slip[i][0] + ct * lt[0], out.slip[i][1] + ct * lt[1]];
            let nw = wv[0].hypot(wv[1]);
            let c = (cap - nt).max(0.0) * nw + (nt * nw + lt[0] * wv[0] + lt[1] * wv[1]);
            out.stick_slip_complementarity = out.stick_slip_complementarity.max(c.abs());
        }
        match status {
            FrictionStatus::Open => {}
            FrictionStatus::Stick => out.stick += 1,
            FrictionStatus::Slip => out.slipping += 1,
        }
        out.closed += (ln > 0.0) as usize;
        out.status.push(status);
    }
    out.coulomb_residual = out.coulomb_residual.max(0.0);
    if m > 0 {
        let rnorm = prob.normal.r.iter().map(|v| v * v).sum::<f64>().sqrt();
        let mut e = 0.0;
        for c in 0..m {
            let s: f64 = (0..3 * n)
                .map(|r| d_entry(prob, c, r) * lambda[r])
                .sum::<f64>()
                - prob.normal.r[c];
            e += s * s;
        }
        out.equilibrium = if rnorm > 0.0 {
            e.sqrt() / rnorm
        } else {
            e.sqrt()
        };
    }
    out.alpha = alpha.clone();
    let normal = ActiveSetSolution {
        lambda: out.lambda_n.clone(),
        alpha,
        gap: out.gap.clone(),
        iterations: start_iterations,
        active: out.closed,
        columns: cols.computed,
        max_violation: out.max_violation,
        complementarity: out.complementarity,
        equilibrium: out.equilibrium,
        ..Default::default()
    };
    Ok((out, normal))
}
