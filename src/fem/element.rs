//! Quadratic solid elements: shape functions, Jacobians, stiffness.
//!
//! Node order is CalculiX/Abaqus (DESIGN.md). Shape functions:
//! * C3D20/C3D20R: 20-node serendipity hexahedron on [-1,1]³
//!   (Zienkiewicz & Taylor, *The Finite Element Method*, vol. 1, §8.7);
//! * C3D15: 15-node wedge, quadratic triangle {r,s ≥ 0, r+s ≤ 1} × quadratic
//!   in ζ ∈ [-1,1] (serendipity: no face-centre nodes).
//!
//! Element stiffness K_ab = ∫ (λ ∇N_a ⊗ ∇N_b + μ ∇N_b ⊗ ∇N_a + μ (∇N_a·∇N_b) I) dV,
//! the isotropic form of ∫ Bᵀ D B dV, node-block by node-block.

use std::sync::OnceLock;

use crate::error::FlankError;
use crate::fem::mesh::ElementKind;
use crate::fem::quadrature::{hex_rule, wedge_rule, QuadraturePoint};

/// Reference coordinates of the 20 hexahedron nodes (CalculiX order).
pub const HEX20_NODES: [[f64; 3]; 20] = [
    [-1.0, -1.0, -1.0],
    [1.0, -1.0, -1.0],
    [1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, 1.0],
    [1.0, -1.0, 1.0],
    [1.0, 1.0, 1.0],
    [-1.0, 1.0, 1.0],
    [0.0, -1.0, -1.0],
    [1.0, 0.0, -1.0],
    [0.0, 1.0, -1.0],
    [-1.0, 0.0, -1.0],
    [0.0, -1.0, 1.0],
    [1.0, 0.0, 1.0],
    [0.0, 1.0, 1.0],
    [-1.0, 0.0, 1.0],
    [-1.0, -1.0, 0.0],
    [1.0, -1.0, 0.0],
    [1.0, 1.0, 0.0],
    [-1.0, 1.0, 0.0],
];

/// Reference coordinates (r, s, ζ) of the 15 wedge nodes (CalculiX order).
pub const WEDGE15_NODES: [[f64; 3]; 15] = [
    [0.0, 0.0, -1.0],
    [1.0, 0.0, -1.0],
    [0.0, 1.0, -1.0],
    [0.0, 0.0, 1.0],
    [1.0, 0.0, 1.0],
    [0.0, 1.0, 1.0],
    [0.5, 0.0, -1.0],
    [0.5, 0.5, -1.0],
    [0.0, 0.5, -1.0],
    [0.5, 0.0, 1.0],
    [0.5, 0.5, 1.0],
    [0.0, 0.5, 1.0],
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
];

/// Face node lists (0-based, corners first, then midsides), CalculiX face
/// numbering; the corner order makes (∂x/∂ξ × ∂x/∂η) point out of the element.
pub const HEX20_FACES: [[usize; 8]; 6] = [
    [3, 2, 1, 0, 10, 9, 8, 11],
    [4, 5, 6, 7, 12, 13, 14, 15],
    [0, 1, 5, 4, 8, 17, 12, 16],
    [1, 2, 6, 5, 9, 18, 13, 17],
    [2, 3, 7, 6, 10, 19, 14, 18],
    [3, 0, 4, 7, 11, 16, 15, 19],
];

/// Wedge faces: 1 and 2 are 6-node triangles, 3..5 are 8-node quadrilaterals.
pub const WEDGE15_FACES: [&[usize]; 5] = [
    &[0, 2, 1, 8, 7, 6],
    &[3, 4, 5, 9, 10, 11],
    &[0, 1, 4, 3, 6, 13, 9, 12],
    &[1, 2, 5, 4, 7, 14, 10, 13],
    &[3, 5, 2, 0, 11, 14, 8, 12],
];

