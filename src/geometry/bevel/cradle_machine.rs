//! The generating cradle machine (Gleason-type hypoid generator): machine
//! settings and the kinematic chain q = (s, θ, ψ) ↦ r(q) in the work frame.
//!
//! The settings and the chain follow the structure of Litvin & Fuentes,
//! *Gear Geometry and Applied Theory*, 2nd ed., §20.4–20.5 (Figs. 20.4.x:
//! machine frame S_m, cradle S_c, cutter head, work S_w; cradle angle q,
//! radial distance S_r, machine root angle γ_m, sliding base ΔX_B, blank
//! offset E_m, machine centre to back ΔX_G, ratio of roll m_cw) and of
//! Litvin, Zhang et al., NASA CR-4342 (1991) §2 for tilt and modified roll.
//! The signs are this module's own and are stated here:
//!
//! * **machine frame** S_m: z_m is the cradle axis; the cradle plane z_m = 0
//!   is the cutter's tip plane (the plane that generates the root); the
//!   blades extend toward +z_m; the work body is below (z_m < 0);
//! * **cradle**: rotates by the roll ψ about z_m. In the cradle frame the
//!   cutter centre is at (S_r cos q, S_r sin q, 0);
//! * **cutter head**: its axis is +z_m, tilted by i about the axis
//!   (cos j, sin j, 0) of the cradle plane (swivel j; the tilt rotation is
//!   Rot_z(j) Rot_x(i) Rot_z(−j)); the blade point r_c(s, θ) is given by
//!   [`crate::geometry::bevel::cutter`];
//! * **work**: its axis d = (cos γ_m, 0, −sin γ_m) (below the cradle plane
//!   by the machine root angle), its pitch apex (origin of the work frame)
//!   at A = E_m e_y + ΔX_B e_z + ΔX_G d. At zero roll the work frame's axes
//!   are x_w = e_y, y_w = (sin γ_m, 0, cos γ_m), z_w = d, so the generating
//!   line (the x_m axis) is on the work's +y side;
//! * **roll**: the work turns about −d by φ(ψ) = (ψ − C ψ² − D ψ³)/R_a,
//!   R_a = ω_cradle/ω_work the ratio of roll and 2C, 6D the modified-roll
//!   coefficients (Litvin & Fuentes eq. 20.5.x: the derivatives of the
//!   work rotation in ψ). For pure rolling of the pitch cone δ on the
//!   generating crown gear with apex at A: R_a = sin δ / cos(δ − γ_m).
//!
//! A point of the tool at (s, θ) and roll ψ in the work frame:
//! r(q) = Rot_z(φ(ψ)) Bᵀ (Rot_z(ψ) (C₀ + T_tilt r_c(s, θ)) − A), B = [x_w y_w z_w].
//! A **formate** work (not generated) takes ψ = 0 and no roll.
//!
//! Instead of the cutter, a **plane** tool (straight blade on a plane: the
//! infinite cutter radius) can be mounted on the cradle: the tooth of a
//! plane generating crown gear, used for the straight-bevel reduction.

use num_dual::DualNum;

use crate::error::{FlankError, Result};
use crate::geometry::bevel::cutter::{Blade, BladeProfile};
use crate::geometry::bevel::generation::{jet_of, EnvelopeMap, Jet};
use crate::geometry::vec3::{cross, norm, V3};

/// The settings of the generating machine (module docs for the frames).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MachineSettings {
    /// Radial distance S_r: cradle axis to cutter centre (mm).
    pub radial_distance: f64,
    /// Cradle angle q (rad).
    pub cradle_angle: f64,
    /// Machine root angle γ_m (rad).
    pub machine_root_angle: f64,
    /// Sliding base ΔX_B: work apex along the cradle axis (mm).
    pub sliding_base: f64,
    /// Blank offset E_m: work apex along y_m (mm).
    pub blank_offset: f64,
    /// Machine centre to back ΔX_G: work apex along the work axis (mm).
    pub machine_center_to_back: f64,
    /// Ratio of roll R_a = ω_cradle / ω_work.
    pub ratio_of_roll: f64,
    /// Modified-roll coefficients (2C, 6D): φ = (ψ − C ψ² − D ψ³)/R_a.
    pub modified_roll: (f64, f64),
    /// Cutter tilt i and swivel j (rad).
    pub tilt: f64,
    pub swivel: f64,
    /// False: formate (no generating roll).
    pub generated: bool,
}

