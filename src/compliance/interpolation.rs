//! Compliance at any flank point and over contact cells, interpolated with
//! the flank faces' own shape functions.
//!
//! A flank point p = (u, v) of one flank set lies on a flank face; inverting
//! the face's isoparametric map in the surface parameters,
//! (u, v) = Σ_a N_a(ξ, η) (u_a, v_a), gives its reference coordinates and the
//! face shape functions N_a(p) (quad8 or tri6). A point force F at p is
//! work-equivalent to the nodal forces N_a(p) F, and the displacement at p
//! is read back as Σ_a N_a(p) u_a, so the compliance between two points is
//!
//! ```text
//! C^{pq} = Σ_a Σ_b N_a(p) N_b(q) C^{ab}        (displacement at p, unit force at q)
//! ```
//!
//! symmetric in the same sense as the nodal tensors (C^{pq} = (C^{qp})ᵀ),
//! and equal to C^{ab} at the nodes (N_a(x_b) = δ_ab). This is seed 001's
//! "bivariate interpolation in the surface parametric space", done with the
//! finite element's own interpolation so that loads and displacements stay
//! consistent with the FE model (seed 003 uses bilinear weights).
//!
//! **Contact cells.** A load spread uniformly over a cell (a rectangle or an
//! ellipse in (u, v) around the point) is the average of point loads over
//! the cell: its nodal weights are W_a = ∫ N_a dA / ∫ dA, integrated with a
//! Gauss rule in (u, v) weighted by the physical area density
//! dA/(du dv) = |x_ξ × x_η| / |det ∂(u, v)/∂(ξ, η)|; the displacement of the
//! cell is read back with the same weights. Sample points outside the
//! meshed flank are dropped ([`SurfaceLoad::coverage`] < 1 says so). Cells
//! make the compliance of a finite contact area mesh-independent as the
//! mesh is refined (a point load on the FE surface is not: its local
//! displacement grows without bound, DESIGN.md "local contact deformation").
//!
//! **Directional compliances** (seed 001), for unit vectors n, t at the
//! points k and l: c_nn = n_kᵀC^{kl}n_l, c_tt = t_kᵀC^{kl}t_l,
//! c_nt = n_kᵀC^{kl}t_l, c_tn = t_kᵀC^{kl}n_l (c_nt ≠ c_tn in general): the
//! displacement along the first direction at k from a unit force along the
//! second at l.

use crate::fem::element::QUAD8_NODES;
use std::sync::{Arc, OnceLock};

use crate::compliance::flank::{cross, face_shape, norm, FlankFace, FlankNodes};
use crate::compliance::pages::TensorPages;
use crate::compliance::ComplianceTensor;
use crate::error::FlankError;

/// Nodal weights of a point or cell load on the flank (Σ weights = 1).
#[derive(Clone, Debug, PartialEq)]
pub struct SurfaceLoad {
    /// (flank node index into the tensor, weight).
    pub weights: Vec<(u32, f64)>,
    /// Fraction of the cell (in (u, v)) that lies on the meshed flank (1 for points).
    pub coverage: f64,
}

/// A contact cell around a point, half-widths in the flank parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CellShape {
    /// [u − hu, u + hu] × [v − hv, v + hv].
    Rectangle { hu: f64, hv: f64 },
    /// ((u' − u)/au)² + ((v' − v)/av)² ≤ 1.
    Ellipse { au: f64, av: f64 },
}

/// The four directional compliances between two points (mm/N).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct Directional {
    pub nn: f64,
    pub tt: f64,
    pub nt: f64,
    pub tn: f64,
}

fn dot3(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn mat_vec(c: &[[f64; 3]; 3], x: [f64; 3]) -> [f64; 3] {
    [dot3(c[0], x), dot3(c[1], x), dot3(c[2], x)]
}

/// Seed 001's directional compliances of the tensor `c` = C^{kl} for the
/// unit normal and tangent (n_k, t_k) at k and (n_l, t_l) at l.
pub fn directional(
    c: &[[f64; 3]; 3],
    n_k: [f64; 3],
    t_k: [f64; 3],
    n_l: [f64; 3],
    t_l: [f64; 3],
) -> Directional {
    let cn = mat_vec(c, n_l);
    let ct = mat_vec(c, t_l);
    Directional {
        nn: dot3(n_k, cn),
        tt: dot3(t_k, ct),
        nt: dot3(n_k, ct),
        tn: dot3(t_k, cn),
    }
}

/// Gauss–Legendre points and weights on [−1, 1] (Newton on P_n); the
/// rules up to 8 points are computed once and then copied.
pub fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    match gauss_legendre_cached(n) {
        Some(r) => r.to_vec(),
        None => gauss_legendre_rule(n),
    }
}

