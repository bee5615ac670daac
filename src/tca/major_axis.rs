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
use crate::geometry::gear_pair::{Flank, PairPlacement};
use crate::geometry::surface::on_active_flank;
use crate::geometry::vec3::{add, dot, norm, sub, unit, V3};

use super::point_contact::PairContact;

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
    pair: &dyn PairPlacement,
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
            if !(u.is_finite() && v.is_finite()) || !on_active_flank(surface, [u, v]) {
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
