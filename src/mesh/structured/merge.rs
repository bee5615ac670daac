//! Merging of coincident nodes (spatial hash, union–find): closes seams of
//! structured meshes and joins separately meshed blocks.

use std::collections::HashMap;

use crate::fem::mesh::Mesh;

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
