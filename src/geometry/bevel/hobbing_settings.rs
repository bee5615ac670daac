//! Face-hobbing machine settings from the blank design, and the face-hobbed
//! flank as a [`ToothSurface`].
//!
//! **Settings from the blank** (one member: pitch angle δ, mean cone
//! distance R_m, mean spiral angle β_m, mean addendum h_am and dedendum
//! h_fm of the ISO 23509 design; cutter radius r_c0 and blade groups z₀;
//! the arithmetic is this module's, the relations are ISO 23509 clause
//! 6.3's):
//!
//! * **uniform depth** (methods 2 and 3): the root cone is parallel to the
//!   pitch cone, so the machine root angle is γ_m = δ and the pitch
//!   element lies in the plane z_m = h_fm above the tip plane: sliding base
//!   ΔX_B = h_fm, blank offset E_m = 0, machine centre to back ΔX_G = 0;
//!   the ratio of roll of the pitch cone rolling on its crown gear
//!   (z_p = z / sin δ) is R_a = sin δ (`cradle_machine`);
//! * **cutter centre** (crown-gear plane, crown centre O at the origin,
//!   the mean point P = (R_m, 0) on the pitch element): sin ν = z₀ m_mn /
//!   (2 r_c0), λ = 90° − β_m + ν the angle at P between PO and PC, so
//!   C = (R_m − r_c0 cos λ, κ r_c0 sin λ), κ = ±1 the hand; radial
//!   distance M = |C|, cradle angle q = atan2(C_y, C_x);
//! * **blade plane**: the trace's normal at P passes through the rolling
//!   circles' contact point I = C ρ_b/M, ρ_b = M z_p/(z_p + z₀); the blades
//!   lie in the plane through P and I parallel to the cutter axis, whose
//!   distance from C is the blade offset |b| = r_c0 sin ν = z₀ m_mn/2
//!   (checked in the tests; the identity needs the blank's own
//!   m_mn = 2 R_m sin δ cos β_m / z, since the distances of O and C from
//!   the line PI are in the ratio ρ_b : (M − ρ_b) = z_p : z₀);
//! * **blades**: at the pitch height h_fm, the outside blade (concave
//!   flank) and the inside blade (convex flank) are W/2 outward and inward
//!   of P in the blade plane, W = π m_mn − s_mn the member's mean normal
//!   space width; blade angles = the design's generated normal pressure
//!   angles (the pinion's concave flank and the wheel's convex flank are
//!   the drive flanks, ISO 23509 clause 7.2, as in face milling); the phase puts the blade
//!   plane through P at θ = 0, so the tooth space is centred on the work's
//!   +y axis at θ = ψ = 0;
//! * **pinion**: generated on its own crown gear with its own δ₁, R_m1,
//!   β_m1 and the opposite hand. This puts the pinion's mean point at the
//!   design's cone distance with the design's spiral angle, but it is not
//!   the Cyclo-Palloid pinion setting derived from the wheel's crown gear
//!   with the hypoid offset and the tilt (tilt = 0 here); see the
//!   verification README.
//!
//! **Flank frame and parameters**: those of
//! [`crate::geometry::bevel::generation`] (axial section, v = cone
//! distance toe → heel, u root → tip, 0 on the pitch cone); tooth 0 is
//! centred on +y, each flank turned by ±π/z onto it.

use crate::error::{FlankError, Result};
use crate::geometry::bevel::cradle_machine::MachineSettings;
use crate::geometry::bevel::cutter::{Blade, BladeSide};
use crate::geometry::bevel::face_hobbing::{
    ExtendedEpicycloid, FaceHobbing, FaceHobbingSettings, HobbingBlade,
};
use crate::geometry::bevel::generation::{
    solve_axial, AxialSection, ConeLine, EnvelopeError, EnvelopeFlank, SolveOptions,
};
use crate::geometry::bevel::BlankDesign;
use crate::geometry::surface::ToothSurface;
use crate::geometry::vec3::{cross, dot, norm, sub, V3};

/// Which member of the pair.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Member {
    Pinion,
    Gear,
}

/// The cutter choice that the blank does not fix.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HobbingCutter {
    /// Nominal cutter radius r_c0 (mm).
    pub radius: f64,
    /// Blade groups z₀.
    pub blade_groups: u32,
    /// Edge radius of both blades (mm).
    pub edge_radius: f64,
}

/// One member's blank in the terms the settings need (mm, rad).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HobbingBlank {
    pub teeth: u32,
    pub pitch_angle: f64,
    pub mean_cone_distance: f64,
    /// Inner and outer cone distance (face width).
    pub cone_distance: (f64, f64),
    pub spiral_angle: f64,
    pub mean_addendum: f64,
    pub mean_dedendum: f64,
    /// Face angle δ_a and root angle δ_f (ISO 23509 clause 7.4): the
    /// axial section's tip and root lines lean by δ_a − δ and δ − δ_f.
    pub face_angle: f64,
    pub root_angle: f64,
    pub normal_module: f64,
    pub normal_thickness: f64,
    /// Blade angles of the concave (outside blade) and convex flank.
    pub pressure_angle_concave: f64,
    pub pressure_angle_convex: f64,
    /// +1 or −1 (module docs: side of the cutter centre).
    pub hand: f64,
}

