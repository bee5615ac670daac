//! Fill-reducing orderings of the reduced stiffness matrix.
//!
//! Both orderings run on the graph of DOF groups (nodes, coupling points),
//! about three times smaller than the DOF graph: METIS nested dissection
//! (`METIS_NodeND`, vendored C through `metis-sys`; the default, least fill on
//! 3D meshes) or faer's approximate minimum degree. On large quadratic meshes
//! METIS orders only the corner nodes and couplings and the midside nodes are
//! placed after ([`order_groups_anchored`]). The reduced DOFs are then
//! numbered in that order, so the assembled matrix is already permuted and the
//! factorization needs no permuted copy of it.

use crate::error::FlankError;

/// Graph of DOF groups in CSR form (no self loops), for the ordering.
#[derive(Clone, Debug)]
pub struct GroupGraph {
    pub xadj: Vec<usize>,
    pub adjncy: Vec<usize>,
    /// Number of reduced DOFs in each group (vertex weight).
    pub weight: Vec<usize>,
}

/// Which fill-reducing ordering the Cholesky factorization uses.
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    serde::Serialize,
    serde::Deserialize,
    clap::ValueEnum,
)]
#[serde(rename_all = "lowercase")]
pub enum OrderingMethod {
    /// METIS nested dissection on the node graph (default: least fill on 3D meshes).
    #[default]
    Metis,
    /// Approximate minimum degree on the DOF graph (faer).
    Amd,
}

impl OrderingMethod {
    pub fn name(self) -> &'static str {
        match self {
            OrderingMethod::Metis => "metis",
            OrderingMethod::Amd => "amd",
        }
    }
}

/// METIS keeps its random-number state in C statics (GKlib): two calls
/// at once race on it and the ordering then differs from run to run, so
/// every METIS call in flank holds this lock.
static METIS_LOCK: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// The group graph in METIS's 32-bit arrays: vertex count, xadj, adjncy
/// and vertex weights.
#[allow(clippy::type_complexity)]
fn metis_arrays(
    graph: &GroupGraph,
) -> Result<
    (
        metis_sys::idx_t,
        Vec<metis_sys::idx_t>,
        Vec<metis_sys::idx_t>,
        Vec<metis_sys::idx_t>,
    ),
    FlankError,
> {
    let to_idx = |v: usize| -> Result<metis_sys::idx_t, FlankError> {
        metis_sys::idx_t::try_from(v)
            .map_err(|_| FlankError::Solver(format!("graph too large for 32-bit METIS ({v})")))
    };
    let conv = |v: &[usize]| -> Result<Vec<metis_sys::idx_t>, FlankError> {
        v.iter().map(|&x| to_idx(x)).collect()
    };
    Ok((
        to_idx(graph.weight.len())?,
        conv(&graph.xadj)?,
        conv(&graph.adjncy)?,
        conv(&graph.weight)?,
    ))
}

/// METIS nested-dissection order of the groups: `perm[new] = old`.
pub fn metis_group_order(graph: &GroupGraph) -> Result<Vec<usize>, FlankError> {
    let n = graph.weight.len();
    if n == 0 {
        return Ok(Vec::new());
    }
    let (mut nvtxs, xadj, adjncy, vwgt) = metis_arrays(graph)?;
    let _metis = METIS_LOCK.lock().unwrap_or_else(|e| e.into_inner());
    let mut perm = vec![0 as metis_sys::idx_t; n];
    let mut iperm = vec![0 as metis_sys::idx_t; n];
    let mut options = [0 as metis_sys::idx_t; metis_sys::METIS_NOPTIONS as usize];
    // SAFETY: buffers have the sizes METIS documents (n+1, nnz, n, NOPTIONS).
    let status = unsafe {
        metis_sys::METIS_SetDefaultOptions(options.as_mut_ptr());
        metis_sys::METIS_NodeND(
            &mut nvtxs,
            xadj.as_ptr() as *mut _,
            adjncy.as_ptr() as *mut _,
            vwgt.as_ptr() as *mut _,
            options.as_mut_ptr(),
            perm.as_mut_ptr(),
            iperm.as_mut_ptr(),
        )
    };
    if status != metis_sys::rstatus_et_METIS_OK {
        return Err(FlankError::Solver(format!(
            "METIS_NodeND failed with status {status}"
        )));
    }
    Ok(perm.into_iter().map(|p| p as usize).collect())
}

