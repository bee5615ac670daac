//! The tensor part of the LTCA's compliance F (see [`crate::ltca::model`]):
//! per body, F_ij = n_iᵀ C(i, j) n_j between the candidates' contact cells,
//! C(i, j) = Σ_{a ∈ i} Σ_{c ∈ j} w_ia w_jc C(a, c) from the node blocks of
//! the body's compliance tensor, and with friction the four directional
//! blocks (normal and tangent). The paged path
//! ([`crate::compliance::pages`]) reads only the blocks C(a, c) with c ≤ a
//! on the cells' node union (C is exactly symmetric); the streamed path,
//! the fallback and the reference of the tests, reads the tensor's rows.

use std::sync::Arc;

use crate::compliance::interpolation::FlankGrids;
use crate::compliance::page_order::PAGE;
use crate::compliance::pages::{FactoredPage, TensorPages};
use crate::compliance::ComplianceTensor;
use crate::error::FlankError;
use crate::geometry::vec3::dot;
use crate::ltca::candidate::Candidate;

/// F's tensor part of both bodies, Σ_b n₍b₎ᵢᵀ C_b(i, j) n₍b₎ⱼ (n × n,
/// row-major): the two bodies' [`normal_compliance`] side by side on the
/// thread pool (one parallel section where there were two, one after the
/// other), added in body order from zero as before (the same bits).
pub(crate) fn normal_compliance_pair(
    tensors: &[Arc<ComplianceTensor>; 2],
    grids: &[Arc<FlankGrids>; 2],
    cands: &[Candidate],
) -> Result<Vec<f64>, FlankError> {
    let (f0, f1) = rayon::join(
        || normal_compliance(&tensors[0], &grids[0], cands, 0),
        || normal_compliance(&tensors[1], &grids[1], cands, 1),
    );
    let (f0, f1) = (f0?, f1?);
    let mut f = vec![0.0; f0.len()];
    for part in [f0, f1] {
        for (x, y) in f.iter_mut().zip(part) {
            *x += y;
        }
    }
    Ok(f)
}

/// n₍b₎ᵢᵀ C(i, j) n₍b₎ⱼ of one body for all candidate pairs (n × n,
/// row-major): from the tensor's paged node blocks
/// ([`crate::compliance::pages`], built on first use and kept for the
/// next positions), else as [`normal_compliance_streamed`]; an error when
/// neither applies (pages of another tensor and no dense matrix).
pub(crate) fn normal_compliance(
    t: &ComplianceTensor,
    grids: &FlankGrids,
    cands: &[Candidate],
    b: usize,
) -> Result<Vec<f64>, FlankError> {
    match grids.pages(t) {
        Some(p) => Ok(normal_compliance_paged(
            t,
            p,
            cands,
            b,
            true,
            LowRankUse::WhenCheaper,
        )),
        None if t.has_matrix() => Ok(normal_compliance_streamed(t, cands, b)),
        None => Err(FlankError::Model(format!(
            "the LTCA's compliance of {}: no dense matrix and no compressed pages of this tensor",
            t.meta.body
        ))),
    }
}

/// Candidates per load window of the F kernel (a multiple of the f64
/// lanes of a vector register: 2 with SSE2, 4 with AVX2).
const LANES: usize = 4;

/// The loads q_jc = w_jc n_j that node c of U carries, for LANES
/// consecutive candidates j0 .. j0 + LANES (zero where c is not in cell j),
/// one row per load component τ: a node lies in the cells of a few
/// neighbouring candidates of one line, so one or two windows hold them.
#[derive(Clone, Copy)]
struct Window {
    j0: usize,
    q: [[f64; LANES]; 3],
}

impl Window {
    /// The window with every load multiplied by `s`.
    fn scaled(&self, s: f64) -> Window {
        Window {
            j0: self.j0,
            q: self.q.map(|row| row.map(|x| s * x)),
        }
    }
}

/// row[s·stride + j] += Σ_τ c[3s + τ] q_jτ for the window's candidates j:
/// the displacement components s at one node from the window's loads
/// through the block c = C(a, c) (row-major). Each sum is formed as
/// c₀q₀ + c₁q₁ + c₂q₂, then added (no fused multiply–add: the same bits
/// as the scalar order), and vectorised over the LANES candidates (SSE2,
/// the build's baseline). The AVX2/FMA copy is [`fma::add_window`].
#[inline(always)]
fn add_window(row: &mut [f64], stride: usize, c: &[f64], w: &Window) {
    let c: &[f64; 9] = c.try_into().expect("a 3 × 3 block");
    for s in 0..3 {
        let x: &mut [f64; LANES] = (&mut row[s * stride + w.j0..][..LANES])
            .try_into()
            .expect("LANES values");
        let (c0, c1, c2) = (c[3 * s], c[3 * s + 1], c[3 * s + 2]);
        for l in 0..LANES {
            x[l] += c0 * w.q[0][l] + c1 * w.q[1][l] + c2 * w.q[2][l];
        }
    }
}

/// The rows lo..hi of U of [`normal_compliance_paged`]'s u: for each
/// column node kc in U's order and each row node ka ≥ kc of the part,
/// u(ka) += C(ka, kc) q(kc) (the diagonal block with q halved), each block
/// through `add` ([`add_window`] or [`fma::add_window`]); the column nodes
/// of a page pair read as low-rank factors ([`Sweep::factored`]) all at
/// once through [`add_low_rank`].
#[inline(always)]
fn sweep_part_with(
    sw: &Sweep,
    lo: usize,
    hi: usize,
    add: impl Fn(&mut [f64], usize, &[f64], &Window),
) -> Vec<f64> {
    let stride = sw.stride;
    let mut u = vec![0.0; (hi - lo) * 3 * stride];
    // the part's rows lie on one page (parts are cut by row page)
    let r = sw.page_of[lo];
    let mut y = Vec::new();
    let mut run = 0;
    while run < hi {
        // a run of column nodes on one page pc
        let pc = sw.page_of[run];
        let mut run_end = run + 1;
        while run_end < hi && sw.page_of[run_end] == pc {
            run_end += 1;
        }
        // the candidates the run's loads reach
        let span = candidate_span(&sw.windows[sw.start[run]..sw.start[run_end]]);
        if let Some(f) = sw.factored(r, pc, hi - lo, (run, run_end), span) {
            add_low_rank(&mut u, sw, (lo, hi), (run, run_end), span, f, &mut y);
            run = run_end;
            continue;
        }
        for kc in run..run_end {
            sweep_column(&mut u, sw, lo, hi, kc, &add);
        }
        run = run_end;
    }
    u
}

