//! Tooth geometry: what a gear is (specs, in internal units), the exact
//! surfaces of its flanks, and the gear-pair interface every analysis uses
//! ([`gear_pair`]: tooth surfaces, gear bodies, the pair's assembly,
//! kinematics and misalignment; [`cylindrical`]: spur and helical gears
//! behind it).
//!
//! Internal units: mm and rad. Scene files convert at their boundary
//! (`crate::scene`); everything here is already converted.

pub mod bevel;
pub mod contact_curvature;
pub mod cylindrical;
pub mod deviation;
pub mod flank;
pub mod frame;
pub mod gear_pair;
pub mod involute;
pub mod iso6336;
pub mod iso6336_3;
pub mod measured;
pub mod measurement_grid;
pub mod micro;
pub mod pair;
pub mod rack;
pub mod rotated;
pub mod surface;
pub mod tangency;
pub mod vec3;

/// Hand of a helical gear (seen along the axis, as ISO 21771 defines it).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Hand {
    Left,
    Right,
}

impl Hand {
    /// The other hand: the mate of a crossed-axis or bevel pair.
    pub fn opposite(self) -> Self {
        match self {
            Hand::Left => Hand::Right,
            Hand::Right => Hand::Left,
        }
    }
}

/// Basic rack profile in module units (ISO 53: h_aP* = 1, h_fP* = 1.25, ρ_fP* = 0.38).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct RackProfile {
    /// Addendum of the generating rack, h_fP*: it cuts the gear's dedendum (×m_n).
    pub addendum: f64,
    /// Dedendum of the generating rack, h_aP*: it shapes the gear's addendum (×m_n).
    pub dedendum: f64,
    /// Tip radius of the generating rack ρ_fP* (×m_n): the root fillet's origin.
    pub tip_radius: f64,
}

impl Default for RackProfile {
    fn default() -> Self {
        RackProfile {
            addendum: 1.25,
            dedendum: 1.0,
            tip_radius: 0.38,
        }
    }
}

/// One cylindrical involute gear, internal units (mm, rad).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct GearSpec {
    pub teeth: u32,
    /// Normal module m_n (mm).
    pub normal_module: f64,
    /// Normal pressure angle α_n (rad).
    pub normal_pressure_angle: f64,
    /// Helix angle β at the reference circle (rad); 0 for spur gears.
    pub helix_angle: f64,
    pub hand: Hand,
    /// Face width b (mm).
    pub face_width: f64,
    /// Profile-shift coefficient x.
    pub profile_shift: f64,
    pub rack: RackProfile,
    /// Tip diameter d_a (mm) if given; otherwise from the rack and the shift.
    pub tip_diameter: Option<f64>,
    /// Bore diameter (mm).
    pub bore_diameter: f64,
}

/// An external gear pair.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct PairSpec {
    pub pinion: GearSpec,
    pub gear: GearSpec,
    /// Centre distance a (mm).
    pub centre_distance: f64,
}
