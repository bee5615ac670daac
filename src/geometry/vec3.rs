//! Small 3-vector helpers on plain `[f64; 3]` (the geometry's and the
//! contact analyses' points and normals), shared instead of repeated.

/// A 3-vector (mm or unit).
pub type V3 = [f64; 3];

pub fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

pub fn norm(a: V3) -> f64 {
    dot(a, a).sqrt()
}

/// a + s b.
pub fn add(a: V3, s: f64, b: V3) -> V3 {
    [a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2]]
}

pub fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// a / |a|.
pub fn unit(a: V3) -> V3 {
    let l = norm(a);
    [a[0] / l, a[1] / l, a[2] / l]
}

/// Determinant of a 3 × 3 matrix (rows), by cofactors of the first row.
pub fn det3(a: &[[f64; 3]; 3]) -> f64 {
    a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
        - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
        + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0])
}

/// Solve a x = b by Cramer's rule (3 × 3); None if singular relative to
/// the rows' scale (|det| ≤ 1e-13 ∏ ‖row‖).
pub fn solve3(a: &[[f64; 3]; 3], b: [f64; 3]) -> Option<[f64; 3]> {
    let d = det3(a);
    let scale: f64 = a
        .iter()
        .map(|r| r.iter().map(|x| x * x).sum::<f64>().sqrt())
        .product();
    if !(d.is_finite() && scale > 0.0) || d.abs() <= 1e-13 * scale {
        return None;
    }
    let mut x = [0.0; 3];
    for (k, xk) in x.iter_mut().enumerate() {
        let mut m = *a;
        for i in 0..3 {
            m[i][k] = b[i];
        }
        *xk = det3(&m) / d;
    }
    Some(x)
}
