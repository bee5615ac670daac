//! Compliance-matrix LTCA of a bevel/hypoid pair over its mesh cycle
//! (`flank ltca` on a hypoid scene; issue 19 point 3, frictionless).
//!
//! Seeds 001 and 003 put M candidate points on the major axis of each
//! tooth pair's contact ellipse, interpolate the nodal compliance tensors
//! there and solve the contact problem per position. flank does the same
//! with its own pieces, none of them forked:
//!
//! * the compliance tensors of both bevel sector bodies
//!   ([`crate::compliance::run::body_tensor`], cached as for spur pairs);
//! * the point TCA of the pair ([`crate::tca::point_contact`]: flank
//!   contacts of every tooth pair over the trace, each with its curvature
//!   ellipse at the approach δ);
//! * per position and tooth pair, the major axis as a contact line of K
//!   points ([`crate::tca::major_axis::major_axis_line`]: separations by
//!   closest point between the exact surfaces, moment arms, radii across
//!   the axis), spanning the axis out to the separation `span_approach_mm`;
//! * the LTCA problem of those lines ([`LtcaBodies::solve`]: compliance of
//!   contact cells from the tensors, the half-space near field across the
//!   axis with the local Hertz width of the strip, the contact QP).
//!
//! The strip model across the axis is the line-contact one: each point
//! stands for a strip of the ellipse of width 2a_c/K along the axis, loaded
//! as a slice of a line contact with the relative curvature across the
//! axis (Hertz p = √(P′E*/(πR))); for the elongated ellipses of hypoid
//! bearings (a/b ≈ 5–15) that is the slender-ellipse limit of the Hertz
//! solution. Positions are the point TCA's grid (`positions` per pitch);
//! requested roll angles are taken at the nearest grid position.
//!
//! **Edge contact** (seed 000, [`crate::ltca::edges`]): with
//! [`BevelLtcaOptions::edges`] the point TCA runs with edges on and a pair
//! in edge contact contributes K points along the edge; `Both` runs the
//! variant with edges and the one without on the same tensors.
//!
//! Outputs (`out`): the files of every pair kind's LTCA
//! ([`crate::ltca::outputs`]: `ltca_cycle.csv` per position,
//! `ltca_positions.csv` per position and tooth pair, `ltca_points.csv` the
//! load along every axis), `summary.json` (the serialization of
//! [`LtcaResult`]); with `edges = Both` the CSVs of each variant in
//! `out/with_edges/` and `out/without_edges/`, and summary.json with one
//! object per variant under `with_edges` and `without_edges`.

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use crate::compliance::body::{bevel_scene_body, BodyMeshOptions};
use crate::compliance::cache::FileFormat;
use crate::compliance::run::{body_tensor, BodyTensorOptions};
use crate::compliance::tensor_cache::ComplianceCache;
use crate::compliance::FlankInterpolator;
use crate::error::FlankError;
use crate::fem::static_analysis::peak_memory_mb;
use crate::geometry::gear_pair::GearPair;
use crate::geometry::tangency::ContactSystem;
use crate::ltca::cycle::LtcaOptions;
use crate::ltca::edges::{edge_line, EdgeLine};
use crate::ltca::local::contact_modulus;
use crate::ltca::model::{LtcaBodies, PositionResult};
use crate::ltca::outputs::{write_cycle_csv, write_points_csv, write_positions_csv};
use crate::ltca::solve_settings::{LtcaFriction, LtcaSettings};
use crate::ltca::summary::{
    peak_to_peak, shares, BevelLtcaSummary, EdgeVariantRatios, EdgeVariantSummaries, KindSummary,
    LtcaResult, LtcaStep, LtcaSummary, SCHEMA_VERSION,
};
use crate::scene::Scene;
use crate::settings::EdgeVariants;
use crate::tca::major_axis::major_axis_line;
use crate::tca::point_contact::{point_tca, PointTca, PointTcaSettings};
use crate::tca::TcaPosition;

/// Options of [`BevelLtca::new`] and [`run_bevel`].
#[derive(Clone, Debug)]
pub struct BevelLtcaOptions {
    pub out: PathBuf,
    /// Compliance mesh (bevel sector sizes; default m_mn/8, m_mn/2).
    pub mesh: BodyMeshOptions,
    /// K: candidate points on each pair's major axis.
    pub points_per_pair: usize,
    /// Positions per mesh cycle (the point TCA's grid).
    pub positions: usize,
    /// Roll angles (deg); default one cycle centred on roll 0.
    pub roll_angles_deg: Option<Vec<f64>>,
    /// Separation (mm) out to which the candidate axis runs.
    pub span_approach_mm: f64,
    pub settings: LtcaSettings,
    /// Coulomb friction coefficient (0: frictionless), load increments,
    /// and whether every position is also solved by Lemke's method.
    pub friction_mu: f64,
    pub increments: usize,
    pub cross_check: bool,
    pub friction_model: crate::settings::FrictionModel,
    pub cache: Option<PathBuf>,
    pub threads: usize,
    /// Edge contact (module docs): [`BevelLtca::new`] traces the TCA with
    /// edges for `With` and `Both`; [`run_bevel`] runs the variants named.
    pub edges: EdgeVariants,
}

