//! A bevel/hypoid body ready to solve: the sector mesh of
//! [`super::bevel_sector`] with its material, the mount (`MOUNT`: the bore
//! of a pinion, the mounting plane of a ring gear) clamped, and optionally
//! a nominal load: one nodal force along the inward normal of the middle
//! tooth's right (drive) flank at the flank node nearest to its mean point
//! (u = 0, v = R_m), of magnitude F = T / |(r × n) · e_z| — the normal
//! force whose moment about the member's axis is the torque T. It makes
//! every written deck solvable as it is; contact analyses replace it.

use crate::error::FlankError;
use crate::fem::material::Material;
use crate::fem::model::{Dirichlet, Model, NodalForce};
use crate::geometry::bevel::body::BevelGear;
use crate::geometry::gear_pair::{Flank, GearBody};
use crate::mesh::bevel_sector::{bevel_sector, BevelSectorMesh, BevelSectorOptions};

/// A meshed, clamped, optionally loaded bevel/hypoid body.
pub struct BevelBodyModel {
    pub name: String,
    pub sector: BevelSectorMesh,
    pub model: Model,
    /// The loaded node (index) and force vector (N), if a load was applied.
    pub load: Option<(usize, [f64; 3])>,
}

/// Meshes `gear`, clamps `MOUNT`, and with `torque` (N·mm, > 0) applies
/// the nominal load (module docs).
pub fn bevel_body_model(
    gear: &BevelGear,
    name: &str,
    material: &Material,
    options: &BevelSectorOptions,
    torque: Option<f64>,
) -> Result<BevelBodyModel, FlankError> {
    let sector = bevel_sector(gear, name, options)?;
    let mesh = sector.mesh.clone();
    let ne = mesh.elements.len();
    let mut model = Model {
        mesh,
        materials: vec![material.clone()],
        element_material: vec![0; ne],
        ..Default::default()
    };
    for &n in &model.mesh.node_sets["MOUNT"] {
        for component in 0..3 {
            model.dirichlet.push(Dirichlet {
                node: n,
                component,
                value: 0.0,
            });
        }
    }
    let mut load = None;
    if let Some(torque) = torque.filter(|&t| t > 0.0) {
        let tooth = gear.sector_teeth().div_ceil(2);
        let set = format!("FLANK_R{tooth}");
        let surface = gear
            .flank(Flank::Right, tooth)
            .ok_or_else(|| FlankError::Model(format!("{name}: no right flank of tooth {tooth}")))?;
        let rm = gear.cones().rm;
        let nodes = &model.mesh.node_sets[&set];
        let node = nodes
            .iter()
            .copied()
            .min_by(|&a, &b| {
                let d = |n: usize| {
                    let (u, v) = sector.flank_uv[&n];
                    u * u + (v - rm) * (v - rm)
                };
                d(a).total_cmp(&d(b))
            })
            .ok_or_else(|| FlankError::Model(format!("{name}: node set {set} is empty")))?;
        let (u, v) = sector.flank_uv[&node];
        let (p, n) = (surface.point(u, v), surface.normal(u, v));
        let lever = (p[0] * n[1] - p[1] * n[0]).abs();
        if !(lever > 1e-9 * rm) {
            return Err(FlankError::Model(format!(
                "{name}: the flank normal at the mean point has no moment about the axis"
            )));
        }
        let force = torque / lever;
        let f = [-force * n[0], -force * n[1], -force * n[2]];
        for (component, &value) in f.iter().enumerate() {
            model.forces.push(NodalForce {
                node,
                component,
                value,
            });
        }
        load = Some((node, f));
    }
    Ok(BevelBodyModel {
        name: name.to_string(),
        sector,
        model,
        load,
    })
}
