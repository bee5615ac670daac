//! The two CSV files of `flank run`, written with the same columns for
//! every pair kind from one kind-neutral record per position
//! ([`PositionRecord`]): `mesh_cycle.csv`, one row per roll angle with a
//! column group per tooth pair, and `positions.csv`, one row per roll
//! angle and tooth pair. A user's script then reads a spur and a hypoid
//! run alike.
//!
//! Column order: the columns each file had before both kinds wrote it
//! keep their index (paper scripts read them by position); the others
//! follow at the end of the row. A quantity a pair kind does not define is
//! an empty cell (`None` here; docs/outputs.md lists them).

use std::fmt::Write as _;
use std::path::Path;

use crate::error::FlankError;
use crate::mesh_cycle::cycle::{MeshCycle, StepResult};
use crate::settings::SlaveBody;

/// One tooth pair at one position.
#[derive(Clone, Debug, PartialEq)]
pub struct PairRecord {
    /// Sector teeth of the pair (pinion tooth k, its mate).
    pub pinion_tooth: usize,
    pub gear_tooth: usize,
    /// Normal contact force (N) and its share of the position's total.
    pub force_n: f64,
    pub load_share: f64,
    /// Kinematic contact position on the line of action from the start of
    /// the path of contact (mm); cylindrical pairs only.
    pub position_mm: Option<f64>,
    /// Largest face-averaged contact pressure (MPa).
    pub max_pressure_mpa: f64,
    /// Closed slave nodes.
    pub closed_nodes: usize,
    /// Body carrying the slave nodes.
    pub slave: SlaveBody,
    /// Resultant tangential contact force (N; 0 frictionless).
    pub friction_n: f64,
    /// Whether closed slave nodes lie on the pinion's tip land; bevel and
    /// hypoid pairs only.
    pub pinion_tip_edge: Option<bool>,
    /// Smallest initial gap of the pair's candidates in the nominal
    /// placement (mm; `inf` without a candidate); bevel and hypoid pairs
    /// only.
    pub min_initial_gap_mm: Option<f64>,
}

/// One solved roll angle, whatever the pair kind.
#[derive(Clone, Debug, PartialEq)]
pub struct PositionRecord {
    pub roll_deg: f64,
    /// The roll in the scene's reference convention, if it gives one.
    pub reference_deg: Option<f64>,
    /// Per tooth pair k = 1 … n.
    pub pairs: Vec<PairRecord>,
    /// Loaded TE at the pinion (µrad, > 0 under a driving torque) and at
    /// the gear (arcsec), [`crate::load_sharing::te_arcsec_at_gear`].
    pub te_urad: f64,
    pub te_arcsec: f64,
    /// `te_urad` × r_b1 (µm on the line of action); cylindrical pairs only.
    pub te_um: Option<f64>,
    pub candidates: usize,
    /// Active-set iterations.
    pub iterations: usize,
    /// Delassus columns (solves with the factor); cylindrical pairs only.
    pub columns: Option<usize>,
    pub max_violation_mm: f64,
    pub complementarity: f64,
    /// Relative equilibrium residual of the pinion; cylindrical pairs only.
    pub equilibrium: Option<f64>,
    /// Σ moments of the pair forces about the pinion axis / T − 1; bevel
    /// and hypoid pairs only.
    pub moment_balance: Option<f64>,
    pub time_s: f64,
}

/// A cell of an optional figure: empty when the kind does not define it.
fn cell<T: std::fmt::Display>(v: Option<T>) -> String {
    v.map_or(String::new(), |v| v.to_string())
}

/// The same in exponent notation (the format of `positions.csv`).
fn cell_e<T: std::fmt::LowerExp>(v: Option<T>) -> String {
    v.map_or(String::new(), |v| format!("{v:e}"))
}

