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
//! inclined in (u, v), so the cell is an approximation there.

use std::sync::Arc;
use std::time::Instant;

use crate::compliance::interpolation::{CellShape, FlankGrids, FlankInterpolator, SurfaceLoad};
use crate::compliance::ComplianceTensor;
use crate::contact::placement::Frame;
use crate::error::FlankError;
use crate::geometry::gear_pair::{Flank, PairPlacement};
use crate::geometry::surface::ToothSurface;
use crate::geometry::vec3::dot;
use crate::ltca::local::{cell_influence, hertz_line, Cell, LocalModel};
use crate::ltca::qp::{condition_number, solve_contact_qp, ContactQp, QpOptions, QpSolution};
use crate::tca::{LineKind, TcaPosition};

/// Settings of the LTCA solve at one position.
#[derive(Clone, Debug, serde::Serialize)]
pub struct LtcaSettings {
    pub local: LocalModel,
    /// κ: FE cell half-width across the line in flank element sizes.
    pub fe_cell_factor: f64,
    /// Gauss points per direction over a cell (tensor interpolation).
    pub cell_samples: usize,
    /// Fixed-point iterations on the Hertz half-widths (≥ 1).
    pub local_iterations: usize,
    pub qp: QpOptions,
    /// Report κ(F) (one symmetric eigen-decomposition per position).
    pub condition: bool,
}

impl Default for LtcaSettings {
    fn default() -> Self {
        LtcaSettings {
            local: LocalModel::default(),
            fe_cell_factor: 1.0,
            cell_samples: 3,
            local_iterations: 4,
            qp: QpOptions::default(),
            condition: false,
        }
    }
}

/// The two bodies of the LTCA: tensors and what the cells need.
pub struct LtcaBodies {
    pub tensors: [Arc<ComplianceTensor>; 2],
    /// Face search structures of the two tensors (built once).
    pub grids: [Arc<FlankGrids>; 2],
    /// The pair: the flank surfaces (profile lengths of the cells, tip
    /// edges).
    pub pair: Arc<dyn PairPlacement>,
    /// Moment arm of the nominal single-pair normal force (mm; the first
    /// guess of the Hertz widths) and the radius that turns a pinion
    /// rotation into a TE length (mm): a spur/helical pair's
    /// [`crate::geometry::gear_pair::GearPair::nominal_moment_arm`] and
    /// [`crate::geometry::gear_pair::GearPair::transmission_error_radius`];
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
    /// Load per unit length of line (N/mm) and Hertz peak pressure (MPa;
    /// 0 at tip-corner points, whose edge radius is zero).
    pub load_per_length: f64,
    pub pressure_mpa: f64,
    pub half_width_mm: f64,
    /// Gap after loading (mm; 0 where loaded).
    pub gap_mm: f64,
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
    /// 2-norm condition number of F (if asked).
    pub condition: Option<f64>,
    /// Wall time of the position (s; the caller adds the TCA) and of its
    /// parts: candidate cells, the tensor part of F, the half-space
    /// correction and the QP solves (summed over local iterations).
    pub time_s: f64,
    pub cells_s: f64,
    pub compliance_s: f64,
    pub local_s: f64,
    pub qp_s: f64,
}

