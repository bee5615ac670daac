//! # Verification: Hertz line contact (cylinder on a flat), FE contact
//!
//! ## What
//!
//! A steel cylinder of radius R = 10 mm pressed onto a steel block by a line
//! load P′ = 1000 N/mm, E = 210 000 MPa, ν = 0.3 for both, frictionless.
//! 3D slice of thickness t = 0.1 mm with plane-strain constraints (u_z = 0
//! on both faces), half model (x ≥ 0, u_x = 0 on the symmetry plane), mesh
//! `flank::mesh::hertz::HertzMesh`: a flat block 6 × 6 mm held at its
//! bottom, and the cylinder's cap x ∈ [0, 6], loaded on its top face
//! (the plane through the axis) by the uniform pressure P′/(2W). The
//! cylinder's vertical motion is held only by contact (a floating mode:
//! its amplitude is an unknown of the contact problem). C3D20 elements,
//! `fine` equal cells over [0, 1.5a] at the contact, growing by 1.25 away
//! from it; slave = the cylinder's arc (element faces), master = the block's
//! top (element faces), node-to-surface, hard contact unless stated.
//!
//! ## Reference (Hertz line contact)
//!
//! ```text
//!   1/E* = (1−ν₁²)/E₁ + (1−ν₂²)/E₂,   a = √(4P′R/(πE*)),   p_max = √(P′E*/(πR)) = 2P′/(πa),
//!   p(x) = p_max √(1 − x²/a²)
//! ```
//!
//! Here E* = 115 384.6 MPa, a = 0.33219 mm (a/R = 0.033), p_max = 1916.46 MPa.
//!
//! ## What is measured
//!
//! * p_max: the largest contact pressure flank reports (`contact.csv`
//!   column `pressure`: nodal forces spread over the slave faces, face means,
//!   averaged back to the nodes);
//! * a (fit): the half-width from a least-squares fit of p² = p₀²(1 − x²/a²)
//!   to the nodes with p ≥ p_max/2 (the edge itself is resolved only to a
//!   cell); a (nodes): the midpoint between the last closed and the first
//!   open slave node, reported with its ± half-cell resolution;
//! * the total contact force against P′t/2 (equilibrium of the floating
//!   cylinder, to round-off), the KKT residuals of the active set.
//!
//! ## Tolerances
//!
//! 3 % on p_max and a (fit) from `fine` = 16 (cell a/10.7) on, as the issue
//! asks; the coarser meshes are reported. Cross-code: flank and CalculiX 2.20
//! on the same deck with the same linear penalty (slope given) agree on the
//! total force to 1e-3 and on the largest nodal pressure λ/A to 1 %. The
//! penalty sweep must converge monotonically to the hard-contact answer.
//!
//! Run: `cargo test --release --test hertz_contact -- --nocapture`
//! (`-- --ignored` for the finest meshes).

#[path = "../common/mod.rs"]
mod common;

use std::collections::HashMap;
use std::f64::consts::PI;
use std::time::Instant;

use flank::contact::pairing::NormalLaw;
use flank::contact::{solve_contact, ContactOptions, ContactSolution, PressureOverclosure};
use flank::fem::model::Model;
use flank::mesh::hertz::{hertz_model, HertzLoad, HertzMesh};
use flank::mesh::structured::BoxElement;

const E: f64 = 210_000.0;
const NU: f64 = 0.3;
const R: f64 = 10.0;
/// Line load of the whole cylinder (N/mm).
const LINE_LOAD: f64 = 1000.0;
const THICKNESS: f64 = 0.1;

/// E*, a, p_max of the closed form.
fn hertz() -> (f64, f64, f64) {
    let estar = E / (2.0 * (1.0 - NU * NU));
    let a = (4.0 * LINE_LOAD * R / (PI * estar)).sqrt();
    let pmax = (LINE_LOAD * estar / (PI * R)).sqrt();
    (estar, a, pmax)
}

