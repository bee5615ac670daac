//! `*EQUATION`: linear multi-point constraints Σ cᵢ uᵢ = 0 (ccx 2.20
//! manual, *EQUATION; read into [`Model::equations`]).
//!
//! Model data (before `*STEP`; ccx refuses it inside a step too), no
//! parameter. Each equation is a set of lines: first the number of terms
//! n ≥ 1, then n terms `node, DOF, coefficient`, at most 4 terms (12
//! entries) per line, continued on the next lines until n terms are read.
//! The first term's DOF is the dependent one, eliminated from the system
//! ([`crate::fem::constraints::resolve_equations`]). Node numbers only, as
//! in ccx (a node set label is an error there too); DOFs 1-3 (ccx silently
//! drops an equation on DOF 4-6 of a solid node: refused here).
//!
//! At the end of the deck ([`Parser::build_equations`]): undefined nodes,
//! reference nodes of couplings and equations together with contact pairs
//! are errors at the term's or equation's line; the elimination's refusals
//! (a zero dependent coefficient, a dependent DOF under `*BOUNDARY` or in
//! two equations, cycles, nodes in no element or in a rigid coupling) at
//! the line of the equation's term count.
//!
//! [`Model::equations`]: crate::fem::model::Model::equations

use std::collections::HashMap;

use super::lexer::looks_numeric;
use super::parser::Parser;
use super::records::{Block, Card, Loc, RawEquation, RefRole, StepState};
use crate::error::Result;
use crate::fem::constraints::{resolve_equations, EquationFault};
use crate::fem::model::{Equation, EquationTerm, Model};

/// Entries per `*EQUATION` data line (ccx: at most 12, four terms).
const MAX_ENTRIES: usize = 12;

impl Parser {
    /// `*EQUATION` (no parameters, model data).
    pub(super) fn kw_equation(&mut self, card: &Card) -> Result<Block> {
        if !matches!(self.step, StepState::Before) {
            return Err(self.err(
                card.loc,
                "*EQUATION must come before *STEP (model data; ccx refuses it inside a step too)",
            ));
        }
        if let Some((k, _)) = card.params.first() {
            return Err(self.err(
                card.loc,
                format!("parameter {k} on *EQUATION is not supported (the equations follow as data lines)"),
            ));
        }
        Ok(Block::Equation {
            open: None,
            seen: false,
            loc: card.loc,
        })
    }

    /// A data line of `*EQUATION`: the number of terms of a new equation
    /// (`open` is None) or terms of the open one.
    pub(super) fn equation_line(
        &mut self,
        open: &mut Option<usize>,
        seen: &mut bool,
        f: &[&str],
        loc: Loc,
    ) -> Result<()> {
        let Some(e) = *open else {
            if f.len() != 1 {
                return Err(self.err(
                    loc,
                    "*EQUATION: expected the number of terms of the next equation (one integer) on this line",
                ));
            }
            let count = match f[0].parse::<usize>() {
                Ok(n) if n > 0 => n,
                _ => {
                    return Err(self.err(
                        loc,
                        format!(
                            "*EQUATION: the number of terms must be a positive integer, found '{}'",
                            f[0]
                        ),
                    ))
                }
            };
            *open = Some(self.equations.len());
            *seen = true;
            self.equations.push(RawEquation {
                count,
                terms: Vec::with_capacity(count),
                loc,
            });
            return Ok(());
        };
        if f.len() > MAX_ENTRIES || !f.len().is_multiple_of(3) {
            return Err(self.err(
                loc,
                format!(
                    "*EQUATION terms must be 'node, DOF, coefficient' triples, at most 4 per line (found {} entries)",
                    f.len()
                ),
            ));
        }
        let (count, start) = (self.equations[e].count, self.equations[e].loc.line);
        if self.equations[e].terms.len() + f.len() / 3 > count {
            return Err(self.err(
                loc,
                format!("*EQUATION: more terms than the {count} announced at line {start}"),
            ));
        }
        for t in f.chunks(3) {
            if !looks_numeric(t[0]) {
                return Err(self.err(
                    loc,
                    format!(
                        "*EQUATION: '{}' is not a node number; node set labels are not supported (ccx reads node numbers only)",
                        t[0]
                    ),
                ));
            }
            let label = self.parse_label(t[0], loc)?;
            let dof = self.parse_dof(t[1], loc)?;
            if dof > 3 {
                return Err(self.err(
                    loc,
                    format!(
                        "*EQUATION: DOF {dof} of node {label}: solid nodes have the translations 1-3 only (ccx would silently drop the equation)"
                    ),
                ));
            }
            let coefficient = self.parse_real(t[2], loc)?;
            self.equations[e]
                .terms
                .push((label, dof - 1, coefficient, loc));
        }
        if self.equations[e].terms.len() == count {
            *open = None;
        }
        Ok(())
    }

