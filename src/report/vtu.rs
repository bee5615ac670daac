//! VTU writer
