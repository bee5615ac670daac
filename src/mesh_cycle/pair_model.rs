//! The FE model of a gear pair in mesh, as seed 002 builds it in Abaqus:
//! both tooth sectors in one model, the pinion hub kinematically coupled to
//! a reference node on its axis that may only turn about the axis and
//! carries the torque, the gear hub clamped, and one frictionless
//! node-to-surface contact pair per meshing tooth pair on the drive flanks.
//!
//! The bodies stay in their own frames (their stiffness is then the same
//! at every roll angle and is factorized once); [`GearPair::nominal_frames`]
//! places them for the contact geometry of each position.

use crate::compliance::body::{scene_body, BodyMeshOptions};
use crate::contact::surface::faces_on_nodes;
use crate::contact::{
    ContactDefinition, ContactPair, PressureOverclosure, Surface, SurfaceInteraction, SurfaceKind,
};
use crate::error::FlankError;
use crate::fem::mesh::Mesh;
use crate::fem::model::{Dirichlet, Model, RigidCoupling};
use crate::geometry::gear_pair::{GearPair, LineContactPair};
use crate::mesh::bevel_body::bevel_body_model;
use crate::mesh::bevel_sector::BevelSectorOptions;
use crate::scene::Scene;
use crate::settings::SlaveBody;

/// The pair model and what the driver needs to read it.
pub struct PairModel {
    pub model: Model,
    /// Body of every node: 0 pinion, 1 gear.
    pub body_of: Vec<u32>,
    /// Nodes of all contact surfaces (flank nodes of both bodies).
    pub contact_nodes: Vec<usize>,
    /// Tooth pair p joins pinion tooth `teeth[p].0` and gear tooth `teeth[p].1`.
    pub teeth: Vec<(usize, usize)>,
    /// Indices into `model.contact.pairs` of tooth pair p with the pinion
    /// as slave (`[p][0]`) and with the gear as slave (`[p][1]`); `None`
    /// where the model was built for one slave body only.
    pub pairings: Vec<[Option<usize>; 2]>,
    /// Flank parameters (u, z) of every flank node (index into the model).
    pub flank_uv: std::collections::HashMap<usize, (f64, f64)>,
    pub nodes: [usize; 2],
    pub elements: [usize; 2],
}

/// Builds the pair model of `scene` with the sector meshes of `mesh`,
/// torque T (N·mm, > 0: drives the right flanks) and the normal law `law`.
pub fn pair_model(
    scene: &Scene,
    gears: &dyn LineContactPair,
    mesh: &BodyMeshOptions,
    law: PressureOverclosure,
    slave: SlaveBody,
) -> Result<PairModel, FlankError> {
    let torque = scene.load.torque_nmm;
    if !(torque > 0.0 && torque.is_finite()) {
        return Err(FlankError::Model(format!(
            "FE contact needs a positive pinion torque ([load] torque_nm); got {} N·m: with no torque the teeth carry nothing and the pinion's rotation is not determined",
            torque / 1000.0
        )));
    }
    let options = BodyMeshOptions {
        with_load: false,
        ..*mesh
    };
    let pinion = scene_body(scene, "pinion", &options)?;
    let gear = scene_body(scene, "gear", &options)?;
    combine(
        gears,
        [
            PairBody::of(&pinion.name, &pinion.model, &pinion.sector.flank_uv),
            PairBody::of(&gear.name, &gear.model, &gear.sector.flank_uv),
        ],
        torque,
        law,
        slave,
    )
}

/// The pair model of a bevel/hypoid `scene`: both members meshed by the
/// bevel sector mesher with `mesh`, kept in their own frames, hard
/// contact, the pinion's drive flanks as slaves (a penalty law and
/// friction are set by [`crate::mesh_cycle::cycle::MeshCycle::of_pair`]).
pub fn bevel_pair_model(scene: &Scene, mesh: &BevelSectorOptions) -> Result<PairModel, FlankError> {
    let bevel = scene.bevel("the bevel/hypoid FE mesh cycle")?;
    check_torque(scene)?;
    let pinion = bevel_body_model(
        &bevel.bodies[0],
        "pinion",
        &scene.pinion_material,
        &mesh.member(true),
        None,
    )?;
    let gear = bevel_body_model(
        &bevel.bodies[1],
        "gear",
        &scene.gear_material,
        &mesh.member(false),
        None,
    )?;
    combine(
        bevel.pair.as_ref(),
        [
            PairBody::of("pinion", &pinion.model, &pinion.sector.flank_uv),
            PairBody::of("gear", &gear.model, &gear.sector.flank_uv),
        ],
        scene.load.torque_nmm,
        PressureOverclosure::Hard,
        SlaveBody::Pinion,
    )
}

