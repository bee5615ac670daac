//! Constraints as a map from full DOFs to the reduced (free) unknowns.
//!
//! Every full DOF u_d is either a free unknown, a prescribed value (Dirichlet,
//! eliminated), or a linear combination of free DOFs plus a constant: the
//! free DOFs of a rigid coupling's reference point, or the independent DOFs
//! of a linear equation (`*EQUATION`, [`resolve_equations`]), whose
//! prescribed independent DOFs give the constant: u = Tq + u₀. The reduced
//! stiffness is Tᵀ K T, which stays symmetric positive definite when the
//! rigid-body modes are constrained (elimination, not Lagrange multipliers).
//!
//! Reduced unknowns are grouped: one group per node with free DOFs (in node
//! order), then one group per rigid coupling. Groups are the vertices of the
//! graph used for the fill-reducing ordering.

use std::collections::HashMap;

use crate::error::FlankError;
use crate::fem::model::Model;

/// Where a full DOF goes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DofTarget {
    /// A free unknown with this reduced index.
    Free(usize),
    /// A prescribed value (Dirichlet).
    Fixed(f64),
    /// A combination of reduced unknowns, `terms[start..start+len]` of
    /// [`DofMap`], plus `offset` (an equation's prescribed independent DOFs;
    /// 0 for a rigid coupling).
    Coupled {
        start: usize,
        len: usize,
        offset: f64,
    },
    /// A node attached to no element: not part of the system, displacement 0.
    Unused,
}

/// Full → reduced DOF map.
#[derive(Clone, Debug)]
pub struct DofMap {
    pub targets: Vec<DofTarget>,
    /// (reduced index, coefficient) terms of coupled DOFs.
    pub terms: Vec<(usize, f64)>,
    pub reduced_count: usize,
    /// First reduced index of each group, plus the end (length groups + 1).
    pub group_start: Vec<usize>,
    /// Group of each node with free DOFs (`usize::MAX` if none).
    pub node_group: Vec<usize>,
    /// Group index of each rigid coupling (`usize::MAX` if it has no free DOF).
    pub coupling_group: Vec<usize>,
    /// For each coupling, the reduced index of each of its six reference DOFs, if free.
    pub coupling_dofs: Vec<[Option<usize>; 6]>,
    /// Full DOF → index of the equation that makes it dependent (empty
    /// without equations).
    pub equation_of: HashMap<usize, usize>,
}

