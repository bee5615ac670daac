//! # Bad decks get clear errors, never a panic or a wrong number
//!
//! Each deck below is a valid one-element C3D20 deck with one thing broken.
//! `flank solve` must exit with an error whose message names the problem (and
//! where it is), must not panic, and must not write results.

use std::process::Command;

/// A valid unit-cube C3D20 deck; `edit` breaks one thing.
fn deck(edit: impl Fn(String) -> String) -> String {
    let mut s = String::from("*NODE, NSET=NALL\n");
    let p: [[f64; 3]; 20] = [
        [0., 0., 0.],
        [1., 0., 0.],
        [1., 1., 0.],
        [0., 1., 0.],
        [0., 0., 1.],
        [1., 0., 1.],
        [1., 1., 1.],
        [0., 1., 1.],
        [0.5, 0., 0.],
        [1., 0.5, 0.],
        [0.5, 1., 0.],
        [0., 0.5, 0.],
        [0.5, 0., 1.],
        [1., 0.5, 1.],
        [0.5, 1., 1.],
        [0., 0.5, 1.],
        [0., 0., 0.5],
        [1., 0., 0.5],
        [1., 1., 0.5],
        [0., 1., 0.5],
    ];
    for (i, x) in p.iter().enumerate() {
        s += &format!("{}, {}, {}, {}\n", i + 1, x[0], x[1], x[2]);
    }
    s += "*ELEMENT, TYPE=C3D20, ELSET=EALL\n1, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15,\n16, 17, 18, 19, 20\n";
    s += "*NSET, NSET=BASE\n1, 2, 3, 4, 9, 10, 11, 12\n";
    s += "*MATERIAL, NAME=STEEL\n*ELASTIC\n210000., 0.3\n*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n";
    s += "*STEP\n*STATIC\n*BOUNDARY\nBASE, 1, 3\n*DLOAD\n1, P2, 10.\n*NODE PRINT, NSET=NALL\nU\n*END STEP\n";
    edit(s)
}

fn run(name: &str, text: &str) -> (bool, String) {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("bad_decks")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(format!("{name}.inp"));
    std::fs::write(&path, text).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_flank"))
        .args([
            "solve",
            path.to_str().unwrap(),
            "--out",
            dir.join("out").to_str().unwrap(),
            "--quiet",
        ])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr).to_string();
    assert!(
        !stderr.contains("panicked"),
        "{name}: flank panicked:\n{stderr}"
    );
    if !out.status.success() {
        assert!(
            !dir.join("out/displacements.csv").exists(),
            "{name}: results written despite the error"
        );
    }
    (out.status.success(), stderr)
}

fn expect_error(name: &str, text: &str, words: &[&str]) {
    let (ok, stderr) = run(name, text);
    assert!(!ok, "{name}: flank accepted a bad deck");
    let lower = stderr.to_lowercase();
    for w in words {
        assert!(
            lower.contains(&w.to_lowercase()),
            "{name}: error message lacks '{w}':\n{stderr}"
        );
    }
    println!(
        "{name:<24} -> {}",
        stderr
            .lines()
            .filter(|l| !l.trim().is_empty())
            .collect::<Vec<_>>()
            .join(" | ")
    );
}

#[test]
fn the_valid_deck_solves() {
    let (ok, stderr) = run("valid", &deck(|s| s));
    assert!(ok, "the reference deck must solve:\n{stderr}");
}

#[test]
fn unknown_element_type() {
    expect_error(
        "unknown_type",
        &deck(|s| s.replace("TYPE=C3D20,", "TYPE=C3D8,")),
        &["C3D8", ":22"],
    );
}

#[test]
fn element_refers_to_missing_node() {
    expect_error(
        "missing_node",
        &deck(|s| s.replace("16, 17, 18, 19, 20\n", "16, 17, 18, 19, 99\n")),
        &["99"],
    );
}

