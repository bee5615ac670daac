//! # Hypoid LTCA against FE contact on the same bodies
//!
//! Issue 19 point 3 (frictionless; see README.md beside this file). The
//! seed 003 pair with the eased pinion (`papers/seed003-hypoid/scene_eased.toml`,
//! 1000 N·m on the gear) at three roll angles of its cycle (the middle
//! pair entering, at the mean point, leaving): the compliance-matrix LTCA
//! (`flank::ltca::bevel`: tensors of both bevel sector bodies, K points on
//! each pair's contact-ellipse major axis from the point TCA, strip Hertz
//! near field, the contact QP; tensors of the bodies at flank 1.5 mm, base
//! 6 mm) against FE contact (`flank::mesh_cycle::bevel`, hard contact,
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
use flank::ltca::bevel::{BevelLtca, BevelLtcaOptions};
use flank::mesh::bevel_sector::BevelSectorOptions;
use flank::mesh_cycle::bevel::{BevelCycle, BevelRunOptions};
use flank::scene::{read_any_scene, AnyScene, BevelScene};

const TOL_SHARE: f64 = 0.02;
const TOL_TE: f64 = 0.03;

fn scene() -> BevelScene {
    let path = format!(
        "{}/papers/seed003-hypoid/scene_eased.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    match read_any_scene(Path::new(&path)).unwrap() {
        AnyScene::Bevel(b) => b,
        _ => panic!("not a bevel scene"),
    }
}

#[test]
fn seed003_ltca_against_fe_contact() {
    let sc = scene();
    let work = Path::new(env!("CARGO_TARGET_TMPDIR")).join("ltca_hypoid");
    let _ = std::fs::remove_dir_all(&work);
    let t = Instant::now();
    let ltca = BevelLtca::new(
        &sc,
        &BevelLtcaOptions {
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
    let fe = BevelCycle::new(
        &sc,
        &BevelRunOptions {
            mesh: BevelSectorOptions {
                flank_size: 0.75,
                base_size: 6.0,
                ..Default::default()
            },
            threads: 2,
            ..Default::default()
        },
    )
    .unwrap();
    let setup_fe = t.elapsed().as_secs_f64();
    println!(
        "setup: LTCA {setup_ltca:.1} s (tensors {:.1} s, TCA {:.2} s), FE {setup_fe:.1} s",
        ltca.compliance_s, ltca.tca_s
    );
    println!("| roll (°) | pair | share LTCA | share FE | diff | force LTCA (N) | force FE (N) |");
    println!("|---|---|---|---|---|---|---|");
    let mut rows = Vec::new();
    // the TCA grid positions nearest to −5, 0, +5 twentieths of the cycle
    let step = ltca.cycle_deg() / 20.0;
    for roll in [-5.0 * step, 0.0, 5.0 * step] {
        let t = Instant::now();
        let r = ltca.solve(roll).unwrap();
        let t_ltca = t.elapsed().as_secs_f64();
        let t = Instant::now();
        let f = fe.solve(r.roll_deg).unwrap();
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
