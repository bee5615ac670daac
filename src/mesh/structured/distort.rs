//! Pseudo-random distortion of a mesh: every node off the boundary moves
//! by at most a fraction of the shortest edge (patch tests, distortion
//! sensitivity), optionally keeping straight edges.

use std::collections::HashMap;

use super::corner_count;
use crate::fem::element::{edges, face_nodes};
use crate::fem::mesh::Mesh;

/// Marks the nodes on the mesh boundary: the nodes of element faces that no
/// other element shares (faces are matched by their sorted corner nodes).
pub(super) fn boundary_nodes(mesh: &Mesh) -> Vec<bool> {
    let mut count: HashMap<Vec<usize>, (usize, usize, usize)> = HashMap::new();
    for (e, el) in mesh.elements.iter().enumerate() {
        for f in 1..=el.kind.face_count() {
            let local = face_nodes(el.kind, f).expect("face number within the element's faces");
            let corners = if local.len() == 8 { 4 } else { 3 };
            let mut key: Vec<usize> = local[..corners].iter().map(|&p| el.nodes[p]).collect();
            key.sort_unstable();
            count.entry(key).or_insert((0, e, f)).0 += 1;
        }
    }
    let mut boundary = vec![false; mesh.node_count()];
    for &(c, e, f) in count.values() {
        if c == 1 {
            let el = &mesh.elements[e];
            for &p in face_nodes(el.kind, f).expect("face number within the element's faces") {
                boundary[el.nodes[p]] = true;
            }
        }
    }
    boundary
}

/// SplitMix64: a small deterministic generator (no external crate).
struct SplitMix64(u64);

impl SplitMix64 {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [-1, 1).
    fn symmetric(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (2.0 / (1u64 << 53) as f64) - 1.0
    }

    /// Uniform in the unit ball (rejection sampling).
    fn in_unit_ball(&mut self) -> [f64; 3] {
        loop {
            let v = [self.symmetric(), self.symmetric(), self.symmetric()];
            if v[0] * v[0] + v[1] * v[1] + v[2] * v[2] <= 1.0 {
                return v;
            }
        }
    }
}

/// Shortest corner-to-corner element edge of the mesh.
fn min_edge_length(mesh: &Mesh) -> f64 {
    let mut h = f64::INFINITY;
    for el in &mesh.elements {
        for &[a, b, _] in edges(el.kind) {
            let (p, q) = (mesh.coords[el.nodes[a]], mesh.coords[el.nodes[b]]);
            h = h.min(dist(p, q));
        }
    }
    h
}

pub(super) fn dist(p: [f64; 3], q: [f64; 3]) -> f64 {
    ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt()
}

/// Moves every node that is not on the mesh boundary by a pseudo-random
/// vector of length at most `amplitude · h`, `h` the shortest element edge
/// (for a box: the smallest cell size). Boundary nodes are those of element
/// faces not shared by two elements (for a box: the sets X0…Z1), so boundary
/// conditions and exact curved surfaces are preserved.
///
/// With `straight_edges`, only interior corner nodes are moved and interior
/// midside nodes are then put at the midpoint of their edge (elements keep
/// straight edges: tests geometric distortion only). Without it, every
/// interior node moves independently (curved edges: also tests the
/// quadratic geometry map). Deterministic for a given `seed`.
pub fn distort_interior(mesh: &mut Mesh, amplitude: f64, seed: u64, straight_edges: bool) {
    let boundary = boundary_nodes(mesh);
    let h = min_edge_length(mesh);
    if !h.is_finite() {
        return;
    }
    let mut midside = vec![false; mesh.node_count()];
    for el in &mesh.elements {
        for &n in &el.nodes[corner_count(el.kind)..] {
            midside[n] = true;
        }
    }
    let mut rng = SplitMix64(seed);
    let scale = amplitude * h;
    for n in 0..mesh.node_count() {
        if boundary[n] || (straight_edges && midside[n]) {
            continue;
        }
        let r = rng.in_unit_ball();
        for (x, d) in mesh.coords[n].iter_mut().zip(r) {
            *x += scale * d;
        }
    }
    if straight_edges {
        for e in 0..mesh.elements.len() {
            let kind = mesh.elements[e].kind;
            for &[a, b, m] in edges(kind) {
                let nodes = &mesh.elements[e].nodes;
                let (a, b, m) = (nodes[a], nodes[b], nodes[m]);
                if boundary[m] {
                    continue;
                }
                let (p, q) = (mesh.coords[a], mesh.coords[b]);
                mesh.coords[m] = [
                    0.5 * (p[0] + q[0]),
                    0.5 * (p[1] + q[1]),
                    0.5 * (p[2] + q[2]),
                ];
            }
        }
    }
}
