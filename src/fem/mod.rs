//! The native 3D linear-elasticity solver.
//!
//! `element` (shape functions, quadrature, element stiffness) →
//! `assembly` (CSC pattern once, numeric passes) → `constraints`
//! (Dirichlet elimination, rigid hub coupling) → `solver` (ordering,
//! sparse Cholesky; `substructuring`: the two-domain factorization) →
//! `refinement` (mixed-precision CG to f64 round-off) → `stress`
//! (recovery at nodes); `thermal` the initial strains of nodal temperatures. `mesh` holds nodes, elements and sets, `model`
//! what a deck defines (the mesh, materials, loads, constraints), `contact_definition` its contact surfaces and pairs (the
//! contact *solution* is [`crate::contact`]'s).

pub mod assembly;
pub mod constraints;
pub mod contact_definition;
pub mod element;
pub mod loads;
pub mod material;
pub mod mesh;
pub mod model;
pub mod ordering;
pub mod quadrature;
pub(crate) mod refinement;
pub mod residual;
pub mod solver;
pub mod static_analysis;
pub mod stress;
pub mod substructuring;
pub mod thermal;
