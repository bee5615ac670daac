//! Plots of the line TCA of a spur or helical pair over a mesh cycle
//! ([`crate::tca::line_cycle`]; SVG and PNG): the unloaded transmission
//! error with and without tip-corner contact, and the bearing pattern on
//! the pinion flank (the points within the approach δ at every position,
//! over the face and the profile roll angle; tip-corner points in red).

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::error::FlankError;
use crate::report::figure::{font_available, write_svg_png, Figure};
use crate::tca::line_cycle::LineTcaCycle;

struct TePlot<'a> {
    with: &'a LineTcaCycle,
    without: &'a LineTcaCycle,
}

fn bounds(points: impl Iterator<Item = (f64, f64)>) -> Option<[f64; 4]> {
    let mut b = [
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    ];
    for (x, y) in points {
        b = [b[0].min(x), b[1].max(x), b[2].min(y), b[3].max(y)];
    }
    b[0].is_finite().then_some(b)
}

/// The range [lo, hi] widened to at least `min_span` and by 5 %.
fn padded(lo: f64, hi: f64, min_span: f64) -> std::ops::Range<f64> {
    let mid = 0.5 * (lo + hi);
    let half = 0.5 * (hi - lo).max(min_span) * 1.05;
    mid - half..mid + half
}

impl Figure for TePlot<'_> {
    fn size(&self) -> (u32, u32) {
        (900, 560)
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let e = |e: &dyn std::fmt::Debug| format!("{e:?}");
        root.fill(&WHITE).map_err(|x| e(&x))?;
        let series = |c: &LineTcaCycle| -> Vec<(f64, f64)> {
            c.positions
                .iter()
                .map(|p| (p.roll_rad.to_degrees(), p.unloaded_te_rad * 1e6))
                .collect()
        };
        let (sw, so) = (series(self.with), series(self.without));
        let Some(b) = bounds(sw.iter().chain(&so).copied()) else {
            return Ok(());
        };
        let text = font_available();
        let mut cb = ChartBuilder::on(root);
        cb.margin(12);
        if text {
            cb.caption("Unloaded transmission error", ("sans-serif", 20))
                .x_label_area_size(40)
                .y_label_area_size(60);
        }
        let mut chart = cb
            .build_cartesian_2d(padded(b[0], b[1], 1e-3), padded(b[2], b[3], 1.0))
            .map_err(|x| e(&x))?;
        let mut mesh = chart.configure_mesh();
        if text {
            mesh.x_desc("pinion roll angle (deg)")
                .y_desc("θ₀ (µrad, pinion)");
        } else {
            mesh.disable_x_mesh().disable_y_mesh();
        }
        mesh.draw().map_err(|x| e(&x))?;
        for (s, colour, label) in [
            (so, BLUE, "without tip-corner contact"),
            (sw, RED, "with tip-corner contact"),
        ] {
            let drawn = chart
                .draw_series(LineSeries::new(s, colour.stroke_width(2)))
                .map_err(|x| e(&x))?;
            if text {
                drawn
                    .label(label)
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour));
            }
        }
        if text {
            chart
                .configure_series_labels()
                .background_style(WHITE.mix(0.8))
                .border_style(BLACK)
                .draw()
                .map_err(|x| e(&x))?;
        }
        Ok(())
    }
}

struct PatternPlot<'a> {
    with: &'a LineTcaCycle,
}

impl Figure for PatternPlot<'_> {
    fn size(&self) -> (u32, u32) {
        (900, 560)
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let e = |e: &dyn std::fmt::Debug| format!("{e:?}");
        root.fill(&WHITE).map_err(|x| e(&x))?;
        // (face v (mm), profile roll angle u (deg), at a tip corner)
        let pts: Vec<(f64, f64, bool)> = self
            .with
            .positions
            .iter()
            .flat_map(|p| &p.pairs)
            .flat_map(|q| {
                let corner = q.kinds.contains("corner");
                q.pattern_uv
                    .iter()
                    .map(move |uv| (uv[1], uv[0].to_degrees(), corner))
            })
            .collect();
        let Some(b) = bounds(pts.iter().map(|p| (p.0, p.1))) else {
            return Ok(());
        };
        let text = font_available();
        let mut cb = ChartBuilder::on(root);
        cb.margin(12);
        if text {
            cb.caption(
                format!(
                    "Bearing pattern on the pinion flank (within δ = {} mm)",
                    self.with.approach_mm
                ),
                ("sans-serif", 20),
            )
            .x_label_area_size(40)
            .y_label_area_size(60);
        }
        let mut chart = cb
            .build_cartesian_2d(padded(b[0], b[1], 1.0), padded(b[2], b[3], 1.0))
            .map_err(|x| e(&x))?;
        let mut mesh = chart.configure_mesh();
        if text {
            mesh.x_desc("face position v (mm)")
                .y_desc("profile roll angle u (deg)");
        } else {
            mesh.disable_x_mesh().disable_y_mesh();
        }
        mesh.draw().map_err(|x| e(&x))?;
        chart
            .draw_series(pts.iter().map(|&(x, y, corner)| {
                Circle::new((x, y), 2, if corner { RED.filled() } else { BLUE.filled() })
            }))
            .map_err(|x| e(&x))?;
        Ok(())
    }
}

/// Writes `transmission_error` and `bearing_pattern_pinion` (.svg, .png)
/// into `out`; returns the file names.
pub fn plot_line_tca(
    out: &Path,
    with: &LineTcaCycle,
    without: &LineTcaCycle,
) -> Result<Vec<String>, FlankError> {
    let mut files = write_svg_png(out, "transmission_error", &TePlot { with, without })?;
    files.extend(write_svg_png(
        out,
        "bearing_pattern_pinion",
        &PatternPlot { with },
    )?);
    Ok(files)
}
