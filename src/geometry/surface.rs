//! A tooth surface: what every gear type gives every analysis.
//!
//! One flank of one tooth, in its gear's own frame (gear axis = own z), as
//! a parametric surface r(u, v): **u runs along the profile** (from the root
//! end of the fillet to the tip), **v across the face** (from one end of
//! the face width to the other). Its boundaries are curves of the parameter
//! domain: the face ends are v = v₀ and v = v₁ ([`ToothSurface::v_range`]);
//! the root, the fillet's junction with the active flank (form circle of a
//! cylindrical gear, the fillet limit of a bevel gear) and the tip edge
//! (tip cylinder, face cone) are u = u_root(v), u_form(v), u_tip(v). The
//! **tip edge** is therefore the space curve v ↦ r(u_tip(v), v), whose
//! tangent hypoid edge contact needs (seed `000_…`: edge tangent · flank
//! normal = 0).
//!
//! The normal is the unit outward normal (out of the tooth's material).
//! Curvatures follow from the first and second derivatives by the first
//! and second fundamental forms (do Carmo, *Differential Geometry of Curves
//! and Surfaces*, §3-3): with E, F, G = r_u·r_u, r_u·r_v, r_v·r_v and
//! L, M, N = r_uu·n, r_uv·n, r_vv·n, the normal curvature in the tangent
//! direction (du, dv) is −(L du² + 2M du dv + N dv²)/(E du² + 2F du dv +
//! G dv²), here signed **positive where the surface is convex** (bends away
//! from its outward normal, as a tooth flank does), the convention of the
//! TCA's curvature radii.
//!
//! Implementations: [`crate::geometry::flank::FlankSurface`] (exact
//! rack-generated involute helicoid with its trochoidal fillet and flank
//! modifications). An implementation gives points, normals and first
//! derivatives; the second derivatives, the tip-edge tangent and the
//! closest-point search have generic defaults that it may replace by exact
//! or faster forms.

use std::fmt::Debug;

use crate::geometry::vec3::{add, cross, dot, norm, sub, unit, V3};

/// One flank of one tooth (module docs). Parameters: u along the profile,
/// v across the face; all points and vectors in the gear's own frame (mm).
pub trait ToothSurface: Debug + Send + Sync {
    /// The whole parameter box: u from the lowest root to the highest tip,
    /// v across the face.
    fn u_range(&self) -> (f64, f64);
    fn v_range(&self) -> (f64, f64);

    /// u of the tip edge at v.
    fn u_tip(&self, v: f64) -> f64;
    /// u of the fillet's junction with the active flank at v.
    fn u_form(&self, v: f64) -> f64;
    /// u of the fillet's root end at v.
    fn u_root(&self, v: f64) -> f64;

    /// Point r(u, v) (mm).
    fn point(&self, u: f64, v: f64) -> V3;
    /// Unit outward normal.
    fn normal(&self, u: f64, v: f64) -> V3;
    /// (∂r/∂u, ∂r/∂v).
    fn derivatives(&self, u: f64, v: f64) -> (V3, V3);

    /// Point, normal and first derivatives in one evaluation.
    fn evaluate(&self, u: f64, v: f64) -> (V3, V3, V3, V3) {
        let (pu, pv) = self.derivatives(u, v);
        (self.point(u, v), self.normal(u, v), pu, pv)
    }

    /// [`Self::evaluate`] where the surface is defined at (u, v), `None`
    /// where it is not: a surface evaluated by an inner solve (generated
    /// and conjugate bevel flanks) returns `None` where that solve fails
    /// (outside the generated region, e.g. beyond the tip of a conjugate
    /// flank), where [`Self::evaluate`] falls back to a nearby point that is
    /// not on the surface. A Newton search that meets such a parameter has
    /// left the surface (`crate::tca::line_intersection` stops there
    /// instead of cycling on fallback points). Default: always defined.
    fn evaluate_checked(&self, u: f64, v: f64) -> Option<(V3, V3, V3, V3)> {
        Some(self.evaluate(u, v))
    }

    /// Second derivatives [r_uu, r_uv, r_vv]. Default: central differences
    /// of the first derivatives with steps of 1e-5 of the parameter spans
    /// (truncation error ~1e-10 relative for smooth surfaces).
    fn second_derivatives(&self, u: f64, v: f64) -> [V3; 3] {
        let (u0, u1) = self.u_range();
        let (v0, v1) = self.v_range();
        let hu = 1e-5 * (u1 - u0);
        let hv = 1e-5 * (v1 - v0);
        let (pu_p, pv_p) = self.derivatives(u + hu, v);
        let (pu_m, pv_m) = self.derivatives(u - hu, v);
        let (pu_vp, pv_vp) = self.derivatives(u, v + hv);
        let (pu_vm, pv_vm) = self.derivatives(u, v - hv);
        let d = |a: V3, b: V3, h: f64| {
            let s = sub(a, b);
            [s[0] / (2.0 * h), s[1] / (2.0 * h), s[2] / (2.0 * h)]
        };
        let uu = d(pu_p, pu_m, hu);
        // r_uv from both directions, averaged (symmetric in exact arithmetic)
        let uv1 = d(pv_p, pv_m, hu);
        let uv2 = d(pu_vp, pu_vm, hv);
        let uv = [
            0.5 * (uv1[0] + uv2[0]),
            0.5 * (uv1[1] + uv2[1]),
            0.5 * (uv1[2] + uv2[2]),
        ];
        let vv = d(pv_vp, pv_vm, hv);
        [uu, uv, vv]
    }

