//! The LTCA problem at one roll angle: candidate points from the unloaded
//! TCA, their normal compliance F from both bodies' tensors, initial
//! separations w and moment arms r; solved as the contact QP of
//! [`crate::ltca::qp`] with the local contact deformation of
//! [`crate::ltca::local`] updated from the loads (a fixed point on the
//! Hertz half-widths, a few iterations).
//!
//! **Compliance.** A normal force p at a contact point acts as +p n on the
//! gear and −p n on the pinion (n: the pinion's outward normal); each body
//! is loaded over a contact cell around its own point (the TCA's (u, v) on
//! its flank) and its tensor, in its own frame, gives the displacement read
//! back over the same cell. The approach of the two surfaces per unit pair
//! of forces is
//!
//! ```text
//! F_ij = n₁ᵢᵀ C¹(i, j) n₁ⱼ + n₂ᵢᵀ C²(i, j) n₂ⱼ + H_ij
//! ```
//!
//! with n_b the contact normal in body b's own frame (the sign drops out)
//! and H the half-space near-field correction. This is seed 004's
//! λ = η + η′ (§3.2), with nodal tensors instead of beam compliances.
//!
//! **Cells.** Across the line: half-width c_FE = κ h, h the flank element
//! size at the point (the larger of the two bodies'), κ
//! [`LtcaSettings::fe_cell_factor`]; in the flank parameter u that is
//! c/(r_b u) (ds/du = r_b u on an involute). Along the line: the length the
//! point represents, projected on the axis (× cos β_b). Cells are axis-
//! aligned rectangles in (u, v); on a helical flank the contact line is
//! inclined in (u, v), so the cell is an approximation there. At a
//! tip-corner point the edge body is loaded on the tip edge line itself
//! (as FE contact loads its slave edge nodes there), the mating body over
//! an ordinary cell of half-width c_FE around its point.

use std::sync::Arc;
use std::time::Instant;

use crate::compliance::interpolation::{CellShape, FlankGrids, FlankInterpolator};
use crate::compliance::ComplianceTensor;
use crate::contact::placement::Frame;
use crate::error::FlankError;
use crate::geometry::gear_pair::{Flank, GearPair};
use crate::geometry::surface::ToothSurface;
use crate::geometry::vec3::{cross, dot, sub};
use crate::iteration_limits::{IterationLimits, LoopEnd};
use crate::ltca::candidate::Candidate;
use crate::ltca::friction::{
    cross_check, friction_coupling, solve_friction, solve_sliding, FrictionProblem, FrictionSolver,
    PointState, MAX_ACTIVE_SET_ITERATIONS, MAX_SLIDING_ITERATIONS, SLIDING_TOLERANCE,
};
use crate::ltca::friction_report::{
    DirectCheck, FrictionReport, IncrementalReport, LemkeCrossCheck, SlidingReport, SlidingResidual,
};
use crate::ltca::influence::{directional_compliance, normal_compliance_pair};
use crate::ltca::local::{hertz_line, Cell, NearField};
use crate::ltca::qp::{
    condition_number, singular_on, solve_contact_qp, ContactQp, QpOptions, QpSolution,
};
use crate::ltca::solve_settings::{LtcaFriction, LtcaSettings};
use crate::settings::{FrictionModel, LocalModel};
use crate::tca::{LineKind, TcaPosition};

/// Relative change of the Hertz half-widths at which their fixed point
/// stops: 1 % moves the near-field term by (2/(π E*)) P′ ln(1.01), < 1e-3 of
/// the TE at gear loads.
pub const HALF_WIDTH_TOLERANCE: f64 = 1e-2;

/// The tip-corner edge cell's profile half-width as a fraction of the FE
/// cell's: small enough that the cell is the edge line (its samples lie
/// within 1e-3 c of u_tip), large enough that they are located on the
/// edge's faces.
const EDGE_CELL_FRACTION: f64 = 1e-3;

/// Extents across the line of a flank point's FE cell (mm), per body
/// `[toward its root, toward its tip]`, with κ the cell factor, h the
/// element size, `a` the point's Hertz half-width under the nominal load
/// per length (the load spread evenly over the flank lines, before the
/// solve knows the shares) and `tips` each body's distance from its tooth
/// tip along the profile:
///
/// * c_FE = max(κ h, a) each way (module docs, [`crate::ltca::local`]):
///   the cell no narrower than the mesh resolves, nor than the contact,
///   since H only narrows a load from c_FE to a. Until 2026-11-27 c_FE was
///   κ h alone and a was cut to it, so a mesh finer than the contact
///   (h < a) loaded a strip narrower than Hertz's: on seed 002 with 0.1 mm
///   tensors the LTCA was 4–6 % too compliant in TE
///   (papers/seed002-spur/README.md).
/// * near a tip the contact zone ends at the tip edge: the cell is cut
///   there (its tip side shortened to the distance from the tip, not below
///   h/5), and on the mating flank, whose root side faces that edge, on
///   the root side. Until 2026-11-27 the cell was narrowed on both sides,
///   which concentrated the load as the mesh was refined (seed 002 at
///   −15°: the entering pair's share 0.445 with 0.1 mm tensors, 0.472 with
///   0.475 mm ones, against FE's 0.470).
fn fe_cell_extents(kappa: f64, h: f64, a: f64, tips: [f64; 2]) -> [[f64; 2]; 2] {
    let a = if a.is_finite() { a } else { 0.0 };
    let c = (kappa * h).max(a);
    let side = |tip: f64| c.min(tip.max(0.2 * h));
    [
        [side(tips[1]), side(tips[0])],
        [side(tips[0]), side(tips[1])],
    ]
}

