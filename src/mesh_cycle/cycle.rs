//! The quasi-static mesh cycle of a gear pair in FE contact
//! ([`MeshCycle`], every pair kind): one contact solve per roll angle with
//! the stiffness factorized once, its result per position ([`StepResult`])
//! and the bookkeeping of its bounded loops. What only a line-contact
//! (cylindrical) pair has, the path of contact and the slave switch at the
//! gear's tip edge, comes from its [`LineContactPair`]; what only a
//! point-contact (bevel/hypoid) pair reports, the tip edge and the contact
//! pattern, from its pinion mesh. The run over a scene, its options and
//! files, is [`crate::mesh_cycle::run`].
//!
//! Reuse: the pair model keeps both bodies in their own frames, so K and
//! its Cholesky factor ([`ElasticSystem`]) are the same at every roll
//! angle. Per position only the contact geometry is rebuilt (bodies placed
//! by [`GearPair::nominal_frames`], search and projection) and the condensed
//! problem is solved: one solve for the gaps under the torque, one per
//! Delassus column of a constraint that enters the active set, one final
//! solve. Nothing is refactorized.

use std::collections::HashSet;

use crate::compliance::body::{bevel_sector_options, BodyMeshOptions};
use crate::contact::pairing::{build_pair_placed, PairGeometry, PairingOptions};
use crate::contact::placement::Placement;
use crate::contact::solve::{face_averaged_pressure, solve_pairs_placed, ContactOptions};
use crate::contact::system::ElasticSystem;
use crate::contact::{Friction, PressureOverclosure};
use crate::error::FlankError;
use crate::fem::ordering::OrderingMethod;
use crate::geometry::gear_pair::{engagement_roll_angles, GearPair, LineContactPair};
use crate::geometry::vec3::V3;
use crate::iteration_limits::{IterationLimits, LoopEnd};
use crate::load_sharing::{te_arcsec_at_gear, te_urad_at_pinion};
use crate::mesh_cycle::pair_model::{bevel_pair_model, pair_model, PairModel};
use crate::report::fe_pattern::PatternNode;
use crate::scene::Scene;
use crate::settings::{ContactLaw, SlaveBody};
use crate::tca::point_contact::{projection, ARCSEC_PER_RAD};
use std::sync::Arc;
use std::time::Instant;

/// How often a position is solved again with twice the search distance
/// when slave nodes outside the candidates penetrate after the solve.
pub const MAX_SEARCH_RAISES: usize = 3;

/// A κ₁ estimate of the diagonally scaled pinned stiffness above this is
/// noted in the summary (κ·u ≈ 1e-4: fewer than 4 digits are guaranteed).
/// The scaled one because the error of a Cholesky solve is bounded by
/// κ₂(D^(−½)KD^(−½)) u, not κ(K) u (Demmel 1989; Higham 2002, §10.1):
/// two bodies of E ratio 10⁴ in one K raise κ₁(K) by 10⁴ (1.6e12 in
/// `verification/extreme`) but not the scaled figure (6.1e6).
pub const ILL_CONDITIONED: f64 = 1e12;

use crate::load_sharing::LOADED_FRACTION;

/// Contact patch of one tooth pair at one position (slave flank).
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct Patch {
    /// Slave nodes in contact.
    pub closed_nodes: usize,
    /// Σ tributary area of the closed slave nodes (mm²).
    pub area_mm2: f64,
    /// Range of the slave flank's radius (own frame, mm) and of z (mm).
    pub radius_min_mm: f64,
    pub radius_max_mm: f64,
    pub z_min_mm: f64,
    pub z_max_mm: f64,
}

/// The bounded loops of the FE positions (the summary's
/// `iteration_limits`): the normal active set, whose limit
/// (`active_set_limit`) is an error, so every recorded call met it, and the
/// friction fixed point, whose limit (50 Tresca problems per working-set
/// round, [`crate::contact::friction::FrictionOptions`]) leaves the last
/// iterate flagged `friction_converged = false` when the polish fails too.
pub(crate) fn iteration_limits(steps: &[StepResult], active_set_limit: usize) -> IterationLimits {
    let mut loops = IterationLimits::new();
    for s in steps {
        record_active_set(
            &mut loops,
            s.active_set_iterations,
            active_set_limit,
            s.max_violation_mm,
        );
        if let Some(converged) = s.friction_converged {
            record_friction(
                &mut loops,
                converged,
                s.friction_iterations,
                s.friction_rounds,
                s.friction_bound_change,
            );
        }
    }
    loops
}

/// One position's friction fixed point in `loops` (`iterations` Tresca
/// problems over `rounds` working-set rounds, the last relative change of
/// the slip bounds), shared by the spur and hypoid FE cycles.
pub(crate) fn record_friction(
    loops: &mut IterationLimits,
    converged: bool,
    iterations: usize,
    rounds: usize,
    bound_change: f64,
) {
    let per_round = crate::contact::friction::FrictionOptions::default();
    let limit = per_round.max_iterations * rounds.max(1);
    loops.record(
        "contact.friction_fixed_point",
        "relative change of the slip bounds",
        per_round.tolerance,
        if converged {
            LoopEnd::converged(iterations, limit, bound_change)
        } else {
            LoopEnd::at_limit(iterations, limit, bound_change)
        },
    );
}

