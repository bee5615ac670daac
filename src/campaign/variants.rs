//! Variants and jobs: a variant is one grid point × one Monte Carlo sample
//! (the base scene with its keys set), a job is one variant × one analysis.
//! Job `j` is variant `j / analyses` and analysis `j % analyses`; variant `v`
//! is grid point `v / samples` (last grid key fastest) and sample
//! `v % samples`. Its identity is a SHA-256 of everything that decides its
//! result: the flank version ([`flank_version`]), the analysis and its
//! options, the resolved scene text and the bytes of the files it names.

use std::path::{Path, PathBuf};

use sha2::{Digest, Sha256};

use crate::error::{FlankError, Result};
use crate::scene::overrides::set_key;
use crate::scene::Scene;

use super::file::{read_campaign_file, CampaignFile, Loc, THREADED};
use super::resources;
use super::sample;

/// flank's version in job identities: `CARGO_PKG_VERSION`, with `+<git
/// hash>` when the build saw a git checkout (`build.rs`; a commit therefore
/// invalidates finished jobs, as it may change their results).
pub fn flank_version() -> String {
    match option_env!("FLANK_GIT_HASH") {
        Some(h) if !h.is_empty() => format!("{}+{h}", env!("CARGO_PKG_VERSION")),
        _ => env!("CARGO_PKG_VERSION").to_string(),
    }
}

/// [`flank_version`] as the command line's `--version` prints it (after
/// `flank `): a program that hands jobs to a `flank` executable compares
/// the two, since job identities differ between builds.
pub fn flank_version_static() -> &'static str {
    static VERSION: std::sync::OnceLock<String> = std::sync::OnceLock::new();
    VERSION.get_or_init(flank_version)
}

/// A campaign: its file and its output folder.
#[derive(Clone, Debug)]
pub struct Campaign {
    pub file: CampaignFile,
    /// Output folder (absolute): `jobs/`, `table.csv`, …
    pub out: PathBuf,
    base: toml::Table,
}

/// One job, resolved.
#[derive(Clone, Debug)]
pub struct Job {
    pub index: usize,
    pub variant: usize,
    pub analysis: String,
    /// The scene keys set in this variant and their values, grid keys first.
    pub inputs: Vec<(String, toml::Value)>,
    /// The variant's scene (relative file paths made absolute).
    pub scene_text: String,
    /// Command-line options after `flank <analysis> <scene> --out <dir>`.
    pub options: Vec<String>,
    /// Identity (64 hex digits); the job folder is `jobs/<first 16>`.
    pub hash: String,
    /// Memory estimate (MB).
    pub memory_mb: f64,
    pub threads: usize,
}

impl Job {
    /// The job's folder name.
    pub fn id(&self) -> &str {
        &self.hash[..16]
    }
}

impl Campaign {
    /// Reads the campaign file; `out` overrides its `[campaign] out`
    /// (default `out/<name>` in the working directory).
    pub fn open(path: &Path, out: Option<&Path>) -> Result<Self> {
        let file = read_campaign_file(path)?;
        let cwd = std::env::current_dir().map_err(|e| FlankError::io(".", e))?;
        let out = match out {
            Some(o) => cwd.join(o),
            None => file
                .out
                .clone()
                .unwrap_or_else(|| cwd.join("out").join(&file.name)),
        };
        let text = crate::text_file::read_utf8(&file.scene)?;
        let base: toml::Table = toml::from_str(&text).map_err(|e| FlankError::Parse {
            file: file.scene.clone(),
            line: e
                .span()
                .map(|s| 1 + text[..s.start].matches('\n').count())
                .unwrap_or(1),
            message: e.message().trim().to_string(),
        })?;
        Ok(Self { file, out, base })
    }

    pub fn samples(&self) -> usize {
        self.file.monte_carlo.as_ref().map_or(1, |m| m.samples)
    }

    pub fn grid_points(&self) -> usize {
        self.file.grid.iter().map(|a| a.values.len()).product()
    }

    pub fn variant_count(&self) -> usize {
        self.grid_points() * self.samples()
    }

    pub fn job_count(&self) -> usize {
        self.variant_count() * self.file.analyses.len()
    }

    /// The input keys of every variant, grid keys first (the table's columns).
    pub fn input_keys(&self) -> Vec<String> {
        let mut k: Vec<String> = self.file.grid.iter().map(|a| a.key.clone()).collect();
        if let Some(m) = &self.file.monte_carlo {
            k.extend(m.keys.iter().map(|d| d.key.clone()));
        }
        k
    }

