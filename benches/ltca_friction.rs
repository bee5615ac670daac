//! The frictional LTCA kernel (`flank::ltca::friction`) on a synthetic
//! contact line: M = 30 and 100 points, crowned, μ = 0.1, all points
//! slipping (s = 3), 10 load increments; the clarabel path (Tresca QPs,
//! fixed point, polish) against Lemke's method on the same problem.
//!
//! `cargo bench --bench ltca_friction`. The compliance is the Laplace-kernel
//! line of `verification/ltca_friction` ([[aK, bK], [bK, eK]] + diagonal).

use criterion::{criterion_group, criterion_main, Criterion};

use flank::ltca::friction::{
    solve_friction, FrictionOptions, FrictionProblem, FrictionSolver, Increments,
};

/// Owned data of the line problem.
struct Line {
    c: [Vec<f64>; 4],
    g0: Vec<f64>,
    r_n: Vec<f64>,
    r_t: Vec<f64>,
    s: Vec<f64>,
}

fn line(m: usize) -> Line {
    let x: Vec<f64> = (0..m).map(|i| 10.0 * (i as f64 + 0.5) / m as f64).collect();
    let (a, b, e, lambda) = (3e-6, 1e-7, 2e-6, 2.0);
    let (dn, dt) = (1e-7 * m as f64, 0.8e-7 * m as f64);
    let k = |i: usize, j: usize| (-(x[i] - x[j]).abs() / lambda).exp();
    let block = |s: f64, d: f64| -> Vec<f64> {
        (0..m * m)
            .map(|p| s * k(p / m, p % m) + if p / m == p % m { d } else { 0.0 })
            .collect()
    };
    Line {
        c: [block(a, dn), block(b, 0.0), block(b, 0.0), block(e, dt)],
        g0: x.iter().map(|&v| 2e-3 * (v - 5.0).powi(2) / 25.0).collect(),
        r_n: x.iter().map(|&v| 40.0 + 0.5 * v).collect(),
        r_t: x.iter().map(|&v| 0.5 * (v - 5.0)).collect(),
        s: vec![3.0; m],
    }
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("ltca_friction");
    group.sample_size(10);
    for m in [30, 100] {
        let d = line(m);
        let pb = FrictionProblem {
            c_nn: &d.c[0],
            c_nt: &d.c[1],
            c_tn: &d.c[2],
            c_tt: &d.c[3],
            separation: &d.g0,
            arm_normal: &d.r_n,
            arm_tangential: &d.r_t,
            sliding: &d.s,
            mu: 0.1,
            point_mu: None,
            torque: 1e5,
        };
        for solver in [FrictionSolver::Clarabel, FrictionSolver::Lemke] {
            let o = FrictionOptions {
                solver,
                increments: Increments::Count(10),
                ..FrictionOptions::default()
            };
            let sol = solve_friction(&pb, &o).unwrap();
            assert!(sol.within_tolerance, "{:?}", sol.max_residual);
            group.bench_function(format!("{}_m{m}_10_increments", solver.name()), |bch| {
                bch.iter(|| solve_friction(&pb, &o).unwrap())
            });
        }
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
