//! Global stiffness assembly: symbolic pass once, numeric passes cheap.
//!
//! The reduced stiffness Tᵀ K T is stored as the lower triangle of a CSC
//! matrix. The symbolic pass builds the graph of DOF groups (nodes and rigid
//! couplings), orders it (METIS or AMD, [`crate::fem::ordering`]), renumbers
//! the reduced DOFs in that elimination order, and computes the pattern, an
//! element→slot map, and a greedy colouring of
//! the elements so that elements of one colour share no node. The numeric pass
//! then integrates element matrices in parallel (rayon) colour by colour and adds
//! them into their slots without locks: within a colour the slots are disjoint.
//! Elements touching a rigid coupling or a dependent DOF of an equation
//! write into shared slots and are added serially afterwards; a node with a
//! dependent DOF joins the groups of its independent DOFs in the graph.

use rayon::prelude::*;

use crate::error::FlankError;
use crate::fem::constraints::{DofMap, DofTarget};
use crate::fem::element::edges;
use crate::fem::element::{stiffness, ElementWorkspace};
use crate::fem::model::Model;
use crate::fem::ordering::{
    order_groups_anchored, order_groups_last, order_groups_two_domain, DomainSplit, OrderingMethod,
    NO_ANCHOR,
};
// defined beside the orderings that consume it; re-exported at its old path
pub use crate::fem::ordering::GroupGraph;

/// Lower-triangular CSC pattern of a symmetric matrix.
#[derive(Clone, Debug)]
pub struct SparsePattern {
    pub n: usize,
    pub col_ptr: Vec<usize>,
    pub row_idx: Vec<usize>,
}

impl SparsePattern {
    pub fn nnz(&self) -> usize {
        self.row_idx.len()
    }

    /// Slot of entry (row, col) with row ≥ col, if present.
    #[inline]
    pub fn slot(&self, row: usize, col: usize) -> Option<usize> {
        let (a, b) = (self.col_ptr[col], self.col_ptr[col + 1]);
        self.row_idx[a..b].binary_search(&row).ok().map(|k| a + k)
    }

    /// y = A x for the symmetric matrix whose lower triangle is `values`.
    ///
    /// In rayon's pool the columns are split into blocks of about equal
    /// non-zeros, one per thread, each adding into its own vector (rows at
    /// or below its first column), summed at the end; the result differs
    /// from the serial product only by the summation order.
    pub fn sym_mul(&self, values: &[f64], x: &[f64]) -> Vec<f64> {
        let threads = rayon::current_num_threads();
        let nnz = self.nnz();
        if threads < 2 || nnz < SYM_MUL_PAR_MIN {
            let mut y = vec![0.0; self.n];
            self.sym_mul_columns(values, x, 0, self.n, &mut y);
            return y;
        }
        // column blocks of ≈ nnz / threads entries
        let mut bounds = vec![0usize];
        for t in 1..threads {
            let target = nnz * t / threads;
            let c = self.col_ptr.partition_point(|&p| p < target).min(self.n);
            if c > *bounds.last().unwrap_or(&0) {
                bounds.push(c);
            }
        }
        bounds.push(self.n);
        let parts: Vec<(usize, Vec<f64>)> = bounds
            .par_windows(2)
            .map(|w| {
                let mut y = vec![0.0; self.n - w[0]];
                self.sym_mul_columns(values, x, w[0], w[1], &mut y);
                (w[0], y)
            })
            .collect();
        let mut y = vec![0.0; self.n];
        y.par_chunks_mut(1 << 14).enumerate().for_each(|(i, out)| {
            let lo = i << 14;
            for (start, part) in &parts {
                let hi = lo + out.len();
                if hi <= *start {
                    continue;
                }
                let from = lo.max(*start);
                for (o, p) in out[from - lo..].iter_mut().zip(&part[from - start..]) {
                    *o += p;
                }
            }
        });
        y
    }

