//! # Body loads: `*DLOAD` GRAV and CENTRIF with `*DENSITY`
//!
//! The consistent body load f_a = ∫ N_a ρ b dV (element stiffness rule) of
//! gravity (b = g n) and of the centrifugal load (b = ω² r⊥, undeformed
//! position; linear statics, no centrifugal stiffening) against
//! * CalculiX 2.20 on the same decks (written by flank's writer, read back
//!   by its reader): displacements of every node and the total reaction of
//!   the supported set, ≤ 1e-6 relative;
//! * closed forms: the total gravity load ρ g V (exact on a box), the
//!   cantilever's tip deflection under its own weight (Timoshenko beam,
//!   printed with its error), the rotating annular disc (plane-stress Lamé
//!   solution, Timoshenko & Goodier §32) and the thin rotating ring
//!   u = ρ ω² r³ / E.
//!
//! Units N, mm, s, t: steel ρ = 7.85e-9 t/mm³, g = 9810 mm/s².

#[path = "../common/mod.rs"]
mod common;

use std::path::{Path, PathBuf};

use flank::deck::{read_deck, write_deck};
use flank::fem::loads::load_vector;
use flank::fem::model::{BodyForce, BodyLoad, Model};
use flank::fem::static_analysis::{solve_static, SolveOptions, StaticSolution};
use flank::mesh::structured::{box_mesh, distort_interior, map_nodes, BoxElement};

const TOLERANCE: f64 = 1e-6;
const E: f64 = 210e3;
const NU: f64 = 0.3;
const RHO: f64 = 7.85e-9;
const G: f64 = 9810.0;
/// ω² of seed 002's racing pinion, 11 758 rpm: (11 758 · 2π / 60)².
const OMEGA2: f64 = 1.516e6;

fn with_body_load(mesh: flank::fem::mesh::Mesh, force: BodyForce) -> Model {
    let mut model = common::model_from_mesh(mesh, E, NU);
    model.materials[0].density = Some(RHO);
    model.body_loads = (0..model.mesh.elements.len())
        .map(|element| BodyLoad {
            element,
            force: force.clone(),
        })
        .collect();
    model
}

