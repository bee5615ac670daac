//! gmsh gear-sector mesher: the same sector, node sets and conventions as the
//! native [`crate::mesh::gear_sector`], meshed unstructured by gmsh.
//!
//! Construction:
//! * **Transverse profile** (z = 0, gmsh geo kernel) of `teeth` consecutive
//!   teeth: per tooth the left root half arc, left fillet, left involute, tip
//!   arc, right involute, right fillet and right root half arc; involutes and
//!   trochoidal fillets are splines through exact points of
//!   [`ToothProfile::point`] (at most `flank_size`/8 apart, at least 64 on
//!   the involute and 48 on the fillet), the root, tip and bore arcs are
//!   circle arcs (exact); the sector is closed by the radial cut lines at the gap centres
//!   (`CUT_A` at −π/z from +y, `CUT_B` after the last tooth) and the bore arc.
//!   A full ring (`teeth` = z) is built as two surfaces sharing their radial
//!   lines; the cut at −π/z is then both CUT_A and CUT_B.
//! * **Size field**: a `Distance` field from all flank curves (involutes and
//!   fillets) feeds a `Threshold` field: size `flank_size` on the flanks,
//!   growing linearly with the distance d from them, size = flank_size +
//!   0.25 d (so neighbouring elements grow by ≈ 1.25, like the native
//!   mesher's grading), up to `base_size`. Sizes from points, curvature and
//!   boundary extension are off, so the field alone sets the sizes.
//! * **2D mesh**: wedge15: Frontal-Delaunay triangles (`Mesh.Algorithm = 6`);
//!   hex20: Delaunay triangles (`Mesh.Algorithm = 5`) recombined into
//!   quadrilaterals by the Blossom full-quad algorithm
//!   (`Mesh.RecombinationAlgorithm = 3`: no triangle is left; Blossom alone
//!   leaves a few). Of the algorithms tried on the seed 002 pinion this pair
//!   gave the best quadrilaterals; the quad-oriented algorithm 8 crashes in
//!   Debian's gmsh 4.8.4 and is not used.
//! * **Extrusion** along z ∈ [0, b] in `face_layers` layers (0: ⌈b/base_size⌉),
//!   recombined (quads → hexahedra, triangles → prisms). Spur: translation;
//!   helical: gmsh `twist` about the z axis by twist_rate · b, so every
//!   section at height z is the transverse section rotated by
//!   φ(z) = twist_rate · z, as on the helicoid [`ToothProfile::surface`].
//! * **Second order**: `Mesh.SecondOrderIncomplete = 1`, order 2: 20-node
//!   hexahedra (gmsh type 17) and 15-node prisms (type 18), permuted into
//!   CalculiX order, `ccx[i] = gmsh[perm[i]]` (derivation in
//!   [`crate::mesh::msh`]; a test checks it against gmsh's own reference
//!   node coordinates, `gmshModelMeshGetElementProperties`):
//!
//!   | element | perm |
//!   |---|---|
//!   | C3D20 ← 17 | 0 1 2 3 4 5 6 7 8 11 13 9 16 18 19 17 10 12 14 15 |
//!   | C3D15 ← 18 | 0 1 2 3 4 5 6 9 7 12 14 13 8 10 11 |
//!
//!   Helical: gmsh puts the midside node of an axial edge inside the volume
//!   on the chord; it is moved onto the helix through the edge's ends (the
//!   sections rotate, as in the native mesher).
//! * **Exact flanks**: every node of a flank set (corner and midside) is
//!   moved onto the exact surface: untwisted by −φ(z), rotated back to tooth
//!   0, the closest point of the exact transverse profile is found by Newton
//!   on the unified profile parameter u (involute roll angle for u ≥ u_form,
//!   fillet u = u_form − t), and the exact point [`ToothProfile::surface`]
//!   at (u, z) is rotated back to the node's tooth. The moves are the
//!   spline's deviation from the exact curve (reported in
//!   [`GmshSectorReport::max_snap_mm`]: 2e-5 to 4e-5 mm at flank sizes 1 and
//!   0.5 mm, 3e-7 mm at 0.1 mm on the seed 002 pinion).
//! * Every element is checked ([`check_jacobian`]; an inverted or degenerate
//!   element is an error naming it and where it is) and the quality figures
//!   are computed as the native mesher's ([`Quality`]). Hexahedra from
//!   recombined triangles are less regular than the native mesher's (min
//!   scaled Jacobian 0.27–0.44 on the seed 002 pinion for flank sizes
//!   1–0.1 mm at base size 1 mm, native 0.63–0.88); wedges 0.70–0.96.
//!   For the same flank size gmsh needs fewer nodes (seed 002 pinion,
//!   0.1 mm: 243 000 hex20 / 259 000 wedge15 nodes, native 396 000 /
//!   493 000): the size grows away from the flank in every direction.
//!
//! Node sets (from gmsh physical groups of the extruded lateral surfaces):
//! `FLANK_L<k>` / `FLANK_R<k>` (involute + fillet, k = 1..=teeth, tooth k is
//! the profile's tooth k − 1 rotated by −2π(k−1)/z, left/right as
//! [`Flank`]), `BORE`, `CUT_A`, `CUT_B`, `NALL`; element set `EALL`. Node and
//! element labels are gmsh's tags, so a `.msh` written alongside
//! ([`gmsh_sector_with_msh`]) and the deck agree.

