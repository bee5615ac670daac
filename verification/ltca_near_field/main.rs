//! The LTCA's near field of an elliptical contact (strips of Hertz line
//! contact along the major axis) against Hertz's elliptical contact on a
//! half-space (README.md).

use flank::ltca::hertz_elliptic::{hertz_elliptic, HertzEllipse};
use flank::ltca::local::{cell_influence, contact_modulus, hertz_line, Cell, NearField};
use flank::ltca::qp::{solve_contact_qp, ContactQp, QpOptions};

/// How the near-field correction H is formed.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Kernel {
    /// flank's model (`NearField`): Hertz pressure across, centre line.
    Centreline,
    /// The model before 2026-11-27: uniform pressure across, cell average.
    CellAverage,
}

/// The strip model's answer for one elliptical contact.
struct Strips {
    approach: f64,
    p_max: f64,
    rounds: usize,
}

/// The LTCA's discretisation on a half-space: `k` points over ± `span` on
/// the major axis x, gap A x², cells of half-length spacing/2; the FE part
/// of F is an exact half-space's (cells of half-width `fe_half` averaged
/// under uniform load, full matrix), H lumped on the diagonal, the Hertz
/// half-widths a_k of line contact (radius 1/(2B) across the axis) from the
/// local load per length, iterated to a fixed point as the LTCA does.
fn strips(hz: &Problem, span: f64, k: usize, fe_half: f64, kernel: Kernel) -> Strips {
    let x: Vec<f64> = (0..k)
        .map(|i| -span + 2.0 * span * i as f64 / (k - 1) as f64)
        .collect();
    let l = span / (k - 1) as f64;
    let gap: Vec<f64> = x.iter().map(|x| hz.a_curv * x * x).collect();
    let radius = 0.5 / hz.b_curv;
    let fe: Vec<Cell> = x
        .iter()
        .map(|&along| Cell {
            across: 0.0,
            along,
            c: fe_half,
            l,
        })
        .collect();
    let f_fe: Vec<Vec<f64>> = (0..k)
        .map(|i| {
            (0..k)
                .map(|j| cell_influence(&fe[i], &fe[j], hz.e_star, 6))
                .collect()
        })
        .collect();
    let near = NearField::new(&fe, &vec![0; k], hz.e_star);
    let sharp = vec![false; k];
    // start as the LTCA does, from the mean load per length
    let mut half = vec![
        hertz_line(hz.load / (2.0 * span), radius, hz.e_star)
            .0
            .min(fe_half);
        k
    ];
    let mut forces = vec![0.0; k];
    let mut approach = 0.0;
    let mut rounds = 0;
    for round in 0..60 {
        rounds = round + 1;
        let h = match kernel {
            Kernel::Centreline => near.diagonal(&half, &sharp),
            Kernel::CellAverage => (0..k)
                .map(|i| {
                    (0..k)
                        .filter(|&j| (x[i] - x[j]).abs() <= 10.0 * fe_half.max(l))
                        .map(|j| {
                            let ni = Cell {
                                c: half[i],
                                ..fe[i]
                            };
                            let nj = Cell {
                                c: half[j],
                                ..fe[j]
                            };
                            cell_influence(&ni, &nj, hz.e_star, 2)
                                - cell_influence(&fe[i], &fe[j], hz.e_star, 2)
                        })
                        .sum()
                })
                .collect(),
        };
        let mut f = f_fe.clone();
        for i in 0..k {
            f[i][i] += h[i];
        }
        (forces, approach) = contact(&f, &gap, hz.load);
        let new: Vec<f64> = forces
            .iter()
            .zip(&half)
            .map(|(&p, &a)| {
                if p > 0.0 {
                    hertz_line(p / (2.0 * l), radius, hz.e_star).0.min(fe_half)
                } else {
                    a
                }
            })
            .collect();
        let change = new
            .iter()
            .zip(&half)
            .map(|(a, b)| (a - b).abs() / a)
            .fold(0.0, f64::max);
        half = new;
        if change < 1e-6 {
            break;
        }
    }
    let p_max = forces
        .iter()
        .map(|&p| hertz_line(p / (2.0 * l), radius, hz.e_star).1)
        .fold(0.0, f64::max);
    Strips {
        approach,
        p_max,
        rounds,
    }
}

/// F p = δ − g where p > 0, F p ≥ δ − g where p = 0, Σ p = P: the LTCA's
/// own contact QP with unit moment arms (the approach is its "rotation").
fn contact(f: &[Vec<f64>], gap: &[f64], load: f64) -> (Vec<f64>, f64) {
    let flat: Vec<f64> = f.iter().flatten().copied().collect();
    let arms = vec![1.0; gap.len()];
    let qp = ContactQp {
        compliance: &flat,
        separation: gap,
        moment_arm: &arms,
        torque: load,
    };
    let s = solve_contact_qp(&qp, &QpOptions::default()).expect("the contact QP solves");
    assert!(s.within_tolerance, "KKT residual above tolerance");
    (s.load, s.rotation)
}