    /// Closes an `*EQUATION` block: the last equation must be complete.
    pub(super) fn close_equations(
        &mut self,
        open: Option<usize>,
        seen: bool,
        loc: Loc,
    ) -> Result<()> {
        if let Some(e) = open {
            let raw = &self.equations[e];
            return Err(self.err(
                raw.loc,
                format!(
                    "*EQUATION: this equation announces {} terms but has {} (ccx: 'mpc definition is not complete')",
                    raw.count,
                    raw.terms.len()
                ),
            ));
        }
        if !seen {
            self.warn(loc, "*EQUATION without an equation (no data lines)");
        }
        Ok(())
    }

    /// The equations with mesh node indices (before the reference nodes
    /// leave the mesh): undefined nodes and reference nodes are errors at
    /// the term's line; equations with contact pairs at the first one.
    pub(super) fn build_equations(
        &self,
        roles: &HashMap<usize, RefRole>,
        contact_pairs: usize,
    ) -> Result<Vec<Equation>> {
        if contact_pairs > 0 {
            if let Some(raw) = self.equations.first() {
                return Err(self.err(
                    raw.loc,
                    "*EQUATION together with *CONTACT PAIR is not supported (the contact solver is not verified with eliminated DOFs)",
                ));
            }
        }
        let mut out = Vec::with_capacity(self.equations.len());
        for raw in &self.equations {
            let mut terms = Vec::with_capacity(raw.terms.len());
            for &(label, component, coefficient, loc) in &raw.terms {
                let Some(node) = self.mesh.node(label) else {
                    return Err(self.err(loc, format!("*EQUATION: node {label} is not defined")));
                };
                if let Some(role) = roles.get(&node) {
                    return Err(self.err(
                        loc,
                        format!(
                            "*EQUATION: node {label} is a reference node of {} (not a mesh node): not supported in an equation",
                            self.coupling_title(role.coupling)
                        ),
                    ));
                }
                terms.push(EquationTerm {
                    node,
                    component,
                    coefficient,
                });
            }
            out.push(Equation { terms });
        }
        Ok(out)
    }

    /// Checks that the model's equations can be eliminated; a refusal names
    /// the equation's line (`dirichlet_loc`: the lines of the model's
    /// Dirichlet conditions).
    pub(super) fn check_equations(&self, model: &Model, dirichlet_loc: &[Loc]) -> Result<()> {
        let Err(e) = resolve_equations(model) else {
            return Ok(());
        };
        let line = |k: usize| self.equations[k].loc.line;
        let name = |k: usize| {
            if k == e.equation {
                "*EQUATION".to_string()
            } else {
                format!("the equation at line {}", line(k))
            }
        };
        let mut message = e.describe(model, &name);
        if let EquationFault::DependentFixed { dirichlet } = e.fault {
            if let Some(l) = dirichlet_loc.get(dirichlet) {
                message += &format!(" (*BOUNDARY at line {})", l.line);
            }
        }
        Err(self.err(self.equations[e.equation].loc, message))
    }
}

#[cfg(test)]
mod tests {
    use crate::deck::test_decks::*;
    use crate::fem::constraints::{DofMap, DofTarget};
    use crate::fem::static_analysis::{solve_static, SolveOptions};

    /// HEX with u7x = u6x and 2 u19y − u18y + 0.5 u17x = 0 (a term line
    /// continued with a trailing comma).
    fn equations() -> String {
        with(
            HEX,
            "*STEP",
            "*EQUATION\n2\n7, 1, 1., 6, 1, -1.\n3\n19, 2, 2.,\n18, 2, -1., 17, 1, 0.5\n*STEP",
        )
    }

