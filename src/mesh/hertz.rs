//! Hertz line contact as a plane-strain slice: a cylinder of radius R
//! pressed onto a flat block, half model (x ≥ 0), graded to the contact.
//!
//! Both bodies are structured quadratic meshes ([`box_mesh`] on integer
//! lattice coordinates, then [`map_nodes`]) one element thick in z:
//!
//! * flat: x ∈ [0, W], y ∈ [−H, 0];
//! * cylinder cap: x ∈ [0, W] (W < R), y from the circle
//!   y = R − √(R² − x²) up to y = R (the horizontal plane through the axis).
//!
//! In x both bodies share one distribution: `fine_cells` equal cells over
//! [0, fine_extent] (the contact zone and a margin), then cells growing by
//! `growth` to W, so the slave nodes lie over master nodes. In y the first
//! cell at the contact has the fine size and the cells grow by `growth`.
//! Midside nodes sit at the middle of straight edges and exactly on the
//! circle at the contact, so the quadratic faces interpolate the circle.
//!
//! Node sets (upper case): FLAT_TOP (y = 0), FLAT_BOTTOM, FLAT_SYM (x = 0),
//! CYL_ARC (the circle), CYL_TOP (y = R), CYL_SYM (x = 0), Z0, Z1 (both
//! bodies), NALL. Element sets FLAT, CYLINDER, EALL. Node labels: flat
//! 1.., cylinder from 10ᵏ + 1, the smallest power of ten above the flat's
//! node count (CalculiX sizes its arrays by the largest label: keep them
//! small); element labels likewise.

use crate::error::FlankError;
use crate::fem::contact_definition::{
    ContactDefinition, ContactPair, PressureOverclosure, Surface, SurfaceInteraction, SurfaceKind,
};
use crate::fem::material::Material;
use crate::fem::mesh::Mesh;
use crate::fem::model::{Dirichlet, Model, Pressure};
use crate::mesh::structured::{box_faces, box_mesh, map_nodes, BoxElement};

/// Geometry and mesh of the Hertz slice.
#[derive(Clone, Debug)]
pub struct HertzMesh {
    /// Cylinder radius R (mm).
    pub radius: f64,
    /// Width W of both bodies (mm), W < R.
    pub width: f64,
    /// Depth H of the flat (mm).
    pub depth: f64,
    /// Slice thickness t in z (mm).
    pub thickness: f64,
    /// Extent of the uniform fine zone from x = 0 (mm).
    pub fine_extent: f64,
    /// Cells over the fine zone.
    pub fine_cells: usize,
    /// Growth ratio of the graded cells (> 1).
    pub growth: f64,
    pub element: BoxElement,
}

/// Cell boundaries on [0, length]: `fine` cells of size `extent/fine`, then
/// geometric growth by `growth`, the graded part scaled to end at `length`.
pub fn graded_distribution(length: f64, extent: f64, fine: usize, growth: f64) -> Vec<f64> {
    let h = extent / fine as f64;
    let mut x: Vec<f64> = (0..=fine)
        .map(|i| extent * i as f64 / fine as f64)
        .collect();
    if extent >= length {
        let s = length / extent;
        return x.iter().map(|v| v * s).collect();
    }
    let mut sizes = Vec::new();
    let mut s = h;
    let mut total = 0.0;
    let rest = length - extent;
    loop {
        s *= growth;
        if total + s > rest {
            break;
        }
        sizes.push(s);
        total += s;
    }
    if sizes.is_empty() {
        sizes.push(rest);
        total = rest;
    }
    // distribute the remainder proportionally (sizes keep their ratios)
    let scale = rest / total;
    let mut pos = extent;
    for s in &sizes {
        pos += s * scale;
        x.push(pos);
    }
    let last = x.len() - 1;
    x[last] = length;
    x
}

/// Lattice coordinate (node index along an axis, 0..=2n) to position on a
/// distribution of cell boundaries: even = boundary, odd = cell middle.
pub(crate) fn lattice_position(dist: &[f64], l: usize) -> f64 {
    if l.is_multiple_of(2) {
        dist[l / 2]
    } else {
        0.5 * (dist[l / 2] + dist[l / 2 + 1])
    }
}

impl HertzMesh {
    fn check(&self) -> Result<(), FlankError> {
        let ok = self.radius > 0.0
            && self.width > 0.0
            && self.width < 0.95 * self.radius
            && self.depth > 0.0
            && self.thickness > 0.0
            && self.fine_extent > 0.0
            && self.fine_cells > 0
            && self.growth > 1.0
            && [
                self.radius,
                self.width,
                self.depth,
                self.thickness,
                self.fine_extent,
                self.growth,
            ]
            .iter()
            .all(|v| v.is_finite());
        if ok {
            Ok(())
        } else {
            Err(FlankError::Model(format!(
                "Hertz mesh: need R, W, H, t > 0, W < 0.95 R, a fine zone and growth > 1: {self:?}"
            )))
        }
    }

