//! The campaign file (TOML): a base scene, the analyses to run, a grid over
//! scene keys and/or a seeded Monte Carlo sample, resources and Slurm
//! options. Parsing and the checks that need no scene; every error is a
//! [`FlankError::Parse`] at the campaign file's line (the scene parser's
//! style, `src/scene/location.rs`).
//!
//! ```toml
//! [campaign]
//! scene = "scene.toml"                 # relative to this file
//! analyses = ["ltca"]                  # flank subcommands: mesh, compliance, ltca, run, compare, tca
//! out = "../../out/study"              # optional; relative to this file
//! figures = ["contact_ratio", "steps.*.te_urad"]   # optional summary.json paths
//! keep = ["summary.json", "*.csv"]     # optional: result files kept (summary.json always)
//!
//! [set]                                # optional: scene keys set in every variant
//! "analyses.ltca.misalignment_urad" = [0.0, 0.0]
//!
//! [args]                               # optional: fixed options per analysis
//! ltca = ["--no-condition"]
//!
//! [grid]                               # scene keys → values (cartesian product)
//! "analyses.ltca.flank_size_mm" = [1.5, 1.0, 0.75]
//!
//! [monte_carlo]
//! seed = 1
//! samples = 100
//! [monte_carlo.keys]
//! "pinion.micro.helix_slope_deviation_um" = { distribution = "normal", mean = 0.0, sd = 3.0 }
//!
//! [resources]
//! threads = 1                          # per job
//! memory_gb = 0.5                      # per job; default: estimated
//! time_min = 30                        # Slurm --time per task
//!
//! [slurm]
//! max_parallel = 8                     # array throttle %N
//!
//! [convergence]
//! key = "analyses.ltca.flank_size_mm"  # grid key holding the cell size
//! reference = "run"                    # optional: whose extrapolation is the
//!                                      # reference of error against run time
//! ```

use std::collections::BTreeMap;
use std::ops::Range;
use std::path::{Path, PathBuf};

use serde::Deserialize;
use toml::Spanned;

use crate::error::{FlankError, Result};

use super::sample::Distribution;

/// The flank subcommands a campaign job may run.
pub const ANALYSES: [&str; 6] = ["mesh", "compliance", "ltca", "run", "compare", "tca"];

/// The subcommands that take `--threads`.
pub const THREADED: [&str; 4] = ["compliance", "ltca", "run", "compare"];

/// A parsed campaign file (paths absolute).
#[derive(Clone, Debug)]
pub struct CampaignFile {
    /// The campaign file.
    pub path: PathBuf,
    /// The file's text (for error lines of later checks).
    pub text: String,
    pub name: String,
    /// The base scene (absolute).
    pub scene: PathBuf,
    pub scene_line: usize,
    pub analyses: Vec<String>,
    pub analyses_line: usize,
    /// Fixed command-line options per analysis.
    pub args: BTreeMap<String, (Vec<String>, usize)>,
    /// Scene keys set in every variant (before the grid and the sample),
    /// with their lines.
    pub set: Vec<(String, toml::Value, usize)>,
    /// Grid axes in file order.
    pub grid: Vec<GridAxis>,
    pub monte_carlo: Option<MonteCarlo>,
    pub resources: Resources,
    pub slurm: SlurmOptions,
    pub convergence: Option<Convergence>,
    /// summary.json paths to collect (empty: every number, see collect).
    pub figures: Vec<String>,
    /// Output folder from the file (absolute), if given.
    pub out: Option<PathBuf>,
    /// File names of a job's result to keep (`*` wildcards); empty: all.
    pub keep: Vec<String>,
}

/// One grid key and its values.
#[derive(Clone, Debug)]
pub struct GridAxis {
    pub key: String,
    pub values: Vec<toml::Value>,
    /// Line of each value.
    pub lines: Vec<usize>,
    pub line: usize,
}

/// The Monte Carlo part: `samples` draws of every key, seeded.
#[derive(Clone, Debug)]
pub struct MonteCarlo {
    pub seed: u64,
    pub samples: usize,
    pub keys: Vec<Draw>,
    pub line: usize,
}

/// One sampled scene key.
#[derive(Clone, Debug)]
pub struct Draw {
    pub key: String,
    pub distribution: Distribution,
    pub line: usize,
}

