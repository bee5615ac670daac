//! Design-space sweep: a seeded sample of ordinary spur and helical designs,
//! each through `flank check` and a coarse `flank ltca` as a user runs them.
//! Every design either runs and reports its loaded contact ratio, its
//! single-pair force check (where a single-pair zone exists) and its KKT
//! residual, or is refused at `flank check` with a geometric reason at the
//! key that causes it. See README.md for the sample, the figures and how to
//! rerun it.

#[path = "design.rs"]
mod design;

use design::{Design, Modification};
use std::path::{Path, PathBuf};
use std::process::Command;

/// Seed of the sample in CI (the README's figures are of this seed).
const SEED: u64 = 56;
/// Designs in CI (issue 56: at least 40).
const CI_DESIGNS: usize = 40;

/// A KKT residual above this is a failed LTCA position (the QP is solved to
/// round-off: 1e-15 on every paper scene; bound set before the sweep).
const KKT_BOUND: f64 = 1e-9;
/// Where only the middle pair is loaded its force is T/(r_b1 cos β_b) by
/// statics, whatever the mesh (bound set before the sweep).
const SINGLE_PAIR_BOUND: f64 = 1e-6;
/// Plausibility band of the mean mesh stiffness against ISO 6336-1's c_γα
/// (DESIGN.md rung 5, as verification/gear_stiffness; set before the sweep).
const STIFFNESS_BAND: [f64; 2] = [0.5, 2.0];

/// What happened to one design.
#[derive(Debug)]
enum Outcome {
    /// `flank check` refused it: the message and the key it names.
    Refused { key: String, message: String },
    /// `flank ltca` ran.
    Ran(LtcaFigures),
}

#[derive(Debug)]
struct LtcaFigures {
    teeth_in_sector: u64,
    total_contact_ratio: f64,
    kinematic_contact_ratio: f64,
    loaded_contact_ratio: Option<f64>,
    single_pair_force_error: Option<f64>,
    max_kkt: f64,
    positions: u64,
    pressure_over_nominal: f64,
    /// The LTCA's mean mesh stiffness per unit face width over ISO 6336-1's
    /// c_γα (verification/gear_stiffness), where both are measured.
    /// Where not: which of the two is missing.
    stiffness_over_iso: Result<f64, &'static str>,
    seconds: f64,
}

fn flank(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_flank"))
        .args(args)
        .env("RAYON_NUM_THREADS", "2")
        .output()
        .expect("flank binary");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into(),
        String::from_utf8_lossy(&out.stderr).into(),
    )
}

/// No figure on the console or in a table is NaN or infinite (issue 56: a
/// figure that cannot be measured is said so in words).
fn assert_no_non_finite(what: &str, text: &str) {
    for token in text.split(|c: char| c.is_whitespace() || ",;:()[]{}\"=".contains(c)) {
        let t = token.trim_start_matches(['+', '-']).to_ascii_lowercase();
        assert!(
            t != "nan" && t != "inf" && t != "infinity",
            "{what} holds the non-finite figure {token:?}:\n{text}"
        );
    }
}

fn number(v: &serde_json::Value, key: &str) -> f64 {
    v[key]
        .as_f64()
        .unwrap_or_else(|| panic!("summary has no number {key}: {v}"))
}

/// Words by which a check refusal states a geometric reason.
const GEOMETRIC_REASONS: [&str; 9] = [
    "undercut",
    "pointed",
    "interference",
    "contact ratio",
    "clearance",
    "root circle",
    "does not fit",
    "base circle",
    "tip",
];

