//! Isothermal, steady, smooth line-contact EHL solver: the numerical
//! reference the film formulas are checked against (README.md gives the
//! equations with their sources).
//!
//! Dimensionless variables of Venner & Lubrecht (*Multilevel Methods in
//! Lubrication*, Elsevier 2000, ch. 8): X = x/b, P = p/p_H, H = hR/b²,
//! with the Hertz half-width b = (8w′R/(πE′))^½ and pressure
//! p_H = 2w′/(πb) = bE′/(4R). Then
//!
//! ```text
//!   Reynolds  d/dX(ε dP/dX) − d(ρ̄H)/dX = 0,  ε = ρ̄H³/(η̄λ̄),  λ̄ = 12 u η₀ R²/(b³ p_H)
//!   film      H = H₀ + X²/2 − (1/π) ∫ ln|X − X′| P(X′) dX′
//!   load      ∫ P dX = π/2
//!   cavitation  P ≥ 0, L(P) ≤ 0, P·L(P) = 0  (Reynolds/Swift–Stieber exit)
//! ```
//!
//! u = (u₁ + u₂)/2 the entraining speed, E′ = 2/[(1 − ν₁²)/E₁ + (1 − ν₂²)/E₂].
//! Discretisation: uniform nodes, central differences for the Poiseuille
//! term, second-order upwind for the wedge term (first order next to the
//! inlet), piecewise-constant pressure on cells of width Δ for the
//! deformation integral, integrated exactly. Solution: semi-smooth Newton on
//! (P, H₀) with the complementarity written as min(P_i, −L_i) = 0, the dense
//! Jacobian (the kernel couples every node), LU, backtracking on the scaled
//! residual, bounded iterations.

use faer::linalg::solvers::Solve;
use faer::Mat;
use std::f64::consts::PI;

/// Pressure–viscosity law.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Viscosity {
    /// Barus (1893): η = η₀ e^(αp).
    Barus,
    /// Roelands (1966): η = η₀ exp{(ln η₀ + 9.67)[(1 + p/p₀)^z − 1]},
    /// p₀ = 1.96e8 Pa, z = αp₀/(ln η₀ + 9.67) (same slope α at p = 0).
    Roelands,
}

/// Roelands' reference pressure p₀ (Pa).
pub const ROELANDS_P0: f64 = 1.96e8;

/// One operating point in SI units.
#[derive(Clone, Copy, Debug)]
pub struct Case {
    /// η₀ (Pa·s), α (1/Pa).
    pub eta0: f64,
    pub alpha: f64,
    /// E′ (Pa), R (m), load per unit length w′ (N/m), entraining speed u (m/s).
    pub e_prime: f64,
    pub radius: f64,
    pub load: f64,
    pub speed: f64,
    pub viscosity: Viscosity,
    /// Dowson–Higginson density (false: incompressible).
    pub compressible: bool,
    /// Elastic deformation (false: rigid cylinders).
    pub elastic: bool,
}