/// u(ka) += C(ka, kc) q(kc) for the rows ka ≥ kc of the part lo..hi, one
/// column node kc (the diagonal block with q halved).
#[inline(always)]
fn sweep_column(
    u: &mut [f64],
    sw: &Sweep,
    lo: usize,
    hi: usize,
    kc: usize,
    add: &impl Fn(&mut [f64], usize, &[f64], &Window),
) {
    let stride = sw.stride;
    let wins = &sw.windows[sw.start[kc]..sw.start[kc + 1]];
    let (pc, ic) = (sw.page_of[kc], sw.slot[kc]);
    let mut k = lo.max(kc);
    if k == kc && kc < hi {
        // the diagonal block, halved
        let page = &sw.pages.page(sw.t, pc, pc)[ic * PAGE * 9..][..PAGE * 9];
        let row = &mut u[(kc - lo) * 3 * stride..][..3 * stride];
        for w in wins {
            add(row, stride, &page[9 * ic..][..9], &w.scaled(0.5));
        }
        k += 1;
    }
    while k < hi {
        // a run of U on one page
        let r = sw.page_of[k];
        let mut end = k + 1;
        while end < hi && sw.page_of[end] == r {
            end += 1;
        }
        let page = &sw.pages.page(sw.t, r, pc)[ic * PAGE * 9..][..PAGE * 9];
        for ka in k..end {
            let row = &mut u[(ka - lo) * 3 * stride..][..3 * stride];
            let c = &page[9 * sw.slot[ka]..][..9];
            for w in wins {
                add(row, stride, c, w);
            }
        }
        k = end;
    }
}

/// u(a) += B q for the rows a of the part `rows` (one page r) and the
/// column nodes `cols` (one page pc < r), with B = C(r, pc) = U Vᵀ in low
/// rank k ([`FactoredPage`]): first Y = Vᵀ q over the columns' loads
/// (k × the candidates they load), then u(a) += U(a) Y, 3 k (windows +
/// rows × candidate lanes) multiply–adds instead of 9 per block and
/// window (the choice: [`Sweep::factored`]). `jlo..jhi`: the candidates
/// the columns load ([`candidate_span`]); `y` is scratch.
#[inline(always)]
fn add_low_rank(
    u: &mut [f64],
    sw: &Sweep,
    (lo, hi): (usize, usize),
    (c0, c1): (usize, usize),
    (jlo, jhi): (usize, usize),
    f: &FactoredPage,
    y: &mut Vec<f64>,
) {
    let (k, stride) = (f.rank, sw.stride);
    let width = jhi - jlo;
    y.clear();
    y.resize(k * width, 0.0);
    for kc in c0..c1 {
        let v = &f.v[3 * sw.slot[kc] * k..][..3 * k];
        let (v0, v1, v2) = (&v[..k], &v[k..2 * k], &v[2 * k..]);
        for w in &sw.windows[sw.start[kc]..sw.start[kc + 1]] {
            let o = w.j0 - jlo;
            for l in 0..k {
                let yl: &mut [f64; LANES] = (&mut y[l * width + o..][..LANES])
                    .try_into()
                    .expect("LANES values");
                let (a, b, c) = (v0[l], v1[l], v2[l]);
                for lane in 0..LANES {
                    yl[lane] += a * w.q[0][lane] + b * w.q[1][lane] + c * w.q[2][lane];
                }
            }
        }
    }
    for ka in lo..hi {
        let ua = &f.u[3 * sw.slot[ka] * k..][..3 * k];
        for s in 0..3 {
            let row = &mut u[(ka - lo) * 3 * stride + s * stride + jlo..][..width];
            for (l, &c) in ua[s * k..][..k].iter().enumerate() {
                for (x, &yl) in row.iter_mut().zip(&y[l * width..][..width]) {
                    *x += c * yl;
                }
            }
        }
    }
}

/// The candidates jlo..jhi the windows `wins` cover (their lanes).
fn candidate_span(wins: &[Window]) -> (usize, usize) {
    let jlo = wins.iter().map(|w| w.j0).min().unwrap_or(0);
    let jhi = wins.iter().map(|w| w.j0 + LANES).max().unwrap_or(jlo);
    (jlo, jhi)
}

/// [`sweep_part_with`] through the AVX2/FMA kernel where the processor has
/// it (checked at run time: the release build targets baseline x86-64),
/// else through the SSE2 one. `simd` false forces the SSE2 kernel (the
/// tests' bit-exact reference). The choice depends on the machine only,
/// so 1 and N threads still give the same bits.
fn sweep_part(sw: &Sweep, lo: usize, hi: usize, simd: bool) -> Vec<f64> {
    #[cfg(target_arch = "x86_64")]
    if simd && fma::available() {
        // SAFETY: the processor has AVX2 and FMA (checked just above)
        return unsafe { fma::sweep_part(sw, lo, hi) };
    }
    let _ = simd;
    sweep_part_with(sw, lo, hi, add_window)
}

/// F's window kernel with 256-bit fused multiply–adds (`std::arch`, chosen
/// at run time by [`sweep_part`]). A window's 4 candidates fill one
/// register per displacement component, and u += c₀q₀ + c₁q₁ + c₂q₂ becomes
/// three fused multiply–adds into u: fewer instructions per 72-byte block
/// than SSE2's 18 multiplies and 18 adds on 2 lanes. The order over the
/// nodes is the SSE2 kernel's, but within a block c₀q₀, c₁q₁, c₂q₂ go into
/// u one by one, each step rounded once (SSE2 sums them first), so F
/// differs from the SSE2 kernel's by round-off (unit test: ≤ 1e-13 of
/// max|F|).
#[cfg(target_arch = "x86_64")]
mod fma {
    use super::{sweep_part_with, Sweep, Window, LANES};
    use std::arch::x86_64::*;

    /// Whether this processor runs the AVX2/FMA kernel (cached by std).
    pub(super) fn available() -> bool {
        is_x86_feature_detected!("avx2") && is_x86_feature_detected!("fma")
    }

