//! Unit tests of the contact QP: small problems with known answers,
//! random flank-like problems solved by both solvers, degenerate and
//! extreme cases, input errors, condition numbers.

use super::clarabel::clarabel_raw;
use super::*;
use crate::settings::QpSolver;
use std::time::Instant;

/// Knuth's MMIX LCG, top 53 bits: a reproducible uniform [0, 1).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

struct Problem {
    f: Vec<f64>,
    w: Vec<f64>,
    r: Vec<f64>,
    t: f64,
}

impl Problem {
    fn qp(&self) -> ContactQp<'_> {
        ContactQp {
            compliance: &self.f,
            separation: &self.w,
            moment_arm: &self.r,
            torque: self.t,
        }
    }
}

fn options(solver: QpSolver) -> QpOptions {
    QpOptions {
        solver,
        ..QpOptions::default()
    }
}

fn solve(pb: &Problem, solver: QpSolver) -> QpSolution {
    solve_contact_qp(&pb.qp(), &options(solver)).unwrap()
}

/// Laplace-kernel compliance c·exp(−|xᵢ − xⱼ|/λ) + d·δᵢⱼ at points
/// `x` (SPD for distinct points: the kernel is positive definite).
fn kernel(x: &[[f64; 2]], c: f64, lambda: f64, d: f64) -> Vec<f64> {
    let n = x.len();
    let mut f = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..n {
            let dist = ((x[i][0] - x[j][0]).powi(2) + (x[i][1] - x[j][1]).powi(2)).sqrt();
            f[i * n + j] = c * (-dist / lambda).exp() + if i == j { d } else { 0.0 };
        }
    }
    f
}

/// A flank-like random problem: points on a 10 × 3 mm patch, Laplace
/// kernel (or, `generic`, F = c·BBᵀ/n + d·I with a random B),
/// separations a·(u − 0.2) (both signs), arms 30…60 mm, T = 1e5 N·mm.
fn random_problem(n: usize, seed: u64, generic: bool) -> Problem {
    let mut rng = Lcg(seed);
    let x: Vec<[f64; 2]> = (0..n)
        .map(|_| [10.0 * rng.next(), 3.0 * rng.next()])
        .collect();
    let f = if generic {
        let b: Vec<f64> = (0..n * n).map(|_| rng.next() - 0.5).collect();
        let mut f = vec![0.0; n * n];
        for i in 0..n {
            for j in 0..n {
                let s: f64 = (0..n).map(|k| b[i * n + k] * b[j * n + k]).sum();
                f[i * n + j] = 2e-5 * s / n as f64 + if i == j { 2e-6 } else { 0.0 };
            }
        }
        f
    } else {
        kernel(&x, 8e-6, 1.5, 4e-6)
    };
    let w = (0..n).map(|_| 2e-2 * (rng.next() - 0.2)).collect();
    let r = (0..n).map(|_| 30.0 + 30.0 * rng.next()).collect();
    Problem { f, w, r, t: 1e5 }
}

fn rel_load_diff(a: &[f64], b: &[f64]) -> f64 {
    let pmax = a.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    a.iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
        / pmax
}

fn check_basic(pb: &Problem, s: &QpSolution) {
    assert!(s.rotation.is_finite());
    assert!(s.load.iter().all(|v| v.is_finite() && *v >= 0.0));
    let rp: f64 = s.load.iter().zip(&pb.r).map(|(p, r)| p * r).sum();
    assert!(
        (rp - pb.t).abs() <= 1e-10 * pb.t,
        "rᵀp = {rp} vs T = {}",
        pb.t
    );
    // the public residual routine gives the same figures
    let k = kkt(&pb.qp(), &s.load, s.rotation);
    assert!((k.max - s.kkt.max).abs() <= 1e-12, "{k:?} vs {:?}", s.kkt);
}

/// Both solvers; active set within tolerance; agreement.
fn agree(pb: &Problem, p_tol: f64, theta_tol: f64) -> (QpSolution, QpSolution) {
    let a = solve(pb, QpSolver::ActiveSet);
    let c = solve(pb, QpSolver::Clarabel);
    check_basic(pb, &a);
    check_basic(pb, &c);
    assert!(a.within_tolerance, "active set KKT {:?}", a.kkt);
    assert!(c.within_tolerance, "clarabel KKT {:?}", c.kkt);
    let dp = rel_load_diff(&a.load, &c.load);
    let dt = (a.rotation - c.rotation).abs() / a.rotation.abs();
    assert!(dp <= p_tol, "loads differ by {dp:.3e}");
    assert!(
        dt <= theta_tol,
        "rotations {} vs {} ({dt:.3e})",
        a.rotation,
        c.rotation
    );
    (a, c)
}