impl HobbingBlank {
    /// The member's blank from the ISO 23509 design (uniform depth; the
    /// face width is centred on the mean cone distance: R_m ± (R_e2 − R_m2)
    /// for the wheel, R_m1 ± (R_e1 − R_m1) for the pinion). The wheel is
    /// cut with κ = +1, the pinion with κ = −1 (opposite hands).
    pub fn from_design(design: &BlankDesign, member: Member) -> Result<Self> {
        let cut = design.cutting_blank();
        // Uniform depth is the face-hobbing methods' (2, 3) tooth depth; the
        // hypoid pinion's face and root cones then still lean slightly
        // (ISO 23509 clause 7.4, uniform clearance): the section follows
        // δ_a and δ_f and the machine root angle is δ_f (`work_placement`).
        if !matches!(design.method, 2 | 3) {
            return Err(FlankError::Model(format!(
                "face hobbing: method {} blank has tapered depth; face-hobbed sets are uniform depth (methods 2, 3)",
                design.method
            )));
        }
        let member_blank = |m: &crate::geometry::bevel::MemberBlank, concave, convex, hand| {
            let half = m.re - m.rm;
            HobbingBlank {
                teeth: m.z.round() as u32,
                pitch_angle: m.delta,
                mean_cone_distance: m.rm,
                cone_distance: (m.rm - half, m.re),
                spiral_angle: m.beta_m.abs(),
                mean_addendum: m.ham,
                mean_dedendum: m.hfm,
                face_angle: m.delta_a,
                root_angle: m.delta_f,
                normal_module: cut.m_mn,
                normal_thickness: m.smn,
                pressure_angle_concave: concave,
                pressure_angle_convex: convex,
                hand,
            }
        };
        let b = match member {
            // Drive side: pinion concave, gear convex (ISO 23509 §7.2).
            Member::Gear => member_blank(&cut.wheel, cut.alpha_n_coast, cut.alpha_n_drive, 1.0),
            Member::Pinion => member_blank(&cut.pinion, cut.alpha_n_drive, cut.alpha_n_coast, -1.0),
        };
        Ok(b)
    }

    /// θ_f = δ − δ_f: the root cone's lean from the pitch cone (rad).
    pub fn root_lean(&self) -> f64 {
        self.pitch_angle - self.root_angle
    }

    /// The axial section: the tip line at h_am with the face angle's lean
    /// tan(δ_a − δ); the root line is the generated root cone (the cutter
    /// tip plane's envelope, machine root angle γ_m = δ_f, see
    /// [`work_placement`]): slope −tan θ_f and depth h_fm/cos θ_f at R_m
    /// below the pitch point (the pitch plane of the crown gear is h_fm
    /// above the tip plane at P; the depth is measured ⟂ to the pitch cone,
    /// which leans by θ_f from the tip plane). θ_f = 0 (uniform depth):
    /// lines parallel to the generatrix at h_am and −h_fm.
    pub fn section(&self) -> AxialSection {
        let lean = self.root_lean();
        AxialSection {
            pitch_angle: self.pitch_angle,
            cone_distance: self.cone_distance,
            mean_cone_distance: self.mean_cone_distance,
            tip: ConeLine {
                u_mean: self.mean_addendum,
                slope: (self.face_angle - self.pitch_angle).tan(),
            },
            root: ConeLine {
                u_mean: -self.mean_dedendum / lean.cos(),
                slope: -lean.tan(),
            },
        }
    }
}

/// The work's place on the cradle machine (`cradle_machine` frames) for a
/// member whose mean pitch point P lies at `p` in the crown gear's pitch
/// plane (height h_fm above the cutter's tip plane) with its pitch-cone
/// generatrix along +x_m at P: machine root angle γ_m = δ_f (the tip plane
/// generates the root cone δ_f), the pitch generatrix through P rising by
/// θ_f = δ − δ_f toward the heel, g = (cos θ_f, 0, sin θ_f), the apex at
/// A = P − R_m g; A = E_m e_y + ΔX_B e_z + ΔX_G d, d = (cos γ_m, 0,
/// −sin γ_m) gives blank offset E_m = A_y, machine centre to back ΔX_G =
/// A_x / cos γ_m, sliding base ΔX_B = A_z + ΔX_G sin γ_m (Litvin & Fuentes,
/// *Gear Geometry and Applied Theory*, 2nd ed., §20.4 for the settings;
/// the construction is this module's). Returns (γ_m, ΔX_B, E_m, ΔX_G).
/// With θ_f = 0 and P = (R_m, 0): (δ, h_fm, 0, 0), the apex at the crown
/// centre.
pub fn work_placement(blank: &HobbingBlank, p: [f64; 2]) -> (f64, f64, f64, f64) {
    let lean = blank.root_lean();
    let rm = blank.mean_cone_distance;
    let gamma = blank.root_angle;
    let a = [
        p[0] - rm * lean.cos(),
        p[1],
        blank.mean_dedendum - rm * lean.sin(),
    ];
    let xg = a[0] / gamma.cos();
    (gamma, a[2] + xg * gamma.sin(), a[1], xg)
}

/// A member's face-hobbing setup: settings, the two blades, the
/// crown-gear geometry behind them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HobbingSetup {
    pub blank: HobbingBlank,
    pub cutter: HobbingCutter,
    pub settings: FaceHobbingSettings,
    /// Outside blade (concave flank) and inside blade (convex flank).
    pub outside: HobbingBlade,
    pub inside: HobbingBlade,
    /// ν, λ, ρ_b of the construction (ISO 23509 clause 6.3).
    pub lead_angle: f64,
    pub lambda: f64,
    pub base_radius: f64,
    /// Crown gear teeth z_p = z / sin δ.
    pub crown_teeth: f64,
    /// In-plane coordinate x of the mean point P in the blade plane.
    pub mean_in_plane: f64,
    /// The mean point P in the cradle frame at zero roll: (R_m, 0, h_fm)
    /// for a member on its own crown gear, elsewhere for a pinion on the
    /// gear's ([`Self::pinion_from_gear`]) or generated by a formate gear
    /// ([`Self::pinion_for_formate_gear`]).
    pub mean_point: V3,
    /// The turn (rad) about the work axis that puts tooth 0 on +y: None for
    /// blades bounding a space around P (each flank turned by ±π/z, the
    /// sign from its mean point); Some(ω) for blades bounding a tooth.
    pub tooth_placement: Option<f64>,
    /// For a pinion generated by a formate gear: the gear's pitch apex in
    /// the cradle frame, whose z axis is then the gear's axis (toward the
    /// gear's heel); None otherwise.
    pub generating_gear_apex: Option<V3>,
}

