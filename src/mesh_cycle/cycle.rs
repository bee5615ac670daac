//! The quasi-static mesh cycle of a gear pair in FE contact
//! ([`MeshCycle`]): one contact solve per roll angle with the stiffness
//! factorized once, its result per position ([`StepResult`]) and the
//! bookkeeping of its bounded loops. The run over a scene, its options and
//! files, is [`crate::mesh_cycle::run`].
//!
//! Reuse: the pair model keeps both bodies in their own frames, so K and
//! its Cholesky factor ([`ElasticSystem`]) are the same at every roll
//! angle. Per position only the contact geometry is rebuilt (bodies placed
//! by [`GearPair::nominal_frames`](crate::geometry::gear_pair::GearPair::nominal_frames), search and projection) and the condensed
//! problem is solved: one solve for the gaps under the torque, one per
//! Delassus column of a constraint that enters the active set, one final
//! solve. Nothing is refactorized.

use crate::compliance::body::BodyMeshOptions;
use crate::contact::pairing::{build_pair_placed, PairGeometry, PairingOptions};
use crate::contact::placement::Placement;
use crate::contact::solve::{face_averaged_pressure, solve_pairs_placed, ContactOptions};
use crate::contact::system::ElasticSystem;
use crate::contact::{Friction, PressureOverclosure};
use crate::error::FlankError;
use crate::fem::ordering::OrderingMethod;
use crate::geometry::gear_pair::{engagement_roll_angles, LineContactPair};
use crate::iteration_limits::{IterationLimits, LoopEnd};
use crate::mesh_cycle::pair_model::{pair_model, PairModel};
use crate::scene::Scene;
use crate::settings::{ContactLaw, SlaveBody};
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
    pub gear_pair: Arc<dyn LineContactPair>,
    pub pair: PairModel,
    pub system: ElasticSystem,
    pub settings: RunSettings,
    pub(crate) contact: ContactOptions,
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
