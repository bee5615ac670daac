//! The compliance matrix C = Eᵀ K⁻¹ E on the flank DOFs from one sparse
//! Cholesky factorization: Schur complement (default) or blocked
//! multi-right-hand-side solves. Formulas and sources: [`crate::compliance`].

use std::time::Instant;

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt;
use faer::{MatMut, MatRef, Par};
use nalgebra::{DMatrix, SymmetricEigen};
use rayon::prelude::*;

use crate::compliance::FlankNodes;
use crate::error::FlankError;
use crate::fem::assembly::Assembly;
use crate::fem::constraints::{DofMap, DofTarget};
use crate::fem::model::Model;
use crate::fem::ordering::OrderingMethod;
use crate::fem::solver::{parallelism, Precision, SparseCholesky};
use crate::fem::static_analysis::{check_rigid_body_modes, peak_memory_mb, validate};
use crate::settings::Method;

/// Options of [`compute_compliance`].
#[derive(Clone, Debug)]
pub struct ComplianceOptions {
    pub method: Method,
    /// Threads (0 = rayon's global pool).
    pub threads: usize,
    /// Fill-reducing ordering (of the non-flank DOFs for the Schur method).
    pub ordering: OrderingMethod,
    /// Memory for the right-hand-side blocks of the blocked method (MB),
    /// shared by the blocks solved at once.
    pub memory_budget_mb: f64,
    /// Right-hand sides per block (0: from the memory budget, at most 256).
    pub block_size: usize,
    /// Estimate the condition number κ(C) = λ_max/λ_min (Lanczos).
    pub condition: bool,
}

impl Default for ComplianceOptions {
    fn default() -> Self {
        ComplianceOptions {
            method: Method::Schur,
            threads: 0,
            ordering: OrderingMethod::Metis,
            memory_budget_mb: 1024.0,
            block_size: 0,
            condition: true,
        }
    }
}

/// Extreme eigenvalues of C (mm/N) and their ratio, by Lanczos iterations
/// (full reorthogonalization) on C and on C⁻¹ (through the factor of
/// C⁻¹ = S in the Schur method, through a dense Cholesky factor of C in the
/// blocked method). Ritz values bound the spectrum from inside, so κ is a
/// lower bound that is tight once the iterations converged.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize, PartialEq)]
pub struct ConditionEstimate {
    pub lambda_min: f64,
    pub lambda_max: f64,
    pub kappa: f64,
    pub lanczos_steps: usize,
    pub seconds: f64,
}

/// Figures of one compliance computation (written to `summary.json`).
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct ComplianceStats {
    pub method: String,
    pub nodes: usize,
    pub elements: usize,
    /// Free DOFs of the body.
    pub dofs: usize,
    pub flank_nodes: usize,
    /// Right-hand sides: free flank DOFs (the order of the dense flank block).
    pub rhs: usize,
    pub threads: usize,
    pub ordering: String,
    pub nnz_factor: usize,
    pub factorization_gflop: f64,
    /// Ordering (inside symbolic assembly), s.
    pub ordering_s: f64,
    pub symbolic_assembly_s: f64,
    pub assembly_s: f64,
    pub symbolic_factorization_s: f64,
    pub factorization_s: f64,
    /// Blocked: all solves and the copy into C. Schur: trailing-block
    /// extraction and the dense inverse (L₂₂L₂₂ᵀ)⁻¹.
    pub solve_s: f64,
    /// Filling the upper triangle from the lower.
    pub symmetrize_s: f64,
    /// (factorization + solve + symmetrize) / factorization of this run.
    pub time_vs_factorization: f64,
    /// rhs / (factorization + solve + symmetrize): right-hand sides per
    /// second from one factorization.
    pub rhs_per_s: f64,
    /// Right-hand sides per block and blocks (blocked method).
    pub block_size: usize,
    pub blocks: usize,
    /// Size of the dense 3N × 3N matrix (MB).
    pub matrix_mb: f64,
    pub total_s: f64,
    pub peak_memory_mb: f64,
    /// The memory guard's estimate of the peak (MB): the resident set after
    /// the symbolic analysis plus the factor, its workspace and the dense
    /// blocks.
    pub estimated_peak_mb: f64,
    pub condition: Option<ConditionEstimate>,
    /// Backward error of a probe solve with the factor (unit loads on every
    /// free flank DOF; [`crate::fem::residual::backward_error`]).
    pub backward_error: f64,
}

