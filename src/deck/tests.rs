//! Tests of the reader as a whole (a deck with every keyword, warnings and
//! refused keywords) and a timing on a large deck.

use std::fmt::Write as _;

use super::test_decks::*;
use super::*;
use crate::fem::mesh::ElementKind;
use crate::fem::model::{NodalForce, Pressure};

#[test]
fn hex_deck_with_all_keywords() {
    let deck = parse(HEX).unwrap();
    assert_eq!(deck.title.as_deref(), Some("One hexahedron"));
    let m = &deck.model;
    let mesh = &m.mesh;
    assert_eq!(mesh.node_count(), 20);
    assert_eq!(mesh.coords[mesh.node(3).unwrap()], [1.0, 1.0, 0.0]);
    assert_eq!(mesh.coords[mesh.node(4).unwrap()], [0.0, 1.0, 0.0]);
    assert_eq!(mesh.coords[mesh.node(20).unwrap()], [0.0, 1.0, 0.5]);
    assert_eq!(mesh.elements.len(), 1);
    assert_eq!(mesh.elements[0].kind, ElementKind::C3D20);
    assert_eq!(mesh.elements[0].nodes, (0..20).collect::<Vec<_>>());

    let bottom = idx(mesh, &[1, 2, 3, 4, 9, 10, 11, 12]);
    let top = idx(mesh, &[5, 6, 7, 8, 13, 14, 15, 16]);
    assert_eq!(mesh.node_sets["BOTTOM"], bottom);
    assert_eq!(mesh.node_sets["TOP"], top);
    assert_eq!(mesh.node_sets["BOTH"].len(), 16);
    assert_eq!(mesh.node_sets["NALL"].len(), 20);
    assert_eq!(mesh.element_sets["BLOCK"], vec![0]);
    assert_eq!(mesh.element_sets["E1"], vec![0]);
    assert_eq!(mesh.element_sets["EALL"], vec![0]);

    assert_eq!(m.materials.len(), 1);
    assert_eq!(m.materials[0].name, "STEEL");
    assert_eq!(m.materials[0].young, 210000.0);
    assert_eq!(m.materials[0].poisson, 0.3);
    assert_eq!(m.element_material, vec![0]);

    // 8 bottom nodes x 3 (node 1/x repeated: deduplicated) + 8 top z.
    assert_eq!(m.dirichlet.len(), 32);
    let bc = |label: u64, c: usize| {
        let n = mesh.node(label).unwrap();
        let v: Vec<f64> = m
            .dirichlet
            .iter()
            .filter(|d| d.node == n && d.component == c)
            .map(|d| d.value)
            .collect();
        assert_eq!(v.len(), 1, "node {label} comp {c}");
        v[0]
    };
    assert_eq!(bc(1, 0), 0.0);
    assert_eq!(bc(12, 2), 0.0);
    assert_eq!(bc(5, 2), -0.01);
    assert_eq!(bc(16, 2), -0.01);

    let n7 = mesh.node(7).unwrap();
    assert_eq!(
        m.forces,
        vec![
            NodalForce {
                node: n7,
                component: 0,
                value: 100.5
            },
            NodalForce {
                node: n7,
                component: 0,
                value: 15.0
            },
        ]
    );
    assert_eq!(
        m.pressures,
        vec![Pressure {
            element: 0,
            face: 2,
            value: 5.0
        }]
    );
    // *DENSITY is read now (body loads), no longer warned about
    assert!(deck.warnings.is_empty(), "{:?}", deck.warnings);
    assert_eq!(m.materials[0].density, Some(7.85e-9));
}

#[test]
fn unknown_keyword_is_a_warning() {
    let d = with(HEX, "*STEP\n", "*FOOBAR, X=1\nsome, data\n*STEP\n");
    let deck = parse(&d).unwrap();
    let w = deck
        .warnings
        .iter()
        .find(|w| w.message.contains("FOOBAR"))
        .expect("warning");
    assert_eq!(w.line, line_of(&d, "*FOOBAR"));
}

#[test]
fn answer_changing_keywords_are_errors() {
    let d = with(HEX, "*STEP\n", "*MPC\nBEAM, 1, 2\n*STEP\n");
    expect_err(&d, line_of(&d, "*MPC"), "multi-point constraints");
    let d = with(HEX, "*ELASTIC", "*ELASTIC, TYPE=ORTHO");
    expect_err(&d, line_of(&d, "TYPE=ORTHO"), "ORTHO");
    let d = with(HEX, "*DENSITY\n7.85e-9", "*PLASTIC\n500., 0.");
    expect_err(&d, line_of(&d, "*PLASTIC"), "PLASTIC");
    let d = with(
        HEX,
        "*CLOAD\n7, 1, 100.5",
        "*CLOAD, AMPLITUDE=A1\n7, 1, 100.5",
    );
    expect_err(&d, line_of(&d, "AMPLITUDE"), "AMPLITUDE");
}

