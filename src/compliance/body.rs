//! Gear bodies of a scene as `flank mesh` builds them, and their flank nodes
//! with exact normals.
//!
//! Both pair types reach the compliance machinery through [`SectorBody`]:
//! a clamped body model, the flank parameters (u, v) of its flank nodes and
//! its nominal tooth surfaces. Spur/helical bodies come from
//! [`scene_body`] (profile roll angle × face position), bevel/hypoid bodies
//! from [`bevel_scene_body`] (the axial-section coordinates of
//! [`crate::mesh::bevel_sector`]: u across the pitch generatrix, v the cone
//! distance); nothing after that point knows which it is.

use crate::compliance::FlankNodes;
use crate::error::FlankError;
use crate::fem::mesh::Mesh;
use crate::fem::model::Model;
use crate::geometry::cylindrical::CylindricalGear;
use crate::geometry::gear_pair::{Flank, GearBody};
use crate::geometry::involute::base_radius;
use crate::mesh::bevel_body::bevel_body_model;
use crate::mesh::bevel_sector::BevelSectorOptions;
use crate::mesh::gear_body::{body_model, BodyModel, Mesher};
use crate::mesh::gear_sector::SectorOptions;
use crate::scene::{ElementKind, Scene};
use crate::settings::FlankSelection;
use std::collections::HashMap;
use std::sync::Arc;

/// A meshed, clamped gear body with what its compliance tensors need.
pub struct SectorBody {
    /// "pinion" or "gear".
    pub name: String,
    /// Mount clamped; the nominal load when asked for (it does not enter
    /// the compliance).
    pub model: Model,
    /// Flank parameters (u, v) of every flank node (mesh index).
    pub flank_uv: HashMap<usize, (f64, f64)>,
    /// The nominal tooth surfaces (exact flank normals).
    pub surfaces: Arc<dyn GearBody>,
}

impl From<BodyModel> for SectorBody {
    fn from(b: BodyModel) -> Self {
        SectorBody {
            name: b.name,
            model: b.model,
            flank_uv: b.sector.flank_uv,
            surfaces: b.surfaces,
        }
    }
}

/// The body `name` ("pinion" or "gear") of a scene of either pair type.
pub fn any_scene_body(
    scene: &Scene,
    name: &str,
    options: &BodyMeshOptions,
) -> Result<SectorBody, FlankError> {
    if scene.is_bevel() {
        bevel_scene_body(scene, name, options)
    } else {
        scene_body(scene, name, options).map(SectorBody::from)
    }
}

/// The bevel sector options `flank mesh` uses for `scene` with these
/// overrides: absent sizes default to m_mn/8 (flank) and m_mn/2 (base);
/// the element family is the option's, else the scene's `[mesh] element`.
pub fn bevel_sector_options(
    scene: &Scene,
    o: &BodyMeshOptions,
) -> Result<BevelSectorOptions, FlankError> {
    let bevel = scene.bevel("the bevel/hypoid compliance")?;
    let mn = bevel.blank.cones.m_mn;
    let flank_size = o.flank_size.or(scene.mesh.flank_size).unwrap_or(mn / 8.0);
    let base_size = o.base_size.or(scene.mesh.base_size).unwrap_or(mn / 2.0);
    // where a size came from: the option, the scene's key (file:line) or the default
    let source =
        |given: Option<f64>, line: Option<usize>, option: &str, key: &str| match (given, line) {
            (Some(_), _) => option.to_string(),
            (None, Some(l)) => format!("{} `{key}`", scene.at(l)),
            _ => format!("the default {option}"),
        };
    let flank_source = source(
        o.flank_size,
        bevel.lines.flank_size,
        "--flank-size",
        "mesh.flank_size_mm",
    );
    let base_source = source(
        o.base_size,
        bevel.lines.base_size,
        "--base-size",
        "mesh.base_size_mm",
    );
    if !(flank_size > 0.0 && base_size >= flank_size) {
        return Err(FlankError::Model(format!(
            "{flank_source} / {base_source}: element sizes must satisfy 0 < flank size ({flank_size}) ≤ base size ({base_size})"
        )));
    }
    // at least two flank elements along the face width and the working
    // depth of each member, and two along the face (their length there is
    // the base size): coarser sizes leave one distorted layer (a 50 mm
    // flank size on seed 003 meshed with scaled Jacobians of 0.12, a 60 mm
    // base size with one face layer and an aspect ratio of 71)
    for (name, body) in ["pinion", "gear"].iter().zip(&bevel.bodies) {
        let c = body.cones();
        let limit = 0.5 * c.b.min(c.ham + c.hfm);
        if flank_size > limit {
            return Err(FlankError::Model(format!(
                "{flank_source} = {flank_size} mm: the flank elements do not fit the {name}'s teeth twice (face width {:.3} mm, mean whole depth {:.3} mm): at most {limit:.3} mm",
                c.b,
                c.ham + c.hfm
            )));
        }
        if base_size > 0.5 * c.b {
            return Err(FlankError::Model(format!(
                "{base_source} = {base_size} mm: the flank elements do not fit the {name}'s face width {:.3} mm twice along the face (their length there is the base size): at most {:.3} mm",
                c.b,
                0.5 * c.b
            )));
        }
    }
    let element = match o.element.unwrap_or(scene.mesh.element) {
        ElementKind::Hex20 => crate::fem::mesh::ElementKind::C3D20,
        ElementKind::Wedge15 => crate::fem::mesh::ElementKind::C3D15,
    };
    Ok(BevelSectorOptions {
        flank_size,
        base_size,
        element,
        shank: bevel.pinion_shank,
        ..Default::default()
    })
}

