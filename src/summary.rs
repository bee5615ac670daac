//! What every `summary.json` (and `compare.json`) of flank shares: the
//! version of their layout and the cycle figures computed the same way in
//! every analysis.

/// Version of the layout of the `summary.json` of `flank tca`, `flank
/// compliance`, `flank ltca` and `flank run`, and of `compare.json`: raised when a key changes its
/// meaning or goes, so that scripts can tell; a key added leaves it.
pub const SCHEMA_VERSION: u32 = 2;

/// The keys every `summary.json` and `compare.json` opens with: the
/// layout's version, the scene file and the pair kind. Each analysis's
/// result flattens it (`#[serde(flatten)]`), so the keys stand at the top
/// level of the file.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct Header {
    /// [`SCHEMA_VERSION`].
    pub schema_version: u32,
    /// The scene file, as given.
    pub scene: String,
    /// `spur`, `helical`, `spiral_bevel` or `hypoid`.
    pub pair_kind: &'static str,
}

impl Header {
    /// The header of a result of the scene file `scene` of kind `pair_kind`.
    pub fn new(scene: &std::path::Path, pair_kind: &'static str) -> Self {
        Header {
            schema_version: SCHEMA_VERSION,
            scene: scene.display().to_string(),
            pair_kind,
        }
    }
}

/// A figure of a summary, or why it was not measured (a sentence, never
/// a NaN): serialized as the figure's object or as
/// `{"not_measured": "…"}`.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
#[serde(untagged)]
pub enum Measured<T> {
    Figures(T),
    NotMeasured { not_measured: String },
}

impl<T> Measured<T> {
    /// The figure of `Ok`, the reason of `Err`.
    pub fn from_result(r: Result<T, String>) -> Self {
        match r {
            Ok(t) => Measured::Figures(t),
            Err(e) => Measured::NotMeasured { not_measured: e },
        }
    }

    /// The figure, if measured.
    pub fn figures(&self) -> Option<&T> {
        match self {
            Measured::Figures(t) => Some(t),
            Measured::NotMeasured { .. } => None,
        }
    }
}

/// max − min of `values` (−∞ for none): the peak-to-peak of a TE series.
pub fn peak_to_peak(values: impl Iterator<Item = f64> + Clone) -> f64 {
    values.clone().fold(f64::NEG_INFINITY, f64::max) - values.fold(f64::INFINITY, f64::min)
}

#[cfg(test)]
mod tests {
    #[test]
    fn peak_to_peak_of_a_series() {
        assert_eq!(super::peak_to_peak([3.0, -1.5, 2.0].into_iter()), 4.5);
    }
}
