//! The 3D sector (module doc of [`super`]): the stations' lattices turned
//! onto every modelled tooth, nodes merged by position where blocks meet
//! (cuts between pitches, the Π bottom and the rim's top), hex20 elements
//! between consecutive corner stations (Jacobian-checked, quality figures),
//! node and element sets.

use std::collections::HashMap;

use rayon::prelude::*;

use super::section::{section, SectionLattice, SectionPoint};
use super::station::FaceLayout;
use super::{err, BevelSectorMesh, BevelSectorOptions, Mount};
use crate::error::FlankError;
use crate::fem::element::check_jacobian;
use crate::geometry::bevel::body::BevelGear;
use crate::geometry::gear_pair::{Flank, GearBody};
use crate::mesh::gear_sector::Quality;
use crate::mesh::Mesh;

/// Nodes merged by position (cells of `tol`).
struct Registry {
    coords: Vec<[f64; 3]>,
    corner: Vec<bool>,
    grid: HashMap<(i64, i64, i64), Vec<usize>>,
    tol: f64,
}

impl Registry {
    fn add(&mut self, p: [f64; 3], corner: bool) -> Result<usize, FlankError> {
        let k = p.map(|x| (x / self.tol).floor() as i64);
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    if let Some(v) = self.grid.get(&(k[0] + dx, k[1] + dy, k[2] + dz)) {
                        for &i in v {
                            let q = self.coords[i];
                            let d = ((q[0] - p[0]).powi(2)
                                + (q[1] - p[1]).powi(2)
                                + (q[2] - p[2]).powi(2))
                            .sqrt();
                            if d < self.tol {
                                if self.corner[i] != corner {
                                    return Err(err(format!(
                                        "lattice mismatch at ({:.6}, {:.6}, {:.6}): a corner and a midside node coincide",
                                        p[0], p[1], p[2]
                                    )));
                                }
                                return Ok(i);
                            }
                        }
                    }
                }
            }
        }
        let i = self.coords.len();
        self.coords.push(p);
        self.corner.push(corner);
        self.grid.entry((k[0], k[1], k[2])).or_default().push(i);
        Ok(i)
    }
}

/// Whether a lattice point with these half indices is a hex20 node (at most
/// one odd index), and whether it is a corner (none odd).
fn node_role(idx: [usize; 3]) -> Option<bool> {
    match idx.iter().filter(|&&i| i % 2 == 1).count() {
        0 => Some(true),
        1 => Some(false),
        _ => None,
    }
}

/// One block of one tooth: node ids per (station, ii, jj), usize::MAX where
/// no node.
struct BlockIds {
    width: usize,
    height: usize,
    /// Element layers (between level pairs 2l, 2l + 2).
    layers: usize,
    ids: Vec<usize>,
}

impl BlockIds {
    fn at(&self, s: usize, ii: usize, jj: usize) -> usize {
        self.ids[(s * self.width + ii) * self.height + jj]
    }
}

