//! One flank of one tooth as a parametric surface, with its modification:
//! points, normals, derivatives, boundaries and closest-point projection.
//!
//! Parameters: **u** is the unified flank parameter of
//! [`crate::mesh::gear_sector`] (the involute roll angle for u ≥ u_form; on the
//! trochoidal root fillet u = u_form − t, t ∈ [0, 1] the fillet parameter, so
//! the fillet spans [u_form − 1, u_form] and u_form − 1 is its end on the root
//! circle). **v is z**: the axial coordinate in mm, v ∈ [0, b] (b the face
//! width), the z of [`ToothProfile::surface`].
//!
//! The modified surface is P(u, v) = N(u, v) − o(u, v)·n(u, v), with N and n
//! the nominal surface and its unit outward normal ([`ToothProfile::surface`])
//! and o the offset of [`FlankModification::offset`] (material removed along
//! the normal). Its derivatives are exact:
//!
//!   P_u = N_u − o_u n − o n_u,   P_v = N_v − o_v n − o n_v,
//!
//! where n_u, n_v follow from the nominal surface's first and second
//! derivatives: with n = (R(φ) n₂, n_z)/ℓ, n_z = −φ′ (p × n₂), ℓ = √(1 + n_z²),
//! φ = φ′ z (the helix twist), n₂′ = −((n₂·p″)/|p′|²) p′ in the transverse
//! section. p″ is analytic on the involute (r_b (e_r − u e_φ)) and, on the
//! fillet, the fourth-order central difference of the analytic tangent
//! [`ToothProfile::tangent`] (step 1e-3 in t; error ~1e-12 relative). The unit
//! outward normal of the modified surface is P_u × P_v normalised and turned
//! to the side of n. With a zero offset and gradient, point and normal are
//! those of [`ToothProfile::surface`], bit for bit.
//!
//! Teeth: `tooth` is the sector numbering of [`crate::mesh::gear_sector`]: tooth
//! k ≥ 1 is the profile's tooth k − 1, tooth 0 rotated about the axis by
//! −2π(k − 1)/z. Derivatives with respect to u are those of the branch that
//! contains u (u ≥ u_form: involute): the parametrisation's speed jumps at the
//! form circle (the surface itself is tangent-continuous there).

use super::micro::FlankModification;
use super::rack::{Flank, Segment, ToothProfile};
use crate::error::FlankError;

type Result<T> = std::result::Result<T, FlankError>;

use crate::geometry::vec3::{cross, dot, norm, V3};

fn axpy(a: f64, x: V3, y: V3) -> V3 {
    [a * x[0] + y[0], a * x[1] + y[1], a * x[2] + y[2]]
}

/// Surface quantities at one parameter, in one frame.
#[derive(Clone, Copy, Debug)]
struct Eval {
    p: V3,
    n: V3,
    pu: V3,
    pv: V3,
}

/// One flank of one tooth of a gear, optionally modified (module docs).
#[derive(Clone, Debug, PartialEq)]
pub struct FlankSurface {
    profile: ToothProfile,
    flank: Flank,
    tooth: usize,
    modification: Option<FlankModification>,
    /// sin, cos of the tooth's rotation −2π(k − 1)/z.
    rot: (f64, f64),
}

impl FlankSurface {
    /// The `flank` of sector tooth `tooth` (≥ 1, ≤ z) of the gear of `profile`,
    /// modified by `modification` if given.
    pub fn new(
        profile: ToothProfile,
        flank: Flank,
        tooth: usize,
        modification: Option<FlankModification>,
    ) -> Result<Self> {
        let z = profile.geometry.teeth as usize;
        if tooth < 1 || tooth > z {
            return Err(FlankError::Model(format!(
                "flank surface: tooth {tooth} does not exist (sector numbering 1..={z})"
            )));
        }
        if let Some(m) = &modification {
            let (uf, _, ut) = m.roll_angles();
            if uf != profile.u_form
                || ut != profile.u_tip
                || (m.face_width() - profile.face_width).abs() > 1e-9 * profile.face_width
            {
                return Err(FlankError::Model(format!(
                    "flank surface: the modification was built for another gear (u_form {uf}, u_a {ut}, b {} mm; this gear: {}, {}, {} mm)",
                    m.face_width(),
                    profile.u_form,
                    profile.u_tip,
                    profile.face_width
                )));
            }
        }
        let a = -((tooth - 1) as f64) * profile.angular_pitch();
        Ok(FlankSurface {
            profile,
            flank,
            tooth,
            modification,
            rot: a.sin_cos(),
        })
    }

