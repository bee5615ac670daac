//! Face hobbing (continuous indexing: Oerlikon, Klingelnberg Cyclo-Palloid,
//! Gleason TriAC/PentAC): the kinematic chain q = (s, θ, ψ) ↦ r(q) in the
//! work frame as an [`EnvelopeMap`], and the closed form of the extended
//! epicycloid that a blade point traces in the generating crown gear.
//!
//! **Process.** The cutter head carries z₀ blade groups and turns by θ;
//! the work turns with it by −(z₀/z) θ (one tooth pitch of the work per
//! blade group passing), and, for a generated member, by the generating
//! roll φ(ψ) of the cradle as in face milling. Seen from the generating
//! crown gear (z_p = z / sin δ teeth) the cutter's rolling circle (radius
//! M z₀/(z_p + z₀), M the radial distance) rolls on the crown gear's base
//! circle (radius ρ_b = M z_p/(z_p + z₀)), so each blade point traces an
//! **extended epicycloid**: the lengthwise tooth curve. References: ISO
//! 23509:2016 clause 6.3 (face-hobbing quantities ν, λ, ρ_b; see
//! `pitch_cone::hobbing`); Fan, "Computerized modeling and simulation of
//! spiral bevel and hypoid gears manufactured by Gleason face hobbing
//! process", ASME J. Mech. Des. 128 (2006), §2 (blade in the offset plane,
//! cutter–work indexing ratio, generating crown gear); Vimercati, Mech.
//! Mach. Theory 42 (2007), §2–3 (the same chain for Oerlikon/Klingelnberg
//! heads, tilt on the pinion). The formulation and signs here are this
//! module's own.
//!
//! **Frames** are those of [`crate::geometry::bevel::cradle_machine`]
//! (machine frame with the cradle axis z_m, tip plane z_m = 0, work axis
//! below the cradle plane by γ_m, roll ψ, work rotation φ(ψ)); the chain
//! reuses its [`CradleGeneration::to_work`]. Only the tool differs:
//!
//! * **blade in an offset plane**: a face-hobbing blade's edge lies in a
//!   plane parallel to the cutter axis at the signed distance b (the blade
//!   offset) from it: in the head frame the blade point at profile
//!   parameter s is (x(s), b, h(s)), (x, h) the blade profile of
//!   [`crate::geometry::bevel::cutter`] with x measured in that plane from
//!   the foot of the offset, turned about the cutter axis by θ + phase.
//!   Its radius from the cutter axis is √(x² + b²). The ISO 23509 relation
//!   |b| = r_c0 sin ν = z₀ m_mn / 2 places the plane along the tooth
//!   trace's normal at the mean point;
//! * **cutter head**: centre at (S_r cos q, S_r sin q, 0) in the cradle
//!   frame, tilt i and swivel j as in the cradle machine
//!   (Rot_z(j) Rot_x(i) Rot_z(−j));
//! * **continuous indexing**: after the cradle chain the work frame is
//!   turned by −(z₀/z) θ about its axis. With the crown gear's rotation
//!   −(z₀/z_p) θ for the cutter's θ (external rolling of the two circles)
//!   and ψ = R_a φ for the roll, this is the same indexing seen from the
//!   work (R_a = z/z_p for a bevel gear rolling on its crown gear).
//!
//! r = Rot_z(−(z₀/z) θ) · to_work(C₀ + T_tilt · Rot_z(θ + phase) (x(s), b, h(s)), ψ);
//! a **formate** member holds ψ = 0 (its flank is the surface swept by the
//! blade edge in the indexing motion alone).
//!
//! **Family parameters.** The map's second parameter is the sheared cutter
//! angle q₁ = θ + c ψ (c = [`ROLL_SHEAR`]), so q = (s, q₁, ψ) and
//! θ = q₁ − c ψ. The equation of meshing is unchanged by the shear
//! (det(r_s, r_θ, r_ψ − c r_θ) = det(r_s, r_θ, r_ψ)), but ∂r/∂ψ at fixed q₁
//! no longer vanishes on the instantaneous axis of rolling, where the
//! pitch-cone points of a generated member are generated (there the
//! relative velocity r_ψ at fixed θ is zero and the envelope engine's
//! dimensionless residual f/(|r_s × r_θ| |r_ψ|) would be 0/0).

