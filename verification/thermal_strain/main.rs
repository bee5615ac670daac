//! # Thermal strains: `*EXPANSION`, `*INITIAL CONDITIONS, TYPE=TEMPERATURE`, `*TEMPERATURE`
//!
//! The initial strain ε_th = α (T − T0) I (temperatures carried to the
//! stiffness rule's points as ccx does: the trilinear projection on C3D20,
//! the quadratic shape functions on C3D20R and C3D15), its consistent load
//! ∫ Bᵀ D ε_th dV and the stress σ = D (ε − ε_th), against
//! * CalculiX 2.20 on the same decks (written by flank's writer, read back
//!   by its reader): every node's displacement, the total reaction of the
//!   supported sets and the stresses at every integration point
//!   (`*EL PRINT` S), ≤ 1e-6 relative;
//! * closed forms: a free bar heated uniformly (u = α ΔT x, σ = 0), a bar
//!   held axially at both ends (σ_xx = −E α ΔT, lateral strain (1 + ν) α ΔT),
//!   and a free plate with a temperature linear through its thickness
//!   (stress-free, curvature κ = α ΔT / h, the exact field quadratic).
//!
//! Units N, mm, K: steel E = 210 000 MPa, ν = 0.3, α = 1.2e-5 /K.

#[path = "../common/mod.rs"]
mod common;

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use flank::deck::{read_deck, write_deck};
use flank::fem::loads::load_vector;
use flank::fem::mesh::Mesh;
use flank::fem::model::{Dirichlet, Model, Temperatures};
use flank::fem::static_analysis::{solve_static, SolveOptions, StaticSolution};
use flank::fem::stress::element_point_stresses;
use flank::mesh::structured::{box_mesh, distort_interior, BoxElement};

const TOLERANCE: f64 = 1e-6;
const E: f64 = 210e3;
const NU: f64 = 0.3;
const ALPHA: f64 = 1.2e-5;
const T0: f64 = 20.0;
const DT: f64 = 100.0;

const KINDS: [(BoxElement, &str); 3] = [
    (BoxElement::Hex20, "c3d20"),
    (BoxElement::Hex20R, "c3d20r"),
    (BoxElement::Wedge15, "c3d15"),
];

/// A model on `mesh` with α and the temperatures T0 (uniform) and `t(x)`.
fn heated(mesh: Mesh, t: impl Fn([f64; 3]) -> f64) -> Model {
    let mut model = common::model_from_mesh(mesh, E, NU);
    model.materials[0].expansion = Some(ALPHA);
    let nn = model.mesh.node_count();
    model.temperatures = Some(Temperatures {
        initial: vec![T0; nn],
        current: model.mesh.coords.iter().map(|&x| t(x)).collect(),
    });
    model
}

/// The node at `x` (a corner of the box).
fn node_at(model: &Model, x: [f64; 3]) -> usize {
    model
        .mesh
        .coords
        .iter()
        .position(|c| (0..3).all(|i| (c[i] - x[i]).abs() < 1e-9))
        .unwrap_or_else(|| panic!("no node at {x:?}"))
}

fn hold(model: &mut Model, node: usize, comps: &[usize]) {
    for &component in comps {
        model.dirichlet.push(Dirichlet {
            node,
            component,
            value: 0.0,
        });
    }
}

/// Statically determinate supports of the box [0, l] × [0, w] × …: the
/// origin in x, y, z, (l, 0, 0) in y, z, (0, w, 0) in z; the node sets
/// P0, PX, PY name them.
fn three_two_one(model: &mut Model, l: f64, w: f64) {
    for (name, x, comps) in [
        ("P0", [0.0, 0.0, 0.0], &[0, 1, 2][..]),
        ("PX", [l, 0.0, 0.0], &[1, 2][..]),
        ("PY", [0.0, w, 0.0], &[2][..]),
    ] {
        let n = node_at(model, x);
        hold(model, n, comps);
        model.mesh.node_sets.insert(name.to_string(), vec![n]);
    }
}

