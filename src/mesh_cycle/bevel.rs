//! FE contact of a bevel/hypoid pair over its mesh cycle (issue 18 point
//! 3): both bodies meshed by the bevel sector mesher and kept in their own
//! frames (the stiffness is factorized once), the pinion's mount coupled to
//! a reference node that turns about the pinion axis under the torque, the
//! gear's mount clamped, frictionless node-to-surface contact between the
//! drive (right) flanks of every modelled tooth pair, pinion nodes as
//! slaves; per roll angle the bodies are placed by
//! [`GearPair::nominal_frames`] and the condensed contact problem is
//! solved ([`crate::contact::solve::solve_pairs_placed`]).
//!
//! Per position: force per tooth pair, load sharing, loaded transmission
//! error (the pinion's advance under load, expressed at the gear:
//! TE = −Δφ₁ z₁/z₂, arc seconds, the sign of the unloaded TCA's TE),
//! largest contact pressure, the closed slave nodes (the contact pattern)
//! and whether the pinion's tip edge carries load (closed slave nodes on
//! the tip land). `flank run` over the cycle, its files and summary, is
//! [`crate::mesh_cycle::bevel_run`].

use std::collections::HashSet;
use std::time::Instant;

use crate::contact::pairing::{build_pair_placed, PairGeometry, PairingOptions};
use crate::contact::placement::Placement;
use crate::contact::solve::{face_averaged_pressure, solve_pairs_placed, ContactOptions};
use crate::contact::system::ElasticSystem;
use crate::contact::PressureOverclosure;
use crate::error::FlankError;
use crate::fem::ordering::OrderingMethod;
use crate::geometry::gear_pair::GearPair;
use crate::mesh::bevel_body::bevel_body_model;
use crate::mesh::bevel_sector::BevelSectorOptions;
use crate::mesh_cycle::bevel_checks as checks;
use crate::mesh_cycle::pair_model::{combine, set_automatic_penalty, PairBody, PairModel};
use crate::report::fe_pattern::PatternNode;
use crate::scene::Scene;
use crate::settings::{ContactLaw, SlaveBody};
use crate::tca::point_contact::{projection, ARCSEC_PER_RAD};

/// Slave nodes beyond the search distance that penetrate: the search is
/// repeated with twice the distance at most this many times.
const MAX_SEARCH_RAISES: usize = 3;
/// Unloaded interpenetration (mm) that is reported as a warning.
const INTERFERENCE_WARNING_MM: f64 = 1e-3;

/// Options of [`BevelCycle::new`].
#[derive(Clone, Debug)]
pub struct BevelRunOptions {
    pub mesh: BevelSectorOptions,
    /// Search distance of the contact pairing (mm).
    pub search_distance_mm: f64,
    pub threads: usize,
    /// Hard contact (default) or a linear penalty of `penalty_factor` ×
    /// the automatic slope ([`set_automatic_penalty`]).
    pub law: ContactLaw,
    pub penalty_factor: f64,
    /// [`run_bevel`] also writes each position's model as a CalculiX deck
    /// ([`BevelCycle::write_deck`]).
    pub decks: bool,
    /// [`run_bevel`] takes the positions of `out/checkpoint.json` left by
    /// an interrupted run of the same scene and options
    /// ([`crate::mesh_cycle::checkpoint`]).
    pub resume: bool,
    /// Coulomb friction coefficient of the flanks (0 = frictionless): the
    /// FE contact's static Coulomb law ([`crate::contact::friction`]), the
    /// friction resisting the slip of the loading step (the LTCA's
    /// `standstill` model), not the kinematic sliding.
    pub friction_mu: f64,
}

impl Default for BevelRunOptions {
    fn default() -> Self {
        BevelRunOptions {
            mesh: BevelSectorOptions::default(),
            search_distance_mm: 0.1,
            threads: 1,
            law: ContactLaw::Hard,
            penalty_factor: 1.0,
            decks: false,
            resume: false,
            friction_mu: 0.0,
        }
    }
}

