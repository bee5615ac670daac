//! What the deck reader keeps while it reads: source positions and keyword
//! cards, the records of elements, materials, surfaces, interactions,
//! contact pairs and couplings as read, the step state, the commands
//! replayed at the end and the block the next data line belongs to. Plain
//! data: the reader ([`super::parser::Parser`]) and the keyword files fill
//! it.

use crate::fem::contact_definition::{Friction, PressureOverclosure};
use crate::fem::mesh::ElementKind;

/// Source position: index into `Parser::files` and 1-based line.
#[derive(Clone, Copy, Debug)]
pub(super) struct Loc {
    pub(super) file: usize,
    pub(super) line: usize,
}

/// A keyword line: upper-case name, parameters (upper-case key, raw value).
pub(super) struct Card {
    pub(super) name: String,
    pub(super) params: Vec<(String, Option<String>)>,
    pub(super) loc: Loc,
}
pub(super) struct RawSurface {
    pub(super) name: String,
    pub(super) node_type: bool,
    pub(super) loc: Loc,
}

pub(super) struct RawInteraction {
    pub(super) name: String,
    pub(super) behavior: Option<PressureOverclosure>,
    pub(super) friction: Option<Friction>,
    pub(super) loc: Loc,
}

pub(super) struct RawPair {
    pub(super) interaction: String,
    pub(super) slave: String,
    pub(super) master: String,
    pub(super) small_sliding: bool,
    pub(super) loc: Loc,
}
/// Which nodes a hub coupling holds.
pub(super) enum CouplingMembers {
    NodeSet(u32),
    /// All nodes of the elements of a set.
    ElementSet(u32),
    /// The nodes of a `*SURFACE` (faces: corner and midside nodes).
    Surface(String),
}

/// A `*RIGID BODY` or a `*COUPLING` + `*KINEMATIC` as read.
pub(super) struct RawCoupling {
    /// `RIGID BODY` or `COUPLING`.
    pub(super) keyword: &'static str,
    /// The set name (*RIGID BODY) or CONSTRAINT NAME (*COUPLING).
    pub(super) name: String,
    pub(super) members: CouplingMembers,
    pub(super) ref_node: u64,
    /// *RIGID BODY only: the node whose DOFs 1-3 are the rotations.
    pub(super) rot_node: Option<u64>,
    /// *COUPLING only: translations covered by the *KINEMATIC lines.
    pub(super) kinematic: [bool; 3],
    pub(super) loc: Loc,
}

/// An `*EQUATION` as read: the announced number of terms, the terms
/// (node label, DOF 0..=2, coefficient, line) and the line of the count.
pub(super) struct RawEquation {
    pub(super) count: usize,
    pub(super) terms: Vec<(u64, usize, f64, Loc)>,
    pub(super) loc: Loc,
}

/// What a reference node's DOFs are: (coupling, `true` for a ROT NODE).
#[derive(Clone, Copy)]
pub(super) struct RefRole {
    pub(super) coupling: usize,
    pub(super) rot: bool,
}
pub(super) struct RawMaterial {
    pub(super) name: String,
    pub(super) elastic: Option<(f64, f64)>,
    /// ρ of `*DENSITY` and its line.
    pub(super) density: Option<(f64, Loc)>,
    /// α of `*EXPANSION` and its line.
    pub(super) expansion: Option<(f64, Loc)>,
    /// The first further (temperature) line of its `*ELASTIC` or
    /// `*DENSITY`: a temperature-dependent constant, refused with a
    /// thermal load.
    pub(super) temperature_table: Option<Loc>,
    pub(super) loc: Loc,
}
pub(super) struct RawElement {
    pub(super) label: u64,
    pub(super) kind: ElementKind,
    pub(super) nodes: Vec<u64>,
    pub(super) loc: Loc,
}
/// Where the deck is relative to its (one) `*STEP`.
pub(super) enum StepState {
    Before,
    Open { loc: Loc, procedure: bool },
    Closed,
}
/// A non-fatal remark about a deck (something was ignored).
#[derive(Clone, Debug, PartialEq)]
pub struct DeckWarning {
    /// 1-based line the remark is about, 0 for the deck as a whole. For lines
    /// of an `*INCLUDE`d file the message names that file.
    pub line: usize,
    pub message: String,
}

