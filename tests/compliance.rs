//! Compliance tensors of the seed 002 bodies (issue 4 checks, coarse meshes
//! to keep the run short): symmetry, columns against direct solves,
//! interpolation at nodes, C_nn on a contact line, the CLI's files, the
//! deck identical to `flank mesh`'s, and a unit force solved by CalculiX
//! against the stored matrix.

use std::path::{Path, PathBuf};
use std::process::Command;

use flank::ccx::{ccx_executable, run_ccx};
use flank::compliance::body::{body_flank_nodes, scene_body, BodyMeshOptions};
use flank::compliance::cache::{self, FileFormat};
use flank::compliance::run::contact_line;
use flank::compliance::{compliance_tensor, ComplianceOptions, FlankInterpolator};
use flank::deck::{read_deck, write_deck};
use flank::fem::model::NodalForce;
use flank::fem::static_analysis::{solve_static, SolveOptions};
use flank::scene::{read_scene, ElementKind};
use flank::settings::FlankSelection;

fn scene_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("papers/seed002-spur/scene.toml")
}

fn coarse(element: ElementKind) -> BodyMeshOptions {
    BodyMeshOptions {
        flank_size: Some(1.0),
        base_size: Some(3.0),
        with_load: true,
        element: Some(element),
    }
}

fn rel(a: &[f64], b: &[f64]) -> f64 {
    let d: f64 = a.iter().zip(b).map(|(x, y)| (x - y) * (x - y)).sum();
    let n: f64 = b.iter().map(|y| y * y).sum();
    (d / n).sqrt()
}

#[test]
fn seed002_compliance_checks() {
    let scene = read_scene(&scene_path()).unwrap();
    for (body_name, element) in [
        ("pinion", ElementKind::Hex20),
        ("gear", ElementKind::Wedge15),
    ] {
        let body = scene_body(&scene, body_name, &coarse(element)).unwrap();
        let flank = body_flank_nodes(&body, FlankSelection::Loaded).unwrap();
        let (t, stats) = compliance_tensor(
            body_name,
            &body.model,
            &flank,
            &ComplianceOptions::default(),
        )
        .unwrap();
        let m = t.dim();
        // symmetry
        let asym = t.asymmetry();
        assert!(asym <= 1e-12, "{body_name}: ‖C − Cᵀ‖/‖C‖ = {asym:e}");
        assert_eq!(t.meta.clamped_sets, vec!["BORE".to_string()]);
        // columns against direct solves with that unit load
        let mut worst: f64 = 0.0;
        for a in [0, m / 3 + 1, m / 2 + 2, m - 1] {
            let mut model = body.model.clone();
            model.forces = vec![NodalForce {
                node: flank.nodes[a / 3],
                component: a % 3,
                value: 1.0,
            }];
            let sol = solve_static(
                &model,
                &SolveOptions {
                    recover_stress: false,
                    ..Default::default()
                },
            )
            .unwrap();
            let direct: Vec<f64> = (0..m)
                .map(|i| sol.displacement[3 * flank.nodes[i / 3] + i % 3])
                .collect();
            let col: Vec<f64> = (0..m).map(|i| t.matrix[i * m + a]).collect();
            worst = worst.max(rel(&col, &direct));
        }
        assert!(
            worst <= 1e-10,
            "{body_name}: column vs direct solve {worst:e}"
        );
        // interpolation at nodes returns the nodal tensors
        let it = FlankInterpolator::new(&t).unwrap();
        let mut err: f64 = 0.0;
        for a in (0..t.node_count()).step_by(7) {
            let [u, v] = t.flank.uv[a];
            let set = &t.flank.sets[t.flank.set_of[a] as usize];
            let p = it.point(set, u, v).unwrap();
            let c = it.tensor(&p, &p);
            let ca = t.block(a, a);
            let scale = ca[0][0].abs().max(ca[1][1].abs()).max(ca[2][2].abs());
            for i in 0..3 {
                for j in 0..3 {
                    err = err.max((c[i][j] - ca[i][j]).abs() / scale);
                }
            }
        }
        assert!(err <= 1e-12, "{body_name}: interpolation at nodes {err:e}");
        // C_nn on the contact line at the working pitch point: positive definite
        let report =
            flank::geometry::pair::check_pair(&scene.cylindrical("this test").unwrap().pair)
                .unwrap();
        let (line, _) =
            contact_line(&t, "FLANK_R2", report.working_pressure_angle_rad.tan()).unwrap();
        println!(
            "VERIFY compliance {body_name} ({element:?}): {} flank nodes, 3N = {m}, ‖C−Cᵀ‖/‖C‖ = {asym:.1e}, \
             columns vs direct ≤ {worst:.1e}, nodes ≤ {err:.1e}, κ(C) = {:.3e}; C_nn on {} u = {:.4} \
             ({} points): λ ∈ [{:.3e}, {:.3e}] mm/N, κ = {:.2}; factorization {:.2} s, solve {:.2} s",
            t.node_count(),
            stats.condition.as_ref().unwrap().kappa,
            line.set,
            line.u,
            line.points,
            line.lambda_min,
            line.lambda_max,
            line.condition,
            stats.factorization_s,
            stats.solve_s
        );
        assert!(line.positive_definite && line.points >= 5, "{line:?}");
        assert!(line.condition.is_finite() && line.condition > 1.0);
    }
}