    pub fn profile(&self) -> &ToothProfile {
        &self.profile
    }

    pub fn flank(&self) -> Flank {
        self.flank
    }

    /// Sector tooth number (1-based).
    pub fn tooth(&self) -> usize {
        self.tooth
    }

    pub fn modification(&self) -> Option<&FlankModification> {
        self.modification.as_ref()
    }

    /// u at the end of the root fillet (on the root circle): u_form − 1.
    pub fn u_root(&self) -> f64 {
        self.profile.u_form - 1.0
    }

    /// u at the form circle (fillet / involute junction).
    pub fn u_form(&self) -> f64 {
        self.profile.u_form
    }

    /// u at the tip edge (roll angle of the tip circle).
    pub fn u_tip(&self) -> f64 {
        self.profile.u_tip
    }

    /// Parameter range of u: [u_root, u_tip].
    pub fn u_range(&self) -> (f64, f64) {
        (self.u_root(), self.u_tip())
    }

    /// Parameter range of v = z: [0, b] (mm).
    pub fn v_range(&self) -> (f64, f64) {
        (0.0, self.profile.face_width)
    }

    /// Profile segment of u: involute for u ≥ u_form, else fillet t = u_form − u.
    pub fn segment(&self, u: f64) -> Segment {
        if u >= self.profile.u_form {
            Segment::Involute(u)
        } else {
            Segment::Fillet(self.profile.u_form - u)
        }
    }

    /// Offset o(u, v) (mm, material removed along the normal); 0 unmodified.
    pub fn offset(&self, u: f64, v: f64) -> f64 {
        self.modification
            .as_ref()
            .map_or(0.0, |m| m.offset(self.flank, u, v))
    }

    /// Point of the modified surface (mm).
    pub fn point(&self, u: f64, v: f64) -> V3 {
        let sp = self.profile.surface(self.flank, self.segment(u), v);
        let o = self.offset(u, v);
        self.to_tooth(axpy(-o, sp.n, sp.p))
    }

    /// Unit outward normal of the modified surface.
    pub fn normal(&self, u: f64, v: f64) -> V3 {
        self.to_tooth(self.eval_local(u, v).n)
    }

    /// Partial derivatives (∂P/∂u, ∂P/∂v) of the modified surface (mm/rad, mm/mm).
    pub fn derivatives(&self, u: f64, v: f64) -> (V3, V3) {
        let e = self.eval_local(u, v);
        (self.to_tooth(e.pu), self.to_tooth(e.pv))
    }

    /// Point, unit outward normal and (∂P/∂u, ∂P/∂v) in one evaluation.
    pub fn evaluate(&self, u: f64, v: f64) -> (V3, V3, V3, V3) {
        let e = self.eval_local(u, v);
        (
            self.to_tooth(e.p),
            self.to_tooth(e.n),
            self.to_tooth(e.pu),
            self.to_tooth(e.pv),
        )
    }

    /// Point on the tip edge (u = u_tip) at v.
    pub fn tip_edge(&self, v: f64) -> V3 {
        self.point(self.u_tip(), v)
    }

    /// Point on the form circle (u = u_form) at v.
    pub fn form_circle(&self, v: f64) -> V3 {
        self.point(self.u_form(), v)
    }

    /// Point on the root end of the fillet (u = u_root, on the root circle) at v.
    pub fn root(&self, v: f64) -> V3 {
        self.point(self.u_root(), v)
    }

    /// Points on the two face ends (v = 0 and v = b) at u.
    pub fn ends(&self, u: f64) -> [V3; 2] {
        [self.point(u, 0.0), self.point(u, self.profile.face_width)]
    }