/// The two bodies of the LTCA: tensors and what the cells need.
#[derive(Clone)]
pub struct LtcaBodies {
    pub tensors: [Arc<ComplianceTensor>; 2],
    /// Face search structures of the two tensors (built once).
    pub grids: [Arc<FlankGrids>; 2],
    /// The pair: the flank surfaces (profile lengths of the cells, tip
    /// edges).
    pub pair: Arc<dyn GearPair>,
    /// Moment arm of the nominal single-pair normal force (mm; the first
    /// guess of the Hertz widths) and the radius that turns a pinion
    /// rotation into a TE length (mm): a spur/helical pair's
    /// [`crate::geometry::gear_pair::LineContactPair::nominal_moment_arm`] and
    /// [`crate::geometry::gear_pair::LineContactPair::transmission_error_radius`];
    /// a bevel pair's moment arm of the mean contact.
    pub nominal_moment_arm_mm: f64,
    pub te_radius_mm: f64,
    /// Contact modulus E* (MPa) of the pair.
    pub contact_modulus: f64,
}

/// One loaded point of a solved position.
#[derive(Clone, Debug, serde::Serialize)]
pub struct PointResult {
    /// Index of the line in [`TcaPosition::lines`].
    pub line: usize,
    pub position: [f64; 3],
    /// Distance along the line from its first point (mm).
    pub along_mm: f64,
    pub separation_mm: f64,
    pub force_n: f64,
    /// Moment arm r of the normal force about the pinion axis (mm).
    pub moment_arm_mm: f64,
    /// Load per unit length of line (N/mm) and Hertz peak pressure (MPa;
    /// 0 at tip-corner points, whose edge radius is zero).
    pub load_per_length: f64,
    pub pressure_mpa: f64,
    pub half_width_mm: f64,
    /// Gap after loading (mm; 0 where loaded).
    pub gap_mm: f64,
    /// Friction force (N, resisting slip along the tangent; 0 without
    /// friction) and the state (`separated`, `stick`, `slip+`, `slip-`;
    /// `frictionless`).
    pub friction_n: f64,
    pub state: &'static str,
    /// Kinematic sliding velocity v_t1 − v_t2 along the tangent (m/s, from
    /// the TCA; 0 without a pinion speed).
    pub sliding_velocity_m_s: f64,
}

/// The answer at one roll angle.
#[derive(Clone, Debug, serde::Serialize)]
pub struct PositionResult {
    pub roll_deg: f64,
    /// (pinion tooth, gear tooth, kind) per line, as in the TCA.
    pub lines: Vec<(usize, usize, String)>,
    /// Normal force per line (N) and its share of the sum.
    pub line_force_n: Vec<f64>,
    pub line_share: Vec<f64>,
    /// Loaded and unloaded TE (µrad; pinion rotation beyond the rigid
    /// kinematic one) and the loaded TE times r_b1 (µm on the line of action).
    pub te_urad: f64,
    pub te_um: f64,
    pub unloaded_te_urad: f64,
    /// Secant mesh stiffness F_n / (r_b1 cos β_b (θ − θ₀)) (N/µm).
    pub mesh_stiffness_n_per_um: f64,
    pub max_pressure_mpa: f64,
    pub points: Vec<PointResult>,
    pub candidates: usize,
    /// TCA points dropped because they lie off a meshed flank.
    pub skipped_points: usize,
    pub qp_iterations: usize,
    pub local_iterations: usize,
    pub kkt_max: f64,
    pub kkt_within_tolerance: bool,
    /// Loaded approach (θ − θ₀)·r on the line of action (mm) and the
    /// corner-contact extension of the TCA that was solved with (mm;
    /// [`crate::ltca::cycle::LtcaCycle::solve`] raises it when the approach
    /// comes near it).
    pub loaded_approach_mm: f64,
    pub corner_extension_mm: f64,
    /// 2-norm condition number of F (if asked) over every candidate, and
    /// over the loaded points only (the matrix the loads are solved with:
    /// a singular F on unloaded points leaves the answer unique).
    pub condition: Option<f64>,
    pub condition_loaded: Option<f64>,
    /// Warnings of the position (a loaded TE beyond the small-displacement
    /// model, [`crate::load_sharing::large_rotation_warning`]).
    pub warnings: Vec<String>,
    /// Friction force per line (N) and the friction solve's report
    /// (residuals, increments, the Lemke cross-check if asked).
    pub line_friction_n: Vec<f64>,
    pub friction: Option<FrictionReport>,
    /// Friction power loss Σ |P_t v_s| over the points (W; 0 without
    /// friction), seed 001's P_loss = Σ μ P_n |v_s| at slipping points.
    pub friction_power_w: f64,
    /// Wall time of the position (s; the caller adds the TCA) and of its
    /// parts: candidate cells, the tensor part of F, the half-space
    /// correction and the QP solves (summed over local iterations).
    pub time_s: f64,
    pub cells_s: f64,
    pub compliance_s: f64,
    pub local_s: f64,
    pub qp_s: f64,
    /// How the position's bounded loops ended (the Hertz half-width fixed
    /// point, the QP, the friction solve): gathered into the summary's
    /// `iteration_limits`.
    #[serde(skip)]
    pub iteration_limits: IterationLimits,
}

