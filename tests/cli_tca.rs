//! `flank tca` on seed 000's hypoid scene: the files of the acceptance
//! (tables, transitions, summary.json with `with_edges` / `without_edges`
//! → `contact_ratio`, `te_peak_to_peak_arcsec`, plots) and the V–H sweep
//! (25 rows, its aligned row equal to the aligned run).

use std::path::Path;
use std::process::Command;

#[test]
fn tca_of_the_seed000_hypoid_pair() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let out = std::env::temp_dir().join(format!("flank_cli_tca_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let status = Command::new(env!("CARGO_BIN_EXE_flank"))
        .args(["tca"])
        .arg(root.join("papers/seed000-hypoid/scene.toml"))
        .args(["--search-directions", "0", "--sweep-mm", "0.05", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(
        status.status.success(),
        "{}",
        String::from_utf8_lossy(&status.stderr)
    );
    for f in [
        "tca_with_edges.csv",
        "tca_without_edges.csv",
        "transitions.csv",
        "summary.json",
        "transmission_error.svg",
        "bearing_pattern_gear.png",
        "bearing_pattern_pinion.svg",
        "vh_sweep.csv",
        "vh_chart.png",
        "vh_chart.svg",
    ] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let mut te = [0.0; 2];
    for (i, v) in ["with_edges", "without_edges"].iter().enumerate() {
        let cr = s[v]["contact_ratio"].as_f64().unwrap();
        te[i] = s[v]["te_peak_to_peak_arcsec"].as_f64().unwrap();
        assert!(cr > 1.0 && cr < 4.0, "{v}: contact ratio {cr}");
        assert!(te[i].is_finite() && te[i] >= 0.0);
    }
    // edge contact only adds contact: the ratio with edges is not smaller
    assert!(
        s["with_edges"]["contact_ratio"].as_f64().unwrap()
            >= s["without_edges"]["contact_ratio"].as_f64().unwrap()
    );
    let sweep = std::fs::read_to_string(out.join("vh_sweep.csv")).unwrap();
    let rows: Vec<Vec<&str>> = sweep
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    assert_eq!(rows.len(), 25);
    let aligned = rows
        .iter()
        .find(|r| r[0].parse::<f64>().unwrap() == 0.0 && r[1].parse::<f64>().unwrap() == 0.0)
        .unwrap();
    let te_aligned: f64 = aligned[4].parse().unwrap();
    assert!(
        (te_aligned - te[0]).abs() <= 1e-3,
        "{te_aligned} vs {}",
        te[0]
    );
    let _ = std::fs::remove_dir_all(&out);
}
