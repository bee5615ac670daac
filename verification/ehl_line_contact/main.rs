//! A numerical EHL reference for flank's film formulas (issue 20 point 5):
//! an isothermal, steady, smooth line-contact solver (`solver.rs`: Reynolds
//! with Reynolds-exit cavitation, Roelands viscosity, Dowson–Higginson
//! density, half-space deformation, load balance; semi-smooth Newton),
//! checked on its two limits and then set against the line-contact film
//! formulas over a 3 × 3 grid of gear-like loads and speeds.
//!
//! * Jacobian: the hand-derived Newton Jacobian against central
//!   differences, 1e-5 of each row's largest entry.
//! * Kernel: the deformation of the Hertz pressure plus X²/2 is the
//!   constant 1/4 + ln2/2 on |X| < 1 (Johnson, *Contact Mechanics*, ch. 4).
//! * Rigid, isoviscous: Martin (1916) with Reynolds' exit condition, in the
//!   closed form derived in README.md (w′ = 24ηuR/h₀ · J, J → 0.2040 for an
//!   infinite inlet, i.e. w′ = 4.896ηuR/h₀), 1 %.
//! * Dry limit (isoviscous, incompressible, slow): p_max → p_H and the
//!   half-width from the pressure's second moment → b, 2 %.
//! * Gear grid (p_H 0.5–1.5 GPa × u 1–20 m/s, seed 002's oil): h_c and
//!   h_min vs Pan & Hamrock (1989), flank's line fit
//!   (`FilmModel::DowsonHigginson`: Dowson–Higginson h_min, Dowson–Toyoda
//!   h_c) and flank's Chittenden fit at R_y = ∞ (what seed 002's run uses),
//!   band ±20 % fixed before the table was computed. Misses kept: the
//!   Dowson–Toyoda h_c at p_H ≥ 1 GPa (ignored test).
//! * Grid and inlet: the table's 1201 nodes within 2 % of 2401 (highest
//!   M) and of a doubled inlet (lowest M).

mod solver;

use flank::lubrication::{film_thickness, FilmFlag, FilmInput, FilmModel};
use solver::{
    deformation, jacobian_check, kernel, solve, Case, Grid, Settings, Solution, Viscosity,
};
use std::f64::consts::PI;
use std::time::Instant;

/// E′ of two steels E = 206 GPa, ν = 0.3 (Pa).
const E_PRIME: f64 = 206e9 / 0.91;
/// Seed 002's oil (MIL-PRF-23699 at 100 °C, `papers/seed002-spur/README.md`).
const ETA0: f64 = 0.00468;
const ALPHA: f64 = 10e-9;
/// Equivalent radius of the gear-like grid (m).
const RADIUS: f64 = 0.01;
/// Nodes of the comparison runs (Δ = 0.005b on the default [−4.5b, 1.5b]).
const NODES: usize = 1201;
/// Agreement band with the film formulas, fixed from the literature's
/// 10–20 % before the table was computed (README.md).
const BAND: f64 = 0.20;

/// Residual limits every converged run must meet.
const MAX_REYNOLDS_RESIDUAL: f64 = 1e-8;
const MAX_LOAD_ERROR: f64 = 1e-12;

/// Load per unit length giving the Hertz pressure p_H: p_H = E′(W′/2π)^½.
fn load_for(p_hertz: f64, radius: f64) -> f64 {
    2.0 * PI * (p_hertz / E_PRIME).powi(2) * E_PRIME * radius
}

fn gear_case(p_hertz: f64, speed: f64) -> Case {
    Case {
        eta0: ETA0,
        alpha: ALPHA,
        e_prime: E_PRIME,
        radius: RADIUS,
        load: load_for(p_hertz, RADIUS),
        speed,
        viscosity: Viscosity::Roelands,
        compressible: true,
        elastic: true,
    }
}

