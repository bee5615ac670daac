//! The input set of the blank design (ISO 23509:2016 clause 6.1, "Initial
//! data for pitch cone parameters", and clause 7.1, "Initial data for tooth
//! profile parameters"), read from a JSON object whose key names are those of
//! the Annex F samples in `../shared/reference/iso23509_annexF.json`.
//!
//! Lengths are mm and angles degrees in the file (the key says so); they are
//! converted to mm and rad here, nowhere else. Unknown keys are refused by
//! serde (`deny_unknown_fields`, whose message names the key); every value is
//! range-checked by [`BlankInputs::validate`], whose errors name the key.

use serde::Deserialize;

use crate::error::{FlankError, Result};

/// One blank-design input set, exactly as in the reference file's `inputs`.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct BlankInputs {
    /// Calculation method of ISO 23509 clause 6: 0 (bevel, no offset),
    /// 1 (hypoid, Gleason), 2 (hypoid, Oerlikon face hobbing), 3 (hypoid,
    /// Klingelnberg).
    pub method: u8,
    /// Shaft angle Σ.
    #[serde(rename = "Sigma_deg")]
    pub sigma_deg: f64,
    /// Hypoid offset a (0 for method 0).
    pub a_mm: f64,
    /// Number of teeth of the pinion.
    pub z1: u32,
    /// Number of teeth of the wheel.
    pub z2: u32,
    /// Outer pitch diameter of the wheel d_e2 (one of `de2_mm`, `dm2_mm`).
    #[serde(default)]
    pub de2_mm: Option<f64>,
    /// Mean pitch diameter of the wheel d_m2 (one of `de2_mm`, `dm2_mm`).
    #[serde(default)]
    pub dm2_mm: Option<f64>,
    /// Face width of the wheel b_2.
    pub b2_mm: f64,
    /// Mean spiral angle of the wheel β_m2 (methods 0, 2, 3; method 1
    /// computes it).
    #[serde(default)]
    pub beta_m2_deg: Option<f64>,
    /// Desired mean spiral angle of the pinion β_Δ1 (method 1 only).
    #[serde(default)]
    pub beta_m1_desired_deg: Option<f64>,
    /// Cutter radius r_c0.
    pub rc0_mm: f64,
    /// Number of blade groups of a face-hobbing cutter z_0 (absent: face
    /// milling, circular-arc tooth trace).
    #[serde(default)]
    pub z0: Option<u32>,
    /// Tooth-profile data type: "I" (ISO factors) or "II" (Gleason factors).
    pub data_type: String,
    /// Nominal design pressure angle, drive flank α_dD.
    #[serde(rename = "alpha_dD_deg")]
    pub alpha_d_drive_deg: f64,
    /// Nominal design pressure angle, coast flank α_dC.
    #[serde(rename = "alpha_dC_deg")]
    pub alpha_d_coast_deg: f64,
    /// Influence factor of the limit pressure angle f_αlim.
    pub f_alim: f64,
    /// Data type I: addendum factor k_hap of the basic rack.
    #[serde(default)]
    pub k_hap: Option<f64>,
    /// Data type I: dedendum factor k_hfp of the basic rack.
    #[serde(default)]
    pub k_hfp: Option<f64>,
    /// Data type I: profile shift coefficient x_hm1.
    #[serde(default)]
    pub x_hm1: Option<f64>,
    /// Data type I: thickness modification coefficient x_smn.
    #[serde(default)]
    pub x_smn: Option<f64>,
    /// Data type II: mean addendum factor of the wheel c_ham.
    #[serde(default)]
    pub c_ham: Option<f64>,
    /// Data type II: depth factor k_d.
    #[serde(default)]
    pub k_d: Option<f64>,
    /// Data type II: clearance factor k_c.
    #[serde(default)]
    pub k_c: Option<f64>,
    /// Data type II: thickness factor k_t.
    #[serde(default)]
    pub k_t: Option<f64>,
    /// Backlash, e.g. "outer normal jen 0.127" (absent: none).
    #[serde(default)]
    pub backlash: Option<String>,
    /// Tapered depth: addendum angle of the wheel θ_a2.
    #[serde(default)]
    pub theta_a2_deg: Option<f64>,
    /// Tapered depth: dedendum angle of the wheel θ_f2.
    #[serde(default)]
    pub theta_f2_deg: Option<f64>,
}

/// The tooth-profile factors of ISO 23509 clause 7.1 in their data-type-I
/// form (data type II converted), in units of m_mn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProfileFactors {
    pub k_hap: f64,
    pub k_hfp: f64,
    /// Set for data type I; data type II gives the wheel's mean addendum from
    /// c_ham instead (clause 7.3), see `tooth_depth`.
    pub x_hm1: Option<f64>,
    pub c_ham: Option<f64>,
    pub x_smn: f64,
}

