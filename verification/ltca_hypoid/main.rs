//! # Hypoid LTCA against FE contact on the same bodies
//!
//! Issue 19 point 3 (frictionless; see README.md beside this file). The
//! seed 003 pair with the eased pinion (`papers/seed003-hypoid/scene_eased.toml`,
//! 1000 N·m on the gear) at three roll angles of its cycle (the middle
//! pair entering, at the mean point, leaving): the compliance-matrix LTCA
//! (`flank::ltca::cycle`: tensors of both bevel sector bodies, K points on
//! each pair's contact-ellipse major axis from the point TCA, strip Hertz
//! near field, the contact QP; tensors of the bodies at flank 1.5 mm, base
//! 6 mm) against FE contact (`flank::mesh_cycle::cycle::MeshCycle`, hard contact,
//! flank 0.75 mm, base 6 mm).
//!
//! Targets of issue 19: load share per tooth pair within 0.02, loaded TE
//! within 3 %, against a converged FE reference. The mesh study of
//! `papers/seed003-hypoid/README.md` (flank 1.5 → 0.25 mm) puts the 0.75 mm
//! FE within 0.005 of the converged shares and 0.4″ (0.3 %) of the
//! converged TE at these angles, at 45 s here; the 1.5 mm FE (the tensors'
//! own mesh) is 1.3″ off in TE at −8.18°, too coarse to be the reference
//! (a first run against it measured 3.95 % there).

use std::path::Path;
use std::time::Instant;

use flank::compliance::body::BodyMeshOptions;
use flank::ltca::cycle::{LtcaCycle, LtcaOptions};
use flank::mesh::bevel_sector::BevelSectorOptions;
use flank::mesh_cycle::cycle::{MeshCycle, RunSettings};
use flank::mesh_cycle::pair_model::bevel_pair_model;
use flank::scene::{read_scene, Scene};

const TOL_SHARE: f64 = 0.02;
const TOL_TE: f64 = 0.03;

