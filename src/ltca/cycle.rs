//! The LTCA over a mesh cycle (`flank ltca`): compliance tensors of both
//! bodies once (computed or read from a cache), then per roll angle the
//! unloaded TCA, the compliance matrix of its candidate points and the
//! contact QP. Outputs: `ltca_cycle.csv`, `ltca_points.csv` (load
//! distribution along every contact line), `summary.json` and plots of the
//! force per tooth pair and the TE (SVG, PNG).
//!
//! Pairs are numbered as in FE contact ([`crate::mesh_cycle`]): pair p is
//! pinion tooth p + 1 with its mate, so the two runs compare column by
//! column.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use rayon::prelude::*;

use crate::compliance::body::{scene_body, BodyMeshOptions};
use crate::compliance::cache::FileFormat;
use crate::compliance::compressed::{BlrOptions, BlrTensor};
use crate::compliance::run::{
    body_tensor, build_compressed, cylindrical_region_cut, open_compressed, BodyTensorOptions,
    OpenedCompressed,
};
use crate::compliance::tensor_cache::ComplianceCache;
use crate::compliance::{ComplianceStats, ComplianceTensor};
use crate::error::FlankError;
use crate::fem::static_analysis::peak_memory_mb;
use crate::geometry::gear_pair::{engagement_roll_angles, GearPair};
use crate::iteration_limits::IterationLimits;
use crate::load_sharing::LOADED_FRACTION;
use crate::ltca::local::contact_modulus;
use crate::ltca::model::{LtcaBodies, LtcaFriction, LtcaSettings, PositionResult};
use crate::scene::{read_scene, Scene};
use crate::settings::FlankRegion;
use crate::settings::QpSolver;
use crate::settings::{FrictionModel, LocalModel};
use crate::tca::{Tca, TcaSettings};

/// Default K (candidate points per contact line).
pub const DEFAULT_POINTS_PER_LINE: usize = 20;

/// Options of [`run`]; `None` falls back to the scene's `[analyses.ltca]`,
/// then to the defaults.
#[derive(Clone, Debug, Default)]
pub struct LtcaOptions {
    pub out: PathBuf,
    /// Compliance mesh overrides (flank/base size, element).
    pub mesh: BodyMeshOptions,
    pub roll_angles_deg: Option<Vec<f64>>,
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
    /// Flank nodes of the tensors (default: the scene's, else `active`).
    pub flank_region: Option<FlankRegion>,
    /// Dense or block low-rank tensors (default: the scene's
    /// `[analyses.ltca] compression`, else dense).
    pub compression: Option<crate::settings::Compression>,
}

/// The corner-contact extension must exceed the loaded approach by this
/// factor ([`LtcaCycle::solve`]).
pub const EXTENSION_MARGIN: f64 = 1.5;

/// How often a position is solved again with a raised corner-contact
/// extension ([`LtcaCycle::solve`]).
pub const MAX_EXTENSION_RAISES: usize = 3;

/// Default load increments of the frictional LTCA.
pub const DEFAULT_INCREMENTS: usize = 10;

/// What the setup cost and produced.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Setup {
    /// Flank nodes per body, compliance matrix dimension, whether it was
    /// computed here (else read), seconds.
    pub flank_nodes: [usize; 2],
    pub computed: [bool; 2],
    /// Backward error of each body's probe solve when its tensor was
    /// computed here (`None`: read from a file or the cache, checked when
    /// it was computed).
    pub backward_error: [Option<f64>; 2],
    pub compliance_s: f64,
    pub flank_size_mm: f64,
    pub base_size_mm: f64,
    /// Per body, the block low-rank compression the pages are read from
    /// (`None`: dense).
    pub compression: [Option<crate::compliance::compressed::BlrStats>; 2],
    /// Per body built compressed here: the panel build's figures and the
    /// factorization's time (s) and peak resident memory so far (MB).
    pub panel_build: [Option<PanelBuild>; 2],
}

/// A compressed body's build ([`Setup::panel_build`]).
#[derive(Clone, Debug, serde::Serialize)]
pub struct PanelBuild {
    #[serde(flatten)]
    pub panels: crate::compliance::compressed_build::PanelStats,
    pub factorization_s: f64,
    pub nnz_factor: usize,
    pub dofs: usize,
    pub peak_memory_mb: f64,
}