#[test]
fn one_point() {
    let pb = Problem {
        f: vec![1.2e-5],
        w: vec![-3e-3],
        r: vec![45.0],
        t: 2e5,
    };
    for solver in QpSolver::ALL {
        let s = solve(&pb, solver);
        let p = 2e5 / 45.0;
        assert!((s.load[0] - p).abs() <= 1e-12 * p);
        let theta = (1.2e-5 * p - 3e-3) / 45.0;
        assert!(
            (s.rotation - theta).abs() <= 1e-12 * theta.abs(),
            "{solver}"
        );
        assert!(s.within_tolerance && s.active[0]);
    }
}

#[test]
fn two_springs() {
    // both in contact: θ = (T + Σ rᵢwᵢ/cᵢ) / Σ rᵢ²/cᵢ, pᵢ = (θrᵢ − wᵢ)/cᵢ
    let (c1, c2, r1, r2, t) = (1e-5, 2e-5, 40.0, 50.0, 1e5);
    let pb = Problem {
        f: vec![c1, 0.0, 0.0, c2],
        w: vec![0.0, 1e-3],
        r: vec![r1, r2],
        t,
    };
    let theta = (t + r2 * 1e-3 / c2) / (r1 * r1 / c1 + r2 * r2 / c2);
    let p = [theta * r1 / c1, (theta * r2 - 1e-3) / c2];
    for solver in QpSolver::ALL {
        let s = solve(&pb, solver);
        assert!(
            (s.rotation - theta).abs() <= 1e-12 * theta,
            "{solver}: {}",
            s.rotation
        );
        assert!(
            rel_load_diff(&p, &s.load) <= 1e-12,
            "{solver}: {:?}",
            s.load
        );
        assert!(s.within_tolerance && s.active == [true, true]);
    }
    // second spring open: θ = (c₁T/r₁ + w₁)/r₁, g₂ = w₂ − θr₂ > 0
    let pb = Problem {
        w: vec![0.0, 5e-2],
        ..pb
    };
    let theta = c1 * t / r1 / r1;
    for solver in QpSolver::ALL {
        let s = solve(&pb, solver);
        assert!((s.rotation - theta).abs() <= 1e-12 * theta, "{solver}");
        assert_eq!(s.load[1], 0.0, "{solver}");
        assert!((s.gap[1] - (5e-2 - theta * r2)).abs() <= 1e-15);
        assert!(s.within_tolerance && s.active == [true, false]);
    }
}

#[test]
fn uniform_line_is_symmetric() {
    let n = 41;
    let x: Vec<[f64; 2]> = (0..n).map(|i| [0.5 * i as f64, 0.0]).collect();
    let pb = Problem {
        f: kernel(&x, 5e-6, 2.0, 5e-6),
        w: vec![0.0; n],
        r: vec![40.0; n],
        t: 1e5,
    };
    let (a, _) = agree(&pb, 1e-6, 1e-8);
    let pmax = a.load.iter().fold(0.0f64, |m, &v| m.max(v));
    for i in 0..n {
        assert!((a.load[i] - a.load[n - 1 - i]).abs() <= 1e-10 * pmax);
    }
    assert!(a.active.iter().all(|&v| v), "all points carry load");
    // the ends of a line carry more than the middle (kernel edge effect)
    assert!(a.load[0] > a.load[n / 2]);
}