impl Default for BevelLtcaOptions {
    fn default() -> Self {
        BevelLtcaOptions {
            out: PathBuf::from("out"),
            mesh: BodyMeshOptions::default(),
            points_per_pair: DEFAULT_POINTS_PER_PAIR,
            positions: 20,
            roll_angles_deg: None,
            span_approach_mm: DEFAULT_SPAN_APPROACH_MM,
            settings: LtcaSettings::default(),
            friction_mu: 0.0,
            increments: 10,
            cross_check: false,
            friction_model: Default::default(),
            cache: None,
            threads: 0,
            edges: EdgeVariants::Without,
        }
    }
}

impl BevelLtcaOptions {
    /// The hypoid LTCA's options of a scene: each one from `o` (the
    /// command line), else the scene's `[analyses.ltca]` (its spur-only
    /// keys are refused when the scene is read), else the default. The
    /// options only a spur/helical LTCA has are refused with the reason.
    pub fn merged(scene: &Scene, o: &LtcaOptions) -> Result<Self, FlankError> {
        let refuse = |m: &str| Err(FlankError::Model(m.into()));
        if o.flank_region == Some(crate::settings::FlankRegion::Active) {
            return refuse("--flank-region active: implemented for spur/helical pairs only (a bevel/hypoid LTCA takes the full flank)");
        }
        if o.compression.is_some_and(|c| c.epsilon().is_some()) {
            return refuse("--compression: implemented for spur/helical pairs only");
        }
        let d = BevelLtcaOptions::default();
        let a = scene.analyses.ltca.clone().unwrap_or_default();
        let mut settings = d.settings.clone();
        if let Some(s) = o.solver.or(a.solver) {
            settings.qp.solver = s;
        }
        if let Some(l) = o.local.or(a.local) {
            settings.local = l;
        }
        if let Some(f) = o.fe_cell_factor.or(a.fe_cell_factor) {
            settings.fe_cell_factor = f;
        }
        if let Some(n) = a.local_iterations {
            settings.local_iterations = n;
        }
        settings.condition = o.condition;
        let friction_mu = o.friction_mu.or(a.friction_mu).unwrap_or(0.0);
        if friction_mu == 0.0
            && (o.cross_check || o.increments.is_some() || o.friction_model.is_some())
        {
            return refuse("--increments, --cross-check and --friction-model need friction (--friction-mu > 0 or [analyses.ltca] friction_mu)");
        }
        Ok(BevelLtcaOptions {
            out: o.out.clone(),
            mesh: o.mesh,
            points_per_pair: o
                .points_per_line
                .or(a.points_per_line)
                .unwrap_or(d.points_per_pair),
            roll_angles_deg: o.roll_angles_deg.clone().or(a.roll_angles_deg),
            span_approach_mm: o.span_approach_mm.unwrap_or(d.span_approach_mm),
            friction_mu,
            increments: o.increments.or(a.increments).unwrap_or(d.increments),
            cross_check: o.cross_check,
            friction_model: o.friction_model.or(a.friction_model).unwrap_or_default(),
            settings,
            cache: o.cache.clone(),
            threads: o.threads,
            edges: o.edges.or(a.edges).unwrap_or(d.edges),
            positions: a.positions.unwrap_or(d.positions),
        })
    }
}

/// Default K on each major axis.
pub const DEFAULT_POINTS_PER_PAIR: usize = 21;
/// Default span of the candidate axis: where the unloaded separation
/// reaches 40 µm, beyond the approach of a loaded hypoid contact at its
/// rated torque (seed 003's FE: ≈ 20–30 µm); a loaded end point is
/// reported ([`PositionResult`] points at the ends).
pub const DEFAULT_SPAN_APPROACH_MM: f64 = 0.04;

/// A prepared hypoid LTCA: tensors, point TCA, settings.
pub struct BevelLtca {
    pub pair: Arc<crate::geometry::bevel::pair::BevelPair>,
    pub tca: PointTca,
    pub bodies: LtcaBodies,
    pub options: BevelLtcaOptions,
    pub torque: f64,
    /// Seconds spent on the tensors (computed or read) and the TCA.
    pub compliance_s: f64,
    pub tca_s: f64,
    pub flank_nodes: [usize; 2],
    /// Whether the TCA traced edge contacts and they are candidates.
    pub edges: bool,
}

impl BevelLtcaOptions {
    /// Checks the options against the scene before anything is computed
    /// or written.
    pub fn validate(&self, scene: &Scene) -> Result<(), FlankError> {
        let torque = scene.load.torque_nmm;
        if !(torque > 0.0 && torque.is_finite()) {
            return Err(FlankError::Model(format!(
                "LTCA needs a positive pinion torque ([load] torque_nm); got {} N·m",
                torque / 1000.0
            )));
        }
        if !(1..=200).contains(&self.points_per_pair) {
            return Err(FlankError::Model(format!(
                "--points-per-line {}: between 1 and 200 points per major axis are needed",
                self.points_per_pair
            )));
        }
        if !(4..=400).contains(&self.positions) {
            return Err(FlankError::Model(format!(
                "positions per cycle {}: between 4 and 400 are needed",
                self.positions
            )));
        }
        if !(self.span_approach_mm > 0.0 && self.span_approach_mm <= 1.0) {
            return Err(FlankError::Model(format!(
                "--span-approach-mm {}: a separation in (0, 1] mm is needed",
                self.span_approach_mm
            )));
        }
        if let Some(r) = self
            .roll_angles_deg
            .iter()
            .flatten()
            .find(|r| !r.is_finite())
        {
            return Err(FlankError::Model(format!(
                "--roll-angles: {r} is not a number"
            )));
        }
        self.friction(scene)?;
        crate::compliance::body::bevel_sector_options(scene, &self.mesh)?;
        Ok(())
    }

