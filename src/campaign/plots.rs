//! Plots of a campaign: histograms of Monte Carlo figures, and the error
//! of a mesh study's figures against run time.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::error::FlankError;
use crate::report::figure::{font_available, write_svg_png, Figure};

struct Histogram<'a> {
    title: &'a str,
    x_desc: &'a str,
    values: &'a [f64],
    bins: usize,
}

/// Writes `<stem>.svg` and `<stem>.png`: a histogram of `values` with
/// `bins` equal bins over their range (Sturges' rule ⌈log2 n⌉ + 1 when 0).
pub fn histogram(
    dir: &Path,
    stem: &str,
    title: &str,
    x_desc: &str,
    values: &[f64],
    bins: usize,
) -> Result<Vec<String>, FlankError> {
    if values.is_empty() {
        return Ok(Vec::new());
    }
    let bins = if bins == 0 {
        (values.len() as f64).log2().ceil() as usize + 1
    } else {
        bins
    };
    write_svg_png(
        dir,
        stem,
        &Histogram {
            title,
            x_desc,
            values,
            bins,
        },
    )
}

/// Counts per bin over [lo, hi] (the last bin closed).
pub fn bin_counts(values: &[f64], lo: f64, hi: f64, bins: usize) -> Vec<usize> {
    let mut c = vec![0; bins.max(1)];
    let w = (hi - lo) / c.len() as f64;
    for &v in values {
        let k = if w > 0.0 {
            ((v - lo) / w).floor() as isize
        } else {
            0
        };
        let last = c.len() as isize - 1;
        c[k.clamp(0, last) as usize] += 1;
    }
    c
}

impl Figure for Histogram<'_> {
    fn size(&self) -> (u32, u32) {
        (800, 500)
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let e = |x: DrawingAreaErrorKind<DB::ErrorType>| x.to_string();
        let text = font_available();
        root.fill(&WHITE).map_err(e)?;
        let lo = self.values.iter().copied().fold(f64::INFINITY, f64::min);
        let mut hi = self
            .values
            .iter()
            .copied()
            .fold(f64::NEG_INFINITY, f64::max);
        if !(hi > lo) {
            hi = lo + 1.0;
        }
        let counts = bin_counts(self.values, lo, hi, self.bins);
        let w = (hi - lo) / counts.len() as f64;
        let top = counts.iter().copied().max().unwrap_or(1) as f64 * 1.1;
        let mut b = ChartBuilder::on(root);
        b.margin(15);
        if text {
            b.caption(self.title, ("sans-serif", 18))
                .x_label_area_size(45)
                .y_label_area_size(60);
        }
        let mut chart = b.build_cartesian_2d(lo..hi, 0.0..top).map_err(e)?;
        if text {
            chart
                .configure_mesh()
                .x_desc(self.x_desc)
                .y_desc("jobs")
                .label_style(("sans-serif", 14))
                .draw()
                .map_err(e)?;
        }
        chart
            .draw_series(counts.iter().enumerate().map(|(k, &n)| {
                let x0 = lo + k as f64 * w;
                Rectangle::new([(x0, 0.0), (x0 + w, n as f64)], BLUE.mix(0.5).filled())
            }))
            .map_err(e)?;
        Ok(())
    }
}

/// One method's (group's) points of an error-against-run-time plot:
/// (run time s, relative error), both > 0, and the relative uncertainty of
/// its reference (GCI), drawn dashed.
pub struct ErrorSeries {
    pub name: String,
    pub points: Vec<(f64, f64)>,
    pub floor: Option<f64>,
}

struct ErrorAgainstTime<'a> {
    title: &'a str,
    series: &'a [ErrorSeries],
}

