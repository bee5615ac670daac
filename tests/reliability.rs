//! Reliability under resource failures and interruptions (issue 22, points
//! 4 and 5), through the binary as a user meets them:
//!
//! * the memory guard: a deliberately oversized case under a lowered limit
//!   (`FLANK_MEMORY_LIMIT_MB`, `--memory-limit-mb`) is refused with the
//!   figures and the alternatives, exit code 1 (never a panic's 101, never
//!   the OOM killer), and writes no result;
//! * SIGINT during `flank run` (spur and hypoid) stops at a position boundary, keeps what is
//!   complete and says how to resume; `--resume` then solves only the rest;
//! * SIGKILL at random instants of `flank run` leaves only complete,
//!   loadable files;
//! * two `flank compliance` processes sharing a cache directory compute
//!   each tensor once and leave one intact cache file.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn flank() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_flank"));
    c.current_dir(root()).env_remove("FLANK_MEMORY_LIMIT_MB");
    c
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("flank-reliability-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn text(o: &Output) -> (String, String) {
    (
        String::from_utf8_lossy(&o.stdout).into_owned(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

/// A refusal: exit code 1, the memory message with both figures, the
/// bound and the alternatives named.
fn assert_refused(o: &Output, bound: &str, alternative: &str) {
    let (_, err) = text(o);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.contains("memory: "), "{err}");
    assert!(
        err.contains("needs about ") && err.contains("is available"),
        "{err}"
    );
    assert!(err.contains(bound), "{err}");
    assert!(err.contains(alternative), "{err}");
    assert!(!err.contains("panicked"), "{err}");
}

/// `flank solve` of NAFEMS LE10 (31 144 DOFs, a 236 MB factor) under a
/// 150 MB limit: refused before the factorization, nothing written; an
/// unparsable limit is an error too.
#[test]
fn memory_guard_refuses_a_factorization_over_the_limit() {
    let d = tmp("mem-solve");
    let out = d.join("out");
    let o = flank()
        .args(["solve", "verification/nafems_le10/le10.inp", "--out"])
        .arg(&out)
        .env("FLANK_MEMORY_LIMIT_MB", "150")
        .output()
        .unwrap();
    assert_refused(&o, "FLANK_MEMORY_LIMIT_MB = 150 MB", "--flank-size");
    assert!(text(&o).1.contains("31144 DOFs"), "{}", text(&o).1);
    assert!(!out.exists(), "a refused solve wrote {}", out.display());
    let o = flank()
        .args(["solve", "verification/nafems_le10/le10.inp", "--out"])
        .arg(&out)
        .env("FLANK_MEMORY_LIMIT_MB", "lots")
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1));
    assert!(text(&o).1.contains("positive number of megabytes"));
    let _ = std::fs::remove_dir_all(&d);
}

/// Seed 002's compliance tensors at a 0.3 mm flank size (4 707 flank
/// nodes, a dense 14 121² matrix, 4.5 GB with the Schur method) under
/// `--memory-limit-mb 2000`: refused after meshing, before assembly, with
/// the compliance alternatives; no tensor file.
#[test]
fn memory_guard_refuses_an_oversized_compliance_tensor() {
    let d = tmp("mem-compliance");
    let o = flank()
        .args([
            "--memory-limit-mb",
            "2000",
            "compliance",
            "papers/seed002-spur/scene.toml",
            "--flank-size",
            "0.3",
            "--out",
        ])
        .arg(&d)
        .output()
        .unwrap();
    assert_refused(&o, "--memory-limit-mb = 2.0 GB", "fewer flank sets");
    assert!(text(&o).1.contains("14121 × 14121"), "{}", text(&o).1);
    assert!(!d.join("pinion.compliance.bin").exists());
    let _ = std::fs::remove_dir_all(&d);
}

/// The library's guard on a cantilever (`solve_static`) under this
/// thread's lowered limit: a [`flank::FlankError::Memory`] naming the
/// DOFs; the same model solves without the limit.
#[test]
fn memory_guard_in_the_library() {
    use flank::fem::static_analysis::{solve_static, SolveOptions};
    use flank::mesh::structured::{cantilever_model, BoxElement};
    let model = cantilever_model([20, 2, 2], BoxElement::Hex20, 1000.0).unwrap();
    let limit = flank::resources::resident_mb() + 0.05;
    let e = flank::resources::with_memory_limit_mb(limit, || {
        solve_static(&model, &SolveOptions::default())
    })
    .unwrap_err();
    assert!(matches!(e, flank::FlankError::Memory(_)), "{e}");
    assert!(
        e.to_string().contains("sparse Cholesky factorization"),
        "{e}"
    );
    solve_static(&model, &SolveOptions::default()).unwrap();
}

