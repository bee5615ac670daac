//! Tooth contact analysis of pairs in point contact (spiral bevel and
//! hypoid pairs with a localized bearing), with edge contact, through the
//! gear-pair interface ([`GearPair`]).
//!
//! # Method
//!
//! * **One trace serves every tooth pair.** The teeth of a body are turned
//!   copies of one tooth, so pair i (i pitches after the middle pair) at
//!   roll θ is the middle pair at θ − i·[`GearPair::tooth_roll_step`],
//!   misalignment included (it moves the whole gear). The middle pair is
//!   traced over a roll grid of step h = pitch / `positions_per_pitch`,
//!   each position's tangency seeded by the previous one
//!   ([`crate::geometry::tangency`]), and every pair at every grid position
//!   is read off the trace.
//! * **Flank and edge systems** (seed `000_…`): the flank system holds
//!   while its contact lies on both active flanks (form line to tip, toe to
//!   heel). Where it leaves them the crossing is located (regula falsi on
//!   the contact's distance to the flanks' boundaries, safeguarded by
//!   bisection) and, with edges on, the trace goes on with the edge system
//!   that takes over: each of the six edges (pinion or gear tip, toe,
//!   heel, against the mating flank) is solved at the next grid roll, and
//!   of those that hold the one that stops the gear first (largest lag, as
//!   for the TE envelope below) is the contact. An edge contact holds while its point stays
//!   on the edge and on the mating active flank and the mating flank rests
//!   on the edge (lean > 0, [`crate::geometry::tangency::Tangency::edge_lean`]).
//!   Each change of system is reported with its roll angle. The trace is
//!   bounded by `max_pitches` on each side of roll 0.
//! * **Transmission error** (seed 000: Δφ₂ = φ₂ − (z₁/z₂) φ₁, gear angle):
//!   each pair allows the driven gear to lag to the turn Δφ₂,ᵢ (in its
//!   drive sense) at which it touches; the gear rests on the pair that
//!   stops it first, so TE(θ) = maxᵢ Δφ₂,ᵢ(θ) and that pair is the active
//!   one. The separation of another pair is (TE − Δφ₂,ᵢ) times its gear
//!   moment arm (mm).
//! * **Kinematic contact ratio**: the roll span over which a pair is within
//!   the elastic approach δ of contact (separation ≤ δ), over the angular
//!   pitch. For a conjugate pair (TE ≡ 0) this is the path of contact over
//!   the pitch; the span where the flank contact exists at all is reported
//!   beside it (`flank_span_ratio`).
//! * **Contact ellipse** at δ from the curvatures, and by the numerical
//!   search of seed 000 ([`super::ellipse`]); at edge contacts only the
//!   search applies.
//! * **Velocities**: v_i = ω_i × (x − a_i) at the pinion speed, their
//!   tangential parts v_ti; sliding v_t1 − v_t2 (magnitude and direction:
//!   the LTCA's tangential direction), rolling |v_t1 + v_t2| / 2 (m/s).

use crate::error::FlankError;
use crate::geometry::bevel::body::BevelGear;
use crate::geometry::frame::Frame;
use crate::geometry::gear_pair::{Flank, GearBody, GearPair};
use crate::geometry::surface::ToothSurface;
use crate::geometry::tangency::{
    self, ContactSystem, Edge, GearTurn, PlacedFlank, Tangency, TangencySeed,
};
use crate::geometry::vec3::{add, cross, dot, norm, sub, unit, V3};
use crate::iteration_limits::{IterationLimits, LoopEnd};

pub use super::crossing::Crossing;
use super::crossing::{CrossingScan, ScanCount};
use super::ellipse::{curvature_ellipse, searched_ellipse, ContactEllipse, FlankAtContact};

type Result<T> = std::result::Result<T, FlankError>;

/// Arc seconds per radian (TE is reported in arc seconds).
pub const ARCSEC_PER_RAD: f64 = 180.0 * 3600.0 / std::f64::consts::PI;

/// Settings of the point-contact TCA.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct PointTcaSettings {
    /// Grid positions per angular pitch (≥ 4).
    pub positions_per_pitch: usize,
    /// Elastic approach δ of the contact ellipse and the contact ratio (mm;
    /// seed 000: 0.00635 for finished teeth, 0.00381 lapped).
    pub approach_mm: f64,
    /// Edge contact on (seed 000 "with") or off ("without").
    pub edges: bool,
    /// Planes of the numerical ellipse search over 180° (0: none).
    pub search_directions: usize,
    /// Trace bound on each side of roll 0 (pitches).
    pub max_pitches: f64,
    /// Pinion speed for the velocities (rpm).
    pub speed_rpm: f64,
    /// The crossing check tests every grid point exactly instead of
    /// screening them ([`super::crossing`]; the screen's reference).
    pub crossing_exhaustive: bool,
}

impl Default for PointTcaSettings {
    fn default() -> Self {
        PointTcaSettings {
            positions_per_pitch: 30,
            approach_mm: 0.00635,
            edges: true,
            search_directions: 18,
            max_pitches: 3.0,
            speed_rpm: 1000.0,
            crossing_exhaustive: false,
        }
    }
}

