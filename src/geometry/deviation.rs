//! A tooth surface moved along its own normal by a deviation field:
//! r̃(u, v) = r(u, v) + δ(u, v) n(u, v).
//!
//! This is how a measured topography (a grid of normal deviations read back,
//! [`super::measurement_grid`]) or a designed ease-off becomes a flank: the
//! field is given over the surface parameters, **positive δ adds material**
//! (the sign measuring machines report: plus metal). The nominal surface and
//! its boundaries (tip, form, root, face ends) are kept; the deviation is
//! microns, so the parameter domain does not change.
//!
//! Derivatives (do Carmo, *Differential Geometry of Curves and Surfaces*,
//! §3-3, Weingarten equations): r̃_u = r_u + δ_u n + δ n_u with
//! n_u = (N_u − n (n·N_u)) / |N|, N = r_u × r_v, N_u = r_uu × r_v + r_u × r_uv
//! (and likewise in v). The second derivatives of the nominal surface come
//! from [`ToothSurface::second_derivatives`]; the deviation's gradient from
//! the field itself. The normal of r̃ is r̃_u × r̃_v, unit, on the side of n.

use std::fmt::Debug;
use std::sync::Arc;

use super::surface::ToothSurface;
use super::vec3::{add, cross, dot, norm, V3};

/// A scalar field over a flank's (u, v) parameters (mm) with its gradient.
pub trait DeviationField: Debug + Send + Sync {
    /// δ(u, v) (mm), positive = material added along the outward normal.
    fn deviation(&self, u: f64, v: f64) -> f64;
    /// (∂δ/∂u, ∂δ/∂v).
    fn gradient(&self, u: f64, v: f64) -> (f64, f64);
}

/// The nominal `surface` plus `field` along its normal (module docs).
#[derive(Clone, Debug)]
pub struct DeviatedSurface {
    surface: Arc<dyn ToothSurface>,
    field: Arc<dyn DeviationField>,
}

impl DeviatedSurface {
    pub fn new(surface: Arc<dyn ToothSurface>, field: Arc<dyn DeviationField>) -> Self {
        DeviatedSurface { surface, field }
    }

    /// The surface without the deviation.
    pub fn nominal(&self) -> &dyn ToothSurface {
        self.surface.as_ref()
    }

    pub fn field(&self) -> &dyn DeviationField {
        self.field.as_ref()
    }

    /// (∂n/∂u, ∂n/∂v) of the nominal surface (Weingarten, module docs).
    fn normal_derivatives(&self, u: f64, v: f64) -> (V3, V3) {
        let (ru, rv) = self.surface.derivatives(u, v);
        let [ruu, ruv, rvv] = self.surface.second_derivatives(u, v);
        let big_n = cross(ru, rv);
        let len = norm(big_n);
        let n = [big_n[0] / len, big_n[1] / len, big_n[2] / len];
        let project = |d: V3| {
            let a = dot(n, d);
            [
                (d[0] - a * n[0]) / len,
                (d[1] - a * n[1]) / len,
                (d[2] - a * n[2]) / len,
            ]
        };
        let nu = add(cross(ruu, rv), 1.0, cross(ru, ruv));
        let nv = add(cross(ruv, rv), 1.0, cross(ru, rvv));
        // The nominal normal may be −N/|N| (outward convention of the
        // implementation): then its derivatives change sign too.
        let s = dot(self.surface.normal(u, v), n).signum();
        let (du, dv) = (project(nu), project(nv));
        (
            [s * du[0], s * du[1], s * du[2]],
            [s * dv[0], s * dv[1], s * dv[2]],
        )
    }
}

