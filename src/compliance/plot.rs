//! A colour map of the nodal normal self-compliance c_nn = n_iᵀ C^{ii} n_i
//! over one flank (face width z horizontally, radius r vertically), as SVG
//! and PNG, drawn with `plotters` (pure Rust backends; text with `ab_glyph`
//! from a TrueType font found at run time: `$FLANK_FONT` or a common system
//! path; without one, or with `FLANK_FONT` set empty, the plots are drawn
//! without text, which the returned [`PlotInfo`] says).

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::compliance::flank::face_shape;
use crate::compliance::ComplianceTensor;
use crate::error::FlankError;
use crate::report::figure::{font_available, write_pair, Figure};

/// What was plotted.
#[derive(Clone, Debug, serde::Serialize)]
pub struct PlotInfo {
    pub set: String,
    /// Range of c_nn over the set's nodes (µm/N).
    pub c_nn_min_um_per_n: f64,
    pub c_nn_max_um_per_n: f64,
    /// Median over the set's nodes (µm/N).
    pub c_nn_median_um_per_n: f64,
    /// False if no font was found: the plots carry no text.
    pub text: bool,
}

/// Nodal c_nn (mm/N) of every flank node.
pub fn nodal_cnn(t: &ComplianceTensor) -> Vec<f64> {
    (0..t.node_count())
        .map(|a| {
            let c = t.block(a, a);
            let n = t.flank.normals[a];
            (0..3)
                .map(|i| (0..3).map(|j| n[i] * c[i][j] * n[j]).sum::<f64>())
                .sum()
        })
        .collect()
}

struct Cells {
    polys: Vec<(Vec<(f64, f64)>, f64)>,
    nodes: Vec<(f64, f64)>,
    x: (f64, f64),
    y: (f64, f64),
    v: (f64, f64),
}

