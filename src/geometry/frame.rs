//! Rigid frames: where a body meshed (or described) in its own frame sits.
//!
//! A gear body's surfaces, mesh and stiffness live in the body's own frame
//! (the frame that turns with it); an assembly places each body by a frame,
//! x_global = R x + t. Defined here, at the bottom of the layers, because
//! the geometry (gear-pair kinematics) and the analyses above it (FE
//! contact, TCA, LTCA) all place bodies the same way.

/// A rigid frame: x_global = rotation · x + translation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// Row-major 3 × 3 rotation matrix.
    pub rotation: [[f64; 3]; 3],
    pub translation: [f64; 3],
}

impl Frame {
    pub const IDENTITY: Frame = Frame {
        rotation: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        translation: [0.0; 3],
    };

    /// Rotation by `angle` (rad, counter-clockwise seen from +z) about the
    /// z axis, then a translation.
    pub fn about_z(angle: f64, translation: [f64; 3]) -> Frame {
        let (s, c) = angle.sin_cos();
        Frame {
            rotation: [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]],
            translation,
        }
    }

    /// R v.
    pub fn rotate(&self, v: [f64; 3]) -> [f64; 3] {
        let r = &self.rotation;
        [
            r[0][0] * v[0] + r[0][1] * v[1] + r[0][2] * v[2],
            r[1][0] * v[0] + r[1][1] * v[1] + r[1][2] * v[2],
            r[2][0] * v[0] + r[2][1] * v[1] + r[2][2] * v[2],
        ]
    }

    /// Rᵀ v (a global vector in the body's own frame).
    pub fn rotate_back(&self, v: [f64; 3]) -> [f64; 3] {
        let r = &self.rotation;
        [
            r[0][0] * v[0] + r[1][0] * v[1] + r[2][0] * v[2],
            r[0][1] * v[0] + r[1][1] * v[1] + r[2][1] * v[2],
            r[0][2] * v[0] + r[1][2] * v[1] + r[2][2] * v[2],
        ]
    }

    /// R x + t.
    pub fn place(&self, x: [f64; 3]) -> [f64; 3] {
        let y = self.rotate(x);
        [
            y[0] + self.translation[0],
            y[1] + self.translation[1],
            y[2] + self.translation[2],
        ]
    }
}

impl Frame {
    /// Rotation by `angle` (rad, right-handed) about the line through
    /// `point` along the unit `axis` (Rodrigues' formula).
    pub fn about_axis(point: [f64; 3], axis: [f64; 3], angle: f64) -> Frame {
        let k = axis;
        let (s, c) = angle.sin_cos();
        let t = 1.0 - c;
        let rotation = [
            [
                c + t * k[0] * k[0],
                t * k[0] * k[1] - s * k[2],
                t * k[0] * k[2] + s * k[1],
            ],
            [
                t * k[0] * k[1] + s * k[2],
                c + t * k[1] * k[1],
                t * k[1] * k[2] - s * k[0],
            ],
            [
                t * k[0] * k[2] - s * k[1],
                t * k[1] * k[2] + s * k[0],
                c + t * k[2] * k[2],
            ],
        ];
        let r = Frame {
            rotation,
            translation: [0.0; 3],
        }
        .rotate(point);
        Frame {
            rotation,
            translation: [point[0] - r[0], point[1] - r[1], point[2] - r[2]],
        }
    }

    /// The frame `self ∘ inner`: x ↦ self.place(inner.place(x)).
    /// The inverse frame: x = Rᵀ (y − t).
    pub fn inverse(&self) -> Frame {
        let r = &self.rotation;
        let rotation = [
            [r[0][0], r[1][0], r[2][0]],
            [r[0][1], r[1][1], r[2][1]],
            [r[0][2], r[1][2], r[2][2]],
        ];
        let t = self.rotate_back(self.translation);
        Frame {
            rotation,
            translation: [-t[0], -t[1], -t[2]],
        }
    }

    pub fn compose(&self, inner: &Frame) -> Frame {
        let mut rotation = [[0.0; 3]; 3];
        for (i, row) in rotation.iter_mut().enumerate() {
            for (j, e) in row.iter_mut().enumerate() {
                *e = (0..3)
                    .map(|k| self.rotation[i][k] * inner.rotation[k][j])
                    .sum();
            }
        }
        Frame {
            rotation,
            translation: self.place(inner.translation),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inverse_undoes_the_frame() {
        let f = Frame::about_z(0.7, [1.0, -2.0, 3.0]).compose(&Frame::about_axis(
            [0.5, 0.0, 1.0],
            [0.0, 0.6, 0.8],
            -0.3,
        ));
        let x = [0.3, 4.0, -1.5];
        let back = f.inverse().place(f.place(x));
        for k in 0..3 {
            assert!((back[k] - x[k]).abs() < 1e-14, "{back:?}");
        }
        let id = f.inverse().compose(&f);
        for i in 0..3 {
            for j in 0..3 {
                let e = if i == j { 1.0 } else { 0.0 };
                assert!((id.rotation[i][j] - e).abs() < 1e-15);
            }
            assert!(id.translation[i].abs() < 1e-14);
        }
    }
}
