//! # Verification: subsurface stress below a Hertz line contact with friction
//!
//! ## What
//!
//! The closed form of McEwen (1949) / Smith & Liu (1953) as Johnson,
//! *Contact Mechanics* §7.2 writes it (`flank::lubrication::subsurface`,
//! the field seed 002's subsurface change rests on) against flank's FE
//! stress field in a plane-strain slab loaded on its top by the Hertz
//! pressure p(x) = p₀ √(1 − x²/a²) and the sliding traction q(x) = μ p(x)
//! along +x, at μ = 0, 0.1 and 0.2.
//!
//! The loads are prescribed tractions (consistent nodal forces,
//! `fem::loads::traction_field_face_load`), not an FE contact: the contact
//! solver is verified in `hertz_contact` and `friction`; this case isolates
//! the elastic field and the stress recovery under a *sliding* traction,
//! which FE contact with Coulomb friction under a normal load alone does
//! not produce (it sticks).
//!
//! ## Model
//!
//! Slab |x| ≤ 20 a, 0 ≤ depth ≤ 20 a, one C3D20 element thick (0.25 a) with
//! u_z = 0 at every node (plane strain); `n` equal cells per a over
//! |x| ≤ 2 a and depth ≤ 1.5 a (the contact edges x = ±a on cell
//! boundaries, so the kink of p(x) is not inside a face), cells growing by
//! 1.2 beyond. The far faces (x = ±20 a, depth 20 a) carry the tractions
//! σ·n of the closed-form half-space field, so the slab is a cut-out of
//! the half-space (no finite-block error); only the rigid motions are held
//! (u_x, u_y on one bottom corner edge, u_y on the other), and their
//! reactions measure how well the applied loads balance (quadrature).
//!
//! ## What is measured
//!
//! In the fine zone (|x| ≤ 2 a, depth ≤ 1.5 a), for the largest principal
//! shear τ₁ (Tresca, σ_zz included: at the maximum it is the in-plane
//! (σ₁ − σ₃)/2), the largest orthogonal shear |τ_xz| and the largest von
//! Mises stress: the FE maximum and where, from the averaged nodal
//! stresses (Gauss-point values extrapolated to the nodes and averaged,
//! `fem::stress::recover`) and from the Gauss points themselves
//! (`fem::stress::element_point_stresses`), against the closed form's
//! maximum (`max_stresses`, located to 1e-6 p₀).
//!
//! ## Tolerances (fixed before the first run)
//!
//! From n = 16 (cell a/16) on: each maximum within 3 % (the issue's
//! figure), the location of the τ₁ maximum within 0.1 a in x and in depth;
//! the top load's resultant within 1e-3 of P′ = π a p₀ / 2 and the
//! reactions at the held edges below 1e-3 P′. n = 8 is reported.
//! The change of the τ₁ maximum from μ = 0.05 to 0.02 (seed 002's dry →
//! wet) within 0.1 percentage points of the closed form at n = 16; n = 2,
//! 3, 4, 8 reported (2.5 cells per a is seed 002's 0.1 mm mesh).
//!
//! Run: `cargo test --release --test subsurface_stress -- --nocapture`
//! (`-- --ignored` for n = 32).

#[path = "../common/mod.rs"]
mod common;

use std::f64::consts::PI;
use std::time::Instant;

use flank::fem::element::ReferenceElement;
use flank::fem::loads::traction_field_face_load;
use flank::fem::model::{Dirichlet, Model, NodalForce};
use flank::fem::static_analysis::{solve_static, SolveOptions};
use flank::fem::stress::element_point_stresses;
use flank::lubrication::subsurface::{max_stresses, stress, MaxStresses, PlaneStress};
use flank::mesh::hertz::graded_distribution;
use flank::mesh::structured::{box_faces, box_mesh, map_nodes, BoxElement};

