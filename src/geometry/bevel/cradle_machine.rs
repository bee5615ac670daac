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

use num_dual::{Dual2_64, DualNum};

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
    /// Precomputed: tilt matrix, work-frame basis B (columns), apex A,
    /// the cutter centre in the cradle plane.
    tilt: [[f64; 3]; 3],
    centre: (f64, f64),
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
        let (sq, cq) = settings.cradle_angle.sin_cos();
        Ok(CradleGeneration {
            settings,
            tool,
            centre: (settings.radial_distance * cq, settings.radial_distance * sq),
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

impl CradleGeneration {
    /// The jet by the dual-number chain ([`jet_of`] on
    /// [`Self::position_generic`]): the reference for [`Self::cutter_jet`].
    pub fn dual_jet(&self, q: [f64; 3]) -> Jet {
        jet_of(q, |x| self.position_generic(x))
    }

    /// The jet of a cutter tool in closed form (f64 arithmetic, a tenth of
    /// the dual chain's cost). With P(s, θ) = (ρ(s) cos θ, ρ(s) sin θ, h(s))
    /// the blade point on the cutter, p = T P + c the cradle point (T the
    /// tilt, c the cutter centre) and the chain r = R_z(φ) Bᵀ (R_z(ψ) p − a)
    /// of [`Self::to_work`], write g(x) = R_z(φ) Bᵀ R_z(ψ) x and
    /// J = ∂R_z/∂angle · R_zᵀ (J x = k × x). Then
    /// r_s = g(T P_s), r_θ = g(T P_θ) (and their s, θ derivatives with
    /// P_ss, P_sθ, P_θθ), r_ψ = φ′ J r + g(J p),
    /// r_sψ = φ′ J r_s + g(J T P_s) (θ likewise),
    /// r_ψψ = φ″ J r + φ′² J J r + 2 φ′ J g(J p) + g(J J p)
    /// (with r here relative to the rotation axis: J acts on the whole
    /// work-frame vector, so the apex term is included). ρ, h and φ with
    /// their derivatives come from scalar second-order duals. A formate
    /// member (no roll) has ψ = 0 and no ψ derivatives. None for a plane
    /// tool.
    pub fn cutter_jet(&self, q: [f64; 3]) -> Option<Jet> {
        let CradleTool::Cutter { profile, .. } = &self.tool else {
            return None;
        };
        let sd = Dual2_64::from_re(q[0]).derivative();
        let (rho_d, h_d) = profile.profile(sd);
        let (rho, rho1, rho2) = (rho_d.re, rho_d.v1, rho_d.v2);
        let (h, h1, h2) = (h_d.re, h_d.v1, h_d.v2);
        let (st, ct) = q[1].sin_cos();
        let pp = [rho * ct, rho * st, h];
        let ps = [rho1 * ct, rho1 * st, h1];
        let pt = [-rho * st, rho * ct, 0.0];
        let pss = [rho2 * ct, rho2 * st, h2];
        let pst = [-rho1 * st, rho1 * ct, 0.0];
        let ptt = [-rho * ct, -rho * st, 0.0];
        let tilt = |x: V3| -> V3 {
            let m = &self.tilt;
            std::array::from_fn(|i| m[i][0] * x[0] + m[i][1] * x[1] + m[i][2] * x[2])
        };
        let tp = tilt(pp);
        let p = [tp[0] + self.centre.0, tp[1] + self.centre.1, tp[2]];
        let (tps, tpt, tpss, tpst, tptt) = (tilt(ps), tilt(pt), tilt(pss), tilt(pst), tilt(ptt));
        let generated = self.settings.generated;
        let psi = if generated { q[2] } else { 0.0 };
        let phi_d = self
            .settings
            .work_rotation(Dual2_64::from_re(psi).derivative());
        let (phi, phi1, phi2) = if generated {
            (phi_d.re, phi_d.v1, phi_d.v2)
        } else {
            (phi_d.re, 0.0, 0.0)
        };
        let (sp, cp) = psi.sin_cos();
        let (sf, cf) = phi.sin_cos();
        let b = &self.basis;
        // g(x) = R_z(φ) Bᵀ R_z(ψ) x (a vector: no apex)
        let g = |x: V3| -> V3 {
            let m = [x[0] * cp - x[1] * sp, x[0] * sp + x[1] * cp, x[2]];
            let w: V3 = std::array::from_fn(|k| m[0] * b[k][0] + m[1] * b[k][1] + m[2] * b[k][2]);
            [w[0] * cf - w[1] * sf, w[0] * sf + w[1] * cf, w[2]]
        };
        let jz = |x: V3| -> V3 { [-x[1], x[0], 0.0] };
        let a = self.apex;
        let gp = g(p);
        let ga = g_apex(self, phi, a);
        let r = [gp[0] - ga[0], gp[1] - ga[1], gp[2] - ga[2]];
        let rs = g(tps);
        let rt = g(tpt);
        let zero = [0.0; 3];
        let lin =
            |u: V3, k: f64, v: V3| -> V3 { [u[0] + k * v[0], u[1] + k * v[1], u[2] + k * v[2]] };
        let (rpsi, rspsi, rtpsi, rpp) = if generated {
            let gjp = g(jz(p));
            let rpsi = lin(gjp, phi1, jz(r));
            let rspsi = lin(g(jz(tps)), phi1, jz(rs));
            let rtpsi = lin(g(jz(tpt)), phi1, jz(rt));
            let jr = jz(r);
            let mut rpp = g(jz(jz(p)));
            rpp = lin(rpp, 2.0 * phi1, jz(gjp));
            rpp = lin(rpp, phi1 * phi1, jz(jr));
            rpp = lin(rpp, phi2, jr);
            (rpsi, rspsi, rtpsi, rpp)
        } else {
            (zero, zero, zero, zero)
        };
        Some(Jet {
            r,
            d1: [rs, rt, rpsi],
            d2: [
                [g(tpss), g(tpst), rspsi],
                [g(tpst), g(tptt), rtpsi],
                [rspsi, rtpsi, rpp],
            ],
        })
    }
}

/// R_z(φ) Bᵀ a: the apex term of the chain (its ψ-dependence is through φ
/// only, which the J terms of [`CradleGeneration::cutter_jet`] carry).
fn g_apex(m: &CradleGeneration, phi: f64, a: V3) -> V3 {
    let b = &m.basis;
    let w: V3 = std::array::from_fn(|k| a[0] * b[k][0] + a[1] * b[k][1] + a[2] * b[k][2]);
    let (sf, cf) = phi.sin_cos();
    [w[0] * cf - w[1] * sf, w[0] * sf + w[1] * cf, w[2]]
}

impl EnvelopeMap for CradleGeneration {
    /// Closed form for a cutter ([`CradleGeneration::cutter_jet`]), the
    /// dual chain for a plane tool.
    fn jet(&self, q: [f64; 3]) -> Jet {
        self.cutter_jet(q).unwrap_or_else(|| self.dual_jet(q))
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
    /// The blade from the tip-plane end of its edge radius to its top.
    fn tool_range(&self) -> Option<(f64, f64)> {
        match &self.tool {
            CradleTool::Cutter { profile, .. } => Some((profile.s_min, profile.s_max)),
            CradleTool::Plane { .. } => None,
        }
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

    /// The closed-form cutter jet equals the dual-number chain's (value,
    /// first and second derivatives) to 1e-12 relative, on every piece of
    /// the blade (edge radius, straight part, toprem, blade curvature),
    /// with tilt, swivel, offsets and modified roll, generated and formate.
    #[test]
    fn closed_form_jet_equals_dual_jet() {
        use crate::geometry::bevel::cutter::Toprem;
        let mut st = settings(0.9, 0.85);
        st.tilt = 0.12;
        st.swivel = -0.7;
        st.blank_offset = 3.5;
        st.machine_center_to_back = -2.0;
        st.sliding_base = 4.0;
        st.modified_roll = (0.05, -0.3);
        for generated in [true, false] {
            st.generated = generated;
            for (side, rp, toprem, curv) in [
                (BladeSide::Inside, 70.0, None, None),
                (
                    BladeSide::Outside,
                    80.0,
                    Some(Toprem {
                        angle: 0.1,
                        height: 1.5,
                    }),
                    Some(-300.0),
                ),
            ] {
                let blade = Blade {
                    side,
                    point_radius: rp,
                    pressure_angle: 0.35,
                    edge_radius: 1.0,
                    toprem,
                    curvature_radius: curv,
                    height: 10.0,
                };
                let m = CradleGeneration::with_blade(st, blade).unwrap();
                let (lo, hi) = m.tool_range().unwrap();
                for k in 0..=12 {
                    let sq = lo + (hi - lo) * (k as f64 + 0.37) / 13.0;
                    for q in [[sq, 0.3, 0.0], [sq, -0.8, 0.21], [sq, 1.9, -0.4]] {
                        let a = m.cutter_jet(q).unwrap();
                        let b = m.dual_jet(q);
                        let scale = norm(b.r);
                        let mut worst = norm(sub(a.r, b.r));
                        for i in 0..3 {
                            worst = worst.max(norm(sub(a.d1[i], b.d1[i])));
                            for j in 0..3 {
                                worst = worst.max(norm(sub(a.d2[i][j], b.d2[i][j])));
                            }
                        }
                        assert!(
                            worst <= 1e-12 * scale,
                            "{generated} {side:?} q {q:?}: {worst:e}"
                        );
                    }
                }
            }
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

    /// The exact jet of the full chain (tilt, swivel, offset, machine
    /// centre to back, modified roll; Toprem and curved blade) against
    /// central differences.
    #[test]
    fn full_chain_jet_matches_differences() {
        let mut s = settings(0.9, 0.85);
        s.tilt = 0.05;
        s.swivel = 0.4;
        s.blank_offset = 3.0;
        s.machine_center_to_back = -1.5;
        s.sliding_base = 0.7;
        s.modified_roll = (0.02, -0.3);
        let blade = Blade {
            side: BladeSide::Outside,
            point_radius: 80.0,
            pressure_angle: 0.35,
            edge_radius: 1.0,
            toprem: Some(crate::geometry::bevel::cutter::Toprem {
                angle: 0.05,
                height: 2.0,
            }),
            curvature_radius: Some(300.0),
            height: 10.0,
        };
        let m = CradleGeneration::with_blade(s, blade).unwrap();
        for q in [[5.0, 0.3, 0.1], [-0.4, 0.2, -0.05], [1.0, -0.1, 0.2]] {
            let j = m.jet(q);
            let h = 1e-5;
            for k in 0..3 {
                let (mut qp, mut qm) = (q, q);
                qp[k] += h;
                qm[k] -= h;
                let (jp, jm) = (m.jet(qp), m.jet(qm));
                for c in 0..3 {
                    let fd = (jp.r[c] - jm.r[c]) / (2.0 * h);
                    assert!((fd - j.d1[k][c]).abs() < 1e-6, "d1 {k} {c} at {q:?}");
                    for l in 0..3 {
                        let fd2 = (jp.d1[l][c] - jm.d1[l][c]) / (2.0 * h);
                        assert!(
                            (fd2 - j.d2[k][l][c]).abs() < 1e-5,
                            "d2 {k} {l} {c} at {q:?}"
                        );
                    }
                }
            }
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