/// METIS's vertex separator of the group graph (`METIS_ComputeVertexSeparator`,
/// the multilevel bisection behind `METIS_NodeND`'s top level): the part of
/// each group, 0 or 1, or 2 for the separator, no edge joining parts 0 and 1.
pub fn metis_vertex_separator(graph: &GroupGraph) -> Result<Vec<u8>, FlankError> {
    let n = graph.weight.len();
    if n == 0 {
        return Ok(Vec::new());
    }
    let (mut nvtxs, xadj, adjncy, vwgt) = metis_arrays(graph)?;
    let _metis = METIS_LOCK.lock().unwrap_or_else(|e| e.into_inner());
    let mut sepsize: metis_sys::idx_t = 0;
    let mut part = vec![0 as metis_sys::idx_t; n];
    let mut options = [0 as metis_sys::idx_t; metis_sys::METIS_NOPTIONS as usize];
    // SAFETY: buffers have the sizes METIS documents (n+1, nnz, n, NOPTIONS, n).
    let status = unsafe {
        metis_sys::METIS_SetDefaultOptions(options.as_mut_ptr());
        metis_sys::METIS_ComputeVertexSeparator(
            &mut nvtxs,
            xadj.as_ptr() as *mut _,
            adjncy.as_ptr() as *mut _,
            vwgt.as_ptr() as *mut _,
            options.as_mut_ptr(),
            &mut sepsize,
            part.as_mut_ptr(),
        )
    };
    if status != metis_sys::rstatus_et_METIS_OK {
        return Err(FlankError::Solver(format!(
            "METIS_ComputeVertexSeparator failed with status {status}"
        )));
    }
    part.into_iter()
        .map(|p| match p {
            0..=2 => Ok(p as u8),
            _ => Err(FlankError::Solver(format!(
                "METIS_ComputeVertexSeparator returned part {p}"
            ))),
        })
        .collect()
}

/// Approximate-minimum-degree order of the groups (faer's AMD on the group graph): `perm[new] = old`.
pub fn amd_group_order(graph: &GroupGraph) -> Result<Vec<usize>, FlankError> {
    use faer::dyn_stack::{MemBuffer, MemStack};
    use faer::sparse::linalg::amd;
    use faer::sparse::SymbolicSparseColMatRef;
    let n = graph.weight.len();
    if n == 0 {
        return Ok(Vec::new());
    }
    let a = SymbolicSparseColMatRef::new_checked(n, n, &graph.xadj, None, &graph.adjncy);
    let mut perm = vec![0usize; n];
    let mut inv = vec![0usize; n];
    let mut mem = MemBuffer::try_new(amd::order_scratch::<usize>(n, graph.adjncy.len()))
        .map_err(|_| FlankError::Solver("out of memory for the AMD ordering".into()))?;
    amd::order(
        &mut perm,
        &mut inv,
        a,
        amd::Control::default(),
        MemStack::new(&mut mem),
    )
    .map_err(|e| FlankError::Solver(format!("AMD ordering failed: {e:?}")))?;
    Ok(perm)
}

/// Fill-reducing order of the DOF groups by `method`: `perm[new] = old`.
pub fn order_groups(graph: &GroupGraph, method: OrderingMethod) -> Result<Vec<usize>, FlankError> {
    match method {
        OrderingMethod::Metis => metis_group_order(graph),
        OrderingMethod::Amd => amd_group_order(graph),
    }
}

/// No anchor: the group is ordered by itself (see [`order_groups_anchored`]).
pub const NO_ANCHOR: [usize; 2] = [usize::MAX; 2];