impl PointTcaSettings {
    pub fn validate(&self) -> Result<()> {
        let err = |m: String| Err(FlankError::Model(format!("TCA settings: {m}")));
        if !(4..=10_000).contains(&self.positions_per_pitch) {
            return err(format!(
                "positions_per_pitch = {}: between 4 and 10000 are needed",
                self.positions_per_pitch
            ));
        }
        if !(self.approach_mm.is_finite() && self.approach_mm > 0.0) {
            return err(format!(
                "approach δ = {} mm: a finite positive elastic approach is needed (seed 000: 0.00635 mm, 0.00381 mm lapped)",
                self.approach_mm
            ));
        }
        if self.search_directions != 0 && !(4..=3600).contains(&self.search_directions) {
            return err(format!(
                "search_directions = {}: 0 (no search) or 4 to 3600 planes are needed",
                self.search_directions
            ));
        }
        if !(self.max_pitches.is_finite() && self.max_pitches >= 1.0 && self.max_pitches <= 20.0) {
            return err(format!(
                "max_pitches = {}: between 1 and 20 pitches are needed",
                self.max_pitches
            ));
        }
        if !(self.speed_rpm.is_finite() && self.speed_rpm >= 0.0) {
            return err(format!(
                "speed {} rpm: a finite value ≥ 0 is needed",
                self.speed_rpm
            ));
        }
        Ok(())
    }
}

/// One tooth pair at one position.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct PairContact {
    /// Pitches after the middle pair (0 = the middle pair).
    pub offset: i64,
    /// Sector teeth (pinion, gear) when the pair lies in the sector.
    pub teeth: Option<[usize; 2]>,
    pub system: ContactSystem,
    pub pinion_uv: [f64; 2],
    pub gear_uv: [f64; 2],
    /// Global point and unit normal (pinion → gear).
    pub point: V3,
    pub normal: V3,
    /// The gear lag this pair allows, Δφ₂,ᵢ (rad, gear angle, drive sense).
    pub gear_lag_rad: f64,
    /// (TE − Δφ₂,ᵢ) × gear moment arm (mm): 0 on the active pair.
    pub separation_mm: f64,
    pub active: bool,
    /// Moment arms of the contact normal about the pinion and the gear axis
    /// (mm).
    pub moment_arm_mm: [f64; 2],
    /// Flank projection of the contact on (pinion, gear): (along the face
    /// from the mean point toward the heel, height above the pitch cone) in
    /// the axial section of a bevel member (mm); (z, radius) otherwise.
    pub projection_mm: [[f64; 2]; 2],
    /// Curvature ellipse at δ (flank contacts).
    pub ellipse: Option<ContactEllipse>,
    /// Searched ellipse at δ (when the search is on).
    pub searched_ellipse: Option<ContactEllipse>,
    /// The ellipse's major axis (searched where the search ran, else from
    /// the curvatures) projected on (pinion, gear): its two ends in the
    /// members' flank projections (mm); `None` for line contact.
    pub major_axis_projection_mm: Option<[[[f64; 2]; 2]; 2]>,
    /// |v_t1 − v_t2| and |v_t1 + v_t2| / 2 (m/s).
    pub sliding_velocity: f64,
    pub rolling_velocity: f64,
    /// Unit direction of v_t1 − v_t2 (global; zero vector at pure rolling).
    pub sliding_direction: V3,
    /// Unit direction of v_t1 + v_t2, the entrainment (global; zero vector
    /// where the surfaces do not move).
    pub rolling_direction: V3,
    /// Point coincidence (mm) and tangency residual of the solve.
    pub residual: [f64; 2],
    pub edge_lean: f64,
    /// The frames (own → global) of pinion and gear that put their middle
    /// teeth (sector teeth `middle` and `mate(middle)`) in this contact:
    /// `placement[b].rotate_back(v)` is a global vector v at this contact
    /// in member b's own frame, on its middle tooth. For a pair at offset
    /// i ≠ 0 the same contact lies on tooth middle + i, the middle tooth's
    /// copy turned by i pitches.
    #[serde(skip)]
    pub placement: [Frame; 2],
}

/// One position of the cycle.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct PointTcaPosition {
    /// Pinion roll θ (rad).
    pub roll_rad: f64,
    /// Unloaded transmission error Δφ₂ (rad, gear angle).
    pub te_rad: f64,
    pub pairs: Vec<PairContact>,
}

/// A change of contact system of the middle pair.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Transition {
    pub roll_rad: f64,
    pub from: String,
    pub to: String,
}

/// The result of a point-contact TCA.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct PointTca {
    pub settings: PointTcaSettings,
    /// Angular pitch of the pinion (rad).
    pub pitch_rad: f64,
    pub positions: Vec<PointTcaPosition>,
    pub transitions: Vec<Transition>,
    /// Kinematic contact ratio at the approach δ (module docs).
    pub contact_ratio: f64,
    /// Span of the middle pair's flank contact on both active flanks, over
    /// the pitch.
    pub flank_span_ratio: f64,
    /// Peak-to-peak of the TE envelope over a pitch (rad).
    pub te_peak_to_peak_rad: f64,
    /// Whether the trace stopped at `max_pitches` on either side.
    pub hit_trace_bound: bool,
    /// Largest residuals over the trace (mm, tangency).
    pub max_residual: [f64; 2],
    /// Newton steps, total over the trace.
    pub newton_steps: usize,
    /// Grid solves whose Newton jumped off the traced branch (to a root
    /// past an edge while every roll before it held) and were solved again
    /// from the located contact next to the grid roll.
    pub branch_jumps: usize,
    /// The tangency Newton solves at the grid rolls: most steps, and those
    /// that ran out of iterations (the trace ends there).
    pub iteration_limits: IterationLimits,
    /// The deepest interpenetration of a pair's flanks found on a grid
    /// over the pinion's active flank, at every position of one pitch and
    /// for the pairs i = −2..=2 around the middle one, the gear where the
    /// TE envelope puts it ([`super::crossing`]); `None` when no grid point
    /// lies inside the gear: the traced contacts are where the bodies
    /// touch, as the method assumes.
    pub crossing: Option<Crossing>,
    /// Grid points of the crossing check, and how many of them the screen
    /// sent to the exact closest-point test.
    pub crossing_scan: ScanCount,
}

