//! [`ComplianceCache`]: compliance tensors by their
//! [`crate::compliance::cache_key`] (mesh hash + Dirichlet conditions +
//! couplings + material + flank nodes), in memory and as files in a
//! directory ([`super::cache`] reads and writes them): the same body is
//! computed once per campaign, and read once per campaign worker process.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use crate::compliance::cache::{read_key, read_trusted, write, FileFormat};
use crate::compliance::ComplianceTensor;
use crate::error::FlankError;

/// Where a tensor came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum CacheOutcome {
    /// Computed now (and stored).
    Computed,
    /// Found in this process's memory.
    Memory,
    /// Read from a file in the cache directory.
    Disk,
}

impl CacheOutcome {
    /// Its name in `summary.json` (`computed`, `memory`, `disk`).
    pub fn name(self) -> &'static str {
        match self {
            CacheOutcome::Computed => "computed",
            CacheOutcome::Memory => "memory",
            CacheOutcome::Disk => "disk",
        }
    }
}

/// Compliance tensors by cache key: in memory, and as files
/// `<body>.<key>.compliance.{h5,bin}` in a directory.
pub struct ComplianceCache {
    dir: Option<PathBuf>,
    format: FileFormat,
    /// key → (body, tensor)
    memory: Mutex<HashMap<String, (String, Arc<ComplianceTensor>)>>,
    /// Keep only the last tensor of each body name in memory
    /// ([`ComplianceCache::shared`]).
    last_per_body: bool,
}

impl ComplianceCache {
    /// A cache in memory only.
    pub fn in_memory() -> Self {
        ComplianceCache {
            dir: None,
            format: FileFormat::default_format(),
            memory: Mutex::new(HashMap::new()),
            last_per_body: false,
        }
    }

    /// A cache in memory and in `dir` (created if absent), files in `format`.
    pub fn in_dir(dir: &Path, format: FileFormat) -> Result<Self, FlankError> {
        std::fs::create_dir_all(dir).map_err(|e| FlankError::io(dir, e))?;
        crate::atomic_file::remove_stale_temps(dir);
        Ok(ComplianceCache {
            dir: Some(dir.to_path_buf()),
            format,
            memory: Mutex::new(HashMap::new()),
            last_per_body: false,
        })
    }

    /// This process's cache of `dir` in `format`, the same one for every
    /// analysis the process runs (a campaign worker running a block of
    /// jobs reads each body's tensor from disk once, not once per job).
    /// It keeps in memory only the last tensor of each body name: a
    /// process never holds more tensors than one analysis needs, however
    /// many variants with other bodies it runs.
    pub fn shared(dir: &Path, format: FileFormat) -> Result<Arc<Self>, FlankError> {
        type Registry = Mutex<HashMap<(PathBuf, FileFormat), Arc<ComplianceCache>>>;
        static REGISTRY: std::sync::OnceLock<Registry> = std::sync::OnceLock::new();
        // the same directory however it is spelled (relative to another
        // working directory, through a link)
        std::fs::create_dir_all(dir).map_err(|e| FlankError::io(dir, e))?;
        let canonical = dir.canonicalize().map_err(|e| FlankError::io(dir, e))?;
        let mut reg = REGISTRY
            .get_or_init(Default::default)
            .lock()
            .map_err(|_| FlankError::Solver("compliance cache registry poisoned".into()))?;
        if let Some(c) = reg.get(&(canonical.clone(), format)) {
            return Ok(Arc::clone(c));
        }
        let mut c = Self::in_dir(&canonical, format)?;
        c.last_per_body = true;
        let c = Arc::new(c);
        reg.insert((canonical, format), Arc::clone(&c));
        Ok(c)
    }

    /// How many tensors this cache holds in memory.
    pub fn in_memory_count(&self) -> usize {
        self.lock().map_or(0, |m| m.len())
    }

    fn remember(&self, body: &str, key: &str, t: &Arc<ComplianceTensor>) -> Result<(), FlankError> {
        let mut m = self.lock()?;
        if self.last_per_body {
            m.retain(|_, (b, _)| b != body);
        }
        m.insert(key.to_string(), (body.to_string(), Arc::clone(t)));
        Ok(())
    }

    /// The file of `key` for `body` in the cache directory.
    pub fn path(&self, body: &str, key: &str) -> Option<PathBuf> {
        let short = &key[..key.len().min(16)];
        self.dir
            .as_ref()
            .map(|d| d.join(format!("{body}.{short}.{}", self.format.extension())))
    }