/// Fill-reducing order with the anchored groups left out of the graph and
/// placed afterwards: `perm[new] = old`.
///
/// `anchor[g]` names up to two groups whose graph neighbourhood contains
/// g's (for a midside node of a quadratic element: the two corner nodes of
/// its edge), or [`NO_ANCHOR`]. The unanchored groups are ordered on the
/// graph they induce (on a C3D20 mesh the corner nodes: ~¼ of the vertices,
/// ~⅕ of the edges, so METIS runs several times faster), each anchored group
/// carrying its weight to its first anchor; each anchored group is then put
/// just before the earlier of its anchors. Eliminating it there adds no
/// fill: the anchor's elimination joins a superset of its neighbours anyway
/// (George & Liu, *Computer Solution of Large Sparse Positive Definite
/// Systems*, 1981, §5.4 on indistinguishable and dominated nodes).
pub fn order_groups_anchored(
    graph: &GroupGraph,
    method: OrderingMethod,
    anchor: &[[usize; 2]],
) -> Result<Vec<usize>, FlankError> {
    let n = graph.weight.len();
    let (sub, old_of) = anchored_subgraph(graph, anchor)?;
    let is_free = |g: usize| anchor[g] == NO_ANCHOR;
    let sub_perm = order_groups(&sub, method)?;
    // position of each free group, then the anchored ones bucketed by the
    // position of their earlier anchor
    let mut pos = vec![usize::MAX; n];
    for (p, &s) in sub_perm.iter().enumerate() {
        pos[old_of[s]] = p;
    }
    let m = sub_perm.len();
    let key = |g: usize| {
        anchor[g]
            .iter()
            .filter(|&&h| h != usize::MAX)
            .map(|&h| pos[h])
            .min()
            .expect("anchors checked above")
    };
    let mut start = vec![0usize; m + 1];
    for g in (0..n).filter(|&g| !is_free(g)) {
        start[key(g) + 1] += 1;
    }
    for p in 0..m {
        start[p + 1] += start[p];
    }
    let mut bucket = vec![0usize; start[m]];
    let mut fill = start.clone();
    for g in (0..n).filter(|&g| !is_free(g)) {
        let k = key(g);
        bucket[fill[k]] = g;
        fill[k] += 1;
    }
    let mut perm = Vec::with_capacity(n);
    for (p, &s) in sub_perm.iter().enumerate() {
        perm.extend_from_slice(&bucket[start[p]..start[p + 1]]);
        perm.push(old_of[s]);
    }
    Ok(perm)
}

/// The graph the unanchored groups induce (renumbered 0..m; each anchored
/// group's weight carried by its first anchor) and the old index of each of
/// its vertices: the graph [`order_groups_anchored`] orders, checked.
fn anchored_subgraph(
    graph: &GroupGraph,
    anchor: &[[usize; 2]],
) -> Result<(GroupGraph, Vec<usize>), FlankError> {
    let n = graph.weight.len();
    if anchor.len() != n {
        return Err(FlankError::Solver(format!(
            "anchored ordering: {} anchors for {n} groups",
            anchor.len()
        )));
    }
    let is_free = |g: usize| anchor[g] == NO_ANCHOR;
    for (g, a) in anchor.iter().enumerate() {
        if !is_free(g)
            && a.iter()
                .any(|&h| h != usize::MAX && (h >= n || !is_free(h)))
        {
            return Err(FlankError::Solver(format!(
                "anchored ordering: group {g} is anchored to a group that is not ordered itself"
            )));
        }
    }
    let first = |g: usize| anchor[g].iter().copied().find(|&h| h != usize::MAX);
    let mut sub_of = vec![usize::MAX; n];
    let mut old_of = Vec::new();
    for g in 0..n {
        if is_free(g) {
            sub_of[g] = old_of.len();
            old_of.push(g);
        }
    }
    let mut weight: Vec<usize> = old_of.iter().map(|&g| graph.weight[g]).collect();
    for g in 0..n {
        if !is_free(g) {
            match first(g) {
                Some(h) => weight[sub_of[h]] += graph.weight[g],
                None => {
                    return Err(FlankError::Solver(format!(
                        "anchored ordering: group {g} has an empty anchor"
                    )))
                }
            }
        }
    }
    let mut xadj = Vec::with_capacity(old_of.len() + 1);
    xadj.push(0);
    let mut adjncy = Vec::new();
    for &g in &old_of {
        for &h in &graph.adjncy[graph.xadj[g]..graph.xadj[g + 1]] {
            if sub_of[h] != usize::MAX {
                adjncy.push(sub_of[h]);
            }
        }
        xadj.push(adjncy.len());
    }
    Ok((
        GroupGraph {
            xadj,
            adjncy,
            weight,
        },
        old_of,
    ))
}