use num_dual::DualNum;

use crate::error::{FlankError, Result};
use crate::geometry::bevel::cradle_machine::{CradleGeneration, CradleTool, MachineSettings};
use crate::geometry::bevel::cutter::{Blade, BladeProfile};
use crate::geometry::bevel::generation::{jet_of, EnvelopeMap, Jet};
use crate::geometry::vec3::V3;

/// The shear c of the family parameters (module docs), rad/rad.
pub const ROLL_SHEAR: f64 = 1.0;

/// A face-hobbing blade: the profile (blade angle, edge radius, Toprem,
/// curvature as in [`Blade`], whose `point_radius` is here the in-plane
/// coordinate x of the blade point at the tip plane) in a plane offset by
/// `offset` from the cutter axis, at the angular position `phase` in the
/// head (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HobbingBlade {
    pub blade: Blade,
    /// Signed blade offset b (mm): distance of the blade plane from the
    /// cutter axis.
    pub offset: f64,
    /// Angular position of the blade in the head at θ = 0 (rad).
    pub phase: f64,
}

impl HobbingBlade {
    /// Radius from the cutter axis of the blade point at the tip plane,
    /// √(x_p² + b²) (mm).
    pub fn point_radius(&self) -> f64 {
        self.blade.point_radius.hypot(self.offset)
    }
}

/// The settings of a face-hobbing machine: the cradle-machine settings
/// (radial distance, cradle angle, machine root angle, sliding base,
/// blank offset, machine centre to back, ratio of roll and modified roll,
/// tilt, swivel, generated or formate) plus the indexing: blade groups z₀
/// and the work's tooth number z.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FaceHobbingSettings {
    pub machine: MachineSettings,
    /// Blade groups z₀ of the cutter head.
    pub blade_groups: u32,
    /// Teeth of the work z.
    pub work_teeth: u32,
}

impl FaceHobbingSettings {
    /// Indexing ratio z₀/z: work turn per cutter turn.
    pub fn index_ratio(&self) -> f64 {
        f64::from(self.blade_groups) / f64::from(self.work_teeth)
    }

    /// Checks the settings; errors name the setting.
    pub fn validate(&self) -> Result<()> {
        if self.blade_groups == 0 {
            return Err(FlankError::Model(
                "face hobbing: blade_groups z0 = 0 (a face-hobbing head has at least one blade group)"
                    .into(),
            ));
        }
        if self.work_teeth < 3 {
            return Err(FlankError::Model(format!(
                "face hobbing: work_teeth {} < 3",
                self.work_teeth
            )));
        }
        self.machine.validate()
    }
}

/// The face-hobbing kinematic chain (module docs): an [`EnvelopeMap`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FaceHobbing {
    pub settings: FaceHobbingSettings,
    pub blade: HobbingBlade,
    profile: BladeProfile,
    tilt: [[f64; 3]; 3],
    /// The cradle machine's chain, used for its cradle → work transform.
    cradle: CradleGeneration,
}

/// The cutter tilt rotation Rot_z(j) Rot_x(i) Rot_z(−j) (tilt i, swivel j).
pub(crate) fn tilt_matrix(tilt: f64, swivel: f64) -> [[f64; 3]; 3] {
    let (si, ci) = tilt.sin_cos();
    let (sj, cj) = swivel.sin_cos();
    let rz = |s: f64, c: f64| [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]];
    let rx = [[1.0, 0.0, 0.0], [0.0, ci, -si], [0.0, si, ci]];
    let mul = |a: [[f64; 3]; 3], b: [[f64; 3]; 3]| {
        let mut m = [[0.0; 3]; 3];
        for (i, row) in m.iter_mut().enumerate() {
            for (j, x) in row.iter_mut().enumerate() {
                *x = (0..3).map(|k| a[i][k] * b[k][j]).sum();
            }
        }
        m
    };
    mul(mul(rz(sj, cj), rx), rz(-sj, cj))
}

