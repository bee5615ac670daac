//! The collected table of a campaign: one row per job with its inputs,
//! figures and run time, and its CSV form (`table.csv`). Filled by
//! [`super::collect`], written as Parquet by [`super::parquet`].

use serde_json::Value;

/// One table row.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    pub index: usize,
    pub id: String,
    pub analysis: String,
    /// `done`, `failed` or `pending`.
    pub status: String,
    pub inputs: Vec<(String, Value)>,
    pub figures: Vec<(String, f64)>,
    /// Wall time of the analysis (s).
    pub seconds: Option<f64>,
}

/// The collected campaign.
#[derive(Clone, Debug)]
pub struct Table {
    pub input_keys: Vec<String>,
    pub figure_keys: Vec<String>,
    pub rows: Vec<Row>,
}

impl Table {
    /// The figure `name` of a row, if it has one.
    pub fn figure(row: &Row, name: &str) -> Option<f64> {
        row.figures.iter().find(|(k, _)| k == name).map(|(_, x)| *x)
    }

    /// The table as CSV: index, id, analysis, status, inputs, figures,
    /// seconds; numbers with Rust's shortest round-trip formatting.
    pub fn csv(&self) -> String {
        let mut s = String::new();
        let mut head = vec![
            "index".to_string(),
            "id".into(),
            "analysis".into(),
            "status".into(),
        ];
        head.extend(self.input_keys.iter().cloned());
        head.extend(self.figure_keys.iter().cloned());
        head.push("seconds".into());
        s.push_str(
            &head
                .iter()
                .map(|h| csv_field(h))
                .collect::<Vec<_>>()
                .join(","),
        );
        s.push('\n');
        for r in &self.rows {
            let mut f = vec![
                r.index.to_string(),
                r.id.clone(),
                r.analysis.clone(),
                r.status.clone(),
            ];
            for k in &self.input_keys {
                f.push(
                    r.inputs
                        .iter()
                        .find(|(n, _)| n == k)
                        .map(|(_, v)| value_text(v))
                        .unwrap_or_default(),
                );
            }
            for k in &self.figure_keys {
                f.push(
                    Self::figure(r, k)
                        .map(|x| x.to_string())
                        .unwrap_or_default(),
                );
            }
            f.push(r.seconds.map(|x| format!("{x:.3}")).unwrap_or_default());
            s.push_str(&f.iter().map(|x| csv_field(x)).collect::<Vec<_>>().join(","));
            s.push('\n');
        }
        s
    }
}

pub(crate) fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

pub(crate) fn value_text(v: &Value) -> String {
    match v {
        Value::String(s) => s.clone(),
        v => v.to_string(),
    }
}