    /// Puts the cache's file of `key` at `target` as a hard link (made under
    /// a temporary name and renamed over `target`, so a reader sees the old
    /// file or the whole new one): the bytes [`write()`] would write, without
    /// writing 2 × 20 MB per LTCA job. `false` (nothing done) when there is
    /// no such file, its header names another key, `target` has another
    /// format, or the link fails (e.g. another file system): then the
    /// caller writes the file.
    pub fn link_into(&self, body: &str, key: &str, target: &Path) -> bool {
        let Some(src) = self.path(body, key) else {
            return false;
        };
        if FileFormat::of_path(target) != Some(self.format)
            || read_key(&src).ok().as_deref() != Some(key)
        {
            return false;
        }
        let tmp = crate::atomic_file::temp_path(target);
        if std::fs::hard_link(&src, &tmp).is_err() {
            return false;
        }
        let renamed = std::fs::rename(&tmp, target).is_ok();
        // a rename between two links of one file does nothing (POSIX): the
        // temporary name stays and must go
        let _ = std::fs::remove_file(&tmp);
        renamed
    }

    /// The tensor with `key`, from memory or disk, else `compute()`d and stored.
    ///
    /// A file is trusted only when its key and checksum match
    /// ([`read_trusted`]); a corrupt, truncated or foreign file is recomputed
    /// with a warning on stderr and replaced. Processes sharing the
    /// directory take the key's lock file `<body>.<key>.lock`
    /// ([`crate::atomic_file::FileLock`]) around "look up, else compute and
    /// store": the second waits for the first and reads its file instead of
    /// computing the same tensor again.
    pub fn get_or_compute(
        &self,
        body: &str,
        key: &str,
        compute: impl FnOnce() -> Result<ComplianceTensor, FlankError>,
    ) -> Result<(Arc<ComplianceTensor>, CacheOutcome), FlankError> {
        {
            let mut m = self.lock()?;
            if let Some((_, t)) = m.get(key) {
                return Ok((t.clone(), CacheOutcome::Memory));
            }
            if self.last_per_body {
                // dropped before the new one is read or computed: the
                // process holds at most one tensor per body
                m.retain(|_, (b, _)| b != body);
            }
        }
        let path = self.path(body, key);
        let _file_lock = match &path {
            Some(p) => Some(crate::atomic_file::FileLock::exclusive(
                &p.with_extension("").with_extension("lock"),
            )?),
            None => None,
        };
        if let Some(p) = &path {
            if let Some(t) = read_trusted(p, key) {
                let t = Arc::new(t);
                self.remember(body, key, &t)?;
                return Ok((t, CacheOutcome::Disk));
            }
        }
        let t = compute()?;
        if t.meta.cache_key != key {
            return Err(FlankError::Model(format!(
                "computed tensor has key {} instead of {key}",
                t.meta.cache_key
            )));
        }
        if let Some(p) = &path {
            write(p, &t)?;
        }
        let t = Arc::new(t);
        self.remember(body, key, &t)?;
        Ok((t, CacheOutcome::Computed))
    }