#[test]
fn random_problems_agree() {
    for (k, &n) in [5usize, 10, 20, 50, 100, 200].iter().enumerate() {
        for generic in [false, true] {
            let pb = random_problem(n, 17 + k as u64, generic);
            let t0 = Instant::now();
            let a = solve(&pb, QpSolver::ActiveSet);
            let ta = t0.elapsed().as_secs_f64();
            let t0 = Instant::now();
            let c = solve(&pb, QpSolver::Clarabel);
            let tc = t0.elapsed().as_secs_f64();
            let (a2, _) = agree(&pb, 1e-6, 1e-8);
            assert_eq!(a.load, a2.load, "deterministic");
            assert!(a.kkt.max <= 1e-9);
            let loaded = a.active.iter().filter(|&&v| v).count();
            assert!(
                loaded > 0 && (n < 10 || loaded < n),
                "a mix of open and loaded points"
            );
            // clarabel's raw interior point, before the polish
            let raw = clarabel_raw(
                &Prepared::new(&pb.qp()).unwrap(),
                &options(QpSolver::Clarabel),
            )
            .unwrap();
            let dp_raw = rel_load_diff(&a.load, &raw.load);
            let dt_raw = (a.rotation - raw.rotation).abs() / a.rotation.abs();
            eprintln!(
                "n {n:3} {}: {loaded:3} loaded; active set {} it {:.2e} s KKT {:.1e}; clarabel {} it {:.2e} s raw KKT {:.1e} Δp {dp_raw:.1e} Δθ {dt_raw:.1e}, polished KKT {:.1e} ({} solves); θ {:.3e} Δp {:.1e} Δθ {:.1e}",
                if generic { "BBᵀ   " } else { "kernel" },
                a.iterations,
                ta,
                a.kkt.max,
                c.iterations,
                tc,
                c.raw_kkt.unwrap().max,
                c.kkt.max,
                c.polish_iterations,
                a.rotation,
                rel_load_diff(&a.load, &c.load),
                (a.rotation - c.rotation).abs() / a.rotation.abs()
            );
            assert!(c.polished);
            assert!(
                dp_raw <= 1e-6 && dt_raw <= 1e-8,
                "raw clarabel: Δp {dp_raw:.1e} Δθ {dt_raw:.1e}"
            );
        }
    }
}

#[test]
fn clarabel_raw_rotation_sign() {
    // θ = −z₀δ₀/r₀ from clarabel's raw duals (no polish) matches the
    // active set: the sign convention of the equality's multiplier
    let pb = random_problem(30, 5, false);
    let prob = Prepared::new(&pb.qp()).unwrap();
    let a = solve(&pb, QpSolver::ActiveSet);
    let raw_theta = clarabel_raw(&prob, &QpOptions::default()).unwrap().rotation;
    assert!(
        (raw_theta - a.rotation).abs() <= 1e-6 * a.rotation,
        "raw θ {raw_theta} vs {}",
        a.rotation
    );
}

#[test]
fn zero_torque() {
    let pb = Problem {
        t: 0.0,
        ..random_problem(12, 3, false)
    };
    let theta = (0..12)
        .map(|i| pb.w[i] / pb.r[i])
        .fold(f64::INFINITY, f64::min);
    for solver in QpSolver::ALL {
        let s = solve(&pb, solver);
        assert!(s.load.iter().all(|&v| v == 0.0));
        assert_eq!(s.rotation, theta);
        assert!(s.gap.iter().all(|&g| g >= -1e-18));
        assert!(s.within_tolerance && s.iterations == 0);
    }
}

/// A named problem and the indices of its twin points (if duplicated).
type Case = (String, Problem, Option<(usize, usize)>);

