//! The contact solve of a model: pairing → factorized stiffness →
//! condensed problem → active set → displacements, pressures, residuals.
//!
//! [`solve_contact`] is what `flank solve` runs on a deck with contact
//! pairs. Its core, [`solve_pairs`], takes an [`ElasticSystem`] (the
//! factorized stiffness) and the pair geometries separately, so a driver
//! that solves many contact configurations of the same bodies (new gaps or
//! pairings, e.g. one per roll angle) factorizes once and calls it per
//! configuration.
//!
//! Why condensed: the bodies are linear and the only nonlinearity is the
//! contact state, so the problem is reduced exactly onto the candidate
//! constraints (W = B K₀⁻¹ Bᵀ, one solve per constraint that ever becomes
//! active) and the small active-set problem is solved there; the full
//! system is solved once more at the end. Iterating on the full system
//! instead would refactorize (penalty: K + BᵀkB changes with the active
//! set) or solve a saddle-point system per active-set iteration.

use std::time::Instant;

use faer::Mat;

use crate::contact::active_set::{
    solve_active_set, ActiveSetOptions, ActiveSetSolution, Condensed, Delassus,
};
use crate::contact::friction::{
    solve_friction, FrictionOptions, FrictionProblem, FrictionSolution, FrictionStatus,
};
use crate::contact::pairing::{build_pair, NormalLaw, PairGeometry, PairingOptions};
use crate::contact::placement::Placement;
use crate::contact::surface::area_weight;
use crate::contact::surface::face_area;
use crate::contact::system::ElasticSystem;
use crate::error::FlankError;
use crate::fem::model::Model;
use crate::fem::ordering::OrderingMethod;
use crate::fem::static_analysis::{peak_memory_mb, SolveStats, StaticSolution};
use crate::fem::stress::recover;

/// How to solve a contact problem.
#[derive(Clone, Debug)]
pub struct ContactOptions {
    pub ordering: OrderingMethod,
    /// Threads (0 = all).
    pub threads: usize,
    pub recover_stress: bool,
    pub pairing: PairingOptions,
    /// Active-set iteration limit.
    pub max_iterations: usize,
    /// Penetration tolerance of hard contact (mm); default 1e-10 × the
    /// model's bounding-box diagonal.
    pub gap_tolerance: Option<f64>,
}

impl Default for ContactOptions {
    fn default() -> Self {
        ContactOptions {
            ordering: OrderingMethod::Metis,
            threads: 0,
            recover_stress: true,
            pairing: PairingOptions::default(),
            max_iterations: 500,
            gap_tolerance: None,
        }
    }
}

/// State of a slave node.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ContactStatus {
    Open,
    Closed,
}

impl ContactStatus {
    pub fn name(self) -> &'static str {
        match self {
            ContactStatus::Open => "open",
            ContactStatus::Closed => "closed",
        }
    }
}

/// Result at one paired slave node.
#[derive(Clone, Debug, serde::Serialize)]
pub struct SlaveResult {
    pub pair: usize,
    pub node: usize,
    /// Final gap (mm): g₀ + n·(u_s − u_master); negative is penetration.
    pub gap: f64,
    /// Normal contact force λ (N), ≥ 0.
    pub force: f64,
    /// Normal contact pressure (MPa): the nodal force spread over the slave
    /// faces and averaged back to the node (see [`ContactSolution`]).
    pub pressure: f64,
    /// λ / tributary area (MPa).
    pub nodal_pressure: f64,
    /// Tributary area (mm²).
    pub area: f64,
    /// Master normal (unit).
    pub normal: [f64; 3],
    pub status: ContactStatus,
    /// Friction results (pairs with μ > 0 only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub friction: Option<SlaveFriction>,
}

/// Friction results at one slave node.
#[derive(Clone, Debug, serde::Serialize)]
pub struct SlaveFriction {
    /// Tangential contact force on the slave node (N, global components).
    pub tangential_force: [f64; 3],
    /// ‖tangential force‖ / tributary area (MPa).
    pub shear: f64,
    /// Total tangential displacement of the slave node relative to its
    /// master point (mm, global components; includes the elastic stick
    /// part when a stick slope is given).
    pub slip: [f64; 3],
    pub slip_magnitude: f64,
    pub status: FrictionStatus,
}

/// Friction figures of one pair.
#[derive(Clone, Debug, serde::Serialize)]
pub struct PairFriction {
    pub mu: f64,
    pub stick_slope: Option<f64>,
    /// Σ of the tangential forces on the slave side (N) and its magnitude.
    pub tangential_resultant: [f64; 3],
    pub total_tangential_force: f64,
    pub stick: usize,
    pub slip: usize,
    pub max_shear: f64,
    pub max_slip: f64,
}

/// Figures of one contact pair.
#[derive(Clone, Debug, serde::Serialize)]
pub struct PairSummary {
    pub slave: String,
    pub master: String,
    pub law: NormalLaw,
    pub slave_nodes: usize,
    pub candidates: usize,
    pub unpaired: usize,
    pub closed: usize,
    /// Σ λ (N) and the resultant Σ λ n (N) on the slave side.
    pub total_normal_force: f64,
    pub resultant: [f64; 3],
    pub max_pressure: f64,
    pub max_nodal_pressure: f64,
    pub max_penetration: f64,
    pub search_distance: f64,
    /// Median depth V/A of the master elements (used by the default penalty).
    pub element_size: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub friction: Option<PairFriction>,
}