const E: f64 = 210_000.0;
const NU: f64 = 0.3;
/// Half-width a (mm) and peak pressure p₀ (MPa): the problem is linear, the
/// figures are in units of a and p₀.
const A: f64 = 0.2;
const P0: f64 = 1500.0;
/// Far faces at ±FAR a and depth FAR a.
const FAR: f64 = 20.0;
/// The uniform zone: |x| ≤ FINE_X a, depth ≤ FINE_Z a.
const FINE_X: f64 = 2.0;
const FINE_Z: f64 = 1.5;
const GROWTH: f64 = 1.2;
/// Slice thickness (units of a).
const THICK: f64 = 0.25;
/// The tolerances of the module doc.
const TOL_MAX: f64 = 0.03;
const TOL_AT: f64 = 0.1;
const TOL_BALANCE: f64 = 1e-3;

/// Position of lattice index `l` (0..=2n) on cell boundaries `d`: even =
/// a boundary, odd = the middle of a cell.
fn lattice(d: &[f64], l: usize) -> f64 {
    if l.is_multiple_of(2) {
        d[l / 2]
    } else {
        0.5 * (d[l / 2] + d[l / 2 + 1])
    }
}

/// The closed-form stress at the FE point (x, y) (y ≤ 0 up), as FE
/// components (MPa): σ_xx, σ_yy, τ_xy. Depth z = −y; τ_xy = −τ_xz (the
/// closed form's z points down).
fn closed_fe(x: f64, y: f64, mu: f64) -> [f64; 3] {
    let s = stress(x / A, -y / A, mu, NU);
    [P0 * s.sigma_x, P0 * s.sigma_z, -P0 * s.tau_xz]
}

/// An FE stress (xx, yy, zz, xy, yz, xz; MPa) in the closed form's terms
/// (units of p₀).
fn as_plane(s: &[f64; 6]) -> PlaneStress {
    PlaneStress {
        sigma_x: s[0] / P0,
        sigma_y: s[2] / P0,
        sigma_z: s[1] / P0,
        tau_xz: -s[3] / P0,
    }
}

/// A traction field on a face: t(x) (MPa) at the point x (mm).
type Traction<'a> = &'a dyn Fn([f64; 3]) -> [f64; 3];

/// The slab with `n` cells per a in the fine zone and the loads of
/// friction μ. Returns the model, the resultant of the top loads (N) and
/// of all loads (N).
fn slab(n: usize, mu: f64) -> (Model, [f64; 2], [f64; 2]) {
    let half = graded_distribution(FAR * A, FINE_X * A, (FINE_X * n as f64) as usize, GROWTH);
    let xs: Vec<f64> = half
        .iter()
        .rev()
        .map(|v| -v)
        .chain(half.iter().skip(1).copied())
        .collect();
    // depth: cells of a/n down to at least FINE_Z a (n = 3: 5 cells, 1.67 a)
    let zc = (FINE_Z * n as f64).ceil();
    let depth = graded_distribution(FAR * A, zc * A / n as f64, zc as usize, GROWTH);
    let ys: Vec<f64> = depth.iter().rev().map(|v| -v).collect();
    let (nx, ny) = (xs.len() - 1, ys.len() - 1);
    let mut mesh = box_mesh([nx as f64, ny as f64, 1.0], [nx, ny, 1], BoxElement::Hex20);
    map_nodes(&mut mesh, |p| {
        let l = p.map(|v| (2.0 * v).round() as usize);
        [
            lattice(&xs, l[0]),
            lattice(&ys, l[1]),
            0.5 * l[2] as f64 * THICK * A,
        ]
    });
    let mut model = common::model_from_mesh(mesh, E, NU);
    common::fix_set(&mut model, "NALL", &[2], 0.0);
    let sets = &model.mesh.node_sets;
    let corner = |a: &str, b: &str| -> Vec<usize> {
        sets[a]
            .iter()
            .filter(|n| sets[b].contains(n))
            .copied()
            .collect()
    };
    let mut held = Vec::new();
    for node in corner("X0", "Y0") {
        held.push((node, 0));
        held.push((node, 1));
    }
    for node in corner("X1", "Y0") {
        held.push((node, 1));
    }
    for (node, component) in held {
        model.dirichlet.push(Dirichlet {
            node,
            component,
            value: 0.0,
        });
    }
    // loads: Hertz pressure and μp on the top, the half-space's σ·n on the
    // far faces (outward normals −x, +x, −y)
    let hertz = |p: [f64; 3]| {
        let r = 1.0 - (p[0] / A).powi(2);
        let pr = if r > 0.0 { P0 * r.sqrt() } else { 0.0 };
        [mu * pr, -pr, 0.0]
    };
    let left = |p: [f64; 3]| {
        let s = closed_fe(p[0], p[1], mu);
        [-s[0], -s[2], 0.0]
    };
    let right = |p: [f64; 3]| {
        let s = closed_fe(p[0], p[1], mu);
        [s[0], s[2], 0.0]
    };
    let bottom = |p: [f64; 3]| {
        let s = closed_fe(p[0], p[1], mu);
        [-s[2], -s[1], 0.0]
    };
    let mut f = vec![0.0; model.dof_count()];
    let (mut top, mut all) = ([0.0; 2], [0.0; 2]);
    let faces: [(&str, Traction); 4] = [
        ("Y1", &hertz),
        ("X0", &left),
        ("X1", &right),
        ("Y0", &bottom),
    ];
    for (set, t) in faces {
        for (e, face) in box_faces(&model.mesh, set) {
            let el = &model.mesh.elements[e];
            let x = model.mesh.element_coords(e);
            for (a, v) in traction_field_face_load(el.kind, &x, face, t).expect("hex face") {
                for i in 0..2 {
                    f[3 * el.nodes[a] + i] += v[i];
                    all[i] += v[i];
                    if set == "Y1" {
                        top[i] += v[i];
                    }
                }
            }
        }
    }
    for (dof, &value) in f.iter().enumerate() {
        if value != 0.0 {
            model.forces.push(NodalForce {
                node: dof / 3,
                component: dof % 3,
                value,
            });
        }
    }
    (model, top, all)
}

