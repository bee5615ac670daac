//! The flank nodes that carry compliance tensors, and the flank faces
//! between them.
//!
//! A flank face is an element face (quad8 of a hex20 or of a wedge15's side,
//! tri6 of a wedge15's end) whose nodes all belong to one selected flank set;
//! its node list is in CalculiX face order (corners, then midsides; the
//! corner order makes ∂x/∂ξ × ∂x/∂η point out of the element), so the face
//! shape functions [`quad8_shape`] / [`tri6_shape`] interpolate over it.

use std::collections::HashMap;

use crate::error::FlankError;
use crate::fem::element::{face_nodes, quad8_shape, tri6_shape};
use crate::fem::mesh::Mesh;

/// Exact outward normal of a flank set's surface at (u, v): `f(set index, u, v)`.
pub type NormalFn<'a> = dyn Fn(usize, f64, f64) -> Result<[f64; 3], FlankError> + 'a;

/// One flank face: indices into [`FlankNodes`] (not mesh indices), 8 for a
/// quad8 face, 6 for a tri6 face, corners first.
#[derive(Clone, Debug, PartialEq)]
pub struct FlankFace {
    /// Index of the flank set (into [`FlankNodes::sets`]).
    pub set: u32,
    pub nodes: Vec<u32>,
}

/// The selected flank nodes of a body, in the order of the compliance
/// matrix: by set, then by v (axial), then by u (profile).
#[derive(Clone, Debug, PartialEq)]
pub struct FlankNodes {
    /// Names of the flank node sets, e.g. `FLANK_R1`, `FLANK_R2`, …
    pub sets: Vec<String>,
    /// Mesh node index of each flank node (empty when read from a file).
    pub nodes: Vec<usize>,
    /// Deck label of each flank node.
    pub labels: Vec<u64>,
    /// Set of each node (index into `sets`).
    pub set_of: Vec<u32>,
    /// Flank parameters (u, v): see [`crate::mesh::gear_sector`].
    pub uv: Vec<[f64; 2]>,
    /// Node positions (mm).
    pub positions: Vec<[f64; 3]>,
    /// Outward unit normals.
    pub normals: Vec<[f64; 3]>,
    /// Flank faces.
    pub faces: Vec<FlankFace>,
}

/// Reference coordinates of the face nodes (quad8 on [−1, 1]², tri6 on the unit triangle).
pub(crate) fn face_node_xi(count: usize) -> &'static [[f64; 2]] {
    const Q: [[f64; 2]; 8] = crate::fem::element::QUAD8_NODES;
    const T: [[f64; 2]; 6] = [
        [0.0, 0.0],
        [1.0, 0.0],
        [0.0, 1.0],
        [0.5, 0.0],
        [0.5, 0.5],
        [0.0, 0.5],
    ];
    if count == 8 {
        &Q
    } else {
        &T
    }
}

/// Face shape functions and their reference derivatives (8 or 6 nodes; a
/// tri6 face fills the first six entries). Fixed-size arrays: this sits in
/// the inner loops of point location and cell integration.
pub(crate) fn face_shape(count: usize, xi: [f64; 2]) -> ([f64; 8], [[f64; 2]; 8]) {
    if count == 8 {
        quad8_shape(xi)
    } else {
        let (n, d) = tri6_shape(xi);
        let mut nn = [0.0; 8];
        let mut dd = [[0.0; 2]; 8];
        nn[..6].copy_from_slice(&n);
        dd[..6].copy_from_slice(&d);
        (nn, dd)
    }
}

pub(crate) fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

