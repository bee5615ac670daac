//! Flank modifications (micro-geometry, measured profiles) applied to a
//! sector mesh: the flank nodes onto the modified surface, the body below
//! them carried along by an elastic extension, with a Jacobian check.
//!
//! Why an extension of the flank displacement and not a modified lattice:
//! the same routine serves the native mesher and the gmsh mesher (whose
//! meshes have no lattice), and a lattice built on the modified surface
//! would still have to place the first layer (down to 0.075 mm) against a
//! 60 µm relief. Moving only the flank nodes (as before) inverts the first
//! layer once the offset is a sizeable part of it (seed 002's 60 µm tip
//! relief at 0.1 mm wedges). Here the flank displacement −o·n is the
//! Dirichlet datum of a linear-elastic problem on the teeth and the rim
//! below them (the "pseudo-solid" mesh morphing; E = 1, ν = 0.3): the
//! displacement decays into the body over the length over which the offset
//! varies along the flank and the tooth's own size, whatever the element
//! size, and every node (corner and midside) moves by the same quadratic
//! field, so the moved elements are the isoparametric images of the old.
//!
//! What moves: every node of the teeth and of the rim down to one tooth
//! height below the lowest flank node (nodes there and the bore are held).
//! Compliance and LTCA figures of a modified scene therefore differ slightly
//! from those of a mesh where only the flank nodes moved. Measured
//! (`tests.rs`, `modified_body_compliance_change`: seed 002's 60 µm tip
//! relief, 1.0 mm wedges, bore clamped, compliance diagonal normal to the
//! middle tooth's right flank at mid face): −0.90 % 0.5 mm below the tip
//! (inside the relief zone, where the flank-only move thinned the 1 mm
//! first layer by 6 %), −0.012 % at the reference circle, −0.013 % near the
//! base circle. A discretisation difference of the coarse mesh, not a
//! change of geometry (the flank nodes are the same in both).

use super::lattice::rot;
use super::quality::Quality;
use super::{err, flank_segment, GearSectorMesh};
use crate::error::FlankError;
use crate::fem::element::check_jacobian;
use crate::fem::material::Material;
use crate::fem::model::{Dirichlet, Model};
use crate::fem::static_analysis::{solve_static, SolveOptions};
use crate::geometry::rack::{Flank, ToothProfile};

/// What [`modify_flanks`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct FlankModificationReport {
    /// Flank nodes moved.
    pub nodes: usize,
    /// Largest and smallest offset applied (mm; positive = material removed).
    pub max_offset_mm: f64,
    pub min_offset_mm: f64,
    /// Nodes below the flanks moved by the extension.
    pub interior_nodes: usize,
    /// Depth of the extended zone below the lowest flank node (mm, radial).
    pub depth_mm: f64,
    /// Elements with a moved node, checked again.
    pub elements_checked: usize,
    /// Smallest scaled Jacobian of those elements after the move (1 when
    /// nothing moved).
    pub min_scaled_jacobian: f64,
}

/// Applies a flank modification (micro-geometry, measured profile) to a
/// sector mesh: every flank node (corner and midside) moves along the
/// nominal outward normal at its (u, z) by −offset(flank, u, z), so it lies
/// on the modified surface [`crate::geometry::flank::FlankSurface::point`];
/// the nodes below are carried along by the elastic extension of the module
/// docs. A modification that is zero everywhere leaves the mesh as it is
/// (bit for bit). Every element with a moved node is Jacobian-checked
/// again; an inverted one is an error naming it, the offset there and what
/// can be done. Works on meshes from either mesher
/// ([`crate::mesh::gear_body::Mesher`]: it only needs `flank_uv` and the
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
        min_scaled_jacobian: 1.0,
        ..Default::default()
    };
    let nn = sector.mesh.node_count();
    // prescribed displacement and offset of every flank node
    let mut flank: Vec<Option<([f64; 3], f64)>> = vec![None; nn];
    let mut sets: Vec<(String, Vec<usize>)> = sector
        .mesh
        .node_sets
        .iter()
        .filter(|(k, _)| k.starts_with("FLANK_L") || k.starts_with("FLANK_R"))
        .map(|(k, v)| (k.clone(), v.clone()))
        .collect();
    sets.sort();
    for (set, nodes) in sets {
        let side = if set.starts_with("FLANK_L") {
            Flank::Left
        } else {
            Flank::Right
        };
        let tooth: usize = set[7..]
            .parse()
            .map_err(|_| err(format!("node set {set}: no tooth number")))?;
        for n in nodes {
            if flank[n].is_some() {
                continue;
            }
            let &(u, z) = sector
                .flank_uv
                .get(&n)
                .ok_or_else(|| err(format!("flank node {} of {set} has no (u, v)", n + 1)))?;
            let o = modification.offset(side, u, z);
            if !o.is_finite() {
                return Err(err(format!(
                    "flank modification is not finite at u = {u}, z = {z} ({set})"
                )));
            }
            let nrm = profile.surface(side, flank_segment(profile, u), z).n;
            let q = rot([nrm[0], nrm[1]], (tooth - 1) as f64 * pitch);
            flank[n] = Some(([-o * q[0], -o * q[1], -o * nrm[2]], o));
            report.nodes += 1;
            report.max_offset_mm = report.max_offset_mm.max(o);
            report.min_offset_mm = report.min_offset_mm.min(o);
        }
    }
    if report.nodes == 0 {
        report.max_offset_mm = 0.0;
        report.min_offset_mm = 0.0;
    }
    if report.max_offset_mm == 0.0 && report.min_offset_mm == 0.0 {
        return Ok(report); // nothing to move: the mesh stays bit-identical
    }
    let shift = extension(sector, &flank, profile, &mut report)?;
    let mut moved = vec![false; nn];
    for (n, d) in shift.iter().enumerate() {
        if let Some(d) = d {
            if flank[n].is_none() && *d == [0.0; 3] {
                continue; // held (or not reached): stays bit for bit
            }
            let x = &mut sector.mesh.coords[n];
            for c in 0..3 {
                x[c] += d[c];
            }
            moved[n] = true;
            if flank[n].is_none() {
                report.interior_nodes += 1;
            }
        }
    }
    let mut quality = Quality::empty();
    for (e, el) in sector.mesh.elements.iter().enumerate() {
        if !el.nodes.iter().any(|&n| moved[n]) {
            continue;
        }
        let x = sector.mesh.element_coords(e);
        check_jacobian(el.kind, &x).map_err(|j| {
            let local = el
                .nodes
                .iter()
                .filter_map(|&n| flank[n].map(|f| f.1.abs()))
                .fold(0.0f64, f64::max);
            let moved_by = el
                .nodes
                .iter()
                .filter_map(|&n| shift[n].map(|d| (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()))
                .fold(0.0f64, f64::max);
            j.into_error_in(
                el.label,
                el.kind,
                &format!(
                    "after carrying the flank modification into the body: offsets {:.4} … {:.4} mm over the flanks, {local:.4} mm at this element's flank nodes, nodes moved by up to {moved_by:.4} mm; \
                     the modification is more than this tooth can take whatever the mesh size: reduce it (the scene's amounts are in µm) or check the measured profile",
                    report.min_offset_mm, report.max_offset_mm
                ),
            )
        })?;
        quality.add(el.kind, &x);
        report.elements_checked += 1;
    }
    if report.elements_checked > 0 {
        report.min_scaled_jacobian = quality.min_scaled_jacobian;
    }
    Ok(report)
}

