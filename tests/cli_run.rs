//! `flank run SCENE.toml`: the FE contact mesh cycle from the command line
//! (seed 002 scene on a coarse mesh at two roll angles), its files and
//! summary keys; a scene without `[analyses] contact` and a bad option are
//! clear errors.

use std::process::Command;

fn flank(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_flank"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into(),
        String::from_utf8_lossy(&out.stderr).into(),
    )
}

#[test]
fn run_writes_the_mesh_cycle_files() {
    let dir = std::env::temp_dir().join(format!("flank_cli_run_{}", std::process::id()));
    let d = dir.to_str().unwrap();
    let (ok, out, err) = flank(&[
        "run",
        "papers/seed002-spur/scene.toml",
        "--flank-size",
        "1.5",
        "--base-size",
        "3",
        "--roll-angles=-6,6",
        "--decks",
        "--out",
        d,
    ]);
    assert!(ok, "{err}");
    assert!(out.contains("single-pair force"), "{out}");
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    for key in [
        "contact_ratio",
        "single_pair_force_n",
        "positions",
        "time_per_position_s",
        "nodes",
    ] {
        assert!(s.get(key).is_some(), "summary.json lacks {key}");
    }
    assert_eq!(s["positions"].as_u64(), Some(2));
    // two positions cannot bracket the engagement: no contact ratio, said so
    assert!(s["contact_ratio"].is_null());
    assert!(s["notes"]
        .as_array()
        .unwrap()
        .iter()
        .any(|n| n.as_str().unwrap().contains("contact ratio not measured")));
    let f = s["single_pair_force_n"].as_f64().unwrap();
    let nominal = s["nominal_force_n"].as_f64().unwrap();
    assert!((f / nominal - 1.0).abs() < 0.03, "{f} vs {nominal}");
    for file in [
        "mesh_cycle.csv",
        "force_per_tooth.svg",
        "transmission_error.png",
        "roll_-006.000deg.vtu",
        "roll_+006.000deg.vtu",
        "roll_+006.000deg.inp",
    ] {
        assert!(dir.join(file).exists(), "{file} missing");
    }
    // the position deck reads back with its coupling and three contact pairs
    let deck = flank::mesh::inp::read_deck(&dir.join("roll_+006.000deg.inp")).unwrap();
    assert_eq!(deck.model.couplings.len(), 1);
    assert_eq!(deck.model.contact.pairs.len(), 3);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn run_needs_a_contact_analysis_and_valid_options() {
    let dir = std::env::temp_dir().join(format!("flank_cli_run_bad_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/papers/seed002-spur/scene.toml"
    ))
    .unwrap();
    let no_contact = dir.join("no_contact.toml");
    std::fs::write(
        &no_contact,
        scene
            .lines()
            .filter(|l| !l.starts_with("contact ="))
            .collect::<Vec<_>>()
            .join("\n"),
    )
    .unwrap();
    let (ok, _, err) = flank(&[
        "run",
        no_contact.to_str().unwrap(),
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(!ok);
    assert!(err.contains("contact = {}"), "{err}");
    let (ok, _, err) = flank(&[
        "run",
        "papers/seed002-spur/scene.toml",
        "--penalty-factor=-1",
        "--law",
        "penalty",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(!ok);
    assert!(err.contains("penalty factor"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}