/// Start of the warning that F is singular over every candidate point
/// while regular on the loaded ones ([`LtcaBodies::solve`]).
pub const UNRESOLVED_CANDIDATES: &str = "the compliance F is singular over the candidate points";

impl LtcaBodies {
    /// The right (drive) flank of sector tooth `k` of body `b`.
    fn flank(&self, b: usize, k: usize) -> Result<&dyn ToothSurface, FlankError> {
        self.pair.body(b).flank(Flank::Right, k).ok_or_else(|| {
            FlankError::Model(format!(
                "LTCA: the {} sector has no tooth {k}",
                self.pair.body(b).name()
            ))
        })
    }

    /// Flank element size across the contact line at (u, v) of `set` on
    /// body `b`: the profile length of the face's u-extent at u
    /// ([`ToothSurface::profile_length`]; r_b u du on an involute).
    fn element_size(
        &self,
        it: &FlankInterpolator,
        flank: &dyn ToothSurface,
        b: usize,
        set: usize,
        uv: [f64; 2],
    ) -> f64 {
        let t = &self.tensors[b];
        let Some((fi, _)) = it.locate(set, uv[0], uv[1]) else {
            return 0.0;
        };
        let (lo, hi) = t.flank.faces[fi]
            .nodes
            .iter()
            .map(|&a| t.flank.uv[a as usize][0])
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), u| {
                (l.min(u), h.max(u))
            });
        flank.profile_length(hi - lo, uv[0], uv[1])
    }

    /// The candidate points of a TCA position with their cells on both
    /// flanks (in parallel over the points), and per point the separation,
    /// moment arm, equivalent radius, width, tangential arm and sliding
    /// velocity; `None` for a point off a meshed flank. Also the number of
    /// TCA points.
    #[allow(clippy::type_complexity)]
    pub(crate) fn candidates(
        &self,
        tca: &TcaPosition,
        frames: &[Frame; 2],
        torque: f64,
        settings: &LtcaSettings,
    ) -> Result<(Vec<Option<(Candidate, [f64; 6])>>, usize), FlankError> {
        let nominal_line_load = self.nominal_line_load(tca, torque);
        let its = [
            FlankInterpolator::with_grids(&self.tensors[0], Arc::clone(&self.grids[0])),
            FlankInterpolator::with_grids(&self.tensors[1], Arc::clone(&self.grids[1])),
        ];
        // candidates and their cells (in parallel over the points)
        let mut jobs = Vec::new();
        for (li, line) in tca.lines.iter().enumerate() {
            let sets = [
                format!("FLANK_R{}", line.pinion_tooth),
                format!("FLANK_R{}", line.gear_tooth),
            ];
            let set_index = [
                self.tensors[0].flank.set_index(&sets[0]).ok_or_else(|| {
                    FlankError::Model(format!("pinion tensor has no flank set {}", sets[0]))
                })?,
                self.tensors[1].flank.set_index(&sets[1]).ok_or_else(|| {
                    FlankError::Model(format!("gear tensor has no flank set {}", sets[1]))
                })?,
            ];
            let flanks = [
                self.flank(0, line.pinion_tooth)?,
                self.flank(1, line.gear_tooth)?,
            ];
            let first = line.points.first().map(|p| p.position).unwrap_or([0.0; 3]);
            for p in &line.points {
                jobs.push((li, line, p, sets.clone(), set_index, first, flanks));
            }
        }
        // the pinion's placed axis: r_t = (ω̂₁ × (x − o₁))·t
        let axis = frames[0].rotate(self.pair.rotation_axes()[0]);
        let origin = frames[0].translation;
        let built: Vec<Option<(Candidate, [f64; 6])>> = {
            use rayon::prelude::*;
            jobs.par_iter()
                .map(|(li, line, p, sets, set_index, first, flanks)| {
                    let uv = [p.pinion_uv, p.gear_uv];
                    // below a restricted tensor's region: an error, not "off the flank"
                    for b in 0..2 {
                        its[b].check_region(set_index[b], uv[b][0], uv[b][0], uv[b][1])?;
                    }
                    let h = (0..2)
                        .map(|b| self.element_size(&its[b], flanks[b], b, set_index[b], uv[b]))
                        .fold(0.0, f64::max);
                    if !(h > 0.0) {
                        // the point lies off a meshed flank: no candidate
                        return Ok(None);
                    }
                    // per body the cell's extent [toward its root, toward
                    // its tip]; tip corners keep κ h on the mating flank,
                    // the edge body's cell is the edge line (below)
                    let extent = if line.kind == LineKind::Flank {
                        let a = hertz_line(
                            nominal_line_load,
                            p.equivalent_radius_mm,
                            self.contact_modulus,
                        )
                        .0;
                        let tip = |b: usize| {
                            let [u, v] = uv[b];
                            flanks[b].profile_length(flanks[b].u_tip(v) - u, u, v)
                        };
                        fe_cell_extents(settings.fe_cell_factor, h, a, [tip(0), tip(1)])
                    } else {
                        let c = settings.fe_cell_factor * h;
                        [[c, c], [c, c]]
                    };
                    // the half-width (the same strip on both flanks)
                    let c = 0.5 * (extent[0][0] + extent[0][1]);
                    let l = 0.5 * p.width_mm;
                    let edge_body = match line.kind {
                        LineKind::PinionTipCorner => Some(0),
                        LineKind::GearTipCorner => Some(1),
                        _ => None,
                    };
                    let cell = |b: usize| {
                        let mut hu = flanks[b].profile_step(c, uv[b][0], uv[b][1]);
                        let hv = (l * line.param_per_mm).max(1e-6);
                        // centred between its root and tip extents
                        let mut u = uv[b][0]
                            + flanks[b].profile_step(
                                0.5 * (extent[b][1] - extent[b][0]),
                                uv[b][0],
                                uv[b][1],
                            );
                        if edge_body == Some(b) {
                            // the edge body of a tip corner carries its load
                            // on the tip edge (u = u_tip), as FE contact's
                            // slave edge nodes do: a cell of width 2c centred
                            // on the edge loses its outer half and moves the
                            // load ≈ c/3 down the tooth (shorter lever arm,
                            // a stiffer corner)
                            hu *= EDGE_CELL_FRACTION;
                            u -= hu;
                        }
                        its[b].cell(
                            &sets[b],
                            u,
                            uv[b][1],
                            CellShape::Rectangle { hu, hv },
                            settings.cell_samples,
                        )
                    };
                    let loads = [cell(0)?, cell(1)?];
                    let n = p.normal;
                    let normals = [
                        frames[0].rotate_back(n),
                        frames[1].rotate_back([-n[0], -n[1], -n[2]]),
                    ];
                    let t = p.tangent;
                    let tangents = [
                        frames[0].rotate_back(t),
                        frames[1].rotate_back([-t[0], -t[1], -t[2]]),
                    ];
                    let d = [
                        p.position[0] - first[0],
                        p.position[1] - first[1],
                        p.position[2] - first[2],
                    ];
                    let radius = if line.kind == LineKind::Flank {
                        p.equivalent_radius_mm
                    } else {
                        0.0
                    };
                    Ok(Some((
                        Candidate {
                            line: *li,
                            position: p.position,
                            along: dot(d, d).sqrt(),
                            half_length: l,
                            c,
                            loads,
                            normals,
                            tangents,
                        },
                        [
                            p.separation_mm,
                            p.moment_arm_mm,
                            radius,
                            p.width_mm,
                            dot(cross(axis, sub(p.position, origin)), p.tangent),
                            p.sliding_velocity,
                        ],
                    )))
                })
                .collect::<Result<_, FlankError>>()?
        };
        Ok((built, jobs.len()))
    }

    /// Solves the LTCA at one TCA position with torque `torque` (N·mm); the
    /// bodies sit in `frames` (own → global) at that roll.
    /// The nominal load per length (N/mm) of a position: the normal force
    /// T / r spread evenly over its flank lines, before the solve knows
    /// the shares (the cells' Hertz width and the first half-widths).
    fn nominal_line_load(&self, tca: &TcaPosition, torque: f64) -> f64 {
        let flank_length: f64 = tca
            .lines
            .iter()
            .filter(|l| l.kind == LineKind::Flank)
            .map(|l| l.length_mm)
            .sum();
        torque / self.nominal_moment_arm_mm / flank_length.max(1e-9)
    }

    /// The position's answer, or a clear error when its loaded TE reaches
    /// the angular pitch (the linear model's tooth pairs are then not the
    /// ones in contact). Applied to the final answer only: the mesh
    /// cycle's corner-contact extension may first have to add the
    /// neighbouring pairs that stop the rotation (at 100× torque the
    /// middle pair alone turns the pinion past a pitch, the three pairs
    /// together by 0.35 rad; `verification/extreme`).
    pub fn within_pitch(&self, r: PositionResult) -> Result<PositionResult, FlankError> {
        match crate::load_sharing::beyond_pitch_error(r.te_urad, self.pair.tooth_roll_step()) {
            Some(e) => Err(FlankError::Model(format!(
                "LTCA at roll {:.4}°: {e}",
                r.roll_deg
            ))),
            None => Ok(r),
        }
    }

    /// The LTCA at one TCA position. Its answer may still turn the pinion
    /// past a pitch: the caller passes its final answer through
    /// [`Self::within_pitch`] (the mesh cycle after its corner-contact
    /// extension, the bevel pair directly).
    pub fn solve(
        &self,
        tca: &TcaPosition,
        frames: &[Frame; 2],
        torque: f64,
        settings: &LtcaSettings,
    ) -> Result<PositionResult, FlankError> {
        let t0 = Instant::now();
        if !(settings.fe_cell_factor > 0.0) || settings.local_iterations == 0 {
            return Err(FlankError::Model(format!(
                "LTCA: fe_cell_factor must be > 0 (got {}) and local_iterations ≥ 1 (got {})",
                settings.fe_cell_factor, settings.local_iterations
            )));
        }
        let (built, jobs_len) = self.candidates(tca, frames, torque, settings)?;
        let mut cands: Vec<Candidate> = Vec::with_capacity(built.len());
        let (mut w, mut r, mut radius, mut width) =
            (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        let (mut r_t, mut v_s) = (Vec::new(), Vec::new());
        for (c, [wi, ri, rad, wid, rti, vsi]) in built.into_iter().flatten() {
            cands.push(c);
            w.push(wi);
            r.push(ri);
            radius.push(rad);
            width.push(wid);
            r_t.push(rti);
            v_s.push(vsi);
        }
        let skipped = jobs_len - cands.len();
        let n = cands.len();
        if n == 0 {
            return Err(FlankError::Model(format!(
                "LTCA at roll {:.4}°: no candidate point lies on both meshed flanks",
                tca.roll.to_degrees()
            )));
        }
        let cells_s = t0.elapsed().as_secs_f64();
        let t_f = Instant::now();
        // bulk compliance from the tensors (with friction also the
        // tangential blocks: [nn, nt, tn, tt])
        let mut f_fe = vec![0.0; n * n];
        let mut blocks = [vec![], vec![], vec![], vec![]];
        if settings.friction.is_some() {
            blocks = [
                vec![0.0; n * n],
                vec![0.0; n * n],
                vec![0.0; n * n],
                vec![0.0; n * n],
            ];
            for b in 0..2 {
                if !self.tensors[b].has_matrix() {
                    return Err(FlankError::Model(format!(
                        "the frictional LTCA reads the dense tensor, and that of {} was built \
                         compressed (no dense matrix): set compression = \"none\"",
                        self.tensors[b].meta.body
                    )));
                }
                let part = directional_compliance(&self.tensors[b], &cands, b);
                for (acc, p) in blocks.iter_mut().zip(part) {
                    for (x, y) in acc.iter_mut().zip(p) {
                        *x += y;
                    }
                }
            }
            f_fe.copy_from_slice(&blocks[0]);
        } else {
            f_fe = normal_compliance_pair(&self.tensors, &self.grids, &cands)?;
        }
        let compliance_s = t_f.elapsed().as_secs_f64();
        let (mut local_s, mut qp_s) = (0.0, 0.0);
        // nominal load per length for the first half-widths
        let p0 = self.nominal_line_load(tca, torque);
        let e_star = self.contact_modulus;
        // a tip corner is a sharp edge (radius 0, no Hertz width): its cell
        // stays the FE one, H = 0 there (the FE alone carries its local
        // deformation)
        let corner: Vec<bool> = radius.iter().map(|&r| !(r > 0.0)).collect();
        let fe_half = |i: usize| cands[i].c;
        let mut half = vec![0.0; n];
        for i in 0..n {
            half[i] = if corner[i] {
                fe_half(i)
            } else {
                // a contact wider than the FE cell (near a tip, where the
                // cell is narrowed) is taken at the cell's width: the FE
                // cell already concentrates the load more than Hertz would,
                // and H keeps only the centre-line/ellipse part
                hertz_line(p0, radius[i], e_star).0.min(fe_half(i))
            };
        }
        let mut f = f_fe.clone();
        // the FE-cell half-space solution is fixed per position
        let near_field = (settings.local == LocalModel::HalfSpace).then(|| {
            let cells: Vec<Cell> = cands
                .iter()
                .map(|c| Cell {
                    across: 0.0,
                    along: c.along,
                    c: c.c.max(1e-6),
                    l: c.half_length.max(1e-6),
                })
                .collect();
            let line: Vec<usize> = cands.iter().map(|c| c.line).collect();
            NearField::new(&cells, &line, e_star)
        });
        let mut solution: Option<Answer> = None;
        let mut local_iterations = 0;
        let mut local_change = 0.0;
        let mut local_converged = false;
        let mut loops = IterationLimits::new();
        for _ in 0..settings.local_iterations {
            local_iterations += 1;
            let t_l = Instant::now();
            f.copy_from_slice(&f_fe);
            if let Some(near) = &near_field {
                // H lumped on the diagonal (row sums): exact for a load
                // uniform over H's reach (a few cell widths, over which the
                // load along a line hardly varies), and it keeps F positive
                // definite; the full H, a difference of two kernels, is not
                // (seed 004's long cells at 1.875 mm gave an indefinite F)
                for (i, h) in near.diagonal(&half, &corner).into_iter().enumerate() {
                    f[i * n + i] += h;
                }
            }
            local_s += t_l.elapsed().as_secs_f64();
            let t_q = Instant::now();
            let s = match &settings.friction {
                None => Answer::of_qp(
                    solve_contact_qp(
                        &ContactQp {
                            compliance: &f,
                            separation: &w,
                            moment_arm: &r,
                            torque,
                        },
                        &settings.qp,
                    )?,
                    &settings.qp,
                ),
                Some(fr) => {
                    let sliding: Vec<f64> = match fr.model {
                        FrictionModel::Standstill => vec![0.0; n],
                        _ => v_s
                            .iter()
                            .zip(&r)
                            .map(|(&v, &rn)| 1e3 * v / (fr.pinion_speed_rad_s * rn))
                            .collect(),
                    };
                    let point_mu =
                        settings.point_mu(cands.iter().map(|c| tca.lines[c.line].pinion_tooth))?;
                    let problem = FrictionProblem {
                        c_nn: &f,
                        c_nt: &blocks[1],
                        c_tn: &blocks[2],
                        c_tt: &blocks[3],
                        separation: &w,
                        arm_normal: &r,
                        arm_tangential: &r_t,
                        sliding: &sliding,
                        mu: fr.mu,
                        point_mu: point_mu.as_deref(),
                        torque,
                    };
                    if fr.model == FrictionModel::Sliding {
                        // no friction where the flanks roll without sliding
                        // (below 1 µm/s)
                        let direction: Vec<f64> = v_s
                            .iter()
                            .map(|&v| if v.abs() < 1e-6 { 0.0 } else { v.signum() })
                            .collect();
                        Answer::of_sliding(&problem, &direction, fr, &settings.qp)?
                    } else {
                        Answer::of_friction(&problem, fr)?
                    }
                }
            };
            qp_s += t_q.elapsed().as_secs_f64();
            // new half-widths from the local loads per length
            let mut change: f64 = 0.0;
            for i in 0..n {
                let a = if corner[i] {
                    fe_half(i)
                } else if s.load[i] > 0.0 {
                    hertz_line(s.load[i] / width[i], radius[i], e_star)
                        .0
                        .min(fe_half(i))
                } else {
                    half[i]
                };
                // relative change of a (see HALF_WIDTH_TOLERANCE)
                change = change.max((a - half[i]).abs() / half[i].max(1e-6));
                half[i] = a;
            }
            loops.merge(&s.loops);
            solution = Some(s);
            local_change = change;
            if settings.local != LocalModel::HalfSpace || change < HALF_WIDTH_TOLERANCE {
                local_converged = true;
                break;
            }
        }
        let s = solution.expect("at least one iteration");
        if settings.local == LocalModel::HalfSpace {
            loops.record(
                "ltca.hertz_half_width",
                "relative change of the Hertz half-widths",
                HALF_WIDTH_TOLERANCE,
                LoopEnd {
                    iterations: local_iterations,
                    limit: settings.local_iterations,
                    converged: local_converged,
                    residual: local_change,
                },
            );
        }
        let time_s = t0.elapsed().as_secs_f64();
        // reported, not part of the solve: outside the timed part
        let condition = settings.condition.then(|| condition_number(&f, n));
        // the loads are unique only if F is regular on the loaded points
        // (always checked: a Cholesky of that block); tip-corner points
        // carry no half-space term, and more of them on a line than the
        // edge has nodes along it make F singular there
        let mut warnings: Vec<String> =
            crate::load_sharing::large_rotation_warning(s.rotation * 1e6)
                .into_iter()
                .collect();
        let loaded: Vec<usize> = (0..n).filter(|&i| s.load[i] > 0.0).collect();
        if singular_on(&f, n, &loaded) {
            let corners = loaded.iter().filter(|&&i| corner[i]).count();
            warnings.push(format!(
                "the compliance F is singular on the {} loaded points ({corners} of them on tip corners): the loads per point (and p_max) are not unique, θ and the gaps are; fewer points per line (K) than nodes along a tip edge avoid it",
                loaded.len()
            ));
        } else if singular_on(&f, n, &(0..n).collect::<Vec<_>>()) {
            // regular where loaded, singular over every candidate: the
            // unloaded points do not enter this answer, but the QPs of
            // the half-width iteration before it may have had several
            // minimisers, so which self-consistent state it reached can
            // depend on round-off (verification/extreme, torque 100×)
            warnings.push(format!(
                "{UNRESOLVED_CANDIDATES} ({n} candidates): more points along a line than the FE mesh resolves along the face, with no near-field term where the Hertz width reaches the FE cell; the loads are unique on the loaded points, but the half-width iteration may settle on another of several self-consistent states under round-off (p_max, TE); fewer points per line (K) or a finer mesh along the face avoid it"
            ));
        }
        let condition_loaded = settings.condition.then(|| {
            let on: Vec<usize> = (0..n).filter(|&i| s.load[i] > 0.0).collect();
            let m = on.len();
            let sub: Vec<f64> = on
                .iter()
                .flat_map(|&i| on.iter().map(move |&j| (i, j)))
                .map(|(i, j)| f[i * n + j])
                .collect();
            condition_number(&sub, m)
        });
        // per line and per point
        let nl = tca.lines.len();
        let mut line_force = vec![0.0; nl];
        let mut line_friction = vec![0.0; nl];
        let mut points = Vec::with_capacity(n);
        let mut pmax: f64 = 0.0;
        for (i, c) in cands.iter().enumerate() {
            line_force[c.line] += s.load[i];
            let (friction_n, state) = match &s.friction {
                Some((pt, states)) => (pt[i], state_name(states[i])),
                None => (0.0, "frictionless"),
            };
            line_friction[c.line] += friction_n;
            let q = s.load[i] / width[i];
            let (a, p) = hertz_line(q, radius[i], e_star);
            pmax = pmax.max(p);
            points.push(PointResult {
                line: c.line,
                position: c.position,
                along_mm: c.along,
                separation_mm: w[i],
                force_n: s.load[i],
                moment_arm_mm: r[i],
                load_per_length: q,
                pressure_mpa: p,
                half_width_mm: a,
                gap_mm: s.gap[i],
                friction_n,
                state,
                sliding_velocity_m_s: v_s[i],
            });
        }
        let total: f64 = line_force.iter().sum();
        let friction_power_w = points
            .iter()
            .map(|p| (p.friction_n * p.sliding_velocity_m_s).abs())
            .sum();
        let theta0 = tca.unloaded_te_rad;
        let rb1 = self.te_radius_mm;
        let approach = self.nominal_moment_arm_mm * (s.rotation - theta0);
        Ok(PositionResult {
            roll_deg: tca.roll.to_degrees(),
            lines: tca
                .lines
                .iter()
                .map(|l| (l.pinion_tooth, l.gear_tooth, format!("{:?}", l.kind)))
                .collect(),
            line_share: line_force
                .iter()
                .map(|&x| if total > 0.0 { x / total } else { 0.0 })
                .collect(),
            line_force_n: line_force,
            te_urad: s.rotation * 1e6,
            te_um: s.rotation * rb1 * 1e3,
            unloaded_te_urad: theta0 * 1e6,
            mesh_stiffness_n_per_um: if approach > 0.0 {
                total / (approach * 1e3)
            } else {
                f64::NAN
            },
            max_pressure_mpa: pmax,
            points,
            candidates: n,
            skipped_points: skipped,
            qp_iterations: s.iterations,
            local_iterations,
            kkt_max: s.kkt_max,
            kkt_within_tolerance: s.within_tolerance,
            loaded_approach_mm: approach,
            corner_extension_mm: f64::NAN,
            condition,
            condition_loaded,
            warnings,
            line_friction_n: line_friction,
            friction: s.report.clone(),
            friction_power_w,
            time_s,
            cells_s,
            compliance_s,
            local_s,
            qp_s,
            iteration_limits: loops,
        })
    }
}

