//! Plots of a campaign: histograms of Monte Carlo figures.

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
