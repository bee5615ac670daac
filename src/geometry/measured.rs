//! Measured (CMM) transverse profiles: read, project onto the nominal
//! involute, interpolate the deviation in the roll angle.
//!
//! # CSV format
//!
//! ```text
//! # comment lines start with '#' (anywhere); blank lines are skipped
//! x_mm,y_mm
//! 7.1234567,23.4567890
//! …
//! ```
//!
//! The first line that is neither blank nor a comment is the header, exactly
//! `x_mm,y_mm` (spaces around the names allowed). Each further line is one
//! point (x, y) in mm of a **transverse section** of one tooth, in the frame of
//! the profile's tooth 0 at z = 0 ([`ToothProfile::point`]): gear axis at the
//! origin, the tooth symmetric about +y with its tip up, [`Flank::Right`] at
//! x > 0. Points with x > 0 belong to the right flank, x < 0 to the left flank
//! (x = 0 is an error). The points of each flank must follow each other along
//! the profile (root to tip or tip to root); exact repeats of the previous
//! point (within 1e-9 mm) are dropped. If only one flank is given, it is
//! mirrored to the other (same deviation at the same roll angle); this is
//! reported as a note.
//!
//! # Deviation
//!
//! Each point p is projected onto the nominal involute of its flank: the
//! projection equation (p − P(u))·P′(u) = 0 has a closed-form solution, since
//! every normal of an involute is a tangent of its base circle (ISO 21771:2007;
//! Litvin & Fuentes, *Gear Geometry and Applied Theory*, involute gears). With
//! r = |p|, θ the polar angle of p from +y (towards +x; mirrored for the left
//! flank), ψ_b the base half angle and L = √(r² − r_b²),
//!
//!   u = ψ_b − θ + atan(L / r_b),   d = L − r_b u,
//!
//! the roll angle of the foot point and the signed distance along the outward
//! normal (d > 0: material beyond the nominal flank). No Newton iteration is
//! needed; the tests check the projection equation to round-off. d is the
//! transverse profile deviation (ISO 1328-1 measures along the base tangent in
//! the transverse plane). The material removed normal to the flank is
//! offset = −d·cos β_b (= −d for spur gears); [`super::micro`] adds it to the
//! analytic modifications, on the involute and above the SAP only.
//!
//! # Interpolation
//!
//! d(u) is interpolated with the monotone piecewise cubic Hermite interpolant
//! of Fritsch & Carlson (SIAM J. Numer. Anal. 17, 1980), slopes by the
//! weighted harmonic mean of Fritsch & Butland (1984) inside and the
//! shape-preserving three-point formula at the ends (as in Moler, *Numerical
//! Computing with MATLAB*, `pchip`): C¹, no overshoot, exact on straight
//! pieces. Outside the measured range the end value is held (derivative 0);
//! [`MeasuredProfile::coverage_warnings`] names the range when it does not
//! cover the active profile.
//!
//! # Errors
//!
//! [`FlankError::Parse`] with the file and the 1-based line: a wrong header, a
//! line without exactly two fields, an unparsable or non-finite number, a
//! point on x = 0, a point whose radius lies outside the involute's range
//! [r_F, r_a] by more than [`RADIUS_TOLERANCE`], a point farther than
//! [`MAX_DEVIATION_MODULES`]·m_n from the nominal involute, roll angles not
//! monotone along the file (after dropping exact repeats), fewer than
//! [`MIN_POINTS`] points on a flank that has points, no points at all.

use std::path::{Path, PathBuf};

use super::rack::{Flank, ToothProfile};
use crate::error::FlankError;

type Result<T> = std::result::Result<T, FlankError>;

/// Smallest number of points on a measured flank.
pub const MIN_POINTS: usize = 4;
/// Largest |deviation| accepted, as a multiple of the normal module.
pub const MAX_DEVIATION_MODULES: f64 = 0.2;
/// Radius tolerance (mm) around the involute's range [r_F, r_a].
pub const RADIUS_TOLERANCE: f64 = 0.01;
/// Two consecutive points closer than this (mm) in x and y are one point.
const DUPLICATE_TOL: f64 = 1e-9;
/// Smallest roll-length step (mm) between consecutive points.
const MIN_STEP: f64 = 1e-9;

/// Roll angle u of the foot point and signed deviation d (mm, along the
/// outward normal) of a transverse point p (tooth 0 frame) relative to the
/// nominal involute of `flank` (module docs). Needs |p| > r_b.
pub fn project_onto_involute(profile: &ToothProfile, flank: Flank, p: [f64; 2]) -> (f64, f64) {
    let rb = profile.geometry.base_radius;
    let x = match flank {
        Flank::Right => p[0],
        Flank::Left => -p[0],
    };
    let y = p[1];
    let r = x.hypot(y);
    let theta = x.atan2(y);
    let l = ((r - rb) * (r + rb)).max(0.0).sqrt();
    let u = profile.base_half_angle - theta + l.atan2(rb);
    (u, l - rb * u)
}

