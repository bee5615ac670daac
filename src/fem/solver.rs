//! Sparse Cholesky (LLᵀ) of the reduced stiffness with faer.
//!
//! The symbolic analysis (ordering, elimination tree, supernodes) is done once
//! per pattern and reused by every numeric factorization of a matrix with the
//! same pattern ([`SparseCholesky::factorize`]). Solves restricted to the
//! reach of a few DOFs in the elimination tree are in `solver/reach.rs`.

use std::time::Instant;

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::linalg::cholesky::supernodal::{SupernodalLltRef, SymbolicSupernodalCholesky};
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, LltRef, SymbolicCholesky,
    SymbolicCholeskyRaw, SymmetricOrdering,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};

use crate::error::FlankError;
use crate::fem::assembly::SparsePattern;
use crate::fem::ordering::OrderingMethod;

mod reach;
mod supernode_tree;
pub use reach::SolveReach;
use supernode_tree::SupernodeTree;

/// Arithmetic of the Cholesky factor.
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
#[serde(rename_all = "lowercase")]
pub enum Precision {
    /// f64 factor: the answer needs no refinement. Forced with
    /// `--precision double`; the FE contact system (many Delassus columns
    /// solved with one factor) and the compliance tensors (the Schur
    /// complement read off the factor's trailing block) factorize in double
    /// explicitly, since they use the factor itself, not one refined solve.
    Double,
    /// f32 factor, half the memory and about twice the speed (default of a
    /// static solve); the caller refines the solution against the f64 matrix
    /// (f32-preconditioned CG, to a backward error of f64 round-off) and
    /// falls back to `Double` if the f32 factor breaks down or the
    /// refinement does not converge.
    #[default]
    Mixed,
}

/// The factor's values in the chosen precision.
enum FactorValues {
    Double(Vec<f64>),
    Single(Vec<f32>),
}

/// A lower-triangular CSC matrix pattern, possibly a leading principal
/// block of a larger one read in place: column j's rows are
/// `row_idx[col_ptr[j]..col_ptr[j] + len]`, `len = col_nnz[j]` when given
/// (faer's non-compact columns), else up to `col_ptr[j + 1]`.
#[derive(Clone, Copy, Debug)]
pub struct LowerCsc<'a> {
    pub n: usize,
    pub col_ptr: &'a [usize],
    pub col_nnz: Option<&'a [usize]>,
    pub row_idx: &'a [usize],
}

impl<'a> LowerCsc<'a> {
    /// Slots of column `j`.
    #[inline]
    pub fn col_range(&self, j: usize) -> std::ops::Range<usize> {
        let a = self.col_ptr[j];
        match self.col_nnz {
            Some(len) => a..a + len[j],
            None => a..self.col_ptr[j + 1],
        }
    }

    /// Stored entries (lower triangle).
    pub fn nnz(&self) -> usize {
        match self.col_nnz {
            Some(len) => len.iter().sum(),
            None => self.col_ptr[self.n] - self.col_ptr[0],
        }
    }

    fn faer(&self) -> SymbolicSparseColMatRef<'a, usize> {
        SymbolicSparseColMatRef::new_checked(
            self.n,
            self.n,
            self.col_ptr,
            self.col_nnz,
            &self.row_idx[..self.col_ptr[self.n]],
        )
    }
}

impl SparsePattern {
    /// The whole pattern as a [`LowerCsc`].
    pub fn view(&self) -> LowerCsc<'_> {
        LowerCsc {
            n: self.n,
            col_ptr: &self.col_ptr,
            col_nnz: None,
            row_idx: &self.row_idx,
        }
    }
}

/// Values of the matrix to factorize, aligned with its [`LowerCsc`] slots.
pub(crate) enum MatrixValues<'a> {
    /// f64 values, factorized in the given precision (mixed: an f32 copy).
    F64(&'a [f64], Precision),
    /// f32 values already rounded: a single-precision factor.
    F32(&'a [f32]),
}

/// Figures of a factorization, for reports and benchmarks.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct FactorStats {
    pub n: usize,
    /// Non-zeros of the lower triangle of the matrix.
    pub nnz_matrix: usize,
    /// Non-zeros of the Cholesky factor L.
    pub nnz_factor: usize,
    /// Floating-point operations of the numeric factorization (Σ_j c_j², c_j = nnz of column j of L).
    pub flops: f64,
    pub ordering: String,
    pub precision: String,
    pub supernodal: bool,
    pub ordering_s: f64,
    pub symbolic_s: f64,
    pub factorization_s: f64,
    /// min_j L_jj² / A_jj: how close the matrix came to a zero pivot (1 = diagonal).
    pub min_pivot_ratio: f64,
    /// The memory guard's estimate of the numeric factorization's extra
    /// memory (MB: factor values, faer's workspace, a single-precision copy
    /// of the matrix) and the resident set when it was made (MB); their sum
    /// is the estimated peak of the factorization.
    pub factor_estimate_mb: f64,
    pub resident_before_mb: f64,
}

