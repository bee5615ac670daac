//! `flank tca` over a scene of any pair kind: the unloaded TCA over the
//! mesh cycle with and without edge contact, its tables and its typed
//! summary ([`TcaSummary`]; `summary.json` is its serialization, written
//! by the caller once the plots are drawn, [`crate::api::tca`]).
//!
//! * Spiral bevel and hypoid scenes: the point-contact TCA
//!   ([`crate::tca::point_contact`]); `tca_with_edges.csv`,
//!   `tca_without_edges.csv` (one row per position and tooth pair) and
//!   `transitions.csv`; with `sweep_mm` the V–H sweep ([`vh_sweep`]).
//! * Spur and helical scenes: the line-contact TCA
//!   ([`crate::tca::line_cycle`]) with and without tip-corner contact (the
//!   edge contact of these pairs) on a sector holding every pair that can
//!   be in mesh; the same two tables (θ₀, the pair's lines, its smallest
//!   gap and closest point).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use serde::Serialize;

use crate::error::FlankError;
use crate::geometry::bevel::pair::BevelPair;
use crate::geometry::gear_pair::{GearPair, LineContactPair, Misalignment};
use crate::iteration_limits::IterationLimits;
use crate::scene::{Gears, Scene};
use crate::tca::crossing::ScanCount;
use crate::tca::line_cycle::{line_tca_cycle, LineTcaCycle};
use crate::tca::point_contact::{
    point_tca, point_tca_shared, EllipseMemo, PointTca, PointTcaSettings, Transition,
    ARCSEC_PER_RAD,
};
use crate::tca::{Tca, TcaSettings};

/// Options of [`run`] (the command line of `flank tca`).
#[derive(Clone, Debug)]
pub struct TcaOptions {
    pub out: PathBuf,
    /// Elastic approach δ of the contact ellipse (mm): 0.00635 finished
    /// teeth, 0.00381 lapped (seed 000).
    pub approach_mm: f64,
    /// Positions per angular pitch (4 … 10 000).
    pub positions_per_pitch: usize,
    /// Planes of the numerical contact-ellipse search over 180° (0: off,
    /// else 4 … 3 600; bevel/hypoid only).
    pub search_directions: usize,
    /// Offset error, axial displacements, shaft-angle error.
    pub misalignment: Misalignment,
    /// The V–H sweep's half-range (mm; bevel/hypoid only).
    pub sweep_mm: Option<f64>,
    /// Print no progress.
    pub quiet: bool,
}

impl Default for TcaOptions {
    fn default() -> Self {
        TcaOptions {
            out: PathBuf::from("out"),
            approach_mm: 0.00635,
            positions_per_pitch: 30,
            search_directions: 18,
            misalignment: Misalignment::default(),
            sweep_mm: None,
            quiet: false,
        }
    }
}

impl TcaOptions {
    /// Every option in its range, named as on the command line.
    pub fn validate(&self) -> Result<(), FlankError> {
        let bad = |m: String| Err(FlankError::Model(m));
        if !(self.approach_mm.is_finite() && self.approach_mm > 0.0) {
            return bad(format!(
                "--approach-mm {}: a finite positive elastic approach δ is needed (seed 000: 0.00635 mm finished, 0.00381 mm lapped)",
                self.approach_mm
            ));
        }
        if !(4..=10_000).contains(&self.positions_per_pitch) {
            return bad(format!(
                "--positions-per-pitch {}: between 4 and 10000 positions per pitch are needed",
                self.positions_per_pitch
            ));
        }
        if self.search_directions != 0 && !(4..=3600).contains(&self.search_directions) {
            return bad(format!(
                "--search-directions {}: 0 (no search) or 4 to 3600 planes are needed",
                self.search_directions
            ));
        }
        let m = &self.misalignment;
        for (v, name) in [
            (m.offset_error_mm, "--offset-error-mm"),
            (m.pinion_axial_mm, "--pinion-axial-mm"),
            (m.gear_axial_mm, "--gear-axial-mm"),
            (
                m.shaft_angle_error_rad.to_degrees(),
                "--shaft-angle-error-deg",
            ),
        ] {
            if !v.is_finite() {
                return bad(format!("{name} {v}: a finite value is needed"));
            }
        }
        if let Some(r) = self.sweep_mm {
            if !(r.is_finite() && r > 0.0) {
                return bad(format!(
                    "--sweep-mm {r}: a finite positive half-range is needed"
                ));
            }
        }
        Ok(())
    }
}

