//! The compliance tensor's 3 × 3 node blocks in pages, for building many
//! small compliance matrices from it (the LTCA's F at every roll position).
//!
//! The tensor is stored row by row in the flank node order of
//! [`crate::compliance::FlankNodes`] (set, v, u): the nodes of a contact
//! cell, close in (u, v), lie far apart in a row, so reading C between the
//! cells of one position costs a cache miss per three values. Here the
//! flank nodes are renumbered by (set, u, v) (a spur contact line, along v
//! at nearly constant u, becomes a run of consecutive nodes) and cut into
//! pages of [`PAGE`] nodes ([`crate::compliance::page_order`]); the blocks
//! between two pages are copied, once, on first use, into one contiguous
//! array, node block by node block.
//! Nothing is approximated: a page holds the tensor's own values.
//! A compressed tensor's low-rank page pairs are also offered as their
//! factors ([`FactoredPage`]), which the F kernel multiplies without
//! forming the pair's node blocks.
//!
//! Memory: a page pair is [`PAGE`]² × 9 × 8 B = 295 kB; only the pairs a
//! computation asked for are built (an LTCA cycle: the pages of the active
//! flanks and of neighbouring teeth). [`TensorPages::bytes`] says how much.
//! The pages belong to one tensor: [`TensorPages::matches`] checks its
//! dimension, cache key and storage address before use.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::OnceLock;

use crate::compliance::compressed::SharedBlr;
use crate::compliance::page_order::{paged_order, paged_positions, PAGE};
use crate::compliance::ComplianceTensor;
use crate::error::FlankError;

/// Paged node blocks of one compliance tensor (built lazily), copied from
/// its dense matrix or decompressed from its block low-rank form
/// ([`crate::compliance::compressed`], [`TensorPages::compressed`]).
pub struct TensorPages {
    dim: usize,
    cache_key: String,
    address: usize,
    /// Flank node at each position, and the position of each flank node.
    order: Vec<u32>,
    position: Vec<u32>,
    pages: usize,
    blocks: Vec<OnceLock<Box<[f64]>>>,
    built: AtomicUsize,
    /// Low-rank page pairs in the F kernel's layout ([`FactoredPage`]),
    /// built on first use; their bytes.
    factored: Vec<OnceLock<Option<FactoredPage>>>,
    factored_bytes: AtomicUsize,
    /// The compressed tensor the pages are read from (else the dense matrix).
    source: Option<SharedBlr>,
}

impl TensorPages {
    /// The page layout of `t` (no block is copied yet).
    pub fn new(t: &ComplianceTensor) -> Self {
        let n = t.node_count();
        let order = paged_order(t);
        let position = paged_positions(&order);
        let pages = n.div_ceil(PAGE);
        TensorPages {
            dim: t.dim(),
            cache_key: t.meta.cache_key.clone(),
            address: t.matrix.as_ptr() as usize,
            order,
            position,
            pages,
            blocks: (0..pages * pages).map(|_| OnceLock::new()).collect(),
            built: AtomicUsize::new(0),
            factored: (0..pages * (pages + 1) / 2)
                .map(|_| OnceLock::new())
                .collect(),
            factored_bytes: AtomicUsize::new(0),
            source: None,
        }
    }

    /// The page layout of `t` with the page pairs decompressed from `blr`,
    /// the block low-rank form of `t` (an error if it is not: another
    /// cache key, dimension or node order).
    pub fn compressed(t: &ComplianceTensor, blr: SharedBlr) -> Result<Self, FlankError> {
        if !blr.matches(t) {
            return Err(FlankError::Model(format!(
                "compressed compliance (key {}, dimension {}) is not the one of tensor {} (key {}, dimension {})",
                blr.cache_key(),
                blr.dim(),
                t.meta.body,
                t.meta.cache_key,
                t.dim()
            )));
        }
        let mut p = TensorPages::new(t);
        p.source = Some(blr);
        Ok(p)
    }

    /// Whether the pages are read from a compressed tensor.
    pub fn is_compressed(&self) -> bool {
        self.source.is_some()
    }

    /// Whether these are the pages of `t`: same dimension and cache key,
    /// and for pages copied from the dense matrix the same matrix storage
    /// (compressed pages never read `t`'s matrix, which a tensor built
    /// compressed does not hold).
    pub fn matches(&self, t: &ComplianceTensor) -> bool {
        if self.dim != t.dim() || self.cache_key != t.meta.cache_key {
            return false;
        }
        self.source.is_some()
            || (t.matrix.len() == self.dim * self.dim && self.address == t.matrix.as_ptr() as usize)
    }

    /// Position of flank node `a` in the paged order.
    pub fn position(&self, a: u32) -> usize {
        self.position[a as usize] as usize
    }

