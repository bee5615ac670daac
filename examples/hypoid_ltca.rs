//! The compliance-matrix LTCA of seed 003's hypoid pair (the pinion with
//! its ease-off), through the library: the same entry point as for a spur
//! pair ([`flank::api::ltca`]); the options not given here come from
//! the scene's `[analyses.ltca]`, else the hypoid LTCA's defaults. The
//! compliance meshes are seed 003's (1.5 mm flank, 6 mm base elements).
//!
//! Run: `cargo run --release --example hypoid_ltca`
//! (writes `out/example_hypoid_ltca/`: `ltca_positions.csv` holds the
//! force, load share and p_max per position and tooth pair, the TE in
//! arcsec of gear rotation; `summary.json`).

use std::path::Path;

use flank::api::{load_scene, ltca, BodyMeshOptions, LtcaOptions};

fn main() -> anyhow::Result<()> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let scene = load_scene(root.join("papers/seed003-hypoid/scene_eased.toml"))?;
    println!(
        "{:?} pair, m_mn = {:.3} mm",
        scene.kind,
        scene.normal_module()
    );
    let options = LtcaOptions {
        out: root.join("out/example_hypoid_ltca"),
        mesh: BodyMeshOptions {
            flank_size: Some(1.5),
            base_size: Some(6.0),
            ..Default::default()
        },
        ..Default::default()
    };
    let result = ltca(&scene, &options)?;
    let summary = result.first();
    println!(
        "{} positions: loaded TE {:.2} arcsec peak-to-peak at the gear ({:.1} µrad at the pinion), largest contact pressure {:.0} MPa, max KKT residual {:.1e}",
        summary.positions,
        summary.te_peak_to_peak_arcsec,
        summary.te_peak_to_peak_urad,
        summary.max_pressure_mpa,
        summary.max_kkt,
    );
    // the same per-pair figures as for a spur pair, position by position
    for step in &summary.steps {
        println!(
            "roll {:+.2}°: load shares {:?}",
            step.position.roll_deg, step.load_share
        );
    }
    println!(
        "load sharing per position and pair: {}",
        options.out.join("ltca_positions.csv").display()
    );
    Ok(())
}
