//! Contact surfaces as quadratic faces: geometry of an 8-node quadrilateral
//! or 6-node triangle face (position, tangents, curvature terms), faces of a
//! surface, the boundary ("skin") faces of a mesh, and the tributary area of
//! every slave node.
//!
//! Tributary areas use positive lumped weights, because the consistent
//! weights of a quadratic face are not: a uniform pressure on an 8-node face
//! gives −1/12 of the force at each corner and 1/3 at each midside node
//! (0 and 1/3 on a 6-node triangle). As CalculiX does for node-to-face
//! contact, flank uses 1/100 (corner) and 24/100 (midside) on 8-node faces;
//! on 6-node faces the HRZ weights 3/57 and 16/57 (∝ ∫N²). The area of a
//! slave node is Σ over its faces of weight × face area; a penalty spring is
//! slope × that area.

use crate::contact::definition::{Surface, SurfaceKind};
use crate::fem::element::face_nodes;
use crate::fem::mesh::Mesh;
use crate::fem::quadrature::{quad_rule, TRIANGLE_3};

/// Lumped area weights of the corner and midside nodes of an 8-node face.
pub const QUAD8_AREA_WEIGHTS: [f64; 2] = [0.01, 0.24];
/// Lumped area weights of the corner and midside nodes of a 6-node face.
pub const TRI6_AREA_WEIGHTS: [f64; 2] = [3.0 / 57.0, 16.0 / 57.0];

/// One quadratic face: global node indices in face order (corners first,
/// then midsides; 8 for quadrilaterals, 6 for triangles), the element it
/// belongs to and its face number. Face order makes ∂x/∂ξ × ∂x/∂η point out
/// of the element.
#[derive(Clone, Debug, PartialEq)]
pub struct Face {
    pub element: usize,
    pub face: usize,
    pub nodes: Vec<usize>,
}

impl Face {
    /// The face `face` (1-based) of element `element`.
    pub fn of_element(mesh: &Mesh, element: usize, face: usize) -> Option<Face> {
        let el = mesh.elements.get(element)?;
        let local = face_nodes(el.kind, face)?;
        Some(Face {
            element,
            face,
            nodes: local.iter().map(|&a| el.nodes[a]).collect(),
        })
    }

    pub fn is_quad(&self) -> bool {
        self.nodes.len() == 8
    }

    /// Corner count (4 or 3).
    pub fn corners(&self) -> usize {
        if self.is_quad() {
            4
        } else {
            3
        }
    }

    /// Node coordinates in face order.
    pub fn coords(&self, coords: &[[f64; 3]]) -> Vec<[f64; 3]> {
        self.nodes.iter().map(|&n| coords[n]).collect()
    }
}

/// Shape functions of a face with first and second derivatives at `xi`.
#[derive(Clone, Debug)]
pub struct FaceShape {
    pub n: Vec<f64>,
    /// ∂N/∂ξ, ∂N/∂η.
    pub d: Vec<[f64; 2]>,
    /// ∂²N/∂ξ², ∂²N/∂η², ∂²N/∂ξ∂η.
    pub dd: Vec<[f64; 3]>,
}

/// Reference coordinates of the 8-node face nodes.
const QUAD8_POINTS: [[f64; 2]; 8] = crate::fem::element::QUAD8_NODES;

