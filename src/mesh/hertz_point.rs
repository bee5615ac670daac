//! Hertz point contact: an elliptic-paraboloid cap with two different
//! principal radii pressed onto a flat block, quarter model (x ≥ 0,
//! y ≥ 0), graded to the contact.
//!
//! The cap's contact surface is z = x²/(2Rₓ) + y²/(2R_y): the gap to the
//! block's top (z = 0) is exactly Hertz's quadratic separation
//! h = A x² + B y², A = 1/(2Rₓ), B = 1/(2R_y) (Johnson, *Contact
//! Mechanics*, §4.1), so what separates the FE answer from the
//! Hertz solution is the mesh and the finite bodies, not a higher-order
//! term of the profile.
//!
//! Both bodies are structured quadratic meshes ([`box_mesh`] on integer
//! lattice coordinates, then [`map_nodes`]):
//!
//! * block: x ∈ [0, Wₓ], y ∈ [0, W_y], z ∈ [−D, 0];
//! * cap: the same x, y; z from the paraboloid up to the plane z = H.
//!
//! In x and in y both bodies share one distribution: `fine_cells` equal
//! cells over [0, fine_x] (resp. [0, fine_y]), then cells growing by
//! `growth` ([`graded_distribution`]), so every slave node lies over a
//! master node. Taking fine_x : fine_y as the ratio of the contact
//! ellipse's semi-axes gives cells shaped like the ellipse, the same number
//! across each semi-axis. In z the first cell at the contact has the
//! smaller fine size and the cells grow by `growth`. Midside nodes of the
//! contact surface lie exactly on the paraboloid.
//!
//! Node sets (upper case): BLOCK_TOP (z = 0), BLOCK_BOTTOM, CAP_SURF (the
//! paraboloid), CAP_TOP (z = H), XSYM (x = 0, both bodies), YSYM (y = 0,
//! both bodies), NALL. Element sets BLOCK, CAP, EALL. Node labels: block
//! 1.., cap from 10ᵏ + 1, the smallest power of ten above the block's
//! node and element counts (CalculiX sizes its arrays by the largest
//! label); element labels likewise.

use std::collections::HashSet;

use crate::error::FlankError;
use crate::fem::contact_definition::{
    ContactDefinition, ContactPair, PressureOverclosure, Surface, SurfaceInteraction, SurfaceKind,
};
use crate::fem::material::Material;
use crate::fem::mesh::{Mesh, SetKind};
use crate::fem::model::{Dirichlet, Model, Pressure};
use crate::mesh::hertz::{graded_distribution, lattice_position};
use crate::mesh::structured::{box_faces, box_mesh, map_nodes, BoxElement};

/// Geometry and mesh of the point-contact quarter model.
#[derive(Clone, Debug)]
pub struct PointContactMesh {
    /// Radius Rₓ of the cap's profile in the xz-plane (mm).
    pub radius_x: f64,
    /// Radius R_y of the cap's profile in the yz-plane (mm).
    pub radius_y: f64,
    /// Extent Wₓ of both bodies in x (mm).
    pub width_x: f64,
    /// Extent W_y of both bodies in y (mm).
    pub width_y: f64,
    /// Depth D of the block (mm).
    pub depth: f64,
    /// Height H of the cap's top plane above the contact point (mm).
    pub height: f64,
    /// Extent of the uniform fine zone along x from x = 0 (mm).
    pub fine_x: f64,
    /// Extent of the uniform fine zone along y from y = 0 (mm).
    pub fine_y: f64,
    /// Cells over each fine zone.
    pub fine_cells: usize,
    /// Growth ratio of the graded cells (> 1).
    pub growth: f64,
    pub element: BoxElement,
}

/// Integer lattice indices of a lattice point of [`box_mesh`] built on
/// integer sizes.
fn lattice(l: [f64; 3]) -> [usize; 3] {
    l.map(|v| v.round() as usize)
}

impl PointContactMesh {
    /// Height of the paraboloid above the contact point (mm).
    pub fn profile(&self, x: f64, y: f64) -> f64 {
        0.5 * x * x / self.radius_x + 0.5 * y * y / self.radius_y
    }

