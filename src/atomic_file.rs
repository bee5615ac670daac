//! Files written whole or not at all, and locks between flank processes.
//!
//! Every result and cache file flank writes goes through [`write`](fn@write) or
//! [`write_with`]: the bytes go to a temporary name beside the target
//! ([`temp_path`], a hidden `.tmp-<pid>-<n>.<name>` that keeps the
//! extension, so that plotters and HDF5 pick the right format), are synced,
//! and the temporary file is renamed over the target. A POSIX rename within
//! one file system is atomic: a reader, or a run killed at any instant,
//! sees the old file, the new file, or no file, never half of one. A kill
//! may leave a temporary file behind; [`is_temp`] names them (readers skip
//! them, and they can be deleted).
//!
//! [`FileLock`] is an exclusive advisory lock on a lock file (std's
//! `File::lock`, `flock(2)` on Linux), held by one process (or one thread's
//! open file) at a time; two flank processes sharing a compliance cache
//! directory take it around "look up, else compute and store".

use std::io::Write;
use std::path::{Path, PathBuf};

use crate::error::FlankError;

/// Prefix of every temporary name.
const TEMP_PREFIX: &str = ".tmp-";

/// A temporary name beside `path` that no other writer uses: the process
/// id and a per-process sequence number (two writers of the same file in
/// one process must not share it), then the file's own name.
pub fn temp_path(path: &Path) -> PathBuf {
    use std::sync::atomic::{AtomicU64, Ordering};
    static SEQUENCE: AtomicU64 = AtomicU64::new(0);
    let n = SEQUENCE.fetch_add(1, Ordering::Relaxed);
    let mut name = std::ffi::OsString::from(format!("{TEMP_PREFIX}{}-{n}.", std::process::id()));
    name.push(path.file_name().unwrap_or_default());
    path.with_file_name(name)
}

/// Whether a file name is one of [`temp_path`]'s (a write in progress, or
/// left by a killed process).
pub fn is_temp(name: &str) -> bool {
    name.starts_with(TEMP_PREFIX)
}

/// Removes the temporary files in `dir` left by killed processes: those of
/// [`temp_path`] whose process no longer runs (Linux: no `/proc/<pid>`;
/// elsewhere nothing is removed). Returns how many were removed. A file of
/// a running writer, this process's included, is left alone.
pub fn remove_stale_temps(dir: &Path) -> usize {
    if !Path::new("/proc/self").exists() {
        return 0;
    }
    let Ok(entries) = std::fs::read_dir(dir) else {
        return 0;
    };
    let mut removed = 0;
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let Some(rest) = name.strip_prefix(TEMP_PREFIX) else {
            continue;
        };
        let Some(pid) = rest.split('-').next().and_then(|p| p.parse::<u32>().ok()) else {
            continue;
        };
        if pid != std::process::id()
            && !Path::new(&format!("/proc/{pid}")).exists()
            && std::fs::remove_file(e.path()).is_ok()
        {
            removed += 1;
        }
    }
    removed
}

/// Writes `bytes` to `path` atomically (temporary name, sync, rename).
pub fn write(path: &Path, bytes: impl AsRef<[u8]>) -> Result<(), FlankError> {
    write_with(path, |tmp| {
        let mut f = std::fs::File::create(tmp).map_err(|e| FlankError::io(tmp, e))?;
        f.write_all(bytes.as_ref())
            .map_err(|e| FlankError::io(tmp, e))
    })
}

/// Writes `path` atomically through a writer that creates the file it is
/// given (a plotting backend, an HDF5 library, a streaming writer): `make`
/// writes the temporary path, which is then synced and renamed over `path`;
/// on any error the temporary file is removed and `path` is untouched.
pub fn write_with<T>(
    path: &Path,
    make: impl FnOnce(&Path) -> Result<T, FlankError>,
) -> Result<T, FlankError> {
    let tmp = temp_path(path);
    let finish = || -> Result<T, FlankError> {
        let value = make(&tmp)?;
        // sync the data before the rename: after a crash of the machine the
        // name never points at a file whose data was not written
        std::fs::File::open(&tmp)
            .and_then(|f| f.sync_all())
            .map_err(|e| FlankError::io(&tmp, e))?;
        std::fs::rename(&tmp, path).map_err(|e| FlankError::io(path, e))?;
        Ok(value)
    };
    let r = finish();
    if r.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    r
}

/// A streaming writer of a file written whole or not at all: writes go to
/// a buffered temporary file; [`commit`](Self::commit) flushes, syncs and
/// renames it over the target; dropped without a commit (an error on the
/// way), the temporary file is removed and the target is untouched.
pub struct AtomicWriter {
    path: PathBuf,
    tmp: PathBuf,
    w: Option<std::io::BufWriter<std::fs::File>>,
}