    #[test]
    fn equations_are_read_and_hold() {
        let d = equations();
        let deck = parse(&d).unwrap();
        assert!(deck.warnings.is_empty(), "{:?}", deck.warnings);
        let m = &deck.model;
        assert_eq!(m.equations.len(), 2);
        let n = |l: u64| m.mesh.node(l).unwrap();
        let t = &m.equations[1].terms;
        assert_eq!(
            t.iter()
                .map(|t| (t.node, t.component, t.coefficient))
                .collect::<Vec<_>>(),
            vec![(n(19), 1, 2.0), (n(18), 1, -1.0), (n(17), 0, 0.5)]
        );
        let dofs = DofMap::new(m).unwrap();
        assert!(matches!(
            dofs.targets[3 * n(7)],
            DofTarget::Coupled { len: 1, .. }
        ));
        assert!(dofs.is_dependent(3 * n(19) + 1) && !dofs.is_dependent(3 * n(18) + 1));
        let sol = solve_static(m, &SolveOptions::default()).unwrap();
        let u = &sol.displacement;
        assert!(u[3 * n(7)].abs() > 1e-9);
        assert!((u[3 * n(7)] - u[3 * n(6)]).abs() <= 1e-15);
        let r = 2.0 * u[3 * n(19) + 1] - u[3 * n(18) + 1] + 0.5 * u[3 * n(17)];
        assert!(r.abs() <= 1e-15 * u[3 * n(18) + 1].abs().max(1e-9), "{r}");
    }

    /// A chain u7x = u6x, u6x = 0.5 u8x (in either order), a repeated DOF
    /// (its coefficients add, as in ccx), a one-term equation (a zero
    /// DOF), and an independent DOF with a prescribed value (the TOP nodes'
    /// u_z = −0.01 of the step).
    #[test]
    fn chains_repeats_and_prescribed_independents() {
        for order in [
            "2\n7, 1, 1., 6, 1, -1.\n2\n6, 1, 1., 8, 1, -0.5\n",
            "2\n6, 1, 1., 8, 1, -0.5\n2\n7, 1, 1., 6, 1, -1.\n",
        ] {
            let d = with(HEX, "*STEP", &format!("*EQUATION\n{order}*STEP"));
            let m = parse(&d).unwrap().model;
            let n = |l: u64| m.mesh.node(l).unwrap();
            let u = solve_static(&m, &SolveOptions::default())
                .unwrap()
                .displacement;
            assert!((u[3 * n(7)] - 0.5 * u[3 * n(8)]).abs() <= 1e-15);
            assert!((u[3 * n(6)] - 0.5 * u[3 * n(8)]).abs() <= 1e-15);
        }
        let d = with(
            HEX,
            "*STEP",
            "*EQUATION\n3\n7, 1, 1., 7, 1, -0.5, 6, 1, -1.\n1\n19, 1, 3.\n2\n17, 2, 1., 7, 3, -2.\n*STEP",
        );
        let m = parse(&d).unwrap().model;
        let n = |l: u64| m.mesh.node(l).unwrap();
        let u = solve_static(&m, &SolveOptions::default())
            .unwrap()
            .displacement;
        assert!((u[3 * n(7)] - 2.0 * u[3 * n(6)]).abs() <= 1e-15);
        assert_eq!(u[3 * n(19)], 0.0);
        assert!(
            (u[3 * n(17) + 1] + 0.02).abs() <= 1e-15,
            "{}",
            u[3 * n(17) + 1]
        );
    }

