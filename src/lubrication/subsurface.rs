//! Stresses below a Hertz line contact with sliding friction: the closed
//! form of McEwen (1949) and Smith & Liu (1953), as written in Johnson,
//! *Contact Mechanics* (1985), §7.2 eqs. (7.18)–(7.19).
//!
//! Plane strain. The contact carries the Hertz pressure
//! p(x) = p₀ √(1 − x²/a²) and, sliding, the traction q(x) = μ p(x) along
//! +x on the body, |x| ≤ a; z is the depth below the surface. With
//!
//! m² = ½ [√((a² − x² + z²)² + 4x²z²) + (a² − x² + z²)],
//! n² = ½ [√((a² − x² + z²)² + 4x²z²) − (a² − x² + z²)],
//!
//! m ≥ 0 and n of the sign of x, the normal pressure gives
//!
//! σ_x = −(p₀/a) [m (1 + (z² + n²)/(m² + n²)) − 2z],
//! σ_z = −(p₀/a) m (1 − (z² + n²)/(m² + n²)),
//! τ_xz = −(p₀/a) n (m² − z²)/(m² + n²),
//!
//! and the traction (q₀ = μ p₀)
//!
//! σ_x = (q₀/a) [n (2 − (z² − m²)/(m² + n²)) − 2x],
//! σ_z = −(q₀/a) n (m² − z²)/(m² + n²),
//! τ_xz = −(q₀/a) [m (1 + (z² + n²)/(m² + n²)) − 2z],
//!
//! with σ_y = ν (σ_x + σ_z). (Signs: compression negative; checked in the
//! tests against the superposition of Flamant's line-load solutions over
//! p and q, an independent derivation.) Frictionless, the largest principal
//! shear is 0.300 p₀ at z = 0.786 a below the centre, and the largest
//! orthogonal shear |τ_xz| is 0.250 p₀ at z = 0.5 a, x = ±0.866 a
//! (Johnson §4.2). Friction moves the maxima toward the surface and raises
//! them; above μ ≈ 0.3 the largest shear reaches the surface.
//!
//! Seed 002 reports the change of the largest subsurface shear from its
//! dry to its wet pass; [`max_stresses`] gives the maxima (as multiples of
//! p₀ and depths as multiples of a) for a friction coefficient.

/// Stress components at a point: σ_x, σ_y, σ_z, τ_xz (units of p₀).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlaneStress {
    pub sigma_x: f64,
    pub sigma_y: f64,
    pub sigma_z: f64,
    pub tau_xz: f64,
}

impl PlaneStress {
    /// Largest principal shear stress (Tresca): half the largest
    /// difference of the three principal stresses.
    pub fn max_shear(&self) -> f64 {
        let c = 0.5 * (self.sigma_x + self.sigma_z);
        let r = (0.25 * (self.sigma_x - self.sigma_z).powi(2) + self.tau_xz.powi(2)).sqrt();
        let s = [c + r, c - r, self.sigma_y];
        let hi = s.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
        let lo = s.iter().cloned().fold(f64::INFINITY, f64::min);
        0.5 * (hi - lo)
    }

    /// Von Mises equivalent stress.
    pub fn von_mises(&self) -> f64 {
        let (x, y, z, t) = (self.sigma_x, self.sigma_y, self.sigma_z, self.tau_xz);
        (0.5 * ((x - y).powi(2) + (y - z).powi(2) + (z - x).powi(2)) + 3.0 * t * t).sqrt()
    }
}

/// The stress at (x, z) (in units of the half-width a; z ≥ 0 the depth)
/// below a Hertz line contact of peak pressure 1 with the sliding
/// traction μ p(x) along +x; ν Poisson's ratio (plane strain).
pub fn stress(x: f64, z: f64, mu: f64, nu: f64) -> PlaneStress {
    let z = z.max(0.0);
    let k = 1.0 - x * x + z * z;
    let root = (k * k + 4.0 * x * x * z * z).sqrt();
    let m = (0.5 * (root + k)).max(0.0).sqrt();
    let n = (0.5 * (root - k)).max(0.0).sqrt().copysign(x);
    let mn = m * m + n * n;
    // at the contact edges on the surface m = n = 0: the stresses are the
    // limits from inside, which the forms below give with the ratios 0
    let (r1, r2) = if mn > 0.0 {
        ((z * z + n * n) / mn, (m * m - z * z) / mn)
    } else {
        (0.0, 0.0)
    };
    let normal = [-(m * (1.0 + r1) - 2.0 * z), -m * (1.0 - r1), -n * r2];
    let traction = [
        n * (2.0 + r2) - 2.0 * x,
        -n * r2,
        -(m * (1.0 + r1) - 2.0 * z),
    ];
    let sx = normal[0] + mu * traction[0];
    let sz = normal[1] + mu * traction[1];
    PlaneStress {
        sigma_x: sx,
        sigma_y: nu * (sx + sz),
        sigma_z: sz,
        tau_xz: normal[2] + mu * traction[2],
    }
}

