//! Rack-generated tooth profile and helical flank surface, exact.
//!
//! The transverse profile of one tooth is the envelope of the generating rack
//! (ISO 53 type: straight flanks at α_n, tip rounding ρ_fP* m_n) rolling on the
//! reference circle, shifted out by x m_n (ISO 21771:2007 generating rack;
//! Litvin & Fuentes, *Gear Geometry and Applied Theory*, 2nd ed., 2004,
//! chapters on conjugated curves and on involute gears). The envelope point of
//! each rack point is found with Willis' theorem: the common normal passes
//! through the pitch point (Litvin & Fuentes, conjugated curves, method of the
//! instantaneous centre). The rack's straight flank generates the involute,
//! its tip rounding the trochoidal root fillet; both meet at the form circle
//! with a common point and normal by construction.
//!
//! Helical gears: the rack tooth is a cylinder along the tooth direction, so
//! its transverse section has flanks at α_t and its rounding is an ellipse with
//! semi-axes ρ/cos β (along the pitch line) and ρ (height). The 3D flank is the
//! transverse profile swept along the helix (Litvin & Fuentes, involute
//! helical gears).
//!
//! Frame (mm): gear axis z, transverse plane x–y. Tooth 0 is symmetric about
//! the +y axis; its RIGHT flank lies at x > 0, its LEFT flank is the mirror
//! image x → −x. Tooth k is tooth 0 rotated by −2πk/z (clockwise, towards +x).
//! Angles "from the centre line" are polar angles from +y, positive towards +x.
//! Normals point out of the tooth material.

use super::involute::{self, GearGeometry};
use super::{GearSpec, Hand};
use crate::error::FlankError;
use std::f64::consts::PI;

type Result<T> = std::result::Result<T, FlankError>;

/// Which flank of the tooth.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Flank {
    Left,
    Right,
}

/// A parameter on the active profile of one flank.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub enum Segment {
    /// Involute, by roll angle u (rad): radius r_b √(1 + u²); flank range [u_form, u_tip].
    Involute(f64),
    /// Root fillet, t ∈ [0, 1]: 0 at the form circle (joins the involute), 1 at the root circle.
    Fillet(f64),
}

/// A point of the transverse profile with its unit outward normal.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct ProfilePoint {
    pub p: [f64; 2],
    pub n: [f64; 2],
}

/// A point of a 3D flank surface with its unit outward normal.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct SurfacePoint {
    pub p: [f64; 3],
    pub n: [f64; 3],
}

/// The rack-generated tooth of one gear (transverse profile and helical flanks).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct ToothProfile {
    pub geometry: GearGeometry,
    /// Half the angular thickness at the base circle, ψ_b = s_t/(2r) + inv α_t.
    pub base_half_angle: f64,
    /// Roll angle of the form point (start of the involute) and of the tip.
    pub u_form: f64,
    pub u_tip: f64,
    /// Half angle of the tip land, s_at / (2 r_a), from the centre line.
    pub tip_half_angle: f64,
    /// Angle from the centre line where the right fillet reaches the root circle;
    /// the root arc runs from it to 2π/z minus it (towards tooth 1).
    pub root_angle: f64,
    /// Twist rate of the transverse section along the axis, dφ/dz = ±tan β / r (rad/mm):
    /// + (counter-clockwise seen from +z) for a right hand, − for a left hand.
    pub twist_rate: f64,
    /// Face width b (mm): the surfaces span z ∈ [0, b].
    pub face_width: f64,
    teeth: u32,
    r: f64,
    cos_beta: f64,
    /// Rack tip rounding, transverse rack frame: centre (X_c, Y_c), normal radius ρ.
    rack_xc_n: f64,
    rack_yc: f64,
    rho: f64,
    alpha_n: f64,
}

fn normalize2(v: [f64; 2]) -> [f64; 2] {
    let l = v[0].hypot(v[1]);
    [v[0] / l, v[1] / l]
}