    /// [`super::add_window`] with fused multiply–adds: x ← c₂q₂ + (c₁q₁ +
    /// (c₀q₀ + x)) per component row.
    ///
    /// # Safety
    /// The processor must have AVX2 and FMA.
    #[inline]
    #[target_feature(enable = "avx2,fma")]
    pub(super) unsafe fn add_window(row: &mut [f64], stride: usize, c: &[f64], w: &Window) {
        const _: () = assert!(LANES == 4);
        let c: &[f64; 9] = c.try_into().expect("a 3 × 3 block");
        let q0 = _mm256_loadu_pd(w.q[0].as_ptr());
        let q1 = _mm256_loadu_pd(w.q[1].as_ptr());
        let q2 = _mm256_loadu_pd(w.q[2].as_ptr());
        for s in 0..3 {
            let x = &mut row[s * stride + w.j0..][..LANES];
            let mut v = _mm256_loadu_pd(x.as_ptr());
            v = _mm256_fmadd_pd(_mm256_set1_pd(c[3 * s]), q0, v);
            v = _mm256_fmadd_pd(_mm256_set1_pd(c[3 * s + 1]), q1, v);
            v = _mm256_fmadd_pd(_mm256_set1_pd(c[3 * s + 2]), q2, v);
            _mm256_storeu_pd(x.as_mut_ptr(), v);
        }
    }

    /// [`super::sweep_part_with`] compiled for AVX2/FMA around
    /// [`add_window`].
    ///
    /// # Safety
    /// The processor must have AVX2 and FMA.
    #[target_feature(enable = "avx2,fma")]
    pub(super) unsafe fn sweep_part(sw: &Sweep, lo: usize, hi: usize) -> Vec<f64> {
        sweep_part_with(sw, lo, hi, |row, stride, c, w| {
            // SAFETY: this function runs only where AVX2 and FMA are
            unsafe { add_window(row, stride, c, w) }
        })
    }
}

/// What [`sweep_part`] reads: U's nodes (page, slot) and load windows.
struct Sweep<'a> {
    t: &'a ComplianceTensor,
    pages: &'a TensorPages,
    page_of: Vec<usize>,
    slot: Vec<usize>,
    /// Windows of node k: windows[start[k]..start[k + 1]].
    windows: Vec<Window>,
    start: Vec<usize>,
    /// Length of one component row of u (≥ n + LANES − 1).
    stride: usize,
    /// When the low-rank page pairs are read as their factors.
    low_rank: LowRankUse,
}

/// Whether F reads a compressed tensor's low-rank page pairs as their
/// factors U, Vᵀ ([`add_low_rank`]) or decompressed into node blocks.
#[derive(Clone, Copy, Debug, PartialEq)]
enum LowRankUse {
    /// Decompressed, always (the tests' reference).
    Never,
    /// As factors where that takes fewer multiply–adds (the default).
    WhenCheaper,
    /// As factors wherever the pair is stored in low rank (tests).
    Always,
}

impl Sweep<'_> {
    /// The factors of page pair (r, pc) when the column nodes `c0..c1`
    /// (page pc, loading the candidates `jlo..jhi`) and `rows` nodes of
    /// page r are to be swept through them:
    /// pc < r, the pair stored in low rank k, and (unless
    /// [`LowRankUse::Always`]) 3 k (W + rows · S) < 9 rows · W
    /// multiply–adds of LANES lanes, W the columns' load windows and S the
    /// lane groups of the candidates they load.
    fn factored(
        &self,
        r: usize,
        pc: usize,
        rows: usize,
        (c0, c1): (usize, usize),
        (jlo, jhi): (usize, usize),
    ) -> Option<&FactoredPage> {
        if self.low_rank == LowRankUse::Never || pc >= r {
            return None;
        }
        let f = self.pages.factored(r, pc)?;
        if self.low_rank == LowRankUse::Always {
            return Some(f);
        }
        let lanes = (jhi - jlo).div_ceil(LANES);
        let w = self.start[c1] - self.start[c0];
        (3 * f.rank * (w + rows * lanes) < 9 * rows * w).then_some(f)
    }
}

