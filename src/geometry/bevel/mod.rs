//! Blank design of spiral bevel and hypoid gears by ISO 23509:2016
//! ("Bevel and hypoid gear geometry"), methods 0–3.
//!
//! One job per file:
//!
//! * [`inputs`]: the input set (clause 6.1 pitch-cone data, clause 7.1
//!   tooth-profile data, data types I and II), read from JSON with the key
//!   names of the Annex F samples; validation errors name the key;
//! * [`pitch_cone`]: clause 6 method 0, the dispatch to the methods, the
//!   clause 7.2 basic data (ζ_m, ζ_mp, a_p, m_mn, α_lim) and the
//!   face-hobbing quantities ν, λ, ρ_P0, ρ_b;
//! * [`hypoid_methods`]: clause 6 methods 1 (Gleason), 2 (Oerlikon) and 3
//!   (Klingelnberg) with their iterations;
//! * [`face_angles`]: clause 7.2 axial positions and 7.4 face and root
//!   angles (uniform clearance for the hypoid pinion);
//! * [`tooth_depth`]: clause 7.3 — addenda, dedenda, clearance;
//! * [`face_width`]: clause 7.5 — pinion and wheel face widths;
//! * [`spiral_angles`]: clause 7.6 — spiral angles at the ends;
//! * [`thickness`]: clause 7.8 — tooth thicknesses and backlash;
//! * [`outputs`]: clauses 7.7 and 7.9 (end depths, diameters) and the
//!   output map with the Annex F key names.
//!
//! [`BlankDesign::cutting_blank`] gathers what the cutting-machine settings
//! need.
//!
//! What is verified against the two Annex F samples and what is not is in
//! `verification/iso23509_blank/README.md`.

pub mod assembly;
pub mod body;
pub mod conjugate;
pub mod cradle_machine;
pub mod cutter;
pub mod cutting;
pub mod cyclo_palloid;
pub mod ease_off;
pub mod face_angles;
pub mod face_hobbing;
pub mod face_width;
pub mod generated_surface;
pub mod generation;
pub mod hobbed_pinion;
pub mod hobbing_settings;
pub mod hypoid_methods;
pub mod inputs;
pub mod machine_settings;
pub mod outputs;
pub mod pair;
pub mod pitch_cone;
pub mod spiral_angles;
pub mod synthesis;
pub mod thickness;
pub mod tooth_depth;

pub use face_angles::FaceAngles;
pub use face_width::FaceWidths;
pub use inputs::BlankInputs;
pub use pitch_cone::{Hobbing, PitchCones};
pub use spiral_angles::EndSpiralAngles;
pub use thickness::Thickness;
pub use tooth_depth::ToothDepth;

use crate::error::{FlankError, Result};

/// The result of the blank design (internal units: mm, rad).
#[derive(Clone, Debug, PartialEq)]
pub struct BlankDesign {
    /// Calculation method, 0–3.
    pub method: u8,
    /// Shaft angle Σ, offset a, number of wheel teeth, cutter radius r_c0
    /// and blade groups z0 (None: face milling), as given.
    pub sigma: f64,
    pub a: f64,
    pub z1: f64,
    pub z2: f64,
    pub rc0: f64,
    pub z0: Option<f64>,
    /// Clause 6 and 7.2.
    pub cones: PitchCones,
    /// Clause 7.2 axial positions and 7.4 face and root angles.
    pub faces: FaceAngles,
    /// Clause 7.3.
    pub depth: ToothDepth,
    /// Clause 7.5.
    pub widths: FaceWidths,
    /// Face-hobbing quantities (z0 given).
    pub hobbing: Option<Hobbing>,
    /// Clause 7.6.
    pub spiral: EndSpiralAngles,
    /// Generated normal pressure angles, drive and coast (clause 7.2,
    /// formulae (118), (119)): α_nD = α_dD + f_αlim α_lim, α_nC = α_dC −
    /// f_αlim α_lim.
    pub alpha_n_drive: f64,
    pub alpha_n_coast: f64,
    /// Clause 7.8.
    pub thickness: Thickness,
}

