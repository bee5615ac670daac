//! Plots of a point-contact TCA (SVG and PNG): the transmission error over
//! the pinion roll angle with and without edge contact (each pair's curve
//! and the envelope), and the bearing pattern on the projected flank of
//! each member (the flank's outline in the axial section, the path of
//! contact, the contact ellipses' major axes along it, edge contacts
//! marked).

use std::path::Path;

use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::error::FlankError;
use crate::geometry::gear_pair::{Flank, GearPair};
use crate::geometry::tangency::ContactSystem;
use crate::report::figure::{font_available, write_svg_png, Figure};
use crate::tca::point_contact::{projection, PointTca, ARCSEC_PER_RAD};

struct TePlot<'a> {
    with: &'a PointTca,
    without: &'a PointTca,
}

fn colour(i: usize) -> RGBColor {
    let (r, g, b) = Palette99::pick(i).to_rgba().rgb();
    RGBColor(r, g, b)
}

impl Figure for TePlot<'_> {
    fn size(&self) -> (u32, u32) {
        (900, 560)
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let e = |e: &dyn std::fmt::Debug| format!("{e:?}");
        root.fill(&WHITE).map_err(|x| e(&x))?;
        let series = |t: &PointTca| -> Vec<(f64, f64)> {
            t.positions
                .iter()
                .map(|p| (p.roll_rad.to_degrees(), p.te_rad * ARCSEC_PER_RAD))
                .collect()
        };
        let (sw, so) = (series(self.with), series(self.without));
        let all: Vec<&(f64, f64)> = sw.iter().chain(&so).collect();
        if all.is_empty() {
            return Ok(());
        }
        let (x0, x1) = all.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |a, p| {
            (a.0.min(p.0), a.1.max(p.0))
        });
        let (mut y0, mut y1) = all.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |a, p| {
            (a.0.min(p.1), a.1.max(p.1))
        });
        // a floor: pair curves reach far below; show 3 × the envelope range
        let span = (y1 - y0).max(1.0);
        y0 -= 2.0 * span;
        y1 += 0.2 * span;
        let text = font_available();
        let mut b = ChartBuilder::on(root);
        b.margin(12);
        if text {
            b.caption("Unloaded transmission error", ("sans-serif", 20))
                .x_label_area_size(40)
                .y_label_area_size(60);
        }
        let mut chart = b.build_cartesian_2d(x0..x1, y0..y1).map_err(|x| e(&x))?;
        let mut mesh = chart.configure_mesh();
        if text {
            mesh.x_desc("pinion roll angle (deg)")
                .y_desc("TE Δφ₂ (arcsec, gear)");
        } else {
            mesh.disable_x_mesh().disable_y_mesh();
        }
        mesh.draw().map_err(|x| e(&x))?;
        // each pair's curve (without edges: thin grey; with: thin colours)
        for (t, c) in [
            (self.without, RGBColor(160, 160, 160)),
            (self.with, colour(1)),
        ] {
            let mut by_pair: std::collections::BTreeMap<i64, Vec<(f64, f64)>> = Default::default();
            for p in &t.positions {
                for c in &p.pairs {
                    let y = c.gear_lag_rad * ARCSEC_PER_RAD;
                    if y >= y0 {
                        by_pair
                            .entry(c.offset)
                            .or_default()
                            .push((p.roll_rad.to_degrees(), y));
                    }
                }
            }
            for pts in by_pair.values() {
                chart
                    .draw_series(LineSeries::new(pts.clone(), c.stroke_width(1)))
                    .map_err(|x| e(&x))?;
            }
        }
        let s = chart
            .draw_series(LineSeries::new(so, BLUE.stroke_width(2)))
            .map_err(|x| e(&x))?;
        if text {
            s.label("envelope without edge contact")
                .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLUE));
        }
        let s = chart
            .draw_series(LineSeries::new(sw, RED.stroke_width(2)))
            .map_err(|x| e(&x))?;
        if text {
            s.label("envelope with edge contact")
                .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], RED));
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
    member: usize,
    outline: Vec<(f64, f64)>,
    with: &'a PointTca,
    without: &'a PointTca,
}

