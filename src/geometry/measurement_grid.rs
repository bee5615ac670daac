//! Measurement grids: a flank as the grid of points and normals that gear
//! measuring machines probe (the "topography" grid, e.g. 9 × 5), and a grid of
//! measured normal deviations read back as a deviation field over the flank
//! ([`GridTopography`], used through [`super::deviation::DeviatedSurface`]).
//!
//! # The grid
//!
//! Over the active flank of one tooth: `face_points` columns across the face
//! (j = 0 at the start of the v range: the toe of a bevel gear, z = 0 of a
//! cylindrical gear) and `profile_points` rows along the profile (i = 0 at
//! the root side). The columns are evenly spaced in v between the face ends
//! inset by `face_inset` × (face extent) at each end; in each column the rows
//! are evenly spaced in u between u_form(v) and u_tip(v), inset by
//! `profile_inset` × (u_tip − u_form) at each end. The flank parameters are
//! the ones measuring machines space their grids in: roll angle (∝ roll
//! length) × axial position for a cylindrical gear, the axial-section
//! ("rotated projection") coordinates for a bevel gear. Margins of 5–10 % at
//! each border are the practice of bevel gear measurement (the probe stays off
//! edges and chamfers); the default is 10 %.
//!
//! # File (CSV)
//!
//! ```text
//! # comment lines start with '#'
//! face,profile,u,v,x_mm,y_mm,z_mm,nx,ny,nz,axial_mm,radius_mm,deviation_um
//! 0,0,…
//! ```
//!
//! Coordinates are the gear's own frame (mm): gear axis = z, tooth 0 of the
//! flank as the surface gives it; (nx, ny, nz) the unit outward normal of the
//! flank (out of the tooth material); `axial_mm` = z and `radius_mm` =
//! √(x² + y²), the rotated projection. `deviation_um` is the measured normal
//! deviation in µm, **positive = material added** (plus metal), the sign
//! measuring machines report; an exported grid carries 0.
//!
//! Reading needs only `face`, `profile`, `u`, `v` and `deviation_um` (other
//! columns may be absent; when present and a flank is given they are checked
//! against it, so that a grid of another gear is refused). Every
//! (face, profile) pair must appear once; all rows of one column must share
//! its v, and all columns the same relative spacing in u.
//!
//! # Interpolation
//!
//! The field between grid points is a tensor product of 1-D cubic Hermite
//! interpolants with three-point (Bessel) slopes: C¹, local, and exact for
//! deviations quadratic in (u, v) on a grid whose u limits are linear in v
//! (crowning, bias and slope are reproduced exactly). Outside the grid the
//! field is continued linearly from its edge (C¹). Written here rather than
//! taken from a crate: a non-uniform 1-D Hermite with Bessel slopes is a few
//! lines, and the gradient the deviated surface needs falls out of it.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::deviation::DeviationField;
use super::surface::ToothSurface;
use super::vec3::{norm, sub, V3};
use crate::error::{FlankError, Result};

/// Size and margins of a measurement grid (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridSpec {
    /// Columns across the face (≥ 2).
    pub face_points: usize,
    /// Rows along the profile (≥ 2).
    pub profile_points: usize,
    /// Inset at each face end, as a fraction of the face extent in v.
    pub face_inset: f64,
    /// Inset at tip and form, as a fraction of u_tip − u_form.
    pub profile_inset: f64,
}

impl Default for GridSpec {
    /// The common 9 × 5 grid (9 across the face, 5 along the profile), 10 %
    /// margins.
    fn default() -> Self {
        GridSpec {
            face_points: 9,
            profile_points: 5,
            face_inset: 0.1,
            profile_inset: 0.1,
        }
    }
}

impl GridSpec {
    fn validate(&self) -> Result<()> {
        if self.face_points < 2 || self.profile_points < 2 {
            return Err(FlankError::Model(format!(
                "measurement grid: {} × {} points; at least 2 × 2 are needed",
                self.face_points, self.profile_points
            )));
        }
        for (name, x) in [
            ("face_inset", self.face_inset),
            ("profile_inset", self.profile_inset),
        ] {
            if !(0.0..0.5).contains(&x) {
                return Err(FlankError::Model(format!(
                    "measurement grid: {name} = {x} must be in [0, 0.5)"
                )));
            }
        }
        Ok(())
    }
}

