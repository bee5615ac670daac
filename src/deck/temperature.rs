//! `*INITIAL CONDITIONS, TYPE=TEMPERATURE` and `*TEMPERATURE`: the nodal
//! temperatures of a thermal load (ccx 2.20 semantics).
//!
//! `*INITIAL CONDITIONS, TYPE=TEMPERATURE` (model data, before the step):
//! `node or set, T0` sets the initial temperature T0 and the temperature T
//! of the nodes (ccx rounds T0 to 1e-6, and so does flank); a later line on
//! the same node wins. Other TYPEs (STRESS, PLASTIC STRAIN, DISPLACEMENT,
//! ...) are errors. `*TEMPERATURE` (step data, `OP=MOD` or `OP=NEW`, both a
//! no-op in the one step: T starts at T0): `node or set, T` sets T; it needs
//! thermal initial conditions before it, as in ccx; AMPLITUDE, USER, FILE,
//! SUBMODEL and the other parameters are errors. Every node of an element
//! whose material has `*EXPANSION` needs an initial temperature: ccx would
//! take its placeholder 1.2357111319 as T0 there (and as T without a
//! `*TEMPERATURE`), measured in verification/thermal_strain; flank refuses
//! the deck at the `*INITIAL CONDITIONS` line instead. (Nodes of other
//! elements carry no thermal strain.)

use super::lexer::norm_name;
use super::parser::Parser;
use super::records::{Block, Card, Cmd, Loc, StepState};
use crate::error::Result;

impl Parser {
    /// `*INITIAL CONDITIONS, TYPE=TEMPERATURE`.
    pub(super) fn kw_initial_conditions(&mut self, card: &Card) -> Result<Block> {
        let ty = self.required(card, "TYPE").map(|t| norm_name(&t))?;
        if ty != "TEMPERATURE" {
            return Err(self.err(
                card.loc,
                format!("*INITIAL CONDITIONS, TYPE={ty} is not supported (only TYPE=TEMPERATURE); ignoring it would change the answer"),
            ));
        }
        self.check_params(card, &["TYPE"])?;
        if !matches!(self.step, StepState::Before) {
            return Err(self.err(
                card.loc,
                "*INITIAL CONDITIONS inside or after the *STEP: initial conditions are model data, before the step",
            ));
        }
        self.initial_temperature.get_or_insert(card.loc);
        Ok(Block::Temperature { initial: true })
    }

    /// `*TEMPERATURE[, OP=MOD|NEW]`: the step's nodal temperatures.
    pub(super) fn kw_temperature(&mut self, card: &Card) -> Result<Block> {
        if !matches!(self.step, StepState::Open { .. }) {
            return Err(self.err(
                card.loc,
                "*TEMPERATURE outside of a *STEP (temperatures are step data)",
            ));
        }
        for (k, v) in &card.params {
            let v = v.as_deref().map(norm_name).unwrap_or_default();
            match k.as_str() {
                // T starts at T0 in the one step: OP=NEW resets nothing
                "OP" if v == "MOD" || v == "NEW" => {}
                _ => {
                    return Err(self.err(
                        card.loc,
                        format!(
                            "parameter {k} on *TEMPERATURE is not supported (only OP=MOD or OP=NEW with the temperatures in the deck); ignoring it would change the answer"
                        ),
                    ))
                }
            }
        }
        if self.initial_temperature.is_none() {
            return Err(self.err(
                card.loc,
                "*TEMPERATURE without *INITIAL CONDITIONS, TYPE=TEMPERATURE before the step (ccx refuses it too: the thermal strain is α (T − T0))",
            ));
        }
        Ok(Block::Temperature { initial: false })
    }