/// The displacement of every node of the extended zone (None elsewhere):
/// the flank nodes' prescribed values exactly, the others from a linear
/// elastic solve (E = 1, ν = 0.3) on the elements whose nodes all lie
/// above r_cut = r_low − (r_a − r_low) (r_low the lowest flank node's
/// radius, r_a the tip radius), held at the nodes they share with the
/// elements below and at the bore.
fn extension(
    sector: &GearSectorMesh,
    flank: &[Option<([f64; 3], f64)>],
    profile: &ToothProfile,
    report: &mut FlankModificationReport,
) -> Result<Vec<Option<[f64; 3]>>, FlankError> {
    let mesh = &sector.mesh;
    let nn = mesh.node_count();
    let radius = |n: usize| mesh.coords[n][0].hypot(mesh.coords[n][1]);
    let r_low = (0..nn)
        .filter(|&n| flank[n].is_some())
        .map(radius)
        .fold(f64::INFINITY, f64::min);
    let depth = (profile.geometry.tip_radius - r_low).max(0.0);
    let r_cut = r_low - depth;
    report.depth_mm = depth;
    let inside: Vec<bool> = mesh
        .elements
        .iter()
        .map(|el| el.nodes.iter().all(|&n| radius(n) >= r_cut))
        .collect();
    let mut used_in = vec![false; nn];
    let mut used_out = vec![false; nn];
    for (el, &i) in mesh.elements.iter().zip(&inside) {
        for &n in &el.nodes {
            if i {
                used_in[n] = true;
            } else {
                used_out[n] = true;
            }
        }
    }
    let bore: std::collections::HashSet<usize> = mesh
        .node_sets
        .get("BORE")
        .map(|v| v.iter().copied().collect())
        .unwrap_or_default();
    let mut sub = mesh.clone();
    sub.elements = mesh
        .elements
        .iter()
        .zip(&inside)
        .filter(|(_, &i)| i)
        .map(|(e, _)| e.clone())
        .collect();
    sub.element_sets.clear();
    let mut model = Model {
        materials: vec![Material::new("extension", 1.0, 0.3)?],
        element_material: vec![0; sub.elements.len()],
        mesh: sub,
        ..Default::default()
    };
    for n in 0..nn {
        let value = match flank[n] {
            Some((d, _)) => d,
            None if used_in[n] && (used_out[n] || bore.contains(&n)) => [0.0; 3],
            None => continue,
        };
        for (component, &value) in value.iter().enumerate() {
            model.dirichlet.push(Dirichlet {
                node: n,
                component,
                value,
            });
        }
    }
    let sol = solve_static(
        &model,
        &SolveOptions {
            recover_stress: false,
            ..Default::default()
        },
    )
    .map_err(|e| {
        err(format!(
            "carrying the flank modification into the body: {e}"
        ))
    })?;
    Ok((0..nn)
        .map(|n| match flank[n] {
            Some((d, _)) => Some(d),
            None if used_in[n] => {
                let u = &sol.displacement[3 * n..3 * n + 3];
                Some([u[0], u[1], u[2]])
            }
            None => None,
        })
        .collect())
}