impl MachineSettings {
    /// Checks that every setting is finite and physical; the error names
    /// the setting.
    pub fn validate(&self) -> Result<()> {
        let named = [
            ("radial_distance", self.radial_distance),
            ("cradle_angle", self.cradle_angle),
            ("machine_root_angle", self.machine_root_angle),
            ("sliding_base", self.sliding_base),
            ("blank_offset", self.blank_offset),
            ("machine_center_to_back", self.machine_center_to_back),
            ("ratio_of_roll", self.ratio_of_roll),
            ("modified_roll 2C", self.modified_roll.0),
            ("modified_roll 6D", self.modified_roll.1),
            ("tilt", self.tilt),
            ("swivel", self.swivel),
        ];
        for (k, v) in named {
            if !v.is_finite() {
                return Err(FlankError::Model(format!(
                    "machine settings: {k} = {v} is not finite"
                )));
            }
        }
        if self.generated && !(self.ratio_of_roll > 1e-6) {
            return Err(FlankError::Model(format!(
                "machine settings: ratio_of_roll {} must be > 0 for a generated member",
                self.ratio_of_roll
            )));
        }
        if !(self.machine_root_angle.abs() < std::f64::consts::FRAC_PI_2) {
            return Err(FlankError::Model(format!(
                "machine settings: machine_root_angle {} outside (−90°, 90°)",
                self.machine_root_angle
            )));
        }
        if !(self.tilt.abs() < 1.0) {
            return Err(FlankError::Model(format!(
                "machine settings: tilt {} rad outside (−1, 1)",
                self.tilt
            )));
        }
        if !(self.radial_distance >= 0.0) {
            return Err(FlankError::Model(format!(
                "machine settings: radial_distance {} must be ≥ 0",
                self.radial_distance
            )));
        }
        Ok(())
    }

    /// Work rotation φ(ψ) (module docs).
    pub fn work_rotation<D: DualNum<Primitive = f64> + Copy>(&self, psi: D) -> D {
        let c = 0.5 * self.modified_roll.0;
        let d = self.modified_roll.1 / 6.0;
        (psi - psi * psi * c - psi * psi * psi * d) / self.ratio_of_roll
    }
}

/// The tool on the cradle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CradleTool {
    /// A cutter blade swept about the cutter axis: q = (s, θ).
    Cutter { blade: Blade, profile: BladeProfile },
    /// A plane generating crown-gear flank in the cradle frame: point
    /// `origin` + s·`profile_dir` + w·`lengthwise_dir` (q = (s, w));
    /// `orientation` = +1 if profile_dir × lengthwise_dir points out of
    /// the generated tooth.
    Plane {
        origin: V3,
        profile_dir: V3,
        lengthwise_dir: V3,
        orientation: f64,
    },
}

/// The kinematic chain of the cradle machine: an [`EnvelopeMap`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CradleGeneration {
    pub settings: MachineSettings,
    pub tool: CradleTool,
    /// Precomputed: tilt matrix, work-frame basis B (columns), apex A.
    tilt: [[f64; 3]; 3],
    basis: [V3; 3],
    apex: V3,
}

fn matvec<D: DualNum<Primitive = f64> + Copy>(m: &[[f64; 3]; 3], p: [D; 3]) -> [D; 3] {
    std::array::from_fn(|i| p[0] * m[i][0] + p[1] * m[i][1] + p[2] * m[i][2])
}

impl CradleGeneration {
    /// A cutter blade on the machine.
    pub fn with_blade(settings: MachineSettings, blade: Blade) -> Result<Self> {
        let profile = blade.profile()?;
        Self::new(settings, CradleTool::Cutter { blade, profile })
    }