/// Where the backlash is given and what it is (ISO 23509 clause 7.8).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Backlash {
    /// Normal backlash at the outer end, j_en.
    OuterNormal(f64),
    /// Transverse backlash of the wheel at the outer end, j_et2.
    OuterTransverse(f64),
    /// Normal backlash at the mean point, j_mn.
    MeanNormal(f64),
    /// Transverse backlash of the wheel at the mean point, j_mt2.
    MeanTransverse(f64),
}

fn err(key: &str, message: impl std::fmt::Display) -> FlankError {
    FlankError::Model(format!("blank input `{key}`: {message}"))
}

fn finite(key: &str, v: f64) -> Result<f64> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(err(key, format!("{v} is not a finite number")))
    }
}

fn in_range(key: &str, v: f64, lo: f64, hi: f64, what: &str) -> Result<f64> {
    let v = finite(key, v)?;
    if v > lo && v < hi {
        Ok(v)
    } else {
        Err(err(key, format!("{v} out of range ({what})")))
    }
}

fn need(key: &str, v: Option<f64>, why: &str) -> Result<f64> {
    v.ok_or_else(|| err(key, format!("missing ({why})")))
}

impl BlankInputs {
    /// Parses a JSON object; unknown keys and bad values are errors naming
    /// the key.
    pub fn from_json(text: &str) -> Result<Self> {
        let inputs: BlankInputs = serde_json::from_str(text)
            .map_err(|e| FlankError::Model(format!("blank inputs: {e}")))?;
        inputs.validate()?;
        Ok(inputs)
    }

    /// From a JSON value (e.g. one `inputs` object of the reference file).
    pub fn from_value(value: serde_json::Value) -> Result<Self> {
        let inputs: BlankInputs = serde_json::from_value(value)
            .map_err(|e| FlankError::Model(format!("blank inputs: {e}")))?;
        inputs.validate()?;
        Ok(inputs)
    }

    /// Checks every value's range and the keys each method and data type
    /// needs; the error names the offending key.
    pub fn validate(&self) -> Result<()> {
        if self.method > 3 {
            return Err(err(
                "method",
                format!("{} is not 0, 1, 2 or 3", self.method),
            ));
        }
        in_range("Sigma_deg", self.sigma_deg, 0.0, 180.0, "0 < Σ < 180°")?;
        let a = finite("a_mm", self.a_mm)?;
        if self.method == 0 && a != 0.0 {
            return Err(err("a_mm", "method 0 has no offset: a must be 0"));
        }
        if self.z1 == 0 {
            return Err(err("z1", "must be positive"));
        }
        if self.z2 < self.z1 {
            return Err(err(
                "z2",
                "the wheel must not have fewer teeth than the pinion",
            ));
        }
        match (self.de2_mm, self.dm2_mm) {
            (Some(d), None) => {
                in_range("de2_mm", d, 0.0, f64::INFINITY, "positive")?;
            }
            (None, Some(d)) => {
                in_range("dm2_mm", d, 0.0, f64::INFINITY, "positive")?;
            }
            (Some(_), Some(_)) => return Err(err("dm2_mm", "give de2_mm or dm2_mm, not both")),
            (None, None) => return Err(err("de2_mm", "missing (or give dm2_mm)")),
        }
        // The diameter each method of clause 6 starts from (a zero offset
        // is method 0, which takes either).
        if a != 0.0 {
            match self.method {
                1 if self.de2_mm.is_none() => {
                    return Err(err(
                        "de2_mm",
                        format!(
                            "missing (method {} starts from the outer pitch diameter)",
                            self.method
                        ),
                    ))
                }
                2 if self.dm2_mm.is_none() => {
                    return Err(err(
                        "dm2_mm",
                        "missing (method 2 starts from the mean pitch diameter)",
                    ))
                }
                _ => {}
            }
        }
        in_range("b2_mm", self.b2_mm, 0.0, f64::INFINITY, "positive")?;
        in_range("rc0_mm", self.rc0_mm, 0.0, f64::INFINITY, "positive")?;
        match (self.method, self.beta_m1_desired_deg) {
            (1, None) => return Err(err("beta_m1_desired_deg", "missing (method 1 needs it)")),
            (1, Some(b)) => {
                in_range("beta_m1_desired_deg", b, -90.0, 90.0, "|β| < 90°")?;
            }
            (_, Some(_)) => return Err(err("beta_m1_desired_deg", "only method 1 takes it")),
            _ => {}
        }
        match (self.method, self.beta_m2_deg) {
            (1, Some(_)) => return Err(err(
                "beta_m2_deg",
                "method 1 computes the wheel's spiral angle from beta_m1_desired_deg; remove it",
            )),
            (1, None) => {}
            (m, None) => return Err(err("beta_m2_deg", format!("missing (method {m} needs it)"))),
            (_, Some(b)) => {
                in_range("beta_m2_deg", b, -90.0, 90.0, "|β| < 90°")?;
            }
        }
        if self.method == 2 && self.z0.is_none() {
            return Err(err("z0", "missing (method 2 is face hobbing)"));
        }
        if self.z0 == Some(0) {
            return Err(err("z0", "must be positive"));
        }
        in_range(
            "alpha_dD_deg",
            self.alpha_d_drive_deg,
            0.0,
            45.0,
            "0 < α < 45°",
        )?;
        in_range(
            "alpha_dC_deg",
            self.alpha_d_coast_deg,
            0.0,
            45.0,
            "0 < α < 45°",
        )?;
        in_range("f_alim", self.f_alim, -1e-12, 1.0 + 1e-12, "0 ≤ f_αlim ≤ 1")?;
        self.profile_factors()?;
        self.backlash()?;
        if self.tapered() {
            let ta = need("theta_a2_deg", self.theta_a2_deg, "tapered depth")?;
            let tf = need("theta_f2_deg", self.theta_f2_deg, "tapered depth")?;
            in_range("theta_a2_deg", ta, -1e-12, 45.0, "0 ≤ θ < 45°")?;
            in_range("theta_f2_deg", tf, -1e-12, 45.0, "0 ≤ θ < 45°")?;
        } else {
            if self.theta_a2_deg.is_some() {
                return Err(err("theta_a2_deg", "uniform depth (methods 2, 3) has none"));
            }
            if self.theta_f2_deg.is_some() {
                return Err(err("theta_f2_deg", "uniform depth (methods 2, 3) has none"));
            }
        }
        Ok(())
    }

