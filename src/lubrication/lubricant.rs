//! Lubricant and thermal data of a lubricated contact, validated.
//!
//! Units: flank's coherent internal system mm, N, s, MPa, K (mass in
//! tonnes). The scene converts from the SI-named keys:
//!
//! | quantity | symbol | scene key | internal |
//! |---|---|---|---|
//! | viscosity at the bulk temperature | η₀ | `viscosity_pa_s` | MPa·s (× 1e-6) |
//! | pressure–viscosity coefficient | α | `pressure_viscosity_per_gpa` | 1/MPa (× 1e-3) |
//! | temperature–viscosity coefficient | β | `temperature_viscosity_per_k` | 1/K |
//! | Eyring stress | τ₀ | `eyring_stress_mpa` | MPa |
//! | lubricant conductivity | K_l | `conductivity_w_per_m_k` | N/(s·K) (= W/(m·K), same number) |
//! | solid density | ρ_g | `solid_density_kg_per_m3` | t/mm³ (× 1e-12) |
//! | solid specific heat | c_g | `solid_specific_heat_j_per_kg_k` | mm²/(s²·K) (× 1e6) |
//! | solid conductivity | K_g | `solid_conductivity_w_per_m_k` | N/(s·K) |
//!
//! The products the formulas use are unit-consistent in this system
//! (ρ_g c_g in MPa/K = J/(m³·K) × 1e-6), so the dimensionless EHL groups
//! come out the same as in SI.

use crate::error::FlankError;

/// A lubricant at its bulk (inlet) temperature and the solids' thermal data
/// (internal units, see the module docs).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Lubricant {
    /// Free text (what oil, which source).
    pub name: String,
    /// Bulk temperature the data refer to (°C; informative).
    pub bulk_temperature_c: Option<f64>,
    /// η₀ (MPa·s).
    pub viscosity_mpa_s: f64,
    /// α (1/MPa), Barus η = η₀ exp(α p).
    pub pressure_viscosity_per_mpa: f64,
    /// β (1/K), η = η₀ exp(−β ΔT): the thermal Eyring traction needs it.
    pub temperature_viscosity_per_k: f64,
    /// τ₀ (MPa).
    pub eyring_stress_mpa: f64,
    /// K_l (N/(s·K) = W/(m·K)).
    pub conductivity: f64,
    /// ρ_g (t/mm³).
    pub solid_density: f64,
    /// c_g (mm²/(s²·K) = 1e-6 J/(kg·K)).
    pub solid_specific_heat: f64,
    /// K_g (N/(s·K) = W/(m·K)).
    pub solid_conductivity: f64,
}

/// One range check: key (scene name), the value in scene units, and the
/// accepted closed interval with why.
pub struct RangeCheck {
    pub key: &'static str,
    pub min: f64,
    pub max: f64,
    pub why: &'static str,
}

/// Accepted ranges of the scene keys (scene units). Wide enough for any
/// mineral, synthetic or aviation oil and any steel or bronze; a value
/// outside is almost surely a unit slip (Pa·s for mPa·s, 1/Pa for 1/GPa).
pub const RANGES: &[RangeCheck] = &[
    RangeCheck {
        key: "viscosity_pa_s",
        min: 1e-4,
        max: 10.0,
        why: "dynamic viscosity in Pa·s (water 0.001, gear oils 0.003–1)",
    },
    RangeCheck {
        key: "pressure_viscosity_per_gpa",
        min: 1.0,
        max: 60.0,
        why: "α in 1/GPa (synthetic esters ≈ 8–12, mineral oils 15–35)",
    },
    RangeCheck {
        key: "temperature_viscosity_per_k",
        min: 1e-3,
        max: 0.2,
        why: "β in 1/K (oils ≈ 0.02–0.06)",
    },
    RangeCheck {
        key: "eyring_stress_mpa",
        min: 0.1,
        max: 100.0,
        why: "τ₀ in MPa (EHL oils ≈ 2–10)",
    },
    RangeCheck {
        key: "conductivity_w_per_m_k",
        min: 0.01,
        max: 1.0,
        why: "oil conductivity in W/(m·K) (≈ 0.1–0.15)",
    },
    RangeCheck {
        key: "solid_density_kg_per_m3",
        min: 1000.0,
        max: 25000.0,
        why: "solid density in kg/m³ (steel 7800)",
    },
    RangeCheck {
        key: "solid_specific_heat_j_per_kg_k",
        min: 50.0,
        max: 5000.0,
        why: "solid specific heat in J/(kg·K) (steel ≈ 460)",
    },
    RangeCheck {
        key: "solid_conductivity_w_per_m_k",
        min: 0.1,
        max: 500.0,
        why: "solid conductivity in W/(m·K) (steel ≈ 45)",
    },
];

/// Checks `value` (scene units) of `key` against [`RANGES`]: the message
/// names the key, the value and the range.
pub fn check_range(key: &str, value: f64) -> Result<f64, String> {
    let Some(r) = RANGES.iter().find(|r| r.key == key) else {
        return Err(format!("`{key}`: not a lubricant key"));
    };
    if !value.is_finite() {
        return Err(format!("`{key}` = {value}: must be a finite number"));
    }
    if !(r.min..=r.max).contains(&value) {
        return Err(format!(
            "`{key}` = {value}: must lie in {} … {} ({})",
            r.min, r.max, r.why
        ));
    }
    Ok(value)
}