impl DofMap {
    /// Builds the map from the model's Dirichlet conditions and rigid couplings.
    pub fn new(model: &Model) -> Result<Self, FlankError> {
        let nn = model.mesh.node_count();
        let used = model.mesh.used_nodes();
        let mut fixed: Vec<Option<f64>> = vec![None; 3 * nn];
        for bc in &model.dirichlet {
            if bc.node >= nn || bc.component > 2 {
                return Err(FlankError::Model(format!(
                    "Dirichlet condition on node index {} component {} is out of range",
                    bc.node, bc.component
                )));
            }
            if !bc.value.is_finite() {
                return Err(FlankError::Model(format!(
                    "prescribed displacement of node {} is not finite",
                    model.mesh.node_labels[bc.node]
                )));
            }
            fixed[3 * bc.node + bc.component] = Some(bc.value);
        }
        // which coupling owns each node
        let mut owner = vec![usize::MAX; nn];
        for (c, cp) in model.couplings.iter().enumerate() {
            for &n in &cp.nodes {
                if n >= nn {
                    return Err(FlankError::Model(format!(
                        "coupling '{}' refers to node index {n} beyond the mesh",
                        cp.name
                    )));
                }
                if owner[n] != usize::MAX && owner[n] != c {
                    return Err(FlankError::Model(format!(
                        "node {} belongs to two rigid couplings ('{}' and '{}')",
                        model.mesh.node_labels[n], model.couplings[owner[n]].name, cp.name
                    )));
                }
                if (0..3).any(|k| fixed[3 * n + k].is_some()) {
                    return Err(FlankError::Model(format!(
                        "node {} of coupling '{}' also has a Dirichlet condition; constrain the reference point instead",
                        model.mesh.node_labels[n], cp.name
                    )));
                }
                owner[n] = c;
            }
        }
        let resolved = resolve_equations(model).map_err(|e| {
            FlankError::Model(e.describe(model, &|k| format!("equation {}", k + 1)))
        })?;
        let equation_of: HashMap<usize, usize> = resolved
            .iter()
            .enumerate()
            .map(|(e, (dep, _))| (*dep, e))
            .collect();
        let mut targets = vec![DofTarget::Unused; 3 * nn];
        let mut group_start = Vec::new();
        let mut node_group = vec![usize::MAX; nn];
        let mut next = 0usize;
        for n in 0..nn {
            if !used[n] || owner[n] != usize::MAX {
                continue;
            }
            let start = next;
            for k in 0..3 {
                if equation_of.contains_key(&(3 * n + k)) {
                    continue;
                }
                targets[3 * n + k] = match fixed[3 * n + k] {
                    Some(v) => DofTarget::Fixed(v),
                    None => {
                        next += 1;
                        DofTarget::Free(next - 1)
                    }
                };
            }
            if next > start {
                node_group[n] = group_start.len();
                group_start.push(start);
            }
        }
        let mut coupling_group = vec![usize::MAX; model.couplings.len()];
        let mut coupling_dofs = vec![[None; 6]; model.couplings.len()];
        for (c, cp) in model.couplings.iter().enumerate() {
            let start = next;
            for k in 0..6 {
                if cp.free[k] {
                    coupling_dofs[c][k] = Some(next);
                    next += 1;
                }
            }
            if next > start {
                coupling_group[c] = group_start.len();
                group_start.push(start);
            }
        }
        group_start.push(next);
        // coupled node DOFs: u = t + θ × (x − x_ref)
        let mut terms = Vec::new();
        for (c, cp) in model.couplings.iter().enumerate() {
            for &n in &cp.nodes {
                if !used[n] {
                    continue;
                }
                let x = model.mesh.coords[n];
                let r = [
                    x[0] - cp.reference_point[0],
                    x[1] - cp.reference_point[1],
                    x[2] - cp.reference_point[2],
                ];
                // θ × r: component i = Σ_k ε_{i k j} θ_k r_j
                let rot = [
                    [0.0, r[2], -r[1]], // x: θ_y r_z − θ_z r_y
                    [-r[2], 0.0, r[0]], // y: θ_z r_x − θ_x r_z
                    [r[1], -r[0], 0.0], // z: θ_x r_y − θ_y r_x
                ];
                for i in 0..3 {
                    let start = terms.len();
                    if let Some(q) = coupling_dofs[c][i] {
                        terms.push((q, 1.0));
                    }
                    for k in 0..3 {
                        if let Some(q) = coupling_dofs[c][3 + k] {
                            if rot[i][k] != 0.0 {
                                terms.push((q, rot[i][k]));
                            }
                        }
                    }
                    targets[3 * n + i] = DofTarget::Coupled {
                        start,
                        len: terms.len() - start,
                        offset: 0.0,
                    };
                }
            }
        }
        // equations: u_dep = Σ cᵢ uᵢ over independent DOFs, free ones as
        // terms, prescribed ones into the offset
        for (dep, flat) in &resolved {
            let start = terms.len();
            let mut offset = 0.0;
            for &(d, c) in flat {
                match targets[d] {
                    DofTarget::Free(r) => terms.push((r, c)),
                    DofTarget::Fixed(v) => offset += c * v,
                    // refused by resolve_equations (coupled nodes, nodes
                    // outside every element)
                    DofTarget::Coupled { .. } | DofTarget::Unused => {
                        return Err(FlankError::Model(format!(
                            "equation on node {}: its independent DOF {} of node {} is not a free or prescribed mesh DOF",
                            model.mesh.node_labels[dep / 3],
                            d % 3 + 1,
                            model.mesh.node_labels[d / 3]
                        )))
                    }
                }
            }
            targets[*dep] = DofTarget::Coupled {
                start,
                len: terms.len() - start,
                offset,
            };
        }
        Ok(DofMap {
            targets,
            terms,
            reduced_count: next,
            group_start,
            node_group,
            coupling_group,
            coupling_dofs,
            equation_of,
        })
    }

    /// Whether full DOF `d` is the dependent DOF of an equation.
    #[inline]
    pub fn is_dependent(&self, d: usize) -> bool {
        !self.equation_of.is_empty() && self.equation_of.contains_key(&d)
    }

