//! Thermal strains of a linear static analysis: the initial strain
//! ε_th = α (T − T0) I of an isotropic material (CalculiX's `*EXPANSION`,
//! `*INITIAL CONDITIONS, TYPE=TEMPERATURE` and `*TEMPERATURE`).
//!
//! The nodal temperatures are carried to the integration points of the
//! element's stiffness rule as ccx does (ccx 2.20, its element routines):
//! * C3D20 (3×3×3 points): the quadratic temperature field of the 20 nodes
//!   is replaced by its L2 projection onto the trilinear functions of the
//!   element (a quadratic temperature would give a quadratic thermal strain
//!   that the element's linear strain field cannot follow). ccx tabulates
//!   the same weights in single precision (about 8 digits); flank computes
//!   them in double precision, which leaves a difference near 1e-8 of the
//!   nodal temperature spread in ε_th.
//! * C3D20R (2×2×2) and C3D15 (9 points): the element's own quadratic shape
//!   functions.
//!
//! With D the isotropic elasticity, the consistent load is
//! f_a = ∫ B_aᵀ D ε_th dV = ∫ (3λ + 2μ) ε_th ∇N_a dV, integrated with the
//! stiffness rule, and the stress is σ = D (ε − ε_th). A constant α makes
//! ε_th independent of ccx's reference temperature (ZERO=).

use std::sync::OnceLock;

use crate::error::FlankError;
use crate::fem::element::{gradients, ReferenceElement, HEX20_NODES};
use crate::fem::mesh::ElementKind;
use crate::fem::model::Model;

/// `weights[g][a]`: the temperature at integration point g of the
/// element's stiffness rule is Σ_a weights[g][a] T_a (see the module doc).
pub fn point_temperature_weights(kind: ElementKind) -> &'static Vec<Vec<f64>> {
    static HEX: OnceLock<Vec<Vec<f64>>> = OnceLock::new();
    static HEXR: OnceLock<Vec<Vec<f64>>> = OnceLock::new();
    static WEDGE: OnceLock<Vec<Vec<f64>>> = OnceLock::new();
    match kind {
        ElementKind::C3D20 => HEX.get_or_init(trilinear_projection),
        ElementKind::C3D20R => HEXR.get_or_init(|| ReferenceElement::get(kind).values.clone()),
        ElementKind::C3D15 => WEDGE.get_or_init(|| ReferenceElement::get(kind).values.clone()),
    }
}

/// Trilinear shape functions of the hexahedron's 8 corners at ξ.
fn trilinear(xi: [f64; 3]) -> [f64; 8] {
    let mut l = [0.0; 8];
    for (c, lc) in l.iter_mut().enumerate() {
        let p = HEX20_NODES[c];
        *lc = 0.125 * (1.0 + p[0] * xi[0]) * (1.0 + p[1] * xi[1]) * (1.0 + p[2] * xi[2]);
    }
    l
}

/// The C3D20 weights: P = L (M⁻¹ R) at the 27 points, M = ∫ L Lᵀ,
/// R = ∫ L Nᵀ over the reference cube (the 27-point rule integrates both
/// exactly: degree ≤ 4 per direction).
fn trilinear_projection() -> Vec<Vec<f64>> {
    let re = ReferenceElement::get(ElementKind::C3D20);
    let mut m = [[0.0; 8]; 8];
    let mut r = [[0.0; 20]; 8];
    for (p, n) in re.points.iter().zip(&re.values) {
        let l = trilinear(p.xi);
        for c in 0..8 {
            for d in 0..8 {
                m[c][d] += p.weight * l[c] * l[d];
            }
            for a in 0..20 {
                r[c][a] += p.weight * l[c] * n[a];
            }
        }
    }
    // M is symmetric positive definite: Gauss elimination without pivoting,
    // applied to the 20 right-hand sides at once
    for k in 0..8 {
        for i in k + 1..8 {
            let f = m[i][k] / m[k][k];
            for j in k..8 {
                m[i][j] -= f * m[k][j];
            }
            for a in 0..20 {
                r[i][a] -= f * r[k][a];
            }
        }
    }
    for k in (0..8).rev() {
        for a in 0..20 {
            let mut s = r[k][a];
            for j in k + 1..8 {
                s -= m[k][j] * r[j][a];
            }
            r[k][a] = s / m[k][k];
        }
    }
    re.points
        .iter()
        .map(|p| {
            let l = trilinear(p.xi);
            (0..20)
                .map(|a| (0..8).map(|c| l[c] * r[c][a]).sum())
                .collect()
        })
        .collect()
}