    /// Adds the product's terms of columns `c0..c1` into `y`, whose entry 0
    /// is row `c0` (rows above `c0` get nothing from these columns).
    fn sym_mul_columns(&self, values: &[f64], x: &[f64], c0: usize, c1: usize, y: &mut [f64]) {
        for c in c0..c1 {
            let mut yc = 0.0;
            let xc = x[c];
            for k in self.col_ptr[c]..self.col_ptr[c + 1] {
                let r = self.row_idx[k];
                let v = values[k];
                y[r - c0] += v * xc;
                if r != c {
                    yc += v * x[r];
                }
            }
            y[c - c0] += yc;
        }
    }
}

const NO_SLOT: u32 = u32::MAX;

/// Non-zeros below which [`SparsePattern::sym_mul`] stays serial.
const SYM_MUL_PAR_MIN: usize = 1 << 18;

/// The symbolic part of assembly: pattern, slots, colouring.
pub struct Assembly {
    pub pattern: SparsePattern,
    pub groups: GroupGraph,
    /// Element colour classes (fast-path elements only).
    pub colors: Vec<Vec<usize>>,
    /// Elements with coupled DOFs, assembled serially.
    pub serial: Vec<usize>,
    /// The ordering that numbered the reduced DOFs, and the time it took.
    pub ordering: OrderingMethod,
    /// The two-domain split of the numbering ([`Assembly::two_domain`]).
    pub split: Option<DomainSplit>,
    pub ordering_s: f64,
    slot_offset: Vec<usize>,
    slots: Vec<u32>,
}

/// Result of a numeric assembly pass.
pub struct AssembledSystem {
    /// Values of the lower triangle, aligned with [`Assembly::pattern`].
    pub values: Vec<f64>,
    /// −Tᵀ K u₀: the load from prescribed non-zero displacements.
    pub prescribed_load: Vec<f64>,
}

struct SharedMut(*mut f64);
unsafe impl Sync for SharedMut {}
unsafe impl Send for SharedMut {}
impl SharedMut {
    /// # Safety
    /// No other thread may write index `i` concurrently.
    #[inline]
    unsafe fn add(&self, i: usize, v: f64) {
        *self.0.add(i) += v;
    }
}

impl Assembly {
    /// Symbolic assembly for `model` with constraints `dofs`: orders the DOF
    /// groups with `ordering` and renumbers `dofs` in that order.
    pub fn new(
        model: &Model,
        dofs: &mut DofMap,
        ordering: OrderingMethod,
    ) -> Result<Self, FlankError> {
        Self::with_nodes_last(model, dofs, ordering, &[])
    }

    /// As [`Assembly::new`], with the free DOFs of `last_nodes` (node
    /// indices) numbered after all others, node by node in the order given:
    /// the trailing block of the Cholesky factor is then the factor of the
    /// Schur complement on those DOFs ([`crate::compliance`]).
    pub fn with_nodes_last(
        model: &Model,
        dofs: &mut DofMap,
        ordering: OrderingMethod,
        last_nodes: &[usize],
    ) -> Result<Self, FlankError> {
        Self::build(model, dofs, ordering, last_nodes, CORNER_GRAPH_MIN_GROUPS)
    }

    /// As [`Assembly::new`], numbering the reduced DOFs in the two-domain
    /// order \[A, S, B\] of [`crate::fem::substructuring`]: a vertex
    /// separator S splits the DOF groups into parts A and B with no
    /// stiffness between them, each part ordered by `ordering` on its own.
    /// Refused (before `dofs` is renumbered) when the separator leaves a part
    /// empty, does not separate, or has more than `max_separator_dofs` DOFs.
    pub fn two_domain(
        model: &Model,
        dofs: &mut DofMap,
        ordering: OrderingMethod,
        max_separator_dofs: usize,
    ) -> Result<Self, FlankError> {
        Self::build_with(
            model,
            dofs,
            ordering,
            &[],
            CORNER_GRAPH_MIN_GROUPS,
            Some(max_separator_dofs),
        )
    }

