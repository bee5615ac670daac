//! Flank modifications (micro-geometry): reliefs, crownings, a helix slope
//! deviation and measured profile deviations, as the material removed normal
//! to the nominal flank.
//!
//! Terms and symbols follow ISO 21771:2007 (flank modifications: tip relief,
//! root relief, profile crowning, lead (helix) crowning, end relief) and DIN
//! 3960 (Kopf-/Fußrücknahme C_a/C_f, Profilballigkeit C_α, Breitenballigkeit
//! C_β, Endrücknahme C_I/C_II); the helix slope deviation f_Hβ is the
//! deviation of ISO 1328-1:2013. Amounts here are **normal to the flank**
//! (mm); ISO 1328-1 measures profile and helix deviations in the transverse
//! plane along the base tangent, which for a helical gear is 1/cos β_b times
//! the normal amount (convert before entering chart values of a helical gear).
//!
//! # Parameters
//!
//! The flank parameter is the unified u of [`crate::mesh::gear_sector`]: the
//! involute roll angle for u ≥ u_form (radius r_b √(1 + u²)); on the trochoidal
//! root fillet u = u_form − t (t ∈ [0, 1] the fillet parameter). Along the
//! profile, lengths are **roll lengths** s = r_b·u (the distance along the
//! line of action from the base tangent point; a length L on the profile is
//! Δu = L / r_b). z ∈ [0, b] is the axial coordinate (mm) of the flank surface
//! [`ToothProfile::surface`].
//!
//! # The offset
//!
//! [`FlankModification::offset`] is o(flank, u, z) = P(flank, u) + L(flank, z),
//! the material removed along the outward normal (mm; the modified flank is
//! nominal − o·n). With s = r_b u, s_SAP = r_b u_SAP (start of active profile),
//! s_a = r_b u_a (tip), on the active profile u_SAP ≤ u ≤ u_a:
//!
//! * **tip relief** C_a over the roll length L_a from the tip: with
//!   x = (s − (s_a − L_a)) / L_a, C_a·x (linear) or C_a·x² (parabolic) for
//!   x > 0, else 0. C_a at the tip, C_a/2 or C_a/4 at mid-zone.
//! * **root relief** C_f over L_f from the SAP: x = ((s_SAP + L_f) − s) / L_f,
//!   C_f·x or C_f·x² for x > 0. C_f at the SAP.
//! * **profile crowning** C_α: a parabola in roll length over the active
//!   profile, zero at its middle s_m = (s_SAP + s_a)/2 and C_α at both ends:
//!   C_α ((s − s_m) / ((s_a − s_SAP)/2))².
//! * **measured profile** (if `measured_profile` is given,
//!   [`super::measured`]): −d(u)·cos β_b with d the measured transverse
//!   deviation (outward positive), interpolated in u. It **adds** to the three
//!   analytic terms above.
//!
//! Only the involute carries profile terms. Between the form circle and the
//! SAP (a flank zone that never touches the mate) the sum of the profile terms
//! runs out linearly in u from its value at u_SAP to 0 at u_form, and on the
//! fillet it is 0, so that the offset is continuous across the form circle.
//! The measured data below u_SAP are therefore not used.
//!
//! The lead terms apply on the whole flank (involute and fillet), with
//! ζ = (z − b/2)/(b/2) ∈ [−1, 1]:
//!
//! * **lead crowning** C_β ζ²: zero in the middle of the face, C_β at both ends.
//! * **helix slope deviation** σ·(f_Hβ/2)·ζ with σ = +1 on [`Flank::Right`],
//!   −1 on [`Flank::Left`]: zero in the middle, ±f_Hβ/2 at the ends. Sign
//!   convention: f_Hβ > 0 removes material from the right flank at z = b and
//!   adds it at z = 0, and the reverse on the left flank, so the tooth is
//!   turned as a whole: its transverse section rotates counter-clockwise seen
//!   from +z as z grows, by Δφ(b) − Δφ(0) = f_Hβ / (r_b cos β_b), the sense of
//!   a right-hand helix ([`ToothProfile::twist_rate`] > 0). f_Hβ > 0 thus
//!   increases the helix angle of a right-hand gear (tan β_b by
//!   f_Hβ/(b cos β_b)), decreases that of a left-hand gear and makes a spur
//!   gear slightly right-handed. The mirroring is what makes it a helix-angle
//!   error; the same sign on both flanks would be a taper of the tooth
//!   thickness. ISO 1328-1 evaluates f_Hβ over L_β (the face width less small
//!   end zones); the linear law here spans the full face width b.
//! * **end relief** C_I = C_II over the length L_e from each face end: with
//!   x = (L_e − z)/L_e at z < L_e and x = (z − (b − L_e))/L_e at z > b − L_e,
//!   C·x (linear) or C·x² (parabolic).
//!
//! Arguments outside the flank are clamped: u to at most u_a, z to [0, b].
//!
//! # Smoothness
//!
//! o is continuous in (u, z) everywhere. It is not differentiable (a kink) at
//! the start of a linear relief zone (tip, root or end relief; a parabolic
//! relief is C¹ there, only its curvature jumps), at u_SAP and u_form (where
//! the profile terms start to run out and where they reach 0), at the ends
//! of the measured range (where the measured offset is held constant), and
//! at the clamps u = u_a, z ∈ {0, b} (one-sided derivatives are used there).
//! The measured offset is C¹ inside its range (piecewise cubic Hermite).