/// `summary.json` of `flank tca`.
#[derive(Clone, Debug, Serialize)]
pub struct TcaSummary {
    /// Schema version, scene file and pair kind.
    #[serde(flatten)]
    pub header: crate::summary::Header,
    /// The pair's kinematic data ([`GearPair::describe`]).
    pub pair: serde_json::Value,
    pub approach_mm: f64,
    pub misalignment: Misalignment,
    #[serde(flatten)]
    pub kind: TcaKind,
    pub run_time_s: f64,
}

/// What only one pair kind's TCA reports.
#[derive(Clone, Debug, Serialize)]
#[serde(untagged)]
pub enum TcaKind {
    Point(Box<PointTcaSummary>),
    Line(Box<LineTcaSummary>),
}

/// The point TCA's variants.
#[derive(Clone, Debug, Serialize)]
pub struct PointTcaSummary {
    pub with_edges: PointVariant,
    pub without_edges: PointVariant,
}

/// One variant of the point TCA.
#[derive(Clone, Debug, Serialize)]
pub struct PointVariant {
    pub contact_ratio: f64,
    pub flank_span_ratio: f64,
    /// Unloaded TE peak-to-peak at the gear (arcsec).
    pub te_peak_to_peak_arcsec: f64,
    pub positions: usize,
    pub transitions: Vec<Transition>,
    pub hit_trace_bound: bool,
    pub max_point_residual_mm: f64,
    pub max_tangency_residual: f64,
    pub newton_steps: usize,
    pub branch_jumps: usize,
    pub iteration_limits: IterationLimits,
    /// Where the flanks cross, if they do.
    pub crossing: Option<CrossingReport>,
    pub crossing_scan: ScanCount,
}

/// Where the flanks of a point TCA cross (roll in degrees).
#[derive(Clone, Debug, Serialize)]
pub struct CrossingReport {
    pub roll_deg: f64,
    pub pair_offset: i64,
    pub depth_mm: f64,
    pub pinion_uv_mm: [f64; 2],
    pub gear_uv_mm: [f64; 2],
}

impl PointVariant {
    fn of(t: &PointTca) -> Self {
        PointVariant {
            contact_ratio: t.contact_ratio,
            flank_span_ratio: t.flank_span_ratio,
            te_peak_to_peak_arcsec: t.te_peak_to_peak_rad * ARCSEC_PER_RAD,
            positions: t.positions.len(),
            transitions: t.transitions.clone(),
            hit_trace_bound: t.hit_trace_bound,
            max_point_residual_mm: t.max_residual[0],
            max_tangency_residual: t.max_residual[1],
            newton_steps: t.newton_steps,
            branch_jumps: t.branch_jumps,
            iteration_limits: t.iteration_limits.clone(),
            crossing: t.crossing.map(|c| CrossingReport {
                roll_deg: c.roll_rad.to_degrees(),
                pair_offset: c.pair_offset,
                depth_mm: c.depth_mm,
                pinion_uv_mm: c.pinion_uv,
                gear_uv_mm: c.gear_uv,
            }),
            crossing_scan: t.crossing_scan,
        }
    }
}

/// The line TCA's sector and variants.
#[derive(Clone, Debug, Serialize)]
pub struct LineTcaSummary {
    pub positions_per_pitch: usize,
    /// Teeth of the TCA's sector.
    pub sector_teeth: usize,
    pub with_edges: LineVariant,
    pub without_edges: LineVariant,
    /// Plot file names (filled by the caller that draws them).
    pub plots: Vec<String>,
}

/// One variant of the line TCA: the keys of the point TCA's variants
/// (`contact_ratio`, `te_peak_to_peak_arcsec` at the gear) and its own.
#[derive(Clone, Debug, Serialize)]
pub struct LineVariant {
    pub contact_ratio: f64,
    pub transverse_contact_ratio: f64,
    pub te_peak_to_peak_arcsec: f64,
    pub te_peak_to_peak_urad: f64,
    pub positions: usize,
    pub tip_corners: bool,
    pub corner_contact_positions: usize,
}

