//! Standard-consistent machine settings from the ISO 23509 blank: a
//! first-order (basic) design after Litvin & Fuentes, *Gear Geometry and
//! Applied Theory*, 2nd ed., ch. 20–21 (gear settings from the pitch cone,
//! mean cone distance, spiral angle and cutter radius; ratio of roll from
//! the generating crown gear), for the gear (generated or formate) and the
//! pinion by the same approach on the pinion's blank. Local synthesis (the
//! pinion's settings from a wanted contact) belongs to a later issue.
//!
//! For a member with pitch angle δ, mean cone distance R_m, mean addendum
//! h_am and dedendum h_fm, face and root angle increments θ_a, θ_f, mean
//! spiral angle β_m and mean cutter radius r_c (frames of `cradle_machine`):
//!
//! * machine root angle γ_m = δ − θ_f: the root cone's generatrix lies in
//!   the cradle (tip) plane, so the blade tips cut the blank's root cone;
//! * the mean root point (z_f, ρ_f) = (R_m cos δ + h_fm sin δ,
//!   R_m sin δ − h_fm cos δ), the root apex on the axis at
//!   z_A = z_f − ρ_f / tan γ_m; the pitch apex on the cradle axis and the
//!   root apex in the cradle plane give the sliding base ΔX_B = z_A sin γ_m
//!   (E_m = ΔX_G = 0), the mean root point at x_M = z_A cos γ_m + ρ_f/sin γ_m
//!   on the x_m axis;
//! * the cutter's mean tip circle (radius r_c) passes through the mean root
//!   point with its tangent at β_m to the root line: cutter centre
//!   C₀ = (x_M − r_c sin β_m, h r_c cos β_m), h = +1 left hand, −1 right
//!   hand (the mirror image y → −y: the spiral angle then grows from toe
//!   to heel on both hands, as ISO 23509 clause 7.6's β_e > β_i); S_r = |C₀|, q = atan2(C₀);
//! * ratio of roll R_a = sin δ / cos(δ − γ_m) (pure rolling of the pitch
//!   cone on the generating crown gear's pitch cone, apex at the pitch
//!   apex; Litvin & Fuentes §20.5); no modified roll, tilt or swivel;
//! * blades: point width W = e_mn − h_fm (tan α_cv + tan α_cc), the mean
//!   normal space width e_mn = π m_mn − s_mn less the flanks' spread down to
//!   the root; blade angles = the blank's generated pressure angles (drive
//!   side: pinion concave / gear convex, ISO 23509 §7.2); point radii
//!   r_c ∓ W/2.
//!
//! A formate member uses the same placement without roll.

use std::f64::consts::PI;

use crate::geometry::bevel::body::{angle_from_y, wrap_angle};

use crate::error::{FlankError, Result};
use crate::geometry::bevel::cradle_machine::MachineSettings;
use crate::geometry::bevel::cutter::{Blade, CutterHead};
use crate::geometry::bevel::generated_surface::{FlankKind, GeneratedFlank};
use crate::geometry::bevel::generation::{AxialSection, ConeLine};
use crate::geometry::bevel::BlankDesign;
use crate::geometry::Hand;

/// Which member of the pair.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Member {
    Pinion,
    Gear,
}

/// The cutter choices the blank does not fix.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CutterChoice {
    /// Mean cutter radius r_c (mm): usually the blank's r_c0.
    pub mean_radius: f64,
    /// Blade edge radius (mm).
    pub edge_radius: f64,
    /// Blade height above the tip plane (mm); None: 1.25 × the whole
    /// depth at the heel.
    pub blade_height: Option<f64>,
}