impl ToothProfile {
    /// Build the profile of `g` (validated by [`GearGeometry::new`], which refuses
    /// undercut, pointed and otherwise unrepresentable teeth); `name` (e.g. "pinion")
    /// goes into error messages.
    pub fn new(g: &GearSpec, name: &str) -> Result<Self> {
        let geometry = GearGeometry::new(g, name)?;
        let mn = g.normal_module;
        let an = g.normal_pressure_angle;
        let r = geometry.reference_radius;
        let rb = geometry.base_radius;
        let rho = g.rack.tip_radius * mn;
        // Rack frame (normal section, X_n along the pitch line, Y outward from the rolling
        // line): right rack flank X_n = p_n/4 + (x m_n − Y) tan α_n, tip line at
        // Y_tip = (x − h_fP*) m_n; rounding centre at distance ρ from both.
        let y_tip = (g.profile_shift - g.rack.addendum) * mn;
        let yc = y_tip + rho;
        let c = PI * mn / 4.0 + g.profile_shift * mn * an.tan();
        let xc_n = c + (rho - yc * an.sin()) / an.cos();
        let u_form = involute::form_roll_length(g) / rb;
        let u_tip = ((geometry.tip_radius / rb).powi(2) - 1.0).sqrt();
        let base_half_angle = involute::base_half_angle(g);
        let tip_half_angle = geometry.tip_thickness_transverse / (2.0 * geometry.tip_radius);
        let cos_beta = g.helix_angle.cos();
        let root_angle = xc_n / cos_beta / r;
        let sign = match g.hand {
            Hand::Right => 1.0,
            Hand::Left => -1.0,
        };
        let twist_rate = sign * g.helix_angle.tan() / r;
        let out = ToothProfile {
            geometry,
            base_half_angle,
            u_form,
            u_tip,
            tip_half_angle,
            root_angle,
            twist_rate,
            face_width: g.face_width,
            teeth: g.teeth,
            r,
            cos_beta,
            rack_xc_n: xc_n,
            rack_yc: yc,
            rho,
            alpha_n: an,
        };
        if !(u_form.is_finite() && u_tip > u_form && root_angle < PI / g.teeth as f64 + 1e-12) {
            return Err(FlankError::Model(format!(
                "{name} profile: inconsistent generation (u_form = {u_form}, u_tip = {u_tip}, root angle = {root_angle} rad)"
            )));
        }
        Ok(out)
    }

    /// Angular pitch 2π/z.
    pub fn angular_pitch(&self) -> f64 {
        2.0 * PI / self.teeth as f64
    }

    /// Involute of the right flank at roll angle u (ISO 21771:2007; Litvin & Fuentes, spur involute gears):
    /// with φ_T = ψ_b − u (base tangent point, from the centre line),
    /// p = r_b [e_r(φ_T) + u e_φ(φ_T)], n = e_φ(φ_T), e_r = (sin φ, cos φ), e_φ = (cos φ, −sin φ).
    fn involute_right(&self, u: f64) -> ProfilePoint {
        let rb = self.geometry.base_radius;
        let ph = self.base_half_angle - u;
        let (s, c) = ph.sin_cos();
        ProfilePoint {
            p: [rb * (s + u * c), rb * (c - u * s)],
            n: [c, -s],
        }
    }

    /// Envelope point of a rack point (X, Y) with normal N (transverse rack frame) by
    /// Willis' theorem: the gear has turned by φ = X_I / r with X_I = X − Y N_X / N_Y,
    /// and the point is R(−φ)(X − rφ, r + Y).
    fn generate(&self, x: f64, y: f64, nx: f64, ny: f64) -> ProfilePoint {
        let xi = x - y * nx / ny;
        let phi = xi / self.r;
        let (s, c) = phi.sin_cos();
        let (px, py) = (x - self.r * phi, self.r + y);
        ProfilePoint {
            p: [c * px + s * py, -s * px + c * py],
            n: normalize2([c * nx + s * ny, -s * nx + c * ny]),
        }
    }

