//! Node-to-surface pairing: for every slave node, the master face it can
//! touch, the closest point on it, the normal and the initial gap; the
//! linearized gap as a linear form of the nodal displacements.
//!
//! Small sliding, linear kinematics: the pairing (face, ξ, normal n) is made
//! once in the configuration given by `coords`, and the gap of slave node s
//! paired with face points ξ is
//!
//! ```text
//!   g = g₀ + n·(u_s − Σ_k N_k(ξ) u_k)          (k: master face nodes)
//! ```
//!
//! with g₀ = n·(x_s − x(ξ)) > 0 for an open gap. The contact force λ ≥ 0 acts
//! as +λn on the slave node and −λN_k n on the master nodes.
//!
//! Candidates: slave nodes whose projection lies on a master face (within
//! [`EDGE_TOLERANCE`] in parameter space beyond its edge) and whose initial
//! gap is at most the search distance. A slave node whose slave-side normal
//! points the same way as the master normal (the back of a face) is not
//! paired with that face. An initial penetration deeper than the sanity
//! limit (by default the size of the master face) is an error: such bodies
//! are misplaced, not in contact.

use crate::contact::definition::{PressureOverclosure, SurfaceKind};
use crate::contact::placement::Placement;
use crate::contact::projection::{project, INSIDE_TOLERANCE};
use crate::contact::search::FaceGrid;
use crate::contact::surface::{dot, face_area, nodal_areas, norm, surface_faces, Face};
use crate::error::FlankError;
use crate::fem::element::{gradients, ReferenceElement};
use crate::fem::model::Model;

/// How far (in face parameters) beyond a master face's edge a projection is
/// still accepted when no face contains it (nodes on the surface's rim).
pub const EDGE_TOLERANCE: f64 = 0.02;
/// Factor of the automatic penalty slope on the underlying element stiffness.
pub const DEFAULT_PENALTY_FACTOR: f64 = 10.0;

/// Options of the pairing.
#[derive(Clone, Debug, Default)]
pub struct PairingOptions {
    /// Largest initial gap (mm) of a candidate; default: 10 % of the master
    /// surface's bounding-box diagonal.
    pub search_distance: Option<f64>,
    /// Deepest initial penetration (mm) accepted; default: the size (√area)
    /// of the master face the slave node projects onto.
    pub max_initial_penetration: Option<f64>,
}

/// The normal law of a pair, resolved.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub enum NormalLaw {
    /// Exact non-penetration (Lagrange multipliers).
    Hard,
    /// Spring slope × area per slave node (MPa/mm); `automatic` if flank
    /// chose the slope.
    Penalty { slope: f64, automatic: bool },
}

/// One candidate contact constraint.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactConstraint {
    /// Contact pair (index into the model's pairs).
    pub pair: usize,
    pub slave: usize,
    /// Master face (index into [`PairGeometry::master_faces`]).
    pub face: usize,
    pub xi: [f64; 2],
    /// Unit normal of the master surface (outward of the master body).
    pub normal: [f64; 3],
    /// Initial gap g₀ (mm); negative: initial penetration.
    pub g0: f64,
    /// Tributary area of the slave node (mm²).
    pub area: f64,
    /// g = g₀ + Σ cᵀ u_node over these (node, c) terms.
    pub terms: Vec<(usize, [f64; 3])>,
    /// Two unit tangents of the master surface at the projection point,
    /// orthonormal with `normal` (t₁ along ∂x/∂ξ₁ of the master face,
    /// t₂ = n × t₁).
    pub tangents: [[f64; 3]; 2],
    /// Linear forms of the tangential relative displacements
    /// sₐ = tₐ·(u_s − Σ_k N_k(ξ) u_k), a = 1, 2 (the total slip of the slave
    /// node against its master point, small sliding), in the same (node, c)
    /// form as `terms`. Empty for a frictionless pair (μ = 0): friction
    /// terms are then left out entirely.
    pub tangent_terms: [Vec<(usize, [f64; 3])>; 2],
}

/// The geometry of one contact pair.
#[derive(Clone, Debug)]
pub struct PairGeometry {
    pub pair: usize,
    pub slave_name: String,
    pub master_name: String,
    pub law: NormalLaw,
    /// Friction coefficient (0: frictionless).
    pub mu: f64,
    /// Stick slope of the friction law (MPa/mm, tangential traction per
    /// slip: CalculiX's *FRICTION second value, force/volume); each slave
    /// node is a tangential spring of stiffness slope × its tributary area.
    /// `None`: hard stick (no slip while sticking).
    pub stick_slope: Option<f64>,
    pub slave_nodes: Vec<usize>,
    /// Faces of the slave surface (for node surfaces: the skin faces whose
    /// nodes all belong to it; may be empty).
    pub slave_faces: Vec<Face>,
    pub master_faces: Vec<Face>,
    /// Candidate constraints (one per paired slave node).
    pub constraints: Vec<ContactConstraint>,
    /// Slave nodes with no master face within reach.
    pub unpaired: Vec<usize>,
    pub search_distance: f64,
    /// Projections whose Newton iteration did not converge (skipped faces).
    pub failed_projections: usize,
    /// Median underlying element size h = V/A of the master faces used.
    pub element_size: f64,
}