/// One probed point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridPoint {
    /// Column index (across the face) and row index (along the profile).
    pub face: usize,
    pub profile: usize,
    pub u: f64,
    pub v: f64,
    /// Position and unit outward normal (gear frame, mm); `None` when read
    /// from a file without them.
    pub point: Option<V3>,
    pub normal: Option<V3>,
    /// Normal deviation (mm), positive = material added.
    pub deviation: f64,
}

/// A grid over one flank, column-major (all rows of column 0 first).
#[derive(Clone, Debug, PartialEq)]
pub struct MeasurementGrid {
    pub face_points: usize,
    pub profile_points: usize,
    pub points: Vec<GridPoint>,
}

/// The grid of `spec` over the active flank of `surface` (module docs).
pub fn measurement_grid(surface: &dyn ToothSurface, spec: &GridSpec) -> Result<MeasurementGrid> {
    spec.validate()?;
    let (v0, v1) = surface.v_range();
    let dv = v1 - v0;
    let (va, vb) = (v0 + spec.face_inset * dv, v1 - spec.face_inset * dv);
    let mut points = Vec::with_capacity(spec.face_points * spec.profile_points);
    for j in 0..spec.face_points {
        let v = va + (vb - va) * j as f64 / (spec.face_points - 1) as f64;
        let (uf, ut) = (surface.u_form(v), surface.u_tip(v));
        if !(ut > uf) {
            return Err(FlankError::Model(format!(
                "measurement grid: no active flank at v = {v} (u_form {uf} ≥ u_tip {ut}: pointed tooth?)"
            )));
        }
        let du = ut - uf;
        let (ua, ub) = (uf + spec.profile_inset * du, ut - spec.profile_inset * du);
        for i in 0..spec.profile_points {
            let u = ua + (ub - ua) * i as f64 / (spec.profile_points - 1) as f64;
            let (p, n, _, _) = surface.evaluate(u, v);
            if !p.iter().chain(n.iter()).all(|x| x.is_finite()) {
                return Err(FlankError::Model(format!(
                    "measurement grid: the flank is not defined at (u, v) = ({u}, {v})"
                )));
            }
            points.push(GridPoint {
                face: j,
                profile: i,
                u,
                v,
                point: Some(p),
                normal: Some(n),
                deviation: 0.0,
            });
        }
    }
    Ok(MeasurementGrid {
        face_points: spec.face_points,
        profile_points: spec.profile_points,
        points,
    })
}

const COLUMNS: [&str; 13] = [
    "face",
    "profile",
    "u",
    "v",
    "x_mm",
    "y_mm",
    "z_mm",
    "nx",
    "ny",
    "nz",
    "axial_mm",
    "radius_mm",
    "deviation_um",
];

impl MeasurementGrid {
    /// Point (column `face`, row `profile`).
    pub fn at(&self, face: usize, profile: usize) -> &GridPoint {
        &self.points[face * self.profile_points + profile]
    }