#[test]
fn inverted_element() {
    // mirror z: nodes 5..8 below 1..4
    let text = deck(|s| {
        s.lines()
            .map(|l| {
                let f: Vec<&str> = l.split(',').map(str::trim).collect();
                if f.len() == 4 && f[0].parse::<u32>().is_ok_and(|n| n <= 20) && !l.starts_with('*')
                {
                    let z: f64 = f[3].parse().unwrap();
                    format!("{}, {}, {}, {}", f[0], f[1], f[2], -z)
                } else {
                    l.to_string()
                }
            })
            .collect::<Vec<_>>()
            .join("\n")
    });
    expect_error("inverted", &text, &["element 1", "inverted"]);
}

#[test]
fn no_constraints_is_singular() {
    expect_error(
        "no_constraints",
        &deck(|s| s.replace("*BOUNDARY\nBASE, 1, 3\n", "")),
        &["singular", "rigid-body", "translation"],
    );
}

#[test]
fn partial_constraints_name_the_free_modes() {
    expect_error(
        "only_z_fixed",
        &deck(|s| s.replace("BASE, 1, 3", "BASE, 3, 3")),
        &["rotation about z", "translation x"],
    );
}

#[test]
fn negative_youngs_modulus() {
    expect_error(
        "negative_e",
        &deck(|s| s.replace("210000., 0.3", "-210000., 0.3")),
        &["young", ":29"],
    );
}

#[test]
fn poisson_ratio_at_one_half() {
    expect_error(
        "nu_half",
        &deck(|s| s.replace("210000., 0.3", "210000., 0.5")),
        &["poisson", ":29"],
    );
}

#[test]
fn undefined_set_name() {
    expect_error(
        "undefined_set",
        &deck(|s| s.replace("BASE, 1, 3", "BOTTOM, 1, 3")),
        &["BOTTOM"],
    );
    expect_error(
        "undefined_elset",
        &deck(|s| s.replace("*SOLID SECTION, ELSET=EALL", "*SOLID SECTION, ELSET=SOLIDS")),
        &["SOLIDS"],
    );
}

#[test]
fn malformed_number_names_the_line() {
    expect_error(
        "malformed",
        &deck(|s| s.replace("\n3, 1, 1, 0\n", "\n3, 1, 1.x, 0\n")),
        &[":4", "1.x"],
    );
}

