//! Two-domain (substructured) Cholesky of the reduced stiffness: the
//! factorization split in two independent halves that run concurrently.
//!
//! A vertex separator S of the DOF-group graph splits the reduced DOFs into
//! parts A and B with no stiffness between them (one bisection of George's
//! nested dissection, SIAM J. Numer. Anal. 10, 1973, computed by METIS on
//! the corner-node graph). The DOFs are numbered \[A, S, B\]. With S last,
//! the principal submatrices M_A = K\[A∪S\] and M_B = K\[B∪S\] (SPD as
//! principal submatrices of an SPD K) are factorized independently, each on
//! its own thread; the trailing block L_SS of M_A's factor gives
//! T_A = L_SS L_SSᵀ = K_SS − K_SA K_AA⁻¹ K_AS, and the Schur complement on
//! the separator is S = T_A + T_B − K_SS (static condensation, Schur-
//! complement domain decomposition: Saad, *Iterative Methods for Sparse
//! Linear Systems*, 2nd ed., 2003, §14.2), factorized dense. A solve is a
//! block elimination whose two halves again run concurrently
//! ([`TwoDomainCholesky::solve_in_place`]).
//!
//! faer's supernodal factorization has no tree-level parallelism (a second
//! core gains 2–3 % on the C3D20 cantilever); the two halves give the
//! factorization and the solves that parallelism one level down.

use std::time::Instant;

use faer::linalg::matmul::triangular::{self, BlockStructure};
use faer::linalg::solvers::{Llt, Solve};
use faer::sparse::linalg::SupernodalThreshold;
use faer::{Accum, Mat, Par, Side};

use crate::error::FlankError;
use crate::fem::assembly::SparsePattern;
use crate::fem::ordering::{DomainSplit, OrderingMethod};
use crate::fem::solver::{LowerCsc, MatrixValues, Precision, SparseCholesky};

/// Whether the static solve may use the two-domain factorization.
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
pub enum Substructure {
    /// Never: one factorization of the whole stiffness.
    Off,
    /// With two or more threads, the mixed precision, at least 50 000
    /// reduced DOFs and a separator of at most 2 000 DOFs (default).
    #[default]
    Auto,
    /// Whenever the precision is mixed, at any size and thread count
    /// (tests, measurements).
    On,
}

impl Substructure {
    /// Whether a static solve of `dofs` reduced DOFs on `threads` threads
    /// in `precision` uses the two-domain factorization.
    pub fn applies(self, dofs: usize, threads: usize, precision: Precision) -> bool {
        precision == Precision::Mixed
            && match self {
                Substructure::Off => false,
                Substructure::Auto => threads >= 2 && dofs >= SUBSTRUCTURE_MIN_DOFS,
                Substructure::On => true,
            }
    }
}

/// Reduced DOFs from which `Substructure::Auto` splits the static solve
/// (below it the whole solve takes a fraction of a second and the second
/// core gains little; see `benches/README.md`).
pub const SUBSTRUCTURE_MIN_DOFS: usize = 50_000;

/// Separator DOFs above which `Substructure::Auto` keeps the plain
/// factorization: the separator's dense work (its block in each half's
/// factor, T = L_SS L_SSᵀ in each half, the Schur complement's Cholesky:
/// ≈ ns³ flops on the critical path against ns³/3 in the plain factor) and
/// memory (five ns × ns f64 matrices) grow as ns³ and ns². On a 20³ C3D20
/// cube (ns = 3 720) the two-domain solve was slower than the plain one;
/// on the 100×10×10 bar (ns = 1 023) faster (benches/README.md).
pub const SUBSTRUCTURE_MAX_SEPARATOR_DOFS: usize = 2_000;

/// Figures of one half's factorization.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct HalfStats {
    /// DOFs of the part (without the separator).
    pub dofs: usize,
    pub nnz_matrix: usize,
    pub nnz_factor: usize,
    pub gflop: f64,
    pub symbolic_s: f64,
    pub factorization_s: f64,
}

