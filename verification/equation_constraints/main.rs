//! # Linear equations: `*EQUATION` against CalculiX
//!
//! Linear multi-point constraints Σ cᵢ uᵢ = 0, the first term's DOF
//! eliminated (`fem::constraints::resolve_equations`), against CalculiX
//! 2.20 on the same decks: each model is built here, written by flank's
//! writer (the equations as `*EQUATION`, with `*NODE PRINT` U of every node,
//! RF of the equation nodes and `*EL PRINT` S), read back by flank's reader
//! and solved by flank and by ccx. Compared, with the tolerance fixed
//! before the runs (1e-6 relative, the cross-code rung of the verification
//! ladder): every node's displacement (max |Δu| / max |u|), the force RF at
//! every node of an equation (ccx prints the internal force f_int there;
//! flank's reaction + f_ext; max |ΔRF| / max |RF|) and the stress at every
//! integration point (max |Δσ| / max |σ|). Then decks flank refuses, with
//! what ccx does on the same deck.
//!
//! Units N, mm, MPa: steel E = 210 000 MPa, ν = 0.3.

#[path = "../common/mod.rs"]
mod common;

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use flank::deck::{read_deck, write_deck};
use flank::fem::loads::load_vector;
use flank::fem::mesh::Mesh;
use flank::fem::model::{Dirichlet, Equation, EquationTerm, Model, NodalForce};
use flank::fem::static_analysis::{solve_static, SolveOptions, StaticSolution};
use flank::fem::stress::element_point_stresses;
use flank::mesh::structured::{box_mesh, BoxElement};

const TOLERANCE: f64 = 1e-6;
const E: f64 = 210e3;
const NU: f64 = 0.3;

/// The node at `x`.
fn node_at(mesh: &Mesh, x: [f64; 3]) -> usize {
    mesh.coords
        .iter()
        .position(|c| (0..3).all(|i| (c[i] - x[i]).abs() < 1e-9))
        .unwrap_or_else(|| panic!("no node at {x:?}"))
}

fn equation(terms: &[(usize, usize, f64)]) -> Equation {
    Equation {
        terms: terms
            .iter()
            .map(|&(node, component, coefficient)| EquationTerm {
                node,
                component,
                coefficient,
            })
            .collect(),
    }
}

fn clamp(model: &mut Model, set: &str) {
    common::fix_set(model, set, &[0, 1, 2], 0.0);
}