use std::path::PathBuf;

use serde::Deserialize;

use super::measured::MeasuredProfile;
use super::rack::{Flank, ToothProfile};
use crate::error::FlankError;

type Result<T> = std::result::Result<T, FlankError>;

/// Shape of a relief (amount as a function of the distance into the relief zone).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ReliefShape {
    /// C·x: proportional to the distance into the zone.
    Linear,
    /// C·x²: tangent to the unmodified flank at the start of the zone.
    Parabolic,
}

/// One relief: the amount removed at the end of the flank (mm), the length
/// of the zone it is spread over (mm) and its shape.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Relief {
    pub amount: f64,
    pub length: f64,
    pub shape: ReliefShape,
}

impl Relief {
    /// Amount and derivative d/dx at the fraction x ∈ [0, 1] into the zone
    /// (x ≤ 0: outside the zone, 0).
    fn at(&self, x: f64) -> (f64, f64) {
        if !(x > 0.0) {
            return (0.0, 0.0);
        }
        match self.shape {
            ReliefShape::Linear => (self.amount * x, self.amount),
            ReliefShape::Parabolic => (self.amount * x * x, 2.0 * self.amount * x),
        }
    }
}

/// Flank modifications of one gear, internal units (mm), as given in a scene
/// (`[<gear>.micro]`); definitions in the module docs.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct MicroGeometry {
    /// Tip relief C_a, over a length along the profile (roll length) from the tip.
    pub tip_relief: Option<Relief>,
    /// Root relief C_f, over a length along the profile from the start of active profile.
    pub root_relief: Option<Relief>,
    /// Profile crowning C_α (mm, ≥ 0).
    pub profile_crowning: f64,
    /// Lead crowning C_β (mm, ≥ 0).
    pub lead_crowning: f64,
    /// Helix slope deviation f_Hβ (mm, signed; sign convention in the module docs).
    pub helix_slope_deviation: f64,
    /// End relief C_I/C_II at both ends of the face width, over a length along the face.
    pub end_relief: Option<Relief>,
    /// Measured profile (CSV, [`super::measured`]); a scene resolves it against
    /// its own folder.
    pub measured_profile: Option<PathBuf>,
}

/// Roll angle at radius r on an involute of base radius r_b: u = √((r/r_b)² − 1).
///
/// Use it for the start of active profile:
/// `roll_angle_at_radius(r_b, check_pair(..)?.pinion.active_start_radius)`.
/// A radius below r_b by no more than 1e-12·r_b (round-off) gives 0; further
/// below, or non-finite, is an error.
pub fn roll_angle_at_radius(base_radius: f64, r: f64) -> Result<f64> {
    if !(base_radius.is_finite() && base_radius > 0.0 && r.is_finite()) {
        return Err(FlankError::Model(format!(
            "roll angle at radius {r} mm on base radius {base_radius} mm: finite positive radii are needed"
        )));
    }
    let q = r / base_radius;
    if q < 1.0 - 1e-12 {
        return Err(FlankError::Model(format!(
            "roll angle at radius {r} mm: the involute exists only at radii ≥ r_b = {base_radius} mm"
        )));
    }
    Ok((q * q - 1.0).max(0.0).sqrt())
}

/// The flank modification of one gear, ready to evaluate: a [`MicroGeometry`]
/// bound to the gear's profile, its start of active profile and face width.
#[derive(Clone, Debug, PartialEq)]
pub struct FlankModification {
    micro: MicroGeometry,
    measured: Option<MeasuredProfile>,
    warnings: Vec<String>,
    base_radius: f64,
    cos_base_helix: f64,
    u_form: f64,
    u_sap: f64,
    u_tip: f64,
    face_width: f64,
}