/// The rule of [`gauss_legendre`] without a copy, for n ≤ 8 (the same
/// values; `None` above).
pub fn gauss_legendre_cached(n: usize) -> Option<&'static [(f64, f64)]> {
    static RULES: std::sync::OnceLock<Vec<Vec<(f64, f64)>>> = std::sync::OnceLock::new();
    (n <= 8).then(|| RULES.get_or_init(|| (0..=8).map(gauss_legendre_rule).collect())[n].as_slice())
}

/// The rule of [`gauss_legendre`], borrowed for n ≤ 8 and computed above.
pub fn gauss_legendre_rule_of(n: usize) -> std::borrow::Cow<'static, [(f64, f64)]> {
    match gauss_legendre_cached(n) {
        Some(r) => std::borrow::Cow::Borrowed(r),
        None => std::borrow::Cow::Owned(gauss_legendre_rule(n)),
    }
}

fn gauss_legendre_rule(n: usize) -> Vec<(f64, f64)> {
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            let (mut p0, mut p1) = (1.0, x);
            for k in 2..=n {
                let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                p0 = p1;
                p1 = p2;
            }
            let p = if n == 0 { 1.0 } else { p1 };
            let pm1 = if n == 0 { 0.0 } else { p0 };
            dp = n as f64 * (x * p - pm1) / (x * x - 1.0);
            let dx = p / dp;
            x -= dx;
            if dx.abs() < 1e-16 {
                break;
            }
        }
        out.push((x, 2.0 / ((1.0 - x * x) * dp * dp)));
    }
    out.sort_by(|a, b| a.0.total_cmp(&b.0));
    out
}

/// A box in (u, v) holding face `f` ([`FlankInterpolator::locate_near`]
/// skips the faces whose box misses the point): the box of its nodes,
/// widened per coordinate by the largest bulge of a quadratic edge
/// (|m − (a + b)/2| for corners a, b and midside m: the edge
/// a(1 − t)(1 − 2t) + 4m t(1 − t) + b t(2t − 1) leaves its chord by
/// 4t(1 − t)(m − (a + b)/2), at most that), and by 1e-6 of its size more,
/// far beyond the 1e-9 in ξ by which [`FlankInterpolator::on_face`]
/// accepts a point past an edge. The face lies within its edges, so every
/// point a face accepts is in its box.
fn face_box(flank: &FlankNodes, f: &FlankFace) -> [f64; 4] {
    let uv = |a: u32| flank.uv[a as usize];
    let nodes = &f.nodes;
    let mut b = [
        f64::INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NEG_INFINITY,
    ];
    for &a in nodes {
        let [u, v] = uv(a);
        b = [b[0].min(u), b[1].min(v), b[2].max(u), b[3].max(v)];
    }
    // edges (corner, corner, midside)
    let corners = if nodes.len() == 8 { 4 } else { 3 };
    let mut bulge = [0.0f64; 2];
    if nodes.len() == 2 * corners {
        for e in 0..corners {
            let (p, q, m) = (
                uv(nodes[e]),
                uv(nodes[(e + 1) % corners]),
                uv(nodes[corners + e]),
            );
            for i in 0..2 {
                bulge[i] = bulge[i].max((m[i] - 0.5 * (p[i] + q[i])).abs());
            }
        }
    } else {
        // not a quadratic face of the known kinds: never skipped
        return [
            f64::NEG_INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::INFINITY,
        ];
    }
    let pad = [
        bulge[0] + 1e-6 * (b[2] - b[0]),
        bulge[1] + 1e-6 * (b[3] - b[1]),
    ];
    [b[0] - pad[0], b[1] - pad[1], b[2] + pad[0], b[3] + pad[1]]
}

/// Most parts per direction of a cell's composite rule
/// ([`FlankInterpolator::cell`]): a cell 128 faces long is sampled at
/// 64 × `samples` points along.
pub const MAX_CELL_PARTS: usize = 64;

