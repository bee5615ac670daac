//! Native gear-sector mesher: structured multi-block meshes of `teeth`
//! consecutive teeth of one gear, exact on the flanks, in 20-node hexahedra
//! (C3D20, or C3D20R) or 15-node wedges (C3D15: every transverse quadrilateral
//! split along its shorter diagonal, so triangles in the transverse plane and
//! quadratic layers across the face width, as in seed 002).
//!
//! Construction (transverse plane, then extrusion along the axis):
//! * per tooth pitch (tooth centre ± half pitch) an **upper block**, a quadratic
//!   lattice (2n+1 points per direction) whose lines of constant `J` run across
//!   the tooth from the left boundary to the right boundary and whose lines of
//!   constant `I` run from the bottom up to the tip. The left boundary is the
//!   half root arc from the sector cut (gap centre) to the left fillet end, the
//!   left fillet and the left involute up to the tip corner; the right boundary
//!   is its mirror; the top is the tip arc; the bottom is a Π-shaped curve: the
//!   cut line from the root circle down to an interface radius r_i, the arc r_i
//!   across the pitch, the other cut line back up. Boundary lattice points
//!   (corner and midside) are placed on the exact profile by its parameter
//!   (root-arc angle, fillet parameter t, involute roll angle u with uniform
//!   arc length), so midside nodes lie on the exact curve. Interior points by
//!   transfinite interpolation (Coons patch) in polar coordinates (angle,
//!   radius), with a graded distribution across the tooth chosen per row
//!   (first layer ≈ `flank_size`, growth ≤ 1.3 towards the tooth centre; where
//!   the tooth is too narrow, near the tip, uniform and thinner). The bottom
//!   curve's blend weight falls from 1 at the bottom to 0 at the form point,
//!   so on the involute the rows are pure polar lerps between the flanks.
//! * per pitch a **rim block** between the bore and r_i, a polar tensor lattice
//!   whose top row is the arc part of the upper block's bottom (the same
//!   points), graded from the cut element size at r_i to ≤ `base_size`.
//! * Blocks share nodes along their interfaces (identical lattice points,
//!   merged by position); neighbouring pitches share the cut lines.
//! * Wedge15 meshes split every transverse quadrilateral into two triangles
//!   and, inside the tooth, coarsen 2:1 along the profile: column lines get a
//!   level λ (0 on the flanks and the first line inside, at most +1 per
//!   column towards the centre) and cells between lines of level λ span 2^λ
//!   rows; a column between levels λ and λ + 1 is a transition of three
//!   triangles per coarse cell; level λ stops below the row where the
//!   narrowing tooth would make its cells more than 3 × as tall as wide.
//!   Edges spanning several rows get straight midpoints (interior only).
//!   The flank faces are unchanged (same nodes as the hex20 mesh).
//! * Extrusion: z ∈ [0, b] in `face_layers` quadratic layers; each transverse
//!   section is rotated by φ(z) = twist_rate · z, which puts flank nodes exactly
//!   on the helicoid [`ToothProfile::surface`].
//!
//! Conventions. Tooth `k` of the sector (sets `FLANK_L<k>`, `FLANK_R<k>`,
//! k = 1..=teeth) is the profile's tooth k − 1, i.e. tooth 0 (symmetric about
//! +y) rotated by −2π(k−1)/z. `FLANK_R<k>` are the nodes of the profile's
//! [`Flank::Right`] (x > 0 for tooth 0), `FLANK_L<k>` those of [`Flank::Left`]:
//! seen with the gear axis (+z) pointing at the viewer and the tooth pointing
//! up, FLANK_L is on the viewer's left, FLANK_R on the right. Flank sets hold
//! every node on the involute and on the trochoidal root fillet (not on the
//! root arc). `CUT_A` is the cut face at the gap centre left of tooth 1 (angle
//! −π/z from +y, positive towards +x), `CUT_B` the cut right of the last tooth.
//! `BORE`: nodes at the bore radius. `NALL`, `EALL`. For helical gears the
//! cut faces are twisted with the section (helicoidal, not planes). With
//! `teeth` = z the ring closes: the two cuts merge and CUT_A = CUT_B.
//!
//! Flank parameter u (in [`GearSectorMesh::flank_uv`]): the involute roll
//! angle for u ≥ u_form; on the fillet u = u_form − t (t ∈ [0, 1] the fillet
//! parameter, 0 at the form circle), see [`flank_segment`].

use std::collections::HashMap;
use std::f64::consts::PI;

use crate::error::FlankError;
use crate::fem::element::{check_jacobian, det3, jacobian, ReferenceElement};
use crate::geometry::rack::{Flank, Segment, ToothProfile};
use crate::geometry::GearSpec;
use crate::mesh::{ElementKind, Mesh};

/// Options of [`gear_sector`].
#[derive(Clone, Debug)]
pub struct SectorOptions {
    /// Number of teeth in the sector (default 3).
    pub teeth: usize,
    /// Element size along and normal to the flank near the surface (mm).
    pub flank_size: f64,
    /// Coarse element size in the rim and body (mm).
    pub base_size: f64,
    /// Elements across the face width; 0 = ⌈b / base_size⌉.
    pub face_layers: usize,
    /// C3D20 (default), C3D20R (same nodes, reduced integration) or C3D15:
    /// each transverse quadrilateral split along its shorter diagonal into two
    /// triangles, i.e. wedges with triangles in the transverse plane and
    /// quadratic layers across the face width (as in seed 002).
    pub element: ElementKind,
}

impl Default for SectorOptions {
    fn default() -> Self {
        SectorOptions {
            teeth: 3,
            flank_size: 0.5,
            base_size: 2.0,
            face_layers: 0,
            element: ElementKind::C3D20,
        }
    }
}

/// Element quality figures.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Quality {
    /// min over elements of (min det J / max det J over the 27 Gauss points).
    pub min_scaled_jacobian: f64,
    /// max over elements of longest / shortest corner-to-corner edge.
    pub max_aspect_ratio: f64,
}

impl Quality {
    /// No element yet: the neutral values of [`Quality::add`].
    pub fn empty() -> Self {
        Quality {
            min_scaled_jacobian: f64::INFINITY,
            max_aspect_ratio: 0.0,
        }
    }

    /// Takes one element (`kind`, node coordinates) into the figures.
    pub fn add(&mut self, kind: ElementKind, x: &[[f64; 3]]) {
        let (mut lo, mut hi) = (f64::INFINITY, 0.0f64);
        for d in &ReferenceElement::get(kind).derivatives {
            let dj = det3(&jacobian(x, d));
            lo = lo.min(dj);
            hi = hi.max(dj);
        }
        self.min_scaled_jacobian = self.min_scaled_jacobian.min(lo / hi);
        let (mut emin, mut emax) = (f64::INFINITY, 0.0f64);
        for e in crate::fem::element::edges(kind) {
            let (p, q) = (x[e[0]], x[e[1]]);
            let d = ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt();
            emin = emin.min(d);
            emax = emax.max(d);
        }
        self.max_aspect_ratio = self.max_aspect_ratio.max(emax / emin);
    }
}

/// A meshed gear sector.
#[derive(Clone, Debug)]
pub struct GearSectorMesh {
    pub mesh: Mesh,
    /// For each flank node: (profile parameter u, z). See the module docs for u.
    pub flank_uv: HashMap<usize, (f64, f64)>,
    pub quality: Quality,
}

/// Profile segment of the unified flank parameter u (module docs).
pub fn flank_segment(profile: &ToothProfile, u: f64) -> Segment {
    if u >= profile.u_form {
        Segment::Involute(u)
    } else {
        Segment::Fillet((profile.u_form - u).min(1.0))
    }
}

fn err(msg: String) -> FlankError {
    FlankError::Model(format!("gear sector mesh: {msg}"))
}

