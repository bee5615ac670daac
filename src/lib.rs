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
//! * [`compliance`]: nodal compliance tensors of a gear body on its flanks
//!   (one factorization; Schur complement or blocked solves), HDF5/native
//!   cache, interpolation at flank points and contact cells (the LTCA input).
//! * [`contact`]: node-to-surface FE contact (search, projection onto
//!   quadratic faces, hard and penalty laws by an active set on the
//!   condensed problem; the stiffness is factorized once).
//! * [`report`]: VTU, CSV and JSON output.
//! * [`tca`]: unloaded tooth contact analysis (contact lines, separations, moment arms, velocities, curvatures: the LTCA's geometric input).
//!
//! The library is usable without the command line; a cantilever solved in
//! memory:
//!
//! ```
//! use flank::fem::static_analysis::{solve_static, SolveOptions};
//! use flank::mesh::structured::{cantilever_model, BoxElement};
//!
//! // 100 × 10 × 10 mm steel beam, 10 × 1 × 1 C3D20 elements, 1 kN tip load
//! let model = cantilever_model([10, 1, 1], BoxElement::Hex20, 1000.0).unwrap();
//! let sol = solve_static(&model, &SolveOptions::default()).unwrap();
//! let tip = model.mesh.node_sets["X1"][0];
//! let uy = sol.displacement[3 * tip + 1];
//! // Euler–Bernoulli: P L³ / (3 E I) = 1.905 mm; the coarse 3D mesh is close
//! assert!((uy + 1.905).abs() < 0.05, "tip deflection {uy}");
//! assert!(sol.stats.backward_error < 1e-14);
//! ```

// Index loops mirror the formulas (K_ab, J_ij, …) in numerical kernels.
#![allow(clippy::needless_range_loop)]
// `!(x > y)` is used on purpose: it is also true when x is NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod ccx;
pub mod compare;
pub mod compliance;
pub mod contact;
pub mod error;
pub mod fem;
pub mod geometry;
pub mod ltca;
pub mod mesh;
pub mod mesh_cycle;
pub mod report;
pub mod scene;
pub mod tca;
#[cfg(test)]
pub(crate) mod testing;

pub use error::{FlankError, Result};
