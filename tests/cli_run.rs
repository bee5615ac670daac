//! `flank run SCENE.toml`: the FE contact mesh cycle from the command line
//! (seed 002 scene on a coarse mesh at two roll angles), its files and
//! summary keys; a scene without `[analyses] contact` and a bad option are
//! clear errors.

mod common;

use common::cli::flank;

#[test]
fn run_writes_the_mesh_cycle_files() {
    let dir = std::env::temp_dir().join(format!("flank_cli_run_{}", std::process::id()));
    let d = dir.to_str().unwrap();
    let (ok, out, err) = flank(&[
        "run",
        "papers/seed002-spur/scene.toml",
        "--flank-size",
        "1.5",
        "--base-size",
        "3",
        "--roll-angles=-6,6",
        "--decks",
        "--out",
        d,
    ]);
    assert!(ok, "{err}");
    assert!(out.contains("single-pair force"), "{out}");
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    for key in [
        "contact_ratio",
        "single_pair_force_n",
        "positions",
        "time_per_position_s",
        "nodes",
    ] {
        assert!(s.get(key).is_some(), "summary.json lacks {key}");
    }
    assert_eq!(s["positions"].as_u64(), Some(2));
    // two positions cannot bracket the engagement: no contact ratio, said so
    assert!(s["contact_ratio"].is_null());
    assert!(s["notes"]
        .as_array()
        .unwrap()
        .iter()
        .any(|n| n.as_str().unwrap().contains("contact ratio not measured")));
    let f = s["single_pair_force_n"].as_f64().unwrap();
    let nominal = s["nominal_force_n"].as_f64().unwrap();
    assert!((f / nominal - 1.0).abs() < 0.03, "{f} vs {nominal}");
    // the active set of each position is tallied; its limit is an error,
    // so no call stopped there
    let active = &s["iteration_limits"]["contact.active_set"];
    assert_eq!(active["calls"].as_u64(), Some(2), "{active}");
    assert_eq!(active["limit_hits"].as_u64(), Some(0), "{active}");
    assert!(active["most_iterations"].as_u64().unwrap() >= 1);
    assert_same_files_as_every_kind(&dir, &s, "spur");
    for file in [
        "mesh_cycle.csv",
        "force_per_tooth.svg",
        "transmission_error.png",
        "roll_-006.000deg.vtu",
        "roll_+006.000deg.vtu",
        "roll_+006.000deg.inp",
    ] {
        assert!(dir.join(file).exists(), "{file} missing");
    }
    // the position deck reads back with its coupling and three contact pairs
    let deck = flank::deck::read_deck(&dir.join("roll_+006.000deg.inp")).unwrap();
    assert_eq!(deck.model.couplings.len(), 1);
    assert_eq!(deck.model.contact.pairs.len(), 3);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn run_needs_a_contact_analysis_and_valid_options() {
    let dir = std::env::temp_dir().join(format!("flank_cli_run_bad_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/papers/seed002-spur/scene.toml"
    ))
    .unwrap();
    let no_contact = dir.join("no_contact.toml");
    std::fs::write(
        &no_contact,
        scene
            .lines()
            .filter(|l| !l.starts_with("contact ="))
            .collect::<Vec<_>>()
            .join("\n"),
    )
    .unwrap();
    let (ok, _, err) = flank(&[
        "run",
        no_contact.to_str().unwrap(),
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(!ok);
    assert!(err.contains("contact = {}"), "{err}");
    let (ok, _, err) = flank(&[
        "run",
        "papers/seed002-spur/scene.toml",
        "--penalty-factor=-1",
        "--law",
        "penalty",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(!ok);
    assert!(err.contains("penalty factor"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The wet–dry loop of seed 002 (`[analyses.lubrication]`) on a coarse
/// mesh at five positions: it converges within its bound, μ stays below
/// the paper's 0.05, every logged μ and h_c is what the EHL formulas give
/// for the logged operating point, and the wet pass's FE friction forces
/// respect the per-pair μ it was solved with.
#[test]
fn run_lubricated_loop_converges() {
    use flank::lubrication::{evaluate, FilmModel, OperatingPoint};
    let dir = std::env::temp_dir().join(format!("flank_cli_run_lub_{}", std::process::id()));
    let d = dir.to_str().unwrap();
    let scene_path = "papers/seed002-spur/scene_lubricated.toml";
    let (ok, stdout, err) = flank(&[
        "run",
        scene_path,
        "--flank-size",
        "1.5",
        "--base-size",
        "3",
        "--roll-angles=-8,-4,0,4,8",
        "--no-vtu",
        "--out",
        d,
    ]);
    assert!(ok, "{err}");
    assert!(
        stdout.contains("lubrication: ") && stdout.contains("converged"),
        "{stdout}"
    );
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    let l = &s["lubrication"];
    // the dry → wet change of the largest subsurface shear (seed 002
    // Fig. 10: +2.51 % / −1.09 %): finite and small, the two signs in order
    let (hi, lo) = (
        l["subsurface_change_max_pct"].as_f64().unwrap(),
        l["subsurface_change_min_pct"].as_f64().unwrap(),
    );
    assert!(lo <= hi && hi.abs() < 5.0 && lo.abs() < 5.0, "{lo} … {hi}");
    for key in [
        "iterations",
        "mu_max",
        "mu_last_change_rel",
        "power_loss_w",
        "efficiency",
    ] {
        assert!(l.get(key).is_some(), "lubrication lacks {key}");
    }
    assert_eq!(l["converged"], true, "{l}");
    let iterations = l["iterations"].as_u64().unwrap();
    assert!((1..=10).contains(&iterations), "{iterations}");
    assert!(l["mu_last_change_rel"].as_f64().unwrap().abs() < 0.005);
    let mu_max = l["mu_max"].as_f64().unwrap();
    assert!(mu_max > 0.0 && mu_max < 0.05, "{mu_max}");
    let eff = l["efficiency"].as_f64().unwrap();
    assert!(eff > 0.9 && eff < 1.0, "{eff}");
    assert_eq!(l["passes"].as_array().unwrap().len() as u64, iterations + 1);

    // every logged μ and h_c from the logged operating point
    let scene = flank::scene::read_scene(
        &std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(scene_path),
    )
    .unwrap();
    let lub = scene.lubricant.unwrap();
    let e_prime = l["reduced_modulus_mpa"].as_f64().unwrap();
    let length = l["contact_length_mm"].as_f64().unwrap();
    let csv = std::fs::read_to_string(dir.join("lubrication.csv")).unwrap();
    let mut rows = 0;
    let mut wet_mu = std::collections::HashMap::new();
    for line in csv.lines().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        let x = |i: usize| f[i].parse::<f64>().unwrap();
        let (load, p) = (x(2), x(3));
        let point = OperatingPoint {
            load_n: load,
            contact_area_mm2: load / p,
            mean_pressure_mpa: p,
            other_mean_pressure_mpa: x(4),
            radius_x_mm: x(5),
            radius_y_mm: if f[6] == "line" { f64::INFINITY } else { x(6) },
            length_mm: length,
            entraining_speed_mm_s: x(7) * 1e3,
            sliding_speed_mm_s: x(8) * 1e3,
            reduced_modulus_mpa: e_prime,
            outside_path: f[18].contains("OutsidePath"),
            hertz_peak_mpa: 0.0,
        };
        let c = evaluate(&lub, FilmModel::Chittenden, &point, None).unwrap();
        let rel = |a: f64, b: f64| (a / b - 1.0).abs();
        assert!(rel(c.film.central * 1e3, x(10)) < 1e-9, "{line}");
        assert!(rel(c.traction.mu, x(14)) < 1e-9, "{line}");
        assert!(
            rel(c.power_loss_w.max(1e-300), x(17).max(1e-300)) < 1e-9,
            "{line}"
        );
        wet_mu.insert((f[0].to_string(), f[1].to_string()), x(14));
        rows += 1;
    }
    assert!(rows >= 5, "{rows} loaded contacts");

    // the last wet pass was solved with per-pair μ: its FE friction force
    // per pair is inside that pair's Coulomb cone, μ_used · W
    let passes = std::fs::read_to_string(dir.join("lubrication_passes.csv")).unwrap();
    let last = iterations.to_string();
    let mut used = std::collections::HashMap::new();
    for line in passes.lines().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        if f[0] == last {
            used.insert(
                (f[1].to_string(), f[2].to_string()),
                f[3].parse::<f64>().unwrap(),
            );
        }
    }
    // μ used in the last pass = μ_EHL of the pass before, within the tolerance of μ_EHL now
    for (k, mu) in &used {
        let now = wet_mu[k];
        assert!((now / mu - 1.0).abs() < 0.005, "{k:?}: {mu} vs {now}");
    }
    let cycle = std::fs::read_to_string(dir.join("mesh_cycle.csv")).unwrap();
    let mut lines = cycle.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| head.iter().position(|h| *h == name).unwrap();
    let mut checked = 0;
    for line in lines {
        let f: Vec<&str> = line.split(',').collect();
        for p in 1..=3 {
            let key = (f[0].to_string(), p.to_string());
            let Some(mu) = used.get(&key) else { continue };
            let w: f64 = f[col(&format!("force_pair{p}_n"))].parse().unwrap();
            let t: f64 = f[col(&format!("friction_pair{p}_n"))].parse().unwrap();
            assert!(
                t <= mu * w * (1.0 + 1e-6) + 1e-6,
                "{key:?}: {t} > {mu} × {w}"
            );
            checked += 1;
        }
    }
    assert!(checked >= 5);
    // the friction fixed point of each position of the final pass is
    // tallied; its hits are exactly the positions flagged not converged
    let fixed_point = &s["iteration_limits"]["contact.friction_fixed_point"];
    let steps = s["steps"].as_array().unwrap();
    assert_eq!(
        fixed_point["calls"].as_u64(),
        Some(steps.len() as u64),
        "{fixed_point}"
    );
    let flagged = steps
        .iter()
        .filter(|p| p["friction_converged"] == serde_json::json!(false))
        .count() as u64;
    assert_eq!(
        fixed_point["limit_hits"].as_u64(),
        Some(flagged),
        "{fixed_point}"
    );
    for file in [
        "lubrication_mu.svg",
        "lubrication_film.png",
        "lubrication_power_loss.svg",
    ] {
        assert!(dir.join(file).exists(), "{file} missing");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `flank run` on a hypoid scene (seed 003 with the eased pinion; the
/// milled one is refused, its flanks cross; coarse, three roll angles):
/// positions.csv and summary.json; per position the contact forces balance
/// the torque about the pinion axis and the shares add to 1.
#[test]
fn seed003_hypoid_run_writes_balanced_positions() {
    let out = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("cli_run_seed003");
    let _ = std::fs::remove_dir_all(&out);
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_flank"))
        .args([
            "run",
            "papers/seed003-hypoid/scene_eased.toml",
            "--flank-size",
            "2",
            "--base-size",
            "8",
            "--roll-angles",
            "-10,0,10",
            "--threads",
            "2",
            "--quiet",
            "--out",
        ])
        .arg(&out)
        .status()
        .unwrap();
    assert!(status.success());
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(s["positions"], 3);
    assert!(s["max_moment_balance"].as_f64().unwrap() < 1e-9);
    // three chosen angles are no cycle: no functional contact ratio
    assert!(s["functional_contact_ratio"].is_null() && s["load_sharing"].is_null());
    for st in s["steps"].as_array().unwrap() {
        let shares: f64 = st["load_share"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .sum();
        assert!((shares - 1.0).abs() < 1e-12, "{shares}");
        assert!(st["te_arcsec"].as_f64().unwrap().is_finite());
    }
    let csv = std::fs::read_to_string(out.join("positions.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + 3 * 3);
    assert_same_files_as_every_kind(&out, &s, "hypoid");
    // the contact pattern: one row per loaded node and position, plotted
    // on both members
    let closed: u64 = s["steps"]
        .as_array()
        .unwrap()
        .iter()
        .flat_map(|st| st["patch"].as_array().unwrap().iter())
        .map(|p| p["closed_nodes"].as_u64().unwrap())
        .sum();
    let pattern = std::fs::read_to_string(out.join("contact_pattern.csv")).unwrap();
    assert!(closed > 0);
    assert_eq!(pattern.lines().count() as u64, 1 + closed);
    for f in s["plots"].as_array().unwrap() {
        assert!(out.join(f.as_str().unwrap()).exists(), "{f}");
    }
    assert_eq!(s["plots"].as_array().unwrap().len(), 4);
}

/// `flank run --friction-mu` on a hypoid scene (seed 003 eased, coarse,
/// roll 0): the Coulomb law met, the contact forces (normal and friction)
/// balance the torque about the pinion axis, every pair's friction force
/// at most μ times its normal force, and friction changes the answer.
#[test]
fn seed003_hypoid_run_with_friction_balances() {
    let run = |name: &str, extra: &[&str]| -> serde_json::Value {
        let out = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
        let _ = std::fs::remove_dir_all(&out);
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_flank"))
            .args([
                "run",
                "papers/seed003-hypoid/scene_eased.toml",
                "--flank-size",
                "2",
                "--base-size",
                "8",
                "--roll-angles=0",
                "--threads",
                "2",
                "--quiet",
            ])
            .args(extra)
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap()
    };
    let dry = run("cli_run_seed003_mu0", &[]);
    let s = run("cli_run_seed003_mu", &["--friction-mu", "0.07"]);
    assert_eq!(s["friction_mu"], 0.07);
    assert_eq!(s["friction_not_converged"], 0);
    let balance = s["max_moment_balance"].as_f64().unwrap();
    let coulomb = s["max_coulomb_residual"].as_f64().unwrap();
    let (st, st0) = (&s["steps"][0], &dry["steps"][0]);
    let floats = |v: &serde_json::Value| -> Vec<f64> {
        v.as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect()
    };
    let (normal, friction, normal0) = (
        floats(&st["pair_force_n"]),
        floats(&st["friction_force_n"]),
        floats(&st0["pair_force_n"]),
    );
    eprintln!(
        "hypoid FE with friction 0.07 at roll 0: normal {normal:?} (frictionless {normal0:?}), friction {friction:?}, TE {} (frictionless {}), moment balance {balance:.1e}, Coulomb residual {coulomb:.1e}, stick/slip {}/{}",
        st["te_arcsec"], st0["te_arcsec"], st["stick_nodes"], st["slip_nodes"]
    );
    assert!(balance < 1e-8, "{balance}");
    for (f, n) in friction.iter().zip(&normal) {
        assert!(*f <= 0.07 * n * (1.0 + 1e-9) + 1e-9, "{f} > μ {n}");
    }
    let total_f: f64 = friction.iter().sum();
    assert!(total_f > 1e-3 * normal.iter().sum::<f64>(), "{total_f}");
    let moved = normal
        .iter()
        .zip(&normal0)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(
        moved > 1.0,
        "friction changed no pair force by 1 N ({moved})"
    );
}

/// The files every pair kind writes with the same columns (3 tooth pairs
/// in both the spur and the hypoid run here): `mesh_cycle.csv` and
/// `positions.csv` have the header of the one writer
/// (`flank::mesh_cycle::outputs`), so a spur and a hypoid run have the same
/// headers; every row is as wide as its header; the summary gives its
/// schema version, the pair kind and the TE peak-to-peak in both forms.
fn assert_same_files_as_every_kind(dir: &std::path::Path, s: &serde_json::Value, kind: &str) {
    use flank::mesh_cycle::outputs::{mesh_cycle_header, POSITIONS_HEADER};
    for (file, header) in [
        ("mesh_cycle.csv", mesh_cycle_header(3)),
        ("positions.csv", POSITIONS_HEADER.to_string()),
    ] {
        let text = std::fs::read_to_string(dir.join(file)).unwrap();
        let mut lines = text.lines();
        assert_eq!(lines.next(), Some(header.as_str()), "{file}");
        let n = header.split(',').count();
        for l in lines {
            assert_eq!(l.split(',').count(), n, "{file}: {l}");
        }
    }
    assert_eq!(
        s["schema_version"].as_u64(),
        Some(flank::mesh_cycle::summary::SCHEMA_VERSION as u64)
    );
    assert_eq!(s["pair_kind"], kind);
    for key in ["te_peak_to_peak_urad", "te_peak_to_peak_arcsec"] {
        assert!(s[key].as_f64().is_some(), "{key}: {}", s[key]);
    }
}