    #[test]
    fn equation_errors_name_the_line() {
        let d = equations();
        let eq = "*EQUATION\n2\n7, 1, 1., 6, 1, -1.\n";
        let e = with(HEX, "*STATIC\n", &format!("*STATIC\n{eq}"));
        expect_err(&e, line_of(&e, "*EQUATION"), "before *STEP");
        let e = with(&d, "*EQUATION\n", "*EQUATION, INPUT=eq.inp\n");
        expect_err(&e, line_of(&e, "INPUT="), "parameter INPUT");
        let e = with(&d, "\n2\n7, 1,", "\n2.5\n7, 1,");
        expect_err(&e, line_of(&e, "*EQUATION") + 1, "positive integer");
        let e = with(&d, "\n2\n7, 1,", "\n0\n7, 1,");
        expect_err(&e, line_of(&e, "*EQUATION") + 1, "positive integer");
        let e = with(&d, "7, 1, 1., 6, 1, -1.", "7, 1, 1., 6, 1, -1., 5, 1, 1.");
        expect_err(&e, line_of(&e, "5, 1, 1."), "more terms than the 2");
        let e = with(&d, "7, 1, 1., 6, 1, -1.", "7, 1, 1., 6, 1");
        expect_err(&e, line_of(&e, "7, 1, 1., 6, 1"), "triples");
        let e = with(&d, "\n3\n19, 2, 2.,", "\n4\n19, 2, 2.,");
        expect_err(
            &e,
            line_of(&e, "19, 2, 2.,") - 1,
            "announces 4 terms but has 3",
        );
        let e = with(
            &d,
            "*EQUATION\n2\n7, 1, 1., 6",
            "*NSET, NSET=A\n7\n*EQUATION\n2\nA, 1, 1., 6",
        );
        expect_err(&e, line_of(&e, "A, 1, 1."), "node set labels");
        let e = with(&d, "7, 1, 1., 6", "7, 4, 1., 6");
        expect_err(&e, line_of(&e, "7, 4, 1."), "translations 1-3");
        let e = with(&d, "7, 1, 1., 6", "77, 1, 1., 6");
        expect_err(&e, line_of(&e, "77, 1, 1."), "node 77 is not defined");
        let e = with(&d, "7, 1, 1., 6, 1, -1.", "7, 1, 1., 6, 1, -x");
        expect_err(&e, line_of(&e, "6, 1, -x"), "malformed number");
        // refusals of the elimination: at the equation's term-count line
        let count = |e: &str| line_of(e, "*EQUATION") + 1;
        let e = with(&d, "7, 1, 1., 6", "7, 1, 0., 6");
        expect_err(&e, count(&e), "coefficient of its first term");
        let e = with(&d, "7, 1, 1., 6", "7, 1, 1., 7, 1, -1., 6");
        let e = with(&e, "\n2\n7, 1, 1., 7", "\n3\n7, 1, 1., 7");
        expect_err(&e, count(&e), "is zero (after adding");
        let e = with(&d, "7, 1, 1., 6", "2, 1, 1., 6");
        expect_err(&e, count(&e), "also prescribed by a *BOUNDARY");
        let e = with(&d, "7, 1, 1., 6", "5, 3, 1., 6");
        expect_err(
            &e,
            count(&e),
            &format!("*BOUNDARY at line {}", line_of(&e, "top, 3, 3")),
        );
        let e = with(&d, "19, 2, 2.,", "7, 1, 2.,");
        expect_err(
            &e,
            line_of(&e, "7, 1, 2.,") - 1,
            "already the dependent DOF of the equation at line",
        );
        let e = with(&d, "18, 2, -1., 17, 1, 0.5", "7, 1, -1., 17, 1, 0.5");
        let e = with(&e, "19, 2, 2.,", "6, 1, 2.,");
        expect_err(&e, count(&e), "cycle");
        let e = with(&d, "*EQUATION\n", "*NODE\n99, 3, 3, 3\n*EQUATION\n");
        let e = with(&e, "7, 1, 1., 6", "7, 1, 1., 99");
        expect_err(&e, line_of(&e, "*EQUATION") + 1, "belongs to no element");
        // an empty *EQUATION is a warning (ccx: no-op)
        let e = with(&d, "*STEP", "*EQUATION\n*STEP");
        let w = parse(&e).unwrap().warnings;
        assert!(
            w.iter().any(|w| w.message.contains("without an equation")),
            "{w:?}"
        );
    }

    #[test]
    fn equations_with_couplings_or_contact_are_refused() {
        let d = with(
            HEX,
            "*STEP",
            "*NODE\n100, 0.5, 0.5, 1.\n*RIGID BODY, NSET=TOP, REF NODE=100\n*EQUATION\n2\n100, 1, 1., 17, 1, -1.\n*STEP",
        );
        let d = with(&d, "top, 3, 3, -0.01", "100, 1, 3");
        expect_err(&d, line_of(&d, "100, 1, 1."), "reference node");
        let d = with(&d, "100, 1, 1., 17", "5, 1, 1., 17");
        expect_err(&d, line_of(&d, "*EQUATION") + 1, "rigid coupling");
        let c = two_cubes(CONTACT);
        let c = with(&c, "*STEP", "*EQUATION\n2\n7, 1, 1., 6, 1, -1.\n*STEP");
        expect_err(&c, line_of(&c, "*EQUATION") + 1, "*CONTACT PAIR");
    }
}
