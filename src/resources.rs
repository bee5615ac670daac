//! Memory of the machine and of this process, and the memory guard that
//! refuses a computation that would not fit.
//!
//! A sparse factorization, a Schur complement or a dense compliance tensor
//! that needs more memory than the machine can give is otherwise ended by
//! the operating system's OOM killer: no message, no result, sometimes after
//! an hour of work. [`check_memory`] compares an estimate of the additional
//! bytes a step will allocate with the [`headroom`] (what this process may
//! still allocate) and returns a [`FlankError::Memory`] that gives both
//! figures and what to do instead.
//!
//! The headroom is the smallest of
//!
//! * the machine's `MemAvailable` (`/proc/meminfo`);
//! * the cgroup limit less the cgroup's usage (v2 `memory.max` /
//!   `memory.current`, v1 `memory.limit_in_bytes` / `memory.usage_in_bytes`,
//!   reclaimable page cache not counted), when a limit is set;
//! * a user limit on the whole process, less its resident set (`VmRSS`):
//!   the environment variable [`LIMIT_VAR`] (`FLANK_MEMORY_LIMIT_MB`), or
//!   `flank --memory-limit-mb`, which sets [`set_memory_limit_mb`].
//!
//! This module is the lowest layer: it imports nothing of flank but the
//! error type, so that `fem`, `compliance` and `campaign` share it.

use std::cell::Cell;
use std::sync::atomic::{AtomicU64, Ordering};

use crate::error::FlankError;

/// The environment variable of a lowered memory limit (MB) for the whole
/// flank process, e.g. `FLANK_MEMORY_LIMIT_MB=4000` on a shared machine.
pub const LIMIT_VAR: &str = "FLANK_MEMORY_LIMIT_MB";

/// The process-wide limit set by [`set_memory_limit_mb`] (f64 bits; 0 = none).
static LIMIT_BITS: AtomicU64 = AtomicU64::new(0);

thread_local! {
    /// A limit for the checks made on this thread only (tests).
    static THREAD_LIMIT: Cell<Option<f64>> = const { Cell::new(None) };
}

/// Sets the process-wide memory limit (MB) that the guard respects, as the
/// command line's `--memory-limit-mb` does; it takes precedence over
/// [`LIMIT_VAR`]. `None` clears it.
pub fn set_memory_limit_mb(limit: Option<f64>) {
    let bits = limit.filter(|l| *l > 0.0).map_or(0, f64::to_bits);
    LIMIT_BITS.store(bits, Ordering::Relaxed);
}

/// Runs `f` with a memory limit of `limit_mb` for the checks made on this
/// thread (a test's lowered limit that does not leak into other tests).
pub fn with_memory_limit_mb<T>(limit_mb: f64, f: impl FnOnce() -> T) -> T {
    let old = THREAD_LIMIT.with(|c| c.replace(Some(limit_mb)));
    let r = f();
    THREAD_LIMIT.with(|c| c.set(old));
    r
}

/// The user's limit (MB) and where it comes from: this thread's, the
/// process-wide one, or [`LIMIT_VAR`]. An unparsable or non-positive
/// variable is an error (a typo must not silently lift the limit).
pub fn user_limit_mb() -> Result<Option<(f64, String)>, FlankError> {
    if let Some(l) = THREAD_LIMIT.with(Cell::get) {
        return Ok(Some((l, "the test's memory limit".into())));
    }
    let bits = LIMIT_BITS.load(Ordering::Relaxed);
    if bits != 0 {
        return Ok(Some((f64::from_bits(bits), "--memory-limit-mb".into())));
    }
    match std::env::var(LIMIT_VAR) {
        Ok(v) => match v.trim().parse::<f64>() {
            Ok(l) if l > 0.0 && l.is_finite() => Ok(Some((l, LIMIT_VAR.into()))),
            _ => Err(FlankError::Memory(format!(
                "{LIMIT_VAR}={v:?}: expected a positive number of megabytes"
            ))),
        },
        Err(_) => Ok(None),
    }
}

