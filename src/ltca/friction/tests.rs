//! Unit tests of the frictional LTCA kernel. References: the frictionless
//! QP of [`crate::ltca::qp`] (μ = 0), the second solver (clarabel vs
//! Lemke), hand formulas for one point (stated in each test), the
//! linearity of an increment with constant states, and the input rules.

use std::time::Instant;

use super::*;
use crate::ltca::qp::{solve_contact_qp, ContactQp, QpOptions};
use crate::testing::Rng;

/// Owned problem data.
#[derive(Clone)]
struct Data {
    c_nn: Vec<f64>,
    c_nt: Vec<f64>,
    c_tn: Vec<f64>,
    c_tt: Vec<f64>,
    g0: Vec<f64>,
    r_n: Vec<f64>,
    r_t: Vec<f64>,
    s: Vec<f64>,
    mu: f64,
    t: f64,
}

impl Data {
    fn pb(&self) -> FrictionProblem<'_> {
        FrictionProblem {
            c_nn: &self.c_nn,
            c_nt: &self.c_nt,
            c_tn: &self.c_tn,
            c_tt: &self.c_tt,
            separation: &self.g0,
            arm_normal: &self.r_n,
            arm_tangential: &self.r_t,
            sliding: &self.s,
            mu: self.mu,
            point_mu: None,
            torque: self.t,
        }
    }

    /// Blocks from a full 2M × 2M row-major compliance.
    fn set_full(&mut self, full: &[f64], m: usize) {
        let at = |i: usize, j: usize| full[i * 2 * m + j];
        self.c_nn = (0..m * m).map(|k| at(k / m, k % m)).collect();
        self.c_nt = (0..m * m).map(|k| at(k / m, m + k % m)).collect();
        self.c_tn = (0..m * m).map(|k| at(m + k / m, k % m)).collect();
        self.c_tt = (0..m * m).map(|k| at(m + k / m, m + k % m)).collect();
    }
}

fn opts(solver: FrictionSolver, n: usize) -> FrictionOptions {
    FrictionOptions {
        solver,
        increments: Increments::Count(n),
        ..FrictionOptions::default()
    }
}

/// A line of M points over 10 mm (a contact-ellipse major axis): the
/// compliance [[a K, b K], [b K, e K]] + diag(d_n, d_t) with the Laplace
/// kernel K = exp(−|xᵢ − xⱼ|/λ) (positive definite; the 2 × 2 factor is
/// for ae > b²), crowned separations g⁰ = crown·(x − 5)²/25, r_n 40 mm,
/// r_t and s given as functions of x.
fn line(m: usize, mu: f64, crown: f64, rt: impl Fn(f64) -> f64, s: impl Fn(f64) -> f64) -> Data {
    let x: Vec<f64> = (0..m).map(|i| 10.0 * (i as f64 + 0.5) / m as f64).collect();
    let (a, b, e, lambda) = (3e-6, 1e-7, 2e-6, 2.0);
    let (dn, dt) = (1e-6 * m as f64 / 10.0, 0.8e-6 * m as f64 / 10.0);
    let mut full = vec![0.0; 4 * m * m];
    for i in 0..m {
        for j in 0..m {
            let k = (-(x[i] - x[j]).abs() / lambda).exp();
            full[i * 2 * m + j] = a * k + if i == j { dn } else { 0.0 };
            full[i * 2 * m + m + j] = b * k;
            full[(m + i) * 2 * m + j] = b * k;
            full[(m + i) * 2 * m + m + j] = e * k + if i == j { dt } else { 0.0 };
        }
    }
    let mut d = Data {
        c_nn: vec![],
        c_nt: vec![],
        c_tn: vec![],
        c_tt: vec![],
        g0: x
            .iter()
            .map(|&xi| crown * (xi - 5.0).powi(2) / 25.0)
            .collect(),
        r_n: x.iter().map(|&xi| 40.0 + 0.5 * xi).collect(),
        r_t: x.iter().map(|&xi| rt(xi)).collect(),
        s: x.iter().map(|&xi| s(xi)).collect(),
        mu,
        t: 1e5,
    };
    d.set_full(&full, m);
    d
}

