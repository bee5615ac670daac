//! Blank design of spiral bevel and hypoid gears by ISO 23509:2016
//! ("Bevel and hypoid gear geometry"), methods 0–3.
//!
//! One job per file:
//!
//! * [`inputs`]: the input set (clause 6.1 pitch-cone data, clause 7.1
//!   tooth-profile data, data types I and II), read from JSON with the key
//!   names of the Annex F samples; validation errors name the key;
//! * [`pitch_cone`]: clause 6 — method 0 (clause 6.2) and the hypoid
//!   pitch-cone solution of methods 1–3 (clause 6.3: offset angles in the
//!   pitch plane ζ_mp and axial plane ζ_m, spiral angles β_m1, β_m2, pitch
//!   angles, mean cone distances, limit pressure angle α_lim), plus the
//!   face-hobbing quantities ν, λ, ρ_b;
//! * [`tooth_depth`]: clauses 7.3 and 7.4 — addenda, dedenda, clearance and
//!   the face and root angles of tapered (methods 0, 1) and uniform depth
//!   (methods 2, 3);
//! * [`thickness`]: clause 7.8 — mean normal circular thickness;
//! * [`outputs`]: clause 7.6 (inner and outer spiral angles) and clause 7.9
//!   (remaining dimensions: outer and inner pitch diameters, outside
//!   diameters), and the output map with the Annex F key names.
//!
//! What is verified against the two Annex F samples and what is not is in
//! `verification/iso23509_blank/README.md`.

pub mod assembly;
pub mod conjugate;
pub mod cradle_machine;
pub mod cutter;
pub mod ease_off;
pub mod generation;
pub mod inputs;
pub mod outputs;
pub mod pitch_cone;
pub mod thickness;
pub mod tooth_depth;

pub use inputs::BlankInputs;
pub use pitch_cone::{Hobbing, PitchCones};
pub use tooth_depth::ToothDepth;

use crate::error::Result;

/// The result of the blank design (internal units: mm, rad).
#[derive(Clone, Debug, PartialEq)]
pub struct BlankDesign {
    /// Calculation method, 0–3.
    pub method: u8,
    pub cones: PitchCones,
    pub depth: ToothDepth,
    /// Face-hobbing quantities (z0 given).
    pub hobbing: Option<Hobbing>,
    /// Outer cone distance of the pinion R_e1 (clause 7.9, see `outputs`).
    pub re1: f64,
    /// Generated normal pressure angles, drive and coast (clause 7.2).
    pub alpha_n_drive: f64,
    pub alpha_n_coast: f64,
    /// Mean normal circular thicknesses s_mn1, s_mn2.
    pub smn1: f64,
    pub smn2: f64,
    /// Wheel spiral angles at the outer and inner end (face milling only).
    pub beta_e2: Option<f64>,
    pub beta_i2: Option<f64>,
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
        beta_m2: inputs.beta_m2_deg.to_radians(),
        beta_m1_desired: inputs.beta_m1_desired_deg.map(f64::to_radians),
        rc0: inputs.rc0_mm,
        z0: inputs.z0.map(f64::from),
    };
    let cones = if inputs.method == 0 {
        pitch_cone::method0(&c)?
    } else {
        pitch_cone::hypoid(&c)?
    };
    let hobbing = match c.z0 {
        Some(z0) => Some(pitch_cone::hobbing(
            z0,
            c.z2,
            c.rc0,
            cones.m_mn,
            cones.rm2,
            cones.delta2,
            cones.beta_m2,
        )?),
        None => None,
    };
    let factors = inputs.profile_factors()?;
    let theta = match (inputs.theta_a2_deg, inputs.theta_f2_deg) {
        (Some(a), Some(f)) if inputs.tapered() => Some((a.to_radians(), f.to_radians())),
        _ => None,
    };
    let b_out = cones.re2 - cones.rm2;
    let depth = tooth_depth::tooth_depth(&factors, cones.m_mn, theta, b_out);
    let lim = inputs.f_alim * cones.alpha_lim;
    let alpha_n_drive = inputs.alpha_d_drive_deg.to_radians() + lim;
    let alpha_n_coast = inputs.alpha_d_coast_deg.to_radians() - lim;
    let j_mn = thickness::mean_normal_backlash(inputs.backlash()?, cones.rm2, cones.re2);
    let (smn1, smn2) = thickness::mean_normal_thickness(
        cones.m_mn,
        depth.x_hm1,
        factors.x_smn,
        (alpha_n_drive, alpha_n_coast),
        j_mn,
    );
    let re1 = outputs::pinion_outer_cone_distance(&cones);
    let (beta_e2, beta_i2) = if hobbing.is_none() {
        let at =
            |r: f64| outputs::circular_spiral_angle(cones.rm2, cones.beta_m2, inputs.rc0_mm, r);
        (Some(at(cones.re2)), Some(at(cones.re2 - inputs.b2_mm)))
    } else {
        (None, None)
    };
    let design = BlankDesign {
        method: inputs.method,
        cones,
        depth,
        hobbing,
        re1,
        alpha_n_drive,
        alpha_n_coast,
        smn1,
        smn2,
        beta_e2: beta_e2.transpose()?,
        beta_i2: beta_i2.transpose()?,
    };
    design.check_finite()?;
    Ok(design)
}