    /// The grid as CSV (module docs); `description` goes into the first
    /// comment line (gear, flank, tooth).
    pub fn to_csv(&self, description: &str) -> String {
        let mut s = String::new();
        let _ = writeln!(s, "# flank measurement grid: {description}");
        let _ = writeln!(
            s,
            "# {} columns across the face (face = 0 at the start of v) × {} rows along the profile (profile = 0 at the root side)",
            self.face_points, self.profile_points
        );
        let _ = writeln!(
            s,
            "# gear frame (mm): axis = z; n = unit outward normal; axial_mm, radius_mm = rotated projection; deviation_um > 0 = material added"
        );
        // Positions and normals are written when every point has them (a grid
        // read from a file without them is written without them).
        let geometric = self
            .points
            .iter()
            .all(|g| g.point.is_some() && g.normal.is_some());
        if geometric {
            let _ = writeln!(s, "{}", COLUMNS.join(","));
        } else {
            let _ = writeln!(s, "face,profile,u,v,deviation_um");
        }
        for g in &self.points {
            let _ = write!(s, "{},{},{:.15e},{:.15e},", g.face, g.profile, g.u, g.v);
            if let (true, Some(p), Some(n)) = (geometric, g.point, g.normal) {
                let _ = write!(
                    s,
                    "{:.9},{:.9},{:.9},{:.12},{:.12},{:.12},{:.9},{:.9},",
                    p[0],
                    p[1],
                    p[2],
                    n[0],
                    n[1],
                    n[2],
                    p[2],
                    p[0].hypot(p[1])
                );
            }
            let _ = writeln!(s, "{:.6}", g.deviation * 1e3);
        }
        s
    }

    /// Write [`Self::to_csv`] to `path`.
    pub fn write(&self, path: &Path, description: &str) -> Result<()> {
        crate::atomic_file::write(path, self.to_csv(description))
    }

    /// Read a grid file (module docs).
    pub fn read(path: &Path) -> Result<Self> {
        let text = crate::text_file::read_utf8(path)?;
        Self::parse(&text, path)
    }

