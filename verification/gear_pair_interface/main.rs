//! # The gear-pair interface on a pair that is not an involute
//!
//! flank's analyses see a gear pair only through
//! [`flank::geometry::gear_pair`]: tooth surfaces, gear bodies and the
//! pair's kinematics. This case implements that interface, in this file and
//! with no involute code, for the simplest pair with a known contact: a
//! **pinion with a plane (radial) drive flank against a pin gear** (the
//! gear's "tooth" is a cylinder of radius ρ parallel to the axes, as in pin
//! or lantern gearing), and runs the TCA on it. README.md gives the closed
//! forms; every figure of the TCA is checked against them.

use std::f64::consts::PI;
use std::sync::Arc;

use flank::geometry::frame::Frame;
use flank::geometry::gear_pair::{
    Assembly, Blank, ContactSeed, Flank, GearBody, GearPair, KinematicLine, LineContactPair,
    LineKind, Misalignment,
};
use flank::geometry::surface::{principal_curvatures, ToothSurface};
use flank::tca::{Tca, TcaSettings};

type V3 = [f64; 3];

/// Centre distance a, pin radius ρ, pin-centre height at roll 0 (its
/// distance from the pinion axis along the flank plane), face width b,
/// teeth z₁, z₂ (mm).
const A: f64 = 100.0;
const RHO: f64 = 6.0;
const HEIGHT: f64 = 30.0;
const B: f64 = 12.0;
const Z: [u32; 2] = [10, 25];
/// Pinion speed (rpm).
const RPM: f64 = 1000.0;

/// The pinion's drive flank in its own frame: the radial half-plane
/// x = 0, u the distance from the axis along +y, v = z; outward normal +x
/// (a clockwise-turning pinion pushes with it).
#[derive(Debug)]
struct RadialPlane;

impl ToothSurface for RadialPlane {
    fn u_range(&self) -> (f64, f64) {
        (10.0, 45.0)
    }
    fn v_range(&self) -> (f64, f64) {
        (0.0, B)
    }
    fn u_tip(&self, _v: f64) -> f64 {
        45.0
    }
    fn u_form(&self, _v: f64) -> f64 {
        12.0
    }
    fn u_root(&self, _v: f64) -> f64 {
        10.0
    }
    fn point(&self, u: f64, v: f64) -> V3 {
        [0.0, u, v]
    }
    fn normal(&self, _u: f64, _v: f64) -> V3 {
        [1.0, 0.0, 0.0]
    }
    fn derivatives(&self, _u: f64, _v: f64) -> (V3, V3) {
        ([0.0, 1.0, 0.0], [0.0, 0.0, 1.0])
    }
}

/// The pin in the gear's own frame: a cylinder of radius ρ about the axis
/// through `centre` parallel to z; u the angle from +x, v = z; outward
/// normal (cos u, sin u, 0).
#[derive(Debug)]
struct Pin {
    centre: [f64; 2],
}

impl ToothSurface for Pin {
    fn u_range(&self) -> (f64, f64) {
        (0.0, 2.0 * PI)
    }
    fn v_range(&self) -> (f64, f64) {
        (0.0, B)
    }
    fn u_tip(&self, _v: f64) -> f64 {
        2.0 * PI
    }
    fn u_form(&self, _v: f64) -> f64 {
        0.0
    }
    fn u_root(&self, _v: f64) -> f64 {
        0.0
    }
    fn point(&self, u: f64, v: f64) -> V3 {
        [
            self.centre[0] + RHO * u.cos(),
            self.centre[1] + RHO * u.sin(),
            v,
        ]
    }
    fn normal(&self, u: f64, _v: f64) -> V3 {
        [u.cos(), u.sin(), 0.0]
    }
    fn derivatives(&self, u: f64, _v: f64) -> (V3, V3) {
        ([-RHO * u.sin(), RHO * u.cos(), 0.0], [0.0, 0.0, 1.0])
    }
}

/// A one-tooth sector of a body whose right flank is `flank`.
#[derive(Debug)]
struct Body<S: ToothSurface + 'static> {
    name: &'static str,
    teeth: u32,
    flank: S,
}

impl<S: ToothSurface + 'static> GearBody for Body<S> {
    fn name(&self) -> &str {
        self.name
    }
    fn teeth(&self) -> u32 {
        self.teeth
    }
    fn sector_teeth(&self) -> usize {
        1
    }
    fn angular_pitch(&self) -> f64 {
        2.0 * PI / self.teeth as f64
    }
    fn flank(&self, side: Flank, tooth: usize) -> Option<&dyn ToothSurface> {
        (side == Flank::Right && tooth == 1).then_some(&self.flank as &dyn ToothSurface)
    }
    fn blank(&self) -> Blank {
        Blank {
            bore_radius: 5.0,
            root_radius: 10.0,
            tip_radius: 45.0,
            axial_range: (0.0, B),
        }
    }
    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}