struct Problem {
    load: f64,
    a_curv: f64,
    b_curv: f64,
    e_star: f64,
    hertz: HertzEllipse,
}

/// Steel on steel, 8 mm radius across the axis, 2 kN, curvature ratios B/A
/// from 4 (a/b 2.5) to 150 (a/b 23): p₀ 1.3–2.8 GPa.
fn problems() -> Vec<(f64, Problem)> {
    let e_star = contact_modulus([206e3, 206e3], [0.3, 0.3]);
    let b_curv = 0.5 / 8.0;
    [4.0, 10.0, 25.0, 60.0, 150.0]
        .into_iter()
        .map(|ratio| {
            let a_curv = b_curv / ratio;
            let load = 2000.0;
            let hertz = hertz_elliptic(load, a_curv, b_curv, e_star).unwrap();
            (
                ratio,
                Problem {
                    load,
                    a_curv,
                    b_curv,
                    e_star,
                    hertz,
                },
            )
        })
        .collect()
}

#[test]
fn strips_reproduce_hertz_elliptical_contact() {
    let mut worst: (f64, f64) = (0.0, 0.0);
    for (ratio, p) in problems() {
        let hz = &p.hertz;
        println!(
            "B/A = {ratio}: a = {:.3} mm, b = {:.3} mm, δ = {:.3} µm, p₀ = {:.0} MPa",
            hz.semi_x,
            hz.semi_y,
            1e3 * hz.approach,
            hz.p0
        );
        for k in [21usize, 41] {
            for fe_half in [0.75, 1.5] {
                for kernel in [Kernel::Centreline, Kernel::CellAverage] {
                    let s = strips(&p, 1.3 * hz.semi_x, k, fe_half, kernel);
                    let (d, pm) = (s.approach / hz.approach - 1.0, s.p_max / hz.p0 - 1.0);
                    println!(
                        "  K {k:>2}, FE cell half-width {fe_half} mm, {kernel:?}: δ {:+.2} %, p_max {:+.2} % ({} rounds)",
                        100.0 * d,
                        100.0 * pm,
                        s.rounds
                    );
                    if kernel == Kernel::Centreline {
                        worst = (worst.0.max(d.abs()), worst.1.max(pm.abs()));
                    }
                }
            }
        }
    }
    println!(
        "flank's near field: |δ error| ≤ {:.2} %, |p_max error| ≤ {:.2} %",
        100.0 * worst.0,
        100.0 * worst.1
    );
    assert!(
        worst.0 <= 0.03,
        "approach off Hertz by {:.2} %",
        100.0 * worst.0
    );
    assert!(
        worst.1 <= 0.10,
        "p_max off Hertz by {:.2} %",
        100.0 * worst.1
    );
}

/// The centre-line kernel against a brute-force quadrature of the
/// semi-elliptic pressure (a point away from the loaded cell, where the
/// integrand is smooth).
#[test]
fn elliptic_kernel_matches_direct_quadrature() {
    use flank::ltca::local::elliptic_centreline_influence;
    let j = Cell {
        across: 0.0,
        along: 0.0,
        c: 0.3,
        l: 0.4,
    };
    for along in [1.0, 2.5] {
        let i = Cell {
            across: 0.0,
            along,
            c: 0.3,
            l: 0.2,
        };
        let kernel = elliptic_centreline_influence(&i, &j, 1.0, 4);
        let g = flank::compliance::interpolation::gauss_legendre(40);
        let mut direct = 0.0;
        let mut force = 0.0;
        for &(a, wa) in &g {
            let y = i.along + a * i.l;
            for &(s, ws) in &g {
                let xi = s * j.c;
                let p = (1.0 - s * s).sqrt();
                for &(t, wt) in &g {
                    let eta = t * j.l;
                    let w = 0.5 * wa * ws * j.c * wt * j.l;
                    direct += w * p / (xi * xi + (y - eta) * (y - eta)).sqrt();
                }
            }
        }
        for &(s, ws) in &g {
            for &(_, wt) in &g {
                force += ws * j.c * wt * j.l * (1.0 - s * s).sqrt();
            }
        }
        let direct = direct / force / std::f64::consts::PI;
        let rel = (kernel - direct).abs() / direct;
        println!(
            "centre line at {along} mm: kernel {kernel:.6e}, direct {direct:.6e}, rel {rel:.1e}"
        );
        assert!(rel < 1e-3, "{rel}");
    }
}