/// [`normal_compliance`] from the paged blocks, through C's symmetry
/// (C(a, c) = C(c, a)ᵀ, exact: the tensor is mirrored from its lower
/// triangle): with Q the 3|U| × n matrix of the loads q_jc = w_jc n_j on
/// the union U of the cells' nodes (sorted in the paged order) and L, D the
/// blocks of C_UU below and on its diagonal, F = Qᵀ C Q = X + Xᵀ with
/// X = Qᵀ (L + D/2) Q. Only the blocks C(a, c) with c ≤ a in U are read
/// (half of them), node row a by node row: u_j(a) is Σ_{c < a} C(a, c) q_jc
/// plus ½ C(a, a) q_ja, then X_ij = Σ_{a ∈ i} q_ia · u_j(a). The rows are cut
/// into parts by page; every u_j(a) is summed over c in U's order within
/// one part, so the round-off depends neither on the cut nor on the thread
/// count.
///
/// The loads of a node c are held as windows of [`LANES`] consecutive
/// candidates (a node lies in the cells of a few neighbours on one line)
/// and u(a) component-major (u[s][j]), so that a block C(a, c) updates
/// LANES candidates at once in vector registers; the zeros of a window
/// add nothing, and every u_j(a) and X_ij is summed in the same order as
/// the candidate-by-candidate loop it replaced. `simd`: the AVX2/FMA
/// kernel where the processor has it (round-off from the fused steps,
/// ≤ 1e-13 of max|F| by unit test), else the SSE2 one (the same bits as
/// the candidate-by-candidate loop, unit test).
///
/// Pages read from a compressed tensor keep its low-rank page pairs
/// C(r, q) = U Vᵀ as factors ([`crate::compliance::pages::FactoredPage`]):
/// the column nodes of U on page q then add U (Vᵀ q) to the rows on page
/// r ([`add_low_rank`]) where that takes fewer multiply–adds than the
/// node blocks (`low_rank`, [`LowRankUse`]). U (Vᵀ q) and (U Vᵀ) q differ
/// by round-off (unit test: ≤ 1e-13 of max|F|); the summation order still
/// depends on neither the cut nor the thread count.
fn normal_compliance_paged(
    t: &ComplianceTensor,
    pages: &TensorPages,
    cands: &[Candidate],
    b: usize,
    simd: bool,
    low_rank: LowRankUse,
) -> Vec<f64> {
    use rayon::prelude::*;
    let n = cands.len();
    // U in the paged order: (position, node)
    let mut nodes: Vec<(usize, u32)> = cell_nodes(cands, b)
        .into_iter()
        .map(|a| (pages.position(a), a))
        .collect();
    nodes.sort_unstable();
    let nu = nodes.len();
    // node → its index in U
    let mut by_node: Vec<(u32, usize)> = nodes
        .iter()
        .enumerate()
        .map(|(k, &(_, a))| (a, k))
        .collect();
    by_node.sort_unstable();
    let index = |a: u32| {
        by_node[by_node
            .binary_search_by_key(&a, |e| e.0)
            .expect("node of a cell")]
        .1
    };
    // the cells in U's indices: (k, w)
    let cells: Vec<Vec<(usize, f64)>> = cands
        .iter()
        .map(|c| {
            c.loads[b]
                .weights
                .iter()
                .map(|&(a, w)| (index(a), w))
                .collect()
        })
        .collect();
    // the loads per node, by U index: (candidate j, q = w_jc n_j)
    let mut entries: Vec<(usize, usize, [f64; 3])> = Vec::new();
    for (j, cell) in cells.iter().enumerate() {
        let nj = cands[j].normals[b];
        for &(k, w) in cell {
            entries.push((k, j, [w * nj[0], w * nj[1], w * nj[2]]));
        }
    }
    // (node, candidate) pairs are unique: an unstable sort gives the same order
    entries.sort_unstable_by_key(|e| (e.0, e.1));
    // ... gathered into windows of LANES consecutive candidates per node
    let mut windows: Vec<Window> = Vec::with_capacity(entries.len());
    let mut start = vec![0usize; nu + 1];
    for (k, e) in entries.chunk_by(|x, y| x.0 == y.0).map(|e| (e[0].0, e)) {
        let first = windows.len();
        for &(_, j, q) in e {
            let fits = windows[first..]
                .last()
                .is_some_and(|w: &Window| j < w.j0 + LANES);
            if !fits {
                windows.push(Window {
                    j0: j,
                    q: [[0.0; LANES]; 3],
                });
            }
            let w = windows.last_mut().expect("a window");
            for (s, &qs) in q.iter().enumerate() {
                w.q[s][j - w.j0] = qs;
            }
        }
        start[k + 1] = windows.len() - first;
    }
    for k in 0..nu {
        start[k + 1] += start[k];
    }
    let stride = n + LANES - 1;
    let sweep_input = Sweep {
        t,
        pages,
        page_of: nodes.iter().map(|&(p, _)| p / PAGE).collect(),
        slot: nodes.iter().map(|&(p, _)| p % PAGE).collect(),
        windows,
        start,
        stride,
        low_rank,
    };
    // rows cut into parts, one per row page: a column node's blocks with
    // the rows of one page are one stretch of a page pair, read in order
    // (parts that split a page read short stretches of it);
    // every u_j(a) is summed within one part in U's order, so neither the
    // cut nor the thread count changes a bit
    let parts: Vec<(usize, usize)> = {
        let mut out = Vec::new();
        let mut lo = 0;
        for k in 1..=nu {
            if k == nu || sweep_input.page_of[k] != sweep_input.page_of[lo] {
                out.push((lo, k));
                lo = k;
            }
        }
        out
    };
    // u[((a − lo)·3 + s)·stride + j]: component s of u_j at U[a]
    let blocks: Vec<Vec<f64>> = parts
        .par_iter()
        .map(|&(lo, hi)| sweep_part(&sweep_input, lo, hi, simd))
        .collect();
    let row = |k: usize| -> &[f64] {
        let p = parts.partition_point(|&(_, hi)| hi <= k);
        let (lo, _) = parts[p];
        &blocks[p][(k - lo) * 3 * stride..][..3 * stride]
    };
    // X_ij = Σ_{a ∈ i} w_ia n_i · u_j(a), row i of X in x[i n ..]
    let x: Vec<Vec<f64>> = (0..n)
        .into_par_iter()
        .map(|i| {
            let ni = cands[i].normals[b];
            let mut xi = vec![0.0; n];
            for &(k, w) in &cells[i] {
                let m = [w * ni[0], w * ni[1], w * ni[2]];
                let u = row(k);
                let (u0, u1, u2) = (&u[..n], &u[stride..][..n], &u[2 * stride..][..n]);
                for (j, xij) in xi.iter_mut().enumerate() {
                    *xij += m[0] * u0[j] + m[1] * u1[j] + m[2] * u2[j];
                }
            }
            xi
        })
        .collect();
    // F = X + Xᵀ: exactly symmetric
    let mut f = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..n {
            f[i * n + j] = x[i][j] + x[j][i];
        }
    }
    f
}

/// n₍b₎ᵢᵀ C(i, j) n₍b₎ⱼ as computed before [`normal_compliance`] (kept to
/// check it): for each j the displacement u_j = C (Σ_c w_c n_j e_c) is
/// formed on the union U of the cells' nodes, reading C by rows of the
/// loaded nodes c (C is symmetric) so that each row is streamed over the
/// sorted U; then F_ij = Σ_{a ∈ i} w_a n_iᵀ u_j(a).
fn normal_compliance_streamed(t: &ComplianceTensor, cands: &[Candidate], b: usize) -> Vec<f64> {
    use rayon::prelude::*;
    let n = cands.len();
    let dim = t.dim();
    let nodes = cell_nodes(cands, b);
    let index = |a: u32| nodes.binary_search(&a).expect("node of a cell");
    let columns: Vec<Vec<f64>> = (0..n)
        .into_par_iter()
        .map(|j| {
            let nj = cands[j].normals[b];
            let mut u = vec![0.0; 3 * nodes.len()];
            for &(c, w) in &cands[j].loads[b].weights {
                for (s, &ns) in nj.iter().enumerate() {
                    let f = w * ns;
                    if f == 0.0 {
                        continue;
                    }
                    let row = &t.matrix[(3 * c as usize + s) * dim..][..dim];
                    for (k, &a) in nodes.iter().enumerate() {
                        let x = &row[3 * a as usize..3 * a as usize + 3];
                        u[3 * k] += f * x[0];
                        u[3 * k + 1] += f * x[1];
                        u[3 * k + 2] += f * x[2];
                    }
                }
            }
            // F_ij for all i
            (0..n)
                .map(|i| {
                    let ni = cands[i].normals[b];
                    cands[i].loads[b]
                        .weights
                        .iter()
                        .map(|&(a, w)| {
                            let k = index(a);
                            w * (ni[0] * u[3 * k] + ni[1] * u[3 * k + 1] + ni[2] * u[3 * k + 2])
                        })
                        .sum::<f64>()
                })
                .collect()
        })
        .collect();
    // column j holds F_ij; symmetrise the round-off
    let mut f = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..n {
            f[i * n + j] = 0.5 * (columns[j][i] + columns[i][j]);
        }
    }
    f
}