/// The plane-and-pin pair: pinion axis on z, gear axis at (0, a); at roll
/// θ the pinion has turned clockwise by θ, the gear counter-clockwise by
/// θ z₁/z₂. The pin centre is at (ρ, HEIGHT) at θ = 0 (touching the plane).
#[derive(Debug)]
struct PlanePin {
    pinion: Body<RadialPlane>,
    gear: Body<Pin>,
}

impl PlanePin {
    fn new() -> Self {
        PlanePin {
            pinion: Body {
                name: "pinion",
                teeth: Z[0],
                flank: RadialPlane,
            },
            gear: Body {
                name: "gear",
                teeth: Z[1],
                flank: Pin {
                    centre: [RHO, HEIGHT - A],
                },
            },
        }
    }
    fn gear_angle(&self, roll: f64) -> f64 {
        roll * Z[0] as f64 / Z[1] as f64
    }
}

impl GearPair for PlanePin {
    fn pinion(&self) -> &dyn GearBody {
        &self.pinion
    }
    fn gear(&self) -> &dyn GearBody {
        &self.gear
    }
    fn assembly(&self) -> Assembly {
        Assembly {
            shaft_angle_rad: 0.0,
            offset_mm: A,
            mounting_distance_mm: [0.0; 2],
        }
    }
    fn misalignment(&self) -> Misalignment {
        Misalignment::default()
    }
    fn mate(&self, _k: usize) -> usize {
        1
    }
    fn tooth_roll_step(&self) -> f64 {
        self.pinion.angular_pitch()
    }
    fn nominal_frames(&self, roll: f64) -> [Frame; 2] {
        [
            Frame::about_z(-roll, [0.0; 3]),
            Frame::about_z(self.gear_angle(roll), [0.0, A, 0.0]),
        ]
    }
    fn frames(&self, roll: f64) -> [Frame; 2] {
        self.nominal_frames(roll)
    }
    fn rotation_axes(&self) -> [V3; 2] {
        [[0.0, 0.0, -1.0], [0.0, 0.0, 1.0]]
    }
    fn describe(&self) -> serde_json::Value {
        serde_json::json!({"pair": "plane and pin"})
    }
}

impl LineContactPair for PlanePin {
    fn engagement(&self, _k: usize) -> (f64, f64) {
        (-0.2, 0.2)
    }
    fn single_contact(&self) -> (f64, f64) {
        (-0.2, 0.2)
    }
    fn kinematic_contact_ratio(&self) -> f64 {
        0.4 / self.pinion.angular_pitch()
    }
    fn path_position(&self, _k: usize, roll: f64) -> f64 {
        roll + 0.2
    }
    fn path_length(&self) -> f64 {
        0.4
    }
    fn path_pitch(&self) -> f64 {
        self.pinion.angular_pitch()
    }
    fn nominal_moment_arm(&self) -> f64 {
        HEIGHT
    }
    fn transmission_error_radius(&self) -> f64 {
        HEIGHT
    }
    /// One line along the face through the foot of the pin centre on the
    /// pinion's plane (`origin` carries the roll angle).
    fn contact_lines(&self, roll: f64, _corner: f64) -> Vec<KinematicLine> {
        vec![KinematicLine {
            pinion_tooth: 1,
            gear_tooth: 1,
            kind: LineKind::Flank,
            range: (0.0, B),
            param_per_mm: 1.0,
            whole_window: false,
            face_span: B,
            origin: roll,
        }]
    }
    fn line_seed(&self, line: &KinematicLine, xi: f64, across: f64) -> ContactSeed {
        let roll = line.origin;
        let [f1, f2] = self.frames(roll);
        let c = f2.place([self.gear.flank.centre[0], self.gear.flank.centre[1], xi]);
        // foot on the pinion plane, in the pinion's own frame
        let own = f1.rotate_back(c);
        let u1 = own[1] + across;
        let foot = f1.place([0.0, u1, xi]);
        // the pin point facing the plane: its normal is −n
        let n = f1.rotate([1.0, 0.0, 0.0]);
        let m = f2.rotate_back([-n[0], -n[1], 0.0]);
        ContactSeed {
            point: foot,
            pinion_uv: [u1, xi],
            gear_uv: [m[1].atan2(m[0]), xi],
            inside: true,
        }
    }
}

/// Closed forms at roll θ (README): pin centre c, plane normal n and
/// direction t, separation w = n·c − ρ, moment arm r = t·c, TE w/r, the
/// surface speeds along e_roll = n × e_z (m/s).
struct Exact {
    w: f64,
    arm: f64,
    foot: V3,
    v_t: [f64; 2],
}

