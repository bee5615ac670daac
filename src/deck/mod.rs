//! CalculiX/Abaqus deck (`.inp`) reader and writer.
//!
//! The reader accepts the subset of the CalculiX (ccx 2.20) deck language that
//! describes one *linear static* analysis of C3D20/C3D20R/C3D15 solids and
//! turns it into a [`Model`]. Anything that would change the answer if it were
//! silently ignored (distributing couplings, plasticity, temperatures, other
//! procedures, ...) is a [`FlankError::Parse`] with file and line; harmless
//! or unknown keywords become [`DeckWarning`]s. No input panics.
//!
//! Where what is read (each file's docs say what it accepts):
//!
//! | file | reads |
//! | --- | --- |
//! | `records.rs` | what the reader keeps: positions, cards, records as read, the commands replayed at the end, the current block |
//! | `parser.rs` | the reader's state (`Parser`), whose methods live in the files below |
//! | `lexer.rs` | lines, comments, keyword lines and their continuation, parameters, `*INCLUDE`, labels, DOFs, reals; file:line of errors |
//! | `nodes_elements.rs` | `*NODE`, `*ELEMENT` |
//! | `sets.rs` | `*NSET`, `*ELSET` (`GENERATE`), `NALL`/`EALL` |
//! | `materials.rs` | `*MATERIAL`, `*ELASTIC`, `*DENSITY`, `*EXPANSION`, `*SOLID SECTION` |
//! | `temperature.rs` | `*INITIAL CONDITIONS, TYPE=TEMPERATURE`, `*TEMPERATURE` |
//! | `step.rs` | `*STEP`, `*STATIC`, `*END STEP`, `*BOUNDARY`, `*CLOAD`, `*DLOAD` (Pn, GRAV, CENTRIF) |
//! | `contact.rs` | `*SURFACE`, `*SURFACE INTERACTION`, `*SURFACE BEHAVIOR`, `*FRICTION`, `*CONTACT PAIR` |
//! | `coupling.rs` | `*RIGID BODY`, `*COUPLING`, `*KINEMATIC` |
//! | `equations.rs` | `*EQUATION` |
//! | `keywords.rs` | output requests (`*NODE PRINT`, ...), ignored and refused keywords |
//! | `resolve.rs` | the end of the deck: connectivity, sets, sections, conditions, loads, couplings, equations, contact |
//! | `mod.rs` (this file) | the driver: which keyword starts which block, what its data lines mean |
//!
//! The writer (`writer.rs`, reals in `real.rs`) produces a deck that ccx runs
//! and [`parse_deck`] reads back to the same model (rigid couplings as `*RIGID
//! BODY` with two fresh reference nodes each, see [`format_deck`]).
//!
//! Parsing is two-phase and linear in the deck size:
//! 1. lines are read once (following `*INCLUDE`); nodes are stored at once,
//!    everything that refers to nodes, elements or sets is recorded together
//!    with its source line;
//! 2. at the end, element connectivity is resolved (so `*NODE` may follow
//!    `*ELEMENT`) and the recorded set, section, boundary and load commands
//!    are replayed in file order.

mod contact;
mod coupling;
mod equations;
mod keywords;
mod lexer;
mod materials;
mod nodes_elements;
mod parser;
mod real;
mod records;
mod resolve;
mod sets;
mod step;
mod temperature;
mod writer;

#[cfg(test)]
mod test_decks;
#[cfg(test)]
mod tests;

use std::collections::HashMap;
use std::path::Path;

use crate::error::{FlankError, Result};
use crate::fem::model::Model;

use keywords::{INTERACTION_KEYWORDS, MATERIAL_KEYWORDS, OUTPUT_KEYWORDS};
use lexer::{read_text, split_fields};
use parser::Parser;
pub use records::DeckWarning;
use records::{Block, Card, Cmd, Loc, StepState};

pub use writer::{format_deck, write_deck};

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

// ---------------------------------------------------------------------------
// Reader state
// ---------------------------------------------------------------------------

