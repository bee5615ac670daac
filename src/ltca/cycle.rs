//! The LTCA over a mesh cycle, for any pair kind ([`LtcaCycle`]): the
//! compliance tensors of both bodies once (computed or read from a cache,
//! [`crate::ltca::bodies`]), the pair's contact candidates
//! ([`crate::tca::candidates`]: the line TCA of a spur/helical pair, the
//! point TCA's major axes and edge lines of a bevel/hypoid pair), then per
//! roll angle the compliance matrix of the candidate points and the
//! contact QP ([`LtcaBodies::solve`]). The `flank ltca` run over a scene,
//! its files and summary, is [`crate::ltca::run`].
//!
//! Pairs are numbered as in FE contact ([`crate::mesh_cycle`]): pair p is
//! pinion tooth p + 1 with its mate, so the two runs compare column by
//! column.

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use crate::compliance::body::BodyMeshOptions;
use crate::error::FlankError;
use crate::geometry::gear_pair::{engagement_roll_angles, GearPair, LineContactPair};
use crate::load_sharing::LOADED_FRACTION;
use crate::ltca::bodies::{tensors, BodyTensors, Setup, TensorRequest};
use crate::ltca::local::contact_modulus;
use crate::ltca::model::{LtcaBodies, PositionResult};
use crate::ltca::solve_settings::{LtcaFriction, LtcaSettings};
use crate::scene::Scene;
use crate::settings::{EdgeVariants, FlankRegion, FrictionModel, LocalModel, QpSolver};
use crate::tca::candidates::ContactCandidates;
use crate::tca::point_candidates::{PointCandidates, DEFAULT_SPAN_APPROACH_MM};
use crate::tca::{Tca, TcaSettings};

/// Default K (candidate points per contact line) of a line-contact pair.
pub const DEFAULT_POINTS_PER_LINE: usize = 20;
/// Default K on each major axis of a point-contact pair.
pub const DEFAULT_POINTS_PER_PAIR: usize = 21;
/// Default positions per pitch of a point-contact pair's TCA grid.
pub const DEFAULT_POSITIONS: usize = 20;

/// Options of [`LtcaCycle::new`] and [`crate::ltca::run::run`], for every
/// pair kind; `None` falls back to the scene's `[analyses.ltca]`, then to
/// the defaults. Options that one kind has no use for are refused for the
/// other with the reason ([`LtcaCycle::new`]).
#[derive(Clone, Debug, Default)]
pub struct LtcaOptions {
    pub out: PathBuf,
    /// Compliance mesh overrides (flank/base size, element).
    pub mesh: BodyMeshOptions,
    pub roll_angles_deg: Option<Vec<f64>>,
    /// K: candidate points per contact line (a major axis of a bevel pair).
    pub points_per_line: Option<usize>,
    pub solver: Option<QpSolver>,
    pub local: Option<LocalModel>,
    pub fe_cell_factor: Option<f64>,
    /// A campaign cache of compliance tensors (directory).
    pub cache: Option<PathBuf>,
    /// Report κ(F) at every position.
    pub condition: bool,
    /// Threads of the tensors' solves and of the LTCA's parallel parts
    /// (0: rayon's global pool, all cores).
    pub threads: usize,
    pub quiet: bool,
    /// Coulomb friction coefficient (0: frictionless; else the scene's
    /// `[analyses.ltca] friction_mu`), load increments (default 10) and
    /// the Lemke cross-check of every position.
    pub friction_mu: Option<f64>,
    pub increments: Option<usize>,
    pub cross_check: bool,
    pub friction_model: Option<FrictionModel>,
    /// Flank nodes of the tensors (default: the scene's, else `active`
    /// for a spur/helical pair, `full` for a bevel pair).
    pub flank_region: Option<FlankRegion>,
    /// Dense or block low-rank tensors (default: the scene's
    /// `[analyses.ltca] compression`, else dense).
    pub compression: Option<crate::settings::Compression>,
    /// Bevel/hypoid pairs: the separation (mm) out to which each pair's
    /// candidate axis runs (default [`DEFAULT_SPAN_APPROACH_MM`]).
    pub span_approach_mm: Option<f64>,
    /// Bevel/hypoid pairs: the TCA's edge contacts as candidates, or not,
    /// or both variants (default: the scene's `[analyses.ltca] edges`,
    /// else without).
    pub edges: Option<EdgeVariants>,
    /// Bevel/hypoid pairs: positions per pitch of the point TCA's grid
    /// (default: the scene's `[analyses.ltca] positions`, else
    /// [`DEFAULT_POSITIONS`]).
    pub positions: Option<usize>,
    /// Pinion torques of the map over torque (N·m; default the scene's
    /// `[analyses.ltca] torques_nm`, else no map;
    /// [`crate::ltca::torque_map`]).
    pub torques_nm: Option<Vec<f64>>,
}

