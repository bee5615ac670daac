//! The pinion flank conjugate to a given gear flank: the envelope of the
//! gear's tooth surface in the pair's meshing motion (Litvin & Fuentes,
//! *Gear Geometry and Applied Theory*, 2nd ed., ch. 6 "envelope to a family
//! of surfaces" and §22.6, where the pinion of a hypoid pair is generated
//! by the gear's surface).
//!
//! The family: gear flank r₂(u₂, v₂) (gear frame) carried by the gear
//! rotation φ₂, seen in the pinion frame while the pinion turns by
//! φ₁ = m φ₂ ([`PairAssembly::roll_ratio`]):
//!
//! r(q) = F₁(m φ₂)⁻¹ F₂(φ₂) r₂(u₂, v₂),  q = (u₂, v₂, φ₂),
//!
//! with F₁, F₂ the nominal member frames of [`PairAssembly`]. Writing
//! x = F₂ r₂ (housing) and R₁ the pinion's rotation, the derivatives are
//! exact in closed form from the gear's first and second derivatives:
//! r_u₂ = R₁ᵀ R₂ r₂,u, r_φ₂ = R₁ᵀ v⁽²¹⁾(x) (the relative velocity, Ω × x + b),
//! r_u₂φ₂ = R₁ᵀ (Ω × x_u), r_φ₂φ₂ = R₁ᵀ (Ω × (k₂ × (x − a₂)) − m k₁ × v⁽²¹⁾).
//! The family is an [`EnvelopeMap`] of the generic envelope engine
//! ([`crate::geometry::bevel::generation`]); the surface point at (u, v)
//! solves the equation of meshing n · v⁽²¹⁾ = 0 together with the pinion's
//! axial-section target (z, ρ) of (u, v), and the tangents follow by the
//! implicit function theorem ([`EnvelopePoint::section_tangent`]). The
//! Newton solve is the engine's ([`solve_axial`]) with the meshing row
//! scaled by a fixed length ([`ConjugateMap::meshing_length`]): n·v⁽²¹⁾ in
//! mm, not a residual normalised by |v⁽²¹⁾|, which is 0/0 on the
//! instantaneous axis — the whole pitch line of a pair with E = 0, where
//! the relative velocity vanishes.
//!
//! **Parameters** as for every bevel flank: the pinion's axial section, v the
//! cone distance along the pitch-cone generatrix (toe → heel), u normal to
//! it in the axial plane (root → tip). Boundaries: toe and heel v = R_i1,
//! R_e1 (the front and back cones are normal to the pitch cone, so they are
//! lines v = const of the section); face cone u_tip(v) = h_am1 + (v − R_m1)
//! tan θ_a1; root cone u_root(v) = −h_fm1 − (v − R_m1) tan θ_f1; u_form is
//! the higher of the root line raised by the clearance c and the line the
//! gear's **tip edge** touches (the contact's gear point at u₂ =
//! u_tip2(v₂); below it the pinion meets only the gear's edge, and the
//! envelope of the gear flank's extension beyond its tip may fold: Litvin &
//! Fuentes §6.3). Below u_form the surface is the tangent continuation of
//! the envelope, not the fillet the gear's tip edge would cut.
//!
//! **Outward normal**: the pinion's material lies on the other side of the
//! contact, so its outward normal is −n₂ (housing).
//!
//! **Roll angle of a point**: the pinion rotation φ₁ = m φ₂ at which the
//! point is in contact ([`ConjugatePoint::roll`]), what the parabolic
//! transmission-error ease-off needs.
//!
//! Each evaluation is a bounded Newton solve started from a seed table
//! (9 × 9 solutions over the active flank, form line to tip line, built at
//! construction by continuation from the mean point; a node it cannot
//! reach — a limit line, a gear flank that does not mesh there — is an
//! error); a point the solve cannot reach later is counted
//! ([`ConjugatePinion::failures`]) and the seed point returned, so an
//! analysis can tell. [`ConjugatePinion::conjugate_point`] gives the
//! `Result`.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;

use crate::error::{FlankError, Result};
use crate::geometry::bevel::assembly::PairAssembly;
use crate::geometry::bevel::generation::{
    solve_axial, AxialSection, ConeLine, EnvelopeError, EnvelopeMap, EnvelopePoint, Jet,
    SolveOptions,
};
use crate::geometry::bevel::{BlankDesign, BlankInputs};
use crate::geometry::frame::Frame;
use crate::geometry::gear_pair::Misalignment;
use crate::geometry::surface::ToothSurface;
use crate::geometry::vec3::{add, cross, dot, norm, sub, V3};

