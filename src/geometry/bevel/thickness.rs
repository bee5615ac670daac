//! Tooth thickness, ISO 23509:2016 clause 7.8 (formulae (201)–(215)).
//!
//! With the mean normal pressure angle α_n = (α_nD + α_nC)/2, the
//! thickness modification coefficients carry the theoretical thickness
//! modification ±x_smn (data type II: x_smn = k_t/2) and half the backlash
//! of the pair each, converted to a mean normal circular thickness:
//! x_sm1 = x_smn − Δ, x_sm2 = −x_smn − Δ with
//!
//! * outer normal backlash j_en: Δ = j_en R_m2 cos β_m2 / (4 m_mn cos α_n
//!   R_e2 cos β_e2) (the normal pitch scales with R cos β along the trace);
//! * outer transverse backlash j_et2: Δ = j_et2 R_m2 cos β_m2 / (4 m_mn R_e2);
//! * mean normal backlash j_mn: Δ = j_mn / (4 m_mn cos α_n);
//! * mean transverse backlash j_mt2: Δ = j_mt2 cos β_m2 / (4 m_mn)
//!
//! (a normal backlash j_n is the circular backlash times cos α_n). Then
//! s_mn1 = m_mn (π/2 + 2 (x_sm1 + x_hm1 tan α_n)),
//! s_mn2 = m_mn (π/2 + 2 (x_sm2 − x_hm1 tan α_n)); the transverse
//! thicknesses s_mt = s_mn / cos β_m; the mean normal (virtual) diameters
//! d_mn = d_m / ((1 − sin² β_m cos² α_n) cos δ), the chordal thickness
//! s_mnc = d_mn sin(s_mn / d_mn) and the chordal addendum h_amc = h_am +
//! d_mn cos δ (1 − cos(s_mn / d_mn)) / 2.

use super::inputs::Backlash;

/// Thickness data of both members (index 0 pinion, 1 wheel; mm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Thickness {
    /// Mean normal pressure angle α_n (rad).
    pub alpha_n: f64,
    pub x_sm: [f64; 2],
    pub s_mn: [f64; 2],
    pub s_mt: [f64; 2],
    pub d_mn: [f64; 2],
    pub s_mnc: [f64; 2],
    pub h_amc: [f64; 2],
}

/// What clause 7.8 needs of the blank (mm, rad; index 0 pinion, 1 wheel).
pub struct ThicknessData {
    pub m_mn: f64,
    pub x_hm1: f64,
    pub x_smn: f64,
    pub alpha_n_drive: f64,
    pub alpha_n_coast: f64,
    pub rm2: f64,
    pub re2: f64,
    pub beta_m: [f64; 2],
    pub beta_e2: f64,
    pub dm: [f64; 2],
    pub delta: [f64; 2],
    pub ham: [f64; 2],
}

/// The backlash share Δ of each member (see the module docs).
pub fn backlash_share(b: Backlash, t: &ThicknessData, alpha_n: f64) -> f64 {
    let m4 = 4.0 * t.m_mn;
    let cb2 = t.beta_m[1].cos();
    match b {
        Backlash::OuterNormal(j) => {
            j * t.rm2 * cb2 / (m4 * alpha_n.cos() * t.re2 * t.beta_e2.cos())
        }
        Backlash::OuterTransverse(j) => j * t.rm2 * cb2 / (m4 * t.re2),
        Backlash::MeanNormal(j) => j / (m4 * alpha_n.cos()),
        Backlash::MeanTransverse(j) => j * cb2 / m4,
    }
}

/// Formulae (201)–(215).
pub fn thickness(t: &ThicknessData, backlash: Backlash) -> Thickness {
    let alpha_n = 0.5 * (t.alpha_n_drive + t.alpha_n_coast);
    let share = backlash_share(backlash, t, alpha_n);
    let x_sm = [t.x_smn - share, -t.x_smn - share];
    let shift = t.x_hm1 * alpha_n.tan();
    let half = std::f64::consts::FRAC_PI_2;
    let s_mn = [
        t.m_mn * (half + 2.0 * (x_sm[0] + shift)),
        t.m_mn * (half + 2.0 * (x_sm[1] - shift)),
    ];
    let each = |f: &dyn Fn(usize) -> f64| [f(0), f(1)];
    let d_mn = each(&|i| {
        t.dm[i] / ((1.0 - (t.beta_m[i].sin() * alpha_n.cos()).powi(2)) * t.delta[i].cos())
    });
    Thickness {
        alpha_n,
        x_sm,
        s_mn,
        s_mt: each(&|i| s_mn[i] / t.beta_m[i].cos()),
        d_mn,
        s_mnc: each(&|i| d_mn[i] * (s_mn[i] / d_mn[i]).sin()),
        h_amc: each(&|i| {
            t.ham[i] + 0.5 * d_mn[i] * t.delta[i].cos() * (1.0 - (s_mn[i] / d_mn[i]).cos())
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn data() -> ThicknessData {
        ThicknessData {
            m_mn: 3.0,
            x_hm1: 0.4,
            x_smn: 0.05,
            alpha_n_drive: 20f64.to_radians(),
            alpha_n_coast: 18f64.to_radians(),
            rm2: 80.0,
            re2: 100.0,
            beta_m: [40f64.to_radians(), 30f64.to_radians()],
            beta_e2: 33f64.to_radians(),
            dm: [40.0, 120.0],
            delta: [0.3, 1.2],
            ham: [4.0, 2.0],
        }
    }

    /// The two thicknesses fill the normal pitch π m_mn less the mean normal
    /// circular backlash j_mn / cos α_n.
    #[test]
    fn thicknesses_fill_the_pitch_less_backlash() {
        let t = data();
        let th = thickness(&t, Backlash::MeanNormal(0.2));
        let sum = th.s_mn[0] + th.s_mn[1];
        assert!((sum - (3.0 * std::f64::consts::PI - 0.2 / th.alpha_n.cos())).abs() < 1e-12);
        assert!(th.s_mn[0] > th.s_mn[1]);
        // Outer normal backlash: scaled by the normal pitch ratio.
        let o = thickness(&t, Backlash::OuterNormal(0.2));
        let ratio = 80.0 * 30f64.to_radians().cos() / (100.0 * 33f64.to_radians().cos());
        let so = o.s_mn[0] + o.s_mn[1];
        assert!((so - (3.0 * std::f64::consts::PI - 0.2 * ratio / th.alpha_n.cos())).abs() < 1e-12);
    }
}