/// Node list of face `face` (1-based, CalculiX numbering) of an element kind.
pub fn face_nodes(kind: ElementKind, face: usize) -> Option<&'static [usize]> {
    match kind {
        ElementKind::C3D20 | ElementKind::C3D20R => {
            HEX20_FACES.get(face.wrapping_sub(1)).map(|f| &f[..])
        }
        ElementKind::C3D15 => WEDGE15_FACES.get(face.wrapping_sub(1)).copied(),
    }
}

/// C3D20 edges as (corner, corner, midside) node positions.
pub const HEX20_EDGES: [[usize; 3]; 12] = [
    [0, 1, 8],
    [1, 2, 9],
    [2, 3, 10],
    [3, 0, 11],
    [4, 5, 12],
    [5, 6, 13],
    [6, 7, 14],
    [7, 4, 15],
    [0, 4, 16],
    [1, 5, 17],
    [2, 6, 18],
    [3, 7, 19],
];

/// C3D15 edges as (corner, corner, midside) node positions.
pub const WEDGE15_EDGES: [[usize; 3]; 9] = [
    [0, 1, 6],
    [1, 2, 7],
    [2, 0, 8],
    [3, 4, 9],
    [4, 5, 10],
    [5, 3, 11],
    [0, 3, 12],
    [1, 4, 13],
    [2, 5, 14],
];

/// Edges of an element kind as (corner, corner, midside) node positions.
pub fn edges(kind: ElementKind) -> &'static [[usize; 3]] {
    match kind {
        ElementKind::C3D20 | ElementKind::C3D20R => &HEX20_EDGES,
        ElementKind::C3D15 => &WEDGE15_EDGES,
    }
}

/// Shape functions N and their derivatives ∂N/∂ξ of the 20-node hexahedron.
pub fn hex20_shape(xi: [f64; 3]) -> ([f64; 20], [[f64; 3]; 20]) {
    let mut n = [0.0; 20];
    let mut d = [[0.0; 3]; 20];
    let [x, y, z] = xi;
    for (a, p) in HEX20_NODES.iter().enumerate() {
        let (xa, ya, za) = (p[0], p[1], p[2]);
        if a < 8 {
            let (fx, fy, fz) = (1.0 + x * xa, 1.0 + y * ya, 1.0 + z * za);
            let s = x * xa + y * ya + z * za - 2.0;
            n[a] = 0.125 * fx * fy * fz * s;
            d[a][0] = 0.125 * xa * fy * fz * (s + fx);
            d[a][1] = 0.125 * ya * fx * fz * (s + fy);
            d[a][2] = 0.125 * za * fx * fy * (s + fz);
        } else if xa == 0.0 {
            let (fy, fz) = (1.0 + y * ya, 1.0 + z * za);
            n[a] = 0.25 * (1.0 - x * x) * fy * fz;
            d[a][0] = -0.5 * x * fy * fz;
            d[a][1] = 0.25 * (1.0 - x * x) * ya * fz;
            d[a][2] = 0.25 * (1.0 - x * x) * fy * za;
        } else if ya == 0.0 {
            let (fx, fz) = (1.0 + x * xa, 1.0 + z * za);
            n[a] = 0.25 * (1.0 - y * y) * fx * fz;
            d[a][0] = 0.25 * (1.0 - y * y) * xa * fz;
            d[a][1] = -0.5 * y * fx * fz;
            d[a][2] = 0.25 * (1.0 - y * y) * fx * za;
        } else {
            let (fx, fy) = (1.0 + x * xa, 1.0 + y * ya);
            n[a] = 0.25 * (1.0 - z * z) * fx * fy;
            d[a][0] = 0.25 * (1.0 - z * z) * xa * fy;
            d[a][1] = 0.25 * (1.0 - z * z) * fx * ya;
            d[a][2] = -0.5 * z * fx * fy;
        }
    }
    (n, d)
}

