//! `*NSET` and `*ELSET`, and the sets at the end of the deck.
//!
//! `*NSET, NSET=name` / `*ELSET, ELSET=name` (also `UNSORTED`) with data
//! lines of labels and set names, or with `GENERATE` lines `first, last[,
//! increment]` (labels in the range that do not exist are skipped with a
//! warning). Set names are upper-cased; node and element sets are separate
//! namespaces. Set contents are replayed in file order at the end of the
//! deck, so a set holds what was added to it *before* the line that uses it;
//! `NALL`/`EALL` mean all nodes/elements unless defined explicitly.

use super::lexer::looks_numeric;
use super::parser::Parser;
use super::records::{Block, Card, Cmd, Loc, SetItem, Target};
use crate::error::Result;

/// Unique members of a set in insertion order; a bitmap makes inserts O(1).
#[derive(Default)]
pub(super) struct IdxSet {
    pub(super) members: Vec<usize>,
    pub(super) bits: Vec<u64>,
}

impl IdxSet {
    pub(super) fn insert(&mut self, i: usize) {
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

impl Parser {
    pub(super) fn kw_set(&mut self, card: &Card, elem: bool) -> Result<Block> {
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

    pub(super) fn set_line(
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

    /// Members of node (`elem == false`) or element set `id` at this point of
    /// the deck; NALL/EALL mean all nodes/elements unless defined explicitly.
    pub(super) fn set_members(
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

    pub(super) fn target_nodes(
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

    pub(super) fn target_elements(
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

    /// `members` of a load's or boundary condition's `target`; an empty set
    /// is an error naming it (the load or condition would silently apply to
    /// nothing, e.g. when the set's data line was lost; found by
    /// tests/fuzz_parsers.rs).
    pub(super) fn nonempty(
        &self,
        members: Vec<usize>,
        target: Target,
        keyword: &str,
        loc: Loc,
    ) -> Result<Vec<usize>> {
        match target {
            Target::Set(id) if members.is_empty() => Err(self.err(
                loc,
                format!(
                    "{keyword} on set {}, which is empty: it would apply to nothing",
                    self.names[id as usize]
                ),
            )),
            _ => Ok(members),
        }
    }

    /// Indices of the existing labels in `first..=last` by `step`, and the
    /// number of labels in the range. Walks the range or all labels,
    /// whichever is shorter, so huge ranges cost no more than the mesh size.
    pub(super) fn generate(
        &self,
        elem: bool,
        first: u64,
        last: u64,
        step: u64,
    ) -> (Vec<usize>, u64) {
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

#[cfg(test)]
mod tests {
    use std::fmt::Write as _;

    use crate::deck::test_decks::*;

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
}