/// Sizes starting at h0, growing by q up to hmax, scaled to sum exactly to len.
fn graded(len: f64, h0: f64, q: f64, hmax: f64) -> Vec<f64> {
    let mut v = Vec::new();
    let mut s = 0.0;
    let mut h = h0.min(hmax).min(len);
    while s + 0.5 * h < len || v.is_empty() {
        v.push(h);
        s += h;
        h = (h * q).min(hmax);
    }
    let f = len / s;
    v.iter().map(|x| x * f).collect()
}

/// Cumulative fractions on the half lattice (2n + 1 values) from n sizes; odd
/// entries are the averages of their neighbours.
fn half_lattice(sizes: &[f64]) -> Vec<f64> {
    let tot: f64 = sizes.iter().sum();
    let mut out = vec![0.0];
    let mut s = 0.0;
    for h in sizes {
        out.push((s + 0.5 * h) / tot);
        s += h;
        out.push(s / tot);
    }
    *out.last_mut().unwrap() = 1.0;
    out
}

fn pol(p: [f64; 2]) -> [f64; 2] {
    [p[0].atan2(p[1]), p[0].hypot(p[1])]
}

fn cart(a: f64, r: f64) -> [f64; 2] {
    [r * a.sin(), r * a.cos()]
}

fn rot(p: [f64; 2], a: f64) -> [f64; 2] {
    // rotate by angle a measured from +y towards +x (clockwise)
    let (s, c) = a.sin_cos();
    [c * p[0] + s * p[1], -s * p[0] + c * p[1]]
}

/// Transverse 2D point registry with merging by position.
struct Points {
    xy: Vec<[f64; 2]>,
    /// true if a corner lattice point (no odd index), false if midside.
    corner: Vec<bool>,
    /// flank info: (sector tooth 1-based, flank, u)
    flank: Vec<Option<(usize, Flank, f64)>>,
    bore: Vec<bool>,
    grid: HashMap<(i64, i64), Vec<usize>>,
    tol: f64,
}

impl Points {
    fn key(&self, p: [f64; 2]) -> (i64, i64) {
        (
            (p[0] / self.tol).floor() as i64,
            (p[1] / self.tol).floor() as i64,
        )
    }
    fn add(&mut self, p: [f64; 2], corner: bool) -> Result<usize, FlankError> {
        let (kx, ky) = self.key(p);
        for dx in -1..=1 {
            for dy in -1..=1 {
                if let Some(v) = self.grid.get(&(kx + dx, ky + dy)) {
                    for &i in v {
                        let q = self.xy[i];
                        if (q[0] - p[0]).hypot(q[1] - p[1]) < self.tol {
                            if self.corner[i] != corner {
                                return Err(err(format!(
                                    "lattice mismatch at ({:.6}, {:.6}): corner and midside point coincide",
                                    p[0], p[1]
                                )));
                            }
                            return Ok(i);
                        }
                    }
                }
            }
        }
        let i = self.xy.len();
        self.xy.push(p);
        self.corner.push(corner);
        self.flank.push(None);
        self.bore.push(false);
        self.grid.entry((kx, ky)).or_default().push(i);
        Ok(i)
    }
}

/// A 2D quadratic block: point ids on a (2ni+1) × (2nj+1) lattice (usize::MAX at odd/odd).
struct Block {
    ni: usize,
    nj: usize,
    ids: Vec<usize>,
}

/// A transverse cell: quadrilateral (corners, midsides; hex20) or two
/// triangles (wedge15), point ids in the order of the element's bottom face.
enum Cell {
    Quad([usize; 4], [usize; 4]),
    Tris(Vec<([usize; 3], [usize; 3])>),
}

/// A lattice point (half-index I, J) of an upper block.
type Lp = (usize, usize);

/// The midside point of an edge of a lattice cell: a lattice point (edges
/// along a row, and edges one row long: shared with fine neighbours and,
/// on the boundary, on the exact curve), or the straight midpoint of the
/// corners (edges spanning several rows and diagonals of coarse or
/// transition cells, which never lie on the boundary: where rows are
/// unevenly spaced a lattice point would sit far off the edge's middle).
#[derive(Clone, Copy)]
enum Mid {
    Lattice(Lp),
    Straight(Lp, Lp),
}

/// Midside of the edge a–b (lattice corners).
fn edge_mid(a: Lp, b: Lp) -> Mid {
    let m = ((a.0 + b.0) / 2, (a.1 + b.1) / 2);
    if a.1 == b.1 || (a.0 == b.0 && a.1.abs_diff(b.1) == 2) {
        Mid::Lattice(m)
    } else {
        Mid::Straight(a, b)
    }
}

/// A transverse cell in lattice coordinates (corners, midsides).
enum LatticeCell {
    Quad([Lp; 4], [Mid; 4]),
    Tris(Vec<([Lp; 3], [Mid; 3])>),
}

/// A quadrilateral cell, or for wedges its two triangles (split along the
/// shorter diagonal, whose midside point, the serendipity centre, is added).
fn quad_cell(
    pts: &mut Points,
    c: [usize; 4],
    m: [usize; 4],
    wedges: bool,
) -> Result<Cell, FlankError> {
    if !wedges {
        return Ok(Cell::Quad(c, m));
    }
    let x = |p: usize| pts.xy[p];
    let dist = |a: usize, b: usize| {
        let (p, q) = (x(a), x(b));
        (p[0] - q[0]).hypot(p[1] - q[1])
    };
    let mut centre = [0.0; 2];
    for k in 0..4 {
        for d in 0..2 {
            centre[d] += -0.25 * x(c[k])[d] + 0.5 * x(m[k])[d];
        }
    }
    let first_diagonal = dist(c[0], c[2]) <= dist(c[1], c[3]);
    let dm = pts.add(centre, false)?;
    Ok(Cell::Tris(if first_diagonal {
        vec![
            ([c[0], c[1], c[2]], [m[0], m[1], dm]),
            ([c[0], c[2], c[3]], [dm, m[2], m[3]]),
        ]
    } else {
        vec![
            ([c[0], c[1], c[3]], [m[0], dm, m[3]]),
            ([c[1], c[2], c[3]], [m[1], m[2], dm]),
        ]
    }))
}

/// Mesh `opts.teeth` teeth of the gear `spec` (see the module docs).
///
/// Wedge meshes coarsen along the profile inside the tooth (2:1
/// transitions; about half the nodes at a given flank size); if that produces an element with a scaled
/// Jacobian below 0.2 (or an inverted one: possible on very coarse meshes,
/// where a coarse cell spans rows of very different spacing), the sector is
/// meshed again without coarsening.
pub fn gear_sector(
    spec: &GearSpec,
    name: &str,
    opts: &SectorOptions,
) -> Result<GearSectorMesh, FlankError> {
    if opts.element == ElementKind::C3D15 {
        match sector_mesh(spec, name, opts, true) {
            Ok(m) if m.quality.min_scaled_jacobian >= 0.2 => return Ok(m),
            Ok(_) | Err(FlankError::Element { .. }) => {}
            Err(e) => return Err(e),
        }
    }
    sector_mesh(spec, name, opts, false)
}