    /// Parse grid CSV `text`; `path` names it in errors.
    pub fn parse(text: &str, path: &Path) -> Result<Self> {
        let err = |line: usize, message: String| FlankError::Parse {
            file: PathBuf::from(path),
            line,
            message,
        };
        let mut lines = text
            .lines()
            .enumerate()
            .map(|(k, l)| (k + 1, l.trim()))
            .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
        let (hline, header) = lines
            .next()
            .ok_or_else(|| err(1, "empty grid file: no header line".into()))?;
        let names: Vec<&str> = header.split(',').map(str::trim).collect();
        for (k, n) in names.iter().enumerate() {
            if !COLUMNS.contains(n) {
                return Err(err(
                    hline,
                    format!("unknown column '{n}' (known: {})", COLUMNS.join(", ")),
                ));
            }
            if names[..k].contains(n) {
                return Err(err(hline, format!("column '{n}' given twice")));
            }
        }
        let col = |n: &str| names.iter().position(|m| *m == n);
        let required = ["face", "profile", "u", "v", "deviation_um"];
        for n in required {
            if col(n).is_none() {
                return Err(err(hline, format!("missing column '{n}'")));
            }
        }
        let idx = |n: &str| col(n).unwrap();
        let xyz = [col("x_mm"), col("y_mm"), col("z_mm")];
        let nxyz = [col("nx"), col("ny"), col("nz")];
        if xyz.iter().any(Option::is_some) && xyz.iter().any(Option::is_none) {
            return Err(err(hline, "x_mm, y_mm, z_mm must be given together".into()));
        }
        if nxyz.iter().any(Option::is_some) && nxyz.iter().any(Option::is_none) {
            return Err(err(hline, "nx, ny, nz must be given together".into()));
        }
        let mut rows: Vec<(usize, GridPoint)> = Vec::new();
        for (ln, line) in lines {
            let cells: Vec<&str> = line.split(',').map(str::trim).collect();
            if cells.len() != names.len() {
                return Err(err(
                    ln,
                    format!(
                        "{} values, the header has {} columns",
                        cells.len(),
                        names.len()
                    ),
                ));
            }
            let num = |k: usize| -> Result<f64> {
                let x: f64 = cells[k].parse().map_err(|_| {
                    err(ln, format!("{}: '{}' is not a number", names[k], cells[k]))
                })?;
                if !x.is_finite() {
                    return Err(err(
                        ln,
                        format!("{}: '{}' is not finite", names[k], cells[k]),
                    ));
                }
                Ok(x)
            };
            let index = |k: usize| -> Result<usize> {
                cells[k].parse().map_err(|_| {
                    err(
                        ln,
                        format!("{}: '{}' is not a non-negative integer", names[k], cells[k]),
                    )
                })
            };
            let vec3 = |c: [Option<usize>; 3]| -> Result<Option<V3>> {
                match c {
                    [Some(a), Some(b), Some(d)] => Ok(Some([num(a)?, num(b)?, num(d)?])),
                    _ => Ok(None),
                }
            };
            let normal = vec3(nxyz)?;
            if let Some(n) = normal {
                if (norm(n) - 1.0).abs() > 1e-6 {
                    return Err(err(
                        ln,
                        format!("normal ({}, {}, {}) is not unit", n[0], n[1], n[2]),
                    ));
                }
            }
            rows.push((
                ln,
                GridPoint {
                    face: index(idx("face"))?,
                    profile: index(idx("profile"))?,
                    u: num(idx("u"))?,
                    v: num(idx("v"))?,
                    point: vec3(xyz)?,
                    normal,
                    deviation: num(idx("deviation_um"))? * 1e-3,
                },
            ));
        }
        let last = rows.last().map(|r| r.0).unwrap_or(hline);
        let nf = rows
            .iter()
            .map(|r| r.1.face.saturating_add(1))
            .max()
            .unwrap_or(0);
        let np = rows
            .iter()
            .map(|r| r.1.profile.saturating_add(1))
            .max()
            .unwrap_or(0);
        if nf < 2 || np < 2 {
            return Err(err(
                last,
                format!("a grid needs at least 2 × 2 points; this one spans {nf} × {np}"),
            ));
        }
        // the indices come from the file: a point is looked up by (face,
        // profile) first, so that a stray huge index is a missing point
        // named in the message, not an nf × np allocation
        let mut by_index: std::collections::HashMap<(usize, usize), (usize, GridPoint)> =
            std::collections::HashMap::with_capacity(rows.len());
        for (ln, g) in rows {
            if let Some((first, _)) = by_index.get(&(g.face, g.profile)) {
                return Err(err(
                    ln,
                    format!(
                        "point (face {}, profile {}) given twice (first on line {first})",
                        g.face, g.profile
                    ),
                ));
            }
            by_index.insert((g.face, g.profile), (ln, g));
        }
        if nf.checked_mul(np) != Some(by_index.len()) {
            // at most len + 1 slots to visit before a missing one
            let k = (0..)
                .find(|k| !by_index.contains_key(&(k / np, k % np)))
                .unwrap_or(0);
            return Err(err(
                last,
                format!(
                    "point (face {}, profile {}) is missing: the grid spans {nf} × {np}",
                    k / np,
                    k % np
                ),
            ));
        }
        let mut slots: Vec<Option<(usize, GridPoint)>> = vec![None; nf * np];
        for ((face, profile), r) in by_index {
            slots[face * np + profile] = Some(r);
        }
        let slots: Vec<(usize, GridPoint)> = slots.into_iter().map(Option::unwrap).collect();
        // Tensor structure: one v per column, increasing; u increasing in each
        // column with the same relative spacing.
        let rel = |j: usize, i: usize| {
            let (a, b) = (slots[j * np].1.u, slots[j * np + np - 1].1.u);
            (slots[j * np + i].1.u - a) / (b - a)
        };
        for j in 0..nf {
            let col = &slots[j * np..(j + 1) * np];
            let v = col[0].1.v;
            for (ln, g) in col {
                if (g.v - v).abs() > 1e-9 * (1.0 + v.abs()) {
                    return Err(err(
                        *ln,
                        format!(
                            "v = {} differs from v = {v} of column {j}'s first point",
                            g.v
                        ),
                    ));
                }
            }
            for w in col.windows(2) {
                if !(w[1].1.u > w[0].1.u) {
                    return Err(err(
                        w[1].0,
                        format!("u must increase along the profile within column {j}"),
                    ));
                }
            }
            if j > 0 {
                if !(v > slots[(j - 1) * np].1.v) {
                    return Err(err(
                        col[0].0,
                        format!("v must increase with the column index (column {j})"),
                    ));
                }
                for i in 0..np {
                    if (rel(j, i) - rel(0, i)).abs() > 1e-6 {
                        return Err(err(
                            col[i].0,
                            format!(
                                "column {j} spaces its profile points unlike column 0 (relative position {:.6} vs {:.6}): not a tensor grid",
                                rel(j, i),
                                rel(0, i)
                            ),
                        ));
                    }
                }
            }
        }
        Ok(MeasurementGrid {
            face_points: nf,
            profile_points: np,
            points: slots.into_iter().map(|s| s.1).collect(),
        })
    }

