//! `flank campaign run` on this machine: a campaign of 8 cheap LTCA jobs
//! (seed 002 scene, 2 mm compliance mesh, 3 positions) killed mid-run with
//! SIGKILL to its process group and rerun gives the same table as an
//! uninterrupted run (times aside), reruns no finished job (counted in
//! events.log), shows no partial result; changing one variant's input reruns
//! exactly that job. Bad campaign files fail before any job starts.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

use flank::campaign::collect::read_figures;

const TORQUES: [f64; 8] = [150.0, 175.0, 200.0, 225.0, 250.0, 275.0, 300.0, 312.0];

fn dir(name: &str) -> PathBuf {
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("campaign_local_{name}"));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn campaign_text(torques: &[f64]) -> String {
    campaign_text_with(torques, "")
}

/// The campaign with `extra` appended to the LTCA's options.
fn campaign_text_with(torques: &[f64], extra: &str) -> String {
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("papers/seed002-spur/scene.toml");
    let list: Vec<String> = torques.iter().map(|t| format!("{t:.1}")).collect();
    format!(
        "[campaign]\nscene = \"{}\"\nanalyses = [\"ltca\"]\n\n[args]\nltca = [\"--no-condition\", \"--roll-angles\", \"-5,0,5\", \"--flank-size\", \"2\", \"--base-size\", \"3\", \"--points-per-line\", \"10\"{extra}]\n\n[grid]\n\"load.torque_nm\" = [{}]\n",
        scene.display(),
        list.join(", ")
    )
}

fn run(campaign: &Path, out: &Path) -> (bool, String, String) {
    run_with(campaign, out, &[])
}

fn run_with(campaign: &Path, out: &Path, args: &[&str]) -> (bool, String, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_flank"))
        .args(["campaign", "run"])
        .arg(campaign)
        .arg("--out")
        .arg(out)
        .args(args)
        .output()
        .unwrap();
    (
        o.status.success(),
        String::from_utf8_lossy(&o.stdout).into(),
        String::from_utf8_lossy(&o.stderr).into(),
    )
}

fn figures(out: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    read_figures(out).unwrap()
}

/// Lines of events.log starting with `word`, as (index, id).
fn events(out: &Path, word: &str) -> Vec<(usize, String)> {
    std::fs::read_to_string(out.join("events.log"))
        .unwrap_or_default()
        .lines()
        .filter_map(|l| {
            let mut f = l.split_whitespace();
            (f.next()? == word).then_some(())?;
            Some((f.next()?.parse().ok()?, f.next()?.to_string()))
        })
        .collect()
}