    /// Builds the two-body mesh.
    pub fn build(&self) -> Result<Mesh, FlankError> {
        self.check()?;
        let r = self.radius;
        let xd = graded_distribution(self.width, self.fine_extent, self.fine_cells, self.growth);
        let h = self.fine_extent / self.fine_cells as f64;
        let yd = graded_distribution(self.depth, h, 1, self.growth);
        let eta = graded_distribution(r, h, 1, self.growth);
        let nx = xd.len() - 1;
        let t = self.thickness;
        let arc = |x: f64| r - (r * r - x * x).sqrt();
        // flat: lattice (lx, ly, lz) → (X, −depth(ny2 − ly), z)
        let ny = yd.len() - 1;
        let mut flat = box_mesh(
            [(2 * nx) as f64, (2 * ny) as f64, 2.0],
            [nx, ny, 1],
            self.element,
        );
        map_nodes(&mut flat, |l| {
            let (lx, ly, lz) = (
                l[0].round() as usize,
                l[1].round() as usize,
                l[2].round() as usize,
            );
            [
                lattice_position(&xd, lx),
                -lattice_position(&yd, 2 * ny - ly),
                0.5 * t * lz as f64,
            ]
        });
        let ne = eta.len() - 1;
        let mut cyl = box_mesh(
            [(2 * nx) as f64, (2 * ne) as f64, 2.0],
            [nx, ne, 1],
            self.element,
        );
        map_nodes(&mut cyl, |l| {
            let (lx, ly, lz) = (
                l[0].round() as usize,
                l[1].round() as usize,
                l[2].round() as usize,
            );
            let x = lattice_position(&xd, lx);
            let y0 = arc(x);
            let e = lattice_position(&eta, ly) / r;
            [x, y0 + e * (r - y0), 0.5 * t * lz as f64]
        });
        let mut mesh = Mesh::new();
        let mut add = |src: &Mesh, offset: u64, prefix: &str, sets: &[(&str, &str)], eset: &str| {
            let base = mesh.node_count();
            for (label, x) in src.node_labels.iter().zip(&src.coords) {
                mesh.add_node(offset + label, *x).expect("unique labels");
            }
            let ebase = mesh.elements.len();
            for el in &src.elements {
                mesh.add_element(
                    offset + el.label,
                    el.kind,
                    el.nodes.iter().map(|&n| n + base).collect(),
                )
                .expect("unique labels");
            }
            for (from, to) in sets {
                let nodes: Vec<usize> = src.node_sets[*from].iter().map(|&n| n + base).collect();
                mesh.extend_node_set(&format!("{prefix}{to}"), nodes.iter().copied());
                if *to == "Z0" || *to == "Z1" {
                    mesh.extend_node_set(to, nodes);
                }
            }
            mesh.extend_element_set(eset, ebase..mesh.elements.len());
        };
        add(
            &flat,
            0,
            "FLAT_",
            &[
                ("Y1", "TOP"),
                ("Y0", "BOTTOM"),
                ("X0", "SYM"),
                ("Z0", "Z0"),
                ("Z1", "Z1"),
            ],
            "FLAT",
        );
        let count = flat.node_count().max(flat.elements.len()) as u64;
        let mut offset = 10u64;
        while offset < count {
            offset *= 10;
        }
        add(
            &cyl,
            offset,
            "CYL_",
            &[
                ("Y0", "ARC"),
                ("Y1", "TOP"),
                ("X0", "SYM"),
                ("Z0", "Z0"),
                ("Z1", "Z1"),
            ],
            "CYLINDER",
        );
        for set in ["FLAT_Z0", "FLAT_Z1", "CYL_Z0", "CYL_Z1"] {
            mesh.node_sets.remove(set);
        }
        let (n, m) = (mesh.node_count(), mesh.elements.len());
        mesh.extend_node_set("NALL", 0..n);
        mesh.extend_element_set("EALL", 0..m);
        Ok(mesh)
    }
}

/// How the cylinder is loaded.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum HertzLoad {
    /// Line load P′ (N/mm) of the whole cylinder; the half model carries
    /// P′/2 as a uniform pressure P′/(2W) on its top face. The cylinder's
    /// vertical motion is then held by contact alone.
    Force(f64),
    /// The top face moved down by this much (mm).
    Displacement(f64),
}

