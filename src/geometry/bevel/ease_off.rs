//! A pinion flank = the conjugate flank minus a specified **ease-off**: a
//! field e(u, v) of normal deviations (mm, > 0 where material is removed)
//! over the pinion's axial-section parameters (u normal to the pitch
//! generatrix root → tip, v the cone distance toe → heel).
//!
//! Why the axial section: it is the projection in which gear engineers plot
//! ease-off and measuring machines lay their grids (the "rotated
//! projection" of Gleason and Klingelnberg summaries), u and v are lengths
//! (mm), so crowning amounts read directly, and they are the surface's own
//! parameters: e and its derivatives are exact polynomials there.
//!
//! With ξ = (u − u_c)/a_u, η = (v − v_c)/a_v about the centre (u_c, v_c):
//!
//! e = C_p ξ² + C_l η² + B ξ η + c_TE (φ₁ − φ₁c)² A(u, v),
//!
//! * C_p profile crowning (relief at ξ = ±1), C_l lengthwise crowning
//!   (at η = ±1), B bias (diagonal twist: relief at ξ = η = 1 and at
//!   ξ = η = −1, the other diagonal gains);
//! * the **transmission-error term**: φ₁(u, v) is the pinion rotation at
//!   which the point is in contact ([`ConjugatePoint::roll`]), φ₁c that of
//!   the centre, A = |n · (k₁ × r)| the normal displacement of the point per
//!   unit pinion rotation (moment arm about the pinion axis k₁). A relief
//!   e = A Δφ delays the contact of the whole contact line through the point
//!   by the rotation Δφ, so this term alone gives the parabolic unloaded
//!   transmission error Δφ₁ = c_TE (φ₁ − φ₁c)², with c_TE = amplitude /
//!   half_range² (Litvin & Fuentes, *Gear Geometry and Applied Theory*,
//!   §9.2 and §22.7: a predesigned parabolic function of transmission
//!   errors absorbs the linear errors caused by misalignment). This holds
//!   to first order in the amplitude: the term also crowns the flank across
//!   the contact lines, which lowers the TE by a relative 2 c A (dφ/dξ)²/K
//!   (ξ across the line, K the relative curvature across it): 0.05–0.2 %
//!   at 50 µrad in `verification/bevel_conjugate`.
//!
//! The modified surface is r_e = r − e n with r_e,u = r_u − e_u n − e n_u
//! (and likewise in v), n_u the exact normal derivative of the conjugate
//! flank; its normal is the unit r_e,u × r_e,v oriented like n.
//!
//! [`deviation_grid`] reads the deviations back from the modified surface
//! (closest-point projection of its points on the conjugate flank) on an
//! n × m grid; [`write_grid_csv`] writes them.

use std::io::Write;
use std::path::Path;
use std::sync::Arc;

use crate::error::{FlankError, Result};
use crate::geometry::bevel::conjugate::{ConjugatePinion, ConjugatePoint};
use crate::geometry::surface::ToothSurface;
use crate::geometry::vec3::{add, cross, dot, unit, V3};

/// The specified ease-off (module docs; lengths mm, angles rad).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EaseOffSpec {
    /// Centre (u_c, v_c) of the ease-off (usually the mean point (0, R_m1)).
    pub centre: (f64, f64),
    /// Half spans a_u, a_v over which the crowning amounts are measured.
    pub half_span: (f64, f64),
    pub profile_crowning_mm: f64,
    pub lengthwise_crowning_mm: f64,
    pub bias_mm: f64,
    /// Transmission-error level: the parabola reaches this value (rad of
    /// pinion rotation) at a roll of ±`te_half_range_rad` from the centre.
    pub te_amplitude_rad: f64,
    pub te_half_range_rad: f64,
}

/// Ease-off value and its exact derivatives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EaseOffValue {
    pub e: f64,
    pub e_u: f64,
    pub e_v: f64,
}

