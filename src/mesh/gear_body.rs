//! A gear body ready to solve: the sector mesh of [`super::gear_sector`] with
//! its material, the bore clamped, and (optionally) the single-pair normal
//! force at the working pitch point of the middle tooth's right flank.
//!
//! The nominal load is F_n = T₁ / r_b1 (the normal force of one tooth pair
//! carrying the whole pinion torque, ISO 6336-1), applied as one nodal force
//! along the inward flank normal at the flank node nearest to the working
//! pitch radius r_w = r_b / cos α_wt at mid face width. It makes every
//! written deck solvable as it is; contact analyses replace it.
//!
//! The sector comes from the native mesher or, with [`Mesher::Gmsh`] and the
//! Cargo feature `gmsh`, from [`crate::mesh::gmsh`] (same node sets and
//! flank parameters, so everything below is the same).
//!
//! [`body_model`] meshes a gear given through the gear-pair interface
//! ([`crate::geometry::gear_pair::GearBody`]): it picks the mesher of the
//! gear's type (spur/helical: the structured sector mesher, which works on
//! the transverse section of [`CylindricalGear`]) and applies the gear's
//! flank modification. The model keeps the nominal (unmodified) tooth
//! surfaces for the exact normals at its flank nodes.

use std::sync::Arc;

use crate::error::FlankError;
use crate::fem::material::Material;
use crate::fem::mesh::ElementKind;
use crate::fem::model::{Dirichlet, Model, NodalForce};
use crate::geometry::cylindrical::CylindricalGear;
use crate::geometry::gear_pair::GearBody;
use crate::geometry::rack::{Flank, ToothProfile};
use crate::geometry::GearSpec;
use crate::mesh::gear_sector::{flank_segment, gear_sector, GearSectorMesh, SectorOptions};

/// Which mesher makes the sector of [`gear_body_with`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Mesher {
    /// The native structured mesher [`gear_sector`] (element from its options).
    #[default]
    Native,
    /// gmsh ([`crate::mesh::gmsh`], Cargo feature `gmsh`) with hexahedra
    /// (C3D20, C3D20R) or wedges (C3D15).
    Gmsh(ElementKind),
}

/// Whether this build has the gmsh mesher (Cargo feature `gmsh`).
pub const GMSH_AVAILABLE: bool = cfg!(feature = "gmsh");

/// The error text of [`Mesher::Gmsh`] in a build without the feature.
pub const GMSH_MISSING: &str = "the gmsh mesher is not in this build of flank: \
     install gmsh's C library (apt-get install libgmsh-dev) and rebuild with \
     `cargo build --release --features gmsh`";

/// The sector mesh of `spec` by `mesher`.
pub fn mesh_sector(
    spec: &GearSpec,
    name: &str,
    options: &SectorOptions,
    mesher: Mesher,
) -> Result<GearSectorMesh, FlankError> {
    match mesher {
        Mesher::Native => gear_sector(spec, name, options),
        #[cfg(feature = "gmsh")]
        Mesher::Gmsh(kind) => crate::mesh::gmsh::gmsh_sector(spec, name, options, kind),
        #[cfg(not(feature = "gmsh"))]
        Mesher::Gmsh(_) => Err(FlankError::Model(format!("{name}: {GMSH_MISSING}"))),
    }
}

/// A meshed, constrained, loaded gear body.
pub struct BodyModel {
    pub name: String,
    pub sector: GearSectorMesh,
    pub model: Model,
    /// The loaded node (index) and force vector, if a nominal load was applied.
    pub load: Option<(usize, [f64; 3])>,
    /// The nominal (unmodified) tooth surfaces of the sector.
    pub surfaces: Arc<dyn GearBody>,
    /// What [`body_model`] did with the gear's flank modification.
    pub modification: Option<crate::mesh::gear_sector::FlankModificationReport>,
}

impl std::fmt::Debug for BodyModel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("BodyModel")
            .field("name", &self.name)
            .field("nodes", &self.model.mesh.node_count())
            .field("load", &self.load)
            .finish()
    }
}

/// Meshes `body` (any gear type behind the interface) as `flank mesh`
/// does: its type's sector mesher, the bore clamped, the nominal load if
/// `normal_force` = (F, radius) is given (see [`gear_body_with`]), then its
/// flank modification.
pub fn body_model(
    body: &dyn GearBody,
    material: &Material,
    options: &SectorOptions,
    mesher: Mesher,
    normal_force: Option<(f64, f64)>,
) -> Result<BodyModel, FlankError> {
    let name = body.name();
    let Some(cyl) = body.as_any().downcast_ref::<CylindricalGear>() else {
        return Err(FlankError::Model(format!(
            "{name}: flank has no sector mesher for this gear type (spur and helical gears are meshed)"
        )));
    };
    if cyl.sector_teeth() != options.teeth {
        return Err(FlankError::Model(format!(
            "{name}: the gear is a sector of {} teeth, the mesh asks for {}",
            cyl.sector_teeth(),
            options.teeth
        )));
    }
    let mut model = gear_body_with(cyl.spec(), name, material, options, mesher, normal_force)?;
    if let Some(m) = cyl.modification() {
        model.modification = Some(model.modify_flanks(cyl.spec(), m)?);
    }
    Ok(model)
}

impl BodyModel {
    /// Applies a flank modification (micro-geometry, measured profile) to the
    /// body's flank nodes, in the sector and in the model alike; see
    /// [`crate::mesh::gear_sector::modify_flanks`]. `spec` is the body's gear.
    pub fn modify_flanks(
        &mut self,
        spec: &GearSpec,
        modification: &crate::geometry::micro::FlankModification,
    ) -> Result<crate::mesh::gear_sector::FlankModificationReport, FlankError> {
        let profile = ToothProfile::new(spec, &self.name)?;
        let report =
            crate::mesh::gear_sector::modify_flanks(&mut self.sector, &profile, modification)
                .map_err(|e| match e {
                    FlankError::Model(m) => FlankError::Model(format!("{}: {m}", self.name)),
                    e => e,
                })?;
        self.model.mesh.coords.clone_from(&self.sector.mesh.coords);
        Ok(report)
    }
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
) -> Result<BodyModel, FlankError> {
    gear_body_with(spec, name, material, options, Mesher::Native, normal_force)
}

/// [`gear_body`] with the sector meshed by `mesher`.
pub fn gear_body_with(
    spec: &GearSpec,
    name: &str,
    material: &Material,
    options: &SectorOptions,
    mesher: Mesher,
    normal_force: Option<(f64, f64)>,
) -> Result<BodyModel, FlankError> {
    let sector = mesh_sector(spec, name, options, mesher)?;
    body_of_sector(spec, name, material, options, sector, normal_force)
}

/// [`gear_body_with`] of an already meshed sector (e.g. one with contact
/// bands, [`crate::mesh::gear_sector::gear_sector_banded`]): the bore
/// clamped, the nominal load if `normal_force` is given.
pub fn body_of_sector(
    spec: &GearSpec,
    name: &str,
    material: &Material,
    options: &SectorOptions,
    sector: GearSectorMesh,
    normal_force: Option<(f64, f64)>,
) -> Result<BodyModel, FlankError> {
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
    Ok(BodyModel {
        name: name.to_string(),
        sector,
        model,
        load,
        surfaces: Arc::new(CylindricalGear::new(spec, name, options.teeth, None)?),
        modification: None,
    })
}