impl HobbingSetup {
    /// Settings from the blank (module docs). `generated` = false gives a
    /// formate (non-generated) member. Errors name the input.
    pub fn new(blank: HobbingBlank, cutter: HobbingCutter, generated: bool) -> Result<Self> {
        if cutter.blade_groups == 0 {
            return Err(FlankError::Model(
                "face hobbing: blade_groups z0 = 0 (at least one blade group)".into(),
            ));
        }
        let z0 = f64::from(cutter.blade_groups);
        let (rc0, mn) = (cutter.radius, blank.normal_module);
        if !(rc0.is_finite() && rc0 > 0.0) {
            return Err(FlankError::Model(format!(
                "face hobbing: cutter radius rc0 {rc0} must be > 0"
            )));
        }
        let sin_nu = z0 * mn / (2.0 * rc0);
        if !(sin_nu < 1.0) {
            return Err(FlankError::Model(format!(
                "face hobbing: cutter radius rc0 {rc0} mm too small for z0 = {z0} blade groups of module {mn} (sin ν = z0 m_mn / (2 rc0) = {sin_nu:.4} ≥ 1)"
            )));
        }
        let nu = sin_nu.asin();
        let beta = blank.spiral_angle;
        let lambda = std::f64::consts::FRAC_PI_2 - beta + nu;
        let rm = blank.mean_cone_distance;
        let kappa = blank.hand.signum();
        let c = [rm - rc0 * lambda.cos(), kappa * rc0 * lambda.sin()];
        let m = c[0].hypot(c[1]);
        let (ri, re) = blank.cone_distance;
        // the cutter circle through P must span the face width
        if !((m - rc0).abs() < ri && m + rc0 > re) {
            return Err(FlankError::Model(format!(
                "face hobbing: cutter radius rc0 {rc0} mm does not fit the face width {ri:.3}–{re:.3} mm \
                 (radial distance {m:.3} mm: the tooth trace does not reach the toe and the heel)"
            )));
        }
        let delta = blank.pitch_angle;
        let zp = f64::from(blank.teeth) / delta.sin();
        let rho_b = m * zp / (zp + z0);
        let i_pt = [c[0] * rho_b / m, c[1] * rho_b / m];
        let p = [rm, 0.0];
        // blade plane direction d through P and I, oriented so that the
        // in-plane coordinate x = d·(P − C) > 0
        let pc = [p[0] - c[0], p[1] - c[1]];
        let ip = [i_pt[0] - p[0], i_pt[1] - p[1]];
        let l = ip[0].hypot(ip[1]);
        let mut d = [ip[0] / l, ip[1] / l];
        if d[0] * pc[0] + d[1] * pc[1] < 0.0 {
            d = [-d[0], -d[1]];
        }
        let x_p = d[0] * pc[0] + d[1] * pc[1];
        let b = d[0] * pc[1] - d[1] * pc[0];
        // head angle of the blade plane at θ = 0: Rot(φ₀)(1, 0) = d
        let phase = d[1].atan2(d[0]);
        let w = std::f64::consts::PI * mn - blank.normal_thickness;
        if !(w > 2.0 * cutter.edge_radius && w > 0.0) {
            return Err(FlankError::Model(format!(
                "face hobbing: space width {w:.4} mm leaves no room for edge_radius {}",
                cutter.edge_radius
            )));
        }
        let h_p = blank.mean_dedendum;
        let height = blank.mean_dedendum + blank.mean_addendum + 0.5 * mn;
        let blade = |side: BladeSide, x: f64, alpha: f64| {
            let sigma = side.sigma();
            HobbingBlade {
                blade: Blade {
                    side,
                    point_radius: x - sigma * h_p * alpha.tan(),
                    pressure_angle: alpha,
                    edge_radius: cutter.edge_radius,
                    toprem: None,
                    curvature_radius: None,
                    height,
                },
                offset: b,
                phase,
            }
        };
        let outside = blade(
            BladeSide::Outside,
            x_p + 0.5 * w,
            blank.pressure_angle_concave,
        );
        let inside = blade(
            BladeSide::Inside,
            x_p - 0.5 * w,
            blank.pressure_angle_convex,
        );
        let (gamma_m, sliding_base, blank_offset, center_to_back) = work_placement(&blank, p);
        let machine = MachineSettings {
            radial_distance: m,
            cradle_angle: c[1].atan2(c[0]),
            machine_root_angle: gamma_m,
            sliding_base,
            blank_offset,
            machine_center_to_back: center_to_back,
            // the work's velocity at P, φ̇ R_m sin δ e_y (whatever θ_f),
            // equals the crown gear's ψ̇ R_m e_y
            ratio_of_roll: delta.sin(),
            modified_roll: (0.0, 0.0),
            tilt: 0.0,
            swivel: 0.0,
            generated,
        };
        let settings = FaceHobbingSettings {
            machine,
            blade_groups: cutter.blade_groups,
            work_teeth: blank.teeth,
        };
        settings.validate()?;
        Ok(HobbingSetup {
            blank,
            cutter,
            settings,
            outside,
            inside,
            lead_angle: nu,
            lambda,
            base_radius: rho_b,
            crown_teeth: zp,
            mean_in_plane: x_p,
            mean_point: [p[0], p[1], h_p],
            tooth_placement: None,
            generating_gear_apex: None,
        })
    }