impl Parser {
    fn new(file: &Path) -> Self {
        Parser {
            files: vec![file.to_path_buf()],
            warnings: Vec::new(),
            mesh: crate::fem::mesh::Mesh::new(),
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
            equations: Vec::new(),
            names: Vec::new(),
            name_ids: HashMap::new(),
            cmds: Vec::new(),
            block: Block::Start,
            step: StepState::Before,
            boundary_seen: false,
            cload_seen: false,
            dload_seen: false,
            initial_temperature: None,
        }
    }

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
            } => self.close_elements(kind, set, start, open)?,
            Block::Elastic { lines: 0, loc, .. } => {
                return Err(self.err(loc, "*ELASTIC without data line (E, nu)"))
            }
            Block::Density { lines: 0, loc, .. } => {
                return Err(self.err(loc, "*DENSITY without data line (rho)"))
            }
            Block::Expansion { lines: 0, loc, .. } => {
                return Err(self.err(loc, "*EXPANSION without data line (alpha)"))
            }
            Block::Friction { lines: 0, loc, .. } => {
                return Err(self.err(loc, "*FRICTION without data line (mu[, stick slope])"))
            }
            Block::Kinematic { coupling, loc } => self.check_kinematic(coupling, loc)?,
            Block::Equation { open, seen, loc } => self.close_equations(open, seen, loc)?,
            _ => {}
        }
        Ok(())
    }

    // -- keywords -----------------------------------------------------------

    /// A keyword line: closes the current block and opens the one of `card`
    /// (the `kw_*` functions live in the files of their keyword families).
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
            "DENSITY" => self.kw_density(&card)?,
            "EXPANSION" => self.kw_expansion(&card)?,
            "INITIAL CONDITIONS" => self.kw_initial_conditions(&card)?,
            "TEMPERATURE" => self.kw_temperature(&card)?,
            "SOLID SECTION" => self.kw_section(&card)?,
            "SURFACE" => self.kw_surface(&card)?,
            "SURFACE INTERACTION" => self.kw_interaction(&card)?,
            "SURFACE BEHAVIOR" => self.kw_behavior(&card)?,
            "FRICTION" => self.kw_friction(&card)?,
            "CONTACT PAIR" => self.kw_contact_pair(&card)?,
            "RIGID BODY" => self.kw_rigid_body(&card)?,
            "COUPLING" => self.kw_coupling(&card)?,
            "KINEMATIC" => self.kw_kinematic(&card, pending)?,
            "EQUATION" => self.kw_equation(&card)?,
            "STEP" => self.kw_step(&card)?,
            "STATIC" => self.kw_static(&card)?,
            "END STEP" => self.kw_end_step(&card)?,
            "BOUNDARY" => self.kw_boundary(&card)?,
            "CLOAD" | "DLOAD" => self.kw_load(&card)?,
            n if OUTPUT_KEYWORDS.contains(&n) => Block::Ignore,
            _ => self.kw_other(&card)?,
        };
        Ok(())
    }

    // -- data lines ---------------------------------------------------------

    fn data(&mut self, text: &str, loc: Loc) -> Result<()> {
        let mut block = std::mem::replace(&mut self.block, Block::Ignore);
        let r = self.data_in(&mut block, text, loc);
        self.block = block;
        r
    }

    /// A data line of `block` (the `*_line` functions live in the files of
    /// their keyword families).
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
            Block::OneNumericLine { keyword, seen } => {
                if *seen {
                    return Err(self.err(
                        loc,
                        format!("unexpected second data line '{text}' after *{keyword} (it takes at most one line of numbers); is a keyword's '*' missing?"),
                    ));
                }
                if let Some(bad) = split_fields(text)
                    .into_iter()
                    .find(|f| !f.is_empty() && f.parse::<f64>().is_err())
                {
                    return Err(self.err(
                        loc,
                        format!("malformed number '{bad}' in the data line of *{keyword}; is a keyword's '*' missing?"),
                    ));
                }
                *seen = true;
                return Ok(());
            }
            _ => {}
        }
        let f = split_fields(text);
        if f.is_empty() {
            return Ok(());
        }
        match block {
            Block::Node { extra_warned, .. } => self.node_line(extra_warned, &f, loc)?,
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
            Block::Density {
                material, lines, ..
            } => {
                *lines += 1;
                self.density_line(*material, *lines, &f, loc)?;
            }
            Block::Expansion {
                material, lines, ..
            } => {
                *lines += 1;
                self.expansion_line(*material, *lines, &f, loc)?;
            }
            Block::Temperature { initial } => self.temperature_line(*initial, &f, loc)?,
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
            Block::Equation { open, seen, .. } => self.equation_line(open, seen, &f, loc)?,
            Block::ContactPair {
                interaction,
                small_sliding,
            } => self.contact_pair_line(interaction, *small_sliding, &f, loc)?,
            _ => {}
        }
        Ok(())
    }
}