/// Writes `<stem>.svg` and `<stem>.png`: relative error against run time,
/// both logarithmic, one line of markers per series (points with a zero
/// error or time left out: a log axis has no place for them).
pub fn error_against_time(
    dir: &Path,
    stem: &str,
    title: &str,
    series: &[ErrorSeries],
) -> Result<Vec<String>, FlankError> {
    let kept: Vec<ErrorSeries> = series
        .iter()
        .map(|s| ErrorSeries {
            name: s.name.clone(),
            floor: s.floor.filter(|g| *g > 0.0 && g.is_finite()),
            points: s
                .points
                .iter()
                .copied()
                .filter(|&(t, e)| t > 0.0 && e > 0.0 && t.is_finite() && e.is_finite())
                .collect(),
        })
        .filter(|s| !s.points.is_empty())
        .collect();
    if kept.is_empty() {
        return Ok(Vec::new());
    }
    write_svg_png(
        dir,
        stem,
        &ErrorAgainstTime {
            title,
            series: &kept,
        },
    )
}

impl Figure for ErrorAgainstTime<'_> {
    fn size(&self) -> (u32, u32) {
        (800, 500)
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        let e = |x: DrawingAreaErrorKind<DB::ErrorType>| x.to_string();
        let text = font_available();
        root.fill(&WHITE).map_err(e)?;
        let all = || self.series.iter().flat_map(|s| s.points.iter().copied());
        let (t0, t1) = all().fold((f64::INFINITY, 0.0f64), |(a, b), (t, _)| {
            (a.min(t), b.max(t))
        });
        let floors = || self.series.iter().filter_map(|s| s.floor);
        let (e0, e1) = all()
            .map(|(_, x)| x)
            .chain(floors())
            .fold((f64::INFINITY, 0.0f64), |(a, b), x| (a.min(x), b.max(x)));
        let mut b = ChartBuilder::on(root);
        b.margin(15);
        if text {
            b.caption(self.title, ("sans-serif", 18))
                .x_label_area_size(45)
                .y_label_area_size(70);
        }
        let mut chart = b
            .build_cartesian_2d(
                ((0.8 * t0)..(1.25 * t1)).log_scale(),
                ((0.8 * e0)..(1.25 * e1)).log_scale(),
            )
            .map_err(e)?;
        if text {
            chart
                .configure_mesh()
                .x_desc("run time (s)")
                .y_desc("relative error against the extrapolated value")
                .label_style(("sans-serif", 14))
                .draw()
                .map_err(e)?;
        }
        let mut floors_drawn: Vec<f64> = Vec::new();
        let mut distinct: Vec<f64> = floors().collect();
        distinct.sort_by(f64::total_cmp);
        distinct.dedup();
        for (k, s) in self.series.iter().enumerate() {
            let colour = Palette99::pick(k).to_rgba();
            let mut pts = s.points.clone();
            pts.sort_by(|a, b| a.0.total_cmp(&b.0));
            let drawn = chart
                .draw_series(LineSeries::new(pts.clone(), colour.stroke_width(2)))
                .map_err(e)?;
            if text {
                drawn.label(s.name.clone()).legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2))
                });
            }
            chart
                .draw_series(pts.iter().map(|&p| Circle::new(p, 4, colour.filled())))
                .map_err(e)?;
            // one dashed line per reference (methods against the same
            // reference share it)
            if let Some(g) = s.floor.filter(|g| !floors_drawn.contains(g)) {
                floors_drawn.push(g);
                let dashed = chart
                    .draw_series(DashedLineSeries::new(
                        [(0.8 * t0, g), (1.25 * t1, g)],
                        8,
                        6,
                        colour.stroke_width(1),
                    ))
                    .map_err(e)?;
                if text {
                    dashed
                        .label(if distinct.len() > 1 {
                            format!("GCI_fine of the reference of {}", s.name)
                        } else {
                            "GCI_fine of the reference".to_string()
                        })
                        .legend(move |(x, y)| {
                            PathElement::new(vec![(x, y), (x + 8, y)], colour.stroke_width(1))
                        });
                }
            }
        }
        if text {
            chart
                .configure_series_labels()
                .background_style(WHITE.mix(0.8))
                .border_style(BLACK)
                .label_font(("sans-serif", 12))
                .draw()
                .map_err(e)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bins_count_every_value_once() {
        let v = [0.0, 0.1, 0.5, 0.99, 1.0];
        let c = bin_counts(&v, 0.0, 1.0, 2);
        assert_eq!(c, [2, 3]);
        assert_eq!(
            bin_counts(&[2.0, 2.0], 2.0, 2.0, 3).iter().sum::<usize>(),
            2
        );
    }
}
