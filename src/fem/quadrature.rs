//! Quadrature rules, as CalculiX uses them (see DESIGN.md, "Quadrature").
//!
//! Volume rules are on the reference element: hexahedron [-1,1]³; wedge
//! {r,s ≥ 0, r+s ≤ 1} × [-1,1]. Face rules: quadrilateral [-1,1]², triangle
//! {r,s ≥ 0, r+s ≤ 1}.

/// A quadrature point: reference coordinates and weight.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuadraturePoint {
    pub xi: [f64; 3],
    pub weight: f64,
}

/// 1D Gauss–Legendre points and weights with `n` = 1, 2 or 3 points.
pub fn gauss_1d(n: usize) -> &'static [(f64, f64)] {
    const G1: [(f64, f64); 1] = [(0.0, 2.0)];
    // ±1/√3
    const G2: [(f64, f64); 2] = [
        (-0.577_350_269_189_625_8, 1.0),
        (0.577_350_269_189_625_8, 1.0),
    ];
    // ±√(3/5), 0
    const G3: [(f64, f64); 3] = [
        (-0.774_596_669_241_483_4, 5.0 / 9.0),
        (0.0, 8.0 / 9.0),
        (0.774_596_669_241_483_4, 5.0 / 9.0),
    ];
    match n {
        1 => &G1,
        2 => &G2,
        3 => &G3,
        _ => panic!("gauss_1d: unsupported point count {n}"),
    }
}

/// Tensor-product Gauss rule on the hexahedron with `n`³ points (ξ fastest).
pub fn hex_rule(n: usize) -> Vec<QuadraturePoint> {
    let g = gauss_1d(n);
    let mut pts = Vec::with_capacity(n * n * n);
    for &(z, wz) in g {
        for &(y, wy) in g {
            for &(x, wx) in g {
                pts.push(QuadraturePoint {
                    xi: [x, y, z],
                    weight: wx * wy * wz,
                });
            }
        }
    }
    pts
}

/// The 3-point triangle rule (1/6,1/6), (2/3,1/6), (1/6,2/3), weights 1/6
/// (degree 2), used by CalculiX for C3D15 and 6-node faces.
pub const TRIANGLE_3: [([f64; 2], f64); 3] = [
    ([1.0 / 6.0, 1.0 / 6.0], 1.0 / 6.0),
    ([2.0 / 3.0, 1.0 / 6.0], 1.0 / 6.0),
    ([1.0 / 6.0, 2.0 / 3.0], 1.0 / 6.0),
];

/// The 9-point wedge rule: 3-point triangle × 3-point Gauss in ζ.
pub fn wedge_rule() -> Vec<QuadraturePoint> {
    let mut pts = Vec::with_capacity(9);
    for &(z, wz) in gauss_1d(3) {
        for &(rs, w) in &TRIANGLE_3 {
            pts.push(QuadraturePoint {
                xi: [rs[0], rs[1], z],
                weight: w * wz,
            });
        }
    }
    pts
}

/// Tensor Gauss rule on the quadrilateral [-1,1]² with `n`² points.
pub fn quad_rule(n: usize) -> Vec<([f64; 2], f64)> {
    let g = gauss_1d(n);
    let mut pts = Vec::with_capacity(n * n);
    for &(y, wy) in g {
        for &(x, wx) in g {
            pts.push(([x, y], wx * wy));
        }
    }
    pts
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weights_sum_to_reference_volume() {
        let s: f64 = hex_rule(3).iter().map(|p| p.weight).sum();
        assert!((s - 8.0).abs() < 1e-14);
        let s: f64 = hex_rule(2).iter().map(|p| p.weight).sum();
        assert!((s - 8.0).abs() < 1e-14);
        let s: f64 = wedge_rule().iter().map(|p| p.weight).sum();
        assert!((s - 1.0).abs() < 1e-14);
    }

    #[test]
    fn gauss3_integrates_quintic() {
        // ∫_{-1}^{1} x⁴ dx = 2/5
        let s: f64 = gauss_1d(3).iter().map(|&(x, w)| w * x.powi(4)).sum();
        assert!((s - 0.4).abs() < 1e-15);
    }
}
