//! The curvature contact ellipse of two flanks in point contact at an
//! elastic approach δ (Litvin & Fuentes, *Gear Geometry and Applied
//! Theory*, 2nd ed., §9.5 and §8): the separation of two surfaces in
//! contact is, to second order in the tangent-plane offset s along a unit
//! direction d, ½ (κ₁(d) + κ₂(d)) s², κᵢ the normal curvatures (convex
//! positive) of each surface; the relative curvature tensor B = K₁ + K₂ in
//! the common tangent plane gives the semi-axes a = √(2δ/λ_min),
//! b = √(2δ/λ_max) and the major axis along λ_min's eigenvector.
//! λ_min ≈ 0 is line contact (a conjugate pair): flagged, no finite major
//! axis. Used by the TCA ([`crate::tca`]) and by the local synthesis of
//! pinion settings ([`crate::geometry::bevel::synthesis`]).

use crate::geometry::frame::Frame;
use crate::geometry::surface::{normal_curvatures, ToothSurface};
use crate::geometry::vec3::{add, cross, dot, unit, V3};

/// One placed flank at a contact: the surface, its frame and the contact's
/// flank parameters.
#[derive(Clone, Copy, Debug)]
pub struct FlankAtContact<'a> {
    pub surface: &'a dyn ToothSurface,
    pub frame: Frame,
    pub uv: [f64; 2],
}

/// A contact ellipse (global vectors, mm).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct ContactEllipse {
    /// Semi-major axis a (mm); `None` for line contact.
    pub semi_major_mm: Option<f64>,
    /// Semi-minor axis b (mm).
    pub semi_minor_mm: f64,
    /// Unit direction of the major axis (global).
    pub major_direction: V3,
    /// Line contact: the relative curvature along the major axis is below
    /// 1e-6 of the one across it.
    pub line_contact: bool,
}

/// The tangent-plane basis at a contact: e₁ along the pinion's profile
/// tangent (projected), e₂ = u₃ × e₁.
pub fn basis(pinion: &FlankAtContact, normal: V3) -> (V3, V3) {
    let (ru, _) = pinion.surface.derivatives(pinion.uv[0], pinion.uv[1]);
    let t = pinion.frame.rotate(ru);
    let e1 = unit(add(t, -dot(t, normal), normal));
    (e1, cross(normal, e1))
}

/// Normal-curvature tensor (convex positive) of one flank in the basis.
fn curvature_tensor(f: &FlankAtContact, e1: V3, e2: V3) -> [f64; 3] {
    let own = |d: V3| f.frame.rotate_back(d);
    let diag = unit(add(e1, 1.0, e2));
    // one evaluation and one set of second derivatives for the three
    let [k11, k22, kd] = normal_curvatures(f.surface, f.uv[0], f.uv[1], [e1, e2, diag].map(own));
    [k11, kd - 0.5 * (k11 + k22), k22]
}

/// Relative curvature tensor B = K₁ + K₂ in the basis (e₁, e₂) (module
/// docs), with the basis.
pub fn relative_curvature(
    pinion: &FlankAtContact,
    gear: &FlankAtContact,
    normal: V3,
) -> ([f64; 3], V3, V3) {
    let (e1, e2) = basis(pinion, normal);
    let a = curvature_tensor(pinion, e1, e2);
    let b = curvature_tensor(gear, e1, e2);
    ([a[0] + b[0], a[1] + b[1], a[2] + b[2]], e1, e2)
}

/// The ellipse from the curvatures at approach `delta` (mm).
pub fn curvature_ellipse(
    pinion: &FlankAtContact,
    gear: &FlankAtContact,
    normal: V3,
    delta: f64,
) -> ContactEllipse {
    let ([b11, b12, b22], e1, e2) = relative_curvature(pinion, gear, normal);
    let mean = 0.5 * (b11 + b22);
    let r = (0.25 * (b11 - b22).powi(2) + b12 * b12).sqrt();
    let (lmin, lmax) = (mean - r, mean + r);
    // eigenvector of λ_min: (b12, λ − b11) or (λ − b22, b12)
    let (x, y) = if (b11 - lmin).abs() > (b22 - lmin).abs() {
        (b12, lmin - b11)
    } else {
        (lmin - b22, b12)
    };
    let major = if x.abs() + y.abs() > 0.0 {
        unit(add([x * e1[0], x * e1[1], x * e1[2]], y, e2))
    } else {
        e1
    };
    let line_contact = !(lmin > 1e-6 * lmax.abs());
    ContactEllipse {
        semi_major_mm: (!line_contact).then(|| (2.0 * delta / lmin).sqrt()),
        semi_minor_mm: (2.0 * delta / lmax).sqrt(),
        major_direction: major,
        line_contact,
    }
}