/// Largest backward error of the probe solve accepted (the FE contact
/// path's limit for its final solve, `contact::solve`).
pub const MAX_BACKWARD_ERROR: f64 = 1e-10;

/// Computes C (3N × 3N, full symmetric, node-major x, y, z, mm/N) for the
/// flank nodes of `flank` (which must carry mesh indices) of `model`, whose
/// Dirichlet conditions and rigid couplings are the boundary conditions;
/// loads are ignored. A flank DOF fixed by a Dirichlet condition has a zero
/// row and column.
pub fn compute_compliance(
    model: &Model,
    flank: &FlankNodes,
    options: &ComplianceOptions,
) -> Result<(Vec<f64>, ComplianceStats), FlankError> {
    crate::fem::solver::with_threads(options.threads, || compute_in_pool(model, flank, options))
}

fn compute_in_pool(
    model: &Model,
    flank: &FlankNodes,
    options: &ComplianceOptions,
) -> Result<(Vec<f64>, ComplianceStats), FlankError> {
    let t_total = Instant::now();
    if !(options.memory_budget_mb > 0.0) {
        return Err(FlankError::Model(format!(
            "memory budget must be positive, got {} MB",
            options.memory_budget_mb
        )));
    }
    let m = 3 * flank.len();
    let matrix_mb = (m * m * 8) as f64 / 1e6;
    // dense storage: C, plus L₂₂ and the inverse's workspace (Schur) or the
    // right-hand-side blocks (blocked); checked with the factor's memory
    // once the symbolic analysis knows nnz(L)
    let dense_mb = match options.method {
        Method::Schur => 3.0 * matrix_mb,
        Method::Blocked => matrix_mb + options.memory_budget_mb,
    } * 1e6
        / 1048576.0;
    let FlankFactor {
        chol,
        n,
        red,
        mut stats,
        estimated_peak_mb,
        ..
    } = factor_flank(
        model,
        flank,
        options,
        &Beside {
            what: dense_what(flank.len(), m, options.method),
            mb: dense_mb,
            mb_per_dof: 0.0,
            mb_per_reach_row: 0.0,
            alternatives: DENSE_ALTERNATIVES,
        },
    )?;
    let par = parallelism(options.threads);
    let free: Vec<usize> = (0..m).filter(|&a| red[a].is_some()).collect();
    stats.matrix_mb = matrix_mb;
    let t = Instant::now();
    let (mut matrix, condition) = match options.method {
        Method::Schur => schur(&chol, &red, &free, m, par, options.condition)?,
        Method::Blocked => {
            let (c, bs, nb) = blocked(&chol, &red, m, n, options)?;
            stats.block_size = bs;
            stats.blocks = nb;
            (c, None)
        }
    };
    stats.solve_s = t.elapsed().as_secs_f64() - condition.as_ref().map_or(0.0, |c| c.seconds);
    let t = Instant::now();
    mirror_lower(&mut matrix, m);
    stats.symmetrize_s = t.elapsed().as_secs_f64();
    if let Some(i) = matrix.iter().position(|v| !v.is_finite()) {
        return Err(FlankError::Solver(format!(
            "compliance entry ({}, {}) is not finite",
            i / m,
            i % m
        )));
    }
    let work = stats.factorization_s + stats.solve_s + stats.symmetrize_s;
    stats.time_vs_factorization = work / stats.factorization_s.max(1e-12);
    stats.rhs_per_s = stats.rhs as f64 / work.max(1e-12);
    stats.condition = match (options.condition, condition) {
        (false, _) => None,
        (true, Some(c)) => Some(c),
        (true, None) => Some(condition_from_matrix(&matrix, m, &free, par)?),
    };
    stats.total_s = t_total.elapsed().as_secs_f64();
    stats.peak_memory_mb = peak_memory_mb();
    stats.estimated_peak_mb = estimated_peak_mb;
    Ok((matrix, stats))
}

/// What a compliance computation's memory check refuses, in words.
fn dense_what(nodes: usize, m: usize, method: Method) -> String {
    format!(
        "the compliance tensor of {nodes} flank nodes (a dense {m} × {m} matrix, {} method)",
        method.name()
    )
}

