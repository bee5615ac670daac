//! The quasi-static mesh cycle: one contact solve per roll angle with the
//! stiffness factorized once, and what a gear engineer reads from it
//! (force per tooth pair, load sharing, loaded transmission error, contact
//! pressure and patch, contact ratio, single-pair force).
//!
//! Reuse: the pair model keeps both bodies in their own frames, so K and
//! its Cholesky factor ([`ElasticSystem`]) are the same at every roll
//! angle. Per position only the contact geometry is rebuilt (bodies placed
//! by [`GearPair::nominal_frames`], search and projection) and the condensed
//! problem is solved: one solve for the gaps under the torque, one per
//! Delassus column of a constraint that enters the active set, one final
//! solve. Nothing is refactorized.

use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::compliance::body::BodyMeshOptions;
use crate::contact::pairing::{build_pair_placed, NormalLaw, PairGeometry, PairingOptions};
use crate::contact::placement::Placement;
use crate::contact::solve::{face_averaged_pressure, solve_pairs_placed, ContactOptions};
use crate::contact::system::ElasticSystem;
use crate::contact::{Friction, PressureOverclosure};
use crate::error::FlankError;
use crate::fem::ordering::OrderingMethod;
use crate::fem::static_analysis::peak_memory_mb;
use crate::iteration_limits::{IterationLimits, LoopEnd};
use std::sync::Arc;

use crate::geometry::gear_pair::{engagement_roll_angles, GearPair};
use crate::mesh_cycle::checkpoint::{self, Checkpoint};
use crate::mesh_cycle::pair_model::{pair_model, PairModel};
use crate::report::vtu::{write_vtu, PointField};
use crate::scene::{read_scene, ContactAnalysis, Scene};
use crate::settings::{ContactLaw, SlaveBody};

/// Options of [`run_scene`]; `None` falls back to the scene's
/// `[analyses.contact]`, then to the defaults.
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    pub out: PathBuf,
    pub mesh: BodyMeshOptions,
    pub threads: usize,
    /// Roll angles (deg, flank's convention); overrides the scene's.
    pub roll_angles_deg: Option<Vec<f64>>,
    /// Roll angles in the scene's reference convention
    /// (`reference_single_contact_start_deg`); overrides the scene's.
    pub reference_angles_deg: Option<Vec<f64>>,
    pub law: Option<ContactLaw>,
    pub penalty_factor: Option<f64>,
    pub slave: Option<SlaveBody>,
    /// Coulomb friction coefficient; overrides the scene's `friction_mu`.
    pub friction_mu: Option<f64>,
    /// Write a VTU file per position.
    pub vtu: Option<bool>,
    /// Write a CalculiX deck per position (the pair model moved to its
    /// placed coordinates, `roll_…deg.inp`), to run the same contact problem
    /// in ccx.
    pub decks: bool,
    /// Bisect the middle pair's first and last loaded roll angles.
    pub refine_contact_limits: Option<bool>,
    pub quiet: bool,
    /// Take the positions of `out/checkpoint.json` left by an interrupted
    /// run of the same scene and options ([`super::checkpoint`]).
    pub resume: bool,
}

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

pub use crate::load_sharing::LOADED_FRACTION;

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

/// Results of one roll angle.
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
    /// contact.
    pub kinematic_position_mm: Vec<f64>,
    /// Loaded transmission error: pinion rotation under load beyond the
    /// rigid kinematic rotation (µrad) and that times r_b1 (µm, along the
    /// line of action).
    pub te_urad: f64,
    pub te_um: f64,
    /// Largest face-averaged contact pressure per pair (MPa) and largest
    /// nodal pressure λ/A (MPa).
    pub max_pressure_mpa: Vec<f64>,
    pub max_nodal_pressure_mpa: Vec<f64>,
    pub patch: Vec<Patch>,
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

/// A solved roll angle with its fields.
pub struct Solved {
    pub step: StepResult,
    /// Displacements in the bodies' own frames (node-major).
    pub displacement: Vec<f64>,
    /// Face-averaged contact pressure at the slave nodes (MPa).
    pub pressure: Vec<f64>,
}

