//! Local synthesis of a face-milled pinion: its machine settings from the
//! gear's and three design targets at the mean contact point, after
//! Litvin & Zhang, *Local synthesis and tooth contact analysis of
//! face-milled spiral bevel gears*, NASA CR-4342 (1991), and Litvin &
//! Fuentes, *Gear Geometry and Applied Theory*, 2nd ed., §9.4–9.5
//! (curvature relations of mating surfaces, contact ellipse) and ch. 20.
//!
//! # What is imposed at the mean point M
//!
//! M is the mean pitch point P of the pair (both members' pitch-cone
//! points at their mean cone distances, placed on P at roll 0 by
//! [`BevelPair`]). Litvin's synthesis imposes, at M:
//!
//! 1. **first order** — the pinion and gear flanks pass through M with one
//!    normal, and the instantaneous ratio there is the nominal z₁/z₂ (the TE
//!    function has its vertex at M). The ISO 23509 blank makes the pitch
//!    cones touch at P with one tooth trace and one pressure angle for both
//!    members (clause 6.3's kinematic condition: the sliding velocity at P
//!    lies along the tooth trace), so a pinion whose generated flank meets
//!    its blank's spiral angle, pressure angle and thickness at its mean
//!    point ([`refined_setup_with`], to 1e-9 rad) meets the first order
//!    whatever its roll and cutter radius; the TE slope at M is measured and
//!    reported as the check of this;
//! 2. **second order** — three targets: the direction of the path of
//!    contact on the gear flank, the length 2a of the contact ellipse's
//!    major axis at the elastic approach δ, and the level of the parabolic
//!    TE (its fall over half an angular pitch π/z₁ from M, i.e.
//!    −½ TE''(θ_M) (π/z₁)², TE = Δφ₂ in gear angle).
//!
//! # How the second order is met
//!
//! Litvin solves the curvature relations in closed form for the pinion's
//! principal curvatures and then for three settings (cutter radius, ratio
//! of roll, modified roll 2C). flank solves the same three conditions on
//! the same three settings numerically: the unknowns are the pinion's mean
//! cutter radius r_c, the ratio of roll as a factor k of its pure-rolling
//! value and the modified-roll coefficient 2C; for each trial the settings
//! are re-matched to the blank at the mean point (first order), the trial
//! pair's contact at M is solved by the tangency system
//! ([`crate::geometry::tangency`]) at rolls 0, ±h, and the three measured
//! figures are the path inclination (from the gear contact points at ±h),
//! 2a from the relative curvature at M ([`curvature_ellipse`]) and TE'' by
//! the central second difference. A Newton iteration with a
//! forward-difference Jacobian and step halving (bounded; it says when it
//! hit its bound) drives the three residuals to zero. The same three
//! settings carry Litvin's solution; the numerical route avoids
//! transcribing his closed-form chain of frames and is checked by running
//! the full TCA on the result (`verification/hypoid_tca`).
//!
//! **Path inclination** η: the angle of the path of contact on the gear's
//! flank projection (axial section: v along the face toward the heel, u up
//! the profile, both mm) from the face direction, positive when the path
//! rises toward the heel, in (−90°, 90°] (a line, not a direction).
//!
//! **Drive flank only**: the trial pinions' drive (concave) flank comes
//! from the trial setup, their coast flank from the basic setup (it does
//! not enter the drive-side TCA); a fixed-setting pinion, each flank on
//! its own settings.
//!
//! **Status** (papers/seed003-hypoid/README.md): the first order and
//! targets near the first-order pinion are met (unit tests); seed 003's
//! bearing targets are not reached — the basic pinion's TE opens upward
//! (−670″) and the continuation toward a positive level drives the blade
//! and machine spiral angles far from the blank until the flank no longer
//! generates over it. Litvin's hypoid synthesis also moves the blank
//! offset, sliding base and machine root angle, kept here at the pinion
//! blank's values. Not yet offered in scenes.

use std::f64::consts::PI;
use std::sync::Arc;

use crate::error::{FlankError, Result};
use crate::geometry::bevel::assembly::PairAssembly;
use crate::geometry::bevel::body::BevelGear;
use crate::geometry::bevel::generated_surface::FlankKind;
use crate::geometry::bevel::machine_settings::{
    refined_setup, setup_with, CutterChoice, Member, MemberBlank, MemberSetup, RollChoice,
};
use crate::geometry::bevel::pair::BevelPair;
use crate::geometry::bevel::BlankDesign;
use crate::geometry::contact_curvature::{curvature_ellipse, FlankAtContact};
use crate::geometry::frame::Frame;
use crate::geometry::gear_pair::{Flank, PairPlacement};
use crate::geometry::surface::ToothSurface;
use crate::geometry::tangency::{self, ContactSystem, GearTurn, PlacedFlank, TangencySeed};
use crate::geometry::Hand;

/// The three second-order design targets at the mean point (module docs).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct SynthesisTargets {
    /// Path inclination η on the gear flank projection (rad).
    pub path_angle_rad: f64,
    /// Length 2a of the contact ellipse's major axis at the approach (mm).
    pub major_axis_mm: f64,
    /// TE level: fall of the parabolic TE over π/z₁ from M (rad, gear angle).
    pub te_level_rad: f64,
    /// Elastic approach δ of the ellipse (mm).
    pub approach_mm: f64,
}

