//! What every `summary.json` (and `compare.json`) of flank shares: the
//! version of their layout and the cycle figures computed the same way in
//! every analysis.

/// Version of the layout of the `summary.json` of `flank tca`, `flank
/// compliance`, `flank ltca` and `flank run`, and of `compare.json`: raised when a key changes its
/// meaning or goes, so that scripts can tell; a key added leaves it.
pub const SCHEMA_VERSION: u32 = 2;

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
