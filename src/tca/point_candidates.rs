//! The candidates of a point-contact pair (bevel, hypoid) for the LTCA:
//! seeds 001 and 003 put M candidate points on the major axis of each
//! tooth pair's contact ellipse; flank does the same with its own pieces:
//!
//! * the point TCA of the pair ([`crate::tca::point_contact`]: flank
//!   contacts of every tooth pair over the trace, each with its curvature
//!   ellipse at the approach δ), traced once on a grid of `positions` per
//!   pitch; a requested roll angle is taken at the nearest grid position;
//! * per position and tooth pair, the major axis as a contact line of K
//!   points ([`crate::tca::major_axis::major_axis_line`]: separations by
//!   closest point between the exact surfaces, moment arms, radii across
//!   the axis), spanning the axis out to the separation `span_approach_mm`;
//! * with edges on, K points along the edge of a pair in edge contact
//!   ([`crate::tca::edge_lines`], seed 000).

use std::sync::Arc;
use std::time::Instant;

use rayon::prelude::*;

use crate::error::FlankError;
use crate::geometry::bevel::pair::BevelPair;
use crate::geometry::gear_pair::GearPair;
use crate::geometry::tangency::ContactSystem;
use crate::tca::candidates::{CandidatePosition, ContactCandidates};
use crate::tca::edge_lines::{edge_line, EdgeLine};
use crate::tca::major_axis::major_axis_line;
use crate::tca::point_contact::{point_tca, PointTca, PointTcaPosition, PointTcaSettings};
use crate::tca::TcaPosition;

/// Default span of the candidate axis: where the unloaded separation
/// reaches 40 µm, beyond the approach of a loaded hypoid contact at its
/// rated torque (seed 003's FE: ≈ 20–30 µm); a loaded end point is
/// reported by the LTCA run.
pub const DEFAULT_SPAN_APPROACH_MM: f64 = 0.04;

/// The major axes (and edge lines) of a bevel/hypoid pair (module docs).
#[derive(Clone, Debug)]
pub struct PointCandidates {
    pub pair: Arc<BevelPair>,
    /// The point TCA on its grid (no ellipse search: the flank axes take
    /// the curvature ellipse, the edge lines search their own).
    pub tca: PointTca,
    /// K: candidate points on each axis.
    pub points_per_pair: usize,
    /// Separation (mm) out to which each axis runs.
    pub span_approach_mm: f64,
    /// Whether the TCA traced edge contacts and they are candidates.
    pub edges: bool,
    /// Grid positions per pitch.
    pub positions: usize,
    /// Seconds the trace took.
    pub trace_s: f64,
}

impl PointCandidates {
    /// Traces the point TCA of `pair` at `positions` per pitch (edges on
    /// or off) and takes K = `points_per_pair` points per axis.
    pub fn trace(
        pair: Arc<BevelPair>,
        positions: usize,
        edges: bool,
        speed_rpm: f64,
        points_per_pair: usize,
        span_approach_mm: f64,
    ) -> Result<Self, FlankError> {
        let t = Instant::now();
        let tca = point_tca(
            pair.as_ref(),
            &PointTcaSettings {
                positions_per_pitch: positions,
                edges,
                search_directions: 0,
                speed_rpm,
                ..Default::default()
            },
        )?;
        Ok(PointCandidates {
            pair,
            tca,
            points_per_pair,
            span_approach_mm,
            edges,
            positions,
            trace_s: t.elapsed().as_secs_f64(),
        })
    }

    /// The same trace with edge contact on or off (traced again).
    pub fn with_edges(&self, edges: bool, speed_rpm: f64) -> Result<Self, FlankError> {
        Self::trace(
            Arc::clone(&self.pair),
            self.positions,
            edges,
            speed_rpm,
            self.points_per_pair,
            self.span_approach_mm,
        )
    }

    /// The mesh cycle (deg): one pinion pitch.
    pub fn cycle_deg(&self) -> f64 {
        self.tca.pitch_rad.to_degrees()
    }

    /// The grid's roll angles over one pitch centred on roll 0 (deg).
    pub fn cycle_rolls_deg(&self) -> Vec<f64> {
        let (pitch, n) = (self.cycle_deg(), self.positions);
        (0..n)
            .map(|i| -0.5 * pitch + pitch * i as f64 / n as f64)
            .collect()
    }

