//! The 3D sector (module doc of [`super`]): the stations' lattices turned
//! onto every modelled tooth, nodes merged by position where blocks meet
//! (cuts between pitches, the Π bottom and the rim's top), hex20 or wedge15
//! elements between consecutive corner stations (Jacobian-checked, quality
//! figures), node and element sets.

use std::collections::HashMap;

use rayon::prelude::*;

use super::cells::{grid_layout, layout_cells, BlockCells, Shape};
use super::section::{section, SectionLattice, SectionPoint};
use super::station::FaceLayout;
use super::{err, BevelSectorMesh, BevelSectorOptions, Mount};
use crate::error::FlankError;
use crate::fem::element::check_jacobian;
use crate::fem::mesh::{ElementKind, Mesh};
use crate::geometry::bevel::body::BevelGear;
use crate::geometry::gear_pair::{Flank, GearBody};
use crate::mesh::gear_sector::Quality;
use crate::mesh::section_cells::upper_layout;

/// Nodes merged by position (cells of `tol`).
struct Registry {
    coords: Vec<[f64; 3]>,
    corner: Vec<bool>,
    grid: HashMap<(i64, i64, i64), Vec<usize>>,
    tol: f64,
}

impl Registry {
    /// The node at `p` (an existing one within `tol`, else a new one); the
    /// error says where a corner and a midside node would merge.
    fn add(&mut self, p: [f64; 3], corner: bool) -> Result<usize, String> {
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
                                    return Err(format!(
                                        "lattice mismatch at ({:.6}, {:.6}, {:.6}): a corner and a midside node coincide",
                                        p[0], p[1], p[2]
                                    ));
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

/// The node ids of one block of one tooth, per level (station, or shank
/// layer) and section point; usize::MAX where no node.
struct BlockIds<'a> {
    cells: &'a BlockCells,
    /// Element layers (between levels 2l, 2l + 2).
    layers: usize,
    ids: Vec<usize>,
}

impl BlockIds<'_> {
    fn at(&self, level: usize, p: usize) -> usize {
        self.ids[level * self.cells.len() + p]
    }
}

/// Whether the diagonal c0–c2 of the quadrilateral with lattice corners
/// `c` is, summed over the stations, no longer than c1–c3 (the split of
/// wedge cells, the same on every station).
fn shorter_first(face: &FaceLayout, pts: &[&[SectionPoint]], c: [usize; 4]) -> bool {
    let mut sum = 0.0;
    for (s, p) in pts.iter().enumerate() {
        let st = &face.stations[s];
        let d = |a: usize, b: usize| {
            let (a, b) = (p[a], p[b]);
            let r = st.radius(&face.cones, 0.5 * (a.u + b.u));
            (r * (b.theta - a.theta)).hypot(b.u - a.u)
        };
        sum += d(c[0], c[2]) - d(c[1], c[3]);
    }
    sum <= 0.0
}

