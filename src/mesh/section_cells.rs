//! Cells of a structured tooth section in lattice (half-index)
//! coordinates, shared by the sector meshers ([`crate::mesh::gear_sector`]
//! in (angle, radius), [`crate::mesh::bevel_sector`] in (θ, u) on each
//! station): the upper block's cells, every row for hex meshes, for wedge
//! meshes the 2:1 coarsening along the profile inside the tooth (levels of
//! the column lines, row breakpoints of each level, transition columns of
//! three triangles per coarse cell); the role of each lattice point
//! (unused, corner or midside); the split of a quadrilateral into two
//! triangles.

/// A lattice point (half-index I, J) of an upper block.
pub type Lp = (usize, usize);

/// The midside point of an edge of a lattice cell: a lattice point (edges
/// along a row, and edges one row long: shared with fine neighbours and,
/// on the boundary, on the exact curve), or the straight midpoint of the
/// corners (edges spanning several rows and diagonals of coarse or
/// transition cells, which never lie on the boundary: where rows are
/// unevenly spaced a lattice point would sit far off the edge's middle).
#[derive(Clone, Copy, Debug)]
pub enum Mid {
    Lattice(Lp),
    Straight(Lp, Lp),
}

/// Midside of the edge a–b (lattice corners).
pub fn edge_mid(a: Lp, b: Lp) -> Mid {
    let m = ((a.0 + b.0) / 2, (a.1 + b.1) / 2);
    if a.1 == b.1 || (a.0 == b.0 && a.1.abs_diff(b.1) == 2) {
        Mid::Lattice(m)
    } else {
        Mid::Straight(a, b)
    }
}

/// A section cell in lattice coordinates (corners, midsides).
#[derive(Clone, Debug)]
pub enum LatticeCell {
    Quad([Lp; 4], [Mid; 4]),
    Tris(Vec<([Lp; 3], [Mid; 3])>),
}

/// The two triangles (corners, midsides) of the quadrilateral with corners
/// `c` and midsides `m` (m\[k\] on the edge c\[k\]–c[k+1]), split along the
/// diagonal c0–c2 (`first`) or c1–c3, whose midside point is `centre`;
/// the triangles keep the quadrilateral's orientation.
pub fn split_quad<P: Copy>(c: [P; 4], m: [P; 4], centre: P, first: bool) -> [([P; 3], [P; 3]); 2] {
    if first {
        [
            ([c[0], c[1], c[2]], [m[0], m[1], centre]),
            ([c[0], c[2], c[3]], [centre, m[2], m[3]]),
        ]
    } else {
        [
            ([c[0], c[1], c[3]], [m[0], centre, m[3]]),
            ([c[1], c[2], c[3]], [m[1], m[2], centre]),
        ]
    }
}

/// The serendipity centre of a quadratic quadrilateral (corners `c`,
/// midsides `m`): the midside point of a diagonal, inside the cell.
pub fn serendipity_centre(c: [[f64; 2]; 4], m: [[f64; 2]; 4]) -> [f64; 2] {
    let mut centre = [0.0; 2];
    for k in 0..4 {
        for d in 0..2 {
            centre[d] += -0.25 * c[k][d] + 0.5 * m[k][d];
        }
    }
    centre
}

/// The cells of an upper block: (column, first row, cell).
pub type UpperCells = Vec<(usize, usize, LatticeCell)>;