    /// Renumbers the reduced DOFs so that groups come in the order `perm`
    /// (`perm[new] = old`), DOFs of a group staying consecutive.
    pub fn renumber_groups(&mut self, perm: &[usize]) {
        let ng = self.group_count();
        debug_assert_eq!(perm.len(), ng);
        let mut new_of_old_dof = vec![0usize; self.reduced_count];
        let mut group_start = Vec::with_capacity(ng + 1);
        let mut new_group = vec![0usize; ng];
        let mut next = 0;
        for (g_new, &g_old) in perm.iter().enumerate() {
            new_group[g_old] = g_new;
            group_start.push(next);
            for d in self.group_start[g_old]..self.group_start[g_old + 1] {
                new_of_old_dof[d] = next;
                next += 1;
            }
        }
        group_start.push(next);
        for t in self.targets.iter_mut() {
            if let DofTarget::Free(r) = t {
                *r = new_of_old_dof[*r];
            }
        }
        for term in self.terms.iter_mut() {
            term.0 = new_of_old_dof[term.0];
        }
        for cd in self.coupling_dofs.iter_mut() {
            for r in cd.iter_mut().flatten() {
                *r = new_of_old_dof[*r];
            }
        }
        for g in self
            .node_group
            .iter_mut()
            .chain(self.coupling_group.iter_mut())
        {
            if *g != usize::MAX {
                *g = new_group[*g];
            }
        }
        self.group_start = group_start;
    }

    pub fn group_count(&self) -> usize {
        self.group_start.len() - 1
    }

    /// Reduced DOFs of a group.
    pub fn group_dofs(&self, g: usize) -> std::ops::Range<usize> {
        self.group_start[g]..self.group_start[g + 1]
    }

    /// Calls `f(reduced index, coefficient)` for every term of full DOF `d`.
    #[inline]
    pub fn for_each_term(&self, d: usize, mut f: impl FnMut(usize, f64)) {
        match self.targets[d] {
            DofTarget::Free(r) => f(r, 1.0),
            DofTarget::Coupled { start, len, .. } => {
                for &(r, c) in &self.terms[start..start + len] {
                    f(r, c);
                }
            }
            DofTarget::Fixed(_) | DofTarget::Unused => {}
        }
    }

    /// Prescribed part u₀ of a full DOF: its value if fixed, the constant
    /// of a dependent DOF, 0 otherwise.
    #[inline]
    pub fn prescribed(&self, d: usize) -> f64 {
        match self.targets[d] {
            DofTarget::Fixed(v) => v,
            DofTarget::Coupled { offset, .. } => offset,
            _ => 0.0,
        }
    }

    /// Full displacement vector u = T q + u₀ from the reduced solution `q`.
    pub fn expand(&self, q: &[f64]) -> Vec<f64> {
        (0..self.targets.len())
            .map(|d| match self.targets[d] {
                DofTarget::Free(r) => q[r],
                DofTarget::Fixed(v) => v,
                DofTarget::Coupled { start, len, offset } => {
                    offset
                        + self.terms[start..start + len]
                            .iter()
                            .map(|&(r, c)| c * q[r])
                            .sum::<f64>()
                }
                DofTarget::Unused => 0.0,
            })
            .collect()
    }

    /// Reduced load Tᵀ f of a full load vector.
    pub fn restrict(&self, f: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; self.reduced_count];
        for (d, &v) in f.iter().enumerate() {
            if v != 0.0 {
                self.for_each_term(d, |r, c| out[r] += c * v);
            }
        }
        out
    }
}

/// Why an equation cannot be eliminated ([`resolve_equations`]).
#[derive(Clone, Debug, PartialEq)]
pub enum EquationFault {
    /// No term, an out-of-range node or DOF, a non-finite coefficient.
    Malformed(String),
    /// The dependent DOF's coefficient is zero (as given, or after adding
    /// the terms that repeat it).
    ZeroDependent,
    /// The dependent DOF is also prescribed (Dirichlet condition number
    /// `dirichlet`): ccx refuses it too.
    DependentFixed { dirichlet: usize },
    /// The dependent DOF is already the dependent DOF of equation `first`.
    DependentTwice { first: usize },
    /// The equations `chain` (this one first) depend on each other in a
    /// cycle.
    Cycle { chain: Vec<usize> },
    /// A term's node belongs to no element (it has no stiffness).
    OutsideElements { node: usize },
    /// A term's node is held by rigid coupling `coupling`.
    InCoupling { node: usize, coupling: usize },
}