/// The meshing motion as a one-parameter family (module docs).
#[derive(Debug, Clone)]
pub struct ConjugateMap {
    gear: Arc<dyn ToothSurface>,
    assembly: PairAssembly,
    ratio: f64,
    orientation: f64,
    /// |r₂,u × r₂,v| at the middle of the gear's parameter box: the fixed
    /// reference of the meshing row ([`EnvelopeMap::meshing_length`]).
    reference_area: f64,
}

fn scale(s: f64, a: V3) -> V3 {
    [s * a[0], s * a[1], s * a[2]]
}

impl ConjugateMap {
    /// The family for `gear` in the nominal `assembly`. The orientation
    /// (pinion outward = −gear outward) is read at the middle of the gear's
    /// parameter box.
    pub fn new(gear: Arc<dyn ToothSurface>, assembly: &PairAssembly) -> Self {
        let assembly = PairAssembly {
            misalignment: Misalignment::default(),
            ..*assembly
        };
        let (u0, u1) = gear.u_range();
        let (v0, v1) = gear.v_range();
        let (um, vm) = (0.5 * (u0 + u1), 0.5 * (v0 + v1));
        let (_, n, pu, pv) = gear.evaluate(um, vm);
        let orientation = if dot(n, cross(pu, pv)) >= 0.0 {
            -1.0
        } else {
            1.0
        };
        ConjugateMap {
            ratio: assembly.roll_ratio(),
            gear,
            assembly,
            orientation,
            reference_area: norm(cross(pu, pv)),
        }
    }

    /// The frames (own → housing) at gear rotation φ₂.
    pub fn frames(&self, phi2: f64) -> [Frame; 2] {
        self.assembly.nominal_frames(self.ratio * phi2, phi2)
    }
}

impl EnvelopeMap for ConjugateMap {
    fn jet(&self, q: [f64; 3]) -> Jet {
        let [f1, f2] = self.frames(q[2]);
        let (x2, _, r2u, r2v) = self.gear.evaluate(q[0], q[1]);
        let [r2uu, r2uv, r2vv] = self.gear.second_derivatives(q[0], q[1]);
        let (omega, b) = self.assembly.relative_motion();
        let k1 = self.assembly.pinion_axis();
        let k2 = self.assembly.gear_axis();
        let x = f2.place(x2);
        let w = add(cross(omega, x), 1.0, b);
        let xu = f2.rotate(r2u);
        let xv = f2.rotate(r2v);
        let back = |v: V3| f1.rotate_back(v);
        let vel2 = cross(k2, sub(x, f2.translation));
        let wphi = add(cross(omega, vel2), -self.ratio, cross(k1, w));
        let d1 = [back(xu), back(xv), back(w)];
        let d2 = [
            [
                back(f2.rotate(r2uu)),
                back(f2.rotate(r2uv)),
                back(cross(omega, xu)),
            ],
            [
                back(f2.rotate(r2uv)),
                back(f2.rotate(r2vv)),
                back(cross(omega, xv)),
            ],
            [back(cross(omega, xu)), back(cross(omega, xv)), back(wphi)],
        ];
        Jet {
            r: f1.rotate_back(sub(x, f1.translation)),
            d1,
            d2,
        }
    }

    fn normal_orientation(&self) -> f64 {
        self.orientation
    }

    /// f/L = n₂·v⁽²¹⁾ |r₂,u × r₂,v| / L, L the gear's |r₂,u × r₂,v| at the
    /// middle of its box: mm, and regular where v⁽²¹⁾ = 0 (the pitch line
    /// of a pair with E = 0 is the instantaneous axis).
    fn meshing_length(&self) -> Option<f64> {
        Some(self.reference_area)
    }

    /// 0.2 rad of gear rotation: bounds a wild step from a poor start (the
    /// gear turns through the whole active flank of a tooth in about one
    /// angular pitch 2π/z₂ times the contact ratio, 0.2–0.4 rad for the
    /// Annex F sets; a converging step from a seed is far smaller).
    fn max_roll_step(&self) -> f64 {
        MAX_ROLL_STEP
    }
}

/// [`ConjugateMap::max_roll_step`] (rad).
const MAX_ROLL_STEP: f64 = 0.2;

