//! Native gear-sector mesher: structured multi-block meshes of `teeth`
//! consecutive teeth of one gear, exact on the flanks, in 20-node hexahedra
//! (C3D20, or C3D20R) or 15-node wedges (C3D15: every transverse quadrilateral
//! split along its shorter diagonal, so triangles in the transverse plane and
//! quadratic layers across the face width, as in seed 002).
//!
//! Construction (transverse plane, then extrusion along the axis):
//! * per tooth pitch (tooth centre ± half pitch) an **upper block**, a quadratic
//!   lattice (2n+1 points per direction) whose lines of constant `J` run across
//!   the tooth from the left boundary to the right boundary and whose lines of
//!   constant `I` run from the bottom up to the tip. The left boundary is the
//!   half root arc from the sector cut (gap centre) to the left fillet end, the
//!   left fillet and the left involute up to the tip corner; the right boundary
//!   is its mirror; the top is the tip arc; the bottom is a Π-shaped curve: the
//!   cut line from the root circle down to an interface radius r_i, the arc r_i
//!   across the pitch, the other cut line back up. Boundary lattice points
//!   (corner and midside) are placed on the exact profile by its parameter
//!   (root-arc angle, fillet parameter t, involute roll angle u with uniform
//!   arc length), so midside nodes lie on the exact curve. Interior points by
//!   transfinite interpolation (Coons patch) in polar coordinates (angle,
//!   radius), with a graded distribution across the tooth chosen per row
//!   (first layer ≈ `flank_size`, growth ≤ 1.3 towards the tooth centre; where
//!   the tooth is too narrow, near the tip, uniform and thinner). The bottom
//!   curve's blend weight falls from 1 at the bottom to 0 at the form point,
//!   so on the involute the rows are pure polar lerps between the flanks.
//! * per pitch a **rim block** between the bore and r_i, a polar tensor lattice
//!   whose top row is the arc part of the upper block's bottom (the same
//!   points), graded from the cut element size at r_i to ≤ `base_size`.
//! * Blocks share nodes along their interfaces (identical lattice points,
//!   merged by position); neighbouring pitches share the cut lines.
//! * Wedge15 meshes split every transverse quadrilateral into two triangles
//!   and, inside the tooth, coarsen 2:1 along the profile: column lines get a
//!   level λ (0 on the flanks and the first line inside, at most +1 per
//!   column towards the centre) and cells between lines of level λ span 2^λ
//!   rows; a column between levels λ and λ + 1 is a transition of three
//!   triangles per coarse cell; level λ stops below the row where the
//!   narrowing tooth would make its cells more than 3 × as tall as wide.
//!   Edges spanning several rows get straight midpoints (interior only).
//!   The flank faces are unchanged (same nodes as the hex20 mesh).
//! * Contact bands ([`ProfileBand`], [`gear_sector_banded`]): the involute
//!   rows are spaced by a band size around given profile points and grow
//!   back to `flank_size` outside ([`crate::mesh::grading::banded_sizes`]);
//!   the first layer across the tooth becomes the band size. Same layout on
//!   every tooth; no 2:1 wedge coarsening with bands.
//! * Extrusion: z ∈ [0, b] in `face_layers` quadratic layers; each transverse
//!   section is rotated by φ(z) = twist_rate · z, which puts flank nodes exactly
//!   on the helicoid [`ToothProfile::surface`].
//!
//! Conventions. Tooth `k` of the sector (sets `FLANK_L<k>`, `FLANK_R<k>`,
//! k = 1..=teeth) is the profile's tooth k − 1, i.e. tooth 0 (symmetric about
//! +y) rotated by −2π(k−1)/z. `FLANK_R<k>` are the nodes of the profile's
//! [`Flank::Right`] (x > 0 for tooth 0), `FLANK_L<k>` those of [`Flank::Left`]:
//! seen with the gear axis (+z) pointing at the viewer and the tooth pointing
//! up, FLANK_L is on the viewer's left, FLANK_R on the right. Flank sets hold
//! every node on the involute and on the trochoidal root fillet (not on the
//! root arc). `CUT_A` is the cut face at the gap centre left of tooth 1 (angle
//! −π/z from +y, positive towards +x), `CUT_B` the cut right of the last tooth.
//! `BORE`: nodes at the bore radius. `NALL`, `EALL`. For helical gears the
//! cut faces are twisted with the section (helicoidal, not planes). With
//! `teeth` = z the ring closes: the two cuts merge and CUT_A = CUT_B.
//!
//! Flank parameter u (in [`GearSectorMesh::flank_uv`]): the involute roll
//! angle for u ≥ u_form; on the fillet u = u_form − t (t ∈ [0, 1] the fillet
//! parameter, 0 at the form circle), see [`flank_segment`].
//!
//! # Files
//!
//! | file | holds |
//! | --- | --- |
//! | `mod.rs` (this file) | [`SectorOptions`], [`GearSectorMesh`], [`flank_segment`] and the entry [`gear_sector`] (one try with wedge coarsening, one without) |
//! | `lattice.rs` | 2D building blocks: graded sizes, half-lattice fractions, polar helpers, the point registry merging by position, blocks and transverse cells (quadrilateral, or two triangles for wedges); the cells in lattice coordinates and their 2:1 coarsening are [`crate::mesh::section_cells`]'s, shared with the bevel mesher |
//! | `section.rs` | the transverse section: element sizes across and along the tooth, boundary points on the exact profile, the Coons blend, the rim; the points of every pitch and their cells |
//! //! | `extrude.rs` | extrusion along the axis (twisted for helical gears), hex20/wedge15 elements with their Jacobian check, node and element sets |
//! | `quality.rs` | [`Quality`]: scaled Jacobian and aspect ratio of the elements |
//! | `modify.rs` | [`modify_flanks`]: flank nodes moved onto a modified surface and the body carried along (elastic extension), [`FlankModificationReport`] |
//! | `tests.rs` | unit tests (validity, exact flank nodes, conformity and sets, a clamped-bore solve, modifications, full ring) |
//!
//! [`Flank::Right`]: crate::geometry::rack::Flank::Right
//! [`Flank::Left`]: crate::geometry::rack::Flank::Left

