//! Rigid kinematics of a parallel-axis pair meshed as two tooth sectors:
//! where each body sits at a roll angle, which teeth pair up, and where the
//! kinematic contact lies on the line of action.
//!
//! Global frame: pinion axis on the z axis, gear axis at (0, a); both face
//! widths centred on the same mid plane. Angles φ below are measured
//! clockwise from +y (e_r(φ) = (sin φ, cos φ)), the convention of
//! [`ToothProfile`]: the right flank of tooth 0 at roll u has its base
//! tangent point at φ_T = ψ_b − u and outward normal e_φ(φ_T).
//!
//! Drive: a positive torque turns the pinion clockwise (seen from +z) and
//! loads the right flanks `FLANK_R<k>` of both bodies (the flanks the gear
//! bodies and the compliance tensors load). The line of action then runs
//! from T₁ = r_b1 e_r(−α_wt) on the pinion's base circle up to T₂ on the
//! gear's, length L = a sin α_wt; a contact point at roll u₁ of the pinion
//! flank lies s = r_b1 u₁ from T₁ (ISO 21771, path of contact). Pinion
//! tooth k (clockwise offset (k − k_m) p₁ from the middle tooth k_m) meets
//! gear tooth n + 1 − k when r_b1 u₁ + r_b2 u₂ = L, which a single gear
//! phase satisfies for all pairs and roll angles (r_b1 p₁ = r_b2 p₂ = p_bt).
//!
//! Roll angle θ (flank's convention): pinion rotation in the drive
//! direction, θ = 0 when the middle pair's kinematic contact is at the
//! pitch point C.

use std::f64::consts::PI;

use crate::error::FlankError;
use crate::geometry::frame::Frame;
use crate::geometry::involute::inv;
use crate::geometry::pair::check_pair;
use crate::geometry::rack::ToothProfile;
use crate::geometry::PairSpec;

/// Kinematics of a pair of sectors (`teeth` teeth each).
#[derive(Clone, Debug, serde::Serialize)]
pub struct MeshKinematics {
    pub z1: f64,
    pub z2: f64,
    /// Teeth per sector n and the middle pinion tooth k_m = ⌈n/2⌉ (1-based).
    pub teeth: usize,
    pub middle: usize,
    pub centre_distance: f64,
    /// r_b1, r_b2 (mm), α_wt (rad).
    pub base_radius: [f64; 2],
    pub working_pressure_angle: f64,
    /// Length of the line of action between the tangent points, L = a sin α_wt.
    pub line_length: f64,
    /// Half angular tooth thickness at the base circle ψ_b (rad).
    pub base_half_angle: [f64; 2],
    /// Angular pitch 2π/z (rad).
    pub angular_pitch: [f64; 2],
    /// Roll angles of the tips (rad).
    pub tip_roll: [f64; 2],
    /// Start and end of the path of contact, distances from T₁ (mm).
    pub path_start: f64,
    pub path_end: f64,
    /// Base helix angle β_b (rad; 0 for spur gears).
    pub base_helix_angle: f64,
    /// Transverse base pitch p_bt and transverse contact ratio ε_α.
    pub base_pitch: f64,
    pub contact_ratio: f64,
    /// Face widths (mm) and the gear's axial shift (b₁ − b₂)/2 (mm).
    pub face_width: [f64; 2],
    pub gear_z_shift: f64,
    /// Clockwise placement angle of the gear at θ = 0 (rad).
    gear_phase: f64,
}

