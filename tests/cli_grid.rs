//! `flank grid SCENE`: writes the 9 × 5 measurement grid of the seed 002
//! gear's drive flank, which reads back as a grid lying on that flank; bad
//! arguments are clear errors.

use std::path::Path;
use std::process::Command;

use flank::geometry::gear_pair::Flank;
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