/// Figures of the whole contact solve (summary.json "contact").
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct ContactSummary {
    pub pairs: Vec<PairSummary>,
    pub active_set: ActiveSetSolution,
    /// Friction solve (iterations, Coulomb residual, stick/slip
    /// complementarity), when a pair has μ > 0.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub friction: Option<FrictionSolution>,
    /// Floating modes held by contact: description and amplitude.
    pub floating_modes: Vec<(String, f64)>,
    /// ‖K₀q − b‖/‖b‖ and backward error of the final full solve.
    pub relative_residual: f64,
    pub backward_error: f64,
    /// Largest pin reaction relative to the largest contact force (0 when
    /// nothing floats): how well the floating bodies are in equilibrium.
    pub pin_reaction: f64,
    pub gap_tolerance: f64,
    pub pairing_s: f64,
    pub factorization_s: f64,
    pub contact_solve_s: f64,
    pub warnings: Vec<String>,
}

/// Result of a contact solve.
#[derive(Clone, Debug)]
pub struct ContactSolution {
    pub solution: StaticSolution,
    pub slaves: Vec<SlaveResult>,
    pub summary: ContactSummary,
    /// Contact pressure at every node (0 off the slave surfaces), MPa.
    pub pressure: Vec<f64>,
    /// Contact force on every node (slave and master sides), N, node-major.
    pub force: Vec<f64>,
}

/// Solves the model's contact problem (the model must have contact pairs).
pub fn solve_contact(
    model: &Model,
    options: &ContactOptions,
) -> Result<ContactSolution, FlankError> {
    crate::fem::solver::with_threads(options.threads, || solve_contact_in_pool(model, options))
}

/// The geometry of every contact pair of the model in its mesh positions.
pub fn build_pairs(
    model: &Model,
    options: &PairingOptions,
) -> Result<Vec<PairGeometry>, FlankError> {
    model.contact.validate(&model.mesh)?;
    (0..model.contact.pairs.len())
        .map(|p| build_pair(model, &model.mesh.coords, p, options))
        .collect()
}

