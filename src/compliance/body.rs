//! Gear bodies of a scene as `flank mesh` builds them, and their flank nodes
//! with exact normals.

use crate::compliance::{FlankNodes, FlankSelection};
use crate::error::FlankError;
use crate::geometry::involute::base_radius;
use crate::geometry::rack::{Flank, ToothProfile};
use crate::geometry::GearSpec;
use crate::mesh::gear_body::{gear_body, GearBody};
use crate::mesh::gear_sector::{flank_segment, SectorOptions};
use crate::mesh::Mesh;
use crate::scene::{ElementKind, Scene};
use std::collections::HashMap;

/// Mesh sizes of a scene's bodies: command-line values override the
/// scene's `[mesh]`, whose absent sizes default to m_n/8 (flank) and m_n/2
/// (base), as in `flank mesh`.
#[derive(Clone, Copy, Debug, Default)]
pub struct BodyMeshOptions {
    pub flank_size: Option<f64>,
    pub base_size: Option<f64>,
    /// Write the nominal single-pair load into the deck (as `flank mesh`
    /// does unless `--no-load`); it does not enter the compliance.
    pub with_load: bool,
    /// Element family; overrides the scene's `[mesh] element`.
    pub element: Option<ElementKind>,
}

/// The sector options `flank mesh` uses for `scene` with these overrides.
pub fn sector_options(scene: &Scene, o: &BodyMeshOptions) -> Result<SectorOptions, FlankError> {
    let mn = scene.pair.pinion.normal_module;
    let flank_size = o.flank_size.or(scene.mesh.flank_size).unwrap_or(mn / 8.0);
    let base_size = o.base_size.or(scene.mesh.base_size).unwrap_or(mn / 2.0);
    if !(flank_size > 0.0 && base_size >= flank_size) {
        return Err(FlankError::Model(format!(
            "element sizes must satisfy 0 < flank size ({flank_size}) ≤ base size ({base_size})"
        )));
    }
    let element = match o.element.unwrap_or(scene.mesh.element) {
        ElementKind::Hex20 => crate::mesh::ElementKind::C3D20,
        ElementKind::Wedge15 => crate::mesh::ElementKind::C3D15,
    };
    Ok(SectorOptions {
        teeth: scene.mesh.teeth_in_sector as usize,
        flank_size,
        base_size,
        face_layers: 0,
        element,
    })
}

/// One body of a scene, meshed and constrained exactly as `flank mesh`
/// (native mesher) writes it, flank modifications of `[<gear>.micro]`
/// applied (`name` = "pinion" or "gear"). The exact normals of
/// [`body_flank_nodes`] are those of the unmodified flank: modifications
/// tilt it by their slope, micrometres over millimetres.
pub fn scene_body<'s>(
    scene: &'s Scene,
    name: &str,
    options: &BodyMeshOptions,
) -> Result<(GearBody, &'s GearSpec), FlankError> {
    let report = crate::geometry::pair::check_pair(&scene.pair)?;
    let (spec, material) = match name {
        "pinion" => (&scene.pair.pinion, &scene.pinion_material),
        "gear" => (&scene.pair.gear, &scene.gear_material),
        other => {
            return Err(FlankError::Model(format!(
                "unknown body '{other}' (pinion or gear)"
            )))
        }
    };
    let sector = sector_options(scene, options)?;
    let force = scene.load.torque_nmm / base_radius(&scene.pair.pinion);
    let cos_aw = report.working_pressure_angle_rad.cos();
    let load = (options.with_load && force > 0.0).then_some((force, base_radius(spec) / cos_aw));
    let mut body = gear_body(spec, name, material, &sector, load)?;
    // the scene's flank modifications move the flank nodes, as in `flank mesh`
    let index = usize::from(name == "gear");
    if let Some(m) = &scene.flank_modifications()?[index] {
        body.modify_flanks(spec, m)?;
    }
    Ok((body, spec))
}

/// The flank nodes of `selection` of a gear body, with the exact outward
/// normals of the tooth surface (sector tooth k is the profile's tooth
/// k − 1, rotated by −2π(k − 1)/z; see [`crate::mesh::gear_sector`]).
pub fn body_flank_nodes(
    body: &GearBody,
    spec: &GearSpec,
    selection: FlankSelection,
) -> Result<FlankNodes, FlankError> {
    flank_nodes_on(
        &body.model.mesh,
        &body.sector.flank_uv,
        spec,
        &body.name,
        selection,
    )
}

