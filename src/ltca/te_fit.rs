//! Quadratic fit of the loaded transmission error over a mesh cycle: seed
//! 003 approximates the LTE of its hypoid pair as Δθ(φ) = a₀ + a₁φ + a₂φ²
//! in the pinion rotation φ. flank fits the cycle's positions by linear
//! least squares (the Vandermonde columns 1, φ − φ̄, (φ − φ̄)² solved by
//! SVD, then expanded about φ = 0, so the coefficients are the paper's
//! form) and reports the residual beside the coefficients: a large one
//! says the curve is no parabola (a transfer inside the cycle).

use nalgebra::{DMatrix, DVector};

/// Δθ(φ) ≈ a₀ + a₁φ + a₂φ² with φ the pinion roll (deg) and Δθ the TE at
/// the gear (arcsec).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct QuadraticTeFit {
    /// a₀ (″), a₁ (″/°), a₂ (″/°²).
    pub a0_arcsec: f64,
    pub a1_arcsec_per_deg: f64,
    pub a2_arcsec_per_deg2: f64,
    /// Root-mean-square and largest residual of the fit over the points (″).
    pub rms_residual_arcsec: f64,
    pub max_residual_arcsec: f64,
    /// Number of positions fitted.
    pub points: usize,
}

/// The least-squares parabola through (φᵢ, Δθᵢ); `None` with fewer than
/// three distinct angles or a non-finite value (no fit to report).
pub fn quadratic_te_fit(roll_deg: &[f64], te_arcsec: &[f64]) -> Option<QuadraticTeFit> {
    let n = roll_deg.len();
    if n != te_arcsec.len() || roll_deg.iter().chain(te_arcsec).any(|x| !x.is_finite()) {
        return None;
    }
    let mut distinct = roll_deg.to_vec();
    distinct.sort_by(f64::total_cmp);
    distinct.dedup();
    if distinct.len() < 3 {
        return None;
    }
    // centred and scaled abscissa: the columns stay well conditioned
    let mean = roll_deg.iter().sum::<f64>() / n as f64;
    let scale = roll_deg
        .iter()
        .map(|x| (x - mean).abs())
        .fold(0.0f64, f64::max);
    let a = DMatrix::from_fn(n, 3, |i, j| ((roll_deg[i] - mean) / scale).powi(j as i32));
    let b = DVector::from_column_slice(te_arcsec);
    let c = a.clone().svd(true, true).solve(&b, 1e-14).ok()?;
    // c₀ + c₁ t + c₂ t², t = (φ − m)/s, expanded in φ
    let (c0, c1, c2) = (c[0], c[1] / scale, c[2] / (scale * scale));
    let fit = QuadraticTeFit {
        a0_arcsec: c0 - c1 * mean + c2 * mean * mean,
        a1_arcsec_per_deg: c1 - 2.0 * c2 * mean,
        a2_arcsec_per_deg2: c2,
        rms_residual_arcsec: 0.0,
        max_residual_arcsec: 0.0,
        points: n,
    };
    let r: Vec<f64> = (&a * &c - &b).iter().map(|x| x.abs()).collect();
    Some(QuadraticTeFit {
        rms_residual_arcsec: (r.iter().map(|x| x * x).sum::<f64>() / n as f64).sqrt(),
        max_residual_arcsec: r.iter().cloned().fold(0.0, f64::max),
        ..fit
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recovers_a_parabola_off_centre() {
        // an asymmetric cycle away from φ = 0, as a grid of roll angles is
        let phi: Vec<f64> = (0..20).map(|i| 10.0 + 1.2 * i as f64).collect();
        let te: Vec<f64> = phi
            .iter()
            .map(|p| -118.0 + 0.35 * p - 0.021 * p * p)
            .collect();
        let f = quadratic_te_fit(&phi, &te).unwrap();
        assert!((f.a0_arcsec + 118.0).abs() < 1e-9, "{f:?}");
        assert!((f.a1_arcsec_per_deg - 0.35).abs() < 1e-10, "{f:?}");
        assert!((f.a2_arcsec_per_deg2 + 0.021).abs() < 1e-12, "{f:?}");
        assert!(f.max_residual_arcsec < 1e-10 && f.points == 20);
    }

    #[test]
    fn residual_of_a_non_parabola() {
        // |φ| is no parabola: the least-squares fit over −1, 0, 1, 2 leaves
        // a residual the report must show
        let f = quadratic_te_fit(&[-1.0, 0.0, 1.0, 2.0], &[1.0, 0.0, 1.0, 2.0]).unwrap();
        assert!(f.rms_residual_arcsec > 0.1, "{f:?}");
        assert!(f.max_residual_arcsec >= f.rms_residual_arcsec);
    }

    #[test]
    fn too_few_angles_or_bad_values() {
        assert!(quadratic_te_fit(&[1.0, 1.0, 2.0], &[0.0, 1.0, 2.0]).is_none());
        assert!(quadratic_te_fit(&[1.0, 2.0], &[0.0, 1.0]).is_none());
        assert!(quadratic_te_fit(&[1.0, 2.0, f64::NAN], &[0.0, 1.0, 2.0]).is_none());
        assert!(quadratic_te_fit(&[1.0, 2.0, 3.0], &[0.0, 1.0]).is_none());
    }
}