/// What a computation holds beside the body's factor once it is
/// factored: in words, its size (MiB) and what to do when it does not fit
/// (the memory guard's message, [`crate::resources::check_memory`]).
pub(crate) struct Beside {
    pub what: String,
    pub mb: f64,
    /// MiB per unknown of the factored system (full-length panels of
    /// solutions).
    pub mb_per_dof: f64,
    /// MiB per row of the flank DOFs' reach in the factor's elimination
    /// tree ([`SparseCholesky::reach`]: panels of restricted solves, which
    /// hold only those rows). Known after the symbolic analysis, so it
    /// enters the second check only; a factor without a reach (simplicial)
    /// counts every unknown.
    pub mb_per_reach_row: f64,
    pub alternatives: &'static str,
}

/// The body's sparse Cholesky factor for solves with unit loads on the
/// flank DOFs, checked by the backward error of a probe solve.
pub(crate) struct FlankFactor {
    pub chol: SparseCholesky,
    /// Unknowns of the factored system (reduced DOFs).
    pub n: usize,
    /// Reduced index of every flank DOF (node-major x, y, z; `None`: fixed,
    /// a zero row and column of C).
    pub red: Vec<Option<usize>>,
    /// Figures up to the factorization and the probe (rhs, nnz(L), times).
    pub stats: ComplianceStats,
    /// The memory guard's estimate of the peak (MB).
    pub estimated_peak_mb: f64,
    /// The part of it for what lives beside the factor (`beside`, MB): the
    /// rest is the resident set when it was made and the factor itself.
    pub beside_mb: f64,
}