/// Two unit tangents orthonormal with the unit normal `n` at a face point:
/// t₁ = ∂x/∂ξ₁ (from the shape derivatives `d`) with its normal part
/// removed, t₂ = n × t₁. Falls back to ∂x/∂ξ₂, then to any vector
/// orthogonal to n, if ∂x/∂ξ₁ is degenerate.
pub fn tangent_pair(face: &[[f64; 3]], d: &[[f64; 2]], n: [f64; 3]) -> [[f64; 3]; 2] {
    let along = |k: usize| {
        let mut a = [0.0; 3];
        for (x, dk) in face.iter().zip(d) {
            for c in 0..3 {
                a[c] += dk[k] * x[c];
            }
        }
        let an = dot(a, n);
        [a[0] - an * n[0], a[1] - an * n[1], a[2] - an * n[2]]
    };
    let mut t = along(0);
    if norm(t) <= 1e-12 * norm(along(1)).max(f64::MIN_POSITIVE) {
        t = along(1);
    }
    if !(norm(t) > 0.0) {
        // any direction orthogonal to n
        let e = if n[0].abs() < 0.9 {
            [1.0, 0.0, 0.0]
        } else {
            [0.0, 1.0, 0.0]
        };
        let en = dot(e, n);
        t = [e[0] - en * n[0], e[1] - en * n[1], e[2] - en * n[2]];
    }
    let l = norm(t);
    let t1 = [t[0] / l, t[1] / l, t[2] / l];
    let t2 = crate::contact::surface::cross(n, t1);
    [t1, t2]
}

/// Constrained (oedometric) modulus E(1−ν)/((1+ν)(1−2ν)) of element `e`.
fn constrained_modulus(model: &Model, e: usize) -> f64 {
    let m = &model.materials[model.element_material[e]];
    let (e_, nu) = (m.young, m.poisson);
    e_ * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu))
}

/// Element volume.
fn element_volume(model: &Model, e: usize) -> f64 {
    let el = &model.mesh.elements[e];
    let re = ReferenceElement::get(el.kind);
    let (mut g, mut d) = (Vec::new(), Vec::new());
    match gradients(re, &model.mesh.element_coords(e), &mut g, &mut d) {
        Ok(()) => d.iter().sum(),
        Err(_) => 0.0,
    }
}

/// The automatic penalty slope of a set of master faces:
/// [`DEFAULT_PENALTY_FACTOR`] × median over the faces of M/h, with M the
/// constrained modulus of the face's element and h = V/A its depth under the
/// face (the normal stiffness per unit area of the underlying element).
/// Returns (slope, median h).
pub fn default_penalty_slope(model: &Model, faces: &[Face]) -> (f64, f64) {
    let mut k: Vec<(f64, f64)> = faces
        .iter()
        .filter_map(|f| {
            let a = face_area(&f.coords(&model.mesh.coords));
            let v = element_volume(model, f.element);
            (a > 0.0 && v > 0.0).then(|| {
                let h = v / a;
                (constrained_modulus(model, f.element) / h, h)
            })
        })
        .collect();
    if k.is_empty() {
        return (f64::NAN, f64::NAN);
    }
    k.sort_by(|a, b| a.0.partial_cmp(&b.0).unwrap_or(std::cmp::Ordering::Equal));
    let mid = k[k.len() / 2];
    (DEFAULT_PENALTY_FACTOR * mid.0, mid.1)
}

/// [`build_pair`] for bodies placed rigidly ([`Placement`]): the pairing is
/// made in the global positions, and each term of a gap's linear form is
/// rotated into its node's own frame (n·u_global = (Rᵀn)·u_own), so the
/// constraints act on the DOFs of the bodies' own-frame stiffness. Normals
/// stay global.
pub fn build_pair_placed(
    model: &Model,
    placement: &Placement,
    pair: usize,
    options: &PairingOptions,
) -> Result<PairGeometry, FlankError> {
    if placement.is_identity() {
        return build_pair(model, &model.mesh.coords, pair, options);
    }
    let coords = placement.positions(&model.mesh.coords);
    let mut g = build_pair(model, &coords, pair, options)?;
    for c in &mut g.constraints {
        for (node, v) in c
            .terms
            .iter_mut()
            .chain(c.tangent_terms.iter_mut().flatten())
        {
            *v = placement.frame(*node).rotate_back(*v);
        }
    }
    Ok(g)
}

