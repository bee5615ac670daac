//! Load vectors: nodal forces and consistent nodal loads of face pressures
//! and tractions (uniform, or a field t(x) evaluated at the face rule's points).
//!
//! Pressure p on a face gives f_a = −∫ p N_a n dA, with n dA = ∂x/∂ξ × ∂x/∂η
//! (outward for CalculiX's face node order). The face rules are CalculiX's
//! (`e_c3d.f`): 3×3 Gauss on C3D20 faces, 2×2 on C3D20R faces and on the
//! quadrilateral faces of C3D15, the 3-point rule on its triangular faces.
//! On a curved face the rule shows at the 1e-6 level, so matching it keeps
//! flank and CalculiX equal to round-off.
//!
//! Body loads (`*DLOAD` GRAV, CENTRIF) give f_a = ∫ N_a ρ b(x) dV with the
//! element's own volume rule, the one of its stiffness (as ccx's `e_c3d.f`:
//! 3×3×3 Gauss on C3D20, 2×2×2 on C3D20R, 9 points on C3D15); b is evaluated
//! at the undeformed position of the integration point.

use crate::error::FlankError;
use crate::fem::element::{
    face_nodes, gradients, quad8_shape, tri6_shape, JacobianError, ReferenceElement,
};
use crate::fem::mesh::ElementKind;
use crate::fem::model::{BodyForce, Model};
use crate::fem::quadrature::{quad_rule, TRIANGLE_3};

/// Calls `f(N, n dA · w)` at every point of CalculiX's rule for this face:
/// the face shape functions and the (unnormalised, outward) area vector
/// ∂x/∂ξ × ∂x/∂η times the weight.
fn for_each_face_point(
    kind: ElementKind,
    x: &[[f64; 3]],
    nodes: &[usize],
    mut f: impl FnMut(&[f64], [f64; 3]),
) {
    let mut point = |n: &[f64], d: &[[f64; 2]], w: f64| {
        let mut t1 = [0.0; 3];
        let mut t2 = [0.0; 3];
        for (k, &a) in nodes.iter().enumerate() {
            for i in 0..3 {
                t1[i] += x[a][i] * d[k][0];
                t2[i] += x[a][i] * d[k][1];
            }
        }
        let nda = [
            (t1[1] * t2[2] - t1[2] * t2[1]) * w,
            (t1[2] * t2[0] - t1[0] * t2[2]) * w,
            (t1[0] * t2[1] - t1[1] * t2[0]) * w,
        ];
        f(n, nda);
    };
    if nodes.len() == 8 {
        let order = if kind == ElementKind::C3D20 { 3 } else { 2 };
        for (xi, w) in quad_rule(order) {
            let (n, d) = quad8_shape(xi);
            point(&n, &d, w);
        }
    } else {
        for &(xi, w) in &TRIANGLE_3 {
            let (n, d) = tri6_shape(xi);
            point(&n, &d, w);
        }
    }
}

/// Consistent nodal forces of a uniform pressure `p` on face `face` (1-based) of
/// an element with node coordinates `x`; returns (local node, force) pairs.
pub fn pressure_face_load(
    kind: ElementKind,
    x: &[[f64; 3]],
    face: usize,
    p: f64,
) -> Option<Vec<(usize, [f64; 3])>> {
    let nodes = face_nodes(kind, face)?;
    let mut out: Vec<(usize, [f64; 3])> = nodes.iter().map(|&a| (a, [0.0; 3])).collect();
    for_each_face_point(kind, x, nodes, |n, nda| {
        for (k, o) in out.iter_mut().enumerate() {
            for i in 0..3 {
                o.1[i] -= n[k] * p * nda[i];
            }
        }
    });
    Some(out)
}