/// Validates `model` and `flank`, assembles K and factors it (flank DOFs
/// ordered last for the Schur method, else one fill-reducing ordering of
/// all DOFs), refusing beforehand when the factor and `beside` would not
/// fit in memory; then the backward error of a probe solve (unit loads on
/// every free flank DOF) must be ≤ [`MAX_BACKWARD_ERROR`].
pub(crate) fn factor_flank(
    model: &Model,
    flank: &FlankNodes,
    options: &ComplianceOptions,
    beside: &Beside,
) -> Result<FlankFactor, FlankError> {
    flank.validate()?;
    if flank.is_empty() {
        return Err(FlankError::Model("no flank nodes".into()));
    }
    if flank.nodes.len() != flank.labels.len() {
        return Err(FlankError::Model(
            "flank nodes without mesh indices (read from a file?)".into(),
        ));
    }
    validate(model)?;
    let nn = model.mesh.node_count();
    for (&n, &l) in flank.nodes.iter().zip(&flank.labels) {
        if n >= nn || model.mesh.node_labels[n] != l {
            return Err(FlankError::Model(format!(
                "flank node {l} does not match the model's mesh"
            )));
        }
    }
    let mut dofs = DofMap::new(model)?;
    check_rigid_body_modes(model, &dofs)?;
    for &n in &flank.nodes {
        for c in 0..3 {
            match dofs.targets[3 * n + c] {
                DofTarget::Free(_) | DofTarget::Fixed(_) => {}
                DofTarget::Coupled { .. } => {
                    return Err(FlankError::Model(format!(
                        "flank node {} belongs to a rigid coupling or is the dependent DOF of an equation: not supported",
                        model.mesh.node_labels[n]
                    )))
                }
                DofTarget::Unused => {
                    return Err(FlankError::Model(format!(
                        "flank node {} belongs to no element",
                        model.mesh.node_labels[n]
                    )))
                }
            }
        }
    }
    let m = 3 * flank.len();
    // a first check on what lives beside the factor, before the assembly
    let beside_mb = beside.mb + beside.mb_per_dof * dofs.reduced_count as f64;
    crate::resources::check_memory(&beside.what, beside_mb, beside.alternatives)?;
    let par = parallelism(options.threads);
    let mut stats = ComplianceStats {
        method: options.method.name().to_string(),
        nodes: nn,
        elements: model.mesh.elements.len(),
        dofs: dofs.reduced_count,
        flank_nodes: flank.len(),
        threads: par.degree(),
        ..Default::default()
    };
    let t = Instant::now();
    let assembly = match options.method {
        Method::Schur => {
            Assembly::with_nodes_last(model, &mut dofs, options.ordering, &flank.nodes)?
        }
        Method::Blocked => Assembly::new(model, &mut dofs, options.ordering)?,
    };
    let dofs = dofs;
    stats.symbolic_assembly_s = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let system = assembly.assemble(model, &dofs)?;
    stats.assembly_s = t.elapsed().as_secs_f64();
    let (pattern, ordering_s) = (assembly.pattern, assembly.ordering_s);
    let mut chol = SparseCholesky::analyze(&pattern, options.ordering, ordering_s, par)?;
    // panels of restricted solves: their rows are the flank DOFs' reach
    let beside_mb = if beside.mb_per_reach_row > 0.0 {
        let free: Vec<usize> = flank
            .nodes
            .iter()
            .flat_map(|&n| (0..3).map(move |c| 3 * n + c))
            .filter_map(|d| match dofs.targets[d] {
                DofTarget::Free(r) => Some(r),
                _ => None,
            })
            .collect();
        let rows = chol.reach(&free).map_or(pattern.n, |r| r.rows());
        beside_mb + beside.mb_per_reach_row * rows as f64
    } else {
        beside_mb
    };
    // the factor and what lives beside it: refuse before the
    // factorization rather than after it
    crate::resources::check_memory(
        &format!(
            "{} with its factorization (nnz(L) = {:.3e})",
            beside.what, chol.stats.nnz_factor
        ),
        beside_mb + chol.factor_memory_mb(Precision::Double),
        beside.alternatives,
    )?;
    let estimated_peak_mb =
        crate::resources::resident_mb() + beside_mb + chol.factor_memory_mb(Precision::Double);
    let name_of = |r: usize| -> String {
        let d = dofs
            .targets
            .iter()
            .position(|t| *t == DofTarget::Free(r))
            .unwrap_or(0);
        format!(
            "node {} u{}",
            model.mesh.node_labels[d / 3],
            ["x", "y", "z"][d % 3]
        )
    };
    chol.factorize(&pattern, &system.values, Precision::Double, &name_of)?;
    // backward error of the factor on a probe: unit loads on every free
    // flank DOF at once (the right-hand sides the tensor is made of)
    let mut probe = vec![0.0; pattern.n];
    for n in &flank.nodes {
        for c in 0..3 {
            if let DofTarget::Free(r) = dofs.targets[3 * n + c] {
                probe[r] = 1.0;
            }
        }
    }
    let mut x = probe.clone();
    chol.solve_in_place(&mut x);
    let (_, backward_error) =
        crate::fem::residual::backward_error(&pattern, &system.values, &x, &probe);
    drop(system);
    stats.backward_error = backward_error;
    if !(backward_error <= MAX_BACKWARD_ERROR) {
        return Err(FlankError::Solver(format!(
            "compliance tensor: backward error {backward_error:.2e} of a probe solve (limit {MAX_BACKWARD_ERROR:.0e}): the factorization of the body's stiffness is not trustworthy"
        )));
    }
    let fs = chol.stats.clone();
    stats.ordering = fs.ordering.clone();
    stats.nnz_factor = fs.nnz_factor;
    stats.factorization_gflop = fs.flops * 1e-9;
    stats.ordering_s = fs.ordering_s;
    stats.symbolic_factorization_s = fs.symbolic_s;
    stats.factorization_s = fs.factorization_s;
    // reduced index of every output DOF (None: fixed, zero row/column)
    let red: Vec<Option<usize>> = (0..m)
        .map(|a| match dofs.targets[3 * flank.nodes[a / 3] + a % 3] {
            DofTarget::Free(r) => Some(r),
            _ => None,
        })
        .collect();
    stats.rhs = red.iter().filter(|r| r.is_some()).count();
    if stats.rhs == 0 {
        return Err(FlankError::Model(
            "every flank DOF is fixed: the compliance is zero".into(),
        ));
    }
    Ok(FlankFactor {
        chol,
        n: pattern.n,
        red,
        stats,
        estimated_peak_mb,
        beside_mb,
    })
}

/// The memory guard's alternatives for a compliance tensor.
const DENSE_ALTERNATIVES: &str = "use a coarser flank mesh (a larger --flank-size: the dense \
matrix grows with the fourth power of 1/size), fewer flank sets or teeth in the sector, the \
blocked method with a smaller --memory-budget-mb, or run where more memory is free";