/// `load.torque_nm` of a bevel/hypoid scene must load the pairs: a zero
/// torque leaves every pair unloaded and the pinion's rotation
/// undetermined (a negative one is refused when the scene is read).
pub fn check_torque(scene: &Scene) -> Result<(), FlankError> {
    let bevel = scene.bevel("the bevel/hypoid FE mesh cycle")?;
    let t = scene.load.torque_nmm;
    if !(t > 0.0 && t.is_finite()) {
        return Err(FlankError::Model(format!(
            "{}: `load.torque_nm` = {}: FE contact needs a positive pinion torque; with none every tooth pair is unloaded and the pinion's rotation is not determined",
            scene.at(bevel.lines.torque),
            t / 1000.0
        )));
    }
    Ok(())
}

/// One body of a pair model: its name, its clamped model (mesh, material,
/// the mount's conditions) and the flank parameters of its flank nodes.
#[derive(Clone, Copy)]
pub struct PairBody<'a> {
    pub name: &'a str,
    pub model: &'a Model,
    pub flank_uv: &'a std::collections::HashMap<usize, (f64, f64)>,
}

impl<'a> PairBody<'a> {
    pub fn of(
        name: &'a str,
        model: &'a Model,
        flank_uv: &'a std::collections::HashMap<usize, (f64, f64)>,
    ) -> Self {
        PairBody {
            name,
            model,
            flank_uv,
        }
    }
}

/// Label offset that keeps the gear's labels apart from the pinion's.
fn label_offset(max: u64) -> u64 {
    let mut off = 10;
    while off <= max {
        off *= 10;
    }
    off
}

