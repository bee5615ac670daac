//! `flank check SCENE.toml`: the paper scenes pass the pair checks with the
//! contact ratios their READMEs state; a bad scene is an error with its line.

use std::process::Command;

fn check(path: &str) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_flank"))
        .args(["check", path])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into(),
        String::from_utf8_lossy(&out.stderr).into(),
    )
}

fn field(json: &str, key: &str) -> f64 {
    let v: serde_json::Value = serde_json::from_str(json).unwrap();
    v[key]
        .as_f64()
        .unwrap_or_else(|| panic!("no {key} in {json}"))
}

#[test]
fn seed002_spur_scene_checks() {
    let (ok, out, err) = check("papers/seed002-spur/scene.toml");
    assert!(ok, "{err}");
    let eps = field(&out, "contact_ratio");
    // the paper reports 1.45 (CALYX) to 1.51 (FE)
    assert!((1.45..=1.51).contains(&eps), "ε_α = {eps}");
    assert!((field(&out, "centre_distance") - 90.0).abs() < 1e-9);
    // ISO 6336-1 c′ of a steel spur pair: of the order of 14 N/(mm·µm)
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let c = v["iso6336_stiffness_n_per_mm_um"]["single"]
        .as_f64()
        .unwrap();
    assert!((10.0..18.0).contains(&c), "c′ = {c}");
}

#[test]
fn seed004_helical_scene_checks() {
    let (ok, out, err) = check("papers/seed004-helical/scene.toml");
    assert!(ok, "{err}");
    assert!(field(&out, "overlap_ratio") > 1.0);
    assert!(field(&out, "contact_ratio") > 1.2);
}

#[test]
fn bad_scene_names_key_and_line() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"));
    let path = dir.join("bad_scene.toml");
    std::fs::write(
        &path,
        "[pair]\nkind = \"spur\"\ncentre_distance_mm = 90\nfoo = 1\n",
    )
    .unwrap();
    let (ok, _, err) = check(path.to_str().unwrap());
    assert!(!ok);
    assert!(
        err.contains(":4") && err.contains("foo") && !err.contains("panicked"),
        "{err}"
    );
}

/// The hypoid paper scenes load, run their ISO 23509 blank design and print
/// the blank table; the figures their READMEs quote come out of it.
#[test]
fn hypoid_paper_scenes_print_their_blank_tables() {
    for (path, method, z, de2, b2) in [
        ("papers/seed000-hypoid/scene.toml", 3, (12, 41), 213.2, 32.0),
        ("papers/seed001-hypoid/scene.toml", 1, (10, 41), 220.0, 33.0),
        ("papers/seed003-hypoid/scene.toml", 1, (11, 41), 225.5, 38.0),
    ] {
        let (ok, out, err) = check(path);
        assert!(ok, "{path}: {err}");
        let v: serde_json::Value = serde_json::from_str(&out).unwrap();
        assert_eq!(v["kind"], "hypoid");
        assert_eq!(v["method"], method);
        let b = &v["blank"];
        let f = |k: &str| b[k].as_f64().unwrap_or_else(|| panic!("{path}: no {k}"));
        assert!((f("de2_mm") - de2).abs() < 1e-9, "{path}");
        assert!((f("be2_mm") + f("bi2_mm") - b2).abs() < 1e-9, "{path}");
        assert!((f("u") - z.1 as f64 / z.0 as f64).abs() < 1e-12, "{path}");
        // Hypoid pinion: larger spiral angle than the wheel by about the
        // offset angle in the pitch plane, ζ_mp (ISO 23509: β_m1 = β_m2 + ζ_mp
        // at the last iterate; methods 1–3 stop their iteration at 1e-4° in
        // the angles, so the printed ζ_mp may be one step further).
        let d = f("beta_m1_deg") - f("beta_m2_deg") - f("zeta_mp_deg");
        assert!(d.abs() < 1e-3, "{path}: β_m1 − β_m2 − ζ_mp = {d}°");
    }
}

