//! Writes the results of a static solve: `displacements.csv`, `stresses.csv`,
//! `reactions.csv`, `result.vtu` and `summary.json`; with contact also
//! `contact.csv`, the contact pressure and force in `result.vtu` and a
//! `contact` section in `summary.json`.

use std::io::Write;
use std::path::Path;

use crate::contact::solve::ContactSolution;
use crate::error::FlankError;
use crate::fem::model::Model;
use crate::fem::static_analysis::StaticSolution;
use crate::report::vtu::{write_vtu, PointField};

/// A result file written whole or not at all ([`crate::atomic_file`]).
fn create(path: &Path) -> Result<crate::atomic_file::AtomicWriter, FlankError> {
    crate::atomic_file::AtomicWriter::create(path)
}

/// `node,ux,uy,uz`, one row per node with the deck's node labels, full precision.
pub fn write_displacements_csv(path: &Path, model: &Model, u: &[f64]) -> Result<(), FlankError> {
    let mut w = create(path)?;
    let io = |e| FlankError::io(path, e);
    writeln!(w, "node,ux,uy,uz").map_err(io)?;
    for (i, label) in model.mesh.node_labels.iter().enumerate() {
        writeln!(
            w,
            "{label},{:e},{:e},{:e}",
            u[3 * i],
            u[3 * i + 1],
            u[3 * i + 2]
        )
        .map_err(io)?;
    }
    w.commit()
}

/// Writes every output file of a solve into `dir` (created if needed).
pub fn write_solution(
    dir: &Path,
    model: &Model,
    sol: &StaticSolution,
    extra: serde_json::Value,
) -> Result<(), FlankError> {
    write_all(dir, model, sol, extra, Vec::new())
}

/// `contact.csv`: one row per paired slave node (deck labels): pair, slave
/// node, position, final gap (mm, negative = penetration), normal force
/// (N), contact pressure (MPa, face-averaged), λ/area (MPa), tributary
/// area (mm²), master normal, status (open/closed). With friction (a pair
/// with μ > 0) the columns go on: tangential force on the slave node
/// `ft_x, ft_y, ft_z` (N, global), `shear` (‖tangential force‖/area, MPa),
/// the total tangential relative displacement `slip_x, slip_y, slip_z` and
/// its magnitude `slip` (mm), and `friction_status` (stick/slip/open); a
/// frictionless solve writes the file exactly as before.
pub fn write_contact_csv(
    path: &Path,
    model: &Model,
    contact: &ContactSolution,
) -> Result<(), FlankError> {
    let mut w = create(path)?;
    let io = |e| FlankError::io(path, e);
    let friction = contact.summary.friction.is_some();
    writeln!(
        w,
        "pair,slave_node,x,y,z,gap,normal_force,pressure,nodal_pressure,area,nx,ny,nz,status{}",
        if friction {
            ",ft_x,ft_y,ft_z,shear,slip_x,slip_y,slip_z,slip,friction_status"
        } else {
            ""
        }
    )
    .map_err(io)?;
    for s in &contact.slaves {
        let x = model.mesh.coords[s.node];
        writeln!(
            w,
            "{},{},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{}{}",
            s.pair + 1,
            model.mesh.node_labels[s.node],
            x[0],
            x[1],
            x[2],
            s.gap,
            s.force,
            s.pressure,
            s.nodal_pressure,
            s.area,
            s.normal[0] + 0.0, // no "-0e0"
            s.normal[1] + 0.0,
            s.normal[2] + 0.0,
            s.status.name(),
            match &s.friction {
                Some(f) => format!(
                    ",{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e},{}",
                    f.tangential_force[0] + 0.0,
                    f.tangential_force[1] + 0.0,
                    f.tangential_force[2] + 0.0,
                    f.shear,
                    f.slip[0] + 0.0,
                    f.slip[1] + 0.0,
                    f.slip[2] + 0.0,
                    f.slip_magnitude,
                    f.status.name()
                ),
                None if friction => ",0e0,0e0,0e0,0e0,0e0,0e0,0e0,0e0,open".to_string(),
                None => String::new(),
            }
        )
        .map_err(io)?;
    }
    w.commit()
}

