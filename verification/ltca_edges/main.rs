//! # Edge-loaded hypoid LTCA (seed 000)
//!
//! Issue 19 point 2 (see README.md beside this file). Seed 000's pair with
//! the Cyclo-Palloid pinion tilt in 5-tooth sectors
//! (`papers/seed000-hypoid/scene_tilted_ltca.toml`, 400 N·m on the gear),
//! one mesh cycle of 20 positions, LTCA with the TCA's edge contacts as
//! candidate lines and without them (`flank::ltca::cycle`,
//! `flank::tca::edge_lines`), tensors of both sector bodies at flank 2 mm,
//! base 8 mm. Checks that could fail: the equilibrium and KKT residuals of
//! both variants, the edge lines' unloaded TE against the TCA's envelope,
//! the without-edges variant of a two-variant run against a separate
//! without-edges LTCA, the positions without contact against the TCA's
//! flank span, and the paper's statements (with edges no single-pair
//! zone; functional contact ratio with edges ≥ without).

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use flank::compliance::body::BodyMeshOptions;
use flank::ltca::cycle::{LtcaCycle, LtcaOptions};
use flank::ltca::run::run;
use flank::scene::{read_scene, Scene};
use flank::settings::EdgeVariants;
use flank::tca::point_contact::ARCSEC_PER_RAD;

/// KKT residual and torque balance of every position (the QP's own
/// tolerance is far below).
const TOL_RESIDUAL: f64 = 1e-9;
/// Unloaded TE of the candidate lines (min w/r, first order in the gear
/// turn) against the TCA's envelope (the exact gear turn), relative: the
/// flank axes of today's LTCA agree to 3.1e-3 on this pair (measured,
/// README); an edge line with a wrong separation, normal or moment arm is
/// off by its whole TE.
const TOL_UNLOADED_TE: f64 = 5e-3;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn scene() -> Scene {
    let path = root().join("papers/seed000-hypoid/scene_tilted_ltca.toml");
    read_scene(&path).unwrap()
}

fn options(work: &Path, edges: EdgeVariants) -> LtcaOptions {
    LtcaOptions {
        out: work.join(format!("{edges:?}")),
        mesh: BodyMeshOptions {
            flank_size: Some(2.0),
            base_size: Some(8.0),
            with_load: false,
            element: None,
        },
        cache: Some(work.join("cache")),
        threads: 2,
        edges: Some(edges),
        quiet: true,
        ..Default::default()
    }
}

fn f(v: &serde_json::Value) -> f64 {
    v.as_f64().unwrap_or(f64::NAN)
}