    /// The pinion generated on the **gear's generating crown gear**
    /// (Klingelnberg Cyclo-Palloid and Oerlikon practice for a face-hobbed
    /// set: one crown gear, complementary members; Litvin & Fuentes, *Gear
    /// Geometry and Applied Theory*, 2nd ed., §22.2–22.4 on generation by a
    /// common generating surface; Vimercati, Mech. Mach. Theory 42 (2007)
    /// §3 for the face-hobbed pinion's settings). `gear` is the gear's setup
    /// ([`Self::new`]), `pinion` the pinion's blank. Tilt and swivel are 0:
    /// the pinion's blades sweep exactly the gear blades' surface in the
    /// crown gear, so a spiral bevel pair (offset 0) cut this way is
    /// conjugate (line contact); the Cyclo-Palloid tilt that localises the
    /// bearing is not derived here.
    ///
    /// Construction (crown-plane coordinates of the gear's machine, crown
    /// centre O, the gear's mean point P = (R_m2, 0)):
    ///
    /// * the pinion's pitch generatrix through P makes the angle
    ///   ε = β_m1 − β_m2 with OP (ISO 23509 clause 6: the offset angle in
    ///   the pitch plane ζ_mp), turned away from the tooth trace's tangent t
    ///   at P so that the angle between t and the generatrix is β_m1; the
    ///   pinion's apex lies in the pitch plane at R_m1 from P;
    /// * the pinion sits on the other side of the crown gear: its machine
    ///   frame is the gear's turned by 180° about the line OP in the pitch
    ///   plane ((x, y, h) ↦ (x, −y, h_fm1 + h_fm2 − h), a rigid motion), then
    ///   about the cradle axis by ε so that its generatrix lies along +x_m
    ///   as the machine's frames require. The cutter centre, the blades'
    ///   angular phases and offsets follow (phase ↦ ε − phase, b ↦ −b,
    ///   θ ↦ −θ: the indexing relation "crown gear turns −(z₀/z_p) θ" is
    ///   unchanged); the gear's outside blade becomes the pinion's inside
    ///   blade (its convex flank, mating the gear's concave flank) and vice
    ///   versa, with the same pressure angle and the same in-plane position
    ///   x at the pitch plane;
    /// * work placement from P, R_m1, δ1, δ_f1 ([`work_placement`]): the
    ///   blank offset is E_m = R_m2 sin ε (the offset in the pitch plane
    ///   a_p of ISO 23509 formula (115)), ΔX_G and ΔX_B put the apex there;
    /// * ratio of roll R_a = z1/z_p = z1 sin δ2/z2 (the same crown gear:
    ///   the continuous indexing already turns the pinion by z_p/z1 of the
    ///   crown gear's turn); at P the crown gear's and the pinion's
    ///   velocities then have equal components normal to the trace
    ///   (ISO 23509 clause 6.3's condition: z1/z2 = R_m1 sin δ1 cos β_m1 /
    ///   (R_m2 sin δ2 cos β_m2)), so P is on the line of contact at ψ = 0.
    ///
    /// The pinion's mean normal space width is the gear's tooth complement
    /// π m_mn − W₂ = s_mn2 + (π m_mn − s_mn1 − s_mn2) (no backlash: s_mn1
    /// exactly). Errors name the input.
    pub fn pinion_from_gear(
        gear: &HobbingSetup,
        pinion: HobbingBlank,
        generated: bool,
    ) -> Result<Self> {
        let gm = &gear.settings.machine;
        if gm.tilt != 0.0 || gm.swivel != 0.0 || gm.blank_offset != 0.0 || gear.mean_point[1] != 0.0
        {
            return Err(FlankError::Model(
                "face hobbing, pinion from the gear's crown gear: the gear setup must be on its own crown gear (HobbingSetup::new: tilt, swivel, blank_offset 0)".into(),
            ));
        }
        let named = [
            ("pitch_angle", pinion.pitch_angle),
            ("mean_cone_distance", pinion.mean_cone_distance),
            ("spiral_angle", pinion.spiral_angle),
            ("mean_dedendum", pinion.mean_dedendum),
        ];
        for (k, v) in named {
            if !(v.is_finite() && v >= 0.0) {
                return Err(FlankError::Model(format!(
                    "face hobbing, pinion from the gear's crown gear: pinion {k} = {v} must be finite and ≥ 0"
                )));
            }
        }
        if !(pinion.mean_cone_distance > 0.0 && pinion.pitch_angle > 0.0 && pinion.teeth >= 3) {
            return Err(FlankError::Model(format!(
                "face hobbing, pinion from the gear's crown gear: pinion mean_cone_distance {}, pitch_angle {}, teeth {} must be positive (teeth ≥ 3)",
                pinion.mean_cone_distance, pinion.pitch_angle, pinion.teeth
            )));
        }
        let rm2 = gear.blank.mean_cone_distance;
        let h2 = gear.blank.mean_dedendum;
        let h1 = pinion.mean_dedendum;
        let eps = pinion.spiral_angle - gear.blank.spiral_angle;
        // the gear's trace tangent at P: ⟂ to P→I (I the rolling circles'
        // contact point on O→C), oriented toward the heel
        let c2 = [
            gm.radial_distance * gm.cradle_angle.cos(),
            gm.radial_distance * gm.cradle_angle.sin(),
        ];
        let k = gear.base_radius / gm.radial_distance;
        let pi = [k * c2[0] - rm2, k * c2[1]];
        let mut t = [-pi[1], pi[0]];
        if t[0] < 0.0 {
            t = [-t[0], -t[1]];
        }
        // generatrix direction at the angle a from OP, away from t
        let a = -t[1].signum() * eps;
        // 180° about OP, then Rot(a) about the cradle axis
        let turn = |x: [f64; 2]| {
            let (sa, ca) = a.sin_cos();
            [ca * x[0] + sa * x[1], sa * x[0] - ca * x[1]]
        };
        let c1 = turn(c2);
        let p1 = turn([rm2, 0.0]);
        let flip = |b: &HobbingBlade| {
            let side = match b.blade.side {
                BladeSide::Outside => BladeSide::Inside,
                BladeSide::Inside => BladeSide::Outside,
            };
            let (sigma, alpha) = (b.blade.side.sigma(), b.blade.pressure_angle);
            // x at the pitch plane, the same in both machines
            let x = b.blade.point_radius + sigma * h2 * alpha.tan();
            HobbingBlade {
                blade: Blade {
                    side,
                    point_radius: x + sigma * h1 * alpha.tan(),
                    height: h1 + pinion.mean_addendum + 0.5 * gear.blank.normal_module,
                    ..b.blade
                },
                offset: -b.offset,
                phase: a - b.phase,
            }
        };
        let (inside, outside) = (flip(&gear.outside), flip(&gear.inside));
        for b in [&inside, &outside] {
            b.blade.profile()?;
        }
        let (gamma_m, sliding_base, blank_offset, center_to_back) = work_placement(&pinion, p1);
        let machine = MachineSettings {
            radial_distance: gm.radial_distance,
            cradle_angle: c1[1].atan2(c1[0]),
            machine_root_angle: gamma_m,
            sliding_base,
            blank_offset,
            machine_center_to_back: center_to_back,
            ratio_of_roll: f64::from(pinion.teeth) / gear.crown_teeth,
            modified_roll: (0.0, 0.0),
            tilt: 0.0,
            swivel: 0.0,
            generated,
        };
        let settings = FaceHobbingSettings {
            machine,
            blade_groups: gear.cutter.blade_groups,
            work_teeth: pinion.teeth,
        };
        settings.validate()?;
        Ok(HobbingSetup {
            blank: pinion,
            cutter: gear.cutter,
            settings,
            outside,
            inside,
            lead_angle: gear.lead_angle,
            lambda: gear.lambda,
            base_radius: gear.base_radius,
            crown_teeth: gear.crown_teeth,
            mean_in_plane: gear.mean_in_plane,
            mean_point: [p1[0], p1[1], h1],
            tooth_placement: Some(0.0),
            generating_gear_apex: None,
        })
    }