/// One position's normal active set in `loops`: its limit is an error, so
/// a recorded call met it; the residual is the largest contact-law
/// violation (mm).
pub(crate) fn record_active_set(
    loops: &mut IterationLimits,
    iterations: usize,
    limit: usize,
    violation_mm: f64,
) {
    loops.record(
        "contact.active_set",
        "largest contact-law violation (mm)",
        f64::NAN,
        LoopEnd::converged(iterations, limit, violation_mm),
    );
}

/// Results of one roll angle, the same for every pair kind. What only a
/// line-contact (cylindrical) pair has is empty or `None` for point-contact
/// (bevel/hypoid) pairs, and the other way round.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct StepResult {
    pub roll_deg: f64,
    /// The roll angle in the scene's reference convention (if it gives one).
    pub reference_deg: Option<f64>,
    /// Normal contact force per tooth pair (N), Σλ over its slave nodes.
    pub pair_force_n: Vec<f64>,
    /// Share of each pair in the total normal force.
    pub load_share: Vec<f64>,
    /// Kinematic contact position of each pair on the line of action, from
    /// the start of the path of contact (mm); outside [0, g_α]: no kinematic
    /// contact. Empty for point-contact pairs (no line of action).
    pub kinematic_position_mm: Vec<f64>,
    /// Loaded transmission error: the pinion's rotation under load beyond
    /// the rigid kinematic rotation (µrad, > 0 loaded), the same at the
    /// gear (arc seconds, −Δφ₁ z₁/z₂, the unloaded TCA's sign; one
    /// conversion, [`crate::load_sharing::te_arcsec_at_gear`]), and for
    /// line-contact pairs that times r_b1 (µm, along the line of action).
    pub te_urad: f64,
    #[serde(default)]
    pub te_arcsec: f64,
    pub te_um: Option<f64>,
    /// Largest face-averaged contact pressure per pair (MPa) and largest
    /// nodal pressure λ/A (MPa).
    pub max_pressure_mpa: Vec<f64>,
    pub max_nodal_pressure_mpa: Vec<f64>,
    pub patch: Vec<Patch>,
    /// Smallest initial gap g₀ of each pair's candidates in the nominal
    /// placement (mm; < 0: the unloaded flanks interpenetrate there, and
    /// the pinion's rotation resolves it before it carries load: the
    /// loaded TE then contains that unloaded TE); `None` for a pair
    /// without candidates.
    #[serde(default)]
    pub min_initial_gap_mm: Vec<Option<f64>>,
    /// Whether closed slave nodes lie on the pinion's tip land, per pair
    /// (point-contact pairs, whose pinion mesh marks its tip land).
    #[serde(default)]
    pub pinion_tip_edge: Option<Vec<bool>>,
    /// Σ (pair forces' moments about the pinion axis) / T − 1 (point-contact
    /// pairs: every pair has the pinion as slave).
    #[serde(default)]
    pub moment_balance: Option<f64>,
    pub candidates: usize,
    pub active_set_iterations: usize,
    pub delassus_columns: usize,
    /// Contact-law violation (mm), complementarity (N·mm), equilibrium of
    /// the pinion (relative), backward error of the final solve.
    pub max_violation_mm: f64,
    pub complementarity: f64,
    pub equilibrium: f64,
    pub backward_error: f64,
    /// Search distance finally used (raised automatically, see
    /// [`MAX_SEARCH_RAISES`]).
    pub search_distance_mm: f64,
    /// Slave body of each tooth pair at this position.
    pub slave: Vec<SlaveBody>,
    /// With friction (μ > 0): magnitude of the resultant tangential contact
    /// force per tooth pair (N), stick and slip node counts, and whether the
    /// frictional solve met the Coulomb law (fixed point or exact polish)
    /// with its cone violation max(0, ‖λₜ‖ − μλₙ) (N).
    pub friction_force_n: Vec<f64>,
    pub stick_nodes: usize,
    pub slip_nodes: usize,
    pub friction_converged: Option<bool>,
    pub coulomb_residual: f64,
    /// Friction fixed point: Tresca problems solved (all working-set
    /// rounds), rounds, and the last relative change of the slip bounds.
    #[serde(default)]
    pub friction_iterations: usize,
    #[serde(default)]
    pub friction_rounds: usize,
    #[serde(default)]
    pub friction_bound_change: f64,
    pub time_s: f64,
    pub warnings: Vec<String>,
    /// The loaded slave nodes of point-contact pairs (the contact pattern
    /// of this position; not in summary.json).
    #[serde(skip)]
    pub pattern: Vec<PatternNode>,
}

