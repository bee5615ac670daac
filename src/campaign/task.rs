//! One job, run the same way under every executor (`flank campaign run-task
//! CAMPAIGN --index I`): resolve job I, skip it if done, run its analysis
//! into a temporary folder, rename that folder to `result`, write the
//! completion record last ([`super::store`]).

use std::path::Path;
use std::time::Instant;

use crate::error::{FlankError, Result};

use super::store::{self, DoneRecord};
use super::variants::{flank_version, Campaign};

/// Analyses that take `--quiet`.
const QUIET: [&str; 4] = ["compliance", "ltca", "run", "compare"];

/// What [`run_task`] did.
#[derive(Clone, Debug, PartialEq)]
pub enum TaskOutcome {
    /// Done before: nothing ran.
    AlreadyDone,
    /// Ran and finished in this many seconds.
    Finished(f64),
}

/// The argument vector (without the program name) of job `index`'s analysis
/// writing into `out_dir`.
pub fn analysis_argv(
    analysis: &str,
    scene: &Path,
    out_dir: &Path,
    options: &[String],
) -> Vec<String> {
    let mut argv = vec![
        analysis.to_string(),
        scene.to_string_lossy().into_owned(),
        "--out".into(),
        out_dir.to_string_lossy().into_owned(),
    ];
    if QUIET.contains(&analysis) {
        argv.push("--quiet".into());
    }
    argv.extend(options.iter().cloned());
    argv
}

/// `name` matches `pattern` with `*` standing for any run of characters.
pub fn glob_match(pattern: &str, name: &str) -> bool {
    let parts: Vec<&str> = pattern.split('*').collect();
    if parts.len() == 1 {
        return pattern == name;
    }
    let (first, last) = (parts[0], parts[parts.len() - 1]);
    if !name.starts_with(first) || name.len() < first.len() + last.len() || !name.ends_with(last) {
        return false;
    }
    let mut rest = &name[first.len()..name.len() - last.len()];
    for p in &parts[1..parts.len() - 1] {
        match rest.find(p) {
            Some(i) => rest = &rest[i + p.len()..],
            None => return false,
        }
    }
    true
}

/// Removes the files of a finished attempt that `keep` does not name
/// (summary.json is always kept: collect reads it); nothing when `keep` is empty.
fn prune(dir: &Path, keep: &[String]) -> Result<()> {
    if keep.is_empty() {
        return Ok(());
    }
    let entries = std::fs::read_dir(dir).map_err(|e| FlankError::io(dir, e))?;
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        if name == "summary.json" || keep.iter().any(|k| glob_match(k, &name)) {
            continue;
        }
        let p = e.path();
        let r = if p.is_dir() {
            std::fs::remove_dir_all(&p)
        } else {
            std::fs::remove_file(&p)
        };
        r.map_err(|e| FlankError::io(&p, e))?;
    }
    Ok(())
}

/// Runs job `index` of `campaign`. `analysis` runs flank with an argument
/// vector (the CLI passes its own dispatcher); relative paths in the
/// campaign's `[args]` are relative to the campaign file's folder, which is
/// the working directory while it runs.
pub fn run_task(
    campaign: &Campaign,
    index: usize,
    analysis: &dyn Fn(&[String]) -> std::result::Result<(), String>,
) -> Result<TaskOutcome> {
    let job = campaign.job(index)?;
    let out = &campaign.out;
    if store::done(out, &job).is_some() {
        return Ok(TaskOutcome::AlreadyDone);
    }
    let dir = store::prepare(out, &job)?;
    let slurm_job = std::env::var("SLURM_ARRAY_JOB_ID").ok().map(|j| {
        format!(
            "{j}_{}",
            std::env::var("SLURM_ARRAY_TASK_ID").unwrap_or_default()
        )
    });
    store::event(
        out,
        &format!(
            "start {index} {} pid {}{}",
            job.id(),
            std::process::id(),
            slurm_job
                .as_deref()
                .map(|s| format!(" slurm {s}"))
                .unwrap_or_default()
        ),
    );
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.subsec_nanos());
    let tmp = dir.join(format!("tmp-{}-{nanos}", std::process::id()));
    std::fs::create_dir_all(&tmp).map_err(|e| FlankError::io(&tmp, e))?;
    let argv = analysis_argv(&job.analysis, &dir.join("scene.toml"), &tmp, &job.options);
    if let Some(cwd) = campaign.file.path.parent() {
        std::env::set_current_dir(cwd).map_err(|e| FlankError::io(cwd, e))?;
    }
    let t0 = Instant::now();
    let result = analysis(&argv);
    let seconds = t0.elapsed().as_secs_f64();
    if let Err(message) = result {
        let _ = std::fs::remove_dir_all(&tmp);
        let rec = serde_json::json!({ "error": message, "argv": argv, "seconds": seconds });
        store::write_atomic(
            &dir.join("failed.json"),
            serde_json::to_string_pretty(&rec)
                .unwrap_or_default()
                .as_bytes(),
        )?;
        store::event(out, &format!("failed {index} {}", job.id()));
        return Err(FlankError::Campaign(format!(
            "job {index} ({}, {}): {message}",
            job.analysis,
            dir.display()
        )));
    }
    prune(&tmp, &campaign.file.keep)?;
    let result_dir = dir.join("result");
    if result_dir.exists() {
        // a previous attempt renamed its result but died before its record
        std::fs::remove_dir_all(&result_dir).map_err(|e| FlankError::io(&result_dir, e))?;
    }
    std::fs::rename(&tmp, &result_dir).map_err(|e| FlankError::io(&result_dir, e))?;
    let _ = std::fs::remove_file(dir.join("failed.json"));
    let record = DoneRecord {
        hash: job.hash.clone(),
        index,
        analysis: job.analysis.clone(),
        version: flank_version(),
        seconds,
        host: store::host_name(),
        slurm_job,
    };
    store::write_atomic(
        &dir.join("done.json"),
        serde_json::to_string_pretty(&record)
            .unwrap_or_default()
            .as_bytes(),
    )?;
    store::event(out, &format!("done {index} {} {seconds:.3}", job.id()));
    Ok(TaskOutcome::Finished(seconds))
}

