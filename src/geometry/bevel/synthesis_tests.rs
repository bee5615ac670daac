//! Tests of [`super`] on seed 003.
use super::*;
use crate::geometry::bevel::cutting::{
    assembly_for, cut_gear, member_body, CutterSpec, MachineCut,
};
use crate::geometry::bevel::{blank_design, BlankInputs};
use crate::geometry::tangency::ContactSystem;

/// Seed 003's blank (papers/seed003-hypoid/scene.toml).
const SEED003: &str = r#"{"method": 1, "Sigma_deg": 90.0, "a_mm": 30.0, "z1": 11, "z2": 41, "de2_mm": 225.5, "b2_mm": 38.0, "beta_m1_desired_deg": 50.0, "rc0_mm": 114.3, "data_type": "II", "alpha_dD_deg": 20.0, "alpha_dC_deg": 20.0, "f_alim": 0.0, "c_ham": 0.2309, "k_d": 2.0, "k_c": 0.125, "k_t": 0.1, "theta_a2_deg": 1.3118, "theta_f2_deg": 4.0355}"#;

fn seed003(design: &BlankDesign, targets: SynthesisTargets) -> SynthesisProblem<'_> {
    let inputs = BlankInputs::from_json(SEED003).unwrap();
    let spec = CutterSpec::of_blank(design);
    let cut = MachineCut {
        generated: true,
        cutter: spec,
        machine: None,
        tilt_from_blank: false,
    };
    let gear_hand = Hand::Right;
    let gear = cut_gear(design, gear_hand, &cut).unwrap();
    let m = design.cutting_blank().wheel;
    let toe_root = m.axial_point(-m.dedendum(m.ri), m.ri).1;
    let body = member_body(design, false, &gear, 0.5 * toe_root, 1).unwrap();
    let assembly = assembly_for(&inputs, design, gear_hand).unwrap();
    SynthesisProblem::new(
        design,
        Hand::Left,
        CutterChoice {
            mean_radius: spec.radius,
            edge_radius: spec.edge_radius,
            blade_height: spec.blade_height,
        },
        Arc::new(body),
        assembly,
        targets,
    )
    .unwrap()
}

fn design() -> BlankDesign {
    blank_design(&BlankInputs::from_json(SEED003).unwrap()).unwrap()
}

/// Targets for the first order only (the second-order ones unused).
const PROBE: SynthesisTargets = SynthesisTargets {
    path_angle_rad: 0.0,
    major_axis_mm: 10.0,
    te_level_rad: 1e-4,
    approach_mm: 0.00635,
    te_cubic_rad: 0.0,
};

/// The basic pinion's state and the first-order solve from it.
fn basic_and_first_order(problem: &SynthesisProblem) -> (State, State, usize) {
    let x0 = PinionSynthesisVariables::basic(problem.cutter.mean_radius);
    let (setup, m0) = problem.measure(&x0).unwrap();
    let basic = State {
        x: x0,
        setup,
        mean: m0,
    };
    let (first, it) = newton(problem, &basic, &PROBE, (&ANGLE_FIRST_ORDER, &FIRST_ORDER)).unwrap();
    (basic, first, it)
}

/// The first order on seed 003: the basic pinion (settings from its
/// blank) touches the gear 3.9 mm from the mean point with a TE slope
/// of −4.8e-3 (the gear's drive-flank normal at P is 0.2° off the
/// blank's, the two flanks' spiral angles differ); the Newton on
/// (Δβ, Δα, θ_M) puts the contact on M within 1 nm with a zero slope.
#[test]
fn first_order_puts_the_contact_on_the_mean_point() {
    let d = design();
    let problem = seed003(&d, PROBE);
    let (basic, s, it) = basic_and_first_order(&problem);
    let (m0, rm2) = (basic.mean, d.cutting_blank().wheel.rm);
    assert!(m0.gear_uv[0].hypot(m0.gear_uv[1] - rm2) > 1.0, "{m0:?}");
    assert!(m0.te_slope.abs() > 1e-3, "{m0:?}");
    let m = s.mean;
    assert!(
        m.gear_uv[0].abs() < 1e-6 && (m.gear_uv[1] - rm2).abs() < 1e-6,
        "{m:?}"
    );
    assert!(m.te_slope.abs() < 1e-9, "{m:?}");
    assert!(it <= 10, "{it} iterations");
}

