//! Sparse Cholesky (LLᵀ) of the reduced stiffness with faer.
//!
//! The symbolic analysis (ordering, elimination tree, supernodes) is done once
//! per pattern and reused by every numeric factorization of a matrix with the
//! same pattern ([`SparseCholesky::factorize`]).

use std::time::Instant;

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltRegularization;
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
    pub supernodal: bool,
    pub ordering_s: f64,
    pub symbolic_s: f64,
    pub factorization_s: f64,
    /// min_j L_jj² / A_jj: how close the matrix came to a zero pivot (1 = diagonal).
    pub min_pivot_ratio: f64,
}

/// A symbolic analysis plus (after [`factorize`](Self::factorize)) the numeric factor.
pub struct SparseCholesky {
    symbolic: SymbolicCholesky<usize>,
    l_values: Vec<f64>,
    /// fwd[new] = old
    perm_fwd: Vec<usize>,
    factorized: bool,
    par: Par,
    pub stats: FactorStats,
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
    pub fn analyze(pattern: &SparsePattern, ordering: OrderingMethod, ordering_s: f64, par: Par) -> Result<Self, FlankError> {
        let n = pattern.n;
        if n == 0 {
            return Err(FlankError::Singular("the system has no free degree of freedom".into()));
        }
        let t0 = Instant::now();
        // faer's symbolic analysis without a permutation reads the upper
        // triangle; give it the transposed pattern (temporarily), so that the
        // numeric factorization can then use the lower triangle in place.
        let (col_ptr_t, row_idx_t) = transpose_pattern(pattern);
        let sym = SymbolicSparseColMatRef::new_checked(n, n, &col_ptr_t, None, &row_idx_t);
        let params = CholeskySymbolicParams {
            supernodal_flop_ratio_threshold: SupernodalThreshold::AUTO,
            ..Default::default()
        };
        let symbolic = factorize_symbolic_cholesky(sym, Side::Upper, SymmetricOrdering::Identity, params)
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
            l_values: Vec::new(),
            symbolic,
            perm_fwd: (0..n).collect(),
            factorized: false,
            par,
            stats,
        })
    }

    /// Numeric LLᵀ of the matrix with this pattern and lower-triangle `values`.
    /// `dof_name` names a reduced DOF in error messages.
    pub fn factorize(
        &mut self,
        pattern: &SparsePattern,
        values: &[f64],
        dof_name: &dyn Fn(usize) -> String,
    ) -> Result<(), FlankError> {
        let n = pattern.n;
        if let Some(k) = values.iter().position(|v| !v.is_finite()) {
            return Err(FlankError::Solver(format!(
                "stiffness entry {k} is not finite"
            )));
        }
        let t0 = Instant::now();
        let a = SparseColMatRef::new(
            SymbolicSparseColMatRef::new_checked(n, n, &pattern.col_ptr, None, &pattern.row_idx),
            values,
        );
        self.l_values.clear();
        self.l_values.resize(self.symbolic.len_val(), 0.0);
        let req = self
            .symbolic
            .factorize_numeric_llt_scratch::<f64>(self.par, Default::default());
        let mut mem = MemBuffer::try_new(req)
            .map_err(|_| FlankError::Solver("out of memory for factorization workspace".into()))?;
        let stack = MemStack::new(&mut mem);
        self.factorized = false;
        self.symbolic
            .factorize_numeric_llt(
                &mut self.l_values,
                a,
                Side::Lower,
                LltRegularization::default(),
                self.par,
                stack,
                Default::default(),
            )
            .map_err(|e| match e {
                faer::linalg::cholesky::llt::factor::LltError::NonPositivePivot { index } => {
                    let old = self.perm_fwd.get(index).copied().unwrap_or(index);
                    FlankError::Singular(format!(
                        "the stiffness matrix is not positive definite: zero or negative pivot at {} \
                         (constraints missing, a mechanism, or an invalid material)",
                        dof_name(old)
                    ))
                }
            })?;
        self.stats.factorization_s = t0.elapsed().as_secs_f64();
        // pivot ratio min_j L_jj² / A_jj
        let mut diag = vec![0.0; n];
        for c in 0..n {
            if let Some(s) = pattern.slot(c, c) {
                diag[c] = values[s];
            }
        }
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
                    let v = &self.l_values[vptr[k]..vptr[k + 1]];
                    for j in 0..ncols {
                        d[beg[k] + j] = v[j * nrows + j];
                    }
                }
            }
            SymbolicCholeskyRaw::Simplicial(s) => {
                let cp = s.col_ptr();
                let ri = s.row_idx();
                for j in 0..n {
                    for k in cp[j]..cp[j + 1] {
                        if ri[k] == j {
                            d[j] = self.l_values[k];
                        }
                    }
                }
            }
        }
        d
    }

    /// Solves A x = b in place for every column of `rhs` (n × k).
    pub fn solve_columns(&self, rhs: MatMut<'_, f64>) {
        assert!(self.factorized, "solve before a successful factorization");
        let k = rhs.ncols();
        let req = self.symbolic.solve_in_place_scratch::<f64>(k, self.par);
        let mut mem = MemBuffer::new(req);
        let stack = MemStack::new(&mut mem);
        LltRef::new(&self.symbolic, &self.l_values).solve_in_place_with_conj(
            Conj::No,
            rhs,
            self.par,
            stack,
        );
    }

    /// Solves A x = b in place for one right-hand side.
    pub fn solve_in_place(&self, rhs: &mut [f64]) {
        let n = rhs.len();
        let m = faer::MatMut::from_column_major_slice_mut(rhs, n, 1);
        self.solve_columns(m);
    }

    /// Bytes held by the factor values.
    pub fn memory_bytes(&self) -> usize {
        self.l_values.len() * 8
    }
}

/// The transpose of a lower-triangular CSC pattern (= its upper-triangular CSC pattern).
fn transpose_pattern(p: &SparsePattern) -> (Vec<usize>, Vec<usize>) {
    let n = p.n;
    let mut count = vec![0usize; n + 1];
    for &r in &p.row_idx {
        count[r + 1] += 1;
    }
    for i in 0..n {
        count[i + 1] += count[i];
    }
    let mut fill = count.clone();
    let mut rows = vec![0usize; p.row_idx.len()];
    for c in 0..n {
        for k in p.col_ptr[c]..p.col_ptr[c + 1] {
            let r = p.row_idx[k];
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