/// The resolved settings of a run.
#[derive(Clone, Debug, serde::Serialize)]
pub struct RunSettings {
    pub law: ContactLaw,
    pub penalty_factor: f64,
    pub slave: SlaveBody,
    /// Coulomb friction coefficient (0: frictionless).
    pub friction_mu: f64,
    pub search_distance_mm: f64,
    pub roll_angles_deg: Vec<f64>,
    pub vtu: bool,
    pub refine_contact_limits: bool,
    /// Set when the roll angles are the default range: its step (deg). The
    /// range is then extended step by step (up to one angular pitch on
    /// each side) while the middle pair still carries load at an end, so
    /// that load-extended contact is inside it.
    pub extend_step_deg: Option<f64>,
    /// reference = roll − (kinematic start of single contact) + this.
    pub reference_single_contact_start_deg: Option<f64>,
    /// The wet–dry loop (`[analyses.lubrication]`); its dry pass runs at
    /// `friction_mu` = μ₀.
    pub lubrication: Option<crate::lubrication::LoopSettings>,
}

impl RunSettings {
    /// The settings of a run with no `[analyses.contact]` and no roll
    /// angles yet (a program that gives its own): hard frictionless
    /// contact, a search distance of 0.2 mm (cylindrical; the slave body
    /// chosen per position) or 0.1 mm (bevel/hypoid; the pinion as slave),
    /// no VTU, no contact-limit bisection, no range extension.
    pub fn default_for(scene: &Scene) -> RunSettings {
        let bevel = scene.is_bevel();
        RunSettings {
            law: ContactLaw::Hard,
            penalty_factor: 1.0,
            slave: if bevel {
                SlaveBody::Pinion
            } else {
                SlaveBody::Auto
            },
            friction_mu: 0.0,
            search_distance_mm: if bevel { 0.1 } else { 0.2 },
            roll_angles_deg: Vec::new(),
            vtu: false,
            refine_contact_limits: false,
            extend_step_deg: None,
            reference_single_contact_start_deg: None,
            lubrication: None,
        }
    }
}

/// A solved roll angle with its fields.
pub struct Solved {
    pub step: StepResult,
    /// Displacements in the bodies' own frames (node-major).
    pub displacement: Vec<f64>,
    /// Face-averaged contact pressure at the slave nodes (MPa).
    pub pressure: Vec<f64>,
}

/// Unloaded interpenetration (mm) of a pair's candidates in the nominal
/// placement that a position reports as a warning.
const INTERFERENCE_WARNING_MM: f64 = 1e-3;

/// Everything a run needs between positions, for every pair kind.
pub struct MeshCycle {
    /// The gear pair (bodies, nominal placement).
    pub gear_pair: Arc<dyn GearPair>,
    /// Its line-contact kinematics (path of contact) for cylindrical pairs;
    /// `None` for point-contact (bevel/hypoid) pairs.
    line: Option<Arc<dyn LineContactPair>>,
    pub pair: PairModel,
    pub system: ElasticSystem,
    pub settings: RunSettings,
    pub(crate) contact: ContactOptions,
    torque: f64,
    /// Slave nodes on the pinion's tip land (point-contact pairs).
    tip_nodes: Option<HashSet<usize>>,
}

impl MeshCycle {
    /// Builds and factorizes the pair model of `scene` (any pair kind: the
    /// bevel sector mesh from `mesh` and the scene's `[mesh]`,
    /// [`crate::compliance::body::bevel_sector_options`]).
    pub fn new(
        scene: &Scene,
        mesh: &BodyMeshOptions,
        settings: RunSettings,
        threads: usize,
    ) -> Result<Self, FlankError> {
        let pair = if scene.is_bevel() {
            bevel_pair_model(scene, &bevel_sector_options(scene, mesh)?)?
        } else {
            let law = match settings.law {
                ContactLaw::Hard => PressureOverclosure::Hard,
                ContactLaw::Penalty => PressureOverclosure::Linear {
                    slope: None,
                    tension: None,
                    c0: None,
                },
            };
            let gear_pair = scene.gear_pair()?;
            pair_model(scene, gear_pair.as_ref(), mesh, law, settings.slave)?
        };
        Self::of_pair(scene, pair, settings, threads)
    }