impl ToothSurface for DeviatedSurface {
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
        let d = self.field.deviation(u, v);
        if d == 0.0 {
            return self.surface.point(u, v);
        }
        add(self.surface.point(u, v), d, self.surface.normal(u, v))
    }

    fn normal(&self, u: f64, v: f64) -> V3 {
        let (ru, rv) = self.derivatives(u, v);
        let c = cross(ru, rv);
        let l = norm(c);
        let s = dot(c, self.surface.normal(u, v)).signum() / l;
        [s * c[0], s * c[1], s * c[2]]
    }

    fn derivatives(&self, u: f64, v: f64) -> (V3, V3) {
        let (ru, rv) = self.surface.derivatives(u, v);
        let d = self.field.deviation(u, v);
        let (du, dv) = self.field.gradient(u, v);
        if d == 0.0 && du == 0.0 && dv == 0.0 {
            return (ru, rv);
        }
        let n = self.surface.normal(u, v);
        let (nu, nv) = self.normal_derivatives(u, v);
        (add(add(ru, du, n), d, nu), add(add(rv, dv, n), d, nv))
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A torus patch (major radius 40, minor 12): doubly curved, closed-form
    /// normal; u the angle around the tube, v around the axis.
    #[derive(Debug)]
    pub(crate) struct Torus;

    impl ToothSurface for Torus {
        fn u_range(&self) -> (f64, f64) {
            (-0.6, 0.6)
        }
        fn v_range(&self) -> (f64, f64) {
            (-0.4, 0.4)
        }
        fn u_tip(&self, v: f64) -> f64 {
            0.5 + 0.05 * v
        }
        fn u_form(&self, _v: f64) -> f64 {
            -0.45
        }
        fn u_root(&self, _v: f64) -> f64 {
            -0.6
        }
        fn point(&self, u: f64, v: f64) -> V3 {
            let r = 40.0 + 12.0 * u.cos();
            [r * v.cos(), r * v.sin(), 12.0 * u.sin()]
        }
        fn normal(&self, u: f64, v: f64) -> V3 {
            [u.cos() * v.cos(), u.cos() * v.sin(), u.sin()]
        }
        fn derivatives(&self, u: f64, v: f64) -> (V3, V3) {
            let r = 40.0 + 12.0 * u.cos();
            (
                [
                    -12.0 * u.sin() * v.cos(),
                    -12.0 * u.sin() * v.sin(),
                    12.0 * u.cos(),
                ],
                [-r * v.sin(), r * v.cos(), 0.0],
            )
        }
    }

    /// δ = a + b u + c v² + e u v (mm).
    #[derive(Debug)]
    struct Quadratic;
    impl DeviationField for Quadratic {
        fn deviation(&self, u: f64, v: f64) -> f64 {
            1e-3 * (2.0 + 3.0 * u + 5.0 * v * v - 4.0 * u * v)
        }
        fn gradient(&self, u: f64, v: f64) -> (f64, f64) {
            (1e-3 * (3.0 - 4.0 * v), 1e-3 * (10.0 * v - 4.0 * u))
        }
    }

    #[test]
    fn derivatives_and_normal_match_finite_differences() {
        let s = DeviatedSurface::new(Arc::new(Torus), Arc::new(Quadratic));
        let h = 1e-6;
        for &(u, v) in &[(0.1, 0.2), (-0.3, -0.1), (0.4, 0.35)] {
            let (ru, rv) = s.derivatives(u, v);
            let fd = |du: f64, dv: f64| {
                let p = s.point(u + du, v + dv);
                let m = s.point(u - du, v - dv);
                [
                    (p[0] - m[0]) / (2.0 * h),
                    (p[1] - m[1]) / (2.0 * h),
                    (p[2] - m[2]) / (2.0 * h),
                ]
            };
            let (fu, fv) = (fd(h, 0.0), fd(0.0, h));
            for k in 0..3 {
                // The nominal second derivatives are central differences:
                // n_u carries their O(h²) error times δ ~ 1e-3.
                assert!(
                    (ru[k] - fu[k]).abs() < 1e-7,
                    "r_u {k}: {} vs {}",
                    ru[k],
                    fu[k]
                );
                assert!(
                    (rv[k] - fv[k]).abs() < 1e-7,
                    "r_v {k}: {} vs {}",
                    rv[k],
                    fv[k]
                );
            }
            let n = s.normal(u, v);
            assert!(dot(n, fu).abs() < 1e-7 && dot(n, fv).abs() < 1e-7);
            assert!((norm(n) - 1.0).abs() < 1e-14);
            assert!(dot(n, Torus.normal(u, v)) > 0.99);
        }
    }

    #[test]
    fn the_offset_is_the_field_along_the_nominal_normal() {
        let s = DeviatedSurface::new(Arc::new(Torus), Arc::new(Quadratic));
        let (u, v) = (0.2, -0.3);
        let p = s.point(u, v);
        let q = Torus.point(u, v);
        let d = [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
        let delta = Quadratic.deviation(u, v);
        // Round-off of coordinates of 50 mm: 1e-16 × 50 per operation.
        assert!((dot(d, Torus.normal(u, v)) - delta).abs() < 1e-13);
        assert!((norm(d) - delta.abs()).abs() < 1e-13);
    }
}