/// An equation that cannot be eliminated: its index in `Model::equations`
/// and the reason.
#[derive(Clone, Debug, PartialEq)]
pub struct EquationError {
    pub equation: usize,
    pub fault: EquationFault,
}

impl EquationError {
    /// The reason in words; `name(k)` names equation k ("equation 3", "the
    /// equation at line 12").
    pub fn describe(&self, model: &Model, name: &dyn Fn(usize) -> String) -> String {
        let labels = &model.mesh.node_labels;
        let dof_name = |d: usize| {
            let node = labels.get(d / 3).copied().unwrap_or(0);
            format!("DOF {} of node {node}", d % 3 + 1)
        };
        let dependent = model.equations[self.equation]
            .terms
            .first()
            .map(|t| dof_name(3 * t.node + t.component))
            .unwrap_or_default();
        let this = name(self.equation);
        match &self.fault {
            EquationFault::Malformed(why) => format!("{this}: {why}"),
            EquationFault::ZeroDependent => format!(
                "{this}: the coefficient of its first term ({dependent}, the dependent DOF) is zero (after adding the terms that repeat that DOF); the first term must have a non-zero coefficient"
            ),
            EquationFault::DependentFixed { .. } => format!(
                "{this}: its dependent DOF ({dependent}, the first term) is also prescribed by a *BOUNDARY; a dependent DOF cannot be prescribed (ccx refuses it too): put another DOF first or drop the *BOUNDARY"
            ),
            EquationFault::DependentTwice { first } => format!(
                "{this}: its dependent DOF ({dependent}, the first term) is already the dependent DOF of {}; a DOF can be dependent in one equation only (ccx refuses it too): put another DOF first",
                name(*first)
            ),
            EquationFault::Cycle { chain } => {
                let path: Vec<String> = chain
                    .iter()
                    .chain(chain.first())
                    .map(|&e| {
                        let t = &model.equations[e].terms[0];
                        dof_name(3 * t.node + t.component)
                    })
                    .collect();
                format!(
                    "{this}: the equations form a cycle, each dependent DOF depending on the next: {} (through {}); flank does not solve cyclic equations: write them without the cycle",
                    path.join(" -> "),
                    chain.iter().map(|&e| name(e)).collect::<Vec<_>>().join(", ")
                )
            }
            EquationFault::OutsideElements { node } => format!(
                "{this}: node {} belongs to no element (it has no stiffness): not supported in an equation",
                labels[*node]
            ),
            EquationFault::InCoupling { node, coupling } => format!(
                "{this}: node {} is held by the rigid coupling '{}': an equation on a coupled node is not supported",
                labels[*node], model.couplings[*coupling].name
            ),
        }
    }
}

