//! The LTCA against FE contact at the same roll angles, error against run
//! time, for seed 002's spur pair, through the library (coarse: FE flank
//! elements of 1.0 and 0.75 mm, LTCA with K = 5 and 10 on 1 mm tensors, three
//! roll angles). The same call takes a hypoid scene.
//!
//! Run: `cargo run --release --example compare`
//! (writes `out/example_compare/`: `compare.json`, `compare.md`,
//! `error_vs_time.svg`).

use std::path::Path;

use flank::compare::run::compare;
use flank::compare::CompareOptions;
use flank::compliance::body::BodyMeshOptions;
use flank::ltca::cycle::LtcaOptions;
use flank::scene::read_scene;

fn main() -> anyhow::Result<()> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let scene = read_scene(&root.join("papers/seed002-spur/scene.toml"))?;
    let options = CompareOptions {
        out: root.join("out/example_compare"),
        points_per_line: vec![5, 10],
        fe_flank_sizes: vec![1.0, 0.75],
        fe_base_size: Some(4.0),
        roll_angles_deg: Some(vec![-5.0, 0.0, 5.0]),
        ltca: LtcaOptions {
            mesh: BodyMeshOptions {
                flank_size: Some(1.0),
                base_size: Some(4.0),
                ..Default::default()
            },
            quiet: true,
            ..Default::default()
        },
        quiet: true,
        ..Default::default()
    };
    let summary = compare(&scene, &options)?;
    let number = |key: &str| summary[key].as_f64().unwrap_or(f64::NAN);
    println!(
        "best LTCA {} against {}: load share within {:.4}, TE {:.2} %, p_max {:.2} %; LTCA cycle {:.3} s, FE cycle {:.1} s",
        summary["best_ltca"],
        summary["reference"],
        number("load_sharing_rel_err"),
        100.0 * number("te_rel_err"),
        100.0 * number("pmax_rel_err"),
        number("ltca_cycle_s"),
        number("fe_cycle_s"),
    );
    println!(
        "the table per K and FE mesh: {}",
        options.out.join("compare.md").display()
    );
    Ok(())
}