    /// The checked friction settings (`None` for μ = 0).
    fn friction(&self, scene: &Scene) -> Result<Option<LtcaFriction>, FlankError> {
        LtcaFriction::checked(
            self.friction_mu,
            self.increments,
            self.friction_model,
            self.cross_check,
            scene.load.speed_rpm,
            &scene.source,
        )
    }
}

impl BevelLtca {
    pub fn new(scene: &Scene, options: &BevelLtcaOptions) -> Result<Self, FlankError> {
        let bevel = scene.bevel("the bevel/hypoid LTCA")?;
        options.validate(scene)?;
        let torque = scene.load.torque_nmm;
        let t = Instant::now();
        let campaign = match &options.cache {
            Some(d) => Some(ComplianceCache::shared(d, FileFormat::default_format())?),
            None => None,
        };
        let topts = BodyTensorOptions::for_ltca(options.threads, campaign.as_deref());
        let mut tensors = Vec::new();
        for name in ["pinion", "gear"] {
            let body =
                bevel_scene_body(scene, name, &options.mesh).map_err(|e| mesh_hint(scene, e))?;
            tensors.push(body_tensor(&body, &topts, &options.out)?.tensor);
        }
        let compliance_s = t.elapsed().as_secs_f64();
        let edges = options.edges != EdgeVariants::Without;
        let (tca, tca_s) = trace(
            bevel.pair.as_ref(),
            options.positions,
            edges,
            scene.load.speed_rpm,
        )?;
        // the mean contact's moment arm: the nominal normal force's
        let arm = tca
            .positions
            .iter()
            .min_by(|a, b| a.roll_rad.abs().total_cmp(&b.roll_rad.abs()))
            .and_then(|p| p.pairs.iter().find(|c| c.offset == 0))
            .map(|c| c.moment_arm_mm[0])
            .filter(|a| *a > 0.0)
            .ok_or_else(|| {
                FlankError::Model("LTCA: the middle pair has no contact at roll 0".into())
            })?;
        let [pinion, gear] = [Arc::clone(&tensors[0]), Arc::clone(&tensors[1])];
        let grids = [
            FlankInterpolator::new(&pinion)?.grids(),
            FlankInterpolator::new(&gear)?.grids(),
        ];
        let flank_nodes = [pinion.node_count(), gear.node_count()];
        let mut options = options.clone();
        options.settings.friction = options.friction(scene)?;
        let bodies = LtcaBodies {
            tensors: [pinion, gear],
            grids,
            pair: Arc::clone(&bevel.pair) as Arc<dyn GearPair>,
            nominal_moment_arm_mm: arm,
            te_radius_mm: arm,
            contact_modulus: contact_modulus(
                [scene.pinion_material.young, scene.gear_material.young],
                [scene.pinion_material.poisson, scene.gear_material.poisson],
            ),
        };
        Ok(BevelLtca {
            pair: Arc::clone(&bevel.pair),
            tca,
            bodies,
            options,
            torque,
            compliance_s,
            tca_s,
            flank_nodes,
            edges,
        })
    }

    /// The same tensors with the TCA traced with edge contact on or off
    /// (the other variant of a `Both` run).
    pub fn with_edges(&self, edges: bool, speed_rpm: f64) -> Result<Self, FlankError> {
        let (tca, tca_s) = trace(self.pair.as_ref(), self.options.positions, edges, speed_rpm)?;
        let b = &self.bodies;
        Ok(BevelLtca {
            pair: Arc::clone(&self.pair),
            tca,
            bodies: LtcaBodies {
                tensors: [Arc::clone(&b.tensors[0]), Arc::clone(&b.tensors[1])],
                grids: [Arc::clone(&b.grids[0]), Arc::clone(&b.grids[1])],
                pair: Arc::clone(&b.pair),
                nominal_moment_arm_mm: b.nominal_moment_arm_mm,
                te_radius_mm: b.te_radius_mm,
                contact_modulus: b.contact_modulus,
            },
            options: self.options.clone(),
            torque: self.torque,
            compliance_s: 0.0,
            tca_s,
            flank_nodes: self.flank_nodes,
            edges,
        })
    }

    /// The mesh cycle (deg): one pinion pitch.
    pub fn cycle_deg(&self) -> f64 {
        self.tca.pitch_rad.to_degrees()
    }

    /// The TCA grid position nearest to `roll_deg`, as the LTCA's contact
    /// lines (one major axis per tooth pair in the sector in flank contact;
    /// with [`Self::edges`] one edge line per pair in edge contact).
    pub fn position(&self, roll_deg: f64) -> Result<TcaPosition, FlankError> {
        Ok(self.position_and_notes(roll_deg)?.0)
    }