fn flank_cli(args: &[&str], out: &Path) {
    let status = Command::new(env!("CARGO_BIN_EXE_flank"))
        .args(args)
        .arg("--out")
        .arg(out)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    assert!(
        status.status.success(),
        "flank {args:?}: {}",
        String::from_utf8_lossy(&status.stderr)
    );
}

#[test]
fn cli_files_deck_and_ccx_unit_force() {
    let tmp = Path::new(env!("CARGO_TARGET_TMPDIR")).join("compliance_seed002");
    let _ = std::fs::remove_dir_all(&tmp);
    let (out, mesh_out) = (tmp.join("compliance"), tmp.join("mesh"));
    let sizes = [
        "--element",
        "hex20",
        "--flank-size",
        "1.0",
        "--base-size",
        "3.0",
    ];
    let mut args = vec![
        "compliance",
        "papers/seed002-spur/scene.toml",
        "--bodies",
        "pinion",
    ];
    args.extend(sizes);
    flank_cli(&args, &out);
    let mut margs = vec!["mesh", "papers/seed002-spur/scene.toml"];
    margs.extend(sizes);
    flank_cli(&margs, &mesh_out);
    // the deck is the one `flank mesh` writes
    let deck = out.join("pinion.inp");
    assert_eq!(
        std::fs::read(&deck).unwrap(),
        std::fs::read(mesh_out.join("pinion.inp")).unwrap(),
        "pinion.inp differs from flank mesh's"
    );
    let file = out.join(FileFormat::default_format().file_name("pinion"));
    assert!(file.exists(), "{} missing", file.display());
    for f in ["summary.json", "pinion_cnn.svg", "pinion_cnn.png"] {
        assert!(out.join(f).exists(), "{f} missing");
    }
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let s = &summary["bodies"]["pinion"];
    assert_eq!(s["source"], "computed");
    for key in ["rhs", "factorization_s", "solve_s", "peak_memory_mb"] {
        assert!(s["stats"][key].as_f64().unwrap() > 0.0, "{key}: {s}");
    }
    assert!(s["stats"]["condition"]["kappa"].as_f64().unwrap() > 1.0);
    // a second run reuses the file (same cache key)
    flank_cli(&args, &out);
    let again: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(again["bodies"]["pinion"]["source"], "disk");

    let t = cache::read(&file).unwrap();
    assert_eq!(t.meta.clamped_sets, vec!["BORE".to_string()]);
    let parsed = read_deck(&deck).unwrap();
    let mesh = &parsed.model.mesh;
    assert_eq!(t.meta.mesh_hash, flank::compliance::mesh_hash(mesh));
    if ccx_executable().is_none() {
        assert!(std::env::var_os("CI").is_none(), "ccx missing on CI");
        return;
    }
    // a unit force along the flank normal at the flank node nearest the
    // middle of the middle tooth's flank, solved by ccx on the written deck
    let set = t.flank.set_index("FLANK_R2").unwrap() as u32;
    let (umid, vmid) = {
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for (p, &s) in t.flank.uv.iter().zip(&t.flank.set_of) {
            if s == set {
                for k in 0..2 {
                    lo[k] = lo[k].min(p[k]);
                    hi[k] = hi[k].max(p[k]);
                }
            }
        }
        (0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]))
    };
    let j = (0..t.node_count())
        .filter(|&a| t.flank.set_of[a] == set)
        .min_by(|&a, &b| {
            let d = |k: usize| {
                (t.flank.uv[k][0] - umid).powi(2) * 100.0 + (t.flank.uv[k][1] - vmid).powi(2)
            };
            d(a).total_cmp(&d(b))
        })
        .unwrap();
    let n = t.flank.normals[j];
    let mut model = parsed.model.clone();
    let node = mesh.node(t.flank.labels[j]).unwrap();
    model.forces = (0..3)
        .map(|c| NodalForce {
            node,
            component: c,
            value: -n[c],
        })
        .collect();
    model.pressures.clear();
    let unit_deck = tmp.join("pinion_unit.inp");
    write_deck(&model, &unit_deck).unwrap();
    let ccx = run_ccx(&unit_deck, &tmp.join("ccx"), 2).unwrap();
    // predicted displacements at every flank node: C[:, j-block] · f
    let m = t.dim();
    let f = [-n[0], -n[1], -n[2]];
    let (mut diff, mut scale) = (0.0f64, 0.0f64);
    for i in 0..t.node_count() {
        let u_ccx = ccx.displacements[&t.flank.labels[i]];
        for (a, ua) in u_ccx.iter().enumerate() {
            let pred: f64 = (0..3)
                .map(|b| t.matrix[(3 * i + a) * m + 3 * j + b] * f[b])
                .sum();
            diff = diff.max((pred - ua).abs());
            scale = scale.max(ua.abs());
        }
    }
    let rel = diff / scale;
    println!(
        "VERIFY compliance_ccx: unit normal force at pinion node {} ({} flank nodes): \
         max |C f − u_ccx| / max |u_ccx| = {rel:.2e} (max |u| = {scale:.3e} mm), ccx {:.1} s",
        t.flank.labels[j],
        t.node_count(),
        ccx.wall_s
    );
    assert!(rel <= 1e-5, "compliance vs ccx: {rel:e}");
}