/// The header row of `mesh_cycle.csv` for `np` tooth pairs (no newline).
pub fn mesh_cycle_header(np: usize) -> String {
    let mut s = String::from("roll_deg,reference_deg");
    for p in 1..=np {
        let _ = write!(
            s,
            ",force_pair{p}_n,share_pair{p},position_pair{p}_mm,max_pressure_pair{p}_mpa,closed_nodes_pair{p}"
        );
    }
    s.push_str(",te_urad,te_um,candidates,iterations,columns,max_violation_mm,complementarity,equilibrium,time_s");
    for p in 1..=np {
        let _ = write!(s, ",slave_pair{p}");
    }
    for p in 1..=np {
        let _ = write!(s, ",friction_pair{p}_n");
    }
    // added when both kinds wrote the file
    s.push_str(",te_arcsec,moment_balance");
    for p in 1..=np {
        let _ = write!(s, ",pinion_tip_edge_pair{p}");
    }
    for p in 1..=np {
        let _ = write!(s, ",min_initial_gap_pair{p}_mm");
    }
    s
}

/// The header row of `positions.csv` (no newline).
pub const POSITIONS_HEADER: &str = "roll_deg,pair,pinion_tooth,gear_tooth,force_n,load_share,max_pressure_mpa,closed_nodes,pinion_tip_edge,min_initial_gap_mm,te_arcsec,\
reference_deg,position_mm,slave,friction_n,te_urad,te_um";

/// The error of a record whose tooth pairs are not the file's.
fn pair_count_error(r: &PositionRecord, np: usize) -> FlankError {
    FlankError::Model(format!(
        "roll angle {}°: {} tooth pair(s) in the position, {np} in the run",
        r.roll_deg,
        r.pairs.len()
    ))
}

/// The text of `mesh_cycle.csv`: header and one row per record (`np` tooth
/// pairs each).
pub fn mesh_cycle_csv(np: usize, records: &[PositionRecord]) -> Result<String, FlankError> {
    let mut s = mesh_cycle_header(np);
    s.push('\n');
    for r in records {
        if r.pairs.len() != np {
            return Err(pair_count_error(r, np));
        }
        let _ = write!(s, "{},{}", r.roll_deg, cell(r.reference_deg));
        for p in &r.pairs {
            let _ = write!(
                s,
                ",{},{},{},{},{}",
                p.force_n,
                p.load_share,
                cell(p.position_mm),
                p.max_pressure_mpa,
                p.closed_nodes
            );
        }
        let _ = write!(
            s,
            ",{},{},{},{},{},{:e},{:e},{},{}",
            r.te_urad,
            cell(r.te_um),
            r.candidates,
            r.iterations,
            cell(r.columns),
            r.max_violation_mm,
            r.complementarity,
            cell_e(r.equilibrium),
            r.time_s
        );
        for p in &r.pairs {
            let _ = write!(s, ",{}", p.slave.name());
        }
        for p in &r.pairs {
            let _ = write!(s, ",{}", p.friction_n);
        }
        let _ = write!(s, ",{},{}", r.te_arcsec, cell_e(r.moment_balance));
        for p in &r.pairs {
            let _ = write!(s, ",{}", cell(p.pinion_tip_edge));
        }
        for p in &r.pairs {
            let _ = write!(s, ",{}", cell(p.min_initial_gap_mm));
        }
        s.push('\n');
    }
    Ok(s)
}

/// The text of `positions.csv`: header and one row per record and tooth
/// pair.
pub fn positions_csv(records: &[PositionRecord]) -> String {
    let mut s = String::from(POSITIONS_HEADER);
    s.push('\n');
    for r in records {
        for (i, p) in r.pairs.iter().enumerate() {
            let _ = writeln!(
                s,
                "{},{},{},{},{:e},{:e},{:e},{},{},{},{:e},{},{},{},{:e},{:e},{}",
                r.roll_deg,
                i + 1,
                p.pinion_tooth,
                p.gear_tooth,
                p.force_n,
                p.load_share,
                p.max_pressure_mpa,
                p.closed_nodes,
                cell(p.pinion_tip_edge),
                cell_e(p.min_initial_gap_mm),
                r.te_arcsec,
                cell(r.reference_deg),
                cell_e(p.position_mm),
                p.slave.name(),
                p.friction_n,
                r.te_urad,
                cell_e(r.te_um)
            );
        }
    }
    s
}