/// Face shape functions (8-node serendipity on [-1,1]², or 6-node triangle
/// with corners (0,0), (1,0), (0,1)) with derivatives up to second order.
/// Values and first derivatives agree with
/// [`crate::fem::element::quad8_shape`] / [`crate::fem::element::tri6_shape`].
pub fn face_shape(nodes: usize, xi: [f64; 2]) -> FaceShape {
    if nodes == 8 {
        let [x, y] = xi;
        let mut n = vec![0.0; 8];
        let mut d = vec![[0.0; 2]; 8];
        let mut dd = vec![[0.0; 3]; 8];
        for (a, p) in QUAD8_POINTS.iter().enumerate() {
            let (xa, ya) = (p[0], p[1]);
            if a < 4 {
                let (fx, fy) = (1.0 + x * xa, 1.0 + y * ya);
                let s = x * xa + y * ya - 1.0;
                n[a] = 0.25 * fx * fy * s;
                d[a] = [
                    0.25 * xa * fy * (2.0 * x * xa + y * ya),
                    0.25 * ya * fx * (x * xa + 2.0 * y * ya),
                ];
                dd[a] = [
                    0.5 * fy,
                    0.5 * fx,
                    0.25 * xa * ya * (2.0 * x * xa + 2.0 * y * ya + 1.0),
                ];
            } else if xa == 0.0 {
                let fy = 1.0 + y * ya;
                n[a] = 0.5 * (1.0 - x * x) * fy;
                d[a] = [-x * fy, 0.5 * (1.0 - x * x) * ya];
                dd[a] = [-fy, 0.0, -x * ya];
            } else {
                let fx = 1.0 + x * xa;
                n[a] = 0.5 * (1.0 - y * y) * fx;
                d[a] = [0.5 * (1.0 - y * y) * xa, -y * fx];
                dd[a] = [0.0, -fx, -y * xa];
            }
        }
        FaceShape { n, d, dd }
    } else {
        let [r, s] = xi;
        let l = [1.0 - r - s, r, s];
        let dl = [[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]];
        let mut n = vec![0.0; 6];
        let mut d = vec![[0.0; 2]; 6];
        let mut dd = vec![[0.0; 3]; 6];
        for i in 0..3 {
            n[i] = l[i] * (2.0 * l[i] - 1.0);
            for k in 0..2 {
                d[i][k] = (4.0 * l[i] - 1.0) * dl[i][k];
            }
            dd[i] = [
                4.0 * dl[i][0] * dl[i][0],
                4.0 * dl[i][1] * dl[i][1],
                4.0 * dl[i][0] * dl[i][1],
            ];
        }
        for (m, &(i, j)) in [(0usize, 1usize), (1, 2), (2, 0)].iter().enumerate() {
            n[3 + m] = 4.0 * l[i] * l[j];
            for k in 0..2 {
                d[3 + m][k] = 4.0 * (dl[i][k] * l[j] + l[i] * dl[j][k]);
            }
            dd[3 + m] = [
                8.0 * dl[i][0] * dl[j][0],
                8.0 * dl[i][1] * dl[j][1],
                4.0 * (dl[i][0] * dl[j][1] + dl[i][1] * dl[j][0]),
            ];
        }
        FaceShape { n, d, dd }
    }
}

/// Position, tangents ∂x/∂ξ, ∂x/∂η and second derivatives (ξξ, ηη, ξη) of
/// a face with node coordinates `x` at `xi`.
pub struct FacePoint {
    pub x: [f64; 3],
    pub t: [[f64; 3]; 2],
    pub tt: [[f64; 3]; 3],
    pub shape: FaceShape,
}

pub fn face_point(x: &[[f64; 3]], xi: [f64; 2]) -> FacePoint {
    let shape = face_shape(x.len(), xi);
    let mut p = [0.0; 3];
    let mut t = [[0.0; 3]; 2];
    let mut tt = [[0.0; 3]; 3];
    for (a, xa) in x.iter().enumerate() {
        for i in 0..3 {
            p[i] += shape.n[a] * xa[i];
            t[0][i] += shape.d[a][0] * xa[i];
            t[1][i] += shape.d[a][1] * xa[i];
            for k in 0..3 {
                tt[k][i] += shape.dd[a][k] * xa[i];
            }
        }
    }
    FacePoint { x: p, t, tt, shape }
}

pub fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

pub fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