/// The blank data of one member that the settings use (mm, rad).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MemberBlank {
    pub teeth: u32,
    pub pitch_angle: f64,
    pub mean_cone_distance: f64,
    pub outer_cone_distance: f64,
    pub inner_cone_distance: f64,
    pub mean_addendum: f64,
    pub mean_dedendum: f64,
    /// θ_a, θ_f (rad).
    pub addendum_angle: f64,
    pub dedendum_angle: f64,
    pub spiral_angle: f64,
    /// Mean normal circular thickness s_mn and module m_mn (mm).
    pub thickness: f64,
    pub normal_module: f64,
    /// Pressure angles of the concave and convex flanks (rad).
    pub pressure_angle_concave: f64,
    pub pressure_angle_convex: f64,
}

impl MemberBlank {
    /// One member's data from the blank design's summary for the cutting
    /// machine ([`BlankDesign::cutting_blank`]: ISO 23509 clauses 6, 7.3–7.5,
    /// 7.8): teeth, cone distances and face width, θ_a = δ_a − δ,
    /// θ_f = δ − δ_f, mean depths, spiral angle, thickness.
    pub fn from_design(b: &BlankDesign, member: Member) -> Result<Self> {
        let cut = b.cutting_blank();
        let (m, concave, convex) = match member {
            // Drive side: pinion concave, gear convex (ISO 23509 §7.2).
            Member::Gear => (&cut.wheel, cut.alpha_n_coast, cut.alpha_n_drive),
            Member::Pinion => (&cut.pinion, cut.alpha_n_drive, cut.alpha_n_coast),
        };
        let teeth = m.z.round();
        if (m.z - teeth).abs() > 1e-9 || teeth < 3.0 {
            return Err(FlankError::Model(format!(
                "blank: tooth number {} is not an integer ≥ 3",
                m.z
            )));
        }
        let out = MemberBlank {
            teeth: teeth as u32,
            pitch_angle: m.delta,
            mean_cone_distance: m.rm,
            outer_cone_distance: m.re,
            inner_cone_distance: m.ri,
            mean_addendum: m.ham,
            mean_dedendum: m.hfm,
            addendum_angle: m.delta_a - m.delta,
            dedendum_angle: m.delta - m.delta_f,
            spiral_angle: m.beta_m,
            thickness: m.smn,
            normal_module: cut.m_mn,
            pressure_angle_concave: concave,
            pressure_angle_convex: convex,
        };
        Ok(out)
    }

    /// The axial section of the flank parametrisation.
    pub fn section(&self) -> AxialSection {
        AxialSection {
            pitch_angle: self.pitch_angle,
            cone_distance: (self.inner_cone_distance, self.outer_cone_distance),
            mean_cone_distance: self.mean_cone_distance,
            tip: ConeLine {
                u_mean: self.mean_addendum,
                slope: self.addendum_angle.tan(),
            },
            root: ConeLine {
                u_mean: -self.mean_dedendum,
                slope: -self.dedendum_angle.tan(),
            },
        }
    }
}

/// A member's cutter, machine settings and flank parametrisation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MemberSetup {
    pub blank: MemberBlank,
    pub hand: Hand,
    pub head: CutterHead,
    pub settings: MachineSettings,
    /// The cutter centre's position in the cradle plane (x, y) and the
    /// mean root point's x_M (module docs).
    pub cutter_centre: (f64, f64),
    pub mean_root_x: f64,
    /// What placed the cutter: the machine spiral angle and the blade
    /// angles (concave = outside, convex = inside) (rad), and the widening
    /// of the point width (mm) ([`setup_with`]).
    pub angles: SetupAngles,
}

/// The angles and width correction a setup was built from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SetupAngles {
    pub machine_spiral_angle: f64,
    pub blade_angle_concave: f64,
    pub blade_angle_convex: f64,
    pub width_correction: f64,
}

/// The generating roll of a member: the ratio of roll as a factor of the
/// pure-rolling value sin δ / cos(δ − γ_m) (module docs) and the
/// modified-roll coefficients (2C, 6D) of [`MachineSettings`]. The default
/// (factor 1, no modified roll) is the basic design; the local synthesis
/// ([`crate::geometry::bevel::synthesis`]) changes them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RollChoice {
    pub ratio_of_roll_factor: f64,
    pub modified_roll: (f64, f64),
}