impl SynthesisTargets {
    /// Ranges: |η| < 90°, 2a > 0, level ≠ 0, δ > 0, all finite; the
    /// error names the target.
    pub fn validate(&self) -> Result<()> {
        let bad = |m: String| Err(FlankError::Model(format!("local synthesis: {m}")));
        if !(self.path_angle_rad.is_finite() && self.path_angle_rad.abs() < 0.5 * PI) {
            return bad(format!(
                "path_angle {:.4}°: an inclination strictly between −90° and 90° is needed",
                self.path_angle_rad.to_degrees()
            ));
        }
        if !(self.major_axis_mm.is_finite() && self.major_axis_mm > 0.0) {
            return bad(format!(
                "major_axis {} mm: a positive ellipse length is needed",
                self.major_axis_mm
            ));
        }
        // the residual is relative to the level; a negative level (a TE
        // parabola open upward: the pair's lag is least at M) is accepted
        // but is no bearing design
        if !(self.te_level_rad.is_finite() && self.te_level_rad != 0.0) {
            return bad(format!(
                "te_level {} rad: a finite non-zero level is needed",
                self.te_level_rad
            ));
        }
        if !(self.approach_mm.is_finite() && self.approach_mm > 0.0) {
            return bad(format!(
                "approach δ = {} mm: a positive elastic approach is needed",
                self.approach_mm
            ));
        }
        Ok(())
    }
}

/// The contact of a pair's middle teeth at the mean point, measured.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct MeanContact {
    /// Flank parameters of the contact at roll 0 (mm).
    pub pinion_uv: [f64; 2],
    pub gear_uv: [f64; 2],
    /// TE slope dΔφ₂/dθ and curvature d²Δφ₂/dθ² at roll 0 (rad/rad, rad/rad²).
    pub te_slope: f64,
    pub te_curvature: f64,
    /// −½ TE'' (π/z₁)² (rad).
    pub te_level_rad: f64,
    /// Path inclination η (rad, module docs).
    pub path_angle_rad: f64,
    /// 2a at the approach (mm); `None`: line contact.
    pub major_axis_mm: Option<f64>,
    /// 2b at the approach (mm).
    pub minor_axis_mm: f64,
    /// Largest tangency residual of the solves (mm).
    pub residual_mm: f64,
}

/// Roll step of the differences, in angular pitches of the pinion: small
/// enough for the local (second-order) figures, large enough that the
/// solves' 1e-13 accuracy leaves 1e-7 relative on TE''.
const DIFFERENCE_STEP_PITCHES: f64 = 0.01;

/// The middle pair's contact at `roll` and `roll` ± h (module docs).
pub fn mean_contact(pair: &BevelPair, roll: f64, approach_mm: f64) -> Result<MeanContact> {
    let km = pair.middle();
    let (ps, gs) = (
        pair.pinion()
            .flank(Flank::Right, km)
            .ok_or_else(|| FlankError::Model("mean contact: no middle pinion tooth".into()))?,
        pair.gear()
            .flank(Flank::Right, pair.mate(km))
            .ok_or_else(|| FlankError::Model("mean contact: no middle gear tooth".into()))?,
    );
    let (rm1, rm2) = (pair.bevel_body(0).cones().rm, pair.bevel_body(1).cones().rm);
    let pitch = pair.pinion().angular_pitch();
    let h = DIFFERENCE_STEP_PITCHES * pitch;
    let solve = |roll: f64, seed: &TangencySeed| {
        let [f1, f2] = pair.frames(roll);
        let turn = GearTurn {
            point: f2.translation,
            axis: f2.rotate([0.0, 0.0, 1.0]),
        };
        tangency::solve(
            ContactSystem::Flank,
            &PlacedFlank {
                surface: ps,
                frame: f1,
            },
            &PlacedFlank {
                surface: gs,
                frame: f2,
            },
            &turn,
            seed,
        )
        .map(|t| {
            (
                t,
                f1,
                Frame::about_axis(turn.point, turn.axis, t.turn).compose(&f2),
            )
        })
        .map_err(|e| {
            FlankError::Model(format!(
                "mean contact: no flank contact at roll {:.5}° ({e})",
                roll.to_degrees()
            ))
        })
    };
    let seed = TangencySeed {
        pinion_uv: [0.0, rm1],
        gear_uv: [0.0, rm2],
        turn: 0.0,
    };
    let (t0, f1, f2) = solve(roll, &seed)?;
    let (tp, _, _) = solve(roll + h, &t0.seed())?;
    let (tm, _, _) = solve(roll - h, &t0.seed())?;
    // gear lag in its drive sense (the TCA's TE)
    let sense2 = pair.rotation_axes()[1][2].signum();
    let lag = |t: &tangency::Tangency| sense2 * t.turn;
    let te_slope = (lag(&tp) - lag(&tm)) / (2.0 * h);
    let te_curvature = (lag(&tp) - 2.0 * lag(&t0) + lag(&tm)) / (h * h);
    let (du, dv) = (tp.gear_uv[0] - tm.gear_uv[0], tp.gear_uv[1] - tm.gear_uv[1]);
    let mut path = du.atan2(dv);
    if path > 0.5 * PI {
        path -= PI;
    } else if path <= -0.5 * PI {
        path += PI;
    }
    let ellipse = curvature_ellipse(
        &FlankAtContact {
            surface: ps,
            frame: f1,
            uv: t0.pinion_uv,
        },
        &FlankAtContact {
            surface: gs,
            frame: f2,
            uv: t0.gear_uv,
        },
        t0.normal,
        approach_mm,
    );
    let half_pitch = 0.5 * pitch;
    Ok(MeanContact {
        pinion_uv: t0.pinion_uv,
        gear_uv: t0.gear_uv,
        te_slope,
        te_curvature,
        te_level_rad: -0.5 * te_curvature * half_pitch * half_pitch,
        path_angle_rad: path,
        major_axis_mm: ellipse.semi_major_mm.map(|a| 2.0 * a),
        minor_axis_mm: 2.0 * ellipse.semi_minor_mm,
        residual_mm: t0
            .point_residual
            .max(tp.point_residual)
            .max(tm.point_residual),
    })
}