/// A random flank-like problem: full compliance G Gᵀ/(2M) scaled to
/// ~1e-5 mm/N plus a diagonal, cross blocks multiplied by `coupling`
/// (keeps it PSD: a convex combination with the block diagonal);
/// separations (u − 0.3)·`sep` mm, r_n 30…60, r_t −15…15 mm, s given.
fn random(
    m: usize,
    seed: u64,
    mu: f64,
    sep: f64,
    coupling: f64,
    s: impl Fn(usize, f64) -> f64,
) -> Data {
    let mut rng = Rng::new(seed);
    let n2 = 2 * m;
    let g: Vec<f64> = (0..n2 * n2).map(|_| rng.unit()).collect();
    let mut full = vec![0.0; n2 * n2];
    for i in 0..n2 {
        for j in 0..n2 {
            let v: f64 = (0..n2).map(|k| g[i * n2 + k] * g[j * n2 + k]).sum();
            let cross = (i < m) != (j < m);
            full[i * n2 + j] = 1e-5 * v / n2 as f64 * if cross { coupling } else { 1.0 }
                + if i == j { 3e-6 } else { 0.0 };
        }
    }
    let mut d = Data {
        c_nn: vec![],
        c_nt: vec![],
        c_tn: vec![],
        c_tt: vec![],
        g0: (0..m)
            .map(|_| (0.5 * (rng.unit() + 1.0) - 0.3) * sep)
            .collect(),
        r_n: (0..m).map(|_| 45.0 + 15.0 * rng.unit()).collect(),
        r_t: (0..m).map(|_| 15.0 * rng.unit()).collect(),
        s: vec![],
        mu,
        t: 1e5,
    };
    d.s = (0..m).map(|i| s(i, rng.unit())).collect();
    d.set_full(&full, m);
    d
}

/// A line whose sliding passes through zero at mid-line (a pitch point):
/// r_t = 8(x − 5) mm/rad and s chosen so that ρ = r_t + s r_n = α(x − 5).
fn zero_sliding_line(m: usize, mu: f64, crown: f64, alpha: f64) -> Data {
    let rt = |x: f64| 8.0 * (x - 5.0);
    let s = move |x: f64| (alpha * (x - 5.0) - rt(x)) / (40.0 + 0.5 * x);
    line(m, mu, crown, rt, s)
}

/// (d): the residuals of every increment within 1e-9 (the default
/// tolerance), no loop at its bound.
fn assert_residuals(sol: &FrictionSolution, what: &str) {
    let r = &sol.max_residual;
    // which increments needed the semismooth Newton polish (README)
    let newton: usize = sol.increments.iter().map(|k| k.newton_iterations).sum();
    if newton > 0 {
        eprintln!(
            "{what} ({}): semismooth Newton polish {newton} iterations, answers in {} of {} increments",
            sol.solver.name(),
            sol.increments.iter().filter(|k| k.newton).count(),
            sol.increments.len()
        );
    }
    assert!(
        sol.within_tolerance && r.max <= 1e-9,
        "{what} ({}): residuals {r:?}",
        sol.solver.name()
    );
}

/// Both solvers, each checked, their difference ≤ 1e-8 (loads relative
/// to max P_n, rotation relative to its loaded change); returns it.
fn agree(d: &Data, n: usize, what: &str) -> CrossCheck {
    let cc = cross_check(&d.pb(), &opts(FrictionSolver::Clarabel, n)).unwrap();
    assert_residuals(&cc.clarabel, what);
    assert_residuals(&cc.lemke, what);
    assert!(
        cc.load_difference <= 1e-8 && cc.rotation_difference <= 1e-8,
        "{what}: clarabel vs Lemke loads {:.2e}, rotation {:.2e}",
        cc.load_difference,
        cc.rotation_difference
    );
    eprintln!(
        "{what}: clarabel vs Lemke loads {:.2e} rotation {:.2e} states differ {}; residual clarabel {:.1e} lemke {:.1e}",
        cc.load_difference,
        cc.rotation_difference,
        cc.state_differences,
        cc.clarabel.max_residual.max,
        cc.lemke.max_residual.max
    );
    cc
}