impl Figure for PatternPlot<'_> {
    fn size(&self) -> (u32, u32) {
        (900, 520)
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let e = |e: &dyn std::fmt::Debug| format!("{e:?}");
        let b = self.member;
        let title = format!(
            "Bearing pattern on the {} drive flank (axial projection)",
            if b == 0 { "pinion" } else { "gear" }
        );
        let mut chart = projection_chart(root, &title, 18, &self.outline, std::iter::empty())?;
        // major axes (with edges), only of pairs in contact at δ
        let delta = self.with.settings.approach_mm;
        for p in &self.with.positions {
            for c in &p.pairs {
                if c.offset != 0 || c.separation_mm > delta {
                    continue;
                }
                if let Some(ends) = c.major_axis_projection_mm {
                    let [a, z] = ends[b];
                    let col = if c.system == ContactSystem::Flank {
                        RGBColor(120, 170, 230)
                    } else {
                        RGBColor(240, 140, 140)
                    };
                    chart
                        .draw_series(std::iter::once(PathElement::new(
                            vec![(a[0], a[1]), (z[0], z[1])],
                            col.stroke_width(1),
                        )))
                        .map_err(|x| e(&x))?;
                }
            }
        }
        // paths: without edges (blue dots), with edges (edge points red)
        for (t, flank_col, size) in [(self.without, BLUE, 3), (self.with, BLUE, 2)] {
            for p in &t.positions {
                for c in p.pairs.iter().filter(|c| c.offset == 0) {
                    let q = c.projection_mm[b];
                    let col = if c.system == ContactSystem::Flank {
                        flank_col
                    } else {
                        RED
                    };
                    chart
                        .draw_series(std::iter::once(Circle::new(
                            (q[0], q[1]),
                            size,
                            col.filled(),
                        )))
                        .map_err(|x| e(&x))?;
                }
            }
        }
        Ok(())
    }
}

/// A chart over a member's axial projection (along the face from the mean
/// point, height above the pitch cone), the flank's outline drawn; the
/// bounds take the outline and `extra` points. Shared by the TCA's bearing
/// pattern and FE contact's loaded pattern
/// ([`crate::report::fe_pattern`]).
pub(crate) fn projection_chart<'a, DB: DrawingBackend>(
    root: &'a DrawingArea<DB, Shift>,
    title: &str,
    title_size: u32,
    outline: &[(f64, f64)],
    extra: impl Iterator<Item = (f64, f64)>,
) -> Result<ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>, String> {
    let e = |e: &dyn std::fmt::Debug| format!("{e:?}");
    root.fill(&WHITE).map_err(|x| e(&x))?;
    let (x0, x1, y0, y1) = outline.iter().copied().chain(extra).fold(
        (
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ),
        |a, p| (a.0.min(p.0), a.1.max(p.0), a.2.min(p.1), a.3.max(p.1)),
    );
    let (mx, my) = (0.08 * (x1 - x0).max(1.0), 0.15 * (y1 - y0).max(1.0));
    let text = font_available();
    let mut cb = ChartBuilder::on(root);
    cb.margin(12);
    if text {
        cb.caption(title, ("sans-serif", title_size))
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
        .draw_series(LineSeries::new(outline.to_vec(), BLACK.stroke_width(1)))
        .map_err(|x| e(&x))?;
    Ok(chart)
}

/// The outline of member `b`'s middle drive flank in its axial projection:
/// form line, heel, tip, toe.
pub(crate) fn outline(pair: &dyn GearPair, b: usize) -> Vec<(f64, f64)> {
    let body = pair.body(b);
    let tooth = if b == 0 {
        pair.middle()
    } else {
        pair.mate(pair.middle())
    };
    let Some(s) = body.flank(Flank::Right, tooth) else {
        return Vec::new();
    };
    let (v0, v1) = s.v_range();
    let n = 40;
    let mut pts = Vec::new();
    let mut push = |u: f64, v: f64| {
        let q = projection(body, s.point(u, v));
        pts.push((q[0], q[1]));
    };
    for i in 0..=n {
        let v = v0 + (v1 - v0) * i as f64 / n as f64;
        push(s.u_form(v), v);
    }
    for i in 0..=n {
        let f = i as f64 / n as f64;
        push(s.u_form(v1) + f * (s.u_tip(v1) - s.u_form(v1)), v1);
    }
    for i in 0..=n {
        let v = v1 - (v1 - v0) * i as f64 / n as f64;
        push(s.u_tip(v), v);
    }
    for i in 0..=n {
        let f = i as f64 / n as f64;
        push(s.u_tip(v0) - f * (s.u_tip(v0) - s.u_form(v0)), v0);
    }
    pts
}

/// Writes `transmission_error`, `bearing_pattern_pinion` and
/// `bearing_pattern_gear` (.svg, .png) into `out`; returns the file names.
pub fn plot_point_tca(
    out: &Path,
    pair: &dyn GearPair,
    with: &PointTca,
    without: &PointTca,
) -> Result<Vec<String>, FlankError> {
    let mut files = write_svg_png(out, "transmission_error", &TePlot { with, without })?;
    for (b, name) in [(0, "bearing_pattern_pinion"), (1, "bearing_pattern_gear")] {
        files.extend(write_svg_png(
            out,
            name,
            &PatternPlot {
                member: b,
                outline: outline(pair, b),
                with,
                without,
            },
        )?);
    }
    Ok(files)
}