/// The synthesis unknowns (module docs).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct PinionSynthesisVariables {
    /// Mean cutter radius r_c (mm).
    pub cutter_radius_mm: f64,
    /// Ratio of roll over its pure-rolling value.
    pub ratio_of_roll_factor: f64,
    /// Modified-roll coefficient 2C.
    pub modified_roll_2c: f64,
    /// Corrections of the machine spiral angle and of the drive (outside)
    /// blade angle against the basic setup's (rad): the first order
    /// (module docs).
    pub spiral_angle_correction_rad: f64,
    pub pressure_angle_correction_rad: f64,
    /// Pinion roll θ_M at which the contact is at M (rad).
    pub mean_roll_rad: f64,
    /// Shift (t_x, t_y) of the cradle axis in the cradle plane against the
    /// pinion and its cutter, which keeps the cutter's tangency at M
    /// (mm): E_m = t_y, ΔX_B = t_x tan γ_m, ΔX_G = t_x / cos γ_m on top of
    /// the basic setup's (module docs).
    pub cradle_shift_mm: [f64; 2],
    /// Cutter tilt i (rad) about the cradle-plane line from the cutter
    /// centre toward M (swivel j: that line's angle), which leaves M on the
    /// blade and turns the blade's pressure angle along the face.
    pub tilt_rad: f64,
    /// Curvature 1/ρ_w of the drive (outside) blade's edge (1/mm; 0 =
    /// straight; positive bends the edge toward the work: profile
    /// crowning).
    pub blade_curvature_per_mm: f64,
}

impl PinionSynthesisVariables {
    /// The basic design: the blank's cutter radius, pure rolling, no
    /// modified roll, the blank's angles.
    pub fn basic(cutter_radius_mm: f64) -> Self {
        PinionSynthesisVariables {
            cutter_radius_mm,
            ratio_of_roll_factor: 1.0,
            modified_roll_2c: 0.0,
            spiral_angle_correction_rad: 0.0,
            pressure_angle_correction_rad: 0.0,
            mean_roll_rad: 0.0,
            cradle_shift_mm: [0.0; 2],
            tilt_rad: 0.0,
            blade_curvature_per_mm: 0.0,
        }
    }

    fn with(&self, i: usize, d: f64) -> Self {
        let mut y = *self;
        let f = match i {
            0 => &mut y.cutter_radius_mm,
            1 => &mut y.ratio_of_roll_factor,
            2 => &mut y.modified_roll_2c,
            3 => &mut y.spiral_angle_correction_rad,
            4 => &mut y.pressure_angle_correction_rad,
            5 => &mut y.mean_roll_rad,
            6 => &mut y.cradle_shift_mm[0],
            7 => &mut y.cradle_shift_mm[1],
            8 => &mut y.tilt_rad,
            _ => &mut y.blade_curvature_per_mm,
        };
        *f += d;
        y
    }
}

/// Number of unknowns and conditions.
const N: usize = 6;

/// The synthesised pinion: its setup, the variables, the mean contact
/// before and after, and the iterations' record.
#[derive(Clone, Debug)]
pub struct PinionSynthesis {
    pub setup: MemberSetup,
    pub variables: PinionSynthesisVariables,
    pub start: MeanContact,
    pub achieved: MeanContact,
    pub targets: SynthesisTargets,
    /// Newton iterations in all (first order and continuation).
    pub iterations: usize,
    /// Continuation steps taken toward the targets.
    pub continuation_steps: usize,
    /// Largest scaled residual at the end ([`TOLERANCE`]).
    pub residual: f64,
}

/// Scaled residuals (module docs): η − η* (rad), (2a − 2a*)/2a_final,
/// (L − L*)/L_final, the gear contact's (u, v) from the mean point
/// (0, R_m2) (mm) and the TE slope over [`TE_SLOPE_SCALE`]. Converged when
/// every one is below [`TOLERANCE`].
fn residual(
    m: &MeanContact,
    now: &SynthesisTargets,
    last: &SynthesisTargets,
    rm2: f64,
) -> Result<[f64; N]> {
    let a = m.major_axis_mm.ok_or_else(|| {
        FlankError::Model(
            "local synthesis: line contact at the mean point (no finite ellipse)".into(),
        )
    })?;
    Ok([
        m.path_angle_rad - now.path_angle_rad,
        (a - now.major_axis_mm) / last.major_axis_mm,
        (m.te_level_rad - now.te_level_rad) / last.te_level_rad,
        m.gear_uv[0],
        m.gear_uv[1] - rm2,
        m.te_slope / TE_SLOPE_SCALE,
    ])
}