/// The four directional blocks [C_nn, C_nt, C_tn, C_tt] of one body for
/// all candidate pairs (n × n, row-major; seed 001's c^{kl}_{ab} =
/// a_kᵀ C^{kl} b_l with the candidates' normals and tangents in the body's
/// own frame): per column j the displacements under the cell load along
/// n_j and along t_j, read back with every cell's weights along n_i and
/// t_i (as [`normal_compliance`], two load directions). C_nn and C_tt are
/// symmetrised and C_tn set to C_ntᵀ (reciprocity; the round-off of the
/// column-wise products is all that differs).
pub(crate) fn directional_compliance(
    t: &ComplianceTensor,
    cands: &[Candidate],
    b: usize,
) -> [Vec<f64>; 4] {
    use rayon::prelude::*;
    let n = cands.len();
    let dim = t.dim();
    let nodes = cell_nodes(cands, b);
    let index = |a: u32| nodes.binary_search(&a).expect("node of a cell");
    // columns[j] = [(n_i·u(n_j), t_i·u(n_j), n_i·u(t_j), t_i·u(t_j)) for all i]
    let columns: Vec<Vec<[f64; 4]>> = (0..n)
        .into_par_iter()
        .map(|j| {
            let dirs = [cands[j].normals[b], cands[j].tangents[b]];
            let mut u = [vec![0.0; 3 * nodes.len()], vec![0.0; 3 * nodes.len()]];
            for &(c, w) in &cands[j].loads[b].weights {
                for s in 0..3 {
                    let f = [w * dirs[0][s], w * dirs[1][s]];
                    if f == [0.0, 0.0] {
                        continue;
                    }
                    let row = &t.matrix[(3 * c as usize + s) * dim..][..dim];
                    for (k, &a) in nodes.iter().enumerate() {
                        let x = &row[3 * a as usize..3 * a as usize + 3];
                        for d in 0..2 {
                            u[d][3 * k] += f[d] * x[0];
                            u[d][3 * k + 1] += f[d] * x[1];
                            u[d][3 * k + 2] += f[d] * x[2];
                        }
                    }
                }
            }
            (0..n)
                .map(|i| {
                    let (ni, ti) = (cands[i].normals[b], cands[i].tangents[b]);
                    let mut out = [0.0; 4];
                    for &(a, w) in &cands[i].loads[b].weights {
                        let k = index(a);
                        let un = [u[0][3 * k], u[0][3 * k + 1], u[0][3 * k + 2]];
                        let ut = [u[1][3 * k], u[1][3 * k + 1], u[1][3 * k + 2]];
                        out[0] += w * dot(ni, un);
                        out[1] += w * dot(ni, ut);
                        out[2] += w * dot(ti, un);
                        out[3] += w * dot(ti, ut);
                    }
                    out
                })
                .collect()
        })
        .collect();
    let mut blocks = [
        vec![0.0; n * n],
        vec![0.0; n * n],
        vec![0.0; n * n],
        vec![0.0; n * n],
    ];
    for i in 0..n {
        for j in 0..n {
            // columns[j][i] = [nn_ij, nt_ij, tn_ij, tt_ij]
            let (a, bt) = (columns[j][i], columns[i][j]);
            blocks[0][i * n + j] = 0.5 * (a[0] + bt[0]);
            blocks[3][i * n + j] = 0.5 * (a[3] + bt[3]);
            // nt_ij and tn_ji are the same entry by reciprocity
            let nt = 0.5 * (a[1] + bt[2]);
            blocks[1][i * n + j] = nt;
            blocks[2][j * n + i] = nt;
        }
    }
    blocks
}