    pub fn new(settings: MachineSettings, tool: CradleTool) -> Result<Self> {
        settings.validate()?;
        let (si, ci) = settings.tilt.sin_cos();
        let (sj, cj) = settings.swivel.sin_cos();
        // Rot_z(j) Rot_x(i) Rot_z(−j)
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
        let tilt = mul(mul(rz(sj, cj), rx), rz(-sj, cj));
        let (sg, cg) = settings.machine_root_angle.sin_cos();
        let d = [cg, 0.0, -sg];
        let basis = [[0.0, 1.0, 0.0], [sg, 0.0, cg], d];
        let apex = [
            settings.machine_center_to_back * d[0],
            settings.blank_offset + settings.machine_center_to_back * d[1],
            settings.sliding_base + settings.machine_center_to_back * d[2],
        ];
        if let CradleTool::Plane {
            profile_dir,
            lengthwise_dir,
            orientation,
            ..
        } = tool
        {
            if !(norm(cross(profile_dir, lengthwise_dir)) > 1e-9 && orientation.abs() == 1.0) {
                return Err(FlankError::Model(
                    "plane tool: profile and lengthwise directions are parallel".into(),
                ));
            }
        }
        Ok(CradleGeneration {
            settings,
            tool,
            tilt,
            basis,
            apex,
        })
    }

    /// The tool point in the cradle frame at tool parameters (s, t).
    pub fn cradle_point<D: DualNum<Primitive = f64> + Copy>(&self, s: D, t: D) -> [D; 3] {
        match &self.tool {
            CradleTool::Cutter { profile, .. } => {
                let (rho, h) = profile.profile(s);
                let pc = [rho * t.cos(), rho * t.sin(), h];
                let p = matvec(&self.tilt, pc);
                let (sq, cq) = self.settings.cradle_angle.sin_cos();
                let sr = self.settings.radial_distance;
                [p[0] + sr * cq, p[1] + sr * sq, p[2]]
            }
            CradleTool::Plane {
                origin,
                profile_dir,
                lengthwise_dir,
                ..
            } => std::array::from_fn(|k| s * profile_dir[k] + t * lengthwise_dir[k] + origin[k]),
        }
    }

    /// A cradle-frame point at roll ψ, in the work frame.
    pub fn to_work<D: DualNum<Primitive = f64> + Copy>(&self, p: [D; 3], psi: D) -> [D; 3] {
        let (sp, cp) = (psi.sin(), psi.cos());
        // machine frame, relative to the work apex
        let m = [
            p[0] * cp - p[1] * sp - self.apex[0],
            p[0] * sp + p[1] * cp - self.apex[1],
            p[2] - self.apex[2],
        ];
        // Bᵀ (m)
        let b = &self.basis;
        let w: [D; 3] = std::array::from_fn(|k| m[0] * b[k][0] + m[1] * b[k][1] + m[2] * b[k][2]);
        let phi = self.settings.work_rotation(psi);
        let (sf, cf) = (phi.sin(), phi.cos());
        [w[0] * cf - w[1] * sf, w[0] * sf + w[1] * cf, w[2]]
    }

    /// r(q) in the work frame (module docs); for a formate member ψ is
    /// ignored (held at 0).
    pub fn position_generic<D: DualNum<Primitive = f64> + Copy>(&self, q: [D; 3]) -> [D; 3] {
        let psi = if self.settings.generated {
            q[2]
        } else {
            q[2] * 0.0
        };
        self.to_work(self.cradle_point(q[0], q[1]), psi)
    }
}