    #[allow(clippy::type_complexity)]
    fn lock(
        &self,
    ) -> Result<
        std::sync::MutexGuard<'_, HashMap<String, (String, Arc<ComplianceTensor>)>>,
        FlankError,
    > {
        self.memory
            .lock()
            .map_err(|_| FlankError::Solver("compliance cache lock poisoned".into()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::compliance::flank::tests::box_flank;
    use crate::compliance::{compliance_tensor, ComplianceOptions};
    use crate::mesh::structured::BoxElement;
    use std::cell::Cell;

    fn tensor() -> ComplianceTensor {
        let (model, flank) = box_flank(BoxElement::Hex20);
        compliance_tensor("box", &model, &flank, &ComplianceOptions::default())
            .unwrap()
            .0
    }

    fn tmp(name: &str) -> PathBuf {
        let d =
            std::env::temp_dir().join(format!("flank_tensor_cache_test_{}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        d.join(name)
    }

    #[test]
    fn cache_computes_once() {
        let t = tensor();
        let key = t.meta.cache_key.clone();
        let dir = tmp("cache_dir");
        let _ = std::fs::remove_dir_all(&dir);
        let calls = Cell::new(0);
        let compute = || {
            calls.set(calls.get() + 1);
            Ok(t.clone())
        };
        let c = ComplianceCache::in_dir(&dir, FileFormat::Native).unwrap();
        let (_, o1) = c.get_or_compute("box", &key, compute).unwrap();
        let (_, o2) = c.get_or_compute("box", &key, compute).unwrap();
        assert_eq!((o1, o2), (CacheOutcome::Computed, CacheOutcome::Memory));
        // a new cache over the same directory finds the file
        let c2 = ComplianceCache::in_dir(&dir, FileFormat::Native).unwrap();
        let (t2, o3) = c2.get_or_compute("box", &key, compute).unwrap();
        assert_eq!(o3, CacheOutcome::Disk);
        assert_eq!(calls.get(), 1);
        assert_eq!(t2.matrix, t.matrix);
        // a different key computes (and the wrong key is caught)
        let e = c2.get_or_compute("box", "other", compute);
        assert!(e.is_err());
    }

    /// The shared cache is one per directory however it is spelled, keeps
    /// only the last tensor of each body in memory, and links its files
    /// into a result folder (the bytes `write` writes) instead of writing.
    #[test]
    fn shared_cache_keeps_the_last_tensor_per_body_and_links_its_files() {
        use std::os::unix::fs::MetadataExt;
        let t = tensor();
        let key = t.meta.cache_key.clone();
        let dir = tmp("cache_shared");
        let _ = std::fs::remove_dir_all(&dir);
        let a = ComplianceCache::shared(&dir, FileFormat::Native).unwrap();
        let b = ComplianceCache::shared(&dir.join("..").join("cache_shared"), FileFormat::Native)
            .unwrap();
        assert!(Arc::ptr_eq(&a, &b));
        let calls = Cell::new(0);
        let compute = |t: &ComplianceTensor| {
            calls.set(calls.get() + 1);
            Ok(t.clone())
        };
        let (_, o) = a.get_or_compute("box", &key, || compute(&t)).unwrap();
        assert_eq!(o, CacheOutcome::Computed);
        let (_, o) = b.get_or_compute("box", &key, || compute(&t)).unwrap();
        assert_eq!(o, CacheOutcome::Memory);
        // another tensor of the same body replaces it in memory; one of
        // another body is kept beside it
        let mut other = t.clone();
        other.meta.cache_key = "0123456789abcdef-other".into();
        let mut lid = t.clone();
        lid.meta.cache_key = "fedcba9876543210-lid".into();
        a.get_or_compute("box", &other.meta.cache_key.clone(), || compute(&other))
            .unwrap();
        assert_eq!(a.in_memory_count(), 1);
        a.get_or_compute("lid", &lid.meta.cache_key.clone(), || compute(&lid))
            .unwrap();
        assert_eq!(a.in_memory_count(), 2);
        let (t2, o) = a.get_or_compute("box", &key, || compute(&t)).unwrap();
        assert_eq!(o, CacheOutcome::Disk);
        assert_eq!(t2.matrix, t.matrix);
        assert_eq!(calls.get(), 3);
        // linked: the same bytes as a written file, one inode with the cache's
        let out = tmp("cache_shared_out");
        std::fs::create_dir_all(&out).unwrap();
        let linked = out.join("box.compliance.bin");
        let written = out.join("written.compliance.bin");
        assert!(a.link_into("box", &key, &linked));
        write(&written, &t).unwrap();
        assert_eq!(
            std::fs::read(&linked).unwrap(),
            std::fs::read(&written).unwrap()
        );
        assert!(std::fs::metadata(&linked).unwrap().nlink() >= 2);
        // linking again replaces the link; no temporary left
        assert!(a.link_into("box", &key, &linked));
        let names: Vec<String> = std::fs::read_dir(&out)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        assert_eq!(names.len(), 2, "{names:?}");
        // no file for that key, another format: nothing linked
        assert!(!a.link_into("box", "no-such-key", &out.join("x.compliance.bin")));
        assert!(!a.link_into("box", &key, &out.join("box.compliance.h5")));
        assert!(!out.join("x.compliance.bin").exists());
    }

    /// A cache file that is truncated, has a flipped byte, or is junk is
    /// never trusted: recomputed (with a warning) and replaced by a whole
    /// file; the lock file stays beside it.
    #[test]
    fn corrupt_cache_files_are_recomputed() {
        let t = tensor();
        let key = t.meta.cache_key.clone();
        let dir = tmp("cache_corrupt");
        let _ = std::fs::remove_dir_all(&dir);
        let calls = Cell::new(0);
        let compute = || {
            calls.set(calls.get() + 1);
            Ok(t.clone())
        };
        ComplianceCache::in_dir(&dir, FileFormat::Native)
            .unwrap()
            .get_or_compute("box", &key, compute)
            .unwrap();
        let c = ComplianceCache::in_dir(&dir, FileFormat::Native).unwrap();
        let p = c.path("box", &key).unwrap();
        let good = std::fs::read(&p).unwrap();
        let mut flipped = good.clone();
        let mid = flipped.len() - 100;
        flipped[mid] ^= 0x10;
        for bad in [good[..good.len() / 2].to_vec(), flipped, b"junk".to_vec()] {
            std::fs::write(&p, &bad).unwrap();
            let c = ComplianceCache::in_dir(&dir, FileFormat::Native).unwrap();
            let (t2, o) = c.get_or_compute("box", &key, compute).unwrap();
            assert_eq!(o, CacheOutcome::Computed);
            assert_eq!(t2.matrix, t.matrix);
            assert_eq!(std::fs::read(&p).unwrap(), good, "replaced whole");
        }
        assert_eq!(calls.get(), 4);
        let mut names: Vec<String> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        assert_eq!(names.len(), 2, "{names:?}");
        assert!(names[1].ends_with(".lock"), "{names:?}");
    }
}
