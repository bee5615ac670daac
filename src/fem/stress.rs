//! Stress recovery and internal forces.
//!
//! Stresses are computed at the integration points and extrapolated to the
//! element's nodes with the Lagrange interpolant through the integration
//! points (triquadratic through 3×3×3, trilinear through 2×2×2, linear-in-
//! triangle × quadratic-in-ζ through the wedge's 9 points), then averaged over
//! the elements meeting at a node. The same pass integrates the internal
//! forces f_int = Σ_e ∫ Bᵀσ dV, from which reactions follow as f_int − f_ext.
//! With thermal strains the stress is σ = D (ε − ε_th) (as ccx prints it), so
//! f_int is K u minus the thermal load and the reactions stay f_int − f_ext
//! with f_ext the mechanical loads.

use std::sync::OnceLock;

use rayon::prelude::*;

use crate::error::FlankError;
use crate::fem::element::{gradients, inv3, ReferenceElement, HEX20_NODES, WEDGE15_NODES};
use crate::fem::mesh::ElementKind;
use crate::fem::model::Model;
use crate::fem::thermal::element_thermal_strains;

/// Nodal results of the stress recovery.
#[derive(Clone, Debug)]
pub struct Recovery {
    /// Averaged nodal stress (xx, yy, zz, xy, yz, xz), MPa; zero at unused nodes.
    pub stress: Vec<[f64; 6]>,
    /// Von Mises stress of the averaged nodal stress.
    pub von_mises: Vec<f64>,
    /// Internal force vector f_int (node-major DOFs), N.
    pub internal_force: Vec<f64>,
}

/// 1D Lagrange basis through abscissae `pts`, evaluated at `x`.
fn lagrange(pts: &[f64], x: f64) -> Vec<f64> {
    (0..pts.len())
        .map(|i| {
            pts.iter()
                .enumerate()
                .filter(|&(j, _)| j != i)
                .map(|(_, &pj)| (x - pj) / (pts[i] - pj))
                .product()
        })
        .collect()
}

/// Extrapolation matrix E (nodes × points) of an element kind: `σ_a = Σ_g E[a][g] σ_g`.
pub fn extrapolation(kind: ElementKind) -> &'static Vec<Vec<f64>> {
    static HEX: OnceLock<Vec<Vec<f64>>> = OnceLock::new();
    static HEXR: OnceLock<Vec<Vec<f64>>> = OnceLock::new();
    static WEDGE: OnceLock<Vec<Vec<f64>>> = OnceLock::new();
    let build = move || -> Vec<Vec<f64>> {
        match kind {
            ElementKind::C3D20 | ElementKind::C3D20R => {
                let n1 = if kind == ElementKind::C3D20 { 3 } else { 2 };
                let g: Vec<f64> = crate::fem::quadrature::gauss_1d(n1)
                    .iter()
                    .map(|p| p.0)
                    .collect();
                HEX20_NODES
                    .iter()
                    .map(|p| {
                        let (lx, ly, lz) =
                            (lagrange(&g, p[0]), lagrange(&g, p[1]), lagrange(&g, p[2]));
                        let mut row = Vec::with_capacity(n1 * n1 * n1);
                        // point order: ξ fastest, then η, then ζ (quadrature::hex_rule)
                        for k in 0..n1 {
                            for j in 0..n1 {
                                for i in 0..n1 {
                                    row.push(lx[i] * ly[j] * lz[k]);
                                }
                            }
                        }
                        row
                    })
                    .collect()
            }
            ElementKind::C3D15 => {
                let g: Vec<f64> = crate::fem::quadrature::gauss_1d(3)
                    .iter()
                    .map(|p| p.0)
                    .collect();
                let tp = crate::fem::quadrature::TRIANGLE_3;
                // linear interpolation in the triangle of the 3 points: solve for barycentric weights
                let m = [
                    [1.0, 1.0, 1.0],
                    [tp[0].0[0], tp[1].0[0], tp[2].0[0]],
                    [tp[0].0[1], tp[1].0[1], tp[2].0[1]],
                ];
                let det = crate::fem::element::det3(&m);
                let mi = inv3(&m, det);
                WEDGE15_NODES
                    .iter()
                    .map(|p| {
                        let rhs = [1.0, p[0], p[1]];
                        let w: Vec<f64> = (0..3)
                            .map(|i| (0..3).map(|k| mi[i][k] * rhs[k]).sum())
                            .collect();
                        let lz = lagrange(&g, p[2]);
                        let mut row = Vec::with_capacity(9);
                        // point order: triangle point fastest, then ζ (quadrature::wedge_rule)
                        for lzk in &lz {
                            for wi in &w {
                                row.push(wi * lzk);
                            }
                        }
                        row
                    })
                    .collect()
            }
        }
    };
    match kind {
        ElementKind::C3D20 => HEX.get_or_init(build),
        ElementKind::C3D20R => HEXR.get_or_init(build),
        ElementKind::C3D15 => WEDGE.get_or_init(build),
    }
}

/// Per-element results: extrapolated nodal stresses and internal forces.
struct ElementResult {
    stress: Vec<[f64; 6]>,
    force: Vec<[f64; 3]>,
}

