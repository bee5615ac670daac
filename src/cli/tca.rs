//! `flank tca SCENE --out DIR`: unloaded tooth contact analysis over the
//! mesh cycle.
//!
//! * Spiral bevel and hypoid scenes: the point-contact TCA
//!   ([`flank::tca::point_contact`]) with and without edge contact; writes
//!   `tca_with_edges.csv`, `tca_without_edges.csv` (one row per position
//!   and tooth pair), `transitions.csv`, `summary.json` (under
//!   `with_edges` and `without_edges`: `contact_ratio`,
//!   `te_peak_to_peak_arcsec`, …) and the plots of `tca_plot`.
//! * Spur and helical scenes: the line-contact TCA over the cycle
//!   ([`flank::tca::line_cycle`]) with and without tip-corner contact (the
//!   edge contact of these pairs); writes `tca_with_edges.csv`,
//!   `tca_without_edges.csv` (one row per position and tooth pair: θ₀, the
//!   pair's lines, its smallest gap and closest point), `summary.json` (the
//!   same keys as for bevel pairs, plus the transverse contact ratio and
//!   the TE in µrad) and the plots `transmission_error` and
//!   `bearing_pattern_pinion`. `--search-directions` does not apply (line
//!   contact has no ellipse).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use anyhow::{bail, Context, Result};
use flank::geometry::gear_pair::{Misalignment, PairPlacement};
use flank::scene::Gears;
use flank::tca::line_cycle::{line_tca_cycle, LineTcaCycle};
use flank::tca::point_contact::{
    point_tca, point_tca_shared, EllipseMemo, PointTca, PointTcaSettings, ARCSEC_PER_RAD,
};
use flank::tca::{Tca, TcaSettings};

#[derive(clap::Args)]
pub struct Args {
    /// Gear-pair scene (TOML).
    scene: PathBuf,
    /// Output directory.
    #[arg(long)]
    out: PathBuf,
    /// Elastic approach δ of the contact ellipse (mm): 0.00635 finished
    /// teeth, 0.00381 lapped (seed 000).
    #[arg(long, default_value_t = 0.00635)]
    approach_mm: f64,
    /// Positions per angular pitch.
    #[arg(long, default_value_t = 30)]
    positions_per_pitch: usize,
    /// Planes of the numerical contact-ellipse search over 180° (0: off).
    #[arg(long, default_value_t = 18)]
    search_directions: usize,
    /// Offset error ΔE (mm, > 0: the axes apart).
    #[arg(long, default_value_t = 0.0)]
    offset_error_mm: f64,
    /// Pinion axial displacement ΔP (mm, along its own +z, toward its heel).
    #[arg(long, default_value_t = 0.0)]
    pinion_axial_mm: f64,
    /// Gear axial displacement ΔG (mm, along its own +z).
    #[arg(long, default_value_t = 0.0)]
    gear_axial_mm: f64,
    /// Shaft-angle error ΔΣ (degrees).
    #[arg(long, default_value_t = 0.0)]
    shaft_angle_error_deg: f64,
    /// V–H style sweep: ΔE and ΔP each over ±MM in 5 steps (25 TCA runs
    /// with edges, curvature ellipses, added to the misalignment above):
    /// writes vh_sweep.csv (bearing centre on the gear: the middle pair's
    /// contact where its TE curve peaks; TE peak-to-peak, contact ratio)
    /// and the V–H chart vh_chart.svg/png.
    #[arg(long)]
    sweep_mm: Option<f64>,
}

