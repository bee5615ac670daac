//! A candidate point of the LTCA's contact problem: where it lies on its
//! contact line, and the FE cells (loads on both flanks) through which the
//! compliance F between candidates is taken from the tensors
//! ([`crate::ltca::influence`]).

use crate::compliance::interpolation::SurfaceLoad;

/// A candidate point with its cells on both flanks.
pub(crate) struct Candidate {
    pub(crate) line: usize,
    pub(crate) position: [f64; 3],
    pub(crate) along: f64,
    pub(crate) half_length: f64,
    /// Half-width across the line of the FE cell (mm).
    pub(crate) c: f64,
    pub(crate) loads: [SurfaceLoad; 2],
    pub(crate) normals: [[f64; 3]; 2],
    /// The tangent (friction) direction in each body's own frame, with the
    /// normal's sign convention (the gear's both reversed).
    pub(crate) tangents: [[f64; 3]; 2],
}
