//! Local contact deformation: the near field the FE compliance cannot see.
//!
//! A load spread over a contact cell of half-width c across the contact
//! line makes the FE surface displace by what the mesh resolves: scales
//! below the element size h are missing, and a point load (c → 0) would
//! give a mesh-dependent, unbounded displacement (DESIGN.md, "local contact
//! deformation"). flank therefore evaluates the FE compliance with cells no
//! narrower than the mesh resolves, c_FE = max(a, κ h), and adds the
//! difference of two elastic half-space solutions,
//!
//! ```text
//! F = F_FE(c_FE) + H,   H_ij = B_ij(a) − B_ij(c_FE)
//! ```
//!
//! on a half-space with the pair's contact modulus
//! 1/E* = (1 − ν₁²)/E₁ + (1 − ν₂²)/E₂, a the Hertz half-width of the local
//! load. B_ij(c_FE) is what the FE part is: the normal approach averaged
//! over cell i from a unit load spread uniformly over cell j, both of
//! half-width c_FE across the line and their own length along it.
//! B_ij(a) is what the contact condition needs: the approach on the
//! candidate line through cell i (where the separation is measured) under
//! Hertz's semi-elliptic pressure of half-width a across cell j
//! ([`elliptic_centreline_influence`]). The far fields of the two are the
//! same (a resultant at the same place), so H only acts where the cells are
//! close: the near field is counted once, by the half-space, and the bulk
//! once, by the FE. Until 2026-11-27 B_ij(a) was also a uniform cell
//! average, which `verification/ltca_near_field` shows 5–10 % too stiff in
//! the local approach against Hertz's elliptical contact (now within 2 %).
//!
//! H enters F lumped on the diagonal, H_ii ← Σ_j H_ij (over the points of
//! the same contact line): the row sum is the correction for a load that is
//! uniform over H's reach (a few cell widths), the way loads vary along a
//! contact line, and a positive diagonal keeps F positive definite. The full
//! H, a difference of two kernels, is not positive semi-definite: with
//! seed 004's long cells (4.75 mm along, 1.9 mm across) it made F
//! indefinite.
//!
//! The half-space influence of a uniformly loaded rectangle is Love's
//! (1929) closed form (Johnson, Contact Mechanics, 1985, eq. 3.25):
//! with I(X, Y) = X ln(Y + r) + Y ln(X + r), r = √(X² + Y²),
//! u_z(x, y) = (1/(π E*)) p [I(x + c, y + l) − I(x − c, y + l)
//! − I(x + c, y − l) + I(x − c, y − l)] for pressure p on |ξ| ≤ c, |η| ≤ l.
//!
//! Hertz line contact (Johnson eq. 4.43): a = √(4 P′ R / (π E*)),
//! p_max = √(P′ E* / (π R)) with P′ the load per unit length and R the
//! equivalent radius.

use std::f64::consts::PI;

use crate::compliance::interpolation::gauss_legendre_rule_of;
// Hertz's line contact lives with the contact layer (FE contact uses it too)
pub use crate::contact::hertz_line::{contact_modulus, hertz_line};

/// ∬ dX dY / √(X² + Y²): the antiderivative with ∂²I/∂X∂Y = 1/r.
fn antiderivative(x: f64, y: f64) -> f64 {
    // √(x² + y²), not hypot: arguments in mm neither overflow nor
    // underflow, and glibc's hypot took a fifth of H's time (perf)
    let r = (x * x + y * y).sqrt();
    // ln(Y + r) loses everything for Y < 0, |X| ≪ |Y|: use X²/(r − Y)
    let ln_plus = |a: f64, b: f64| -> f64 {
        if a >= 0.0 {
            (a + r).ln()
        } else {
            (b * b / (r - a)).ln()
        }
    };
    let tx = if x == 0.0 { 0.0 } else { x * ln_plus(y, x) };
    let ty = if y == 0.0 { 0.0 } else { y * ln_plus(x, y) };
    tx + ty
}

/// ∬ over the rectangle |ξ| ≤ c, |η| ≤ l of 1/|(x, y) − (ξ, η)|: the normal
/// displacement at (x, y) times π E*/p of a uniform pressure p.
pub fn rectangle_influence(x: f64, y: f64, c: f64, l: f64) -> f64 {
    antiderivative(x + c, y + l) - antiderivative(x - c, y + l) - antiderivative(x + c, y - l)
        + antiderivative(x - c, y - l)
}

