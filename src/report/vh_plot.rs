//! The V–H chart of a misalignment sweep (SVG and PNG): how the bearing's
//! centre moves on the gear's projected flank and how the TE amplitude
//! changes over a grid of offset error ΔE ("V") and pinion axial
//! displacement ΔP ("H"), the two settings a bevel-gear tester moves
//! (Gleason's V–H check; Litvin & Fuentes §20.9 on the sensitivity of the
//! bearing to misalignment).
//!
//! Left: the bearing centre of every grid point, joined along lines of
//! constant ΔE and of constant ΔP (the deformed grid is the chart), the
//! nominal point marked. Right: the TE peak-to-peak over ΔP, one line per
//! ΔE. Grid points where the pair did not mesh are left out.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::error::FlankError;
use crate::report::figure::{font_available, write_svg_png, Figure};

/// One grid point of the sweep.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VhPoint {
    pub offset_error_mm: f64,
    pub pinion_axial_mm: f64,
    /// The bearing centre on the gear's projected flank (along the face
    /// from the mean point, height above the pitch cone, mm) and the TE
    /// peak-to-peak (arcsec); `None` where the pair did not mesh.
    pub centre_mm: Option<[f64; 2]>,
    pub te_peak_to_peak_arcsec: Option<f64>,
}

struct VhChart<'a> {
    points: &'a [VhPoint],
}

fn colour(i: usize) -> RGBColor {
    let (r, g, b) = Palette99::pick(i).to_rgba().rgb();
    RGBColor(r, g, b)
}

/// Distinct values of a key, sorted.
fn levels(points: &[VhPoint], key: impl Fn(&VhPoint) -> f64) -> Vec<f64> {
    let mut v: Vec<f64> = points.iter().map(key).collect();
    v.sort_by(f64::total_cmp);
    v.dedup_by(|a, b| (*a - *b).abs() < 1e-12);
    v
}

fn range(values: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    let (a, b) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |r, x| {
        (r.0.min(x), r.1.max(x))
    });
    if a.is_finite() && b.is_finite() {
        let pad = if b > a { 0.08 * (b - a) } else { 0.5 };
        Some((a - pad, b + pad))
    } else {
        None
    }
}

type Axes<'a, DB> = ChartContext<
    'a,
    DB,
    plotters::coord::cartesian::Cartesian2d<
        plotters::coord::types::RangedCoordf64,
        plotters::coord::types::RangedCoordf64,
    >,
>;

/// A panel's axes: caption, ranges and axis names (text only with a font).
fn axes<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    caption: &str,
    (x, y): ((f64, f64), (f64, f64)),
    (x_desc, y_desc): (&str, &str),
) -> Result<Axes<'a, DB>, String> {
    let e = |e: &dyn std::fmt::Debug| format!("{e:?}");
    let text = font_available();
    let mut b = ChartBuilder::on(area);
    b.margin(12);
    if text {
        b.caption(caption, ("sans-serif", 20))
            .x_label_area_size(40)
            .y_label_area_size(55);
    }
    let mut chart = b
        .build_cartesian_2d(x.0..x.1, y.0..y.1)
        .map_err(|x| e(&x))?;
    if text {
        chart
            .configure_mesh()
            .x_desc(x_desc)
            .y_desc(y_desc)
            .draw()
            .map_err(|x| e(&x))?;
    }
    Ok(chart)
}

