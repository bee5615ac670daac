//! Cross-code verification against CalculiX (`ccx`, Debian package
//! `calculix-ccx`): run a deck, read the displacements it prints, compare.
//!
//! The deck must request `*NODE PRINT, NSET=NALL` / `U` (flank's deck writer
//! does); ccx then writes `displacements (vx,vy,vz) for set NALL` blocks to
//! `<job>.dat`.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use crate::error::FlankError;
use crate::fem::mesh::Mesh;

/// The ccx executable: `$FLANK_CCX` or `ccx` on the PATH, if it runs.
pub fn ccx_executable() -> Option<PathBuf> {
    let exe = std::env::var_os("FLANK_CCX")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("ccx"));
    let ok = Command::new(&exe)
        .arg("-v")
        .output()
        .map(|o| String::from_utf8_lossy(&o.stdout).contains("Version") || o.status.success())
        .unwrap_or(false);
    ok.then_some(exe)
}

/// Displacements printed by a ccx run, by node label, and its wall time.
pub struct CcxResult {
    pub displacements: HashMap<u64, [f64; 3]>,
    pub wall_s: f64,
}

/// Runs ccx on `deck` inside `workdir` (the deck is copied there) with `threads` threads.
pub fn run_ccx(deck: &Path, workdir: &Path, threads: usize) -> Result<CcxResult, FlankError> {
    let exe = ccx_executable().ok_or_else(|| {
        FlankError::Solver("ccx (CalculiX) not found: apt-get install calculix-ccx".into())
    })?;
    std::fs::create_dir_all(workdir).map_err(|e| FlankError::io(workdir, e))?;
    let job = "job";
    let target = workdir.join(format!("{job}.inp"));
    std::fs::copy(deck, &target).map_err(|e| FlankError::io(deck, e))?;
    let t = Instant::now();
    let out = Command::new(&exe)
        .arg("-i")
        .arg(job)
        .current_dir(workdir)
        .env("OMP_NUM_THREADS", threads.max(1).to_string())
        .env("CCX_NPROC_EQUATION_SOLVER", threads.max(1).to_string())
        .output()
        .map_err(|e| FlankError::io(&exe, e))?;
    let wall_s = t.elapsed().as_secs_f64();
    let stdout = String::from_utf8_lossy(&out.stdout);
    if !out.status.success() || stdout.contains("*ERROR") {
        let err: Vec<&str> = stdout
            .lines()
            .filter(|l| l.contains("ERROR"))
            .take(5)
            .collect();
        return Err(FlankError::Solver(format!(
            "ccx failed on {}: {}",
            deck.display(),
            err.join(" | ")
        )));
    }
    let dat = workdir.join(format!("{job}.dat"));
    let text = std::fs::read_to_string(&dat).map_err(|e| FlankError::io(&dat, e))?;
    Ok(CcxResult {
        displacements: parse_dat_displacements(&text),
        wall_s,
    })
}

/// Parses the last `displacements (vx,vy,vz)` block(s) of a ccx `.dat` file.
pub fn parse_dat_displacements(text: &str) -> HashMap<u64, [f64; 3]> {
    let mut out = HashMap::new();
    let mut inside = false;
    for line in text.lines() {
        let t = line.trim();
        if t.starts_with("displacements") {
            inside = true;
            continue;
        }
        if t.is_empty() {
            continue;
        }
        if !inside {
            continue;
        }
        let f: Vec<&str> = t.split_whitespace().collect();
        if f.len() == 4 {
            if let (Ok(n), Ok(x), Ok(y), Ok(z)) = (
                f[0].parse::<u64>(),
                f[1].parse::<f64>(),
                f[2].parse::<f64>(),
                f[3].parse::<f64>(),
            ) {
                out.insert(n, [x, y, z]);
                continue;
            }
        }
        inside = false;
    }
    out
}

/// max_i |u_flank − u_ccx| / max_i |u_ccx| over the nodes ccx printed.
pub fn relative_difference(
    mesh: &Mesh,
    u: &[f64],
    ccx: &HashMap<u64, [f64; 3]>,
) -> Result<f64, FlankError> {
    if ccx.is_empty() {
        return Err(FlankError::Solver("ccx printed no displacements".into()));
    }
    let mut max_diff = 0.0f64;
    let mut max_ref = 0.0f64;
    for (&label, v) in ccx {
        let i = mesh.node(label).ok_or_else(|| {
            FlankError::Solver(format!("ccx printed node {label}, unknown to flank"))
        })?;
        let d = ((u[3 * i] - v[0]).powi(2)
            + (u[3 * i + 1] - v[1]).powi(2)
            + (u[3 * i + 2] - v[2]).powi(2))
        .sqrt();
        max_diff = max_diff.max(d);
        max_ref = max_ref.max((v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt());
    }
    Ok(if max_ref > 0.0 {
        max_diff / max_ref
    } else {
        max_diff
    })
}
