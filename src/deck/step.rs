//! `*STEP`, `*STATIC`, `*END STEP`, `*BOUNDARY`, `*CLOAD` and `*DLOAD`.
//!
//! One linear static step: `*STEP` (`NLGEOM` only as `NLGEOM=NO`),
//! `*STATIC` (its one data line, the time stepping, cannot change a linear
//! answer and is skipped; a second or non-numeric line is an error), `*END STEP`. A second step, a step without
//! `*STATIC` and other procedures are errors (see [`super::keywords`]).
//!
//! `*BOUNDARY` (model or step data): `node or set, first DOF[, last DOF[,
//! value]]`; DOFs 1-3 of mesh nodes, zero DOFs 4-6 ignored with a warning
//! (solid elements have no rotations); a later value on the same DOF wins.
//! `*CLOAD` (step data): `node or set, DOF, value`, forces add up. `*DLOAD`
//! (step data): `element or set, Pn, value`, a pressure on face n; `element
//! or set, GRAV, g, nx, ny, nz`, gravity ρ g n (n normalised, as ccx does);
//! `element or set, CENTRIF, ω², px, py, pz, ax, ay, az`, the centrifugal
//! load ρ ω² r⊥ about the axis through p along a (normalised), r⊥ from the
//! undeformed position; no centrifugal stiffening (linear statics, as ccx
//! without NLGEOM). Both need a `*DENSITY` in the elements' material. Other
//! load types (NEWGRAV, edge and body-flux loads, ...) are errors. DOFs of
//! rigid-coupling reference nodes are resolved in [`super::coupling`].
//! `OP=MOD` is accepted, `OP=NEW` only where it removes nothing.

use super::lexer::norm_name;
use super::parser::Parser;
use super::records::{Block, Card, Cmd, Loc, StepState, Target};
use crate::error::Result;
use crate::fem::model::BodyForce;

