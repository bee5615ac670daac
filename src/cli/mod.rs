//! The subcommands of the `flank` binary, one module each: its clap
//! arguments (`Args`) and its `run`. Shared pieces are in `common`.

pub mod blank;
pub mod campaign;
pub mod cantilever;
pub mod check;
pub mod common;
pub mod compare;
pub mod compliance;
pub mod grid;
pub mod import;
pub mod ltca;
pub mod mesh;
pub mod run;
pub mod solve;
pub mod tca;