/// Normal module m_n of a profile: m_t cos β with tan β = |dφ/dz|·r.
pub fn normal_module(profile: &ToothProfile) -> f64 {
    let g = &profile.geometry;
    let beta = (profile.twist_rate.abs() * g.reference_radius).atan();
    g.transverse_module * beta.cos()
}

/// The measured deviation of one flank: d(u) at strictly increasing roll angles.
#[derive(Clone, Debug, PartialEq)]
pub struct MeasuredFlank {
    /// Roll angles (rad), strictly increasing.
    pub u: Vec<f64>,
    /// Transverse deviation d (mm), outward positive.
    pub deviation: Vec<f64>,
    /// True if copied from the other flank.
    pub mirrored: bool,
    slopes: Vec<f64>,
}

impl MeasuredFlank {
    fn new(u: Vec<f64>, deviation: Vec<f64>, mirrored: bool) -> Self {
        let slopes = pchip_slopes(&u, &deviation);
        MeasuredFlank {
            u,
            deviation,
            mirrored,
            slopes,
        }
    }

    /// (d, dd/du) at u: the interpolant inside the range (at its ends the
    /// one-sided inner slope), the end value and slope 0 outside.
    pub fn eval(&self, u: f64) -> (f64, f64) {
        let (x, y, d) = (&self.u, &self.deviation, &self.slopes);
        let n = x.len();
        if !(u >= x[0]) {
            return (y[0], 0.0);
        }
        if u > x[n - 1] {
            return (y[n - 1], 0.0);
        }
        // x[k] ≤ u ≤ x[k+1], k in [0, n-2] (at the range ends: the inner derivative)
        let k = (x.partition_point(|&xi| xi <= u) - 1).min(n - 2);
        let h = x[k + 1] - x[k];
        let t = (u - x[k]) / h;
        let (t2, t3) = (t * t, t * t * t);
        let v = (2.0 * t3 - 3.0 * t2 + 1.0) * y[k]
            + (t3 - 2.0 * t2 + t) * h * d[k]
            + (-2.0 * t3 + 3.0 * t2) * y[k + 1]
            + (t3 - t2) * h * d[k + 1];
        let dv = (6.0 * t2 - 6.0 * t) * (y[k] - y[k + 1]) / h
            + (3.0 * t2 - 4.0 * t + 1.0) * d[k]
            + (3.0 * t2 - 2.0 * t) * d[k + 1];
        (v, dv)
    }

    /// Measured roll-angle range [u_first, u_last].
    pub fn range(&self) -> (f64, f64) {
        (self.u[0], self.u[self.u.len() - 1])
    }
}

/// Fritsch–Carlson / Fritsch–Butland slopes (module docs).
fn pchip_slopes(x: &[f64], y: &[f64]) -> Vec<f64> {
    let n = x.len();
    let h: Vec<f64> = (0..n - 1).map(|k| x[k + 1] - x[k]).collect();
    let del: Vec<f64> = (0..n - 1).map(|k| (y[k + 1] - y[k]) / h[k]).collect();
    let mut d = vec![0.0; n];
    if n == 2 {
        d[0] = del[0];
        d[1] = del[0];
        return d;
    }
    for k in 1..n - 1 {
        if del[k - 1] * del[k] > 0.0 {
            let w1 = 2.0 * h[k] + h[k - 1];
            let w2 = h[k] + 2.0 * h[k - 1];
            d[k] = (w1 + w2) / (w1 / del[k - 1] + w2 / del[k]);
        }
    }
    let end = |h0: f64, h1: f64, d0: f64, d1: f64| -> f64 {
        let s = ((2.0 * h0 + h1) * d0 - h0 * d1) / (h0 + h1);
        if s * d0 <= 0.0 {
            0.0
        } else if d0 * d1 < 0.0 && s.abs() > 3.0 * d0.abs() {
            3.0 * d0
        } else {
            s
        }
    };
    d[0] = end(h[0], h[1], del[0], del[1]);
    d[n - 1] = end(h[n - 2], h[n - 3], del[n - 2], del[n - 3]);
    d
}

/// A measured transverse profile (both flanks), in the roll angle of the nominal involute.
#[derive(Clone, Debug, PartialEq)]
pub struct MeasuredProfile {
    path: PathBuf,
    right: MeasuredFlank,
    left: MeasuredFlank,
    cos_base_helix: f64,
    notes: Vec<String>,
}

struct Point {
    line: usize,
    x: f64,
    y: f64,
    u: f64,
    d: f64,
}

impl MeasuredProfile {
    /// Read and convert the CSV at `path` for the gear of `profile` (format and
    /// errors in the module docs).
    pub fn read(path: &Path, profile: &ToothProfile) -> Result<Self> {
        let text = crate::text_file::read_utf8(path)?;
        Self::parse(&text, path, profile)
    }