impl AtomicWriter {
    /// Starts writing `path` (through a temporary file beside it).
    pub fn create(path: &Path) -> Result<Self, FlankError> {
        let tmp = temp_path(path);
        let f = std::fs::File::create(&tmp).map_err(|e| FlankError::io(&tmp, e))?;
        Ok(AtomicWriter {
            path: path.to_path_buf(),
            tmp,
            w: Some(std::io::BufWriter::with_capacity(1 << 16, f)),
        })
    }

    /// Flushes, syncs and renames the temporary file over the target.
    pub fn commit(mut self) -> Result<(), FlankError> {
        let Some(w) = self.w.take() else {
            return Ok(());
        };
        let r = w
            .into_inner()
            .map_err(|e| e.into_error())
            .and_then(|f| f.sync_all())
            .map_err(|e| FlankError::io(&self.tmp, e))
            .and_then(|()| {
                std::fs::rename(&self.tmp, &self.path).map_err(|e| FlankError::io(&self.path, e))
            });
        if r.is_err() {
            let _ = std::fs::remove_file(&self.tmp);
        }
        r
    }
}

impl Write for AtomicWriter {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        match &mut self.w {
            Some(w) => w.write(buf),
            None => Err(std::io::Error::other("write after commit")),
        }
    }
    fn flush(&mut self) -> std::io::Result<()> {
        match &mut self.w {
            Some(w) => w.flush(),
            None => Ok(()),
        }
    }
}

impl Drop for AtomicWriter {
    fn drop(&mut self) {
        if self.w.take().is_some() {
            let _ = std::fs::remove_file(&self.tmp);
        }
    }
}

/// An exclusive lock on a lock file, released when dropped.
pub struct FileLock {
    _file: std::fs::File,
}

impl FileLock {
    /// Waits for and takes the exclusive lock of `path` (created if absent;
    /// it is never removed, so that every process locks the same file).
    pub fn exclusive(path: &Path) -> Result<FileLock, FlankError> {
        let file = std::fs::OpenOptions::new()
            .create(true)
            .truncate(false)
            .read(true)
            .write(true)
            .open(path)
            .map_err(|e| FlankError::io(path, e))?;
        file.lock().map_err(|e| FlankError::io(path, e))?;
        Ok(FileLock { _file: file })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("flank-atomic-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    fn names(d: &Path) -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(d)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn replaces_whole_files_and_leaves_no_temporary() {
        let d = dir("replace");
        let p = d.join("r.csv");
        write(&p, "first").unwrap();
        write(&p, b"second").unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"second");
        assert_eq!(names(&d), ["r.csv"]);
        let t = temp_path(&p);
        let tn = t.file_name().unwrap().to_str().unwrap();
        assert!(is_temp(tn) && tn.ends_with(".r.csv"), "{tn}");
    }

    #[test]
    fn a_failed_writer_leaves_the_old_file() {
        let d = dir("fail");
        let p = d.join("r.json");
        write(&p, "old").unwrap();
        let e = write_with(&p, |tmp| -> Result<(), FlankError> {
            std::fs::write(tmp, "half").unwrap();
            Err(FlankError::Model("writer failed".into()))
        });
        assert!(e.is_err());
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "old");
        assert_eq!(names(&d), ["r.json"]);
        // a missing directory is an I/O error naming the path
        let e = write(&d.join("no/such/dir.txt"), "x").unwrap_err();
        assert!(e.to_string().contains("no/such"), "{e}");
    }

    #[test]
    fn a_streaming_writer_is_visible_only_once_committed() {
        let d = dir("stream");
        let p = d.join("s.csv");
        let mut w = AtomicWriter::create(&p).unwrap();
        writeln!(w, "a,b").unwrap();
        assert!(!p.exists());
        w.commit().unwrap();
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "a,b\n");
        // dropped uncommitted: target untouched, temporary removed
        let mut w = AtomicWriter::create(&p).unwrap();
        writeln!(w, "half").unwrap();
        drop(w);
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "a,b\n");
        assert_eq!(names(&d), ["s.csv"]);
    }

    #[test]
    fn stale_temporaries_of_dead_processes_are_removed() {
        let d = dir("stale");
        // pid 4194304 is above Linux's pid_max limit: never a live process
        std::fs::write(d.join(".tmp-4194304-0.r.csv"), "half").unwrap();
        let own = temp_path(&d.join("s.csv"));
        std::fs::write(&own, "in progress").unwrap();
        std::fs::write(d.join("r.csv"), "whole").unwrap();
        assert_eq!(remove_stale_temps(&d), 1);
        let own = own.file_name().unwrap().to_string_lossy().into_owned();
        let mut want = vec![own, "r.csv".to_string()];
        want.sort();
        assert_eq!(names(&d), want);
    }

    #[test]
    fn lock_is_exclusive_between_open_files() {
        let d = dir("lock");
        let p = d.join("c.lock");
        let first = FileLock::exclusive(&p).unwrap();
        let other = std::fs::OpenOptions::new().write(true).open(&p).unwrap();
        assert!(other.try_lock().is_err(), "second lock taken while held");
        drop(first);
        assert!(other.try_lock().is_ok());
    }
}
