//! Solves restricted to a set of DOFs with a supernodal factor: the reach
//! of the DOFs in the elimination tree ([`SparseCholesky::reach`], a
//! [`SolveReach`]) and the forward and backward substitutions on it only
//! ([`SparseCholesky::solve_restricted`]), exactly the full solve's
//! arithmetic on those rows. Used where many sparse right-hand sides are
//! solved with one factor and only a few rows of the answers are read (the
//! compliance tensors, the FE contact's Delassus columns).

use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::prelude::{Reborrow, ReborrowMut};
use faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky;
use faer::sparse::linalg::cholesky::SymbolicCholeskyRaw;
use faer::{Accum, MatMut, MatRef, Par};

use super::supernode_tree::{SupernodeTree, NONE};
use super::{FactorValues, SparseCholesky};

impl SparseCholesky {
    /// The reach of the reduced DOFs `dofs` in the factor's elimination
    /// tree, for [`solve_restricted`](Self::solve_restricted): the
    /// supernodes holding them and all their ancestors. `None` when the
    /// restricted solve does not apply (a simplicial factor, chosen by faer
    /// for small or very sparse systems, or a factor with its own
    /// permutation): use [`solve_columns`](Self::solve_columns) then.
    pub fn reach(&self, dofs: &[usize]) -> Option<SolveReach> {
        if self.symbolic.perm().is_some() {
            return None;
        }
        let SymbolicCholeskyRaw::Supernodal(s) = self.symbolic.raw() else {
            return None;
        };
        let tree = self
            .tree
            .get_or_init(|| Some(SupernodeTree::new(s)))
            .as_ref()?;
        let ns = s.n_supernodes();
        let mut mark = vec![false; ns];
        for &d in dofs {
            let mut k = tree.of_row[d];
            while k != NONE && !mark[k] {
                mark[k] = true;
                k = tree.parent[k];
            }
        }
        let supernodes: Vec<usize> = (0..ns).filter(|&k| mark[k]).collect();
        let (beg, end) = (s.supernode_begin(), s.supernode_end());
        let rptr = s.col_ptr_for_row_idx();
        let mut local = vec![NONE; self.stats.n];
        let mut offsets = Vec::with_capacity(supernodes.len() + 1);
        let mut parent = Vec::with_capacity(supernodes.len());
        let mut rows = 0usize;
        let mut touched = 0usize;
        let mut max_pattern = 0usize;
        for &k in &supernodes {
            offsets.push(rows);
            for (i, l) in local[beg[k]..end[k]].iter_mut().enumerate() {
                *l = rows + i;
            }
            rows += end[k] - beg[k];
            let below = rptr[k + 1] - rptr[k];
            let c = end[k] - beg[k];
            touched += c * (c + 1) / 2 + c * below;
            max_pattern = max_pattern.max(below);
            let p = tree.parent[k];
            parent.push(if p == NONE {
                NONE
            } else {
                supernodes
                    .binary_search(&p)
                    .expect("the reach is closed under parent")
            });
        }
        offsets.push(rows);
        Some(SolveReach {
            supernodes,
            parent,
            offsets,
            local,
            max_pattern,
            touched_nnz: touched,
            factor_nnz: self.stats.nnz_factor,
        })
    }

    /// [`solve_restricted`](Self::solve_restricted) where only the rows of
    /// the supernodes flagged in `wanted` ([`SolveReach::wanted`]: a set
    /// closed under parent) are read: the backward substitution skips the
    /// others, whose rows are returned as zeros. The wanted rows are exactly
    /// those of `solve_restricted` (a row of x depends only on the rows of
    /// its supernode's ancestors). The compliance panels use it: panel q
    /// keeps only the blocks of pages r ≥ q.
    pub fn solve_restricted_to(
        &self,
        reach: &SolveReach,
        columns: &[&[(usize, f64)]],
        wanted: &[bool],
        par: Par,
    ) -> faer::Mat<f64> {
        assert_eq!(
            wanted.len(),
            reach.supernodes.len(),
            "one flag per supernode of the reach"
        );
        self.solve_restricted_with(reach, columns, Some(wanted), par)
    }

    /// Rows `reach` of the solutions X of A X = B for sparse right-hand
    /// sides: `columns[j]` lists the non-zeros `(dof, value)` of column j
    /// (repeated DOFs add up), every `dof` inside `reach`. Returns the
    /// `reach.rows() × columns.len()` block of X on the reach
    /// ([`SolveReach::local`] gives the row of a DOF), exactly the rows the
    /// full [`solve_columns`](Self::solve_columns) would give: the forward
    /// substitution visits only the ancestors of each block's non-zeros,
    /// the backward one only the reach. With a single-precision factor the
    /// solve is done in f32, as `solve_columns`.
    pub fn solve_restricted(
        &self,
        reach: &SolveReach,
        columns: &[&[(usize, f64)]],
        par: Par,
    ) -> faer::Mat<f64> {
        self.solve_restricted_with(reach, columns, None, par)
    }

