//! Output: VTU, CSV and JSON writers, the plots shared by the analyses.
pub mod cycle_plot;
pub mod fe_pattern;
pub mod figure;
pub mod line_tca_plot;
pub mod lubrication;
pub mod solution;
pub mod tca_plot;
pub mod vh_plot;
pub mod vtu;