/// Pairs the slave nodes of contact pair `pair` of `model` with its master
/// faces in the configuration `coords` (node positions, e.g. the mesh's).
pub fn build_pair(
    model: &Model,
    coords: &[[f64; 3]],
    pair: usize,
    options: &PairingOptions,
) -> Result<PairGeometry, FlankError> {
    let def = &model.contact;
    let p = def
        .pairs
        .get(pair)
        .ok_or_else(|| FlankError::Model(format!("contact pair index {pair} out of range")))?;
    let missing =
        |what: &str, name: &str| FlankError::Model(format!("{what} {name} is not defined"));
    let slave = def
        .surface(&p.slave)
        .ok_or_else(|| missing("surface", &p.slave))?;
    let master = def
        .surface(&p.master)
        .ok_or_else(|| missing("surface", &p.master))?;
    let interaction = def
        .interaction(&p.interaction)
        .ok_or_else(|| missing("surface interaction", &p.interaction))?;
    let mesh = &model.mesh;
    let nn = mesh.node_count();
    let mut skin = None;
    let slave_faces = surface_faces(mesh, slave, &mut skin);
    let master_faces = surface_faces(mesh, master, &mut skin);
    if master_faces.is_empty() {
        return Err(FlankError::Model(format!(
            "master surface {} names no element face",
            master.name
        )));
    }
    let slave_nodes: Vec<usize> = match &slave.kind {
        SurfaceKind::Element(_) => {
            let mut v: Vec<usize> = slave_faces.iter().flat_map(|f| f.nodes.clone()).collect();
            v.sort_unstable();
            v.dedup();
            v
        }
        SurfaceKind::Node(nodes) => {
            let mut v = nodes.clone();
            v.sort_unstable();
            v.dedup();
            v
        }
    };
    if slave_nodes.is_empty() {
        return Err(FlankError::Model(format!(
            "slave surface {} names no node",
            slave.name
        )));
    }
    let (area, slave_normal) = nodal_areas(coords, &slave_faces, nn);
    let law = match &interaction.behavior {
        Some(PressureOverclosure::Hard) => NormalLaw::Hard,
        Some(PressureOverclosure::Linear { slope, .. }) => match slope {
            Some(s) => NormalLaw::Penalty {
                slope: *s,
                automatic: false,
            },
            None => {
                let (s, _) = default_penalty_slope(model, &master_faces);
                NormalLaw::Penalty {
                    slope: s,
                    automatic: true,
                }
            }
        },
        None => {
            return Err(FlankError::Model(format!(
                "surface interaction {} has no *SURFACE BEHAVIOR",
                interaction.name
            )))
        }
    };
    if let NormalLaw::Penalty { slope, .. } = law {
        if !(slope > 0.0 && slope.is_finite()) {
            return Err(FlankError::Model(format!(
                "contact pair {} / {}: penalty slope {slope} is not positive",
                slave.name, master.name
            )));
        }
    }
    let mu = interaction.friction.as_ref().map_or(0.0, |f| f.mu);
    if mu < 0.0 || !mu.is_finite() {
        return Err(FlankError::Model(format!(
            "surface interaction {}: friction coefficient μ = {mu} must be ≥ 0",
            interaction.name
        )));
    }
    let face_coords: Vec<Vec<[f64; 3]>> = master_faces.iter().map(|f| f.coords(coords)).collect();
    let search_distance = match options.search_distance {
        Some(d) => d,
        None => {
            let mut lo = [f64::INFINITY; 3];
            let mut hi = [f64::NEG_INFINITY; 3];
            for x in face_coords.iter().flatten() {
                for k in 0..3 {
                    lo[k] = lo[k].min(x[k]);
                    hi[k] = hi[k].max(x[k]);
                }
            }
            0.1 * norm([hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]])
        }
    };
    if !(search_distance >= 0.0) || !search_distance.is_finite() {
        return Err(FlankError::Model(format!(
            "search distance {search_distance} must be non-negative and finite"
        )));
    }
    let face_size: Vec<f64> = face_coords.iter().map(|x| face_area(x).sqrt()).collect();
    // look far enough behind each face to see penetrations beyond the limit
    let margins: Vec<f64> = face_size
        .iter()
        .map(|&s| search_distance.max(2.0 * options.max_initial_penetration.unwrap_or(s)))
        .collect();
    let grid = FaceGrid::with_margins(&face_coords, &margins);
    let mut constraints = Vec::new();
    let mut unpaired = Vec::new();
    let mut failed = 0usize;
    let mut master_node = vec![false; nn];
    for f in &master_faces {
        for &n in &f.nodes {
            master_node[n] = true;
        }
    }
    for &s in &slave_nodes {
        if master_node[s] {
            return Err(FlankError::Model(format!(
                "node {} belongs to both the slave surface {} and the master surface {}",
                mesh.node_labels[s], slave.name, master.name
            )));
        }
        let xs = coords[s];
        let ns = slave_normal[s];
        let ns_len = norm(ns);
        // best inside projection (smallest |gap|), else the least outside one
        let mut best: Option<(usize, crate::contact::projection::Projection)> = None;
        let mut deep: Option<(usize, f64)> = None;
        for fi in grid.query(xs) {
            let pr = project(&face_coords[fi], xs);
            if pr.outside_by > EDGE_TOLERANCE {
                continue;
            }
            if !pr.converged {
                failed += 1;
                continue;
            }
            if ns_len > 0.0 && dot(ns, pr.normal) > 0.0 {
                continue; // slave face and master face look the same way
            }
            let limit = options.max_initial_penetration.unwrap_or(face_size[fi]);
            if pr.gap < -limit && pr.outside_by <= INSIDE_TOLERANCE {
                if deep.is_none_or(|d| pr.gap < d.1) {
                    deep = Some((fi, pr.gap));
                }
                continue;
            }
            if pr.gap > search_distance || pr.gap < -limit {
                continue;
            }
            let better = match &best {
                None => true,
                Some((_, b)) => {
                    let (bi, pi) = (
                        b.outside_by <= INSIDE_TOLERANCE,
                        pr.outside_by <= INSIDE_TOLERANCE,
                    );
                    if bi != pi {
                        pi
                    } else if pi {
                        pr.gap.abs() < b.gap.abs() - 1e-14 * face_size[fi]
                    } else {
                        pr.outside_by < b.outside_by
                    }
                }
            };
            if better {
                best = Some((fi, pr));
            }
        }
        match best {
            Some((fi, pr)) => {
                let shape =
                    crate::contact::surface::face_shape(master_faces[fi].nodes.len(), pr.xi);
                let n = pr.normal;
                let mut terms = vec![(s, n)];
                for (k, &m) in master_faces[fi].nodes.iter().enumerate() {
                    let c = shape.n[k];
                    if c != 0.0 {
                        terms.push((m, [-c * n[0], -c * n[1], -c * n[2]]));
                    }
                }
                let tangents = tangent_pair(&face_coords[fi], &shape.d, n);
                let tangent_terms = if mu > 0.0 {
                    tangents.map(|t| {
                        let mut v = vec![(s, t)];
                        for (k, &m) in master_faces[fi].nodes.iter().enumerate() {
                            let c = shape.n[k];
                            if c != 0.0 {
                                v.push((m, [-c * t[0], -c * t[1], -c * t[2]]));
                            }
                        }
                        v
                    })
                } else {
                    [Vec::new(), Vec::new()]
                };
                let a = if area[s] > 0.0 { area[s] } else { 1.0 };
                constraints.push(ContactConstraint {
                    pair,
                    slave: s,
                    face: fi,
                    xi: pr.xi,
                    normal: n,
                    g0: pr.gap,
                    area: a,
                    terms,
                    tangents,
                    tangent_terms,
                });
            }
            None => {
                if let Some((fi, gap)) = deep {
                    let limit = options.max_initial_penetration.unwrap_or(face_size[fi]);
                    return Err(FlankError::Model(format!(
                        "contact pair {} / {}: slave node {} penetrates master face S{} of element {} by {:.4e} mm initially, deeper than the sanity limit {:.4e} mm; the bodies are misplaced (positions, units) or the surfaces are swapped",
                        slave.name,
                        master.name,
                        mesh.node_labels[s],
                        master_faces[fi].face,
                        mesh.elements[master_faces[fi].element].label,
                        -gap,
                        limit
                    )));
                }
                unpaired.push(s);
            }
        }
    }
    let (_, h) = default_penalty_slope(model, &master_faces);
    Ok(PairGeometry {
        pair,
        slave_name: slave.name.clone(),
        master_name: master.name.clone(),
        law,
        mu,
        stick_slope: interaction.friction.as_ref().and_then(|f| f.stick_slope),
        slave_nodes,
        slave_faces,
        master_faces,
        constraints,
        unpaired,
        search_distance,
        failed_projections: failed,
        element_size: h,
    })
}
