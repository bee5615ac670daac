//! FE contact: node-to-surface contact between linear-elastic bodies.
//!
//! Data flow of a contact solve ([`solve::solve_contact`]):
//!
//! ```text
//! definition (surfaces, interactions, pairs: from the deck)
//!   └► pairing: search (grid of face boxes) + projection (Newton on the
//!      quadratic face) → candidate constraints g = g₀ + Σ cᵀu, slave areas
//! system: floating modes pinned, K₀ assembled and factorized ONCE
//!   └► condensed problem on the candidates: W = B K₀⁻¹ Bᵀ (lazy columns,
//!      blocks of 32; the substitutions restricted to the reach of the
//!      candidates' DOFs in the factor's elimination tree, exact),
//!      q (gaps under the loads), penalty compliances, floating-mode rows
//!   └► active_set: primal active-set QP (hard = Lagrange multipliers,
//!      penalty = the same problem with W + 1/k) → λ, α, KKT residuals
//!   └► with μ > 0 (*FRICTION): friction — two tangential rows per node,
//!      Tresca fixed point (clarabel SOCP) + Coulomb polish → λₙ, λₜ, slip
//!   └► final solve, stresses, pressures (face-averaged), contact.csv
//! ```
//!
//! Kinematics: small displacements and small sliding (pairing, normals and
//! face parameters fixed in the initial configuration); Coulomb friction
//! in one static step (the slip is the total tangential displacement),
//! [`friction`]; friction terms are left out entirely when μ = 0.
//! A driver that moves the contact between solves (gear roll angles) keeps
//! the [`system::ElasticSystem`] and calls [`solve::solve_pairs`] with new
//! pair geometries ([`pairing::build_pair`] takes the node positions
//! separately from the mesh).

pub mod active_set;
/// The contact definition is model data (surfaces, interactions, pairs as
/// a deck states them): it lives with the model in [`crate::fem`].
pub use crate::fem::contact_definition as definition;
pub mod floating;
pub mod friction;
pub mod hertz_line;
pub mod pairing;
pub mod placement;
pub mod projection;
pub mod search;
pub mod solve;
pub mod surface;
pub mod system;

pub use definition::{
    ContactDefinition, ContactPair, Friction, PressureOverclosure, Surface, SurfaceInteraction,
    SurfaceKind,
};
pub use solve::{solve_contact, ContactOptions, ContactSolution};