impl FlankModification {
    /// Bind `micro` to a gear: its `profile`, the roll angle `u_sap` of the
    /// start of active profile (see [`roll_angle_at_radius`]) and the face
    /// width b (mm). Reads the measured profile if one is named.
    ///
    /// Errors ([`FlankError::Model`], or the CSV's errors): non-finite or
    /// negative amounts, non-positive lengths; u_SAP outside [u_form, u_a);
    /// a tip or root relief longer than the active profile, or the two zones
    /// overlapping; an end relief longer than b/2; a profile modification at
    /// u_SAP when the SAP lies on the form circle (no room for the run-out,
    /// the flank would step there).
    pub fn new(
        micro: &MicroGeometry,
        profile: &ToothProfile,
        u_sap: f64,
        face_width: f64,
    ) -> Result<Self> {
        fn err<T>(m: String) -> Result<T> {
            Err(FlankError::Model(format!("flank modification: {m}")))
        }
        let rb = profile.geometry.base_radius;
        let (u_form, u_tip) = (profile.u_form, profile.u_tip);
        if !(face_width.is_finite() && face_width > 0.0) {
            return err(format!(
                "face width {face_width} mm: a finite positive value is needed"
            ));
        }
        // check_pair accepts a SAP up to 1e-9 r_b (roll length) below the form circle
        let slack = 1e-9;
        if !(u_sap.is_finite() && u_sap >= u_form - slack && u_sap < u_tip) {
            return err(format!(
                "start of active profile u_SAP = {u_sap} rad (radius {:.6} mm) is outside the involute [u_form, u_a) = [{u_form:.6}, {u_tip:.6}) rad",
                rb * (1.0 + u_sap * u_sap).sqrt()
            ));
        }
        let u_sap = u_sap.max(u_form);
        let active = rb * (u_tip - u_sap);
        let check_relief = |r: &Option<Relief>, what: &str| -> Result<f64> {
            match r {
                None => Ok(0.0),
                Some(r) => {
                    if !(r.amount.is_finite() && r.amount >= 0.0) {
                        return err(format!(
                            "{what} amount {} mm: a finite value ≥ 0 is needed",
                            r.amount
                        ));
                    }
                    if !(r.length.is_finite() && r.length > 0.0) {
                        return err(format!(
                            "{what} length {} mm: a finite positive value is needed",
                            r.length
                        ));
                    }
                    Ok(r.length)
                }
            }
        };
        let la = check_relief(&micro.tip_relief, "tip relief")?;
        let lf = check_relief(&micro.root_relief, "root relief")?;
        let le = check_relief(&micro.end_relief, "end relief")?;
        let tol = 1e-9 * rb;
        for (l, what) in [(la, "tip relief"), (lf, "root relief")] {
            if l > active + tol {
                return err(format!(
                    "{what} length {l} mm exceeds the active profile's roll length {active:.6} mm (from the SAP at radius {:.6} mm to the tip at {:.6} mm)",
                    rb * (1.0 + u_sap * u_sap).sqrt(),
                    profile.geometry.tip_radius
                ));
            }
        }
        if la + lf > active + tol {
            return err(format!(
                "tip relief ({la} mm) and root relief ({lf} mm) zones overlap: together they exceed the active profile's roll length {active:.6} mm"
            ));
        }
        if le > 0.5 * face_width * (1.0 + 1e-12) {
            return err(format!(
                "end relief length {le} mm: the reliefs at both ends must fit the face width {face_width} mm (≤ b/2)"
            ));
        }
        for (v, what, signed) in [
            (micro.profile_crowning, "profile crowning", false),
            (micro.lead_crowning, "lead crowning", false),
            (micro.helix_slope_deviation, "helix slope deviation", true),
        ] {
            if !(v.is_finite() && (signed || v >= 0.0)) {
                return err(format!(
                    "{what} {v} mm: a finite value{} is needed",
                    if signed { "" } else { " ≥ 0" }
                ));
            }
        }
        let mut warnings = Vec::new();
        let measured = match &micro.measured_profile {
            Some(path) => {
                let m = MeasuredProfile::read(path, profile)?;
                warnings.extend(m.notes().iter().cloned());
                warnings.extend(m.coverage_warnings(u_sap, u_tip, rb));
                Some(m)
            }
            None => None,
        };
        let mut out = FlankModification {
            micro: micro.clone(),
            measured,
            warnings,
            base_radius: rb,
            cos_base_helix: profile.geometry.base_helix_angle.cos(),
            u_form,
            u_sap,
            u_tip,
            face_width,
        };
        if u_sap - u_form < 1e-9 {
            for f in [Flank::Left, Flank::Right] {
                let p = out.active_profile_terms(f, u_sap).0;
                if p != 0.0 {
                    return err(format!(
                        "the start of active profile lies on the form circle (radius {:.6} mm) and the profile modification there is {:.3e} mm on the {f:?} flank: with no room to run out the flank would step at the form circle",
                        profile.geometry.form_radius, p
                    ));
                }
            }
            out.u_sap = u_form;
        }
        Ok(out)
    }