/// Writes the files of a contact solve: those of [`write_solution`] plus
/// `contact.csv`, the fields `contact_pressure` and `contact_force` in
/// `result.vtu`, and the contact figures (iterations, active set, residuals,
/// penalty used, ...) under `"contact"` in `summary.json`.
pub fn write_contact_solution(
    dir: &Path,
    model: &Model,
    contact: &ContactSolution,
    extra: serde_json::Value,
) -> Result<(), FlankError> {
    std::fs::create_dir_all(dir).map_err(|e| FlankError::io(dir, e))?;
    write_contact_csv(&dir.join("contact.csv"), model, contact)?;
    let mut extra = extra;
    if let serde_json::Value::Object(obj) = &mut extra {
        obj.insert(
            "contact".into(),
            serde_json::to_value(&contact.summary).expect("contact summary serializes"),
        );
    }
    write_all(
        dir,
        model,
        &contact.solution,
        extra,
        vec![
            PointField {
                name: "contact_pressure",
                components: 1,
                values: &contact.pressure,
            },
            PointField {
                name: "contact_force",
                components: 3,
                values: &contact.force,
            },
        ],
    )
}

fn write_all(
    dir: &Path,
    model: &Model,
    sol: &StaticSolution,
    extra: serde_json::Value,
    more_fields: Vec<PointField>,
) -> Result<(), FlankError> {
    std::fs::create_dir_all(dir).map_err(|e| FlankError::io(dir, e))?;
    write_displacements_csv(&dir.join("displacements.csv"), model, &sol.displacement)?;
    let mut point_fields = vec![PointField {
        name: "displacement",
        components: 3,
        values: &sol.displacement,
    }];
    point_fields.extend(more_fields);
    let stress_flat: Vec<f64>;
    if let Some(rec) = &sol.recovery {
        let path = dir.join("stresses.csv");
        let mut w = create(&path)?;
        let io = |e| FlankError::io(&path, e);
        writeln!(w, "node,sxx,syy,szz,sxy,syz,sxz,von_mises").map_err(io)?;
        for (i, label) in model.mesh.node_labels.iter().enumerate() {
            let s = rec.stress[i];
            writeln!(
                w,
                "{label},{:e},{:e},{:e},{:e},{:e},{:e},{:e}",
                s[0], s[1], s[2], s[3], s[4], s[5], rec.von_mises[i]
            )
            .map_err(io)?;
        }
        w.commit()?;
        stress_flat = rec.stress.iter().flat_map(|s| s.iter().copied()).collect();
        point_fields.push(PointField {
            name: "stress",
            components: 6,
            values: &stress_flat,
        });
        point_fields.push(PointField {
            name: "von_mises",
            components: 1,
            values: &rec.von_mises,
        });
    }
    if let Some(reaction) = &sol.reaction {
        let path = dir.join("reactions.csv");
        let mut w = create(&path)?;
        let io = |e| FlankError::io(&path, e);
        writeln!(w, "node,rx,ry,rz").map_err(io)?;
        let constrained = constrained_nodes(model);
        for (i, label) in model.mesh.node_labels.iter().enumerate() {
            if constrained[i] {
                writeln!(
                    w,
                    "{label},{:e},{:e},{:e}",
                    reaction[3 * i],
                    reaction[3 * i + 1],
                    reaction[3 * i + 2]
                )
                .map_err(io)?;
            }
        }
        w.commit()?;
        point_fields.push(PointField {
            name: "reaction",
            components: 3,
            values: reaction,
        });
    }
    write_vtu(&dir.join("result.vtu"), &model.mesh, &point_fields, &[])?;
    let mut summary = serde_json::to_value(&sol.stats).expect("stats serialize");
    if let (Some(obj), serde_json::Value::Object(extra)) = (summary.as_object_mut(), extra) {
        for (k, v) in extra {
            obj.insert(k, v);
        }
        let umax = (0..model.mesh.node_count())
            .map(|i| {
                (sol.displacement[3 * i].powi(2)
                    + sol.displacement[3 * i + 1].powi(2)
                    + sol.displacement[3 * i + 2].powi(2))
                .sqrt()
            })
            .fold(0.0f64, f64::max);
        obj.insert("max_displacement_mm".into(), umax.into());
        if let Some(rec) = &sol.recovery {
            obj.insert(
                "max_von_mises_mpa".into(),
                rec.von_mises.iter().copied().fold(0.0f64, f64::max).into(),
            );
        }
    }
    let path = dir.join("summary.json");
    crate::atomic_file::write(
        &path,
        serde_json::to_string_pretty(&summary).expect("json") + "\n",
    )
}

/// Nodes with at least one prescribed DOF, in a rigid coupling or in an
/// equation (its constraint force acts on all of its terms' nodes).
fn constrained_nodes(model: &Model) -> Vec<bool> {
    let mut c = vec![false; model.mesh.node_count()];
    for bc in &model.dirichlet {
        c[bc.node] = true;
    }
    for cp in &model.couplings {
        for &n in &cp.nodes {
            c[n] = true;
        }
    }
    for t in model.equations.iter().flat_map(|e| &e.terms) {
        if let Some(slot) = c.get_mut(t.node) {
            *slot = true;
        }
    }
    c
}