/// A field of a `/proc` status-like file in kB, as MB.
fn proc_field_mb(file: &str, name: &str) -> Option<f64> {
    let text = std::fs::read_to_string(file).ok()?;
    let line = text.lines().find(|l| l.starts_with(name))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb / 1024.0)
}

/// The machine's memory (MB): (total, available) from /proc/meminfo; `None`
/// where it cannot be read (not Linux).
pub fn machine_memory_mb() -> Option<(f64, f64)> {
    let total = proc_field_mb("/proc/meminfo", "MemTotal:")?;
    Some((
        total,
        proc_field_mb("/proc/meminfo", "MemAvailable:").unwrap_or(total),
    ))
}

/// Resident memory of this process now (MB, `VmRSS`; 0 where unknown).
pub fn resident_mb() -> f64 {
    proc_field_mb("/proc/self/status", "VmRSS:").unwrap_or(0.0)
}

/// Peak resident memory of this process (MB, `VmHWM`; 0 where unknown).
pub fn peak_memory_mb() -> f64 {
    proc_field_mb("/proc/self/status", "VmHWM:").unwrap_or(0.0)
}

/// A number of bytes from a cgroup file (`max` and absurd v1 "no limit"
/// values are `None`).
fn cgroup_bytes(path: &str) -> Option<f64> {
    let s = std::fs::read_to_string(path).ok()?;
    let v: f64 = s.trim().parse().ok()?;
    (v < 1e18).then_some(v)
}

/// Reclaimable page cache of a cgroup (bytes) from its `memory.stat`.
fn cgroup_inactive_file(stat: &str) -> f64 {
    let text = std::fs::read_to_string(stat).unwrap_or_default();
    ["total_inactive_file ", "inactive_file "]
        .iter()
        .find_map(|k| {
            text.lines()
                .find(|l| l.starts_with(k))
                .and_then(|l| l.split_whitespace().nth(1))
                .and_then(|v| v.parse::<f64>().ok())
        })
        .unwrap_or(0.0)
}

/// The cgroup memory limit and usage of this process (MB), when a limit
/// is set: v2 (`0::/path`) or v1 (`N:memory:/path`), at the process's own
/// cgroup or, in a container, at the mount's root.
pub fn cgroup_memory_mb() -> Option<(f64, f64)> {
    let own = std::fs::read_to_string("/proc/self/cgroup").unwrap_or_default();
    let path_of = |pred: &dyn Fn(&str) -> bool| -> Option<String> {
        own.lines().find_map(|l| {
            let mut it = l.splitn(3, ':');
            let (_, ctl, p) = (it.next()?, it.next()?, it.next()?);
            pred(ctl).then(|| p.trim_end_matches('/').to_string())
        })
    };
    let mut dirs = Vec::new();
    if let Some(p) = path_of(&|c| c.is_empty()) {
        dirs.push((format!("/sys/fs/cgroup{p}"), false));
    }
    dirs.push(("/sys/fs/cgroup".to_string(), false));
    if let Some(p) = path_of(&|c| c.split(',').any(|x| x == "memory")) {
        dirs.push((format!("/sys/fs/cgroup/memory{p}"), true));
    }
    dirs.push(("/sys/fs/cgroup/memory".to_string(), true));
    for (d, v1) in dirs {
        let (max, cur) = if v1 {
            ("memory.limit_in_bytes", "memory.usage_in_bytes")
        } else {
            ("memory.max", "memory.current")
        };
        if let Some(limit) = cgroup_bytes(&format!("{d}/{max}")) {
            let used = cgroup_bytes(&format!("{d}/{cur}")).unwrap_or(0.0)
                - cgroup_inactive_file(&format!("{d}/memory.stat"));
            return Some((limit / 1048576.0, used.max(0.0) / 1048576.0));
        }
    }
    None
}