    /// Material removed normal to the flank at (u, z) (mm): ≥ 0 for reliefs
    /// and crownings, signed for f_Hβ and measured deviations. u is the unified
    /// flank parameter (roll angle on the involute, u_form − t on the fillet),
    /// z ∈ [0, b] the axial position. Definitions in the module docs.
    pub fn offset(&self, flank: Flank, u: f64, z: f64) -> f64 {
        self.offset_with_gradient(flank, u, z)[0]
    }

    /// [o, ∂o/∂u, ∂o/∂z] at (u, z): the offset and its gradient (mm, mm/rad,
    /// mm/mm). At a kink (module docs) one side's derivative is returned: at
    /// u_form and u_SAP the side above (u ≥ u_form is the involute, u ≥ u_SAP
    /// the active profile); at the start of a relief zone the unmodified side;
    /// at the ends of a measured range and at the clamps the inner side.
    pub fn offset_with_gradient(&self, flank: Flank, u: f64, z: f64) -> [f64; 3] {
        let (p, pu) = self.profile_terms(flank, u);
        let (l, lz) = self.lead_terms(flank, z);
        [p + l, pu, lz]
    }

    /// Profile part P(flank, u) and dP/du (involute only; run-out below the SAP).
    pub fn profile_terms(&self, flank: Flank, u: f64) -> (f64, f64) {
        if !(u >= self.u_form) {
            return (0.0, 0.0);
        }
        if u >= self.u_sap {
            return self.active_profile_terms(flank, u);
        }
        // run-out on [u_form, u_SAP): linear from P(u_SAP) to 0
        let w = self.u_sap - self.u_form;
        let p0 = self.active_profile_terms(flank, self.u_sap).0;
        (p0 * (u - self.u_form) / w, p0 / w)
    }

    /// Profile terms on the active profile, u clamped to [u_SAP, u_a].
    fn active_profile_terms(&self, flank: Flank, u: f64) -> (f64, f64) {
        let beyond = u > self.u_tip;
        let u = u.clamp(self.u_sap, self.u_tip);
        let rb = self.base_radius;
        let s = rb * u;
        let (s_sap, s_a) = (rb * self.u_sap, rb * self.u_tip);
        let (mut p, mut ds) = (0.0, 0.0);
        if let Some(r) = &self.micro.tip_relief {
            let (a, d) = r.at((s - (s_a - r.length)) / r.length);
            p += a;
            ds += d / r.length;
        }
        if let Some(r) = &self.micro.root_relief {
            let (a, d) = r.at(((s_sap + r.length) - s) / r.length);
            p += a;
            ds -= d / r.length;
        }
        let ca = self.micro.profile_crowning;
        if ca != 0.0 {
            let h = 0.5 * (s_a - s_sap);
            let x = (s - 0.5 * (s_sap + s_a)) / h;
            p += ca * x * x;
            ds += 2.0 * ca * x / h;
        }
        let mut pu = ds * rb;
        if let Some(m) = &self.measured {
            let (d, dd) = m.deviation(flank, u);
            p -= d * self.cos_base_helix;
            pu -= dd * self.cos_base_helix;
        }
        // the clamp at the tip: one-sided (inner) derivative at u_a, 0 beyond
        if beyond {
            pu = 0.0;
        }
        (p, pu)
    }

    /// Lead part L(flank, z) and dL/dz (z clamped to [0, b]).
    pub fn lead_terms(&self, flank: Flank, z: f64) -> (f64, f64) {
        let b = self.face_width;
        let outside = !(0.0..=b).contains(&z);
        let z = z.clamp(0.0, b);
        let h = 0.5 * b;
        let zeta = (z - h) / h;
        let cb = self.micro.lead_crowning;
        let mut l = cb * zeta * zeta;
        let mut dl = 2.0 * cb * zeta / h;
        let sigma = match flank {
            Flank::Right => 1.0,
            Flank::Left => -1.0,
        };
        let f = self.micro.helix_slope_deviation;
        l += sigma * 0.5 * f * zeta;
        dl += sigma * 0.5 * f / h;
        if let Some(r) = &self.micro.end_relief {
            let le = r.length;
            let (a, d) = r.at((le - z) / le);
            l += a;
            dl -= d / le;
            let (a, d) = r.at((z - (b - le)) / le);
            l += a;
            dl += d / le;
        }
        if outside {
            dl = 0.0;
        }
        (l, dl)
    }