#[test]
fn seed000_ltca_with_and_without_edge_contact() {
    let sc = scene();
    let work = Path::new(env!("CARGO_TARGET_TMPDIR")).join("ltca_edges");
    let _ = std::fs::remove_dir_all(&work);
    let t = Instant::now();
    let s = run(&sc, &options(&work, EdgeVariants::Both))
        .unwrap()
        .to_json();
    let run_s = t.elapsed().as_secs_f64();
    let (w, o) = (&s["with_edges"], &s["without_edges"]);
    println!(
        "flank ltca (both variants): {run_s:.1} s; tensors {:.1} s ({:?} flank nodes)",
        f(&s["compliance_s"]),
        s["flank_nodes"]
    );
    for (name, v) in [("with edges", w), ("without edges", o)] {
        let sh = &v["load_sharing"];
        println!(
            "{name}: {} positions solved, FCR {:.3} (loaded pairs {}…{}, single-pair zone {:.2}°), TE p-p {:.2}″, max share {:.3}, KKT {:.1e}, torque balance {:.1e}, edge points {}, largest edge force {:.0} N, p_max {:.0} MPa (flank points), TCA {:.2} s, cycle {:.2} s, no contact at {:?}",
            v["positions"],
            f(&v["functional_contact_ratio"]),
            sh["min_loaded_pairs"],
            sh["max_loaded_pairs"],
            f(&sh["single_pair_span_deg"]),
            f(&v["te_peak_to_peak_arcsec"]),
            f(&sh["max_share"]),
            f(&v["max_kkt"]),
            f(&v["max_torque_balance_error"]),
            v["edge_candidate_points"],
            f(&v["max_edge_force_n"]),
            f(&v["max_pressure_mpa"]),
            f(&v["tca_s"]),
            f(&v["cycle_s"]),
            v["positions_without_contact_deg"],
        );
        println!("  roll (°) | shares by pinion tooth | lines | TE loaded / unloaded (″)");
        for st in v["steps"].as_array().unwrap() {
            let sh: Vec<String> = st["load_share"]
                .as_array()
                .unwrap()
                .iter()
                .map(|x| format!("{:.3}", f(x)))
                .collect();
            let lines: Vec<String> = st["lines"]
                .as_array()
                .unwrap()
                .iter()
                .zip(st["line_force_n"].as_array().unwrap())
                .map(|(l, x)| format!("{}:{}={:.0}N", l[0], l[2].as_str().unwrap_or(""), f(x)))
                .collect();
            println!(
                "  {:7.2} | {} | {} | {:.2} / {:.2}",
                f(&st["roll_deg"]),
                sh.join(" "),
                lines.join(" "),
                f(&st["te_arcsec"]),
                f(&st["unloaded_te_arcsec"])
            );
        }
        // residuals of every position
        assert!(
            f(&v["max_kkt"]) <= TOL_RESIDUAL,
            "{name}: KKT {}",
            v["max_kkt"]
        );
        assert!(
            f(&v["max_torque_balance_error"]) <= TOL_RESIDUAL,
            "{name}: Σ P r − T {}",
            v["max_torque_balance_error"]
        );
        // the 5-tooth sector holds every pair within the loaded approach,
        // and no candidate point fell off the tensors' flank grids
        assert_eq!(v["pairs_beyond_sector_within_approach"], 0, "{name}");
        for st in v["steps"].as_array().unwrap() {
            assert_eq!(st["skipped_points"], 0, "{name} at {}", st["roll_deg"]);
        }
    }
    // with edges: the edge lines carry load, at every position of the cycle
    assert!(w["edge_candidate_points"].as_u64().unwrap() > 0);
    assert!(f(&w["max_edge_force_n"]) > 0.0);
    assert_eq!(
        w["positions_without_contact_deg"].as_array().unwrap().len(),
        0
    );
    assert_eq!(w["positions"], 20);
    // without edges: no edge candidates
    assert_eq!(o["edge_candidate_points"], 0);

    // the paper's statements: no single-pair zone with edge contact; the
    // functional contact ratio with edges at least the one without
    let (fw, fo) = (
        f(&w["functional_contact_ratio"]),
        f(&o["functional_contact_ratio"]),
    );
    assert!(fw >= fo, "FCR with edges {fw} < without {fo}");
    assert!(
        w["load_sharing"]["min_loaded_pairs"].as_u64().unwrap() >= 2,
        "a single-pair zone with edges: {}",
        w["load_sharing"]
    );
    println!(
        "paper: FCR with edges > 2, no single-pair zone; flank: {fw:.3} (min loaded pairs {}), without edges {fo:.3}",
        w["load_sharing"]["min_loaded_pairs"]
    );

    // the variants one at a time on the cached tensors: the two-variant
    // run's without-edges cycle is the plain LTCA's, bit for bit
    let t = Instant::now();
    let plain = LtcaCycle::new(&sc, &options(&work, EdgeVariants::Without)).unwrap();
    let with = LtcaCycle::new(&sc, &options(&work, EdgeVariants::With)).unwrap();
    println!(
        "separate LTCAs on the cached tensors: {:.1} s",
        t.elapsed().as_secs_f64()
    );
    assert!(!plain.point().unwrap().edges && with.point().unwrap().edges);
    let steps_o = o["steps"].as_array().unwrap();
    let rolls: Vec<f64> = steps_o.iter().map(|st| f(&st["roll_deg"])).collect();
    let again = plain.solve_cycle_gaps(&rolls).unwrap();
    let mut worst: f64 = 0.0;
    for (st, r) in steps_o.iter().zip(&again) {
        let r = r.as_ref().expect("solved in the two-variant run");
        worst = worst.max((plain.te_arcsec(r) - f(&st["te_arcsec"])).abs());
        for (a, b) in plain
            .pair_forces(r)
            .iter()
            .zip(st["pair_force_n"].as_array().unwrap())
        {
            worst = worst.max((a - f(b)).abs());
        }
    }
    println!("without-edges variant against the plain LTCA: largest difference {worst:.1e}");
    assert_eq!(worst, 0.0);

    // positions without contact (no edges): where no pair's flank trace
    // reaches, 1 − flank span of the TCA over the pitch, to a grid step
    let n = 20.0;
    let gaps = o["positions_without_contact_deg"].as_array().unwrap().len() as f64;
    let expected = (1.0 - plain.point().unwrap().tca.flank_span_ratio).max(0.0);
    println!(
        "without edges: no contact at {gaps} of 20 positions; TCA flank span {:.3} pitches (gap {:.3} of the pitch)",
        plain.point().unwrap().tca.flank_span_ratio, expected
    );
    assert!((gaps / n - expected).abs() <= 1.0 / n + 1e-12);

    // unloaded TE of the candidate lines against the TCA's envelope at the
    // same grid rolls (edge lines with edges, flank axes without)
    for (name, ltca, v) in [("with edges", &with, w), ("without edges", &plain, o)] {
        let mut worst: f64 = 0.0;
        for st in v["steps"].as_array().unwrap() {
            let roll = f(&st["roll_deg"]);
            let Some(p) = ltca
                .point()
                .unwrap()
                .tca
                .positions
                .iter()
                .find(|p| (p.roll_rad.to_degrees() - roll).abs() < 1e-9)
            else {
                continue;
            };
            let tca = p.te_rad * ARCSEC_PER_RAD;
            let rel = (f(&st["unloaded_te_arcsec"]) - tca).abs() / tca.abs().max(1.0);
            worst = worst.max(rel);
        }
        println!("{name}: unloaded TE of the candidate lines against the TCA envelope, largest relative difference {worst:.2e}");
        assert!(worst <= TOL_UNLOADED_TE, "{name}: {worst}");
    }
}

