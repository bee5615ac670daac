//! Generic envelope engine for generated tooth surfaces.
//!
//! A generating tool surface r_t(q₀, q₁) (q₀ = s along the blade, q₁ = θ
//! around the cutter axis) moves relative to the work by a one-parameter
//! motion with generating roll q₂ = ψ. Written in the work's own frame
//! the tool positions form the family r(q), q = (s, θ, ψ); the generated
//! tooth surface is its envelope, the points of the family where the
//! **equation of meshing**
//!
//! f(q) = (r_s × r_θ) · r_ψ = 0
//!
//! holds (the normal of the family member is perpendicular to the relative
//! velocity, n · v^(t,w) = 0; Litvin & Fuentes, *Gear Geometry and Applied
//! Theory*, 2nd ed., ch. 6, eqs. 6.1.x). The engine only sees the map
//! q ↦ r(q) in the work frame with its exact first and second derivatives
//! (a [`Jet`]): face milling (`cradle_machine`), face hobbing (where the work
//! rotation also depends on θ) and the conjugate pinion (tool = the gear's
//! flank, motion = the pair's rotation) plug in the same way. Maps written
//! generic over [`num_dual::DualNum`] get their jet from [`jet_of`]
//! (second-order vector dual numbers: exact derivatives, no differences).
//!
//! The surface is parametrised by its **axial section** ("rotated
//! projection" of measuring machines and Gleason summaries): the point at
//! (u, v) is the flank point whose axial coordinate z and radius ρ equal
//! those of the axial-plane point v·(cos δ, sin δ) + u·(−sin δ, cos δ)
//! (v = cone distance along the pitch-cone generatrix, u = distance
//! perpendicular to it, root → tip), its angular position solved. So a
//! surface point solves the three equations z(q) = z*, ρ(q) = ρ*,
//! f(q) = 0 ([`solve_axial`], bounded damped Newton from a warm start); its
//! derivatives in (u, v) follow from the implicit function theorem
//! ([`EnvelopePoint::section_tangent`]); its unit normal is the tool
//! normal, oriented by [`EnvelopeMap::normal_orientation`].
//!
//! A **formate** (non-generated) surface has no roll: the map reports
//! [`EnvelopeMap::is_generated`] = false, ψ stays at its start value and
//! only (s, θ) are solved from z and ρ.

use num_dual::{Dual2SVec64, DualNum};

use crate::geometry::surface::ToothSurface;
use crate::geometry::vec3::{cross, det3, dot, norm, solve3, V3};

/// The map q ↦ r(q) with exact derivatives at one q.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Jet {
    /// r(q) (work frame, mm).
    pub r: V3,
    /// ∂r/∂q_k, k = 0, 1, 2.
    pub d1: [V3; 3],
    /// ∂²r/∂q_j∂q_k (symmetric).
    pub d2: [[V3; 3]; 3],
}

/// A one-parameter family of tool surfaces in the work frame: what the
/// envelope engine needs to know about a generating process.
pub trait EnvelopeMap: std::fmt::Debug + Send + Sync {
    /// r(q) and its exact first and second derivatives, q = (s, θ, ψ).
    fn jet(&self, q: [f64; 3]) -> Jet;

    /// r(q) alone (default: from the jet).
    fn position(&self, q: [f64; 3]) -> V3 {
        self.jet(q).r
    }

    /// +1 if r_s × r_θ points out of the generated tooth's material, −1
    /// if into it.
    fn normal_orientation(&self) -> f64;

    /// False for a formate (non-generated) surface: no roll, the surface
    /// is the tool surface itself.
    fn is_generated(&self) -> bool {
        true
    }

    /// The range of the tool parameter q₀ (e.g. the blade from its tip to
    /// its top): a solution outside it is not on the tool
    /// ([`EnvelopeError::OutsideTool`]). Default: unbounded.
    fn tool_range(&self) -> Option<(f64, f64)> {
        None
    }

    /// A fixed reference L (a product of reference lengths, e.g. the
    /// nominal |r_s × r_θ|) that makes the meshing row f/L a **length** (mm,
    /// the normal component of r_ψ scaled by |r_s × r_θ|/L). With Some(L)
    /// [`solve_axial`] solves (z − z*, ρ − ρ*, f/L), all three rows in mm,
    /// and accepts the point when each is within `tol_position`: the row
    /// keeps its gradient and its meaning where the relative velocity
    /// r_ψ vanishes (the instantaneous axis: the whole pitch line of a
    /// bevel pair with E = 0), where any residual normalised by |r_ψ| is
    /// 0/0. Default None: the row f/|∇f(q₀)| and the normalised
    /// [`meshing_residual`] ≤ `tol_meshing`.
    fn meshing_length(&self) -> Option<f64> {
        None
    }

    /// The largest change of ψ in one Newton step (rad): a step that
    /// would turn the work further is shortened to it, so that Newton
    /// stays on the contact it started near (the next tooth's contact is
    /// one angular pitch away). Default: unbounded.
    fn max_roll_step(&self) -> f64 {
        f64::INFINITY
    }
}