    /// Parse CSV text; `path` names the file in errors.
    pub fn parse(text: &str, path: &Path, profile: &ToothProfile) -> Result<Self> {
        let err = |line: usize, message: String| FlankError::Parse {
            file: path.to_path_buf(),
            line,
            message,
        };
        let g = &profile.geometry;
        let (r_lo, r_hi) = (g.form_radius, g.tip_radius);
        let d_max = MAX_DEVIATION_MODULES * normal_module(profile);
        let mut header_line = 0;
        let mut last_line = 0;
        // [right, left]
        let mut sides: [Vec<Point>; 2] = [Vec::new(), Vec::new()];
        for (i, raw) in text.split('\n').enumerate() {
            let line = i + 1;
            let s = raw.trim_start_matches('\u{feff}').trim();
            if s.is_empty() || s.starts_with('#') {
                continue;
            }
            last_line = line;
            let fields: Vec<&str> = s.split(',').map(str::trim).collect();
            if header_line == 0 {
                if fields != ["x_mm", "y_mm"] {
                    return Err(err(
                        line,
                        format!("expected the header `x_mm,y_mm`, found `{}`", clip(s)),
                    ));
                }
                header_line = line;
                continue;
            }
            if fields.len() != 2 {
                return Err(err(
                    line,
                    format!(
                        "expected two fields `x_mm,y_mm`, found {} in `{}`",
                        fields.len(),
                        clip(s)
                    ),
                ));
            }
            let mut v = [0.0; 2];
            for (k, f) in fields.iter().enumerate() {
                let name = ["x_mm", "y_mm"][k];
                v[k] = f
                    .parse::<f64>()
                    .map_err(|_| err(line, format!("{name}: unparsable number `{}`", clip(f))))?;
                if !v[k].is_finite() {
                    return Err(err(line, format!("{name} = {}: not a finite number", v[k])));
                }
            }
            let [x, y] = v;
            if x == 0.0 {
                return Err(err(
                    line,
                    format!("point ({x}, {y}) lies on the tooth centre line x = 0: it belongs to neither flank"),
                ));
            }
            let r = x.hypot(y);
            if r < r_lo - RADIUS_TOLERANCE || r > r_hi + RADIUS_TOLERANCE {
                return Err(err(
                    line,
                    format!(
                        "point ({x}, {y}) at radius {r:.6} mm is outside the involute's radius range [r_F, r_a] = [{r_lo:.6}, {r_hi:.6}] mm (tolerance {RADIUS_TOLERANCE} mm)"
                    ),
                ));
            }
            let (flank, side) = if x > 0.0 {
                (Flank::Right, 0)
            } else {
                (Flank::Left, 1)
            };
            let (u, d) = project_onto_involute(profile, flank, [x, y]);
            if !(d.abs() <= d_max) {
                return Err(err(
                    line,
                    format!(
                        "point ({x}, {y}) is {d:.6} mm from the nominal {flank:?} involute, more than {MAX_DEVIATION_MODULES}·m_n = {d_max:.4} mm: not a point of this flank (check the frame: tooth symmetric about +y, tip up, mm)"
                    ),
                ));
            }
            sides[side].push(Point { line, x, y, u, d });
        }
        if header_line == 0 {
            return Err(err(
                last_line.max(1),
                "empty file: the header `x_mm,y_mm` is missing".to_string(),
            ));
        }
        let rb = g.base_radius;
        let mut flanks: [Option<MeasuredFlank>; 2] = [None, None];
        for (k, pts) in sides.iter().enumerate() {
            if pts.is_empty() {
                continue;
            }
            let name = ["right", "left"][k];
            // drop exact repeats of the previous point
            let mut kept: Vec<&Point> = Vec::with_capacity(pts.len());
            for p in pts {
                if let Some(q) = kept.last() {
                    if (p.x - q.x).abs() <= DUPLICATE_TOL && (p.y - q.y).abs() <= DUPLICATE_TOL {
                        continue;
                    }
                }
                kept.push(p);
            }
            // monotone in u along the file
            let mut dir = 0.0;
            for w in kept.windows(2) {
                let step = w[1].u - w[0].u;
                let ok = rb * step.abs() > MIN_STEP && (dir == 0.0 || step * dir > 0.0);
                if !ok {
                    return Err(err(
                        w[1].line,
                        format!(
                            "{name} flank: roll angles not monotone along the file: u = {:.9} rad (radius {:.6} mm) after u = {:.9} rad (radius {:.6} mm) at line {}; the points of a flank must follow each other along the profile",
                            w[1].u,
                            w[1].x.hypot(w[1].y),
                            w[0].u,
                            w[0].x.hypot(w[0].y),
                            w[0].line
                        ),
                    ));
                }
                dir = step.signum();
            }
            if kept.len() < MIN_POINTS {
                return Err(err(
                    kept[kept.len() - 1].line,
                    format!(
                        "{name} flank: {} distinct point(s), at least {MIN_POINTS} are needed",
                        kept.len()
                    ),
                ));
            }
            if dir < 0.0 {
                kept.reverse();
            }
            flanks[k] = Some(MeasuredFlank::new(
                kept.iter().map(|p| p.u).collect(),
                kept.iter().map(|p| p.d).collect(),
                false,
            ));
        }
        let mut notes = Vec::new();
        let [right, left] = flanks;
        let (right, left) = match (right, left) {
            (Some(r), Some(l)) => (r, l),
            (Some(r), None) => {
                notes.push(format!(
                    "measured profile {}: only the right flank is given; it is mirrored to the left flank",
                    path.display()
                ));
                let mut l = r.clone();
                l.mirrored = true;
                (r, l)
            }
            (None, Some(l)) => {
                notes.push(format!(
                    "measured profile {}: only the left flank is given; it is mirrored to the right flank",
                    path.display()
                ));
                let mut r = l.clone();
                r.mirrored = true;
                (r, l)
            }
            (None, None) => {
                return Err(err(
                    last_line.max(header_line),
                    format!("no data points: at least {MIN_POINTS} on one flank are needed"),
                ))
            }
        };
        Ok(MeasuredProfile {
            path: path.to_path_buf(),
            right,
            left,
            cos_base_helix: g.base_helix_angle.cos(),
            notes,
        })
    }

