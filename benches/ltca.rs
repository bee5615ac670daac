//! LTCA of the seed 002 pair with the compliance tensors in memory
//! (`flank::ltca`): one roll position in double and in single contact, and
//! a whole mesh cycle of 30 positions (issue target: < 0.1 s), at K = 20 (by default):
//! one position after the other, and side by side on the thread pool as
//! `flank ltca` runs it (`LtcaCycle::solve_cycle`).
//!
//! `cargo bench --bench ltca`. The tensors are computed once before timing
//! (flank 0.475 mm, base 1 mm, hex20 as the scene's LTCA default would be
//! with these sizes; cached in target/ltca-bench). The breakdown of a
//! position (cells, tensor part of F, half-space correction, QP) is printed
//! for the first call and as medians of 30 calls,
//! and at the end the memory of the paged tensor blocks F is read from
//! (`flank::compliance::pages`). `FLANK_LTCA_BENCH_COMPRESSION=1e-6` builds
//! the tensors compressed from the factor (as `flank ltca --compression`)
//! and times the LTCA on them. `FLANK_LTCA_BENCH_FLANK_SIZE` (mm, default
//! 0.475) and `FLANK_LTCA_BENCH_K` (default 20) set the flank mesh and the
//! points per line, `FLANK_LTCA_BENCH_BODIES` the folder the bodies and
//! their tensors are written to and read back from (default
//! target/ltca-bench/bodies): issue 23's accuracy needs the paper's 0.1 mm
//! tensors, whose compressed build takes minutes, so a folder of
//! `flank compare … --flank-size 0.1 --compression 1e-6` (its
//! `ltca_bodies`) can be reused. Figures: benches/README.md.

use std::path::Path;

use criterion::{criterion_group, criterion_main, Criterion};

use flank::compliance::body::BodyMeshOptions;
use flank::ltca::cycle::{LtcaCycle, LtcaOptions};

fn bench(c: &mut Criterion) {
    let scene = flank::scene::read_scene(Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/papers/seed002-spur/scene.toml"
    )))
    .unwrap();
    let work = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/ltca-bench");
    let compression = std::env::var("FLANK_LTCA_BENCH_COMPRESSION").ok().map(|s| {
        s.parse()
            .expect("FLANK_LTCA_BENCH_COMPRESSION: none or ε, e.g. 1e-6")
    });
    let flank_size: f64 = std::env::var("FLANK_LTCA_BENCH_FLANK_SIZE").map_or(0.475, |s| {
        s.parse()
            .expect("FLANK_LTCA_BENCH_FLANK_SIZE: the flank element size in mm, e.g. 0.1")
    });
    let k: usize = std::env::var("FLANK_LTCA_BENCH_K").map_or(20, |s| {
        s.parse()
            .expect("FLANK_LTCA_BENCH_K: points per contact line, e.g. 5")
    });
    // a given bodies' folder is read as `flank ltca --out` reads it (no
    // cache: a cache file would take precedence over the folder's tensors)
    let given = std::env::var("FLANK_LTCA_BENCH_BODIES").ok();
    let cache = given.is_none().then(|| work.join("cache"));
    let bodies = given.map_or_else(|| work.join("bodies"), std::path::PathBuf::from);
    let o = LtcaOptions {
        compression,
        out: bodies,
        mesh: BodyMeshOptions {
            flank_size: Some(flank_size),
            base_size: Some(1.0),
            ..Default::default()
        },
        points_per_line: Some(k),
        cache,
        quiet: true,
        ..Default::default()
    };
    let cycle = LtcaCycle::new(&scene, &o).unwrap();
    println!(
        "tensors: {:?} flank nodes, {:.1} s (computed {:?})",
        cycle.setup.flank_nodes, cycle.setup.compliance_s, cycle.setup.computed
    );
    let (a, e) = cycle.line_pair().unwrap().engagement(cycle.pair.middle());
    let (l, h) = cycle.line_pair().unwrap().single_contact();
    let double = 0.5 * (a + l).to_degrees();
    let single = 0.5 * (l + h).to_degrees();
    for (name, roll) in [("double", double), ("single", single)] {
        let r = cycle.solve(roll).unwrap();
        println!(
            "{name} contact {roll:.3}°: {} candidates, first call {:.2} ms (cells {:.2}, F {:.2}, H {:.2}, QP {:.2})",
            r.candidates,
            1e3 * r.time_s,
            1e3 * r.cells_s,
            1e3 * r.compliance_s,
            1e3 * r.local_s,
            1e3 * r.qp_s
        );
        // the parts once the pages are built: medians of 30 calls
        let mut parts = [const { Vec::new() }; 5];
        for _ in 0..30 {
            let r = cycle.solve(roll).unwrap();
            for (v, x) in
                parts
                    .iter_mut()
                    .zip([r.time_s, r.cells_s, r.compliance_s, r.local_s, r.qp_s])
            {
                v.push(1e3 * x);
            }
        }
        let m: Vec<f64> = parts
            .iter_mut()
            .map(|v| {
                v.sort_by(f64::total_cmp);
                v[v.len() / 2]
            })
            .collect();
        println!(
            "{name} contact, medians of 30 calls: {:.3} ms (cells {:.3}, F {:.3}, H {:.3}, QP {:.3}; TCA and the rest {:.3})",
            m[0],
            m[1],
            m[2],
            m[3],
            m[4],
            m[0] - m[1] - m[2] - m[3] - m[4]
        );
    }
    let pitch = cycle.pair.pinion().angular_pitch().to_degrees();
    let start = 0.5 * (a + e).to_degrees() - 0.5 * pitch;
    let angles: Vec<f64> = (0..30).map(|i| start + pitch * i as f64 / 30.0).collect();
    let mut g = c.benchmark_group(format!("ltca_seed002_flank{flank_size}_K{k}"));
    g.sample_size(10);
    g.bench_function("position_double_contact", |b| {
        b.iter(|| cycle.solve(double).unwrap())
    });
    g.bench_function("position_single_contact", |b| {
        b.iter(|| cycle.solve(single).unwrap())
    });
    g.bench_function("cycle_30_positions", |b| {
        b.iter(|| {
            for &x in &angles {
                cycle.solve(x).unwrap();
            }
        })
    });
    // as `flank ltca` runs a cycle: the positions side by side
    g.bench_function("cycle_30_positions_side_by_side", |b| {
        b.iter(|| cycle.solve_cycle(&angles).unwrap())
    });
    g.finish();
    println!(
        "paged tensor blocks built: pinion {:.1} MB, gear {:.1} MB",
        cycle.bodies.grids[0].page_bytes() as f64 * 1e-6,
        cycle.bodies.grids[1].page_bytes() as f64 * 1e-6
    );
}

criterion_group!(benches, bench);
criterion_main!(benches);