    /// Check that the grid's positions and normals (where given) lie on
    /// `surface` at their (u, v): position within `tolerance` mm, normal
    /// within 1e-3 rad. Refuses a grid measured on another gear or flank.
    pub fn check_against(&self, surface: &dyn ToothSurface, tolerance: f64) -> Result<()> {
        for g in &self.points {
            let (p, n, _, _) = surface.evaluate(g.u, g.v);
            if let Some(q) = g.point {
                let d = norm(sub(q, p));
                if !(d <= tolerance) {
                    return Err(FlankError::Model(format!(
                        "measurement grid point (face {}, profile {}) is {d:.3e} mm from the flank at its (u, v) (tolerance {tolerance:.1e} mm): the grid belongs to another gear or flank",
                        g.face, g.profile
                    )));
                }
            }
            if let Some(m) = g.normal {
                let d = norm(sub(m, n));
                if !(d <= 1e-3) {
                    return Err(FlankError::Model(format!(
                        "measurement grid point (face {}, profile {}): its normal differs from the flank's by {d:.3e}: the grid belongs to another gear or flank",
                        g.face, g.profile
                    )));
                }
            }
        }
        Ok(())
    }

    /// The deviations as a field over the flank (module docs, interpolation).
    pub fn topography(&self) -> GridTopography {
        let (nf, np) = (self.face_points, self.profile_points);
        let v: Vec<f64> = (0..nf).map(|j| self.at(j, 0).v).collect();
        let u_lo: Vec<f64> = (0..nf).map(|j| self.at(j, 0).u).collect();
        let u_hi: Vec<f64> = (0..nf).map(|j| self.at(j, np - 1).u).collect();
        let xi: Vec<f64> = (0..np)
            .map(|i| (self.at(0, i).u - u_lo[0]) / (u_hi[0] - u_lo[0]))
            .collect();
        let values = (0..np)
            .map(|i| (0..nf).map(|j| self.at(j, i).deviation).collect())
            .collect();
        GridTopography {
            v,
            u_lo,
            u_hi,
            xi,
            values,
        }
    }
}

/// 1-D cubic Hermite interpolation on increasing knots `x` with Bessel
/// (three-point) slopes; linear continuation outside. Returns (f, f′).
fn hermite(x: &[f64], y: &[f64], t: f64) -> (f64, f64) {
    let n = x.len();
    let slope = |k: usize| -> f64 {
        if n == 2 {
            return (y[1] - y[0]) / (x[1] - x[0]);
        }
        // Derivative at x[k] of the parabola through three neighbours.
        let c = k.clamp(1, n - 2);
        let (x0, x1, x2) = (x[c - 1], x[c], x[c + 1]);
        let (y0, y1, y2) = (y[c - 1], y[c], y[c + 1]);
        let t = x[k];
        y0 * ((t - x1) + (t - x2)) / ((x0 - x1) * (x0 - x2))
            + y1 * ((t - x0) + (t - x2)) / ((x1 - x0) * (x1 - x2))
            + y2 * ((t - x0) + (t - x1)) / ((x2 - x0) * (x2 - x1))
    };
    if t <= x[0] {
        let s = slope(0);
        return (y[0] + s * (t - x[0]), s);
    }
    if t >= x[n - 1] {
        let s = slope(n - 1);
        return (y[n - 1] + s * (t - x[n - 1]), s);
    }
    let k = x.partition_point(|&xk| xk <= t).clamp(1, n - 1) - 1;
    let h = x[k + 1] - x[k];
    let s = (t - x[k]) / h;
    let (m0, m1) = (slope(k) * h, slope(k + 1) * h);
    let (s2, s3) = (s * s, s * s * s);
    let f = (2.0 * s3 - 3.0 * s2 + 1.0) * y[k]
        + (s3 - 2.0 * s2 + s) * m0
        + (-2.0 * s3 + 3.0 * s2) * y[k + 1]
        + (s3 - s2) * m1;
    let df = ((6.0 * s2 - 6.0 * s) * y[k]
        + (3.0 * s2 - 4.0 * s + 1.0) * m0
        + (-6.0 * s2 + 6.0 * s) * y[k + 1]
        + (3.0 * s2 - 2.0 * s) * m1)
        / h;
    (f, df)
}

