//! Mesh generation: the gear-sector meshers of every gear type
//! ([`gear_body::body_model`] picks the mesher of the gear's type), .msh
//! import, structured meshes and the Hertz models for verification. The
//! mesh data type itself ([`crate::fem::mesh::Mesh`]: nodes, quadratic solid
//! elements, sets) belongs to the FE model, below this layer; CalculiX
//! decks are read and written by [`crate::deck`].

pub mod bevel_body;
pub mod bevel_sector;
pub mod gear_body;
pub mod gear_sector;
#[cfg(feature = "gmsh")]
pub mod gmsh;
pub mod grading;
pub mod hertz;
pub mod hertz_point;
pub mod msh;
pub mod section_cells;
pub mod structured;