impl PositionResult {
    /// A per-line value (e.g. [`Self::line_force_n`]) summed over the
    /// lines of each pinion tooth 1..=`teeth` of the sector.
    pub fn per_pair(&self, line_values: &[f64], teeth: usize) -> Vec<f64> {
        let mut f = vec![0.0; teeth];
        for (i, (k, _, _)) in self.lines.iter().enumerate() {
            if (1..=teeth).contains(k) {
                f[k - 1] += line_values.get(i).copied().unwrap_or(0.0);
            }
        }
        f
    }
}

/// One solve of a position's contact problem, frictionless (the QP) or
/// with friction (the incremental problem), in the terms the LTCA reports.
struct Answer {
    load: Vec<f64>,
    rotation: f64,
    gap: Vec<f64>,
    iterations: usize,
    /// KKT residual (QP) or the largest friction residual.
    kkt_max: f64,
    within_tolerance: bool,
    /// Friction forces and states of the last increment.
    friction: Option<(Vec<f64>, Vec<PointState>)>,
    report: Option<FrictionReport>,
    /// How the solve's bounded loops ended.
    loops: IterationLimits,
}

impl Answer {
    fn of_qp(s: QpSolution, options: &QpOptions) -> Self {
        // reaching the limit is an error of the QP: a returned answer met it
        let mut loops = IterationLimits::new();
        loops.record(
            "ltca.contact_qp",
            "largest relative KKT residual",
            options.kkt_tolerance,
            LoopEnd::converged(s.iterations, options.max_iterations, s.kkt.max),
        );
        Answer {
            load: s.load,
            rotation: s.rotation,
            gap: s.gap,
            iterations: s.iterations,
            kkt_max: s.kkt.max,
            within_tolerance: s.within_tolerance,
            friction: None,
            report: None,
            loops,
        }
    }