impl LineVariant {
    fn of(c: &LineTcaCycle, ratio: f64) -> Self {
        LineVariant {
            contact_ratio: c.contact_ratio,
            transverse_contact_ratio: c.transverse_contact_ratio,
            te_peak_to_peak_arcsec: c.te_peak_to_peak_rad * ratio * ARCSEC_PER_RAD,
            te_peak_to_peak_urad: c.te_peak_to_peak_rad * 1e6,
            positions: c.positions.len(),
            tip_corners: c.corners,
            corner_contact_positions: c.corner_contact_positions,
        }
    }
}

/// The traced cycles [`run`] returns beside the summary, for plots.
pub enum TcaCycles {
    /// A bevel/hypoid pair (misaligned as asked) and its point TCAs.
    Point {
        pair: Arc<dyn GearPair>,
        with: Box<PointTca>,
        without: Box<PointTca>,
    },
    /// A cylindrical pair's line TCAs.
    Line {
        with: Box<LineTcaCycle>,
        without: Box<LineTcaCycle>,
    },
}

/// What [`run`] computed: the summary, the cycles, warnings for the user.
pub struct TcaRun {
    pub summary: TcaSummary,
    pub cycles: TcaCycles,
    pub warnings: Vec<String>,
}

/// The TCA of `scene` with and without edge contact: writes the tables
/// into `options.out` (not `summary.json`, not the plots) and returns them.
pub fn run(scene: &Scene, options: &TcaOptions) -> Result<TcaRun, FlankError> {
    options.validate()?;
    let mis = options.misalignment;
    let out = &options.out;
    match &scene.gears {
        Gears::Bevel(bevel) => {
            let pair: Arc<dyn GearPair> = Arc::new(bevel.pair.with_misalignment(mis));
            let settings = point_settings(scene, options);
            let t0 = std::time::Instant::now();
            // the flank contacts of both runs are the same points: their
            // ellipse searches are done once
            let memo = EllipseMemo::default();
            let say = |m: String| {
                if !options.quiet {
                    eprintln!("{m}");
                }
            };
            if settings.search_directions > 0 {
                say(format!(
                    "TCA with edge contact, numerical ellipse search in {} planes at every contact (--search-directions 0 skips it; minutes on a conjugate pinion without ease-off, whose contact is a line) …",
                    settings.search_directions
                ));
            }
            let with = point_tca_shared(pair.as_ref(), &settings, &memo)?;
            if settings.search_directions > 0 {
                say(format!(
                    "  {} contacts searched in {:.1} s; TCA without edge contact …",
                    memo.len(),
                    t0.elapsed().as_secs_f64()
                ));
            }
            let without = point_tca_shared(
                pair.as_ref(),
                &PointTcaSettings {
                    edges: false,
                    ..settings.clone()
                },
                &memo,
            )?;
            let seconds = t0.elapsed().as_secs_f64();
            std::fs::create_dir_all(out).map_err(|e| FlankError::io(out, e))?;
            write_point_table(&out.join("tca_with_edges.csv"), &with)?;
            write_point_table(&out.join("tca_without_edges.csv"), &without)?;
            write_transitions(&out.join("transitions.csv"), &with, &without)?;
            let mut warnings = Vec::new();
            for (variant, t) in [("with edges", &with), ("without edges", &without)] {
                for w in t.iteration_limits.warnings() {
                    warnings.push(format!(
                        "TCA {variant}: {w}; the trace ends there (summary.json: iteration_limits)"
                    ));
                }
            }
            if let Some(c) = with.crossing {
                warnings.push(format!(
                    "the flanks cross: at roll {:.3}° a point of the pinion's active flank (u, v) = ({:.3}, {:.3}) mm lies {:.4} mm inside the gear flank with the gear where the TE envelope puts it (pair offset {}); the pairs touch elsewhere first, and this TCA's TE and bearing are not the pair's (summary.json: crossing)",
                    c.roll_rad.to_degrees(),
                    c.pinion_uv[0],
                    c.pinion_uv[1],
                    c.depth_mm,
                    c.pair_offset
                ));
            }
            Ok(TcaRun {
                summary: TcaSummary {
                    header: scene.summary_header(),
                    pair: pair.describe(),
                    approach_mm: options.approach_mm,
                    misalignment: mis,
                    kind: TcaKind::Point(Box::new(PointTcaSummary {
                        with_edges: PointVariant::of(&with),
                        without_edges: PointVariant::of(&without),
                    })),
                    run_time_s: seconds,
                },
                cycles: TcaCycles::Point {
                    pair,
                    with: Box::new(with),
                    without: Box::new(without),
                },
                warnings,
            })
        }
        Gears::Cylindrical(cyl) => {
            if options.sweep_mm.is_some() {
                return Err(FlankError::Model("--sweep-mm: the V–H sweep is for bevel and hypoid scenes; a spur or helical pair's misalignment is swept by a campaign (docs/campaigns.md)".into()));
            }
            // a sector with every pair that can be in mesh and one more on
            // each side: ε_γ = ε_α + ε_β (ISO 21771), b the common face
            let g = &cyl.pair;
            let face = g.pinion.face_width.min(g.gear.face_width);
            let eps_beta = face * g.pinion.helix_angle.sin().abs()
                / (std::f64::consts::PI * g.pinion.normal_module);
            let eps_alpha = LineContactPair::kinematic_contact_ratio(&scene.cylindrical_pair()?);
            let mut teeth = (scene.mesh.teeth_in_sector as usize)
                .max((eps_alpha + eps_beta).ceil() as usize + 2);
            if teeth.is_multiple_of(2) {
                teeth += 1;
            }
            let pair: Arc<dyn LineContactPair> = Arc::new(
                crate::geometry::cylindrical::CylindricalPair::new(
                    g,
                    cyl.flank_modifications()?,
                    teeth,
                )?
                .with_misalignment(mis)?,
            );
            let t0 = std::time::Instant::now();
            let variant = |extension_mm: f64| -> Result<LineTcaCycle, FlankError> {
                let tca = Tca::new(
                    Arc::clone(&pair),
                    scene.load.speed_rpm,
                    TcaSettings {
                        extension_mm,
                        ..TcaSettings::default()
                    },
                )?;
                line_tca_cycle(&tca, options.positions_per_pitch, options.approach_mm)
            };
            let with = variant(TcaSettings::default().extension_mm)?;
            let without = variant(0.0)?;
            let seconds = t0.elapsed().as_secs_f64();
            std::fs::create_dir_all(out).map_err(|e| FlankError::io(out, e))?;
            let ratio = pair.ratio();
            write_line_table(&out.join("tca_with_edges.csv"), &with, ratio)?;
            write_line_table(&out.join("tca_without_edges.csv"), &without, ratio)?;
            Ok(TcaRun {
                summary: TcaSummary {
                    header: scene.summary_header(),
                    pair: pair.describe(),
                    approach_mm: options.approach_mm,
                    misalignment: mis,
                    kind: TcaKind::Line(Box::new(LineTcaSummary {
                        positions_per_pitch: options.positions_per_pitch,
                        sector_teeth: teeth,
                        with_edges: LineVariant::of(&with, ratio),
                        without_edges: LineVariant::of(&without, ratio),
                        plots: Vec::new(),
                    })),
                    run_time_s: seconds,
                },
                cycles: TcaCycles::Line {
                    with: Box::new(with),
                    without: Box::new(without),
                },
                warnings: Vec::new(),
            })
        }
    }
}

