//! Hertz point (elliptical) contact: the exact solution through complete
//! elliptic integrals.
//!
//! Two bodies whose initial separation near the first point of contact is
//! h = A x² + B y² (A, B the principal relative curvatures halved:
//! A = ½(1/R₁ₓ + 1/R₂ₓ), B = ½(1/R₁ᵧ + 1/R₂ᵧ) for aligned principal
//! directions) pressed together by a force P touch over an ellipse with
//! the Hertz pressure p = p₀ √(1 − x²/aₓ² − y²/a_y²) (Johnson, *Contact
//! Mechanics*, 1985, §4.2). With the semi-major axis a along the smaller
//! curvature, the semi-minor axis b, e² = 1 − b²/a² and the complete
//! elliptic integrals K(e), E(e) (Johnson's notation: modulus e), the
//! displacements of the ellipsoidal pressure on a half-space (Johnson ch. 3,
//! pressure on an elliptical region) give
//!
//! ```text
//!   B/A = ((a/b)² E(e) − K(e)) / (K(e) − E(e))               (eccentricity)
//!   A   = p₀ b (K(e) − E(e)) / (E* e² a²)                      (size)
//!   δ   = p₀ b K(e) / E*                                       (approach)
//!   P   = (2/3) π a b p₀
//! ```
//!
//! The first equation fixes e from the curvature ratio alone (solved here
//! by bisection on b/a); the second with p₀ = 3P/(2πab) gives
//! a³ = 3 P (K − E) / (2π E* e² A).
//!
//! K and E come from the arithmetic–geometric mean (Abramowitz & Stegun,
//! *Handbook of Mathematical Functions*, 17.6.1–17.6.4):
//! a₀ = 1, b₀ = k′ = √(1 − m), c₀ = √m; aₙ₊₁ = (aₙ + bₙ)/2,
//! bₙ₊₁ = √(aₙbₙ), cₙ₊₁ = cₙ²/(4aₙ₊₁); K = π/(2a_N),
//! K − E = K Σₙ 2ⁿ⁻¹ cₙ². Written with σ = Σ 2ⁿ⁻¹ cₙ²/m, K − E = m K σ
//! has no cancellation even for a nearly circular contact (σ → ½ as
//! m → 0), which the eccentricity equation needs:
//! B/A = (1 − σ) / (k′² σ).

use std::f64::consts::PI;

use crate::error::FlankError;

/// Iteration bound of the AGM: it converges quadratically, six or seven
/// steps reach round-off for every k′ ≥ 1e-12.
const AGM_MAX_ITERATIONS: usize = 40;
/// Bisection bound on b/a (each halves the bracket of the unit interval).
const BISECTION_MAX_ITERATIONS: usize = 200;
/// Smallest b/a solved for (curvature ratio ≈ 2.6e15).
const MIN_AXIS_RATIO: f64 = 1e-12;

/// K(m) and σ(m) = (K − E)/(m K) of the complementary modulus
/// k′ = √(1 − m) (AGM, A&S 17.6).
fn agm_k_sigma(k_prime: f64) -> Result<(f64, f64), FlankError> {
    let m = (1.0 - k_prime) * (1.0 + k_prime);
    let (mut a, mut b) = (1.0f64, k_prime);
    // t = cₙ²/m and the running sum σ = Σ 2ⁿ⁻¹ tₙ, n = 0 first
    let mut t = 1.0f64;
    let mut weight = 0.5f64;
    let mut sigma = 0.5f64;
    for _ in 0..AGM_MAX_ITERATIONS {
        let a_next = 0.5 * (a + b);
        let b_next = (a * b).sqrt();
        // c_{n+1} = c_n² / (4 a_{n+1})  ⇒  t_{n+1} = m t_n² / (16 a_{n+1}²)
        t = m * t * t / (16.0 * a_next * a_next);
        weight *= 2.0;
        sigma += weight * t;
        let done = (a_next - b_next).abs() <= 4.0 * f64::EPSILON * a_next
            && weight * t <= f64::EPSILON * sigma;
        a = a_next;
        b = b_next;
        if done {
            return Ok((PI / (2.0 * a), sigma));
        }
    }
    Err(FlankError::Solver(format!(
        "elliptic integrals: the AGM did not converge in {AGM_MAX_ITERATIONS} steps (k′ = {k_prime})"
    )))
}

/// Complete elliptic integrals of the first and second kind, K(m) and
/// E(m), of parameter m = k² ∈ [0, 1) (A&S 17.3.1–17.3.3; Johnson writes
/// K(e), E(e) with the modulus e = √m).
pub fn complete_elliptic(m: f64) -> Result<(f64, f64), FlankError> {
    if !(0.0..1.0).contains(&m) {
        return Err(FlankError::Model(format!(
            "elliptic integrals: parameter m = {m} outside [0, 1)"
        )));
    }
    let (k, sigma) = agm_k_sigma((1.0 - m).sqrt())?;
    Ok((k, k * (1.0 - m * sigma)))
}

