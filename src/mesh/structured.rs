//! Structured quadratic meshes for verification (boxes, cylinders, plates).
//!
//! Every generator works on the *quadratic lattice* of a block of
//! `nx × ny × nz` cells: `2n+1` lattice points per direction, lattice index
//! `2c` at cell boundaries and `2c+1` at cell mid-planes. Each lattice point
//! that some element uses becomes exactly one node, so midside nodes are
//! shared between neighbouring elements by construction. The lattice is then
//! placed in space by a coordinate function (identity scaling for a box,
//! polar map for a cylinder, elliptic blend for NAFEMS LE10); curved edges
//! are therefore exact at the midside nodes.
//!
//! Node labels are `1..=n` in lattice order (x fastest, then y, then z) and
//! element labels `1..=m` in cell order (same ordering). All elements are
//! positively oriented when the coordinate map has a positive Jacobian.

use std::collections::HashMap;
use std::f64::consts::FRAC_PI_2;

use super::{ElementKind, Mesh};
use crate::fem::element::{edges, face_nodes};

/// Element type of a structured mesh.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BoxElement {
    /// C3D20, one per cell.
    Hex20,
    /// C3D20R, one per cell.
    Hex20R,
    /// C3D15, two per cell: the xy-cell (lattice axes 0 and 1) is split along
    /// its diagonal from (x0, y0) to (x1, y1) and extruded along axis 2.
    Wedge15,
}

impl BoxElement {
    /// The CalculiX element kind generated.
    pub fn kind(self) -> ElementKind {
        match self {
            BoxElement::Hex20 => ElementKind::C3D20,
            BoxElement::Hex20R => ElementKind::C3D20R,
            BoxElement::Wedge15 => ElementKind::C3D15,
        }
    }
}

/// C3D20 nodes as lattice offsets within a cell (0, 1, 2 per axis), CalculiX order.
const HEX20_LATTICE: [[usize; 3]; 20] = [
    [0, 0, 0],
    [2, 0, 0],
    [2, 2, 0],
    [0, 2, 0],
    [0, 0, 2],
    [2, 0, 2],
    [2, 2, 2],
    [0, 2, 2],
    [1, 0, 0],
    [2, 1, 0],
    [1, 2, 0],
    [0, 1, 0],
    [1, 0, 2],
    [2, 1, 2],
    [1, 2, 2],
    [0, 1, 2],
    [0, 0, 1],
    [2, 0, 1],
    [2, 2, 1],
    [0, 2, 1],
];

/// The two triangles of an xy-cell (lattice offsets), both counter-clockwise
/// seen from +axis 2, so that the wedges extruded along axis 2 are positive.
const CELL_TRIANGLES: [[[usize; 2]; 3]; 2] = [[[0, 0], [2, 0], [2, 2]], [[0, 0], [2, 2], [0, 2]]];

/// Number of corner nodes (8 or 6); the remaining nodes are midside nodes.
fn corner_count(kind: ElementKind) -> usize {
    match kind {
        ElementKind::C3D20 | ElementKind::C3D20R => 8,
        ElementKind::C3D15 => 6,
    }
}

/// Wedge nodes (lattice offsets) over triangle `t` of an xy-cell, CalculiX order.
fn wedge_lattice(t: [[usize; 2]; 3]) -> [[usize; 3]; 15] {
    let mid = |a: [usize; 2], b: [usize; 2]| [(a[0] + b[0]) / 2, (a[1] + b[1]) / 2];
    let at = |p: [usize; 2], z: usize| [p[0], p[1], z];
    let m = [mid(t[0], t[1]), mid(t[1], t[2]), mid(t[2], t[0])];
    [
        at(t[0], 0),
        at(t[1], 0),
        at(t[2], 0),
        at(t[0], 2),
        at(t[1], 2),
        at(t[2], 2),
        at(m[0], 0),
        at(m[1], 0),
        at(m[2], 0),
        at(m[0], 2),
        at(m[1], 2),
        at(m[2], 2),
        at(t[0], 1),
        at(t[1], 1),
        at(t[2], 1),
    ]
}

/// Whether lattice point `l` is a node of the given element type.
///
/// Hex20 (serendipity): at most one odd index (corner or edge midpoint).
/// Wedge15: on even z-levels every point is a node (corners, edge midpoints
/// and the cell-diagonal midpoints, which have two odd indices); on odd
/// z-levels only the vertical-edge midpoints (x and y even).
fn is_lattice_node(kind: BoxElement, l: [usize; 3]) -> bool {
    let odd = l.iter().filter(|&&i| i % 2 == 1).count();
    match kind {
        BoxElement::Hex20 | BoxElement::Hex20R => odd <= 1,
        BoxElement::Wedge15 => l[2].is_multiple_of(2) || odd == 1,
    }
}

/// `i`-th of `n+1` equidistant points on `[a, b]`, with both ends exact.
fn lerp(a: f64, b: f64, i: usize, n: usize) -> f64 {
    if i == 0 {
        a
    } else if i == n {
        b
    } else {
        a + (b - a) * (i as f64 / n as f64)
    }
}

