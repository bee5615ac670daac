//! `flank compare --pmax-reference` (issue 23: p_max against a reference
//! that resolves the Hertz width): contact-band runs as the p_max
//! reference, the LTCA solved at their roll angle, its error in
//! compare.json and compare.md; bad inputs refused before anything runs.
//! Coarse seed 002 (flank 2 mm FE and tensors, one position), synthetic
//! band runs at the scene's kinematic contact of one-tooth sectors.

mod common;

use common::cli::flank;
use std::path::PathBuf;

use flank::mesh_cycle::contact_band::band_contacts;
use flank::scene::read_scene;

fn dir(name: &str) -> PathBuf {
    common::cli::scratch_dir("cli_compare_pmax", name)
}

const SCENE: &str = "papers/seed002-spur/scene.toml";

/// A contact_band.json at `roll`, band `h`, the scene's contacts numbered
/// as in a one-tooth sector, p_max = 2400 − 400 h^1.5 (mid face 20 below).
fn band_run(d: &std::path::Path, roll: f64, h: f64) -> PathBuf {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(SCENE);
    let s = read_scene(&path).unwrap();
    let c = band_contacts(&s, roll).unwrap();
    assert_eq!(c.len(), 1, "a single-contact position");
    let c = &c[0];
    let p = 2400.0 - 400.0 * h.powf(1.5);
    let json = serde_json::json!([{
        "roll_deg": roll, "band_size_mm": h,
        "contacts": [{"pinion_tooth": 1, "gear_tooth": 1, "radius_mm": c.radius_mm,
            "curvature_radius_mm": c.curvature_radius_mm,
            "equivalent_radius_mm": c.equivalent_radius_mm,
            "nominal_half_width_mm": c.nominal_half_width_mm}],
        "bands": [[], []],
        "pairs": [{"pinion_tooth": 1, "force_n": 13200.0, "load_share": 1.0,
            "line_load_n_per_mm": 992.5, "hertz_p0_mpa": 2390.0, "hertz_half_width_mm": 0.264,
            "p_max_mpa": p, "p_max_mid_face_mpa": p - 20.0, "p_max_nodal_mpa": 3200.0,
            "closed_nodes_mid_face": 8, "elements_across_2b": 0.53 / h}],
        "te_urad": 35000.0, "nodes": 1, "dofs": 3, "min_scaled_jacobian": 0.7,
        "max_aspect_ratio": 30.0, "setup_s": 1.0, "solve_s": 1.0, "peak_memory_mb": 100.0,
    }]);
    let sub = d.join(format!("band_{h}"));
    std::fs::create_dir_all(&sub).unwrap();
    std::fs::write(sub.join("contact_band.json"), json.to_string()).unwrap();
    sub
}

/// Three synthetic bands at 5.415°: the reference is their Richardson
/// extrapolation (2400 MPa, order 1.5), the LTCA's p_max at 5.415° (pair
/// 2, the sector's middle tooth) is measured against it in the summary,
/// and compare.md holds the table and the labelled uniform-FE column.
#[test]
fn compare_states_pmax_against_contact_bands() {
    let d = dir("ok");
    let bands = dir("ok_bands");
    let runs: Vec<String> = [0.2, 0.1, 0.05]
        .iter()
        .map(|&h| band_run(&bands, 5.415, h).display().to_string())
        .collect();
    let (ok, out, err) = flank(&[
        "compare",
        SCENE,
        "--flank-size",
        "2",
        "--base-size",
        "4",
        "--fe-flank-sizes",
        "2",
        "--fe-base-size",
        "4",
        "--points-per-line",
        "5",
        "--roll-angles=0",
        "--threads",
        "1",
        "--pmax-reference",
        &runs.join(","),
        "--out",
        d.to_str().unwrap(),
    ]);
    assert!(ok, "{out}\n{err}");
    assert!(out.contains("against FE with contact bands"), "{out}");
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("compare.json")).unwrap()).unwrap();
    let r = &s["pmax_contact_band"]["reference"][0];
    assert_eq!(r["pair"], 2);
    assert_eq!(r["reference"]["method"], "richardson");
    let reference = r["reference"]["value_mpa"].as_f64().unwrap();
    assert!((reference - 2400.0).abs() < 1e-6, "{r}");
    let l = &s["pmax_contact_band"]["ltca"][0];
    let p = l["p_max_mpa"][0].as_f64().unwrap();
    assert!(p > 1000.0 && p < 4000.0, "LTCA p_max {p}");
    assert_eq!(l["load_share"][0].as_f64().unwrap(), 1.0);
    let e = s["pmax_rel_err"].as_f64().unwrap();
    assert!((e - (p - reference).abs() / reference).abs() < 1e-12, "{e}");
    assert!(s["pmax_uniform_fe_rel_err"].is_number());
    let md = std::fs::read_to_string(d.join("compare.md")).unwrap();
    assert!(
        md.contains("## p_max against the contact-band FE reference"),
        "{md}"
    );
    assert!(
        md.contains("p_max rel err vs uniform FE flank 2 mm"),
        "{md}"
    );
    assert!(
        md.contains("| 5.415 | 2 | 1.000 | 0.05 / 0.1 / 0.2 | 2400 |"),
        "{md}"
    );
}

/// A missing run and a run of another load are refused before anything
/// runs, naming the flag and the file; a hypoid scene is refused.
#[test]
fn compare_refuses_bad_pmax_references() {
    let d = dir("bad");
    let (ok, _, err) = flank(&[
        "compare",
        SCENE,
        "--pmax-reference",
        "no/such/run",
        "--out",
        d.to_str().unwrap(),
    ]);
    assert!(!ok && err.contains("--pmax-reference no/such/run"), "{err}");
    assert!(!d.exists(), "nothing written");
    let bands = dir("bad_bands");
    let run = band_run(&bands, 5.415, 0.1).join("contact_band.json");
    let text = std::fs::read_to_string(&run).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    v[0]["contacts"][0]["nominal_half_width_mm"] = serde_json::json!(0.3);
    std::fs::write(&run, v.to_string()).unwrap();
    let (ok, _, err) = flank(&[
        "compare",
        SCENE,
        "--pmax-reference",
        run.to_str().unwrap(),
        "--out",
        d.to_str().unwrap(),
    ]);
    assert!(
        !ok && err.contains("another scene, load or material"),
        "{err}"
    );
    assert!(!d.exists(), "nothing written");
    let (ok, _, err) = flank(&[
        "compare",
        "papers/seed003-hypoid/scene_eased.toml",
        "--pmax-reference",
        run.to_str().unwrap(),
        "--out",
        d.to_str().unwrap(),
    ]);
    assert!(!ok && err.contains("spur pairs only"), "{err}");
}
