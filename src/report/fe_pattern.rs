//! The loaded contact pattern of an FE-contact mesh cycle of a bevel or
//! hypoid pair (SVG and PNG): every loaded contact node of every position,
//! at its place on each member's drive flank in the axial projection
//! (along the face from the mean point, height above the pitch cone: the
//! projection bevel-gear engineers read a marking-compound pattern in),
//! coloured by its contact pressure, over the flank's outline. The union
//! over the cycle is the pattern a run on the test rig leaves.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::error::FlankError;
use crate::geometry::gear_pair::PairPlacement;
use crate::report::figure::{font_available, write_svg_png, Figure};
use crate::report::tca_plot::outline;

/// One loaded contact node at one position.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
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
/// into `out`; returns the file names (none without a loaded node).
pub fn plot_fe_pattern(
    out: &Path,
    pair: &dyn PairPlacement,
    nodes: &[PatternNode],
) -> Result<Vec<String>, FlankError> {
    if nodes.is_empty() {
        return Ok(Vec::new());
    }
    // ascending pressure: the highest pressure at a place is drawn last
    let mut sorted = nodes.to_vec();
    sorted.sort_by(|a, b| a.pressure_mpa.total_cmp(&b.pressure_mpa));
    let mut files = Vec::new();
    for (b, name) in ["pinion", "gear"].iter().enumerate() {
        let figure = FePattern {
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

struct FePattern<'a> {
    member: &'a str,
    outline: Vec<(f64, f64)>,
    /// (along the face, height, pressure).
    points: Vec<(f64, f64, f64)>,
}

impl Figure for FePattern<'_> {
    fn size(&self) -> (u32, u32) {
        (900, 520)
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let e = |e: &dyn std::fmt::Debug| format!("{e:?}");
        root.fill(&WHITE).map_err(|x| e(&x))?;
        let all = self
            .outline
            .iter()
            .copied()
            .chain(self.points.iter().map(|p| (p.0, p.1)));
        let (x0, x1, y0, y1) = all.fold(
            (
                f64::INFINITY,
                f64::NEG_INFINITY,
                f64::INFINITY,
                f64::NEG_INFINITY,
            ),
            |a, p| (a.0.min(p.0), a.1.max(p.0), a.2.min(p.1), a.3.max(p.1)),
        );
        let (mx, my) = (0.08 * (x1 - x0).max(1.0), 0.15 * (y1 - y0).max(1.0));
        let pmax = self
            .points
            .iter()
            .map(|p| p.2)
            .fold(0.0f64, f64::max)
            .max(1e-9);
        let text = font_available();
        let mut cb = ChartBuilder::on(root);
        cb.margin(12);
        if text {
            cb.caption(
                format!(
                    "FE contact pattern over the cycle, {} drive flank (colour: pressure, max {pmax:.0} MPa)",
                    self.member
                ),
                ("sans-serif", 16),
            )
            .x_label_area_size(40)
            .y_label_area_size(50);
        }
        let mut chart = cb
            .build_cartesian_2d((x0 - mx)..(x1 + mx), (y0 - my)..(y1 + my))
            .map_err(|x| e(&x))?;
        let mut mesh = chart.configure_mesh();
        if text {
            mesh.x_desc("along the face from the mean point (mm)")
                .y_desc("height above the pitch cone (mm)");
        }
        mesh.draw().map_err(|x| e(&x))?;
        chart
            .draw_series(LineSeries::new(self.outline.clone(), BLACK.stroke_width(1)))
            .map_err(|x| e(&x))?;
        chart
            .draw_series(self.points.iter().map(|&(x, y, p)| {
                let c = ViridisRGB::get_color_normalized(p, 0.0, pmax);
                Circle::new((x, y), 3, c.filled())
            }))
            .map_err(|x| e(&x))?;
        Ok(())
    }
}
