//! The native gmsh `.msh` 4.1 reader without the gmsh library: the committed
//! fixture (2 hex20 + 4 wedge15 made by gmsh, physical groups) imports into
//! a deck with `flank import`, solves, and agrees with CalculiX; bad files
//! give `file:line` errors; `--mesher gmsh` without the feature says how to
//! get it.

use std::path::{Path, PathBuf};
use std::process::Command;

use flank::ccx::{ccx_executable, relative_difference, run_ccx};
use flank::deck::{read_deck, write_deck};
use flank::fem::material::Material;
use flank::fem::mesh::ElementKind;
use flank::fem::model::{Dirichlet, Model, NodalForce};
use flank::fem::static_analysis::{solve_static, SolveOptions};
use flank::mesh::msh::read_msh;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn tmp(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("msh_reader");
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}

fn flank_cmd(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_flank"))
        .args(args)
        .current_dir(root())
        .output()
        .unwrap()
}

#[test]
fn import_fixture_to_deck() {
    let deck = tmp("blocks.inp");
    let o = flank_cmd(&[
        "import",
        "tests/data/blocks.msh",
        "--out",
        deck.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("2 C3D20 + 4 C3D15"), "{stdout}");
    let m = read_msh(&root().join("tests/data/blocks.msh")).unwrap();
    let d = read_deck(&deck).unwrap();
    assert!(d.warnings.is_empty(), "{:?}", d.warnings);
    let dm = &d.model.mesh;
    assert_eq!(dm.node_count(), m.node_count());
    assert_eq!(dm.elements.len(), m.elements.len());
    for (a, b) in m.elements.iter().zip(&dm.elements) {
        assert_eq!(a.kind, b.kind);
        let la: Vec<u64> = a.nodes.iter().map(|&n| m.node_labels[n]).collect();
        let lb: Vec<u64> = b.nodes.iter().map(|&n| dm.node_labels[n]).collect();
        assert_eq!(la, lb);
    }
    for set in ["BOTTOM", "X0", "EDGE", "CORNER", "PG2_77"] {
        assert_eq!(dm.node_sets[set].len(), m.node_sets[set].len(), "{set}");
    }
    assert_eq!(dm.element_sets["PRISMS"].len(), 4);
    assert_eq!(d.model.materials[0].young, 206000.0);
}

/// The imported mixed hex/wedge mesh as a cantilever: x = 0 clamped, a
/// force on the edge at x = 2; flank solves it, CalculiX agrees.
#[test]
fn imported_mesh_solves_and_matches_ccx() {
    let mesh = read_msh(&root().join("tests/data/blocks.msh")).unwrap();
    let ne = mesh.elements.len();
    let mut model = Model {
        materials: vec![Material::new("steel", 206e3, 0.3).unwrap()],
        element_material: vec![0; ne],
        ..Default::default()
    };
    for &n in &mesh.node_sets["X0"] {
        for component in 0..3 {
            model.dirichlet.push(Dirichlet {
                node: n,
                component,
                value: 0.0,
            });
        }
    }
    for &n in &mesh.node_sets["EDGE"] {
        model.forces.push(NodalForce {
            node: n,
            component: 2,
            value: -100.0,
        });
    }
    let tip = mesh.node_sets["EDGE"][0];
    model.mesh = mesh;
    let sol = solve_static(
        &model,
        &SolveOptions {
            threads: 1,
            recover_stress: false,
            ..Default::default()
        },
    )
    .unwrap();
    assert!(sol.displacement[3 * tip + 2] < 0.0);
    assert!(model
        .mesh
        .elements
        .iter()
        .any(|e| e.kind == ElementKind::C3D15));
    if ccx_executable().is_none() {
        assert!(std::env::var_os("CI").is_none(), "ccx missing on CI");
        return;
    }
    let deck = tmp("blocks_loaded.inp");
    write_deck(&model, &deck).unwrap();
    let ccx = run_ccx(&deck, &tmp("ccx_blocks"), 1).unwrap();
    let rel = relative_difference(&model.mesh, &sol.displacement, &ccx.displacements).unwrap();
    println!("imported blocks: flank vs ccx {rel:.2e}");
    assert!(rel < 1e-6, "{rel}");
}

#[test]
fn import_errors_name_file_and_line() {
    let bad = tmp("bad.msh");
    let text = std::fs::read_to_string(root().join("tests/data/blocks.msh")).unwrap();
    std::fs::write(&bad, text.replacen("4.1 0 8", "2.2 0 8", 1)).unwrap();
    let o = flank_cmd(&["import", bad.to_str().unwrap(), "--out", "/dev/null"]);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("bad.msh:2:") && err.contains("MSH version 2.2"),
        "{err}"
    );
}

#[cfg(not(feature = "gmsh"))]
#[test]
fn mesher_gmsh_without_the_feature_says_how_to_get_it() {
    let o = flank_cmd(&[
        "mesh",
        "papers/seed002-spur/scene.toml",
        "--mesher",
        "gmsh",
        "--out",
        tmp("no_gmsh").to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("--features gmsh") && err.contains("libgmsh-dev"),
        "{err}"
    );
}
