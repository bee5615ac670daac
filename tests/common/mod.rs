//! Shared by the integration tests: the seed 002 LTCA on a coarse
//! compliance mesh (`ltca_compressed.rs`, `ltca_flank_region.rs`) and
//! running the binary ([`cli`]). Each test crate uses a part of it.
#![allow(dead_code)]

pub mod cli;

use std::path::{Path, PathBuf};

use flank::compliance::body::BodyMeshOptions;
use flank::ltca::cycle::LtcaOptions;

/// The seed 002 spur scene.
pub fn seed002_scene() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("papers/seed002-spur/scene.toml")
}

/// LTCA options on the coarse compliance mesh of these tests (flank
/// 0.7 mm, base 3 mm, 2 threads, quiet), writing to `out`.
pub fn coarse_ltca_options(out: &Path) -> LtcaOptions {
    LtcaOptions {
        out: out.to_path_buf(),
        mesh: BodyMeshOptions {
            flank_size: Some(0.7),
            base_size: Some(3.0),
            with_load: false,
            element: None,
        },
        threads: 2,
        quiet: true,
        ..Default::default()
    }
}

/// |a − b| relative to the larger magnitude (0 when equal).
pub fn rel(a: f64, b: f64) -> f64 {
    if a == b {
        0.0
    } else {
        (a - b).abs() / a.abs().max(b.abs())
    }
}
