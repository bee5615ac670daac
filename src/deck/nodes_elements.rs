//! `*NODE` and `*ELEMENT`.
//!
//! `*NODE[, NSET=set][, SYSTEM=R]` with data lines `label, x[, y[, z]]`
//! (missing coordinates are 0; further fields are ignored with a warning);
//! nodes are stored in the mesh at once. `*ELEMENT, TYPE=C3D20|C3D20R|C3D15[,
//! ELSET=set]` with data lines `label, n1, n2, ...`; an element's node
//! labels may continue over several lines. Elements are kept as labels and
//! resolved at the end of the deck ([`Parser::resolve_elements`]), so
//! `*NODE` may follow `*ELEMENT`; an `NSET=`/`ELSET=` on the keyword records
//! the range of nodes/elements of its block.

use super::lexer::norm_name;
use super::parser::Parser;
use super::records::{Block, Card, Cmd, Loc, RawElement};
use crate::error::Result;
use crate::fem::mesh::ElementKind;

impl Parser {
    pub(super) fn kw_node(&mut self, card: &Card) -> Result<Block> {
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

    pub(super) fn kw_element(&mut self, card: &Card) -> Result<Block> {
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

    /// A `*NODE` data line: `label, x[, y[, z]]`.
    pub(super) fn node_line(
        &mut self,
        extra_warned: &mut bool,
        f: &[&str],
        loc: Loc,
    ) -> Result<()> {
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
        Ok(())
    }

    pub(super) fn element_line(
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

    /// Closes an `*ELEMENT` block: its last element must be complete; an
    /// `ELSET=` records the block's range of elements.
    pub(super) fn close_elements(
        &mut self,
        kind: ElementKind,
        set: Option<u32>,
        start: usize,
        open: bool,
    ) -> Result<()> {
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
        Ok(())
    }

    /// Adds the elements to the mesh in file order, their node labels
    /// resolved; returns the source line of each element.
    pub(super) fn resolve_elements(&mut self) -> Result<Vec<Loc>> {
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
        Ok(elem_loc)
    }
}

#[cfg(test)]
mod tests {
    use crate::deck::test_decks::*;
    use crate::fem::mesh::ElementKind;
    use crate::fem::model::Pressure;

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
}