/// Lubricant data in the scene's units (SI-named), before conversion.
#[derive(Clone, Debug, PartialEq)]
pub struct LubricantSi {
    pub name: String,
    pub bulk_temperature_c: Option<f64>,
    pub viscosity_pa_s: f64,
    pub pressure_viscosity_per_gpa: f64,
    pub temperature_viscosity_per_k: f64,
    pub eyring_stress_mpa: f64,
    pub conductivity_w_per_m_k: f64,
    pub solid_density_kg_per_m3: f64,
    pub solid_specific_heat_j_per_kg_k: f64,
    pub solid_conductivity_w_per_m_k: f64,
}

impl LubricantSi {
    /// The values with their keys, in [`RANGES`] order.
    pub fn keyed(&self) -> [(&'static str, f64); 8] {
        [
            ("viscosity_pa_s", self.viscosity_pa_s),
            (
                "pressure_viscosity_per_gpa",
                self.pressure_viscosity_per_gpa,
            ),
            (
                "temperature_viscosity_per_k",
                self.temperature_viscosity_per_k,
            ),
            ("eyring_stress_mpa", self.eyring_stress_mpa),
            ("conductivity_w_per_m_k", self.conductivity_w_per_m_k),
            ("solid_density_kg_per_m3", self.solid_density_kg_per_m3),
            (
                "solid_specific_heat_j_per_kg_k",
                self.solid_specific_heat_j_per_kg_k,
            ),
            (
                "solid_conductivity_w_per_m_k",
                self.solid_conductivity_w_per_m_k,
            ),
        ]
    }
}

impl Lubricant {
    /// Range-checks `si` and converts it to internal units.
    pub fn from_si(si: &LubricantSi) -> Result<Self, FlankError> {
        for (key, v) in si.keyed() {
            check_range(key, v).map_err(|m| FlankError::Model(format!("[lubricant] {m}")))?;
        }
        Ok(Lubricant {
            name: si.name.clone(),
            bulk_temperature_c: si.bulk_temperature_c,
            viscosity_mpa_s: si.viscosity_pa_s * 1e-6,
            pressure_viscosity_per_mpa: si.pressure_viscosity_per_gpa * 1e-3,
            temperature_viscosity_per_k: si.temperature_viscosity_per_k,
            eyring_stress_mpa: si.eyring_stress_mpa,
            conductivity: si.conductivity_w_per_m_k,
            solid_density: si.solid_density_kg_per_m3 * 1e-12,
            solid_specific_heat: si.solid_specific_heat_j_per_kg_k * 1e6,
            solid_conductivity: si.solid_conductivity_w_per_m_k,
        })
    }

    /// ρ_g c_g (MPa/K).
    pub fn solid_heat_capacity_volumetric(&self) -> f64 {
        self.solid_density * self.solid_specific_heat
    }

    /// Checks values built by hand in internal units (library callers):
    /// every value finite and in the ranges of [`RANGES`].
    pub fn validate(&self) -> Result<(), FlankError> {
        let si = LubricantSi {
            name: self.name.clone(),
            bulk_temperature_c: self.bulk_temperature_c,
            viscosity_pa_s: self.viscosity_mpa_s * 1e6,
            pressure_viscosity_per_gpa: self.pressure_viscosity_per_mpa * 1e3,
            temperature_viscosity_per_k: self.temperature_viscosity_per_k,
            eyring_stress_mpa: self.eyring_stress_mpa,
            conductivity_w_per_m_k: self.conductivity,
            solid_density_kg_per_m3: self.solid_density * 1e12,
            solid_specific_heat_j_per_kg_k: self.solid_specific_heat * 1e-6,
            solid_conductivity_w_per_m_k: self.solid_conductivity,
        };
        for (key, v) in si.keyed() {
            check_range(key, v).map_err(|m| FlankError::Model(format!("lubricant: {m}")))?;
        }
        Ok(())
    }
}

#[cfg(test)]
pub(crate) fn test_oil() -> LubricantSi {
    LubricantSi {
        name: "test oil".into(),
        bulk_temperature_c: Some(100.0),
        viscosity_pa_s: 0.0045,
        pressure_viscosity_per_gpa: 11.0,
        temperature_viscosity_per_k: 0.03,
        eyring_stress_mpa: 4.0,
        conductivity_w_per_m_k: 0.14,
        solid_density_kg_per_m3: 7800.0,
        solid_specific_heat_j_per_kg_k: 460.0,
        solid_conductivity_w_per_m_k: 45.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn converts_and_round_trips() {
        let l = Lubricant::from_si(&test_oil()).unwrap();
        assert!((l.viscosity_mpa_s - 4.5e-9).abs() < 1e-20);
        assert!((l.pressure_viscosity_per_mpa - 0.011).abs() < 1e-15);
        // ρc = 7800 × 460 J/(m³K) = 3.588e6 Pa/K = 3.588 MPa/K
        assert!((l.solid_heat_capacity_volumetric() - 3.588).abs() < 1e-12);
        l.validate().unwrap();
    }

    #[test]
    fn bad_values_name_the_key() {
        for (edit, words) in [
            (
                (|s: &mut LubricantSi| s.viscosity_pa_s = -0.01) as fn(&mut LubricantSi),
                &["viscosity_pa_s", "-0.01"][..],
            ),
            (
                |s: &mut LubricantSi| s.pressure_viscosity_per_gpa = 2.0e-8,
                &["pressure_viscosity_per_gpa", "1/GPa"][..],
            ),
            (
                |s: &mut LubricantSi| s.eyring_stress_mpa = f64::NAN,
                &["eyring_stress_mpa", "finite"][..],
            ),
        ] {
            let mut s = test_oil();
            edit(&mut s);
            let e = Lubricant::from_si(&s).unwrap_err().to_string();
            for w in words {
                assert!(e.contains(w), "{e} lacks {w}");
            }
        }
    }
}
