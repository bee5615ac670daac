//! Collection: one table of every job's figures (`table.csv`), and the
//! summaries: GCI per figure for a mesh study (`convergence.csv`), the
//! distribution of each figure for a Monte Carlo sample (`montecarlo.csv`,
//! `hist_*.png/svg`), and `summary.md` with both. Convergence skips time and
//! memory columns ([`is_time_column`]) and integer-valued figures (counts).
//!
//! Figures come from each job's `result/summary.json`: the campaign's
//! `figures` paths (dot-separated, `*` expands an array or object), or by
//! default every number at the top level, in top-level objects, and in
//! numeric arrays of at most four values (`name.0`, …); `steps` and
//! `settings` are left out unless named. `table.parquet` holds the same
//! columns ([`super::parquet`]); the table itself is [`super::table::Table`].

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde_json::Value;

use crate::error::{FlankError, Result};

use super::stats;
use super::store;
use super::table::{csv_field, value_text, Row, Table};
use super::variants::{Campaign, Job};
use crate::grid_convergence::gci;

/// A column of run time or memory, not a result: left out of comparisons,
/// convergence and statistics (names ending `_s`, or with `time` or
/// `memory`).
pub fn is_time_column(name: &str) -> bool {
    let last = name.rsplit('.').next().unwrap_or(name);
    name == "seconds" || last.ends_with("_s") || name.contains("time") || name.contains("memory")
}

/// Numbers of `v` at `path` (`a.b.*.c`), named by their concrete path.
fn select(v: &Value, path: &[&str], prefix: String, out: &mut Vec<(String, f64)>) {
    let join = |p: &str| {
        if prefix.is_empty() {
            p.to_string()
        } else {
            format!("{prefix}.{p}")
        }
    };
    let Some((head, rest)) = path.split_first() else {
        match v {
            Value::Number(n) => out.extend(n.as_f64().map(|x| (prefix, x))),
            Value::Array(a) => {
                for (i, x) in a.iter().enumerate() {
                    if let Some(x) = x.as_f64() {
                        out.push((join(&i.to_string()), x));
                    }
                }
            }
            _ => {}
        }
        return;
    };
    match (v, *head) {
        (Value::Array(a), "*") => {
            for (i, x) in a.iter().enumerate() {
                select(x, rest, join(&i.to_string()), out);
            }
        }
        (Value::Object(o), "*") => {
            for (k, x) in o {
                select(x, rest, join(k), out);
            }
        }
        (Value::Array(a), h) => {
            if let Some(x) = h.parse::<usize>().ok().and_then(|i| a.get(i)) {
                select(x, rest, join(h), out);
            }
        }
        (Value::Object(o), h) => {
            if let Some(x) = o.get(h) {
                select(x, rest, join(h), out);
            }
        }
        _ => {}
    }
}

/// The default figures of a summary (see the module doc).
fn default_figures(v: &Value) -> Vec<(String, f64)> {
    let mut out = Vec::new();
    let Value::Object(o) = v else { return out };
    for (k, x) in o {
        if k == "steps" || k == "settings" {
            continue;
        }
        match x {
            Value::Number(n) => out.extend(n.as_f64().map(|f| (k.clone(), f))),
            Value::Array(a) if a.len() <= 4 && a.iter().all(Value::is_number) => {
                select(x, &[], k.clone(), &mut out)
            }
            Value::Object(inner) => {
                for (k2, y) in inner {
                    if let Some(f) = y.as_f64() {
                        out.push((format!("{k}.{k2}"), f));
                    }
                }
            }
            _ => {}
        }
    }
    out
}