/// Writes the model as a deck (with a `TOTALS=ONLY` reaction print of the
/// node set `rf_set`), reads it back and solves it.
fn write_read_solve(model: &Model, name: &str, rf_set: &str) -> (PathBuf, Model, StaticSolution) {
    let dir = common::scratch_dir(&format!("body_loads_{name}"));
    let path = dir.join(format!("{name}.inp"));
    write_deck(model, &path).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    let text = text.replace(
        "*END STEP",
        &format!("*NODE PRINT, NSET={rf_set}, TOTALS=ONLY\nRF\n*END STEP"),
    );
    std::fs::write(&path, text).unwrap();
    let parsed = read_deck(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
    assert_eq!(parsed.model.body_loads.len(), model.body_loads.len());
    let sol = solve_static(&parsed.model, &SolveOptions::default())
        .unwrap_or_else(|e| panic!("{name}: {e}"));
    (path, parsed.model, sol)
}

/// Σ of the reactions over the node set `set`.
fn total_reaction(model: &Model, sol: &StaticSolution, set: &str) -> [f64; 3] {
    let r = sol.reaction.as_ref().expect("reactions");
    let mut t = [0.0; 3];
    for &n in &model.mesh.node_sets[set] {
        for i in 0..3 {
            t[i] += r[3 * n + i];
        }
    }
    t
}

fn norm(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

/// flank against ccx on the deck: displacements and the total reaction of
/// `rf_set` (ccx's deck set name is the upper-cased one).
fn compare_with_ccx(name: &str, deck: &Path, model: &Model, sol: &StaticSolution, rf_set: &str) {
    if !common::ccx_available() {
        return;
    }
    let work = common::scratch_dir(&format!("body_loads_ccx_{name}"));
    let ccx = common::run_ccx(deck, &work);
    assert_eq!(ccx.displacements.len(), model.mesh.node_count(), "{name}");
    let du = flank::ccx::relative_difference(&model.mesh, &sol.displacement, &ccx.displacements)
        .unwrap();
    let totals = ccx.totals();
    let rf_ccx = *totals
        .get(&rf_set.to_ascii_uppercase())
        .unwrap_or_else(|| panic!("{name}: ccx printed no total force of {rf_set}: {totals:?}"));
    // ccx's RF is the internal force f_int at the constrained nodes; flank's
    // reaction is f_int − f_ext (the body load carried by the support nodes
    // themselves is part of what the support holds): compare f_int.
    let f_ext = load_vector(model).unwrap();
    let mut rf = total_reaction(model, sol, rf_set);
    for &n in &model.mesh.node_sets[rf_set] {
        for i in 0..3 {
            rf[i] += f_ext[3 * n + i];
        }
    }
    let drf = norm([rf[0] - rf_ccx[0], rf[1] - rf_ccx[1], rf[2] - rf_ccx[2]]) / norm(rf_ccx);
    println!(
        "VERIFY body_loads {name:<22} nodes {:>5}  ccx: max|du|/max|u| = {du:.2e}, |dRF|/|RF| ({rf_set}) = {drf:.2e}  (tol {TOLERANCE:.0e})",
        model.mesh.node_count()
    );
    assert!(
        du <= TOLERANCE,
        "{name}: displacements differ from ccx by {du:.3e}"
    );
    assert!(
        drf <= TOLERANCE,
        "{name}: reactions differ from ccx by {drf:.3e}"
    );
}

/// Gravity along (0, 0.6, −0.8) on a 100 × 10 × 10 C3D20 cantilever
/// clamped at x = 0.
fn cantilever(distorted: bool) -> Model {
    let mut mesh = box_mesh([100.0, 10.0, 10.0], [10, 2, 2], BoxElement::Hex20);
    if distorted {
        distort_interior(&mut mesh, 0.15, 11, false);
    }
    let mut model = with_body_load(
        mesh,
        BodyForce::Gravity {
            acceleration: [0.0, 0.6 * G, -0.8 * G],
        },
    );
    common::fix_set(&mut model, "X0", &[0, 1, 2], 0.0);
    model
}

/// The total gravity load is ρ g V exactly (Σ N_a = 1, V of a box is
/// integrated exactly), the reactions balance it, and ccx agrees on a
/// cantilever with curved interior edges. The tip deflection under the
/// z part of the weight, q = 0.8 ρ g A per length, against Timoshenko's
/// beam: q L⁴/(8 E I) + q L²/(2 κ G A).
#[test]
fn gravity_cantilever_c3d20() {
    let model = cantilever(false);
    let f = load_vector(&model).unwrap();
    let v = 100.0 * 10.0 * 10.0;
    let fz: f64 = f.iter().skip(2).step_by(3).sum();
    let fy: f64 = f.iter().skip(1).step_by(3).sum();
    let (wz, wy) = (-0.8 * RHO * G * v, 0.6 * RHO * G * v);
    let e_total = ((fz - wz) / wz).abs().max(((fy - wy) / wy).abs());
    println!("VERIFY body_loads gravity total load        Σf = ({fy:.9e}, {fz:.9e}) N vs ρgV: rel. error {e_total:.1e}");
    assert!(e_total < 1e-13, "total gravity load off by {e_total:.2e}");

    let (deck, parsed, sol) = write_read_solve(&model, "grav_c3d20", "X0");
    let rf = total_reaction(&parsed, &sol, "X0");
    let e_rf = ((rf[2] + wz).abs() + (rf[1] + wy).abs()) / norm([0.0, wy, wz]);
    println!("VERIFY body_loads gravity reaction          Σ RF(X0) + ρgV: rel. {e_rf:.1e}");
    assert!(
        e_rf < 1e-9,
        "reactions do not balance the weight: {e_rf:.2e}"
    );

    // tip deflection (mean u_z over the tip face) against the beam
    let tip = &parsed.mesh.node_sets["X1"];
    let uz: f64 = tip
        .iter()
        .map(|&n| sol.displacement[3 * n + 2])
        .sum::<f64>()
        / tip.len() as f64;
    let beam = common::TipLoadedBeam {
        length: 100.0,
        height: 10.0,
        width: 10.0,
        young: E,
        poisson: NU,
        load: 0.0,
    };
    let q = 0.8 * RHO * G * 100.0;
    let i = 10.0 * 10f64.powi(3) / 12.0;
    let shear = E / (2.0 * (1.0 + NU));
    let w = q * 100f64.powi(4) / (8.0 * E * i)
        + q * 100f64.powi(2) / (2.0 * beam.cowper_kappa() * shear * 100.0);
    let e_beam = (-uz - w) / w;
    // a plausibility figure, not asserted: the clamp's Poisson effect and the
    // short beam (L/h = 10) are not in the beam theory (verification/cantilever:
    // −0.72 % under a tip load on 80 × 8 × 8)
    println!("VERIFY body_loads gravity tip deflection    flank {:.6e} mm, Timoshenko beam {w:.6e} mm: {:+.2} %", -uz, 100.0 * e_beam);
    compare_with_ccx("grav_c3d20", &deck, &parsed, &sol, "X0");

    let model = cantilever(true);
    let (deck, parsed, sol) = write_read_solve(&model, "grav_c3d20_curved", "X0");
    compare_with_ccx("grav_c3d20_curved", &deck, &parsed, &sol, "X0");
}

/// A quarter of an annular disc a ≤ r ≤ b, half of its thickness h
/// (0 ≤ z ≤ h/2, mid-plane z = 0 held in z), rotating about the z axis;
/// symmetry: u_y = 0 on θ = 0 (set Y0), u_x = 0 on θ = 90° (set Y1).
/// The CENTRIF axis is given through (0, 0, −50), not the origin.
fn disc(kind: BoxElement, a: f64, b: f64, h: f64, cells: [usize; 3]) -> Model {
    let mut mesh = box_mesh([b - a, std::f64::consts::FRAC_PI_2, 0.5 * h], cells, kind);
    map_nodes(&mut mesh, |p| {
        let r = a + p[0];
        [r * p[1].cos(), r * p[1].sin(), p[2]]
    });
    let mut model = with_body_load(
        mesh,
        BodyForce::Centrifugal {
            omega_squared: OMEGA2,
            point: [0.0, 0.0, -50.0],
            axis: [0.0, 0.0, 1.0],
        },
    );
    common::fix_set(&mut model, "Y0", &[1], 0.0);
    common::fix_set(&mut model, "Y1", &[0], 0.0);
    common::fix_set(&mut model, "Z0", &[2], 0.0);
    model
}

/// Plane-stress radial displacement of a free annular disc a ≤ r ≤ b
/// rotating at ω (Timoshenko & Goodier, Theory of Elasticity, §32):
/// u = ρω² r / (8E) [(3+ν)(1−ν)(a²+b²) + (3+ν)(1+ν) a²b²/r² − (1−ν²) r²].
fn lame_disc_u(a: f64, b: f64, r: f64) -> f64 {
    RHO * OMEGA2 * r / (8.0 * E)
        * ((3.0 + NU) * (1.0 - NU) * (a * a + b * b)
            + (3.0 + NU) * (1.0 + NU) * a * a * b * b / (r * r)
            - (1.0 - NU * NU) * r * r)
}

/// max over the mesh nodes of |u_r − u_ref(r)| / max u_ref, and of |u_θ|.
fn radial_error(model: &Model, sol: &StaticSolution, u_ref: impl Fn(f64) -> f64) -> f64 {
    let mut err = 0.0f64;
    let mut scale = 0.0f64;
    for (n, x) in model.mesh.coords.iter().enumerate() {
        let r = x[0].hypot(x[1]);
        let (c, s) = (x[0] / r, x[1] / r);
        let (ux, uy) = (sol.displacement[3 * n], sol.displacement[3 * n + 1]);
        let ur = ux * c + uy * s;
        let ut = -ux * s + uy * c;
        let want = u_ref(r);
        err = err.max((ur - want).abs()).max(ut.abs());
        scale = scale.max(want.abs());
    }
    err / scale
}

/// CENTRIF on a rotating annular disc (a = 40, b = 120, h = 4): ccx on
/// C3D20, C3D20R and C3D15 meshes, and the plane-stress Lamé solution.
#[test]
fn centrifugal_disc() {
    let (a, b, h) = (40.0, 120.0, 4.0);
    for (kind, name) in [
        (BoxElement::Hex20, "centrif_disc_c3d20"),
        (BoxElement::Hex20R, "centrif_disc_c3d20r"),
        (BoxElement::Wedge15, "centrif_disc_c3d15"),
    ] {
        let model = disc(kind, a, b, h, [8, 12, 1]);
        let (deck, parsed, sol) = write_read_solve(&model, name, "Y0");
        let e = radial_error(&parsed, &sol, |r| lame_disc_u(a, b, r));
        println!("VERIFY body_loads {name:<22} vs plane-stress Lamé disc: max|u − u_Lamé|/max u_Lamé = {e:.2e}");
        assert!(e < 2e-3, "{name}: {e:.3e} from the Lamé disc");
        compare_with_ccx(name, &deck, &parsed, &sol, "Y0");
    }
}

/// A thin rotating ring (r = 99 … 101, h = 2): u_r at the mean radius
/// against u = ρ ω² r³ / E (the hoop stress ρ ω² r² of a thin ring) and
/// against the Lamé disc of the same radii; ccx on C3D20 and C3D15.
#[test]
fn centrifugal_thin_ring() {
    let (a, b, h) = (99.0, 101.0, 2.0);
    for (kind, name) in [
        (BoxElement::Hex20, "centrif_ring_c3d20"),
        (BoxElement::Wedge15, "centrif_ring_c3d15"),
    ] {
        let model = disc(kind, a, b, h, [1, 24, 1]);
        let (deck, parsed, sol) = write_read_solve(&model, name, "Y0");
        let e_lame = radial_error(&parsed, &sol, |r| lame_disc_u(a, b, r));
        // u_r at the mean radius r = 100 (nodes there: the midside row), z = 0
        let mut ur = Vec::new();
        for (n, x) in parsed.mesh.coords.iter().enumerate() {
            let r = x[0].hypot(x[1]);
            if (r - 100.0).abs() < 1e-9 && x[2].abs() < 1e-12 {
                ur.push((sol.displacement[3 * n] * x[0] + sol.displacement[3 * n + 1] * x[1]) / r);
            }
        }
        assert!(!ur.is_empty());
        let mean = ur.iter().sum::<f64>() / ur.len() as f64;
        let thin = RHO * OMEGA2 * 100f64.powi(3) / E;
        let e_thin = (mean - thin) / thin;
        println!("VERIFY body_loads {name:<22} u_r(100) = {mean:.6e} mm; thin ring ρω²r³/E = {thin:.6e}: {e_thin:+.2e}; vs Lamé disc (all nodes) {e_lame:.2e}");
        assert!(e_thin.abs() < 1e-3, "{name}: thin ring {e_thin:.3e}");
        assert!(e_lame < 1e-3, "{name}: Lamé {e_lame:.3e}");
        compare_with_ccx(name, &deck, &parsed, &sol, "Y0");
    }
}