/// A symbolic analysis plus (after [`factorize`](Self::factorize)) the numeric factor.
pub struct SparseCholesky {
    symbolic: SymbolicCholesky<usize>,
    /// Elimination tree of the supernodes, built on the first
    /// [`reach`](Self::reach).
    tree: std::sync::OnceLock<Option<SupernodeTree>>,
    l_values: FactorValues,
    /// fwd[new] = old
    perm_fwd: Vec<usize>,
    factorized: bool,
    par: Par,
    pub stats: FactorStats,
}

/// Runs `f` in a rayon pool of `threads` threads, or in the current pool
/// when `threads` is 0 or already its size: the `--threads` option of the
/// solvers, which then use `Par::rayon` and rayon's iterators inside.
pub fn with_threads<T: Send>(
    threads: usize,
    f: impl FnOnce() -> Result<T, FlankError> + Send,
) -> Result<T, FlankError> {
    if threads > 0 && threads != rayon::current_num_threads() {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .map_err(|e| FlankError::Solver(format!("cannot start {threads} threads: {e}")))?;
        return pool.install(f);
    }
    f()
}

/// Threads to use: `0` = all of rayon's pool.
pub fn parallelism(threads: usize) -> Par {
    if threads == 1 {
        Par::Seq
    } else {
        Par::rayon(threads)
    }
}

impl SparseCholesky {
    /// Analyses the pattern (elimination tree, supernodes). The matrix must
    /// already be in elimination order (see [`crate::fem::assembly`]); the
    /// ordering's name and time are recorded in the statistics.
    pub fn analyze(
        pattern: &SparsePattern,
        ordering: OrderingMethod,
        ordering_s: f64,
        par: Par,
    ) -> Result<Self, FlankError> {
        Self::analyze_with(
            pattern,
            ordering,
            ordering_s,
            par,
            SupernodalThreshold::AUTO,
        )
    }

    /// [`analyze`](Self::analyze) with faer's choice between a simplicial
    /// and a supernodal factor given (tests force either).
    pub(crate) fn analyze_with(
        pattern: &SparsePattern,
        ordering: OrderingMethod,
        ordering_s: f64,
        par: Par,
        supernodal: SupernodalThreshold,
    ) -> Result<Self, FlankError> {
        Self::analyze_view(pattern.view(), ordering, ordering_s, par, supernodal)
    }

    /// [`analyze_with`](Self::analyze_with) of a [`LowerCsc`] (e.g. a
    /// leading principal block of the stiffness read in place).
    pub(crate) fn analyze_view(
        pattern: LowerCsc<'_>,
        ordering: OrderingMethod,
        ordering_s: f64,
        par: Par,
        supernodal: SupernodalThreshold,
    ) -> Result<Self, FlankError> {
        let n = pattern.n;
        if n == 0 {
            return Err(FlankError::Singular(
                "the system has no free degree of freedom".into(),
            ));
        }
        let t0 = Instant::now();
        // faer's symbolic analysis without a permutation reads the upper
        // triangle; give it the transposed pattern (temporarily), so that the
        // numeric factorization can then use the lower triangle in place.
        let (col_ptr_t, row_idx_t) = transpose_pattern(&pattern);
        let sym = SymbolicSparseColMatRef::new_checked(n, n, &col_ptr_t, None, &row_idx_t);
        let params = CholeskySymbolicParams {
            supernodal_flop_ratio_threshold: supernodal,
            ..Default::default()
        };
        let symbolic =
            factorize_symbolic_cholesky(sym, Side::Upper, SymmetricOrdering::Identity, params)
                .map_err(|e| FlankError::Solver(format!("symbolic factorization: {e:?}")))?;
        let (nnz_factor, flops, supernodal) = factor_counts(&symbolic);
        let stats = FactorStats {
            n,
            nnz_matrix: pattern.nnz(),
            nnz_factor,
            flops,
            ordering: ordering.name().to_string(),
            supernodal,
            ordering_s,
            symbolic_s: t0.elapsed().as_secs_f64(),
            ..Default::default()
        };
        Ok(SparseCholesky {
            l_values: FactorValues::Double(Vec::new()),
            symbolic,
            tree: std::sync::OnceLock::new(),
            perm_fwd: (0..n).collect(),
            factorized: false,
            par,
            stats,
        })
    }