#[test]
fn killed_campaign_resumes_to_the_same_table() {
    let d = dir("kill");
    let c = d.join("tolerance.toml");
    std::fs::write(&c, campaign_text(&TORQUES)).unwrap();

    // uninterrupted reference
    let reference = d.join("reference");
    let (ok, out, err) = run(&c, &reference);
    assert!(ok, "{out}\n{err}");
    assert!(
        out.contains("8 jobs: 0 done before, 8 finished, 0 failed"),
        "{out}"
    );
    let (head, ref_rows) = figures(&reference);
    assert!(head.iter().any(|h| h == "single_pair_force_n"), "{head:?}");
    assert_eq!(ref_rows.len(), 8);
    assert!(ref_rows.iter().all(|r| r[3] == "done"));

    // killed mid-run: SIGKILL to the campaign's process group once two jobs are done
    let killed = d.join("killed");
    std::fs::create_dir_all(&killed).unwrap();
    let mut child = {
        use std::os::unix::process::CommandExt;
        Command::new(env!("CARGO_BIN_EXE_flank"))
            .args(["campaign", "run", "-q"])
            .arg(&c)
            .arg("--out")
            .arg(&killed)
            .process_group(0)
            .spawn()
            .unwrap()
    };
    let t0 = Instant::now();
    while events(&killed, "done").len() < 2 {
        assert!(
            t0.elapsed() < Duration::from_secs(120),
            "no job finished in 120 s"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    // SAFETY: kill(2) of the process group this test created
    unsafe {
        libc::killpg(child.id() as i32, libc::SIGKILL);
    }
    child.wait().unwrap();
    std::thread::sleep(Duration::from_millis(300));
    let done_at_kill = events(&killed, "done");
    assert!(
        (2..8).contains(&done_at_kill.len()),
        "the kill should land mid-run: {} done",
        done_at_kill.len()
    );
    // no partial result visible: collect shows exactly the recorded jobs, with figures
    let o = Command::new(env!("CARGO_BIN_EXE_flank"))
        .args(["campaign", "collect"])
        .arg(&c)
        .arg("--out")
        .arg(&killed)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (h, rows) = figures(&killed);
    let col = h.iter().position(|x| x == "single_pair_force_n").unwrap();
    for r in &rows {
        let i: usize = r[0].parse().unwrap();
        let done = done_at_kill.iter().any(|(j, _)| *j == i);
        assert_eq!(r[3] == "done", done, "row {r:?}");
        assert_eq!(!r[col].is_empty(), done, "row {r:?}");
    }

    // rerun: finishes the rest, runs no finished job again
    let (ok, out, err) = run(&c, &killed);
    assert!(ok, "{out}\n{err}");
    assert!(
        out.contains(&format!("8 jobs: {} done before", done_at_kill.len())),
        "{out}"
    );
    let starts = events(&killed, "start");
    for (i, id) in &done_at_kill {
        let n = starts.iter().filter(|(_, s)| s == id).count();
        assert_eq!(n, 1, "job {i} ({id}) started {n} times");
    }
    assert_eq!(events(&killed, "done").len(), 8);
    // no attempt left behind
    for e in std::fs::read_dir(killed.join("jobs")).unwrap().flatten() {
        for f in std::fs::read_dir(e.path()).unwrap().flatten() {
            let name = f.file_name().to_string_lossy().into_owned();
            assert!(!name.starts_with("tmp-"), "{}", f.path().display());
        }
        assert!(e.path().join("done.json").is_file());
    }
    assert_eq!(figures(&killed), (head.clone(), ref_rows.clone()));

    // one changed input reruns exactly that job
    let mut changed = TORQUES;
    changed[5] = 280.0;
    std::fs::write(&c, campaign_text(&changed)).unwrap();
    let before = events(&killed, "start").len();
    let (ok, out, err) = run(&c, &killed);
    assert!(ok, "{out}\n{err}");
    assert!(out.contains("8 jobs: 7 done before, 1 finished"), "{out}");
    let starts = events(&killed, "start");
    assert_eq!(starts.len(), before + 1);
    assert_eq!(starts.last().unwrap().0, 5);
}

/// Blocks of 4 jobs per worker process (`--batch 4`) sharing a compliance
/// cache: killed mid-block and rerun, the table equals that of one process
/// per job (`--batch 1`), no finished job runs again, every job has its
/// own log and completion record, and the result's tensor files are links
/// to the cache's (not rewritten).
#[test]
fn batched_workers_resume_to_the_one_process_per_job_table() {
    use std::os::unix::fs::MetadataExt;
    let d = dir("batch");
    let c = d.join("batch.toml");
    let cache = d.join("cache");
    let extra = format!(", \"--cache\", \"{}\"", cache.display());
    std::fs::write(&c, campaign_text_with(&TORQUES, &extra)).unwrap();
    // the tensors computed before either run: the job that computes them
    // reports their backward error, and which job that is depends on the
    // order the workers reach the cache, not on the executor
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("papers/seed002-spur/scene.toml");
    let o = Command::new(env!("CARGO_BIN_EXE_flank"))
        .arg("ltca")
        .arg(&scene)
        .args(["--out"])
        .arg(d.join("warm"))
        .args(["--quiet", "--no-condition", "--roll-angles", "0"])
        .args(["--flank-size", "2", "--base-size", "3", "--cache"])
        .arg(&cache)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));

    let single = d.join("single");
    let (ok, out, err) = run_with(&c, &single, &["--batch", "1"]);
    assert!(ok, "{out}\n{err}");
    assert!(err.contains("up to 1 jobs per process"), "{err}");
    assert!(!single.join("workers.log").exists());
    let (head, ref_rows) = figures(&single);
    assert_eq!(ref_rows.len(), 8);
    assert!(ref_rows.iter().all(|r| r[3] == "done"), "{ref_rows:?}");
    assert!(
        !head.iter().any(|h| h.starts_with("tensor_backward")),
        "{head:?}"
    );

    let batched = d.join("batched");
    std::fs::create_dir_all(&batched).unwrap();
    let mut child = {
        use std::os::unix::process::CommandExt;
        Command::new(env!("CARGO_BIN_EXE_flank"))
            .args(["campaign", "run", "-q", "--batch", "4"])
            .arg(&c)
            .arg("--out")
            .arg(&batched)
            .process_group(0)
            .spawn()
            .unwrap()
    };
    let t0 = Instant::now();
    while events(&batched, "done").len() < 2 {
        assert!(
            t0.elapsed() < Duration::from_secs(120),
            "no job finished in 120 s"
        );
        std::thread::sleep(Duration::from_millis(10));
    }
    // SAFETY: kill(2) of the process group this test created
    unsafe {
        libc::killpg(child.id() as i32, libc::SIGKILL);
    }
    child.wait().unwrap();
    std::thread::sleep(Duration::from_millis(300));
    let done_at_kill = events(&batched, "done");
    assert!(
        (2..8).contains(&done_at_kill.len()),
        "the kill should land mid-run: {} done",
        done_at_kill.len()
    );
    let (ok, out, err) = run_with(&c, &batched, &["--batch", "4"]);
    assert!(ok, "{out}\n{err}");
    assert!(
        out.contains(&format!("8 jobs: {} done before", done_at_kill.len())),
        "{out}"
    );
    let starts = events(&batched, "start");
    for (i, id) in &done_at_kill {
        let n = starts.iter().filter(|(_, s)| s == id).count();
        assert_eq!(n, 1, "job {i} ({id}) started {n} times");
    }
    assert_eq!(events(&batched, "done").len(), 8);
    assert_eq!(figures(&batched), (head, ref_rows));
    // blocks ran: the workers' log has their lines
    let workers = std::fs::read_to_string(batched.join("workers.log")).unwrap();
    assert!(workers.contains(" finished, "), "{workers}");
    for e in std::fs::read_dir(batched.join("jobs")).unwrap().flatten() {
        let p = e.path();
        assert!(p.join("done.json").is_file(), "{}", p.display());
        let log = std::fs::read_to_string(p.join("log.txt")).unwrap();
        assert!(log.contains("finished in"), "{}: {log}", p.display());
        for body in ["pinion", "gear"] {
            // .bin, or .h5 when built with the hdf5 feature
            let file = ["bin", "h5"]
                .iter()
                .map(|e| p.join(format!("result/{body}.compliance.{e}")))
                .find(|f| f.is_file())
                .unwrap_or_else(|| panic!("{}: no {body} tensor", p.display()));
            let m = std::fs::metadata(&file).unwrap();
            assert!(m.nlink() >= 2, "{}: not linked", file.display());
        }
    }
}

