//! Floating bodies: rigid-body modes that only contact holds.
//!
//! A body loaded by forces and held only by contact (a cylinder pressed on a
//! flat by a force, a pinion whose hub rotation is free and loaded by a
//! torque) has a singular stiffness. flank finds such modes R (per connected
//! body, as null vectors of the constraint rows, the same test as
//! [`crate::fem::static_analysis::check_rigid_body_modes`]), pins exactly as
//! many DOFs as there are modes (a statically determinate support chosen by
//! pivoted Gram–Schmidt on the mode values, so the pinned stiffness K₀ is
//! non-singular), and adds the mode amplitudes α as unknowns of the contact
//! problem with the equilibrium equations Rᵀ(f + Bᵀλ) = 0. The pins then
//! carry no reaction, and u = K₀⁻¹(f + Bᵀλ) + Rα.

use nalgebra::{DMatrix, SymmetricEigen};

use crate::fem::constraints::{DofMap, DofTarget};
use crate::fem::model::{Dirichlet, Model};

/// A free rigid-body mode of one body.
#[derive(Clone, Debug)]
pub struct RigidMode {
    /// Label of a node of the body (for messages).
    pub body_node: u64,
    /// Nodes of the body (indices).
    pub body_nodes: Vec<usize>,
    /// "translation y", "rotation about z + translation x", ...
    pub description: String,
    /// Full-DOF displacement field of the mode (node-major, 3 per node;
    /// max |u| = 1 over the body).
    pub displacement: Vec<f64>,
    /// Motion of free coupling reference DOFs: (coupling, dof 0..6, value).
    pub reference: Vec<(usize, usize, f64)>,
}

/// A DOF pinned to remove a floating mode from the stiffness.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Pin {
    /// Node DOF held at zero (an added Dirichlet condition).
    Node { node: usize, component: usize },
    /// Coupling reference DOF made fixed.
    Reference { coupling: usize, dof: usize },
}

/// The floating modes of a model and the pins that remove them.
#[derive(Clone, Debug, Default)]
pub struct FloatingModes {
    pub modes: Vec<RigidMode>,
    pub pins: Vec<Pin>,
}

impl FloatingModes {
    /// The model with the pins applied (the same model if there is none).
    pub fn pinned_model(&self, model: &Model) -> Model {
        let mut m = model.clone();
        for pin in &self.pins {
            match *pin {
                Pin::Node { node, component } => m.dirichlet.push(Dirichlet {
                    node,
                    component,
                    value: 0.0,
                }),
                Pin::Reference { coupling, dof } => m.couplings[coupling].free[dof] = false,
            }
        }
        m
    }

    /// Virtual work of mode `k` under the full load vector `f` and the
    /// coupling reference loads of `model`.
    pub fn work(&self, model: &Model, k: usize, f: &[f64]) -> f64 {
        let mode = &self.modes[k];
        let mut w: f64 = mode.displacement.iter().zip(f).map(|(a, b)| a * b).sum();
        for &(c, d, v) in &mode.reference {
            w += model.couplings[c].load[d] * v;
        }
        w
    }
}

fn find(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}

const MODE_NAMES: [&str; 6] = [
    "translation x",
    "translation y",
    "translation z",
    "rotation about x",
    "rotation about y",
    "rotation about z",
];

