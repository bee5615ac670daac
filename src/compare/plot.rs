//! "Error against run time": one point per run (LTCA at each K, FE contact
//! at each mesh size), x the time of the cycle (s, log), y the error
//! against the reference (log): TE (circles) and load sharing (triangles).
//! The reference itself (error 0) has no point on a log axis.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::compare::method_run::MethodRun;
use crate::error::FlankError;
use crate::report::figure::{font_available, write_svg_png, Figure};

/// Writes `error_vs_time.{svg,png}` into `out`, its title naming the
/// reference (`reference_label`: the finest FE run or the extrapolated
/// one); returns the file names.
pub fn plot_error_vs_time(
    out: &Path,
    fe: &[MethodRun],
    ltca: &[MethodRun],
    reference_label: &str,
) -> Result<Vec<String>, FlankError> {
    write_svg_png(
        out,
        "error_vs_time",
        &ErrorVsTime {
            fe,
            ltca,
            reference_label,
        },
    )
}

struct ErrorVsTime<'a> {
    fe: &'a [MethodRun],
    ltca: &'a [MethodRun],
    reference_label: &'a str,
}

impl Figure for ErrorVsTime<'_> {
    fn size(&self) -> (u32, u32) {
        (900, 600)
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        draw(root, self.fe, self.ltca, self.reference_label)
    }
}

/// A tick of the log time axis: three decimals at most, trailing zeros
/// dropped (a bare `{v}` printed 0.30000000000000004).
fn seconds(v: f64) -> String {
    let s = format!("{v:.3}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s.is_empty() || s == "-" {
        "0".into()
    } else {
        s.into()
    }
}

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    fe: &[MethodRun],
    ltca: &[MethodRun],
    reference_label: &str,
) -> Result<(), String> {
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| x.to_string();
    let text = font_available();
    root.fill(&WHITE).map_err(e)?;
    let points: Vec<(f64, f64)> = fe
        .iter()
        .chain(ltca)
        .flat_map(|r| [(r.cycle_s, r.te_rel_err), (r.cycle_s, r.load_sharing_err)])
        .filter(|&(x, y)| x > 0.0 && y > 0.0 && x.is_finite() && y.is_finite())
        .collect();
    if points.is_empty() {
        return Ok(());
    }
    let (mut x0, mut x1, mut y0, mut y1) = (f64::INFINITY, 0.0f64, f64::INFINITY, 0.0f64);
    for &(x, y) in &points {
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    let (x0, x1, y0, y1) = (x0 / 3.0, x1 * 3.0, y0 / 3.0, y1 * 3.0);
    let mut b = ChartBuilder::on(root);
    b.margin(15);
    if text {
        b.caption(
            format!("Error against run time (reference: {reference_label})"),
            ("sans-serif", 20),
        )
        .x_label_area_size(45)
        .y_label_area_size(70);
    }
    let mut chart = b
        .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
        .map_err(e)?;
    if text {
        chart
            .configure_mesh()
            .x_desc("run time of the cycle (s)")
            .y_desc("error against the reference")
            .y_label_formatter(&|v| format!("{v:.3}"))
            .x_label_formatter(&|v| seconds(*v))
            .label_style(("sans-serif", 15))
            .draw()
            .map_err(e)?;
    }
    for (runs, colour, name) in [(fe, RED, "FE contact"), (ltca, BLUE, "LTCA")] {
        let ok = |x: f64, y: f64| x > 0.0 && y > 0.0 && x.is_finite() && y.is_finite();
        let te: Vec<(f64, f64)> = runs
            .iter()
            .map(|r| (r.cycle_s, r.te_rel_err))
            .filter(|&(x, y)| ok(x, y))
            .collect();
        let ls: Vec<(f64, f64)> = runs
            .iter()
            .map(|r| (r.cycle_s, r.load_sharing_err))
            .filter(|&(x, y)| ok(x, y))
            .collect();
        let s = chart
            .draw_series(te.iter().map(|&p| Circle::new(p, 5, colour.filled())))
            .map_err(e)?;
        if text {
            s.label(format!("{name}: TE"))
                .legend(move |(x, y)| Circle::new((x + 10, y), 5, colour.filled()));
        }
        let s = chart
            .draw_series(
                ls.iter()
                    .map(|&p| TriangleMarker::new(p, 6, colour.stroke_width(2))),
            )
            .map_err(e)?;
        if text {
            s.label(format!("{name}: load sharing"))
                .legend(move |(x, y)| TriangleMarker::new((x + 10, y), 6, colour.stroke_width(2)));
            for r in runs {
                if ok(r.cycle_s, r.te_rel_err) {
                    chart
                        .draw_series(std::iter::once(Text::new(
                            r.label.replace("LTCA ", "").replace("FE ", ""),
                            (r.cycle_s * 1.1, r.te_rel_err),
                            ("sans-serif", 13),
                        )))
                        .map_err(e)?;
                }
            }
        }
    }
    if text {
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .position(SeriesLabelPosition::UpperRight)
            .draw()
            .map_err(e)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    #[test]
    fn time_ticks_are_short() {
        assert_eq!(super::seconds(0.30000000000000004), "0.3");
        assert_eq!(super::seconds(100.0), "100");
        assert_eq!(super::seconds(0.0005), "0.001");
        assert_eq!(super::seconds(0.0001), "0");
        assert_eq!(super::seconds(2.5), "2.5");
    }
}