    /// [`Self::position`] with notes on edge contacts left out or taken
    /// whole ([`crate::ltca::edges`]).
    fn position_and_notes(&self, roll_deg: f64) -> Result<(TcaPosition, Vec<String>), FlankError> {
        let Some(p) = self.tca_at(roll_deg) else {
            return Err(FlankError::Model(format!(
                "LTCA: roll angle {roll_deg}° lies beyond the traced contact ({:.3}° … {:.3}°, and a pitch on either side)",
                self.tca.positions.first().map(|p| p.roll_rad.to_degrees()).unwrap_or(f64::NAN),
                self.tca.positions.last().map(|p| p.roll_rad.to_degrees()).unwrap_or(f64::NAN)
            )));
        };
        // one major axis per pair, the pairs in parallel
        use rayon::prelude::*;
        let (k, delta, span) = (
            self.options.points_per_pair,
            self.tca.settings.approach_mm,
            self.options.span_approach_mm,
        );
        let built: Vec<_> = p
            .pairs
            .par_iter()
            .map(|c| {
                if c.system == ContactSystem::Flank {
                    major_axis_line(self.pair.as_ref(), c, p.roll_rad, k, delta, span)
                        .map(|l| (l, None))
                } else if self.edges {
                    Ok(
                        match edge_line(self.pair.as_ref(), c, p.roll_rad, k, delta, span)? {
                            Some(EdgeLine::Line { line, whole_edge }) => (
                                Some(line),
                                whole_edge.then(|| {
                                    format!(
                                        "{:.3}°: the {} contact of pinion tooth {} has no closed patch at δ: its whole edge is the candidate line",
                                        p.roll_rad.to_degrees(),
                                        c.system.name(),
                                        c.teeth.map(|t| t[0]).unwrap_or(0)
                                    )
                                }),
                            ),
                            Some(EdgeLine::Unsupported(e)) => (
                                None,
                                Some(format!(
                                    "{:.3}°: the {} contact of pinion tooth {} is left out ({} edges are not candidates, crate::ltca::edges)",
                                    p.roll_rad.to_degrees(),
                                    c.system.name(),
                                    c.teeth.map(|t| t[0]).unwrap_or(0),
                                    e.name()
                                )),
                            ),
                            Some(EdgeLine::Empty) | None => (None, None),
                        },
                    )
                } else {
                    Ok((None, None))
                }
            })
            .collect::<Result<Vec<_>, FlankError>>()?;
        let mut lines = Vec::new();
        let mut notes = Vec::new();
        for (l, n) in built {
            lines.extend(l);
            notes.extend(n);
        }
        let unloaded = lines
            .iter()
            .flat_map(|l| l.points.iter())
            .map(|q| q.separation_mm / q.moment_arm_mm)
            .fold(f64::INFINITY, f64::min);
        Ok((
            TcaPosition {
                roll: p.roll_rad,
                unloaded_te_rad: unloaded,
                lines,
            },
            notes,
        ))
    }

    /// The TCA grid position nearest to `roll_deg` (within half a grid
    /// step). The TCA lists positions over the middle pair's trace only;
    /// a roll beyond it is taken from the position m tooth steps away,
    /// every pair's offset raised by m (pair i at roll θ is the middle pair
    /// at θ − i·step, [`crate::tca::point_contact`]: the same contacts,
    /// other teeth), for |m| ≤ 3.
    fn tca_at(&self, roll_deg: f64) -> Option<crate::tca::point_contact::PointTcaPosition> {
        let h = self.tca.pitch_rad.to_degrees() / self.options.positions as f64;
        let nearest = |r: f64| {
            self.tca
                .positions
                .iter()
                .min_by(|a, b| {
                    (a.roll_rad.to_degrees() - r)
                        .abs()
                        .total_cmp(&(b.roll_rad.to_degrees() - r).abs())
                })
                .filter(|p| (p.roll_rad.to_degrees() - r).abs() <= 0.51 * h)
        };
        if let Some(p) = nearest(roll_deg) {
            return Some(p.clone());
        }
        let step = self.pair.tooth_roll_step();
        let (km, n) = (self.pair.middle() as i64, self.pair.sector_teeth() as i64);
        for m in [1i64, -1, 2, -2, 3, -3] {
            let Some(p) = nearest(roll_deg - (m as f64 * step).to_degrees()) else {
                continue;
            };
            let mut q = p.clone();
            q.roll_rad += m as f64 * step;
            for c in &mut q.pairs {
                c.offset += m;
                let k = km + c.offset;
                c.teeth = (k >= 1 && k <= n).then(|| [k as usize, self.pair.mate(k as usize)]);
            }
            return Some(q);
        }
        None
    }

    /// The pairs of the TCA position nearest to `roll_deg` outside the
    /// sector (not modelled) whose separation lies below `approach_mm`:
    /// (pair offset, separation mm).
    pub fn beyond_sector(&self, roll_deg: f64, approach_mm: f64) -> Vec<(i64, f64)> {
        self.tca_at(roll_deg)
            .into_iter()
            .flat_map(|p| p.pairs)
            .filter(|c| c.teeth.is_none() && c.separation_mm < approach_mm)
            .map(|c| (c.offset, c.separation_mm))
            .collect()
    }

