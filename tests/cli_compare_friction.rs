//! `flank compare --friction-mu` on a hypoid scene (issue 19: LTCA against
//! FE contact with friction; seed 003 eased, coarse 3 mm / 8 mm bodies,
//! three positions): both methods take the μ, the tangential force is
//! compared, friction lowers the total normal force in both, bad μ is a
//! clear error naming the flag.

mod common;

use common::cli::flank;
use std::path::PathBuf;

fn dir(name: &str) -> PathBuf {
    common::cli::scratch_dir("cli_compare_friction", name)
}

/// The coarse hypoid comparison at μ (`None`: without the flag).
fn compare(name: &str, mu: Option<&str>) -> serde_json::Value {
    let d = dir(name);
    let mut args = vec![
        "compare",
        "papers/seed003-hypoid/scene_eased.toml",
        "--flank-size",
        "3",
        "--base-size",
        "8",
        "--fe-base-size",
        "8",
        "--fe-flank-sizes",
        "3",
        "--points-per-line",
        "11",
        "--roll-angles=-8.182,0,8.182",
        "--threads",
        "1",
        "--out",
        d.to_str().unwrap(),
    ];
    if let Some(m) = mu {
        args.extend(["--friction-mu", m]);
    }
    let (ok, out, err) = flank(&args);
    assert!(ok, "{out}\n{err}");
    if mu.is_some() {
        assert!(out.contains("friction μ = 0.07: tangential force"), "{out}");
        let md = std::fs::read_to_string(d.join("compare.md")).unwrap();
        assert!(md.contains("## Friction (μ = 0.07)"), "{md}");
    }
    serde_json::from_str(&std::fs::read_to_string(d.join("compare.json")).unwrap()).unwrap()
}

/// Per run (FE first, then LTCA): per position Σ P_n and Σ P_t.
fn totals(s: &serde_json::Value) -> Vec<(String, Vec<(f64, f64)>)> {
    let sum = |v: &serde_json::Value| -> f64 {
        v.as_array()
            .map(|a| a.iter().map(|x| x.as_f64().unwrap()).sum())
            .unwrap_or(0.0)
    };
    s["runs"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| {
            let n = r["pair_force_n"].as_array().unwrap();
            let t = r["pair_tangential_n"].as_array().unwrap();
            (
                r["method"].as_str().unwrap().to_string(),
                n.iter().zip(t).map(|(n, t)| (sum(n), sum(t))).collect(),
            )
        })
        .collect()
}

/// μ = 0.07 against μ = 0: every loaded point of this hypoid flank slips
/// (seed 003 README), so in both methods Σ P_t / Σ P_n is μ (FE's
/// resultant a little below: its nodes' slip directions differ) and the
/// total normal force falls (friction carries part of the pinion torque);
/// the tangential force error is finite and small, and absent without
/// friction.
#[test]
fn hypoid_compare_with_friction() {
    let dry = compare("dry", None);
    let wet = compare("wet", Some("0.07"));
    assert_eq!(dry["friction_mu"].as_f64(), Some(0.0));
    assert!(dry["tangential_force_rel_err"].is_null(), "{dry}");
    assert_eq!(wet["friction_mu"].as_f64(), Some(0.07));
    assert_eq!(wet["ltca_friction_model"], "incremental");
    for key in [
        "load_sharing_rel_err",
        "te_rel_err",
        "pmax_rel_err",
        "tangential_force_rel_err",
        "ltca_cycle_s",
        "fe_cycle_s",
    ] {
        assert!(
            wet[key].as_f64().is_some_and(f64::is_finite),
            "{key}: {wet}"
        );
    }
    // the tangential forces are ≈ 7 % of the normal ones, so an error of
    // 0.01 of the total normal force would be a 14 % miss
    let e = wet["tangential_force_rel_err"].as_f64().unwrap();
    assert!(e < 0.01, "tangential force error {e}");
    let (d, w) = (totals(&dry), totals(&wet));
    assert_eq!(w.len(), 2);
    let mut drops = Vec::new();
    for ((method, dry), (_, wet)) in d.iter().zip(&w) {
        for (i, (&(n0, t0), &(n, t))) in dry.iter().zip(wet).enumerate() {
            assert_eq!(t0, 0.0, "{method}: friction without μ");
            let ratio = t / n;
            assert!(
                (0.065..=0.07 + 1e-9).contains(&ratio),
                "{method} position {i}: P_t/P_n {ratio}"
            );
            let drop = 1.0 - n / n0;
            assert!(
                (0.05..0.13).contains(&drop),
                "{method} position {i}: Σ P_n {n0} → {n} ({:.2} %)",
                100.0 * drop
            );
            drops.push(drop);
        }
    }
    // the two methods agree on what friction does (≈ 9 % each at 2 mm,
    // verification/ltca_hypoid): within one point of the drop per position
    let (fe, ltca) = drops.split_at(3);
    for (a, b) in fe.iter().zip(ltca) {
        assert!((a - b).abs() < 0.01, "Σ P_n drop FE {a} vs LTCA {b}");
    }
}

/// A μ outside [0, 1] or not a number is refused before anything runs,
/// naming the flag; `--increments` without friction is refused.
#[test]
fn compare_refuses_bad_friction() {
    for mu in ["-0.1", "1.5", "NaN"] {
        let d = dir("bad");
        let (ok, _, err) = flank(&[
            "compare",
            "papers/seed003-hypoid/scene_eased.toml",
            &format!("--friction-mu={mu}"),
            "--out",
            d.to_str().unwrap(),
        ]);
        assert!(
            !ok && err.contains(&format!("--friction-mu {mu}: a coefficient in [0, 1]")),
            "{mu}: {err}"
        );
        assert!(!d.exists(), "nothing written for μ = {mu}");
    }
    let (ok, _, err) = flank(&[
        "compare",
        "papers/seed003-hypoid/scene_eased.toml",
        "--increments",
        "5",
    ]);
    assert!(!ok && err.contains("--increments"), "{err}");
    let (ok, _, err) = flank(&[
        "compare",
        "papers/seed002-spur/scene.toml",
        "--friction-mu=-1",
    ]);
    assert!(!ok && err.contains("--friction-mu -1"), "{err}");
}