/// The flank binary with `args`: (success, stderr).
fn flank(args: &[&str]) -> (bool, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_flank"))
        .args(args)
        .output()
        .unwrap();
    (
        o.status.success(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// The paper's "functional contact ratio > 2" measured where it is
/// physical: FE contact (`flank run`, the default 20 positions over one
/// pitch, same scene and 2 mm / 8 mm sectors as the LTCA above), with the
/// LTCA's measure (pairs above 1 % of the normal force,
/// `flank::load_sharing::cycle`). FE loads at least two pairs at every
/// position (no single-pair zone) and three over part of the cycle (the
/// tip/toe corner contact the LTCA has no candidate for; README,
/// "Whole-cycle functional contact ratio"). 13 s here.
#[test]
fn seed000_fe_cycle_functional_contact_ratio_above_two() {
    let work = Path::new(env!("CARGO_TARGET_TMPDIR")).join("ltca_edges_fe_cycle");
    let _ = std::fs::remove_dir_all(&work);
    let scene = root().join("papers/seed000-hypoid/scene_tilted_ltca.toml");
    let (ok, err) = flank(&[
        "run",
        scene.to_str().unwrap(),
        "--flank-size",
        "2",
        "--base-size",
        "8",
        "--threads",
        "2",
        "--quiet",
        "--out",
        work.to_str().unwrap(),
    ]);
    assert!(ok, "{err}");
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(work.join("summary.json")).unwrap()).unwrap();
    assert_eq!(s["positions"], 20);
    assert!(f(&s["max_moment_balance"]) < TOL_RESIDUAL);
    let ratio = f(&s["functional_contact_ratio"]);
    let sharing = &s["load_sharing"];
    println!(
        "VERIFY ltca_edges FE cycle: functional contact ratio {ratio:.3}, loaded pairs {} … {}, single-pair zone {}°",
        sharing["min_loaded_pairs"], sharing["max_loaded_pairs"], sharing["single_pair_span_deg"]
    );
    assert!(ratio > 2.0, "FE functional contact ratio {ratio}");
    assert!(sharing["min_loaded_pairs"].as_u64().unwrap() >= 2);
    assert_eq!(f(&sharing["single_pair_fraction"]), 0.0);
}

#[test]
fn bad_edge_input_gives_clear_errors() {
    let work = Path::new(env!("CARGO_TARGET_TMPDIR")).join("ltca_edges_input");
    let _ = std::fs::remove_dir_all(&work);
    std::fs::create_dir_all(&work).unwrap();
    let out = work.join("out");
    let out = out.to_str().unwrap();
    // the upright scene: its pinion body cannot be meshed; the error says
    // why and points to the tilted scene
    let upright = root().join("papers/seed000-hypoid/scene.toml");
    let (ok, err) = flank(&["ltca", upright.to_str().unwrap(), "--out", out]);
    println!("upright: {err}");
    assert!(!ok && !err.contains("panicked"), "{err}");
    assert!(
        err.contains("no gap land") && err.contains("scene_tilted.toml"),
        "{err}"
    );
    // an unknown variant on the command line
    let tilted = root().join("papers/seed000-hypoid/scene_tilted.toml");
    let (ok, err) = flank(&["ltca", tilted.to_str().unwrap(), "--edges", "sideways"]);
    assert!(!ok && err.contains("--edges"), "{err}");
    // an unknown variant in the scene: file and line
    let text = std::fs::read_to_string(&tilted).unwrap();
    let bad = work.join("bad.toml");
    std::fs::write(
        &bad,
        text.replace("edges = \"both\"", "edges = \"sideways\""),
    )
    .unwrap();
    let (ok, err) = flank(&["ltca", bad.to_str().unwrap(), "--out", out]);
    println!("unknown variant: {err}");
    let line = text
        .lines()
        .position(|l| l.starts_with("edges = "))
        .map(|i| i + 1)
        .unwrap();
    assert!(!ok && err.contains("sideways"), "{err}");
    assert!(
        err.contains(&format!("bad.toml:{line}"))
            || err.contains(&format!("bad.toml:{}", line - 1)),
        "{err}"
    );
    // edges on a spur scene (scene key and option)
    let spur = std::fs::read_to_string(root().join("papers/seed002-spur/scene.toml")).unwrap();
    let sp = work.join("spur.toml");
    std::fs::write(&sp, format!("{spur}\n[analyses.ltca]\nedges = \"with\"\n")).unwrap();
    let (ok, err) = flank(&["ltca", sp.to_str().unwrap(), "--out", out]);
    println!("spur scene key: {err}");
    assert!(
        !ok && err.contains("spur.toml:") && err.contains("bevel and hypoid"),
        "{err}"
    );
    let (ok, err) = flank(&[
        "ltca",
        root()
            .join("papers/seed002-spur/scene.toml")
            .to_str()
            .unwrap(),
        "--edges",
        "with",
        "--out",
        out,
    ]);
    assert!(!ok && err.contains("--edges"), "{err}");
}

/// Load share of each tooth pair, LTCA with edges against FE contact on
/// the same bodies (issue 19's acceptance).
const TOL_FE_SHARE: f64 = 0.02;
/// Loaded TE, LTCA with edges against FE contact, relative to the FE's.
const TOL_FE_TE: f64 = 0.03;

/// Issue 19 point 5 on seed 000: one position of the former single-pair
/// zone (−9°, where the LTCA with edges loads the tip edges of pairs 4
/// and 5 and the LTCA without edges the flank of pair 3 alone) by the
/// LTCA with edges and by FE contact, both on the 5-tooth sector bodies
/// at flank 2 mm / base 8 mm. Tolerances fixed before the FE figures were
/// read (`papers/seed000-hypoid/results/edge_fe/PLAN.md`): every pair's
/// share within 0.02, the loaded TE within 3 %, and FE contact closing
/// nodes on the pinion's tip edge of both pairs the LTCA loads at an
/// edge. 16.5 s here, but it fails: at flank 2 mm FE gives shares 0.719 /
/// 0.281 against 0.636 / 0.364 and a TE of −40.8″ against −15.5″ (README,
/// "Against FE contact").
#[test]
#[ignore = "misses: the edge-loaded LTCA is 0.09 off FE contact in load share and 15 % in TE at −9° (README, \"Against FE contact\"); run with --ignored"]
fn seed000_edge_ltca_against_fe_contact() {
    use flank::compliance::body::bevel_sector_options;
    use flank::mesh_cycle::cycle::{MeshCycle, RunSettings};
    use flank::mesh_cycle::pair_model::bevel_pair_model;
    let sc = scene();
    let work = Path::new(env!("CARGO_TARGET_TMPDIR")).join("ltca_edges_fe");
    let _ = std::fs::remove_dir_all(&work);
    let roll = -9.0;
    let t = Instant::now();
    let opts = options(&work, EdgeVariants::With);
    let ltca = LtcaCycle::new(&sc, &opts).unwrap();
    let r = ltca.solve(roll).unwrap();
    let t_ltca = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let mesh = bevel_sector_options(&sc, &opts.mesh).unwrap();
    let fe = MeshCycle::of_pair(
        &sc,
        bevel_pair_model(&sc, &mesh).unwrap(),
        RunSettings::default_for(&sc),
        2,
    )
    .unwrap();
    let s = fe.solve(r.roll_deg).unwrap().step;
    let tip = s.pinion_tip_edge.clone().unwrap();
    let t_fe = t.elapsed().as_secs_f64();
    assert!(r.kkt_within_tolerance, "KKT {}", r.kkt_max);
    let forces = ltca.pair_forces(&r);
    let total: f64 = forces.iter().sum();
    let mut worst: f64 = 0.0;
    println!(
        "roll {:.3}°: LTCA with edges {t_ltca:.1} s, FE contact {t_fe:.1} s",
        r.roll_deg
    );
    println!("| pair | lines (LTCA) | share LTCA | share FE | FE tip edge | force LTCA (N) | force FE (N) |");
    for (p, &x) in forces.iter().enumerate() {
        let kinds: Vec<&str> = r
            .lines
            .iter()
            .zip(&r.line_force_n)
            .filter(|((k, _, _), f)| *k == p + 1 && **f > 0.0)
            .map(|((_, _, kind), _)| kind.as_str())
            .collect();
        let share = x / total;
        worst = worst.max((share - s.load_share[p]).abs());
        println!(
            "| {} | {} | {share:.4} | {:.4} | {} | {x:.0} | {:.0} |",
            p + 1,
            kinds.join("+"),
            s.load_share[p],
            tip[p],
            s.pair_force_n[p]
        );
    }
    let te = ltca.te_arcsec(&r);
    let d = (te - s.te_arcsec).abs() / s.te_arcsec.abs();
    println!(
        "VERIFY ltca_edges FE {:+.3}°: shares {worst:.4} (tol {TOL_FE_SHARE}), TE {te:.2}″ vs FE {:.2}″: {d:.4} (tol {TOL_FE_TE}), FE tip edge of pairs 4/5: {}/{}",
        r.roll_deg, s.te_arcsec, tip[3], tip[4]
    );
    assert!(tip[3] && tip[4], "FE: no tip-edge contact of pair 4 or 5");
    assert!(worst <= TOL_FE_SHARE, "shares {worst}");
    assert!(d <= TOL_FE_TE, "TE {d}");
}
