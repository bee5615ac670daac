//! Output: VTU, CSV and JSON writers.
pub mod solution;
pub mod vtu;