/// Reads every job's state and figures.
pub fn collect(campaign: &Campaign, jobs: &[Job]) -> Result<Table> {
    let out = &campaign.out;
    let mut figure_keys: Vec<String> = Vec::new();
    let mut rows = Vec::with_capacity(jobs.len());
    for j in jobs {
        let done = store::done(out, j);
        let status = if done.is_some() {
            "done"
        } else if store::failed(out, j).is_some() {
            "failed"
        } else {
            "pending"
        };
        let mut figures = Vec::new();
        if done.is_some() {
            let p = store::job_dir(out, j).join("result").join("summary.json");
            let text = std::fs::read_to_string(&p).map_err(|e| FlankError::io(&p, e))?;
            let v: Value = serde_json::from_str(&text)
                .map_err(|e| FlankError::Campaign(format!("{}: {e}", p.display())))?;
            if campaign.file.figures.is_empty() {
                figures = default_figures(&v);
            } else {
                for f in &campaign.file.figures {
                    let path: Vec<&str> = f.split('.').collect();
                    select(&v, &path, String::new(), &mut figures);
                }
            }
        }
        for (k, _) in &figures {
            if !figure_keys.contains(k) {
                figure_keys.push(k.clone());
            }
        }
        rows.push(Row {
            index: j.index,
            id: j.id().to_string(),
            analysis: j.analysis.clone(),
            status: status.into(),
            inputs: j
                .inputs
                .iter()
                .map(|(k, v)| (k.clone(), store::toml_to_json(v)))
                .collect(),
            figures,
            seconds: done.map(|d| d.seconds),
        });
    }
    Ok(Table {
        input_keys: campaign.input_keys(),
        figure_keys,
        rows,
    })
}

/// Rows grouped by analysis and the inputs other than `except`, in
/// first-seen order: (label "analysis, k = v, …", the inputs part alone,
/// rows).
fn groups<'a>(table: &'a Table, except: &[String]) -> Vec<(String, String, Vec<&'a Row>)> {
    let mut order: Vec<(String, String)> = Vec::new();
    let mut map: BTreeMap<String, Vec<&Row>> = BTreeMap::new();
    for r in table.rows.iter().filter(|r| r.status == "done") {
        let mut context = Vec::new();
        for (k, v) in &r.inputs {
            if !except.contains(k) {
                context.push(format!("{k} = {}", value_text(v)));
            }
        }
        let context = context.join(", ");
        let key = if context.is_empty() {
            r.analysis.clone()
        } else {
            format!("{}, {context}", r.analysis)
        };
        if !map.contains_key(&key) {
            order.push((key.clone(), context));
        }
        map.entry(key).or_default().push(r);
    }
    order
        .into_iter()
        .map(|(k, context)| {
            let rows = map.remove(&k).unwrap_or_default();
            (k, context, rows)
        })
        .collect()
}

/// A group of a mesh study (one analysis, the same other inputs) and its
/// done levels (cell size, row), finest first.
struct GroupLevels<'a> {
    label: String,
    context: String,
    analysis: String,
    levels: Vec<(f64, &'a Row)>,
}

/// One level of a mesh study: a figure's value and run time, and the
/// reference of its error (the Richardson-extrapolated value of the
/// reference analysis, or of its own group) with that estimate's GCI.
struct ErrorPoint {
    figure: String,
    group: String,
    h: f64,
    seconds: f64,
    value: f64,
    reference: f64,
    reference_gci: Option<f64>,
}

impl ErrorPoint {
    fn relative_error(&self) -> f64 {
        ((self.value - self.reference) / self.reference).abs()
    }
}