    /// Closest point of the modified surface (within the parameter ranges) to
    /// `p`: (u, v, signed distance), distance > 0 when p lies outside the
    /// material (on the side of the outward normal), < 0 inside.
    ///
    /// Seed: the transverse section through p is turned back by the helix
    /// twist and the nearest of 65 profile points is taken (v = p_z clamped).
    /// Then Gauss–Newton on ½|P(u, v) − p|² with bounds (a variable at a bound
    /// whose gradient points outward is held) and step halving for steps
    /// longer than 1e-6 mm; it stops when a step moves the foot point by less
    /// than 1e-13 mm, after 200 steps, or when no step decreases the distance.
    /// Converges quadratically for points on the surface, linearly (rate ≈
    /// distance × curvature) off it.
    pub fn closest_point(&self, p: V3) -> (f64, f64, f64) {
        let q = self.to_tooth0(p);
        let (u0, v0) = self.seed(q);
        self.newton(q, u0, v0)
    }

    /// [`Self::closest_point`] from a starting parameter (u0, v0) instead of the seed search.
    pub fn closest_point_from(&self, p: V3, u0: f64, v0: f64) -> (f64, f64, f64) {
        let (lo, hi) = self.u_range();
        let b = self.profile.face_width;
        let (u0, v0) = if u0.is_finite() && v0.is_finite() {
            (u0.clamp(lo, hi), v0.clamp(0.0, b))
        } else {
            self.seed(self.to_tooth0(p))
        };
        self.newton(self.to_tooth0(p), u0, v0)
    }

    fn seed(&self, q: V3) -> (f64, f64) {
        let b = self.profile.face_width;
        let v0 = if q[2].is_finite() {
            q[2].clamp(0.0, b)
        } else {
            0.5 * b
        };
        let (s, c) = (-self.profile.twist_rate * v0).sin_cos();
        let x = [c * q[0] - s * q[1], s * q[0] + c * q[1]];
        let (lo, hi) = self.u_range();
        let n = 64;
        let mut best = (f64::INFINITY, 0.5 * (lo + hi));
        for i in 0..=n {
            let u = lo + (hi - lo) * i as f64 / n as f64;
            let pp = self.profile.point(self.flank, self.segment(u)).p;
            let d = (pp[0] - x[0]).hypot(pp[1] - x[1]);
            if d < best.0 {
                best = (d, u);
            }
        }
        (best.1, v0)
    }

    /// Bounded Gauss–Newton in the tooth-0 frame:
    /// [`crate::geometry::surface::closest_point_newton`] on this flank's
    /// tooth-0 view.
    fn newton(&self, q: V3, u0: f64, v0: f64) -> (f64, f64, f64) {
        crate::geometry::surface::closest_point_newton(&ToothZero(self), q, u0, v0)
    }

    /// Modified point in the tooth-0 frame (cheaper than [`Self::eval_local`]).
    fn local_point(&self, u: f64, v: f64) -> V3 {
        let sp = self.profile.surface(self.flank, self.segment(u), v);
        axpy(-self.offset(u, v), sp.n, sp.p)
    }

    /// Transverse profile at u: point, unit normal, dp/du, d²p/du².
    fn profile_d2(&self, u: f64) -> ([f64; 2], [f64; 2], [f64; 2], [f64; 2]) {
        let tp = &self.profile;
        let seg = self.segment(u);
        let q = tp.point(self.flank, seg);
        let mirror = |v: [f64; 2]| match self.flank {
            Flank::Right => v,
            Flank::Left => [-v[0], v[1]],
        };
        match seg {
            Segment::Involute(u) => {
                let rb = tp.geometry.base_radius;
                let (s, c) = (tp.base_half_angle - u).sin_cos();
                let d2 = mirror([rb * (s - u * c), rb * (c + u * s)]);
                (q.p, q.n, tp.tangent(self.flank, seg), d2)
            }
            Segment::Fillet(t) => {
                let h = 1e-3;
                let tg = |d: f64| tp.tangent(self.flank, Segment::Fillet(t + d));
                let (a, b, c, e) = (tg(2.0 * h), tg(h), tg(-h), tg(-2.0 * h));
                let d2 = [0, 1].map(|i| (-a[i] + 8.0 * b[i] - 8.0 * c[i] + e[i]) / (12.0 * h));
                let d1 = tp.tangent(self.flank, seg);
                // d/du = −d/dt, d²/du² = d²/dt²
                (q.p, q.n, [-d1[0], -d1[1]], d2)
            }
        }
    }