    /// The inputs of variant `v` with the campaign-file line of each.
    fn variant_inputs(&self, v: usize) -> Vec<(String, toml::Value, usize)> {
        let samples = self.samples();
        let (mut g, s) = (v / samples, v % samples);
        let mut grid = Vec::new();
        for axis in self.file.grid.iter().rev() {
            let i = g % axis.values.len();
            g /= axis.values.len();
            grid.push((axis.key.clone(), axis.values[i].clone(), axis.lines[i]));
        }
        grid.reverse();
        if let Some(m) = &self.file.monte_carlo {
            let d: Vec<_> = m.keys.iter().map(|k| &k.distribution).collect();
            for (k, x) in m.keys.iter().zip(sample::sample(m.seed, s, &d)) {
                grid.push((k.key.clone(), toml::Value::Float(x), k.line));
            }
        }
        grid
    }

    /// The scene text with the campaign's `[set]` keys, then `inputs`, set;
    /// errors are messages.
    fn scene_with(
        &self,
        inputs: &[(String, toml::Value, usize)],
    ) -> std::result::Result<String, String> {
        let mut t = self.base.clone();
        for (k, v, _) in self.file.set.iter().chain(inputs) {
            set_key(&mut t, k, v.clone()).map_err(|e| format!("`{k}`: {e}"))?;
        }
        let dir = self.file.scene.parent().unwrap_or(Path::new("."));
        absolute_paths(&mut t, dir);
        toml::to_string(&t).map_err(|e| e.to_string())
    }

    /// Parses a variant's scene; the error is the scene parser's message.
    fn check_scene(&self, text: &str) -> std::result::Result<Scene, String> {
        crate::scene::parse_scene(text, &self.file.scene).map_err(|e| match e {
            FlankError::Parse { message, .. } => message,
            e => e.to_string(),
        })
    }

    /// Job `index`, resolved and checked: its scene parses and validates,
    /// its memory estimate is known. A bad variant is an error at the
    /// campaign line of the input that breaks it.
    pub fn job(&self, index: usize) -> Result<Job> {
        let n = self.file.analyses.len();
        if index >= self.job_count() {
            return Err(FlankError::Campaign(format!(
                "job index {index} out of range: the campaign has {} jobs (0 … {})",
                self.job_count(),
                self.job_count().saturating_sub(1)
            )));
        }
        let (v, a) = (index / n, index % n);
        let inputs = self.variant_inputs(v);
        let loc = Loc {
            text: &self.file.text,
            file: &self.file.path,
        };
        let describe = |k: &str, x: &toml::Value| format!("variant {v}: `{k}` = {x}");
        let culprit = |message: String| -> FlankError {
            // the first input that breaks the scene on its own, else the combination
            if let Some(e) = self.scene_with(&[]).err().or_else(|| {
                self.scene_with(&[])
                    .ok()
                    .and_then(|t| self.check_scene(&t).err())
            }) {
                let line = self.file.set.first().map_or(self.file.scene_line, |s| s.2);
                return loc.at(line, format!("the scene with the `[set]` keys: {e}"));
            }
            for (k, x, line) in &inputs {
                let one = [(k.clone(), x.clone(), *line)];
                let bad = match self.scene_with(&one) {
                    Err(e) => Some(e),
                    Ok(t) => self.check_scene(&t).err(),
                };
                if let Some(e) = bad {
                    return loc.at(
                        *line,
                        format!("{}: the scene rejects it: {e}", describe(k, x)),
                    );
                }
            }
            let line = inputs.first().map_or(self.file.scene_line, |i| i.2);
            let all: Vec<String> = inputs
                .iter()
                .map(|(k, x, _)| format!("{k} = {x}"))
                .collect();
            loc.at(
                line,
                format!(
                    "variant {v} ({}): the scene rejects it: {message}",
                    all.join(", ")
                ),
            )
        };
        let scene_text = self.scene_with(&inputs).map_err(culprit)?;
        let scene = self.check_scene(&scene_text).map_err(culprit)?;

        let analysis = self.file.analyses[a].clone();
        let mut options = self
            .file
            .args
            .get(&analysis)
            .map(|(o, _)| o.clone())
            .unwrap_or_default();
        let threads = self.file.resources.threads;
        if THREADED.contains(&analysis.as_str()) {
            options.extend(["--threads".to_string(), threads.to_string()]);
        }
        let memory_mb = match self.file.resources.memory_gb {
            Some(gb) => gb * 1024.0,
            None => resources::estimate_mb(&analysis, &scene, &options),
        };
        let mut h = Sha256::new();
        for part in [flank_version().as_str(), analysis.as_str()]
            .into_iter()
            .chain(options.iter().map(String::as_str))
        {
            h.update(part.as_bytes());
            h.update([0x1f]);
        }
        h.update(scene_text.as_bytes());
        for p in referenced_files(&scene_text) {
            h.update([0x1e]);
            h.update(std::fs::read(&p).map_err(|e| FlankError::io(&p, e))?);
        }
        let hash = h
            .finalize()
            .iter()
            .map(|b| format!("{b:02x}"))
            .collect::<String>();
        Ok(Job {
            index,
            variant: v,
            analysis,
            inputs: inputs.into_iter().map(|(k, x, _)| (k, x)).collect(),
            scene_text,
            options,
            hash,
            memory_mb,
            threads,
        })
    }

