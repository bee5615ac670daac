//! Compliance-matrix loaded tooth contact analysis (LTCA).
//!
//! * [`qp`]: the frictionless contact problem at one roll position (seed 000:
//!   compatibility F p + w = θ r + g, equilibrium rᵀp = T, complementarity)
//!   as a convex QP, solved by a dedicated active-set method or by clarabel,
//!   every answer with its KKT residual.

pub mod cycle;
pub mod hertz_elliptic;
pub mod local;
pub mod model;
pub mod pattern;
pub mod qp;
