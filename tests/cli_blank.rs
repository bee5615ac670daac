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