/// `error_vs_time.csv` and, per figure, `error_vs_time_<figure>` (svg,
/// png): |φ − φ_ref| / |φ_ref| against the job's run time, both
/// logarithmic, one series per group (analysis and the other inputs), the
/// reference's GCI_fine dashed (below it an error is not resolved): the
/// error-against-run-time front of the methods of a mesh study.
fn write_error_against_time(
    out: &Path,
    points: &[ErrorPoint],
    reference: &str,
) -> Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    if points.is_empty() {
        return Ok(files);
    }
    let opt = |x: Option<f64>| x.map(|x| x.to_string()).unwrap_or_default();
    let mut csv =
        String::from("figure,group,h,seconds,value,reference,reference_gci,relative_error\n");
    for p in points {
        csv.push_str(&format!(
            "{},{},{},{},{},{},{},{}\n",
            csv_field(&p.figure),
            csv_field(&p.group),
            p.h,
            p.seconds,
            p.value,
            p.reference,
            opt(p.reference_gci),
            p.relative_error()
        ));
    }
    let path = out.join("error_vs_time.csv");
    store::write_atomic(&path, csv.as_bytes())?;
    files.push(path);
    let mut figures: Vec<&str> = Vec::new();
    for p in points {
        if !figures.contains(&p.figure.as_str()) {
            figures.push(&p.figure);
        }
    }
    for f in figures {
        let mut series: Vec<super::plots::ErrorSeries> = Vec::new();
        for p in points.iter().filter(|p| p.figure == f) {
            let e = p.relative_error();
            match series.iter_mut().find(|s| s.name == p.group) {
                Some(s) => s.points.push((p.seconds, e)),
                None => series.push(super::plots::ErrorSeries {
                    name: p.group.clone(),
                    points: vec![(p.seconds, e)],
                    floor: p.reference_gci,
                }),
            }
        }
        for name in super::plots::error_against_time(
            out,
            &format!("error_vs_time_{}", sanitize(f)),
            &format!("{f}: error against {reference}"),
            &series,
        )? {
            files.push(out.join(name));
        }
    }
    Ok(files)
}

/// What [`write_all`] wrote.
#[derive(Clone, Debug, Default)]
pub struct Written {
    pub files: Vec<PathBuf>,
    pub done: usize,
    pub pending: usize,
    pub failed: usize,
}