/// The conjugate pinion with an ease-off (module docs).
#[derive(Debug, Clone)]
pub struct EasedPinion {
    conjugate: Arc<ConjugatePinion>,
    spec: EaseOffSpec,
    /// φ₁c, the roll angle of the centre.
    roll_centre: f64,
    /// c_TE (rad⁻¹).
    te_coefficient: f64,
}

/// Grid nodes per direction for the size check of the ease-off.
const CHECK_NODES: usize = 17;

impl EasedPinion {
    /// The conjugate flank with the ease-off `spec`. `tooth_thickness_mm`
    /// (the pinion's normal tooth thickness, e.g. s_mn1) bounds it: the
    /// ease-off of one flank must stay within ±half of it over the active
    /// flank, else the flank would cross the tooth's middle (an error).
    pub fn new(
        conjugate: Arc<ConjugatePinion>,
        spec: EaseOffSpec,
        tooth_thickness_mm: f64,
    ) -> Result<Self> {
        let bad = |what: &str| FlankError::Model(format!("ease-off: {what}"));
        let finite = [
            spec.centre.0,
            spec.centre.1,
            spec.half_span.0,
            spec.half_span.1,
            spec.profile_crowning_mm,
            spec.lengthwise_crowning_mm,
            spec.bias_mm,
            spec.te_amplitude_rad,
            spec.te_half_range_rad,
            tooth_thickness_mm,
        ];
        if finite.iter().any(|x| !x.is_finite()) {
            return Err(bad("non-finite value in the specification"));
        }
        if !(spec.half_span.0 > 0.0 && spec.half_span.1 > 0.0) {
            return Err(bad("half spans must be > 0"));
        }
        if spec.te_amplitude_rad != 0.0 && !(spec.te_half_range_rad > 0.0) {
            return Err(bad(
                "the transmission-error level needs a roll half range > 0",
            ));
        }
        if !(tooth_thickness_mm > 0.0) {
            return Err(bad("tooth thickness must be > 0"));
        }
        let centre = conjugate.conjugate_point(spec.centre.0, spec.centre.1)?;
        let te_coefficient = if spec.te_amplitude_rad == 0.0 {
            0.0
        } else {
            spec.te_amplitude_rad / (spec.te_half_range_rad * spec.te_half_range_rad)
        };
        let eased = EasedPinion {
            conjugate,
            spec,
            roll_centre: centre.roll,
            te_coefficient,
        };
        // size check over the active flank
        let c = &eased.conjugate;
        let (v0, v1) = c.v_range();
        let limit = 0.5 * tooth_thickness_mm;
        for j in 0..CHECK_NODES {
            let v = v0 + (v1 - v0) * j as f64 / (CHECK_NODES - 1) as f64;
            let (ua, ub) = (c.u_form(v), c.u_tip(v));
            for i in 0..CHECK_NODES {
                let u = ua + (ub - ua) * i as f64 / (CHECK_NODES - 1) as f64;
                let p = c.conjugate_point(u, v)?;
                let e = eased.ease_off_at(u, v, &p).e;
                if e.abs() > limit {
                    return Err(bad(&format!(
                        "{e:.4} mm at (u, v) = ({u:.3}, {v:.3}) mm exceeds half the tooth thickness ({limit:.4} mm)"
                    )));
                }
            }
        }
        Ok(eased)
    }

    pub fn conjugate(&self) -> &Arc<ConjugatePinion> {
        &self.conjugate
    }

    pub fn spec(&self) -> &EaseOffSpec {
        &self.spec
    }

    /// Roll angle φ₁c of the ease-off centre.
    pub fn roll_centre(&self) -> f64 {
        self.roll_centre
    }

    /// c_TE = amplitude / half_range² (rad⁻¹).
    pub fn te_coefficient(&self) -> f64 {
        self.te_coefficient
    }

