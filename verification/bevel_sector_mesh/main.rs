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
//! the ccx cross-check of the other decks. The coarse seed 003 pinion with
//! a shank (30 mm diameter, 40 mm long), held at its bearing seat, is
//! checked the same way. Seed 003's members in wedge15 against hex20
//! (nodes, quality, the ring gear's tip deflection under the same load).

#[path = "../common/mod.rs"]
mod common;

use std::path::Path;
use std::time::Instant;

use flank::ccx::relative_difference;
use flank::deck::{read_deck, write_deck};
use flank::fem::static_analysis::{solve_static, SolveOptions};
use flank::mesh::bevel_body::bevel_body_model;
use flank::mesh::bevel_sector::{bevel_sector, flank_edge_deviation, BevelSectorOptions, Shank};
use flank::scene::{read_scene, Scene};

/// The bevel gears of a scene this case reads.
fn gears(s: &Scene) -> &flank::scene::BevelGears {
    s.bevel("this case").unwrap()
}

fn scene(seed: &str) -> Scene {
    let path = format!("{}/papers/{seed}/scene.toml", env!("CARGO_MANIFEST_DIR"));
    read_scene(Path::new(&path)).unwrap()
}

/// The mesh table of the README: every hypoid member that meshes, at two
/// flank sizes (base size 4 × flank size).
#[test]
fn hypoid_members_mesh_validly() {
    println!("| seed | member | flank size | nodes | elements | min scaled Jacobian | max aspect | flank edge deviation (mm) | mount | time (s) |");
    println!("|---|---|---|---|---|---|---|---|---|---|");
    for seed in ["seed003-hypoid", "seed001-hypoid", "seed000-hypoid"] {
        let sc = scene(seed);
        for (m, gear) in gears(&sc).bodies.iter().enumerate() {
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
    deck_matches_ccx(1, None, 1.0, true);
}

/// The same ring gear in wedge15 (C3D15 node order and faces as written
/// in the deck): flank and ccx agree.
#[test]
fn seed003_gear_wedge15_deck_matches_ccx() {
    deck_matches_ccx_in(1, None, 1.0, true, flank::fem::mesh::ElementKind::C3D15);
}

/// The seed 003 pinion with a shank (30 mm × 40 mm), clamped at its
/// bearing seat, as a deck at 2 mm (ccx needs 130 s at 1 mm, whose figure
/// the README gives): flank and ccx agree; beside it the load point's
/// displacement without the shank (clamped at the bore; flank only).
#[test]
fn seed003_pinion_with_shank_deck_matches_ccx() {
    let plain = deck_matches_ccx(0, None, 2.0, false);
    let shank = deck_matches_ccx(
        0,
        Some(Shank {
            length: 40.0,
            diameter: 30.0,
        }),
        2.0,
        true,
    );
    println!(
        "pinion load point along the force: {plain:.4e} mm held at the bore, {shank:.4e} mm held at the shank's bearing seat (×{:.2})",
        shank / plain
    );
    assert!(shank > plain, "{shank} {plain}");
}

/// Member `m` of seed 003 at flank size `fs` (base 4 fs; with `shank`),
/// loaded at the drive flank's mean point: the deck solved by flank and
/// (with `ccx`, when installed) by ccx agree to 1e-6; returns the load
/// point's displacement along the load.
fn deck_matches_ccx(m: usize, shank: Option<Shank>, fs: f64, ccx: bool) -> f64 {
    deck_matches_ccx_in(m, shank, fs, ccx, flank::fem::mesh::ElementKind::C3D20)
}

/// [`deck_matches_ccx`] in elements of `element`.
fn deck_matches_ccx_in(
    m: usize,
    shank: Option<Shank>,
    fs: f64,
    ccx: bool,
    element: flank::fem::mesh::ElementKind,
) -> f64 {
    let sc = scene("seed003-hypoid");
    let opts = BevelSectorOptions {
        flank_size: fs,
        base_size: 4.0 * fs,
        shank,
        element,
        ..Default::default()
    };
    let torque = sc.load.torque_nmm * [1.0, gears(&sc).blank.z2 / gears(&sc).blank.z1][m];
    let name = ["pinion", "gear"][m];
    let material = [&sc.pinion_material, &sc.gear_material][m];
    let body =
        bevel_body_model(&gears(&sc).bodies[m], name, material, &opts, Some(torque)).unwrap();
    if let Some(sh) = body.sector.shank {
        println!(
            "{name} with shank: {} nodes, min scaled Jacobian {:.3}, max aspect {:.1}; {sh:?}",
            body.model.mesh.node_count(),
            body.sector.quality.min_scaled_jacobian,
            body.sector.quality.max_aspect_ratio
        );
    }
    let tag = match (shank.is_some(), element) {
        (true, _) => "_shank",
        (false, flank::fem::mesh::ElementKind::C3D15) => "_wedge15",
        _ => "",
    };
    // one folder per deck: the tests run in parallel, and a shared scratch
    // folder was emptied under a running ccx ("cannot open frd file")
    let work = common::scratch_dir(&format!("bevel_sector_mesh/{name}{tag}"));
    let deck = work.join(format!("{name}{tag}.inp"));
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
        "{name}{tag} deck: {} nodes, {} dofs; load {fnorm:.1} N at the drive flank's mean point, displacement along it {along:.4e} mm; flank {t_flank:.2} s",
        parsed.model.mesh.node_count(),
        sol.stats.dofs
    );
    assert!(along > 0.0);
    if !(ccx && common::ccx_available()) {
        return along;
    }
    let ccx = common::run_ccx(&deck, &work.join(format!("ccx_{name}{tag}")));
    let diff =
        relative_difference(&parsed.model.mesh, &sol.displacement, &ccx.displacements).unwrap();
    println!(
        "VERIFY bevel_sector_mesh seed003 {name}{tag} deck: max|du|/max|u| = {diff:.2e} (tol 1e-6); flank {t_flank:.2} s, ccx {:.2} s",
        ccx.wall_s
    );
    assert!(diff <= 1e-6, "{diff}");
    along
}

/// Hex20 against wedge15 (README section "Wedge15"): seed 003's pinion
/// and ring gear at 1 and 0.5 mm (base 4 × flank size): nodes, DOFs,
/// quality, meshing time; the ring gear clamped at its mounting plane
/// under the nominal load, solved in both: the tip-land node nearest the
/// load moves along the force within 3 % alike (the unit test's bound,
/// set before the runs). CI: 1 mm; `--ignored`: 0.5 mm (two 400 k-DOF
/// solves, over a minute each on the 2-core machine).
#[test]
fn seed003_wedge15_against_hex20() {
    wedge15_against_hex20(&[1.0]);
}

/// [`seed003_wedge15_against_hex20`] at 0.5 mm.
#[test]
#[ignore = "two 400 k-DOF solves of the ring gear (about 2 min on 2 cores)"]
fn seed003_wedge15_against_hex20_fine() {
    wedge15_against_hex20(&[0.5]);
}

fn wedge15_against_hex20(sizes: &[f64]) {
    use flank::fem::mesh::ElementKind;
    let sc = scene("seed003-hypoid");
    println!("| member | flank size (mm) | element | nodes | DOFs | elements | min scaled Jacobian | max aspect | meshing (s) | tip along the force (mm) | solve (s) |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    for &fs in sizes {
        for m in 0..2 {
            let mut tips = Vec::new();
            for element in [ElementKind::C3D20, ElementKind::C3D15] {
                let opts = BevelSectorOptions {
                    flank_size: fs,
                    base_size: 4.0 * fs,
                    element,
                    ..Default::default()
                };
                let name = ["pinion", "gear"][m];
                let t = Instant::now();
                let r = bevel_sector(&gears(&sc).bodies[m], name, &opts).unwrap();
                let t_mesh = t.elapsed().as_secs_f64();
                assert!(r.quality.min_scaled_jacobian > 0.2, "{:?}", r.quality);
                let (mut tip, mut t_solve) = (String::from("—"), String::from("—"));
                if m == 1 {
                    let body = bevel_body_model(
                        &gears(&sc).bodies[1],
                        name,
                        &sc.gear_material,
                        &opts,
                        Some(sc.load.torque_nmm * gears(&sc).blank.z2 / gears(&sc).blank.z1),
                    )
                    .unwrap();
                    let (node, f) = body.load.unwrap();
                    let mesh = &body.model.mesh;
                    let x = mesh.coords[node];
                    let dist = |n: usize| {
                        let y = mesh.coords[n];
                        (0..3).map(|c| (y[c] - x[c]).powi(2)).sum::<f64>()
                    };
                    let tn = mesh.node_sets["TIP_LAND"]
                        .iter()
                        .copied()
                        .min_by(|&a, &b| dist(a).total_cmp(&dist(b)))
                        .unwrap();
                    let t = Instant::now();
                    let sol = solve_static(
                        &body.model,
                        &SolveOptions {
                            recover_stress: false,
                            ..Default::default()
                        },
                    )
                    .unwrap();
                    t_solve = format!("{:.1}", t.elapsed().as_secs_f64());
                    let fnorm = f.iter().map(|c| c * c).sum::<f64>().sqrt();
                    let d = &sol.displacement[3 * tn..3 * tn + 3];
                    let along = (d[0] * f[0] + d[1] * f[1] + d[2] * f[2]) / fnorm;
                    tips.push(along);
                    tip = format!("{along:.4e}");
                }
                println!(
                    "| {} | {fs} | {} | {} | {} | {} | {:.3} | {:.1} | {t_mesh:.2} | {tip} | {t_solve} |",
                    ["pinion", "gear"][m],
                    element.name(),
                    r.mesh.node_count(),
                    3 * r.mesh.node_count(),
                    r.mesh.elements.len(),
                    r.quality.min_scaled_jacobian,
                    r.quality.max_aspect_ratio
                );
            }
            if let [h, w] = tips[..] {
                let rel = (w - h).abs() / h.abs();
                println!(
                    "VERIFY bevel_sector_mesh seed003 gear {fs} mm: tip displacement wedge15 vs hex20 {:.2} % (tol 3 %)",
                    100.0 * rel
                );
                assert!(rel < 0.03, "{h} {w}");
            }
        }
    }
}
