use super::*;
use crate::fem::assembly::Assembly;
use crate::fem::constraints::DofMap;
use crate::fem::ordering::{order_groups_two_domain, GroupGraph, NO_ANCHOR};
use crate::mesh::structured::{cantilever_model, BoxElement};
use crate::testing::Rng;

/// Lower-triangle CSC of a shifted 7-point Laplacian with random couplings
/// (SPD: diagonally dominant) on an `a × b × c` grid split at the plane
/// k = c / 2 and numbered \[A (k < c/2), S (the plane), B (k > c/2)\]; with
/// `cut`, the plane's couplings to B are dropped and S is empty (two
/// uncoupled blocks).
fn grid_split(
    a: usize,
    b: usize,
    c: usize,
    cut: bool,
    rng: &mut Rng,
) -> (SparsePattern, Vec<f64>, DomainSplit) {
    let plane = a * b;
    let mid = c / 2;
    let part = |k: usize| (k > mid) as usize * 2 + (k == mid && !cut) as usize;
    // number A, then S, then B; with `cut` the plane joins A
    let mut order: Vec<(usize, usize, usize)> = Vec::new();
    for p in [0, 1, 2] {
        for k in 0..c {
            let kp = if cut && k == mid { 0 } else { part(k) };
            if kp == p {
                for j in 0..b {
                    for i in 0..a {
                        order.push((i, j, k));
                    }
                }
            }
        }
    }
    let n = order.len();
    let mut id = vec![0usize; n];
    for (new, &(i, j, k)) in order.iter().enumerate() {
        id[i + a * (j + b * k)] = new;
    }
    let mut cols: Vec<Vec<(usize, f64)>> = vec![Vec::new(); n];
    for k in 0..c {
        for j in 0..b {
            for i in 0..a {
                let me = id[i + a * (j + b * k)];
                cols[me].push((me, 6.5 + rng.unit().abs()));
                let mut nb = Vec::new();
                if i + 1 < a {
                    nb.push(id[i + 1 + a * (j + b * k)]);
                }
                if j + 1 < b {
                    nb.push(id[i + a * (j + 1 + b * k)]);
                }
                if k + 1 < c && !(cut && k == mid) {
                    nb.push(id[i + a * (j + b * (k + 1))]);
                }
                for o in nb {
                    let v = -0.5 - 0.5 * rng.unit().abs();
                    cols[me.min(o)].push((me.max(o), v));
                }
            }
        }
    }
    let mut col_ptr = vec![0];
    let mut row_idx = Vec::new();
    let mut values = Vec::new();
    for mut col in cols {
        col.sort_by_key(|e| e.0);
        for (r, v) in col {
            row_idx.push(r);
            values.push(v);
        }
        col_ptr.push(row_idx.len());
    }
    let ns = if cut { 0 } else { plane };
    let na = mid * plane + if cut { plane } else { 0 };
    (
        SparsePattern {
            n,
            col_ptr,
            row_idx,
        },
        values,
        DomainSplit {
            a: na,
            s: ns,
            b: n - na - ns,
        },
    )
}

/// The largest |x − y| / max|y|.
fn rel_diff(x: &[f64], y: &[f64]) -> f64 {
    let m = y.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    x.iter()
        .zip(y)
        .fold(0.0f64, |a, (u, v)| a.max((u - v).abs()))
        / m
}

/// The two-domain solve against a plain double factorization of the same
/// matrix: equal to round-off with f64 halves, to f32 accuracy with f32
/// halves, and the same with 1 and 2 threads.
fn check_against_plain(pattern: &SparsePattern, values: &[f64], split: DomainSplit, rng: &mut Rng) {
    let n = pattern.n;
    let mut plain = SparseCholesky::analyze(pattern, OrderingMethod::Metis, 0.0, Par::Seq).unwrap();
    plain
        .factorize(pattern, values, Precision::Double, &|r| r.to_string())
        .unwrap();
    let rhs: Vec<f64> = (0..n).map(|_| rng.unit()).collect();
    let mut x = rhs.clone();
    plain.solve_in_place(&mut x);
    // f32 accuracy is κ-dependent: the plain f32 factor's error sets the scale
    let mut plain32 =
        SparseCholesky::analyze(pattern, OrderingMethod::Metis, 0.0, Par::Seq).unwrap();
    plain32
        .factorize(pattern, values, Precision::Mixed, &|r| r.to_string())
        .unwrap();
    let mut x32 = rhs.clone();
    plain32.solve_in_place(&mut x32);
    let f32_error = rel_diff(&x32, &x);
    for (precision, tol) in [
        (Precision::Double, 1e-11),
        (Precision::Mixed, 10.0 * f32_error + 1e-6),
    ] {
        let mut answers = Vec::new();
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let z = pool.install(|| {
                let mut td = TwoDomainCholesky::analyze(
                    pattern,
                    split,
                    OrderingMethod::Metis,
                    0.0,
                    Par::rayon(threads),
                )
                .unwrap();
                td.adopt(pattern.clone());
                td.factorize(values, precision, &|r| r.to_string()).unwrap();
                assert_eq!(td.stats.separator_dofs, split.s);
                let mut z = rhs.clone();
                td.solve_in_place(&mut z);
                // K's product on the split storage, and K's pattern back
                let y = td.sym_mul(values, &rhs);
                assert!(rel_diff(&y, &pattern.sym_mul(values, &rhs)) <= 1e-14);
                let back = td.into_pattern().unwrap();
                assert_eq!(back.col_ptr, pattern.col_ptr);
                assert_eq!(back.row_idx, pattern.row_idx);
                z
            });
            let err = rel_diff(&z, &x);
            assert!(err <= tol, "{precision:?}, {threads} threads: {err:.2e}");
            answers.push(z);
        }
        assert!(rel_diff(&answers[0], &answers[1]) <= 1e-14);
    }
}