/// `flank compliance` on a hypoid scene (issue 18 point 2): the tensors of
/// the bevel sector body on the deck `flank mesh` writes, the directional
/// compliances at the mean contact in the summary, reuse on a second run.
#[test]
fn cli_hypoid_gear_tensors_and_mean_contact() {
    let tmp = Path::new(env!("CARGO_TARGET_TMPDIR")).join("compliance_seed003");
    let _ = std::fs::remove_dir_all(&tmp);
    let (out, mesh_out) = (tmp.join("compliance"), tmp.join("mesh"));
    let scene = "papers/seed003-hypoid/scene_eased.toml";
    let sizes = ["--flank-size", "2.0", "--base-size", "8.0"];
    let mut args = vec!["compliance", scene, "--bodies", "gear"];
    args.extend(sizes);
    flank_cli(&args, &out);
    let mut margs = vec!["mesh", scene];
    margs.extend(sizes);
    flank_cli(&margs, &mesh_out);
    assert_eq!(
        std::fs::read(out.join("gear.inp")).unwrap(),
        std::fs::read(mesh_out.join("gear.inp")).unwrap(),
        "gear.inp differs from flank mesh's"
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let g = &summary["bodies"]["gear"];
    assert_eq!(g["source"], "computed");
    assert_eq!(g["clamped_sets"], serde_json::json!(["MOUNT"]));
    assert_eq!(
        g["flank_sets"],
        serde_json::json!(["FLANK_R1", "FLANK_R2", "FLANK_R3"])
    );
    assert!(g["contact_line"].is_null(), "a spur/helical figure: {g}");
    let m = &g["mean_contact"];
    assert!(m["error"].is_null(), "{m}");
    let r = &m["report"];
    let f = |k: &str| r[k].as_f64().unwrap_or(f64::NAN);
    assert!(r["points"].as_u64().unwrap() >= 5, "{m}");
    assert!(f("c_nn") > 0.0 && f("c_tt") > 0.0, "{m}");
    assert!(f("c_nt").abs() < f("c_nn"), "{m}");
    assert!(f("reciprocity") <= 1e-12, "{m}");
    assert_eq!(r["positive_definite"], true);
    flank_cli(&args, &out);
    let again: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(again["bodies"]["gear"]["source"], "disk");
    assert_eq!(again["bodies"]["gear"]["mean_contact"], *m);
}