/// The point TCA's settings of [`run`] (edges on; the variant without
/// edges turns them off).
fn point_settings(scene: &Scene, options: &TcaOptions) -> PointTcaSettings {
    PointTcaSettings {
        positions_per_pitch: options.positions_per_pitch,
        approach_mm: options.approach_mm,
        edges: true,
        search_directions: options.search_directions,
        max_pitches: 3.0,
        speed_rpm: scene.load.speed_rpm,
        crossing_exhaustive: false,
    }
}

/// One setting of the V–H sweep: the misalignment added to the base, the
/// bearing centre on the gear (the middle pair's contact where its TE
/// peaks; face, profile in mm) and the TE peak-to-peak (arcsec), or the
/// reason the pair does not mesh there.
#[derive(Clone, Debug)]
pub struct VhSetting {
    pub offset_error_mm: f64,
    pub pinion_axial_mm: f64,
    pub centre_mm: Option<[f64; 2]>,
    pub te_peak_to_peak_arcsec: Option<f64>,
}

/// The V–H sweep of a bevel/hypoid scene: ΔE and ΔP each over
/// ±`options.sweep_mm` in 5 steps (25 point TCAs with edges, curvature
/// ellipses only) added to the options' misalignment; writes
/// `vh_sweep.csv` and returns the settings for the V–H chart.
pub fn vh_sweep(scene: &Scene, options: &TcaOptions) -> Result<Vec<VhSetting>, FlankError> {
    let Some(half_range) = options.sweep_mm else {
        return Ok(Vec::new());
    };
    let bevel: &BevelPair = &scene.bevel("the V–H sweep")?.pair;
    let base = options.misalignment;
    let mut s = String::from(
        "offset_error_mm,pinion_axial_mm,gear_face_mm,gear_profile_mm,te_peak_to_peak_arcsec,contact_ratio,edge_transitions\n",
    );
    let mut chart = Vec::new();
    let st = PointTcaSettings {
        search_directions: 0,
        ..point_settings(scene, options)
    };
    let steps: Vec<f64> = (0..5)
        .map(|i| half_range * (i as f64 / 2.0 - 1.0))
        .collect();
    for &de in &steps {
        for &dp in &steps {
            let m = Misalignment {
                offset_error_mm: base.offset_error_mm + de,
                pinion_axial_mm: base.pinion_axial_mm + dp,
                ..base
            };
            let row = match point_tca(&bevel.with_misalignment(m), &st) {
                Ok(t) => {
                    // the bearing centre: the middle pair where its lag peaks
                    let c = t
                        .positions
                        .iter()
                        .filter_map(|p| p.pairs.iter().find(|c| c.offset == 0))
                        .max_by(|a, b| a.gear_lag_rad.total_cmp(&b.gear_lag_rad));
                    let (f, h) = c
                        .map(|c| (c.projection_mm[1][0], c.projection_mm[1][1]))
                        .unwrap_or((f64::NAN, f64::NAN));
                    chart.push(VhSetting {
                        offset_error_mm: m.offset_error_mm - base.offset_error_mm,
                        pinion_axial_mm: m.pinion_axial_mm - base.pinion_axial_mm,
                        centre_mm: c.map(|_| [f, h]),
                        te_peak_to_peak_arcsec: Some(t.te_peak_to_peak_rad * ARCSEC_PER_RAD),
                    });
                    let edges = t
                        .transitions
                        .iter()
                        .filter(|x| x.to.contains("edge"))
                        .count();
                    format!(
                        "{:.4},{:.4},{f:.4},{h:.4},{:.4},{:.4},{edges}",
                        m.offset_error_mm,
                        m.pinion_axial_mm,
                        t.te_peak_to_peak_rad * ARCSEC_PER_RAD,
                        t.contact_ratio
                    )
                }
                // a setting where the pair does not mesh is a row saying so
                Err(e) => {
                    chart.push(VhSetting {
                        offset_error_mm: m.offset_error_mm - base.offset_error_mm,
                        pinion_axial_mm: m.pinion_axial_mm - base.pinion_axial_mm,
                        centre_mm: None,
                        te_peak_to_peak_arcsec: None,
                    });
                    format!(
                        "{:.4},{:.4},,,,,\"{}\"",
                        m.offset_error_mm,
                        m.pinion_axial_mm,
                        e.to_string().replace('"', "'")
                    )
                }
            };
            s.push_str(&row);
            s.push('\n');
        }
    }
    crate::atomic_file::write(&options.out.join("vh_sweep.csv"), s)?;
    Ok(chart)
}