/// The Gauss rule `gl` on [−1, 1] repeated on m equal parts of it.
fn composite(gl: &[(f64, f64)], m: usize) -> Vec<(f64, f64)> {
    let h = 1.0 / m as f64;
    (0..m)
        .flat_map(|k| {
            let c = -1.0 + (2 * k + 1) as f64 * h;
            gl.iter().map(move |&(a, w)| (c + h * a, w * h))
        })
        .collect()
}

/// Point location and load spreading on the flank of a compliance tensor.
pub struct FlankInterpolator<'a> {
    tensor: &'a ComplianceTensor,
    grids: Arc<FlankGrids>,
}

/// The face search structure of a tensor's flank sets, built once by
/// [`FlankInterpolator::new`] and shareable between interpolators of the
/// same tensor ([`FlankInterpolator::with_grids`]). It also carries the
/// tensor's paged node blocks ([`FlankGrids::pages`]), built on first use,
/// and per face a box in (u, v) that holds it (`face_box`): a point
/// outside a face's box is not tried on it (no Newton solve).
pub struct FlankGrids(
    Vec<Grid>,
    OnceLock<TensorPages>,
    Vec<[f64; 4]>,
    Vec<Option<SeparableFace>>,
);

/// A quad8 face whose (u, v) map is separable: u a quadratic of one
/// reference coordinate alone and v of the other (the structured flank
/// meshes' faces, profile rows at constant u and face layers at constant
/// v). Its inverse in closed form starts the Newton solve of
/// [`FlankInterpolator::on_face`], which then takes one step to confirm
/// it (four to five from the face's centre); the root it converges to,
/// and its tolerance, are unchanged.
#[derive(Clone, Copy, Debug)]
struct SeparableFace {
    /// The reference coordinate (0: ξ, 1: η) u depends on; v on the other.
    u_axis: usize,
    /// u(t) = q₀ + q₁ t + q₂ t² along that coordinate, likewise v.
    qu: [f64; 3],
    qv: [f64; 3],
}

impl SeparableFace {
    /// The face's separable form, if its nodes' u depend on one reference
    /// coordinate only and v on the other (to 1e-9 of the face's extent).
    fn of(uv: &[[f64; 2]; 8]) -> Option<Self> {
        let extent = |c: usize| {
            let (lo, hi) = uv
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), p| {
                    (l.min(p[c]), h.max(p[c]))
                });
            hi - lo
        };
        // value c of the nodes along reference coordinate `axis`: the
        // quadratic through t = −1, 0, 1, if the nodes agree at each t
        let along = |c: usize, axis: usize| -> Option<[f64; 3]> {
            let tol = 1e-9 * extent(c).max(f64::MIN_POSITIVE);
            let mut at = [f64::NAN; 3];
            for (a, p) in QUAD8_NODES.iter().enumerate() {
                let k = (p[axis] + 1.0) as usize;
                if at[k].is_nan() {
                    at[k] = uv[a][c];
                } else if (at[k] - uv[a][c]).abs() > tol {
                    return None;
                }
            }
            let [m, z, p] = at;
            Some([z, 0.5 * (p - m), 0.5 * (p + m) - z])
        };
        (0..2).find_map(|u_axis| {
            Some(SeparableFace {
                u_axis,
                qu: along(0, u_axis)?,
                qv: along(1, 1 - u_axis)?,
            })
        })
    }

    /// (ξ, η) of (u, v) on the face's map extended beyond it (the root of
    /// each quadratic nearer the linear one), `None` without a real root.
    fn inverse(&self, u: f64, v: f64) -> Option<[f64; 2]> {
        // q₂t² + q₁t + (q₀ − x) = 0, the small root in the stable form
        let root = |q: [f64; 3], x: f64| -> Option<f64> {
            let (a, b, c) = (q[2], q[1], q[0] - x);
            let d = b * b - 4.0 * a * c;
            if !(d >= 0.0) {
                return None;
            }
            let den = b + b.signum() * d.sqrt();
            let t = if den != 0.0 { -2.0 * c / den } else { 0.0 };
            t.is_finite().then_some(t)
        };
        let (tu, tv) = (root(self.qu, u)?, root(self.qv, v)?);
        Some(if self.u_axis == 0 { [tu, tv] } else { [tv, tu] })
    }
}