/// The jet of a map written generic over dual numbers: `f` evaluates the
/// kinematic chain on second-order vector duals seeded with q.
pub fn jet_of<F>(q: [f64; 3], f: F) -> Jet
where
    F: Fn([Dual2SVec64<3>; 3]) -> [Dual2SVec64<3>; 3],
{
    let x: [Dual2SVec64<3>; 3] =
        std::array::from_fn(|k| Dual2SVec64::<3>::from_re(q[k]).derivative(k));
    let y = f(x);
    let mut jet = Jet {
        r: [0.0; 3],
        d1: [[0.0; 3]; 3],
        d2: [[[0.0; 3]; 3]; 3],
    };
    for (c, yc) in y.iter().enumerate() {
        jet.r[c] = yc.re;
        if let Some(g) = yc.v1.0.as_ref() {
            for k in 0..3 {
                jet.d1[k][c] = g[(0, k)];
            }
        }
        if let Some(h) = yc.v2.0.as_ref() {
            for j in 0..3 {
                for k in 0..3 {
                    jet.d2[j][k][c] = h[(j, k)];
                }
            }
        }
    }
    jet
}

/// A constant as a dual number of any kind (for kinematic chains written
/// generic over [`DualNum`]).
pub fn cst<D: DualNum<Primitive = f64>>(x: f64) -> D {
    D::from(x)
}

fn det(a: V3, b: V3, c: V3) -> f64 {
    dot(cross(a, b), c)
}

/// The equation of meshing f = (r_s × r_θ)·r_ψ and its gradient in q
/// (Litvin & Fuentes ch. 6), from the jet.
pub fn meshing(j: &Jet) -> (f64, [f64; 3]) {
    let [a, b, c] = j.d1;
    let f = det(a, b, c);
    let g = std::array::from_fn(|k| {
        det(j.d2[0][k], b, c) + det(a, j.d2[1][k], c) + det(a, b, j.d2[2][k])
    });
    (f, g)
}

/// The dimensionless meshing residual n · r_ψ / max(|r_ψ|, |r|), n the
/// unit normal of the family member: the cosine of the angle between the
/// normal and the relative velocity where that velocity is at least |r|
/// per radian, and the velocity's normal component relative to |r|
/// elsewhere (near the instantaneous axis of rolling, the pitch element,
/// the velocity vanishes and its direction is undefined). 0 on the
/// envelope; 0 also for a formate map (r_ψ = 0).
pub fn meshing_residual(j: &Jet) -> f64 {
    let nn = norm(cross(j.d1[0], j.d1[1]));
    let vv = norm(j.d1[2]).max(norm(j.r));
    if nn == 0.0 || vv == 0.0 {
        return 0.0;
    }
    det(j.d1[0], j.d1[1], j.d1[2]) / (nn * vv)
}

/// Axial position z and radius ρ = √(x² + y²) of a work-frame point.
pub fn axial_radius(r: V3) -> (f64, f64) {
    (r[2], r[0].hypot(r[1]))
}

/// Why a surface point could not be found.
#[derive(Clone, Debug, PartialEq)]
pub enum EnvelopeError {
    /// Newton did not reach the tolerance within its step bound.
    NotConverged {
        iterations: usize,
        residual: f64,
        q: [f64; 3],
    },
    /// The Jacobian of (z, ρ, f) is singular: the tool normal lies in the
    /// axial plane of the point, or r_s × r_θ = 0, or the non-generation
    /// condition ∂f/∂q ∥ … holds (undercut / self-intersection, Litvin &
    /// Fuentes ch. 6.3–6.4).
    Singular { q: [f64; 3], determinant: f64 },
    /// A non-finite value appeared (non-physical map or settings).
    NonFinite { q: [f64; 3] },
    /// The solution lies outside the tool's range of q₀ (the point is not
    /// generated by the tool: outside the generated region).
    OutsideTool { q: [f64; 3], range: (f64, f64) },
    /// A limit line of undercut (Litvin & Fuentes ch. 6.3): going down the
    /// profile at cone distance `v`, the contact runs down the tool ever
    /// faster (the rate |ds/du| of the blade parameter grew from
    /// `rate.0` to `rate.1`) and no generated point exists below
    /// `u_lowest`; the flank's root line is at `u_root` (mm).
    LimitLine {
        v: f64,
        u_lowest: f64,
        u_root: f64,
        rate: (f64, f64),
    },
}

impl std::fmt::Display for EnvelopeError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            EnvelopeError::NotConverged {
                iterations,
                residual,
                q,
            } => write!(
                f,
                "equation of meshing: Newton did not converge in {iterations} steps \
                 (residual {residual:.3e} at s, θ, ψ = {:.6}, {:.6}, {:.6})",
                q[0], q[1], q[2]
            ),
            EnvelopeError::Singular { q, determinant } => write!(
                f,
                "singular meshing Jacobian (det {determinant:.3e}) at s, θ, ψ = {:.6}, {:.6}, {:.6}: \
                 the surface is not generated there (undercut or self-intersection)",
                q[0], q[1], q[2]
            ),
            EnvelopeError::NonFinite { q } => write!(
                f,
                "non-finite tool position at s, θ, ψ = {:?} (non-physical settings)",
                q
            ),
            EnvelopeError::OutsideTool { q, range } => write!(
                f,
                "the point is outside the generated region: blade parameter s = {:.6} \
                 outside the blade [{:.6}, {:.6}]",
                q[0], range.0, range.1
            ),
            EnvelopeError::LimitLine {
                v,
                u_lowest,
                u_root,
                rate,
            } => write!(
                f,
                "limit line of undercut at cone distance {v:.3} mm: the generated flank folds \
                 (down the profile the contact runs down the blade ever faster, |ds/du| from \
                 {:.2} to {:.0}) and no generated point exists below u = {u_lowest:.4} mm, \
                 {:.3} mm above the root line (u = {u_root:.4} mm): the tooth would be \
                 undercut (Litvin & Fuentes ch. 6.3)",
                rate.0,
                rate.1,
                u_lowest - u_root
            ),
        }
    }
}

