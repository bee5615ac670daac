//! The positions of a `flank run` solved so far, kept on disk so that an
//! interrupted run (SIGINT, a kill, a lost node) resumes where it stopped.
//! One format for every pair kind's positions ([`StepResult`], or what a
//! run keeps beside it), through [`Position`].
//!
//! `OUT/checkpoint.json` holds `{"format": 1, "key": …, "steps": [...]}`:
//! every position solved so far (its whole result), rewritten
//! atomically ([`crate::atomic_file`]) after each position, removed when
//! the run completes (summary.json then holds everything). The key is a
//! SHA-256 of what determines a position's result: the flank version, the
//! scene file's text, the mesh options and the resolved settings (roll
//! angles aside, so that a resumed run may ask for more). `flank run
//! --resume` takes the positions of a checkpoint whose key matches and
//! solves only the others; a checkpoint of another scene or other options
//! is an error, never mixed in.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use sha2::{Digest, Sha256};

use crate::error::FlankError;
use crate::mesh_cycle::cycle::{RunSettings, StepResult};

/// The file name in the output folder.
pub const FILE: &str = "checkpoint.json";
const FORMAT: u32 = 1;

#[derive(serde::Serialize, serde::Deserialize)]
struct Stored {
    format: u32,
    key: String,
    /// Each step as JSON: one that does not read back (a non-finite number
    /// is written as null) is solved again rather than failing the resume.
    steps: Vec<serde_json::Value>,
}

/// A position's result as a checkpoint keeps it: serialisable both ways
/// and known by its roll angle.
pub trait Position: serde::Serialize + serde::de::DeserializeOwned + Clone {
    /// The roll angle (deg) the result belongs to.
    fn roll_deg(&self) -> f64;
}

impl Position for StepResult {
    fn roll_deg(&self) -> f64 {
        self.roll_deg
    }
}

/// The checkpoint of one run.
pub struct Checkpoint<T: Position = StepResult> {
    path: PathBuf,
    key: String,
    /// Positions solved by this run or taken from the resumed checkpoint.
    steps: Vec<T>,
    /// Positions of the resumed checkpoint, by the bits of their roll angle.
    resumed: HashMap<u64, T>,
    /// Positions taken from it so far.
    reused: usize,
}

/// The key of a run: the hash of what determines its positions' results.
pub fn run_key(
    scene_source: &Path,
    mesh: &impl std::fmt::Debug,
    settings: &RunSettings,
) -> Result<String, FlankError> {
    let mut s = settings.clone();
    s.roll_angles_deg.clear();
    let settings =
        serde_json::to_string(&s).map_err(|e| FlankError::Model(format!("checkpoint key: {e}")))?;
    Ok(key(scene_source, mesh, &settings))
}

/// The key of a run from its scene file's text, its mesh options and its
/// other settings (`settings`, their serialised form without the roll
/// angles), with the flank version.
pub fn key(scene_source: &Path, mesh: &impl std::fmt::Debug, settings: &str) -> String {
    let scene = std::fs::read(scene_source).unwrap_or_default();
    let mut h = Sha256::new();
    for part in [
        env!("CARGO_PKG_VERSION").as_bytes(),
        option_env!("FLANK_GIT_HASH").unwrap_or("").as_bytes(),
        &scene,
        format!("{mesh:?}").as_bytes(),
        settings.as_bytes(),
    ] {
        h.update((part.len() as u64).to_le_bytes());
        h.update(part);
    }
    h.finalize().iter().map(|b| format!("{b:02x}")).collect()
}

impl<T: Position> Checkpoint<T> {
    /// A checkpoint in `out` with `key`; with `resume`, the positions of an
    /// existing checkpoint of the same key are taken (none there: a fresh
    /// start). A checkpoint of another key, or one that cannot be read, is
    /// an error under `resume` (it names the file and what to do).
    pub fn open(out: &Path, key: String, resume: bool) -> Result<Self, FlankError> {
        let path = out.join(FILE);
        let mut resumed = HashMap::new();
        if resume && path.exists() {
            let text = std::fs::read_to_string(&path).map_err(|e| FlankError::io(&path, e))?;
            let stored: Stored = serde_json::from_str(&text).map_err(|e| FlankError::Parse {
                file: path.clone(),
                line: e.line(),
                message: format!("not a readable checkpoint ({e}); remove it to start afresh"),
            })?;
            if stored.format != FORMAT || stored.key != key {
                return Err(FlankError::Model(format!(
                    "{}: this checkpoint was written for another scene, other options or another \
                     flank version; run without --resume (it is then replaced) or with the \
                     options of the interrupted run",
                    path.display()
                )));
            }
            for v in stored.steps {
                if let Ok(s) = serde_json::from_value::<T>(v) {
                    resumed.insert(s.roll_deg().to_bits(), s);
                }
            }
        }
        Ok(Checkpoint {
            path,
            key,
            steps: Vec::new(),
            resumed,
            reused: 0,
        })
    }

    /// The resumed result of `roll_deg`, if the checkpoint has it (it is
    /// then recorded as solved by this run too).
    pub fn take(&mut self, roll_deg: f64) -> Result<Option<T>, FlankError> {
        match self.resumed.remove(&roll_deg.to_bits()) {
            Some(s) => {
                self.reused += 1;
                self.record(&s)?;
                Ok(Some(s))
            }
            None => Ok(None),
        }
    }

    /// Records a solved position and rewrites the file (atomically).
    pub fn record(&mut self, step: &T) -> Result<(), FlankError> {
        self.steps.push(step.clone());
        let mut steps: Vec<&T> = self.steps.iter().collect();
        // positions not asked for this time are kept for a later resume
        steps.extend(self.resumed.values());
        let stored = serde_json::json!({
            "format": FORMAT,
            "key": self.key,
            "steps": steps,
        });
        let text = serde_json::to_string(&stored)
            .map_err(|e| FlankError::Model(format!("checkpoint: {e}")))?;
        crate::atomic_file::write(&self.path, text)
    }

    /// Positions solved or resumed so far.
    pub fn len(&self) -> usize {
        self.steps.len()
    }

    pub fn is_empty(&self) -> bool {
        self.steps.is_empty()
    }

    /// Positions taken from the resumed checkpoint so far.
    pub fn reused(&self) -> usize {
        self.reused
    }

    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Removes the file (the run is complete).
    pub fn remove(self) -> Result<(), FlankError> {
        match std::fs::remove_file(&self.path) {
            Ok(()) => Ok(()),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
            Err(e) => Err(FlankError::io(&self.path, e)),
        }
    }
}