fn run_design(d: &Design, dir: &Path) -> Outcome {
    std::fs::create_dir_all(dir).unwrap();
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, d.scene_toml()).unwrap();
    let scene_arg = scene.to_str().unwrap();
    let (ok, out, err) = flank(&["check", scene_arg]);
    assert_no_non_finite("flank check's output", &out);
    if !ok {
        // file:line: message, naming the key as table.key
        let message = err.trim().to_string();
        let prefix = format!("{scene_arg}:");
        assert!(
            message.contains(&prefix),
            "design {d:?}: the refusal does not name the scene's line:\n{message}"
        );
        let key = ["pair.centre_distance_mm", "pinion.", "gear."]
            .iter()
            .find_map(|k| {
                message
                    .split(|c: char| c.is_whitespace() || ":,`()".contains(c))
                    .find(|w| w.starts_with(k))
                    .map(str::to_string)
            })
            .unwrap_or_else(|| panic!("design {d:?}: the refusal names no key:\n{message}"));
        let lower = message.to_lowercase();
        assert!(
            GEOMETRIC_REASONS.iter().any(|r| lower.contains(r)),
            "design {d:?}: the refusal states no geometric reason:\n{message}"
        );
        return Outcome::Refused { key, message };
    }
    let check: serde_json::Value = serde_json::from_str(&out).expect("check JSON");
    let teeth_in_sector = check["sector"]["teeth"].as_u64().expect("sector teeth");
    let out_dir = dir.join("ltca");
    let t0 = std::time::Instant::now();
    let (ok, stdout, stderr) = flank(&[
        "ltca",
        scene_arg,
        "--out",
        out_dir.to_str().unwrap(),
        "--quiet",
    ]);
    let seconds = t0.elapsed().as_secs_f64();
    assert!(ok, "design {d:?}: flank ltca failed:\n{stderr}");
    assert_no_non_finite("flank ltca's console", &stdout);
    assert_no_non_finite("flank ltca's console", &stderr);
    for table in ["ltca_cycle.csv", "ltca_positions.csv"] {
        let text = std::fs::read_to_string(out_dir.join(table)).unwrap();
        assert_no_non_finite(table, &text);
    }
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out_dir.join("summary.json")).unwrap())
            .unwrap();
    let max_kkt = number(&s, "max_kkt");
    assert!(
        max_kkt <= KKT_BOUND,
        "design {d:?}: KKT residual {max_kkt:e}"
    );
    assert!(
        s["kkt_flagged"].as_array().is_some_and(|a| a.is_empty()),
        "design {d:?}: flagged positions {}",
        s["kkt_flagged"]
    );
    let loaded_contact_ratio = s["contact_ratio"].as_f64();
    assert!(
        loaded_contact_ratio.is_some(),
        "design {d:?}: no loaded contact ratio ({})",
        s["notes"]
    );
    let single_pair_force_error = s["single_pair_force_error"].as_f64();
    if let Some(e) = single_pair_force_error {
        assert!(
            e.abs() <= SINGLE_PAIR_BOUND,
            "design {d:?}: single-pair force off by {e:e}"
        );
    }
    let nominal = d.nominal_contact_stress_mpa();
    let stiffness_over_iso = match (
        s["torque_map"]["torques"][0]["mesh_stiffness"]["mean_n_per_mm_um"].as_f64(),
        check["iso6336_stiffness_n_per_mm_um"]["mesh"].as_f64(),
    ) {
        (Some(k), Some(c)) => Ok(k / c),
        (None, _) => Err("LTCA stiffness not measured"),
        (_, None) => Err("ISO 6336-1 not applicable"),
    };
    if let Ok(r) = stiffness_over_iso {
        assert!(
            (STIFFNESS_BAND[0]..=STIFFNESS_BAND[1]).contains(&r),
            "design {d:?}: mean mesh stiffness {r:.3} × ISO 6336-1's c_γα"
        );
    }
    Outcome::Ran(LtcaFigures {
        teeth_in_sector,
        total_contact_ratio: number(&check, "total_contact_ratio"),
        kinematic_contact_ratio: number(&s, "contact_ratio_kinematic"),
        loaded_contact_ratio,
        single_pair_force_error,
        max_kkt,
        positions: s["positions"].as_u64().unwrap(),
        pressure_over_nominal: number(&s, "max_pressure_mpa") / nominal,
        stiffness_over_iso,
        seconds,
    })
}