impl Default for RollChoice {
    fn default() -> Self {
        RollChoice {
            ratio_of_roll_factor: 1.0,
            modified_roll: (0.0, 0.0),
        }
    }
}

/// The settings of one member (module docs). `generated` = false gives a
/// formate member.
pub fn member_setup(
    blank: &MemberBlank,
    hand: Hand,
    cutter: &CutterChoice,
    generated: bool,
) -> Result<MemberSetup> {
    let angles = (
        blank.spiral_angle,
        blank.pressure_angle_concave,
        blank.pressure_angle_convex,
    );
    setup_with(
        blank,
        hand,
        cutter,
        generated,
        angles,
        0.0,
        &RollChoice::default(),
    )
}

/// [`member_setup`] with the machine's spiral angle and the blade angles
/// (concave = outside, convex = inside) given apart from the blank's, the
/// point width widened by `width_correction` (mm), on the roll `roll`.
pub fn setup_with(
    blank: &MemberBlank,
    hand: Hand,
    cutter: &CutterChoice,
    generated: bool,
    (beta_machine, blade_cc, blade_cv): (f64, f64, f64),
    width_correction: f64,
    roll: &RollChoice,
) -> Result<MemberSetup> {
    let b = blank;
    let bad = |m: String| {
        Err(FlankError::Model(format!(
            "machine settings from the blank: {m}"
        )))
    };
    if !(cutter.mean_radius.is_finite() && cutter.mean_radius > 0.0) {
        return bad(format!(
            "cutter mean_radius {} must be > 0",
            cutter.mean_radius
        ));
    }
    let gamma = b.pitch_angle - b.dedendum_angle;
    if !(gamma > 1e-3 && gamma < 0.5 * PI) {
        return bad(format!(
            "machine_root_angle (root angle) {gamma} rad must lie in (0, 90°)"
        ));
    }
    let (sd, cd) = b.pitch_angle.sin_cos();
    let (zf, rf) = (
        b.mean_cone_distance * cd + b.mean_dedendum * sd,
        b.mean_cone_distance * sd - b.mean_dedendum * cd,
    );
    let (sg, cg) = gamma.sin_cos();
    let z_apex = zf - rf * cg / sg;
    let x_m = z_apex * cg + rf / sg;
    let h = match hand {
        Hand::Left => 1.0,
        Hand::Right => -1.0,
    };
    let (sb, cb) = beta_machine.sin_cos();
    let rc = cutter.mean_radius;
    // the cutter must cover the face width with its lengthwise curve
    let half_face = 0.5 * (b.outer_cone_distance - b.inner_cone_distance);
    if rc <= half_face * 0.5 {
        return bad(format!(
            "cutter mean_radius {rc} too small for the face width {:.3}",
            2.0 * half_face
        ));
    }
    // a right-hand member is the mirror image (y → −y) of a left-hand one
    let centre = (x_m - rc * sb, h * rc * cb);
    let e_mn = PI * b.normal_module - b.thickness;
    let w = e_mn
        - b.mean_dedendum * (b.pressure_angle_concave.tan() + b.pressure_angle_convex.tan())
        + width_correction;
    if !(w > 2.0 * cutter.edge_radius * 0.5 && w > 0.0) {
        return bad(format!(
            "point width {w:.4} mm (space width {e_mn:.4} at pitch less the flanks' spread) \
             leaves no room for edge_radius {}",
            cutter.edge_radius
        ));
    }
    // the whole depth at the heel (tapered depth), with a quarter margin
    let heel_depth = b.mean_addendum
        + b.mean_dedendum
        + (b.outer_cone_distance - b.mean_cone_distance)
            * (b.addendum_angle.tan() + b.dedendum_angle.tan()).max(0.0);
    let height = cutter.blade_height.unwrap_or(1.25 * heel_depth);
    let head = CutterHead {
        inside: Blade {
            side: crate::geometry::bevel::cutter::BladeSide::Inside,
            point_radius: rc - 0.5 * w,
            pressure_angle: blade_cv,
            edge_radius: cutter.edge_radius,
            toprem: None,
            curvature_radius: None,
            height,
        },
        outside: Blade {
            side: crate::geometry::bevel::cutter::BladeSide::Outside,
            point_radius: rc + 0.5 * w,
            pressure_angle: blade_cc,
            edge_radius: cutter.edge_radius,
            toprem: None,
            curvature_radius: None,
            height,
        },
    };
    head.inside.profile()?;
    head.outside.profile()?;
    let settings = MachineSettings {
        radial_distance: centre.0.hypot(centre.1),
        cradle_angle: centre.1.atan2(centre.0),
        machine_root_angle: gamma,
        sliding_base: z_apex * sg,
        blank_offset: 0.0,
        machine_center_to_back: 0.0,
        ratio_of_roll: if generated {
            roll.ratio_of_roll_factor * sd / (b.pitch_angle - gamma).cos()
        } else {
            1.0
        },
        modified_roll: if generated {
            roll.modified_roll
        } else {
            (0.0, 0.0)
        },
        tilt: 0.0,
        swivel: 0.0,
        generated,
    };
    settings.validate()?;
    Ok(MemberSetup {
        blank: *b,
        hand,
        head,
        settings,
        cutter_centre: centre,
        mean_root_x: x_m,
        angles: SetupAngles {
            machine_spiral_angle: beta_machine,
            blade_angle_concave: blade_cc,
            blade_angle_convex: blade_cv,
            width_correction,
        },
    })
}

