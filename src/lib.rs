//! # flank — finite-element-first gear tooth contact
//!
//! Data flow (see DESIGN.md):
//!
//! ```text
//! deck.inp / scene.toml ─► mesh ─► fem (K, constraints, Cholesky) ─► results ─► report
//! ```
//!
//! * [`mesh`]: nodes, quadratic solid elements (C3D20, C3D20R, C3D15), sets;
//!   CalculiX/Abaqus deck reader and writer; structured meshes for verification.
//! * [`fem`]: elements, quadrature, assembly, constraints, sparse Cholesky,
//!   stress recovery, the linear static analysis.
//! * [`report`]: VTU, CSV and JSON output.

// Index loops mirror the formulas (K_ab, J_ij, …) in numerical kernels.
#![allow(clippy::needless_range_loop)]
// `!(x > y)` is used on purpose: it is also true when x is NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod ccx;
pub mod error;
pub mod fem;
pub mod mesh;
pub mod report;

pub use error::{FlankError, Result};
