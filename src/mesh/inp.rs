//! CalculiX/Abaqus deck (`.inp`) reader and writer.
//!
//! The reader accepts the subset of the CalculiX (ccx 2.20) deck language that
//! describes one *linear static* analysis of C3D20/C3D20R/C3D15 solids and
//! turns it into a [`Model`]. Anything that would change the answer if it were
//! silently ignored (equations, distributing couplings, plasticity, temperatures, other
//! procedures, ...) is a [`FlankError::Parse`] with file and line; harmless
//! or unknown keywords become [`DeckWarning`]s. No input panics.
//!
//! Hub couplings (read into [`Model::couplings`] as [`RigidCoupling`]s):
//! `*RIGID BODY, NSET=|ELSET=, REF NODE=r[, ROT NODE=m]` (the set's nodes,
//! or all nodes of the element set, follow the rigid motion of r; r's DOFs
//! 1-3 are the reference translations, m's DOFs 1-3 its rotations; without
//! ROT NODE the rotations are free and unloaded, as in ccx, which then
//! creates a node no card can reach; without REF NODE it is an error), and
//! `*COUPLING, REF NODE=r, SURFACE=s, CONSTRAINT NAME=c` followed by
//! `*KINEMATIC` with DOF lines `first[, last]` that must cover 1-3 (ccx
//! couples translations only, DOFs ≤ 3; a partial coupling is refused); the
//! rotations are then DOFs 4-6 of r. Both are model data (before *STEP).
//! The reference point is r's position. `*BOUNDARY` on a reference DOF
//! fixes it (zero only: a prescribed reference motion is an error), `*CLOAD`
//! on it is the reference force (N) or moment (N·mm); every other reference
//! DOF is free. REF and ROT nodes must belong to no element and serve one
//! coupling; they are *not* mesh nodes of the model (their motion is the
//! solution's `coupling_motion`, not a row of `displacements.csv`). Errors
//! (with file and line): undefined or element-attached reference nodes, an
//! empty set or surface, a node in two couplings, a `*BOUNDARY` on a coupled
//! node, DOFs a rigid body's reference nodes do not have, `*DISTRIBUTING`
//! (distributing coupling: not rigid), `ORIENTATION`, `PINNSET`.
//!
//! Contact (read into [`Model::contact`]): `*SURFACE` (TYPE=ELEMENT with
//! `element or elset, Sn` lines, TYPE=NODE with `node or nset` lines),
//! `*SURFACE INTERACTION` with `*SURFACE BEHAVIOR` (PRESSURE-OVERCLOSURE=
//! HARD, or LINEAR with `slope[, σ∞[, c₀]]`, slope optional) and `*FRICTION`
//! (`μ[, stick slope]`), `*CONTACT PAIR` (TYPE=NODE TO SURFACE, optional
//! SMALL SLIDING; lines `slave, master`). Other contact types and laws are
//! errors; `*CONTACT PRINT/FILE/OUTPUT` are accepted output requests.
//!
//! A keyword line ending with a comma continues on the next line when that
//! line holds parameters (Abaqus); ccx 2.20 has no such continuation and
//! stops on it, so accepting it cannot change an answer. A trailing comma
//! followed by data is just ignored, as in ccx.
//!
//! Parsing is two-phase and linear in the deck size:
//! 1. lines are read once (following `*INCLUDE`); nodes are stored at once,
//!    everything that refers to nodes, elements or sets is recorded together
//!    with its source line;
//! 2. at the end, element connectivity is resolved (so `*NODE` may follow
//!    `*ELEMENT`) and the recorded set, section, boundary and load commands
//!    are replayed in file order.
//!
//! The writer produces a deck that ccx runs and [`parse_deck`] reads back to
//! the same model (rigid couplings as `*RIGID BODY` with two fresh reference
//! nodes each, see [`format_deck`]). ccx reads real numbers from the first 20 characters of a
//! field only (`f20.0`), so every real is written in the shortest form that
//! fits in 20 characters: exact (bit-for-bit round trip) whenever such a form
//! exists, otherwise rounded to as many significant digits as fit: at least
//! 15 (relative error ≤ 5e-15) for 1e-9 ≤ |x| < 1e10, at least 13 anywhere.
//! Every value with 0.01 ≤ |x| < 1e26 (and 0) is exact; below that, values
//! needing 16-17 significant digits (e.g. -0.0019289749616291370) may be
//! rounded.

use std::collections::{HashMap, HashSet};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::error::{FlankError, Result};
use crate::fem::contact_definition::{
    ContactDefinition, ContactPair, Friction, PressureOverclosure, Surface, SurfaceInteraction,
    SurfaceKind,
};
use crate::fem::material::Material;
use crate::fem::model::{Dirichlet, Model, NodalForce, Pressure, RigidCoupling};
use crate::mesh::ElementKind;

/// A non-fatal remark about a deck (something was ignored).
#[derive(Clone, Debug, PartialEq)]
pub struct DeckWarning {
    /// 1-based line the remark is about, 0 for the deck as a whole. For lines
    /// of an `*INCLUDE`d file the message names that file.
    pub line: usize,
    pub message: String,
}

/// A parsed deck: the model plus what was ignored on the way.
#[derive(Clone, Debug)]
pub struct Deck {
    pub model: Model,
    pub warnings: Vec<DeckWarning>,
    /// Text of the `*HEADING` block, if any.
    pub title: Option<String>,
}

/// Reads and parses a deck file, following `*INCLUDE, INPUT=...` (relative
/// paths are relative to the including file). Invalid UTF-8 is replaced, not
/// rejected, so Latin-1 comments do not stop a deck.
pub fn read_deck(path: &Path) -> Result<Deck> {
    let text = read_text(path).map_err(|e| FlankError::io(path, e))?;
    parse_deck(&text, path)
}

/// Parses deck text; `file` is used for error messages and to resolve
/// `*INCLUDE` paths.
pub fn parse_deck(text: &str, file: &Path) -> Result<Deck> {
    let mut parser = Parser::new(file);
    parser.run(text, 0, 0)?;
    parser.finish()
}

fn read_text(path: &Path) -> std::io::Result<String> {
    let bytes = std::fs::read(path)?;
    Ok(match String::from_utf8(bytes) {
        Ok(s) => s,
        Err(e) => String::from_utf8_lossy(e.as_bytes()).into_owned(),
    })
}

// ---------------------------------------------------------------------------
// Keyword tables
// ---------------------------------------------------------------------------

/// Output requests: accepted, data lines skipped silently.
const OUTPUT_KEYWORDS: &[&str] = &[
    "NODE PRINT",
    "EL PRINT",
    "NODE FILE",
    "EL FILE",
    "NODE OUTPUT",
    "ELEMENT OUTPUT",
    "OUTPUT",
    "CONTACT PRINT",
    "CONTACT FILE",
    "CONTACT OUTPUT",
];

/// Keywords that cannot be ignored without changing the answer, with the reason.
const FATAL_KEYWORDS: &[(&str, &str)] = &[
    ("EQUATION", "linear multi-point constraints"),
    ("MPC", "multi-point constraints"),
    (
        "DISTRIBUTING",
        "distributing coupling: the reference load is spread over the surface, the nodes are not held rigid; only *KINEMATIC maps onto flank's rigid coupling",
    ),
    (
        "DISTRIBUTING COUPLING",
        "distributing coupling: the nodes are not held rigid; only *COUPLING + *KINEMATIC or *RIGID BODY",
    ),
    (
        "KINEMATIC COUPLING",
        "Abaqus kinematic coupling; write it as *COUPLING + *KINEMATIC or *RIGID BODY",
    ),
    ("TIE", "tied surfaces"),
    ("CLEARANCE", "contact clearances"),
    ("GAP", "gap elements"),
    ("CONTACT DAMPING", "contact damping"),
    ("GAP CONDUCTANCE", "thermal contact"),
    ("PLASTIC", "plasticity"),
    ("DEFORMATION PLASTICITY", "plasticity"),
    ("CREEP", "creep"),
    ("HYPERELASTIC", "hyperelasticity"),
    ("HYPERFOAM", "hyperelasticity"),
    ("USER MATERIAL", "user materials"),
    ("TEMPERATURE", "thermal loads"),
    ("INITIAL CONDITIONS", "initial conditions"),
    ("TRANSFORM", "local coordinate systems"),
    ("ORIENTATION", "local material directions"),
    ("FREQUENCY", "not a linear static step"),
    ("BUCKLE", "not a linear static step"),
    ("DYNAMIC", "not a linear static step"),
    ("MODAL DYNAMIC", "not a linear static step"),
    ("STEADY STATE DYNAMICS", "not a linear static step"),
    ("COMPLEX FREQUENCY", "not a linear static step"),
    ("HEAT TRANSFER", "not a linear static step"),
    (
        "COUPLED TEMPERATURE-DISPLACEMENT",
        "not a linear static step",
    ),
    (
        "UNCOUPLED TEMPERATURE-DISPLACEMENT",
        "not a linear static step",
    ),
    ("VISCO", "not a linear static step"),
    ("GREEN", "not a linear static step"),
    ("SENSITIVITY", "not a linear static step"),
    ("ELECTROMAGNETICS", "not a linear static step"),
    ("NO ANALYSIS", "not a linear static step"),
    ("SUBSTRUCTURE GENERATE", "not a linear static step"),
    ("SPRING", "spring elements"),
    ("DASHPOT", "dashpot elements"),
    ("BEAM SECTION", "beam elements"),
    ("BEAM GENERAL SECTION", "beam elements"),
    ("SHELL SECTION", "shell elements"),
    ("MEMBRANE SECTION", "membrane elements"),
    ("PRE-TENSION SECTION", "pre-tension"),
    ("DSLOAD", "surface loads"),
    ("CHANGE MATERIAL", "changed materials"),
    ("CHANGE SOLID SECTION", "changed sections"),
    ("MODEL CHANGE", "element removal"),
    ("SUBMODEL", "submodel boundary conditions"),
    ("CYCLIC SYMMETRY MODEL", "cyclic symmetry"),
];

/// Known keywords without effect on a linear static answer: warned and skipped.
const HARMLESS_KEYWORDS: &[&str] = &[
    "DENSITY",
    "EXPANSION",
    "CONDUCTIVITY",
    "SPECIFIC HEAT",
    "DAMPING",
    "AMPLITUDE",
    "MASS",
    "PHYSICAL CONSTANTS",
    "RESTART",
    "CONTROLS",
    "TIME POINTS",
    "NORMAL",
];

/// Keywords that belong to the current `*MATERIAL` (do not end it).
const MATERIAL_KEYWORDS: &[&str] = &[
    "ELASTIC",
    "DENSITY",
    "EXPANSION",
    "CONDUCTIVITY",
    "SPECIFIC HEAT",
    "DAMPING",
];

/// Keywords that belong to the current `*SURFACE INTERACTION`.
const INTERACTION_KEYWORDS: &[&str] = &["SURFACE BEHAVIOR", "FRICTION"];

/// Nesting limit for `*INCLUDE` (also stops include cycles).
const MAX_INCLUDE_DEPTH: usize = 16;

// ---------------------------------------------------------------------------
// Parser state
// ---------------------------------------------------------------------------

/// Source position: index into `Parser::files` and 1-based line.
#[derive(Clone, Copy, Debug)]
struct Loc {
    file: usize,
    line: usize,
}

/// A keyword line: upper-case name, parameters (upper-case key, raw value).
struct Card {
    name: String,
    params: Vec<(String, Option<String>)>,
    loc: Loc,
}

/// A node/element given by label or by set (name id).
#[derive(Clone, Copy)]
enum Target {
    Label(u64),
    Set(u32),
}

enum SetItem {
    Label(u64),
    Set(u32),
    Range { first: u64, last: u64, step: u64 },
}

/// Commands replayed in file order once all nodes and elements are known.
enum Cmd {
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

/// Which nodes a hub coupling holds.
enum CouplingMembers {
    NodeSet(u32),
    /// All nodes of the elements of a set.
    ElementSet(u32),
    /// The nodes of a `*SURFACE` (faces: corner and midside nodes).
    Surface(String),
}

/// A `*RIGID BODY` or a `*COUPLING` + `*KINEMATIC` as read.
struct RawCoupling {
    /// `RIGID BODY` or `COUPLING`.
    keyword: &'static str,
    /// The set name (*RIGID BODY) or CONSTRAINT NAME (*COUPLING).
    name: String,
    members: CouplingMembers,
    ref_node: u64,
    /// *RIGID BODY only: the node whose DOFs 1-3 are the rotations.
    rot_node: Option<u64>,
    /// *COUPLING only: translations covered by the *KINEMATIC lines.
    kinematic: [bool; 3],
    loc: Loc,
}

/// What a reference node's DOFs are: (coupling, `true` for a ROT NODE).
#[derive(Clone, Copy)]
struct RefRole {
    coupling: usize,
    rot: bool,
}

struct RawSurface {
    name: String,
    node_type: bool,
    loc: Loc,
}

struct RawInteraction {
    name: String,
    behavior: Option<PressureOverclosure>,
    friction: Option<Friction>,
    loc: Loc,
}

struct RawPair {
    interaction: String,
    slave: String,
    master: String,
    small_sliding: bool,
    loc: Loc,
}

struct RawElement {
    label: u64,
    kind: ElementKind,
    nodes: Vec<u64>,
    loc: Loc,
}

struct RawMaterial {
    name: String,
    elastic: Option<(f64, f64)>,
    loc: Loc,
}

/// What the data lines after the current keyword mean.
enum Block {
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
    /// Keyword without data lines: a data line is an error.
    NoData(String),
    /// Data lines skipped silently.
    Ignore,
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
    /// DOF lines of the `*KINEMATIC` of coupling `coupling`.
    Kinematic {
        coupling: usize,
        loc: Loc,
    },
}

enum StepState {
    Before,
    Open { loc: Loc, procedure: bool },
    Closed,
}

/// Unique members of a set in insertion order; a bitmap makes inserts O(1).
#[derive(Default)]
struct IdxSet {
    members: Vec<usize>,
    bits: Vec<u64>,
}

impl IdxSet {
    fn insert(&mut self, i: usize) {
        let w = i / 64;
        if w >= self.bits.len() {
            self.bits.resize(w + 1, 0);
        }
        let m = 1u64 << (i % 64);
        if self.bits[w] & m == 0 {
            self.bits[w] |= m;
            self.members.push(i);
        }
    }
}

struct Parser {
    files: Vec<PathBuf>,
    warnings: Vec<DeckWarning>,
    mesh: crate::mesh::Mesh,
    title: Vec<String>,
    elements: Vec<RawElement>,
    materials: Vec<RawMaterial>,
    material_ids: HashMap<String, usize>,
    current_material: Option<usize>,
    surfaces: Vec<RawSurface>,
    interactions: Vec<RawInteraction>,
    current_interaction: Option<usize>,
    pairs: Vec<RawPair>,
    couplings: Vec<RawCoupling>,
    /// A `*COUPLING` whose `*KINEMATIC` must come next.
    pending_coupling: Option<usize>,
    names: Vec<String>,
    name_ids: HashMap<String, u32>,
    cmds: Vec<Cmd>,
    block: Block,
    step: StepState,
    boundary_seen: bool,
    cload_seen: bool,
    dload_seen: bool,
}

/// Upper-case name without surrounding blanks or quotes.
fn norm_name(raw: &str) -> String {
    raw.trim().trim_matches('"').trim().to_ascii_uppercase()
}

/// Keyword names compare upper-case with single blanks ("END  STEP" = "END STEP").
fn norm_keyword(raw: &str) -> String {
    raw.split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
        .to_ascii_uppercase()
}

/// Whether a token is meant as a number (labels and set names are told apart
/// by their first character; set names start with a letter).
fn looks_numeric(tok: &str) -> bool {
    tok.starts_with(|c: char| c.is_ascii_digit() || matches!(c, '+' | '-' | '.'))
}

/// Parameters that may stand without `=value` on a continuation line.
const FLAG_PARAMETERS: &[&str] = &["GENERATE", "UNSORTED", "NLGEOM", "PERTURBATION"];

/// Whether a line continues a keyword line: its first field is `KEY=VALUE`
/// or a flag parameter (data lines are numbers or set names).
fn looks_like_parameters(line: &str) -> bool {
    let first = line.split(',').next().unwrap_or("").trim();
    !line.starts_with('*')
        && (first.contains('=') || FLAG_PARAMETERS.contains(&norm_keyword(first).as_str()))
}

/// Comma-separated fields, trimmed, without trailing empty fields.
fn split_fields(text: &str) -> Vec<&str> {
    let mut f: Vec<&str> = text.split(',').map(str::trim).collect();
    while f.last().is_some_and(|s| s.is_empty()) {
        f.pop();
    }
    f
}

impl Parser {
    fn new(file: &Path) -> Self {
        Parser {
            files: vec![file.to_path_buf()],
            warnings: Vec::new(),
            mesh: crate::mesh::Mesh::new(),
            title: Vec::new(),
            elements: Vec::new(),
            materials: Vec::new(),
            material_ids: HashMap::new(),
            current_material: None,
            surfaces: Vec::new(),
            interactions: Vec::new(),
            current_interaction: None,
            pairs: Vec::new(),
            couplings: Vec::new(),
            pending_coupling: None,
            names: Vec::new(),
            name_ids: HashMap::new(),
            cmds: Vec::new(),
            block: Block::Start,
            step: StepState::Before,
            boundary_seen: false,
            cload_seen: false,
            dload_seen: false,
        }
    }

    fn err(&self, loc: Loc, message: impl Into<String>) -> FlankError {
        FlankError::Parse {
            file: self.files[loc.file].clone(),
            line: loc.line,
            message: message.into(),
        }
    }

    fn warn(&mut self, loc: Loc, message: impl Into<String>) {
        let mut message = message.into();
        if loc.file != 0 {
            message = format!("{message} (in {})", self.files[loc.file].display());
        }
        self.warnings.push(DeckWarning {
            line: loc.line,
            message,
        });
    }

    /// Reads the lines of one file. `*INCLUDE` is handled here, transparently:
    /// the included lines continue the current keyword block (Abaqus allows
    /// data-only include files).
    fn run(&mut self, text: &str, file: usize, depth: usize) -> Result<()> {
        let text = text.strip_prefix('\u{feff}').unwrap_or(text);
        let mut lines = text.lines().enumerate().peekable();
        while let Some((i, raw)) = lines.next() {
            let loc = Loc { file, line: i + 1 };
            let t = raw.trim();
            if t.is_empty() || t.starts_with("**") {
                continue;
            }
            let Some(kw) = t.strip_prefix('*') else {
                self.data(t, loc)?;
                continue;
            };
            // A keyword line ending with a comma continues on the next line
            // if that line holds parameters (Abaqus); otherwise the comma is
            // a harmless trailing one and the next line is data (ccx).
            let mut kw = kw.to_string();
            while kw.trim_end().ends_with(',') {
                let Some(&(_, next)) = lines.peek() else {
                    break;
                };
                let n = next.trim();
                if n.starts_with("**") {
                    lines.next();
                    continue;
                }
                if !looks_like_parameters(n) {
                    break;
                }
                kw.push_str(n);
                lines.next();
            }
            let card = self.parse_card(&kw, loc)?;
            if card.name == "INCLUDE" {
                self.include(&card, depth)?;
            } else {
                self.keyword(card)?;
            }
        }
        Ok(())
    }

    fn parse_card(&self, kw: &str, loc: Loc) -> Result<Card> {
        let mut parts = kw.split(',');
        let name = norm_keyword(parts.next().unwrap_or(""));
        if name.is_empty() {
            return Err(self.err(loc, "empty keyword ('*' without a name)"));
        }
        let mut params = Vec::new();
        for p in parts {
            let p = p.trim();
            if p.is_empty() {
                continue;
            }
            let (key, value) = match p.split_once('=') {
                Some((k, v)) => (norm_keyword(k), Some(v.trim().to_string())),
                None => (norm_keyword(p), None),
            };
            if key.is_empty() {
                return Err(self.err(loc, format!("malformed parameter '{p}' on *{name}")));
            }
            params.push((key, value));
        }
        Ok(Card { name, params, loc })
    }

    /// Rejects parameters not in `allowed` (an unknown parameter might change
    /// the meaning of the data).
    fn check_params(&self, card: &Card, allowed: &[&str]) -> Result<()> {
        for (k, _) in &card.params {
            if !allowed.contains(&k.as_str()) {
                return Err(self.err(
                    card.loc,
                    format!("parameter {k} on *{} is not supported", card.name),
                ));
            }
        }
        Ok(())
    }

    /// Value of parameter `key` (raw text); present without `=value` is an error.
    fn value(&self, card: &Card, key: &str) -> Result<Option<String>> {
        match card.params.iter().find(|(k, _)| k == key) {
            None => Ok(None),
            Some((_, Some(v))) if !v.is_empty() => Ok(Some(v.clone())),
            Some(_) => Err(self.err(
                card.loc,
                format!(
                    "parameter {key} on *{} needs a value ({key}=...)",
                    card.name
                ),
            )),
        }
    }

    fn required(&self, card: &Card, key: &str) -> Result<String> {
        self.value(card, key)?.ok_or_else(|| {
            self.err(
                card.loc,
                format!("*{} needs the parameter {key}=...", card.name),
            )
        })
    }

    fn flag(card: &Card, key: &str) -> bool {
        card.params.iter().any(|(k, _)| k == key)
    }

    /// Id of a set name (upper-cased; node and element sets share ids but
    /// not namespaces).
    fn intern(&mut self, raw: &str, loc: Loc) -> Result<u32> {
        let name = norm_name(raw);
        if name.is_empty() {
            return Err(self.err(loc, "empty set name"));
        }
        if let Some(&id) = self.name_ids.get(&name) {
            return Ok(id);
        }
        let id = self.names.len() as u32;
        self.names.push(name.clone());
        self.name_ids.insert(name, id);
        Ok(id)
    }

    fn include(&mut self, card: &Card, depth: usize) -> Result<()> {
        self.check_params(card, &["INPUT"])?;
        let input = self.required(card, "INPUT")?;
        let input = input.trim().trim_matches(|c| c == '"' || c == '\'').trim();
        if depth >= MAX_INCLUDE_DEPTH {
            return Err(self.err(
                card.loc,
                format!("*INCLUDE nested more than {MAX_INCLUDE_DEPTH} deep (include cycle?)"),
            ));
        }
        let rel = Path::new(input);
        let path = match self.files[card.loc.file].parent() {
            Some(dir) if rel.is_relative() => dir.join(rel),
            _ => rel.to_path_buf(),
        };
        let text = read_text(&path).map_err(|e| {
            self.err(
                card.loc,
                format!("cannot read *INCLUDE file '{}': {e}", path.display()),
            )
        })?;
        self.files.push(path);
        let id = self.files.len() - 1;
        self.run(&text, id, depth + 1)
    }