/// Figures of a two-domain factorization (in `summary.json`).
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct SubstructureStats {
    pub separator_dofs: usize,
    /// Parts A and B.
    pub halves: [HalfStats; 2],
    /// Wall time of the two concurrent factorizations (with T = L_SS L_SSᵀ).
    pub factorization_s: f64,
    /// Assembly and dense Cholesky of the separator's Schur complement.
    pub schur_s: f64,
    /// The memory guard's estimate of both factorizations' extra memory
    /// and the resident set when it was made (MB).
    pub factor_estimate_mb: f64,
    pub resident_before_mb: f64,
}

/// The two-domain factorization: M_A = K\[A∪S\] (a leading principal block
/// of K in the \[A, S, B\] numbering, read in place), M_B = K\[B∪S\] (a copy
/// of its pattern in the order \[B, S\]), and the dense Cholesky factor of
/// the Schur complement on S.
pub struct TwoDomainCholesky {
    split: DomainSplit,
    /// Entries of each column of M_A in K's columns (the S columns end
    /// before their B rows).
    a_col_nnz: Vec<usize>,
    /// M_B's pattern, order \[B, S\]; its B columns begin with K's B
    /// columns' rows (shifted), the only copy of them once K's pattern is
    /// [`adopt`](Self::adopt)ed.
    b_pattern: SparsePattern,
    /// K's pattern, its B columns' rows dropped after [`adopt`](Self::adopt).
    k: Option<SparsePattern>,
    a: SparseCholesky,
    b: SparseCholesky,
    /// Trailing blocks L_SS of the two factors (dense, lower).
    l_ss: [Mat<f64>; 2],
    schur: Option<Llt<f64>>,
    half_par: Par,
    pub stats: SubstructureStats,
}

