//! The local executor: a pool of worker threads, each running one job at a
//! time as a child process (`flank campaign run-task CAMPAIGN --index I`,
//! the program being this executable), so a crash or kill of one job
//! cannot corrupt another. Workers: cores / threads per job (or `workers`);
//! a job starts only while the running jobs' memory estimates plus its own
//! fit the budget (the machine's available memory by default), and a job
//! whose estimate exceeds the machine is refused before anything starts.

use std::collections::VecDeque;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::{Condvar, Mutex};
use std::time::Instant;

use crate::error::{FlankError, Result};

use super::resources;
use super::store;
use super::variants::{Campaign, Job};

/// Options of [`run_local`].
#[derive(Clone, Debug)]
pub struct LocalOptions {
    /// The flank executable (normally `std::env::current_exe()`).
    pub exe: PathBuf,
    /// Parallel jobs (default: cores / threads per job).
    pub workers: Option<usize>,
    /// Memory budget (MB; default: the machine's available memory).
    pub memory_mb: Option<f64>,
    /// No progress output.
    pub quiet: bool,
}

/// What [`run_local`] did.
#[derive(Clone, Debug, Default)]
pub struct LocalReport {
    pub jobs: usize,
    /// Done before this run (not run again).
    pub skipped: usize,
    pub finished: usize,
    /// Failed jobs: index and log file.
    pub failed: Vec<(usize, PathBuf)>,
    pub workers: usize,
    pub wall_s: f64,
}

/// Checks every job's memory estimate against `budget_mb` (MB) and the
/// machine's memory: the error names the first job that cannot fit.
pub fn check_memory(campaign: &Campaign, jobs: &[Job], budget_mb: f64) -> Result<()> {
    if let Some(j) = jobs.iter().find(|j| j.memory_mb > budget_mb) {
        let what = match campaign.file.resources.memory_gb {
            Some(_) => format!("`resources.memory_gb` = {:.2} GB", j.memory_mb / 1024.0),
            None => format!(
                "an estimated {:.2} GB (src/campaign/resources.rs; set `resources.memory_gb` if the rule does not fit)",
                j.memory_mb / 1024.0
            ),
        };
        let inputs: Vec<String> = j.inputs.iter().map(|(k, v)| format!("{k} = {v}")).collect();
        return Err(FlankError::Campaign(format!(
            "{}: job {} ({}{}{}) needs {what}, more than the {:.2} GB this machine can give: run it on a larger machine (flank campaign submit) or coarsen it",
            campaign.file.path.display(),
            j.index,
            j.analysis,
            if inputs.is_empty() { "" } else { ", " },
            inputs.join(", "),
            budget_mb / 1024.0
        )));
    }
    Ok(())
}

struct Pool {
    queue: VecDeque<usize>,
    memory_in_use: f64,
    running: usize,
}

