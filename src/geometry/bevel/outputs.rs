//! Remaining dimensions and the output map.
//!
//! * Clause 7.6, inner and outer spiral angles of a face-milled (circular
//!   arc, radius r_c0) tooth trace: at cone distance R,
//!   sin β(R) = (2 R_m r_c0 sin β_m − R_m² + R²) / (2 R r_c0)
//!   (the cutter centre's distance from the crown-gear centre is the same
//!   for every point of the trace). Face hobbing: not given here.
//! * Clause 7.9: d_e2 = 2 R_e2 sin δ2, d_i2 = 2 (R_e2 − b2) sin δ2;
//!   outer addenda h_ae = h_am + (R_e − R_m) tan θ_a; outside diameters
//!   d_ae = d_e + 2 h_ae cos δ, d_e1 = 2 R_e1 sin δ1.
//! * Pinion outer cone distance: R_e1 = R_m1 + (R_e2 − R_m2) / cos ζ_mp
//!   (the wheel's heel line, perpendicular to its generator in the pitch
//!   plane, meets the pinion generator there). This is this module's
//!   choice, not the standard's pinion face width of clause 7.5 (which
//!   widens the pinion of a hypoid pair); for method 0 both are R_e2.
//!
//! [`BlankDesign::outputs`] gives lengths in mm and angles in degrees with
//! the key names of `../shared/reference/iso23509_annexF.json`, and leaves
//! out what the design's method does not define.

use serde_json::{Map, Value};

use super::pitch_cone::PitchCones;
use super::BlankDesign;
use crate::error::{FlankError, Result};

/// R_e1 (see the module docs).
pub fn pinion_outer_cone_distance(c: &PitchCones) -> f64 {
    c.rm1 + (c.re2 - c.rm2) / c.zeta_mp.cos()
}

/// Spiral angle of a circular-arc tooth trace at cone distance `r`.
pub fn circular_spiral_angle(rm: f64, beta_m: f64, rc0: f64, r: f64) -> Result<f64> {
    let s = (2.0 * rm * rc0 * beta_m.sin() - rm * rm + r * r) / (2.0 * r * rc0);
    if s.abs() <= 1.0 {
        Ok(s.asin())
    } else {
        Err(FlankError::Model(format!(
            "blank input `rc0_mm`: the cutter radius {rc0} mm cannot cut the face width (no spiral angle at R = {r:.3} mm)"
        )))
    }
}

impl BlankDesign {
    /// Outer pitch diameters (d_e1, d_e2).
    pub fn outer_pitch_diameters(&self) -> (f64, f64) {
        let c = &self.cones;
        (
            2.0 * self.re1 * c.delta1.sin(),
            2.0 * c.re2 * c.delta2.sin(),
        )
    }

    /// Outside diameters (d_ae1, d_ae2).
    pub fn outside_diameters(&self) -> (f64, f64) {
        let (c, d) = (&self.cones, &self.depth);
        let (de1, de2) = self.outer_pitch_diameters();
        let hae1 = d.ham1 + (self.re1 - c.rm1) * d.theta_a1.tan();
        let hae2 = d.ham2 + (c.re2 - c.rm2) * d.theta_a2.tan();
        (
            de1 + 2.0 * hae1 * c.delta1.cos(),
            de2 + 2.0 * hae2 * c.delta2.cos(),
        )
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
        let (c, d) = (&self.cones, &self.depth);
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
        put("Re2_mm", c.re2);
        put("dm1_mm", c.dm1);
        put("dm2_mm", c.dm2);
        put("m_mn_mm", c.m_mn);
        put("beta_m1_deg", deg(c.beta_m1));
        put("beta_m2_deg", deg(c.beta_m2));
        put("zeta_m_deg", deg(c.zeta_m));
        put("zeta_mp_deg", deg(c.zeta_mp));
        put("alpha_lim_deg", deg(c.alpha_lim));
        put(
            "di2_mm",
            2.0 * (c.re2 - (c.re2 - c.rm2) * 2.0) * c.delta2.sin(),
        );
        put("hmw_mm", d.hmw);
        put("ham1_mm", d.ham1);
        put("ham2_mm", d.ham2);
        put("hfm1_mm", d.hfm1);
        put("hfm2_mm", d.hfm2);
        put("c_mm", d.c);
        put("hm_mm", d.hm);
        put("delta_a1_deg", deg(c.delta1 + d.theta_a1));
        put("delta_f1_deg", deg(c.delta1 - d.theta_f1));
        put("delta_a2_deg", deg(c.delta2 + d.theta_a2));
        put("delta_f2_deg", deg(c.delta2 - d.theta_f2));
        if let (Some(e), Some(i)) = (self.beta_e2, self.beta_i2) {
            put("beta_e2_deg", deg(e));
            put("beta_i2_deg", deg(i));
        }
        if let Some(h) = &self.hobbing {
            put("nu_deg", deg(h.nu));
            put("lambda_deg", deg(h.lambda));
            put("rho_b_mm", h.rho_b);
        }
        let (dae1, dae2) = self.outside_diameters();
        put("dae1_mm", dae1);
        put("dae2_mm", dae2);
        put("smn1_mm", self.smn1);
        put("smn2_mm", self.smn2);
        m
    }
}