/// The corner-contact extension must exceed the loaded approach by this
/// factor ([`LtcaCycle::solve`]).
pub const EXTENSION_MARGIN: f64 = 1.5;

/// How often a position is solved again with a raised corner-contact
/// extension ([`LtcaCycle::solve`]).
pub const MAX_EXTENSION_RAISES: usize = 3;

/// Default load increments of the frictional LTCA.
pub const DEFAULT_INCREMENTS: usize = 10;

/// Where a pair kind's candidates come from (the seam,
/// [`crate::tca::candidates`]), with what the kind's run reports of them.
#[derive(Clone, Debug)]
pub enum CycleCandidates {
    /// A line-contact pair (spur, helical) and its line TCA.
    Line {
        pair: Arc<dyn LineContactPair>,
        tca: Tca,
    },
    /// A point-contact pair (bevel, hypoid): its point TCA's major axes.
    Point(Box<PointCandidates>),
}

impl CycleCandidates {
    /// The seam's view.
    pub fn source(&self) -> &dyn ContactCandidates {
        match self {
            CycleCandidates::Line { tca, .. } => tca,
            CycleCandidates::Point(p) => p.as_ref(),
        }
    }
}

/// A prepared LTCA: both bodies' tensors, the pair's candidates and the
/// settings.
pub struct LtcaCycle {
    /// The pair (the candidates').
    pub pair: Arc<dyn GearPair>,
    pub candidates: CycleCandidates,
    pub bodies: LtcaBodies,
    pub settings: LtcaSettings,
    /// K: candidate points per line.
    pub points_per_line: usize,
    /// Pinion torque (N·mm).
    pub torque: f64,
    pub setup: Setup,
}

