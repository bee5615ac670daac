//! FE contact over a mesh cycle: both gear bodies meshed and placed in
//! mesh, one quasi-static contact solve per roll angle (seed 002's Abaqus
//! procedure, with the stiffness factorized once).
//!
//! ```text
//! pair_model  both sectors in one model (own frames), pinion hub coupled
//!             to a torque-loaded reference node, gear hub clamped,
//!             one contact pair per tooth pair (right flanks); the
//!             cylindrical sector meshes or the bevel sector meshes
//! cycle       one MeshCycle for every pair kind: factorize once; per roll
//!             angle: place, pair, solve the condensed contact problem;
//!             one StepResult (force per pair, TE in µrad and arcsec,
//!             pressure, patch; the path position of line contact, the
//!             tip edge, moment balance and pattern of point contact)
//! options     `flank run`'s options and their one merge for every pair
//!             kind (`settings`: command line > scene > default)
//! run         `flank run`: the cylindrical cycle over the roll angles,
//!             load sharing, transmission error, contact ratio,
//!             single-pair force; checkpoints; CSV, summary.json, VTU,
//!             plots (`report::cycle_plot`)
//! bevel_run   `flank run` on a bevel/hypoid scene: the checked cycle
//!             over one mesh cycle, checkpoints, contact pattern, files,
//!             summary
//! positions   the positions of a run, every kind: resumed from the
//!             checkpoint or solved, VTU and deck files, SIGINT between
//!             positions
//! outputs     mesh_cycle.csv and positions.csv, the same columns for
//!             every pair kind, from one record per position
//! summary     summary.json as a typed struct (`RunSummary`), the keys
//!             of both kinds and each kind's own
//! bevel_checks  the bad inputs a hypoid run refuses before factorizing
//!             (a sector too small, interpenetrating bodies) and the
//!             checked cycle built after them
//! contact_band  FE contact per roll angle on meshes with contact bands
//!             (finer involute rows around the contact points): p_max
//!             against Hertz, elements across 2b (`flank run --contact-band`)
//! lubricated  the wet–dry loop of seed 002 (`[analyses.lubrication]`):
//!             EHL μ per tooth pair and position, wet passes
//! ```
//!
//! The pair's kinematics (frames, tooth pairs, kinematic contact) come
//! from the gear-pair interface ([`crate::geometry::gear_pair`]).

pub mod bevel_checks;
pub mod bevel_run;
pub mod checkpoint;
pub mod contact_band;
pub mod cycle;
pub mod lubricated;
pub mod options;
pub mod outputs;
pub mod pair_model;
pub mod positions;
pub mod run;
pub mod summary;

pub use run::RunOptions;
pub use summary::RunSummary;