/// Writes `model` (with the node set EQN of its equation nodes), adds the
/// RF and stress prints, reads it back and solves it.
fn write_read_solve(model: &Model, name: &str) -> (PathBuf, Model, StaticSolution) {
    let mut model = model.clone();
    let mut eqn: Vec<usize> = model
        .equations
        .iter()
        .flat_map(|e| e.terms.iter().map(|t| t.node))
        .collect();
    eqn.sort_unstable();
    eqn.dedup();
    model.mesh.node_sets.insert("EQN".into(), eqn);
    let dir = common::scratch_dir(&format!("equation_{name}"));
    let path = dir.join(format!("{name}.inp"));
    write_deck(&model, &path).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let text = text.replace(
        "*END STEP",
        "*NODE PRINT, NSET=EQN\nRF\n*EL PRINT, ELSET=EALL\nS\n*END STEP",
    );
    std::fs::write(&path, text).unwrap();
    let parsed = read_deck(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
    assert_eq!(
        parsed.model.equations, model.equations,
        "{name}: round trip"
    );
    let sol = solve_static(&parsed.model, &SolveOptions::default())
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    (path, parsed.model, sol)
}

/// `forces (fx,fy,fz) for set EQN` of a ccx .dat file, by node label.
fn ccx_forces(dat: &str) -> HashMap<u64, [f64; 3]> {
    let mut out = HashMap::new();
    let mut on = false;
    for line in dat.lines() {
        let t = line.trim();
        if t.starts_with("forces") {
            on = true;
            continue;
        }
        if t.is_empty() {
            continue;
        }
        let v: Vec<&str> = t.split_whitespace().collect();
        if on && v.len() == 4 {
            if let Ok(n) = v[0].parse::<u64>() {
                let f: Vec<f64> = v[1..].iter().map(|x| x.parse().unwrap()).collect();
                out.insert(n, [f[0], f[1], f[2]]);
                continue;
            }
        }
        on = false;
    }
    out
}

/// The `stresses (elem, integ.pnt.,sxx,...)` block of a ccx .dat file.
fn ccx_point_stresses(dat: &str) -> HashMap<(u64, usize), [f64; 6]> {
    let mut out = HashMap::new();
    let mut on = false;
    for line in dat.lines() {
        let t = line.trim();
        if t.starts_with("stresses") {
            on = true;
            continue;
        }
        if t.is_empty() {
            continue;
        }
        let v: Vec<&str> = t.split_whitespace().collect();
        if on && v.len() == 8 {
            if let (Ok(e), Ok(g)) = (v[0].parse::<u64>(), v[1].parse::<usize>()) {
                let s: Vec<f64> = v[2..].iter().map(|x| x.parse().unwrap()).collect();
                out.insert((e, g), [s[0], s[1], s[2], s[3], s[4], s[5]]);
                continue;
            }
        }
        on = false;
    }
    out
}

/// flank against ccx on the written deck: (u, RF, σ) relative
/// differences, asserted ≤ 1e-6; None when ccx is missing (skipped).
fn compare_with_ccx(
    name: &str,
    deck: &Path,
    model: &Model,
    sol: &StaticSolution,
) -> Option<(f64, f64, f64)> {
    if !common::ccx_available() {
        return None;
    }
    let work = common::scratch_dir(&format!("equation_ccx_{name}"));
    let ccx = common::run_ccx(deck, &work);
    assert_eq!(ccx.displacements.len(), model.mesh.node_count(), "{name}");
    let du = flank::ccx::relative_difference(&model.mesh, &sol.displacement, &ccx.displacements)
        .unwrap();
    // RF at the equation nodes: flank's f_int = reaction + f_ext
    let r = sol.reaction.as_ref().expect("reactions");
    let f = load_vector(model).unwrap();
    let theirs = ccx_forces(&ccx.dat);
    let eqn = &model.mesh.node_sets["EQN"];
    assert_eq!(theirs.len(), eqn.len(), "{name}: ccx RF of the EQN nodes");
    let (mut diff, mut scale) = (0.0f64, 0.0f64);
    for &n in eqn {
        let c = theirs[&model.mesh.node_labels[n]];
        for k in 0..3 {
            diff = diff.max((r[3 * n + k] + f[3 * n + k] - c[k]).abs());
            scale = scale.max(c[k].abs());
        }
    }
    let drf = diff / scale;
    // stresses at the integration points (ccx order xx, yy, zz, xy, xz, yz)
    let theirs = ccx_point_stresses(&ccx.dat);
    let (mut diff, mut scale, mut points) = (0.0f64, 0.0f64, 0);
    for (e, el) in model.mesh.elements.iter().enumerate() {
        let ps = element_point_stresses(model, e, &sol.displacement).unwrap();
        for (g, s) in ps.stress.iter().enumerate() {
            let ours = [s[0], s[1], s[2], s[3], s[5], s[4]];
            let c = theirs
                .get(&(el.label, g + 1))
                .unwrap_or_else(|| panic!("{name}: no ccx stress at {} {}", el.label, g + 1));
            for k in 0..6 {
                diff = diff.max((ours[k] - c[k]).abs());
                scale = scale.max(c[k].abs());
            }
            points += 1;
        }
    }
    assert_eq!(points, theirs.len(), "{name}: ccx point stresses");
    let ds = diff / scale;
    println!(
        "VERIFY equation_constraints {name:<28} nodes {:>4}, {:>3} equations  ccx: max|du|/max|u| = {du:.2e}, max|dRF|/max|RF| = {drf:.2e}, max|dS|/max|S| = {ds:.2e} ({points} points, ccx {:.2} s)  (tol {TOLERANCE:.0e})",
        model.mesh.node_count(),
        model.equations.len(),
        ccx.wall_s
    );
    assert!(du <= TOLERANCE, "{name}: displacements differ by {du:.3e}");
    assert!(drf <= TOLERANCE, "{name}: RF differ by {drf:.3e}");
    assert!(ds <= TOLERANCE, "{name}: stresses differ by {ds:.3e}");
    Some((du, drf, ds))
}

/// Asserts that every equation holds in flank's solution to round-off.
fn assert_equations_hold(name: &str, model: &Model, sol: &StaticSolution) {
    let u = &sol.displacement;
    let umax = u.iter().fold(0.0f64, |a, b| a.max(b.abs()));
    for (k, eq) in model.equations.iter().enumerate() {
        let cmax = eq
            .terms
            .iter()
            .fold(0.0f64, |a, t| a.max(t.coefficient.abs()));
        let r: f64 = eq
            .terms
            .iter()
            .map(|t| t.coefficient * u[3 * t.node + t.component])
            .sum();
        assert!(
            r.abs() <= 1e-13 * cmax * umax,
            "{name}: equation {k} residual {r:.3e}"
        );
    }
}

fn run_case(name: &str, model: &Model) {
    let (deck, parsed, sol) = write_read_solve(model, name);
    assert_equations_hold(name, &parsed, &sol);
    compare_with_ccx(name, &deck, &parsed, &sol);
}

/// A cantilever 40 × 10 × 10 (4 × 2 × 2 C3D20) clamped at x = 0 whose end
/// face follows its centre node in all three translations (60 equations
/// written by flank's writer), loaded by 1 kN in −y on that node.
#[test]
fn cantilever_end_tied_to_a_node() {
    let mesh = box_mesh([40.0, 10.0, 10.0], [4, 2, 2], BoxElement::Hex20);
    let mut model = common::model_from_mesh(mesh, E, NU);
    clamp(&mut model, "X0");
    let c = node_at(&model.mesh, [40.0, 5.0, 5.0]);
    for &n in &model.mesh.node_sets["X1"].clone() {
        if n != c {
            for k in 0..3 {
                model.equations.push(equation(&[(n, k, 1.0), (c, k, -1.0)]));
            }
        }
    }
    assert_eq!(model.equations.len(), 60);
    model.forces.push(NodalForce {
        node: c,
        component: 1,
        value: -1000.0,
    });
    run_case("tied_end_c3d20", &model);
}

/// Two bars 20 × 10 × 10 (2 × 2 × 2 C3D20R each) with separate nodes on
/// the shared face x = 20, joined node to node by equations (u_b = u_a),
/// the first clamped at x = 0, the second loaded at its end.
#[test]
fn two_part_bar_joined_node_to_node() {
    let a = box_mesh([20.0, 10.0, 10.0], [2, 2, 2], BoxElement::Hex20R);
    let mut mesh = a.clone();
    let shift = a.node_count();
    let label_shift = 1000;
    for (&l, x) in a.node_labels.iter().zip(&a.coords) {
        mesh.add_node(l + label_shift, [x[0] + 20.0, x[1], x[2]])
            .unwrap();
    }
    for el in &a.elements {
        mesh.add_element(
            el.label + label_shift,
            el.kind,
            el.nodes.iter().map(|&n| n + shift).collect(),
        )
        .unwrap();
    }
    mesh.node_sets
        .insert("NALL".into(), (0..mesh.node_count()).collect());
    mesh.element_sets
        .insert("EALL".into(), (0..mesh.elements.len()).collect());
    let mut model = common::model_from_mesh(mesh, E, NU);
    clamp(&mut model, "X0");
    // part a's node at x = 20 and part b's node at the same point
    for &na in &a.node_sets["X1"] {
        let x = a.coords[na];
        let nb = a.node_sets["X0"]
            .iter()
            .find(|&&m| a.coords[m][1] == x[1] && a.coords[m][2] == x[2])
            .unwrap()
            + shift;
        assert_eq!(model.mesh.coords[nb], x);
        for k in 0..3 {
            model
                .equations
                .push(equation(&[(nb, k, 1.0), (na, k, -1.0)]));
        }
    }
    // end load on the far face of part b: 100 N in −y, 50 N in +z on each node
    let far: Vec<usize> = (0..model.mesh.node_count())
        .filter(|&n| (model.mesh.coords[n][0] - 40.0).abs() < 1e-9)
        .collect();
    for n in far {
        model.forces.push(NodalForce {
            node: n,
            component: 1,
            value: -100.0,
        });
        model.forces.push(NodalForce {
            node: n,
            component: 2,
            value: 50.0,
        });
    }
    run_case("two_part_bar_c3d20r", &model);
}

/// A block 20 × 10 × 10 (2 × 2 × 2 C3D15) on a skew roller: u_z = 0 and
/// u_x − u_y = 0 on its base (one equation per node), one base corner held
/// in x; pushed sideways on its top.
#[test]
fn skew_support() {
    let mesh = box_mesh([20.0, 10.0, 10.0], [2, 2, 2], BoxElement::Wedge15);
    let mut model = common::model_from_mesh(mesh, E, NU);
    common::fix_set(&mut model, "Z0", &[2], 0.0);
    let o = node_at(&model.mesh, [0.0, 0.0, 0.0]);
    for &n in &model.mesh.node_sets["Z0"].clone() {
        if n != o {
            model.equations.push(equation(&[(n, 0, 1.0), (n, 1, -1.0)]));
        }
    }
    model.dirichlet.push(Dirichlet {
        node: o,
        component: 0,
        value: 0.0,
    });
    model.dirichlet.push(Dirichlet {
        node: o,
        component: 1,
        value: 0.0,
    });
    for &n in &model.mesh.node_sets["Z1"].clone() {
        model.forces.push(NodalForce {
            node: n,
            component: 0,
            value: 40.0,
        });
    }
    run_case("skew_support_c3d15", &model);
}

/// The cantilever (C3D20R) with its end face pushed down by a prescribed
/// u_y = −0.05 mm of the centre node, which the other end-face nodes follow
/// through equations (u_y(n) − u_y(c) = 0): an independent DOF with a
/// prescribed non-zero value.
#[test]
fn prescribed_independent_dof() {
    let mesh = box_mesh([40.0, 10.0, 10.0], [4, 2, 2], BoxElement::Hex20R);
    let mut model = common::model_from_mesh(mesh, E, NU);
    clamp(&mut model, "X0");
    let c = node_at(&model.mesh, [40.0, 5.0, 5.0]);
    for &n in &model.mesh.node_sets["X1"].clone() {
        if n != c {
            model.equations.push(equation(&[(n, 1, 1.0), (c, 1, -1.0)]));
        }
    }
    model.dirichlet.push(Dirichlet {
        node: c,
        component: 1,
        value: -0.05,
    });
    run_case("prescribed_independent_c3d20r", &model);
}

/// A chain on the cantilever's end face (C3D20): A depends on B (and D),
/// B on C, C on E, written in that order (each dependent DOF appears as an
/// independent of an earlier equation), with mixed DOFs and coefficients,
/// under a tip load.
#[test]
fn chain_of_equations() {
    let mesh = box_mesh([40.0, 10.0, 10.0], [4, 2, 2], BoxElement::Hex20);
    let mut model = common::model_from_mesh(mesh, E, NU);
    clamp(&mut model, "X0");
    let p = |y: f64, z: f64| node_at(&model.mesh, [40.0, y, z]);
    let (a, b, c, d, e) = (
        p(0.0, 0.0),
        p(10.0, 0.0),
        p(10.0, 10.0),
        p(0.0, 10.0),
        p(5.0, 5.0),
    );
    model.equations = vec![
        equation(&[(a, 1, 1.0), (b, 1, -0.5), (d, 2, -0.25)]),
        equation(&[(b, 1, 2.0), (c, 1, -1.0), (e, 0, 0.75)]),
        equation(&[(c, 1, 1.0), (e, 1, -1.0)]),
    ];
    model.forces.push(NodalForce {
        node: e,
        component: 1,
        value: -1000.0,
    });
    model.forces.push(NodalForce {
        node: a,
        component: 0,
        value: 300.0,
    });
    run_case("chain_c3d20", &model);
}

/// A general equation over several nodes and DOFs (C3D15 cantilever):
/// 3 u_x(A) + u_y(B) − 2 u_z(C) + 0.5 u_x(D) = 0 and a one-term equation
/// u_z(E) = 0 (a support written as an equation).
#[test]
fn general_equation() {
    let mesh = box_mesh([40.0, 10.0, 10.0], [4, 2, 2], BoxElement::Wedge15);
    let mut model = common::model_from_mesh(mesh, E, NU);
    clamp(&mut model, "X0");
    let p = |x: f64, y: f64, z: f64| node_at(&model.mesh, [x, y, z]);
    let (a, b, c, d, e) = (
        p(40.0, 0.0, 0.0),
        p(40.0, 10.0, 10.0),
        p(30.0, 10.0, 0.0),
        p(20.0, 0.0, 10.0),
        p(40.0, 10.0, 0.0),
    );
    model.equations = vec![
        equation(&[(a, 0, 3.0), (b, 1, 1.0), (c, 2, -2.0), (d, 0, 0.5)]),
        equation(&[(e, 2, 1.0)]),
    ];
    for &n in &model.mesh.node_sets["X1"].clone() {
        model.forces.push(NodalForce {
            node: n,
            component: 2,
            value: -50.0,
        });
    }
    run_case("general_c3d15", &model);
}

/// The unit-cube deck of `verification/bad_decks` with `model` model data
/// and `step` step data added.
fn cube_deck(model: &str, boundary: &str, step: &str) -> String {
    let mesh = box_mesh([1.0, 1.0, 1.0], [1, 1, 1], BoxElement::Hex20);
    let mut m = common::model_from_mesh(mesh, E, NU);
    clamp(&mut m, "Z0");
    let text = flank::deck::format_deck(&m).unwrap();
    let text = text.replace("*STEP\n", &format!("{model}*STEP\n"));
    let text = text.replace("*BOUNDARY\n", &format!("*BOUNDARY\n{boundary}"));
    text.replace("*END STEP", &format!("{step}*END STEP"))
}

/// Decks flank refuses, at the line given, and what ccx 2.20 does on them
/// (measured on this machine, asserted where ccx is present).
#[test]
fn refused_decks() {
    let mesh = box_mesh([1.0, 1.0, 1.0], [1, 1, 1], BoxElement::Hex20);
    let top = |x: f64, y: f64| node_at(&mesh, [x, y, 1.0]) as u64 + 1;
    let (a, b, c) = (top(1.0, 1.0), top(1.0, 0.0), top(0.0, 1.0));
    let base = node_at(&mesh, [0.0, 0.0, 0.0]) as u64 + 1;
    let load = format!("*CLOAD\n{a}, 1, 10.\n");
    // (name, deck, flank's message, line of the refusal, ccx refuses)
    let cases: Vec<(&str, String, &str, String, bool)> = vec![
        (
            "dependent_under_boundary",
            cube_deck(
                &format!("*EQUATION\n2\n{base}, 1, 1., {a}, 1, -1.\n"),
                "",
                &load,
            ),
            "also prescribed by a *BOUNDARY",
            "2".into(),
            true,
        ),
        (
            "dependent_twice",
            cube_deck(
                &format!("*EQUATION\n2\n{a}, 1, 1., {b}, 1, -1.\n2\n{a}, 1, 1., {c}, 1, -1.\n"),
                "",
                &load,
            ),
            "already the dependent DOF",
            format!("2\n{a}, 1, 1., {c}"),
            true,
        ),
        (
            "two_equation_cycle",
            cube_deck(
                &format!("*EQUATION\n2\n{a}, 1, 1., {b}, 1, -1.\n2\n{b}, 1, 1., {a}, 1, -1.\n"),
                "",
                &load,
            ),
            "cycle",
            "2".into(),
            true,
        ),
        (
            "equation_in_step",
            cube_deck("", "", &format!("{load}*EQUATION\n2\n{a}, 1, 1., {b}, 1, -1.\n")),
            "before *STEP",
            "*EQUATION".into(),
            true,
        ),
        (
            "zero_first_coefficient",
            cube_deck(
                &format!("*EQUATION\n2\n{a}, 1, 0., {b}, 1, -1.\n"),
                "",
                &load,
            ),
            "is zero",
            "2".into(),
            true,
        ),
        (
            "three_equation_cycle",
            cube_deck(
                &format!(
                    "*EQUATION\n2\n{a}, 1, 1., {b}, 1, -2.\n2\n{b}, 1, 1., {c}, 1, -2.\n2\n{c}, 1, 1., {a}, 1, -2.\n"
                ),
                "",
                &load,
            ),
            "cycle",
            "2".into(),
            false,
        ),
    ];
    for (name, text, words, needle, ccx_refuses) in cases {
        let dir = common::scratch_dir(&format!("equation_refused_{name}"));
        let path = dir.join(format!("{name}.inp"));
        std::fs::write(&path, &text).unwrap();
        let err = read_deck(&path).map(|_| ()).expect_err(name).to_string();
        let line = text
            .lines()
            .position(|l| l == needle.lines().next().unwrap())
            .unwrap()
            + 1;
        // the line of the first equation set (or the keyword), or the second
        let line = if needle.contains('\n') {
            text.find(&needle)
                .map(|at| text[..at].lines().count() + 1)
                .unwrap()
        } else {
            line
        };
        assert!(
            err.contains(&format!(".inp:{line}:")) && err.contains(words),
            "{name}: {err}"
        );
        let ccx = if common::ccx_available() {
            let work = common::scratch_dir(&format!("equation_refused_ccx_{name}"));
            match flank::ccx::run_ccx(&path, &work, 1) {
                Ok(_) => "solves it".to_string(),
                Err(e) => format!("fails: {e}"),
            }
        } else {
            "not run".to_string()
        };
        println!("VERIFY equation_constraints refused {name:<26} flank: {err}\n    ccx: {ccx}");
        if common::ccx_available() {
            assert_eq!(ccx.starts_with("fails"), ccx_refuses, "{name}: ccx {ccx}");
        }
    }
}