impl FaceHobbing {
    /// The chain for one blade; errors name the setting or blade field.
    pub fn new(settings: FaceHobbingSettings, blade: HobbingBlade) -> Result<Self> {
        settings.validate()?;
        let profile = blade.blade.profile()?;
        if !(blade.offset.is_finite() && blade.phase.is_finite()) {
            return Err(FlankError::Model(format!(
                "face-hobbing blade: offset {} and phase {} must be finite",
                blade.offset, blade.phase
            )));
        }
        let m = settings.machine;
        // the cradle chain with a neutral tool: only its transform is used
        let cradle = CradleGeneration::new(
            m,
            CradleTool::Plane {
                origin: [0.0; 3],
                profile_dir: [1.0, 0.0, 0.0],
                lengthwise_dir: [0.0, 1.0, 0.0],
                orientation: 1.0,
            },
        )?;
        Ok(FaceHobbing {
            settings,
            blade,
            profile,
            tilt: tilt_matrix(m.tilt, m.swivel),
            cradle,
        })
    }

    /// The blade's profile constants.
    pub fn profile(&self) -> &BladeProfile {
        &self.profile
    }

    /// Blade point at (s, θ) in the head frame (cutter axis +z, tip plane
    /// z = 0).
    pub fn head_point<D: DualNum<Primitive = f64> + Copy>(&self, s: D, theta: D) -> [D; 3] {
        let (x, h) = self.profile.profile(s);
        let t = theta + self.blade.phase;
        let (st, ct) = (t.sin(), t.cos());
        let b = self.blade.offset;
        [x * ct - st * b, x * st + ct * b, h]
    }

    /// Blade point in the cradle frame: tilted head, centre at the radial
    /// distance and cradle angle.
    pub fn cradle_point<D: DualNum<Primitive = f64> + Copy>(&self, s: D, theta: D) -> [D; 3] {
        let p = self.head_point(s, theta);
        let m = &self.tilt;
        let sr = self.settings.machine.radial_distance;
        let (sq, cq) = self.settings.machine.cradle_angle.sin_cos();
        [
            p[0] * m[0][0] + p[1] * m[0][1] + p[2] * m[0][2] + sr * cq,
            p[0] * m[1][0] + p[1] * m[1][1] + p[2] * m[1][2] + sr * sq,
            p[0] * m[2][0] + p[1] * m[2][1] + p[2] * m[2][2],
        ]
    }

    /// The angle about the cutter axis of a cradle-frame point `p`, in the
    /// head frame (the tilt undone): the θ + phase at which a blade's
    /// plane-foot direction points at p's projection.
    pub fn head_angle(&self, p: [f64; 3]) -> f64 {
        let m = &self.tilt;
        let sr = self.settings.machine.radial_distance;
        let (sq, cq) = self.settings.machine.cradle_angle.sin_cos();
        let d = [p[0] - sr * cq, p[1] - sr * sq, p[2]];
        // Tᵀ d
        let h: [f64; 3] = std::array::from_fn(|k| m[0][k] * d[0] + m[1][k] * d[1] + m[2][k] * d[2]);
        h[1].atan2(h[0])
    }

    /// The cutter angle θ of the family parameters q (module docs).
    pub fn cutter_angle(&self, q: [f64; 3]) -> f64 {
        if self.settings.machine.generated {
            q[1] - ROLL_SHEAR * q[2]
        } else {
            q[1]
        }
    }

    /// r(q) in the work frame (module docs).
    pub fn position_generic<D: DualNum<Primitive = f64> + Copy>(&self, q: [D; 3]) -> [D; 3] {
        let psi = if self.settings.machine.generated {
            q[2]
        } else {
            q[2] * 0.0
        };
        let theta = q[1] - psi * ROLL_SHEAR;
        let w = self.cradle.to_work(self.cradle_point(q[0], theta), psi);
        let a = -(theta * self.settings.index_ratio());
        let (sa, ca) = (a.sin(), a.cos());
        [w[0] * ca - w[1] * sa, w[0] * sa + w[1] * ca, w[2]]
    }
}