fn sector_mesh(
    spec: &GearSpec,
    name: &str,
    opts: &SectorOptions,
    coarsen: bool,
) -> Result<GearSectorMesh, FlankError> {
    let prof = ToothProfile::new(spec, name)?;
    let z = spec.teeth as usize;
    if opts.teeth == 0 || opts.teeth > z {
        return Err(err(format!(
            "{name}: {} teeth requested of {z}",
            opts.teeth
        )));
    }
    if !(opts.flank_size > 0.0 && opts.base_size >= opts.flank_size) {
        return Err(err(format!(
            "{name}: need 0 < flank_size ({}) ≤ base_size ({})",
            opts.flank_size, opts.base_size
        )));
    }
    let g = &prof.geometry;
    let (rf, ra, rb) = (g.root_radius, g.tip_radius, g.base_radius);
    let r_bore = 0.5 * spec.bore_diameter;
    if !(r_bore > 0.0 && r_bore < rf) {
        return Err(err(format!(
            "{name}: bore radius {r_bore} mm must lie in (0, root radius {rf:.4} mm)"
        )));
    }
    let h = PI / z as f64; // half pitch angle
    let ar = prof.root_angle;
    let fs = opts.flank_size;
    let q = 1.25;

    // --- across the tooth: graded sizes from both flanks to the centre.
    let w = g.reference_thickness_transverse;
    let half = graded(0.5 * w, fs, q, opts.base_size);
    let mut half = half;
    if half.len() < 2 {
        let x = half[0] / 2.0;
        half = vec![x, x];
    }
    let nh = half.len();
    let mut sizes_s = half.clone();
    sizes_s.extend(half.iter().rev());
    let ns = sizes_s.len();
    let sig = half_lattice(&sizes_s); // 2ns+1

    // --- interface radius and bottom Π curve split.
    // The cut lines (root circle down to r_i) take the first nc lattice steps
    // across the tooth at the same physical spacing, so the corner cells at the
    // gap centre are near-square: depth = σ_nc · W_s.
    let w_s: f64 = sizes_s.iter().sum();
    let target = (0.4 * (rf - r_bore)).min(0.5 * spec.normal_module);
    let mut nc = 1;
    for i in 1..nh {
        if sig[2 * i] * w_s <= target {
            nc = i;
        }
    }
    let depth = sig[2 * nc] * w_s;
    let ri = rf - depth;
    let s_c0 = sig[2 * nc];
    let s_c1 = sig[2 * (ns - nc)];

    // --- along the left boundary: gap half arc, fillet, involute.
    let gap_len = rf * (h - ar);
    let ng = ((gap_len / fs).ceil() as usize).max(1);
    // Fillet arc length s(t), tabulated (chords of 2048 pieces), so that the
    // lattice points are uniform in arc length; the points themselves are
    // evaluated at their parameter, hence exact whatever the table's accuracy.
    const FT: usize = 2048;
    let mut fil_s = vec![0.0; FT + 1];
    {
        let mut p0 = prof.point(Flank::Right, Segment::Fillet(0.0)).p;
        for k in 1..=FT {
            let p = prof
                .point(Flank::Right, Segment::Fillet(k as f64 / FT as f64))
                .p;
            fil_s[k] = fil_s[k - 1] + (p[0] - p0[0]).hypot(p[1] - p0[1]);
            p0 = p;
        }
    }
    let fil_len = fil_s[FT];
    let fillet_t = |f: f64| -> f64 {
        // parameter t at arc-length fraction f from the form point (t = 0)
        let target = f * fil_len;
        let k = fil_s.partition_point(|&v| v < target).clamp(1, FT);
        let (a, b) = (fil_s[k - 1], fil_s[k]);
        let w = if b > a { (target - a) / (b - a) } else { 0.0 };
        ((k - 1) as f64 + w) / FT as f64
    };
    let nf = ((fil_len / fs).ceil() as usize).max(1);
    let (uf, ut) = (prof.u_form, prof.u_tip);
    let inv_len = 0.5 * rb * (ut * ut - uf * uf);
    let ni = ((inv_len / fs).ceil() as usize).max(1);
    let nt = ng + nf + ni;
    // Left boundary point at half-lattice index jj (0..=2nt), tooth-0 local,
    // with Some(u) for flank points.
    let left = |jj: usize| -> ([f64; 2], Option<f64>) {
        if jj < 2 * ng {
            let a = -h + (h - ar) * jj as f64 / (2 * ng) as f64;
            (cart(a, rf), None)
        } else if jj <= 2 * (ng + nf) {
            let t = match jj - 2 * ng {
                0 => 1.0,
                d if d == 2 * nf => 0.0,
                d => fillet_t(1.0 - d as f64 / (2 * nf) as f64),
            };
            (prof.point(Flank::Left, Segment::Fillet(t)).p, Some(uf - t))
        } else {
            let f = (jj - 2 * (ng + nf)) as f64 / (2 * ni) as f64;
            let u = (uf * uf + (ut * ut - uf * uf) * f).sqrt();
            let u = if jj == 2 * nt { ut } else { u };
            (prof.point(Flank::Left, Segment::Involute(u)).p, Some(u))
        }
    };
    let lpts: Vec<([f64; 2], Option<f64>)> = (0..=2 * nt).map(left).collect();
    // blend τ: cumulative chord length along the left boundary
    let mut tau = vec![0.0; 2 * nt + 1];
    for j in 1..=2 * nt {
        let (a, b) = (lpts[j - 1].0, lpts[j].0);
        tau[j] = tau[j - 1] + (a[0] - b[0]).hypot(a[1] - b[1]);
    }
    let tl = tau[2 * nt];
    tau.iter_mut().for_each(|t| *t /= tl);
    // Blend of the bottom curve: 1 at the bottom, 0 from the form point up, so
    // that on the involute the lines across the tooth are pure (polar) lerps
    // between the flanks and the flank-normal layers keep their thickness.
    let tau_f = tau[2 * (ng + nf)];
    let alpha = |t: f64| {
        if t < tau_f {
            (1.0 - t / tau_f).powi(2)
        } else {
            0.0
        }
    };

    // bottom Π curve (polar) at lattice ii
    let bottom = |ii: usize| -> [f64; 2] {
        let s = sig[ii];
        if ii <= 2 * nc {
            [-h, rf - depth * s / s_c0]
        } else if ii >= 2 * (ns - nc) {
            [h, rf - depth * (1.0 - s) / (1.0 - s_c1)]
        } else {
            [-h + 2.0 * h * (s - s_c0) / (s_c1 - s_c0), ri]
        }
    };

    // Distribution across the tooth per lattice row: first layer flank_size,
    // geometric growth q ∈ [1, 1.3] to the centre (q = 1.3 and a thicker first
    // layer where the tooth is too wide for ns elements, uniform where it is
    // too narrow, i.e. near the tip). Rows below the form point use the form row's.
    let jform = 2 * (ng + nf);
    let row_dist = |width: f64| -> Vec<f64> {
        let sum = |q: f64| (0..nh).map(|k| q.powi(k as i32)).sum::<f64>();
        let target = 0.5 * width / fs;
        let q = if target <= nh as f64 {
            1.0
        } else if target >= sum(1.3) {
            1.3
        } else {
            let (mut lo, mut hi) = (1.0, 1.3);
            for _ in 0..60 {
                let m = 0.5 * (lo + hi);
                if sum(m) < target {
                    lo = m;
                } else {
                    hi = m;
                }
            }
            0.5 * (lo + hi)
        };
        let half: Vec<f64> = (0..nh).map(|k| q.powi(k as i32)).collect();
        let mut all = half.clone();
        all.extend(half.iter().rev());
        half_lattice(&all)
    };
    let row_sig: Vec<Vec<f64>> = (0..=2 * nt)
        .map(|jj| {
            let lp = pol(lpts[jj.max(jform)].0);
            row_dist(2.0 * (-lp[0]) * lp[1])
        })
        .collect();

    // --- rim radial sizes, from r_i down to the bore.
    // First rim layer: the cut lines' last step, or more if the rim cells
    // across the pitch are much wider (keeps the rim's aspect ratio ≤ ≈ 4).
    let cut_h0 = depth * (sig[2 * nc] - sig[2 * nc - 2]) / s_c0;
    let arc_cell_max = (0..ns - 2 * nc)
        .map(|i| 2.0 * h * ri * (sig[2 * (nc + i + 1)] - sig[2 * (nc + i)]) / (s_c1 - s_c0))
        .fold(0.0, f64::max);
    let rim_h0 = cut_h0.max(0.25 * arc_cell_max).min(opts.base_size);
    let rim_sizes = graded(ri - r_bore, rim_h0, q, opts.base_size);
    let nr = rim_sizes.len();
    let rho = half_lattice(&rim_sizes); // from r_i (0) to bore (1)

    // --- transverse points of all pitches.
    let mut pts = Points {
        xy: Vec::new(),
        corner: Vec::new(),
        flank: Vec::new(),
        bore: Vec::new(),
        grid: HashMap::new(),
        tol: 1e-7 * ra,
    };
    // --- upper-block layout in lattice (half-index) coordinates, the same for
    // every pitch. Wedge meshes coarsen along the profile inside the tooth:
    // column line i gets a level λ (0 at the flanks and on the first line
    // inside, rising by at most 1 per column towards the tooth centre, where
    // 2^λ rows of the flank spacing make a cell about 1.5 × as tall as the
    // graded column is wide); a column between lines of equal level has cells
    // of 2^λ rows, a column between levels λ and λ + 1 is a 2:1 transition of
    // three triangles per coarse cell. Hex meshes keep every row (λ = 0).
    let mut levels = vec![0u32; ns + 1];
    if coarsen {
        let max_level = (nt / 2).max(1).ilog2();
        for d in 2..=ns / 2 {
            let want = (1.5 * sizes_s[d.min(ns - 1)] / fs).log2().floor().max(0.0) as u32;
            let l = want
                .min(levels[d - 1] + 1)
                .max(levels[d - 1])
                .min(max_level);
            levels[d] = l;
            levels[ns - d] = l;
        }
    }
    // Row breakpoints of each level: level λ keeps every 2^λ-th row up to
    // the row j_λ where its narrowest cells (next to the line where λ first
    // appears) would become more than 3 × as tall as wide (the tooth narrows
    // towards the tip); above j_λ it
    // keeps the rows of level λ − 1. So B_λ ⊂ B_{λ−1}, and every coarse
    // chunk holds at most one breakpoint of the level below.
    let max_level = *levels.iter().max().unwrap_or(&0);
    let cell_width = |d: usize, jj: usize| {
        let lp = pol(lpts[jj.max(jform)].0);
        let w = 2.0 * (-lp[0]) * lp[1];
        w * (row_sig[jj][2 * d + 2] - row_sig[jj][2 * d])
    };
    let mut row_breaks: Vec<Vec<usize>> = vec![(0..=nt).collect()];
    for l in 1..=max_level {
        let d_l = levels.iter().position(|&x| x >= l).unwrap_or(ns / 2);
        let step = 1usize << l;
        let mut j_l = 0;
        while j_l + step <= nt
            && (0..=2 * (j_l + step))
                .all(|jj| (step as f64) * fs <= 3.0 * cell_width(d_l.min(ns - 1), jj))
        {
            j_l += step;
        }
        let below = &row_breaks[l as usize - 1];
        let v: Vec<usize> = below
            .iter()
            .copied()
            .filter(|&j| if j <= j_l { j % step == 0 } else { true })
            .collect();
        row_breaks.push(v);
    }
    let breaks = |l: u32| -> Vec<usize> { row_breaks[l as usize].clone() };
    let mid = edge_mid;
    let tri = |a: Lp, b: Lp, c: Lp| ([a, b, c], [mid(a, b), mid(b, c), mid(c, a)]);
    let mut layout: Vec<(usize, usize, LatticeCell)> = Vec::new();
    for c in 0..ns {
        let quad = |ja: usize, jb: usize| {
            let q = [
                (2 * c, 2 * ja),
                (2 * c + 2, 2 * ja),
                (2 * c + 2, 2 * jb),
                (2 * c, 2 * jb),
            ];
            LatticeCell::Quad(
                q,
                [
                    mid(q[0], q[1]),
                    mid(q[1], q[2]),
                    mid(q[2], q[3]),
                    mid(q[3], q[0]),
                ],
            )
        };
        let (l0, l1) = (levels[c], levels[c + 1]);
        if l0 == l1 {
            for w in breaks(l0).windows(2) {
                layout.push((c, w[0], quad(w[0], w[1])));
            }
            continue;
        }
        let fine = breaks(l0.min(l1));
        for w in breaks(l0.max(l1)).windows(2) {
            let (ja, jb) = (w[0], w[1]);
            let inner: Vec<usize> = fine.iter().copied().filter(|&j| j > ja && j < jb).collect();
            let jm = match inner[..] {
                [] => {
                    layout.push((c, ja, quad(ja, jb)));
                    continue;
                }
                [jm] => jm,
                _ => {
                    return Err(err(format!(
                        "{name}: internal: rows {ja}..{jb} of column {c} hold {} finer rows",
                        inner.len()
                    )))
                }
            };
            let (la, lm, lb) = ((2 * c, 2 * ja), (2 * c, 2 * jm), (2 * c, 2 * jb));
            let (ra, rm, rb) = (
                (2 * c + 2, 2 * ja),
                (2 * c + 2, 2 * jm),
                (2 * c + 2, 2 * jb),
            );
            let t = if l0 < l1 {
                vec![tri(la, ra, lm), tri(lm, ra, rb), tri(lm, rb, lb)]
            } else {
                vec![tri(la, ra, rm), tri(la, rm, lb), tri(lb, rm, rb)]
            };
            layout.push((c, ja, LatticeCell::Tris(t)));
        }
    }
    // role of each lattice point: 0 unused, 1 corner, 2 midside
    let w2 = 2 * nt + 1;
    let mut role = vec![0u8; (2 * ns + 1) * w2];
    let mut mark = |p: Lp, r: u8| -> Result<(), FlankError> {
        let slot = &mut role[p.0 * w2 + p.1];
        if *slot != 0 && *slot != r {
            return Err(err(format!(
                "{name}: lattice point ({}, {}) is both a corner and a midside node",
                p.0, p.1
            )));
        }
        *slot = r;
        Ok(())
    };
    for (_, _, cell) in &layout {
        let (corners, mids): (Vec<Lp>, Vec<Mid>) = match cell {
            LatticeCell::Quad(c, m) => (c.to_vec(), m.to_vec()),
            LatticeCell::Tris(t) => (
                t.iter().flat_map(|(c, _)| c.iter().copied()).collect(),
                t.iter().flat_map(|(_, m)| m.iter().copied()).collect(),
            ),
        };
        for p in corners {
            mark(p, 1)?;
        }
        for m in mids {
            if let Mid::Lattice(p) = m {
                mark(p, 2)?;
            }
        }
    }

    let mut blocks: Vec<Block> = Vec::new();
    let na = ns - 2 * nc; // rim elements across
    let mut cut_a = Vec::new();
    let mut cut_b = Vec::new();
    for k in 0..opts.teeth {
        let ak = 2.0 * PI * k as f64 / z as f64;
        // upper block
        let l1 = pol(lpts[2 * nt].0);
        let c00 = bottom(0);
        let c10 = bottom(2 * ns);
        let c01 = l1;
        let c11 = [-l1[0], l1[1]];
        let mut ids = vec![usize::MAX; (2 * ns + 1) * (2 * nt + 1)];
        for ii in 0..=2 * ns {
            for jj in 0..=2 * nt {
                if role[ii * w2 + jj] == 0 {
                    continue;
                }
                let s = row_sig[jj][ii];
                let t = tau[jj];
                let mut fl = None;
                let p_loc: [f64; 2] = if ii == 0 || ii == 2 * ns {
                    let (p, u) = lpts[jj];
                    if ii == 0 {
                        fl = u.map(|u| (Flank::Left, u));
                        p
                    } else {
                        fl = u.map(|u| (Flank::Right, u));
                        [-p[0], p[1]]
                    }
                } else if jj == 2 * nt {
                    prof.tip_arc(2.0 * s - 1.0).p
                } else if jj == 0 {
                    let b = bottom(ii);
                    cart(b[0], b[1])
                } else {
                    let lp = pol(lpts[jj].0);
                    let rp = [-lp[0], lp[1]];
                    let bp = bottom(ii);
                    let tp = pol(prof.tip_arc(2.0 * s - 1.0).p);
                    let mut o = [0.0; 2];
                    let (al, be) = (alpha(t), t);
                    for c in 0..2 {
                        let ls = (1.0 - s) * lp[c] + s * rp[c];
                        let ls0 = (1.0 - s) * c00[c] + s * c10[c];
                        let ls1 = (1.0 - s) * c01[c] + s * c11[c];
                        o[c] = ls + al * (bp[c] - ls0) + be * (tp[c] - ls1);
                    }
                    cart(o[0], o[1])
                };
                let p = rot(p_loc, ak);
                let id = pts.add(p, role[ii * w2 + jj] == 1)?;
                if let Some((f, u)) = fl {
                    pts.flank[id] = Some((k + 1, f, u));
                }
                if k == 0 && jj == 0 && ii <= 2 * nc {
                    cut_a.push(id);
                }
                if k + 1 == opts.teeth && jj == 0 && ii >= 2 * (ns - nc) {
                    cut_b.push(id);
                }
                ids[ii * (2 * nt + 1) + jj] = id;
            }
        }
        blocks.push(Block {
            ni: ns,
            nj: nt,
            ids,
        });
        // rim block: I across (arc part), J from bore (0) to r_i (2nr)
        let mut ids = vec![usize::MAX; (2 * na + 1) * (2 * nr + 1)];
        for ii in 0..=2 * na {
            let a = bottom(ii + 2 * nc)[0];
            for jj in 0..=2 * nr {
                if ii % 2 == 1 && jj % 2 == 1 {
                    continue;
                }
                let r = if jj == 2 * nr {
                    ri
                } else if jj == 0 {
                    r_bore
                } else {
                    ri - (ri - r_bore) * rho[2 * nr - jj]
                };
                let p = rot(cart(a, r), ak);
                let id = pts.add(p, ii % 2 == 0 && jj % 2 == 0)?;
                if jj == 0 {
                    pts.bore[id] = true;
                }
                if k == 0 && ii == 0 {
                    cut_a.push(id);
                }
                if k + 1 == opts.teeth && ii == 2 * na {
                    cut_b.push(id);
                }
                ids[ii * (2 * nr + 1) + jj] = id;
            }
        }
        blocks.push(Block {
            ni: na,
            nj: nr,
            ids,
        });
    }

    // --- transverse cells: quadrilaterals, or triangles for wedges (each
    // quadrilateral split along its shorter diagonal; the diagonal's midside
    // point is the serendipity centre of the quadrilateral, inside the cell).
    if !matches!(
        opts.element,
        ElementKind::C3D20 | ElementKind::C3D20R | ElementKind::C3D15
    ) {
        return Err(err(format!("{name}: unsupported element kind")));
    }
    let wedges = opts.element == ElementKind::C3D15;
    let mut cells: Vec<(usize, usize, usize, Cell)> = Vec::new();
    for (bi, blk) in blocks.iter().enumerate() {
        let id = |p: Lp| blk.ids[p.0 * (2 * blk.nj + 1) + p.1];
        let mid_id = |pts: &mut Points, m: Mid| -> Result<usize, FlankError> {
            match m {
                Mid::Lattice(p) => Ok(id(p)),
                Mid::Straight(a, b) => {
                    let (xa, xb) = (pts.xy[id(a)], pts.xy[id(b)]);
                    pts.add([0.5 * (xa[0] + xb[0]), 0.5 * (xa[1] + xb[1])], false)
                }
            }
        };
        if bi % 2 == 0 {
            for (i, j, cell) in &layout {
                let cell = match cell {
                    LatticeCell::Quad(c, m) => {
                        let mut mi = [0; 4];
                        for k in 0..4 {
                            mi[k] = mid_id(&mut pts, m[k])?;
                        }
                        quad_cell(&mut pts, c.map(id), mi, wedges)?
                    }
                    LatticeCell::Tris(t) => {
                        let mut tris = Vec::with_capacity(t.len());
                        for (c, m) in t {
                            let mut mi = [0; 3];
                            for k in 0..3 {
                                mi[k] = mid_id(&mut pts, m[k])?;
                            }
                            tris.push((c.map(id), mi));
                        }
                        Cell::Tris(tris)
                    }
                };
                cells.push((bi, *i, *j, cell));
            }
            continue;
        }
        for i in 0..blk.ni {
            for j in 0..blk.nj {
                let (i0, j0) = (2 * i, 2 * j);
                let c = [(i0, j0), (i0 + 2, j0), (i0 + 2, j0 + 2), (i0, j0 + 2)];
                let m = [
                    (i0 + 1, j0),
                    (i0 + 2, j0 + 1),
                    (i0 + 1, j0 + 2),
                    (i0, j0 + 1),
                ];
                cells.push((bi, i, j, quad_cell(&mut pts, c.map(id), m.map(id), wedges)?));
            }
        }
    }

    // --- extrusion.
    let b = spec.face_width;
    let nz = if opts.face_layers > 0 {
        opts.face_layers
    } else {
        ((b / opts.base_size).ceil() as usize).max(1)
    };
    let np = pts.xy.len();
    let nk = 2 * nz + 1;
    let mut node3 = vec![usize::MAX; np * nk];
    let mut mesh = Mesh::new();
    let mut flank_uv = HashMap::new();
    let mut flank_sets: HashMap<String, Vec<usize>> = HashMap::new();
    let mut bore = Vec::new();
    for kk in 0..nk {
        let zz = b * kk as f64 / (2 * nz) as f64;
        let phi = prof.twist_rate * zz;
        let (sn, cs) = phi.sin_cos();
        for p in 0..np {
            if kk % 2 == 1 && !pts.corner[p] {
                continue;
            }
            let [x, y] = pts.xy[p];
            let id = mesh.coords.len();
            mesh.add_node(id as u64 + 1, [cs * x - sn * y, sn * x + cs * y, zz])
                .map_err(|_| err("duplicate node label".into()))?;
            node3[p * nk + kk] = id;
            if let Some((t, f, u)) = pts.flank[p] {
                flank_uv.insert(id, (u, zz));
                let nm = match f {
                    Flank::Left => format!("FLANK_L{t}"),
                    Flank::Right => format!("FLANK_R{t}"),
                };
                flank_sets.entry(nm).or_default().push(id);
            }
            if pts.bore[p] {
                bore.push(id);
            }
        }
    }
    let cut3 = |set: &[usize]| -> Vec<usize> {
        let mut v = Vec::new();
        for &p in set {
            for kk in 0..nk {
                let n = node3[p * nk + kk];
                if n != usize::MAX {
                    v.push(n);
                }
            }
        }
        v
    };
    let (ca, cb) = (cut3(&cut_a), cut3(&cut_b));

    // --- elements.
    let kind = opts.element;
    let mut quality = Quality::empty();
    for (bi, i, j, cell) in cells {
        // transverse cells → (corner, midside) point triples or quads
        let shapes: Vec<(Vec<usize>, Vec<usize>)> = match cell {
            Cell::Quad(c, m) => vec![(c.to_vec(), m.to_vec())],
            Cell::Tris(t) => t.iter().map(|(c, m)| (c.to_vec(), m.to_vec())).collect(),
        };
        for (c, m) in &shapes {
            for l in 0..nz {
                let (k0, km, k1) = (2 * l, 2 * l + 1, 2 * l + 2);
                let mut nodes = Vec::with_capacity(kind.node_count());
                for k in [k0, k1] {
                    nodes.extend(c.iter().map(|&p| node3[p * nk + k]));
                }
                for k in [k0, k1] {
                    nodes.extend(m.iter().map(|&p| node3[p * nk + k]));
                }
                nodes.extend(c.iter().map(|&p| node3[p * nk + km]));
                let label = mesh.elements.len() as u64 + 1;
                let x: Vec<[f64; 3]> = nodes.iter().map(|&n| mesh.coords[n]).collect();
                check_jacobian(kind, &x).map_err(|e| match e.into_error(label, kind) {
                    FlankError::Element {
                        label,
                        kind,
                        message,
                    } => FlankError::Element {
                        label,
                        kind,
                        message: format!(
                            "{message} (gear sector {name}: tooth {} {} block, cell ({i}, {j}) of {}×{}, layer {})",
                            bi / 2 + 1,
                            if bi % 2 == 0 { "upper" } else { "rim" },
                            blocks[bi].ni,
                            blocks[bi].nj,
                            l + 1
                        ),
                    },
                    other => other,
                })?;
                quality.add(kind, &x);
                mesh.add_element(label, kind, nodes)
                    .map_err(|_| err("duplicate element label".into()))?;
            }
        }
    }
    for (nm, v) in flank_sets {
        mesh.extend_node_set(&nm, v);
    }
    mesh.extend_node_set("BORE", bore);
    mesh.extend_node_set("CUT_A", ca);
    mesh.extend_node_set("CUT_B", cb);
    let n = mesh.node_count();
    mesh.extend_node_set("NALL", 0..n);
    let ne = mesh.elements.len();
    mesh.extend_element_set("EALL", 0..ne);
    Ok(GearSectorMesh {
        mesh,
        flank_uv,
        quality,
    })
}