fn geometry(fine: usize) -> HertzMesh {
    let (_, a, _) = hertz();
    HertzMesh {
        radius: R,
        width: 6.0,
        depth: 6.0,
        thickness: THICKNESS,
        fine_extent: 1.5 * a,
        fine_cells: fine,
        growth: 1.25,
        element: BoxElement::Hex20,
    }
}

fn model(fine: usize, load: HertzLoad, law: PressureOverclosure) -> Model {
    hertz_model(&geometry(fine), E, NU, load, law).expect("Hertz model")
}

/// Figures of one solve.
#[derive(Debug, Clone)]
struct Figures {
    pmax: f64,
    a_fit: f64,
    a_nodes: f64,
    half_cell: f64,
    force: f64,
    approach: f64,
    penetration: f64,
    iterations: usize,
    active: usize,
    columns: usize,
    violation: f64,
    complementarity: f64,
    equilibrium: f64,
    dofs: usize,
    seconds: f64,
    /// assembly + factorization, active set + final solve (s)
    factor_s: f64,
    contact_s: f64,
}

/// Least-squares fit p² = c₀ + c₁x² over the points; a = √(−c₀/c₁).
fn fit_half_width(points: &[(f64, f64)]) -> f64 {
    let n = points.len() as f64;
    let (mut sx, mut sy, mut sxx, mut sxy) = (0.0, 0.0, 0.0, 0.0);
    for &(x, p) in points {
        let (u, v) = (x * x, p * p);
        sx += u;
        sy += v;
        sxx += u * u;
        sxy += u * v;
    }
    let c1 = (n * sxy - sx * sy) / (n * sxx - sx * sx);
    let c0 = (sy - c1 * sx) / n;
    (-c0 / c1).sqrt()
}

fn figures(model: &Model, sol: &ContactSolution, seconds: f64) -> Figures {
    let coords = &model.mesh.coords;
    let pmax = sol.slaves.iter().fold(0.0f64, |m, s| m.max(s.pressure));
    let pts: Vec<(f64, f64)> = sol
        .slaves
        .iter()
        .filter(|s| s.pressure >= 0.5 * pmax)
        .map(|s| (coords[s.node][0], s.pressure))
        .collect();
    let last_closed = sol
        .slaves
        .iter()
        .filter(|s| s.force > 0.0)
        .map(|s| coords[s.node][0])
        .fold(0.0f64, f64::max);
    let first_open = sol
        .slaves
        .iter()
        .filter(|s| coords[s.node][0] > last_closed)
        .map(|s| coords[s.node][0])
        .fold(f64::INFINITY, f64::min);
    let top = &model.mesh.node_sets["CYL_TOP"];
    let approach = -top
        .iter()
        .map(|&n| sol.solution.displacement[3 * n + 1])
        .sum::<f64>()
        / top.len() as f64;
    let a = &sol.summary.active_set;
    Figures {
        pmax,
        a_fit: fit_half_width(&pts),
        a_nodes: 0.5 * (last_closed + first_open),
        half_cell: 0.5 * (first_open - last_closed),
        force: sol.summary.pairs[0].total_normal_force,
        approach,
        penetration: sol.summary.pairs[0].max_penetration,
        iterations: a.iterations,
        active: a.active,
        columns: a.columns,
        violation: a.max_violation,
        complementarity: a.complementarity,
        equilibrium: a.equilibrium,
        dofs: sol.solution.stats.dofs,
        seconds,
        factor_s: sol.summary.factorization_s,
        contact_s: sol.summary.contact_solve_s,
    }
}

fn run(fine: usize, load: HertzLoad, law: PressureOverclosure) -> (Model, Figures) {
    let m = model(fine, load, law);
    let t = Instant::now();
    let sol = solve_contact(
        &m,
        &ContactOptions {
            recover_stress: false,
            ..Default::default()
        },
    )
    .expect("contact solve");
    let f = figures(&m, &sol, t.elapsed().as_secs_f64());
    (m, f)
}