/// Shape functions and derivatives of the 15-node wedge at (r, s, ζ).
pub fn wedge15_shape(xi: [f64; 3]) -> ([f64; 15], [[f64; 3]; 15]) {
    let [r, s, z] = xi;
    // Area coordinates L1 = 1 − r − s, L2 = r, L3 = s and their (r, s) derivatives.
    let l = [1.0 - r - s, r, s];
    let dl = [[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]];
    let mut n = [0.0; 15];
    let mut d = [[0.0; 3]; 15];
    // corners: N = ½ Lᵢ [(2Lᵢ − 1)(1 + ζζᵢ) − (1 − ζ²)]
    for c in 0..6 {
        let i = c % 3;
        let zc = if c < 3 { -1.0 } else { 1.0 };
        let li = l[i];
        let g = (2.0 * li - 1.0) * (1.0 + z * zc) - (1.0 - z * z);
        n[c] = 0.5 * li * g;
        let dndl = 0.5 * (g + li * 2.0 * (1.0 + z * zc));
        d[c][0] = dndl * dl[i][0];
        d[c][1] = dndl * dl[i][1];
        d[c][2] = 0.5 * li * ((2.0 * li - 1.0) * zc + 2.0 * z);
    }
    // triangle edge midsides: N = 2 Lᵢ Lⱼ (1 + ζζₖ)
    let edges = [
        (6, 0, 1, -1.0),
        (7, 1, 2, -1.0),
        (8, 2, 0, -1.0),
        (9, 0, 1, 1.0),
        (10, 1, 2, 1.0),
        (11, 2, 0, 1.0),
    ];
    for &(a, i, j, zc) in &edges {
        let f = 1.0 + z * zc;
        n[a] = 2.0 * l[i] * l[j] * f;
        for k in 0..2 {
            d[a][k] = 2.0 * (dl[i][k] * l[j] + l[i] * dl[j][k]) * f;
        }
        d[a][2] = 2.0 * l[i] * l[j] * zc;
    }
    // vertical midsides: N = Lᵢ (1 − ζ²)
    for i in 0..3 {
        let a = 12 + i;
        n[a] = l[i] * (1.0 - z * z);
        d[a][0] = dl[i][0] * (1.0 - z * z);
        d[a][1] = dl[i][1] * (1.0 - z * z);
        d[a][2] = -2.0 * z * l[i];
    }
    (n, d)
}

/// Shape functions (values, derivatives) of `kind` at reference point `xi`.
pub fn shape(kind: ElementKind, xi: [f64; 3]) -> (Vec<f64>, Vec<[f64; 3]>) {
    match kind {
        ElementKind::C3D20 | ElementKind::C3D20R => {
            let (n, d) = hex20_shape(xi);
            (n.to_vec(), d.to_vec())
        }
        ElementKind::C3D15 => {
            let (n, d) = wedge15_shape(xi);
            (n.to_vec(), d.to_vec())
        }
    }
}

/// Reference coordinates of the 8-node quadrilateral face's nodes on
/// [-1,1]²: corners counter-clockwise, then the midsides of edges 0–1,
/// 1–2, 2–3, 3–0.
pub const QUAD8_NODES: [[f64; 2]; 8] = [
    [-1.0, -1.0],
    [1.0, -1.0],
    [1.0, 1.0],
    [-1.0, 1.0],
    [0.0, -1.0],
    [1.0, 0.0],
    [0.0, 1.0],
    [-1.0, 0.0],
];