use std::collections::{BTreeMap, HashMap};
use std::f64::consts::PI;
use std::path::Path;
use std::time::Instant;

use super::Session;
use crate::error::FlankError;
use crate::fem::element::{check_jacobian, edges};
use crate::fem::mesh::{ElementKind, Mesh};
use crate::geometry::rack::{Flank, Segment, ToothProfile};
use crate::geometry::GearSpec;
use crate::mesh::gear_sector::{flank_segment, GearSectorMesh, Quality, SectorOptions};
use crate::mesh::msh::{GMSH_HEX20_TO_CCX, GMSH_PRISM15_TO_CCX};

type Result<T> = std::result::Result<T, FlankError>;

/// Figures of one gmsh sector mesh.
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct GmshSectorReport {
    /// Largest move of a flank node onto the exact surface (mm).
    pub max_snap_mm: f64,
    /// Wall time in gmsh (geometry, 2D/3D mesh, order 2) (s).
    pub gmsh_s: f64,
    /// Wall time of the whole call (s).
    pub total_s: f64,
    /// Elements across the face width.
    pub layers: usize,
}

fn err(msg: String) -> FlankError {
    FlankError::Model(format!("gmsh gear sector: {msg}"))
}

/// Clockwise rotation by `a` (from +y towards +x), the sector's tooth angle.
fn rot(p: [f64; 2], a: f64) -> [f64; 2] {
    let (s, c) = a.sin_cos();
    [c * p[0] + s * p[1], -s * p[0] + c * p[1]]
}

/// Point at polar angle `a` from +y (towards +x) and radius `r`.
fn cart(a: f64, r: f64) -> [f64; 2] {
    [r * a.sin(), r * a.cos()]
}

/// Closest points on the exact transverse profile of one flank (tooth 0).
struct Snapper<'a> {
    prof: &'a ToothProfile,
    lo: f64,
    hi: f64,
    /// (u, point) samples of the right flank over [lo, hi].
    samples: Vec<(f64, [f64; 2])>,
}

impl<'a> Snapper<'a> {
    fn new(prof: &'a ToothProfile) -> Self {
        let (lo, hi) = (prof.u_form - 1.0, prof.u_tip);
        let mut samples = Vec::new();
        const N: usize = 256;
        for i in 0..=N {
            // fillet, t from 1 to 0
            let u = lo + i as f64 / N as f64;
            samples.push((u, Self::p(prof, u)));
        }
        for i in 1..=N {
            // involute, uniform in arc length (∝ u²)
            let (a, b) = (prof.u_form, prof.u_tip);
            let u = (a * a + (b * b - a * a) * i as f64 / N as f64).sqrt();
            samples.push((u, Self::p(prof, u)));
        }
        Snapper {
            prof,
            lo,
            hi,
            samples,
        }
    }

    fn p(prof: &ToothProfile, u: f64) -> [f64; 2] {
        prof.point(Flank::Right, flank_segment(prof, u)).p
    }

    /// dp/du of the right flank (the fillet's u runs against t).
    fn dp(&self, u: f64) -> [f64; 2] {
        match flank_segment(self.prof, u) {
            Segment::Involute(v) => self.prof.tangent(Flank::Right, Segment::Involute(v)),
            Segment::Fillet(t) => {
                let d = self.prof.tangent(Flank::Right, Segment::Fillet(t));
                [-d[0], -d[1]]
            }
        }
    }

    /// Unified parameter u of the point of `flank` closest to `q` (tooth 0, z = 0).
    fn closest(&self, flank: Flank, q: [f64; 2]) -> f64 {
        let q = match flank {
            Flank::Right => q,
            Flank::Left => [-q[0], q[1]],
        };
        let d2 = |p: [f64; 2]| (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2);
        let mut best = 0;
        for (i, s) in self.samples.iter().enumerate() {
            if d2(s.1) < d2(self.samples[best].1) {
                best = i;
            }
        }
        let mut u = self.samples[best].0;
        // Newton on g(u) = (p − q)·p′ = 0, g′ = p′·p′ + (p − q)·p″ (p″ by differences)
        for _ in 0..50 {
            let p = Self::p(self.prof, u);
            let d = self.dp(u);
            let r = [p[0] - q[0], p[1] - q[1]];
            let g = r[0] * d[0] + r[1] * d[1];
            let dd = d[0] * d[0] + d[1] * d[1];
            if !(dd > 0.0) {
                break;
            }
            let h = 1e-6;
            let (a, b) = (self.dp(u + h), self.dp(u - h));
            let p2 = [(a[0] - b[0]) / (2.0 * h), (a[1] - b[1]) / (2.0 * h)];
            let mut gp = dd + r[0] * p2[0] + r[1] * p2[1];
            if !(gp > 0.1 * dd) {
                gp = dd;
            }
            let un = (u - g / gp).clamp(self.lo, self.hi);
            let step = (un - u).abs();
            u = un;
            if step * dd.sqrt() < 1e-15 * self.prof.geometry.tip_radius {
                break;
            }
        }
        u
    }
}