    /// [`Self::new`] with a pair model built by the caller (hard contact,
    /// or the normal law of `settings.law` for cylindrical pairs), e.g. of
    /// banded sector meshes ([`crate::mesh_cycle::contact_band`]) or of a
    /// bevel pair after its input checks
    /// ([`crate::mesh_cycle::bevel_checks::checked_cycle`]).
    pub fn of_pair(
        scene: &Scene,
        mut pair: PairModel,
        settings: RunSettings,
        threads: usize,
    ) -> Result<Self, FlankError> {
        let (gear_pair, line, tip_nodes): (Arc<dyn GearPair>, _, _) = if scene.is_bevel() {
            if settings.slave == SlaveBody::Gear {
                return Err(FlankError::Model(
                    "the gear as slave: not available for bevel and hypoid pairs yet (their FE contact has the pinion as slave)".into(),
                ));
            }
            let tip: HashSet<usize> = pair
                .model
                .mesh
                .node_sets
                .get("PINION_TIP_LAND")
                .map(|v| v.iter().copied().collect())
                .unwrap_or_default();
            (
                scene.bevel("the FE mesh cycle")?.pair.clone(),
                None,
                Some(tip),
            )
        } else {
            let line = scene.gear_pair()?;
            (line.clone(), Some(line), None)
        };
        if settings.law == ContactLaw::Penalty {
            // the automatic slope of the (first pair's) master faces, scaled
            crate::mesh_cycle::pair_model::set_automatic_penalty(
                &mut pair,
                settings.penalty_factor,
            )?;
        }
        if !(0.0..=1.0).contains(&settings.friction_mu) {
            return Err(FlankError::Model(format!(
                "friction coefficient {} must be in 0…1",
                settings.friction_mu
            )));
        }
        if settings.friction_mu > 0.0 {
            for i in pair.model.contact.interactions.iter_mut() {
                i.friction = Some(Friction {
                    mu: settings.friction_mu,
                    stick_slope: None,
                });
            }
        }
        let system = ElasticSystem::new(
            &pair.model,
            &pair.contact_nodes,
            OrderingMethod::Metis,
            threads,
        )?;
        if system.floating.modes.len() != 1 {
            return Err(FlankError::Model(format!(
                "the pair model should have exactly one floating mode (the pinion's rotation), found {}",
                system.floating.modes.len()
            )));
        }
        let contact = ContactOptions {
            ordering: OrderingMethod::Metis,
            threads,
            recover_stress: false,
            pairing: PairingOptions {
                search_distance: Some(settings.search_distance_mm),
                max_initial_penetration: None,
            },
            max_iterations: 1000,
            gap_tolerance: None,
        };
        Ok(MeshCycle {
            gear_pair,
            line,
            pair,
            system,
            settings,
            contact,
            torque: scene.load.torque_nmm,
            tip_nodes,
        })
    }

    /// The line-contact kinematics of a cylindrical pair.
    pub fn line_pair(&self) -> Result<&Arc<dyn LineContactPair>, FlankError> {
        self.line.as_ref().ok_or_else(|| {
            FlankError::Model(
                "a bevel/hypoid pair has point contact: no path of contact along a line of action"
                    .into(),
            )
        })
    }

    /// The pinion torque (N·mm).
    pub fn torque_nmm(&self) -> f64 {
        self.torque
    }

    /// The total normal force that carries the torque, T/(r_b1 cos β_b)
    /// (N; T/r_b1 for spur gears): the single-pair force of a spur pair
    /// (line-contact pairs).
    pub fn nominal_force(&self) -> Result<f64, FlankError> {
        Ok(self.torque / self.line_pair()?.nominal_moment_arm())
    }

    /// One mesh cycle: the pinion roll of one tooth pitch (deg).
    pub fn cycle_deg(&self) -> f64 {
        self.gear_pair.tooth_roll_step().abs().to_degrees()
    }

    /// The placement of both bodies at `roll` (rad).
    pub fn placement(&self, roll: f64) -> Placement {
        Placement {
            body_of: self.pair.body_of.clone(),
            frames: self.gear_pair.nominal_frames(roll).to_vec(),
        }
    }

    /// The pair model at roll angle `roll_deg` as it is solved there, in
    /// the pinion's own frame: the pinion where it is meshed (its axis the
    /// z axis, so the `*RIGID BODY` of its mount turns about z under the
    /// torque, as in the model), the gear moved to its place relative to
    /// it (P⁻¹G of the pair's frames; contact and the clamped mount do not
    /// depend on the frame), only the contact pairs solved at this
    /// position (one per tooth pair), the normal law of the run. Solved as
    /// it is (flank `solve`, ccx) it is this position's problem; ccx's
    /// HARD contact is a 50 E penalty, so compare like with like through
    /// the penalty law.
    pub fn deck_model(&self, roll_deg: f64) -> crate::fem::model::Model {
        let roll = roll_deg.to_radians();
        let mut model = self.pair.model.clone();
        let placed = self.placement(roll);
        let to_pinion = placed.frames[0].inverse();
        let relative = Placement {
            body_of: placed.body_of,
            frames: placed.frames.iter().map(|f| to_pinion.compose(f)).collect(),
        };
        model.mesh.coords = relative.positions(&model.mesh.coords);
        model.contact.pairs = (0..self.pair.teeth.len())
            .map(|p| model.contact.pairs[self.pairing_at(p, roll).0].clone())
            .collect();
        model
    }

    /// Writes [`Self::deck_model`] as a CalculiX deck `path`.
    pub fn write_deck(&self, roll_deg: f64, path: &std::path::Path) -> Result<(), FlankError> {
        crate::deck::write_deck(&self.deck_model(roll_deg), path)
    }