#[test]
fn missing_file() {
    let out = Command::new(env!("CARGO_BIN_EXE_flank"))
        .args(["solve", "/nonexistent/deck.inp", "--quiet"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("/nonexistent/deck.inp") && !stderr.contains("panicked"),
        "{stderr}"
    );
}

// ---------------------------------------------------------------------------
// Contact decks
// ---------------------------------------------------------------------------

/// Two unit C3D20 cubes: the lower one on z ∈ [0, 1] clamped at its bottom,
/// the upper one lifted by `lift` (its bottom at z = 1 + lift), held in x and
/// y on its top face; contact of its bottom face (slave) on the lower cube's
/// top (master). `load` is the step's load on the upper cube, `contact` the
/// interaction lines.
fn contact_deck(lift: f64, load: &str, contact: &str) -> String {
    let unit: [[f64; 3]; 20] = [
        [0., 0., 0.],
        [1., 0., 0.],
        [1., 1., 0.],
        [0., 1., 0.],
        [0., 0., 1.],
        [1., 0., 1.],
        [1., 1., 1.],
        [0., 1., 1.],
        [0.5, 0., 0.],
        [1., 0.5, 0.],
        [0.5, 1., 0.],
        [0., 0.5, 0.],
        [0.5, 0., 1.],
        [1., 0.5, 1.],
        [0.5, 1., 1.],
        [0., 0.5, 1.],
        [0., 0., 0.5],
        [1., 0., 0.5],
        [1., 1., 0.5],
        [0., 1., 0.5],
    ];
    let mut s = String::from("*NODE, NSET=NALL\n");
    for b in 0..2 {
        for (i, x) in unit.iter().enumerate() {
            let z = x[2] + if b == 1 { 1.0 + lift } else { 0.0 };
            s += &format!("{}, {}, {}, {}\n", 100 * b + i + 1, x[0], x[1], z);
        }
    }
    s += "*ELEMENT, TYPE=C3D20, ELSET=EALL\n";
    for b in 0..2 {
        let n: Vec<String> = (1..=20).map(|i| (100 * b + i).to_string()).collect();
        s += &format!(
            "{}, {},\n{}\n",
            b + 1,
            n[..15].join(", "),
            n[15..].join(", ")
        );
    }
    s += "*ELSET, ELSET=UPPER\n2\n*ELSET, ELSET=LOWER\n1\n";
    s += "*NSET, NSET=BOT\n1, 2, 3, 4, 9, 10, 11, 12\n*NSET, NSET=TOP\n105, 106, 107, 108, 113, 114, 115, 116\n";
    s += "*MATERIAL, NAME=STEEL\n*ELASTIC\n210000., 0.3\n*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n";
    s += "*SURFACE, NAME=SLAVE, TYPE=ELEMENT\nUPPER, S1\n*SURFACE, NAME=MASTER, TYPE=ELEMENT\nLOWER, S2\n";
    s += contact;
    s += "*CONTACT PAIR, INTERACTION=SI, TYPE=NODE TO SURFACE\nSLAVE, MASTER\n";
    s += "*BOUNDARY\nBOT, 1, 3\nTOP, 1, 2\n*STEP\n*STATIC\n";
    s += load;
    s += "*NODE PRINT, NSET=NALL\nU\n*END STEP\n";
    s
}

const HARD: &str = "*SURFACE INTERACTION, NAME=SI\n*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=HARD\n";
/// Downward pressure on the upper cube's top face: only contact can hold it.
const PUSH: &str = "*DLOAD\n2, P2, 10.\n";
/// The upper cube's top face moved down by 0.001 mm.
const MOVE: &str = "*BOUNDARY\nTOP, 3, 3, -0.001\n";

#[test]
fn valid_contact_decks_solve() {
    for (name, load) in [("contact_push", PUSH), ("contact_move", MOVE)] {
        let (ok, stderr) = run(name, &contact_deck(0.0, load, HARD));
        assert!(ok, "{name} must solve:\n{stderr}");
    }
    // a node-based slave surface (areas from the skin faces of its nodes)
    let text = contact_deck(0.0, PUSH, HARD).replace(
        "*SURFACE, NAME=SLAVE, TYPE=ELEMENT\nUPPER, S1\n",
        "*NSET, NSET=UPPER_BOTTOM\n101, 102, 103, 104, 109, 110, 111, 112\n*SURFACE, NAME=SLAVE, TYPE=NODE\nUPPER_BOTTOM\n",
    );
    let (ok, stderr) = run("contact_node_surface", &text);
    assert!(ok, "node surface must solve:\n{stderr}");
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("bad_decks");
    let csv = |name: &str| std::fs::read_to_string(dir.join(name).join("out/contact.csv")).unwrap();
    assert_eq!(csv("contact_node_surface"), csv("contact_push"));
}

#[test]
fn bodies_that_never_touch() {
    // pushed by a load, held only by contact that never comes: an error
    expect_error(
        "never_touch_force",
        &contact_deck(5.0, PUSH, HARD),
        &["cannot be balanced", "do not touch"],
    );
    // moved by a prescribed displacement: solves, with a warning
    let (ok, stderr) = run("never_touch_move", &contact_deck(5.0, MOVE, HARD));
    assert!(ok, "{stderr}");
    assert!(stderr.contains("do not touch"), "no warning:\n{stderr}");
    println!("{:<24} -> {}", "never_touch_move", stderr.trim());
}

#[test]
fn deep_initial_interpenetration() {
    // the upper cube starts 1.2 mm inside the lower one (faces are 1 mm)
    expect_error(
        "deep_penetration",
        &contact_deck(-1.2, MOVE, HARD),
        &["penetrates", "sanity limit"],
    );
}

#[test]
fn contact_surface_naming_no_face() {
    let text = contact_deck(0.0, MOVE, HARD).replace(
        "*SURFACE, NAME=SLAVE, TYPE=ELEMENT\nUPPER, S1\n",
        "*ELSET, ELSET=NOTHING\n*SURFACE, NAME=SLAVE, TYPE=ELEMENT\nNOTHING, S1\n",
    );
    let line = text.lines().position(|l| l.contains("NAME=SLAVE")).unwrap() + 1;
    expect_error(
        "empty_surface",
        &text,
        &["names no element face", &format!(":{line}")],
    );
}

#[test]
fn negative_friction_coefficient() {
    let text = contact_deck(0.0, MOVE, &format!("{HARD}*FRICTION\n-0.1\n"));
    let line = text.lines().position(|l| l == "-0.1").unwrap() + 1;
    expect_error(
        "negative_mu",
        &text,
        &["must not be negative", &format!(":{line}")],
    );
    // a non-positive stick slope is refused (μ > 0 is solved: verification/friction)
    expect_error(
        "nonpositive_stick_slope",
        &contact_deck(0.0, MOVE, &format!("{HARD}*FRICTION\n0.2, 0\n")),
        &["stick slope"],
    );
}

#[test]
fn contact_pair_with_missing_parts() {
    expect_error(
        "missing_interaction",
        &contact_deck(0.0, MOVE, HARD).replace("INTERACTION=SI,", "INTERACTION=STEEL,"),
        &["STEEL is not defined"],
    );
    expect_error(
        "missing_surface",
        &contact_deck(0.0, MOVE, HARD).replace("SLAVE, MASTER", "SLAVE, FLANK"),
        &["FLANK is not defined"],
    );
}

#[test]
fn floating_body_pulled_away_or_unloaded() {
    // the load pulls the upper cube off: contact cannot balance it
    expect_error(
        "pulled_away",
        &contact_deck(0.0, "*DLOAD\n2, P2, -10.\n", HARD),
        &["cannot be balanced", "wrong sign"],
    );
    // no load on a body only contact holds: its position is undetermined
    expect_error(
        "unloaded_floating",
        &contact_deck(0.0, "", HARD),
        &["not held", "undetermined"],
    );
}

/// The unit cube with its top face held by a `*RIGID BODY` (REF NODE 100,
/// ROT NODE 101, both fixed but for the rotation about z, which carries a
/// moment) instead of the pressure; `edit` breaks one thing.
fn rigid(edit: impl Fn(String) -> String) -> String {
    let s = deck(|s| {
        s.replace(
            "*ELEMENT,",
            "*NODE\n100, 0.5, 0.5, 1.\n101, 0.5, 0.5, 1.\n*ELEMENT,",
        )
        .replace(
            "*STEP\n",
            "*NSET, NSET=TOP\n5, 6, 7, 8, 13, 14, 15, 16\n*RIGID BODY, NSET=TOP, REF NODE=100, ROT NODE=101\n*STEP\n",
        )
        .replace("BASE, 1, 3\n", "BASE, 1, 3\n100, 1, 3\n101, 1, 2\n")
        .replace("*DLOAD\n1, P2, 10.\n", "*CLOAD\n101, 3, 1000.\n")
    });
    edit(s)
}

#[test]
fn the_valid_rigid_body_deck_solves() {
    let (ok, stderr) = run("valid_rigid", &rigid(|s| s));
    assert!(ok, "the rigid-body deck must solve:\n{stderr}");
    assert!(!stderr.contains("warning"), "{stderr}");
}

#[test]
fn rigid_coupling_errors() {
    let line = |text: &str, needle: &str| {
        format!(
            ":{}:",
            text.lines().position(|l| l.contains(needle)).unwrap() + 1
        )
    };
    let t = rigid(|s| s.replace("REF NODE=100", "REF NODE=99"));
    expect_error(
        "rigid_ref_missing",
        &t,
        &[&line(&t, "*RIGID BODY"), "REF NODE 99 is not defined"],
    );
    let t = rigid(|s| s.replace("REF NODE=100", "REF NODE=7"));
    expect_error(
        "rigid_ref_in_element",
        &t,
        &[&line(&t, "*RIGID BODY"), "belongs to an element"],
    );
    let t = rigid(|s| s.replace("BASE, 1, 3\n", "BASE, 1, 3\n7, 1, 1, 0.\n"));
    expect_error(
        "rigid_coupled_node_fixed",
        &t,
        &[&line(&t, "7, 1, 1, 0."), "constrain the reference node"],
    );
    let t = rigid(|s| {
        s.replace(
            "*STEP\n",
            "*NODE\n102, 0, 0, 2\n*NSET, NSET=CORNER\n7\n*RIGID BODY, NSET=CORNER, REF NODE=102\n*STEP\n",
        )
    });
    expect_error(
        "rigid_node_twice",
        &t,
        &[&line(&t, "NSET=CORNER, REF"), "node 7 is already coupled"],
    );
    let t = rigid(|s| {
        s.replace(
            "*RIGID BODY, NSET=TOP",
            "*NSET, NSET=NONE\n*RIGID BODY, NSET=NONE",
        )
    });
    expect_error(
        "rigid_empty_set",
        &t,
        &[&line(&t, "*RIGID BODY"), "node set NONE has no node"],
    );
    let t = rigid(|s| s.replace("101, 1, 2\n", "101, 1, 2, 0.01\n"));
    expect_error(
        "rigid_prescribed_rotation",
        &t,
        &[&line(&t, "101, 1, 2, 0.01"), "only zero"],
    );
    // *COUPLING + *DISTRIBUTING / a partial *KINEMATIC
    let coupling = |kin: &'static str| {
        rigid(move |s| {
            s.replace(
                "*RIGID BODY, NSET=TOP, REF NODE=100, ROT NODE=101\n",
                &format!("*SURFACE, NAME=STOP, TYPE=ELEMENT\n1, S2\n*COUPLING, REF NODE=100, SURFACE=STOP, CONSTRAINT NAME=C1\n{kin}"),
            )
            .replace("101, 1, 2\n", "100, 4, 5\n")
            .replace("101, 3, 1000.", "100, 6, 1000.")
        })
    };
    let (ok, stderr) = run("valid_coupling", &coupling("*KINEMATIC\n1, 3\n"));
    assert!(ok, "the *COUPLING deck must solve:\n{stderr}");
    let t = coupling("*DISTRIBUTING\n1, 3\n");
    expect_error(
        "coupling_distributing",
        &t,
        &[&line(&t, "*DISTRIBUTING"), "distributing", "not held rigid"],
    );
    let t = coupling("*KINEMATIC\n3\n");
    expect_error(
        "coupling_partial",
        &t,
        &[&line(&t, "*KINEMATIC"), "couples only dof(s) 3", "partial"],
    );
    // a body held by a free reference DOF that nothing else holds
    let t = rigid(|s| s.replace("BASE, 1, 3\n", ""));
    expect_error(
        "rigid_floating",
        &t,
        &["free rigid-body mode", "rotation about z"],
    );
}

