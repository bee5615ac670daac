//! Extrusion of a transverse section along the axis: `face_layers`
//! quadratic layers over the face width, each section rotated by the helix
//! twist; hex20/wedge15 elements (Jacobian-checked, quality figures), the
//! flank (u, z) of every flank node, the node and element sets.

use std::collections::HashMap;

use super::lattice::Cell;
use super::section::Section;
use super::{err, GearSectorMesh, Quality, SectorOptions};
use crate::error::FlankError;
use crate::fem::element::check_jacobian;
use crate::fem::mesh::Mesh;
use crate::geometry::rack::Flank;
use crate::geometry::GearSpec;

/// The sector mesh of `section` (module doc of [`super`]).
pub(super) fn extrude(
    spec: &GearSpec,
    name: &str,
    opts: &SectorOptions,
    section: Section,
) -> Result<GearSectorMesh, FlankError> {
    let Section {
        prof,
        pts,
        blocks,
        cells,
        cut_a,
        cut_b,
    } = section;
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
                check_jacobian(kind, &x).map_err(|e| {
                    e.into_error_in(
                        label,
                        kind,
                        &format!(
                            "gear sector {name}: tooth {} {} block, cell ({i}, {j}) of {}×{}, layer {}",
                            bi / 2 + 1,
                            if bi % 2 == 0 { "upper" } else { "rim" },
                            blocks[bi].ni,
                            blocks[bi].nj,
                            l + 1
                        ),
                    )
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
