//! The hypoid LTCA (`flank::ltca::cycle`) of seed 003's eased pair
//! (`papers/seed003-hypoid/scene_eased.toml`, 1000 N·m on the gear) with its
//! compliance tensors cached (coarse bodies: flank 2 mm, base 8 mm, computed
//! once before the timing): one position (roll 0) with friction μ = 0.07 in
//! 10 load increments, and the whole frictionless cycle of 20 positions
//! (`LtcaCycle::solve_cycle`, positions in parallel). Issue 19's target:
//! the cycle ≤ 1 s with the tensors cached. Medians in `benches/README.md`.
//!
//! `cargo bench --bench ltca_hypoid` (`RAYON_NUM_THREADS=1` for one thread).

use std::hint::black_box;
use std::path::Path;

use criterion::{criterion_group, criterion_main, Criterion};

use flank::compliance::body::BodyMeshOptions;
use flank::ltca::cycle::{LtcaCycle, LtcaOptions};
use flank::scene::read_scene;

fn bench(c: &mut Criterion) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let scene = read_scene(&root.join("papers/seed003-hypoid/scene_eased.toml")).unwrap();
    let tmp = Path::new(env!("CARGO_TARGET_TMPDIR")).join("bench_ltca_hypoid");
    let options = LtcaOptions {
        out: tmp.join("out"),
        mesh: BodyMeshOptions {
            flank_size: Some(2.0),
            base_size: Some(8.0),
            ..Default::default()
        },
        cache: Some(tmp.join("cache")),
        quiet: true,
        ..Default::default()
    };
    std::fs::create_dir_all(&options.out).unwrap();
    let frictionless = LtcaCycle::new(&scene, &options).unwrap();
    let friction = LtcaCycle::new(
        &scene,
        &LtcaOptions {
            friction_mu: Some(0.07),
            increments: Some(10),
            ..options.clone()
        },
    )
    .unwrap();
    let pitch = frictionless.point().unwrap().cycle_deg();
    let rolls: Vec<f64> = (0..20)
        .map(|i| -0.5 * pitch + pitch * i as f64 / 20.0)
        .collect();
    let r = friction.solve(0.0).unwrap();
    assert!(r.kkt_within_tolerance && r.friction.is_some());
    let cycle = frictionless.solve_cycle(&rolls).unwrap();
    assert_eq!(cycle.len(), 20);
    let mut g = c.benchmark_group("ltca_hypoid_seed003");
    g.sample_size(10);
    g.bench_function("position_friction_10_increments", |b| {
        b.iter(|| black_box(friction.solve(0.0).unwrap()))
    });
    g.bench_function("cycle_20_positions_tensors_cached", |b| {
        b.iter(|| black_box(frictionless.solve_cycle(&rolls).unwrap()))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