    /// Extra memory (MB) the numeric factorization in `precision` will
    /// allocate: nnz(L) values, faer's workspace (from the symbolic
    /// analysis: the largest supernode's dense update blocks), and for the
    /// mixed precision the f32 copy of the matrix; known before any of it
    /// is allocated.
    pub fn factor_memory_mb(&self, precision: Precision) -> f64 {
        let (value, scratch) = match precision {
            Precision::Double => (
                8,
                self.symbolic
                    .factorize_numeric_llt_scratch::<f64>(self.par, Default::default()),
            ),
            Precision::Mixed => (
                4,
                self.symbolic
                    .factorize_numeric_llt_scratch::<f32>(self.par, Default::default()),
            ),
        };
        let copy = match precision {
            Precision::Double => 0,
            Precision::Mixed => 4 * self.stats.nnz_matrix,
        };
        (value * self.symbolic.len_val() + scratch.size_bytes() + copy) as f64 / 1048576.0
    }

    /// Numeric LLᵀ of the matrix with this pattern and lower-triangle `values`.
    /// `dof_name` names a reduced DOF in error messages. Refused with a
    /// [`FlankError::Memory`] before any allocation when the factor would
    /// not fit in the memory available ([`crate::resources::check_memory`]).
    pub fn factorize(
        &mut self,
        pattern: &SparsePattern,
        values: &[f64],
        precision: Precision,
        dof_name: &dyn Fn(usize) -> String,
    ) -> Result<(), FlankError> {
        let n = pattern.n;
        if let Some(k) = values.iter().position(|v| !v.is_finite()) {
            return Err(FlankError::Solver(format!(
                "stiffness entry {k} is not finite"
            )));
        }
        let need = self.factor_memory_mb(precision);
        self.stats.factor_estimate_mb = need;
        self.stats.resident_before_mb = crate::resources::resident_mb();
        crate::resources::check_memory(
            &format!(
                "the sparse Cholesky factorization ({} DOFs, nnz(L) = {:.3e}, {:?} precision)",
                n, self.stats.nnz_factor, precision
            ),
            need,
            crate::resources::ALTERNATIVES,
        )?;
        self.factorize_view(
            pattern.view(),
            MatrixValues::F64(values, precision),
            dof_name,
        )
    }