    /// Every job, resolved and checked (the first bad variant is the error).
    pub fn jobs(&self) -> Result<Vec<Job>> {
        (0..self.job_count()).map(|i| self.job(i)).collect()
    }
}

/// Makes relative file names in the scene (string keys ending in `_csv`)
/// absolute against the scene's folder, so the scene can be written anywhere.
fn absolute_paths(t: &mut toml::Table, dir: &Path) {
    for (k, v) in t.iter_mut() {
        match v {
            toml::Value::Table(sub) => absolute_paths(sub, dir),
            toml::Value::String(s)
                if k.ends_with("_csv") && Path::new(s.as_str()).is_relative() =>
            {
                *s = dir.join(s.as_str()).to_string_lossy().into_owned();
            }
            _ => {}
        }
    }
}

/// The files a resolved scene names (keys ending in `_csv`).
fn referenced_files(scene_text: &str) -> Vec<PathBuf> {
    fn walk(t: &toml::Table, out: &mut Vec<PathBuf>) {
        for (k, v) in t {
            match v {
                toml::Value::Table(sub) => walk(sub, out),
                toml::Value::String(s) if k.ends_with("_csv") => out.push(PathBuf::from(s)),
                _ => {}
            }
        }
    }
    let mut out = Vec::new();
    if let Ok(t) = toml::from_str::<toml::Table>(scene_text) {
        walk(&t, &mut out);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        p
    }

    fn campaign(extra: &str) -> (Campaign, PathBuf) {
        // one folder per call: tests run in parallel and two calls with the
        // same `extra` once shared a folder, one truncating the other's file
        static CALLS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
        let call = CALLS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let dir =
            std::env::temp_dir().join(format!("flank-variants-{}-{call}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("papers/seed002-spur/scene.toml");
        let p = write(
            &dir,
            "c.toml",
            &format!(
                "[campaign]\nscene = \"{}\"\nanalyses = [\"ltca\", \"tca\"]\n\n[grid]\n\"load.torque_nm\" = [100.0, 200.0]\n\"mesh.teeth_in_sector\" = [3, 5]\n{extra}",
                scene.display()
            ),
        );
        (Campaign::open(&p, Some(&dir.join("out"))).unwrap(), dir)
    }

    #[test]
    fn jobs_enumerate_grid_and_analyses() {
        let (c, _) = campaign("");
        assert_eq!(c.job_count(), 8);
        let jobs = c.jobs().unwrap();
        // last grid key fastest, analyses innermost
        let j = &jobs[3];
        assert_eq!((j.variant, j.analysis.as_str()), (1, "tca"));
        assert_eq!(j.inputs[0].1, toml::Value::Float(100.0));
        assert_eq!(j.inputs[1].1, toml::Value::Integer(5));
        assert!(j.scene_text.contains("teeth_in_sector = 5"));
        assert!(j.options.is_empty(), "{:?}", j.options);
        assert_eq!(jobs[2].options, ["--threads", "1"]);
        // identities differ between variants and analyses, not between calls
        let mut ids: Vec<&str> = jobs.iter().map(Job::id).collect();
        ids.sort();
        ids.dedup();
        assert_eq!(ids.len(), 8);
        assert_eq!(c.job(3).unwrap().hash, j.hash);
    }

    #[test]
    fn bad_values_point_at_the_campaign_line() {
        let (c, _) = campaign("");
        let _ = c;
        let (c, _) = campaign("\"load.torqe_nm\" = [1.0]\n");
        let e = c.job(0).unwrap_err().to_string();
        assert!(
            e.contains("c.toml:8:") && e.contains("unknown field `torqe_nm`"),
            "{e}"
        );
        let (c, _) = campaign("\"pinion.teeth\" = [13, 2]\n");
        let e = c.jobs().unwrap_err().to_string();
        assert!(
            e.contains("c.toml:8:") && e.contains("`pinion.teeth` = 2"),
            "{e}"
        );
        let e = c.job(1000).unwrap_err().to_string();
        assert!(e.contains("out of range"), "{e}");
    }

    #[test]
    fn set_keys_come_before_the_sample() {
        let (c, _) = campaign(
            "\n[set]\n\"analyses.ltca.misalignment_urad\" = [0.0, 0.0]\n[monte_carlo]\nseed = 1\nsamples = 3\n[monte_carlo.keys]\n\"analyses.ltca.misalignment_urad.1\" = { distribution = \"uniform\", low = 10.0, high = 20.0 }\n",
        );
        assert_eq!(c.job_count(), 4 * 3 * 2);
        let j = c.job(2).unwrap();
        let t: toml::Table = toml::from_str(&j.scene_text).unwrap();
        let m = t["analyses"]["ltca"]["misalignment_urad"]
            .as_array()
            .unwrap();
        assert_eq!(m[0].as_float(), Some(0.0));
        assert!((10.0..=20.0).contains(&m[1].as_float().unwrap()));
        assert_eq!(j.inputs.len(), 3);
    }
}