    /// Everything in the tooth-0 frame.
    fn eval_local(&self, u: f64, v: f64) -> Eval {
        let tp = &self.profile;
        let seg = self.segment(u);
        let sp = tp.surface(self.flank, seg, v);
        let (rs, rz) = tp.surface_derivatives(self.flank, seg, v);
        let nu = match seg {
            Segment::Involute(_) => rs,
            Segment::Fillet(_) => [-rs[0], -rs[1], -rs[2]],
        };
        let [o, ou, ov] = match &self.modification {
            Some(m) => m.offset_with_gradient(self.flank, u, v),
            None => [0.0; 3],
        };
        if o == 0.0 && ou == 0.0 && ov == 0.0 {
            return Eval {
                p: sp.p,
                n: sp.n,
                pu: nu,
                pv: rz,
            };
        }
        // derivatives of the nominal unit normal
        let (p2, n2, d1, d2) = self.profile_d2(u);
        let k = tp.twist_rate;
        let cr = |a: [f64; 2], b: [f64; 2]| a[0] * b[1] - a[1] * b[0];
        let dn2 = {
            let f = -(n2[0] * d2[0] + n2[1] * d2[1]) / (d1[0] * d1[0] + d1[1] * d1[1]);
            [f * d1[0], f * d1[1]]
        };
        let nz = -k * cr(p2, n2);
        let l = (1.0 + nz * nz).sqrt();
        let dnz = -k * (cr(d1, n2) + cr(p2, dn2));
        let dl = nz * dnz / l;
        let (s, c) = (v * k).sin_cos();
        let rot = |w: [f64; 2]| [c * w[0] - s * w[1], s * w[0] + c * w[1]];
        let rn = rot(n2);
        let rdn = rot(dn2);
        let n_u = [
            rdn[0] / l - rn[0] * dl / (l * l),
            rdn[1] / l - rn[1] * dl / (l * l),
            dnz / l - nz * dl / (l * l),
        ];
        let rjn = rot([-n2[1], n2[0]]);
        let n_v = [k * rjn[0] / l, k * rjn[1] / l, 0.0];
        let n = sp.n;
        let pu = axpy(-o, n_u, axpy(-ou, n, nu));
        let pv = axpy(-o, n_v, axpy(-ov, n, rz));
        let m = cross(pu, pv);
        let lm = norm(m);
        let sgn = if dot(m, n) < 0.0 { -1.0 } else { 1.0 };
        let nm = if lm > 0.0 && lm.is_finite() {
            [sgn * m[0] / lm, sgn * m[1] / lm, sgn * m[2] / lm]
        } else {
            n
        };
        Eval {
            p: axpy(-o, n, sp.p),
            n: nm,
            pu,
            pv,
        }
    }

    /// Tooth-0 frame → this tooth (rotation about z by −2π(k − 1)/z).
    fn to_tooth(&self, w: V3) -> V3 {
        if self.tooth == 1 {
            return w;
        }
        let (s, c) = self.rot;
        [c * w[0] - s * w[1], s * w[0] + c * w[1], w[2]]
    }

    /// This tooth → tooth-0 frame.
    fn to_tooth0(&self, w: V3) -> V3 {
        if self.tooth == 1 {
            return w;
        }
        let (s, c) = self.rot;
        [c * w[0] + s * w[1], -s * w[0] + c * w[1], w[2]]
    }
}

/// A flank seen in its tooth-0 frame (no rotation to the sector tooth):
/// the frame of the closest-point search.
#[derive(Debug)]
struct ToothZero<'a>(&'a FlankSurface);

impl crate::geometry::surface::ToothSurface for ToothZero<'_> {
    fn u_range(&self) -> (f64, f64) {
        self.0.u_range()
    }
    fn v_range(&self) -> (f64, f64) {
        self.0.v_range()
    }
    fn u_tip(&self, _v: f64) -> f64 {
        self.0.u_tip()
    }
    fn u_form(&self, _v: f64) -> f64 {
        self.0.u_form()
    }
    fn u_root(&self, _v: f64) -> f64 {
        self.0.u_root()
    }
    fn point(&self, u: f64, v: f64) -> V3 {
        self.0.local_point(u, v)
    }
    fn normal(&self, u: f64, v: f64) -> V3 {
        self.0.eval_local(u, v).n
    }
    fn derivatives(&self, u: f64, v: f64) -> (V3, V3) {
        let e = self.0.eval_local(u, v);
        (e.pu, e.pv)
    }
    fn evaluate(&self, u: f64, v: f64) -> (V3, V3, V3, V3) {
        let e = self.0.eval_local(u, v);
        (e.p, e.n, e.pu, e.pv)
    }
}

