//! The line-contact TCA of a spur or helical pair over one mesh cycle:
//! what `flank tca` reports for those pairs, beside the point-contact TCA
//! of bevel and hypoid pairs ([`super::point_contact`]).
//!
//! At each of `positions_per_pitch` roll angles over one pinion angular
//! pitch ([`Tca::roll_angles_for_cycle`]), the TCA of the module docs gives
//! the unloaded transmission error θ₀ = min wᵢ/rᵢ and every tooth pair's
//! contact line. Turning the pinion by θ₀ closes the nearest point; a pair
//! is **in contact at the approach δ** when some point of its lines is then
//! within δ of its mate: gᵢ = wᵢ − θ₀ rᵢ ≤ δ (the elastic approach of
//! seed 000, whose contact ellipse bounds the pattern at δ). The contact
//! ratio at δ is the mean number of such pairs over the cycle's positions
//! (for unmodified flanks, with tip-corner contact off, the kinematic
//! total contact ratio ε_γ = ε_α + ε_β to within the position spacing). Tip-corner lines
//! (the tip edge against the mating flank beyond the path's ends,
//! [`LineKind`]) are the edge contact of these pairs: the TCA is run with
//! and without them.

use crate::error::FlankError;
use crate::geometry::gear_pair::{LineContactPair, LineKind};
use crate::tca::Tca;

type Result<T> = std::result::Result<T, FlankError>;

/// One tooth pair at one position.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct PairAtPosition {
    pub pinion_tooth: usize,
    pub gear_tooth: usize,
    /// The pair's lines: `flank`, `pinion_tip_corner`, `gear_tip_corner`,
    /// joined by `+` when several.
    pub kinds: String,
    /// Length of the pair's sampled lines (mm).
    pub length_mm: f64,
    /// Smallest gap after the rigid rotation θ₀, min (wᵢ − θ₀ rᵢ) (mm).
    pub min_gap_mm: f64,
    /// The pair is within the approach δ of contact.
    pub in_contact: bool,
    /// The pair's closest point: pinion flank parameters (u, v), global
    /// position (mm), sliding and entraining velocities (m/s), equivalent
    /// radius across the line (mm; 0 at a corner).
    pub pinion_uv: [f64; 2],
    pub position_mm: [f64; 3],
    pub sliding_velocity_m_s: f64,
    pub rolling_velocity_m_s: f64,
    pub equivalent_radius_mm: f64,
    /// Pinion (u, v) of the pair's points within δ (the bearing pattern).
    #[serde(skip)]
    pub pattern_uv: Vec<[f64; 2]>,
}

/// One position of the cycle.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct CyclePosition {
    pub roll_rad: f64,
    /// θ₀ (rad, pinion), > 0: the flanks are apart by that rotation.
    pub unloaded_te_rad: f64,
    pub pairs: Vec<PairAtPosition>,
}

/// The cycle.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct LineTcaCycle {
    pub approach_mm: f64,
    /// Tip-corner contact included.
    pub corners: bool,
    pub pitch_rad: f64,
    pub positions: Vec<CyclePosition>,
    /// Mean number of pairs within δ of contact (module docs).
    pub contact_ratio: f64,
    /// The pair's transverse contact ratio ε_α (path of contact over the
    /// base pitch; helical pairs add the overlap ratio ε_β to it in the
    /// contact ratio at δ).
    pub transverse_contact_ratio: f64,
    /// Peak-to-peak of θ₀ over the cycle (rad, pinion).
    pub te_peak_to_peak_rad: f64,
    /// Positions at which a tip-corner line is within δ of contact.
    pub corner_contact_positions: usize,
}