/// Plots c_nn over the flank set `set` of `t` to `svg` and `png`.
pub fn plot_cnn(
    t: &ComplianceTensor,
    set: &str,
    title: &str,
    svg: &Path,
    png: &Path,
) -> Result<PlotInfo, FlankError> {
    let s = t
        .flank
        .set_index(set)
        .ok_or_else(|| FlankError::Model(format!("no flank set {set} to plot")))?
        as u32;
    let cnn: Vec<f64> = nodal_cnn(t).iter().map(|v| v * 1e3).collect(); // µm/N
    let f = &t.flank;
    let zr = |x: [f64; 3]| (x[2], x[0].hypot(x[1]));
    let mut vals: Vec<f64> = (0..f.len())
        .filter(|&a| f.set_of[a] == s)
        .map(|a| cnn[a])
        .collect();
    if vals.is_empty() {
        return Err(FlankError::Model(format!("flank set {set} has no nodes")));
    }
    vals.sort_by(f64::total_cmp);
    let (vmin, vmax) = (vals[0], vals[vals.len() - 1]);
    let median = vals[vals.len() / 2];
    // sub-cells of every face, coloured by the interpolated nodal field
    const K: usize = 4;
    let mut cells = Cells {
        polys: Vec::new(),
        nodes: Vec::new(),
        x: (f64::INFINITY, f64::NEG_INFINITY),
        y: (f64::INFINITY, f64::NEG_INFINITY),
        v: (vmin, vmax),
    };
    let eval = |nodes: &[u32], xi: [f64; 2]| -> ((f64, f64), f64) {
        let (n, _) = face_shape(nodes.len(), xi);
        let mut x = [0.0; 3];
        let mut v = 0.0;
        for (a, &node) in nodes.iter().enumerate() {
            for i in 0..3 {
                x[i] += n[a] * f.positions[node as usize][i];
            }
            v += n[a] * cnn[node as usize];
        }
        (zr(x), v)
    };
    for face in f.faces.iter().filter(|fc| fc.set == s) {
        let quad = face.nodes.len() == 8;
        for i in 0..K {
            for j in 0..K {
                let sub: Vec<[f64; 2]> = if quad {
                    let a = |k: usize| -1.0 + 2.0 * k as f64 / K as f64;
                    vec![
                        [a(i), a(j)],
                        [a(i + 1), a(j)],
                        [a(i + 1), a(j + 1)],
                        [a(i), a(j + 1)],
                    ]
                } else {
                    if i + j >= K {
                        continue;
                    }
                    let a = |k: usize| k as f64 / K as f64;
                    let mut v = vec![[a(i), a(j)], [a(i + 1), a(j)], [a(i), a(j + 1)]];
                    if i + j + 1 < K {
                        v.insert(2, [a(i + 1), a(j + 1)]);
                    }
                    v
                };
                let c = sub
                    .iter()
                    .fold([0.0, 0.0], |s, p| [s[0] + p[0], s[1] + p[1]]);
                let c = [c[0] / sub.len() as f64, c[1] / sub.len() as f64];
                let pts: Vec<(f64, f64)> = sub.iter().map(|&p| eval(&face.nodes, p).0).collect();
                for p in &pts {
                    cells.x = (cells.x.0.min(p.0), cells.x.1.max(p.0));
                    cells.y = (cells.y.0.min(p.1), cells.y.1.max(p.1));
                }
                cells.polys.push((pts, eval(&face.nodes, c).1));
            }
        }
    }
    for a in (0..f.len()).filter(|&a| f.set_of[a] == s) {
        cells.nodes.push(zr(f.positions[a]));
    }
    if cells.polys.is_empty() {
        return Err(FlankError::Model(format!(
            "flank set {set} has no faces to plot"
        )));
    }
    let text = font_available();
    let figure = CnnMap {
        cells: &cells,
        title,
        text,
    };
    write_pair(svg, png, &figure)?;
    Ok(PlotInfo {
        set: set.to_string(),
        c_nn_min_um_per_n: vmin,
        c_nn_max_um_per_n: vmax,
        c_nn_median_um_per_n: median,
        text,
    })
}

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    c: &Cells,
    title: &str,
    text: bool,
) -> Result<(), String> {
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| x.to_string();
    root.fill(&WHITE).map_err(e)?;
    let (w, _) = root.dim_in_pixel();
    let (main, bar) = root.split_horizontally(w.saturating_sub(130));
    let (vmin, vmax) = c.v;
    let span = (vmax - vmin).max(1e-300);
    let colour = |v: f64| ViridisRGB.get_color(((v - vmin) / span).clamp(0.0, 1.0) as f32);
    let pad_x = 0.03 * (c.x.1 - c.x.0).max(1e-9);
    let pad_y = 0.03 * (c.y.1 - c.y.0).max(1e-9);
    let mut b = ChartBuilder::on(&main);
    b.margin(15);
    if text {
        b.caption(title, ("sans-serif", 20))
            .x_label_area_size(45)
            .y_label_area_size(60);
    }
    let mut chart = b
        .build_cartesian_2d(
            (c.x.0 - pad_x)..(c.x.1 + pad_x),
            (c.y.0 - pad_y)..(c.y.1 + pad_y),
        )
        .map_err(e)?;
    if text {
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc("face width z (mm)")
            .y_desc("radius r (mm)")
            .label_style(("sans-serif", 15))
            .draw()
            .map_err(e)?;
    }
    chart
        .draw_series(
            c.polys
                .iter()
                .map(|(pts, v)| Polygon::new(pts.clone(), colour(*v).filled())),
        )
        .map_err(e)?;
    chart
        .draw_series(
            c.nodes
                .iter()
                .map(|&p| Circle::new(p, 1, BLACK.mix(0.5).filled())),
        )
        .map_err(e)?;
    // colour bar
    let mut bb = ChartBuilder::on(&bar);
    bb.margin_top(40).margin_bottom(60).margin_right(10);
    if text {
        bb.caption("c_nn (µm/N)", ("sans-serif", 15))
            .y_label_area_size(70);
    }
    let mut cb = bb
        .build_cartesian_2d(0.0..1.0, vmin..(vmin + span))
        .map_err(e)?;
    if text {
        cb.configure_mesh()
            .disable_mesh()
            .disable_x_axis()
            .y_labels(8)
            .y_label_formatter(&|v| format!("{v:.4}"))
            .label_style(("sans-serif", 13))
            .draw()
            .map_err(e)?;
    }
    let steps = 100;
    cb.draw_series((0..steps).map(|k| {
        let a = vmin + span * k as f64 / steps as f64;
        let b = vmin + span * (k + 1) as f64 / steps as f64;
        Rectangle::new([(0.0, a), (1.0, b)], colour(0.5 * (a + b)).filled())
    }))
    .map_err(e)?;
    Ok(())
}

struct CnnMap<'a> {
    cells: &'a Cells,
    title: &'a str,
    text: bool,
}

impl Figure for CnnMap<'_> {
    fn size(&self) -> (u32, u32) {
        (900, 700)
    }
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String> {
        draw(root, self.cells, self.title, self.text)
    }
}