fn count(inc: &Increment, s: PointState) -> usize {
    inc.state.iter().filter(|&&v| v == s).count()
}

// (a) μ = 0 reproduces the frictionless QP (reference: solve_contact_qp,
// active set) to 1e-10, both solvers, random and structured problems.
#[test]
fn mu_zero_reproduces_frictionless_qp() {
    let mut cases = Vec::new();
    for seed in 1..=6u64 {
        cases.push((
            format!("random {seed}"),
            random(12 + 3 * seed as usize, seed, 0.0, 4e-3, 0.3, |_, u| 3.0 * u),
        ));
    }
    cases.push((
        "line crowned".into(),
        line(40, 0.0, 2e-3, |x| x - 5.0, |_| 2.0),
    ));
    cases.push(("line flat".into(), line(25, 0.0, 0.0, |x| x - 5.0, |_| 2.0)));
    let mut worst = 0.0f64;
    for (name, d) in &cases {
        let qp = solve_contact_qp(
            &ContactQp {
                compliance: &d.c_nn,
                separation: &d.g0,
                moment_arm: &d.r_n,
                torque: d.t,
            },
            &QpOptions::default(),
        )
        .unwrap();
        assert!(qp.within_tolerance);
        let pmax = qp.load.iter().fold(0.0f64, |a, v| a.max(*v));
        for solver in [FrictionSolver::Clarabel, FrictionSolver::Lemke] {
            for n in [1, 4] {
                let sol = solve_friction(&d.pb(), &opts(solver, n)).unwrap();
                assert_residuals(&sol, name);
                let last = sol.increments.last().unwrap();
                let dp = (0..d.g0.len()).fold(0.0f64, |a, i| {
                    a.max((last.normal[i] - qp.load[i]).abs() / pmax)
                        .max(last.tangential[i].abs() / pmax)
                });
                let dth =
                    (last.rotation - qp.rotation).abs() / (qp.rotation - sol.start_rotation).abs();
                worst = worst.max(dp).max(dth);
                assert!(
                    dp <= 1e-10 && dth <= 1e-10,
                    "{name} {} N={n}: loads {dp:.2e}, rotation {dth:.2e}",
                    solver.name()
                );
            }
        }
    }
    eprintln!("μ = 0 vs frictionless QP: max difference {worst:.2e}");
}

// (b) clarabel vs Lemke on random problems: mixed separations, kinematic
// sliding of both signs (all-slip when |s| is large) and weak sliding.
#[test]
fn clarabel_and_lemke_agree_random() {
    for seed in 1..=6u64 {
        let m = 8 + 4 * seed as usize;
        let d = random(m, seed, 0.1, 4e-3, 0.3, |_, u| 4.0 * u);
        let cc = agree(&d, 3, &format!("random seed {seed} M {m}"));
        let last = cc.lemke.increments.last().unwrap();
        assert!(
            count(last, PointState::Separated) > 0,
            "seed {seed}: some points must stay open"
        );
        // weak sliding: stick possible
        let d = random(m, seed + 100, 0.15, 2e-3, 0.2, |_, u| 0.02 * u);
        agree(&d, 4, &format!("random weak sliding seed {seed}"));
    }
}

