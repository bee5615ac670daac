//! A spiral bevel or hypoid pair behind the gear-pair interface
//! ([`GearPair`]): two [`BevelGear`] sectors placed by the assembly
//! ([`PairAssembly`]) and turned together.
//!
//! * **Body frames**: a member's body has tooth 1 centred on its own +y
//!   ([`super::body`]); the assembly's member frame has its own +x through
//!   the mean pitch point P at rotation 0 ([`super::assembly`]). The body
//!   frame is the member frame at rotation φ − π/2.
//! * **Drive**: a positive roll θ turns the pinion so that its drive flank
//!   (`Flank::Right`, concave) advances along its outward normal, i.e.
//!   pushes the gear's drive flank (convex); the gear follows at the ratio
//!   z₁/z₂ in the sense the rolling pitch cones give
//!   ([`PairAssembly::roll_ratio`]).
//! * **Roll 0**: the middle pinion tooth's drive flank passes through P
//!   (its pitch-cone point at the mean cone distance lies in the plane of
//!   the pinion axis and P) and the gear is turned into contact with it
//!   (flank tangency, [`crate::geometry::tangency`]); for a conjugate pair
//!   the contact is then at P.
//! * **Tooth order**: tooth k + 1 of a body is tooth k turned by −2π/z
//!   about its own +z, so it follows tooth k into mesh after the body turns
//!   by +2π/z about own +z: after a roll of ±2π/z₁ by the sense of the
//!   pinion's rotation ([`GearPair::tooth_roll_step`]).

use std::f64::consts::PI;
use std::sync::Arc;

use serde_json::json;

use super::assembly::PairAssembly;
use super::body::BevelGear;
use crate::error::{FlankError, Result};
use crate::geometry::frame::Frame;
use crate::geometry::gear_pair::{Assembly, Flank, GearBody, GearPair, Misalignment};
use crate::geometry::tangency::{self, ContactSystem, GearTurn, PlacedFlank, TangencySeed};
use crate::geometry::vec3::{cross, dot, sub, V3};

/// A bevel/hypoid pair (module docs).
#[derive(Clone, Debug)]
pub struct BevelPair {
    bodies: [Arc<BevelGear>; 2],
    assembly: PairAssembly,
    /// Sense of each body's rotation about its own +z for a positive roll.
    sense: [f64; 2],
    /// Member rotations φ₁, φ₂ of the assembly at roll 0 (rad).
    reference: [f64; 2],
}

impl BevelPair {
    /// The pair of `bodies` = [pinion, gear] in `assembly` (its
    /// misalignment included).
    pub fn new(bodies: [Arc<BevelGear>; 2], assembly: PairAssembly) -> Result<Self> {
        let z = [bodies[0].teeth(), bodies[1].teeth()];
        if z != assembly.teeth {
            return Err(FlankError::Model(format!(
                "bevel pair: the bodies have {}/{} teeth, the assembly {}/{}",
                z[0], z[1], assembly.teeth[0], assembly.teeth[1]
            )));
        }
        if bodies[0].sector_teeth() != bodies[1].sector_teeth() {
            return Err(FlankError::Model(
                "bevel pair: the two bodies' sectors have different tooth counts".into(),
            ));
        }
        let m = assembly.roll_ratio();
        let nominal = PairAssembly {
            misalignment: Misalignment::default(),
            ..assembly
        };
        let mut pair = BevelPair {
            bodies: bodies.clone(),
            assembly,
            sense: [1.0, m.signum()],
            reference: [0.0, 0.0],
        };
        let km = pair.middle();
        // φ that brings a body's drive-flank mean pitch point onto the
        // member frame's +x (the plane of its axis and P)
        let onto_p = |b: &BevelGear, tooth: usize| -> Result<f64> {
            let rm = b.cones().rm;
            let s = b.flank(Flank::Right, tooth).ok_or_else(|| {
                FlankError::Model(format!("bevel pair: {} has no tooth {tooth}", b.name()))
            })?;
            let q = s.point(0.0, rm);
            // body → member frame: a turn by −π/2 about z
            let (x, y) = (q[1], -q[0]);
            Ok(-y.atan2(x))
        };
        let phi1 = onto_p(&bodies[0], km)?;
        // The drive sense: the drive flank advances along its normal.
        let f1 = member_frames(&nominal, phi1, 0.0)[0];
        let s1 = bodies[0].flank(Flank::Right, km).unwrap();
        let rm1 = bodies[0].cones().rm;
        let (x, n) = (f1.place(s1.point(0.0, rm1)), f1.rotate(s1.normal(0.0, rm1)));
        let k1 = nominal.pinion_axis();
        let c1 = nominal.crossing_points()[0];
        let advance = dot(cross(k1, sub(x, c1)), n);
        if advance == 0.0 || !advance.is_finite() {
            return Err(FlankError::Model(
                "bevel pair: the pinion's drive flank does not face the direction of rotation at the mean point".into(),
            ));
        }
        let s = advance.signum();
        pair.sense = [s, s * m.signum()];
        // the gear: its mate's drive flank at P, then turned into contact
        let gm = pair.mate(km);
        let phi2 = onto_p(&bodies[1], gm)?;
        let frames = member_frames(&nominal, phi1, phi2);
        let gear_flank = bodies[1].flank(Flank::Right, gm).unwrap();
        let turn = GearTurn {
            point: frames[1].translation,
            axis: frames[1].rotate([0.0, 0.0, 1.0]),
        };
        let rm2 = bodies[1].cones().rm;
        let contact = tangency::solve(
            ContactSystem::Flank,
            &PlacedFlank {
                surface: s1,
                frame: frames[0],
            },
            &PlacedFlank {
                surface: gear_flank,
                frame: frames[1],
            },
            &turn,
            &TangencySeed {
                pinion_uv: [0.0, rm1],
                gear_uv: [0.0, rm2],
                turn: 0.0,
            },
        )
        .map_err(|e| {
            FlankError::Model(format!(
                "bevel pair: the middle teeth do not touch near the mean point ({e}): the pair does not mesh (hands, offset sign or flanks)"
            ))
        })?;
        pair.reference = [phi1, phi2 + contact.turn];
        Ok(pair)
    }

