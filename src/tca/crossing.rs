//! The crossing check of the point TCA: with the gear where the TE envelope
//! puts it, does any point of a pair's pinion active flank lie inside the
//! gear flank? A pair whose flanks cross (an ease-off that is not convex)
//! or whose trace ended where its flanks still interfere stops the gear
//! elsewhere, and the TCA's TE and bearing are then not the pair's.
//!
//! # Method
//!
//! * A [`CROSSING_GRID`] of points over the pinion's active flank (form
//!   line to tip, toe to heel) is evaluated once, in the pinion's own frame
//!   (the same points at every roll); each is placed at the roll and taken
//!   to the gear's frame.
//! * **Exact test** of one point: its signed distance to the gear flank by
//!   closest point (two starts), counted where the closest point lies
//!   strictly inside the gear's active flank; a point deeper than
//!   [`CROSSING_TOLERANCE_MM`] crosses.
//! * **Screen.** The exact test costs some ten envelope solves on a
//!   generated flank, and the check runs it for every grid point at every
//!   position of a pitch for five pairs (23 000 points on seed 000: 2.7 s,
//!   98 % of a TCA cycle). The gear's active flank is sampled once on a
//!   [`SCREEN_GRID`] of nodes (point, normal, r_u, r_v); at each node a
//!   quadratic height h(a, b) = ½(L a² + 2M ab + N b²) over the tangent
//!   plane is fitted by least squares to the offsets of its 8 neighbours
//!   (a, b: parameter steps, first order), and the largest misfit at those
//!   neighbours is the node's model error e_q. A placed pinion point x is
//!   screened at its nearest node q (a greedy walk over the nodes from the
//!   previous point's node): d̃ = n·(x − p_q) − h(a, b) estimates its signed
//!   distance. The exact test runs only where d̃ − 2 e_q − [`SCREEN_FLOOR_MM`]
//!   < −[`CROSSING_TOLERANCE_MM`], i.e. where a crossing is not excluded
//!   with twice the model's measured error to spare. A point projecting
//!   beyond the sampled flank (tangential offset above the node spacing)
//!   is always tested exactly.
//! * Where the gear flank cannot be sampled (a node outside its generated
//!   region), every point is tested exactly.
//!
//! The screened and the exhaustive check agree on the seed scenes (test
//! `verification/hypoid_tca`); [`CrossingScan::check_every_point`] is the
//! exhaustive one.

use crate::geometry::frame::Frame;
use crate::geometry::gear_pair::{Flank, GearPair};
use crate::geometry::surface::ToothSurface;
use crate::geometry::vec3::{dot, norm, solve3, sub, V3};

/// Grid over the pinion's active flank: profile × face points.
pub const CROSSING_GRID: (usize, usize) = (9, 17);
/// Depth (mm) below which a grid point counts as crossing: far above the
/// closest-point accuracy, far below any approach δ.
pub const CROSSING_TOLERANCE_MM: f64 = 1e-5;
/// Nodes of the gear-flank screen: profile × face.
pub const SCREEN_GRID: (usize, usize) = (13, 25);
/// Margin (mm) added to the screen's measured model error (round-off of
/// the placed coordinates, ~1e-12 relative to 100 mm, with room).
pub const SCREEN_FLOOR_MM: f64 = 1e-7;

/// Where the flanks cross.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Crossing {
    /// Roll angle of the position (rad).
    pub roll_rad: f64,
    /// The pair: the middle pair's offset i (pair i at this roll is the
    /// middle pair at roll − i·step).
    pub pair_offset: i64,
    /// Depth of the pinion point inside the gear flank (mm, > 0).
    pub depth_mm: f64,
    /// Pinion and gear flank parameters there.
    pub pinion_uv: [f64; 2],
    pub gear_uv: [f64; 2],
}

/// Grid points tested over a check (or a whole scan).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct ScanCount {
    /// Pinion grid points placed and screened.
    pub points: usize,
    /// Of these, tested exactly (closest point on the gear flank).
    pub exact: usize,
    /// Checks (position × pair) that found a crossing.
    pub crossed: usize,
}