    /// The file it was read from.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The measured data of one flank.
    pub fn flank(&self, flank: Flank) -> &MeasuredFlank {
        match flank {
            Flank::Right => &self.right,
            Flank::Left => &self.left,
        }
    }

    /// Transverse deviation d and dd/du at roll angle u (end values held outside the range).
    pub fn deviation(&self, flank: Flank, u: f64) -> (f64, f64) {
        self.flank(flank).eval(u)
    }

    /// Material removed normal to the flank, −d(u)·cos β_b (mm).
    pub fn offset(&self, flank: Flank, u: f64) -> f64 {
        -self.deviation(flank, u).0 * self.cos_base_helix
    }

    /// Notes from reading (a mirrored flank).
    pub fn notes(&self) -> &[String] {
        &self.notes
    }

    /// Warnings, one per flank whose measured range does not cover [u_lo, u_hi]
    /// (e.g. the active profile) to within 1 µm of roll length, naming both
    /// ranges in roll angle and diameter.
    pub fn coverage_warnings(&self, u_lo: f64, u_hi: f64, base_radius: f64) -> Vec<String> {
        let dia = |u: f64| 2.0 * base_radius * (1.0 + u * u).sqrt();
        let tol = 1e-3 / base_radius;
        let mut out = Vec::new();
        for (f, name) in [(Flank::Right, "right"), (Flank::Left, "left")] {
            let m = self.flank(f);
            let (a, b) = m.range();
            if a > u_lo + tol || b < u_hi - tol {
                out.push(format!(
                    "measured profile {}: the {name} flank{} is measured over roll angles [{a:.6}, {b:.6}] rad (diameters [{:.4}, {:.4}] mm), which does not cover [{u_lo:.6}, {u_hi:.6}] rad (diameters [{:.4}, {:.4}] mm); outside the measured range the end deviation is held",
                    self.path.display(),
                    if m.mirrored { " (mirrored)" } else { "" },
                    dia(a),
                    dia(b),
                    dia(u_lo),
                    dia(u_hi)
                ));
            }
        }
        out
    }
}

