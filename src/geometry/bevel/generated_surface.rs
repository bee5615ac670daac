//! A face-milled (Gleason) bevel or hypoid flank generated on the cradle
//! machine, as a [`ToothSurface`].
//!
//! **Frame** (the work's own): axis +z, origin at the member's pitch-cone
//! apex, +z from the apex toward the heel (a pitch-cone point at cone
//! distance R has z = R cos δ and radius R sin δ). **Tooth 0** is centred
//! on the +y side of the axis: the machine cuts the tooth space centred on
//! +y at zero roll (`cradle_machine`), and each flank is turned by ±π/z
//! about +z onto the tooth on whose side it lies.
//!
//! **Parameters**: the axial-section ("rotated projection") coordinates of
//! [`crate::geometry::bevel::generation`]: v = cone distance along the
//! pitch-cone generatrix (toe R_i → heel R_e), u = distance perpendicular to
//! it in the axial plane (root → tip, 0 on the pitch cone); u_tip(v) is the
//! face-cone line, u_root(v) the root-cone line lifted by 0.005 ρ_f (the
//! root cone touches the fillet tangentially, where the axial section is
//! singular; a formate member's root is its blade-tip trace), u_form(v)
//! where the blade's edge radius (the fillet) ends. The normal is the unit outward normal
//! (out of the tooth's material).
//!
//! The concave flank is cut by the outside blade, the convex flank by the
//! inside blade (`cutter`).

use crate::error::{FlankError, Result};
use crate::geometry::bevel::cradle_machine::{CradleGeneration, MachineSettings};
use crate::geometry::bevel::cutter::{Blade, BladeSide};
use crate::geometry::bevel::generation::{
    solve_axial, AxialSection, EnvelopeError, EnvelopeFlank, EnvelopeMap, SolveOptions,
};
use crate::geometry::surface::ToothSurface;
use crate::geometry::vec3::{cross, dot, norm, unit, V3};

/// Angle (rad) up the blade's edge radius from its tangency with the tip
/// plane where the flank's parameter domain starts (see
/// [`GeneratedFlank::new`]): the last ρ_f (1 − cos 0.1) = 0.005 ρ_f of
/// fillet depth above the root cone is left out.
pub const ROOT_ARC_ANGLE: f64 = 0.1;

/// Which flank of a tooth.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FlankKind {
    /// Cut by the outside blade.
    Concave,
    /// Cut by the inside blade.
    Convex,
}

impl FlankKind {
    pub fn blade_side(self) -> BladeSide {
        match self {
            FlankKind::Concave => BladeSide::Outside,
            FlankKind::Convex => BladeSide::Inside,
        }
    }
}

/// One generated (or formate) flank (module docs).
#[derive(Debug)]
pub struct GeneratedFlank {
    surface: EnvelopeFlank<CradleGeneration>,
    pub kind: FlankKind,
    pub teeth: u32,
}

/// What a flank measures at one point, in the pitch cone's terms.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlankMeasure {
    /// Distance from the apex (mm).
    pub cone_distance: f64,
    /// Spiral angle: between the lengthwise tangent (the flank's tangent
    /// plane ∩ the pitch cone's tangent plane) and the generatrix (rad,
    /// ≥ 0).
    pub spiral_angle: f64,
    /// +1 if the lengthwise curve turns about +z with growing cone
    /// distance (right hand, seen from the apex side), −1 otherwise.
    pub hand_sign: f64,
    /// Normal pressure angle: between the flank normal and the pitch
    /// cone's tangent plane (rad).
    pub pressure_angle: f64,
}

fn describe(settings: &MachineSettings, e: &EnvelopeError, what: &str) -> FlankError {
    FlankError::Model(format!(
        "{what}: {e}; machine settings radial_distance {:.4}, cradle_angle {:.6}, \
         machine_root_angle {:.6}, sliding_base {:.4}, blank_offset {:.4}, \
         machine_center_to_back {:.4}, ratio_of_roll {:.6}, modified_roll {:?}, tilt {:.6}, \
         swivel {:.6} do not generate this flank over its blank",
        settings.radial_distance,
        settings.cradle_angle,
        settings.machine_root_angle,
        settings.sliding_base,
        settings.blank_offset,
        settings.machine_center_to_back,
        settings.ratio_of_roll,
        settings.modified_roll,
        settings.tilt,
        settings.swivel,
    ))
}