/// Shape functions of the 8-node quadrilateral face on [-1,1]² and their derivatives.
pub fn quad8_shape(xi: [f64; 2]) -> ([f64; 8], [[f64; 2]; 8]) {
    const P: [[f64; 2]; 8] = QUAD8_NODES;
    let [x, y] = xi;
    let mut n = [0.0; 8];
    let mut d = [[0.0; 2]; 8];
    for (a, p) in P.iter().enumerate() {
        let (xa, ya) = (p[0], p[1]);
        if a < 4 {
            let (fx, fy) = (1.0 + x * xa, 1.0 + y * ya);
            let s = x * xa + y * ya - 1.0;
            n[a] = 0.25 * fx * fy * s;
            d[a][0] = 0.25 * xa * fy * (s + fx);
            d[a][1] = 0.25 * ya * fx * (s + fy);
        } else if xa == 0.0 {
            let fy = 1.0 + y * ya;
            n[a] = 0.5 * (1.0 - x * x) * fy;
            d[a][0] = -x * fy;
            d[a][1] = 0.5 * (1.0 - x * x) * ya;
        } else {
            let fx = 1.0 + x * xa;
            n[a] = 0.5 * (1.0 - y * y) * fx;
            d[a][0] = 0.5 * (1.0 - y * y) * xa;
            d[a][1] = -y * fx;
        }
    }
    (n, d)
}

/// Shape functions of the 6-node triangle face (corners (0,0),(1,0),(0,1), then
/// midsides 1-2, 2-3, 3-1) and their derivatives.
pub fn tri6_shape(xi: [f64; 2]) -> ([f64; 6], [[f64; 2]; 6]) {
    let [r, s] = xi;
    let l = [1.0 - r - s, r, s];
    let dl = [[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]];
    let mut n = [0.0; 6];
    let mut d = [[0.0; 2]; 6];
    for i in 0..3 {
        n[i] = l[i] * (2.0 * l[i] - 1.0);
        for k in 0..2 {
            d[i][k] = (4.0 * l[i] - 1.0) * dl[i][k];
        }
    }
    for (m, &(i, j)) in [(0usize, 1usize), (1, 2), (2, 0)].iter().enumerate() {
        n[3 + m] = 4.0 * l[i] * l[j];
        for k in 0..2 {
            d[3 + m][k] = 4.0 * (dl[i][k] * l[j] + l[i] * dl[j][k]);
        }
    }
    (n, d)
}

/// Shape-function values and reference derivatives at each quadrature point of a rule.
pub struct ReferenceElement {
    pub kind: ElementKind,
    pub nodes: usize,
    pub points: Vec<QuadraturePoint>,
    /// `values[g][a]` = N_a at point g.
    pub values: Vec<Vec<f64>>,
    /// `derivatives[g][a]` = ∂N_a/∂ξ at point g.
    pub derivatives: Vec<Vec<[f64; 3]>>,
}

impl ReferenceElement {
    fn build(kind: ElementKind) -> Self {
        let points = match kind {
            ElementKind::C3D20 => hex_rule(3),
            ElementKind::C3D20R => hex_rule(2),
            ElementKind::C3D15 => wedge_rule(),
        };
        let (values, derivatives) = points.iter().map(|p| shape(kind, p.xi)).unzip();
        ReferenceElement {
            kind,
            nodes: kind.node_count(),
            points,
            values,
            derivatives,
        }
    }

    /// The cached reference element of `kind`.
    pub fn get(kind: ElementKind) -> &'static ReferenceElement {
        static HEX: OnceLock<ReferenceElement> = OnceLock::new();
        static HEXR: OnceLock<ReferenceElement> = OnceLock::new();
        static WEDGE: OnceLock<ReferenceElement> = OnceLock::new();
        match kind {
            ElementKind::C3D20 => HEX.get_or_init(|| Self::build(kind)),
            ElementKind::C3D20R => HEXR.get_or_init(|| Self::build(kind)),
            ElementKind::C3D15 => WEDGE.get_or_init(|| Self::build(kind)),
        }
    }
}

/// Jacobian J (J_ij = ∂x_i/∂ξ_j) from node coordinates and reference derivatives.
#[inline]
pub fn jacobian(x: &[[f64; 3]], dn: &[[f64; 3]]) -> [[f64; 3]; 3] {
    let mut j = [[0.0; 3]; 3];
    for (xa, da) in x.iter().zip(dn) {
        for i in 0..3 {
            for k in 0..3 {
                j[i][k] += xa[i] * da[k];
            }
        }
    }
    j
}