impl EnvelopeMap for CradleGeneration {
    fn jet(&self, q: [f64; 3]) -> Jet {
        jet_of(q, |x| self.position_generic(x))
    }
    fn position(&self, q: [f64; 3]) -> V3 {
        self.position_generic(q)
    }
    /// The cutter's r_s × r_θ = ρ (−h′, ρ′) (radial, axial) points out of
    /// the work's tooth for the outside blade (σ = +1) and into it for the
    /// inside blade: orientation σ (cutter module docs).
    fn normal_orientation(&self) -> f64 {
        match &self.tool {
            CradleTool::Cutter { profile, .. } => profile.sigma(),
            CradleTool::Plane { orientation, .. } => *orientation,
        }
    }
    fn is_generated(&self) -> bool {
        self.settings.generated
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::bevel::cutter::BladeSide;
    use crate::geometry::vec3::{dot, sub};

    fn settings(delta: f64, gamma: f64) -> MachineSettings {
        MachineSettings {
            radial_distance: 80.0,
            cradle_angle: 0.9,
            machine_root_angle: gamma,
            sliding_base: 0.0,
            blank_offset: 0.0,
            machine_center_to_back: 0.0,
            ratio_of_roll: delta.sin() / (delta - gamma).cos(),
            modified_roll: (0.0, 0.0),
            tilt: 0.0,
            swivel: 0.0,
            generated: true,
        }
    }

    /// On the pitch element (the instantaneous axis of rolling) the
    /// relative velocity r_ψ of a tool point vanishes: checks the roll's
    /// sign and the ratio of roll formula.
    #[test]
    fn pitch_element_is_the_instantaneous_axis() {
        let (delta, gamma) = (0.9, 0.85);
        let s = settings(delta, gamma);
        // plane tool through the pitch element: points (t cos(δ−γ), 0,
        // t sin(δ−γ)) in the machine frame at ψ = 0
        let e = [(delta - gamma).cos(), 0.0, (delta - gamma).sin()];
        let tool = CradleTool::Plane {
            origin: [0.0; 3],
            profile_dir: [0.0, 1.0, 0.0],
            lengthwise_dir: e,
            orientation: 1.0,
        };
        let m = CradleGeneration::new(s, tool).unwrap();
        let j = m.jet([0.0, 60.0, 0.0]);
        assert!(norm(j.d1[2]) < 1e-12, "{:?}", j.d1[2]);
        // that point lies on the work's pitch cone: z = R cos δ, ρ = R sin δ
        assert!((j.r[2] - 60.0 * delta.cos()).abs() < 1e-12);
        assert!((j.r[0].hypot(j.r[1]) - 60.0 * delta.sin()).abs() < 1e-12);
        // on the +y side
        assert!(j.r[1] > 0.0 && j.r[0].abs() < 1e-12);
    }

    /// The cutter normal orientation: for each blade, σ (r_s × r_θ) points
    /// from the blade into the tooth space, i.e. toward the cutter's mean
    /// radius circle at the tip plane.
    #[test]
    fn orientation_points_into_the_space() {
        let s = settings(0.9, 0.85);
        for (side, rp) in [(BladeSide::Inside, 70.0), (BladeSide::Outside, 80.0)] {
            let blade = Blade {
                side,
                point_radius: rp,
                pressure_angle: 0.35,
                edge_radius: 1.0,
                toprem: None,
                curvature_radius: None,
                height: 10.0,
            };
            let m = CradleGeneration::with_blade(s, blade).unwrap();
            let j = m.jet([2.0, 0.3, 0.0]);
            let n = cross(j.d1[0], j.d1[1]);
            let n = [
                n[0] * m.normal_orientation(),
                n[1] * m.normal_orientation(),
                n[2] * m.normal_orientation(),
            ];
            // the same blade point with a radius toward the mean 75 mm
            let toward = m.to_work(
                {
                    let p = m.cradle_point(2.0, 0.3);
                    let c = [80.0 * 0.9f64.cos(), 80.0 * 0.9f64.sin(), 0.0];
                    let r = sub(p, c);
                    let k = 75.0 / r[0].hypot(r[1]);
                    [c[0] + r[0] * k, c[1] + r[1] * k, p[2]]
                },
                0.0,
            );
            assert!(dot(n, sub(toward, j.r)) > 0.0, "{side:?}");
        }
    }

    #[test]
    fn bad_settings_name_the_key() {
        let mut s = settings(0.9, 0.85);
        s.ratio_of_roll = 0.0;
        let blade = Blade {
            side: BladeSide::Inside,
            point_radius: 70.0,
            pressure_angle: 0.35,
            edge_radius: 1.0,
            toprem: None,
            curvature_radius: None,
            height: 10.0,
        };
        let e = CradleGeneration::with_blade(s, blade)
            .unwrap_err()
            .to_string();
        assert!(e.contains("ratio_of_roll"), "{e}");
        s.ratio_of_roll = 0.9;
        s.tilt = f64::NAN;
        let e = CradleGeneration::with_blade(s, blade)
            .unwrap_err()
            .to_string();
        assert!(e.contains("tilt"), "{e}");
    }
}