/// What [`run_block`] did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BlockReport {
    /// Finished now, with seconds.
    pub finished: Vec<(usize, f64)>,
    /// Done before: not run.
    pub already_done: Vec<usize>,
    /// Failed, with the message.
    pub failed: Vec<(usize, String)>,
    /// Not run because a stop was requested (SIGINT).
    pub not_run: Vec<usize>,
}

/// Runs jobs `indices` of `campaign` one after the other in this process
/// (a local worker's block: `flank campaign run-task CAMPAIGN --index
/// 0-31`), each exactly as [`run_task`] runs it (its own temporary folder,
/// rename, completion record): a kill loses only the job under way. The
/// process keeps what the jobs share, e.g. the compliance tensors of a
/// campaign cache ([`crate::compliance::tensor_cache::ComplianceCache::shared`]),
/// so the second job of a block reads no tensor file. A failed job does
/// not stop the block; a stop request (SIGINT) does, before the next job.
/// With `job_logs`, each job's output (this process's stdout and stderr
/// while it runs) goes to its folder's `log.txt`, as the local executor
/// gives a single job's.
pub fn run_block(
    campaign: &Campaign,
    indices: &[usize],
    job_logs: bool,
    analysis: &dyn Fn(&[String]) -> std::result::Result<(), String>,
) -> Result<BlockReport> {
    let mut report = BlockReport::default();
    for (k, &index) in indices.iter().enumerate() {
        if crate::interrupt::requested() {
            report.not_run.extend_from_slice(&indices[k..]);
            break;
        }
        let job = campaign.job(index)?;
        if store::done(&campaign.out, &job).is_some() {
            report.already_done.push(index);
            continue;
        }
        let _log = if job_logs {
            let dir = store::job_dir(&campaign.out, &job);
            std::fs::create_dir_all(&dir).map_err(|e| FlankError::io(&dir, e))?;
            Some(OutputTo::file(&dir.join("log.txt"))?)
        } else {
            None
        };
        match run_task(campaign, index, analysis) {
            Ok(TaskOutcome::Finished(s)) => {
                println!("job {index}: finished in {s:.2} s");
                report.finished.push((index, s));
            }
            Ok(TaskOutcome::AlreadyDone) => {
                println!("job {index}: done before");
                report.already_done.push(index);
            }
            Err(e) => {
                eprintln!("error: {e}");
                report.failed.push((index, e.to_string()));
            }
        }
    }
    Ok(report)
}

/// This process's stdout and stderr sent to a file until dropped (then
/// back where they were).
struct OutputTo {
    #[cfg(unix)]
    saved: [i32; 2],
}

impl OutputTo {
    fn file(path: &Path) -> Result<Self> {
        use std::io::Write;
        let _ = std::io::stdout().flush();
        let _ = std::io::stderr().flush();
        let f = std::fs::File::create(path).map_err(|e| FlankError::io(path, e))?;
        #[cfg(unix)]
        {
            use std::os::fd::AsRawFd;
            // SAFETY: dup/dup2 on this process's own descriptors 1 and 2 and
            // on an open file; the copies are restored and closed in drop.
            let saved = unsafe { [libc::dup(1), libc::dup(2)] };
            let fd = f.as_raw_fd();
            let ok = saved.iter().all(|&s| s >= 0)
                && unsafe { libc::dup2(fd, 1) >= 0 && libc::dup2(fd, 2) >= 0 };
            if !ok {
                let e = std::io::Error::last_os_error();
                let g = OutputTo { saved };
                drop(g);
                return Err(FlankError::io(path, e));
            }
            Ok(OutputTo { saved })
        }
        #[cfg(not(unix))]
        {
            drop(f);
            Ok(OutputTo {})
        }
    }
}

impl Drop for OutputTo {
    fn drop(&mut self) {
        use std::io::Write;
        let _ = std::io::stdout().flush();
        let _ = std::io::stderr().flush();
        #[cfg(unix)]
        for (k, &s) in self.saved.iter().enumerate() {
            if s >= 0 {
                // SAFETY: s is this process's duplicate of descriptor k + 1
                unsafe {
                    libc::dup2(s, k as i32 + 1);
                    libc::close(s);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::glob_match;

    #[test]
    fn globs_match_like_a_shell() {
        assert!(glob_match("*.csv", "ltca_cycle.csv"));
        assert!(!glob_match("*.csv", "summary.json"));
        assert!(glob_match("ltca_*_error.*", "ltca_transmission_error.png"));
        assert!(!glob_match("ltca_*_error.*", "ltca_points.csv"));
        assert!(glob_match("summary.json", "summary.json"));
        assert!(!glob_match("a*a", "a"));
    }
}