impl Case {
    /// Hertz half-width b (m).
    pub fn b(&self) -> f64 {
        (8.0 * self.load * self.radius / (PI * self.e_prime)).sqrt()
    }
    /// Hertz maximum pressure p_H (Pa).
    pub fn p_hertz(&self) -> f64 {
        2.0 * self.load / (PI * self.b())
    }
    /// Hamrock's groups U = η₀u/(E′R), G = αE′, W′ = w′/(E′R).
    pub fn groups(&self) -> (f64, f64, f64) {
        (
            self.eta0 * self.speed / (self.e_prime * self.radius),
            self.alpha * self.e_prime,
            self.load / (self.e_prime * self.radius),
        )
    }
    /// Moes' M = W′(2U)^−½ and L = G(2U)^¼ (2U: the group on u₁ + u₂).
    pub fn moes(&self) -> (f64, f64) {
        let (u, g, w) = self.groups();
        (w / (2.0 * u).sqrt(), g * (2.0 * u).powf(0.25))
    }
    fn lambda(&self) -> f64 {
        let b = self.b();
        12.0 * self.speed * self.eta0 * self.radius * self.radius / (b.powi(3) * self.p_hertz())
    }
    /// η̄ = η/η₀ and d ln η̄/dP at dimensionless pressure P.
    fn viscosity(&self, pd: f64) -> (f64, f64) {
        let ph = self.p_hertz();
        let p = pd * ph;
        match self.viscosity {
            Viscosity::Barus => ((self.alpha * p).exp(), self.alpha * ph),
            Viscosity::Roelands => {
                let c = self.eta0.ln() + 9.67;
                let z = self.alpha * ROELANDS_P0 / c;
                let s = 1.0 + p / ROELANDS_P0;
                (
                    (c * (s.powf(z) - 1.0)).exp(),
                    c * z * s.powf(z - 1.0) * ph / ROELANDS_P0,
                )
            }
        }
    }
    /// ρ̄ = ρ/ρ₀ and dρ̄/dP: Dowson & Higginson (1966)
    /// ρ̄ = 1 + 0.6e-9 p/(1 + 1.7e-9 p), p in Pa.
    fn density(&self, pd: f64) -> (f64, f64) {
        if !self.compressible {
            return (1.0, 0.0);
        }
        let ph = self.p_hertz();
        let p = pd * ph;
        let d = 1.0 + 1.7e-9 * p;
        (1.0 + 0.6e-9 * p / d, 0.6e-9 * ph / (d * d))
    }
}

/// Uniform grid on [x_in, x_out] (units of b) with n nodes.
#[derive(Clone, Copy, Debug)]
pub struct Grid {
    pub x_in: f64,
    pub x_out: f64,
    pub n: usize,
}

/// Iteration bounds, tolerances and the starting point.
#[derive(Clone, Debug)]
pub struct Settings {
    pub max_newton: usize,
    /// Converged when the scaled Reynolds residual, the load error and the
    /// last relative change of H₀ are all below `tol`.
    pub tol: f64,
    /// Initial film guess H_c·R/b²; None: Grubin's inlet estimate
    /// H_c = 1.95 (GU)^(8/11) W′^(−1/11) (Grubin 1949), or Martin's
    /// 4.9U/W′ for a rigid or isoviscous case, whichever is larger.
    pub film_guess: Option<f64>,
    /// Start from (P, H₀) of an earlier solution on the same grid
    /// (continuation); None: the Hertz pressure and the film guess.
    pub start: Option<(Vec<f64>, f64)>,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            max_newton: 100,
            tol: 1e-10,
            film_guess: None,
            start: None,
        }
    }
}

/// Converged (or last) state.
#[derive(Clone, Debug)]
pub struct Solution {
    pub x: Vec<f64>,
    /// P = p/p_H and H = hR/b² at the nodes.
    pub p: Vec<f64>,
    pub h: Vec<f64>,
    pub h0: f64,
    /// Central (X = 0) and minimum film thickness (m).
    pub h_central: f64,
    pub h_min: f64,
    /// Largest pressure (Pa).
    pub p_max: f64,
    pub newton_iterations: usize,
    /// Steps whose backtracking reached its bound (step taken anyway).
    pub line_search_bound_hits: usize,
    pub converged: bool,
    /// Reynolds residual: the largest flux imbalance |L_i|Δ of a pressurised
    /// cell relative to H(X = 0) (the Couette flow through the centre), or
    /// |P_i| of a cavitated node.
    pub reynolds_residual: f64,
    /// |Δ Σ P − π/2| / (π/2).
    pub load_error: f64,
    /// Hertz half-width b (m) and pressure p_H (Pa) of the scaling.
    pub b: f64,
    pub p_hertz: f64,
}

/// Deformation kernel of a piecewise-constant pressure cell: the film
/// contribution at a node `d` cells away from a cell of width Δ carrying
/// unit pressure, −(1/π) ∫ ln|X − X′| dX′ over the cell, exactly:
/// −(1/π)[F(dΔ + Δ/2) − F(dΔ − Δ/2)], F(t) = t ln|t| − t.
pub fn kernel(n: usize, dx: f64) -> Vec<f64> {
    let f = |t: f64| if t == 0.0 { 0.0 } else { t * t.abs().ln() - t };
    (0..n)
        .map(|d| {
            let t = d as f64 * dx;
            -(f(t + 0.5 * dx) - f(t - 0.5 * dx)) / PI
        })
        .collect()
}