fn exact(pair: &PlanePin, roll: f64, z: f64) -> Exact {
    let (s, c) = roll.sin_cos();
    let n = [c, -s, 0.0];
    let t = [s, c, 0.0];
    let g = pair.gear_angle(roll);
    let (sg, cg) = g.sin_cos();
    let p0 = pair.gear.flank.centre;
    let centre = [cg * p0[0] - sg * p0[1], A + sg * p0[0] + cg * p0[1], z];
    let dot = |a: V3, b: V3| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let w = dot(n, centre) - RHO;
    let arm = dot(t, centre);
    let foot = [arm * t[0], arm * t[1], z];
    // pinion: ω₁ (−e_z) × x is along n (no tangential part); gear point x₂
    // = foot + w n: ω₂ e_z × (x₂ − A e_y), along e_roll = n × e_z = −t
    let w1 = RPM * PI / 30.0;
    let w2 = w1 * Z[0] as f64 / Z[1] as f64;
    let x2 = [foot[0] + w * n[0], foot[1] + w * n[1], z];
    let r2 = [x2[0], x2[1] - A, 0.0];
    let v2 = [-w2 * r2[1], w2 * r2[0], 0.0];
    let e = [-t[0], -t[1], 0.0];
    Exact {
        w,
        arm,
        foot,
        v_t: [0.0, dot(v2, e) * 1e-3],
    }
}

fn check(name: &str, got: f64, want: f64, tol: f64) {
    let err = (got - want).abs();
    println!("{name:<40} {got:>+.12e}  exact {want:>+.12e}  |err| {err:.1e}  (tol {tol:.0e})");
    assert!(err <= tol, "{name}: {got} vs {want}, error {err} > {tol}");
}

/// The TCA through the interface: separation, moment arm, unloaded TE,
/// curvature radii, velocities and sampling against the closed forms.
#[test]
fn tca_of_a_plane_against_a_pin() {
    let pair = Arc::new(PlanePin::new());
    let settings = TcaSettings {
        points_per_line: 6,
        extension_mm: 0.0,
        ..TcaSettings::default()
    };
    let tca = Tca::new(pair.clone(), RPM, settings).unwrap();
    for roll in [-0.15, -0.05, 0.0, 0.04, 0.12] {
        let p = tca.position(roll).unwrap();
        assert_eq!(p.lines.len(), 1, "one line at roll {roll}");
        let line = &p.lines[0];
        assert_eq!(line.points.len(), 6);
        check("line length (mm)", line.length_mm, B, 1e-12);
        let mut te = f64::INFINITY;
        for (i, q) in line.points.iter().enumerate() {
            let z = B * (i as f64 + 0.5) / 6.0;
            let e = exact(&pair, roll, z);
            check(
                &format!("roll {roll:+.2}: separation w (mm)"),
                q.separation_mm,
                e.w,
                1e-11,
            );
            check("moment arm r (mm)", q.moment_arm_mm, e.arm, 1e-11);
            check("pinion flank u (mm)", q.pinion_uv[0], e.arm, 1e-11);
            check("width (mm)", q.width_mm, B / 6.0, 1e-12);
            // midpoint of the two surface points: foot + w n / 2
            let mid = [
                e.foot[0] + 0.5 * e.w * roll.cos(),
                e.foot[1] - 0.5 * e.w * roll.sin(),
                z,
            ];
            for (got, want) in q.position.iter().zip(mid) {
                check("position (mm)", *got, want, 1e-10);
            }
            assert!(q.curvature_radius[0].is_infinite(), "plane: ρ₁ = ∞");
            check("pin radius ρ₂ (mm)", q.curvature_radius[1], RHO, 1e-6 * RHO);
            check(
                "equivalent radius (mm)",
                q.equivalent_radius_mm,
                RHO,
                1e-6 * RHO,
            );
            // v_t1 = 0: the plane's points move along its normal
            let [vt1, vt2] = e.v_t;
            check(
                "sliding v_t1 − v_t2 (m/s)",
                q.sliding_velocity,
                vt1 - vt2,
                1e-9,
            );
            check(
                "rolling (v_t1 + v_t2)/2 (m/s)",
                q.rolling_velocity,
                0.5 * (vt1 + vt2),
                1e-9,
            );
            check("sum v_t1 + v_t2 (m/s)", q.sum_velocity, vt1 + vt2, 1e-9);
            te = te.min(e.w / e.arm);
        }
        check(
            &format!("roll {roll:+.2}: unloaded TE (rad)"),
            p.unloaded_te_rad,
            te,
            1e-12,
        );
    }
    // the interface's own figures agree with the closed forms
    let q = principal_curvatures(&pair.gear.flank, 1.0, 3.0);
    check(
        "pin κ₁ from the fundamental forms",
        q.principal[0],
        1.0 / RHO,
        1e-7,
    );
    check("pin κ₂ (along the axis)", q.principal[1], 0.0, 1e-7);
    // the cycle's positions come from the pair's engagement and pitch
    let rolls = tca.roll_angles_for_cycle(4);
    let pitch = 2.0 * PI / Z[0] as f64;
    check("first roll of a cycle (rad)", rolls[0], -0.5 * pitch, 1e-15);
}