/// Stresses at the integration points of one element, with the points'
/// volume weights (det J · w) and the shape-function gradients (point-major).
pub struct PointStresses {
    pub stress: Vec<[f64; 6]>,
    pub dvol: Vec<f64>,
    pub grads: Vec<[f64; 3]>,
}

/// Stresses σ = D (ε − ε_th) at the integration points of element `e` for
/// the full displacement `u` (ε_th: [`crate::fem::thermal`], zero without
/// temperatures).
pub fn element_point_stresses(
    model: &Model,
    e: usize,
    u: &[f64],
) -> Result<PointStresses, FlankError> {
    let el = &model.mesh.elements[e];
    let re = ReferenceElement::get(el.kind);
    let x = model.mesh.element_coords(e);
    let mut grads = Vec::new();
    let mut dvol = Vec::new();
    gradients(re, &x, &mut grads, &mut dvol).map_err(|j| j.into_error(el.label, el.kind))?;
    let mat = &model.materials[model.element_material[e]];
    let n = el.nodes.len();
    // σ = D (ε − ε_th): the isotropic thermal strain ε_th I takes
    // (3λ + 2μ) ε_th off the normal stresses
    let thermal = element_thermal_strains(model, e);
    let (lambda, mu) = mat.lame();
    let sig = (0..dvol.len())
        .map(|g| {
            let mut h = [[0.0; 3]; 3];
            for (a, &node) in el.nodes.iter().enumerate() {
                let ga = grads[g * n + a];
                for i in 0..3 {
                    let ui = u[3 * node + i];
                    for j in 0..3 {
                        h[i][j] += ui * ga[j];
                    }
                }
            }
            let mut s = mat.stress_from_gradient(&h);
            if let Some(eth) = &thermal {
                let st = (3.0 * lambda + 2.0 * mu) * eth[g];
                for v in s.iter_mut().take(3) {
                    *v -= st;
                }
            }
            s
        })
        .collect();
    Ok(PointStresses {
        stress: sig,
        dvol,
        grads,
    })
}

fn element_result(model: &Model, e: usize, u: &[f64]) -> Result<ElementResult, FlankError> {
    let el = &model.mesh.elements[e];
    let n = el.nodes.len();
    let PointStresses {
        stress: sig,
        dvol,
        grads,
    } = element_point_stresses(model, e, u)?;
    let mut force = vec![[0.0; 3]; n];
    for (g, s) in sig.iter().enumerate() {
        let t = [[s[0], s[3], s[5]], [s[3], s[1], s[4]], [s[5], s[4], s[2]]];
        for (a, f) in force.iter_mut().enumerate() {
            let ga = grads[g * n + a];
            for i in 0..3 {
                f[i] += dvol[g] * (t[i][0] * ga[0] + t[i][1] * ga[1] + t[i][2] * ga[2]);
            }
        }
    }
    let ex = extrapolation(el.kind);
    let stress = ex
        .iter()
        .map(|row| {
            let mut s = [0.0; 6];
            for (w, sg) in row.iter().zip(&sig) {
                for k in 0..6 {
                    s[k] += w * sg[k];
                }
            }
            s
        })
        .collect();
    Ok(ElementResult { stress, force })
}

/// Recovers averaged nodal stresses and the internal force vector.
pub fn recover(model: &Model, u: &[f64]) -> Result<Recovery, FlankError> {
    let nn = model.mesh.node_count();
    let results: Vec<ElementResult> = (0..model.mesh.elements.len())
        .into_par_iter()
        .map(|e| element_result(model, e, u))
        .collect::<Result<_, _>>()?;
    let mut stress = vec![[0.0; 6]; nn];
    let mut count = vec![0u32; nn];
    let mut internal_force = vec![0.0; 3 * nn];
    for (el, r) in model.mesh.elements.iter().zip(&results) {
        for (a, &node) in el.nodes.iter().enumerate() {
            for k in 0..6 {
                stress[node][k] += r.stress[a][k];
            }
            count[node] += 1;
            for i in 0..3 {
                internal_force[3 * node + i] += r.force[a][i];
            }
        }
    }
    for (s, &c) in stress.iter_mut().zip(&count) {
        if c > 0 {
            for v in s.iter_mut() {
                *v /= c as f64;
            }
        }
    }
    let von_mises = stress.iter().map(crate::fem::material::von_mises).collect();
    Ok(Recovery {
        stress,
        von_mises,
        internal_force,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Extrapolation reproduces polynomials the point set can represent.
    #[test]
    fn extrapolation_reproduces_linear_fields() {
        for kind in [ElementKind::C3D20, ElementKind::C3D20R, ElementKind::C3D15] {
            let re = ReferenceElement::get(kind);
            let f = |p: [f64; 3]| 1.0 + 2.0 * p[0] - 0.5 * p[1] + 0.25 * p[2];
            let vals: Vec<f64> = re.points.iter().map(|q| f(q.xi)).collect();
            let nodes: &[[f64; 3]] = if kind == ElementKind::C3D15 {
                &WEDGE15_NODES
            } else {
                &HEX20_NODES
            };
            for (row, p) in extrapolation(kind).iter().zip(nodes) {
                let v: f64 = row.iter().zip(&vals).map(|(w, v)| w * v).sum();
                assert!((v - f(*p)).abs() < 1e-12, "{kind:?}");
            }
        }
    }
}