/// Schur complement: C_free = (L₂₂L₂₂ᵀ)⁻¹, lower triangle, column-major.
fn schur(
    chol: &SparseCholesky,
    red: &[Option<usize>],
    free: &[usize],
    m: usize,
    par: Par,
    condition: bool,
) -> Result<(Vec<f64>, Option<ConditionEstimate>), FlankError> {
    let n = chol.stats.n;
    let mf = free.len();
    for (k, &a) in free.iter().enumerate() {
        if red[a] != Some(n - mf + k) {
            return Err(FlankError::Solver(
                "flank DOFs are not the last unknowns of the factor (ordering)".into(),
            ));
        }
    }
    let l22 = chol.trailing_factor(mf)?;
    let mut inv = vec![0.0; mf * mf];
    {
        let out = MatMut::from_column_major_slice_mut(&mut inv, mf, mf);
        let mut mem =
            MemBuffer::try_new(llt::inverse::inverse_scratch::<f64>(mf, par)).map_err(|_| {
                FlankError::Solver(format!("out of memory for the {mf} × {mf} inverse"))
            })?;
        llt::inverse::inverse(out, l22.as_ref(), par, MemStack::new(&mut mem));
    }
    let estimate = if condition {
        let t = Instant::now();
        // λ_max(S) with S x = L₂₂(L₂₂ᵀx); λ_min(C) = 1/λ_max(S)
        let (s_max, k1) = lanczos_max(mf, |x| {
            let xc = faer::ColRef::from_slice(x);
            let y = l22.as_ref().transpose() * xc;
            let z = l22.as_ref() * &y;
            z.iter().copied().collect()
        });
        let c_sym = SymLower {
            a: &inv,
            m: mf,
            par,
        };
        let (c_max, k2) = lanczos_max(mf, |x| c_sym.apply(x));
        Some(ConditionEstimate {
            lambda_min: 1.0 / s_max,
            lambda_max: c_max,
            kappa: c_max * s_max,
            lanczos_steps: k1.max(k2),
            seconds: t.elapsed().as_secs_f64(),
        })
    } else {
        None
    };
    drop(l22);
    if mf == m {
        return Ok((inv, estimate));
    }
    let mut c = vec![0.0; m * m];
    for (kj, &a) in free.iter().enumerate() {
        for (ki, &b) in free.iter().enumerate().skip(kj) {
            c[a * m + b] = inv[kj * mf + ki];
        }
    }
    Ok((c, estimate))
}

/// Blocked unit right-hand sides; returns C (lower triangle, column-major),
/// the block size and the block count.
fn blocked(
    chol: &SparseCholesky,
    red: &[Option<usize>],
    m: usize,
    n: usize,
    options: &ComplianceOptions,
) -> Result<(Vec<f64>, usize, usize), FlankError> {
    let threads = rayon::current_num_threads().max(1);
    let b = if options.block_size > 0 {
        options.block_size
    } else {
        // a block holds n × b doubles; the supernodal solve needs about as much scratch
        let per_column = 2.0 * 8.0 * n as f64;
        ((options.memory_budget_mb * 1e6 / threads as f64 / per_column) as usize).clamp(1, 256)
    }
    .min(m);
    let mut c = vec![0.0; m * m];
    let blocks = m.div_ceil(b);
    c.par_chunks_mut(b * m)
        .enumerate()
        .for_each(|(blk, chunk)| {
            let c0 = blk * b;
            let c1 = (c0 + b).min(m);
            let cols: Vec<(usize, usize)> =
                (c0..c1).filter_map(|a| red[a].map(|r| (a, r))).collect();
            if cols.is_empty() {
                return;
            }
            let mut x = faer::Mat::<f64>::zeros(n, cols.len());
            for (k, &(_, r)) in cols.iter().enumerate() {
                x[(r, k)] = 1.0;
            }
            chol.solve_columns_with(x.as_mut(), Par::Seq);
            for (k, &(a, _)) in cols.iter().enumerate() {
                let col = &mut chunk[(a - c0) * m..(a - c0 + 1) * m];
                let xk = x.col(k);
                for i in a..m {
                    col[i] = red[i].map_or(0.0, |r| xk[r]);
                }
            }
        });
    Ok((c, b, blocks))
}

