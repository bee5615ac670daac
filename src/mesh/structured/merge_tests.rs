//! Unit tests of [`super::merge_coincident_nodes`] and the closed ring
//! [`super::annulus`].

use super::distort::{boundary_nodes, dist};
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