/// One body's tensor for the LTCA: dense, or flank and key only with its
/// block low-rank form.
struct Prepared {
    tensor: Arc<ComplianceTensor>,
    /// Present when computed here.
    stats: Option<ComplianceStats>,
    blr: Option<Arc<BlrTensor>>,
    panel: Option<PanelBuild>,
}

/// A prepared LTCA: both bodies' tensors, the TCA and the settings.
pub struct LtcaCycle {
    /// The pair (the TCA's).
    pub pair: Arc<dyn GearPair>,
    pub tca: Tca,
    pub bodies: LtcaBodies,
    pub settings: LtcaSettings,
    pub points_per_line: usize,
    /// Pinion torque (N·mm).
    pub torque: f64,
    pub setup: Setup,
}

impl LtcaCycle {
    /// Tensors (from `out`, the cache, or computed) and the TCA of `scene`.
    pub fn new(scene: &Scene, options: &LtcaOptions) -> Result<Self, FlankError> {
        let a = scene.analyses.ltca.clone().unwrap_or_default();
        let mn = scene.pair.pinion.normal_module;
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
        let t = Instant::now();
        let campaign = match &options.cache {
            Some(d) => Some(ComplianceCache::shared(d, FileFormat::default_format())?),
            None => None,
        };
        let mut topts = BodyTensorOptions::for_ltca(options.threads, campaign.as_deref());
        // the pair is known: by default the tensors cover the active flanks
        let region = options
            .flank_region
            .or(a.flank_region)
            .unwrap_or(FlankRegion::Active);
        // the frictional directional blocks read the dense tensor: refused
        // before any tensor is computed
        let compression = options.compression.or(a.compression).unwrap_or_default();
        if compression.epsilon().is_some() && ltca_friction(scene, options)?.is_some() {
            return Err(FlankError::Model(
                "compression: implemented for the frictionless LTCA only (the frictional \
                 directional blocks read the dense tensor); set compression = \"none\" or drop \
                 the friction"
                    .into(),
            ));
        }
        let mut bodies = Vec::with_capacity(2);
        match compression.epsilon() {
            // compressed: built panel by panel, the dense tensor never
            // formed (compliance::compressed_build); the two bodies are
            // meshed and their files read side by side, a missing tensor
            // is then built one body at a time (a factor and the panels'
            // threads each)
            Some(epsilon) => {
                let blr = BlrOptions {
                    epsilon,
                    ..Default::default()
                };
                let mut per_body = Vec::with_capacity(2);
                for name in ["pinion", "gear"] {
                    let mut o = topts.clone();
                    o.region_u_min = cylindrical_region_cut(scene, name, region, &mesh)?;
                    per_body.push((name, o));
                }
                let opened: Vec<OpenedCompressed> = per_body
                    .par_iter()
                    .map(|(name, o)| {
                        let body = scene_body(scene, name, &mesh)?.into();
                        open_compressed(&body, o, &blr, options.cache.as_deref(), &options.out)
                    })
                    .collect::<Result<_, FlankError>>()?;
                for (opened, (_, o)) in opened.into_iter().zip(&per_body) {
                    let c = match opened {
                        OpenedCompressed::Read(c) => *c,
                        OpenedCompressed::Missing(m) => {
                            build_compressed(m, o, &blr, !options.quiet)?
                        }
                    };
                    bodies.push(Prepared {
                        tensor: c.tensor,
                        panel: c.stats.as_ref().map(|(s, p)| PanelBuild {
                            panels: p.clone(),
                            factorization_s: s.factorization_s,
                            nnz_factor: s.nnz_factor,
                            dofs: s.dofs,
                            peak_memory_mb: s.peak_memory_mb,
                        }),
                        stats: c.stats.map(|s| s.0),
                        blr: Some(c.blr),
                    });
                }
            }
            None => {
                for name in ["pinion", "gear"] {
                    topts.region_u_min = cylindrical_region_cut(scene, name, region, &mesh)?;
                    let body = scene_body(scene, name, &mesh)?.into();
                    let t = body_tensor(&body, &topts, &options.out)?;
                    bodies.push(Prepared {
                        tensor: t.tensor,
                        stats: t.stats,
                        blr: None,
                        panel: None,
                    });
                }
            }
        }
        let gear = bodies.pop().expect("two bodies");
        let pinion = bodies.pop().expect("two bodies");
        let compliance_s = t.elapsed().as_secs_f64();
        let points_per_line = options
            .points_per_line
            .or(a.points_per_line)
            .unwrap_or(DEFAULT_POINTS_PER_LINE);
        let mis = a.misalignment_urad.unwrap_or([0.0; 2]);
        let tca_settings = TcaSettings {
            points_per_line,
            extension_mm: a
                .extension_mm
                .unwrap_or(TcaSettings::default().extension_mm),
            // one corner point per FE element length along the face (the
            // coarser body's): well inside the 2n + 1 edge load patterns
            corner_spacing_mm: pinion
                .tensor
                .flank
                .largest_face_length_v()
                .max(gear.tensor.flank.largest_face_length_v()),
            ..TcaSettings::default()
        };
        tca_settings.validate()?;
        let pair: Arc<dyn GearPair> = Arc::new(
            scene
                .cylindrical_pair()?
                .with_plane_of_action_misalignment(
                    [mis[0] * 1e-6, mis[1] * 1e-6],
                    a.centre_distance_error_um.unwrap_or(0.0) * 1e-3,
                )?,
        );
        let tca = Tca::new(Arc::clone(&pair), scene.load.speed_rpm, tca_settings)?;
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
        let mut setup = Setup {
            flank_nodes: [pinion.tensor.node_count(), gear.tensor.node_count()],
            computed: [pinion.stats.is_some(), gear.stats.is_some()],
            backward_error: [
                pinion.stats.as_ref().map(|s| s.backward_error),
                gear.stats.as_ref().map(|s| s.backward_error),
            ],
            compliance_s,
            flank_size_mm: mesh.flank_size.unwrap_or(f64::NAN),
            base_size_mm: mesh.base_size.unwrap_or(f64::NAN),
            compression: [None, None],
            panel_build: [pinion.panel.clone(), gear.panel.clone()],
        };
        // the flanks' face grids (geometry only: a compressed tensor has
        // no dense matrix), the pages read from the compressed form if any
        let grids = [
            crate::compliance::interpolation::FlankGrids::of(&pinion.tensor)?,
            crate::compliance::interpolation::FlankGrids::of(&gear.tensor)?,
        ];
        for (b, body) in [&pinion, &gear].into_iter().enumerate() {
            if let Some(blr) = &body.blr {
                setup.compression[b] = Some(blr.stats.clone());
                grids[b].set_pages(crate::compliance::pages::TensorPages::compressed(
                    &body.tensor,
                    Arc::clone(blr),
                )?)?;
            }
        }
        let bodies = LtcaBodies {
            tensors: [pinion.tensor, gear.tensor],
            grids,
            pair: Arc::clone(&pair) as Arc<dyn crate::geometry::gear_pair::PairPlacement>,
            nominal_moment_arm_mm: pair.nominal_moment_arm(),
            te_radius_mm: pair.transmission_error_radius(),
            contact_modulus: contact_modulus(
                [scene.pinion_material.young, scene.gear_material.young],
                [scene.pinion_material.poisson, scene.gear_material.poisson],
            ),
        };
        Ok(LtcaCycle {
            pair,
            tca,
            bodies,
            settings,
            points_per_line,
            torque: scene.load.torque_nmm,
            setup,
        })
    }

