//! # Verification: the wet–dry loop through the LTCA (seed 002, issue 20)
//!
//! ## What
//!
//! `flank ltca papers/seed002-spur/scene_lubricated.toml`: the dry LTCA
//! pass at μ₀ = 0.05, the EHL model (Chittenden film, Evans & Johnson
//! traction) per position and tooth pair, wet LTCA passes with that μ per
//! pair, until the largest change of μ is below 0.5 % (`src/ltca/lubricated.rs`).
//! Tensors on coarse meshes (flank 1 mm, base 2 mm) so that the case runs
//! in CI.
//!
//! ## Checks (bands fixed before the CI-size run; reasons in README.md)
//!
//! 1. **μ per pair = μ everywhere.** A per-pair table with the same μ in
//!    every entry gives the single-μ LTCA to ≤ 1e-10 of the largest load
//!    (normal and friction forces, TE), in the three friction models, at
//!    three positions. A table with different μ per pair reaches the
//!    solver: in the sliding model every loaded point carries
//!    |P_t| = μ_pair P_n (1e-9 relative), in the other two |P_t| ≤ μ_pair P_n.
//! 2. **The loop on seed 002** converges within its bound, μ < 0.05
//!    everywhere (the paper's Fig. 9), every logged μ and h_c is what the
//!    EHL formulas give for the logged operating point (1e-9), and the final
//!    pass's friction forces are μ_used P_n of each point's pair (1e-9).
//! 3. **The bound.** With a tolerance of 1e-9 and one wet pass the loop
//!    stops at its bound and says so (`converged: false`, a warning).
//! 4. **LTCA loop against the FE loop** on the same scene, element sizes
//!    and five positions, P̄ by Hertz in both: μ per (position, pair)
//!    within 5 % where both carry > 25 % of F_nom, the mesh power loss
//!    within 10 %, the subsurface change dry → wet within 1 percentage
//!    point; both converge (the counts are reported, not compared).
//!
//! 5. **Point contacts**: the loop on seed 003's eased hypoid pair with
//!    seed 002's oil converges, keeps 0 < μ < μ₀, logs what the formulas
//!    give (1e-9) and applies μ_used per pair (1e-9).
//!
//! Run: `cargo test --release --test ltca_lubricated -- --nocapture`

use std::path::{Path, PathBuf};

use flank::compliance::body::BodyMeshOptions;
use flank::ltca::cycle::{LtcaCycle, LtcaOptions};
use flank::ltca::model::PositionResult;
use flank::ltca::solve_settings::LtcaSettings;
use flank::lubrication::{evaluate, MeanPressure, OperatingPoint};
use flank::scene::{read_scene, Scene};
use flank::settings::FrictionModel;

const MU: f64 = 0.05;

fn scene(name: &str) -> Scene {
    read_scene(
        &Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("papers/seed002-spur")
            .join(name),
    )
    .unwrap()
}

fn mesh() -> BodyMeshOptions {
    BodyMeshOptions {
        flank_size: Some(1.0),
        base_size: Some(2.0),
        ..Default::default()
    }
}

