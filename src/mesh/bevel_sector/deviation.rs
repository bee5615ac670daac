//! How far the quadratic flank faces of a bevel sector leave the exact
//! tooth surfaces: the quarter points (ξ = ±½) of every element edge whose
//! three nodes lie on one flank, measured against the surface.
//!
//! The distance of a quarter point q is the smaller of (a) the
//! closest-point distance to the surface and (b) the distance to a dense
//! polyline (64 chords) of surface points along the straight parameter
//! segment between the edge's end nodes — an upper bound of the distance
//! to the surface (its chords are exact to (L/64)² κ / 8). (b) is what
//! holds where (a) fails: at a formate member's fillet end, where the
//! fillet meets the root cone tangentially, the axial-section
//! parameterisation is singular (∂r/∂u unbounded) and the closest-point
//! Newton stops on the domain's edge.

use std::collections::HashSet;

use super::BevelSectorMesh;
use crate::geometry::bevel::body::BevelGear;
use crate::geometry::gear_pair::{Flank, GearBody};
use crate::geometry::surface::ToothSurface;

/// Chords of the polyline of (b).
const POLYLINE_CHORDS: usize = 64;
/// (b) is only computed where (a) exceeds this (mm): below it the
/// reported largest deviation cannot change by more than this.
const POLYLINE_BELOW: f64 = 1e-5;

fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// Distance from q to the segment a–b.
fn to_segment(q: [f64; 3], a: [f64; 3], b: [f64; 3]) -> f64 {
    let ab = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let aq = [q[0] - a[0], q[1] - a[1], q[2] - a[2]];
    let l2 = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
    let t = if l2 > 0.0 {
        ((aq[0] * ab[0] + aq[1] * ab[1] + aq[2] * ab[2]) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    distance(q, [a[0] + t * ab[0], a[1] + t * ab[1], a[2] + t * ab[2]])
}

fn quarter_point_distance(
    surface: &dyn ToothSurface,
    q: [f64; 3],
    (ua, va): (f64, f64),
    (ub, vb): (f64, f64),
) -> f64 {
    let closest = surface.closest_point_from(q, ua, va).2.abs();
    if closest < POLYLINE_BELOW {
        return closest;
    }
    let mut prev = surface.point(ua, va);
    let mut poly = f64::INFINITY;
    for k in 1..=POLYLINE_CHORDS {
        let t = k as f64 / POLYLINE_CHORDS as f64;
        let p = surface.point(ua + t * (ub - ua), va + t * (vb - va));
        poly = poly.min(to_segment(q, prev, p));
        prev = p;
    }
    closest.min(poly)
}

/// Largest deviation (mm) of flank-edge quarter points from the surface
/// (module docs): [edges along the profile (both ends on one station),
/// edges along the face].
pub fn flank_edge_deviation(gear: &BevelGear, sector: &BevelSectorMesh) -> [f64; 2] {
    let mesh = &sector.mesh;
    let mut dev = [0.0f64; 2];
    for (set, nodes) in &mesh.node_sets {
        let side = match set.get(..7) {
            Some("FLANK_L") => Flank::Left,
            Some("FLANK_R") => Flank::Right,
            _ => continue,
        };
        let Some(surface) = set[7..].parse().ok().and_then(|k| gear.flank(side, k)) else {
            continue;
        };
        let on: HashSet<usize> = nodes.iter().copied().collect();
        for e in &mesh.elements {
            for edge in crate::fem::element::edges(e.kind) {
                let [a, b, m] = edge.map(|i| e.nodes[i]);
                if !(on.contains(&a) && on.contains(&b) && on.contains(&m)) {
                    continue;
                }
                let (xa, xb, xm) = (mesh.coords[a], mesh.coords[b], mesh.coords[m]);
                let (pa, pb) = (sector.flank_uv[&a], sector.flank_uv[&b]);
                let along_face = usize::from((pa.1 - pb.1).abs() > 1e-9);
                for xi in [-0.5f64, 0.5] {
                    let (na, nb, nm) =
                        (0.5 * xi * (xi - 1.0), 0.5 * xi * (xi + 1.0), 1.0 - xi * xi);
                    let q = [0, 1, 2].map(|c| na * xa[c] + nb * xb[c] + nm * xm[c]);
                    let d = quarter_point_distance(surface, q, pa, pb);
                    dev[along_face] = dev[along_face].max(d);
                }
            }
        }
    }
    dev
}
