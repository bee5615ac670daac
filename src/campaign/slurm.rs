//! The Slurm executor: `flank campaign submit` writes one `sbatch` job-array
//! script per chunk of at most `MaxArraySize − 1` jobs (Slurm's default
//! MaxArraySize is 1001) and submits it; array task `t` of a chunk with
//! offset `o` runs `flank campaign run-task CAMPAIGN --out OUT --index o+t`,
//! the same code as the local executor. `--mem` is the largest estimate of
//! the chunk's jobs, `--cpus-per-task` the campaign's threads, `--time` its
//! `time_min`, the throttle `%N` its `slurm.max_parallel`. Only jobs not
//! done are submitted, so a resubmission runs the failed (and lost) ones
//! alone. `status` follows the submissions with `squeue` and the job
//! folders' records (sacct needs Slurm's accounting database, which many
//! clusters have and a test cluster does not; it is not needed here).
//!
//! The flank executable and the output folder must be on a file system
//! the compute nodes share (they are on a one-node cluster).

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

use crate::error::{FlankError, Result};

use super::store;
use super::variants::{Campaign, Job};

/// Largest array task id + 1 accepted by Slurm's default configuration.
pub const DEFAULT_MAX_ARRAY_SIZE: usize = 1001;

/// One submitted array.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct Submission {
    pub slurm_job: String,
    pub script: PathBuf,
    /// Job index = offset + array task id.
    pub offset: usize,
    pub indices: Vec<usize>,
}

/// `0-3,5,7-9`: Slurm's array index list of sorted `ids`.
pub fn index_list(ids: &[usize]) -> String {
    let mut parts = Vec::new();
    let mut i = 0;
    while i < ids.len() {
        let mut j = i;
        while j + 1 < ids.len() && ids[j + 1] == ids[j] + 1 {
            j += 1;
        }
        parts.push(if i == j {
            ids[i].to_string()
        } else {
            format!("{}-{}", ids[i], ids[j])
        });
        i = j + 1;
    }
    parts.join(",")
}

fn quote(s: &str) -> String {
    format!("'{}'", s.replace('\'', "'\\''"))
}

/// The sbatch script of `jobs` (indices offset + task id).
pub fn array_script(campaign: &Campaign, exe: &Path, jobs: &[&Job], offset: usize) -> String {
    let tasks: Vec<usize> = jobs.iter().map(|j| j.index - offset).collect();
    let mem_mb = jobs.iter().map(|j| j.memory_mb).fold(0.0, f64::max).ceil() as u64;
    let f = &campaign.file;
    let throttle = match f.slurm.max_parallel {
        0 => String::new(),
        n => format!("%{n}"),
    };
    let logs = campaign.out.join("slurm").join("logs");
    let mut s = String::from("#!/bin/sh\n");
    s.push_str(&format!("#SBATCH --job-name=flank-{}\n", f.name));
    s.push_str(&format!(
        "#SBATCH --array={}{throttle}\n",
        index_list(&tasks)
    ));
    s.push_str("#SBATCH --ntasks=1\n");
    s.push_str(&format!(
        "#SBATCH --cpus-per-task={}\n",
        f.resources.threads
    ));
    s.push_str(&format!("#SBATCH --mem={mem_mb}M\n"));
    s.push_str(&format!(
        "#SBATCH --time={}\n",
        f.resources.time_min.ceil().max(1.0) as u64
    ));
    s.push_str(&format!("#SBATCH --output={}/%A_%a.out\n", logs.display()));
    if let Some(p) = &f.slurm.partition {
        s.push_str(&format!("#SBATCH --partition={p}\n"));
    }
    for extra in &f.slurm.sbatch {
        s.push_str(&format!("#SBATCH {extra}\n"));
    }
    s.push_str(&format!(
        "# flank campaign {} — array task t runs job {offset} + t\nexec {} campaign run-task {} --out {} --index $(( {offset} + SLURM_ARRAY_TASK_ID ))\n",
        f.path.display(),
        quote(&exe.to_string_lossy()),
        quote(&f.path.to_string_lossy()),
        quote(&campaign.out.to_string_lossy()),
    ));
    s
}

fn submissions_path(out: &Path) -> PathBuf {
    out.join("slurm").join("submissions.json")
}

/// The campaign's submissions so far.
pub fn submissions(out: &Path) -> Vec<Submission> {
    std::fs::read_to_string(submissions_path(out))
        .ok()
        .and_then(|t| serde_json::from_str(&t).ok())
        .unwrap_or_default()
}