/// The sorted union of the flank nodes that body `b`'s cells load.
pub(crate) fn cell_nodes(cands: &[Candidate], b: usize) -> Vec<u32> {
    let mut nodes: Vec<u32> = cands
        .iter()
        .flat_map(|c| c.loads[b].weights.iter().map(|&(a, _)| a))
        .collect();
    nodes.sort_unstable();
    nodes.dedup();
    nodes
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Largest |a_i − b_i|.
    fn max_abs_diff(a: &[f64], b: &[f64]) -> f64 {
        a.iter()
            .zip(b)
            .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
    }

    /// F (n × n, row-major) equals its transpose to the bit.
    fn assert_symmetric(f: &[f64], n: usize) {
        for i in 0..n {
            for j in 0..n {
                assert_eq!(f[i * n + j], f[j * n + i], "F({i}, {j})");
            }
        }
    }

    /// Whether F runs the AVX2/FMA kernel on this processor.
    fn fma_available() -> bool {
        #[cfg(target_arch = "x86_64")]
        return fma::available();
        #[cfg(not(target_arch = "x86_64"))]
        false
    }

    /// [`normal_compliance_paged`] as it was before the candidate windows
    /// (kept to check that the window kernel gives the same bits), through C's symmetry
    /// (C(a, c) = C(c, a)ᵀ, exact: the tensor is mirrored from its lower
    /// triangle): with Q the 3|U| × n matrix of the loads q_jc = w_jc n_j on
    /// the union U of the cells' nodes (sorted in the paged order) and L, D the
    /// blocks of C_UU below and on its diagonal, F = Qᵀ C Q = X + Xᵀ with
    /// X = Qᵀ (L + D/2) Q. Only the blocks C(a, c) with c ≤ a in U are read
    /// (half of them), node row a by node row: u_j(a) is Σ_{c < a} C(a, c) q_jc
    /// plus ½ C(a, a) q_ja, then X_ij = Σ_{a ∈ i} q_ia · u_j(a). The rows are cut
    /// into parts of equal work; every u_j(a) is summed over c in U's order
    /// within one part, so the round-off does not depend on the thread count.
    fn normal_compliance_paged_rowwise(
        t: &ComplianceTensor,
        pages: &TensorPages,
        cands: &[Candidate],
        b: usize,
    ) -> Vec<f64> {
        use rayon::prelude::*;
        let n = cands.len();
        // U in the paged order: (position, node)
        let mut nodes: Vec<(usize, u32)> = cell_nodes(cands, b)
            .into_iter()
            .map(|a| (pages.position(a), a))
            .collect();
        nodes.sort_unstable();
        let nu = nodes.len();
        // node → its index in U
        let mut by_node: Vec<(u32, usize)> = nodes
            .iter()
            .enumerate()
            .map(|(k, &(_, a))| (a, k))
            .collect();
        by_node.sort_unstable();
        let index = |a: u32| {
            by_node[by_node
                .binary_search_by_key(&a, |e| e.0)
                .expect("node of a cell")]
            .1
        };
        // the cells in U's indices: (k, w)
        let cells: Vec<Vec<(usize, f64)>> = cands
            .iter()
            .map(|c| {
                c.loads[b]
                    .weights
                    .iter()
                    .map(|&(a, w)| (index(a), w))
                    .collect()
            })
            .collect();
        // the loads per node, by U index: (candidate j, q = w_jc n_j)
        let mut entries: Vec<(usize, usize, [f64; 3])> = Vec::new();
        for (j, cell) in cells.iter().enumerate() {
            let nj = cands[j].normals[b];
            for &(k, w) in cell {
                entries.push((k, j, [w * nj[0], w * nj[1], w * nj[2]]));
            }
        }
        entries.sort_by_key(|e| (e.0, e.1));
        let mut start = vec![0usize; nu + 1];
        for e in &entries {
            start[e.0 + 1] += 1;
        }
        for k in 0..nu {
            start[k + 1] += start[k];
        }
        // page and slot of each node of U
        let page_of: Vec<usize> = nodes.iter().map(|&(p, _)| p / PAGE).collect();
        let slot: Vec<usize> = nodes.iter().map(|&(p, _)| p % PAGE).collect();
        // rows cut into parts of about equal work (row a reads a + 1 blocks)
        let parts: Vec<(usize, usize)> = {
            const PARTS: usize = 8;
            let total = nu * (nu + 1) / 2;
            let mut out = Vec::with_capacity(PARTS);
            let (mut lo, mut acc) = (0, 0);
            for k in 0..nu {
                acc += k + 1;
                if acc * PARTS >= total * (out.len() + 1) || k + 1 == nu {
                    out.push((lo, k + 1));
                    lo = k + 1;
                }
            }
            out
        };
        // row a of u += C(a, c) q_jc for the loads (j, q_jc) at c
        fn add(row: &mut [f64], c: &[f64], loads: impl Iterator<Item = (usize, [f64; 3])>) {
            for (j, q) in loads {
                let x = &mut row[3 * j..3 * j + 3];
                x[0] += c[0] * q[0] + c[1] * q[1] + c[2] * q[2];
                x[1] += c[3] * q[0] + c[4] * q[1] + c[5] * q[2];
                x[2] += c[6] * q[0] + c[7] * q[1] + c[8] * q[2];
            }
        }
        // u[(a n + j) 3 + s]: component s of u_j at U[a]
        let blocks: Vec<Vec<f64>> = parts
            .par_iter()
            .map(|&(lo, hi)| {
                let mut u = vec![0.0; (hi - lo) * n * 3];
                for kc in 0..hi {
                    let loads = &entries[start[kc]..start[kc + 1]];
                    let (pc, ic) = (page_of[kc], slot[kc]);
                    let mut k = lo.max(kc);
                    if k == kc && kc < hi {
                        // the diagonal block, halved
                        let page = &pages.page(t, pc, pc)[ic * PAGE * 9..][..PAGE * 9];
                        let half: Vec<(usize, [f64; 3])> = loads
                            .iter()
                            .map(|&(_, j, q)| (j, [0.5 * q[0], 0.5 * q[1], 0.5 * q[2]]))
                            .collect();
                        let row = &mut u[(kc - lo) * n * 3..][..n * 3];
                        add(row, &page[9 * ic..][..9], half.iter().copied());
                        k += 1;
                    }
                    while k < hi {
                        // a run of U on one page
                        let r = page_of[k];
                        let mut end = k + 1;
                        while end < hi && page_of[end] == r {
                            end += 1;
                        }
                        let page = &pages.page(t, r, pc)[ic * PAGE * 9..][..PAGE * 9];
                        for ka in k..end {
                            let row = &mut u[(ka - lo) * n * 3..][..n * 3];
                            let c = &page[9 * slot[ka]..][..9];
                            add(row, c, loads.iter().map(|&(_, j, q)| (j, q)));
                        }
                        k = end;
                    }
                }
                u
            })
            .collect();
        let row = |k: usize| -> &[f64] {
            let p = parts.partition_point(|&(_, hi)| hi <= k);
            let (lo, _) = parts[p];
            &blocks[p][(k - lo) * n * 3..][..n * 3]
        };
        // X_ij = Σ_{a ∈ i} w_ia n_i · u_j(a), row i of X in x[i n ..]
        let x: Vec<Vec<f64>> = (0..n)
            .into_par_iter()
            .map(|i| {
                let ni = cands[i].normals[b];
                let mut xi = vec![0.0; n];
                for &(k, w) in &cells[i] {
                    let m = [w * ni[0], w * ni[1], w * ni[2]];
                    for (xij, uj) in xi.iter_mut().zip(row(k).chunks_exact(3)) {
                        *xij += m[0] * uj[0] + m[1] * uj[1] + m[2] * uj[2];
                    }
                }
                xi
            })
            .collect();
        // F = X + Xᵀ: exactly symmetric
        let mut f = vec![0.0; n * n];
        for i in 0..n {
            for j in 0..n {
                f[i * n + j] = x[i][j] + x[j][i];
            }
        }
        f
    }
    use crate::compliance::body::BodyMeshOptions;
    use crate::ltca::cycle::{LtcaCycle, LtcaOptions};
    use std::path::{Path, PathBuf};
    use std::time::Instant;

    /// Seed 002's LTCA cycle on bodies of flank size `flank`, base size
    /// `base` (mm), meshed under `work`, K = 20.
    fn seed002_cycle(flank: f64, base: f64, work: &Path, cache: Option<PathBuf>) -> LtcaCycle {
        let scene = crate::scene::read_scene(Path::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/papers/seed002-spur/scene.toml"
        )))
        .unwrap();
        let o = LtcaOptions {
            out: work.join("bodies"),
            mesh: BodyMeshOptions {
                flank_size: Some(flank),
                base_size: Some(base),
                ..Default::default()
            },
            points_per_line: Some(20),
            cache,
            quiet: true,
            ..Default::default()
        };
        LtcaCycle::new(&scene, &o).unwrap()
    }

    /// A tip-corner candidate loads its edge body on the tip edge itself
    /// (the top row of flank nodes, as FE contact's slave edge nodes), not
    /// on a cell centred on the edge whose inner half moves the load down
    /// the tooth; the mating body keeps an ordinary flank cell.
    #[test]
    fn tip_corner_cells_load_the_tip_edge() {
        let work =
            std::env::temp_dir().join(format!("flank_ltca_edge_cell_{}", std::process::id()));
        let cycle = seed002_cycle(1.5, 3.0, &work, None);
        let (a, e) = cycle.line_pair().unwrap().engagement(cycle.pair.middle());
        let pitch = cycle.pair.pinion().angular_pitch();
        let mut corners = [0usize; 2];
        // approach and recess beyond the kinematic ends: both tip corners
        for roll in (0..=8).flat_map(|i| {
            let d = 0.06 * pitch * i as f64 / 8.0;
            [a - d, e + d]
        }) {
            let position = cycle.line_tca().unwrap().position(roll).unwrap();
            let frames = cycle.line_tca().unwrap().frames(roll);
            let (built, _) = cycle
                .bodies
                .candidates(&position, &frames, cycle.torque, &cycle.settings)
                .unwrap();
            for (c, _) in built.into_iter().flatten() {
                let edge = match position.lines[c.line].kind {
                    crate::tca::LineKind::PinionTipCorner => 0,
                    crate::tca::LineKind::GearTipCorner => 1,
                    _ => continue,
                };
                corners[edge] += 1;
                let flank = &cycle.bodies.tensors[edge].flank;
                let set = flank.set_of[c.loads[edge].weights[0].0 as usize];
                // spur: the tip is one u for the whole set
                let u_tip = (0..flank.len())
                    .filter(|&a| flank.set_of[a] == set)
                    .map(|a| flank.uv[a][0])
                    .fold(f64::NEG_INFINITY, f64::max);
                // the next node row below the tip (a midside row)
                let row = (0..flank.len())
                    .filter(|&a| flank.set_of[a] == set)
                    .map(|a| u_tip - flank.uv[a][0])
                    .filter(|&d| d > 1e-12)
                    .fold(f64::INFINITY, f64::min);
                // the load's centroid in u: on the edge to 1 % of a row (a
                // cell centred on the edge puts it ≈ c/3 below, over half
                // a row)
                let below: f64 = c.loads[edge]
                    .weights
                    .iter()
                    .map(|&(node, w)| w * (u_tip - flank.uv[node as usize][0]))
                    .sum();
                assert!(
                    below.abs() <= 0.01 * row,
                    "roll {:.4}°: edge body {edge}: load centroid {below} below the tip (node rows {row} apart)",
                    roll.to_degrees()
                );
                // the mating cell spreads over more than one node row
                let mate = &cycle.bodies.tensors[1 - edge].flank;
                let rows: Vec<f64> = c.loads[1 - edge]
                    .weights
                    .iter()
                    .map(|&(node, _)| mate.uv[node as usize][0])
                    .collect();
                let spread = rows.iter().fold(f64::NEG_INFINITY, |m, &x| m.max(x))
                    - rows.iter().fold(f64::INFINITY, |m, &x| m.min(x));
                assert!(spread > 0.0, "mating cell on one node row");
            }
        }
        assert!(
            corners[0] > 0 && corners[1] > 0,
            "no tip-corner candidates of both bodies found: {corners:?}"
        );
        let _ = std::fs::remove_dir_all(work);
    }

    /// Largest |F_fast − F_streamed| over the largest |F_streamed| of both
    /// bodies at the seed 002 positions in double and single contact.
    fn fast_against_streamed(flank: f64, base: f64, work: PathBuf, cache: Option<PathBuf>) {
        let cycle = seed002_cycle(flank, base, &work, cache);
        let (a, e) = cycle.line_pair().unwrap().engagement(cycle.pair.middle());
        let (l, h) = cycle.line_pair().unwrap().single_contact();
        let mut rolls = vec![0.5 * (a + l), 0.5 * (l + h)];
        // and a few more across the pitch
        let pitch = cycle.pair.pinion().angular_pitch();
        rolls.extend((0..5).map(|i| 0.5 * (a + e) - 0.5 * pitch + pitch * i as f64 / 5.0));
        let mut sizes = Vec::new();
        let mut worst_fused: f64 = 0.0;
        // the same tensors compressed (ε = 1e-6), their pages read with
        // the low-rank pairs decompressed, as factors where cheaper, and
        // as factors always
        let compressed: Vec<TensorPages> = (0..2)
            .map(|b| {
                let t = &cycle.bodies.tensors[b];
                let blr = crate::compliance::compressed::BlrTensor::from_dense(
                    t,
                    &crate::compliance::compressed::BlrOptions::default(),
                )
                .unwrap();
                assert!(blr.stats.low_rank_blocks > 0);
                TensorPages::compressed(t, Arc::new(blr)).unwrap()
            })
            .collect();
        let mut worst_factored: f64 = 0.0;
        for roll in rolls {
            let position = cycle.line_tca().unwrap().position(roll).unwrap();
            let frames = cycle.line_tca().unwrap().frames(roll);
            let (built, _) = cycle
                .bodies
                .candidates(&position, &frames, cycle.torque, &cycle.settings)
                .unwrap();
            let cands: Vec<Candidate> = built.into_iter().flatten().map(|(c, _)| c).collect();
            for b in 0..2 {
                let t = &cycle.bodies.tensors[b];
                let fast = normal_compliance(t, &cycle.bodies.grids[b], &cands, b).unwrap();
                assert!(cycle.bodies.grids[b].pages(t).is_some());
                // the same bits on 1 and 3 threads (fixed summation order)
                for threads in [1, 3] {
                    let pool = rayon::ThreadPoolBuilder::new()
                        .num_threads(threads)
                        .build()
                        .unwrap();
                    let again = pool.install(|| {
                        normal_compliance(t, &cycle.bodies.grids[b], &cands, b).unwrap()
                    });
                    assert_eq!(again, fast, "{threads} threads");
                }
                // the SSE2 window kernel gives the bits of the row-wise
                // one; the AVX2/FMA kernel (where the processor has it)
                // differs by the fused steps' round-off only
                let pages = cycle.bodies.grids[b].pages(t).unwrap();
                let rowwise = normal_compliance_paged_rowwise(t, pages, &cands, b);
                let sse2 = normal_compliance_paged(t, pages, &cands, b, false, LowRankUse::Never);
                assert_eq!(sse2, rowwise, "SSE2 window against row-wise kernel");
                let top = rowwise.iter().fold(0.0f64, |m, x| m.max(x.abs()));
                let fused = max_abs_diff(&fast, &rowwise);
                assert!(
                    fused <= 1e-13 * top,
                    "AVX2/FMA against SSE2 window kernel: {fused:e} of {top:e}"
                );
                worst_fused = worst_fused.max(fused / top);
                let slow = normal_compliance_streamed(t, &cands, b);
                let scale = slow.iter().fold(0.0f64, |m, x| m.max(x.abs()));
                let diff = max_abs_diff(&fast, &slow);
                assert!(scale > 0.0);
                assert!(
                    diff <= 1e-12 * scale,
                    "roll {:.4}°, body {b}: |ΔF| {diff:e} of {scale:e}",
                    roll.to_degrees()
                );
                // compressed pages: the factors give the decompressed
                // blocks' F to round-off, which is within ε of the dense F
                let cp = &compressed[b];
                let decompressed =
                    normal_compliance_paged(t, cp, &cands, b, true, LowRankUse::Never);
                for mode in [LowRankUse::WhenCheaper, LowRankUse::Always] {
                    let f = normal_compliance_paged(t, cp, &cands, b, true, mode);
                    let d = max_abs_diff(&f, &decompressed);
                    assert!(
                        d <= 1e-13 * top,
                        "{mode:?} against decompressed: {d:e} of {top:e}"
                    );
                    worst_factored = worst_factored.max(d / top);
                    assert_symmetric(&f, cands.len());
                }
                let e = max_abs_diff(&decompressed, &rowwise);
                assert!(
                    e <= 1e-5 * top,
                    "compressed against dense: {e:e} of {top:e}"
                );
                // exactly symmetric
                assert_symmetric(&fast, cands.len());
            }
            sizes.push((cands.len(), cell_nodes(&cands, 0).len()));
            // a tensor that is not the pages' one falls back to the streamed F
            let other = &cycle.bodies.tensors[1];
            assert!(cycle.bodies.grids[0].pages(other).is_none());
            let fallback = normal_compliance(other, &cycle.bodies.grids[0], &cands, 1).unwrap();
            assert_eq!(fallback, normal_compliance_streamed(other, &cands, 1));
        }
        // the factors were read (Always takes every low-rank pair)
        assert!(compressed.iter().any(|p| p.factored_bytes() > 0));
        eprintln!(
            "compressed pages: factored F against decompressed, largest |ΔF| {worst_factored:.1e} \
             of max|F|"
        );
        eprintln!(
            "candidates, pinion cell nodes per position: {sizes:?}; pages built {} + {} MB; \
             AVX2/FMA kernel {} (largest |ΔF| against SSE2 {worst_fused:.1e} of max|F|)",
            cycle.bodies.grids[0].page_bytes() / 1_000_000,
            cycle.bodies.grids[1].page_bytes() / 1_000_000,
            if cfg!(target_arch = "x86_64") && fma_available() {
                "used"
            } else {
                "not available"
            }
        );
    }

    #[test]
    fn node_by_node_compliance_matches_the_streamed_one() {
        let work = std::env::temp_dir().join(format!("flank_ltca_fast_f_{}", std::process::id()));
        fast_against_streamed(1.5, 3.0, work.clone(), None);
        let _ = std::fs::remove_dir_all(work);
    }

    /// The same at the benchmark's tensors (flank 0.475 mm, base 1 mm;
    /// `cargo bench --bench ltca` computes and caches them in
    /// target/ltca-bench/cache, about 3 min): `--ignored`.
    #[test]
    #[ignore]
    fn node_by_node_compliance_matches_the_streamed_one_at_the_bench_mesh() {
        let work = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/ltca-bench");
        fast_against_streamed(0.475, 1.0, work.clone(), Some(work.join("cache")));
    }

    /// Wall time of the two orders of F's tensor part on the benchmark's
    /// tensors, alternated in one process (medians of 15 rounds of 10
    /// calls per body and position): `--ignored --nocapture`.
    #[test]
    #[ignore]
    fn time_node_by_node_against_streamed() {
        let work = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/ltca-bench");
        let cycle = seed002_cycle(0.475, 1.0, &work, Some(work.join("cache")));
        let (a, _) = cycle.line_pair().unwrap().engagement(cycle.pair.middle());
        let (l, h) = cycle.line_pair().unwrap().single_contact();
        for (name, roll) in [("double", 0.5 * (a + l)), ("single", 0.5 * (l + h))] {
            let position = cycle.line_tca().unwrap().position(roll).unwrap();
            let frames = cycle.line_tca().unwrap().frames(roll);
            let (built, _) = cycle
                .bodies
                .candidates(&position, &frames, cycle.torque, &cycle.settings)
                .unwrap();
            let cands: Vec<Candidate> = built.into_iter().flatten().map(|(c, _)| c).collect();
            // window kernel (AVX2/FMA where available), SSE2 window
            // kernel, row-wise paged kernel, streamed
            let names = ["window", "SSE2 window", "row-wise", "streamed"];
            let mut times = [const { Vec::new() }; 4];
            for _ in 0..15 {
                for (m, times) in times.iter_mut().enumerate() {
                    let t0 = Instant::now();
                    for _ in 0..10 {
                        for b in 0..2 {
                            let t = &cycle.bodies.tensors[b];
                            let pages = cycle.bodies.grids[b].pages(t).unwrap();
                            std::hint::black_box(match m {
                                0 => {
                                    normal_compliance(t, &cycle.bodies.grids[b], &cands, b).unwrap()
                                }
                                1 => normal_compliance_paged(
                                    t,
                                    pages,
                                    &cands,
                                    b,
                                    false,
                                    LowRankUse::Never,
                                ),
                                2 => normal_compliance_paged_rowwise(t, pages, &cands, b),
                                _ => normal_compliance_streamed(t, &cands, b),
                            });
                        }
                    }
                    times.push(t0.elapsed().as_secs_f64() / 10.0);
                }
            }
            let median = |v: &mut Vec<f64>| {
                v.sort_by(f64::total_cmp);
                v[v.len() / 2]
            };
            let m: Vec<f64> = times.iter_mut().map(median).collect();
            eprintln!(
                "{name} contact, {} candidates, F (both bodies), medians: {}",
                cands.len(),
                names
                    .iter()
                    .zip(&m)
                    .map(|(k, t)| format!("{k} {:.3} ms ({:.2} of row-wise)", 1e3 * t, t / m[2]))
                    .collect::<Vec<_>>()
                    .join(", ")
            );
        }
    }
}
