//! Helpers shared by the verification programs (included with `#[path]`).
#![allow(dead_code)]

use flank::fem::material::Material;
use flank::fem::model::{Dirichlet, Model};
use flank::mesh::Mesh;

/// A model with one material on every element.
pub fn model_from_mesh(mesh: Mesh, young: f64, poisson: f64) -> Model {
    let ne = mesh.elements.len();
    Model {
        mesh,
        materials: vec![Material::new("material", young, poisson).expect("valid material")],
        element_material: vec![0; ne],
        ..Default::default()
    }
}

/// Prescribes `value` on components `comps` of every node of node set `set`.
pub fn fix_set(model: &mut Model, set: &str, comps: &[usize], value: f64) {
    let nodes = model
        .mesh
        .node_sets
        .get(set)
        .unwrap_or_else(|| panic!("node set {set}"))
        .clone();
    for n in nodes {
        for &k in comps {
            model.dirichlet.push(Dirichlet {
                node: n,
                component: k,
                value,
            });
        }
    }
}

/// Prints one verification figure in a fixed format (visible with `--nocapture`)
/// and asserts it is within tolerance.
pub fn check(
    case: &str,
    quantity: &str,
    obtained: f64,
    reference: f64,
    tolerance: f64,
    seconds: f64,
) {
    let err = if reference != 0.0 {
        ((obtained - reference) / reference).abs()
    } else {
        obtained.abs()
    };
    println!(
        "VERIFY {case:<16} {quantity:<40} obtained {obtained:>14.7e}  reference {reference:>14.7e}  rel.error {err:>9.2e}  tol {tolerance:>8.1e}  {seconds:>7.3} s"
    );
    assert!(err <= tolerance, "{case}: {quantity}: relative error {err:.3e} above tolerance {tolerance:.1e} (obtained {obtained}, reference {reference})");
}

/// Whether ccx can run here. On CI (env `CI` set) a missing ccx is a failure,
/// elsewhere the cross-code test is skipped with a message.
pub fn ccx_available() -> bool {
    if flank::ccx::ccx_executable().is_some() {
        return true;
    }
    if std::env::var_os("CI").is_some() {
        panic!("ccx not found on CI: .ci/run must install calculix-ccx");
    }
    eprintln!("ccx not found: cross-code comparison skipped (apt-get install calculix-ccx)");
    false
}

/// A scratch directory under the target dir for one case.
pub fn scratch_dir(case: &str) -> std::path::PathBuf {
    let d = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(case);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("scratch dir");
    d
}
