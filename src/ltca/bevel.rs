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
//! Outputs (`out`): `ltca_positions.csv` (per position and tooth pair, the
//! columns of the FE run's `positions.csv`), `ltca_points.csv` (load along
//! every axis), `summary.json`.

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use crate::compliance::body::{bevel_scene_body, BodyMeshOptions};
use crate::compliance::cache::{ComplianceCache, FileFormat};
use crate::compliance::run::{body_tensor, BodyTensorOptions};
use crate::compliance::FlankInterpolator;
use crate::error::FlankError;
use crate::fem::static_analysis::peak_memory_mb;
use crate::geometry::gear_pair::PairPlacement;
use crate::ltca::local::contact_modulus;
use crate::ltca::model::{LtcaBodies, LtcaFriction, LtcaSettings, PositionResult};
use crate::scene::BevelScene;
use crate::tca::major_axis::major_axis_line;
use crate::tca::point_contact::{point_tca, PointTca, PointTcaSettings, ARCSEC_PER_RAD};
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
    pub friction_model: crate::ltca::model::FrictionModel,
    pub cache: Option<PathBuf>,
    pub threads: usize,
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
        }
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
}

impl BevelLtcaOptions {
    /// Checks the options against the scene before anything is computed
    /// or written.
    pub fn validate(&self, scene: &BevelScene) -> Result<(), FlankError> {
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
    fn friction(&self, scene: &BevelScene) -> Result<Option<LtcaFriction>, FlankError> {
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
    pub fn new(scene: &BevelScene, options: &BevelLtcaOptions) -> Result<Self, FlankError> {
        options.validate(scene)?;
        let torque = scene.load.torque_nmm;
        let t = Instant::now();
        let campaign = match &options.cache {
            Some(d) => Some(ComplianceCache::in_dir(d, FileFormat::default_format())?),
            None => None,
        };
        let topts = BodyTensorOptions::for_ltca(options.threads, campaign.as_ref());
        let mut tensors = Vec::new();
        for name in ["pinion", "gear"] {
            let body = bevel_scene_body(scene, name, &options.mesh)?;
            tensors.push(body_tensor(&body, &topts, &options.out)?.tensor);
        }
        let compliance_s = t.elapsed().as_secs_f64();
        let t = Instant::now();
        let tca = point_tca(
            scene.pair.as_ref(),
            &PointTcaSettings {
                positions_per_pitch: options.positions,
                edges: false,
                search_directions: 0,
                speed_rpm: scene.load.speed_rpm,
                ..Default::default()
            },
        )?;
        let tca_s = t.elapsed().as_secs_f64();
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
            pair: Arc::clone(&scene.pair) as Arc<dyn PairPlacement>,
            nominal_moment_arm_mm: arm,
            te_radius_mm: arm,
            contact_modulus: contact_modulus(
                [scene.pinion_material.young, scene.gear_material.young],
                [scene.pinion_material.poisson, scene.gear_material.poisson],
            ),
        };
        Ok(BevelLtca {
            pair: Arc::clone(&scene.pair),
            tca,
            bodies,
            options,
            torque,
            compliance_s,
            tca_s,
            flank_nodes,
        })
    }

    /// The mesh cycle (deg): one pinion pitch.
    pub fn cycle_deg(&self) -> f64 {
        self.tca.pitch_rad.to_degrees()
    }

    /// The TCA grid position nearest to `roll_deg`, as the LTCA's contact
    /// lines (one major axis per tooth pair in the sector).
    pub fn position(&self, roll_deg: f64) -> Result<TcaPosition, FlankError> {
        let p = self
            .tca
            .positions
            .iter()
            .min_by(|a, b| {
                (a.roll_rad.to_degrees() - roll_deg)
                    .abs()
                    .total_cmp(&(b.roll_rad.to_degrees() - roll_deg).abs())
            })
            .ok_or_else(|| FlankError::Model("LTCA: the point TCA traced no position".into()))?;
        let step = self.tca.pitch_rad.to_degrees() / self.options.positions as f64;
        if (p.roll_rad.to_degrees() - roll_deg).abs() > 0.51 * step {
            return Err(FlankError::Model(format!(
                "LTCA: roll angle {roll_deg}° lies beyond the traced contact ({:.3}° … {:.3}°)",
                self.tca.positions[0].roll_rad.to_degrees(),
                self.tca.positions[self.tca.positions.len() - 1]
                    .roll_rad
                    .to_degrees()
            )));
        }
        // one major axis per pair, the pairs in parallel
        use rayon::prelude::*;
        let lines: Vec<_> = p
            .pairs
            .par_iter()
            .map(|c| {
                major_axis_line(
                    self.pair.as_ref(),
                    c,
                    p.roll_rad,
                    self.options.points_per_pair,
                    self.tca.settings.approach_mm,
                    self.options.span_approach_mm,
                )
            })
            .collect::<Result<Vec<_>, _>>()?
            .into_iter()
            .flatten()
            .collect();
        let unloaded = lines
            .iter()
            .flat_map(|l| l.points.iter())
            .map(|q| q.separation_mm / q.moment_arm_mm)
            .fold(f64::INFINITY, f64::min);
        Ok(TcaPosition {
            roll: p.roll_rad,
            unloaded_te_rad: unloaded,
            lines,
        })
    }

    /// Solves the position nearest to `roll_deg`.
    pub fn solve(&self, roll_deg: f64) -> Result<PositionResult, FlankError> {
        let position = self.position(roll_deg)?;
        if position.lines.is_empty() {
            return Err(FlankError::Model(format!(
                "LTCA at roll {roll_deg}°: no tooth pair of the sector has a flank contact"
            )));
        }
        let frames = self.pair.frames(position.roll);
        self.bodies
            .solve(&position, &frames, self.torque, &self.options.settings)
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
        -r.te_urad * 1e-6 * self.pair.ratio() * ARCSEC_PER_RAD
    }
}

/// `flank ltca` on a bevel/hypoid scene: the cycle's positions, the files
/// of the module docs; returns the summary.
pub fn run_bevel(
    scene: &BevelScene,
    options: &BevelLtcaOptions,
) -> Result<serde_json::Value, FlankError> {
    use std::fmt::Write;
    let t_total = Instant::now();
    options.validate(scene)?;
    let out = &options.out;
    std::fs::create_dir_all(out).map_err(|e| FlankError::io(out, e))?;
    let ltca = BevelLtca::new(scene, options)?;
    let pitch = ltca.cycle_deg();
    let n = options.positions;
    let rolls = options.roll_angles_deg.clone().unwrap_or_else(|| {
        (0..n)
            .map(|i| -0.5 * pitch + pitch * i as f64 / n as f64)
            .collect()
    });
    let t_cycle = Instant::now();
    let results = ltca.solve_cycle(&rolls)?;
    let cycle_s = t_cycle.elapsed().as_secs_f64();
    let np = ltca.pair.sector_teeth();
    let mut csv = String::from(
        "roll_deg,pair,pinion_tooth,gear_tooth,force_n,load_share,max_pressure_mpa,te_arcsec,friction_n\n",
    );
    let mut notes = Vec::new();
    let mut te = Vec::new();
    let mut edge_loaded = 0usize;
    for r in &results {
        let forces = ltca.pair_forces(r);
        let friction = ltca.pair_friction(r);
        let total: f64 = forces.iter().sum();
        let te_arcsec = ltca.te_arcsec(r);
        te.push(te_arcsec);
        for (p, &f) in forces.iter().enumerate() {
            let pmax = r
                .points
                .iter()
                .filter(|q| r.lines[q.line].0 == p + 1)
                .map(|q| q.pressure_mpa)
                .fold(0.0f64, f64::max);
            let _ = writeln!(
                csv,
                "{},{},{},{},{:e},{:e},{:e},{:e},{:e}",
                r.roll_deg,
                p + 1,
                p + 1,
                ltca.pair.mate(p + 1),
                f,
                if total > 0.0 { f / total } else { 0.0 },
                pmax,
                te_arcsec,
                friction[p]
            );
        }
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
    let loops = crate::ltca::cycle::iteration_limits(&results);
    notes.extend(loops.warnings());
    let path = out.join("ltca_positions.csv");
    crate::atomic_file::write(&path, csv)?;
    crate::ltca::cycle::write_points_csv(&out.join("ltca_points.csv"), &results)?;
    let te_pp = te.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
        - te.iter().cloned().fold(f64::INFINITY, f64::min);
    let worst = |f: fn(&PositionResult) -> f64| results.iter().map(f).fold(0.0f64, f64::max);
    let summary = serde_json::json!({
        "scene": scene.source.display().to_string(),
        "analysis": "ltca_bevel_cycle",
        "positions": results.len(),
        "mesh_cycle_deg": pitch,
        "torque_nm": ltca.torque / 1000.0,
        "points_per_pair": options.points_per_pair,
        "span_approach_mm": options.span_approach_mm,
        "friction_mu": options.friction_mu,
        "increments": (options.friction_mu > 0.0).then_some(options.increments),
        "approach_mm": ltca.tca.settings.approach_mm,
        "flank_nodes": ltca.flank_nodes,
        "tooth_pairs": (1..=np).map(|k| (k, ltca.pair.mate(k))).collect::<Vec<_>>(),
        "te_peak_to_peak_arcsec": te_pp,
        "max_pressure_mpa": worst(|r| r.max_pressure_mpa),
        "max_kkt": worst(|r| r.kkt_max),
        "iteration_limits": loops.to_json(),
        "friction": ltca.options.settings.friction.as_ref().map(|f| crate::ltca::cycle::friction_summary(&results, f, ltca.torque)),
        "pairs_loaded_at_a_flank_edge": edge_loaded,
        "compliance_s": ltca.compliance_s,
        "tca_s": ltca.tca_s,
        "cycle_s": cycle_s,
        "time_per_position_s": cycle_s / results.len().max(1) as f64,
        "total_s": t_total.elapsed().as_secs_f64(),
        "peak_memory_mb": peak_memory_mb(),
        "settings": options.settings,
        "notes": notes,
        "steps": results.iter().zip(&te).map(|(r, &t)| serde_json::json!({
            "roll_deg": r.roll_deg,
            "pair_force_n": ltca.pair_forces(r),
            "load_share": shares(&ltca.pair_forces(r)),
            "pair_friction_n": ltca.pair_friction(r),
            "friction": r.friction,
            "te_arcsec": t,
            "unloaded_te_arcsec": -r.unloaded_te_urad * 1e-6 * ltca.pair.ratio() * ARCSEC_PER_RAD,
            "max_pressure_mpa": r.max_pressure_mpa,
            "candidates": r.candidates,
            "qp_iterations": r.qp_iterations,
            "kkt_max": r.kkt_max,
            "time_s": r.time_s,
        })).collect::<Vec<_>>(),
    });
    let path = out.join("summary.json");
    crate::atomic_file::write(
        &path,
        serde_json::to_string_pretty(&summary).unwrap_or_default() + "\n",
    )?;
    Ok(summary)
}

/// Each force's share of their sum (0 without load).
fn shares(forces: &[f64]) -> Vec<f64> {
    let s: f64 = forces.iter().sum();
    forces
        .iter()
        .map(|x| if s > 0.0 { x / s } else { 0.0 })
        .collect()
}
