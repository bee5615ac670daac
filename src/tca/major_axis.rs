//! Points of a point contact's major axis on both members' flanks: where a
//! compliance-matrix LTCA of a point-contact pair puts its candidate
//! points (seeds `001_…` and `003_…`: "M contact points along the major
//! axis"), with what it needs of each in the member's own frame.
//!
//! The axis runs through the contact x along the ellipse's major direction
//! d (the searched ellipse where the search ran, else the curvature one),
//! from x − a d to x + a d. K points s_k a d (s_k evenly spaced in
//! [−1, 1]) are carried into each member's own frame by the contact's
//! [`PairContact::placement`] and put on its flank by closest point; the
//! unit normal there is the flank's own outward normal and the tangent is
//! the contact's sliding direction (v_t1 − v_t2, [`PairContact`]) projected
//! onto that point's tangent plane. Points beyond the active flank (an
//! ellipse running off the face or over the tip) are left out and counted.

use crate::error::FlankError;
use crate::geometry::gear_pair::{Flank, GearPair, LineKind};
use crate::geometry::surface::{normal_curvature, on_active_flank, ToothSurface};
use crate::geometry::vec3::{add, cross, dot, norm, sub, unit, V3};

use super::point_contact::PairContact;
use super::{line_intersection, ContactLine, ContactPoint};

/// Step tolerance of the line–flank intersections (mm): generated flanks
/// are evaluated by an inner Newton whose round-off lies above 1e-12 mm.
const INTERSECTION_TOL_MM: f64 = 1e-9;

/// One point of the major axis on one member's middle tooth (own frame).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct AxisPoint {
    /// Sector tooth (the member's middle tooth, or its mate on the gear).
    pub tooth: usize,
    /// Position along the axis, −1 … 1 (units of the semi-major axis).
    pub s: f64,
    pub uv: [f64; 2],
    /// Outward unit normal of the member's flank.
    pub normal: V3,
    /// Unit sliding direction in the tangent plane (zero where the
    /// contact rolls without sliding).
    pub sliding: V3,
}

/// The major axis of the middle pair's contact `c` on [pinion, gear], K
/// points each (K ≥ 1; K = 1 is the contact point alone). Errors for a
/// pair at offset ≠ 0, a contact without ellipse (edge contact without
/// search), or a line contact (no finite major axis).
pub fn major_axis_points(
    pair: &dyn GearPair,
    c: &PairContact,
    k: usize,
) -> Result<[Vec<AxisPoint>; 2], FlankError> {
    if c.offset != 0 {
        return Err(FlankError::Model(format!(
            "major-axis points are taken on the middle pair (offset 0), not offset {}",
            c.offset
        )));
    }
    let e = c.searched_ellipse.or(c.ellipse).ok_or_else(|| {
        FlankError::Model("the contact has no ellipse (an edge contact without the search)".into())
    })?;
    let a = e
        .semi_major_mm
        .ok_or_else(|| FlankError::Model("line contact: the major axis is not finite".into()))?;
    if k == 0 {
        return Err(FlankError::Model("K = 0 points on the major axis".into()));
    }
    let middle = pair.middle();
    let teeth = [middle, pair.mate(middle)];
    let starts = [c.pinion_uv, c.gear_uv];
    let mut out: [Vec<AxisPoint>; 2] = [Vec::new(), Vec::new()];
    for b in 0..2 {
        let body = pair.body(b);
        let surface = body.flank(Flank::Right, teeth[b]).ok_or_else(|| {
            FlankError::Model(format!(
                "{}: no right flank of tooth {}",
                body.name(),
                teeth[b]
            ))
        })?;
        let frame = &c.placement[b];
        let slide_own = frame.rotate_back(c.sliding_direction);
        let mut warm = starts[b];
        for i in 0..k {
            let s = if k == 1 {
                0.0
            } else {
                -1.0 + 2.0 * i as f64 / (k - 1) as f64
            };
            let x = add(c.point, s * a, e.major_direction);
            let own = frame.rotate_back(sub(x, frame.translation));
            let (u, v, _) = surface.closest_point_from(own, warm[0], warm[1]);
            if !(u.is_finite() && v.is_finite() && on_active_flank(surface, [u, v])) {
                continue;
            }
            warm = [u, v];
            let n = surface.normal(u, v);
            let t = add(slide_own, -dot(slide_own, n), n);
            out[b].push(AxisPoint {
                tooth: teeth[b],
                s,
                uv: [u, v],
                normal: n,
                sliding: if norm(t) > 1e-12 { unit(t) } else { [0.0; 3] },
            });
        }
    }
    Ok(out)
}

