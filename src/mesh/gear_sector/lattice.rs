//! 2D building blocks of the transverse section: graded element sizes and
//! their half-lattice fractions (corner and midside positions), polar
//! coordinates, the point registry that merges points by position, the
//! quadratic blocks and the transverse cells (quadrilaterals, or two
//! triangles for wedges) in point ids (in lattice coordinates:
//! [`crate::mesh::section_cells`]).

use std::collections::HashMap;

use super::err;
use crate::error::FlankError;
use crate::geometry::rack::Flank;
use crate::mesh::section_cells::{serendipity_centre, split_quad};

/// Graded sizes ([`crate::mesh::grading::graded`]) with this mesher's
/// error prefix.
pub(super) fn graded(
    len: f64,
    h0: f64,
    q: f64,
    hmax: f64,
    what: &str,
) -> Result<Vec<f64>, FlankError> {
    crate::mesh::grading::graded(len, h0, q, hmax, what).map_err(err)
}

pub(super) use crate::mesh::grading::half_lattice;

pub(super) fn pol(p: [f64; 2]) -> [f64; 2] {
    [p[0].atan2(p[1]), p[0].hypot(p[1])]
}

pub(super) fn cart(a: f64, r: f64) -> [f64; 2] {
    [r * a.sin(), r * a.cos()]
}

pub(super) fn rot(p: [f64; 2], a: f64) -> [f64; 2] {
    // rotate by angle a measured from +y towards +x (clockwise)
    let (s, c) = a.sin_cos();
    [c * p[0] + s * p[1], -s * p[0] + c * p[1]]
}

/// Transverse 2D point registry with merging by position.
pub(super) struct Points {
    pub(super) xy: Vec<[f64; 2]>,
    /// true if a corner lattice point (no odd index), false if midside.
    pub(super) corner: Vec<bool>,
    /// flank info: (sector tooth 1-based, flank, u)
    pub(super) flank: Vec<Option<(usize, Flank, f64)>>,
    pub(super) bore: Vec<bool>,
    pub(super) grid: HashMap<(i64, i64), Vec<usize>>,
    pub(super) tol: f64,
}

impl Points {
    fn key(&self, p: [f64; 2]) -> (i64, i64) {
        (
            (p[0] / self.tol).floor() as i64,
            (p[1] / self.tol).floor() as i64,
        )
    }
    pub(super) fn add(&mut self, p: [f64; 2], corner: bool) -> Result<usize, FlankError> {
        let (kx, ky) = self.key(p);
        for dx in -1..=1 {
            for dy in -1..=1 {
                if let Some(v) = self.grid.get(&(kx + dx, ky + dy)) {
                    for &i in v {
                        let q = self.xy[i];
                        if (q[0] - p[0]).hypot(q[1] - p[1]) < self.tol {
                            if self.corner[i] != corner {
                                return Err(err(format!(
                                    "lattice mismatch at ({:.6}, {:.6}): corner and midside point coincide",
                                    p[0], p[1]
                                )));
                            }
                            return Ok(i);
                        }
                    }
                }
            }
        }
        let i = self.xy.len();
        self.xy.push(p);
        self.corner.push(corner);
        self.flank.push(None);
        self.bore.push(false);
        self.grid.entry((kx, ky)).or_default().push(i);
        Ok(i)
    }
}

/// A 2D quadratic block: point ids on a (2ni+1) × (2nj+1) lattice (usize::MAX at odd/odd).
pub(super) struct Block {
    pub(super) ni: usize,
    pub(super) nj: usize,
    pub(super) ids: Vec<usize>,
}

/// A transverse cell: quadrilateral (corners, midsides; hex20) or two
/// triangles (wedge15), point ids in the order of the element's bottom face.
pub(super) enum Cell {
    Quad([usize; 4], [usize; 4]),
    Tris(Vec<([usize; 3], [usize; 3])>),
}

/// A quadrilateral cell, or for wedges its two triangles (split along the
/// shorter diagonal, whose midside point, the serendipity centre, is added).
pub(super) fn quad_cell(
    pts: &mut Points,
    c: [usize; 4],
    m: [usize; 4],
    wedges: bool,
) -> Result<Cell, FlankError> {
    if !wedges {
        return Ok(Cell::Quad(c, m));
    }
    let x = |p: usize| pts.xy[p];
    let dist = |a: usize, b: usize| {
        let (p, q) = (x(a), x(b));
        (p[0] - q[0]).hypot(p[1] - q[1])
    };
    let centre = serendipity_centre(c.map(x), m.map(x));
    let first_diagonal = dist(c[0], c[2]) <= dist(c[1], c[3]);
    let dm = pts.add(centre, false)?;
    Ok(Cell::Tris(split_quad(c, m, dm, first_diagonal).to_vec()))
}