impl LtcaCycle {
    /// Tensors (from `options.out`, the cache, or computed) and the
    /// candidates of `scene`, every option merged (options > the scene's
    /// `[analyses.ltca]` > default).
    pub fn new(scene: &Scene, options: &LtcaOptions) -> Result<Self, FlankError> {
        let a = scene.analyses.ltca.clone().unwrap_or_default();
        let settings = LtcaSettings {
            local: options.local.or(a.local).unwrap_or_default(),
            fe_cell_factor: options
                .fe_cell_factor
                .or(a.fe_cell_factor)
                .unwrap_or(LtcaSettings::default().fe_cell_factor),
            condition: options.condition,
            qp: crate::ltca::qp::QpOptions {
                solver: options.solver.or(a.solver).unwrap_or(QpSolver::ActiveSet),
                ..Default::default()
            },
            friction: ltca_friction(scene, options)?,
            local_iterations: a
                .local_iterations
                .unwrap_or(LtcaSettings::default().local_iterations),
            ..Default::default()
        };
        let compression = options.compression.or(a.compression).unwrap_or_default();
        let points = options.points_per_line.or(a.points_per_line);
        if scene.is_bevel() {
            return Self::point_contact(scene, options, settings, points);
        }
        if options.span_approach_mm.is_some() {
            return Err(FlankError::Model(
                "--span-approach-mm: for bevel and hypoid scenes only (a spur/helical pair's candidates are its contact lines)".into(),
            ));
        }
        if options.edges.is_some() {
            return Err(FlankError::Model("--edges: for bevel and hypoid scenes only (a spur/helical LTCA always takes its tip corners as candidates)".into()));
        }
        let cyl = scene.cylindrical("the spur/helical LTCA")?;
        let mn = cyl.pair.pinion.normal_module;
        let mesh = BodyMeshOptions {
            flank_size: options
                .mesh
                .flank_size
                .or(a.flank_size_mm)
                .or(Some(mn / 8.0)),
            base_size: options
                .mesh
                .base_size
                .or(a.base_size_mm)
                .or(scene.mesh.base_size)
                .or(Some(mn / 2.0)),
            with_load: false,
            element: options.mesh.element,
        };
        // the frictional directional blocks read the dense tensor: refused
        // before any tensor is computed
        if compression.epsilon().is_some() && settings.friction.is_some() {
            return Err(FlankError::Model(
                "compression: implemented for the frictionless LTCA only (the frictional \
                 directional blocks read the dense tensor); set compression = \"none\" or drop \
                 the friction"
                    .into(),
            ));
        }
        let BodyTensors {
            tensors: [pinion, gear],
            grids,
            setup,
        } = tensors(
            scene,
            &TensorRequest {
                mesh,
                // the pair is known: by default the tensors cover the
                // active flanks
                region: options
                    .flank_region
                    .or(a.flank_region)
                    .unwrap_or(FlankRegion::Active),
                compression,
                out: &options.out,
                cache: options.cache.as_deref(),
                threads: options.threads,
                quiet: options.quiet,
                mesh_hint: &|e| e,
            },
        )?;
        let points_per_line = points.unwrap_or(DEFAULT_POINTS_PER_LINE);
        let mis = a.misalignment_urad.unwrap_or([0.0; 2]);
        let tca_settings = TcaSettings {
            points_per_line,
            extension_mm: a
                .extension_mm
                .unwrap_or(TcaSettings::default().extension_mm),
            // one corner point per FE element length along the face (the
            // coarser body's): well inside the 2n + 1 edge load patterns
            corner_spacing_mm: pinion
                .flank
                .largest_face_length_v()
                .max(gear.flank.largest_face_length_v()),
            ..TcaSettings::default()
        };
        tca_settings.validate()?;
        let line_pair: Arc<dyn LineContactPair> = Arc::new(
            scene
                .cylindrical_pair()?
                .with_plane_of_action_misalignment(
                    [mis[0] * 1e-6, mis[1] * 1e-6],
                    a.centre_distance_error_um.unwrap_or(0.0) * 1e-3,
                )?,
        );
        let tca = Tca::new(Arc::clone(&line_pair), scene.load.speed_rpm, tca_settings)?;
        let pair: Arc<dyn GearPair> = line_pair.clone();
        let bodies = LtcaBodies {
            tensors: [pinion, gear],
            grids,
            pair: Arc::clone(&pair),
            nominal_moment_arm_mm: line_pair.nominal_moment_arm(),
            te_radius_mm: line_pair.transmission_error_radius(),
            contact_modulus: scene_contact_modulus(scene),
        };
        Ok(LtcaCycle {
            pair,
            candidates: CycleCandidates::Line {
                pair: line_pair,
                tca,
            },
            bodies,
            settings,
            points_per_line,
            torque: scene.load.torque_nmm,
            setup,
        })
    }