/// A node/element given by label or by set (name id).
#[derive(Clone, Copy)]
pub(super) enum Target {
    Label(u64),
    Set(u32),
}

pub(super) enum SetItem {
    Label(u64),
    Set(u32),
    Range { first: u64, last: u64, step: u64 },
}

/// Commands replayed in file order once all nodes and elements are known.
pub(super) enum Cmd {
    NodeRange {
        set: u32,
        start: usize,
        end: usize,
    },
    ElemRange {
        set: u32,
        start: usize,
        end: usize,
    },
    Define {
        elem: bool,
        set: u32,
    },
    SetItem {
        elem: bool,
        set: u32,
        item: SetItem,
        loc: Loc,
    },
    Section {
        elset: u32,
        material: String,
        loc: Loc,
    },
    /// Components `first..=last` (0-based, 0..=5: rotations 3..=5 mean
    /// something only on a reference node) of the target nodes.
    Boundary {
        target: Target,
        first: usize,
        last: usize,
        value: f64,
        loc: Loc,
    },
    Cload {
        target: Target,
        comp: usize,
        value: f64,
        loc: Loc,
    },
    Dload {
        target: Target,
        face: usize,
        value: f64,
        loc: Loc,
    },
    /// `*DLOAD` GRAV or CENTRIF: a body force per unit mass.
    BodyLoad {
        target: Target,
        force: crate::fem::model::BodyForce,
        loc: Loc,
    },
    /// A data line of `*INITIAL CONDITIONS, TYPE=TEMPERATURE` (`initial`:
    /// sets T0 and T) or of the step's `*TEMPERATURE` (sets T).
    Temperature {
        target: Target,
        value: f64,
        initial: bool,
        loc: Loc,
    },
    /// `*RIGID BODY` number `coupling`: its node or element set is taken as
    /// it stands at this point of the deck.
    Coupling {
        coupling: usize,
    },
    /// A data line of `*SURFACE` number `surface`: element(s) with a face,
    /// or node(s) (`face == 0`).
    SurfaceItem {
        surface: usize,
        target: Target,
        face: usize,
        loc: Loc,
    },
}

/// What the data lines after the current keyword mean.
pub(super) enum Block {
    Start,
    Heading,
    Node {
        set: Option<u32>,
        start: usize,
        extra_warned: bool,
    },
    Element {
        kind: ElementKind,
        set: Option<u32>,
        start: usize,
        /// The last element still lacks node labels.
        open: bool,
    },
    Set {
        elem: bool,
        set: u32,
        generate: bool,
    },
    Elastic {
        material: usize,
        lines: usize,
        loc: Loc,
    },
    Density {
        material: usize,
        lines: usize,
        loc: Loc,
    },
    Expansion {
        material: usize,
        lines: usize,
        loc: Loc,
    },
    /// Data lines `node or set, temperature` of `*INITIAL CONDITIONS,
    /// TYPE=TEMPERATURE` (`initial`) or `*TEMPERATURE`.
    Temperature {
        initial: bool,
    },
    /// Keyword without data lines: a data line is an error.
    NoData(String),
    /// Data lines skipped silently.
    Ignore,
    /// At most one data line of numbers, skipped (`*STATIC`'s time stepping,
    /// `*SOLID SECTION`'s thickness): anything more is an error, since it is
    /// most likely a keyword line that lost its `*` and would be dropped.
    OneNumericLine {
        keyword: String,
        seen: bool,
    },
    Boundary,
    Cload,
    Dload,
    Surface {
        surface: usize,
        node_type: bool,
    },
    SurfaceBehavior {
        interaction: usize,
        linear: bool,
        lines: usize,
    },
    Friction {
        interaction: usize,
        lines: usize,
        loc: Loc,
    },
    ContactPair {
        interaction: String,
        small_sliding: bool,
    },
    /// Data lines of `*EQUATION`: `open` is the equation still reading
    /// terms (None: a term count comes next), `seen` whether any was read.
    Equation {
        open: Option<usize>,
        seen: bool,
        loc: Loc,
    },
    /// DOF lines of the `*KINEMATIC` of coupling `coupling`.
    Kinematic {
        coupling: usize,
        loc: Loc,
    },
}