    /// Point of the tip edge at v: r(u_tip(v), v).
    fn tip_edge(&self, v: f64) -> V3 {
        self.point(self.u_tip(v), v)
    }

    /// Unit tangent of the tip edge at v, in the direction of growing v:
    /// d/dv r(u_tip(v), v) = r_u u_tip′(v) + r_v, with u_tip′ by a central
    /// difference (exactly 0 where the tip is a parameter line).
    fn tip_edge_tangent(&self, v: f64) -> V3 {
        let (v0, v1) = self.v_range();
        let h = 1e-6 * (v1 - v0);
        let slope = (self.u_tip(v + h) - self.u_tip(v - h)) / (2.0 * h);
        let (pu, pv) = self.derivatives(self.u_tip(v), v);
        unit(add(pv, slope, pu))
    }

    /// Closest point of the surface (within the parameter box) to `p`:
    /// (u, v, signed distance), > 0 when p lies outside the material.
    /// Default: the nearest of a 33 × 17 grid of parameters, then
    /// [`Self::closest_point_from`].
    fn closest_point(&self, p: V3) -> (f64, f64, f64) {
        let (u0, u1) = self.u_range();
        let (v0, v1) = self.v_range();
        let mut best = (f64::INFINITY, 0.5 * (u0 + u1), 0.5 * (v0 + v1));
        for i in 0..=32 {
            let u = u0 + (u1 - u0) * i as f64 / 32.0;
            for j in 0..=16 {
                let v = v0 + (v1 - v0) * j as f64 / 16.0;
                let d = norm(sub(self.point(u, v), p));
                if d < best.0 {
                    best = (d, u, v);
                }
            }
        }
        self.closest_point_from(p, best.1, best.2)
    }

    /// [`Self::closest_point`] from a starting parameter. Default:
    /// [`closest_point_newton`].
    fn closest_point_from(&self, p: V3, u0: f64, v0: f64) -> (f64, f64, f64) {
        closest_point_newton(self, p, u0, v0)
    }

    /// Length along the profile (mm) of the parameter step `du` at (u, v):
    /// |r_u| du (a cylindrical gear gives it in closed form).
    fn profile_length(&self, du: f64, u: f64, v: f64) -> f64 {
        du * norm(self.derivatives(u, v).0)
    }

    /// The parameter step along the profile that covers `length` mm at
    /// (u, v): the inverse of [`Self::profile_length`].
    fn profile_step(&self, length: f64, u: f64, v: f64) -> f64 {
        length / norm(self.derivatives(u, v).0)
    }
}

/// Whether (u, v) lies on the active flank of `s`: form line to tip,
/// toe to heel.
pub fn on_active_flank(s: &(impl ToothSurface + ?Sized), uv: [f64; 2]) -> bool {
    let (v0, v1) = s.v_range();
    let [u, v] = uv;
    v >= v0 && v <= v1 && u <= s.u_tip(v) && u >= s.u_form(v)
}