impl GeneratedFlank {
    /// The flank of `kind` cut by `blade` on a machine with `settings`,
    /// over the blank's axial `section`, of a member with `teeth` teeth.
    /// `q_start` is a guess of (s, θ, ψ) at the mean point (u = 0,
    /// v = R_m). Errs, naming the settings, if the surface is not generated
    /// over the whole blank (undercut, singular meshing, no convergence).
    pub fn new(
        settings: MachineSettings,
        blade: Blade,
        kind: FlankKind,
        section: AxialSection,
        teeth: u32,
        q_start: [f64; 3],
    ) -> Result<Self> {
        if blade.side != kind.blade_side() {
            return Err(FlankError::Model(format!(
                "{kind:?} flank needs the {:?} blade, got {:?}",
                kind.blade_side(),
                blade.side
            )));
        }
        if teeth < 3 {
            return Err(FlankError::Model(format!("teeth {teeth} < 3")));
        }
        let map = CradleGeneration::with_blade(settings, blade)?;
        // the root cone touches the generated fillet tangentially, where the
        // axial-section parametrisation is singular (the circle z, ρ grazes
        // the surface): the flank's root line is lifted to where the edge
        // radius has turned ROOT_ARC_ANGLE from the tip plane
        let mut section = section;
        section.root.u_mean += blade.edge_radius * (1.0 - ROOT_ARC_ANGLE.cos());
        let opt = SolveOptions::default();
        let what = format!("{kind:?} flank");
        // which side of the space the flank lies on decides the tooth
        let (z, rho) = section.target(0.0, section.mean_cone_distance).0;
        let mean = solve_axial(&map, z, rho, q_start, &opt)
            .map_err(|e| describe(&settings, &e, &format!("{what}, mean point")))?;
        let ang = mean.jet.r[1].atan2(mean.jet.r[0]) - std::f64::consts::FRAC_PI_2;
        let placement = -ang.signum() * std::f64::consts::PI / teeth as f64;
        let form = match map.tool {
            crate::geometry::bevel::cradle_machine::CradleTool::Cutter { profile, .. } => {
                Some(profile.form_parameter())
            }
            _ => None,
        };
        // a formate member's root is the trace of the blade tip (the cutter
        // does not sweep the root cone): the blade line 0.1 rad up the edge
        // radius from its tangency with the tip plane (where the axial
        // section meets the surface transversally), 400 samples across the
        // face
        let root_curve = match (settings.generated, map.tool) {
            (false, crate::geometry::bevel::cradle_machine::CradleTool::Cutter { profile, .. }) => {
                let s_root = profile.s_min + ROOT_ARC_ANGLE * profile.rho_f();
                let (sd, cd) = section.pitch_angle.sin_cos();
                let mut pts: Vec<(f64, f64)> = (0..=400)
                    .map(|k| {
                        let th = mean.q[1] - 0.6 + 1.2 * k as f64 / 400.0;
                        let r = map.position([s_root, th, 0.0]);
                        let (z, rho) = (r[2], r[0].hypot(r[1]));
                        (z * cd + rho * sd, -z * sd + rho * cd)
                    })
                    .filter(|p| p.0.is_finite() && p.1.is_finite())
                    .collect();
                pts.sort_by(|a, b| a.0.total_cmp(&b.0));
                Some(pts)
            }
            _ => None,
        };
        let surface =
            EnvelopeFlank::with_root_curve(map, section, placement, form, mean.q, opt, root_curve)
                .map_err(|e| describe(&settings, &e, &what))?;
        Ok(GeneratedFlank {
            surface,
            kind,
            teeth,
        })
    }

    /// The envelope surface behind the flank (for its solver details).
    pub fn envelope(&self) -> &EnvelopeFlank<CradleGeneration> {
        &self.surface
    }

    /// The machine settings.
    pub fn settings(&self) -> &MachineSettings {
        &self.surface.map().settings
    }

    /// Point, normal, r_u, r_v, or the solver's error naming the settings.
    pub fn try_evaluate(&self, u: f64, v: f64) -> Result<(V3, V3, V3, V3)> {
        self.surface.try_evaluate(u, v).map_err(|e| {
            describe(
                self.settings(),
                &e,
                &format!("{:?} flank at u {u}, v {v}", self.kind),
            )
        })
    }

    /// The dimensionless meshing residual at (u, v).
    pub fn meshing_residual(&self, u: f64, v: f64) -> Result<f64> {
        self.surface
            .meshing_residual(u, v)
            .map_err(|e| describe(self.settings(), &e, &format!("{:?} flank", self.kind)))
    }

    /// Spiral angle, pressure angle and cone distance measured on the
    /// surface at (u, v) (see [`FlankMeasure`]).
    pub fn measure(&self, u: f64, v: f64) -> Result<FlankMeasure> {
        let (p, n, _, _) = self.try_evaluate(u, v)?;
        Ok(FlankMeasure::on_pitch_cone(
            p,
            n,
            self.surface.section().pitch_angle,
        ))
    }
}