/// Scale of the TE slope residual (rad/rad): 1e-6 of it is a ratio error
/// of 1e-9.
const TE_SLOPE_SCALE: f64 = 1e-3;
/// Convergence tolerance of the scaled residuals (1e-6: 0.2″ of path
/// inclination, 1e-6 of 2a and of the TE level, 1 nm of contact position).
pub const TOLERANCE: f64 = 1e-6;
/// Newton iterations at most per solve.
pub const MAX_ITERATIONS: usize = 30;
/// Continuation steps at most (accepted or halved).
pub const MAX_CONTINUATION_STEPS: usize = 60;
/// Smallest continuation step (fraction of the way to the targets).
const MIN_CONTINUATION_STEP: f64 = 1e-3;
/// Step halvings at most per Newton iteration.
const MAX_HALVINGS: usize = 10;
/// Number of variables ([`PinionSynthesisVariables`]).
const NX: usize = 10;
/// Forward-difference steps of the Jacobian: r_c (mm), k, 2C, Δβ, Δα,
/// θ_M (rad), E_m, ΔX_B (mm).
const JACOBIAN_STEPS: [f64; NX] = [0.05, 1e-5, 1e-4, 1e-6, 1e-6, 1e-5, 1e-4, 1e-4, 1e-6, 1e-7];
/// Tolerance and rounds of the basic setup's match to the blank.
const FIRST_ORDER_TOL: f64 = 1e-10;
const FIRST_ORDER_ROUNDS: usize = 40;
/// Conditions of the first order: the contact position and the TE slope.
const FIRST_ORDER: [usize; 3] = [3, 4, 5];
/// Unknowns of the first order, Litvin's for a hypoid pinion: E_m, ΔX_B
/// and θ_M (the blade and machine spiral angles stay the blank's).
const LITVIN_FIRST_ORDER: [usize; 3] = [6, 7, 5];
/// The earlier choice: the machine spiral and blade angles Δβ, Δα and θ_M.
const ANGLE_FIRST_ORDER: [usize; 3] = [3, 4, 5];
const CONDITIONS: [usize; N] = [0, 1, 2, 3, 4, 5];

fn max_abs(r: &[f64; N], active: &[usize]) -> f64 {
    active.iter().map(|&i| r[i].abs()).fold(0.0, f64::max)
}

fn sum_sq(r: &[f64; N], active: &[usize]) -> f64 {
    active.iter().map(|&i| r[i] * r[i]).sum()
}

/// A solved state.
struct State {
    x: PinionSynthesisVariables,
    setup: MemberSetup,
    mean: MeanContact,
}

/// Damped Newton on the `active` unknowns and conditions toward `now`
/// (forward-difference Jacobian, step halving on the residual's sum of
/// squares); at most [`MAX_ITERATIONS`]. Returns the state and the
/// iterations, or why it stopped.
fn newton(
    problem: &SynthesisProblem,
    from: &State,
    now: &SynthesisTargets,
    (unknowns, active): (&[usize], &[usize]),
) -> std::result::Result<(State, usize), String> {
    let last = &problem.targets;
    let rm2 = problem.design.cutting_blank().wheel.rm;
    let measure = |x: &PinionSynthesisVariables| -> std::result::Result<(MemberSetup, MeanContact, [f64; N]), String> {
        let (setup, m) = problem.measure(x).map_err(|e| e.to_string())?;
        let r = residual(&m, now, last, rm2).map_err(|e| e.to_string())?;
        Ok((setup, m, r))
    };
    let n = active.len();
    let mut x = from.x;
    let (mut setup, mut mean, mut r) = measure(&x)?;
    for iteration in 0..MAX_ITERATIONS {
        if max_abs(&r, active) <= TOLERANCE {
            return Ok((State { x, setup, mean }, iteration));
        }
        let mut jac = nalgebra::DMatrix::<f64>::zeros(n, n);
        for (col, &j) in unknowns.iter().enumerate() {
            let step = JACOBIAN_STEPS[j];
            let (_, _, rj) = measure(&x.with(j, step))?;
            for (row, &i) in active.iter().enumerate() {
                jac[(row, col)] = (rj[i] - r[i]) / step;
            }
        }
        let rhs = nalgebra::DVector::<f64>::from_iterator(n, active.iter().map(|&i| -r[i]));
        let dx = jac
            .lu()
            .solve(&rhs)
            .ok_or_else(|| format!("singular Jacobian at iteration {iteration}"))?;
        let mut lambda = 1.0;
        let mut accepted = None;
        for _ in 0..=MAX_HALVINGS {
            let y = unknowns
                .iter()
                .enumerate()
                .fold(x, |y, (col, &j)| y.with(j, lambda * dx[col]));
            if let Ok((sy, my, ry)) = measure(&y) {
                if sum_sq(&ry, active) < sum_sq(&r, active) {
                    accepted = Some((y, sy, my, ry));
                    break;
                }
            }
            lambda *= 0.5;
        }
        let Some((y, sy, my, ry)) = accepted else {
            return Err(format!(
                "no step reduces the residual at iteration {iteration} (largest scaled residual {:.3e})",
                max_abs(&r, active)
            ));
        };
        (x, setup, mean, r) = (y, sy, my, ry);
    }
    if max_abs(&r, active) <= TOLERANCE {
        return Ok((State { x, setup, mean }, MAX_ITERATIONS));
    }
    Err(format!(
        "not converged in {MAX_ITERATIONS} iterations (largest scaled residual {:.3e})",
        max_abs(&r, active)
    ))
}

