//! Output: VTU, CSV and JSON writers.
pub mod vtu;