/// [`body_flank_nodes`] on any mesh of a gear sector with its node sets
/// `FLANK_L<k>`/`FLANK_R<k>` and flank parameters `flank_uv` (mesh index →
/// (u, v)), e.g. the mesh read back from the body's deck.
pub fn flank_nodes_on(
    mesh: &Mesh,
    flank_uv: &HashMap<usize, (f64, f64)>,
    spec: &GearSpec,
    name: &str,
    selection: FlankSelection,
) -> Result<FlankNodes, FlankError> {
    let teeth = (1..)
        .take_while(|k| mesh.node_sets.contains_key(&format!("FLANK_R{k}")))
        .count();
    if teeth == 0 {
        return Err(FlankError::Model(format!(
            "{name}: the mesh has no FLANK_R1 set"
        )));
    }
    let sets = selection.set_names(teeth);
    let profile = ToothProfile::new(spec, name)?;
    let parsed: Vec<(Flank, usize)> = sets
        .iter()
        .map(|s| {
            let side = if s.starts_with("FLANK_L") {
                Flank::Left
            } else {
                Flank::Right
            };
            let k: usize = s[7..].parse().unwrap_or(1);
            (side, k)
        })
        .collect();
    let normal = |set: usize, u: f64, v: f64| -> Result<[f64; 3], FlankError> {
        let (side, k) = parsed[set];
        let n0 = profile.surface(side, flank_segment(&profile, u), v).n;
        let a = -((k - 1) as f64) * profile.angular_pitch();
        let (s, c) = a.sin_cos();
        Ok([c * n0[0] - s * n0[1], s * n0[0] + c * n0[1], n0[2]])
    };
    FlankNodes::from_mesh(mesh, &sets, flank_uv, Some(&normal))
}

/// The flank parameters of `body` re-keyed to the node indices of `mesh`
/// (matched by node label), e.g. the body's deck read back.
pub fn flank_uv_on(body: &GearBody, mesh: &Mesh) -> Result<HashMap<usize, (f64, f64)>, FlankError> {
    body.sector
        .flank_uv
        .iter()
        .map(|(&n, &uv)| {
            let label = body.model.mesh.node_labels[n];
            mesh.node(label)
                .map(|i| (i, uv))
                .ok_or_else(|| FlankError::Model(format!("flank node {label} is not in the mesh")))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::compliance::flank::norm;

    #[test]
    fn exact_normals_agree_with_face_normals() {
        let scene = crate::scene::read_scene(std::path::Path::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/papers/seed002-spur/scene.toml"
        )))
        .unwrap();
        let o = BodyMeshOptions {
            flank_size: Some(1.0),
            base_size: Some(3.0),
            with_load: true,
            element: Some(ElementKind::Hex20),
        };
        let (body, spec) = scene_body(&scene, "pinion", &o).unwrap();
        assert!(body.load.is_some());
        assert!(body
            .model
            .mesh
            .elements
            .iter()
            .all(|e| e.kind == crate::mesh::ElementKind::C3D20));
        for sel in [FlankSelection::Loaded, FlankSelection::Left] {
            let f = body_flank_nodes(&body, spec, sel).unwrap();
            assert_eq!(f.sets.len(), 3);
            assert!(!f.faces.is_empty());
            let mesh_normals = f.face_normals().unwrap();
            let mut worst: f64 = 1.0;
            for (a, b) in f.normals.iter().zip(&mesh_normals) {
                worst = worst.min(a[0] * b[0] + a[1] * b[1] + a[2] * b[2]);
                assert!((norm(*a) - 1.0).abs() < 1e-12);
            }
            // outward and close to the faces' normals (1 mm elements)
            assert!(worst > 0.99, "{sel:?}: min cos = {worst}");
        }
        assert!(scene_body(&scene, "wheel", &o).is_err());
        // the scene's own element (seed 002: wedge15): quad8 flank faces, normals as well
        let o = BodyMeshOptions { element: None, ..o };
        let (body, spec) = scene_body(&scene, "gear", &o).unwrap();
        assert!(body
            .model
            .mesh
            .elements
            .iter()
            .all(|e| e.kind == crate::mesh::ElementKind::C3D15));
        let f = body_flank_nodes(&body, spec, FlankSelection::Loaded).unwrap();
        assert!(!f.faces.is_empty() && f.faces.iter().all(|x| x.nodes.len() == 8));
        let mesh_normals = f.face_normals().unwrap();
        for (a, b) in f.normals.iter().zip(&mesh_normals) {
            assert!(a[0] * b[0] + a[1] * b[1] + a[2] * b[2] > 0.99);
        }
    }
}