/// A solved surface point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnvelopePoint {
    /// The generating parameters (s, θ, ψ).
    pub q: [f64; 3],
    /// The map's jet at q.
    pub jet: Jet,
    /// Unit normal, out of the tooth's material.
    pub normal: V3,
    /// The Jacobian of (z, ρ, f) in q (rows), used for the tangents.
    pub jacobian: [[f64; 3]; 3],
    /// Whether ψ was solved (generated) or held (formate).
    pub generated: bool,
    /// Newton steps taken.
    pub iterations: usize,
}

/// How far above its tolerances [`solve_axial`] accepts a point at which
/// no step lowers the merit any more (30 halvings tried): the rows' own
/// round-off floor. Where the blade's straight flank meets its edge round
/// (the form line) the tool's jet is only C¹, and Newton stalls just above
/// `tol_meshing` = 1e-14: seed 003's generated pinion at cone distance
/// 115.373 mm stalled at a normalised meshing residual of 1.07e-14 with the
/// positions ≤ 3.6e-15 mm, a step of 5e-14, and its form line fell back to
/// the root line (a fillet of zero length: the sector mesher's "corner and
/// midside node coincide").
const STALL_FACTOR: f64 = 10.0;

/// Newton's bound and tolerances for [`solve_axial`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolveOptions {
    /// Maximum Newton steps (each with up to 30 halvings).
    pub max_iterations: usize,
    /// Tolerance on |z − z*| and |ρ − ρ*| (mm), and on the meshing row
    /// f/L of a map with a [`EnvelopeMap::meshing_length`] L.
    pub tol_position: f64,
    /// Tolerance on the dimensionless meshing residual (maps without a
    /// meshing length).
    pub tol_meshing: f64,
}

impl Default for SolveOptions {
    fn default() -> Self {
        SolveOptions {
            max_iterations: 60,
            tol_position: 1e-12,
            tol_meshing: 1e-14,
        }
    }
}

fn rows(j: &Jet, generated: bool) -> ([f64; 3], [[f64; 3]; 3]) {
    let (z, rho) = axial_radius(j.r);
    let drho: [f64; 3] = std::array::from_fn(|k| {
        if rho > 0.0 {
            (j.r[0] * j.d1[k][0] + j.r[1] * j.d1[k][1]) / rho
        } else {
            0.0
        }
    });
    let dz: [f64; 3] = std::array::from_fn(|k| j.d1[k][2]);
    let (f, df) = if generated {
        meshing(j)
    } else {
        (0.0, [0.0, 0.0, 1.0])
    };
    ([z, rho, f], [dz, drho, df])
}

impl EnvelopePoint {
    fn build<M: EnvelopeMap + ?Sized>(map: &M, q: [f64; 3], jet: Jet, iterations: usize) -> Self {
        let generated = map.is_generated();
        let (_, jac) = rows(&jet, generated);
        let n = cross(jet.d1[0], jet.d1[1]);
        let l = norm(n) * map.normal_orientation();
        EnvelopePoint {
            q,
            jet,
            normal: [n[0] / l, n[1] / l, n[2] / l],
            jacobian: jac,
            generated,
            iterations,
        }
    }

    /// The surface tangent for a motion of the axial-section target by
    /// (dz*, dρ*) (implicit function theorem on z(q) = z*, ρ(q) = ρ*,
    /// f(q) = 0: J dq = (dz*, dρ*, 0), dr = r_q dq). Also returns dq.
    pub fn section_tangent(&self, dz: f64, drho: f64) -> Option<(V3, [f64; 3])> {
        let dq = solve3(&self.jacobian, [dz, drho, 0.0])?;
        let d1 = self.jet.d1;
        let t = std::array::from_fn(|c| d1[0][c] * dq[0] + d1[1][c] * dq[1] + d1[2][c] * dq[2]);
        Some((t, dq))
    }

    /// Dimensionless meshing residual at the point ([`meshing_residual`]).
    pub fn meshing_residual(&self) -> f64 {
        if self.generated {
            meshing_residual(&self.jet)
        } else {
            0.0
        }
    }
}

fn within_tool<M: EnvelopeMap + ?Sized>(map: &M, q: [f64; 3]) -> Result<(), EnvelopeError> {
    match map.tool_range() {
        Some(range) if !(q[0] >= range.0 && q[0] <= range.1) => {
            Err(EnvelopeError::OutsideTool { q, range })
        }
        _ => Ok(()),
    }
}