    // -- keywords -----------------------------------------------------------

    /// Closes the current block: records node/element set ranges and checks
    /// that elements and *ELASTIC are complete.
    fn end_block(&mut self) -> Result<()> {
        match std::mem::replace(&mut self.block, Block::Ignore) {
            Block::Node {
                set: Some(set),
                start,
                ..
            } => self.cmds.push(Cmd::NodeRange {
                set,
                start,
                end: self.mesh.node_count(),
            }),
            Block::Element {
                kind,
                set,
                start,
                open,
            } => {
                if open {
                    if let Some(el) = self.elements.last() {
                        return Err(self.err(
                            el.loc,
                            format!(
                                "incomplete element {}: {} of {} node labels given",
                                el.label,
                                el.nodes.len(),
                                kind.node_count()
                            ),
                        ));
                    }
                }
                if let Some(set) = set {
                    self.cmds.push(Cmd::ElemRange {
                        set,
                        start,
                        end: self.elements.len(),
                    });
                }
            }
            Block::Elastic { lines: 0, loc, .. } => {
                return Err(self.err(loc, "*ELASTIC without data line (E, nu)"))
            }
            Block::Friction { lines: 0, loc, .. } => {
                return Err(self.err(loc, "*FRICTION without data line (mu[, stick slope])"))
            }
            Block::Kinematic { coupling, loc } => {
                let k = self.couplings[coupling].kinematic;
                if !k.iter().any(|&b| b) {
                    return Err(self.err(
                        loc,
                        "*KINEMATIC without DOF lines couples nothing (ccx generates no constraint); give '1, 3'",
                    ));
                }
                if !k.iter().all(|&b| b) {
                    let given: Vec<String> = (0..3)
                        .filter(|&i| k[i])
                        .map(|i| (i + 1).to_string())
                        .collect();
                    return Err(self.err(
                        loc,
                        format!(
                            "*KINEMATIC couples only DOF(s) {} of the surface nodes: flank's rigid coupling holds all three translations (give '1, 3'); a partial kinematic coupling is not supported",
                            given.join(", ")
                        ),
                    ));
                }
            }
            _ => {}
        }
        Ok(())
    }

    fn keyword(&mut self, card: Card) -> Result<()> {
        self.end_block()?;
        let loc = card.loc;
        let name = card.name.clone();
        let pending = self.pending_coupling.take();
        if let Some(c) = pending {
            if name != "KINEMATIC" {
                let line = self.couplings[c].loc.line;
                if name.starts_with("DISTRIBUTING") {
                    return Err(self.err(
                        loc,
                        format!("*{name} after the *COUPLING of line {line} is not supported (distributing coupling: the reference load is spread over the surface by weights, the nodes are not held rigid); only *KINEMATIC, which flank maps onto its rigid coupling"),
                    ));
                }
                return Err(self.err(
                    self.couplings[c].loc,
                    format!(
                        "*COUPLING must be followed by *KINEMATIC (found *{name} at line {})",
                        loc.line
                    ),
                ));
            }
        }
        if !MATERIAL_KEYWORDS.contains(&name.as_str()) {
            self.current_material = None;
        }
        if !INTERACTION_KEYWORDS.contains(&name.as_str()) {
            self.current_interaction = None;
        }
        self.block = match name.as_str() {
            "HEADING" => Block::Heading,
            "NODE" => self.kw_node(&card)?,
            "ELEMENT" => self.kw_element(&card)?,
            "NSET" => self.kw_set(&card, false)?,
            "ELSET" => self.kw_set(&card, true)?,
            "MATERIAL" => self.kw_material(&card)?,
            "ELASTIC" => self.kw_elastic(&card)?,
            "SOLID SECTION" => self.kw_section(&card)?,
            "SURFACE" => self.kw_surface(&card)?,
            "SURFACE INTERACTION" => self.kw_interaction(&card)?,
            "SURFACE BEHAVIOR" => self.kw_behavior(&card)?,
            "FRICTION" => self.kw_friction(&card)?,
            "CONTACT PAIR" => self.kw_contact_pair(&card)?,
            "RIGID BODY" => self.kw_rigid_body(&card)?,
            "COUPLING" => self.kw_coupling(&card)?,
            "KINEMATIC" => self.kw_kinematic(&card, pending)?,
            "STEP" => self.kw_step(&card)?,
            "STATIC" => {
                match &mut self.step {
                    StepState::Open { procedure, .. } => *procedure = true,
                    _ => return Err(self.err(loc, "*STATIC outside of a *STEP")),
                }
                Block::Ignore
            }
            "END STEP" => {
                match self.step {
                    StepState::Open {
                        procedure: false, ..
                    } => return Err(self.err(loc, "*END STEP: the step has no *STATIC procedure")),
                    StepState::Open { .. } => self.step = StepState::Closed,
                    _ => return Err(self.err(loc, "*END STEP without *STEP")),
                }
                Block::NoData(name)
            }
            "BOUNDARY" => {
                if matches!(self.step, StepState::Closed) {
                    return Err(
                        self.err(loc, "*BOUNDARY after *END STEP: only one step is supported")
                    );
                }
                self.load_params(&card, self.boundary_seen)?;
                self.boundary_seen = true;
                Block::Boundary
            }
            "CLOAD" | "DLOAD" => {
                if !matches!(self.step, StepState::Open { .. }) {
                    return Err(self.err(
                        loc,
                        format!("*{name} outside of a *STEP (loads are step data)"),
                    ));
                }
                if name == "CLOAD" {
                    self.load_params(&card, self.cload_seen)?;
                    self.cload_seen = true;
                    Block::Cload
                } else {
                    self.load_params(&card, self.dload_seen)?;
                    self.dload_seen = true;
                    Block::Dload
                }
            }
            n if OUTPUT_KEYWORDS.contains(&n) => Block::Ignore,
            n => {
                if let Some((_, why)) = FATAL_KEYWORDS.iter().find(|(k, _)| *k == n) {
                    return Err(self.err(
                        loc,
                        format!(
                            "*{n} is not supported ({why}); ignoring it would change the answer"
                        ),
                    ));
                }
                if HARMLESS_KEYWORDS.contains(&n) {
                    self.warn(
                        loc,
                        format!("*{n} ignored (no effect on a linear static analysis)"),
                    );
                } else {
                    self.warn(
                        loc,
                        format!("unknown keyword *{n} ignored (data lines skipped)"),
                    );
                }
                Block::Ignore
            }
        };
        Ok(())
    }

    fn kw_node(&mut self, card: &Card) -> Result<Block> {
        self.check_params(card, &["NSET", "SYSTEM"])?;
        if let Some(sys) = self.value(card, "SYSTEM")? {
            if !sys.trim().eq_ignore_ascii_case("R") {
                return Err(self.err(
                    card.loc,
                    format!("*NODE, SYSTEM={sys}: only rectangular coordinates (SYSTEM=R) are supported"),
                ));
            }
        }
        let set = match self.value(card, "NSET")? {
            Some(v) => Some(self.intern(&v, card.loc)?),
            None => None,
        };
        Ok(Block::Node {
            set,
            start: self.mesh.node_count(),
            extra_warned: false,
        })
    }

    fn kw_element(&mut self, card: &Card) -> Result<Block> {
        self.check_params(card, &["TYPE", "ELSET"])?;
        let ty = self.required(card, "TYPE")?;
        let kind = ElementKind::from_name(&ty).ok_or_else(|| {
            self.err(
                card.loc,
                format!(
                    "unsupported element type {} (supported: C3D20, C3D20R, C3D15)",
                    norm_name(&ty)
                ),
            )
        })?;
        let set = match self.value(card, "ELSET")? {
            Some(v) => Some(self.intern(&v, card.loc)?),
            None => None,
        };
        Ok(Block::Element {
            kind,
            set,
            start: self.elements.len(),
            open: false,
        })
    }

    fn kw_set(&mut self, card: &Card, elem: bool) -> Result<Block> {
        let key = if elem { "ELSET" } else { "NSET" };
        self.check_params(card, &[key, "GENERATE", "UNSORTED"])?;
        let name = self.required(card, key)?;
        let set = self.intern(&name, card.loc)?;
        self.cmds.push(Cmd::Define { elem, set });
        Ok(Block::Set {
            elem,
            set,
            generate: Self::flag(card, "GENERATE"),
        })
    }

    fn kw_material(&mut self, card: &Card) -> Result<Block> {
        self.check_params(card, &["NAME"])?;
        let name = norm_name(&self.required(card, "NAME")?);
        if name.is_empty() {
            return Err(self.err(card.loc, "empty material name"));
        }
        if let Some(&m) = self.material_ids.get(&name) {
            let first = self.materials[m].loc.line;
            return Err(self.err(
                card.loc,
                format!("material {name} defined twice (first at line {first})"),
            ));
        }
        self.material_ids.insert(name.clone(), self.materials.len());
        self.current_material = Some(self.materials.len());
        self.materials.push(RawMaterial {
            name,
            elastic: None,
            loc: card.loc,
        });
        Ok(Block::NoData(card.name.clone()))
    }

    fn kw_elastic(&mut self, card: &Card) -> Result<Block> {
        self.check_params(card, &["TYPE"])?;
        if let Some(t) = self.value(card, "TYPE")? {
            let t = norm_name(&t);
            if t != "ISO" && t != "ISOTROPIC" {
                return Err(self.err(
                    card.loc,
                    format!("*ELASTIC, TYPE={t} is not supported (only isotropic); ignoring it would change the answer"),
                ));
            }
        }
        let Some(material) = self.current_material else {
            return Err(self.err(card.loc, "*ELASTIC outside of a *MATERIAL"));
        };
        if self.materials[material].elastic.is_some() {
            return Err(self.err(
                card.loc,
                format!(
                    "second *ELASTIC for material {}",
                    self.materials[material].name
                ),
            ));
        }
        Ok(Block::Elastic {
            material,
            lines: 0,
            loc: card.loc,
        })
    }

    fn kw_section(&mut self, card: &Card) -> Result<Block> {
        if Self::flag(card, "ORIENTATION") {
            return Err(self.err(
                card.loc,
                "*SOLID SECTION, ORIENTATION=... is not supported; ignoring it would change the answer",
            ));
        }
        self.check_params(card, &["ELSET", "MATERIAL"])?;
        let elset = self.required(card, "ELSET")?;
        let elset = self.intern(&elset, card.loc)?;
        let material = norm_name(&self.required(card, "MATERIAL")?);
        self.cmds.push(Cmd::Section {
            elset,
            material,
            loc: card.loc,
        });
        // A data line (plane-element thickness) is meaningless for solids.
        Ok(Block::Ignore)
    }

    fn kw_surface(&mut self, card: &Card) -> Result<Block> {
        self.check_params(card, &["NAME", "TYPE"])?;
        let name = norm_name(&self.required(card, "NAME")?);
        if name.is_empty() {
            return Err(self.err(card.loc, "empty surface name"));
        }
        let node_type = match self.value(card, "TYPE")?.map(|t| norm_name(&t)) {
            None => false,
            Some(t) if t == "ELEMENT" => false,
            Some(t) if t == "NODE" => true,
            Some(t) => {
                return Err(self.err(
                    card.loc,
                    format!("*SURFACE, TYPE={t} is not supported (ELEMENT or NODE)"),
                ))
            }
        };
        if let Some(first) = self.surfaces.iter().find(|s| s.name == name) {
            return Err(self.err(
                card.loc,
                format!(
                    "surface {name} defined twice (first at line {})",
                    first.loc.line
                ),
            ));
        }
        self.surfaces.push(RawSurface {
            name,
            node_type,
            loc: card.loc,
        });
        Ok(Block::Surface {
            surface: self.surfaces.len() - 1,
            node_type,
        })
    }

    fn kw_interaction(&mut self, card: &Card) -> Result<Block> {
        self.check_params(card, &["NAME"])?;
        let name = norm_name(&self.required(card, "NAME")?);
        if name.is_empty() {
            return Err(self.err(card.loc, "empty surface interaction name"));
        }
        if let Some(first) = self.interactions.iter().find(|s| s.name == name) {
            return Err(self.err(
                card.loc,
                format!(
                    "surface interaction {name} defined twice (first at line {})",
                    first.loc.line
                ),
            ));
        }
        self.current_interaction = Some(self.interactions.len());
        self.interactions.push(RawInteraction {
            name,
            behavior: None,
            friction: None,
            loc: card.loc,
        });
        Ok(Block::NoData(card.name.clone()))
    }

    fn kw_behavior(&mut self, card: &Card) -> Result<Block> {
        self.check_params(card, &["PRESSURE-OVERCLOSURE"])?;
        let Some(interaction) = self.current_interaction else {
            return Err(self.err(
                card.loc,
                "*SURFACE BEHAVIOR outside of a *SURFACE INTERACTION",
            ));
        };
        if self.interactions[interaction].behavior.is_some() {
            return Err(self.err(
                card.loc,
                format!(
                    "second *SURFACE BEHAVIOR for surface interaction {}",
                    self.interactions[interaction].name
                ),
            ));
        }
        let law = self
            .value(card, "PRESSURE-OVERCLOSURE")?
            .map(|v| norm_name(&v))
            .unwrap_or_else(|| "HARD".into());
        let (behavior, linear) = match law.as_str() {
            "HARD" => (PressureOverclosure::Hard, false),
            "LINEAR" => (
                PressureOverclosure::Linear {
                    slope: None,
                    tension: None,
                    c0: None,
                },
                true,
            ),
            other => {
                return Err(self.err(
                    card.loc,
                    format!("*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE={other} is not supported (HARD or LINEAR); ignoring it would change the answer"),
                ))
            }
        };
        self.interactions[interaction].behavior = Some(behavior);
        Ok(Block::SurfaceBehavior {
            interaction,
            linear,
            lines: 0,
        })
    }

    fn kw_friction(&mut self, card: &Card) -> Result<Block> {
        self.check_params(card, &[])?;
        let Some(interaction) = self.current_interaction else {
            return Err(self.err(card.loc, "*FRICTION outside of a *SURFACE INTERACTION"));
        };
        if self.interactions[interaction].friction.is_some() {
            return Err(self.err(
                card.loc,
                format!(
                    "second *FRICTION for surface interaction {}",
                    self.interactions[interaction].name
                ),
            ));
        }
        Ok(Block::Friction {
            interaction,
            lines: 0,
            loc: card.loc,
        })
    }

    fn kw_contact_pair(&mut self, card: &Card) -> Result<Block> {
        for (k, _) in &card.params {
            if k == "ADJUST" {
                return Err(self.err(
                    card.loc,
                    "*CONTACT PAIR, ADJUST is not supported (it moves slave nodes); ignoring it would change the answer",
                ));
            }
        }
        self.check_params(card, &["INTERACTION", "TYPE", "SMALL SLIDING"])?;
        let interaction = norm_name(&self.required(card, "INTERACTION")?);
        if let Some(t) = self.value(card, "TYPE")? {
            let t = norm_keyword(&t);
            if t != "NODE TO SURFACE" && t != "NODE TO FACE" {
                return Err(self.err(
                    card.loc,
                    format!("*CONTACT PAIR, TYPE={t} is not supported (only NODE TO SURFACE)"),
                ));
            }
        }
        Ok(Block::ContactPair {
            interaction,
            small_sliding: Self::flag(card, "SMALL SLIDING"),
        })
    }

    /// Value of a parameter that ccx also accepts without blanks
    /// (`REF NODE=` or `REFNODE=`).
    fn value_either(&self, card: &Card, keys: [&str; 2]) -> Result<Option<String>> {
        match self.value(card, keys[0])? {
            Some(v) => Ok(Some(v)),
            None => self.value(card, keys[1]),
        }
    }

    /// Hub couplings are model data: ccx refuses them inside a step.
    fn coupling_before_step(&self, card: &Card) -> Result<()> {
        if matches!(self.step, StepState::Before) {
            Ok(())
        } else {
            Err(self.err(
                card.loc,
                format!(
                    "*{} must come before *STEP (model data; ccx refuses it too)",
                    card.name
                ),
            ))
        }
    }

    /// `*RIGID BODY, NSET=|ELSET=, REF NODE=n[, ROT NODE=m]`.
    fn kw_rigid_body(&mut self, card: &Card) -> Result<Block> {
        self.coupling_before_step(card)?;
        self.check_params(
            card,
            &[
                "NSET", "ELSET", "REF NODE", "REFNODE", "ROT NODE", "ROTNODE",
            ],
        )?;
        let members = match (self.value(card, "NSET")?, self.value(card, "ELSET")?) {
            (Some(n), None) => CouplingMembers::NodeSet(self.intern(&n, card.loc)?),
            (None, Some(e)) => CouplingMembers::ElementSet(self.intern(&e, card.loc)?),
            (Some(_), Some(_)) => {
                return Err(self.err(card.loc, "*RIGID BODY: give NSET or ELSET, not both"))
            }
            (None, None) => {
                return Err(self.err(card.loc, "*RIGID BODY needs NSET=... or ELSET=..."))
            }
        };
        let name = match &members {
            CouplingMembers::NodeSet(id) | CouplingMembers::ElementSet(id) => {
                self.names[*id as usize].clone()
            }
            CouplingMembers::Surface(s) => s.clone(),
        };
        let Some(r) = self.value_either(card, ["REF NODE", "REFNODE"])? else {
            return Err(self.err(
                card.loc,
                "*RIGID BODY needs REF NODE=... (ccx would create a reference node at the origin that no *BOUNDARY or *CLOAD can reach)",
            ));
        };
        let ref_node = self.parse_label(&r, card.loc)?;
        let rot_node = match self.value_either(card, ["ROT NODE", "ROTNODE"])? {
            Some(r) => Some(self.parse_label(&r, card.loc)?),
            None => None,
        };
        let coupling = self.couplings.len();
        self.couplings.push(RawCoupling {
            keyword: "RIGID BODY",
            name,
            members,
            ref_node,
            rot_node,
            kinematic: [true; 3],
            loc: card.loc,
        });
        self.cmds.push(Cmd::Coupling { coupling });
        Ok(Block::NoData(card.name.clone()))
    }

    /// `*COUPLING, REF NODE=n, SURFACE=s, CONSTRAINT NAME=c`; the
    /// `*KINEMATIC` must follow.
    fn kw_coupling(&mut self, card: &Card) -> Result<Block> {
        self.coupling_before_step(card)?;
        if Self::flag(card, "ORIENTATION") {
            return Err(self.err(
                card.loc,
                "*COUPLING, ORIENTATION=... is not supported (local directions); ignoring it would change the answer",
            ));
        }
        self.check_params(
            card,
            &[
                "REF NODE",
                "REFNODE",
                "SURFACE",
                "CONSTRAINT NAME",
                "CONSTRAINTNAME",
            ],
        )?;
        let Some(r) = self.value_either(card, ["REF NODE", "REFNODE"])? else {
            return Err(self.err(card.loc, "*COUPLING needs the parameter REF NODE=..."));
        };
        let ref_node = self.parse_label(&r, card.loc)?;
        let surface = norm_name(&self.required(card, "SURFACE")?);
        let Some(name) = self.value_either(card, ["CONSTRAINT NAME", "CONSTRAINTNAME"])? else {
            return Err(self.err(
                card.loc,
                "*COUPLING needs the parameter CONSTRAINT NAME=... (ccx requires it)",
            ));
        };
        let name = norm_name(&name);
        if let Some(first) = self
            .couplings
            .iter()
            .find(|c| c.keyword == "COUPLING" && c.name == name)
        {
            return Err(self.err(
                card.loc,
                format!(
                    "constraint {name} defined twice (first at line {})",
                    first.loc.line
                ),
            ));
        }
        self.pending_coupling = Some(self.couplings.len());
        self.couplings.push(RawCoupling {
            keyword: "COUPLING",
            name,
            members: CouplingMembers::Surface(surface),
            ref_node,
            rot_node: None,
            kinematic: [false; 3],
            loc: card.loc,
        });
        Ok(Block::NoData(card.name.clone()))
    }

    /// `*KINEMATIC` right after the `*COUPLING` number `pending`.
    fn kw_kinematic(&mut self, card: &Card, pending: Option<usize>) -> Result<Block> {
        let Some(coupling) = pending else {
            return Err(self.err(card.loc, "*KINEMATIC without a preceding *COUPLING"));
        };
        self.check_params(card, &[])?;
        Ok(Block::Kinematic {
            coupling,
            loc: card.loc,
        })
    }

    /// A `*KINEMATIC` data line: `first[, last]` translational DOF.
    fn kinematic_line(&mut self, coupling: usize, f: &[&str], loc: Loc) -> Result<()> {
        if f.len() > 2 {
            return Err(self.err(loc, "*KINEMATIC data must be: first DOF[, last DOF]"));
        }
        let first = self.parse_dof(f[0], loc)?;
        let last = match f.get(1) {
            Some(t) if !t.is_empty() => self.parse_dof(t, loc)?,
            _ => first,
        };
        if last < first {
            return Err(self.err(loc, format!("last DOF {last} is below first DOF {first}")));
        }
        if last > 3 {
            return Err(self.err(
                loc,
                format!("*KINEMATIC DOF {last}: only the translations 1-3 of the surface nodes can be coupled (ccx limit); the rotations are DOFs 4-6 of the REF NODE"),
            ));
        }
        for d in first..=last {
            self.couplings[coupling].kinematic[d - 1] = true;
        }
        Ok(())
    }

    fn kw_step(&mut self, card: &Card) -> Result<Block> {
        if !matches!(self.step, StepState::Before) {
            return Err(self.err(card.loc, "second *STEP: only one step is supported"));
        }
        if let Some((_, v)) = card.params.iter().find(|(k, _)| k == "NLGEOM") {
            let v = v.as_deref().map(norm_name);
            if v.as_deref() != Some("NO") {
                return Err(self.err(
                    card.loc,
                    "*STEP, NLGEOM: geometrically nonlinear analysis is not supported (linear static only)",
                ));
            }
        }
        self.step = StepState::Open {
            loc: card.loc,
            procedure: false,
        };
        Ok(Block::NoData(card.name.clone()))
    }