    /// Right root fillet, t ∈ [0, 1]: the envelope of the rack tip rounding. In the
    /// normal section the rounding point at θ = α_n + t(π/2 − α_n) is
    /// (X_c − ρ cos θ, Y_c − ρ sin θ) with normal (cos θ, sin θ); the transverse section
    /// divides X by cos β (normal ∝ (cos θ, sin θ / cos β)).
    fn fillet_right(&self, t: f64) -> ProfilePoint {
        let th = self.alpha_n + t * (PI / 2.0 - self.alpha_n);
        let (s, c) = th.sin_cos();
        let x = (self.rack_xc_n - self.rho * c) / self.cos_beta;
        let y = self.rack_yc - self.rho * s;
        let n = normalize2([c, s / self.cos_beta]);
        self.generate(x, y, n[0], n[1])
    }

    /// d/dt of the right fillet point, analytic: with the rack point (X, Y)(θ) and
    /// φ(θ) = (X − Y N_X/N_Y)/r, dp/dθ = R(−φ)(X′ + φ′Y, Y′ − φ′(X − rφ)), dθ/dt = π/2 − α_n.
    fn fillet_right_tangent(&self, t: f64) -> [f64; 2] {
        let dth = PI / 2.0 - self.alpha_n;
        let th = self.alpha_n + t * dth;
        let (s, c) = th.sin_cos();
        let cb = self.cos_beta;
        let x = (self.rack_xc_n - self.rho * c) / cb;
        let y = self.rack_yc - self.rho * s;
        let (xp, yp) = (self.rho * s / cb, -self.rho * c);
        // N_X / N_Y = cos β cot θ
        let q = cb * c / s;
        let qp = -cb / (s * s);
        let phi = (x - y * q) / self.r;
        let phip = (xp - yp * q - y * qp) / self.r;
        let (a, b) = (xp + phip * y, yp - phip * (x - self.r * phi));
        let (sp, cp) = phi.sin_cos();
        [dth * (cp * a + sp * b), dth * (-sp * a + cp * b)]
    }

    /// Derivative dp/ds of a flank's transverse profile with respect to its parameter
    /// (u on the involute: r_b u e_r(φ_T); t on the fillet). Zero at u = 0 (the cusp).
    pub fn tangent(&self, flank: Flank, seg: Segment) -> [f64; 2] {
        let d = match seg {
            Segment::Involute(u) => {
                let ph = self.base_half_angle - u;
                let rb = self.geometry.base_radius;
                [rb * u * ph.sin(), rb * u * ph.cos()]
            }
            Segment::Fillet(t) => self.fillet_right_tangent(t),
        };
        match flank {
            Flank::Right => d,
            Flank::Left => [-d[0], d[1]],
        }
    }

    /// Partial derivatives (r_s, r_z) of the flank surface [`Self::surface`]:
    /// r_s = R_z(φ)(p′, 0), r_z = R_z(φ)(φ′ J p, 0) + e_z, J p = (−p_y, p_x).
    pub fn surface_derivatives(&self, flank: Flank, seg: Segment, z: f64) -> ([f64; 3], [f64; 3]) {
        let q = self.point(flank, seg);
        let d = self.tangent(flank, seg);
        let k = self.twist_rate;
        let (s, c) = (z * k).sin_cos();
        let rot = |v: [f64; 2]| [c * v[0] - s * v[1], s * v[0] + c * v[1]];
        let a = rot(d);
        let b = rot([-k * q.p[1], k * q.p[0]]);
        ([a[0], a[1], 0.0], [b[0], b[1], 1.0])
    }