    /// Solves one roll angle (deg) with the factorized stiffness.
    pub fn solve(&self, roll_deg: f64) -> Result<Solved, FlankError> {
        self.solve_with_mu(roll_deg, None)
    }

    /// [`Self::solve`] with a Coulomb coefficient per tooth pair (`mu[p]`,
    /// ≥ 0) instead of the run's `friction_mu` (which must be > 0: the
    /// tangential rows are built with it).
    pub fn solve_with_mu(&self, roll_deg: f64, mu: Option<&[f64]>) -> Result<Solved, FlankError> {
        if let Some(m) = mu {
            if m.len() != self.pair.teeth.len() {
                return Err(FlankError::Model(format!(
                    "roll angle {roll_deg}°: {} friction coefficients for {} tooth pairs",
                    m.len(),
                    self.pair.teeth.len()
                )));
            }
            if !(self.settings.friction_mu > 0.0) {
                return Err(FlankError::Model(
                    "a friction coefficient per tooth pair needs a run with friction (friction_mu > 0)".into(),
                ));
            }
            if let Some(bad) = m.iter().find(|v| !(**v >= 0.0 && **v <= 1.0)) {
                return Err(FlankError::Model(format!(
                    "roll angle {roll_deg}°: friction coefficient {bad} must be in 0…1"
                )));
            }
        }
        let t = Instant::now();
        let roll = roll_deg.to_radians();
        let placement = self.placement(roll);
        let model = &self.pair.model;
        let at = |e: FlankError| match e {
            FlankError::Solver(m) => FlankError::Solver(format!("roll angle {roll_deg}°: {m}")),
            FlankError::Model(m) => FlankError::Model(format!("roll angle {roll_deg}°: {m}")),
            other => other,
        };
        // slave nodes beyond the search distance that close under load (the
        // pinion turns by tens of µm): search again, twice as far
        let mut options = self.contact.clone();
        let mut raised = Vec::new();
        let mut pairing: Vec<(usize, SlaveBody)> = (0..self.pair.teeth.len())
            .map(|p| self.pairing_at(p, roll))
            .collect();
        let mut raises = 0;
        let mut switched = false;
        let (pairs, state) = loop {
            let mut pairs: Vec<PairGeometry> = pairing
                .iter()
                .map(|&(p, _)| build_pair_placed(model, &placement, p, &options.pairing))
                .collect::<Result<_, _>>()
                .map_err(at)?;
            if let Some(m) = mu {
                for (g, &v) in pairs.iter_mut().zip(m) {
                    g.mu = v;
                }
            }
            let state = solve_pairs_placed(model, &self.system, &pairs, &placement, &options)
                .map_err(at)?;
            if state.uncovered == 0 {
                break (pairs, state);
            }
            // pinion nodes cut by the gear's tip edge just after a pair's
            // kinematic start (load-extended corner contact): that pair is
            // solved with the gear as the slave
            if let (false, SlaveBody::Auto, Some(line)) =
                (switched, self.settings.slave, self.line.as_ref())
            {
                let mid = 0.5 * line.path_length();
                let near_gear_tip: Vec<usize> = (0..pairing.len())
                    .filter(|&p| {
                        pairing[p].1 == SlaveBody::Pinion
                            && self.pair.pairings[p][1].is_some()
                            && line.path_position(self.pair.teeth[p].0, roll) < mid
                    })
                    .collect();
                if !near_gear_tip.is_empty() {
                    for &p in &near_gear_tip {
                        pairing[p] = (self.pair.pairings[p][1].unwrap_or(0), SlaveBody::Gear);
                    }
                    raised.push(format!(
                        "{} pinion slave node(s) outside the candidates penetrated: tooth pair(s) {:?} (contact in the first half of the path, near the gear's tip edge) solved again with the gear as the slave",
                        state.uncovered,
                        near_gear_tip.iter().map(|p| p + 1).collect::<Vec<_>>()
                    ));
                    switched = true;
                    continue;
                }
            }
            if raises >= MAX_SEARCH_RAISES {
                raised.push(format!(
                    "{} slave node(s) beyond the search distance penetrated after {MAX_SEARCH_RAISES} raises",
                    state.uncovered
                ));
                break (pairs, state);
            }
            let d = options.pairing.search_distance.unwrap_or(0.1);
            raised.push(format!(
                "{} slave node(s) beyond the search distance {d} mm penetrated: solved again with {} mm",
                state.uncovered,
                2.0 * d
            ));
            options.pairing.search_distance = Some(2.0 * d);
            raises += 1;
        };
        let np = pairs.len();
        let mut step = StepResult {
            roll_deg,
            reference_deg: self.reference_deg(roll_deg),
            pair_force_n: vec![0.0; np],
            load_share: vec![0.0; np],
            kinematic_position_mm: match &self.line {
                Some(line) => self
                    .pair
                    .teeth
                    .iter()
                    .map(|&(k, _)| line.path_position(k, roll))
                    .collect(),
                None => Vec::new(),
            },
            max_pressure_mpa: vec![0.0; np],
            max_nodal_pressure_mpa: vec![0.0; np],
            patch: vec![Patch::default(); np],
            min_initial_gap_mm: pairs
                .iter()
                .map(|g| g.constraints.iter().map(|c| c.g0).reduce(f64::min))
                .collect(),
            pinion_tip_edge: self.tip_nodes.as_ref().map(|_| vec![false; np]),
            candidates: state.constraints.len(),
            active_set_iterations: state.active_set.iterations,
            delassus_columns: state.active_set.columns,
            max_violation_mm: state.active_set.max_violation,
            complementarity: state.active_set.complementarity,
            equilibrium: state.active_set.equilibrium,
            backward_error: state.backward_error,
            warnings: raised
                .into_iter()
                .chain(state.warnings.iter().cloned())
                .collect(),
            search_distance_mm: options.pairing.search_distance.unwrap_or(0.1),
            slave: pairing.iter().map(|&(_, b)| b).collect(),
            friction_force_n: vec![0.0; np],
            stick_nodes: state.friction.as_ref().map_or(0, |f| f.stick),
            slip_nodes: state.friction.as_ref().map_or(0, |f| f.slipping),
            friction_converged: state.friction.as_ref().map(|f| f.converged),
            coulomb_residual: state.friction.as_ref().map_or(0.0, |f| f.coulomb_residual),
            friction_iterations: state.friction.as_ref().map_or(0, |f| f.iterations),
            friction_rounds: state.friction.as_ref().map_or(0, |f| f.rounds),
            friction_bound_change: state.friction.as_ref().map_or(0.0, |f| f.bound_change),
            ..Default::default()
        };
        // moments about the pinion axis (own frame: +z through the origin)
        // of the contact forces on the pinion, in the drive sense, where
        // every pair has the pinion as slave
        let pinion_slaves = step.slave.iter().all(|&b| b == SlaveBody::Pinion);
        let sense = self.gear_pair.rotation_axes()[0][2].signum();
        let mut moment = 0.0;
        let nn = model.mesh.node_count();
        let mut pressure = vec![0.0; nn];
        let mut offset = 0;
        for (p, g) in pairs.iter().enumerate() {
            let k = g.constraints.len();
            let lam = &state.active_set.lambda[offset..offset + k];
            if let Some(fr) = &state.friction {
                // the force on each slave node along the slip rows' slave
                // terms (the master's tangents in the slave's own frame),
                // their resultant per pair and their moments
                let mut resultant = [0.0; 3];
                for (c, lt) in g.constraints.iter().zip(&fr.lambda_t[offset..offset + k]) {
                    let x = model.mesh.coords[c.slave];
                    for (a, rows) in c.tangent_terms.iter().enumerate() {
                        let Some(&(_, t)) = rows.iter().find(|(node, _)| *node == c.slave) else {
                            continue;
                        };
                        for d in 0..3 {
                            resultant[d] += lt[a] * t[d];
                        }
                        moment += lt[a] * (x[0] * t[1] - x[1] * t[0]) * sense;
                    }
                }
                step.friction_force_n[p] = crate::geometry::vec3::norm(resultant);
            }
            let smooth = face_averaged_pressure(model, g, lam);
            let patch = &mut step.patch[p];
            patch.radius_min_mm = f64::INFINITY;
            patch.z_min_mm = f64::INFINITY;
            for (i, c) in g.constraints.iter().enumerate() {
                step.pair_force_n[p] += lam[i];
                pressure[c.slave] = smooth[i];
                step.max_pressure_mpa[p] = step.max_pressure_mpa[p].max(smooth[i]);
                step.max_nodal_pressure_mpa[p] =
                    step.max_nodal_pressure_mpa[p].max(lam[i] / c.area);
                if lam[i] > 0.0 {
                    let x = model.mesh.coords[c.slave];
                    let r = x[0].hypot(x[1]);
                    patch.closed_nodes += 1;
                    patch.area_mm2 += c.area;
                    patch.radius_min_mm = patch.radius_min_mm.min(r);
                    patch.radius_max_mm = patch.radius_max_mm.max(r);
                    patch.z_min_mm = patch.z_min_mm.min(x[2]);
                    patch.z_max_mm = patch.z_max_mm.max(x[2]);
                    // the force on the slave (pinion) node is λ n, n the
                    // master's normal in the slave's own frame (the slave's
                    // term of the gap's linear form)
                    let f = c.terms[0].1;
                    moment += lam[i] * (x[0] * f[1] - x[1] * f[0]) * sense;
                    if let Some(tip) = &self.tip_nodes {
                        step.pattern
                            .push(self.pattern_node(&placement, p, x, smooth[i]));
                        if tip.contains(&c.slave) {
                            if let Some(edge) = step.pinion_tip_edge.as_mut() {
                                edge[p] = true;
                            }
                        }
                    }
                }
            }
            if patch.closed_nodes == 0 {
                *patch = Patch::default();
            }
            offset += k;
        }
        for (p, g) in step.min_initial_gap_mm.iter().enumerate() {
            if let Some(g) = g.filter(|&g| g < -INTERFERENCE_WARNING_MM) {
                step.warnings.push(format!(
                    "tooth pair {} (pinion tooth {} / gear tooth {}): the unloaded flanks interpenetrate by {:.4} mm in the nominal placement",
                    p + 1,
                    self.pair.teeth[p].0,
                    self.pair.teeth[p].1,
                    -g
                ));
            }
        }
        let total: f64 = step.pair_force_n.iter().sum();
        if !(total > 0.0) {
            return Err(at(FlankError::Model(format!(
                "no tooth pair carries load under the pinion torque {} N·m ({} candidates): the modelled pairs do not reach each other",
                self.torque / 1000.0,
                step.candidates
            ))));
        }
        for p in 0..np {
            step.load_share[p] = step.pair_force_n[p] / total;
        }
        if pinion_slaves {
            step.moment_balance = Some(-moment / self.torque - 1.0);
        }
        // the pinion hub's rotation about its own +z
        let rz = state.coupling_motion[0][5];
        let ratio = self.gear_pair.ratio();
        match &self.line {
            // the drive turns a cylindrical pinion clockwise
            Some(line) => {
                step.te_urad = -rz * 1e6;
                step.te_arcsec = te_arcsec_at_gear(step.te_urad, ratio);
                step.te_um = Some(-rz * line.transmission_error_radius() * 1e3);
            }
            // a bevel pinion turns in the sense of its rotation axis
            None => {
                step.te_arcsec = -rz * sense * ratio * ARCSEC_PER_RAD;
                step.te_urad = te_urad_at_pinion(step.te_arcsec, ratio);
            }
        }
        if !(step.te_urad.is_finite() && step.te_arcsec.is_finite()) {
            return Err(at(FlankError::Solver(
                "the pinion rotation is not finite".into(),
            )));
        }
        if let Some(e) =
            crate::load_sharing::beyond_pitch_error(step.te_urad, self.gear_pair.tooth_roll_step())
        {
            return Err(FlankError::Model(format!("roll angle {roll_deg}°: {e}")));
        }
        step.warnings
            .extend(crate::load_sharing::large_rotation_warning(step.te_urad));
        step.time_s = t.elapsed().as_secs_f64();
        Ok(Solved {
            step,
            displacement: state.displacement,
            pressure,
        })
    }

