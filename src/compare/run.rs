//! `flank compare` over a scene of any pair kind: the spur/helical
//! comparison ([`super::compare_cylindrical`]) or the bevel/hypoid one
//! ([`super::bevel::compare_bevel`], its LTCA options
//! [`super::bevel::ltca_options`]).

use std::path::Path;

use super::bevel::compare_bevel;
use super::summary::CompareSummary;
use super::{compare_cylindrical, CompareOptions};
use crate::error::FlankError;
use crate::scene::{read_scene, Scene};

/// `flank compare SCENE`: reads the scene and runs [`compare`].
pub fn compare_scene(path: &Path, options: &CompareOptions) -> Result<CompareSummary, FlankError> {
    compare(&read_scene(path)?, options)
}

/// LTCA against FE contact at the same positions, for any pair kind;
/// writes `compare.json`, `compare.md` and `error_vs_time.{svg,png}` into
/// `options.out` and returns the summary.
pub fn compare(scene: &Scene, options: &CompareOptions) -> Result<CompareSummary, FlankError> {
    if scene.is_bevel() {
        return compare_bevel(scene, options);
    }
    compare_cylindrical(scene, options)
}