    /// The modifications this was built from.
    pub fn micro(&self) -> &MicroGeometry {
        &self.micro
    }

    /// The measured profile, if one was given.
    pub fn measured(&self) -> Option<&MeasuredProfile> {
        self.measured.as_ref()
    }

    /// Warnings from building (measured range not covering the active
    /// profile, a mirrored side); empty when all is as expected.
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }

    /// Roll angles (u_form, u_SAP, u_a) (rad).
    pub fn roll_angles(&self) -> (f64, f64, f64) {
        (self.u_form, self.u_sap, self.u_tip)
    }

    /// Face width b (mm).
    pub fn face_width(&self) -> f64 {
        self.face_width
    }

    /// True if the offset is 0 everywhere (no modification given).
    pub fn is_zero(&self) -> bool {
        let m = &self.micro;
        let zero = |r: &Option<Relief>| r.is_none_or(|r| r.amount == 0.0);
        zero(&m.tip_relief)
            && zero(&m.root_relief)
            && zero(&m.end_relief)
            && m.profile_crowning == 0.0
            && m.lead_crowning == 0.0
            && m.helix_slope_deviation == 0.0
            && self.measured.is_none()
    }
}

/// Gears of the paper scenes for the tests of this module and its neighbours.
#[cfg(test)]
pub(crate) mod test_gears {
    use super::super::pair::check_pair;
    use super::super::rack::ToothProfile;
    use super::roll_angle_at_radius;
    use std::path::{Path, PathBuf};

    pub fn papers() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("papers")
    }

    /// (profile, u_SAP) of gear `which` (0 pinion, 1 gear) of a paper scene
    /// ("seed002-spur", "seed004-helical").
    pub fn gear(scene: &str, which: usize) -> (ToothProfile, f64) {
        let s = crate::scene::read_scene(&papers().join(scene).join("scene.toml")).unwrap();
        let r = check_pair(&s.cylindrical("this test").unwrap().pair).unwrap();
        let (spec, rep, name) = if which == 0 {
            (
                &s.cylindrical("this test").unwrap().pair.pinion,
                &r.pinion,
                "pinion",
            )
        } else {
            (
                &s.cylindrical("this test").unwrap().pair.gear,
                &r.gear,
                "gear",
            )
        };
        let tp = ToothProfile::new(spec, name).unwrap();
        let u = roll_angle_at_radius(tp.geometry.base_radius, rep.active_start_radius).unwrap();
        (tp, u)
    }
}

#[cfg(test)]
mod tests {
    use super::test_gears::gear;
    use super::*;

    const FLANKS: [Flank; 2] = [Flank::Left, Flank::Right];

    fn relief(amount: f64, length: f64, shape: ReliefShape) -> Option<Relief> {
        Some(Relief {
            amount,
            length,
            shape,
        })
    }

    fn build(m: &MicroGeometry, scene: &str, which: usize) -> (FlankModification, ToothProfile) {
        let (tp, u_sap) = gear(scene, which);
        let fm = FlankModification::new(m, &tp, u_sap, tp.face_width).unwrap();
        (fm, tp)
    }

    fn close(a: f64, b: f64, tol: f64) -> bool {
        (a - b).abs() <= tol
    }

    #[test]
    fn roll_angle_helper() {
        let (tp, u_sap) = gear("seed002-spur", 0);
        let rb = tp.geometry.base_radius;
        let u = roll_angle_at_radius(rb, tp.geometry.tip_radius).unwrap();
        assert!(close(u, tp.u_tip, 1e-14));
        assert!(u_sap > tp.u_form && u_sap < tp.u_tip);
        assert_eq!(roll_angle_at_radius(rb, rb).unwrap(), 0.0);
        assert_eq!(roll_angle_at_radius(rb, rb * (1.0 - 1e-14)).unwrap(), 0.0);
        assert!(roll_angle_at_radius(rb, 0.99 * rb).is_err());
        assert!(roll_angle_at_radius(rb, f64::NAN).is_err());
        assert!(roll_angle_at_radius(0.0, 1.0).is_err());
    }

    #[test]
    fn zero_modification() {
        let (fm, tp) = build(&MicroGeometry::default(), "seed002-spur", 0);
        assert!(fm.is_zero());
        assert!(fm.warnings().is_empty());
        for f in FLANKS {
            for u in [tp.u_form - 1.0, tp.u_form - 0.3, tp.u_form, tp.u_tip] {
                for z in [0.0, 3.0, tp.face_width] {
                    assert_eq!(fm.offset_with_gradient(f, u, z), [0.0; 3]);
                }
            }
        }
    }