/// The mean-point figures of a setup measured on its generated flanks
/// (spiral angles and pressure angles of the concave and convex flank,
/// rad; the mean normal circular thickness, mm) and their design values.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeanPointCheck {
    pub spiral_angle: (f64, f64),
    pub pressure_angle: (f64, f64),
    pub design_spiral_angle: f64,
    pub design_pressure_angle: (f64, f64),
    /// Cone distance of the measured point and its design value (mm).
    pub cone_distance: (f64, f64),
    pub design_cone_distance: f64,
    /// Mean normal circular thickness s_mn: the arc ρ_m Δθ between the two
    /// flanks on the pitch cone at R_m times cos β_m (ISO 23509 clause 7.8:
    /// s_mt = s_mn / cos β_m), and the blank's (mm).
    pub thickness: f64,
    pub design_thickness: f64,
}

impl MeanPointCheck {
    /// Largest angular deviation from the design (rad): the mean of the two
    /// flanks' spiral angles against β_m, each pressure angle against its
    /// flank's.
    pub fn max_angle_error(&self) -> f64 {
        let beta = 0.5 * (self.spiral_angle.0 + self.spiral_angle.1);
        (beta - self.design_spiral_angle)
            .abs()
            .max((self.pressure_angle.0 - self.design_pressure_angle.0).abs())
            .max((self.pressure_angle.1 - self.design_pressure_angle.1).abs())
    }
}

/// Measure a setup's flanks at the mean point (u = 0, v = R_m).
pub fn check_mean_point(setup: &MemberSetup) -> Result<MeanPointCheck> {
    let rm = setup.blank.mean_cone_distance;
    let (concave, convex) = (
        setup.flank(FlankKind::Concave)?,
        setup.flank(FlankKind::Convex)?,
    );
    let cc = concave.measure(0.0, rm)?;
    let cv = convex.measure(0.0, rm)?;
    // both flanks of tooth 0 at (0, R_m) lie on one circle of the pitch cone
    let (pa, pb) = (
        concave.try_evaluate(0.0, rm)?.0,
        convex.try_evaluate(0.0, rm)?.0,
    );
    let d = wrap_angle(angle_from_y(pa) - angle_from_y(pb)).abs();
    let rho = rm * setup.blank.pitch_angle.sin();
    Ok(MeanPointCheck {
        spiral_angle: (cc.spiral_angle, cv.spiral_angle),
        pressure_angle: (cc.pressure_angle, cv.pressure_angle),
        design_spiral_angle: setup.blank.spiral_angle,
        design_pressure_angle: (
            setup.blank.pressure_angle_concave,
            setup.blank.pressure_angle_convex,
        ),
        cone_distance: (cc.cone_distance, cv.cone_distance),
        design_cone_distance: rm,
        thickness: rho * d * setup.blank.spiral_angle.cos(),
        design_thickness: setup.blank.thickness,
    })
}

