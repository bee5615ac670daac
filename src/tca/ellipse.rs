//! The instantaneous contact ellipse of a point contact at an elastic
//! approach δ, two ways.
//!
//! * **From the curvatures** (Litvin & Fuentes §9.5: the relative
//!   curvature tensor gives a = √(2δ/λ_min), b = √(2δ/λ_max)):
//!   [`crate::geometry::contact_curvature`], re-exported here; λ_min ≈ 0
//!   is line contact, flagged.
//! * **By the numerical search of seed `000_…`** (steps 1–6): the plane Q
//!   through the common normal u₃ and a tangent direction d(α) cuts each
//!   flank in a plane curve; along Q the points of both curves at the same
//!   tangent offset s are found (a 2 × 2 Newton on the flank parameters),
//!   and the offsets s₊ > 0, s₋ < 0 at which their separation along u₃ is
//!   δ are the boundary points c(α) = s± d; α turns through 180°. The major
//!   axis is max |c|, its direction the α of the maximum (refined by a
//!   parabola through the three best directions). Near an edge the body
//!   ends where its flank ends: a boundary point never lies beyond the
//!   flank's active region (the tip land, toe and heel faces fall away
//!   steeply from the flank, so the separation grows past δ at the edge —
//!   an approximation of the face cone by a cliff, stated in the case's
//!   README).

use crate::geometry::contact_curvature::basis;
pub use crate::geometry::contact_curvature::{
    curvature_ellipse, relative_curvature, ContactEllipse, FlankAtContact,
};
use crate::geometry::surface::on_active_flank;
use crate::geometry::vec3::{add, cross, dot, norm, sub, unit, V3};

/// Bound of the Newton steps of one section point and of the boundary
/// search along one direction.
const SEARCH_STEPS: usize = 60;

/// Golden-section steps refining the major and minor directions (the
/// bracket of two scan steps shrinks by 0.618 each: 14 steps, 1e-3 of it).
const GOLDEN_STEPS: usize = 14;

/// The point of flank `f` in the plane through `m` spanned by `d` and `u3`
/// at tangent offset `s` along d: (height along u₃, flank parameters), or
/// `None` when the Newton iteration leaves the surface or fails.
fn section_point(
    f: &FlankAtContact,
    m: V3,
    d: V3,
    u3: V3,
    s: f64,
    start: [f64; 2],
) -> Option<(f64, [f64; 2])> {
    let w = cross(u3, d);
    let [mut u, mut v] = start;
    for _ in 0..SEARCH_STEPS {
        let (p, _, pu, pv) = f.surface.evaluate(u, v);
        let x = sub(f.frame.place(p), m);
        let (gu, gv) = (f.frame.rotate(pu), f.frame.rotate(pv));
        let r = [dot(x, d) - s, dot(x, w)];
        let j = [[dot(gu, d), dot(gv, d)], [dot(gu, w), dot(gv, w)]];
        let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
        if !(det.abs() > 0.0) {
            return None;
        }
        let du = -(j[1][1] * r[0] - j[0][1] * r[1]) / det;
        let dv = -(j[0][0] * r[1] - j[1][0] * r[0]) / det;
        u += du;
        v += dv;
        if !(u.is_finite() && v.is_finite()) {
            return None;
        }
        if (du * norm(gu)).abs() + (dv * norm(gv)).abs() < 1e-12 {
            let x = sub(f.frame.place(f.surface.point(u, v)), m);
            return Some((dot(x, u3), [u, v]));
        }
    }
    None
}