/// Everything at one pinion point (own frame).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConjugatePoint {
    pub point: V3,
    /// Unit outward normal.
    pub normal: V3,
    /// ∂r/∂u, ∂r/∂v.
    pub r_u: V3,
    pub r_v: V3,
    /// ∂n/∂u, ∂n/∂v (exact where the gear's second derivatives are).
    pub n_u: V3,
    pub n_v: V3,
    /// Pinion rotation φ₁ = m φ₂ at which the point is in contact, and its
    /// derivatives in u and v.
    pub roll: f64,
    pub roll_u: f64,
    pub roll_v: f64,
    /// The gear parameters (u₂, v₂) of the contact and the gear rotation φ₂.
    pub gear_q: [f64; 3],
    /// Dimensionless meshing residual n₂·v⁽²¹⁾ / R_m1 (v⁽²¹⁾ per unit φ₂).
    pub meshing_residual: f64,
    /// True on the envelope, false on the continuation below the form line.
    pub conjugate: bool,
}

/// The conjugate pinion flank (module docs).
#[derive(Debug)]
pub struct ConjugatePinion {
    map: ConjugateMap,
    section: AxialSection,
    form: ConeLine,
    /// u of the form line at [`EDGE_NODES`] cone distances toe → heel where
    /// the gear's tip edge touches above the clearance line (None: it
    /// touches below it everywhere; the form line is `form`).
    edge_form: Option<Vec<f64>>,
    /// Seed table: q at (u_i, v_j), i over `nu` values of the u box.
    seeds: Vec<[f64; 3]>,
    u_box: (f64, f64),
    v_box: (f64, f64),
    failures: AtomicUsize,
}

/// Seed-table size per direction.
const SEED_NODES: usize = 9;
/// Newton's step bound per point.
pub const MAX_NEWTON: usize = 50;
/// Newton's tolerance on z, ρ and the length-scaled meshing row (mm).
pub const TOL_POSITION: f64 = 1e-11;
/// Continuation sub-steps between two seed nodes.
const SUB_STEPS: usize = 4;
/// Cone distances (toe → heel) at which the gear tip edge's contact line
/// is located.
const EDGE_NODES: usize = 17;

impl ConjugatePinion {
    /// The pinion conjugate to `gear` in `assembly`, bounded by `section`
    /// (pitch angle, toe/heel cone distances, face and root lines) with the
    /// fillet junction `form`.
    ///
    /// Errors when the gear flank and the assembly do not mesh inside the
    /// pinion blank: no solution of the meshing equation at the pinion's
    /// mean point, a mean-point contact outside the gear flank's parameter
    /// box, or a node of the blank the continuation cannot reach.
    pub fn new(
        gear: Arc<dyn ToothSurface>,
        assembly: &PairAssembly,
        section: AxialSection,
        form: ConeLine,
    ) -> Result<Self> {
        let map = ConjugateMap::new(gear, assembly);
        let v_box = section.cone_distance;
        if !(v_box.0 < v_box.1 && v_box.0 > 0.0) {
            return Err(FlankError::Model(format!(
                "conjugate pinion: toe/heel cone distances {v_box:?} are not increasing and positive"
            )));
        }
        let us = [
            section.u_root(v_box.0),
            section.u_root(v_box.1),
            section.u_tip(v_box.0),
            section.u_tip(v_box.1),
        ];
        let u_box = (us[0].min(us[1]), us[2].max(us[3]));
        if !(u_box.0 < u_box.1) {
            return Err(FlankError::Model(
                "conjugate pinion: the face cone lies below the root cone".into(),
            ));
        }
        let mut pinion = ConjugatePinion {
            map,
            section,
            form,
            edge_form: None,
            seeds: Vec::new(),
            u_box,
            v_box,
            failures: AtomicUsize::new(0),
        };
        let q0 = pinion.mean_contact()?;
        pinion.edge_form = pinion.tip_edge_line(q0);
        pinion.seeds = pinion.seed_table(q0)?;
        Ok(pinion)
    }