/// The middle pair's placed flanks and turn axis at a roll.
struct Placement<'a> {
    pinion: PlacedFlank<'a>,
    gear: PlacedFlank<'a>,
    turn: GearTurn,
}

fn placement<'a>(pair: &'a dyn GearPair, roll: f64) -> Placement<'a> {
    let km = pair.middle();
    let [f1, f2] = pair.frames(roll);
    let p = pair
        .pinion()
        .flank(Flank::Right, km)
        .expect("middle pinion tooth");
    let g = pair
        .gear()
        .flank(Flank::Right, pair.mate(km))
        .expect("middle gear tooth");
    Placement {
        pinion: PlacedFlank {
            surface: p,
            frame: f1,
        },
        gear: PlacedFlank {
            surface: g,
            frame: f2,
        },
        turn: GearTurn {
            point: f2.translation,
            axis: f2.rotate([0.0, 0.0, 1.0]),
        },
    }
}

fn solve_at(
    pair: &dyn GearPair,
    roll: f64,
    system: ContactSystem,
    seed: &TangencySeed,
) -> std::result::Result<Tangency, tangency::TangencyFailure> {
    let p = placement(pair, roll);
    tangency::solve(system, &p.pinion, &p.gear, &p.turn, seed)
}

/// The drive flanks of the middle pair (pinion, gear), on which the trace
/// runs.
fn middle_drive_flanks(pair: &dyn GearPair) -> (&dyn ToothSurface, &dyn ToothSurface) {
    let km = pair.middle();
    (
        pair.pinion().flank(Flank::Right, km).unwrap(),
        pair.gear().flank(Flank::Right, pair.mate(km)).unwrap(),
    )
}

/// A drive flank whose form line u_form(v) is remembered for the last few
/// v asked (on a face-hobbed flank it is a Newton of envelope solves, and
/// the boundary checks of one contact ask it at the same v: [`crossed`] or
/// [`edge_holds`], then [`holding_margin`]). The same numbers as
/// [`ToothSurface::u_form`].
struct FormMemo<'a> {
    surface: &'a dyn ToothSurface,
    seen: std::cell::RefCell<FormSeen>,
}

/// The last four (v bits, u_form) of a [`FormMemo`] and the slot to fill
/// next.
type FormSeen = ([Option<(u64, f64)>; 4], usize);

impl<'a> FormMemo<'a> {
    fn new(surface: &'a dyn ToothSurface) -> Self {
        FormMemo {
            surface,
            seen: std::cell::RefCell::new(([None; 4], 0)),
        }
    }

    fn u_form(&self, v: f64) -> f64 {
        let key = v.to_bits();
        let mut seen = self.seen.borrow_mut();
        if let Some((_, u)) = seen.0.iter().flatten().find(|(k, _)| *k == key) {
            return *u;
        }
        let u = self.surface.u_form(v);
        let slot = seen.1;
        seen.0[slot] = Some((key, u));
        seen.1 = (slot + 1) % 4;
        u
    }

    /// [`crate::geometry::surface::on_active_flank`] with the remembered
    /// form line.
    fn on_active_flank(&self, [u, v]: [f64; 2]) -> bool {
        let (v0, v1) = self.surface.v_range();
        v >= v0 && v <= v1 && u <= self.surface.u_tip(v) && u >= self.u_form(v)
    }
}

/// The middle pair's drive flanks (pinion, gear) for the boundary checks
/// of one trace.
struct DriveFlanks<'a> {
    pinion: FormMemo<'a>,
    gear: FormMemo<'a>,
}

impl<'a> DriveFlanks<'a> {
    fn new(pair: &'a dyn GearPair) -> Self {
        let (ps, gs) = middle_drive_flanks(pair);
        DriveFlanks {
            pinion: FormMemo::new(ps),
            gear: FormMemo::new(gs),
        }
    }
}

/// Where a flank contact lies: on both active flanks (`None`), or the
/// edge system of the first boundary it crossed (`Some(Some(_))`), or
/// below a form line (`Some(None)`: no edge takes over).
fn crossed(f: &DriveFlanks, t: &Tangency) -> Option<Option<ContactSystem>> {
    let edge = |m: &FormMemo, [u, v]: [f64; 2]| -> Option<Option<Edge>> {
        let s = m.surface;
        let (v0, v1) = s.v_range();
        if v < v0 {
            Some(Some(Edge::Toe))
        } else if v > v1 {
            Some(Some(Edge::Heel))
        } else if u > s.u_tip(v) {
            Some(Some(Edge::Tip))
        } else if u < m.u_form(v) {
            Some(None)
        } else {
            None
        }
    };
    match (edge(&f.pinion, t.pinion_uv), edge(&f.gear, t.gear_uv)) {
        (None, None) => None,
        (Some(Some(e)), _) => Some(Some(ContactSystem::PinionEdge(e))),
        (_, Some(Some(e))) => Some(Some(ContactSystem::GearEdge(e))),
        _ => Some(None),
    }
}

/// Whether a solution of `system` holds: a flank contact on both active
/// flanks ([`crossed`] is `None`), an edge contact on its edge
/// ([`edge_holds`]).
fn holds(f: &DriveFlanks, system: ContactSystem, t: &Tangency) -> bool {
    match system {
        ContactSystem::Flank => crossed(f, t).is_none(),
        _ => edge_holds(f, t),
    }
}

