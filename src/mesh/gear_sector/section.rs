//! The transverse section of a sector (module doc of [`super`]): element
//! sizes across the tooth and along its boundary (gap arc, fillet uniform in
//! arc length, involute uniform in arc length), the boundary points on the
//! exact profile, the blend towards the bottom curve and the tip, the
//! distribution across each row, the rim sizes; then the points of the
//! upper and rim blocks of every pitch (shared by position) and their
//! transverse cells.

use std::collections::HashMap;
use std::f64::consts::PI;

use super::lattice::{cart, graded, half_lattice, pol, quad_cell, rot, Block, Cell, Points};
use super::{err, ProfileBand, SectorOptions};
use crate::error::FlankError;
use crate::fem::mesh::ElementKind;
use crate::geometry::rack::{Flank, Segment, ToothProfile};
use crate::geometry::GearSpec;
use crate::mesh::section_cells::{upper_layout, LatticeCell, Lp, Mid};

/// A transverse section, ready for the extrusion.
pub(super) struct Section {
    pub(super) prof: ToothProfile,
    /// The transverse points (corner and midside) of all pitches.
    pub(super) pts: Points,
    /// Per pitch the upper block, then the rim block.
    pub(super) blocks: Vec<Block>,
    /// (block, I, J, cell) of every transverse cell.
    pub(super) cells: Vec<(usize, usize, usize, Cell)>,
    /// Points on the cut faces left of the first and right of the last tooth.
    pub(super) cut_a: Vec<usize>,
    pub(super) cut_b: Vec<usize>,
}

/// The transverse section of `opts.teeth` teeth of `spec` (module doc of
/// [`super`]); `coarsen`: wedge cells coarsen 2:1 along the profile inside
/// the tooth.
pub(super) fn transverse_section(
    spec: &GearSpec,
    name: &str,
    opts: &SectorOptions,
    bands: &[ProfileBand],
    coarsen: bool,
) -> Result<Section, FlankError> {
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
    // Contact bands (module doc of [`super`]): checked here, where the
    // involute's extent is known. The first layer across the tooth is the
    // finest band size, so that the elements under a band are about square
    // at the surface and several layers lie within the Hertz depth.
    let (uf, ut) = (prof.u_form, prof.u_tip);
    let band_intervals = band_intervals(name, bands, fs, rb, uf, ut)?;
    let first_layer = bands.iter().fold(fs, |m, b| m.min(b.size_mm));

    // --- across the tooth: graded sizes from both flanks to the centre.
    let w = g.reference_thickness_transverse;
    let half = graded(
        0.5 * w,
        first_layer,
        q,
        opts.base_size,
        "half tooth thickness",
    )?;
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
    let inv_len = 0.5 * rb * (ut * ut - uf * uf);
    // involute rows: uniform in arc length, or banded (fractions of the
    // arc length from the form point at the half-lattice rows)
    let inv_frac: Option<Vec<f64>> = if band_intervals.is_empty() {
        None
    } else {
        let sizes = crate::mesh::grading::banded_sizes(
            inv_len,
            fs,
            &band_intervals,
            crate::mesh::grading::BAND_GROWTH,
            &format!("{name}: involute rows of the contact band"),
        )
        .map_err(err)?;
        Some(half_lattice(&sizes))
    };
    let ni = match &inv_frac {
        Some(f) => (f.len() - 1) / 2,
        None => ((inv_len / fs).ceil() as usize).max(1),
    };
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
            let f = match &inv_frac {
                Some(fr) => fr[jj - 2 * (ng + nf)],
                None => (jj - 2 * (ng + nf)) as f64 / (2 * ni) as f64,
            };
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
    let row_sig: Vec<Vec<f64>> = (0..=2 * nt)
        .map(|jj| {
            let lp = pol(lpts[jj.max(jform)].0);
            crate::mesh::grading::row_fractions(2.0 * (-lp[0]) * lp[1], nh, first_layer)
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
    if !(r_bore < ri) {
        return Err(err(format!(
            "{name}: the bore (diameter {:.4} mm) leaves no rim below the tooth section (inner diameter {:.4} mm, under the root circle): make `bore_diameter_mm` smaller than {:.4} mm",
            2.0 * r_bore,
            2.0 * ri,
            2.0 * ri
        )));
    }
    let rim_sizes = graded(
        ri - r_bore,
        rim_h0,
        q,
        opts.base_size,
        "rim below the teeth",
    )?;
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
    // width of column d (between lattice lines 2d and 2d + 2) at row jj
    let cell_width = |d: usize, jj: usize| {
        let lp = pol(lpts[jj.max(jform)].0);
        let w = 2.0 * (-lp[0]) * lp[1];
        w * (row_sig[jj][2 * d + 2] - row_sig[jj][2 * d])
    };
    let (layout, role) =
        upper_layout(name, coarsen, ns, nt, &sizes_s, fs, cell_width).map_err(err)?;
    let w2 = 2 * nt + 1;

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
    Ok(Section {
        prof,
        pts,
        blocks,
        cells,
        cut_a,
        cut_b,
    })
}

/// The bands as arc-length intervals of the involute from the form point
/// (start, end, size; mm), checked: a size that is not positive or above
/// the flank size, a half-width that is not positive, a centre off the
/// involute (below the form or above the tip radius) are errors naming the
/// band's field.
fn band_intervals(
    name: &str,
    bands: &[ProfileBand],
    fs: f64,
    rb: f64,
    uf: f64,
    ut: f64,
) -> Result<Vec<(f64, f64, f64)>, FlankError> {
    let (r_form, r_tip) = (rb * uf.hypot(1.0), rb * ut.hypot(1.0));
    let mut out = Vec::with_capacity(bands.len());
    for (i, b) in bands.iter().enumerate() {
        let at = format!("{name}: contact band {}", i + 1);
        if !(b.size_mm > 0.0 && b.size_mm.is_finite()) {
            return Err(err(format!(
                "{at}: size_mm = {} must be positive and finite",
                b.size_mm
            )));
        }
        if b.size_mm > fs {
            return Err(err(format!(
                "{at}: size_mm = {} is above the flank size {fs} mm (a band refines the flank rows)",
                b.size_mm
            )));
        }
        if !(b.half_width_mm > 0.0 && b.half_width_mm.is_finite()) {
            return Err(err(format!(
                "{at}: half_width_mm = {} must be positive and finite",
                b.half_width_mm
            )));
        }
        if !(b.radius_mm >= r_form && b.radius_mm <= r_tip) {
            return Err(err(format!(
                "{at}: radius_mm = {} lies beyond the involute flank (form radius {r_form:.4} mm to tip radius {r_tip:.4} mm)",
                b.radius_mm
            )));
        }
        let u = ((b.radius_mm / rb).powi(2) - 1.0).max(0.0).sqrt();
        let s = 0.5 * rb * (u * u - uf * uf);
        out.push((s - b.half_width_mm, s + b.half_width_mm, b.size_mm));
    }
    Ok(out)
}