/// The surface point at axial position `z` and radius `rho` (work frame):
/// bounded damped Newton on (z(q) − z*, ρ(q) − ρ*, f(q)/f_scale) from `q0`
/// (for a formate map ψ = q0\[2\] is held). f_scale is the map's fixed
/// [`EnvelopeMap::meshing_length`] when it gives one (all rows in mm), else
/// |∇f| frozen at the start (so that all three rows weigh alike). Each step
/// is shortened to the map's [`EnvelopeMap::max_roll_step`] in ψ, then
/// halved until the merit (sum of squared rows) decreases; stops when the
/// position is within `tol_position` and the meshing row within
/// `tol_position` (length-scaled) or the normalised meshing residual
/// within `tol_meshing`, or errs after `max_iterations` steps.
pub fn solve_axial<M: EnvelopeMap + ?Sized>(
    map: &M,
    z: f64,
    rho: f64,
    q0: [f64; 3],
    opt: &SolveOptions,
) -> Result<EnvelopePoint, EnvelopeError> {
    let generated = map.is_generated();
    let mut q = q0;
    let mut jet = map.jet(q);
    let finite = |j: &Jet| {
        j.r.iter()
            .chain(j.d1.iter().flatten())
            .chain(j.d2.iter().flatten().flatten())
            .all(|x| x.is_finite())
    };
    if !finite(&jet) {
        return Err(EnvelopeError::NonFinite { q });
    }
    // f's row scale: the map's fixed reference length product, else |∇f|
    // at the start (1 for a formate map), so that the three rows of the
    // merit weigh alike (|∇z|, |∇ρ| are O(1) per unit q)
    let length_scaled = generated && map.meshing_length().is_some();
    let f_scale = if let (true, Some(l)) = (generated, map.meshing_length()) {
        if !(l.is_finite() && l > 0.0) {
            return Err(EnvelopeError::NonFinite { q });
        }
        l
    } else if generated {
        let g = meshing(&jet).1;
        let s = (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]).sqrt();
        if s.is_finite() && s > 0.0 {
            s
        } else {
            1.0
        }
    } else {
        1.0
    };
    let residual = |j: &Jet| {
        let (v, _) = rows(j, generated);
        [v[0] - z, v[1] - rho, v[2] / f_scale]
    };
    let merit = |r: [f64; 3]| r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
    // the rows within `factor` × the tolerances
    let within = |res: [f64; 3], jet: &Jet, factor: f64| {
        let pos_ok =
            res[0].abs() <= factor * opt.tol_position && res[1].abs() <= factor * opt.tol_position;
        let mesh_ok = !generated
            || if length_scaled {
                res[2].abs() <= factor * opt.tol_position
            } else {
                meshing_residual(jet).abs() <= factor * opt.tol_meshing
            };
        pos_ok && mesh_ok
    };
    let mut res = residual(&jet);
    for it in 0..=opt.max_iterations {
        if within(res, &jet, 1.0) {
            return within_tool(map, q).map(|_| EnvelopePoint::build(map, q, jet, it));
        }
        if it == opt.max_iterations {
            break;
        }
        let (_, mut jac) = rows(&jet, generated);
        for v in jac[2].iter_mut() {
            *v /= f_scale;
        }
        if !generated {
            jac[2] = [0.0, 0.0, 1.0];
        }
        let Some(mut dq) = solve3(&jac, [-res[0], -res[1], -res[2]]) else {
            return Err(EnvelopeError::Singular {
                q,
                determinant: det3(&jac),
            });
        };
        let cap = map.max_roll_step();
        if generated && dq[2].abs() > cap {
            let shrink = cap / dq[2].abs();
            dq = dq.map(|x| x * shrink);
        }
        let m0 = merit(res);
        let mut lambda = 1.0;
        let mut accepted = false;
        for _ in 0..30 {
            let qn = [
                q[0] + lambda * dq[0],
                q[1] + lambda * dq[1],
                q[2] + if generated { lambda * dq[2] } else { 0.0 },
            ];
            let jn = map.jet(qn);
            if finite(&jn) {
                let rn = residual(&jn);
                if merit(rn) < m0 || (merit(rn) <= m0 && lambda == 1.0) {
                    q = qn;
                    jet = jn;
                    res = rn;
                    accepted = true;
                    break;
                }
            }
            lambda *= 0.5;
        }
        if !accepted {
            // no decrease: converged to rounding if the step is tiny
            let step = dq.iter().map(|x| x.abs()).fold(0.0, f64::max);
            // ... or stalled at the rows' round-off floor, within
            // STALL_FACTOR of the tolerances
            if step < 1e-14 * (1.0 + q.iter().map(|x| x.abs()).fold(0.0, f64::max))
                || within(res, &jet, STALL_FACTOR)
            {
                return within_tool(map, q).map(|_| EnvelopePoint::build(map, q, jet, it));
            }
            return Err(EnvelopeError::NotConverged {
                iterations: it,
                residual: merit(res).sqrt(),
                q,
            });
        }
    }
    Err(EnvelopeError::NotConverged {
        iterations: opt.max_iterations,
        residual: merit(res).sqrt(),
        q,
    })
}

/// The axial-section parametrisation of a bevel flank (module docs): the
/// pitch-cone generatrix at pitch angle δ, the face width as a range of
/// cone distance, and the face-cone (tip) and root-cone lines as straight
/// lines u(v) = u_m + slope·(v − R_m) in the (v, u) axial plane (u ⟂ to the
/// generatrix, positive toward the tip). Apex at the work-frame origin,
/// axis +z toward the heel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AxialSection {
    /// Pitch angle δ (rad).
    pub pitch_angle: f64,
    /// Inner and outer cone distance R_i, R_e (mm): the v range.
    pub cone_distance: (f64, f64),
    /// Mean cone distance R_m (mm): where the cone lines are referenced.
    pub mean_cone_distance: f64,
    /// Face-cone line: u at R_m (the mean addendum h_am) and slope
    /// tan(θ_a) (face angle − pitch angle).
    pub tip: ConeLine,
    /// Root-cone line: u at R_m (−h_fm) and slope −tan(θ_f).
    pub root: ConeLine,
}

/// A straight line u(v) = u_m + slope·(v − R_m) of the axial section.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConeLine {
    pub u_mean: f64,
    pub slope: f64,
}

