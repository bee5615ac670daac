//! The supernodal elimination tree of a sparse Cholesky factor: the parent
//! of each supernode and the supernode of each row, read from faer's
//! symbolic factor. The restricted solves of [`super::SolveReach`] walk it.

use faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky;

/// "No index" in the reach's tables.
pub(super) const NONE: usize = usize::MAX;

/// The supernodal elimination tree: parent of each supernode (the supernode
/// of the first off-diagonal row of its columns, [`NONE`] for a root) and
/// the supernode of each row.
pub(super) struct SupernodeTree {
    pub(super) parent: Vec<usize>,
    pub(super) of_row: Vec<usize>,
}

impl SupernodeTree {
    pub(super) fn new(s: &SymbolicSupernodalCholesky<usize>) -> Self {
        let (beg, end) = (s.supernode_begin(), s.supernode_end());
        let mut of_row = vec![NONE; s.nrows()];
        for k in 0..s.n_supernodes() {
            of_row[beg[k]..end[k]].fill(k);
        }
        let rptr = s.col_ptr_for_row_idx();
        let ridx = s.row_idx();
        let parent = (0..s.n_supernodes())
            .map(|k| {
                ridx[rptr[k]..rptr[k + 1]]
                    .iter()
                    .min()
                    .map_or(NONE, |&r| of_row[r])
            })
            .collect();
        SupernodeTree { parent, of_row }
    }
}