#[inline]
pub fn det3(j: &[[f64; 3]; 3]) -> f64 {
    j[0][0] * (j[1][1] * j[2][2] - j[1][2] * j[2][1])
        - j[0][1] * (j[1][0] * j[2][2] - j[1][2] * j[2][0])
        + j[0][2] * (j[1][0] * j[2][1] - j[1][1] * j[2][0])
}

/// Inverse of a 3×3 matrix with known determinant.
#[inline]
pub fn inv3(j: &[[f64; 3]; 3], det: f64) -> [[f64; 3]; 3] {
    let d = 1.0 / det;
    [
        [
            (j[1][1] * j[2][2] - j[1][2] * j[2][1]) * d,
            (j[0][2] * j[2][1] - j[0][1] * j[2][2]) * d,
            (j[0][1] * j[1][2] - j[0][2] * j[1][1]) * d,
        ],
        [
            (j[1][2] * j[2][0] - j[1][0] * j[2][2]) * d,
            (j[0][0] * j[2][2] - j[0][2] * j[2][0]) * d,
            (j[0][2] * j[1][0] - j[0][0] * j[1][2]) * d,
        ],
        [
            (j[1][0] * j[2][1] - j[1][1] * j[2][0]) * d,
            (j[0][1] * j[2][0] - j[0][0] * j[2][1]) * d,
            (j[0][0] * j[1][1] - j[0][1] * j[1][0]) * d,
        ],
    ]
}