    /// [`LtcaCycle::new`] of a bevel/hypoid scene: the options checked
    /// before anything is computed, the tensors of both sector bodies
    /// (full flanks, dense), the point TCA traced (with edges for `With`
    /// and `Both`), the nominal force's arm that of the middle pair's
    /// contact at roll 0.
    fn point_contact(
        scene: &Scene,
        options: &LtcaOptions,
        settings: LtcaSettings,
        points: Option<usize>,
    ) -> Result<Self, FlankError> {
        let refuse = |m: &str| Err(FlankError::Model(m.into()));
        if options.flank_region == Some(FlankRegion::Active) {
            return refuse("--flank-region active: implemented for spur/helical pairs only (a bevel/hypoid LTCA takes the full flank)");
        }
        if options.compression.is_some_and(|c| c.epsilon().is_some()) {
            return refuse("--compression: implemented for spur/helical pairs only");
        }
        let bevel = scene.bevel("the bevel/hypoid LTCA")?;
        let a = scene.analyses.ltca.clone().unwrap_or_default();
        let k = points.unwrap_or(DEFAULT_POINTS_PER_PAIR);
        let positions = options
            .positions
            .or(a.positions)
            .unwrap_or(DEFAULT_POSITIONS);
        let span = options.span_approach_mm.unwrap_or(DEFAULT_SPAN_APPROACH_MM);
        check_point_options(scene, options, k, positions, span)?;
        let BodyTensors {
            tensors: [pinion, gear],
            grids,
            setup,
        } = tensors(
            scene,
            &TensorRequest {
                mesh: options.mesh,
                region: FlankRegion::Full,
                compression: crate::settings::Compression::default(),
                out: &options.out,
                cache: options.cache.as_deref(),
                threads: options.threads,
                quiet: options.quiet,
                mesh_hint: &|e| mesh_hint(scene, e),
            },
        )?;
        let edges = options.edges.or(a.edges).unwrap_or(EdgeVariants::Without);
        let point = PointCandidates::trace(
            Arc::clone(&bevel.pair),
            positions,
            edges != EdgeVariants::Without,
            scene.load.speed_rpm,
            k,
            span,
        )?;
        let arm = point.middle_moment_arm()?;
        let pair: Arc<dyn GearPair> = bevel.pair.clone();
        Ok(LtcaCycle {
            bodies: LtcaBodies {
                tensors: [pinion, gear],
                grids,
                pair: Arc::clone(&pair),
                nominal_moment_arm_mm: arm,
                te_radius_mm: arm,
                contact_modulus: scene_contact_modulus(scene),
            },
            pair,
            candidates: CycleCandidates::Point(Box::new(point)),
            settings,
            points_per_line: k,
            torque: scene.load.torque_nmm,
            setup,
        })
    }

    /// The line-contact pair of a spur/helical cycle.
    pub fn line_pair(&self) -> Result<&Arc<dyn LineContactPair>, FlankError> {
        match &self.candidates {
            CycleCandidates::Line { pair, .. } => Ok(pair),
            CycleCandidates::Point(_) => Err(not_line()),
        }
    }

    /// The line TCA of a spur/helical cycle.
    pub fn line_tca(&self) -> Result<&Tca, FlankError> {
        match &self.candidates {
            CycleCandidates::Line { tca, .. } => Ok(tca),
            CycleCandidates::Point(_) => Err(not_line()),
        }
    }

    /// The point candidates of a bevel/hypoid cycle.
    pub fn point(&self) -> Result<&PointCandidates, FlankError> {
        match &self.candidates {
            CycleCandidates::Point(p) => Ok(p),
            CycleCandidates::Line { .. } => Err(FlankError::Model(
                "LTCA: a spur/helical pair has no point TCA (its candidates are contact lines)"
                    .into(),
            )),
        }
    }

    /// The same prepared bodies with another K (a line pair's TCA is
    /// rebuilt, a point pair's trace kept).
    pub fn with_points_per_line(&self, k: usize) -> Result<Self, FlankError> {
        let candidates = match &self.candidates {
            CycleCandidates::Line { pair, tca } => {
                let mut settings = tca.settings().clone();
                settings.points_per_line = k;
                CycleCandidates::Line {
                    pair: Arc::clone(pair),
                    tca: tca.with_settings(settings)?,
                }
            }
            CycleCandidates::Point(p) => {
                let mut p = p.clone();
                p.points_per_pair = k;
                CycleCandidates::Point(p)
            }
        };
        Ok(self.with_candidates(candidates, k))
    }

