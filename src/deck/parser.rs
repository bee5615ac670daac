//! The deck reader's state ([`Parser`]): the files read, the warnings,
//! the mesh so far, the records and commands of [`super::records`], the
//! current block. Its methods live in the files of the keyword families
//! they read (`impl Parser` in each); the driver is the module root.

use std::collections::HashMap;
use std::path::PathBuf;

use super::records::{
    Block, Cmd, DeckWarning, RawCoupling, RawElement, RawEquation, RawInteraction, RawMaterial,
    RawPair, RawSurface, StepState,
};

/// The reader: what was read so far and the block the next data line
/// belongs to.
pub(super) struct Parser {
    pub(super) files: Vec<PathBuf>,
    pub(super) warnings: Vec<DeckWarning>,
    pub(super) mesh: crate::fem::mesh::Mesh,
    pub(super) title: Vec<String>,
    pub(super) elements: Vec<RawElement>,
    pub(super) materials: Vec<RawMaterial>,
    pub(super) material_ids: HashMap<String, usize>,
    pub(super) current_material: Option<usize>,
    pub(super) surfaces: Vec<RawSurface>,
    pub(super) interactions: Vec<RawInteraction>,
    pub(super) current_interaction: Option<usize>,
    pub(super) pairs: Vec<RawPair>,
    pub(super) couplings: Vec<RawCoupling>,
    /// A `*COUPLING` whose `*KINEMATIC` must come next.
    pub(super) pending_coupling: Option<usize>,
    /// `*EQUATION`s, in deck order.
    pub(super) equations: Vec<RawEquation>,
    pub(super) names: Vec<String>,
    pub(super) name_ids: HashMap<String, u32>,
    pub(super) cmds: Vec<Cmd>,
    pub(super) block: Block,
    pub(super) step: StepState,
    pub(super) boundary_seen: bool,
    pub(super) cload_seen: bool,
    pub(super) dload_seen: bool,
    /// The first `*INITIAL CONDITIONS, TYPE=TEMPERATURE` (the deck has a
    /// thermal load: ccx's ithermal).
    pub(super) initial_temperature: Option<super::records::Loc>,
}
