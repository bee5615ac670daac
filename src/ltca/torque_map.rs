//! The map of the loaded TE over torque (the "Harris map": TE
//! peak-to-peak and first-harmonic amplitude against torque, after Harris
//! 1958, "Dynamic loads on the teeth of spur gears", Proc. IMechE 172),
//! for every pair kind through the one LTCA cycle ([`LtcaCycle`]): the
//! same prepared bodies and candidates, solved at each torque over one
//! mesh pitch of equally spaced positions, with the harmonics
//! ([`crate::ltca::harmonics`]) and the mesh stiffness
//! ([`crate::ltca::mesh_stiffness`]) of each torque.
//!
//! Positions: a spur/helical pair [`MAP_POSITIONS_PER_PITCH`] equal steps
//! over one pitch centred on the middle pair's kinematic engagement, plus
//! the position one pitch after the first (the closure, how periodic the
//! sector's TE is); a bevel/hypoid pair its point TCA's grid over one
//! pitch (`positions` per cycle, no closure: the grid holds one pitch).
//!
//! Files: `ltca_torque_map.csv` (one row per torque),
//! `ltca_torque_map_positions.csv` (per torque and position: TE,
//! deflection, force, mesh stiffness, for dynamic models) and the plot
//! `ltca_torque_map.{svg,png}`.

use std::path::Path;
use std::time::Instant;

use serde::Serialize;

use crate::error::FlankError;
use crate::ltca::cycle::LtcaCycle;
use crate::ltca::harmonics::{te_harmonics, TeHarmonics, MESH_ORDERS};
use crate::ltca::mesh_stiffness::{
    mesh_stiffness, stiffness_row, MeshStiffness, STIFFNESS_COLUMNS,
};
use crate::ltca::model::PositionResult;
use crate::summary::{peak_to_peak, Measured};

/// Positions per pitch of a spur/helical pair's map (mesh order 5 well
/// below the Nyquist order 12).
pub const MAP_POSITIONS_PER_PITCH: usize = 24;

/// Most torques of one map.
pub const MAX_TORQUES: usize = 50;

/// The map over torque.
#[derive(Clone, Debug, Serialize)]
pub struct TorqueMap {
    /// One pinion pitch (deg) and the positions solved at every torque
    /// (deg; the spur/helical closure position last).
    pub pitch_deg: f64,
    pub roll_deg: Vec<f64>,
    /// The radius that turns µrad into µm (mm): r_b1 (spur/helical, the
    /// line of action), the middle pair's moment arm at roll 0 (bevel).
    pub te_radius_mm: f64,
    pub torques: Vec<TorqueMapPoint>,
    pub files: Vec<String>,
    /// Wall time of the map (s).
    pub time_s: f64,
}

/// One torque of the map.
#[derive(Clone, Debug, Serialize)]
pub struct TorqueMapPoint {
    pub torque_nm: f64,
    /// Loaded TE over the pitch sample: peak-to-peak at the pinion (µrad),
    /// times the TE radius (µm), at the gear (arcsec); its mean (µrad).
    pub te_peak_to_peak_urad: f64,
    pub te_peak_to_peak_um: f64,
    pub te_peak_to_peak_arcsec: f64,
    pub te_mean_urad: f64,
    pub max_pressure_mpa: f64,
    pub max_kkt: f64,
    pub harmonics: Measured<TeHarmonics>,
    pub mesh_stiffness: Measured<MeshStiffness>,
}

/// The roll angles of the map of `cycle` (module docs).
pub fn map_rolls(cycle: &LtcaCycle) -> Result<Vec<f64>, FlankError> {
    if let Ok(point) = cycle.point() {
        return Ok(point.cycle_rolls_deg());
    }
    let pair = cycle.line_pair()?;
    let (a, e) = pair.engagement(cycle.pair.middle());
    let pitch = cycle.pair.pinion().angular_pitch().to_degrees();
    let start = 0.5 * (a + e).to_degrees() - 0.5 * pitch;
    let n = MAP_POSITIONS_PER_PITCH;
    Ok((0..=n)
        .map(|i| start + pitch * i as f64 / n as f64)
        .collect())
}

/// Checks a list of torques (N·m): 1 … [`MAX_TORQUES`] values, each
/// finite and > 0; `what` names where they come from.
pub fn check_torques(torques_nm: &[f64], what: &str) -> Result<(), String> {
    if torques_nm.is_empty() || torques_nm.len() > MAX_TORQUES {
        return Err(format!(
            "{what}: 1 … {MAX_TORQUES} torques are needed, got {}",
            torques_nm.len()
        ));
    }
    if let Some(t) = torques_nm.iter().find(|t| !(t.is_finite() && **t > 0.0)) {
        return Err(format!(
            "{what}: every torque must be > 0 N·m and finite, got {t}"
        ));
    }
    Ok(())
}