impl Parser {
    /// `*STEP[, NLGEOM=NO]`: opens the one step.
    pub(super) fn kw_step(&mut self, card: &Card) -> Result<Block> {
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

    /// `*STATIC`: the procedure of the open step.
    pub(super) fn kw_static(&mut self, card: &Card) -> Result<Block> {
        let loc = card.loc;
        match &mut self.step {
            StepState::Open { procedure, .. } => *procedure = true,
            _ => return Err(self.err(loc, "*STATIC outside of a *STEP")),
        }
        Ok(Block::OneNumericLine {
            keyword: card.name.clone(),
            seen: false,
        })
    }

    /// `*END STEP`: closes the step, which needs its `*STATIC`.
    pub(super) fn kw_end_step(&mut self, card: &Card) -> Result<Block> {
        let loc = card.loc;
        match self.step {
            StepState::Open {
                procedure: false, ..
            } => return Err(self.err(loc, "*END STEP: the step has no *STATIC procedure")),
            StepState::Open { .. } => self.step = StepState::Closed,
            _ => return Err(self.err(loc, "*END STEP without *STEP")),
        }
        Ok(Block::NoData(card.name.clone()))
    }

    /// `*BOUNDARY`: model data, or data of the (one) step.
    pub(super) fn kw_boundary(&mut self, card: &Card) -> Result<Block> {
        let loc = card.loc;
        if matches!(self.step, StepState::Closed) {
            return Err(self.err(loc, "*BOUNDARY after *END STEP: only one step is supported"));
        }
        self.load_params(card, self.boundary_seen)?;
        self.boundary_seen = true;
        Ok(Block::Boundary)
    }

    /// `*CLOAD` or `*DLOAD`: step data.
    pub(super) fn kw_load(&mut self, card: &Card) -> Result<Block> {
        let loc = card.loc;
        let name = &card.name;
        if !matches!(self.step, StepState::Open { .. }) {
            return Err(self.err(
                loc,
                format!("*{name} outside of a *STEP (loads are step data)"),
            ));
        }
        if name == "CLOAD" {
            self.load_params(card, self.cload_seen)?;
            self.cload_seen = true;
            Ok(Block::Cload)
        } else {
            self.load_params(card, self.dload_seen)?;
            self.dload_seen = true;
            Ok(Block::Dload)
        }
    }

    /// Parameters of *BOUNDARY/*CLOAD/*DLOAD. OP=NEW is accepted only where it
    /// is a no-op (nothing of that kind defined before).
    pub(super) fn load_params(&self, card: &Card, seen: bool) -> Result<()> {
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

    pub(super) fn boundary_line(&mut self, f: &[&str], loc: Loc) -> Result<()> {
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

    pub(super) fn cload_line(&mut self, f: &[&str], loc: Loc) -> Result<()> {
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

    pub(super) fn dload_line(&mut self, f: &[&str], loc: Loc) -> Result<()> {
        if f.len() < 2 {
            return Err(self.err(loc, "*DLOAD data must be: element or set, Pn, value"));
        }
        let target = self.parse_target(f[0], loc)?;
        let ty = f[1].to_ascii_uppercase();
        if ty == "GRAV" || ty == "CENTRIF" {
            return self.body_load_line(target, &ty, f, loc);
        }
        let face = match ty.strip_prefix('P') {
            Some(d) if !d.is_empty() && d.bytes().all(|b| b.is_ascii_digit()) => {
                d.parse::<usize>().unwrap_or(usize::MAX)
            }
            _ => {
                return Err(self.err(
                    loc,
                    format!("unsupported *DLOAD load type {ty} (only face pressure P1..P6, GRAV and CENTRIF); ignoring it would change the answer"),
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

    /// `*DLOAD` GRAV (`g, nx, ny, nz`) or CENTRIF (`ω², px, py, pz, ax, ay,
    /// az`) after the target: the direction and the axis are normalised.
    fn body_load_line(&mut self, target: Target, ty: &str, f: &[&str], loc: Loc) -> Result<()> {
        let (n, form) = if ty == "GRAV" {
            (6, "element or set, GRAV, g, nx, ny, nz")
        } else {
            (
                9,
                "element or set, CENTRIF, omega^2, px, py, pz, ax, ay, az",
            )
        };
        if f.len() != n {
            return Err(self.err(loc, format!("*DLOAD {ty} data must be: {form}")));
        }
        let v = f[2..]
            .iter()
            .map(|t| self.parse_real(t, loc))
            .collect::<Result<Vec<f64>>>()?;
        let unit = |d: &[f64], what: &str| {
            let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            if !(len > 0.0 && len.is_finite()) {
                return Err(self.err(loc, format!("*DLOAD {ty}: the {what} is zero")));
            }
            Ok([d[0] / len, d[1] / len, d[2] / len])
        };
        let force = if ty == "GRAV" {
            let d = unit(&v[1..4], "direction")?;
            BodyForce::Gravity {
                acceleration: [v[0] * d[0], v[0] * d[1], v[0] * d[2]],
            }
        } else {
            BodyForce::Centrifugal {
                omega_squared: v[0],
                point: [v[1], v[2], v[3]],
                axis: unit(&v[4..7], "axis direction")?,
            }
        };
        self.cmds.push(Cmd::BodyLoad { target, force, loc });
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use crate::deck::test_decks::*;

    #[test]
    fn undefined_set_in_boundary() {
        let d = with(HEX, "bottom, 1, 3", "bottm, 1, 3");
        expect_err(&d, line_of(&d, "bottm"), "BOTTM");
    }

    #[test]
    fn dload_face_out_of_range() {
        let d = with(HEX, "E1, P2, 5.0", "E1, P7, 5.0");
        expect_err(&d, line_of(&d, "E1, P7"), "face");
        let d = with(HEX, "E1, P2, 5.0", "E1, NEWGRAV, 9810., 0., 0., -1.");
        expect_err(
            &d,
            line_of(&d, "NEWGRAV"),
            "unsupported *DLOAD load type NEWGRAV",
        );
    }

    #[test]
    fn dload_grav_and_centrif() {
        // HEX's material has *DENSITY 7.85e-9; a non-unit direction is normalised
        let d = with(
            HEX,
            "E1, P2, 5.0",
            "E1, P2, 5.0\nBLOCK, GRAV, 9810., 0., 0., -2.",
        );
        let m = parse(&d).unwrap().model;
        assert_eq!(m.materials[0].density, Some(7.85e-9));
        assert_eq!(
            m.body_loads,
            vec![crate::fem::model::BodyLoad {
                element: 0,
                force: crate::fem::model::BodyForce::Gravity {
                    acceleration: [0.0, 0.0, -9810.0]
                }
            }]
        );
        let d = with(HEX, "E1, P2, 5.0", "E1, CENTRIF, 1e6, 0, 0, 0, 0, 0, 3");
        let m = parse(&d).unwrap().model;
        assert_eq!(
            m.body_loads[0].force,
            crate::fem::model::BodyForce::Centrifugal {
                omega_squared: 1e6,
                point: [0.0; 3],
                axis: [0.0, 0.0, 1.0]
            }
        );
        // malformed, zero direction, repeated, missing density
        let d = with(HEX, "E1, P2, 5.0", "E1, GRAV, 9810., 0., 0.");
        expect_err(&d, line_of(&d, "GRAV"), "GRAV data must be");
        let d = with(HEX, "E1, P2, 5.0", "E1, CENTRIF, 1e6, 0, 0, 0, 0, 0");
        expect_err(&d, line_of(&d, "CENTRIF"), "CENTRIF data must be");
        let d = with(HEX, "E1, P2, 5.0", "E1, GRAV, 9810., 0., 0., 0.");
        expect_err(&d, line_of(&d, "GRAV"), "direction is zero");
        let d = with(
            HEX,
            "E1, P2, 5.0",
            "E1, GRAV, 9810., 0., 0., -1.\nBLOCK, GRAV, 1., 1., 0., 0.",
        );
        expect_err(&d, line_of(&d, "BLOCK, GRAV"), "second *DLOAD GRAV");
        let d = with(HEX, "*DENSITY\n7.85e-9\n", "");
        assert!(parse(&d).is_ok());
        let d = with(&d, "E1, P2, 5.0", "E1, CENTRIF, 1e6, 0, 0, 0, 0, 0, 1");
        expect_err(&d, line_of(&d, "CENTRIF"), "has no *DENSITY");
    }

    #[test]
    fn density_keyword() {
        let d = with(HEX, "7.85e-9", "-7.85e-9");
        expect_err(&d, line_of(&d, "-7.85e-9"), "density must be positive");
        let d = with(HEX, "*DENSITY\n7.85e-9\n", "*DENSITY\n");
        expect_err(&d, line_of(&d, "*DENSITY"), "*DENSITY without data line");
        let d = with(HEX, "7.85e-9", "7.85e-9\n*DENSITY\n1e-9");
        // at the second *DENSITY's keyword line, the one before its data
        expect_err(&d, line_of(&d, "1e-9") - 1, "second *DENSITY");
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
}
