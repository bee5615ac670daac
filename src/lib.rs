//! # flank — finite-element-first gear tooth contact
//!
//! Data flow (see DESIGN.md), with the module that does each step:
//!
//! ```text
//! scene.toml ──► scene ──► geometry ──────────────► mesh ──────────► fem
//!   (TOML, units     (gear-pair interface:   (sector mesher,   (K, constraints,
//!    converted)       surfaces, bodies,       node sets,         Cholesky once
//!                     pair kinematics)        flank (u, v))      per body)
//!                          │                                      │
//!                          │              ┌───────────────────────┴─────────┐
//!                          │              ▼                                 ▼
//!                          │        compliance                       contact, mesh_cycle
//!                          │        (nodal tensors C^ij,             (FE contact of the
//!                          │         cache, interpolation)            placed pair per roll)
//!                          ▼              │                                 │
//!                         tca ──────────► ltca (QP per position)            │
//!                  (contact lines,        │                                 │
//!                   separations, arms)    └──────────► compare ◄────────────┘
//!                                                  (error against run time)
//!                                                          │
//!                                                       report
//!                                             (CSV, JSON, VTU, SVG/PNG plots)
//! deck.inp ─► deck ─► fem ─► (contact) ─► report               (`flank solve`)
//! ```
//!
//! **Start at [`api`]**: load a scene, override keys, run an analysis, read
//! its typed result. The modules below are the layers it stands on.
//!
//! * [`scene`]: scene files (TOML) into one [`scene::Scene`] for every pair
//!   kind (its [`scene::PairKind`] is data): the pair, gears and
//!   micro-geometry, materials, load, the analyses asked for; errors name
//!   file:line.
//! * [`geometry`]: what a gear is. The **gear-pair interface**
//!   ([`geometry::gear_pair`]: [`geometry::surface::ToothSurface`] r(u, v)
//!   with normals, derivatives, boundaries and tip edge;
//!   [`geometry::gear_pair::GearBody`]; [`geometry::gear_pair::LineContactPair`]
//!   with assembly, misalignment, frames, engagement and kinematic contact
//!   lines) and its spur/helical implementation
//!   ([`geometry::cylindrical`], exact rack-generated involute helicoids,
//!   micro-geometry). Every analysis below sees gears only through it.
//! * [`mesh`]: the gear-sector meshers ([`mesh::gear_body::body_model`]
//!   picks the mesher of the gear's type); .msh import; structured meshes
//!   for verification.
//! * [`deck`]: CalculiX/Abaqus decks read into an FE model and written
//!   from one.
//! * [`fem`]: the mesh (nodes, quadratic solid elements C3D20, C3D20R,
//!   C3D15, sets), elements, quadrature, assembly, constraints, sparse
//!   Cholesky, stress recovery, the linear static analysis; the model data
//!   a deck defines (including its contact definition).
//! * [`summary`]: what every `summary.json` shares (its header: `schema_version`, `scene`, `pair_kind`).
//! * [`settings`]: the choices the analyses offer (solvers, laws, models),
//!   plain data read by the scene, the command line and the engines.
//! * [`compliance`]: nodal compliance tensors of a gear body on its flanks
//!   (one factorization; Schur complement or blocked solves), HDF5/native
//!   cache, interpolation at flank points and contact cells (the LTCA input).
//! * [`contact`]: node-to-surface FE contact (search, projection onto
//!   quadratic faces, hard and penalty laws, Coulomb friction, by an active
//!   set on the condensed problem; the stiffness is factorized once).
//! * [`mesh_cycle`]: FE contact of a gear pair over roll angles (`flank run`),
//!   with the wet–dry lubrication loop of seed 002.
//! * [`lubrication`]: lubricant data, EHL film thickness and traction per
//!   contact, the wet–dry loop driver (called by mesh_cycle; uses geometry).
//! * [`tca`]: unloaded tooth contact analysis through the interface
//!   (contact lines, separations, moment arms, velocities, curvatures).
//! * [`ltca`]: compliance-matrix LTCA, the contact QP per position (`flank ltca`).
//! * [`compare`]: LTCA against FE contact, error against run time (`flank compare`).
//! * [`load_sharing`]: when a tooth pair counts as loaded (shared by FE and LTCA).
//! * [`report`]: VTU, CSV and JSON output, the plots shared by the analyses.
//! * [`grid_convergence`]: observed order, Richardson extrapolation and GCI
//!   from three grids (Celik et al. 2008), for `compare` and campaigns.
//! * [`resources`], [`atomic_file`], [`interrupt`]: the lowest layer, used
//!   by all: the memory guard (memory available vs a step's estimate), files
//!   written whole or not at all (temporary name + rename, locks), and the
//!   SIGINT flag a long run polls at its safe points; [`progress`]: the
//!   steps of a long run reported to an embedding program (the Python
//!   package's callback).
//! * [`campaign`]: studies over many variants of a scene (grid, Monte Carlo),
//!   run as child `flank` processes locally or as a Slurm job array; the
//!   top layer: nothing imports it.
//!
//! Layers, lowest first: error; the leaves (text files, atomic files,
//! interrupt, progress, resources, iteration limits, grid convergence); settings;
//! geometry; fem; mesh and deck; lubrication; scene; tca, ccx and
//! load_sharing; contact; report; compliance; ltca; mesh_cycle; compare;
//! campaign. A module imports only from lower layers and no files import
//! each other in a circle (`tests/layering.rs`, the README's "Layout").
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

