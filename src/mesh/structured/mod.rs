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
//!
//! # Files
//!
//! | file | holds |
//! | --- | --- |
//! | `mod.rs` (this file) | [`BoxElement`], the lattice mesher, the generators ([`box_mesh`], [`thick_cylinder_quarter`], [`le10_plate`], [`annulus`]), [`map_nodes`], [`box_faces`] and the benchmark [`cantilever_model`] |
//! | `distort.rs` | [`distort_interior`]: pseudo-random moves of the interior nodes (patch and distortion tests) |
//! | `merge.rs` | [`merge_coincident_nodes`]: nodes closer than a tolerance merged into one |
//! | `tests.rs` | unit tests of the generators and the distortion |
//! | `merge_tests.rs` | unit tests of the merge and the closed ring |

mod distort;
mod merge;

#[cfg(test)]
mod merge_tests;
#[cfg(test)]
mod tests;

use std::f64::consts::FRAC_PI_2;

use crate::fem::element::face_nodes;
use crate::fem::mesh::{ElementKind, Mesh};

pub use distort::distort_interior;
pub use merge::merge_coincident_nodes;

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