/// Bounded Gauss–Newton on ½|r(u, v) − p|² from (u0, v0), the parameters
/// kept in the box (a variable at a bound whose gradient points outward is
/// held) with step halving; stops when a step moves the foot point by less
/// than 1e-13 mm, after 200 steps, or when no step decreases the distance.
/// Returns (u, v, signed distance along the outward normal).
pub fn closest_point_newton<S: ToothSurface + ?Sized>(
    s: &S,
    p: V3,
    u0: f64,
    v0: f64,
) -> (f64, f64, f64) {
    let (lo, hi) = s.u_range();
    let (vlo, vhi) = s.v_range();
    let (mut u, mut v) = if u0.is_finite() && v0.is_finite() {
        (u0.clamp(lo, hi), v0.clamp(vlo, vhi))
    } else {
        (0.5 * (lo + hi), 0.5 * (vlo + vhi))
    };
    let dist2 = |u: f64, v: f64| {
        let r = sub(s.point(u, v), p);
        dot(r, r)
    };
    for _ in 0..200 {
        let (x, _, pu, pv) = s.evaluate(u, v);
        let r = sub(x, p);
        let f = dot(r, r);
        let g = [dot(pu, r), dot(pv, r)];
        let a = [dot(pu, pu), dot(pu, pv), dot(pv, pv)];
        let free_u = !((u <= lo && g[0] > 0.0) || (u >= hi && g[0] < 0.0));
        let free_v = !((v <= vlo && g[1] > 0.0) || (v >= vhi && g[1] < 0.0));
        let step = match (free_u, free_v) {
            (true, true) => {
                let det = a[0] * a[2] - a[1] * a[1];
                if det > 0.0 {
                    [
                        -(a[2] * g[0] - a[1] * g[1]) / det,
                        -(a[0] * g[1] - a[1] * g[0]) / det,
                    ]
                } else {
                    [-g[0] / a[0], -g[1] / a[2]]
                }
            }
            (true, false) => [-g[0] / a[0], 0.0],
            (false, true) => [0.0, -g[1] / a[2]],
            (false, false) => break,
        };
        if !(step[0].is_finite() && step[1].is_finite()) {
            break;
        }
        let small = norm(add(
            [step[0] * pu[0], step[0] * pu[1], step[0] * pu[2]],
            step[1],
            pv,
        )) < 1e-6;
        let mut lambda = 1.0;
        let mut accepted = None;
        for _ in 0..40 {
            let un = (u + lambda * step[0]).clamp(lo, hi);
            let vn = (v + lambda * step[1]).clamp(vlo, vhi);
            if small || dist2(un, vn) <= f {
                accepted = Some((un, vn));
                break;
            }
            lambda *= 0.5;
        }
        let Some((un, vn)) = accepted else { break };
        let moved = norm(add(
            [(un - u) * pu[0], (un - u) * pu[1], (un - u) * pu[2]],
            vn - v,
            pv,
        ));
        u = un;
        v = vn;
        if moved < 1e-13 {
            break;
        }
    }
    let (x, n, _, _) = s.evaluate(u, v);
    let r = sub(p, x);
    let d = norm(r);
    (u, v, if dot(r, n) < 0.0 { -d } else { d })
}

/// Principal curvatures of a surface at one parameter (module docs for the
/// sign: > 0 convex).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Curvatures {
    /// κ₁ ≥ κ₂ (1/mm).
    pub principal: [f64; 2],
    /// Unit principal directions (own frame), tangent to the surface.
    pub directions: [V3; 2],
}

/// Normal curvature (1/mm, > 0 convex) of `s` at (u, v) in the tangent
/// direction `t` (own frame; its normal component is ignored), from the
/// fundamental forms (module docs).
pub fn normal_curvature<S: ToothSurface + ?Sized>(s: &S, u: f64, v: f64, t: V3) -> f64 {
    normal_curvatures(s, u, v, [t])[0]
}

/// [`normal_curvature`] in several directions from one evaluation of the
/// surface and its second derivatives (the same numbers; on a generated
/// bevel flank each evaluation is an envelope solve, and the second
/// derivatives four more).
pub fn normal_curvatures<S: ToothSurface + ?Sized, const K: usize>(
    s: &S,
    u: f64,
    v: f64,
    ts: [V3; K],
) -> [f64; K] {
    let (_, n, pu, pv) = s.evaluate(u, v);
    let [ruu, ruv, rvv] = s.second_derivatives(u, v);
    ts.map(|t| normal_curvature_from(n, pu, pv, [ruu, ruv, rvv], t))
}

/// The normal curvature in direction `t` from the normal, the first and
/// the second derivatives.
fn normal_curvature_from(n: V3, pu: V3, pv: V3, [ruu, ruv, rvv]: [V3; 3], t: V3) -> f64 {
    let (e, f, g) = (dot(pu, pu), dot(pu, pv), dot(pv, pv));
    let (l, m, nn) = (dot(ruu, n), dot(ruv, n), dot(rvv, n));
    // t = du r_u + dv r_v in the least-squares sense
    let (a, b) = (dot(pu, t), dot(pv, t));
    let det = e * g - f * f;
    let du = (g * a - f * b) / det;
    let dv = (e * b - f * a) / det;
    let first = e * du * du + 2.0 * f * du * dv + g * dv * dv;
    -(l * du * du + 2.0 * m * du * dv + nn * dv * dv) / first
}

