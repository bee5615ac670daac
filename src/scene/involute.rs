//! Involute relations used by the checks (ISO 21771), internal units.

use std::f64::consts::PI;

use crate::geometry::GearSpec;
#[cfg(test)]
use crate::geometry::PairSpec;

pub(super) fn inv(a: f64) -> f64 {
    a.tan() - a
}

pub(super) fn transverse_pressure_angle(g: &GearSpec) -> f64 {
    (g.normal_pressure_angle.tan() / g.helix_angle.cos()).atan()
}

pub(super) fn reference_diameter(g: &GearSpec) -> f64 {
    f64::from(g.teeth) * g.normal_module / g.helix_angle.cos()
}

pub(super) fn base_diameter(g: &GearSpec) -> f64 {
    reference_diameter(g) * transverse_pressure_angle(g).cos()
}

/// d_a as given, else d + 2 m_n (h_aP* + x) (no tip shortening).
pub(super) fn tip_diameter(g: &GearSpec) -> f64 {
    g.tip_diameter.unwrap_or(
        reference_diameter(g) + 2.0 * g.normal_module * (g.rack.dedendum + g.profile_shift),
    )
}

/// d_f = d − 2 m_n (h_fP* − x).
pub(super) fn root_diameter(g: &GearSpec) -> f64 {
    reference_diameter(g) - 2.0 * g.normal_module * (g.rack.addendum - g.profile_shift)
}

/// Transverse tooth thickness (arc) at diameter `dy` (> d_b).
pub(super) fn tip_thickness(g: &GearSpec, dy: f64) -> f64 {
    let d = reference_diameter(g);
    let at = transverse_pressure_angle(g);
    let mt = g.normal_module / g.helix_angle.cos();
    let st = mt * (PI / 2.0 + 2.0 * g.profile_shift * g.normal_pressure_angle.tan());
    let ay = (d * at.cos() / dy).acos();
    dy * (st / d + inv(at) - inv(ay))
}

/// Working transverse pressure angle at centre distance a: cos α_wt = (r_b1 + r_b2)/a.
pub(super) fn working_pressure_angle(p: &GearSpec, g: &GearSpec, a: f64) -> f64 {
    ((base_diameter(p) + base_diameter(g)) / (2.0 * a)).acos()
}

/// x1 + x2 for backlash-free meshing at centre distance a:
/// inv α_wt = inv α_t + 2 (x1 + x2) tan α_n / (z1 + z2).
pub(super) fn shift_sum_for_centre_distance(p: &GearSpec, g: &GearSpec, a: f64) -> f64 {
    let awt = working_pressure_angle(p, g, a);
    let at = transverse_pressure_angle(p);
    let z = f64::from(p.teeth + g.teeth);
    (inv(awt) - inv(at)) * z / (2.0 * p.normal_pressure_angle.tan())
}

/// Transverse contact ratio ε_α of a pair (used by the paper-scene tests).
#[cfg(test)]
pub(super) fn transverse_contact_ratio(pair: &PairSpec) -> f64 {
    let (p, g, a) = (&pair.pinion, &pair.gear, pair.centre_distance);
    let (ra1, rb1) = (tip_diameter(p) / 2.0, base_diameter(p) / 2.0);
    let (ra2, rb2) = (tip_diameter(g) / 2.0, base_diameter(g) / 2.0);
    let awt = working_pressure_angle(p, g, a);
    let at = transverse_pressure_angle(p);
    let mt = p.normal_module / p.helix_angle.cos();
    ((ra1 * ra1 - rb1 * rb1).sqrt() + (ra2 * ra2 - rb2 * rb2).sqrt() - a * awt.sin())
        / (PI * mt * at.cos())
}
