//! Pitch-cone parameters, ISO 23509:2016 clause 6.
//!
//! * Method 0 (clause 6.2, bevel gears, a = 0): the pitch cones share their
//!   apex, tan δ1 = sin Σ / (cos Σ + u), δ2 = Σ − δ1; R_e2 = d_e2 / (2 sin δ2),
//!   R_m2 = R_e2 − b2/2 (face width factor c_be2 = 1/2), R_m1 = R_m2;
//!   m_mn = 2 R_m2 sin δ2 cos β_m2 / z2; β_m1 = β_m2.
//! * Methods 1–3 (clause 6.3, hypoid gears): the pitch cones touch at the
//!   mean point P only. Here the tangent-cone geometry is solved exactly in
//!   space rather than with the clause's trigonometric chain: the wheel axis
//!   is z, the pinion axis is at the shortest distance a along x and at the
//!   shaft angle Σ; P lies at the wheel's mean pitch radius r_m2 = d_m2/2,
//!   at the wheel axial position h and the angle φ about the wheel axis.
//!   The pitch plane is spanned by the two circumferential directions at P;
//!   the cone generators lie in it. This gives:
//!   - ζ_m, the pinion offset angle in the axial plane: 90° − φ (the angle
//!     at the wheel axis between the offset direction and P);
//!   - ζ_mp, the offset angle in the pitch plane: the angle between the two
//!     generators, and β_m1 = β_m2 + ζ_mp;
//!   - δ1, δ2 from the generators and the axes, R_m1 = r_m1 / sin δ1,
//!     R_m2 = r_m2 / sin δ2;
//!   - the condition that the relative velocity at P lies along the tooth
//!     trace (the normal velocities of both members agree):
//!     u r_m1 cos β_m1 = r_m2 cos β_m2 (clause 6.3, the mean normal module
//!     is common: m_mn = d_m1 cos β_m1 / z1 = d_m2 cos β_m2 / z2).
//!
//!   One freedom remains, closed per method: method 1 by the desired pinion
//!   spiral angle β_m1; methods 2 and 3 by Wildhaber's condition that the
//!   limit curvature radius ρ_lim of the pair equals the curvature radius of
//!   the wheel's tooth trace at P (circle r_c0 for face milling, the
//!   extended epicycloid of the face-hobbing cutter otherwise). **This closure
//!   of methods 2 and 3 is this module's assumption, not checked against the
//!   standard's text**; see `verification/iso23509_blank/README.md` for what
//!   it gives on sample F4.
//! * The limit pressure angle (clause 6.3): tan α_lim =
//!   −(tan δ1 tan δ2 / cos ζ_mp) (R_m1 sin β_m1 − R_m2 sin β_m2) /
//!   (R_m1 tan δ1 + R_m2 tan δ2); 0 for method 0.
//! * For method 1, given d_e2, the mean point is R_m2 = R_e2 − b2/2 and the
//!   solution is iterated on d_m2 = 2 R_m2 sin δ2 (bounded).

use crate::error::{FlankError, Result};

/// The pitch cones of a pair (internal units: mm, rad).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PitchCones {
    pub u: f64,
    pub delta1: f64,
    pub delta2: f64,
    pub rm1: f64,
    pub rm2: f64,
    pub re2: f64,
    pub dm1: f64,
    pub dm2: f64,
    pub beta_m1: f64,
    pub beta_m2: f64,
    /// Pinion offset angle in the axial plane ζ_m (0 for method 0).
    pub zeta_m: f64,
    /// Offset angle in the pitch plane ζ_mp (0 for method 0).
    pub zeta_mp: f64,
    pub m_mn: f64,
    /// Limit pressure angle α_lim.
    pub alpha_lim: f64,
}

/// Inputs of the pitch-cone calculation in internal units.
#[derive(Clone, Copy, Debug)]
pub struct ConeInputs {
    pub method: u8,
    pub sigma: f64,
    pub a: f64,
    pub z1: f64,
    pub z2: f64,
    pub de2: Option<f64>,
    pub dm2: Option<f64>,
    pub b2: f64,
    pub beta_m2: f64,
    pub beta_m1_desired: Option<f64>,
    pub rc0: f64,
    pub z0: Option<f64>,
}