    /// Tapered depth (methods 0 and 1) or uniform depth (methods 2 and 3).
    pub fn tapered(&self) -> bool {
        self.method <= 1
    }

    pub fn profile_factors(&self) -> Result<ProfileFactors> {
        let type_i = ["k_hap", "k_hfp", "x_hm1", "x_smn"];
        let type_ii = ["c_ham", "k_d", "k_c", "k_t"];
        let given = |k: &str| match k {
            "k_hap" => self.k_hap.is_some(),
            "k_hfp" => self.k_hfp.is_some(),
            "x_hm1" => self.x_hm1.is_some(),
            "x_smn" => self.x_smn.is_some(),
            "c_ham" => self.c_ham.is_some(),
            "k_d" => self.k_d.is_some(),
            "k_c" => self.k_c.is_some(),
            _ => self.k_t.is_some(),
        };
        match self.data_type.as_str() {
            "I" => {
                if let Some(k) = type_ii.iter().find(|k| given(k)) {
                    return Err(err(k, "is a data type II factor (data_type is \"I\")"));
                }
                let k_hap = need("k_hap", self.k_hap, "data type I")?;
                let k_hfp = need("k_hfp", self.k_hfp, "data type I")?;
                let x_hm1 = need("x_hm1", self.x_hm1, "data type I")?;
                let x_smn = need("x_smn", self.x_smn, "data type I")?;
                in_range("k_hap", k_hap, 0.0, 3.0, "0 < k_hap < 3")?;
                in_range("k_hfp", k_hfp, 0.0, 3.0, "0 < k_hfp < 3")?;
                in_range("x_hm1", x_hm1, -1.0, 1.0, "|x_hm1| < 1")?;
                in_range("x_smn", x_smn, -0.5, 0.5, "|x_smn| < 0.5")?;
                Ok(ProfileFactors {
                    k_hap,
                    k_hfp,
                    x_hm1: Some(x_hm1),
                    c_ham: None,
                    x_smn,
                })
            }
            "II" => {
                if let Some(k) = type_i.iter().find(|k| given(k)) {
                    return Err(err(k, "is a data type I factor (data_type is \"II\")"));
                }
                let c_ham = need("c_ham", self.c_ham, "data type II")?;
                let k_d = need("k_d", self.k_d, "data type II")?;
                let k_c = need("k_c", self.k_c, "data type II")?;
                let k_t = need("k_t", self.k_t, "data type II")?;
                in_range("c_ham", c_ham, 0.0, 1.0, "0 < c_ham < 1")?;
                in_range("k_d", k_d, 0.0, 6.0, "0 < k_d < 6")?;
                in_range("k_c", k_c, -1e-12, 1.0, "0 ≤ k_c < 1")?;
                in_range("k_t", k_t, -0.5, 0.5, "|k_t| < 0.5")?;
                // Clause 7.1: k_hap = k_d/2, k_hfp = k_d/2 + k_c k_d,
                // x_smn = k_t/2 (the thickness factor splits the
                // thickness change over both members).
                Ok(ProfileFactors {
                    k_hap: k_d / 2.0,
                    k_hfp: k_d / 2.0 + k_c * k_d,
                    x_hm1: None,
                    c_ham: Some(c_ham),
                    x_smn: k_t / 2.0,
                })
            }
            other => Err(err(
                "data_type",
                format!("{other:?} is not \"I\" or \"II\""),
            )),
        }
    }