impl AxialSection {
    /// (z*, ρ*) of the axial-plane point (u, v) and its derivatives
    /// ((∂z/∂u, ∂ρ/∂u), (∂z/∂v, ∂ρ/∂v)).
    pub fn target(&self, u: f64, v: f64) -> ((f64, f64), (f64, f64), (f64, f64)) {
        let (s, c) = self.pitch_angle.sin_cos();
        ((v * c - u * s, v * s + u * c), (-s, c), (c, s))
    }

    /// u of the face-cone line at v.
    pub fn u_tip(&self, v: f64) -> f64 {
        self.tip.u_mean + self.tip.slope * (v - self.mean_cone_distance)
    }

    /// u of the root-cone line at v.
    pub fn u_root(&self, v: f64) -> f64 {
        self.root.u_mean + self.root.slope * (v - self.mean_cone_distance)
    }
}

/// Rotate a vector about +z by the angle with (cos, sin) = `cs`.
pub fn rot_z(cs: (f64, f64), p: V3) -> V3 {
    [cs.0 * p[0] - cs.1 * p[1], cs.1 * p[0] + cs.0 * p[1], p[2]]
}

/// One solved sample of a flank grid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlankSample {
    pub u: f64,
    pub v: f64,
    /// Point (work frame, placed).
    pub point: V3,
    /// Unit outward normal (placed).
    pub normal: V3,
    /// The generating parameters (s, θ, ψ).
    pub q: [f64; 3],
    /// Newton steps the point took.
    pub iterations: usize,
}

/// Nodes of the warm-start table across the profile (fraction from the
/// root line to the tip line) and across the face.
const TABLE_NA: usize = 9;
const TABLE_NV: usize = 7;
/// The check grid solved by [`EnvelopeFlank::new`] (every point of it must
/// solve, so the validated domain has no undercut or gap).
const CHECK_NU: usize = 21;
/// The smallest step (mm) of the continuation that looks for a limit line
/// ([`EnvelopeFlank::fold_below`]).
const FOLD_MIN_STEP: f64 = 1e-6;
const CHECK_NV: usize = 11;

/// A generated flank as a [`ToothSurface`] over the axial section (module
/// docs): the envelope of an [`EnvelopeMap`], rotated about +z by
/// `placement` (the tooth's position on the blank).
///
/// Evaluation: each (u, v) is solved by [`solve_axial`] from a warm start
/// bilinearly interpolated in a 9 × 7 table of solved parameters (built by
/// continuation when the flank is made), so a point costs 2–4 Newton
/// steps. [`Self::grid`] marches a grid by continuation instead.
#[derive(Debug)]
pub struct EnvelopeFlank<M: EnvelopeMap> {
    map: M,
    section: AxialSection,
    placement: (f64, f64),
    form_parameter: Option<f64>,
    opt: SolveOptions,
    /// q at (fraction a_i from root to tip line, v_j).
    table: Vec<[f64; 3]>,
    /// A root curve (v, u) sorted by v, replacing the root-cone line (a
    /// formate member's blade-tip trace).
    root_curve: Option<Vec<(f64, f64)>>,
}

impl<M: EnvelopeMap> EnvelopeFlank<M> {
    /// The flank of `map` over `section`, placed by a rotation of
    /// `placement` (rad) about +z. `q_start` is a guess of (s, θ, ψ) at the
    /// mean point (u = 0, v = R_m); `form_parameter` is the blade
    /// parameter s where the blade's edge radius (fillet) begins (None: no
    /// fillet, u_form = u_root). Errs if any point of a 21 × 11 grid over
    /// root–tip × face width cannot be solved (undercut, singular meshing,
    /// not generated there).
    pub fn new(
        map: M,
        section: AxialSection,
        placement: f64,
        form_parameter: Option<f64>,
        q_start: [f64; 3],
        opt: SolveOptions,
    ) -> Result<Self, EnvelopeError> {
        Self::with_root_curve(map, section, placement, form_parameter, q_start, opt, None)
    }