/// Writes table.csv, convergence.csv / montecarlo.csv with their plots and
/// summary.md into the campaign's folder (each file atomically).
pub fn write_all(campaign: &Campaign, table: &Table) -> Result<Written> {
    let out = &campaign.out;
    std::fs::create_dir_all(out).map_err(|e| FlankError::io(out, e))?;
    let mut w = Written::default();
    for r in &table.rows {
        match r.status.as_str() {
            "done" => w.done += 1,
            "failed" => w.failed += 1,
            _ => w.pending += 1,
        }
    }
    let mut md = format!(
        "# Campaign {}\n\n{} jobs: {} done, {} failed, {} pending. Table: `table.csv` (and `table.parquet`). flank {}\n\n",
        campaign.file.name,
        table.rows.len(),
        w.done,
        w.failed,
        w.pending,
        super::variants::flank_version()
    );
    let p = out.join("table.csv");
    store::write_atomic(&p, table.csv().as_bytes())?;
    w.files.push(p);
    let p = out.join("table.parquet");
    super::parquet::write_table(table, &p)?;
    w.files.push(p);
    let figures: Vec<&String> = table
        .figure_keys
        .iter()
        .filter(|k| !is_time_column(k))
        .collect();

    if let Some(conv) = &campaign.file.convergence {
        let mut csv = String::from(
            "group,figure,h1,h2,h3,phi1,phi2,phi3,order,extrapolated,approximate_error,extrapolated_error,gci_fine,oscillatory,note\n",
        );
        md.push_str(&format!(
            "## Mesh convergence (`{}`; Celik et al. 2008 / Roache 1998, F_s = {})\n\n| group | figure | φ1 (h1) | φ2 | φ3 | p | φ_ext | GCI_fine |\n|---|---|---|---|---|---|---|---|\n",
            conv.key, conv.safety_factor
        ));
        // every group's levels, and the extrapolation of each (analysis,
        // inputs, figure): the references of the error against run time
        let mut levels: Vec<GroupLevels> = Vec::new();
        let mut extrapolated: BTreeMap<(String, String, String), (f64, Option<f64>)> =
            BTreeMap::new();
        for (group, context, rows) in groups(table, std::slice::from_ref(&conv.key)) {
            let mut hs: Vec<(f64, &Row)> = rows
                .iter()
                .filter_map(|r| {
                    let h = r.inputs.iter().find(|(k, _)| *k == conv.key)?.1.as_f64()?;
                    Some((h, *r))
                })
                .collect();
            hs.sort_by(|a, b| a.0.total_cmp(&b.0));
            let analysis = hs.first().map(|(_, r)| r.analysis.clone());
            levels.push(GroupLevels {
                label: group.clone(),
                context: context.clone(),
                analysis: analysis.clone().unwrap_or_default(),
                levels: hs.clone(),
            });
            if hs.len() < 3 {
                continue;
            }
            let three = [hs[0], hs[1], hs[2]];
            for f in &figures {
                let vals: Option<Vec<f64>> =
                    three.iter().map(|(_, r)| Table::figure(r, f)).collect();
                let Some(v) = vals else { continue };
                let h = [three[0].0, three[1].0, three[2].0];
                let phi = [v[0], v[1], v[2]];
                if phi.iter().all(|x| x.fract() == 0.0) {
                    continue; // counts (nodes, DOFs, positions) are not discretised results
                }
                let opt = |x: Option<f64>| x.map(|x| x.to_string()).unwrap_or_default();
                let estimate = gci(h, phi, conv.safety_factor);
                if let (Ok(g), Some(a)) = (&estimate, &analysis) {
                    extrapolated.insert(
                        (a.clone(), context.clone(), f.to_string()),
                        (g.extrapolated, g.gci_fine),
                    );
                }
                let (cols, note, mdrow) = match estimate {
                    Ok(g) => (
                        format!(
                            "{},{},{},{},{},{}",
                            g.order,
                            g.extrapolated,
                            opt(g.approximate_error),
                            opt(g.extrapolated_error),
                            opt(g.gci_fine),
                            g.oscillatory
                        ),
                        String::new(),
                        format!(
                            "{:.3}{} | {:.6} | {}",
                            g.order,
                            if g.oscillatory { " (osc.)" } else { "" },
                            g.extrapolated,
                            g.gci_fine
                                .map_or("—".into(), |x| format!("{:.3} %", 100.0 * x))
                        ),
                    ),
                    Err(issue) => (
                        ",,,,,".into(),
                        issue.to_string(),
                        format!("— | — | {issue}"),
                    ),
                };
                csv.push_str(&format!(
                    "{},{},{},{},{},{},{},{},{cols},{}\n",
                    csv_field(&group),
                    csv_field(f),
                    h[0],
                    h[1],
                    h[2],
                    phi[0],
                    phi[1],
                    phi[2],
                    csv_field(&note)
                ));
                md.push_str(&format!(
                    "| {group} | {f} | {:.6} ({}) | {:.6} | {:.6} | {mdrow} |\n",
                    phi[0], h[0], phi[1], phi[2]
                ));
            }
        }
        md.push('\n');
        let p = out.join("convergence.csv");
        store::write_atomic(&p, csv.as_bytes())?;
        w.files.push(p);
        let mut error_time: Vec<ErrorPoint> = Vec::new();
        for g in &levels {
            let (group, context, hs) = (&g.label, &g.context, &g.levels);
            let reference = conv.reference.as_ref().unwrap_or(&g.analysis);
            for f in &figures {
                let key = (reference.clone(), context.clone(), f.to_string());
                let Some(&(reference, reference_gci)) = extrapolated.get(&key) else {
                    continue;
                };
                if reference == 0.0 {
                    continue;
                }
                for (h, r) in hs {
                    if let (Some(seconds), Some(value)) = (r.seconds, Table::figure(r, f)) {
                        error_time.push(ErrorPoint {
                            figure: f.to_string(),
                            group: group.clone(),
                            h: *h,
                            seconds,
                            value,
                            reference,
                            reference_gci,
                        });
                    }
                }
            }
        }
        let reference = match &conv.reference {
            Some(a) => format!("the extrapolated `{a}`"),
            None => "its own extrapolation".to_string(),
        };
        let written = write_error_against_time(out, &error_time, &reference)?;
        if !written.is_empty() {
            md.push_str(&format!(
                "Error against run time (`error_vs_time.csv`, `error_vs_time_<figure>.svg/png`): each level's |φ − φ_ref| / |φ_ref| against its wall time, φ_ref {reference}, {} points.\n\n",
                error_time.len()
            ));
        }
        w.files.extend(written);
    }

    if let Some(mc) = &campaign.file.monte_carlo {
        let sampled: Vec<String> = mc.keys.iter().map(|d| d.key.clone()).collect();
        let mut head = "group,figure,n,mean,sd,min,p5,p25,p50,p75,p95,max".to_string();
        for k in &sampled {
            head.push_str(&format!(",{}", csv_field(&format!("spearman[{k}]"))));
        }
        let mut csv = head + "\n";
        md.push_str(&format!(
            "## Monte Carlo ({} samples, seed {})\n\n| group | figure | n | mean | sd | p5 | p50 | p95 | Spearman ρ ({}) |\n|---|---|---|---|---|---|---|---|---|\n",
            mc.samples,
            mc.seed,
            sampled.join(", ")
        ));
        for (gi, (group, _, rows)) in groups(table, &sampled).into_iter().enumerate() {
            for f in &figures {
                let pairs: Vec<(&Row, f64)> = rows
                    .iter()
                    .filter_map(|r| Table::figure(r, f).map(|x| (*r, x)))
                    .collect();
                if pairs.is_empty() {
                    continue;
                }
                let ys: Vec<f64> = pairs.iter().map(|p| p.1).collect();
                let mut sorted = ys.clone();
                sorted.sort_by(f64::total_cmp);
                let q = |p: f64| {
                    stats::percentile(&sorted, p)
                        .map(|x| x.to_string())
                        .unwrap_or_default()
                };
                let sd = stats::std_dev(&ys);
                let rho: Vec<Option<f64>> = sampled
                    .iter()
                    .map(|k| {
                        let xs: Vec<f64> = pairs
                            .iter()
                            .filter_map(|(r, _)| r.inputs.iter().find(|(n, _)| n == k)?.1.as_f64())
                            .collect();
                        (xs.len() == ys.len())
                            .then(|| stats::spearman(&xs, &ys))
                            .flatten()
                    })
                    .collect();
                csv.push_str(&format!(
                    "{},{},{},{},{},{},{},{},{},{},{},{}",
                    csv_field(&group),
                    csv_field(f),
                    ys.len(),
                    stats::mean(&ys),
                    sd.map(|x| x.to_string()).unwrap_or_default(),
                    q(0.0),
                    q(5.0),
                    q(25.0),
                    q(50.0),
                    q(75.0),
                    q(95.0),
                    q(100.0)
                ));
                for r in &rho {
                    csv.push_str(&format!(
                        ",{}",
                        r.map(|x| x.to_string()).unwrap_or_default()
                    ));
                }
                csv.push('\n');
                let qf = |p: f64| stats::percentile(&sorted, p).unwrap_or(f64::NAN);
                md.push_str(&format!(
                    "| {group} | {f} | {} | {:.6} | {} | {:.6} | {:.6} | {:.6} | {} |\n",
                    ys.len(),
                    stats::mean(&ys),
                    sd.map_or("—".into(), |x| format!("{x:.4e}")),
                    qf(5.0),
                    qf(50.0),
                    qf(95.0),
                    rho.iter()
                        .map(|r| r.map_or("—".into(), |x| format!("{x:+.3}")))
                        .collect::<Vec<_>>()
                        .join(", ")
                ));
                if ys.len() >= 2 && sorted.first() != sorted.last() {
                    let stem = format!("hist_{gi}_{}", sanitize(f));
                    for name in
                        super::plots::histogram(out, &stem, &format!("{f} ({group})"), f, &ys, 0)?
                    {
                        w.files.push(out.join(name));
                    }
                }
            }
        }
        let p = out.join("montecarlo.csv");
        store::write_atomic(&p, csv.as_bytes())?;
        w.files.push(p);
    }
    let p = out.join("summary.md");
    store::write_atomic(&p, md.as_bytes())?;
    w.files.push(p);
    Ok(w)
}