/// The second order: from the first-order pinion, targets 0.5° of path
/// inclination, 5 % of 2a and 40″ of TE level away (and its cubic term
/// kept) are met to the tolerance by the default stages, and the path,
/// 2a and level move by what was asked (the residual definition is not
/// the only check: the figures are measured again on the result).
#[test]
fn second_order_meets_nearby_targets() {
    let d = design();
    let problem = seed003(&d, PROBE);
    let x0 = PinionSynthesisVariables::basic(problem.cutter.mean_radius);
    let (_, first, _) = basic_and_first_order(&problem);
    let f = first.mean;
    let targets = SynthesisTargets {
        path_angle_rad: f.path_angle_rad + 0.5f64.to_radians(),
        major_axis_mm: 1.05 * f.major_axis_mm.unwrap(),
        te_level_rad: f.te_level_rad + (40.0f64 / 3600.0).to_radians(),
        approach_mm: 0.00635,
        // the third stage keeps the first-order pinion's cubic term
        te_cubic_rad: f.te_cubic_rad,
    };
    let problem = SynthesisProblem { targets, ..problem };
    let s = synthesize_pinion(&problem, x0).unwrap();
    assert!(s.residual <= TOLERANCE, "{s:?}");
    // measured again on the resulting variables
    let (_, m) = problem.measure(&s.variables).unwrap();
    assert!(
        (m.path_angle_rad - targets.path_angle_rad).abs() < 1e-5,
        "{m:?}"
    );
    assert!((m.major_axis_mm.unwrap() / targets.major_axis_mm - 1.0).abs() < 1e-5);
    assert!((m.te_level_rad / targets.te_level_rad - 1.0).abs() < 1e-5);
    assert!(m.te_slope.abs() < 1e-8);
    eprintln!(
        "seed003 nearby synthesis: {:?} in {} iterations, {} steps",
        s.variables, s.iterations, s.continuation_steps
    );
}

/// The three figures measured by the point TCA ([`point_tca`]) on the
/// synthesised pair, around the mean roll θ_M: the TE parabola
/// (least-squares quadratic of the middle pair's gear lag over
/// |θ − θ_M| ≤ `window` pitches), its level −½ TE'' (π/z₁)²; the path
/// inclination from the linear fits of the gear-flank projection (v, u)
/// over the same rolls; 2a from the linear fit of the curvature
/// ellipse's major axis, at θ_M.
#[derive(Debug)]
struct TcaFigures {
    path_angle_rad: f64,
    major_axis_mm: f64,
    te_level_rad: f64,
    /// The TCA's own TE of the middle pair: its fall from θ_M to
    /// θ_M ± π/z₁ (mean of the two sides; rad), where the flank
    /// contact reaches that far.
    te_fall_half_pitch_rad: Option<f64>,
    points: usize,
}

fn tca_figures(pair: &BevelPair, theta_m: f64, approach_mm: f64, window: f64) -> TcaFigures {
    use crate::tca::point_contact::{point_tca, PointTcaSettings};
    let settings = PointTcaSettings {
        positions_per_pitch: 80,
        approach_mm,
        edges: false,
        search_directions: 0,
        max_pitches: 1.0,
        ..Default::default()
    };
    let t = point_tca(pair, &settings).unwrap();
    let pitch = t.pitch_rad;
    let middle: Vec<(f64, &crate::tca::point_contact::PairContact)> = t
        .positions
        .iter()
        .flat_map(|p| {
            p.pairs
                .iter()
                .filter(|c| c.offset == 0 && c.system == ContactSystem::Flank)
                .map(move |c| (p.roll_rad - theta_m, c))
        })
        .collect();
    let near: Vec<_> = middle
        .iter()
        .filter(|(x, _)| x.abs() <= window * pitch)
        .collect();
    // least squares of y on (1, x, x²) or (1, x)
    let fit = |deg: usize, y: &dyn Fn(&crate::tca::point_contact::PairContact) -> f64| {
        let n = deg + 1;
        let mut a = nalgebra::DMatrix::<f64>::zeros(near.len(), n);
        let mut b = nalgebra::DVector::<f64>::zeros(near.len());
        for (row, (x, c)) in near.iter().enumerate() {
            for k in 0..n {
                a[(row, k)] = x.powi(k as i32);
            }
            b[row] = y(c);
        }
        a.svd(true, true).solve(&b, 1e-14).unwrap()
    };
    let lag = fit(2, &|c| c.gear_lag_rad);
    let v = fit(1, &|c| c.projection_mm[1][0]);
    let u = fit(1, &|c| c.projection_mm[1][1]);
    let major = fit(1, &|c| 2.0 * c.ellipse.unwrap().semi_major_mm.unwrap());
    let mut path = u[1].atan2(v[1]);
    if path > 0.5 * PI {
        path -= PI;
    } else if path <= -0.5 * PI {
        path += PI;
    }
    let z1 = pair.pinion().teeth() as f64;
    let half = PI / z1;
    // the TCA's middle-pair lag at θ_M + x by linear interpolation
    let lag_at = |x: f64| -> Option<f64> {
        let i = middle.iter().position(|(xi, _)| *xi >= x)?;
        if i == 0 {
            return None;
        }
        let ((x0, c0), (x1, c1)) = (middle[i - 1], middle[i]);
        if x1 - x0 > 1.5 * pitch / 80.0 {
            return None;
        }
        let f = (x - x0) / (x1 - x0);
        Some(c0.gear_lag_rad + f * (c1.gear_lag_rad - c0.gear_lag_rad))
    };
    let fall = match (lag_at(0.0), lag_at(-half), lag_at(half)) {
        (Some(m), Some(a), Some(b)) => Some(m - 0.5 * (a + b)),
        _ => None,
    };
    TcaFigures {
        path_angle_rad: path,
        major_axis_mm: major[0],
        te_level_rad: -lag[2] * half * half,
        te_fall_half_pitch_rad: fall,
        points: near.len(),
    }
}