/// Convergence of p_max and a under mesh refinement, hard contact.
fn convergence(levels: &[usize], assert_from: usize) {
    let (_, a, pmax) = hertz();
    println!(
        "Hertz: a = {a:.6} mm, p_max = {pmax:.3} MPa; load P′ = {LINE_LOAD} N/mm, slice t = {THICKNESS} mm"
    );
    println!("| fine | h/a | DOFs | p_max (MPa) | err | a fit (mm) | err | a nodes (mm) | err ± | iter | closed | solves | violation (mm) | compl. (N·mm) | K₀ (s) | contact (s) | total (s) |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for &fine in levels {
        let (_, f) = run(fine, HertzLoad::Force(LINE_LOAD), PressureOverclosure::Hard);
        let h = 1.5 / fine as f64;
        let ep = f.pmax / pmax - 1.0;
        let ea = f.a_fit / a - 1.0;
        let en = f.a_nodes / a - 1.0;
        println!(
            "| {fine} | {h:.3} | {} | {:.2} | {:+.2} % | {:.5} | {:+.2} % | {:.5} | {:+.1} % ± {:.1} % | {} | {} | {} | {:.1e} | {:.1e} | {:.2} | {:.2} | {:.2} |",
            f.dofs,
            f.pmax,
            100.0 * ep,
            f.a_fit,
            100.0 * ea,
            f.a_nodes,
            100.0 * en,
            100.0 * f.half_cell / a,
            f.iterations,
            f.active,
            f.columns,
            f.violation,
            f.complementarity,
            f.factor_s,
            f.contact_s,
            f.seconds
        );
        // the floating cylinder is in equilibrium with the contact forces
        let expected = 0.5 * LINE_LOAD * THICKNESS;
        assert!(
            (f.force / expected - 1.0).abs() < 1e-10,
            "force {}",
            f.force
        );
        assert!(f.equilibrium < 1e-12 && f.violation < 1e-9 && f.complementarity < 1e-9);
        if fine >= assert_from {
            common::check(
                "hertz_contact",
                &format!("p_max, fine {fine}"),
                f.pmax,
                pmax,
                0.03,
                f.seconds,
            );
            common::check(
                "hertz_contact",
                &format!("a (fit), fine {fine}"),
                f.a_fit,
                a,
                0.03,
                f.seconds,
            );
        }
    }
}

#[test]
fn hertz_convergence() {
    convergence(&[4, 8, 16, 32], 16);
}

#[test]
#[ignore]
fn hertz_convergence_refined() {
    convergence(&[64, 128], 64);
}

// ---------------------------------------------------------------------------
// Subsurface stress below the contact (issue 20, point 4)
// ---------------------------------------------------------------------------

/// Line load of the subsurface case (N/mm): a tenth of the contact
/// cases', so that a = 0.105 mm is small against the block (9 × 30 mm:
/// 86 a wide, 285 a deep). On the 6 × 6 mm block at 1000 N/mm (18 a × 18 a)
/// the finite block shifted σ_x by ≈ +0.03 p₀ everywhere below the contact
/// (first run, README), a 5 % error in τ₁ that is the block's, not the
/// method's.
const SUBSURFACE_LOAD: f64 = 100.0;

/// The subsurface case's model: the contact cases' geometry with a wider,
/// deeper block and the slice 0.3 a thick.
fn subsurface_model(fine: usize) -> (Model, f64, f64) {
    let estar = E / (2.0 * (1.0 - NU * NU));
    let a = (4.0 * SUBSURFACE_LOAD * R / (PI * estar)).sqrt();
    let p0 = (SUBSURFACE_LOAD * estar / (PI * R)).sqrt();
    let g = HertzMesh {
        width: 9.0,
        depth: 30.0,
        thickness: 0.3 * a,
        fine_extent: 1.5 * a,
        ..geometry(fine)
    };
    let m = hertz_model(
        &g,
        E,
        NU,
        HertzLoad::Force(SUBSURFACE_LOAD),
        PressureOverclosure::Hard,
    )
    .expect("Hertz model");
    (m, a, p0)
}