/// Whether the model has a thermal load on at least one element: nodal
/// temperatures and a material with an expansion coefficient.
pub fn has_thermal_strain(model: &Model) -> bool {
    model.temperatures.is_some()
        && model.element_material.iter().any(|&m| {
            model
                .materials
                .get(m)
                .is_some_and(|m| m.expansion.is_some())
        })
}

/// The scalar thermal strain α (T − T0) at each integration point of element
/// `e`, or `None` if the element has none (no temperatures in the model, or
/// no expansion coefficient in its material).
pub fn element_thermal_strains(model: &Model, e: usize) -> Option<Vec<f64>> {
    let t = model.temperatures.as_ref()?;
    let alpha = model.materials[model.element_material[e]].expansion?;
    let el = &model.mesh.elements[e];
    let w = point_temperature_weights(el.kind);
    Some(
        w.iter()
            .map(|row| {
                let (mut t1, mut t0) = (0.0, 0.0);
                for (wa, &n) in row.iter().zip(&el.nodes) {
                    t1 += wa * t.current[n];
                    t0 += wa * t.initial[n];
                }
                alpha * (t1 - t0)
            })
            .collect(),
    )
}

/// Checks the temperature fields against the mesh: one finite value per node.
pub fn validate_temperatures(model: &Model) -> Result<(), FlankError> {
    let Some(t) = &model.temperatures else {
        return Ok(());
    };
    let nn = model.mesh.node_count();
    if t.initial.len() != nn || t.current.len() != nn {
        return Err(FlankError::Model(format!(
            "{} nodes but {} initial and {} current temperatures",
            nn,
            t.initial.len(),
            t.current.len()
        )));
    }
    if let Some(i) = (0..nn).find(|&i| !(t.initial[i].is_finite() && t.current[i].is_finite())) {
        return Err(FlankError::Model(format!(
            "node {} has a non-finite temperature",
            model.mesh.node_labels[i]
        )));
    }
    Ok(())
}