/// What this process may still allocate (MB), and the bound that sets it.
#[derive(Clone, Debug, PartialEq)]
pub struct Headroom {
    pub mb: f64,
    /// The bound, in words: "MemAvailable", "the cgroup limit of 8.0 GB
    /// (5.1 GB in use)", "FLANK_MEMORY_LIMIT_MB = 200 MB (this process uses
    /// 150 MB)".
    pub source: String,
}

/// The smallest of the bounds named in the module doc; `None` when none is
/// known (not Linux and no user limit).
pub fn headroom() -> Result<Option<Headroom>, FlankError> {
    let mut best: Option<Headroom> = None;
    let mut take = |mb: f64, source: String| {
        if best.as_ref().is_none_or(|b| mb < b.mb) {
            best = Some(Headroom { mb, source });
        }
    };
    if let Some((_, avail)) = machine_memory_mb() {
        take(
            avail,
            "the machine's available memory (MemAvailable)".into(),
        );
    }
    if let Some((limit, used)) = cgroup_memory_mb() {
        take(
            limit - used,
            format!(
                "the cgroup memory limit of {} ({} in use)",
                format_mb(limit),
                format_mb(used)
            ),
        );
    }
    if let Some((limit, from)) = user_limit_mb()? {
        let rss = resident_mb();
        take(
            limit - rss,
            format!(
                "{from} = {} (this process already uses {})",
                format_mb(limit),
                format_mb(rss)
            ),
        );
    }
    Ok(best)
}

/// "850 MB", "12.4 GB".
pub fn format_mb(mb: f64) -> String {
    if mb.abs() >= 1024.0 {
        format!("{:.1} GB", mb / 1024.0)
    } else {
        format!("{:.0} MB", mb)
    }
}

/// What to do instead, for messages of the guard's callers.
pub const ALTERNATIVES: &str = "use a coarser mesh (a larger --flank-size or --base-size, \
fewer teeth in the sector, fewer flank nodes), the mixed-precision factor (half the \
factor's memory: the default of flank solve; --precision mixed where another command \
offers it), or run where more memory is free";

/// Refuses `what` when its estimated additional memory `need_mb` exceeds
/// the [`headroom`]: the error names the step, both figures, the bound, and
/// `alternatives`. Where no bound is known, the check passes.
pub fn check_memory(what: &str, need_mb: f64, alternatives: &str) -> Result<(), FlankError> {
    let Some(room) = headroom()? else {
        return Ok(());
    };
    if need_mb <= room.mb {
        return Ok(());
    }
    Err(FlankError::Memory(format!(
        "{what} needs about {} more memory, but only {} is available ({}); \
         refused rather than killed by the operating system: {alternatives}",
        format_mb(need_mb),
        format_mb(room.mb.max(0.0)),
        room.source
    )))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thread_limit_refuses_with_both_figures() {
        with_memory_limit_mb(1.0, || {
            let e = check_memory("a 3 GB test step", 3072.0, ALTERNATIVES).unwrap_err();
            let m = e.to_string();
            assert!(m.contains("needs about 3.0 GB more"), "{m}");
            assert!(m.contains("the test's memory limit = 1 MB"), "{m}");
            assert!(m.contains("--flank-size"), "{m}");
        });
        // outside the closure the thread's limit is gone
        assert!(THREAD_LIMIT.with(Cell::get).is_none());
    }

    #[test]
    fn small_steps_pass_on_this_machine() {
        check_memory("a 1 MB step", 1.0, ALTERNATIVES).unwrap();
        let room = headroom().unwrap().expect("Linux knows its memory");
        assert!(room.mb > 1.0, "{room:?}");
    }

    #[test]
    fn figures_read_on_linux() {
        let (total, avail) = machine_memory_mb().unwrap();
        assert!(total >= avail && avail > 0.0);
        // resident first: the high-water mark read after it is at least
        // that (read the other way round, the set can grow in between)
        let resident = resident_mb();
        let peak = peak_memory_mb();
        assert!(resident > 0.0 && peak >= resident, "{peak} < {resident}");
        assert_eq!(format_mb(850.4), "850 MB");
        assert_eq!(format_mb(12.4 * 1024.0), "12.4 GB");
    }
}