    /// The same tensors with a bevel pair's TCA traced with edge contact
    /// on or off (the other variant of an `edges = both` run).
    pub fn with_edges(&self, edges: bool, speed_rpm: f64) -> Result<Self, FlankError> {
        let point = self.point()?.with_edges(edges, speed_rpm)?;
        Ok(self.with_candidates(
            CycleCandidates::Point(Box::new(point)),
            self.points_per_line,
        ))
    }

    /// The same prepared bodies and candidates at another pinion torque
    /// (N·mm): the map over torque ([`crate::ltca::torque_map`]).
    pub fn with_torque(&self, torque_nmm: f64) -> Self {
        LtcaCycle {
            torque: torque_nmm,
            ..self.with_candidates(self.candidates.clone(), self.points_per_line)
        }
    }

    fn with_candidates(&self, candidates: CycleCandidates, k: usize) -> Self {
        LtcaCycle {
            pair: Arc::clone(&self.pair),
            candidates,
            bodies: self.bodies.clone(),
            settings: self.settings.clone(),
            points_per_line: k,
            torque: self.torque,
            setup: self.setup.clone(),
        }
    }

    /// Total nominal normal force T / r (N): r = r_b1 cos β_b of a
    /// cylindrical pair, the mean contact's moment arm of a bevel pair.
    pub fn nominal_force(&self) -> f64 {
        self.torque / self.bodies.nominal_moment_arm_mm
    }

    /// The LTCA at one roll angle (deg); an error where no tooth pair of
    /// the sector is in contact ([`LtcaCycle::solve_or_gap`]).
    ///
    /// The candidate set must hold every point that closes under load. Tip
    /// corners beyond the kinematic path of a line-contact pair are
    /// candidates up to a separation of `extension_mm`; when the loaded
    /// approach (θ − θ₀)·r comes within [`EXTENSION_MARGIN`] of it, the
    /// position is solved again with the extension raised to twice the
    /// margin times the approach (at most [`MAX_EXTENSION_RAISES`] times,
    /// then a clear error), as the FE contact raises its search distance.
    /// An extension of 0 (corner contact switched off) is kept.
    pub fn solve(&self, roll_deg: f64) -> Result<PositionResult, FlankError> {
        self.solve_with(roll_deg, &self.settings)
    }

    /// [`LtcaCycle::solve`], or `None` where no tooth pair of the sector is
    /// in contact at all (a bevel pair whose flank path is shorter than a
    /// pitch, without the edge contact that would carry it across).
    pub fn solve_or_gap(&self, roll_deg: f64) -> Result<Option<PositionResult>, FlankError> {
        self.solve_or_gap_with(roll_deg, &self.settings)
    }

    /// [`LtcaCycle::solve`] with other settings (the wet–dry loop's μ per
    /// tooth pair, [`crate::ltca::lubricated`]).
    pub fn solve_with(
        &self,
        roll_deg: f64,
        settings: &LtcaSettings,
    ) -> Result<PositionResult, FlankError> {
        self.solve_or_gap_with(roll_deg, settings)?.ok_or_else(|| {
            FlankError::Model(format!(
                "LTCA at roll {roll_deg}°: no tooth pair of the sector has a flank contact"
            ))
        })
    }