impl std::ops::AddAssign for ScanCount {
    fn add_assign(&mut self, o: Self) {
        self.points += o.points;
        self.exact += o.exact;
        self.crossed += o.crossed;
    }
}

/// One node of the gear-flank screen.
#[derive(Clone, Copy, Debug)]
struct Node {
    uv: [f64; 2],
    p: V3,
    n: V3,
    ru: V3,
    rv: V3,
    /// Inverse first fundamental form [g^uu, g^uv, g^vv].
    g_inv: [f64; 3],
    /// Fitted second form [L, M, N] (height = ½ Δᵀ II Δ).
    ii: [f64; 3],
    /// Largest misfit of the quadratic at the neighbours (mm).
    error: f64,
}

impl Node {
    /// Parameter steps (a, b) of the tangential part of `d`, first order.
    fn steps(&self, d: V3) -> [f64; 2] {
        let (x, y) = (dot(self.ru, d), dot(self.rv, d));
        [
            self.g_inv[0] * x + self.g_inv[1] * y,
            self.g_inv[1] * x + self.g_inv[2] * y,
        ]
    }

    fn height(&self, [a, b]: [f64; 2]) -> f64 {
        0.5 * (self.ii[0] * a * a + 2.0 * self.ii[1] * a * b + self.ii[2] * b * b)
    }
}

/// The gear flank sampled for the screen (module docs).
#[derive(Debug)]
struct Screen {
    nodes: Vec<Node>,
    /// Largest distance between neighbouring nodes (mm).
    spacing: f64,
    /// Parameter steps (Δu, Δv) between nodes, per face line.
    cells: Vec<[f64; 2]>,
}

impl Screen {
    /// Samples the active flank of `s`; `None` where a node does not
    /// evaluate or a fit is singular.
    fn sample(s: &dyn ToothSurface) -> Option<Screen> {
        let (nu, nv) = SCREEN_GRID;
        let (v0, v1) = s.v_range();
        let mut nodes = Vec::with_capacity(nu * nv);
        let mut cells = Vec::with_capacity(nv);
        for j in 0..nv {
            let v = v0 + (v1 - v0) * j as f64 / (nv - 1) as f64;
            let (uf, ut) = (s.u_form(v), s.u_tip(v));
            cells.push([(ut - uf) / (nu - 1) as f64, (v1 - v0) / (nv - 1) as f64]);
            for i in 0..nu {
                let u = uf + (ut - uf) * i as f64 / (nu - 1) as f64;
                let (p, n, ru, rv) = s.evaluate_checked(u, v)?;
                let (e, f, g) = (dot(ru, ru), dot(ru, rv), dot(rv, rv));
                let det = e * g - f * f;
                if !(det > 0.0) {
                    return None;
                }
                nodes.push(Node {
                    uv: [u, v],
                    p,
                    n,
                    ru,
                    rv,
                    g_inv: [g / det, -f / det, e / det],
                    ii: [0.0; 3],
                    error: 0.0,
                });
            }
        }
        let mut spacing: f64 = 0.0;
        for k in 0..nodes.len() {
            let q = nodes[k];
            // least squares of ½ Δᵀ II Δ = height over the neighbours
            let mut ata = [[0.0; 3]; 3];
            let mut atb = [0.0; 3];
            let mut rows = Vec::with_capacity(8);
            for r in neighbours(k) {
                let d = sub(nodes[r].p, q.p);
                spacing = spacing.max(norm(d));
                let [a, b] = q.steps(d);
                let row = [0.5 * a * a, a * b, 0.5 * b * b];
                let h = dot(q.n, d);
                for x in 0..3 {
                    atb[x] += row[x] * h;
                    for y in 0..3 {
                        ata[x][y] += row[x] * row[y];
                    }
                }
                rows.push((row, h));
            }
            let ii = solve3(&ata, atb)?;
            let error = rows
                .iter()
                .map(|(row, h)| (row[0] * ii[0] + row[1] * ii[1] + row[2] * ii[2] - h).abs())
                .fold(0.0, f64::max);
            nodes[k].ii = ii;
            nodes[k].error = error;
        }
        Some(Screen {
            nodes,
            spacing,
            cells,
        })
    }

