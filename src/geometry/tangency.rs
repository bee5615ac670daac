//! Surfaces in tangency: where a pinion flank and a gear flank, or a flank
//! and an edge of the mating tooth, touch when the gear turns about its
//! axis.
//!
//! **Flank contact** (Litvin & Fuentes, *Gear Geometry and Applied
//! Theory*, 2nd ed. 2004, §9.4, tooth contact analysis): with the pinion
//! placed and the gear turned by ψ about its axis, r₁(u₁, v₁) = r₂(u₂, v₂)
//! and n₁ = −n₂. Of the normal condition two equations are independent
//! (both pinion tangents r₁,u, r₁,v normal to n₂), so the system is five
//! equations in (u₁, v₁, u₂, v₂, ψ).
//!
//! **Edge contact** (seed `000_…`, "Modeling edge contact conditions"): an
//! edge of one tooth (a boundary curve of its flank: the tip edge
//! u = u_tip(v), the toe v = v₀ or the heel v = v₁) touches the mating
//! flank where the points coincide and the edge tangent t lies in the
//! mating flank's tangent plane, t·n = 0: four equations in the edge
//! parameter s, the mating flank's (u, v) and ψ. The edge point lies on its
//! flank's boundary by construction, so on the tip edge it lies on the tip
//! (face) cone when u_tip is the face-cone line (the seed's third
//! equation).
//!
//! Both systems are solved by Newton's method with a central-difference
//! Jacobian (the generated surfaces of a bevel member have no closed-form
//! second derivatives), with step halving on the residual and at most
//! [`MAX_ITERATIONS`] steps; a system that does not converge is an error
//! that states its residual, never a silent answer. A Jacobian column
//! evaluates only the member its unknown moves (the other member's surface
//! is the iterate's; the gear turn ψ moves no surface): 8 surface
//! evaluations a flank-system column set instead of 20, the same numbers.
//!
//! Conventions: points and vectors global (mm); the gear's extra turn ψ
//! (rad) is right-handed about [`GearTurn::axis`]; the contact normal
//! points from the pinion into the gear (−n₂, the gear flank's inward
//! normal).

use crate::geometry::frame::Frame;
use crate::geometry::surface::ToothSurface;
use crate::geometry::vec3::{add, cross, dot, norm, sub, unit, V3};

/// Newton steps at most.
pub const MAX_ITERATIONS: usize = 60;
/// Convergence: coincidence of the points (mm).
pub const POINT_TOLERANCE: f64 = 1e-10;
/// Convergence: sine of the angle between a tangent and the mating tangent
/// plane.
pub const ANGLE_TOLERANCE: f64 = 1e-11;

/// A boundary curve of a flank along which an edge contact runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Edge {
    /// u = u_tip(v): the tooth's tip edge, parameter v.
    Tip,
    /// v = v₀ (the toe of a bevel member, one face end of a cylindrical
    /// one), parameter u.
    Toe,
    /// v = v₁, parameter u.
    Heel,
}

impl Edge {
    /// (u, v) of the edge point with parameter `s`.
    pub fn uv(self, surface: &dyn ToothSurface, s: f64) -> [f64; 2] {
        match self {
            Edge::Tip => [surface.u_tip(s), s],
            Edge::Toe => [s, surface.v_range().0],
            Edge::Heel => [s, surface.v_range().1],
        }
    }

    /// The edge parameter of the flank point (u, v).
    pub fn parameter(self, uv: [f64; 2]) -> f64 {
        match self {
            Edge::Tip => uv[1],
            Edge::Toe | Edge::Heel => uv[0],
        }
    }

    /// Unit tangent of the edge at `s` (own frame).
    pub fn tangent(self, surface: &dyn ToothSurface, s: f64) -> V3 {
        match self {
            Edge::Tip => surface.tip_edge_tangent(s),
            Edge::Toe | Edge::Heel => {
                let [u, v] = self.uv(surface, s);
                unit(surface.derivatives(u, v).0)
            }
        }
    }