mod extrude;
mod lattice;
mod modify;
mod quality;
mod section;
mod sector;

#[cfg(test)]
mod tests;

use crate::error::FlankError;
use crate::fem::mesh::ElementKind;
use crate::geometry::rack::{Segment, ToothProfile};
use crate::geometry::GearSpec;

use extrude::extrude;
pub use modify::{modify_flanks, FlankModificationReport};
pub use quality::Quality;
use section::transverse_section;
use sector::err;
pub use sector::{GearSectorMesh, ProfileBand, SectorOptions};

/// Profile segment of the unified flank parameter u (module docs).
pub fn flank_segment(profile: &ToothProfile, u: f64) -> Segment {
    if u >= profile.u_form {
        Segment::Involute(u)
    } else {
        Segment::Fillet((profile.u_form - u).min(1.0))
    }
}

/// Mesh `opts.teeth` teeth of the gear `spec` (see the module docs).
///
/// Wedge meshes coarsen along the profile inside the tooth (2:1
/// transitions; about half the nodes at a given flank size); if that produces an element with a scaled
/// Jacobian below 0.2 (or an inverted one: possible on very coarse meshes,
/// where a coarse cell spans rows of very different spacing), the sector is
/// meshed again without coarsening.
pub fn gear_sector(
    spec: &GearSpec,
    name: &str,
    opts: &SectorOptions,
) -> Result<GearSectorMesh, FlankError> {
    gear_sector_banded(spec, name, opts, &[])
}

/// [`gear_sector`] with contact bands ([`ProfileBand`]): finer involute
/// rows around given profile points and a finer first layer across the
/// tooth. No band: exactly [`gear_sector`]'s mesh. Bands apply to every
/// tooth of the sector: the section's layout (rows, columns, cells) is
/// one for all pitches, so the teeth stay conforming at the cuts, and a
/// position in double contact needs a band at each pair's contact point
/// anyway (both bands then lie on every tooth). Wedge meshes with bands
/// keep every row inside the tooth (no 2:1 coarsening: its levels assume
/// rows of the flank size).
pub fn gear_sector_banded(
    spec: &GearSpec,
    name: &str,
    opts: &SectorOptions,
    bands: &[ProfileBand],
) -> Result<GearSectorMesh, FlankError> {
    if opts.element == ElementKind::C3D15 && bands.is_empty() {
        match sector_mesh(spec, name, opts, bands, true) {
            Ok(m) if m.quality.min_scaled_jacobian >= 0.2 => return Ok(m),
            Ok(_) | Err(FlankError::Element { .. }) => {}
            Err(e) => return Err(e),
        }
    }
    sector_mesh(spec, name, opts, bands, false)
}

/// One meshing try: the transverse section (with or without 2:1 coarsening
/// of wedge cells), extruded along the axis.
fn sector_mesh(
    spec: &GearSpec,
    name: &str,
    opts: &SectorOptions,
    bands: &[ProfileBand],
    coarsen: bool,
) -> Result<GearSectorMesh, FlankError> {
    let section = transverse_section(spec, name, opts, bands, coarsen)?;
    extrude(spec, name, opts, section)
}