/// Local synthesis from `start` (module docs): the first order by Newton
/// on (Δβ, Δα, θ_M), then the three targets reached by continuation from
/// the values the first-order pinion has (each step a Newton solve on all
/// six unknowns; a failed step is halved, at most
/// [`MAX_CONTINUATION_STEPS`] in all).
pub fn synthesize_pinion(
    problem: &SynthesisProblem,
    start: PinionSynthesisVariables,
) -> Result<PinionSynthesis> {
    let t = problem.targets;
    t.validate()?;
    let fail = |m: String| FlankError::Model(format!("local synthesis: {m}"));
    let (setup, first) = problem.measure(&start)?;
    let basic = State {
        x: start,
        setup,
        mean: first,
    };
    let (mut state, mut iterations) = newton(problem, &basic, &t, (&ANGLE_FIRST_ORDER, &FIRST_ORDER))
        .map_err(|e| {
            fail(format!(
                "first order (contact at the mean point, TE slope 0): {e}"
            ))
        })?;
    let from = SynthesisTargets {
        path_angle_rad: state.mean.path_angle_rad,
        major_axis_mm: state.mean.major_axis_mm.ok_or_else(|| {
            fail("line contact at the mean point of the first-order pinion".into())
        })?,
        te_level_rad: state.mean.te_level_rad,
        approach_mm: t.approach_mm,
    };
    let at = |s: f64| SynthesisTargets {
        path_angle_rad: from.path_angle_rad + s * (t.path_angle_rad - from.path_angle_rad),
        major_axis_mm: from.major_axis_mm + s * (t.major_axis_mm - from.major_axis_mm),
        te_level_rad: from.te_level_rad + s * (t.te_level_rad - from.te_level_rad),
        approach_mm: t.approach_mm,
    };
    let (mut s, mut ds) = (0.0f64, 0.25f64);
    let mut steps = 0;
    let mut last_error = String::new();
    while s < 1.0 {
        if steps == MAX_CONTINUATION_STEPS {
            return Err(fail(format!(
                "the targets were not reached in {MAX_CONTINUATION_STEPS} continuation steps (reached {:.1} % of the way from the first-order pinion; last failure: {last_error})",
                100.0 * s
            )));
        }
        steps += 1;
        let next = (s + ds).min(1.0);
        let (unknowns, conditions) = problem.system();
        match newton(problem, &state, &at(next), (&unknowns, &conditions)) {
            Ok((st, it)) => {
                iterations += it;
                state = st;
                s = next;
                ds = (1.5 * ds).min(0.5);
            }
            Err(e) => {
                last_error = e;
                ds *= 0.5;
                if ds < MIN_CONTINUATION_STEP {
                    return Err(fail(format!(
                        "the targets were not reached: the continuation step fell below {MIN_CONTINUATION_STEP} at {:.1} % of the way from the first-order pinion (last failure: {last_error})",
                        100.0 * s
                    )));
                }
            }
        }
    }
    let rm2 = problem.design.cutting_blank().wheel.rm;
    let r = residual(&state.mean, &t, &t, rm2)?;
    Ok(PinionSynthesis {
        setup: state.setup,
        variables: state.x,
        start: first,
        achieved: state.mean,
        targets: t,
        iterations,
        continuation_steps: steps,
        residual: max_abs(&r, &problem.system().1),
    })
}

/// What the synthesis needs of the pair: the blank, the pinion's hand and
/// cutter, the gear body (sector of one tooth), the assembly, the targets
/// and the basic pinion setup ([`SynthesisProblem::new`]).
pub struct SynthesisProblem<'a> {
    pub design: &'a BlankDesign,
    pub pinion_hand: Hand,
    pub cutter: CutterChoice,
    pub gear: Arc<BevelGear>,
    pub assembly: PairAssembly,
    pub targets: SynthesisTargets,
    /// The pinion's setup derived from its blank (mean point matched,
    /// [`refined_setup`]): the synthesis starts from it, and its coast
    /// flank completes the trial pinions' tooth.
    pub basic: MemberSetup,
    basic_coast: Arc<dyn ToothSurface>,
    /// The equation of meshing at M on the basic setup: (X_M · w, w/|w|²)
    /// with X_M the cutter point at M in the cradle plane's frame and
    /// w = n × k ([`cradle_shift_for_meshing`]).
    meshing_line: (f64, [f64; 2]),
    /// The settings that carry the second order (variable indices) and
    /// the second-order targets imposed (0 path, 1 2a, 2 TE level), as
    /// many of each.
    pub second_order: Vec<usize>,
    pub imposed: Vec<usize>,
}