/// The upper-block layout: (column, first row, cell) of every cell, and the
/// role of each lattice point ((2ns + 1) × (2nt + 1), index I·(2nt + 1) + J):
/// 0 unused, 1 corner, 2 midside. `ns` columns across the tooth (widths
/// `sizes_s`), `nt` rows along it, `fs` the flank size; `cell_width(d, jj)`
/// is the width of column d at lattice row jj. Without `coarsen` every row
/// is kept.
/// Errors (internal inconsistencies) start with `name`.
pub fn upper_layout(
    name: &str,
    coarsen: bool,
    ns: usize,
    nt: usize,
    sizes_s: &[f64],
    fs: f64,
    cell_width: impl Fn(usize, usize) -> f64,
) -> Result<(UpperCells, Vec<u8>), String> {
    // --- upper-block layout in lattice (half-index) coordinates, the same for
    // every pitch. Wedge meshes coarsen along the profile inside the tooth:
    // column line i gets a level λ (0 at the flanks and on the first line
    // inside, rising by at most 1 per column towards the tooth centre, where
    // 2^λ rows of the flank spacing make a cell about 1.5 × as tall as the
    // graded column is wide); a column between lines of equal level has cells
    // of 2^λ rows, a column between levels λ and λ + 1 is a 2:1 transition of
    // three triangles per coarse cell. Hex meshes keep every row (λ = 0).
    let mut levels = vec![0u32; ns + 1];
    if coarsen {
        let max_level = (nt / 2).max(1).ilog2();
        for d in 2..=ns / 2 {
            let want = (1.5 * sizes_s[d.min(ns - 1)] / fs).log2().floor().max(0.0) as u32;
            let l = want
                .min(levels[d - 1] + 1)
                .max(levels[d - 1])
                .min(max_level);
            levels[d] = l;
            levels[ns - d] = l;
        }
    }
    // Row breakpoints of each level: level λ keeps every 2^λ-th row up to
    // the row j_λ where its narrowest cells (next to the line where λ first
    // appears) would become more than 3 × as tall as wide (the tooth narrows
    // towards the tip); above j_λ it
    // keeps the rows of level λ − 1. So B_λ ⊂ B_{λ−1}, and every coarse
    // chunk holds at most one breakpoint of the level below.
    let max_level = *levels.iter().max().unwrap_or(&0);
    let mut row_breaks: Vec<Vec<usize>> = vec![(0..=nt).collect()];
    for l in 1..=max_level {
        let d_l = levels.iter().position(|&x| x >= l).unwrap_or(ns / 2);
        let step = 1usize << l;
        let mut j_l = 0;
        while j_l + step <= nt
            && (0..=2 * (j_l + step))
                .all(|jj| (step as f64) * fs <= 3.0 * cell_width(d_l.min(ns - 1), jj))
        {
            j_l += step;
        }
        let below = &row_breaks[l as usize - 1];
        let v: Vec<usize> = below
            .iter()
            .copied()
            .filter(|&j| if j <= j_l { j % step == 0 } else { true })
            .collect();
        row_breaks.push(v);
    }
    let breaks = |l: u32| -> Vec<usize> { row_breaks[l as usize].clone() };
    let mid = edge_mid;
    let tri = |a: Lp, b: Lp, c: Lp| ([a, b, c], [mid(a, b), mid(b, c), mid(c, a)]);
    let mut layout: Vec<(usize, usize, LatticeCell)> = Vec::new();
    for c in 0..ns {
        let quad = |ja: usize, jb: usize| {
            let q = [
                (2 * c, 2 * ja),
                (2 * c + 2, 2 * ja),
                (2 * c + 2, 2 * jb),
                (2 * c, 2 * jb),
            ];
            LatticeCell::Quad(
                q,
                [
                    mid(q[0], q[1]),
                    mid(q[1], q[2]),
                    mid(q[2], q[3]),
                    mid(q[3], q[0]),
                ],
            )
        };
        let (l0, l1) = (levels[c], levels[c + 1]);
        if l0 == l1 {
            for w in breaks(l0).windows(2) {
                layout.push((c, w[0], quad(w[0], w[1])));
            }
            continue;
        }
        let fine = breaks(l0.min(l1));
        for w in breaks(l0.max(l1)).windows(2) {
            let (ja, jb) = (w[0], w[1]);
            let inner: Vec<usize> = fine.iter().copied().filter(|&j| j > ja && j < jb).collect();
            let jm = match inner[..] {
                [] => {
                    layout.push((c, ja, quad(ja, jb)));
                    continue;
                }
                [jm] => jm,
                _ => {
                    return Err(format!(
                        "{name}: internal: rows {ja}..{jb} of column {c} hold {} finer rows",
                        inner.len()
                    ))
                }
            };
            let (la, lm, lb) = ((2 * c, 2 * ja), (2 * c, 2 * jm), (2 * c, 2 * jb));
            let (ra, rm, rb) = (
                (2 * c + 2, 2 * ja),
                (2 * c + 2, 2 * jm),
                (2 * c + 2, 2 * jb),
            );
            let t = if l0 < l1 {
                vec![tri(la, ra, lm), tri(lm, ra, rb), tri(lm, rb, lb)]
            } else {
                vec![tri(la, ra, rm), tri(la, rm, lb), tri(lb, rm, rb)]
            };
            layout.push((c, ja, LatticeCell::Tris(t)));
        }
    }
    // role of each lattice point: 0 unused, 1 corner, 2 midside
    let w2 = 2 * nt + 1;
    let mut role = vec![0u8; (2 * ns + 1) * w2];
    let mut mark = |p: Lp, r: u8| -> Result<(), String> {
        let slot = &mut role[p.0 * w2 + p.1];
        if *slot != 0 && *slot != r {
            return Err(format!(
                "{name}: lattice point ({}, {}) is both a corner and a midside node",
                p.0, p.1
            ));
        }
        *slot = r;
        Ok(())
    };
    for (_, _, cell) in &layout {
        let (corners, mids): (Vec<Lp>, Vec<Mid>) = match cell {
            LatticeCell::Quad(c, m) => (c.to_vec(), m.to_vec()),
            LatticeCell::Tris(t) => (
                t.iter().flat_map(|(c, _)| c.iter().copied()).collect(),
                t.iter().flat_map(|(_, m)| m.iter().copied()).collect(),
            ),
        };
        for p in corners {
            mark(p, 1)?;
        }
        for m in mids {
            if let Mid::Lattice(p) = m {
                mark(p, 2)?;
            }
        }
    }
    Ok((layout, role))
}