// (b) structured: a line with all points slipping forward (s = 3 ≫ the
// elastic terms), with crowning (separated ends) and without.
#[test]
fn clarabel_and_lemke_agree_all_slip() {
    for (crown, sep) in [(0.0, false), (3e-3, true)] {
        let d = line(30, 0.1, crown, |x| 0.5 * (x - 5.0), |_| 3.0);
        let cc = agree(&d, 5, &format!("all slip, crown {crown}"));
        let last = cc.clarabel.increments.last().unwrap();
        let closed = 30 - count(last, PointState::Separated);
        assert_eq!(
            count(last, PointState::SlipPositive),
            closed,
            "every closed point slips along +t"
        );
        assert_eq!(count(last, PointState::Separated) > 0, sep);
        for i in 0..30 {
            let (pn, pt) = (last.normal[i], last.tangential[i]);
            assert!((pt - 0.1 * pn).abs() <= 1e-12 * pn.abs().max(1.0));
        }
    }
}

// (b) structured: sliding through zero at mid-line (a pitch point): ρ =
// r_t + s r_n = x − 5 mm/rad. Near x = 5 the points stick, away from
// it they slip in opposite directions (ρ changes sign).
#[test]
fn clarabel_and_lemke_agree_stick_near_zero_sliding() {
    for crown in [0.0, 1e-3] {
        let d = zero_sliding_line(31, 0.12, crown, 1.0);
        let cc = agree(&d, 6, &format!("zero sliding at mid-line, crown {crown}"));
        let last = cc.lemke.increments.last().unwrap();
        let (st, sp, sn) = (
            count(last, PointState::Stick),
            count(last, PointState::SlipPositive),
            count(last, PointState::SlipNegative),
        );
        eprintln!("  states: stick {st}, slip+ {sp}, slip− {sn}");
        assert!(
            st > 0 && sp > 0 && sn > 0,
            "stick near zero sliding, slip both ways away from it"
        );
        assert_eq!(
            last.state[15],
            PointState::Stick,
            "the zero-sliding point sticks"
        );
    }
}

// (c) One point, slipping: with s ≫ 0 the point slips along +t, so
// P_t = μP_n, T = (r_n + μ r_t)P_n ⇒ P_n = T/(r_n + μ r_t), and g = 0 ⇒
// θ = (g⁰ + (c_nn + μ c_nt)P_n)/r_n. One point, sticking: with ρ = 0
// (s = −r_t/r_n) and |c_tn/c_tt| ≤ μ, Δσ = −(c_tn ΔP_n + c_tt ΔP_t) = 0 ⇒
// P_t = −(c_tn/c_tt)P_n, P_n = T/(r_n − r_t c_tn/c_tt),
// θ = (g⁰ + (c_nn − c_nt c_tn/c_tt)P_n)/r_n.
#[test]
fn one_point_closed_forms() {
    let (c, b, e, g0, rn, rt, mu, t) = (2e-5, 1e-6, 1.5e-5, 1e-3, 40.0, 12.0, 0.1, 5e4);
    let mut d = Data {
        c_nn: vec![c],
        c_nt: vec![b],
        c_tn: vec![b],
        c_tt: vec![e],
        g0: vec![g0],
        r_n: vec![rn],
        r_t: vec![rt],
        s: vec![5.0],
        mu,
        t,
    };
    let pn = t / (rn + mu * rt);
    let th = (g0 + (c + mu * b) * pn) / rn;
    for solver in [FrictionSolver::Clarabel, FrictionSolver::Lemke] {
        let sol = solve_friction(&d.pb(), &opts(solver, 3)).unwrap();
        assert_residuals(&sol, "one point slip");
        let k = sol.increments.last().unwrap();
        assert_eq!(k.state[0], PointState::SlipPositive);
        assert!(
            (k.normal[0] - pn).abs() <= 1e-12 * pn,
            "{} vs {pn}",
            k.normal[0]
        );
        assert!((k.tangential[0] - mu * pn).abs() <= 1e-12 * pn);
        assert!((k.rotation - th).abs() <= 1e-12 * th.abs());
    }
    // stick
    d.s = vec![-rt / rn];
    let pn = t / (rn - rt * b / e);
    let th = (g0 + (c - b * b / e) * pn) / rn;
    for solver in [FrictionSolver::Clarabel, FrictionSolver::Lemke] {
        let sol = solve_friction(&d.pb(), &opts(solver, 2)).unwrap();
        assert_residuals(&sol, "one point stick");
        let k = sol.increments.last().unwrap();
        assert_eq!(k.state[0], PointState::Stick);
        assert!(
            (k.normal[0] - pn).abs() <= 1e-12 * pn,
            "{} vs {pn}",
            k.normal[0]
        );
        assert!((k.tangential[0] + b / e * pn).abs() <= 1e-12 * pn);
        assert!((k.rotation - th).abs() <= 1e-12 * th.abs());
    }
    // the same with s ≪ 0: slip along −t, P_n = T/(r_n − μ r_t)
    d.s = vec![-5.0];
    let pn = t / (rn - mu * rt);
    let sol = solve_friction(&d.pb(), &opts(FrictionSolver::Lemke, 1)).unwrap();
    let k = sol.increments.last().unwrap();
    assert_eq!(k.state[0], PointState::SlipNegative);
    assert!((k.normal[0] - pn).abs() <= 1e-12 * pn);
}