/// Writes and submits the array scripts of the jobs not done; returns the
/// new submissions (none when every job is done).
pub fn submit(
    campaign: &Campaign,
    jobs: &[Job],
    exe: &Path,
    max_array_size: usize,
) -> Result<Vec<Submission>> {
    let out = &campaign.out;
    let dir = out.join("slurm");
    let logs = dir.join("logs");
    std::fs::create_dir_all(&logs).map_err(|e| FlankError::io(&logs, e))?;
    let pending: Vec<&Job> = jobs
        .iter()
        .filter(|j| store::done(out, j).is_none())
        .collect();
    for j in &pending {
        store::prepare(out, j)?;
    }
    let chunk = max_array_size.max(2) - 1;
    let mut all = submissions(out);
    let mut new = Vec::new();
    let mut k = 0;
    while k < pending.len() {
        let offset = pending[k].index / chunk * chunk;
        let group: Vec<&Job> = pending[k..]
            .iter()
            .take_while(|j| j.index < offset + chunk)
            .copied()
            .collect();
        k += group.len();
        let script = dir.join(format!("array_{}_{offset}.sh", all.len() + new.len()));
        store::write_atomic(
            &script,
            array_script(campaign, exe, &group, offset).as_bytes(),
        )?;
        let o = Command::new("sbatch")
            .arg("--parsable")
            .arg(&script)
            .output()
            .map_err(|e| {
                FlankError::Campaign(format!(
                    "cannot run sbatch (is Slurm installed and SLURM_CONF set?): {e}"
                ))
            })?;
        if !o.status.success() {
            return Err(FlankError::Campaign(format!(
                "sbatch {} failed: {}",
                script.display(),
                String::from_utf8_lossy(&o.stderr).trim()
            )));
        }
        let id = String::from_utf8_lossy(&o.stdout)
            .trim()
            .split(';')
            .next()
            .unwrap_or("")
            .to_string();
        store::event(out, &format!("submit slurm {id} jobs {}", group.len()));
        new.push(Submission {
            slurm_job: id,
            script,
            offset,
            indices: group.iter().map(|j| j.index).collect(),
        });
    }
    all.extend(new.iter().cloned());
    store::write_atomic(
        &submissions_path(out),
        serde_json::to_string_pretty(&all)
            .unwrap_or_default()
            .as_bytes(),
    )?;
    Ok(new)
}

/// The state of a campaign under Slurm.
#[derive(Clone, Debug, Default)]
pub struct Status {
    pub done: usize,
    /// Job index → Slurm state (PENDING, RUNNING, …) of queued tasks.
    pub queued: Vec<(usize, String)>,
    /// Not done, not queued, submitted: failed or lost (killed by Slurm for
    /// time or memory), with the task's log.
    pub failed: Vec<(usize, PathBuf)>,
    /// Never submitted.
    pub unsubmitted: usize,
}

/// Asks squeue which of the campaign's tasks are queued or running.
pub fn status(campaign: &Campaign, jobs: &[Job]) -> Result<Status> {
    let out = &campaign.out;
    let subs = submissions(out);
    let mut queued = Vec::new();
    if !subs.is_empty() {
        let ids: Vec<&str> = subs.iter().map(|s| s.slurm_job.as_str()).collect();
        let o = Command::new("squeue")
            .args(["-h", "-r", "-o", "%i %T", "-j", &ids.join(",")])
            .output()
            .map_err(|e| FlankError::Campaign(format!("cannot run squeue: {e}")))?;
        let text = String::from_utf8_lossy(&o.stdout);
        if !o.status.success() && !String::from_utf8_lossy(&o.stderr).contains("Invalid job id") {
            return Err(FlankError::Campaign(format!(
                "squeue failed: {}",
                String::from_utf8_lossy(&o.stderr).trim()
            )));
        }
        for line in text.lines() {
            let mut f = line.split_whitespace();
            let (Some(id), Some(state)) = (f.next(), f.next()) else {
                continue;
            };
            let Some((array, task)) = id.split_once('_') else {
                continue;
            };
            let Some(s) = subs.iter().find(|s| s.slurm_job == array) else {
                continue;
            };
            // a pending array shows as 123_[4-9]: expand the bracket
            let tasks = task.trim_start_matches('[').trim_end_matches(']');
            let tasks = tasks.split('%').next().unwrap_or("");
            for part in tasks.split(',') {
                let (a, b) = part.split_once('-').unwrap_or((part, part));
                if let (Ok(a), Ok(b)) = (a.parse::<usize>(), b.parse::<usize>()) {
                    for t in a..=b {
                        queued.push((s.offset + t, state.to_string()));
                    }
                }
            }
        }
    }
    let mut st = Status::default();
    for j in jobs {
        if store::done(out, j).is_some() {
            st.done += 1;
        } else if queued.iter().any(|(i, _)| *i == j.index) {
        } else if let Some(s) = subs.iter().rev().find(|s| s.indices.contains(&j.index)) {
            let log = out.join("slurm").join("logs").join(format!(
                "{}_{}.out",
                s.slurm_job,
                j.index - s.offset
            ));
            st.failed.push((j.index, log));
        } else {
            st.unsubmitted += 1;
        }
    }
    queued.sort();
    queued.dedup();
    st.queued = queued;
    Ok(st)
}

/// Polls [`status`] every `poll` until nothing of the campaign is queued,
/// at most `timeout`; the error says how far it got.
pub fn wait(
    campaign: &Campaign,
    jobs: &[Job],
    timeout: Duration,
    poll: Duration,
) -> Result<Status> {
    let t0 = Instant::now();
    loop {
        let st = status(campaign, jobs)?;
        if st.queued.is_empty() {
            return Ok(st);
        }
        if t0.elapsed() >= timeout {
            return Err(FlankError::Campaign(format!(
                "waited {:.0} s: {} done, {} still queued or running (first: job {} {})",
                timeout.as_secs_f64(),
                st.done,
                st.queued.len(),
                st.queued[0].0,
                st.queued[0].1
            )));
        }
        std::thread::sleep(poll);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn index_lists_compress_runs() {
        assert_eq!(index_list(&[0, 1, 2, 3, 5, 7, 8, 9]), "0-3,5,7-9");
        assert_eq!(index_list(&[4]), "4");
        assert_eq!(index_list(&[]), "");
        assert_eq!(quote("a'b"), "'a'\\''b'");
    }
}