    /// Parameters of *BOUNDARY/*CLOAD/*DLOAD. OP=NEW is accepted only where it
    /// is a no-op (nothing of that kind defined before).
    fn load_params(&self, card: &Card, seen: bool) -> Result<()> {
        for (k, v) in &card.params {
            let v = v.as_deref().map(norm_name).unwrap_or_default();
            match k.as_str() {
                "OP" if v == "MOD" => {}
                "OP" if v == "NEW" && !seen => {}
                "OP" if v == "NEW" => {
                    return Err(self.err(
                        card.loc,
                        format!("*{}, OP=NEW would remove the earlier ones; not supported", card.name),
                    ))
                }
                "TYPE" if card.name == "BOUNDARY" && v == "DISPLACEMENT" => {}
                _ => {
                    return Err(self.err(
                        card.loc,
                        format!(
                            "parameter {k} on *{} is not supported; ignoring it would change the answer",
                            card.name
                        ),
                    ))
                }
            }
        }
        Ok(())
    }

    // -- data lines ---------------------------------------------------------

    fn data(&mut self, text: &str, loc: Loc) -> Result<()> {
        let mut block = std::mem::replace(&mut self.block, Block::Ignore);
        let r = self.data_in(&mut block, text, loc);
        self.block = block;
        r
    }

    fn data_in(&mut self, block: &mut Block, text: &str, loc: Loc) -> Result<()> {
        match block {
            Block::Start => return Err(self.err(loc, "data line before the first keyword")),
            Block::Heading => {
                self.title.push(text.to_string());
                return Ok(());
            }
            Block::NoData(kw) => {
                return Err(self.err(loc, format!("unexpected data line after *{kw}")))
            }
            Block::Ignore => return Ok(()),
            _ => {}
        }
        let f = split_fields(text);
        if f.is_empty() {
            return Ok(());
        }
        match block {
            Block::Node { extra_warned, .. } => {
                let label = self.parse_label(f[0], loc)?;
                let mut x = [0.0; 3];
                for (k, xk) in x.iter_mut().enumerate() {
                    match f.get(k + 1) {
                        Some(tok) if !tok.is_empty() => *xk = self.parse_real(tok, loc)?,
                        _ => {}
                    }
                }
                if f.len() > 4 && !*extra_warned {
                    *extra_warned = true;
                    self.warn(loc, "*NODE: fields after the z coordinate ignored");
                }
                if self.mesh.add_node(label, x).is_err() {
                    return Err(self.err(loc, format!("duplicate node label {label}")));
                }
            }
            Block::Element { kind, open, .. } => self.element_line(*kind, open, &f, loc)?,
            Block::Set {
                elem,
                set,
                generate,
            } => self.set_line(*elem, *set, *generate, &f, loc)?,
            Block::Elastic {
                material, lines, ..
            } => {
                *lines += 1;
                self.elastic_line(*material, *lines, &f, loc)?;
            }
            Block::Boundary => self.boundary_line(&f, loc)?,
            Block::Cload => self.cload_line(&f, loc)?,
            Block::Dload => self.dload_line(&f, loc)?,
            Block::Surface { surface, node_type } => {
                self.surface_line(*surface, *node_type, &f, loc)?
            }
            Block::SurfaceBehavior {
                interaction,
                linear,
                lines,
            } => {
                *lines += 1;
                self.behavior_line(*interaction, *linear, *lines, &f, loc)?;
            }
            Block::Friction {
                interaction, lines, ..
            } => {
                *lines += 1;
                self.friction_line(*interaction, *lines, &f, loc)?;
            }
            Block::Kinematic { coupling, .. } => self.kinematic_line(*coupling, &f, loc)?,
            Block::ContactPair {
                interaction,
                small_sliding,
            } => {
                if f.len() != 2 || f.iter().any(|t| t.is_empty()) {
                    return Err(self.err(
                        loc,
                        "*CONTACT PAIR data must be: slave surface, master surface",
                    ));
                }
                self.pairs.push(RawPair {
                    interaction: interaction.clone(),
                    slave: norm_name(f[0]),
                    master: norm_name(f[1]),
                    small_sliding: *small_sliding,
                    loc,
                });
            }
            _ => {}
        }
        Ok(())
    }

    fn element_line(
        &mut self,
        kind: ElementKind,
        open: &mut bool,
        f: &[&str],
        loc: Loc,
    ) -> Result<()> {
        let count = kind.node_count();
        if *open {
            if let Some(el) = self.elements.last() {
                let need = count - el.nodes.len();
                if f.len() > need {
                    return Err(self.err(
                        loc,
                        format!(
                            "incomplete element {}: {} of {count} node labels given, but this line has {} entries (new element?)",
                            el.label,
                            el.nodes.len(),
                            f.len()
                        ),
                    ));
                }
            }
            let more = f
                .iter()
                .map(|t| self.parse_label(t, loc))
                .collect::<Result<Vec<_>>>()?;
            if let Some(el) = self.elements.last_mut() {
                el.nodes.extend(more);
                *open = el.nodes.len() < count;
            }
            return Ok(());
        }
        let label = self.parse_label(f[0], loc)?;
        let nodes = f[1..]
            .iter()
            .map(|t| self.parse_label(t, loc))
            .collect::<Result<Vec<_>>>()?;
        if nodes.len() > count {
            return Err(self.err(
                loc,
                format!(
                    "element {label}: {} node labels given, {} has {count}",
                    nodes.len(),
                    kind.name()
                ),
            ));
        }
        *open = nodes.len() < count;
        self.elements.push(RawElement {
            label,
            kind,
            nodes,
            loc,
        });
        Ok(())
    }

    fn set_line(
        &mut self,
        elem: bool,
        set: u32,
        generate: bool,
        f: &[&str],
        loc: Loc,
    ) -> Result<()> {
        if generate {
            if f.len() < 2 || f.len() > 3 {
                return Err(self.err(loc, "GENERATE data must be: first, last[, increment]"));
            }
            let first = self.parse_label(f[0], loc)?;
            let last = self.parse_label(f[1], loc)?;
            let step = match f.get(2) {
                Some(t) if !t.is_empty() => self.parse_label(t, loc)?,
                _ => 1,
            };
            if last < first {
                return Err(self.err(
                    loc,
                    format!("GENERATE range {first}..{last} is empty (last < first)"),
                ));
            }
            self.cmds.push(Cmd::SetItem {
                elem,
                set,
                item: SetItem::Range { first, last, step },
                loc,
            });
            return Ok(());
        }
        for tok in f {
            if tok.is_empty() {
                continue;
            }
            let item = if looks_numeric(tok) {
                SetItem::Label(self.parse_label(tok, loc)?)
            } else {
                SetItem::Set(self.intern(tok, loc)?)
            };
            self.cmds.push(Cmd::SetItem {
                elem,
                set,
                item,
                loc,
            });
        }
        Ok(())
    }

    fn elastic_line(
        &mut self,
        material: usize,
        line_no: usize,
        f: &[&str],
        loc: Loc,
    ) -> Result<()> {
        if line_no > 1 {
            if line_no == 2 {
                self.warn(
                    loc,
                    "*ELASTIC with several (temperature) lines: only the first is used",
                );
            }
            return Ok(());
        }
        if f.len() < 2 {
            return Err(self.err(loc, "*ELASTIC data must be: E, nu[, temperature]"));
        }
        if f.len() > 3 {
            return Err(self.err(
                loc,
                "too many values for isotropic *ELASTIC (expected E, nu[, temperature])",
            ));
        }
        let young = self.parse_real(f[0], loc)?;
        let poisson = self.parse_real(f[1], loc)?;
        if let Some(t) = f.get(2) {
            self.parse_real(t, loc)?;
        }
        let m = Material {
            name: self.materials[material].name.clone(),
            young,
            poisson,
        };
        m.validate().map_err(|e| self.err(loc, e.to_string()))?;
        self.materials[material].elastic = Some((young, poisson));
        Ok(())
    }

    fn boundary_line(&mut self, f: &[&str], loc: Loc) -> Result<()> {
        if f.len() < 2 || f.len() > 4 {
            return Err(self.err(
                loc,
                "*BOUNDARY data must be: node or set, first DOF[, last DOF[, value]]",
            ));
        }
        let target = self.parse_target(f[0], loc)?;
        let first = self.parse_dof(f[1], loc)?;
        let last = match f.get(2) {
            Some(t) if !t.is_empty() => self.parse_dof(t, loc)?,
            _ => first,
        };
        let value = match f.get(3) {
            Some(t) if !t.is_empty() => self.parse_real(t, loc)?,
            _ => 0.0,
        };
        if last < first {
            return Err(self.err(loc, format!("last DOF {last} is below first DOF {first}")));
        }
        if last > 6 {
            return Err(self.err(
                loc,
                format!(
                    "DOF {} is not supported (only displacements 1-3; 11 is temperature)",
                    first.max(7)
                ),
            ));
        }
        // DOFs 4-6 are the rotations of a *COUPLING reference node; on any
        // other node they are ignored or an error (decided at the end, when
        // the reference nodes are known).
        self.cmds.push(Cmd::Boundary {
            target,
            first: first - 1,
            last: last - 1,
            value,
            loc,
        });
        Ok(())
    }

    fn cload_line(&mut self, f: &[&str], loc: Loc) -> Result<()> {
        if f.len() != 3 {
            return Err(self.err(loc, "*CLOAD data must be: node or set, DOF, value"));
        }
        let target = self.parse_target(f[0], loc)?;
        let dof = self.parse_dof(f[1], loc)?;
        if dof > 6 {
            return Err(self.err(
                loc,
                format!("*CLOAD on DOF {dof} is not supported (only forces on DOFs 1-3)"),
            ));
        }
        let value = self.parse_real(f[2], loc)?;
        self.cmds.push(Cmd::Cload {
            target,
            comp: dof - 1,
            value,
            loc,
        });
        Ok(())
    }

    fn dload_line(&mut self, f: &[&str], loc: Loc) -> Result<()> {
        if f.len() < 2 {
            return Err(self.err(loc, "*DLOAD data must be: element or set, Pn, value"));
        }
        let target = self.parse_target(f[0], loc)?;
        let ty = f[1].to_ascii_uppercase();
        let face = match ty.strip_prefix('P') {
            Some(d) if !d.is_empty() && d.bytes().all(|b| b.is_ascii_digit()) => {
                d.parse::<usize>().unwrap_or(usize::MAX)
            }
            _ => {
                return Err(self.err(
                    loc,
                    format!("unsupported *DLOAD load type {ty} (only face pressure P1..P6); ignoring it would change the answer"),
                ))
            }
        };
        if !(1..=6).contains(&face) {
            return Err(self.err(
                loc,
                format!("*DLOAD face {ty} out of range (P1..P6 for hexahedra, P1..P5 for wedges)"),
            ));
        }
        if f.len() != 3 {
            return Err(self.err(loc, "*DLOAD data must be: element or set, Pn, value"));
        }
        let value = self.parse_real(f[2], loc)?;
        self.cmds.push(Cmd::Dload {
            target,
            face,
            value,
            loc,
        });
        Ok(())
    }

    fn surface_line(
        &mut self,
        surface: usize,
        node_type: bool,
        f: &[&str],
        loc: Loc,
    ) -> Result<()> {
        if node_type {
            if f.len() != 1 {
                return Err(self.err(
                    loc,
                    "*SURFACE, TYPE=NODE data must be: node or node set (one per line)",
                ));
            }
            let target = self.parse_target(f[0], loc)?;
            self.cmds.push(Cmd::SurfaceItem {
                surface,
                target,
                face: 0,
                loc,
            });
            return Ok(());
        }
        if f.len() != 2 {
            return Err(self.err(
                loc,
                "*SURFACE, TYPE=ELEMENT data must be: element or element set, face S1..S6",
            ));
        }
        let target = self.parse_target(f[0], loc)?;
        let ty = f[1].to_ascii_uppercase();
        let face = match ty.strip_prefix('S') {
            Some(d) if !d.is_empty() && d.bytes().all(|b| b.is_ascii_digit()) => {
                d.parse::<usize>().unwrap_or(usize::MAX)
            }
            _ => return Err(self.err(loc, format!("unsupported face identifier {ty} (S1..S6)"))),
        };
        if !(1..=6).contains(&face) {
            return Err(self.err(
                loc,
                format!("face {ty} out of range (S1..S6 for hexahedra, S1..S5 for wedges)"),
            ));
        }
        self.cmds.push(Cmd::SurfaceItem {
            surface,
            target,
            face,
            loc,
        });
        Ok(())
    }

    fn behavior_line(
        &mut self,
        interaction: usize,
        linear: bool,
        line_no: usize,
        f: &[&str],
        loc: Loc,
    ) -> Result<()> {
        if !linear {
            if line_no == 1 {
                self.warn(
                    loc,
                    "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=HARD: data ignored (flank's hard contact is exact, no penalty)",
                );
            }
            return Ok(());
        }
        if line_no > 1 {
            return Err(self.err(loc, "*SURFACE BEHAVIOR, LINEAR has one data line"));
        }
        if f.len() > 3 {
            return Err(self.err(
                loc,
                "*SURFACE BEHAVIOR, LINEAR data must be: slope[, tension at large clearance[, c0]]",
            ));
        }
        let mut v = [None; 3];
        for (k, tok) in f.iter().enumerate() {
            if !tok.is_empty() {
                v[k] = Some(self.parse_real(tok, loc)?);
            }
        }
        if let Some(s) = v[0] {
            if !(s > 0.0) {
                return Err(self.err(
                    loc,
                    format!("pressure-overclosure slope {s} must be positive"),
                ));
            }
        }
        for (k, what) in [(1, "tension"), (2, "c0")] {
            if let Some(x) = v[k] {
                if x < 0.0 {
                    return Err(self.err(loc, format!("{what} {x} must not be negative")));
                }
            }
        }
        self.interactions[interaction].behavior = Some(PressureOverclosure::Linear {
            slope: v[0],
            tension: v[1],
            c0: v[2],
        });
        Ok(())
    }

    fn friction_line(
        &mut self,
        interaction: usize,
        line_no: usize,
        f: &[&str],
        loc: Loc,
    ) -> Result<()> {
        if line_no > 1 {
            return Err(self.err(loc, "*FRICTION has one data line (mu[, stick slope])"));
        }
        if f.is_empty() || f.len() > 2 || f[0].is_empty() {
            return Err(self.err(loc, "*FRICTION data must be: mu[, stick slope]"));
        }
        let mu = self.parse_real(f[0], loc)?;
        if mu < 0.0 {
            return Err(self.err(
                loc,
                format!("friction coefficient mu = {mu} must not be negative"),
            ));
        }
        let stick_slope = match f.get(1) {
            Some(t) if !t.is_empty() => {
                let k = self.parse_real(t, loc)?;
                if !(k > 0.0) {
                    return Err(self.err(loc, format!("stick slope {k} must be positive")));
                }
                Some(k)
            }
            _ => None,
        };
        self.interactions[interaction].friction = Some(Friction { mu, stick_slope });
        Ok(())
    }

    // -- tokens -------------------------------------------------------------

    /// A positive integer label.
    fn parse_label(&self, tok: &str, loc: Loc) -> Result<u64> {
        match tok.trim().parse::<u64>() {
            Ok(0) => Err(self.err(loc, "label 0 is not allowed (labels start at 1)")),
            Ok(v) => Ok(v),
            Err(_) => Err(self.err(
                loc,
                format!("malformed number '{tok}' (expected a positive integer)"),
            )),
        }
    }

    /// A degree of freedom number (1-based).
    fn parse_dof(&self, tok: &str, loc: Loc) -> Result<usize> {
        match tok.trim().parse::<usize>() {
            Ok(0) => Err(self.err(loc, "DOF 0 does not exist (DOFs start at 1)")),
            Ok(v) => Ok(v),
            Err(_) => Err(self.err(loc, format!("malformed DOF number '{tok}'"))),
        }
    }

    /// A finite real; Fortran `D` exponents are accepted, `inf`/`nan` are not.
    fn parse_real(&self, tok: &str, loc: Loc) -> Result<f64> {
        let t = tok.trim();
        let plausible = !t.is_empty()
            && t.bytes().all(|b| {
                b.is_ascii_digit() || matches!(b, b'+' | b'-' | b'.' | b'e' | b'E' | b'd' | b'D')
            });
        if plausible {
            let parsed = if t.contains(['d', 'D']) {
                t.replace(['d', 'D'], "e").parse::<f64>()
            } else {
                t.parse::<f64>()
            };
            if let Ok(v) = parsed {
                if v.is_finite() {
                    return Ok(v);
                }
                return Err(self.err(loc, format!("number '{t}' is out of range")));
            }
        }
        Err(self.err(loc, format!("malformed number '{t}'")))
    }

    fn parse_target(&mut self, tok: &str, loc: Loc) -> Result<Target> {
        if tok.is_empty() {
            return Err(self.err(loc, "missing label or set name"));
        }
        if looks_numeric(tok) {
            Ok(Target::Label(self.parse_label(tok, loc)?))
        } else {
            Ok(Target::Set(self.intern(tok, loc)?))
        }
    }

    // -- end of deck --------------------------------------------------------

    /// Members of node (`elem == false`) or element set `id` at this point of
    /// the deck; NALL/EALL mean all nodes/elements unless defined explicitly.
    fn set_members(
        &self,
        sets: &[Option<IdxSet>],
        elem: bool,
        id: u32,
        loc: Loc,
    ) -> Result<Vec<usize>> {
        if let Some(Some(s)) = sets.get(id as usize) {
            return Ok(s.members.clone());
        }
        let name = &self.names[id as usize];
        match (elem, name.as_str()) {
            (false, "NALL") => Ok((0..self.mesh.node_count()).collect()),
            (true, "EALL") => Ok((0..self.mesh.elements.len()).collect()),
            _ => Err(self.err(
                loc,
                format!(
                    "{} set {name} is not defined",
                    if elem { "element" } else { "node" }
                ),
            )),
        }
    }

    fn target_nodes(
        &self,
        sets: &[Option<IdxSet>],
        target: Target,
        loc: Loc,
    ) -> Result<Vec<usize>> {
        match target {
            Target::Label(l) => self
                .mesh
                .node(l)
                .map(|i| vec![i])
                .ok_or_else(|| self.err(loc, format!("node {l} is not defined"))),
            Target::Set(id) => self.set_members(sets, false, id, loc),
        }
    }

    fn target_elements(
        &self,
        sets: &[Option<IdxSet>],
        target: Target,
        loc: Loc,
    ) -> Result<Vec<usize>> {
        match target {
            Target::Label(l) => self
                .mesh
                .element(l)
                .map(|i| vec![i])
                .ok_or_else(|| self.err(loc, format!("element {l} is not defined"))),
            Target::Set(id) => self.set_members(sets, true, id, loc),
        }
    }

