//! Traction coefficient of an EHL contact in the thermal Eyring regime
//! (Evans & Johnson, "The rheological properties of elastohydrodynamic
//! lubricants", Proc. IMechE C 200 (1986) 303–312; seed 002 eqs. 4–5):
//!
//! ```text
//!   μ = 0.87 α τ₀ + (1.74 τ₀ / P̄) ln[ (1.2 / (τ₀ h_c)) (2 K_l η₀ / (β (1 + 9.6 ζ)))^½ ]
//!   ζ = (4 K_l / (π h_c*)) (P̄ / (E_r R_x K_g ρ_g c_g u))^½,   h_c* = h_c / R_x
//! ```
//!
//! **β restored.** Seed 002's eq. 4 reads (2 K_l η₀/(1 + 9.6ζ))^½ without
//! the temperature–viscosity coefficient β: then the argument of the
//! logarithm has the unit K^−½ and μ would change with the temperature
//! scale. The thermal Eyring limit behind the formula (an Eyring fluid
//! η = η₀ exp(α p − β ΔT) whose shear heating is conducted to the walls,
//! Johnson & Greenwood, Wear 61 (1980) 353–374) limits the stress to
//! τ ≈ τ₀ ln[c · K_l η/(β τ₀ τ h²)] (c a number), whose group is
//! dimensionless only with β; and 1.74 = 2 × 0.87 is the Hertz mean of the
//! ½ α p that comes out of the root of η₀ exp(α p). flank uses β. (The
//! original paper was not at hand: this is a dimensional argument, stated
//! in `verification/ehl_formulas/README.md`.)
//!
//! **E_r in ζ**: the seed does not define its reduced modulus; flank uses
//! the E′ of the film formula (R_x P̄/E′ stands for a length of the order of
//! the contact semi-width). ζ enters through ln(1 + 9.6ζ)/2 only.
//!
//! **Regime check** (Evans & Johnson's map: Newtonian, Eyring, thermal,
//! limiting shear): the formula assumes a thermal Eyring film whose mean
//! shear stress τ̄ = μ P̄ is well above τ₀ (sinh x ≈ eˣ/2 within 2 % needs
//! x ≥ 2) and a sliding speed high enough that shear heating limits the
//! stress. Two flags, the value itself is never altered:
//! [`TractionFlag::NotEyring`] when τ̄ < 2 τ₀, and
//! [`TractionFlag::IsothermalBelowThermal`] when the isothermal Eyring stress
//! τ₀ asinh(η₀ e^(α P̄) |v_s| /(τ₀ h_c)) at the contact's sliding speed is
//! below the thermal τ̄ (low slide, near the pitch point: the formula,
//! which does not depend on the sliding speed, overestimates the traction).
//! At low mean pressure and thin films the logarithm turns so negative that
//! the formula gives μ ≤ 0 (it has left its regime altogether): then μ is
//! the isothermal Eyring value τ_iso/P̄ instead, flagged
//! [`TractionFlag::ThermalFormulaNotPositive`] (and counted in the run's
//! summary), never a silent negative or clipped value.

use crate::error::FlankError;
use crate::lubrication::lubricant::Lubricant;

/// Where the contact is outside the formula's regime.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum TractionFlag {
    /// Mean shear stress μP̄ below 2τ₀: not in the (non-linear) Eyring regime.
    NotEyring,
    /// The isothermal Eyring stress at this sliding speed is below the
    /// thermal one: the thermal formula overestimates μ.
    IsothermalBelowThermal,
    /// The thermal formula gave μ ≤ 0; μ is the isothermal Eyring value.
    ThermalFormulaNotPositive,
}

/// What the traction formula needs (internal units mm, N, s, MPa, K).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct TractionInput {
    /// Central film thickness h_c (mm), R_x (mm), E′ (MPa).
    pub central_film: f64,
    pub radius_x: f64,
    pub reduced_modulus: f64,
    /// P̄ = W/A (MPa).
    pub mean_pressure: f64,
    /// Entraining speed u and sliding speed v_s (mm/s).
    pub entraining_speed: f64,
    pub sliding_speed: f64,
}

/// The traction coefficient with its terms and regime flags.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Traction {
    /// The traction coefficient used: `mu_thermal` when positive, else the
    /// isothermal Eyring value (flagged).
    pub mu: f64,
    /// Evans & Johnson's thermal Eyring value (seed eq. 4, β restored).
    pub mu_thermal: f64,
    /// ζ (thermal parameter of seed eq. 5).
    pub zeta: f64,
    /// Mean shear stress τ̄ = μ P̄ (MPa) and the isothermal Eyring one (MPa).
    pub shear_stress_mpa: f64,
    pub isothermal_shear_stress_mpa: f64,
    pub flags: Vec<TractionFlag>,
}