    /// Point and outward normal of a flank's transverse profile (tooth 0, z = 0).
    pub fn point(&self, flank: Flank, seg: Segment) -> ProfilePoint {
        let q = match seg {
            Segment::Involute(u) => self.involute_right(u),
            Segment::Fillet(t) => self.fillet_right(t),
        };
        match flank {
            Flank::Right => q,
            Flank::Left => ProfilePoint {
                p: [-q.p[0], q.p[1]],
                n: [-q.n[0], q.n[1]],
            },
        }
    }

    /// Involute point at radius r_y (≥ r_b): roll angle u = √(r_y²/r_b² − 1).
    pub fn point_at_radius(&self, flank: Flank, r_y: f64) -> Result<ProfilePoint> {
        let rb = self.geometry.base_radius;
        if !(r_y.is_finite() && r_y >= rb) {
            return Err(FlankError::Model(format!(
                "profile point at radius {r_y} mm: the involute exists only at radii ≥ r_b = {rb:.6} mm"
            )));
        }
        Ok(self.point(flank, Segment::Involute(((r_y / rb).powi(2) - 1.0).sqrt())))
    }

    /// Tip circle arc, s ∈ [−1, 1] from the left to the right flank's tip corner.
    pub fn tip_arc(&self, s: f64) -> ProfilePoint {
        let a = s * self.tip_half_angle;
        let (sn, c) = a.sin_cos();
        let ra = self.geometry.tip_radius;
        ProfilePoint {
            p: [ra * sn, ra * c],
            n: [sn, c],
        }
    }

    /// Root circle arc, s ∈ [0, 1] from the right fillet's end of tooth 0 to the left
    /// fillet's end of tooth 1.
    pub fn root_arc(&self, s: f64) -> ProfilePoint {
        let a0 = self.root_angle;
        let a = a0 + s * (self.angular_pitch() - 2.0 * a0);
        let (sn, c) = a.sin_cos();
        let rf = self.geometry.root_radius;
        ProfilePoint {
            p: [rf * sn, rf * c],
            n: [sn, c],
        }
    }

    /// Rotate a transverse point by the angle of tooth k (−2πk/z, clockwise).
    pub fn on_tooth(&self, q: ProfilePoint, k: i64) -> ProfilePoint {
        let a = -(k as f64) * self.angular_pitch();
        let (s, c) = a.sin_cos();
        ProfilePoint {
            p: [c * q.p[0] - s * q.p[1], s * q.p[0] + c * q.p[1]],
            n: [c * q.n[0] - s * q.n[1], s * q.n[0] + c * q.n[1]],
        }
    }

    /// Flank surface r(s, z) = R_z(φ(z)) p(s) + z e_z with φ(z) = z · twist_rate
    /// (helicoid: tan β / r = tan β_b / r_b; Litvin & Fuentes, helical gears), z ∈ [0, b]. Unit normal from
    /// r_s × r_z in closed form: R_z(φ)(n_x, n_y, −φ′ (p × n)_z), normalized.
    pub fn surface(&self, flank: Flank, seg: Segment, z: f64) -> SurfacePoint {
        let q = self.point(flank, seg);
        let k = self.twist_rate;
        let (s, c) = (z * k).sin_cos();
        let nz = -k * (q.p[0] * q.n[1] - q.p[1] * q.n[0]);
        let l = (1.0 + nz * nz).sqrt();
        SurfacePoint {
            p: [c * q.p[0] - s * q.p[1], s * q.p[0] + c * q.p[1], z],
            n: [
                (c * q.n[0] - s * q.n[1]) / l,
                (s * q.n[0] + c * q.n[1]) / l,
                nz / l,
            ],
        }
    }

    /// Transverse arc tooth thickness measured on the profile at radius r_y (involute part):
    /// 2 r_y × (polar angle of the right flank point from the centre line).
    pub fn measured_thickness(&self, r_y: f64) -> Result<f64> {
        let q = self.point_at_radius(Flank::Right, r_y)?;
        Ok(2.0 * r_y * q.p[0].atan2(q.p[1]))
    }
}