/// The first-order settings corrected so that the generated flanks meet
/// the blank at the mean point: the cutter sits on the root cone, tilted by
/// the dedendum angle θ_f from the pitch cone's normal, so the flanks'
/// pressure angles on the pitch cone differ from the blade angles by about
/// θ_f sin β_m and their spiral angles by a similar amount. A fixed-point
/// iteration on the machine spiral angle (mean of the two flanks' spiral
/// angles → β_m) and the two blade angles (each flank's pressure angle →
/// the blank's) removes that, and a correction of the point width (by the
/// thickness error: widening the slot by δ thins the tooth by δ) brings
/// the mean normal thickness to the blank's s_mn (the cutter's axis is
/// normal to the root cone, not to the pitch cone, so the first-order
/// width misses it by θ_f-order terms: 25 µm on seed 003's gear). At most
/// `max_iterations` rounds, until the largest angular deviation is below
/// `tol` (rad) and the thickness error below `tol` R_m (mm). Returns the
/// setup and its check.
pub fn refined_setup(
    blank: &MemberBlank,
    hand: Hand,
    cutter: &CutterChoice,
    generated: bool,
    tol: f64,
    max_iterations: usize,
) -> Result<(MemberSetup, MeanPointCheck)> {
    refined_setup_with(
        blank,
        hand,
        cutter,
        generated,
        &RollChoice::default(),
        tol,
        max_iterations,
    )
}

/// [`refined_setup`] on a generating roll of choice: the mean point's
/// spiral and pressure angles and thickness are matched whatever the roll.
pub fn refined_setup_with(
    blank: &MemberBlank,
    hand: Hand,
    cutter: &CutterChoice,
    generated: bool,
    roll: &RollChoice,
    tol: f64,
    max_iterations: usize,
) -> Result<(MemberSetup, MeanPointCheck)> {
    refined_setup_counted(blank, hand, cutter, generated, roll, tol, max_iterations)
        .map(|(s, c, _)| (s, c))
}

/// How a mean-point correction of settings from the blank ended
/// ([`refined_setup_counted`], [`crate::geometry::bevel::hobbing_settings::refined_setup`]):
/// `rounds` corrections applied before the check passed (0: the
/// first-order settings already met it) and the largest deviation left,
/// `residual` (rad; the thickness or space-width error divided by R_m),
/// ≤ `tolerance`. `flank check` reports it for each member cut on settings
/// from the blank.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct SettingsRefinement {
    pub rounds: usize,
    pub residual: f64,
    pub tolerance: f64,
}

/// [`refined_setup_with`], also returning how the correction ended.
pub fn refined_setup_counted(
    blank: &MemberBlank,
    hand: Hand,
    cutter: &CutterChoice,
    generated: bool,
    roll: &RollChoice,
    tol: f64,
    max_iterations: usize,
) -> Result<(MemberSetup, MeanPointCheck, SettingsRefinement)> {
    let mut angles = (
        blank.spiral_angle,
        blank.pressure_angle_concave,
        blank.pressure_angle_convex,
    );
    let mut width = 0.0;
    let mut last = f64::INFINITY;
    for rounds in 0..=max_iterations {
        let setup = setup_with(blank, hand, cutter, generated, angles, width, roll)?;
        let c = check_mean_point(&setup)?;
        let thickness_error = c.thickness - c.design_thickness;
        last = c
            .max_angle_error()
            .max(thickness_error.abs() / blank.mean_cone_distance);
        if last <= tol {
            let r = SettingsRefinement {
                rounds,
                residual: last,
                tolerance: tol,
            };
            return Ok((setup, c, r));
        }
        width += thickness_error;
        angles.0 += c.design_spiral_angle - 0.5 * (c.spiral_angle.0 + c.spiral_angle.1);
        angles.1 += c.design_pressure_angle.0 - c.pressure_angle.0;
        angles.2 += c.design_pressure_angle.1 - c.pressure_angle.1;
    }
    Err(FlankError::Model(format!(
        "machine settings from the blank: the mean-point correction did not reach {tol:e} rad \
         (thickness: {tol:e} R_m) in {max_iterations} rounds (last deviation {last:.3e})"
    )))
}

