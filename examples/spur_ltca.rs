//! The compliance-matrix LTCA of seed 002's spur pair over a mesh cycle,
//! through the library: read the scene, set the options the command line
//! would, run, and read the load sharing and the loaded TE from the
//! summary. Coarse compliance meshes (1 mm flank, 4 mm base elements), so
//! it runs in seconds; `flank ltca` with the scene's sizes is the analysis.
//!
//! Run: `cargo run --release --example spur_ltca`
//! (writes `out/example_spur_ltca/`: `ltca_cycle.csv` holds the force and
//! share per tooth pair and roll angle, the TE in µrad; `summary.json`).

use std::path::Path;

use flank::api::{load_scene, ltca, BodyMeshOptions, KindSummary, LtcaOptions};

fn main() -> anyhow::Result<()> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let scene = load_scene(root.join("papers/seed002-spur/scene.toml"))?;
    let options = LtcaOptions {
        out: root.join("out/example_spur_ltca"),
        mesh: BodyMeshOptions {
            flank_size: Some(1.0),
            base_size: Some(4.0),
            ..Default::default()
        },
        // every other option: the scene's [analyses.ltca], else the default
        ..Default::default()
    };
    let result = ltca(&scene, &options)?;
    let summary = result.first();
    let KindSummary::Cylindrical(spur) = &summary.kind else {
        anyhow::bail!("a spur scene gives a cylindrical summary");
    };
    let or_nan = |x: Option<f64>| x.unwrap_or(f64::NAN);
    println!(
        "{} positions: contact ratio {:.3} (kinematic {:.3}), single-pair force {:.1} N ({:+.2} % from T/r_b), loaded TE {:.2} µrad peak-to-peak, max KKT residual {:.1e}",
        summary.positions,
        or_nan(spur.contact_ratio),
        spur.contact_ratio_kinematic,
        or_nan(spur.single_pair_force_n),
        100.0 * or_nan(spur.single_pair_force_error),
        summary.te_peak_to_peak_urad,
        summary.max_kkt,
    );
    println!(
        "load sharing and TE per roll angle: {}",
        options.out.join("ltca_cycle.csv").display()
    );
    Ok(())
}