/// The Hertz contact ellipse of a point contact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HertzEllipse {
    /// Semi-axis along x, the direction of curvature `curvature_x` (mm).
    pub semi_x: f64,
    /// Semi-axis along y (mm).
    pub semi_y: f64,
    /// Largest pressure p₀ = 3P/(2π aₓ a_y) (MPa).
    pub p0: f64,
    /// Approach δ of distant points of the two half-spaces (mm).
    pub approach: f64,
    /// Eccentricity e = √(1 − b²/a²) of the ellipse.
    pub eccentricity: f64,
    /// K(e) and E(e) at that eccentricity.
    pub k: f64,
    pub e: f64,
}

/// Hertz elliptical contact (Johnson §4.2, in the form of
/// the module doc): total force `load` P (N), gap coefficients
/// `curvature_x` A and `curvature_y` B (1/mm; h = A x² + B y², so
/// A = 1/(2R) for a sphere of radius R on a flat), contact modulus
/// `e_star` E* (MPa). Either curvature may be the larger.
pub fn hertz_elliptic(
    load: f64,
    curvature_x: f64,
    curvature_y: f64,
    e_star: f64,
) -> Result<HertzEllipse, FlankError> {
    let finite = [load, curvature_x, curvature_y, e_star]
        .iter()
        .all(|v| v.is_finite());
    if !(finite && load > 0.0 && curvature_x > 0.0 && curvature_y > 0.0 && e_star > 0.0) {
        return Err(FlankError::Model(format!(
            "Hertz point contact needs P > 0, both curvatures > 0 and E* > 0 (finite): \
             P = {load}, A = {curvature_x}, B = {curvature_y}, E* = {e_star}"
        )));
    }
    // A ≤ B: the major axis a lies along the smaller curvature A
    let (small, large) = if curvature_x <= curvature_y {
        (curvature_x, curvature_y)
    } else {
        (curvature_y, curvature_x)
    };
    let ratio = large / small;
    // B/A as a function of s = b/a ∈ (0, 1]: 1 at s = 1, growing without
    // bound as s → 0 (monotone)
    let ratio_of = |s: f64| -> Result<f64, FlankError> {
        let (_, sigma) = agm_k_sigma(s)?;
        Ok((1.0 - sigma) / (s * s * sigma))
    };
    let s = if ratio == 1.0 {
        1.0
    } else {
        if ratio_of(MIN_AXIS_RATIO)? < ratio {
            return Err(FlankError::Model(format!(
                "Hertz point contact: curvature ratio {ratio:.3e} beyond b/a = {MIN_AXIS_RATIO:e} \
                 (treat it as line contact)"
            )));
        }
        let (mut lo, mut hi) = (MIN_AXIS_RATIO, 1.0f64);
        let mut converged = false;
        for _ in 0..BISECTION_MAX_ITERATIONS {
            let mid = 0.5 * (lo + hi);
            if ratio_of(mid)? > ratio {
                lo = mid;
            } else {
                hi = mid;
            }
            if hi - lo <= 2.0 * f64::EPSILON * hi {
                converged = true;
                break;
            }
        }
        if !converged {
            return Err(FlankError::Solver(format!(
                "Hertz point contact: eccentricity bisection hit its bound of \
                 {BISECTION_MAX_ITERATIONS} steps (B/A = {ratio})"
            )));
        }
        0.5 * (lo + hi)
    };
    let (k, sigma) = agm_k_sigma(s)?;
    let m = (1.0 - s) * (1.0 + s);
    // a³ = 3P (K − E)/(2π E* e² A) with K − E = m K σ
    let major = (3.0 * load * k * sigma / (2.0 * PI * e_star * small)).cbrt();
    let minor = s * major;
    let p0 = 3.0 * load / (2.0 * PI * major * minor);
    let approach = p0 * minor * k / e_star;
    let (semi_x, semi_y) = if curvature_x <= curvature_y {
        (major, minor)
    } else {
        (minor, major)
    };
    Ok(HertzEllipse {
        semi_x,
        semi_y,
        p0,
        approach,
        eccentricity: m.sqrt(),
        k,
        e: k * (1.0 - m * sigma),
    })
}