/// Default flank size of a bevel/hypoid body meshed for its compliance
/// tensors (`flank compliance`, `flank ltca`), in mean normal modules; the
/// base size is 4 × that. The meshing default m_mn/8 (0.49 mm on seed 003)
/// needs 46.5 GB for the tensors (the memory guard refuses it); tensors
/// on 1.5 mm / 6 mm bodies (0.39 m_mn) meet issue 19's LTCA targets on
/// seed 003 (`verification/ltca_hypoid`: shares within 0.015, TE within
/// 2.97 %) and 0.75 mm tensors did not bring the TE closer (3.6 %): the
/// near-field model, not the tensors' mesh, sets the LTCA's error there.
pub const COMPLIANCE_FLANK_MODULES: f64 = 0.4;

/// `o` with the compliance defaults ([`COMPLIANCE_FLANK_MODULES`]) where
/// neither the option nor the scene's `[mesh]` gives a size.
pub fn compliance_sizes(scene: &Scene, o: &BodyMeshOptions) -> BodyMeshOptions {
    let flank = COMPLIANCE_FLANK_MODULES * scene.normal_module();
    let flank_size = o.flank_size.or(scene.mesh.flank_size).unwrap_or(flank);
    let base_size = o
        .base_size
        .or(scene.mesh.base_size)
        .unwrap_or((4.0 * flank).max(flank_size));
    BodyMeshOptions {
        flank_size: Some(flank_size),
        base_size: Some(base_size),
        ..*o
    }
}

/// One body of a bevel/hypoid scene meshed and clamped as `flank mesh`
/// writes it (nominal load: the pinion torque on the pinion, the torque ×
/// z₂/z₁ on the gear, at the middle tooth's drive flank).
pub fn bevel_scene_body(
    scene: &Scene,
    name: &str,
    options: &BodyMeshOptions,
) -> Result<SectorBody, FlankError> {
    let bevel = scene.bevel("the bevel/hypoid compliance")?;
    let (index, material) = match name {
        "pinion" => (0, &scene.pinion_material),
        "gear" => (1, &scene.gear_material),
        other => {
            return Err(FlankError::Model(format!(
                "unknown body '{other}' (pinion or gear)"
            )))
        }
    };
    let sector = bevel_sector_options(scene, &compliance_sizes(scene, options))?;
    let torque = [
        scene.load.torque_nmm,
        scene.load.torque_nmm * bevel.blank.z2 / bevel.blank.z1,
    ][index];
    let gear = &bevel.bodies[index];
    let body = bevel_body_model(
        gear,
        name,
        material,
        &sector.member(index == 0),
        options.with_load.then_some(torque),
    )?;
    Ok(SectorBody {
        name: body.name,
        model: body.model,
        flank_uv: body.sector.flank_uv,
        surfaces: gear.clone(),
    })
}