    /// Tip relief: C_a at the tip, C_a/2 (linear) or C_a/4 (parabolic) at mid-zone, 0 below.
    #[test]
    fn tip_relief_closed_form() {
        for scene in ["seed002-spur", "seed004-helical"] {
            for (shape, mid) in [(ReliefShape::Linear, 0.5), (ReliefShape::Parabolic, 0.25)] {
                let ca = 0.010;
                let la = 1.2;
                let m = MicroGeometry {
                    tip_relief: relief(ca, la, shape),
                    ..Default::default()
                };
                let (fm, tp) = build(&m, scene, 0);
                let rb = tp.geometry.base_radius;
                let u_start = tp.u_tip - la / rb;
                for f in FLANKS {
                    assert!(close(fm.offset(f, tp.u_tip, 5.0), ca, 1e-15));
                    let u_mid = tp.u_tip - 0.5 * la / rb;
                    assert!(close(fm.offset(f, u_mid, 5.0), mid * ca, 1e-15));
                    assert!(close(fm.offset(f, u_start, 5.0), 0.0, 1e-15));
                    assert_eq!(fm.offset(f, u_start - 0.01, 5.0), 0.0);
                    assert_eq!(fm.offset(f, tp.u_form - 0.5, 5.0), 0.0);
                    // three quarters into the zone
                    let u34 = tp.u_tip - 0.25 * la / rb;
                    let want = match shape {
                        ReliefShape::Linear => 0.75 * ca,
                        ReliefShape::Parabolic => 0.5625 * ca,
                    };
                    assert!(close(fm.offset(f, u34, 1.0), want, 1e-15));
                    // held beyond the tip
                    assert!(close(fm.offset(f, tp.u_tip + 0.1, 5.0), ca, 1e-15));
                }
            }
        }
    }

    #[test]
    fn root_relief_closed_form() {
        for (shape, mid) in [(ReliefShape::Linear, 0.5), (ReliefShape::Parabolic, 0.25)] {
            let cf = 0.008;
            let lf = 0.9;
            let m = MicroGeometry {
                root_relief: relief(cf, lf, shape),
                ..Default::default()
            };
            let (fm, tp) = build(&m, "seed002-spur", 0);
            let rb = tp.geometry.base_radius;
            let (uf, us, _) = fm.roll_angles();
            for f in FLANKS {
                assert!(close(fm.offset(f, us, 0.0), cf, 1e-15));
                assert!(close(
                    fm.offset(f, us + 0.5 * lf / rb, 0.0),
                    mid * cf,
                    1e-15
                ));
                assert!(close(fm.offset(f, us + lf / rb, 0.0), 0.0, 1e-15));
                assert_eq!(fm.offset(f, us + lf / rb + 0.01, 0.0), 0.0);
                // run-out below the SAP: linear to 0 at the form circle, 0 on the fillet
                assert!(close(fm.offset(f, 0.5 * (uf + us), 0.0), 0.5 * cf, 1e-15));
                assert_eq!(fm.offset(f, uf, 0.0), 0.0);
                assert_eq!(fm.offset(f, uf - 0.2, 0.0), 0.0);
            }
        }
    }

    #[test]
    fn profile_crowning_symmetric() {
        let c = 0.006;
        let m = MicroGeometry {
            profile_crowning: c,
            ..Default::default()
        };
        let (fm, tp) = build(&m, "seed002-spur", 1);
        let (_, us, ut) = fm.roll_angles();
        let um = 0.5 * (us + ut);
        for f in FLANKS {
            assert!(close(fm.offset(f, us, 2.0), c, 1e-15));
            assert!(close(fm.offset(f, ut, 2.0), c, 1e-15));
            assert!(close(fm.offset(f, um, 2.0), 0.0, 1e-15));
            for k in 1..10 {
                let d = 0.1 * k as f64 * 0.5 * (ut - us);
                let (a, b) = (fm.offset(f, um + d, 2.0), fm.offset(f, um - d, 2.0));
                assert!(close(a, b, 1e-15), "{a} vs {b}");
                assert!(close(a, c * (0.1 * k as f64).powi(2), 1e-15));
            }
        }
        assert!(tp.u_form < us);
    }