/// The major axis of pair contact `c` as a contact line of `k` candidate
/// points for the compliance-matrix LTCA at pinion roll `roll` (rad), the
/// pair's frames at that roll ([`GearPair::frames`], misalignment
/// included), in the conventions of [`super::TcaPosition`]: the line runs
/// over the axis where the curvature separation stays below
/// `span_approach_mm` (semi-axis a·√(δ_span/δ), a the ellipse's at the
/// TCA's approach `approach_mm`: the loaded contact is wider than the
/// unloaded δ-ellipse), its points at the centres of k equal segments.
/// Every point is put on the pinion's flank along the contact normal,
/// placed, and measured against the gear's flank along the pinion normal
/// there (line–flank intersections, as the spur TCA's): the separation w
/// is that distance (exact surfaces, > 0 a gap), the
/// moment arm r = (ω̂₁ × (x − o₁))·n, the radii across the axis the
/// flanks' normal curvatures across it. Points whose gear point leaves the
/// gear's active flank are left out. `None` for a pair outside the sector,
/// an edge contact or a line contact (no finite major axis).
pub fn major_axis_line(
    pair: &dyn GearPair,
    c: &PairContact,
    roll: f64,
    k: usize,
    approach_mm: f64,
    span_approach_mm: f64,
) -> Result<Option<ContactLine>, FlankError> {
    let Some([pinion_tooth, gear_tooth]) = c.teeth else {
        return Ok(None);
    };
    let Some(e) = c.ellipse else {
        return Ok(None);
    };
    let Some(a) = e.semi_major_mm else {
        return Ok(None);
    };
    if k == 0 || !(approach_mm > 0.0 && span_approach_mm > 0.0) {
        return Err(FlankError::Model(format!(
            "major-axis line: K = {k}, approach {approach_mm} mm, span approach {span_approach_mm} mm (K ≥ 1 and positive approaches are needed)"
        )));
    }
    let span = a * (span_approach_mm / approach_mm).sqrt();
    let middle = pair.middle();
    let (p_mid, g_flank) = (
        pair.pinion().flank(Flank::Right, middle),
        pair.gear().flank(Flank::Right, gear_tooth),
    );
    let (Some(p_mid), Some(p_flank), Some(g_flank)) = (
        p_mid,
        pair.pinion().flank(Flank::Right, pinion_tooth),
        g_flank,
    ) else {
        return Ok(None);
    };
    let frames = pair.frames(roll);
    let axis = frames[0].rotate(pair.rotation_axes()[0]);
    let origin = frames[0].translation;
    let traced = &c.placement[0];
    let width = 2.0 * span / k as f64;
    // march from the middle of the axis outward, each closest point
    // started from its neighbour's (a far start can land on a wrong foot)
    let centre = k / 2;
    let order: Vec<usize> = (centre..k).chain((0..centre).rev()).collect();
    let mut found: Vec<Option<ContactPoint>> = vec![None; k];
    let mut warm_of: Vec<Option<[[f64; 2]; 2]>> = vec![None; k];
    for &i in &order {
        let start = if i >= centre {
            (i > centre).then(|| warm_of[i - 1]).flatten()
        } else {
            warm_of[i + 1]
        }
        .unwrap_or([c.pinion_uv, c.gear_uv]);
        let s = -1.0 + (2 * i + 1) as f64 / k as f64;
        // the axis point on the middle tooth where it was traced: its (u, v)
        // are those of the same point on tooth `pinion_tooth`
        let x = add(c.point, s * span, e.major_direction);
        // onto the pinion flank along the contact normal, then along the
        // pinion's normal there onto the gear flank (the spur TCA's
        // construction, `super::Tca`): w is the distance along the normal
        let Some((u, v, _, _)) =
            line_intersection(p_mid, traced, x, c.normal, start[0], INTERSECTION_TOL_MM)
        else {
            continue;
        };
        if !inside_active_flank(p_flank, [u, v]) {
            continue;
        }
        let xp = frames[0].place(p_flank.point(u, v));
        let n = frames[0].rotate(p_flank.normal(u, v));
        let Some((gu, gv, w, _)) =
            line_intersection(g_flank, &frames[1], xp, n, start[1], INTERSECTION_TOL_MM)
        else {
            continue;
        };
        if !inside_active_flank(g_flank, [gu, gv]) {
            continue;
        }
        warm_of[i] = Some([[u, v], [gu, gv]]);
        let xg = frames[1].place(g_flank.point(gu, gv));
        // across the axis, in the tangent plane
        let d = unit(add(e.major_direction, -dot(e.major_direction, n), n));
        let across = unit(cross(n, d));
        let kp = normal_curvature(p_flank, u, v, frames[0].rotate_back(across));
        let kg = normal_curvature(g_flank, gu, gv, frames[1].rotate_back(across));
        let radius = |k: f64| if k != 0.0 { 1.0 / k } else { f64::INFINITY };
        found[i] = Some(ContactPoint {
            pinion_uv: [u, v],
            gear_uv: [gu, gv],
            position: [
                0.5 * (xp[0] + xg[0]),
                0.5 * (xp[1] + xg[1]),
                0.5 * (xp[2] + xg[2]),
            ],
            normal: n,
            separation_mm: w,
            moment_arm_mm: dot(cross(axis, sub(xp, origin)), n),
            width_mm: width,
            across_mm: 0.0,
            tangent: {
                let t = add(c.sliding_direction, -dot(c.sliding_direction, n), n);
                if norm(t) > 1e-12 {
                    unit(t)
                } else {
                    d
                }
            },
            sliding_velocity: c.sliding_velocity,
            rolling_velocity: c.rolling_velocity,
            sum_velocity: 2.0 * c.rolling_velocity,
            curvature_radius: [radius(kp), radius(kg)],
            equivalent_radius_mm: if kp + kg > 0.0 {
                1.0 / (kp + kg)
            } else {
                f64::INFINITY
            },
        });
    }
    let points: Vec<ContactPoint> = found.into_iter().flatten().collect();
    let v_ends = points
        .iter()
        .fold([f64::INFINITY, f64::NEG_INFINITY], |e, q| {
            [e[0].min(q.pinion_uv[1]), e[1].max(q.pinion_uv[1])]
        });
    if points.is_empty() {
        return Ok(None);
    }
    let length = width * points.len() as f64;
    Ok(Some(ContactLine {
        pinion_tooth,
        gear_tooth,
        kind: LineKind::Flank,
        length_mm: length,
        param_per_mm: if v_ends[1] > v_ends[0] {
            (v_ends[1] - v_ends[0]) / (length - width).max(width)
        } else {
            0.0
        },
        points,
    }))
}

/// (u, v) strictly inside the active flank (form line to tip, toe to
/// heel), 1e-9 from its edges: a closest point clamped to an edge is out.
fn inside_active_flank(s: &dyn ToothSurface, uv: [f64; 2]) -> bool {
    let (v0, v1) = s.v_range();
    let [u, v] = uv;
    let e = 1e-9;
    v > v0 + e && v < v1 - e && u < s.u_tip(v) - e && u > s.u_form(v) + e
}