/// Size scale of an element: half the diagonal of its bounding box.
fn size_scale(x: &[[f64; 3]]) -> f64 {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in x {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    0.5 * ((hi[0] - lo[0]).powi(2) + (hi[1] - lo[1]).powi(2) + (hi[2] - lo[2]).powi(2)).sqrt()
}

/// Why an element's Jacobian was rejected.
#[derive(Clone, Debug, PartialEq)]
pub struct JacobianError {
    /// The integration point (0-based) where the check failed.
    pub point: usize,
    pub det: f64,
    /// det J divided by the cube of the element's size scale.
    pub relative: f64,
}

impl JacobianError {
    /// [`Self::into_error`] with where the element was made (a mesher's
    /// block, cell and layer) appended to the message.
    pub fn into_error_in(self, label: u64, kind: ElementKind, context: &str) -> FlankError {
        match self.into_error(label, kind) {
            FlankError::Element {
                label,
                kind,
                message,
            } => FlankError::Element {
                label,
                kind,
                message: format!("{message} ({context})"),
            },
            other => other,
        }
    }

    /// Converts to a [`FlankError`] naming the element.
    pub fn into_error(self, label: u64, kind: ElementKind) -> FlankError {
        let what = if self.det.is_finite() && self.relative.abs() <= DEGENERATE_RELATIVE_DET {
            "degenerate (Jacobian determinant ~ 0)"
        } else if self.det < 0.0 || !self.det.is_finite() {
            "inverted (negative Jacobian determinant)"
        } else {
            "degenerate (Jacobian determinant ~ 0)"
        };
        FlankError::Element {
            label,
            kind: kind.name(),
            message: format!(
                "{what} at integration point {}: det J = {:.3e} (relative {:.3e}); check node order and coordinates",
                self.point + 1,
                self.det,
                self.relative
            ),
        }
    }
}

/// Relative determinant below which an element is called degenerate.
pub const DEGENERATE_RELATIVE_DET: f64 = 1e-12;

/// Spatial gradients ∇N_a and det J·w at each integration point of one element.
/// Fails if det J is non-positive or degenerate at any integration point.
pub fn gradients(
    re: &ReferenceElement,
    x: &[[f64; 3]],
    grads: &mut Vec<[f64; 3]>,
    dvol: &mut Vec<f64>,
) -> Result<(), JacobianError> {
    let n = re.nodes;
    grads.clear();
    dvol.clear();
    let scale3 = size_scale(x).powi(3);
    for (g, (p, dn)) in re.points.iter().zip(&re.derivatives).enumerate() {
        let j = jacobian(x, dn);
        let det = det3(&j);
        let relative = det / scale3;
        if !(det > 0.0) || !(relative > DEGENERATE_RELATIVE_DET) {
            return Err(JacobianError {
                point: g,
                det,
                relative,
            });
        }
        let ji = inv3(&j, det);
        for da in dn.iter().take(n) {
            // ∂N/∂x_i = Σ_k ∂N/∂ξ_k ∂ξ_k/∂x_i = Σ_k da[k] ji[k][i]
            grads.push([
                da[0] * ji[0][0] + da[1] * ji[1][0] + da[2] * ji[2][0],
                da[0] * ji[0][1] + da[1] * ji[1][1] + da[2] * ji[2][1],
                da[0] * ji[0][2] + da[1] * ji[1][2] + da[2] * ji[2][2],
            ]);
        }
        dvol.push(det * p.weight);
    }
    Ok(())
}

/// Reusable buffers for element integration (one per thread).
#[derive(Default)]
pub struct ElementWorkspace {
    pub grads: Vec<[f64; 3]>,
    pub dvol: Vec<f64>,
    pub coords: Vec<[f64; 3]>,
}

/// Element stiffness matrix (3n×3n, row-major, node-major DOFs) for an isotropic
/// material with Lamé constants (λ, μ), written into `k`.
pub fn stiffness(
    kind: ElementKind,
    x: &[[f64; 3]],
    lambda: f64,
    mu: f64,
    ws: &mut ElementWorkspace,
    k: &mut Vec<f64>,
) -> Result<(), JacobianError> {
    let re = ReferenceElement::get(kind);
    let n = re.nodes;
    let m = 3 * n;
    gradients(re, x, &mut ws.grads, &mut ws.dvol)?;
    k.clear();
    k.resize(m * m, 0.0);
    for (g, &dv) in ws.dvol.iter().enumerate() {
        let gr = &ws.grads[g * n..(g + 1) * n];
        let (l, u) = (lambda * dv, mu * dv);
        for a in 0..n {
            let ga = gr[a];
            let la = [l * ga[0], l * ga[1], l * ga[2]];
            let ua = [u * ga[0], u * ga[1], u * ga[2]];
            for b in a..n {
                let gb = gr[b];
                let dot = ua[0] * gb[0] + ua[1] * gb[1] + ua[2] * gb[2];
                let base = (3 * a) * m + 3 * b;
                for i in 0..3 {
                    let row = base + i * m;
                    for j in 0..3 {
                        k[row + j] += la[i] * gb[j] + ua[j] * gb[i];
                    }
                    k[row + i] += dot;
                }
            }
        }
    }
    // mirror the upper node blocks into the lower ones
    for a in 0..n {
        for b in 0..a {
            for i in 0..3 {
                for j in 0..3 {
                    k[(3 * a + i) * m + 3 * b + j] = k[(3 * b + j) * m + 3 * a + i];
                }
            }
        }
    }
    Ok(())
}

/// Checks the Jacobian of an element at all its integration points.
pub fn check_jacobian(kind: ElementKind, x: &[[f64; 3]]) -> Result<(), JacobianError> {
    let mut g = Vec::new();
    let mut d = Vec::new();
    gradients(ReferenceElement::get(kind), x, &mut g, &mut d)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn partition_of_unity(kind: ElementKind, pts: &[[f64; 3]]) {
        for &p in pts {
            let (n, d) = shape(kind, p);
            let s: f64 = n.iter().sum();
            assert!((s - 1.0).abs() < 1e-14, "{kind:?} ΣN = {s}");
            for k in 0..3 {
                let s: f64 = d.iter().map(|v| v[k]).sum();
                assert!(s.abs() < 1e-13, "{kind:?} Σ∂N = {s}");
            }
        }
    }

    #[test]
    fn kronecker_property() {
        for (a, &p) in HEX20_NODES.iter().enumerate() {
            let (n, _) = hex20_shape(p);
            for (b, v) in n.iter().enumerate() {
                assert!((v - if a == b { 1.0 } else { 0.0 }).abs() < 1e-14);
            }
        }
        for (a, &p) in WEDGE15_NODES.iter().enumerate() {
            let (n, _) = wedge15_shape(p);
            for (b, v) in n.iter().enumerate() {
                assert!(
                    (v - if a == b { 1.0 } else { 0.0 }).abs() < 1e-14,
                    "wedge N{b} at node {a} = {v}"
                );
            }
        }
    }

    #[test]
    fn unity_and_derivatives_by_finite_differences() {
        let pts = [[0.1, -0.3, 0.7], [0.2, 0.3, -0.4], [0.05, 0.6, 0.9]];
        partition_of_unity(ElementKind::C3D20, &pts);
        partition_of_unity(ElementKind::C3D15, &pts);
        for kind in [ElementKind::C3D20, ElementKind::C3D15] {
            for &p in &pts {
                let (_, d) = shape(kind, p);
                for k in 0..3 {
                    let h = 1e-6;
                    let mut pp = p;
                    pp[k] += h;
                    let mut pm = p;
                    pm[k] -= h;
                    let (np, _) = shape(kind, pp);
                    let (nm, _) = shape(kind, pm);
                    for a in 0..np.len() {
                        let fd = (np[a] - nm[a]) / (2.0 * h);
                        assert!(
                            (fd - d[a][k]).abs() < 1e-8,
                            "{kind:?} dN{a}/dξ{k}: {fd} vs {}",
                            d[a][k]
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn face_shapes() {
        for p in [[0.3, -0.2], [-0.7, 0.9]] {
            let (n, d) = quad8_shape(p);
            assert!((n.iter().sum::<f64>() - 1.0).abs() < 1e-14);
            for k in 0..2 {
                let h = 1e-6;
                let mut pp = p;
                pp[k] += h;
                let mut pm = p;
                pm[k] -= h;
                let (np, _) = quad8_shape(pp);
                let (nm, _) = quad8_shape(pm);
                for a in 0..8 {
                    assert!(((np[a] - nm[a]) / (2.0 * h) - d[a][k]).abs() < 1e-8);
                }
            }
        }
        for p in [[0.2, 0.3], [0.6, 0.1]] {
            let (n, d) = tri6_shape(p);
            assert!((n.iter().sum::<f64>() - 1.0).abs() < 1e-14);
            for k in 0..2 {
                let h = 1e-6;
                let mut pp = p;
                pp[k] += h;
                let mut pm = p;
                pm[k] -= h;
                let (np, _) = tri6_shape(pp);
                let (nm, _) = tri6_shape(pm);
                for a in 0..6 {
                    assert!(((np[a] - nm[a]) / (2.0 * h) - d[a][k]).abs() < 1e-8);
                }
            }
        }
    }

    #[test]
    fn inverted_element_is_rejected() {
        let mut x: Vec<[f64; 3]> = HEX20_NODES.to_vec();
        assert!(check_jacobian(ElementKind::C3D20, &x).is_ok());
        for p in x.iter_mut() {
            p[2] = -p[2];
        }
        let e = check_jacobian(ElementKind::C3D20, &x).unwrap_err();
        assert!(e.det < 0.0);
        let msg = e.into_error(7, ElementKind::C3D20).to_string();
        assert!(
            msg.contains("element 7") && msg.contains("inverted"),
            "{msg}"
        );
    }
}