pub fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// Area of a face (3×3 Gauss on quadrilaterals, 3 points on triangles).
pub fn face_area(x: &[[f64; 3]]) -> f64 {
    let mut area = 0.0;
    let mut add = |xi: [f64; 2], w: f64| {
        let p = face_point(x, xi);
        area += w * norm(cross(p.t[0], p.t[1]));
    };
    if x.len() == 8 {
        for (xi, w) in quad_rule(3) {
            add(xi, w);
        }
    } else {
        for &(xi, w) in &TRIANGLE_3 {
            add(xi, w);
        }
    }
    area
}

/// Lumped area weight of local node `a` of a face with `nodes` nodes.
pub fn area_weight(nodes: usize, a: usize) -> f64 {
    let (w, corners) = if nodes == 8 {
        (QUAD8_AREA_WEIGHTS, 4)
    } else {
        (TRI6_AREA_WEIGHTS, 3)
    };
    if a < corners {
        w[0]
    } else {
        w[1]
    }
}

/// Boundary faces of the mesh: faces of exactly one element (matched by
/// their sorted corner nodes).
pub fn skin_faces(mesh: &Mesh) -> Vec<Face> {
    use std::collections::HashMap;
    let mut count: HashMap<Vec<usize>, (usize, usize, usize)> = HashMap::new();
    for (e, el) in mesh.elements.iter().enumerate() {
        for f in 1..=el.kind.face_count() {
            let Some(local) = face_nodes(el.kind, f) else {
                continue;
            };
            let corners = if local.len() == 8 { 4 } else { 3 };
            let mut key: Vec<usize> = local[..corners].iter().map(|&p| el.nodes[p]).collect();
            key.sort_unstable();
            count.entry(key).or_insert((0, e, f)).0 += 1;
        }
    }
    let mut faces: Vec<(usize, usize)> = count
        .values()
        .filter(|c| c.0 == 1)
        .map(|c| (c.1, c.2))
        .collect();
    faces.sort_unstable();
    faces
        .into_iter()
        .filter_map(|(e, f)| Face::of_element(mesh, e, f))
        .collect()
}

/// Element faces (element index, CalculiX face 1..) whose nodes all lie in
/// `nodes`: the element-face surface of a node set (e.g. a gear flank),
/// as ccx builds one from a node set. Sorted by element and face.
pub fn faces_on_nodes(mesh: &Mesh, nodes: &[usize]) -> Vec<(usize, usize)> {
    let mut member = vec![false; mesh.node_count()];
    for &n in nodes {
        if n < member.len() {
            member[n] = true;
        }
    }
    let mut out = Vec::new();
    for (e, el) in mesh.elements.iter().enumerate() {
        if !el.nodes.iter().any(|&n| member[n]) {
            continue;
        }
        for f in 1..=el.kind.face_count() {
            if let Some(local) = face_nodes(el.kind, f) {
                if local.iter().all(|&p| member[el.nodes[p]]) {
                    out.push((e, f));
                }
            }
        }
    }
    out
}

/// The faces of a surface. For a node surface: the skin faces whose nodes
/// all belong to the surface (used for tributary areas and slave normals;
/// possibly none).
pub fn surface_faces(mesh: &Mesh, surface: &Surface, skin: &mut Option<Vec<Face>>) -> Vec<Face> {
    match &surface.kind {
        SurfaceKind::Element(list) => list
            .iter()
            .filter_map(|&(e, f)| Face::of_element(mesh, e, f))
            .collect(),
        SurfaceKind::Node(nodes) => {
            let mut member = vec![false; mesh.node_count()];
            for &n in nodes {
                if n < member.len() {
                    member[n] = true;
                }
            }
            let skin = skin.get_or_insert_with(|| skin_faces(mesh));
            skin.iter()
                .filter(|f| f.nodes.iter().all(|&n| member[n]))
                .cloned()
                .collect()
        }
    }
}