    /// The same prepared bodies with another K (the TCA is rebuilt).
    pub fn with_points_per_line(&self, _scene: &Scene, k: usize) -> Result<Self, FlankError> {
        let mut settings = self.tca.settings().clone();
        settings.points_per_line = k;
        let tca = self.tca.with_settings(settings)?;
        Ok(LtcaCycle {
            pair: Arc::clone(&self.pair),
            tca,
            bodies: LtcaBodies {
                tensors: [
                    Arc::clone(&self.bodies.tensors[0]),
                    Arc::clone(&self.bodies.tensors[1]),
                ],
                grids: [
                    Arc::clone(&self.bodies.grids[0]),
                    Arc::clone(&self.bodies.grids[1]),
                ],
                pair: Arc::clone(&self.bodies.pair),
                nominal_moment_arm_mm: self.bodies.nominal_moment_arm_mm,
                te_radius_mm: self.bodies.te_radius_mm,
                contact_modulus: self.bodies.contact_modulus,
            },
            settings: self.settings.clone(),
            points_per_line: k,
            torque: self.torque,
            setup: self.setup.clone(),
        })
    }

    /// Total normal force T/(r_b1 cos β_b) (N).
    pub fn nominal_force(&self) -> f64 {
        self.torque / self.pair.nominal_moment_arm()
    }