/// Runs a sample, prints its table and writes it as CSV; returns the
/// outcomes.
fn sweep(seed: u64, n: usize, name: &str) -> Vec<(Design, Outcome)> {
    let root = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&root);
    let designs = design::sample(seed, n);
    let mut rows = vec![format!(
        "design,kind,z1,z2,m_n_mm,alpha_n_deg,beta_deg,b_mm,x1,x2,modification,outcome,key,teeth_in_sector,eps_gamma,eps_alpha,loaded_contact_ratio,single_pair_force_error,max_kkt,positions,p_max_over_nominal,k_over_c_gamma_alpha,ltca_s"
    )];
    let mut outcomes = Vec::new();
    for (i, d) in designs.into_iter().enumerate() {
        let o = run_design(&d, &root.join(format!("design_{i:03}")));
        let head = format!(
            "{i},{},{},{},{:.3},{:.2},{:.2},{:.2},{:.4},{:.4},{}",
            if d.helix_angle_deg == 0.0 {
                "spur"
            } else {
                "helical"
            },
            d.z1,
            d.z2,
            d.normal_module_mm,
            d.pressure_angle_deg,
            d.helix_angle_deg,
            d.face_width_mm,
            d.x1,
            d.x2,
            d.modification.label()
        );
        let row = match &o {
            Outcome::Refused { key, .. } => format!("{head},refused,{key},,,,,,,,,,"),
            Outcome::Ran(f) => format!(
                "{head},ran,,{},{:.3},{:.3},{},{},{:.1e},{},{:.2},{},{:.1}",
                f.teeth_in_sector,
                f.total_contact_ratio,
                f.kinematic_contact_ratio,
                f.loaded_contact_ratio
                    .map_or("not measured".into(), |c| format!("{c:.3}")),
                f.single_pair_force_error
                    .map_or("no single-pair zone".into(), |e| format!("{e:.1e}")),
                f.max_kkt,
                f.positions,
                f.pressure_over_nominal,
                match f.stiffness_over_iso {
                    Ok(k) => format!("{k:.3}"),
                    Err(why) => why.to_string(),
                },
                f.seconds
            ),
        };
        println!("{row}");
        if let Outcome::Refused { message, .. } = &o {
            println!("    refused: {message}");
        }
        rows.push(row);
        outcomes.push((d, o));
    }
    std::fs::write(root.join("sweep.csv"), rows.join("\n") + "\n").unwrap();
    let ran = outcomes
        .iter()
        .filter(|(_, o)| matches!(o, Outcome::Ran(_)))
        .count();
    println!(
        "{name}: {} designs, {ran} ran, {} refused at flank check; table {}",
        outcomes.len(),
        outcomes.len() - ran,
        root.join("sweep.csv").display()
    );
    outcomes
}

/// The CI sample: 40 designs; both kinds and every modification kind must
/// have run for the sweep to say anything about them.
#[test]
fn forty_designs_run_or_are_refused_with_their_reason() {
    let outcomes = sweep(SEED, CI_DESIGNS, "design_sweep_ci");
    let ran = |f: &dyn Fn(&Design) -> bool| {
        outcomes
            .iter()
            .filter(|(d, o)| f(d) && matches!(o, Outcome::Ran(_)))
            .count()
    };
    assert!(ran(&|d| d.helix_angle_deg == 0.0) > 0, "no spur design ran");
    assert!(
        ran(&|d| d.helix_angle_deg > 0.0) > 0,
        "no helical design ran"
    );
    assert!(
        ran(&|d| matches!(d.modification, Modification::TipRelief { .. })) > 0,
        "no tip-relieved design ran"
    );
    assert!(
        ran(&|d| matches!(d.modification, Modification::LeadCrowning { .. })) > 0,
        "no lead-crowned design ran"
    );
}

