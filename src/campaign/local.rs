//! The local executor: a pool of worker threads, each running a block of
//! jobs at a time in a child process (`flank campaign run-task CAMPAIGN
//! --index 40-71`, the program being this executable; a block of one job
//! is `--index I`), so a crash or kill of one process cannot corrupt
//! another's jobs, and the jobs of a block share what the process keeps
//! (cached compliance tensors: [`super::task::run_block`]). Workers: cores
//! / threads per job (or `workers`); a block starts only while the running
//! blocks' memory estimates plus its own (its largest job's) fit the budget
//! (the machine's available memory by default), and a job whose estimate
//! exceeds the machine is refused before anything starts.

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
    /// Jobs per worker process (default [`default_batch`]).
    pub batch: Option<usize>,
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

/// Jobs per worker process when not given: the pending jobs / (4 ×
/// workers), within 1 … [`MAX_BATCH`]: blocks long enough that a process
/// start, a scene's meshing setup and a tensor read are paid once per
/// block, short enough that the workers finish together (4 blocks each at
/// least) and that a few slow jobs (FE contact) still get one process each.
pub fn default_batch(pending: usize, workers: usize) -> usize {
    pending.div_ceil(4 * workers.max(1)).clamp(1, MAX_BATCH)
}

/// The largest default block.
pub const MAX_BATCH: usize = 32;

/// A block of jobs (indices into the job list) run by one process, and its
/// memory: the largest of its jobs' (they run one after the other).
struct Block {
    jobs: Vec<usize>,
    memory_mb: f64,
}

struct Pool {
    queue: VecDeque<Block>,
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
    let batch = options
        .batch
        .unwrap_or_else(|| default_batch(pending.len(), workers))
        .max(1);
    let mut report = LocalReport {
        jobs: jobs.len(),
        skipped: jobs.len() - pending.len(),
        workers,
        ..Default::default()
    };
    if !options.quiet {
        eprintln!(
            "{}: {} jobs, {} done before, {} to run on {workers} workers ({} thread(s) each, up to {batch} jobs per process, memory budget {:.1} GB)",
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
    let progress = crate::progress::Counter::start("campaign jobs", pending.len());
    let pool = Mutex::new(Pool {
        queue: pending
            .chunks(batch)
            .map(|c| Block {
                jobs: c.to_vec(),
                memory_mb: c.iter().map(|&i| jobs[i].memory_mb).fold(0.0, f64::max),
            })
            .collect(),
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
                let block = {
                    let mut p = pool.lock().unwrap_or_else(|e| e.into_inner());
                    loop {
                        if p.queue.is_empty() {
                            return;
                        }
                        let fits = p.queue.iter().position(|b| {
                            p.running == 0 || p.memory_in_use + b.memory_mb <= budget
                        });
                        if let Some(k) = fits {
                            let Some(b) = p.queue.remove(k) else { return };
                            p.memory_in_use += b.memory_mb;
                            p.running += 1;
                            break b;
                        }
                        p = cv.wait(p).unwrap_or_else(|e| e.into_inner());
                    }
                };
                let block_jobs: Vec<&Job> = block.jobs.iter().map(|&i| &jobs[i]).collect();
                match run_block_child(campaign, &block_jobs, &options.exe, campaign_dir) {
                    Ok(results) => {
                        // in block order; `i` is the job's index in the campaign
                        for (i, ok, log) in results {
                            let Some(job) = block_jobs.iter().find(|j| j.index == i) else {
                                continue;
                            };
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
                            if let Some(b) = &bar {
                                b.inc(1);
                            }
                            progress.step();
                            outcomes
                                .lock()
                                .unwrap_or_else(|e| e.into_inner())
                                .push((i, ok, log));
                        }
                    }
                    Err(e) => {
                        spawn_error
                            .lock()
                            .unwrap_or_else(|e| e.into_inner())
                            .get_or_insert(e);
                    }
                }
                let mut p = pool.lock().unwrap_or_else(|e| e.into_inner());
                p.memory_in_use -= block.memory_mb;
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
    // an embedding program that observes progress draws its own bar
    if quiet || !std::io::stderr().is_terminal() || crate::progress::observed() {
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

/// Runs a block of jobs in one child process (`run-task --index 0-31`,
/// each job's output in its `log.txt`, the process's own in
/// `OUT/workers.log`); a block of one job runs as before, its output in its
/// log. A job the process did not finish and did not record as failed
/// (the process died under it, or before it) runs again alone, so that it
/// gets its own attempt and log. Per job of the block: index, whether it
/// finished, its log.
fn run_block_child(
    campaign: &Campaign,
    block: &[&Job],
    exe: &Path,
    cwd: &Path,
) -> Result<Vec<(usize, bool, PathBuf)>> {
    if let [job] = block {
        return Ok(vec![run_child(campaign, job, exe, cwd)?]);
    }
    // file times come from a coarse kernel clock (a few ms behind): a
    // failure record newer than 50 ms before the start is this attempt's
    let started = std::time::SystemTime::now() - std::time::Duration::from_millis(50);
    let list = super::slurm::index_list(&block.iter().map(|j| j.index).collect::<Vec<_>>());
    let log_path = campaign.out.join("workers.log");
    let log = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(&log_path)
        .map_err(|e| FlankError::io(&log_path, e))?;
    let log2 = log.try_clone().map_err(|e| FlankError::io(&log_path, e))?;
    let mut cmd = child_command(campaign, &list, exe, cwd);
    cmd.stdout(log).stderr(log2);
    cmd.status()
        .map_err(|e| FlankError::Campaign(format!("cannot start {}: {e}", exe.display())))?;
    let mut results = Vec::with_capacity(block.len());
    for job in block {
        let log = store::job_dir(&campaign.out, job).join("log.txt");
        if store::done(&campaign.out, job).is_some() {
            results.push((job.index, true, log));
        } else if store::failed_since(&campaign.out, job, started) {
            results.push((job.index, false, log));
        } else if crate::interrupt::requested() {
            results.push((job.index, false, log_path.clone()));
        } else {
            results.push(run_child(campaign, job, exe, cwd)?);
        }
    }
    Ok(results)
}

/// `flank campaign run-task CAMPAIGN --index LIST --out OUT`, killed with
/// this process (Linux).
fn child_command(campaign: &Campaign, list: &str, exe: &Path, cwd: &Path) -> Command {
    let mut cmd = Command::new(exe);
    cmd.arg("campaign")
        .arg("run-task")
        .arg(&campaign.file.path)
        .arg("--index")
        .arg(list)
        .arg("--out")
        .arg(&campaign.out)
        .current_dir(cwd)
        .stdin(Stdio::null());
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
    cmd
}

/// Runs one job as a child process, its output in the job's `log.txt`;
/// its index, whether it finished, and the log.
fn run_child(
    campaign: &Campaign,
    job: &Job,
    exe: &Path,
    cwd: &Path,
) -> Result<(usize, bool, PathBuf)> {
    let dir = store::job_dir(&campaign.out, job);
    std::fs::create_dir_all(&dir).map_err(|e| FlankError::io(&dir, e))?;
    let log_path = dir.join("log.txt");
    let log = std::fs::File::create(&log_path).map_err(|e| FlankError::io(&log_path, e))?;
    let log2 = log.try_clone().map_err(|e| FlankError::io(&log_path, e))?;
    let mut cmd = child_command(campaign, &job.index.to_string(), exe, cwd);
    cmd.stdout(log).stderr(log2);
    let status = cmd
        .status()
        .map_err(|e| FlankError::Campaign(format!("cannot start {}: {e}", exe.display())))?;
    Ok((job.index, status.success(), log_path))
}