    /// Direction on the flank pointing out across the edge (own frame, in
    /// the tangent plane, normal to the edge): beyond the tip (+r_u), before
    /// the toe (−r_v), beyond the heel (+r_v).
    fn outward(self, surface: &dyn ToothSurface, uv: [f64; 2]) -> V3 {
        let (pu, pv) = surface.derivatives(uv[0], uv[1]);
        match self {
            Edge::Tip => pu,
            Edge::Toe => [-pv[0], -pv[1], -pv[2]],
            Edge::Heel => pv,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Edge::Tip => "tip",
            Edge::Toe => "toe",
            Edge::Heel => "heel",
        }
    }
}

/// Which system holds at a contact.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ContactSystem {
    /// Flank against flank.
    Flank,
    /// An edge of the pinion tooth against the gear flank.
    PinionEdge(Edge),
    /// An edge of the gear tooth against the pinion flank.
    GearEdge(Edge),
}

impl ContactSystem {
    pub fn name(self) -> String {
        match self {
            ContactSystem::Flank => "flank".into(),
            ContactSystem::PinionEdge(e) => format!("pinion {} edge", e.name()),
            ContactSystem::GearEdge(e) => format!("gear {} edge", e.name()),
        }
    }

    fn unknowns(self) -> usize {
        match self {
            ContactSystem::Flank => 5,
            _ => 4,
        }
    }
}

/// A flank placed by its body's frame (own → global).
#[derive(Clone, Copy, Debug)]
pub struct PlacedFlank<'a> {
    pub surface: &'a dyn ToothSurface,
    pub frame: Frame,
}

/// The axis the gear turns about to meet the pinion (global, unit axis).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GearTurn {
    pub point: V3,
    pub axis: V3,
}

/// Where to start: flank parameters of both members and the gear turn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TangencySeed {
    pub pinion_uv: [f64; 2],
    pub gear_uv: [f64; 2],
    pub turn: f64,
}

/// A solved contact (module docs for the conventions).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tangency {
    pub system: ContactSystem,
    pub pinion_uv: [f64; 2],
    pub gear_uv: [f64; 2],
    /// Gear turn ψ (rad).
    pub turn: f64,
    /// Contact point (global, gear turned).
    pub point: V3,
    /// Unit contact normal from the pinion into the gear.
    pub normal: V3,
    /// Edge contacts: the edge tangent's component along the mating
    /// flank's normal, t·n (0 at a solution); flank contacts: the sine of
    /// the angle between the normals' directions, |n₁ × n₂|.
    pub tangency_residual: f64,
    /// Distance between the two contact points (mm).
    pub point_residual: f64,
    /// Edge contacts: the share of the contact normal that leans out across
    /// the edge (> 0: the mating flank rests on the edge; ≤ 0: it would
    /// cut into the edge body's flank, so the edge is not where the bodies
    /// touch). Flank contacts: 0.
    pub edge_lean: f64,
    pub iterations: usize,
}

impl Tangency {
    pub fn seed(&self) -> TangencySeed {
        TangencySeed {
            pinion_uv: self.pinion_uv,
            gear_uv: self.gear_uv,
            turn: self.turn,
        }
    }
}

/// Why a system has no solution from the seed.
#[derive(Clone, Debug, PartialEq)]
pub struct TangencyFailure {
    pub system: ContactSystem,
    pub iterations: usize,
    /// Residual norm where the iteration stopped.
    pub residual: f64,
    pub reason: &'static str,
}

impl std::fmt::Display for TangencyFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} contact: {} after {} Newton steps (residual {:.3e})",
            self.system.name(),
            self.reason,
            self.iterations,
            self.residual
        )
    }
}

/// One member's surface at its parameters (own frame): point, unit
/// normal, r_u, r_v and, for the member whose edge the system follows, the
/// edge's unit tangent.
#[derive(Clone, Copy)]
struct MemberEval {
    uv: [f64; 2],
    point: V3,
    normal: V3,
    ru: V3,
    rv: V3,
    tangent: Option<V3>,
}

/// The state of one evaluation.
struct Evaluation {
    residual: [f64; 5],
    pinion_uv: [f64; 2],
    gear_uv: [f64; 2],
    x1: V3,
    x2: V3,
    n1: V3,
    n2: V3,
    /// The members' surfaces behind it (a Jacobian column that moves one
    /// member's parameters reuses the other's).
    members: [MemberEval; 2],
}