// (e) With constant states every increment is the same linear map of ΔT:
// the answer must not depend on the number of increments (all points in
// contact from the start and slipping forward throughout).
#[test]
fn constant_states_do_not_depend_on_increments() {
    let d = line(24, 0.1, 0.0, |x| 0.5 * (x - 5.0), |_| 3.0);
    for solver in [FrictionSolver::Clarabel, FrictionSolver::Lemke] {
        let one = solve_friction(&d.pb(), &opts(solver, 1)).unwrap();
        let a = one.increments.last().unwrap();
        let pmax = a.normal.iter().fold(0.0f64, |x, v| x.max(*v));
        for n in [3, 10] {
            let many = solve_friction(&d.pb(), &opts(solver, n)).unwrap();
            assert_residuals(&many, "constant states");
            for k in &many.increments {
                assert_eq!(count(k, PointState::SlipPositive), 24);
            }
            let b = many.increments.last().unwrap();
            for i in 0..24 {
                assert!((a.normal[i] - b.normal[i]).abs() <= 1e-10 * pmax);
                assert!((a.tangential[i] - b.tangential[i]).abs() <= 1e-10 * pmax);
            }
            assert!(
                (a.rotation - b.rotation).abs() <= 1e-10 * (a.rotation - one.start_rotation).abs()
            );
        }
    }
}

// (e) Path dependence: crowned line, zero sliding at mid-line; points
// close during the loading (and enter in slip), the centre point sticks
// along the fine path. With 1 or 5 increments the centre point slips in
// the first (coarse) increment, so its friction force, which carries the
// history, differs from the load path's (3e-3 of max P_n); from 20
// increments on the states at the increments' ends are those of the fine
// path and, each increment being linear in its states, the answer is
// that of 80 increments to round-off.
#[test]
fn state_changes_make_the_answer_path_dependent() {
    let d = zero_sliding_line(21, 0.12, 2e-3, 4.0);
    let run = |n| {
        let sol = solve_friction(&d.pb(), &opts(FrictionSolver::Lemke, n)).unwrap();
        assert_residuals(&sol, "path dependence");
        sol.increments.last().unwrap().clone()
    };
    let reference = run(80);
    let pmax = reference.normal.iter().fold(0.0f64, |x, v| x.max(*v));
    let diff = |k: &Increment| {
        (0..21).fold(0.0f64, |a, i| {
            a.max((k.tangential[i] - reference.tangential[i]).abs() / pmax)
                .max((k.normal[i] - reference.normal[i]).abs() / pmax)
        })
    };
    let d1 = diff(&run(1));
    let d5 = diff(&run(5));
    let d20 = diff(&run(20));
    eprintln!("path dependence vs 80 increments: N=1 {d1:.2e}, N=5 {d5:.2e}, N=20 {d20:.2e}");
    assert!(
        d1 > 1e-4,
        "one increment must differ from the load path: {d1:.2e}"
    );
    assert!(
        d20 < d1 / 4.0 && d5 <= d1,
        "refining must converge: {d1:.2e} {d5:.2e} {d20:.2e}"
    );
    // and the two solvers still agree on the path
    agree(&d, 7, "path-dependent case");
}