/// One quantity's maximum: value (p₀) and where ([x, depth] in a).
type Peak = (f64, [f64; 2]);

/// The three maxima (τ₁, |τ_xz|, von Mises) over samples (x, depth, stress).
fn peaks(samples: &[(f64, f64, PlaneStress)]) -> [Peak; 3] {
    let mut best = [(f64::NEG_INFINITY, [0.0; 2]); 3];
    for (x, z, s) in samples {
        for (k, v) in [s.max_shear(), s.tau_xz.abs(), s.von_mises()]
            .into_iter()
            .enumerate()
        {
            if v > best[k].0 {
                best[k] = (v, [*x, *z]);
            }
        }
    }
    best
}

/// Figures of one slab solve.
struct Figures {
    dofs: usize,
    seconds: f64,
    /// top load resultant / P′ − 1 (y), and its x part / (μ P′) − 1
    top_error: [f64; 2],
    /// largest reaction at the held DOFs / P′
    reaction: f64,
    /// maxima from the nodes and from the Gauss points
    nodes: [Peak; 3],
    points: [Peak; 3],
    /// largest |Δτ₁| (p₀) over the fine zone's nodes with depth ≥ 0.25 a,
    /// and over the surface row
    deep_error: f64,
    surface_error: f64,
}

fn in_fine_zone(x: f64, z: f64) -> bool {
    x.abs() <= FINE_X + 1e-9 && (-1e-9..=FINE_Z + 1e-9).contains(&z)
}