/// Fills the upper triangle of a column-major m × m matrix from its lower
/// triangle (tiled transpose).
fn mirror_lower(a: &mut [f64], m: usize) {
    const T: usize = 64;
    for j0 in (0..m).step_by(T) {
        for i0 in (j0..m).step_by(T) {
            for j in j0..(j0 + T).min(m) {
                for i in i0.max(j + 1)..(i0 + T).min(m) {
                    a[i * m + j] = a[j * m + i];
                }
            }
        }
    }
}

/// A symmetric matrix given by its lower triangle (column-major) as an operator.
struct SymLower<'a> {
    a: &'a [f64],
    m: usize,
    par: Par,
}

impl SymLower<'_> {
    fn apply(&self, x: &[f64]) -> Vec<f64> {
        let m = self.m;
        // y_i = Σ_{j ≤ i} a_ij x_j + Σ_{j > i} a_ji x_j, column by column in parallel chunks
        let parts = match self.par {
            Par::Seq => 1,
            _ => rayon::current_num_threads().max(1),
        };
        let chunk = m.div_ceil(parts).max(1);
        let partial: Vec<Vec<f64>> = (0..m)
            .step_by(chunk)
            .collect::<Vec<_>>()
            .into_par_iter()
            .map(|j0| {
                let mut y = vec![0.0; m];
                for j in j0..(j0 + chunk).min(m) {
                    let col = &self.a[j * m..(j + 1) * m];
                    let xj = x[j];
                    let mut dot = 0.0;
                    for i in j + 1..m {
                        y[i] += col[i] * xj;
                        dot += col[i] * x[i];
                    }
                    y[j] += col[j] * xj + dot;
                }
                y
            })
            .collect();
        let mut y = vec![0.0; m];
        for p in partial {
            for (a, b) in y.iter_mut().zip(p) {
                *a += b;
            }
        }
        y
    }
}

/// Largest eigenvalue of a symmetric positive semi-definite operator by
/// Lanczos with full reorthogonalization; returns (λ_max, steps).
fn lanczos_max(m: usize, apply: impl Fn(&[f64]) -> Vec<f64>) -> (f64, usize) {
    let steps = m.min(60);
    // deterministic start vector with all components non-zero
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut q: Vec<f64> = (0..m)
        .map(|_| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            0.5 + (state >> 11) as f64 / (1u64 << 53) as f64
        })
        .collect();
    let nrm = q.iter().map(|v| v * v).sum::<f64>().sqrt();
    q.iter_mut().for_each(|v| *v /= nrm);
    let mut basis: Vec<Vec<f64>> = vec![q];
    let mut alpha = Vec::new();
    let mut beta: Vec<f64> = Vec::new();
    let mut last = f64::NAN;
    for k in 0..steps {
        let mut w = apply(&basis[k]);
        let a: f64 = w.iter().zip(&basis[k]).map(|(x, y)| x * y).sum();
        alpha.push(a);
        // full reorthogonalization (twice is enough)
        for _ in 0..2 {
            for v in &basis {
                let d: f64 = w.iter().zip(v).map(|(x, y)| x * y).sum();
                w.iter_mut().zip(v).for_each(|(x, y)| *x -= d * y);
            }
        }
        let b = w.iter().map(|v| v * v).sum::<f64>().sqrt();
        let t = DMatrix::from_fn(k + 1, k + 1, |i, j| {
            if i == j {
                alpha[i]
            } else if i + 1 == j || j + 1 == i {
                beta[i.min(j)]
            } else {
                0.0
            }
        });
        let lmax = SymmetricEigen::new(t)
            .eigenvalues
            .iter()
            .fold(f64::NEG_INFINITY, |a, &b| a.max(b));
        let converged = (lmax - last).abs() <= 1e-10 * lmax.abs();
        last = lmax;
        if converged || b <= 1e-14 * lmax.abs() || k + 1 == steps {
            return (lmax, k + 1);
        }
        beta.push(b);
        basis.push(w.into_iter().map(|v| v / b).collect());
    }
    (last, steps)
}