/// Builds the mesh of the quadratic lattice of `cells`, placing lattice point
/// `l` at `coord(l)`. `faces` names the node sets of the six lattice faces in
/// the order (axis0 min, axis0 max, axis1 min, axis1 max, axis2 min, axis2 max).
/// Also creates the sets NALL and EALL.
fn lattice_mesh(
    cells: [usize; 3],
    kind: BoxElement,
    faces: [&str; 6],
    coord: impl Fn([usize; 3]) -> [f64; 3],
) -> Mesh {
    assert!(
        cells.iter().all(|&c| c >= 1),
        "structured mesh needs at least one cell per direction, got {cells:?}"
    );
    let n2 = cells.map(|c| 2 * c);
    let dim = n2.map(|n| n + 1);
    let flat = |l: [usize; 3]| l[0] + dim[0] * (l[1] + dim[1] * l[2]);
    let mut index = vec![usize::MAX; dim[0] * dim[1] * dim[2]];
    let mut mesh = Mesh::new();
    let mut face_sets: [Vec<usize>; 6] = Default::default();
    for k in 0..dim[2] {
        for j in 0..dim[1] {
            for i in 0..dim[0] {
                let l = [i, j, k];
                if !is_lattice_node(kind, l) {
                    continue;
                }
                let label = mesh.node_count() as u64 + 1;
                let n = mesh
                    .add_node(label, coord(l))
                    .expect("fresh node labels are unique");
                index[flat(l)] = n;
                for axis in 0..3 {
                    if l[axis] == 0 {
                        face_sets[2 * axis].push(n);
                    }
                    if l[axis] == n2[axis] {
                        face_sets[2 * axis + 1].push(n);
                    }
                }
            }
        }
    }
    let node_at = |base: [usize; 3], o: [usize; 3]| {
        let n = index[flat([base[0] + o[0], base[1] + o[1], base[2] + o[2]])];
        debug_assert_ne!(n, usize::MAX, "lattice point {base:?}+{o:?} is not a node");
        n
    };
    let ekind = kind.kind();
    for ck in 0..cells[2] {
        for cj in 0..cells[1] {
            for ci in 0..cells[0] {
                let base = [2 * ci, 2 * cj, 2 * ck];
                let mut add = |nodes: Vec<usize>| {
                    let label = mesh.elements.len() as u64 + 1;
                    mesh.add_element(label, ekind, nodes)
                        .expect("fresh element labels are unique");
                };
                match kind {
                    BoxElement::Hex20 | BoxElement::Hex20R => {
                        add(HEX20_LATTICE.iter().map(|&o| node_at(base, o)).collect());
                    }
                    BoxElement::Wedge15 => {
                        for t in CELL_TRIANGLES {
                            add(wedge_lattice(t).iter().map(|&o| node_at(base, o)).collect());
                        }
                    }
                }
            }
        }
    }
    for (name, set) in faces.iter().zip(face_sets) {
        mesh.extend_node_set(name, set);
    }
    let n = mesh.node_count();
    let m = mesh.elements.len();
    mesh.extend_node_set("NALL", 0..n);
    mesh.extend_element_set("EALL", 0..m);
    mesh
}

/// Box `[0, size[0]] × [0, size[1]] × [0, size[2]]` with `cells` cells per
/// direction. Node sets X0, X1, Y0, Y1, Z0, Z1 (all nodes on each face),
/// NALL; element set EALL.
///
/// # Panics
/// If a cell count is zero.
pub fn box_mesh(size: [f64; 3], cells: [usize; 3], kind: BoxElement) -> Mesh {
    let n2 = cells.map(|c| 2 * c);
    lattice_mesh(cells, kind, ["X0", "X1", "Y0", "Y1", "Z0", "Z1"], |l| {
        [
            lerp(0.0, size[0], l[0], n2[0]),
            lerp(0.0, size[1], l[1], n2[1]),
            lerp(0.0, size[2], l[2], n2[2]),
        ]
    })
}

/// Applies a smooth map to every node (graded or curved meshes). Midside
/// nodes are mapped too, so curved edges follow the map exactly there.
pub fn map_nodes(mesh: &mut Mesh, f: impl Fn([f64; 3]) -> [f64; 3]) {
    for x in &mut mesh.coords {
        *x = f(*x);
    }
}

