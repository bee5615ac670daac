//! `flank grid SCENE`: writes the 9 × 5 measurement grid of the seed 002
//! gear's drive flank and of every flank of the hypoid seeds' members,
//! which read back as grids lying on those flanks; bad arguments are clear
//! errors.

use std::path::Path;
use std::process::Command;

use flank::geometry::gear_pair::{Flank, GearBody};
use flank::geometry::measurement_grid::MeasurementGrid;

fn flank_grid(args: &[&str]) -> (bool, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_flank"))
        .arg("grid")
        .args(args)
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stderr).into(),
    )
}

#[test]
fn grid_of_the_seed002_gear() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let scene = root.join("papers/seed002-spur/scene.toml");
    let dir = std::env::temp_dir().join(format!("flank_cli_grid_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("gear.csv");
    let (ok, err) = flank_grid(&[
        scene.to_str().unwrap(),
        "--member",
        "gear",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let grid = MeasurementGrid::read(&out).unwrap();
    assert_eq!((grid.face_points, grid.profile_points), (9, 5));
    let pair = flank::scene::read_scene(&scene)
        .unwrap()
        .gear_pair()
        .unwrap();
    let surface = pair.body(1).flank(Flank::Right, 1).unwrap();
    grid.check_against(surface, 1e-6).unwrap();
    // The pinion's flank is another surface: its grid does not fit the gear.
    let other = dir.join("pinion.csv");
    let (ok, err) = flank_grid(&[
        scene.to_str().unwrap(),
        "--member",
        "pinion",
        "--points",
        "7x4",
        "--out",
        other.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let pg = MeasurementGrid::read(&other).unwrap();
    assert_eq!((pg.face_points, pg.profile_points), (7, 4));
    assert!(pg.check_against(surface, 1e-3).is_err());

    let (ok, err) = flank_grid(&[scene.to_str().unwrap(), "--points", "9-5", "--out", "x.csv"]);
    assert!(!ok && err.contains("--points '9-5'"), "{err}");
    let (ok, err) = flank_grid(&[scene.to_str().unwrap(), "--tooth", "9", "--out", "x.csv"]);
    assert!(!ok && err.contains("--tooth 9"), "{err}");
    let (ok, err) = flank_grid(&[scene.to_str().unwrap(), "--inset", "0.7", "--out", "x.csv"]);
    assert!(!ok && err.contains("--inset 0.7"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

/// Every flank of both members of the face-milled (seed 003) and the
/// face-hobbed (seed 000) hypoid scenes: the grid reads back and lies on
/// the flank the scene cuts (≤ 1e-6 mm); the drive grid is not the coast
/// flank.
#[test]
fn grids_of_the_hypoid_seeds() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = std::env::temp_dir().join(format!("flank_cli_grid_hypoid_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for seed in ["seed003-hypoid", "seed000-hypoid"] {
        let scene = root.join("papers").join(seed).join("scene.toml");
        let scene_read = flank::scene::read_scene(&scene).unwrap();
        let s = scene_read.bevel("this test").unwrap();
        for (b, member) in ["pinion", "gear"].into_iter().enumerate() {
            for (side, name) in [(Flank::Left, "left"), (Flank::Right, "right")] {
                let out = dir.join(format!("{seed}_{member}_{name}.csv"));
                let (ok, err) = flank_grid(&[
                    scene.to_str().unwrap(),
                    "--member",
                    member,
                    "--flank",
                    name,
                    "--out",
                    out.to_str().unwrap(),
                ]);
                assert!(ok, "{seed} {member} {name}: {err}");
                let grid = MeasurementGrid::read(&out).unwrap();
                assert_eq!((grid.face_points, grid.profile_points), (9, 5));
                let body = &s.bodies[b];
                grid.check_against(body.flank(side, 1).unwrap(), 1e-6)
                    .unwrap_or_else(|e| panic!("{seed} {member} {name}: {e}"));
                let other = if side == Flank::Left {
                    Flank::Right
                } else {
                    Flank::Left
                };
                assert!(grid
                    .check_against(body.flank(other, 1).unwrap(), 1e-3)
                    .is_err());
            }
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// `--ease-off` on a conjugate pinion (seed 003's gear, 10 µm profile and
/// 20 µm lengthwise crowning): the grid's deviations are the ease-off read
/// back against the conjugate flank, equal to the specified ease-off at
/// every node to 0.01 µm (issue 16 point 8), material removed everywhere;
/// `--ease-off` on a machined member is an error.
#[test]
fn ease_off_grid_of_a_conjugate_pinion() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = std::env::temp_dir().join(format!("flank_cli_grid_ease_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let base = std::fs::read_to_string(root.join("papers/seed003-hypoid/scene.toml")).unwrap();
    let text = base.replacen("[pinion]\n", "[pinion]\nprocess = \"conjugate\"\n", 1).replacen(
        "\n[gear]\n",
        "\n[pinion.ease_off]\nprofile_crowning_um = 10.0\nlengthwise_crowning_um = 20.0\n\n[gear]\n",
        1,
    );
    let scene = dir.join("conjugate.toml");
    std::fs::write(&scene, text).unwrap();
    let parsed = flank::scene::read_scene(&scene).unwrap();
    let eased = parsed
        .bevel("this test")
        .unwrap()
        .pinion_eased
        .clone()
        .expect("eased pinion");
    for side in ["left", "right"] {
        let out = dir.join(format!("ease_{side}.csv"));
        let (ok, err) = flank_grid(&[
            scene.to_str().unwrap(),
            "--member",
            "pinion",
            "--flank",
            side,
            "--ease-off",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(ok, "{side}: {err}");
        let grid = MeasurementGrid::read(&out).unwrap();
        let e = &eased[if side == "right" { 0 } else { 1 }];
        let mut worst: f64 = 0.0;
        for p in &grid.points {
            let specified = e.ease_off(p.u, p.v).unwrap().e;
            assert!(
                p.deviation <= 1e-9,
                "{side}: material added at ({}, {})",
                p.u,
                p.v
            );
            worst = worst.max((p.deviation + specified).abs());
        }
        // the CSV keeps 6 decimals of µm
        assert!(
            1e3 * worst <= 0.01,
            "{side}: read back vs specified {:.2e} µm",
            1e3 * worst
        );
    }
    let (ok, err) = flank_grid(&[
        root.join("papers/seed003-hypoid/scene.toml")
            .to_str()
            .unwrap(),
        "--member",
        "pinion",
        "--ease-off",
        "--out",
        dir.join("x.csv").to_str().unwrap(),
    ]);
    assert!(
        !ok && err.contains("--ease-off") && !err.contains("panicked"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).ok();
}