/// One solved roll angle.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct BevelStep {
    pub roll_deg: f64,
    /// Per tooth pair (pinion tooth k = 1..n against its mate).
    pub pair_force_n: Vec<f64>,
    pub load_share: Vec<f64>,
    pub max_pressure_mpa: Vec<f64>,
    pub closed_nodes: Vec<usize>,
    /// Whether closed slave nodes lie on the pinion's tip edge.
    pub pinion_tip_edge: Vec<bool>,
    /// Smallest initial gap g₀ of each pair's candidates in the nominal
    /// placement (mm; < 0: the unloaded flanks interpenetrate there, and
    /// the pinion's rotation resolves it before it carries load: the
    /// loaded TE then contains that unloaded TE).
    pub min_initial_gap_mm: Vec<f64>,
    /// Loaded transmission error at the gear (arc seconds; module docs).
    pub te_arcsec: f64,
    /// Σ (pair forces' moments about the pinion axis) / T − 1.
    pub moment_balance: f64,
    pub candidates: usize,
    pub active_set_iterations: usize,
    pub max_violation_mm: f64,
    pub complementarity: f64,
    pub warnings: Vec<String>,
    pub time_s: f64,
    /// With friction (μ > 0): magnitude of the resultant tangential force
    /// per tooth pair (N), stick and slip node counts, whether the Coulomb
    /// law was met, its largest residual, and the fixed point's effort
    /// (Tresca problems, working-set rounds, last relative change of the
    /// slip bounds).
    #[serde(default)]
    pub friction_force_n: Vec<f64>,
    #[serde(default)]
    pub stick_nodes: usize,
    #[serde(default)]
    pub slip_nodes: usize,
    #[serde(default)]
    pub friction_converged: Option<bool>,
    #[serde(default)]
    pub coulomb_residual: f64,
    #[serde(default)]
    pub friction_iterations: usize,
    #[serde(default)]
    pub friction_rounds: usize,
    #[serde(default)]
    pub friction_bound_change: f64,
    /// The loaded slave nodes (the contact pattern of this position).
    #[serde(skip)]
    pub pattern: Vec<PatternNode>,
}

/// A factorized hypoid pair model, ready to solve roll angles.
pub struct BevelCycle {
    pub pair: std::sync::Arc<crate::geometry::bevel::pair::BevelPair>,
    pub model: PairModel,
    pub system: ElasticSystem,
    /// The pairing and active-set options, and the pinion torque (N·mm).
    pub(super) contact: ContactOptions,
    pub(super) torque: f64,
    /// Slave nodes on the pinion's tip land.
    tip_nodes: HashSet<usize>,
}

impl BevelCycle {
    /// Meshes both members, builds the pair model and factorizes it.
    pub fn new(scene: &Scene, options: &BevelRunOptions) -> Result<Self, FlankError> {
        let model = Self::pair_model(scene, options)?;
        Self::factorize(scene, model, options)
    }

    /// Both members meshed and combined into the pair model (the law of
    /// `options`), not yet factorized.
    pub fn pair_model(scene: &Scene, options: &BevelRunOptions) -> Result<PairModel, FlankError> {
        let bevel = scene.bevel("the bevel/hypoid FE mesh cycle")?;
        checks::check_torque(scene)?;
        let torque = scene.load.torque_nmm;
        let pinion = bevel_body_model(
            &bevel.bodies[0],
            "pinion",
            &scene.pinion_material,
            &options.mesh.member(true),
            None,
        )?;
        let gear = bevel_body_model(
            &bevel.bodies[1],
            "gear",
            &scene.gear_material,
            &options.mesh.member(false),
            None,
        )?;
        let mut model = combine(
            bevel.pair.as_ref(),
            [
                PairBody::of("pinion", &pinion.model, &pinion.sector.flank_uv),
                PairBody::of("gear", &gear.model, &gear.sector.flank_uv),
            ],
            torque,
            PressureOverclosure::Hard,
            SlaveBody::Pinion,
        )?;
        if options.law == ContactLaw::Penalty {
            set_automatic_penalty(&mut model, options.penalty_factor)?;
        }
        if !(0.0..=1.0).contains(&options.friction_mu) {
            return Err(FlankError::Model(format!(
                "friction coefficient {} must be in 0…1",
                options.friction_mu
            )));
        }
        if options.friction_mu > 0.0 {
            for i in model.model.contact.interactions.iter_mut() {
                i.friction = Some(crate::contact::Friction {
                    mu: options.friction_mu,
                    stick_slope: None,
                });
            }
        }
        Ok(model)
    }

