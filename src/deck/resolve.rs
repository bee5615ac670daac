//! The end of the deck (phase 2 of the reader).
//!
//! Element connectivity is resolved (so `*NODE` may follow `*ELEMENT`), then
//! the commands recorded while reading (set contents, sections, `*BOUNDARY`,
//! `*CLOAD`, `*DLOAD`, temperatures, the sets of `*RIGID BODY`, surface items) are
//! replayed in file order; the couplings, the equations and the contact
//! definition are checked and built, materials assigned, the sets stored in the mesh, and
//! the couplings' reference nodes leave the mesh. Every error names the line
//! that caused it.

use std::collections::HashMap;

use super::parser::Parser;
use super::records::{Cmd, CouplingMembers, Loc, SetItem, StepState};
use super::sets::IdxSet;
use super::Deck;
use crate::error::Result;
use crate::fem::contact_definition::SurfaceKind;
use crate::fem::model::{
    BodyForce, BodyLoad, Dirichlet, Model, NodalForce, Pressure, Temperatures,
};

impl Parser {
    /// Resolves everything recorded in phase 1 and builds the model.
    pub(super) fn finish(mut self) -> Result<Deck> {
        self.end_block()?;
        if let Some(c) = self.pending_coupling {
            return Err(self.err(
                self.couplings[c].loc,
                "*COUPLING must be followed by *KINEMATIC (end of deck reached)",
            ));
        }
        match self.step {
            StepState::Open {
                loc,
                procedure: false,
            } => return Err(self.err(loc, "*STEP has no *STATIC procedure")),
            StepState::Open { loc, .. } => self.warn(loc, "*STEP without *END STEP"),
            StepState::Before => {
                self.warn(Loc { file: 0, line: 0 }, "deck has no *STEP (no loads)")
            }
            StepState::Closed => {}
        }

        // Elements, in file order.
        let elem_loc = self.resolve_elements()?;

        // Reference nodes of the hub couplings: not part of the mesh.
        let roles = self.reference_roles()?;
        let ncp = self.couplings.len();
        let mut cp_nodes: Vec<Vec<usize>> = vec![Vec::new(); ncp];
        let mut cp_fixed: Vec<[Option<Loc>; 6]> = vec![[None; 6]; ncp];
        let mut cp_load: Vec<[(f64, Option<Loc>); 6]> = vec![[(0.0, None); 6]; ncp];

        // Replay of sets, sections, boundary conditions and loads.
        let nn = self.mesh.node_count();
        let ne = self.mesh.elements.len();
        let mut nsets: Vec<Option<IdxSet>> = (0..self.names.len()).map(|_| None).collect();
        let mut esets: Vec<Option<IdxSet>> = (0..self.names.len()).map(|_| None).collect();
        let mut elem_mat: Vec<Option<usize>> = vec![None; ne];
        let mut dirichlet: Vec<Dirichlet> = Vec::new();
        let mut dirichlet_loc: Vec<Loc> = Vec::new();
        let mut bc_index: HashMap<(usize, usize), usize> = HashMap::new();
        let mut forces = Vec::new();
        let mut pressures = Vec::new();
        let mut body_loads: Vec<BodyLoad> = Vec::new();
        let mut body_loc: Vec<Loc> = Vec::new();
        // (element, centrifugal?) → the line of its GRAV / CENTRIF
        let mut body_seen: HashMap<(usize, bool), Loc> = HashMap::new();
        // T0 and T of each node (None: not given, 0 as in ccx)
        let mut t0: Vec<Option<f64>> = vec![None; nn];
        let mut t1: Vec<Option<f64>> = vec![None; nn];
        let mut surface_faces: Vec<Vec<(usize, usize)>> = vec![Vec::new(); self.surfaces.len()];
        let mut surface_nodes: Vec<Vec<usize>> = vec![Vec::new(); self.surfaces.len()];
        for cmd in std::mem::take(&mut self.cmds) {
            match cmd {
                Cmd::NodeRange { set, start, end } => {
                    let s = nsets[set as usize].get_or_insert_with(IdxSet::default);
                    (start..end).for_each(|i| s.insert(i));
                }
                Cmd::ElemRange { set, start, end } => {
                    let s = esets[set as usize].get_or_insert_with(IdxSet::default);
                    (start..end).for_each(|i| s.insert(i));
                }
                Cmd::Define { elem, set } => {
                    let sets = if elem { &mut esets } else { &mut nsets };
                    sets[set as usize].get_or_insert_with(IdxSet::default);
                }
                Cmd::SetItem {
                    elem,
                    set,
                    item,
                    loc,
                } => {
                    let what = if elem { "element" } else { "node" };
                    let new: Vec<usize> = match item {
                        SetItem::Label(l) => {
                            let i = if elem {
                                self.mesh.element(l)
                            } else {
                                self.mesh.node(l)
                            };
                            vec![i.ok_or_else(|| {
                                self.err(loc, format!("{what} {l} is not defined"))
                            })?]
                        }
                        SetItem::Set(other) => {
                            let sets = if elem { &esets } else { &nsets };
                            self.set_members(sets, elem, other, loc)?
                        }
                        SetItem::Range { first, last, step } => {
                            let (found, count) = self.generate(elem, first, last, step);
                            if (found.len() as u64) < count {
                                self.warn(
                                    loc,
                                    format!(
                                        "GENERATE {first}..{last} step {step}: {} of {count} {what} labels are not defined (skipped)",
                                        count - found.len() as u64
                                    ),
                                );
                            }
                            found
                        }
                    };
                    let sets = if elem { &mut esets } else { &mut nsets };
                    let s = sets[set as usize].get_or_insert_with(IdxSet::default);
                    new.into_iter().for_each(|i| s.insert(i));
                }
                Cmd::Section {
                    elset,
                    material,
                    loc,
                } => {
                    let members = self.set_members(&esets, true, elset, loc)?;
                    let m = *self.material_ids.get(&material).ok_or_else(|| {
                        self.err(loc, format!("material {material} is not defined"))
                    })?;
                    if self.materials[m].elastic.is_none() {
                        return Err(self.err(loc, format!("material {material} has no *ELASTIC")));
                    }
                    let mut reassigned = false;
                    for e in members {
                        reassigned |= elem_mat[e].replace(m).is_some();
                    }
                    if reassigned {
                        let name = self.names[elset as usize].clone();
                        self.warn(
                            loc,
                            format!(
                                "elements of {name} already had a section: material reassigned"
                            ),
                        );
                    }
                }
                Cmd::Boundary {
                    target,
                    first,
                    last,
                    value,
                    loc,
                } => {
                    let mut rotations_ignored = false;
                    let nodes = self.target_nodes(&nsets, target, loc)?;
                    for node in self.nonempty(nodes, target, "*BOUNDARY", loc)? {
                        if let Some(&role) = roles.get(&node) {
                            for component in first..=last {
                                let k = self.reference_dof(role, component, "*BOUNDARY", loc)?;
                                if value != 0.0 {
                                    return Err(self.err(
                                        loc,
                                        format!(
                                            "prescribed value {value} on DOF {} of reference node {} ({}): only zero (fixed) reference DOFs are supported",
                                            component + 1,
                                            self.mesh.node_labels[node],
                                            self.coupling_title(role.coupling)
                                        ),
                                    ));
                                }
                                cp_fixed[role.coupling][k] = Some(loc);
                            }
                            continue;
                        }
                        if last >= 3 {
                            if value != 0.0 {
                                return Err(self.err(
                                    loc,
                                    format!(
                                        "nonzero value {value} on rotational DOFs 4-6 of node {}: solid elements have none",
                                        self.mesh.node_labels[node]
                                    ),
                                ));
                            }
                            rotations_ignored = true;
                        }
                        for component in first..=last.min(2) {
                            match bc_index.get(&(node, component)) {
                                Some(&k) => {
                                    dirichlet[k].value = value;
                                    dirichlet_loc[k] = loc;
                                }
                                None => {
                                    bc_index.insert((node, component), dirichlet.len());
                                    dirichlet.push(Dirichlet {
                                        node,
                                        component,
                                        value,
                                    });
                                    dirichlet_loc.push(loc);
                                }
                            }
                        }
                    }
                    if rotations_ignored {
                        self.warn(
                            loc,
                            "*BOUNDARY on rotational DOFs 4-6 ignored (solid elements have none)",
                        );
                    }
                }
                Cmd::Cload {
                    target,
                    comp,
                    value,
                    loc,
                } => {
                    let nodes = self.target_nodes(&nsets, target, loc)?;
                    for node in self.nonempty(nodes, target, "*CLOAD", loc)? {
                        if let Some(&role) = roles.get(&node) {
                            let k = self.reference_dof(role, comp, "*CLOAD", loc)?;
                            let slot = &mut cp_load[role.coupling][k];
                            slot.0 += value;
                            slot.1 = Some(loc);
                            continue;
                        }
                        if comp > 2 {
                            return Err(self.err(
                                loc,
                                format!(
                                    "*CLOAD on DOF {} of node {} is not supported (only forces on DOFs 1-3; moments only on a *COUPLING REF NODE or a *RIGID BODY ROT NODE)",
                                    comp + 1,
                                    self.mesh.node_labels[node]
                                ),
                            ));
                        }
                        forces.push(NodalForce {
                            node,
                            component: comp,
                            value,
                        });
                    }
                }
                Cmd::Temperature {
                    target,
                    value,
                    initial,
                    loc,
                } => {
                    let kw = if initial {
                        "*INITIAL CONDITIONS"
                    } else {
                        "*TEMPERATURE"
                    };
                    let nodes = self.target_nodes(&nsets, target, loc)?;
                    for node in self.nonempty(nodes, target, kw, loc)? {
                        if initial {
                            t0[node] = Some(value);
                        }
                        t1[node] = Some(value);
                    }
                }
                Cmd::Coupling { coupling } => {
                    let raw = &self.couplings[coupling];
                    let loc = raw.loc;
                    let nodes = match raw.members {
                        CouplingMembers::NodeSet(id) => self.set_members(&nsets, false, id, loc)?,
                        CouplingMembers::ElementSet(id) => {
                            let mut v: Vec<usize> = self
                                .set_members(&esets, true, id, loc)?
                                .into_iter()
                                .flat_map(|e| self.mesh.elements[e].nodes.iter().copied())
                                .collect();
                            v.sort_unstable();
                            v.dedup();
                            v
                        }
                        CouplingMembers::Surface(_) => Vec::new(),
                    };
                    cp_nodes[coupling] = nodes;
                }
                Cmd::Dload {
                    target,
                    face,
                    value,
                    loc,
                } => {
                    let elements = self.target_elements(&esets, target, loc)?;
                    for element in self.nonempty(elements, target, "*DLOAD", loc)? {
                        let el = &self.mesh.elements[element];
                        if face > el.kind.face_count() {
                            return Err(self.err(
                                loc,
                                format!(
                                    "*DLOAD face P{face} out of range for {} element {} (P1..P{})",
                                    el.kind.name(),
                                    el.label,
                                    el.kind.face_count()
                                ),
                            ));
                        }
                        pressures.push(Pressure {
                            element,
                            face,
                            value,
                        });
                    }
                }
                Cmd::BodyLoad { target, force, loc } => {
                    let centrif = matches!(force, BodyForce::Centrifugal { .. });
                    let ty = if centrif { "CENTRIF" } else { "GRAV" };
                    let elements = self.target_elements(&esets, target, loc)?;
                    for element in self.nonempty(elements, target, "*DLOAD", loc)? {
                        if let Some(first) = body_seen.insert((element, centrif), loc) {
                            return Err(self.err(
                                loc,
                                format!(
                                    "second *DLOAD {ty} on element {} (first at line {}): several loads of one type on an element are not supported (ccx would replace or add them depending on the sets); give one {ty} per element",
                                    self.mesh.elements[element].label,
                                    first.line
                                ),
                            ));
                        }
                        body_loads.push(BodyLoad {
                            element,
                            force: force.clone(),
                        });
                        body_loc.push(loc);
                    }
                }
                Cmd::SurfaceItem {
                    surface,
                    target,
                    face,
                    loc,
                } => {
                    if face == 0 {
                        let nodes = self.target_nodes(&nsets, target, loc)?;
                        surface_nodes[surface].extend(nodes);
                        continue;
                    }
                    for element in self.target_elements(&esets, target, loc)? {
                        let el = &self.mesh.elements[element];
                        if face > el.kind.face_count() {
                            return Err(self.err(
                                loc,
                                format!(
                                    "*SURFACE face S{face} out of range for {} element {} (S1..S{})",
                                    el.kind.name(),
                                    el.label,
                                    el.kind.face_count()
                                ),
                            ));
                        }
                        surface_faces[surface].push((element, face));
                    }
                }
            }
        }
        // *COUPLING surfaces (complete now: a surface is defined once).
        self.coupling_surface_nodes(&mut cp_nodes, &surface_faces, &surface_nodes)?;
        let couplings = self.build_couplings(
            &roles,
            cp_nodes,
            &cp_fixed,
            &cp_load,
            &dirichlet,
            &dirichlet_loc,
        )?;
        let contact = self.contact_definition(surface_faces, surface_nodes)?;
        let mut equations = self.build_equations(&roles, contact.pairs.len())?;

        // Materials: keep complete ones; drop unused ones without *ELASTIC.
        let (materials, element_material) = self.element_materials(&elem_mat, &elem_loc)?;
        // Body loads need the density of their elements' material.
        for (bl, &loc) in body_loads.iter().zip(&body_loc) {
            let m = &materials[element_material[bl.element]];
            if m.density.is_none() {
                let ty = match bl.force {
                    BodyForce::Gravity { .. } => "GRAV",
                    BodyForce::Centrifugal { .. } => "CENTRIF",
                };
                return Err(self.err(
                    loc,
                    format!(
                        "*DLOAD {ty} on element {}: its material {} has no *DENSITY",
                        self.mesh.elements[bl.element].label, m.name
                    ),
                ));
            }
        }

        // A thermal load takes the elastic constants at one temperature:
        // ccx would interpolate a temperature table at each point's T.
        if let Some(initial_loc) = self.initial_temperature {
            let mut used = vec![false; self.materials.len()];
            for m in elem_mat.iter().flatten() {
                used[*m] = true;
            }
            for (m, raw) in self.materials.iter().enumerate() {
                if let (true, Some(loc)) = (used[m], raw.temperature_table) {
                    return Err(self.err(
                        loc,
                        format!(
                            "material {} has temperature-dependent constants (several *ELASTIC or *DENSITY lines) and the deck has a thermal load: not supported (ccx would take them at each point's temperature); give one line",
                            raw.name
                        ),
                    ));
                }
            }
            // every node of an element with an expansion coefficient needs
            // its T0: ccx would take its placeholder 1.2357111319 there
            for (e, el) in self.mesh.elements.iter().enumerate() {
                if materials[element_material[e]].expansion.is_none() {
                    continue;
                }
                if let Some(&n) = el.nodes.iter().find(|&&n| t0[n].is_none()) {
                    let missing = (0..nn).filter(|&n| t0[n].is_none()).count();
                    return Err(self.err(
                        initial_loc,
                        format!(
                            "node {} of element {} (material {} with *EXPANSION) has no initial temperature ({missing} node(s) in all have none): ccx would silently take its placeholder value 1.2357111319 as T0 (and as T without a *TEMPERATURE); give these nodes an *INITIAL CONDITIONS, TYPE=TEMPERATURE line",
                            self.mesh.node_labels[n],
                            el.label,
                            materials[element_material[e]].name
                        ),
                    ));
                }
            }
        }

        // Sets into the mesh (sorted once), NALL/EALL implicit.
        for (id, s) in nsets.into_iter().enumerate() {
            if let Some(s) = s {
                let mut v = s.members;
                v.sort_unstable();
                self.mesh.node_sets.insert(self.names[id].clone(), v);
            }
        }
        for (id, s) in esets.into_iter().enumerate() {
            if let Some(s) = s {
                let mut v = s.members;
                v.sort_unstable();
                self.mesh.element_sets.insert(self.names[id].clone(), v);
            }
        }
        self.mesh
            .node_sets
            .entry("NALL".to_string())
            .or_insert_with(|| (0..nn).collect());
        self.mesh
            .element_sets
            .entry("EALL".to_string())
            .or_insert_with(|| (0..ne).collect());

        // The reference nodes leave the mesh: their DOFs are the couplings'.
        let mut dropped = vec![false; nn];
        for &n in roles.keys() {
            dropped[n] = true;
        }
        for s in &contact.surfaces {
            if let SurfaceKind::Node(nodes) = &s.kind {
                if let Some(&n) = nodes.iter().find(|&&n| dropped[n]) {
                    let loc = self
                        .surfaces
                        .iter()
                        .find(|r| r.name == s.name)
                        .map_or(Loc { file: 0, line: 0 }, |r| r.loc);
                    return Err(self.err(
                        loc,
                        format!(
                            "surface {} contains node {}, the reference node of {} (not a mesh node)",
                            s.name,
                            self.mesh.node_labels[n],
                            self.coupling_title(roles[&n].coupling)
                        ),
                    ));
                }
            }
        }
        let (mesh, remap) = if roles.is_empty() {
            (std::mem::take(&mut self.mesh), None)
        } else {
            let (mesh, remap) = without_nodes(&self.mesh, &dropped);
            (mesh, Some(remap))
        };
        self.mesh = mesh;
        let mut couplings = couplings;
        let mut contact = contact;
        if let Some(remap) = &remap {
            for cp in couplings.iter_mut() {
                for n in cp.nodes.iter_mut() {
                    *n = remap[*n];
                }
            }
            for d in dirichlet.iter_mut() {
                d.node = remap[d.node];
            }
            for f in forces.iter_mut() {
                f.node = remap[f.node];
            }
            for t in equations.iter_mut().flat_map(|e| e.terms.iter_mut()) {
                t.node = remap[t.node];
            }
            for s in contact.surfaces.iter_mut() {
                if let SurfaceKind::Node(nodes) = &mut s.kind {
                    for n in nodes.iter_mut() {
                        *n = remap[*n];
                    }
                }
            }
        }

        // the temperatures of the mesh nodes (a reference node's has no effect)
        let temperatures = self.initial_temperature.map(|_| {
            let keep: Vec<usize> = (0..nn).filter(|&n| !dropped[n]).collect();
            Temperatures {
                initial: keep.iter().map(|&n| t0[n].unwrap_or(0.0)).collect(),
                current: keep.iter().map(|&n| t1[n].unwrap_or(0.0)).collect(),
            }
        });

        let unused = self.mesh.used_nodes().iter().filter(|u| !**u).count();
        if unused > 0 {
            self.warn(
                Loc { file: 0, line: 0 },
                format!("{unused} node(s) belong to no element"),
            );
        }

        let title = self.title.join("\n").trim().to_string();
        let model = Model {
            mesh: std::mem::take(&mut self.mesh),
            materials,
            element_material,
            dirichlet,
            forces,
            pressures,
            body_loads,
            temperatures,
            couplings,
            equations,
            contact,
        };
        self.check_equations(&model, &dirichlet_loc)?;
        Ok(Deck {
            model,
            warnings: self.warnings,
            title: (!title.is_empty()).then_some(title),
        })
    }
}

/// The mesh without the `drop`ped nodes (which belong to no element) and
/// the map old → new node index (`usize::MAX` for dropped nodes).
fn without_nodes(
    mesh: &crate::fem::mesh::Mesh,
    drop: &[bool],
) -> (crate::fem::mesh::Mesh, Vec<usize>) {
    let mut out = crate::fem::mesh::Mesh::new();
    let mut remap = vec![usize::MAX; mesh.node_count()];
    for (i, (&label, &x)) in mesh.node_labels.iter().zip(&mesh.coords).enumerate() {
        if !drop[i] {
            remap[i] = out.add_node(label, x).expect("labels are unique");
        }
    }
    for el in &mesh.elements {
        let nodes = el.nodes.iter().map(|&n| remap[n]).collect();
        out.add_element(el.label, el.kind, nodes)
            .expect("labels are unique");
    }
    for (name, members) in &mesh.node_sets {
        let v: Vec<usize> = members
            .iter()
            .filter(|&&n| !drop[n])
            .map(|&n| remap[n])
            .collect();
        out.node_sets.insert(name.clone(), v);
    }
    out.element_sets = mesh.element_sets.clone();
    (out, remap)
}