/// The map of `cycle` at `torques_nm` (N·m) over `rolls` ([`map_rolls`]),
/// its files written into `out`; `face_width_mm` for the stiffness per
/// unit face width (`None`: bevel/hypoid).
pub fn torque_map(
    cycle: &LtcaCycle,
    torques_nm: &[f64],
    rolls: &[f64],
    face_width_mm: Option<f64>,
    out: &Path,
) -> Result<TorqueMap, FlankError> {
    check_torques(torques_nm, "torques_nm").map_err(FlankError::Model)?;
    let t0 = Instant::now();
    let pitch = cycle.pair.pinion().angular_pitch().to_degrees();
    let ratio = cycle.pair.ratio();
    let r_te = cycle.bodies.te_radius_mm;
    let r_n = cycle.bodies.nominal_moment_arm_mm;
    let mut points = Vec::with_capacity(torques_nm.len());
    let mut rows = String::from("torque_nm,");
    rows.push_str(STIFFNESS_COLUMNS);
    rows.push('\n');
    for &t in torques_nm {
        let at = cycle.with_torque(t * 1e3);
        let solved = at.solve_cycle_gaps(rolls)?;
        let gaps: Vec<f64> = rolls
            .iter()
            .zip(&solved)
            .filter(|(_, r)| r.is_none())
            .map(|(&x, _)| x)
            .collect();
        let results: Vec<PositionResult> = solved.into_iter().flatten().collect();
        for r in &results {
            rows.push_str(&format!(
                "{t},{}\n",
                stiffness_row(r, rolls[0], pitch, face_width_mm)
            ));
        }
        let rs: Vec<f64> = results.iter().map(|r| r.roll_deg).collect();
        let te: Vec<f64> = results.iter().map(|r| r.te_urad).collect();
        let harmonics = if gaps.is_empty() {
            te_harmonics(&rs, &te, pitch, r_te, ratio)
        } else {
            Err(format!(
                "no tooth pair of the sector is in contact at {gaps:?}°: the pitch is not sampled whole"
            ))
        };
        // the sample without its closing position
        let n = harmonics.as_ref().map_or(results.len(), |h| h.positions);
        let sample = &results[..n.min(results.len())];
        let stiffness = match &harmonics {
            Ok(_) => mesh_stiffness(sample, face_width_mm, r_n),
            Err(e) => Err(e.clone()),
        };
        let te_s: Vec<f64> = sample.iter().map(|r| r.te_urad).collect();
        let pp = peak_to_peak(te_s.iter().copied());
        points.push(TorqueMapPoint {
            torque_nm: t,
            te_peak_to_peak_urad: pp,
            te_peak_to_peak_um: pp * r_te * 1e-3,
            te_peak_to_peak_arcsec: crate::load_sharing::te_arcsec_at_gear(pp, ratio).abs(),
            te_mean_urad: te_s.iter().sum::<f64>() / te_s.len().max(1) as f64,
            max_pressure_mpa: sample
                .iter()
                .map(|r| r.max_pressure_mpa)
                .fold(0.0, f64::max),
            max_kkt: sample.iter().map(|r| r.kkt_max).fold(0.0, f64::max),
            harmonics: Measured::from_result(harmonics),
            mesh_stiffness: Measured::from_result(stiffness),
        });
    }
    crate::atomic_file::write(&out.join("ltca_torque_map_positions.csv"), rows)?;
    write_map_csv(&out.join("ltca_torque_map.csv"), &points)?;
    let mut files = vec![
        "ltca_torque_map.csv".to_string(),
        "ltca_torque_map_positions.csv".to_string(),
    ];
    files.extend(plot_map(out, &points, cycle.line_pair().is_ok(), r_te)?);
    Ok(TorqueMap {
        pitch_deg: pitch,
        roll_deg: rolls.to_vec(),
        te_radius_mm: r_te,
        torques: points,
        files,
        time_s: t0.elapsed().as_secs_f64(),
    })
}

/// `ltca_torque_map.csv`: per torque the TE peak-to-peak (µrad, µm,
/// arcsec), the amplitudes of mesh orders 1 … 5 (µrad, µm, arcsec), the
/// mean mesh stiffness (N/µm, N/(mm·µm)) and its max − min; cells not
/// measured are empty (the summary says why).
fn write_map_csv(path: &Path, points: &[TorqueMapPoint]) -> Result<(), FlankError> {
    use std::fmt::Write;
    let mut s = String::from("torque_nm,te_pp_urad,te_pp_um,te_pp_arcsec,te_mean_urad");
    for unit in ["urad", "um", "arcsec"] {
        for k in 1..=MESH_ORDERS {
            let _ = write!(s, ",te_order{k}_{unit}");
        }
    }
    s.push_str(",closure_urad,mesh_stiffness_mean_n_per_um,mesh_stiffness_mean_n_per_mm_um,mesh_stiffness_pp_n_per_um,max_pressure_mpa\n");
    let cell = |x: Option<f64>| x.map_or(String::new(), |x| format!("{x:e}"));
    for p in points {
        let _ = write!(
            s,
            "{},{:e},{:e},{:e},{:e}",
            p.torque_nm,
            p.te_peak_to_peak_urad,
            p.te_peak_to_peak_um,
            p.te_peak_to_peak_arcsec,
            p.te_mean_urad
        );
        let h = p.harmonics.figures();
        for unit in 0..3 {
            for k in 0..MESH_ORDERS {
                let v = h.map(|h| {
                    let x = &h.harmonics[k];
                    [x.amplitude_urad, x.amplitude_um, x.amplitude_arcsec][unit]
                });
                let _ = write!(s, ",{}", cell(v));
            }
        }
        let k = p.mesh_stiffness.figures();
        let _ = writeln!(
            s,
            ",{},{},{},{},{:e}",
            cell(h.and_then(|h| h.closure_urad)),
            cell(k.map(|k| k.mean_n_per_um)),
            cell(k.and_then(|k| k.mean_n_per_mm_um)),
            cell(k.map(|k| k.peak_to_peak_n_per_um)),
            p.max_pressure_mpa
        );
    }
    crate::atomic_file::write(path, s)
}

