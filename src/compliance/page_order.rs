//! The paged node order of a compliance tensor: flank nodes by (set, u, v),
//! cut into pages of [`PAGE`] nodes. Shared by the dense tensor's pages
//! ([`crate::compliance::pages`]) and the block low-rank form, whose blocks
//! are the page pairs ([`crate::compliance::compressed`]).

use crate::compliance::ComplianceTensor;

/// Nodes per page.
pub const PAGE: usize = 64;

/// The paged position of each flank node: the inverse of [`paged_order`].
pub(crate) fn paged_positions(order: &[u32]) -> Vec<u32> {
    let mut position = vec![0u32; order.len()];
    for (p, &a) in order.iter().enumerate() {
        position[a as usize] = p as u32;
    }
    position
}

/// The flank nodes of `t` in the paged order: by (set, u, v), then node.
pub fn paged_order(t: &ComplianceTensor) -> Vec<u32> {
    let f = &t.flank;
    let mut order: Vec<u32> = (0..t.node_count() as u32).collect();
    order.sort_by(|&a, &b| {
        let (a, b) = (a as usize, b as usize);
        f.set_of[a]
            .cmp(&f.set_of[b])
            .then(f.uv[a][0].total_cmp(&f.uv[b][0]))
            .then(f.uv[a][1].total_cmp(&f.uv[b][1]))
            .then(a.cmp(&b))
    });
    order
}