/// μ of `input` with `lub` (module docs).
pub fn traction(lub: &Lubricant, input: &TractionInput) -> Result<Traction, FlankError> {
    let TractionInput {
        central_film: h,
        radius_x: rx,
        reduced_modulus: e,
        mean_pressure: p,
        entraining_speed: u,
        sliding_speed: vs,
    } = *input;
    for (name, v) in [
        ("central film thickness h_c (mm)", h),
        ("equivalent radius R_x (mm)", rx),
        ("reduced modulus E′ (MPa)", e),
        ("mean pressure P̄ (MPa)", p),
        ("entraining speed u (mm/s)", u),
    ] {
        if !(v > 0.0 && v.is_finite()) {
            return Err(FlankError::Model(format!(
                "traction: {name} = {v}: a finite value > 0 is needed"
            )));
        }
    }
    if !vs.is_finite() {
        return Err(FlankError::Model(format!(
            "traction: sliding speed {vs} mm/s is not finite"
        )));
    }
    let tau0 = lub.eyring_stress_mpa;
    let alpha = lub.pressure_viscosity_per_mpa;
    let k = lub.conductivity;
    let eta0 = lub.viscosity_mpa_s;
    let beta = lub.temperature_viscosity_per_k;
    let h_star = h / rx;
    let zeta = 4.0 * k / (std::f64::consts::PI * h_star)
        * (p / (e * rx * lub.solid_conductivity * lub.solid_heat_capacity_volumetric() * u)).sqrt();
    let arg = 1.2 / (tau0 * h) * (2.0 * k * eta0 / (beta * (1.0 + 9.6 * zeta))).sqrt();
    let mu_thermal = 0.87 * alpha * tau0 + 1.74 * tau0 / p * arg.ln();
    // isothermal Eyring: τ = τ₀ asinh(η γ̇/τ₀), η at P̄ (Barus), γ̇ = |v_s|/h
    let eta = eta0 * (alpha * p).exp();
    let tau_iso = tau0 * (eta * vs.abs() / (tau0 * h)).asinh();
    if !(mu_thermal.is_finite() && tau_iso.is_finite()) {
        return Err(FlankError::Model(format!(
            "traction (Evans & Johnson): μ = {mu_thermal}, isothermal stress {tau_iso} MPa at h_c = {:.4} µm, P̄ = {p:.1} MPa, u = {:.3} m/s: not finite",
            h * 1e3,
            u * 1e-3
        )));
    }
    let mut flags = Vec::new();
    let mu = if mu_thermal > 0.0 {
        mu_thermal
    } else {
        flags.push(TractionFlag::ThermalFormulaNotPositive);
        tau_iso / p
    };
    let tau = mu * p;
    if tau < 2.0 * tau0 {
        flags.push(TractionFlag::NotEyring);
    }
    if mu_thermal > 0.0 && tau_iso < tau {
        flags.push(TractionFlag::IsothermalBelowThermal);
    }
    Ok(Traction {
        mu,
        mu_thermal,
        zeta,
        shear_stress_mpa: tau,
        isothermal_shear_stress_mpa: tau_iso,
        flags,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lubrication::lubricant::test_oil;

    #[test]
    fn si_hand_value() {
        // the same formula evaluated in SI (m, Pa, W) must agree
        let si = test_oil();
        let lub = Lubricant::from_si(&si).unwrap();
        let (h, r, e, p, u) = (0.5e-6, 0.01, 2.26e11, 1.0e9, 10.0);
        let t = traction(
            &lub,
            &TractionInput {
                central_film: h * 1e3,
                radius_x: r * 1e3,
                reduced_modulus: e * 1e-6,
                mean_pressure: p * 1e-6,
                entraining_speed: u * 1e3,
                sliding_speed: 3.0e3,
            },
        )
        .unwrap();
        let tau0 = si.eyring_stress_mpa * 1e6;
        let alpha = si.pressure_viscosity_per_gpa * 1e-9;
        let k = si.conductivity_w_per_m_k;
        let zeta = 4.0 * k / (std::f64::consts::PI * h / r)
            * (p / (e
                * r
                * si.solid_conductivity_w_per_m_k
                * si.solid_density_kg_per_m3
                * si.solid_specific_heat_j_per_kg_k
                * u))
                .sqrt();
        let mu = 0.87 * alpha * tau0
            + 1.74 * tau0 / p
                * (1.2 / (tau0 * h)
                    * (2.0 * k * si.viscosity_pa_s
                        / (si.temperature_viscosity_per_k * (1.0 + 9.6 * zeta)))
                        .sqrt())
                .ln();
        assert!((t.zeta / zeta - 1.0).abs() < 1e-12, "{} {zeta}", t.zeta);
        assert!((t.mu / mu - 1.0).abs() < 1e-12, "{} {mu}", t.mu);
    }
}