fn work(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("ltca_lubricated")
        .join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn cache() -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("ltca_lubricated_cache");
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn options(out: PathBuf) -> LtcaOptions {
    LtcaOptions {
        out,
        mesh: mesh(),
        points_per_line: Some(20),
        cache: Some(cache()),
        threads: 1,
        quiet: true,
        ..Default::default()
    }
}

/// The largest difference of normal and friction forces over the points,
/// relative to the largest normal force, and of TE (relative).
fn difference(a: &PositionResult, b: &PositionResult) -> f64 {
    let pmax = a.points.iter().map(|p| p.force_n).fold(0.0f64, f64::max);
    let loads = a
        .points
        .iter()
        .zip(&b.points)
        .map(|(x, y)| {
            (x.force_n - y.force_n)
                .abs()
                .max((x.friction_n - y.friction_n).abs())
        })
        .fold(0.0f64, f64::max)
        / pmax;
    loads.max((a.te_urad - b.te_urad).abs() / a.te_urad.abs())
}

#[test]
fn constant_mu_table_reproduces_the_single_mu_ltca() {
    check_tables(false);
}

/// The standstill model with a varied μ table at mid single contact
/// (5.415°): nearly every point sits at the cone's edge; the active-set
/// polish of the Tresca answer cycles there, and the semismooth Newton
/// polish (`src/ltca/friction/semismooth.rs`) takes the Tresca answer's
/// residual (1.6e-7) to round-off (README, check 1b). An ignored known
/// miss until 2026-11-27.
#[test]
fn standstill_varied_table_meets_the_tolerance() {
    check_tables(true);
}

/// Tables against the single-μ LTCA (README check 1); the standstill
/// model's varied table only with `standstill_varied`.
fn check_tables(standstill_varied: bool) {
    let sc = scene("scene.toml");
    let out = work(if standstill_varied {
        "table_standstill"
    } else {
        "table"
    });
    println!(
        "1. model | roll | constant table vs single μ | varied table: sliding max ||P_t|/(μ_pair P_n) − 1|, others max |P_t|/(μ_pair P_n)"
    );
    for model in [
        FrictionModel::Sliding,
        FrictionModel::Incremental,
        FrictionModel::Standstill,
    ] {
        let c = LtcaCycle::new(
            &sc,
            &LtcaOptions {
                friction_mu: Some(MU),
                friction_model: Some(model),
                ..options(out.clone())
            },
        )
        .unwrap();
        let np = c.pair.sector_teeth();
        let (a, e) = c.line_pair().unwrap().engagement(c.pair.middle());
        let (l, h) = c.line_pair().unwrap().single_contact();
        for roll in [
            0.5 * (a + l).to_degrees(),
            0.5 * (l + h).to_degrees(),
            0.5 * (h + e).to_degrees(),
        ] {
            let single = c.solve(roll).unwrap();
            let table = |mu: Vec<f64>| LtcaSettings {
                pair_mu: Some(mu),
                ..c.settings.clone()
            };
            let same = c.solve_with(roll, &table(vec![MU; np])).unwrap();
            let d = difference(&single, &same);
            assert!(d <= 1e-10, "{model:?} at {roll}: {d:.2e}");
            if model == FrictionModel::Standstill && !standstill_varied {
                println!("{model:?} | {roll:.3} | {d:.1e} | (varied table: ignored test)");
                continue;
            }
            // a table that differs per pair
            let mu: Vec<f64> = (0..np).map(|p| 0.02 + 0.02 * p as f64).collect();
            let varied = c.solve_with(roll, &table(mu.clone())).unwrap();
            assert!(varied.kkt_within_tolerance, "{model:?} at {roll}");
            let mut worst: f64 = 0.0;
            for p in varied.points.iter().filter(|p| p.force_n > 0.0) {
                let m = mu[varied.lines[p.line].0 - 1];
                let ratio = p.friction_n.abs() / (m * p.force_n);
                if model == FrictionModel::Sliding {
                    if p.sliding_velocity_m_s.abs() >= 1e-6 {
                        worst = worst.max((ratio - 1.0).abs());
                    }
                } else {
                    assert!(ratio <= 1.0 + 1e-9, "{model:?} at {roll}: {ratio}");
                    worst = worst.max(ratio);
                }
            }
            if model == FrictionModel::Sliding {
                assert!(worst <= 1e-9, "{model:?} at {roll}: {worst:.2e}");
            }
            println!("{model:?} | {roll:.3} | {d:.1e} | {worst:.1e}");
        }
    }
}

/// The loop on `sc` through `flank::ltca::run::run`; the summary.
fn ltca_loop(
    sc: &Scene,
    name: &str,
    roll_angles: Option<Vec<f64>>,
) -> (serde_json::Value, PathBuf) {
    let out = work(name);
    let s = flank::ltca::run::run(
        sc,
        &LtcaOptions {
            roll_angles_deg: roll_angles,
            ..options(out.clone())
        },
    )
    .unwrap()
    .to_json();
    (s, out)
}

#[test]
fn loop_converges_on_seed_002() {
    let sc = scene("scene_lubricated.toml");
    let (s, out) = ltca_loop(&sc, "loop", None);
    let l = &s["lubrication"];
    let f = |k: &str| l[k].as_f64().unwrap();
    println!(
        "2. {} positions: {} wet passes, converged {}, last change {:+.3} %, μ {:.4} … {:.4}, power loss {:.0} W, efficiency {:.3} %, subsurface {:+.2} % / {:+.2} %; dry cycle {:.2} s + loop {:.2} s",
        s["positions"],
        l["iterations"],
        l["converged"],
        100.0 * f("mu_last_change_rel"),
        f("mu_min"),
        f("mu_max"),
        f("power_loss_w"),
        100.0 * f("efficiency"),
        f("subsurface_change_max_pct"),
        f("subsurface_change_min_pct"),
        s["cycle_s"].as_f64().unwrap(),
        f("loop_s")
    );
    assert_eq!(l["converged"], true, "{l}");
    let iterations = l["iterations"].as_u64().unwrap();
    assert!((1..=10).contains(&iterations));
    assert_eq!(l["passes"].as_array().unwrap().len() as u64, iterations + 1);
    assert!(f("mu_last_change_rel").abs() < 0.005);
    assert!(f("mu_max") > 0.0 && f("mu_max") < 0.05, "{}", f("mu_max"));
    let eff = f("efficiency");
    assert!(eff > 0.9 && eff < 1.0, "{eff}");

    // every logged μ and h_c from the logged operating point
    let lub = sc.lubricant.clone().unwrap();
    let csv = std::fs::read_to_string(out.join("lubrication.csv")).unwrap();
    let mut rows = 0;
    for line in csv.lines().skip(1) {
        let c: Vec<&str> = line.split(',').collect();
        let x = |i: usize| c[i].parse::<f64>().unwrap();
        let point = logged_point(&c, f("contact_length_mm"), f("reduced_modulus_mpa"));
        let e = evaluate(
            &lub,
            flank::lubrication::FilmModel::Chittenden,
            &point,
            None,
        )
        .unwrap();
        assert!((e.film.central * 1e3 / x(10) - 1.0).abs() < 1e-9, "{line}");
        assert!((e.traction.mu / x(14) - 1.0).abs() < 1e-9, "{line}");
        rows += 1;
    }
    assert!(rows >= 40, "{rows} loaded contacts");

    // the final pass's friction forces are μ_used P_n of each point's pair
    // (sliding model; points that roll without sliding carry none)
    let passes = std::fs::read_to_string(out.join("lubrication_passes.csv")).unwrap();
    let mut used = std::collections::HashMap::new();
    for line in passes.lines().skip(1) {
        let c: Vec<&str> = line.split(',').collect();
        if c[0] == iterations.to_string() {
            let roll: f64 = c[1].parse().unwrap();
            used.insert(
                (format!("{roll:.6}"), c[2].parse::<usize>().unwrap()),
                c[3].parse::<f64>().unwrap(),
            );
        }
    }
    let mut checked = 0;
    for step in s["steps"].as_array().unwrap() {
        let roll = step["roll_deg"].as_f64().unwrap();
        let lines = step["lines"].as_array().unwrap();
        for p in step["points"].as_array().unwrap() {
            let pn = p["force_n"].as_f64().unwrap();
            let vs = p["sliding_velocity_m_s"].as_f64().unwrap();
            let k = lines[p["line"].as_u64().unwrap() as usize][0]
                .as_u64()
                .unwrap() as usize;
            let Some(mu) = used.get(&(format!("{roll:.6}"), k)) else {
                continue;
            };
            if pn > 0.0 && vs.abs() >= 1e-6 {
                let pt = p["friction_n"].as_f64().unwrap().abs();
                assert!(
                    (pt / (mu * pn) - 1.0).abs() < 1e-9,
                    "{roll}°, pair {k}: {pt} vs {mu} × {pn}"
                );
                checked += 1;
            }
        }
    }
    assert!(checked >= 100, "{checked} points checked");
}

#[test]
fn bounded_loop_reports_its_bound() {
    let mut sc = scene("scene_lubricated.toml");
    let l = sc.analyses.lubrication.as_mut().unwrap();
    l.tolerance = Some(1e-9);
    l.max_iterations = Some(1);
    let (s, _) = ltca_loop(&sc, "bound", Some(vec![-4.0, 0.0, 4.0]));
    let l = &s["lubrication"];
    println!("3. {}", l["warnings"]);
    assert_eq!(l["converged"], false);
    assert_eq!(l["iterations"], 1);
    assert!(
        l["warnings"][0]
            .as_str()
            .unwrap()
            .contains("bound of 1 wet passes"),
        "{l}"
    );
}

#[test]
fn ltca_loop_against_the_fe_loop() {
    let mut sc = scene("scene_lubricated.toml");
    sc.analyses.lubrication.as_mut().unwrap().mean_pressure = Some(MeanPressure::Hertz);
    let angles = vec![-8.0, -4.0, 0.0, 4.0, 8.0];
    let t = std::time::Instant::now();
    let (lt, lout) = ltca_loop(&sc, "vs_fe_ltca", Some(angles.clone()));
    let ltca_s = t.elapsed().as_secs_f64();
    let fout = work("vs_fe_fe");
    let t = std::time::Instant::now();
    let fe = flank::mesh_cycle::run::run(
        &sc,
        &flank::mesh_cycle::run::RunOptions {
            out: fout.clone(),
            mesh: mesh(),
            threads: 1,
            roll_angles_deg: Some(angles),
            vtu: Some(false),
            refine_contact_limits: Some(false),
            quiet: true,
            ..Default::default()
        },
    )
    .unwrap()
    .to_json();
    let fe_s = t.elapsed().as_secs_f64();
    let (l, f) = (&lt["lubrication"], &fe["lubrication"]);
    let g = |v: &serde_json::Value, k: &str| v[k].as_f64().unwrap();
    println!(
        "4. LTCA vs FE (1 mm / 2 mm, 5 positions, Hertz P̄): LTCA {ltca_s:.1} s, FE {fe_s:.1} s"
    );
    for k in [
        "iterations",
        "mu_last_change_rel",
        "mu_min",
        "mu_max",
        "power_loss_w",
        "efficiency",
        "subsurface_change_max_pct",
        "subsurface_change_min_pct",
    ] {
        println!("{k}: LTCA {} | FE {}", l[k], f[k]);
    }
    assert_eq!(l["converged"], true);
    assert_eq!(f["converged"], true);
    // μ per (position, pair) where both carry > 25 % of F_nom
    let read = |dir: &Path| -> std::collections::HashMap<(String, String), (f64, f64)> {
        std::fs::read_to_string(dir.join("lubrication.csv"))
            .unwrap()
            .lines()
            .skip(1)
            .map(|line| {
                let c: Vec<&str> = line.split(',').collect();
                (
                    (c[0].to_string(), c[1].to_string()),
                    (c[2].parse().unwrap(), c[14].parse().unwrap()),
                )
            })
            .collect()
    };
    let (ml, mf) = (read(&lout), read(&fout));
    let nominal = lt["nominal_force_n"].as_f64().unwrap();
    let mut worst: f64 = 0.0;
    let mut compared = 0;
    let mut keys: Vec<_> = ml.keys().cloned().collect();
    keys.sort();
    println!("roll | pair | W LTCA | W FE (N) | μ LTCA | μ FE");
    for k in keys {
        let (wl, mul) = ml[&k];
        let Some(&(wf, muf)) = mf.get(&k) else {
            println!("{} | {} | {wl:.0} | — | {mul:.4} | —", k.0, k.1);
            continue;
        };
        println!(
            "{} | {} | {wl:.0} | {wf:.0} | {mul:.4} | {muf:.4}",
            k.0, k.1
        );
        if wl > 0.25 * nominal && wf > 0.25 * nominal {
            worst = worst.max((mul / muf - 1.0).abs());
            compared += 1;
        }
    }
    let dp = (g(l, "power_loss_w") / g(f, "power_loss_w") - 1.0).abs();
    let ds = (g(l, "subsurface_change_max_pct") - g(f, "subsurface_change_max_pct"))
        .abs()
        .max((g(l, "subsurface_change_min_pct") - g(f, "subsurface_change_min_pct")).abs());
    println!("worst μ {:.2} % over {compared} contacts; power loss {:.2} %; subsurface change {ds:.2} points", 100.0 * worst, 100.0 * dp);
    assert!(compared >= 5, "{compared}");
    assert!(
        worst <= 0.05,
        "μ per contact differs by {:.2} %",
        100.0 * worst
    );
    assert!(dp <= 0.10, "power loss differs by {:.2} %", 100.0 * dp);
    assert!(
        ds <= 1.0,
        "subsurface change differs by {ds:.2} percentage points"
    );
}

/// Check 5, the loop on point contacts: seed 003's eased hypoid pair with
/// seed 002's oil (`hypoid_scene.toml`), the default cycle on coarse tensors
/// (flank 2 mm, base 8 mm, K = 11). The operating points come from the
/// point TCA (`flank::ltca::lubricated::point_contact_kinematics`, checked
/// against the involute closed form in its unit test); here: the loop
/// converges within its bound, μ stays below μ₀ = 0.05 and above 0, every
/// logged μ and h_c is what the EHL formulas give for the logged operating
/// point (1e-9), and the final pass's friction forces are μ_used P_n of
/// each point's pair (1e-9).
#[test]
fn point_contact_loop_on_the_hypoid_pair() {
    let sc = read_scene(
        &Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("verification/ltca_lubricated/hypoid_scene.toml"),
    )
    .unwrap();
    let out = work("hypoid");
    let s = flank::ltca::run::run(
        &sc,
        &LtcaOptions {
            mesh: BodyMeshOptions {
                flank_size: Some(2.0),
                base_size: Some(8.0),
                ..Default::default()
            },
            points_per_line: Some(11),
            ..options(out.clone())
        },
    )
    .unwrap();
    let c = s.first();
    let l = c.lubrication.as_ref().expect("the loop's summary");
    println!(
        "5. hypoid, {} positions: {} wet passes, converged {}, last change {:+.3} %, μ {:.4} … {:.4}, power loss {:.0} W, efficiency {:.3} %, subsurface {:+.2} % / {:+.2} %; flags {:?}; notes {:?}",
        c.positions,
        l.iterations,
        l.converged,
        100.0 * l.mu_last_change_rel,
        l.mu_min.unwrap_or(f64::NAN),
        l.mu_max,
        l.power_loss_w,
        100.0 * l.efficiency,
        l.subsurface_change_max_pct.unwrap_or(f64::NAN),
        l.subsurface_change_min_pct.unwrap_or(f64::NAN),
        l.flags,
        l.notes
    );
    assert!(l.converged, "{:?}", l.warnings);
    assert!((1..=10).contains(&l.iterations));
    assert!(l.mu_max > 0.0 && l.mu_max < MU, "{}", l.mu_max);
    assert!(l.mu_min.is_some_and(|m| m > 0.0));
    assert_eq!(l.contact_length_mm, None);
    let lub = sc.lubricant.clone().unwrap();
    let csv = std::fs::read_to_string(out.join("lubrication.csv")).unwrap();
    let mut rows = 0;
    for line in csv.lines().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        let x = |i: usize| f[i].parse::<f64>().unwrap();
        // the point-contact fit does not read a length
        let point = logged_point(&f, f64::NAN, l.reduced_modulus_mpa);
        let e = evaluate(
            &lub,
            flank::lubrication::FilmModel::Chittenden,
            &point,
            None,
        )
        .unwrap();
        assert!((e.film.central * 1e3 / x(10) - 1.0).abs() < 1e-9, "{line}");
        assert!((e.traction.mu / x(14) - 1.0).abs() < 1e-9, "{line}");
        rows += 1;
    }
    assert!(rows >= c.positions, "{rows} loaded contacts");
    // μ_used of the final pass per (roll, pinion tooth)
    let mut checked = 0;
    for step in &c.steps {
        let r = &step.position;
        for p in r.points.iter().filter(|p| p.force_n > 0.0) {
            let k = r.lines[p.line].0;
            let mu = last_mu(&out, l.iterations, r.roll_deg, k);
            if p.sliding_velocity_m_s.abs() >= 1e-6 {
                assert!(
                    (p.friction_n.abs() / (mu * p.force_n) - 1.0).abs() < 1e-9,
                    "{}°, pair {k}: {} vs {mu} × {}",
                    r.roll_deg,
                    p.friction_n,
                    p.force_n
                );
                checked += 1;
            }
        }
    }
    assert!(checked >= 2 * c.positions, "{checked} points checked");
    // the FE loop has no point-contact operating points: refused, with
    // where the loop runs instead
    let e = flank::mesh_cycle::run::run(
        &sc,
        &flank::mesh_cycle::run::RunOptions {
            out: work("hypoid_fe"),
            quiet: true,
            ..Default::default()
        },
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("`analyses.lubrication`") && e.contains("flank ltca"),
        "{e}"
    );
}