/// Measured normal deviations interpolated over a flank (module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct GridTopography {
    /// v of each column.
    v: Vec<f64>,
    /// First and last row's u of each column.
    u_lo: Vec<f64>,
    u_hi: Vec<f64>,
    /// Relative profile position of each row, 0 … 1.
    xi: Vec<f64>,
    /// values[row][column] (mm).
    values: Vec<Vec<f64>>,
}

impl GridTopography {
    /// δ, ∂δ/∂u, ∂δ/∂v at (u, v).
    fn eval(&self, u: f64, v: f64) -> (f64, f64, f64) {
        let (lo, dlo) = hermite(&self.v, &self.u_lo, v);
        let (hi, dhi) = hermite(&self.v, &self.u_hi, v);
        let w = hi - lo;
        let xi = (u - lo) / w;
        let dxi_du = 1.0 / w;
        let dxi_dv = -(dlo * w + (u - lo) * (dhi - dlo)) / (w * w);
        let rows: Vec<(f64, f64)> = self.values.iter().map(|r| hermite(&self.v, r, v)).collect();
        let g: Vec<f64> = rows.iter().map(|r| r.0).collect();
        let dg: Vec<f64> = rows.iter().map(|r| r.1).collect();
        let (f, df_dxi) = hermite(&self.xi, &g, xi);
        // ∂/∂v at fixed ξ: interpolate the row derivatives in ξ.
        let (df_dv_xi, _) = hermite(&self.xi, &dg, xi);
        (f, df_dxi * dxi_du, df_dv_xi + df_dxi * dxi_dv)
    }
}