/// Depth below which the FE field is compared (units of a): within about
/// two fine cells of the surface the node-to-surface contact loads the
/// block by nodal forces of the cylinder's face nodes (the corner nodes of
/// 8-node faces carry none, see above), and the stresses there are those of
/// that nodal load pattern, not of a smooth Hertz traction (first run:
/// σ_z = −1.6 p₀ at the surface node). Fixed before the second run.
const SUBSURFACE_FROM: f64 = 0.25;

/// The block's nodal stresses on the symmetry line x = 0 (front face
/// z = 0) against the closed form below a frictionless Hertz contact
/// (McEwen 1949, `flank::lubrication::subsurface::stress` with μ = 0),
/// evaluated with the closed-form p₀ and a: the whole chain (FE contact
/// pressure → FE stress field → nodal recovery) against Johnson §4.2's
/// field. Mapping: closed-form x, depth z, σ_x, σ_z, τ_xz, σ_y =
/// FE x, −y, σ_xx, σ_yy, τ_xy, σ_zz (plane strain through u_z = 0).
/// Returns (largest principal shear τ₁/p₀, its depth/a, largest |error|
/// of τ₁/p₀ over depths ≤ 3a, von Mises maximum/p₀ and its depth/a, the
/// nodes compared).
fn subsurface_profile(fine: usize) -> ([f64; 5], [f64; 2], usize, f64) {
    use flank::lubrication::subsurface::stress;
    let (m, a, p0) = subsurface_model(fine);
    let t = Instant::now();
    let sol = solve_contact(&m, &ContactOptions::default()).expect("contact solve");
    let secs = t.elapsed().as_secs_f64();
    let rec = sol.solution.recovery.as_ref().expect("stresses recovered");
    // block nodes on the line x = 0, z = 0, depth ≤ 3a (the block's own
    // nodes: the cylinder's are other nodes)
    let block: std::collections::HashSet<usize> = m.mesh.element_sets["FLAT"]
        .iter()
        .flat_map(|&e| m.mesh.elements[e].nodes.iter().copied())
        .collect();
    let mut line: Vec<(f64, [f64; 6])> = block
        .iter()
        .filter(|&&n| {
            let c = m.mesh.coords[n];
            c[0].abs() < 1e-12 && c[2].abs() < 1e-12 && -c[1] <= 3.0 * a
        })
        .map(|&n| (-m.mesh.coords[n][1] / a, rec.stress[n]))
        .collect();
    line.sort_by(|x, y| x.0.total_cmp(&y.0));
    let shear = |s: &[f64; 6]| {
        // largest principal shear of the full tensor in the x–y plane
        // (τ_yz = τ_xz = 0 on the symmetry plane of a plane-strain slice)
        let c = 0.5 * (s[0] + s[1]);
        let r = (0.25 * (s[0] - s[1]).powi(2) + s[3] * s[3]).sqrt();
        let p = [c + r, c - r, s[2]];
        0.5 * (p.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
            - p.iter().cloned().fold(f64::INFINITY, f64::min))
    };
    let (mut tau, mut at, mut err, mut vm, mut vm_at) = (0.0, 0.0, 0.0f64, 0.0, 0.0);
    let mut around = [0.0, 0.0];
    let mut compared = 0;
    println!("| depth z/a | τ₁/p₀ FE | τ₁/p₀ closed form | σ_x/p₀ FE | closed | σ_z/p₀ FE | closed | σ_y/p₀ FE | closed |");
    println!("|---|---|---|---|---|---|---|---|---|");
    for (i, (z, s)) in line.iter().enumerate() {
        let c = stress(0.0, *z, 0.0, NU);
        let t1 = shear(s) / p0;
        let zone = if *z < SUBSURFACE_FROM {
            " (surface zone)"
        } else {
            ""
        };
        println!(
            "| {z:.3}{zone} | {t1:.4} | {:.4} | {:.4} | {:.4} | {:.4} | {:.4} | {:.4} | {:.4} |",
            c.max_shear(),
            s[0] / p0,
            c.sigma_x,
            s[1] / p0,
            c.sigma_z,
            s[2] / p0,
            c.sigma_y
        );
        if *z < SUBSURFACE_FROM {
            continue;
        }
        compared += 1;
        err = err.max((t1 - c.max_shear()).abs());
        if t1 > tau {
            (tau, at) = (t1, *z);
            // the neighbouring nodes: the depth resolution there
            around = [
                line[i.saturating_sub(1)].0,
                line[(i + 1).min(line.len() - 1)].0,
            ];
        }
        let v = flank::fem::material::von_mises(s) / p0;
        if v > vm {
            (vm, vm_at) = (v, *z);
        }
    }
    ([tau, at, err, vm, vm_at], around, compared, secs)
}