    /// From the blank design: pitch angle δ₁, R_m1, R_e1 of the blank,
    /// R_i1 = R_m1 − (R_m2 − R_i2)/cos ζ_mp (the gear's toe mapped like the
    /// blank's R_e1), h_am1, h_fm1, θ_a1, θ_f1 and the clearance c.
    pub fn from_blank(
        gear: Arc<dyn ToothSurface>,
        assembly: &PairAssembly,
        inputs: &BlankInputs,
        design: &BlankDesign,
    ) -> Result<Self> {
        let (section, form) = pinion_section(inputs, design);
        Self::new(gear, assembly, section, form)
    }

    /// The gear flank.
    pub fn gear(&self) -> &Arc<dyn ToothSurface> {
        &self.map.gear
    }

    /// The nominal assembly it was generated in.
    pub fn assembly(&self) -> &PairAssembly {
        &self.map.assembly
    }

    /// m = dφ₁/dφ₂.
    pub fn roll_ratio(&self) -> f64 {
        self.map.ratio
    }

    /// The axial section (boundaries).
    pub fn section(&self) -> &AxialSection {
        &self.section
    }

    /// The meshing family (for checks).
    pub fn map(&self) -> &ConjugateMap {
        &self.map
    }

    /// Evaluations that did not converge since construction.
    pub fn failures(&self) -> usize {
        self.failures.load(Ordering::Relaxed)
    }

    fn solve_from(&self, u: f64, v: f64, q0: [f64; 3]) -> Result<EnvelopePoint> {
        let ((z, rho), _, _) = self.section.target(u, v);
        self.newton(z, rho, q0).map_err(|e| {
            FlankError::Model(format!(
                "conjugate pinion at (u, v) = ({u:.4}, {v:.4}) mm: {e}"
            ))
        })
    }