/// Elastic part of H at every node for nodal pressures `p` (cells centred on the nodes).
pub fn deformation(k: &[f64], p: &[f64]) -> Vec<f64> {
    let n = p.len();
    (0..n)
        .map(|i| (0..n).map(|j| k[i.abs_diff(j)] * p[j]).sum())
        .collect()
}

struct State {
    h: Vec<f64>,
    eps: Vec<f64>,
    rho: Vec<f64>,
    drho: Vec<f64>,
    dlneta: Vec<f64>,
    /// Reynolds operator L_i at interior nodes (0 at the ends).
    l: Vec<f64>,
    /// c_i = Δ²/(ε_{i−½} + ε_{i+½}): −c_i L_i is the pressure change a
    /// Gauss–Seidel step on node i would make (Christopherson's test).
    c: Vec<f64>,
}

impl State {
    /// Node i carries pressure (Reynolds row) rather than being cavitated
    /// (P_i = 0 row): P_i + c_i L_i > 0, i.e. min(P_i, −c_i L_i) = −c_i L_i.
    fn pressurised(&self, p: &[f64], i: usize) -> bool {
        p[i] > -self.c[i] * self.l[i]
    }
}

/// Upwind weights of d(ρ̄H)/dX at node i: (node, weight·Δ).
fn wedge(i: usize) -> Vec<(usize, f64)> {
    if i >= 2 {
        vec![(i, 1.5), (i - 1, -2.0), (i - 2, 0.5)]
    } else {
        vec![(i, 1.0), (i - 1, -1.0)]
    }
}

fn evaluate(case: &Case, k: &[f64], x: &[f64], p: &[f64], h0: f64, lam: f64, dx: f64) -> State {
    let n = x.len();
    let el = if case.elastic {
        deformation(k, p)
    } else {
        vec![0.0; n]
    };
    let h: Vec<f64> = (0..n).map(|i| h0 + 0.5 * x[i] * x[i] + el[i]).collect();
    let mut rho = vec![0.0; n];
    let mut drho = vec![0.0; n];
    let mut dlneta = vec![0.0; n];
    let mut eps = vec![0.0; n];
    for i in 0..n {
        let (r, dr) = case.density(p[i]);
        let (eta, dle) = case.viscosity(p[i]);
        rho[i] = r;
        drho[i] = dr;
        dlneta[i] = dle;
        eps[i] = r * h[i].powi(3) / (eta * lam);
    }
    let mut l = vec![0.0; n];
    let mut c = vec![0.0; n];
    for i in 1..n - 1 {
        let ep = 0.5 * (eps[i] + eps[i + 1]);
        let em = 0.5 * (eps[i - 1] + eps[i]);
        c[i] = dx * dx / (ep + em);
        let pois = (ep * (p[i + 1] - p[i]) - em * (p[i] - p[i - 1])) / (dx * dx);
        let w: f64 = wedge(i)
            .iter()
            .map(|&(j, c)| c * rho[j] * h[j])
            .sum::<f64>()
            / dx;
        l[i] = pois - w;
    }
    State {
        h,
        eps,
        rho,
        drho,
        dlneta,
        l,
        c,
    }
}

/// Residual vector F (interior complementarity rows, then load) and its
/// scaled max-norm pieces (Reynolds, load).
fn residual(st: &State, p: &[f64], dx: f64, qc: f64) -> (Vec<f64>, f64, f64) {
    let n = p.len();
    let mut f = Vec::with_capacity(n - 1);
    let mut rmax: f64 = 0.0;
    for i in 1..n - 1 {
        // the row Newton solves: −L_i (pressurised) or P_i (cavitated)
        let v = if st.pressurised(p, i) { -st.l[i] } else { p[i] };
        f.push(v);
        // a pressurised row's residual is the flux imbalance |L|Δ of its cell
        let s = if st.pressurised(p, i) {
            st.l[i].abs() * dx / qc
        } else {
            p[i].abs()
        };
        rmax = rmax.max(s);
    }
    let load = dx * p.iter().sum::<f64>() - 0.5 * PI;
    f.push(load);
    (f, rmax, load.abs() / (0.5 * PI))
}