/// Per-job resources.
#[derive(Clone, Debug)]
pub struct Resources {
    /// Threads per job (`--threads` of the analysis, Slurm cpus-per-task).
    pub threads: usize,
    /// Memory per job (GB) instead of the estimate.
    pub memory_gb: Option<f64>,
    pub memory_line: usize,
    /// Wall time per job (min), for Slurm.
    pub time_min: f64,
}

/// Slurm options.
#[derive(Clone, Debug, Default)]
pub struct SlurmOptions {
    /// Array throttle `%N` (0: none).
    pub max_parallel: usize,
    pub partition: Option<String>,
    /// Extra `#SBATCH` options, e.g. `--account=abc`.
    pub sbatch: Vec<String>,
}

/// The mesh-convergence study: the grid key whose values are the cell sizes.
#[derive(Clone, Debug)]
pub struct Convergence {
    pub key: String,
    /// Roache's safety factor F_s (1.25 for three or more grids).
    pub safety_factor: f64,
    /// The analysis whose Richardson-extrapolated figures are the reference
    /// of every analysis's error against run time (e.g. `run`, FE contact,
    /// for `ltca`); none: each analysis against its own extrapolation.
    pub reference: Option<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Raw {
    campaign: RawCampaign,
    #[serde(default)]
    args: BTreeMap<Spanned<String>, Spanned<Vec<String>>>,
    #[serde(default)]
    set: BTreeMap<Spanned<String>, Spanned<toml::Value>>,
    #[serde(default)]
    grid: BTreeMap<Spanned<String>, Spanned<Vec<Spanned<toml::Value>>>>,
    monte_carlo: Option<Spanned<RawMonteCarlo>>,
    resources: Option<RawResources>,
    slurm: Option<RawSlurm>,
    convergence: Option<RawConvergence>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawCampaign {
    name: Option<String>,
    scene: Spanned<String>,
    analyses: Spanned<Vec<Spanned<String>>>,
    out: Option<String>,
    #[serde(default)]
    figures: Vec<String>,
    #[serde(default)]
    keep: Vec<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawMonteCarlo {
    seed: Spanned<i64>,
    samples: Spanned<i64>,
    keys: BTreeMap<Spanned<String>, Spanned<RawDraw>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawDraw {
    distribution: Spanned<String>,
    mean: Option<f64>,
    sd: Option<f64>,
    low: Option<f64>,
    high: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawResources {
    threads: Option<Spanned<i64>>,
    memory_gb: Option<Spanned<f64>>,
    time_min: Option<Spanned<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSlurm {
    max_parallel: Option<Spanned<i64>>,
    partition: Option<String>,
    #[serde(default)]
    sbatch: Vec<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawConvergence {
    key: Spanned<String>,
    safety_factor: Option<Spanned<f64>>,
    reference: Option<Spanned<String>>,
}

/// Text and file for errors at file:line.
pub(super) struct Loc<'a> {
    pub text: &'a str,
    pub file: &'a Path,
}

impl Loc<'_> {
    pub fn line(&self, offset: usize) -> usize {
        let end = offset.min(self.text.len());
        1 + self.text.as_bytes()[..end]
            .iter()
            .filter(|&&b| b == b'\n')
            .count()
    }

    pub fn at(&self, line: usize, message: String) -> FlankError {
        FlankError::Parse {
            file: self.file.to_path_buf(),
            line,
            message,
        }
    }

    pub fn err(&self, span: Range<usize>, message: String) -> FlankError {
        self.at(self.line(span.start), message)
    }
}

/// Reads and parses a campaign file (no scene is read yet: see
/// [`super::variants`]).
pub fn read_campaign_file(path: &Path) -> Result<CampaignFile> {
    let text = crate::text_file::read_utf8(path)?;
    parse_campaign_file(&text, path)
}

/// Parses campaign text; `path` names the file and anchors relative paths.
pub fn parse_campaign_file(text: &str, path: &Path) -> Result<CampaignFile> {
    let loc = Loc { text, file: path };
    let raw: Raw = toml::from_str(text).map_err(|e| {
        let line = e.span().map(|s| loc.line(s.start)).unwrap_or(1);
        loc.at(line, e.message().trim().to_string())
    })?;
    let base = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."))
        .canonicalize()
        .map_err(|e| FlankError::io(path, e))?;
    let c = raw.campaign;

    let scene_line = loc.line(c.scene.span().start);
    let scene = base.join(c.scene.get_ref());
    if !scene.is_file() {
        return Err(loc.at(
            scene_line,
            format!(
                "`campaign.scene` = \"{}\": no such file ({})",
                c.scene.get_ref(),
                scene.display()
            ),
        ));
    }

    let analyses_line = loc.line(c.analyses.span().start);
    if c.analyses.get_ref().is_empty() {
        return Err(loc.at(
            analyses_line,
            format!(
                "`campaign.analyses` is empty: name at least one of {}",
                ANALYSES.join(", ")
            ),
        ));
    }
    let mut analyses = Vec::new();
    for a in c.analyses.get_ref() {
        if !ANALYSES.contains(&a.get_ref().as_str()) {
            return Err(loc.err(
                a.span(),
                format!(
                    "`campaign.analyses`: unknown analysis \"{}\" (one of {})",
                    a.get_ref(),
                    ANALYSES.join(", ")
                ),
            ));
        }
        if analyses.contains(a.get_ref()) {
            return Err(loc.err(
                a.span(),
                format!("`campaign.analyses`: \"{}\" twice", a.get_ref()),
            ));
        }
        analyses.push(a.get_ref().clone());
    }

    let mut args = BTreeMap::new();
    for (k, v) in raw.args {
        let line = loc.line(k.span().start);
        if !analyses.contains(k.get_ref()) {
            return Err(loc.at(
                line,
                format!(
                    "`args.{}`: not an analysis of this campaign ({})",
                    k.get_ref(),
                    analyses.join(", ")
                ),
            ));
        }
        for a in v.get_ref() {
            for reserved in ["--out", "--threads", "--quiet", "-q"] {
                if a == reserved || a.starts_with(&format!("{reserved}=")) {
                    return Err(loc.at(
                        line,
                        format!(
                            "`args.{}`: `{reserved}` is set by the campaign",
                            k.get_ref()
                        ),
                    ));
                }
            }
        }
        args.insert(k.into_inner(), (v.into_inner(), line));
    }

    let mut set = Vec::new();
    for (k, v) in raw.set {
        let line = loc.line(k.span().start);
        check_key(&loc, k.get_ref(), line, "set")?;
        set.push((k.into_inner(), v.into_inner(), line));
    }
    set.sort_by_key(|s| s.2);

    let mut grid: Vec<GridAxis> = Vec::new();
    for (k, v) in raw.grid {
        let line = loc.line(k.span().start);
        check_key(&loc, k.get_ref(), line, "grid")?;
        if v.get_ref().is_empty() {
            return Err(loc.at(
                line,
                format!("`grid.\"{}\"`: empty list of values", k.get_ref()),
            ));
        }
        let lines = v
            .get_ref()
            .iter()
            .map(|x| loc.line(x.span().start))
            .collect();
        grid.push(GridAxis {
            key: k.into_inner(),
            values: v
                .into_inner()
                .into_iter()
                .map(Spanned::into_inner)
                .collect(),
            lines,
            line,
        });
    }
    grid.sort_by_key(|a| a.line);

    let monte_carlo = match raw.monte_carlo {
        None => None,
        Some(m) => {
            let line = loc.line(m.span().start);
            let m = m.into_inner();
            let seed = *m.seed.get_ref();
            if seed < 0 {
                return Err(loc.err(
                    m.seed.span(),
                    format!("`monte_carlo.seed` = {seed}: must be ≥ 0"),
                ));
            }
            let samples = *m.samples.get_ref();
            if !(1..=10_000_000).contains(&samples) {
                return Err(loc.err(
                    m.samples.span(),
                    format!("`monte_carlo.samples` = {samples}: must be 1 … 10 000 000"),
                ));
            }
            if m.keys.is_empty() {
                return Err(loc.at(
                    line,
                    "`monte_carlo.keys` is empty: give at least one sampled scene key".into(),
                ));
            }
            let mut keys = Vec::new();
            for (k, d) in m.keys {
                let kline = loc.line(k.span().start);
                check_key(&loc, k.get_ref(), kline, "monte_carlo.keys")?;
                if grid.iter().any(|a| &a.key == k.get_ref()) {
                    return Err(loc.at(
                        kline,
                        format!("`{}` is both a grid key and a sampled key", k.get_ref()),
                    ));
                }
                let d = d.into_inner();
                let distribution =
                    Distribution::new(d.distribution.get_ref(), d.mean, d.sd, d.low, d.high)
                        .map_err(|e| {
                            loc.at(
                                kline,
                                format!("`monte_carlo.keys.\"{}\"`: {e}", k.get_ref()),
                            )
                        })?;
                keys.push(Draw {
                    key: k.into_inner(),
                    distribution,
                    line: kline,
                });
            }
            keys.sort_by_key(|d| d.line);
            Some(MonteCarlo {
                seed: seed as u64,
                samples: samples as usize,
                keys,
                line,
            })
        }
    };

    let mut resources = Resources {
        threads: 1,
        memory_gb: None,
        memory_line: 1,
        time_min: 60.0,
    };
    if let Some(r) = raw.resources {
        if let Some(t) = r.threads {
            let n = *t.get_ref();
            if !(1..=1024).contains(&n) {
                return Err(loc.err(
                    t.span(),
                    format!("`resources.threads` = {n}: must be 1 … 1024"),
                ));
            }
            resources.threads = n as usize;
        }
        if let Some(m) = r.memory_gb {
            let x = *m.get_ref();
            resources.memory_line = loc.line(m.span().start);
            if !(x.is_finite() && x > 0.0) {
                return Err(loc.err(
                    m.span(),
                    format!("`resources.memory_gb` = {x}: must be a positive number"),
                ));
            }
            resources.memory_gb = Some(x);
        }
        if let Some(t) = r.time_min {
            let x = *t.get_ref();
            if !(x.is_finite() && x > 0.0) {
                return Err(loc.err(
                    t.span(),
                    format!("`resources.time_min` = {x}: must be a positive number"),
                ));
            }
            resources.time_min = x;
        }
    }

    let mut slurm = SlurmOptions::default();
    if let Some(s) = raw.slurm {
        if let Some(n) = s.max_parallel {
            let x = *n.get_ref();
            if !(0..=100_000).contains(&x) {
                return Err(loc.err(
                    n.span(),
                    format!("`slurm.max_parallel` = {x}: must be 0 (no throttle) … 100 000"),
                ));
            }
            slurm.max_parallel = x as usize;
        }
        slurm.partition = s.partition;
        slurm.sbatch = s.sbatch;
    }

    let convergence = match raw.convergence {
        None => None,
        Some(c) => {
            let line = loc.line(c.key.span().start);
            let Some(axis) = grid.iter().find(|a| &a.key == c.key.get_ref()) else {
                return Err(loc.at(
                    line,
                    format!(
                        "`convergence.key` = \"{}\": not a grid key (the grid holds the cell sizes)",
                        c.key.get_ref()
                    ),
                ));
            };
            let sizes: Vec<f64> = axis
                .values
                .iter()
                .filter_map(toml::Value::as_float)
                .collect();
            if sizes.len() != axis.values.len() || sizes.iter().any(|h| !(*h > 0.0)) {
                return Err(loc.at(
                    axis.line,
                    format!(
                        "`grid.\"{}\"`: the convergence key's values must be positive floats (cell sizes)",
                        axis.key
                    ),
                ));
            }
            if sizes.len() < 3 {
                return Err(loc.at(
                    axis.line,
                    format!(
                        "`grid.\"{}\"`: a convergence study needs at least three cell sizes, got {}",
                        axis.key,
                        sizes.len()
                    ),
                ));
            }
            let safety_factor = match c.safety_factor {
                None => 1.25,
                Some(f) => {
                    let x = *f.get_ref();
                    if !(x.is_finite() && x >= 1.0) {
                        return Err(loc.err(
                            f.span(),
                            format!("`convergence.safety_factor` = {x}: must be ≥ 1"),
                        ));
                    }
                    x
                }
            };
            let reference = match c.reference {
                None => None,
                Some(r) if analyses.contains(r.get_ref()) => Some(r.into_inner()),
                Some(r) => {
                    return Err(loc.err(
                        r.span(),
                        format!(
                        "`convergence.reference` = \"{}\": not one of the campaign's analyses ({})",
                        r.get_ref(),
                        analyses.join(", ")
                    ),
                    ))
                }
            };
            Some(Convergence {
                key: c.key.into_inner(),
                safety_factor,
                reference,
            })
        }
    };

    let name = c.name.unwrap_or_else(|| {
        path.file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "campaign".into())
    });
    Ok(CampaignFile {
        path: base.join(path.file_name().unwrap_or_default()),
        text: text.to_string(),
        name,
        scene,
        scene_line,
        analyses,
        analyses_line,
        args,
        set,
        grid,
        monte_carlo,
        resources,
        slurm,
        convergence,
        figures: c.figures,
        out: c.out.map(|o| base.join(o)),
        keep: c.keep,
    })
}

/// A scene key: dot-separated, non-empty parts.
fn check_key(loc: &Loc, key: &str, line: usize, table: &str) -> Result<()> {
    if key.is_empty() || key.split('.').any(str::is_empty) {
        return Err(loc.at(
            line,
            format!("`{table}`: \"{key}\" is not a scene key (dot-separated, e.g. \"mesh.flank_size_mm\")"),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    pub(crate) fn scene_path() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("papers/seed002-spur/campaign_test.toml")
    }

    fn err(text: &str) -> (usize, String) {
        match parse_campaign_file(text, &scene_path()).unwrap_err() {
            FlankError::Parse { line, message, .. } => (line, message),
            e => panic!("{e}"),
        }
    }

    const OK: &str = "[campaign]\nscene = \"scene.toml\"\nanalyses = [\"ltca\"]\n\n[grid]\n\"load.torque_nm\" = [100.0, 200.0]\n";

    #[test]
    fn parses_a_grid() {
        let c = parse_campaign_file(OK, &scene_path()).unwrap();
        assert_eq!(c.analyses, ["ltca"]);
        assert_eq!(c.grid.len(), 1);
        assert_eq!(c.grid[0].lines, [6, 6]);
        assert_eq!(c.name, "campaign_test");
    }

    #[test]
    fn bad_files_name_the_line() {
        let (l, m) = err(&OK.replace("[grid]", "[grid]\nbogus_table = 1\n[gird]"));
        assert!(
            m.contains("invalid type") || m.contains("unknown"),
            "{l} {m}"
        );
        let (l, m) = err(&OK.replace("[100.0, 200.0]", "[]"));
        assert_eq!(l, 6);
        assert!(m.contains("empty list"), "{m}");
        let (l, m) = err(&OK.replace("\"ltca\"", "\"ltcb\""));
        assert_eq!(l, 3);
        assert!(m.contains("unknown analysis \"ltcb\""), "{m}");
        let (l, m) = err(&format!("{OK}[resources]\nthreeds = 2\n"));
        assert_eq!(l, 8);
        assert!(m.contains("unknown field `threeds`"), "{m}");
        let (l, m) = err(&format!(
            "{OK}[monte_carlo]\nseed = 1\nsamples = 4\n[monte_carlo.keys]\n\"load.speed_rpm\" = {{ distribution = \"normal\", mean = 1.0, sd = -2.0 }}\n"
        ));
        assert_eq!(l, 11);
        assert!(m.contains("sd") && m.contains("-2"), "{m}");
        let (l, m) = err(&OK.replace("scene.toml", "nope.toml"));
        assert_eq!(l, 2);
        assert!(m.contains("no such file"), "{m}");
        let (l, m) = err(&format!("{OK}[convergence]\nkey = \"load.torque_nm\"\n"));
        assert_eq!(l, 6);
        assert!(m.contains("at least three"), "{m}");
        let three = OK.replace("[100.0, 200.0]", "[100.0, 200.0, 400.0]");
        let (l, m) = err(&format!(
            "{three}[convergence]\nkey = \"load.torque_nm\"\nreference = \"run\"\n"
        ));
        assert_eq!(l, 9);
        assert!(m.contains("`convergence.reference` = \"run\""), "{m}");
        let c = parse_campaign_file(
            &format!("{three}[convergence]\nkey = \"load.torque_nm\"\nreference = \"ltca\"\n"),
            &scene_path(),
        )
        .unwrap();
        assert_eq!(c.convergence.unwrap().reference.as_deref(), Some("ltca"));
        let (l, m) = err(&format!("{OK}[args]\nltca = [\"--out\", \"x\"]\n"));
        assert_eq!(l, 8);
        assert!(m.contains("`--out` is set by the campaign"), "{m}");
    }
}
