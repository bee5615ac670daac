//! `flank blank INPUTS.json` on the F2 inputs of ISO 23509 Annex F (from
//! `../shared/reference/iso23509_annexF.json`): prints the outputs as JSON;
//! an unknown key is an error naming it.

use std::process::Command;

fn f2_inputs() -> serde_json::Value {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../shared/reference/iso23509_annexF.json");
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    v["F2_spiral_bevel_method0_face_milling"]["inputs"].clone()
}

fn blank(inputs: &serde_json::Value, name: &str) -> (bool, String, String) {
    let dir = std::env::temp_dir().join(format!("flank_cli_blank_{}_{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("inputs.json");
    std::fs::write(&path, inputs.to_string()).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_flank"))
        .arg("blank")
        .arg(&path)
        .output()
        .unwrap();
    std::fs::remove_dir_all(&dir).ok();
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into(),
        String::from_utf8_lossy(&out.stderr).into(),
    )
}

#[test]
fn f2_outputs_as_json() {
    let (ok, out, err) = blank(&f2_inputs(), "f2");
    assert!(ok, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert!((v["delta1_deg"].as_f64().unwrap() - 19.747).abs() < 0.0005);
    assert!((v["Rm_mm"].as_f64().unwrap() - 81.273).abs() < 0.0005);
    assert!((v["dae2_mm"].as_f64().unwrap() - 178.288).abs() < 0.0005);
}

#[test]
fn unknown_key_is_named() {
    let mut inputs = f2_inputs();
    inputs["rc_mm"] = serde_json::json!(100.0);
    let (ok, _, err) = blank(&inputs, "bad");
    assert!(!ok);
    assert!(err.contains("rc_mm"), "{err}");
}

fn sample(name: &str) -> serde_json::Value {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../shared/reference/iso23509_annexF.json");
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    v[name]["inputs"].clone()
}

fn f4_inputs() -> serde_json::Value {
    sample("F4_hypoid_method2_oerlikon_face_hobbing")
}

fn edit(mut v: serde_json::Value, changes: &[(&str, serde_json::Value)]) -> serde_json::Value {
    for (k, x) in changes {
        if x.is_null() {
            v.as_object_mut().unwrap().remove(*k);
        } else {
            v[*k] = x.clone();
        }
    }
    v
}

fn outputs(inputs: &serde_json::Value, name: &str) -> serde_json::Value {
    let (ok, out, err) = blank(inputs, name);
    assert!(ok, "{name}: {err}");
    serde_json::from_str(&out).unwrap()
}

fn error(inputs: &serde_json::Value, name: &str) -> String {
    let (ok, out, err) = blank(inputs, name);
    assert!(!ok, "{name}: expected an error, got {out}");
    err
}

fn get(v: &serde_json::Value, k: &str) -> f64 {
    v[k].as_f64().unwrap_or_else(|| panic!("no output `{k}`"))
}

/// Data type I: the mean depths are m_mn (k_hap ± x_hm1), m_mn (k_hfp ∓ x_hm1)
/// and the thicknesses carry ±x_smn (formulae (133)–(136), (206), (211)).
#[test]
fn data_type_i_factors() {
    use serde_json::json;
    let n = serde_json::Value::Null;
    let inputs = edit(
        f2_inputs(),
        &[
            ("data_type", json!("I")),
            ("c_ham", n.clone()),
            ("k_d", n.clone()),
            ("k_c", n.clone()),
            ("k_t", n),
            ("x_hm1", json!(0.4)),
            ("k_hap", json!(1.0)),
            ("k_hfp", json!(1.25)),
            ("x_smn", json!(0.05)),
        ],
    );
    let v = outputs(&inputs, "type_i");
    let m = get(&v, "m_mn_mm");
    assert!((get(&v, "ham1_mm") - 1.4 * m).abs() < 1e-9);
    assert!((get(&v, "ham2_mm") - 0.6 * m).abs() < 1e-9);
    assert!((get(&v, "hfm1_mm") - 0.85 * m).abs() < 1e-9);
    assert!((get(&v, "hfm2_mm") - 1.65 * m).abs() < 1e-9);
    // x_sm1 − x_sm2 = 2 x_smn whatever the backlash.
    assert!((get(&v, "xsm1") - get(&v, "xsm2") - 0.1).abs() < 1e-12);
}

fn method1_inputs() -> serde_json::Value {
    // A Gleason face-milled hypoid chosen for this test (not a sample of
    // the standard).
    serde_json::json!({
        "method": 1, "Sigma_deg": 90, "a_mm": 20.0, "z1": 11, "z2": 43,
        "de2_mm": 210.0, "b2_mm": 32.0, "beta_m1_desired_deg": 45.0, "rc0_mm": 88.9,
        "data_type": "II", "alpha_dD_deg": 20, "alpha_dC_deg": 20, "f_alim": 1.0,
        "c_ham": 0.3, "k_d": 2.0, "k_c": 0.125, "k_t": 0.08,
        "backlash": "outer normal jen 0.15", "theta_a2_deg": 1.5, "theta_f2_deg": 4.5
    })
}

/// Method 1 takes `beta_m1_desired_deg` and returns β_m2, c_be2 and a pinion
/// spiral angle close to the desired one.
#[test]
fn method1_desired_pinion_spiral_angle() {
    let v = outputs(&method1_inputs(), "method1");
    assert!((get(&v, "beta_m1_deg") - 45.0).abs() < 0.02, "{v}");
    let b2 = get(&v, "beta_m2_deg");
    assert!((get(&v, "beta_m1_deg") - b2 - get(&v, "zeta_mp_deg")).abs() < 1e-9);
    assert!(get(&v, "c_be2") > 0.4 && get(&v, "c_be2") < 0.6);
    // Generated pressure angles shifted by the limit pressure angle.
    let lim = get(&v, "alpha_lim_deg");
    assert!(lim != 0.0 && (get(&v, "alpha_nD_deg") - 20.0 - lim).abs() < 1e-9);
}

/// Method 3 (Klingelnberg, face hobbing): constant depth, the face and root
/// angles of the wheel are its pitch angle.
#[test]
fn method3_constant_depth() {
    use serde_json::json;
    let inputs = edit(
        f4_inputs(),
        &[
            ("method", json!(3)),
            ("dm2_mm", serde_json::Value::Null),
            ("de2_mm", json!(170.0)),
            ("z0", json!(5)),
            ("rc0_mm", json!(100.0)),
        ],
    );
    let v = outputs(&inputs, "method3");
    let d2 = get(&v, "delta2_deg");
    assert!((get(&v, "delta_a2_deg") - d2).abs() < 1e-12);
    assert!((get(&v, "delta_f2_deg") - d2).abs() < 1e-12);
    assert!((get(&v, "hae2_mm") - get(&v, "ham2_mm")).abs() < 1e-12);
    assert!((get(&v, "hai2_mm") - get(&v, "ham2_mm")).abs() < 1e-12);
    assert!((get(&v, "Re2_mm") - get(&v, "Rm2_mm") - 13.0).abs() < 1e-9);
    // b1 in whole millimetres (formula (170)).
    assert_eq!(get(&v, "b1_mm").fract(), 0.0);
}

/// Bad input: a clear error naming the key (issue 16 point 9, blank part).
#[test]
fn bad_input_names_the_key() {
    use serde_json::json;
    let n = serde_json::Value::Null;
    let cases: Vec<(&str, serde_json::Value, &str)> = vec![
        (
            "offset_too_large",
            edit(f4_inputs(), &[("a_mm", json!(120.0))]),
            "`a_mm`",
        ),
        (
            "cutter_too_small_for_face_width",
            edit(f2_inputs(), &[("rc0_mm", json!(10.0))]),
            "`rc0_mm`",
        ),
        (
            "hobbing_cutter_too_small",
            edit(f4_inputs(), &[("rc0_mm", json!(20.0))]),
            "`rc0_mm`",
        ),
        (
            "pointed_teeth",
            edit(
                f2_inputs(),
                &[
                    ("data_type", json!("I")),
                    ("c_ham", n.clone()),
                    ("k_d", n.clone()),
                    ("k_c", n.clone()),
                    ("k_t", n.clone()),
                    ("x_hm1", json!(0.9)),
                    ("k_hap", json!(2.5)),
                    ("k_hfp", json!(2.75)),
                    ("x_smn", json!(0.0)),
                ],
            ),
            "`x_hm1`",
        ),
        (
            "method1_without_desired_angle",
            edit(method1_inputs(), &[("beta_m1_desired_deg", n.clone())]),
            "`beta_m1_desired_deg`",
        ),
        (
            "method1_with_wheel_angle",
            edit(method1_inputs(), &[("beta_m2_deg", json!(30.0))]),
            "`beta_m2_deg`",
        ),
        (
            "method2_without_z0",
            edit(f4_inputs(), &[("z0", n.clone())]),
            "`z0`",
        ),
        (
            "method2_without_dm2",
            edit(
                f4_inputs(),
                &[("dm2_mm", n.clone()), ("de2_mm", json!(170.0))],
            ),
            "`dm2_mm`",
        ),
        (
            "method3_without_wheel_angle",
            edit(
                f4_inputs(),
                &[
                    ("method", json!(3)),
                    ("dm2_mm", n.clone()),
                    ("de2_mm", json!(170.0)),
                    ("beta_m2_deg", n),
                ],
            ),
            "`beta_m2_deg`",
        ),
    ];
    for (name, inputs, key) in cases {
        let e = error(&inputs, name);
        assert!(e.contains(key), "{name}: {e}");
        assert!(!e.contains("panicked"), "{name}: {e}");
    }
}
