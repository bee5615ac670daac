//! Tooth depths at the mean point, ISO 23509:2016 clause 7.3 (tooth depth
//! at the calculation point).
//!
//! Mean working depth h_mw = 2 k_hap m_mn. Data type I: h_am1,2 =
//! m_mn (k_hap ± x_hm1), h_fm1,2 = m_mn (k_hfp ∓ x_hm1). Data type II
//! (Gleason factors): the wheel's addendum is c_ham times the working depth
//! *at the outer end*, h_ae2 = c_ham h_we with h_we = h_mw + (R_e2 − R_m2)
//! (tan θ_a1 + tan θ_a2), and h_am2 = h_ae2 − (R_e2 − R_m2) tan θ_a2 (for
//! uniform depth simply c_ham h_mw); h_am1 = h_mw − h_am2; clearance c = k_c
//! h_mw; h_fm1 = h_am2 + c, h_fm2 = h_am1 + c; whole depth h_m = h_mw + c.

use super::inputs::ProfileFactors;

/// Mean tooth depths (mm) and the addendum/dedendum angles (rad).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ToothDepth {
    pub hmw: f64,
    pub ham1: f64,
    pub ham2: f64,
    pub hfm1: f64,
    pub hfm2: f64,
    pub c: f64,
    pub hm: f64,
    /// Profile shift coefficient x_hm1 (data type II: derived).
    pub x_hm1: f64,
}

/// Clause 7.3; `theta_a` = (θ_a1, θ_a2), the nominal addendum angles
/// (θ_a1 = θ_f2 for uniform clearance; zero for uniform depth), and
/// `b_out` = R_e2 − R_m2 (both used by data type II only).
pub fn tooth_depth(f: &ProfileFactors, m_mn: f64, theta_a: (f64, f64), b_out: f64) -> ToothDepth {
    let (theta_a1, theta_a2) = theta_a;
    let hmw = 2.0 * f.k_hap * m_mn;
    let c = (f.k_hfp - f.k_hap) * m_mn;
    let ham2 = match (f.x_hm1, f.c_ham) {
        (Some(x), _) => m_mn * (f.k_hap - x),
        (None, Some(c_ham)) => {
            let hwe = hmw + b_out * (theta_a1.tan() + theta_a2.tan());
            c_ham * hwe - b_out * theta_a2.tan()
        }
        (None, None) => unreachable!("validated: data type I or II"),
    };
    let ham1 = hmw - ham2;
    ToothDepth {
        hmw,
        ham1,
        ham2,
        hfm1: ham2 + c,
        hfm2: ham1 + c,
        c,
        hm: hmw + c,
        x_hm1: (ham1 - ham2) / (2.0 * m_mn),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniform_depth_type_ii_splits_the_working_depth_by_c_ham() {
        let f = ProfileFactors {
            k_hap: 1.0,
            k_hfp: 1.25,
            x_hm1: None,
            c_ham: Some(0.3),
            x_smn: 0.0,
        };
        let d = tooth_depth(&f, 4.0, (0.0, 0.0), 13.0);
        assert!((d.hmw - 8.0).abs() < 1e-12);
        assert!((d.ham2 - 2.4).abs() < 1e-12);
        assert!((d.ham1 - 5.6).abs() < 1e-12);
        assert!((d.c - 1.0).abs() < 1e-12);
        assert!((d.hfm1 - 3.4).abs() < 1e-12 && (d.hfm2 - 6.6).abs() < 1e-12);
        assert!((d.x_hm1 - 0.4).abs() < 1e-12);
    }

    #[test]
    fn type_i_and_type_ii_agree_for_the_same_shift() {
        let t1 = ProfileFactors {
            k_hap: 1.0,
            k_hfp: 1.25,
            x_hm1: Some(0.4),
            c_ham: None,
            x_smn: 0.0,
        };
        let t2 = ProfileFactors {
            x_hm1: None,
            c_ham: Some(0.3),
            ..t1
        };
        let (a, b) = (
            tooth_depth(&t1, 4.0, (0.0, 0.0), 13.0),
            tooth_depth(&t2, 4.0, (0.0, 0.0), 13.0),
        );
        assert!((a.ham1 - b.ham1).abs() < 1e-12 && (a.hfm2 - b.hfm2).abs() < 1e-12);
    }
}