fn sanitize(s: &str) -> String {
    s.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '_' {
                c
            } else {
                '-'
            }
        })
        .collect()
}

/// Reads a table.csv back as rows of fields (for comparisons in tests and
/// scripts): a header and rows, quoted fields unquoted.
pub fn read_csv(path: &Path) -> Result<(Vec<String>, Vec<Vec<String>>)> {
    let text = std::fs::read_to_string(path).map_err(|e| FlankError::io(path, e))?;
    let mut lines = text.lines().map(split_csv);
    let head = lines.next().unwrap_or_default();
    Ok((head, lines.collect()))
}

/// A campaign's figures: `DIR/table.csv` without its time and memory
/// columns ([`is_time_column`]), which differ between two runs of the same
/// jobs (to compare executors, or a resumed run with an uninterrupted one).
pub fn read_figures(dir: &Path) -> Result<(Vec<String>, Vec<Vec<String>>)> {
    let (head, rows) = read_csv(&dir.join("table.csv"))?;
    let keep: Vec<usize> = (0..head.len())
        .filter(|&i| !is_time_column(&head[i]))
        .collect();
    Ok((
        keep.iter().map(|&i| head[i].clone()).collect(),
        rows.iter()
            .map(|r| keep.iter().map(|&i| r[i].clone()).collect())
            .collect(),
    ))
}