    /// The moment arm of the middle pair's contact at the grid position
    /// nearest roll 0 (mm): the arm of the nominal normal force.
    pub fn middle_moment_arm(&self) -> Result<f64, FlankError> {
        self.tca
            .positions
            .iter()
            .min_by(|a, b| a.roll_rad.abs().total_cmp(&b.roll_rad.abs()))
            .and_then(|p| p.pairs.iter().find(|c| c.offset == 0))
            .map(|c| c.moment_arm_mm[0])
            .filter(|a| *a > 0.0)
            .ok_or_else(|| {
                FlankError::Model("LTCA: the middle pair has no contact at roll 0".into())
            })
    }

    /// The candidate lines of a grid position (one major axis per tooth
    /// pair of the sector in flank contact; with edges one edge line per
    /// pair in edge contact), with notes on edge contacts left out or
    /// taken whole.
    fn lines(&self, p: &PointTcaPosition) -> Result<(TcaPosition, Vec<String>), FlankError> {
        let (k, delta, span) = (
            self.points_per_pair,
            self.tca.settings.approach_mm,
            self.span_approach_mm,
        );
        let built: Vec<_> = p
            .pairs
            .par_iter()
            .map(|c| {
                if c.system == ContactSystem::Flank {
                    return major_axis_line(self.pair.as_ref(), c, p.roll_rad, k, delta, span)
                        .map(|l| (l, None));
                }
                if !self.edges {
                    return Ok((None, None));
                }
                let at = |what: String| {
                    format!(
                        "{:.3}°: the {} contact of pinion tooth {} {what}",
                        p.roll_rad.to_degrees(),
                        c.system.name(),
                        c.teeth.map(|t| t[0]).unwrap_or(0)
                    )
                };
                Ok(
                    match edge_line(self.pair.as_ref(), c, p.roll_rad, k, delta, span)? {
                        Some(EdgeLine::Line { line, whole_edge }) => (
                            Some(line),
                            whole_edge.then(|| {
                                at("has no closed patch at δ: its whole edge is the candidate line"
                                    .into())
                            }),
                        ),
                        Some(EdgeLine::Unsupported(e)) => (
                            None,
                            Some(at(format!(
                                "is left out ({} edges are not candidates, crate::tca::edge_lines)",
                                e.name()
                            ))),
                        ),
                        Some(EdgeLine::Empty) | None => (None, None),
                    },
                )
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
    pub fn grid_position(&self, roll_deg: f64) -> Option<PointTcaPosition> {
        let h = self.tca.pitch_rad.to_degrees() / self.positions as f64;
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

    /// The pairs of the grid position nearest to `roll_deg` outside the
    /// sector (not modelled) whose separation lies below `approach_mm`:
    /// (pair offset, separation mm).
    pub fn beyond_sector(&self, roll_deg: f64, approach_mm: f64) -> Vec<(i64, f64)> {
        self.grid_position(roll_deg)
            .into_iter()
            .flat_map(|p| p.pairs)
            .filter(|c| c.teeth.is_none() && c.separation_mm < approach_mm)
            .map(|c| (c.offset, c.separation_mm))
            .collect()
    }
}

impl ContactCandidates for PointCandidates {
    /// The grid position nearest to `roll_deg`; `None` where no tooth pair
    /// of the sector is in contact (a roll that no pair's trace reaches: a
    /// pair whose flank path is shorter than a pitch, without the edge
    /// contact that would carry it across); an error beyond the trace.
    fn candidates(&self, roll_deg: f64) -> Result<Option<CandidatePosition>, FlankError> {
        let Some(p) = self.grid_position(roll_deg) else {
            // no position within reach: a gap inside the trace, an error
            // beyond it
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
            return Err(FlankError::Model(format!(
                "LTCA: roll angle {roll_deg}° lies beyond the traced contact ({:.3}° … {:.3}°, and a pitch on either side)",
                first.unwrap_or(f64::NAN),
                last.unwrap_or(f64::NAN)
            )));
        };
        if p.pairs.iter().all(|c| c.teeth.is_none()) {
            return Ok(None);
        }
        let (position, notes) = self.lines(&p)?;
        if position.lines.is_empty() {
            return Ok(None);
        }
        Ok(Some(CandidatePosition {
            frames: self.pair.frames(position.roll),
            position,
            notes,
        }))
    }
}