/// Consistent nodal forces f_a = ∫ N_a t dA of a uniform traction `t` (MPa,
/// global components) on face `face` (1-based), same face rules as pressures.
pub fn traction_face_load(
    kind: ElementKind,
    x: &[[f64; 3]],
    face: usize,
    t: [f64; 3],
) -> Option<Vec<(usize, [f64; 3])>> {
    let nodes = face_nodes(kind, face)?;
    let mut out: Vec<(usize, [f64; 3])> = nodes.iter().map(|&a| (a, [0.0; 3])).collect();
    for_each_face_point(kind, x, nodes, |n, nda| {
        let da = (nda[0] * nda[0] + nda[1] * nda[1] + nda[2] * nda[2]).sqrt();
        for (k, o) in out.iter_mut().enumerate() {
            for i in 0..3 {
                o.1[i] += n[k] * da * t[i];
            }
        }
    });
    Some(out)
}

/// Consistent nodal forces f_a = ∫ N_a t(x) dA of a traction field `t`
/// (MPa, global components, a function of the point x on the face) on face
/// `face` (1-based), evaluated at the points of the same face rules as
/// pressures (3×3 Gauss on C3D20 faces: a smooth t(x) is integrated to the
/// rule's degree; a kink such as the edge of a Hertz pressure belongs on a
/// face boundary).
pub fn traction_field_face_load(
    kind: ElementKind,
    x: &[[f64; 3]],
    face: usize,
    t: impl Fn([f64; 3]) -> [f64; 3],
) -> Option<Vec<(usize, [f64; 3])>> {
    let nodes = face_nodes(kind, face)?;
    let mut out: Vec<(usize, [f64; 3])> = nodes.iter().map(|&a| (a, [0.0; 3])).collect();
    for_each_face_point(kind, x, nodes, |n, nda| {
        let da = (nda[0] * nda[0] + nda[1] * nda[1] + nda[2] * nda[2]).sqrt();
        let mut p = [0.0; 3];
        for (k, &a) in nodes.iter().enumerate() {
            for i in 0..3 {
                p[i] += n[k] * x[a][i];
            }
        }
        let tp = t(p);
        for (k, o) in out.iter_mut().enumerate() {
            for i in 0..3 {
                o.1[i] += n[k] * da * tp[i];
            }
        }
    });
    Some(out)
}

/// Consistent nodal forces f_a = ∫ N_a ρ b(x) dV (one per element node) of a
/// body force per unit mass `b` on an element of density `rho` with node
/// coordinates `x`, integrated with the element's stiffness rule.
pub fn body_force_load(
    kind: ElementKind,
    x: &[[f64; 3]],
    rho: f64,
    b: &BodyForce,
) -> Result<Vec<[f64; 3]>, JacobianError> {
    let re = ReferenceElement::get(kind);
    let mut grads = Vec::new();
    let mut dvol = Vec::new();
    gradients(re, x, &mut grads, &mut dvol)?;
    let mut out = vec![[0.0; 3]; re.nodes];
    for (n, &dv) in re.values.iter().zip(&dvol) {
        let mut p = [0.0; 3];
        for (na, xa) in n.iter().zip(x) {
            for i in 0..3 {
                p[i] += na * xa[i];
            }
        }
        let bp = b.at(p);
        for (o, na) in out.iter_mut().zip(n) {
            let w = na * rho * dv;
            for i in 0..3 {
                o[i] += w * bp[i];
            }
        }
    }
    Ok(out)
}