/// Method 0, clause 6.2.
pub fn method0(c: &ConeInputs) -> Result<PitchCones> {
    let u = c.z2 / c.z1;
    let delta1 = c.sigma.sin().atan2(c.sigma.cos() + u);
    let delta2 = c.sigma - delta1;
    let (re2, rm2) = match (c.de2, c.dm2) {
        (Some(de2), _) => {
            let re2 = de2 / (2.0 * delta2.sin());
            (re2, re2 - c.b2 / 2.0)
        }
        (None, Some(dm2)) => {
            let rm2 = dm2 / (2.0 * delta2.sin());
            (rm2 + c.b2 / 2.0, rm2)
        }
        (None, None) => return Err(FlankError::Model("blank input `de2_mm`: missing".into())),
    };
    if rm2 <= 0.0 {
        return Err(FlankError::Model(
            "blank input `b2_mm`: face width not smaller than twice the outer cone distance".into(),
        ));
    }
    let dm2 = 2.0 * rm2 * delta2.sin();
    let dm1 = 2.0 * rm2 * delta1.sin();
    Ok(PitchCones {
        u,
        delta1,
        delta2,
        rm1: rm2,
        rm2,
        re2,
        dm1,
        dm2,
        beta_m1: c.beta_m2,
        beta_m2: c.beta_m2,
        zeta_m: 0.0,
        zeta_mp: 0.0,
        m_mn: dm2 * c.beta_m2.cos() / c.z2,
        alpha_lim: 0.0,
    })
}

type V3 = [f64; 3];
fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn scale(s: f64, a: V3) -> V3 {
    [s * a[0], s * a[1], s * a[2]]
}
fn unit(a: V3) -> V3 {
    scale(1.0 / dot(a, a).sqrt(), a)
}

/// The tangent-cone geometry at the mean point (φ, h) for the wheel's mean
/// pitch radius rm2.
#[derive(Clone, Copy, Debug)]
struct Tangent {
    rm1: f64,
    delta1: f64,
    delta2: f64,
    zeta_mp: f64,
    zeta_m: f64,
}

fn tangent(sigma: f64, a: f64, rm2: f64, phi: f64, h: f64) -> Tangent {
    let k2 = [0.0, 0.0, 1.0];
    let k1 = [0.0, sigma.sin(), sigma.cos()];
    let a1 = [a, 0.0, 0.0];
    let p = [rm2 * phi.cos(), rm2 * phi.sin(), h];
    let t2 = unit(cross(k2, p));
    let d = sub(p, a1);
    let r1 = sub(d, scale(dot(d, k1), k1));
    let rm1 = dot(r1, r1).sqrt();
    let t1 = unit(cross(k1, r1));
    let n = unit(cross(t1, t2));
    let g2 = cross(n, t2);
    let g1 = cross(n, t1);
    Tangent {
        rm1,
        delta1: dot(g1, k1).abs().min(1.0).acos(),
        delta2: dot(g2, k2).abs().min(1.0).acos(),
        zeta_mp: dot(g1, g2).abs().min(1.0).acos(),
        zeta_m: std::f64::consts::FRAC_PI_2 - phi,
    }
}

/// Limit pressure angle, clause 6.3.
pub fn limit_pressure_angle(
    delta1: f64,
    delta2: f64,
    zeta_mp: f64,
    rm1: f64,
    rm2: f64,
    beta_m1: f64,
    beta_m2: f64,
) -> f64 {
    let (t1, t2) = (delta1.tan(), delta2.tan());
    (-(t1 * t2 / zeta_mp.cos()) * (rm1 * beta_m1.sin() - rm2 * beta_m2.sin())
        / (rm1 * t1 + rm2 * t2))
        .atan()
}

/// Wildhaber's limit curvature radius of the pair at the mean point.
fn limit_curvature_radius(cones: &PitchCones) -> f64 {
    let c = cones;
    let ta = c.alpha_lim.tan();
    (c.beta_m1.tan() - c.beta_m2.tan())
        / (c.alpha_lim.cos()
            * (-ta * (1.0 / (c.rm1 * c.delta1.tan()) + 1.0 / (c.rm2 * c.delta2.tan()))
                + 1.0 / (c.rm1 * c.beta_m1.cos())
                - 1.0 / (c.rm2 * c.beta_m2.cos())))
}