    /// The pinion generated by a **formate gear** (non-generated gear,
    /// generated pinion: the usual face-hobbed "formate" set): the
    /// generating body is the gear itself, whose tooth surface is the
    /// surface the blades sweep in the gear's indexing motion; the pinion
    /// is cut with the gear's blades turned about the gear's axis as the
    /// gear would turn in mesh (ratio of roll z1/z2), so it is the envelope
    /// of the gear's flank in the pair's relative motion: conjugate to the
    /// formate gear (line contact) before any ease-off (Litvin & Fuentes,
    /// *Gear Geometry and Applied Theory*, 2nd ed., §21 on formate hypoid
    /// gears, where the pinion generator imitates the gear; the
    /// construction is this module's).
    ///
    /// Construction: the cutter and the work placed as by
    /// [`Self::pinion_from_gear`] (frame S′ of that machine); the cradle
    /// axis is now the gear's axis k (the gear's d₂ = (cos γ_m2, 0,
    /// −sin γ_m2) through its apex, carried into S′ by the same 180° turn),
    /// so the cradle frame K has z_K = k, y_K ∥ k × d₁ (d₁ the pinion axis,
    /// so that it lies in the x_K z_K plane as the machine's frames
    /// require) and its origin on k in the plane ⟂ k through the cutter
    /// centre. In K the cutter head is tilted: tilt i and swivel j from the
    /// cutter axis e_z′ = T e_z, T = Rot_z(j) Rot_x(i) Rot_z(−j), the
    /// blades' phases advanced by φ₀ where Tᵀ R = Rot_z(φ₀) (R: S′ → K); the
    /// work settings (γ_m, E_m, ΔX_G, ΔX_B) are the pinion apex and axis
    /// written in K. `tooth_placement` turns the work frame back to that of
    /// S′ (the two differ by a turn about d₁). Errors name the input.
    pub fn pinion_for_formate_gear(gear: &HobbingSetup, pinion: HobbingBlank) -> Result<Self> {
        if gear.settings.machine.generated {
            return Err(FlankError::Model(
                "face hobbing, pinion for a formate gear: the gear setup is generated (`generated` = true); use pinion_from_gear".into(),
            ));
        }
        let s0 = Self::pinion_from_gear(gear, pinion, true)?;
        let (gm, pm) = (&gear.settings.machine, &s0.settings.machine);
        let (h1, h2) = (pinion.mean_dedendum, gear.blank.mean_dedendum);
        let a = s0.mean_point[1].atan2(s0.mean_point[0]);
        // gear machine → S′: Rot_z(a) (x, −y, h1 + h2 − z)
        let (sa, ca) = a.sin_cos();
        let dir = |v: V3| [ca * v[0] + sa * v[1], sa * v[0] - ca * v[1], -v[2]];
        let pos = |v: V3| {
            let d = dir([v[0], v[1], v[2] - h1 - h2]);
            [d[0], d[1], d[2]]
        };
        let (sg, cg) = gm.machine_root_angle.sin_cos();
        let d2 = [cg, 0.0, -sg];
        let apex2 = [
            gm.machine_center_to_back * d2[0],
            gm.blank_offset,
            gm.sliding_base + gm.machine_center_to_back * d2[2],
        ];
        let k = dir(d2);
        let a2 = pos(apex2);
        let (s1, c1) = pm.machine_root_angle.sin_cos();
        let d1 = [c1, 0.0, -s1];
        let apex1 = [
            pm.machine_center_to_back * d1[0],
            pm.blank_offset,
            pm.sliding_base + pm.machine_center_to_back * d1[2],
        ];
        let mut y = cross(k, d1);
        let ny = norm(y);
        if !(ny > 1e-9) {
            return Err(FlankError::Model(
                "face hobbing, pinion for a formate gear: the pinion axis is parallel to the gear axis".into(),
            ));
        }
        y = [y[0] / ny, y[1] / ny, y[2] / ny];
        let mut x = cross(y, k);
        if dot(x, d1) < 0.0 {
            x = [-x[0], -x[1], -x[2]];
            y = [-y[0], -y[1], -y[2]];
        }
        let (sq, cq) = pm.cradle_angle.sin_cos();
        let centre = [pm.radial_distance * cq, pm.radial_distance * sq, 0.0];
        let t = dot(sub(centre, a2), k);
        let origin = [a2[0] + t * k[0], a2[1] + t * k[1], a2[2] + t * k[2]];
        let to_k = |v: V3| [dot(x, v), dot(y, v), dot(k, v)];
        let c_k = to_k(sub(centre, origin));
        // cutter axis e_z′ in K = (x_z, y_z, k_z)
        let axis = [x[2], y[2], k[2]];
        let tilt = axis[2].clamp(-1.0, 1.0).acos();
        let swivel = axis[0].atan2(-axis[1]);
        let tm = crate::geometry::bevel::face_hobbing::tilt_matrix(tilt, swivel);
        // Tᵀ R e_x′ = (cos φ₀, sin φ₀, 0)
        let re_x = [x[0], y[0], k[0]];
        let h: [f64; 3] = std::array::from_fn(|c| (0..3).map(|r| tm[r][c] * re_x[r]).sum());
        let phi0 = h[1].atan2(h[0]);
        let d1k = to_k(d1);
        let gamma = (-d1k[2]).atan2(d1k[0]);
        let a1k = to_k(sub(apex1, origin));
        let xg = a1k[0] / gamma.cos();
        let mp = s0.mean_point;
        let mean_point = to_k(sub(mp, origin));
        // the work frames' x axes: e_y′ (S′) and y_K; ω = angle of y_K in
        // S′'s work frame (x_w = e_y′, y_w = d₁ × e_y′)
        let yw = cross(d1, [0.0, 1.0, 0.0]);
        let omega = dot(y, yw).atan2(y[1]);
        let machine = MachineSettings {
            radial_distance: c_k[0].hypot(c_k[1]),
            cradle_angle: c_k[1].atan2(c_k[0]),
            machine_root_angle: gamma,
            sliding_base: a1k[2] + xg * gamma.sin(),
            blank_offset: a1k[1],
            machine_center_to_back: xg,
            ratio_of_roll: f64::from(pinion.teeth) / f64::from(gear.blank.teeth),
            modified_roll: (0.0, 0.0),
            tilt,
            swivel,
            generated: true,
        };
        let settings = FaceHobbingSettings {
            machine,
            ..s0.settings
        };
        settings.validate().map_err(|e| {
            FlankError::Model(format!(
                "face hobbing, pinion for a formate gear: {e} (the cutter tilt is 90° − the gear's root angle)"
            ))
        })?;
        let shift = |b: HobbingBlade| HobbingBlade {
            phase: b.phase + phi0,
            ..b
        };
        Ok(HobbingSetup {
            settings,
            outside: shift(s0.outside),
            inside: shift(s0.inside),
            crown_teeth: f64::from(gear.blank.teeth),
            mean_point,
            tooth_placement: Some(omega),
            generating_gear_apex: Some(to_k(sub(a2, origin))),
            ..s0
        })
    }