    /// The node nearest to `x` by a greedy walk from node `start`.
    fn nearest(&self, x: V3, start: usize) -> usize {
        let d2 = |k: usize| {
            let d = sub(x, self.nodes[k].p);
            dot(d, d)
        };
        let (mut k, mut best) = (start, d2(start));
        // each move strictly lowers the distance: at most one visit a node
        for _ in 0..self.nodes.len() {
            let next = neighbours(k)
                .map(|r| (r, d2(r)))
                .min_by(|a, b| a.1.total_cmp(&b.1));
            match next {
                Some((r, d)) if d < best => {
                    k = r;
                    best = d;
                }
                _ => break,
            }
        }
        k
    }

    /// Whether the point `x` (gear frame) needs the exact test, and the
    /// node it was screened at.
    fn needs_exact(&self, x: V3, start: usize) -> (bool, usize) {
        let k = self.nearest(x, start);
        let q = &self.nodes[k];
        let d = sub(x, q.p);
        let along = dot(q.n, d);
        let tangential = norm(sub(d, [along * q.n[0], along * q.n[1], along * q.n[2]]));
        // where the foot lies, in grid cells beyond the sampled flank (the
        // first-order foot, trusted to half the tangential offset)
        let [da, db] = q.steps(d);
        let (nu, nv) = (SCREEN_GRID.0 as f64, SCREEN_GRID.1 as f64);
        let (i, j) = ((k % SCREEN_GRID.0) as f64, (k / SCREEN_GRID.0) as f64);
        let cell = self.cells[k / SCREEN_GRID.0];
        let (a, b) = (i + da / cell[0], j + db / cell[1]);
        let beyond = (-a).max(a - (nu - 1.0)).max(-b).max(b - (nv - 1.0));
        if beyond > 1.0 + 0.5 * tangential / self.spacing {
            // its closest point on the active flank is on the flank's
            // boundary, never strictly inside: the exact test would not
            // count it
            return (false, k);
        }
        if tangential > self.spacing {
            return (true, k);
        }
        let estimate = along - q.height(q.steps(d));
        let margin = 2.0 * q.error + SCREEN_FLOOR_MM;
        (estimate - margin < -CROSSING_TOLERANCE_MM, k)
    }
}

/// The (up to 8) neighbours of node `k` of a [`SCREEN_GRID`].
fn neighbours(k: usize) -> impl Iterator<Item = usize> {
    let (nu, nv) = (SCREEN_GRID.0 as i64, SCREEN_GRID.1 as i64);
    let (i, j) = (k as i64 % nu, k as i64 / nu);
    (-1i64..=1)
        .flat_map(move |dj| (-1i64..=1).map(move |di| (i + di, j + dj)))
        .filter(move |&(a, b)| (a, b) != (i, j) && a >= 0 && a < nu && b >= 0 && b < nv)
        .map(move |(a, b)| (b * nu + a) as usize)
}

/// The crossing check of one pair over a TCA (module docs): the pinion
/// grid and the gear screen, built once.
pub struct CrossingScan<'a> {
    pair: &'a dyn GearPair,
    /// (u, v) and own-frame point of each pinion grid point, face line by
    /// face line (toe to heel), form line to tip along each.
    pinion: Vec<([f64; 2], V3)>,
    screen: Option<Screen>,
}

impl<'a> CrossingScan<'a> {
    /// The pinion grid and the gear screen of `pair`'s middle pair.
    pub fn new(pair: &'a dyn GearPair) -> Self {
        let km = pair.middle();
        let ps = pair
            .pinion()
            .flank(Flank::Right, km)
            .expect("middle pinion tooth");
        let gs = pair
            .gear()
            .flank(Flank::Right, pair.mate(km))
            .expect("middle gear tooth");
        let (pv0, pv1) = ps.v_range();
        let mut pinion = Vec::with_capacity(CROSSING_GRID.0 * CROSSING_GRID.1);
        for j in 0..CROSSING_GRID.1 {
            let v = pv0 + (pv1 - pv0) * j as f64 / (CROSSING_GRID.1 - 1) as f64;
            let (uf, ut) = (ps.u_form(v), ps.u_tip(v));
            for i in 0..CROSSING_GRID.0 {
                let u = uf + (ut - uf) * i as f64 / (CROSSING_GRID.0 - 1) as f64;
                pinion.push(([u, v], ps.point(u, v)));
            }
        }
        CrossingScan {
            pair,
            pinion,
            screen: Screen::sample(gs),
        }
    }

