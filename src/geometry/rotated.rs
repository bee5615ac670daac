//! A tooth surface turned about its gear's axis (own z): the flanks of the
//! other teeth of a sector are those of one tooth, turned by multiples of
//! the angular pitch. Every quantity of [`ToothSurface`] turns with it; the
//! parameters (u, v) and the boundaries do not change.

use std::sync::Arc;

use super::surface::ToothSurface;
use super::vec3::V3;

/// `surface` turned by `angle` (rad, right-handed about +z).
#[derive(Clone, Debug)]
pub struct RotatedSurface {
    surface: Arc<dyn ToothSurface>,
    angle: f64,
    cos: f64,
    sin: f64,
}

impl RotatedSurface {
    pub fn new(surface: Arc<dyn ToothSurface>, angle: f64) -> Self {
        let (sin, cos) = angle.sin_cos();
        RotatedSurface {
            surface,
            angle,
            cos,
            sin,
        }
    }

    /// The turn (rad).
    pub fn angle(&self) -> f64 {
        self.angle
    }

    /// The surface before the turn.
    pub fn unrotated(&self) -> &dyn ToothSurface {
        self.surface.as_ref()
    }

    fn turn(&self, p: V3) -> V3 {
        [
            self.cos * p[0] - self.sin * p[1],
            self.sin * p[0] + self.cos * p[1],
            p[2],
        ]
    }

    fn unturn(&self, p: V3) -> V3 {
        [
            self.cos * p[0] + self.sin * p[1],
            -self.sin * p[0] + self.cos * p[1],
            p[2],
        ]
    }
}

impl ToothSurface for RotatedSurface {
    fn u_range(&self) -> (f64, f64) {
        self.surface.u_range()
    }
    fn v_range(&self) -> (f64, f64) {
        self.surface.v_range()
    }
    fn u_tip(&self, v: f64) -> f64 {
        self.surface.u_tip(v)
    }
    fn u_form(&self, v: f64) -> f64 {
        self.surface.u_form(v)
    }
    fn u_root(&self, v: f64) -> f64 {
        self.surface.u_root(v)
    }
    fn point(&self, u: f64, v: f64) -> V3 {
        self.turn(self.surface.point(u, v))
    }
    fn normal(&self, u: f64, v: f64) -> V3 {
        self.turn(self.surface.normal(u, v))
    }
    fn derivatives(&self, u: f64, v: f64) -> (V3, V3) {
        let (a, b) = self.surface.derivatives(u, v);
        (self.turn(a), self.turn(b))
    }
    fn evaluate(&self, u: f64, v: f64) -> (V3, V3, V3, V3) {
        let (p, n, a, b) = self.surface.evaluate(u, v);
        (self.turn(p), self.turn(n), self.turn(a), self.turn(b))
    }
    fn evaluate_checked(&self, u: f64, v: f64) -> Option<(V3, V3, V3, V3)> {
        let (p, n, a, b) = self.surface.evaluate_checked(u, v)?;
        Some((self.turn(p), self.turn(n), self.turn(a), self.turn(b)))
    }
    fn second_derivatives(&self, u: f64, v: f64) -> [V3; 3] {
        self.surface.second_derivatives(u, v).map(|d| self.turn(d))
    }
    fn closest_point(&self, p: V3) -> (f64, f64, f64) {
        self.surface.closest_point(self.unturn(p))
    }
    fn closest_point_from(&self, p: V3, u0: f64, v0: f64) -> (f64, f64, f64) {
        self.surface.closest_point_from(self.unturn(p), u0, v0)
    }
    fn profile_length(&self, du: f64, u: f64, v: f64) -> f64 {
        self.surface.profile_length(du, u, v)
    }
    fn profile_step(&self, length: f64, u: f64, v: f64) -> f64 {
        self.surface.profile_step(length, u, v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::deviation::tests::Torus;
    use crate::geometry::surface::principal_curvatures;
    use crate::geometry::vec3::{dot, norm, sub};

    #[test]
    fn a_turned_surface_is_the_surface_turned() {
        let a = 0.7;
        let s = RotatedSurface::new(Arc::new(Torus), a);
        let (u, v) = (0.2, -0.1);
        let p = Torus.point(u, v);
        let q = s.point(u, v);
        // Same distance from the axis and height, polar angle advanced by a.
        assert!((p[0].hypot(p[1]) - q[0].hypot(q[1])).abs() < 1e-12);
        assert_eq!(p[2], q[2]);
        let turned = q[1].atan2(q[0]) - p[1].atan2(p[0]);
        assert!((turned - a).abs() < 1e-14);
        // Normal and derivatives keep their relations; curvatures are invariant.
        let (n, (ru, rv)) = (s.normal(u, v), s.derivatives(u, v));
        assert!(dot(n, ru).abs() < 1e-12 && dot(n, rv).abs() < 1e-12);
        let k0 = principal_curvatures(&Torus, u, v).principal;
        let k1 = principal_curvatures(&s, u, v).principal;
        assert!((k0[0] - k1[0]).abs() < 1e-9 && (k0[1] - k1[1]).abs() < 1e-9);
        // The closest point of a turned point is found at its parameters.
        let target = [q[0] + 0.01 * n[0], q[1] + 0.01 * n[1], q[2] + 0.01 * n[2]];
        let (cu, cv, d) = s.closest_point_from(target, 0.0, 0.0);
        assert!((cu - u).abs() < 1e-9 && (cv - v).abs() < 1e-9, "{cu} {cv}");
        assert!((d.abs() - 0.01).abs() < 1e-9);
        assert!(norm(sub(s.point(cu, cv), q)) < 1e-8);
    }
}
