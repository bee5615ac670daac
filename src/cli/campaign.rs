//! `flank campaign run|run-task|submit|status|collect CAMPAIGN.toml`: studies
//! over many variants of a scene (`flank::campaign`).

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};

use flank::campaign::Campaign;

#[derive(clap::Args)]
pub struct Args {
    #[command(subcommand)]
    command: Sub,
}

#[derive(clap::Args)]
struct Common {
    /// The campaign file (.toml).
    campaign: PathBuf,
    /// Output folder; overrides the file's `campaign.out` (default out/<name>).
    #[arg(long)]
    out: Option<PathBuf>,
}

#[derive(clap::Subcommand)]
enum Sub {
    /// Run the jobs not done yet on this machine (a child process each),
    /// then collect.
    Run {
        #[command(flatten)]
        common: Common,
        /// Parallel jobs (default: cores / threads per job).
        #[arg(long)]
        workers: Option<usize>,
        /// Memory budget (GB; default: the machine's available memory).
        #[arg(long)]
        memory_gb: Option<f64>,
        /// Run only these job indices (e.g. 0-2,5); the rest stay as they are.
        #[arg(long)]
        only: Option<String>,
        /// Jobs per worker process (run one after the other, sharing what
        /// they can, e.g. cached compliance tensors); default: the pending
        /// jobs / (4 × workers), 1 … 32.
        #[arg(long)]
        batch: Option<usize>,
        /// Print nothing but errors.
        #[arg(long, short)]
        quiet: bool,
    },
    /// Run one job (what every executor runs: Slurm array task I is
    /// `flank campaign run-task CAMPAIGN --index I`), or a block of jobs
    /// one after the other in this process (`--index 0-31`: what a local
    /// worker runs; each job's output then goes to its folder's log.txt).
    RunTask {
        #[command(flatten)]
        common: Common,
        /// The job's index (0-based), or a list of them (0-31,40).
        #[arg(long)]
        index: String,
    },
    /// Submit the jobs not done yet as Slurm job arrays (sbatch), one
    /// array task per job.
    Submit {
        #[command(flatten)]
        common: Common,
        /// Slurm's MaxArraySize (arrays are split below it).
        #[arg(long, default_value_t = flank::campaign::slurm::DEFAULT_MAX_ARRAY_SIZE)]
        max_array_size: usize,
    },
    /// Done, queued and failed jobs of a submitted campaign (squeue and the
    /// job records); failed ones with their logs (resubmit runs them alone).
    Status {
        #[command(flatten)]
        common: Common,
        /// Wait until nothing is queued, at most this many seconds.
        #[arg(long)]
        wait: Option<f64>,
    },
    /// Gather every finished job's figures into table.csv, with the
    /// convergence (GCI) or Monte Carlo summaries and summary.md.
    Collect {
        #[command(flatten)]
        common: Common,
    },
    /// Check the campaign and print its jobs (index, analysis, memory
    /// estimate, inputs) without running anything.
    List {
        #[command(flatten)]
        common: Common,
    },
}

/// The flank command line as a campaign sees it: check an analysis's
/// arguments before any job runs, and run a job's analysis in this process
/// (`run-task`). `main` owns the parser and hands these in, so this module
/// does not import it.
pub struct CommandLine {
    /// Parses `flank ARGV…`; the parser's message on failure.
    pub check: fn(&[String]) -> std::result::Result<(), String>,
    /// Parses and runs `flank ARGV…`; the error chain on failure.
    pub run: fn(&[String]) -> std::result::Result<(), String>,
}