    /// [`Self::new`] with a root curve: polyline (v, u) sorted by v; the
    /// flank's root u_root(v) is that curve instead of the root-cone line.
    pub fn with_root_curve(
        map: M,
        section: AxialSection,
        placement: f64,
        form_parameter: Option<f64>,
        q_start: [f64; 3],
        opt: SolveOptions,
        root_curve: Option<Vec<(f64, f64)>>,
    ) -> Result<Self, EnvelopeError> {
        let mut f = EnvelopeFlank {
            map,
            section,
            placement: (placement.cos(), placement.sin()),
            form_parameter,
            opt,
            table: vec![[0.0; 3]; TABLE_NA * TABLE_NV],
            root_curve,
        };
        let (z, rho) = f.target(0.0, section.mean_cone_distance);
        let mean = solve_axial(&f.map, z, rho, q_start, &f.opt)?;
        // continuation: along the pitch line to each table column, then
        // from the pitch line down to the root and up to the tip
        let (r0, r1) = section.cone_distance;
        let nv = TABLE_NV;
        let mut columns: Vec<(usize, f64)> = (0..nv)
            .map(|j| (j, r0 + (r1 - r0) * j as f64 / (nv - 1) as f64))
            .collect();
        columns.sort_by(|a, b| {
            (a.1 - section.mean_cone_distance)
                .abs()
                .total_cmp(&(b.1 - section.mean_cone_distance).abs())
        });
        let mut pitch_q: Vec<(f64, [f64; 3])> = vec![(section.mean_cone_distance, mean.q)];
        for &(j, v) in &columns {
            // start from the nearest solved pitch point, in up to 8 steps
            let (v_near, q_near) = *pitch_q
                .iter()
                .min_by(|a, b| (a.0 - v).abs().total_cmp(&(b.0 - v).abs()))
                .expect("non-empty");
            let mut q = q_near;
            for k in 1..=8 {
                let vk = v_near + (v - v_near) * k as f64 / 8.0;
                let (z, rho) = f.target(0.0, vk);
                q = solve_axial(&f.map, z, rho, q, &f.opt)?.q;
            }
            pitch_q.push((v, q));
            // the pitch line's fraction between root and tip
            let (ur, ut) = (f.root_u(v), section.u_tip(v));
            let a_pitch = -ur / (ut - ur);
            let na = TABLE_NA;
            for dir in [-1.0, 1.0] {
                let mut qa = q;
                let mut a_prev = a_pitch;
                for i in 0..na {
                    let i = if dir > 0.0 { i } else { na - 1 - i };
                    let a = i as f64 / (na - 1) as f64;
                    if (a - a_pitch) * dir < 0.0 {
                        continue;
                    }
                    // sub-steps of at most 1/16 of the depth
                    let steps = (((a - a_prev).abs() * 16.0).ceil() as usize).max(1);
                    for k in 1..=steps {
                        let a_from = a_prev + (a - a_prev) * (k - 1) as f64 / steps as f64;
                        let ak = a_prev + (a - a_prev) * k as f64 / steps as f64;
                        let (z, rho) = f.target(ur + ak * (ut - ur), v);
                        qa = match solve_axial(&f.map, z, rho, qa, &f.opt) {
                            Ok(p) => p.q,
                            Err(e) if dir < 0.0 => {
                                let from = ur + a_from * (ut - ur);
                                return Err(f
                                    .fold_below(v, from, qa, ur + ak * (ut - ur))
                                    .unwrap_or(e));
                            }
                            Err(e) => return Err(e),
                        };
                    }
                    a_prev = a;
                    f.table[i * nv + j] = qa;
                }
            }
        }
        // the check grid
        for j in 0..CHECK_NV {
            let v = r0 + (r1 - r0) * j as f64 / (CHECK_NV - 1) as f64;
            for i in 0..CHECK_NU {
                let a = i as f64 / (CHECK_NU - 1) as f64;
                let u = f.root_u(v) + a * (section.u_tip(v) - f.root_u(v));
                let p = match f.solve(u, v) {
                    Ok(p) => p,
                    Err(e) if u < 0.0 => {
                        let fold = f
                            .solve(0.0, v)
                            .ok()
                            .and_then(|p0| f.fold_below(v, 0.0, p0.q, u));
                        return Err(fold.unwrap_or(e));
                    }
                    Err(e) => return Err(e),
                };
                if p.section_tangent(0.0, 1.0).is_none() {
                    return Err(EnvelopeError::Singular {
                        q: p.q,
                        determinant: det3(&p.jacobian),
                    });
                }
            }
        }
        Ok(f)
    }

    /// Why the flank cannot be solved down to `u_to` at `v` when it can at
    /// `(u_from, q_from)` (u_to < u_from): continuation down the profile in
    /// 32 steps, each halved where Newton fails (down to 1 nm). If it
    /// stops short of `u_to` and the blade parameter's rate |Δs/Δu| grew
    /// at least fivefold and kept growing over the last three steps (near
    /// a fold s − s_f ∝ √(u − u_f), the rate grows as 1/√(u − u_f)), that
    /// is a limit line of undercut: [`EnvelopeError::LimitLine`]. Otherwise
    /// None (the caller keeps its own error).
    fn fold_below(
        &self,
        v: f64,
        u_from: f64,
        q_from: [f64; 3],
        u_to: f64,
    ) -> Option<EnvelopeError> {
        let mut h = (u_to - u_from) / 32.0;
        if !(h < 0.0) {
            return None;
        }
        let (mut u, mut q) = (u_from, q_from);
        let mut rates: Vec<f64> = Vec::new();
        while u > u_to {
            let next = (u + h).max(u_to);
            match self.solve_from(next, v, q) {
                Ok(p) => {
                    rates.push(((p.q[0] - q[0]) / (next - u)).abs());
                    u = next;
                    q = p.q;
                }
                // steps below 1 nm: s moves by the solver's tolerance only
                Err(_) if h < -FOLD_MIN_STEP => h *= 0.5,
                Err(_) => break,
            }
        }
        if u <= u_to || rates.len() < 4 {
            return None;
        }
        let n = rates.len();
        let growing = rates[n - 3] < rates[n - 2] && rates[n - 2] < rates[n - 1];
        (growing && rates[n - 1] >= 5.0 * rates[0]).then_some(EnvelopeError::LimitLine {
            v,
            u_lowest: u,
            u_root: self.root_u(v),
            rate: (rates[0], rates[n - 1]),
        })
    }

    fn u_range_inner(&self) -> (f64, f64) {
        let (r0, r1) = self.section.cone_distance;
        let s = &self.section;
        let lo = (0..=32)
            .map(|k| self.root_u(r0 + (r1 - r0) * k as f64 / 32.0))
            .fold(f64::INFINITY, f64::min);
        (lo, s.u_tip(r0).max(s.u_tip(r1)))
    }

