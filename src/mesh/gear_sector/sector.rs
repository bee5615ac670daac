//! What the gear-sector mesher is asked for ([`SectorOptions`], the
//! contact bands of [`ProfileBand`]) and what it gives
//! ([`GearSectorMesh`]), and its error constructor.

use std::collections::HashMap;

use super::quality::Quality;
use crate::error::FlankError;
use crate::fem::mesh::{ElementKind, Mesh};

/// Options of [`super::gear_sector`].
#[derive(Clone, Debug)]
pub struct SectorOptions {
    /// Number of teeth in the sector (default 3).
    pub teeth: usize,
    /// Element size along and normal to the flank near the surface (mm).
    pub flank_size: f64,
    /// Coarse element size in the rim and body (mm).
    pub base_size: f64,
    /// Elements across the face width; 0 = ⌈b / base_size⌉.
    pub face_layers: usize,
    /// C3D20 (default), C3D20R (same nodes, reduced integration) or C3D15:
    /// each transverse quadrilateral split along its shorter diagonal into two
    /// triangles, i.e. wedges with triangles in the transverse plane and
    /// quadratic layers across the face width (as in seed 002).
    pub element: ElementKind,
}

impl Default for SectorOptions {
    fn default() -> Self {
        SectorOptions {
            teeth: 3,
            flank_size: 0.5,
            base_size: 2.0,
            face_layers: 0,
            element: ElementKind::C3D20,
        }
    }
}

/// A contact band of the involute rows ([`super::gear_sector_banded`]): around
/// the profile point at `radius_mm` (the contact point of one position,
/// the same on every tooth of the sector and on both flanks, since the rows
/// run across the tooth), rows of arc length `size_mm` over
/// ±`half_width_mm` of arc length, growing by about 1.25 per row
/// ([`crate::mesh::grading::banded_sizes`]) back to the flank size outside.
/// Across the tooth the first layer at the flanks becomes the finest band
/// size (growth 1.25 inwards), on every row: the Hertz stress field
/// reaches a depth of a few half-widths b below the surface (Johnson,
/// *Contact Mechanics*, 1985, §4.2), so the elements there must be about
/// as small as along the profile.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ProfileBand {
    /// Radius of the band centre on the involute (mm, own frame).
    pub radius_mm: f64,
    /// Half-width of the band along the profile (mm of arc length).
    pub half_width_mm: f64,
    /// Row size inside the band (mm of arc length); ≤ the flank size.
    pub size_mm: f64,
}

/// A meshed gear sector.
#[derive(Clone, Debug)]
pub struct GearSectorMesh {
    pub mesh: Mesh,
    /// For each flank node: (profile parameter u, z). See the module docs for u.
    pub flank_uv: HashMap<usize, (f64, f64)>,
    pub quality: Quality,
}

/// An error of the gear-sector mesher.
pub(super) fn err(msg: String) -> FlankError {
    FlankError::Model(format!("gear sector mesh: {msg}"))
}
