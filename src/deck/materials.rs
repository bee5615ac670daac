//! `*MATERIAL`, `*ELASTIC`, `*DENSITY`, `*EXPANSION` and `*SOLID SECTION`.
//!
//! `*MATERIAL, NAME=name` followed by `*ELASTIC[, TYPE=ISO]` with one data
//! line `E, ν[, temperature]` (further temperature lines: only the first is
//! used, with a warning); `*DENSITY` with one data line `ρ[, temperature]`
//! (same rule), used by the body loads `*DLOAD` GRAV and CENTRIF (with a
//! thermal load, several temperature lines are an error: ccx would take the
//! constants at each point's temperature); `*EXPANSION[, TYPE=ISO][,
//! ZERO=T]` with one data line `α[, temperature]`, the isotropic expansion
//! coefficient of the thermal strain α (T − T0) (a constant α makes ZERO
//! irrelevant; several temperature lines, other TYPEs and USER are errors);
//! `*CONDUCTIVITY`, ... stay inside the material and are ignored with a
//! warning (see [`super::keywords`]).
//! `*SOLID SECTION, ELSET=set, MATERIAL=name` gives the elements of the set
//! their material (replayed in file order; a later section reassigns, with
//! a warning). At the end every element needs a material; materials without
//! `*ELASTIC` that no section uses are dropped with a warning.

use super::lexer::norm_name;
use super::parser::Parser;
use super::records::{Block, Card, Cmd, Loc, RawMaterial};
use crate::error::Result;
use crate::fem::material::Material;