impl TwoDomainCholesky {
    /// Builds M_A's view and M_B's pattern from K's `pattern` (numbered
    /// \[A, S, B\] by `split`) and analyses both (concurrently), each with
    /// half of `par`'s threads.
    pub fn analyze(
        pattern: &SparsePattern,
        split: DomainSplit,
        ordering: OrderingMethod,
        ordering_s: f64,
        par: Par,
    ) -> Result<Self, FlankError> {
        let DomainSplit {
            a: na,
            s: ns,
            b: nb,
        } = split;
        let n = pattern.n;
        if na + ns + nb != n || na == 0 || nb == 0 {
            return Err(FlankError::Solver(format!(
                "two-domain split {na} + {ns} + {nb} of {n} DOFs: a part is empty or the sizes do not add up"
            )));
        }
        let nas = na + ns;
        let (cp, ri) = (&pattern.col_ptr, &pattern.row_idx);
        let mut a_col_nnz = Vec::with_capacity(nas);
        for c in 0..nas {
            let rows = &ri[cp[c]..cp[c + 1]];
            let len = rows.partition_point(|&r| r < nas);
            if c < na && len != rows.len() {
                return Err(FlankError::Solver(format!(
                    "two-domain split: DOF {c} of part A is coupled to DOF {} of part B",
                    rows[len]
                )));
            }
            a_col_nnz.push(len);
        }
        // M_B in the order [B, S]: B column i = K's column nas + i (B rows)
        // followed by its S rows, found in K's S columns
        let mut count = vec![0usize; nb + ns + 1];
        for c in nas..n {
            count[c - nas + 1] = cp[c + 1] - cp[c];
        }
        for c in na..nas {
            for &r in &ri[cp[c]..cp[c + 1]] {
                if r >= nas {
                    count[r - nas + 1] += 1;
                } else {
                    count[nb + c - na + 1] += 1;
                }
            }
        }
        for i in 0..nb + ns {
            count[i + 1] += count[i];
        }
        let mut b_rows = vec![0usize; count[nb + ns]];
        walk_b(pattern, split, &count, |slot, row, _| b_rows[slot] = row);
        let b_pattern = SparsePattern {
            n: nb + ns,
            col_ptr: count,
            row_idx: b_rows,
        };
        let half_par = match par.degree() {
            d if d >= 4 => Par::rayon(d / 2),
            _ => Par::Seq,
        };
        let a_view = LowerCsc {
            n: nas,
            col_ptr: &cp[..=nas],
            col_nnz: Some(&a_col_nnz),
            row_idx: ri,
        };
        let analyze = |view: LowerCsc<'_>| {
            SparseCholesky::analyze_view(
                view,
                ordering,
                ordering_s,
                half_par,
                SupernodalThreshold::FORCE_SUPERNODAL,
            )
        };
        let (a, b) = rayon::join(|| analyze(a_view), || analyze(b_pattern.view()));
        let (a, b) = (a?, b?);
        let half = |c: &SparseCholesky, dofs: usize| HalfStats {
            dofs,
            nnz_matrix: c.stats.nnz_matrix,
            nnz_factor: c.stats.nnz_factor,
            gflop: c.stats.flops * 1e-9,
            symbolic_s: c.stats.symbolic_s,
            factorization_s: 0.0,
        };
        let stats = SubstructureStats {
            separator_dofs: ns,
            halves: [half(&a, na), half(&b, nb)],
            ..Default::default()
        };
        Ok(TwoDomainCholesky {
            split,
            a_col_nnz,
            b_pattern,
            k: None,
            a,
            b,
            l_ss: [Mat::zeros(0, 0), Mat::zeros(0, 0)],
            schur: None,
            half_par,
            stats,
        })
    }

    /// The numbering's split.
    pub fn split(&self) -> DomainSplit {
        self.split
    }

    /// Takes K's pattern (the one given to [`analyze`](Self::analyze)) and
    /// drops its B columns' rows, which M_B's pattern holds too; K's
    /// product is then [`sym_mul`](Self::sym_mul) and
    /// [`into_pattern`](Self::into_pattern) gives K's pattern back.
    pub fn adopt(&mut self, mut pattern: SparsePattern) {
        let nas = self.split.a + self.split.s;
        pattern.row_idx.truncate(pattern.col_ptr[nas]);
        pattern.row_idx.shrink_to_fit();
        self.k = Some(pattern);
    }

    /// Row `k`-th slot of K's column `c ≥ nas` (a B column).
    #[inline]
    fn b_rows_of(&self, k: &SparsePattern, c: usize) -> &[usize] {
        let nas = self.split.a + self.split.s;
        let i = c - nas;
        let start = self.b_pattern.col_ptr[i];
        &self.b_pattern.row_idx[start..start + k.col_ptr[c + 1] - k.col_ptr[c]]
    }

    /// K's whole pattern again (after [`adopt`](Self::adopt)), e.g. for a
    /// plain factorization after the two-domain one failed.
    pub fn into_pattern(mut self) -> Option<SparsePattern> {
        let nas = self.split.a + self.split.s;
        let mut k = self.k.take()?;
        let mut rows = Vec::with_capacity(k.col_ptr[k.n]);
        rows.extend_from_slice(&k.row_idx);
        for c in nas..k.n {
            rows.extend(self.b_rows_of(&k, c).iter().map(|&r| r + nas));
        }
        k.row_idx = rows;
        Some(k)
    }

    /// y = K x for K's lower-triangle `values` on the adopted pattern: the
    /// columns of A and S and those of B, concurrently.
    pub fn sym_mul(&self, values: &[f64], x: &[f64]) -> Vec<f64> {
        let k = self.k.as_ref().expect("sym_mul before adopt");
        let n = k.n;
        let nas = self.split.a + self.split.s;
        let (mut y, yb) = rayon::join(
            || {
                let mut y = vec![0.0; n];
                for c in 0..nas {
                    let (lo, hi) = (k.col_ptr[c], k.col_ptr[c + 1]);
                    let xc = x[c];
                    let mut yc = 0.0;
                    for (&r, &v) in k.row_idx[lo..hi].iter().zip(&values[lo..hi]) {
                        y[r] += v * xc;
                        if r != c {
                            yc += v * x[r];
                        }
                    }
                    y[c] += yc;
                }
                y
            },
            || {
                let mut y = vec![0.0; n - nas];
                for c in nas..n {
                    let lo = k.col_ptr[c];
                    let rows = self.b_rows_of(k, c);
                    let xc = x[c];
                    let mut yc = 0.0;
                    for (&r, &v) in rows.iter().zip(&values[lo..lo + rows.len()]) {
                        y[r] += v * xc;
                        if r + nas != c {
                            yc += v * x[r + nas];
                        }
                    }
                    y[c - nas] += yc;
                }
                y
            },
        );
        for (a, b) in y[nas..].iter_mut().zip(&yb) {
            *a += b;
        }
        y
    }

    /// nnz of both factors.
    pub fn nnz_factor(&self) -> usize {
        self.a.stats.nnz_factor + self.b.stats.nnz_factor
    }

    /// Factorization flops of both halves.
    pub fn flops(&self) -> f64 {
        self.a.stats.flops + self.b.stats.flops
    }

    /// Non-zeros of K's lower triangle.
    pub fn nnz_matrix(&self) -> usize {
        self.a.stats.nnz_matrix + self.b.stats.nnz_matrix
    }

    /// Smaller pivot ratio of the two factors.
    pub fn min_pivot_ratio(&self) -> f64 {
        self.a
            .stats
            .min_pivot_ratio
            .min(self.b.stats.min_pivot_ratio)
    }

    /// Extra memory (MB) of [`factorize`](Self::factorize) in `precision`:
    /// both factors and workspaces (they run at once), M_B's values, and
    /// the dense separator blocks.
    pub fn factor_memory_mb(&self, precision: Precision) -> f64 {
        let ns = self.split.s as f64;
        let value = match precision {
            Precision::Double => 8.0,
            Precision::Mixed => 4.0,
        };
        self.a.factor_memory_mb(precision)
            + self.b.factor_memory_mb(precision)
            + value * self.b_pattern.nnz() as f64 / 1048576.0
            // five ns × ns f64 matrices at the Schur step's peak
            // (SUBSTRUCTURE_MAX_SEPARATOR_DOFS)
            + 5.0 * ns * ns * 8.0 / 1048576.0
    }

    /// Factorizes both halves of K (lower-triangle `values` on the pattern
    /// given to [`analyze`](Self::analyze)) concurrently, then the Schur
    /// complement on the separator. `dof_name` names a reduced DOF of K.
    /// Refused before any allocation when it would not fit in memory.
    pub fn factorize(
        &mut self,
        values: &[f64],
        precision: Precision,
        dof_name: &(dyn Fn(usize) -> String + Sync),
    ) -> Result<(), FlankError> {
        let DomainSplit {
            a: na,
            s: ns,
            b: nb,
        } = self.split;
        let nas = na + ns;
        let Some(pattern) = self.k.as_ref() else {
            return Err(FlankError::Solver(
                "two-domain factorization before the stiffness pattern was adopted".into(),
            ));
        };
        if let Some(k) = values.iter().position(|v| !v.is_finite()) {
            return Err(FlankError::Solver(format!(
                "stiffness entry {k} is not finite"
            )));
        }
        let need = self.factor_memory_mb(precision);
        self.stats.factor_estimate_mb = need;
        let resident = crate::resources::resident_mb();
        self.stats.resident_before_mb = resident;
        crate::resources::check_memory(
            &format!(
                "the two-domain sparse Cholesky factorization ({} + {} + {} DOFs, nnz(L) = {:.3e}, {:?} precision)",
                na,
                ns,
                nb,
                self.nnz_factor(),
                precision
            ),
            need,
            crate::resources::ALTERNATIVES,
        )?;
        for c in [&mut self.a, &mut self.b] {
            c.stats.resident_before_mb = resident;
        }
        let t0 = Instant::now();
        let a_view = LowerCsc {
            n: nas,
            col_ptr: &pattern.col_ptr[..=nas],
            col_nnz: Some(&self.a_col_nnz),
            row_idx: &pattern.row_idx,
        };
        let nnz_b = self.b_pattern.nnz();
        let (mut b64, mut b32) = match precision {
            Precision::Double => (vec![0.0f64; nnz_b], Vec::new()),
            Precision::Mixed => (Vec::new(), vec![0.0f32; nnz_b]),
        };
        walk_b(
            pattern,
            self.split,
            &self.b_pattern.col_ptr,
            |slot, _, k| match precision {
                Precision::Double => b64[slot] = values[k],
                Precision::Mixed => b32[slot] = values[k] as f32,
            },
        );
        if b32.iter().any(|v| !v.is_finite()) {
            return Err(FlankError::Solver(
                "stiffness entries overflow single precision; use --precision double".into(),
            ));
        }
        let b_values = match precision {
            Precision::Double => MatrixValues::F64(&b64, Precision::Double),
            Precision::Mixed => MatrixValues::F32(&b32),
        };
        let name_b = |i: usize| dof_name(if i < nb { nas + i } else { na + i - nb });
        let b_view = self.b_pattern.view();
        let par = self.half_par;
        // factor a half, then T = L_SS L_SSᵀ
        let half = |chol: &mut SparseCholesky,
                    view: LowerCsc<'_>,
                    vals: MatrixValues<'_>,
                    name: &(dyn Fn(usize) -> String + Sync)|
         -> Result<(Mat<f64>, Mat<f64>), FlankError> {
            chol.factorize_view(view, vals, name)?;
            let l = chol.trailing_factor(ns)?;
            // T = L_SS L_SSᵀ, lower triangle only (ns³/3 flops)
            let mut t = Mat::<f64>::zeros(ns, ns);
            triangular::matmul(
                t.as_mut(),
                BlockStructure::TriangularLower,
                Accum::Replace,
                l.as_ref(),
                BlockStructure::TriangularLower,
                l.transpose(),
                BlockStructure::TriangularUpper,
                1.0,
                par,
            );
            Ok((l, t))
        };
        let (ra, rb) = {
            let (ca, cb) = (&mut self.a, &mut self.b);
            rayon::join(
                || half(ca, a_view, MatrixValues::F64(values, precision), dof_name),
                || half(cb, b_view, b_values, &name_b),
            )
        };
        drop((b64, b32));
        let ((la, ta), (lb, tb)) = (ra?, rb?);
        self.stats.factorization_s = t0.elapsed().as_secs_f64();
        self.stats.halves[0].factorization_s = self.a.stats.factorization_s;
        self.stats.halves[1].factorization_s = self.b.stats.factorization_s;
        // S = T_A + T_B − K_SS (lower triangle)
        let t1 = Instant::now();
        let mut s = ta;
        for j in 0..ns {
            for i in j..ns {
                s[(i, j)] += tb[(i, j)];
            }
            let c = na + j;
            for k in a_view.col_range(c) {
                let r = pattern.row_idx[k];
                s[(r - na, j)] -= values[k];
            }
        }
        let schur = s.llt(Side::Lower).map_err(|_| {
            FlankError::Singular(format!(
                "the Schur complement on the {ns} separator DOFs is not positive definite \
                 (a mechanism, or beyond the factor's precision)"
            ))
        })?;
        self.schur = Some(schur);
        self.l_ss = [la, lb];
        self.stats.schur_s = t1.elapsed().as_secs_f64();
        Ok(())
    }

    /// Solves K z = r in place (r in the \[A, S, B\] numbering) by block
    /// elimination, the halves concurrently: with forward substitutions of
    /// M_A's factor on \[r_A; 0\] giving \[w_A; t_A\] (so K_SA K_AA⁻¹ r_A =
    /// L_SA w_A = −L_SS t_A), z_S = S⁻¹ (r_S + L_SS t_A + L'_SS t_B), and
    /// backward substitutions on \[w_A; L_SSᵀ z_S\] giving
    /// z_A = K_AA⁻¹ (r_A − K_AS z_S), and the same for B. In f32 with f32
    /// factors (refine outside), the separator in f64.
    pub fn solve_in_place(&self, r: &mut [f64]) {
        let DomainSplit {
            a: na,
            s: ns,
            b: nb,
        } = self.split;
        let nas = na + ns;
        let schur = self
            .schur
            .as_ref()
            .expect("solve before a successful factorization");
        let mut wa = vec![0.0; nas];
        wa[..na].copy_from_slice(&r[..na]);
        let mut wb = vec![0.0; nb + ns];
        wb[..nb].copy_from_slice(&r[nas..]);
        let par = self.half_par;
        rayon::join(
            || self.a.forward_in_place(&mut wa, par),
            || self.b.forward_in_place(&mut wb, par),
        );
        let mut g = Mat::<f64>::from_fn(ns, 1, |i, _| r[na + i]);
        for (l, t) in [(&self.l_ss[0], &wa[na..]), (&self.l_ss[1], &wb[nb..])] {
            for j in 0..ns {
                let tj = t[j];
                for i in j..ns {
                    g[(i, 0)] += l[(i, j)] * tj;
                }
            }
        }
        schur.solve_in_place(g.as_mut());
        for (l, w) in [
            (&self.l_ss[0], &mut wa[na..]),
            (&self.l_ss[1], &mut wb[nb..]),
        ] {
            for j in 0..ns {
                w[j] = (j..ns).map(|i| l[(i, j)] * g[(i, 0)]).sum();
            }
        }
        rayon::join(
            || self.a.backward_in_place(&mut wa, par),
            || self.b.backward_in_place(&mut wb, par),
        );
        r[..na].copy_from_slice(&wa[..na]);
        for i in 0..ns {
            r[na + i] = g[(i, 0)];
        }
        r[nas..].copy_from_slice(&wb[..nb]);
    }
}

