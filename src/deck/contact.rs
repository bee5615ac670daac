//! Contact: `*SURFACE`, `*SURFACE INTERACTION`, `*SURFACE BEHAVIOR`,
//! `*FRICTION` and `*CONTACT PAIR` (read into [`Model::contact`]).
//!
//! * `*SURFACE, NAME=s[, TYPE=ELEMENT]` with lines `element or element set,
//!   Sn` (face n), or `TYPE=NODE` with lines `node or node set`;
//! * `*SURFACE INTERACTION, NAME=i` followed by `*SURFACE BEHAVIOR,
//!   PRESSURE-OVERCLOSURE=HARD` (data ignored: flank's hard contact is
//!   exact) or `=LINEAR` with `slope[, σ∞[, c₀]]` (all optional), and
//!   optionally `*FRICTION` with `μ[, stick slope]`;
//! * `*CONTACT PAIR, INTERACTION=i[, TYPE=NODE TO SURFACE][, SMALL
//!   SLIDING]` with lines `slave, master` (the master made of element
//!   faces).
//!
//! Other contact types and laws, `ADJUST` and self contact are errors.
//! Cross references are checked at the end ([`Parser::contact_definition`]),
//! with the line that names what is wrong.
//!
//! [`Model::contact`]: crate::fem::model::Model::contact

use super::lexer::{norm_keyword, norm_name};
use super::parser::Parser;
use super::records::{Block, Card, Cmd, Loc, RawInteraction, RawPair, RawSurface};
use crate::error::Result;
use crate::fem::contact_definition::{
    ContactDefinition, ContactPair, Friction, PressureOverclosure, Surface, SurfaceInteraction,
    SurfaceKind,
};

impl Parser {
    pub(super) fn kw_surface(&mut self, card: &Card) -> Result<Block> {
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

    pub(super) fn kw_interaction(&mut self, card: &Card) -> Result<Block> {
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

    pub(super) fn kw_behavior(&mut self, card: &Card) -> Result<Block> {
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

    pub(super) fn kw_friction(&mut self, card: &Card) -> Result<Block> {
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

    pub(super) fn kw_contact_pair(&mut self, card: &Card) -> Result<Block> {
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

    pub(super) fn surface_line(
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

    pub(super) fn behavior_line(
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

    pub(super) fn friction_line(
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

    /// A `*CONTACT PAIR` data line: `slave surface, master surface`.
    pub(super) fn contact_pair_line(
        &mut self,
        interaction: &str,
        small_sliding: bool,
        f: &[&str],
        loc: Loc,
    ) -> Result<()> {
        if f.len() != 2 || f.iter().any(|t| t.is_empty()) {
            return Err(self.err(
                loc,
                "*CONTACT PAIR data must be: slave surface, master surface",
            ));
        }
        self.pairs.push(RawPair {
            interaction: interaction.to_string(),
            slave: norm_name(f[0]),
            master: norm_name(f[1]),
            small_sliding,
            loc,
        });
        Ok(())
    }

    /// The contact definition from the recorded surfaces, interactions and
    /// pairs, with its cross references checked (errors at the lines that
    /// name what is wrong).
    pub(super) fn contact_definition(
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
}

#[cfg(test)]
mod tests {
    use crate::deck::test_decks::*;
    use crate::fem::contact_definition::{ContactPair, PressureOverclosure, SurfaceKind};

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
}
