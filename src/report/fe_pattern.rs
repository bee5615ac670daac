//! The loaded contact pattern of a mesh cycle of a bevel or hypoid pair
//! (SVG and PNG), from FE contact or from the LTCA: every loaded contact
//! node (or LTCA candidate point) of every position,
//! at its place on each member's drive flank in the axial projection
//! (along the face from the mean point, height above the pitch cone: the
//! projection bevel-gear engineers read a marking-compound pattern in),
//! coloured by its contact pressure, over the flank's outline. The union
//! over the cycle is the pattern a run on the test rig leaves.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::error::FlankError;
use crate::geometry::gear_pair::GearPair;
use crate::report::figure::{write_svg_png, Figure};
use crate::report::tca_plot::{outline, projection_chart};

/// One loaded contact node at one position.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PatternNode {
    /// Tooth pair (1-based, as in `positions.csv`).
    pub pair: usize,
    /// Axial projection on [pinion, gear] (mm): along the face from the
    /// mean point toward the heel, height above the pitch cone.
    pub projection_mm: [[f64; 2]; 2],
    /// Contact pressure (face-averaged, MPa).
    pub pressure_mpa: f64,
}

/// Writes `contact_pattern_pinion` and `contact_pattern_gear` (.svg, .png)
/// of an FE-contact cycle into `out`; returns the file names (none without
/// a loaded node).
pub fn plot_fe_pattern(
    out: &Path,
    pair: &dyn GearPair,
    nodes: &[PatternNode],
) -> Result<Vec<String>, FlankError> {
    plot_pattern(out, pair, nodes, "FE contact")
}

/// [`plot_fe_pattern`] for the loaded points of any `method` (named in the
/// title, e.g. "LTCA").
pub fn plot_pattern(
    out: &Path,
    pair: &dyn GearPair,
    nodes: &[PatternNode],
    method: &str,
) -> Result<Vec<String>, FlankError> {
    if nodes.is_empty() {
        return Ok(Vec::new());
    }
    // ascending pressure: the highest pressure at a place is drawn last
    let mut sorted = nodes.to_vec();
    sorted.sort_by(|a, b| a.pressure_mpa.total_cmp(&b.pressure_mpa));
    let mut files = Vec::new();
    for (b, name) in ["pinion", "gear"].iter().enumerate() {
        let figure = PatternFigure {
            method,
            member: name,
            outline: outline(pair, b),
            points: sorted
                .iter()
                .map(|n| (n.projection_mm[b][0], n.projection_mm[b][1], n.pressure_mpa))
                .collect(),
        };
        files.extend(write_svg_png(
            out,
            &format!("contact_pattern_{name}"),
            &figure,
        )?);
    }
    Ok(files)
}

struct PatternFigure<'a> {
    method: &'a str,
    member: &'a str,
    outline: Vec<(f64, f64)>,
    /// (along the face, height, pressure).
    points: Vec<(f64, f64, f64)>,
}

impl Figure for PatternFigure<'_> {
    fn size(&self) -> (u32, u32) {
        (900, 520)
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let e = |e: &dyn std::fmt::Debug| format!("{e:?}");
        let pmax = self
            .points
            .iter()
            .map(|p| p.2)
            .fold(0.0f64, f64::max)
            .max(1e-9);
        let title = format!(
            "{} pattern over the cycle, {} drive flank (colour: pressure, max {pmax:.0} MPa)",
            self.method, self.member
        );
        let mut chart = projection_chart(
            root,
            &title,
            16,
            &self.outline,
            self.points.iter().map(|p| (p.0, p.1)),
        )?;
        chart
            .draw_series(self.points.iter().map(|&(x, y, p)| {
                let c = ViridisRGB::get_color_normalized(p, 0.0, pmax);
                Circle::new((x, y), 3, c.filled())
            }))
            .map_err(|x| e(&x))?;
        Ok(())
    }
}