/// Everything a run needs between positions.
pub struct MeshCycle {
    /// The gear pair (kinematics, nominal placement).
    pub gear_pair: Arc<dyn GearPair>,
    pub pair: PairModel,
    pub system: ElasticSystem,
    pub settings: RunSettings,
    contact: ContactOptions,
    torque: f64,
}

impl MeshCycle {
    /// Builds and factorizes the pair model of `scene`.
    pub fn new(
        scene: &Scene,
        mesh: &BodyMeshOptions,
        settings: RunSettings,
        threads: usize,
    ) -> Result<Self, FlankError> {
        let gear_pair = scene.gear_pair()?;
        let law = match settings.law {
            ContactLaw::Hard => PressureOverclosure::Hard,
            ContactLaw::Penalty => PressureOverclosure::Linear {
                slope: None,
                tension: None,
                c0: None,
            },
        };
        let pair = pair_model(scene, gear_pair.as_ref(), mesh, law, settings.slave)?;
        Self::of_pair(scene, pair, settings, threads)
    }

    /// [`Self::new`] with a pair model built by the caller (with the
    /// normal law of `settings.law`), e.g. of banded sector meshes
    /// ([`crate::mesh_cycle::contact_band`]).
    pub fn of_pair(
        scene: &Scene,
        mut pair: PairModel,
        settings: RunSettings,
        threads: usize,
    ) -> Result<Self, FlankError> {
        let gear_pair = scene.gear_pair()?;
        if settings.law == ContactLaw::Penalty {
            // the automatic slope of the (first pair's) master faces, scaled
            crate::mesh_cycle::pair_model::set_automatic_penalty(
                &mut pair,
                settings.penalty_factor,
            )?;
        }
        if settings.friction_mu > 0.0 {
            pair.model.contact.interactions[0].friction = Some(Friction {
                mu: settings.friction_mu,
                stick_slope: None,
            });
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
            pair,
            system,
            settings,
            contact,
            torque: scene.load.torque_nmm,
        })
    }

    /// The total normal force that carries the torque, T/(r_b1 cos β_b)
    /// (N; T/r_b1 for spur gears): the single-pair force of a spur pair.
    pub fn nominal_force(&self) -> f64 {
        self.torque / self.gear_pair.nominal_moment_arm()
    }

    /// The placement of both bodies at `roll` (rad).
    pub fn placement(&self, roll: f64) -> Placement {
        Placement {
            body_of: self.pair.body_of.clone(),
            frames: self.gear_pair.nominal_frames(roll).to_vec(),
        }
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
            if !switched && self.settings.slave == SlaveBody::Auto {
                let mid = 0.5 * self.gear_pair.path_length();
                let near_gear_tip: Vec<usize> = (0..pairing.len())
                    .filter(|&p| {
                        pairing[p].1 == SlaveBody::Pinion
                            && self.pair.pairings[p][1].is_some()
                            && self.gear_pair.path_position(self.pair.teeth[p].0, roll) < mid
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
            kinematic_position_mm: self
                .pair
                .teeth
                .iter()
                .map(|&(k, _)| self.gear_pair.path_position(k, roll))
                .collect(),
            max_pressure_mpa: vec![0.0; np],
            max_nodal_pressure_mpa: vec![0.0; np],
            patch: vec![Patch::default(); np],
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
            friction_force_n: vec![0.0; pairing.len()],
            stick_nodes: state.friction.as_ref().map_or(0, |f| f.stick),
            slip_nodes: state.friction.as_ref().map_or(0, |f| f.slipping),
            friction_converged: state.friction.as_ref().map(|f| f.converged),
            coulomb_residual: state.friction.as_ref().map_or(0.0, |f| f.coulomb_residual),
            friction_iterations: state.friction.as_ref().map_or(0, |f| f.iterations),
            friction_rounds: state.friction.as_ref().map_or(0, |f| f.rounds),
            friction_bound_change: state.friction.as_ref().map_or(0.0, |f| f.bound_change),
            ..Default::default()
        };
        let nn = model.mesh.node_count();
        let mut pressure = vec![0.0; nn];
        let mut offset = 0;
        for (p, g) in pairs.iter().enumerate() {
            let k = g.constraints.len();
            let lam = &state.active_set.lambda[offset..offset + k];
            if let Some(fr) = &state.friction {
                let mut f = [0.0; 3];
                for (c, lt) in g.constraints.iter().zip(&fr.lambda_t[offset..offset + k]) {
                    for (d, fd) in f.iter_mut().enumerate() {
                        *fd += lt[0] * c.tangents[0][d] + lt[1] * c.tangents[1][d];
                    }
                }
                step.friction_force_n[p] = (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt();
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
                }
            }
            if patch.closed_nodes == 0 {
                *patch = Patch::default();
            }
            offset += k;
        }
        let total: f64 = step.pair_force_n.iter().sum();
        if total > 0.0 {
            for p in 0..np {
                step.load_share[p] = step.pair_force_n[p] / total;
            }
        }
        // pinion hub rotation about +z; the drive turns it clockwise
        let rz = state.coupling_motion[0][5];
        step.te_urad = -rz * 1e6;
        step.te_um = -rz * self.gear_pair.transmission_error_radius() * 1e3;
        if !(step.te_urad.is_finite()) {
            return Err(FlankError::Solver(format!(
                "roll angle {roll_deg}°: the pinion rotation is not finite"
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
                if self.gear_pair.path_position(self.pair.teeth[p].0, roll) < 0.0 {
                    (gear, SlaveBody::Gear)
                } else {
                    (pin, SlaveBody::Pinion)
                }
            }
            [None, None] => unreachable!("every tooth pair has a contact pair"),
        }
    }

    fn reference_deg(&self, roll_deg: f64) -> Option<f64> {
        self.settings
            .reference_single_contact_start_deg
            .map(|r| roll_deg - self.gear_pair.single_contact().0.to_degrees() + r)
    }

    /// Whether pair `p` carries load in `step`.
    pub fn loaded(&self, step: &StepResult, p: usize) -> bool {
        step.pair_force_n[p] > LOADED_FRACTION * self.nominal_force()
    }

    /// Bisects the roll angle (deg) between `off` (pair `p` unloaded) and
    /// `on` (loaded) to `tol` degrees.
    fn bisect(
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
pub fn default_roll_angles(pair: &dyn GearPair, step_deg: f64) -> Vec<f64> {
    engagement_roll_angles(pair, step_deg)
}

/// Resolves the run's settings from the options, the scene's
/// `[analyses.contact]` and the defaults.
pub fn settings(
    scene: &Scene,
    pair: &dyn GearPair,
    o: &RunOptions,
) -> Result<RunSettings, FlankError> {
    let a = scene.analyses.contact.clone().unwrap_or_default();
    let law = o.law.or(a.law).unwrap_or_default();
    let penalty_factor = o.penalty_factor.or(a.penalty_factor).unwrap_or(1.0);
    let mut friction_mu = o.friction_mu.or(a.friction_mu).unwrap_or(0.0);
    let lubrication = crate::mesh_cycle::lubricated::loop_settings(scene, o.friction_mu)?;
    if let Some(s) = &lubrication {
        friction_mu = s.initial_mu;
    }
    if !(0.0..=1.0).contains(&friction_mu) {
        return Err(FlankError::Model(format!(
            "friction coefficient {friction_mu} must be in 0…1"
        )));
    }
    if !(penalty_factor > 0.0 && penalty_factor.is_finite()) {
        return Err(FlankError::Model(format!(
            "penalty factor {penalty_factor} must be positive"
        )));
    }
    let default_range = o.roll_angles_deg.is_none()
        && o.reference_angles_deg.is_none()
        && a.roll_angles_deg.is_none()
        && a.reference_angles_deg.is_none()
        && a.roll_start_deg.is_none();
    let roll_angles_deg = match (&o.roll_angles_deg, &o.reference_angles_deg) {
        (Some(_), Some(_)) => {
            return Err(FlankError::Model(
                "give roll angles or reference angles, not both".into(),
            ))
        }
        (Some(v), None) => v.clone(),
        (None, Some(v)) => {
            let r = a.reference_single_contact_start_deg.ok_or_else(|| {
                FlankError::Model(
                    "reference angles need reference_single_contact_start_deg in the scene's [analyses.contact]".into(),
                )
            })?;
            reference_to_roll(pair, r, v)
        }
        (None, None) => scene_roll_angles(&a, pair)?,
    };
    if roll_angles_deg.is_empty() || roll_angles_deg.iter().any(|v| !v.is_finite()) {
        return Err(FlankError::Model(
            "the roll angles must be finite and at least one".into(),
        ));
    }
    Ok(RunSettings {
        law,
        penalty_factor,
        friction_mu,
        slave: o.slave.or(a.slave).unwrap_or_default(),
        search_distance_mm: a.search_distance_mm.unwrap_or(0.2),
        roll_angles_deg,
        vtu: o.vtu.or(a.vtu).unwrap_or(true),
        refine_contact_limits: o
            .refine_contact_limits
            .or(a.refine_contact_limits)
            .unwrap_or(true),
        reference_single_contact_start_deg: a.reference_single_contact_start_deg,
        extend_step_deg: default_range.then(|| a.roll_step_deg.unwrap_or(1.0)),
        lubrication,
    })
}

/// Roll angles (deg) of angles given in a reference convention whose
/// value `start` marks the kinematic start of single contact.
fn reference_to_roll(pair: &dyn GearPair, start: f64, angles: &[f64]) -> Vec<f64> {
    let lpstc = pair.single_contact().0.to_degrees();
    angles.iter().map(|x| x - start + lpstc).collect()
}

fn scene_roll_angles(a: &ContactAnalysis, pair: &dyn GearPair) -> Result<Vec<f64>, FlankError> {
    if let Some(v) = &a.roll_angles_deg {
        return Ok(v.clone());
    }
    if let Some(v) = &a.reference_angles_deg {
        let r = a.reference_single_contact_start_deg.ok_or_else(|| {
            FlankError::Model(
                "reference_angles_deg needs reference_single_contact_start_deg".into(),
            )
        })?;
        return Ok(reference_to_roll(pair, r, v));
    }
    let step = a.roll_step_deg.unwrap_or(1.0);
    match (a.roll_start_deg, a.roll_end_deg) {
        (Some(s), Some(e)) => {
            let n = ((e - s) / step + 1e-9).floor() as i64;
            Ok((0..=n).map(|i| s + i as f64 * step).collect())
        }
        (None, None) => Ok(default_roll_angles(pair, step)),
        _ => Err(FlankError::Model(
            "[analyses.contact]: give both roll_start_deg and roll_end_deg, or neither".into(),
        )),
    }
}

/// `flank run SCENE`: the FE contact mesh cycle of the scene, written to
/// `options.out`. Returns the summary (also written as summary.json).
pub fn run_scene(path: &Path, options: &RunOptions) -> Result<serde_json::Value, FlankError> {
    let scene = read_scene(path)?;
    if scene.analyses.contact.is_none() {
        return Err(FlankError::Model(format!(
            "{}: the scene asks for no analysis `flank run` performs; add `contact = {{}}` under [analyses] for the FE contact mesh cycle",
            path.display()
        )));
    }
    run(&scene, options)
}

/// The mesh cycle of a parsed scene (see [`run_scene`]).
pub fn run(scene: &Scene, options: &RunOptions) -> Result<serde_json::Value, FlankError> {
    let t_total = Instant::now();
    let gear_pair = scene.gear_pair()?;
    let settings = settings(scene, gear_pair.as_ref(), options)?;
    let out = &options.out;
    std::fs::create_dir_all(out).map_err(|e| FlankError::io(out, e))?;
    // what a killed earlier run left half-written (never a result file)
    crate::atomic_file::remove_stale_temps(out);
    let t = Instant::now();
    let cycle = MeshCycle::new(scene, &options.mesh, settings, options.threads)?;
    let setup_s = t.elapsed().as_secs_f64();
    let nominal = cycle.nominal_force();
    let np = cycle.pair.teeth.len();
    let mid = cycle.gear_pair.middle() - 1;
    let angles = cycle.settings.roll_angles_deg.clone();
    let bar = if options.quiet {
        indicatif::ProgressBar::hidden()
    } else {
        let b = indicatif::ProgressBar::new(angles.len() as u64);
        b.set_style(
            indicatif::ProgressStyle::with_template(
                "{msg} [{bar:30}] {pos}/{len} positions, {elapsed} (eta {eta})",
            )
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        b.set_message("mesh cycle");
        b
    };
    let mut steps = Vec::with_capacity(angles.len());
    let key = checkpoint::run_key(&scene.source, &options.mesh, &cycle.settings)?;
    let mut checkpoint = Checkpoint::open(out, key, options.resume)?;
    let mut solve = |a: f64| -> Result<StepResult, FlankError> {
        if let Some(step) = checkpoint.take(a)? {
            return Ok(step);
        }
        let solved = cycle.solve(a)?;
        if cycle.settings.vtu {
            write_position_vtu(&cycle, out, a, &solved)?;
        }
        if options.decks {
            write_position_deck(&cycle, out, a)?;
        }
        checkpoint.record(&solved.step)?;
        Ok(solved.step)
    };
    // SIGINT is polled between positions: what is solved is kept
    let stop = |steps: &[StepResult]| -> Result<(), FlankError> {
        if crate::interrupt::requested() {
            bar.abandon();
            return Err(interrupted(out, steps, np));
        }
        Ok(())
    };
    for &a in &angles {
        steps.push(solve(a)?);
        bar.inc(1);
        stop(&steps)?;
    }
    // a default range grows while the middle pair is loaded at an end
    let mut extended = 0;
    if let Some(step) = cycle.settings.extend_step_deg {
        let limit = (cycle.gear_pair.pinion().angular_pitch().to_degrees() / step).ceil() as usize;
        for _ in 0..limit {
            if !cycle.loaded(&steps[0], mid) {
                break;
            }
            bar.inc_length(1);
            steps.insert(0, solve(steps[0].roll_deg - step)?);
            bar.inc(1);
            extended += 1;
            stop(&steps)?;
        }
        for _ in 0..limit {
            let last = steps.len() - 1;
            if !cycle.loaded(&steps[last], mid) {
                break;
            }
            bar.inc_length(1);
            steps.push(solve(steps[last].roll_deg + step)?);
            bar.inc(1);
            extended += 1;
            stop(&steps)?;
        }
    }
    bar.finish_and_clear();
    let reused = checkpoint.reused();
    let mut notes: Vec<String> = scene.material_warnings();
    // the wet–dry loop: the positions solved so far are its dry pass
    let mut lubrication = None;
    if let Some(ls) = cycle.settings.lubrication.clone() {
        let dry = std::mem::take(&mut steps);
        let lc = crate::mesh_cycle::lubricated::lubricated_cycle(&cycle, scene, &ls, dry, out)?;
        steps = lc.steps;
        if cycle.settings.refine_contact_limits {
            notes.push(format!(
                "the contact-limit bisection runs at the dry pass's μ₀ = {}",
                ls.initial_mu
            ));
        }
        lubrication = Some(lc.summary);
    }
    let time_per_position_s =
        steps.iter().map(|s| s.time_s).sum::<f64>() / steps.len().max(1) as f64;

    // contact ratio from the middle pair's loaded interval
    let mut refine_solves = 0;
    let mut limits: Option<(f64, f64)> = None;
    let loaded: Vec<bool> = steps.iter().map(|s| cycle.loaded(s, mid)).collect();
    let first = loaded.iter().position(|&l| l);
    let last = loaded.iter().rposition(|&l| l);
    match (first, last) {
        (Some(f), Some(l)) if f > 0 && l + 1 < steps.len() => {
            let (mut start, mut end) = (
                0.5 * (steps[f - 1].roll_deg + steps[f].roll_deg),
                0.5 * (steps[l].roll_deg + steps[l + 1].roll_deg),
            );
            if cycle.settings.refine_contact_limits {
                let (s, n1) = cycle.bisect(mid, steps[f - 1].roll_deg, steps[f].roll_deg, 0.01)?;
                let (e, n2) = cycle.bisect(mid, steps[l + 1].roll_deg, steps[l].roll_deg, 0.01)?;
                start = s;
                end = e;
                refine_solves = n1 + n2;
            }
            limits = Some((start, end));
        }
        _ => notes.push(
            "contact ratio not measured: the roll angles do not cover the middle pair's whole engagement with an unloaded position before and after"
                .into(),
        ),
    }
    let pitch_deg = cycle.gear_pair.pinion().angular_pitch().to_degrees();
    let contact_ratio = limits.map(|(s, e)| (e - s) / pitch_deg);
    // single contact: only the middle pair loaded
    let single: Vec<&StepResult> = steps
        .iter()
        .filter(|s| (0..np).all(|p| (p == mid) == cycle.loaded(s, p)))
        .collect();
    let single_pair_force_n = if single.is_empty() {
        notes.push("no position with a single loaded pair".into());
        None
    } else {
        Some(single.iter().map(|s| s.pair_force_n[mid]).sum::<f64>() / single.len() as f64)
    };
    let worst = |f: fn(&StepResult) -> f64| steps.iter().map(f).fold(0.0f64, f64::max);
    let warnings: Vec<String> = steps
        .iter()
        .flat_map(|s| {
            s.warnings
                .iter()
                .map(move |w| format!("{}°: {w}", s.roll_deg))
        })
        .collect();
    let loops = iteration_limits(&steps, cycle.contact.max_iterations);
    notes.extend(loops.warnings());
    write_steps_csv(&out.join("mesh_cycle.csv"), &steps, np)?;
    let (lpstc, hpstc) = cycle.gear_pair.single_contact();
    let (eng_a, eng_e) = cycle.gear_pair.engagement(cycle.gear_pair.middle());
    // TE over the positions where the middle pair carries load (1.5
    // pitches: a whole mesh cycle away from the sector's outer teeth)
    let te: Vec<f64> = steps
        .iter()
        .filter(|s| cycle.loaded(s, mid))
        .map(|s| s.te_urad)
        .collect();
    let te_mean = te.iter().sum::<f64>() / te.len().max(1) as f64;
    let te_pp = te.iter().fold(f64::NEG_INFINITY, |a, &v| a.max(v))
        - te.iter().fold(f64::INFINITY, |a, &v| a.min(v));
    let roll_deg: Vec<f64> = steps.iter().map(|s| s.roll_deg).collect();
    let pair_forces: Vec<Vec<f64>> = (0..cycle.pair.teeth.len())
        .map(|p| steps.iter().map(|s| s.pair_force_n[p]).collect())
        .collect();
    let te_series: Vec<f64> = steps.iter().map(|s| s.te_urad).collect();
    let plot_files = crate::report::cycle_plot::plot_cycle(
        out,
        "",
        &roll_deg,
        &pair_forces,
        &te_series,
        &cycle.pair.teeth,
        nominal,
        cycle.gear_pair.transmission_error_radius(),
    )
    .unwrap_or_else(|e| {
        notes.push(format!("plots not written: {e}"));
        Vec::new()
    });
    let stats = &cycle.system.stats;
    if !(stats.scaled_condition_estimate <= ILL_CONDITIONED) {
        notes.push(format!(
            "the pinned stiffness is ill-conditioned: κ₁ estimate of the diagonally scaled stiffness, which Cholesky's accuracy depends on, {:.2e} (above {ILL_CONDITIONED:.0e}: a solve may lose more than 12 of 16 digits; the backward error per position says whether the solves themselves were stable; unscaled κ₁ {:.2e})",
            stats.scaled_condition_estimate, stats.condition_estimate
        ));
    }
    let mut summary = serde_json::json!({
        "scene": scene.source.display().to_string(),
        "analysis": "fe_contact_mesh_cycle",
        "contact_ratio": contact_ratio,
        "contact_ratio_kinematic": cycle.gear_pair.kinematic_contact_ratio(),
        "single_pair_force_n": single_pair_force_n,
        "nominal_force_n": nominal,
        "single_pair_force_error": single_pair_force_n.map(|f| f / nominal - 1.0),
        "single_contact_positions": single.len(),
        "middle_pair_loaded_deg": limits.map(|(s, e)| [s, e]),
        "middle_pair_kinematic_deg": [eng_a.to_degrees(), eng_e.to_degrees()],
        "kinematic_single_contact_deg": [lpstc.to_degrees(), hpstc.to_degrees()],
        "angular_pitch_deg": pitch_deg,
        "loaded_threshold_fraction": LOADED_FRACTION,
        "positions": steps.len(),
        "refinement_positions": refine_solves,
        "extension_positions": extended,
        "resumed_positions": reused,
        "time_per_position_s": time_per_position_s,
        "setup_s": setup_s,
        "total_s": t_total.elapsed().as_secs_f64(),
        "nodes": cycle.pair.model.mesh.node_count(),
    });
    if let (Some(m), Some(l)) = (summary.as_object_mut(), lubrication) {
        m.insert("lubrication".into(), l);
    }
    let more = serde_json::json!({
        "nodes_per_body": cycle.pair.nodes,
        "elements_per_body": cycle.pair.elements,
        "dofs": stats.dofs,
        "nnz_factor": stats.nnz_factor,
        "factorization_flops": stats.flops,
        "factorization_gflop_per_s": stats.flops / stats.factorization_s.max(1e-9) / 1e9,
        "ordering": stats.ordering,
        "assembly_s": stats.assembly_s,
        "factorization_s": stats.factorization_s,
        "condition_estimate": stats.condition_estimate,
        "scaled_condition_estimate": stats.scaled_condition_estimate,
        "condition_estimate_s": stats.condition_s,
        "threads": crate::fem::solver::parallelism(options.threads).degree(),
        "peak_memory_mb": peak_memory_mb(),
        "estimated_peak_memory_mb": stats.estimated_peak_mb,
    });
    let more2 = serde_json::json!({
        "te_positions": te.len(),
        "te_mean_urad": te_mean,
        "te_peak_to_peak_urad": te_pp,
        "te_peak_to_peak_um": te_pp * cycle.gear_pair.transmission_error_radius() * 1e-3,
        "max_violation_mm": worst(|s| s.max_violation_mm),
        "max_complementarity": worst(|s| s.complementarity),
        "max_equilibrium": worst(|s| s.equilibrium),
        "max_backward_error": worst(|s| s.backward_error),
        "iteration_limits": loops.to_json(),
        "settings": cycle.settings,
        "law": match cycle.pair.model.contact.interactions[0].behavior {
            Some(PressureOverclosure::Linear { slope: Some(s), .. }) =>
                serde_json::to_value(NormalLaw::Penalty { slope: s, automatic: cycle.settings.penalty_factor == 1.0 }).unwrap_or_default(),
            _ => serde_json::to_value(NormalLaw::Hard).unwrap_or_default(),
        },
        "tooth_pairs": cycle.pair.teeth,
        "kinematics": cycle.gear_pair.describe(),
        "files": {
            "csv": "mesh_cycle.csv",
            "plots": plot_files,
            "vtu": if cycle.settings.vtu { "roll_<angle>deg.vtu" } else { "" },
        },
        "notes": notes,
        "warnings": warnings,
        "steps": steps,
    });
    if let (Some(m), Some(a), Some(b)) =
        (summary.as_object_mut(), more.as_object(), more2.as_object())
    {
        m.extend(a.clone());
        m.extend(b.clone());
    }
    let text = serde_json::to_string_pretty(&summary)
        .map_err(|e| FlankError::Model(format!("summary: {e}")))?;
    let p = out.join("summary.json");
    crate::atomic_file::write(&p, text)?;
    // complete: summary.json holds every position
    checkpoint.remove()?;
    let _ = std::fs::remove_file(out.join("mesh_cycle.partial.csv"));
    Ok(summary)
}

/// The error of a run stopped by SIGINT after the positions `steps`: they
/// are in checkpoint.json (and their VTU files), and in
/// `mesh_cycle.partial.csv` for a look; the message says how to resume.
fn interrupted(out: &Path, steps: &[StepResult], np: usize) -> FlankError {
    let mut sorted = steps.to_vec();
    sorted.sort_by(|a, b| a.roll_deg.total_cmp(&b.roll_deg));
    let partial = out.join("mesh_cycle.partial.csv");
    let written = match write_steps_csv(&partial, &sorted, np) {
        Ok(()) => format!(" and {}", partial.display()),
        Err(e) => format!(" ({e})"),
    };
    FlankError::Interrupted(format!(
        "stopped at a position boundary after {} solved position(s); \
         they are kept in {}{written}; resume with the same command and options plus \
         --resume (`flank run SCENE --out {} ... --resume`): only the remaining positions \
         are solved",
        steps.len(),
        out.join(checkpoint::FILE).display(),
        out.display()
    ))
}

/// `roll_…deg.inp`: the pair model with its nodes at the placed positions
/// of `roll_deg` (coupling, clamps, contact pairs as solved), a deck ccx
/// runs (its HARD contact is a 50 E penalty; use the penalty law to compare
/// like with like).
fn write_position_deck(cycle: &MeshCycle, out: &Path, roll_deg: f64) -> Result<(), FlankError> {
    let roll = roll_deg.to_radians();
    let placement = cycle.placement(roll);
    let mut model = cycle.pair.model.clone();
    model.mesh.coords = placement.positions(&model.mesh.coords);
    // only the pairings solved at this position
    model.contact.pairs = (0..cycle.pair.teeth.len())
        .map(|p| model.contact.pairs[cycle.pairing_at(p, roll).0].clone())
        .collect();
    let name = vtu_name(roll_deg).replace(".vtu", ".inp");
    crate::deck::write_deck(&model, &out.join(name))
}

/// The VTU file of a roll angle: `roll_+012.50deg.vtu`.
pub fn vtu_name(roll_deg: f64) -> String {
    format!("roll_{roll_deg:+08.3}deg.vtu")
}

/// `roll_…deg.vtu`: both bodies placed at the roll angle, displacement
/// (global frame) and contact pressure.
fn write_position_vtu(
    cycle: &MeshCycle,
    out: &Path,
    roll_deg: f64,
    solved: &Solved,
) -> Result<(), FlankError> {
    let placement = cycle.placement(roll_deg.to_radians());
    let mut mesh = cycle.pair.model.mesh.clone();
    mesh.coords = placement.positions(&mesh.coords);
    let u = placement.global_vectors(&solved.displacement);
    let p = out.join(vtu_name(roll_deg));
    write_vtu(
        &p,
        &mesh,
        &[
            PointField {
                name: "displacement",
                components: 3,
                values: &u,
            },
            PointField {
                name: "contact_pressure",
                components: 1,
                values: &solved.pressure,
            },
        ],
        &[],
    )
}

fn write_steps_csv(path: &Path, steps: &[StepResult], np: usize) -> Result<(), FlankError> {
    use std::fmt::Write as _;
    let mut s = String::from("roll_deg,reference_deg");
    for p in 1..=np {
        let _ = write!(
            s,
            ",force_pair{p}_n,share_pair{p},position_pair{p}_mm,max_pressure_pair{p}_mpa,closed_nodes_pair{p}"
        );
    }
    s.push_str(",te_urad,te_um,candidates,iterations,columns,max_violation_mm,complementarity,equilibrium,time_s");
    for p in 1..=np {
        let _ = write!(s, ",slave_pair{p}");
    }
    for p in 1..=np {
        let _ = write!(s, ",friction_pair{p}_n");
    }
    s.push('\n');
    for st in steps {
        let _ = write!(
            s,
            "{},{}",
            st.roll_deg,
            st.reference_deg.map_or(String::new(), |v| format!("{v}"))
        );
        for p in 0..np {
            let _ = write!(
                s,
                ",{},{},{},{},{}",
                st.pair_force_n[p],
                st.load_share[p],
                st.kinematic_position_mm[p],
                st.max_pressure_mpa[p],
                st.patch[p].closed_nodes
            );
        }
        let _ = write!(
            s,
            ",{},{},{},{},{},{:e},{:e},{:e},{}",
            st.te_urad,
            st.te_um,
            st.candidates,
            st.active_set_iterations,
            st.delassus_columns,
            st.max_violation_mm,
            st.complementarity,
            st.equilibrium,
            st.time_s
        );
        for b in &st.slave {
            let _ = write!(s, ",{}", b.name());
        }
        for f in &st.friction_force_n {
            let _ = write!(s, ",{f}");
        }
        s.push('\n');
    }
    crate::atomic_file::write(path, s)
}