/// The involute flank behind the gear-pair interface: every method is the
/// inherent one of [`FlankSurface`] (u the roll angle, v = z), and the
/// profile length is closed-form: ds = r_b u du (the involute's arc, |P_u|
/// of the helicoid).
impl crate::geometry::surface::ToothSurface for FlankSurface {
    fn u_range(&self) -> (f64, f64) {
        FlankSurface::u_range(self)
    }
    fn v_range(&self) -> (f64, f64) {
        FlankSurface::v_range(self)
    }
    fn u_tip(&self, _v: f64) -> f64 {
        FlankSurface::u_tip(self)
    }
    fn u_form(&self, _v: f64) -> f64 {
        FlankSurface::u_form(self)
    }
    fn u_root(&self, _v: f64) -> f64 {
        FlankSurface::u_root(self)
    }
    fn point(&self, u: f64, v: f64) -> V3 {
        FlankSurface::point(self, u, v)
    }
    fn normal(&self, u: f64, v: f64) -> V3 {
        FlankSurface::normal(self, u, v)
    }
    fn derivatives(&self, u: f64, v: f64) -> (V3, V3) {
        FlankSurface::derivatives(self, u, v)
    }
    fn evaluate(&self, u: f64, v: f64) -> (V3, V3, V3, V3) {
        FlankSurface::evaluate(self, u, v)
    }
    fn tip_edge(&self, v: f64) -> V3 {
        FlankSurface::tip_edge(self, v)
    }
    fn closest_point(&self, p: V3) -> (f64, f64, f64) {
        FlankSurface::closest_point(self, p)
    }
    fn closest_point_from(&self, p: V3, u0: f64, v0: f64) -> (f64, f64, f64) {
        FlankSurface::closest_point_from(self, p, u0, v0)
    }
    fn profile_length(&self, du: f64, u: f64, _v: f64) -> f64 {
        du * self.profile().geometry.base_radius * u.max(1e-3)
    }
    fn profile_step(&self, length: f64, u: f64, _v: f64) -> f64 {
        length / (self.profile().geometry.base_radius * u.max(1e-3))
    }
}

#[cfg(test)]
mod tests {
    use super::super::micro::test_gears::gear;
    use super::super::micro::{MicroGeometry, Relief, ReliefShape};
    use super::*;

    const FLANKS: [Flank; 2] = [Flank::Left, Flank::Right];
    const SCENES: [(&str, usize); 3] = [
        ("seed002-spur", 0),
        ("seed002-spur", 1),
        ("seed004-helical", 0),
    ];

    fn all_terms() -> MicroGeometry {
        let r = |amount, length, shape| {
            Some(Relief {
                amount,
                length,
                shape,
            })
        };
        MicroGeometry {
            tip_relief: r(0.012, 1.0, ReliefShape::Parabolic),
            root_relief: r(0.006, 0.8, ReliefShape::Linear),
            profile_crowning: 0.004,
            lead_crowning: 0.010,
            helix_slope_deviation: 0.007,
            end_relief: r(0.005, 2.0, ReliefShape::Parabolic),
            measured_profile: None,
        }
    }

    fn surface(
        scene: &str,
        which: usize,
        flank: Flank,
        tooth: usize,
        m: Option<&MicroGeometry>,
    ) -> FlankSurface {
        let (tp, u_sap) = gear(scene, which);
        let fm = m.map(|m| FlankModification::new(m, &tp, u_sap, tp.face_width).unwrap());
        FlankSurface::new(tp, flank, tooth, fm).unwrap()
    }