/// How long the test waits for a child at most.
const CHILD_TIMEOUT: Duration = Duration::from_secs(120);

/// Waits for `child` (killing it after [`CHILD_TIMEOUT`]).
fn wait(child: &mut std::process::Child) -> std::process::ExitStatus {
    let t = Instant::now();
    loop {
        if let Some(s) = child.try_wait().unwrap() {
            return s;
        }
        if t.elapsed() > CHILD_TIMEOUT {
            let _ = child.kill();
            panic!("child did not finish within {CHILD_TIMEOUT:?}");
        }
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// The fast mesh cycle of these tests: seed 002 on a coarse mesh (27 633
/// DOFs, about 0.6 s of setup and 0.1 s per position on 2 cores).
fn run_command(out: &Path, angles: &str) -> Command {
    let mut c = flank();
    c.args([
        "run",
        "papers/seed002-spur/scene.toml",
        "--flank-size",
        "1.5",
        "--base-size",
        "3",
        "--no-refine",
        "-q",
        &format!("--roll-angles={angles}"),
        "--out",
    ])
    .arg(out);
    c
}

/// Sends `signal` to the child.
fn signal(child: &std::process::Child, signal: i32) {
    let pid = i32::try_from(child.id()).unwrap();
    // SAFETY: kill(2) on our own child's pid, with a valid signal number
    assert_eq!(unsafe { libc::kill(pid, signal) }, 0);
}

/// Lines of a CSV file, each with the header's number of fields; the file
/// ends with a newline.
fn csv_rows(p: &Path) -> usize {
    let t = std::fs::read_to_string(p).unwrap();
    assert!(t.ends_with('\n'), "{}: no final newline", p.display());
    let mut lines = t.lines();
    let fields = lines.next().unwrap().split(',').count();
    let mut rows = 0;
    for l in lines {
        assert_eq!(l.split(',').count(), fields, "{}: {l}", p.display());
        rows += 1;
    }
    rows
}

/// Checks that every file in `dir` (temporary files of
/// `flank::atomic_file` aside) is complete and loads: JSON parses, CSV rows
/// are whole, VTU and SVG end with their closing tag, PNG ends with its
/// IEND chunk. Returns (files checked, temporary files left).
fn check_files_complete(dir: &Path) -> (usize, usize) {
    let (mut checked, mut temps) = (0, 0);
    let Ok(entries) = std::fs::read_dir(dir) else {
        return (0, 0);
    };
    for e in entries {
        let p = e.unwrap().path();
        let name = p.file_name().unwrap().to_string_lossy().into_owned();
        if flank::atomic_file::is_temp(&name) {
            temps += 1;
            continue;
        }
        let bytes = std::fs::read(&p).unwrap();
        let text = || String::from_utf8(bytes.clone()).unwrap();
        match p.extension().and_then(|x| x.to_str()) {
            Some("json") => {
                let v: serde_json::Value =
                    serde_json::from_slice(&bytes).unwrap_or_else(|e| panic!("{name}: {e}"));
                if name == "checkpoint.json" {
                    assert!(v["steps"].is_array(), "{name}");
                }
            }
            Some("csv") => {
                csv_rows(&p);
            }
            Some("vtu") => assert!(text().trim_end().ends_with("</VTKFile>"), "{name}"),
            Some("svg") => assert!(text().trim_end().ends_with("</svg>"), "{name}"),
            Some("png") => {
                assert!(bytes.starts_with(b"\x89PNG\r\n\x1a\n"), "{name}");
                assert!(bytes.ends_with(b"IEND\xae\x42\x60\x82"), "{name}");
            }
            _ => panic!("unexpected file {name}"),
        }
        checked += 1;
    }
    (checked, temps)
}

/// Starts `command`, sends SIGINT once `checkpoint` exists (a position is
/// solved), and checks the stop: exit code 130, a message that says how to
/// resume, no panic. Returns the positions the checkpoint kept.
fn interrupt_after_a_position(mut command: Command, checkpoint: &Path) -> usize {
    let mut child = command
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let t = Instant::now();
    while !checkpoint.exists() {
        assert!(t.elapsed() < CHILD_TIMEOUT, "no position solved");
        std::thread::sleep(Duration::from_millis(5));
    }
    signal(&child, libc::SIGINT);
    let status = wait(&mut child);
    let mut err = String::new();
    std::io::Read::read_to_string(child.stderr.as_mut().unwrap(), &mut err).unwrap();
    assert_eq!(status.code(), Some(130), "{err}");
    assert!(
        err.contains("position boundary") && err.contains("--resume"),
        "{err}"
    );
    assert!(!err.contains("panicked"), "{err}");
    let kept: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(checkpoint).unwrap()).unwrap();
    kept["steps"].as_array().unwrap().len()
}

/// SIGINT during `flank run` (13 positions): exit code 130 after the
/// position under way, the solved positions kept (checkpoint.json,
/// mesh_cycle.partial.csv, their VTU files), the message says how to
/// resume; `--resume` then solves only the rest, and the complete run
/// leaves no checkpoint.
#[test]
fn sigint_stops_at_a_position_and_resumes() {
    let d = tmp("sigint");
    let out = d.join("out");
    let angles = "-12,-10,-8,-6,-4,-2,0,2,4,6,8,10,12";
    let checkpoint = out.join("checkpoint.json");
    let n = interrupt_after_a_position(run_command(&out, angles), &checkpoint);
    assert!((1..13).contains(&n), "{n} positions kept");
    assert_eq!(csv_rows(&out.join("mesh_cycle.partial.csv")), n);
    assert!(!out.join("summary.json").exists());
    check_files_complete(&out);

    let o = run_command(&out, angles).arg("--resume").output().unwrap();
    assert!(o.status.success(), "{}", text(&o).1);
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(s["positions"].as_u64(), Some(13));
    assert_eq!(s["resumed_positions"].as_u64(), Some(n as u64));
    assert_eq!(csv_rows(&out.join("mesh_cycle.csv")), 13);
    assert!(!checkpoint.exists() && !out.join("mesh_cycle.partial.csv").exists());
    // a checkpoint of other options is refused under --resume, not mixed in
    std::fs::write(&checkpoint, r#"{"format":1,"key":"other","steps":[]}"#).unwrap();
    let o = run_command(&out, angles).arg("--resume").output().unwrap();
    assert_eq!(o.status.code(), Some(1));
    assert!(
        text(&o).1.contains("another scene, other options"),
        "{}",
        text(&o).1
    );
    let _ = std::fs::remove_dir_all(&d);
}

/// `flank run` on the eased hypoid scene (seed 003, coarse, one thread so that
/// whole and resumed runs compare bit for bit).
fn hypoid_run_command(out: &Path, angles: &str) -> Command {
    let mut c = flank();
    c.args([
        "run",
        "papers/seed003-hypoid/scene_eased.toml",
        "--flank-size",
        "2",
        "--base-size",
        "8",
        "--threads",
        "1",
        "-q",
        &format!("--roll-angles={angles}"),
        "--out",
    ])
    .arg(out);
    c
}

/// SIGINT during a hypoid `flank run` (9 positions): exit code 130 after
/// the position under way, the solved positions kept in checkpoint.json,
/// the message says how to resume; `--resume` solves only the rest and
/// writes positions.csv and contact_pattern.csv identical to those of an
/// uninterrupted run (the contact pattern of the kept positions included).
#[test]
fn hypoid_sigint_stops_at_a_position_and_resumes() {
    let d = tmp("sigint_hypoid");
    let (out, whole) = (d.join("out"), d.join("whole"));
    let angles = "-8,-6,-4,-2,0,2,4,6,8";
    assert!(hypoid_run_command(&whole, angles)
        .status()
        .unwrap()
        .success());
    assert!(!whole.join("checkpoint.json").exists());
    let checkpoint = out.join("checkpoint.json");
    let n = interrupt_after_a_position(hypoid_run_command(&out, angles), &checkpoint);
    assert!((1..9).contains(&n), "{n} positions kept");
    assert!(!out.join("summary.json").exists());
    let o = hypoid_run_command(&out, angles)
        .arg("--resume")
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", text(&o).1);
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(s["positions"].as_u64(), Some(9));
    assert_eq!(s["resumed_positions"].as_u64(), Some(n as u64));
    assert!(!checkpoint.exists());
    for f in ["positions.csv", "contact_pattern.csv"] {
        let a = std::fs::read_to_string(whole.join(f)).unwrap();
        let b = std::fs::read_to_string(out.join(f)).unwrap();
        assert!(a.lines().count() > 9, "{f}: {} lines", a.lines().count());
        assert!(a == b, "{f} differs between the whole and the resumed run");
    }
    let _ = std::fs::remove_dir_all(&d);
}

/// SIGKILL at 20 random instants of `flank run` (5 positions with VTU
/// files and plots, about 1.2 s; the kill falls uniformly in 20–100 % of a
/// whole run's time) into one output folder that a whole run filled first,
/// so that kills hit the overwriting of its files: every file present is
/// complete and loads, none is lost; at the end a `--resume` from what the
/// last kill left completes the cycle.
#[test]
fn sigkill_at_random_points_leaves_only_complete_files() {
    let d = tmp("sigkill");
    let out = d.join("out");
    let angles = "-6,-3,0,3,6";
    // a small LCG seeded by the clock: the seed is printed for a rerun
    let seed = std::env::var("FLANK_KILL_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| {
            std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .unwrap()
                .as_nanos() as u64
        });
    eprintln!("FLANK_KILL_SEED={seed}");
    let mut state = seed | 1;
    let mut uniform = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    // one whole run first: its duration sets the kill window (the machine
    // may be loaded), and its files are what the killed runs overwrite
    let t = Instant::now();
    assert!(run_command(&out, angles).status().unwrap().success());
    let whole = t.elapsed().as_secs_f64();
    let (files, _) = check_files_complete(&out);
    assert!(files >= 10, "{files} files");
    let (mut killed, mut finished, mut checked, mut temps) = (0, 0, 0, 0);
    for _ in 0..20 {
        let mut child = run_command(&out, angles).spawn().unwrap();
        // 0.1–0.7 of the whole run: on a machine whose load falls after
        // the first run, 0.2–1.0 let most runs finish before the kill
        std::thread::sleep(Duration::from_secs_f64(whole * (0.1 + 0.6 * uniform())));
        if child.try_wait().unwrap().is_none() {
            signal(&child, libc::SIGKILL);
            killed += 1;
        } else {
            finished += 1;
        }
        wait(&mut child);
        let (c, t) = check_files_complete(&out);
        assert!(c >= files, "a kill removed files: {c} of {files}");
        checked += c;
        temps += t;
    }
    eprintln!(
        "whole run {whole:.2} s; {killed} killed, {finished} finished; {checked} files checked, \
         {temps} temporary files left by kills"
    );
    assert!(killed >= 10, "only {killed} of 20 runs were killed mid-way");
    let o = run_command(&out, angles).arg("--resume").output().unwrap();
    assert!(o.status.success(), "{}", text(&o).1);
    assert_eq!(csv_rows(&out.join("mesh_cycle.csv")), 5);
    // the next run removed what the kills left half-written
    let (_, temps) = check_files_complete(&out);
    assert_eq!(temps, 0);
    let _ = std::fs::remove_dir_all(&d);
}

/// Two `flank compliance` processes started together on one cache
/// directory (seed 002, coarse): the lock makes each body's tensor computed
/// once (by one process; the other waits and reads it), the cache holds one
/// whole file per body and no temporary file. A truncated cache file is
/// then recomputed with a warning, never trusted.
#[test]
fn two_processes_share_a_cache_directory() {
    let d = tmp("cache");
    let cache = d.join("cache");
    let compliance = |out: &str| {
        let mut c = flank();
        c.args([
            "compliance",
            "papers/seed002-spur/scene.toml",
            "--flank-size",
            "1.5",
            "--base-size",
            "3",
            "--format",
            "native",
            "--cache",
        ])
        .arg(&cache)
        .arg("--out")
        .arg(d.join(out));
        c
    };
    let source = |out: &str, body: &str| -> String {
        let s: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(d.join(out).join("summary.json")).unwrap(),
        )
        .unwrap();
        s["bodies"][body]["source"].as_str().unwrap().to_string()
    };
    let mut a = compliance("a").spawn().unwrap();
    let mut b = compliance("b").spawn().unwrap();
    assert!(wait(&mut a).success() && wait(&mut b).success());
    let mut tensors = Vec::new();
    for e in std::fs::read_dir(&cache).unwrap() {
        let p = e.unwrap().path();
        let name = p.file_name().unwrap().to_string_lossy().into_owned();
        assert!(!flank::atomic_file::is_temp(&name), "{name} left");
        if name.ends_with(".compliance.bin") {
            flank::compliance::cache::read(&p).unwrap();
            tensors.push(p);
        } else {
            assert!(name.ends_with(".lock"), "{name}");
        }
    }
    assert_eq!(tensors.len(), 2, "{tensors:?}");
    for body in ["pinion", "gear"] {
        let mut s = [source("a", body), source("b", body)];
        s.sort();
        assert_eq!(s, ["computed", "disk"], "{body}");
    }
    // a truncated cache file: recomputed with a warning and replaced
    let p = tensors
        .iter()
        .find(|p| p.to_string_lossy().contains("pinion"))
        .unwrap();
    let whole = std::fs::read(p).unwrap();
    std::fs::write(p, &whole[..whole.len() / 3]).unwrap();
    let o = compliance("c").output().unwrap();
    assert!(o.status.success(), "{}", text(&o).1);
    assert!(
        text(&o)
            .1
            .contains("warning: compliance cache file not used"),
        "{}",
        text(&o).1
    );
    assert_eq!(source("c", "pinion"), "computed");
    assert_eq!(source("c", "gear"), "disk");
    assert_eq!(std::fs::read(p).unwrap().len(), whole.len());
    flank::compliance::cache::read(p).unwrap();
    let _ = std::fs::remove_dir_all(&d);
}