fn split_csv(line: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut cur = String::new();
    let mut quoted = false;
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match (c, quoted) {
            ('"', true) if chars.peek() == Some(&'"') => {
                cur.push('"');
                chars.next();
            }
            ('"', _) => quoted = !quoted,
            (',', false) => out.push(std::mem::take(&mut cur)),
            (c, _) => cur.push(c),
        }
    }
    out.push(cur);
    out
}

#[cfg(test)]
mod tests {
    use super::super::variants::Campaign;
    use super::*;

    #[test]
    fn figures_are_selected_by_path() {
        let v: Value = serde_json::from_str(
            r#"{"a": 1.5, "b": [1, 2], "c": {"d": 3}, "steps": [{"te": 4, "f": [5, 6]}, {"te": 7, "f": [8, 9]}], "s": "x"}"#,
        )
        .unwrap();
        let d = default_figures(&v);
        let names: Vec<&str> = d.iter().map(|x| x.0.as_str()).collect();
        assert_eq!(names, ["a", "b.0", "b.1", "c.d"]);
        let mut out = Vec::new();
        select(&v, &["steps", "*", "f", "1"], String::new(), &mut out);
        assert_eq!(
            out,
            [
                ("steps.0.f.1".to_string(), 6.0),
                ("steps.1.f.1".to_string(), 9.0)
            ]
        );
        let mut out = Vec::new();
        select(&v, &["steps", "*", "f"], String::new(), &mut out);
        assert_eq!(out.len(), 4);
        assert!(is_time_column("setup.compliance_s") && is_time_column("peak_memory_mb"));
        assert!(!is_time_column("contact_ratio"));
        assert_eq!(split_csv("a,\"b,c\",\"d\"\"e\""), ["a", "b,c", "d\"e"]);
    }