/// The unit cube heated from T0 = 20 to 120 (α = 1.2e-5, base held, the
/// pressure kept); `edit` breaks one thing.
fn thermal(edit: impl Fn(String) -> String) -> String {
    let s = deck(|s| {
        s.replace(
            "210000., 0.3\n",
            "210000., 0.3\n*EXPANSION\n1.2e-5\n",
        )
        .replace(
            "*STEP\n*STATIC\n",
            "*INITIAL CONDITIONS, TYPE=TEMPERATURE\nNALL, 20.\n*STEP\n*STATIC\n*TEMPERATURE\nNALL, 120.\n",
        )
    });
    edit(s)
}

#[test]
fn thermal_load_errors() {
    let (ok, stderr) = run("valid_thermal", &thermal(|s| s));
    assert!(ok, "the thermal deck must solve:\n{stderr}");
    let line = |text: &str, needle: &str| {
        let n = text.lines().position(|l| l.contains(needle)).unwrap() + 1;
        format!(".inp:{n}:")
    };
    let t = thermal(|s| s.replace("*INITIAL CONDITIONS, TYPE=TEMPERATURE\nNALL, 20.\n", ""));
    expect_error(
        "thermal_no_initial",
        &t,
        &[&line(&t, "*TEMPERATURE"), "without *initial conditions"],
    );
    let t = thermal(|s| s.replace("1.2e-5\n", "1.2e-5, 20.\n1.3e-5, 300.\n"));
    expect_error(
        "thermal_alpha_table",
        &t,
        &[&line(&t, "1.3e-5, 300."), "temperature-dependent expansion"],
    );
    let t = thermal(|s| s.replace("TYPE=TEMPERATURE", "TYPE=STRESS"));
    expect_error(
        "thermal_initial_stress",
        &t,
        &[&line(&t, "TYPE=STRESS"), "TYPE=STRESS is not supported"],
    );
    let t = thermal(|s| s.replace("NALL, 20.\n", "BASE, 20.\n"));
    expect_error(
        "thermal_missing_t0",
        &t,
        &[
            &line(&t, "*INITIAL CONDITIONS"),
            "no initial temperature",
            "1.2357111319",
        ],
    );
    // a thermal load on a contact deck: the contact solver refuses it
    let t = contact_deck(0.0, &format!("*TEMPERATURE\nNALL, 120.\n{PUSH}"), HARD)
        .replace("210000., 0.3\n", "210000., 0.3\n*EXPANSION\n1.2e-5\n")
        .replace(
            "*STEP\n",
            "*INITIAL CONDITIONS, TYPE=TEMPERATURE\nNALL, 20.\n*STEP\n",
        );
    expect_error(
        "thermal_with_contact",
        &t,
        &["thermal strains", "contact are not supported"],
    );
    let t = thermal(|s| s.replace("*TEMPERATURE\n", "*TEMPERATURE, AMPLITUDE=RAMP\n"));
    expect_error(
        "thermal_amplitude",
        &t,
        &[&line(&t, "AMPLITUDE=RAMP"), "AMPLITUDE"],
    );
}