    fn solve_or_gap_with(
        &self,
        roll_deg: f64,
        settings: &LtcaSettings,
    ) -> Result<Option<PositionResult>, FlankError> {
        // a stop asked for (Ctrl-C in an embedding program such as the
        // Python package; the binary installs no handler for `ltca`): a
        // position boundary is the LTCA's safe point, and the cycle's
        // tables and summary.json come after the last position
        if crate::interrupt::requested() {
            return Err(FlankError::Interrupted(format!(
                "the LTCA stopped on request before the position at {roll_deg}° roll; \
                 the files written so far are whole, the cycle's tables and summary.json are not written"
            )));
        }
        let t = Instant::now();
        let base = self.candidates.source();
        let mut raised: Option<Box<dyn ContactCandidates>> = None;
        let mut raises = 0;
        loop {
            let source = raised.as_deref().unwrap_or(base);
            let Some(c) = source.candidates(roll_deg)? else {
                return Ok(None);
            };
            let mut r = self
                .bodies
                .solve(&c.position, &c.frames, self.torque, settings)?;
            r.warnings.extend(c.notes);
            let Some(ext) = source.corner_extension_mm() else {
                return self.bodies.within_pitch(r).map(Some);
            };
            r.corner_extension_mm = ext;
            if ext == 0.0 || !(EXTENSION_MARGIN * r.loaded_approach_mm > ext) {
                r.time_s = t.elapsed().as_secs_f64();
                return self.bodies.within_pitch(r).map(Some);
            }
            if raises == MAX_EXTENSION_RAISES {
                return Err(FlankError::Model(format!(
                    "LTCA at roll {roll_deg:.4}°: the loaded approach {:.4} mm still reaches the corner-contact extension {ext:.4} mm after {MAX_EXTENSION_RAISES} raises: points that may close under this load are not candidates (the load deforms the teeth by more than a linear model covers?)",
                    r.loaded_approach_mm
                )));
            }
            raises += 1;
            raised =
                Some(source.with_corner_extension(2.0 * EXTENSION_MARGIN * r.loaded_approach_mm)?);
        }
    }

    /// [`LtcaCycle::solve`] at every roll angle of `rolls_deg` (deg), in
    /// that order, the positions solved side by side on the thread pool:
    /// they are independent (each reads the tensors, their pages, the
    /// candidates and the surfaces and writes only its own result), and
    /// each position's own parallel sums have a fixed order, so the
    /// results are those of solving one after the other, to the bit, on
    /// any number of threads (unit test). A position's `time_s` is then
    /// its wall time beside the others; the cycle's time per position is
    /// the whole call's wall time over the positions. The first failing
    /// position's error, in the order given.
    pub fn solve_cycle(&self, rolls_deg: &[f64]) -> Result<Vec<PositionResult>, FlankError> {
        self.solve_cycle_with(rolls_deg, &self.settings)
    }

    /// [`LtcaCycle::solve_cycle`] with other settings (as
    /// [`LtcaCycle::solve_with`]).
    pub fn solve_cycle_with(
        &self,
        rolls_deg: &[f64],
        settings: &LtcaSettings,
    ) -> Result<Vec<PositionResult>, FlankError> {
        use rayon::prelude::*;
        let progress = crate::progress::Counter::start("ltca positions", rolls_deg.len());
        let all: Vec<_> = rolls_deg
            .par_iter()
            .map(|&a| {
                let r = self.solve_with(a, settings);
                progress.step();
                r
            })
            .collect();
        all.into_iter().collect()
    }

    /// [`LtcaCycle::solve_or_gap`] at every roll, side by side as
    /// [`LtcaCycle::solve_cycle`].
    pub fn solve_cycle_gaps(
        &self,
        rolls_deg: &[f64],
    ) -> Result<Vec<Option<PositionResult>>, FlankError> {
        use rayon::prelude::*;
        let progress = crate::progress::Counter::start("ltca positions", rolls_deg.len());
        let all: Vec<_> = rolls_deg
            .par_iter()
            .map(|&a| {
                let r = self.solve_or_gap(a);
                progress.step();
                r
            })
            .collect();
        all.into_iter().collect()
    }

    /// Normal force per pair (pinion tooth p + 1), summed over its lines.
    pub fn pair_forces(&self, r: &PositionResult) -> Vec<f64> {
        r.per_pair(&r.line_force_n, self.pair.sector_teeth())
    }

    /// Friction force per pair (N, resisting slip along the tangent),
    /// summed over its lines; zeros without friction.
    pub fn pair_friction(&self, r: &PositionResult) -> Vec<f64> {
        r.per_pair(&r.line_friction_n, self.pair.sector_teeth())
    }

    /// Loaded TE at the gear (arcsec), with the FE run's sign: −θ z₁/z₂.
    pub fn te_arcsec(&self, r: &PositionResult) -> f64 {
        crate::load_sharing::te_arcsec_at_gear(r.te_urad, self.pair.ratio())
    }