    /// Whether the gear flank was sampled (else every point is exact).
    pub fn screened(&self) -> bool {
        self.screen.is_some()
    }

    /// The deepest crossing (below −[`CROSSING_TOLERANCE_MM`]) of the
    /// middle pair at `roll` with the gear turned by `turn` (its
    /// `pair_offset` 0), screened (module docs).
    pub fn check(&self, roll: f64, turn: f64) -> (Option<Crossing>, ScanCount) {
        self.scan(roll, turn, true)
    }

    /// [`Self::check`] with every grid point tested exactly.
    pub fn check_every_point(&self, roll: f64, turn: f64) -> (Option<Crossing>, ScanCount) {
        self.scan(roll, turn, false)
    }

    fn scan(&self, roll: f64, turn: f64, screened: bool) -> (Option<Crossing>, ScanCount) {
        let km = self.pair.middle();
        let gs = self
            .pair
            .gear()
            .flank(Flank::Right, self.pair.mate(km))
            .expect("middle gear tooth");
        let [f1, f2] = self.pair.frames(roll);
        let axis = f2.rotate([0.0, 0.0, 1.0]);
        let g2t = Frame::about_axis(f2.translation, axis, turn).compose(&f2);
        let (gv0, gv1) = gs.v_range();
        let mid = [0.0, 0.5 * (gv0 + gv1)];
        let screen = self.screen.as_ref().filter(|_| screened);
        let mut node = SCREEN_GRID.0 * SCREEN_GRID.1 / 2;
        let mut count = ScanCount::default();
        let mut worst: Option<Crossing> = None;
        let mut warm = mid;
        for (k, &(uv, x)) in self.pinion.iter().enumerate() {
            if k % CROSSING_GRID.0 == 0 {
                warm = mid;
            }
            let placed = f1.place(x);
            let own = g2t.rotate_back(sub(placed, g2t.translation));
            count.points += 1;
            if let Some(s) = screen {
                let (exact, at) = s.needs_exact(own, node);
                node = at;
                if !exact {
                    continue;
                }
                warm = s.nodes[at].uv;
            }
            count.exact += 1;
            let mut best: Option<(f64, f64, f64)> = None;
            for start in [warm, mid] {
                let (gu, gv, d) = gs.closest_point_from(own, start[0], start[1]);
                // strictly inside: a closest point clamped to the domain's
                // edge (a pinion point beyond the gear's face) has no
                // meaningful sign. The form line (a Newton of envelope
                // solves on generated flanks) is asked last, and only of a
                // point that would improve on the other start's.
                let better = best.is_none_or(|b| d < b.2);
                let inside = || {
                    gv > gv0 + 1e-9
                        && gv < gv1 - 1e-9
                        && gu < gs.u_tip(gv) - 1e-9
                        && gu > gs.u_form(gv) + 1e-9
                };
                if better && inside() {
                    best = Some((gu, gv, d));
                }
            }
            let Some((gu, gv, d)) = best else {
                continue;
            };
            warm = [gu, gv];
            // the gear's outward normal: d < 0 is inside the gear tooth
            if d < -CROSSING_TOLERANCE_MM && worst.is_none_or(|w| -d > w.depth_mm) {
                worst = Some(Crossing {
                    roll_rad: roll,
                    pair_offset: 0,
                    depth_mm: -d,
                    pinion_uv: uv,
                    gear_uv: [gu, gv],
                });
            }
        }
        count.crossed = usize::from(worst.is_some());
        (worst, count)
    }
}