/// Whether an edge solution holds (module docs).
fn edge_holds(f: &DriveFlanks, t: &Tangency) -> bool {
    let on_edge = |m: &FormMemo, e: Edge, uv: [f64; 2]| {
        let s = m.surface;
        let (v0, v1) = s.v_range();
        match e {
            Edge::Tip => uv[1] >= v0 && uv[1] <= v1,
            Edge::Toe | Edge::Heel => uv[0] >= m.u_form(uv[1]) && uv[0] <= s.u_tip(uv[1]),
        }
    };
    t.edge_lean > 0.0
        && match t.system {
            ContactSystem::Flank => false,
            ContactSystem::PinionEdge(e) => {
                on_edge(&f.pinion, e, t.pinion_uv) && f.gear.on_active_flank(t.gear_uv)
            }
            ContactSystem::GearEdge(e) => {
                on_edge(&f.gear, e, t.gear_uv) && f.pinion.on_active_flank(t.pinion_uv)
            }
        }
}

/// One traced grid position of the middle pair.
#[derive(Clone, Debug)]
struct Traced {
    index: i64,
    contact: Tangency,
}

/// Traces the middle pair from roll 0 in the direction `dir` (±1).
fn trace(
    pair: &dyn GearPair,
    settings: &PointTcaSettings,
    h: f64,
    start: &Tangency,
    dir: i64,
    transitions: &mut Vec<Transition>,
    newton: &mut NewtonTally,
) -> Result<(Vec<Traced>, bool)> {
    let limit = (settings.max_pitches * settings.positions_per_pitch as f64).ceil() as i64;
    let mut out = Vec::new();
    let mut prev = *start;
    let mut prev_prev: Option<Tangency> = None;
    let mut system = ContactSystem::Flank;
    let flanks = &DriveFlanks::new(pair);
    for j in 1..=limit {
        let index = dir * j;
        let roll = index as f64 * h;
        // seed: the previous contact, its turn extrapolated linearly
        let mut seed = prev.seed();
        if let Some(pp) = prev_prev.filter(|pp| pp.system == prev.system) {
            seed.turn = 2.0 * prev.turn - pp.turn;
        }
        let solved = solve_at(pair, roll, system, &seed);
        match &solved {
            Ok(t) => {
                newton.steps += t.iterations;
                newton.record(LoopEnd::converged(
                    t.iterations,
                    tangency::MAX_ITERATIONS,
                    t.point_residual,
                ));
            }
            // the trace ends where Newton fails; one that ran out of
            // iterations is a bound hit, reported (the others say the
            // contact left a surface)
            Err(f) if f.iterations >= tangency::MAX_ITERATIONS => {
                newton.record(LoopEnd::at_limit(
                    f.iterations,
                    tangency::MAX_ITERATIONS,
                    f.residual,
                ));
            }
            Err(_) => {}
        }
        if solved.as_ref().is_ok_and(|t| holds(flanks, system, t)) {
            let t = solved.unwrap();
            prev_prev = Some(prev);
            prev = t;
            out.push(Traced { index, contact: t });
            continue;
        }
        // locate the change between the previous roll and this one
        let roll_prev = (index - dir) as f64 * h;
        let at_b = solved.ok().map(|t| holding_margin(flanks, &t));
        let (a, b, last) = locate_change(pair, flanks, system, (roll_prev, prev), (roll, at_b));
        // every trial up to the grid roll held (the bracket's end never
        // moved): the grid solve left the branch, Newton from the
        // extrapolated seed jumping to another root (seed 003 eased at
        // −34.909°: 4 mm away, beyond the tip, while the contact next to it
        // lies 1.5 mm inside). Solved again from the located contact on the
        // same branch; the trace goes on if that holds (counted).
        if b == roll {
            if let Ok(t) = solve_at(pair, roll, system, &last.seed()) {
                if holds(flanks, system, &t) {
                    newton.steps += t.iterations;
                    newton.branch_jumps += 1;
                    prev_prev = Some(prev);
                    prev = t;
                    out.push(Traced { index, contact: t });
                    continue;
                }
            }
        }
        // which edge takes over: every edge system solved just past the
        // crossing and then at this grid roll; of those that hold, the one
        // that stops the gear first (module docs)
        let here = if system == ContactSystem::Flank && settings.edges {
            let uv = |t: &Tangency| [t.pinion_uv, t.gear_uv];
            let moved = uv(&prev)
                .iter()
                .zip(uv(&last))
                .map(|(p, l)| (p[0] - l[0]).hypot(p[1] - l[1]))
                .fold(0.0, f64::max);
            take_over(pair, flanks, b, roll, &last, moved, newton)
        } else {
            None
        };
        transitions.push(Transition {
            roll_rad: 0.5 * (a + b),
            from: system.name(),
            to: here.map_or_else(|| "none".into(), |t| t.system.name()),
        });
        let Some(t) = here else {
            return Ok((out, false));
        };
        system = t.system;
        prev_prev = None;
        prev = t;
        out.push(Traced { index, contact: t });
    }
    Ok((out, true))
}

/// The edge systems a flank contact can hand over to.
const EDGE_SYSTEMS: [ContactSystem; 6] = [
    ContactSystem::PinionEdge(Edge::Tip),
    ContactSystem::PinionEdge(Edge::Toe),
    ContactSystem::PinionEdge(Edge::Heel),
    ContactSystem::GearEdge(Edge::Tip),
    ContactSystem::GearEdge(Edge::Toe),
    ContactSystem::GearEdge(Edge::Heel),
];

/// How far a flank contact lies inside each edge of the active flanks
/// (mm in the flanks' (u, v); < 0 beyond it), in [`EDGE_SYSTEMS`]' order.
fn edge_distances(f: &DriveFlanks, t: &Tangency) -> [f64; 6] {
    let (ps, gs) = (f.pinion.surface, f.gear.surface);
    let three = |s: &dyn ToothSurface, [u, v]: [f64; 2]| {
        let (v0, v1) = s.v_range();
        [s.u_tip(v) - u, v - v0, v1 - v]
    };
    let (p, g) = (three(ps, t.pinion_uv), three(gs, t.gear_uv));
    [p[0], p[1], p[2], g[0], g[1], g[2]]
}

