//! (i) The Cyclo-Palloid pinion's head tilt (`bevel::cyclo_palloid`): the
//! pinion on the gear's crown gear with its head tilted about the mean
//! trace through P, its blade angle and point width set by a bounded
//! Newton, meets the blank's mean-point pressure angles and s_mn; its
//! flanks satisfy the equation of meshing; seed 000's tilted scene checks,
//! meshes and runs its TCA (figures in README.md).

use std::path::Path;
use std::process::Command;
use std::time::Instant;

use flank::geometry::bevel::body::{angle_from_y, wrap_angle};
use flank::geometry::bevel::cyclo_palloid::cyclo_palloid_pinion;
use flank::geometry::bevel::hobbing_settings::{HobbingBlank, HobbingCutter, HobbingSetup, Member};
use flank::geometry::bevel::{blank_design, BlankInputs};
use flank::geometry::surface::ToothSurface;

use super::{cutter, grid_residuals, F4, SIDES};

/// Seed 000's blank (papers/seed000-hypoid/scene.toml `[blank]`).
const SEED000: &str = r#"{"method": 3, "Sigma_deg": 90.0, "a_mm": 30.0, "z1": 12, "z2": 41,
 "de2_mm": 213.2, "b2_mm": 32.0, "beta_m2_deg": 32.0, "rc0_mm": 100.0, "z0": 5,
 "data_type": "I", "alpha_dD_deg": 20.0, "alpha_dC_deg": 20.0, "f_alim": 0.0,
 "k_hap": 1.0, "k_hfp": 1.25, "x_hm1": 0.53, "x_smn": 0.0}"#;

#[test]
fn i_tilted_pinion_meets_the_blank() {
    let deg = f64::to_degrees;
    for (name, json, cut, hands) in [
        ("F4", F4, cutter(), (1.0, -1.0)),
        (
            "seed 000",
            SEED000,
            // the scene's default cutter: r_c0, z0 of the blank, edge 0.2 m_mn
            HobbingCutter {
                radius: 100.0,
                blade_groups: 5,
                edge_radius: 0.0,
            },
            (-1.0, 1.0),
        ),
    ] {
        let d = blank_design(&BlankInputs::from_json(json).unwrap()).unwrap();
        let cut = if cut.edge_radius == 0.0 {
            HobbingCutter {
                edge_radius: 0.2 * d.cones.m_mn,
                ..cut
            }
        } else {
            cut
        };
        let gb = HobbingBlank {
            hand: hands.0,
            ..HobbingBlank::from_design(&d, Member::Gear).unwrap()
        };
        let pb = HobbingBlank {
            hand: hands.1,
            ..HobbingBlank::from_design(&d, Member::Pinion).unwrap()
        };
        let gear = HobbingSetup::new(gb, cut, true).unwrap();
        let t0 = Instant::now();
        let (s, fit) = cyclo_palloid_pinion(&gear, pb, true, 1e-10, 30).unwrap();
        let took = t0.elapsed().as_secs_f64();
        let rm = pb.mean_cone_distance;
        let mut alpha = [0.0; 2];
        let mut beta = [0.0; 2];
        let mut pts = Vec::new();
        let (mut mesh, mut rel) = (0.0f64, 0.0f64);
        for (k, side) in SIDES.into_iter().enumerate() {
            let f = s.flank(side).unwrap();
            let m = f.measure(0.0, rm).unwrap();
            alpha[k] = m.pressure_angle;
            beta[k] = m.spiral_angle;
            pts.push(f.point(0.0, rm));
            let (g, _, r) = grid_residuals(&f);
            mesh = mesh.max(g);
            rel = rel.max(r);
        }
        let ea = [
            alpha[0] - pb.pressure_angle_concave,
            alpha[1] - pb.pressure_angle_convex,
        ];
        let d_phi = wrap_angle(angle_from_y(pts[0]) - angle_from_y(pts[1])).abs();
        let s_mn = rm * pb.pitch_angle.sin() * d_phi * pb.spiral_angle.cos();
        println!(
            "{name}: tilt {:+.6}° about the mean trace (swivel {:.4}°), blade angle {:+.6}°, point width {:+.6} mm; {} Newton steps, residual {:.1e}, {took:.3} s",
            deg(fit.variables.tilt),
            deg(fit.swivel),
            deg(fit.variables.blade_angle_change),
            fit.variables.width_change,
            fit.iterations,
            fit.residual
        );
        println!(
            "  blank α {:.6}° / {:.6}°, β_m1 {:.6}°, s_mn1 {:.6} mm",
            deg(pb.pressure_angle_concave),
            deg(pb.pressure_angle_convex),
            deg(pb.spiral_angle),
            pb.normal_thickness
        );
        println!(
            "  upright: α {:.6}° / {:.6}°, β {:.6}° / {:.6}°, s_mn {:.6} mm",
            deg(fit.upright.pressure_angle.0),
            deg(fit.upright.pressure_angle.1),
            deg(fit.upright.spiral_angle.0),
            deg(fit.upright.spiral_angle.1),
            fit.upright.thickness
        );
        println!(
            "  tilted (full flanks): α errors {:.1e} / {:.1e} rad, β {:.6}° / {:.6}° (mean − β_m1 {:+.2e}°), s_mn error {:.1e} mm; meshing residual ≤ {mesh:.1e}, |n·r_u|/|r_u|, |n·r_v|/|r_v| ≤ {rel:.1e}",
            ea[0],
            ea[1],
            deg(beta[0]),
            deg(beta[1]),
            deg(0.5 * (beta[0] + beta[1]) - pb.spiral_angle),
            s_mn - pb.normal_thickness
        );
        assert!(fit.residual <= 1e-10);
        assert!(ea[0].abs() <= 1e-9 && ea[1].abs() <= 1e-9, "{ea:?}");
        assert!((s_mn - pb.normal_thickness).abs() <= 1e-9 * rm);
        assert!(mesh <= 1e-10 && rel <= 1e-10, "{mesh} {rel}");
    }
}

