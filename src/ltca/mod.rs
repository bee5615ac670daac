//! Compliance-matrix loaded tooth contact analysis (LTCA).
//!
//! * [`qp`]: the frictionless contact problem at one roll position (seed 000:
//!   compatibility F p + w = θ r + g, equilibrium rᵀp = T, complementarity)
//!   as a convex QP, solved by a dedicated active-set method or by clarabel,
//!   every answer with its KKT residual.
//! * [`friction`]: the frictional contact problem at one roll position
//!   (seeds 001, 003: normal and tangential compliances, stick/slip/
//!   separation, load increments), solved per increment by clarabel
//!   (Tresca QPs, fixed point, polish) and cross-checked by Lemke's method.
//! * [`cycle`]: one LTCA cycle for every pair kind over the contact
//!   candidates the kind hands it ([`crate::tca::candidates`]: the line
//!   TCA's contact lines of a spur/helical pair; the point TCA's
//!   major axes and edge lines of a bevel/hypoid pair,
//!   [`crate::tca::point_candidates`]), both bodies' tensors from
//!   [`bodies`], solved through [`model::LtcaBodies`] (its compliance F
//!   from the tensors: [`influence`]); run over a scene with its files by
//!   [`run`] (the point-contact tables, edge variants and plots:
//!   [`point_run`]); load sharing and the functional contact ratio in
//!   [`crate::load_sharing`], [`te_fit`]: the loaded TE's quadratic fit
//!   over a cycle (seed 003); [`harmonics`]: its mesh-order amplitudes
//!   over whole pitches, [`mesh_stiffness`] per position, [`torque_map`]:
//!   both over a list of torques (the Harris map).
//! * [`lubricated`]: the wet–dry loop of seed 002 through the frictional
//!   spur/helical LTCA (μ per position and tooth pair from the EHL model of
//!   [`crate::lubrication`]).

pub mod bodies;
pub mod candidate;
pub mod cycle;
pub mod friction;
pub mod friction_report;
pub mod harmonics;
pub mod hertz_elliptic;
pub mod influence;
pub mod local;
pub mod lubricated;
pub mod mesh_stiffness;
pub mod model;
pub mod outputs;
pub mod pattern;
pub mod point_run;
pub mod qp;
pub mod run;
pub mod solve_settings;
pub mod summary;
pub mod te_fit;
pub mod torque_map;