/// Inlet of the comparison runs: −4.5b (Venner & Lubrecht's choice for
/// moderate and high loads) or, when the contact is light, ten inlet
/// lengths √(2H_c) upstream (rigid gap 101 h_c, Grubin's estimate of h_c),
/// so that the inlet is flooded; outlet 1.5b.
fn gear_grid(c: &Case, nodes: usize, inlet_factor: f64) -> Grid {
    let (u, g, w) = c.groups();
    let hc = 1.95 * (g * u).powf(8.0 / 11.0) * w.powf(-1.0 / 11.0) * c.radius;
    let big_h = hc * c.radius / (c.b() * c.b());
    Grid {
        x_in: -4.5f64.max(10.0 * (2.0 * big_h).sqrt()) * inlet_factor,
        x_out: 1.5,
        n: nodes,
    }
}

/// Pan & Hamrock (1989) line contact: H_c = 2.922 W′^−0.166 U^0.692 G^0.470,
/// H_min = 1.714 W′^−0.128 U^0.694 G^0.568 (m).
fn pan_hamrock(c: &Case) -> (f64, f64) {
    let (u, g, w) = c.groups();
    (
        2.922 * w.powf(-0.166) * u.powf(0.692) * g.powf(0.470) * c.radius,
        1.714 * w.powf(-0.128) * u.powf(0.694) * g.powf(0.568) * c.radius,
    )
}

/// flank's film formula `model` through `film_thickness` in flank's units
/// (mm, N, s, MPa), R_y = ∞, contact length `length_mm` (the line fit sees
/// w′ = w/L only; a point-contact fit at R_y = ∞ sees the total load w′L).
fn flank_fit(c: &Case, model: FilmModel, length_mm: f64) -> (f64, f64) {
    let f = film_thickness(
        model,
        &FilmInput {
            viscosity: c.eta0 * 1e-6,
            pressure_viscosity: c.alpha * 1e6,
            reduced_modulus: c.e_prime * 1e-6,
            radius_x: c.radius * 1e3,
            radius_y: f64::INFINITY,
            load: c.load * length_mm * 1e-3,
            length: length_mm,
            entraining_speed: c.speed * 1e3,
        },
    )
    .expect("film formula");
    if matches!(model, FilmModel::DowsonHigginson | FilmModel::PanHamrock) {
        assert!(f.flags.is_empty(), "{:?}", f.flags);
    } else {
        assert_eq!(f.flags, vec![FilmFlag::OutsideEllipticityRange]);
    }
    (f.central * 1e-3, f.minimum * 1e-3)
}

/// Seed 002's face width (mm): the line length its lubricated run gives
/// the Chittenden fit (`papers/seed002-spur/`).
const SEED_FACE_WIDTH_MM: f64 = 13.3;

fn check_converged(what: &str, s: &Solution) {
    println!(
        "{what}: Newton {} (line-search bound hits {}), Reynolds residual {:.1e}, load error {:.1e}",
        s.newton_iterations, s.line_search_bound_hits, s.reynolds_residual, s.load_error
    );
    assert!(s.converged, "{what}: not converged");
    assert!(s.reynolds_residual < MAX_REYNOLDS_RESIDUAL, "{what}");
    assert!(s.load_error < MAX_LOAD_ERROR, "{what}");
    // P ≥ 0 up to the Newton tolerance (a pressurised node satisfies
    // P_i > −c_i L_i with L_i at round-off)
    let pmax = s.p.iter().cloned().fold(0.0, f64::max);
    let pmin = s.p.iter().cloned().fold(f64::INFINITY, f64::min);
    assert!(pmin >= -1e-9 * pmax, "{what}: negative pressure {pmin}");
    assert!(s.h.iter().all(|&h| h > 0.0), "{what}: film ≤ 0");
}