impl FlankGrids {
    /// The paged node blocks of `tensor` (the tensor these grids were
    /// built for; laid out on the first call), or `None` when `tensor` is
    /// not the one the pages were laid out for.
    pub fn pages(&self, tensor: &ComplianceTensor) -> Option<&TensorPages> {
        let p = self.1.get_or_init(|| TensorPages::new(tensor));
        p.matches(tensor).then_some(p)
    }

    /// Reads this tensor's pages from `pages` (e.g.
    /// [`TensorPages::compressed`]) instead of its dense matrix: an error
    /// once the pages were laid out.
    pub fn set_pages(&self, pages: TensorPages) -> Result<(), FlankError> {
        self.1.set(pages).map_err(|_| {
            FlankError::Model(
                "the tensor's pages were laid out already: cannot replace them".into(),
            )
        })
    }

    /// Whether the pages are read from a compressed tensor.
    pub fn compressed(&self) -> bool {
        self.1.get().is_some_and(TensorPages::is_compressed)
    }

    /// Bytes of the page pairs built so far (0 before any use).
    pub fn page_bytes(&self) -> usize {
        self.1.get().map_or(0, TensorPages::bytes)
    }
}

/// Faces of one flank set bucketed by their (u, v) bounding boxes.
struct Grid {
    lo: [f64; 2],
    cell: [f64; 2],
    n: [usize; 2],
    buckets: Vec<Vec<u32>>,
}

impl Grid {
    fn bucket(&self, u: f64, v: f64) -> Option<usize> {
        let iu = ((u - self.lo[0]) / self.cell[0]).floor();
        let iv = ((v - self.lo[1]) / self.cell[1]).floor();
        if !(iu >= 0.0 && iv >= 0.0) {
            return None;
        }
        let (iu, iv) = (iu as usize, iv as usize);
        (iu < self.n[0] && iv < self.n[1]).then(|| iu * self.n[1] + iv)
    }
}

impl<'a> FlankInterpolator<'a> {
    /// An interpolator of `tensor`, which must hold its dense matrix (a
    /// compressed tensor's geometry: [`FlankGrids::of`]).
    pub fn new(tensor: &'a ComplianceTensor) -> Result<Self, FlankError> {
        if tensor.matrix.is_empty() && tensor.dim() > 0 {
            return Err(FlankError::Model(format!(
                "the compliance tensor of {} holds no dense matrix (built compressed): \
                 its entries are read from the block low-rank form only",
                tensor.meta.body
            )));
        }
        if tensor.matrix.len() != tensor.dim() * tensor.dim() {
            return Err(FlankError::Model(format!(
                "compliance matrix has {} entries, expected {}²",
                tensor.matrix.len(),
                tensor.dim()
            )));
        }
        Ok(FlankInterpolator {
            tensor,
            grids: FlankGrids::of(tensor)?,
        })
    }

    /// The search structure, to build further interpolators of the same
    /// tensor without rebuilding it.
    pub fn grids(&self) -> Arc<FlankGrids> {
        Arc::clone(&self.grids)
    }
}