    /// Continuation from (u_a, v_a) with solution q to (u_b, v_b).
    fn walk(&self, q: [f64; 3], a: (f64, f64), b: (f64, f64), steps: usize) -> Result<[f64; 3]> {
        let mut q = q;
        for k in 1..=steps {
            let t = k as f64 / steps as f64;
            let p = self.solve_from(a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1), q)?;
            q = p.q;
        }
        Ok(q)
    }

    /// The contact at the pinion's mean point (u = 0, v = R_m1): started
    /// from the gear point nearest the mean pitch point at φ₂ = 0, then from
    /// a scan of gear rotations if that fails.
    fn mean_contact(&self) -> Result<[f64; 3]> {
        let rm = self.section.mean_cone_distance;
        let ((z, rho), _, _) = self.section.target(0.0, rm);
        let gear = &self.map.gear;
        let (gu, gv) = (gear.u_range(), gear.v_range());
        let mut found = None;
        let z2 = self.map.assembly.teeth[1] as f64;
        for k in 0..=16 {
            // φ₂ = 0, then ± growing multiples of an eighth of the pitch
            let s = if k % 2 == 1 { 1.0 } else { -1.0 };
            let phi2 = s * ((k + 1) / 2) as f64 * std::f64::consts::PI / (4.0 * z2);
            let [f1, f2] = self.map.frames(phi2);
            let target = f2.rotate_back(sub(f1.place([rho, 0.0, z]), f2.translation));
            let (u2, v2, _) = gear.closest_point(target);
            if let Ok(p) = self.newton(z, rho, [u2, v2, phi2]) {
                found = Some(p);
                break;
            }
        }
        let Some(p) = found else {
            return Err(FlankError::Model(
                "conjugate pinion: the gear flank and the assembly do not mesh at the pinion's mean point (no solution of the equation of meshing)".into(),
            ));
        };
        let [u2, v2, _] = p.q;
        let tol = |r: (f64, f64)| 1e-6 * (r.1 - r.0);
        if u2 < gu.0 - tol(gu) || u2 > gu.1 + tol(gu) || v2 < gv.0 - tol(gv) || v2 > gv.1 + tol(gv)
        {
            return Err(FlankError::Model(format!(
                "conjugate pinion: the gear flank and the assembly do not mesh in the pinion blank: \
                 the pinion's mean point is in contact with gear parameters (u, v) = ({u2:.4}, {v2:.4}), \
                 outside the gear flank's box u {gu:?}, v {gv:?}"
            )));
        }
        Ok(p.q)
    }

    /// The length that makes the meshing row dimensionless: R_m1.
    fn length(&self) -> f64 {
        self.section.mean_cone_distance
    }

    /// (z, ρ, n·v⁽²¹⁾) of a jet (mm; v⁽²¹⁾ per unit φ₂).
    fn residual_of(&self, j: &Jet) -> [f64; 3] {
        let nn = cross(j.d1[0], j.d1[1]);
        let n = scale(self.map.orientation / norm(nn), nn);
        [j.r[2], j.r[0].hypot(j.r[1]), dot(n, j.d1[2])]
    }

    /// Unit normal and its derivatives in q (n = o N/|N|, N = r_u₂ × r_v₂).
    fn normal_jet(&self, j: &Jet) -> (V3, [V3; 3]) {
        let nn = cross(j.d1[0], j.d1[1]);
        let len = norm(nn);
        let n = scale(self.map.orientation / len, nn);
        let dn = std::array::from_fn(|k| {
            let dk = add(cross(j.d2[0][k], j.d1[1]), 1.0, cross(j.d1[0], j.d2[1][k]));
            scale(self.map.orientation / len, add(dk, -dot(n, dk), n))
        });
        (n, dn)
    }

    /// The envelope engine's bounded damped Newton
    /// ([`solve_axial`]) on (z(q) − z*, ρ(q) − ρ*, f/L), all three rows in
    /// mm ([`ConjugateMap::meshing_length`]: the row keeps its gradient
    /// where the relative velocity vanishes, the pitch line of a bevel pair
    /// with E = 0). Stops when each row is ≤ [`TOL_POSITION`] mm, errs after
    /// [`MAX_NEWTON`] steps, on a singular Jacobian or a non-finite value.
    fn newton(&self, z: f64, rho: f64, q0: [f64; 3]) -> Result<EnvelopePoint> {
        let opt = SolveOptions {
            max_iterations: MAX_NEWTON,
            tol_position: TOL_POSITION,
            ..SolveOptions::default()
        };
        solve_axial(&self.map, z, rho, q0, &opt).map_err(|e| match e {
            EnvelopeError::Singular { q, .. } => FlankError::Model(format!(
                "singular meshing Jacobian at gear (u, v, φ₂) = {q:?}: the envelope is not regular there (limit line / undercut)"
            )),
            EnvelopeError::NonFinite { q } => {
                FlankError::Model(format!("non-finite gear point at q = {q:?}"))
            }
            EnvelopeError::NotConverged {
                iterations,
                residual,
                q,
            } => FlankError::Model(format!(
                "equation of meshing: Newton did not converge in {iterations} steps (residual {residual:.2e} mm at gear (u, v, φ₂) = {q:?})"
            )),
            e => FlankError::Model(e.to_string()),
        })
    }

    /// u of the clearance line (root + c) at v.
    fn clearance_u(&self, v: f64) -> f64 {
        self.form.u_mean + self.form.slope * (v - self.section.mean_cone_distance)
    }

    /// The tip-edge form line linearly interpolated at v, and its slope.
    fn edge_interpolated(&self, v: f64) -> Option<(f64, f64)> {
        let e = self.edge_form.as_ref()?;
        let n = (EDGE_NODES - 1) as f64;
        let t = ((v - self.v_box.0) / (self.v_box.1 - self.v_box.0) * n).clamp(0.0, n);
        let k = (t.floor() as usize).min(EDGE_NODES - 2);
        let a = t - k as f64;
        let dv = (self.v_box.1 - self.v_box.0) / n;
        Some((e[k] + a * (e[k + 1] - e[k]), (e[k + 1] - e[k]) / dv))
    }

    /// du_form/dv at v.
    fn form_slope(&self, v: f64) -> f64 {
        match self.edge_interpolated(v) {
            Some((u, slope)) if u > self.clearance_u(v) => slope,
            _ => self.form.slope,
        }
    }

    /// The line the gear's **tip edge** touches on the pinion flank, where
    /// it lies above the clearance line: below it the pinion is not
    /// generated by the gear's flank but by its tip edge (a fillet trace),
    /// and the envelope of the flank's extension beyond the tip may fold
    /// there (limit line of undercut, Litvin & Fuentes §6.3). At each of
    /// [`EDGE_NODES`] cone distances, continuation from the pitch line down
    /// the profile in 24 steps to the clearance line watches
    /// g = u₂ − u_tip2(v₂) of the contact; where g changes sign, bisection
    /// (≤ 60 halvings, to 1e-12 of the step) gives the pinion's u. None if
    /// the tip edge touches below the clearance line everywhere (or is
    /// never reached before the continuation stops; the seed table then
    /// reports the failure).
    fn tip_edge_line(&self, q0: [f64; 3]) -> Option<Vec<f64>> {
        let rm = self.section.mean_cone_distance;
        let gear = &self.map.gear;
        let g_of = |q: [f64; 3]| q[0] - gear.u_tip(q[1]);
        let mut out = Vec::with_capacity(EDGE_NODES);
        let mut active = false;
        for j in 0..EDGE_NODES {
            let v =
                self.v_box.0 + (self.v_box.1 - self.v_box.0) * j as f64 / (EDGE_NODES - 1) as f64;
            let clear = self.clearance_u(v);
            let mut found = None;
            if let Ok(q) = self.walk(q0, (0.0, rm), (0.0, v), 2 * SUB_STEPS) {
                let steps = 24;
                let (mut u_prev, mut q_prev) = (0.0, q);
                if g_of(q) < 0.0 {
                    for k in 1..=steps {
                        let u = clear * k as f64 / steps as f64;
                        let Ok(p) = self.solve_from(u, v, q_prev) else {
                            break;
                        };
                        if g_of(p.q) >= 0.0 {
                            // bisection between u_prev (g < 0) and u (g ≥ 0)
                            let (mut lo, mut hi, mut q_lo) = (u_prev, u, q_prev);
                            for _ in 0..60 {
                                if (lo - hi).abs() <= 1e-12 * (1.0 + clear.abs()) {
                                    break;
                                }
                                let mid = 0.5 * (lo + hi);
                                match self.solve_from(mid, v, q_lo) {
                                    Ok(pm) if g_of(pm.q) < 0.0 => {
                                        lo = mid;
                                        q_lo = pm.q;
                                    }
                                    _ => hi = mid,
                                }
                            }
                            found = Some(0.5 * (lo + hi));
                            break;
                        }
                        u_prev = u;
                        q_prev = p.q;
                    }
                }
            }
            match found {
                Some(u) if u > clear => {
                    active = true;
                    out.push(u);
                }
                _ => out.push(clear),
            }
        }
        active.then_some(out)
    }

    /// Seed node (i, j): v_j across the face, u_i from the form line to
    /// the tip line at v_j (the envelope's own region).
    fn node(&self, i: usize, j: usize) -> (f64, f64) {
        let n = (SEED_NODES - 1) as f64;
        let v = self.v_box.0 + (self.v_box.1 - self.v_box.0) * j as f64 / n;
        let (ur, ut) = (self.u_form(v), self.section.u_tip(v));
        (ur + (ut - ur) * i as f64 / n, v)
    }

    /// Fractional node coordinates (s, t) ∈ [0, n]² of (u, v).
    fn node_coordinates(&self, u: f64, v: f64) -> (f64, f64) {
        let n = (SEED_NODES - 1) as f64;
        let t = (v - self.v_box.0) / (self.v_box.1 - self.v_box.0) * n;
        let (ur, ut) = (self.u_form(v), self.section.u_tip(v));
        ((u - ur) / (ut - ur) * n, t)
    }

    fn seed_table(&self, q0: [f64; 3]) -> Result<Vec<[f64; 3]>> {
        let rm = self.section.mean_cone_distance;
        let mut table = vec![[0.0; 3]; SEED_NODES * SEED_NODES];
        let fold = |(u, v): (f64, f64), e: FlankError| {
            FlankError::Model(format!(
                "conjugate pinion: the envelope of the gear flank cannot be continued to the \
                 active-flank node (u, v) = ({u:.4}, {v:.4}) mm of the pinion blank (a limit line \
                 of undercut, or the gear flank does not mesh there): {e}"
            ))
        };
        for j in 0..SEED_NODES {
            let (_, vj) = self.node(0, j);
            let qj = self
                .walk(q0, (0.0, rm), (0.0, vj), 2 * SUB_STEPS)
                .map_err(|e| fold((0.0, vj), e))?;
            for i in 0..SEED_NODES {
                let (ui, _) = self.node(i, j);
                table[j * SEED_NODES + i] = self
                    .walk(qj, (0.0, vj), (ui, vj), 2 * SUB_STEPS)
                    .map_err(|e| fold((ui, vj), e))?;
            }
        }
        Ok(table)
    }

    /// Bilinear interpolation of the seed table (clamped to the box).
    fn seed(&self, u: f64, v: f64) -> [f64; 3] {
        let n = (SEED_NODES - 1) as f64;
        let (s, t) = self.node_coordinates(u, v);
        let (s, t) = (s.clamp(0.0, n), t.clamp(0.0, n));
        let (i, j) = (
            (s.floor() as usize).min(SEED_NODES - 2),
            (t.floor() as usize).min(SEED_NODES - 2),
        );
        let (a, b) = (s - i as f64, t - j as f64);
        let at = |i: usize, j: usize| self.seeds[j * SEED_NODES + i];
        std::array::from_fn(|k| {
            (1.0 - a) * (1.0 - b) * at(i, j)[k]
                + a * (1.0 - b) * at(i + 1, j)[k]
                + (1.0 - a) * b * at(i, j + 1)[k]
                + a * b * at(i + 1, j + 1)[k]
        })
    }

    /// The envelope point at (u, v): Newton from the interpolated seed,
    /// then by continuation from the nearest seed node if that fails.
    pub fn solve(&self, u: f64, v: f64) -> Result<EnvelopePoint> {
        if !(u.is_finite() && v.is_finite()) {
            return Err(FlankError::Model(format!(
                "conjugate pinion: non-finite parameters ({u}, {v})"
            )));
        }
        match self.solve_from(u, v, self.seed(u, v)) {
            Ok(p) => Ok(p),
            Err(_) => {
                let n = (SEED_NODES - 1) as f64;
                let (s, t) = self.node_coordinates(u, v);
                let i = s.round().clamp(0.0, n) as usize;
                let j = t.round().clamp(0.0, n) as usize;
                let q = self.walk(
                    self.seeds[j * SEED_NODES + i],
                    self.node(i, j),
                    (u, v),
                    4 * SUB_STEPS,
                )?;
                self.solve_from(u, v, q)
            }
        }
    }

    /// Point, normal, tangents, normal derivatives and roll angle at (u, v)
    /// (module docs).
    ///
    /// Below the form line (u < u_form(v), the fillet zone, where the
    /// envelope of the gear flank extended beyond its tip may fold: the
    /// limit line of undercut, Litvin & Fuentes §6.3) the surface is the
    /// tangent continuation of the envelope at the form line,
    /// r(u, v) = r_f(v) + (u − u_f(v)) r_u(u_f(v), v), with r_v from central
    /// differences (1e-4 mm) of the envelope's exact r_u at the form line;
    /// its normal does not change along u there; `conjugate` is false.
    pub fn conjugate_point(&self, u: f64, v: f64) -> Result<ConjugatePoint> {
        let uf = self.u_form(v);
        if u >= uf {
            let p = self.solve(u, v)?;
            return self.describe(&p);
        }
        let f = self.describe(&self.solve(uf, v)?)?;
        let h = 1e-4;
        let slope = self.form_slope(v);
        let up = self.describe(&self.solve(uf + h, v)?)?;
        let um = self.describe(&self.solve(uf - h, v)?)?;
        let ruu = scale(0.5 / h, sub(up.r_u, um.r_u));
        let ruv = scale(0.5 / h, sub(up.r_v, um.r_v));
        let d = u - uf;
        let r_v = add(f.r_v, d, add(scale(slope, ruu), 1.0, ruv));
        let mut n = crate::geometry::vec3::unit(cross(f.r_u, r_v));
        if dot(n, f.normal) < 0.0 {
            n = scale(-1.0, n);
        }
        Ok(ConjugatePoint {
            point: add(f.point, d, f.r_u),
            normal: n,
            r_u: f.r_u,
            r_v,
            n_u: [0.0; 3],
            n_v: f.n_v,
            roll: f.roll,
            roll_u: 0.0,
            roll_v: f.roll_v + slope * f.roll_u,
            gear_q: f.gear_q,
            meshing_residual: f.meshing_residual,
            conjugate: false,
        })
    }

    fn describe(&self, p: &EnvelopePoint) -> Result<ConjugatePoint> {
        let (_, du, dv) = self.section.target(0.0, 0.0);
        let singular = || {
            FlankError::Model(format!(
                "conjugate pinion: singular tangent system at gear (u, v, φ₂) = {:?}",
                p.q
            ))
        };
        let (r_u, q_u) = p.section_tangent(du.0, du.1).ok_or_else(singular)?;
        let (r_v, q_v) = p.section_tangent(dv.0, dv.1).ok_or_else(singular)?;
        let j = &p.jet;
        let (n, dn) = self.normal_jet(j);
        let comb = |d: [f64; 3]| add(add(scale(d[0], dn[0]), d[1], dn[1]), d[2], dn[2]);
        Ok(ConjugatePoint {
            point: j.r,
            normal: n,
            r_u,
            r_v,
            n_u: comb(q_u),
            n_v: comb(q_v),
            roll: self.map.ratio * p.q[2],
            roll_u: self.map.ratio * q_u[2],
            roll_v: self.map.ratio * q_v[2],
            gear_q: p.q,
            meshing_residual: self.residual_of(j)[2] / self.length(),
            conjugate: true,
        })
    }

    /// Evaluate, counting a failure and falling back to the seed point.
    fn eval(&self, u: f64, v: f64) -> ConjugatePoint {
        match self.conjugate_point(u, v) {
            Ok(c) => c,
            Err(_) => {
                self.failures.fetch_add(1, Ordering::Relaxed);
                let q = self.seed(u, v);
                let jet = self.map.jet(q);
                let nn = cross(jet.d1[0], jet.d1[1]);
                let n = scale(self.map.orientation / norm(nn), nn);
                ConjugatePoint {
                    point: jet.r,
                    normal: n,
                    r_u: jet.d1[0],
                    r_v: jet.d1[1],
                    n_u: [0.0; 3],
                    n_v: [0.0; 3],
                    roll: self.map.ratio * q[2],
                    roll_u: 0.0,
                    roll_v: 0.0,
                    gear_q: q,
                    meshing_residual: self.residual_of(&jet)[2] / self.length(),
                    conjugate: false,
                }
            }
        }
    }
}