fn solve_contact_in_pool(
    model: &Model,
    options: &ContactOptions,
) -> Result<ContactSolution, FlankError> {
    let t_total = Instant::now();
    if model.contact.pairs.is_empty() {
        return Err(FlankError::Model("the model has no contact pair".into()));
    }
    crate::fem::static_analysis::validate(model)?;
    let t = Instant::now();
    let pairs = build_pairs(model, &options.pairing)?;
    let pairing_s = t.elapsed().as_secs_f64();
    let mut warnings = Vec::new();
    for g in &pairs {
        if g.constraints.is_empty() {
            warnings.push(format!(
                "contact pair {} / {}: no slave node lies within the search distance {:.4e} mm of the master surface: the bodies do not touch",
                g.slave_name, g.master_name, g.search_distance
            ));
        }
        if g.failed_projections > 0 {
            warnings.push(format!(
                "contact pair {} / {}: {} projections onto master faces did not converge within {} Newton iterations (those faces were skipped)",
                g.slave_name,
                g.master_name,
                g.failed_projections,
                crate::contact::projection::MAX_NEWTON
            ));
        }
    }
    let mut contact_nodes: Vec<usize> = Vec::new();
    for g in &pairs {
        contact_nodes.extend(&g.slave_nodes);
        for f in &g.master_faces {
            contact_nodes.extend(&f.nodes);
        }
    }
    let t = Instant::now();
    let system = ElasticSystem::new(model, &contact_nodes, options.ordering, options.threads)?;
    let factorization_s = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let state = solve_pairs(model, &system, &pairs, options)?;
    let contact_solve_s = t.elapsed().as_secs_f64();
    warnings.extend(state.warnings.iter().cloned());
    let nn = model.mesh.node_count();

    // contact forces on the nodes, pressures
    let mut force = vec![0.0; 3 * nn];
    for (c, &l) in state.constraints.iter().zip(&state.active_set.lambda) {
        if l != 0.0 {
            for &(node, v) in &c.terms {
                for k in 0..3 {
                    force[3 * node + k] += l * v[k];
                }
            }
        }
    }
    if let Some(fr) = &state.friction {
        for (c, lt) in state.constraints.iter().zip(&fr.lambda_t) {
            for a in 0..2 {
                if lt[a] != 0.0 {
                    for &(node, v) in &c.tangent_terms[a] {
                        for k in 0..3 {
                            force[3 * node + k] += lt[a] * v[k];
                        }
                    }
                }
            }
        }
    }
    let mut slaves = Vec::with_capacity(state.constraints.len());
    let mut pressure = vec![0.0; nn];
    let mut pair_summaries = Vec::new();
    let mut offset = 0;
    for g in &pairs {
        let k = g.constraints.len();
        let lam = &state.active_set.lambda[offset..offset + k];
        let gap = &state.active_set.gap[offset..offset + k];
        let smooth = face_averaged_pressure(model, g, lam);
        let mut summary = PairSummary {
            slave: g.slave_name.clone(),
            master: g.master_name.clone(),
            law: g.law,
            slave_nodes: g.slave_nodes.len(),
            candidates: k,
            unpaired: g.unpaired.len(),
            closed: 0,
            total_normal_force: 0.0,
            resultant: [0.0; 3],
            max_pressure: 0.0,
            max_nodal_pressure: 0.0,
            max_penetration: 0.0,
            search_distance: g.search_distance,
            element_size: g.element_size,
            friction: state.friction.as_ref().map(|_| PairFriction {
                mu: g.mu,
                stick_slope: g.stick_slope,
                tangential_resultant: [0.0; 3],
                total_tangential_force: 0.0,
                stick: 0,
                slip: 0,
                max_shear: 0.0,
                max_slip: 0.0,
            }),
        };
        for (i, c) in g.constraints.iter().enumerate() {
            let status = if lam[i] > 0.0 {
                ContactStatus::Closed
            } else {
                ContactStatus::Open
            };
            let p = smooth[i];
            let np = lam[i] / c.area;
            pressure[c.slave] = p;
            summary.closed += (status == ContactStatus::Closed) as usize;
            summary.total_normal_force += lam[i];
            for kk in 0..3 {
                summary.resultant[kk] += lam[i] * c.normal[kk];
            }
            summary.max_pressure = summary.max_pressure.max(p);
            summary.max_nodal_pressure = summary.max_nodal_pressure.max(np);
            summary.max_penetration = summary.max_penetration.max(-gap[i]);
            let friction = state.friction.as_ref().map(|fr| {
                let j = offset + i;
                let (lt, sl) = (fr.lambda_t[j], fr.slip[j]);
                let mut tf = [0.0; 3];
                let mut sv = [0.0; 3];
                for kk in 0..3 {
                    tf[kk] = lt[0] * c.tangents[0][kk] + lt[1] * c.tangents[1][kk];
                    sv[kk] = sl[0] * c.tangents[0][kk] + sl[1] * c.tangents[1][kk];
                }
                SlaveFriction {
                    tangential_force: tf,
                    shear: lt[0].hypot(lt[1]) / c.area,
                    slip: sv,
                    slip_magnitude: sl[0].hypot(sl[1]),
                    status: fr.status[j],
                }
            });
            if let (Some(pf), Some(sf)) = (summary.friction.as_mut(), friction.as_ref()) {
                for kk in 0..3 {
                    pf.tangential_resultant[kk] += sf.tangential_force[kk];
                }
                pf.stick += (sf.status == FrictionStatus::Stick) as usize;
                pf.slip += (sf.status == FrictionStatus::Slip) as usize;
                pf.max_shear = pf.max_shear.max(sf.shear);
                pf.max_slip = pf.max_slip.max(sf.slip_magnitude);
            }
            slaves.push(SlaveResult {
                pair: g.pair,
                node: c.slave,
                gap: gap[i],
                force: lam[i],
                pressure: p,
                nodal_pressure: np,
                area: c.area,
                normal: c.normal,
                status,
                friction,
            });
        }
        if k > 0 && summary.closed == 0 {
            warnings.push(format!(
                "contact pair {} / {}: no slave node came into contact ({} candidates, smallest final gap {:.4e} mm)",
                g.slave_name,
                g.master_name,
                k,
                gap.iter().copied().fold(f64::INFINITY, f64::min)
            ));
        }
        if let Some(pf) = summary.friction.as_mut() {
            let r = pf.tangential_resultant;
            pf.total_tangential_force = (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt();
        }
        pair_summaries.push(summary);
        offset += k;
    }

    // stresses and reactions (contact forces are not reactions)
    let t = Instant::now();
    let (recovery, reaction) = if options.recover_stress {
        let rec = recover(model, &state.displacement)?;
        let reaction: Vec<f64> = (0..3 * nn)
            .map(|d| rec.internal_force[d] - state.external_force[d] - force[d])
            .collect();
        (Some(rec), Some(reaction))
    } else {
        (None, None)
    };
    let recovery_s = t.elapsed().as_secs_f64();
    // pins of floating modes must carry (almost) nothing
    let mut pin_reaction = 0.0;
    if let Some(r) = &reaction {
        let fmax = state
            .active_set
            .lambda
            .iter()
            .fold(0.0f64, |a, v| a.max(v.abs()))
            .max(f64::MIN_POSITIVE);
        for pin in &system.floating.pins {
            if let crate::contact::floating::Pin::Node { node, component } = *pin {
                pin_reaction = f64::max(pin_reaction, r[3 * node + component].abs() / fmax);
            }
        }
    }
    let mut stats = SolveStats {
        nodes: nn,
        elements: model.mesh.elements.len(),
        dofs: system.stats.dofs,
        nnz_factor: system.stats.nnz_factor,
        ordering: system.stats.ordering.clone(),
        precision: "double".into(),
        threads: crate::fem::solver::parallelism(options.threads).degree(),
        assembly_s: system.stats.assembly_s,
        factorization_s: system.stats.factorization_s,
        solve_s: contact_solve_s,
        recovery_s,
        relative_residual: state.relative_residual,
        backward_error: state.backward_error,
        ..Default::default()
    };
    stats.total_s = t_total.elapsed().as_secs_f64();
    stats.peak_memory_mb = peak_memory_mb();
    let summary = ContactSummary {
        pairs: pair_summaries,
        active_set: state.active_set.clone(),
        friction: state.friction.clone(),
        floating_modes: system
            .floating
            .modes
            .iter()
            .zip(&state.active_set.alpha)
            .map(|(m, a)| {
                (
                    format!("body of node {}: {}", m.body_node, m.description),
                    *a,
                )
            })
            .collect(),
        relative_residual: state.relative_residual,
        backward_error: state.backward_error,
        pin_reaction,
        gap_tolerance: state.gap_tolerance,
        pairing_s,
        factorization_s,
        contact_solve_s,
        warnings,
    };
    Ok(ContactSolution {
        solution: StaticSolution {
            displacement: state.displacement,
            reaction,
            recovery,
            coupling_motion: state.coupling_motion,
            stats,
        },
        slaves,
        summary,
        pressure,
        force,
    })
}

/// Pressure at the paired slave nodes of a pair (`lambda`: the normal
/// force of each of `g.constraints`): each node's force is
/// shared among its slave faces in proportion to its lumped area on each,
/// every face gets the mean pressure (its force / its area), and the node
/// takes the area-weighted mean of its faces. A uniform pressure is
/// reproduced exactly; the quadratic faces' corner/midside imbalance of the
/// nodal forces (corner nodes of 8-node faces carry little or nothing) is
/// averaged out. Without slave faces (a node surface with no face) it is
/// λ/area.
pub fn face_averaged_pressure(model: &Model, g: &PairGeometry, lambda: &[f64]) -> Vec<f64> {
    let nn = model.mesh.node_count();
    let mut node_force = vec![0.0; nn];
    let mut index = vec![usize::MAX; nn];
    for (i, c) in g.constraints.iter().enumerate() {
        node_force[c.slave] = lambda[i];
        index[c.slave] = i;
    }
    if g.slave_faces.is_empty() {
        return g
            .constraints
            .iter()
            .zip(lambda)
            .map(|(c, l)| l / c.area)
            .collect();
    }
    let coords = &model.mesh.coords;
    let areas: Vec<f64> = g
        .slave_faces
        .iter()
        .map(|f| face_area(&f.coords(coords)))
        .collect();
    let mut node_area = vec![0.0; nn];
    for (f, &a) in g.slave_faces.iter().zip(&areas) {
        for (k, &n) in f.nodes.iter().enumerate() {
            node_area[n] += area_weight(f.nodes.len(), k) * a;
        }
    }
    let mut acc = vec![0.0; nn];
    for (f, &a) in g.slave_faces.iter().zip(&areas) {
        if a <= 0.0 {
            continue;
        }
        let mut face_force = 0.0;
        for (k, &n) in f.nodes.iter().enumerate() {
            if node_area[n] > 0.0 {
                face_force += node_force[n] * area_weight(f.nodes.len(), k) * a / node_area[n];
            }
        }
        let p = face_force / a;
        for (k, &n) in f.nodes.iter().enumerate() {
            acc[n] += p * area_weight(f.nodes.len(), k) * a;
        }
    }
    g.constraints
        .iter()
        .zip(lambda)
        .map(|(c, l)| {
            if node_area[c.slave] > 0.0 && index[c.slave] != usize::MAX {
                acc[c.slave] / node_area[c.slave]
            } else {
                l / c.area
            }
        })
        .collect()
}

/// The solved contact state of a set of pairs.
#[derive(Clone, Debug)]
pub struct ContactState {
    /// All candidate constraints in pair order.
    pub constraints: Vec<crate::contact::pairing::ContactConstraint>,
    /// Normal contact (with friction: the normal part of the frictional
    /// answer; its `iterations` are those of the frictionless start).
    pub active_set: ActiveSetSolution,
    /// Tangential forces, slips and states when a pair has μ > 0.
    pub friction: Option<FrictionSolution>,
    /// Full displacement (with prescribed values and floating motions).
    pub displacement: Vec<f64>,
    pub coupling_motion: Vec<[f64; 6]>,
    /// External load vector (full DOFs).
    pub external_force: Vec<f64>,
    pub relative_residual: f64,
    pub backward_error: f64,
    pub gap_tolerance: f64,
    pub warnings: Vec<String>,
    /// Slave nodes that were not candidates but penetrate after the solve
    /// (the search distance was too small; see the warnings).
    pub uncovered: usize,
}

/// Columns of W = B K₀⁻¹ Bᵀ by solves with the factorized stiffness.
///
/// The right-hand sides Bⱼᵀ are non-zero only at the DOFs of constraint j
/// and only the rows of K₀⁻¹Bⱼᵀ at the candidates' DOFs are needed: with a
/// supernodal factor the substitutions are restricted to the reach of those
/// DOFs in the elimination tree (computed once per set of pairs), exact
/// like the full ones; a simplicial factor (small models) solves in full.
struct SystemDelassus<'a> {
    system: &'a ElasticSystem,
    forms: &'a [Vec<(usize, f64)>],
    /// The reach of all candidates' DOFs and the forms in its rows.
    restricted: Option<RestrictedForms>,
}