pub(super) fn assemble(
    gear: &BevelGear,
    name: &str,
    opts: &BevelSectorOptions,
    face: &FaceLayout,
    coarsen: bool,
) -> Result<BevelSectorMesh, FlankError> {
    let c = face.counts;
    let nst = 2 * c.face + 1;
    let nt = c.land + c.fillet + c.flank;
    let (uw, uh) = (2 * c.across + 1, 2 * nt + 1);
    let nar = c.across - 2 * c.cut;
    let (rw, rh) = (2 * nar + 1, 2 * c.rim + 1);
    let sections: Vec<SectionLattice> =
        (0..nst).into_par_iter().map(|s| section(face, s)).collect();
    // the cells of each block, the same on every station
    let wedges = opts.element == ElementKind::C3D15;
    let upper_pts: Vec<&[SectionPoint]> = sections.iter().map(|s| &s.upper[..]).collect();
    let rim_pts: Vec<&[SectionPoint]> = sections.iter().map(|s| &s.rim[..]).collect();
    let upper_layout_cells = if wedges {
        // the layout bounds coarse cells by (rows × flank size) / width;
        // each station's own row height takes the place of the flank size
        let cell_width = |d: usize, jj: usize| {
            sections
                .iter()
                .map(|s| s.cell_widths[jj][d] * face.flank_size / s.row_heights[jj])
                .fold(f64::INFINITY, f64::min)
        };
        upper_layout(
            name,
            coarsen,
            c.across,
            nt,
            &face.across_sizes,
            face.flank_size,
            cell_width,
        )
        .map_err(err)?
        .0
    } else {
        grid_layout(c.across, nt)
    };
    let upper_cells = layout_cells(&upper_layout_cells, uw, uh, wedges, |q| {
        shorter_first(face, &upper_pts, q)
    });
    let rim_cells = layout_cells(&grid_layout(nar, c.rim), rw, rh, wedges, |q| {
        shorter_first(face, &rim_pts, q)
    });
    let upper_roles = upper_cells.roles();
    let rim_roles = rim_cells.roles();
    // every station's points of both blocks (lattice, then extra points)
    let station_pts: Vec<[Vec<SectionPoint>; 2]> = sections
        .iter()
        .map(|sec| [upper_cells.points(&sec.upper), rim_cells.points(&sec.rim)])
        .collect();
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
    // Whether a point of `role` has a node on level `level`, and whether
    // that node is an element corner: section corners on every level,
    // section midsides on the corner levels only.
    let node_role = |role: u8, level: usize| match (role, level % 2) {
        (0, _) | (2, 1) => None,
        (r, l) => Some(r == 1 && l == 0),
    };
    let mut blocks: Vec<(usize, &str, BlockIds)> = Vec::new();
    for k in 0..teeth {
        for upper in [true, false] {
            let (cells, roles) = if upper {
                (&upper_cells, &upper_roles)
            } else {
                (&rim_cells, &rim_roles)
            };
            let (w, h, np) = (cells.width, cells.height, cells.len());
            let mut ids = vec![usize::MAX; nst * np];
            for (s, sp) in station_pts.iter().enumerate() {
                let v = face.stations[s].v;
                let pts = &sp[usize::from(!upper)];
                for (pi, p) in pts.iter().enumerate() {
                    let Some(corner) = node_role(roles[pi], s) else {
                        continue;
                    };
                    let id = reg.add(point(p, v, k)?, corner).map_err(|e| {
                        err(format!(
                            "{name}, tooth {} of the sector, {} block, station {s} of {nst} \
                             (cone distance {v:.3} mm), section point {:?} ({}): {e}",
                            k + 1,
                            if upper { "upper" } else { "rim" },
                            cells.lattice_index(pi),
                            match p.flank {
                                Some(Flank::Left) => "left flank",
                                Some(Flank::Right) => "right flank",
                                None => "off the flanks",
                            },
                        ))
                    })?;
                    ids[s * np + pi] = id;
                    if s == 0 {
                        toe.push(id);
                    }
                    if s + 1 == nst {
                        heel.push(id);
                    }
                    let Some((ii, jj)) = cells.lattice_index(pi) else {
                        continue;
                    };
                    if let Some(side) = p.flank {
                        flank_uv.insert(id, (p.u, v));
                        let set = match side {
                            Flank::Left => format!("FLANK_L{}", k + 1),
                            Flank::Right => format!("FLANK_R{}", k + 1),
                        };
                        flank_sets.entry(set).or_default().push(id);
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
            blocks.push((
                k,
                if upper { "upper" } else { "rim" },
                BlockIds {
                    cells,
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
    let shank_cells = face.shank.as_ref().map(|sh| rim_cells.below(sh.row));
    if let (Some(sh), Some(cells)) = (&face.shank, &shank_cells) {
        let heel = &station_pts[nst - 1][1];
        let roles = cells.roles();
        let v1 = face.stations[nst - 1].v;
        let (w, np, nl) = (rw, cells.len(), 2 * sh.layers + 1);
        for k in 0..teeth {
            let mut ids = vec![usize::MAX; nl * np];
            for ll in 0..nl {
                let t = ll as f64 / (nl - 1) as f64;
                for (pi, p) in heel.iter().enumerate() {
                    let Some(corner) = node_role(roles[pi], ll) else {
                        continue;
                    };
                    let lattice = cells.lattice_index(pi);
                    let kk = lattice.map(|(_, kk)| kk);
                    let (z0, rho) = face.cones.axial_point(p.u, v1);
                    // the row on r_s and the bore exactly on their cylinders
                    let rho = match kk {
                        Some(0) => sh.bore,
                        Some(x) if x == sh.row => sh.radius,
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
                    let id = reg
                        .add(x, corner)
                        .map_err(|e| err(format!("{name}, shank of tooth {}: {e}", k + 1)))?;
                    ids[ll * np + pi] = id;
                    if ll == nl - 1 {
                        shank_end.push(id);
                    }
                    if ll == 0 && kk.is_none_or(|kk| kk < sh.row) {
                        covered.insert(id);
                    }
                    let Some((ii, kk)) = lattice else {
                        continue;
                    };
                    if kk == 0 {
                        bore_nodes.push(id);
                    }
                    if kk == sh.row && z >= sh.z_start - 1e-9 * face.cones.re {
                        seat.push(id);
                    }
                    if k == 0 && ii == 0 {
                        cut_a.push(id);
                    }
                    if k + 1 == teeth && ii == w - 1 {
                        cut_b.push(id);
                    }
                }
            }
            blocks.push((
                k,
                "shank",
                BlockIds {
                    cells,
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
    // elements: each section cell between levels 2L and 2L + 2
    let mut quality = Quality::empty();
    for (k, block, b) in &blocks {
        for ((i, j), shape) in &b.cells.cells {
            let (cs, ms, kind): (&[usize], &[usize], ElementKind) = match shape {
                Shape::Quad(c, m) => (c, m, opts.element),
                Shape::Tri(c, m) => (c, m, ElementKind::C3D15),
            };
            for l in 0..b.layers {
                let (mut s0, sm, mut s1) = (2 * l, 2 * l + 1, 2 * l + 2);
                // orientation: (e_1 × e_last) · e_face > 0
                let x = |s: usize, p: usize| reg.coords[b.at(s, p)];
                let d = |a: [f64; 3], b: [f64; 3]| [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
                let o = x(s0, cs[0]);
                let (a, bb, cc) = (
                    d(o, x(s0, cs[1])),
                    d(o, x(s0, cs[cs.len() - 1])),
                    d(o, x(s1, cs[0])),
                );
                let det = a[0] * (bb[1] * cc[2] - bb[2] * cc[1])
                    - a[1] * (bb[0] * cc[2] - bb[2] * cc[0])
                    + a[2] * (bb[0] * cc[1] - bb[1] * cc[0]);
                if det < 0.0 {
                    std::mem::swap(&mut s0, &mut s1);
                }
                let mut nodes = Vec::with_capacity(kind.node_count());
                for s in [s0, s1] {
                    nodes.extend(cs.iter().map(|&p| b.at(s, p)));
                }
                for s in [s0, s1] {
                    nodes.extend(ms.iter().map(|&p| b.at(s, p)));
                }
                nodes.extend(cs.iter().map(|&p| b.at(sm, p)));
                let label = mesh.elements.len() as u64 + 1;
                let xs: Vec<[f64; 3]> = nodes.iter().map(|&n| reg.coords[n]).collect();
                check_jacobian(kind, &xs).map_err(|e| {
                    e.into_error_in(
                        label,
                        kind,
                        &format!(
                            "bevel sector {name}: tooth {} {block} block, cell ({i}, {j}), layer {}",
                            k + 1,
                            l + 1
                        ),
                    )
                })?;
                quality.add(kind, &xs);
                mesh.add_element(label, kind, nodes)
                    .map_err(|_| err("duplicate element label".into()))?;
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
