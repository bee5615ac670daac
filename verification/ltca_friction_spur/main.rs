//! # Verification: friction in the spur LTCA (seed 002, μ = 0.05, coarse)
//!
//! ## What
//!
//! `flank ltca --friction-mu 0.05` on the seed 002 spur pair (z 13/35,
//! m 3.8 mm, 312 N·m at 11 758 rpm) with its three friction models
//! (`flank::settings::FrictionModel`): `incremental` (seeds 001/003),
//! `standstill` (the same with the kinematic sliding off: the mate held,
//! the model of one static FE contact step) and `sliding` (the running
//! mesh: μP_n against the kinematic sliding velocity). Tensors on coarse
//! meshes (flank 1 mm, base 2 mm) so that the case runs in CI.
//!
//! ## Checks and references (tolerances fixed before the CI-size run)
//!
//! 1. **Closed form, sliding model, single contact.** One spur contact
//!    line sits at one radius, so every point has r_n = r_b1 and
//!    r_t = ρ₁ = r_b1 (tan α_w + φ) (φ the roll from the pitch point) and
//!    the friction force μP_n opposes the sliding, whose sign is that of
//!    φ: the pair's normal force is T / (r_b1 + sign(φ) μ ρ₁). Tolerance
//!    1e-9 relative; every loaded point's P_t has the sign of v_s.
//! 2. **μ → 0** reproduces the frictionless LTCA to 1e-10 of the largest
//!    load in every model.
//! 3. **Two solvers.** Incremental and standstill: clarabel vs Lemke
//!    ≤ 1e-8; sliding: fixed point vs the direct solve on the loaded set
//!    ≤ 1e-10.
//! 4. **Against FE contact with friction** (`flank run --friction-mu`,
//!    hard contact and hard stick, one static step: the standstill
//!    model's physics) on the same element sizes, at four double-contact
//!    positions, and FE/LTCA without friction at the same positions.
//!    Tolerances: the friction force per pair (FE reports its magnitude)
//!    within 0.1 μ F_nom (F_nom = T/r_b1), the change of each pair's
//!    normal force by friction within 0.1 μ F_nom, the change of TE by
//!    friction within 25 % of the FE's or 3 µrad.
//! 5. **Known miss (ignored test):** mid single contact, where the
//!    standstill slip r_t Δθ and the elastic tangential motion nearly
//!    cancel and part of the line sticks, the friction forces differ
//!    (README).
//!
//! Run: `cargo test --release --test ltca_friction_spur -- --nocapture`

use std::path::{Path, PathBuf};

use flank::compliance::body::BodyMeshOptions;
use flank::ltca::cycle::{LtcaCycle, LtcaOptions};
use flank::ltca::model::PositionResult;
use flank::mesh_cycle::cycle::MeshCycle;
use flank::mesh_cycle::run::{settings, RunOptions};
use flank::scene::{read_scene, Scene};
use flank::settings::FrictionModel;

const MU: f64 = 0.05;

fn scene() -> Scene {
    read_scene(Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/papers/seed002-spur/scene.toml"
    )))
    .unwrap()
}

fn mesh() -> BodyMeshOptions {
    BodyMeshOptions {
        flank_size: Some(1.0),
        base_size: Some(2.0),
        ..Default::default()
    }
}

/// The finer tensors of the solver cross-check (the LTCA benchmark's):
/// on the 1 mm ones Lemke's method fails (README).
fn fine_mesh() -> BodyMeshOptions {
    BodyMeshOptions {
        flank_size: Some(0.475),
        base_size: Some(1.0),
        ..Default::default()
    }
}