/// Nodes of a surface (sorted, unique): the nodes of its faces, or its node list.
pub fn surface_nodes(surface: &Surface, faces: &[Face]) -> Vec<usize> {
    let mut v: Vec<usize> = match &surface.kind {
        SurfaceKind::Element(_) => faces.iter().flat_map(|f| f.nodes.clone()).collect(),
        SurfaceKind::Node(nodes) => nodes.clone(),
    };
    v.sort_unstable();
    v.dedup();
    v
}

/// Tributary area and area-weighted outward normal (of the slave body) of
/// each node of `faces`, indexed by node. Nodes on no face get area 0.
pub fn nodal_areas(coords: &[[f64; 3]], faces: &[Face], nn: usize) -> (Vec<f64>, Vec<[f64; 3]>) {
    let mut area = vec![0.0; nn];
    let mut normal = vec![[0.0; 3]; nn];
    for f in faces {
        let x = f.coords(coords);
        let a = face_area(&x);
        for (k, &n) in f.nodes.iter().enumerate() {
            let w = area_weight(f.nodes.len(), k) * a;
            area[n] += w;
            // outward normal at the node's reference position
            let xi = node_reference(f.nodes.len(), k);
            let p = face_point(&x, xi);
            let nv = cross(p.t[0], p.t[1]);
            let l = norm(nv);
            if l > 0.0 {
                for i in 0..3 {
                    normal[n][i] += w * nv[i] / l;
                }
            }
        }
    }
    (area, normal)
}

/// Reference coordinates of local node `a` of a face with `nodes` nodes.
pub fn node_reference(nodes: usize, a: usize) -> [f64; 2] {
    if nodes == 8 {
        QUAD8_POINTS[a]
    } else {
        [
            [0.0, 0.0],
            [1.0, 0.0],
            [0.0, 1.0],
            [0.5, 0.0],
            [0.5, 0.5],
            [0.0, 0.5],
        ][a]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fem::element::{quad8_shape, tri6_shape};

    /// Second derivatives against central differences of the first ones;
    /// values and first derivatives against the element module.
    #[test]
    fn shape_derivatives() {
        let h = 1e-6;
        for (nodes, xi) in [(8usize, [0.3, -0.7]), (6, [0.2, 0.35])] {
            let s = face_shape(nodes, xi);
            let (n0, d0): (Vec<f64>, Vec<[f64; 2]>) = if nodes == 8 {
                let (n, d) = quad8_shape(xi);
                (n.to_vec(), d.to_vec())
            } else {
                let (n, d) = tri6_shape(xi);
                (n.to_vec(), d.to_vec())
            };
            let sx = |dx: f64, dy: f64| face_shape(nodes, [xi[0] + dx, xi[1] + dy]);
            let (px, mx, py, my) = (sx(h, 0.0), sx(-h, 0.0), sx(0.0, h), sx(0.0, -h));
            for a in 0..nodes {
                assert!((s.n[a] - n0[a]).abs() < 1e-14);
                assert!((s.d[a][0] - d0[a][0]).abs() < 1e-14);
                assert!((s.d[a][1] - d0[a][1]).abs() < 1e-14);
                let fxx = (px.d[a][0] - mx.d[a][0]) / (2.0 * h);
                let fyy = (py.d[a][1] - my.d[a][1]) / (2.0 * h);
                let fxy = (py.d[a][0] - my.d[a][0]) / (2.0 * h);
                assert!((s.dd[a][0] - fxx).abs() < 1e-7, "{nodes} {a} xx");
                assert!((s.dd[a][1] - fyy).abs() < 1e-7, "{nodes} {a} yy");
                assert!((s.dd[a][2] - fxy).abs() < 1e-7, "{nodes} {a} xy");
            }
        }
    }

    #[test]
    fn weights_sum_to_one() {
        let q: f64 = (0..8).map(|a| area_weight(8, a)).sum();
        let t: f64 = (0..6).map(|a| area_weight(6, a)).sum();
        assert!((q - 1.0).abs() < 1e-15 && (t - 1.0).abs() < 1e-15);
    }
}