/// Hamrock & Brewe's curve fits of the elliptical contact (Hamrock & Brewe,
/// "Simplified solution for elliptical-contact deformation between two
/// elastic solids", ASME J. Lubr. Technol. 105, 1983; Hamrock, Schmid &
/// Jacobson, *Fundamentals of Machine Elements*, §8.4.3): with
/// Rₓ ≤ R_y the reduced radii (A = 1/(2Rₓ) ≥ B = 1/(2R_y)),
/// 1/R = 1/Rₓ + 1/R_y, E′ = 2E*,
/// k = 1.0339 (R_y/Rₓ)^0.6360, Ɛ = 1.0003 + 0.5968 Rₓ/R_y,
/// F = 1.5277 + 0.6023 ln(R_y/Rₓ),
/// D_y = 2 (6 k² Ɛ P R/(π E′))^⅓, Dₓ = 2 (6 Ɛ P R/(π k E′))^⅓,
/// δ = F (9/(2ƐR) (P/(π k E′))²)^⅓. A cross-check of the exact solution
/// only (their stated accuracy is a few per cent).
pub fn hamrock_brewe(load: f64, curvature_x: f64, curvature_y: f64, e_star: f64) -> HertzEllipse {
    // Rx: the smaller reduced radius (larger curvature)
    let (ax, ay) = (curvature_x.max(curvature_y), curvature_x.min(curvature_y));
    let (rx, ry) = (0.5 / ax, 0.5 / ay);
    let r = 1.0 / (1.0 / rx + 1.0 / ry);
    let e_prime = 2.0 * e_star;
    let kappa = 1.0339 * (ry / rx).powf(0.6360);
    let eps = 1.0003 + 0.5968 * rx / ry;
    let f = 1.5277 + 0.6023 * (ry / rx).ln();
    let dy = 2.0 * (6.0 * kappa * kappa * eps * load * r / (PI * e_prime)).cbrt();
    let dx = 2.0 * (6.0 * eps * load * r / (PI * kappa * e_prime)).cbrt();
    let approach = f * (4.5 / (eps * r) * (load / (PI * kappa * e_prime)).powi(2)).cbrt();
    // the long semi-axis D_y/2 lies along the smaller curvature
    let (semi_x, semi_y) = if curvature_x <= curvature_y {
        (0.5 * dy, 0.5 * dx)
    } else {
        (0.5 * dx, 0.5 * dy)
    };
    HertzEllipse {
        semi_x,
        semi_y,
        p0: 3.0 * load / (2.0 * PI * semi_x * semi_y),
        approach,
        eccentricity: (1.0 - (dx / dy).powi(2)).sqrt(),
        k: f,
        e: eps,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_PI_2;

    fn close(x: f64, y: f64, tol: f64) -> bool {
        (x / y - 1.0).abs() <= tol
    }

    /// Abramowitz & Stegun Table 17.1 (and 17.3.11–12 for m = 0).
    #[test]
    fn elliptic_integrals_match_the_tables() {
        let table = [
            (0.0, FRAC_PI_2, FRAC_PI_2),
            (0.1, 1.612_441_348_720_219, 1.530_757_636_897_763),
            (0.5, 1.854_074_677_301_372, 1.350_643_881_047_675),
            (0.9, 2.578_092_113_348_173, 1.104_774_732_704_073),
        ];
        for (m, k, e) in table {
            let (kk, ee) = complete_elliptic(m).unwrap();
            assert!(close(kk, k, 1e-14), "K({m}) = {kk}, table {k}");
            assert!(close(ee, e, 1e-14), "E({m}) = {ee}, table {e}");
        }
        // Legendre's relation E K′ + E′ K − K K′ = π/2 (A&S 17.3.13)
        for m in [0.01, 0.3, 0.77, 0.999] {
            let (k, e) = complete_elliptic(m).unwrap();
            let (kp, ep) = complete_elliptic(1.0 - m).unwrap();
            assert!(
                (e * kp + ep * k - k * kp - 0.5 * PI).abs() < 1e-13,
                "m = {m}"
            );
        }
        assert!(complete_elliptic(1.0).is_err());
        assert!(complete_elliptic(-0.1).is_err());
        assert!(complete_elliptic(f64::NAN).is_err());
    }

    /// Equal curvatures: the sphere on a flat, a = (3PR/(4E*))^⅓,
    /// p₀ = 3P/(2πa²), δ = a²/R (Johnson §4.2, the circular case).
    #[test]
    fn circular_limit_is_the_sphere() {
        let (p, r, es) = (1000.0, 10.0, 115_384.6);
        let h = hertz_elliptic(p, 0.5 / r, 0.5 / r, es).unwrap();
        let a = (3.0 * p * r / (4.0 * es)).cbrt();
        assert!(close(h.semi_x, a, 1e-14) && close(h.semi_y, a, 1e-14));
        assert!(close(h.p0, 3.0 * p / (2.0 * PI * a * a), 1e-14));
        assert!(close(h.approach, a * a / r, 1e-14));
        assert_eq!(h.eccentricity, 0.0);
        // a nearly circular contact tends to the same (no cancellation)
        let n = hertz_elliptic(p, 0.5 / r, 0.5 / r * (1.0 + 1e-9), es).unwrap();
        assert!(close(n.semi_x, a, 1e-9) && close(n.semi_y, a, 1e-9));
        assert!(n.semi_x > n.semi_y);
    }

    /// Timoshenko & Goodier, *Theory of Elasticity*, 3rd ed. 1970, §140:
    /// a = m (3P/(4E*(A+B)))^⅓, b = n (…)^⅓ with cos θ = (B − A)/(B + A);
    /// their table (three decimals; the entries 30°–60° and 90°; Cooper,
    /// J. Appl. Mech. 36, 1969, notes third-decimal errors in the classical
    /// tables, so the table is a check to its rounding, not to round-off).
    #[test]
    fn semi_axes_match_timoshenko_goodier() {
        let table = [
            (30.0, 2.731, 0.493),
            (40.0, 2.136, 0.567),
            (50.0, 1.754, 0.641),
            (60.0, 1.486, 0.717),
            (90.0, 1.0, 1.0),
        ];
        let (p, es) = (500.0, 100_000.0);
        for (theta, m, n) in table {
            let c = f64::to_radians(theta).cos();
            // A + B = 1, B − A = cos θ
            let (a_curv, b_curv) = (0.5 * (1.0 - c), 0.5 * (1.0 + c));
            let h = hertz_elliptic(p, a_curv, b_curv, es).unwrap();
            let scale = (3.0 * p / (4.0 * es)).cbrt();
            assert!(
                (h.semi_x / scale - m).abs() <= 6e-4 && (h.semi_y / scale - n).abs() <= 6e-4,
                "θ = {theta}: m = {:.4} ({m}), n = {:.4} ({n})",
                h.semi_x / scale,
                h.semi_y / scale
            );
        }
    }

    /// The exact solution satisfies its defining equations, and Hamrock &
    /// Brewe's fits agree with it within their few per cent (0.3 % at
    /// B/A = 4).
    #[test]
    fn solution_satisfies_the_hertz_equations_and_hamrock_brewe() {
        let (p, es) = (2000.0, 115_384.6);
        for (ax, ay) in [
            (0.025, 0.1),
            (0.1, 0.025),
            (0.05, 0.06),
            (0.05, 0.1),
            (0.01, 0.5),
        ] {
            let h = hertz_elliptic(p, ax, ay, es).unwrap();
            let (a, b) = (h.semi_x.max(h.semi_y), h.semi_x.min(h.semi_y));
            let (sa, sb) = (ax.min(ay), ax.max(ay));
            let e2 = 1.0 - (b / a).powi(2);
            assert!(close(
                sb / sa,
                ((a / b).powi(2) * h.e - h.k) / (h.k - h.e),
                1e-10
            ));
            assert!(close(sa, h.p0 * b * (h.k - h.e) / (es * e2 * a * a), 1e-12));
            assert!(close(p, 2.0 / 3.0 * PI * a * b * h.p0, 1e-14));
            // semi-axis along the smaller curvature is the larger one
            assert_eq!(ax < ay, h.semi_x > h.semi_y);
            // Hamrock & Brewe fitted ratios 1–100, but near 1 their k is
            // 3.4 % high (1.0339 at ratio 1): compared from ratio 2 on
            if ax.max(ay) / ax.min(ay) < 2.0 {
                continue;
            }
            let hb = hamrock_brewe(p, ax, ay, es);
            for (x, y, what) in [
                (hb.semi_x, h.semi_x, "a_x"),
                (hb.semi_y, h.semi_y, "a_y"),
                (hb.p0, h.p0, "p0"),
                (hb.approach, h.approach, "δ"),
            ] {
                assert!(close(x, y, 0.03), "{what}: H&B {x}, exact {y} ({ax}, {ay})");
            }
        }
    }

    #[test]
    fn bad_input_is_an_error() {
        assert!(hertz_elliptic(0.0, 0.1, 0.1, 1e5).is_err());
        assert!(hertz_elliptic(1.0, -0.1, 0.1, 1e5).is_err());
        assert!(hertz_elliptic(1.0, 0.1, f64::NAN, 1e5).is_err());
        assert!(hertz_elliptic(1.0, 0.1, 0.1, 0.0).is_err());
        assert!(hertz_elliptic(1.0, 1e-30, 1.0, 1e5).is_err());
    }
}