/// The unit cube with its top face corner 7 following corner 6 in x
/// (`*EQUATION`, model data); `edit` breaks one thing.
fn equation(edit: impl Fn(String) -> String) -> String {
    let s = deck(|s| s.replace("*STEP\n", "*EQUATION\n2\n7, 1, 1., 6, 1, -1.\n*STEP\n"));
    edit(s)
}

#[test]
fn equation_errors() {
    let (ok, stderr) = run("valid_equation", &equation(|s| s));
    assert!(ok, "the equation deck must solve:\n{stderr}");
    let line = |text: &str, needle: &str| {
        let n = text.lines().position(|l| l.contains(needle)).unwrap() + 1;
        format!(".inp:{n}:")
    };
    let count = |text: &str| {
        let n = text.lines().position(|l| l == "*EQUATION").unwrap() + 2;
        format!(".inp:{n}:")
    };
    let t = equation(|s| s.replace("7, 1, 1., 6", "1, 1, 1., 6"));
    expect_error(
        "equation_dependent_fixed",
        &t,
        &[&count(&t), "also prescribed by a *boundary"],
    );
    let t = equation(|s| s.replace("6, 1, -1.\n", "6, 1, -1.\n2\n7, 1, 1., 8, 1, -1.\n"));
    expect_error(
        "equation_dependent_twice",
        &t,
        &[
            &format!(
                ".inp:{}:",
                t.lines().position(|l| l.contains("7, 1, 1., 8")).unwrap()
            ),
            "already the dependent dof",
        ],
    );
    let t = equation(|s| s.replace("6, 1, -1.\n", "6, 1, -1.\n2\n6, 1, 1., 7, 1, -1.\n"));
    expect_error("equation_cycle", &t, &[&count(&t), "cycle"]);
    let t = deck(|s| s.replace("*END STEP", "*EQUATION\n2\n7, 1, 1., 6, 1, -1.\n*END STEP"));
    expect_error(
        "equation_in_step",
        &t,
        &[&line(&t, "*EQUATION"), "before *step"],
    );
    let t = equation(|s| s.replace("7, 1, 1., 6", "7, 1, 0., 6"));
    expect_error("equation_zero_coefficient", &t, &[&count(&t), "is zero"]);
    let t = equation(|s| s.replace("7, 1, 1., 6", "7, 4, 1., 6"));
    expect_error(
        "equation_rotation_dof",
        &t,
        &[&line(&t, "7, 4, 1."), "translations 1-3"],
    );
}