/// Full load vector (node-major DOFs) of the model's nodal forces, pressures
/// and body loads.
pub fn load_vector(model: &Model) -> Result<Vec<f64>, FlankError> {
    let nn = model.mesh.node_count();
    let mut f = vec![0.0; 3 * nn];
    for load in &model.forces {
        if load.node >= nn || load.component > 2 || !load.value.is_finite() {
            return Err(FlankError::Model(format!(
                "invalid nodal force (node index {}, component {}, value {})",
                load.node, load.component, load.value
            )));
        }
        f[3 * load.node + load.component] += load.value;
    }
    for pr in &model.pressures {
        let el = model.mesh.elements.get(pr.element).ok_or_else(|| {
            FlankError::Model(format!(
                "pressure on element index {} beyond the mesh",
                pr.element
            ))
        })?;
        if !pr.value.is_finite() {
            return Err(FlankError::Model(format!(
                "pressure on element {} is not finite",
                el.label
            )));
        }
        let x = model.mesh.element_coords(pr.element);
        let loads = pressure_face_load(el.kind, &x, pr.face, pr.value).ok_or_else(|| {
            FlankError::Model(format!(
                "element {} ({}) has no face {}",
                el.label,
                el.kind.name(),
                pr.face
            ))
        })?;
        for (a, v) in loads {
            let n = el.nodes[a];
            for i in 0..3 {
                f[3 * n + i] += v[i];
            }
        }
    }
    for bl in &model.body_loads {
        let el = model.mesh.elements.get(bl.element).ok_or_else(|| {
            FlankError::Model(format!(
                "body load on element index {} beyond the mesh",
                bl.element
            ))
        })?;
        let mat = model
            .element_material
            .get(bl.element)
            .and_then(|&m| model.materials.get(m))
            .ok_or_else(|| FlankError::Model(format!("element {} has no material", el.label)))?;
        let rho = mat.density.ok_or_else(|| {
            FlankError::Model(format!(
                "body load on element {}: material '{}' has no density",
                el.label, mat.name
            ))
        })?;
        let finite = match &bl.force {
            BodyForce::Gravity { acceleration } => acceleration.iter().all(|v| v.is_finite()),
            BodyForce::Centrifugal {
                omega_squared,
                point,
                axis,
            } => {
                omega_squared.is_finite()
                    && point.iter().chain(axis).all(|v| v.is_finite())
                    && (axis.iter().map(|a| a * a).sum::<f64>() - 1.0).abs() < 1e-12
            }
        };
        if !finite {
            return Err(FlankError::Model(format!(
                "body load on element {} is not finite (or its axis is not a unit vector)",
                el.label
            )));
        }
        let x = model.mesh.element_coords(bl.element);
        let loads = body_force_load(el.kind, &x, rho, &bl.force)
            .map_err(|e| e.into_error(el.label, el.kind))?;
        for (&n, v) in el.nodes.iter().zip(loads) {
            for i in 0..3 {
                f[3 * n + i] += v[i];
            }
        }
    }
    Ok(f)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fem::element::{HEX20_NODES, WEDGE15_NODES};

    /// Gravity on an undistorted box element (2 × 2 × 1 hex, unit wedge) sums to ρ g V for
    /// every element type (Σ N_a = 1); the centrifugal load about the z axis
    /// of the box [1, 3] × [−1, 1] × [0, 1] sums to ρ ω² ∫ x dV = ρ ω² · 2 · 4
    /// in x, 0 in y and z.
    #[test]
    fn body_load_resultants() {
        for (kind, nodes) in [
            (ElementKind::C3D20, &HEX20_NODES[..]),
            (ElementKind::C3D20R, &HEX20_NODES[..]),
            (ElementKind::C3D15, &WEDGE15_NODES[..]),
        ] {
            let x: Vec<[f64; 3]> = nodes
                .iter()
                .map(|p| [2.0 + p[0], p[1], 0.5 * (p[2] + 1.0)])
                .collect();
            // mapped volumes: hex 2 × 2 × 1, wedge ½ × 1
            let vol = if kind == ElementKind::C3D15 { 0.5 } else { 4.0 };
            let g = BodyForce::Gravity {
                acceleration: [0.0, 0.0, -9810.0],
            };
            let l = body_force_load(kind, &x, 7.85e-9, &g).unwrap();
            let fz: f64 = l.iter().map(|f| f[2]).sum();
            let want = -7.85e-9 * 9810.0 * vol;
            assert!(
                (fz - want).abs() < 1e-14 * want.abs(),
                "{kind:?}: {fz} vs {want}"
            );
            let c = BodyForce::Centrifugal {
                omega_squared: 1e6,
                point: [0.0, 0.0, 5.0],
                axis: [0.0, 0.0, 1.0],
            };
            let l = body_force_load(kind, &x, 1.0, &c).unwrap();
            let s: Vec<f64> = (0..3).map(|i| l.iter().map(|f| f[i]).sum()).collect();
            // ∫ x dV over the element
            let mx = if kind == ElementKind::C3D15 {
                // wedge: triangle (0,0),(1,0),(0,1) shifted by 2 in x, height 1
                0.5 * (2.0 + 1.0 / 3.0)
            } else {
                2.0 * 4.0
            };
            assert!(
                (s[0] - 1e6 * mx).abs() < 1e-12 * 1e6 * mx,
                "{kind:?}: {s:?}"
            );
            let my = if kind == ElementKind::C3D15 {
                0.5 / 3.0 * 1e6
            } else {
                0.0
            };
            assert!((s[1] - my).abs() < 1e-6, "{kind:?}: {s:?}");
            assert!(s[2].abs() < 1e-6, "{kind:?}: {s:?}");
        }
    }

    /// A uniform pressure on a flat face sums to p·A along the inward normal.
    #[test]
    fn resultant_equals_pressure_times_area() {
        let x: Vec<[f64; 3]> = HEX20_NODES
            .iter()
            .map(|p| [2.0 * p[0], p[1], 0.5 * p[2]])
            .collect();
        // face 2 is ζ = +1 (z = 0.5), area 4 × 2 = 8; inward normal −z
        for kind in [ElementKind::C3D20, ElementKind::C3D20R] {
            let l = pressure_face_load(kind, &x, 2, 3.0).unwrap();
            let fz: f64 = l.iter().map(|(_, f)| f[2]).sum();
            assert!((fz + 24.0).abs() < 1e-12, "{fz}");
        }
        // wedge face 1 (bottom triangle, area 1/2, outward −z): force +z
        let l = pressure_face_load(ElementKind::C3D15, &WEDGE15_NODES, 1, 2.0).unwrap();
        let fz: f64 = l.iter().map(|(_, f)| f[2]).sum();
        assert!((fz - 1.0).abs() < 1e-12, "{fz}");
        // wedge face 3 (y = 0, area 1 × 2, outward −y): force +y
        let l = pressure_face_load(ElementKind::C3D15, &WEDGE15_NODES, 3, 1.0).unwrap();
        let fy: f64 = l.iter().map(|(_, f)| f[1]).sum();
        assert!((fy - 2.0).abs() < 1e-12, "{fy}");
        assert!(pressure_face_load(ElementKind::C3D15, &WEDGE15_NODES, 6, 1.0).is_none());
    }

    /// A constant field gives the uniform traction's loads; a linear field
    /// t_y = c·x on the face z = 0.5 of a 4 × 2 × 1 hex sums to ∫ t dA = 0
    /// and its moment Σ x_a f_a = c ∫ x² dA = c · 2 · 2 · 2³/3 (exact: the
    /// rule integrates the cubic N_a x exactly).
    #[test]
    fn traction_field_resultant_and_moment() {
        let x: Vec<[f64; 3]> = HEX20_NODES
            .iter()
            .map(|p| [2.0 * p[0], p[1], 0.5 * p[2]])
            .collect();
        let t = [0.3, -1.2, 2.0];
        let a = traction_face_load(ElementKind::C3D20, &x, 2, t).unwrap();
        let b = traction_field_face_load(ElementKind::C3D20, &x, 2, |_| t).unwrap();
        for ((na, fa), (nb, fb)) in a.iter().zip(&b) {
            assert_eq!(na, nb);
            for i in 0..3 {
                assert!((fa[i] - fb[i]).abs() < 1e-14, "{fa:?} vs {fb:?}");
            }
        }
        let c = 0.7;
        let l =
            traction_field_face_load(ElementKind::C3D20, &x, 2, |p| [0.0, c * p[0], 0.0]).unwrap();
        let fy: f64 = l.iter().map(|(_, f)| f[1]).sum();
        let m: f64 = l.iter().map(|(a, f)| x[*a][0] * f[1]).sum();
        assert!(fy.abs() < 1e-14, "{fy}");
        assert!((m - c * 2.0 * 2.0 * 8.0 / 3.0).abs() < 1e-13, "{m}");
        assert!(traction_field_face_load(ElementKind::C3D20, &x, 7, |_| t).is_none());
    }
}
