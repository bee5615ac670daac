//! Remaining dimensions and the output map.
//!
//! * Clause 7.7 (formulae (195)–(200)): outer and inner addenda and
//!   dedenda, h_ae = h_am + b_e tan θ_a, h_fe = h_fm + b_e tan θ_f,
//!   h_ai = h_am − b_i tan θ_a, h_fi = h_fm − b_i tan θ_f.
//! * Clause 7.9 (formulae (216)–(225)): R_e1 = R_m1 + b_e1, R_i1 = R_m1 −
//!   b_i1, d_e = 2 R_e sin δ, d_i = 2 R_i sin δ, outside diameters d_ae =
//!   d_e + 2 h_ae cos δ, root diameters d_fe = d_e − 2 h_fe cos δ (and at the
//!   inner end), crossing point to crown t_xo = t_zm + b_e cos δ − h_ae sin δ
//!   and to front crown t_xi = t_zm − b_i cos δ − h_ai sin δ.
//!
//! [`BlankDesign::outputs`] gives lengths in mm and angles in degrees with
//! the key names of `../shared/reference/iso23509_annexF.json` (and, for
//! the quantities those samples do not print, the standard's symbols in
//! the same style), leaving out what the design's method does not define.

use serde_json::{Map, Value};

use super::BlankDesign;
use crate::error::{FlankError, Result};

/// Clause 7.7 and 7.9 dimensions of one member (mm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EndDimensions {
    pub hae: f64,
    pub hfe: f64,
    pub hai: f64,
    pub hfi: f64,
    pub re: f64,
    pub ri: f64,
    pub de: f64,
    pub di: f64,
    pub dae: f64,
    pub dfe: f64,
    pub dai: f64,
    pub dfi: f64,
    pub txo: f64,
    pub txi: f64,
}

impl BlankDesign {
    /// Clause 7.7 and 7.9 for member `i` (0 pinion, 1 wheel).
    pub fn end_dimensions(&self, i: usize) -> EndDimensions {
        let (c, d, w, f) = (&self.cones, &self.depth, &self.widths, &self.faces);
        let (rm, delta, be, bi, ham, hfm, ta, tf, tzm) = if i == 0 {
            let t = (c.rm1, c.delta1, w.be1, w.bi1, d.ham1, d.hfm1);
            (t.0, t.1, t.2, t.3, t.4, t.5, f.theta_a1, f.theta_f1, f.tzm1)
        } else {
            let t = (c.rm2, c.delta2, w.be2, w.bi2, d.ham2, d.hfm2);
            (t.0, t.1, t.2, t.3, t.4, t.5, f.theta_a2, f.theta_f2, f.tzm2)
        };
        let hae = ham + be * ta.tan();
        let hfe = hfm + be * tf.tan();
        let hai = ham - bi * ta.tan();
        let hfi = hfm - bi * tf.tan();
        let (re, ri) = (rm + be, rm - bi);
        let (de, di) = (2.0 * re * delta.sin(), 2.0 * ri * delta.sin());
        let (s, k) = (delta.sin(), delta.cos());
        EndDimensions {
            hae,
            hfe,
            hai,
            hfi,
            re,
            ri,
            de,
            di,
            dae: de + 2.0 * hae * k,
            dfe: de - 2.0 * hfe * k,
            dai: di + 2.0 * hai * k,
            dfi: di - 2.0 * hfi * k,
            txo: tzm + be * k - hae * s,
            txi: tzm - bi * k - hai * s,
        }
    }

    /// Outside diameters (d_ae1, d_ae2).
    pub fn outside_diameters(&self) -> (f64, f64) {
        (self.end_dimensions(0).dae, self.end_dimensions(1).dae)
    }

    pub(super) fn check_finite(&self) -> Result<()> {
        for (k, v) in self.outputs() {
            if !v.as_f64().is_some_and(f64::is_finite) {
                return Err(FlankError::Model(format!(
                    "blank design: output `{k}` is not finite ({v})"
                )));
            }
        }
        Ok(())
    }