impl EnvelopeMap for FaceHobbing {
    fn jet(&self, q: [f64; 3]) -> Jet {
        jet_of(q, |x| self.position_generic(x))
    }
    fn position(&self, q: [f64; 3]) -> V3 {
        self.position_generic(q)
    }
    /// As for the face-milling head: r_s × r_θ points out of the tooth for
    /// the outside blade (σ = +1), into it for the inside blade. The
    /// indexing only reduces the blade's speed along the trace (the
    /// relative angular velocity is ω₀(1 + z₀/z_p), same sense), so the
    /// orientation is the head's.
    fn normal_orientation(&self) -> f64 {
        self.profile.sigma()
    }
    fn is_generated(&self) -> bool {
        self.settings.machine.generated
    }
}

/// The extended epicycloid in the crown-gear plane (origin at the crown
/// gear's centre, the cradle axis): the path of a point at distance
/// `point_radius` from the cutter centre, at angle `point_phase` in the
/// head, when the cutter turns by τ about its centre C (at `centre_distance`
/// M and angle `centre_angle`) and the crown gear by −(z₀/z_p) τ:
/// E(τ) = Rot(τ z₀/z_p) (C + r (cos(τ + α₀), sin(τ + α₀))) in the crown
/// gear's frame. Rolling circles ρ_b = M z_p/(z_p + z₀) and M z₀/(z_p + z₀)
/// (ISO 23509 clause 6.3).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExtendedEpicycloid {
    pub centre_distance: f64,
    pub centre_angle: f64,
    pub point_radius: f64,
    pub point_phase: f64,
    /// z₀/z_p.
    pub ratio: f64,
}

impl ExtendedEpicycloid {
    /// E(τ) and E′(τ).
    pub fn point(&self, tau: f64) -> ([f64; 2], [f64; 2]) {
        let (sc, cc) = self.centre_angle.sin_cos();
        let (sp, cp) = (tau + self.point_phase).sin_cos();
        let r = self.point_radius;
        let m = self.centre_distance;
        let p = [m * cc + r * cp, m * sc + r * sp];
        let dp = [-r * sp, r * cp];
        let a = tau * self.ratio;
        let (sa, ca) = a.sin_cos();
        let rot = |v: [f64; 2]| [ca * v[0] - sa * v[1], sa * v[0] + ca * v[1]];
        let e = rot(p);
        let de = rot(dp);
        // d/dτ of Rot(kτ) p = k J Rot p + Rot p′
        let k = self.ratio;
        ([e[0], e[1]], [de[0] - k * e[1], de[1] + k * e[0]])
    }

    /// Base circle radius ρ_b of the crown gear's rolling circle.
    pub fn base_radius(&self) -> f64 {
        self.centre_distance / (1.0 + self.ratio)
    }

    /// τ where |E(τ)| = `radius`, by bounded Newton from `tau0` (≤ 50
    /// steps); None if it does not converge.
    pub fn at_radius(&self, radius: f64, tau0: f64) -> Option<f64> {
        let mut tau = tau0;
        for _ in 0..50 {
            let (e, de) = self.point(tau);
            let g = e[0].hypot(e[1]) - radius;
            let dg = (e[0] * de[0] + e[1] * de[1]) / e[0].hypot(e[1]);
            if g.abs() < 1e-13 * radius.max(1.0) {
                return Some(tau);
            }
            if !(dg.is_finite() && dg != 0.0) {
                return None;
            }
            tau -= (g / dg).clamp(-0.2, 0.2);
        }
        None
    }