/// Principal curvatures and directions of `s` at (u, v): the eigenpairs of
/// the shape operator (module docs).
pub fn principal_curvatures<S: ToothSurface + ?Sized>(s: &S, u: f64, v: f64) -> Curvatures {
    let (_, n, pu, pv) = s.evaluate(u, v);
    let [ruu, ruv, rvv] = s.second_derivatives(u, v);
    let (e, f, g) = (dot(pu, pu), dot(pu, pv), dot(pv, pv));
    // convex-positive second form
    let (l, m, nn) = (-dot(ruu, n), -dot(ruv, n), -dot(rvv, n));
    let det = e * g - f * f;
    let h = (e * nn - 2.0 * f * m + g * l) / (2.0 * det);
    let k = (l * nn - m * m) / det;
    let disc = (h * h - k).max(0.0).sqrt();
    let (k1, k2) = (h + disc, h - disc);
    // direction of κ: (L − κE) du + (M − κF) dv = 0
    let dir = |kap: f64| {
        let (a, b) = (l - kap * e, m - kap * f);
        let (c, d) = (m - kap * f, nn - kap * g);
        let (du, dv) = if a.abs() + b.abs() >= c.abs() + d.abs() {
            (-b, a)
        } else {
            (-d, c)
        };
        let w = add([du * pu[0], du * pu[1], du * pu[2]], dv, pv);
        if norm(w) > 0.0 {
            unit(w)
        } else {
            unit(pu)
        }
    };
    let d1 = dir(k1);
    // the second direction is normal to the first in the tangent plane
    let d2 = unit(cross(n, d1));
    Curvatures {
        principal: [k1, k2],
        directions: [d1, d2],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A circular cylinder of radius R about the z axis, outward normal:
    /// u the angle, v = z. Curvatures 1/R (around) and 0 (along z).
    #[derive(Debug)]
    struct Cylinder(f64);

    impl ToothSurface for Cylinder {
        fn u_range(&self) -> (f64, f64) {
            (-0.5, 0.5)
        }
        fn v_range(&self) -> (f64, f64) {
            (0.0, 10.0)
        }
        fn u_tip(&self, v: f64) -> f64 {
            0.4 + 0.01 * v
        }
        fn u_form(&self, _v: f64) -> f64 {
            -0.4
        }
        fn u_root(&self, _v: f64) -> f64 {
            -0.5
        }
        fn point(&self, u: f64, v: f64) -> V3 {
            [self.0 * u.cos(), self.0 * u.sin(), v]
        }
        fn normal(&self, u: f64, _v: f64) -> V3 {
            [u.cos(), u.sin(), 0.0]
        }
        fn derivatives(&self, u: f64, _v: f64) -> (V3, V3) {
            ([-self.0 * u.sin(), self.0 * u.cos(), 0.0], [0.0, 0.0, 1.0])
        }
    }

    #[test]
    fn cylinder_curvatures_and_second_derivatives() {
        let c = Cylinder(20.0);
        let [uu, uv, vv] = c.second_derivatives(0.2, 3.0);
        let exact = [-20.0 * 0.2f64.cos(), -20.0 * 0.2f64.sin(), 0.0];
        assert!(norm(sub(uu, exact)) < 1e-8, "{uu:?}");
        assert!(norm(uv) < 1e-12 && norm(vv) < 1e-12);
        let k = principal_curvatures(&c, 0.2, 3.0);
        assert!((k.principal[0] - 0.05).abs() < 1e-9, "{:?}", k.principal);
        assert!(k.principal[1].abs() < 1e-9);
        // the convex direction is around the axis
        assert!(k.directions[0][2].abs() < 1e-9);
        let (pu, _) = c.derivatives(0.2, 3.0);
        assert!((normal_curvature(&c, 0.2, 3.0, pu) - 0.05).abs() < 1e-9);
        assert!(normal_curvature(&c, 0.2, 3.0, [0.0, 0.0, 1.0]).abs() < 1e-9);
    }

    #[test]
    fn cylinder_closest_point_and_tip_edge() {
        let c = Cylinder(20.0);
        // outside the material at angle 0.1, z 4
        let p = [25.0 * 0.1f64.cos(), 25.0 * 0.1f64.sin(), 4.0];
        let (u, v, d) = c.closest_point(p);
        assert!((u - 0.1).abs() < 1e-10 && (v - 4.0).abs() < 1e-10 && (d - 5.0).abs() < 1e-10);
        let (_, _, d) = c.closest_point_from([15.0, 0.0, 4.0], 0.3, 1.0);
        assert!((d + 5.0).abs() < 1e-10, "{d}");
        // the tip edge u = 0.4 + 0.01 v is a helix on the cylinder
        let t = c.tip_edge_tangent(5.0);
        let u = c.u_tip(5.0);
        let exact = unit([-20.0 * u.sin() * 0.01, 20.0 * u.cos() * 0.01, 1.0]);
        assert!(norm(sub(t, exact)) < 1e-8, "{t:?}");
        assert!(norm(sub(c.tip_edge(5.0), c.point(u, 5.0))) == 0.0);
        // profile length: |r_u| = R
        assert!((c.profile_length(0.01, 0.0, 0.0) - 0.2).abs() < 1e-12);
        assert!((c.profile_step(0.2, 0.0, 0.0) - 0.01).abs() < 1e-12);
    }
}
