//! Output: VTU, CSV and JSON writers.
pub mod figure;
pub mod solution;
pub mod vtu;