/// A reach and the constraint forms with their DOFs as rows of it.
type RestrictedForms = (crate::fem::solver::SolveReach, Vec<Vec<(usize, f64)>>);

/// Right-hand sides solved together.
const BLOCK: usize = 32;

impl<'a> SystemDelassus<'a> {
    fn new(system: &'a ElasticSystem, forms: &'a [Vec<(usize, f64)>]) -> Self {
        let dofs: Vec<usize> = forms.iter().flatten().map(|&(r, _)| r).collect();
        let restricted = system.solve_reach(&dofs).map(|reach| {
            let local = forms
                .iter()
                .map(|f| {
                    f.iter()
                        .map(|&(r, v)| (reach.local(r).expect("a form's DOF in its reach"), v))
                        .collect()
                })
                .collect();
            (reach, local)
        });
        SystemDelassus {
            system,
            forms,
            restricted,
        }
    }
}

impl Delassus for SystemDelassus<'_> {
    fn block_size(&self) -> usize {
        BLOCK
    }

    fn columns(&mut self, cols: &[usize]) -> Result<Vec<Vec<f64>>, FlankError> {
        let n = self.system.reduced_count();
        let mut out = Vec::with_capacity(cols.len());
        for chunk in cols.chunks(BLOCK) {
            if let Some((reach, local)) = &self.restricted {
                let rhs: Vec<&[(usize, f64)]> = chunk.iter().map(|&j| &self.forms[j][..]).collect();
                let x = self.system.solve_restricted(reach, &rhs);
                for k in 0..chunk.len() {
                    let col = x.col(k);
                    out.push(
                        local
                            .iter()
                            .map(|f| f.iter().map(|&(r, v)| v * col[r]).sum())
                            .collect(),
                    );
                }
                continue;
            }
            let mut x = Mat::<f64>::zeros(n, chunk.len());
            for (k, &j) in chunk.iter().enumerate() {
                for &(r, v) in &self.forms[j] {
                    x[(r, k)] += v;
                }
            }
            self.system.solve_columns(x.as_mut());
            for k in 0..chunk.len() {
                let col = x.col(k);
                out.push(
                    self.forms
                        .iter()
                        .map(|f| f.iter().map(|&(r, v)| v * col[r]).sum())
                        .collect(),
                );
            }
        }
        Ok(out)
    }
}

