//! # Cross-code check: the same deck solved by flank and by CalculiX
//!
//! Rung 3 of the verification ladder (DESIGN.md). Each deck is read by flank's
//! deck reader, solved by the native solver, and solved by `ccx` (CalculiX
//! 2.20, Debian package `calculix-ccx`); the displacements of every node must
//! agree: max |u_flank − u_ccx| / max |u_ccx| ≤ 1e-6.
//!
//! The decks exercise what could differ between two correct codes:
//! * distorted elements with **curved** edges (midside nodes off the chords),
//!   where the quadrature rules must be exactly CalculiX's;
//! * pressure (`*DLOAD Pn`) on curved faces, where the face rule shows;
//! * non-zero prescribed displacements, `*CLOAD`, all three element types.
//!
//! `decks/*.inp` are stored decks (written once by flank's writer from
//! distorted meshes, then frozen); the other decks are generated here.
//! ccx prints displacements with 7 significant digits, which bounds the
//! agreement we can observe at about 5e-8.

#[path = "../common/mod.rs"]
mod common;

use std::path::{Path, PathBuf};
use std::time::Instant;

use flank::ccx::{relative_difference, run_ccx};
use flank::deck::{read_deck, write_deck};
use flank::fem::model::{Dirichlet, NodalForce, Pressure};
use flank::fem::static_analysis::{solve_static, SolveOptions};
use flank::mesh::structured::{box_faces, box_mesh, distort_interior, BoxElement};

const TOLERANCE: f64 = 1e-6;

fn compare_deck(name: &str, deck: &Path) {
    let t = Instant::now();
    let parsed = read_deck(deck).unwrap_or_else(|e| panic!("{name}: {e}"));
    let sol = solve_static(
        &parsed.model,
        &SolveOptions {
            recover_stress: false,
            ..Default::default()
        },
    )
    .unwrap_or_else(|e| panic!("{name}: {e}"));
    let t_flank = t.elapsed().as_secs_f64();
    let work = common::scratch_dir(&format!("ccx_{name}"));
    let ccx = run_ccx(deck, &work, 1).unwrap_or_else(|e| panic!("{name}: {e}"));
    assert_eq!(
        ccx.displacements.len(),
        parsed.model.mesh.node_count(),
        "{name}: ccx printed {} nodes, the deck has {}",
        ccx.displacements.len(),
        parsed.model.mesh.node_count()
    );
    let diff =
        relative_difference(&parsed.model.mesh, &sol.displacement, &ccx.displacements).unwrap();
    println!(
        "VERIFY ccx_crosscheck {name:<28} nodes {:>6}  max|du|/max|u| = {diff:.2e}  (tol {TOLERANCE:.0e})  flank {t_flank:.3} s, ccx {:.3} s",
        parsed.model.mesh.node_count(),
        ccx.wall_s
    );
    assert!(
        diff <= TOLERANCE,
        "{name}: flank and ccx differ by {diff:.3e} (relative)"
    );
}

/// A distorted box with curved element edges, pressure on a curved face,
/// a prescribed displacement and a point load.
fn generated_deck(kind: BoxElement, name: &str) -> PathBuf {
    let mut mesh = box_mesh([4.0, 2.0, 1.5], [4, 2, 2], kind);
    // curved edges inside, and a bulged top face so the pressure acts on curved faces
    distort_interior(&mut mesh, 0.15, 7, false);
    flank::mesh::structured::map_nodes(&mut mesh, |p| {
        [
            p[0],
            p[1],
            p[2] + 0.05 * (p[0] * 0.8).sin() * p[2] * (1.0 + 0.3 * p[1]),
        ]
    });
    let top = box_faces(&mesh, "Z1");
    let mut model = common::model_from_mesh(mesh, 210e3, 0.3);
    common::fix_set(&mut model, "X0", &[0, 1, 2], 0.0);
    let x1 = model.mesh.node_sets["X1"].clone();
    for &n in &x1 {
        model.dirichlet.push(Dirichlet {
            node: n,
            component: 0,
            value: 1e-3,
        });
    }
    for (e, f) in top {
        model.pressures.push(Pressure {
            element: e,
            face: f,
            value: 5.0,
        });
    }
    let corner = model.mesh.node_sets["Y0"]
        .iter()
        .copied()
        .find(|&n| x1.contains(&n))
        .unwrap();
    model.forces.push(NodalForce {
        node: corner,
        component: 1,
        value: 200.0,
    });
    let dir = common::scratch_dir(&format!("deck_{name}"));
    let path = dir.join(format!("{name}.inp"));
    write_deck(&model, &path).unwrap();
    path
}

#[test]
fn generated_decks_match_ccx() {
    if !common::ccx_available() {
        return;
    }
    for (kind, name) in [
        (BoxElement::Hex20, "c3d20_curved"),
        (BoxElement::Hex20R, "c3d20r_curved"),
        (BoxElement::Wedge15, "c3d15_curved"),
    ] {
        let deck = generated_deck(kind, name);
        compare_deck(name, &deck);
    }
}

#[test]
fn stored_decks_match_ccx() {
    if !common::ccx_available() {
        return;
    }
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("verification/ccx_crosscheck/decks");
    let mut decks: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "inp"))
        .collect();
    decks.sort();
    assert!(!decks.is_empty(), "no stored decks in {}", dir.display());
    for deck in decks {
        let name = deck.file_stem().unwrap().to_string_lossy().to_string();
        compare_deck(&name, &deck);
    }
}

/// The README's main-job deck (NAFEMS LE10, 31 144 DOFs, pressure on the top
/// face of a curved plate): the same answer in both codes at full size.
#[test]
fn le10_deck_matches_ccx() {
    if !common::ccx_available() {
        return;
    }
    let deck = Path::new(env!("CARGO_MANIFEST_DIR")).join("verification/nafems_le10/le10.inp");
    compare_deck("nafems_le10", &deck);
}