    fn solve_restricted_with(
        &self,
        reach: &SolveReach,
        columns: &[&[(usize, f64)]],
        wanted: Option<&[bool]>,
        par: Par,
    ) -> faer::Mat<f64> {
        assert!(self.factorized, "solve before a successful factorization");
        let SymbolicCholeskyRaw::Supernodal(s) = self.symbolic.raw() else {
            panic!("a restricted solve needs a supernodal factor (see SparseCholesky::reach)");
        };
        let k = columns.len();
        // supernodes the forward substitution must visit: the ancestors of
        // the right-hand sides' non-zeros (the rest of y = L⁻¹b is zero)
        let entries: Vec<usize> = columns.iter().flat_map(|c| c.iter().map(|e| e.0)).collect();
        let active = reach
            .wanted(&entries)
            .unwrap_or_else(|e| panic!("right-hand side entry at {e}"));
        match &self.l_values {
            FactorValues::Double(v) => {
                let mut w = faer::Mat::<f64>::zeros(reach.rows(), k);
                for (j, col) in columns.iter().enumerate() {
                    for &(d, x) in col.iter() {
                        w[(reach.local[d], j)] += x;
                    }
                }
                restricted_substitutions(s, v, reach, &active, wanted, w.as_mut(), par);
                w
            }
            FactorValues::Single(v) => {
                let mut w = faer::Mat::<f32>::zeros(reach.rows(), k);
                for (j, col) in columns.iter().enumerate() {
                    for &(d, x) in col.iter() {
                        w[(reach.local[d], j)] += x as f32;
                    }
                }
                restricted_substitutions(s, v, reach, &active, wanted, w.as_mut(), par);
                faer::Mat::from_fn(reach.rows(), k, |i, j| w[(i, j)] as f64)
            }
        }
    }
}

/// The part of a supernodal factor that solves restricted to a set of DOFs
/// touch ([`SparseCholesky::reach`]): the supernodes holding those DOFs and
/// all their ancestors in the elimination tree, a set closed under parent.
///
/// The rows of L's columns in a supernode lie in its ancestors, so the
/// forward substitution L y = b for a right-hand side that is non-zero on
/// the reach only changes y on the reach, and x = L⁻ᵀ y on the reach
/// depends only on y there: both substitutions, restricted to the reach,
/// are exactly the full ones' arithmetic on those rows. Built once per set
/// of DOFs and reused for every block of right-hand sides.
#[derive(Clone, Debug)]
pub struct SolveReach {
    /// Supernodes of the reach, ascending (children before parents).
    supernodes: Vec<usize>,
    /// Position in `supernodes` of each one's parent ([`NONE`]: a root).
    parent: Vec<usize>,
    /// First workspace row of each supernode (and the total at the end).
    offsets: Vec<usize>,
    /// Workspace row of each reduced DOF ([`NONE`] outside the reach).
    local: Vec<usize>,
    /// Largest off-diagonal row count of a supernode of the reach.
    max_pattern: usize,
    /// Non-zeros of L in the reach's columns (what one restricted
    /// substitution reads).
    pub touched_nnz: usize,
    /// Non-zeros of L.
    pub factor_nnz: usize,
}

impl SolveReach {
    /// Rows of the reach (reduced DOFs in its supernodes).
    pub fn rows(&self) -> usize {
        self.offsets.last().copied().unwrap_or(0)
    }

    /// Supernodes in the reach.
    pub fn supernode_count(&self) -> usize {
        self.supernodes.len()
    }

    /// Row of reduced DOF `dof` in a restricted solution, if in the reach.
    pub fn local(&self, dof: usize) -> Option<usize> {
        self.local.get(dof).copied().filter(|&l| l != NONE)
    }

    /// Fraction of nnz(L) a restricted substitution reads.
    pub fn touched_fraction(&self) -> f64 {
        self.touched_nnz as f64 / self.factor_nnz.max(1) as f64
    }