pub(crate) fn norm(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

impl FlankNodes {
    /// The largest extent in v (the face direction) of a flank face: the
    /// element length along the face (0 without faces).
    pub fn largest_face_length_v(&self) -> f64 {
        self.faces
            .iter()
            .map(|f| {
                let (lo, hi) = f
                    .nodes
                    .iter()
                    .map(|&a| self.uv[a as usize][1])
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| {
                        (l.min(v), h.max(v))
                    });
                hi - lo
            })
            .filter(|d| d.is_finite())
            .fold(0.0, f64::max)
    }

    /// Collects the nodes of the named sets of `mesh` with their (u, v)
    /// from `uv` (mesh index → (u, v)), finds the flank faces, and sets the
    /// normals by `normal(set index, u, v)` if given, else from the faces
    /// (the average of the adjacent faces' outward normals at the node).
    pub fn from_mesh(
        mesh: &Mesh,
        sets: &[String],
        uv: &HashMap<usize, (f64, f64)>,
        normal: Option<&NormalFn>,
    ) -> Result<Self, FlankError> {
        if sets.is_empty() {
            return Err(FlankError::Model("no flank sets selected".into()));
        }
        let nn = mesh.node_count();
        let mut set_of_mesh = vec![u32::MAX; nn];
        let mut entries: Vec<(u32, f64, f64, usize)> = Vec::new();
        for (s, name) in sets.iter().enumerate() {
            let nodes = mesh
                .node_sets
                .get(&name.to_ascii_uppercase())
                .ok_or_else(|| {
                    FlankError::Model(format!("the mesh has no flank node set {name}"))
                })?;
            if nodes.is_empty() {
                return Err(FlankError::Model(format!("flank node set {name} is empty")));
            }
            for &n in nodes {
                if n >= nn {
                    return Err(FlankError::Model(format!(
                        "flank node set {name} refers to node index {n} beyond the mesh"
                    )));
                }
                if set_of_mesh[n] != u32::MAX {
                    continue; // first set wins
                }
                let &(u, v) = uv.get(&n).ok_or_else(|| {
                    FlankError::Model(format!(
                        "flank node {} of set {name} has no flank parameters (u, v)",
                        mesh.node_labels[n]
                    ))
                })?;
                if !(u.is_finite() && v.is_finite()) {
                    return Err(FlankError::Model(format!(
                        "flank node {} has non-finite (u, v)",
                        mesh.node_labels[n]
                    )));
                }
                set_of_mesh[n] = s as u32;
                entries.push((s as u32, v, u, n));
            }
        }
        entries.sort_by(|a, b| {
            a.0.cmp(&b.0)
                .then(a.1.total_cmp(&b.1))
                .then(a.2.total_cmp(&b.2))
                .then(a.3.cmp(&b.3))
        });
        let mut index_of = vec![u32::MAX; nn];
        for (k, e) in entries.iter().enumerate() {
            index_of[e.3] = k as u32;
        }
        // flank faces: all nodes in one selected set
        let mut faces = Vec::new();
        let mut seen = std::collections::HashSet::new();
        for el in &mesh.elements {
            for f in 1..=el.kind.face_count() {
                let Some(local) = face_nodes(el.kind, f) else {
                    continue;
                };
                let idx: Vec<u32> = local.iter().map(|&a| index_of[el.nodes[a]]).collect();
                if idx.contains(&u32::MAX) {
                    continue;
                }
                let set = entries[idx[0] as usize].0;
                if idx.iter().any(|&i| entries[i as usize].0 != set) {
                    continue;
                }
                let mut key = idx.clone();
                key.sort_unstable();
                if seen.insert(key) {
                    faces.push(FlankFace { set, nodes: idx });
                }
            }
        }
        let nodes: Vec<usize> = entries.iter().map(|e| e.3).collect();
        let mut out = FlankNodes {
            sets: sets.iter().map(|s| s.to_ascii_uppercase()).collect(),
            labels: nodes.iter().map(|&n| mesh.node_labels[n]).collect(),
            set_of: entries.iter().map(|e| e.0).collect(),
            uv: entries.iter().map(|e| [e.2, e.1]).collect(),
            positions: nodes.iter().map(|&n| mesh.coords[n]).collect(),
            normals: Vec::new(),
            faces,
            nodes,
        };
        out.normals = match normal {
            Some(f) => (0..out.labels.len())
                .map(|k| {
                    let n = f(out.set_of[k] as usize, out.uv[k][0], out.uv[k][1])?;
                    let l = norm(n);
                    if !(l > 0.0) || !l.is_finite() {
                        return Err(FlankError::Model(format!(
                            "flank node {}: degenerate normal",
                            out.labels[k]
                        )));
                    }
                    Ok([n[0] / l, n[1] / l, n[2] / l])
                })
                .collect::<Result<_, _>>()?,
            None => out.face_normals()?,
        };
        Ok(out)
    }

    /// Outward unit normals at the nodes from the flank faces: the average of
    /// ∂x/∂ξ × ∂x/∂η (normalized) of every face at the node's reference point.
    pub fn face_normals(&self) -> Result<Vec<[f64; 3]>, FlankError> {
        let mut acc = vec![[0.0; 3]; self.labels.len()];
        for face in &self.faces {
            let k = face.nodes.len();
            for (a, xi) in face_node_xi(k).iter().enumerate() {
                let (_, d) = face_shape(k, *xi);
                let mut t1 = [0.0; 3];
                let mut t2 = [0.0; 3];
                for (b, &node) in face.nodes.iter().enumerate() {
                    let x = self.positions[node as usize];
                    for i in 0..3 {
                        t1[i] += x[i] * d[b][0];
                        t2[i] += x[i] * d[b][1];
                    }
                }
                let n = cross(t1, t2);
                let l = norm(n);
                if l > 0.0 {
                    let t = &mut acc[face.nodes[a] as usize];
                    for i in 0..3 {
                        t[i] += n[i] / l;
                    }
                }
            }
        }
        acc.into_iter()
            .enumerate()
            .map(|(k, n)| {
                let l = norm(n);
                if l > 0.0 {
                    Ok([n[0] / l, n[1] / l, n[2] / l])
                } else {
                    Err(FlankError::Model(format!(
                        "flank node {} lies on no flank face: no normal",
                        self.labels[k]
                    )))
                }
            })
            .collect()
    }

    /// The part of these flank nodes at and above `u_min[set]` in the
    /// profile parameter u: every flank face that reaches u ≥ `u_min` of
    /// its set, with all its nodes (so no face is cut and every kept node
    /// keeps a face to interpolate on), in the same order (set, v, u).
    /// Every flank point with u ≥ `u_min` lies on a kept face (the face
    /// that holds it reaches u), so `u_min` is where the restricted tensor
    /// is complete ([`crate::compliance::ComplianceMeta::region_u_min`]).
    /// An entry of −∞ keeps the whole set. Errors when `u_min` has not one
    /// finite-or-−∞ value per set, or when a set keeps no face.
    pub fn restrict_u(&self, u_min: &[f64]) -> Result<FlankNodes, FlankError> {
        self.validate()?;
        if u_min.len() != self.sets.len() {
            return Err(FlankError::Model(format!(
                "flank restriction: {} lower bounds of u for {} flank sets",
                u_min.len(),
                self.sets.len()
            )));
        }
        if let Some(bad) = u_min.iter().find(|u| u.is_nan() || **u == f64::INFINITY) {
            return Err(FlankError::Model(format!(
                "flank restriction: lower bound of u {bad} (a finite value or −∞ is needed)"
            )));
        }
        let n = self.len();
        let mut keep = vec![false; n];
        let mut kept_faces = Vec::new();
        for f in &self.faces {
            let top = f
                .nodes
                .iter()
                .map(|&a| self.uv[a as usize][0])
                .fold(f64::NEG_INFINITY, f64::max);
            if top >= u_min[f.set as usize] {
                for &a in &f.nodes {
                    keep[a as usize] = true;
                }
                kept_faces.push(f);
            }
        }
        let mut new_index = vec![u32::MAX; n];
        let mut order = Vec::new();
        for (k, _) in keep.iter().enumerate().filter(|(_, &x)| x) {
            new_index[k] = order.len() as u32;
            order.push(k);
        }
        let mut kept_per_set = vec![0usize; self.sets.len()];
        for f in &kept_faces {
            kept_per_set[f.set as usize] += 1;
        }
        if let Some(s) = kept_per_set.iter().position(|&c| c == 0) {
            return Err(FlankError::Model(format!(
                "flank restriction: no face of {} reaches u ≥ {} (its nodes end at u = {})",
                self.sets[s],
                u_min[s],
                self.uv
                    .iter()
                    .zip(&self.set_of)
                    .filter(|(_, &t)| t as usize == s)
                    .map(|(p, _)| p[0])
                    .fold(f64::NEG_INFINITY, f64::max)
            )));
        }
        let pick = |v: &[[f64; 3]]| -> Vec<[f64; 3]> { order.iter().map(|&k| v[k]).collect() };
        let out = FlankNodes {
            sets: self.sets.clone(),
            nodes: if self.nodes.is_empty() {
                Vec::new()
            } else {
                order.iter().map(|&k| self.nodes[k]).collect()
            },
            labels: order.iter().map(|&k| self.labels[k]).collect(),
            set_of: order.iter().map(|&k| self.set_of[k]).collect(),
            uv: order.iter().map(|&k| self.uv[k]).collect(),
            positions: pick(&self.positions),
            normals: pick(&self.normals),
            faces: kept_faces
                .into_iter()
                .map(|f| FlankFace {
                    set: f.set,
                    nodes: f.nodes.iter().map(|&a| new_index[a as usize]).collect(),
                })
                .collect(),
        };
        Ok(out)
    }

    /// Number of flank nodes.
    pub fn len(&self) -> usize {
        self.labels.len()
    }

    pub fn is_empty(&self) -> bool {
        self.labels.is_empty()
    }

    /// Index of a set by name.
    pub fn set_index(&self, name: &str) -> Option<usize> {
        let name = name.to_ascii_uppercase();
        self.sets.iter().position(|s| *s == name)
    }

    /// Checks the internal consistency (lengths, face indices, finite values).
    pub fn validate(&self) -> Result<(), FlankError> {
        let n = self.labels.len();
        let bad = |what: &str| Err(FlankError::Model(format!("flank nodes: {what}")));
        if self.set_of.len() != n
            || self.uv.len() != n
            || self.positions.len() != n
            || self.normals.len() != n
            || !(self.nodes.is_empty() || self.nodes.len() == n)
        {
            return bad("inconsistent array lengths");
        }
        if self.set_of.iter().any(|&s| s as usize >= self.sets.len()) {
            return bad("set index out of range");
        }
        for f in &self.faces {
            if !(f.nodes.len() == 8 || f.nodes.len() == 6)
                || f.nodes.iter().any(|&i| i as usize >= n)
                || f.set as usize >= self.sets.len()
            {
                return bad("face with a bad node count or index");
            }
        }
        let finite = self
            .uv
            .iter()
            .flatten()
            .chain(self.positions.iter().flatten())
            .chain(self.normals.iter().flatten())
            .all(|v| v.is_finite());
        if !finite {
            return bad("non-finite values");
        }
        Ok(())
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::mesh::structured::{cantilever_model, BoxElement};

    /// The top face (y = 10) of a small box as a "flank" with (u, v) = (x, z).
    pub(crate) fn box_flank(kind: BoxElement) -> (crate::fem::model::Model, FlankNodes) {
        box_flank_cells([4, 2, 2], kind)
    }

    /// [`box_flank`] on a box of `cells` cells (the box's nodes at x = 0
    /// clamped).
    pub(crate) fn box_flank_cells(
        cells: [usize; 3],
        kind: BoxElement,
    ) -> (crate::fem::model::Model, FlankNodes) {
        let mut model = cantilever_model(cells, kind, 0.0).unwrap();
        let top: Vec<usize> = (0..model.mesh.node_count())
            .filter(|&n| (model.mesh.coords[n][1] - 10.0).abs() < 1e-9)
            .collect();
        model.mesh.extend_node_set("TOP", top.iter().copied());
        let uv: HashMap<usize, (f64, f64)> = top
            .iter()
            .map(|&n| (n, (model.mesh.coords[n][0], model.mesh.coords[n][2])))
            .collect();
        let flank = FlankNodes::from_mesh(&model.mesh, &["TOP".into()], &uv, None).unwrap();
        (model, flank)
    }

    #[test]
    fn box_top_faces_and_normals() {
        for kind in [BoxElement::Hex20, BoxElement::Wedge15] {
            let (_, flank) = box_flank(kind);
            flank.validate().unwrap();
            // 4 × 2 cells on the top face
            assert_eq!(flank.faces.len(), 8, "{kind:?}");
            assert!(flank.faces.iter().all(|f| f.nodes.len() == 8));
            for n in &flank.normals {
                assert!((n[1] - 1.0).abs() < 1e-12, "{n:?}");
            }
            // sorted by v then u
            for w in flank.uv.windows(2) {
                assert!(w[0][1] < w[1][1] || (w[0][1] == w[1][1] && w[0][0] < w[1][0]));
            }
        }
    }

    #[test]
    fn missing_set_and_uv_are_errors() {
        let (model, _) = box_flank(BoxElement::Hex20);
        let e = FlankNodes::from_mesh(&model.mesh, &["NOPE".into()], &HashMap::new(), None)
            .unwrap_err();
        assert!(e.to_string().contains("NOPE"), "{e}");
        let e =
            FlankNodes::from_mesh(&model.mesh, &["TOP".into()], &HashMap::new(), None).unwrap_err();
        assert!(e.to_string().contains("(u, v)"), "{e}");
    }
}