/// Solves the contact problem of `pairs` with the factorized `system` of
/// `model` (whose loads and prescribed displacements act).
pub fn solve_pairs(
    model: &Model,
    system: &ElasticSystem,
    pairs: &[PairGeometry],
    options: &ContactOptions,
) -> Result<ContactState, FlankError> {
    solve_pairs_placed(model, system, pairs, &Placement::identity(), options)
}

/// [`solve_pairs`] for bodies placed rigidly (pairs from
/// [`crate::contact::pairing::build_pair_placed`] with the same
/// `placement`); displacements stay in the bodies' own frames.
pub fn solve_pairs_placed(
    model: &Model,
    system: &ElasticSystem,
    pairs: &[PairGeometry],
    placement: &Placement,
    options: &ContactOptions,
) -> Result<ContactState, FlankError> {
    let constraints: Vec<_> = pairs
        .iter()
        .flat_map(|g| g.constraints.iter().cloned())
        .collect();
    let mut compliance = Vec::with_capacity(constraints.len());
    for g in pairs {
        for c in &g.constraints {
            compliance.push(match g.law {
                NormalLaw::Hard => 0.0,
                NormalLaw::Penalty { slope, .. } => 1.0 / (slope * c.area),
            });
        }
    }
    let forms: Vec<Vec<(usize, f64)>> = constraints
        .iter()
        .map(|c| system.reduced_form(&c.terms))
        .collect();
    // response to the external loads
    let ext = system.external_response(model)?;
    let (b_ext, f_full, u_ext) = (ext.rhs.clone(), ext.load.clone(), &ext.displacement);
    let gap_of = |c: &crate::contact::pairing::ContactConstraint, u: &[f64]| -> f64 {
        c.terms
            .iter()
            .map(|&(n, v)| v[0] * u[3 * n] + v[1] * u[3 * n + 1] + v[2] * u[3 * n + 2])
            .sum()
    };
    let q: Vec<f64> = constraints
        .iter()
        .map(|c| c.g0 + gap_of(c, u_ext))
        .collect();
    let fm = &system.floating;
    let d: Vec<Vec<f64>> = fm
        .modes
        .iter()
        .map(|m| {
            constraints
                .iter()
                .map(|c| gap_of(c, &m.displacement))
                .collect()
        })
        .collect();
    let r: Vec<f64> = (0..fm.modes.len())
        .map(|k| -fm.work(model, k, &f_full))
        .collect();
    let gap_tolerance = options.gap_tolerance.unwrap_or_else(|| {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for x in &model.mesh.coords {
            for k in 0..3 {
                lo[k] = lo[k].min(x[k]);
                hi[k] = hi[k].max(x[k]);
            }
        }
        1e-10 * ((hi[0] - lo[0]).powi(2) + (hi[1] - lo[1]).powi(2) + (hi[2] - lo[2]).powi(2)).sqrt()
    });
    let mut warnings = Vec::new();
    let prob = Condensed {
        q,
        compliance,
        d,
        r,
    };
    let frictional = pairs.iter().any(|g| g.mu > 0.0);
    let mut friction = None;
    let mut tangent_forms: Vec<[Vec<(usize, f64)>; 2]> = Vec::new();
    let active_set = if constraints.is_empty() && fm.modes.is_empty() {
        ActiveSetSolution::default()
    } else if !frictional {
        let mut w = SystemDelassus::new(system, &forms);
        solve_active_set(
            &mut w,
            &prob,
            &ActiveSetOptions {
                max_iterations: options.max_iterations,
                gap_tolerance,
            },
        )?
    } else {
        // Coulomb friction: normal and two tangential rows per candidate
        tangent_forms = constraints
            .iter()
            .map(|c| c.tangent_terms.clone().map(|t| system.reduced_form(&t)))
            .collect();
        let mut forms3 = Vec::with_capacity(3 * constraints.len());
        for (f, t) in forms.iter().zip(&tangent_forms) {
            forms3.push(f.clone());
            forms3.push(t[0].clone());
            forms3.push(t[1].clone());
        }
        let slip_of = |c: &crate::contact::pairing::ContactConstraint, u: &[f64]| -> [f64; 2] {
            c.tangent_terms.clone().map(|t| {
                t.iter()
                    .map(|&(n, v)| v[0] * u[3 * n] + v[1] * u[3 * n + 1] + v[2] * u[3 * n + 2])
                    .sum()
            })
        };
        let mut mu = Vec::with_capacity(constraints.len());
        let mut stick_compliance = Vec::with_capacity(constraints.len());
        for g in pairs {
            for c in &g.constraints {
                mu.push(g.mu);
                stick_compliance.push(match g.stick_slope {
                    Some(k) if g.mu > 0.0 => 1.0 / (k * c.area),
                    _ => 0.0,
                });
            }
        }
        let mut inert = vec![false; 3 * constraints.len()];
        for (i, t) in tangent_forms.iter().enumerate() {
            for a in 0..2 {
                inert[3 * i + 1 + a] = t[a].iter().all(|e| e.1 == 0.0)
                    && fm.modes.iter().all(|m| {
                        constraints[i].tangent_terms[a].iter().all(|&(nd, v)| {
                            (0..3).all(|k| v[k] * m.displacement[3 * nd + k] == 0.0)
                        })
                    });
            }
        }
        let fprob = FrictionProblem {
            inert,
            qt: constraints.iter().map(|c| slip_of(c, u_ext)).collect(),
            dt: fm
                .modes
                .iter()
                .map(|m| {
                    constraints
                        .iter()
                        .map(|c| slip_of(c, &m.displacement))
                        .collect()
                })
                .collect(),
            normal: prob.clone(),
            mu,
            stick_compliance,
        };
        let mut w = SystemDelassus::new(system, &forms3);
        let (fr, normal) = solve_friction(
            &mut w,
            &fprob,
            &FrictionOptions {
                active_set: ActiveSetOptions {
                    max_iterations: options.max_iterations,
                    gap_tolerance,
                },
                ..Default::default()
            },
        )?;
        warnings.extend(fr.warnings.iter().cloned());
        friction = Some(fr);
        normal
    };
    // final solve with the contact forces
    let mut b = b_ext;
    for (form, &l) in forms.iter().zip(&active_set.lambda) {
        if l != 0.0 {
            for &(rr, v) in form {
                b[rr] += l * v;
            }
        }
    }
    if let Some(fr) = &friction {
        for (tf, lt) in tangent_forms.iter().zip(&fr.lambda_t) {
            for a in 0..2 {
                if lt[a] != 0.0 {
                    for &(rr, v) in &tf[a] {
                        b[rr] += lt[a] * v;
                    }
                }
            }
        }
    }
    let mut qsol = b.clone();
    system.solve(&mut qsol);
    let (relative_residual, backward_error) = system.residual(&qsol, &b);
    if !(backward_error <= 1e-10) {
        return Err(FlankError::Solver(format!(
            "backward error {backward_error:.2e} of the final solve: the factorization is not trustworthy"
        )));
    }
    let mut displacement = system.expand(&qsol);
    let mut coupling_motion = system.coupling_motion(&qsol);
    for (m, &a) in fm.modes.iter().zip(&active_set.alpha) {
        for (u, v) in displacement.iter_mut().zip(&m.displacement) {
            *u += a * v;
        }
        for &(c, k, v) in &m.reference {
            coupling_motion[c][k] += a * v;
        }
    }
    if displacement.iter().any(|v| !v.is_finite()) {
        return Err(FlankError::Solver(
            "the contact solution contains non-finite values".into(),
        ));
    }
    // slave nodes that were not candidates but penetrate in the deformed
    // configuration: the search distance was too small
    let mut uncovered = 0;
    for g in pairs {
        let (count, depth) =
            uncovered_penetration(model, g, placement, &displacement, gap_tolerance);
        uncovered += count;
        if count > 0 {
            warnings.push(format!(
                "contact pair {} / {}: {count} slave node(s) outside the candidate set penetrate the master surface after the solve (deepest {depth:.3e} mm); increase the search distance",
                g.slave_name, g.master_name
            ));
        }
    }
    if active_set.iterations > 0 && active_set.max_violation > gap_tolerance * 10.0 {
        warnings.push(format!(
            "contact law violated by {:.3e} mm after the active set (tolerance {:.3e} mm)",
            active_set.max_violation, gap_tolerance
        ));
    }
    Ok(ContactState {
        constraints,
        active_set,
        friction,
        displacement,
        coupling_motion,
        external_force: f_full,
        relative_residual,
        backward_error,
        gap_tolerance,
        warnings,
        uncovered,
    })
}