fn merit(f: &[f64], st: &State, p: &[f64], dx: f64) -> f64 {
    // rows scaled as in `residual` (flux imbalance per cell)
    let n = p.len();
    let mut s = 0.0;
    for i in 1..n - 1 {
        let v = if st.pressurised(p, i) {
            st.l[i] * dx
        } else {
            p[i]
        };
        s += v * v;
    }
    s + f[n - 2] * f[n - 2]
}

/// h at X = 0 (linear interpolation) and the minimum of h (parabola
/// through the smallest node and its neighbours).
fn films(x: &[f64], h: &[f64]) -> (f64, f64) {
    let n = x.len();
    let j = x.iter().position(|&v| v >= 0.0).unwrap_or(n - 1).max(1);
    let t = (0.0 - x[j - 1]) / (x[j] - x[j - 1]);
    let hc = h[j - 1] + t * (h[j] - h[j - 1]);
    let (m, _) = h.iter().enumerate().fold(
        (0, f64::INFINITY),
        |a, (i, &v)| if v < a.1 { (i, v) } else { a },
    );
    let hm = if m > 0 && m + 1 < n {
        let (a, b, c) = (h[m - 1], h[m], h[m + 1]);
        let den = a - 2.0 * b + c;
        if den > 0.0 {
            b - (c - a) * (c - a) / (8.0 * den)
        } else {
            b
        }
    } else {
        h[m]
    };
    (hc, hm)
}

/// Jacobian of the Newton system at (P, H₀) (rows: −L_i or P_i by the
/// current active set; the load row is left to the caller): dε_k and
/// d(ρ̄H)_k through η̄(P_k), ρ̄(P_k) and H(P, H₀), the kernel coupling every node.
fn jacobian(case: &Case, k: &[f64], p: &[f64], st: &State, dx: f64) -> Mat<f64> {
    let n = p.len();
    let m = n - 1;
    let mut jac = Mat::<f64>::zeros(m, m);
    // ∂ε/∂H (H depends on H₀, and on P through the kernel when elastic)
    let g3: Vec<f64> = (0..n).map(|i| 3.0 * st.eps[i] / st.h[i]).collect();
    let a: Vec<f64> = (0..n)
        .map(|i| st.eps[i] * (st.drho[i] / st.rho[i] - st.dlneta[i]))
        .collect();
    for i in 1..n - 1 {
        let r = i - 1;
        if !st.pressurised(p, i) {
            jac[(r, r)] = 1.0;
            continue;
        }
        // F_i = −L_i
        let ep = 0.5 * (st.eps[i] + st.eps[i + 1]);
        let em = 0.5 * (st.eps[i - 1] + st.eps[i]);
        let dp = p[i + 1] - p[i];
        let dm = p[i] - p[i - 1];
        let d2 = dx * dx;
        // coefficients of dε_k and dq_k (q = ρ̄H) in L_i
        let ce: [(usize, f64); 3] = [
            (i - 1, -0.5 * dm / d2),
            (i, 0.5 * (dp - dm) / d2),
            (i + 1, 0.5 * dp / d2),
        ];
        let cq: Vec<(usize, f64)> = wedge(i).into_iter().map(|(j, c)| (j, -c / dx)).collect();
        let mut dense: Vec<(usize, f64)> = Vec::new();
        let mut h0col = 0.0;
        for &(kk, c) in &ce {
            // dε_k = a_k dP_k + g_k (K dP + dH₀)
            if (1..n - 1).contains(&kk) {
                jac[(r, kk - 1)] -= c * a[kk];
            }
            dense.push((kk, c * g3[kk]));
            h0col += c * g3[kk];
        }
        for &(kk, c) in &cq {
            // dq_k = ρ̄′_k H_k dP_k + ρ̄_k (K dP + dH₀)
            if (1..n - 1).contains(&kk) {
                jac[(r, kk - 1)] -= c * st.drho[kk] * st.h[kk];
            }
            dense.push((kk, c * st.rho[kk]));
            h0col += c * st.rho[kk];
        }
        if case.elastic {
            for j in 1..n - 1 {
                let s: f64 = dense.iter().map(|&(kk, c)| c * k[kk.abs_diff(j)]).sum();
                jac[(r, j - 1)] -= s;
            }
        }
        jac[(r, m - 1)] -= h0col;
        // Poiseuille stencil
        if i > 1 {
            jac[(r, r - 1)] -= em / d2;
        }
        jac[(r, r)] += (ep + em) / d2;
        if i + 2 < n {
            jac[(r, r + 1)] -= ep / d2;
        }
    }
    jac
}

