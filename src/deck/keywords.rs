//! Keywords read by no keyword family: output requests (accepted, data
//! skipped), keywords without effect on a linear static answer (skipped
//! with a warning), keywords that would change the answer if ignored
//! (errors, with the reason), and unknown ones (skipped with a warning).
//! Also which keywords stay inside a `*MATERIAL` or a `*SURFACE
//! INTERACTION`.

use super::parser::Parser;
use super::records::{Block, Card};
use crate::error::Result;

/// Output requests: accepted, data lines skipped silently.
pub(super) const OUTPUT_KEYWORDS: &[&str] = &[
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
pub(super) const MATERIAL_KEYWORDS: &[&str] = &[
    "ELASTIC",
    "DENSITY",
    "EXPANSION",
    "CONDUCTIVITY",
    "SPECIFIC HEAT",
    "DAMPING",
];

/// Keywords that belong to the current `*SURFACE INTERACTION`.
pub(super) const INTERACTION_KEYWORDS: &[&str] = &["SURFACE BEHAVIOR", "FRICTION"];

impl Parser {
    /// A keyword no family reads: an error if ignoring it would change the
    /// answer, otherwise skipped with a warning.
    pub(super) fn kw_other(&mut self, card: &Card) -> Result<Block> {
        let loc = card.loc;
        let n = card.name.as_str();
        if let Some((_, why)) = FATAL_KEYWORDS.iter().find(|(k, _)| *k == n) {
            return Err(self.err(
                loc,
                format!("*{n} is not supported ({why}); ignoring it would change the answer"),
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
        Ok(Block::Ignore)
    }
}