    /// Resolves everything recorded in phase 1 and builds the model.
    fn finish(mut self) -> Result<Deck> {
        self.end_block()?;
        if let Some(c) = self.pending_coupling {
            return Err(self.err(
                self.couplings[c].loc,
                "*COUPLING must be followed by *KINEMATIC (end of deck reached)",
            ));
        }
        match self.step {
            StepState::Open {
                loc,
                procedure: false,
            } => return Err(self.err(loc, "*STEP has no *STATIC procedure")),
            StepState::Open { loc, .. } => self.warn(loc, "*STEP without *END STEP"),
            StepState::Before => {
                self.warn(Loc { file: 0, line: 0 }, "deck has no *STEP (no loads)")
            }
            StepState::Closed => {}
        }

        // Elements, in file order.
        let raw = std::mem::take(&mut self.elements);
        let mut elem_loc = Vec::with_capacity(raw.len());
        for el in raw {
            let mut nodes = Vec::with_capacity(el.nodes.len());
            for &l in &el.nodes {
                let i = self.mesh.node(l).ok_or_else(|| {
                    self.err(
                        el.loc,
                        format!("element {} refers to undefined node {l}", el.label),
                    )
                })?;
                nodes.push(i);
            }
            for (k, l) in el.nodes.iter().enumerate() {
                if el.nodes[..k].contains(l) {
                    return Err(self.err(
                        el.loc,
                        format!("element {} uses node {l} more than once", el.label),
                    ));
                }
            }
            if self.mesh.add_element(el.label, el.kind, nodes).is_err() {
                return Err(self.err(el.loc, format!("duplicate element label {}", el.label)));
            }
            elem_loc.push(el.loc);
        }

        // Reference nodes of the hub couplings: not part of the mesh.
        let roles = self.reference_roles()?;
        let ncp = self.couplings.len();
        let mut cp_nodes: Vec<Vec<usize>> = vec![Vec::new(); ncp];
        let mut cp_fixed: Vec<[Option<Loc>; 6]> = vec![[None; 6]; ncp];
        let mut cp_load: Vec<[(f64, Option<Loc>); 6]> = vec![[(0.0, None); 6]; ncp];

        // Replay of sets, sections, boundary conditions and loads.
        let nn = self.mesh.node_count();
        let ne = self.mesh.elements.len();
        let mut nsets: Vec<Option<IdxSet>> = (0..self.names.len()).map(|_| None).collect();
        let mut esets: Vec<Option<IdxSet>> = (0..self.names.len()).map(|_| None).collect();
        let mut elem_mat: Vec<Option<usize>> = vec![None; ne];
        let mut dirichlet: Vec<Dirichlet> = Vec::new();
        let mut dirichlet_loc: Vec<Loc> = Vec::new();
        let mut bc_index: HashMap<(usize, usize), usize> = HashMap::new();
        let mut forces = Vec::new();
        let mut pressures = Vec::new();
        let mut surface_faces: Vec<Vec<(usize, usize)>> = vec![Vec::new(); self.surfaces.len()];
        let mut surface_nodes: Vec<Vec<usize>> = vec![Vec::new(); self.surfaces.len()];
        for cmd in std::mem::take(&mut self.cmds) {
            match cmd {
                Cmd::NodeRange { set, start, end } => {
                    let s = nsets[set as usize].get_or_insert_with(IdxSet::default);
                    (start..end).for_each(|i| s.insert(i));
                }
                Cmd::ElemRange { set, start, end } => {
                    let s = esets[set as usize].get_or_insert_with(IdxSet::default);
                    (start..end).for_each(|i| s.insert(i));
                }
                Cmd::Define { elem, set } => {
                    let sets = if elem { &mut esets } else { &mut nsets };
                    sets[set as usize].get_or_insert_with(IdxSet::default);
                }
                Cmd::SetItem {
                    elem,
                    set,
                    item,
                    loc,
                } => {
                    let what = if elem { "element" } else { "node" };
                    let new: Vec<usize> = match item {
                        SetItem::Label(l) => {
                            let i = if elem {
                                self.mesh.element(l)
                            } else {
                                self.mesh.node(l)
                            };
                            vec![i.ok_or_else(|| {
                                self.err(loc, format!("{what} {l} is not defined"))
                            })?]
                        }
                        SetItem::Set(other) => {
                            let sets = if elem { &esets } else { &nsets };
                            self.set_members(sets, elem, other, loc)?
                        }
                        SetItem::Range { first, last, step } => {
                            let (found, count) = self.generate(elem, first, last, step);
                            if (found.len() as u64) < count {
                                self.warn(
                                    loc,
                                    format!(
                                        "GENERATE {first}..{last} step {step}: {} of {count} {what} labels are not defined (skipped)",
                                        count - found.len() as u64
                                    ),
                                );
                            }
                            found
                        }
                    };
                    let sets = if elem { &mut esets } else { &mut nsets };
                    let s = sets[set as usize].get_or_insert_with(IdxSet::default);
                    new.into_iter().for_each(|i| s.insert(i));
                }
                Cmd::Section {
                    elset,
                    material,
                    loc,
                } => {
                    let members = self.set_members(&esets, true, elset, loc)?;
                    let m = *self.material_ids.get(&material).ok_or_else(|| {
                        self.err(loc, format!("material {material} is not defined"))
                    })?;
                    if self.materials[m].elastic.is_none() {
                        return Err(self.err(loc, format!("material {material} has no *ELASTIC")));
                    }
                    let mut reassigned = false;
                    for e in members {
                        reassigned |= elem_mat[e].replace(m).is_some();
                    }
                    if reassigned {
                        let name = self.names[elset as usize].clone();
                        self.warn(
                            loc,
                            format!(
                                "elements of {name} already had a section: material reassigned"
                            ),
                        );
                    }
                }
                Cmd::Boundary {
                    target,
                    first,
                    last,
                    value,
                    loc,
                } => {
                    let mut rotations_ignored = false;
                    for node in self.target_nodes(&nsets, target, loc)? {
                        if let Some(&role) = roles.get(&node) {
                            for component in first..=last {
                                let k = self.reference_dof(role, component, "*BOUNDARY", loc)?;
                                if value != 0.0 {
                                    return Err(self.err(
                                        loc,
                                        format!(
                                            "prescribed value {value} on DOF {} of reference node {} ({}): only zero (fixed) reference DOFs are supported",
                                            component + 1,
                                            self.mesh.node_labels[node],
                                            self.coupling_title(role.coupling)
                                        ),
                                    ));
                                }
                                cp_fixed[role.coupling][k] = Some(loc);
                            }
                            continue;
                        }
                        if last >= 3 {
                            if value != 0.0 {
                                return Err(self.err(
                                    loc,
                                    format!(
                                        "nonzero value {value} on rotational DOFs 4-6 of node {}: solid elements have none",
                                        self.mesh.node_labels[node]
                                    ),
                                ));
                            }
                            rotations_ignored = true;
                        }
                        for component in first..=last.min(2) {
                            match bc_index.get(&(node, component)) {
                                Some(&k) => {
                                    dirichlet[k].value = value;
                                    dirichlet_loc[k] = loc;
                                }
                                None => {
                                    bc_index.insert((node, component), dirichlet.len());
                                    dirichlet.push(Dirichlet {
                                        node,
                                        component,
                                        value,
                                    });
                                    dirichlet_loc.push(loc);
                                }
                            }
                        }
                    }
                    if rotations_ignored {
                        self.warn(
                            loc,
                            "*BOUNDARY on rotational DOFs 4-6 ignored (solid elements have none)",
                        );
                    }
                }
                Cmd::Cload {
                    target,
                    comp,
                    value,
                    loc,
                } => {
                    for node in self.target_nodes(&nsets, target, loc)? {
                        if let Some(&role) = roles.get(&node) {
                            let k = self.reference_dof(role, comp, "*CLOAD", loc)?;
                            let slot = &mut cp_load[role.coupling][k];
                            slot.0 += value;
                            slot.1 = Some(loc);
                            continue;
                        }
                        if comp > 2 {
                            return Err(self.err(
                                loc,
                                format!(
                                    "*CLOAD on DOF {} of node {} is not supported (only forces on DOFs 1-3; moments only on a *COUPLING REF NODE or a *RIGID BODY ROT NODE)",
                                    comp + 1,
                                    self.mesh.node_labels[node]
                                ),
                            ));
                        }
                        forces.push(NodalForce {
                            node,
                            component: comp,
                            value,
                        });
                    }
                }
                Cmd::Coupling { coupling } => {
                    let raw = &self.couplings[coupling];
                    let loc = raw.loc;
                    let nodes = match raw.members {
                        CouplingMembers::NodeSet(id) => self.set_members(&nsets, false, id, loc)?,
                        CouplingMembers::ElementSet(id) => {
                            let mut v: Vec<usize> = self
                                .set_members(&esets, true, id, loc)?
                                .into_iter()
                                .flat_map(|e| self.mesh.elements[e].nodes.iter().copied())
                                .collect();
                            v.sort_unstable();
                            v.dedup();
                            v
                        }
                        CouplingMembers::Surface(_) => Vec::new(),
                    };
                    cp_nodes[coupling] = nodes;
                }
                Cmd::Dload {
                    target,
                    face,
                    value,
                    loc,
                } => {
                    for element in self.target_elements(&esets, target, loc)? {
                        let el = &self.mesh.elements[element];
                        if face > el.kind.face_count() {
                            return Err(self.err(
                                loc,
                                format!(
                                    "*DLOAD face P{face} out of range for {} element {} (P1..P{})",
                                    el.kind.name(),
                                    el.label,
                                    el.kind.face_count()
                                ),
                            ));
                        }
                        pressures.push(Pressure {
                            element,
                            face,
                            value,
                        });
                    }
                }
                Cmd::SurfaceItem {
                    surface,
                    target,
                    face,
                    loc,
                } => {
                    if face == 0 {
                        let nodes = self.target_nodes(&nsets, target, loc)?;
                        surface_nodes[surface].extend(nodes);
                        continue;
                    }
                    for element in self.target_elements(&esets, target, loc)? {
                        let el = &self.mesh.elements[element];
                        if face > el.kind.face_count() {
                            return Err(self.err(
                                loc,
                                format!(
                                    "*SURFACE face S{face} out of range for {} element {} (S1..S{})",
                                    el.kind.name(),
                                    el.label,
                                    el.kind.face_count()
                                ),
                            ));
                        }
                        surface_faces[surface].push((element, face));
                    }
                }
            }
        }
        // *COUPLING surfaces (complete now: a surface is defined once).
        for (c, raw) in self.couplings.iter().enumerate() {
            let CouplingMembers::Surface(name) = &raw.members else {
                continue;
            };
            let Some(s) = self.surfaces.iter().position(|s| &s.name == name) else {
                return Err(self.err(raw.loc, format!("*COUPLING: surface {name} is not defined")));
            };
            let mut v = surface_nodes[s].clone();
            for &(e, face) in &surface_faces[s] {
                let el = &self.mesh.elements[e];
                if let Some(local) = crate::fem::element::face_nodes(el.kind, face) {
                    v.extend(local.iter().map(|&i| el.nodes[i]));
                }
            }
            v.sort_unstable();
            v.dedup();
            cp_nodes[c] = v;
        }
        let couplings = self.build_couplings(
            &roles,
            cp_nodes,
            &cp_fixed,
            &cp_load,
            &dirichlet,
            &dirichlet_loc,
        )?;
        let contact = self.contact_definition(surface_faces, surface_nodes)?;

        // Materials: keep complete ones; drop unused ones without *ELASTIC.
        let mut remap = vec![None; self.materials.len()];
        let mut materials = Vec::new();
        let mut dropped = Vec::new();
        for (i, m) in self.materials.iter().enumerate() {
            match m.elastic {
                Some((young, poisson)) => {
                    remap[i] = Some(materials.len());
                    materials.push(Material {
                        name: m.name.clone(),
                        young,
                        poisson,
                    });
                }
                None => dropped.push((m.loc, m.name.clone())),
            }
        }
        for (loc, name) in dropped {
            self.warn(
                loc,
                format!("material {name} has no *ELASTIC and is unused: dropped"),
            );
        }
        let mut element_material = Vec::with_capacity(ne);
        for (e, m) in elem_mat.iter().enumerate() {
            match m.and_then(|m| remap[m]) {
                Some(m) => element_material.push(m),
                None => {
                    return Err(self.err(
                        elem_loc[e],
                        format!(
                            "element {} has no *SOLID SECTION (no material)",
                            self.mesh.elements[e].label
                        ),
                    ))
                }
            }
        }

        // Sets into the mesh (sorted once), NALL/EALL implicit.
        for (id, s) in nsets.into_iter().enumerate() {
            if let Some(s) = s {
                let mut v = s.members;
                v.sort_unstable();
                self.mesh.node_sets.insert(self.names[id].clone(), v);
            }
        }
        for (id, s) in esets.into_iter().enumerate() {
            if let Some(s) = s {
                let mut v = s.members;
                v.sort_unstable();
                self.mesh.element_sets.insert(self.names[id].clone(), v);
            }
        }
        self.mesh
            .node_sets
            .entry("NALL".to_string())
            .or_insert_with(|| (0..nn).collect());
        self.mesh
            .element_sets
            .entry("EALL".to_string())
            .or_insert_with(|| (0..ne).collect());

        // The reference nodes leave the mesh: their DOFs are the couplings'.
        let mut dropped = vec![false; nn];
        for &n in roles.keys() {
            dropped[n] = true;
        }
        for s in &contact.surfaces {
            if let SurfaceKind::Node(nodes) = &s.kind {
                if let Some(&n) = nodes.iter().find(|&&n| dropped[n]) {
                    let loc = self
                        .surfaces
                        .iter()
                        .find(|r| r.name == s.name)
                        .map_or(Loc { file: 0, line: 0 }, |r| r.loc);
                    return Err(self.err(
                        loc,
                        format!(
                            "surface {} contains node {}, the reference node of {} (not a mesh node)",
                            s.name,
                            self.mesh.node_labels[n],
                            self.coupling_title(roles[&n].coupling)
                        ),
                    ));
                }
            }
        }
        let (mesh, remap) = if roles.is_empty() {
            (std::mem::take(&mut self.mesh), None)
        } else {
            let (mesh, remap) = without_nodes(&self.mesh, &dropped);
            (mesh, Some(remap))
        };
        self.mesh = mesh;
        let mut couplings = couplings;
        let mut contact = contact;
        if let Some(remap) = &remap {
            for cp in couplings.iter_mut() {
                for n in cp.nodes.iter_mut() {
                    *n = remap[*n];
                }
            }
            for d in dirichlet.iter_mut() {
                d.node = remap[d.node];
            }
            for f in forces.iter_mut() {
                f.node = remap[f.node];
            }
            for s in contact.surfaces.iter_mut() {
                if let SurfaceKind::Node(nodes) = &mut s.kind {
                    for n in nodes.iter_mut() {
                        *n = remap[*n];
                    }
                }
            }
        }

        let unused = self.mesh.used_nodes().iter().filter(|u| !**u).count();
        if unused > 0 {
            self.warn(
                Loc { file: 0, line: 0 },
                format!("{unused} node(s) belong to no element"),
            );
        }

        let title = self.title.join("\n").trim().to_string();
        Ok(Deck {
            model: Model {
                mesh: self.mesh,
                materials,
                element_material,
                dirichlet,
                forces,
                pressures,
                couplings,
                contact,
            },
            warnings: self.warnings,
            title: (!title.is_empty()).then_some(title),
        })
    }

    /// "*RIGID BODY HUB (line 12)" / "*COUPLING C1 (line 20)".
    fn coupling_title(&self, c: usize) -> String {
        let raw = &self.couplings[c];
        format!("*{} {} (line {})", raw.keyword, raw.name, raw.loc.line)
    }

    /// Node index → role of every REF NODE and ROT NODE, checked: defined,
    /// in no element, not shared between couplings.
    fn reference_roles(&self) -> Result<HashMap<usize, RefRole>> {
        let used = self.mesh.used_nodes();
        let mut roles: HashMap<usize, RefRole> = HashMap::new();
        for (c, raw) in self.couplings.iter().enumerate() {
            let nodes = [(raw.ref_node, false, "REF NODE")]
                .into_iter()
                .chain(raw.rot_node.map(|r| (r, true, "ROT NODE")));
            for (label, rot, what) in nodes {
                let Some(n) = self.mesh.node(label) else {
                    return Err(self.err(
                        raw.loc,
                        format!("*{}: {what} {label} is not defined", raw.keyword),
                    ));
                };
                if used[n] {
                    return Err(self.err(
                        raw.loc,
                        format!(
                            "*{}: {what} {label} belongs to an element; the reference node must be a separate node (in no element)",
                            raw.keyword
                        ),
                    ));
                }
                if let Some(other) = roles.insert(n, RefRole { coupling: c, rot }) {
                    return Err(self.err(
                        raw.loc,
                        format!(
                            "*{}: node {label} is already the {} of {}",
                            raw.keyword,
                            if other.rot { "ROT NODE" } else { "REF NODE" },
                            self.coupling_title(other.coupling)
                        ),
                    ));
                }
            }
        }
        Ok(roles)
    }

    /// Reference DOF (0..6: tx, ty, tz, rx, ry, rz) that DOF `component`
    /// (0-based) of a reference node stands for.
    fn reference_dof(
        &self,
        role: RefRole,
        component: usize,
        what: &str,
        loc: Loc,
    ) -> Result<usize> {
        let raw = &self.couplings[role.coupling];
        match (raw.keyword, role.rot, component) {
            ("COUPLING", _, k) => Ok(k),
            (_, false, k) if k < 3 => Ok(k),
            (_, true, k) if k < 3 => Ok(3 + k),
            _ => Err(self.err(
                loc,
                format!(
                    "{what} on DOF {} of the {} {} of {}: a *RIGID BODY's translations are DOFs 1-3 of its REF NODE, its rotations DOFs 1-3 of its ROT NODE{}",
                    component + 1,
                    if role.rot { "ROT NODE" } else { "REF NODE" },
                    if role.rot { raw.rot_node } else { Some(raw.ref_node) }.unwrap_or(0),
                    self.coupling_title(role.coupling),
                    if raw.rot_node.is_none() { " (this one has none: its rotations are free and unloaded)" } else { "" }
                ),
            )),
        }
    }

    /// The rigid couplings, checked: nodes present and held by elements, a
    /// node in one coupling only, no *BOUNDARY on a coupled node.
    fn build_couplings(
        &mut self,
        roles: &HashMap<usize, RefRole>,
        nodes: Vec<Vec<usize>>,
        fixed: &[[Option<Loc>; 6]],
        load: &[[(f64, Option<Loc>); 6]],
        dirichlet: &[Dirichlet],
        dirichlet_loc: &[Loc],
    ) -> Result<Vec<RigidCoupling>> {
        let used = self.mesh.used_nodes();
        let mut owner: HashMap<usize, usize> = HashMap::new();
        let mut out = Vec::with_capacity(nodes.len());
        for (c, mut members) in nodes.into_iter().enumerate() {
            let raw = &self.couplings[c];
            // ccx skips a rigid body's own reference nodes in its set
            members.retain(|n| roles.get(n).is_none_or(|r| r.coupling != c));
            members.sort_unstable();
            members.dedup();
            let what = match &raw.members {
                CouplingMembers::NodeSet(id) => format!("node set {}", self.names[*id as usize]),
                CouplingMembers::ElementSet(id) => {
                    format!("element set {}", self.names[*id as usize])
                }
                CouplingMembers::Surface(s) => format!("surface {s}"),
            };
            if members.is_empty() {
                return Err(self.err(
                    raw.loc,
                    format!("*{}: {what} has no node to couple", raw.keyword),
                ));
            }
            if let Some(&n) = members.iter().find(|n| roles.contains_key(n)) {
                return Err(self.err(
                    raw.loc,
                    format!(
                        "*{}: {what} contains node {}, the reference node of {}",
                        raw.keyword,
                        self.mesh.node_labels[n],
                        self.coupling_title(roles[&n].coupling)
                    ),
                ));
            }
            if !members.iter().any(|&n| used[n]) {
                return Err(self.err(
                    raw.loc,
                    format!(
                        "*{}: no node of {what} belongs to an element; the coupling would hold nothing",
                        raw.keyword
                    ),
                ));
            }
            for &n in &members {
                if let Some(other) = owner.insert(n, c) {
                    return Err(self.err(
                        raw.loc,
                        format!(
                            "*{}: node {} is already coupled by {}; a node can follow one reference only",
                            raw.keyword,
                            self.mesh.node_labels[n],
                            self.coupling_title(other)
                        ),
                    ));
                }
            }
            let r = self
                .mesh
                .node(raw.ref_node)
                .expect("checked reference node");
            let mut free = [true; 6];
            let mut loads = [0.0; 6];
            for k in 0..6 {
                free[k] = fixed[c][k].is_none();
                let (v, at) = load[c][k];
                if free[k] {
                    loads[k] = v;
                } else if let Some(at) = at {
                    if v != 0.0 {
                        let msg = format!(
                            "load {v} on reference DOF {} of {} ignored: that DOF is held by the *BOUNDARY of line {}",
                            ["ux", "uy", "uz", "rx", "ry", "rz"][k],
                            self.coupling_title(c),
                            fixed[c][k].map_or(0, |l| l.line)
                        );
                        self.warn(at, msg);
                    }
                }
            }
            let raw = &self.couplings[c];
            out.push(RigidCoupling {
                name: raw.name.clone(),
                reference_point: self.mesh.coords[r],
                nodes: members,
                free,
                load: loads,
            });
        }
        for (d, at) in dirichlet.iter().zip(dirichlet_loc) {
            if let Some(&c) = owner.get(&d.node) {
                return Err(self.err(
                    *at,
                    format!(
                        "*BOUNDARY on node {}, which {} couples to its reference node: constrain the reference node instead",
                        self.mesh.node_labels[d.node],
                        self.coupling_title(c)
                    ),
                ));
            }
        }
        Ok(out)
    }

    /// The contact definition from the recorded surfaces, interactions and
    /// pairs, with its cross references checked (errors at the lines that
    /// name what is wrong).
    fn contact_definition(
        &self,
        mut faces: Vec<Vec<(usize, usize)>>,
        mut nodes: Vec<Vec<usize>>,
    ) -> Result<ContactDefinition> {
        let mut def = ContactDefinition::default();
        for (k, raw) in self.surfaces.iter().enumerate() {
            let kind = if raw.node_type {
                let mut v = std::mem::take(&mut nodes[k]);
                v.sort_unstable();
                v.dedup();
                if v.is_empty() {
                    return Err(self.err(raw.loc, format!("surface {} names no node", raw.name)));
                }
                SurfaceKind::Node(v)
            } else {
                let mut v = std::mem::take(&mut faces[k]);
                v.sort_unstable();
                v.dedup();
                if v.is_empty() {
                    return Err(self.err(
                        raw.loc,
                        format!("surface {} names no element face", raw.name),
                    ));
                }
                SurfaceKind::Element(v)
            };
            def.surfaces.push(Surface {
                name: raw.name.clone(),
                kind,
            });
        }
        for raw in &self.interactions {
            if raw.behavior.is_none() {
                return Err(self.err(
                    raw.loc,
                    format!(
                        "surface interaction {} has no *SURFACE BEHAVIOR (pressure-overclosure law)",
                        raw.name
                    ),
                ));
            }
            def.interactions.push(SurfaceInteraction {
                name: raw.name.clone(),
                behavior: raw.behavior.clone(),
                friction: raw.friction.clone(),
            });
        }
        for raw in &self.pairs {
            if def.interaction(&raw.interaction).is_none() {
                return Err(self.err(
                    raw.loc,
                    format!(
                        "*CONTACT PAIR: surface interaction {} is not defined",
                        raw.interaction
                    ),
                ));
            }
            for (role, name) in [("slave", &raw.slave), ("master", &raw.master)] {
                match def.surface(name) {
                    None => {
                        return Err(self.err(
                            raw.loc,
                            format!("*CONTACT PAIR: {role} surface {name} is not defined"),
                        ))
                    }
                    Some(s) if role == "master" && matches!(s.kind, SurfaceKind::Node(_)) => {
                        return Err(self.err(
                            raw.loc,
                            format!("*CONTACT PAIR: master surface {name} must be made of element faces (TYPE=ELEMENT)"),
                        ))
                    }
                    _ => {}
                }
            }
            if raw.slave == raw.master {
                return Err(self.err(
                    raw.loc,
                    format!(
                        "*CONTACT PAIR: surface {} against itself (self contact) is not supported",
                        raw.slave
                    ),
                ));
            }
            def.pairs.push(ContactPair {
                interaction: raw.interaction.clone(),
                slave: raw.slave.clone(),
                master: raw.master.clone(),
                small_sliding: raw.small_sliding,
            });
        }
        def.validate(&self.mesh)
            .map_err(|e| self.err(Loc { file: 0, line: 0 }, e.to_string()))?;
        Ok(def)
    }