/// Face-hobbing quantities of the wheel at its mean point (clause 7 notation):
/// the cutter lead angle ν, the angle λ at P between the cone generator and
/// the cutter radius, and the base radius ρ_b of the epicycloid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hobbing {
    pub nu: f64,
    pub lambda: f64,
    pub rho_b: f64,
    /// Curvature radius of the tooth trace at P (extended epicycloid).
    pub rho_trace: f64,
}

/// ν from sin ν = z0 m_mn / (2 r_c0); λ = 90° − β_m2 + ν; the crown gear of
/// the wheel has z_p = z2 / sin δ2 teeth and the cutter centre lies at
/// distance M from its centre (triangle crown centre, P, cutter centre with
/// sides R_m2, r_c0 and the angle λ at P); ρ_b = M z_p / (z_p + z0). The trace
/// is the path of the blade point in the crown gear when the cutter turns by
/// τ and the crown gear by −τ z0/z_p; its curvature at P by central
/// differences of the closed form.
pub fn hobbing(
    z0: f64,
    z2: f64,
    rc0: f64,
    m_mn: f64,
    rm2: f64,
    delta2: f64,
    beta_m2: f64,
) -> Result<Hobbing> {
    let s = z0 * m_mn / (2.0 * rc0);
    if !(s.abs() < 1.0) {
        return Err(FlankError::Model(format!(
            "blank input `rc0_mm`: cutter radius {rc0} too small for z0 = {z0} blade groups"
        )));
    }
    let nu = s.asin();
    let lambda = std::f64::consts::FRAC_PI_2 - beta_m2.abs() + nu;
    let zp = z2 / delta2.sin();
    let c = [rm2 - rc0 * lambda.cos(), rc0 * lambda.sin()];
    let m = c[0].hypot(c[1]);
    let rho_b = m * zp / (zp + z0);
    let path = |t: f64| {
        let x = c[0] + t.cos() * (rm2 - c[0]) + t.sin() * c[1];
        let y = c[1] + t.sin() * (rm2 - c[0]) - t.cos() * c[1];
        let q = t * z0 / zp;
        [q.cos() * x - q.sin() * y, q.sin() * x + q.cos() * y]
    };
    let hstep = 1e-4;
    let (p0, p1, p2) = (path(-hstep), path(0.0), path(hstep));
    let d = [
        (p2[0] - p0[0]) / (2.0 * hstep),
        (p2[1] - p0[1]) / (2.0 * hstep),
    ];
    let dd = [
        (p2[0] - 2.0 * p1[0] + p0[0]) / (hstep * hstep),
        (p2[1] - 2.0 * p1[1] + p0[1]) / (hstep * hstep),
    ];
    let k = (d[0] * dd[1] - d[1] * dd[0]).abs() / (d[0] * d[0] + d[1] * d[1]).powf(1.5);
    Ok(Hobbing {
        nu,
        lambda,
        rho_b,
        rho_trace: 1.0 / k,
    })
}

/// Bound of every iteration here.
pub const MAX_ITERATIONS: usize = 100;

/// Newton on the wheel axial position h of the mean point for a fixed
/// angle φ (finite-difference derivative, steps limited to `h_step`,
/// bounded); None if it does not converge.
fn solve_h(mut h: f64, h_step: f64, f: impl Fn(f64) -> Option<f64>) -> Option<f64> {
    for _ in 0..MAX_ITERATIONS {
        let r = f(h)?;
        let e = 1e-6 * h.abs().max(1.0);
        let d = (f(h + e)? - f(h - e)?) / (2.0 * e);
        if !(d.is_finite() && d != 0.0) {
            return None;
        }
        let dh = (r / d).clamp(-h_step, h_step);
        h -= dh;
        if dh.abs() < 1e-10 * h.abs().max(1.0) {
            return Some(h);
        }
    }
    None
}