    /// u of the root at v: the root-cone line, or the root curve when one
    /// is given (linear between its points).
    pub fn root_u(&self, v: f64) -> f64 {
        let Some(c) = self.root_curve.as_ref().filter(|c| c.len() >= 2) else {
            return self.section.u_root(v);
        };
        let k = c.partition_point(|p| p.0 < v).clamp(1, c.len() - 1);
        let (a, b) = (c[k - 1], c[k]);
        let t = if b.0 > a.0 {
            (v - a.0) / (b.0 - a.0)
        } else {
            0.0
        };
        a.1 + t * (b.1 - a.1)
    }

    /// The generating map.
    pub fn map(&self) -> &M {
        &self.map
    }

    /// The axial section.
    pub fn section(&self) -> &AxialSection {
        &self.section
    }

    /// The placement rotation (rad).
    pub fn placement(&self) -> f64 {
        self.placement.1.atan2(self.placement.0)
    }

    fn target(&self, u: f64, v: f64) -> (f64, f64) {
        self.section.target(u, v).0
    }

    /// The warm start at (u, v): bilinear in the table.
    pub fn warm_start(&self, u: f64, v: f64) -> [f64; 3] {
        let (r0, r1) = self.section.cone_distance;
        let (ur, ut) = (self.root_u(v), self.section.u_tip(v));
        let a = ((u - ur) / (ut - ur)).clamp(0.0, 1.0) * (TABLE_NA - 1) as f64;
        let b = ((v - r0) / (r1 - r0)).clamp(0.0, 1.0) * (TABLE_NV - 1) as f64;
        let (i, j) = (
            (a.floor() as usize).min(TABLE_NA - 2),
            (b.floor() as usize).min(TABLE_NV - 2),
        );
        let (fa, fb) = (a - i as f64, b - j as f64);
        let t = |i: usize, j: usize| self.table[i * TABLE_NV + j];
        std::array::from_fn(|k| {
            (1.0 - fa) * (1.0 - fb) * t(i, j)[k]
                + fa * (1.0 - fb) * t(i + 1, j)[k]
                + (1.0 - fa) * fb * t(i, j + 1)[k]
                + fa * fb * t(i + 1, j + 1)[k]
        })
    }

    /// The envelope point at (u, v) (unplaced: the map's own frame).
    pub fn solve(&self, u: f64, v: f64) -> Result<EnvelopePoint, EnvelopeError> {
        self.solve_from(u, v, self.warm_start(u, v))
    }

    /// [`Self::solve`] from a given start.
    pub fn solve_from(&self, u: f64, v: f64, q0: [f64; 3]) -> Result<EnvelopePoint, EnvelopeError> {
        let (z, rho) = self.target(u, v);
        solve_axial(&self.map, z, rho, q0, &self.opt)
    }

    /// Point, unit outward normal, r_u, r_v (placed), or the reason why
    /// the point is not on the generated surface.
    pub fn try_evaluate(&self, u: f64, v: f64) -> Result<(V3, V3, V3, V3), EnvelopeError> {
        let p = self.solve(u, v)?;
        self.placed(&p, u, v)
    }

    fn placed(&self, p: &EnvelopePoint, u: f64, v: f64) -> Result<(V3, V3, V3, V3), EnvelopeError> {
        let (_, du, dv) = self.section.target(u, v);
        let singular = || EnvelopeError::Singular {
            q: p.q,
            determinant: det3(&p.jacobian),
        };
        let (ru, _) = p.section_tangent(du.0, du.1).ok_or_else(singular)?;
        let (rv, _) = p.section_tangent(dv.0, dv.1).ok_or_else(singular)?;
        let c = self.placement;
        Ok((
            rot_z(c, p.jet.r),
            rot_z(c, p.normal),
            rot_z(c, ru),
            rot_z(c, rv),
        ))
    }

    /// The dimensionless meshing residual at (u, v).
    pub fn meshing_residual(&self, u: f64, v: f64) -> Result<f64, EnvelopeError> {
        Ok(self.solve(u, v)?.meshing_residual())
    }

    /// An nu × nv grid (u from u_root(v) to u_tip(v), v from toe to heel)
    /// by continuation: each point starts from its neighbour's solution
    /// (the previous one along the profile; a column's first point from
    /// the previous column's first) moved by the implicit-function
    /// tangent, q₀ = q_prev + J⁻¹ (Δz*, Δρ*, 0), plus along u the
    /// second-order term ½ (dq − dq_prev) from the previous step's tangent
    /// (so Newton mostly needs one correction). Row-major in v, then u.
    pub fn grid(&self, nu: usize, nv: usize) -> Result<Vec<FlankSample>, EnvelopeError> {
        let (r0, r1) = self.section.cone_distance;
        let mut out = Vec::with_capacity(nu * nv);
        let mut col_start: Option<(EnvelopePoint, (f64, f64))> = None;
        for j in 0..nv {
            let v = r0 + (r1 - r0) * j as f64 / (nv.max(2) - 1) as f64;
            let (ur, ut) = (self.root_u(v), self.section.u_tip(v));
            let mut last: Option<(EnvelopePoint, (f64, f64))> = None;
            // the tangent step used to predict the previous point along u
            let mut prev_step: Option<[f64; 3]> = None;
            for i in 0..nu {
                let u = ur + (ut - ur) * i as f64 / (nu.max(2) - 1) as f64;
                let (z, rho) = self.target(u, v);
                let base = if i == 0 {
                    col_start.as_ref()
                } else {
                    last.as_ref()
                };
                let fallback = base.map(|b| b.0.q).unwrap_or_else(|| self.warm_start(u, v));
                let q0 = match base {
                    Some((p, (zb, rb))) => match p.section_tangent(z - zb, rho - rb) {
                        Some((_, dq)) => {
                            // second order along u (equal steps): the
                            // tangent's change from the previous step
                            // estimates ½ q'' Δ²
                            let q: [f64; 3] = match (i > 0, prev_step) {
                                (true, Some(d0)) => {
                                    std::array::from_fn(|k| p.q[k] + dq[k] + 0.5 * (dq[k] - d0[k]))
                                }
                                _ => std::array::from_fn(|k| p.q[k] + dq[k]),
                            };
                            if i > 0 {
                                prev_step = Some(dq);
                            }
                            q
                        }
                        None => p.q,
                    },
                    None => self.warm_start(u, v),
                };
                // the second-order predictor can overshoot where the
                // blade's curvature jumps (the edge radius's end): retry
                // from the neighbour's solution, then from the table
                let p = match solve_axial(&self.map, z, rho, q0, &self.opt) {
                    Ok(p) => p,
                    Err(_) => match solve_axial(&self.map, z, rho, fallback, &self.opt) {
                        Ok(p) => p,
                        Err(_) => self.solve(u, v)?,
                    },
                };
                let (x, n, _, _) = self.placed(&p, u, v)?;
                out.push(FlankSample {
                    u,
                    v,
                    point: x,
                    normal: n,
                    q: p.q,
                    iterations: p.iterations,
                });
                if i == 0 {
                    col_start = Some((p, (z, rho)));
                }
                last = Some((p, (z, rho)));
            }
        }
        Ok(out)
    }