/// Both bodies in one model (module docs): the pinion's mount (`MOUNT`,
/// else `BORE`) coupled to a reference node on its axis loaded by the
/// torque T (N·mm) in the drive sense ([`GearPair::rotation_axes`]),
/// the gear's own conditions kept, one contact pair per tooth pair on the
/// right (drive) flanks, pinion tooth k against gear tooth `mate(k)`.
pub fn combine(
    gears: &dyn GearPair,
    bodies: [PairBody; 2],
    torque: f64,
    law: PressureOverclosure,
    slave: SlaveBody,
) -> Result<PairModel, FlankError> {
    let [pinion, gear] = bodies;
    let pm = &pinion.model.mesh;
    let gm = &gear.model.mesh;
    let node_off = label_offset(pm.node_labels.iter().copied().max().unwrap_or(0));
    let elem_off = label_offset(pm.elements.iter().map(|e| e.label).max().unwrap_or(0));
    let mut mesh = Mesh::new();
    let mut body_of = Vec::with_capacity(pm.node_count() + gm.node_count());
    let mut flank_uv = std::collections::HashMap::new();
    let mut base = [0usize; 2];
    for (b, (body, src)) in [(pinion, pm), (gear, gm)].into_iter().enumerate() {
        let (noff, eoff) = if b == 0 { (0, 0) } else { (node_off, elem_off) };
        // every set of the body, prefixed with its name (PINION_BORE, ...)
        let prefix = body.name.to_ascii_uppercase();
        let (nbase, _) = mesh
            .append(src, noff, eoff, |_, name| Some(format!("{prefix}_{name}")))
            .map_err(|e| FlankError::Model(format!("{}: {e}", body.name)))?;
        base[b] = nbase;
        body_of.resize(mesh.node_count(), b as u32);
        for (&n, &uv) in body.flank_uv {
            flank_uv.insert(n + nbase, uv);
        }
    }
    let ne = mesh.elements.len();
    let mut element_material = vec![0; pm.elements.len()];
    element_material.resize(ne, 1);
    let mut model = Model {
        mesh,
        materials: vec![
            pinion.model.materials[0].clone(),
            gear.model.materials[0].clone(),
        ],
        element_material,
        ..Default::default()
    };
    // gear hub clamped (the gear body's own BORE conditions), pinion hub coupled
    for d in &gear.model.dirichlet {
        model.dirichlet.push(Dirichlet {
            node: d.node + base[1],
            ..*d
        });
    }
    let hub = ["PINION_MOUNT", "PINION_BORE"]
        .iter()
        .find_map(|set| model.mesh.node_sets.get(*set).cloned())
        .ok_or_else(|| {
            FlankError::Model("pinion: the sector mesh has no MOUNT or BORE set".into())
        })?;
    // the torque turns the pinion in its drive sense about its own axis +z
    // (spur and helical pinions: clockwise seen from +z, a moment −T)
    let sense = gears.rotation_axes()[0][2];
    if !(sense.abs() > 0.5) {
        return Err(FlankError::Model(
            "the pinion's drive rotation is not about its own axis z".into(),
        ));
    }
    model.couplings.push(RigidCoupling::rotation_about(
        "PINION_HUB",
        [0.0, 0.0, {
            let (z0, z1) = gears.pinion().blank().axial_range;
            0.5 * (z1 + z0)
        }],
        2,
        hub,
        torque * sense.signum(),
    ));
    // contact: right flanks, pinion tooth k against gear tooth n + 1 − k
    let mut contact = ContactDefinition {
        interactions: vec![SurfaceInteraction {
            name: "TOOTH_CONTACT".into(),
            behavior: Some(law),
            friction: None,
        }],
        ..Default::default()
    };
    let mut contact_nodes = Vec::new();
    let mut teeth = Vec::new();
    let mut pairings = Vec::new();
    for k in 1..=gears.sector_teeth() {
        let mate = gears.mate(k);
        let mut names = Vec::new();
        for (body, tooth) in [("PINION", k), ("GEAR", mate)] {
            let set = format!("{body}_FLANK_R{tooth}");
            let nodes = model.mesh.node_sets.get(&set).cloned().ok_or_else(|| {
                FlankError::Model(format!("the pair model has no node set {set}"))
            })?;
            let faces = faces_on_nodes(&model.mesh, &nodes);
            if faces.is_empty() {
                return Err(FlankError::Model(format!(
                    "node set {set} is on no element face"
                )));
            }
            contact_nodes.extend(&nodes);
            let name = format!("{body}_R{tooth}");
            contact.surfaces.push(Surface {
                name: name.clone(),
                kind: SurfaceKind::Element(faces),
            });
            names.push(name);
        }
        let mut pairing = [None, None];
        for (side, body) in [(0, SlaveBody::Pinion), (1, SlaveBody::Gear)] {
            if slave != SlaveBody::Auto && slave != body {
                continue;
            }
            pairing[side] = Some(contact.pairs.len());
            contact.pairs.push(ContactPair {
                interaction: "TOOTH_CONTACT".into(),
                slave: names[side].clone(),
                master: names[1 - side].clone(),
                small_sliding: true,
            });
        }
        pairings.push(pairing);
        teeth.push((k, mate));
    }
    contact_nodes.sort_unstable();
    contact_nodes.dedup();
    model.contact = contact;
    Ok(PairModel {
        body_of,
        contact_nodes,
        teeth,
        pairings,
        flank_uv,
        nodes: [pm.node_count(), gm.node_count()],
        elements: [pm.elements.len(), gm.elements.len()],
        model,
    })
}

/// Makes the pair model's normal law a linear penalty of `factor` × the
/// automatic slope of its first pair's master faces
/// ([`crate::contact::pairing::default_penalty_slope`]); returns that
/// slope (MPa/mm).
pub fn set_automatic_penalty(pair: &mut PairModel, factor: f64) -> Result<f64, FlankError> {
    if !(factor > 0.0 && factor.is_finite()) {
        return Err(FlankError::Model(format!(
            "penalty factor {factor} must be positive"
        )));
    }
    let contact = &pair.model.contact;
    let pair0 = contact
        .pairs
        .first()
        .ok_or_else(|| FlankError::Model("the pair model has no contact pair".into()))?;
    let master = contact
        .surface(&pair0.master)
        .ok_or_else(|| FlankError::Model("the pair model has no master surface".into()))?;
    let faces = crate::contact::surface::surface_faces(&pair.model.mesh, master, &mut None);
    let (slope, _) = crate::contact::pairing::default_penalty_slope(&pair.model, &faces);
    let slope = slope * factor;
    pair.model.contact.interactions[0].behavior = Some(PressureOverclosure::Linear {
        slope: Some(slope),
        tension: None,
        c0: None,
    });
    Ok(slope)
}