/// The largest subsurface principal shear of the FE field within 3 % of
/// the closed form's 0.3003 p₀ (issue 20's acceptance) at fine 16 and 32,
/// its depth between the nodes next to the FE maximum (the block's cells
/// grow by 1.25 from h at the surface: about 0.14 a apart there at fine
/// 16); the von Mises maximum (0.5575 p₀ at 0.704 a) within 3 % too.
#[test]
fn subsurface_stress_below_the_contact() {
    let closed = flank::lubrication::subsurface::max_stresses(0.0, NU);
    println!("closed form (μ = 0, ν = {NU}): {closed:?}");
    for fine in [16, 32] {
        let ([tau, at, err, vm, vm_at], around, nodes, secs) = subsurface_profile(fine);
        let h = 1.5 / fine as f64;
        println!(
            "fine {fine} (cell {h:.4} a): τ₁ max {tau:.4} p₀ at {at:.3} a, von Mises max {vm:.4} p₀ at {vm_at:.3} a, largest |Δτ₁| {err:.4} p₀ over the {nodes} nodes from 0.25 a to 3 a, {secs:.2} s"
        );
        common::check(
            "hertz_contact",
            &format!("subsurface τ₁ max, fine {fine}"),
            tau,
            closed.max_shear,
            0.03,
            secs,
        );
        common::check(
            "hertz_contact",
            &format!("subsurface von Mises max, fine {fine}"),
            vm,
            closed.max_von_mises,
            0.03,
            secs,
        );
        let depth = closed.max_shear_at[1];
        assert!(
            around[0] <= depth && depth <= around[1],
            "depth of τ₁ max {at} a (nodes {around:?}) vs {depth} a"
        );
    }
}

// ---------------------------------------------------------------------------
// Cross-code: the same deck in flank (`flank solve`) and CalculiX
// ---------------------------------------------------------------------------

/// Contact stresses printed by ccx in a .dat file (set totals:
/// [`common::CcxRun::totals`]).
struct CcxDat {
    /// slave node label → (pressure, normal overclosure)
    cstr: HashMap<u64, f64>,
    cdis: HashMap<u64, f64>,
}

fn parse_ccx_dat(text: &str) -> CcxDat {
    let mut out = CcxDat {
        cstr: HashMap::new(),
        cdis: HashMap::new(),
    };
    let mut mode = 0;
    for line in text.lines() {
        let t = line.trim();
        if t.starts_with("contact stress") {
            mode = 1;
            out.cstr.clear();
            continue;
        }
        if t.starts_with("relative contact displacement") {
            mode = 2;
            out.cdis.clear();
            continue;
        }
        if t.starts_with("total force") {
            mode = 0;
            continue;
        }
        if t.is_empty() {
            continue;
        }
        let f: Vec<&str> = t.split_whitespace().collect();
        match mode {
            1 | 2 if f.len() == 4 => {
                if let (Ok(n), Ok(v)) = (f[0].parse::<u64>(), f[1].parse::<f64>()) {
                    if mode == 1 {
                        out.cstr.insert(n, v);
                    } else {
                        out.cdis.insert(n, v);
                    }
                    continue;
                }
                mode = 0;
            }
            _ => mode = 0,
        }
    }
    out
}

/// (x, normal force, pressure, nodal pressure) of a `contact.csv` row.
type ContactRow = (f64, f64, f64, f64);