#[test]
fn extreme_cases() {
    let n = 60;
    let mut cases: Vec<(&str, Problem)> = Vec::new();
    for (name, s) in [("F×1e-3", 1e-3), ("F×1e3", 1e3)] {
        let mut pb = random_problem(n, 99, false);
        pb.f.iter_mut().for_each(|v| *v *= s);
        pb.w.iter_mut().for_each(|v| *v *= s);
        cases.push((name, pb));
    }
    for (name, s) in [("T×1e-3", 1e-3), ("T×10", 10.0)] {
        let mut pb = random_problem(n, 99, false);
        pb.t *= s;
        cases.push((name, pb));
    }
    // two bodies: the second half 100× stiffer, no coupling
    let mut pb = random_problem(n, 99, false);
    for i in 0..n {
        for j in 0..n {
            if (i < n / 2) != (j < n / 2) {
                pb.f[i * n + j] = 0.0;
            } else if i >= n / 2 {
                pb.f[i * n + j] *= 1e-2;
            }
        }
    }
    cases.push(("two bodies 100×", pb));
    // zero backlash: all separations equal
    let mut pb = random_problem(n, 99, false);
    pb.w.iter_mut().for_each(|v| *v = 1e-3);
    cases.push(("all w equal", pb));
    // heavy crowning along a line: w from 0 to 1 mm
    let x: Vec<[f64; 2]> = (0..n)
        .map(|i| [20.0 * i as f64 / (n - 1) as f64, 0.0])
        .collect();
    cases.push((
        "crowning 0…1 mm",
        Problem {
            f: kernel(&x, 8e-6, 1.5, 4e-6),
            w: x.iter().map(|p| ((p[0] - 6.0) / 14.0).powi(2)).collect(),
            r: vec![40.0; n],
            t: 1e5,
        },
    ));
    let mut all: Vec<Case> = cases
        .into_iter()
        .map(|(a, b)| (a.to_string(), b, None))
        .collect();
    // nearly duplicated points: a copy of the first point to close
    // (exact, and with its diagonal compliance 1e-9 larger)
    for (name, eps, flat) in [
        ("duplicate", 0.0, false),
        ("near duplicate", 1e-9, false),
        ("duplicate, w = 0", 0.0, true),
    ] {
        let mut pb = random_problem(n, 99, false);
        if flat {
            // both twins enter the loaded set together: F_SS singular
            pb.w.iter_mut().for_each(|v| *v = 0.0);
        }
        let k = (0..n)
            .min_by(|&a, &b| (pb.w[a] / pb.r[a]).total_cmp(&(pb.w[b] / pb.r[b])))
            .unwrap();
        // (w = 0: a pair away from the start point, 0)
        let (src, dst) = if flat {
            (n / 2, n / 2 + 1)
        } else {
            (k, if k == 0 { 1 } else { 0 })
        };
        for j in 0..n {
            pb.f[dst * n + j] = pb.f[src * n + j];
        }
        for i in 0..n {
            pb.f[i * n + dst] = pb.f[i * n + src];
        }
        pb.f[dst * n + dst] = pb.f[src * n + src] * (1.0 + eps);
        pb.w[dst] = pb.w[src];
        pb.r[dst] = pb.r[src];
        all.push((name.to_string(), pb, Some((src, dst))));
    }
    for (name, pb, twins) in &all {
        let a = solve(pb, QpSolver::ActiveSet);
        let c = solve(pb, QpSolver::Clarabel);
        check_basic(pb, &a);
        check_basic(pb, &c);
        let loaded = a.active.iter().filter(|&&v| v).count();
        eprintln!(
            "{name:16}: {loaded:2} loaded, κ(F) {:.1e}; active set {} it KKT {:.1e} reg {:.0e}; clarabel {} it KKT {:.1e} polished {} ({} solves) reg {:.0e}; Δp {:.1e} Δθ {:.1e}",
            condition_number(&pb.f, n),
            a.iterations,
            a.kkt.max,
            a.regularization,
            c.iterations,
            c.kkt.max,
            c.polished,
            c.polish_iterations,
            c.regularization,
            rel_load_diff(&a.load, &c.load),
            (a.rotation - c.rotation).abs() / a.rotation.abs()
        );
        assert!(a.within_tolerance, "{name}: active set {:?}", a.kkt);
        if name.contains("w = 0") {
            assert!(a.regularization > 0.0, "both twins entered together");
        }
        assert!(c.within_tolerance, "{name}: clarabel {:?}", c.kkt);
        assert!(
            (a.rotation - c.rotation).abs() <= 1e-8 * a.rotation.abs(),
            "{name}"
        );
        if let Some((i, j)) = *twins {
            // the split between the twins is not determined (exact
            // copy) or ill-determined (κ ~ 1e10): their sum and every
            // other load are
            let sum = |s: &QpSolution| {
                let mut l = s.load.clone();
                l[i] += l[j];
                l[j] = 0.0;
                l
            };
            assert!(rel_load_diff(&sum(&a), &sum(&c)) <= 1e-6, "{name}");
        } else {
            assert!(rel_load_diff(&a.load, &c.load) <= 1e-6, "{name}");
        }
    }
}