/// A(t, Y) − A(−t, Y) of [`antiderivative`], t > 0: the two halves of a
/// strip seen from its centre line, 2t ln(Y + r) + 2Y ln((r + t)/|Y|) with
/// r = √(t² + Y²). Two logarithms instead of four, and no cancellation:
/// ln((r + t)/|Y|) = ln_1p((t + t²/(r + |Y|))/|Y|), and for Y < 0
/// ln(Y + r) = ln(t²/(r − Y)).
fn centreline_antiderivative(t: f64, y: f64) -> f64 {
    let r = (t * t + y * y).sqrt(); // not hypot: see antiderivative
    let ln_y_plus_r = if y >= 0.0 {
        (y + r).ln()
    } else {
        (t * t / (r - y)).ln()
    };
    let along = if y == 0.0 {
        0.0
    } else {
        let a = y.abs();
        2.0 * y * ((t + t * t / (r + a)) / a).ln_1p()
    };
    2.0 * t * ln_y_plus_r + along
}

/// [`rectangle_influence`] at x = 0 (on the strip's centre line across),
/// half-width `c` > 0: half the logarithms of the general form, which the
/// near field evaluates for every strip of every pair of points on a line.
pub fn centreline_rectangle_influence(y: f64, c: f64, l: f64) -> f64 {
    centreline_antiderivative(c, y + l) - centreline_antiderivative(c, y - l)
}

/// ∫ dY of [`centreline_antiderivative`] (a second antiderivative of the
/// rectangle influence along the line): B(t, Y) = 2tY ln(Y + r) − t r +
/// Y² asinh(t/|Y|), r = √(t² + Y²); ∂B/∂Y = 2t ln(Y + r) + 2Y asinh(t/|Y|).
/// The logarithms in the cancellation-free forms of
/// [`centreline_antiderivative`].
fn centreline_second_antiderivative(t: f64, y: f64) -> f64 {
    let r = (t * t + y * y).sqrt(); // not hypot: see antiderivative
    let ln_y_plus_r = if y >= 0.0 {
        (y + r).ln()
    } else {
        (t * t / (r - y)).ln()
    };
    let along = if y == 0.0 {
        0.0
    } else {
        let a = y.abs();
        y * y * ((t + t * t / (r + a)) / a).ln_1p()
    };
    2.0 * t * y * ln_y_plus_r - t * r + along
}

/// The mean of [`centreline_rectangle_influence`]`(y, c, l)` over
/// y ∈ [y₀ − m, y₀ + m] (m > 0: a cell of half-length m along the line whose
/// centre is y₀ from the strip's), in closed form through
/// `centreline_second_antiderivative`:
/// [B(y₀+m+l) − B(y₀+m−l) − B(y₀−m+l) + B(y₀−m−l)] / (2m). Exact where a
/// Gauss rule along the cell is not: the integrand has y ln|y| kinks at the
/// strip's ends (4 Gauss points: 0.2 % off for a cell on itself, 1 % for
/// its neighbour). The second difference costs ≈ (y₀/l)² ε of round-off
/// (3e-13 relative at y₀ = 13 l against 50-digit quadrature).
pub fn centreline_strip_mean(y0: f64, m: f64, c: f64, l: f64) -> f64 {
    let b = |y: f64| centreline_second_antiderivative(c, y);
    (b(y0 + m + l) - b(y0 + m - l) - b(y0 - m + l) + b(y0 - m - l)) / (2.0 * m)
}

/// A contact cell on the plane of contact: centre (across, along) in mm,
/// half-widths across (c) and along (l) the line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cell {
    pub across: f64,
    pub along: f64,
    pub c: f64,
    pub l: f64,
}