#[test]
fn two_domain_solve_matches_plain_factorization_on_grids() {
    let mut rng = Rng::new(0x5eed_2323);
    for (a, b, c) in [(4, 3, 5), (7, 6, 9), (12, 11, 10)] {
        let (pattern, values, split) = grid_split(a, b, c, false, &mut rng);
        assert_eq!(split.s, a * b);
        check_against_plain(&pattern, &values, split, &mut rng);
    }
    // an empty separator: two uncoupled blocks
    let (pattern, values, split) = grid_split(6, 5, 8, true, &mut rng);
    assert_eq!(split.s, 0);
    check_against_plain(&pattern, &values, split, &mut rng);
}

#[test]
fn two_domain_solve_matches_plain_factorization_on_a_cantilever() {
    let mut rng = Rng::new(77);
    for (cells, kind) in [
        ([16, 3, 3], BoxElement::Hex20),
        ([30, 4, 3], BoxElement::Hex20),
        ([10, 3, 3], BoxElement::Wedge15),
    ] {
        let model = cantilever_model(cells, kind, 100.0).unwrap();
        let mut dofs = DofMap::new(&model).unwrap();
        let asm =
            Assembly::two_domain(&model, &mut dofs, OrderingMethod::Metis, usize::MAX).unwrap();
        let split = asm.split.expect("a two-domain numbering");
        assert!(split.a > 0 && split.b > 0 && split.s > 0, "{split:?}");
        // a bar's separator is a cross-section: far smaller than either part
        assert!(split.s * 4 < split.a.min(split.b), "{split:?}");
        let sys = asm.assemble(&model, &dofs).unwrap();
        check_against_plain(&asm.pattern, &sys.values, split, &mut rng);
    }
}

#[test]
fn corner_graph_separator_separates() {
    // the anchored (corner-graph) separator on a mesh above the corner-graph
    // threshold: A and B never share an element
    let model = cantilever_model([60, 10, 10], BoxElement::Hex20, 100.0).unwrap();
    let mut dofs = DofMap::new(&model).unwrap();
    let asm = Assembly::two_domain(&model, &mut dofs, OrderingMethod::Metis, usize::MAX).unwrap();
    let split = asm.split.unwrap();
    let side = |r: usize| {
        if r < split.a {
            0
        } else if r < split.a + split.s {
            1
        } else {
            2
        }
    };
    for el in &model.mesh.elements {
        let mut seen = [false; 3];
        for &nd in &el.nodes {
            for k in 0..3 {
                if let crate::fem::constraints::DofTarget::Free(r) = dofs.targets[3 * nd + k] {
                    seen[side(r)] = true;
                }
            }
        }
        assert!(!(seen[0] && seen[2]), "element {} spans A and B", el.label);
    }
    // one cross-section of 11 × 11 corners and 2 × 10 × 11 midsides
    assert!(split.s <= 3 * 400, "{split:?}");
}

#[test]
fn degenerate_splits_are_refused() {
    let mut rng = Rng::new(5);
    let (pattern, _, split) = grid_split(4, 4, 6, false, &mut rng);
    // a part empty
    for bad in [
        DomainSplit {
            a: 0,
            s: split.s,
            b: pattern.n - split.s,
        },
        DomainSplit {
            a: pattern.n - split.s,
            s: split.s,
            b: 0,
        },
        DomainSplit {
            a: split.a,
            s: split.s,
            b: split.b + 1,
        },
    ] {
        let err = TwoDomainCholesky::analyze(&pattern, bad, OrderingMethod::Metis, 0.0, Par::Seq)
            .err()
            .expect("refused");
        assert!(err.to_string().contains("two-domain split"), "{err}");
    }
    // a "separator" that does not separate: S too small by one plane row
    let not = DomainSplit {
        a: split.a + 4,
        s: split.s - 4,
        b: split.b,
    };
    let err = TwoDomainCholesky::analyze(&pattern, not, OrderingMethod::Metis, 0.0, Par::Seq)
        .err()
        .expect("refused");
    assert!(err.to_string().contains("coupled"), "{err}");
    // a graph METIS cannot split: one vertex
    let graph = GroupGraph {
        xadj: vec![0, 0],
        adjncy: vec![],
        weight: vec![3],
    };
    let err =
        order_groups_two_domain(&graph, OrderingMethod::Metis, &[NO_ANCHOR]).expect_err("refused");
    assert!(err.to_string().contains("part empty"), "{err}");
}