/// Fill-reducing order of the DOF groups by `method` with the groups `last`
/// eliminated after all others, in the order given: `perm[new] = old`.
///
/// The other groups are ordered on the subgraph they induce, so the factor's
/// trailing block is the Cholesky factor of the Schur complement on `last`
/// (used by [`crate::compliance`]). An empty `last` is [`order_groups`].
pub fn order_groups_last(
    graph: &GroupGraph,
    method: OrderingMethod,
    last: &[usize],
) -> Result<Vec<usize>, FlankError> {
    if last.is_empty() {
        return order_groups(graph, method);
    }
    let n = graph.weight.len();
    let mut is_last = vec![false; n];
    for &g in last {
        if g >= n || is_last[g] {
            return Err(FlankError::Solver(format!(
                "constrained ordering: group {g} out of range or given twice"
            )));
        }
        is_last[g] = true;
    }
    // the subgraph induced by the other groups, renumbered 0..k
    let mut sub_of = vec![usize::MAX; n];
    let mut old_of = Vec::with_capacity(n - last.len());
    for g in 0..n {
        if !is_last[g] {
            sub_of[g] = old_of.len();
            old_of.push(g);
        }
    }
    let mut xadj = vec![0usize];
    let mut adjncy = Vec::new();
    let mut weight = Vec::with_capacity(old_of.len());
    for &g in &old_of {
        for &h in &graph.adjncy[graph.xadj[g]..graph.xadj[g + 1]] {
            if sub_of[h] != usize::MAX {
                adjncy.push(sub_of[h]);
            }
        }
        xadj.push(adjncy.len());
        weight.push(graph.weight[g]);
    }
    let sub = GroupGraph {
        xadj,
        adjncy,
        weight,
    };
    let mut perm: Vec<usize> = order_groups(&sub, method)?
        .into_iter()
        .map(|s| old_of[s])
        .collect();
    perm.extend_from_slice(last);
    Ok(perm)
}

/// Expands a group order to a DOF permutation (`fwd[new] = old`, `inv[old] = new`).
pub fn expand_group_order(group_perm: &[usize], group_start: &[usize]) -> (Vec<usize>, Vec<usize>) {
    let n = *group_start.last().unwrap_or(&0);
    let mut fwd = Vec::with_capacity(n);
    for &g in group_perm {
        fwd.extend(group_start[g]..group_start[g + 1]);
    }
    let mut inv = vec![0; n];
    for (new, &old) in fwd.iter().enumerate() {
        inv[old] = new;
    }
    (fwd, inv)
}

/// DOF counts of the two-domain numbering \[A, S, B\].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct DomainSplit {
    pub a: usize,
    pub s: usize,
    pub b: usize,
}