    /// The supernodes of the reach (flags by position) whose rows a
    /// solution on the reduced DOFs `dofs` needs: those holding them and
    /// their ancestors, for [`SparseCholesky::solve_restricted_to`]. An
    /// error names a DOF outside the reach.
    pub fn wanted(&self, dofs: &[usize]) -> Result<Vec<bool>, String> {
        let mut flags = vec![false; self.supernodes.len()];
        for &d in dofs {
            let Some(l) = self.local(d) else {
                return Err(format!("DOF {d} outside the reach"));
            };
            let mut p = self.offsets.partition_point(|&o| o <= l) - 1;
            while p != NONE && !flags[p] {
                flags[p] = true;
                p = self.parent[p];
            }
        }
        Ok(flags)
    }
}

/// Supernodes smaller than this (stored values) are done sequentially: the
/// threads' start-up costs more than their dense kernels.
const PAR_MIN_VALUES: usize = 1 << 16;

/// Forward and backward substitution with the supernodal factor `values`
/// restricted to `reach` (workspace `w`: the reach's rows, the right-hand
/// sides scattered in, the solution on return). The forward pass visits
/// the `active` supernodes (positions in the reach), the backward pass the
/// `wanted` ones (all if `None`; the rows of the others are zeroed).
fn restricted_substitutions<T>(
    s: &SymbolicSupernodalCholesky<usize>,
    values: &[T],
    reach: &SolveReach,
    active: &[bool],
    wanted: Option<&[bool]>,
    mut w: MatMut<'_, T>,
    par: Par,
) where
    T: faer::traits::ComplexField + Copy + std::ops::SubAssign + std::ops::Neg<Output = T>,
{
    let k = w.ncols();
    if k == 0 {
        return;
    }
    let (beg, end) = (s.supernode_begin(), s.supernode_end());
    let vptr = s.col_ptr_for_val();
    let rptr = s.col_ptr_for_row_idx();
    let ridx = s.row_idx();
    let mut tmp = faer::Mat::<T>::zeros(reach.max_pattern, k);
    let block = |p: usize| {
        let sn = reach.supernodes[p];
        let nc = end[sn] - beg[sn];
        let pattern = &ridx[rptr[sn]..rptr[sn + 1]];
        let l = MatRef::from_column_major_slice(
            &values[vptr[sn]..vptr[sn + 1]],
            nc + pattern.len(),
            nc,
        );
        let kpar = if l.nrows() * nc >= PAR_MIN_VALUES {
            par
        } else {
            Par::Seq
        };
        (l, pattern, reach.offsets[p], nc, kpar)
    };
    // L y = b, children before parents
    for p in 0..reach.supernodes.len() {
        if !active[p] {
            continue;
        }
        let (l, pattern, off, nc, kpar) = block(p);
        let (top, bot) = l.split_at_row(nc);
        solve_lower_triangular_in_place(top, w.rb_mut().subrows_mut(off, nc), kpar);
        if pattern.is_empty() {
            continue;
        }
        let mut t = tmp.rb_mut().subrows_mut(0, pattern.len());
        matmul(
            t.rb_mut(),
            Accum::Replace,
            bot,
            w.rb().subrows(off, nc),
            T::one_impl(),
            kpar,
        );
        for j in 0..k {
            for (i, &r) in pattern.iter().enumerate() {
                w[(reach.local[r], j)] -= t[(i, j)];
            }
        }
    }
    // Lᵀ x = y, parents before children
    for p in (0..reach.supernodes.len()).rev() {
        if wanted.is_some_and(|f| !f[p]) {
            let (off, nc) = (reach.offsets[p], reach.offsets[p + 1] - reach.offsets[p]);
            w.rb_mut().subrows_mut(off, nc).fill(T::zero_impl());
            continue;
        }
        let (l, pattern, off, nc, kpar) = block(p);
        let (top, bot) = l.split_at_row(nc);
        if !pattern.is_empty() {
            let mut t = tmp.rb_mut().subrows_mut(0, pattern.len());
            for j in 0..k {
                for (i, &r) in pattern.iter().enumerate() {
                    t[(i, j)] = w[(reach.local[r], j)];
                }
            }
            matmul(
                w.rb_mut().subrows_mut(off, nc),
                Accum::Add,
                bot.transpose(),
                t.rb(),
                -T::one_impl(),
                kpar,
            );
        }
        solve_upper_triangular_in_place(top.transpose(), w.rb_mut().subrows_mut(off, nc), kpar);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fem::assembly::{Assembly, SparsePattern};
    use crate::fem::constraints::DofMap;
    use crate::fem::ordering::OrderingMethod;
    use crate::fem::solver::Precision;
    use crate::mesh::structured::{cantilever_model, BoxElement};
    use crate::testing::Rng;
    use faer::sparse::linalg::SupernodalThreshold;

    /// Lower-triangle CSC of a shifted 7-point Laplacian on an
    /// `a × b × c` grid with random couplings (SPD: diagonally dominant),
    /// in natural order (large fronts: a deep supernodal tree).
    fn grid_system(a: usize, b: usize, c: usize, rng: &mut Rng) -> (SparsePattern, Vec<f64>) {
        let n = a * b * c;
        let id = |i: usize, j: usize, k: usize| i + a * (j + b * k);
        let mut col_ptr = vec![0];
        let mut row_idx = Vec::new();
        let mut values = Vec::new();
        for k in 0..c {
            for j in 0..b {
                for i in 0..a {
                    let me = id(i, j, k);
                    let mut below = Vec::new();
                    if i + 1 < a {
                        below.push(id(i + 1, j, k));
                    }
                    if j + 1 < b {
                        below.push(id(i, j + 1, k));
                    }
                    if k + 1 < c {
                        below.push(id(i, j, k + 1));
                    }
                    row_idx.push(me);
                    values.push(6.5 + rng.unit().abs());
                    for r in below {
                        row_idx.push(r);
                        values.push(-0.5 - 0.5 * rng.unit().abs());
                    }
                    col_ptr.push(row_idx.len());
                }
            }
        }
        (
            SparsePattern {
                n,
                col_ptr,
                row_idx,
            },
            values,
        )
    }

    /// The stiffness of a small hex20 cantilever, METIS-ordered, as the
    /// contact system assembles it.
    fn cantilever_system() -> (SparsePattern, Vec<f64>) {
        let model = cantilever_model([8, 3, 3], BoxElement::Hex20, 100.0).unwrap();
        let mut dofs = DofMap::new(&model).unwrap();
        let asm = Assembly::new(&model, &mut dofs, OrderingMethod::Metis).unwrap();
        let sys = asm.assemble(&model, &dofs).unwrap();
        (asm.pattern, sys.values)
    }

    /// [`cantilever_system`] factorized, double precision, supernodal.
    fn cantilever_factor() -> SparseCholesky {
        let (pattern, values) = cantilever_system();
        factor(
            &pattern,
            &values,
            Precision::Double,
            SupernodalThreshold::FORCE_SUPERNODAL,
        )
    }

    fn factor(
        pattern: &SparsePattern,
        values: &[f64],
        precision: Precision,
        supernodal: SupernodalThreshold,
    ) -> SparseCholesky {
        let mut chol =
            SparseCholesky::analyze_with(pattern, OrderingMethod::Metis, 0.0, Par::Seq, supernodal)
                .unwrap();
        chol.factorize(pattern, values, precision, &|r| r.to_string())
            .unwrap();
        chol
    }

    /// Restricted against full solves on random sparse right-hand sides and
    /// random row sets; returns the largest relative difference.
    fn compare(chol: &SparseCholesky, rng: &mut Rng, par: Par) -> f64 {
        let n = chol.stats.n;
        let mut worst = 0.0f64;
        for &(ncols, nrows) in &[(1, 1), (1, 12), (5, 30), (40, 60)] {
            let rows: Vec<usize> = (0..nrows).map(|_| rng.below(n)).collect();
            let columns: Vec<Vec<(usize, f64)>> = (0..ncols)
                .map(|_| {
                    (0..1 + rng.below(8))
                        .map(|_| (rng.below(n), rng.unit()))
                        .collect()
                })
                .collect();
            let mut dofs = rows.clone();
            dofs.extend(columns.iter().flatten().map(|e| e.0));
            let reach = chol.reach(&dofs).expect("a supernodal factor has a reach");
            // closed under parent, ascending, rows consistent
            let tree = chol.tree.get().unwrap().as_ref().unwrap();
            for (p, &sn) in reach.supernodes.iter().enumerate() {
                let par_sn = tree.parent[sn];
                if par_sn == NONE {
                    assert_eq!(reach.parent[p], NONE);
                } else {
                    assert!(par_sn > sn);
                    assert_eq!(reach.supernodes[reach.parent[p]], par_sn);
                }
            }
            for &d in &dofs {
                assert!(reach.local(d).is_some());
            }
            assert!(reach.touched_nnz <= reach.factor_nnz);
            let refs: Vec<&[(usize, f64)]> = columns.iter().map(|c| &c[..]).collect();
            let x = chol.solve_restricted(&reach, &refs, par);
            let mut full = faer::Mat::<f64>::zeros(n, ncols);
            for (j, c) in columns.iter().enumerate() {
                for &(d, v) in c {
                    full[(d, j)] += v;
                }
            }
            chol.solve_columns_with(full.as_mut(), par);
            for j in 0..ncols {
                let scale = (0..n).fold(0.0f64, |m, i| m.max(full[(i, j)].abs()));
                for &r in &rows {
                    let diff = (x[(reach.local(r).unwrap(), j)] - full[(r, j)]).abs();
                    worst = worst.max(diff / scale);
                }
            }
        }
        worst
    }

    /// Solving for a subset of the reach's rows gives those rows' bits of
    /// the restricted solve, zeros on the supernodes it skips, skips some,
    /// and names a DOF outside the reach.
    #[test]
    fn wanted_rows_are_the_restricted_solve_s() {
        let mut rng = Rng::new(0x5eed_0f7a_1100);
        let chol = cantilever_factor();
        let n = chol.stats.n;
        let dofs: Vec<usize> = (0..80).map(|_| rng.below(n)).collect();
        let reach = chol.reach(&dofs).unwrap();
        let columns: Vec<Vec<(usize, f64)>> = dofs[..6].iter().map(|&d| vec![(d, 1.0)]).collect();
        let refs: Vec<&[(usize, f64)]> = columns.iter().map(|c| &c[..]).collect();
        let all = chol.solve_restricted(&reach, &refs, Par::Seq);
        let kept = &dofs[40..];
        let wanted = reach.wanted(kept).unwrap();
        assert!(wanted.iter().any(|&w| !w), "nothing skipped");
        let part = chol.solve_restricted_to(&reach, &refs, &wanted, Par::Seq);
        for &d in kept {
            let l = reach.local(d).unwrap();
            for j in 0..refs.len() {
                assert_eq!(part[(l, j)].to_bits(), all[(l, j)].to_bits(), "DOF {d}");
            }
        }
        for (p, &w) in wanted.iter().enumerate() {
            if !w {
                for l in reach.offsets[p]..reach.offsets[p + 1] {
                    assert!((0..refs.len()).all(|j| part[(l, j)] == 0.0));
                }
            }
        }
        let outside = (0..n).find(|&d| reach.local(d).is_none());
        if let Some(d) = outside {
            let e = reach.wanted(&[d]).unwrap_err();
            assert!(e.contains(&d.to_string()), "{e}");
        }
    }

    #[test]
    fn restricted_solve_matches_full_solve() {
        let mut rng = Rng::new(0x9e37_79b9_7f4a_7c15);
        let systems = [
            grid_system(6, 5, 4, &mut rng),
            grid_system(14, 13, 12, &mut rng),
            cantilever_system(),
        ];
        for (pattern, values) in &systems {
            let chol = factor(
                pattern,
                values,
                Precision::Double,
                SupernodalThreshold::FORCE_SUPERNODAL,
            );
            assert!(chol.stats.supernodal);
            for par in [Par::Seq, Par::rayon(2)] {
                let err = compare(&chol, &mut rng, par);
                assert!(err <= 1e-12, "n = {}: {err:.2e}", pattern.n);
            }
            // the single-precision factor: same arithmetic in f32
            let chol32 = factor(
                pattern,
                values,
                Precision::Mixed,
                SupernodalThreshold::FORCE_SUPERNODAL,
            );
            let err = compare(&chol32, &mut rng, Par::Seq);
            assert!(err <= 1e-5, "f32, n = {}: {err:.2e}", pattern.n);
        }
    }

    #[test]
    fn reach_of_a_point_is_a_fraction_of_the_factor() {
        // natural order on a grid makes the tree a path; nested dissection
        // (the cantilever, METIS) gives it branches; this body is small, so
        // the top separator alone is a good part of the factor (about half)
        let chol = cantilever_factor();
        let reach = chol.reach(&[0]).unwrap();
        assert!(
            reach.touched_fraction() < 0.75,
            "{}",
            reach.touched_fraction()
        );
        let all: Vec<usize> = (0..chol.stats.n).collect();
        let whole = chol.reach(&all).unwrap();
        assert_eq!(whole.touched_nnz, chol.stats.nnz_factor);
        assert_eq!(whole.rows(), chol.stats.n);
    }

    #[test]
    fn simplicial_factor_has_no_reach() {
        let mut rng = Rng::new(3);
        let (pattern, values) = grid_system(4, 4, 3, &mut rng);
        let chol = factor(
            &pattern,
            &values,
            Precision::Double,
            SupernodalThreshold::FORCE_SIMPLICIAL,
        );
        assert!(!chol.stats.supernodal);
        assert!(chol.reach(&[0, 5]).is_none());
    }
}
