//! # h-convergence of C3D20, C3D20R and C3D15 on a smooth exact solution
//!
//! ## What
//!
//! On the unit cube [0,1]³ take the displacement field
//!
//! ```text
//! u = ∇φ,  φ = e^{kx} cos(ky) / k²,  k = 1
//! u = (e^{kx} cos ky, −e^{kx} sin ky, 0) / k
//! ```
//!
//! Since div u = Δφ = 0 and Δu = ∇Δφ = 0, Navier's equations
//! μΔu + (λ + μ)∇(div u) = 0 hold with zero body force for any λ, μ: u is an
//! exact elastic solution. The FE problem prescribes u at every boundary node
//! (sets X0, X1, Y0, Y1, Z0, Z1) and is solved on n × n × n meshes of C3D20
//! and C3D15 (two wedges per cell), n = 2, 4, 8, 16, and of C3D20R,
//! n = 2, 4, 8. The errors
//!
//! ```text
//! L²:      ‖u − u_h‖ / ‖u‖
//! energy:  ( ∫ (ε − ε_h) : C : (ε − ε_h) dV / ∫ ε : C : ε dV )^{1/2}
//! ```
//!
//! are integrated element by element with rules finer than the stiffness
//! rules — 4×4×4 Gauss on the hexahedra, the 7-point degree-5 triangle rule ×
//! 4-point Gauss on the wedges — evaluating u_h with the element shape
//! functions ([`shape`]) and ε_h with their spatial gradients. Observed rates
//! are log2(e_h / e_{h/2}).
//!
//! ## Expected
//!
//! Quadratic (serendipity) elements: L² error O(h³), energy error O(h²)
//! (Ciarlet; Strang & Fix, ch. 3). Asserted on the finest pair of every
//! sequence: L² rate within 3 ± 0.2 and energy rate within 2 ± 0.2 (so at
//! least 2.8 and 1.8), and the errors must decrease monotonically. C3D20R
//! (2×2×2 Gauss) is expected to keep the same rates: its rule integrates the
//! energy of quadratic fields on parallelepipeds exactly and is the classical
//! reduced rule that keeps the optimal order.
//!
//! A second run moves the interior corner nodes of each mesh by up to 0.1 of
//! the cell size (straight edges kept, [`distort_interior`], n = 2, 4, 8);
//! those rates are asserted with the same bounds.
//!
//! ## Reference
//!
//! P. G. Ciarlet, *The Finite Element Method for Elliptic Problems* (1978),
//! §§ 3.2, 4.1 (interpolation and isoparametric error estimates);
//! G. Strang, G. Fix, *An Analysis of the Finite Element Method* (1973), ch. 3.

// Index loops read like the tensor formulas they implement.
#![allow(clippy::needless_range_loop)]

#[path = "../common/mod.rs"]
mod common;

use std::time::Instant;

use flank::fem::element::{det3, inv3, jacobian, shape};
use flank::fem::material::Material;
use flank::fem::mesh::ElementKind;
use flank::fem::model::{Dirichlet, Model};
use flank::fem::static_analysis::{solve_static, SolveOptions};
use flank::mesh::structured::{box_mesh, distort_interior, BoxElement};

const YOUNG: f64 = 1.0;
const POISSON: f64 = 0.3;
/// Wave number k of the potential φ.
const K: f64 = 1.0;

/// Exact displacement and its gradient (row i = ∂u_i/∂x_j).
fn exact(p: [f64; 3]) -> ([f64; 3], [[f64; 3]; 3]) {
    let e = (K * p[0]).exp();
    let (c, s) = ((K * p[1]).cos(), (K * p[1]).sin());
    (
        [e * c / K, -e * s / K, 0.0],
        [[e * c, -e * s, 0.0], [-e * s, -e * c, 0.0], [0.0, 0.0, 0.0]],
    )
}

/// Strain energy density ε : C : ε of the symmetric part of a gradient h.
fn energy_density(h: &[[f64; 3]; 3], lambda: f64, mu: f64) -> f64 {
    let tr = h[0][0] + h[1][1] + h[2][2];
    let mut ee = 0.0;
    for i in 0..3 {
        for j in 0..3 {
            let e = 0.5 * (h[i][j] + h[j][i]);
            ee += e * e;
        }
    }
    lambda * tr * tr + 2.0 * mu * ee
}