fn scene() -> Scene {
    let path = format!(
        "{}/papers/seed003-hypoid/scene_eased.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    read_scene(Path::new(&path)).unwrap()
}

#[test]
fn seed003_ltca_against_fe_contact() {
    let sc = scene();
    let work = Path::new(env!("CARGO_TARGET_TMPDIR")).join("ltca_hypoid");
    let _ = std::fs::remove_dir_all(&work);
    let t = Instant::now();
    let ltca = LtcaCycle::new(
        &sc,
        &LtcaOptions {
            out: work.clone(),
            mesh: BodyMeshOptions {
                flank_size: Some(1.5),
                base_size: Some(6.0),
                with_load: false,
                element: None,
            },
            threads: 2,
            ..Default::default()
        },
    )
    .unwrap();
    let setup_ltca = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let mesh = BevelSectorOptions {
        flank_size: 0.75,
        base_size: 6.0,
        ..Default::default()
    };
    let fe = MeshCycle::of_pair(
        &sc,
        bevel_pair_model(&sc, &mesh).unwrap(),
        RunSettings::default_for(&sc),
        2,
    )
    .unwrap();
    let setup_fe = t.elapsed().as_secs_f64();
    println!(
        "setup: LTCA {setup_ltca:.1} s (tensors {:.1} s, TCA {:.2} s), FE {setup_fe:.1} s",
        ltca.setup.compliance_s,
        ltca.point().unwrap().trace_s
    );
    println!("| roll (°) | pair | share LTCA | share FE | diff | force LTCA (N) | force FE (N) |");
    println!("|---|---|---|---|---|---|---|");
    let mut rows = Vec::new();
    // the TCA grid positions nearest to −5, 0, +5 twentieths of the cycle
    let step = ltca.point().unwrap().cycle_deg() / 20.0;
    for roll in [-5.0 * step, 0.0, 5.0 * step] {
        let t = Instant::now();
        let r = ltca.solve(roll).unwrap();
        let t_ltca = t.elapsed().as_secs_f64();
        let t = Instant::now();
        let f = fe.solve(r.roll_deg).unwrap().step;
        let t_fe = t.elapsed().as_secs_f64();
        let forces = ltca.pair_forces(&r);
        let total: f64 = forces.iter().sum();
        let mut worst: f64 = 0.0;
        for (p, &x) in forces.iter().enumerate() {
            let share = x / total;
            let d = share - f.load_share[p];
            worst = worst.max(d.abs());
            println!(
                "| {:.3} | {} | {share:.4} | {:.4} | {d:+.4} | {x:.0} | {:.0} |",
                r.roll_deg,
                p + 1,
                f.load_share[p],
                f.pair_force_n[p]
            );
        }
        let te = ltca.te_arcsec(&r);
        rows.push((r.roll_deg, worst, te, f.te_arcsec, r.kkt_max, t_ltca, t_fe));
        assert!(r.kkt_within_tolerance, "{}: KKT {}", r.roll_deg, r.kkt_max);
    }
    println!("| roll (°) | worst share diff | TE LTCA (″) | TE FE (″) | TE diff | KKT | LTCA (s) | FE (s) |");
    println!("|---|---|---|---|---|---|---|---|");
    for &(roll, worst, te, te_fe, kkt, tl, tf) in &rows {
        let d = (te - te_fe) / te_fe.abs();
        println!(
            "| {roll:.3} | {worst:.4} | {te:.2} | {te_fe:.2} | {:+.2} % | {kkt:.1e} | {tl:.3} | {tf:.2} |",
            100.0 * d
        );
    }
    for &(roll, worst, te, te_fe, ..) in &rows {
        let d = (te - te_fe).abs() / te_fe.abs();
        println!(
            "VERIFY ltca_hypoid {roll:+.3}°: shares {worst:.4} (tol {TOL_SHARE}), TE {d:.4} (tol {TOL_TE})"
        );
        assert!(worst <= TOL_SHARE, "{roll}: share {worst}");
        assert!(d <= TOL_TE, "{roll}: TE {d}");
    }
}

/// Issue 19 point 1 on the hypoid pair: the frictional LTCA (seed 003:
/// μ = 0.07, 10 increments) at roll 0, solved by clarabel and by Lemke
/// (agreement ≤ 1e-8), μ = 0 through the friction solver equal to the
/// frictionless QP (≤ 1e-10), the Coulomb law at every loaded point, and
/// the direction of friction's effects (seed 003: p_max lower with
/// friction by 3–5 %; every loaded point of a hypoid flank slips).
#[test]
fn seed003_frictional_ltca_cross_checks() {
    use flank::ltca::friction::{FrictionOptions, Increments};
    use flank::ltca::solve_settings::LtcaFriction;
    let sc = scene();
    let work = Path::new(env!("CARGO_TARGET_TMPDIR")).join("ltca_hypoid_friction");
    let _ = std::fs::remove_dir_all(&work);
    let base = LtcaOptions {
        out: work.clone(),
        mesh: BodyMeshOptions {
            flank_size: Some(2.0),
            base_size: Some(8.0),
            with_load: false,
            element: None,
        },
        points_per_line: Some(15),
        threads: 2,
        ..Default::default()
    };
    let frictionless = LtcaCycle::new(&sc, &base).unwrap();
    let r0 = frictionless.solve(0.0).unwrap();
    // μ = 0 through the friction solver
    let mut zero = LtcaCycle::new(&sc, &base).unwrap();
    zero.settings.friction = Some(LtcaFriction {
        mu: 0.0,
        options: FrictionOptions {
            increments: Increments::Count(3),
            ..Default::default()
        },
        pinion_speed_rad_s: sc.load.speed_rpm * std::f64::consts::PI / 30.0,
        cross_check: false,
        model: Default::default(),
    });
    let rz = zero.solve(0.0).unwrap();
    let pmax0 = r0.points.iter().map(|p| p.force_n).fold(0.0f64, f64::max);
    let dz = r0
        .points
        .iter()
        .zip(&rz.points)
        .map(|(a, b)| (a.force_n - b.force_n).abs() / pmax0)
        .fold(0.0f64, f64::max);
    let dte = (r0.te_urad - rz.te_urad).abs() / r0.te_urad.abs();
    println!("VERIFY ltca_hypoid friction μ = 0 vs frictionless: loads {dz:.2e}, TE {dte:.2e} (tol 1e-10)");
    assert!(dz <= 1e-10 && dte <= 1e-10, "{dz} {dte}");
    // μ = 0.07 by both solvers
    let mu = 0.07;
    let with = LtcaCycle::new(
        &sc,
        &LtcaOptions {
            friction_mu: Some(mu),
            increments: Some(10),
            cross_check: true,
            ..base.clone()
        },
    )
    .unwrap();
    let rf = with.solve(0.0).unwrap();
    let Some(flank::ltca::friction_report::FrictionReport::Incremental(report)) = &rf.friction
    else {
        panic!("an incremental friction report: {:?}", rf.friction)
    };
    let check = report.cross_check.as_ref().expect("a Lemke cross-check");
    let (load_diff, rot_diff) = (check.load_difference, check.rotation_difference);
    println!(
        "VERIFY ltca_hypoid friction clarabel vs Lemke: loads {load_diff:.2e}, rotation {rot_diff:.2e}, states differing {} (tol 1e-8); residual {:.2e}",
        check.state_differences, report.max_residual.max
    );
    assert!(load_diff <= 1e-8 && rot_diff <= 1e-8, "{check:?}");
    assert_eq!(check.state_differences, 0);
    assert!(report.within_tolerance);
    // Coulomb law: every loaded point slips with |P_t| = μ P_n
    let (mut n_sum, mut t_sum) = (0.0, 0.0);
    for p in &rf.points {
        if p.force_n > 0.0 {
            assert!(p.state.starts_with("slip"), "{}: {}", p.along_mm, p.state);
            assert!((p.friction_n.abs() - mu * p.force_n).abs() <= 1e-9 * p.force_n);
            n_sum += p.force_n;
            t_sum += p.friction_n.abs();
        }
    }
    let p_without = r0.max_pressure_mpa;
    let p_with = rf.max_pressure_mpa;
    let te = (with.te_arcsec(&rf), frictionless.te_arcsec(&r0));
    println!(
        "μ = {mu}: tangential / normal = {:.4}; Σ P_n {n_sum:.0} N (frictionless {:.0} N); p_max {p_with:.0} vs {p_without:.0} MPa ({:+.1} %); TE {:.2} vs {:.2}″",
        t_sum / n_sum,
        r0.points.iter().map(|p| p.force_n).sum::<f64>(),
        100.0 * (p_with / p_without - 1.0),
        te.0,
        te.1
    );
    assert!(p_with < p_without);
}

/// The hypoid FE-with-friction reference (issue 19): what friction
/// (μ = 0.07) does to the loaded contact at roll 0, in FE contact
/// (`flank::mesh_cycle::cycle::MeshCycle`, the contact solver's static Coulomb law)
/// and in the frictional LTCA (10 increments, the kinematic sliding
/// direction), both on the same 2 mm / 8 mm bodies. Compared: the relative
/// change of the total normal force and of the loaded TE from μ = 0 to
/// 0.07, within 10 % of the FE's change (a tolerance chosen after a first
/// command-line run of both at this mesh had shown −8.9 / −9.0 % and
/// −5.6 / −5.7 %: it states the agreement, it was not a target set
/// blind; README.md), and the FE's own checks: moment balance with the
/// friction moments ≤ 1e-8, the Coulomb law met.
#[test]
fn seed003_friction_effect_against_fe_contact() {
    let sc = scene();
    let work = Path::new(env!("CARGO_TARGET_TMPDIR")).join("ltca_hypoid_friction_fe");
    let _ = std::fs::remove_dir_all(&work);
    let mu = 0.07;
    let mesh = BodyMeshOptions {
        flank_size: Some(2.0),
        base_size: Some(8.0),
        with_load: false,
        element: None,
    };
    let ltca = |friction_mu: f64| {
        let o = LtcaOptions {
            out: work.clone(),
            mesh,
            friction_mu: Some(friction_mu),
            increments: (friction_mu > 0.0).then_some(10),
            threads: 2,
            ..Default::default()
        };
        let l = LtcaCycle::new(&sc, &o).unwrap();
        let r = l.solve(0.0).unwrap();
        let forces = l.pair_forces(&r);
        (r.roll_deg, forces, l.te_arcsec(&r))
    };
    let (roll, n0, te0) = ltca(0.0);
    let (_, n1, te1) = ltca(mu);
    let fe = |friction_mu: f64| {
        let mesh = BevelSectorOptions {
            flank_size: 2.0,
            base_size: 8.0,
            ..Default::default()
        };
        let settings = RunSettings {
            friction_mu,
            ..RunSettings::default_for(&sc)
        };
        let c =
            MeshCycle::of_pair(&sc, bevel_pair_model(&sc, &mesh).unwrap(), settings, 2).unwrap();
        c.solve(roll).unwrap().step
    };
    let (f0, f1) = (fe(0.0), fe(mu));
    let sum = |v: &[f64]| v.iter().sum::<f64>();
    let rel = |a: f64, b: f64| b / a - 1.0;
    let (dn_ltca, dn_fe) = (
        rel(sum(&n0), sum(&n1)),
        rel(sum(&f0.pair_force_n), sum(&f1.pair_force_n)),
    );
    let (dte_ltca, dte_fe) = (rel(te0, te1), rel(f0.te_arcsec, f1.te_arcsec));
    let friction_ratio = sum(&f1.friction_force_n) / sum(&f1.pair_force_n);
    println!("| μ = 0 → {mu} at roll {roll:.3}° | LTCA | FE |");
    println!("|---|---|---|");
    println!(
        "| pair forces μ = 0 (N) | {n0:.0?} | {:.0?} |",
        f0.pair_force_n
    );
    println!(
        "| pair forces μ = {mu} (N) | {n1:.0?} | {:.0?} |",
        f1.pair_force_n
    );
    println!(
        "| Σ normal force change | {:+.2} % | {:+.2} % |",
        100.0 * dn_ltca,
        100.0 * dn_fe
    );
    println!(
        "| loaded TE μ = 0 / {mu} (″) | {te0:.2} / {te1:.2} | {:.2} / {:.2} |",
        f0.te_arcsec, f1.te_arcsec
    );
    println!(
        "| TE change | {:+.2} % | {:+.2} % |",
        100.0 * dte_ltca,
        100.0 * dte_fe
    );
    println!(
        "FE with friction: friction / normal force {friction_ratio:.4}, stick/slip nodes {}/{}, Coulomb residual {:.1e}, moment balance {:.1e}, {} Tresca problems",
        f1.stick_nodes, f1.slip_nodes, f1.coulomb_residual, f1.moment_balance.unwrap(), f1.friction_iterations
    );
    println!(
        "VERIFY ltca_hypoid friction effect: normal force {:.2e}, TE {:.2e} of the FE's change (tol 0.1)",
        (dn_ltca - dn_fe).abs() / dn_fe.abs(),
        (dte_ltca - dte_fe).abs() / dte_fe.abs()
    );
    assert_eq!(f1.friction_converged, Some(true));
    assert!(
        f1.moment_balance.unwrap().abs() <= 1e-8,
        "{:?}",
        f1.moment_balance
    );
    assert!(friction_ratio <= mu * (1.0 + 1e-9), "{friction_ratio}");
    assert!(
        (dn_ltca - dn_fe).abs() <= 0.1 * dn_fe.abs(),
        "{dn_ltca} {dn_fe}"
    );
    assert!(
        (dte_ltca - dte_fe).abs() <= 0.1 * dte_fe.abs(),
        "{dte_ltca} {dte_fe}"
    );
}
