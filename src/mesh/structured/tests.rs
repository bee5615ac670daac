//! Unit tests of the structured generators: counts, shared midside nodes,
//! sets and faces, orientation, graded maps, distortion, cylinder and plate
//! geometry.

use super::distort::dist;
use super::*;
use crate::fem::element::edges;
use std::collections::HashMap;

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
                let local = face_nodes(el.kind, f).expect("face number within the element's faces");
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