/// 4-point Gauss–Legendre rule on [-1, 1] (exact to degree 7).
const GAUSS4: [(f64, f64); 4] = [
    (-0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
    (-0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
    (0.339_981_043_584_856_3, 0.652_145_154_862_546_1),
    (0.861_136_311_594_052_6, 0.347_854_845_137_453_9),
];

/// Radon's 7-point degree-5 rule on the triangle {r, s ≥ 0, r + s ≤ 1};
/// weights sum to the area 1/2 (exactness checked in `error_rules_are_exact`).
fn triangle7() -> Vec<([f64; 2], f64)> {
    let sq = 15f64.sqrt();
    let (a, b) = ((6.0 - sq) / 21.0, (6.0 + sq) / 21.0);
    let (wa, wb) = ((155.0 - sq) / 2400.0, (155.0 + sq) / 2400.0);
    vec![
        ([1.0 / 3.0, 1.0 / 3.0], 9.0 / 80.0),
        ([a, a], wa),
        ([1.0 - 2.0 * a, a], wa),
        ([a, 1.0 - 2.0 * a], wa),
        ([b, b], wb),
        ([1.0 - 2.0 * b, b], wb),
        ([b, 1.0 - 2.0 * b], wb),
    ]
}

/// The error-integration rule of an element kind: (ξ, weight) pairs.
fn error_rule(kind: ElementKind) -> Vec<([f64; 3], f64)> {
    let mut pts = Vec::new();
    match kind {
        ElementKind::C3D20 | ElementKind::C3D20R => {
            for &(z, wz) in &GAUSS4 {
                for &(y, wy) in &GAUSS4 {
                    for &(x, wx) in &GAUSS4 {
                        pts.push(([x, y, z], wx * wy * wz));
                    }
                }
            }
        }
        ElementKind::C3D15 => {
            for &(z, wz) in &GAUSS4 {
                for (rs, w) in triangle7() {
                    pts.push(([rs[0], rs[1], z], w * wz));
                }
            }
        }
    }
    pts
}

/// The error rules are exact where they must be: every monomial rᵃsᵇζᶜ with
/// a + b ≤ 5, c ≤ 7 on the wedge and ξᵃηᵇζᶜ, a, b, c ≤ 7 on the hexahedron.
#[test]
fn error_rules_are_exact() {
    let fact = |n: u32| (1..=n).map(f64::from).product::<f64>();
    let line = |c: u32| {
        if c % 2 == 1 {
            0.0
        } else {
            2.0 / (c as f64 + 1.0)
        }
    };
    for a in 0..=5u32 {
        for b in 0..=(5 - a) {
            for c in 0..=7u32 {
                // ∫_T r^a s^b = a! b! / (a + b + 2)!
                let exact = fact(a) * fact(b) / fact(a + b + 2) * line(c);
                let q: f64 = error_rule(ElementKind::C3D15)
                    .iter()
                    .map(|(x, w)| {
                        w * x[0].powi(a as i32) * x[1].powi(b as i32) * x[2].powi(c as i32)
                    })
                    .sum();
                assert!(
                    (q - exact).abs() < 1e-14,
                    "wedge r^{a} s^{b} z^{c}: {q} vs {exact}"
                );
            }
        }
    }
    for a in 0..=7u32 {
        for b in 0..=7u32 {
            for c in 0..=7u32 {
                let exact = line(a) * line(b) * line(c);
                let q: f64 = error_rule(ElementKind::C3D20)
                    .iter()
                    .map(|(x, w)| {
                        w * x[0].powi(a as i32) * x[1].powi(b as i32) * x[2].powi(c as i32)
                    })
                    .sum();
                assert!(
                    (q - exact).abs() < 1e-14,
                    "hex x^{a} y^{b} z^{c}: {q} vs {exact}"
                );
            }
        }
    }
}

/// Errors of one mesh.
struct Errors {
    n: usize,
    dofs: usize,
    l2: f64,
    energy: f64,
    seconds: f64,
}

/// Solves the n×n×n mesh and integrates the relative L² and energy errors.
fn solve_and_measure(kind: BoxElement, n: usize, distortion: f64) -> Errors {
    let t = Instant::now();
    let mut mesh = box_mesh([1.0, 1.0, 1.0], [n, n, n], kind);
    if distortion > 0.0 {
        distort_interior(&mut mesh, distortion, 1000 + n as u64, true);
    }
    let mut boundary = vec![false; mesh.node_count()];
    for set in ["X0", "X1", "Y0", "Y1", "Z0", "Z1"] {
        for &i in &mesh.node_sets[set] {
            boundary[i] = true;
        }
    }
    let mut model: Model = common::model_from_mesh(mesh, YOUNG, POISSON);
    for (i, _) in boundary.iter().enumerate().filter(|(_, &b)| b) {
        let (u, _) = exact(model.mesh.coords[i]);
        for (k, &value) in u.iter().enumerate() {
            model.dirichlet.push(Dirichlet {
                node: i,
                component: k,
                value,
            });
        }
    }
    let options = SolveOptions {
        recover_stress: false,
        ..Default::default()
    };
    let sol = solve_static(&model, &options).expect("solves");
    let (lambda, mu) = Material::new("m", YOUNG, POISSON).expect("valid").lame();

    let (mut e_l2, mut u_l2, mut e_en, mut u_en) = (0.0, 0.0, 0.0, 0.0);
    let mesh = &model.mesh;
    for (e, el) in mesh.elements.iter().enumerate() {
        let x = mesh.element_coords(e);
        let ue: Vec<[f64; 3]> = el
            .nodes
            .iter()
            .map(|&a| [0, 1, 2].map(|k| sol.displacement[3 * a + k]))
            .collect();
        for (xi, w) in error_rule(el.kind) {
            let (nv, dn) = shape(el.kind, xi);
            let j = jacobian(&x, &dn);
            let det = det3(&j);
            assert!(det > 0.0, "element {} inverted", el.label);
            let ji = inv3(&j, det);
            let dv = det * w;
            let mut p = [0.0; 3];
            let mut uh = [0.0; 3];
            let mut gh = [[0.0; 3]; 3];
            for a in 0..nv.len() {
                // ∂N_a/∂x_i = Σ_k ∂N_a/∂ξ_k ∂ξ_k/∂x_i
                let g = [0, 1, 2]
                    .map(|i| dn[a][0] * ji[0][i] + dn[a][1] * ji[1][i] + dn[a][2] * ji[2][i]);
                for i in 0..3 {
                    p[i] += nv[a] * x[a][i];
                    uh[i] += nv[a] * ue[a][i];
                    for jj in 0..3 {
                        gh[i][jj] += ue[a][i] * g[jj];
                    }
                }
            }
            let (u, gu) = exact(p);
            let mut diff = [[0.0; 3]; 3];
            for i in 0..3 {
                e_l2 += dv * (u[i] - uh[i]).powi(2);
                u_l2 += dv * u[i] * u[i];
                for jj in 0..3 {
                    diff[i][jj] = gu[i][jj] - gh[i][jj];
                }
            }
            e_en += dv * energy_density(&diff, lambda, mu);
            u_en += dv * energy_density(&gu, lambda, mu);
        }
    }
    Errors {
        n,
        dofs: sol.stats.dofs,
        l2: (e_l2 / u_l2).sqrt(),
        energy: (e_en / u_en).sqrt(),
        seconds: t.elapsed().as_secs_f64(),
    }
}

/// Runs the mesh sequence, prints the table and asserts the finest-pair rates.
fn study(kind: BoxElement, sizes: &[usize], distortion: f64) {
    let name = kind.kind().name();
    let tag = if distortion > 0.0 {
        format!("{name} distorted {distortion}")
    } else {
        name.to_string()
    };
    let runs: Vec<Errors> = sizes
        .iter()
        .map(|&n| solve_and_measure(kind, n, distortion))
        .collect();
    println!("TABLE {tag}: n, DOFs, L2 error, rate, energy error, rate, seconds");
    for (i, r) in runs.iter().enumerate() {
        let (rl, re) = if i > 0 {
            (
                (runs[i - 1].l2 / r.l2).log2(),
                (runs[i - 1].energy / r.energy).log2(),
            )
        } else {
            (f64::NAN, f64::NAN)
        };
        println!(
            "TABLE {tag}: {:>3} {:>7} {:>10.3e} {:>5.2} {:>10.3e} {:>5.2} {:>7.3}",
            r.n, r.dofs, r.l2, rl, r.energy, re, r.seconds
        );
    }
    for w in runs.windows(2) {
        assert!(
            w[1].l2 < w[0].l2 && w[1].energy < w[0].energy,
            "{tag}: error grows from n = {} to {}",
            w[0].n,
            w[1].n
        );
    }
    let (c, f) = (&runs[runs.len() - 2], &runs[runs.len() - 1]);
    let secs: f64 = runs.iter().map(|r| r.seconds).sum();
    let q = format!("rate n={}->{}", c.n, f.n);
    // Expected rates 3 (L²) and 2 (energy); accepted within ±0.2, i.e. the
    // required L² rate ≥ 2.8 and energy rate ≥ 1.8, and no suspicious
    // super-convergence above 3.2 / 2.2 either.
    let l2_rate = (c.l2 / f.l2).log2();
    let en_rate = (c.energy / f.energy).log2();
    common::check(
        &tag,
        &format!("L2 {q} (3 +- 0.2)"),
        l2_rate,
        3.0,
        0.2 / 3.0,
        secs,
    );
    common::check(
        &tag,
        &format!("energy {q} (2 +- 0.2)"),
        en_rate,
        2.0,
        0.2 / 2.0,
        secs,
    );
}

/// Full sequence for the two elements the ladder requires.
const SIZES: [usize; 4] = [2, 4, 8, 16];
/// Shorter sequence for the optional C3D20R run and the distorted meshes
/// (each n = 16 solve costs 4–6 s on the 2-core machine).
const SIZES_SHORT: [usize; 3] = [2, 4, 8];

#[test]
fn hex20_rates() {
    study(BoxElement::Hex20, &SIZES, 0.0);
}

#[test]
fn wedge15_rates() {
    study(BoxElement::Wedge15, &SIZES, 0.0);
}

#[test]
fn hex20r_rates() {
    study(BoxElement::Hex20R, &SIZES_SHORT, 0.0);
}

#[test]
fn distorted_rates() {
    study(BoxElement::Hex20, &SIZES_SHORT, 0.1);
    study(BoxElement::Wedge15, &SIZES_SHORT, 0.1);
}