impl MeshKinematics {
    /// Kinematics of `pair` meshed as sectors of `teeth` teeth.
    pub fn new(pair: &PairSpec, teeth: usize) -> Result<Self, FlankError> {
        if teeth == 0 {
            return Err(FlankError::Model(
                "a sector needs at least one tooth".into(),
            ));
        }
        let report = check_pair(pair)?;
        let p1 = ToothProfile::new(&pair.pinion, "pinion")?;
        let p2 = ToothProfile::new(&pair.gear, "gear")?;
        let rb = [p1.geometry.base_radius, p2.geometry.base_radius];
        let alpha = report.working_pressure_angle_rad;
        let a = pair.centre_distance;
        let line_length = a * alpha.sin();
        let psi = [p1.base_half_angle, p2.base_half_angle];
        let pitch = [p1.angular_pitch(), p2.angular_pitch()];
        let middle = teeth.div_ceil(2);
        let path_start = line_length - rb[1] * p2.u_tip;
        let path_end = rb[0] * p1.u_tip;
        let base_pitch = report.transverse_base_pitch;
        let shift = 0.5 * (pair.pinion.face_width - pair.gear.face_width);
        // gear tooth n + 1 − k_m meets the middle pinion tooth at θ_c = 0
        let gear_phase = (line_length - rb[0] * (psi[0] + alpha)) / rb[1]
            - psi[1]
            - (teeth - middle) as f64 * pitch[1]
            + PI
            - alpha
            - p2.twist_rate * shift;
        Ok(MeshKinematics {
            z1: pair.pinion.teeth as f64,
            z2: pair.gear.teeth as f64,
            teeth,
            middle,
            centre_distance: a,
            base_radius: rb,
            working_pressure_angle: alpha,
            line_length,
            base_half_angle: psi,
            angular_pitch: pitch,
            tip_roll: [p1.u_tip, p2.u_tip],
            path_start,
            path_end,
            base_helix_angle: crate::geometry::involute::base_helix_angle(&pair.pinion),
            base_pitch,
            contact_ratio: (path_end - path_start) / base_pitch,
            face_width: [pair.pinion.face_width, pair.gear.face_width],
            gear_z_shift: shift,
            gear_phase,
        })
    }

    /// θ_c: the roll angle from the position with the middle pinion tooth
    /// centred on +y.
    fn centred(&self, roll: f64) -> f64 {
        roll + inv(self.working_pressure_angle) - self.base_half_angle[0]
    }

    /// Clockwise rotations (rad) of the pinion and the gear sector from
    /// their own frames to their positions at `roll`.
    pub fn body_angles(&self, roll: f64) -> [f64; 2] {
        let tc = self.centred(roll);
        [
            tc - (self.middle - 1) as f64 * self.angular_pitch[0],
            self.gear_phase - tc * self.z1 / self.z2,
        ]
    }

    /// Frames (own → global) of the pinion and the gear at `roll`.
    pub fn frames(&self, roll: f64) -> [Frame; 2] {
        let [a1, a2] = self.body_angles(roll);
        [
            Frame::about_z(-a1, [0.0; 3]),
            Frame::about_z(-a2, [0.0, self.centre_distance, self.gear_z_shift]),
        ]
    }

    /// The gear tooth meeting pinion tooth `k` (both 1-based sector teeth).
    pub fn mate(&self, k: usize) -> usize {
        self.teeth + 1 - k
    }

    /// Kinematic contact position of pinion tooth `k` at `roll`: distance
    /// from T₁ along the line of action (mm), s = r_b1 u₁.
    pub fn contact_position(&self, k: usize, roll: f64) -> f64 {
        let u = self.base_half_angle[0]
            + self.centred(roll)
            + self.working_pressure_angle
            + (k as f64 - self.middle as f64) * self.angular_pitch[0];
        self.base_radius[0] * u
    }

    /// The roll angle at which pinion tooth `k`'s kinematic contact is at `s`.
    pub fn roll_at(&self, k: usize, s: f64) -> f64 {
        let s0 = self.contact_position(k, 0.0);
        (s - s0) / self.base_radius[0]
    }

    /// Kinematic engagement of pinion tooth `k`: roll angles of its start
    /// (gear tip on the pinion flank) and end (pinion tip) of contact.
    pub fn engagement(&self, k: usize) -> (f64, f64) {
        (
            self.roll_at(k, self.path_start),
            self.roll_at(k, self.path_end),
        )
    }