impl MemberSetup {
    /// The start guess (s, θ, ψ) at the mean point for a flank: the blade
    /// at the pitch height above the mean root point, zero roll.
    pub fn start_guess(&self, kind: FlankKind) -> Result<[f64; 3]> {
        let blade = self.head.blade(kind.blade_side());
        let p = blade.profile()?;
        let s = p.s_at_height(self.blank.mean_dedendum);
        let (cx, cy) = self.cutter_centre;
        let theta = (-cy).atan2(self.mean_root_x - cx);
        Ok([s, theta, 0.0])
    }

    /// The flank of `kind`.
    pub fn flank(&self, kind: FlankKind) -> Result<GeneratedFlank> {
        GeneratedFlank::new(
            self.settings,
            *self.head.blade(kind.blade_side()),
            kind,
            self.blank.section(),
            self.blank.teeth,
            self.start_guess(kind)?,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::bevel::{blank_design, BlankInputs};

    /// ISO 23509 Annex F.2 (spiral bevel, method 0, face milling).
    pub(crate) const F2: &str = r#"{"method": 0, "Sigma_deg": 90, "a_mm": 0, "z1": 14, "z2": 39, "de2_mm": 176.893, "b2_mm": 25.4, "beta_m2_deg": 35.0, "rc0_mm": 114.3, "data_type": "II", "alpha_dD_deg": 20, "alpha_dC_deg": 20, "f_alim": 0, "c_ham": 0.24737, "k_d": 2.0, "k_c": 0.125, "k_t": 0.0915, "backlash": "outer normal jen 0.127", "theta_a2_deg": 2.1342, "theta_f2_deg": 6.4934}"#;

    /// The corrected settings meet the blank's mean spiral and pressure
    /// angles to 1e-9 rad on the generated surfaces of both members (and
    /// on the formate gear); the first-order ones within θ_f-order.
    #[test]
    fn f2_settings_meet_the_blank_at_the_mean_point() {
        let design = blank_design(&BlankInputs::from_json(F2).unwrap()).unwrap();
        let cutter = CutterChoice {
            mean_radius: 114.3,
            edge_radius: 0.6,
            blade_height: None,
        };
        for (member, hand, generated) in [
            (Member::Gear, Hand::Left, true),
            (Member::Gear, Hand::Left, false),
            (Member::Pinion, Hand::Right, true),
        ] {
            let blank = MemberBlank::from_design(&design, member).unwrap();
            let first =
                check_mean_point(&member_setup(&blank, hand, &cutter, generated).unwrap()).unwrap();
            assert!(first.max_angle_error() < 2.0 * blank.dedendum_angle.max(0.05));
            let (setup, c) = refined_setup(&blank, hand, &cutter, generated, 1e-9, 30).unwrap();
            assert!(c.max_angle_error() <= 1e-9, "{c:?}");
            assert!((c.cone_distance.0 - blank.mean_cone_distance).abs() < 1e-9);
            // the hand is the one asked for
            let m = setup
                .flank(FlankKind::Convex)
                .unwrap()
                .measure(0.0, blank.mean_cone_distance)
                .unwrap();
            assert_eq!(m.hand_sign, if hand == Hand::Right { 1.0 } else { -1.0 });
        }
    }
}