/// What the cutting-machine settings of one member need from the blank
/// (mm, rad), at the mean point unless said: ISO 23509 clause 6 and 7
/// quantities gathered for the surface generation (issue 16 points 2, 3).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MemberBlank {
    /// Number of teeth.
    pub z: f64,
    /// Mean cone distance R_m, outer R_e and inner R_i cone distances.
    pub rm: f64,
    pub re: f64,
    pub ri: f64,
    /// Face width along the pitch cone and its parts outside (b_e) and
    /// inside (b_i) the mean point.
    pub b: f64,
    pub be: f64,
    pub bi: f64,
    /// Pitch, face and root angles δ, δ_a, δ_f.
    pub delta: f64,
    pub delta_a: f64,
    pub delta_f: f64,
    /// Mean spiral angle β_m.
    pub beta_m: f64,
    /// Mean addendum h_am and dedendum h_fm.
    pub ham: f64,
    pub hfm: f64,
    /// Mean normal circular thickness s_mn.
    pub smn: f64,
}

/// The pair-level data the machine settings need besides [`MemberBlank`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CuttingBlank {
    pub pinion: MemberBlank,
    pub wheel: MemberBlank,
    /// Shaft angle Σ and offset a.
    pub sigma: f64,
    pub a: f64,
    /// Mean normal module m_mn.
    pub m_mn: f64,
    /// Cutter radius r_c0 and blade groups z0 (None: face milling).
    pub rc0: f64,
    pub z0: Option<f64>,
    /// Generated normal pressure angles, drive and coast flank.
    pub alpha_n_drive: f64,
    pub alpha_n_coast: f64,
    /// Limit pressure angle α_lim.
    pub alpha_lim: f64,
}

impl BlankDesign {
    /// The summary for the cutting-machine settings.
    pub fn cutting_blank(&self) -> CuttingBlank {
        let (c, d, f, w) = (&self.cones, &self.depth, &self.faces, &self.widths);
        let (e1, e2) = (self.end_dimensions(0), self.end_dimensions(1));
        CuttingBlank {
            pinion: MemberBlank {
                z: self.z1,
                rm: c.rm1,
                re: e1.re,
                ri: e1.ri,
                b: w.b1,
                be: w.be1,
                bi: w.bi1,
                delta: c.delta1,
                delta_a: c.delta1 + f.theta_a1,
                delta_f: c.delta1 - f.theta_f1,
                beta_m: c.beta_m1,
                ham: d.ham1,
                hfm: d.hfm1,
                smn: self.thickness.s_mn[0],
            },
            wheel: MemberBlank {
                z: self.z2,
                rm: c.rm2,
                re: e2.re,
                ri: e2.ri,
                b: w.b2,
                be: w.be2,
                bi: w.bi2,
                delta: c.delta2,
                delta_a: c.delta2 + f.theta_a2,
                delta_f: c.delta2 - f.theta_f2,
                beta_m: c.beta_m2,
                ham: d.ham2,
                hfm: d.hfm2,
                smn: self.thickness.s_mn[1],
            },
            sigma: self.sigma,
            a: self.a,
            m_mn: c.m_mn,
            rc0: self.rc0,
            z0: self.z0,
            alpha_n_drive: self.alpha_n_drive,
            alpha_n_coast: self.alpha_n_coast,
            alpha_lim: c.alpha_lim,
        }
    }

    /// Top lands at the outer end (pinion, wheel), mm: the mean normal
    /// thickness scaled with the normal pitch, s_en = s_mn R_e cos β_e /
    /// (R_m cos β_m), less the addendum times tan α_nD + tan α_nC. An
    /// approximation of this code (the standard gives no top land), used
    /// only to refuse pointed teeth.
    pub fn outer_top_lands(&self) -> (f64, f64) {
        let (c, s) = (&self.cones, &self.spiral);
        let k = self.alpha_n_drive.tan() + self.alpha_n_coast.tan();
        let land = |i: usize, rm: f64, bm: f64, be: f64| {
            let e = self.end_dimensions(i);
            self.thickness.s_mn[i] * e.re * be.cos() / (rm * bm.cos()) - e.hae * k
        };
        (
            land(0, c.rm1, c.beta_m1, s.beta_e1),
            land(1, c.rm2, c.beta_m2, s.beta_e2),
        )
    }
}