    /// The contact options of the run's pairing and active set.
    fn contact_options(options: &BevelRunOptions) -> ContactOptions {
        ContactOptions {
            ordering: OrderingMethod::Metis,
            threads: options.threads,
            recover_stress: false,
            pairing: PairingOptions {
                search_distance: Some(options.search_distance_mm),
                max_initial_penetration: None,
            },
            max_iterations: 1000,
            gap_tolerance: None,
        }
    }

    /// Factorizes the pair model of [`Self::pair_model`].
    pub fn factorize(
        scene: &Scene,
        model: PairModel,
        options: &BevelRunOptions,
    ) -> Result<Self, FlankError> {
        let bevel = scene.bevel("the bevel/hypoid FE mesh cycle")?;
        let torque = scene.load.torque_nmm;
        let system = ElasticSystem::new(
            &model.model,
            &model.contact_nodes,
            OrderingMethod::Metis,
            options.threads,
        )?;
        if system.floating.modes.len() != 1 {
            return Err(FlankError::Model(format!(
                "the hypoid pair model should have exactly one floating mode (the pinion's rotation), found {}",
                system.floating.modes.len()
            )));
        }
        let tip_nodes = model
            .model
            .mesh
            .node_sets
            .get("PINION_TIP_LAND")
            .map(|v| v.iter().copied().collect())
            .unwrap_or_default();
        Ok(BevelCycle {
            pair: bevel.pair.clone(),
            model,
            system,
            contact: Self::contact_options(options),
            torque,
            tip_nodes,
        })
    }

    /// One mesh cycle: the pinion roll of one tooth pitch.
    pub fn cycle_deg(&self) -> f64 {
        self.pair.tooth_roll_step().abs().to_degrees()
    }

    /// Where both bodies sit at roll angle `roll_deg` (the pair's nominal
    /// frames).
    pub fn placement(&self, roll_deg: f64) -> Placement {
        Placement {
            body_of: self.model.body_of.clone(),
            frames: self.pair.nominal_frames(roll_deg.to_radians()).to_vec(),
        }
    }

    /// Writes the pair model at roll angle `roll_deg` as a CalculiX deck
    /// `path`, in the pinion's own frame: the pinion where it is meshed
    /// (its axis the z axis, so the `*RIGID BODY` of its mount turns about
    /// z under the torque, as in the model), the gear moved to its place
    /// relative to it (P⁻¹G of the pair's frames; contact and the clamped
    /// mount do not depend on the frame), one `*CONTACT PAIR` per tooth
    /// pair (pinion flanks slave), the normal law of the run. Solved as it
    /// is (flank `solve`, ccx) it is this position's problem.
    pub fn write_deck(&self, roll_deg: f64, path: &std::path::Path) -> Result<(), FlankError> {
        crate::deck::write_deck(&self.deck_model(roll_deg), path)
    }

    /// The model [`Self::write_deck`] writes.
    pub fn deck_model(&self, roll_deg: f64) -> crate::fem::model::Model {
        let mut model = self.model.model.clone();
        let placed = self.placement(roll_deg);
        let to_pinion = placed.frames[0].inverse();
        let relative = Placement {
            body_of: placed.body_of,
            frames: placed.frames.iter().map(|f| to_pinion.compose(f)).collect(),
        };
        model.mesh.coords = relative.positions(&model.mesh.coords);
        model
    }