/// The equation of meshing of the pinion and its cutter at M kept for a
/// ratio of roll k·R_a (Litvin & Fuentes §20.5 on the equation of meshing
/// n · v^(c1) = 0; the settings E_m, ΔX_B from it as in Litvin & Zhang,
/// NASA CR-4342 §4): at ψ = 0 the cradle turns about k with unit speed and
/// the work about −d with 1/R_a, so the relative velocity at the cutter
/// point X_M is v = k × X_M + d × (X_M − A)/R_a. On the basic setup
/// (k = 1) n · v = 0 (M is generated at ψ = 0). Moving the cradle axis by
/// t in the cradle plane against the pinion and the cutter (which keeps
/// the cutter tangent to the pinion at M) and scaling R_a by k gives
/// n · v = t · w + (1 − 1/k) X_M · w, w = n × k: the least shift that
/// keeps M generated at ψ = 0 is t = −(1 − 1/k) (X_M · w) w/|w|². Returns
/// (X_M · w, w/|w|²).
fn cradle_shift_for_meshing(setup: &MemberSetup) -> Result<(f64, [f64; 2])> {
    let flank = setup.flank(FlankKind::Concave)?;
    let rm = setup.blank.mean_cone_distance;
    let p = flank.envelope().solve(0.0, rm).map_err(|e| {
        FlankError::Model(format!(
            "local synthesis: the basic pinion's mean point is not generated ({e})"
        ))
    })?;
    let map = flank.envelope().map();
    let [s, th, _] = p.q;
    let x: [f64; 3] = map.cradle_point(s, th);
    let h = 1e-5;
    let d = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let xs = d(map.cradle_point(s + h, th), map.cradle_point(s - h, th));
    let xt = d(map.cradle_point(s, th + h), map.cradle_point(s, th - h));
    let n = crate::geometry::vec3::cross(xs, xt);
    // w = n × e_z
    let w = [n[1], -n[0]];
    let w2 = w[0] * w[0] + w[1] * w[1];
    if !(w2 > 0.0) {
        return Err(FlankError::Model(
            "local synthesis: the cutter normal at the mean point is along the cradle axis".into(),
        ));
    }
    Ok((x[0] * w[0] + x[1] * w[1], [w[0] / w2, w[1] / w2]))
}

impl<'a> SynthesisProblem<'a> {
    pub fn new(
        design: &'a BlankDesign,
        pinion_hand: Hand,
        cutter: CutterChoice,
        gear: Arc<BevelGear>,
        assembly: PairAssembly,
        targets: SynthesisTargets,
    ) -> Result<Self> {
        let blank = MemberBlank::from_design(design, Member::Pinion)?;
        let (basic, _) = refined_setup(
            &blank,
            pinion_hand,
            &cutter,
            true,
            FIRST_ORDER_TOL,
            FIRST_ORDER_ROUNDS,
        )?;
        let basic_coast: Arc<dyn ToothSurface> = Arc::new(basic.flank(FlankKind::Convex)?);
        let meshing_line = cradle_shift_for_meshing(&basic)?;
        Ok(SynthesisProblem {
            design,
            pinion_hand,
            cutter,
            gear,
            assembly,
            targets,
            basic,
            basic_coast,
            meshing_line,
            second_order: vec![0, 1, 2],
            imposed: vec![0, 1, 2],
        })
    }

    /// The Newton system's unknowns and conditions: the second-order
    /// settings and targets, then the first order's.
    fn system(&self) -> (Vec<usize>, Vec<usize>) {
        let mut u = self.second_order.clone();
        u.extend(ANGLE_FIRST_ORDER);
        let mut c = self.imposed.clone();
        c.extend(FIRST_ORDER);
        (u, c)
    }

    /// The pinion setup of the variables: the basic setup's angles
    /// corrected, the cutter radius and roll of the variables. Only its
    /// drive (concave) flank is the synthesis's.
    pub fn setup(&self, x: &PinionSynthesisVariables) -> Result<MemberSetup> {
        let a = self.basic.angles;
        let cutter = CutterChoice {
            mean_radius: x.cutter_radius_mm,
            ..self.cutter
        };
        let roll = RollChoice {
            ratio_of_roll_factor: x.ratio_of_roll_factor,
            modified_roll: (x.modified_roll_2c, 0.0),
        };
        let mut setup = setup_with(
            &self.basic.blank,
            self.pinion_hand,
            &cutter,
            true,
            (
                a.machine_spiral_angle + x.spiral_angle_correction_rad,
                a.blade_angle_concave + x.pressure_angle_correction_rad,
                a.blade_angle_convex,
            ),
            a.width_correction,
            &roll,
        )?;
        let [tx, ty] = {
            let (c, w) = self.meshing_line;
            let f = -(1.0 - 1.0 / x.ratio_of_roll_factor) * c;
            [
                x.cradle_shift_mm[0] + f * w[0],
                x.cradle_shift_mm[1] + f * w[1],
            ]
        };
        let (sg, cg) = setup.settings.machine_root_angle.sin_cos();
        let m = &mut setup.settings;
        m.blank_offset += ty;
        m.sliding_base += tx * sg / cg;
        m.machine_center_to_back += tx / cg;
        let c = (setup.cutter_centre.0 + tx, setup.cutter_centre.1 + ty);
        m.radial_distance = c.0.hypot(c.1);
        m.cradle_angle = c.1.atan2(c.0);
        setup.cutter_centre = c;
        setup.mean_root_x += tx;
        // the tilt axis: from the cutter centre toward the mean root point
        let m = &mut setup.settings;
        m.tilt = x.tilt_rad;
        m.swivel = (ty - c.1).atan2(setup.mean_root_x - c.0);
        let k = x.blade_curvature_per_mm;
        setup.head.outside.curvature_radius = (k != 0.0).then(|| 1.0 / k);
        setup.head.outside.profile()?;
        setup.settings.validate()?;
        Ok(setup)
    }