/// Marks the nodes on the mesh boundary: the nodes of element faces that no
/// other element shares (faces are matched by their sorted corner nodes).
fn boundary_nodes(mesh: &Mesh) -> Vec<bool> {
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

fn dist(p: [f64; 3], q: [f64; 3]) -> f64 {
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

/// Element faces (element index, CalculiX face number 1-based) whose nodes
/// all belong to node set `set` (name case-insensitive): the faces to load
/// with `*DLOAD … Pn`. Empty if the set does not exist.
pub fn box_faces(mesh: &Mesh, set: &str) -> Vec<(usize, usize)> {
    let Some(nodes) = mesh.node_sets.get(&set.to_ascii_uppercase()) else {
        return Vec::new();
    };
    let mut member = vec![false; mesh.node_count()];
    for &n in nodes {
        member[n] = true;
    }
    let mut faces = Vec::new();
    for (e, el) in mesh.elements.iter().enumerate() {
        for f in 1..=el.kind.face_count() {
            if face_nodes(el.kind, f)
                .expect("face number within the element's faces")
                .iter()
                .all(|&p| member[el.nodes[p]])
            {
                faces.push((e, f));
            }
        }
    }
    faces
}

/// `(cos θ, sin θ)` for lattice angle `j` of `n` steps over `[0, π/2]`, exact
/// at both ends (so nodes at θ = 0 have y = 0 and at θ = π/2 have x = 0).
fn quarter_cos_sin(j: usize, n: usize) -> (f64, f64) {
    if j == 0 {
        (1.0, 0.0)
    } else if j == n {
        (0.0, 1.0)
    } else {
        let t = FRAC_PI_2 * (j as f64 / n as f64);
        (t.cos(), t.sin())
    }
}

/// Quarter of a hollow cylinder about the z axis: `r ∈ [r_inner, r_outer]`,
/// `θ ∈ [0, π/2]`, `z ∈ [0, length]`; `cells` = (radial, circumferential,
/// axial). Every node, midside nodes included, lies exactly on its cylinder
/// (the lattice (r, θ, z) is mapped by (r cos θ, r sin θ, z)). Node sets
/// INNER, OUTER, THETA0 (plane y = 0), THETA90 (plane x = 0), Z0, Z1, NALL;
/// element set EALL.
///
/// # Panics
/// If `0 < r_inner < r_outer` and `length > 0` do not hold, or a cell count is zero.
pub fn thick_cylinder_quarter(
    r_inner: f64,
    r_outer: f64,
    length: f64,
    cells: [usize; 3],
    kind: BoxElement,
) -> Mesh {
    assert!(
        0.0 < r_inner && r_inner < r_outer && length > 0.0,
        "thick cylinder needs 0 < r_inner < r_outer and length > 0"
    );
    let n2 = cells.map(|c| 2 * c);
    let faces = ["INNER", "OUTER", "THETA0", "THETA90", "Z0", "Z1"];
    lattice_mesh(cells, kind, faces, |l| {
        let r = lerp(r_inner, r_outer, l[0], n2[0]);
        let (c, s) = quarter_cos_sin(l[1], n2[1]);
        [r * c, r * s, lerp(0.0, length, l[2], n2[2])]
    })
}

/// NAFEMS LE10 thick elliptic plate, quarter model (mm). Between the inner
/// ellipse (semi-axes 2000 along x, 1000 along y) and the outer ellipse
/// (3250, 2750), `z ∈ [-300, 300]`. Lattice point (s, t, z) with `s ∈ [0, 1]`
/// radial and `t ∈ [0, π/2]` maps to
/// `(1−s)·(2000 cos t, 1000 sin t) + s·(3250 cos t, 2750 sin t)`.
/// `cells` = (radial, circumferential, through-thickness).
///
/// Node sets: INNER, OUTER, X0 (face x = 0), Y0 (face y = 0), TOP (z = 300),
/// BOTTOM (z = −300), MIDPLANE_OUTER (outer-face nodes at z = 0), D (the node
/// at exactly (2000, 0, 300)), NALL; element set EALL.
///
/// # Panics
/// If a cell count is zero.
pub fn le10_plate(
    cells_radial: usize,
    cells_circ: usize,
    cells_thick: usize,
    kind: BoxElement,
) -> Mesh {
    let cells = [cells_radial, cells_circ, cells_thick];
    let n2 = cells.map(|c| 2 * c);
    let faces = ["INNER", "OUTER", "Y0", "X0", "BOTTOM", "TOP"];
    let mut mesh = lattice_mesh(cells, kind, faces, |l| {
        let s = lerp(0.0, 1.0, l[0], n2[0]);
        let (c, sn) = quarter_cos_sin(l[1], n2[1]);
        let z = if 2 * l[2] == n2[2] {
            0.0
        } else {
            lerp(-300.0, 300.0, l[2], n2[2])
        };
        [
            (1.0 - s) * 2000.0 * c + s * 3250.0 * c,
            (1.0 - s) * 1000.0 * sn + s * 2750.0 * sn,
            z,
        ]
    });
    let mid: Vec<usize> = mesh.node_sets["OUTER"]
        .iter()
        .copied()
        .filter(|&n| mesh.coords[n][2] == 0.0)
        .collect();
    mesh.extend_node_set("MIDPLANE_OUTER", mid);
    let d = mesh.node_sets["INNER"]
        .iter()
        .copied()
        .find(|&n| mesh.coords[n] == [2000.0, 0.0, 300.0])
        .expect("lattice point (0, 0, top) is a corner node at D");
    mesh.extend_node_set("D", [d]);
    mesh
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
        [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
    }

    fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    }

    fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
        a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
    }

    fn tet_volume(p: [f64; 3], q: [f64; 3], r: [f64; 3], s: [f64; 3]) -> f64 {
        dot(cross(sub(q, p), sub(r, p)), sub(s, p)) / 6.0
    }

    /// Signed volumes of a tetrahedral split of the element's corner polyhedron.
    fn corner_tets(mesh: &Mesh, e: usize) -> Vec<f64> {
        let x = mesh.element_coords(e);
        let tets: &[[usize; 4]] = match mesh.elements[e].kind {
            ElementKind::C3D20 | ElementKind::C3D20R => &[
                [0, 1, 2, 6],
                [0, 2, 3, 6],
                [0, 3, 7, 6],
                [0, 7, 4, 6],
                [0, 4, 5, 6],
                [0, 5, 1, 6],
            ],
            ElementKind::C3D15 => &[[0, 1, 2, 3], [1, 2, 3, 4], [2, 3, 4, 5]],
        };
        tets.iter()
            .map(|t| tet_volume(x[t[0]], x[t[1]], x[t[2]], x[t[3]]))
            .collect()
    }

    /// Asserts every corner tetrahedron of every element is positive; returns
    /// the total corner-polyhedron volume.
    fn assert_positive(mesh: &Mesh) -> f64 {
        let mut total = 0.0;
        for e in 0..mesh.elements.len() {
            for v in corner_tets(mesh, e) {
                assert!(
                    v > 0.0,
                    "element {} has tet volume {v}",
                    mesh.elements[e].label
                );
                total += v;
            }
        }
        total
    }

    fn hex_node_count(n: [usize; 3]) -> usize {
        let [nx, ny, nz] = n;
        (nx + 1) * (ny + 1) * (nz + 1)
            + nx * (ny + 1) * (nz + 1)
            + (nx + 1) * ny * (nz + 1)
            + (nx + 1) * (ny + 1) * nz
    }

    fn assert_no_duplicate_coords(mesh: &Mesh) {
        let mut seen = HashMap::new();
        for (i, x) in mesh.coords.iter().enumerate() {
            let key = x.map(|v| (v * 1e6).round() as i64);
            if let Some(j) = seen.insert(key, i) {
                panic!("nodes {j} and {i} coincide at {x:?}");
            }
        }
    }

    fn assert_midsides_at_midpoints(mesh: &Mesh) {
        for el in &mesh.elements {
            for &[a, b, m] in edges(el.kind) {
                let (p, q, r) = (
                    mesh.coords[el.nodes[a]],
                    mesh.coords[el.nodes[b]],
                    mesh.coords[el.nodes[m]],
                );
                for k in 0..3 {
                    assert!((0.5 * (p[k] + q[k]) - r[k]).abs() < 1e-9 * (1.0 + r[k].abs()));
                }
            }
        }
    }

    #[test]
    fn hex20_box_counts_sharing_and_sets() {
        for n in [[1, 1, 1], [2, 3, 4], [3, 1, 2]] {
            let mesh = box_mesh([3.0, 2.0, 1.5], n, BoxElement::Hex20);
            assert_eq!(mesh.node_count(), hex_node_count(n));
            assert_eq!(mesh.elements.len(), n[0] * n[1] * n[2]);
            assert!(mesh.used_nodes().iter().all(|&u| u));
            assert_no_duplicate_coords(&mesh);
            assert_midsides_at_midpoints(&mesh);
            let [nx, ny, nz] = n;
            // A face of the lattice: (2a+1)(2b+1) points minus a·b cell centres.
            let face = |a: usize, b: usize| (2 * a + 1) * (2 * b + 1) - a * b;
            for (set, size) in [
                ("X0", face(ny, nz)),
                ("X1", face(ny, nz)),
                ("Y0", face(nx, nz)),
                ("Y1", face(nx, nz)),
                ("Z0", face(nx, ny)),
                ("Z1", face(nx, ny)),
            ] {
                assert_eq!(mesh.node_sets[set].len(), size, "set {set} for {n:?}");
            }
            assert_eq!(mesh.node_sets["NALL"].len(), mesh.node_count());
            assert_eq!(mesh.element_sets["EALL"].len(), mesh.elements.len());
            for &i in &mesh.node_sets["X1"] {
                assert_eq!(mesh.coords[i][0], 3.0);
            }
            for &i in &mesh.node_sets["Z1"] {
                assert_eq!(mesh.coords[i][2], 1.5);
            }
            let vol = assert_positive(&mesh);
            assert!((vol - 9.0).abs() < 1e-12);
            // Labels 1..n and 1..m, findable.
            assert_eq!(mesh.node(1), Some(0));
            assert_eq!(
                mesh.node(mesh.node_count() as u64),
                Some(mesh.node_count() - 1)
            );
            assert_eq!(
                mesh.element(mesh.elements.len() as u64),
                Some(mesh.elements.len() - 1)
            );
        }
        let r = box_mesh([1.0; 3], [1, 1, 1], BoxElement::Hex20R);
        assert_eq!(r.elements[0].kind, ElementKind::C3D20R);
    }

    #[test]
    fn hex20_box_faces_by_set() {
        let (nx, ny, nz) = (3, 2, 4);
        let mesh = box_mesh([1.0, 1.0, 1.0], [nx, ny, nz], BoxElement::Hex20);
        for (set, face, count) in [
            ("Z0", 1, nx * ny),
            ("Z1", 2, nx * ny),
            ("Y0", 3, nx * nz),
            ("X1", 4, ny * nz),
            ("Y1", 5, nx * nz),
            ("X0", 6, ny * nz),
        ] {
            let faces = box_faces(&mesh, set);
            assert_eq!(faces.len(), count, "{set}");
            assert!(faces.iter().all(|&(_, f)| f == face), "{set}");
        }
        assert_eq!(box_faces(&mesh, "z1"), box_faces(&mesh, "Z1"));
        assert!(box_faces(&mesh, "NOPE").is_empty());
        assert_eq!(box_faces(&mesh, "NALL").len(), 6 * nx * ny * nz);
    }

    #[test]
    fn benchmark_box_100x10x10() {
        let t = std::time::Instant::now();
        let mesh = box_mesh([100.0, 10.0, 10.0], [100, 10, 10], BoxElement::Hex20);
        let elapsed = t.elapsed().as_secs_f64();
        assert_eq!(mesh.node_count(), 46_541);
        assert_eq!(mesh.elements.len(), 10_000);
        assert_eq!(box_faces(&mesh, "Z1").len(), 1000);
        assert!(elapsed < 1.0, "100×10×10 took {elapsed} s");
    }

    #[test]
    fn wedge_box_counts_sharing_and_sets() {
        for n in [[1, 1, 1], [2, 3, 2]] {
            let [nx, ny, nz] = n;
            let mesh = box_mesh([2.0, 3.0, 1.0], n, BoxElement::Wedge15);
            assert_eq!(mesh.node_count(), hex_node_count(n) + nx * ny * (nz + 1));
            assert_eq!(mesh.elements.len(), 2 * nx * ny * nz);
            assert!(mesh.elements.iter().all(|e| e.kind == ElementKind::C3D15));
            assert!(mesh.used_nodes().iter().all(|&u| u));
            assert_no_duplicate_coords(&mesh);
            assert_midsides_at_midpoints(&mesh);
            assert_eq!(mesh.node_sets["Z1"].len(), (2 * nx + 1) * (2 * ny + 1));
            let side = |a: usize, b: usize| (2 * a + 1) * (2 * b + 1) - a * b;
            assert_eq!(mesh.node_sets["X0"].len(), side(ny, nz));
            assert_eq!(mesh.node_sets["Y1"].len(), side(nx, nz));
            let vol = assert_positive(&mesh);
            assert!((vol - 6.0).abs() < 1e-12);
            for (set, face, count) in [
                ("Z0", 1, 2 * nx * ny),
                ("Z1", 2, 2 * nx * ny),
                ("Y0", 3, nx * nz),
                ("X1", 4, ny * nz),
                ("Y1", 4, nx * nz),
                ("X0", 5, ny * nz),
            ] {
                let faces = box_faces(&mesh, set);
                assert_eq!(faces.len(), count, "{set}");
                assert!(faces.iter().all(|&(_, f)| f == face), "{set}");
            }
        }
    }

    /// Corner order of every face table gives an outward normal, and the face
    /// midsides are the midpoints of consecutive face corners.
    #[test]
    fn face_tables_are_outward_and_consistent() {
        for kind in [BoxElement::Hex20, BoxElement::Wedge15] {
            let mesh = box_mesh([1.0, 1.0, 1.0], [1, 1, 1], kind);
            for (e, el) in mesh.elements.iter().enumerate() {
                let x = mesh.element_coords(e);
                let nc = corner_count(el.kind);
                let centre = x[..nc]
                    .iter()
                    .fold([0.0; 3], |a, p| [a[0] + p[0], a[1] + p[1], a[2] + p[2]])
                    .map(|v| v / nc as f64);
                for f in 1..=el.kind.face_count() {
                    let local =
                        face_nodes(el.kind, f).expect("face number within the element's faces");
                    let c = local.len() / 2;
                    let normal = cross(
                        sub(x[local[1]], x[local[0]]),
                        sub(x[local[c - 1]], x[local[0]]),
                    );
                    assert!(
                        dot(normal, sub(x[local[0]], centre)) > 0.0,
                        "{kind:?} face {f}"
                    );
                    for i in 0..c {
                        let (p, q) = (x[local[i]], x[local[(i + 1) % c]]);
                        let m = x[local[c + i]];
                        for k in 0..3 {
                            assert!(
                                (0.5 * (p[k] + q[k]) - m[k]).abs() < 1e-12,
                                "{kind:?} face {f}"
                            );
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn map_nodes_grades_the_mesh() {
        let mut mesh = box_mesh([1.0, 1.0, 1.0], [4, 1, 1], BoxElement::Hex20);
        map_nodes(&mut mesh, |[x, y, z]| [x * x * 10.0, y, z]);
        let xs: Vec<f64> = mesh.node_sets["Y0"]
            .iter()
            .filter(|&&n| mesh.coords[n][2] == 0.0)
            .map(|&n| mesh.coords[n][0])
            .collect();
        assert_eq!(xs.len(), 9);
        assert_eq!(xs[8], 10.0);
        assert!((xs[1] - 10.0 / 64.0).abs() < 1e-12);
        assert_positive(&mesh);
    }

    #[test]
    fn distortion_keeps_boundary_and_orientation() {
        for kind in [BoxElement::Hex20, BoxElement::Wedge15] {
            for straight in [true, false] {
                let base = box_mesh([4.0, 2.0, 2.0], [4, 2, 2], kind);
                let mut mesh = base.clone();
                distort_interior(&mut mesh, 0.2, 7, straight);
                let mut boundary = vec![false; base.node_count()];
                for set in ["X0", "X1", "Y0", "Y1", "Z0", "Z1"] {
                    for &n in &base.node_sets[set] {
                        boundary[n] = true;
                    }
                }
                let mut moved = 0;
                for n in 0..base.node_count() {
                    let d = dist(base.coords[n], mesh.coords[n]);
                    if boundary[n] {
                        assert_eq!(d, 0.0);
                    } else if d > 0.0 {
                        moved += 1;
                        assert!(d <= 0.2 * 1.0 + 1e-12);
                    }
                }
                assert!(moved > 0);
                // Warped faces: corner-tet volumes need not add up to the box.
                assert_positive(&mesh);
                if straight {
                    assert_midsides_at_midpoints(&mesh);
                }
                let mut again = base.clone();
                distort_interior(&mut again, 0.2, 7, straight);
                assert_eq!(again.coords, mesh.coords);
                let mut other = base.clone();
                distort_interior(&mut other, 0.2, 8, straight);
                assert_ne!(other.coords, mesh.coords);
            }
        }
    }

    #[test]
    fn thick_cylinder_nodes_on_cylinders() {
        let (ri, ro, len) = (10.0, 20.0, 5.0);
        for kind in [BoxElement::Hex20, BoxElement::Wedge15] {
            let cells = [2, 4, 1];
            let mesh = thick_cylinder_quarter(ri, ro, len, cells, kind);
            let r = |n: usize| mesh.coords[n][0].hypot(mesh.coords[n][1]);
            for &n in &mesh.node_sets["INNER"] {
                assert!((r(n) - ri).abs() < 1e-12 * ri);
            }
            for &n in &mesh.node_sets["OUTER"] {
                assert!((r(n) - ro).abs() < 1e-12 * ro);
            }
            for &n in &mesh.node_sets["THETA0"] {
                assert_eq!(mesh.coords[n][1], 0.0);
            }
            for &n in &mesh.node_sets["THETA90"] {
                assert_eq!(mesh.coords[n][0], 0.0);
            }
            for &n in &mesh.node_sets["Z1"] {
                assert_eq!(mesh.coords[n][2], len);
            }
            // Every node (midsides included) sits on one of the lattice radii.
            for n in 0..mesh.node_count() {
                let k = (r(n) - ri) / (ro - ri) * 4.0;
                assert!(
                    (k - k.round()).abs() < 1e-9,
                    "node {n} off the radial lattice"
                );
            }
            assert_no_duplicate_coords(&mesh);
            let vol = assert_positive(&mesh);
            let exact = std::f64::consts::FRAC_PI_4 * (ro * ro - ri * ri) * len;
            assert!(vol < exact && vol > 0.95 * exact, "{vol} vs {exact}");
            // One face per (θ, z) cell on the inner surface, for hexes and wedges alike.
            assert_eq!(box_faces(&mesh, "INNER").len(), cells[1] * cells[2]);
        }
    }

    #[test]
    fn le10_plate_geometry_and_sets() {
        for (kind, thick) in [
            (BoxElement::Hex20, 2),
            (BoxElement::Wedge15, 3),
            (BoxElement::Hex20R, 1),
        ] {
            let mesh = le10_plate(3, 4, thick, kind);
            let d = mesh.node_sets["D"].clone();
            assert_eq!(d.len(), 1);
            assert_eq!(mesh.coords[d[0]], [2000.0, 0.0, 300.0]);
            for &n in &mesh.node_sets["INNER"] {
                let [x, y, _] = mesh.coords[n];
                assert!(((x / 2000.0).powi(2) + (y / 1000.0).powi(2) - 1.0).abs() < 1e-12);
            }
            for &n in &mesh.node_sets["OUTER"] {
                let [x, y, _] = mesh.coords[n];
                assert!(((x / 3250.0).powi(2) + (y / 2750.0).powi(2) - 1.0).abs() < 1e-12);
            }
            for &n in &mesh.node_sets["X0"] {
                assert_eq!(mesh.coords[n][0], 0.0);
            }
            for &n in &mesh.node_sets["Y0"] {
                assert_eq!(mesh.coords[n][1], 0.0);
            }
            for &n in &mesh.node_sets["TOP"] {
                assert_eq!(mesh.coords[n][2], 300.0);
            }
            for &n in &mesh.node_sets["BOTTOM"] {
                assert_eq!(mesh.coords[n][2], -300.0);
            }
            let mid = &mesh.node_sets["MIDPLANE_OUTER"];
            // 2·cells_circ + 1 outer nodes at z = 0 when the mid-plane is a
            // corner level, else only the corner columns' vertical midsides.
            let expected = if thick % 2 == 0 { 9 } else { 5 };
            assert_eq!(mid.len(), expected, "{kind:?} thick {thick}");
            assert!(mid.iter().all(|&n| mesh.coords[n][2] == 0.0));
            if thick % 2 == 0 {
                assert!(mesh.coords.contains(&[2000.0, 0.0, 0.0]));
            }
            assert_positive(&mesh);
            assert_eq!(box_faces(&mesh, "TOP").len(), mesh.elements.len() / thick);
        }
    }
}

/// The benchmark cantilever: a box 10·nx/ny × 10 × 10 mm (cubic elements when
/// ny = nz), material E = 210 GPa, ν = 0.3, clamped on x = 0, a total force
/// `tip_force` (N) in −y shared equally by the nodes of the face x = L.
pub fn cantilever_model(
    cells: [usize; 3],
    kind: BoxElement,
    tip_force: f64,
) -> Result<crate::fem::model::Model, crate::FlankError> {
    use crate::fem::model::{Dirichlet, Model, NodalForce};
    let length = 10.0 * cells[0] as f64 / cells[1].max(1) as f64;
    let mesh = box_mesh([length, 10.0, 10.0], cells, kind);
    let clamped = mesh.node_sets["X0"].clone();
    let tip = mesh.node_sets["X1"].clone();
    let ne = mesh.elements.len();
    let mut model = Model {
        mesh,
        materials: vec![crate::fem::material::Material::new("STEEL", 210e3, 0.3)?],
        element_material: vec![0; ne],
        ..Default::default()
    };
    for &n in &clamped {
        for component in 0..3 {
            model.dirichlet.push(Dirichlet {
                node: n,
                component,
                value: 0.0,
            });
        }
    }
    for &n in &tip {
        model.forces.push(NodalForce {
            node: n,
            component: 1,
            value: -tip_force / tip.len() as f64,
        });
    }
    Ok(model)
}

/// Merges nodes closer than `tolerance` to each other (Euclidean distance
/// `< tolerance`) into one node; returns how many nodes were removed.
///
/// Clusters are transitive (a–b and b–c close ⇒ a, b, c become one node). The
/// survivor of a cluster is its lowest node index, which keeps its label and
/// coordinates; the surviving nodes keep their labels and their relative order
/// (indices are compacted). Element connectivity and node sets are rewritten
/// to the survivors (sets stay sorted and unique); elements, their labels and
/// the element sets are unchanged. The mesh is rebuilt through [`Mesh::new`],
/// so label lookups ([`Mesh::node`]) stay right.
///
/// Candidate pairs come from a spatial hash with cells of size `tolerance`
/// (each node is compared with the nodes of its own and the 26 neighbouring
/// cells): O(n) for meshes whose node spacing exceeds the tolerance.
///
/// An element two of whose own nodes merge is left degenerate (repeated node);
/// [`crate::fem::element::check_jacobian`] rejects it. A non-positive or
/// non-finite `tolerance` merges nothing.
pub fn merge_coincident_nodes(mesh: &mut Mesh, tolerance: f64) -> usize {
    let n = mesh.node_count();
    if n == 0 || !(tolerance > 0.0 && tolerance.is_finite()) {
        return 0;
    }
    fn find(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    let inv = 1.0 / tolerance;
    // `as` saturates (and maps NaN to 0): far-out or non-finite coordinates
    // only share cells, never produce a wrong merge (the distance decides).
    let cell_of = |x: [f64; 3]| x.map(|v| (v * inv).floor() as i64);
    let tol2 = tolerance * tolerance;
    let mut grid: HashMap<[i64; 3], Vec<usize>> = HashMap::with_capacity(n);
    let mut parent: Vec<usize> = (0..n).collect();
    for i in 0..n {
        let x = mesh.coords[i];
        let c = cell_of(x);
        for dx in -1i64..=1 {
            for dy in -1i64..=1 {
                for dz in -1i64..=1 {
                    let key = [
                        c[0].saturating_add(dx),
                        c[1].saturating_add(dy),
                        c[2].saturating_add(dz),
                    ];
                    let Some(list) = grid.get(&key) else {
                        continue;
                    };
                    for &j in list {
                        let y = mesh.coords[j];
                        let d2 =
                            (x[0] - y[0]).powi(2) + (x[1] - y[1]).powi(2) + (x[2] - y[2]).powi(2);
                        if d2 < tol2 {
                            // union, the smaller index becoming the root
                            let (ri, rj) = (find(&mut parent, i), find(&mut parent, j));
                            if ri != rj {
                                parent[ri.max(rj)] = ri.min(rj);
                            }
                        }
                    }
                }
            }
        }
        grid.entry(c).or_default().push(i);
    }
    let rep: Vec<usize> = (0..n).map(|i| find(&mut parent, i)).collect();
    let survivors = rep.iter().enumerate().filter(|&(i, &r)| i == r).count();
    if survivors == n {
        return 0;
    }
    let mut new_index = vec![usize::MAX; n];
    let mut out = Mesh::new();
    for i in 0..n {
        if rep[i] == i {
            new_index[i] = out
                .add_node(mesh.node_labels[i], mesh.coords[i])
                .expect("node labels of a mesh are unique");
        }
    }
    let map = |i: usize| new_index[rep[i]];
    for el in &mesh.elements {
        out.add_element(
            el.label,
            el.kind,
            el.nodes.iter().map(|&i| map(i)).collect(),
        )
        .expect("element labels of a mesh are unique");
    }
    for (name, set) in &mesh.node_sets {
        out.extend_node_set(name, set.iter().map(|&i| map(i)));
    }
    for (name, set) in &mesh.element_sets {
        out.extend_element_set(name, set.iter().copied());
    }
    *mesh = out;
    n - survivors
}

/// `(cos θ, sin θ)` for lattice angle `j` of `n` steps over `[0, 2π]`, exact
/// at multiples of π/2 (so θ = 0 and θ = 2π give the same point bit for bit).
fn full_cos_sin(j: usize, n: usize) -> (f64, f64) {
    if (4 * j).is_multiple_of(n) {
        match (4 * j / n) % 4 {
            0 => (1.0, 0.0),
            1 => (0.0, 1.0),
            2 => (-1.0, 0.0),
            _ => (0.0, -1.0),
        }
    } else {
        let t = std::f64::consts::TAU * (j as f64 / n as f64);
        (t.cos(), t.sin())
    }
}

/// Full ring about the z axis: `r ∈ [r_inner, r_outer]`, `θ ∈ [0, 2π)`,
/// `z ∈ [0, thickness]`; `cells` = (radial, circumferential, axial). The
/// lattice (r, θ, z) is mapped by (r cos θ, r sin θ, z), so every node,
/// midside nodes included, lies exactly on its circle; the seam nodes at
/// θ = 2π are then merged into those at θ = 0
/// ([`merge_coincident_nodes`]), which closes the ring. Node and element
/// labels are those of the lattice (node labels are therefore not
/// contiguous: the seam labels at θ = 2π are gone).
///
/// Node sets: INNER (r = r_inner), OUTER (r = r_outer), Z0, Z1, THETA0 (the
/// seam, half-plane y = 0, x > 0), NALL; element set EALL.
///
/// # Panics
/// If `0 < r_inner < r_outer` and `thickness > 0` do not hold, a cell count is
/// zero, or there are fewer than 3 circumferential cells.
pub fn annulus(
    r_inner: f64,
    r_outer: f64,
    thickness: f64,
    cells: [usize; 3],
    kind: BoxElement,
) -> Mesh {
    assert!(
        0.0 < r_inner && r_inner < r_outer && thickness > 0.0,
        "annulus needs 0 < r_inner < r_outer and thickness > 0"
    );
    assert!(
        cells.iter().all(|&c| c >= 1) && cells[1] >= 3,
        "annulus needs at least one radial and axial cell and 3 circumferential cells, got {cells:?}"
    );
    let n2 = cells.map(|c| 2 * c);
    let faces = ["INNER", "OUTER", "THETA0", "THETA360", "Z0", "Z1"];
    let mut mesh = lattice_mesh(cells, kind, faces, |l| {
        let r = lerp(r_inner, r_outer, l[0], n2[0]);
        let (c, s) = full_cos_sin(l[1], n2[1]);
        [r * c, r * s, lerp(0.0, thickness, l[2], n2[2])]
    });
    // far below the closest lattice spacing (the seam nodes coincide exactly)
    let spacing = (r_inner * std::f64::consts::TAU / n2[1] as f64 * 0.5)
        .min((r_outer - r_inner) / n2[0] as f64)
        .min(thickness / n2[2] as f64);
    let seam = mesh.node_sets["THETA360"].len();
    let merged = merge_coincident_nodes(&mut mesh, 1e-6 * spacing);
    assert_eq!(
        merged, seam,
        "every seam node at θ = 2π merges with one at θ = 0"
    );
    mesh.node_sets.remove("THETA360");
    mesh
}

#[cfg(test)]
mod merge_tests {
    use super::*;
    use crate::fem::element::check_jacobian;

    /// Brute-force: no two nodes closer than `tol`.
    fn assert_no_close_nodes(mesh: &Mesh, tol: f64) {
        for i in 0..mesh.node_count() {
            for j in 0..i {
                let d = dist(mesh.coords[i], mesh.coords[j]);
                assert!(
                    d >= tol,
                    "nodes {} and {} are {d} apart",
                    mesh.node_labels[j],
                    mesh.node_labels[i]
                );
            }
        }
    }

    fn assert_positive_jacobians(mesh: &Mesh) {
        for (e, el) in mesh.elements.iter().enumerate() {
            if let Err(err) = check_jacobian(el.kind, &mesh.element_coords(e)) {
                panic!("element {} ({:?}): {err:?}", el.label, el.kind);
            }
        }
    }

    /// Face of the lattice with a·b cells: (2a+1)(2b+1) points minus a·b centres.
    fn face(a: usize, b: usize) -> usize {
        (2 * a + 1) * (2 * b + 1) - a * b
    }

    #[test]
    fn annulus_closes_the_ring() {
        let (ri, ro, t) = (10.0, 25.0, 5.0);
        for (kind, cells) in [
            (BoxElement::Hex20, [2, 16, 1]),
            (BoxElement::Hex20, [3, 5, 2]),
            (BoxElement::Hex20R, [1, 3, 1]),
            (BoxElement::Wedge15, [2, 8, 2]),
        ] {
            let mesh = annulus(ri, ro, t, cells, kind);
            let lattice = box_mesh([1.0; 3], cells, kind);
            let seam = face(cells[0], cells[2]);
            assert_eq!(
                mesh.node_count(),
                lattice.node_count() - seam,
                "{kind:?} {cells:?}"
            );
            assert_eq!(mesh.elements.len(), lattice.elements.len());
            assert_eq!(mesh.node_sets["THETA0"].len(), seam);
            assert!(!mesh.node_sets.contains_key("THETA360"));
            assert_eq!(mesh.node_sets["NALL"].len(), mesh.node_count());
            assert!(mesh.used_nodes().iter().all(|&u| u));
            assert_no_close_nodes(&mesh, 1e-6);
            assert_positive_jacobians(&mesh);
            let r = |n: usize| mesh.coords[n][0].hypot(mesh.coords[n][1]);
            for &n in &mesh.node_sets["INNER"] {
                assert!((r(n) - ri).abs() < 1e-12 * ri);
            }
            for &n in &mesh.node_sets["OUTER"] {
                assert!((r(n) - ro).abs() < 1e-12 * ro);
            }
            for &n in &mesh.node_sets["Z1"] {
                assert_eq!(mesh.coords[n][2], t);
            }
            for &n in &mesh.node_sets["THETA0"] {
                assert_eq!(mesh.coords[n][1], 0.0);
                assert!(mesh.coords[n][0] > 0.0);
            }
            // A closed ring has no boundary faces but INNER, OUTER, Z0, Z1.
            let per_set = |s: &str| box_faces(&mesh, s).len();
            let wedges = if kind == BoxElement::Wedge15 { 2 } else { 1 };
            assert_eq!(per_set("INNER"), cells[1] * cells[2]);
            assert_eq!(per_set("OUTER"), cells[1] * cells[2]);
            assert_eq!(per_set("Z0"), wedges * cells[0] * cells[1]);
            let boundary = boundary_nodes(&mesh);
            for n in 0..mesh.node_count() {
                let on_surface = ["INNER", "OUTER", "Z0", "Z1"]
                    .iter()
                    .any(|s| mesh.node_sets[*s].binary_search(&n).is_ok());
                assert_eq!(
                    boundary[n], on_surface,
                    "node {} at {:?}",
                    mesh.node_labels[n], mesh.coords[n]
                );
            }
            // labels still find their nodes
            for (i, &l) in mesh.node_labels.iter().enumerate() {
                assert_eq!(mesh.node(l), Some(i));
            }
        }
    }

    #[test]
    fn merge_two_boxes() {
        // two 2×1×1 boxes sharing the face x = 2
        let a = box_mesh([2.0, 1.0, 1.0], [2, 1, 1], BoxElement::Hex20);
        let mut mesh = a.clone();
        let shift = a.node_count();
        let max_label = *a.node_labels.iter().max().unwrap();
        for (i, x) in a.coords.iter().enumerate() {
            mesh.add_node(max_label + a.node_labels[i], [x[0] + 2.0, x[1], x[2]])
                .unwrap();
        }
        for el in &a.elements {
            let nodes = el.nodes.iter().map(|&n| n + shift).collect();
            mesh.add_element(el.label + 100, el.kind, nodes).unwrap();
        }
        mesh.extend_node_set("RIGHT_X0", a.node_sets["X0"].iter().map(|&n| n + shift));
        mesh.extend_element_set("RIGHT", a.elements.len()..2 * a.elements.len());
        let shared = a.node_sets["X1"].len();
        let merged = merge_coincident_nodes(&mut mesh, 1e-9);
        assert_eq!(merged, shared);
        let whole = box_mesh([4.0, 1.0, 1.0], [4, 1, 1], BoxElement::Hex20);
        assert_eq!(mesh.node_count(), whole.node_count());
        assert_no_close_nodes(&mesh, 1e-9);
        assert_positive_jacobians(&mesh);
        // the left box keeps its nodes (lowest index survives), the shared face
        // set of the right box now points at the left box's X1 nodes
        assert_eq!(mesh.coords[..shift], a.coords[..]);
        assert_eq!(mesh.node_labels[..shift], a.node_labels[..]);
        assert_eq!(mesh.node_sets["RIGHT_X0"], a.node_sets["X1"]);
        assert_eq!(mesh.element_sets["RIGHT"].len(), a.elements.len());
        for (i, &l) in mesh.node_labels.iter().enumerate() {
            assert_eq!(mesh.node(l), Some(i));
        }
        for (e, el) in mesh.elements.iter().enumerate() {
            assert_eq!(mesh.element(el.label), Some(e));
            assert!(el.nodes.iter().all(|&n| n < mesh.node_count()));
        }
        // element nodes sit where they sat before the merge
        let right0 = &mesh.elements[a.elements.len()];
        for (k, &n) in right0.nodes.iter().enumerate() {
            let x = a.coords[a.elements[0].nodes[k]];
            assert_eq!(mesh.coords[n], [x[0] + 2.0, x[1], x[2]]);
        }
        // nothing left to merge
        assert_eq!(merge_coincident_nodes(&mut mesh, 1e-9), 0);
    }

    #[test]
    fn merge_is_transitive_and_strict() {
        let mut mesh = Mesh::new();
        // 5, 3, 9 form a chain 0.6 apart (tolerance 1): one node, label 5
        for (label, x) in [(5, 0.0), (3, 0.6), (9, 1.2), (7, 3.0), (8, 4.0)] {
            mesh.add_node(label, [x, 0.0, 0.0]).unwrap();
        }
        mesh.extend_node_set("S", [2, 4]);
        // distance exactly 1.0 (labels 7, 8) is not "closer than" 1.0
        assert_eq!(merge_coincident_nodes(&mut mesh, 1.0), 2);
        assert_eq!(mesh.node_labels, vec![5, 7, 8]);
        assert_eq!(mesh.coords[0], [0.0, 0.0, 0.0]);
        assert_eq!(mesh.node_sets["S"], vec![0, 2]);
        assert_eq!(mesh.node(9), None);
        assert_eq!(mesh.node(8), Some(2));
        assert_eq!(merge_coincident_nodes(&mut mesh, 0.0), 0);
        assert_eq!(merge_coincident_nodes(&mut mesh, f64::NAN), 0);
    }

    #[test]
    fn merge_is_linear_time() {
        // a 40×40×4 Hex20 box (≈ 33 000 nodes) duplicated: every node merges
        let a = box_mesh([40.0, 40.0, 4.0], [40, 40, 4], BoxElement::Hex20);
        let mut mesh = a.clone();
        let shift = a.node_count() as u64;
        for (i, x) in a.coords.iter().enumerate() {
            mesh.add_node(shift + a.node_labels[i], *x).unwrap();
        }
        let t = std::time::Instant::now();
        assert_eq!(merge_coincident_nodes(&mut mesh, 1e-6), a.node_count());
        let s = t.elapsed().as_secs_f64();
        assert_eq!(mesh.coords, a.coords);
        assert!(s < 1.0, "merging {} nodes took {s} s", 2 * a.node_count());
    }
}