#[test]
fn bad_input() {
    let pb = random_problem(4, 1, false);
    let opts = QpOptions::default();
    let err = |qp: ContactQp| solve_contact_qp(&qp, &opts).unwrap_err().to_string();
    let empty: [f64; 0] = [];
    assert!(err(ContactQp {
        compliance: &empty,
        separation: &empty,
        moment_arm: &empty,
        torque: 1.0
    })
    .contains("no candidate"));
    assert!(err(ContactQp {
        moment_arm: &pb.r[..3],
        ..pb.qp()
    })
    .contains("moment arms"));
    assert!(err(ContactQp {
        compliance: &pb.f[..15],
        ..pb.qp()
    })
    .contains("compliance entries"));
    assert!(err(ContactQp {
        torque: -1.0,
        ..pb.qp()
    })
    .contains("torque"));
    assert!(err(ContactQp {
        torque: f64::NAN,
        ..pb.qp()
    })
    .contains("torque"));
    let mut w = pb.w.clone();
    w[2] = f64::INFINITY;
    assert!(err(ContactQp {
        separation: &w,
        ..pb.qp()
    })
    .contains("separation of point 2"));
    let mut r = pb.r.clone();
    r[1] = 0.0;
    assert!(err(ContactQp {
        moment_arm: &r,
        ..pb.qp()
    })
    .contains("moment arm of point 1"));
    let mut f = pb.f.clone();
    f[1] *= 2.0;
    assert!(err(ContactQp {
        compliance: &f,
        ..pb.qp()
    })
    .contains("not symmetric"));
    let mut f = pb.f.clone();
    f[5] = -1e-6;
    assert!(err(ContactQp {
        compliance: &f,
        ..pb.qp()
    })
    .contains("diagonal"));
    let mut f = pb.f.clone();
    f[7] = f64::NAN;
    assert!(err(ContactQp {
        compliance: &f,
        ..pb.qp()
    })
    .contains("compliance entry (1, 3)"));
    // iteration limits are errors naming the limit
    let big = random_problem(50, 7, false);
    for solver in QpSolver::ALL {
        let opts = QpOptions {
            solver,
            max_iterations: 2,
            ..QpOptions::default()
        };
        let e = solve_contact_qp(&big.qp(), &opts).unwrap_err().to_string();
        assert!(e.contains("iteration limit 2"), "{e}");
        // with the residual the iterate was left with
        assert!(e.contains("penetration") || e.contains("residuals"), "{e}");
    }
    assert!("simplex".parse::<QpSolver>().is_err());
    assert_eq!("clarabel".parse::<QpSolver>().unwrap(), QpSolver::Clarabel);
    assert_eq!(
        "active-set".parse::<QpSolver>().unwrap(),
        QpSolver::ActiveSet
    );
    assert_eq!(
        serde_json::to_string(&QpSolver::ActiveSet).unwrap(),
        "\"active-set\""
    );
    // the public residual on wrong lengths is NaN (never within tolerance)
    assert!(kkt(&pb.qp(), &[1.0], 0.0).max.is_nan());
    assert!(kkt(&pb.qp(), &[1.0, f64::NAN, 0.0, 0.0], 0.0).max.is_nan());
    assert!(kkt(&pb.qp(), &[1.0; 4], f64::INFINITY).max.is_nan());
}

#[test]
fn singular_blocks_on_chosen_points() {
    // rank 1 on points {0, 1}, regular on {0, 2} and {2}
    let f = [1.0, 1.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0, 2.0];
    assert!(singular_on(&f, 3, &[0, 1]));
    assert!(!singular_on(&f, 3, &[0, 2]));
    assert!(!singular_on(&f, 3, &[2]));
    assert!(!singular_on(&f, 3, &[]));
    // three points' loads interpolated from two nodes (the corner-line
    // case): F = Lᵀ C L with L 2 × 3 is singular; plus a diagonal is not
    let l = [[1.0, 0.5, 0.0], [0.0, 0.5, 1.0]];
    let c = [[2.0, 0.3], [0.3, 1.0]];
    let mut g = [0.0; 9];
    for i in 0..3 {
        for j in 0..3 {
            for a in 0..2 {
                for b in 0..2 {
                    g[i * 3 + j] += l[a][i] * c[a][b] * l[b][j];
                }
            }
        }
    }
    assert!(singular_on(&g, 3, &[0, 1, 2]));
    assert!(!singular_on(&g, 3, &[0, 2]));
    for k in 0..3 {
        g[k * 4] += 1e-3;
    }
    assert!(!singular_on(&g, 3, &[0, 1, 2]));
}

#[test]
fn condition_numbers() {
    assert!((condition_number(&[1.0, 0.0, 0.0, 4.0], 2) - 4.0).abs() < 1e-12);
    assert_eq!(condition_number(&[1.0, 1.0, 1.0, 1.0], 2), f64::INFINITY);
    assert!(condition_number(&[1.0], 2).is_nan());
}