/// Clause 6 for any method; a zero offset is method 0 (with β = β_Δ1 for
/// method 1).
fn pitch_cones(c: &pitch_cone::ConeInputs) -> Result<PitchCones> {
    let s6 = if c.method == 0 || c.a == 0.0 {
        let beta = match (c.method, c.beta_m1_desired, c.beta_m2) {
            (1, Some(b), _) => b,
            (_, _, Some(b)) => b,
            _ => {
                return Err(pitch_cone::missing(
                    "beta_m2_deg",
                    "the wheel's mean spiral angle",
                ))
            }
        };
        pitch_cone::method0(c, beta)?
    } else {
        match c.method {
            1 => hypoid_methods::method1(c)?,
            2 => hypoid_methods::method2(c)?,
            _ => hypoid_methods::method3(c)?,
        }
    };
    pitch_cone::finish(c, &s6)
}

/// The standard's calculation for one input set.
pub fn blank_design(inputs: &BlankInputs) -> Result<BlankDesign> {
    inputs.validate()?;
    let c = pitch_cone::ConeInputs {
        method: inputs.method,
        sigma: inputs.sigma_deg.to_radians(),
        a: inputs.a_mm,
        z1: inputs.z1 as f64,
        z2: inputs.z2 as f64,
        de2: inputs.de2_mm,
        dm2: inputs.dm2_mm,
        b2: inputs.b2_mm,
        beta_m2: inputs.beta_m2_deg.map(f64::to_radians),
        beta_m1_desired: inputs.beta_m1_desired_deg.map(f64::to_radians),
        rc0: inputs.rc0_mm,
        z0: inputs.z0.map(f64::from),
    };
    let cones = pitch_cones(&c)?;
    let hobbing = match c.z0 {
        Some(z0) => Some(pitch_cone::hobbing(z0, c.z2, c.rc0, &cones)?),
        None => None,
    };
    let factors = inputs.profile_factors()?;
    let theta = match (inputs.theta_a2_deg, inputs.theta_f2_deg) {
        (Some(a), Some(f)) if inputs.tapered() => (a.to_radians(), f.to_radians()),
        _ => (0.0, 0.0),
    };
    let faces = face_angles::face_angles(&cones, c.sigma, c.a, theta)?;
    let be2 = cones.re2 - cones.rm2;
    // Data type II's outer working depth grows with the sum of the wheel's
    // addendum and dedendum angles (the pinion's nominal addendum angle is
    // the wheel's dedendum angle, uniform clearance).
    let depth = tooth_depth::tooth_depth(&factors, cones.m_mn, (theta.1, theta.0), be2);
    let widths = face_width::face_widths(inputs.method, &cones, c.b2, &faces, &depth)?;
    let spiral = spiral_angles::end_spiral_angles(&cones, &widths, c.rc0, hobbing.as_ref())?;
    let lim = inputs.f_alim * cones.alpha_lim;
    let alpha_n_drive = inputs.alpha_d_drive_deg.to_radians() + lim;
    let alpha_n_coast = inputs.alpha_d_coast_deg.to_radians() - lim;
    let thickness = thickness::thickness(
        &thickness::ThicknessData {
            m_mn: cones.m_mn,
            x_hm1: depth.x_hm1,
            x_smn: factors.x_smn,
            alpha_n_drive,
            alpha_n_coast,
            rm2: cones.rm2,
            re2: cones.re2,
            beta_m: [cones.beta_m1, cones.beta_m2],
            beta_e2: spiral.beta_e2,
            dm: [cones.dm1, cones.dm2],
            delta: [cones.delta1, cones.delta2],
            ham: [depth.ham1, depth.ham2],
        },
        inputs.backlash()?,
    );
    let design = BlankDesign {
        method: inputs.method,
        sigma: c.sigma,
        a: c.a,
        z1: c.z1,
        z2: c.z2,
        rc0: c.rc0,
        z0: c.z0,
        cones,
        faces,
        depth,
        widths,
        hobbing,
        spiral,
        alpha_n_drive,
        alpha_n_coast,
        thickness,
    };
    design.check_finite()?;
    let shift_key = if factors.x_hm1.is_some() {
        "x_hm1"
    } else {
        "c_ham"
    };
    let (land1, land2) = design.outer_top_lands();
    for (member, land) in [("pinion", land1), ("wheel", land2)] {
        if land <= 0.0 {
            return Err(FlankError::Model(format!(
                "blank input `{shift_key}`: pointed teeth, the {member}'s top land at the outer end is {land:.4} mm \
                 (addendum too large for its thickness; change `{shift_key}` or the depth factor)"
            )));
        }
    }
    Ok(design)
}

#[cfg(test)]
mod tests;