/// The gear's frame turned by ψ.
fn turned(gear: &PlacedFlank, turn: &GearTurn, psi: f64) -> Frame {
    Frame::about_axis(turn.point, turn.axis, psi).compose(&gear.frame)
}

/// Which unknowns of `system` move member `m` (0 pinion, 1 gear); the
/// last unknown, ψ, moves neither surface (only the gear's frame).
fn moves_member(system: ContactSystem, m: usize, k: usize) -> bool {
    let pinion_unknowns = match system {
        ContactSystem::Flank => 2,
        ContactSystem::PinionEdge(_) => 1,
        ContactSystem::GearEdge(_) => 2,
    };
    let n = system.unknowns();
    match m {
        0 => k < pinion_unknowns,
        _ => k >= pinion_unknowns && k < n - 1,
    }
}

/// Member `m`'s surface at the unknowns `x` (one surface evaluation, and
/// the edge tangent when `m` carries the system's edge).
fn evaluate_member(
    system: ContactSystem,
    m: usize,
    pinion: &PlacedFlank,
    gear: &PlacedFlank,
    x: &[f64],
) -> MemberEval {
    let (surface, uv, edge) = match (system, m) {
        (ContactSystem::Flank, 0) => (pinion.surface, [x[0], x[1]], None),
        (ContactSystem::Flank, _) => (gear.surface, [x[2], x[3]], None),
        (ContactSystem::PinionEdge(e), 0) => {
            (pinion.surface, e.uv(pinion.surface, x[0]), Some((e, x[0])))
        }
        (ContactSystem::PinionEdge(_), _) => (gear.surface, [x[1], x[2]], None),
        (ContactSystem::GearEdge(_), 0) => (pinion.surface, [x[0], x[1]], None),
        (ContactSystem::GearEdge(e), _) => {
            (gear.surface, e.uv(gear.surface, x[2]), Some((e, x[2])))
        }
    };
    let (point, normal, ru, rv) = surface.evaluate(uv[0], uv[1]);
    MemberEval {
        uv,
        point,
        normal,
        ru,
        rv,
        tangent: edge.map(|(e, s)| e.tangent(surface, s)),
    }
}

/// The residuals of `system` at the unknowns `x` from both members'
/// surfaces there.
fn combine(
    system: ContactSystem,
    pinion: &PlacedFlank,
    gear: &PlacedFlank,
    turn: &GearTurn,
    x: &[f64],
    members: [MemberEval; 2],
) -> Option<Evaluation> {
    let psi = x[system.unknowns() - 1];
    let [m1, m2] = members;
    let f1 = pinion.frame;
    let f2 = turned(gear, turn, psi);
    let (x1, x2) = (f1.place(m1.point), f2.place(m2.point));
    let (n1, n2) = (f1.rotate(m1.normal), f2.rotate(m2.normal));
    let d = sub(x1, x2);
    let mut residual = [d[0], d[1], d[2], 0.0, 0.0];
    match system {
        ContactSystem::Flank => {
            residual[3] = dot(unit(f1.rotate(m1.ru)), n2);
            residual[4] = dot(unit(f1.rotate(m1.rv)), n2);
        }
        ContactSystem::PinionEdge(_) => {
            residual[3] = dot(f1.rotate(m1.tangent?), n2);
        }
        ContactSystem::GearEdge(_) => {
            residual[3] = dot(f2.rotate(m2.tangent?), n1);
        }
    }
    if residual.iter().any(|r| !r.is_finite()) {
        return None;
    }
    Some(Evaluation {
        residual,
        pinion_uv: m1.uv,
        gear_uv: m2.uv,
        x1,
        x2,
        n1,
        n2,
        members,
    })
}

fn evaluate(
    system: ContactSystem,
    pinion: &PlacedFlank,
    gear: &PlacedFlank,
    turn: &GearTurn,
    x: &[f64],
) -> Option<Evaluation> {
    let members = [0, 1].map(|m| evaluate_member(system, m, pinion, gear, x));
    combine(system, pinion, gear, turn, x, members)
}