impl Parser {
    pub(super) fn kw_material(&mut self, card: &Card) -> Result<Block> {
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
            density: None,
            expansion: None,
            temperature_table: None,
            loc: card.loc,
        });
        Ok(Block::NoData(card.name.clone()))
    }

    pub(super) fn kw_elastic(&mut self, card: &Card) -> Result<Block> {
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
        let material = self.material_card(card, "ELASTIC", |m| m.elastic.is_some())?;
        Ok(Block::Elastic {
            material,
            lines: 0,
            loc: card.loc,
        })
    }

    /// The material a material card (`*ELASTIC`, `*DENSITY`, `*EXPANSION`)
    /// belongs to: the current `*MATERIAL`, refused outside one or when the
    /// material has that data already (`given`).
    fn material_card(
        &self,
        card: &Card,
        keyword: &str,
        given: impl Fn(&RawMaterial) -> bool,
    ) -> Result<usize> {
        let Some(material) = self.current_material else {
            return Err(self.err(card.loc, format!("*{keyword} outside of a *MATERIAL")));
        };
        if given(&self.materials[material]) {
            return Err(self.err(
                card.loc,
                format!(
                    "second *{keyword} for material {}",
                    self.materials[material].name
                ),
            ));
        }
        Ok(material)
    }

    /// `*DENSITY`: ρ of the current material (CalculiX manual, *DENSITY).
    pub(super) fn kw_density(&mut self, card: &Card) -> Result<Block> {
        self.check_params(card, &[])?;
        let material = self.material_card(card, "DENSITY", |m| m.density.is_some())?;
        Ok(Block::Density {
            material,
            lines: 0,
            loc: card.loc,
        })
    }

    /// A temperature table's lines after the first are skipped (flank
    /// reads temperature-independent data), with one warning at the second.
    fn beyond_first_line(
        &mut self,
        material: usize,
        keyword: &str,
        line_no: usize,
        loc: Loc,
    ) -> bool {
        if line_no == 2 {
            let m = &mut self.materials[material];
            m.temperature_table.get_or_insert(loc);
            self.warn(
                loc,
                format!("{keyword} with several (temperature) lines: only the first is used"),
            );
        }
        line_no > 1
    }

    pub(super) fn density_line(
        &mut self,
        material: usize,
        line_no: usize,
        f: &[&str],
        loc: Loc,
    ) -> Result<()> {
        if self.beyond_first_line(material, "*DENSITY", line_no, loc) {
            return Ok(());
        }
        if f.is_empty() || f.len() > 2 {
            return Err(self.err(loc, "*DENSITY data must be: rho[, temperature]"));
        }
        let rho = self.parse_real(f[0], loc)?;
        if let Some(t) = f.get(1) {
            self.parse_real(t, loc)?;
        }
        if !(rho.is_finite() && rho > 0.0) {
            return Err(self.err(
                loc,
                format!(
                    "*DENSITY of material {}: the density must be positive, got {rho}",
                    self.materials[material].name
                ),
            ));
        }
        self.materials[material].density = Some((rho, loc));
        Ok(())
    }

    /// `*EXPANSION[, TYPE=ISO][, ZERO=T]`: α of the current material
    /// (CalculiX manual, *EXPANSION). ccx's thermal strain is
    /// α(T)(T − Z) − α(T0)(T0 − Z) with Z the ZERO temperature: for the one
    /// constant α read here that is α (T − T0) whatever Z, so ZERO is read
    /// and has no effect.
    pub(super) fn kw_expansion(&mut self, card: &Card) -> Result<Block> {
        self.check_params(card, &["TYPE", "ZERO"])?;
        if let Some(t) = self.value(card, "TYPE")? {
            let t = norm_name(&t);
            if t != "ISO" && t != "ISOTROPIC" {
                return Err(self.err(
                    card.loc,
                    format!("*EXPANSION, TYPE={t} is not supported (only isotropic); ignoring it would change the answer"),
                ));
            }
        }
        if let Some(z) = self.value(card, "ZERO")? {
            self.parse_real(&z, card.loc)?;
        }
        let material = self.material_card(card, "EXPANSION", |m| m.expansion.is_some())?;
        Ok(Block::Expansion {
            material,
            lines: 0,
            loc: card.loc,
        })
    }

    pub(super) fn expansion_line(
        &mut self,
        material: usize,
        line_no: usize,
        f: &[&str],
        loc: Loc,
    ) -> Result<()> {
        if line_no > 1 {
            return Err(self.err(
                loc,
                format!(
                    "*EXPANSION of material {} with several (temperature) lines: a temperature-dependent expansion coefficient is not supported (give one line alpha[, temperature])",
                    self.materials[material].name
                ),
            ));
        }
        if f.is_empty() || f.len() > 2 {
            return Err(self.err(
                loc,
                "*EXPANSION data must be: alpha[, temperature] (isotropic)",
            ));
        }
        let alpha = self.parse_real(f[0], loc)?;
        if let Some(t) = f.get(1) {
            self.parse_real(t, loc)?;
        }
        self.materials[material].expansion = Some((alpha, loc));
        Ok(())
    }

    pub(super) fn kw_section(&mut self, card: &Card) -> Result<Block> {
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
        // A data line (plane-element thickness) is meaningless for solids;
        // more than one is a keyword that lost its '*'.
        Ok(Block::OneNumericLine {
            keyword: card.name.clone(),
            seen: false,
        })
    }

    pub(super) fn elastic_line(
        &mut self,
        material: usize,
        line_no: usize,
        f: &[&str],
        loc: Loc,
    ) -> Result<()> {
        if self.beyond_first_line(material, "*ELASTIC", line_no, loc) {
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
            density: None,
            expansion: None,
        };
        m.validate().map_err(|e| self.err(loc, e.to_string()))?;
        self.materials[material].elastic = Some((young, poisson));
        Ok(())
    }

    /// The materials with an `*ELASTIC` (unused ones without it are dropped
    /// with a warning) and each element's index among them; an element
    /// without a section is an error at its line.
    pub(super) fn element_materials(
        &mut self,
        elem_mat: &[Option<usize>],
        elem_loc: &[Loc],
    ) -> Result<(Vec<Material>, Vec<usize>)> {
        let ne = elem_mat.len();
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
                        density: m.density.map(|d| d.0),
                        expansion: m.expansion.map(|a| a.0),
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
        Ok((materials, element_material))
    }
}

#[cfg(test)]
mod tests {
    use crate::deck::test_decks::*;

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
}