/// Visits M_B's slots in K's \[A, S, B\] numbering (`split`): for each
/// entry of K in B's columns and in S's columns, `f(slot of M_B, row in
/// M_B, slot of K)`, M_B's column starts `col_ptr` (order \[B, S\]: B
/// column i is K's column nas + i, its B rows first, then its rows of S,
/// found in K's S columns); the row is `usize::MAX` for K's B columns once
/// their rows are dropped ([`TwoDomainCholesky::adopt`]).
fn walk_b(
    k: &SparsePattern,
    split: DomainSplit,
    col_ptr: &[usize],
    mut f: impl FnMut(usize, usize, usize),
) {
    let DomainSplit {
        a: na,
        s: ns,
        b: nb,
    } = split;
    let nas = na + ns;
    let mut fill = col_ptr[..nb + ns].to_vec();
    for i in 0..nb {
        let c = nas + i;
        for slot in k.col_ptr[c]..k.col_ptr[c + 1] {
            // K's row, unless its B rows were dropped (adopt)
            let row = k.row_idx.get(slot).map_or(usize::MAX, |&r| r - nas);
            f(fill[i], row, slot);
            fill[i] += 1;
        }
    }
    for c in na..nas {
        let sc = nb + c - na;
        for slot in k.col_ptr[c]..k.col_ptr[c + 1] {
            let r = k.row_idx[slot];
            let (col, row) = if r >= nas {
                (r - nas, sc)
            } else {
                (sc, nb + r - na)
            };
            f(fill[col], row, slot);
            fill[col] += 1;
        }
    }
}

#[cfg(test)]
mod tests;