    /// The numeric factorization of [`factorize`](Self::factorize) without
    /// its checks of finiteness and memory (the caller's): `values` aligned
    /// with the slots of `a`, the matrix analysed.
    pub(crate) fn factorize_view(
        &mut self,
        a: LowerCsc<'_>,
        values: MatrixValues<'_>,
        dof_name: &dyn Fn(usize) -> String,
    ) -> Result<(), FlankError> {
        let n = a.n;
        let t0 = Instant::now();
        let sym = a.faer();
        self.factorized = false;
        let singular = |index: usize| {
            let old = self.perm_fwd.get(index).copied().unwrap_or(index);
            FlankError::Singular(format!(
                "the stiffness matrix is not positive definite: zero or negative pivot at {} \
                 (constraints missing, a mechanism, or an invalid material)",
                dof_name(old)
            ))
        };
        let end = a.col_ptr[n];
        let (l_values, precision) = match values {
            MatrixValues::F64(values, Precision::Double) => {
                let a64 = SparseColMatRef::new(sym, &values[..end]);
                (
                    FactorValues::Double(
                        numeric_llt(&self.symbolic, a64, self.par).map_err(singular)?,
                    ),
                    Precision::Double,
                )
            }
            MatrixValues::F64(values, Precision::Mixed) => {
                let v32: Vec<f32> = values[..end].iter().map(|&v| v as f32).collect();
                if v32.iter().any(|v| !v.is_finite()) {
                    return Err(FlankError::Solver(
                        "stiffness entries overflow single precision; use --precision double"
                            .into(),
                    ));
                }
                let a32 = SparseColMatRef::new(sym, &v32[..]);
                (
                    FactorValues::Single(
                        numeric_llt(&self.symbolic, a32, self.par).map_err(singular)?,
                    ),
                    Precision::Mixed,
                )
            }
            MatrixValues::F32(v32) => {
                let a32 = SparseColMatRef::new(sym, &v32[..end]);
                (
                    FactorValues::Single(
                        numeric_llt(&self.symbolic, a32, self.par).map_err(singular)?,
                    ),
                    Precision::Mixed,
                )
            }
        };
        self.l_values = l_values;
        self.stats.precision = format!("{precision:?}").to_lowercase();
        self.stats.factorization_s = t0.elapsed().as_secs_f64();
        // pivot ratio min_j L_jj² / A_jj (the diagonal is each column's first entry)
        let diag: Vec<f64> = (0..n)
            .map(|c| {
                let k = a.col_range(c).start;
                if a.row_idx.get(k) != Some(&c) {
                    return 0.0;
                }
                match values {
                    MatrixValues::F64(v, _) => v[k],
                    MatrixValues::F32(v) => v[k] as f64,
                }
            })
            .collect();
        let ldiag = self.factor_diagonal();
        let mut worst = (f64::INFINITY, 0usize);
        for (new, &l) in ldiag.iter().enumerate() {
            let old = self.perm_fwd[new];
            let r = l * l / diag[old];
            if r < worst.0 {
                worst = (r, old);
            }
        }
        self.stats.min_pivot_ratio = worst.0;
        if !(worst.0 > 1e-14) {
            return Err(FlankError::Singular(format!(
                "the stiffness matrix is numerically singular: pivot ratio {:.2e} at {} \
                 (an unconstrained rigid-body mode or mechanism)",
                worst.0,
                dof_name(worst.1)
            )));
        }
        self.factorized = true;
        Ok(())
    }

    #[inline]
    fn l_value(&self, k: usize) -> f64 {
        match &self.l_values {
            FactorValues::Double(v) => v[k],
            FactorValues::Single(v) => v[k] as f64,
        }
    }

    /// Diagonal of L in factor (permuted) order.
    fn factor_diagonal(&self) -> Vec<f64> {
        let n = self.stats.n;
        let mut d = vec![0.0; n];
        match self.symbolic.raw() {
            SymbolicCholeskyRaw::Supernodal(s) => {
                let (beg, end) = (s.supernode_begin(), s.supernode_end());
                let vptr = s.col_ptr_for_val();
                let rptr = s.col_ptr_for_row_idx();
                for k in 0..s.n_supernodes() {
                    let ncols = end[k] - beg[k];
                    let nrows = ncols + (rptr[k + 1] - rptr[k]);
                    for j in 0..ncols {
                        d[beg[k] + j] = self.l_value(vptr[k] + j * nrows + j);
                    }
                }
            }
            SymbolicCholeskyRaw::Simplicial(s) => {
                let cp = s.col_ptr();
                let ri = s.row_idx();
                for j in 0..n {
                    for k in cp[j]..cp[j + 1] {
                        if ri[k] == j {
                            d[j] = self.l_value(k);
                        }
                    }
                }
            }
        }
        d
    }

    /// Solves A x = b in place for every column of `rhs` (n × k). With a
    /// single-precision factor the solve is done in f32 (refine outside).
    pub fn solve_columns(&self, rhs: MatMut<'_, f64>) {
        self.solve_columns_with(rhs, self.par);
    }

    /// [`solve_columns`](Self::solve_columns) with the parallelism `par`
    /// (e.g. `Par::Seq` when several blocks are solved concurrently).
    pub fn solve_columns_with(&self, mut rhs: MatMut<'_, f64>, par: Par) {
        assert!(self.factorized, "solve before a successful factorization");
        let k = rhs.ncols();
        match &self.l_values {
            FactorValues::Double(l) => {
                let req = self.symbolic.solve_in_place_scratch::<f64>(k, par);
                let mut mem = MemBuffer::new(req);
                LltRef::new(&self.symbolic, l).solve_in_place_with_conj(
                    Conj::No,
                    rhs,
                    par,
                    MemStack::new(&mut mem),
                );
            }
            FactorValues::Single(l) => {
                let n = rhs.nrows();
                let mut r32 = faer::Mat::<f32>::from_fn(n, k, |i, j| rhs[(i, j)] as f32);
                let req = self.symbolic.solve_in_place_scratch::<f32>(k, par);
                let mut mem = MemBuffer::new(req);
                LltRef::new(&self.symbolic, l).solve_in_place_with_conj(
                    Conj::No,
                    r32.as_mut(),
                    par,
                    MemStack::new(&mut mem),
                );
                for j in 0..k {
                    for i in 0..n {
                        rhs[(i, j)] = r32[(i, j)] as f64;
                    }
                }
            }
        }
    }

