//! When a tooth pair carries load: the threshold that FE contact
//! ([`crate::mesh_cycle`]) and the LTCA ([`crate::ltca`]) share, so that
//! their contact ratios from load sharing (the roll-angle span in which the
//! middle pair is loaded, per angular pitch) are measured the same way.

/// Fraction of the nominal single-pair force T / r (r the pair's
/// [`crate::geometry::gear_pair::GearPair::nominal_moment_arm`], r_b1 cos β_b
/// for a cylindrical pair) above which a tooth pair counts as carrying load
/// (contact ratio, single contact).
pub const LOADED_FRACTION: f64 = 1e-3;