/// `ltca_torque_map.{svg,png}`: TE peak-to-peak and the first mesh order's
/// amplitude against torque, in µm along the line of action for a
/// cylindrical pair, in µrad at the pinion for a bevel pair.
fn plot_map(
    out: &Path,
    points: &[TorqueMapPoint],
    line_of_action: bool,
    te_radius_mm: f64,
) -> Result<Vec<String>, FlankError> {
    let scale = |urad: f64| {
        if line_of_action {
            urad * te_radius_mm * 1e-3
        } else {
            urad
        }
    };
    let pp: Vec<(f64, f64)> = points
        .iter()
        .map(|p| (p.torque_nm, scale(p.te_peak_to_peak_urad)))
        .collect();
    let first: Vec<(f64, f64)> = points
        .iter()
        .filter_map(|p| {
            p.harmonics
                .figures()
                .map(|h| (p.torque_nm, scale(h.harmonics[0].amplitude_urad)))
        })
        .collect();
    let unit = if line_of_action {
        "loaded TE along the line of action (µm)"
    } else {
        "loaded TE at the pinion (µrad)"
    };
    crate::report::cycle_plot::plot_series(
        out,
        "ltca_torque_map",
        "Loaded TE over one mesh pitch against torque",
        "pinion torque (N·m)",
        unit,
        &[
            ("peak-to-peak".to_string(), pp),
            ("first mesh order amplitude".to_string(), first),
        ],
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Torques outside the accepted list are refused with the key; a map
    /// row whose harmonics and stiffness were not measured leaves its
    /// cells empty (never "NaN"), a measured one fills all five orders in
    /// the three units.
    #[test]
    fn torques_checked_and_unmeasured_cells_left_empty() {
        assert!(check_torques(&[], "torques_nm")
            .unwrap_err()
            .contains("torques_nm"));
        assert!(check_torques(&[100.0, f64::NAN], "--torques")
            .unwrap_err()
            .contains("> 0 N·m"));
        assert!(check_torques(&[1.0; 51], "x").is_err());
        assert!(check_torques(&[50.0, 312.0], "x").is_ok());
        let pitch = 360.0 / 13.0;
        let roll: Vec<f64> = (0..24).map(|i| pitch * i as f64 / 24.0).collect();
        let te: Vec<f64> = roll
            .iter()
            .map(|r| 100.0 + 3.0 * (2.0 * std::f64::consts::PI * r / pitch).cos())
            .collect();
        let h = te_harmonics(&roll, &te, pitch, 22.93, 13.0 / 35.0).unwrap();
        let point = |harmonics| TorqueMapPoint {
            torque_nm: 100.0,
            te_peak_to_peak_urad: 6.0,
            te_peak_to_peak_um: 6.0 * 22.93e-3,
            te_peak_to_peak_arcsec: 1.0,
            te_mean_urad: 100.0,
            max_pressure_mpa: 900.0,
            max_kkt: 1e-12,
            harmonics,
            mesh_stiffness: Measured::NotMeasured {
                not_measured: "a reason".into(),
            },
        };
        let dir = std::env::temp_dir().join(format!("flank_map_csv_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("map.csv");
        write_map_csv(
            &path,
            &[
                point(Measured::Figures(h)),
                point(Measured::NotMeasured {
                    not_measured: "gaps".into(),
                }),
            ],
        )
        .unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        let _ = std::fs::remove_dir_all(&dir);
        assert!(!text.to_lowercase().contains("nan"), "{text}");
        let rows: Vec<Vec<&str>> = text.lines().map(|l| l.split(',').collect()).collect();
        let col = |name: &str| rows[0].iter().position(|c| *c == name).unwrap();
        assert_eq!(rows[0].len(), rows[1].len());
        let a1: f64 = rows[1][col("te_order1_urad")].parse().unwrap();
        assert!((a1 - 3.0).abs() < 1e-12, "{a1}");
        assert!(rows[1][col("te_order5_arcsec")].parse::<f64>().is_ok());
        assert_eq!(rows[2][col("te_order1_urad")], "");
        assert_eq!(rows[2][col("mesh_stiffness_mean_n_per_um")], "");
    }
}