/// The numerical search (module docs) with `directions` planes over 180°
/// (≥ 4). `max_offset_mm` bounds the search along a direction (a boundary
/// not found within it is reported at it, and the ellipse as line contact).
pub fn searched_ellipse(
    pinion: &FlankAtContact,
    gear: &FlankAtContact,
    point: V3,
    normal: V3,
    delta: f64,
    directions: usize,
    max_offset_mm: f64,
) -> ContactEllipse {
    let (e1, e2) = basis(pinion, normal);
    // separation at tangent offset s along d: None when a flank ends
    let separation = |d: V3, s: f64, starts: &mut [[f64; 2]; 2]| -> Option<f64> {
        let (h1, uv1) = section_point(pinion, point, d, normal, s, starts[0])?;
        let (h2, uv2) = section_point(gear, point, d, normal, s, starts[1])?;
        if !on_active_flank(pinion.surface, uv1) || !on_active_flank(gear.surface, uv2) {
            return None;
        }
        *starts = [uv1, uv2];
        Some(h2 - h1)
    };
    // boundary offset along +d: the first s > 0 with separation ≥ δ or
    // where a flank ends (bracket by doubling, then regula falsi/bisection)
    // start each direction at the curvature estimate √(2δ / B(d, d)) and
    // bracket from there (growing or shrinking by 1.25)
    let ([b11, b12, b22], _, _) = relative_curvature(pinion, gear, normal);
    let estimate = |d: V3| {
        let (x, y) = (dot(d, e1), dot(d, e2));
        let bdd = b11 * x * x + 2.0 * b12 * x * y + b22 * y * y;
        if bdd > 0.0 {
            (2.0 * delta / bdd).sqrt().min(max_offset_mm)
        } else {
            max_offset_mm
        }
    };
    let boundary = |d: V3| -> (f64, bool) {
        let mut starts = [pinion.uv, gear.uv];
        let (mut lo, mut g_lo) = (0.0, 0.0);
        let mut hi = None;
        let mut s = estimate(d);
        for _ in 0..SEARCH_STEPS {
            let mut st = starts;
            match separation(d, s, &mut st) {
                Some(g) if g < delta => {
                    lo = s;
                    g_lo = g;
                    starts = st;
                    if hi.is_some() || s >= max_offset_mm {
                        break;
                    }
                    s = (1.25 * s).min(max_offset_mm);
                }
                other => {
                    hi = Some((s, other));
                    if lo > 0.0 {
                        break;
                    }
                    s *= 0.8;
                    if s < 1e-9 * max_offset_mm {
                        break;
                    }
                }
            }
        }
        let Some((mut hi, mut g_hi)) = hi else {
            return (max_offset_mm, false);
        };
        // Illinois regula falsi (bisection where a flank ended)
        let mut side = 0i8;
        for _ in 0..SEARCH_STEPS {
            if hi - lo <= 1e-7 * hi {
                break;
            }
            let t = match g_hi {
                Some(g) if g > g_lo => {
                    let w = if side == 1 { 0.5 } else { 1.0 };
                    let gh = delta + w * (g - delta);
                    lo + (hi - lo) * (delta - g_lo) / (gh - g_lo)
                }
                _ => 0.5 * (lo + hi),
            };
            let t = t.clamp(lo + 1e-3 * (hi - lo), hi - 1e-3 * (hi - lo));
            let mut st = starts;
            match separation(d, t, &mut st) {
                Some(g) if g < delta => {
                    lo = t;
                    g_lo = g;
                    starts = st;
                    side = 1;
                }
                other => {
                    hi = t;
                    g_hi = other;
                    side = -1;
                }
            }
        }
        (0.5 * (lo + hi), true)
    };
    let n = directions.max(4);
    let dir = |a: f64| {
        unit(add(
            [a.cos() * e1[0], a.cos() * e1[1], a.cos() * e1[2]],
            a.sin(),
            e2,
        ))
    };
    // the half-chord through the contact point along α: the patch's extent
    let chord = |a: f64| -> (f64, bool) {
        let d = dir(a);
        let (sp, okp) = boundary(d);
        let (sm, okm) = boundary([-d[0], -d[1], -d[2]]);
        (0.5 * (sp + sm), okp && okm)
    };
    let step = std::f64::consts::PI / n as f64;
    let mut radii = Vec::with_capacity(n);
    let mut closed = true;
    for i in 0..n {
        let (r, ok) = chord(step * i as f64);
        closed &= ok;
        radii.push(r);
    }
    let best = |sign: f64| {
        radii
            .iter()
            .enumerate()
            .fold((0, f64::NEG_INFINITY), |b, (i, &r)| {
                if sign * r > b.1 {
                    (i, sign * r)
                } else {
                    b
                }
            })
            .0
    };
    // golden-section refinement of the extreme between the neighbouring
    // directions (a long ellipse's extent peaks sharply about its axis)
    let refine = |i: usize, sign: f64| -> (f64, f64) {
        let g = 0.5 * (5f64.sqrt() - 1.0);
        let (mut lo, mut hi) = (step * (i as f64 - 1.0), step * (i as f64 + 1.0));
        let f = |a: f64| sign * chord(a).0;
        let (mut x1, mut x2) = (hi - g * (hi - lo), lo + g * (hi - lo));
        let (mut f1, mut f2) = (f(x1), f(x2));
        for _ in 0..GOLDEN_STEPS {
            if f1 > f2 {
                hi = x2;
                x2 = x1;
                f2 = f1;
                x1 = hi - g * (hi - lo);
                f1 = f(x1);
            } else {
                lo = x1;
                x1 = x2;
                f1 = f2;
                x2 = lo + g * (hi - lo);
                f2 = f(x2);
            }
        }
        let (a, v) = if f1 > f2 { (x1, f1) } else { (x2, f2) };
        // never worse than the scanned sample
        if v >= sign * radii[i] {
            (a, sign * v)
        } else {
            (step * i as f64, radii[i])
        }
    };
    let (a, rmax) = refine(best(1.0), 1.0);
    let (_, rmin) = refine(best(-1.0), -1.0);
    let major = dir(a);
    ContactEllipse {
        semi_major_mm: closed.then_some(rmax),
        semi_minor_mm: rmin,
        major_direction: major,
        line_contact: !closed,
    }
}