pub fn run(args: Args) -> Result<()> {
    let scene = flank::scene::read_scene(&args.scene)?;
    if !(args.approach_mm.is_finite() && args.approach_mm > 0.0) {
        bail!(
            "--approach-mm {}: a finite positive elastic approach δ is needed (seed 000: 0.00635 mm finished, 0.00381 mm lapped)",
            args.approach_mm
        );
    }
    if !(4..=10_000).contains(&args.positions_per_pitch) {
        bail!(
            "--positions-per-pitch {}: between 4 and 10000 positions per pitch are needed",
            args.positions_per_pitch
        );
    }
    if args.search_directions != 0 && !(4..=3600).contains(&args.search_directions) {
        bail!(
            "--search-directions {}: 0 (no search) or 4 to 3600 planes are needed",
            args.search_directions
        );
    }
    let mis = Misalignment {
        offset_error_mm: args.offset_error_mm,
        pinion_axial_mm: args.pinion_axial_mm,
        gear_axial_mm: args.gear_axial_mm,
        shaft_angle_error_rad: args.shaft_angle_error_deg.to_radians(),
        out_of_plane_tilt_rad: 0.0,
    };
    for (v, name) in [
        (args.offset_error_mm, "--offset-error-mm"),
        (args.pinion_axial_mm, "--pinion-axial-mm"),
        (args.gear_axial_mm, "--gear-axial-mm"),
        (args.shaft_angle_error_deg, "--shaft-angle-error-deg"),
    ] {
        if !v.is_finite() {
            bail!("{name} {v}: a finite value is needed");
        }
    }
    let s = &scene;
    match &scene.gears {
        Gears::Bevel(bevel) => {
            let pair: Arc<dyn PairPlacement> = Arc::new(bevel.pair.with_misalignment(mis));
            let settings = PointTcaSettings {
                positions_per_pitch: args.positions_per_pitch,
                approach_mm: args.approach_mm,
                edges: true,
                search_directions: args.search_directions,
                max_pitches: 3.0,
                speed_rpm: s.load.speed_rpm,
                crossing_exhaustive: false,
            };
            let t0 = std::time::Instant::now();
            // the flank contacts of both runs are the same points: their
            // ellipse searches are done once
            let memo = EllipseMemo::default();
            if settings.search_directions > 0 {
                eprintln!(
                    "TCA with edge contact, numerical ellipse search in {} planes at every contact (--search-directions 0 skips it; minutes on a conjugate pinion without ease-off, whose contact is a line) …",
                    settings.search_directions
                );
            }
            let with = point_tca_shared(pair.as_ref(), &settings, &memo)?;
            if settings.search_directions > 0 {
                eprintln!(
                    "  {} contacts searched in {:.1} s; TCA without edge contact …",
                    memo.len(),
                    t0.elapsed().as_secs_f64()
                );
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
            std::fs::create_dir_all(&args.out)
                .with_context(|| format!("cannot create {}", args.out.display()))?;
            write_table(&args.out.join("tca_with_edges.csv"), &with)?;
            write_table(&args.out.join("tca_without_edges.csv"), &without)?;
            write_transitions(&args.out.join("transitions.csv"), &with, &without)?;
            let summary = serde_json::json!({
                "scene": args.scene.display().to_string(),
                "pair": pair.describe(),
                "approach_mm": args.approach_mm,
                "misalignment": mis,
                "with_edges": variant_summary(&with),
                "without_edges": variant_summary(&without),
                "run_time_s": seconds,
            });
            flank::atomic_file::write(
                &args.out.join("summary.json"),
                serde_json::to_string_pretty(&summary)?,
            )?;
            flank::report::tca_plot::plot_point_tca(&args.out, pair.as_ref(), &with, &without)?;
            if let Some(r) = args.sweep_mm {
                if !(r.is_finite() && r > 0.0) {
                    bail!("--sweep-mm {r}: a finite positive half-range is needed");
                }
                sweep(&args.out, &bevel.pair, mis, r, &settings)?;
            }
            println!("{}", serde_json::to_string_pretty(&summary)?);
            for (variant, t) in [("with edges", &with), ("without edges", &without)] {
                for w in t.iteration_limits.warnings() {
                    eprintln!("warning: TCA {variant}: {w}; the trace ends there (summary.json: iteration_limits)");
                }
            }
            if let Some(c) = with.crossing {
                eprintln!(
                    "warning: the flanks cross: at roll {:.3}° a point of the pinion's active flank (u, v) = ({:.3}, {:.3}) mm lies {:.4} mm inside the gear flank with the gear where the TE envelope puts it (pair offset {}); the pairs touch elsewhere first, and this TCA's TE and bearing are not the pair's (summary.json: crossing)",
                    c.roll_rad.to_degrees(),
                    c.pinion_uv[0],
                    c.pinion_uv[1],
                    c.depth_mm,
                    c.pair_offset
                );
            }
            Ok(())
        }
        Gears::Cylindrical(cyl) => {
            if args.sweep_mm.is_some() {
                bail!("--sweep-mm: the V–H sweep is for bevel and hypoid scenes; a spur or helical pair's misalignment is swept by a campaign (docs/campaigns.md)");
            }
            // a sector with every pair that can be in mesh and one more on
            // each side: ε_γ = ε_α + ε_β (ISO 21771), b the common face
            let g = &cyl.pair;
            let face = g.pinion.face_width.min(g.gear.face_width);
            let eps_beta = face * g.pinion.helix_angle.sin().abs()
                / (std::f64::consts::PI * g.pinion.normal_module);
            let eps_alpha = flank::geometry::gear_pair::GearPair::kinematic_contact_ratio(
                &s.cylindrical_pair()?,
            );
            let mut teeth =
                (s.mesh.teeth_in_sector as usize).max((eps_alpha + eps_beta).ceil() as usize + 2);
            if teeth.is_multiple_of(2) {
                teeth += 1;
            }
            let pair: Arc<dyn flank::geometry::gear_pair::GearPair> = Arc::new(
                flank::geometry::cylindrical::CylindricalPair::new(
                    g,
                    cyl.flank_modifications()?,
                    teeth,
                )?
                .with_misalignment(mis)?,
            );
            let t0 = std::time::Instant::now();
            let variant = |extension_mm: f64| -> Result<LineTcaCycle> {
                let tca = Tca::new(
                    Arc::clone(&pair),
                    s.load.speed_rpm,
                    TcaSettings {
                        extension_mm,
                        ..TcaSettings::default()
                    },
                )?;
                Ok(line_tca_cycle(
                    &tca,
                    args.positions_per_pitch,
                    args.approach_mm,
                )?)
            };
            let with = variant(TcaSettings::default().extension_mm)?;
            let without = variant(0.0)?;
            let seconds = t0.elapsed().as_secs_f64();
            std::fs::create_dir_all(&args.out)
                .with_context(|| format!("cannot create {}", args.out.display()))?;
            let ratio = pair.ratio();
            write_line_table(&args.out.join("tca_with_edges.csv"), &with, ratio)?;
            write_line_table(&args.out.join("tca_without_edges.csv"), &without, ratio)?;
            let plots = flank::report::line_tca_plot::plot_line_tca(&args.out, &with, &without)?;
            let summary = serde_json::json!({
                "scene": args.scene.display().to_string(),
                "pair": pair.describe(),
                "approach_mm": args.approach_mm,
                "misalignment": mis,
                "positions_per_pitch": args.positions_per_pitch,
                "sector_teeth": teeth,
                "with_edges": line_variant_summary(&with, ratio),
                "without_edges": line_variant_summary(&without, ratio),
                "plots": plots,
                "run_time_s": seconds,
            });
            flank::atomic_file::write(
                &args.out.join("summary.json"),
                serde_json::to_string_pretty(&summary)?,
            )?;
            println!("{}", serde_json::to_string_pretty(&summary)?);
            Ok(())
        }
    }
}

/// One variant of the line TCA in summary.json: the keys of the bevel
/// variants (`contact_ratio`, `te_peak_to_peak_arcsec` at the gear) and
/// the line TCA's own.
fn line_variant_summary(c: &LineTcaCycle, ratio: f64) -> serde_json::Value {
    serde_json::json!({
        "contact_ratio": c.contact_ratio,
        "transverse_contact_ratio": c.transverse_contact_ratio,
        "te_peak_to_peak_arcsec": c.te_peak_to_peak_rad * ratio * ARCSEC_PER_RAD,
        "te_peak_to_peak_urad": c.te_peak_to_peak_rad * 1e6,
        "positions": c.positions.len(),
        "tip_corners": c.corners,
        "corner_contact_positions": c.corner_contact_positions,
    })
}

/// One row per position and tooth pair of a line TCA cycle.
fn write_line_table(path: &Path, c: &LineTcaCycle, ratio: f64) -> Result<()> {
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
    flank::atomic_file::write(path, s).with_context(|| format!("cannot write {}", path.display()))
}

/// The V–H sweep (module docs of `--sweep-mm`).
fn sweep(
    out: &Path,
    pair: &flank::geometry::bevel::pair::BevelPair,
    base: Misalignment,
    half_range: f64,
    settings: &PointTcaSettings,
) -> Result<()> {
    let mut s = String::from(
        "offset_error_mm,pinion_axial_mm,gear_face_mm,gear_profile_mm,te_peak_to_peak_arcsec,contact_ratio,edge_transitions\n",
    );
    let mut chart = Vec::new();
    let st = PointTcaSettings {
        search_directions: 0,
        ..settings.clone()
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
            let row = match point_tca(&pair.with_misalignment(m), &st) {
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
                    chart.push(flank::report::vh_plot::VhPoint {
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
                    chart.push(flank::report::vh_plot::VhPoint {
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
    let path = out.join("vh_sweep.csv");
    flank::atomic_file::write(&path, s)
        .with_context(|| format!("cannot write {}", path.display()))?;
    flank::report::vh_plot::plot_vh_sweep(out, &chart)?;
    Ok(())
}

fn variant_summary(t: &PointTca) -> serde_json::Value {
    serde_json::json!({
        "contact_ratio": t.contact_ratio,
        "flank_span_ratio": t.flank_span_ratio,
        "te_peak_to_peak_arcsec": t.te_peak_to_peak_rad * ARCSEC_PER_RAD,
        "positions": t.positions.len(),
        "transitions": t.transitions,
        "hit_trace_bound": t.hit_trace_bound,
        "max_point_residual_mm": t.max_residual[0],
        "max_tangency_residual": t.max_residual[1],
        "newton_steps": t.newton_steps,
        "branch_jumps": t.branch_jumps,
        "iteration_limits": t.iteration_limits.to_json(),
        "crossing": t.crossing.map(|c| serde_json::json!({
            "roll_deg": c.roll_rad.to_degrees(),
            "pair_offset": c.pair_offset,
            "depth_mm": c.depth_mm,
            "pinion_uv_mm": c.pinion_uv,
            "gear_uv_mm": c.gear_uv,
        })),
        "crossing_scan": t.crossing_scan,
    })
}

/// One row per position and tooth pair.
fn write_table(path: &Path, t: &PointTca) -> Result<()> {
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
            writeln!(
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
            )?;
        }
    }
    flank::atomic_file::write(path, s)
        .with_context(|| format!("cannot write {}", path.display()))?;
    Ok(())
}

fn write_transitions(path: &Path, with: &PointTca, without: &PointTca) -> Result<()> {
    let mut s = String::from("variant,roll_deg,from,to\n");
    for (name, t) in [("with_edges", with), ("without_edges", without)] {
        for tr in &t.transitions {
            writeln!(
                s,
                "{name},{:.6},{},{}",
                tr.roll_rad.to_degrees(),
                tr.from,
                tr.to
            )?;
        }
    }
    flank::atomic_file::write(path, s)
        .with_context(|| format!("cannot write {}", path.display()))?;
    Ok(())
}