    /// Parameter samples away from the offset's kinks (u_SAP, zone starts, form circle).
    fn samples(fs: &FlankSurface) -> Vec<(f64, f64)> {
        let (lo, hi) = fs.u_range();
        let b = fs.v_range().1;
        let mut out = Vec::new();
        for i in 0..13 {
            let u = lo + (hi - lo) * (i as f64 + 0.29) / 13.0;
            for j in 0..5 {
                out.push((u, b * (j as f64 + 0.37) / 5.0));
            }
        }
        out
    }

    fn sub(a: V3, b: V3) -> V3 {
        [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
    }

    #[test]
    fn zero_modification_is_the_profile_surface_exactly() {
        for (scene, which) in SCENES {
            let (tp, u_sap) = gear(scene, which);
            let zero = FlankModification::new(&MicroGeometry::default(), &tp, u_sap, tp.face_width)
                .unwrap();
            for f in FLANKS {
                for m in [None, Some(zero.clone())] {
                    let fs = FlankSurface::new(tp.clone(), f, 1, m).unwrap();
                    for u in [
                        fs.u_root(),
                        fs.u_form() - 0.37,
                        fs.u_form(),
                        0.5 * (fs.u_form() + fs.u_tip()),
                        fs.u_tip(),
                    ] {
                        for v in [0.0, 0.3 * tp.face_width, tp.face_width] {
                            let seg = if u >= tp.u_form {
                                Segment::Involute(u)
                            } else {
                                Segment::Fillet(tp.u_form - u)
                            };
                            let sp = tp.surface(f, seg, v);
                            assert_eq!(fs.point(u, v), sp.p);
                            assert_eq!(fs.normal(u, v), sp.n);
                        }
                    }
                }
                // another tooth: the same surface turned by −2π(k − 1)/z
                let fs = FlankSurface::new(tp.clone(), f, 3, None).unwrap();
                let a = -2.0 * tp.angular_pitch();
                let (s, c) = a.sin_cos();
                let u = 0.5 * (fs.u_form() + fs.u_tip());
                let sp = tp.surface(f, Segment::Involute(u), 4.0);
                let p = fs.point(u, 4.0);
                let want = [
                    c * sp.p[0] - s * sp.p[1],
                    s * sp.p[0] + c * sp.p[1],
                    sp.p[2],
                ];
                assert!(norm(sub(p, want)) < 1e-12);
            }
        }
    }

    #[test]
    fn offset_is_along_the_nominal_normal() {
        let m = all_terms();
        for (scene, which) in SCENES {
            for f in FLANKS {
                let fs = surface(scene, which, f, 2, Some(&m));
                let nominal = surface(scene, which, f, 2, None);
                for (u, v) in samples(&fs) {
                    let d = sub(nominal.point(u, v), fs.point(u, v));
                    let n = nominal.normal(u, v);
                    let o = fs.offset(u, v);
                    assert!(norm(sub(d, [o * n[0], o * n[1], o * n[2]])) < 1e-13);
                }
            }
        }
    }

    /// Exact derivatives against 4th-order central differences of the point;
    /// normals unit and orthogonal to both derivatives.
    #[test]
    fn derivatives_and_normals() {
        let m = all_terms();
        let mut worst_fd: f64 = 0.0;
        let mut worst_orth: f64 = 0.0;
        for (scene, which) in SCENES {
            for f in FLANKS {
                for tooth in [1, 2] {
                    for mm in [None, Some(&m)] {
                        let fs = surface(scene, which, f, tooth, mm);
                        for (u, v) in samples(&fs) {
                            let (pu, pv) = fs.derivatives(u, v);
                            let n = fs.normal(u, v);
                            let fd = |g: &dyn Fn(f64) -> V3, h: f64| {
                                let (a, b, c, e) = (g(2.0 * h), g(h), g(-h), g(-2.0 * h));
                                [0, 1, 2]
                                    .map(|i| (-a[i] + 8.0 * b[i] - 8.0 * c[i] + e[i]) / (12.0 * h))
                            };
                            let pu_fd = fd(&|d| fs.point(u + d, v), 1e-4);
                            let pv_fd = fd(&|d| fs.point(u, v + d), 1e-2);
                            let eu = norm(sub(pu, pu_fd)) / norm(pu);
                            let ev = norm(sub(pv, pv_fd)) / norm(pv);
                            worst_fd = worst_fd.max(eu).max(ev);
                            assert!(
                                eu < 1e-8 && ev < 1e-8,
                                "{scene} {f:?} u = {u} v = {v}: {eu:e} {ev:e}"
                            );
                            assert!((norm(n) - 1.0).abs() < 1e-14);
                            let o = (dot(n, pu) / norm(pu))
                                .abs()
                                .max((dot(n, pv) / norm(pv)).abs());
                            worst_orth = worst_orth.max(o);
                            assert!(o <= 1e-10, "{o:e}");
                            // outward: on the side of the nominal normal
                            let nn = surface(scene, which, f, tooth, None).normal(u, v);
                            assert!(dot(n, nn) > 0.99);
                        }
                    }
                }
            }
        }
        eprintln!("derivatives vs FD: {worst_fd:.2e} relative; |n·P_u|, |n·P_v|: {worst_orth:.2e}");
    }

    /// The modified normal differs from the nominal by the offset gradient: for
    /// a spur gear with lead crowning only, n·e_z = −∂o/∂z / |…| to first order.
    #[test]
    fn modified_normal_tilts_with_the_offset_gradient() {
        let m = MicroGeometry {
            lead_crowning: 0.02,
            ..Default::default()
        };
        let fs = surface("seed002-spur", 0, Flank::Right, 1, Some(&m));
        let b = fs.v_range().1;
        let u = 0.5 * (fs.u_form() + fs.u_tip());
        for v in [0.0, 0.25 * b, 0.5 * b, b] {
            let [_, _, oz] = fs
                .modification()
                .unwrap()
                .offset_with_gradient(Flank::Right, u, v);
            let n = fs.normal(u, v);
            // P_v = e_z − o_z n₀ ⟂ n  ⇒  n_z = o_z (n·n₀) ⇒ n_z = o_z / √(1 + o_z²)
            let want = oz / (1.0 + oz * oz).sqrt();
            assert!((n[2] - want).abs() < 1e-12, "{} vs {want}", n[2]);
        }
    }

    #[test]
    fn boundaries() {
        for (scene, which) in SCENES {
            let fs = surface(scene, which, Flank::Left, 2, None);
            let g = &fs.profile().geometry;
            let rad = |p: V3| p[0].hypot(p[1]);
            for v in [0.0, 0.5 * fs.v_range().1] {
                assert!((rad(fs.tip_edge(v)) - g.tip_radius).abs() < 1e-10);
                assert!((rad(fs.form_circle(v)) - g.form_radius).abs() < 1e-10);
                assert!((rad(fs.root(v)) - g.root_radius).abs() < 1e-10);
            }
            let [a, b] = fs.ends(fs.u_form());
            assert_eq!((a[2], b[2]), (0.0, fs.profile().face_width));
            assert_eq!(fs.u_range(), (fs.u_form() - 1.0, fs.u_tip()));
        }
    }

    #[test]
    fn closest_point_round_trip() {
        let m = all_terms();
        let mut worst: f64 = 0.0;
        let mut n = 0;
        let t0 = std::time::Instant::now();
        for (scene, which) in SCENES {
            for f in FLANKS {
                for tooth in [1, 3] {
                    for mm in [None, Some(&m)] {
                        let fs = surface(scene, which, f, tooth, mm);
                        let (lo, hi) = fs.u_range();
                        let b = fs.v_range().1;
                        for i in 0..9 {
                            let u = lo + (hi - lo) * (i as f64 + 0.31) / 9.0;
                            for v in [0.0, 0.37 * b, b] {
                                for d in [0.0, 0.03, -0.03] {
                                    let p = fs.point(u, v);
                                    let nn = fs.normal(u, v);
                                    let q = axpy(d, nn, p);
                                    let (u2, v2, d2) = fs.closest_point(q);
                                    let e = norm(sub(fs.point(u2, v2), p)).max((d2 - d).abs());
                                    worst = worst.max(e);
                                    n += 1;
                                    assert!(e <= 1e-9, "{scene} {f:?} tooth {tooth} u = {u} v = {v} d = {d}: {e:e} (u2 = {u2}, v2 = {v2}, d2 = {d2})");
                                }
                            }
                        }
                    }
                }
            }
        }
        eprintln!(
            "closest point: {n} round trips, worst {worst:.2e} mm, {:.1} µs each (with the checks)",
            t0.elapsed().as_secs_f64() * 1e6 / n as f64
        );
    }

    #[test]
    fn closest_point_outside_the_patch_and_odd_input() {
        let fs = surface("seed002-spur", 0, Flank::Right, 1, Some(&all_terms()));
        let b = fs.v_range().1;
        // beyond the face end: the foot is on the end edge v = b
        let u = 0.5 * (fs.u_form() + fs.u_tip());
        let p = fs.point(u, b);
        let (u2, v2, d2) = fs.closest_point([p[0], p[1], p[2] + 1.0]);
        assert!((u2 - u).abs() < 1e-9 && v2 == b && (d2.abs() - 1.0).abs() < 1e-9);
        // beyond the tip: the foot is on the tip edge
        let t = fs.tip_edge(3.0);
        let (u3, _, _) = fs.closest_point([t[0] * 1.05, t[1] * 1.05, 3.0]);
        assert_eq!(u3, fs.u_tip());
        // no panic on nonsense
        for q in [
            [f64::NAN, 0.0, 0.0],
            [f64::INFINITY, 1.0, 2.0],
            [0.0, 0.0, 0.0],
            [1e9, -1e9, 5.0],
        ] {
            let _ = fs.closest_point(q);
            let _ = fs.closest_point_from(q, f64::NAN, 0.0);
        }
        // a warm start from a nearby parameter gives the same answer
        let q = axpy(0.01, fs.normal(u, 4.0), fs.point(u, 4.0));
        let (a, bb, c) = fs.closest_point_from(q, u + 0.05, 5.0);
        assert!((a - u).abs() < 1e-10 && (bb - 4.0).abs() < 1e-9 && (c - 0.01).abs() < 1e-10);
    }

    /// f_Hβ > 0 turns the tooth counter-clockwise (seen from +z) as z grows, by
    /// f_Hβ/(r_b cos β_b) over the face: the modified flanks lie on the nominal
    /// tooth turned by Δφ(z) = f_Hβ (z − b/2)/(b r_b cos β_b) (to O(f²)).
    #[test]
    fn helix_slope_is_a_rigid_twist() {
        let mut worst: f64 = 0.0;
        for (scene, which) in SCENES {
            for fh in [0.01, -0.01] {
                let m = MicroGeometry {
                    helix_slope_deviation: fh,
                    ..Default::default()
                };
                for f in FLANKS {
                    let fs = surface(scene, which, f, 1, Some(&m));
                    let nominal = surface(scene, which, f, 1, None);
                    let g = &fs.profile().geometry;
                    let b = fs.v_range().1;
                    let k = fh / (b * g.base_radius * g.base_helix_angle.cos());
                    for (u, v) in samples(&fs) {
                        if u < fs.u_form() {
                            continue;
                        }
                        let p = fs.point(u, v);
                        let dphi = -k * (p[2] - 0.5 * b); // turn back
                        let (s, c) = dphi.sin_cos();
                        let q = [c * p[0] - s * p[1], s * p[0] + c * p[1], p[2]];
                        let (_, _, d) = nominal.closest_point(q);
                        worst = worst.max(d.abs());
                        assert!(d.abs() < 2e-7, "{scene} {f:?} f = {fh}: {d:e}");
                    }
                }
            }
        }
        eprintln!("f_Hβ = ±10 µm as a rigid twist: worst distance {worst:.2e} mm");
    }

    #[test]
    fn bad_construction() {
        let (tp, u_sap) = gear("seed002-spur", 0);
        assert!(FlankSurface::new(tp.clone(), Flank::Left, 0, None).is_err());
        assert!(FlankSurface::new(tp.clone(), Flank::Left, 14, None).is_err());
        assert!(FlankSurface::new(tp.clone(), Flank::Left, 13, None).is_ok());
        let (other, u2) = gear("seed002-spur", 1);
        let fm = FlankModification::new(&MicroGeometry::default(), &other, u2, other.face_width)
            .unwrap();
        let e = FlankSurface::new(tp.clone(), Flank::Left, 1, Some(fm)).unwrap_err();
        assert!(e.to_string().contains("another gear"), "{e}");
        let _ = u_sap;
    }
}
