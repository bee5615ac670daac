//! Mean normal circular tooth thickness, ISO 23509:2016 clause 7.8.
//!
//! s_mn1 = m_mn (π/2 + x_hm1 (tan α_nD + tan α_nC) + 2 x_smn) − j_mn/2,
//! s_mn2 = m_mn (π/2 − x_hm1 (tan α_nD + tan α_nC) − 2 x_smn) − j_mn/2,
//! with the generated pressure angles α_nD = α_dD + f_αlim α_lim,
//! α_nC = α_dC − f_αlim α_lim (clause 7.2) and the mean normal backlash j_mn
//! (from an outer normal backlash, j_mn = j_en R_m2 / R_e2), split equally
//! over both members. Data type II: x_smn = k_t / 2.

use super::inputs::Backlash;

/// Mean normal backlash j_mn from the input's backlash.
pub fn mean_normal_backlash(backlash: Backlash, rm2: f64, re2: f64) -> f64 {
    match backlash {
        Backlash::OuterNormal(j) => j * rm2 / re2,
        Backlash::MeanNormal(j) => j,
    }
}

/// (s_mn1, s_mn2) in mm; `alpha_n` = (α_nD, α_nC).
pub fn mean_normal_thickness(
    m_mn: f64,
    x_hm1: f64,
    x_smn: f64,
    alpha_n: (f64, f64),
    j_mn: f64,
) -> (f64, f64) {
    let (alpha_n_drive, alpha_n_coast) = alpha_n;
    let shift = x_hm1 * (alpha_n_drive.tan() + alpha_n_coast.tan()) + 2.0 * x_smn;
    let half = std::f64::consts::FRAC_PI_2;
    (
        m_mn * (half + shift) - j_mn / 2.0,
        m_mn * (half - shift) - j_mn / 2.0,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thicknesses_fill_the_pitch_less_backlash() {
        let (s1, s2) = mean_normal_thickness(
            3.0,
            0.4,
            0.05,
            (20f64.to_radians(), 18f64.to_radians()),
            mean_normal_backlash(Backlash::OuterNormal(0.2), 80.0, 100.0),
        );
        assert!((s1 + s2 - (3.0 * std::f64::consts::PI - 0.16)).abs() < 1e-12);
        assert!(s1 > s2);
    }
}