//!
//! One scene type reads every pair kind, and each analysis has one entry
//! point for all of them (the pair kind is data, [`scene::Gears`]):
//!
//! ```
//! use std::path::Path;
//! use flank::scene::{read_scene, PairKind};
//!
//! let papers = Path::new(env!("CARGO_MANIFEST_DIR")).join("papers");
//! let spur = read_scene(&papers.join("seed002-spur/scene.toml"))?;
//! assert_eq!(spur.kind, PairKind::Spur);
//! assert_eq!(spur.cylindrical("this example")?.pair.pinion.teeth, 13);
//! assert!((spur.load.torque_nmm - 312_000.0).abs() < 1e-9); // internal units: N·mm
//!
//! let hypoid = read_scene(&papers.join("seed003-hypoid/scene_eased.toml"))?;
//! assert_eq!(hypoid.kind, PairKind::Hypoid);
//! assert_eq!(hypoid.bevel("this example")?.blank_inputs.z1, 11);
//! // an analysis of one kind refuses the other at the scene's `pair.kind` line
//! let refused = hypoid.cylindrical("the contact-band study").unwrap_err();
//! assert!(refused.to_string().contains("spur and helical pairs only"));
//! # Ok::<(), flank::error::FlankError>(())
//! ```
//!
//! The analyses take the options of their command (`None`: the scene's
//! `[analyses.*]`, else the default) and write their files into `out`;
//! `examples/` runs each of them:
//!
//! ```no_run
//! use flank::ltca::cycle::LtcaOptions;
//! # let scene = flank::scene::read_scene(std::path::Path::new("scene.toml"))?;
//! let options = LtcaOptions { out: "out/ltca".into(), ..Default::default() };
//! let result = flank::ltca::run::run(&scene, &options)?; // spur, helical, bevel or hypoid
//! let cycle = result.first(); // a typed summary, the same fields for every pair kind
//! println!(
//!     "TE {:.2} µrad ({:.2} arcsec at the gear) peak-to-peak; max KKT residual {:.1e}",
//!     cycle.te_peak_to_peak_urad, cycle.te_peak_to_peak_arcsec, cycle.max_kkt
//! );
//! for step in &cycle.steps {
//!     println!("{:+.2}°: shares {:?}", step.position.roll_deg, step.load_share);
//! }
//! # Ok::<(), flank::error::FlankError>(())
//! ```

// Index loops mirror the formulas (K_ab, J_ij, …) in numerical kernels.
#![allow(clippy::needless_range_loop)]
// `!(x > y)` is used on purpose: it is also true when x is NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod api;
pub mod atomic_file;
pub mod campaign;
pub mod ccx;
pub mod compare;
pub mod compliance;
pub mod contact;
pub mod deck;
pub mod error;
pub mod fem;
pub mod geometry;
pub mod grid_convergence;
pub mod interrupt;
pub mod iteration_limits;
pub mod load_sharing;
pub mod ltca;
pub mod lubrication;
pub mod mesh;
pub mod mesh_cycle;
pub mod progress;
pub mod report;
pub mod resources;
pub mod scene;
pub mod settings;
pub mod summary;
pub mod tca;
#[cfg(test)]
pub(crate) mod testing;
pub mod text_file;

pub use error::{FlankError, Result};