/// At most 60 characters of a field or line, for messages.
fn clip(s: &str) -> String {
    let mut out: String = s.chars().take(60).collect();
    if s.chars().count() > 60 {
        out.push('…');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::super::micro::test_gears::{gear, papers};
    use super::super::micro::{FlankModification, MicroGeometry, Relief, ReliefShape};
    use super::super::rack::Segment;
    use super::*;

    /// Transverse point of `flank` at roll angle u, displaced by d along the outward normal.
    fn displaced(tp: &ToothProfile, flank: Flank, u: f64, d: f64) -> [f64; 2] {
        let q = tp.point(flank, Segment::Involute(u));
        [q.p[0] + d * q.n[0], q.p[1] + d * q.n[1]]
    }

    fn csv(points: &[[f64; 2]]) -> String {
        let mut s = String::from("# test\nx_mm,y_mm\n");
        for p in points {
            s.push_str(&format!("{:.10},{:.10}\n", p[0], p[1]));
        }
        s
    }

    /// Roll angles evenly spaced in roll length over [u0, u1].
    fn roll_grid(tp: &ToothProfile, u0: f64, u1: f64, n: usize) -> Vec<f64> {
        let _ = tp;
        (0..=n)
            .map(|i| u0 + (u1 - u0) * i as f64 / n as f64)
            .collect()
    }

    #[test]
    fn projection_is_exact() {
        for (scene, which) in [
            ("seed002-spur", 0),
            ("seed002-spur", 1),
            ("seed004-helical", 0),
        ] {
            let (tp, _) = gear(scene, which);
            let mut worst: f64 = 0.0;
            for f in [Flank::Left, Flank::Right] {
                for u in roll_grid(&tp, tp.u_form, tp.u_tip, 20) {
                    for d in [-0.05, -0.003, 0.0, 0.002, 0.04] {
                        let p = displaced(&tp, f, u, d);
                        let (u2, d2) = project_onto_involute(&tp, f, p);
                        worst = worst.max((u2 - u).abs()).max((d2 - d).abs());
                        // the projection equation (p − P(u))·P′(u) = 0
                        let q = tp.point(f, Segment::Involute(u2)).p;
                        let t = tp.tangent(f, Segment::Involute(u2));
                        let res = ((p[0] - q[0]) * t[0] + (p[1] - q[1]) * t[1]) / t[0].hypot(t[1]);
                        assert!(res.abs() < 1e-12, "{res}");
                    }
                }
            }
            assert!(worst < 1e-12, "{scene}: {worst:e}");
        }
    }

    #[test]
    fn pchip_properties() {
        let u: Vec<f64> = (0..8)
            .map(|i| 0.1 + 0.03 * i as f64 + 0.002 * (i * i) as f64)
            .collect();
        // exact on straight data
        let lin = MeasuredFlank::new(u.clone(), u.iter().map(|x| 2.0 * x - 0.3).collect(), false);
        for i in 0..=100 {
            let x = u[0] + (u[7] - u[0]) * i as f64 / 100.0;
            let (v, dv) = lin.eval(x);
            assert!(
                (v - (2.0 * x - 0.3)).abs() < 1e-14 && (dv - 2.0).abs() < 1e-12,
                "x = {x}: {v} {dv}"
            );
        }
        // monotone data (a step): no overshoot, values within the data bounds
        let step = MeasuredFlank::new(
            u.clone(),
            vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 2.0, 2.0],
            false,
        );
        let mut prev = -1.0;
        for i in 0..=700 {
            let x = u[0] + (u[7] - u[0]) * i as f64 / 700.0;
            let (v, _) = step.eval(x);
            assert!(v >= prev - 1e-15 && (-1e-15..=2.0 + 1e-15).contains(&v));
            prev = v;
        }
        // interpolates, C¹ at the knots, holds the ends
        let y: Vec<f64> = u.iter().map(|x| (7.0 * x).sin()).collect();
        let s = MeasuredFlank::new(u.clone(), y.clone(), false);
        for k in 0..8 {
            assert!((s.eval(u[k]).0 - y[k]).abs() < 1e-15);
        }
        for k in 1..7 {
            let (a, b) = (s.eval(u[k] - 1e-9).1, s.eval(u[k] + 1e-9).1);
            assert!((a - b).abs() < 1e-6, "{a} {b}");
        }
        assert_eq!(s.eval(u[0] - 1.0), (y[0], 0.0));
        assert_eq!(s.eval(u[7] + 1.0), (y[7], 0.0));
        assert_eq!(s.eval(f64::NAN).0, y[0]);
    }

    /// Writes papers/seed002-spur/measured_profile_example.csv (run on purpose:
    /// `cargo test --release --lib geometry::measured -- --ignored write_seed002_example`).
    #[test]
    #[ignore]
    fn write_seed002_example() {
        let (tp, _) = gear("seed002-spur", 0);
        let rb = tp.geometry.base_radius;
        let (ca, la) = (0.005, 1.0);
        let (s0, s1) = (rb * tp.u_form, rb * tp.u_tip);
        let sa = s1 - la;
        let mut s_list = Vec::new();
        let n0 = ((sa - s0) / 0.2).ceil() as usize;
        for i in 0..n0 {
            s_list.push(s0 + (sa - s0) * i as f64 / n0 as f64);
        }
        for i in 0..=40 {
            s_list.push(sa + la * i as f64 / 40.0);
        }
        let mut text = String::from(
            "# SYNTHETIC example, not measured data.\n\
             # Seed 002 pinion (z = 13, m_n = 3.8 mm, alpha_n = 20 deg, x = 0.30, d_a = 58.7 mm):\n\
             # the nominal involute of the right flank with a 5 um linear tip relief over a roll\n\
             # length of 1.0 mm from the tip, transverse section of tooth 0 (symmetric about +y,\n\
             # tip up), from the form circle to the tip. Only the right flank: it is mirrored.\n\
             # Format: src/geometry/measured.rs. Written by the ignored test\n\
             # geometry::measured::tests::write_seed002_example.\n\
             x_mm,y_mm\n",
        );
        for s in s_list {
            let u = s / rb;
            let x = ((s - sa) / la).max(0.0);
            let p = displaced(&tp, Flank::Right, u, -ca * x);
            text.push_str(&format!("{:.8},{:.8}\n", p[0], p[1]));
        }
        std::fs::write(
            papers().join("seed002-spur/measured_profile_example.csv"),
            text,
        )
        .unwrap();
    }

    /// The example CSV (nominal involute with a 5 µm linear tip relief over 1 mm)
    /// gives the analytic tip-relief offset.
    #[test]
    fn seed002_example_round_trip() {
        let path = papers().join("seed002-spur/measured_profile_example.csv");
        let (tp, u_sap) = gear("seed002-spur", 0);
        let measured = MicroGeometry {
            measured_profile: Some(path.clone()),
            ..Default::default()
        };
        let analytic = MicroGeometry {
            tip_relief: Some(Relief {
                amount: 0.005,
                length: 1.0,
                shape: ReliefShape::Linear,
            }),
            ..Default::default()
        };
        let fm = FlankModification::new(&measured, &tp, u_sap, tp.face_width).unwrap();
        let fa = FlankModification::new(&analytic, &tp, u_sap, tp.face_width).unwrap();
        // only the right flank is given: mirrored, and it covers the active profile
        assert_eq!(fm.warnings().len(), 1, "{:?}", fm.warnings());
        assert!(fm.warnings()[0].contains("mirrored"));
        let m = fm.measured().unwrap();
        assert!(m.flank(Flank::Left).mirrored && !m.flank(Flank::Right).mirrored);
        let mut worst: f64 = 0.0;
        for f in [Flank::Left, Flank::Right] {
            for i in 0..=4000 {
                let u = tp.u_form - 0.2 + (tp.u_tip - tp.u_form + 0.2) * i as f64 / 4000.0;
                for z in [0.0, 5.0] {
                    worst = worst.max((fm.offset(f, u, z) - fa.offset(f, u, z)).abs());
                }
            }
            // the raw data, too
            let mf = m.flank(f);
            for (u, d) in mf.u.iter().zip(&mf.deviation) {
                let want = -fa.offset(f, *u, 0.0);
                if *u >= u_sap {
                    assert!((d - want).abs() < 1e-8, "{d} vs {want}");
                }
            }
        }
        eprintln!(
            "seed 002 example: max |measured − analytic| = {:.4} µm",
            worst * 1e3
        );
        assert!(worst < 5e-5, "{worst:e} mm");
    }

    #[test]
    fn both_flanks_and_reversed_order() {
        let (tp, u_sap) = gear("seed004-helical", 1);
        let us = roll_grid(&tp, tp.u_form, tp.u_tip, 30);
        let dev_r = |u: f64| 0.004 * (u - tp.u_form) / (tp.u_tip - tp.u_form);
        let dev_l = |_u: f64| -0.002;
        let mut pts: Vec<[f64; 2]> = us
            .iter()
            .map(|&u| displaced(&tp, Flank::Right, u, dev_r(u)))
            .collect();
        // left flank tip to root, with a repeated point
        let mut left: Vec<[f64; 2]> = us
            .iter()
            .rev()
            .map(|&u| displaced(&tp, Flank::Left, u, dev_l(u)))
            .collect();
        left.insert(5, left[4]);
        pts.extend(left);
        let m = MeasuredProfile::parse(&csv(&pts), Path::new("both.csv"), &tp).unwrap();
        assert!(m.notes().is_empty());
        assert_eq!(m.flank(Flank::Left).u.len(), 31);
        assert!(m
            .coverage_warnings(u_sap, tp.u_tip, tp.geometry.base_radius)
            .is_empty());
        let cb = tp.geometry.base_helix_angle.cos();
        for &u in &us {
            assert!((m.deviation(Flank::Right, u).0 - dev_r(u)).abs() < 1e-9);
            assert!((m.deviation(Flank::Left, u).0 + 0.002).abs() < 1e-9);
            assert!((m.offset(Flank::Left, u) - 0.002 * cb).abs() < 1e-9);
        }
        // left only: mirrored to the right
        let left_only: Vec<[f64; 2]> = us
            .iter()
            .map(|&u| displaced(&tp, Flank::Left, u, dev_r(u)))
            .collect();
        let m = MeasuredProfile::parse(&csv(&left_only), Path::new("l.csv"), &tp).unwrap();
        assert!(m.notes()[0].contains("only the left flank"));
        assert!((m.deviation(Flank::Right, us[7]).0 - dev_r(us[7])).abs() < 1e-9);
    }

    #[test]
    fn partial_range_holds_and_warns() {
        let (tp, u_sap) = gear("seed002-spur", 1);
        let (u0, u1) = (u_sap + 0.05, tp.u_tip - 0.05);
        let us = roll_grid(&tp, u0, u1, 10);
        let pts: Vec<[f64; 2]> = us
            .iter()
            .map(|&u| displaced(&tp, Flank::Right, u, 0.001 * u))
            .collect();
        let path = std::env::temp_dir().join(format!("flank-measured-{}.csv", std::process::id()));
        std::fs::write(&path, csv(&pts)).unwrap();
        let micro = MicroGeometry {
            measured_profile: Some(path.clone()),
            ..Default::default()
        };
        let fm = FlankModification::new(&micro, &tp, u_sap, tp.face_width).unwrap();
        let _ = std::fs::remove_file(&path);
        let w = fm.warnings().join("\n");
        assert!(
            w.contains("does not cover") && w.contains(&format!("{u0:.6}")),
            "{w}"
        );
        assert!(w.contains(&format!("{u1:.6}")), "{w}");
        for f in [Flank::Left, Flank::Right] {
            assert!((fm.offset(f, tp.u_tip, 0.0) + 0.001 * u1).abs() < 1e-9);
            assert!((fm.offset(f, u_sap, 0.0) + 0.001 * u0).abs() < 1e-9);
        }
    }

    /// A helical gear's transverse deviation d gives a flank whose transverse
    /// section deviates by d (the normal offset is d cos β_b).
    #[test]
    fn helical_transverse_deviation_round_trip() {
        use super::super::flank::FlankSurface;
        let (tp, u_sap) = gear("seed004-helical", 0);
        let d = -0.02;
        let us = roll_grid(&tp, tp.u_form, tp.u_tip, 12);
        let pts: Vec<[f64; 2]> = us
            .iter()
            .map(|&u| displaced(&tp, Flank::Right, u, d))
            .collect();
        let path =
            std::env::temp_dir().join(format!("flank-measured-h-{}.csv", std::process::id()));
        std::fs::write(&path, csv(&pts)).unwrap();
        let micro = MicroGeometry {
            measured_profile: Some(path.clone()),
            ..Default::default()
        };
        let fm = FlankModification::new(&micro, &tp, u_sap, tp.face_width).unwrap();
        let _ = std::fs::remove_file(&path);
        let fs = FlankSurface::new(tp.clone(), Flank::Right, 1, Some(fm)).unwrap();
        for i in 0..=10 {
            let u = u_sap + (tp.u_tip - u_sap) * i as f64 / 10.0;
            let p = fs.point(u, 90.0);
            // turn the point back to the z = 0 section along the helix
            let (s, c) = (-tp.twist_rate * p[2]).sin_cos();
            let q = [c * p[0] - s * p[1], s * p[0] + c * p[1]];
            let (_, dev) = project_onto_involute(&tp, Flank::Right, q);
            // the CSV carries 10 decimals (5e-11 mm)
            assert!((dev - d).abs() < 1e-10, "{dev} vs {d}");
        }
    }

    fn parse_err(text: &str) -> (usize, String) {
        let (tp, _) = gear("seed002-spur", 0);
        match MeasuredProfile::parse(text, Path::new("cmm/p.csv"), &tp) {
            Err(e @ FlankError::Parse { .. }) => {
                let s = e.to_string();
                let FlankError::Parse { line, file, .. } = e else {
                    unreachable!()
                };
                assert_eq!(file, Path::new("cmm/p.csv"));
                assert!(s.starts_with(&format!("cmm/p.csv:{line}: ")), "{s}");
                (line, s)
            }
            Err(e) => panic!("not a parse error: {e}"),
            Ok(_) => panic!("accepted: {text}"),
        }
    }

    fn example() -> String {
        std::fs::read_to_string(papers().join("seed002-spur/measured_profile_example.csv")).unwrap()
    }

    /// The line number (1-based) of the first line of `text` containing `pat`.
    fn line_of(text: &str, pat: &str) -> usize {
        text.lines().position(|l| l.contains(pat)).unwrap() + 1
    }

    #[test]
    fn every_csv_error_has_file_and_line() {
        let ex = example();
        let header = line_of(&ex, "x_mm,y_mm");
        let data: Vec<&str> = ex.lines().skip(header).collect();
        let with_line = |k: usize, new: &str| -> String {
            let mut l: Vec<&str> = ex.lines().collect();
            l[header + k] = new;
            l.join("\n")
        };
        // wrong header
        let (line, m) = parse_err(&ex.replace("x_mm,y_mm", "x,y"));
        assert_eq!(line, header);
        assert!(m.contains("header"), "{m}");
        // unparsable number
        let t = with_line(3, "12.5,abc");
        let (line, m) = parse_err(&t);
        assert_eq!(line, header + 4);
        assert!(m.contains("unparsable") && m.contains("abc"), "{m}");
        // wrong field count, non-finite
        let (line, m) = parse_err(&with_line(2, "1,2,3"));
        assert_eq!((line, m.contains("two fields")), (header + 3, true), "{m}");
        let (line, m) = parse_err(&with_line(2, "nan,25"));
        assert_eq!((line, m.contains("finite")), (header + 3, true), "{m}");
        // on the centre line
        let (line, m) = parse_err(&with_line(6, "0,27.0"));
        assert_eq!((line, m.contains("centre line")), (header + 7, true), "{m}");
        // outside the radius range (in the fillet, beyond the tip)
        let (line, m) = parse_err(&with_line(1, "1.0,21.5"));
        assert_eq!(
            (line, m.contains("radius range")),
            (header + 2, true),
            "{m}"
        );
        let (line, m) = parse_err(&with_line(1, "3.0,29.5"));
        assert_eq!(
            (line, m.contains("radius range")),
            (header + 2, true),
            "{m}"
        );
        // far from the involute (inside the radius range, 1.5 mm off)
        // far from the involute: turned by 0.06 rad about the axis (≈ 1.5 mm at r ≈ 26 mm)
        let f: Vec<f64> = data[60].split(',').map(|v| v.parse().unwrap()).collect();
        let (s, c) = 0.06f64.sin_cos();
        let far = format!("{},{}", c * f[0] - s * f[1], s * f[0] + c * f[1]);
        let (line, m) = parse_err(&with_line(60, &far));
        assert_eq!((line, m.contains("m_n")), (header + 61, true), "{m}");
        // not monotone: swap two points
        let mut l: Vec<&str> = ex.lines().collect();
        l.swap(header + 20, header + 21);
        let (line, m) = parse_err(&l.join("\n"));
        assert_eq!((line, m.contains("monotone")), (header + 22, true), "{m}");
        // a repeated point later in the file (not consecutive)
        let mut l: Vec<&str> = ex.lines().collect();
        l.insert(header + 30, data[3]);
        let (line, m) = parse_err(&l.join("\n"));
        assert_eq!((line, m.contains("monotone")), (header + 31, true), "{m}");
        // fewer than 4 points on a side: 3 left points beside a full right flank
        let mut t = ex.clone();
        for k in [2, 12, 22] {
            let f: Vec<f64> = data[k].split(',').map(|v| v.parse().unwrap()).collect();
            t.push_str(&format!("{},{}\n", -f[0], f[1]));
        }
        let (line, m) = parse_err(&t);
        assert_eq!(line, t.lines().count());
        assert!(m.contains("left flank") && m.contains("at least 4"), "{m}");
        // repeats do not count
        let t = format!("x_mm,y_mm\n{0}\n{0}\n{0}\n{0}\n{1}\n", data[0], data[1]);
        let (line, m) = parse_err(&t);
        assert_eq!((line, m.contains("2 distinct")), (6, true), "{m}");
        // no points, no header
        let (line, m) = parse_err("# nothing\nx_mm,y_mm\n\n");
        assert_eq!((line, m.contains("no data")), (2, true), "{m}");
        let (line, m) = parse_err("# only a comment\n");
        assert_eq!((line, m.contains("header")), (1, true), "{m}");
        // an I/O error names the path
        let (tp, _) = gear("seed002-spur", 0);
        let e = MeasuredProfile::read(Path::new("/nonexistent/p.csv"), &tp).unwrap_err();
        assert!(matches!(e, FlankError::Io { .. }) && e.to_string().contains("/nonexistent/p.csv"));
        // CRLF line ends and a BOM are fine
        let crlf = format!("\u{feff}{}", ex.replace('\n', "\r\n"));
        assert!(MeasuredProfile::parse(&crlf, Path::new("x.csv"), &tp).is_ok());
    }

    /// Deterministic mutations of the example: each parses or is a Parse error, none panics.
    #[test]
    fn mutated_csvs_never_panic() {
        let (tp, u_sap) = gear("seed002-spur", 0);
        let base: Vec<char> = example().chars().collect();
        let alphabet: Vec<char> = ",.-+0123456789eE\n\r #xyinfa_mé\u{0}".chars().collect();
        let mut state: u64 = 0x2545_f491_4f6c_dd1d;
        let mut next = |n: usize| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state % n as u64) as usize
        };
        let (mut ok, mut errs) = (0, 0);
        for _ in 0..3000 {
            let mut t = base.clone();
            for _ in 0..1 + next(4) {
                let at = next(t.len());
                match next(5) {
                    0 => {
                        t.remove(at);
                    }
                    1 => t.insert(at, alphabet[next(alphabet.len())]),
                    2 => {
                        // drop a stretch (lines vanish, fields merge)
                        let n = next(80).min(t.len() - at);
                        t.drain(at..at + n);
                    }
                    3 => {
                        // duplicate a stretch
                        let n = next(60).min(t.len() - at);
                        let s: Vec<char> = t[at..at + n].to_vec();
                        let to = next(t.len());
                        for (i, c) in s.into_iter().enumerate() {
                            t.insert(to + i, c);
                        }
                    }
                    _ => t[at] = alphabet[next(alphabet.len())],
                }
                if t.is_empty() {
                    t.push('\n');
                }
            }
            let text: String = t.into_iter().collect();
            match MeasuredProfile::parse(&text, Path::new("m.csv"), &tp) {
                Ok(m) => {
                    ok += 1;
                    for f in [Flank::Left, Flank::Right] {
                        for u in [u_sap, tp.u_tip, -1.0, f64::NAN] {
                            let _ = m.deviation(f, u);
                        }
                    }
                }
                Err(FlankError::Parse { .. }) => errs += 1,
                Err(e) => panic!("{e}"),
            }
        }
        eprintln!("mutated CSVs: {ok} accepted, {errs} rejected");
        assert!(ok > 0 && errs > 0);
    }
}