    /// Solves the position nearest to `roll_deg`.
    pub fn solve(&self, roll_deg: f64) -> Result<PositionResult, FlankError> {
        let (position, notes) = self.position_and_notes(roll_deg)?;
        if position.lines.is_empty() {
            return Err(FlankError::Model(format!(
                "LTCA at roll {roll_deg}°: no tooth pair of the sector has a flank contact"
            )));
        }
        let frames = self.pair.frames(position.roll);
        let mut r = self
            .bodies
            .solve(&position, &frames, self.torque, &self.options.settings)?;
        r.warnings.extend(notes);
        self.bodies.within_pitch(r)
    }

    /// [`Self::solve`], or `None` where no tooth pair of the sector is in
    /// contact at all: a roll that no pair's trace reaches (a pair whose
    /// flank path is shorter than a pitch, without the edge contact that
    /// would carry it across).
    pub fn solve_or_gap(&self, roll_deg: f64) -> Result<Option<PositionResult>, FlankError> {
        let Some(p) = self.tca_at(roll_deg) else {
            // no position within the reach of tca_at: a gap inside it, an
            // error (Self::solve's) beyond it
            let reach = 3.0 * self.pair.tooth_roll_step().abs().to_degrees();
            let (first, last) = (
                self.tca.positions.first().map(|p| p.roll_rad.to_degrees()),
                self.tca.positions.last().map(|p| p.roll_rad.to_degrees()),
            );
            if let (Some(a), Some(b)) = (first, last) {
                if roll_deg > a - reach && roll_deg < b + reach {
                    return Ok(None);
                }
            }
            return self.solve(roll_deg).map(Some);
        };
        if p.pairs.iter().all(|c| c.teeth.is_none()) || self.position(roll_deg)?.lines.is_empty() {
            return Ok(None);
        }
        self.solve(roll_deg).map(Some)
    }

    /// [`Self::solve_or_gap`] at every roll, in parallel, as
    /// [`Self::solve_cycle`].
    pub fn solve_cycle_gaps(
        &self,
        rolls_deg: &[f64],
    ) -> Result<Vec<Option<PositionResult>>, FlankError> {
        use rayon::prelude::*;
        let run = || -> Result<Vec<Option<PositionResult>>, FlankError> {
            let all: Vec<_> = rolls_deg
                .par_iter()
                .map(|&r| self.solve_or_gap(r))
                .collect();
            all.into_iter().collect()
        };
        let n = self.options.threads;
        if n > 0 && n != rayon::current_num_threads() {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .map_err(|e| FlankError::Solver(format!("cannot start {n} threads: {e}")))?;
            return pool.install(run);
        }
        run()
    }

    /// The positions nearest to `rolls_deg` ([`Self::solve`]), in that
    /// order, solved in parallel: positions are independent (each reads the
    /// tensors, the point TCA and the surfaces and writes only its own
    /// result), so the results are the same on any number of threads. On
    /// `options.threads` threads (0: rayon's global pool); the first failing
    /// position's error, in the order given.
    pub fn solve_cycle(&self, rolls_deg: &[f64]) -> Result<Vec<PositionResult>, FlankError> {
        use rayon::prelude::*;
        let run = || -> Result<Vec<PositionResult>, FlankError> {
            let all: Vec<_> = rolls_deg.par_iter().map(|&r| self.solve(r)).collect();
            all.into_iter().collect()
        };
        let n = self.options.threads;
        if n > 0 && n != rayon::current_num_threads() {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .map_err(|e| FlankError::Solver(format!("cannot start {n} threads: {e}")))?;
            return pool.install(run);
        }
        run()
    }

    /// Force per pinion tooth of the sector (N).
    pub fn pair_forces(&self, r: &PositionResult) -> Vec<f64> {
        r.per_pair(&r.line_force_n, self.pair.sector_teeth())
    }

    /// Friction force per pinion tooth of the sector (N).
    pub fn pair_friction(&self, r: &PositionResult) -> Vec<f64> {
        r.per_pair(&r.line_friction_n, self.pair.sector_teeth())
    }

    /// Loaded TE at the gear (arcsec), with the FE run's sign: −θ z₁/z₂.
    pub fn te_arcsec(&self, r: &PositionResult) -> f64 {
        crate::load_sharing::te_arcsec_at_gear(r.te_urad, self.pair.ratio())
    }
}

/// `flank ltca` on a bevel/hypoid scene: the cycle's positions, the files
/// of the module docs, for each variant of [`BevelLtcaOptions::edges`];
/// returns the summary.
pub fn run_bevel(scene: &Scene, options: &BevelLtcaOptions) -> Result<LtcaResult, FlankError> {
    let t_total = Instant::now();
    options.validate(scene)?;
    let out = &options.out;
    std::fs::create_dir_all(out).map_err(|e| FlankError::io(out, e))?;
    let first = BevelLtca::new(scene, options)?;
    let runs = options.edges.runs();
    if runs.len() == 1 {
        let mut s = run_variant(scene, &first, out, runs[0].1)?;
        s.total_s = t_total.elapsed().as_secs_f64();
        let result = LtcaResult::Cycle(Box::new(s));
        result.write(out)?;
        return Ok(result);
    }
    let mut variants = Vec::new();
    for (edges, name) in runs {
        let other;
        let ltca = if edges == first.edges {
            &first
        } else {
            other = first.with_edges(edges, scene.load.speed_rpm)?;
            &other
        };
        let dir = out.join(name);
        std::fs::create_dir_all(&dir).map_err(|e| FlankError::io(&dir, e))?;
        variants.push(run_variant(scene, ltca, &dir, name)?);
    }
    let (Some(without_edges), Some(with_edges)) = (variants.pop(), variants.pop()) else {
        return Err(FlankError::Model(
            "LTCA: --edges both ran fewer than two variants".into(),
        ));
    };
    let ratio = |s: &LtcaSummary| match &s.kind {
        KindSummary::Bevel(b) => b.functional_contact_ratio,
        KindSummary::Cylindrical(_) => None,
    };
    let result = LtcaResult::EdgeVariants(Box::new(EdgeVariantSummaries {
        schema_version: SCHEMA_VERSION,
        scene: scene.source.display().to_string(),
        analysis: "ltca_bevel_cycle",
        pair_kind: scene.kind.name(),
        edges: "both",
        compliance_s: first.compliance_s,
        flank_nodes: first.flank_nodes,
        functional_contact_ratio: EdgeVariantRatios {
            with_edges: ratio(&with_edges),
            without_edges: ratio(&without_edges),
        },
        with_edges,
        without_edges,
        total_s: t_total.elapsed().as_secs_f64(),
        peak_memory_mb: peak_memory_mb(),
    }));
    result.write(out)?;
    Ok(result)
}

