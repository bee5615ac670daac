//! Constraints as a map from full DOFs to the reduced (free) unknowns.
//!
//! Every full DOF u_d is either a free unknown, a prescribed value (Dirichlet,
//! eliminated), or a linear combination of the free DOFs of a rigid coupling's
//! reference point: u = Tq + u₀. The reduced stiffness is Tᵀ K T, which stays
//! symmetric positive definite when the rigid-body modes are constrained.
//!
//! Reduced unknowns are grouped: one group per node with free DOFs (in node
//! order), then one group per rigid coupling. Groups are the vertices of the
//! graph used for the fill-reducing ordering.

use crate::error::FlankError;
use crate::fem::model::Model;

/// Where a full DOF goes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DofTarget {
    /// A free unknown with this reduced index.
    Free(usize),
    /// A prescribed value (Dirichlet).
    Fixed(f64),
    /// A combination of reduced unknowns: `terms[start..start+len]` of [`DofMap`].
    Coupled { start: usize, len: usize },
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
                    };
                }
            }
        }
        Ok(DofMap {
            targets,
            terms,
            reduced_count: next,
            group_start,
            node_group,
            coupling_group,
            coupling_dofs,
        })
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
            DofTarget::Coupled { start, len } => {
                for &(r, c) in &self.terms[start..start + len] {
                    f(r, c);
                }
            }
            DofTarget::Fixed(_) | DofTarget::Unused => {}
        }
    }

    /// Prescribed value of a full DOF (0 for non-fixed DOFs).
    #[inline]
    pub fn prescribed(&self, d: usize) -> f64 {
        match self.targets[d] {
            DofTarget::Fixed(v) => v,
            _ => 0.0,
        }
    }

    /// Full displacement vector u = T q + u₀ from the reduced solution `q`.
    pub fn expand(&self, q: &[f64]) -> Vec<f64> {
        (0..self.targets.len())
            .map(|d| match self.targets[d] {
                DofTarget::Free(r) => q[r],
                DofTarget::Fixed(v) => v,
                DofTarget::Coupled { start, len } => self.terms[start..start + len]
                    .iter()
                    .map(|&(r, c)| c * q[r])
                    .sum(),
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