    /// The blade of one side.
    pub fn blade(&self, side: BladeSide) -> HobbingBlade {
        match side {
            BladeSide::Outside => self.outside,
            BladeSide::Inside => self.inside,
        }
    }

    /// The closed-form extended epicycloid of a blade at pitch height h
    /// (in-plane coordinate `x`): the lengthwise tooth curve on the crown
    /// gear (face_hobbing docs).
    pub fn epicycloid(&self, blade: &HobbingBlade, x: f64) -> ExtendedEpicycloid {
        let m = &self.settings.machine;
        ExtendedEpicycloid {
            centre_distance: m.radial_distance,
            centre_angle: m.cradle_angle,
            point_radius: x.hypot(blade.offset),
            point_phase: blade.phase + blade.offset.atan2(x),
            ratio: f64::from(self.cutter.blade_groups) / self.crown_teeth,
        }
    }

    /// The flank cut by `blade` (the setup's own blade or a variant).
    /// A formate member's section starts above the path of the blade tip
    /// ([`Self::formate_root`]).
    pub fn flank_with(&self, blade: HobbingBlade) -> Result<HobbedFlank> {
        let mut section = self.blank.section();
        if !self.settings.machine.generated {
            section.root.u_mean = self.formate_root(&blade)?;
        } else if self.settings.machine.tilt != 0.0 {
            // generated by a formate gear ([`Self::pinion_for_formate_gear`])
            section.root = ConeLine {
                u_mean: self.generated_root(&blade)?,
                slope: 0.0,
            };
        }
        HobbedFlank::new_at(
            self.settings,
            blade,
            section,
            self.blank.teeth,
            self.blank.mean_dedendum,
            self.mean_point,
            self.tooth_placement,
        )
    }

    /// A formate member is not rolled, so the blade tip (the edge radius's
    /// end on the tip plane) reaches the root cone only where its path
    /// crosses the pitch element; elsewhere the tip plane passes above the
    /// root cone by about y²/(2ρ). The flank's root line (straight, as the
    /// axial section needs) is put at the highest u of the tip's path over
    /// the face width (sampled at 401 cutter angles; the surface's edge
    /// radius below it is left out).
    pub fn formate_root(&self, blade: &HobbingBlade) -> Result<f64> {
        let map = FaceHobbing::new(self.settings, *blade)?;
        let s_min = map.profile().s_min;
        let (sd, cd) = self.blank.pitch_angle.sin_cos();
        let (ri, re) = self.blank.cone_distance;
        let mut top = f64::NEG_INFINITY;
        for k in 0..=400 {
            let theta = -1.0 + 2.0 * k as f64 / 400.0;
            let r: V3 = map.position_generic([s_min, theta, 0.0]);
            let (z, rho) = (r[2], r[0].hypot(r[1]));
            let (u, v) = (-z * sd + rho * cd, z * cd + rho * sd);
            if v >= ri && v <= re {
                top = top.max(u);
            }
        }
        if !top.is_finite() {
            return Err(FlankError::Model(
                "face hobbing (formate): the blade tip's path does not cross the face width: the settings do not cut this blank".into(),
            ));
        }
        Ok(top + 1e-3 * self.blank.normal_module)
    }

    /// The root of a member generated by a formate gear
    /// ([`Self::pinion_for_formate_gear`]): the cutter tip turns with the
    /// gear about the gear's axis, so it does not sweep the blank's root
    /// cone (the tip plane only generates a cone when the cradle axis is ⟂
    /// to it). The flank's root line (straight, parallel to the pitch
    /// element, as the axial section needs) is put at the highest of the
    /// lowest points u the blade tip reaches in 16 bands of cone distance
    /// over the face width (sampled over 201 cutter angles × 121 roll
    /// angles in ±0.6 rad), plus 0.02 m_mn: the part of the fillet below
    /// is left out. Errs if a band is not reached.
    pub fn generated_root(&self, blade: &HobbingBlade) -> Result<f64> {
        let map = FaceHobbing::new(self.settings, *blade)?;
        let s_min = map.profile().s_min;
        let (sd, cd) = self.blank.pitch_angle.sin_cos();
        let (ri, re) = self.blank.cone_distance;
        const BANDS: usize = 16;
        let mut low = [f64::INFINITY; BANDS];
        for i in 0..=200 {
            let q1 = -1.0 + 2.0 * i as f64 / 200.0;
            for j in 0..=120 {
                let psi = -0.6 + 1.2 * j as f64 / 120.0;
                let r: V3 = map.position_generic([
                    s_min,
                    q1 + crate::geometry::bevel::face_hobbing::ROLL_SHEAR * psi,
                    psi,
                ]);
                let (z, rho) = (r[2], r[0].hypot(r[1]));
                let (u, v) = (-z * sd + rho * cd, z * cd + rho * sd);
                if v >= ri && v <= re {
                    let b = (((v - ri) / (re - ri)) * BANDS as f64).floor() as usize;
                    let b = b.min(BANDS - 1);
                    low[b] = low[b].min(u);
                }
            }
        }
        let top = low.iter().fold(f64::NEG_INFINITY, |a, &b| a.max(b));
        if !top.is_finite() {
            return Err(FlankError::Model(
                "face hobbing (pinion for a formate gear): the blade tip does not reach every part of the face width: the settings do not cut this blank".into(),
            ));
        }
        Ok(top + 0.02 * self.blank.normal_module)
    }