impl Figure for VhChart<'_> {
    fn size(&self) -> (u32, u32) {
        (1200, 560)
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let e = |e: &dyn std::fmt::Debug| format!("{e:?}");
        root.fill(&WHITE).map_err(|x| e(&x))?;
        let (left, right) = root.split_horizontally(640);
        let text = font_available();
        let des = levels(self.points, |p| p.offset_error_mm);
        let dps = levels(self.points, |p| p.pinion_axial_mm);
        let same = |a: f64, b: f64| (a - b).abs() < 1e-12;

        // left: the bearing centres
        let centres: Vec<[f64; 2]> = self.points.iter().filter_map(|p| p.centre_mm).collect();
        if let (Some(xr), Some(yr)) = (
            range(centres.iter().map(|c| c[0])),
            range(centres.iter().map(|c| c[1])),
        ) {
            let mut chart = axes(
                &left,
                "Bearing centre on the gear flank",
                (xr, yr),
                (
                    "along the face from the mean point (mm)",
                    "height above the pitch cone (mm)",
                ),
            )?;
            // lines of constant ΔE (colour per ΔE), then of constant ΔP (grey)
            for (i, &de) in des.iter().enumerate() {
                let line: Vec<(f64, f64)> = self
                    .points
                    .iter()
                    .filter(|p| same(p.offset_error_mm, de))
                    .filter_map(|p| p.centre_mm.map(|c| (c[0], c[1])))
                    .collect();
                let s = chart
                    .draw_series(LineSeries::new(line, colour(i).stroke_width(2)))
                    .map_err(|x| e(&x))?;
                if text {
                    s.label(format!("ΔE = {de:+.3} mm")).legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 16, y)], colour(i).stroke_width(2))
                    });
                }
            }
            for &dp in &dps {
                let line: Vec<(f64, f64)> = self
                    .points
                    .iter()
                    .filter(|p| same(p.pinion_axial_mm, dp))
                    .filter_map(|p| p.centre_mm.map(|c| (c[0], c[1])))
                    .collect();
                chart
                    .draw_series(LineSeries::new(line, BLACK.mix(0.35)))
                    .map_err(|x| e(&x))?;
            }
            chart
                .draw_series(
                    self.points
                        .iter()
                        .filter_map(|p| p.centre_mm.map(|c| (p, c)))
                        .map(|(p, c)| {
                            let nominal =
                                p.offset_error_mm.abs() < 1e-12 && p.pinion_axial_mm.abs() < 1e-12;
                            Circle::new((c[0], c[1]), if nominal { 6 } else { 3 }, BLACK.filled())
                        }),
                )
                .map_err(|x| e(&x))?;
            if text {
                chart
                    .configure_series_labels()
                    .background_style(WHITE.mix(0.85))
                    .border_style(BLACK)
                    .draw()
                    .map_err(|x| e(&x))?;
            }
        }

        // right: TE peak-to-peak over ΔP, one line per ΔE
        let te: Vec<f64> = self
            .points
            .iter()
            .filter_map(|p| p.te_peak_to_peak_arcsec)
            .collect();
        if let (Some(xr), Some(yr)) = (
            range(dps.iter().copied()),
            range(te.iter().copied().chain([0.0])),
        ) {
            let mut chart = axes(
                &right,
                "TE peak-to-peak",
                (xr, (yr.0.max(0.0), yr.1)),
                ("pinion axial ΔP (mm)", "TE p-p (arcsec, gear)"),
            )?;
            for (i, &de) in des.iter().enumerate() {
                let line: Vec<(f64, f64)> = self
                    .points
                    .iter()
                    .filter(|p| same(p.offset_error_mm, de))
                    .filter_map(|p| p.te_peak_to_peak_arcsec.map(|t| (p.pinion_axial_mm, t)))
                    .collect();
                chart
                    .draw_series(LineSeries::new(line.clone(), colour(i).stroke_width(2)))
                    .map_err(|x| e(&x))?;
                chart
                    .draw_series(
                        line.into_iter()
                            .map(|q| Circle::new(q, 3, colour(i).filled())),
                    )
                    .map_err(|x| e(&x))?;
            }
        }
        Ok(())
    }
}

/// Writes `vh_chart.svg` and `vh_chart.png` into `dir`; returns their names.
pub fn plot_vh_sweep(dir: &Path, points: &[VhPoint]) -> Result<Vec<String>, FlankError> {
    write_svg_png(dir, "vh_chart", &VhChart { points })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The chart is drawn from a grid with a missing point (no mesh there)
    /// and its files are non-empty.
    #[test]
    fn draws_a_grid_with_a_gap() {
        let mut points = Vec::new();
        for de in [-0.1, 0.0, 0.1] {
            for dp in [-0.1, 0.0, 0.1] {
                let meshes = !(de > 0.05 && dp > 0.05);
                points.push(VhPoint {
                    offset_error_mm: de,
                    pinion_axial_mm: dp,
                    centre_mm: meshes.then_some([10.0 * dp + 3.0 * de, -5.0 * de]),
                    te_peak_to_peak_arcsec: meshes.then_some(10.0 + 20.0 * (de * de + dp * dp)),
                });
            }
        }
        let dir = std::env::temp_dir().join(format!("flank_vh_{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let files = plot_vh_sweep(&dir, &points).unwrap();
        for f in files {
            assert!(std::fs::metadata(dir.join(&f)).unwrap().len() > 100, "{f}");
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