    /// Kinematic single-tooth contact of the middle pair: from the end of
    /// the preceding pair's contact (lowest point of single-tooth contact on
    /// the pinion) to the start of the following pair's.
    pub fn single_contact(&self) -> (f64, f64) {
        let k = self.middle;
        let pitch = self.base_pitch / self.base_radius[0];
        let (start, end) = self.engagement(k);
        (end - pitch, start + pitch)
    }

    /// Roll of the mating gear tooth's involute at the kinematic contact of
    /// pinion tooth `k`: u₂ = (L − s)/r_b2.
    pub fn gear_roll(&self, k: usize, roll: f64) -> f64 {
        (self.line_length - self.contact_position(k, roll)) / self.base_radius[1]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::rack::{Flank, Segment};

    fn seed002() -> PairSpec {
        crate::scene::read_scene(std::path::Path::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/papers/seed002-spur/scene.toml"
        )))
        .unwrap()
        .cylindrical("this test")
        .unwrap()
        .pair
        .clone()
    }

    /// Placed with [`MeshKinematics::frames`], the exact right flanks of
    /// every pinion tooth and its mate touch at the kinematic contact point
    /// with opposite normals, at several roll angles.
    #[test]
    fn placed_flanks_touch_on_the_line_of_action() {
        let pair = seed002();
        let kin = MeshKinematics::new(&pair, 3).unwrap();
        let p1 = ToothProfile::new(&pair.pinion, "pinion").unwrap();
        let p2 = ToothProfile::new(&pair.gear, "gear").unwrap();
        assert!(
            (kin.contact_ratio - 1.484).abs() < 2e-3,
            "{}",
            kin.contact_ratio
        );
        for roll_deg in [-20.0, -7.0, 0.0, 3.5, 15.0] {
            let roll = roll_deg * PI / 180.0;
            let [f1, f2] = kin.frames(roll);
            for k in 1..=3 {
                let s = kin.contact_position(k, roll);
                let u1 = s / kin.base_radius[0];
                let u2 = kin.gear_roll(k, roll);
                // sector tooth k is the profile's tooth k − 1 rotated by −2π(k−1)/z
                let own = |prof: &ToothProfile, u: f64, tooth: usize| {
                    let q = prof.surface(Flank::Right, Segment::Involute(u), 5.0);
                    let t = Frame::about_z(-((tooth - 1) as f64) * prof.angular_pitch(), [0.0; 3]);
                    (t.place(q.p), t.rotate(q.n))
                };
                let (x1, n1) = own(&p1, u1, k);
                let (x2, n2) = own(&p2, u2, kin.mate(k));
                let (x1, n1) = (f1.place(x1), f1.rotate(n1));
                let (x2, n2) = (f2.place(x2), f2.rotate(n2));
                let d =
                    ((x1[0] - x2[0]).powi(2) + (x1[1] - x2[1]).powi(2) + (x1[2] - x2[2]).powi(2))
                        .sqrt();
                assert!(
                    d < 1e-9,
                    "roll {roll_deg}, tooth {k}: points {d:.3e} mm apart"
                );
                let c = n1[0] * n2[0] + n1[1] * n2[1] + n1[2] * n2[2];
                assert!((c + 1.0).abs() < 1e-12, "normals not opposite: {c}");
                // the normal is the line of action (α_wt to the x axis)
                let a = kin.working_pressure_angle;
                assert!((n1[0] - a.cos()).abs() < 1e-12 && (n1[1] - a.sin()).abs() < 1e-12);
            }
        }
        // pitch point at roll 0, and the single contact inside the engagement
        let c = kin.contact_position(kin.middle, 0.0);
        let rb1 = kin.base_radius[0];
        assert!((c - rb1 * kin.working_pressure_angle.tan()).abs() < 1e-12);
        let (a, e) = kin.engagement(2);
        let (l, h) = kin.single_contact();
        assert!(a < l && l < h && h < e);
        let eps = (e - a) / kin.angular_pitch[0];
        assert!((eps - kin.contact_ratio).abs() < 1e-12);
    }
}