    /// Solves roll angle `roll_deg` with the factorized stiffness.
    pub fn solve(&self, roll_deg: f64) -> Result<BevelStep, FlankError> {
        let t = Instant::now();
        let placement = self.placement(roll_deg);
        let model = &self.model.model;
        let at = |e: FlankError| match e {
            FlankError::Solver(m) => FlankError::Solver(format!("roll angle {roll_deg}°: {m}")),
            FlankError::Model(m) => FlankError::Model(format!("roll angle {roll_deg}°: {m}")),
            other => other,
        };
        let mut options = self.contact.clone();
        let mut warnings = Vec::new();
        let mut raises = 0;
        let pair_index: Vec<usize> = self
            .model
            .pairings
            .iter()
            .map(|p| p[0].expect("pinion-slave pairs"))
            .collect();
        let (pairs, state) = loop {
            let pairs: Vec<PairGeometry> = pair_index
                .iter()
                .map(|&p| build_pair_placed(model, &placement, p, &options.pairing))
                .collect::<Result<_, _>>()
                .map_err(at)?;
            let state = solve_pairs_placed(model, &self.system, &pairs, &placement, &options)
                .map_err(at)?;
            if state.uncovered == 0 || raises >= MAX_SEARCH_RAISES {
                if state.uncovered > 0 {
                    warnings.push(format!(
                        "{} slave node(s) beyond the search distance penetrated after {MAX_SEARCH_RAISES} raises",
                        state.uncovered
                    ));
                }
                break (pairs, state);
            }
            let d = options.pairing.search_distance.unwrap_or(0.1);
            warnings.push(format!(
                "{} slave node(s) beyond the search distance {d} mm penetrated: solved again with {} mm",
                state.uncovered,
                2.0 * d
            ));
            options.pairing.search_distance = Some(2.0 * d);
            raises += 1;
        };
        let np = pairs.len();
        let mut step = BevelStep {
            roll_deg,
            pair_force_n: vec![0.0; np],
            load_share: vec![0.0; np],
            max_pressure_mpa: vec![0.0; np],
            closed_nodes: vec![0; np],
            pinion_tip_edge: vec![false; np],
            min_initial_gap_mm: pairs
                .iter()
                .map(|g| {
                    g.constraints
                        .iter()
                        .map(|c| c.g0)
                        .fold(f64::INFINITY, f64::min)
                })
                .collect(),
            candidates: state.constraints.len(),
            active_set_iterations: state.active_set.iterations,
            max_violation_mm: state.active_set.max_violation,
            complementarity: state.active_set.complementarity,
            warnings: warnings
                .into_iter()
                .chain(state.warnings.iter().cloned())
                .collect(),
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
        // of the contact forces on the pinion, in the drive sense
        let sense = self.pair.rotation_axes()[0][2].signum();
        let mut moment = 0.0;
        let mut offset = 0;
        for (p, g) in pairs.iter().enumerate() {
            let k = g.constraints.len();
            let lam = &state.active_set.lambda[offset..offset + k];
            // friction: the force on each slave node along the slip rows'
            // slave terms (the master's tangents in the pinion's own
            // frame), their resultant per pair and their moments
            if let Some(fr) = &state.friction {
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
            for (i, c) in g.constraints.iter().enumerate() {
                step.pair_force_n[p] += lam[i];
                step.max_pressure_mpa[p] = step.max_pressure_mpa[p].max(smooth[i]);
                if lam[i] > 0.0 {
                    step.closed_nodes[p] += 1;
                    let own = model.mesh.coords[c.slave];
                    let global = placement.frames[0].place(own);
                    let g = &placement.frames[1];
                    let in_gear = g.rotate_back([
                        global[0] - g.translation[0],
                        global[1] - g.translation[1],
                        global[2] - g.translation[2],
                    ]);
                    step.pattern.push(PatternNode {
                        pair: p + 1,
                        projection_mm: [
                            projection(self.pair.pinion(), own),
                            projection(self.pair.gear(), in_gear),
                        ],
                        pressure_mpa: smooth[i],
                    });
                    if self.tip_nodes.contains(&c.slave) {
                        step.pinion_tip_edge[p] = true;
                    }
                    // the force on the slave (pinion) node is λ n, n the
                    // master's normal in the slave's own frame (the slave's
                    // term of the gap's linear form)
                    let x = model.mesh.coords[c.slave];
                    let f = c.terms[0].1;
                    moment += lam[i] * (x[0] * f[1] - x[1] * f[0]) * sense;
                }
            }
            offset += k;
        }
        for (p, &g) in step.min_initial_gap_mm.iter().enumerate() {
            if g < -INTERFERENCE_WARNING_MM {
                step.warnings.push(format!(
                    "tooth pair {} (pinion tooth {} / gear tooth {}): the unloaded flanks interpenetrate by {:.4} mm in the nominal placement",
                    p + 1,
                    self.model.teeth[p].0,
                    self.model.teeth[p].1,
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
        step.moment_balance = -moment / self.torque - 1.0;
        let rz = state.coupling_motion[0][5];
        step.te_arcsec = -rz * sense * self.pair.ratio() * ARCSEC_PER_RAD;
        if !step.te_arcsec.is_finite() {
            return Err(at(FlankError::Solver(
                "the pinion rotation is not finite".into(),
            )));
        }
        step.time_s = t.elapsed().as_secs_f64();
        Ok(step)
    }
}

/// Positions of the default run over one mesh cycle.
pub const DEFAULT_POSITIONS: usize = 20;

/// A factorized cycle after the input checks (see [`BevelCycle::checked`]).
pub struct CheckedCycle {
    pub cycle: BevelCycle,
    /// The unloaded pairs' exact depths at the roll angles checked.
    pub unloaded: Vec<checks::UnloadedPair>,
    /// What the checks could not establish (shank with a partial sector;
    /// the point TCA did not run).
    pub warnings: Vec<String>,
    /// Time of the checks and of the factorization (s).
    pub checks_s: f64,
    pub factorization_s: f64,
}

impl BevelCycle {
    /// The cycle of `scene` for the roll angles `rolls`, built only after
    /// the checks that refuse bad inputs before the factorization
    /// ([`crate::mesh_cycle::bevel_checks`]): the torque, the members
    /// meshed (the more basic error first), a sector that holds every pair
    /// in mesh at these angles, no gross unloaded interpenetration. Every
    /// FE contact cycle of a bevel pair goes through it (`flank run`,
    /// `flank compare`).
    pub fn checked(
        scene: &Scene,
        options: &BevelRunOptions,
        rolls: &[f64],
    ) -> Result<CheckedCycle, FlankError> {
        let bevel = scene.bevel("the bevel/hypoid FE mesh cycle")?;
        let mut warnings = Vec::new();
        let t_check = Instant::now();
        // meshing first (it checks the torque): a member that cannot be
        // meshed is the more basic error
        let model = BevelCycle::pair_model(scene, options)?;
        if options.mesh.shank.is_some() && scene.mesh.teeth_in_sector < bevel.blank_inputs.z1 {
            warnings.push(crate::mesh::bevel_sector::SHANK_SECTOR_WARNING.to_string());
        }
        if checks::check_sector(scene, rolls)?.is_none() {
            warnings.push(
                "the point TCA did not run: whether the sector holds every pair in mesh is not checked"
                    .to_string(),
            );
        }
        let unloaded = checks::exact_depths(
            &model,
            bevel.pair.as_ref(),
            rolls,
            &BevelCycle::contact_options(options).pairing,
        )?;
        checks::check_interpenetration(scene, &model, &unloaded)?;
        let checks_s = t_check.elapsed().as_secs_f64();
        let t0 = Instant::now();
        let cycle = BevelCycle::factorize(scene, model, options)?;
        Ok(CheckedCycle {
            cycle,
            unloaded,
            warnings,
            checks_s,
            factorization_s: t0.elapsed().as_secs_f64(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::gear_pair::Flank;
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
        let cycle = BevelCycle::new(
            &s,
            &BevelRunOptions {
                mesh: BevelSectorOptions {
                    flank_size: 1.5,
                    base_size: 6.0,
                    ..Default::default()
                },
                threads: 2,
                ..Default::default()
            },
        )
        .unwrap();
        let st = cycle.solve(0.0).unwrap();
        println!("{st:?}");
        assert!(st.moment_balance.abs() < 1e-10, "{}", st.moment_balance);
        assert!(st.max_violation_mm < 1e-9 && st.complementarity.abs() < 1e-6);
        assert!((st.load_share.iter().sum::<f64>() - 1.0).abs() < 1e-12);
        assert!(
            st.min_initial_gap_mm[1] > -1e-3,
            "{:?}",
            st.min_initial_gap_mm
        );
        // the deepest candidate of pinion tooth 1 / gear tooth 3: its FE
        // gap against the exact surfaces' signed distance at the same
        // pinion point; they differ by the master faces' deviation from
        // the gear flank (< 1 % of the flank size, verification/bevel_sector_mesh)
        let pair = &cycle.pair;
        let placement = Placement {
            body_of: cycle.model.body_of.clone(),
            frames: pair.nominal_frames(0.0).to_vec(),
        };
        let g = build_pair_placed(
            &cycle.model.model,
            &placement,
            cycle.model.pairings[0][0].unwrap(),
            &cycle.contact.pairing,
        )
        .unwrap();
        let c = g
            .constraints
            .iter()
            .min_by(|a, b| a.g0.total_cmp(&b.g0))
            .unwrap();
        assert_eq!(c.g0, st.min_initial_gap_mm[0]);
        let (u, v) = cycle.model.flank_uv[&c.slave];
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