    /// The concave (outside blade) or convex (inside blade) flank.
    pub fn flank(&self, side: BladeSide) -> Result<HobbedFlank> {
        self.flank_with(self.blade(side))
    }
}

/// A face-hobbed flank: the envelope of the blade in the face-hobbing
/// motion over the member's axial section, placed on tooth 0.
#[derive(Debug)]
pub struct HobbedFlank {
    surface: EnvelopeFlank<FaceHobbing>,
    pub teeth: u32,
}

/// Spiral angle, hand and pressure angle measured on a flank: the same
/// figures as on a face-milled flank.
pub use crate::geometry::bevel::generated_surface::FlankMeasure as HobbedMeasure;

fn describe(s: &FaceHobbingSettings, e: &EnvelopeError, what: &str) -> FlankError {
    let m = &s.machine;
    FlankError::Model(format!(
        "{what}: {e}; face-hobbing settings blade_groups {}, radial_distance {:.4}, cradle_angle {:.6}, \
         machine_root_angle {:.6}, sliding_base {:.4}, blank_offset {:.4}, machine_center_to_back {:.4}, \
         ratio_of_roll {:.6}, tilt {:.6}, swivel {:.6} do not generate this flank over its blank",
        s.blade_groups,
        m.radial_distance,
        m.cradle_angle,
        m.machine_root_angle,
        m.sliding_base,
        m.blank_offset,
        m.machine_center_to_back,
        m.ratio_of_roll,
        m.tilt,
        m.swivel
    ))
}

impl HobbedFlank {
    /// The flank of `blade` on a face-hobbing machine with `settings` over
    /// `section`. The mean-point start: the blade at the pitch height
    /// (h = h_fm above the tip plane = the section's root depth), θ where
    /// the blade point lies on the pitch element at R_m, ψ = 0. Errs,
    /// naming the settings, if the flank is not generated over the blank.
    pub fn new(
        settings: FaceHobbingSettings,
        blade: HobbingBlade,
        section: AxialSection,
        teeth: u32,
    ) -> Result<Self> {
        let rm = section.mean_cone_distance;
        let h = -section.root.u_mean;
        Self::new_at(settings, blade, section, teeth, h, [rm, 0.0, h], None)
    }

    /// [`Self::new`] with the mean point's start given: the blade point at
    /// `pitch_height` above the tip plane lies at `mean_point` (cradle
    /// frame at ψ = 0; for a pinion on the gear's crown gear P is not at
    /// (R_m, 0, h_fm)). `placement`: None turns the flank by ±π/z (blades
    /// bounding a space around P: tooth 0 on +y), Some(ω) by ω (see
    /// [`HobbingSetup::tooth_placement`]).
    pub fn new_at(
        settings: FaceHobbingSettings,
        blade: HobbingBlade,
        section: AxialSection,
        teeth: u32,
        pitch_height: f64,
        mean_point: V3,
        placement: Option<f64>,
    ) -> Result<Self> {
        let map = FaceHobbing::new(settings, blade)?;
        let side = blade.blade.side;
        let what = format!("face-hobbed {side:?}-blade flank");
        let s0 = map.profile().s_at_height(pitch_height);
        let x = map.profile().rho_h(s0).0;
        let rm = section.mean_cone_distance;
        let theta0 = map.head_angle(mean_point) - blade.offset.atan2(x) - blade.phase;
        let theta0 = (theta0 + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU)
            - std::f64::consts::PI;
        let opt = SolveOptions::default();
        let (z, rho) = section.target(0.0, rm).0;
        let mean = solve_axial(&map, z, rho, [s0, theta0, 0.0], &opt)
            .map_err(|e| describe(&settings, &e, &format!("{what}, mean point")))?;
        let ang = mean.jet.r[1].atan2(mean.jet.r[0]) - std::f64::consts::FRAC_PI_2;
        let placement =
            placement.unwrap_or_else(|| -ang.signum() * std::f64::consts::PI / f64::from(teeth));
        let form = Some(map.profile().form_parameter());
        let surface = EnvelopeFlank::new(map, section, placement, form, mean.q, opt)
            .map_err(|e| describe(&settings, &e, &what))?;
        Ok(HobbedFlank { surface, teeth })
    }

    /// The envelope behind the flank (unplaced solves, generating
    /// parameters).
    pub fn envelope(&self) -> &EnvelopeFlank<FaceHobbing> {
        &self.surface
    }

    /// The kinematic chain.
    pub fn map(&self) -> &FaceHobbing {
        self.surface.map()
    }

    /// Point, normal, r_u, r_v or the solver's error naming the settings.
    pub fn try_evaluate(&self, u: f64, v: f64) -> Result<(V3, V3, V3, V3)> {
        self.surface.try_evaluate(u, v).map_err(|e| {
            describe(
                &self.map().settings,
                &e,
                &format!("face-hobbed flank at u {u}, v {v}"),
            )
        })
    }

    /// The dimensionless meshing residual at (u, v).
    pub fn meshing_residual(&self, u: f64, v: f64) -> Result<f64> {
        self.surface
            .meshing_residual(u, v)
            .map_err(|e| describe(&self.map().settings, &e, "face-hobbed flank"))
    }

    /// Spiral angle, hand and pressure angle at (u, v).
    pub fn measure(&self, u: f64, v: f64) -> Result<HobbedMeasure> {
        let (p, n, _, _) = self.try_evaluate(u, v)?;
        Ok(HobbedMeasure::on_pitch_cone(
            p,
            n,
            self.surface.section().pitch_angle,
        ))
    }
}