impl FlankGrids {
    /// The face search structure of `tensor`'s flank (geometry only: the
    /// matrix is not read, a tensor built compressed has none); its pages
    /// laid out on first use or set by [`FlankGrids::set_pages`].
    pub fn of(tensor: &ComplianceTensor) -> Result<Arc<Self>, FlankError> {
        let flank = &tensor.flank;
        flank.validate()?;
        let mut grids = Vec::with_capacity(flank.sets.len());
        for s in 0..flank.sets.len() {
            let faces: Vec<(usize, [f64; 4])> = flank
                .faces
                .iter()
                .enumerate()
                .filter(|(_, f)| f.set as usize == s)
                .map(|(i, f)| {
                    let mut b = [
                        f64::INFINITY,
                        f64::INFINITY,
                        f64::NEG_INFINITY,
                        f64::NEG_INFINITY,
                    ];
                    for &a in &f.nodes {
                        let [u, v] = flank.uv[a as usize];
                        b = [b[0].min(u), b[1].min(v), b[2].max(u), b[3].max(v)];
                    }
                    // quadratic edges may bulge past the nodes: pad by a quarter of the size
                    let (pu, pv) = (0.25 * (b[2] - b[0]), 0.25 * (b[3] - b[1]));
                    (i, [b[0] - pu, b[1] - pv, b[2] + pu, b[3] + pv])
                })
                .collect();
            if faces.is_empty() {
                grids.push(Grid {
                    lo: [0.0; 2],
                    cell: [1.0; 2],
                    n: [0, 0],
                    buckets: Vec::new(),
                });
                continue;
            }
            let mut lo = [f64::INFINITY; 2];
            let mut hi = [f64::NEG_INFINITY; 2];
            for (_, b) in &faces {
                lo = [lo[0].min(b[0]), lo[1].min(b[1])];
                hi = [hi[0].max(b[2]), hi[1].max(b[3])];
            }
            let k = (faces.len() as f64).sqrt().ceil() as usize;
            let n = [k.max(1), k.max(1)];
            let cell = [
                ((hi[0] - lo[0]) / n[0] as f64).max(f64::MIN_POSITIVE),
                ((hi[1] - lo[1]) / n[1] as f64).max(f64::MIN_POSITIVE),
            ];
            let mut buckets = vec![Vec::new(); n[0] * n[1]];
            for (i, b) in &faces {
                let i0 = (((b[0] - lo[0]) / cell[0]).floor().max(0.0) as usize).min(n[0] - 1);
                let i1 = (((b[2] - lo[0]) / cell[0]).floor().max(0.0) as usize).min(n[0] - 1);
                let j0 = (((b[1] - lo[1]) / cell[1]).floor().max(0.0) as usize).min(n[1] - 1);
                let j1 = (((b[3] - lo[1]) / cell[1]).floor().max(0.0) as usize).min(n[1] - 1);
                for iu in i0..=i1 {
                    for iv in j0..=j1 {
                        buckets[iu * n[1] + iv].push(*i as u32);
                    }
                }
            }
            grids.push(Grid {
                lo,
                cell,
                n,
                buckets,
            });
        }
        let boxes = flank.faces.iter().map(|f| face_box(flank, f)).collect();
        let separable = flank
            .faces
            .iter()
            .map(|f| {
                let uv: [[f64; 2]; 8] = (f.nodes.len() == 8)
                    .then(|| std::array::from_fn(|a| flank.uv[f.nodes[a] as usize]))?;
                SeparableFace::of(&uv)
            })
            .collect();
        Ok(Arc::new(FlankGrids(
            grids,
            OnceLock::new(),
            boxes,
            separable,
        )))
    }
}

impl<'a> FlankInterpolator<'a> {
    /// An interpolator of `tensor` with the search structure of an earlier
    /// [`FlankInterpolator::new`] of the same tensor (not checked: pass the
    /// grids of this tensor).
    pub fn with_grids(tensor: &'a ComplianceTensor, grids: Arc<FlankGrids>) -> Self {
        FlankInterpolator { tensor, grids }
    }

    fn set(&self, name: &str) -> Result<usize, FlankError> {
        self.tensor.flank.set_index(name).ok_or_else(|| {
            FlankError::Model(format!(
                "no flank set {name} in the compliance tensor (sets: {})",
                self.tensor.flank.sets.join(", ")
            ))
        })
    }

    /// Face and reference coordinates of (u, v) on the flank set `set`.
    pub fn locate(&self, set: usize, u: f64, v: f64) -> Option<(usize, [f64; 2])> {
        self.locate_near(set, u, v, None)
    }

    /// [`Self::locate`], trying face `hint` first (the face of a nearby
    /// point: cells sample neighbouring points).
    pub fn locate_near(
        &self,
        set: usize,
        u: f64,
        v: f64,
        hint: Option<usize>,
    ) -> Option<(usize, [f64; 2])> {
        // a face whose box does not hold (u, v) would reject it: skipped
        let boxes = &self.grids.2;
        let within = |fi: usize| {
            let b = boxes[fi];
            u >= b[0] && u <= b[2] && v >= b[1] && v <= b[3]
        };
        if let Some(fi) = hint {
            if self.tensor.flank.faces.get(fi).map(|f| f.set as usize) == Some(set) && within(fi) {
                if let Some(xi) = self.on_face(fi, u, v) {
                    return Some((fi, xi));
                }
            }
        }
        let grid = self.grids.0.get(set)?;
        let b = grid.bucket(u, v)?;
        grid.buckets[b].iter().find_map(|&fi| {
            let fi = fi as usize;
            within(fi)
                .then(|| self.on_face(fi, u, v).map(|xi| (fi, xi)))
                .flatten()
        })
    }