    /// A mesh study of two methods: `run` converging to 10 (φ = 10 + 0.5 h²)
    /// and `ltca` to 10.2 (φ = 10.2 + 0.1 h²), at h = 1, ½, ¼, with run
    /// times. Against the extrapolated `run`, LTCA's error tends to 2 %; each
    /// against its own extrapolation, to 0.
    #[test]
    fn error_against_run_time_uses_the_reference_analysis() {
        let dir = std::env::temp_dir().join(format!("flank-collect-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("papers/seed002-spur/scene.toml");
        let file = |reference: &str| {
            let p = dir.join(format!("c{}.toml", reference.len()));
            std::fs::write(
                &p,
                format!(
                    "[campaign]\nscene = \"{}\"\nanalyses = [\"ltca\", \"run\"]\nfigures = [\"te\"]\n\n[grid]\n\"mesh.flank_size_mm\" = [1.0, 0.5, 0.25]\n\n[convergence]\nkey = \"mesh.flank_size_mm\"\n{reference}",
                    scene.display()
                ),
            )
            .unwrap();
            p
        };
        let mut rows = Vec::new();
        for (k, h) in [1.0, 0.5, 0.25].into_iter().enumerate() {
            for (analysis, limit, c, t) in [("ltca", 10.2, 0.1, 0.01), ("run", 10.0, 0.5, 10.0)] {
                rows.push(Row {
                    index: rows.len(),
                    id: format!("{analysis}{k}"),
                    analysis: analysis.into(),
                    status: "done".into(),
                    inputs: vec![("mesh.flank_size_mm".into(), Value::from(h))],
                    figures: vec![("te".into(), limit + c * h * h)],
                    seconds: Some(t / (h * h)),
                });
            }
        }
        let table = Table {
            input_keys: vec!["mesh.flank_size_mm".into()],
            figure_keys: vec!["te".into()],
            rows,
        };
        let read = |out: &Path| {
            let (head, rows) = read_csv(&out.join("error_vs_time.csv")).unwrap();
            assert_eq!(
                head,
                [
                    "figure",
                    "group",
                    "h",
                    "seconds",
                    "value",
                    "reference",
                    "reference_gci",
                    "relative_error"
                ]
            );
            rows
        };

        let c = Campaign::open(&file("reference = \"run\"\n"), Some(&dir.join("a"))).unwrap();
        let w = write_all(&c, &table).unwrap();
        let rows = read(&c.out);
        assert_eq!(rows.len(), 6);
        for r in &rows {
            let reference: f64 = r[5].parse().unwrap();
            assert!((reference - 10.0).abs() < 1e-9, "{r:?}");
            let (h, e): (f64, f64) = (r[2].parse().unwrap(), r[7].parse().unwrap());
            let expected = match r[1].as_str() {
                "ltca" => (0.2 + 0.1 * h * h) / 10.0,
                "run" => 0.05 * h * h,
                g => panic!("group {g}"),
            };
            assert!((e - expected).abs() < 1e-12, "{r:?}: {expected}");
        }
        // the extrapolation from exact h² data is exact: GCI_fine = F_s |e_ext| / …
        assert!(rows.iter().all(|r| !r[6].is_empty()));
        for ext in ["svg", "png"] {
            let p = c.out.join(format!("error_vs_time_te.{ext}"));
            assert!(
                w.files.contains(&p) && p.metadata().unwrap().len() > 0,
                "{p:?}"
            );
        }

        let c = Campaign::open(&file(""), Some(&dir.join("b"))).unwrap();
        write_all(&c, &table).unwrap();
        for r in read(&c.out) {
            let (h, e, reference): (f64, f64, f64) = (
                r[2].parse().unwrap(),
                r[7].parse().unwrap(),
                r[5].parse().unwrap(),
            );
            let (limit, coefficient) = if r[1] == "ltca" {
                (10.2, 0.1)
            } else {
                (10.0, 0.5)
            };
            assert!((reference - limit).abs() < 1e-9, "{r:?}");
            assert!((e - coefficient * h * h / limit).abs() < 1e-12, "{r:?}");
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
