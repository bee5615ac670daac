//! The cells of a block's station section, the same on every station:
//! quadrilaterals (hex20), or for wedges (C3D15) triangles, the upper
//! block's coarsened 2:1 along the profile as the cylindrical mesher's
//! ([`crate::mesh::section_cells`]); the extra midside points of wedge
//! cells (straight midpoints of edges spanning several rows, centres of
//! split quadrilaterals) as combinations of the lattice points, so that
//! every station places them from its own lattice.

use std::collections::HashMap;

use super::section::SectionPoint;
use crate::mesh::section_cells::{edge_mid, split_quad, LatticeCell, Lp, Mid};

/// A section cell in point indices (lattice point ii·h + jj, extra point
/// w·h + e): a quadrilateral (hex20) or a triangle (wedge15), corners and
/// midsides in the order of the element's bottom face.
#[derive(Clone, Debug)]
pub(super) enum Shape {
    Quad([usize; 4], [usize; 4]),
    Tri([usize; 3], [usize; 3]),
}

/// The cells of one block ((2·ni + 1) × (2·nj + 1) lattice).
#[derive(Clone, Debug)]
pub(super) struct BlockCells {
    pub(super) width: usize,
    pub(super) height: usize,
    /// Extra point w·h + e: weights of earlier points.
    pub(super) extra: Vec<Vec<(usize, f64)>>,
    /// (column, row) of the lattice cell, and one of its shapes.
    pub(super) cells: Vec<((usize, usize), Shape)>,
}

impl BlockCells {
    pub(super) fn len(&self) -> usize {
        self.width * self.height + self.extra.len()
    }

    /// The lattice index (ii, jj) of point `p`, None for extra points.
    pub(super) fn lattice_index(&self, p: usize) -> Option<(usize, usize)> {
        (p < self.width * self.height).then(|| (p / self.height, p % self.height))
    }

    /// Role of every point: 0 unused, 1 corner, 2 midside (of the section).
    pub(super) fn roles(&self) -> Vec<u8> {
        let mut role = vec![0u8; self.len()];
        for (_, shape) in &self.cells {
            let (c, m): (&[usize], &[usize]) = match shape {
                Shape::Quad(c, m) => (c, m),
                Shape::Tri(c, m) => (c, m),
            };
            c.iter().for_each(|&p| role[p] = 1);
            m.iter().for_each(|&p| role[p] = 2);
        }
        role
    }

    /// The points of one station: its lattice (index ii·h + jj), then the
    /// extra points (off the flanks).
    pub(super) fn points(&self, lattice: &[SectionPoint]) -> Vec<SectionPoint> {
        let mut out = lattice.to_vec();
        for w in &self.extra {
            let (mut theta, mut u) = (0.0, 0.0);
            for &(p, f) in w {
                theta += f * out[p].theta;
                u += f * out[p].u;
            }
            out.push(SectionPoint {
                theta,
                u,
                flank: None,
            });
        }
        out
    }

    /// The cells whose corners all lie on rows ≤ `row` (the shank's part
    /// of the rim).
    pub(super) fn below(&self, row: usize) -> BlockCells {
        let on = |p: usize| self.lattice_index(p).is_some_and(|(_, kk)| kk <= row);
        let cells = self
            .cells
            .iter()
            .filter(|(_, s)| match s {
                Shape::Quad(c, _) => c.iter().all(|&p| on(p)),
                Shape::Tri(c, _) => c.iter().all(|&p| on(p)),
            })
            .cloned()
            .collect();
        BlockCells {
            cells,
            ..self.clone()
        }
    }
}

/// Every cell of an ni × nj block, one row high.
pub(super) fn grid_layout(ni: usize, nj: usize) -> Vec<(usize, usize, LatticeCell)> {
    let mut out = Vec::with_capacity(ni * nj);
    for i in 0..ni {
        for j in 0..nj {
            let (i0, j0) = (2 * i, 2 * j);
            let c = [(i0, j0), (i0 + 2, j0), (i0 + 2, j0 + 2), (i0, j0 + 2)];
            let m = [0, 1, 2, 3].map(|k| edge_mid(c[k], c[(k + 1) % 4]));
            out.push((i, j, LatticeCell::Quad(c, m)));
        }
    }
    out
}

/// The cells of a layout on a `width` × `height` lattice; with `wedges`
/// every quadrilateral split into two triangles along the diagonal c0–c2
/// where `first_diagonal` of its lattice corners says so, else c1–c3.
pub(super) fn layout_cells(
    layout: &[(usize, usize, LatticeCell)],
    width: usize,
    height: usize,
    wedges: bool,
    first_diagonal: impl Fn([usize; 4]) -> bool,
) -> BlockCells {
    let mut out = BlockCells {
        width,
        height,
        extra: Vec::new(),
        cells: Vec::new(),
    };
    let lat = |p: Lp| p.0 * height + p.1;
    let mut straight: HashMap<(usize, usize), usize> = HashMap::new();
    let mut mid = |out: &mut BlockCells, m: Mid| match m {
        Mid::Lattice(p) => lat(p),
        Mid::Straight(a, b) => {
            let (a, b) = (lat(a).min(lat(b)), lat(a).max(lat(b)));
            *straight.entry((a, b)).or_insert_with(|| {
                out.extra.push(vec![(a, 0.5), (b, 0.5)]);
                width * height + out.extra.len() - 1
            })
        }
    };
    for (i, j, cell) in layout {
        match cell {
            LatticeCell::Quad(c, m) => {
                let c = c.map(lat);
                let m = m.map(|x| mid(&mut out, x));
                if !wedges {
                    out.cells.push(((*i, *j), Shape::Quad(c, m)));
                    continue;
                }
                let mut w: Vec<(usize, f64)> = c.iter().map(|&p| (p, -0.25)).collect();
                w.extend(m.iter().map(|&p| (p, 0.5)));
                out.extra.push(w);
                let centre = width * height + out.extra.len() - 1;
                for (tc, tm) in split_quad(c, m, centre, first_diagonal(c)) {
                    out.cells.push(((*i, *j), Shape::Tri(tc, tm)));
                }
            }
            LatticeCell::Tris(t) => {
                for (tc, tm) in t {
                    let tm = tm.map(|x| mid(&mut out, x));
                    out.cells.push(((*i, *j), Shape::Tri(tc.map(lat), tm)));
                }
            }
        }
    }
    out
}