/// Timing on a large structured deck (about 800k nodes, 96k C3D20):
/// `cargo test --lib deck::tests::large_deck -- --ignored --nocapture`.
#[test]
#[ignore]
fn large_deck() {
    let (nx, ny, nz) = (40usize, 40usize, 60usize);
    let (ax, ay) = (2 * nx + 1, 2 * ny + 1);
    let id = |a: usize, b: usize, c: usize| 1 + a + ax * (b + ay * c);
    let mut s = String::from("*NODE, NSET=NALL\n");
    for c in 0..=2 * nz {
        for b in 0..ay {
            for a in 0..ax {
                let x = [a as f64 * 0.25, b as f64 * 0.25, c as f64 * 0.1 - 3.0];
                let _ = writeln!(s, "{}, {}, {}, {}", id(a, b, c), x[0], x[1], x[2]);
            }
        }
    }
    s.push_str("*ELEMENT, TYPE=C3D20, ELSET=EALL\n");
    let pattern: [(usize, usize, usize); 20] = [
        (0, 0, 0),
        (2, 0, 0),
        (2, 2, 0),
        (0, 2, 0),
        (0, 0, 2),
        (2, 0, 2),
        (2, 2, 2),
        (0, 2, 2),
        (1, 0, 0),
        (2, 1, 0),
        (1, 2, 0),
        (0, 1, 0),
        (1, 0, 2),
        (2, 1, 2),
        (1, 2, 2),
        (0, 1, 2),
        (0, 0, 1),
        (2, 0, 1),
        (2, 2, 1),
        (0, 2, 1),
    ];
    let mut label = 0;
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                label += 1;
                let nodes: Vec<String> = pattern
                    .iter()
                    .map(|&(a, b, c)| id(2 * i + a, 2 * j + b, 2 * k + c).to_string())
                    .collect();
                let _ = writeln!(
                    s,
                    "{label}, {},\n{}",
                    nodes[..15].join(", "),
                    nodes[15..].join(", ")
                );
            }
        }
    }
    s.push_str("*MATERIAL, NAME=STEEL\n*ELASTIC\n210000, 0.3\n");
    s.push_str("*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n");
    s.push_str("*NSET, NSET=BOTTOM, GENERATE\n1, 6561\n*BOUNDARY\nBOTTOM, 1, 3\n");
    s.push_str("*STEP\n*STATIC\n*CLOAD\nNALL, 3, 0.001\n*END STEP\n");
    let t = std::time::Instant::now();
    let deck = parse(&s).unwrap();
    let parse_time = t.elapsed();
    let t = std::time::Instant::now();
    let text = format_deck(&deck.model).unwrap();
    let write_time = t.elapsed();
    eprintln!(
        "{} MB, {} nodes, {} elements: parse {parse_time:?}, format {write_time:?} ({} MB)",
        s.len() >> 20,
        deck.model.mesh.node_count(),
        deck.model.mesh.elements.len(),
        text.len() >> 20
    );
    assert_eq!(deck.model.mesh.elements.len(), nx * ny * nz);
}

/// A keyword line that lost its `*` (or has junk before it) after `*STATIC`
/// or `*SOLID SECTION` was skipped silently with their data lines, dropping
/// e.g. a `*BOUNDARY` (found by tests/fuzz_parsers.rs): now an error at its
/// line. One line of numbers (time stepping, thickness) is still accepted.
#[test]
fn keyword_without_star_after_static_is_an_error() {
    let d = with(HEX, "*STATIC\n", "*STATIC\n0.1, 1.\nBOUNDARY\n");
    expect_err(
        &d,
        line_of(&d, "*STATIC") + 2,
        "second data line 'BOUNDARY'",
    );
    let d = with(HEX, "*STATIC\n", "*STATIC\n\0*BOUNDARY\n");
    expect_err(&d, line_of(&d, "*STATIC") + 1, "malformed number");
    let d = with(HEX, "*STATIC\n", "*STATIC\n1., 1.\n");
    parse(&d).unwrap();
    let d = with(HEX, "MATERIAL=steel\n", "MATERIAL=steel\n1.\nELASTIC\n");
    expect_err(&d, line_of(&d, "*SOLID SECTION") + 2, "SOLID SECTION");
}

/// A load or boundary condition on an empty set applied to nothing, silently
/// (found by tests/fuzz_parsers.rs: an *ELSET whose data line moved away):
/// now an error at the load's line naming the set.
#[test]
fn load_on_empty_set_is_an_error() {
    let d = with(
        HEX,
        "*STEP\n",
        "*ELSET, ELSET=NOTHING\n*NSET, NSET=NONODE\n*STEP\n",
    );
    let dl = with(&d, "*END STEP", "*DLOAD\nNOTHING, P2, 1.\n*END STEP");
    expect_err(
        &dl,
        line_of(&dl, "NOTHING, P2"),
        "set NOTHING, which is empty",
    );
    let cl = with(&d, "*END STEP", "*CLOAD\nNONODE, 1, 1.\n*END STEP");
    expect_err(&cl, line_of(&cl, "NONODE, 1, 1."), "*CLOAD on set NONODE");
    let bc = with(&d, "*END STEP", "*BOUNDARY\nNONODE, 1, 3\n*END STEP");
    expect_err(&bc, line_of(&bc, "NONODE, 1, 3"), "*BOUNDARY on set NONODE");
}

/// A set name with a control character (a corrupted byte) is an error at
/// its line, not a set the writer would rename (found by tests/fuzz_parsers.rs).
#[test]
fn control_character_in_name_is_an_error() {
    let d = with(HEX, "*STEP\n", "*NSET, NSET=\u{e}IXED\n1\n*STEP\n");
    expect_err(&d, line_of(&d, "IXED"), "control character U+000E");
}