    /// Reference coordinates of (u, v) on face `fi` if it lies on it
    /// (Newton on the face's isoparametric map in (u, v)).
    fn on_face(&self, fi: usize, u: f64, v: f64) -> Option<[f64; 2]> {
        let flank = &self.tensor.flank;
        let face = &flank.faces[fi];
        let k = face.nodes.len();
        // the face's centre, or the closed-form inverse of a separable face
        let mut xi = if k == 8 {
            self.grids.3[fi]
                .and_then(|q| q.inverse(u, v))
                .filter(|x| x[0].abs() < 10.0 && x[1].abs() < 10.0)
                .unwrap_or([0.0, 0.0])
        } else {
            [1.0 / 3.0, 1.0 / 3.0]
        };
        let mut ok = false;
        for _ in 0..30 {
            let (n, d) = face_shape(k, xi);
            let mut r = [u, v];
            let mut j = [[0.0; 2]; 2];
            for (a, &node) in face.nodes.iter().enumerate() {
                let p = flank.uv[node as usize];
                for i in 0..2 {
                    r[i] -= n[a] * p[i];
                    j[i][0] += d[a][0] * p[i];
                    j[i][1] += d[a][1] * p[i];
                }
            }
            let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
            if !(det.abs() > 0.0) || !det.is_finite() {
                break;
            }
            let dx = [
                (j[1][1] * r[0] - j[0][1] * r[1]) / det,
                (-j[1][0] * r[0] + j[0][0] * r[1]) / det,
            ];
            xi = [xi[0] + dx[0], xi[1] + dx[1]];
            if !(xi[0].abs() < 10.0 && xi[1].abs() < 10.0) {
                break;
            }
            // converged: Newton's next step would be of order |dx|², so
            // xi is at round-off. Until 2026-11-27 this asked |dx| < 1e-14,
            // below the round-off of a step on fine meshes (|dx| ≈ ε |u| /
            // |∂u/∂ξ|: 2e-14 on seed 002's 0.1 mm flank faces), so Newton
            // never confirmed the root and the sample was dropped as off
            // the flank: cells lost 3–13 % of their load there
            if dx[0].abs() + dx[1].abs() < 1e-10 {
                ok = true;
                break;
            }
        }
        if !ok {
            return None;
        }
        const TOL: f64 = 1e-9;
        let inside = if k == 8 {
            xi[0].abs() <= 1.0 + TOL && xi[1].abs() <= 1.0 + TOL
        } else {
            xi[0] >= -TOL && xi[1] >= -TOL && xi[0] + xi[1] <= 1.0 + TOL
        };
        inside.then(|| {
            if k == 8 {
                [xi[0].clamp(-1.0, 1.0), xi[1].clamp(-1.0, 1.0)]
            } else {
                let (a, b) = (xi[0].max(0.0), xi[1].max(0.0));
                let s = (a + b).max(1.0);
                [a / s, b / s]
            }
        })
    }

    /// Refuses a point or cell (around (u, v)) of flank set `s` (index into
    /// the tensor's flank sets) reaching down to u = `lowest` when the tensor stops above that
    /// ([`crate::compliance::ComplianceMeta::region_u_min`]): the restricted
    /// tensor does not hold those nodes, and dropping the samples there
    /// would silently take the load off them.
    pub fn check_region(&self, s: usize, lowest: f64, u: f64, v: f64) -> Result<(), FlankError> {
        let Some(floor) = self
            .tensor
            .meta
            .region_u_min
            .as_ref()
            .and_then(|f| f.get(s).copied())
        else {
            return Ok(());
        };
        if lowest < floor - 1e-12 * (1.0 + floor.abs()) {
            return Err(FlankError::Model(format!(
                "{}: the contact at (u, v) = ({u}, {v}) on {} reaches u = {lowest}, below u = {floor} where its compliance tensor stops (flank region `active`: the active flank plus a margin); widen the margin or use the full flank (`--flank-region full`, `[analyses.ltca] flank_region = \"full\"`)",
                self.tensor.meta.body, self.tensor.flank.sets[s]
            )));
        }
        Ok(())
    }