/// The maxima of the subsurface stress field (units of p₀; positions in
/// units of a).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct MaxStresses {
    /// Largest principal shear (Tresca) and where.
    pub max_shear: f64,
    pub max_shear_at: [f64; 2],
    /// Largest |τ_xz| (orthogonal shear) and where.
    pub max_orthogonal_shear: f64,
    pub max_orthogonal_shear_at: [f64; 2],
    /// Largest von Mises stress and where.
    pub max_von_mises: f64,
    pub max_von_mises_at: [f64; 2],
}

/// The maximum of f(x, z) over |x| ≤ nx h, 0 ≤ z ≤ nz h on a grid of
/// step h, refined twice by 10× on a ±`reach` step grid around the best
/// point; returns the maximum and where.
fn grid_maximum(
    f: &dyn Fn(f64, f64) -> f64,
    h: f64,
    nx: i32,
    nz: i32,
    reach: i32,
) -> (f64, [f64; 2]) {
    let mut best = (f64::NEG_INFINITY, [0.0, 0.0]);
    let visit = |x: f64, z: f64, best: &mut (f64, [f64; 2])| {
        let v = f(x, z);
        if v > best.0 {
            *best = (v, [x, z]);
        }
    };
    for i in -nx..=nx {
        for j in 0..=nz {
            visit(i as f64 * h, j as f64 * h, &mut best);
        }
    }
    for step in [0.1 * h, 0.01 * h] {
        let [x0, z0] = best.1;
        for i in -reach..=reach {
            for j in -reach..=reach {
                let (x, z) = (x0 + i as f64 * step, (z0 + j as f64 * step).max(0.0));
                visit(x, z, &mut best);
            }
        }
    }
    best
}

/// The largest principal shear (units of p₀) below a Hertz line contact
/// with sliding friction μ: the maximum of [`PlaneStress::max_shear`] over
/// |x| ≤ 1.5a, 0 ≤ z ≤ 1.2a (grid 0.02a refined twice by 10×: to about
/// 1e-6 p₀; about 0.5 ms).
pub fn max_subsurface_shear(mu: f64, nu: f64) -> f64 {
    grid_maximum(&|x, z| stress(x, z, mu, nu).max_shear(), 0.02, 75, 60, 10).0
}