/// [`evaluate`] at `x`, which differs from `base`'s unknowns in unknown
/// `k` only: the member that unknown does not move is taken from `base`
/// (ψ moves neither). The same numbers as [`evaluate`] (a surface
/// evaluation depends on its parameters only).
fn evaluate_moved(
    system: ContactSystem,
    pinion: &PlacedFlank,
    gear: &PlacedFlank,
    turn: &GearTurn,
    x: &[f64],
    base: &Evaluation,
    k: usize,
) -> Option<Evaluation> {
    let members = [0, 1].map(|m| {
        if moves_member(system, m, k) {
            evaluate_member(system, m, pinion, gear, x)
        } else {
            base.members[m]
        }
    });
    combine(system, pinion, gear, turn, x, members)
}

/// Newton's method on `system` from `seed` (module docs).
pub fn solve(
    system: ContactSystem,
    pinion: &PlacedFlank,
    gear: &PlacedFlank,
    turn: &GearTurn,
    seed: &TangencySeed,
) -> Result<Tangency, TangencyFailure> {
    let n = system.unknowns();
    let mut x: Vec<f64> = match system {
        ContactSystem::Flank => vec![
            seed.pinion_uv[0],
            seed.pinion_uv[1],
            seed.gear_uv[0],
            seed.gear_uv[1],
            seed.turn,
        ],
        ContactSystem::PinionEdge(e) => vec![
            e.parameter(seed.pinion_uv),
            seed.gear_uv[0],
            seed.gear_uv[1],
            seed.turn,
        ],
        ContactSystem::GearEdge(e) => vec![
            seed.pinion_uv[0],
            seed.pinion_uv[1],
            e.parameter(seed.gear_uv),
            seed.turn,
        ],
    };
    let span = |s: &dyn ToothSurface, i: usize| {
        let (a, b) = if i == 0 { s.u_range() } else { s.v_range() };
        (b - a).abs().max(1e-3)
    };
    // finite-difference steps per unknown
    let (ps, gs) = (pinion.surface, gear.surface);
    let steps: Vec<f64> = match system {
        ContactSystem::Flank => vec![span(ps, 0), span(ps, 1), span(gs, 0), span(gs, 1)],
        ContactSystem::PinionEdge(e) => vec![
            span(ps, if e == Edge::Tip { 1 } else { 0 }),
            span(gs, 0),
            span(gs, 1),
        ],
        ContactSystem::GearEdge(e) => vec![
            span(ps, 0),
            span(ps, 1),
            span(gs, if e == Edge::Tip { 1 } else { 0 }),
        ],
    }
    .into_iter()
    .map(|s| 1e-7 * s)
    .chain(std::iter::once(1e-8))
    .collect();
    // residual weight: angles as lengths over a tenth of the gear's span
    let scale = 0.1 * span(gs, 1);
    let merit = |e: &Evaluation| -> f64 {
        let r = &e.residual;
        (r[0] * r[0] + r[1] * r[1] + r[2] * r[2] + scale * scale * (r[3] * r[3] + r[4] * r[4]))
            .sqrt()
    };
    let fail = |iterations, residual, reason| TangencyFailure {
        system,
        iterations,
        residual,
        reason,
    };
    let Some(mut e) = evaluate(system, pinion, gear, turn, &x) else {
        return Err(fail(
            0,
            f64::NAN,
            "the seed lies where a surface is undefined",
        ));
    };
    let converged = |e: &Evaluation| {
        norm(sub(e.x1, e.x2)) <= POINT_TOLERANCE
            && e.residual[3].abs() <= ANGLE_TOLERANCE
            && e.residual[4].abs() <= ANGLE_TOLERANCE
    };
    let mut iterations = 0;
    while !converged(&e) {
        if iterations == MAX_ITERATIONS {
            return Err(fail(iterations, merit(&e), "no convergence"));
        }
        iterations += 1;
        // Jacobian by central differences
        let mut jac = nalgebra::DMatrix::<f64>::zeros(n, n);
        for k in 0..n {
            let (mut xp, mut xm) = (x.clone(), x.clone());
            xp[k] += steps[k];
            xm[k] -= steps[k];
            let (Some(ep), Some(em)) = (
                evaluate_moved(system, pinion, gear, turn, &xp, &e, k),
                evaluate_moved(system, pinion, gear, turn, &xm, &e, k),
            ) else {
                return Err(fail(
                    iterations,
                    merit(&e),
                    "a surface is undefined next to the iterate",
                ));
            };
            for i in 0..n {
                jac[(i, k)] = (ep.residual[i] - em.residual[i]) / (2.0 * steps[k]);
            }
        }
        let rhs = nalgebra::DVector::from_iterator(n, e.residual[..n].iter().map(|r| -r));
        // least-norm step (SVD): a line contact (conjugate flanks) makes
        // the flank system rank-deficient by one; the step then goes to the
        // nearest point of the contact line
        let svd = jac.svd(true, true);
        let smax = svd.singular_values.max();
        let dx = match svd.solve(&rhs, 1e-10 * smax) {
            Ok(dx) if smax > 0.0 && dx.iter().all(|d| d.is_finite()) => dx,
            _ => return Err(fail(iterations, merit(&e), "singular system")),
        };
        let m0 = merit(&e);
        let mut t = 1.0;
        let mut accepted = None;
        for _ in 0..30 {
            let xt: Vec<f64> = x.iter().zip(dx.iter()).map(|(a, d)| a + t * d).collect();
            if let Some(et) = evaluate(system, pinion, gear, turn, &xt) {
                if merit(&et) < m0 || converged(&et) {
                    accepted = Some((xt, et));
                    break;
                }
            }
            t *= 0.5;
        }
        match accepted {
            Some((xt, et)) => {
                x = xt;
                e = et;
            }
            None => {
                // no decrease: converged to rounding if the residual is tiny
                if m0 <= 1e3 * POINT_TOLERANCE {
                    break;
                }
                return Err(fail(iterations, m0, "no step decreases the residual"));
            }
        }
    }
    let psi = x[n - 1];
    let normal = [-e.n2[0], -e.n2[1], -e.n2[2]];
    let (tangency_residual, edge_lean) = match system {
        ContactSystem::Flank => {
            if dot(e.n1, e.n2) >= 0.0 {
                return Err(fail(
                    iterations,
                    merit(&e),
                    "the flanks' normals point the same way",
                ));
            }
            (norm(cross(e.n1, e.n2)), 0.0)
        }
        ContactSystem::PinionEdge(edge) => {
            let out = pinion
                .frame
                .rotate(edge.outward(pinion.surface, e.pinion_uv));
            let m = unit(add(out, -dot(out, e.n1), e.n1));
            (e.residual[3].abs(), dot(normal, m))
        }
        ContactSystem::GearEdge(edge) => {
            let f2 = turned(gear, turn, psi);
            let out = f2.rotate(edge.outward(gear.surface, e.gear_uv));
            let m = unit(add(out, -dot(out, e.n2), e.n2));
            // as for the pinion's edge with the roles swapped: the mating
            // (pinion) flank's normal into its own body, −n₁, across the
            // gear's edge (m lies in the gear's tangent plane, so n₂·m,
            // used here before, is 0 by construction)
            (e.residual[3].abs(), -dot(e.n1, m))
        }
    };
    Ok(Tangency {
        system,
        pinion_uv: e.pinion_uv,
        gear_uv: e.gear_uv,
        turn: psi,
        point: e.x1,
        normal,
        tangency_residual,
        point_residual: norm(sub(e.x1, e.x2)),
        edge_lean,
        iterations,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::surface::closest_point_newton;

    /// A sphere patch of radius `r` about `c`, outward normal (u, v) =
    /// (polar angle from −x toward +z, azimuth about x): a crowned "tooth"
    /// whose tip edge is u = 0.6 and whose face ends are v = ±0.5.
    #[derive(Debug)]
    struct Ball {
        c: V3,
        r: f64,
    }

    impl ToothSurface for Ball {
        fn u_range(&self) -> (f64, f64) {
            (-0.6, 0.6)
        }
        fn v_range(&self) -> (f64, f64) {
            (-0.5, 0.5)
        }
        fn u_tip(&self, _v: f64) -> f64 {
            0.6
        }
        fn u_form(&self, _v: f64) -> f64 {
            -0.6
        }
        fn u_root(&self, _v: f64) -> f64 {
            -0.6
        }
        fn point(&self, u: f64, v: f64) -> V3 {
            add(self.c, self.r, self.normal(u, v))
        }
        fn normal(&self, u: f64, v: f64) -> V3 {
            // direction: +x turned by u toward +y and by v toward +z
            [u.cos() * v.cos(), u.sin() * v.cos(), v.sin()]
        }
        fn derivatives(&self, u: f64, v: f64) -> (V3, V3) {
            let r = self.r;
            (
                [-r * u.sin() * v.cos(), r * u.cos() * v.cos(), 0.0],
                [-r * u.cos() * v.sin(), -r * u.sin() * v.sin(), r * v.cos()],
            )
        }
    }

    fn placed(s: &Ball) -> PlacedFlank<'_> {
        PlacedFlank {
            surface: s,
            frame: Frame::IDENTITY,
        }
    }

    /// Two balls, the "gear" one turned about the z axis through (0, d, 0):
    /// the contact lies on the line of centres; ψ closes the gap exactly.
    #[test]
    fn two_balls_touch_on_the_line_of_centres() {
        let pinion = Ball {
            c: [0.0, 0.0, 0.0],
            r: 10.0,
        };
        // gear ball: outward normal −x at (u, v) = (π, 0)... use a ball whose
        // frame is turned by π about z so that its (0, 0) faces −x
        let gear = Ball {
            c: [0.0, 0.0, 0.0],
            r: 5.0,
        };
        let d = 40.0;
        let gear_frame = Frame::about_z(std::f64::consts::PI, [25.0, d, 0.0]);
        let g = PlacedFlank {
            surface: &gear,
            frame: gear_frame,
        };
        // a simple root: the gear centre's circle crosses |c| = 15
        let turn = GearTurn {
            point: [0.0, 30.0, 0.0],
            axis: [0.0, 0.0, 1.0],
        };
        let seed = TangencySeed {
            pinion_uv: [0.3, 0.0],
            gear_uv: [0.1, 0.05],
            turn: 0.2,
        };
        let t = solve(ContactSystem::Flank, &placed(&pinion), &g, &turn, &seed).unwrap();
        // gear centre after the turn at distance 15 from the pinion centre
        let gc = Frame::about_axis(turn.point, turn.axis, t.turn).place([25.0, d, 0.0]);
        assert!((norm(gc) - 15.0).abs() < 1e-9, "{}", norm(gc));
        assert!(norm(sub(t.point, add([0.0; 3], 10.0 / 15.0, gc))) < 1e-9);
        assert!(norm(sub(t.normal, unit(gc))) < 1e-9);
        assert!(t.point_residual < 1e-10 && t.tangency_residual < 1e-10);
        assert!(t.iterations < 15, "{}", t.iterations);
    }

    /// The tip edge (u = 0.6) of a ball against a plane-like large ball:
    /// the edge point satisfies t·n = 0 and lies on the edge; the closest
    /// point of the mating surface to it is itself (touching, not cutting).
    #[test]
    fn tip_edge_against_a_flank() {
        let pinion = Ball {
            c: [0.0, 0.0, 0.0],
            r: 10.0,
        };
        let gear = Ball {
            c: [0.0, 0.0, 0.0],
            r: 200.0,
        };
        // the big ball's (0, 0) faces −y after a turn of −π/2, placed so
        // that it lies beyond the pinion's tip edge direction
        let a: f64 = 0.9;
        let centre = [210.0 * a.cos(), 210.0 * a.sin(), 0.0];
        let frame = Frame::about_z(a + std::f64::consts::PI, centre);
        let g = PlacedFlank {
            surface: &gear,
            frame,
        };
        let turn = GearTurn {
            point: [0.0, 300.0, 0.0],
            axis: [0.0, 0.0, 1.0],
        };
        let seed = TangencySeed {
            pinion_uv: [0.6, 0.01],
            gear_uv: [0.0, 0.0],
            turn: 0.0,
        };
        let sys = ContactSystem::PinionEdge(Edge::Tip);
        let t = solve(sys, &placed(&pinion), &g, &turn, &seed).unwrap();
        assert_eq!(t.pinion_uv[0], 0.6);
        assert!(t.tangency_residual < 1e-10 && t.point_residual < 1e-10);
        // the mating sphere is tangent to the edge circle (radius 10 sin…):
        // the closest point of the turned gear sphere to the edge point is
        // the point itself, and the normal leans beyond the tip (a > 0.6)
        assert!(t.edge_lean > 0.0, "{}", t.edge_lean);
        let f2 = Frame::about_axis(turn.point, turn.axis, t.turn).compose(&frame);
        let own = f2.rotate_back(sub(t.point, f2.translation));
        let (_, _, dist) = closest_point_newton(&gear, own, 0.0, 0.0);
        assert!(dist.abs() < 1e-9, "{dist}");
        // flank contact from the same seed sits beyond the tip (u > 0.6)
        let f = solve(ContactSystem::Flank, &placed(&pinion), &g, &turn, &seed).unwrap();
        assert!(f.pinion_uv[0] > 0.6, "{:?}", f.pinion_uv);
    }

    /// The mirror of [`tip_edge_against_a_flank`]: the small ball is the
    /// gear (its tip edge u = 0.6), the large one the pinion, fixed; the
    /// gear turns until its edge touches. The lean is measured the same
    /// way from the gear's side (the share of the pinion's contact normal,
    /// into the pinion, that leans out across the gear's edge): > 0 here,
    /// as the flank contact from the same seed lies beyond the gear's tip.
    #[test]
    fn gear_tip_edge_against_a_pinion_flank() {
        let gear = Ball {
            c: [0.0, 0.0, 0.0],
            r: 10.0,
        };
        let pinion = Ball {
            c: [0.0, 0.0, 0.0],
            r: 200.0,
        };
        let a: f64 = 0.9;
        let centre = [210.0 * a.cos(), 210.0 * a.sin(), 0.0];
        let frame = Frame::about_z(a + std::f64::consts::PI, centre);
        let p = PlacedFlank {
            surface: &pinion,
            frame,
        };
        let turn = GearTurn {
            point: [0.0, 300.0, 0.0],
            axis: [0.0, 0.0, 1.0],
        };
        let seed = TangencySeed {
            pinion_uv: [0.0, 0.0],
            gear_uv: [0.6, 0.01],
            turn: 0.0,
        };
        let sys = ContactSystem::GearEdge(Edge::Tip);
        let t = solve(sys, &p, &placed(&gear), &turn, &seed).unwrap();
        assert_eq!(t.gear_uv[0], 0.6);
        assert!(t.tangency_residual < 1e-10 && t.point_residual < 1e-10);
        assert!(t.edge_lean > 1e-3, "{}", t.edge_lean);
        // touching, not cutting: the pinion ball's closest point to the
        // contact point is the point itself
        let own = frame.rotate_back(sub(t.point, frame.translation));
        let (_, _, dist) = closest_point_newton(&pinion, own, 0.0, 0.0);
        assert!(dist.abs() < 1e-9, "{dist}");
        let f = solve(ContactSystem::Flank, &p, &placed(&gear), &turn, &seed).unwrap();
        assert!(f.gear_uv[0] > 0.6, "{:?}", f.gear_uv);
    }

    #[test]
    fn a_seed_without_solution_is_an_error_with_its_residual() {
        let pinion = Ball {
            c: [0.0, 0.0, 0.0],
            r: 10.0,
        };
        let gear = Ball {
            c: [0.0, 0.0, 0.0],
            r: 5.0,
        };
        // the gear turns about the pinion's own centre line: the distance
        // between the centres never changes, no turn brings them to touch
        let g = PlacedFlank {
            surface: &gear,
            frame: Frame::about_z(std::f64::consts::PI, [40.0, 0.0, 0.0]),
        };
        let turn = GearTurn {
            point: [0.0, 0.0, 0.0],
            axis: [0.0, 0.0, 1.0],
        };
        let seed = TangencySeed {
            pinion_uv: [0.0, 0.0],
            gear_uv: [0.0, 0.0],
            turn: 0.0,
        };
        let e = solve(ContactSystem::Flank, &placed(&pinion), &g, &turn, &seed).unwrap_err();
        assert!(
            e.residual > 1.0 && e.to_string().contains("flank contact"),
            "{e}"
        );
    }
}
