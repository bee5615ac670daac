//! Plots of a mesh cycle (FE contact or LTCA) against roll angle (SVG and PNG, `plotters`):
//! normal force per tooth pair with the total normal force T/(r_b1 cos β_b)
//! (seed 002's Figure 4), and the loaded transmission error. Text needs a
//! font found at run time, as for the compliance plots.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::error::FlankError;
use crate::report::figure::{font_available, write_svg_png, Figure};

/// One curve: label, colour index, points.
struct Curve {
    label: String,
    colour: usize,
    points: Vec<(f64, f64)>,
}

/// A line chart.
struct Chart<'a> {
    title: &'a str,
    x_desc: &'a str,
    y_desc: &'a str,
    curves: Vec<Curve>,
    /// Horizontal reference line (value, label).
    reference: Option<(f64, String)>,
}

/// Writes `<prefix>force_per_tooth.{svg,png}` and
/// `<prefix>transmission_error.{svg,png}` into `out` from series: roll
/// angles (deg), the normal force of each tooth pair (N) and the TE (µrad)
/// at them (FE contact and LTCA alike); returns the file names.
#[allow(clippy::too_many_arguments)]
pub fn plot_cycle(
    out: &Path,
    prefix: &str,
    x: &[f64],
    pair_force_n: &[Vec<f64>],
    te_urad: &[f64],
    teeth: &[(usize, usize)],
    nominal_force: f64,
    base_radius: f64,
) -> Result<Vec<String>, FlankError> {
    if x.is_empty() {
        return Ok(Vec::new());
    }
    let forces = Chart {
        title: "Normal force per tooth pair",
        x_desc: "pinion roll angle (deg)",
        y_desc: "normal force (N)",
        curves: teeth
            .iter()
            .enumerate()
            .map(|(p, &(k, m))| Curve {
                label: format!("pinion tooth {k} / gear tooth {m}"),
                colour: p,
                points: x
                    .iter()
                    .zip(&pair_force_n[p])
                    .map(|(&a, &f)| (a, f))
                    .collect(),
            })
            .collect(),
        reference: Some((
            nominal_force,
            format!("T/(r_b1 cos β_b) = {nominal_force:.0} N"),
        )),
    };
    let te_title = format!(
        "Loaded transmission error (1 µrad = {:.4} µm on the line of action)",
        base_radius * 1e-3
    );
    let te = Chart {
        title: &te_title,
        x_desc: "pinion roll angle (deg)",
        y_desc: "transmission error (µrad)",
        curves: vec![Curve {
            label: "pinion rotation beyond the rigid kinematics".into(),
            colour: 0,
            points: x.iter().zip(te_urad).map(|(&a, &t)| (a, t)).collect(),
        }],
        reference: None,
    };
    let mut files = Vec::new();
    for (stem, chart) in [("force_per_tooth", &forces), ("transmission_error", &te)] {
        files.extend(write_svg_png(out, &format!("{prefix}{stem}"), chart)?);
    }
    Ok(files)
}

/// Writes `<stem>.{svg,png}` into `out`: a line chart of `curves` (label,
/// points (x, y)); a curve may have gaps (it is drawn through its points).
/// Returns the file names.
pub fn plot_series(
    out: &Path,
    stem: &str,
    title: &str,
    x_desc: &str,
    y_desc: &str,
    curves: &[(String, Vec<(f64, f64)>)],
) -> Result<Vec<String>, FlankError> {
    if curves.iter().all(|(_, p)| p.is_empty()) {
        return Ok(Vec::new());
    }
    let chart = Chart {
        title,
        x_desc,
        y_desc,
        curves: curves
            .iter()
            .enumerate()
            .map(|(i, (label, points))| Curve {
                label: label.clone(),
                colour: i,
                points: points.clone(),
            })
            .collect(),
        reference: None,
    };
    write_svg_png(out, stem, &chart)
}

impl Figure for Chart<'_> {
    fn size(&self) -> (u32, u32) {
        (900, 600)
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        draw(root, self)
    }
}

fn draw<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, c: &Chart) -> Result<(), String> {
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| x.to_string();
    let text = font_available();
    root.fill(&WHITE).map_err(e)?;
    let pts = c.curves.iter().flat_map(|k| k.points.iter());
    let (mut x0, mut x1, mut y0, mut y1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for &(x, y) in pts {
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    if let Some((v, _)) = &c.reference {
        y0 = y0.min(*v);
        y1 = y1.max(*v);
    }
    y0 = y0.min(0.0);
    if !(x1 > x0) {
        x1 = x0 + 1.0;
    }
    if !(y1 > y0) {
        y1 = y0 + 1.0;
    }
    let pad = 0.08 * (y1 - y0);
    let mut b = ChartBuilder::on(root);
    b.margin(15);
    if text {
        b.caption(c.title, ("sans-serif", 20))
            .x_label_area_size(45)
            .y_label_area_size(70);
    }
    let mut chart = b
        .build_cartesian_2d(x0..x1, (y0 - 0.02 * (y1 - y0))..(y1 + pad))
        .map_err(e)?;
    if text {
        chart
            .configure_mesh()
            .x_desc(c.x_desc)
            .y_desc(c.y_desc)
            .label_style(("sans-serif", 15))
            .draw()
            .map_err(e)?;
    }
    for k in &c.curves {
        let colour = Palette99::pick(k.colour).to_rgba();
        let s = chart
            .draw_series(LineSeries::new(k.points.clone(), colour.stroke_width(2)))
            .map_err(e)?;
        if text {
            s.label(k.label.clone()).legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2))
            });
        }
        chart
            .draw_series(k.points.iter().map(|&p| Circle::new(p, 3, colour.filled())))
            .map_err(e)?;
    }
    if let Some((v, label)) = &c.reference {
        let s = chart
            .draw_series(LineSeries::new(
                vec![(x0, *v), (x1, *v)],
                BLACK.mix(0.6).stroke_width(1),
            ))
            .map_err(e)?;
        if text {
            let label = label.clone();
            s.label(label).legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], BLACK.mix(0.6).stroke_width(1))
            });
        }
    }
    if text {
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK.mix(0.4))
            .label_font(("sans-serif", 14))
            .position(SeriesLabelPosition::UpperRight)
            .draw()
            .map_err(e)?;
    }
    Ok(())
}