    /// The precision of the current factor.
    pub fn precision(&self) -> Precision {
        match self.l_values {
            FactorValues::Double(_) => Precision::Double,
            FactorValues::Single(_) => Precision::Mixed,
        }
    }

    /// Solves A x = b in place for one right-hand side.
    pub fn solve_in_place(&self, rhs: &mut [f64]) {
        let n = rhs.len();
        let m = faer::MatMut::from_column_major_slice_mut(rhs, n, 1);
        self.solve_columns(m);
    }

    /// The forward substitution L y = b in place (factor order; in f32 with
    /// a single-precision factor). Supernodal factors only (see
    /// [`analyze_view`](Self::analyze_view)'s threshold).
    pub(crate) fn forward_in_place(&self, x: &mut [f64], par: Par) {
        self.substitute(x, par, true);
    }

    /// The backward substitution Lᵀ x = y in place, as
    /// [`forward_in_place`](Self::forward_in_place).
    pub(crate) fn backward_in_place(&self, x: &mut [f64], par: Par) {
        self.substitute(x, par, false);
    }

    fn substitute(&self, x: &mut [f64], par: Par, forward: bool) {
        assert!(self.factorized, "solve before a successful factorization");
        let SymbolicCholeskyRaw::Supernodal(s) = self.symbolic.raw() else {
            panic!("a partial substitution needs a supernodal factor");
        };
        fn run<T: faer::traits::ComplexField>(
            s: &SymbolicSupernodalCholesky<usize>,
            symbolic: &SymbolicCholesky<usize>,
            l: &[T],
            x: MatMut<'_, T>,
            par: Par,
            forward: bool,
        ) {
            let mut mem = MemBuffer::new(symbolic.solve_in_place_scratch::<T>(1, par));
            let stack = MemStack::new(&mut mem);
            let llt = SupernodalLltRef::new(s, l);
            if forward {
                llt.l_solve_with_conj(Conj::No, x, par, stack);
            } else {
                llt.l_transpose_solve_with_conj(Conj::No, x, par, stack);
            }
        }
        let n = x.len();
        match &self.l_values {
            FactorValues::Double(l) => {
                let m = MatMut::from_column_major_slice_mut(x, n, 1);
                run(s, &self.symbolic, l, m, par, forward);
            }
            FactorValues::Single(l) => {
                let mut x32: Vec<f32> = x.iter().map(|&v| v as f32).collect();
                let m = MatMut::from_column_major_slice_mut(&mut x32, n, 1);
                run(s, &self.symbolic, l, m, par, forward);
                for (a, b) in x.iter_mut().zip(&x32) {
                    *a = *b as f64;
                }
            }
        }
    }

    /// The trailing `m × m` block L₂₂ of the factor (factor order, lower
    /// triangle, dense): with the last `m` unknowns eliminated last, L₂₂L₂₂ᵀ
    /// is the Schur complement S = A₂₂ − A₂₁A₁₁⁻¹A₁₂ on them.
    pub fn trailing_factor(&self, m: usize) -> Result<faer::Mat<f64>, FlankError> {
        let n = self.stats.n;
        if !self.factorized {
            return Err(FlankError::Solver(
                "trailing factor block before a successful factorization".into(),
            ));
        }
        if m > n {
            return Err(FlankError::Solver(format!(
                "trailing factor block of {m} columns of a {n} × {n} factor"
            )));
        }
        if self.perm_fwd.iter().enumerate().any(|(i, &p)| i != p) {
            return Err(FlankError::Solver(
                "trailing factor block of a permuted factor".into(),
            ));
        }
        let s0 = n - m;
        let mut l = faer::Mat::<f64>::zeros(m, m);
        match self.symbolic.raw() {
            SymbolicCholeskyRaw::Supernodal(s) => {
                let (beg, end) = (s.supernode_begin(), s.supernode_end());
                let vptr = s.col_ptr_for_val();
                let rptr = s.col_ptr_for_row_idx();
                let ridx = s.row_idx();
                for k in 0..s.n_supernodes() {
                    if end[k] <= s0 {
                        continue;
                    }
                    let ncols = end[k] - beg[k];
                    let below = &ridx[rptr[k]..rptr[k + 1]];
                    let nrows = ncols + below.len();
                    for j in beg[k].max(s0)..end[k] {
                        let jl = j - beg[k];
                        let col = vptr[k] + jl * nrows;
                        for il in jl..ncols {
                            l[(beg[k] + il - s0, j - s0)] = self.l_value(col + il);
                        }
                        for (t, &r) in below.iter().enumerate() {
                            l[(r - s0, j - s0)] = self.l_value(col + ncols + t);
                        }
                    }
                }
            }
            SymbolicCholeskyRaw::Simplicial(s) => {
                let cp = s.col_ptr();
                let ri = s.row_idx();
                for j in s0..n {
                    for k in cp[j]..cp[j + 1] {
                        if ri[k] >= j {
                            l[(ri[k] - s0, j - s0)] = self.l_value(k);
                        }
                    }
                }
            }
        }
        Ok(l)
    }

