//! The gear-pair interface: what every analysis (sector mesher, compliance
//! bodies, TCA, LTCA, FE mesh cycle, comparison) knows of a gear pair,
//! whatever its type.
//!
//! * a **gear body** ([`GearBody`]): tooth count, the tooth surfaces
//!   ([`ToothSurface`]) of both flanks of every tooth of the sector that is
//!   modelled, the blank (bore, root, face), the axis (own z);
//! * a **gear pair** ([`GearPair`], implemented by every pair kind): the
//!   assembly (shaft angle, offset,
//!   mounting distances: [`Assembly`]), the misalignment set
//!   ([`Misalignment`]: ΔE, ΔP, ΔG, ΔΣ of bevel/hypoid practice), the ratio
//!   and the kinematics (rigid placement of both bodies for a pinion roll
//!   angle, which teeth pair up, when a tooth pair is in mesh, where its
//!   kinematic contact lies);
//! * a **line-contact pair** ([`LineContactPair`]): a gear pair whose
//!   unloaded flanks touch along lines (spur and helical pairs): its path
//!   of contact, engagement and kinematic contact lines, which the line
//!   TCA samples. A bevel/hypoid pair touches at points; its candidates
//!   come from the point TCA (`tca::candidates` is the seam of both).
//!
//! Spur and helical gears (parallel axes, exact rack-generated involute
//! helicoids) implement both in [`crate::geometry::cylindrical`], bevel and
//! hypoid pairs [`GearPair`] in [`crate::geometry::bevel::pair`]; a test
//! pair of rolling cylinders implements both in `tca` tests.
//!
//! # Conventions shared by every implementation
//!
//! * **Own frames**: each body's surfaces and mesh are in its own frame,
//!   axis = own z. [`GearPair::frames`] places them (own → global).
//! * **Roll angle** θ: the pinion rotation in the drive direction (rad),
//!   0 when the middle tooth pair's kinematic contact is at its reference
//!   point (the pitch point of a cylindrical pair). The gear turns by
//!   [`GearPair::ratio`] θ.
//! * **Drive flanks**: a positive torque loads the right flanks
//!   ([`Flank::Right`]) of both bodies (`FLANK_R<k>` node sets).
//! * **Sector teeth** are numbered 1..=n; pinion tooth k meets gear tooth
//!   [`GearPair::mate`]`(k)`.
//! * **Kinematic contact lines** ([`KinematicLine`]): where the unloaded,
//!   unmodified surfaces touch (or, for tip-corner windows, where an edge
//!   may touch under load), as a line parameter ξ with a seed for the
//!   TCA's Newton solves ([`LineContactPair::line_seed`]).

use std::fmt::Debug;

use crate::geometry::frame::Frame;
pub use crate::geometry::rack::Flank;
use crate::geometry::surface::ToothSurface;
use crate::geometry::vec3::V3;

/// The blank of a gear body: what the mesher puts below the teeth.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Blank {
    /// Bore radius (mm): the hub surface that is clamped or coupled.
    pub bore_radius: f64,
    /// Root radius at the middle of the face (mm): the rim below the teeth.
    pub root_radius: f64,
    /// Tip radius at the middle of the face (mm).
    pub tip_radius: f64,
    /// Axial extent of the body in its own z (mm).
    pub axial_range: (f64, f64),
}

/// One gear of a pair, as a sector of teeth (module docs).
pub trait GearBody: Debug + Send + Sync {
    /// "pinion" or "gear".
    fn name(&self) -> &str;
    /// Teeth of the whole gear z.
    fn teeth(&self) -> u32;
    /// Teeth of the modelled sector (1..=n).
    fn sector_teeth(&self) -> usize;
    /// Angular pitch 2π/z (rad).
    fn angular_pitch(&self) -> f64;
    /// The flank `side` of sector tooth `tooth` (1-based), `None` outside
    /// the sector.
    fn flank(&self, side: Flank, tooth: usize) -> Option<&dyn ToothSurface>;
    /// Axis (point, unit direction) in the own frame: the own z axis.
    fn axis(&self) -> (V3, V3) {
        ([0.0; 3], [0.0, 0.0, 1.0])
    }
    fn blank(&self) -> Blank;
    /// The concrete type, for the parts of flank that need more than the
    /// surfaces (the structured cylindrical mesher needs the transverse
    /// section): `body.as_any().downcast_ref::<CylindricalGear>()`.
    fn as_any(&self) -> &dyn std::any::Any;
}

