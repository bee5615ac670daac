//! # Verification: ISO 23509:2016 Annex F blank design
//!
//! See `README.md` beside this file for what is checked, the reference, the
//! tolerance and the obtained errors. Every printed output of every sample
//! in `../shared/reference/iso23509_annexF.json` (read at run time) is
//! compared with the printed digits: |obtained − printed| ≤ half a unit of
//! the last printed digit. No sample is special-cased: the outputs that
//! miss are listed in `MISSES` (with the reason) and checked only by the
//! `#[ignore]`d test.

use std::path::PathBuf;

use flank::geometry::bevel::{blank_design, BlankInputs};
use serde_json::Value;

/// (sample, key, reason) of the printed outputs this implementation misses.
const MISSES: &[(&str, &str, &str)] = &[
    ("F2_spiral_bevel_method0", "dae1_mm", "75.3234 by formula (220) from the unrounded chain; with Table 4's x_hm1 written to three decimals (0.505) it is 75.3244 — the sample's rounded factors, not a prescription found in the standard, see README"),
    ("F2_spiral_bevel_method0", "smn1_mm", "6.4625 with x_smn = k_t/2 = 0.04575 and x_hm1 = 0.50483; the printed pair follows from x_smn = 0.046, x_hm1 = 0.505 (three decimals), see README"),
    ("F2_spiral_bevel_method0", "smn2_mm", "3.5128; see smn1 and README"),
];

fn reference() -> serde_json::Map<String, Value> {
    let path =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/reference/iso23509_annexF.json");
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let v: Value = serde_json::from_str(&text).expect("reference JSON");
    v.as_object().expect("object").clone()
}

/// Half a unit of the last printed digit of `x` as the file prints it.
fn half_unit(x: &Value) -> f64 {
    let s = x.to_string();
    let decimals = s.split_once('.').map_or(0, |(_, d)| d.len());
    0.5 * 10f64.powi(-(decimals as i32))
}

struct Row {
    sample: String,
    key: String,
    printed: f64,
    obtained: f64,
    tol: f64,
}

fn rows() -> Vec<Row> {
    rows_with(|_, v| v.clone())
}

/// Every printed output of every sample, the inputs first passed through
/// `edit` (sample name, inputs object).
fn rows_with(edit: impl Fn(&str, &Value) -> Value) -> Vec<Row> {
    let mut rows = Vec::new();
    for (name, sample) in reference() {
        let Some(sample) = sample.as_object() else {
            continue;
        };
        let inputs = BlankInputs::from_value(edit(&name, &sample["inputs"]))
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        let design = blank_design(&inputs).unwrap_or_else(|e| panic!("{name}: {e}"));
        let out = design.outputs();
        for (key, printed) in sample["outputs"].as_object().expect("outputs") {
            let obtained = out
                .get(key)
                .and_then(Value::as_f64)
                .unwrap_or_else(|| panic!("{name}: output `{key}` not produced"));
            rows.push(Row {
                sample: name.clone(),
                key: key.clone(),
                printed: printed.as_f64().expect("number"),
                obtained,
                tol: half_unit(printed),
            });
        }
    }
    rows
}

fn is_miss(r: &Row) -> bool {
    MISSES
        .iter()
        .any(|(s, k, _)| r.sample.starts_with(s) && r.key == *k)
}

fn report(rows: &[Row]) {
    println!(
        "{:<45} {:<14} {:>12} {:>12} {:>10} {:>8}",
        "sample", "key", "printed", "obtained", "error", "tol"
    );
    for r in rows {
        let e = r.obtained - r.printed;
        let flag = if e.abs() <= r.tol { "" } else { "  MISS" };
        println!(
            "{:<45} {:<14} {:>12} {:>12.5} {:>10.5} {:>8}{flag}",
            r.sample, r.key, r.printed, r.obtained, e, r.tol
        );
    }
}

#[test]
fn annex_f_outputs_to_their_printed_digits() {
    let t = std::time::Instant::now();
    let rows = rows();
    println!("blank designs in {:?}", t.elapsed());
    report(&rows);
    let bad: Vec<String> = rows
        .iter()
        .filter(|r| !is_miss(r) && (r.obtained - r.printed).abs() > r.tol)
        .map(|r| {
            format!(
                "{} {}: {} vs printed {}",
                r.sample, r.key, r.obtained, r.printed
            )
        })
        .collect();
    assert!(
        bad.is_empty(),
        "outputs off their printed digits:\n{}",
        bad.join("\n")
    );
}

/// The known misses (see `MISSES` and the README): fails until fixed.
#[test]
#[ignore = "known misses against the printed Annex F values, see README"]
fn annex_f_known_misses() {
    let rows = rows();
    let misses: Vec<&Row> = rows.iter().filter(|r| is_miss(r)).collect();
    for (s, k, why) in MISSES {
        println!("{s} {k}: {why}");
    }
    let bad: Vec<String> = misses
        .iter()
        .filter(|r| (r.obtained - r.printed).abs() > r.tol)
        .map(|r| {
            format!(
                "{} {}: {} vs printed {}",
                r.sample, r.key, r.obtained, r.printed
            )
        })
        .collect();
    assert!(bad.is_empty(), "still missing:\n{}", bad.join("\n"));
}

/// Diagnostic of the samples' own arithmetic, not of flank's default chain
/// (the misses above stay misses): a data-type-II sample is rewritten as
/// data type I with the factors of the standard's Table 4 as transcribed
/// (k_hap = k_d/2, k_hfp = k_d (1/2 + k_c), x_hm1 = k_d (1/2 − c_ham),
/// x_smn = k_t/2), x_hm1 and x_smn written to three decimals as the
/// standard's type I factors are (F2: 0.50526 → 0.505, 0.04575 → 0.046; F4
/// is exact at three decimals, 0.450 and 0.050). Every printed output of
/// both samples must then reproduce, F2's d_ae1, s_mn1, s_mn2 included.
/// See the README's "misses" section for why this is evidence about the
/// printed F2 and not a prescription flank can adopt.
#[test]
fn annex_f_type_ii_samples_as_type_i_factors_at_three_decimals() {
    let three = |x: f64| (x * 1000.0).round() / 1000.0;
    let rows = rows_with(|_, v| {
        let mut o = v.as_object().expect("inputs object").clone();
        if o["data_type"] != "II" {
            return Value::Object(o);
        }
        let f = |k: &str| o[k].as_f64().expect("type II factor");
        let (c_ham, k_d, k_c, k_t) = (f("c_ham"), f("k_d"), f("k_c"), f("k_t"));
        for k in ["c_ham", "k_d", "k_c", "k_t"] {
            o.remove(k);
        }
        o.insert("data_type".into(), "I".into());
        o.insert("k_hap".into(), (k_d / 2.0).into());
        o.insert("k_hfp".into(), (k_d * (0.5 + k_c)).into());
        o.insert("x_hm1".into(), three(k_d * (0.5 - c_ham)).into());
        o.insert("x_smn".into(), three(k_t / 2.0).into());
        Value::Object(o)
    });
    report(&rows);
    assert!(rows.len() >= 40, "{} printed outputs", rows.len());
    let bad: Vec<String> = rows
        .iter()
        .filter(|r| (r.obtained - r.printed).abs() > r.tol)
        .map(|r| {
            format!(
                "{} {}: {} vs printed {}",
                r.sample, r.key, r.obtained, r.printed
            )
        })
        .collect();
    assert!(
        bad.is_empty(),
        "type I at three decimals off the printed digits:\n{}",
        bad.join("\n")
    );
}