/// What [`modify_flanks`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct FlankModificationReport {
    /// Flank nodes moved.
    pub nodes: usize,
    /// Largest and smallest offset applied (mm; positive = material removed).
    pub max_offset_mm: f64,
    pub min_offset_mm: f64,
}

/// Applies a flank modification (micro-geometry, measured profile) to a
/// sector mesh: every flank node (corner and midside) moves along the
/// nominal outward normal at its (u, z) by −offset(flank, u, z), so it lies
/// on the modified surface [`crate::geometry::flank::FlankSurface::point`].
///
/// Only flank nodes move: modifications are micrometres, the first element
/// layer is at least the flank size (≥ 0.075 mm) thick. Every element that
/// touches a moved node is Jacobian-checked again; an inverted one is an
/// error naming it (the modification is then too large for that mesh).
/// Works on meshes from either mesher (it only needs `flank_uv` and the
/// `FLANK_L<k>`/`FLANK_R<k>` sets with the sector's tooth numbering).
pub fn modify_flanks(
    sector: &mut GearSectorMesh,
    profile: &ToothProfile,
    modification: &crate::geometry::micro::FlankModification,
) -> Result<FlankModificationReport, FlankError> {
    let pitch = profile.angular_pitch();
    let mut report = FlankModificationReport {
        nodes: 0,
        max_offset_mm: f64::NEG_INFINITY,
        min_offset_mm: f64::INFINITY,
    };
    let mut moved = vec![false; sector.mesh.node_count()];
    let mut sets: Vec<(String, Vec<usize>)> = sector
        .mesh
        .node_sets
        .iter()
        .filter(|(k, _)| k.starts_with("FLANK_L") || k.starts_with("FLANK_R"))
        .map(|(k, v)| (k.clone(), v.clone()))
        .collect();
    sets.sort();
    for (set, nodes) in sets {
        let flank = if set.starts_with("FLANK_L") {
            Flank::Left
        } else {
            Flank::Right
        };
        let tooth: usize = set[7..]
            .parse()
            .map_err(|_| err(format!("node set {set}: no tooth number")))?;
        for n in nodes {
            if moved[n] {
                continue;
            }
            let &(u, z) = sector
                .flank_uv
                .get(&n)
                .ok_or_else(|| err(format!("flank node {} of {set} has no (u, v)", n + 1)))?;
            let o = modification.offset(flank, u, z);
            if !o.is_finite() {
                return Err(err(format!(
                    "flank modification is not finite at u = {u}, z = {z} ({set})"
                )));
            }
            let nrm = profile.surface(flank, flank_segment(profile, u), z).n;
            let q = rot([nrm[0], nrm[1]], (tooth - 1) as f64 * pitch);
            let x = &mut sector.mesh.coords[n];
            x[0] -= o * q[0];
            x[1] -= o * q[1];
            x[2] -= o * nrm[2];
            moved[n] = true;
            report.nodes += 1;
            report.max_offset_mm = report.max_offset_mm.max(o);
            report.min_offset_mm = report.min_offset_mm.min(o);
        }
    }
    if report.nodes == 0 {
        report.max_offset_mm = 0.0;
        report.min_offset_mm = 0.0;
    }
    for (e, el) in sector.mesh.elements.iter().enumerate() {
        if el.nodes.iter().any(|&n| moved[n]) {
            check_jacobian(el.kind, &sector.mesh.element_coords(e)).map_err(|j| {
                match j.into_error(el.label, el.kind) {
                    FlankError::Element {
                        label,
                        kind,
                        message,
                    } => FlankError::Element {
                        label,
                        kind,
                        message: format!(
                            "{message} (after applying the flank modification: offsets {:.4} … {:.4} mm; refine less or reduce the modification)",
                            report.min_offset_mm, report.max_offset_mm
                        ),
                    },
                    other => other,
                }
            })?;
        }
    }
    Ok(report)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Hand, RackProfile};
    use std::time::Instant;

    fn pinion() -> GearSpec {
        GearSpec {
            teeth: 13,
            normal_module: 3.8,
            normal_pressure_angle: 20f64.to_radians(),
            helix_angle: 0.0,
            hand: Hand::Right,
            face_width: 13.3,
            profile_shift: 0.3,
            rack: RackProfile::default(),
            tip_diameter: Some(58.7),
            bore_diameter: 20.0,
        }
    }

    fn helical() -> GearSpec {
        GearSpec {
            teeth: 21,
            normal_module: 15.0,
            normal_pressure_angle: 20f64.to_radians(),
            helix_angle: 20f64.to_radians(),
            hand: Hand::Right,
            face_width: 180.0,
            profile_shift: 0.0,
            rack: RackProfile::default(),
            tip_diameter: None,
            bore_diameter: 150.0,
        }
    }

    fn report(tag: &str, m: &GearSectorMesh, t: f64) {
        println!(
            "{tag}: {} nodes, {} elements, min scaled Jacobian {:.4}, max aspect ratio {:.2}, {:.3} s",
            m.mesh.node_count(),
            m.mesh.elements.len(),
            m.quality.min_scaled_jacobian,
            m.quality.max_aspect_ratio,
            t
        );
    }

    #[test]
    fn gear_sector_pinion_valid() {
        for kind in [ElementKind::C3D20, ElementKind::C3D15] {
            pinion_valid(kind);
        }
    }

    fn pinion_valid(kind: ElementKind) {
        let t = Instant::now();
        let opts = SectorOptions {
            flank_size: 0.5,
            base_size: 2.0,
            element: kind,
            ..Default::default()
        };
        let m = gear_sector(&pinion(), "pinion", &opts).unwrap();
        report(
            &format!("pinion {kind:?} fs 0.5"),
            &m,
            t.elapsed().as_secs_f64(),
        );
        assert!(m.quality.min_scaled_jacobian > 0.0);
        assert!(m.mesh.elements.iter().all(|e| e.kind == kind));
        for e in 0..m.mesh.elements.len() {
            check_jacobian(kind, &m.mesh.element_coords(e)).unwrap();
        }
        for s in ["BORE", "CUT_A", "CUT_B", "NALL", "FLANK_L1", "FLANK_R3"] {
            assert!(!m.mesh.node_sets[s].is_empty(), "{s}");
        }
        assert_eq!(m.mesh.used_nodes().iter().filter(|&&u| !u).count(), 0);
    }

    /// Exact surface point of tooth k (1-based sector numbering) at (u, z).
    fn exact(p: &ToothProfile, k: usize, f: Flank, u: f64, z: f64) -> [f64; 3] {
        let sp = p.surface(f, flank_segment(p, u), z);
        let q = rot([sp.p[0], sp.p[1]], (k - 1) as f64 * p.angular_pitch());
        [q[0], q[1], sp.p[2]]
    }

    fn check_flank_nodes(spec: &GearSpec, m: &GearSectorMesh, teeth: usize) -> f64 {
        let p = ToothProfile::new(spec, "g").unwrap();
        let mut worst = 0.0f64;
        let mut count = 0;
        for k in 1..=teeth {
            for (f, nm) in [
                (Flank::Left, format!("FLANK_L{k}")),
                (Flank::Right, format!("FLANK_R{k}")),
            ] {
                for &n in &m.mesh.node_sets[&nm] {
                    let (u, z) = m.flank_uv[&n];
                    let e = exact(&p, k, f, u, z);
                    let x = m.mesh.coords[n];
                    let d = ((x[0] - e[0]).powi(2) + (x[1] - e[1]).powi(2) + (x[2] - e[2]).powi(2))
                        .sqrt();
                    worst = worst.max(d);
                    count += 1;
                }
            }
        }
        assert_eq!(count, m.flank_uv.len());
        worst
    }

    /// Max deviation of the elements' quadratic flank edges (transverse and
    /// axial) from the exact flank, at ξ = ±1/2 of each edge whose three nodes
    /// are flank nodes (at ξ = 0 the edge passes through its exact midside
    /// node). Distance measured in the transverse plane after untwisting the
    /// point by φ(z): equal to the normal distance for spur gears, an upper
    /// bound of it for helical ones.
    fn flank_edge_deviation(spec: &GearSpec, m: &GearSectorMesh) -> f64 {
        let p = ToothProfile::new(spec, "g").unwrap();
        let pitch = p.angular_pitch();
        let mut worst = 0.0f64;
        for el in &m.mesh.elements {
            for e in crate::fem::element::edges(el.kind) {
                let ns = [el.nodes[e[0]], el.nodes[e[1]], el.nodes[e[2]]];
                let fl: Vec<_> = ns.iter().map(|n| m.flank_uv.get(n)).collect();
                if fl.iter().any(|f| f.is_none()) {
                    continue;
                }
                let us: Vec<f64> = fl.iter().map(|f| f.unwrap().0).collect();
                let (xa, xb, xm) = (
                    m.mesh.coords[ns[0]],
                    m.mesh.coords[ns[1]],
                    m.mesh.coords[ns[2]],
                );
                let (mut lo0, mut hi0) = (us[0].min(us[1]), us[0].max(us[1]));
                let du = 0.02 * (p.u_tip - p.u_form);
                lo0 -= du;
                hi0 += du;
                for xi in [-0.5f64, 0.5] {
                    let (na, nb, nm) =
                        (0.5 * xi * (xi - 1.0), 0.5 * xi * (xi + 1.0), 1.0 - xi * xi);
                    let x: Vec<f64> = (0..3)
                        .map(|c| na * xa[c] + nb * xb[c] + nm * xm[c])
                        .collect();
                    // untwist, then rotate back to tooth 0
                    let q = rot([x[0], x[1]], p.twist_rate * x[2]);
                    let a = q[0].atan2(q[1]);
                    let k = (a / pitch).round();
                    let q = rot(q, -k * pitch);
                    let f = if q[0] < 0.0 {
                        Flank::Left
                    } else {
                        Flank::Right
                    };
                    let d2 = |u: f64| {
                        let e = p.point(f, flank_segment(&p, u)).p;
                        (e[0] - q[0]).powi(2) + (e[1] - q[1]).powi(2)
                    };
                    let (mut lo, mut hi) = (lo0, hi0);
                    let gr = 0.5 * (5f64.sqrt() - 1.0);
                    for _ in 0..100 {
                        let a = hi - gr * (hi - lo);
                        let b = lo + gr * (hi - lo);
                        if d2(a) < d2(b) {
                            hi = b;
                        } else {
                            lo = a;
                        }
                    }
                    worst = worst.max(d2(0.5 * (lo + hi)).sqrt());
                }
            }
        }
        worst
    }

    #[test]
    fn gear_sector_flank_nodes_exact() {
        let spec = pinion();
        let mut nodes = Vec::new();
        for (fs, kind) in [
            (0.5, ElementKind::C3D20),
            (0.1, ElementKind::C3D20),
            (0.1, ElementKind::C3D15),
        ] {
            let t = Instant::now();
            let opts = SectorOptions {
                flank_size: fs,
                base_size: 2.0,
                element: kind,
                ..Default::default()
            };
            let m = gear_sector(&spec, "pinion", &opts).unwrap();
            report(
                &format!("pinion {kind:?} fs {fs}"),
                &m,
                t.elapsed().as_secs_f64(),
            );
            let d = check_flank_nodes(&spec, &m, 3);
            let dev = flank_edge_deviation(&spec, &m);
            println!("{kind:?} fs {fs}: flank node distance max {d:.3e} mm, flank edge deviation max {dev:.3e} mm");
            assert!(d < 1e-9, "{d}");
            // observed: 9.1e-4 mm at fs 0.5, 5.6e-5 mm at fs 0.1
            if fs <= 0.1 {
                assert!(dev < 1e-3, "{dev}");
            }
            nodes.push(m.mesh.node_count());
        }
        // wedges coarsen 2:1 inside the tooth: fewer nodes than the hex20
        // mesh of the same flank size although each quad became two wedges
        // (observed 115 371 against 206 337)
        assert!((nodes[2] as f64) < 0.7 * nodes[1] as f64, "{nodes:?}");
    }

    #[test]
    fn gear_sector_helical_valid() {
        let spec = helical();
        for kind in [ElementKind::C3D20, ElementKind::C3D15] {
            let t = Instant::now();
            let opts = SectorOptions {
                flank_size: 5.0,
                base_size: 20.0,
                face_layers: 6,
                element: kind,
                ..Default::default()
            };
            let m = gear_sector(&spec, "gear", &opts).unwrap();
            report(
                &format!("helical {kind:?} fs 5"),
                &m,
                t.elapsed().as_secs_f64(),
            );
            assert!(m.quality.min_scaled_jacobian > 0.0);
            let d = check_flank_nodes(&spec, &m, 3);
            let dev = flank_edge_deviation(&spec, &m);
            println!(
                "helical {kind:?}: flank node distance max {d:.3e} mm, flank edge deviation max {dev:.3e} mm"
            );
            assert!(d < 1e-9, "{d}");
        }
    }

    #[test]
    fn gear_sector_clamped_bore_solve() {
        use crate::fem::material::Material;
        use crate::fem::model::{Dirichlet, Model, NodalForce};
        use crate::fem::static_analysis::{solve_static, SolveOptions};
        let spec = pinion();
        let opts = SectorOptions {
            flank_size: 1.0,
            base_size: 2.0,
            ..Default::default()
        };
        let m = gear_sector(&spec, "pinion", &opts).unwrap();
        let p = ToothProfile::new(&spec, "g").unwrap();
        // loaded node: a FLANK_R2 node near the pitch circle, mid face width
        let set = &m.mesh.node_sets["FLANK_R2"];
        let r_ref = p.geometry.reference_radius;
        let zm = 0.5 * spec.face_width;
        let &n = set
            .iter()
            .min_by(|&&a, &&b| {
                let f = |i: usize| {
                    let x = m.mesh.coords[i];
                    (x[0].hypot(x[1]) - r_ref).abs() + (x[2] - zm).abs()
                };
                f(a).partial_cmp(&f(b)).unwrap()
            })
            .unwrap();
        let (u, z) = m.flank_uv[&n];
        let sp = p.surface(Flank::Right, flank_segment(&p, u), z);
        let q = rot([sp.n[0], sp.n[1]], p.angular_pitch());
        let dir = [-q[0], -q[1], -sp.n[2]]; // pushes into the tooth
        let mut model = Model {
            materials: vec![Material::new("steel", 206e3, 0.3).unwrap()],
            element_material: vec![0; m.mesh.elements.len()],
            ..Default::default()
        };
        for &b in &m.mesh.node_sets["BORE"] {
            for c in 0..3 {
                model.dirichlet.push(Dirichlet {
                    node: b,
                    component: c,
                    value: 0.0,
                });
            }
        }
        for c in 0..3 {
            model.forces.push(NodalForce {
                node: n,
                component: c,
                value: dir[c],
            });
        }
        model.mesh = m.mesh;
        let t = Instant::now();
        let sol = solve_static(
            &model,
            &SolveOptions {
                threads: 2,
                ..Default::default()
            },
        )
        .unwrap();
        let d = &sol.displacement[3 * n..3 * n + 3];
        let along = d[0] * dir[0] + d[1] * dir[1] + d[2] * dir[2];
        let norm = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        println!(
            "solve: {} dofs, {:.3} s, loaded node displacement {norm:.3e} mm, along force {along:.3e} mm",
            sol.stats.dofs,
            t.elapsed().as_secs_f64()
        );
        assert!(along > 0.0 && along > 0.5 * norm, "{along} {norm}");
    }

    /// Conformity: every face used once (a boundary face) lies on the bore,
    /// a cut face, an end face or the outer surface (radius ≥ root radius);
    /// CUT_A / CUT_B lie on their planes, BORE on the bore circle.
    #[test]
    fn gear_sector_conforming_and_sets() {
        for kind in [ElementKind::C3D20, ElementKind::C3D15] {
            conforming_and_sets(kind);
        }
    }

    fn conforming_and_sets(kind: ElementKind) {
        use crate::fem::element::face_nodes;
        let spec = pinion();
        let p = ToothProfile::new(&spec, "g").unwrap();
        let m = gear_sector(
            &spec,
            "pinion",
            &SectorOptions {
                element: kind,
                ..Default::default()
            },
        )
        .unwrap();
        let mut faces: HashMap<Vec<usize>, usize> = HashMap::new();
        let nfaces = if kind == ElementKind::C3D15 { 5 } else { 6 };
        for el in &m.mesh.elements {
            for f in 1..=nfaces {
                let fnodes = face_nodes(kind, f).unwrap();
                let corners = fnodes.len() / 2;
                let mut k: Vec<usize> = fnodes[..corners].iter().map(|&i| el.nodes[i]).collect();
                k.sort_unstable();
                *faces.entry(k).or_default() += 1;
            }
        }
        assert!(faces.values().all(|&c| c <= 2));
        let inset = |nm: &str, n: usize| m.mesh.node_sets[nm].binary_search(&n).is_ok();
        let rf = p.geometry.root_radius;
        let mut boundary = 0;
        for (k, &c) in &faces {
            if c == 2 {
                continue;
            }
            boundary += 1;
            let x: Vec<[f64; 3]> = k.iter().map(|&n| m.mesh.coords[n]).collect();
            let ok = x.iter().all(|q| q[2].abs() < 1e-12)
                || x.iter().all(|q| (q[2] - spec.face_width).abs() < 1e-9)
                || k.iter().all(|&n| inset("BORE", n))
                || k.iter().all(|&n| inset("CUT_A", n))
                || k.iter().all(|&n| inset("CUT_B", n))
                || x.iter().all(|q| q[0].hypot(q[1]) > rf - 1e-9);
            assert!(ok, "interior crack or stray boundary face at {x:?}");
        }
        for &n in &m.mesh.node_sets["BORE"] {
            let q = m.mesh.coords[n];
            assert!((q[0].hypot(q[1]) - 10.0).abs() < 1e-9);
        }
        let h = PI / 13.0;
        for (nm, a) in [("CUT_A", -h), ("CUT_B", -h + 3.0 * 2.0 * h)] {
            for &n in &m.mesh.node_sets[nm] {
                let q = m.mesh.coords[n];
                assert!((q[0].atan2(q[1]) - a).abs() < 1e-9, "{nm}");
            }
        }
        // first-layer thickness normal to the flank (z = 0): distance from each
        // involute corner node to the next lattice line inside
        let mut lo = f64::INFINITY;
        let mut hi = 0.0f64;
        for el in &m.mesh.elements {
            for e in crate::fem::element::edges(kind).iter().take(nfaces - 2) {
                let (a, b) = (el.nodes[e[0]], el.nodes[e[1]]);
                for (s, t) in [(a, b), (b, a)] {
                    if let (Some(&(u, z)), None) = (m.flank_uv.get(&s), m.flank_uv.get(&t)) {
                        if z == 0.0 && u > p.u_form {
                            let (x, y) = (m.mesh.coords[s], m.mesh.coords[t]);
                            let d = (x[0] - y[0]).hypot(x[1] - y[1]);
                            lo = lo.min(d);
                            hi = hi.max(d);
                        }
                    }
                }
            }
        }
        println!("{kind:?}: boundary faces {boundary}; first layer across the involute (fs 0.5): {lo:.3} .. {hi:.3} mm");
    }

    /// Micro-geometry moves every flank node onto the modified surface
    /// (FlankSurface::point, with the same modification) and nothing else.
    #[test]
    fn modified_flanks_on_modified_surface() {
        use crate::geometry::flank::FlankSurface;
        use crate::geometry::micro::{FlankModification, MicroGeometry, Relief, ReliefShape};
        let spec = pinion();
        let p = ToothProfile::new(&spec, "pinion").unwrap();
        let micro = MicroGeometry {
            tip_relief: Some(Relief {
                amount: 0.020,
                length: 2.0,
                shape: ReliefShape::Linear,
            }),
            lead_crowning: 0.010,
            helix_slope_deviation: 0.005,
            ..Default::default()
        };
        let fm = FlankModification::new(&micro, &p, p.u_form + 0.05, spec.face_width).unwrap();
        for kind in [ElementKind::C3D20, ElementKind::C3D15] {
            let opts = SectorOptions {
                flank_size: 0.5,
                base_size: 2.0,
                element: kind,
                ..Default::default()
            };
            let mut m = gear_sector(&spec, "pinion", &opts).unwrap();
            let before = m.mesh.coords.clone();
            let rep = modify_flanks(&mut m, &p, &fm).unwrap();
            assert_eq!(rep.nodes, m.flank_uv.len());
            assert!(
                rep.max_offset_mm > 0.019 && rep.max_offset_mm < 0.040,
                "{rep:?}"
            );
            let mut worst = 0.0f64;
            for k in 1..=3 {
                for (f, nm) in [
                    (Flank::Left, format!("FLANK_L{k}")),
                    (Flank::Right, format!("FLANK_R{k}")),
                ] {
                    let surf = FlankSurface::new(p.clone(), f, k, Some(fm.clone())).unwrap();
                    for &n in &m.mesh.node_sets[&nm] {
                        let (u, z) = m.flank_uv[&n];
                        let e = surf.point(u, z);
                        let x = m.mesh.coords[n];
                        let d =
                            ((x[0] - e[0]).powi(2) + (x[1] - e[1]).powi(2) + (x[2] - e[2]).powi(2))
                                .sqrt();
                        worst = worst.max(d);
                    }
                }
            }
            println!("{kind:?}: {rep:?}; max distance to the modified surface {worst:.2e} mm");
            assert!(worst < 1e-12, "{worst}");
            for (n, (a, b)) in before.iter().zip(&m.mesh.coords).enumerate() {
                if !m.flank_uv.contains_key(&n) {
                    assert_eq!(a, b);
                }
            }
        }
    }

    #[test]
    fn gear_sector_full_ring_closes() {
        let spec = pinion();
        let opts = SectorOptions {
            teeth: 13,
            flank_size: 1.0,
            base_size: 2.0,
            face_layers: 2,
            ..Default::default()
        };
        let m = gear_sector(&spec, "pinion", &opts).unwrap();
        assert_eq!(m.mesh.node_sets["CUT_A"], m.mesh.node_sets["CUT_B"]);
        let one = gear_sector(
            &spec,
            "pinion",
            &SectorOptions {
                teeth: 1,
                ..opts.clone()
            },
        )
        .unwrap();
        // 13 pitches minus the 13 shared cut lines
        let cut = one.mesh.node_sets["CUT_A"].len();
        assert_eq!(m.mesh.node_count(), 13 * (one.mesh.node_count() - cut));
        println!(
            "full ring: {} nodes, {} elements",
            m.mesh.node_count(),
            m.mesh.elements.len()
        );
    }
}