/// The line TCA of `tca`'s pair over one mesh cycle at `positions_per_pitch`
/// positions, pairs in contact at the approach `approach_mm`. `tca`'s
/// settings say whether tip corners are included (`extension_mm` > 0).
pub fn line_tca_cycle(
    tca: &Tca,
    positions_per_pitch: usize,
    approach_mm: f64,
) -> Result<LineTcaCycle> {
    if positions_per_pitch < 2 {
        return Err(FlankError::Model(format!(
            "line TCA: {positions_per_pitch} positions per pitch; at least 2 are needed"
        )));
    }
    if !(approach_mm.is_finite() && approach_mm > 0.0) {
        return Err(FlankError::Model(format!(
            "line TCA: approach δ = {approach_mm} mm; a finite positive value is needed"
        )));
    }
    let pair: &dyn LineContactPair = tca.pair().as_ref();
    let mut positions = Vec::with_capacity(positions_per_pitch);
    for roll in tca.roll_angles_for_cycle(positions_per_pitch) {
        let p = tca.position(roll)?;
        let theta0 = p.unloaded_te_rad;
        let mut pairs: Vec<PairAtPosition> = Vec::new();
        for line in &p.lines {
            let kind = match line.kind {
                LineKind::Flank => "flank",
                LineKind::PinionTipCorner => "pinion_tip_corner",
                LineKind::GearTipCorner => "gear_tip_corner",
            };
            let at = match pairs
                .iter()
                .position(|q| q.pinion_tooth == line.pinion_tooth)
            {
                Some(i) => i,
                None => {
                    pairs.push(PairAtPosition {
                        pinion_tooth: line.pinion_tooth,
                        gear_tooth: line.gear_tooth,
                        kinds: String::new(),
                        length_mm: 0.0,
                        min_gap_mm: f64::INFINITY,
                        in_contact: false,
                        pinion_uv: [0.0; 2],
                        position_mm: [0.0; 3],
                        sliding_velocity_m_s: 0.0,
                        rolling_velocity_m_s: 0.0,
                        equivalent_radius_mm: 0.0,
                        pattern_uv: Vec::new(),
                    });
                    pairs.len() - 1
                }
            };
            let q = &mut pairs[at];
            if !q.kinds.is_empty() {
                q.kinds.push('+');
            }
            q.kinds.push_str(kind);
            q.length_mm += line.length_mm;
            for c in &line.points {
                let gap = c.separation_mm - theta0 * c.moment_arm_mm;
                if gap <= approach_mm {
                    q.pattern_uv.push(c.pinion_uv);
                }
                if gap < q.min_gap_mm {
                    q.min_gap_mm = gap;
                    q.pinion_uv = c.pinion_uv;
                    q.position_mm = c.position;
                    q.sliding_velocity_m_s = c.sliding_velocity;
                    q.rolling_velocity_m_s = c.rolling_velocity;
                    q.equivalent_radius_mm = if c.equivalent_radius_mm.is_finite() {
                        c.equivalent_radius_mm
                    } else {
                        0.0
                    };
                }
            }
        }
        for q in &mut pairs {
            q.in_contact = q.min_gap_mm <= approach_mm;
        }
        pairs.sort_by_key(|q| q.pinion_tooth);
        positions.push(CyclePosition {
            roll_rad: roll,
            unloaded_te_rad: theta0,
            pairs,
        });
    }
    let n = positions.len() as f64;
    let contact_ratio = positions
        .iter()
        .map(|p| p.pairs.iter().filter(|q| q.in_contact).count() as f64)
        .sum::<f64>()
        / n;
    let te = positions.iter().map(|p| p.unloaded_te_rad);
    let te_peak_to_peak_rad =
        te.clone().fold(f64::NEG_INFINITY, f64::max) - te.fold(f64::INFINITY, f64::min);
    let corner_contact_positions = positions
        .iter()
        .filter(|p| {
            p.pairs
                .iter()
                .any(|q| q.in_contact && q.kinds.contains("corner"))
        })
        .count();
    Ok(LineTcaCycle {
        approach_mm,
        corners: tca.settings().extension_mm > 0.0,
        pitch_rad: pair.pinion().angular_pitch(),
        positions,
        contact_ratio,
        transverse_contact_ratio: tca.kinematic_contact_ratio(),
        te_peak_to_peak_rad,
        corner_contact_positions,
    })
}