    /// The ease-off at (u, v) given the conjugate point there.
    pub fn ease_off_at(&self, u: f64, v: f64, p: &ConjugatePoint) -> EaseOffValue {
        let s = &self.spec;
        let (au, av) = s.half_span;
        let xi = (u - s.centre.0) / au;
        let eta = (v - s.centre.1) / av;
        let mut e = s.profile_crowning_mm * xi * xi
            + s.lengthwise_crowning_mm * eta * eta
            + s.bias_mm * xi * eta;
        let mut e_u = (2.0 * s.profile_crowning_mm * xi + s.bias_mm * eta) / au;
        let mut e_v = (2.0 * s.lengthwise_crowning_mm * eta + s.bias_mm * xi) / av;
        if self.te_coefficient != 0.0 {
            let k: V3 = [0.0, 0.0, 1.0];
            let arm = |r: V3, n: V3| dot(n, cross(k, r));
            let a = arm(p.point, p.normal);
            let sign = a.signum();
            let a_u = sign * (dot(p.n_u, cross(k, p.point)) + dot(p.normal, cross(k, p.r_u)));
            let a_v = sign * (dot(p.n_v, cross(k, p.point)) + dot(p.normal, cross(k, p.r_v)));
            let a = a.abs();
            let d = p.roll - self.roll_centre;
            let c = self.te_coefficient;
            e += c * d * d * a;
            e_u += c * (2.0 * d * p.roll_u * a + d * d * a_u);
            e_v += c * (2.0 * d * p.roll_v * a + d * d * a_v);
        }
        EaseOffValue { e, e_u, e_v }
    }

    /// The ease-off at (u, v) (solves the conjugate point).
    pub fn ease_off(&self, u: f64, v: f64) -> Result<EaseOffValue> {
        let p = self.conjugate.conjugate_point(u, v)?;
        Ok(self.ease_off_at(u, v, &p))
    }

    fn modified(&self, u: f64, v: f64) -> (V3, V3, V3, V3) {
        let c = &self.conjugate;
        match c.conjugate_point(u, v) {
            Ok(p) => self.modified_at(u, v, &p),
            // counted by the conjugate's own fallback
            Err(_) => c.evaluate(u, v),
        }
    }

    /// Point, normal, r_u, r_v of the modified flank from the conjugate
    /// point `p` at (u, v).
    fn modified_at(&self, u: f64, v: f64, p: &ConjugatePoint) -> (V3, V3, V3, V3) {
        let e = self.ease_off_at(u, v, p);
        let x = add(p.point, -e.e, p.normal);
        let ru = add(add(p.r_u, -e.e_u, p.normal), -e.e, p.n_u);
        let rv = add(add(p.r_v, -e.e_v, p.normal), -e.e, p.n_v);
        let mut n = unit(cross(ru, rv));
        if dot(n, p.normal) < 0.0 {
            n = [-n[0], -n[1], -n[2]];
        }
        (x, n, ru, rv)
    }
}

impl ToothSurface for EasedPinion {
    fn u_range(&self) -> (f64, f64) {
        self.conjugate.u_range()
    }
    fn v_range(&self) -> (f64, f64) {
        self.conjugate.v_range()
    }
    fn u_tip(&self, v: f64) -> f64 {
        self.conjugate.u_tip(v)
    }
    fn u_form(&self, v: f64) -> f64 {
        self.conjugate.u_form(v)
    }
    fn u_root(&self, v: f64) -> f64 {
        self.conjugate.u_root(v)
    }
    fn point(&self, u: f64, v: f64) -> V3 {
        self.modified(u, v).0
    }
    fn normal(&self, u: f64, v: f64) -> V3 {
        self.modified(u, v).1
    }
    fn derivatives(&self, u: f64, v: f64) -> (V3, V3) {
        let (_, _, ru, rv) = self.modified(u, v);
        (ru, rv)
    }
    fn evaluate(&self, u: f64, v: f64) -> (V3, V3, V3, V3) {
        self.modified(u, v)
    }
    /// `None` where the conjugate point does not exist.
    fn evaluate_checked(&self, u: f64, v: f64) -> Option<(V3, V3, V3, V3)> {
        let p = self.conjugate.conjugate_point(u, v).ok()?;
        Some(self.modified_at(u, v, &p))
    }
}

