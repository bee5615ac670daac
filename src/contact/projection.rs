//! Closest-point projection of a point onto a quadratic face.
//!
//! Minimizes f(ξ) = ½|p − x(ξ)|² over the face parameters by Newton's method
//! with the exact Hessian H_αβ = t_α·t_β − x,_αβ·(p − x) (the face's
//! curvature enters through the second derivatives). Safeguards: where H is
//! not positive definite (a point on the concave side, far from the face)
//! the Gauss–Newton matrix t_α·t_β is used instead; steps are limited to 0.5
//! in parameter space and halved until f decreases; iterates stay within an
//! extended parameter box. Convergence: |Δξ| < 1e-13 or a stationary
//! gradient; at most [`MAX_NEWTON`] iterations (a face whose projection does
//! not converge is reported as such and skipped by the search).

use crate::contact::surface::{cross, dot, face_point, norm, sub};

/// Newton iteration limit of one projection.
pub const MAX_NEWTON: usize = 30;
/// Parameter tolerance within which a projection counts as inside a face.
pub const INSIDE_TOLERANCE: f64 = 1e-6;

/// Result of projecting a point onto one face.
#[derive(Clone, Debug, PartialEq)]
pub struct Projection {
    /// Face parameters of the closest point (clamped to the face if outside).
    pub xi: [f64; 2],
    /// The closest point.
    pub point: [f64; 3],
    /// Unit outward normal of the face's element at the closest point.
    pub normal: [f64; 3],
    /// Signed normal gap n·(p − x): positive outside the master body.
    pub gap: f64,
    /// Distance in parameter space by which the unconstrained minimizer lies
    /// outside the face (0 inside).
    pub outside_by: f64,
    pub iterations: usize,
    pub converged: bool,
}

/// How far `xi` lies outside the parameter domain of a face with `nodes`
/// nodes (0 inside), and the clamped point.
pub fn clamp_to_face(nodes: usize, xi: [f64; 2]) -> (f64, [f64; 2]) {
    if nodes == 8 {
        let c = [xi[0].clamp(-1.0, 1.0), xi[1].clamp(-1.0, 1.0)];
        let d = ((xi[0] - c[0]).powi(2) + (xi[1] - c[1]).powi(2)).sqrt();
        (d, c)
    } else {
        // triangle r, s ≥ 0, r + s ≤ 1: project onto the closest of the region
        let [r, s] = xi;
        if r >= 0.0 && s >= 0.0 && r + s <= 1.0 {
            return (0.0, xi);
        }
        let candidates = [[r.clamp(0.0, 1.0), 0.0], [0.0, s.clamp(0.0, 1.0)], {
            // onto r + s = 1
            let t = ((r - s + 1.0) * 0.5).clamp(0.0, 1.0);
            [t, 1.0 - t]
        }];
        let mut best = (f64::INFINITY, xi);
        for c in candidates {
            let d = ((r - c[0]).powi(2) + (s - c[1]).powi(2)).sqrt();
            if d < best.0 {
                best = (d, c);
            }
        }
        best
    }
}