impl DeviationField for GridTopography {
    fn deviation(&self, u: f64, v: f64) -> f64 {
        self.eval(u, v).0
    }
    fn gradient(&self, u: f64, v: f64) -> (f64, f64) {
        let (_, a, b) = self.eval(u, v);
        (a, b)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::deviation::tests::Torus;
    use crate::geometry::deviation::DeviatedSurface;
    use crate::geometry::vec3::dot;
    use std::sync::Arc;

    fn quadratic(u: f64, v: f64) -> f64 {
        1e-3 * (4.0 - 6.0 * u + 9.0 * u * u + 3.0 * v - 7.0 * v * v + 5.0 * u * v)
    }

    #[test]
    fn hermite_is_exact_for_quadratics_and_c1() {
        let x = [0.0, 0.3, 1.1, 1.5, 2.8];
        let f = |t: f64| 2.0 - 3.0 * t + 1.5 * t * t;
        let y: Vec<f64> = x.iter().map(|&t| f(t)).collect();
        for k in 0..=60 {
            let t = -0.2 + 3.2 * k as f64 / 60.0;
            let (a, da) = hermite(&x, &y, t);
            if (0.0..=2.8).contains(&t) {
                assert!((a - f(t)).abs() < 1e-13, "t {t}: {a} vs {}", f(t));
                assert!((da - (-3.0 + 3.0 * t)).abs() < 1e-12);
            }
        }
        // Continuity of the slope at an inner knot.
        let y2 = [0.0, 1.0, -1.0, 2.0, 0.5];
        let (_, l) = hermite(&x, &y2, 1.1 - 1e-12);
        let (_, r) = hermite(&x, &y2, 1.1 + 1e-12);
        assert!((l - r).abs() < 1e-9);
    }

    #[test]
    fn round_trip_of_a_quadratic_deviation() {
        let grid = measurement_grid(&Torus, &GridSpec::default()).unwrap();
        assert_eq!(grid.points.len(), 45);
        let mut measured = grid.clone();
        for g in &mut measured.points {
            g.deviation = quadratic(g.u, g.v);
        }
        let path = Path::new("grid.csv");
        let read = MeasurementGrid::parse(&measured.to_csv("torus test"), path).unwrap();
        read.check_against(&Torus, 1e-6).unwrap();
        let field = Arc::new(read.topography());
        let s = DeviatedSurface::new(Arc::new(Torus), field.clone());
        // At the grid points the modified surface is off by the deviation
        // (µm print precision of the file: 1e-6 µm).
        for g in &grid.points {
            let p = s.point(g.u, g.v);
            let d = dot(sub(p, g.point.unwrap()), g.normal.unwrap());
            assert!(
                (d - quadratic(g.u, g.v)).abs() < 1e-8,
                "{d} vs {}",
                quadratic(g.u, g.v)
            );
        }
        // Between them the quadratic is reproduced (the torus grid's u limits
        // are linear in v).
        for &(u, v) in &[(0.05, 0.01), (-0.2, 0.25), (0.3, -0.2)] {
            let (d, du, dv) = field.eval(u, v);
            assert!((d - quadratic(u, v)).abs() < 1e-8);
            let h = 1e-6;
            let fu = (quadratic(u + h, v) - quadratic(u - h, v)) / (2.0 * h);
            let fv = (quadratic(u, v + h) - quadratic(u, v - h)) / (2.0 * h);
            assert!(
                (du - fu).abs() < 1e-7 && (dv - fv).abs() < 1e-7,
                "{du} {fu} {dv} {fv}"
            );
        }
    }

    #[test]
    fn bad_grids_name_the_line() {
        let grid = measurement_grid(&Torus, &GridSpec::default()).unwrap();
        let csv = grid.to_csv("t");
        let p = Path::new("m.csv");
        let e = |t: &str| MeasurementGrid::parse(t, p).unwrap_err().to_string();
        // Drop one data line.
        let lines: Vec<&str> = csv.lines().collect();
        let missing: String = lines
            .iter()
            .enumerate()
            .filter(|(k, _)| *k != 10)
            .map(|(_, l)| format!("{l}\n"))
            .collect();
        assert!(e(&missing).contains("is missing"), "{}", e(&missing));
        let bad = csv.replacen(",0.000000\n", ",abc\n", 1);
        let msg = e(&bad);
        assert!(
            msg.starts_with("m.csv:5:") && msg.contains("deviation_um"),
            "{msg}"
        );
        // A huge face index (found by tests/fuzz_parsers.rs: the reader
        // allocated nf × np slots and aborted) is a missing point.
        let huge = "face,profile,u,v,deviation_um\n0,0,0,0,0\n0,1,1,0,0\n1,0,0,1,0\n\
                    99999999999999999,1,1,1,0\n";
        let msg = e(huge);
        assert!(
            msg.contains("point (face 1, profile 1) is missing"),
            "{msg}"
        );
        let max = format!(
            "face,profile,u,v,deviation_um\n0,0,0,0,0\n{},1,1,1,0\n",
            usize::MAX
        );
        assert!(e(&max).contains("is missing"), "{}", e(&max));
        assert!(e("face,profile,u\n").contains("missing column 'v'"));
        assert!(e("face,profile,u,v,deviation_um,foo\n").contains("unknown column 'foo'"));
        assert!(e("").contains("empty"));
        // A grid of another surface is refused.
        let mut other = grid.clone();
        for g in &mut other.points {
            g.point = g.point.map(|p| [p[0] + 0.01, p[1], p[2]]);
        }
        let o = MeasurementGrid::parse(&other.to_csv("x"), p).unwrap();
        assert!(o.check_against(&Torus, 1e-4).is_err());
        assert!(measurement_grid(
            &Torus,
            &GridSpec {
                face_points: 1,
                ..GridSpec::default()
            }
        )
        .is_err());
    }
}