/// The two-domain order of the DOF groups: `perm[new] = old` with the
/// groups of part A first, then the separator S, then part B, and the group
/// counts of the three.
///
/// The separator is METIS's vertex separator of the graph of unanchored
/// groups (`anchor`, as in [`order_groups_anchored`]: on a quadratic mesh
/// the corner nodes, each carrying its midside nodes' weight). An anchored
/// group joins the part of an anchor (its neighbourhood lies inside each
/// anchor's, so it cannot touch the other part), or S if its anchors are in
/// S. Each part is then ordered on its own by `method` (anchored the same
/// way). Refused if a part is empty or an edge of
/// `graph` joins A and B.
pub fn order_groups_two_domain(
    graph: &GroupGraph,
    method: OrderingMethod,
    anchor: &[[usize; 2]],
) -> Result<(Vec<usize>, [usize; 3]), FlankError> {
    let n = graph.weight.len();
    let (sub, old_of) = anchored_subgraph(graph, anchor)?;
    let sub_part = metis_vertex_separator(&sub)?;
    let mut part = vec![2u8; n];
    for (i, &g) in old_of.iter().enumerate() {
        part[g] = sub_part[i];
    }
    for g in 0..n {
        if anchor[g] != NO_ANCHOR {
            let sides = anchor[g]
                .iter()
                .filter(|&&h| h != usize::MAX)
                .map(|&h| part[h]);
            let (mut in_a, mut in_b) = (false, false);
            for p in sides {
                in_a |= p == 0;
                in_b |= p == 1;
            }
            part[g] = match (in_a, in_b) {
                (true, false) => 0,
                (false, true) => 1,
                _ => 2,
            };
        }
    }
    for g in 0..n {
        if part[g] == 2 {
            continue;
        }
        if let Some(&h) = graph.adjncy[graph.xadj[g]..graph.xadj[g + 1]]
            .iter()
            .find(|&&h| part[h] != 2 && part[h] != part[g])
        {
            return Err(FlankError::Solver(format!(
                "two-domain split: groups {g} and {h} on opposite sides are coupled"
            )));
        }
    }
    let members = |p: u8| -> Vec<usize> { (0..n).filter(|&g| part[g] == p).collect() };
    let (a, s, b) = (members(0), members(2), members(1));
    if a.is_empty() || b.is_empty() {
        return Err(FlankError::Solver(format!(
            "two-domain split: the separator leaves a part empty ({} / {} / {} groups)",
            a.len(),
            s.len(),
            b.len()
        )));
    }
    let order_part = |groups: &[usize]| -> Result<Vec<usize>, FlankError> {
        let mut local = vec![usize::MAX; n];
        for (i, &g) in groups.iter().enumerate() {
            local[g] = i;
        }
        let mut xadj = vec![0usize];
        let mut adjncy = Vec::new();
        let mut anchors = Vec::with_capacity(groups.len());
        for &g in groups {
            adjncy.extend(
                graph.adjncy[graph.xadj[g]..graph.xadj[g + 1]]
                    .iter()
                    .filter(|&&h| local[h] != usize::MAX)
                    .map(|&h| local[h]),
            );
            xadj.push(adjncy.len());
            // anchors in this part (at least one if anchored, see above)
            let mut a = NO_ANCHOR;
            let mut k = 0;
            for &h in &anchor[g] {
                if h != usize::MAX && local[h] != usize::MAX {
                    a[k] = local[h];
                    k += 1;
                }
            }
            anchors.push(a);
        }
        let weight = groups.iter().map(|&g| graph.weight[g]).collect();
        let sub = GroupGraph {
            xadj,
            adjncy,
            weight,
        };
        let perm = if anchors.iter().any(|a| *a != NO_ANCHOR) {
            order_groups_anchored(&sub, method, &anchors)?
        } else {
            order_groups(&sub, method)?
        };
        Ok(perm.into_iter().map(|i| groups[i]).collect())
    };
    // one after the other: METIS's random generator (GKlib) is a C static,
    // and `ordering` serializes every METIS call on it anyway
    let mut perm = order_part(&a)?;
    perm.extend_from_slice(&s);
    perm.extend(order_part(&b)?);
    Ok((perm, [a.len(), s.len(), b.len()]))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A chain of quadratic bars 0–1–2–…: the even (corner) groups are
    /// ordered, each odd (midside) group lands just before the earlier of its
    /// two corners, and the result is a permutation.
    #[test]
    fn anchored_groups_precede_their_earlier_anchor() {
        let n: usize = 41;
        let mut xadj = vec![0];
        let mut adjncy = Vec::new();
        for g in 0..n {
            // a corner sees the two bars it ends, a midside its own bar
            let (lo, hi) = if g % 2 == 0 {
                (g.saturating_sub(2), (g + 2).min(n - 1))
            } else {
                (g - 1, g + 1)
            };
            adjncy.extend((lo..=hi).filter(|&h| h != g));
            xadj.push(adjncy.len());
        }
        let graph = GroupGraph {
            xadj,
            adjncy,
            weight: vec![3; n],
        };
        let anchor: Vec<[usize; 2]> = (0..n)
            .map(|g| {
                if g % 2 == 0 {
                    NO_ANCHOR
                } else {
                    [g - 1, g + 1]
                }
            })
            .collect();
        for method in [OrderingMethod::Metis, OrderingMethod::Amd] {
            let perm = order_groups_anchored(&graph, method, &anchor).unwrap();
            let mut seen = vec![false; n];
            let mut pos = vec![0; n];
            for (p, &g) in perm.iter().enumerate() {
                assert!(!seen[g]);
                seen[g] = true;
                pos[g] = p;
            }
            assert!(seen.iter().all(|&s| s));
            for g in (1..n).step_by(2) {
                let (a, b) = (pos[g - 1], pos[g + 1]);
                assert!(pos[g] < a.min(b), "{method:?}: midside {g} after a corner");
                // nothing but other midsides between it and that corner
                assert!(perm[pos[g]..a.min(b)].iter().all(|&h| h % 2 == 1));
            }
        }
        // anchors must be groups ordered themselves
        let mut bad = anchor.clone();
        bad[1] = [3, 3];
        assert!(order_groups_anchored(&graph, OrderingMethod::Metis, &bad).is_err());
        assert!(order_groups_anchored(&graph, OrderingMethod::Metis, &anchor[1..]).is_err());
    }
}