    #[test]
    fn lead_crowning_and_end_relief() {
        for (shape, mid) in [(ReliefShape::Linear, 0.5), (ReliefShape::Parabolic, 0.25)] {
            let (cb, ce, le) = (0.012, 0.004, 2.0);
            let m = MicroGeometry {
                lead_crowning: cb,
                end_relief: relief(ce, le, shape),
                ..Default::default()
            };
            let (fm, tp) = build(&m, "seed002-spur", 0);
            let b = tp.face_width;
            // lead terms apply on the involute and on the fillet
            for u in [
                tp.u_form - 0.7,
                tp.u_form,
                0.5 * (tp.u_form + tp.u_tip),
                tp.u_tip,
            ] {
                for f in FLANKS {
                    assert!(close(fm.offset(f, u, 0.0), cb + ce, 1e-15));
                    assert!(close(fm.offset(f, u, b), cb + ce, 1e-15));
                    assert!(close(fm.offset(f, u, 0.5 * b), 0.0, 1e-15));
                    let zeta = |z: f64| (z - 0.5 * b) / (0.5 * b);
                    let lc = |z: f64| cb * zeta(z).powi(2);
                    assert!(close(
                        fm.offset(f, u, 0.5 * le),
                        lc(0.5 * le) + mid * ce,
                        1e-15
                    ));
                    assert!(close(
                        fm.offset(f, u, b - 0.5 * le),
                        lc(b - 0.5 * le) + mid * ce,
                        1e-15
                    ));
                    assert!(close(fm.offset(f, u, le), lc(le), 1e-15));
                    for k in 0..=10 {
                        let z = 0.05 * k as f64 * b;
                        assert!(close(fm.offset(f, u, z), fm.offset(f, u, b - z), 1e-15));
                    }
                }
            }
        }
    }

    /// f_Hβ: ±f/2 at the ends, 0 in the middle, mirrored between the flanks.
    #[test]
    fn helix_slope_sign() {
        for fh in [0.008, -0.005] {
            let m = MicroGeometry {
                helix_slope_deviation: fh,
                ..Default::default()
            };
            let (fm, tp) = build(&m, "seed004-helical", 0);
            let b = tp.face_width;
            let u = 0.5 * (tp.u_form + tp.u_tip);
            assert!(close(fm.offset(Flank::Right, u, b), 0.5 * fh, 1e-15));
            assert!(close(fm.offset(Flank::Right, u, 0.0), -0.5 * fh, 1e-15));
            assert!(close(fm.offset(Flank::Left, u, b), -0.5 * fh, 1e-15));
            assert!(close(fm.offset(Flank::Left, u, 0.0), 0.5 * fh, 1e-15));
            assert!(close(fm.offset(Flank::Right, u, 0.5 * b), 0.0, 1e-15));
            assert!(close(
                fm.offset(Flank::Right, u, 0.75 * b),
                0.25 * fh,
                1e-15
            ));
            let [_, _, dz] = fm.offset_with_gradient(Flank::Right, u, 1.0);
            assert!(close(dz, fh / b, 1e-15));
        }
    }

    /// The offset is continuous across every zone boundary, and its gradient
    /// matches central differences away from them.
    #[test]
    fn continuity_and_gradient() {
        let m = MicroGeometry {
            tip_relief: relief(0.010, 1.0, ReliefShape::Linear),
            root_relief: relief(0.006, 0.8, ReliefShape::Parabolic),
            profile_crowning: 0.004,
            lead_crowning: 0.009,
            helix_slope_deviation: -0.007,
            end_relief: relief(0.003, 1.5, ReliefShape::Linear),
            measured_profile: None,
        };
        for scene in ["seed002-spur", "seed004-helical"] {
            let (fm, tp) = build(&m, scene, 0);
            let rb = tp.geometry.base_radius;
            let b = tp.face_width;
            let (uf, us, ut) = fm.roll_angles();
            let ub = [uf, us, us + 0.8 / rb, ut - 1.0 / rb, ut];
            let zb = [0.0, 1.5, b - 1.5, b];
            let eps = 1e-10;
            let mut max_jump: f64 = 0.0;
            for f in FLANKS {
                for &u in &ub {
                    for z in [0.3, 0.5 * b] {
                        let j = (fm.offset(f, u + eps, z) - fm.offset(f, u - eps, z)).abs();
                        max_jump = max_jump.max(j);
                    }
                }
                for &z in &zb {
                    let u = 0.5 * (us + ut);
                    let j = (fm.offset(f, u, z + eps) - fm.offset(f, u, z - eps)).abs();
                    max_jump = max_jump.max(j);
                }
                // gradient vs central differences on a grid that avoids the kinks
                for i in 0..40 {
                    let u = uf - 0.9 + (ut - uf + 0.9) * (i as f64 + 0.37) / 40.0;
                    if ub.iter().any(|&k| (u - k).abs() < 1e-4) {
                        continue;
                    }
                    for j in 0..9 {
                        let z = b * (j as f64 + 0.41) / 9.0;
                        if zb.iter().any(|&k| (z - k).abs() < 1e-3) {
                            continue;
                        }
                        let [_, gu, gz] = fm.offset_with_gradient(f, u, z);
                        let h = 1e-6;
                        let fu = (fm.offset(f, u + h, z) - fm.offset(f, u - h, z)) / (2.0 * h);
                        let hz = 1e-4;
                        let fz = (fm.offset(f, u, z + hz) - fm.offset(f, u, z - hz)) / (2.0 * hz);
                        assert!(close(gu, fu, 1e-7), "{scene} u = {u}: {gu} vs {fu}");
                        assert!(close(gz, fz, 1e-9), "{scene} z = {z}: {gz} vs {fz}");
                    }
                }
            }
            // slopes are below ~3 mm/rad and ~0.02 mm/mm: a jump would be ≫ 1e-9
            assert!(max_jump < 1e-9, "{scene}: max jump {max_jump:e} mm");
        }
    }