    /// `node or set, temperature`.
    pub(super) fn temperature_line(&mut self, initial: bool, f: &[&str], loc: Loc) -> Result<()> {
        let kw = if initial {
            "*INITIAL CONDITIONS, TYPE=TEMPERATURE"
        } else {
            "*TEMPERATURE"
        };
        if f.len() != 2 {
            return Err(self.err(
                loc,
                format!("{kw} data must be: node or set, temperature (no gradients: solid elements only)"),
            ));
        }
        let target = self.parse_target(f[0], loc)?;
        let mut value = self.parse_real(f[1], loc)?;
        if initial {
            // ccx keeps T0 to 1e-6 (truncating 1e6 T0 + 1/2)
            value = 1e-6 * (1e6 * value + 0.5).trunc();
        }
        self.cmds.push(Cmd::Temperature {
            target,
            value,
            initial,
            loc,
        });
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use crate::deck::test_decks::*;

    const INITIAL: &str = "*INITIAL CONDITIONS, TYPE=TEMPERATURE\nNALL, 20.\n*STEP";

    /// A thermal deck: HEX with α, T0 = 20 on all nodes and T = 120 on the
    /// set TOP, 70 on node 1.
    fn thermal() -> String {
        let d = with(HEX, "*DENSITY", "*EXPANSION\n1.2e-5\n*DENSITY");
        let d = with(&d, "*STEP", INITIAL);
        with(
            &d,
            "*END STEP",
            "*TEMPERATURE\nTOP, 120.\n1, 70.\n*END STEP",
        )
    }

    #[test]
    fn temperatures_and_expansion_are_read() {
        let d = thermal();
        let deck = parse(&d).unwrap();
        let m = deck.model;
        assert_eq!(m.materials[0].expansion, Some(1.2e-5));
        let t = m.temperatures.expect("temperatures");
        assert!(t.initial.iter().all(|&v| v == 20.0));
        let top = &m.mesh.node_sets["TOP"];
        for (n, &v) in t.current.iter().enumerate() {
            let want = if m.mesh.node_labels[n] == 1 {
                70.0
            } else if top.contains(&n) {
                120.0
            } else {
                20.0
            };
            assert_eq!(v, want, "node {}", m.mesh.node_labels[n]);
        }
        assert!(deck.warnings.is_empty(), "{:?}", deck.warnings);
        // ccx's rounding of T0 to 1e-6
        let d = with(&d, "NALL, 20.", "NALL, 20.12345678");
        let t = parse(&d).unwrap().model.temperatures.unwrap();
        assert!((t.initial[0] - 20.123457).abs() < 1e-12, "{}", t.initial[0]);
    }

    #[test]
    fn nodes_without_initial_temperature_are_refused() {
        let d = with(&thermal(), "NALL, 20.", "TOP, 20.");
        expect_err(
            &d,
            line_of(&d, "*INITIAL CONDITIONS"),
            "has no initial temperature",
        );
        // without *EXPANSION the missing T0 carries no strain
        let d = with(&d, "*EXPANSION\n1.2e-5\n", "");
        assert!(parse(&d).is_ok());
    }

    #[test]
    fn thermal_refusals() {
        let d = thermal();
        // *TEMPERATURE without initial conditions
        let e = with(&d, INITIAL, "*STEP");
        expect_err(
            &e,
            line_of(&e, "*TEMPERATURE"),
            "without *INITIAL CONDITIONS",
        );
        // other types of initial conditions
        let e = with(&d, "TYPE=TEMPERATURE", "TYPE=STRESS");
        expect_err(
            &e,
            line_of(&e, "TYPE=STRESS"),
            "TYPE=STRESS is not supported",
        );
        // initial conditions in the step
        let e = with(
            &d,
            "*TEMPERATURE\n",
            "*INITIAL CONDITIONS, TYPE=TEMPERATURE\nNALL, 0.\n*TEMPERATURE\n",
        );
        expect_err(
            &e,
            line_of(&e, "NALL, 0.") - 1,
            "model data, before the step",
        );
        // *TEMPERATURE outside of the step
        let e = with(&d, INITIAL, &format!("*TEMPERATURE\nNALL, 5.\n{INITIAL}"));
        expect_err(&e, line_of(&e, "NALL, 5.") - 1, "outside of a *STEP");
        // parameters
        let e = with(&d, "*TEMPERATURE\n", "*TEMPERATURE, AMPLITUDE=A1\n");
        expect_err(&e, line_of(&e, "AMPLITUDE=A1"), "AMPLITUDE");
        let e = with(&d, "*TEMPERATURE\n", "*TEMPERATURE, USER\n");
        expect_err(&e, line_of(&e, "USER"), "USER");
        let e = with(&d, "*TEMPERATURE\n", "*TEMPERATURE, OP=NEW\n");
        assert!(parse(&e).is_ok());
        // data lines
        let e = with(&d, "TOP, 120.", "TOP, 120., 3.");
        expect_err(&e, line_of(&e, "TOP, 120., 3."), "no gradients");
        let e = with(&d, "TOP, 120.", "TOP, hot");
        expect_err(&e, line_of(&e, "TOP, hot"), "malformed number");
        let e = with(&d, "TOP, 120.", "NOSUCH, 120.");
        expect_err(&e, line_of(&e, "NOSUCH, 120."), "NOSUCH");
        // *EXPANSION
        let e = with(&d, "1.2e-5\n", "1.2e-5, 20.\n1.3e-5, 200.\n");
        expect_err(&e, line_of(&e, "1.3e-5, 200."), "temperature-dependent");
        let e = with(&d, "*EXPANSION\n", "*EXPANSION, TYPE=ORTHO\n");
        expect_err(&e, line_of(&e, "TYPE=ORTHO"), "only isotropic");
        let e = with(&d, "*EXPANSION\n", "*EXPANSION, USER\n");
        expect_err(&e, line_of(&e, "*EXPANSION, USER"), "USER");
        let e = with(&d, "*EXPANSION\n1.2e-5\n", "*EXPANSION\n");
        expect_err(&e, line_of(&e, "*EXPANSION"), "without data line");
        let e = with(&d, "1.2e-5\n", "1.2e-5, 1., 2.\n");
        expect_err(&e, line_of(&e, "1.2e-5, 1., 2."), "*EXPANSION data must be");
        let e = with(&d, "*EXPANSION\n", "*EXPANSION, ZERO=20.\n");
        assert!(parse(&e).is_ok());
        // a temperature table of *ELASTIC with a thermal load
        let e = with(&d, "210000., 0.3", "210000., 0.3, 20.\n200000., 0.3, 300.");
        expect_err(&e, line_of(&e, "200000., 0.3, 300."), "temperature");
    }
}