    /// Indices of the existing labels in `first..=last` by `step`, and the
    /// number of labels in the range. Walks the range or all labels,
    /// whichever is shorter, so huge ranges cost no more than the mesh size.
    fn generate(&self, elem: bool, first: u64, last: u64, step: u64) -> (Vec<usize>, u64) {
        let count = (last - first) / step + 1;
        let total = if elem {
            self.mesh.elements.len()
        } else {
            self.mesh.node_count()
        } as u64;
        let lookup = |l: u64| {
            if elem {
                self.mesh.element(l)
            } else {
                self.mesh.node(l)
            }
        };
        let found = if count <= total {
            (0..count)
                .filter_map(|k| lookup(first + k * step))
                .collect()
        } else {
            let in_range = |l: u64| l >= first && l <= last && (l - first).is_multiple_of(step);
            if elem {
                (0..self.mesh.elements.len())
                    .filter(|&e| in_range(self.mesh.elements[e].label))
                    .collect()
            } else {
                (0..self.mesh.node_count())
                    .filter(|&n| in_range(self.mesh.node_labels[n]))
                    .collect()
            }
        };
        (found, count)
    }
}

/// The mesh without the `drop`ped nodes (which belong to no element) and
/// the map old → new node index (`usize::MAX` for dropped nodes).
fn without_nodes(mesh: &crate::mesh::Mesh, drop: &[bool]) -> (crate::mesh::Mesh, Vec<usize>) {
    let mut out = crate::mesh::Mesh::new();
    let mut remap = vec![usize::MAX; mesh.node_count()];
    for (i, (&label, &x)) in mesh.node_labels.iter().zip(&mesh.coords).enumerate() {
        if !drop[i] {
            remap[i] = out.add_node(label, x).expect("labels are unique");
        }
    }
    for el in &mesh.elements {
        let nodes = el.nodes.iter().map(|&n| remap[n]).collect();
        out.add_element(el.label, el.kind, nodes)
            .expect("labels are unique");
    }
    for (name, members) in &mesh.node_sets {
        let v: Vec<usize> = members
            .iter()
            .filter(|&&n| !drop[n])
            .map(|&n| remap[n])
            .collect();
        out.node_sets.insert(name.clone(), v);
    }
    out.element_sets = mesh.element_sets.clone();
    (out, remap)
}

// ---------------------------------------------------------------------------
// Writer
// ---------------------------------------------------------------------------

/// ccx reads labels as 32-bit integers.
const CCX_MAX_LABEL: u64 = i32::MAX as u64;
/// ccx reads reals from the first 20 characters of a field.
const CCX_REAL_WIDTH: usize = 20;
/// Entries per data line (ccx accepts at most 16).
const PER_LINE: usize = 8;

/// Writes the model as a CalculiX deck (see [`format_deck`]).
pub fn write_deck(model: &Model, path: &Path) -> Result<()> {
    let text = format_deck(model)?;
    std::fs::write(path, text).map_err(|e| FlankError::io(path, e))
}

/// The model as a CalculiX deck: *NODE (NSET=NALL), *ELEMENT blocks
/// (ELSET=EALL), node and element sets, one element set and *SOLID SECTION per
/// material, and one *STEP/*STATIC with *BOUNDARY, *CLOAD, *DLOAD and a
/// displacement *NODE PRINT. Names are upper-cased and made deck-safe.
///
/// Each rigid coupling becomes `*RIGID BODY, NSET=<its nodes>, REF NODE=r,
/// ROT NODE=q` with two extra nodes (a second `*NODE` block, not in NALL)
/// labelled above the largest node label, both at the reference point: r's
/// DOFs 1-3 are the reference translations, q's DOFs 1-3 its rotations;
/// fixed reference DOFs are `*BOUNDARY` lines on them, loads `*CLOAD` lines
/// (force N, moment N·mm). [`parse_deck`] reads it back to the same
/// couplings (nodes sorted) and no extra mesh node.
///
/// Fails with [`FlankError::Model`] for inconsistent models (bad indices,
/// non-finite values, labels ccx cannot read, a node in two couplings or a
/// coupled node with a Dirichlet condition), instead of writing a wrong deck.
pub fn format_deck(model: &Model) -> Result<String> {
    check_writable(model)?;
    let mesh = &model.mesh;
    let nn = mesh.node_count();
    let ne = mesh.elements.len();
    let mut out = String::with_capacity(80 * (nn + 2 * ne) + 4096);
    macro_rules! w {
        ($($arg:tt)*) => { let _ = writeln!(out, $($arg)*); };
    }

    w!(
        "** Linear static deck written by flank {}",
        env!("CARGO_PKG_VERSION")
    );
    w!("*HEADING");
    w!("flank model: {nn} nodes, {ne} elements");

    w!("*NODE, NSET=NALL");
    for (label, [x, y, z]) in mesh.node_labels.iter().zip(&mesh.coords) {
        w!(
            "{label}, {}, {}, {}",
            fmt_real(*x),
            fmt_real(*y),
            fmt_real(*z)
        );
    }
    // reference (translations) and rotation node of each coupling
    let first_free = mesh.node_labels.iter().max().copied().unwrap_or(0) + 1;
    let ref_labels: Vec<(u64, u64)> = (0..model.couplings.len() as u64)
        .map(|c| (first_free + 2 * c, first_free + 2 * c + 1))
        .collect();
    if !model.couplings.is_empty() {
        w!("** rigid-coupling reference nodes (REF NODE: translations, ROT NODE: rotations)");
        w!("*NODE");
        for (cp, &(r, q)) in model.couplings.iter().zip(&ref_labels) {
            let [x, y, z] = cp.reference_point.map(fmt_real);
            w!("{r}, {x}, {y}, {z}");
            w!("{q}, {x}, {y}, {z}");
        }
    }

    let mut e = 0;
    while e < ne {
        let kind = mesh.elements[e].kind;
        w!("*ELEMENT, TYPE={}, ELSET=EALL", kind.name());
        while e < ne && mesh.elements[e].kind == kind {
            let el = &mesh.elements[e];
            let labels: Vec<u64> = std::iter::once(el.label)
                .chain(el.nodes.iter().map(|&n| mesh.node_labels[n]))
                .collect();
            let lines: Vec<&[u64]> = labels.chunks(PER_LINE).collect();
            for (k, chunk) in lines.iter().enumerate() {
                let sep = if k + 1 < lines.len() { "," } else { "" };
                w!("{}{sep}", join(chunk));
            }
            e += 1;
        }
    }

    let mut nset_names = Names::default();
    nset_names.claim("NALL".to_string());
    let mut written_nsets: HashMap<String, &Vec<usize>> = HashMap::new();
    for (name, members) in &mesh.node_sets {
        let base = deck_name(name);
        if base == "NALL" {
            if !is_identity(members, nn) {
                return Err(FlankError::Model(format!(
                    "node set {name} is not the set of all nodes, but NALL is reserved for it"
                )));
            }
            continue;
        }
        if members.is_empty() {
            w!("** empty node set {name} omitted");
            continue;
        }
        let dn = nset_names.claim(base);
        w!("*NSET, NSET={dn}");
        write_labels(&mut out, members.iter().map(|&n| mesh.node_labels[n]));
        written_nsets.insert(dn, members);
    }
    // the node set of each coupling: an identical set of the same name is reused
    let mut coupling_sets = Vec::with_capacity(model.couplings.len());
    for cp in &model.couplings {
        let mut nodes = cp.nodes.clone();
        nodes.sort_unstable();
        nodes.dedup();
        let base = deck_name(&cp.name);
        let set = if written_nsets.get(&base).is_some_and(|s| **s == nodes) {
            base
        } else {
            let dn = nset_names.claim(base);
            w!("*NSET, NSET={dn}");
            write_labels(&mut out, nodes.iter().map(|&n| mesh.node_labels[n]));
            dn
        };
        coupling_sets.push(set);
    }

    let mut elset_names = Names::default();
    elset_names.claim("EALL".to_string());
    let mut written_elsets: HashMap<String, &Vec<usize>> = HashMap::new();
    for (name, members) in &mesh.element_sets {
        let base = deck_name(name);
        if base == "EALL" {
            if !is_identity(members, ne) {
                return Err(FlankError::Model(format!(
                    "element set {name} is not the set of all elements, but EALL is reserved for it"
                )));
            }
            continue;
        }
        if members.is_empty() {
            w!("** empty element set {name} omitted");
            continue;
        }
        let dn = elset_names.claim(base);
        w!("*ELSET, ELSET={dn}");
        write_labels(&mut out, members.iter().map(|&e| mesh.elements[e].label));
        written_elsets.insert(dn, members);
    }

    // One element set per used material; an identical existing set named
    // M_<material> is reused, so writing a parsed deck again is stable.
    let mut by_material: Vec<Vec<usize>> = vec![Vec::new(); model.materials.len()];
    for (e, &m) in model.element_material.iter().enumerate() {
        by_material[m].push(e);
    }
    let mut mat_names = Names::default();
    let material_names: Vec<String> = model
        .materials
        .iter()
        .map(|m| mat_names.claim(deck_name(&m.name)))
        .collect();
    let mut sections = Vec::new();
    for (m, members) in by_material.iter().enumerate() {
        if members.is_empty() {
            continue;
        }
        let base = format!("M_{}", material_names[m]);
        let set = if written_elsets.get(&base).is_some_and(|s| *s == members) {
            base
        } else {
            let dn = elset_names.claim(base);
            w!("*ELSET, ELSET={dn}");
            write_labels(&mut out, members.iter().map(|&e| mesh.elements[e].label));
            dn
        };
        sections.push((set, m));
    }
    for (m, mat) in model.materials.iter().enumerate() {
        w!("*MATERIAL, NAME={}", material_names[m]);
        w!("*ELASTIC");
        w!("{}, {}", fmt_real(mat.young), fmt_real(mat.poisson));
    }
    for (set, m) in &sections {
        w!(
            "*SOLID SECTION, ELSET={set}, MATERIAL={}",
            material_names[*m]
        );
    }
    write_contact(&mut out, model);
    for (set, &(r, q)) in coupling_sets.iter().zip(&ref_labels) {
        w!("*RIGID BODY, NSET={set}, REF NODE={r}, ROT NODE={q}");
    }

    // reference DOF k of coupling c: (node label, DOF 1..3)
    let ref_dof = |c: usize, k: usize| {
        let (r, q) = ref_labels[c];
        if k < 3 {
            (r, k + 1)
        } else {
            (q, k - 2)
        }
    };
    w!("*STEP");
    w!("*STATIC");
    let coupling_fixed = model.couplings.iter().any(|cp| cp.free.contains(&false));
    if !model.dirichlet.is_empty() || coupling_fixed {
        w!("*BOUNDARY");
        for d in &model.dirichlet {
            let c = d.component + 1;
            w!(
                "{}, {c}, {c}, {}",
                mesh.node_labels[d.node],
                fmt_real(d.value)
            );
        }
        for (c, cp) in model.couplings.iter().enumerate() {
            for k in (0..6).filter(|&k| !cp.free[k]) {
                let (node, dof) = ref_dof(c, k);
                w!("{node}, {dof}, {dof}, 0");
            }
        }
    }
    let coupling_loaded = model
        .couplings
        .iter()
        .any(|cp| (0..6).any(|k| cp.free[k] && cp.load[k] != 0.0));
    if !model.forces.is_empty() || coupling_loaded {
        w!("*CLOAD");
        for f in &model.forces {
            w!(
                "{}, {}, {}",
                mesh.node_labels[f.node],
                f.component + 1,
                fmt_real(f.value)
            );
        }
        for (c, cp) in model.couplings.iter().enumerate() {
            for k in (0..6).filter(|&k| cp.free[k] && cp.load[k] != 0.0) {
                let (node, dof) = ref_dof(c, k);
                w!("{node}, {dof}, {}", fmt_real(cp.load[k]));
            }
        }
    }
    if !model.pressures.is_empty() {
        w!("*DLOAD");
        for p in &model.pressures {
            w!(
                "{}, P{}, {}",
                mesh.elements[p.element].label,
                p.face,
                fmt_real(p.value)
            );
        }
    }
    w!("*NODE PRINT, NSET=NALL");
    w!("U");
    if !model.contact.pairs.is_empty() {
        w!("*CONTACT PRINT");
        w!("CSTR, CDIS");
    }
    w!("*END STEP");
    Ok(out)
}

/// Writes the contact definition: surfaces, interactions, pairs. Names are
/// made deck-safe and unique per namespace; pairs use the written names.
fn write_contact(out: &mut String, model: &Model) {
    let def = &model.contact;
    if def.surfaces.is_empty() && def.interactions.is_empty() && def.pairs.is_empty() {
        return;
    }
    let mesh = &model.mesh;
    let mut surface_names = Names::default();
    let mut written_surface: HashMap<String, String> = HashMap::new();
    for surf in &def.surfaces {
        let dn = surface_names.claim(deck_name(&surf.name));
        written_surface.insert(surf.name.to_ascii_uppercase(), dn.clone());
        match &surf.kind {
            SurfaceKind::Element(faces) => {
                let _ = writeln!(out, "*SURFACE, NAME={dn}, TYPE=ELEMENT");
                for &(e, f) in faces {
                    let _ = writeln!(out, "{}, S{f}", mesh.elements[e].label);
                }
            }
            SurfaceKind::Node(nodes) => {
                let _ = writeln!(out, "*SURFACE, NAME={dn}, TYPE=NODE");
                for &n in nodes {
                    let _ = writeln!(out, "{}", mesh.node_labels[n]);
                }
            }
        }
    }
    let mut interaction_names = Names::default();
    let mut written_interaction: HashMap<String, String> = HashMap::new();
    for it in &def.interactions {
        let dn = interaction_names.claim(deck_name(&it.name));
        written_interaction.insert(it.name.to_ascii_uppercase(), dn.clone());
        let _ = writeln!(out, "*SURFACE INTERACTION, NAME={dn}");
        match &it.behavior {
            Some(PressureOverclosure::Hard) => {
                let _ = writeln!(out, "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=HARD");
            }
            Some(PressureOverclosure::Linear { slope, tension, c0 }) => {
                let _ = writeln!(out, "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR");
                // trailing values may be left out; a later one needs the earlier
                let vals = [*slope, *tension, *c0];
                if let Some(last) = vals.iter().rposition(|v| v.is_some()) {
                    let fields: Vec<String> = vals[..=last]
                        .iter()
                        .map(|v| v.map(fmt_real).unwrap_or_default())
                        .collect();
                    let _ = writeln!(out, "{}", fields.join(", "));
                }
            }
            None => {}
        }
        if let Some(fr) = &it.friction {
            let _ = writeln!(out, "*FRICTION");
            match fr.stick_slope {
                Some(k) => {
                    let _ = writeln!(out, "{}, {}", fmt_real(fr.mu), fmt_real(k));
                }
                None => {
                    let _ = writeln!(out, "{}", fmt_real(fr.mu));
                }
            }
        }
    }
    let name_of = |map: &HashMap<String, String>, n: &str| {
        map.get(&n.to_ascii_uppercase())
            .cloned()
            .unwrap_or_else(|| deck_name(n))
    };
    for p in &def.pairs {
        let sliding = if p.small_sliding {
            ", SMALL SLIDING"
        } else {
            ""
        };
        let _ = writeln!(
            out,
            "*CONTACT PAIR, INTERACTION={}, TYPE=NODE TO SURFACE{sliding}",
            name_of(&written_interaction, &p.interaction)
        );
        let _ = writeln!(
            out,
            "{}, {}",
            name_of(&written_surface, &p.slave),
            name_of(&written_surface, &p.master)
        );
    }
}

/// Rejects models the writer cannot express faithfully (so that no index
/// below can be out of range).
fn check_writable(model: &Model) -> Result<()> {
    let bad = |m: String| Err(FlankError::Model(m));
    let mesh = &model.mesh;
    let nn = mesh.coords.len();
    let ne = mesh.elements.len();
    if mesh.node_labels.len() != nn {
        return bad(format!(
            "{} node labels for {nn} nodes",
            mesh.node_labels.len()
        ));
    }
    let mut seen = HashSet::with_capacity(nn);
    for (&l, x) in mesh.node_labels.iter().zip(&mesh.coords) {
        if l == 0 || l > CCX_MAX_LABEL {
            return bad(format!(
                "node label {l} outside 1..={CCX_MAX_LABEL} (ccx limit)"
            ));
        }
        if !seen.insert(l) {
            return bad(format!("duplicate node label {l}"));
        }
        if !x.iter().all(|c| c.is_finite()) {
            return bad(format!("node {l} has a non-finite coordinate"));
        }
    }
    seen.clear();
    for el in &mesh.elements {
        if el.label == 0 || el.label > CCX_MAX_LABEL {
            return bad(format!(
                "element label {} outside 1..={CCX_MAX_LABEL} (ccx limit)",
                el.label
            ));
        }
        if !seen.insert(el.label) {
            return bad(format!("duplicate element label {}", el.label));
        }
        if el.nodes.len() != el.kind.node_count() || el.nodes.iter().any(|&n| n >= nn) {
            return bad(format!("element {} has invalid node indices", el.label));
        }
    }
    if model.element_material.len() != ne {
        return bad(format!(
            "{} element materials for {ne} elements",
            model.element_material.len()
        ));
    }
    if let Some(e) = model
        .element_material
        .iter()
        .position(|&m| m >= model.materials.len())
    {
        return bad(format!(
            "element {} has an undefined material",
            mesh.elements[e].label
        ));
    }
    for m in &model.materials {
        m.validate()?;
    }
    for d in &model.dirichlet {
        if d.node >= nn || d.component > 2 || !d.value.is_finite() {
            return bad(format!("invalid boundary condition {d:?}"));
        }
    }
    for f in &model.forces {
        if f.node >= nn || f.component > 2 || !f.value.is_finite() {
            return bad(format!("invalid nodal force {f:?}"));
        }
    }
    for p in &model.pressures {
        let ok = p.element < ne
            && p.face >= 1
            && p.face <= mesh.elements[p.element].kind.face_count()
            && p.value.is_finite();
        if !ok {
            return bad(format!("invalid pressure {p:?}"));
        }
    }
    for (name, s) in &mesh.node_sets {
        if s.iter().any(|&n| n >= nn) {
            return bad(format!("node set {name} has an invalid node index"));
        }
    }
    for (name, s) in &mesh.element_sets {
        if s.iter().any(|&e| e >= ne) {
            return bad(format!("element set {name} has an invalid element index"));
        }
    }
    let max_label = mesh.node_labels.iter().max().copied().unwrap_or(0);
    if max_label + 2 * model.couplings.len() as u64 > CCX_MAX_LABEL {
        return bad(format!(
            "no room above node label {max_label} for the couplings' reference nodes (ccx limit {CCX_MAX_LABEL})"
        ));
    }
    let mut owner: Vec<Option<usize>> = vec![None; nn];
    for (c, cp) in model.couplings.iter().enumerate() {
        if cp.nodes.is_empty() {
            return bad(format!("rigid coupling '{}' has no node", cp.name));
        }
        if !cp
            .reference_point
            .iter()
            .chain(&cp.load)
            .all(|v| v.is_finite())
        {
            return bad(format!(
                "rigid coupling '{}' has a non-finite reference point or load",
                cp.name
            ));
        }
        for &n in &cp.nodes {
            if n >= nn {
                return bad(format!(
                    "rigid coupling '{}' has an invalid node index",
                    cp.name
                ));
            }
            if let Some(o) = owner[n].filter(|&o| o != c) {
                return bad(format!(
                    "node {} belongs to two rigid couplings ('{}' and '{}')",
                    mesh.node_labels[n], model.couplings[o].name, cp.name
                ));
            }
            owner[n] = Some(c);
        }
    }
    if let Some(d) = model.dirichlet.iter().find(|d| owner[d.node].is_some()) {
        return bad(format!(
            "node {} of rigid coupling '{}' also has a Dirichlet condition",
            mesh.node_labels[d.node],
            model.couplings[owner[d.node].unwrap_or(0)].name
        ));
    }
    model.contact.validate(mesh)?;
    for it in &model.contact.interactions {
        let vals: Vec<f64> = match &it.behavior {
            Some(PressureOverclosure::Linear { slope, tension, c0 }) => {
                [*slope, *tension, *c0].iter().flatten().copied().collect()
            }
            _ => Vec::new(),
        };
        let fr: Vec<f64> = it
            .friction
            .iter()
            .flat_map(|f| std::iter::once(f.mu).chain(f.stick_slope))
            .collect();
        if vals.iter().chain(&fr).any(|v| !v.is_finite()) {
            return bad(format!(
                "surface interaction {} has a non-finite value",
                it.name
            ));
        }
    }
    Ok(())
}

/// Whether a sorted unique set is exactly `0..n`.
fn is_identity(members: &[usize], n: usize) -> bool {
    members.len() == n && members.iter().enumerate().all(|(i, &m)| i == m)
}

fn join(labels: &[u64]) -> String {
    labels
        .iter()
        .map(u64::to_string)
        .collect::<Vec<_>>()
        .join(", ")
}

fn write_labels(out: &mut String, labels: impl Iterator<Item = u64>) {
    let labels: Vec<u64> = labels.collect();
    for chunk in labels.chunks(PER_LINE) {
        let _ = writeln!(out, "{}", join(chunk));
    }
}

/// A deck-safe name: upper case, `[A-Z0-9_-]`, starting with a letter, at
/// most 70 characters (ccx allows 80; room for a uniqueness suffix).
fn deck_name(name: &str) -> String {
    let mut s: String = name
        .trim()
        .chars()
        .map(|c| {
            let c = c.to_ascii_uppercase();
            if c.is_ascii_alphanumeric() || c == '_' || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect();
    if !s.starts_with(|c: char| c.is_ascii_alphabetic()) {
        s.insert(0, 'X');
    }
    s.truncate(70);
    s
}

/// Names already used in one namespace.
#[derive(Default)]
struct Names(HashSet<String>);

impl Names {
    /// `base`, or `base_1`, `base_2`, ... if taken.
    fn claim(&mut self, base: String) -> String {
        if self.0.insert(base.clone()) {
            return base;
        }
        let mut k = 1;
        loop {
            let candidate = format!("{base}_{k}");
            if self.0.insert(candidate.clone()) {
                return candidate;
            }
            k += 1;
        }
    }
}

/// Formats a finite real for ccx: at most [`CCX_REAL_WIDTH`] characters,
/// exact (shortest round-trip digits) whenever an exact form fits, otherwise
/// rounded to as many significant digits as fit.
fn fmt_real(x: f64) -> String {
    // Fast path: Display is the shortest round-trip, positional; most fit.
    let plain = x.to_string();
    if plain.len() <= CCX_REAL_WIDTH {
        return plain;
    }
    let exact = compact_real(&format!("{x:e}"));
    if exact.len() <= CCX_REAL_WIDTH {
        return exact;
    }
    for digits in (1..17).rev() {
        let s = compact_real(&format!("{:.*e}", digits - 1, x));
        if s.len() <= CCX_REAL_WIDTH {
            return s;
        }
    }
    format!("{x:.0e}")
}

/// The shortest of scientific, integer-mantissa and positional notation for
/// a number given in Rust's `{:e}` form ("-1.25e-3"); all parse back to the
/// same value in Rust and Fortran.
fn compact_real(sci: &str) -> String {
    let (sign, rest) = match sci.strip_prefix('-') {
        Some(r) => ("-", r),
        None => ("", sci),
    };
    let Some((mantissa, exp)) = rest.split_once('e') else {
        return sci.to_string();
    };
    let Ok(exp) = exp.parse::<i64>() else {
        return sci.to_string();
    };
    let mut digits: String = mantissa.chars().filter(|c| *c != '.').collect();
    while digits.len() > 1 && digits.ends_with('0') {
        digits.pop();
    }
    let n = digits.len() as i64;
    // value = d1.d2d3... × 10^exp
    let scientific = {
        let mut s = digits[..1].to_string();
        if n > 1 {
            s.push('.');
            s.push_str(&digits[1..]);
        }
        if exp != 0 {
            s.push_str(&format!("e{exp}"));
        }
        s
    };
    let integer_mantissa = {
        let e = exp - (n - 1);
        if e == 0 {
            digits.clone()
        } else {
            format!("{digits}e{e}")
        }
    };
    let positional = if exp >= n - 1 {
        if exp - (n - 1) > 40 {
            None
        } else {
            Some(format!("{digits}{}", "0".repeat((exp - (n - 1)) as usize)))
        }
    } else if exp >= 0 {
        let k = (exp + 1) as usize;
        Some(format!("{}.{}", &digits[..k], &digits[k..]))
    } else if -exp > 40 {
        None
    } else {
        Some(format!(".{}{digits}", "0".repeat((-exp - 1) as usize)))
    };
    // Prefer positional notation on ties: it is the most readable.
    let mut best = positional.unwrap_or_else(|| scientific.clone());
    for cand in [scientific, integer_mantissa] {
        if cand.len() < best.len() {
            best = cand;
        }
    }
    format!("{sign}{best}")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::Mesh;

    /// One C3D20 element using every supported keyword, with comments, mixed
    /// case, a continued keyword line, GENERATE and a Fortran exponent.
    const HEX: &str = "\
** One C3D20 element: every supported keyword
*Heading
One hexahedron
*NODE, NSET=Nall
1, 0, 0, 0
2, 1., 0., 0.
3, 1, 1
4, 0, 1.0e0, 0,
5, 0, 0, 1
6, 1, 0, 1
7, 1, 1, 1
8, 0, 1, 1
9, 0.5, 0, 0
10, 1, 0.5, 0
11, 0.5, 1, 0
12, 0, 0.5, 0
13, 0.5, 0, 1
14, 1, 0.5, 1
15, 0.5, 1, 1
16, 0, 0.5, 1
17, 0, 0, 0.5
18, 1, 0, 0.5
19, 1, 1, 0.5
20, 0, 1, 5D-1
*Element, type=c3d20,
** comment inside a continued keyword line
 elset=Block
1, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15,
16, 17, 18, 19, 20
*NSET, NSET = bottom
1, 2, 3, 4, 9, 10, 11, 12
*nset,nset=TOP,generate
5, 8
13, 16, 1
*Nset, nset=Both
bottom, TOP
*ELSET,ELSET=E1,GENERATE
1,1
*MATERIAL, NAME=Steel
*ELASTIC
210000., 0.3
*DENSITY
7.85e-9
*SOLID SECTION, ELSET=BLOCK, MATERIAL=steel

*BOUNDARY
bottom, 1, 3
*STEP
*STATIC
*BOUNDARY
1, 1, 1, 0.0
top, 3, 3, -0.01
*CLOAD
7, 1, 100.5
*cload
7, 1, 1.5D1
*DLOAD
E1, P2, 5.0
*NODE PRINT, NSET=NALL
U
*EL PRINT, ELSET=EALL
S
*END STEP
";

    /// One C3D15 wedge.
    const WEDGE: &str = "\
*NODE, NSET=NALL
1,0,0,0
2,1,0,0
3,0,1,0
4,0,0,1
5,1,0,1
6,0,1,1
7,.5,0,0
8,.5,.5,0
9,0,.5,0
10,.5,0,1
11,.5,.5,1
12,0,.5,1
13,0,0,.5
14,1,0,.5
15,0,1,.5
*ELEMENT,TYPE=C3D15,ELSET=W
1,1,2,3,4,5,6,7,8,9,10,
11,12,13,14,15
*MATERIAL,NAME=AL
*ELASTIC
70000,0.33
*SOLID SECTION,ELSET=W,MATERIAL=AL
*BOUNDARY
1,1,3
2,2,3
3,3
*STEP
*STATIC
*DLOAD
1,P5,2.5
*NODE PRINT, NSET=NALL
U
*END STEP
";

    fn parse(deck: &str) -> Result<Deck> {
        parse_deck(deck, Path::new("test.inp"))
    }

    /// 1-based line of the first line containing `needle`.
    fn line_of(deck: &str, needle: &str) -> usize {
        deck.lines()
            .position(|l| l.contains(needle))
            .unwrap_or_else(|| panic!("'{needle}' not in deck"))
            + 1
    }

    fn with(deck: &str, from: &str, to: &str) -> String {
        assert!(deck.contains(from), "'{from}' not in deck");
        deck.replacen(from, to, 1)
    }

    /// Asserts a Parse error at `line` whose message contains `word`.
    fn expect_err(deck: &str, line: usize, word: &str) {
        match parse(deck) {
            Err(FlankError::Parse {
                line: l, message, ..
            }) => {
                assert_eq!(l, line, "wrong line for: {message}");
                assert!(
                    message.to_lowercase().contains(&word.to_lowercase()),
                    "'{word}' not in: {message}"
                );
            }
            other => panic!("expected a parse error, got {other:?}"),
        }
    }

    /// Node indices of the given labels.
    fn idx(mesh: &Mesh, labels: &[u64]) -> Vec<usize> {
        let mut v: Vec<usize> = labels.iter().map(|&l| mesh.node(l).unwrap()).collect();
        v.sort_unstable();
        v
    }

    #[test]
    fn hex_deck_with_all_keywords() {
        let deck = parse(HEX).unwrap();
        assert_eq!(deck.title.as_deref(), Some("One hexahedron"));
        let m = &deck.model;
        let mesh = &m.mesh;
        assert_eq!(mesh.node_count(), 20);
        assert_eq!(mesh.coords[mesh.node(3).unwrap()], [1.0, 1.0, 0.0]);
        assert_eq!(mesh.coords[mesh.node(4).unwrap()], [0.0, 1.0, 0.0]);
        assert_eq!(mesh.coords[mesh.node(20).unwrap()], [0.0, 1.0, 0.5]);
        assert_eq!(mesh.elements.len(), 1);
        assert_eq!(mesh.elements[0].kind, ElementKind::C3D20);
        assert_eq!(mesh.elements[0].nodes, (0..20).collect::<Vec<_>>());

        let bottom = idx(mesh, &[1, 2, 3, 4, 9, 10, 11, 12]);
        let top = idx(mesh, &[5, 6, 7, 8, 13, 14, 15, 16]);
        assert_eq!(mesh.node_sets["BOTTOM"], bottom);
        assert_eq!(mesh.node_sets["TOP"], top);
        assert_eq!(mesh.node_sets["BOTH"].len(), 16);
        assert_eq!(mesh.node_sets["NALL"].len(), 20);
        assert_eq!(mesh.element_sets["BLOCK"], vec![0]);
        assert_eq!(mesh.element_sets["E1"], vec![0]);
        assert_eq!(mesh.element_sets["EALL"], vec![0]);

        assert_eq!(m.materials.len(), 1);
        assert_eq!(m.materials[0].name, "STEEL");
        assert_eq!(m.materials[0].young, 210000.0);
        assert_eq!(m.materials[0].poisson, 0.3);
        assert_eq!(m.element_material, vec![0]);

        // 8 bottom nodes x 3 (node 1/x repeated: deduplicated) + 8 top z.
        assert_eq!(m.dirichlet.len(), 32);
        let bc = |label: u64, c: usize| {
            let n = mesh.node(label).unwrap();
            let v: Vec<f64> = m
                .dirichlet
                .iter()
                .filter(|d| d.node == n && d.component == c)
                .map(|d| d.value)
                .collect();
            assert_eq!(v.len(), 1, "node {label} comp {c}");
            v[0]
        };
        assert_eq!(bc(1, 0), 0.0);
        assert_eq!(bc(12, 2), 0.0);
        assert_eq!(bc(5, 2), -0.01);
        assert_eq!(bc(16, 2), -0.01);

        let n7 = mesh.node(7).unwrap();
        assert_eq!(
            m.forces,
            vec![
                NodalForce {
                    node: n7,
                    component: 0,
                    value: 100.5
                },
                NodalForce {
                    node: n7,
                    component: 0,
                    value: 15.0
                },
            ]
        );
        assert_eq!(
            m.pressures,
            vec![Pressure {
                element: 0,
                face: 2,
                value: 5.0
            }]
        );
        assert_eq!(deck.warnings.len(), 1, "{:?}", deck.warnings);
        assert_eq!(deck.warnings[0].line, line_of(HEX, "*DENSITY"));
        assert!(deck.warnings[0].message.contains("DENSITY"));
    }

    #[test]
    fn trailing_comma_on_keyword_before_data() {
        // ccx ignores the comma; "bottom, 1, 3" stays a data line.
        let d = with(HEX, "*BOUNDARY\nbottom", "*BOUNDARY,\nbottom");
        let d = with(&d, "*nset,nset=TOP,generate", "*nset,nset=TOP,\n GENERATE");
        let m = parse(&d).unwrap().model;
        assert_eq!(m.dirichlet, parse(HEX).unwrap().model.dirichlet);
        assert_eq!(m.mesh.node_sets["TOP"].len(), 8);
    }

    #[test]
    fn wedge_deck() {
        let deck = parse(WEDGE).unwrap();
        let m = &deck.model;
        assert_eq!(m.mesh.node_count(), 15);
        assert_eq!(m.mesh.elements[0].kind, ElementKind::C3D15);
        assert_eq!(m.mesh.elements[0].nodes, (0..15).collect::<Vec<_>>());
        assert_eq!(m.mesh.coords[10], [0.5, 0.5, 1.0]);
        assert_eq!(m.materials[0].poisson, 0.33);
        let mut bcs: Vec<(usize, usize)> =
            m.dirichlet.iter().map(|d| (d.node, d.component)).collect();
        bcs.sort_unstable();
        assert_eq!(bcs, vec![(0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2)]);
        assert_eq!(
            m.pressures,
            vec![Pressure {
                element: 0,
                face: 5,
                value: 2.5
            }]
        );
        assert!(deck.warnings.is_empty(), "{:?}", deck.warnings);
        // A wedge has five faces.
        let bad = with(WEDGE, "1,P5,2.5", "1,P6,2.5");
        expect_err(&bad, line_of(&bad, "1,P6"), "P6");
    }

    #[test]
    fn nodes_may_follow_elements() {
        let nodes_end = WEDGE.find("*ELEMENT").unwrap();
        let elems_end = WEDGE.find("*MATERIAL").unwrap();
        let reordered = format!(
            "{}{}{}",
            &WEDGE[nodes_end..elems_end],
            &WEDGE[..nodes_end],
            &WEDGE[elems_end..]
        );
        let m = parse(&reordered).unwrap().model;
        assert_eq!(m.mesh.elements[0].nodes, (0..15).collect::<Vec<_>>());
    }

    #[test]
    fn implicit_eall_and_nall() {
        let deck = with(HEX, "ELSET=BLOCK, MATERIAL", "ELSET=EALL, MATERIAL");
        let deck = with(&deck, "*NODE, NSET=Nall", "*NODE");
        let deck = with(&deck, "bottom, 1, 3", "NALL, 1, 1");
        let m = parse(&deck).unwrap().model;
        assert_eq!(m.element_material, vec![0]);
        assert_eq!(m.mesh.node_sets["NALL"].len(), 20);
        assert_eq!(m.dirichlet.iter().filter(|d| d.component == 0).count(), 20);
    }

    #[test]
    fn include_is_followed_relative_to_including_file() {
        let dir = std::env::temp_dir().join(format!("flank-inp-test-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("sub")).unwrap();
        let node_start = HEX.find("1, 0, 0, 0").unwrap();
        let node_end = HEX.find("*Element").unwrap();
        // Data-only include: the node lines continue the *NODE block.
        std::fs::write(dir.join("sub/nodes.inc"), &HEX[node_start..node_end]).unwrap();
        let main = format!(
            "{}*INCLUDE, INPUT=sub/nodes.inc\n{}",
            &HEX[..node_start],
            &HEX[node_end..]
        );
        std::fs::write(dir.join("main.inp"), &main).unwrap();
        let deck = read_deck(&dir.join("main.inp")).unwrap();
        assert_eq!(deck.model.mesh.node_count(), 20);
        assert_eq!(deck.model.mesh.node_sets["NALL"].len(), 20);

        // Errors inside an included file name that file and its line.
        let bad = HEX[node_start..node_end].replace("6, 1, 0, 1", "6, 1, x, 1");
        std::fs::write(dir.join("sub/nodes.inc"), &bad).unwrap();
        match read_deck(&dir.join("main.inp")) {
            Err(FlankError::Parse { file, line, .. }) => {
                assert!(file.ends_with("sub/nodes.inc"));
                assert_eq!(line, line_of(&bad, "6, 1, x"));
            }
            other => panic!("{other:?}"),
        }

        // A file including itself stops with an error, and a missing file too.
        std::fs::write(dir.join("loop.inp"), "*INCLUDE, INPUT=loop.inp\n").unwrap();
        assert!(matches!(
            read_deck(&dir.join("loop.inp")),
            Err(FlankError::Parse { line: 1, .. })
        ));
        std::fs::write(dir.join("missing.inp"), "**\n*INCLUDE, INPUT=nope.inp\n").unwrap();
        assert!(matches!(
            read_deck(&dir.join("missing.inp")),
            Err(FlankError::Parse { line: 2, .. })
        ));
        std::fs::remove_dir_all(&dir).unwrap();
    }

    // -- bad decks ----------------------------------------------------------

    #[test]
    fn unknown_element_type() {
        let d = with(HEX, "type=c3d20", "type=C3D8");
        expect_err(&d, line_of(&d, "type=C3D8"), "C3D8");
    }

    #[test]
    fn element_with_missing_node() {
        let d = with(HEX, "16, 17, 18, 19, 20", "16, 17, 18, 19, 99");
        expect_err(&d, line_of(&d, "1, 1, 2, 3, 4"), "undefined node 99");
    }

    #[test]
    fn negative_young_modulus() {
        let d = with(HEX, "210000., 0.3", "-210000., 0.3");
        expect_err(&d, line_of(&d, "-210000."), "Young");
    }

    #[test]
    fn poisson_ratio_half() {
        let d = with(HEX, "210000., 0.3", "210000., 0.5");
        expect_err(&d, line_of(&d, "210000., 0.5"), "Poisson");
    }

    #[test]
    fn undefined_set_in_boundary() {
        let d = with(HEX, "bottom, 1, 3", "bottm, 1, 3");
        expect_err(&d, line_of(&d, "bottm"), "BOTTM");
    }

    #[test]
    fn undefined_set_in_solid_section() {
        let d = with(HEX, "ELSET=BLOCK, MATERIAL", "ELSET=BLOK, MATERIAL");
        expect_err(&d, line_of(&d, "ELSET=BLOK"), "BLOK");
    }

    #[test]
    fn undefined_material() {
        let d = with(HEX, "MATERIAL=steel", "MATERIAL=brass");
        expect_err(&d, line_of(&d, "MATERIAL=brass"), "BRASS");
    }

    #[test]
    fn malformed_number() {
        let d = with(HEX, "2, 1., 0., 0.", "2, 1.0.0, 0., 0.");
        expect_err(&d, line_of(&d, "1.0.0"), "malformed number '1.0.0'");
        let d = with(HEX, "7, 1, 100.5", "7, 1, nan");
        expect_err(&d, line_of(&d, "7, 1, nan"), "nan");
        let d = with(HEX, "7, 1, 100.5", "7x, 1, 100.5");
        expect_err(&d, line_of(&d, "7x, 1"), "7x");
    }

    #[test]
    fn incomplete_element() {
        // Cut off by the next keyword: error at the element's first line.
        let d = with(HEX, "16, 17, 18, 19, 20\n", "");
        expect_err(&d, line_of(&d, "1, 1, 2, 3, 4"), "incomplete");
        // A new element starts while the previous one lacks nodes.
        let d = with(
            HEX,
            "16, 17, 18, 19, 20\n",
            "2, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15,\n16, 17, 18, 19, 20\n",
        );
        expect_err(&d, line_of(&d, "2, 1, 2, 3, 4"), "incomplete element 1");
        // Too many nodes on one element.
        let d = with(HEX, "16, 17, 18, 19, 20", "16, 17, 18, 19, 20, 1");
        expect_err(&d, line_of(&d, "16, 17, 18, 19, 20, 1"), "incomplete");
    }

    #[test]
    fn duplicate_labels_and_repeated_nodes() {
        let d = with(HEX, "6, 1, 0, 1", "5, 1, 0, 1");
        expect_err(&d, line_of(&d, "5, 1, 0, 1"), "duplicate node label 5");
        let d = with(HEX, "16, 17, 18, 19, 20", "16, 17, 18, 19, 1");
        expect_err(&d, line_of(&d, "1, 1, 2, 3, 4"), "more than once");
        let d = with(
            HEX,
            "*NSET, NSET = bottom",
            "*ELEMENT, TYPE=C3D20\n1, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16,\n17, 18, 19, 20\n*NSET, NSET = bottom",
        );
        expect_err(&d, line_of(&d, "15, 16,"), "duplicate element label 1");
    }

    #[test]
    fn dload_face_out_of_range() {
        let d = with(HEX, "E1, P2, 5.0", "E1, P7, 5.0");
        expect_err(&d, line_of(&d, "E1, P7"), "face");
        let d = with(HEX, "E1, P2, 5.0", "E1, GRAV, 9810., 0., 0., -1.");
        expect_err(&d, line_of(&d, "GRAV"), "unsupported *DLOAD load type GRAV");
    }

    #[test]
    fn cload_before_step() {
        let d = with(HEX, "*STEP\n", "*CLOAD\n7, 1, 1.0\n*STEP\n");
        expect_err(&d, line_of(&d, "*CLOAD"), "step");
    }

    #[test]
    fn second_step() {
        let d = with(HEX, "*END STEP", "*END STEP\n*STEP\n*STATIC\n*END STEP");
        expect_err(&d, line_of(&d, "*END STEP") + 1, "step");
    }

    #[test]
    fn nonlinear_step_and_other_procedures() {
        let d = with(HEX, "*STEP\n", "*STEP, NLGEOM\n");
        expect_err(&d, line_of(&d, "NLGEOM"), "NLGEOM");
        let d = with(HEX, "*STEP\n", "*STEP, NLGEOM=YES, INC=100\n");
        expect_err(&d, line_of(&d, "NLGEOM"), "NLGEOM");
        let d = with(HEX, "*STEP\n", "*STEP, NLGEOM=NO, INC=100\n");
        assert!(parse(&d).is_ok());
        let d = with(HEX, "*STATIC", "*FREQUENCY");
        expect_err(&d, line_of(&d, "*FREQUENCY"), "FREQUENCY");
    }

    #[test]
    fn unknown_keyword_is_a_warning() {
        let d = with(HEX, "*STEP\n", "*FOOBAR, X=1\nsome, data\n*STEP\n");
        let deck = parse(&d).unwrap();
        let w = deck
            .warnings
            .iter()
            .find(|w| w.message.contains("FOOBAR"))
            .expect("warning");
        assert_eq!(w.line, line_of(&d, "*FOOBAR"));
    }

    #[test]
    fn answer_changing_keywords_are_errors() {
        let d = with(
            HEX,
            "*STEP\n",
            "*EQUATION\n2\n1, 1, 1.0, 2, 1, -1.0\n*STEP\n",
        );
        expect_err(&d, line_of(&d, "*EQUATION"), "EQUATION");
        let d = with(HEX, "*ELASTIC", "*ELASTIC, TYPE=ORTHO");
        expect_err(&d, line_of(&d, "TYPE=ORTHO"), "ORTHO");
        let d = with(HEX, "*DENSITY\n7.85e-9", "*PLASTIC\n500., 0.");
        expect_err(&d, line_of(&d, "*PLASTIC"), "PLASTIC");
        let d = with(
            HEX,
            "*CLOAD\n7, 1, 100.5",
            "*CLOAD, AMPLITUDE=A1\n7, 1, 100.5",
        );
        expect_err(&d, line_of(&d, "AMPLITUDE"), "AMPLITUDE");
    }

    #[test]
    fn boundary_dofs() {
        let d = with(HEX, "1, 1, 1, 0.0", "1, 11, 11, 20.");
        expect_err(&d, line_of(&d, "1, 11"), "11");
        let d = with(HEX, "1, 1, 1, 0.0", "1, 5, 5, 0.1");
        expect_err(&d, line_of(&d, "1, 5, 5"), "rotational");
        let d = with(HEX, "1, 1, 1, 0.0", "1, 1, 6");
        let deck = parse(&d).unwrap();
        assert!(deck
            .warnings
            .iter()
            .any(|w| w.line == line_of(&d, "1, 1, 6")));
        let d = with(HEX, "7, 1, 100.5", "7, 4, 100.5");
        expect_err(&d, line_of(&d, "7, 4"), "DOF 4");
        // Last value wins on a repeated constraint.
        let d = with(HEX, "1, 1, 1, 0.0", "1, 1, 1, 0.25");
        let m = parse(&d).unwrap().model;
        let n1 = m.mesh.node(1).unwrap();
        let v: Vec<f64> = m
            .dirichlet
            .iter()
            .filter(|b| b.node == n1 && b.component == 0)
            .map(|b| b.value)
            .collect();
        assert_eq!(v, vec![0.25]);
    }

    #[test]
    fn element_without_section() {
        let d = with(HEX, "*SOLID SECTION, ELSET=BLOCK, MATERIAL=steel\n", "");
        expect_err(
            &d,
            line_of(&d, "1, 1, 2, 3, 4"),
            "element 1 has no *SOLID SECTION",
        );
    }

    #[test]
    fn temperature_dependent_elastic_uses_first_line() {
        let d = with(
            HEX,
            "210000., 0.3",
            "210000., 0.3, 20.\n200000., 0.31, 300.",
        );
        let deck = parse(&d).unwrap();
        assert_eq!(deck.model.materials[0].young, 210000.0);
        assert!(deck
            .warnings
            .iter()
            .any(|w| w.line == line_of(&d, "200000.")));
    }

    #[test]
    fn huge_generate_range_is_cheap() {
        let d = with(
            HEX,
            "*Nset, nset=Both",
            "*NSET, NSET=G, GENERATE\n1, 18446744073709551615\n*Nset, nset=Both",
        );
        let deck = parse(&d).unwrap();
        assert_eq!(deck.model.mesh.node_sets["G"].len(), 20);
        assert!(deck.warnings.iter().any(|w| w.message.contains("GENERATE")));
    }

    #[test]
    fn many_set_blocks_stay_linear() {
        // 2000 *NODE blocks all extending one set: no re-sorting per block.
        let mut s = String::new();
        for b in 0..2000u64 {
            s.push_str("*NODE, NSET=BIG\n");
            for k in 0..100u64 {
                let l = b * 100 + k + 1;
                let _ = writeln!(s, "{l}, {}, 0, 0", l as f64 * 0.5);
            }
            let _ = writeln!(s, "*NSET, NSET=BIG\n{}", b * 100 + 1);
        }
        let deck = parse(&s).unwrap();
        assert_eq!(deck.model.mesh.node_sets["BIG"].len(), 200_000);
    }

    #[test]
    fn garbage_does_not_panic() {
        let bytes: Vec<u8> = (0..=255u8).cycle().take(4096).collect();
        let binary = String::from_utf8_lossy(&bytes).into_owned();
        let cases = [
            binary.as_str(),
            "\0\u{1}\u{2}\u{ff}\u{fe}\u{7f}",
            "*",
            "*,,,=",
            "*=,=",
            "1, 2, 3",
            "*NODE\n1,2,3,4,5,6,7\n*ELEMENT,TYPE=\n",
            "*ELEMENT, TYPE=C3D20\n1,\n",
            "*ELEMENT, TYPE=C3D20\n1,2,3\n*NODE\n1\n",
            "*NSET,NSET=A,GENERATE\n1\n",
            "*NSET,NSET=A,GENERATE\n5, 1\n",
            "*NSET,NSET=A\nA\n",
            "*NODE\n-1, 0, 0, 0",
            "*NODE\n18446744073709551616, 0",
            "*NODE\n1, 1e999",
            "*STEP\n*STEP",
            "*STEP\n*STATIC\n*DLOAD\n1, P99999999999999999999999, 1\n",
            "*BOUNDARY\n1, 3, 1\n",
            "*BOUNDARY\n1, 0\n",
            "*MATERIAL\n*ELASTIC\n1,0.3\n",
            "*ELASTIC\n1, 0.3",
            "*MATERIAL, NAME=\"\"\n",
            "*INCLUDE\n",
            "*INCLUDE, INPUT=\n",
            "*HEADING\n\u{feff}\u{202e}text",
            "\u{feff}*NODE\n1,0,0,0\r\n2,0,0,0\r\n",
        ];
        for c in cases {
            let _ = parse(c);
        }
        // Random decks from keyword and data fragments.
        let fragments = [
            "*NODE",
            "*NODE, NSET=A",
            "*ELEMENT, TYPE=C3D20",
            "*ELEMENT,TYPE=C3D15,ELSET=E",
            "*ELEMENT,TYPE=C3D20R,",
            "*NSET,NSET=A,GENERATE",
            "*ELSET,ELSET=E",
            "*ELSET,ELSET=E,GENERATE",
            "*MATERIAL,NAME=M",
            "*ELASTIC",
            "*SOLID SECTION,ELSET=E,MATERIAL=M",
            "*STEP",
            "*STATIC",
            "*END STEP",
            "*BOUNDARY",
            "*CLOAD",
            "*DLOAD",
            "*HEADING",
            "*FOO",
            "**",
            "",
            "*INCLUDE,INPUT=/nonexistent/x.inp",
            "1, 2, 3",
            "1, 0, 0, 0",
            "2, 1.5, -3e2",
            "a, b",
            ",",
            ",,,",
            "E, P3, 1",
            "E, P6, -1",
            "A, 1, 3",
            "A, 2",
            "1, 1, 3, 0.5",
            "1e999",
            "P0",
            "1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15,",
            "16, 17, 18, 19, 20",
            "3, 1",
            "0, 0",
            "18446744073709551615, 1, 1",
            "210000, 0.3",
            "1, 0.5",
            "NALL, 1, 3",
            "EALL, P1, 2",
            "\u{0}\u{1}*",
            "1,,,",
            "  *  node  ,  nset = a  ",
            "7, 1, 1.0",
            "*SURFACE, NAME=S, TYPE=ELEMENT",
            "*SURFACE,NAME=N,TYPE=NODE",
            "*SURFACE, NAME=S",
            "E, S2",
            "1, S9",
            "1, SPOS",
            "*SURFACE INTERACTION, NAME=I",
            "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR",
            "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=HARD",
            "*SURFACE BEHAVIOR",
            "*FRICTION",
            "-0.1",
            "0.2, 1e5",
            "*CONTACT PAIR, INTERACTION=I, TYPE=NODE TO SURFACE",
            "*CONTACT PAIR, INTERACTION=J",
            "S, N",
            "N, S",
            "1e7, 0.1, 1e-3",
            "*CONTACT PRINT",
        ];
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        for _ in 0..3000 {
            let mut deck = String::new();
            for _ in 0..(next() % 40) {
                deck.push_str(fragments[(next() % fragments.len() as u64) as usize]);
                deck.push('\n');
            }
            let _ = parse(&deck);
        }
    }

    /// Timing on a large structured deck (about 800k nodes, 96k C3D20):
    /// `cargo test --lib mesh::inp::tests::large_deck -- --ignored --nocapture`.
    #[test]
    #[ignore]
    fn large_deck() {
        let (nx, ny, nz) = (40usize, 40usize, 60usize);
        let (ax, ay) = (2 * nx + 1, 2 * ny + 1);
        let id = |a: usize, b: usize, c: usize| 1 + a + ax * (b + ay * c);
        let mut s = String::from("*NODE, NSET=NALL\n");
        for c in 0..=2 * nz {
            for b in 0..ay {
                for a in 0..ax {
                    let x = [a as f64 * 0.25, b as f64 * 0.25, c as f64 * 0.1 - 3.0];
                    let _ = writeln!(s, "{}, {}, {}, {}", id(a, b, c), x[0], x[1], x[2]);
                }
            }
        }
        s.push_str("*ELEMENT, TYPE=C3D20, ELSET=EALL\n");
        let pattern: [(usize, usize, usize); 20] = [
            (0, 0, 0),
            (2, 0, 0),
            (2, 2, 0),
            (0, 2, 0),
            (0, 0, 2),
            (2, 0, 2),
            (2, 2, 2),
            (0, 2, 2),
            (1, 0, 0),
            (2, 1, 0),
            (1, 2, 0),
            (0, 1, 0),
            (1, 0, 2),
            (2, 1, 2),
            (1, 2, 2),
            (0, 1, 2),
            (0, 0, 1),
            (2, 0, 1),
            (2, 2, 1),
            (0, 2, 1),
        ];
        let mut label = 0;
        for k in 0..nz {
            for j in 0..ny {
                for i in 0..nx {
                    label += 1;
                    let nodes: Vec<String> = pattern
                        .iter()
                        .map(|&(a, b, c)| id(2 * i + a, 2 * j + b, 2 * k + c).to_string())
                        .collect();
                    let _ = writeln!(
                        s,
                        "{label}, {},\n{}",
                        nodes[..15].join(", "),
                        nodes[15..].join(", ")
                    );
                }
            }
        }
        s.push_str("*MATERIAL, NAME=STEEL\n*ELASTIC\n210000, 0.3\n");
        s.push_str("*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n");
        s.push_str("*NSET, NSET=BOTTOM, GENERATE\n1, 6561\n*BOUNDARY\nBOTTOM, 1, 3\n");
        s.push_str("*STEP\n*STATIC\n*CLOAD\nNALL, 3, 0.001\n*END STEP\n");
        let t = std::time::Instant::now();
        let deck = parse(&s).unwrap();
        let parse_time = t.elapsed();
        let t = std::time::Instant::now();
        let text = format_deck(&deck.model).unwrap();
        let write_time = t.elapsed();
        eprintln!(
            "{} MB, {} nodes, {} elements: parse {parse_time:?}, format {write_time:?} ({} MB)",
            s.len() >> 20,
            deck.model.mesh.node_count(),
            deck.model.mesh.elements.len(),
            text.len() >> 20
        );
        assert_eq!(deck.model.mesh.elements.len(), nx * ny * nz);
    }

    /// Runs ccx (if on PATH) in a fresh directory on `deck`; returns the
    /// displacements printed to the .dat file, by node label.
    fn run_ccx(dir: &Path, job: &str, deck: &str) -> Option<HashMap<u64, [f64; 3]>> {
        std::fs::write(dir.join(format!("{job}.inp")), deck).unwrap();
        let status = std::process::Command::new("ccx")
            .args(["-i", job])
            .current_dir(dir)
            .env("OMP_NUM_THREADS", "1")
            .env("CCX_NPROC_EQUATION_SOLVER", "1")
            .stdout(std::process::Stdio::null())
            .status()
            .ok()?;
        assert!(status.success(), "ccx failed on {job}");
        let dat = std::fs::read_to_string(dir.join(format!("{job}.dat"))).unwrap();
        let mut u = HashMap::new();
        let mut on = false;
        for line in dat.lines() {
            if line.contains("displacements") {
                on = true;
                continue;
            }
            let f: Vec<&str> = line.split_whitespace().collect();
            if on && f.len() == 4 {
                let v = |k: usize| f[k].parse::<f64>().unwrap();
                u.insert(f[0].parse().unwrap(), [v(1), v(2), v(3)]);
            } else if on && !u.is_empty() {
                on = false;
            }
        }
        assert!(!u.is_empty(), "no displacements in {job}.dat");
        Some(u)
    }

    /// Checks the writer against a real ccx 2.20: written decks give the same
    /// answer as the hand-written ones, and every real notation the writer
    /// emits is read correctly. `cargo test --lib mesh::inp -- --ignored`.
    #[test]
    #[ignore]
    fn ccx_reads_written_decks() {
        let dir = std::env::temp_dir().join(format!("flank-inp-ccx-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        // ccx 2.20 has no keyword-line continuation (an Abaqus feature).
        let hex = with(
            HEX,
            "*Element, type=c3d20,\n** comment inside a continued keyword line\n elset=Block",
            "*Element, type=c3d20, elset=Block",
        );
        for (name, deck) in [("hex", hex.as_str()), ("wedge", WEDGE)] {
            let Some(reference) = run_ccx(&dir, &format!("{name}_orig"), deck) else {
                eprintln!("ccx not found: skipped");
                return;
            };
            let written = format_deck(&parse(deck).unwrap().model).unwrap();
            let u = run_ccx(&dir, &format!("{name}_flank"), &written).unwrap();
            assert_eq!(u, reference, "{name}");
        }
        // Prescribed displacements in every notation fmt_real produces.
        let mut m = parse(HEX).unwrap().model;
        let values = [
            -0.5,
            0.3,
            -0.001_928_974_961_629_137,
            -2.5e-27,
            1.234_567_890_123_456_7e-15,
            1200.0,
            -6.123_233_995_736_766e-17,
            0.1 + 0.2,
        ];
        let top: Vec<usize> = m.mesh.node_sets["TOP"].clone();
        m.dirichlet.retain(|d| !top.contains(&d.node));
        for (&node, &value) in top.iter().zip(&values) {
            eprintln!("{value:e} written as {}", fmt_real(value));
            m.dirichlet.push(Dirichlet {
                node,
                component: 2,
                value,
            });
        }
        let u = run_ccx(&dir, "notation", &format_deck(&m).unwrap()).unwrap();
        for (&node, &value) in top.iter().zip(&values) {
            let uz = u[&m.mesh.node_labels[node]][2];
            assert!(
                (uz - value).abs() <= 1e-6 * value.abs(),
                "{value:e}: ccx read {uz:e}"
            );
        }
        // Why 20 characters: a {:.17e} value loses its exponent in ccx 2.20
        // (the run succeeds with uz = -3 instead of -0.3).
        let long = format!("{:.17e}", -0.3);
        let bad = with(&hex, "top, 3, 3, -0.01", &format!("top, 3, 3, {long}"));
        let u = run_ccx(&dir, "long", &bad).unwrap();
        eprintln!("{long} was read by ccx as {:e}", u[&5][2]);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    // -- writer -------------------------------------------------------------

    /// Three elements of all kinds, two materials, sets, every load type.
    fn sample_model() -> Model {
        let mut mesh = Mesh::new();
        for i in 0..36u64 {
            let f = i as f64;
            let x = [
                f * 0.1,
                ((i * 7 % 13) as f64).sqrt() * 3.3,
                -f / 3.0 + (f * 0.7).sin() * 40.0,
            ];
            mesh.add_node(1000 + 3 * i, x).unwrap();
        }
        mesh.add_element(7, ElementKind::C3D20, (0..20).collect())
            .unwrap();
        mesh.add_element(3, ElementKind::C3D20R, (8..28).collect())
            .unwrap();
        mesh.add_element(100, ElementKind::C3D15, (21..36).collect())
            .unwrap();
        mesh.extend_node_set("FIX", [0, 1, 2, 3]);
        mesh.extend_element_set("HUB", [1]);
        let mut dirichlet = Vec::new();
        for node in 0..4 {
            for component in 0..3 {
                dirichlet.push(Dirichlet {
                    node,
                    component,
                    value: 0.0,
                });
            }
        }
        dirichlet.push(Dirichlet {
            node: 30,
            component: 1,
            value: -0.0123,
        });
        Model {
            mesh,
            materials: vec![
                Material::new("steel", 210000.0, 0.3).unwrap(),
                Material::new("Bronze alloy", 1.1e5, 0.34).unwrap(),
            ],
            element_material: vec![0, 1, 0],
            dirichlet,
            forces: vec![
                NodalForce {
                    node: 33,
                    component: 2,
                    value: 1234.5,
                },
                NodalForce {
                    node: 33,
                    component: 2,
                    value: 0.1 + 0.2,
                },
            ],
            pressures: vec![
                Pressure {
                    element: 0,
                    face: 2,
                    value: 1.5,
                },
                Pressure {
                    element: 2,
                    face: 5,
                    value: -2.25,
                },
            ],
            couplings: Vec::new(),
            contact: Default::default(),
        }
    }

    #[test]
    fn round_trip() {
        let m = sample_model();
        let text = format_deck(&m).unwrap();
        let deck = parse(&text).unwrap();
        assert!(deck.warnings.is_empty(), "{:?}", deck.warnings);
        let p = &deck.model;
        assert_eq!(p.mesh.node_labels, m.mesh.node_labels);
        for (a, b) in p.mesh.coords.iter().zip(&m.mesh.coords) {
            for k in 0..3 {
                assert_eq!(a[k].to_bits(), b[k].to_bits(), "{a:?} vs {b:?}");
            }
        }
        assert_eq!(p.mesh.elements, m.mesh.elements);
        assert_eq!(p.materials.len(), 2);
        for (a, b) in p.materials.iter().zip(&m.materials) {
            assert_eq!(a.name, deck_name(&b.name));
            assert_eq!(a.young.to_bits(), b.young.to_bits());
            assert_eq!(a.poisson.to_bits(), b.poisson.to_bits());
        }
        assert_eq!(p.materials[1].name, "BRONZE_ALLOY");
        assert_eq!(p.element_material, m.element_material);
        assert_eq!(p.dirichlet, m.dirichlet);
        assert_eq!(p.forces, m.forces);
        assert_eq!(p.pressures, m.pressures);
        assert_eq!(p.mesh.node_sets["FIX"], m.mesh.node_sets["FIX"]);
        assert_eq!(p.mesh.element_sets["HUB"], m.mesh.element_sets["HUB"]);
        assert_eq!(p.mesh.node_sets["NALL"].len(), 36);
        assert_eq!(p.mesh.element_sets["EALL"], vec![0, 1, 2]);

        // Writing the parsed model again reaches a fixed point.
        let again = format_deck(p).unwrap();
        let twice = format_deck(&parse(&again).unwrap().model).unwrap();
        assert_eq!(again, twice);
    }

    #[test]
    fn written_deck_fits_ccx_limits() {
        let text = format_deck(&sample_model()).unwrap();
        for line in text.lines() {
            assert!(line.len() <= 132, "{line}");
            if !looks_numeric(line) {
                continue; // keywords, comments, heading text
            }
            let fields = split_fields(line);
            assert!(fields.len() <= 16, "{line}");
            for f in fields {
                assert!(f.len() <= CCX_REAL_WIDTH, "{line}");
            }
        }
        assert!(text.contains("*NODE, NSET=NALL\n"));
        assert!(text.contains("*ELEMENT, TYPE=C3D20R, ELSET=EALL\n"));
        assert!(text.contains("*SOLID SECTION, ELSET=M_STEEL, MATERIAL=STEEL\n"));
        assert!(text.contains("*NODE PRINT, NSET=NALL\nU\n*END STEP\n"));
    }

    #[test]
    fn write_deck_to_file() {
        let path = std::env::temp_dir().join(format!("flank-inp-write-{}.inp", std::process::id()));
        let m = sample_model();
        write_deck(&m, &path).unwrap();
        let p = read_deck(&path).unwrap().model;
        assert_eq!(p.mesh.elements, m.mesh.elements);
        std::fs::remove_file(&path).unwrap();
    }

    #[test]
    fn writer_rejects_what_it_cannot_express() {
        // a node in two couplings, a coupled node with a Dirichlet condition
        let mut m = sample_model();
        for name in ["HUB", "SECOND"] {
            m.couplings.push(RigidCoupling::rotation_about(
                name,
                [0.0; 3],
                2,
                vec![20, 21],
                1.0,
            ));
        }
        assert!(
            matches!(format_deck(&m), Err(FlankError::Model(e)) if e.contains("two rigid couplings"))
        );
        let mut m = sample_model();
        m.couplings.push(RigidCoupling::rotation_about(
            "HUB",
            [0.0; 3],
            2,
            vec![0, 1],
            1.0,
        ));
        assert!(matches!(format_deck(&m), Err(FlankError::Model(e)) if e.contains("Dirichlet")));
        let mut m = sample_model();
        m.forces[0].node = 999;
        assert!(matches!(format_deck(&m), Err(FlankError::Model(_))));
        let mut m = sample_model();
        m.pressures[1].face = 6; // wedge has 5 faces
        assert!(matches!(format_deck(&m), Err(FlankError::Model(_))));
        let mut m = sample_model();
        m.mesh.coords[0][1] = f64::NAN;
        assert!(matches!(format_deck(&m), Err(FlankError::Model(_))));
        let mut m = sample_model();
        m.mesh.extend_node_set("NALL", [0]);
        assert!(matches!(format_deck(&m), Err(FlankError::Model(_))));
    }

    #[test]
    fn reals_fit_twenty_characters() {
        // Exact whenever an exact form fits.
        for x in [
            0.0,
            -0.0,
            1.0,
            -1.0,
            0.1,
            0.30000000000000004,
            1.0 / 3.0,
            -12.345678901234567,
            210000.0,
            1e300,
            -5e-324,
            6.123233995736766e-17,
            123456789012345680.0,
        ] {
            let s = fmt_real(x);
            assert!(s.len() <= CCX_REAL_WIDTH, "{s}");
            assert_eq!(s.parse::<f64>().unwrap().to_bits(), x.to_bits(), "{s}");
        }
        assert_eq!(fmt_real(1200.0), "1200");
        assert_eq!(fmt_real(-0.5), "-0.5");
        assert_eq!(fmt_real(2.5e-7), "0.00000025");
        assert_eq!(fmt_real(-2.5e-27), "-25e-28");
        // Needs 22 characters exactly; 15 significant digits fit.
        assert_eq!(fmt_real(-1.2345678901234567e-5), "-1.23456789012346e-5");
        // Random bit patterns: always short; exact or rounded to at least 15
        // significant digits in 1e-9..1e10, 13 anywhere.
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut inexact = 0;
        for _ in 0..200_000 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let x = f64::from_bits(state);
            if !x.is_finite() {
                continue;
            }
            let s = fmt_real(x);
            assert!(s.len() <= CCX_REAL_WIDTH, "{s}");
            let y: f64 = s.parse().unwrap();
            if y.to_bits() != x.to_bits() {
                inexact += 1;
                let tol = if (1e-9..1e10).contains(&x.abs()) {
                    5e-15
                } else {
                    5e-13
                };
                assert!(((y - x) / x).abs() <= tol, "{x:e} -> {s}");
            }
        }
        assert!(inexact > 0);
        // Everything with 0.01 <= |x| < 1e26 is exact.
        for i in 0..200_000u32 {
            let t = (f64::from(i) * 0.618_033_988_749_894_9).fract();
            for x in [
                t * 400.0 - 200.0,
                -0.01 - t * 0.09,
                10f64.powf(t * 28.0 - 2.0),
            ] {
                if x.abs() >= 0.01 && x.abs() < 1e26 {
                    let s = fmt_real(x);
                    assert_eq!(s.parse::<f64>().unwrap().to_bits(), x.to_bits(), "{s}");
                    let s = fmt_real(-x);
                    assert_eq!(s.parse::<f64>().unwrap().to_bits(), (-x).to_bits(), "{s}");
                }
            }
        }
    }

    // -- contact ------------------------------------------------------------

    /// Two unit C3D20 cubes stacked in z (touching at z = 1), a contact pair
    /// of the upper cube's bottom face (slave, element face) on the lower
    /// cube's top face (master), hard contact; the upper cube is pushed down.
    fn two_cubes(contact: &str) -> String {
        let mut s = String::from("*NODE, NSET=NALL\n");
        for b in 0..2u64 {
            for (i, p) in crate::fem::element::HEX20_NODES.iter().enumerate() {
                let x = [
                    0.5 * (p[0] + 1.0),
                    0.5 * (p[1] + 1.0),
                    0.5 * (p[2] + 1.0) + b as f64,
                ];
                s += &format!("{}, {}, {}, {}\n", 100 * b + i as u64 + 1, x[0], x[1], x[2]);
            }
        }
        s += "*ELEMENT, TYPE=C3D20, ELSET=EALL\n";
        for b in 0..2u64 {
            let n: Vec<String> = (1..=20).map(|i| (100 * b + i).to_string()).collect();
            s += &format!(
                "{}, {},\n{}\n",
                b + 1,
                n[..15].join(", "),
                n[15..].join(", ")
            );
        }
        s += "*ELSET, ELSET=UPPER\n2\n*NSET, NSET=UPPER_BOTTOM\n101, 102, 103, 104, 109, 110, 111, 112\n";
        s += "*NSET, NSET=BOT\n1, 2, 3, 4, 9, 10, 11, 12\n";
        s += "*NSET, NSET=TOP\n105, 106, 107, 108, 113, 114, 115, 116\n";
        s += "*MATERIAL, NAME=STEEL\n*ELASTIC\n210000., 0.3\n*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n";
        s += contact;
        s += "*BOUNDARY\nBOT, 1, 3\nTOP, 1, 2\n*STEP\n*STATIC\n*BOUNDARY\nTOP, 3, 3, -0.001\n*NODE PRINT, NSET=NALL\nU\n*CONTACT PRINT\nCSTR\n*END STEP\n";
        s
    }

    const CONTACT: &str = "\
*SURFACE, NAME=SLAVE, TYPE=ELEMENT
UPPER, S1
*SURFACE, NAME=MASTER
1, S2
*SURFACE, NAME=NODES, TYPE=NODE
UPPER_BOTTOM
*SURFACE INTERACTION, NAME=SI
*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR
1e7, 0.001
*FRICTION
0.0
*SURFACE INTERACTION, NAME=HARD
*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=HARD
*CONTACT PAIR, INTERACTION=SI, TYPE=NODE TO SURFACE, SMALL SLIDING
SLAVE, MASTER
";

    #[test]
    fn contact_keywords_are_read() {
        let deck = parse(&two_cubes(CONTACT)).unwrap();
        let c = &deck.model.contact;
        assert_eq!(c.surfaces.len(), 3);
        assert_eq!(c.surfaces[0].kind, SurfaceKind::Element(vec![(1, 1)]));
        assert_eq!(c.surfaces[1].kind, SurfaceKind::Element(vec![(0, 2)]));
        match &c.surfaces[2].kind {
            SurfaceKind::Node(n) => assert_eq!(n.len(), 8),
            other => panic!("{other:?}"),
        }
        assert_eq!(
            c.interactions[0].behavior,
            Some(PressureOverclosure::Linear {
                slope: Some(1e7),
                tension: Some(0.001),
                c0: None
            })
        );
        assert_eq!(c.interactions[0].friction.as_ref().unwrap().mu, 0.0);
        assert_eq!(c.interactions[1].behavior, Some(PressureOverclosure::Hard));
        assert_eq!(
            c.pairs,
            vec![ContactPair {
                interaction: "SI".into(),
                slave: "SLAVE".into(),
                master: "MASTER".into(),
                small_sliding: true
            }]
        );
        assert!(deck.warnings.is_empty(), "{:?}", deck.warnings);
    }

    #[test]
    fn contact_round_trip() {
        let m = parse(&two_cubes(CONTACT)).unwrap().model;
        let text = format_deck(&m).unwrap();
        assert!(text.contains(
            "*CONTACT PAIR, INTERACTION=SI, TYPE=NODE TO SURFACE, SMALL SLIDING\nSLAVE, MASTER\n"
        ));
        assert!(
            text.contains("*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR\n10000000, 0.001\n"),
            "{text}"
        );
        let p = parse(&text).unwrap().model;
        assert_eq!(p.contact, m.contact);
        // automatic slope (no data line) survives too
        let auto = CONTACT.replace("1e7, 0.001\n", "");
        let m = parse(&two_cubes(&auto)).unwrap().model;
        assert_eq!(
            m.contact.interactions[0].behavior,
            Some(PressureOverclosure::Linear {
                slope: None,
                tension: None,
                c0: None
            })
        );
        let p = parse(&format_deck(&m).unwrap()).unwrap().model;
        assert_eq!(p.contact, m.contact);
    }

    #[test]
    fn contact_errors_name_the_line() {
        let d = two_cubes(CONTACT);
        // a surface that names no face (empty element set)
        let e = with(
            &d,
            "*SURFACE, NAME=SLAVE, TYPE=ELEMENT\nUPPER, S1\n",
            "*ELSET, ELSET=NONE\n*SURFACE, NAME=SLAVE, TYPE=ELEMENT\nNONE, S1\n",
        );
        expect_err(&e, line_of(&e, "NAME=SLAVE"), "names no element face");
        let e = with(
            &d,
            "*SURFACE, NAME=SLAVE, TYPE=ELEMENT\nUPPER, S1\n",
            "*SURFACE, NAME=SLAVE, TYPE=ELEMENT\n",
        );
        expect_err(&e, line_of(&e, "NAME=SLAVE"), "names no element face");
        // unknown surface in a pair
        let e = with(&d, "SLAVE, MASTER", "SLAVE, MASTRE");
        expect_err(&e, line_of(&e, "SLAVE, MASTRE"), "MASTRE is not defined");
        // pair referencing a missing interaction
        let e = with(&d, "INTERACTION=SI,", "INTERACTION=STEEL,");
        expect_err(
            &e,
            line_of(&e, "SLAVE, MASTER"),
            "interaction STEEL is not defined",
        );
        // negative friction coefficient
        let e = with(&d, "*FRICTION\n0.0", "*FRICTION\n-0.1");
        expect_err(&e, line_of(&e, "-0.1"), "must not be negative");
        // node surface as master
        let e = with(&d, "SLAVE, MASTER", "SLAVE, NODES");
        expect_err(&e, line_of(&e, "SLAVE, NODES"), "element faces");
        // face out of range, malformed face
        let e = with(&d, "1, S2\n", "1, S7\n");
        expect_err(&e, line_of(&e, "1, S7"), "out of range");
        let e = with(&d, "1, S2\n", "1, SPOS\n");
        expect_err(&e, line_of(&e, "1, SPOS"), "SPOS");
        // unsupported laws and types
        let e = with(
            &d,
            "PRESSURE-OVERCLOSURE=LINEAR",
            "PRESSURE-OVERCLOSURE=EXPONENTIAL",
        );
        expect_err(&e, line_of(&e, "EXPONENTIAL"), "EXPONENTIAL");
        let e = with(&d, "TYPE=NODE TO SURFACE", "TYPE=SURFACE TO SURFACE");
        expect_err(
            &e,
            line_of(&e, "SURFACE TO SURFACE"),
            "only NODE TO SURFACE",
        );
        let e = with(&d, "SMALL SLIDING", "ADJUST=0.01");
        expect_err(&e, line_of(&e, "ADJUST"), "ADJUST");
        let e = with(&d, "1e7, 0.001", "-1e7");
        expect_err(&e, line_of(&e, "-1e7"), "positive");
        // behaviour outside an interaction; interaction without behaviour
        let e = with(
            &d,
            "*SURFACE, NAME=SLAVE",
            "*SURFACE BEHAVIOR\n*SURFACE, NAME=SLAVE",
        );
        expect_err(&e, line_of(&e, "*SURFACE BEHAVIOR"), "outside");
        let e = with(&d, "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=HARD\n", "");
        expect_err(&e, line_of(&e, "NAME=HARD"), "no *SURFACE BEHAVIOR");
        // duplicate surface
        let e = with(&d, "*SURFACE, NAME=MASTER", "*SURFACE, NAME=SLAVE");
        let second = e
            .lines()
            .enumerate()
            .filter(|(_, l)| l.contains("NAME=SLAVE"))
            .nth(1)
            .unwrap()
            .0
            + 1;
        expect_err(&e, second, "defined twice");
        // wedge faces stop at S5
        let e = with(&d, "1, S2\n", "1, S6\n");
        assert!(parse(&e).is_ok(), "S6 is a valid hexahedron face");
    }

    // -- rigid couplings ------------------------------------------------------

    /// The unit cube of HEX, base clamped, its top face held by a rigid body
    /// whose reference node 100 is fixed and whose rotation node 101 may
    /// turn about z only, loaded by a moment.
    const RIGID: &str = "\
*NODE, NSET=NALL
1, 0, 0, 0
2, 1, 0, 0
3, 1, 1, 0
4, 0, 1, 0
5, 0, 0, 1
6, 1, 0, 1
7, 1, 1, 1
8, 0, 1, 1
9, 0.5, 0, 0
10, 1, 0.5, 0
11, 0.5, 1, 0
12, 0, 0.5, 0
13, 0.5, 0, 1
14, 1, 0.5, 1
15, 0.5, 1, 1
16, 0, 0.5, 1
17, 0, 0, 0.5
18, 1, 0, 0.5
19, 1, 1, 0.5
20, 0, 1, 0.5
*NODE
100, 0.5, 0.5, 1.25
101, 0.5, 0.5, 1.25
*ELEMENT, TYPE=C3D20, ELSET=EALL
1, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15,
16, 17, 18, 19, 20
*NSET, NSET=BASE
1, 2, 3, 4, 9, 10, 11, 12
*NSET, NSET=TOP
5, 6, 7, 8, 13, 14, 15, 16
*NSET, NSET=REFS
100, 101
*MATERIAL, NAME=STEEL
*ELASTIC
210000., 0.3
*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL
*RIGID BODY, NSET=TOP, REF NODE=100, ROT NODE=101
*STEP
*STATIC
*BOUNDARY
BASE, 1, 3
100, 1, 3
101, 1, 2
*CLOAD
101, 3, 1000.
*NODE PRINT, NSET=NALL
U
*END STEP
";

    /// RIGID with the rigid body replaced by *COUPLING + *KINEMATIC on the
    /// top face; the rotations are DOFs 4-6 of the reference node.
    fn coupling_deck() -> String {
        let d = with(
            RIGID,
            "*RIGID BODY, NSET=TOP, REF NODE=100, ROT NODE=101\n",
            "*SURFACE, NAME=STOP, TYPE=ELEMENT\n1, S2\n*COUPLING, REF NODE=100, SURFACE=STOP, CONSTRAINT NAME=HUB\n*KINEMATIC\n1, 3\n",
        );
        let d = with(&d, "100, 1, 3\n101, 1, 2\n", "100, 1, 5\n");
        let d = with(&d, "101, 0.5, 0.5, 1.25\n", "");
        let d = with(&d, "100, 101\n", "100\n");
        with(&d, "101, 3, 1000.", "100, 6, 1000.")
    }

    #[test]
    fn rigid_body_is_read() {
        let deck = parse(RIGID).unwrap();
        assert!(deck.warnings.is_empty(), "{:?}", deck.warnings);
        let m = &deck.model;
        assert_eq!(
            m.mesh.node_count(),
            20,
            "reference nodes are not mesh nodes"
        );
        assert!(m.mesh.node(100).is_none() && m.mesh.node(101).is_none());
        assert_eq!(m.mesh.node_sets["NALL"].len(), 20);
        assert!(m.mesh.node_sets["REFS"].is_empty());
        assert_eq!(m.couplings.len(), 1);
        let cp = &m.couplings[0];
        assert_eq!(cp.name, "TOP");
        assert_eq!(cp.reference_point, [0.5, 0.5, 1.25]);
        assert_eq!(cp.nodes, idx(&m.mesh, &[5, 6, 7, 8, 13, 14, 15, 16]));
        assert_eq!(cp.free, [false, false, false, false, false, true]);
        assert_eq!(cp.load, [0.0, 0.0, 0.0, 0.0, 0.0, 1000.0]);
        // only the base is a Dirichlet condition, no force on a mesh node
        assert_eq!(m.dirichlet.len(), 24);
        assert!(m.forces.is_empty());
        // *COUPLING + *KINEMATIC: the same coupling under its constraint name
        let deck = parse(&coupling_deck()).unwrap();
        assert!(deck.warnings.is_empty(), "{:?}", deck.warnings);
        let c2 = &deck.model.couplings[0];
        assert_eq!(c2.name, "HUB");
        assert_eq!(
            (c2.reference_point, &c2.nodes, c2.free, c2.load),
            (cp.reference_point, &cp.nodes, cp.free, cp.load)
        );
        assert_eq!(deck.model.mesh.node_count(), 20);
    }

    #[test]
    fn rigid_body_variants() {
        // ELSET: all nodes of the elements; without ROT NODE the rotations
        // are free and unloaded (ccx creates an unreachable node)
        let d = with(
            RIGID,
            "*RIGID BODY, NSET=TOP, REF NODE=100, ROT NODE=101",
            "*RIGID BODY, ELSET=EALL, REFNODE=100",
        );
        let d = with(&d, "101, 1, 2\n", "");
        let d = with(&d, "BASE, 1, 3\n", "");
        let d = with(&d, "101, 3, 1000.", "100, 3, -50.");
        let m = parse(&d).unwrap().model;
        let cp = &m.couplings[0];
        assert_eq!(cp.nodes.len(), 20);
        assert_eq!(cp.free, [false, false, false, true, true, true]);
        assert_eq!(cp.load, [0.0; 6], "load on a fixed DOF is ignored");
        assert_eq!(m.mesh.node_count(), 21, "101 is now an ordinary node");
        let w = parse(&d).unwrap().warnings;
        assert!(
            w.iter()
                .any(|w| w.line == line_of(&d, "100, 3, -50.") && w.message.contains("ignored")),
            "{w:?}"
        );
        // a free reference translation takes the load; loads add up
        let e = with(&d, "100, 1, 3\n", "100, 1, 2\n");
        let e = with(&e, "100, 3, -50.", "100, 3, -50.\n100, 3, -25.");
        let cp = parse(&e).unwrap().model.couplings[0].clone();
        assert_eq!(cp.free, [false, false, true, true, true, true]);
        assert_eq!(cp.load, [0.0, 0.0, -75.0, 0.0, 0.0, 0.0]);
        // a set *BOUNDARY on the reference node set fixes it
        let e = with(RIGID, "100, 1, 3\n101, 1, 2\n", "REFS, 1, 3\n");
        let cp = parse(&e).unwrap().model.couplings[0].clone();
        assert_eq!(cp.free, [false; 6]);
    }

    #[test]
    fn rigid_coupling_errors_name_the_line() {
        let rb = "*RIGID BODY, NSET=TOP, REF NODE=100, ROT NODE=101";
        let d = with(
            RIGID,
            rb,
            "*RIGID BODY, NSET=TOP, REF NODE=999, ROT NODE=101",
        );
        expect_err(
            &d,
            line_of(&d, "*RIGID BODY"),
            "REF NODE 999 is not defined",
        );
        let d = with(RIGID, rb, "*RIGID BODY, NSET=TOP, REF NODE=7, ROT NODE=101");
        expect_err(&d, line_of(&d, "*RIGID BODY"), "belongs to an element");
        let d = with(
            RIGID,
            rb,
            "*RIGID BODY, NSET=TOP, REF NODE=100, ROT NODE=100",
        );
        expect_err(&d, line_of(&d, "*RIGID BODY"), "already the REF NODE");
        let d = with(RIGID, rb, "*RIGID BODY, NSET=TOP, ROT NODE=101");
        expect_err(&d, line_of(&d, "*RIGID BODY"), "REF NODE");
        let d = with(RIGID, rb, "*RIGID BODY, NSET=NOPE, REF NODE=100");
        expect_err(&d, line_of(&d, "*RIGID BODY"), "NOPE is not defined");
        let d = with(
            RIGID,
            rb,
            "*NSET, NSET=EMPTY\n*RIGID BODY, NSET=EMPTY, REF NODE=100",
        );
        expect_err(&d, line_of(&d, "*RIGID BODY"), "no node to couple");
        let d = with(
            RIGID,
            rb,
            "*RIGID BODY, NSET=REFS, REF NODE=100, ROT NODE=101",
        );
        expect_err(&d, line_of(&d, "*RIGID BODY"), "no node to couple");
        let d = with(RIGID, rb, "*RIGID BODY, NSET=REFS, REF NODE=100");
        expect_err(
            &d,
            line_of(&d, "*RIGID BODY"),
            "no node of node set REFS belongs to an element",
        );
        let d = with(
            RIGID,
            rb,
            "*RIGID BODY, NSET=TOP, REF NODE=100, PINNSET=TOP",
        );
        expect_err(&d, line_of(&d, "*RIGID BODY"), "PINNSET");
        // a node in two couplings: the second one is named
        let d = with(
            RIGID,
            "*STEP\n",
            "*NODE\n102, 0, 0, 2\n*NSET, NSET=CORNER\n5\n*RIGID BODY, NSET=CORNER, REF NODE=102\n*STEP\n",
        );
        expect_err(
            &d,
            line_of(&d, "NSET=CORNER, REF"),
            "already coupled by *RIGID BODY TOP",
        );
        // *BOUNDARY on a coupled node: at that line
        let d = with(RIGID, "BASE, 1, 3\n", "BASE, 1, 3\n7, 3, 3\n");
        expect_err(&d, line_of(&d, "7, 3, 3"), "constrain the reference node");
        let d = with(RIGID, "BASE, 1, 3\n", "BASE, 1, 3\nTOP, 1, 1\n");
        expect_err(&d, line_of(&d, "TOP, 1, 1"), "constrain the reference node");
        // prescribed reference motion, DOFs a rigid body's nodes do not have
        let d = with(RIGID, "101, 1, 2\n", "101, 1, 2, 0.001\n");
        expect_err(&d, line_of(&d, "101, 1, 2, 0.001"), "only zero");
        let d = with(RIGID, "101, 1, 2\n", "101, 1, 2\n100, 4, 6\n");
        expect_err(&d, line_of(&d, "100, 4, 6"), "ROT NODE");
        let d = with(RIGID, "101, 3, 1000.", "101, 6, 1000.");
        expect_err(&d, line_of(&d, "101, 6"), "DOFs 1-3 of its ROT NODE");
        let d = with(RIGID, "101, 3, 1000.", "7, 6, 1000.");
        expect_err(&d, line_of(&d, "7, 6"), "DOF 6 of node 7");
        // model data only
        let d = with(RIGID, &format!("{rb}\n"), "");
        let d = with(&d, "*STATIC\n", &format!("*STATIC\n{rb}\n"));
        expect_err(&d, line_of(&d, "*RIGID BODY"), "before *STEP");
        // a reference node used as a contact node surface
        let d = with(
            RIGID,
            "*STEP\n",
            "*SURFACE, NAME=S, TYPE=NODE\n100\n*STEP\n",
        );
        expect_err(&d, line_of(&d, "*SURFACE"), "reference node");
    }

    #[test]
    fn coupling_kinematic_errors() {
        let d = coupling_deck();
        let kin = "*KINEMATIC\n1, 3\n";
        let e = with(&d, kin, "");
        expect_err(&e, line_of(&e, "*COUPLING"), "followed by *KINEMATIC");
        let e = with(&d, kin, "*DISTRIBUTING\n1, 3\n");
        expect_err(&e, line_of(&e, "*DISTRIBUTING"), "distributing");
        let e = with(&d, kin, "*KINEMATIC\n1, 2\n");
        expect_err(&e, line_of(&e, "*KINEMATIC"), "partial");
        let e = with(&d, kin, "*KINEMATIC\n1\n2\n3\n");
        assert!(parse(&e).is_ok(), "DOF lines one by one");
        let e = with(&d, kin, "*KINEMATIC\n");
        expect_err(&e, line_of(&e, "*KINEMATIC"), "couples nothing");
        let e = with(&d, kin, "*KINEMATIC\n1, 4\n");
        expect_err(&e, line_of(&e, "1, 4"), "1-3");
        let e = with(&d, "*SOLID SECTION", "*KINEMATIC\n1, 3\n*SOLID SECTION");
        expect_err(
            &e,
            line_of(&e, "*KINEMATIC"),
            "without a preceding *COUPLING",
        );
        let e = with(&d, "SURFACE=STOP,", "SURFACE=STOP, ORIENTATION=OR1,");
        expect_err(&e, line_of(&e, "*COUPLING"), "ORIENTATION");
        let e = with(&d, ", CONSTRAINT NAME=HUB", "");
        expect_err(&e, line_of(&e, "*COUPLING"), "CONSTRAINT NAME");
        let e = with(&d, "SURFACE=STOP,", "SURFACE=OTHER,");
        expect_err(&e, line_of(&e, "*COUPLING"), "surface OTHER is not defined");
        // the reference node of a *COUPLING has rotations 4-6; a moment
        // on a free rotation is kept, a prescribed rotation is refused
        let e = with(&d, "100, 1, 5\n", "100, 1, 5\n100, 6, 6, 0.01\n");
        expect_err(&e, line_of(&e, "100, 6, 6, 0.01"), "only zero");
        let e = with(&d, "*STEP\n", "*DISTRIBUTING COUPLING\n*STEP\n");
        expect_err(&e, line_of(&e, "*DISTRIBUTING COUPLING"), "not held rigid");
    }

    #[test]
    fn coupling_round_trip() {
        let mut m = sample_model();
        m.couplings.push(RigidCoupling {
            name: "HUB".into(),
            reference_point: [0.125, -3.5, 1.0 / 3.0],
            nodes: vec![4, 5, 6, 7, 9],
            free: [true, false, true, false, false, true],
            load: [12.5, 0.0, -3.0, 0.0, 0.0, 1.0e5],
        });
        m.couplings.push(RigidCoupling::rotation_about(
            "second hub",
            [1.0, 2.0, 3.0],
            0,
            vec![31, 32, 34],
            -250.0,
        ));
        let text = format_deck(&m).unwrap();
        let max = *m.mesh.node_labels.iter().max().unwrap();
        assert!(text.contains(&format!(
            "*RIGID BODY, NSET=HUB, REF NODE={}, ROT NODE={}\n",
            max + 1,
            max + 2
        )));
        let deck = parse(&text).unwrap();
        assert!(deck.warnings.is_empty(), "{:?}", deck.warnings);
        let p = &deck.model;
        assert_eq!(p.mesh.node_labels, m.mesh.node_labels, "no extra mesh node");
        assert_eq!(p.couplings[0], m.couplings[0]);
        let mut second = m.couplings[1].clone();
        second.name = "SECOND_HUB".into();
        assert_eq!(p.couplings[1], second);
        assert_eq!(p.dirichlet, m.dirichlet);
        assert_eq!(p.forces, m.forces);
        // a fixed point: the parsed model writes the same deck again
        let again = format_deck(p).unwrap();
        let twice = format_deck(&parse(&again).unwrap().model).unwrap();
        assert_eq!(again, twice);
        assert_eq!(again.matches("*NSET, NSET=HUB\n").count(), 1);
    }
}
