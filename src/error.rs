//! Errors of the flank library. Every variant says what is wrong and where.

use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum FlankError {
    /// A malformed or unsupported input file; `line` is 1-based.
    #[error("{file}:{line}: {message}")]
    Parse {
        file: PathBuf,
        line: usize,
        message: String,
    },
    /// An invalid material definition.
    #[error("{0}")]
    Material(String),
    /// An inverted or degenerate element (non-positive Jacobian).
    #[error("element {label} ({kind}): {message}")]
    Element {
        label: u64,
        kind: &'static str,
        message: String,
    },
    /// Inconsistent model data (missing sets, bad node references, ...).
    #[error("model: {0}")]
    Model(String),
    /// The stiffness matrix is singular: rigid-body modes are not constrained.
    #[error("singular stiffness: {0}")]
    Singular(String),
    /// The linear solver failed.
    #[error("solver: {0}")]
    Solver(String),
    /// A campaign that cannot run as asked (job out of range, memory above
    /// the machine, a failed job, a scheduler error).
    #[error("campaign: {0}")]
    Campaign(String),
    /// A step that would need more memory than the process may allocate
    /// ([`crate::resources::check_memory`]): the figures and alternatives.
    #[error("memory: {0}")]
    Memory(String),
    /// A run stopped by the user (SIGINT) at a safe point; says what was
    /// written and how to resume.
    #[error("interrupted: {0}")]
    Interrupted(String),
    /// An I/O error on `path`; the OS error is the source (printed by `{:#}`).
    #[error("{}", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
}

impl FlankError {
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        FlankError::Io {
            path: path.into(),
            source,
        }
    }
}

pub type Result<T> = std::result::Result<T, FlankError>;
