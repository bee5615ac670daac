//! Flank modifications (micro-geometry, measured profiles) applied to the
//! nodes of a sector mesh, with a Jacobian check of the touched elements.

use super::lattice::rot;
use super::{err, flank_segment, GearSectorMesh};
use crate::error::FlankError;
use crate::fem::element::check_jacobian;
use crate::geometry::rack::{Flank, ToothProfile};

/// What [`modify_flanks`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct FlankModificationReport {
    /// Flank nodes moved.
    pub nodes: usize,
    /// Largest and smallest offset applied (mm; positive = material removed).
    pub max_offset_mm: f64,
    pub min_offset_mm: f64,
}

/// Applies a flank modification (micro-geometry, measured profile) to a
/// sector mesh: every flank node (corner and midside) moves along the
/// nominal outward normal at its (u, z) by −offset(flank, u, z), so it lies
/// on the modified surface [`crate::geometry::flank::FlankSurface::point`].
///
/// Only flank nodes move: modifications are micrometres, the first element
/// layer is at least the flank size (≥ 0.075 mm) thick. Every element that
/// touches a moved node is Jacobian-checked again; an inverted one is an
/// error naming it (the modification is then too large for that mesh).
/// Works on meshes from either mesher (it only needs `flank_uv` and the
/// `FLANK_L<k>`/`FLANK_R<k>` sets with the sector's tooth numbering).
pub fn modify_flanks(
    sector: &mut GearSectorMesh,
    profile: &ToothProfile,
    modification: &crate::geometry::micro::FlankModification,
) -> Result<FlankModificationReport, FlankError> {
    let pitch = profile.angular_pitch();
    let mut report = FlankModificationReport {
        nodes: 0,
        max_offset_mm: f64::NEG_INFINITY,
        min_offset_mm: f64::INFINITY,
    };
    let mut moved = vec![false; sector.mesh.node_count()];
    let mut sets: Vec<(String, Vec<usize>)> = sector
        .mesh
        .node_sets
        .iter()
        .filter(|(k, _)| k.starts_with("FLANK_L") || k.starts_with("FLANK_R"))
        .map(|(k, v)| (k.clone(), v.clone()))
        .collect();
    sets.sort();
    for (set, nodes) in sets {
        let flank = if set.starts_with("FLANK_L") {
            Flank::Left
        } else {
            Flank::Right
        };
        let tooth: usize = set[7..]
            .parse()
            .map_err(|_| err(format!("node set {set}: no tooth number")))?;
        for n in nodes {
            if moved[n] {
                continue;
            }
            let &(u, z) = sector
                .flank_uv
                .get(&n)
                .ok_or_else(|| err(format!("flank node {} of {set} has no (u, v)", n + 1)))?;
            let o = modification.offset(flank, u, z);
            if !o.is_finite() {
                return Err(err(format!(
                    "flank modification is not finite at u = {u}, z = {z} ({set})"
                )));
            }
            let nrm = profile.surface(flank, flank_segment(profile, u), z).n;
            let q = rot([nrm[0], nrm[1]], (tooth - 1) as f64 * pitch);
            let x = &mut sector.mesh.coords[n];
            x[0] -= o * q[0];
            x[1] -= o * q[1];
            x[2] -= o * nrm[2];
            moved[n] = true;
            report.nodes += 1;
            report.max_offset_mm = report.max_offset_mm.max(o);
            report.min_offset_mm = report.min_offset_mm.min(o);
        }
    }
    if report.nodes == 0 {
        report.max_offset_mm = 0.0;
        report.min_offset_mm = 0.0;
    }
    for (e, el) in sector.mesh.elements.iter().enumerate() {
        if el.nodes.iter().any(|&n| moved[n]) {
            check_jacobian(el.kind, &sector.mesh.element_coords(e)).map_err(|j| {
                j.into_error_in(
                    el.label,
                    el.kind,
                    &format!(
                        "after applying the flank modification: offsets {:.4} … {:.4} mm; refine less or reduce the modification",
                        report.min_offset_mm, report.max_offset_mm
                    ),
                )
            })?;
        }
    }
    Ok(report)
}