/// One variant's cycle: its CSVs in `out`, its summary returned.
fn run_variant(
    scene: &Scene,
    ltca: &BevelLtca,
    out: &std::path::Path,
    variant: &'static str,
) -> Result<LtcaSummary, FlankError> {
    let t_variant = Instant::now();
    let options = &ltca.options;
    let pitch = ltca.cycle_deg();
    let n = options.positions;
    let default_cycle = options.roll_angles_deg.is_none();
    let rolls = options.roll_angles_deg.clone().unwrap_or_else(|| {
        (0..n)
            .map(|i| -0.5 * pitch + pitch * i as f64 / n as f64)
            .collect()
    });
    let t_cycle = Instant::now();
    let solved = ltca.solve_cycle_gaps(&rolls)?;
    let cycle_s = t_cycle.elapsed().as_secs_f64();
    let gaps: Vec<f64> = rolls
        .iter()
        .zip(&solved)
        .filter(|(_, r)| r.is_none())
        .map(|(&x, _)| x)
        .collect();
    let results: Vec<PositionResult> = solved.iter().flatten().cloned().collect();
    let np = ltca.pair.sector_teeth();
    let ratio = ltca.pair.ratio();
    let steps: Vec<LtcaStep> = results
        .iter()
        .map(|r| LtcaStep::new(r.clone(), np, ratio))
        .collect();
    let mut notes = Vec::new();
    let te: Vec<f64> = steps.iter().map(|s| s.te_arcsec).collect();
    let te_urad: Vec<f64> = results.iter().map(|r| r.te_urad).collect();
    let mut edge_loaded = 0usize;
    let mut beyond = 0usize;
    let mut beyond_rolls = Vec::new();
    for r in &results {
        // a loaded end point: where the axis kept all K points the span is
        // too short; where the flank's edge clipped it the contact reaches
        // that edge (counted)
        for (li, line) in r.lines.iter().enumerate() {
            let loads: Vec<f64> = r
                .points
                .iter()
                .filter(|q| q.line == li)
                .map(|q| q.force_n)
                .collect();
            let end_loaded = loads.len() > 2
                && [loads.first(), loads.last()]
                    .iter()
                    .any(|e| e.is_some_and(|&x| x > 0.0));
            if !end_loaded {
                continue;
            }
            if loads.len() == options.points_per_pair {
                notes.push(format!(
                    "{:.3}°: pinion tooth {} carries load at an end of its candidate axis: raise --span-approach-mm",
                    r.roll_deg, line.0
                ));
            } else {
                edge_loaded += 1;
            }
        }
        notes.extend(
            r.warnings
                .iter()
                .map(|w| format!("{:.3}°: {w}", r.roll_deg)),
        );
        for (offset, sep) in ltca.beyond_sector(r.roll_deg, r.loaded_approach_mm) {
            beyond += 1;
            beyond_rolls.push(format!(
                "{:.3}° (pair {offset}: {:.1} µm < {:.1} µm)",
                r.roll_deg,
                1e3 * sep,
                1e3 * r.loaded_approach_mm
            ));
        }
        if !r.kkt_within_tolerance {
            notes.push(format!(
                "{:.3}°: {} residual {:.2e} above tolerance",
                r.roll_deg,
                if r.friction.is_some() {
                    "friction"
                } else {
                    "KKT"
                },
                r.kkt_max
            ));
        }
    }
    if !beyond_rolls.is_empty() {
        notes.push(format!(
            "a pair outside the {np}-tooth sector (not modelled; pitches from the middle pair) lies within the loaded approach at {} of {} positions: {} (its unloaded separation < the loaded approach (θ − θ₀) r): raise [mesh] teeth_in_sector",
            beyond_rolls.len(),
            results.len(),
            beyond_rolls.join(", ")
        ));
    }
    let loops = crate::ltca::outputs::iteration_limits(&results);
    notes.extend(loops.warnings());
    let mates: Vec<usize> = (1..=np).map(|k| ltca.pair.mate(k)).collect();
    write_cycle_csv(&out.join("ltca_cycle.csv"), &steps, np)?;
    write_positions_csv(&out.join("ltca_positions.csv"), &steps, &mates)?;
    write_points_csv(&out.join("ltca_points.csv"), &results)?;
    let plots = plot_variant(ltca, out, &results)?;
    let worst = |f: fn(&PositionResult) -> f64| results.iter().map(f).fold(0.0f64, f64::max);
    // the functional contact ratio needs the default cycle (positions
    // spread evenly over one pitch)
    // (a position without contact counts with no loaded pair)
    let sharing = default_cycle
        .then(|| {
            let forces: Vec<Vec<f64>> = solved
                .iter()
                .map(|r| match r {
                    Some(r) => ltca.pair_forces(r),
                    None => vec![0.0; np],
                })
                .collect();
            crate::load_sharing::cycle_sharing(&forces, pitch)
        })
        .flatten();
    if !gaps.is_empty() {
        notes.push(format!(
            "no tooth pair of the sector is in contact at {} of {} positions ({}°): the pair cannot carry the torque there{}",
            gaps.len(),
            rolls.len(),
            gaps.iter().map(|g| format!("{g:.3}")).collect::<Vec<_>>().join(", "),
            if ltca.edges { "" } else { " without edge contact" }
        ));
    }
    let edge_points: usize = results
        .iter()
        .map(|r| {
            r.points
                .iter()
                .filter(|q| r.lines[q.line].2 != "Flank")
                .count()
        })
        .sum();
    let edge_force: f64 = results
        .iter()
        .map(|r| {
            r.line_force_n
                .iter()
                .zip(&r.lines)
                .filter(|(_, l)| l.2 != "Flank")
                .map(|(f, _)| f)
                .sum::<f64>()
        })
        .fold(0.0, f64::max);
    // frictionless: Σ P r = T (with friction the tangential forces take
    // part of the torque)
    let torque_balance = (options.friction_mu == 0.0).then(|| {
        results
            .iter()
            .map(|r| {
                let m: f64 = r.points.iter().map(|q| q.force_n * q.moment_arm_mm).sum();
                (m - ltca.torque).abs() / ltca.torque
            })
            .fold(0.0f64, f64::max)
    });
    Ok(LtcaSummary {
        schema_version: SCHEMA_VERSION,
        scene: scene.source.display().to_string(),
        analysis: "ltca_bevel_cycle",
        pair_kind: scene.kind.name(),
        positions: results.len(),
        tooth_pairs: (1..=np).map(|k| (k, ltca.pair.mate(k))).collect(),
        te_peak_to_peak_urad: peak_to_peak(&te_urad),
        te_peak_to_peak_arcsec: peak_to_peak(&te),
        max_pressure_mpa: worst(|r| r.max_pressure_mpa),
        max_kkt: worst(|r| r.kkt_max),
        iteration_limits: loops,
        friction: ltca
            .options
            .settings
            .friction
            .as_ref()
            .map(|f| crate::ltca::outputs::friction_summary(&results, f, ltca.torque)),
        settings: options.settings.clone(),
        cycle_s,
        time_per_position_s: cycle_s / results.len().max(1) as f64,
        total_s: t_variant.elapsed().as_secs_f64(),
        peak_memory_mb: peak_memory_mb(),
        notes,
        kind: KindSummary::Bevel(Box::new(BevelLtcaSummary {
            edges: variant,
            edge_contact: ltca.edges,
            mesh_cycle_deg: pitch,
            torque_nm: ltca.torque / 1000.0,
            points_per_pair: options.points_per_pair,
            span_approach_mm: options.span_approach_mm,
            approach_mm: ltca.tca.settings.approach_mm,
            friction_mu: options.friction_mu,
            increments: (options.friction_mu > 0.0).then_some(options.increments),
            flank_nodes: ltca.flank_nodes,
            // seed 003's Δθ(φ) = a₀ + a₁φ + a₂φ² (φ pinion roll in °, Δθ at
            // the gear in ″)
            te_quadratic_fit: crate::ltca::te_fit::quadratic_te_fit(
                &results.iter().map(|r| r.roll_deg).collect::<Vec<_>>(),
                &te,
            ),
            max_torque_balance_error: torque_balance,
            pairs_loaded_at_a_flank_edge: edge_loaded,
            pairs_beyond_sector_within_approach: beyond,
            positions_without_contact_deg: gaps,
            edge_candidate_points: edge_points,
            max_edge_force_n: edge_force,
            functional_contact_ratio: sharing.as_ref().map(|s| s.functional_contact_ratio),
            load_sharing: sharing,
            tca_contact_ratio: ltca.tca.contact_ratio,
            tca_transitions: ltca.tca.transitions.clone(),
            compliance_s: ltca.compliance_s,
            tca_s: ltca.tca_s,
            plots,
        })),
        steps,
    })
}