impl ToothSurface for HobbedFlank {
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
}

#[cfg(test)]
mod tests {
    use super::*;

    /// m_mn consistent with z, δ, R_m, β (m_mn = 2 R_m sin δ cos β / z).
    fn module() -> f64 {
        2.0 * 90.0 * 1.2f64.sin() * 0.55f64.cos() / 37.0
    }

    fn blank() -> HobbingBlank {
        HobbingBlank {
            teeth: 37,
            pitch_angle: 1.2,
            mean_cone_distance: 90.0,
            cone_distance: (75.0, 105.0),
            spiral_angle: 0.55,
            mean_addendum: 3.5,
            mean_dedendum: 4.5,
            face_angle: 1.2,
            root_angle: 1.2,
            normal_module: module(),
            normal_thickness: 6.0,
            pressure_angle_concave: 0.35,
            pressure_angle_convex: 0.35,
            hand: 1.0,
        }
    }

    const CUTTER: HobbingCutter = HobbingCutter {
        radius: 88.0,
        blade_groups: 5,
        edge_radius: 0.8,
    };

    /// The construction's triangle: |PC| = r_c0, angle λ at P, blade
    /// offset z₀ m_mn/2 (ISO 23509 clause 6.3), ρ_b + M z₀/(z_p + z₀) = M.
    #[test]
    fn construction_relations() {
        let s = HobbingSetup::new(blank(), CUTTER, true).unwrap();
        let m = &s.settings.machine;
        let c = [
            m.radial_distance * m.cradle_angle.cos(),
            m.radial_distance * m.cradle_angle.sin(),
        ];
        assert!(((c[0] - 90.0).hypot(c[1]) - 88.0).abs() < 1e-10);
        let cos_l = (90.0 - c[0]) / 88.0;
        assert!((cos_l - s.lambda.cos()).abs() < 1e-12);
        assert!((s.outside.offset.abs() - 5.0 * module() / 2.0).abs() < 1e-10);
        let zp = 37.0 / 1.2f64.sin();
        assert!((s.base_radius * (zp + 5.0) / zp - m.radial_distance).abs() < 1e-10);
        // the two blades are W apart in the blade plane at pitch height
        let w = std::f64::consts::PI * module() - 6.0;
        let x = |b: &HobbingBlade| {
            b.blade.point_radius + b.blade.side.sigma() * 4.5 * b.blade.pressure_angle.tan()
        };
        assert!((x(&s.outside) - x(&s.inside) - w).abs() < 1e-10);
    }

    /// work_placement: with no lean the apex is the crown centre below
    /// P's pitch height; with a lean θ_f the apex A lies R_m from P with
    /// P − A at δ to the work axis, and the root point at R_m (the
    /// section's root line) lies on the tip plane z = 0 with the root
    /// generatrix horizontal (tangent to the tip plane: the root cone δ_f).
    #[test]
    fn work_placement_puts_the_root_cone_on_the_tip_plane() {
        let mut b = blank();
        let (g, xb, em, xg) = work_placement(&b, [90.0, 0.0]);
        assert!((g - 1.2).abs() < 1e-15 && (xb - 4.5).abs() < 1e-12);
        assert!(em == 0.0 && xg.abs() < 1e-12);
        for lean in [0.01, -0.02] {
            b.root_angle = b.pitch_angle - lean;
            let p = [88.0, 3.0];
            let (g, xb, em, xg) = work_placement(&b, p);
            let d = [g.cos(), 0.0, -g.sin()];
            let a = [xg * d[0], em, xb + xg * d[2]];
            let pa = [p[0] - a[0], p[1] - a[1], 4.5 - a[2]];
            assert!((norm(pa) - 90.0).abs() < 1e-10);
            assert!((dot(pa, d) / 90.0 - 1.2f64.cos()).abs() < 1e-12);
            // root point at R_m: P − (h_fm / cos θ_f) n, n ⟂ g in the
            // vertical plane, pointing up
            let gv = [pa[0] / 90.0, pa[1] / 90.0, pa[2] / 90.0];
            let n = [-gv[2], 0.0, gv[0]];
            let h = b.mean_dedendum / lean.cos();
            assert!((4.5 - h * n[2]).abs() < 1e-12);
            // the section's root line slope is −tan θ_f, as the root
            // generatrix (horizontal) seen from the pitch generatrix
            let sec = b.section();
            assert!((sec.root.slope + lean.tan()).abs() < 1e-15);
            assert!((gv[2] - lean.sin()).abs() < 1e-12);
        }
    }

    /// pinion_from_gear needs a gear on its own crown gear;
    /// pinion_for_formate_gear needs a formate gear.
    #[test]
    fn pinion_constructors_check_the_gear() {
        let g = HobbingSetup::new(blank(), CUTTER, true).unwrap();
        let mut p = blank();
        p.teeth = 11;
        p.pitch_angle = 0.35;
        p.mean_cone_distance = 90.0;
        p.hand = -1.0;
        assert!(HobbingSetup::pinion_from_gear(&g, p, true).is_ok());
        let e = HobbingSetup::pinion_for_formate_gear(&g, p)
            .unwrap_err()
            .to_string();
        assert!(e.contains("generated"), "{e}");
        let mut tilted = g;
        tilted.settings.machine.tilt = 0.1;
        let e = HobbingSetup::pinion_from_gear(&tilted, p, true)
            .unwrap_err()
            .to_string();
        assert!(e.contains("tilt"), "{e}");
        let mut bad = p;
        bad.mean_cone_distance = f64::NAN;
        let e = HobbingSetup::pinion_from_gear(&g, bad, true)
            .unwrap_err()
            .to_string();
        assert!(e.contains("mean_cone_distance"), "{e}");
    }

    #[test]
    fn bad_input_names_the_key() {
        let e = HobbingSetup::new(
            blank(),
            HobbingCutter {
                blade_groups: 0,
                ..CUTTER
            },
            true,
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("blade_groups"), "{e}");
        let e = HobbingSetup::new(
            blank(),
            HobbingCutter {
                edge_radius: 5.0,
                ..CUTTER
            },
            true,
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("edge_radius"), "{e}");
    }
}