    fn of_friction(problem: &FrictionProblem, fr: &LtcaFriction) -> Result<Self, FlankError> {
        let (sol, check) = if fr.cross_check {
            let c = cross_check(problem, &fr.options)?;
            let summary = LemkeCrossCheck {
                load_difference: c.load_difference,
                rotation_difference: c.rotation_difference,
                state_differences: c.state_differences,
                lemke_within_tolerance: c.lemke.within_tolerance,
            };
            let sol = match fr.options.solver {
                FrictionSolver::Lemke => c.lemke,
                FrictionSolver::Clarabel => c.clarabel,
            };
            (sol, Some(summary))
        } else {
            (solve_friction(problem, &fr.options)?, None)
        };
        let last = sol.increments.last().ok_or_else(|| {
            FlankError::Solver("friction LTCA: no load increment was solved".into())
        })?;
        let mut loops = IterationLimits::new();
        for k in &sol.increments {
            let r = k.residual.max;
            match sol.solver {
                FrictionSolver::Clarabel => loops.record(
                    "ltca.friction_fixed_point",
                    "largest Coulomb residual of the increment",
                    fr.options.tolerance,
                    // a polished answer is the exact one of its states
                    if k.limit_hit && !k.polished {
                        LoopEnd::at_limit(k.iterations, fr.options.max_fixed_point, r)
                    } else {
                        LoopEnd::converged(k.iterations, fr.options.max_fixed_point, r)
                    },
                ),
                // Lemke's pivot limit is an error
                FrictionSolver::Lemke => loops.record(
                    "ltca.lemke_pivots",
                    "largest Coulomb residual of the increment",
                    fr.options.tolerance,
                    LoopEnd::converged(k.iterations, fr.options.max_pivots, r),
                ),
            }
        }
        let report = FrictionReport::Incremental(IncrementalReport {
            mu: fr.mu,
            model: fr.model,
            coupling: friction_coupling(problem, &last.normal),
            solver: sol.solver.name(),
            increments: sol.increments.len(),
            max_residual: sol.max_residual,
            within_tolerance: sol.within_tolerance,
            limit_hit: sol.increments.iter().any(|k| k.limit_hit),
            cross_check: check,
        });
        Ok(Answer {
            load: last.normal.clone(),
            rotation: last.rotation,
            gap: last.gap.clone(),
            iterations: sol.increments.iter().map(|k| k.iterations).sum(),
            kkt_max: sol.max_residual.max,
            within_tolerance: sol.within_tolerance,
            friction: Some((last.tangential.clone(), last.state.clone())),
            report: Some(report),
            loops,
        })
    }
}