    fn check(&self) -> Result<(), FlankError> {
        let values = [
            self.radius_x,
            self.radius_y,
            self.width_x,
            self.width_y,
            self.depth,
            self.height,
            self.fine_x,
            self.fine_y,
            self.growth,
        ];
        let ok = values.iter().all(|v| v.is_finite() && *v > 0.0)
            && self.fine_cells > 0
            && self.growth > 1.0
            && self.fine_x <= self.width_x
            && self.fine_y <= self.width_y;
        if !ok {
            return Err(FlankError::Model(format!(
                "Hertz point mesh: need finite positive radii, widths, depth, height and \
                 fine zones within the widths, fine cells > 0 and growth > 1: {self:?}"
            )));
        }
        // the cap must keep a body above its paraboloid everywhere
        let rim = self.profile(self.width_x, self.width_y);
        if rim > 0.75 * self.height {
            return Err(FlankError::Model(format!(
                "Hertz point mesh: the paraboloid rises {rim:.4} mm at the far corner, more than \
                 3/4 of the cap height H = {} mm: raise H or shrink the widths",
                self.height
            )));
        }
        Ok(())
    }

    /// Builds the two-body mesh.
    pub fn build(&self) -> Result<Mesh, FlankError> {
        self.check()?;
        let n = self.fine_cells;
        let xd = graded_distribution(self.width_x, self.fine_x, n, self.growth);
        let yd = graded_distribution(self.width_y, self.fine_y, n, self.growth);
        let h = self.fine_x.min(self.fine_y) / n as f64;
        let zb = graded_distribution(self.depth, h, 1, self.growth);
        let zc = graded_distribution(self.height, h, 1, self.growth);
        let (nx, ny) = (xd.len() - 1, yd.len() - 1);
        let size = |nz: usize| [(2 * nx) as f64, (2 * ny) as f64, (2 * nz) as f64];
        // block: lattice (lx, ly, lz) → (x, y, −depth(nz2 − lz))
        let nzb = zb.len() - 1;
        let mut block = box_mesh(size(nzb), [nx, ny, nzb], self.element);
        map_nodes(&mut block, |l| {
            let [lx, ly, lz] = lattice(l);
            [
                lattice_position(&xd, lx),
                lattice_position(&yd, ly),
                -lattice_position(&zb, 2 * nzb - lz),
            ]
        });
        // cap: z from the paraboloid f(x, y) to H, graded from the contact
        let nzc = zc.len() - 1;
        let mut cap = box_mesh(size(nzc), [nx, ny, nzc], self.element);
        let height = self.height;
        map_nodes(&mut cap, |l| {
            let [lx, ly, lz] = lattice(l);
            let (x, y) = (lattice_position(&xd, lx), lattice_position(&yd, ly));
            let z0 = self.profile(x, y);
            let eta = lattice_position(&zc, lz) / height;
            [x, y, z0 + eta * (height - z0)]
        });
        let mut mesh = Mesh::new();
        let rename = |prefix: &'static str, pairs: &'static [(&'static str, &'static str)]| {
            move |kind: SetKind, name: &str| -> Option<String> {
                if kind == SetKind::Element {
                    return None;
                }
                pairs.iter().find(|(from, _)| *from == name).map(|(_, to)| {
                    if to.ends_with("SYM") {
                        to.to_string()
                    } else {
                        format!("{prefix}{to}")
                    }
                })
            }
        };
        const BLOCK_SETS: &[(&str, &str)] = &[
            ("Z1", "TOP"),
            ("Z0", "BOTTOM"),
            ("X0", "XSYM"),
            ("Y0", "YSYM"),
        ];
        const CAP_SETS: &[(&str, &str)] = &[
            ("Z0", "SURF"),
            ("Z1", "TOP"),
            ("X0", "XSYM"),
            ("Y0", "YSYM"),
        ];
        let clash = |e| FlankError::Model(format!("Hertz point mesh: label clash {e:?}"));
        mesh.append(&block, 0, 0, rename("BLOCK_", BLOCK_SETS))
            .map_err(clash)?;
        let block_elements = mesh.elements.len();
        mesh.extend_element_set("BLOCK", 0..block_elements);
        let count = block.node_count().max(block.elements.len()) as u64;
        let mut offset = 10u64;
        while offset < count {
            offset *= 10;
        }
        mesh.append(&cap, offset, offset, rename("CAP_", CAP_SETS))
            .map_err(clash)?;
        let (nn, ne) = (mesh.node_count(), mesh.elements.len());
        mesh.extend_element_set("CAP", block_elements..ne);
        mesh.extend_node_set("NALL", 0..nn);
        mesh.extend_element_set("EALL", 0..ne);
        Ok(mesh)
    }
}

