//! `flank mesh`: both paper scenes mesh into two decks each, in hex20 and in
//! wedge15, that flank solves and that CalculiX solves to the same
//! displacements (issue 3 acceptance, on coarse meshes to keep the test short).

use std::path::Path;
use std::process::Command;

use flank::ccx::{ccx_executable, relative_difference, run_ccx};
use flank::deck::read_deck;
use flank::fem::static_analysis::{solve_static, SolveOptions};

#[test]
fn seed002_hex20_bodies_match_ccx() {
    mesh_solve_compare(
        "papers/seed002-spur/scene.toml",
        "hex20",
        "1.0",
        "3.0",
        "C3D20",
    );
}

#[test]
fn seed002_wedge15_bodies_match_ccx() {
    mesh_solve_compare(
        "papers/seed002-spur/scene.toml",
        "wedge15",
        "1.0",
        "3.0",
        "C3D15",
    );
}

#[test]
fn seed004_hex20_bodies_match_ccx() {
    mesh_solve_compare(
        "papers/seed004-helical/scene.toml",
        "hex20",
        "6.0",
        "20.0",
        "C3D20",
    );
}

#[test]
fn seed004_wedge15_bodies_match_ccx() {
    mesh_solve_compare(
        "papers/seed004-helical/scene.toml",
        "wedge15",
        "6.0",
        "20.0",
        "C3D15",
    );
}

/// Meshes `scene` with `flank mesh`, then solves each body's deck (BORE
/// clamped, nominal load on a flank node) in flank and, if present, in ccx.
fn mesh_solve_compare(
    scene: &str,
    element: &str,
    flank_size: &str,
    base_size: &str,
    ccx_type: &str,
) {
    let tag = format!(
        "{}_{element}",
        Path::new(scene)
            .parent()
            .unwrap()
            .file_name()
            .unwrap()
            .to_string_lossy()
    );
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("mesh_{tag}"));
    let _ = std::fs::remove_dir_all(&out);
    let status = Command::new(env!("CARGO_BIN_EXE_flank"))
        .args([
            "mesh",
            scene,
            "--element",
            element,
            "--flank-size",
            flank_size,
            "--base-size",
            base_size,
            "--out",
        ])
        .arg(&out)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    assert!(
        status.status.success(),
        "{}",
        String::from_utf8_lossy(&status.stderr)
    );
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("mesh_report.json")).unwrap())
            .unwrap();
    for body in ["pinion", "gear"] {
        let b = &report["bodies"][body];
        assert!(
            b["min_scaled_jacobian"].as_f64().unwrap() > 0.2,
            "{body}: {b}"
        );
        assert!(b["flank_nodes"].as_u64().unwrap() > 0);
        let by_type = b["elements"].as_object().unwrap();
        assert_eq!(by_type.len(), 1, "{body}: {by_type:?}");
        assert!(
            by_type[ccx_type].as_u64().unwrap() > 0,
            "{body}: {by_type:?}"
        );
        assert!(b["base_radius_mm"].as_f64().unwrap() > 0.0);
        let deck = read_deck(&out.join(format!("{body}.inp"))).unwrap();
        for set in [
            "BORE", "FLANK_L1", "FLANK_R1", "FLANK_L3", "FLANK_R3", "CUT_A", "CUT_B",
        ] {
            assert!(
                deck.model.mesh.node_sets.contains_key(set),
                "{body}: no set {set}"
            );
        }
        let sol = solve_static(
            &deck.model,
            &SolveOptions {
                recover_stress: false,
                ..Default::default()
            },
        )
        .unwrap();
        assert!(sol.stats.backward_error < 1e-14);
        if ccx_executable().is_none() {
            assert!(std::env::var_os("CI").is_none(), "ccx missing on CI");
            continue;
        }
        let ccx = run_ccx(
            &out.join(format!("{body}.inp")),
            &out.join(format!("ccx_{body}")),
            2,
        )
        .unwrap();
        let diff =
            relative_difference(&deck.model.mesh, &sol.displacement, &ccx.displacements).unwrap();
        println!(
            "{tag} {body}: {} nodes, flank vs ccx max|du|/max|u| = {diff:.2e}",
            deck.model.mesh.node_count()
        );
        assert!(
            diff <= 1e-6,
            "{tag} {body}: flank and ccx differ by {diff:.2e}"
        );
    }
}

