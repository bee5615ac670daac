//! Isotropic linear-elastic material.

use crate::error::FlankError;

/// Poisson's ratio above which [`Material::locking_warning`] warns.
pub const NEARLY_INCOMPRESSIBLE: f64 = 0.49;

/// Isotropic linear-elastic material (E in MPa).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Material {
    pub name: String,
    /// Young's modulus E (MPa).
    pub young: f64,
    /// Poisson's ratio ν.
    pub poisson: f64,
    /// Mass density ρ (t/mm³ in flank's N-mm-s units), CalculiX's `*DENSITY`;
    /// needed only by body loads (gravity, centrifugal).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub density: Option<f64>,
    /// Isotropic thermal expansion coefficient α (1/K), CalculiX's
    /// `*EXPANSION`; the thermal strain is α (T − T0) I where the model has
    /// temperatures.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub expansion: Option<f64>,
}

impl Material {
    /// Creates a material, rejecting E ≤ 0, ν ≤ −1, ν ≥ 0.5 and non-finite values.
    pub fn new(name: &str, young: f64, poisson: f64) -> Result<Self, FlankError> {
        let m = Material {
            name: name.to_string(),
            young,
            poisson,
            density: None,
            expansion: None,
        };
        m.validate()?;
        Ok(m)
    }

    /// Checks that the elasticity tensor is positive definite.
    pub fn validate(&self) -> Result<(), FlankError> {
        if !self.young.is_finite() || self.young <= 0.0 {
            return Err(FlankError::Material(format!(
                "material '{}': Young's modulus must be positive and finite, got {}",
                self.name, self.young
            )));
        }
        if !self.poisson.is_finite() || self.poisson <= -1.0 || self.poisson >= 0.5 {
            return Err(FlankError::Material(format!(
                "material '{}': Poisson's ratio must lie in (-1, 0.5), got {}",
                self.name, self.poisson
            )));
        }
        if let Some(rho) = self.density {
            if !rho.is_finite() || rho <= 0.0 {
                return Err(FlankError::Material(format!(
                    "material '{}': density must be positive and finite, got {rho}",
                    self.name
                )));
            }
        }
        if let Some(alpha) = self.expansion {
            if !alpha.is_finite() {
                return Err(FlankError::Material(format!(
                    "material '{}': expansion coefficient must be finite, got {alpha}",
                    self.name
                )));
            }
        }
        Ok(())
    }

    /// A warning when ν is near ½: the fully integrated quadratic elements
    /// of flank's meshers (C3D20, C3D15) lock volumetrically as λ/μ grows
    /// like 1/(1 − 2ν), and flank has no mixed (u–p) formulation. Above
    /// [`NEARLY_INCOMPRESSIBLE`] (λ/μ > 49). Measured in
    /// verification/extreme: at ν = 0.4999 the hex20 and wedge15 answers of
    /// the same pair differ by 5.5 % in TE (0.4 % at ν = 0.3).
    pub fn locking_warning(&self) -> Option<String> {
        (self.poisson > NEARLY_INCOMPRESSIBLE).then(|| {
            format!(
                "material '{}': Poisson's ratio {} is near 0.5 (λ/μ = {:.3e}): fully integrated hex20/wedge15 elements lock volumetrically there and flank has no mixed formulation; the stiffness may be overestimated (verification/extreme: hex20 and wedge15 differ by 5.5 % in TE at ν = 0.4999)",
                self.name,
                self.poisson,
                2.0 * self.poisson / (1.0 - 2.0 * self.poisson)
            )
        })
    }

    /// Lamé parameters (λ, μ).
    pub fn lame(&self) -> (f64, f64) {
        let e = self.young;
        let nu = self.poisson;
        let mu = e / (2.0 * (1.0 + nu));
        let lambda = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
        (lambda, mu)
    }

    /// Shear modulus G.
    pub fn shear_modulus(&self) -> f64 {
        self.lame().1
    }

    /// Stress (Voigt: xx, yy, zz, xy, yz, xz) from the displacement gradient ∇u (row i = ∂u_i/∂x_j).
    pub fn stress_from_gradient(&self, grad: &[[f64; 3]; 3]) -> [f64; 6] {
        let (lambda, mu) = self.lame();
        let tr = grad[0][0] + grad[1][1] + grad[2][2];
        [
            lambda * tr + 2.0 * mu * grad[0][0],
            lambda * tr + 2.0 * mu * grad[1][1],
            lambda * tr + 2.0 * mu * grad[2][2],
            mu * (grad[0][1] + grad[1][0]),
            mu * (grad[1][2] + grad[2][1]),
            mu * (grad[0][2] + grad[2][0]),
        ]
    }
}

/// Von Mises equivalent stress of a Voigt stress (xx, yy, zz, xy, yz, xz).
pub fn von_mises(s: &[f64; 6]) -> f64 {
    let [xx, yy, zz, xy, yz, xz] = *s;
    (0.5 * ((xx - yy).powi(2) + (yy - zz).powi(2) + (zz - xx).powi(2))
        + 3.0 * (xy * xy + yz * yz + xz * xz))
        .sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn locking_warning_near_one_half_only() {
        let m = |nu: f64| Material::new("m", 1.0, nu).unwrap();
        assert!(m(0.3).locking_warning().is_none());
        assert!(m(0.49).locking_warning().is_none());
        let w = m(0.4999).locking_warning().unwrap();
        assert!(w.contains("near 0.5") && w.contains("4.999e3"), "{w}");
    }

    #[test]
    fn rejects_bad_constants() {
        assert!(Material::new("a", -1.0, 0.3).is_err());
        assert!(Material::new("a", 1.0, 0.5).is_err());
        assert!(Material::new("a", 1.0, f64::NAN).is_err());
        assert!(Material::new("a", 210e3, 0.3).is_ok());
    }

    #[test]
    fn von_mises_uniaxial() {
        assert!((von_mises(&[100.0, 0.0, 0.0, 0.0, 0.0, 0.0]) - 100.0).abs() < 1e-12);
        assert!((von_mises(&[0.0, 0.0, 0.0, 10.0, 0.0, 0.0]) - 10.0 * 3f64.sqrt()).abs() < 1e-12);
    }
}