pub fn run(args: Args, command_line: &CommandLine) -> Result<()> {
    match args.command {
        Sub::Run {
            common,
            workers,
            memory_gb,
            only,
            batch,
            quiet,
        } => {
            let c = open(&common, command_line)?;
            let jobs = c.jobs()?;
            let selected: Vec<flank::campaign::Job> = match &only {
                None => jobs.clone(),
                Some(list) => {
                    let keep = parse_index_list(list, jobs.len()).context("--only")?;
                    jobs.iter()
                        .filter(|j| keep.contains(&j.index))
                        .cloned()
                        .collect()
                }
            };
            let exe = std::env::current_exe().context("the flank executable")?;
            let options = flank::campaign::local::LocalOptions {
                exe,
                workers,
                memory_mb: memory_gb.map(|g| g * 1024.0),
                batch,
                quiet,
            };
            let r = flank::campaign::local::run_local(&c, &selected, &options)?;
            if !quiet {
                println!(
                    "{} jobs: {} done before, {} finished, {} failed; {:.1} s on {} workers; results in {}",
                    r.jobs,
                    r.skipped,
                    r.finished,
                    r.failed.len(),
                    r.wall_s,
                    r.workers,
                    c.out.display()
                );
            }
            collect(&c, &jobs, quiet)?;
            if !r.failed.is_empty() {
                let list: Vec<String> = r
                    .failed
                    .iter()
                    .map(|(i, log)| format!("job {i}: {}", log.display()))
                    .collect();
                anyhow::bail!(
                    "{} job(s) failed (rerun to retry them alone):\n  {}",
                    r.failed.len(),
                    list.join("\n  ")
                );
            }
            Ok(())
        }
        Sub::RunTask { common, index } => {
            let c = open(&common, command_line)?;
            let indices = parse_index_list(&index, c.job_count()).context("--index")?;
            anyhow::ensure!(!indices.is_empty(), "--index `{index}`: no job index");
            let analysis = command_line.run;
            if let [index] = indices[..] {
                match flank::campaign::task::run_task(&c, index, &analysis)? {
                    flank::campaign::task::TaskOutcome::AlreadyDone => {
                        println!("job {index}: done before")
                    }
                    flank::campaign::task::TaskOutcome::Finished(s) => {
                        println!("job {index}: finished in {s:.2} s")
                    }
                }
                return Ok(());
            }
            let r = flank::campaign::task::run_block(&c, &indices, true, &analysis)?;
            println!(
                "{} jobs: {} finished, {} done before, {} failed, {} not run (stopped)",
                indices.len(),
                r.finished.len(),
                r.already_done.len(),
                r.failed.len(),
                r.not_run.len()
            );
            if !r.failed.is_empty() || !r.not_run.is_empty() {
                let list: Vec<String> = r.failed.iter().map(|(i, _)| i.to_string()).collect();
                anyhow::bail!(
                    "job(s) failed: [{}] (messages in their log.txt); not run: {:?}",
                    list.join(", "),
                    r.not_run
                );
            }
            Ok(())
        }
        Sub::Submit {
            common,
            max_array_size,
        } => {
            let c = open(&common, command_line)?;
            let jobs = c.jobs()?;
            let exe = std::env::current_exe().context("the flank executable")?;
            let subs = flank::campaign::slurm::submit(&c, &jobs, &exe, max_array_size)?;
            if subs.is_empty() {
                println!("every job is done: nothing submitted");
            }
            for s in subs {
                println!(
                    "submitted {} jobs as Slurm array {} ({})",
                    s.indices.len(),
                    s.slurm_job,
                    s.script.display()
                );
            }
            Ok(())
        }
        Sub::Status { common, wait } => {
            let c = open(&common, command_line)?;
            let jobs = c.jobs()?;
            let st = match wait {
                Some(w) => flank::campaign::slurm::wait(
                    &c,
                    &jobs,
                    std::time::Duration::from_secs_f64(w.max(0.0)),
                    std::time::Duration::from_secs(2),
                )?,
                None => flank::campaign::slurm::status(&c, &jobs)?,
            };
            println!(
                "{} jobs: {} done, {} queued or running, {} failed or lost, {} not submitted",
                jobs.len(),
                st.done,
                st.queued.len(),
                st.failed.len(),
                st.unsubmitted
            );
            for (i, log) in &st.failed {
                println!("failed: job {i}, log {}", log.display());
            }
            Ok(())
        }
        Sub::Collect { common } => {
            let c = open(&common, command_line)?;
            let jobs = c.jobs()?;
            collect(&c, &jobs, false)
        }
        Sub::List { common } => {
            let c = open(&common, command_line)?;
            let jobs = c.jobs()?;
            for j in &jobs {
                let inputs: Vec<String> =
                    j.inputs.iter().map(|(k, v)| format!("{k} = {v}")).collect();
                let done = flank::campaign::store::done(&c.out, j).is_some();
                println!(
                    "{:>5} {} {:<10} {:>8.0} MB {} {}",
                    j.index,
                    j.id(),
                    j.analysis,
                    j.memory_mb,
                    if done { "done   " } else { "pending" },
                    inputs.join(", ")
                );
            }
            Ok(())
        }
    }
}

fn collect(c: &Campaign, jobs: &[flank::campaign::Job], quiet: bool) -> Result<()> {
    let table = flank::campaign::collect::collect(c, jobs)?;
    let w = flank::campaign::collect::write_all(c, &table)?;
    if !quiet {
        println!(
            "collected {} jobs ({} done, {} failed, {} pending): {}",
            table.rows.len(),
            w.done,
            w.failed,
            w.pending,
            w.files
                .iter()
                .filter(|f| f.extension().is_some_and(|e| e != "png" && e != "svg"))
                .map(|f| f.display().to_string())
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    Ok(())
}

/// `0-2,5` → [0, 1, 2, 5], each below `n`.
fn parse_index_list(list: &str, n: usize) -> Result<Vec<usize>> {
    let mut out = Vec::new();
    for part in list.split(',').map(str::trim).filter(|p| !p.is_empty()) {
        let (a, b) = part.split_once('-').unwrap_or((part, part));
        let (a, b): (usize, usize) = (
            a.trim()
                .parse()
                .with_context(|| format!("`{part}` is not an index or a range"))?,
            b.trim()
                .parse()
                .with_context(|| format!("`{part}` is not an index or a range"))?,
        );
        if a > b || b >= n {
            anyhow::bail!(
                "`{part}`: the campaign's jobs are 0 … {}",
                n.saturating_sub(1)
            );
        }
        out.extend(a..=b);
    }
    Ok(out)
}

/// Opens the campaign and checks each analysis's `[args]` with flank's own
/// command line, so a wrong option is an error at its line before anything runs.
fn open(common: &Common, command_line: &CommandLine) -> Result<Campaign> {
    let c = Campaign::open(&common.campaign, common.out.as_deref())?;
    check_args(&c, command_line)?;
    Ok(c)
}

fn check_args(c: &Campaign, command_line: &CommandLine) -> Result<()> {
    for analysis in &c.file.analyses {
        let (options, line) = match c.file.args.get(analysis) {
            Some((o, l)) => (o.clone(), *l),
            None => (Vec::new(), c.file.analyses_line),
        };
        let argv = flank::campaign::task::analysis_argv(
            analysis,
            Path::new("scene.toml"),
            Path::new("out"),
            &options,
        );
        if let Err(msg) = (command_line.check)(&argv) {
            let first = msg
                .lines()
                .next()
                .unwrap_or("")
                .trim_start_matches("error: ");
            return Err(flank::error::FlankError::Parse {
                file: c.file.path.clone(),
                line,
                message: format!("`args.{analysis}`: flank {analysis} rejects it: {first}"),
            }
            .into());
        }
    }
    Ok(())
}