/// A scene with micro-geometry (tip relief, lead crowning, a measured
/// profile): `flank mesh` applies it to the flank nodes and reports it.
#[test]
fn seed002_with_flank_modifications_meshes_and_solves() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("mesh_seed002_micro");
    let _ = std::fs::remove_dir_all(&out);
    std::fs::create_dir_all(&out).unwrap();
    let csv = root.join("papers/seed002-spur/measured_profile_example.csv");
    let scene = std::fs::read_to_string(root.join("papers/seed002-spur/scene.toml")).unwrap()
        + &format!(
            "\n[pinion.micro]\nmeasured_profile_csv = {csv:?}\nlead_crowning_um = 8.0\n\
             \n[gear.micro]\ntip_relief_um = 15.0\ntip_relief_length_mm = 1.5\n"
        );
    let scene_path = out.join("scene.toml");
    std::fs::write(&scene_path, scene).unwrap();
    let status = Command::new(env!("CARGO_BIN_EXE_flank"))
        .args(["mesh"])
        .arg(&scene_path)
        .args(["--flank-size", "1.0", "--base-size", "3.0", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&status.stderr);
    assert!(status.status.success(), "{stderr}");
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("mesh_report.json")).unwrap())
            .unwrap();
    let p = &report["bodies"]["pinion"]["flank_modification"];
    let g = &report["bodies"]["gear"]["flank_modification"];
    println!("pinion {p}\ngear {g}\n{stderr}");
    // pinion: the example's 5 µm tip relief plus up to 8 µm lead crowning at
    // the face ends; gear: 15 µm tip relief
    let pmax = p["max_offset_mm"].as_f64().unwrap();
    assert!(pmax > 0.008 && pmax <= 0.013 + 1e-6, "{pmax}");
    let gmax = g["max_offset_mm"].as_f64().unwrap();
    assert!((gmax - 0.015).abs() < 1e-9, "{gmax}");
    for body in ["pinion", "gear"] {
        let deck = read_deck(&out.join(format!("{body}.inp"))).unwrap();
        let sol = solve_static(
            &deck.model,
            &SolveOptions {
                recover_stress: false,
                ..Default::default()
            },
        )
        .unwrap();
        assert!(sol.stats.backward_error < 1e-14);
    }
}

/// A hypoid scene: `flank mesh` writes both decks, VTUs, flank parameters
/// and a report whose figures are the decks' (nodes, hex20 elements, the
/// mount, the nominal load's moment = the member's torque); flank solves
/// the decks.
#[test]
fn seed003_hypoid_bodies_mesh_and_solve() {
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli_mesh_seed003");
    let _ = std::fs::remove_dir_all(&out);
    let status = Command::new(env!("CARGO_BIN_EXE_flank"))
        .args([
            "mesh",
            "papers/seed003-hypoid/scene.toml",
            "--flank-size",
            "1.5",
            "--base-size",
            "6",
            "--out",
        ])
        .arg(&out)
        .status()
        .unwrap();
    assert!(status.success());
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("mesh_report.json")).unwrap())
            .unwrap();
    assert_eq!(report["pair"]["kind"], "hypoid");
    // pinion torque 268.29 N·m, gear torque × 41/11
    for (name, torque) in [("pinion", 268.29e3), ("gear", 268.29e3 * 41.0 / 11.0)] {
        let body = &report["bodies"][name];
        let deck = read_deck(&out.join(format!("{name}.inp"))).unwrap();
        let mesh = &deck.model.mesh;
        assert_eq!(body["nodes"].as_u64().unwrap() as usize, mesh.node_count());
        assert_eq!(
            body["elements"]["C3D20"].as_u64().unwrap() as usize,
            mesh.elements.len()
        );
        assert!(body["min_scaled_jacobian"].as_f64().unwrap() > 0.2);
        let mount = if name == "pinion" { "bore" } else { "plane" };
        assert!(
            body["mount"].get(mount).is_some(),
            "{name}: {}",
            body["mount"]
        );
        // the nominal load's moment about the member's axis is its torque
        let load = &body["nominal_load"];
        let label = load["node"].as_u64().unwrap();
        let n = mesh.node_labels.iter().position(|&l| l == label).unwrap();
        let (x, f) = (mesh.coords[n], &load["force_n"]);
        let moment = x[0] * f[1].as_f64().unwrap() - x[1] * f[0].as_f64().unwrap();
        assert!(
            (moment.abs() - torque).abs() < 1e-6 * torque,
            "{name}: {moment}"
        );
        assert!(out.join(format!("{name}.vtu")).exists());
        assert!(out.join(format!("{name}_flank_uv.csv")).exists());
        let sol = solve_static(
            &deck.model,
            &SolveOptions {
                recover_stress: false,
                ..Default::default()
            },
        )
        .unwrap();
        assert!(sol.displacement.iter().all(|u| u.is_finite()));
    }
}