/// The maxima of [`stress`] over −2a ≤ x ≤ 2a, 0 ≤ z ≤ 2a (a grid of
/// 0.01 a refined twice by 10× around each maximum: the maxima to about
/// 1e-6 p₀).
pub fn max_stresses(mu: f64, nu: f64) -> MaxStresses {
    let search = |f: &dyn Fn(f64, f64) -> f64| grid_maximum(f, 0.01, 200, 200, 20);
    let (s, s_at) = search(&|x, z| stress(x, z, mu, nu).max_shear());
    let (o, o_at) = search(&|x, z| stress(x, z, mu, nu).tau_xz.abs());
    let (v, v_at) = search(&|x, z| stress(x, z, mu, nu).von_mises());
    MaxStresses {
        max_shear: s,
        max_shear_at: s_at,
        max_orthogonal_shear: o,
        max_orthogonal_shear_at: o_at,
        max_von_mises: v,
        max_von_mises_at: v_at,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The same field by superposing Flamant's line-load solutions
    /// (Johnson eqs. 2.15, 2.19) over p(s) = √(1 − s²) and q(s) = μ p(s),
    /// by Gauss–Chebyshev quadrature of the second kind (exact weight
    /// √(1 − s²)); a point below the surface, so the kernels are smooth.
    fn flamant(x: f64, z: f64, mu: f64, nu: f64) -> PlaneStress {
        let n = 4000;
        let (mut sx, mut sz, mut t) = (0.0, 0.0, 0.0);
        for k in 1..=n {
            let th = k as f64 * std::f64::consts::PI / (n + 1) as f64;
            let s = th.cos();
            let w = std::f64::consts::PI / (n + 1) as f64 * th.sin().powi(2);
            let (dx, r2) = (x - s, (x - s).powi(2) + z * z);
            let c = -2.0 / std::f64::consts::PI / (r2 * r2);
            // normal line load P = 1 (pressing into the body)
            sx += w * c * dx * dx * z;
            sz += w * c * z * z * z;
            t += w * c * dx * z * z;
            // tangential line load Q = μ along +x
            sx += w * mu * c * dx * dx * dx;
            sz += w * mu * c * dx * z * z;
            t += w * mu * c * dx * dx * z;
        }
        PlaneStress {
            sigma_x: sx,
            sigma_y: nu * (sx + sz),
            sigma_z: sz,
            tau_xz: t,
        }
    }

    #[test]
    fn closed_form_equals_superposed_line_loads() {
        let mut worst: f64 = 0.0;
        for mu in [0.0, 0.1, 0.3] {
            for (x, z) in [
                (0.0, 0.5),
                (0.3, 0.78),
                (-0.7, 0.3),
                (1.2, 0.4),
                (-1.5, 1.0),
                (0.9, 0.1),
            ] {
                let a = stress(x, z, mu, 0.3);
                let b = flamant(x, z, mu, 0.3);
                for (u, v) in [
                    (a.sigma_x, b.sigma_x),
                    (a.sigma_z, b.sigma_z),
                    (a.tau_xz, b.tau_xz),
                ] {
                    worst = worst.max((u - v).abs());
                    assert!((u - v).abs() < 1e-5, "μ {mu} at ({x}, {z}): {a:?} vs {b:?}");
                }
            }
        }
        eprintln!("closed form vs Flamant superposition: {worst:.2e} p0");
    }

    #[test]
    fn surface_values() {
        // on the surface inside the contact: σ_x = σ_z = −p(x) − 2μx,
        // σ_z = −p(x), and the traction τ_xz = −μ p(x) (Johnson 7.20)
        for x in [-0.8, -0.2, 0.0, 0.5, 0.9] {
            let p = (1.0f64 - x * x).sqrt();
            let s = stress(x, 0.0, 0.2, 0.3);
            assert!((s.sigma_z + p).abs() < 1e-12, "{x}: {s:?}");
            assert!((s.sigma_x + p + 0.4 * x).abs() < 1e-12, "{x}: {s:?}");
            assert!((s.tau_xz + 0.2 * p).abs() < 1e-12, "{x}: {s:?}");
        }
        // outside the contact the surface is free of normal and shear stress
        let s = stress(1.5, 0.0, 0.2, 0.3);
        assert!(s.sigma_z.abs() < 1e-12 && s.tau_xz.abs() < 1e-12, "{s:?}");
    }

    /// Frictionless maxima, Johnson §4.2: principal shear 0.300 p₀ at
    /// z = 0.786 a below the centre; orthogonal shear 0.250 p₀ at z = 0.5 a,
    /// x = ±0.866 a.
    #[test]
    fn frictionless_maxima_are_the_textbook_ones() {
        let m = max_stresses(0.0, 0.3);
        assert!((m.max_shear - 0.3005).abs() < 1e-3, "{m:?}");
        assert!(m.max_shear_at[0].abs() < 1e-3 && (m.max_shear_at[1] - 0.786).abs() < 2e-3);
        assert!((m.max_orthogonal_shear - 0.25).abs() < 1e-6, "{m:?}");
        assert!((m.max_orthogonal_shear_at[1] - 0.5).abs() < 1e-3);
        assert!((m.max_orthogonal_shear_at[0].abs() - 0.75f64.sqrt()).abs() < 1e-3);
        eprintln!("{m:?}");
    }

    /// Friction raises the largest shear and moves it toward the surface;
    /// at μ = 0.4 it is on the surface (Smith & Liu: above μ ≈ 0.3).
    #[test]
    fn friction_raises_the_maxima_and_lifts_them() {
        let dry = max_stresses(0.0, 0.3);
        let mut last = dry;
        for mu in [0.05, 0.1, 0.2] {
            let m = max_stresses(mu, 0.3);
            assert!(m.max_shear > last.max_shear, "{mu}: {m:?}");
            assert!(
                m.max_shear_at[1] < last.max_shear_at[1] + 1e-3,
                "{mu}: {m:?}"
            );
            last = m;
        }
        let m = max_stresses(0.4, 0.3);
        assert!(m.max_shear_at[1] < 0.01, "{m:?}");
    }

    #[test]
    fn the_fast_maximum_agrees_with_the_full_search() {
        for mu in [0.0, 0.03, 0.05, 0.1, 0.25] {
            let a = max_subsurface_shear(mu, 0.3);
            let b = max_stresses(mu, 0.3).max_shear;
            assert!((a - b).abs() < 1e-5, "μ {mu}: {a} vs {b}");
        }
    }
}