/// The hypoid scenes also print how each member is cut: process, hand, the
/// machine settings, the correction of the settings to the blank (rounds,
/// residual) and the mean-point figures measured on the flanks.
#[test]
fn hypoid_paper_scenes_print_their_cutting() {
    for (path, process) in [
        ("papers/seed000-hypoid/scene.toml", "face_hobbing"),
        ("papers/seed001-hypoid/scene.toml", "face_milling"),
        ("papers/seed003-hypoid/scene.toml", "face_milling"),
    ] {
        let (ok, out, err) = check(path);
        assert!(ok, "{path}: {err}");
        let v: serde_json::Value = serde_json::from_str(&out).unwrap();
        for (member, hand) in [("pinion", "left"), ("gear", "right")] {
            let m = &v[member];
            assert_eq!(m["process"], process, "{path} {member}");
            assert_eq!(m["hand"], hand, "{path} {member}");
            assert!(m["machine"]["radial_distance_mm"].as_f64().unwrap() > 0.0);
            // settings from the blank, corrected to it at the mean point:
            // the rounds and the residual are reported (a face-hobbed
            // pinion is cut on the gear's corrected crown gear)
            let r = &m["settings_refinement"];
            let of = if process == "face_hobbing" {
                "gear"
            } else {
                member
            };
            assert_eq!(r["member"], of, "{path} {member}: {r}");
            assert!(r["rounds"].as_u64().is_some(), "{path} {member}: {r}");
            let residual = r["residual_rad"].as_f64().unwrap();
            assert!(residual <= 1e-9, "{path} {member}: {r}");
            for side in ["drive", "coast"] {
                assert_eq!(
                    m["mean_point"][side]["hand"], hand,
                    "{path} {member} {side}"
                );
            }
        }
    }
}

/// Bad cutting input in a hypoid scene (issue 16 point 9): a clear error
/// at the file and line of the key, never a panic — a cutter too small for
/// the face width, machine settings that make a pointed tooth, explicit
/// settings on a face-hobbed blank, an ease-off on a machined pinion.
#[test]
fn bad_hypoid_cutting_names_key_and_line() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"));
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let milled = std::fs::read_to_string(root.join("papers/seed003-hypoid/scene.toml")).unwrap();
    let hobbed = std::fs::read_to_string(root.join("papers/seed000-hypoid/scene.toml")).unwrap();
    let machine = "\n[gear.machine]\nradial_distance_mm = 51.5\ncradle_angle_deg = -68.8\nmachine_root_angle_deg = 69.1\nsliding_base_mm = 0.0\nblank_offset_mm = 0.0\nmachine_center_to_back_mm = 0.0\nratio_of_roll = 0.9594\n\n[gear.cutter]\ninside_point_radius_mm = 112.8\noutside_point_radius_mm = 115.8\ninside_blade_angle_deg = 22.1\noutside_blade_angle_deg = 17.8\n";
    let cases: [(&str, String, &str, &[&str]); 4] = [
        (
            "small_cutter",
            milled.replace(
                "\n[materials.steel]",
                "\n[gear.cutter]\nradius_mm = 5.0\n\n[materials.steel]",
            ),
            "radius_mm = 5.0",
            &["gear.cutter.radius_mm", "face width"],
        ),
        (
            "pointed",
            milled.replace(
                "\n[materials.steel]",
                &format!("{machine}\n[materials.steel]"),
            ),
            "[gear.machine]",
            &["[gear.machine]", "pointed tooth"],
        ),
        (
            "hobbed_machine",
            hobbed.replace(
                "\n[materials.steel]",
                &format!("{machine}\n[materials.steel]"),
            ),
            "[gear.machine]",
            &["gear.machine", "face hobbing"],
        ),
        (
            "ease_off",
            milled.replace(
                "\n[gear]\n",
                "\n[pinion.ease_off]\nbias_um = 5.0\n\n[gear]\n",
            ),
            "[pinion.ease_off]",
            &["pinion.ease_off", "conjugate"],
        ),
    ];
    for (name, text, at, words) in cases {
        let path = dir.join(format!("bad_hypoid_{name}.toml"));
        std::fs::write(&path, &text).unwrap();
        let line = 1 + text[..text.find(at).unwrap()].matches('\n').count();
        let (ok, _, err) = check(path.to_str().unwrap());
        assert!(!ok, "{name}");
        assert!(err.contains(&format!(".toml:{line}:")), "{name}: {err}");
        for w in words {
            assert!(err.contains(w), "{name}: '{w}' not in {err}");
        }
        assert!(!err.contains("panicked"), "{name}: {err}");
    }
}