fn run(n: usize, mu: f64) -> Figures {
    let (model, top, _all) = slab(n, mu);
    let t = Instant::now();
    let sol = solve_static(&model, &SolveOptions::default()).expect("slab solve");
    let seconds = t.elapsed().as_secs_f64();
    let line = PI * A * P0 / 2.0 * THICK * A;
    let reaction = sol
        .reaction
        .as_ref()
        .expect("reactions")
        .chunks(3)
        .map(|r| r[0].abs().max(r[1].abs()))
        .fold(0.0, f64::max)
        / line;
    let rec = sol.recovery.as_ref().expect("stresses recovered");
    let coords = &model.mesh.coords;
    let mut nodal = Vec::new();
    let (mut deep_error, mut surface_error) = (0.0f64, 0.0f64);
    for (node, c) in coords.iter().enumerate() {
        let (x, z) = (c[0] / A, -c[1] / A);
        if c[2].abs() > 1e-12 || !in_fine_zone(x, z) {
            continue;
        }
        let s = as_plane(&rec.stress[node]);
        let d = (s.max_shear() - stress(x, z, mu, NU).max_shear()).abs();
        if z >= 0.25 {
            deep_error = deep_error.max(d);
        } else if z.abs() < 1e-9 {
            surface_error = surface_error.max(d);
        }
        nodal.push((x, z, s));
    }
    let mut gauss = Vec::new();
    for (e, el) in model.mesh.elements.iter().enumerate() {
        let x = model.mesh.element_coords(e);
        let re = ReferenceElement::get(el.kind);
        let ps = element_point_stresses(&model, e, &sol.displacement).expect("point stresses");
        for (g, s) in ps.stress.iter().enumerate() {
            let mut p = [0.0; 3];
            for (a, xa) in x.iter().enumerate() {
                for i in 0..3 {
                    p[i] += re.values[g][a] * xa[i];
                }
            }
            let (px, pz) = (p[0] / A, -p[1] / A);
            if in_fine_zone(px, pz) {
                gauss.push((px, pz, as_plane(s)));
            }
        }
    }
    Figures {
        dofs: sol.stats.dofs,
        seconds,
        top_error: [-top[1] / line - 1.0, top[0] / (mu * line) - 1.0],
        reaction,
        nodes: peaks(&nodal),
        points: peaks(&gauss),
        deep_error,
        surface_error,
    }
}

fn closed_peaks(m: &MaxStresses) -> [Peak; 3] {
    [
        (m.max_shear, m.max_shear_at),
        (m.max_orthogonal_shear, m.max_orthogonal_shear_at),
        (m.max_von_mises, m.max_von_mises_at),
    ]
}

const NAMES: [&str; 3] = ["τ₁", "|τ_xz|", "von Mises"];