#[test]
fn bad_campaigns_fail_before_any_job() {
    let d = dir("bad");
    let c = d.join("bad.toml");
    let cases: [(&str, &str, &[&str]); 4] = [
        (
            "unknown scene key",
            "\"load.torqe_nm\" = [1.0]\n",
            &["bad.toml:10:", "unknown field `torqe_nm`"],
        ),
        (
            "memory above the machine",
            "[resources]\nmemory_gb = 1000000.0\n",
            &["needs `resources.memory_gb` = 1000000.00 GB", "more than the"],
        ),
        (
            "negative spread",
            "[monte_carlo]\nseed = 3\nsamples = 10\n[monte_carlo.keys]\n\"pinion.face_width_mm\" = { distribution = \"normal\", mean = 13.3, sd = -0.1 }\n",
            &["bad.toml:14:", "must not be negative"],
        ),
        (
            "bad analysis option",
            "",
            &["bad.toml:6:", "`args.ltca`", "--no-such-option"],
        ),
    ];
    for (what, extra, expect) in cases {
        let mut text = campaign_text(&TORQUES[..2]);
        if what == "bad analysis option" {
            text = text.replace("\"--no-condition\"", "\"--no-such-option\"");
        }
        std::fs::write(&c, format!("{text}{extra}")).unwrap();
        let out = d.join("out");
        let (ok, stdout, err) = run(&c, &out);
        assert!(!ok, "{what}: {stdout}");
        for e in expect {
            assert!(err.contains(e), "{what}: {err}");
        }
        assert!(!out.join("jobs").exists(), "{what}: a job folder was made");
    }
    // an empty grid
    std::fs::write(&c, campaign_text(&[])).unwrap();
    let (ok, _, err) = run(&c, &d.join("out"));
    assert!(
        !ok && err.contains("bad.toml:9:") && err.contains("empty list"),
        "{err}"
    );
}