    /// The trial pair of a setup (one tooth per body): its drive flank and
    /// the basic coast flank.
    pub fn pair(&self, setup: &MemberSetup) -> Result<BevelPair> {
        let drive: Arc<dyn ToothSurface> = Arc::new(setup.flank(FlankKind::Concave)?);
        let m = self.design.cutting_blank().pinion;
        let toe_root = m.axial_point(-m.dedendum(m.ri), m.ri).1;
        // the bore does not enter the TCA: half the toe's root radius
        let pinion = BevelGear::new(
            "pinion",
            m.z.round() as u32,
            1,
            self.basic_coast.clone(),
            drive,
            m,
            0.5 * toe_root,
        )?;
        BevelPair::new([Arc::new(pinion), self.gear.clone()], self.assembly)
    }

    /// The mean contact of the variables.
    pub fn measure(&self, x: &PinionSynthesisVariables) -> Result<(MemberSetup, MeanContact)> {
        let setup = self.setup(x)?;
        let pair = self.pair(&setup)?;
        let m = mean_contact(&pair, x.mean_roll_rad, self.targets.approach_mm)?;
        Ok((setup, m))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::bevel::cutting::{
        assembly_for, cut_gear, member_body, CutterSpec, MachineCut,
    };
    use crate::geometry::bevel::{blank_design, BlankInputs};

    /// Seed 003's blank (papers/seed003-hypoid/scene.toml).
    const SEED003: &str = r#"{"method": 1, "Sigma_deg": 90.0, "a_mm": 30.0, "z1": 11, "z2": 41, "de2_mm": 225.5, "b2_mm": 38.0, "beta_m1_desired_deg": 50.0, "rc0_mm": 114.3, "data_type": "II", "alpha_dD_deg": 20.0, "alpha_dC_deg": 20.0, "f_alim": 0.0, "c_ham": 0.2309, "k_d": 2.0, "k_c": 0.125, "k_t": 0.1, "theta_a2_deg": 1.3118, "theta_f2_deg": 4.0355}"#;

    fn seed003(design: &BlankDesign, targets: SynthesisTargets) -> SynthesisProblem<'_> {
        let inputs = BlankInputs::from_json(SEED003).unwrap();
        let spec = CutterSpec::of_blank(design);
        let cut = MachineCut {
            generated: true,
            cutter: spec,
            machine: None,
        };
        let gear_hand = Hand::Right;
        let gear = cut_gear(design, gear_hand, &cut).unwrap();
        let m = design.cutting_blank().wheel;
        let toe_root = m.axial_point(-m.dedendum(m.ri), m.ri).1;
        let body = member_body(design, false, &gear, 0.5 * toe_root, 1).unwrap();
        let assembly = assembly_for(&inputs, design, gear_hand).unwrap();
        SynthesisProblem::new(
            design,
            Hand::Left,
            CutterChoice {
                mean_radius: spec.radius,
                edge_radius: spec.edge_radius,
                blade_height: spec.blade_height,
            },
            Arc::new(body),
            assembly,
            targets,
        )
        .unwrap()
    }

    fn design() -> BlankDesign {
        blank_design(&BlankInputs::from_json(SEED003).unwrap()).unwrap()
    }

    /// Targets for the first order only (the second-order ones unused).
    const PROBE: SynthesisTargets = SynthesisTargets {
        path_angle_rad: 0.0,
        major_axis_mm: 10.0,
        te_level_rad: 1e-4,
        approach_mm: 0.00635,
    };

    /// The basic pinion's state and the first-order solve from it.
    fn basic_and_first_order(problem: &SynthesisProblem) -> (State, State, usize) {
        let x0 = PinionSynthesisVariables::basic(problem.cutter.mean_radius);
        let (setup, m0) = problem.measure(&x0).unwrap();
        let basic = State {
            x: x0,
            setup,
            mean: m0,
        };
        let (first, it) = newton(
            problem,
            &basic,
            &PROBE,
            (&ANGLE_FIRST_ORDER, &FIRST_ORDER),
        )
        .unwrap();
        (basic, first, it)
    }

    /// The first order on seed 003: the basic pinion (settings from its
    /// blank) touches the gear 3.9 mm from the mean point with a TE slope
    /// of −4.8e-3 (the gear's drive-flank normal at P is 0.2° off the
    /// blank's, the two flanks' spiral angles differ); the Newton on
    /// (Δβ, Δα, θ_M) puts the contact on M within 1 nm with a zero slope.
    #[test]
    fn first_order_puts_the_contact_on_the_mean_point() {
        let d = design();
        let problem = seed003(&d, PROBE);
        let (basic, s, it) = basic_and_first_order(&problem);
        let (m0, rm2) = (basic.mean, d.cutting_blank().wheel.rm);
        assert!(m0.gear_uv[0].hypot(m0.gear_uv[1] - rm2) > 1.0, "{m0:?}");
        assert!(m0.te_slope.abs() > 1e-3, "{m0:?}");
        let m = s.mean;
        assert!(
            m.gear_uv[0].abs() < 1e-6 && (m.gear_uv[1] - rm2).abs() < 1e-6,
            "{m:?}"
        );
        assert!(m.te_slope.abs() < 1e-9, "{m:?}");
        assert!(it <= 10, "{it} iterations");
    }