/// Relative position of the two axes (mm, rad).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Assembly {
    /// Shaft angle Σ (0 for parallel axes, π/2 for most hypoid sets).
    pub shaft_angle_rad: f64,
    /// Shortest distance between the axes: the offset E of a hypoid pair,
    /// the centre distance a of a parallel pair.
    pub offset_mm: f64,
    /// Axial position of each body's own origin from the foot of the common
    /// perpendicular on its axis (pinion, gear): the mounting distances of
    /// a bevel pair; for a parallel pair 0 and the gear's axial shift.
    pub mounting_distance_mm: [f64; 2],
}

/// The misalignment set of bevel/hypoid practice, and its parallel-axis
/// reading (mm, rad).
///
/// * ΔE `offset_error_mm`: change of the shortest distance between the
///   axes, > 0 apart, on either hand of a hypoid pair whichever side of
///   the gear axis the pinion axis lies on (a parallel pair: the
///   centre-distance error Δa);
/// * ΔP `pinion_axial_mm`, ΔG `gear_axial_mm`: axial displacements of the
///   pinion and the gear along their own axes (> 0 along own +z);
/// * ΔΣ `shaft_angle_error_rad`: change of the shaft angle, a tilt of the
///   gear axis in the plane of the axes (a parallel pair: f_Σδ / L, the
///   inclination error of ISO/TR 10064-3 over the bearing span L);
/// * `out_of_plane_tilt_rad`: a tilt of the gear axis normal to the plane
///   of the axes (a parallel pair: f_Σβ / L, the deviation error; zero in
///   the usual bevel set, where it is an offset change along the face; a
///   bevel pair: > 0 tips the gear's +z toward the pinion axis's side).
///
/// A bevel pair applies them relative to the side of the gear axis on
/// which the pinion axis lies (`geometry::bevel::assembly` module docs),
/// so a pair and its mirror image (both hands swapped) are misaligned as
/// mirror images.
///
/// For a parallel pair with working pressure angle α_wt these are the
/// plane-of-action tilts of [`crate::geometry::cylindrical`]:
/// γ_β = t cos α_wt + ΔΣ sin α_wt, γ_δ = −t sin α_wt + ΔΣ cos α_wt
/// (t the out-of-plane tilt), and Δa = ΔE.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct Misalignment {
    pub offset_error_mm: f64,
    pub pinion_axial_mm: f64,
    pub gear_axial_mm: f64,
    pub shaft_angle_error_rad: f64,
    pub out_of_plane_tilt_rad: f64,
}

/// What a kinematic contact line is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum LineKind {
    /// On the flanks, inside the kinematic path of contact and the face.
    Flank,
    /// The pinion's tip edge against the gear flank, after the end of the path.
    PinionTipCorner,
    /// The gear's tip edge against the pinion flank, before the start of the path.
    GearTipCorner,
}

/// A kinematic contact line of one tooth pair at one roll angle: a line
/// parameter ξ over `range`, sampled by [`LineContactPair::line_seed`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KinematicLine {
    pub pinion_tooth: usize,
    pub gear_tooth: usize,
    pub kind: LineKind,
    /// ξ interval. Flank lines: (start, end). Corner windows: the first end
    /// lies next to the end of the path of contact.
    pub range: (f64, f64),
    /// dξ per mm of line: the line's length is |Δξ| / `param_per_mm`.
    pub param_per_mm: f64,
    /// Corner windows only: `true` when the whole window is at the path end
    /// (a corner line parallel to it, as on spur gears); `false` when the
    /// edge's separation grows from `range.0` to `range.1` (helical gears:
    /// the TCA keeps the part where it stays below its limit).
    pub whole_window: bool,
    /// ξ span of the common face: the scale below which a line is empty.
    pub face_span: f64,
    /// The implementation's position of the line (a cylindrical pair: the
    /// distance along the line of action at ξ = 0).
    pub origin: f64,
}