/// Mesh sizes of a scene's bodies: command-line values override the
/// scene's `[mesh]`, whose absent sizes default to m_n/8 (flank) and m_n/2
/// (base), as in `flank mesh` (bevel/hypoid bodies meshed for their
/// tensors: [`compliance_sizes`]).
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
    let cyl = scene.cylindrical("the spur/helical compliance")?;
    let mn = cyl.pair.pinion.normal_module;
    let flank_size = o.flank_size.or(scene.mesh.flank_size).unwrap_or(mn / 8.0);
    let base_size = o.base_size.or(scene.mesh.base_size).unwrap_or(mn / 2.0);
    if !(flank_size > 0.0 && base_size >= flank_size) {
        return Err(FlankError::Model(format!(
            "element sizes must satisfy 0 < flank size ({flank_size}) ≤ base size ({base_size})"
        )));
    }
    let element = match o.element.unwrap_or(scene.mesh.element) {
        ElementKind::Hex20 => crate::fem::mesh::ElementKind::C3D20,
        ElementKind::Wedge15 => crate::fem::mesh::ElementKind::C3D15,
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
pub fn scene_body(
    scene: &Scene,
    name: &str,
    options: &BodyMeshOptions,
) -> Result<BodyModel, FlankError> {
    let cyl = scene.cylindrical("the spur/helical compliance")?;
    let report = crate::geometry::pair::check_pair(&cyl.pair)?;
    let (spec, material, index) = match name {
        "pinion" => (&cyl.pair.pinion, &scene.pinion_material, 0),
        "gear" => (&cyl.pair.gear, &scene.gear_material, 1),
        other => {
            return Err(FlankError::Model(format!(
                "unknown body '{other}' (pinion or gear)"
            )))
        }
    };
    let sector = sector_options(scene, options)?;
    // the scene's gear behind the gear-pair interface, with its flank
    // modification (applied to the flank nodes, as in `flank mesh`)
    let [m1, m2] = cyl.flank_modifications()?;
    let modification = if index == 0 { m1 } else { m2 };
    let gear = CylindricalGear::new(spec, name, sector.teeth, modification)?;
    // the deck's nominal load of `flank mesh`: T/r_b1 at the working pitch
    // radius r_b/cos α_wt (ISO 6336-1 single-pair normal force)
    let force = scene.load.torque_nmm / base_radius(&cyl.pair.pinion);
    let cos_aw = report.working_pressure_angle_rad.cos();
    let load = (options.with_load && force > 0.0).then_some((force, base_radius(spec) / cos_aw));
    body_model(&gear, material, &sector, Mesher::Native, load)
}

/// Margin of the active flank region below the start of active profile,
/// in flank element sizes ([`active_margin_mm`]).
pub const ACTIVE_MARGIN_ELEMENTS: f64 = 2.0;

/// Margin of the active flank region below the start of active profile
/// beyond the element sizes (mm, arc length of the transverse profile):
/// room for tip-corner contact before the kinematic start (the LTCA keeps
/// corner points up to its extension, 0.2 mm separation by default, raised
/// under load) and for the cells' half-width.
pub const ACTIVE_MARGIN_MM: f64 = 1.0;

/// The margin below the start of active profile of a body meshed with
/// flank elements of `flank_size` mm: [`ACTIVE_MARGIN_ELEMENTS`] elements
/// plus [`ACTIVE_MARGIN_MM`] (2 × 0.475 + 1 = 1.95 mm at the seed 002
/// default size). A contact that still reaches below it is an error
/// ([`crate::compliance::FlankInterpolator::check_region`]), never a load
/// silently dropped.
pub fn active_margin_mm(flank_size: f64) -> f64 {
    ACTIVE_MARGIN_ELEMENTS * flank_size + ACTIVE_MARGIN_MM
}

/// The lowest profile parameter u of the active flank of body `name`
/// ("pinion" or "gear") of a spur/helical scene, plus `margin_mm` down the
/// profile: the start of active profile (the radius the mating tip reaches,
/// [`crate::geometry::pair::check_pair`], at the form circle if it lies
/// below it), then `margin_mm` of arc length of the transverse profile
/// further down, along the involute and on into the root fillet
/// (u = u_form − t there, as in [`crate::mesh::gear_sector`]); at most down
/// to the root circle (u_form − 1, the whole fillet).
pub fn active_flank_cut(scene: &Scene, name: &str, margin_mm: f64) -> Result<f64, FlankError> {
    let cyl = scene.cylindrical("the spur/helical compliance")?;
    use crate::geometry::gear_pair::Flank as Side;
    use crate::geometry::rack::ToothProfile;
    use crate::mesh::gear_sector::flank_segment;
    if !(margin_mm.is_finite() && margin_mm >= 0.0) {
        return Err(FlankError::Model(format!(
            "active flank margin {margin_mm} mm: a finite value ≥ 0 is needed"
        )));
    }
    let report = crate::geometry::pair::check_pair(&cyl.pair)?;
    let (spec, sap) = match name {
        "pinion" => (&cyl.pair.pinion, report.pinion.active_start_radius),
        "gear" => (&cyl.pair.gear, report.gear.active_start_radius),
        other => {
            return Err(FlankError::Model(format!(
                "unknown body '{other}' (pinion or gear)"
            )))
        }
    };
    let profile = ToothProfile::new(spec, name)?;
    let rb = profile.geometry.base_radius;
    let u_sap = crate::geometry::micro::roll_angle_at_radius(rb, sap.max(rb))?;
    let bottom = profile.u_form - 1.0;
    let at = |u: f64| profile.point(Side::Right, flank_segment(&profile, u)).p;
    // walk down the profile in steps of 1e-3 in u (a roll angle on the
    // involute, the fillet parameter on the fillet)
    let mut u = u_sap.max(profile.u_form).min(profile.u_tip);
    let mut p = at(u);
    let mut left = margin_mm;
    const STEP: f64 = 1e-3;
    while left > 0.0 && u > bottom {
        let next = (u - STEP).max(bottom);
        let q = at(next);
        let d = (q[0] - p[0]).hypot(q[1] - p[1]);
        if d >= left {
            return Ok(u - (u - next) * left / d);
        }
        left -= d;
        u = next;
        p = q;
    }
    Ok(u)
}

/// The flank nodes of `selection` of a gear body, with the exact outward
/// normals of its nominal tooth surfaces (`BodyModel::surfaces`).
pub fn body_flank_nodes(
    body: &BodyModel,
    selection: FlankSelection,
) -> Result<FlankNodes, FlankError> {
    flank_nodes_on(
        &body.model.mesh,
        &body.sector.flank_uv,
        body.surfaces.as_ref(),
        selection,
    )
}

/// [`body_flank_nodes`] on any mesh of a gear sector with its node sets
/// `FLANK_L<k>`/`FLANK_R<k>` and flank parameters `flank_uv` (mesh index →
/// (u, v)), e.g. the mesh read back from the body's deck.
pub fn flank_nodes_on(
    mesh: &Mesh,
    flank_uv: &HashMap<usize, (f64, f64)>,
    surfaces: &dyn GearBody,
    selection: FlankSelection,
) -> Result<FlankNodes, FlankError> {
    let name = surfaces.name();
    let teeth = (1..)
        .take_while(|k| mesh.node_sets.contains_key(&format!("FLANK_R{k}")))
        .count();
    if teeth == 0 {
        return Err(FlankError::Model(format!(
            "{name}: the mesh has no FLANK_R1 set"
        )));
    }
    let sets = selection.set_names(teeth);
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
        let flank = surfaces.flank(side, k).ok_or_else(|| {
            FlankError::Model(format!(
                "{name}: the gear has no flank {side:?} of tooth {k}"
            ))
        })?;
        Ok(flank.normal(u, v))
    };
    FlankNodes::from_mesh(mesh, &sets, flank_uv, Some(&normal))
}