/// μ_used of pass `pass` at `roll_deg` for pinion tooth `k`
/// (`lubrication_passes.csv`).
fn last_mu(out: &Path, pass: usize, roll_deg: f64, k: usize) -> f64 {
    let passes = std::fs::read_to_string(out.join("lubrication_passes.csv")).unwrap();
    passes
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect::<Vec<_>>())
        .find(|c| {
            c[0] == pass.to_string()
                && (c[1].parse::<f64>().unwrap() - roll_deg).abs() < 1e-9
                && c[2].parse::<usize>().unwrap() == k
        })
        .map(|c| c[3].parse().unwrap())
        .unwrap_or_else(|| panic!("no μ of pass {pass} at {roll_deg}° for pair {k}"))
}

/// The operating point of a `lubrication.csv` row (`c`, its cells) with
/// the loop's contact length (mm) and E′ (MPa).
fn logged_point(c: &[&str], length_mm: f64, reduced_modulus_mpa: f64) -> OperatingPoint {
    let x = |i: usize| c[i].parse::<f64>().unwrap();
    OperatingPoint {
        load_n: x(2),
        contact_area_mm2: x(2) / x(3),
        mean_pressure_mpa: x(3),
        other_mean_pressure_mpa: x(4),
        radius_x_mm: x(5),
        radius_y_mm: if c[6] == "line" { f64::INFINITY } else { x(6) },
        length_mm,
        entraining_speed_mm_s: x(7) * 1e3,
        sliding_speed_mm_s: x(8) * 1e3,
        reduced_modulus_mpa,
        outside_path: c[18].contains("OutsidePath"),
        hertz_peak_mpa: 0.0,
    }
}