/// Where the TCA starts its Newton solves for one point of a line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactSeed {
    /// Global point on the kinematic line.
    pub point: V3,
    /// Seed parameters (u, v) on the pinion and on the gear flank. On a
    /// corner line the edge body's v is the edge point's.
    pub pinion_uv: [f64; 2],
    pub gear_uv: [f64; 2],
    /// Whether the point (offset across the line) lies inside the path of
    /// contact and the common face.
    pub inside: bool,
}

/// Where the two bodies of a pair are and how they turn together: what
/// every analysis of a pair needs, whatever its kind of contact (the
/// point-contact TCA of a bevel pair needs no more).
pub trait GearPair: Debug + Send + Sync {
    fn pinion(&self) -> &dyn GearBody;
    fn gear(&self) -> &dyn GearBody;
    /// Body 0 (pinion) or 1 (gear).
    fn body(&self, b: usize) -> &dyn GearBody {
        if b == 0 {
            self.pinion()
        } else {
            self.gear()
        }
    }
    fn assembly(&self) -> Assembly;
    fn misalignment(&self) -> Misalignment;

    /// Speed ratio ω₂/ω₁ = z₁/z₂.
    fn ratio(&self) -> f64 {
        self.pinion().teeth() as f64 / self.gear().teeth() as f64
    }
    /// Teeth per sector n.
    fn sector_teeth(&self) -> usize {
        self.pinion().sector_teeth()
    }
    /// The middle pinion tooth k_m (1-based).
    fn middle(&self) -> usize {
        self.sector_teeth().div_ceil(2)
    }
    /// The gear tooth meeting pinion tooth `k`.
    fn mate(&self, k: usize) -> usize;
    /// Pinion roll angle by which pinion tooth k + 1 follows tooth k into
    /// mesh (rad, ± the angular pitch 2π/z₁).
    fn tooth_roll_step(&self) -> f64;

    /// Frames (own → global) of pinion and gear at `roll`, in the nominal
    /// (aligned) assembly.
    fn nominal_frames(&self, roll: f64) -> [Frame; 2];
    /// Frames at `roll` with the misalignment applied to the gear.
    fn frames(&self, roll: f64) -> [Frame; 2];
    /// Unit angular-velocity directions of pinion and gear, own frames, for
    /// a positive (drive) pinion rotation.
    fn rotation_axes(&self) -> [V3; 2];

    /// The pair's kinematic data for reports (JSON).
    fn describe(&self) -> serde_json::Value;
}

/// A gear pair with line-contact kinematics: the placement
/// ([`GearPair`]) and the kinematic contact lines, paths and arms the
/// LTCA and the FE mesh cycle sample (module docs).
pub trait LineContactPair: GearPair {
    /// Kinematic engagement of pinion tooth `k`: roll angles of the start
    /// and the end of its contact.
    fn engagement(&self, k: usize) -> (f64, f64);
    /// Whole engagement of pinion tooth `k` over the common face: the
    /// first and the last roll angle at which its contact line meets the
    /// face (transverse plus overlap, ε_α + ε_β pitches of a helical
    /// pair); [`Self::engagement`] where the two coincide (spur pairs).
    fn face_engagement(&self, k: usize) -> (f64, f64) {
        self.engagement(k)
    }
    /// Kinematic single-tooth contact of the middle pair (roll angles).
    fn single_contact(&self) -> (f64, f64);
    /// Kinematic contact ratio (path of contact / base pitch).
    fn kinematic_contact_ratio(&self) -> f64;
    /// Position of pinion tooth `k`'s kinematic contact at `roll`, measured
    /// along the path of contact from its start (mm; < 0 before the start,
    /// > [`Self::path_length`] after the end).
    fn path_position(&self, k: usize, roll: f64) -> f64;
    /// Length of the path of contact (mm).
    fn path_length(&self) -> f64;
    /// Path length of one pitch (the transverse base pitch of a
    /// cylindrical pair, mm).
    fn path_pitch(&self) -> f64;