impl Answer {
    fn of_sliding(
        problem: &FrictionProblem,
        direction: &[f64],
        fr: &LtcaFriction,
        qp: &QpOptions,
    ) -> Result<Self, FlankError> {
        let a = solve_sliding(problem, direction, qp)?;
        let state = (0..direction.len())
            .map(|i| {
                if !(a.normal[i] > 0.0) {
                    PointState::Separated
                } else if direction[i] > 0.0 {
                    PointState::SlipPositive
                } else if direction[i] < 0.0 {
                    PointState::SlipNegative
                } else {
                    PointState::Stick
                }
            })
            .collect();
        let max = a.residual.max(a.kkt);
        let coupling = friction_coupling(problem, &a.normal);
        let mut loops = IterationLimits::new();
        // the fixed point at its limit hands over to the active set, whose
        // own limit is an error
        loops.record(
            "ltca.sliding_fixed_point",
            "relative change of P_t",
            SLIDING_TOLERANCE,
            if a.limit_hit {
                LoopEnd::at_limit(a.iterations, MAX_SLIDING_ITERATIONS, a.change)
            } else {
                LoopEnd::converged(a.iterations, MAX_SLIDING_ITERATIONS, a.change)
            },
        );
        if a.active_set_iterations > 0 {
            loops.record(
                "ltca.sliding_active_set",
                "largest residual of the sliding law",
                fr.options.tolerance,
                LoopEnd::converged(
                    a.active_set_iterations,
                    MAX_ACTIVE_SET_ITERATIONS,
                    a.residual,
                ),
            );
        }
        let report = FrictionReport::Sliding(SlidingReport {
            mu: fr.mu,
            model: fr.model,
            coupling,
            solver: "sliding fixed point",
            iterations: a.iterations,
            active_set_iterations: a.active_set_iterations,
            limit_hit: a.limit_hit,
            change: a.change,
            max_residual: SlidingResidual {
                max,
                sliding_law: a.residual,
                qp_kkt: a.kkt,
            },
            within_tolerance: a.within_tolerance,
            cross_check: (a.active_set_iterations == 0).then_some(DirectCheck {
                method: "direct solve on the loaded set",
                load_difference: a.direct_difference,
            }),
        });
        Ok(Answer {
            load: a.normal,
            rotation: a.rotation,
            gap: a.gap,
            iterations: a.iterations,
            kkt_max: max,
            within_tolerance: a.within_tolerance,
            friction: Some((a.tangential, state)),
            report: Some(report),
            loops,
        })
    }
}