/// Runs `flank solve` on a deck; returns (contact.csv rows: label → (x,
/// force, pressure, nodal pressure), summary.json).
fn flank_solve(
    deck: &std::path::Path,
    out: &std::path::Path,
) -> (HashMap<u64, ContactRow>, serde_json::Value) {
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_flank"))
        .args([
            "solve",
            deck.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--quiet",
            "--no-stress",
        ])
        .output()
        .expect("run flank");
    assert!(
        o.status.success(),
        "flank solve failed: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    let csv = std::fs::read_to_string(out.join("contact.csv")).unwrap();
    let mut rows = HashMap::new();
    for line in csv.lines().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        let v = |k: usize| f[k].parse::<f64>().unwrap();
        rows.insert(f[1].parse::<u64>().unwrap(), (v(2), v(6), v(7), v(8)));
    }
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    (rows, summary)
}

/// Penalty sweep: slopes 1e-2 … 1e4 × flank's automatic default converge to
/// the hard-contact answer (p_max, a, approach of the cylinder).
#[test]
fn penalty_sweep() {
    let fine = 16;
    let (_, a, pmax) = hertz();
    let (_, hard) = run(fine, HertzLoad::Force(LINE_LOAD), PressureOverclosure::Hard);
    // the automatic slope of this mesh
    let m = model(
        fine,
        HertzLoad::Force(LINE_LOAD),
        PressureOverclosure::Linear {
            slope: None,
            tension: None,
            c0: None,
        },
    );
    let sol = solve_contact(
        &m,
        &ContactOptions {
            recover_stress: false,
            ..Default::default()
        },
    )
    .unwrap();
    let NormalLaw::Penalty {
        slope: eps0,
        automatic: true,
    } = sol.summary.pairs[0].law
    else {
        panic!("expected the automatic penalty");
    };
    println!(
        "fine {fine}: automatic penalty slope ε₀ = {eps0:.4e} MPa/mm (10 × constrained modulus / element depth {:.4e} mm)",
        sol.summary.pairs[0].element_size
    );
    println!("| ε/ε₀ | p_max (MPa) | vs hard | a fit (mm) | vs hard | approach (mm) | vs hard | max penetration (mm) | iter | time (s) |");
    println!("|---|---|---|---|---|---|---|---|---|---|");
    let mut last = f64::INFINITY;
    let mut rows = Vec::new();
    for k in -2..=4 {
        let factor = 10f64.powi(k);
        let (_, f) = run(
            fine,
            HertzLoad::Force(LINE_LOAD),
            PressureOverclosure::Linear {
                slope: Some(factor * eps0),
                tension: None,
                c0: None,
            },
        );
        let d = [
            f.pmax / hard.pmax - 1.0,
            f.a_fit / hard.a_fit - 1.0,
            f.approach / hard.approach - 1.0,
        ];
        println!(
            "| {factor:.0e} | {:.2} | {:+.2e} | {:.5} | {:+.2e} | {:.6e} | {:+.2e} | {:.2e} | {} | {:.2} |",
            f.pmax, d[0], f.a_fit, d[1], f.approach, d[2], f.penetration, f.iterations, f.seconds
        );
        // the approach difference is the penalty's compliance: it shrinks
        // monotonically with the slope
        assert!(
            d[2] > 0.0 && d[2] < last,
            "approach difference must fall: {d:?}"
        );
        last = d[2];
        rows.push((factor, d));
    }
    println!(
        "| hard | {:.2} | | {:.5} | | {:.6e} | | {:.2e} | {} | {:.2} |",
        hard.pmax, hard.a_fit, hard.approach, hard.penetration, hard.iterations, hard.seconds
    );
    let (_, d) = rows.last().unwrap();
    assert!(
        d.iter().all(|v| v.abs() < 1e-3),
        "1e4 × ε₀ must give the hard answer to 1e-3: {d:?}"
    );
    let (_, d1) = rows[2];
    common::check(
        "hertz_contact",
        "p_max, default penalty",
        hard.pmax * (1.0 + d1[0]),
        pmax,
        0.03,
        0.0,
    );
    common::check(
        "hertz_contact",
        "a (fit), default penalty",
        hard.a_fit * (1.0 + d1[1]),
        a,
        0.03,
        0.0,
    );
}