/// Consistent nodal loads f = Σ_e ∫ Bᵀ D ε_th dV of the thermal strains
/// (node-major DOFs; all zero without thermal strains).
pub fn thermal_load_vector(model: &Model) -> Result<Vec<f64>, FlankError> {
    validate_temperatures(model)?;
    let mut f = vec![0.0; 3 * model.mesh.node_count()];
    if !has_thermal_strain(model) {
        return Ok(f);
    }
    let mut grads = Vec::new();
    let mut dvol = Vec::new();
    for (e, el) in model.mesh.elements.iter().enumerate() {
        let Some(eth) = element_thermal_strains(model, e) else {
            continue;
        };
        let mat = &model.materials[model.element_material[e]];
        let (lambda, mu) = mat.lame();
        let bulk3 = 3.0 * lambda + 2.0 * mu;
        let re = ReferenceElement::get(el.kind);
        let x = model.mesh.element_coords(e);
        gradients(re, &x, &mut grads, &mut dvol).map_err(|j| j.into_error(el.label, el.kind))?;
        let n = el.nodes.len();
        for (g, (&dv, &eps)) in dvol.iter().zip(&eth).enumerate() {
            let s = bulk3 * eps * dv;
            for (a, &node) in el.nodes.iter().enumerate() {
                let ga = grads[g * n + a];
                for i in 0..3 {
                    f[3 * node + i] += s * ga[i];
                }
            }
        }
    }
    Ok(f)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fem::element::WEDGE15_NODES;

    /// Every kind's weights sum to one (a uniform temperature is kept) and
    /// reproduce a linear temperature field exactly; the C3D20 projection
    /// of a quadratic field is its trilinear L2 projection, so it differs
    /// from the quadratic interpolation (where C3D20R keeps it).
    #[test]
    fn weights_keep_uniform_and_linear_fields() {
        let lin = |p: [f64; 3]| 3.0 + 0.7 * p[0] - 1.1 * p[1] + 0.4 * p[2];
        for kind in [ElementKind::C3D20, ElementKind::C3D20R, ElementKind::C3D15] {
            let nodes: &[[f64; 3]] = if kind == ElementKind::C3D15 {
                &WEDGE15_NODES
            } else {
                &HEX20_NODES
            };
            let re = ReferenceElement::get(kind);
            let w = point_temperature_weights(kind);
            assert_eq!(w.len(), re.points.len());
            for (row, p) in w.iter().zip(&re.points) {
                let s: f64 = row.iter().sum();
                assert!((s - 1.0).abs() < 1e-14, "{kind:?}: Σw = {s}");
                let t: f64 = row.iter().zip(nodes).map(|(w, x)| w * lin(*x)).sum();
                assert!((t - lin(p.xi)).abs() < 1e-13, "{kind:?}: {t}");
            }
        }
        // T = ξ²: the projection onto {1, ξ, η, ζ, ξη, ...} is its mean 1/3
        // (ξ² is orthogonal to the linear part), the interpolation is ξ²
        let q = |p: [f64; 3]| p[0] * p[0];
        let w = point_temperature_weights(ElementKind::C3D20);
        for (row, p) in w
            .iter()
            .zip(&ReferenceElement::get(ElementKind::C3D20).points)
        {
            let t: f64 = row.iter().zip(&HEX20_NODES).map(|(w, x)| w * q(*x)).sum();
            assert!((t - 1.0 / 3.0).abs() < 1e-13, "{t} at {:?}", p.xi);
        }
        let w = point_temperature_weights(ElementKind::C3D20R);
        for (row, p) in w
            .iter()
            .zip(&ReferenceElement::get(ElementKind::C3D20R).points)
        {
            let t: f64 = row.iter().zip(&HEX20_NODES).map(|(w, x)| w * q(*x)).sum();
            assert!((t - q(p.xi)).abs() < 1e-13, "{t} at {:?}", p.xi);
        }
    }

    /// A uniform ε_th on one element gives f_a = (3λ+2μ) ε_th ∫ ∇N_a dV,
    /// whose sum is zero (Σ ∇N_a = 0) and whose first moment Σ_a x_a f_a,i
    /// is (3λ+2μ) ε_th V in every direction (∫ ∇(x_i) dV = V e_i).
    #[test]
    fn uniform_thermal_load_is_self_equilibrated() {
        use crate::fem::material::Material;
        use crate::fem::mesh::Mesh;
        use crate::fem::model::Temperatures;
        for (kind, nodes, vol) in [
            (ElementKind::C3D20, &HEX20_NODES[..], 8.0 * 0.5 * 2.0),
            (ElementKind::C3D20R, &HEX20_NODES[..], 8.0 * 0.5 * 2.0),
            (
                ElementKind::C3D15,
                &WEDGE15_NODES[..],
                0.5 * 2.0 * 0.5 * 2.0,
            ),
        ] {
            let mut mesh = Mesh::new();
            for (i, p) in nodes.iter().enumerate() {
                mesh.add_node(i as u64 + 1, [p[0], 0.5 * p[1], 2.0 * p[2]])
                    .unwrap();
            }
            mesh.add_element(1, kind, (0..nodes.len()).collect())
                .unwrap();
            let mut mat = Material::new("m", 210e3, 0.3).unwrap();
            mat.expansion = Some(1.2e-5);
            let model = Model {
                mesh,
                materials: vec![mat.clone()],
                element_material: vec![0],
                temperatures: Some(Temperatures {
                    initial: vec![20.0; nodes.len()],
                    current: vec![120.0; nodes.len()],
                }),
                ..Default::default()
            };
            let f = thermal_load_vector(&model).unwrap();
            let (l, m) = mat.lame();
            let want = (3.0 * l + 2.0 * m) * 1.2e-5 * 100.0 * vol;
            for i in 0..3 {
                let s: f64 = f.iter().skip(i).step_by(3).sum();
                assert!(s.abs() < 1e-9 * want, "{kind:?}: Σf_{i} = {s}");
                let mom: f64 = (0..nodes.len())
                    .map(|a| model.mesh.coords[a][i] * f[3 * a + i])
                    .sum();
                assert!(
                    (mom - want).abs() < 1e-12 * want,
                    "{kind:?}: moment {mom} vs {want}"
                );
            }
            // no expansion coefficient: no load
            let mut cold = model.clone();
            cold.materials[0].expansion = None;
            assert!(thermal_load_vector(&cold)
                .unwrap()
                .iter()
                .all(|&v| v == 0.0));
        }
    }
}
