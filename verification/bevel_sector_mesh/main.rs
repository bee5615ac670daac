//! # Bevel/hypoid sector meshes: validity, exact flanks, and the same deck in flank and CalculiX
//!
//! Issue 18 point 1 (see README.md beside this file). For the hypoid
//! scenes of seeds 003, 001 and 000 the native bevel sector mesher
//! (`flank::mesh::bevel_sector`) meshes both members (3 teeth, hex20):
//! every element Jacobian-checked, the flank nodes on the generated
//! surfaces, the quadratic flank edges' deviation from the surface
//! measured by closest point; then the coarse seed 003 ring gear, clamped
//! at its mounting plane and loaded at the drive flank's mean point, is
//! written as a deck and solved by flank and by ccx: the displacements of
//! every node must agree to 1e-6 (relative to the largest), the figure of
//! the ccx cross-check of the other decks.

#[path = "../common/mod.rs"]
mod common;

use std::path::Path;
use std::time::Instant;

use flank::ccx::relative_difference;
use flank::fem::static_analysis::{solve_static, SolveOptions};
use flank::mesh::bevel_body::bevel_body_model;
use flank::mesh::bevel_sector::{bevel_sector, flank_edge_deviation, BevelSectorOptions};
use flank::mesh::inp::{read_deck, write_deck};
use flank::scene::{read_any_scene, AnyScene, BevelScene};

fn scene(seed: &str) -> BevelScene {
    let path = format!("{}/papers/{seed}/scene.toml", env!("CARGO_MANIFEST_DIR"));
    match read_any_scene(Path::new(&path)).unwrap() {
        AnyScene::Bevel(b) => b,
        _ => panic!("{seed} is not a bevel scene"),
    }
}

/// The mesh table of the README: every hypoid member that meshes, at two
/// flank sizes (base size 4 × flank size).
#[test]
fn hypoid_members_mesh_validly() {
    println!("| seed | member | flank size | nodes | elements | min scaled Jacobian | max aspect | flank edge deviation (mm) | mount | time (s) |");
    println!("|---|---|---|---|---|---|---|---|---|---|");
    for seed in ["seed003-hypoid", "seed001-hypoid", "seed000-hypoid"] {
        let sc = scene(seed);
        for (m, gear) in sc.bodies.iter().enumerate() {
            for fs in [1.0, 0.5] {
                let opts = BevelSectorOptions {
                    flank_size: fs,
                    base_size: 4.0 * fs,
                    ..Default::default()
                };
                let t = Instant::now();
                let r = match bevel_sector(gear, ["pinion", "gear"][m], &opts) {
                    Ok(r) => r,
                    Err(e) => {
                        println!(
                            "| {seed} | {} | {fs} | refused: {e} |",
                            ["pinion", "gear"][m]
                        );
                        // only seed 000's face-hobbed pinion is known to be refused
                        assert!(seed == "seed000-hypoid" && m == 0, "{seed} {m}: {e}");
                        assert!(e.to_string().contains("no gap land"), "{e}");
                        continue;
                    }
                };
                let time = t.elapsed().as_secs_f64();
                let dev = flank_edge_deviation(gear, &r);
                let dev = dev[0].max(dev[1]);
                println!(
                    "| {seed} | {} | {fs} | {} | {} | {:.3} | {:.1} | {dev:.2e} | {:?} | {time:.2} |",
                    ["pinion", "gear"][m],
                    r.mesh.node_count(),
                    r.mesh.elements.len(),
                    r.quality.min_scaled_jacobian,
                    r.quality.max_aspect_ratio,
                    r.mount
                );
                assert!(r.quality.min_scaled_jacobian > 0.2, "{:?}", r.quality);
                // quadratic edges: at most 1 % of the flank size off the flank
                assert!(dev < 0.01 * fs, "{seed} {m} {fs}: {dev}");
            }
        }
    }
}

/// The coarse seed 003 ring gear as a deck: flank and ccx agree.
#[test]
fn seed003_gear_deck_matches_ccx() {
    let sc = scene("seed003-hypoid");
    let opts = BevelSectorOptions {
        flank_size: 1.0,
        base_size: 4.0,
        ..Default::default()
    };
    let torque = sc.load.torque_nmm * sc.blank.z2 / sc.blank.z1;
    let body = bevel_body_model(
        &sc.bodies[1],
        "gear",
        &sc.gear_material,
        &opts,
        Some(torque),
    )
    .unwrap();
    let work = common::scratch_dir("bevel_sector_mesh");
    let deck = work.join("gear.inp");
    write_deck(&body.model, &deck).unwrap();
    let parsed = read_deck(&deck).unwrap();
    let t = Instant::now();
    let sol = solve_static(
        &parsed.model,
        &SolveOptions {
            recover_stress: false,
            ..Default::default()
        },
    )
    .unwrap();
    let t_flank = t.elapsed().as_secs_f64();
    let (node, f) = body.load.unwrap();
    let d = &sol.displacement[3 * node..3 * node + 3];
    let fnorm = f.iter().map(|x| x * x).sum::<f64>().sqrt();
    let along = (d[0] * f[0] + d[1] * f[1] + d[2] * f[2]) / fnorm;
    println!(
        "gear deck: {} nodes, {} dofs; load {fnorm:.1} N at the drive flank's mean point, displacement along it {along:.4e} mm; flank {t_flank:.2} s",
        parsed.model.mesh.node_count(),
        sol.stats.dofs
    );
    assert!(along > 0.0);
    if !common::ccx_available() {
        return;
    }
    let ccx = common::run_ccx(&deck, &work.join("ccx"));
    let diff =
        relative_difference(&parsed.model.mesh, &sol.displacement, &ccx.displacements).unwrap();
    println!(
        "VERIFY bevel_sector_mesh seed003 gear deck: max|du|/max|u| = {diff:.2e} (tol 1e-6); flank {t_flank:.2} s, ccx {:.2} s",
        ccx.wall_s
    );
    assert!(diff <= 1e-6, "{diff}");
}