/// κ(C) on the free DOFs from a dense Cholesky factor of C (blocked method).
fn condition_from_matrix(
    c: &[f64],
    m: usize,
    free: &[usize],
    par: Par,
) -> Result<ConditionEstimate, FlankError> {
    let t = Instant::now();
    let mf = free.len();
    let mut l = faer::Mat::<f64>::from_fn(mf, mf, |i, j| {
        if i >= j {
            c[free[j] * m + free[i]]
        } else {
            0.0
        }
    });
    let mut mem = MemBuffer::try_new(llt::factor::cholesky_in_place_scratch::<f64>(
        mf,
        par,
        Default::default(),
    ))
    .map_err(|_| FlankError::Solver("out of memory for the dense Cholesky of C".into()))?;
    llt::factor::cholesky_in_place(
        l.as_mut(),
        Default::default(),
        par,
        MemStack::new(&mut mem),
        Default::default(),
    )
    .map_err(|_| FlankError::Singular("the compliance matrix is not positive definite".into()))?;
    let lr: MatRef<'_, f64> = l.as_ref();
    let (inv_max, k1) = lanczos_max(mf, |x| {
        let mut y = faer::Mat::<f64>::from_fn(mf, 1, |i, _| x[i]);
        llt::solve::solve_in_place(
            lr,
            y.as_mut(),
            par,
            MemStack::new(&mut MemBuffer::new(
                llt::solve::solve_in_place_scratch::<f64>(mf, 1, par),
            )),
        );
        (0..mf).map(|i| y[(i, 0)]).collect()
    });
    let sub: Vec<f64> = if mf == m {
        Vec::new()
    } else {
        let mut s = vec![0.0; mf * mf];
        for (kj, &a) in free.iter().enumerate() {
            for (ki, &b) in free.iter().enumerate() {
                s[kj * mf + ki] = c[a * m + b];
            }
        }
        s
    };
    let op = SymLower {
        a: if mf == m { c } else { &sub },
        m: mf,
        par,
    };
    let (c_max, k2) = lanczos_max(mf, |x| op.apply(x));
    Ok(ConditionEstimate {
        lambda_min: 1.0 / inv_max,
        lambda_max: c_max,
        kappa: c_max * inv_max,
        lanczos_steps: k1.max(k2),
        seconds: t.elapsed().as_secs_f64(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::compliance::flank::tests::box_flank;
    use crate::fem::model::NodalForce;
    use crate::fem::static_analysis::{solve_static, SolveOptions};
    use crate::mesh::structured::BoxElement;

    fn rel(a: &[f64], b: &[f64]) -> f64 {
        let d: f64 = a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum();
        let n: f64 = b.iter().map(|y| y * y).sum();
        (d / n).sqrt()
    }

    /// The memory guard: under a lowered limit (this thread's, 1 MB below
    /// what the process already holds) the tensor is refused with the
    /// dense matrix's size, the figures and the alternatives, for both
    /// methods, before anything is assembled.
    #[test]
    fn refused_under_a_lowered_memory_limit() {
        let (model, flank) = box_flank(BoxElement::Hex20);
        let limit = crate::resources::resident_mb() - 1.0;
        for method in [Method::Schur, Method::Blocked] {
            let opts = ComplianceOptions {
                method,
                threads: 0,
                ..Default::default()
            };
            let e = crate::resources::with_memory_limit_mb(limit, || {
                compute_compliance(&model, &flank, &opts)
            })
            .unwrap_err();
            let m = e.to_string();
            assert!(matches!(e, FlankError::Memory(_)), "{m}");
            let dim = 3 * flank.len();
            assert!(m.contains(&format!("{dim} × {dim}")), "{m}");
            assert!(
                m.contains("needs about") && m.contains("--flank-size"),
                "{m}"
            );
        }
        // without the limit the same tensor is computed
        compute_compliance(&model, &flank, &ComplianceOptions::default()).unwrap();
    }

    #[test]
    fn schur_and_blocked_agree_with_direct_solves() {
        for kind in [BoxElement::Hex20, BoxElement::Wedge15] {
            let (model, flank) = box_flank(kind);
            let m = 3 * flank.len();
            let (cs, ss) =
                compute_compliance(&model, &flank, &ComplianceOptions::default()).unwrap();
            let opts = ComplianceOptions {
                method: Method::Blocked,
                block_size: 7,
                threads: 2,
                ..Default::default()
            };
            let (cb, sb) = compute_compliance(&model, &flank, &opts).unwrap();
            assert_eq!(sb.blocks, m.div_ceil(7));
            // the probe solve of both methods is backward stable
            for st in [&ss, &sb] {
                assert!(
                    st.backward_error > 0.0 && st.backward_error < 1e-14,
                    "{kind:?}: probe backward error {}",
                    st.backward_error
                );
            }
            assert!(
                rel(&cs, &cb) < 1e-12,
                "{kind:?}: schur vs blocked {}",
                rel(&cs, &cb)
            );
            // exact symmetry
            for i in 0..m {
                for j in 0..m {
                    assert_eq!(cs[i * m + j], cs[j * m + i]);
                    assert_eq!(cb[i * m + j], cb[j * m + i]);
                }
            }
            // columns against direct solves (the nodes at x = 0 are clamped: zero columns)
            let free: Vec<usize> = (0..m)
                .filter(|&a| flank.positions[a / 3][0] > 0.0)
                .collect();
            assert!(free.iter().all(|&a| cs[a * m + a] > 0.0));
            assert!((0..m)
                .filter(|a| !free.contains(a))
                .all(|a| cs[a * m + a] == 0.0));
            for a in [free[0], free[4], free[free.len() / 2], free[free.len() - 1]] {
                let mut mm = model.clone();
                mm.forces = vec![NodalForce {
                    node: flank.nodes[a / 3],
                    component: a % 3,
                    value: 1.0,
                }];
                let sol = solve_static(
                    &mm,
                    &SolveOptions {
                        recover_stress: false,
                        ..Default::default()
                    },
                )
                .unwrap();
                let direct: Vec<f64> = (0..m)
                    .map(|i| sol.displacement[3 * flank.nodes[i / 3] + i % 3])
                    .collect();
                let col: Vec<f64> = (0..m).map(|i| cs[i * m + a]).collect();
                assert!(
                    rel(&col, &direct) < 1e-10,
                    "{kind:?} column {a}: {}",
                    rel(&col, &direct)
                );
            }
            // condition estimates of both paths agree
            let (k1, k2) = (ss.condition.unwrap(), sb.condition.unwrap());
            assert!(k1.lambda_min > 0.0 && k1.kappa > 1.0);
            assert!((k1.kappa / k2.kappa - 1.0).abs() < 1e-6, "{k1:?} {k2:?}");
        }
    }

    #[test]
    fn fixed_flank_dofs_give_zero_rows() {
        let (mut model, flank) = box_flank(BoxElement::Hex20);
        // clamp one flank node in y only
        let n0 = flank.nodes[3];
        model.dirichlet.push(crate::fem::model::Dirichlet {
            node: n0,
            component: 1,
            value: 0.0,
        });
        let m = 3 * flank.len();
        let (cs, ss) = compute_compliance(&model, &flank, &ComplianceOptions::default()).unwrap();
        let (cb, _) = compute_compliance(
            &model,
            &flank,
            &ComplianceOptions {
                method: Method::Blocked,
                ..Default::default()
            },
        )
        .unwrap();
        let clamped = flank.positions.iter().filter(|x| x[0] == 0.0).count();
        assert_eq!(ss.rhs, m - 3 * clamped - 1);
        let a = 3 * 3 + 1;
        assert!((0..m).all(|i| cs[i * m + a] == 0.0 && cs[a * m + i] == 0.0));
        assert!(rel(&cs, &cb) < 1e-12);
    }

    #[test]
    fn unconstrained_body_is_an_error() {
        let (mut model, flank) = box_flank(BoxElement::Hex20);
        model.dirichlet.clear();
        let e = compute_compliance(&model, &flank, &ComplianceOptions::default()).unwrap_err();
        assert!(e.to_string().contains("rigid-body"), "{e}");
    }

    #[test]
    fn mirror_fills_upper() {
        let m = 130;
        let mut a = vec![0.0; m * m];
        for j in 0..m {
            for i in j..m {
                a[j * m + i] = (i * 1000 + j) as f64;
            }
        }
        mirror_lower(&mut a, m);
        for i in 0..m {
            for j in 0..m {
                assert_eq!(a[j * m + i], a[i * m + j]);
            }
        }
    }
}