/// A campaign of the hypoid LTCA (seed 003's eased pair, two torques,
/// coarse tensors, three positions) through the library façade
/// (`flank::api::campaign`): both jobs finish, the table has one row per
/// torque with the same figure columns as any LTCA summary, and the
/// largest contact pressure grows with the torque.
#[test]
fn hypoid_campaign_through_the_library() {
    let d = dir("hypoid");
    let c = d.join("hypoid.toml");
    let scene =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("papers/seed003-hypoid/scene_eased.toml");
    std::fs::write(
        &c,
        format!(
            "[campaign]\nscene = \"{}\"\nanalyses = [\"ltca\"]\n\n[args]\nltca = [\"--roll-angles=-8.182,0,8.182\", \"--flank-size\", \"2\", \"--base-size\", \"8\", \"--points-per-line\", \"11\"]\n\n[grid]\n\"load.torque_nm\" = [134.0, 268.0]\n",
            scene.display()
        ),
    )
    .unwrap();
    let out = d.join("out");
    let run = flank::api::campaign(
        &c,
        &flank::api::CampaignOptions {
            out: Some(out.clone()),
            exe: PathBuf::from(env!("CARGO_BIN_EXE_flank")),
            workers: Some(1),
            memory_mb: None,
            quiet: true,
        },
    )
    .unwrap();
    assert_eq!(
        (run.report.jobs, run.report.finished),
        (2, 2),
        "{:?}",
        run.report
    );
    assert!(run.report.failed.is_empty());
    let t = &run.table;
    assert_eq!(t.rows.len(), 2);
    for key in [
        "te_peak_to_peak_arcsec",
        "te_peak_to_peak_urad",
        "max_pressure_mpa",
        "positions",
    ] {
        assert!(
            t.figure_keys.iter().any(|k| k == key),
            "{key} not in {:?}",
            t.figure_keys
        );
    }
    let figure = |key: &str| -> Vec<f64> {
        t.rows
            .iter()
            .map(|r| flank::campaign::table::Table::figure(r, key).unwrap())
            .collect()
    };
    let (te, p) = (figure("te_peak_to_peak_urad"), figure("max_pressure_mpa"));
    println!("hypoid campaign: TE p-p {te:?} µrad, p_max {p:?} MPa at 134 and 268 N·m");
    assert!(p[1] > p[0], "{p:?}");
    assert!(t.rows.iter().all(|r| r.status == "done"));
    assert!(out.join("table.csv").exists());
}