    /// The symbolic pass. With at least `corner_min_groups` DOF groups (and
    /// no `last_nodes`) METIS orders the graph of corner nodes and couplings
    /// and the midside nodes are placed after ([`order_groups_anchored`]);
    /// otherwise it orders the whole group graph (tests compare the two).
    pub(crate) fn build(
        model: &Model,
        dofs: &mut DofMap,
        ordering: OrderingMethod,
        last_nodes: &[usize],
        corner_min_groups: usize,
    ) -> Result<Self, FlankError> {
        Self::build_with(model, dofs, ordering, last_nodes, corner_min_groups, None)
    }

    fn build_with(
        model: &Model,
        dofs: &mut DofMap,
        ordering: OrderingMethod,
        last_nodes: &[usize],
        corner_min_groups: usize,
        two_domain: Option<usize>,
    ) -> Result<Self, FlankError> {
        let mesh = &model.mesh;
        let ne = mesh.elements.len();
        let nn = mesh.node_count();
        let ng = dofs.group_count();
        // groups touched by each node: its own group or its coupling's group
        let mut node_coupling = vec![usize::MAX; nn];
        for (c, cp) in model.couplings.iter().enumerate() {
            for &n in &cp.nodes {
                node_coupling[n] = c;
            }
        }
        let node_groups = |n: usize| -> Option<usize> {
            if dofs.node_group[n] != usize::MAX {
                Some(dofs.node_group[n])
            } else if node_coupling[n] != usize::MAX {
                let g = dofs.coupling_group[node_coupling[n]];
                (g != usize::MAX).then_some(g)
            } else {
                None
            }
        };
        // nodes with a dependent DOF (`*EQUATION`) also touch the groups of
        // its independent DOFs
        let equation_groups: std::collections::HashMap<usize, Vec<usize>> =
            if dofs.equation_of.is_empty() {
                Default::default()
            } else {
                let mut group_of = vec![0usize; dofs.reduced_count];
                for g in 0..ng {
                    dofs.group_dofs(g).for_each(|r| group_of[r] = g);
                }
                let mut map: std::collections::HashMap<usize, Vec<usize>> = Default::default();
                for &d in dofs.equation_of.keys() {
                    let list = map.entry(d / 3).or_default();
                    dofs.for_each_term(d, |r, _| list.push(group_of[r]));
                }
                map
            };
        let elem_groups: Vec<Vec<usize>> = mesh
            .elements
            .iter()
            .map(|el| {
                let mut g: Vec<usize> = el.nodes.iter().filter_map(|&n| node_groups(n)).collect();
                if !equation_groups.is_empty() {
                    for n in &el.nodes {
                        if let Some(extra) = equation_groups.get(n) {
                            g.extend_from_slice(extra);
                        }
                    }
                }
                g.sort_unstable();
                g.dedup();
                g
            })
            .collect();
        // group → elements
        let mut ge_ptr = vec![0usize; ng + 1];
        for gs in &elem_groups {
            for &g in gs {
                ge_ptr[g + 1] += 1;
            }
        }
        for g in 0..ng {
            ge_ptr[g + 1] += ge_ptr[g];
        }
        let mut ge = vec![0usize; ge_ptr[ng]];
        let mut fill = ge_ptr.clone();
        for (e, gs) in elem_groups.iter().enumerate() {
            for &g in gs {
                ge[fill[g]] = e;
                fill[g] += 1;
            }
        }
        // group adjacency (including self), sorted
        let neighbors: Vec<Vec<usize>> = (0..ng)
            .into_par_iter()
            .map_init(
                || (vec![usize::MAX; ng], Vec::new()),
                |(mark, list): &mut (Vec<usize>, Vec<usize>), g| {
                    list.clear();
                    for &e in &ge[ge_ptr[g]..ge_ptr[g + 1]] {
                        for &h in &elem_groups[e] {
                            if mark[h] != g {
                                mark[h] = g;
                                list.push(h);
                            }
                        }
                    }
                    list.sort_unstable();
                    list.clone()
                },
            )
            .collect();
        // group graph (no self loops), ordered; then renumber the reduced DOFs
        let mut xadj = vec![0usize];
        let mut adjncy = Vec::new();
        for (g, nb) in neighbors.iter().enumerate() {
            adjncy.extend(nb.iter().copied().filter(|&h| h != g));
            xadj.push(adjncy.len());
        }
        let weight: Vec<usize> = (0..ng).map(|g| dofs.group_dofs(g).len()).collect();
        let mut last_groups = Vec::with_capacity(last_nodes.len());
        for &n in last_nodes {
            match dofs.node_group.get(n) {
                Some(&g) if g != usize::MAX => last_groups.push(g),
                Some(_) => {}
                None => {
                    return Err(FlankError::Model(format!(
                        "node index {n} to be ordered last is beyond the mesh"
                    )))
                }
            }
        }
        let t = std::time::Instant::now();
        let graph = GroupGraph {
            xadj,
            adjncy,
            weight,
        };
        let mut group_split = None;
        let perm = if two_domain.is_some() {
            // the separator on the corner graph on large quadratic meshes
            let anchor = if ng >= corner_min_groups {
                midside_anchors(model, dofs, &node_groups)
            } else {
                vec![NO_ANCHOR; ng]
            };
            let (perm, counts) = order_groups_two_domain(&graph, ordering, &anchor)?;
            group_split = Some(counts);
            perm
        } else if ng >= corner_min_groups
            && last_groups.is_empty()
            && ordering == OrderingMethod::Metis
        {
            let anchor = midside_anchors(model, dofs, &node_groups);
            order_groups_anchored(&graph, ordering, &anchor)?
        } else {
            order_groups_last(&graph, ordering, &last_groups)?
        };
        let split = group_split.map(|[ga, gs, _]| {
            let dofs_of = |r: &[usize]| r.iter().map(|&g| graph.weight[g]).sum::<usize>();
            let a = dofs_of(&perm[..ga]);
            let s = dofs_of(&perm[ga..ga + gs]);
            DomainSplit {
                a,
                s,
                b: dofs.reduced_count - a - s,
            }
        });
        drop(graph);
        if let (Some(sp), Some(max)) = (&split, two_domain) {
            if sp.s > max {
                return Err(FlankError::Solver(format!(
                    "two-domain split: the separator has {} DOFs, more than {max}",
                    sp.s
                )));
            }
        }
        let ordering_s = t.elapsed().as_secs_f64();
        dofs.renumber_groups(&perm);
        let mut new_of_old = vec![0usize; ng];
        for (new, &old) in perm.iter().enumerate() {
            new_of_old[old] = new;
        }
        let neighbors: Vec<Vec<usize>> = perm
            .par_iter()
            .map(|&old| {
                let mut nb: Vec<usize> = neighbors[old].iter().map(|&h| new_of_old[h]).collect();
                nb.sort_unstable();
                nb
            })
            .collect();
        // CSC lower pattern in the new numbering
        let n = dofs.reduced_count;
        let mut col_ptr = Vec::with_capacity(n + 1);
        col_ptr.push(0usize);
        let mut row_idx = Vec::new();
        for g in 0..ng {
            for c in dofs.group_dofs(g) {
                for &h in &neighbors[g] {
                    if h < g {
                        continue;
                    }
                    for r in dofs.group_dofs(h) {
                        if r >= c {
                            row_idx.push(r);
                        }
                    }
                }
                col_ptr.push(row_idx.len());
            }
        }
        if row_idx.len() >= NO_SLOT as usize {
            return Err(FlankError::Solver(format!(
                "stiffness pattern has {} entries, beyond the 32-bit slot map",
                row_idx.len()
            )));
        }
        let pattern = SparsePattern {
            n,
            col_ptr,
            row_idx,
        };
        let mut xadj = vec![0usize];
        let mut adjncy = Vec::new();
        for (g, nb) in neighbors.iter().enumerate() {
            adjncy.extend(nb.iter().copied().filter(|&h| h != g));
            xadj.push(adjncy.len());
        }
        let weight = (0..ng).map(|g| dofs.group_dofs(g).len()).collect();
        let groups = GroupGraph {
            xadj,
            adjncy,
            weight,
        };
        let dofs: &DofMap = dofs;

        // element classification and slot map
        let is_serial: Vec<bool> = mesh
            .elements
            .iter()
            .map(|el| {
                el.nodes.iter().any(|&n| {
                    (0..3).any(|k| matches!(dofs.targets[3 * n + k], DofTarget::Coupled { .. }))
                })
            })
            .collect();
        let mut slot_offset = Vec::with_capacity(ne + 1);
        slot_offset.push(0usize);
        for (e, el) in mesh.elements.iter().enumerate() {
            let m = if is_serial[e] { 0 } else { 3 * el.nodes.len() };
            slot_offset.push(slot_offset[e] + m * (m + 1) / 2);
        }
        let mut slots = vec![NO_SLOT; slot_offset[ne]];
        {
            let mut chunks: Vec<&mut [u32]> = Vec::with_capacity(ne);
            let mut rest = slots.as_mut_slice();
            for e in 0..ne {
                let (a, b) = rest.split_at_mut(slot_offset[e + 1] - slot_offset[e]);
                chunks.push(a);
                rest = b;
            }
            chunks.into_par_iter().enumerate().for_each(|(e, out)| {
                if out.is_empty() {
                    return;
                }
                let el = &mesh.elements[e];
                let m = 3 * el.nodes.len();
                let red: Vec<Option<usize>> = (0..m)
                    .map(|p| match dofs.targets[3 * el.nodes[p / 3] + p % 3] {
                        DofTarget::Free(r) => Some(r),
                        _ => None,
                    })
                    .collect();
                let mut k = 0;
                for p in 0..m {
                    for q in 0..=p {
                        if let (Some(rp), Some(rq)) = (red[p], red[q]) {
                            let s = pattern
                                .slot(rp.max(rq), rp.min(rq))
                                .expect("pattern contains every element pair");
                            out[k] = s as u32;
                        }
                        k += 1;
                    }
                }
            });
        }
        // greedy colouring of the fast-path elements
        let mut ne_ptr = vec![0usize; nn + 1];
        for el in &mesh.elements {
            for &n in &el.nodes {
                ne_ptr[n + 1] += 1;
            }
        }
        for i in 0..nn {
            ne_ptr[i + 1] += ne_ptr[i];
        }
        let mut nel = vec![0usize; ne_ptr[nn]];
        let mut fill = ne_ptr.clone();
        for (e, el) in mesh.elements.iter().enumerate() {
            for &n in &el.nodes {
                nel[fill[n]] = e;
                fill[n] += 1;
            }
        }
        let mut color = vec![usize::MAX; ne];
        let mut forbidden_stamp: Vec<usize> = Vec::new();
        let mut colors: Vec<Vec<usize>> = Vec::new();
        let mut serial = Vec::new();
        for e in 0..ne {
            if is_serial[e] {
                serial.push(e);
                continue;
            }
            for &n in &mesh.elements[e].nodes {
                for &f in &nel[ne_ptr[n]..ne_ptr[n + 1]] {
                    let c = color[f];
                    if c != usize::MAX {
                        forbidden_stamp[c] = e;
                    }
                }
            }
            let c = (0..colors.len())
                .find(|&c| forbidden_stamp[c] != e)
                .unwrap_or_else(|| {
                    colors.push(Vec::new());
                    forbidden_stamp.push(usize::MAX);
                    colors.len() - 1
                });
            color[e] = c;
            colors[c].push(e);
        }
        Ok(Assembly {
            pattern,
            groups,
            colors,
            serial,
            ordering,
            split,
            ordering_s,
            slot_offset,
            slots,
        })
    }