    pub(crate) fn loaded(&self, r: &PositionResult, p: usize) -> bool {
        self.pair_forces(r)[p] > LOADED_FRACTION * self.nominal_force()
    }

    /// The middle pair's loaded interval (deg), bisected to 0.01°.
    pub fn loaded_limits(
        &self,
        angles: &[f64],
        results: &[PositionResult],
    ) -> Result<Option<(f64, f64)>, FlankError> {
        let mid = self.pair.middle() - 1;
        let loaded: Vec<bool> = results.iter().map(|r| self.loaded(r, mid)).collect();
        let (Some(f), Some(l)) = (
            loaded.iter().position(|&x| x),
            loaded.iter().rposition(|&x| x),
        ) else {
            return Ok(None);
        };
        if f == 0 || l + 1 == angles.len() {
            return Ok(None);
        }
        let start = self.limit(mid, angles[f - 1], angles[f])?;
        let end = self.limit(mid, angles[l + 1], angles[l])?;
        Ok(Some((start, end)))
    }

    fn limit(&self, p: usize, mut off: f64, mut on: f64) -> Result<f64, FlankError> {
        while (on - off).abs() > 0.01 {
            let mid = 0.5 * (on + off);
            if self.loaded(&self.solve(mid)?, p) {
                on = mid;
            } else {
                off = mid;
            }
        }
        Ok(0.5 * (on + off))
    }
}

fn not_line() -> FlankError {
    FlankError::Model(
        "LTCA: a bevel/hypoid pair has no line TCA (its candidates are the point TCA's major axes)"
            .into(),
    )
}

/// E* of the scene's two materials.
fn scene_contact_modulus(scene: &Scene) -> f64 {
    contact_modulus(
        [scene.pinion_material.young, scene.gear_material.young],
        [scene.pinion_material.poisson, scene.gear_material.poisson],
    )
}

