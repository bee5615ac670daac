//! Rigid placement of bodies meshed in their own frames.
//!
//! A gear body's stiffness is the same at every roll angle in its own frame
//! (the frame that turns with it). A driver that solves many positions
//! therefore keeps the mesh, the displacements and the factorized stiffness
//! in the bodies' own frames and places the bodies rigidly only for the
//! contact geometry: x_global = R_b x + t_b for the nodes of body b, and
//! u_global = R_b u. A gap's linear form n·u_global becomes (R_bᵀ n)·u in
//! the body's own DOFs.

pub use crate::geometry::frame::Frame;

/// The frame of every node: `frames[body_of[node]]`. The identity placement
/// (every node in the global frame) is [`Placement::identity`].
#[derive(Clone, Debug, Default)]
pub struct Placement {
    /// Body of each node (index into `frames`); empty: all in frame 0.
    pub body_of: Vec<u32>,
    /// One frame per body; empty: the identity.
    pub frames: Vec<Frame>,
}

impl Placement {
    /// Every node where the mesh has it.
    pub fn identity() -> Self {
        Placement::default()
    }

    pub fn is_identity(&self) -> bool {
        self.frames.iter().all(|f| *f == Frame::IDENTITY)
    }

    /// The frame of node `n`.
    pub fn frame(&self, n: usize) -> &Frame {
        if self.frames.is_empty() {
            return &Frame::IDENTITY;
        }
        let b = self.body_of.get(n).copied().unwrap_or(0) as usize;
        &self.frames[b.min(self.frames.len() - 1)]
    }

    /// Global positions of all nodes (`coords` in the bodies' own frames).
    pub fn positions(&self, coords: &[[f64; 3]]) -> Vec<[f64; 3]> {
        coords
            .iter()
            .enumerate()
            .map(|(n, &x)| self.frame(n).place(x))
            .collect()
    }

    /// Global position of node `n` displaced by `u` (own-frame vectors,
    /// node-major).
    pub fn displaced(&self, coords: &[[f64; 3]], u: &[f64], n: usize) -> [f64; 3] {
        let f = self.frame(n);
        f.place([
            coords[n][0] + u[3 * n],
            coords[n][1] + u[3 * n + 1],
            coords[n][2] + u[3 * n + 2],
        ])
    }

    /// Own-frame displacements rotated into the global frame.
    pub fn global_vectors(&self, u: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; u.len()];
        for n in 0..u.len() / 3 {
            let v = self.frame(n).rotate([u[3 * n], u[3 * n + 1], u[3 * n + 2]]);
            out[3 * n..3 * n + 3].copy_from_slice(&v);
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_round_trip() {
        let f = Frame::about_z(0.7, [1.0, 2.0, 3.0]);
        let v = [0.3, -1.2, 0.5];
        let w = f.rotate_back(f.rotate(v));
        for k in 0..3 {
            assert!((w[k] - v[k]).abs() < 1e-15);
        }
        // a quarter turn takes x to y
        let q = Frame::about_z(std::f64::consts::FRAC_PI_2, [0.0; 3]).rotate([1.0, 0.0, 0.0]);
        assert!(q[0].abs() < 1e-15 && (q[1] - 1.0).abs() < 1e-15);
        let p = Placement {
            body_of: vec![0, 1],
            frames: vec![Frame::IDENTITY, f],
        };
        assert!(!p.is_identity());
        let x = p.positions(&[[1.0, 0.0, 0.0], [1.0, 0.0, 0.0]]);
        assert_eq!(x[0], [1.0, 0.0, 0.0]);
        assert!((x[1][2] - 3.0).abs() < 1e-15);
    }
}