/// Normal approach (mm) at cell `i`, averaged over it, from a unit force
/// (N) spread uniformly over cell `j`, on the half-space pair with contact
/// modulus `e_star` (MPa). The average uses `samples`² Gauss points.
pub fn cell_influence(i: &Cell, j: &Cell, e_star: f64, samples: usize) -> f64 {
    let rule = gauss_legendre_rule_of(samples);
    let g = &rule[..];
    let p = 1.0 / (4.0 * j.c * j.l);
    let mut sum = 0.0;
    for &(s, ws) in g {
        for &(t, wt) in g {
            let x = i.across + s * i.c - j.across;
            let y = i.along + t * i.l - j.along;
            sum += 0.25 * ws * wt * rectangle_influence(x, y, j.c, j.l);
        }
    }
    p * sum / (PI * e_star)
}

/// Normal approach (mm) along the centre line of cell `i` (averaged along
/// its length) from a unit force (N) on cell `j` with Hertz's
/// semi-elliptic pressure p₀ √(1 − ξ²/c²) across it (half-width c = `j.c`)
/// and uniform along it: what the contact condition on the candidate line
/// needs, since the separation is measured on that line.
///
/// The ellipse is a stack of uniform strips: √(1 − ξ²/c²) = ∫ over t from |ξ|
/// to c of t/(c √(c² − t²)) dt, so with t = c sin θ the pressure is
/// ∫₀^{π/2} sin θ · 1{|ξ| ≤ c sin θ} dθ, and the influence is the θ-integral
/// (Gauss–Legendre, `samples` points) of uniform strips of half-width
/// c sin θ. On the strip's centre line (i.across = j.across, the LTCA's
/// case) each strip's average along cell i is in closed form
/// ([`centreline_strip_mean`]); off it, [`rectangle_influence`] at
/// `samples` Gauss points along. The force of the ellipse at unit p₀ is
/// (π/2) c · 2l. Checked against Hertz's elliptical contact in
/// `verification/ltca_near_field`.
pub fn elliptic_centreline_influence(i: &Cell, j: &Cell, e_star: f64, samples: usize) -> f64 {
    let rule = gauss_legendre_rule_of(samples);
    let g = &rule[..];
    let quarter = 0.25 * PI;
    let x = i.across - j.across;
    let y0 = i.along - j.along;
    let mut sum = 0.0;
    for &(s, ws) in g {
        let theta = quarter * (s + 1.0);
        let (sin, _) = theta.sin_cos();
        let t = j.c * sin;
        let strip = if x == 0.0 {
            centreline_strip_mean(y0, i.l, t, j.l)
        } else {
            g.iter()
                .map(|&(a, wa)| 0.5 * wa * rectangle_influence(x, y0 + a * i.l, t, j.l))
                .sum()
        };
        sum += ws * quarter * sin * strip;
    }
    sum / (PI * j.c * j.l) / (PI * e_star)
}

/// The half-space correction H of the module docs for the points of one
/// position, lumped on the diagonal: built once per position from the FE
/// cells, then [`NearField::diagonal`] for each set of Hertz half-widths.
///
/// H_ij = B^Hertz_ij(a) − B^FE_ij(c_FE): B^Hertz the approach on the centre
/// line of cell i under Hertz's semi-elliptic pressure of half-width a_j
/// across cell j ([`elliptic_centreline_influence`]); B^FE that of the FE
/// cells, averaged over cell i under a uniform load on cell j
/// ([`cell_influence`]), which is what the FE part of F is. Their far
/// fields agree (a resultant at the same place), so H acts only between
/// nearby points of one line (within ten cell sizes).
pub struct NearField {
    pairs: Vec<(usize, usize)>,
    fe: Vec<f64>,
    cells: Vec<Cell>,
    e_star: f64,
}

impl NearField {
    /// `cells`: the FE cells (half-widths c_FE) of the points, on the plane
    /// of their line; `line`: the line of each point.
    pub fn new(cells: &[Cell], line: &[usize], e_star: f64) -> Self {
        use rayon::prelude::*;
        let n = cells.len();
        let mut pairs = Vec::new();
        for i in 0..n {
            for j in i..n {
                let (ci, cj) = (&cells[i], &cells[j]);
                let reach = 10.0 * ci.c.max(cj.c).max(ci.l.max(cj.l));
                if line[i] == line[j] && (ci.along - cj.along).abs() <= reach {
                    pairs.push((i, j));
                }
            }
        }
        let fe = pairs
            .par_iter()
            .map(|&(i, j)| cell_influence(&cells[i], &cells[j], e_star, 2))
            .collect();
        NearField {
            pairs,
            fe,
            cells: cells.to_vec(),
            e_star,
        }
    }

