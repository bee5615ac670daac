//! One run of either method (LTCA or FE contact) over the positions of a
//! comparison, with its errors against the reference: the rows of
//! `flank compare`'s tables.

/// One run of either method over the positions.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct MethodRun {
    pub method: String,
    /// "K = 20" or "flank 0.25 mm".
    pub label: String,
    pub points_per_line: Option<usize>,
    pub flank_size_mm: Option<f64>,
    pub nodes: Option<usize>,
    /// Per position: normal force per pair (N), TE (µrad), p_max (MPa).
    pub pair_force_n: Vec<Vec<f64>>,
    /// Per position: tangential (friction) force per pair (N; zeros
    /// without friction): the LTCA's |Σ P_t| over the pair's points (each
    /// P_t along its point's tangent), FE contact's magnitude of the
    /// resultant over the pair's slave nodes.
    #[serde(default)]
    pub pair_tangential_n: Vec<Vec<f64>>,
    pub te_urad: Vec<f64>,
    pub pmax_mpa: Vec<f64>,
    pub cycle_s: f64,
    pub setup_s: f64,
    /// FE contact: the slave body per position (the one whose tip corner
    /// is in contact, else the pinion).
    #[serde(default)]
    pub slave: Vec<String>,
    #[serde(deserialize_with = "null_as_nan")]
    pub load_sharing_err: f64,
    #[serde(deserialize_with = "null_as_nan")]
    pub te_rel_err: f64,
    /// max relative p_max error: an LTCA run's against the contact-band
    /// reference when one is given ([`super::pmax_reference`]), else (and every
    /// FE run's) against the finest uniform FE run.
    #[serde(deserialize_with = "null_as_nan")]
    pub pmax_rel_err: f64,
    /// max relative p_max error against the finest uniform FE run over the
    /// flank-contact positions (its p_max does not resolve the Hertz width).
    #[serde(default = "nan", deserialize_with = "null_as_nan")]
    pub pmax_uniform_fe_rel_err: f64,
    /// max |P_t − P_t,ref| / Σ P_n,ref over positions and pairs (NaN
    /// without friction).
    #[serde(default = "nan", deserialize_with = "null_as_nan")]
    pub tangential_force_err: f64,
}

fn nan() -> f64 {
    f64::NAN
}

/// JSON has no NaN (serde_json writes null): read null back as NaN.
fn null_as_nan<'de, D: serde::Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    use serde::Deserialize;
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
}

/// Each pair's share of the total force (zeros when it is 0).
pub(crate) fn shares(f: &[f64]) -> Vec<f64> {
    let t: f64 = f.iter().sum();
    f.iter()
        .map(|&x| if t > 0.0 { x / t } else { 0.0 })
        .collect()
}
