//! Native bevel/hypoid sector mesher: structured meshes of the modelled
//! teeth of a [`BevelGear`] in 20-node hexahedra (C3D20, or C3D20R) or
//! 15-node wedges (C3D15), flank nodes (corner and midside) exactly on the
//! generated tooth surfaces.
//!
//! **Coordinates.** Every bevel tooth surface is parameterised by its
//! axial-section coordinates (u, v) ([`crate::geometry::bevel::body`]): v
//! the cone distance along the pitch generatrix, u the distance
//! perpendicular to it in the axial plane, so that r(u, v) lies on the
//! circle of (z, ρ) = (v cos δ − u sin δ, v sin δ + u cos δ) at an angle
//! θ about the axis (from +y toward +x). The mesher works in (θ, u, v):
//! a point (θ, u, v) is that circle's point at θ. The body it fills is
//! bounded by the two flanks of each tooth, the face cone (the tip land),
//! the gap land between the fillets, the front cone v = v₀ (toe) and the
//! back cone v = v₁ (heel) — the cones perpendicular to the pitch cone,
//! which bound the teeth of a real blank — and, below the teeth, the
//! mounting surface: lines of constant v continued below the root cone
//! down to
//! * the **bore** ρ = r_b for a member whose pitch angle δ < 45° (a
//!   pinion: the shank), set `BORE` (also `MOUNT`);
//! * the **mounting plane** z = z_m for δ ≥ 45° (a ring gear: its back
//!   face), z_m one whole depth h_m = h_am + h_fm (or
//!   [`BevelSectorOptions::rim_thickness`]) behind the deepest point of the
//!   gap land, set `MOUNT`. A ring gear's bore is then the front cone's
//!   continuation to the mounting plane; the scene's bore diameter is not
//!   used for it.
//!
//! **Stations.** The face is cut by `2·face_layers + 1` back cones
//! v_s = v₀ + (v₁ − v₀) s / (2 face_layers) (corner and midside stations).
//! On each station the section of one pitch, in (θ, u), is laid out as the
//! cylindrical sector mesher lays out its transverse section
//! ([`crate::mesh::gear_sector`]) in (angle, radius): an **upper block**
//! around the tooth whose left and right boundaries run from the sector
//! cut (gap centre) along the half gap land, up the fillet (uniform in arc
//! length) and the flank (uniform in arc length) to the tip corner, whose
//! top is the tip land and whose bottom is a Π curve (the cut line down
//! a depth d below the gap land, across the pitch, back up); interior
//! points by a Coons blend, graded across the tooth from `flank_size` at
//! the flanks (growth ≤ 1.3); and a **rim block** below, across the pitch
//! and down to the mounting surface, graded from the cut's step to
//! `base_size`. The lattice counts are the same on every station (taken
//! from the largest lengths over the face), so consecutive stations join
//! into hexahedra; the tooth winds along its spiral through the stations
//! and the elements follow it (skewed by about the spiral angle).
//! Midside nodes on flanks sit at their own (u, v): exact on the surface.
//!
//! **The gap land** is the straight line in (θ, u) between the two fillet
//! ends (the flanks' u_root: the root cone lifted by 0.005 ρ_f, where the
//! axial-section parameterisation of the fillet ends, see
//! [`crate::geometry::bevel::generated_surface`]), so the land lies at
//! most 0.005 ρ_f (≈ 1 µm for an edge radius of 0.2 mm) above the true
//! root cone.
//!
//! **Conventions.** Sector tooth k = 1..=n is the body's tooth k
//! (`GearBody::flank(side, k)`, θ growing with k). Sets: `FLANK_L<k>`,
//! `FLANK_R<k>` (the body's [`Flank::Left`]/[`Flank::Right`] flank of tooth
//! k, fillet included, gap land excluded), `CUT_A` (the cut at the gap
//! centre on the low-θ side of tooth 1), `CUT_B` (high-θ side of the last
//! tooth; a full ring has no cuts: CUT_A = CUT_B), `TOE` (v = v₀), `HEEL`
//! (v = v₁), `MOUNT`, `BORE` (bore mounts only), `TIP_LAND` (face cone,
//! tip edges included), `GAP_LAND` (the gap lands, from the cut to the
//! fillet ends), `NALL`, `EALL`. Flank
//! parameters of every flank node in [`BevelSectorMesh::flank_uv`].
//!
//! **Pinion shank** ([`BevelSectorOptions::shank`], bore mounts only): a
//! hollow cylinder ρ ∈ [r_b, r_s] (r_s = half the shank diameter) on the
//! heel side, the pinion's stem with its bearing seats. The rim's rows are
//! graded so that one row lies on ρ = r_s at the heel; the heel face's rim
//! rows from the bore up to that row are extruded along +z (each node
//! keeps θ and ρ, z runs linearly from the heel cone to the shank's end
//! plane z_e), so the shank is exactly the cylinder r_s of axial length L
//! from where it leaves the heel face (z_e = z_heel(r_s) + L); the heel
//! face above r_s is the shoulder. `MOUNT` is then the bearing seat (the
//! shank's outer cylinder), `BORE` the bore through teeth and shank,
//! `SHANK_END` the end plane.
//!
//! The shank is a sector of the tube as the teeth are a sector of the
//! gear: its torsional stiffness is that of an open sector, far below the
//! closed tube's, so the pinion's rotation at a bearing seat is only the
//! real one with the whole pinion meshed (`[mesh] teeth_in_sector` = z₁);
//! [`SHANK_SECTOR_WARNING`] says so.
//!
//! **Wedges** (C3D15): the station section is split into triangles as the
//! cylindrical mesher's transverse section is ([`crate::mesh::section_cells`]):
//! inside the tooth the cells coarsen 2:1 along the profile (levels of the
//! column lines rising towards the tooth centre, transition columns of
//! three triangles), every remaining quadrilateral is split along its
//! shorter diagonal (summed over the stations, so every station splits it
//! alike), and the triangles join consecutive stations into wedges. A
//! coarse cell is at most 3 × as tall as wide on every station (each
//! station's own row height). Midside points off the lattice (quadrilateral
//! centres, straight midpoints of edges spanning several rows) are
//! combinations of lattice points in (θ, u), placed on each station; none
//! lies on a boundary, so the flank faces and every boundary set except
//! `TOE`/`HEEL` are the hex20 mesh's. As in the cylindrical mesher, a
//! coarsened mesh with an inverted element or a scaled Jacobian below 0.2
//! is meshed again without coarsening. The rim is not coarsened: at 1 mm on
//! seed 003 (teeth ten elements across) the wedge mesh has slightly more
//! nodes than hex20's, at 0.5 mm 13–14 % fewer.
//!
//! Not here (yet): a ring gear's bore (its mount is the mounting plane).
//!
//! [`Flank::Left`]: crate::geometry::gear_pair::Flank::Left
//! [`Flank::Right`]: crate::geometry::gear_pair::Flank::Right
//!
//! # Files
//!
//! | file | holds |
//! | --- | --- |
//! | `mod.rs` (this file) | [`BevelSectorOptions`], [`BevelSectorMesh`], [`Mount`], the entry [`bevel_sector`] |
//! | `station.rs` | one station's profiles (fillet and flank tables, lands, cut, mount) and the lattice counts over the face |
//! | `section.rs` | the (θ, u) lattice points of the upper and rim blocks on one station |
//! | `cells.rs` | the section's cells, the same on every station: quadrilaterals, or triangles (coarsened, split) with their extra midside points |
//! | `deviation.rs` | [`flank_edge_deviation`]: how far the quadratic flank edges leave the surfaces |
//! | `assemble.rs` | 3D nodes (merged by position), hex20 or wedge15 elements (Jacobian-checked), sets, quality |
//! | `tests.rs` | unit tests (seed scenes: validity, exact flank nodes, sets, a clamped solve, bad input; wedges against hex20) |