/// A candidate point with its cells on both flanks.
struct Candidate {
    line: usize,
    position: [f64; 3],
    along: f64,
    half_length: f64,
    /// Half-width across the line of the FE cell (mm).
    c: f64,
    loads: [SurfaceLoad; 2],
    normals: [[f64; 3]; 2],
}

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

    /// Solves the LTCA at one TCA position with torque `torque` (N·mm); the
    /// bodies sit in `frames` (own → global) at that roll.
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
        let built: Vec<Option<(Candidate, [f64; 4])>> = {
            use rayon::prelude::*;
            jobs.par_iter()
                .map(|(li, line, p, sets, set_index, first, flanks)| {
                    let uv = [p.pinion_uv, p.gear_uv];
                    let h = (0..2)
                        .map(|b| self.element_size(&its[b], flanks[b], b, set_index[b], uv[b]))
                        .fold(0.0, f64::max);
                    if !(h > 0.0) {
                        // the point lies off a meshed flank: no candidate
                        return Ok(None);
                    }
                    // the cell stays on the flank: near a tip it is narrowed
                    // to the distance from the tip (arc length
                    // (u_tip − u) r_b u), not below a fifth of the element
                    // (tip corners keep κ h: their cell straddles the edge)
                    let mut c = settings.fe_cell_factor * h;
                    if line.kind == LineKind::Flank {
                        for b in 0..2 {
                            let [u, v] = uv[b];
                            let d = flanks[b].profile_length(flanks[b].u_tip(v) - u, u, v);
                            c = c.min(d.max(0.2 * h));
                        }
                    }
                    let l = 0.5 * p.width_mm;
                    let cell = |b: usize| {
                        let hu = flanks[b].profile_step(c, uv[b][0], uv[b][1]);
                        let hv = (l * line.param_per_mm).max(1e-6);
                        its[b].cell(
                            &sets[b],
                            uv[b][0],
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
                        },
                        [p.separation_mm, p.moment_arm_mm, radius, p.width_mm],
                    )))
                })
                .collect::<Result<_, FlankError>>()?
        };
        let mut cands: Vec<Candidate> = Vec::with_capacity(built.len());
        let (mut w, mut r, mut radius, mut width) =
            (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for (c, [wi, ri, rad, wid]) in built.into_iter().flatten() {
            cands.push(c);
            w.push(wi);
            r.push(ri);
            radius.push(rad);
            width.push(wid);
        }
        let skipped = jobs.len() - cands.len();
        let n = cands.len();
        if n == 0 {
            return Err(FlankError::Model(format!(
                "LTCA at roll {:.4}°: no candidate point lies on both meshed flanks",
                tca.roll.to_degrees()
            )));
        }
        let cells_s = t0.elapsed().as_secs_f64();
        let t_f = Instant::now();
        // bulk compliance from the tensors
        let mut f_fe = vec![0.0; n * n];
        for b in 0..2 {
            let part = normal_compliance(&self.tensors[b], &cands, b);
            for (x, y) in f_fe.iter_mut().zip(part) {
                *x += y;
            }
        }
        let compliance_s = t_f.elapsed().as_secs_f64();
        let (mut local_s, mut qp_s) = (0.0, 0.0);
        // nominal load per length for the first half-widths
        let flank_length: f64 = tca
            .lines
            .iter()
            .filter(|l| l.kind == LineKind::Flank)
            .map(|l| l.length_mm)
            .sum();
        let nominal = torque / self.nominal_moment_arm_mm;
        let p0 = nominal / flank_length.max(1e-9);
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
                // cell is narrowed) gets no correction: the FE cell already
                // concentrates the load more than Hertz would
                hertz_line(p0, radius[i], e_star).0.min(fe_half(i))
            };
        }
        let mut f = f_fe.clone();
        // the FE-cell half-space solution is fixed per position
        let pairs = half_space_pairs(&cands);
        let b_fe = if settings.local == LocalModel::HalfSpace {
            let c: Vec<f64> = cands.iter().map(|c| c.c).collect();
            half_space_influence(&cands, &pairs, &c, e_star)
        } else {
            Vec::new()
        };
        let mut solution: Option<QpSolution> = None;
        let mut local_iterations = 0;
        for _ in 0..settings.local_iterations {
            local_iterations += 1;
            let t_l = Instant::now();
            f.copy_from_slice(&f_fe);
            if settings.local == LocalModel::HalfSpace {
                // H lumped on the diagonal (row sums): exact for a load
                // uniform over H's reach (a few cell widths, over which the
                // load along a line hardly varies), and it keeps F positive
                // definite; the full H, a difference of two kernels, is not
                // (seed 004's long cells at 1.875 mm gave an indefinite F)
                let near = half_space_influence(&cands, &pairs, &half, e_star);
                for (k, &(i, j)) in pairs.iter().enumerate() {
                    let h = near[k] - b_fe[k];
                    f[i * n + i] += h;
                    if i != j {
                        f[j * n + j] += h;
                    }
                }
            }
            local_s += t_l.elapsed().as_secs_f64();
            let t_q = Instant::now();
            let qp = ContactQp {
                compliance: &f,
                separation: &w,
                moment_arm: &r,
                torque,
            };
            let s = solve_contact_qp(&qp, &settings.qp)?;
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
                // relative change of a: 1 % moves the near-field term by
                // (2/(π E*)) P′ ln(1.01), < 1e-3 of the TE at gear loads
                change = change.max((a - half[i]).abs() / half[i].max(1e-6));
                half[i] = a;
            }
            solution = Some(s);
            if settings.local != LocalModel::HalfSpace || change < 1e-2 {
                break;
            }
        }
        let s = solution.expect("at least one iteration");
        let time_s = t0.elapsed().as_secs_f64();
        // reported, not part of the solve: outside the timed part
        let condition = settings.condition.then(|| condition_number(&f, n));
        // per line and per point
        let nl = tca.lines.len();
        let mut line_force = vec![0.0; nl];
        let mut points = Vec::with_capacity(n);
        let mut pmax: f64 = 0.0;
        for (i, c) in cands.iter().enumerate() {
            line_force[c.line] += s.load[i];
            let q = s.load[i] / width[i];
            let (a, p) = hertz_line(q, radius[i], e_star);
            pmax = pmax.max(p);
            points.push(PointResult {
                line: c.line,
                position: c.position,
                along_mm: c.along,
                separation_mm: w[i],
                force_n: s.load[i],
                load_per_length: q,
                pressure_mpa: p,
                half_width_mm: a,
                gap_mm: s.gap[i],
            });
        }
        let total: f64 = line_force.iter().sum();
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
            kkt_max: s.kkt.max,
            kkt_within_tolerance: s.within_tolerance,
            condition,
            time_s,
            cells_s,
            compliance_s,
            local_s,
            qp_s,
        })
    }
}