/// `load_sharing.{svg,png}` (share of each pinion tooth against roll),
/// `transmission_error.{svg,png}` (loaded and unloaded TE, gear arcsec),
/// the loaded contact pattern on both drive flanks
/// (`contact_pattern_{pinion,gear}.{svg,png}`: every loaded candidate
/// point of the cycle at its place in the axial projection, coloured by
/// its Hertz pressure, as the FE cycle draws its nodes) and, with friction,
/// `friction_power.{svg,png}` (Σ |P_t v_s| per position) in `out`; returns
/// the file names.
fn plot_variant(
    ltca: &BevelLtca,
    out: &std::path::Path,
    results: &[PositionResult],
) -> Result<Vec<String>, FlankError> {
    use crate::report::cycle_plot::plot_series;
    let np = ltca.pair.sector_teeth();
    let shares: Vec<Vec<f64>> = results
        .iter()
        .map(|r| shares(&ltca.pair_forces(r)))
        .collect();
    let curves: Vec<(String, Vec<(f64, f64)>)> = (0..np)
        .filter(|&p| shares.iter().any(|s| s[p] > 0.0))
        .map(|p| {
            (
                format!(
                    "pinion tooth {} / gear tooth {}",
                    p + 1,
                    ltca.pair.mate(p + 1)
                ),
                results
                    .iter()
                    .zip(&shares)
                    .map(|(r, s)| (r.roll_deg, s[p]))
                    .collect(),
            )
        })
        .collect();
    let variant = if ltca.edges {
        "with edge contact"
    } else {
        "without edge contact"
    };
    let mut files = plot_series(
        out,
        "load_sharing",
        &format!("Load share per tooth pair, {variant}"),
        "pinion roll angle (deg)",
        "share of the normal force",
        &curves,
    )?;
    let arcsec = |x: f64| crate::load_sharing::te_arcsec_at_gear(x, ltca.pair.ratio());
    files.extend(plot_series(
        out,
        "transmission_error",
        &format!("Transmission error at the gear, {variant}"),
        "pinion roll angle (deg)",
        "TE (arcsec)",
        &[
            (
                "loaded".into(),
                results
                    .iter()
                    .map(|r| (r.roll_deg, arcsec(r.te_urad)))
                    .collect(),
            ),
            (
                "unloaded".into(),
                results
                    .iter()
                    .map(|r| (r.roll_deg, arcsec(r.unloaded_te_urad)))
                    .collect(),
            ),
        ],
    )?);
    files.extend(crate::report::fe_pattern::plot_pattern(
        out,
        ltca.pair.as_ref(),
        &pattern_points(ltca, results),
        "LTCA",
    )?);
    if ltca.options.settings.friction.is_some() {
        files.extend(plot_series(
            out,
            "friction_power",
            &format!("Friction power loss Σ |P_t v_s|, {variant}"),
            "pinion roll angle (deg)",
            "power loss (W)",
            &[(
                "all tooth pairs".into(),
                results
                    .iter()
                    .map(|r| (r.roll_deg, r.friction_power_w))
                    .collect(),
            )],
        )?);
    }
    Ok(files)
}