impl FlankMeasure {
    /// The figures of a flank point `p` with unit normal `n` on a member
    /// of pitch angle `delta` (own frame, apex at the origin): the
    /// lengthwise tangent is the flank's tangent plane ∩ the pitch cone's
    /// tangent plane at p's angular position.
    pub fn on_pitch_cone(p: V3, n: V3, delta: f64) -> Self {
        let rho = p[0].hypot(p[1]);
        let e_rho = [p[0] / rho, p[1] / rho, 0.0];
        let (sd, cd) = delta.sin_cos();
        // pitch-cone generatrix and normal at the point's angular position
        let e_g = [sd * e_rho[0], sd * e_rho[1], cd];
        let e_n = [cd * e_rho[0], cd * e_rho[1], -sd];
        let t = unit(cross(n, e_n));
        let t = if dot(t, e_g) < 0.0 {
            [-t[0], -t[1], -t[2]]
        } else {
            t
        };
        let e_phi = [-e_rho[1], e_rho[0], 0.0];
        FlankMeasure {
            cone_distance: norm(p),
            spiral_angle: dot(t, e_g).clamp(-1.0, 1.0).acos(),
            hand_sign: dot(t, e_phi).signum(),
            pressure_angle: dot(n, e_n).abs().clamp(0.0, 1.0).asin(),
        }
    }
}

impl ToothSurface for GeneratedFlank {
    fn u_range(&self) -> (f64, f64) {
        self.surface.u_range()
    }
    fn v_range(&self) -> (f64, f64) {
        self.surface.v_range()
    }
    fn u_tip(&self, v: f64) -> f64 {
        self.surface.u_tip(v)
    }
    fn u_form(&self, v: f64) -> f64 {
        self.surface.u_form(v)
    }
    fn u_root(&self, v: f64) -> f64 {
        self.surface.u_root(v)
    }
    fn point(&self, u: f64, v: f64) -> V3 {
        self.surface.point(u, v)
    }
    fn normal(&self, u: f64, v: f64) -> V3 {
        self.surface.normal(u, v)
    }
    fn derivatives(&self, u: f64, v: f64) -> (V3, V3) {
        self.surface.derivatives(u, v)
    }
    fn evaluate(&self, u: f64, v: f64) -> (V3, V3, V3, V3) {
        self.surface.evaluate(u, v)
    }
    fn evaluate_checked(&self, u: f64, v: f64) -> Option<(V3, V3, V3, V3)> {
        self.surface.evaluate_checked(u, v)
    }
}

/// The map of a flank (for checks that need the raw jet).
pub fn flank_map(f: &GeneratedFlank) -> &impl EnvelopeMap {
    f.surface.map()
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use super::*;
    use crate::geometry::bevel::machine_settings::{
        member_setup, CutterChoice, Member, MemberBlank,
    };
    use crate::geometry::bevel::{blank_design, BlankInputs};
    use crate::geometry::rotated::RotatedSurface;
    use crate::geometry::Hand;

    /// `evaluate_checked` is `evaluate` where the flank's solve converges
    /// and `None` where it errs (a parameter far beyond the tip, off the
    /// blade), where `evaluate` returns a fallback point; a turned copy
    /// forwards both, turned.
    #[test]
    fn checked_evaluation_is_none_off_the_generated_flank() {
        let f2 = r#"{"method": 0, "Sigma_deg": 90, "a_mm": 0, "z1": 14, "z2": 39, "de2_mm": 176.893, "b2_mm": 25.4, "beta_m2_deg": 35.0, "rc0_mm": 114.3, "data_type": "II", "alpha_dD_deg": 20, "alpha_dC_deg": 20, "f_alim": 0, "c_ham": 0.24737, "k_d": 2.0, "k_c": 0.125, "k_t": 0.0915, "backlash": "outer normal jen 0.127", "theta_a2_deg": 2.1342, "theta_f2_deg": 6.4934}"#;
        let design = blank_design(&BlankInputs::from_json(f2).unwrap()).unwrap();
        let blank = MemberBlank::from_design(&design, Member::Gear).unwrap();
        let cutter = CutterChoice {
            mean_radius: 114.3,
            edge_radius: 0.6,
            blade_height: None,
        };
        let setup = member_setup(&blank, Hand::Left, &cutter, true).unwrap();
        let flank = Arc::new(setup.flank(FlankKind::Convex).unwrap());
        let v = blank.mean_cone_distance;
        let on = flank
            .evaluate_checked(0.0, v)
            .expect("the mean point is on the flank");
        assert_eq!(on, flank.evaluate(0.0, v));
        let far = 50.0;
        assert!(flank.try_evaluate(far, v).is_err());
        assert!(flank.evaluate_checked(far, v).is_none());
        let turned = RotatedSurface::new(flank.clone(), 0.3);
        let t = turned.evaluate_checked(0.0, v).unwrap();
        assert_eq!(t, turned.evaluate(0.0, v));
        assert!(turned.evaluate_checked(far, v).is_none());
    }
}
