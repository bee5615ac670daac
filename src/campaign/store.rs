//! The campaign's output folder: one folder per job, named by its identity,
//! results made visible by a rename and completed by a record written last.
//!
//! ```text
//! OUT/events.log                  start/done/failed lines, appended
//! OUT/jobs/<id>/scene.toml        the variant's scene
//! OUT/jobs/<id>/job.json          analysis, options, inputs, estimate
//! OUT/jobs/<id>/log.txt           the job's output (local executor)
//! OUT/jobs/<id>/tmp-<pid>-<n>/    a running attempt (removed on failure/rerun)
//! OUT/jobs/<id>/result/           the finished attempt's files (renamed from tmp)
//! OUT/jobs/<id>/done.json         completion record, written last (tmp + rename)
//! OUT/jobs/<id>/failed.json       the last failure's message
//! ```
//!
//! A job is done exactly when `done.json` exists and names its identity: a
//! kill before the record leaves a `tmp-*` folder or a `result` folder
//! without record, both removed by the next attempt.

use std::io::Write;
use std::path::{Path, PathBuf};

use crate::error::{FlankError, Result};

use super::variants::{flank_version, Job};

/// The folder of `job` under `out`.
pub fn job_dir(out: &Path, job: &Job) -> PathBuf {
    out.join("jobs").join(job.id())
}

/// Writes `bytes` to `path` atomically (temporary name, sync, rename):
/// [`crate::atomic_file::write`].
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    crate::atomic_file::write(path, bytes)
}

/// The completion record of a job.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct DoneRecord {
    pub hash: String,
    pub index: usize,
    pub analysis: String,
    pub version: String,
    /// Wall time of the analysis (s).
    pub seconds: f64,
    /// Where it ran (host name, Slurm job id if any).
    pub host: String,
    pub slurm_job: Option<String>,
}

/// The completion record of `job`, if it is done (a record naming another
/// identity, e.g. from a hash-prefix collision, is not).
pub fn done(out: &Path, job: &Job) -> Option<DoneRecord> {
    let text = std::fs::read_to_string(job_dir(out, job).join("done.json")).ok()?;
    let r: DoneRecord = serde_json::from_str(&text).ok()?;
    (r.hash == job.hash).then_some(r)
}

/// The last failure message of `job`, if its last attempt failed.
pub fn failed(out: &Path, job: &Job) -> Option<String> {
    let text = std::fs::read_to_string(job_dir(out, job).join("failed.json")).ok()?;
    let v: serde_json::Value = serde_json::from_str(&text).ok()?;
    Some(v["error"].as_str().unwrap_or("").to_string())
}

/// Whether `job`'s last attempt failed at or after `since` (its
/// `failed.json` was written then).
pub fn failed_since(out: &Path, job: &Job, since: std::time::SystemTime) -> bool {
    std::fs::metadata(job_dir(out, job).join("failed.json"))
        .and_then(|m| m.modified())
        .is_ok_and(|t| t >= since)
}

/// Creates the job's folder with its scene and description (idempotent),
/// and removes what an interrupted attempt left: `tmp-*` folders and a
/// `result` folder without completion record.
pub fn prepare(out: &Path, job: &Job) -> Result<PathBuf> {
    let dir = job_dir(out, job);
    std::fs::create_dir_all(&dir).map_err(|e| FlankError::io(&dir, e))?;
    let entries = std::fs::read_dir(&dir).map_err(|e| FlankError::io(&dir, e))?;
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        if name.starts_with("tmp-") || (name == "result" && done(out, job).is_none()) {
            let p = e.path();
            std::fs::remove_dir_all(&p).map_err(|e| FlankError::io(&p, e))?;
        }
    }
    write_atomic(&dir.join("scene.toml"), job.scene_text.as_bytes())?;
    let inputs: serde_json::Map<String, serde_json::Value> = job
        .inputs
        .iter()
        .map(|(k, v)| (k.clone(), toml_to_json(v)))
        .collect();
    let desc = serde_json::json!({
        "index": job.index,
        "variant": job.variant,
        "analysis": job.analysis,
        "options": job.options,
        "inputs": inputs,
        "hash": job.hash,
        "memory_mb": job.memory_mb,
        "threads": job.threads,
        "version": flank_version(),
    });
    write_atomic(
        &dir.join("job.json"),
        serde_json::to_string_pretty(&desc)
            .unwrap_or_default()
            .as_bytes(),
    )?;
    Ok(dir)
}

/// A TOML value as JSON (for records and tables).
pub fn toml_to_json(v: &toml::Value) -> serde_json::Value {
    serde_json::to_value(v).unwrap_or(serde_json::Value::Null)
}

/// Appends one line to `OUT/events.log` (one `write` of a short line with
/// O_APPEND: lines of concurrent jobs do not interleave).
pub fn event(out: &Path, line: &str) {
    let path = out.join("events.log");
    if let Ok(mut f) = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(&path)
    {
        let _ = f.write_all(format!("{line}\n").as_bytes());
    }
}

/// This machine's name (for records): /etc/hostname or `HOSTNAME`.
pub fn host_name() -> String {
    std::fs::read_to_string("/proc/sys/kernel/hostname")
        .ok()
        .map(|s| s.trim().to_string())
        .filter(|s| !s.is_empty())
        .or_else(|| std::env::var("HOSTNAME").ok())
        .unwrap_or_else(|| "unknown".into())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn atomic_write_replaces_whole_files() {
        let dir = std::env::temp_dir().join(format!("flank-store-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("r.json");
        write_atomic(&p, b"first").unwrap();
        write_atomic(&p, b"second").unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"second");
        // no temporary left behind
        let names: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .flatten()
            .map(|e| e.file_name())
            .collect();
        assert_eq!(names.len(), 1, "{names:?}");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