    /// Shape-function weights of the point (u, v) of flank set `set`.
    pub fn point(&self, set: &str, u: f64, v: f64) -> Result<SurfaceLoad, FlankError> {
        let s = self.set(set)?;
        self.check_region(s, u, u, v)?;
        let (fi, xi) = self.locate(s, u, v).ok_or_else(|| {
            FlankError::Model(format!(
                "flank point (u, v) = ({u}, {v}) lies outside the meshed flank {set}"
            ))
        })?;
        let face = &self.tensor.flank.faces[fi];
        let (n, _) = face_shape(face.nodes.len(), xi);
        Ok(SurfaceLoad {
            weights: face.nodes.iter().zip(n).map(|(&a, w)| (a, w)).collect(),
            coverage: 1.0,
        })
    }

    /// Weights of a load spread uniformly over the cell `shape` around
    /// (u, v), `samples` Gauss points per direction (≥ 1).
    pub fn cell(
        &self,
        set: &str,
        u: f64,
        v: f64,
        shape: CellShape,
        samples: usize,
    ) -> Result<SurfaceLoad, FlankError> {
        let s = self.set(set)?;
        if samples == 0 {
            return Err(FlankError::Model("a contact cell needs ≥ 1 sample".into()));
        }
        let gl = gauss_legendre(samples);
        let mut pts: Vec<(f64, f64, f64)> = Vec::new();
        match shape {
            CellShape::Rectangle { hu, hv } => {
                if !(hu > 0.0 && hv > 0.0) {
                    return Err(FlankError::Model(format!(
                        "contact rectangle half-widths must be positive, got ({hu}, {hv})"
                    )));
                }
                // a composite rule: `samples` points in each of m equal
                // parts per direction, a part no longer than two faces
                // (the face at the cell's centre measured in (u, v)); a
                // cell many faces long sampled at `samples` points only
                // would load a few points of a fine mesh, not the cell
                let [mu, mv] = self.spans(s, u, v, hu, hv);
                let au = composite(&gl, mu);
                let av = composite(&gl, mv);
                for &(a, wa) in &au {
                    for &(b, wb) in &av {
                        pts.push((u + hu * a, v + hv * b, wa * wb));
                    }
                }
            }
            CellShape::Ellipse { au, av } => {
                if !(au > 0.0 && av > 0.0) {
                    return Err(FlankError::Model(format!(
                        "contact ellipse semi-axes must be positive, got ({au}, {av})"
                    )));
                }
                let nt = 4 * samples;
                for &(a, wa) in &gl {
                    let rho = 0.5 * (a + 1.0);
                    for j in 0..nt {
                        let th = 2.0 * std::f64::consts::PI * (j as f64 + 0.5) / nt as f64;
                        let w = 0.5 * wa * rho / nt as f64;
                        pts.push((u + au * rho * th.cos(), v + av * rho * th.sin(), w));
                    }
                }
            }
        }
        // a tensor restricted to the active flank must cover the whole cell
        // below: samples there would be dropped as "off the flank"
        let lowest = pts.iter().map(|p| p.0).fold(f64::INFINITY, f64::min);
        self.check_region(s, lowest, u, v)?;
        let flank = &self.tensor.flank;
        let total: f64 = pts.iter().map(|p| p.2).sum();
        let mut inside = 0.0;
        // a handful of nodes: a small vector beats a map here
        let mut acc: Vec<(u32, f64)> = Vec::with_capacity(24);
        let mut mass = 0.0;
        let mut hint = None;
        for (pu, pv, w) in pts {
            let Some((fi, xi)) = self.locate_near(s, pu, pv, hint) else {
                continue;
            };
            hint = Some(fi);
            inside += w;
            let face = &flank.faces[fi];
            let (n, d) = face_shape(face.nodes.len(), xi);
            let mut t1 = [0.0; 3];
            let mut t2 = [0.0; 3];
            let mut j = [[0.0; 2]; 2];
            for (a, &node) in face.nodes.iter().enumerate() {
                let x = flank.positions[node as usize];
                let p = flank.uv[node as usize];
                for i in 0..3 {
                    t1[i] += d[a][0] * x[i];
                    t2[i] += d[a][1] * x[i];
                }
                for i in 0..2 {
                    j[i][0] += d[a][0] * p[i];
                    j[i][1] += d[a][1] * p[i];
                }
            }
            let det = (j[0][0] * j[1][1] - j[0][1] * j[1][0]).abs();
            let density = norm(cross(t1, t2)) / det;
            if !density.is_finite() {
                continue;
            }
            let wd = w * density;
            mass += wd;
            for (a, &node) in face.nodes.iter().enumerate() {
                match acc.iter_mut().find(|e| e.0 == node) {
                    Some(e) => e.1 += wd * n[a],
                    None => acc.push((node, wd * n[a])),
                }
            }
        }
        acc.sort_unstable_by_key(|e| e.0);
        if !(mass > 0.0) {
            return Err(FlankError::Model(format!(
                "contact cell around (u, v) = ({u}, {v}) lies outside the meshed flank {set}"
            )));
        }
        Ok(SurfaceLoad {
            weights: acc.into_iter().map(|(a, w)| (a, w / mass)).collect(),
            coverage: inside / total,
        })
    }