/// ccx options appended to the written deck: totals of the reaction
/// forces, one increment with enough iterations, contact springs generated
/// up to a clearance c₀√A with c₀ = 0.3 (ccx's default 1e-3 pairs only the
/// nodes touching at the start).
fn ccx_deck(m: &Model) -> String {
    let mut text = flank::deck::format_deck(m).unwrap();
    text = text.replace(
        "*STATIC\n",
        "*STATIC\n*CONTROLS, PARAMETERS=TIME INCREMENTATION\n30, 30, 9, 200, 10, 4, 0, 5\n",
    );
    text = text.replace(
        "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=HARD\n",
        "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=HARD\n, 0.01, 0.3\n",
    );
    text.replace(
        "*END STEP",
        "*NODE PRINT, NSET=FLAT_BOTTOM, TOTALS=ONLY\nRF\n*END STEP",
    )
}

/// One deck in both codes: (flank total force, ccx total force, flank max
/// λ/A, ccx max CSTR, flank max pressure, largest nodal difference / p_max,
/// flank time, ccx time, ccx max pressure with flank's face averaging).
fn cross_code(fine: usize, law: PressureOverclosure, name: &str) -> Option<[f64; 9]> {
    let dir = common::scratch_dir(&format!("hertz_contact_{name}"));
    let m = model(fine, HertzLoad::Displacement(0.02), law);
    let deck = dir.join(format!("{name}.inp"));
    std::fs::write(&deck, ccx_deck(&m)).unwrap();
    let t = Instant::now();
    let (rows, summary) = flank_solve(&deck, &dir.join("flank"));
    let flank_s = t.elapsed().as_secs_f64();
    let pair = &summary["contact"]["pairs"][0];
    let f_flank = pair["total_normal_force"].as_f64().unwrap();
    let pn_flank = pair["max_nodal_pressure"].as_f64().unwrap();
    let p_flank = pair["max_pressure"].as_f64().unwrap();
    if !common::ccx_available() {
        eprintln!("{name}: flank {f_flank:.6} N only");
        return None;
    }
    let t = Instant::now();
    let run = common::run_ccx(&deck, &dir.join("ccx"));
    let ccx_s = t.elapsed().as_secs_f64();
    let dat = parse_ccx_dat(&run.dat);
    let f_ccx = run.totals()["FLAT_BOTTOM"][1];
    let pn_ccx = dat.cstr.values().fold(0.0f64, |a, &b| a.max(b));
    let mut worst = 0.0f64;
    for (label, &p) in &dat.cstr {
        let fl = rows.get(label).map_or(0.0, |r| r.3);
        worst = worst.max((fl - p.max(0.0)).abs() / pn_ccx);
    }
    // ccx's nodal forces (CSTR × the same tributary area) through flank's
    // face averaging
    let pairs = flank::contact::solve::build_pairs(&m, &Default::default()).unwrap();
    let g = &pairs[0];
    let lambda: Vec<f64> = g
        .constraints
        .iter()
        .map(|c| {
            dat.cstr
                .get(&m.mesh.node_labels[c.slave])
                .map_or(0.0, |p| p.max(0.0))
                * c.area
        })
        .collect();
    let p_ccx = flank::contact::solve::face_averaged_pressure(&m, g, &lambda)
        .into_iter()
        .fold(0.0f64, f64::max);
    Some([
        f_flank, f_ccx, pn_flank, pn_ccx, p_flank, worst, flank_s, ccx_s, p_ccx,
    ])
}

/// Hertz p_max of the line load carried by a force F on the half slice.
fn hertz_pmax(force: f64) -> f64 {
    let (estar, _, _) = hertz();
    (2.0 * force / THICKNESS * estar / (PI * R)).sqrt()
}