/// Runs level `n` for each μ, prints a results row per μ and quantity,
/// and asserts the module doc's tolerances when `assert` is set.
fn level(n: usize, mus: &[f64], assert: bool) {
    println!(
        "| n | μ | quantity | closed form (p₀) | at (x, z)/a | FE nodes | error | at | FE Gauss points | error | at |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    let mut changes = Vec::new();
    for &mu in mus {
        let closed = closed_peaks(&max_stresses(mu, NU));
        let f = run(n, mu);
        for k in 0..3 {
            let (c, c_at) = closed[k];
            let (v, v_at) = f.nodes[k];
            let (g, g_at) = f.points[k];
            println!(
                "| {n} | {mu} | {} | {c:.4} | ({:+.3}, {:.3}) | {v:.4} | {:+.2} % | ({:+.3}, {:.3}) | {g:.4} | {:+.2} % | ({:+.3}, {:.3}) |",
                NAMES[k],
                c_at[0],
                c_at[1],
                100.0 * (v / c - 1.0),
                v_at[0],
                v_at[1],
                100.0 * (g / c - 1.0),
                g_at[0],
                g_at[1],
            );
        }
        let tangential = if mu > 0.0 {
            format!("{:+.1e}", f.top_error[1])
        } else {
            "—".to_string()
        };
        println!(
            "n {n}, μ {mu}: {} DOFs, solve {:.2} s; top load vs P′ {:+.1e} (normal), {tangential} (tangential); largest reaction {:.1e} P′; largest |Δτ₁| {:.4} p₀ (nodes, depth ≥ 0.25 a), {:.4} p₀ (surface row)",
            f.dofs, f.seconds, f.top_error[0], f.reaction, f.deep_error, f.surface_error
        );
        changes.push((mu, closed[0].0, f.nodes[0].0, f.points[0].0));
        if !assert {
            continue;
        }
        assert!(
            f.top_error[0].abs() < TOL_BALANCE,
            "top load {:?}",
            f.top_error
        );
        if mu > 0.0 {
            assert!(
                f.top_error[1].abs() < TOL_BALANCE,
                "top load {:?}",
                f.top_error
            );
        }
        assert!(f.reaction < TOL_BALANCE, "reaction {} P′", f.reaction);
        for k in 0..3 {
            for (how, peak) in [("nodes", f.nodes[k]), ("Gauss points", f.points[k])] {
                common::check(
                    "subsurface",
                    &format!("{} max μ {mu} n {n} {how}", NAMES[k]),
                    peak.0,
                    closed[k].0,
                    TOL_MAX,
                    f.seconds,
                );
            }
        }
        let (at, c_at) = (f.nodes[0].1, closed[0].1);
        assert!(
            (at[0] - c_at[0]).abs() <= TOL_AT && (at[1] - c_at[1]).abs() <= TOL_AT,
            "μ {mu}, n {n}: τ₁ max at {at:?} a, closed form {c_at:?} a"
        );
    }
    // the change of the τ₁ maximum with μ (what seed 002 reports dry → wet)
    if let Some(&(m0, c0, v0, g0)) = changes.first() {
        for &(mu, c, v, g) in &changes[1..] {
            println!(
                "n {n}: τ₁ max from μ {m0} to {mu}: closed form {:+.3} %, FE nodes {:+.3} %, FE Gauss points {:+.3} %",
                100.0 * (c / c0 - 1.0),
                100.0 * (v / v0 - 1.0),
                100.0 * (g / g0 - 1.0)
            );
        }
    }
}

/// n = 8 reported, n = 16 asserted (module doc), μ = 0, 0.1, 0.2.
#[test]
fn subsurface_stress_with_friction() {
    level(8, &[0.0, 0.1, 0.2], false);
    level(16, &[0.0, 0.1, 0.2], true);
}

/// n = 32 (cell a/32), asserted with the same tolerances; ignored for CI
/// time only (about four times n = 16's DOFs).
#[test]
#[ignore]
fn subsurface_stress_with_friction_refined() {
    level(32, &[0.0, 0.1, 0.2], true);
}

/// Seed 002's dry → wet question on coarse meshes: the change of the τ₁
/// maximum from μ = 0.05 (the dry pass) to 0.02 (a wet μ) at constant p₀,
/// FE against the closed form (−0.315 %), from n = 2 (about seed 002's
/// 0.1 mm flank elements under b ≈ 0.25 mm) to n = 16. Asserted (fixed
/// before the first run): within 0.1 percentage points of the closed form
/// at n = 16; the coarse levels are reported.
#[test]
fn the_change_with_mu_on_coarse_meshes() {
    let (dry, wet) = (0.05, 0.02);
    let c = max_stresses(wet, NU).max_shear / max_stresses(dry, NU).max_shear - 1.0;
    println!("| n (cells/a) | τ₁ max μ {dry} (nodes) | error | τ₁ max μ {wet} | error | change nodes | Gauss points | closed form |");
    println!("|---|---|---|---|---|---|---|---|");
    for n in [2, 3, 4, 8, 16] {
        let (fd, fw) = (run(n, dry), run(n, wet));
        let closed = |mu: f64| max_stresses(mu, NU).max_shear;
        let (vd, vw) = (fd.nodes[0].0, fw.nodes[0].0);
        let nodes = vw / vd - 1.0;
        let gauss = fw.points[0].0 / fd.points[0].0 - 1.0;
        println!(
            "| {n} | {vd:.4} | {:+.2} % | {vw:.4} | {:+.2} % | {:+.3} % | {:+.3} % | {:+.3} % |",
            100.0 * (vd / closed(dry) - 1.0),
            100.0 * (vw / closed(wet) - 1.0),
            100.0 * nodes,
            100.0 * gauss,
            100.0 * c
        );
        if n == 16 {
            assert!(
                (nodes - c).abs() < 1e-3 && (gauss - c).abs() < 1e-3,
                "change {nodes} (nodes), {gauss} (Gauss points) vs {c}"
            );
        }
    }
}