    /// The assembly (with its misalignment).
    pub fn pair_assembly(&self) -> &PairAssembly {
        &self.assembly
    }

    /// The same pair with `misalignment` in place of its own.
    pub fn with_misalignment(&self, misalignment: Misalignment) -> Self {
        BevelPair {
            assembly: PairAssembly {
                misalignment,
                ..self.assembly
            },
            ..self.clone()
        }
    }

    pub fn bevel_body(&self, b: usize) -> &BevelGear {
        &self.bodies[b]
    }

    /// Member rotations (φ₁, φ₂) of the assembly at `roll`.
    fn rotations(&self, roll: f64) -> (f64, f64) {
        (
            self.reference[0] + self.sense[0] * roll,
            self.reference[1] + self.sense[1] * self.ratio() * roll,
        )
    }
}

/// Body frames (tooth 1 on own +y) of the member rotations φ₁, φ₂.
fn member_frames(assembly: &PairAssembly, phi1: f64, phi2: f64) -> [Frame; 2] {
    assembly.frames(phi1 - 0.5 * PI, phi2 - 0.5 * PI)
}

impl GearPair for BevelPair {
    fn pinion(&self) -> &dyn GearBody {
        self.bodies[0].as_ref()
    }
    fn gear(&self) -> &dyn GearBody {
        self.bodies[1].as_ref()
    }
    fn assembly(&self) -> Assembly {
        Assembly {
            shaft_angle_rad: self.assembly.shaft_angle,
            offset_mm: self.assembly.offset,
            mounting_distance_mm: self.assembly.apex,
        }
    }
    fn misalignment(&self) -> Misalignment {
        self.assembly.misalignment
    }
    fn mate(&self, k: usize) -> usize {
        if self.sense[0] * self.sense[1] > 0.0 {
            k
        } else {
            self.sector_teeth() + 1 - k
        }
    }
    fn tooth_roll_step(&self) -> f64 {
        self.sense[0] * self.pinion().angular_pitch()
    }
    fn nominal_frames(&self, roll: f64) -> [Frame; 2] {
        let (p, g) = self.rotations(roll);
        let nominal = PairAssembly {
            misalignment: Misalignment::default(),
            ..self.assembly
        };
        member_frames(&nominal, p, g)
    }
    fn frames(&self, roll: f64) -> [Frame; 2] {
        let (p, g) = self.rotations(roll);
        member_frames(&self.assembly, p, g)
    }
    fn rotation_axes(&self) -> [V3; 2] {
        [[0.0, 0.0, self.sense[0]], [0.0, 0.0, self.sense[1]]]
    }
    fn describe(&self) -> serde_json::Value {
        let a = &self.assembly;
        json!({
            "pair": "bevel",
            "shaft_angle_deg": a.shaft_angle.to_degrees(),
            "offset_mm": a.offset,
            "pitch_apex_beyond_crossing_point_mm": a.apex,
            "teeth": a.teeth,
            "roll_ratio": a.roll_ratio(),
            "rotation_sense": self.sense,
            "reference_rotation_deg": [self.reference[0].to_degrees(), self.reference[1].to_degrees()],
            "misalignment": a.misalignment,
        })
    }
}