    /// A loaded pinion node `own` (its own frame) of pair `p` as the
    /// contact pattern holds it: its axial projection on both members.
    fn pattern_node(&self, placement: &Placement, p: usize, own: V3, pressure: f64) -> PatternNode {
        let global = placement.frames[0].place(own);
        let g = &placement.frames[1];
        let in_gear = g.rotate_back([
            global[0] - g.translation[0],
            global[1] - g.translation[1],
            global[2] - g.translation[2],
        ]);
        PatternNode {
            pair: p + 1,
            projection_mm: [
                projection(self.gear_pair.pinion(), own),
                projection(self.gear_pair.gear(), in_gear),
            ],
            pressure_mpa: pressure,
        }
    }

    /// The contact pair (index into the model's pairs) that represents
    /// tooth pair `p` at `roll` (rad), and its slave body: with
    /// [`SlaveBody::Auto`] the gear while the pair is before its kinematic
    /// start of contact (only the gear's tip edge can touch the pinion's
    /// flank there), the pinion from then on (its tip edge carries the end
    /// of contact and the load-extended contact beyond it). [`Self::solve`]
    /// switches a pair in the first half of its path to the gear as slave
    /// when pinion nodes outside the candidates penetrate (the gear's tip
    /// edge still bearing just after the kinematic start).
    pub fn pairing_at(&self, p: usize, roll: f64) -> (usize, SlaveBody) {
        match self.pair.pairings[p] {
            [Some(i), None] => (i, SlaveBody::Pinion),
            [None, Some(i)] => (i, SlaveBody::Gear),
            [Some(pin), Some(gear)] => {
                let before_start = self
                    .line
                    .as_ref()
                    .is_some_and(|line| line.path_position(self.pair.teeth[p].0, roll) < 0.0);
                if before_start {
                    (gear, SlaveBody::Gear)
                } else {
                    (pin, SlaveBody::Pinion)
                }
            }
            [None, None] => unreachable!("every tooth pair has a contact pair"),
        }
    }

