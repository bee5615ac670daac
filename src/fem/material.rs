//! Isotropic linear-elastic material.

use crate::error::FlankError;

/// Isotropic linear-elastic material (E in MPa).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Material {
    pub name: String,
    /// Young's modulus E (MPa).
    pub young: f64,
    /// Poisson's ratio ν.
    pub poisson: f64,
}

impl Material {
    /// Creates a material, rejecting E ≤ 0, ν ≤ −1, ν ≥ 0.5 and non-finite values.
    pub fn new(name: &str, young: f64, poisson: f64) -> Result<Self, FlankError> {
        let m = Material {
            name: name.to_string(),
            young,
            poisson,
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
        Ok(())
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