/// A bevel/hypoid LTCA's options checked against the scene before
/// anything is computed or written.
fn check_point_options(
    scene: &Scene,
    options: &LtcaOptions,
    k: usize,
    positions: usize,
    span: f64,
) -> Result<(), FlankError> {
    let torque = scene.load.torque_nmm;
    if !(torque > 0.0 && torque.is_finite()) {
        return Err(FlankError::Model(format!(
            "LTCA needs a positive pinion torque ([load] torque_nm); got {} N·m",
            torque / 1000.0
        )));
    }
    if !(1..=200).contains(&k) {
        return Err(FlankError::Model(format!(
            "--points-per-line {k}: between 1 and 200 points per major axis are needed"
        )));
    }
    if !(4..=400).contains(&positions) {
        return Err(FlankError::Model(format!(
            "positions per cycle {positions}: between 4 and 400 are needed"
        )));
    }
    if !(span > 0.0 && span <= 1.0) {
        return Err(FlankError::Model(format!(
            "--span-approach-mm {span}: a separation in (0, 1] mm is needed"
        )));
    }
    let a = scene.analyses.ltca.clone().unwrap_or_default();
    if let Some(r) = options
        .roll_angles_deg
        .iter()
        .chain(a.roll_angles_deg.iter())
        .flatten()
        .find(|r| !r.is_finite())
    {
        return Err(FlankError::Model(format!(
            "--roll-angles: {r} is not a number"
        )));
    }
    crate::compliance::body::bevel_sector_options(scene, &options.mesh)?;
    Ok(())
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

/// The frictional settings of the options (first) or of the scene's
/// `[analyses.ltca]`; `None` for μ = 0. Friction needs the sliding
/// direction, i.e. a pinion speed.
fn ltca_friction(scene: &Scene, o: &LtcaOptions) -> Result<Option<LtcaFriction>, FlankError> {
    let a = scene.analyses.ltca.clone().unwrap_or_default();
    let mu = o.friction_mu.or(a.friction_mu).unwrap_or(0.0);
    if mu == 0.0 && (o.cross_check || o.increments.is_some() || o.friction_model.is_some()) {
        return Err(FlankError::Model(
            "--increments, --cross-check and --friction-model need friction (--friction-mu > 0 or [analyses.ltca] friction_mu)".into(),
        ));
    }
    LtcaFriction::checked(
        mu,
        o.increments.or(a.increments).unwrap_or(DEFAULT_INCREMENTS),
        o.friction_model.or(a.friction_model).unwrap_or_default(),
        o.cross_check,
        scene.load.speed_rpm,
        &scene.source,
    )
}

/// Roll angles of a spur/helical LTCA: the options', else the scene's
/// `[analyses.ltca]`, else the middle pair's engagement (then `true`: the
/// run extends it while loaded).
pub fn roll_angles(scene: &Scene, pair: &dyn LineContactPair, o: &LtcaOptions) -> (Vec<f64>, bool) {
    let a = scene.analyses.ltca.clone().unwrap_or_default();
    if let Some(r) = o.roll_angles_deg.clone().or(a.roll_angles_deg) {
        return (r, false);
    }
    let step = a.roll_step_deg.unwrap_or(1.0);
    if let (Some(s), Some(e)) = (a.roll_start_deg, a.roll_end_deg) {
        let n = ((e - s) / step + 1e-9).floor() as i64;
        return ((0..=n).map(|i| s + i as f64 * step).collect(), false);
    }
    (engagement_roll_angles(pair, step), true)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::read_scene;
    use std::path::Path;

    /// A position's result without its wall times (the only fields that
    /// differ between runs).
    fn answer(r: &PositionResult) -> serde_json::Value {
        let mut v = serde_json::to_value(r).unwrap();
        for k in ["time_s", "cells_s", "compliance_s", "local_s", "qp_s"] {
            v.as_object_mut().unwrap().remove(k);
        }
        v
    }

    /// Positions solved side by side give, to the bit, the results of
    /// solving them one after the other, on 1, 2 and 3 threads, in the
    /// order asked; a failing position gives its own error.
    #[test]
    fn positions_side_by_side_give_the_bits_of_one_after_the_other() {
        let scene = read_scene(Path::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/papers/seed002-spur/scene.toml"
        )))
        .unwrap();
        let work = std::env::temp_dir().join(format!("flank_ltca_side_{}", std::process::id()));
        let o = LtcaOptions {
            out: work.join("bodies"),
            mesh: BodyMeshOptions {
                flank_size: Some(1.5),
                base_size: Some(3.0),
                ..Default::default()
            },
            points_per_line: Some(10),
            quiet: true,
            ..Default::default()
        };
        let cycle = LtcaCycle::new(&scene, &o).unwrap();
        let (a, e) = cycle.line_pair().unwrap().engagement(cycle.pair.middle());
        let pitch = cycle.pair.pinion().angular_pitch().to_degrees();
        let start = 0.5 * (a + e).to_degrees() - 0.5 * pitch;
        let rolls: Vec<f64> = (0..12).map(|i| start + pitch * i as f64 / 12.0).collect();
        let one_by_one: Vec<serde_json::Value> = rolls
            .iter()
            .map(|&r| answer(&cycle.solve(r).unwrap()))
            .collect();
        for threads in [1, 2, 3] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let side = pool.install(|| cycle.solve_cycle(&rolls)).unwrap();
            assert_eq!(side.len(), rolls.len());
            for (k, (r, expected)) in side.iter().zip(&one_by_one).enumerate() {
                assert_eq!(r.roll_deg, rolls[k]);
                assert_eq!(&answer(r), expected, "{threads} threads, roll {}", rolls[k]);
            }
        }
        // a roll angle off the gear pair's path is the error of that position
        let mut bad = rolls.clone();
        bad.insert(3, f64::NAN);
        let one = cycle.solve(f64::NAN).unwrap_err().to_string();
        let side = cycle.solve_cycle(&bad).unwrap_err().to_string();
        assert_eq!(side, one);
        let _ = std::fs::remove_dir_all(work);
    }
}
