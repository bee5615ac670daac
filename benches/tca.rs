//! A whole point-contact TCA cycle (`flank::tca::point_contact`) of seed
//! 000's hypoid pair (`papers/seed000-hypoid/scene.toml`, both members
//! face-hobbed): the middle pair traced at 30 positions a pitch over its
//! whole engagement (≈ 72 positions, 2.4 pitches, every pair in mesh read
//! off the trace), flank and edge systems with the bisected transitions,
//! curvature ellipses and velocities at every traced point; with and
//! without the numerical ellipse search (18 planes over 180°, golden-
//! section refinement). Target (issue 17): a cycle with ellipses and edge
//! checks under 50 ms.
//!
//! Criterion medians (2 threads, 2-core machine, 10 samples): 61.1 ms
//! with curvature ellipses (target missed by 22 %; 307 Newton steps, 74
//! positions: ≈ 0.2 ms a tangency solve on the face-hobbed surfaces, whose
//! every evaluation is an envelope solve), 4.2 s with the search (≈ 30 ms a
//! searched ellipse, 1 300 separation probes of two section points each).
//!
//! `cargo bench --bench tca`.

use std::hint::black_box;
use std::path::Path;

use criterion::{criterion_group, criterion_main, Criterion};

use flank::scene::{read_any_scene, AnyScene};
use flank::tca::point_contact::{point_tca, PointTcaSettings};

fn bench(c: &mut Criterion) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("papers/seed000-hypoid/scene.toml");
    let AnyScene::Bevel(scene) = read_any_scene(&path).unwrap() else {
        panic!("seed 000 is a bevel scene");
    };
    let pair = scene.pair.clone();
    let mut g = c.benchmark_group("point_tca_seed000");
    g.sample_size(10);
    for (name, search) in [
        ("curvature_ellipses_edges", 0),
        ("searched_ellipses_edges", 18),
    ] {
        let settings = PointTcaSettings {
            search_directions: search,
            ..Default::default()
        };
        let t = point_tca(pair.as_ref(), &settings).unwrap();
        eprintln!(
            "{name}: {} positions, {} Newton steps, {} transitions",
            t.positions.len(),
            t.newton_steps,
            t.transitions.len()
        );
        g.bench_function(name, |b| {
            b.iter(|| black_box(point_tca(pair.as_ref(), &settings).unwrap()))
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