/// Writes the model as a deck (with `TOTALS=ONLY` reaction prints of the
/// node sets `rf_sets` and an integration-point stress print), applies
/// `edit` to the text, reads it back and solves it.
fn write_read_solve(
    model: &Model,
    name: &str,
    rf_sets: &[&str],
    edit: impl Fn(String) -> String,
) -> (PathBuf, Model, StaticSolution) {
    let dir = common::scratch_dir(&format!("thermal_{name}"));
    let path = dir.join(format!("{name}.inp"));
    write_deck(model, &path).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let prints: String = rf_sets
        .iter()
        .map(|s| format!("*NODE PRINT, NSET={s}, TOTALS=ONLY\nRF\n"))
        .collect();
    let text = text.replace(
        "*END STEP",
        &format!("{prints}*EL PRINT, ELSET=EALL\nS\n*END STEP"),
    );
    std::fs::write(&path, edit(text)).unwrap();
    let parsed = read_deck(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
    assert!(parsed.model.temperatures.is_some(), "{name}");
    let sol = solve_static(&parsed.model, &SolveOptions::default())
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    (path, parsed.model, sol)
}

/// Σ of ccx's RF (the internal force f_int) over the set: flank's reaction
/// is f_int − f_ext with f_ext the mechanical loads.
fn total_internal_force(model: &Model, sol: &StaticSolution, set: &str) -> [f64; 3] {
    let r = sol.reaction.as_ref().expect("reactions");
    let f = load_vector(model).unwrap();
    let mut t = [0.0; 3];
    for &n in &model.mesh.node_sets[set] {
        for i in 0..3 {
            t[i] += r[3 * n + i] + f[3 * n + i];
        }
    }
    t
}

fn norm(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

/// flank's stresses at the integration points, by (element label, point
/// 1-based), in ccx's component order xx, yy, zz, xy, xz, yz.
fn point_stresses(model: &Model, sol: &StaticSolution) -> HashMap<(u64, usize), [f64; 6]> {
    let mut out = HashMap::new();
    for (e, el) in model.mesh.elements.iter().enumerate() {
        let ps = element_point_stresses(model, e, &sol.displacement).unwrap();
        for (g, s) in ps.stress.iter().enumerate() {
            out.insert((el.label, g + 1), [s[0], s[1], s[2], s[3], s[5], s[4]]);
        }
    }
    out
}

/// The `stresses (elem, integ.pnt.,sxx,syy,szz,sxy,sxz,syz)` block of a
/// ccx .dat file.
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

/// flank against ccx on the deck: displacements (max |Δu| / max |u|), the
/// total reactions of `rf_sets` (|ΔRF| / `force_scale`) and every
/// integration point's stress (max |Δσ| / `stress_scale`). The scales are
/// the case's own magnitudes (E α ΔT and E α ΔT A: a stress-free case
/// prints ccx's round-off as its stresses).
#[allow(clippy::too_many_arguments)]
fn compare_with_ccx(
    name: &str,
    deck: &Path,
    model: &Model,
    sol: &StaticSolution,
    rf_sets: &[&str],
    force_scale: f64,
    stress_scale: f64,
) -> Option<(f64, f64, f64)> {
    if !common::ccx_available() {
        return None;
    }
    let work = common::scratch_dir(&format!("thermal_ccx_{name}"));
    let ccx = common::run_ccx(deck, &work);
    assert_eq!(ccx.displacements.len(), model.mesh.node_count(), "{name}");
    let du = flank::ccx::relative_difference(&model.mesh, &sol.displacement, &ccx.displacements)
        .unwrap();
    let totals = ccx.totals();
    let mut drf = 0.0f64;
    for set in rf_sets {
        let rf_ccx = *totals
            .get(&set.to_ascii_uppercase())
            .unwrap_or_else(|| panic!("{name}: ccx printed no total force of {set}: {totals:?}"));
        let rf = total_internal_force(model, sol, set);
        drf =
            drf.max(norm([rf[0] - rf_ccx[0], rf[1] - rf_ccx[1], rf[2] - rf_ccx[2]]) / force_scale);
    }
    let ours = point_stresses(model, sol);
    let theirs = ccx_point_stresses(&ccx.dat);
    assert_eq!(
        theirs.len(),
        ours.len(),
        "{name}: ccx printed {} point stresses",
        theirs.len()
    );
    let mut ds = 0.0f64;
    for (key, s) in &ours {
        let c = theirs
            .get(key)
            .unwrap_or_else(|| panic!("{name}: no ccx stress at {key:?}"));
        for k in 0..6 {
            ds = ds.max((s[k] - c[k]).abs() / stress_scale);
        }
    }
    println!(
        "VERIFY thermal_strain {name:<24} nodes {:>4}  ccx: max|du|/max|u| = {du:.2e}, |dRF|/F = {drf:.2e}, max|dS|/S = {ds:.2e} ({} points)  (tol {TOLERANCE:.0e})",
        model.mesh.node_count(),
        ours.len()
    );
    assert!(
        du <= TOLERANCE,
        "{name}: displacements differ from ccx by {du:.3e}"
    );
    assert!(
        drf <= TOLERANCE,
        "{name}: reactions differ from ccx by {drf:.3e}"
    );
    assert!(
        ds <= TOLERANCE,
        "{name}: stresses differ from ccx by {ds:.3e}"
    );
    Some((du, drf, ds))
}

/// max over the nodes of |u − u_ref(x)| / max |u_ref|.
fn field_error(model: &Model, sol: &StaticSolution, u_ref: impl Fn([f64; 3]) -> [f64; 3]) -> f64 {
    let mut err = 0.0f64;
    let mut scale = 0.0f64;
    for (n, &x) in model.mesh.coords.iter().enumerate() {
        let want = u_ref(x);
        for (i, w) in want.iter().enumerate() {
            err = err.max((sol.displacement[3 * n + i] - w).abs());
        }
        scale = scale.max(norm(want));
    }
    err / scale
}

/// max over all integration points of |σ − σ_ref| / `scale`.
fn stress_error(model: &Model, sol: &StaticSolution, want: [f64; 6], scale: f64) -> f64 {
    let mut err = 0.0f64;
    for s in point_stresses(model, sol).values() {
        for k in 0..6 {
            err = err.max((s[k] - want[k]).abs() / scale);
        }
    }
    err
}

/// A free bar 40 × 10 × 10 heated uniformly by ΔT, held statically
/// determinately: u = α ΔT x exactly, no stress, no reaction. ccx on the
/// same deck, once more with `*EXPANSION, ZERO=100.` (no effect with a
/// constant α).
#[test]
fn free_bar_uniform_heating() {
    let (l, w) = (40.0, 10.0);
    for (kind, tag) in KINDS {
        let mut model = heated(box_mesh([l, w, w], [4, 2, 2], kind), |_| T0 + DT);
        three_two_one(&mut model, l, w);
        let name = format!("free_bar_{tag}");
        let (deck, parsed, sol) = write_read_solve(&model, &name, &["P0"], |s| s);
        let eth = ALPHA * DT;
        let e_u = field_error(&parsed, &sol, |x| [eth * x[0], eth * x[1], eth * x[2]]);
        let e_s = stress_error(&parsed, &sol, [0.0; 6], E * eth);
        println!(
            "VERIFY thermal_strain {name:<24} vs u = αΔT x: {e_u:.2e}; max|σ|/(EαΔT) = {e_s:.2e}"
        );
        assert!(e_u < 1e-8, "{name}: {e_u:.3e} from u = αΔT x");
        assert!(e_s < 1e-8, "{name}: stress {e_s:.3e} in a free bar");
        compare_with_ccx(
            &name,
            &deck,
            &parsed,
            &sol,
            &["P0"],
            E * eth * w * w,
            E * eth,
        );
        if kind == BoxElement::Hex20 && common::ccx_available() {
            // ZERO= on the same deck: ccx's answer does not move
            let text = std::fs::read_to_string(&deck).unwrap();
            let zero = deck.with_file_name("zero.inp");
            std::fs::write(
                &zero,
                text.replace("*EXPANSION\n", "*EXPANSION, ZERO=100.\n"),
            )
            .unwrap();
            let parsed_zero = read_deck(&zero).unwrap().model;
            compare_with_ccx(
                "free_bar_c3d20_zero",
                &zero,
                &parsed_zero,
                &sol,
                &["P0"],
                E * eth * w * w,
                E * eth,
            );
        }
    }
}

/// The bar held axially at both ends (u_x = 0 on X0 and X1, laterally
/// free): σ_xx = −E α ΔT, the other components zero, u_y = (1 + ν) α ΔT y,
/// u_z = (1 + ν) α ΔT z, and the end reaction E α ΔT A.
#[test]
fn clamped_bar_uniform_heating() {
    let (l, w) = (40.0, 10.0);
    for (kind, tag) in KINDS {
        let mut model = heated(box_mesh([l, w, w], [4, 2, 2], kind), |_| T0 + DT);
        common::fix_set(&mut model, "X0", &[0], 0.0);
        common::fix_set(&mut model, "X1", &[0], 0.0);
        let o = node_at(&model, [0.0, 0.0, 0.0]);
        hold(&mut model, o, &[1, 2]);
        let py = node_at(&model, [0.0, w, 0.0]);
        hold(&mut model, py, &[2]);
        let name = format!("clamped_bar_{tag}");
        let (deck, parsed, sol) = write_read_solve(&model, &name, &["X0", "X1"], |s| s);
        let eth = ALPHA * DT;
        let lat = (1.0 + NU) * eth;
        let e_u = field_error(&parsed, &sol, |x| [0.0, lat * x[1], lat * x[2]]);
        let s = E * eth;
        let e_s = stress_error(&parsed, &sol, [-s, 0.0, 0.0, 0.0, 0.0, 0.0], s);
        let rf = total_internal_force(&parsed, &sol, "X0");
        let e_rf = (norm(rf) - s * w * w).abs() / (s * w * w);
        println!("VERIFY thermal_strain {name:<24} vs σ_xx = −EαΔT: {e_s:.2e}; u vs (1+ν)αΔT (y, z): {e_u:.2e}; |RF(X0)| vs EαΔT A: {e_rf:.2e}");
        assert!(e_s < 1e-8, "{name}: stress {e_s:.3e} from −EαΔT");
        assert!(e_u < 1e-8, "{name}: {e_u:.3e} from the lateral expansion");
        assert!(e_rf < 1e-8, "{name}: end reaction {e_rf:.3e} from EαΔT A");
        compare_with_ccx(&name, &deck, &parsed, &sol, &["X0", "X1"], s * w * w, s);
    }
}

/// A free plate 40 × 30 × 4 with T = T0 + ΔT z / h (linear through the
/// thickness): the thermal strain α ΔT z / h is compatible, so the plate is
/// stress-free and bends with curvature κ = α ΔT / h:
/// u = κ (x z, y z, (z² − x² − y²)/2) + ω × x, ω = κ (w/2, −l/2, 0) from
/// the supports. Every element type represents the quadratic field exactly.
#[test]
fn plate_linear_gradient() {
    let (l, w, h) = (40.0, 30.0, 4.0);
    for (kind, tag) in KINDS {
        let mut model = heated(box_mesh([l, w, h], [4, 3, 2], kind), |x| T0 + DT * x[2] / h);
        three_two_one(&mut model, l, w);
        let name = format!("plate_gradient_{tag}");
        let (deck, parsed, sol) = write_read_solve(&model, &name, &["P0"], |s| s);
        let k = ALPHA * DT / h;
        let om = [k * w / 2.0, -k * l / 2.0, 0.0];
        let e_u = field_error(&parsed, &sol, |x| {
            [
                k * x[0] * x[2] + om[1] * x[2] - om[2] * x[1],
                k * x[1] * x[2] + om[2] * x[0] - om[0] * x[2],
                k * (x[2] * x[2] - x[0] * x[0] - x[1] * x[1]) / 2.0 + om[0] * x[1] - om[1] * x[0],
            ]
        });
        let e_s = stress_error(&parsed, &sol, [0.0; 6], E * ALPHA * DT);
        println!("VERIFY thermal_strain {name:<24} vs bending-free curvature αΔT/h: {e_u:.2e}; max|σ|/(EαΔT) = {e_s:.2e}");
        assert!(e_u < 1e-8, "{name}: {e_u:.3e} from the free plate's field");
        assert!(e_s < 1e-8, "{name}: stress {e_s:.3e} in a free plate");
        compare_with_ccx(
            &name,
            &deck,
            &parsed,
            &sol,
            &["P0"],
            E * ALPHA * DT * w * h,
            E * ALPHA * DT,
        );
    }
}

/// A cantilever 40 × 10 × 10 with curved interior edges, clamped at x = 0,
/// under a temperature quadratic in x and y and trigonometric in z (T
/// lies outside every element's interpolation: C3D20's trilinear projection
/// and C3D20R/C3D15's quadratic interpolation differ here) and a
/// nonuniform T0. ccx only: no closed form. Then the tip face's nodes lose
/// their initial-condition lines: flank refuses that deck, and ccx's answer
/// on it is flank's with its placeholder T0 = 1.2357111319 on those nodes
/// (what the refusal says).
#[test]
fn cantilever_nonuniform_temperature() {
    let (l, w) = (40.0, 10.0);
    for (kind, tag) in KINDS {
        let mut mesh = box_mesh([l, w, w], [4, 2, 2], kind);
        distort_interior(&mut mesh, 0.15, 7, false);
        let mut model = heated(mesh, |x| {
            T0 + DT * (x[0] / l).powi(2) - 30.0 * (x[1] / w) * (x[1] / w - 1.0)
                + 15.0 * (x[2] / w * 3.0).sin()
        });
        let t = model.temperatures.as_mut().unwrap();
        for (t0, x) in t.initial.iter_mut().zip(&model.mesh.coords) {
            *t0 = T0 + 5.0 * x[1] / w;
        }
        common::fix_set(&mut model, "X0", &[0, 1, 2], 0.0);
        let name = format!("cantilever_nonuniform_{tag}");
        let (deck, parsed, sol) = write_read_solve(&model, &name, &["X0"], |s| s);
        let scales = (E * ALPHA * DT * w * w, E * ALPHA * DT);
        compare_with_ccx(&name, &deck, &parsed, &sol, &["X0"], scales.0, scales.1);

        // the same deck without T0 on the tip face's nodes
        let tip: Vec<u64> = parsed.mesh.node_sets["X1"]
            .iter()
            .map(|&n| parsed.mesh.node_labels[n])
            .collect();
        let text = std::fs::read_to_string(&deck).unwrap();
        let mut edited = String::new();
        let mut initial = false;
        for line in text.lines() {
            if line.starts_with('*') {
                initial = line.starts_with("*INITIAL CONDITIONS");
            } else if initial {
                let label: u64 = line.split(',').next().unwrap().trim().parse().unwrap();
                if tip.contains(&label) {
                    continue;
                }
            }
            edited += line;
            edited.push('\n');
        }
        let no_t0 = deck.with_file_name("no_t0.inp");
        std::fs::write(&no_t0, &edited).unwrap();
        let err = read_deck(&no_t0)
            .expect_err("a deck without T0 on some nodes")
            .to_string();
        assert!(err.contains("has no initial temperature"), "{name}: {err}");
        let mut placeholder = parsed.clone();
        let t = placeholder.temperatures.as_mut().unwrap();
        for &n in &placeholder.mesh.node_sets["X1"] {
            t.initial[n] = 1.2357111319;
        }
        let sol = solve_static(&placeholder, &SolveOptions::default()).unwrap();
        let name = format!("no_t0_placeholder_{tag}");
        compare_with_ccx(
            &name,
            &no_t0,
            &placeholder,
            &sol,
            &["X0"],
            scales.0,
            scales.1,
        );
    }
}
