//! `flank campaign submit/status/collect` on a real Slurm cluster: the test
//! starts a one-node cluster on this machine (`tests/slurm/cluster.sh`:
//! private munge key and socket, slurmctld and slurmd as root,
//! proctrack/linuxproc, no cgroups, no accounting), submits the 8-job LTCA
//! campaign of `campaign_local` as a job array, waits (bounded) until the
//! queue is empty, collects, and compares the table with the local
//! executor's (figures equal, times aside).
//!
//! Needs root and Debian's `slurm-wlm` and `munge`. Without the Slurm
//! binaries the test fails when `FLANK_REQUIRE_SLURM=1` (set by `.ci/run`)
//! and otherwise says it did not run; with them, a cluster that does not
//! come up is a failure with the daemons' log files named.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use flank::campaign::collect::read_figures;

const TORQUES: [f64; 8] = [150.0, 175.0, 200.0, 225.0, 250.0, 275.0, 300.0, 312.0];

fn campaign_text() -> String {
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("papers/seed002-spur/scene.toml");
    let list: Vec<String> = TORQUES.iter().map(|t| format!("{t:.1}")).collect();
    format!(
        "[campaign]\nscene = \"{}\"\nanalyses = [\"ltca\"]\n\n[args]\nltca = [\"--no-condition\", \"--roll-angles\", \"-5,0,5\", \"--flank-size\", \"2\", \"--base-size\", \"3\", \"--points-per-line\", \"10\"]\n\n[grid]\n\"load.torque_nm\" = [{}]\n\n[resources]\nmemory_gb = 0.5\ntime_min = 10\n\n[slurm]\nmax_parallel = 4\n",
        scene.display(),
        list.join(", ")
    )
}

fn flank(args: &[&str], conf: Option<&Path>) -> (bool, String, String) {
    let mut c = Command::new(env!("CARGO_BIN_EXE_flank"));
    c.args(args);
    if let Some(conf) = conf {
        c.env("SLURM_CONF", conf);
    }
    let o = c.output().unwrap();
    (
        o.status.success(),
        String::from_utf8_lossy(&o.stdout).into(),
        String::from_utf8_lossy(&o.stderr).into(),
    )
}

fn figures(out: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    read_figures(out).unwrap()
}

/// The cluster's state folder; stops the daemons and removes it when dropped.
struct Cluster {
    dir: PathBuf,
    script: PathBuf,
}

impl Drop for Cluster {
    fn drop(&mut self) {
        let _ = Command::new("sh")
            .arg(&self.script)
            .arg("stop")
            .arg(&self.dir)
            .status();
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

fn slurm_installed() -> bool {
    [
        "/usr/sbin/slurmctld",
        "/usr/sbin/slurmd",
        "/usr/sbin/munged",
        "/usr/bin/sbatch",
    ]
    .iter()
    .all(|p| Path::new(p).exists())
}

#[test]
fn slurm_array_matches_the_local_table() {
    if !slurm_installed() {
        let required = std::env::var("FLANK_REQUIRE_SLURM").is_ok_and(|v| v == "1");
        assert!(
            !required,
            "FLANK_REQUIRE_SLURM=1 but Slurm is not installed: apt-get install -y slurm-wlm munge"
        );
        eprintln!(
            "campaign_slurm: NOT RUN: Slurm is not installed (apt-get install -y slurm-wlm munge)"
        );
        return;
    }
    let t_all = Instant::now();
    // a short path: the munge socket's name must fit a Unix socket address (108 bytes)
    let dir = std::env::temp_dir().join(format!("flank-slurm-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let cluster = Cluster {
        dir: dir.join("cluster"),
        script: Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/slurm/cluster.sh"),
    };
    let t0 = Instant::now();
    let o = Command::new("sh")
        .arg(&cluster.script)
        .arg("start")
        .arg(&cluster.dir)
        .output()
        .unwrap();
    assert!(
        o.status.success(),
        "the one-node Slurm cluster did not start: {}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    let up_s = t0.elapsed().as_secs_f64();
    let conf = cluster.dir.join("slurm.conf");

    let c = dir.join("tolerance.toml");
    std::fs::write(&c, campaign_text()).unwrap();
    let cs = c.to_str().unwrap();
    let local = dir.join("local");
    let slurm = dir.join("slurm");
    let (ok, out, err) = flank(
        &["campaign", "run", cs, "--out", local.to_str().unwrap()],
        None,
    );
    assert!(ok, "{out}\n{err}");

    let t1 = Instant::now();
    let so = slurm.to_str().unwrap();
    let (ok, out, err) = flank(&["campaign", "submit", cs, "--out", so], Some(&conf));
    assert!(ok, "{out}\n{err}");
    assert!(out.contains("submitted 8 jobs as Slurm array"), "{out}");
    let script = std::fs::read_to_string(slurm.join("slurm/array_0_0.sh")).unwrap();
    for line in [
        "--array=0-7%4",
        "--mem=512M",
        "--cpus-per-task=1",
        "--time=10",
    ] {
        assert!(script.contains(line), "{line} missing:\n{script}");
    }
    let (ok, out, err) = flank(
        &["campaign", "status", cs, "--out", so, "--wait", "300"],
        Some(&conf),
    );
    let logs = || {
        ["slurmctld.log", "slurmd.log"]
            .iter()
            .map(|f| std::fs::read_to_string(cluster.dir.join(f)).unwrap_or_default())
            .collect::<Vec<_>>()
            .join("\n")
    };
    assert!(ok, "{out}\n{err}\n{}", logs());
    assert!(
        out.contains("8 jobs: 8 done, 0 queued or running, 0 failed"),
        "{out}\n{}",
        logs()
    );
    let slurm_s = t1.elapsed().as_secs_f64();
    let (ok, out, err) = flank(&["campaign", "collect", cs, "--out", so], None);
    assert!(ok, "{out}\n{err}");
    let (h, rows) = figures(&slurm);
    assert_eq!(rows.len(), 8);
    assert!(h.iter().any(|x| x == "single_pair_force_n"));
    assert_eq!((h, rows), figures(&local));
    // every job ran under Slurm (its completion record names the array task)
    for e in std::fs::read_dir(slurm.join("jobs")).unwrap().flatten() {
        let rec = std::fs::read_to_string(e.path().join("done.json")).unwrap();
        assert!(rec.contains("\"slurm_job\": \""), "{rec}");
    }
    // nothing left to submit
    let (ok, out, _) = flank(&["campaign", "submit", cs, "--out", so], Some(&conf));
    assert!(ok && out.contains("nothing submitted"), "{out}");
    eprintln!(
        "campaign_slurm: cluster up in {up_s:.1} s, 8 array tasks in {slurm_s:.1} s, whole test {:.1} s",
        t_all.elapsed().as_secs_f64()
    );
    drop(cluster);
    let _ = std::fs::remove_dir_all(&dir);
}