    fn reference_deg(&self, roll_deg: f64) -> Option<f64> {
        let line = self.line.as_ref()?;
        self.settings
            .reference_single_contact_start_deg
            .map(|r| roll_deg - line.single_contact().0.to_degrees() + r)
    }

    /// Whether pair `p` carries load in `step`: more than
    /// [`LOADED_FRACTION`] of the nominal force (line-contact pairs) or of
    /// the position's total normal force (point-contact pairs, the LTCA's
    /// measure, [`crate::load_sharing::cycle`]).
    pub fn loaded(&self, step: &StepResult, p: usize) -> bool {
        let reference = match self.nominal_force() {
            Ok(f) => f,
            Err(_) => step.pair_force_n.iter().sum(),
        };
        step.pair_force_n[p] > LOADED_FRACTION * reference
    }

    /// Bisects the roll angle (deg) between `off` (pair `p` unloaded) and
    /// `on` (loaded) to `tol` degrees.
    pub(crate) fn bisect(
        &self,
        p: usize,
        mut off: f64,
        mut on: f64,
        tol: f64,
    ) -> Result<(f64, usize), FlankError> {
        let mut solves = 0;
        while (on - off).abs() > tol {
            let mid = 0.5 * (on + off);
            let s = self.solve(mid)?;
            solves += 1;
            if self.loaded(&s.step, p) {
                on = mid;
            } else {
                off = mid;
            }
        }
        Ok((0.5 * (on + off), solves))
    }
}