/// The pinion's axial section and fillet junction from the blank (see
/// [`ConjugatePinion::from_blank`]).
pub fn pinion_section(inputs: &BlankInputs, design: &BlankDesign) -> (AxialSection, ConeLine) {
    let _ = inputs;
    // The pinion's cones from the blank design's summary (ISO 23509 7.3–7.5):
    // θ_a1 = δ_a1 − δ1, θ_f1 = δ1 − δ_f1.
    let p = design.cutting_blank().pinion;
    let (theta_a, theta_f) = (p.delta_a - p.delta, p.delta - p.delta_f);
    let section = AxialSection {
        pitch_angle: p.delta,
        cone_distance: (p.ri, p.re),
        mean_cone_distance: p.rm,
        tip: ConeLine {
            u_mean: p.ham,
            slope: theta_a.tan(),
        },
        root: ConeLine {
            u_mean: -p.hfm,
            slope: -theta_f.tan(),
        },
    };
    let form = ConeLine {
        u_mean: -p.hfm + design.depth.c,
        slope: -theta_f.tan(),
    };
    (section, form)
}

impl ToothSurface for ConjugatePinion {
    fn u_range(&self) -> (f64, f64) {
        self.u_box
    }
    fn v_range(&self) -> (f64, f64) {
        self.v_box
    }
    fn u_tip(&self, v: f64) -> f64 {
        self.section.u_tip(v)
    }
    /// The clearance line (root raised by c), or the line the gear's tip
    /// edge touches where that is higher ([`ConjugatePinion::new`]).
    fn u_form(&self, v: f64) -> f64 {
        let clear = self.clearance_u(v);
        match self.edge_interpolated(v) {
            Some((u, _)) => clear.max(u),
            None => clear,
        }
    }
    fn u_root(&self, v: f64) -> f64 {
        self.section.u_root(v)
    }
    fn point(&self, u: f64, v: f64) -> V3 {
        self.eval(u, v).point
    }
    fn normal(&self, u: f64, v: f64) -> V3 {
        self.eval(u, v).normal
    }
    fn derivatives(&self, u: f64, v: f64) -> (V3, V3) {
        let c = self.eval(u, v);
        (c.r_u, c.r_v)
    }
    fn evaluate(&self, u: f64, v: f64) -> (V3, V3, V3, V3) {
        let c = self.eval(u, v);
        (c.point, c.normal, c.r_u, c.r_v)
    }
    /// `None` where [`ConjugatePinion::conjugate_point`] errs (not counted
    /// as a failure: nothing falls back).
    fn evaluate_checked(&self, u: f64, v: f64) -> Option<(V3, V3, V3, V3)> {
        let c = self.conjugate_point(u, v).ok()?;
        Some((c.point, c.normal, c.r_u, c.r_v))
    }
}
