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
