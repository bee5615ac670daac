//! Criterion benchmarks of the FE core: element integration, assembly
//! (symbolic and numeric), ordering + factorization, at three mesh sizes of a
//! C3D20 cantilever box (the side-by-side run against CalculiX is
//! `benches/ccx_side_by_side.sh`), and a block of 32 sparse right-hand
//! sides at the tip face solved in full and restricted to the reach of the
//! tip's DOFs (the Delassus columns of FE contact).

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};

use flank::fem::assembly::Assembly;
use flank::fem::constraints::DofMap;
use flank::fem::element::{stiffness, ElementWorkspace, HEX20_NODES, WEDGE15_NODES};
use flank::fem::mesh::ElementKind;
use flank::fem::model::Model;
use flank::fem::ordering::OrderingMethod;
use flank::fem::solver::{parallelism, Precision, SparseCholesky};
use flank::mesh::structured::{cantilever_model, BoxElement};

fn cantilever(cells: [usize; 3]) -> Model {
    cantilever_model(cells, BoxElement::Hex20, 1000.0).unwrap()
}

fn element_integration(c: &mut Criterion) {
    let mut g = c.benchmark_group("element_stiffness");
    let distort = |p: &[f64; 3]| {
        [
            p[0] + 0.05 * p[1] * p[2],
            p[1] + 0.03 * p[0],
            p[2] - 0.02 * p[0] * p[1],
        ]
    };
    for kind in [ElementKind::C3D20, ElementKind::C3D20R, ElementKind::C3D15] {
        let x: Vec<[f64; 3]> = match kind {
            ElementKind::C3D15 => WEDGE15_NODES.iter().map(distort).collect(),
            _ => HEX20_NODES.iter().map(distort).collect(),
        };
        let mut ws = ElementWorkspace::default();
        let mut k = Vec::new();
        g.bench_function(kind.name(), |b| {
            b.iter(|| stiffness(kind, &x, 121e3, 81e3, &mut ws, &mut k).unwrap())
        });
    }
    g.finish();
}

const SIZES: [[usize; 3]; 3] = [[20, 4, 4], [50, 6, 6], [100, 10, 10]];

fn assembly(c: &mut Criterion) {
    let mut g = c.benchmark_group("assembly");
    g.sample_size(10);
    for cells in SIZES {
        let model = cantilever(cells);
        let dofs = DofMap::new(&model).unwrap();
        let id = format!("{}x{}x{}", cells[0], cells[1], cells[2]);
        g.bench_with_input(
            BenchmarkId::new("symbolic_with_metis", &id),
            &model,
            |b, m| b.iter(|| Assembly::new(m, &mut dofs.clone(), OrderingMethod::Metis).unwrap()),
        );
        let mut dofs = dofs;
        let asm = Assembly::new(&model, &mut dofs, OrderingMethod::Metis).unwrap();
        g.bench_with_input(BenchmarkId::new("numeric", &id), &model, |b, m| {
            b.iter(|| asm.assemble(m, &dofs).unwrap())
        });
    }
    g.finish();
}

fn factorization(c: &mut Criterion) {
    let mut g = c.benchmark_group("factorization");
    g.sample_size(10);
    for cells in SIZES {
        let model = cantilever(cells);
        let id = format!("{}x{}x{}", cells[0], cells[1], cells[2]);
        for ordering in [OrderingMethod::Metis, OrderingMethod::Amd] {
            if ordering == OrderingMethod::Amd && cells[0] == 100 {
                continue; // AMD's fill on the largest box makes the run long; see benches/README.md
            }
            let mut dofs = DofMap::new(&model).unwrap();
            let asm = Assembly::new(&model, &mut dofs, ordering).unwrap();
            let sys = asm.assemble(&model, &dofs).unwrap();
            g.bench_function(
                BenchmarkId::new(format!("symbolic_{}", ordering.name()), &id),
                |b| {
                    b.iter(|| {
                        SparseCholesky::analyze(&asm.pattern, ordering, 0.0, parallelism(0))
                            .unwrap()
                    })
                },
            );
            let mut chol =
                SparseCholesky::analyze(&asm.pattern, ordering, 0.0, parallelism(0)).unwrap();
            g.bench_function(
                BenchmarkId::new(format!("numeric_{}", ordering.name()), &id),
                |b| {
                    b.iter(|| {
                        chol.factorize(&asm.pattern, &sys.values, Precision::Double, &|r| {
                            r.to_string()
                        })
                        .unwrap()
                    })
                },
            );
        }
    }
    g.finish();
}

fn substitution(c: &mut Criterion) {
    let mut g = c.benchmark_group("substitution_32_rhs");
    g.sample_size(10);
    for cells in [[50, 6, 6], [100, 10, 10]] {
        let model = cantilever(cells);
        let id = format!("{}x{}x{}", cells[0], cells[1], cells[2]);
        let mut dofs = DofMap::new(&model).unwrap();
        let asm = Assembly::new(&model, &mut dofs, OrderingMethod::Metis).unwrap();
        let sys = asm.assemble(&model, &dofs).unwrap();
        let mut chol =
            SparseCholesky::analyze(&asm.pattern, OrderingMethod::Metis, 0.0, parallelism(0))
                .unwrap();
        chol.factorize(&asm.pattern, &sys.values, Precision::Double, &|r| {
            r.to_string()
        })
        .unwrap();
        // unit loads in y at the tip nodes (a contact zone's right-hand sides)
        let tip: Vec<usize> = model.mesh.node_sets["X1"]
            .iter()
            .filter_map(|&node| match dofs.targets[3 * node + 1] {
                flank::fem::constraints::DofTarget::Free(r) => Some(r),
                _ => None,
            })
            .collect();
        let columns: Vec<Vec<(usize, f64)>> =
            tip.iter().take(32).map(|&r| vec![(r, 1.0)]).collect();
        let refs: Vec<&[(usize, f64)]> = columns.iter().map(|c| &c[..]).collect();
        let n = asm.pattern.n;
        g.bench_function(BenchmarkId::new("full", &id), |b| {
            b.iter(|| {
                let mut x = faer::Mat::<f64>::zeros(n, refs.len());
                for (j, col) in columns.iter().enumerate() {
                    x[(col[0].0, j)] = 1.0;
                }
                chol.solve_columns(x.as_mut());
                x
            })
        });
        let reach = chol.reach(&tip).expect("a supernodal factor");
        println!(
            "{id}: the reach of the tip's y DOFs holds {:.1} % of nnz(L)",
            100.0 * reach.touched_fraction()
        );
        g.bench_function(BenchmarkId::new("restricted", &id), |b| {
            b.iter(|| chol.solve_restricted(&reach, &refs, parallelism(0)))
        });
    }
    g.finish();
}

criterion_group!(
    benches,
    element_integration,
    assembly,
    factorization,
    substitution
);
criterion_main!(benches);