/// Seed 000 with `pinion.cutter_tilt = "from_blank"`: `flank check`,
/// `flank mesh` (coarse, flank size 1.5 mm) and `flank tca` run; the TCA's
/// residuals are at round-off, with edge contact no pair's flanks cross
/// (without it only a tip edge may cut the mate's flank: the edge contact
/// that variant leaves out), edge contact does not shorten the path. The
/// upright scene's TCA is run for comparison.
#[test]
fn i_tilted_seed000_checks_meshes_and_runs_its_tca() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let out = std::env::temp_dir().join(format!("flank_vf_tilt_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let flank = |args: &[&str], scene: &str, dir: &str| {
        let t0 = Instant::now();
        let o = Command::new(env!("CARGO_BIN_EXE_flank"))
            .args(args)
            .arg(root.join(scene))
            .arg("--out")
            .arg(out.join(dir))
            .output()
            .unwrap();
        assert!(
            o.status.success(),
            "{args:?} {scene}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
        t0.elapsed().as_secs_f64()
    };
    let tilted = "papers/seed000-hypoid/scene_tilted.toml";
    let o = Command::new(env!("CARGO_BIN_EXE_flank"))
        .arg("check")
        .arg(root.join(tilted))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let check: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let ham = [
        check["blank"]["ham1_mm"].as_f64().unwrap(),
        check["blank"]["ham2_mm"].as_f64().unwrap(),
    ];
    let t_mesh = flank(&["mesh", "--flank-size", "1.5"], tilted, "mesh");
    let report = std::fs::read_to_string(out.join("mesh/mesh_report.json")).unwrap();
    println!("seed 000 tilted: flank mesh (flank size 1.5 mm) {t_mesh:.2} s");
    assert!(report.contains("pinion"));
    for (scene, dir) in [
        (tilted, "tca_tilted"),
        ("papers/seed000-hypoid/scene.toml", "tca_upright"),
    ] {
        let t = flank(&["tca", "--search-directions", "0"], scene, dir);
        let s: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(out.join(dir).join("summary.json")).unwrap(),
        )
        .unwrap();
        for v in ["with_edges", "without_edges"] {
            let w = &s[v];
            println!(
                "  {dir} {v}: contact ratio {:.3}, TE p-p {:.3}″, point residual {:.1e} mm, tangency residual {:.1e}, crossing {} ({t:.1} s)",
                w["contact_ratio"].as_f64().unwrap(),
                w["te_peak_to_peak_arcsec"].as_f64().unwrap(),
                w["max_point_residual_mm"].as_f64().unwrap(),
                w["max_tangency_residual"].as_f64().unwrap(),
                w["crossing"]
            );
            // with edges no pair's flanks cross; without edges a crossing
            // may only be a tip edge cutting the mate's flank (the edge
            // contact that variant leaves out)
            let c = &w["crossing"];
            if v == "with_edges" {
                assert!(c.is_null(), "{dir} {v}: {c}");
            } else if !c.is_null() {
                let (up, ug) = (
                    c["pinion_uv_mm"][0].as_f64().unwrap(),
                    c["gear_uv_mm"][0].as_f64().unwrap(),
                );
                assert!(up >= ham[0] - 1e-6 || ug >= ham[1] - 1e-6, "{dir} {v}: {c}");
            }
            assert!(w["max_point_residual_mm"].as_f64().unwrap() <= 1e-10);
            assert!(w["max_tangency_residual"].as_f64().unwrap() <= 1e-10);
        }
        assert!(
            s["with_edges"]["contact_ratio"].as_f64().unwrap()
                >= s["without_edges"]["contact_ratio"].as_f64().unwrap()
        );
    }
    let _ = std::fs::remove_dir_all(&out);
}
