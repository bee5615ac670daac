//! Contact pattern of one pinion tooth over a mesh cycle (SVG and PNG): every
//! loaded LTCA point of that tooth at its place on the flank (face width z
//! across, pinion radius up), coloured by its Hertz pressure, as a marking
//! compound would show it on the real tooth.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::error::FlankError;
use crate::ltca::model::PositionResult;
use crate::report::figure::{font_available, write_svg_png, Figure};

/// Writes `ltca_contact_pattern.{svg,png}` for pinion tooth `tooth`;
/// returns the file names (none if no point of it carries load).
pub fn plot_contact_pattern(
    out: &Path,
    results: &[PositionResult],
    tooth: usize,
    face_width: f64,
) -> Result<Vec<String>, FlankError> {
    // (z, radius, pressure)
    let pts: Vec<(f64, f64, f64)> = results
        .iter()
        .flat_map(|r| {
            r.points
                .iter()
                .filter(move |p| r.lines[p.line].0 == tooth && p.force_n > 0.0)
                .map(|p| {
                    (
                        p.position[2],
                        p.position[0].hypot(p.position[1]),
                        p.pressure_mpa,
                    )
                })
        })
        .collect();
    if pts.is_empty() {
        return Ok(Vec::new());
    }
    let figure = Pattern {
        pts: &pts,
        tooth,
        face_width,
    };
    write_svg_png(out, "ltca_contact_pattern", &figure)
}

struct Pattern<'a> {
    pts: &'a [(f64, f64, f64)],
    tooth: usize,
    face_width: f64,
}

impl Figure for Pattern<'_> {
    fn size(&self) -> (u32, u32) {
        (700, 700)
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        draw(root, self.pts, self.tooth, self.face_width)
    }
}

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    pts: &[(f64, f64, f64)],
    tooth: usize,
    face_width: f64,
) -> Result<(), String> {
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| x.to_string();
    let text = font_available();
    root.fill(&WHITE).map_err(e)?;
    let (r0, r1) = pts.iter().fold((f64::INFINITY, 0.0f64), |(a, b), p| {
        (a.min(p.1), b.max(p.1))
    });
    let pmax = pts.iter().map(|p| p.2).fold(0.0f64, f64::max).max(1e-9);
    let pad = 0.05 * (r1 - r0).max(0.1);
    let title = format!(
        "Contact pattern, pinion tooth {tooth} (colour: Hertz pressure, max {pmax:.0} MPa)"
    );
    let mut b = ChartBuilder::on(root);
    b.margin(15);
    if text {
        b.caption(&title, ("sans-serif", 16))
            .x_label_area_size(40)
            .y_label_area_size(60);
    }
    let mut chart = b
        .build_cartesian_2d(
            -0.02 * face_width..1.02 * face_width,
            (r0 - pad)..(r1 + pad),
        )
        .map_err(e)?;
    if text {
        chart
            .configure_mesh()
            .x_desc("face width z (mm)")
            .y_desc("pinion radius (mm)")
            .label_style(("sans-serif", 14))
            .draw()
            .map_err(e)?;
    }
    chart
        .draw_series(pts.iter().map(|&(z, r, p)| {
            let c = ViridisRGB::get_color_normalized(p, 0.0, pmax);
            Circle::new((z, r), 3, c.filled())
        }))
        .map_err(e)?;
    Ok(())
}