/// How the cap is loaded.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PointLoad {
    /// Total force P (N) of the whole contact; the quarter model carries
    /// P/4 as a uniform pressure P/(4WₓW_y) on the cap's top face. The
    /// cap's vertical motion is then held by contact alone (a floating
    /// mode, [`crate::contact::floating`]).
    Force(f64),
    /// The cap's top face moved down by this much (mm).
    Displacement(f64),
}

/// The complete contact model: one linear-elastic material on both
/// bodies, symmetry u_x = 0 on XSYM and u_y = 0 on YSYM, block bottom held
/// in z, the load, and the contact pair CAP_SURF (slave, element faces) on
/// BLOCK_TOP (master) with the given law, frictionless, small sliding.
pub fn hertz_point_model(
    geometry: &PointContactMesh,
    young: f64,
    poisson: f64,
    load: PointLoad,
    law: PressureOverclosure,
) -> Result<Model, FlankError> {
    match load {
        PointLoad::Force(p) | PointLoad::Displacement(p) if !(p.is_finite() && p > 0.0) => {
            return Err(FlankError::Model(format!(
                "Hertz point model: the load must be a positive force or approach, got {load:?}"
            )));
        }
        _ => {}
    }
    let mesh = geometry.build()?;
    let ne = mesh.elements.len();
    let mut model = Model {
        materials: vec![Material::new("STEEL", young, poisson)?],
        element_material: vec![0; ne],
        mesh,
        ..Default::default()
    };
    let fix = |m: &mut Model, set: &str, component: usize, value: f64| {
        for node in m.mesh.node_sets[set].clone() {
            m.dirichlet.push(Dirichlet {
                node,
                component,
                value,
            });
        }
    };
    fix(&mut model, "XSYM", 0, 0.0);
    fix(&mut model, "YSYM", 1, 0.0);
    fix(&mut model, "BLOCK_BOTTOM", 2, 0.0);
    let faces_of = |m: &Model, set: &str, body: &str| -> Vec<(usize, usize)> {
        let members: HashSet<usize> = m.mesh.element_sets[body].iter().copied().collect();
        box_faces(&m.mesh, set)
            .into_iter()
            .filter(|(e, _)| members.contains(e))
            .collect()
    };
    match load {
        PointLoad::Force(total) => {
            let p = 0.25 * total / (geometry.width_x * geometry.width_y);
            for (element, face) in faces_of(&model, "CAP_TOP", "CAP") {
                model.pressures.push(Pressure {
                    element,
                    face,
                    value: p,
                });
            }
        }
        PointLoad::Displacement(d) => fix(&mut model, "CAP_TOP", 2, -d),
    }
    let slave = faces_of(&model, "CAP_SURF", "CAP");
    let master = faces_of(&model, "BLOCK_TOP", "BLOCK");
    model.contact = ContactDefinition {
        surfaces: vec![
            Surface {
                name: "CAP_SURF".into(),
                kind: SurfaceKind::Element(slave),
            },
            Surface {
                name: "BLOCK_SURF".into(),
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
            slave: "CAP_SURF".into(),
            master: "BLOCK_SURF".into(),
            small_sliding: true,
        }],
    };
    Ok(model)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fem::element::check_jacobian;

    fn geometry() -> PointContactMesh {
        PointContactMesh {
            radius_x: 40.0,
            radius_y: 10.0,
            width_x: 4.0,
            width_y: 3.0,
            depth: 4.0,
            height: 4.0,
            fine_x: 1.2,
            fine_y: 0.5,
            fine_cells: 3,
            growth: 1.5,
            element: BoxElement::Hex20,
        }
    }

    #[test]
    fn mesh_is_valid_and_the_paraboloid_is_exact() {
        let g = geometry();
        let mesh = g.build().unwrap();
        for (e, el) in mesh.elements.iter().enumerate() {
            assert!(
                check_jacobian(el.kind, &mesh.element_coords(e)).is_ok(),
                "element {}",
                el.label
            );
        }
        let surf = &mesh.node_sets["CAP_SURF"];
        assert!(!surf.is_empty());
        for &n in surf {
            let x = mesh.coords[n];
            assert!((x[2] - g.profile(x[0], x[1])).abs() < 1e-15);
        }
        // every slave node lies over a master node (same x, y)
        let xy = |set: &str| {
            let mut v: Vec<(i64, i64)> = mesh.node_sets[set]
                .iter()
                .map(|&n| {
                    let x = mesh.coords[n];
                    ((x[0] * 1e9).round() as i64, (x[1] * 1e9).round() as i64)
                })
                .collect();
            v.sort_unstable();
            v
        };
        assert_eq!(xy("CAP_SURF"), xy("BLOCK_TOP"));
        assert!(mesh.node_sets["BLOCK_TOP"]
            .iter()
            .all(|&n| mesh.coords[n][2] == 0.0));
        assert!(mesh.node_sets["XSYM"]
            .iter()
            .all(|&n| mesh.coords[n][0] == 0.0));
        assert!(mesh.node_sets["YSYM"]
            .iter()
            .all(|&n| mesh.coords[n][1] == 0.0));
        // the symmetry sets hold nodes of both bodies
        for set in ["XSYM", "YSYM"] {
            let z: Vec<f64> = mesh.node_sets[set]
                .iter()
                .map(|&n| mesh.coords[n][2])
                .collect();
            assert!(z.iter().any(|&v| v > 0.0) && z.iter().any(|&v| v < 0.0));
        }
        // cap labels above every block label
        let first_cap = mesh.node_labels[mesh.elements[mesh.element_sets["CAP"][0]].nodes[0]];
        let block_max = mesh.element_sets["BLOCK"]
            .iter()
            .flat_map(|&e| mesh.elements[e].nodes.iter())
            .map(|&n| mesh.node_labels[n])
            .max()
            .unwrap();
        assert!(first_cap > block_max);
    }

    #[test]
    fn model_has_one_pair_and_the_quarter_load() {
        let g = geometry();
        let m = hertz_point_model(
            &g,
            210_000.0,
            0.3,
            PointLoad::Force(1000.0),
            PressureOverclosure::Hard,
        )
        .unwrap();
        // Σ p·area of the top faces = P/4 (flat rectangles in z = H)
        let top: f64 = m
            .pressures
            .iter()
            .map(|p| {
                let x = m.mesh.element_coords(p.element);
                let nodes =
                    crate::fem::element::face_nodes(m.mesh.elements[p.element].kind, p.face)
                        .unwrap();
                let c: Vec<[f64; 3]> = nodes.iter().map(|&k| x[k]).collect();
                assert!(c.iter().all(|v| v[2] == g.height));
                let span = |k: usize| {
                    let (lo, hi) = c
                        .iter()
                        .fold((f64::MAX, f64::MIN), |(a, b), v| (a.min(v[k]), b.max(v[k])));
                    hi - lo
                };
                p.value * span(0) * span(1)
            })
            .sum();
        assert!((top - 250.0).abs() < 1e-9, "{top}");
        assert_eq!(m.contact.pairs.len(), 1);
    }

    #[test]
    fn bad_geometry_and_load_are_errors() {
        let mut g = geometry();
        g.height = 0.8; // paraboloid rises 0.65 mm at the corner
        assert!(g.build().is_err());
        let mut g = geometry();
        g.radius_y = f64::NAN;
        assert!(g.build().is_err());
        let mut g = geometry();
        g.fine_x = 5.0;
        assert!(g.build().is_err());
        assert!(hertz_point_model(
            &geometry(),
            210_000.0,
            0.3,
            PointLoad::Force(-1.0),
            PressureOverclosure::Hard
        )
        .is_err());
    }
}