/// One row per position and tooth pair of a line TCA cycle.
fn write_line_table(path: &Path, c: &LineTcaCycle, ratio: f64) -> Result<(), FlankError> {
    let mut s = String::from(
        "roll_deg,unloaded_te_urad,te_arcsec,pinion_tooth,gear_tooth,lines,length_mm,min_gap_mm,in_contact,pinion_u_rad,pinion_v_mm,x_mm,y_mm,z_mm,sliding_velocity_m_s,rolling_velocity_m_s,equivalent_radius_mm\n",
    );
    for p in &c.positions {
        for q in &p.pairs {
            let _ = writeln!(
                s,
                "{:.6},{:.6e},{:.6e},{},{},{},{:.6},{:.6e},{},{:.8},{:.6},{:.6},{:.6},{:.6},{:.6e},{:.6e},{:.6}",
                p.roll_rad.to_degrees(),
                p.unloaded_te_rad * 1e6,
                -p.unloaded_te_rad * ratio * ARCSEC_PER_RAD,
                q.pinion_tooth,
                q.gear_tooth,
                q.kinds,
                q.length_mm,
                q.min_gap_mm,
                q.in_contact,
                q.pinion_uv[0],
                q.pinion_uv[1],
                q.position_mm[0],
                q.position_mm[1],
                q.position_mm[2],
                q.sliding_velocity_m_s,
                q.rolling_velocity_m_s,
                q.equivalent_radius_mm
            );
        }
    }
    crate::atomic_file::write(path, s)
}