/// Slave nodes of `g` that were not paired but, in the deformed
/// configuration, lie behind a master face: their count and deepest gap.
fn uncovered_penetration(
    model: &Model,
    g: &PairGeometry,
    placement: &Placement,
    u: &[f64],
    tol: f64,
) -> (usize, f64) {
    if g.unpaired.is_empty() {
        return (0, 0.0);
    }
    let moved = |n: usize| placement.displaced(&model.mesh.coords, u, n);
    let faces: Vec<Vec<[f64; 3]>> = g
        .master_faces
        .iter()
        .map(|f| f.nodes.iter().map(|&n| moved(n)).collect())
        .collect();
    let grid = crate::contact::search::FaceGrid::new(&faces, 0.0);
    let mut count = 0;
    let mut depth = 0.0f64;
    for &s in &g.unpaired {
        let p = moved(s);
        let mut deepest: Option<f64> = None;
        for fi in grid.query(p) {
            let pr = crate::contact::projection::project(&faces[fi], p);
            if pr.converged && pr.outside_by <= crate::contact::projection::INSIDE_TOLERANCE {
                let size = face_area(&faces[fi]).sqrt();
                if pr.gap < -tol && pr.gap > -size {
                    deepest = Some(deepest.map_or(pr.gap, |d: f64| d.min(pr.gap)));
                }
            }
        }
        if let Some(d) = deepest {
            count += 1;
            depth = depth.max(-d);
        }
    }
    (count, depth)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::{
        ContactDefinition, ContactPair, PressureOverclosure, Surface, SurfaceInteraction,
        SurfaceKind,
    };
    use crate::fem::material::Material;
    use crate::fem::mesh::{Mesh, SetKind};
    use crate::fem::model::Dirichlet;
    use crate::mesh::structured::{box_faces, box_mesh, BoxElement};

    /// Two blocks L × L × H stacked in z, `n_low` and `n_up` cells across,
    /// the upper one pressed down by δ on its top; statically determinate
    /// lateral supports, frictionless contact of the upper block's bottom
    /// (slave) on the lower block's top (master). Uniaxial stress: the
    /// exact total force is E δ L² / (2H).
    fn blocks(
        kind: BoxElement,
        n_low: usize,
        n_up: usize,
        law: PressureOverclosure,
    ) -> (Model, f64) {
        let (l, h, delta, e) = (2.0, 1.0, 1e-3, 210e3);
        let low = box_mesh([l, l, h], [n_low, n_low, 1], kind);
        let mut up = box_mesh([l, l, h], [n_up, n_up, 1], kind);
        for x in up.coords.iter_mut() {
            x[2] += h;
        }
        let mut mesh = Mesh::new();
        let mut faces = Vec::new();
        for (b, src) in [&low, &up].into_iter().enumerate() {
            // labels + 10 000 b; node sets B0_Z0, B1_Z1, ..., no element sets
            let offset = 10_000 * b as u64;
            let (_, ebase) = mesh
                .append(src, offset, offset, |kind, name| {
                    (kind == SetKind::Node).then(|| format!("B{b}_{name}"))
                })
                .unwrap();
            let set = if b == 0 { "Z1" } else { "Z0" };
            faces.push(
                box_faces(src, set)
                    .into_iter()
                    .map(|(el, f)| (el + ebase, f))
                    .collect::<Vec<_>>(),
            );
        }
        let ne = mesh.elements.len();
        let mut model = Model {
            mesh,
            materials: vec![Material::new("steel", e, 0.3).unwrap()],
            element_material: vec![0; ne],
            ..Default::default()
        };
        let at = |m: &Model, p: [f64; 3]| {
            (0..m.mesh.node_count())
                .find(|&n| (0..3).all(|k| (m.mesh.coords[n][k] - p[k]).abs() < 1e-12))
                .unwrap()
        };
        let push = |m: &mut Model, node: usize, component: usize, value: f64| {
            m.dirichlet.push(Dirichlet {
                node,
                component,
                value,
            })
        };
        for n in model.mesh.node_sets["B0_Z0"].clone() {
            push(&mut model, n, 2, 0.0);
        }
        for n in model.mesh.node_sets["B1_Z1"].clone() {
            push(&mut model, n, 2, -delta);
        }
        for z in [0.0, 2.0 * h] {
            let a = at(&model, [0.0, 0.0, z]);
            let b = at(&model, [l, 0.0, z]);
            push(&mut model, a, 0, 0.0);
            push(&mut model, a, 1, 0.0);
            push(&mut model, b, 1, 0.0);
        }
        model.contact = ContactDefinition {
            surfaces: vec![
                Surface {
                    name: "UP".into(),
                    kind: SurfaceKind::Element(faces[1].clone()),
                },
                Surface {
                    name: "LOW".into(),
                    kind: SurfaceKind::Element(faces[0].clone()),
                },
            ],
            interactions: vec![SurfaceInteraction {
                name: "I".into(),
                behavior: Some(law),
                friction: None,
            }],
            pairs: vec![ContactPair {
                interaction: "I".into(),
                slave: "UP".into(),
                master: "LOW".into(),
                small_sliding: true,
            }],
        };
        (model, e * delta * l * l / (2.0 * h))
    }

    /// The contact patch test: tri6 slave faces on a matching mesh give the
    /// uniform pressure exactly; non-matching meshes and 8-node slave faces
    /// (whose corner nodes would have to pull, so they open) are close and
    /// converge with the mesh.
    #[test]
    fn pressed_blocks_carry_the_uniaxial_force() {
        let mut hex = Vec::new();
        for (kind, n_low, n_up, tol) in [
            (BoxElement::Wedge15, 2, 2, 1e-12),
            (BoxElement::Wedge15, 2, 3, 1e-2),
            (BoxElement::Hex20, 2, 2, 8e-2),
            (BoxElement::Hex20, 2, 3, 3e-2),
            (BoxElement::Hex20, 4, 4, 3e-2),
            (BoxElement::Hex20, 8, 8, 1e-2),
            (BoxElement::Hex20R, 4, 4, 3e-2),
        ] {
            let (model, exact) = blocks(kind, n_low, n_up, PressureOverclosure::Hard);
            let sol = solve_contact(&model, &ContactOptions::default()).unwrap();
            let f = sol.summary.pairs[0].total_normal_force;
            let pmax = sol.summary.pairs[0].max_pressure;
            let pmin = sol
                .slaves
                .iter()
                .fold(f64::INFINITY, |a, s| a.min(s.pressure));
            let err = f / exact - 1.0;
            println!(
                "{kind:?} {n_low}/{n_up}: force {f:.9} exact {exact:.9} rel {err:.2e}; pressure {pmin:.6}..{pmax:.6} (exact {:.6})",
                exact / 4.0
            );
            assert!(err.abs() <= tol, "{kind:?} {n_low}/{n_up}: {err:.3e}");
            assert!(
                err <= 1e-12,
                "node-to-surface contact is never stiffer than exact"
            );
            let a = &sol.summary.active_set;
            assert!(a.max_violation < 1e-12 && a.complementarity < 1e-9);
            if kind == BoxElement::Hex20 && n_low == n_up {
                hex.push(err.abs());
            }
        }
        assert!(hex.windows(2).all(|w| w[1] < 0.5 * w[0]), "{hex:?}");
        // the same with a penalty: converges to the hard answer
        let (model, _) = blocks(BoxElement::Wedge15, 2, 2, PressureOverclosure::Hard);
        let hard = solve_contact(&model, &ContactOptions::default()).unwrap();
        let (model, _) = blocks(
            BoxElement::Wedge15,
            2,
            2,
            PressureOverclosure::Linear {
                slope: Some(1e12),
                tension: None,
                c0: None,
            },
        );
        let pen = solve_contact(&model, &ContactOptions::default()).unwrap();
        let (fh, fp) = (
            hard.summary.pairs[0].total_normal_force,
            pen.summary.pairs[0].total_normal_force,
        );
        assert!(fp < fh && (fp / fh - 1.0).abs() < 1e-5, "{fp} vs {fh}");
    }

    /// Frictionless contact cannot hold the upper block's sliding and
    /// spinning: without lateral supports it is an error, not a garbage answer.
    #[test]
    fn sliding_modes_are_not_held_by_frictionless_contact() {
        let (mut model, _) = blocks(BoxElement::Hex20, 2, 2, PressureOverclosure::Hard);
        let top: std::collections::HashSet<usize> =
            model.mesh.node_sets["B1_Z1"].iter().copied().collect();
        model
            .dirichlet
            .retain(|d| !(top.contains(&d.node) && d.component < 2));
        // pushed by a pressure instead of a displacement: all in-plane modes float
        model.dirichlet.retain(|d| !top.contains(&d.node));
        let faces = box_faces(&model.mesh, "B1_Z1");
        for (element, face) in faces {
            model.pressures.push(crate::fem::model::Pressure {
                element,
                face,
                value: 10.0,
            });
        }
        let err = solve_contact(&model, &ContactOptions::default())
            .unwrap_err()
            .to_string();
        assert!(err.contains("not held"), "{err}");
    }

    /// The factorized system is reused for a new contact configuration: the
    /// upper block lifted by a rigid translation (K unchanged, gaps changed)
    /// solved with the old factor and new pair geometry equals a fresh solve
    /// of the moved model.
    #[test]
    fn system_is_reused_for_new_positions() {
        let (model, _) = blocks(BoxElement::Hex20, 2, 3, PressureOverclosure::Hard);
        let options = ContactOptions::default();
        let pairs = build_pairs(&model, &options.pairing).unwrap();
        let mut nodes = pairs[0].slave_nodes.clone();
        for f in &pairs[0].master_faces {
            nodes.extend(&f.nodes);
        }
        let system = ElasticSystem::new(&model, &nodes, options.ordering, 1).unwrap();
        let upper: std::collections::HashSet<usize> = (0..model.mesh.node_count())
            .filter(|&n| model.mesh.node_labels[n] > 10_000)
            .collect();
        let lift = 2e-4;
        let mut coords = model.mesh.coords.clone();
        for &n in &upper {
            coords[n][2] += lift;
        }
        let moved_pairs = vec![build_pair(&model, &coords, 0, &options.pairing).unwrap()];
        let reused = solve_pairs(&model, &system, &moved_pairs, &options).unwrap();
        let mut moved = model.clone();
        moved.mesh.coords = coords;
        let fresh = solve_contact(&moved, &options).unwrap();
        let f_reused: f64 = reused.active_set.lambda.iter().sum();
        let f_fresh = fresh.summary.pairs[0].total_normal_force;
        assert!(f_reused < 0.9 * blocks(BoxElement::Hex20, 2, 3, PressureOverclosure::Hard).1);
        assert!(
            (f_reused / f_fresh - 1.0).abs() < 1e-10,
            "{f_reused} vs {f_fresh}"
        );
        let umax = fresh
            .solution
            .displacement
            .iter()
            .fold(0.0f64, |a, v| a.max(v.abs()));
        for (a, b) in reused.displacement.iter().zip(&fresh.solution.displacement) {
            assert!((a - b).abs() < 1e-10 * umax);
        }
    }
}