    /// Bytes of the page pairs built so far (dense and factored).
    pub fn bytes(&self) -> usize {
        self.built.load(Ordering::Relaxed) * PAGE * PAGE * 9 * std::mem::size_of::<f64>()
            + self.factored_bytes.load(Ordering::Relaxed)
    }

    /// Bytes of the factored page pairs built so far (part of [`Self::bytes`]).
    pub fn factored_bytes(&self) -> usize {
        self.factored_bytes.load(Ordering::Relaxed)
    }

    /// The page pair (r, q), r > q, as its low-rank factors when the
    /// pages are read from a compressed tensor that stores this pair in
    /// low rank (None for a dense tensor, a dense block, or r ≤ q). Built
    /// on first use, in the layout of [`FactoredPage`].
    pub fn factored(&self, r: usize, q: usize) -> Option<&FactoredPage> {
        if r <= q || r >= self.pages {
            return None;
        }
        let blr = self.source.as_ref()?;
        self.factored[r * (r + 1) / 2 + q]
            .get_or_init(|| {
                let f = FactoredPage::of(blr.block(r, q))?;
                self.factored_bytes.fetch_add(
                    (f.u.len() + f.v.len()) * std::mem::size_of::<f64>(),
                    Ordering::Relaxed,
                );
                Some(f)
            })
            .as_ref()
    }

    /// The blocks between row page `r` and column page `q` of `t` (which
    /// must [`Self::matches`]): for the column node c at position
    /// q·PAGE + ic and the row node a at r·PAGE + ia, entry
    /// (ic·PAGE + ia)·9 + 3s + τ is C(3a + s, 3c + τ) (zero past the last
    /// node).
    pub fn page(&self, t: &ComplianceTensor, r: usize, q: usize) -> &[f64] {
        debug_assert!(self.matches(t));
        self.blocks[r * self.pages + q].get_or_init(|| {
            let mut out = vec![0.0; PAGE * PAGE * 9].into_boxed_slice();
            if let Some(blr) = &self.source {
                blr.page_into(r, q, &mut out);
                self.built.fetch_add(1, Ordering::Relaxed);
                return out;
            }
            let dim = self.dim;
            let rows = &self.order[(r * PAGE).min(self.order.len())..]
                [..PAGE.min(self.order.len().saturating_sub(r * PAGE))];
            let cols = &self.order[(q * PAGE).min(self.order.len())..]
                [..PAGE.min(self.order.len().saturating_sub(q * PAGE))];
            for (ic, &c) in cols.iter().enumerate() {
                for tau in 0..3 {
                    // row 3c + τ holds column 3c + τ (C is symmetric)
                    let row = &t.matrix[(3 * c as usize + tau) * dim..][..dim];
                    for (ia, &a) in rows.iter().enumerate() {
                        let x = &row[3 * a as usize..3 * a as usize + 3];
                        let o = &mut out[(ic * PAGE + ia) * 9..][..9];
                        o[tau] = x[0];
                        o[3 + tau] = x[1];
                        o[6 + tau] = x[2];
                    }
                }
            }
            self.built.fetch_add(1, Ordering::Relaxed);
            out
        })
    }
}

/// A page pair B(r, q) = U Vᵀ (rank k, r > q) of a compressed tensor
/// ([`crate::compliance::compressed::Block::LowRank`]) laid out for the
/// LTCA's F: with a the row node at slot ia and c the column node at slot
/// ic, `u[(3 ia + s) k + l]` = U(3a + s, l) and `v[(3 ic + τ) k + l]` =
/// V(3c + τ, l): the k values a node component multiplies are contiguous,
/// so B q = U (Vᵀ q) over a few nodes reads 2 · 3 · k values per node
/// instead of a node's 3 × 3 blocks with every node of the other page
/// (zero past the last node of a page). The values are the compressed
/// tensor's own, only moved.
pub struct FactoredPage {
    pub rank: usize,
    pub u: Box<[f64]>,
    pub v: Box<[f64]>,
}

impl FactoredPage {
    /// The factors of a low-rank block (None for a dense one).
    fn of(block: &crate::compliance::compressed::Block) -> Option<FactoredPage> {
        let crate::compliance::compressed::Block::LowRank { rank, u, v } = block else {
            return None;
        };
        let k = *rank;
        let node_major = |f: &[f64]| -> Box<[f64]> {
            // column-major (len × k) → row-major, zero-padded to 3 · PAGE rows
            let len = f.len() / k.max(1);
            let mut out = vec![0.0; 3 * PAGE * k].into_boxed_slice();
            for l in 0..k {
                for i in 0..len {
                    out[i * k + l] = f[l * len + i];
                }
            }
            out
        };
        Some(FactoredPage {
            rank: k,
            u: node_major(u),
            v: node_major(v),
        })
    }
}