/// The loaded candidate points of the cycle in each member's axial
/// projection (the FE pattern's coordinates,
/// [`crate::tca::point_contact::projection`]): the global point taken back
/// into each member's own frame at its position.
fn pattern_points(
    ltca: &BevelLtca,
    results: &[PositionResult],
) -> Vec<crate::report::fe_pattern::PatternNode> {
    use crate::tca::point_contact::projection;
    let own = |f: &crate::geometry::frame::Frame, x: [f64; 3]| {
        f.rotate_back([
            x[0] - f.translation[0],
            x[1] - f.translation[1],
            x[2] - f.translation[2],
        ])
    };
    results
        .iter()
        .flat_map(|r| {
            let frames = ltca.pair.frames(r.roll_deg.to_radians());
            r.points
                .iter()
                .filter(|q| q.force_n > 0.0)
                .map(|q| crate::report::fe_pattern::PatternNode {
                    pair: r.lines[q.line].0,
                    projection_mm: [
                        projection(ltca.pair.pinion(), own(&frames[0], q.position)),
                        projection(ltca.pair.gear(), own(&frames[1], q.position)),
                    ],
                    pressure_mpa: q.pressure_mpa,
                })
                .collect::<Vec<_>>()
        })
        .collect()
}

/// The point TCA of the LTCA (no ellipse search: the flank axes take the
/// curvature ellipse, the edge lines search their own) and its time (s).
fn trace(
    pair: &crate::geometry::bevel::pair::BevelPair,
    positions: usize,
    edges: bool,
    speed_rpm: f64,
) -> Result<(PointTca, f64), FlankError> {
    let t = Instant::now();
    let tca = point_tca(
        pair,
        &PointTcaSettings {
            positions_per_pitch: positions,
            edges,
            search_directions: 0,
            speed_rpm,
            ..Default::default()
        },
    )?;
    Ok((tca, t.elapsed().as_secs_f64()))
}

/// A sector body that cannot be meshed: the error, with what clears a toe
/// slot whose fillets meet (seed 000's upright pinion).
fn mesh_hint(scene: &Scene, e: FlankError) -> FlankError {
    let m = match &e {
        FlankError::Model(m) if m.contains("no gap land") => m.clone(),
        _ => return e,
    };
    let tilted = scene
        .source
        .parent()
        .map(|d| d.join("scene_tilted.toml"))
        .filter(|p| p.is_file())
        .map(|p| format!(" (as {})", p.display()))
        .unwrap_or_default();
    FlankError::Model(format!(
        "{m}. The LTCA needs the compliance tensors of both sector bodies, so both must be meshed: a pinion cut with the Cyclo-Palloid head tilt, `[pinion] cutter_tilt = \"from_blank\"`{tilted}, opens the toe slot"
    ))
}