    pub fn backlash(&self) -> Result<Backlash> {
        let Some(text) = self.backlash.as_deref() else {
            return Ok(Backlash::MeanNormal(0.0));
        };
        let words: Vec<&str> = text.split_whitespace().collect();
        let bad = || {
            err(
                "backlash",
                format!(
                    "{text:?}: expected \"outer normal jen <mm>\", \"outer transverse jet2 <mm>\", \
                     \"mean normal jmn <mm>\" or \"mean transverse jmt2 <mm>\""
                ),
            )
        };
        let [place, section, _, value] = words.as_slice() else {
            return Err(bad());
        };
        let j: f64 = value.parse().map_err(|_| bad())?;
        let j = in_range("backlash", j, -1e-12, f64::INFINITY, "≥ 0")?;
        match (*place, *section) {
            ("outer", "normal") => Ok(Backlash::OuterNormal(j)),
            ("outer", "transverse") => Ok(Backlash::OuterTransverse(j)),
            ("mean", "normal") => Ok(Backlash::MeanNormal(j)),
            ("mean", "transverse") => Ok(Backlash::MeanTransverse(j)),
            _ => Err(bad()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const F2: &str = r#"{"method":0,"Sigma_deg":90,"a_mm":0,"z1":14,"z2":39,"de2_mm":176.893,
        "b2_mm":25.4,"beta_m2_deg":35.0,"rc0_mm":114.3,"data_type":"II","alpha_dD_deg":20,
        "alpha_dC_deg":20,"f_alim":0,"c_ham":0.24737,"k_d":2.0,"k_c":0.125,"k_t":0.0915,
        "backlash":"outer normal jen 0.127","theta_a2_deg":2.1342,"theta_f2_deg":6.4934}"#;

    fn with(key: &str, value: serde_json::Value) -> String {
        let mut v: serde_json::Value = serde_json::from_str(F2).unwrap();
        if value.is_null() {
            v.as_object_mut().unwrap().remove(key);
        } else {
            v[key] = value;
        }
        v.to_string()
    }

    fn error_of(text: &str) -> String {
        BlankInputs::from_json(text).unwrap_err().to_string()
    }

    #[test]
    fn the_f2_inputs_parse() {
        let i = BlankInputs::from_json(F2).unwrap();
        assert_eq!(i.backlash().unwrap(), Backlash::OuterNormal(0.127));
        let f = i.profile_factors().unwrap();
        assert_eq!((f.k_hap, f.k_hfp), (1.0, 1.25));
    }

    #[test]
    fn bad_inputs_name_the_key() {
        use serde_json::json;
        let cases = [
            (with("zz_mm", json!(1.0)), "zz_mm"),
            (with("Sigma_deg", json!(190.0)), "Sigma_deg"),
            (with("a_mm", json!(5.0)), "a_mm"),
            (with("z1", json!(0)), "z1"),
            (with("z2", json!(10)), "z2"),
            (with("de2_mm", json!(-1.0)), "de2_mm"),
            (with("de2_mm", serde_json::Value::Null), "de2_mm"),
            (with("dm2_mm", json!(150.0)), "dm2_mm"),
            (with("b2_mm", json!(0.0)), "b2_mm"),
            (with("beta_m2_deg", json!(95.0)), "beta_m2_deg"),
            (with("beta_m2_deg", serde_json::Value::Null), "beta_m2_deg"),
            (with("rc0_mm", json!(-3.0)), "rc0_mm"),
            (with("method", json!(4)), "method"),
            (with("data_type", json!("III")), "data_type"),
            (with("c_ham", serde_json::Value::Null), "c_ham"),
            (with("x_hm1", json!(0.3)), "x_hm1"),
            (with("k_c", json!(-0.2)), "k_c"),
            (with("f_alim", json!(2.0)), "f_alim"),
            (with("alpha_dD_deg", json!(50.0)), "alpha_dD_deg"),
            (with("backlash", json!("some 0.1")), "backlash"),
            (
                with("theta_f2_deg", serde_json::Value::Null),
                "theta_f2_deg",
            ),
            (
                with("beta_m1_desired_deg", json!(40.0)),
                "beta_m1_desired_deg",
            ),
            (with("z0", json!(0)), "z0"),
        ];
        for (text, key) in cases {
            let e = error_of(&text);
            assert!(e.contains(&format!("`{key}`")), "{key}: {e}");
        }
    }
}