    /// The second order: from the first-order pinion, targets 0.5° of path
    /// inclination, 5 % of 2a and 40″ of TE level away are met to the
    /// tolerance by the continuation on all six unknowns, and the path,
    /// 2a and level move by what was asked (the residual definition is not
    /// the only check: the figures are measured again on the result).
    #[test]
    fn second_order_meets_nearby_targets() {
        let d = design();
        let problem = seed003(&d, PROBE);
        let x0 = PinionSynthesisVariables::basic(problem.cutter.mean_radius);
        let (_, first, _) = basic_and_first_order(&problem);
        let f = first.mean;
        let targets = SynthesisTargets {
            path_angle_rad: f.path_angle_rad + 0.5f64.to_radians(),
            major_axis_mm: 1.05 * f.major_axis_mm.unwrap(),
            te_level_rad: f.te_level_rad + (40.0f64 / 3600.0).to_radians(),
            approach_mm: 0.00635,
        };
        let problem = SynthesisProblem { targets, ..problem };
        let s = synthesize_pinion(&problem, x0).unwrap();
        assert!(s.residual <= TOLERANCE, "{s:?}");
        // measured again on the resulting variables
        let (_, m) = problem.measure(&s.variables).unwrap();
        assert!(
            (m.path_angle_rad - targets.path_angle_rad).abs() < 1e-5,
            "{m:?}"
        );
        assert!((m.major_axis_mm.unwrap() / targets.major_axis_mm - 1.0).abs() < 1e-5);
        assert!((m.te_level_rad / targets.te_level_rad - 1.0).abs() < 1e-5);
        assert!(m.te_slope.abs() < 1e-8);
        eprintln!(
            "seed003 nearby synthesis: {:?} in {} iterations, {} steps",
            s.variables, s.iterations, s.continuation_steps
        );
    }

    /// Exploration: the synthesis toward seed 003's bearing targets.
    #[test]
    fn explore_seed003_bearing() {
        let d = design();
        let targets = SynthesisTargets {
            path_angle_rad: 0.0,
            major_axis_mm: 0.3 * 38.0,
            te_level_rad: (8.0f64 / 3600.0).to_radians(),
            approach_mm: 0.00635,
        };
        let problem = seed003(&d, targets);
        let x0 = PinionSynthesisVariables::basic(problem.cutter.mean_radius);
        let (basic, first, it) = basic_and_first_order(&problem);
        let (_, _, r0) = {
            let (su, m) = problem.measure(&first.x).unwrap();
            let r = residual(&m, &targets, &targets, d.cutting_blank().wheel.rm).unwrap();
            (su, m, r)
        };
        for j in 0..NX {
            let h = JACOBIAN_STEPS[j];
            match problem.measure(&first.x.with(j, h)) {
                Ok((_, m)) => {
                    let r = residual(&m, &targets, &targets, d.cutting_blank().wheel.rm).unwrap();
                    let col: Vec<String> = (0..N).map(|i| format!("{:+.3e}", (r[i] - r0[i]) / h)).collect();
                    eprintln!("d/dx{j}: {}", col.join(" "));
                }
                Err(e) => eprintln!("d/dx{j}: {e}"),
            }
        }
        eprintln!("basic {:?}", basic.mean);
        for k in [0.9, 1.0, 1.1] {
            let mut x = first.x;
            x.ratio_of_roll_factor = k;
            let su = problem.setup(&x).unwrap();
            let f = su.flank(FlankKind::Concave).unwrap();
            let q = f.envelope().solve(0.0, su.blank.mean_cone_distance).unwrap().q;
            eprintln!("k {k}: psi_M {:.3e} settings {:?}", q[2], su.settings);
        }
        eprintln!("first order ({it} it) {:?}\n  {:?}", first.mean, first.x);
        let cases: [(&[usize], &[usize]); 6] = [
            (&[0, 9], &[2, 1]),
            (&[1, 9], &[2, 1]),
            (&[0, 1, 9], &[2, 0, 1]),
            (&[1, 2, 9], &[2, 0, 1]),
            (&[0, 2, 9], &[2, 0, 1]),
            (&[0, 1, 2], &[2, 0, 1]),
        ];
        for (so, imp) in cases {
            let problem = SynthesisProblem { second_order: so.to_vec(), imposed: imp.to_vec(), ..seed003(&d, targets) };
            match synthesize_pinion(&problem, x0) {
                Ok(s) => eprintln!("{so:?} synthesis {:?}\n {:?}\n {} it {} steps\n SETTINGS {:?}", s.achieved, s.variables, s.iterations, s.continuation_steps, s.setup.settings),
                Err(e) => eprintln!("{so:?} synthesis failed: {e}"),
            }
        }
    }
}
