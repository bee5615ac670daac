//! The seam between a gear type and the LTCA: where the contact can be at a
//! roll angle, as candidate lines ([`TcaPosition`]) with the bodies'
//! frames.
//!
//! * a **line-contact pair** (spur, helical) hands over the line TCA
//!   ([`Tca`]): one sampled line per tooth pair in mesh, and tip-corner
//!   lines beyond the kinematic path out to a separation (the corner
//!   extension, which the LTCA raises when the loaded approach nears it);
//! * a **point-contact pair** (bevel, hypoid) hands over its point TCA
//!   ([`crate::tca::point_candidates::PointCandidates`]): the major axis of
//!   each tooth pair's contact ellipse, and edge lines where an edge is in
//!   contact.
//!
//! The LTCA ([`crate::ltca::cycle`]) sees only this trait; a new gear type
//! joins it by implementing it.

use crate::error::FlankError;
use crate::geometry::frame::Frame;
use crate::tca::{Tca, TcaPosition};

/// The candidates of one roll angle.
#[derive(Clone, Debug)]
pub struct CandidatePosition {
    /// The candidate lines and the unloaded TE.
    pub position: TcaPosition,
    /// Frames (own → global) of pinion and gear at the position's roll.
    pub frames: [Frame; 2],
    /// What the candidate set left out or took whole, for the position's
    /// warnings.
    pub notes: Vec<String>,
}

/// Where the contact of a pair can be (module docs).
pub trait ContactCandidates: Send + Sync {
    /// The candidates at `roll_deg` (pinion roll, deg); `None` where no
    /// tooth pair of the modelled sector is in contact (a gap of the
    /// cycle: the pair cannot carry the torque there).
    fn candidates(&self, roll_deg: f64) -> Result<Option<CandidatePosition>, FlankError>;

    /// The separation (mm) out to which points beyond the kinematic path
    /// are candidates, when the set has such a bound for the LTCA to check
    /// against the loaded approach (`None`: no bound).
    fn corner_extension_mm(&self) -> Option<f64> {
        None
    }

    /// The same candidates with the corner extension raised to `mm`.
    fn with_corner_extension(&self, mm: f64) -> Result<Box<dyn ContactCandidates>, FlankError> {
        Err(FlankError::Model(format!(
            "candidates: no corner extension to raise (to {mm} mm)"
        )))
    }
}

impl ContactCandidates for Tca {
    fn candidates(&self, roll_deg: f64) -> Result<Option<CandidatePosition>, FlankError> {
        let roll = roll_deg.to_radians();
        Ok(Some(CandidatePosition {
            position: self.position(roll)?,
            frames: self.frames(roll),
            notes: Vec::new(),
        }))
    }

    fn corner_extension_mm(&self) -> Option<f64> {
        Some(self.settings().extension_mm)
    }

    fn with_corner_extension(&self, mm: f64) -> Result<Box<dyn ContactCandidates>, FlankError> {
        let mut s = self.settings().clone();
        s.extension_mm = mm;
        Ok(Box::new(self.with_settings(s)?))
    }
}