    /// Bytes held by the factor values.
    pub fn memory_bytes(&self) -> usize {
        match &self.l_values {
            FactorValues::Double(v) => v.len() * 8,
            FactorValues::Single(v) => v.len() * 4,
        }
    }
}

/// Numeric LLᵀ in arithmetic `T`; `Err(index)` of a non-positive pivot.
fn numeric_llt<T: faer::traits::ComplexField + Copy>(
    symbolic: &SymbolicCholesky<usize>,
    a: SparseColMatRef<'_, usize, T>,
    par: Par,
) -> Result<Vec<T>, usize> {
    let mut l = vec![T::zero_impl(); symbolic.len_val()];
    let req = symbolic.factorize_numeric_llt_scratch::<T>(par, Default::default());
    let mut mem = MemBuffer::new(req);
    symbolic
        .factorize_numeric_llt(
            &mut l,
            a,
            Side::Lower,
            LltRegularization::default(),
            par,
            MemStack::new(&mut mem),
            Default::default(),
        )
        .map_err(
            |faer::linalg::cholesky::llt::factor::LltError::NonPositivePivot { index }| {
                // faer's simplicial path reports the pivot 1-based, the supernodal one 0-based
                match symbolic.raw() {
                    SymbolicCholeskyRaw::Simplicial(_) => index.saturating_sub(1),
                    SymbolicCholeskyRaw::Supernodal(_) => index,
                }
            },
        )?;
    Ok(l)
}

/// The transpose of a lower-triangular CSC pattern (= its upper-triangular CSC pattern).
fn transpose_pattern(p: &LowerCsc<'_>) -> (Vec<usize>, Vec<usize>) {
    let n = p.n;
    let mut count = vec![0usize; n + 1];
    for c in 0..n {
        for &r in &p.row_idx[p.col_range(c)] {
            count[r + 1] += 1;
        }
    }
    for i in 0..n {
        count[i + 1] += count[i];
    }
    let mut fill = count.clone();
    let mut rows = vec![0usize; count[n]];
    for c in 0..n {
        for &r in &p.row_idx[p.col_range(c)] {
            rows[fill[r]] = c;
            fill[r] += 1;
        }
    }
    (count, rows)
}

/// nnz(L), factorization flops, and whether the factor is supernodal.
fn factor_counts(symbolic: &SymbolicCholesky<usize>) -> (usize, f64, bool) {
    match symbolic.raw() {
        SymbolicCholeskyRaw::Supernodal(s) => {
            let (beg, end) = (s.supernode_begin(), s.supernode_end());
            let rptr = s.col_ptr_for_row_idx();
            let mut nnz = 0usize;
            let mut flops = 0.0;
            for k in 0..s.n_supernodes() {
                let below = rptr[k + 1] - rptr[k];
                for j in beg[k]..end[k] {
                    let c = (end[k] - j) + below;
                    nnz += c;
                    flops += (c as f64) * (c as f64);
                }
            }
            (nnz, flops, true)
        }
        SymbolicCholeskyRaw::Simplicial(s) => {
            let cp = s.col_ptr();
            let mut flops = 0.0;
            for j in 0..s.nrows() {
                let c = (cp[j + 1] - cp[j]) as f64;
                flops += c * c;
            }
            (s.len_val(), flops, false)
        }
    }
}