/// The flank parameters of `body` re-keyed to the node indices of `mesh`
/// (matched by node label), e.g. the body's deck read back.
pub fn flank_uv_on(
    body: &SectorBody,
    mesh: &Mesh,
) -> Result<HashMap<usize, (f64, f64)>, FlankError> {
    body.flank_uv
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
        let body = scene_body(&scene, "pinion", &o).unwrap();
        assert!(body.load.is_some());
        assert!(body
            .model
            .mesh
            .elements
            .iter()
            .all(|e| e.kind == crate::fem::mesh::ElementKind::C3D20));
        for sel in [FlankSelection::Loaded, FlankSelection::Left] {
            let f = body_flank_nodes(&body, sel).unwrap();
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
        let body = scene_body(&scene, "gear", &o).unwrap();
        assert!(body
            .model
            .mesh
            .elements
            .iter()
            .all(|e| e.kind == crate::fem::mesh::ElementKind::C3D15));
        let f = body_flank_nodes(&body, FlankSelection::Loaded).unwrap();
        assert!(!f.faces.is_empty() && f.faces.iter().all(|x| x.nodes.len() == 8));
        let mesh_normals = f.face_normals().unwrap();
        for (a, b) in f.normals.iter().zip(&mesh_normals) {
            assert!(a[0] * b[0] + a[1] * b[1] + a[2] * b[2] > 0.99);
        }
    }

    /// A hypoid body in wedge15 (`element` = wedge15): its flank faces are
    /// the quad8 sides of the wedges, as many as the hex20 body's, with the
    /// same nodes, and the exact normals agree with theirs.
    #[test]
    fn hypoid_wedge15_flank_faces() {
        let path = format!(
            "{}/papers/seed003-hypoid/scene.toml",
            env!("CARGO_MANIFEST_DIR")
        );
        let s = crate::scene::read_scene(std::path::Path::new(&path)).unwrap();
        let faces = |element| {
            let o = BodyMeshOptions {
                flank_size: Some(2.0),
                base_size: Some(8.0),
                with_load: false,
                element: Some(element),
            };
            let body = bevel_scene_body(&s, "gear", &o).unwrap();
            let kinds: std::collections::HashSet<_> =
                body.model.mesh.elements.iter().map(|e| e.kind).collect();
            let f = flank_nodes_on(
                &body.model.mesh,
                &body.flank_uv,
                body.surfaces.as_ref(),
                FlankSelection::Loaded,
            )
            .unwrap();
            let mesh_normals = f.face_normals().unwrap();
            let worst = f
                .normals
                .iter()
                .zip(&mesh_normals)
                .map(|(a, b)| a[0] * b[0] + a[1] * b[1] + a[2] * b[2])
                .fold(1.0, f64::min);
            let mut corners: Vec<Vec<[u64; 3]>> = f
                .faces
                .iter()
                .map(|x| {
                    let mut c: Vec<[u64; 3]> = x
                        .nodes
                        .iter()
                        .map(|&n| f.positions[n as usize].map(f64::to_bits))
                        .collect();
                    c.sort_unstable();
                    c
                })
                .collect();
            corners.sort_unstable();
            (
                kinds,
                f.faces.iter().all(|x| x.nodes.len() == 8),
                corners,
                worst,
            )
        };
        let (kh, qh, ch, wh) = faces(ElementKind::Hex20);
        let (kw, qw, cw, ww) = faces(ElementKind::Wedge15);
        assert_eq!(
            kh.into_iter().collect::<Vec<_>>(),
            [crate::fem::mesh::ElementKind::C3D20]
        );
        assert_eq!(
            kw.into_iter().collect::<Vec<_>>(),
            [crate::fem::mesh::ElementKind::C3D15]
        );
        assert!(qh && qw && !cw.is_empty());
        assert!(cw == ch, "wedge15 and hex20 flank faces differ");
        assert!(ww > 0.99 && (ww - wh).abs() < 1e-12, "{wh} {ww}");
    }

    /// The compliance default of a hypoid body: 0.4 m_mn and 4 × that
    /// (1.56 / 6.22 mm on seed 003) where nothing is given; a given size
    /// wins, and a base size below a given flank size follows it.
    #[test]
    fn hypoid_compliance_default_sizes() {
        let path = format!(
            "{}/papers/seed003-hypoid/scene.toml",
            env!("CARGO_MANIFEST_DIR")
        );
        let s = crate::scene::read_scene(std::path::Path::new(&path)).unwrap();
        let m = s.bevel("this test").unwrap().blank.cones.m_mn;
        let d = compliance_sizes(&s, &BodyMeshOptions::default());
        assert_eq!(d.flank_size, Some(COMPLIANCE_FLANK_MODULES * m));
        assert_eq!(d.base_size, Some(4.0 * COMPLIANCE_FLANK_MODULES * m));
        let o = BodyMeshOptions {
            flank_size: Some(10.0),
            ..Default::default()
        };
        let g = compliance_sizes(&s, &o);
        assert_eq!((g.flank_size, g.base_size), (Some(10.0), Some(10.0)));
        assert!(bevel_sector_options(&s, &d).is_ok());
    }
}