/// The complete contact model: steel-like material on both bodies, plane
/// strain (u_z = 0 on Z0 and Z1), symmetry u_x = 0 on x = 0, flat bottom
/// held in y, the load, and the contact pair CYL_ARC (slave, element faces)
/// on FLAT_TOP (master) with the given law.
pub fn hertz_model(
    geometry: &HertzMesh,
    young: f64,
    poisson: f64,
    load: HertzLoad,
    law: PressureOverclosure,
) -> Result<Model, FlankError> {
    let mesh = geometry.build()?;
    let ne = mesh.elements.len();
    let mut model = Model {
        materials: vec![Material::new("STEEL", young, poisson)?],
        element_material: vec![0; ne],
        mesh,
        ..Default::default()
    };
    let sets = |m: &Model, s: &str| m.mesh.node_sets[s].clone();
    let fix = |m: &mut Model, set: &str, component: usize, value: f64| {
        for node in sets(m, set) {
            m.dirichlet.push(Dirichlet {
                node,
                component,
                value,
            });
        }
    };
    fix(&mut model, "Z0", 2, 0.0);
    fix(&mut model, "Z1", 2, 0.0);
    fix(&mut model, "FLAT_SYM", 0, 0.0);
    fix(&mut model, "CYL_SYM", 0, 0.0);
    fix(&mut model, "FLAT_BOTTOM", 1, 0.0);
    let cyl_faces = |m: &Model, set: &str| -> Vec<(usize, usize)> {
        let cyl: std::collections::HashSet<usize> =
            m.mesh.element_sets["CYLINDER"].iter().copied().collect();
        box_faces(&m.mesh, set)
            .into_iter()
            .filter(|(e, _)| cyl.contains(e))
            .collect()
    };
    match load {
        HertzLoad::Force(line_load) => {
            let p = 0.5 * line_load / geometry.width;
            for (element, face) in cyl_faces(&model, "CYL_TOP") {
                model.pressures.push(Pressure {
                    element,
                    face,
                    value: p,
                });
            }
        }
        HertzLoad::Displacement(d) => fix(&mut model, "CYL_TOP", 1, -d),
    }
    let slave = cyl_faces(&model, "CYL_ARC");
    let flat: std::collections::HashSet<usize> =
        model.mesh.element_sets["FLAT"].iter().copied().collect();
    let master: Vec<(usize, usize)> = box_faces(&model.mesh, "FLAT_TOP")
        .into_iter()
        .filter(|(e, _)| flat.contains(e))
        .collect();
    model.contact = ContactDefinition {
        surfaces: vec![
            Surface {
                name: "CYL_SURF".into(),
                kind: SurfaceKind::Element(slave),
            },
            Surface {
                name: "FLAT_SURF".into(),
                kind: SurfaceKind::Element(master),
            },
        ],
        interactions: vec![SurfaceInteraction {
            name: "STEEL_STEEL".into(),
            behavior: Some(law),
            friction: None,
        }],
        pairs: vec![ContactPair {
            interaction: "STEEL_STEEL".into(),
            slave: "CYL_SURF".into(),
            master: "FLAT_SURF".into(),
            small_sliding: true,
        }],
    };
    Ok(model)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fem::element::check_jacobian;

    #[test]
    fn distribution_is_graded_and_exact_at_the_ends() {
        let d = graded_distribution(6.0, 0.5, 10, 1.25);
        assert_eq!(d[0], 0.0);
        assert_eq!(*d.last().unwrap(), 6.0);
        assert!((d[10] - 0.5).abs() < 1e-15);
        for w in d.windows(3) {
            let (a, b) = (w[1] - w[0], w[2] - w[1]);
            assert!(b >= a * 0.999 && b <= a * 1.3, "{a} {b}");
        }
    }

    #[test]
    fn mesh_is_valid_and_the_arc_is_exact() {
        let g = HertzMesh {
            radius: 10.0,
            width: 6.0,
            depth: 6.0,
            thickness: 0.1,
            fine_extent: 0.5,
            fine_cells: 5,
            growth: 1.3,
            element: BoxElement::Hex20,
        };
        let mesh = g.build().unwrap();
        for (e, el) in mesh.elements.iter().enumerate() {
            assert!(
                check_jacobian(el.kind, &mesh.element_coords(e)).is_ok(),
                "element {}",
                el.label
            );
        }
        for &n in &mesh.node_sets["CYL_ARC"] {
            let x = mesh.coords[n];
            let r = (x[0] * x[0] + (x[1] - 10.0).powi(2)).sqrt();
            assert!((r - 10.0).abs() < 1e-12);
        }
        // slave nodes lie over master nodes (same x distribution)
        let xs = |set: &str| {
            let mut v: Vec<i64> = mesh.node_sets[set]
                .iter()
                .map(|&n| (mesh.coords[n][0] * 1e9).round() as i64)
                .collect();
            v.sort_unstable();
            v.dedup();
            v
        };
        assert_eq!(xs("CYL_ARC"), xs("FLAT_TOP"));
        assert!(mesh.node_sets["FLAT_TOP"]
            .iter()
            .all(|&n| mesh.coords[n][1] == 0.0));
    }
}