/// One node of a deviation grid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GridNode {
    /// Grid parameters on the modified flank.
    pub u: f64,
    pub v: f64,
    /// Point and unit normal of the modified flank (pinion frame, mm).
    pub point: V3,
    pub normal: V3,
    /// Foot of the closest-point projection on the conjugate flank.
    pub foot_uv: (f64, f64),
    /// Ease-off read back: the distance from the conjugate flank, > 0 where
    /// material is removed (mm).
    pub deviation_mm: f64,
}

/// Deviations of `eased` from its conjugate flank at the given (u, v)
/// nodes: each modified point is projected on the conjugate flank
/// (Gauss–Newton closest point from (u, v)); the deviation is minus the
/// signed distance. A node outside the flank (v outside the face or u
/// outside [u_root(v), u_tip(v)]) is an error naming it.
pub fn deviation_grid_at(eased: &EasedPinion, nodes: &[(f64, f64)]) -> Result<Vec<GridNode>> {
    let c = eased.conjugate();
    let (v0, v1) = c.v_range();
    let failures = c.failures();
    let mut out = Vec::with_capacity(nodes.len());
    for (k, &(u, v)) in nodes.iter().enumerate() {
        let tol = 1e-9 * (v1 - v0);
        if !(u.is_finite() && v.is_finite())
            || v < v0 - tol
            || v > v1 + tol
            || u < c.u_root(v) - tol
            || u > c.u_tip(v) + tol
        {
            return Err(FlankError::Model(format!(
                "deviation grid node {k}: (u, v) = ({u}, {v}) mm lies outside the flank \
                 (v in [{v0:.4}, {v1:.4}], u in [u_root, u_tip] = [{:.4}, {:.4}] at v)",
                c.u_root(v),
                c.u_tip(v)
            )));
        }
        let (x, n, _, _) = eased.evaluate(u, v);
        let (fu, fv, d) = c.closest_point_from(x, u, v);
        out.push(GridNode {
            u,
            v,
            point: x,
            normal: n,
            foot_uv: (fu, fv),
            deviation_mm: -d,
        });
    }
    if c.failures() != failures {
        return Err(FlankError::Model(format!(
            "deviation grid: {} conjugate-flank evaluations did not converge",
            c.failures() - failures
        )));
    }
    Ok(out)
}

/// The n × m grid (n along the profile from u_form to u_tip, m across the
/// face from toe to heel; n, m ≥ 2) over the active flank, row-major in v.
pub fn deviation_grid(eased: &EasedPinion, n: usize, m: usize) -> Result<Vec<GridNode>> {
    if n < 2 || m < 2 {
        return Err(FlankError::Model(format!(
            "deviation grid: {n} × {m} nodes, need at least 2 × 2"
        )));
    }
    let c = eased.conjugate();
    let (v0, v1) = c.v_range();
    let mut nodes = Vec::with_capacity(n * m);
    for j in 0..m {
        let v = v0 + (v1 - v0) * j as f64 / (m - 1) as f64;
        let (ua, ub) = (c.u_form(v), c.u_tip(v));
        for i in 0..n {
            nodes.push((ua + (ub - ua) * i as f64 / (n - 1) as f64, v));
        }
    }
    deviation_grid_at(eased, &nodes)
}

/// Writes a grid as CSV: u, v (mm), point x, y, z (mm), normal, deviation
/// (µm).
pub fn write_grid_csv(path: &Path, grid: &[GridNode]) -> Result<()> {
    let io = |e| FlankError::io(path, e);
    let mut f = crate::atomic_file::AtomicWriter::create(path)?;
    writeln!(f, "u_mm,v_mm,x_mm,y_mm,z_mm,nx,ny,nz,deviation_um").map_err(io)?;
    for g in grid {
        writeln!(
            f,
            "{},{},{},{},{},{},{},{},{}",
            g.u,
            g.v,
            g.point[0],
            g.point[1],
            g.point[2],
            g.normal[0],
            g.normal[1],
            g.normal[2],
            1e3 * g.deviation_mm
        )
        .map_err(io)?;
    }
    f.commit()
}