mod assemble;
mod cells;
mod deviation;
mod section;
mod sector;
mod station;

#[cfg(test)]
mod tests;

pub use deviation::flank_edge_deviation;
use sector::err;
pub use sector::{
    BevelSectorMesh, BevelSectorOptions, LatticeCounts, Mount, Shank, ShankReport,
    SHANK_SECTOR_WARNING,
};

use crate::error::FlankError;
use crate::fem::mesh::ElementKind;
use crate::geometry::bevel::body::BevelGear;

/// Mesh the modelled teeth of `gear` (its `sector_teeth`; module docs).
pub fn bevel_sector(
    gear: &BevelGear,
    name: &str,
    opts: &BevelSectorOptions,
) -> Result<BevelSectorMesh, FlankError> {
    if !(opts.flank_size > 0.0
        && opts.flank_size.is_finite()
        && opts.base_size >= opts.flank_size
        && opts.base_size.is_finite())
    {
        return Err(err(format!(
            "{name}: need 0 < flank_size ({}) ≤ base_size ({})",
            opts.flank_size, opts.base_size
        )));
    }
    if let Some(sh) = opts.shank {
        if !(sh.length > 0.0
            && sh.length.is_finite()
            && sh.diameter > 0.0
            && sh.diameter.is_finite())
        {
            return Err(err(format!(
                "{name}: shank length {} mm and diameter {} mm must be positive",
                sh.length, sh.diameter
            )));
        }
    }
    if let Some(t) = opts.rim_thickness {
        if !(t > 0.0 && t.is_finite()) {
            return Err(err(format!(
                "{name}: rim thickness {t} mm must be positive"
            )));
        }
    }
    let face = station::FaceLayout::new(gear, name, opts)?;
    if opts.element == ElementKind::C3D15 {
        match assemble::assemble(gear, name, opts, &face, true) {
            Ok(m) if m.quality.min_scaled_jacobian >= 0.2 => return Ok(m),
            Ok(_) | Err(FlankError::Element { .. }) => {}
            Err(e) => return Err(e),
        }
    }
    assemble::assemble(gear, name, opts, &face, false)
}
