//! FE contact over three roll angles of seed 002's spur pair (the
//! reference the LTCA is checked against), through the library: both
//! bodies meshed once (coarse: 1 mm flank elements), factorized once, and
//! the contact problem solved at each roll angle.
//!
//! Run: `cargo run --release --example fe_mesh_cycle`
//! (writes `out/example_fe_mesh_cycle/`: `mesh_cycle.csv` holds the force,
//! share and p_max per tooth pair and roll angle, the TE in µrad;
//! `summary.json`, one VTU file per roll angle).

use std::path::Path;

use flank::api::{fe_mesh_cycle, load_scene, BodyMeshOptions, FeOptions};

fn main() -> anyhow::Result<()> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let scene = load_scene(root.join("papers/seed002-spur/scene.toml"))?;
    let options = FeOptions {
        out: root.join("out/example_fe_mesh_cycle"),
        mesh: BodyMeshOptions {
            flank_size: Some(1.0),
            base_size: Some(4.0),
            ..Default::default()
        },
        roll_angles_deg: Some(vec![-5.0, 0.0, 5.0]),
        // contact law, slave, friction: the scene's [analyses.contact], else the defaults
        ..Default::default()
    };
    let summary = fe_mesh_cycle(&scene, &options)?;
    println!(
        "{} positions, {} DOFs, factorization {:.2} s once, {:.2} s per position; TE peak-to-peak {:.2} µrad",
        summary.positions,
        summary.dofs,
        summary.factorization_s,
        summary.time_per_position_s,
        summary.te_peak_to_peak_urad,
    );
    println!(
        "force and share per pair: {}",
        options.out.join("mesh_cycle.csv").display()
    );
    Ok(())
}
