//! Candidate search: which master faces can a slave node touch?
//!
//! Every master face gets its axis-aligned bounding box (of all its nodes;
//! a quadratic face bulges at most to its midside nodes' hull only
//! approximately, so the box is also inflated by 10 % of its size) inflated
//! by the search distance. The boxes are binned into a uniform grid whose
//! cell size is the median box size; a query visits the one cell holding
//! the point. Cost: O(faces) to build, O(faces per cell) per query.

use std::collections::HashMap;

/// Uniform-grid index of inflated face bounding boxes.
pub struct FaceGrid {
    lo: [f64; 3],
    cell: f64,
    bins: HashMap<[i64; 3], Vec<usize>>,
    boxes: Vec<([f64; 3], [f64; 3])>,
}

impl FaceGrid {
    /// Builds the grid for faces given by their node coordinates, each box
    /// inflated by `margin` (≥ 0).
    pub fn new(faces: &[Vec<[f64; 3]>], margin: f64) -> Self {
        Self::with_margins(faces, &vec![margin; faces.len()])
    }

    /// As [`FaceGrid::new`] with one margin per face.
    pub fn with_margins(faces: &[Vec<[f64; 3]>], margins: &[f64]) -> Self {
        let mut boxes = Vec::with_capacity(faces.len());
        let mut sizes = Vec::with_capacity(faces.len());
        for (f, &margin) in faces.iter().zip(margins) {
            let mut lo = [f64::INFINITY; 3];
            let mut hi = [f64::NEG_INFINITY; 3];
            for x in f {
                for k in 0..3 {
                    lo[k] = lo[k].min(x[k]);
                    hi[k] = hi[k].max(x[k]);
                }
            }
            let size = (0..3).map(|k| hi[k] - lo[k]).fold(0.0f64, f64::max);
            let pad = margin + 0.1 * size;
            for k in 0..3 {
                lo[k] -= pad;
                hi[k] += pad;
            }
            sizes.push(size + 2.0 * pad);
            boxes.push((lo, hi));
        }
        let mut glo = [f64::INFINITY; 3];
        for (lo, _) in &boxes {
            for k in 0..3 {
                glo[k] = glo[k].min(lo[k]);
            }
        }
        sizes.sort_by(|a, b| a.partial_cmp(b).unwrap_or(std::cmp::Ordering::Equal));
        let cell = sizes
            .get(sizes.len() / 2)
            .copied()
            .filter(|c| *c > 0.0 && c.is_finite())
            .unwrap_or(1.0);
        let mut grid = FaceGrid {
            lo: glo,
            cell,
            bins: HashMap::new(),
            boxes,
        };
        for (i, (lo, hi)) in grid.boxes.clone().iter().enumerate() {
            let a = grid.key(*lo);
            let b = grid.key(*hi);
            // a box spanning very many cells (a huge margin) is capped by
            // visiting at most 64³ cells; beyond that it goes everywhere
            let span: i64 = (0..3).map(|k| b[k] - a[k] + 1).product();
            if span > 262_144 {
                grid.bins.entry([i64::MIN; 3]).or_default().push(i);
                continue;
            }
            for x in a[0]..=b[0] {
                for y in a[1]..=b[1] {
                    for z in a[2]..=b[2] {
                        grid.bins.entry([x, y, z]).or_default().push(i);
                    }
                }
            }
        }
        grid
    }

    fn key(&self, p: [f64; 3]) -> [i64; 3] {
        let k = |i: usize| (((p[i] - self.lo[i]) / self.cell).floor()).clamp(-1e15, 1e15) as i64;
        [k(0), k(1), k(2)]
    }

    /// Faces whose inflated box contains `p`.
    pub fn query(&self, p: [f64; 3]) -> Vec<usize> {
        let mut out = Vec::new();
        let inside = |i: usize| {
            let (lo, hi) = &self.boxes[i];
            (0..3).all(|k| p[k] >= lo[k] && p[k] <= hi[k])
        };
        if let Some(v) = self.bins.get(&self.key(p)) {
            out.extend(v.iter().copied().filter(|&i| inside(i)));
        }
        if let Some(v) = self.bins.get(&[i64::MIN; 3]) {
            out.extend(v.iter().copied().filter(|&i| inside(i)));
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_exactly_the_boxes_containing_the_point() {
        // a 10 × 10 grid of unit squares in z = 0 (as 4-node outlines)
        let mut faces = Vec::new();
        for i in 0..10 {
            for j in 0..10 {
                let (x, y) = (i as f64, j as f64);
                faces.push(vec![
                    [x, y, 0.0],
                    [x + 1.0, y, 0.0],
                    [x + 1.0, y + 1.0, 0.0],
                    [x, y + 1.0, 0.0],
                ]);
            }
        }
        let grid = FaceGrid::new(&faces, 0.05);
        let hits = grid.query([3.5, 7.5, 0.1]);
        assert_eq!(hits, vec![37]);
        let mut hits = grid.query([4.0, 2.0, 0.0]);
        hits.sort_unstable();
        assert_eq!(hits, vec![31, 32, 41, 42]);
        assert!(grid.query([3.5, 7.5, 0.3]).is_empty());
        assert!(grid.query([-5.0, 0.0, 0.0]).is_empty());
    }
}
