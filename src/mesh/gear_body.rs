//! A gear body ready to solve: the sector mesh of [`super::gear_sector`] with
//! its material, the bore clamped, and (optionally) the single-pair normal
//! force at the working pitch point of the middle tooth's right flank.
//!
//! The nominal load is F_n = T₁ / r_b1 (the normal force of one tooth pair
//! carrying the whole pinion torque, ISO 6336-1), applied as one nodal force
//! along the inward flank normal at the flank node nearest to the working
//! pitch radius r_w = r_b / cos α_wt at mid face width. It makes every
//! written deck solvable as it is; contact analyses replace it.

use crate::error::FlankError;
use crate::fem::material::Material;
use crate::fem::model::{Dirichlet, Model, NodalForce};
use crate::geometry::rack::{Flank, ToothProfile};
use crate::geometry::GearSpec;
use crate::mesh::gear_sector::{flank_segment, gear_sector, GearSectorMesh, SectorOptions};

/// A meshed, constrained, loaded gear body.
pub struct GearBody {
    pub name: String,
    pub sector: GearSectorMesh,
    pub model: Model,
    /// The loaded node (index) and force vector, if a nominal load was applied.
    pub load: Option<(usize, [f64; 3])>,
}

/// Meshes one gear as a sector, assigns `material`, clamps the set `BORE`,
/// and, if `normal_force` (N) is given, loads the middle tooth's right flank
/// at radius `load_radius` (mm), mid face width.
pub fn gear_body(
    spec: &GearSpec,
    name: &str,
    material: &Material,
    options: &SectorOptions,
    normal_force: Option<(f64, f64)>,
) -> Result<GearBody, FlankError> {
    let sector = gear_sector(spec, name, options)?;
    let mesh = sector.mesh.clone();
    let ne = mesh.elements.len();
    let bore = mesh
        .node_sets
        .get("BORE")
        .cloned()
        .ok_or_else(|| FlankError::Model(format!("{name}: the sector mesh has no BORE set")))?;
    let mut model = Model {
        mesh,
        materials: vec![material.clone()],
        element_material: vec![0; ne],
        ..Default::default()
    };
    for n in bore {
        for component in 0..3 {
            model.dirichlet.push(Dirichlet {
                node: n,
                component,
                value: 0.0,
            });
        }
    }
    let mut load = None;
    if let Some((force, radius)) = normal_force {
        let tooth = options.teeth.div_ceil(2); // middle tooth, 1-based
        let set = format!("FLANK_R{tooth}");
        let nodes = model
            .mesh
            .node_sets
            .get(&set)
            .ok_or_else(|| FlankError::Model(format!("{name}: no node set {set}")))?;
        let mid = 0.5 * spec.face_width;
        let node = nodes
            .iter()
            .copied()
            .min_by(|&a, &b| {
                let d = |n: usize| {
                    let x = model.mesh.coords[n];
                    let r = (x[0] * x[0] + x[1] * x[1]).sqrt();
                    ((r - radius) / radius).powi(2) + ((x[2] - mid) / spec.face_width).powi(2)
                };
                d(a).total_cmp(&d(b))
            })
            .ok_or_else(|| FlankError::Model(format!("{name}: node set {set} is empty")))?;
        let profile = ToothProfile::new(spec, name)?;
        let &(u, z) = sector
            .flank_uv
            .get(&node)
            .ok_or_else(|| FlankError::Model(format!("{name}: flank node without (u, v)")))?;
        let n0 = profile
            .surface(Flank::Right, flank_segment(&profile, u), z)
            .n;
        // sector tooth k is the profile's tooth k − 1, rotated by −2π(k−1)/z
        let a = -((tooth - 1) as f64) * profile.angular_pitch();
        let (s, c) = a.sin_cos();
        let n = [c * n0[0] - s * n0[1], s * n0[0] + c * n0[1], n0[2]];
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
    Ok(GearBody {
        name: name.to_string(),
        sector,
        model,
        load,
    })
}