/// Finds the free rigid-body modes of `model` under its Dirichlet conditions
/// and couplings, and a statically determinate set of pins removing them.
pub fn floating_modes(model: &Model, dofs: &DofMap) -> FloatingModes {
    let mesh = &model.mesh;
    let nn = mesh.node_count();
    let mut parent: Vec<usize> = (0..nn).collect();
    let mut union = |a: usize, b: usize| {
        let (ra, rb) = (find(&mut parent, a), find(&mut parent, b));
        if ra != rb {
            parent[ra.max(rb)] = ra.min(rb);
        }
    };
    for el in &mesh.elements {
        for &n in &el.nodes[1..] {
            union(el.nodes[0], n);
        }
    }
    for cp in &model.couplings {
        for w in cp.nodes.windows(2) {
            union(w[0], w[1]);
        }
    }
    let used = mesh.used_nodes();
    let mut bodies: Vec<Vec<usize>> = Vec::new();
    let mut body_of = vec![usize::MAX; nn];
    for n in 0..nn {
        if !used[n] {
            continue;
        }
        let r = find(&mut parent, n);
        if body_of[r] == usize::MAX {
            body_of[r] = bodies.len();
            bodies.push(Vec::new());
        }
        body_of[n] = body_of[r];
        bodies[body_of[n]].push(n);
    }
    let mut coupling_of = vec![usize::MAX; nn];
    for (k, cp) in model.couplings.iter().enumerate() {
        for &n in &cp.nodes {
            coupling_of[n] = k;
        }
    }
    let mut out = FloatingModes::default();
    for nodes in &bodies {
        let mut c = [0.0; 3];
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for &n in nodes {
            for k in 0..3 {
                c[k] += mesh.coords[n][k];
                lo[k] = lo[k].min(mesh.coords[n][k]);
                hi[k] = hi[k].max(mesh.coords[n][k]);
            }
        }
        for ck in c.iter_mut() {
            *ck /= nodes.len() as f64;
        }
        let size = ((hi[0] - lo[0]).powi(2) + (hi[1] - lo[1]).powi(2) + (hi[2] - lo[2]).powi(2))
            .sqrt()
            .max(f64::MIN_POSITIVE);
        // rigid mode j at x, component i (rotations scaled by the body size)
        let mode = |x: [f64; 3]| -> [[f64; 6]; 3] {
            let r = [
                (x[0] - c[0]) / size,
                (x[1] - c[1]) / size,
                (x[2] - c[2]) / size,
            ];
            [
                [1.0, 0.0, 0.0, 0.0, r[2], -r[1]],
                [0.0, 1.0, 0.0, -r[2], 0.0, r[0]],
                [0.0, 0.0, 1.0, r[1], -r[0], 0.0],
            ]
        };
        // free reference DOFs of couplings on this body
        let mut refs: Vec<(usize, usize)> = Vec::new();
        let mut couplings: Vec<usize> = nodes
            .iter()
            .filter(|&&n| coupling_of[n] != usize::MAX)
            .map(|&n| coupling_of[n])
            .collect();
        couplings.sort_unstable();
        couplings.dedup();
        for &k in &couplings {
            for j in 0..6 {
                if model.couplings[k].free[j] {
                    refs.push((k, j));
                }
            }
        }
        let width = 6 + refs.len();
        let mut gram = DMatrix::<f64>::zeros(width, width);
        for &n in nodes {
            let m = mode(mesh.coords[n]);
            for i in 0..3 {
                let mut row: Vec<(usize, f64)> = (0..6).map(|j| (j, m[i][j])).collect();
                match dofs.targets[3 * n + i] {
                    DofTarget::Fixed(_) => {}
                    // an equation's dependent DOF follows other DOFs: free
                    // here, not fixed (the contact solver refuses equations)
                    DofTarget::Coupled { .. } if dofs.is_dependent(3 * n + i) => continue,
                    DofTarget::Coupled { .. } => {
                        let k = coupling_of[n];
                        let cp = &model.couplings[k];
                        let x = mesh.coords[n];
                        let r = [
                            (x[0] - cp.reference_point[0]) / size,
                            (x[1] - cp.reference_point[1]) / size,
                            (x[2] - cp.reference_point[2]) / size,
                        ];
                        let rot = [[0.0, r[2], -r[1]], [-r[2], 0.0, r[0]], [r[1], -r[0], 0.0]];
                        for (col, &(kk, j)) in refs.iter().enumerate() {
                            if kk != k {
                                continue;
                            }
                            let v = if j < 3 {
                                if i == j {
                                    1.0
                                } else {
                                    0.0
                                }
                            } else {
                                rot[i][j - 3]
                            };
                            if v != 0.0 {
                                row.push((6 + col, -v));
                            }
                        }
                    }
                    _ => continue,
                }
                for &(a, va) in &row {
                    for &(b, vb) in &row {
                        gram[(a, b)] += va * vb;
                    }
                }
            }
        }
        let eig = SymmetricEigen::new(gram);
        let scale = eig.eigenvalues.iter().fold(1.0f64, |a, &b| a.max(b));
        let mut body_modes = Vec::new();
        for k in 0..width {
            if eig.eigenvalues[k] > 1e-10 * scale {
                continue;
            }
            let v = eig.eigenvectors.column(k);
            let mut disp = vec![0.0; 3 * nn];
            let mut umax = 0.0f64;
            for &n in nodes {
                let m = mode(mesh.coords[n]);
                for i in 0..3 {
                    let u: f64 = (0..6).map(|j| m[i][j] * v[j]).sum();
                    let u = if matches!(dofs.targets[3 * n + i], DofTarget::Fixed(_)) {
                        0.0
                    } else {
                        u
                    };
                    disp[3 * n + i] = u;
                    umax = umax.max(u.abs());
                }
            }
            // reference rotations in rad: θ = v_rot / size
            let mut reference: Vec<(usize, usize, f64)> = refs
                .iter()
                .enumerate()
                .map(|(col, &(kk, j))| {
                    let val = v[6 + col];
                    (kk, j, if j >= 3 { val / size } else { val })
                })
                .collect();
            if umax <= 0.0 {
                // a reference DOF its nodes do not feel: not a body mode
                umax = reference.iter().fold(0.0f64, |a, r| a.max(r.2.abs()));
            }
            if umax <= 0.0 {
                continue;
            }
            for u in disp.iter_mut() {
                *u /= umax;
            }
            for r in reference.iter_mut() {
                r.2 /= umax;
            }
            let body: f64 = (0..6).map(|j| v[j] * v[j]).sum::<f64>().sqrt();
            let mut parts: Vec<(f64, usize)> = (0..6)
                .map(|j| (v[j].abs() / body.max(f64::MIN_POSITIVE), j))
                .filter(|p| p.0 > 0.2)
                .collect();
            parts.sort_by(|a, b| b.0.partial_cmp(&a.0).unwrap_or(std::cmp::Ordering::Equal));
            let description = parts
                .iter()
                .map(|p| MODE_NAMES[p.1])
                .collect::<Vec<_>>()
                .join(" + ");
            body_modes.push(RigidMode {
                body_node: mesh.node_labels[nodes[0]],
                body_nodes: nodes.clone(),
                description,
                displacement: disp,
                reference,
            });
        }
        if body_modes.is_empty() {
            continue;
        }
        // pins: pivoted Gram–Schmidt over the candidate DOF rows
        let m = body_modes.len();
        let mut rows: Vec<(Pin, Vec<f64>)> = Vec::new();
        for &n in nodes {
            for i in 0..3 {
                if let DofTarget::Free(_) = dofs.targets[3 * n + i] {
                    rows.push((
                        Pin::Node {
                            node: n,
                            component: i,
                        },
                        body_modes
                            .iter()
                            .map(|bm| bm.displacement[3 * n + i])
                            .collect(),
                    ));
                }
            }
        }
        for &(kk, j) in &refs {
            rows.push((
                Pin::Reference {
                    coupling: kk,
                    dof: j,
                },
                body_modes
                    .iter()
                    .map(|bm| {
                        bm.reference
                            .iter()
                            .find(|r| r.0 == kk && r.1 == j)
                            .map_or(0.0, |r| r.2)
                    })
                    .collect(),
            ));
        }
        for _ in 0..m {
            let Some((best, norm)) = rows
                .iter()
                .enumerate()
                .map(|(i, r)| (i, r.1.iter().map(|v| v * v).sum::<f64>().sqrt()))
                .max_by(|a, b| a.1.partial_cmp(&b.1).unwrap_or(std::cmp::Ordering::Equal))
            else {
                break;
            };
            if !(norm > 1e-8) {
                break;
            }
            let q: Vec<f64> = rows[best].1.iter().map(|v| v / norm).collect();
            out.pins.push(rows[best].0);
            rows.swap_remove(best);
            for r in rows.iter_mut() {
                let d: f64 = r.1.iter().zip(&q).map(|(a, b)| a * b).sum();
                for (a, b) in r.1.iter_mut().zip(&q) {
                    *a -= d * b;
                }
            }
        }
        out.modes.extend(body_modes);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fem::element::HEX20_NODES;
    use crate::fem::material::Material;
    use crate::fem::mesh::{ElementKind, Mesh};

    fn cube() -> Model {
        let mut mesh = Mesh::new();
        for (i, p) in HEX20_NODES.iter().enumerate() {
            mesh.add_node(i as u64 + 1, *p).unwrap();
        }
        mesh.add_element(1, ElementKind::C3D20, (0..20).collect())
            .unwrap();
        Model {
            mesh,
            materials: vec![Material::new("steel", 200e3, 0.3).unwrap()],
            element_material: vec![0],
            ..Default::default()
        }
    }

    /// A free cube has 6 modes; pinning them gives a solvable model; with z
    /// held on the bottom face, x, y and rotation about z remain.
    #[test]
    fn finds_and_pins_free_modes() {
        let model = cube();
        let dofs = DofMap::new(&model).unwrap();
        let fm = floating_modes(&model, &dofs);
        assert_eq!(fm.modes.len(), 6);
        assert_eq!(fm.pins.len(), 6);
        let pinned = fm.pinned_model(&model);
        let d2 = DofMap::new(&pinned).unwrap();
        assert!(crate::fem::static_analysis::check_rigid_body_modes(&pinned, &d2).is_ok());
        let mut m = cube();
        for (i, p) in HEX20_NODES.iter().enumerate() {
            if p[2] == -1.0 {
                m.dirichlet.push(Dirichlet {
                    node: i,
                    component: 2,
                    value: 0.0,
                });
            }
        }
        let dofs = DofMap::new(&m).unwrap();
        let fm = floating_modes(&m, &dofs);
        assert_eq!(fm.modes.len(), 3);
        let pinned = fm.pinned_model(&m);
        let d2 = DofMap::new(&pinned).unwrap();
        assert!(crate::fem::static_analysis::check_rigid_body_modes(&pinned, &d2).is_ok());
        // modes are rigid: zero at the fixed z DOFs, unit maximum
        for md in &fm.modes {
            let umax = md.displacement.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            assert!((umax - 1.0).abs() < 1e-12);
            for (i, p) in HEX20_NODES.iter().enumerate() {
                if p[2] == -1.0 {
                    assert_eq!(md.displacement[3 * i + 2], 0.0);
                }
            }
        }
    }
}