// Increment size: ΔT = 3e4 on T = 1e5 gives 3e4, 6e4, 9e4, 1e5.
#[test]
fn increment_size_schedule() {
    let t = incremental::schedule(1e5, Increments::Size(3e4)).unwrap();
    assert_eq!(t, vec![3e4, 6e4, 9e4, 1e5]);
    let t = incremental::schedule(1e5, Increments::Size(2.5e4)).unwrap();
    assert_eq!(t.len(), 4);
    assert_eq!(*t.last().unwrap(), 1e5);
    assert!(incremental::schedule(0.0, Increments::Count(3))
        .unwrap()
        .is_empty());
}

// T = 0: no increments, the rigid start θ₀ = min g⁰/r_n.
#[test]
fn zero_torque_is_the_rigid_start() {
    let mut d = line(10, 0.1, 1e-3, |x| x - 5.0, |_| 1.0);
    d.t = 0.0;
    let sol = solve_friction(&d.pb(), &FrictionOptions::default()).unwrap();
    assert!(sol.increments.is_empty());
    let th = (0..10)
        .map(|i| d.g0[i] / d.r_n[i])
        .fold(f64::INFINITY, f64::min);
    assert_eq!(sol.rotation(), th);
}

// (f) bad input: a clear error, never a panic or NaN.
#[test]
fn bad_input_is_an_error() {
    let good = line(6, 0.1, 1e-3, |x| x - 5.0, |_| 1.0);
    assert!(solve_friction(&good.pb(), &FrictionOptions::default()).is_ok());
    let mut cases: Vec<(&str, Data, FrictionOptions)> = Vec::new();
    let o = FrictionOptions::default();
    let mut d = good.clone();
    d.c_nn[3] = f64::NAN;
    cases.push(("NaN compliance", d, o.clone()));
    let mut d = good.clone();
    d.g0[2] = f64::INFINITY;
    cases.push(("infinite separation", d, o.clone()));
    let mut d = good.clone();
    d.mu = -0.1;
    cases.push(("μ < 0", d, o.clone()));
    let mut d = good.clone();
    d.mu = f64::NAN;
    cases.push(("μ NaN", d, o.clone()));
    let mut d = good.clone();
    d.t = -1.0;
    cases.push(("T < 0", d, o.clone()));
    cases.push((
        "zero increments",
        good.clone(),
        FrictionOptions {
            increments: Increments::Count(0),
            ..o.clone()
        },
    ));
    cases.push((
        "increment size 0",
        good.clone(),
        FrictionOptions {
            increments: Increments::Size(0.0),
            ..o.clone()
        },
    ));
    let mut d = good.clone();
    d.r_t.pop();
    cases.push(("dimension mismatch", d, o.clone()));
    let mut d = good.clone();
    d.c_tt.pop();
    cases.push(("compliance size", d, o.clone()));
    let mut d = good.clone();
    d.r_n[1] = 0.0;
    cases.push(("r_n = 0", d, o.clone()));
    let mut d = good.clone();
    d.r_t[1] = 500.0;
    cases.push(("self-locking", d, o.clone()));
    let mut d = good.clone();
    d.c_nn[1] *= 1.01;
    cases.push(("asymmetric C_nn", d, o.clone()));
    let mut d = good.clone();
    d.c_tn[1] += 1e-7;
    cases.push(("C_tn ≠ C_ntᵀ", d, o.clone()));
    let mut d = good.clone();
    for v in d.c_nt.iter_mut().chain(d.c_tn.iter_mut()) {
        *v *= 100.0;
    }
    cases.push(("not PSD", d, o.clone()));
    let mut d = good.clone();
    d.c_nn[0] = -1e-6;
    cases.push(("C_nn diagonal ≤ 0", d, o.clone()));
    let mut d = good.clone();
    d.g0.clear();
    d.r_n.clear();
    d.r_t.clear();
    d.s.clear();
    d.c_nn.clear();
    d.c_nt.clear();
    d.c_tn.clear();
    d.c_tt.clear();
    cases.push(("no points", d, o.clone()));
    cases.push((
        "zero pivot limit",
        good.clone(),
        FrictionOptions {
            max_pivots: 0,
            ..o.clone()
        },
    ));
    for (name, d, o) in cases {
        match solve_friction(&d.pb(), &o) {
            Err(FlankError::Model(msg)) => eprintln!("{name}: {msg}"),
            other => panic!("{name}: expected a model error, got {other:?}"),
        }
    }
}