/// Largest difference between the analytic Jacobian of the pressurised
/// Reynolds rows (active set frozen at (P, H₀)) and central finite
/// differences of L, relative to the row's largest entry.
pub fn jacobian_check(case: &Case, grid: &Grid, p: &[f64], h0: f64) -> f64 {
    let n = grid.n;
    let dx = (grid.x_out - grid.x_in) / (n - 1) as f64;
    let x: Vec<f64> = (0..n).map(|i| grid.x_in + i as f64 * dx).collect();
    let k = kernel(n, dx);
    let lam = case.lambda();
    let st = evaluate(case, &k, &x, p, h0, lam, dx);
    let jac = jacobian(case, &k, p, &st, dx);
    let m = n - 1;
    let mut fd = Mat::<f64>::zeros(m, m);
    for j in 0..m {
        let mut pp = p.to_vec();
        let mut pm = p.to_vec();
        let (mut hp, mut hm) = (h0, h0);
        let del = if j + 1 < m {
            let d = 1e-5 * p[j + 1].abs().max(1e-3);
            pp[j + 1] += d;
            pm[j + 1] -= d;
            d
        } else {
            let d = 1e-5 * h0.abs().max(1e-3);
            hp += d;
            hm -= d;
            d
        };
        let sp = evaluate(case, &k, &x, &pp, hp, lam, dx);
        let sm = evaluate(case, &k, &x, &pm, hm, lam, dx);
        for i in 1..n - 1 {
            fd[(i - 1, j)] = -(sp.l[i] - sm.l[i]) / (2.0 * del);
        }
    }
    let mut worst: f64 = 0.0;
    for i in 1..n - 1 {
        if !st.pressurised(p, i) {
            continue;
        }
        let r = i - 1;
        let big = (0..m).map(|j| fd[(r, j)].abs()).fold(0.0, f64::max);
        for j in 0..m {
            worst = worst.max((jac[(r, j)] - fd[(r, j)]).abs() / big);
        }
    }
    worst
}