    /// Numeric pass: integrates all element matrices and adds them into the
    /// pattern; also returns the load from prescribed displacements.
    pub fn assemble(&self, model: &Model, dofs: &DofMap) -> Result<AssembledSystem, FlankError> {
        let mesh = &model.mesh;
        let lame: Vec<(f64, f64)> = model.materials.iter().map(|m| m.lame()).collect();
        let mut values = vec![0.0; self.pattern.nnz()];
        let mut rhs = vec![0.0; dofs.reduced_count];
        let vals = SharedMut(values.as_mut_ptr());
        let rhs_ptr = SharedMut(rhs.as_mut_ptr());
        let integrate =
            |e: usize, ws: &mut ElementWorkspace, k: &mut Vec<f64>| -> Result<(), FlankError> {
                let el = &mesh.elements[e];
                ws.coords.clear();
                ws.coords.extend(el.nodes.iter().map(|&n| mesh.coords[n]));
                let (l, u) = lame[model.element_material[e]];
                let coords = std::mem::take(&mut ws.coords);
                let r = stiffness(el.kind, &coords, l, u, ws, k);
                ws.coords = coords;
                r.map_err(|j| j.into_error(el.label, el.kind))
            };
        for class in &self.colors {
            class.par_iter().try_for_each_init(
                || (ElementWorkspace::default(), Vec::new()),
                |(ws, k), &e| -> Result<(), FlankError> {
                    integrate(e, ws, k)?;
                    let el = &mesh.elements[e];
                    let m = 3 * el.nodes.len();
                    let slots = &self.slots[self.slot_offset[e]..self.slot_offset[e + 1]];
                    let mut s = 0;
                    for p in 0..m {
                        let row = &k[p * m..p * m + p + 1];
                        for &kv in row {
                            let slot = slots[s];
                            if slot != NO_SLOT {
                                // SAFETY: elements of one colour share no node, hence no slot.
                                unsafe { vals.add(slot as usize, kv) };
                            }
                            s += 1;
                        }
                    }
                    // load from prescribed displacements: f_r −= Σ_q K_pq u0_q
                    let dof = |p: usize| 3 * el.nodes[p / 3] + p % 3;
                    if (0..m).any(|q| dofs.prescribed(dof(q)) != 0.0) {
                        for p in 0..m {
                            if let DofTarget::Free(r) = dofs.targets[dof(p)] {
                                let f: f64 =
                                    (0..m).map(|q| k[p * m + q] * dofs.prescribed(dof(q))).sum();
                                // SAFETY: free DOFs belong to one node; nodes are exclusive within a colour.
                                unsafe { rhs_ptr.add(r, -f) };
                            }
                        }
                    }
                    Ok(())
                },
            )?;
        }
        // elements with coupled DOFs: general Tᵀ K T, serially
        let mut ws = ElementWorkspace::default();
        let mut k = Vec::new();
        for &e in &self.serial {
            integrate(e, &mut ws, &mut k)?;
            let el = &mesh.elements[e];
            let m = 3 * el.nodes.len();
            let dof = |p: usize| 3 * el.nodes[p / 3] + p % 3;
            for p in 0..m {
                for q in 0..m {
                    let kpq = k[p * m + q];
                    if kpq == 0.0 {
                        continue;
                    }
                    dofs.for_each_term(dof(p), |rp, cp| {
                        dofs.for_each_term(dof(q), |rq, cq| {
                            if rp >= rq {
                                let s = self.pattern.slot(rp, rq).expect("coupled pair in pattern");
                                values[s] += cp * cq * kpq;
                            }
                        });
                    });
                    let u0 = dofs.prescribed(dof(q));
                    if u0 != 0.0 {
                        dofs.for_each_term(dof(p), |rp, cp| rhs[rp] -= cp * kpq * u0);
                    }
                }
            }
        }
        Ok(AssembledSystem {
            values,
            prescribed_load: rhs,
        })
    }