fn print_cross(name: &str, r: &[f64; 9]) {
    println!(
        "| {name} | {:.6} | {:.6} | {:+.2e} | {:.2} | {:.2} | {:+.2e} | {:.2e} | {:.2} ({:+.2} %) | {:.2} ({:+.2} %) | {:.2} | {:.1} |",
        r[0],
        r[1],
        r[0] / r[1] - 1.0,
        r[2],
        r[3],
        r[2] / r[3] - 1.0,
        r[5],
        r[4],
        100.0 * (r[4] / hertz_pmax(r[0]) - 1.0),
        r[8],
        100.0 * (r[8] / hertz_pmax(r[1]) - 1.0),
        r[6],
        r[7]
    );
}

/// The same Hertz deck (displacement-controlled, δ = 0.02 mm) in `flank
/// solve` and in CalculiX: linear penalty with the same slope, and hard
/// contact (exact in flank; in CalculiX node-to-face HARD is a linear
/// penalty of slope 50 E).
fn cross_code_cases(fine: usize) {
    let slope = {
        let m = model(
            fine,
            HertzLoad::Displacement(0.02),
            PressureOverclosure::Linear {
                slope: None,
                tension: None,
                c0: None,
            },
        );
        let sol = solve_contact(
            &m,
            &ContactOptions {
                recover_stress: false,
                ..Default::default()
            },
        )
        .unwrap();
        match sol.summary.pairs[0].law {
            NormalLaw::Penalty { slope, .. } => slope,
            NormalLaw::Hard => unreachable!(),
        }
    };
    let cases = [
        (
            format!("linear_{fine}"),
            PressureOverclosure::Linear {
                slope: Some(slope),
                tension: Some(0.01),
                c0: Some(0.3),
            },
        ),
        (format!("hard_{fine}"), PressureOverclosure::Hard),
        (
            format!("linear50e_{fine}"),
            PressureOverclosure::Linear {
                slope: Some(50.0 * E),
                tension: Some(0.01),
                c0: Some(0.3),
            },
        ),
    ];
    let results: Vec<Option<[f64; 9]>> = std::thread::scope(|s| {
        let handles: Vec<_> = cases
            .iter()
            .map(|(name, law)| s.spawn(move || cross_code(fine, law.clone(), name)))
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    });
    println!("fine {fine}: flank penalty slope {slope:.4e} MPa/mm; CalculiX HARD = linear 50 E = {:.4e} MPa/mm", 50.0 * E);
    println!("| deck | force flank (N) | force ccx (N) | diff | max λ/A flank (MPa) | max CSTR ccx (MPa) | diff | max nodal diff / p | p_max flank (vs Hertz) | p_max ccx, face-averaged (vs Hertz) | flank (s) | ccx (s) |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    for ((name, _), r) in cases.iter().zip(&results) {
        if let Some(r) = r {
            print_cross(name, r);
        }
    }
    if let [Some(lin), Some(hard), Some(lin50)] = &results[..] {
        common::check(
            "hertz_contact",
            "ccx: total force, same penalty",
            lin[0],
            lin[1],
            1e-3,
            lin[7],
        );
        common::check(
            "hertz_contact",
            "ccx: max nodal pressure, same penalty",
            lin[2],
            lin[3],
            1e-2,
            lin[7],
        );
        assert!(
            lin[5] < 2e-2,
            "nodal pressures differ by {:.2e} of p_max",
            lin[5]
        );
        // ccx's HARD is flank's linear 50 E
        common::check(
            "hertz_contact",
            "ccx HARD vs flank linear 50E: force",
            lin50[0],
            hard[1],
            1e-3,
            hard[7],
        );
        // flank's exact hard contact is stiffer than ccx's 50 E penalty
        assert!(
            hard[0] > hard[1],
            "exact hard contact carries more than a penalty"
        );
        common::check(
            "hertz_contact",
            "ccx HARD vs flank hard: force",
            hard[0],
            hard[1],
            2e-2,
            hard[7],
        );
    }
}

#[test]
fn cross_code_ccx() {
    cross_code_cases(8);
}

#[test]
#[ignore]
fn cross_code_ccx_refined() {
    cross_code_cases(4);
    cross_code_cases(16);
}
