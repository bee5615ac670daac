//! Hub couplings: `*RIGID BODY`, and `*COUPLING` + `*KINEMATIC` (read into
//! [`Model::couplings`] as [`RigidCoupling`]s).
//!
//! `*RIGID BODY, NSET=|ELSET=, REF NODE=r[, ROT NODE=m]` (the set's nodes,
//! or all nodes of the element set, follow the rigid motion of r; r's DOFs
//! 1-3 are the reference translations, m's DOFs 1-3 its rotations; without
//! ROT NODE the rotations are free and unloaded, as in ccx, which then
//! creates a node no card can reach; without REF NODE it is an error), and
//! `*COUPLING, REF NODE=r, SURFACE=s, CONSTRAINT NAME=c` followed by
//! `*KINEMATIC` with DOF lines `first[, last]` that must cover 1-3 (ccx
//! couples translations only, DOFs ≤ 3; a partial coupling is refused); the
//! rotations are then DOFs 4-6 of r. Both are model data (before *STEP).
//! `REFNODE`/`ROTNODE`/`CONSTRAINTNAME` without blanks are accepted too.
//!
//! At the end of the deck ([`Parser::reference_roles`],
//! [`Parser::build_couplings`]): a `*BOUNDARY` on a reference DOF fixes it
//! (zero only), a `*CLOAD` on it is the reference force or moment; the
//! reference nodes leave the mesh. Errors, with file and line: undefined or
//! element-attached reference nodes, an empty set or surface, a node in two
//! couplings, a `*BOUNDARY` on a coupled node, DOFs a rigid body's
//! reference nodes do not have, `*DISTRIBUTING`, `ORIENTATION`, `PINNSET`.
//!
//! [`Model::couplings`]: crate::fem::model::Model::couplings

use std::collections::HashMap;

use super::lexer::norm_name;
use super::parser::Parser;
use super::records::{Block, Card, Cmd, CouplingMembers, Loc, RawCoupling, RefRole, StepState};
use crate::error::Result;
use crate::fem::model::{Dirichlet, RigidCoupling};

impl Parser {
    /// Hub couplings are model data: ccx refuses them inside a step.
    pub(super) fn coupling_before_step(&self, card: &Card) -> Result<()> {
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
    pub(super) fn kw_rigid_body(&mut self, card: &Card) -> Result<Block> {
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
    pub(super) fn kw_coupling(&mut self, card: &Card) -> Result<Block> {
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
    pub(super) fn kw_kinematic(&mut self, card: &Card, pending: Option<usize>) -> Result<Block> {
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
    pub(super) fn kinematic_line(&mut self, coupling: usize, f: &[&str], loc: Loc) -> Result<()> {
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

    /// Closes a `*KINEMATIC` block: its DOF lines must cover 1-3.
    pub(super) fn check_kinematic(&self, coupling: usize, loc: Loc) -> Result<()> {
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
        Ok(())
    }

    /// The nodes of each `*COUPLING`'s surface (its nodes, or the corner
    /// and midside nodes of its faces) into `cp_nodes`.
    pub(super) fn coupling_surface_nodes(
        &self,
        cp_nodes: &mut [Vec<usize>],
        surface_faces: &[Vec<(usize, usize)>],
        surface_nodes: &[Vec<usize>],
    ) -> Result<()> {
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
        Ok(())
    }

    /// "*RIGID BODY HUB (line 12)" / "*COUPLING C1 (line 20)".
    pub(super) fn coupling_title(&self, c: usize) -> String {
        let raw = &self.couplings[c];
        format!("*{} {} (line {})", raw.keyword, raw.name, raw.loc.line)
    }

    /// Node index → role of every REF NODE and ROT NODE, checked: defined,
    /// in no element, not shared between couplings.
    pub(super) fn reference_roles(&self) -> Result<HashMap<usize, RefRole>> {
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
    pub(super) fn reference_dof(
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
    pub(super) fn build_couplings(
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
}

#[cfg(test)]
mod tests {
    use crate::deck::test_decks::*;

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
}