    /// The pattern alone; the slot map and colouring are freed.
    pub fn into_pattern(self) -> SparsePattern {
        self.pattern
    }

    /// Bytes held by the symbolic structures (pattern and slot map).
    pub fn memory_bytes(&self) -> usize {
        self.pattern.row_idx.len() * 8
            + self.pattern.col_ptr.len() * 8
            + self.slots.len() * 4
            + self.slot_offset.len() * 8
    }
}

/// Group count from which METIS orders the corner-node graph: on the
/// 100×10×10 C3D20 cantilever (46 541 groups) that takes 0.16 s instead of
/// 0.8–1.3 s for +3.8 % nnz(L), +4.7 % flops (benches/README.md, issue 23
/// item 5); on small meshes the fill grows more (+12 % on 24×4×4) and the
/// whole graph takes milliseconds.
pub(crate) const CORNER_GRAPH_MIN_GROUPS: usize = 20_000;

/// For each DOF group, the groups of the two corner nodes of the edge whose
/// midside node it is ([`order_groups_anchored`]), or [`NO_ANCHOR`] for
/// corner nodes, couplings, groups in no element, and a midside node seen
/// with different edges or as a corner elsewhere (not a conforming mesh:
/// ordered itself, which is always correct).
fn midside_anchors(
    model: &Model,
    dofs: &DofMap,
    node_groups: &dyn Fn(usize) -> Option<usize>,
) -> Vec<[usize; 2]> {
    let ng = dofs.group_count();
    let mut anchor = vec![NO_ANCHOR; ng];
    let mut own = vec![false; ng]; // a corner, a coupling, or inconsistent
    for el in &model.mesh.elements {
        let e = edges(el.kind);
        let midside = |p: usize| e.iter().any(|ed| ed[2] == p);
        for (p, &n) in el.nodes.iter().enumerate() {
            if dofs.node_group[n] == usize::MAX || !midside(p) {
                if let Some(g) = node_groups(n) {
                    own[g] = true;
                }
            }
        }
        for &[a, b, m] in e {
            let g = dofs.node_group[el.nodes[m]];
            if g == usize::MAX || own[g] {
                continue;
            }
            let ga = node_groups(el.nodes[a]).unwrap_or(usize::MAX);
            let gb = node_groups(el.nodes[b]).unwrap_or(usize::MAX);
            let pair = [ga.min(gb), ga.max(gb)];
            if anchor[g] == NO_ANCHOR {
                anchor[g] = pair;
            } else if anchor[g] != pair {
                own[g] = true;
            }
        }
    }
    for g in 0..ng {
        if own[g] {
            anchor[g] = NO_ANCHOR;
        }
    }
    anchor
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::Rng;

    /// METIS on the corner graph with the midside nodes placed after gives
    /// about the fill of METIS on the whole node graph (hex20 and wedge15
    /// cantilevers), and the same solution.
    #[test]
    fn corner_graph_ordering_keeps_the_fill() {
        use crate::fem::solver::{parallelism, Precision, SparseCholesky};
        use crate::mesh::structured::{cantilever_model, BoxElement};
        for kind in [BoxElement::Hex20, BoxElement::Wedge15] {
            let cells = if kind == BoxElement::Hex20 {
                [40, 6, 6]
            } else {
                [24, 4, 4]
            };
            let model = cantilever_model(cells, kind, 1000.0).unwrap();
            let run = |corner_min_groups: usize| {
                let mut dofs = DofMap::new(&model).unwrap();
                let asm = Assembly::build(
                    &model,
                    &mut dofs,
                    OrderingMethod::Metis,
                    &[],
                    corner_min_groups,
                )
                .unwrap();
                let sys = asm.assemble(&model, &dofs).unwrap();
                let mut chol = SparseCholesky::analyze(
                    &asm.pattern,
                    OrderingMethod::Metis,
                    0.0,
                    parallelism(1),
                )
                .unwrap();
                chol.factorize(&asm.pattern, &sys.values, Precision::Double, &|r| {
                    r.to_string()
                })
                .unwrap();
                let f = crate::fem::loads::load_vector(&model).unwrap();
                let mut q = dofs.restrict(&f);
                chol.solve_in_place(&mut q);
                (chol.stats.nnz_factor, chol.stats.flops, dofs.expand(&q))
            };
            let (nnz_full, flops_full, u_full) = run(usize::MAX);
            let (nnz, flops, u) = run(0);
            println!(
                "{kind:?}: nnz(L) {:.3}, flops {:.3} of the whole graph's",
                nnz as f64 / nnz_full as f64,
                flops / flops_full
            );
            // a guard against misplaced midside nodes (which would fill in
            // whole separators), not the fill of large meshes (+4 %)
            assert!(
                (nnz as f64) <= 1.2 * nnz_full as f64 && flops <= 1.5 * flops_full,
                "{kind:?}: nnz(L) {nnz} vs {nnz_full}, flops {flops:.3e} vs {flops_full:.3e}"
            );
            let m = u_full.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            for (a, b) in u.iter().zip(&u_full) {
                assert!((a - b).abs() <= 1e-10 * m);
            }
        }
        // the hex20 midside nodes are anchored, the corners not
        let model = cantilever_model([3, 2, 2], BoxElement::Hex20, 1000.0).unwrap();
        let dofs = DofMap::new(&model).unwrap();
        let groups = |n: usize| (dofs.node_group[n] != usize::MAX).then_some(dofs.node_group[n]);
        let anchor = midside_anchors(&model, &dofs, &groups);
        let el = &model.mesh.elements[0];
        for (p, &n) in el.nodes.iter().enumerate() {
            if let Some(g) = groups(n) {
                assert_eq!(anchor[g] == NO_ANCHOR, p < 8, "position {p}");
            }
        }
    }

    /// The product split over threads equals the serial one to round-off
    /// (a random lower pattern large enough for the parallel path).
    #[test]
    fn sym_mul_in_parallel_matches_serial() {
        let mut rng = Rng::new(23);
        let n = 20_000;
        let mut col_ptr = vec![0usize];
        let mut row_idx = Vec::new();
        for c in 0..n {
            let mut rows: Vec<usize> = (0..16).map(|_| c + rng.below(n - c)).collect();
            rows.push(c);
            rows.sort_unstable();
            rows.dedup();
            row_idx.extend(rows);
            col_ptr.push(row_idx.len());
        }
        assert!(row_idx.len() >= SYM_MUL_PAR_MIN);
        let p = SparsePattern {
            n,
            col_ptr,
            row_idx,
        };
        let values: Vec<f64> = (0..p.nnz()).map(|_| rng.unit()).collect();
        let x: Vec<f64> = (0..n).map(|_| rng.unit()).collect();
        // reference: the plain definition, y_r += a_rc x_c and y_c += a_rc x_r
        let mut reference = vec![0.0; n];
        for c in 0..n {
            for k in p.col_ptr[c]..p.col_ptr[c + 1] {
                let r = p.row_idx[k];
                reference[r] += values[k] * x[c];
                if r != c {
                    reference[c] += values[k] * x[r];
                }
            }
        }
        let scale = reference.iter().fold(0.0f64, |a, b| a.max(b.abs()));
        for threads in [1, 2, 3] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let y = pool.install(|| p.sym_mul(&values, &x));
            let diff = y
                .iter()
                .zip(&reference)
                .fold(0.0f64, |a, (u, v)| a.max((u - v).abs()));
            assert!(diff <= 1e-13 * scale, "{threads} threads: {diff:.2e}");
        }
    }
}