    /// The LTCA at one roll angle (deg).
    ///
    /// The candidate set must hold every point that closes under load. Tip
    /// corners beyond the kinematic path are candidates up to a separation
    /// of `extension_mm`; when the loaded approach (θ − θ₀)·r comes within
    /// [`EXTENSION_MARGIN`] of it, the position is solved again with the
    /// extension raised to twice the margin times the approach (at most
    /// [`MAX_EXTENSION_RAISES`] times, then a clear error), as the FE
    /// contact raises its search distance. An extension of 0 (corner
    /// contact switched off) is kept.
    pub fn solve(&self, roll_deg: f64) -> Result<PositionResult, FlankError> {
        self.solve_with(roll_deg, &self.settings)
    }

    /// [`LtcaCycle::solve`] at every roll angle of `rolls_deg` (deg), in
    /// that order, the positions solved side by side on the thread pool:
    /// they are independent (each reads the tensors, their pages, the TCA
    /// and the surfaces and writes only its own result), and each
    /// position's own parallel sums have a fixed order, so the results are
    /// those of solving one after the other, to the bit, on any number of
    /// threads (unit test). A position's `time_s` is then its wall time
    /// beside the others; the cycle's time per position is the whole
    /// call's wall time over the positions. The first failing position's
    /// error, in the order given.
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
        let all: Vec<_> = rolls_deg
            .par_iter()
            .map(|&a| self.solve_with(a, settings))
            .collect();
        all.into_iter().collect()
    }

    /// [`LtcaCycle::solve`] with other settings (the wet–dry loop's μ per
    /// tooth pair, [`crate::ltca::lubricated`]).
    pub fn solve_with(
        &self,
        roll_deg: f64,
        settings: &LtcaSettings,
    ) -> Result<PositionResult, FlankError> {
        let t = Instant::now();
        let roll = roll_deg.to_radians();
        let mut tca = std::borrow::Cow::Borrowed(&self.tca);
        let mut raises = 0;
        loop {
            let position = tca.position(roll)?;
            let frames = tca.frames(roll);
            let mut r = self
                .bodies
                .solve(&position, &frames, self.torque, settings)?;
            let ext = tca.settings().extension_mm;
            r.corner_extension_mm = ext;
            if ext == 0.0 || !(EXTENSION_MARGIN * r.loaded_approach_mm > ext) {
                r.time_s = t.elapsed().as_secs_f64();
                return self.bodies.within_pitch(r);
            }
            if raises == MAX_EXTENSION_RAISES {
                return Err(FlankError::Model(format!(
                    "LTCA at roll {roll_deg:.4}°: the loaded approach {:.4} mm still reaches the corner-contact extension {ext:.4} mm after {MAX_EXTENSION_RAISES} raises: points that may close under this load are not candidates (the load deforms the teeth by more than a linear model covers?)",
                    r.loaded_approach_mm
                )));
            }
            raises += 1;
            let mut s = tca.settings().clone();
            s.extension_mm = 2.0 * EXTENSION_MARGIN * r.loaded_approach_mm;
            tca = std::borrow::Cow::Owned(tca.with_settings(s)?);
        }
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

    fn loaded(&self, r: &PositionResult, p: usize) -> bool {
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

/// Roll angles of the scene's `[analyses.ltca]` (or the options'), and
/// whether they are the default range (then extended while loaded).
pub fn roll_angles(scene: &Scene, pair: &dyn GearPair, o: &LtcaOptions) -> (Vec<f64>, bool) {
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

/// `flank ltca SCENE`: reads the scene and runs [`run`].
pub fn run_scene(path: &Path, options: &LtcaOptions) -> Result<serde_json::Value, FlankError> {
    let scene = read_scene(path)?;
    run(&scene, options)
}

/// The LTCA over the scene's roll angles; writes the outputs into
/// `options.out` and returns the summary. On `options.threads` threads
/// (0: rayon's global pool); the answer is the same on any number (fixed
/// summation orders).
pub fn run(scene: &Scene, options: &LtcaOptions) -> Result<serde_json::Value, FlankError> {
    crate::fem::solver::with_threads(options.threads, || run_cycle(scene, options))
}

fn run_cycle(scene: &Scene, options: &LtcaOptions) -> Result<serde_json::Value, FlankError> {
    let t_total = Instant::now();
    let out = &options.out;
    // the wet–dry loop (seed 002): the cycle below is its dry pass at μ₀
    let lubricated = crate::ltca::lubricated::loop_settings(scene, options)?;
    std::fs::create_dir_all(out).map_err(|e| FlankError::io(out, e))?;
    let dry_options;
    let options = match &lubricated {
        Some(l) => {
            dry_options = l.dry_options(options);
            &dry_options
        }
        None => options,
    };
    let cycle = LtcaCycle::new(scene, options)?;
    let (mut angles, default_range) = roll_angles(scene, cycle.pair.as_ref(), options);
    let mid = cycle.pair.middle() - 1;
    let t_cycle = Instant::now();
    let mut results = cycle.solve_cycle(&angles)?;
    let cycle_s = t_cycle.elapsed().as_secs_f64();
    let positions_solved = results.len();
    let mut extended = 0;
    if default_range {
        let step = scene
            .analyses
            .ltca
            .as_ref()
            .and_then(|a| a.roll_step_deg)
            .unwrap_or(1.0);
        let limit = (cycle.pair.pinion().angular_pitch().to_degrees() / step).ceil() as usize;
        for _ in 0..limit {
            if !cycle.loaded(&results[0], mid) {
                break;
            }
            let a = angles[0] - step;
            results.insert(0, cycle.solve(a)?);
            angles.insert(0, a);
            extended += 1;
        }
        for _ in 0..limit {
            if !cycle.loaded(&results[results.len() - 1], mid) {
                break;
            }
            let a = angles[angles.len() - 1] + step;
            results.push(cycle.solve(a)?);
            angles.push(a);
            extended += 1;
        }
    }
    let mut notes = scene.material_warnings();
    let limits = cycle.loaded_limits(&angles, &results)?;
    if limits.is_none() {
        notes.push("contact ratio not measured: the roll angles do not cover the middle pair's whole engagement with an unloaded position before and after".to_string());
    }
    let mut lubrication = None;
    if let Some(l) = &lubricated {
        let dry = std::mem::take(&mut results);
        let lc = crate::ltca::lubricated::lubricated_cycle(&cycle, scene, l, dry, &angles, out)?;
        results = lc.results;
        notes.push(format!(
            "lubricated: the contact-limit bisection ran at the dry pass's μ₀ = {}; the positions, and the forces and power of `friction` (whose `mu` is μ₀; its power is the mean over all positions, the `lubrication` one over one pitch), are the last wet pass's, solved with μ per tooth pair (lubrication_passes.csv)",
            l.settings.initial_mu
        ));
        lubrication = Some(lc.summary);
    }
    let pitch_deg = cycle.pair.pinion().angular_pitch().to_degrees();
    let contact_ratio = limits.map(|(s, e)| (e - s) / pitch_deg);
    let nominal = cycle.nominal_force();
    let np = cycle.pair.sector_teeth();
    let forces: Vec<Vec<f64>> = results.iter().map(|r| cycle.pair_forces(r)).collect();
    let single: Vec<usize> = (0..results.len())
        .filter(|&i| (0..np).all(|p| (p == mid) == (forces[i][p] > LOADED_FRACTION * nominal)))
        .collect();
    let single_pair_force_n = (!single.is_empty())
        .then(|| single.iter().map(|&i| forces[i][mid]).sum::<f64>() / single.len() as f64);
    let flagged: Vec<String> = results
        .iter()
        .filter(|r| !r.kkt_within_tolerance)
        .map(|r| {
            format!(
                "{}°: KKT residual {:.2e} above tolerance",
                r.roll_deg, r.kkt_max
            )
        })
        .collect();
    let friction: Vec<Vec<f64>> = results.iter().map(|r| cycle.pair_friction(r)).collect();
    write_cycle_csv(
        &out.join("ltca_cycle.csv"),
        &results,
        &forces,
        &friction,
        nominal,
    )?;
    write_points_csv(&out.join("ltca_points.csv"), &results)?;
    let teeth: Vec<(usize, usize)> = (1..=np).map(|k| (k, cycle.pair.mate(k))).collect();
    let series: Vec<Vec<f64>> = (0..np)
        .map(|p| forces.iter().map(|f| f[p]).collect())
        .collect();
    let te: Vec<f64> = results.iter().map(|r| r.te_urad).collect();
    let plots = crate::report::cycle_plot::plot_cycle(
        out,
        "ltca_",
        &angles,
        &series,
        &te,
        &teeth,
        nominal,
        cycle.pair.transmission_error_radius(),
    )
    .unwrap_or_else(|e| {
        notes.push(format!("plots not written: {e}"));
        Vec::new()
    });
    let pattern = crate::ltca::pattern::plot_contact_pattern(out, &results, cycle.pair.middle(), {
        let (z0, z1) = cycle.pair.pinion().blank().axial_range;
        z1 - z0
    })
    .unwrap_or_else(|e| {
        notes.push(format!("contact pattern not plotted: {e}"));
        Vec::new()
    });
    let loops = iteration_limits(&results);
    notes.extend(loops.warnings());
    // the positions run side by side: the wall time of the cycle over them
    // (the extension and the bisection after it, one position at a time,
    // are not in it)
    let time_per_position_s = cycle_s / positions_solved.max(1) as f64;
    let worst = |f: fn(&PositionResult) -> f64| results.iter().map(f).fold(0.0f64, f64::max);
    let summary = serde_json::json!({
        "scene": scene.source.display().to_string(),
        "analysis": "ltca_mesh_cycle",
        "contact_ratio": contact_ratio,
        "contact_ratio_kinematic": cycle.pair.kinematic_contact_ratio(),
        "middle_pair_loaded_deg": limits.map(|(s, e)| [s, e]),
        "single_pair_force_n": single_pair_force_n,
        "nominal_force_n": nominal,
        "single_pair_force_error": single_pair_force_n.map(|f| f / nominal - 1.0),
        "positions": results.len(),
        "extension_positions": extended,
        "points_per_line": cycle.points_per_line,
        "cycle_s": cycle_s,
        "time_per_position_s": time_per_position_s,
        "total_s": t_total.elapsed().as_secs_f64(),
        "setup": cycle.setup,
        "settings": cycle.settings,
        "max_kkt": worst(|r| r.kkt_max),
        "max_condition": results.iter().filter_map(|r| r.condition).reduce(f64::max),
        "max_condition_loaded": results.iter().filter_map(|r| r.condition_loaded).reduce(f64::max),
        "tensor_backward_error": cycle.setup.backward_error,
        "warnings": results
            .iter()
            .flat_map(|r| r.warnings.iter().map(move |w| format!("{:.4}°: {w}", r.roll_deg)))
            .collect::<Vec<_>>(),
        "kkt_flagged": flagged,
        "iteration_limits": loops.to_json(),
        "max_pressure_mpa": worst(|r| r.max_pressure_mpa),
        "friction": cycle.settings.friction.as_ref().map(|f| friction_summary(&results, f, cycle.torque)),
        "peak_memory_mb": peak_memory_mb(),
        "tooth_pairs": teeth,
        "files": {"csv": ["ltca_cycle.csv", "ltca_points.csv"], "plots": plots, "contact_pattern": pattern},
        "notes": notes,
        "steps": results,
    });
    let mut summary = summary;
    if let (Some(m), Some(l)) = (summary.as_object_mut(), lubrication) {
        m.insert("lubrication".into(), l);
    }
    let p = out.join("summary.json");
    crate::atomic_file::write(
        &p,
        serde_json::to_string_pretty(&summary)
            .map_err(|e| FlankError::Model(format!("summary: {e}")))?
            + "\n",
    )?;
    Ok(summary)
}

/// The bounded loops of every position together (the summary's
/// `iteration_limits`).
pub(crate) fn iteration_limits(results: &[PositionResult]) -> IterationLimits {
    let mut all = IterationLimits::new();
    for r in results {
        all.merge(&r.iteration_limits);
    }
    all
}

/// The frictional LTCA over the cycle (seeds 001/003): the Coulomb
/// solve's worst residual and, if run, the largest difference from Lemke's
/// method; the tangential-to-normal force ratio; the friction power loss
/// Σ |P_t v_s| (W) and the mesh efficiency 1 − P_loss/(T ω₁), mean over the
/// positions (seed 001 eq. for P_loss; η as Xu & Kahraman's
/// instantaneous mesh efficiency).
pub(crate) fn friction_summary(
    results: &[PositionResult],
    friction: &LtcaFriction,
    torque_nmm: f64,
) -> serde_json::Value {
    let num = |r: &PositionResult, k: &str| -> f64 {
        r.friction
            .as_ref()
            .and_then(|f| f.pointer(k))
            .and_then(serde_json::Value::as_f64)
            .unwrap_or(0.0)
    };
    let max = |k: &str| results.iter().map(|r| num(r, k)).fold(0.0f64, f64::max);
    let (pt, pn): (f64, f64) = results
        .iter()
        .flat_map(|r| &r.points)
        .fold((0.0, 0.0), |(a, b), p| {
            (a + p.friction_n.abs(), b + p.force_n)
        });
    let n = results.len().max(1) as f64;
    let power: Vec<f64> = results.iter().map(|r| r.friction_power_w).collect();
    let mean_power = power.iter().sum::<f64>() / n;
    let input_w = torque_nmm * 1e-3 * friction.pinion_speed_rad_s;
    let within = results.iter().all(|r| r.kkt_within_tolerance);
    serde_json::json!({
        "mu": friction.mu,
        "increments": friction.options.increments,
        "max_residual": max("/max_residual/max"),
        "max_coupling": max("/coupling"),
        "within_tolerance": within,
        "cross_check_max_load_difference": friction.cross_check.then(|| max("/cross_check/load_difference")),
        "cross_check_max_rotation_difference": friction.cross_check.then(|| max("/cross_check/rotation_difference")),
        "tangential_to_normal": if pn > 0.0 { pt / pn } else { 0.0 },
        "power_loss_w": power,
        "mean_power_loss_w": mean_power,
        "input_power_w": input_w,
        "mesh_efficiency": if input_w > 0.0 { 1.0 - mean_power / input_w } else { f64::NAN },
    })
}

fn write_cycle_csv(
    path: &Path,
    results: &[PositionResult],
    forces: &[Vec<f64>],
    friction: &[Vec<f64>],
    nominal: f64,
) -> Result<(), FlankError> {
    use std::fmt::Write;
    let np = forces.first().map_or(0, Vec::len);
    let mut s = String::from("roll_deg");
    for p in 1..=np {
        let _ = write!(s, ",force_pair{p}_n,share_pair{p}");
    }
    for p in 1..=np {
        let _ = write!(s, ",friction_pair{p}_n");
    }
    s.push_str(",te_urad,te_um,unloaded_te_urad,mesh_stiffness_n_per_um,max_pressure_mpa,friction_power_w,candidates,qp_iterations,local_iterations,kkt,condition,time_s\n");
    for ((r, f), ft) in results.iter().zip(forces).zip(friction) {
        let _ = write!(s, "{}", r.roll_deg);
        let total: f64 = f.iter().sum::<f64>().max(1e-300);
        for &x in f {
            let _ = write!(s, ",{x},{}", if nominal > 0.0 { x / total } else { 0.0 });
        }
        for &x in ft {
            let _ = write!(s, ",{x}");
        }
        let _ = writeln!(
            s,
            ",{},{},{},{},{},{},{},{},{},{:e},{},{}",
            r.te_urad,
            r.te_um,
            r.unloaded_te_urad,
            r.mesh_stiffness_n_per_um,
            r.max_pressure_mpa,
            r.friction_power_w,
            r.candidates,
            r.qp_iterations,
            r.local_iterations,
            r.kkt_max,
            r.condition.map_or(String::new(), |c| format!("{c:e}")),
            r.time_s
        );
    }
    crate::atomic_file::write(path, s)
}

pub(crate) fn write_points_csv(path: &Path, results: &[PositionResult]) -> Result<(), FlankError> {
    use std::fmt::Write;
    let mut s = String::from("roll_deg,pinion_tooth,gear_tooth,kind,along_mm,x_mm,y_mm,z_mm,separation_um,force_n,load_per_length_n_per_mm,pressure_mpa,half_width_mm,gap_um,friction_n,state,sliding_velocity_m_s\n");
    for r in results {
        for p in &r.points {
            let (k, m, kind) = &r.lines[p.line];
            let _ = writeln!(
                s,
                "{},{k},{m},{kind},{},{},{},{},{},{},{},{},{},{},{},{},{}",
                r.roll_deg,
                p.along_mm,
                p.position[0],
                p.position[1],
                p.position[2],
                p.separation_mm * 1e3,
                p.force_n,
                p.load_per_length,
                p.pressure_mpa,
                p.half_width_mm,
                p.gap_mm * 1e3,
                p.friction_n,
                p.state,
                p.sliding_velocity_m_s
            );
        }
    }
    crate::atomic_file::write(path, s)
}

#[cfg(test)]
mod tests {
    use super::*;

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
        let (a, e) = cycle.pair.engagement(cycle.pair.middle());
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