    /// u where the blade parameter reaches `form_parameter` (the edge
    /// radius's end) at v: bounded Newton in u (≤ 40 steps, u kept between
    /// the root and tip lines); u_root where there is no fillet.
    pub fn try_u_form(&self, v: f64) -> Result<f64, EnvelopeError> {
        let (ur, ut) = (self.root_u(v), self.section.u_tip(v));
        let Some(s_form) = self.form_parameter else {
            return Ok(ur);
        };
        let mut u = ur + 0.1 * (ut - ur);
        let (_, du, _) = self.section.target(u, v);
        for it in 0..40 {
            let p = self.solve(u, v)?;
            let (_, dq) = p
                .section_tangent(du.0, du.1)
                .ok_or(EnvelopeError::Singular {
                    q: p.q,
                    determinant: det3(&p.jacobian),
                })?;
            let g = p.q[0] - s_form;
            if g.abs() < 1e-13 * (1.0 + s_form.abs()) {
                return Ok(u);
            }
            if dq[0] == 0.0 {
                return Err(EnvelopeError::NotConverged {
                    iterations: it,
                    residual: g.abs(),
                    q: p.q,
                });
            }
            let un = (u - g / dq[0]).clamp(ur, ut);
            if un == u {
                // the fillet's end lies beyond the root or tip line
                return Ok(u);
            }
            u = un;
        }
        let p = self.solve(u, v)?;
        Err(EnvelopeError::NotConverged {
            iterations: 40,
            residual: (p.q[0] - s_form).abs(),
            q: p.q,
        })
    }
}

impl<M: EnvelopeMap> ToothSurface for EnvelopeFlank<M> {
    fn u_range(&self) -> (f64, f64) {
        self.u_range_inner()
    }
    fn v_range(&self) -> (f64, f64) {
        self.section.cone_distance
    }
    fn u_tip(&self, v: f64) -> f64 {
        self.section.u_tip(v)
    }
    fn u_form(&self, v: f64) -> f64 {
        self.try_u_form(v).unwrap_or_else(|_| self.root_u(v))
    }
    fn u_root(&self, v: f64) -> f64 {
        self.root_u(v)
    }
    /// Outside the validated domain a failed solve returns the last
    /// Newton iterate's tool point (never NaN); use
    /// [`EnvelopeFlank::try_evaluate`] to see the error.
    fn point(&self, u: f64, v: f64) -> V3 {
        self.evaluate(u, v).0
    }
    fn normal(&self, u: f64, v: f64) -> V3 {
        self.evaluate(u, v).1
    }
    fn derivatives(&self, u: f64, v: f64) -> (V3, V3) {
        let (_, _, ru, rv) = self.evaluate(u, v);
        (ru, rv)
    }
    /// `None` where [`EnvelopeFlank::try_evaluate`] errs.
    fn evaluate_checked(&self, u: f64, v: f64) -> Option<(V3, V3, V3, V3)> {
        self.try_evaluate(u, v).ok()
    }
    fn evaluate(&self, u: f64, v: f64) -> (V3, V3, V3, V3) {
        match self.try_evaluate(u, v) {
            Ok(e) => e,
            Err(e) => {
                let q = match e {
                    EnvelopeError::NotConverged { q, .. }
                    | EnvelopeError::Singular { q, .. }
                    | EnvelopeError::NonFinite { q }
                    | EnvelopeError::OutsideTool { q, .. } => q,
                    // (only the flank's construction reports a limit line)
                    EnvelopeError::LimitLine { .. } => self.warm_start(u, v),
                };
                let q = if self.map.jet(q).r.iter().all(|x| x.is_finite()) {
                    q
                } else {
                    self.warm_start(u, v)
                };
                let p = EnvelopePoint::build(&self.map, q, self.map.jet(q), 0);
                let c = self.placement;
                let d = p.jet.d1;
                (
                    rot_z(c, p.jet.r),
                    rot_z(c, p.normal),
                    rot_z(c, d[0]),
                    rot_z(c, d[1]),
                )
            }
        }
    }
}

#[cfg(test)]
#[path = "generation_tests.rs"]
mod tests;