    /// The outputs with the Annex F key names (mm, degrees).
    pub fn outputs(&self) -> Map<String, Value> {
        let (c, d, f, w) = (&self.cones, &self.depth, &self.faces, &self.widths);
        let (t, s) = (&self.thickness, &self.spiral);
        let mut m = Map::new();
        let mut put = |k: &str, v: f64| {
            // Non-finite values become null (serde_json's choice) and are
            // reported by `check_finite`.
            m.insert(k.to_string(), Value::from(v));
        };
        let deg = f64::to_degrees;
        put("u", c.u);
        put("delta1_deg", deg(c.delta1));
        put("delta2_deg", deg(c.delta2));
        if self.method == 0 {
            put("Rm_mm", c.rm2);
        }
        put("Rm1_mm", c.rm1);
        put("Rm2_mm", c.rm2);
        put("c_be2", c.c_be2);
        put("dm1_mm", c.dm1);
        put("dm2_mm", c.dm2);
        put("beta_m1_deg", deg(c.beta_m1));
        put("beta_m2_deg", deg(c.beta_m2));
        put("zeta_m_deg", deg(c.zeta_m));
        put("zeta_mp_deg", deg(c.zeta_mp));
        put("ap_mm", c.ap);
        put("m_mn_mm", c.m_mn);
        put("alpha_lim_deg", deg(c.alpha_lim));
        put("alpha_nD_deg", deg(self.alpha_n_drive));
        put("alpha_nC_deg", deg(self.alpha_n_coast));
        put("alpha_eD_deg", deg(self.alpha_n_drive - c.alpha_lim));
        put("alpha_eC_deg", deg(self.alpha_n_coast + c.alpha_lim));
        let (e1, e2) = (self.end_dimensions(0), self.end_dimensions(1));
        put("Re_mm", e2.re);
        put("Re1_mm", e1.re);
        put("Re2_mm", e2.re);
        put("Ri1_mm", e1.ri);
        put("Ri2_mm", e2.ri);
        put("de1_mm", e1.de);
        put("de2_mm", e2.de);
        put("di1_mm", e1.di);
        put("di2_mm", e2.di);
        put("met2_mm", e2.de / self.z2);
        put("b1_mm", w.b1);
        put("be1_mm", w.be1);
        put("bi1_mm", w.bi1);
        put("be2_mm", w.be2);
        put("bi2_mm", w.bi2);
        put("bp1_mm", w.bp1);
        put("tzm1_mm", f.tzm1);
        put("tzm2_mm", f.tzm2);
        put("tz1_mm", f.tz1);
        put("tz2_mm", f.tz2);
        put("hmw_mm", d.hmw);
        put("ham1_mm", d.ham1);
        put("ham2_mm", d.ham2);
        put("hfm1_mm", d.hfm1);
        put("hfm2_mm", d.hfm2);
        put("c_mm", d.c);
        put("hm_mm", d.hm);
        put("x_hm1", d.x_hm1);
        put("theta_a1_deg", deg(f.theta_a1));
        put("theta_f1_deg", deg(f.theta_f1));
        put("theta_a2_deg", deg(f.theta_a2));
        put("theta_f2_deg", deg(f.theta_f2));
        put("delta_a1_deg", deg(c.delta1 + f.theta_a1));
        put("delta_f1_deg", deg(c.delta1 - f.theta_f1));
        put("delta_a2_deg", deg(c.delta2 + f.theta_a2));
        put("delta_f2_deg", deg(c.delta2 - f.theta_f2));
        put("zeta_R_deg", deg(f.zeta_r));
        put("zeta_o_deg", deg(f.zeta_o));
        put("beta_e1_deg", deg(s.beta_e1));
        put("beta_i1_deg", deg(s.beta_i1));
        put("beta_e2_deg", deg(s.beta_e2));
        put("beta_i2_deg", deg(s.beta_i2));
        if let Some(h) = &self.hobbing {
            put("nu_deg", deg(h.nu));
            put("lambda_deg", deg(h.lambda));
            put("rho_P0_mm", h.rho_p0);
            put("rho_b_mm", h.rho_b);
        }
        for (i, e) in [(1, &e1), (2, &e2)] {
            put(&format!("hae{i}_mm"), e.hae);
            put(&format!("hfe{i}_mm"), e.hfe);
            put(&format!("he{i}_mm"), e.hae + e.hfe);
            put(&format!("hai{i}_mm"), e.hai);
            put(&format!("hfi{i}_mm"), e.hfi);
            put(&format!("hi{i}_mm"), e.hai + e.hfi);
            put(&format!("dae{i}_mm"), e.dae);
            put(&format!("dfe{i}_mm"), e.dfe);
            put(&format!("dai{i}_mm"), e.dai);
            put(&format!("dfi{i}_mm"), e.dfi);
            put(&format!("txo{i}_mm"), e.txo);
            put(&format!("txi{i}_mm"), e.txi);
        }
        put("alpha_n_deg", deg(t.alpha_n));
        for i in 0..2 {
            let n = i + 1;
            put(&format!("xsm{n}"), t.x_sm[i]);
            put(&format!("smn{n}_mm"), t.s_mn[i]);
            put(&format!("smt{n}_mm"), t.s_mt[i]);
            put(&format!("dmn{n}_mm"), t.d_mn[i]);
            put(&format!("smnc{n}_mm"), t.s_mnc[i]);
            put(&format!("hamc{n}_mm"), t.h_amc[i]);
        }
        m
    }
}
