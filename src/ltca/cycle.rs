//! The LTCA of a spur/helical pair over a mesh cycle: compliance tensors of
//! both bodies once (computed or read from a cache), then per roll angle
//! the unloaded TCA, the compliance matrix of its candidate points and the
//! contact QP ([`LtcaCycle`]). The `flank ltca` run over a scene, its files
//! and summary, is [`crate::ltca::run`].
//!
//! Pairs are numbered as in FE contact ([`crate::mesh_cycle`]): pair p is
//! pinion tooth p + 1 with its mate, so the two runs compare column by
//! column.

use std::path::PathBuf;
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
use crate::geometry::gear_pair::{engagement_roll_angles, LineContactPair};
use crate::load_sharing::LOADED_FRACTION;
use crate::ltca::local::contact_modulus;
use crate::ltca::model::{LtcaBodies, PositionResult};
use crate::ltca::solve_settings::{LtcaFriction, LtcaSettings};
use crate::scene::Scene;
use crate::settings::{FlankRegion, FrictionModel, LocalModel, QpSolver};
use crate::tca::{Tca, TcaSettings};

/// Default K (candidate points per contact line).
pub const DEFAULT_POINTS_PER_LINE: usize = 20;

/// Options of [`crate::ltca::run::run`]; `None` falls back to the scene's `[analyses.ltca]`,
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
    /// Bevel/hypoid pairs: the separation (mm) out to which each pair's
    /// candidate axis runs (default
    /// [`crate::ltca::bevel::DEFAULT_SPAN_APPROACH_MM`]).
    pub span_approach_mm: Option<f64>,
    /// Bevel/hypoid pairs: the TCA's edge contacts as candidates, or not,
    /// or both variants (default: the scene's `[analyses.ltca] edges`,
    /// else without).
    pub edges: Option<crate::settings::EdgeVariants>,
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
    pub pair: Arc<dyn LineContactPair>,
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
        let cyl = scene.cylindrical("the spur/helical LTCA")?;
        let a = scene.analyses.ltca.clone().unwrap_or_default();
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
        let pair: Arc<dyn LineContactPair> = Arc::new(
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
            pair: Arc::clone(&pair) as Arc<dyn crate::geometry::gear_pair::GearPair>,
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