    /// Spiral angle at E(τ): the angle between the curve's tangent and the
    /// radial direction from the crown centre (rad, in [0, π/2]).
    pub fn spiral_angle(&self, tau: f64) -> f64 {
        let (e, de) = self.point(tau);
        let c = (e[0] * de[0] + e[1] * de[1]).abs() / (e[0].hypot(e[1]) * de[0].hypot(de[1]));
        c.clamp(0.0, 1.0).acos()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::bevel::cutter::BladeSide;

    fn machine() -> MachineSettings {
        let delta: f64 = 1.1;
        MachineSettings {
            radial_distance: 70.0,
            cradle_angle: 0.9,
            machine_root_angle: delta,
            sliding_base: 4.0,
            blank_offset: 0.0,
            machine_center_to_back: 0.0,
            ratio_of_roll: delta.sin(),
            modified_roll: (0.0, 0.0),
            tilt: 0.05,
            swivel: 0.3,
            generated: true,
        }
    }

    fn blade() -> HobbingBlade {
        HobbingBlade {
            blade: Blade {
                side: BladeSide::Outside,
                point_radius: 60.0,
                pressure_angle: 0.35,
                edge_radius: 0.8,
                toprem: None,
                curvature_radius: None,
                height: 10.0,
            },
            offset: 20.0,
            phase: 0.2,
        }
    }

    fn map() -> FaceHobbing {
        let s = FaceHobbingSettings {
            machine: machine(),
            blade_groups: 5,
            work_teeth: 37,
        };
        FaceHobbing::new(s, blade()).unwrap()
    }

    /// The exact jet against central differences of the position.
    #[test]
    fn jet_matches_central_differences() {
        let m = map();
        let q = [3.0, 0.4, 0.05];
        let j = m.jet(q);
        let h = 1e-5;
        for k in 0..3 {
            let (mut qp, mut qm) = (q, q);
            qp[k] += h;
            qm[k] -= h;
            let (jp, jm) = (m.jet(qp), m.jet(qm));
            for c in 0..3 {
                let fd = (jp.r[c] - jm.r[c]) / (2.0 * h);
                assert!((fd - j.d1[k][c]).abs() < 1e-6, "d1 {k} {c}");
                for l in 0..3 {
                    let fd2 = (jp.d1[l][c] - jm.d1[l][c]) / (2.0 * h);
                    assert!((fd2 - j.d2[k][l][c]).abs() < 1e-5, "d2 {k} {l}");
                }
            }
        }
    }

    /// Continuous indexing: turning the cutter by one blade-group pitch
    /// Δ = 2π/z₀ brings the blade to where the next group's blade (phase
    /// + Δ) was at θ, with the work turned by one tooth pitch −2π/z.
    #[test]
    fn one_group_pitch_indexes_one_tooth() {
        let mut m = map();
        m.settings.machine.generated = false;
        let dl = 2.0 * std::f64::consts::PI / 5.0;
        let mut next = m;
        next.blade.phase += dl;
        let a = next.position([2.0, 0.3, 0.0]);
        let b = m.position([2.0, 0.3 + dl, 0.0]);
        let t = -2.0 * std::f64::consts::PI / 37.0;
        let rot = [
            a[0] * t.cos() - a[1] * t.sin(),
            a[0] * t.sin() + a[1] * t.cos(),
            a[2],
        ];
        for c in 0..3 {
            assert!((rot[c] - b[c]).abs() < 1e-10, "{rot:?} {b:?}");
        }
    }

    /// The closed-form derivative of the epicycloid and its base circle.
    #[test]
    fn epicycloid_derivative_and_base() {
        let e = ExtendedEpicycloid {
            centre_distance: 90.0,
            centre_angle: 0.7,
            point_radius: 60.0,
            point_phase: 0.3,
            ratio: 0.12,
        };
        let h = 1e-6;
        let (_, d) = e.point(0.4);
        let (p, _) = e.point(0.4 + h);
        let (m, _) = e.point(0.4 - h);
        for c in 0..2 {
            assert!(((p[c] - m[c]) / (2.0 * h) - d[c]).abs() < 1e-6);
        }
        assert!((e.base_radius() * (1.0 + 0.12) - 90.0).abs() < 1e-12);
        let t = e.at_radius(100.0, 0.0).unwrap();
        let (x, _) = e.point(t);
        assert!((x[0].hypot(x[1]) - 100.0).abs() < 1e-10);
    }

    #[test]
    fn bad_settings_name_the_key() {
        let s = FaceHobbingSettings {
            machine: machine(),
            blade_groups: 0,
            work_teeth: 37,
        };
        let e = FaceHobbing::new(s, blade()).unwrap_err().to_string();
        assert!(e.contains("blade_groups"), "{e}");
        let mut s = FaceHobbingSettings {
            blade_groups: 5,
            ..s
        };
        s.machine.ratio_of_roll = 0.0;
        let e = FaceHobbing::new(s, blade()).unwrap_err().to_string();
        assert!(e.contains("ratio_of_roll"), "{e}");
    }
}
