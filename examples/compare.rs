//! The LTCA against FE contact at the same roll angles, error against run
//! time, for seed 002's spur pair, through the library (coarse: FE flank
//! elements of 1.0 and 0.75 mm, LTCA with K = 5 and 10 on 1 mm tensors, three
//! roll angles). The same call takes a hypoid scene.
//!
//! Run: `cargo run --release --example compare`
//! (writes `out/example_compare/`: `compare.json`, `compare.md`,
//! `error_vs_time.svg`).

use std::path::Path;

use flank::api::{compare, load_scene, BodyMeshOptions, CompareOptions, LtcaOptions};

fn main() -> anyhow::Result<()> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let scene = load_scene(root.join("papers/seed002-spur/scene.toml"))?;
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
    println!(
        "best LTCA {} against {}: load share within {:.4}, TE {:.2} %, p_max {:.2} %; LTCA cycle {:.3} s, FE cycle {:.1} s",
        summary.best_ltca,
        summary.reference,
        summary.load_sharing_rel_err,
        100.0 * summary.te_rel_err,
        100.0 * summary.pmax_rel_err,
        summary.ltca_cycle_s,
        summary.fe_cycle_s,
    );
    println!(
        "the table per K and FE mesh: {}",
        options.out.join("compare.md").display()
    );
    Ok(())
}