/// Writes `mesh_cycle.csv` (or its partial form) to `path`.
pub fn write_mesh_cycle_csv(
    path: &Path,
    np: usize,
    records: &[PositionRecord],
) -> Result<(), FlankError> {
    crate::atomic_file::write(path, mesh_cycle_csv(np, records)?)
}

/// Writes `positions.csv` to `path`.
pub fn write_positions_csv(path: &Path, records: &[PositionRecord]) -> Result<(), FlankError> {
    crate::atomic_file::write(path, positions_csv(records))
}

/// The positions as the files of every pair kind hold them: what a kind
/// does not have is an empty cell (point contact: the position on the
/// line of action, TE along it, the reference roll; line contact: the
/// tip edge and the moment balance).
pub fn position_records(cycle: &MeshCycle, steps: &[StepResult]) -> Vec<PositionRecord> {
    steps
        .iter()
        .map(|st| PositionRecord {
            roll_deg: st.roll_deg,
            reference_deg: st.reference_deg,
            pairs: (0..st.pair_force_n.len())
                .map(|p| PairRecord {
                    pinion_tooth: cycle.pair.teeth[p].0,
                    gear_tooth: cycle.pair.teeth[p].1,
                    force_n: st.pair_force_n[p],
                    load_share: st.load_share[p],
                    position_mm: st.kinematic_position_mm.get(p).copied(),
                    max_pressure_mpa: st.max_pressure_mpa[p],
                    closed_nodes: st.patch[p].closed_nodes,
                    slave: st.slave[p],
                    friction_n: st.friction_force_n[p],
                    pinion_tip_edge: st.pinion_tip_edge.as_ref().map(|e| e[p]),
                    min_initial_gap_mm: st.min_initial_gap_mm.get(p).copied().flatten(),
                })
                .collect(),
            te_urad: st.te_urad,
            te_arcsec: st.te_arcsec,
            te_um: st.te_um,
            candidates: st.candidates,
            iterations: st.active_set_iterations,
            columns: Some(st.delassus_columns),
            max_violation_mm: st.max_violation_mm,
            complementarity: st.complementarity,
            equilibrium: Some(st.equilibrium),
            moment_balance: st.moment_balance,
            time_s: st.time_s,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A position as the cylindrical cycle fills it.
    fn spur_like() -> PositionRecord {
        PositionRecord {
            roll_deg: -6.0,
            reference_deg: Some(1.5),
            pairs: (1..=3)
                .map(|k| PairRecord {
                    pinion_tooth: k,
                    gear_tooth: 4 - k,
                    force_n: 100.0 * k as f64,
                    load_share: k as f64 / 6.0,
                    position_mm: Some(2.0 * k as f64),
                    max_pressure_mpa: 500.0,
                    closed_nodes: 7,
                    slave: SlaveBody::Gear,
                    friction_n: 0.0,
                    pinion_tip_edge: None,
                    min_initial_gap_mm: None,
                })
                .collect(),
            te_urad: 5000.0,
            te_arcsec: crate::load_sharing::te_arcsec_at_gear(5000.0, 18.0 / 39.0),
            te_um: Some(120.0),
            candidates: 56,
            iterations: 7,
            columns: Some(56),
            max_violation_mm: 1e-16,
            complementarity: 1e-13,
            equilibrium: Some(1e-16),
            moment_balance: None,
            time_s: 0.2,
        }
    }

    /// A position as the bevel cycle fills it.
    fn bevel_like() -> PositionRecord {
        let mut r = spur_like();
        r.reference_deg = None;
        r.te_um = None;
        r.columns = None;
        r.equilibrium = None;
        r.moment_balance = Some(1e-12);
        for p in &mut r.pairs {
            p.position_mm = None;
            p.slave = SlaveBody::Pinion;
            p.pinion_tip_edge = Some(false);
            p.min_initial_gap_mm = Some(f64::INFINITY);
        }
        r
    }

    fn header_and_widths(text: &str) -> (String, Vec<usize>) {
        let mut lines = text.lines();
        let head = lines.next().unwrap().to_string();
        (head, lines.map(|l| l.split(',').count()).collect())
    }

    /// Both kinds write the same header, every row as wide as it, and the
    /// columns of the spur-only `mesh_cycle.csv` and of the bevel-only
    /// `positions.csv` of before keep their place.
    #[test]
    fn both_kinds_write_the_same_columns() {
        let spur = [spur_like(), spur_like()];
        let bevel = [bevel_like(), bevel_like()];
        let (hs, ws) = header_and_widths(&mesh_cycle_csv(3, &spur).unwrap());
        let (hb, wb) = header_and_widths(&mesh_cycle_csv(3, &bevel).unwrap());
        assert_eq!(hs, hb);
        let n = hs.split(',').count();
        assert!(ws.iter().chain(&wb).all(|&w| w == n), "{n}: {ws:?} {wb:?}");
        assert!(hs.starts_with(
            "roll_deg,reference_deg,force_pair1_n,share_pair1,position_pair1_mm,max_pressure_pair1_mpa,closed_nodes_pair1,force_pair2_n,share_pair2,position_pair2_mm,max_pressure_pair2_mpa,closed_nodes_pair2,force_pair3_n,share_pair3,position_pair3_mm,max_pressure_pair3_mpa,closed_nodes_pair3,te_urad,te_um,candidates,iterations,columns,max_violation_mm,complementarity,equilibrium,time_s,slave_pair1,slave_pair2,slave_pair3,friction_pair1_n,friction_pair2_n,friction_pair3_n,"
        ), "{hs}");
        let (ps, ws) = header_and_widths(&positions_csv(&spur));
        let (pb, wb) = header_and_widths(&positions_csv(&bevel));
        assert_eq!(ps, pb);
        let n = ps.split(',').count();
        assert_eq!((ws.len(), wb.len()), (6, 6));
        assert!(ws.iter().chain(&wb).all(|&w| w == n), "{n}: {ws:?} {wb:?}");
        assert!(ps.starts_with(
            "roll_deg,pair,pinion_tooth,gear_tooth,force_n,load_share,max_pressure_mpa,closed_nodes,pinion_tip_edge,min_initial_gap_mm,te_arcsec,"
        ), "{ps}");
        // both TE forms on every row of both files
        for h in [&hs, &ps] {
            assert!(h.split(',').any(|c| c == "te_urad") && h.split(',').any(|c| c == "te_arcsec"));
        }
    }

    /// A quantity the kind does not define is an empty cell, not a number.
    #[test]
    fn undefined_quantities_are_empty_cells() {
        let text = mesh_cycle_csv(3, &[bevel_like()]).unwrap();
        let mut lines = text.lines();
        let head: Vec<&str> = lines.next().unwrap().split(',').collect();
        let row: Vec<&str> = lines.next().unwrap().split(',').collect();
        let at = |name: &str| row[head.iter().position(|h| *h == name).unwrap()];
        for name in [
            "reference_deg",
            "position_pair1_mm",
            "te_um",
            "columns",
            "equilibrium",
        ] {
            assert_eq!(at(name), "", "{name}");
        }
        assert_eq!(at("slave_pair2"), "pinion");
        assert_eq!(at("min_initial_gap_pair3_mm"), "inf");
        let text = mesh_cycle_csv(3, &[spur_like()]).unwrap();
        let row: Vec<&str> = text.lines().nth(1).unwrap().split(',').collect();
        let at = |name: &str| row[head.iter().position(|h| *h == name).unwrap()];
        for name in [
            "moment_balance",
            "pinion_tip_edge_pair1",
            "min_initial_gap_pair1_mm",
        ] {
            assert_eq!(at(name), "", "{name}");
        }
    }

    /// A record with the wrong number of tooth pairs is an error.
    #[test]
    fn a_record_of_other_pairs_is_refused() {
        let e = mesh_cycle_csv(2, &[spur_like()]).unwrap_err().to_string();
        assert!(
            e.contains("3 tooth pair(s) in the position, 2 in the run"),
            "{e}"
        );
    }
}