#[test]
fn kernel_gives_the_flat_hertz_film() {
    // (1/π)∫ ln|X − s| (1 − s²)^½ ds = X²/2 − 1/4 − ln2/2 on |X| ≤ 1
    let mut errs = Vec::new();
    for dx in [0.02f64, 0.01, 0.005] {
        let n = (4.0 / dx).round() as usize + 1;
        let x: Vec<f64> = (0..n).map(|i| -2.0 + i as f64 * dx).collect();
        let p: Vec<f64> = x.iter().map(|&v| (1.0 - v * v).max(0.0).sqrt()).collect();
        let el = deformation(&kernel(n, dx), &p);
        let want = 0.25 + 0.5 * 2f64.ln();
        let err = x
            .iter()
            .zip(&el)
            .filter(|(v, _)| v.abs() < 1.0)
            .map(|(v, e)| (0.5 * v * v + e - want).abs())
            .fold(0.0, f64::max);
        println!("Δ = {dx}: max |X²/2 + deformation − (1/4 + ln2/2)| on |X| < 1 = {err:.2e}");
        errs.push(err);
    }
    // converging, and within 0.1 % of the constant on the finest cells
    assert!(errs[1] < errs[0] && errs[2] < errs[1], "{errs:?}");
    assert!(errs[2] < 1e-3 * (0.25 + 0.5 * 2f64.ln()), "{errs:?}");
}

#[test]
fn jacobian_matches_finite_differences() {
    // the hand-derived Newton Jacobian against central differences of the
    // Reynolds operator, at the Hertz start and at the converged solution
    // (1 GPa, 5 m/s; 201 nodes), and for rigid cylinders
    let c = gear_case(1.0e9, 5.0);
    let grid = Grid {
        x_in: -4.5,
        x_out: 1.5,
        n: 201,
    };
    let hertz: Vec<f64> = (0..grid.n)
        .map(|i| {
            let x = grid.x_in + i as f64 * 0.03;
            (1.0 - x * x).max(0.0).sqrt()
        })
        .collect();
    let e0 = jacobian_check(&c, &grid, &hertz, 0.1);
    let s = solve(&c, &grid, &Settings::default());
    check_converged("Jacobian check point", &s);
    let e1 = jacobian_check(&c, &grid, &s.p, s.h0);
    let mut rigid = c;
    rigid.elastic = false;
    let e2 = jacobian_check(&rigid, &grid, &s.p, s.h0 + 1.0);
    println!(
        "Jacobian vs finite differences: Hertz start {e0:.1e}, converged {e1:.1e}, rigid {e2:.1e}"
    );
    // row-wise: |J − FD| / max|FD row| (small entries are FD noise)
    for e in [e0, e1, e2] {
        assert!(e < 1e-5, "{e}");
    }
}

/// Rigid, isoviscous, incompressible cylinder on a plane with Reynolds'
/// exit condition and the inlet at ξ_in = x_in/√(2Rh₀): the load
/// w′ = (24ηuR/h₀)·J(ξ_in) in closed form (README.md), J(−∞) = 0.2040.
fn martin_load_factor(xi_in: f64) -> f64 {
    let a = |t: f64| t / 8.0 - (4.0 * t).sin() / 32.0;
    let bb = |t: f64| 3.0 * t / 8.0 + (2.0 * t).sin() / 4.0 + (4.0 * t).sin() / 32.0;
    let t_in = xi_in.atan();
    // exit θ_c: ∫_{θ_in}^{θ_c} (sin²θ cos²θ − tan²θ_c cos⁴θ) dθ = 0
    let g = |tc: f64| a(tc) - a(t_in) - tc.tan().powi(2) * (bb(tc) - bb(t_in));
    let (mut lo, mut hi) = (1e-9, 0.5 * PI - 1e-9);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if g(mid) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let tc = 0.5 * (lo + hi);
    let c2 = tc.tan().powi(2);
    let big_g = |t: f64| t.sin().powi(4) / 4.0 + c2 * t.cos().powi(4) / 4.0;
    big_g(t_in) - big_g(tc)
}