/// Default roll angles: [`engagement_roll_angles`].
pub fn default_roll_angles(pair: &dyn LineContactPair, step_deg: f64) -> Vec<f64> {
    engagement_roll_angles(pair, step_deg)
}
#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::gear_pair::Flank;
    use crate::mesh::bevel_sector::BevelSectorOptions;
    use crate::scene::read_scene;

    /// Seed 003, coarse, roll 0: the contact forces balance the torque
    /// about the pinion axis (moment balance at round-off), the active set
    /// is consistent (no violation, complementarity at round-off), the
    /// shares add to 1; and the FE pairing sees the unloaded geometry: the
    /// middle pair touches (smallest g₀ ≥ −1 µm), and the smallest g₀ of
    /// the pair of pinion tooth 1 / gear tooth 3 equals the exact
    /// surfaces' deepest interpenetration (closest points on a 21 × 11
    /// flank grid) within 5 % (the mesh's slave nodes are a coarser grid).
    #[test]
    fn seed003_position_balances_and_sees_the_unloaded_geometry() {
        let path = format!(
            "{}/papers/seed003-hypoid/scene.toml",
            env!("CARGO_MANIFEST_DIR")
        );
        let s = read_scene(std::path::Path::new(&path)).unwrap();
        let mesh = BevelSectorOptions {
            flank_size: 1.5,
            base_size: 6.0,
            ..Default::default()
        };
        let model = bevel_pair_model(&s, &mesh).unwrap();
        let cycle = MeshCycle::of_pair(&s, model, RunSettings::default_for(&s), 2).unwrap();
        let st = cycle.solve(0.0).unwrap().step;
        println!("{st:?}");
        let balance = st.moment_balance.unwrap();
        assert!(balance.abs() < 1e-10, "{balance}");
        assert!(st.max_violation_mm < 1e-9 && st.complementarity.abs() < 1e-6);
        assert!((st.load_share.iter().sum::<f64>() - 1.0).abs() < 1e-12);
        assert!(
            st.min_initial_gap_mm[1].unwrap() > -1e-3,
            "{:?}",
            st.min_initial_gap_mm
        );
        // the deepest candidate of pinion tooth 1 / gear tooth 3: its FE
        // gap against the exact surfaces' signed distance at the same
        // pinion point; they differ by the master faces' deviation from
        // the gear flank (< 1 % of the flank size, verification/bevel_sector_mesh)
        let pair = &cycle.gear_pair;
        let placement = Placement {
            body_of: cycle.pair.body_of.clone(),
            frames: pair.nominal_frames(0.0).to_vec(),
        };
        let g = build_pair_placed(
            &cycle.pair.model,
            &placement,
            cycle.pair.pairings[0][0].unwrap(),
            &cycle.contact.pairing,
        )
        .unwrap();
        let c = g
            .constraints
            .iter()
            .min_by(|a, b| a.g0.total_cmp(&b.g0))
            .unwrap();
        assert_eq!(Some(c.g0), st.min_initial_gap_mm[0]);
        let (u, v) = cycle.pair.flank_uv[&c.slave];
        let fr = pair.nominal_frames(0.0);
        let pf = pair.pinion().flank(Flank::Right, 1).unwrap();
        let gf = pair.gear().flank(Flank::Right, pair.mate(1)).unwrap();
        let x = fr[0].place(pf.point(u, v));
        let o = fr[1].place([0.0; 3]);
        let xg = fr[1].rotate_back([x[0] - o[0], x[1] - o[1], x[2] - o[2]]);
        let (gv0, gv1) = gf.v_range();
        let (_, _, d) = gf.closest_point_from(xg, 0.0, 0.5 * (gv0 + gv1));
        println!("pair 1: deepest candidate (u, v) = ({u:.3}, {v:.3}) mm: FE g0 {:.5} mm, exact {d:.5} mm", c.g0);
        assert!(d < -0.1 && (c.g0 - d).abs() < 0.01 * 1.5, "{} {d}", c.g0);
    }
}