/// Designs with an undercut or pointed member on purpose: `flank check`
/// refuses every one at the member's `profile_shift` with the reason.
#[test]
fn flawed_designs_are_refused_at_the_shift_with_their_reason() {
    let root = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("design_sweep_flawed");
    let _ = std::fs::remove_dir_all(&root);
    let flawed = design::flawed(SEED, 12);
    assert!(flawed.len() >= 8, "only {} flawed designs", flawed.len());
    for (i, (d, flaw, member)) in flawed.iter().enumerate() {
        match run_design(d, &root.join(format!("design_{i:03}"))) {
            Outcome::Refused { key, message } => {
                println!("{flaw:?} {member}: refused at {key}: {message}");
                assert_eq!(key, format!("{member}.profile_shift"), "{message}");
                let reason = match flaw {
                    design::Flaw::Undercut => "undercut",
                    design::Flaw::PointedTip => "pointed tip",
                };
                assert!(message.contains(reason), "{flaw:?}: {message}");
            }
            Outcome::Ran(_) => panic!("{flaw:?} {member} design {d:?} was not refused"),
        }
    }
}

/// A larger sample of another seed (200 designs).
#[test]
#[ignore = "200 coarse LTCAs: about 25 min on 2 cores (the 40 of CI take 3 min)"]
fn two_hundred_designs_run_or_are_refused_with_their_reason() {
    sweep(SEED + 1, 200, "design_sweep_large");
}

/// FE contact (`flank run`) on the first two spur and the first helical
/// design of the CI sample that pass `flank check`, on a coarse FE mesh
/// (flank m_n/4, base m_n, a quarter-pitch step): it runs with its loaded
/// contact ratio and single-pair force check reported, beside the LTCA's.
#[test]
#[ignore = "three coarse FE contact cycles: about 2 min on 2 cores"]
fn fe_contact_runs_on_three_designs() {
    let root = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("design_sweep_fe");
    let _ = std::fs::remove_dir_all(&root);
    let mut picked = Vec::new();
    for (i, d) in design::sample(SEED, CI_DESIGNS).into_iter().enumerate() {
        let spur = d.helix_angle_deg == 0.0;
        let wanted = if spur { 2 } else { 1 };
        if picked
            .iter()
            .filter(|(_, p): &&(usize, Design)| (p.helix_angle_deg == 0.0) == spur)
            .count()
            >= wanted
        {
            continue;
        }
        let dir = root.join(format!("design_{i:03}"));
        std::fs::create_dir_all(&dir).unwrap();
        let scene = dir.join("scene.toml");
        std::fs::write(&scene, d.scene_toml()).unwrap();
        if flank(&["check", scene.to_str().unwrap()]).0 {
            picked.push((i, d));
        }
        if picked.len() == 3 {
            break;
        }
    }
    assert_eq!(picked.len(), 3, "the sample has too few designs that check");
    for (i, d) in picked {
        let dir = root.join(format!("design_{i:03}"));
        let m = d.normal_module_mm;
        let scene = dir.join("scene_fe.toml");
        std::fs::write(
            &scene,
            format!(
                "{}contact = {{ roll_step_deg = {:.6}, vtu = false, refine_contact_limits = false }}\n\n[mesh]\nflank_size_mm = {}\nbase_size_mm = {}\n",
                d.scene_toml(),
                360.0 / d.z1 as f64 / 4.0,
                0.25 * m,
                m
            ),
        )
        .unwrap();
        let out = dir.join("run");
        let (ok, stdout, stderr) = flank(&[
            "run",
            scene.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
            "--quiet",
        ]);
        assert!(ok, "design {i}: flank run failed:\n{stderr}");
        assert_no_non_finite("flank run's console", &stdout);
        let s: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap())
                .unwrap();
        let eps = s["contact_ratio"].as_f64();
        assert!(
            eps.is_some(),
            "design {i}: no loaded contact ratio: {}",
            s["notes"]
        );
        println!(
            "design {i}: FE loaded contact ratio {:.3}, single-pair force error {}, {} positions, {:.0} s",
            eps.unwrap(),
            s["single_pair_force_error"],
            s["positions"],
            number(&s, "total_s")
        );
    }
}