/// The edge contact that takes over where the flank contact `last` leaves
/// the active flanks (just before roll `past`), at the grid roll `roll`.
/// The candidates are the edges the contact is near: within twice the
/// distance it moved over the last grid step (`moved`, mm) of the flank
/// solution just past the crossing (the contact moves continuously from
/// the flank onto an edge). Each is solved at `past` from `last` (at the
/// crossing the mating normal lies in the edge's plane, lean 0 in exact
/// arithmetic, so that solve only seeds) and then at `roll`, where it must
/// hold; of those that hold, the one with the largest gear lag, the
/// feature that stops the gear first (the TE envelope's rule applied to
/// the edges). Trying every near edge, rather than only the one whose
/// boundary the flank solution just past the crossing lies beyond, makes
/// the choice independent of how precisely the crossing is located (two
/// boundaries can be a round-off apart there).
fn take_over(
    pair: &dyn GearPair,
    flanks: &DriveFlanks,
    past: f64,
    roll: f64,
    last: &Tangency,
    moved: f64,
    newton: &mut NewtonTally,
) -> Option<Tangency> {
    let sense2 = pair.rotation_axes()[1][2].signum();
    let beyond = solve_at(pair, past, ContactSystem::Flank, &last.seed()).unwrap_or(*last);
    let near = edge_distances(flanks, &beyond).map(|d| d <= 2.0 * moved + 1e-3);
    let mut best: Option<Tangency> = None;
    for (system, _) in EDGE_SYSTEMS.into_iter().zip(near).filter(|(_, n)| *n) {
        let seed = solve_at(pair, past, system, &last.seed())
            .map(|t| t.seed())
            .unwrap_or_else(|_| last.seed());
        let Ok(t) = solve_at(pair, roll, system, &seed) else {
            continue;
        };
        newton.steps += t.iterations;
        if edge_holds(flanks, &t) && best.is_none_or(|b| sense2 * t.turn > sense2 * b.turn) {
            best = Some(t);
        }
    }
    best
}

/// The bracket of [`locate_change`] shrinks to this share of the grid
/// step (h/2⁴⁰, the 40 bisections it replaced).
const CHANGE_WIDTH: f64 = 1.0 / (1u64 << 40) as f64;
/// Solves [`locate_change`] may spend (it needs about 10; bisection
/// alone needs 40).
const CHANGE_SOLVES: usize = 120;

/// How far a solved contact lies inside the region where its system holds
/// (mm; ≥ 0 inside, < 0 outside): the least distance in (u, v) to the
/// active flanks' boundaries (form line, tip, toe, heel) and, for an edge
/// system, to the edge's ends and the edge lean (10 mm per unit share). It
/// only guides [`locate_change`]'s trial rolls: whether a contact holds is
/// decided by [`crossed`] and [`edge_holds`].
fn holding_margin(f: &DriveFlanks, t: &Tangency) -> f64 {
    let face = |s: &dyn ToothSurface, v: f64| {
        let (v0, v1) = s.v_range();
        (v - v0).min(v1 - v)
    };
    let profile = |m: &FormMemo, [u, v]: [f64; 2]| (m.surface.u_tip(v) - u).min(u - m.u_form(v));
    let flank = |m: &FormMemo, uv: [f64; 2]| {
        let f = face(m.surface, uv[1]);
        // the form line is a Newton of envelope solves: not asked off the face
        if f < 0.0 {
            f
        } else {
            f.min(profile(m, uv))
        }
    };
    let edge = |m: &FormMemo, e: Edge, uv: [f64; 2]| match e {
        Edge::Tip => face(m.surface, uv[1]),
        Edge::Toe | Edge::Heel => profile(m, uv),
    };
    let (p, g) = (&f.pinion, &f.gear);
    match t.system {
        ContactSystem::Flank => flank(p, t.pinion_uv).min(flank(g, t.gear_uv)),
        ContactSystem::PinionEdge(e) => (10.0 * t.edge_lean)
            .min(edge(p, e, t.pinion_uv))
            .min(flank(g, t.gear_uv)),
        ContactSystem::GearEdge(e) => (10.0 * t.edge_lean)
            .min(edge(g, e, t.gear_uv))
            .min(flank(p, t.pinion_uv)),
    }
}

/// Where `system` stops holding between roll a (it holds there: the
/// contact `at_a`) and roll b (it does not; the margin of its solution
/// there, `None` when it did not solve): the bracket [a, b] shrunk to
/// [`CHANGE_WIDTH`] of its width, and the last contact that holds. Trial
/// rolls by regula falsi on [`holding_margin`] with the Illinois halving,
/// a bisection when the margin at b is unknown or the bracket did not
/// halve in two trials; each trial solved from the last contact that
/// holds. Bounded by [`CHANGE_SOLVES`] solves (the bracket is then wider).
fn locate_change(
    pair: &dyn GearPair,
    flanks: &DriveFlanks,
    system: ContactSystem,
    (a0, at_a): (f64, Tangency),
    (b0, margin_b): (f64, Option<f64>),
) -> (f64, f64, Tangency) {
    let width = (b0 - a0).abs() * CHANGE_WIDTH;
    let (mut a, mut b, mut last) = (a0, b0, at_a);
    let mut ga = holding_margin(flanks, &at_a).max(0.0);
    let mut gb = margin_b.filter(|g| g.is_finite() && *g <= 0.0);
    // which end was kept by the last trial (Illinois), and the bracket's
    // width two trials ago
    let mut kept: Option<bool> = None;
    let mut widths = [(b - a).abs(); 2];
    for _ in 0..CHANGE_SOLVES {
        if (b - a).abs() <= width {
            break;
        }
        let secant = match gb {
            Some(g) if ga - g > 0.0 && (b - a).abs() <= 0.5 * widths[0] => {
                Some((ga / (ga - g)).clamp(1e-3, 1.0 - 1e-3))
            }
            _ => None,
        };
        let share = secant.unwrap_or(0.5);
        let m = a + share * (b - a);
        widths = [widths[1], (b - a).abs()];
        match solve_at(pair, m, system, &last.seed()) {
            Ok(t) if holds(flanks, system, &t) => {
                last = t;
                a = m;
                ga = holding_margin(flanks, &t).max(0.0);
                if kept == Some(false) {
                    gb = gb.map(|g| 0.5 * g);
                }
                kept = Some(false);
            }
            solved => {
                b = m;
                gb = solved
                    .ok()
                    .map(|t| holding_margin(flanks, &t))
                    .filter(|g| g.is_finite() && *g <= 0.0);
                if kept == Some(true) {
                    ga *= 0.5;
                }
                kept = Some(true);
            }
        }
    }
    (a, b, last)
}