// A pivot limit too small for the problem is a solver error naming it.
#[test]
fn lemke_pivot_limit_is_reported() {
    let d = line(12, 0.1, 1e-3, |x| x - 5.0, |_| 1.0);
    let o = FrictionOptions {
        max_pivots: 3,
        ..opts(FrictionSolver::Lemke, 1)
    };
    match solve_friction(&d.pb(), &o) {
        Err(FlankError::Solver(msg)) => assert!(msg.contains("pivot limit"), "{msg}"),
        other => panic!("expected a pivot-limit error, got {other:?}"),
    }
}

// A fixed-point limit of 1 on the clarabel path: the polish still makes
// the answer exact, or the limit is reported.
#[test]
fn fixed_point_limit_is_reported_or_polished() {
    let d = line(16, 0.12, 1e-3, |x| x - 5.0, |_| 0.5);
    let o = FrictionOptions {
        max_fixed_point: 1,
        ..opts(FrictionSolver::Clarabel, 3)
    };
    let sol = solve_friction(&d.pb(), &o).unwrap();
    for k in &sol.increments {
        assert!(k.polished || k.limit_hit);
    }
    assert!(sol.within_tolerance || sol.increments.iter().any(|k| k.limit_hit));
}

// Timings and figures for the README (M = 30, 50, 100; 10 increments):
// `cargo test --release --lib ltca::friction::tests::timing -- --ignored --nocapture`.
#[test]
#[ignore]
fn timing() {
    for m in [30, 50, 100] {
        for (name, d) in [
            ("all slip", line(m, 0.1, 2e-3, |x| 0.5 * (x - 5.0), |_| 3.0)),
            (
                "zero sliding mid-line",
                zero_sliding_line(m, 0.12, 2e-3, 4.0),
            ),
        ] {
            let n = 10;
            let t0 = Instant::now();
            let a = solve_friction(&d.pb(), &opts(FrictionSolver::Clarabel, n)).unwrap();
            let ta = t0.elapsed().as_secs_f64() / n as f64;
            let t0 = Instant::now();
            let b = solve_friction(&d.pb(), &opts(FrictionSolver::Lemke, n)).unwrap();
            let tb = t0.elapsed().as_secs_f64() / n as f64;
            let cc = cross_check(&d.pb(), &opts(FrictionSolver::Clarabel, n)).unwrap();
            let fp: usize = a.increments.iter().map(|k| k.iterations).max().unwrap();
            let ipm: usize = a.increments.iter().map(|k| k.inner_iterations).sum();
            let pol: usize = a
                .increments
                .iter()
                .map(|k| k.polish_iterations)
                .max()
                .unwrap();
            let piv: usize = b.increments.iter().map(|k| k.iterations).max().unwrap();
            let last = b.increments.last().unwrap();
            println!(
                "M {m:3} {name:22} clarabel {:.2} ms/inc (fixed point ≤ {fp}, IPM {ipm} total, polish ≤ {pol}), Lemke {:.2} ms/inc (≤ {piv} pivots); diff loads {:.1e} θ {:.1e}; residual {:.1e} / {:.1e}; states sep {} stick {} slip+ {} slip− {}",
                ta * 1e3,
                tb * 1e3,
                cc.load_difference,
                cc.rotation_difference,
                a.max_residual.max,
                b.max_residual.max,
                count(last, PointState::Separated),
                count(last, PointState::Stick),
                count(last, PointState::SlipPositive),
                count(last, PointState::SlipNegative),
            );
        }
    }
}