/// Seed 003's bearing targets (papers/seed003-hypoid/README.md, "Local
/// synthesis"), chosen before any run: a path along the face (no bias,
/// η = 0), 2a = 0.3 b₂ = 11.4 mm (inside the usual quarter to third of
/// the face width) at δ = 0.00635 mm (seed 000's approach for finished
/// teeth), TE level 8″ in gear angle (Litvin & Fuentes §9.2's parabolic
/// function of 8″).
fn seed003_targets() -> SynthesisTargets {
    SynthesisTargets {
        path_angle_rad: 0.0,
        major_axis_mm: 0.3 * 38.0,
        te_level_rad: (8.0f64 / 3600.0).to_radians(),
        approach_mm: 0.00635,
        te_cubic_rad: 0.0,
    }
}

/// Tolerances of the TCA check, stated before measuring: path ±1°, 2a
/// ±5 %, TE level ±10 %.
const PATH_TOL_RAD: f64 = 1.0 * PI / 180.0;
const MAJOR_AXIS_TOL: f64 = 0.05;
const TE_LEVEL_TOL: f64 = 0.10;

/// Issue 17 point 5's verification: the pinion synthesised for seed 003's
/// gear (default stages) meets its three targets, measured by the point
/// TCA on the synthesised pair (not by the synthesis's own difference
/// formulas), and generates over its whole blank (the flank is built
/// over the blank or the synthesis errs).
#[test]
fn seed003_synthesised_pinion_meets_its_targets_in_the_tca() {
    let d = design();
    let targets = seed003_targets();
    let problem = seed003(&d, targets);
    let t0 = std::time::Instant::now();
    let x0 = PinionSynthesisVariables::basic(problem.cutter.mean_radius);
    let s = synthesize_pinion(&problem, x0).unwrap();
    let synth_time = t0.elapsed();
    assert!(s.residual <= TOLERANCE, "{s:?}");
    let pair = problem.pair(&s.setup).unwrap();
    let f = tca_figures(&pair, s.variables.mean_roll_rad, targets.approach_mm, 0.1);
    let arcsec = |r: f64| r.to_degrees() * 3600.0;
    eprintln!(
        "seed003 synthesis ({:.1} s): {} Newton iterations, {} continuation steps, residual {:.2e}\n\
         basic {:?}\nfirst order {:?}\nachieved {:?}\nvariables {:?}\nsettings {:?}\nhead {:?}\n\
         TCA ({} points): path {:.3}° (target {:.3}°), 2a {:.3} mm (target {:.3}), level {:.3}″ (target {:.3}″), \
         TE fall over ±π/z₁ {:?}″, cubic term {:.2e}″",
        synth_time.as_secs_f64(),
        s.iterations,
        s.continuation_steps,
        s.residual,
        s.start,
        s.first_order,
        s.achieved,
        s.variables,
        s.setup.settings,
        s.setup.head.outside,
        f.points,
        f.path_angle_rad.to_degrees(),
        targets.path_angle_rad.to_degrees(),
        f.major_axis_mm,
        targets.major_axis_mm,
        arcsec(f.te_level_rad),
        arcsec(targets.te_level_rad),
        f.te_fall_half_pitch_rad.map(arcsec),
        arcsec(s.achieved.te_cubic_rad),
    );
    assert!(
        (f.path_angle_rad - targets.path_angle_rad).abs() <= PATH_TOL_RAD,
        "{f:?}"
    );
    assert!(
        (f.major_axis_mm / targets.major_axis_mm - 1.0).abs() <= MAJOR_AXIS_TOL,
        "{f:?}"
    );
    assert!(
        (f.te_level_rad / targets.te_level_rad - 1.0).abs() <= TE_LEVEL_TOL,
        "{f:?}"
    );
}