/// One row per position and tooth pair.
fn write_point_table(path: &Path, t: &PointTca) -> Result<(), FlankError> {
    let mut s = String::from(
        "roll_deg,te_arcsec,pair,pinion_tooth,gear_tooth,system,active,separation_um,\
         pinion_face_mm,pinion_profile_mm,gear_face_mm,gear_profile_mm,\
         x_mm,y_mm,z_mm,nx,ny,nz,pinion_u,pinion_v,gear_u,gear_v,\
         semi_major_mm,semi_minor_mm,line_contact,major_x,major_y,major_z,\
         searched_semi_major_mm,searched_semi_minor_mm,\
         sliding_m_s,rolling_m_s,slide_x,slide_y,slide_z,arm_pinion_mm,arm_gear_mm,\
         point_residual_mm,tangency_residual,edge_lean\n",
    );
    let opt = |v: Option<f64>| v.map(|x| format!("{x:.6}")).unwrap_or_default();
    for p in &t.positions {
        for c in &p.pairs {
            let (pt, gt) = match c.teeth {
                Some([a, b]) => (a.to_string(), b.to_string()),
                None => (String::new(), String::new()),
            };
            let e = c.ellipse;
            let sr = c.searched_ellipse;
            let major = e.or(sr).map(|e| e.major_direction).unwrap_or([0.0; 3]);
            let _ = writeln!(
                s,
                "{:.6},{:.4},{},{},{},{},{},{:.4},{:.5},{:.5},{:.5},{:.5},{:.6},{:.6},{:.6},{:.8},{:.8},{:.8},{:.8},{:.8},{:.8},{:.8},{},{},{},{:.6},{:.6},{:.6},{},{},{:.5},{:.5},{:.6},{:.6},{:.6},{:.5},{:.5},{:.2e},{:.2e},{:.5}",
                p.roll_rad.to_degrees(),
                p.te_rad * ARCSEC_PER_RAD,
                c.offset,
                pt,
                gt,
                c.system.name(),
                c.active,
                1e3 * c.separation_mm,
                c.projection_mm[0][0],
                c.projection_mm[0][1],
                c.projection_mm[1][0],
                c.projection_mm[1][1],
                c.point[0],
                c.point[1],
                c.point[2],
                c.normal[0],
                c.normal[1],
                c.normal[2],
                c.pinion_uv[0],
                c.pinion_uv[1],
                c.gear_uv[0],
                c.gear_uv[1],
                opt(e.and_then(|e| e.semi_major_mm)),
                opt(e.map(|e| e.semi_minor_mm)),
                e.map(|e| e.line_contact.to_string()).unwrap_or_default(),
                major[0],
                major[1],
                major[2],
                opt(sr.and_then(|e| e.semi_major_mm)),
                opt(sr.map(|e| e.semi_minor_mm)),
                c.sliding_velocity,
                c.rolling_velocity,
                c.sliding_direction[0],
                c.sliding_direction[1],
                c.sliding_direction[2],
                c.moment_arm_mm[0],
                c.moment_arm_mm[1],
                c.residual[0],
                c.residual[1],
                c.edge_lean,
            );
        }
    }
    crate::atomic_file::write(path, s)
}

fn write_transitions(path: &Path, with: &PointTca, without: &PointTca) -> Result<(), FlankError> {
    let mut s = String::from("variant,roll_deg,from,to\n");
    for (name, t) in [("with_edges", with), ("without_edges", without)] {
        for tr in &t.transitions {
            let _ = writeln!(
                s,
                "{name},{:.6},{},{}",
                tr.roll_rad.to_degrees(),
                tr.from,
                tr.to
            );
        }
    }
    crate::atomic_file::write(path, s)
}