/// Solve one operating point on one grid.
pub fn solve(case: &Case, grid: &Grid, set: &Settings) -> Solution {
    let n = grid.n;
    let dx = (grid.x_out - grid.x_in) / (n - 1) as f64;
    let x: Vec<f64> = (0..n).map(|i| grid.x_in + i as f64 * dx).collect();
    let k = kernel(n, dx);
    let lam = case.lambda();
    let b = case.b();
    let ph = case.p_hertz();
    let scale = case.radius / (b * b);

    // initial guess: Hertz pressure, film from an inlet estimate
    let (u, g, w) = case.groups();
    let grubin = 1.95 * (g * u).powf(8.0 / 11.0) * w.powf(-1.0 / 11.0);
    let martin = 4.9 * u / w;
    let guess = set.film_guess.unwrap_or_else(|| {
        if case.elastic && case.alpha > 0.0 {
            grubin.max(martin) * case.radius * scale
        } else {
            martin * case.radius * scale
        }
    });
    let mut p: Vec<f64> = x
        .iter()
        .map(|&v| {
            if case.elastic {
                (1.0 - v * v).max(0.0).sqrt()
            } else {
                // rigid: a parabola over the whole domain carrying the load,
                // so that the first steps move the exit boundary upstream
                let len = grid.x_out - grid.x_in;
                6.0 * (0.5 * PI) * (v - grid.x_in) * (grid.x_out - v) / len.powi(3)
            }
        })
        .collect();
    // the flat Hertz film is H₀ + 1/4 + ln2/2 (kernel on the Hertz pressure)
    let mut h0 = if case.elastic {
        guess - 0.25 - 0.5 * 2f64.ln()
    } else {
        guess
    };

    if let Some((p_start, h0_start)) = &set.start {
        assert_eq!(p_start.len(), n, "continuation start on another grid");
        p.clone_from(p_start);
        h0 = *h0_start;
    }
    let m = n - 1; // unknowns: P_1..P_{n-2}, H₀
    let mut st = evaluate(case, &k, &x, &p, h0, lam, dx);
    let mut it = 0;
    let mut bound_hits = 0;
    let mut converged = false;
    let mut last_dh0 = f64::INFINITY;
    loop {
        let qc = films(&x, &st.h).0.abs().max(1e-300);
        let (f, rres, lres) = residual(&st, &p, dx, qc);
        if rres < set.tol && lres < set.tol && last_dh0 < set.tol {
            converged = true;
            break;
        }
        if std::env::var("EHL_DEBUG").is_ok() {
            let ncav = (1..n - 1).filter(|&i| !st.pressurised(&p, i)).count();
            eprintln!(
                "it {it} res {rres:.3e} load {lres:.3e} dh0 {last_dh0:.3e} h0 {h0:.6e} cav {ncav}"
            );
        }
        if it >= set.max_newton {
            break;
        }
        it += 1;
        let mut jac = jacobian(case, &k, &p, &st, dx);
        // rigid cylinders: H₀ held at its guess until the Reynolds rows are
        // solved (for fixed H₀ they are linear in P), then the load row
        let frozen = !case.elastic && rres > 1e-6 && it <= set.max_newton / 2;
        if frozen {
            jac[(m - 1, m - 1)] = 1.0;
        } else {
            for j in 0..m - 1 {
                jac[(m - 1, j)] = dx;
            }
        }
        let rhs = Mat::<f64>::from_fn(m, 1, |i, _| if frozen && i == m - 1 { 0.0 } else { -f[i] });
        let step = jac.partial_piv_lu().solve(&rhs);
        // backtracking on the scaled residual, P ≥ 0, H > 0
        let m0 = merit(&f, &st, &p, dx);
        let mut omega = 1.0;
        let mut accepted = None;
        for _ in 0..12 {
            let mut pt = p.clone();
            for i in 1..n - 1 {
                // no projection: a node may go negative for one step and is
                // then held at zero by its complementarity row
                pt[i] = p[i] + omega * step[(i - 1, 0)];
            }
            let h0t = h0 + omega * step[(m - 1, 0)];
            let stt = evaluate(case, &k, &x, &pt, h0t, lam, dx);
            if stt.h.iter().all(|&v| v > 0.0) && stt.eps.iter().all(|v| v.is_finite()) {
                let qt = films(&x, &stt.h).0.abs().max(1e-300);
                let (ft, _, _) = residual(&stt, &pt, dx, qt);
                let mt = merit(&ft, &stt, &pt, dx);
                let last = accepted.is_none() && omega < 1.0 / 1024.0;
                let mt = if frozen { mt - ft[m - 1].powi(2) } else { mt };
                let m0 = if frozen { m0 - f[m - 1].powi(2) } else { m0 };
                if mt < (1.0 - 1e-4 * omega) * m0 || last {
                    if last {
                        bound_hits += 1;
                    }
                    accepted = Some((pt, h0t, stt));
                    break;
                }
            }
            omega *= 0.5;
        }
        let Some((pt, h0t, stt)) = accepted else {
            bound_hits += 1;
            break; // no admissible step (H ≤ 0 along the whole search)
        };
        last_dh0 = ((h0t - h0) / h0t.abs().max(1e-300)).abs();
        p = pt;
        h0 = h0t;
        st = stt;
    }
    let qc = films(&x, &st.h).0.abs().max(1e-300);
    let (_, rres, lres) = residual(&st, &p, dx, qc);
    let (hc, hm) = films(&x, &st.h);
    let p_max = p.iter().cloned().fold(0.0, f64::max) * ph;
    Solution {
        x,
        p,
        h: st.h,
        h0,
        h_central: hc / scale,
        h_min: hm / scale,
        p_max,
        newton_iterations: it,
        line_search_bound_hits: bound_hits,
        converged,
        reynolds_residual: rres,
        load_error: lres,
        b,
        p_hertz: ph,
    }
}