/// Runs the jobs not done yet, in parallel, each in its own process.
pub fn run_local(campaign: &Campaign, jobs: &[Job], options: &LocalOptions) -> Result<LocalReport> {
    let t0 = Instant::now();
    let budget = match options.memory_mb {
        Some(m) => m,
        None => resources::machine_memory_mb().map_or(f64::INFINITY, |(_, avail)| avail),
    };
    check_memory(campaign, jobs, budget)?;
    let out = &campaign.out;
    std::fs::create_dir_all(out.join("jobs")).map_err(|e| FlankError::io(out, e))?;
    let pending: Vec<usize> = (0..jobs.len())
        .filter(|&i| store::done(out, &jobs[i]).is_none())
        .collect();
    let threads = campaign.file.resources.threads.max(1);
    let workers = options
        .workers
        .unwrap_or_else(|| (resources::cores() / threads).max(1))
        .clamp(1, pending.len().max(1));
    let mut report = LocalReport {
        jobs: jobs.len(),
        skipped: jobs.len() - pending.len(),
        workers,
        ..Default::default()
    };
    if !options.quiet {
        eprintln!(
            "{}: {} jobs, {} done before, {} to run on {workers} workers ({} thread(s) each, memory budget {:.1} GB)",
            campaign.file.name,
            jobs.len(),
            report.skipped,
            pending.len(),
            threads,
            budget / 1024.0
        );
    }
    store::event(
        out,
        &format!("run pid {} pending {}", std::process::id(), pending.len()),
    );
    let bar = progress_bar(pending.len(), options.quiet);
    let pool = Mutex::new(Pool {
        queue: pending.into_iter().collect(),
        memory_in_use: 0.0,
        running: 0,
    });
    let cv = Condvar::new();
    let outcomes: Mutex<Vec<(usize, bool, PathBuf)>> = Mutex::new(Vec::new());
    let campaign_dir = campaign.file.path.parent().unwrap_or(Path::new("."));
    let spawn_error: Mutex<Option<FlankError>> = Mutex::new(None);

    std::thread::scope(|s| {
        for _ in 0..workers {
            s.spawn(|| loop {
                let i = {
                    let mut p = pool.lock().unwrap_or_else(|e| e.into_inner());
                    loop {
                        if p.queue.is_empty() {
                            return;
                        }
                        let fits = p.queue.iter().position(|&i| {
                            p.running == 0 || p.memory_in_use + jobs[i].memory_mb <= budget
                        });
                        if let Some(k) = fits {
                            let i = p.queue.remove(k).unwrap_or_default();
                            p.memory_in_use += jobs[i].memory_mb;
                            p.running += 1;
                            break i;
                        }
                        p = cv.wait(p).unwrap_or_else(|e| e.into_inner());
                    }
                };
                let job = &jobs[i];
                let ok = match run_child(campaign, job, &options.exe, campaign_dir) {
                    Ok((ok, log)) => {
                        outcomes.lock().unwrap_or_else(|e| e.into_inner()).push((
                            i,
                            ok,
                            log.clone(),
                        ));
                        let line = if ok {
                            format!("job {i} ({}) done", job.analysis)
                        } else {
                            format!("job {i} ({}) FAILED: see {}", job.analysis, log.display())
                        };
                        if !options.quiet {
                            match &bar {
                                Some(b) => b.println(line),
                                None => eprintln!("{line}"),
                            }
                        }
                        ok
                    }
                    Err(e) => {
                        spawn_error
                            .lock()
                            .unwrap_or_else(|e| e.into_inner())
                            .get_or_insert(e);
                        false
                    }
                };
                let _ = ok;
                if let Some(b) = &bar {
                    b.inc(1);
                }
                let mut p = pool.lock().unwrap_or_else(|e| e.into_inner());
                p.memory_in_use -= job.memory_mb;
                p.running -= 1;
                cv.notify_all();
            });
        }
    });
    if let Some(b) = &bar {
        b.finish_and_clear();
    }
    if let Some(e) = spawn_error.into_inner().unwrap_or_else(|e| e.into_inner()) {
        return Err(e);
    }
    let mut outcomes = outcomes.into_inner().unwrap_or_else(|e| e.into_inner());
    outcomes.sort_by_key(|o| o.0);
    for (i, ok, log) in outcomes {
        if ok {
            report.finished += 1;
        } else {
            report.failed.push((i, log));
        }
    }
    report.wall_s = t0.elapsed().as_secs_f64();
    Ok(report)
}

fn progress_bar(n: usize, quiet: bool) -> Option<indicatif::ProgressBar> {
    use std::io::IsTerminal;
    if quiet || !std::io::stderr().is_terminal() {
        return None;
    }
    let b = indicatif::ProgressBar::new(n as u64);
    if let Ok(style) = indicatif::ProgressStyle::with_template(
        "{bar:40} {pos}/{len} jobs, {elapsed} elapsed, ETA {eta}",
    ) {
        b.set_style(style);
    }
    Some(b)
}

/// Runs one job as a child process, its output in the job's `log.txt`;
/// whether it finished, and the log.
fn run_child(campaign: &Campaign, job: &Job, exe: &Path, cwd: &Path) -> Result<(bool, PathBuf)> {
    let dir = store::job_dir(&campaign.out, job);
    std::fs::create_dir_all(&dir).map_err(|e| FlankError::io(&dir, e))?;
    let log_path = dir.join("log.txt");
    let log = std::fs::File::create(&log_path).map_err(|e| FlankError::io(&log_path, e))?;
    let log2 = log.try_clone().map_err(|e| FlankError::io(&log_path, e))?;
    let mut cmd = Command::new(exe);
    cmd.arg("campaign")
        .arg("run-task")
        .arg(&campaign.file.path)
        .arg("--index")
        .arg(job.index.to_string())
        .arg("--out")
        .arg(&campaign.out)
        .current_dir(cwd)
        .stdin(Stdio::null())
        .stdout(log)
        .stderr(log2);
    #[cfg(target_os = "linux")]
    {
        use std::os::unix::process::CommandExt;
        // SAFETY: prctl is async-signal-safe; it only sets this child's
        // parent-death signal, so a killed campaign takes its jobs with it
        // (they would otherwise run on unseen; the next run redoes them).
        unsafe {
            cmd.pre_exec(|| {
                libc::prctl(libc::PR_SET_PDEATHSIG, libc::SIGKILL);
                Ok(())
            });
        }
    }
    let status = cmd
        .status()
        .map_err(|e| FlankError::Campaign(format!("cannot start {}: {e}", exe.display())))?;
    Ok((status.success(), log_path))
}