    #[test]
    fn bad_modifications_are_errors() {
        let (tp, us) = gear("seed002-spur", 0);
        let b = tp.face_width;
        let rb = tp.geometry.base_radius;
        let active = rb * (tp.u_tip - us);
        let ok = MicroGeometry::default();
        let bad = |m: MicroGeometry, u_sap: f64, b: f64, want: &str| {
            let e = FlankModification::new(&m, &tp, u_sap, b).unwrap_err();
            assert!(e.to_string().contains(want), "{e}");
        };
        bad(ok.clone(), tp.u_form - 0.01, b, "start of active profile");
        bad(ok.clone(), tp.u_tip, b, "start of active profile");
        bad(ok.clone(), f64::NAN, b, "start of active profile");
        bad(ok.clone(), us, 0.0, "face width");
        let with = |f: &dyn Fn(&mut MicroGeometry)| {
            let mut m = MicroGeometry::default();
            f(&mut m);
            m
        };
        bad(
            with(&|m| m.tip_relief = relief(0.01, active + 0.1, ReliefShape::Linear)),
            us,
            b,
            "exceeds the active profile",
        );
        bad(
            with(&|m| {
                m.tip_relief = relief(0.01, 0.6 * active, ReliefShape::Linear);
                m.root_relief = relief(0.01, 0.6 * active, ReliefShape::Linear);
            }),
            us,
            b,
            "overlap",
        );
        bad(
            with(&|m| m.tip_relief = relief(-0.01, 1.0, ReliefShape::Linear)),
            us,
            b,
            "tip relief amount",
        );
        bad(
            with(&|m| m.root_relief = relief(0.01, 0.0, ReliefShape::Linear)),
            us,
            b,
            "root relief length",
        );
        bad(
            with(&|m| m.end_relief = relief(0.01, 0.6 * b, ReliefShape::Linear)),
            us,
            b,
            "b/2",
        );
        bad(with(&|m| m.lead_crowning = -1e-3), us, b, "lead crowning");
        bad(
            with(&|m| m.helix_slope_deviation = f64::INFINITY),
            us,
            b,
            "helix slope",
        );
        // SAP on the form circle: fine without profile terms, an error with them
        assert!(FlankModification::new(&ok, &tp, tp.u_form, b).is_ok());
        bad(
            with(&|m| m.profile_crowning = 1e-3),
            tp.u_form,
            b,
            "form circle",
        );
        // the slack check_pair allows below the form circle is accepted and clamped
        let fm = FlankModification::new(&ok, &tp, tp.u_form - 1e-10, b).unwrap();
        assert_eq!(fm.roll_angles().1, tp.u_form);
    }

    #[test]
    fn scene_conversion_helper() {
        let path = super::test_gears::papers().join("seed002-spur/scene.toml");
        let text = std::fs::read_to_string(&path).unwrap();
        let text = text.replace(
            "material = \"15NiMoCr10\"\n\n[gear]",
            "material = \"15NiMoCr10\"\n[pinion.micro]\ntip_relief_um = 10.0\ntip_relief_length_mm = 1.0\nlead_crowning_um = 4.0\n\n[gear]",
        );
        let s = crate::scene::parse_scene(&text, &path).unwrap();
        let [p, g] = s
            .cylindrical("this test")
            .unwrap()
            .flank_modifications()
            .unwrap();
        assert!(g.is_none());
        let p = p.unwrap();
        let (tp, _) = gear("seed002-spur", 0);
        assert!(close(p.offset(Flank::Left, tp.u_tip, 0.0), 0.014, 1e-15));
        assert!(close(p.offset(Flank::Right, tp.u_tip, 6.65), 0.010, 1e-15));
    }
}