    /// The normal approach of the flanks per unit pinion rotation on an
    /// ideal contact (mm): the nominal normal force of a single pair is
    /// torque / arm (r_b1 cos β_b for a cylindrical pair).
    fn nominal_moment_arm(&self) -> f64;
    /// Radius that turns a pinion rotation into a transmission error
    /// length (mm; the base radius r_b1: TE on the line of action).
    fn transmission_error_radius(&self) -> f64;

    /// The kinematic contact lines of all tooth pairs at `roll`; corner
    /// windows only when `corner_separation_mm` > 0 (the largest separation
    /// of a corner point the caller keeps).
    fn contact_lines(&self, roll: f64, corner_separation_mm: f64) -> Vec<KinematicLine>;
    /// The seed of the point at ξ of `line`, offset `across` mm across it
    /// (in the surface of action).
    fn line_seed(&self, line: &KinematicLine, xi: f64, across: f64) -> ContactSeed;
}

/// Offsets j from the middle pair (pinion tooth k_m + j) of every tooth
/// pair whose whole engagement ([`LineContactPair::face_engagement`]),
/// widened by `reach` (rad of roll) on each side, contains one of `rolls`
/// (rad): the pairs a sector must hold to model those positions, as the
/// smallest and the largest offset ((0, 0) when only the middle pair is
/// in mesh, or for no roll). Pair k_m + j engages `j` tooth roll steps
/// after the middle one ([`GearPair::tooth_roll_step`]).
pub fn pairs_in_mesh(pair: &dyn LineContactPair, rolls: &[f64], reach: f64) -> (i64, i64) {
    let (a, e) = pair.face_engagement(pair.middle());
    let step = pair.tooth_roll_step();
    let z = i64::from(pair.pinion().teeth());
    let (mut lo, mut hi) = (0, 0);
    for j in -z..=z {
        let (aj, ej) = (a + j as f64 * step, e + j as f64 * step);
        let (from, to) = (aj.min(ej) - reach, aj.max(ej) + reach);
        if rolls.iter().any(|&r| r >= from && r <= to) {
            lo = lo.min(j);
            hi = hi.max(j);
        }
    }
    (lo, hi)
}

/// The smallest sector (n teeth, middle tooth ⌈n/2⌉) that holds the tooth
/// pairs at offsets `lo ..= hi` from the middle one ([`pairs_in_mesh`]).
pub fn sector_teeth_holding(lo: i64, hi: i64) -> usize {
    let (lo, hi) = (lo.min(0), hi.max(0));
    // n = 2 max(−lo, hi) + 1 always holds them: the search is bounded
    let bound = (2 * (-lo).max(hi) + 1) as usize;
    (1..=bound)
        .find(|&n| {
            let km = n.div_ceil(2) as i64;
            km + lo >= 1 && km + hi <= n as i64
        })
        .unwrap_or(bound)
}

/// Roll angles (deg) on whole multiples of `step_deg` over the middle
/// pair's whole kinematic engagement over the face
/// ([`LineContactPair::face_engagement`]: ε_α + ε_β pitches of a helical
/// pair), widened by two steps on each side: the default positions of a
/// mesh cycle (FE contact and LTCA alike).
pub fn engagement_roll_angles(pair: &dyn LineContactPair, step_deg: f64) -> Vec<f64> {
    let (a, e) = pair.face_engagement(pair.middle());
    let start = (a.to_degrees() / step_deg).floor() - 2.0;
    let end = (e.to_degrees() / step_deg).ceil() + 2.0;
    let n = (end - start).round() as i64;
    (0..=n).map(|i| (start + i as f64) * step_deg).collect()
}