/// h₀ of the rigid problem for load w′ and an inlet at x_in (m).
fn martin_h0(c: &Case, x_in: f64) -> f64 {
    let load = |h0: f64| {
        24.0 * c.eta0 * c.speed * c.radius / h0
            * martin_load_factor(x_in / (2.0 * c.radius * h0).sqrt())
    };
    let (mut lo, mut hi) = (1e-12f64, 1e-3f64);
    for _ in 0..200 {
        let mid = (lo * hi).sqrt();
        if load(mid) > c.load {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    (lo * hi).sqrt()
}

#[test]
fn rigid_isoviscous_limit_is_martin() {
    let j = martin_load_factor(-1e9);
    println!(
        "Martin, infinite inlet: w′ = 24 J ηuR/h₀, 24 J = {:.4}",
        24.0 * j
    );
    // 4.896 = 2 × 2.448 as usually printed (rounded)
    assert!((24.0 * j / 4.896 - 1.0).abs() < 1e-3);
    let case = Case {
        eta0: ETA0,
        alpha: 0.0,
        e_prime: E_PRIME,
        radius: RADIUS,
        load: load_for(0.5e9, RADIUS),
        speed: 5.0,
        viscosity: Viscosity::Barus,
        compressible: false,
        elastic: false,
    };
    let h_inf = 4.896 * case.eta0 * case.speed * case.radius / case.load;
    let len = (2.0 * case.radius * h_inf).sqrt() / case.b();
    let mut errs = Vec::new();
    for n in [401, 801] {
        let grid = Grid {
            x_in: -30.0 * len,
            x_out: 3.0 * len,
            n,
        };
        let s = solve(&case, &grid, &Settings::default());
        check_converged(&format!("rigid n = {n}"), &s);
        let exact = martin_h0(&case, grid.x_in * case.b());
        let e = s.h_min / exact - 1.0;
        let e_inf = s.h_min / h_inf - 1.0;
        println!(
            "rigid n = {n}: h_min {:.5e} m, exact (inlet −30 lengths) {exact:.5e} ({e:+.2e}), Martin 4.896ηuR/w′ {h_inf:.5e} ({e_inf:+.2e})",
            s.h_min
        );
        errs.push((e, e_inf));
    }
    let (e, e_inf) = errs[1];
    assert!(e.abs() < 0.01 && e_inf.abs() < 0.01, "{e} {e_inf}");
}

#[test]
fn low_load_elastic_isoviscous_approaches_martin() {
    // the full solver (elastic, Roelands law with α = 0, i.e. isoviscous,
    // incompressible) at Moes M = 0.05: elastic flattening ≪ film
    let mut case = gear_case(1.0e9, 5.0);
    case.alpha = 0.0;
    case.compressible = false;
    let (u, _, _) = case.groups();
    case.load = 0.05 * (2.0 * u).sqrt() * E_PRIME * RADIUS;
    let h_inf = 4.896 * case.eta0 * case.speed * case.radius / case.load;
    let len = (2.0 * case.radius * h_inf).sqrt() / case.b();
    let grid = Grid {
        x_in: -30.0 * len,
        x_out: 3.0 * len,
        n: 801,
    };
    let s = solve(&case, &grid, &Settings::default());
    check_converged("low load, elastic", &s);
    let exact = martin_h0(&case, grid.x_in * case.b());
    let e = s.h_min / exact - 1.0;
    println!(
        "M = {:.3}, p_H = {:.1} MPa: h_min {:.5e} m, rigid exact {exact:.5e} ({e:+.2e}), Martin {h_inf:.5e} ({:+.2e})",
        case.moes().0,
        case.p_hertz() * 1e-6,
        s.h_min,
        s.h_min / h_inf - 1.0
    );
    assert!(e.abs() < 0.02, "{e}");
}

#[test]
fn dry_limit_is_hertz() {
    // isoviscous, incompressible, slow: M = 100, 300, 1000 at p_H = 1 GPa
    let mut last = (0.0, 0.0);
    let mut start = None;
    for m in [100.0, 300.0, 1000.0] {
        let mut case = gear_case(1.0e9, 1.0);
        case.alpha = 0.0;
        case.compressible = false;
        let (_, _, w) = case.groups();
        // M = W′(2U)^−½ → U = (W′/M)²/2
        case.speed = 0.5 * (w / m).powi(2) * E_PRIME * RADIUS / case.eta0;
        let grid = Grid {
            x_in: -2.0,
            x_out: 1.5,
            n: 701,
        };
        // continuation: each M starts from the previous solution
        let set = Settings {
            start: start.take(),
            ..Default::default()
        };
        let s = solve(&case, &grid, &set);
        check_converged(&format!("dry limit M = {m}"), &s);
        start = Some((s.p.clone(), s.h0));
        // half-width from the second moment: ∫X²P/∫P = b²/4 for Hertz
        let dx = (grid.x_out - grid.x_in) / (grid.n - 1) as f64;
        let m0: f64 = s.p.iter().sum::<f64>() * dx;
        let m2: f64 = s.x.iter().zip(&s.p).map(|(x, p)| x * x * p).sum::<f64>() * dx;
        let xm: f64 = s.x.iter().zip(&s.p).map(|(x, p)| x * p).sum::<f64>() * dx / m0;
        let half = (4.0 * (m2 / m0 - xm * xm)).sqrt();
        let ep = s.p_max / s.p_hertz - 1.0;
        let eb = half - 1.0;
        println!(
            "M = {m}: u = {:.2e} m/s, p_max/p_H − 1 = {ep:+.2e}, half-width/b − 1 = {eb:+.2e} (b = {:.1} µm, centroid {xm:+.3e} b), h_c = {:.3e} m",
            case.speed,
            s.b * 1e6, s.h_central
        );
        last = (ep, eb);
    }
    assert!(last.0.abs() < 0.02 && last.1.abs() < 0.02, "{last:?}");
}

/// One operating point of the gear grid: numerical films and the formulas' (m).
struct Row {
    what: String,
    hc: f64,
    hm: f64,
    pan: (f64, f64),
    flank: (f64, f64),
    /// flank's Chittenden fit at R_y = ∞ with seed 002's face width (flagged).
    chittenden: (f64, f64),
}

fn d(num: f64, formula: f64) -> f64 {
    num / formula - 1.0
}

/// The 3 × 3 grid p_H ∈ {0.5, 1, 1.5} GPa × u ∈ {1, 5, 20} m/s with the
/// given viscosity law; prints the README's table, asserts convergence.
fn gear_table(viscosity: Viscosity) -> Vec<Row> {
    println!("{viscosity:?}:");
    println!(
        "| p_H (GPa) | u (m/s) | M | L | nodes | h_c (µm) | h_min (µm) | h_c PH | Δ | h_min PH | Δ | h_c D–T | Δ | h_min D–H | Δ | h_c Ch. | Δ | h_min Ch. | Δ | p_max/p_H | Newton | residual | s |"
    );
    println!("|{}", "---|".repeat(23));
    let t0 = Instant::now();
    let mut rows = Vec::new();
    for ph in [0.5e9, 1.0e9, 1.5e9] {
        for u in [1.0, 5.0, 20.0] {
            let mut c = gear_case(ph, u);
            c.viscosity = viscosity;
            let grid = gear_grid(&c, NODES, 1.0);
            let t = Instant::now();
            // Barus: continued from the Roelands solution (from the Hertz
            // start Newton stalls at 1.5 GPa, 1 m/s)
            let start = (viscosity == Viscosity::Barus).then(|| {
                let r = solve(&gear_case(ph, u), &grid, &Settings::default());
                (r.p, r.h0)
            });
            let s = solve(
                &c,
                &grid,
                &Settings {
                    start,
                    ..Default::default()
                },
            );
            let what = format!("p_H {} GPa, u {u} m/s", ph * 1e-9);
            assert!(s.converged, "{what}: not converged");
            assert!(s.reynolds_residual < MAX_REYNOLDS_RESIDUAL, "{what}");
            assert!(s.load_error < MAX_LOAD_ERROR, "{what}");
            let (pc, pm) = pan_hamrock(&c);
            // flank's `FilmModel::PanHamrock` is this formula (unit conversions
            // and the load per length included)
            let (qc, qm) = flank_fit(&c, FilmModel::PanHamrock, 10.0);
            assert!(
                d(qc, pc).abs() < 1e-12 && d(qm, pm).abs() < 1e-12,
                "{what}: flank Pan–Hamrock {qc:e}, {qm:e} vs {pc:e}, {pm:e}"
            );
            let (fc, fm) = flank_fit(&c, FilmModel::DowsonHigginson, 10.0);
            let (cc, cm) = flank_fit(&c, FilmModel::Chittenden, SEED_FACE_WIDTH_MM);
            let (m, l) = c.moes();
            println!(
                "| {:.1} | {u} | {m:.1} | {l:.2} | {} | {:.4} | {:.4} | {:.4} | {:+.1} % | {:.4} | {:+.1} % | {:.4} | {:+.1} % | {:.4} | {:+.1} % | {:.4} | {:+.1} % | {:.4} | {:+.1} % | {:.3} | {} | {:.0e} | {:.2} |",
                ph * 1e-9,
                grid.n,
                s.h_central * 1e6,
                s.h_min * 1e6,
                pc * 1e6,
                100.0 * d(s.h_central, pc),
                pm * 1e6,
                100.0 * d(s.h_min, pm),
                fc * 1e6,
                100.0 * d(s.h_central, fc),
                fm * 1e6,
                100.0 * d(s.h_min, fm),
                cc * 1e6,
                100.0 * d(s.h_central, cc),
                cm * 1e6,
                100.0 * d(s.h_min, cm),
                s.p_max / s.p_hertz,
                s.newton_iterations,
                s.reynolds_residual,
                t.elapsed().as_secs_f64()
            );
            rows.push(Row {
                what,
                hc: s.h_central,
                hm: s.h_min,
                pan: (pc, pm),
                flank: (fc, fm),
                chittenden: (cc, cm),
            });
        }
    }
    println!("{viscosity:?} grid: {:.1} s", t0.elapsed().as_secs_f64());
    rows
}

/// The rows' films outside ±BAND against the formulas `pick` selects.
fn misses(rows: &[Row], pick: &[&str]) -> Vec<String> {
    let mut out = Vec::new();
    for r in rows {
        for (name, num, f) in [
            ("h_c vs Pan–Hamrock", r.hc, r.pan.0),
            ("h_min vs Pan–Hamrock", r.hm, r.pan.1),
            ("h_c vs flank Dowson–Toyoda", r.hc, r.flank.0),
            ("h_min vs flank Dowson–Higginson", r.hm, r.flank.1),
            ("h_c vs flank Chittenden (R_y = ∞)", r.hc, r.chittenden.0),
            ("h_min vs flank Chittenden (R_y = ∞)", r.hm, r.chittenden.1),
        ] {
            if pick.iter().any(|p| name.contains(p)) && d(num, f).abs() > BAND {
                out.push(format!("{}: {name} {:+.1} %", r.what, 100.0 * d(num, f)));
            }
        }
    }
    out
}

#[test]
fn film_formulas_over_gear_conditions() {
    let rows = gear_table(Viscosity::Roelands);
    let m = misses(&rows, &["Pan–Hamrock", "Dowson–Higginson", "Chittenden"]);
    println!(
        "Pan–Hamrock, flank Dowson–Higginson h_min, flank Chittenden (R_y = ∞) outside ±{:.0} %: {m:#?}",
        BAND * 100.0
    );
    println!(
        "flank's central fit (kept as the ignored test): {:#?}",
        misses(&rows, &["Dowson–Toyoda"])
    );
    assert!(m.is_empty(), "{m:#?}");
}

#[test]
#[ignore = "miss kept: the numerical h_c is 20–26 % below flank's central line fit (Dowson–Toyoda 1979) at p_H ≥ 1 GPa (README)"]
fn flank_central_line_fit_within_band() {
    let rows = gear_table(Viscosity::Roelands);
    let m = misses(&rows, &["Dowson–Toyoda"]);
    assert!(m.is_empty(), "{m:#?}");
}

#[test]
#[ignore = "informative, 20–30 s: the gear grid with Barus' law (README)"]
fn barus_instead_of_roelands() {
    // informative: the same grid with Barus' law (the fits of the 1960s–70s
    // were made with exponential viscosity); convergence asserted only
    let rows = gear_table(Viscosity::Barus);
    println!(
        "Barus, outside ±{:.0} %: {:#?}",
        BAND * 100.0,
        misses(&rows, &["Pan", "Dowson", "Chittenden"])
    );
}

/// Films on `nodes` nodes and an inlet `factor` × the rule's.
fn refine(c: &Case, nodes: &[usize], factor: f64) -> Vec<(f64, f64)> {
    nodes
        .iter()
        .map(|&n| {
            let grid = gear_grid(c, n, factor);
            let t = Instant::now();
            let s = solve(c, &grid, &Settings::default());
            let dx = (grid.x_out - grid.x_in) / (n - 1) as f64;
            check_converged(
                &format!("{n} nodes (Δ = {dx:.4}), inlet {:.2} b", grid.x_in),
                &s,
            );
            println!(
                "   h_c {:.5} µm, h_min {:.5} µm, p_max/p_H {:.4} ({:.2} s)",
                s.h_central * 1e6,
                s.h_min * 1e6,
                s.p_max / s.p_hertz,
                t.elapsed().as_secs_f64()
            );
            (s.h_central, s.h_min)
        })
        .collect()
}

#[test]
fn grid_and_inlet_convergence() {
    // highest M of the grid (1.5 GPa, 1 m/s, M = 136): 601, 1201 (the
    // table's), 2401 nodes on [−4.5b, 1.5b]
    let hi = refine(&gear_case(1.5e9, 1.0), &[601, 1201, 2401], 1.0);
    for k in 1..3 {
        println!(
            "M = 136, Δ halved: h_c {:+.2} %, h_min {:+.2} %",
            100.0 * d(hi[k].0, hi[k - 1].0),
            100.0 * d(hi[k].1, hi[k - 1].1)
        );
    }
    // lowest M (0.5 GPa, 20 m/s, M = 3.4, inlet −10b): 601 and 1201 nodes,
    // and the inlet doubled on 1201 nodes (same Δ as 601 on the rule's inlet)
    let c = gear_case(0.5e9, 20.0);
    let lo = refine(&c, &[601, 1201], 1.0);
    let inlet = refine(&c, &[1201], 2.0);
    let dl = (d(lo[1].0, lo[0].0), d(lo[1].1, lo[0].1));
    let di = (d(inlet[0].0, lo[0].0), d(inlet[0].1, lo[0].1));
    println!(
        "M = 3.4: Δ halved: h_c {:+.2} %, h_min {:+.2} %; inlet doubled: h_c {:+.2} %, h_min {:+.2} %",
        100.0 * dl.0,
        100.0 * dl.1,
        100.0 * di.0,
        100.0 * di.1
    );
    // the table's grid is within 2 % of the next finer one (small against the band)
    for e in [
        d(hi[2].0, hi[1].0),
        d(hi[2].1, hi[1].1),
        dl.0,
        dl.1,
        di.0,
        di.1,
    ] {
        assert!(e.abs() < 0.02, "{e}");
    }
}