/// Which named boundary a source curve of the transverse profile belongs to.
#[derive(Clone, Debug, PartialEq)]
enum Role {
    Flank(usize, Flank),
    Bore,
    Cut(usize),
}

/// Mesh `opts.teeth` teeth of `spec` with gmsh (see the module docs).
pub fn gmsh_sector(
    spec: &GearSpec,
    name: &str,
    opts: &SectorOptions,
    element: ElementKind,
) -> Result<GearSectorMesh> {
    gmsh_sector_with_msh(spec, name, opts, element, None).map(|(m, _)| m)
}

/// [`gmsh_sector`], also writing gmsh's mesh (with the exact flank nodes) as
/// a `.msh` 4.1 ASCII file to `msh` if given, and returning the figures.
pub fn gmsh_sector_with_msh(
    spec: &GearSpec,
    name: &str,
    opts: &SectorOptions,
    element: ElementKind,
    msh: Option<&Path>,
) -> Result<(GearSectorMesh, GmshSectorReport)> {
    let t_all = Instant::now();
    let prof = ToothProfile::new(spec, name)?;
    let z = spec.teeth as usize;
    let n = opts.teeth;
    if n == 0 || n > z {
        return Err(err(format!("{name}: {n} teeth requested of {z}")));
    }
    if !(opts.flank_size > 0.0 && opts.base_size >= opts.flank_size) {
        return Err(err(format!(
            "{name}: need 0 < flank_size ({}) ≤ base_size ({})",
            opts.flank_size, opts.base_size
        )));
    }
    let g = &prof.geometry;
    let (rf, rb) = (g.root_radius, g.base_radius);
    let r_bore = 0.5 * spec.bore_diameter;
    if !(r_bore > 0.0 && r_bore < rf) {
        return Err(err(format!(
            "{name}: bore radius {r_bore} mm must lie in (0, root radius {rf:.4} mm)"
        )));
    }
    let h = PI / z as f64;
    let pitch = 2.0 * h;
    let ar = prof.root_angle;
    if !(h - ar > 1e-9) {
        return Err(err(format!(
            "{name}: the fillets of neighbouring teeth meet (no root arc); not supported"
        )));
    }
    let b = spec.face_width;
    let twist = prof.twist_rate * b;
    if !(twist.abs() < 0.9 * PI) {
        return Err(err(format!(
            "{name}: section twist {twist:.3} rad over the face width is too large for one gmsh twist extrusion"
        )));
    }
    let nz = if opts.face_layers > 0 {
        opts.face_layers
    } else {
        ((b / opts.base_size).ceil() as usize).max(1)
    };
    let fs = opts.flank_size;
    let (uf, ut) = (prof.u_form, prof.u_tip);
    let inv_len = 0.5 * rb * (ut * ut - uf * uf);
    let ring = n == z;

    let t_gmsh = Instant::now();
    let s = Session::start()?;
    s.model_add(name)?;
    s.option("General.NumThreads", 1.0)?;
    s.option("Geometry.Tolerance", 1e-10 * g.tip_radius)?;

    // --- transverse geometry (z = 0)
    let pt = |p: [f64; 2]| s.geo_point([p[0], p[1], 0.0], 0.0);
    let origin = s.geo_point([0.0; 3], 0.0)?;
    // tooth k of the sector (0-based) is tooth 0 rotated clockwise by k·pitch
    let gap: Vec<i32> = (0..=n)
        .map(|j| {
            if ring && j == n {
                Ok(-1)
            } else {
                pt(cart(j as f64 * pitch - h, rf))
            }
        })
        .collect::<Result<_>>()?;
    let gap_tag = |j: usize| if ring && j == n { gap[0] } else { gap[j] };
    let mut roles: HashMap<i32, Role> = HashMap::new();
    let mut flank_curves = Vec::new();
    // per tooth: the seven boundary curves from gap j to gap j + 1 (clockwise)
    let mut tooth_curves: Vec<[i32; 7]> = Vec::new();
    // spline points at most flank_size / 8 apart (at least 64 / 48): the
    // flank nodes then move ≤ ≈ 1 µm onto the exact curve (the spline's ends
    // are its least accurate part, and fine meshes put nodes there)
    let fil_len: f64 = (1..=256)
        .map(|i| {
            let a = prof
                .point(Flank::Right, Segment::Fillet((i - 1) as f64 / 256.0))
                .p;
            let b = prof
                .point(Flank::Right, Segment::Fillet(i as f64 / 256.0))
                .p;
            (a[0] - b[0]).hypot(a[1] - b[1])
        })
        .sum();
    let spline_points = |len: f64, min: usize| ((8.0 * len / fs).ceil() as usize).clamp(min, 4000);
    let ni = spline_points(inv_len, 64);
    let nf = spline_points(fil_len, 48);
    for k in 0..n {
        let ak = k as f64 * pitch;
        let at = |p: [f64; 2]| pt(rot(p, ak));
        let fil = |f: Flank, t: f64| prof.point(f, Segment::Fillet(t)).p;
        let inv = |f: Flank, i: usize| {
            let u = if i == ni {
                ut
            } else {
                (uf * uf + (ut * ut - uf * uf) * i as f64 / ni as f64).sqrt()
            };
            prof.point(f, Segment::Involute(u)).p
        };
        // left flank: root end (t = 1) up to the tip corner
        let rl = at(fil(Flank::Left, 1.0))?;
        let mut fl_pts = vec![rl];
        for i in 1..nf {
            fl_pts.push(at(fil(Flank::Left, 1.0 - i as f64 / nf as f64))?);
        }
        let form_l = at(fil(Flank::Left, 0.0))?;
        fl_pts.push(form_l);
        let mut il_pts = vec![form_l];
        for i in 1..ni {
            il_pts.push(at(inv(Flank::Left, i))?);
        }
        let tip_l = at(inv(Flank::Left, ni))?;
        il_pts.push(tip_l);
        // right flank: tip corner down to the root end
        let tip_r = at(inv(Flank::Right, ni))?;
        let mut ir_pts = vec![tip_r];
        for i in (1..ni).rev() {
            ir_pts.push(at(inv(Flank::Right, i))?);
        }
        let form_r = at(fil(Flank::Right, 0.0))?;
        ir_pts.push(form_r);
        let mut fr_pts = vec![form_r];
        for i in 1..nf {
            fr_pts.push(at(fil(Flank::Right, i as f64 / nf as f64))?);
        }
        let rr = at(fil(Flank::Right, 1.0))?;
        fr_pts.push(rr);

        let c_root_l = s.geo_circle_arc(gap_tag(k), origin, rl)?;
        let c_fil_l = s.geo_spline(&fl_pts)?;
        let c_inv_l = s.geo_spline(&il_pts)?;
        let c_tip = s.geo_circle_arc(tip_l, origin, tip_r)?;
        let c_inv_r = s.geo_spline(&ir_pts)?;
        let c_fil_r = s.geo_spline(&fr_pts)?;
        let c_root_r = s.geo_circle_arc(rr, origin, gap_tag(k + 1))?;
        for c in [c_fil_l, c_inv_l] {
            roles.insert(c, Role::Flank(k + 1, Flank::Left));
            flank_curves.push(c);
        }
        for c in [c_inv_r, c_fil_r] {
            roles.insert(c, Role::Flank(k + 1, Flank::Right));
            flank_curves.push(c);
        }
        tooth_curves.push([
            c_root_l, c_fil_l, c_inv_l, c_tip, c_inv_r, c_fil_r, c_root_r,
        ]);
    }
    // parts (surfaces) and their radial boundary lines
    let bounds: Vec<usize> = if ring { vec![0, n / 2, n] } else { vec![0, n] };
    let mut bore_pt: HashMap<usize, i32> = HashMap::new();
    let mut radial: HashMap<usize, i32> = HashMap::new();
    for &j in &bounds {
        let jj = if ring && j == n { 0 } else { j };
        if radial.contains_key(&jj) {
            continue;
        }
        let bp = pt(cart(jj as f64 * pitch - h, r_bore))?;
        bore_pt.insert(jj, bp);
        let l = s.geo_line(bp, gap_tag(jj))?;
        radial.insert(jj, l);
        if jj == 0 {
            roles.insert(l, Role::Cut(0));
        } else if jj == n {
            roles.insert(l, Role::Cut(n));
        }
    }
    let wrap = |j: usize| if ring && j == n { 0 } else { j };
    let mut surfaces = Vec::new();
    for w in bounds.windows(2) {
        let (j0, j1) = (w[0], w[1]);
        // clockwise loop: up the radial line at j0, along the teeth, down at j1, bore back
        let mut lp: Vec<i32> = vec![radial[&wrap(j0)]];
        for c in &tooth_curves[j0..j1] {
            lp.extend_from_slice(c);
        }
        lp.push(-radial[&wrap(j1)]);
        let span = (j1 - j0) as f64 * pitch;
        let pieces = (span / (0.5 * PI)).ceil().max(1.0) as usize;
        let mut prev = bore_pt[&wrap(j1)];
        for i in 1..=pieces {
            let next = if i == pieces {
                bore_pt[&wrap(j0)]
            } else {
                let a = j1 as f64 * pitch - h - span * i as f64 / pieces as f64;
                pt(cart(a, r_bore))?
            };
            let c = s.geo_circle_arc(prev, origin, next)?;
            roles.insert(c, Role::Bore);
            lp.push(c);
            prev = next;
        }
        // counter-clockwise (normal +z): reversed
        let ccw: Vec<i32> = lp.iter().rev().map(|c| -c).collect();
        let cl = s.geo_curve_loop(&ccw)?;
        surfaces.push(s.geo_plane_surface(&[cl])?);
    }

    // --- mesh options and size field
    let hex = matches!(element, ElementKind::C3D20 | ElementKind::C3D20R);
    s.option("Mesh.MeshSizeFromPoints", 0.0)?;
    s.option("Mesh.MeshSizeFromCurvature", 0.0)?;
    s.option("Mesh.MeshSizeExtendFromBoundary", 0.0)?;
    s.option("Mesh.MeshSizeMax", opts.base_size)?;
    // hex: Delaunay + Blossom full-quad gave the best quadrilaterals here
    // (min scaled Jacobian 0.32 against 0.15 with Frontal-Delaunay)
    s.option("Mesh.Algorithm", if hex { 5.0 } else { 6.0 })?;
    s.option("Mesh.RecombineAll", if hex { 1.0 } else { 0.0 })?;
    s.option("Mesh.RecombinationAlgorithm", 3.0)?;
    s.option("Mesh.SecondOrderIncomplete", 1.0)?;
    let fd = s.field_add("Distance")?;
    let fc: Vec<f64> = flank_curves.iter().map(|&c| c as f64).collect();
    s.field_numbers(fd, "CurvesList", &fc)?;
    let longest = inv_len.max(2.0 * spec.normal_module);
    s.field_number(
        fd,
        "NumPointsPerCurve",
        ((4.0 * longest / fs).ceil() + 16.0).min(20000.0),
    )?;
    let ft = s.field_add("Threshold")?;
    s.field_number(ft, "InField", fd as f64)?;
    s.field_number(ft, "SizeMin", fs)?;
    s.field_number(ft, "SizeMax", opts.base_size)?;
    s.field_number(ft, "DistMin", 0.0)?;
    s.field_number(ft, "DistMax", (opts.base_size - fs) / 0.25)?;
    s.field_background(ft)?;

    // --- extrusion
    let dt: Vec<(i32, i32)> = surfaces.iter().map(|&t| (2, t)).collect();
    let layers = [nz as i32];
    if twist == 0.0 {
        s.geo_extrude(&dt, [0.0, 0.0, b], &layers, true)?;
    } else {
        s.geo_twist(
            &dt,
            [0.0; 3],
            [0.0, 0.0, b],
            [0.0, 0.0, 1.0],
            twist,
            &layers,
            true,
        )?;
    }
    s.geo_synchronize()?;

    // lateral surfaces: the one whose boundary holds a source curve
    let mut groups: BTreeMap<String, Vec<i32>> = BTreeMap::new();
    for (_, st) in s.entities(2)? {
        if surfaces.contains(&st) {
            continue;
        }
        for (_, c) in s.boundary(&[(2, st)])? {
            let name = match roles.get(&c.abs()) {
                Some(Role::Flank(k, Flank::Left)) => format!("FLANK_L{k}"),
                Some(Role::Flank(k, Flank::Right)) => format!("FLANK_R{k}"),
                Some(Role::Bore) => "BORE".to_string(),
                Some(Role::Cut(0)) => "CUT_A".to_string(),
                Some(Role::Cut(_)) => "CUT_B".to_string(),
                None => continue,
            };
            groups.entry(name).or_default().push(st);
        }
    }
    if ring {
        let a = groups.get("CUT_A").cloned().unwrap_or_default();
        groups.insert("CUT_B".into(), a);
    }
    let mut group_tags = BTreeMap::new();
    for (nm, tags) in &groups {
        let mut t = tags.clone();
        t.sort_unstable();
        t.dedup();
        group_tags.insert(nm.clone(), s.physical_group(2, &t, nm)?);
    }
    for k in 1..=n {
        for f in ["L", "R"] {
            if !group_tags.contains_key(&format!("FLANK_{f}{k}")) {
                return Err(err(format!(
                    "{name}: no extruded flank surface found for FLANK_{f}{k}"
                )));
            }
        }
    }
    let volumes: Vec<i32> = s.entities(3)?.iter().map(|&(_, t)| t).collect();
    s.physical_group(3, &volumes, "EALL")?;

    // --- mesh
    s.generate(3)?;
    s.set_order(2)?;
    let gmsh_s = t_gmsh.elapsed().as_secs_f64();

    let (gtype, kind, perm): (i32, ElementKind, &[usize]) = if hex {
        (17, element, &GMSH_HEX20_TO_CCX)
    } else {
        (18, ElementKind::C3D15, &GMSH_PRISM15_TO_CCX)
    };
    for t in s.element_types(3)? {
        if t != gtype {
            let p = s.element_properties(t)?;
            return Err(err(format!(
                "{name}: gmsh made elements of type {t} ({}) besides type {gtype}; \
                 recombination left triangles?",
                p.name
            )));
        }
    }
    let (etags, enodes) = s.elements_of_type(gtype)?;
    let nn = kind.node_count();
    if etags.is_empty() || enodes.len() != nn * etags.len() {
        return Err(err(format!(
            "{name}: gmsh returned {} elements with {} node tags",
            etags.len(),
            enodes.len()
        )));
    }
    let (ntags, ncoords) = s.nodes()?;
    let mut coord_of: HashMap<usize, [f64; 3]> = HashMap::with_capacity(ntags.len());
    for (i, &t) in ntags.iter().enumerate() {
        coord_of.insert(t, [ncoords[3 * i], ncoords[3 * i + 1], ncoords[3 * i + 2]]);
    }
    let mut used: Vec<usize> = enodes.clone();
    used.sort_unstable();
    used.dedup();
    let mut mesh = Mesh::new();
    for &t in &used {
        let x = *coord_of
            .get(&t)
            .ok_or_else(|| err(format!("{name}: element node {t} has no coordinates")))?;
        mesh.add_node(t as u64, x)
            .map_err(|_| err(format!("{name}: duplicate node tag {t}")))?;
    }
    for (e, &et) in etags.iter().enumerate() {
        let g = &enodes[nn * e..nn * (e + 1)];
        let nodes: Vec<usize> = perm
            .iter()
            .map(|&p| mesh.node(g[p] as u64).unwrap_or(usize::MAX))
            .collect();
        mesh.add_element(et as u64, kind, nodes)
            .map_err(|_| err(format!("{name}: duplicate element tag {et}")))?;
    }

    // --- helical: gmsh puts the midside node of an axial edge inside the
    // volume on the chord; put it on the helix through the edge's ends, as
    // the sections rotate (flank nodes are snapped below anyway)
    let mut moved: Vec<usize> = Vec::new();
    if prof.twist_rate != 0.0 {
        let k = prof.twist_rate;
        let untwist = |x: [f64; 3]| {
            let (sn, cs) = (k * x[2]).sin_cos();
            [cs * x[0] + sn * x[1], -sn * x[0] + cs * x[1]]
        };
        let tol = 1e-8 * g.tip_radius;
        let mut done = vec![false; mesh.node_count()];
        for e in 0..mesh.elements.len() {
            for ed in edges(kind) {
                let el = &mesh.elements[e];
                let (a, b, m) = (el.nodes[ed[0]], el.nodes[ed[1]], el.nodes[ed[2]]);
                let (xa, xb) = (mesh.coords[a], mesh.coords[b]);
                if done[m] || (xa[2] - xb[2]).abs() < tol {
                    continue;
                }
                let (pa, pb) = (untwist(xa), untwist(xb));
                if (pa[0] - pb[0]).hypot(pa[1] - pb[1]) > tol {
                    continue; // not an axial edge
                }
                let zm = 0.5 * (xa[2] + xb[2]);
                let p = [0.5 * (pa[0] + pb[0]), 0.5 * (pa[1] + pb[1])];
                let (sn, cs) = (k * zm).sin_cos();
                mesh.coords[m] = [cs * p[0] - sn * p[1], sn * p[0] + cs * p[1], zm];
                done[m] = true;
                moved.push(m);
            }
        }
    }

    // --- node sets; flank nodes onto the exact surface
    let snap = Snapper::new(&prof);
    let mut flank_uv = HashMap::new();
    let mut max_snap = 0.0f64;
    for (nm, &pg) in &group_tags {
        let tags = s.physical_group_nodes(2, pg)?;
        let idx: Vec<usize> = tags.iter().filter_map(|&t| mesh.node(t as u64)).collect();
        if idx.len() != tags.len() {
            return Err(err(format!(
                "{name}: {} nodes of {nm} are not element nodes",
                tags.len() - idx.len()
            )));
        }
        let flank = if let Some(k) = nm.strip_prefix("FLANK_L") {
            Some((k, Flank::Left))
        } else {
            nm.strip_prefix("FLANK_R").map(|k| (k, Flank::Right))
        };
        if let Some((k, f)) = flank {
            let k: usize = k
                .parse()
                .map_err(|_| err(format!("bad flank set name {nm}")))?;
            let ak = (k - 1) as f64 * pitch;
            for &i in &idx {
                let x = mesh.coords[i];
                let phi = prof.twist_rate * x[2];
                let (sn, cs) = phi.sin_cos();
                let q = [cs * x[0] + sn * x[1], -sn * x[0] + cs * x[1]];
                let q0 = rot(q, -ak);
                let u = snap.closest(f, q0);
                let sp = prof.surface(f, flank_segment(&prof, u), x[2]);
                let e = rot([sp.p[0], sp.p[1]], ak);
                let e = [e[0], e[1], x[2]];
                let d = ((e[0] - x[0]).powi(2) + (e[1] - x[1]).powi(2)).sqrt();
                max_snap = max_snap.max(d);
                mesh.coords[i] = e;
                flank_uv.insert(i, (u, x[2]));
            }
        }
        mesh.extend_node_set(nm, idx);
    }
    if let Some(path) = msh {
        for &i in moved.iter().chain(flank_uv.keys()) {
            s.set_node(mesh.node_labels[i] as usize, mesh.coords[i])?;
        }
        s.option("Mesh.MshFileVersion", 4.1)?;
        s.option("Mesh.Binary", 0.0)?;
        s.option("Mesh.SaveAll", 0.0)?;
        s.write(path)?;
    }
    drop(s);
    let nn_all = mesh.node_count();
    mesh.extend_node_set("NALL", 0..nn_all);
    let ne = mesh.elements.len();
    mesh.extend_element_set("EALL", 0..ne);

    // --- element checks and quality
    let mut quality = Quality::empty();
    for e in 0..ne {
        let x = mesh.element_coords(e);
        let label = mesh.elements[e].label;
        check_jacobian(kind, &x).map_err(|je| match je.into_error(label, kind) {
            FlankError::Element {
                label,
                kind,
                message,
            } => {
                let w = 1.0 / x.len() as f64;
                let c = x.iter().fold([0.0; 3], |a, p| {
                    [a[0] + w * p[0], a[1] + w * p[1], a[2] + w * p[2]]
                });
                FlankError::Element {
                    label,
                    kind,
                    message: format!(
                        "{message} (gmsh gear sector {name}, element centre ({:.4}, {:.4}, {:.4}) mm, radius {:.4} mm)",
                        c[0],
                        c[1],
                        c[2],
                        c[0].hypot(c[1])
                    ),
                }
            }
            other => other,
        })?;
        quality.add(kind, &x);
    }
    let report = GmshSectorReport {
        max_snap_mm: max_snap,
        gmsh_s,
        total_s: t_all.elapsed().as_secs_f64(),
        layers: nz,
    };
    Ok((
        GearSectorMesh {
            mesh,
            flank_uv,
            quality,
        },
        report,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fem::element::{HEX20_NODES, WEDGE15_NODES};
    use crate::geometry::{Hand, RackProfile};

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

    fn helical(hand: Hand) -> GearSpec {
        GearSpec {
            teeth: 21,
            normal_module: 15.0,
            normal_pressure_angle: 20f64.to_radians(),
            helix_angle: 20f64.to_radians(),
            hand,
            face_width: 180.0,
            profile_shift: 0.0,
            rack: RackProfile::default(),
            tip_diameter: None,
            bore_diameter: 150.0,
        }
    }

    /// The permutation tables against gmsh's own reference elements: gmsh
    /// node perm[i] of type 17/18 sits where CalculiX puts node i.
    #[test]
    fn gmsh_node_order_matches_calculix() {
        let s = Session::start().unwrap();
        let p = s.element_properties(17).unwrap();
        assert_eq!(
            (p.dim, p.order, p.nodes, p.primary_nodes),
            (3, 2, 20, 8),
            "{p:?}"
        );
        for (i, &g) in GMSH_HEX20_TO_CCX.iter().enumerate() {
            let x = &p.local_coords[3 * g..3 * g + 3];
            assert_eq!(x, &HEX20_NODES[i][..], "C3D20 node {i} ← gmsh {g}");
        }
        let p = s.element_properties(18).unwrap();
        assert_eq!(
            (p.dim, p.order, p.nodes, p.primary_nodes),
            (3, 2, 15, 6),
            "{p:?}"
        );
        for (i, &g) in GMSH_PRISM15_TO_CCX.iter().enumerate() {
            let x = &p.local_coords[3 * g..3 * g + 3];
            assert_eq!(x, &WEDGE15_NODES[i][..], "C3D15 node {i} ← gmsh {g}");
        }
    }

    fn check(spec: &GearSpec, opts: &SectorOptions, kind: ElementKind) -> GearSectorMesh {
        let (m, r) = gmsh_sector_with_msh(spec, "g", opts, kind, None).unwrap();
        println!(
            "{kind:?}, {} teeth: {} nodes, {} elements, min scaled Jacobian {:.3}, max aspect ratio {:.1}, snap ≤ {:.2e} mm, {:.2} s",
            opts.teeth,
            m.mesh.node_count(),
            m.mesh.elements.len(),
            m.quality.min_scaled_jacobian,
            m.quality.max_aspect_ratio,
            r.max_snap_mm,
            r.total_s
        );
        assert!(m.quality.min_scaled_jacobian > 0.0);
        assert!(m.mesh.elements.iter().all(|e| e.kind == kind));
        // the splines are close to the exact curves: small moves only
        assert!(
            r.max_snap_mm < 1e-3 * spec.normal_module,
            "{}",
            r.max_snap_mm
        );
        let prof = ToothProfile::new(spec, "g").unwrap();
        let mut nflank = 0;
        for k in 1..=opts.teeth {
            for (f, set) in [(Flank::Left, "FLANK_L"), (Flank::Right, "FLANK_R")] {
                let set = &m.mesh.node_sets[&format!("{set}{k}")];
                assert!(!set.is_empty());
                nflank += set.len();
                for &n in set {
                    let (u, zz) = m.flank_uv[&n];
                    let sp = prof.surface(f, flank_segment(&prof, u), zz);
                    let e = rot([sp.p[0], sp.p[1]], (k - 1) as f64 * prof.angular_pitch());
                    let x = m.mesh.coords[n];
                    assert!((x[0] - e[0]).hypot(x[1] - e[1]) < 1e-12 * spec.normal_module * 100.0);
                }
            }
        }
        assert_eq!(nflank, m.flank_uv.len());
        let rb = 0.5 * spec.bore_diameter;
        for &n in &m.mesh.node_sets["BORE"] {
            let x = m.mesh.coords[n];
            assert!((x[0].hypot(x[1]) - rb).abs() < 1e-9 * rb);
        }
        assert!(!m.mesh.node_sets["CUT_A"].is_empty());
        assert!(!m.mesh.node_sets["CUT_B"].is_empty());
        assert_eq!(m.mesh.node_sets["NALL"].len(), m.mesh.node_count());
        m
    }

    #[test]
    fn gmsh_sector_spur_hex_and_wedge() {
        let opts = SectorOptions {
            flank_size: 1.0,
            base_size: 2.0,
            ..Default::default()
        };
        for kind in [ElementKind::C3D20, ElementKind::C3D15] {
            let m = check(&pinion(), &opts, kind);
            // cut faces on their planes
            let h = PI / 13.0;
            for (nm, a) in [("CUT_A", -h), ("CUT_B", -h + 6.0 * h)] {
                for &n in &m.mesh.node_sets[nm] {
                    let q = m.mesh.coords[n];
                    assert!((q[0].atan2(q[1]) - a).abs() < 1e-9, "{nm}");
                }
            }
        }
    }

    /// Both hands: a wrong twist sense would move the flank nodes by
    /// millimetres (and fail the snap bound), not micrometres.
    #[test]
    fn gmsh_sector_helical_twist_follows_helix() {
        let opts = SectorOptions {
            flank_size: 8.0,
            base_size: 25.0,
            face_layers: 6,
            ..Default::default()
        };
        for hand in [Hand::Right, Hand::Left] {
            let spec = helical(hand);
            let m = check(&spec, &opts, ElementKind::C3D15);
            let prof = ToothProfile::new(&spec, "g").unwrap();
            // the cut face CUT_A turns with the section: angle −π/z + φ(z)
            // (polar angle from +y, positive towards +x, so φ counts negative)
            for &n in &m.mesh.node_sets["CUT_A"] {
                let q = m.mesh.coords[n];
                let a = -PI / 21.0 - prof.twist_rate * q[2];
                assert!((q[0].atan2(q[1]) - a).abs() < 1e-9);
            }
        }
    }

    #[test]
    fn gmsh_sector_full_ring() {
        let spec = pinion();
        let opts = SectorOptions {
            teeth: 13,
            flank_size: 1.5,
            base_size: 3.0,
            face_layers: 2,
            ..Default::default()
        };
        let m = check(&spec, &opts, ElementKind::C3D20);
        assert_eq!(m.mesh.node_sets["CUT_A"], m.mesh.node_sets["CUT_B"]);
    }

    #[test]
    fn gmsh_sector_rejects_bad_options() {
        let spec = pinion();
        for (opts, what) in [
            (
                SectorOptions {
                    teeth: 0,
                    ..Default::default()
                },
                "teeth",
            ),
            (
                SectorOptions {
                    teeth: 14,
                    ..Default::default()
                },
                "teeth",
            ),
            (
                SectorOptions {
                    flank_size: 3.0,
                    base_size: 1.0,
                    ..Default::default()
                },
                "flank_size",
            ),
        ] {
            let e = gmsh_sector(&spec, "p", &opts, ElementKind::C3D20)
                .unwrap_err()
                .to_string();
            assert!(e.contains(what), "{e}");
        }
        let mut s = spec.clone();
        s.bore_diameter = 50.0;
        let e = gmsh_sector(&s, "p", &SectorOptions::default(), ElementKind::C3D20)
            .unwrap_err()
            .to_string();
        assert!(e.contains("bore"), "{e}");
    }
}