    /// Parts of a rectangle of half-widths (hu, hv) around (u, v) per
    /// direction for its composite rule: its width over two widths of the
    /// (u, v) box of the face at its centre, rounded up (1 where no face
    /// holds the centre), at most [`MAX_CELL_PARTS`]. With 3 points a part
    /// that is 1.5 points per face or more.
    fn spans(&self, set: usize, u: f64, v: f64, hu: f64, hv: f64) -> [usize; 2] {
        let Some((fi, _)) = self.locate(set, u, v) else {
            return [1, 1];
        };
        let b = self.grids.2[fi];
        let parts = |width: f64, face: f64| {
            let m = (width / (2.0 * face)).ceil();
            if m.is_finite() && m >= 1.0 {
                (m as usize).min(MAX_CELL_PARTS)
            } else {
                1
            }
        };
        [parts(2.0 * hu, b[2] - b[0]), parts(2.0 * hv, b[3] - b[1])]
    }

    /// C^{pq}: the displacement at p (read back with p's weights) from a
    /// unit force spread with q's weights.
    pub fn tensor(&self, p: &SurfaceLoad, q: &SurfaceLoad) -> [[f64; 3]; 3] {
        let mut c = [[0.0; 3]; 3];
        for &(a, wa) in &p.weights {
            for &(b, wb) in &q.weights {
                let cab = self.tensor.block(a as usize, b as usize);
                let w = wa * wb;
                for i in 0..3 {
                    for j in 0..3 {
                        c[i][j] += w * cab[i][j];
                    }
                }
            }
        }
        c
    }

    /// Position (mm) of a point or cell centroid (weighted nodal positions).
    pub fn position(&self, p: &SurfaceLoad) -> [f64; 3] {
        let mut x = [0.0; 3];
        for &(a, w) in &p.weights {
            let y = self.tensor.flank.positions[a as usize];
            for i in 0..3 {
                x[i] += w * y[i];
            }
        }
        x
    }

    /// Outward unit normal interpolated from the nodal normals.
    pub fn normal(&self, p: &SurfaceLoad) -> [f64; 3] {
        let mut x = [0.0; 3];
        for &(a, w) in &p.weights {
            let y = self.tensor.flank.normals[a as usize];
            for i in 0..3 {
                x[i] += w * y[i];
            }
        }
        let l = norm(x);
        [x[0] / l, x[1] / l, x[2] / l]
    }

    /// The K × K normal compliance matrix (row-major) of a set of points
    /// with unit normals: `C_nn[k][l] = n_kᵀ C^{kl} n_l`.
    pub fn normal_matrix(&self, points: &[SurfaceLoad], normals: &[[f64; 3]]) -> Vec<f64> {
        let k = points.len();
        let mut out = vec![0.0; k * k];
        for i in 0..k {
            for j in i..k {
                let c = self.tensor(&points[i], &points[j]);
                let v = dot3(normals[i], mat_vec(&c, normals[j]));
                out[i * k + j] = v;
                out[j * k + i] = v;
            }
        }
        out
    }
}

#[cfg(test)]
#[path = "interpolation_tests.rs"]
mod tests;