// (b) Beyond the seeds' μ = 0.07: μ = 0.3 and 0.5 with cross blocks at
// 0.9 of the PSD limit, strong and weak sliding; the solvers still agree
// (Lemke has no termination guarantee for friction LCPs; none of these
// ends on a ray).
#[test]
fn clarabel_and_lemke_agree_strong_friction() {
    for (mu, coupling) in [(0.3, 0.9), (0.5, 0.9)] {
        for seed in 1..=3u64 {
            let d = random(20, seed, mu, 4e-3, coupling, |_, u| 4.0 * u);
            agree(&d, 5, &format!("μ {mu} coupling {coupling} seed {seed}"));
            let d = random(20, seed, mu, 4e-3, coupling, |_, u| 0.05 * u);
            agree(
                &d,
                5,
                &format!("μ {mu} coupling {coupling} seed {seed}, weak sliding"),
            );
        }
    }
}

// A duplicated candidate point (C singular, the split of the load between
// the two copies not unique): no panic, both solvers within tolerance
// (clarabel's state system is singular, so the active-set polish fails
// and the semismooth Newton polish gets there through its
// Levenberg–Marquardt direction, 2.2e-16; before it the Tresca answer
// stood at ~1e-10; Lemke puts the load on one copy), and the pair's total
// load agrees to 1e-8 (5.3e-16).
#[test]
fn duplicated_point_is_handled() {
    let m = 10;
    let mut d = line(m, 0.1, 1e-3, |x| 0.5 * (x - 5.0), |_| 3.0);
    for c in [&mut d.c_nn, &mut d.c_nt, &mut d.c_tn, &mut d.c_tt] {
        for j in 0..m {
            c[5 * m + j] = c[4 * m + j];
        }
        for i in 0..m {
            c[i * m + 5] = c[i * m + 4];
        }
    }
    d.g0[5] = d.g0[4];
    d.r_n[5] = d.r_n[4];
    d.r_t[5] = d.r_t[4];
    d.s[5] = d.s[4];
    let sums: Vec<f64> = [FrictionSolver::Clarabel, FrictionSolver::Lemke]
        .into_iter()
        .map(|solver| {
            let sol = solve_friction(&d.pb(), &opts(solver, 3)).unwrap();
            let k = sol.increments.last().unwrap();
            eprintln!(
                "duplicated point, {}: residual {:.1e}, polished {}, semismooth Newton {} iterations (answer: {})",
                solver.name(),
                sol.max_residual.max,
                k.polished,
                sol.increments.iter().map(|k| k.newton_iterations).sum::<usize>(),
                k.newton
            );
            assert!(
                sol.within_tolerance,
                "{}: {:?}",
                solver.name(),
                sol.max_residual
            );
            let k = sol.increments.last().unwrap();
            k.normal[4] + k.normal[5]
        })
        .collect();
    eprintln!(
        "duplicated point: pair total clarabel vs Lemke {:.1e}",
        (sums[0] - sums[1]).abs() / sums[1]
    );
    assert!((sums[0] - sums[1]).abs() <= 1e-8 * sums[1], "{sums:?}");
}