fn work(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("ltca_friction_spur")
        .join(name);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The LTCA with friction coefficient `mu` in `model` (μ = 0: none).
fn cycle(scene: &Scene, mu: f64, model: FrictionModel, cross_check: bool) -> LtcaCycle {
    cycle_on(scene, mesh(), mu, model, cross_check)
}

fn cycle_on(
    scene: &Scene,
    mesh: BodyMeshOptions,
    mu: f64,
    model: FrictionModel,
    cross_check: bool,
) -> LtcaCycle {
    let o = LtcaOptions {
        out: work("bodies"),
        mesh,
        points_per_line: Some(20),
        cache: Some(work("cache")),
        quiet: true,
        friction_mu: Some(mu),
        friction_model: (mu > 0.0).then_some(model),
        cross_check: cross_check && mu > 0.0,
        ..Default::default()
    };
    LtcaCycle::new(scene, &o).unwrap()
}

/// The cross-check's load difference of `r` (NaN without one).
fn cross_check_load_difference(r: &PositionResult) -> f64 {
    r.friction
        .as_ref()
        .and_then(|f| f.cross_check_load_difference())
        .unwrap_or(f64::NAN)
}

fn largest_load_difference(a: &PositionResult, b: &PositionResult) -> f64 {
    let pmax = a.points.iter().map(|p| p.force_n).fold(0.0f64, f64::max);
    a.points
        .iter()
        .zip(&b.points)
        .map(|(x, y)| (x.force_n - y.force_n).abs())
        .fold(0.0f64, f64::max)
        / pmax
}

const MODELS: [FrictionModel; 3] = [
    FrictionModel::Incremental,
    FrictionModel::Standstill,
    FrictionModel::Sliding,
];

#[test]
fn friction_ltca_closed_form_limits_and_solvers() {
    let scene = scene();
    let frictionless = cycle(&scene, 0.0, FrictionModel::Incremental, false);
    let pair = frictionless.line_pair().unwrap();
    let torque = frictionless.torque;
    let rb1 = pair.nominal_moment_arm();
    // operating pressure angle: r_w1 = a z1/(z1 + z2)
    let (z1, z2) = (13.0, 35.0);
    let rw1 = 90.0 * z1 / (z1 + z2);
    let tan_aw = ((rw1 / rb1).powi(2) - 1.0).sqrt();
    let (l, h) = pair.single_contact();
    let sliding = cycle(&scene, MU, FrictionModel::Sliding, false);
    println!("1. sliding model, single contact: roll (deg) | F_n | T/(r_b1 ± μρ₁) | rel. error");
    let mut worst: f64 = 0.0;
    // (near the ends of single contact a neighbour's tip corner still
    // carries load at this mesh size, 0.15 and 0.85 of it: there the
    // closed form for one line does not hold, and at 0.15 the sliding
    // fixed point does not converge and the answer is flagged; README)
    for f in [0.35, 0.5, 0.7] {
        let roll = l + f * (h - l);
        let r = sliding.solve(roll.to_degrees()).unwrap();
        assert!(r.kkt_within_tolerance, "{roll}: residual {:.2e}", r.kkt_max);
        let forces = sliding.pair_forces(&r);
        let fnorm: f64 = forces.iter().sum();
        assert_eq!(
            forces.iter().filter(|&&x| x > 0.0).count(),
            1,
            "{roll}: one pair alone must carry the load: {forces:?}"
        );
        let rho1 = rb1 * (tan_aw + roll);
        let expected = torque / (rb1 + roll.signum() * MU * rho1);
        let e = (fnorm / expected - 1.0).abs();
        worst = worst.max(e);
        println!(
            "{:8.3} | {fnorm:.4} | {expected:.4} | {e:.2e}",
            roll.to_degrees()
        );
        for p in r.points.iter().filter(|p| p.force_n > 0.0) {
            assert!(
                p.friction_n * p.sliding_velocity_m_s >= 0.0,
                "{roll}: friction {} against sliding {}",
                p.friction_n,
                p.sliding_velocity_m_s
            );
        }
    }
    assert!(worst < 1e-9, "closed form missed: {worst:.2e}");

    // 2 and 3 on the finer tensors (the 1 mm ones: ignored test below)
    let (a, _) = pair.engagement(pair.middle());
    let (_, e) = pair.engagement(pair.middle());
    let angles = [
        0.5 * (a + l).to_degrees(),
        0.5 * (l + h).to_degrees(),
        0.5 * (h + e).to_degrees(),
    ];
    limits_and_solvers(&scene, fine_mesh(), &angles);
}

/// Checks 2 and 3 at `angles` (deg) on tensors of `mesh`.
fn limits_and_solvers(scene: &Scene, mesh: BodyMeshOptions, angles: &[f64]) {
    let frictionless = cycle_on(scene, mesh, 0.0, FrictionModel::Incremental, false);
    println!("2./3. model | roll | μ→0 difference | cross-check");
    for &roll in angles {
        let r0 = frictionless.solve(roll).unwrap();
        for model in MODELS {
            let zero = cycle_on(scene, mesh, 1e-300, model, false);
            let dz = largest_load_difference(&r0, &zero.solve(roll).unwrap());
            let c = cycle_on(scene, mesh, MU, model, true).solve(roll).unwrap();
            let dc = cross_check_load_difference(&c);
            println!("{model:?} | {roll:.3} | {dz:.1e} | {dc:.1e}");
            assert!(
                dz <= 1e-10,
                "{model:?} at {roll}: μ → 0 differs by {dz:.2e}"
            );
            let limit = if model == FrictionModel::Sliding {
                1e-10
            } else {
                1e-8
            };
            assert!(dc <= limit, "{model:?} at {roll}: cross-check {dc:.2e}");
            assert!(
                c.kkt_within_tolerance,
                "{model:?} at {roll}: {:.2e}",
                c.kkt_max
            );
        }
    }
}

#[test]
#[ignore = "known defect: on the 1 mm tensors Lemke's method hits its pivot limit or disagrees with clarabel (40× the largest load at −8.43°, 5.4× at 5.41°); README"]
fn solvers_agree_on_coarse_tensors() {
    let scene = scene();
    let c = cycle(&scene, 0.0, FrictionModel::Incremental, false);
    let (a, _) = c.line_pair().unwrap().engagement(c.pair.middle());
    let (l, h) = c.line_pair().unwrap().single_contact();
    limits_and_solvers(
        &scene,
        mesh(),
        &[0.5 * (a + l).to_degrees(), 0.5 * (l + h).to_degrees()],
    );
}

/// FE contact (with and without friction) and the standstill LTCA at
/// `angles` (deg); returns the worst friction-force, normal-force-change
/// and TE-change differences (the last relative to the FE change, or in
/// µrad below 12 µrad of change).
fn against_fe(scene: &Scene, angles: &[f64]) -> (f64, f64, f64) {
    let l0 = cycle(scene, 0.0, FrictionModel::Standstill, false);
    let l1 = cycle(scene, MU, FrictionModel::Standstill, false);
    let fe = |mu: f64| {
        let o = RunOptions {
            roll_angles_deg: Some(angles.to_vec()),
            vtu: Some(false),
            refine_contact_limits: Some(false),
            friction_mu: Some(mu),
            quiet: true,
            ..Default::default()
        };
        let s = settings(scene, &o).unwrap();
        MeshCycle::new(scene, &mesh(), s, 0).unwrap()
    };
    let (fe0, fe1) = (fe(0.0), fe(MU));
    let scale = MU * l0.nominal_force();
    println!("4. roll | pair | FE F_t | LTCA |F_t| | FE ΔF_n | LTCA ΔF_n (N) ; FE ΔTE | LTCA ΔTE (µrad) | FE TE | LTCA TE");
    let (mut wt, mut wn, mut wte): (f64, f64, f64) = (0.0, 0.0, 0.0);
    for &roll in angles {
        let (f0, f1) = (fe0.solve(roll).unwrap().step, fe1.solve(roll).unwrap().step);
        let (r0, r1) = (l0.solve(roll).unwrap(), l1.solve(roll).unwrap());
        assert!(
            r1.kkt_within_tolerance,
            "{roll}: residual {:.2e}",
            r1.kkt_max
        );
        let (n0, n1, t1) = (
            l0.pair_forces(&r0),
            l1.pair_forces(&r1),
            l1.pair_friction(&r1),
        );
        for p in 0..n1.len() {
            if f1.pair_force_n[p] <= 0.0 && n1[p] <= 0.0 {
                continue;
            }
            let dfe = f1.pair_force_n[p] - f0.pair_force_n[p];
            let dl = n1[p] - n0[p];
            println!(
                "{roll:8.3} | {} | {:7.1} | {:7.1} | {dfe:7.1} | {dl:7.1}",
                p + 1,
                f1.friction_force_n[p],
                t1[p].abs()
            );
            wt = wt.max((f1.friction_force_n[p] - t1[p].abs()).abs() / scale);
            wn = wn.max((dfe - dl).abs() / scale);
        }
        let (dtf, dtl) = (f1.te_urad - f0.te_urad, r1.te_urad - r0.te_urad);
        println!(
            "{roll:8.3} | TE change FE {dtf:.2} LTCA {dtl:.2} µrad; TE FE {:.1} LTCA {:.1} µrad",
            f1.te_urad, r1.te_urad
        );
        let e = if dtf.abs() > 12.0 {
            (dtl - dtf).abs() / dtf.abs()
        } else {
            (dtl - dtf).abs() / 12.0 * 0.25
        };
        wte = wte.max(e);
    }
    println!("worst: friction force {wt:.3} μF_nom, ΔF_n {wn:.3} μF_nom, ΔTE {wte:.3}");
    (wt, wn, wte)
}

#[test]
fn standstill_ltca_against_fe_contact_with_friction() {
    let scene = scene();
    let c = cycle(&scene, 0.0, FrictionModel::Standstill, false);
    let (a, e) = c.line_pair().unwrap().engagement(c.pair.middle());
    let (l, h) = c.line_pair().unwrap().single_contact();
    let angles = [
        a.to_degrees() + 1.0,
        0.5 * (a + l).to_degrees(),
        0.5 * (h + e).to_degrees(),
        e.to_degrees() - 1.0,
    ];
    let (wt, wn, wte) = against_fe(&scene, &angles);
    assert!(wt <= 0.1, "friction force per pair: {wt:.3} μF_nom > 0.1");
    assert!(
        wn <= 0.1,
        "normal-force change by friction: {wn:.3} μF_nom > 0.1"
    );
    assert!(wte <= 0.25, "TE change by friction: {wte:.3} > 0.25");
}

#[test]
fn standstill_ltca_against_fe_mid_single_contact() {
    let scene = scene();
    let c = cycle(&scene, 0.0, FrictionModel::Standstill, false);
    let (l, h) = c.line_pair().unwrap().single_contact();
    let (wt, wn, wte) = against_fe(&scene, &[0.5 * (l + h).to_degrees()]);
    assert!(wt <= 0.1 && wn <= 0.1 && wte <= 0.25);
}