/// Resolves the model's equations (`*EQUATION`, ccx 2.20 manual): in each
/// equation Σ cᵢ uᵢ = 0 the first term's DOF is the dependent one,
/// u_dep = −Σ_{i≥2} (cᵢ/c₁) uᵢ (terms repeating a DOF add up, as in ccx).
/// An independent DOF that is itself dependent is replaced by its own
/// combination (chains, in a depth-first pass bounded by the number of
/// equations), so each result is over DOFs no equation makes dependent.
///
/// Returns per equation (dependent full DOF, [(independent full DOF,
/// coefficient)]). Refused: malformed terms, a zero dependent coefficient,
/// a dependent DOF that is prescribed or dependent twice, cycles (ccx
/// solves some cycles by substitution; flank refuses them all), nodes in no
/// element and nodes of rigid couplings.
#[allow(clippy::type_complexity)]
pub fn resolve_equations(model: &Model) -> Result<Vec<(usize, Vec<(usize, f64)>)>, EquationError> {
    let eqs = &model.equations;
    if eqs.is_empty() {
        return Ok(Vec::new());
    }
    let nn = model.mesh.node_count();
    let fail = |equation: usize, fault: EquationFault| Err(EquationError { equation, fault });
    let used = model.mesh.used_nodes();
    let mut coupling_of: HashMap<usize, usize> = HashMap::new();
    for (c, cp) in model.couplings.iter().enumerate() {
        for &n in &cp.nodes {
            coupling_of.insert(n, c);
        }
    }
    // merged terms (DOF, coefficient) per equation, the dependent first
    let mut merged: Vec<Vec<(usize, f64)>> = Vec::with_capacity(eqs.len());
    for (e, eq) in eqs.iter().enumerate() {
        if eq.terms.is_empty() {
            return fail(e, EquationFault::Malformed("it has no term".into()));
        }
        let mut terms: Vec<(usize, f64)> = Vec::with_capacity(eq.terms.len());
        for t in &eq.terms {
            if t.node >= nn || t.component > 2 {
                return fail(
                    e,
                    EquationFault::Malformed(format!(
                        "term on node index {} DOF {} is out of range (nodes 0..{nn}, DOFs 1-3)",
                        t.node,
                        t.component + 1
                    )),
                );
            }
            if !t.coefficient.is_finite() {
                return fail(
                    e,
                    EquationFault::Malformed(format!(
                        "the coefficient of node {} DOF {} is not finite",
                        model.mesh.node_labels[t.node],
                        t.component + 1
                    )),
                );
            }
            if !used[t.node] {
                return fail(e, EquationFault::OutsideElements { node: t.node });
            }
            if let Some(&c) = coupling_of.get(&t.node) {
                return fail(
                    e,
                    EquationFault::InCoupling {
                        node: t.node,
                        coupling: c,
                    },
                );
            }
            let d = 3 * t.node + t.component;
            match terms.iter_mut().find(|(k, _)| *k == d) {
                Some(slot) => slot.1 += t.coefficient,
                None => terms.push((d, t.coefficient)),
            }
        }
        if terms[0].1 == 0.0 {
            return fail(e, EquationFault::ZeroDependent);
        }
        merged.push(terms);
    }
    // dependent DOFs: once each, never prescribed
    let mut dep_of: HashMap<usize, usize> = HashMap::with_capacity(eqs.len());
    for (e, terms) in merged.iter().enumerate() {
        if let Some(first) = dep_of.insert(terms[0].0, e) {
            return fail(e, EquationFault::DependentTwice { first });
        }
    }
    for (k, bc) in model.dirichlet.iter().enumerate() {
        if let Some(&e) = dep_of.get(&(3 * bc.node + bc.component)) {
            return fail(e, EquationFault::DependentFixed { dirichlet: k });
        }
    }
    // depth-first elimination of dependent independents; state 0 new,
    // 1 on the stack, 2 resolved
    let mut state = vec![0u8; eqs.len()];
    let mut flat: Vec<Vec<(usize, f64)>> = vec![Vec::new(); eqs.len()];
    for root in 0..eqs.len() {
        if state[root] != 0 {
            continue;
        }
        // (equation, next term to look at)
        let mut stack: Vec<(usize, usize)> = vec![(root, 1)];
        state[root] = 1;
        while let Some(top) = stack.last_mut() {
            let (e, next) = *top;
            if let Some(&(d, _)) = merged[e].get(next) {
                top.1 += 1;
                if let Some(&f) = dep_of.get(&d) {
                    match state[f] {
                        0 => {
                            state[f] = 1;
                            stack.push((f, 1));
                        }
                        1 => {
                            let at = stack.iter().position(|&(g, _)| g == f).unwrap_or(0);
                            let chain = stack[at..].iter().map(|&(g, _)| g).collect();
                            return fail(f, EquationFault::Cycle { chain });
                        }
                        _ => {}
                    }
                }
                continue;
            }
            // all independents resolved: combine
            let c1 = merged[e][0].1;
            let mut out: Vec<(usize, f64)> = Vec::new();
            let mut add = |d: usize, c: f64| match out.iter_mut().find(|(k, _)| *k == d) {
                Some(slot) => slot.1 += c,
                None => out.push((d, c)),
            };
            for &(d, c) in &merged[e][1..] {
                let w = -c / c1;
                match dep_of.get(&d) {
                    Some(&f) => flat[f].iter().for_each(|&(g, cg)| add(g, w * cg)),
                    None => add(d, w),
                }
            }
            out.retain(|&(_, c)| c != 0.0);
            flat[e] = out;
            state[e] = 2;
            stack.pop();
        }
    }
    Ok(merged
        .iter()
        .zip(flat)
        .map(|(terms, f)| (terms[0].0, f))
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fem::model::{Dirichlet, Equation, EquationTerm};
    use crate::mesh::structured::{cantilever_model, BoxElement};

    fn eq(terms: &[(usize, usize, f64)]) -> Equation {
        Equation {
            terms: terms
                .iter()
                .map(|&(node, component, coefficient)| EquationTerm {
                    node,
                    component,
                    coefficient,
                })
                .collect(),
        }
    }

    /// A chain of 200 equations (each on the next) resolves to the last
    /// independent DOF, whatever the order; a prescribed independent DOF
    /// becomes the offset of the dependent one.
    #[test]
    fn chains_resolve_and_offsets_follow_prescribed_dofs() {
        let mut model = cantilever_model([8, 2, 2], BoxElement::Hex20, 1000.0).unwrap();
        let x0: Vec<usize> = (0..model.mesh.node_count())
            .filter(|&n| model.mesh.coords[n][0] > 5.0)
            .take(201)
            .collect();
        for w in x0.windows(2).rev() {
            model.equations.push(eq(&[(w[0], 1, 2.0), (w[1], 1, -1.0)]));
        }
        let r = resolve_equations(&model).unwrap();
        let first = r.iter().find(|(d, _)| *d == 3 * x0[0] + 1).unwrap();
        assert_eq!(first.1.len(), 1);
        assert_eq!(first.1[0].0, 3 * x0[200] + 1);
        assert!((first.1[0].1 - 0.5f64.powi(200)).abs() <= 1e-15 * 0.5f64.powi(200));
        model.dirichlet.push(Dirichlet {
            node: x0[200],
            component: 1,
            value: 0.25,
        });
        let dofs = DofMap::new(&model).unwrap();
        assert_eq!(dofs.prescribed(3 * x0[199] + 1), 0.125);
        let u = dofs.expand(&vec![0.0; dofs.reduced_count]);
        assert_eq!(u[3 * x0[198] + 1], 0.0625);
    }

    #[test]
    fn refusals() {
        let model = cantilever_model([4, 1, 1], BoxElement::Hex20, 1000.0).unwrap();
        let far: Vec<usize> = (0..model.mesh.node_count())
            .filter(|&n| model.mesh.coords[n][0] > 5.0)
            .collect();
        let (a, b, c) = (far[0], far[1], far[2]);
        let fault = |eqs: Vec<Equation>| {
            let mut m = model.clone();
            m.equations = eqs;
            resolve_equations(&m).unwrap_err()
        };
        let e = fault(vec![
            eq(&[(a, 0, 1.0), (b, 0, -1.0)]),
            eq(&[(b, 0, 1.0), (c, 0, -1.0)]),
            eq(&[(c, 0, 1.0), (a, 0, -2.0)]),
        ]);
        assert_eq!(
            e,
            EquationError {
                equation: 0,
                fault: EquationFault::Cycle {
                    chain: vec![0, 1, 2]
                }
            }
        );
        let e = fault(vec![
            eq(&[(a, 0, 1.0), (b, 0, -1.0)]),
            eq(&[(a, 0, 1.0), (c, 0, -1.0)]),
        ]);
        assert_eq!(e.fault, EquationFault::DependentTwice { first: 0 });
        assert_eq!(e.equation, 1);
        let e = fault(vec![eq(&[(a, 0, 0.0), (b, 0, -1.0)])]);
        assert_eq!(e.fault, EquationFault::ZeroDependent);
        let fixed = model.dirichlet[0].clone();
        let e = fault(vec![eq(&[(fixed.node, fixed.component, 1.0), (b, 0, 1.0)])]);
        assert_eq!(e.fault, EquationFault::DependentFixed { dirichlet: 0 });
        let e = fault(vec![eq(&[(a, 3, 1.0)])]);
        assert!(matches!(e.fault, EquationFault::Malformed(_)));
        let e = fault(vec![Equation { terms: Vec::new() }]);
        assert!(matches!(e.fault, EquationFault::Malformed(_)));
    }
}