    /// Σ_j H_ij for every point i, with Hertz half-widths `half` (≤ the FE
    /// cell's: see the model). Lumped because the full H, a difference of
    /// two kernels, is not positive semi-definite. Points marked `sharp`
    /// (a tip corner: an edge, no Hertz pressure) take no part in H.
    pub fn diagonal(&self, half: &[f64], sharp: &[bool]) -> Vec<f64> {
        use rayon::prelude::*;
        let narrow = |i: usize| Cell {
            c: half[i].max(1e-6),
            ..self.cells[i]
        };
        let h: Vec<(f64, f64)> = self
            .pairs
            .par_iter()
            .zip(&self.fe)
            .map(|(&(i, j), &fe)| {
                if sharp[i] || sharp[j] {
                    return (0.0, 0.0);
                }
                let ij = elliptic_centreline_influence(&narrow(i), &narrow(j), self.e_star, 4);
                let ji = if i == j {
                    ij
                } else {
                    elliptic_centreline_influence(&narrow(j), &narrow(i), self.e_star, 4)
                };
                (ij - fe, ji - fe)
            })
            .collect();
        let mut d = vec![0.0; self.cells.len()];
        for (&(i, j), &(ij, ji)) in self.pairs.iter().zip(&h) {
            d[i] += ij;
            if i != j {
                d[j] += ji;
            }
        }
        d
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The centre of a uniformly loaded square: u = 4 ln(1 + √2) c p/(π E*)·…
    /// (Johnson eq. 3.26: ū at the centre of a square of side 2c is
    /// (4/π) ln(1 + √2) · 2c p / E* · … with 1/E* the contact modulus).
    #[test]
    fn square_centre_matches_closed_form() {
        let c = 0.7;
        let v = rectangle_influence(0.0, 0.0, c, c);
        let exact = 8.0 * c * (1.0 + 2f64.sqrt()).ln();
        assert!((v - exact).abs() < 1e-12 * exact, "{v} vs {exact}");
    }

    /// Far from the cell the influence is that of a point force: 1/(π E* d).
    #[test]
    fn far_field_is_a_point_force() {
        let i = Cell {
            across: 0.0,
            along: 40.0,
            c: 0.1,
            l: 0.3,
        };
        let j = Cell {
            across: 0.0,
            along: 0.0,
            c: 0.2,
            l: 0.3,
        };
        let b = cell_influence(&i, &j, 1.0, 4);
        let point = 1.0 / (PI * 40.0);
        assert!((b - point).abs() < 1e-4 * point, "{b} vs {point}");
        // and the correction between two widths vanishes there
        let j2 = Cell { c: 0.05, ..j };
        let i2 = Cell { c: 0.05, ..i };
        let h = cell_influence(&i2, &j2, 1.0, 4) - b;
        assert!(h.abs() < 1e-5 * point, "{h}");
    }

    /// A long strip (l ≫ c): the centre displacement difference between
    /// half-widths a and c is (2/(π E*)) P′ ln(c/a) (2D plane strain).
    #[test]
    fn long_strip_difference_is_logarithmic() {
        let (a, c, l) = (0.2, 0.5, 200.0);
        let ua = rectangle_influence(0.0, 0.0, a, l) / (4.0 * a * l);
        let uc = rectangle_influence(0.0, 0.0, c, l) / (4.0 * c * l);
        // per unit force; P′ = 1/(2 l)
        let expect = 2.0 / PI * (1.0 / (2.0 * l)) * (c / a).ln() * PI;
        assert!(
            ((ua - uc) - expect).abs() < 1e-3 * expect,
            "{} vs {expect}",
            ua - uc
        );
    }

    /// The centre-line form equals the general one where the general one
    /// is accurate, and stays accurate where the general one cancels (a
    /// strip far narrower than its distance: the point-force limit).
    #[test]
    fn centreline_form_matches_the_general_form() {
        let mut worst: f64 = 0.0;
        for &c in &[1e-3, 0.05, 0.3, 2.0] {
            for &l in &[0.1, 0.5, 3.0] {
                for &y in &[
                    -40.0f64, -3.0, -0.5, -0.1, 0.0, 0.02, 0.1, 0.49, 0.5, 0.51, 2.0, 40.0,
                ] {
                    if c / (y.abs() + l) < 1e-2 {
                        continue;
                    }
                    let g = rectangle_influence(0.0, y, c, l);
                    let f = centreline_rectangle_influence(y, c, l);
                    worst = worst.max((f - g).abs() / g.abs());
                }
            }
        }
        // the general form itself cancels to 3.4e-12 at c = 2, l = 0.1,
        // y = −40 (against 50-digit arithmetic, below)
        assert!(worst < 1e-11, "worst relative difference {worst:e}");
        // against the general form evaluated in 50-digit arithmetic (mpmath)
        for (y, c, l, exact) in [
            (-40.0, 2.0, 0.1, 0.019_991_717_590_687_19),
            (40.0, 2.0, 0.1, 0.019_991_717_590_687_19),
            (0.5, 0.05, 0.5, 0.468_908_767_037_587_9),
            (-3.0, 1e-3, 0.5, 0.000_672_944_460_181_202_1),
            (0.0, 0.3, 3.0, 4.795_876_487_148_054),
        ] {
            let f = centreline_rectangle_influence(y, c, l);
            assert!(
                (f - exact).abs() < 2e-13 * exact,
                "({y}, {c}, {l}): {f:e} vs {exact:e}"
            );
        }
        // narrow strip far away: the influence per unit pressure tends to
        // 2c·2l/d (a point force), with relative correction O((l/d)²)
        let (c, l, d) = (1e-7, 0.5, 30.0);
        let f = centreline_rectangle_influence(d, c, l);
        let point = 4.0 * c * l / d;
        assert!((f - point).abs() < 1e-3 * point, "{f:e} vs {point:e}");
        // exact in the 2D sense for the same strip: ∫ 2c/|y − η| dη
        let exact = 2.0 * c * ((d + l) / (d - l)).ln();
        assert!((f - exact).abs() < 1e-9 * exact, "{f:e} vs {exact:e}");
    }

    /// The closed-form mean along a cell against 50-digit quadrature
    /// (mpmath, tanh-sinh split at the strip's ends) of the centre-line
    /// influence: on itself, neighbours, a longer cell over a kink, far
    /// away, a wide strip.
    #[test]
    fn strip_mean_matches_high_precision_quadrature() {
        for (y0, m, c, l, exact) in [
            (0.0, 0.25, 0.05, 0.25, 0.608_979_912_747_592_6),
            (0.5, 0.25, 0.03, 0.25, 0.081_404_652_562_883_82),
            (0.3, 0.4, 0.02, 0.2, 0.144_208_439_869_710_38),
            (3.0, 0.25, 0.05, 0.25, 0.016_743_903_934_803_694),
            (-1.1, 0.2, 0.1, 0.3, 0.113_172_331_172_419_32),
            (0.2, 0.1, 2.0, 0.5, 5.993_732_191_489_96),
            (-4.0, 0.3, 1e-3, 0.3, 0.000_301_135_245_580_720_16),
        ] {
            let f = centreline_strip_mean(y0, m, c, l);
            assert!(
                (f - exact).abs() < 1e-12 * exact,
                "({y0}, {m}, {c}, {l}): {f:e} vs {exact:e}, {:e}",
                (f - exact) / exact
            );
        }
        // the old 4-point Gauss rule along the cell where the integrand is
        // smooth (far from the strip's ends): the same to 1e-10
        let g = gauss_legendre_rule_of(4);
        let (y0, m, c, l) = (3.0, 0.25, 0.05, 0.25);
        let gauss: f64 = g
            .iter()
            .map(|&(a, w)| 0.5 * w * centreline_rectangle_influence(y0 + a * m, c, l))
            .sum();
        let f = centreline_strip_mean(y0, m, c, l);
        assert!((f - gauss).abs() < 1e-10 * f, "{f:e} vs {gauss:e}");
    }

    #[test]
    fn antiderivative_is_finite_on_axes() {
        for (x, y) in [
            (0.0, -1.0),
            (-1.0, 0.0),
            (0.0, 0.0),
            (-1e-9, -3.0),
            (2.0, -1e12),
        ] {
            assert!(antiderivative(x, y).is_finite(), "({x}, {y})");
        }
    }
}