/// The point pairs (i ≤ j) H acts on: same line, within ten cell sizes of
/// each other (beyond that the two half-space solutions agree to < 1e-4 of
/// the point-force value, see `local::tests`).
fn half_space_pairs(cands: &[Candidate]) -> Vec<(usize, usize)> {
    let n = cands.len();
    let mut out = Vec::new();
    for i in 0..n {
        for j in i..n {
            let (ci, cj) = (&cands[i], &cands[j]);
            let reach = 10.0 * ci.c.max(cj.c).max(ci.half_length.max(cj.half_length));
            if ci.line == cj.line && (ci.along - cj.along).abs() <= reach {
                out.push((i, j));
            }
        }
    }
    out
}

/// B_ij over `pairs` with cells of half-width `half` across the line.
fn half_space_influence(
    cands: &[Candidate],
    pairs: &[(usize, usize)],
    half: &[f64],
    e_star: f64,
) -> Vec<f64> {
    use rayon::prelude::*;
    let cell = |i: usize| Cell {
        across: 0.0,
        along: cands[i].along,
        c: half[i].max(1e-6),
        l: cands[i].half_length.max(1e-6),
    };
    pairs
        .par_iter()
        .map(|&(i, j)| cell_influence(&cell(i), &cell(j), e_star, 2))
        .collect()
}

/// n₍b₎ᵢᵀ C(i, j) n₍b₎ⱼ of one body for all candidate pairs (n × n,
/// row-major): for each j the displacement u_j = C (Σ_c w_c n_j e_c) is
/// formed on the union U of the cells' nodes, reading C by rows of the
/// loaded nodes c (C is symmetric) so that each row is streamed over the
/// sorted U; then F_ij = Σ_{a ∈ i} w_a n_iᵀ u_j(a).
fn normal_compliance(t: &ComplianceTensor, cands: &[Candidate], b: usize) -> Vec<f64> {
    use rayon::prelude::*;
    let n = cands.len();
    let dim = t.dim();
    let mut nodes: Vec<u32> = cands
        .iter()
        .flat_map(|c| c.loads[b].weights.iter().map(|&(a, _)| a))
        .collect();
    nodes.sort_unstable();
    nodes.dedup();
    let index = |a: u32| nodes.binary_search(&a).expect("node of a cell");
    let columns: Vec<Vec<f64>> = (0..n)
        .into_par_iter()
        .map(|j| {
            let nj = cands[j].normals[b];
            let mut u = vec![0.0; 3 * nodes.len()];
            for &(c, w) in &cands[j].loads[b].weights {
                for (s, &ns) in nj.iter().enumerate() {
                    let f = w * ns;
                    if f == 0.0 {
                        continue;
                    }
                    let row = &t.matrix[(3 * c as usize + s) * dim..][..dim];
                    for (k, &a) in nodes.iter().enumerate() {
                        let x = &row[3 * a as usize..3 * a as usize + 3];
                        u[3 * k] += f * x[0];
                        u[3 * k + 1] += f * x[1];
                        u[3 * k + 2] += f * x[2];
                    }
                }
            }
            // F_ij for all i
            (0..n)
                .map(|i| {
                    let ni = cands[i].normals[b];
                    cands[i].loads[b]
                        .weights
                        .iter()
                        .map(|&(a, w)| {
                            let k = index(a);
                            w * (ni[0] * u[3 * k] + ni[1] * u[3 * k + 1] + ni[2] * u[3 * k + 2])
                        })
                        .sum::<f64>()
                })
                .collect()
        })
        .collect();
    // column j holds F_ij; symmetrise the round-off
    let mut f = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..n {
            f[i * n + j] = 0.5 * (columns[j][i] + columns[i][j]);
        }
    }
    f
}
