//! What the bevel-sector mesher is asked for ([`BevelSectorOptions`], the
//! pinion's [`Shank`], the [`Mount`]) and what it gives
//! ([`BevelSectorMesh`], [`ShankReport`], [`LatticeCounts`]), and its error
//! constructor.

use std::collections::HashMap;

use crate::error::FlankError;
use crate::fem::mesh::{ElementKind, Mesh};
use crate::mesh::gear_sector::Quality;

/// Options of [`super::bevel_sector`].
#[derive(Clone, Debug)]
pub struct BevelSectorOptions {
    /// Element size along and normal to the flank near the surface (mm).
    pub flank_size: f64,
    /// Coarse element size in the rim and along the face (mm).
    pub base_size: f64,
    /// Elements along the face; 0 = ⌈length of the pitch line on the
    /// flank / base_size⌉.
    pub face_layers: usize,
    /// C3D20 (default), C3D20R or C3D15 (wedges: triangles in the station
    /// section, coarsened 2:1 along the profile inside the tooth).
    pub element: ElementKind,
    /// Ring gears (δ ≥ 45°): distance of the mounting plane behind the
    /// deepest point of the gap land (mm); `None` = one mean whole depth.
    pub rim_thickness: Option<f64>,
    /// The pinion's shank (module docs); bore mounts only.
    pub shank: Option<Shank>,
}

/// The warning of a shank on a partial sector (module docs).
pub const SHANK_SECTOR_WARNING: &str = "the pinion's shank is meshed as a sector of the tube, like the teeth: an open sector is far softer in torsion than the closed tube, so the pinion turns more at its bearing seat than it would; mesh the whole pinion (`[mesh] teeth_in_sector` = z1) for the shank's torsion";

/// A pinion shank: a cylinder of `diameter` and axial `length` (mm) beyond
/// the heel face (module docs).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Shank {
    pub length: f64,
    pub diameter: f64,
}

impl BevelSectorOptions {
    /// The options of one member of a pair: the shank is the pinion's.
    pub fn member(&self, pinion: bool) -> BevelSectorOptions {
        BevelSectorOptions {
            shank: if pinion { self.shank } else { None },
            ..self.clone()
        }
    }
}

impl Default for BevelSectorOptions {
    fn default() -> Self {
        BevelSectorOptions {
            flank_size: 1.0,
            base_size: 4.0,
            face_layers: 0,
            element: ElementKind::C3D20,
            rim_thickness: None,
            shank: None,
        }
    }
}

/// The surface the body is held by (module docs).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Mount {
    /// The bore cylinder ρ = radius (mm).
    Bore { radius: f64 },
    /// The mounting plane z = z (mm, the member's own frame).
    Plane { z: f64 },
}

/// A meshed bevel/hypoid sector.
#[derive(Clone, Debug)]
pub struct BevelSectorMesh {
    pub mesh: Mesh,
    /// For each flank node: the surface parameters (u, v) (mm).
    pub flank_uv: HashMap<usize, (f64, f64)>,
    pub quality: Quality,
    pub mount: Mount,
    /// Lattice counts: across the tooth, up the boundary (land, fillet,
    /// flank), rim rows, face layers.
    pub counts: LatticeCounts,
    /// The shank as meshed: radii, axial extent of the bearing seat, layers.
    pub shank: Option<ShankReport>,
}

/// The meshed shank ([`BevelSectorMesh::shank`]).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct ShankReport {
    pub bore_radius_mm: f64,
    pub radius_mm: f64,
    /// z of the shank's outer cylinder where it leaves the heel face and at
    /// its end plane (mm, member frame).
    pub z_mm: [f64; 2],
    /// Element layers along the shank.
    pub layers: usize,
}

/// The lattice counts of a sector (elements; the same on every station).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct LatticeCounts {
    /// Across the tooth (flank to flank).
    pub across: usize,
    /// Along each half gap land.
    pub land: usize,
    /// Along the fillet.
    pub fillet: usize,
    /// Along the flank (form line to tip).
    pub flank: usize,
    /// Steps of each cut line below the gap land.
    pub cut: usize,
    /// Rows of the rim below the teeth.
    pub rim: usize,
    /// Along the face.
    pub face: usize,
}

/// An error of the bevel-sector mesher.
pub(super) fn err(msg: String) -> FlankError {
    FlankError::Model(format!("bevel sector mesh: {msg}"))
}