/// Transverse pressure angle at the form circle, cos α_F = r_b / r_F (ISO 21771:2007).
pub fn form_pressure_angle(p: &ToothProfile) -> f64 {
    (p.geometry.base_radius / p.geometry.form_radius).acos()
}

#[cfg(test)]
mod tests {
    use super::super::{Hand, RackProfile};
    use super::*;

    fn spec(z: u32, m: f64, x: f64, beta_deg: f64, hand: Hand) -> GearSpec {
        GearSpec {
            teeth: z,
            normal_module: m,
            normal_pressure_angle: 20f64.to_radians(),
            helix_angle: beta_deg.to_radians(),
            hand,
            face_width: 20.0,
            profile_shift: x,
            rack: RackProfile::default(),
            tip_diameter: None,
            bore_diameter: 0.0,
        }
    }

    fn cases() -> Vec<GearSpec> {
        vec![
            spec(20, 4.0, 0.0, 0.0, Hand::Right),
            spec(13, 3.8, 0.25, 0.0, Hand::Right),
            spec(35, 3.8, -0.549317, 0.0, Hand::Right),
            spec(21, 15.0, 0.0, 20.0, Hand::Right),
            spec(37, 15.0, 0.3, 20.0, Hand::Left),
        ]
    }

    fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
        a[0] * b[0] + a[1] * b[1]
    }

    fn norm(a: [f64; 2]) -> f64 {
        a[0].hypot(a[1])
    }

    #[test]
    fn involute_radius_normal_and_thickness() {
        for g in cases() {
            let tp = ToothProfile::new(&g, "gear").unwrap();
            let geo = &tp.geometry;
            for i in 0..=20 {
                let ry = geo.form_radius + (geo.tip_radius - geo.form_radius) * i as f64 / 20.0;
                for f in [Flank::Left, Flank::Right] {
                    let q = tp.point_at_radius(f, ry).unwrap();
                    assert!((norm(q.p) - ry).abs() < 1e-12 * ry);
                    assert!((norm(q.n) - 1.0).abs() < 1e-14);
                    // tangent by central differences in u
                    let u = ((ry / geo.base_radius).powi(2) - 1.0).sqrt();
                    let h = (1e-3 * u).min(1e-5); // balances rounding and truncation near the base circle
                    let a = tp.point(f, Segment::Involute(u + h)).p;
                    let b = tp.point(f, Segment::Involute(u - h)).p;
                    let t = [a[0] - b[0], a[1] - b[1]];
                    let c = dot(t, q.n).abs() / norm(t);
                    assert!(c < 1e-7, "u = {u}: cos(tangent, normal) = {c}");
                    // outward: the normal points away from the centre line
                    let side = if f == Flank::Right { 1.0 } else { -1.0 };
                    assert!(side * q.n[0] > 0.0);
                }
                let s = tp.measured_thickness(ry).unwrap();
                let s_formula = involute::thickness_at_radius(&g, ry).unwrap();
                assert!((s - s_formula).abs() < 1e-11, "{s} vs {s_formula}");
            }
            let s_ref = tp.measured_thickness(geo.reference_radius).unwrap();
            assert!((s_ref - involute::reference_thickness(&g)).abs() < 1e-11);
            // tip corner
            let corner = tp.point(Flank::Right, Segment::Involute(tp.u_tip)).p;
            let tip = tp.tip_arc(1.0).p;
            assert!((corner[0] - tip[0]).abs() < 1e-10 && (corner[1] - tip[1]).abs() < 1e-10);
        }
    }

    /// Independent path: the involute as the envelope of the rack's straight flank.
    #[test]
    fn involute_is_the_envelope_of_the_straight_rack_flank() {
        for g in cases() {
            let tp = ToothProfile::new(&g, "gear").unwrap();
            let at = tp.geometry.transverse_pressure_angle;
            let mn = g.normal_module;
            let pt = PI * tp.geometry.transverse_module;
            for i in 0..10 {
                let y = (g.profile_shift - 1.0) * mn + i as f64 * 0.2 * mn;
                let x = pt / 4.0 + (g.profile_shift * mn - y) * at.tan();
                let q = tp.generate(x, y, at.cos(), at.sin());
                let ry = norm(q.p);
                let e = tp.point_at_radius(Flank::Right, ry).unwrap();
                assert!((q.p[0] - e.p[0]).abs() < 1e-10 && (q.p[1] - e.p[1]).abs() < 1e-10);
                assert!((dot(q.n, e.n) - 1.0).abs() < 1e-13);
            }
        }
    }

    #[test]
    fn fillet_joins_involute_and_reaches_root() {
        for g in cases() {
            let tp = ToothProfile::new(&g, "gear").unwrap();
            for f in [Flank::Left, Flank::Right] {
                let a = tp.point(f, Segment::Involute(tp.u_form));
                let b = tp.point(f, Segment::Fillet(0.0));
                assert!((a.p[0] - b.p[0]).abs() < 1e-10 && (a.p[1] - b.p[1]).abs() < 1e-10);
                assert!(
                    (dot(a.n, b.n) - 1.0).abs() < 1e-13,
                    "tangent at the form circle"
                );
                assert!((norm(a.p) - tp.geometry.form_radius).abs() < 1e-10);
                let e = tp.point(f, Segment::Fillet(1.0));
                assert!((norm(e.p) - tp.geometry.root_radius).abs() < 1e-10);
                // radial normal at the root, ending where the root arc starts
                assert!((dot(e.n, normalize2(e.p)) - 1.0).abs() < 1e-13);
                let ra = tp.root_arc(0.0).p;
                if f == Flank::Right {
                    assert!((ra[0] - e.p[0]).abs() < 1e-10 && (ra[1] - e.p[1]).abs() < 1e-10);
                }
                // along the fillet: normal ⟂ tangent, radius decreasing
                let mut r_prev = f64::INFINITY;
                for i in 0..=50 {
                    let t = (i as f64 / 50.0).clamp(1e-5, 1.0 - 1e-5);
                    let q = tp.point(f, Segment::Fillet(t));
                    let h = 1e-6;
                    let p1 = tp.point(f, Segment::Fillet(t + h)).p;
                    let p0 = tp.point(f, Segment::Fillet(t - h)).p;
                    let tg = [p1[0] - p0[0], p1[1] - p0[1]];
                    let c = dot(tg, q.n).abs() / norm(tg);
                    assert!(c < 1e-7, "t = {t}: cos(tangent, normal) = {c}");
                    let rr = norm(q.p);
                    assert!(rr <= r_prev + 1e-12);
                    r_prev = rr;
                }
            }
            // the next tooth's left fillet ends where the root arc ends
            let e = tp
                .on_tooth(tp.point(Flank::Left, Segment::Fillet(1.0)), 1)
                .p;
            let ra = tp.root_arc(1.0).p;
            assert!((ra[0] - e[0]).abs() < 1e-10 && (ra[1] - e[1]).abs() < 1e-10);
        }
    }

    /// Newton: the point of `flank` on tooth k on the line p + s n (transverse).
    fn hit(tp: &ToothProfile, flank: Flank, k: i64, p: [f64; 2], n: [f64; 2], u0: f64) -> [f64; 2] {
        let f = |u: f64| {
            let q = tp.on_tooth(tp.point(flank, Segment::Involute(u)), k).p;
            (q[0] - p[0]) * n[1] - (q[1] - p[1]) * n[0]
        };
        let mut u = u0;
        for _ in 0..50 {
            let h = 1e-7;
            let d = (f(u + h) - f(u - h)) / (2.0 * h);
            let du = f(u) / d;
            u -= du;
            if du.abs() < 1e-15 {
                break;
            }
        }
        tp.on_tooth(tp.point(flank, Segment::Involute(u)), k).p
    }

    #[test]
    fn base_pitch_between_neighbouring_flanks() {
        for g in cases() {
            let tp = ToothProfile::new(&g, "gear").unwrap();
            // From the tip of tooth 0 along −n to the right flank of tooth −1: a base
            // tangent crosses every involute of the base circle at right angles.
            let u = tp.u_tip;
            let q = tp.point(Flank::Right, Segment::Involute(u));
            let u1 = u - tp.angular_pitch();
            assert!(u1 > tp.u_form);
            let o = hit(&tp, Flank::Right, -1, q.p, q.n, u1 + 0.05);
            let d = norm([o[0] - q.p[0], o[1] - q.p[1]]);
            assert!((d - tp.geometry.transverse_base_pitch).abs() < 1e-9, "{d}");
        }
    }

    /// Span W_k: formula vs the geometric distance between the right flank of tooth 0 and
    /// the left flank of tooth −(k−1) along a base tangent, W_k = W_kt cos β_b.
    #[test]
    fn span_formula_vs_profile() {
        for g in cases() {
            let tp = ToothProfile::new(&g, "gear").unwrap();
            let k = tp.geometry.span_teeth;
            let wk = involute::span(&g, k);
            assert_eq!(wk, tp.geometry.span);
            let u = 0.5 * (tp.u_form + tp.u_tip);
            let q = tp.point(Flank::Right, Segment::Involute(u));
            let o = hit(&tp, Flank::Left, -(k as i64 - 1), q.p, q.n, u);
            let wkt = norm([o[0] - q.p[0], o[1] - q.p[1]]);
            let w = wkt * tp.geometry.base_helix_angle.cos();
            assert!((w - wk).abs() < 1e-9, "z = {}: {w} vs {wk}", g.teeth);
        }
        // worked example z = 20, m = 4, x = 0: W_3 = 30.641757504 mm
        let tp = ToothProfile::new(&spec(20, 4.0, 0.0, 0.0, Hand::Right), "gear").unwrap();
        assert_eq!(tp.geometry.span_teeth, 3);
        assert!((tp.geometry.span - 30.641757504).abs() < 1e-8);
    }

    #[test]
    fn helical_surface_normal_matches_cross_product() {
        for g in cases() {
            let tp = ToothProfile::new(&g, "gear").unwrap();
            for f in [Flank::Left, Flank::Right] {
                for (seg, mk) in [
                    (0.5 * (tp.u_form + tp.u_tip), true),
                    (0.4, false),
                    (0.9 * tp.u_tip + 0.1 * tp.u_form, true),
                ] {
                    for z in [0.0, 7.0, 20.0] {
                        let s = |d: f64| {
                            if mk {
                                Segment::Involute(seg + d)
                            } else {
                                Segment::Fillet(seg + d)
                            }
                        };
                        let sp = tp.surface(f, s(0.0), z);
                        // 4th-order central differences
                        let h = 1e-3;
                        let du = |d: f64| tp.surface(f, s(d), z).p;
                        let dz = |d: f64| tp.surface(f, s(0.0), z + d * 1e3).p;
                        let diff = |g: &dyn Fn(f64) -> [f64; 3]| {
                            let (a, b, c, e) = (g(2.0 * h), g(h), g(-h), g(-2.0 * h));
                            [0, 1, 2].map(|i| (-a[i] + 8.0 * b[i] - 8.0 * c[i] + e[i]) / (12.0 * h))
                        };
                        let ru = diff(&du);
                        let rz = diff(&dz);
                        let cr = [
                            ru[1] * rz[2] - ru[2] * rz[1],
                            ru[2] * rz[0] - ru[0] * rz[2],
                            ru[0] * rz[1] - ru[1] * rz[0],
                        ];
                        let l = (cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]).sqrt();
                        let c = [cr[0] / l, cr[1] / l, cr[2] / l];
                        let d = (c[0] * sp.n[0] + c[1] * sp.n[1] + c[2] * sp.n[2]).abs();
                        assert!((1.0 - d) < 1e-10, "1 − |n·n_fd| = {}", 1.0 - d);
                        let nn = (sp.n[0].powi(2) + sp.n[1].powi(2) + sp.n[2].powi(2)).sqrt();
                        assert!((nn - 1.0).abs() < 1e-14);
                    }
                }
            }
            // radius preserved along the helix; section rotated by z tan β / r
            let a = tp.surface(Flank::Right, Segment::Involute(tp.u_tip), 0.0).p;
            let b = tp
                .surface(Flank::Right, Segment::Involute(tp.u_tip), g.face_width)
                .p;
            assert!((a[0].hypot(a[1]) - b[0].hypot(b[1])).abs() < 1e-10);
            let rot = b[1].atan2(b[0]) - a[1].atan2(a[0]);
            let want = tp.twist_rate * g.face_width;
            assert!((rot - want).abs() < 1e-12);
            if g.helix_angle > 0.0 {
                assert_eq!(want > 0.0, g.hand == Hand::Right);
            }
        }
    }

    #[test]
    fn analytic_tangents_and_surface_derivatives() {
        for g in cases() {
            let tp = ToothProfile::new(&g, "gear").unwrap();
            for f in [Flank::Left, Flank::Right] {
                for seg in [
                    Segment::Involute(0.5 * (tp.u_form + tp.u_tip)),
                    Segment::Fillet(0.1),
                    Segment::Fillet(0.5),
                    Segment::Fillet(0.9),
                ] {
                    let h = 1e-4;
                    let sh = |d: f64| match seg {
                        Segment::Involute(u) => Segment::Involute(u + d),
                        Segment::Fillet(t) => Segment::Fillet(t + d),
                    };
                    let z = 5.0;
                    let (rs, rz) = tp.surface_derivatives(f, seg, z);
                    let p = |d: f64, dz: f64| tp.surface(f, sh(d), z + dz).p;
                    let fd = |g: &dyn Fn(f64) -> [f64; 3], h: f64| {
                        let (a, b, c, e) = (g(2.0 * h), g(h), g(-h), g(-2.0 * h));
                        [0, 1, 2].map(|i| (-a[i] + 8.0 * b[i] - 8.0 * c[i] + e[i]) / (12.0 * h))
                    };
                    let rs_fd = fd(&|d| p(d, 0.0), h);
                    let rz_fd = fd(&|d| p(0.0, d), 0.1);
                    let scale = rs.iter().map(|v| v * v).sum::<f64>().sqrt();
                    for i in 0..3 {
                        assert!((rs[i] - rs_fd[i]).abs() < 1e-9 * scale, "{seg:?} r_s");
                        assert!((rz[i] - rz_fd[i]).abs() < 1e-9, "{seg:?} r_z");
                    }
                    // the normal is orthogonal to both
                    let n = tp.surface(f, seg, z).n;
                    let dn = |v: [f64; 3]| v[0] * n[0] + v[1] * n[1] + v[2] * n[2];
                    assert!(dn(rs).abs() < 1e-12 * scale && dn(rz).abs() < 1e-12);
                }
            }
        }
    }

    #[test]
    fn bad_spec_is_an_error_not_a_panic() {
        let mut g = spec(8, 4.0, 0.0, 0.0, Hand::Right);
        assert!(ToothProfile::new(&g, "gear").is_err());
        g.teeth = 20;
        g.normal_module = f64::NAN;
        assert!(ToothProfile::new(&g, "gear").is_err());
        let tp = ToothProfile::new(&spec(20, 4.0, 0.0, 0.0, Hand::Right), "gear").unwrap();
        assert!(tp.point_at_radius(Flank::Left, 1.0).is_err());
    }
}