fn state_name(s: PointState) -> &'static str {
    match s {
        PointState::Separated => "separated",
        PointState::Stick => "stick",
        PointState::SlipPositive => "slip+",
        PointState::SlipNegative => "slip-",
    }
}

#[cfg(test)]
mod tests {
    use super::fe_cell_extents;

    /// c_FE = max(κ h, a) each way; near a tip cut at the tip edge (not
    /// below h/5) on that body's tip side and the mating body's root side.
    #[test]
    fn fe_cell_is_no_narrower_than_the_mesh_or_the_contact() {
        let far = [f64::INFINITY; 2];
        let both = |c: f64| [[c, c], [c, c]];
        // a coarse mesh: κ h
        assert_eq!(fe_cell_extents(1.0, 0.475, 0.26, far), both(0.475));
        // a mesh finer than the contact: the Hertz half-width, not κ h
        assert_eq!(fe_cell_extents(1.0, 0.1, 0.26, far), both(0.26));
        let e = fe_cell_extents(3.0, 0.1, 0.26, far);
        assert!(e.iter().flatten().all(|&x| (x - 0.3).abs() < 1e-15));
        // near the gear's tip: the gear's tip side and the pinion's root
        // side end at the edge, the other sides keep their width
        let e = fe_cell_extents(1.0, 0.1, 0.26, [f64::INFINITY, 0.05]);
        assert_eq!(e, [[0.05, 0.26], [0.26, 0.05]]);
        // near the pinion's tip, closer than h/5: h/5
        let e = fe_cell_extents(1.0, 0.1, 0.26, [0.001, f64::INFINITY]);
        assert_eq!(e, [[0.26, 0.2 * 0.1], [0.2 * 0.1, 0.26]]);
        // no Hertz width (no radius, no load): κ h
        assert_eq!(fe_cell_extents(1.0, 0.1, f64::NAN, far), both(0.1));
        assert_eq!(fe_cell_extents(1.0, 0.1, 0.0, far), both(0.1));
    }
}
