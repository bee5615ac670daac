//! A whole point-contact TCA cycle (`flank::tca::point_contact`) of seed
//! 000's hypoid pair (`papers/seed000-hypoid/scene.toml`, both members
//! face-hobbed): the middle pair traced at 30 positions a pitch over its
//! whole engagement (91 positions, 3.0 pitches, every pair in mesh read
//! off the trace), flank and edge systems with the located transitions,
//! curvature ellipses and velocities at every traced point; with and
//! without the numerical ellipse search (18 planes over 180°, golden-
//! section refinement). Target (issue 17): a cycle with ellipses and edge
//! checks under 50 ms.
//!
//! Criterion medians (2 threads, 2-core machine, 10 samples):
//! * 2026-11-26 morning, after the gear-edge lean fix (91 positions, 358
//!   Newton steps, 4 transitions): **49.6 ms** (45.8–52.2 ms) with
//!   curvature ellipses; 5.15 s with the search (≈ 30 ms a searched
//!   ellipse).
//! * 2026-11-26 afternoon, transitions by regula falsi and the edge chosen
//!   among the near edges by the largest lag (361 Newton steps): **51.3 ms**
//!   (45.8–56.8) and **55.6 ms** (51.6–58.8) in two runs on a quiet
//!   machine; 4.91 s with the search. Target 50 ms: **missed** (the
//!   intervals overlap the morning's: not a measured slowdown; the whole
//!   `flank tca` command, both variants, new/old CPU time 0.92 median
//!   over 20 paired runs, 0.62–1.17, on a machine shared with a CI run).
//!   The trace (tangency solves, the transitions)
//!   is about two thirds of the cycle, the curvature ellipses and the
//!   crossing check the rest.
//! * 2026-11-26 late afternoon, tca-speed branch (the same 91 positions,
//!   361 Newton steps, 4 transitions; tables byte-identical): a tangency
//!   Jacobian column evaluates only the member its unknown moves (8
//!   surface evaluations a flank-system column set instead of 20, the
//!   turn none), the form lines u_form(v) are remembered per trace (the
//!   boundary checks and the regula falsi's margin asked them twice at the
//!   same v), the backward and forward traces run side by side
//!   (`rayon::join`), and the curvature ellipse takes its three normal
//!   curvatures of a flank from one evaluation and one set of second
//!   derivatives (5 evaluations a flank instead of 15). Old and new bench
//!   binaries alternated, 7 pairs, on a machine shared with three other
//!   sessions (load average 6–8 for the first 4 pairs, 1.7–3.2 for the
//!   last 3): medians old 68.2 / 65.0 / 64.7 / 45.8 / 60.7 / 55.6 /
//!   42.5 ms, new 31.8 / 31.8 / 38.3 / 21.6 / 25.9 / 36.0 / 56.3 ms;
//!   median of the seven **60.7 ms old, 31.8 ms new**, new/old 0.43–0.65
//!   in six pairs and 1.32 in the last (the load rose during the new run
//!   of that pair), **0.49** median pair. On 1 rayon thread (no join, the
//!   work itself): old 66.0 / 48.5 ms, new 37.1 / 39.5 ms. Target 50 ms:
//!   **met** by the median and by 6 of 7 new runs, not by every run on
//!   this shared machine (single runs reached 56 ms under load; the
//!   afternoon's quiet-machine 51.3 ms times 0.49 is about 25 ms). CPU profile of
//!   the new cycle (samples over both threads): trace 60 % (tangency
//!   Newton solves 44 %, the form-line Newtons 16 %, the located
//!   transitions 18 % of it), the screened crossing check 32 %, the
//!   curvature ellipses 6 % (13 % before the change), the rest 2 %.
//!   Tried and reverted (commit b52d5a7, reverted in debc1b5): chord
//!   steps with the trace's last Jacobian and seeds extrapolated in (u, v)
//!   cut the steps to 275 and the CPU by about a quarter (33.5 → 25.0 ms
//!   a cycle, one noisy harness run each), but seed 003 eased's
//!   flank trace then ran on past −34.909° (where the Newton at that grid
//!   roll fails from the old seed and the trace ends) to −38.694° and a
//!   gear heel edge to −46.091°: a change of contact type.
//!
//! Before the crossing check was screened (`tca::crossing`) the same cycle
//! took about 2.8 s, 98 % of it in the check's 22 950 exact closest points
//! on face-hobbed flanks (each an envelope solve per evaluation); the
//! figure of 61 ms measured before the check existed had not been updated.
//!
//! `cargo bench --bench tca`.

use std::hint::black_box;
use std::path::Path;

use criterion::{criterion_group, criterion_main, Criterion};

use flank::scene::read_scene;
use flank::tca::point_contact::{point_tca, PointTcaSettings};

fn bench(c: &mut Criterion) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("papers/seed000-hypoid/scene.toml");
    let scene = read_scene(&path).unwrap();
    let pair = scene.bevel("the point-TCA bench").unwrap().pair.clone();
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