pub(super) fn assemble(
    gear: &BevelGear,
    name: &str,
    opts: &BevelSectorOptions,
    face: &FaceLayout,
) -> Result<BevelSectorMesh, FlankError> {
    let c = face.counts;
    let nst = 2 * c.face + 1;
    let nt = c.land + c.fillet + c.flank;
    let (uw, uh) = (2 * c.across + 1, 2 * nt + 1);
    let nar = c.across - 2 * c.cut;
    let (rw, rh) = (2 * nar + 1, 2 * c.rim + 1);
    let sections: Vec<SectionLattice> =
        (0..nst).into_par_iter().map(|s| section(face, s)).collect();
    let teeth = gear.sector_teeth();
    let pitch = face.pitch;
    let mut reg = Registry {
        coords: Vec::new(),
        corner: Vec::new(),
        grid: HashMap::new(),
        tol: 1e-7 * face.cones.re,
    };
    let mut flank_uv = HashMap::new();
    let mut flank_sets: HashMap<String, Vec<usize>> = HashMap::new();
    let (mut cut_a, mut cut_b, mut toe, mut heel, mut mount) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let (mut tip_land, mut gap_land) = (Vec::new(), Vec::new());
    // 3D point of a section point on tooth k (0-based)
    let point = |p: &SectionPoint, v: f64, k: usize| -> Result<[f64; 3], FlankError> {
        if let Some(side) = p.flank {
            let f = gear
                .flank(side, k + 1)
                .ok_or_else(|| err(format!("{name}: no flank of tooth {}", k + 1)))?;
            Ok(f.point(p.u, v))
        } else {
            let (z, rho) = face.cones.axial_point(p.u, v);
            let t = p.theta + k as f64 * pitch;
            Ok([rho * t.sin(), rho * t.cos(), z])
        }
    };
    let mut blocks: Vec<(usize, bool, BlockIds)> = Vec::new();
    for k in 0..teeth {
        for upper in [true, false] {
            let (w, h) = if upper { (uw, uh) } else { (rw, rh) };
            let mut ids = vec![usize::MAX; nst * w * h];
            for (s, sec) in sections.iter().enumerate() {
                let v = face.stations[s].v;
                let pts = if upper { &sec.upper } else { &sec.rim };
                for ii in 0..w {
                    for jj in 0..h {
                        let Some(corner) = node_role([s, ii, jj]) else {
                            continue;
                        };
                        let p = &pts[ii * h + jj];
                        let id = reg.add(point(p, v, k)?, corner)?;
                        ids[(s * w + ii) * h + jj] = id;
                        if let Some(side) = p.flank {
                            flank_uv.insert(id, (p.u, v));
                            let set = match side {
                                Flank::Left => format!("FLANK_L{}", k + 1),
                                Flank::Right => format!("FLANK_R{}", k + 1),
                            };
                            flank_sets.entry(set).or_default().push(id);
                        }
                        if s == 0 {
                            toe.push(id);
                        }
                        if s + 1 == nst {
                            heel.push(id);
                        }
                        let (first, last) = (k == 0, k + 1 == teeth);
                        if upper && jj == h - 1 {
                            tip_land.push(id);
                        }
                        if upper && (ii == 0 || ii == w - 1) && jj <= 2 * c.land {
                            gap_land.push(id);
                        }
                        if upper && jj == 0 {
                            if first && ii <= 2 * c.cut {
                                cut_a.push(id);
                            }
                            if last && ii >= 2 * (c.across - c.cut) {
                                cut_b.push(id);
                            }
                        }
                        if !upper {
                            if first && ii == 0 {
                                cut_a.push(id);
                            }
                            if last && ii == w - 1 {
                                cut_b.push(id);
                            }
                            if jj == 0 {
                                mount.push(id);
                            }
                        }
                    }
                }
            }
            blocks.push((
                k,
                upper,
                BlockIds {
                    width: w,
                    height: h,
                    layers: c.face,
                    ids,
                },
            ));
        }
    }
    // the shank: the heel face's rim rows 0..=row extruded along +z
    let (mut bore_nodes, mut seat, mut shank_end) = (Vec::new(), Vec::new(), Vec::new());
    // heel nodes the shank covers (inside the body now)
    let mut covered = std::collections::HashSet::new();
    let mut shank_blocks = Vec::new();
    if let Some(sh) = &face.shank {
        let heel = &sections[nst - 1];
        let v1 = face.stations[nst - 1].v;
        let (w, h, nl) = (rw, sh.row + 1, 2 * sh.layers + 1);
        for k in 0..teeth {
            let mut ids = vec![usize::MAX; nl * w * h];
            for ll in 0..nl {
                let t = ll as f64 / (nl - 1) as f64;
                for ii in 0..w {
                    for kk in 0..h {
                        let Some(corner) = node_role([ll, ii, kk]) else {
                            continue;
                        };
                        let p = &heel.rim[ii * rh + kk];
                        let (z0, rho) = face.cones.axial_point(p.u, v1);
                        // the row on r_s and the bore exactly on their cylinders
                        let rho = match kk {
                            0 => sh.bore,
                            x if x == sh.row => sh.radius,
                            _ => rho,
                        };
                        let z = if ll == 0 {
                            z0
                        } else {
                            z0 + t * (sh.z_end - z0)
                        };
                        let th = p.theta + k as f64 * pitch;
                        let x = if ll == 0 {
                            point(p, v1, k)?
                        } else {
                            [rho * th.sin(), rho * th.cos(), z]
                        };
                        let id = reg.add(x, corner)?;
                        ids[(ll * w + ii) * h + kk] = id;
                        if kk == 0 {
                            bore_nodes.push(id);
                        }
                        if kk == sh.row && z >= sh.z_start - 1e-9 * face.cones.re {
                            seat.push(id);
                        }
                        if ll == nl - 1 {
                            shank_end.push(id);
                        }
                        if ll == 0 && kk < sh.row {
                            covered.insert(id);
                        }
                        if k == 0 && ii == 0 {
                            cut_a.push(id);
                        }
                        if k + 1 == teeth && ii == w - 1 {
                            cut_b.push(id);
                        }
                    }
                }
            }
            shank_blocks.push((
                k,
                BlockIds {
                    width: w,
                    height: h,
                    layers: sh.layers,
                    ids,
                },
            ));
        }
    }

    // nodes
    let mut mesh = Mesh::new();
    for (i, &x) in reg.coords.iter().enumerate() {
        mesh.add_node(i as u64 + 1, x)
            .map_err(|_| err("duplicate node label".into()))?;
    }
    // elements: 2D cell (I, J) of a block between stations 2L and 2L + 2
    let kind = opts.element;
    let mut quality = Quality::empty();
    let all_blocks = blocks
        .iter()
        .map(|(k, upper, b)| (*k, if *upper { "upper" } else { "rim" }, b))
        .chain(shank_blocks.iter().map(|(k, b)| (*k, "shank", b)));
    for (k, block, b) in all_blocks {
        for i in 0..(b.width - 1) / 2 {
            for j in 0..(b.height - 1) / 2 {
                let (i0, j0) = (2 * i, 2 * j);
                let cs = [(i0, j0), (i0 + 2, j0), (i0 + 2, j0 + 2), (i0, j0 + 2)];
                let ms = [
                    (i0 + 1, j0),
                    (i0 + 2, j0 + 1),
                    (i0 + 1, j0 + 2),
                    (i0, j0 + 1),
                ];
                for l in 0..b.layers {
                    let (mut s0, sm, mut s1) = (2 * l, 2 * l + 1, 2 * l + 2);
                    // orientation: (e_across × e_up) · e_face > 0
                    let x = |s: usize, p: (usize, usize)| reg.coords[b.at(s, p.0, p.1)];
                    let d = |a: [f64; 3], b: [f64; 3]| [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
                    let (o, e1, e2, e3) = (x(s0, cs[0]), x(s0, cs[1]), x(s0, cs[3]), x(s1, cs[0]));
                    let (a, bb, cc) = (d(o, e1), d(o, e2), d(o, e3));
                    let det = a[0] * (bb[1] * cc[2] - bb[2] * cc[1])
                        - a[1] * (bb[0] * cc[2] - bb[2] * cc[0])
                        + a[2] * (bb[0] * cc[1] - bb[1] * cc[0]);
                    if det < 0.0 {
                        std::mem::swap(&mut s0, &mut s1);
                    }
                    let mut nodes = Vec::with_capacity(20);
                    for s in [s0, s1] {
                        nodes.extend(cs.iter().map(|&p| b.at(s, p.0, p.1)));
                    }
                    for s in [s0, s1] {
                        nodes.extend(ms.iter().map(|&p| b.at(s, p.0, p.1)));
                    }
                    nodes.extend(cs.iter().map(|&p| b.at(sm, p.0, p.1)));
                    let label = mesh.elements.len() as u64 + 1;
                    let xs: Vec<[f64; 3]> = nodes.iter().map(|&n| reg.coords[n]).collect();
                    check_jacobian(kind, &xs).map_err(|e| match e.into_error(label, kind) {
                        FlankError::Element {
                            label,
                            kind,
                            message,
                        } => FlankError::Element {
                            label,
                            kind,
                            message: format!(
                                "{message} (bevel sector {name}: tooth {} {block} block, cell ({i}, {j}), layer {})",
                                k + 1,
                                l + 1
                            ),
                        },
                        other => other,
                    })?;
                    quality.add(kind, &xs);
                    mesh.add_element(label, kind, nodes)
                        .map_err(|_| err("duplicate element label".into()))?;
                }
            }
        }
    }
    let dedup = |mut v: Vec<usize>| {
        v.sort_unstable();
        v.dedup();
        v
    };
    let mut names: Vec<_> = flank_sets.into_iter().collect();
    names.sort();
    for (nm, v) in names {
        mesh.extend_node_set(&nm, dedup(v));
    }
    let mount_set = dedup(mount);
    if face.shank.is_some() {
        // the bore runs through teeth and shank; the mount is the bearing seat
        bore_nodes.extend(mount_set);
        mesh.extend_node_set("BORE", dedup(bore_nodes));
        mesh.extend_node_set("MOUNT", dedup(seat));
        mesh.extend_node_set("SHANK_END", dedup(shank_end));
    } else {
        if matches!(face.mount, Mount::Bore { .. }) {
            mesh.extend_node_set("BORE", mount_set.clone());
        }
        mesh.extend_node_set("MOUNT", mount_set);
    }
    mesh.extend_node_set("CUT_A", dedup(cut_a));
    mesh.extend_node_set("CUT_B", dedup(cut_b));
    mesh.extend_node_set("TIP_LAND", dedup(tip_land));
    mesh.extend_node_set("GAP_LAND", dedup(gap_land));
    mesh.extend_node_set("TOE", dedup(toe));
    heel.retain(|n| !covered.contains(n));
    mesh.extend_node_set("HEEL", dedup(heel));
    let n = mesh.node_count();
    mesh.extend_node_set("NALL", 0..n);
    let ne = mesh.elements.len();
    mesh.extend_element_set("EALL", 0..ne);
    Ok(BevelSectorMesh {
        mesh,
        flank_uv,
        quality,
        mount: face.mount,
        counts: c,
        shank: face.shank.as_ref().map(|sh| super::ShankReport {
            bore_radius_mm: sh.bore,
            radius_mm: sh.radius,
            z_mm: [sh.z_start, sh.z_end],
            layers: sh.layers,
        }),
    })
}