/// Axial-section projection of an own-frame point (module docs of
/// [`PairContact::projection_mm`]).
pub fn projection(body: &dyn GearBody, p: V3) -> [f64; 2] {
    let rho = p[0].hypot(p[1]);
    match body.as_any().downcast_ref::<BevelGear>() {
        Some(b) => {
            let c = b.cones();
            let (s, co) = c.delta.sin_cos();
            [p[2] * co + rho * s - c.rm, -p[2] * s + rho * co]
        }
        None => [p[2], rho],
    }
}

/// Numerical ellipse searches already done, shared between TCA runs of one
/// pair (e.g. with and without edge contact, whose flank contacts are the
/// same points): the search is the costly part of a point TCA (minutes on a
/// conjugate pinion, whose every surface point is a Newton solve), and its
/// result depends only on the contact it starts from. Keyed by the bits of
/// that contact (grid index, gear turn, point, normal, flank parameters)
/// and of the search settings, so only identical inputs share a result.
#[derive(Default)]
pub struct EllipseMemo {
    searched: std::sync::Mutex<std::collections::HashMap<Vec<u64>, ContactEllipse>>,
}

impl EllipseMemo {
    /// Searches stored so far.
    pub fn len(&self) -> usize {
        self.searched.lock().map(|m| m.len()).unwrap_or(0)
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    fn get_or_search(
        &self,
        key: Vec<u64>,
        search: impl FnOnce() -> ContactEllipse,
    ) -> ContactEllipse {
        if let Some(e) = self.searched.lock().ok().and_then(|m| m.get(&key).copied()) {
            return e;
        }
        let e = search();
        if let Ok(mut m) = self.searched.lock() {
            m.insert(key, e);
        }
        e
    }
}

/// The point-contact TCA of `pair` (module docs).
pub fn point_tca(pair: &dyn GearPair, settings: &PointTcaSettings) -> Result<PointTca> {
    point_tca_shared(pair, settings, &EllipseMemo::default())
}

/// [`point_tca`] reusing the ellipse searches of earlier runs on the same
/// pair held in `memo` (and adding its own): the results are those of
/// [`point_tca`] bit for bit.
pub fn point_tca_shared(
    pair: &dyn GearPair,
    settings: &PointTcaSettings,
    memo: &EllipseMemo,
) -> Result<PointTca> {
    settings.validate()?;
    let pitch = pair.pinion().angular_pitch();
    let step = pair.tooth_roll_step();
    let p_per = settings.positions_per_pitch as i64;
    let h = pitch / p_per as f64;
    let km = pair.middle();
    let (rm1, rm2) = (
        pair.pinion()
            .as_any()
            .downcast_ref::<BevelGear>()
            .map(|b| b.cones().rm),
        pair.gear()
            .as_any()
            .downcast_ref::<BevelGear>()
            .map(|b| b.cones().rm),
    );
    // roll 0: the flank contact near the mean points (or the middles of
    // the flanks' parameter boxes)
    let mid = |s: &dyn ToothSurface, rm: Option<f64>| {
        let v = rm.unwrap_or_else(|| 0.5 * (s.v_range().0 + s.v_range().1));
        [0.5 * (s.u_form(v) + s.u_tip(v)), v]
    };
    let ps = pair
        .pinion()
        .flank(Flank::Right, km)
        .ok_or_else(|| FlankError::Model("TCA: the pinion sector has no middle tooth".into()))?;
    let gs = pair
        .gear()
        .flank(Flank::Right, pair.mate(km))
        .ok_or_else(|| FlankError::Model("TCA: the gear sector has no mate tooth".into()))?;
    // other pairs: the middle of the pinion's active flank, and the gear
    // flank's point closest to it
    let pinion_uv = rm1.map(|r| [0.0, r]).unwrap_or_else(|| mid(ps, None));
    let gear_uv = rm2.map(|r| [0.0, r]).unwrap_or_else(|| {
        let [f1, f2] = pair.frames(0.0);
        let x = f1.place(ps.point(pinion_uv[0], pinion_uv[1]));
        let (u, v, _) = gs.closest_point(f2.rotate_back(sub(x, f2.translation)));
        [u, v]
    });
    let seed = TangencySeed {
        pinion_uv,
        gear_uv,
        turn: 0.0,
    };
    let start = solve_at(pair, 0.0, ContactSystem::Flank, &seed).map_err(|e| {
        FlankError::Model(format!(
            "TCA at roll 0: the middle pair's flanks do not touch ({e}): the pair does not mesh"
        ))
    })?;
    if let Some(c) = crossed(&DriveFlanks::new(pair), &start) {
        return Err(FlankError::Model(format!(
            "TCA at roll 0: the middle pair touches off its active flanks (pinion (u, v) = ({:.4}, {:.4}), gear ({:.4}, {:.4}){}): the bearing is not on the teeth",
            start.pinion_uv[0],
            start.pinion_uv[1],
            start.gear_uv[0],
            start.gear_uv[1],
            c.map(|s| format!(", beyond the {}", s.name())).unwrap_or_default()
        )));
    }
    let mut transitions = Vec::new();
    let mut newton = NewtonTally {
        steps: start.iterations,
        loops: IterationLimits::new(),
        branch_jumps: 0,
    };
    newton.record(LoopEnd::converged(
        start.iterations,
        tangency::MAX_ITERATIONS,
        start.point_residual,
    ));
    // the two directions are independent: traced side by side, each with
    // its own transitions and Newton tally (merged, then sorted by roll)
    let run = |dir: i64| {
        let mut found = Vec::new();
        let mut tally = NewtonTally {
            steps: 0,
            loops: IterationLimits::new(),
            branch_jumps: 0,
        };
        let traced = trace(pair, settings, h, &start, dir, &mut found, &mut tally);
        (traced, found, tally)
    };
    let ((back, found_b, tally_b), (fwd, found_f, tally_f)) = rayon::join(|| run(-1), || run(1));
    let (back, bound_b) = back?;
    let (fwd, bound_f) = fwd?;
    for (found, tally) in [(found_b, tally_b), (found_f, tally_f)] {
        transitions.extend(found);
        newton.steps += tally.steps;
        newton.branch_jumps += tally.branch_jumps;
        newton.loops.merge(&tally.loops);
    }
    let mut traced: Vec<Traced> = back.into_iter().rev().collect();
    traced.push(Traced {
        index: 0,
        contact: start,
    });
    traced.extend(fwd);
    transitions.sort_by(|a, b| a.roll_rad.total_cmp(&b.roll_rad));
    // gear lag in its drive sense; pair i at grid j is the middle pair at
    // j − i·P·sign(step)
    let sense2 = pair.rotation_axes()[1][2].signum();
    let shift = p_per * step.signum() as i64;
    let lag = |t: &Tangency| sense2 * t.turn;
    let envelope = |j: i64| -> f64 {
        let mut best = f64::NEG_INFINITY;
        for t in &traced {
            if (j - t.index).rem_euclid(shift.abs()) == 0 {
                best = best.max(lag(&t.contact));
            }
        }
        best
    };
    let omega1 = settings.speed_rpm * std::f64::consts::PI / 30.0;
    let omega2 = omega1 * pair.ratio();
    let axes = pair.rotation_axes();
    // Every traced point once (in parallel): its contact is the same for
    // every pair and position it stands for, and so is its separation from
    // the periodic envelope.
    use rayon::prelude::*;
    let per_point: Vec<PairContact> = traced
        .par_iter()
        .map(|tr| {
            let t = &tr.contact;
            let [g1, g2] = pair.frames(tr.index as f64 * h);
            let g2t =
                Frame::about_axis(g2.translation, g2.rotate([0.0, 0.0, 1.0]), t.turn).compose(&g2);
            let own1 = g1.rotate_back(sub(t.point, g1.translation));
            let own2 = g2t.rotate_back(sub(t.point, g2t.translation));
            let (x, n) = (t.point, t.normal);
            let a1 = g1.rotate(axes[0]);
            let a2 = g2t.rotate(axes[1]);
            let arm1 = dot(cross(a1, sub(x, g1.translation)), n);
            let arm2 = dot(cross(a2, sub(x, g2t.translation)), n);
            let separation = (envelope(tr.index) - lag(t)) * arm2.abs();
            // velocities
            let v1 = cross(a1, sub(x, g1.translation));
            let v2 = cross(a2, sub(x, g2t.translation));
            let tang = |v: V3| add(v, -dot(v, n), n);
            let (v1t, v2t) = (
                tang([omega1 * v1[0], omega1 * v1[1], omega1 * v1[2]]),
                tang([omega2 * v2[0], omega2 * v2[1], omega2 * v2[2]]),
            );
            let slide = sub(v1t, v2t);
            let roll_v = add(v1t, 1.0, v2t);
            let at1 = FlankAtContact {
                surface: ps,
                frame: g1,
                uv: t.pinion_uv,
            };
            let at2 = FlankAtContact {
                surface: gs,
                frame: g2t,
                uv: t.gear_uv,
            };
            let ellipse = (t.system == ContactSystem::Flank)
                .then(|| curvature_ellipse(&at1, &at2, n, settings.approach_mm));
            // the search only where the pair is within δ of contact
            let searched = (settings.search_directions > 0 && separation <= settings.approach_mm)
                .then(|| {
                    let span = ps.v_range().1 - ps.v_range().0;
                    let mut key = vec![tr.index as u64, settings.search_directions as u64];
                    key.extend(
                        [settings.approach_mm, span, t.turn]
                            .iter()
                            .chain(&x)
                            .chain(&n)
                            .chain(&t.pinion_uv)
                            .chain(&t.gear_uv)
                            .map(|v| v.to_bits()),
                    );
                    memo.get_or_search(key, || {
                        searched_ellipse(
                            &at1,
                            &at2,
                            x,
                            n,
                            settings.approach_mm,
                            settings.search_directions,
                            span,
                        )
                    })
                });
            let axis_ends = searched.or(ellipse).and_then(|e| {
                let a = e.semi_major_mm?;
                let d = e.major_direction;
                let end = |f: &Frame, body: &dyn GearBody, s: f64| {
                    projection(body, f.rotate_back(sub(add(x, s * a, d), f.translation)))
                };
                Some([
                    [end(&g1, pair.pinion(), -1.0), end(&g1, pair.pinion(), 1.0)],
                    [end(&g2t, pair.gear(), -1.0), end(&g2t, pair.gear(), 1.0)],
                ])
            });
            PairContact {
                offset: 0,
                teeth: None,
                system: t.system,
                pinion_uv: t.pinion_uv,
                gear_uv: t.gear_uv,
                point: x,
                normal: n,
                gear_lag_rad: lag(t),
                separation_mm: separation,
                active: separation <= 1e-12 * arm2.abs().max(1.0),
                moment_arm_mm: [arm1.abs(), arm2.abs()],
                projection_mm: [
                    projection(pair.pinion(), own1),
                    projection(pair.gear(), own2),
                ],
                ellipse,
                searched_ellipse: searched,
                major_axis_projection_mm: axis_ends,
                sliding_velocity: 1e-3 * norm(slide),
                rolling_velocity: 0.5e-3 * norm(roll_v),
                sliding_direction: if norm(slide) > 0.0 {
                    unit(slide)
                } else {
                    [0.0; 3]
                },
                rolling_direction: if norm(roll_v) > 0.0 {
                    unit(roll_v)
                } else {
                    [0.0; 3]
                },
                residual: [t.point_residual, t.tangency_residual],
                edge_lean: t.edge_lean,
                placement: [g1, g2t],
            }
        })
        .collect();
    let max_residual = per_point.iter().fold([0.0f64; 2], |m, c| {
        [m[0].max(c.residual[0]), m[1].max(c.residual[1])]
    });
    let in_contact = per_point
        .iter()
        .filter(|c| c.separation_mm <= settings.approach_mm)
        .count();
    let flank_span = per_point
        .iter()
        .filter(|c| c.system == ContactSystem::Flank)
        .count();
    let (j0, j1) = (traced[0].index, traced.last().unwrap().index);
    let n_sector = pair.sector_teeth() as i64;
    let mut positions = Vec::new();
    for j in j0..=j1 {
        let mut pairs = Vec::new();
        // every pair i whose trace index j − i·shift exists (pair i at this
        // roll is the middle pair at roll jj·h: its teeth are the middle
        // teeth turned by i pitches and the bodies have turned by i·step
        // since, so every global point and vector coincides)
        let imin = (j - j1).div_euclid(shift.abs()) - 1;
        let imax = (j - j0).div_euclid(shift.abs()) + 1;
        for ii in imin..=imax {
            let i = ii * shift.signum();
            let jj = j - i * shift;
            if jj < j0 || jj > j1 {
                continue;
            }
            let k = km as i64 + i;
            pairs.push(PairContact {
                offset: i,
                teeth: (k >= 1 && k <= n_sector).then(|| [k as usize, pair.mate(k as usize)]),
                ..per_point[(jj - j0) as usize].clone()
            });
        }
        pairs.sort_by_key(|p| p.offset);
        positions.push(PointTcaPosition {
            roll_rad: j as f64 * h,
            te_rad: envelope(j),
            pairs,
        });
    }
    // TE over one pitch of the periodic envelope
    let te: Vec<f64> = (0..shift.abs())
        .map(envelope)
        .filter(|t| t.is_finite())
        .collect();
    let te_pp = te.iter().cloned().fold(f64::NEG_INFINITY, f64::max)
        - te.iter().cloned().fold(f64::INFINITY, f64::min);
    // the gear where the envelope puts it, every modelled pair around it
    let scan = CrossingScan::new(pair);
    let checks: Vec<(Option<Crossing>, ScanCount)> = (0..shift.abs())
        .into_par_iter()
        .flat_map_iter(|j| (-2i64..=2).map(move |i| (j, i)))
        .map(|(j, i)| {
            let te = envelope(j);
            if !te.is_finite() {
                return (None, ScanCount::default());
            }
            let (roll, turn) = ((j - i * shift) as f64 * h, sense2 * te);
            let (c, n) = if settings.crossing_exhaustive {
                scan.check_every_point(roll, turn)
            } else {
                scan.check(roll, turn)
            };
            let c = c.map(|c| Crossing {
                roll_rad: j as f64 * h,
                pair_offset: i,
                ..c
            });
            (c, n)
        })
        .collect();
    let mut crossing_scan = ScanCount::default();
    for (_, n) in &checks {
        crossing_scan += *n;
    }
    let crossing = checks.into_iter().filter_map(|(c, _)| c).reduce(|a, b| {
        if b.depth_mm > a.depth_mm {
            b
        } else {
            a
        }
    });
    Ok(PointTca {
        settings: settings.clone(),
        pitch_rad: pitch,
        positions,
        transitions,
        contact_ratio: in_contact as f64 / p_per as f64,
        flank_span_ratio: flank_span as f64 / p_per as f64,
        te_peak_to_peak_rad: te_pp,
        hit_trace_bound: bound_b || bound_f,
        max_residual,
        newton_steps: newton.steps,
        branch_jumps: newton.branch_jumps,
        iteration_limits: newton.loops,
        crossing,
        crossing_scan,
    })
}

/// The tangency solves of a trace: Newton steps in all, and how the
/// grid-roll solves ended.
struct NewtonTally {
    steps: usize,
    loops: IterationLimits,
    /// Grid solves that left the traced branch and were solved again
    /// from the located contact.
    branch_jumps: usize,
}

impl NewtonTally {
    /// One tangency solve at a grid roll of the trace.
    fn record(&mut self, end: LoopEnd) {
        self.loops.record(
            "tca.tangency_newton",
            "point residual |r₁ − r₂| (mm; the merit at a failure)",
            tangency::POINT_TOLERANCE,
            end,
        );
    }
}