/// Projects `p` onto the face with node coordinates `x` (8 or 6 nodes, face
/// order).
pub fn project(x: &[[f64; 3]], p: [f64; 3]) -> Projection {
    let nodes = x.len();
    let mut xi = if nodes == 8 {
        [0.0, 0.0]
    } else {
        [1.0 / 3.0, 1.0 / 3.0]
    };
    // start from the nearest face node's parameters if it is much closer
    let mut best_node = (f64::INFINITY, 0);
    for (a, xa) in x.iter().enumerate() {
        let d = norm(sub(p, *xa));
        if d < best_node.0 {
            best_node = (d, a);
        }
    }
    let start = crate::contact::surface::node_reference(nodes, best_node.1);
    // halfway between the centre and the nearest node: robust on curved faces
    xi = [0.5 * (xi[0] + start[0]), 0.5 * (xi[1] + start[1])];
    let limit = 3.0;
    let f_of = |xi: [f64; 2]| {
        let fp = face_point(x, xi);
        let r = sub(p, fp.x);
        0.5 * dot(r, r)
    };
    let mut converged = false;
    let mut iterations = 0;
    let mut f = f_of(xi);
    // scale for the stationarity test: face size squared
    let size2 = {
        let d = norm(sub(x[0], x[2])).max(norm(sub(x[1], x[nodes / 2 - 1])));
        (d * d).max(f64::MIN_POSITIVE)
    };
    while iterations < MAX_NEWTON {
        iterations += 1;
        let fp = face_point(x, xi);
        let r = sub(p, fp.x);
        let g = [dot(fp.t[0], r), dot(fp.t[1], r)]; // = −∇f
        let a = dot(fp.t[0], fp.t[0]);
        let b = dot(fp.t[0], fp.t[1]);
        let c = dot(fp.t[1], fp.t[1]);
        if (g[0] * g[0] + g[1] * g[1]).sqrt() <= 1e-15 * size2 {
            converged = true;
            break;
        }
        // exact Hessian, or Gauss–Newton where it is not positive definite
        let (h11, h12, h22) = {
            let e = (
                a - dot(fp.tt[0], r),
                b - dot(fp.tt[2], r),
                c - dot(fp.tt[1], r),
            );
            if e.0 > 0.0 && e.0 * e.2 - e.1 * e.1 > 1e-12 * (a * c).max(f64::MIN_POSITIVE) {
                e
            } else {
                (a, b, c)
            }
        };
        let det = h11 * h22 - h12 * h12;
        if !(det > 0.0) || !det.is_finite() {
            break;
        }
        let mut step = [
            (h22 * g[0] - h12 * g[1]) / det,
            (h11 * g[1] - h12 * g[0]) / det,
        ];
        let len = (step[0] * step[0] + step[1] * step[1]).sqrt();
        if len > 0.5 {
            step = [step[0] * 0.5 / len, step[1] * 0.5 / len];
        }
        let mut t = 1.0;
        let mut moved = 0.0;
        for _ in 0..12 {
            let trial = [
                (xi[0] + t * step[0]).clamp(-limit, limit),
                (xi[1] + t * step[1]).clamp(-limit, limit),
            ];
            let ft = f_of(trial);
            if ft <= f {
                moved = ((trial[0] - xi[0]).powi(2) + (trial[1] - xi[1]).powi(2)).sqrt();
                xi = trial;
                f = ft;
                break;
            }
            t *= 0.5;
        }
        if moved < 1e-13 {
            // no further progress: a minimum (or round-off level), or stuck
            // on the extended box far outside the face
            converged = t * len < 1e-10 || xi[0].abs() >= limit || xi[1].abs() >= limit;
            break;
        }
    }
    let (outside_by, clamped) = clamp_to_face(nodes, xi);
    let fp = face_point(x, clamped);
    let nv = cross(fp.t[0], fp.t[1]);
    let l = norm(nv);
    let normal = if l > 0.0 {
        [nv[0] / l, nv[1] / l, nv[2] / l]
    } else {
        [0.0; 3]
    };
    Projection {
        xi: clamped,
        point: fp.x,
        normal,
        gap: dot(normal, sub(p, fp.x)),
        outside_by,
        iterations,
        converged: converged && l > 0.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A curved 8-node face on the cylinder r = 10 (axis z), θ ∈ [−0.2, 0.2],
    /// z ∈ [0, 2]: the closest point of an outside point lies on the radius.
    fn cylinder_face() -> Vec<[f64; 3]> {
        let r = 10.0;
        let pt = |t: f64, z: f64| [r * t.cos(), r * t.sin(), z];
        vec![
            pt(-0.2, 0.0),
            pt(0.2, 0.0),
            pt(0.2, 2.0),
            pt(-0.2, 2.0),
            pt(0.0, 0.0),
            pt(0.2, 1.0),
            pt(0.0, 2.0),
            pt(-0.2, 1.0),
        ]
    }

    #[test]
    fn projects_onto_a_curved_quad() {
        let x = cylinder_face();
        for (t, z, d) in [(0.05, 0.7, 0.3), (-0.13, 1.9, -0.05), (0.19, 0.01, 2.0)] {
            let p = [(10.0 + d) * f64::cos(t), (10.0 + d) * f64::sin(t), z];
            let pr = project(&x, p);
            assert!(pr.converged && pr.outside_by == 0.0, "{pr:?}");
            // the quadratic arc through the nodes deviates from the circle
            // by up to ~5e-4 mm on this 0.4 rad face
            assert!((pr.gap - d).abs() < 1e-3, "gap {} vs {d}", pr.gap);
            assert!((pr.point[2] - z).abs() < 1e-9);
            // the normal is outward (+r) and orthogonal to both tangents
            let fp = face_point(&x, pr.xi);
            assert!(dot(fp.t[0], pr.normal).abs() < 1e-12);
            assert!(pr.normal[0] > 0.9);
            // the residual p − x is along the normal
            let r = sub(p, pr.point);
            assert!(dot(r, fp.t[0]).abs() < 1e-10 && dot(r, fp.t[1]).abs() < 1e-10);
        }
        // a point beyond the edge θ = 0.2: outside, clamped to the edge
        let p = [10.0 * f64::cos(0.35), 10.0 * f64::sin(0.35), 1.0];
        let pr = project(&x, p);
        assert!(
            pr.outside_by > 0.1 && (pr.xi[0] - 1.0).abs() < 1e-12,
            "{pr:?}"
        );
    }

    #[test]
    fn projects_onto_a_triangle() {
        // flat triangle in z = 1 with a bulged midside node (out of plane)
        let x = vec![
            [0.0, 0.0, 1.0],
            [2.0, 0.0, 1.0],
            [0.0, 2.0, 1.0],
            [1.0, 0.0, 1.0],
            [1.0, 1.0, 1.2],
            [0.0, 1.0, 1.0],
        ];
        let p = [0.3, 0.4, 3.0];
        let pr = project(&x, p);
        assert!(pr.converged && pr.outside_by == 0.0, "{pr:?}");
        let fp = face_point(&x, pr.xi);
        let r = sub(p, fp.x);
        assert!(dot(r, fp.t[0]).abs() < 1e-10 && dot(r, fp.t[1]).abs() < 1e-10);
        assert!(pr.gap > 1.5 && pr.normal[2] > 0.9);
        // outside across the hypotenuse
        let pr = project(&x, [1.6, 1.6, 1.0]);
        assert!(pr.outside_by > 0.0);
        assert!((pr.xi[0] + pr.xi[1] - 1.0).abs() < 1e-12);
    }
}