/// Methods 1–3, clause 6.3.
pub fn hypoid(c: &ConeInputs) -> Result<PitchCones> {
    let u = c.z2 / c.z1;
    let base = method0(&ConeInputs { a: 0.0, ..*c })?;
    let beta2 = c.beta_m2;
    // Solve for (φ, h) at a given wheel mean pitch radius.
    let solve = |rm2: f64, seed: [f64; 2]| -> Result<(PitchCones, [f64; 2])> {
        let cones_at = |x: [f64; 2]| -> Option<PitchCones> {
            let t = tangent(c.sigma, c.a, rm2, x[0], x[1]);
            let beta1 = beta2 + t.zeta_mp.copysign(c.a);
            let (s1, s2) = (t.delta1.sin(), t.delta2.sin());
            if !(s1 > 1e-9 && s2 > 1e-9 && t.rm1 > 0.0) {
                return None;
            }
            let (r1, r2) = (t.rm1 / s1, rm2 / s2);
            let alpha_lim =
                limit_pressure_angle(t.delta1, t.delta2, t.zeta_mp, r1, r2, beta1, beta2);
            Some(PitchCones {
                u,
                delta1: t.delta1,
                delta2: t.delta2,
                rm1: r1,
                rm2: r2,
                re2: r2 + c.b2 / 2.0,
                dm1: 2.0 * t.rm1,
                dm2: 2.0 * rm2,
                beta_m1: beta1,
                beta_m2: beta2,
                zeta_m: t.zeta_m,
                zeta_mp: t.zeta_mp,
                m_mn: 2.0 * rm2 * beta2.cos() / c.z2,
                alpha_lim,
            })
        };
        // The kinematic condition fixes h for each φ; the method's closure
        // is then a function of φ alone. Scan φ outwards from the seed for
        // a sign change of the closure (the nearest one), then bisect.
        let kin = |phi: f64, h: f64| {
            let p = cones_at([phi, h])?;
            Some((u * p.dm1 * p.beta_m1.cos() - p.dm2 * beta2.cos()) / p.dm2)
        };
        let closure = |p: &PitchCones| -> Option<f64> {
            let r = match (c.method, c.beta_m1_desired, c.z0) {
                (1, Some(b1), _) => p.beta_m1 - b1,
                (_, _, Some(z0)) => {
                    let hob = hobbing(z0, c.z2, c.rc0, p.m_mn, p.rm2, p.delta2, beta2).ok()?;
                    (limit_curvature_radius(p) - hob.rho_trace) / c.rc0
                }
                _ => (limit_curvature_radius(p) - c.rc0) / c.rc0,
            };
            r.is_finite().then_some(r)
        };
        let h_step = 0.1 * rm2;
        let at = |phi: f64, h0: f64| -> Option<(f64, f64, PitchCones)> {
            let h = solve_h(h0, h_step, |h| kin(phi, h))?;
            let p = cones_at([phi, h])?;
            Some((closure(&p)?, h, p))
        };
        let fail =
            |why: String| FlankError::Model(format!("blank design, hypoid pitch cones: {why}"));
        // Bisection on [φa, φb] where the closure changes sign; None if the
        // change is a pole, not a root.
        let bisect = |phi_a: f64,
                      phi_b: f64,
                      f_a: f64,
                      h_a: f64|
         -> Result<Option<(PitchCones, [f64; 2])>> {
            let (mut lo, mut hi, mut f_lo, mut h) = (phi_a, phi_b, f_a, h_a);
            for _ in 0..MAX_ITERATIONS {
                let mid = 0.5 * (lo + hi);
                let (f_m, h_m, p) =
                    at(mid, h).ok_or_else(|| fail("left the valid geometry".into()))?;
                h = h_m;
                if (hi - lo).abs() < 1e-14 {
                    return Ok((f_m.abs() < 1e-6).then_some((p, [mid, h])));
                }
                if f_lo * f_m <= 0.0 {
                    hi = mid;
                } else {
                    lo = mid;
                    f_lo = f_m;
                }
            }
            Err(fail(format!(
                "bisection did not converge in {MAX_ITERATIONS} steps"
            )))
        };
        let step = 0.25f64.to_radians();
        let n_scan = 240;
        // Two walkers, one each way, stepped alternately: the root nearest
        // to the seed wins.
        let mut walkers: Vec<(f64, f64, f64, f64)> = Vec::new(); // (dir, φ, h, f)
        if let Some((f0, h0, _)) = at(seed[0], seed[1]) {
            walkers.push((1.0, seed[0], h0, f0));
            walkers.push((-1.0, seed[0], h0, f0));
        }
        for _ in 0..n_scan {
            if walkers.is_empty() {
                break;
            }
            let mut alive = Vec::new();
            for (dir, phi_a, h_a, f_a) in walkers {
                let phi_b = phi_a + dir * step;
                let Some((f_b, h_b, _)) = at(phi_b, h_a) else {
                    continue;
                };
                if f_a * f_b <= 0.0 {
                    if let Some(found) = bisect(phi_a, phi_b, f_a, h_a)? {
                        return Ok(found);
                    }
                }
                alive.push((dir, phi_b, h_b, f_b));
            }
            walkers = alive;
        }
        Err(fail(format!(
            "no root of the method {} closure within ±{}° of the seed",
            c.method,
            (step * n_scan as f64).to_degrees()
        )))
    };
    // Seed: P a little inside the plane x = a through the pinion axis
    // (on it the pinion pitch cone degenerates), at the wheel's method-0
    // pitch apex height.
    let rm2_0 = base.dm2 / 2.0;
    let phi0 = std::f64::consts::FRAC_PI_2 - 0.85 * (c.a / rm2_0).clamp(-0.9, 0.9).asin();
    let h0 = -c.a.signum() * rm2_0 / base.delta2.tan();
    let seed = [phi0, h0];
    match (c.dm2, c.de2) {
        (Some(dm2), _) => Ok(solve(dm2 / 2.0, seed)?.0),
        (None, Some(de2)) => {
            // d_e2 given: iterate on d_m2 so that R_m2 = R_e2 − b2/2.
            let mut rm2 = base.dm2 / 2.0;
            let mut x = seed;
            for _ in 0..MAX_ITERATIONS {
                let (p, xn) = solve(rm2, x)?;
                x = xn;
                let re2 = de2 / (2.0 * p.delta2.sin());
                let next = (re2 - c.b2 / 2.0) * p.delta2.sin();
                if (next - rm2).abs() < 1e-12 * rm2 {
                    return Ok(PitchCones { re2, ..p });
                }
                rm2 = next;
            }
            Err(FlankError::Model(format!(
                "blank design, hypoid from d_e2: no convergence in {MAX_ITERATIONS} iterations"
            )))
        }
        (None, None) => Err(FlankError::Model("blank input `de2_mm`: missing".into())),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn inputs(sigma_deg: f64) -> ConeInputs {
        ConeInputs {
            method: 0,
            sigma: sigma_deg.to_radians(),
            a: 0.0,
            z1: 13.0,
            z2: 41.0,
            de2: Some(200.0),
            dm2: None,
            b2: 30.0,
            beta_m2: 30f64.to_radians(),
            beta_m1_desired: None,
            rc0: 100.0,
            z0: None,
        }
    }

    #[test]
    fn method0_pitch_angles_follow_the_shaft_angle() {
        for sigma in [60.0, 90.0, 110.0] {
            let c = inputs(sigma);
            let p = method0(&c).unwrap();
            let u = 41.0 / 13.0;
            let s = c.sigma;
            assert!((p.delta1.tan() - s.sin() / (s.cos() + u)).abs() < 1e-12);
            assert!((p.delta1 + p.delta2 - s).abs() < 1e-12);
            // Both members share the mean cone distance and the normal module.
            assert!((p.dm1 / p.delta1.sin() - p.dm2 / p.delta2.sin()).abs() < 1e-9);
            assert!((p.dm1 * p.beta_m1.cos() / 13.0 - p.m_mn).abs() < 1e-12);
        }
    }

    /// Method 1 from d_e2: the solution satisfies the kinematic condition,
    /// β_m1 = β_m2 + ζ_mp, the desired β_m1 and R_m2 = R_e2 − b2/2.
    #[test]
    fn hypoid_solution_satisfies_its_equations() {
        let c = ConeInputs {
            method: 1,
            a: 10.0,
            beta_m1_desired: Some(45f64.to_radians()),
            ..inputs(90.0)
        };
        let p = hypoid(&c).unwrap();
        assert!((p.beta_m1 - 45f64.to_radians()).abs() < 1e-10);
        assert!((p.beta_m1 - p.beta_m2 - p.zeta_mp).abs() < 1e-12);
        let u = 41.0 / 13.0;
        assert!((u * p.dm1 * p.beta_m1.cos() - p.dm2 * p.beta_m2.cos()).abs() < 1e-8);
        assert!(((p.re2 - 15.0) * p.delta2.sin() * 2.0 - p.dm2).abs() < 1e-8);
        assert!((2.0 * p.re2 * p.delta2.sin() - 200.0).abs() < 1e-8);
    }
}
