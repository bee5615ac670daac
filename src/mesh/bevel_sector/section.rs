//! The (θ, u) lattice of one station (module doc of [`super`]): the upper
//! block around tooth 1 (boundaries on the gap lands, fillets and flanks,
//! the tip land on top, the Π bottom below, a Coons blend inside, graded
//! across the tooth) and the rim block below it down to the mount.

use super::station::FaceLayout;
use crate::geometry::gear_pair::Flank;
use crate::mesh::grading::row_fractions;

/// A lattice point of a station: angle θ about the axis (from +y toward
/// +x, tooth 1), axial-section u, and the flank it lies on (its point is
/// then the surface's r(u, v)).
#[derive(Clone, Copy, Debug)]
pub(super) struct SectionPoint {
    pub(super) theta: f64,
    pub(super) u: f64,
    pub(super) flank: Option<Flank>,
}

/// The points of both blocks of one station (odd/odd entries unused).
pub(super) struct SectionLattice {
    /// Upper block, index ii·(2·nt + 1) + jj; ii across (low θ → high θ),
    /// jj up the boundary (cut → land → fillet → flank → tip).
    pub(super) upper: Vec<SectionPoint>,
    /// Rim block, index ii·(2·rim + 1) + kk; ii across, kk up (mount → Π).
    pub(super) rim: Vec<SectionPoint>,
    /// Width (mm, arc) of column d across the tooth at lattice row jj,
    /// index [jj][d], and the height (mm) of the row holding lattice row
    /// jj along the low-θ boundary (for the wedges' coarsening).
    pub(super) cell_widths: Vec<Vec<f64>>,
    pub(super) row_heights: Vec<f64>,
}

/// The lattice of station `s` (module doc of [`super`]).
pub(super) fn section(face: &FaceLayout, s: usize) -> SectionLattice {
    let st = &face.stations[s];
    let c = &face.counts;
    let (ng, nf, ni) = (c.land, c.fillet, c.flank);
    let nt = ng + nf + ni;
    let na = c.across;
    let nc = c.cut;
    let v = st.v;
    let pitch = face.pitch;
    let radius = |u: f64| st.radius(&face.cones, u);

    // the two boundary sides, jj = 0..=2nt
    let side = |hi: bool| -> Vec<SectionPoint> {
        let (prof, theta_cut, theta_root) = if hi {
            (&st.hi, st.theta_cut + pitch, st.theta_root[1])
        } else {
            (&st.lo, st.theta_cut, st.theta_root[0])
        };
        (0..=2 * nt)
            .map(|jj| {
                if jj < 2 * ng {
                    let f = jj as f64 / (2 * ng) as f64;
                    SectionPoint {
                        theta: theta_cut + f * (theta_root - theta_cut),
                        u: st.u_cut + f * (prof.u_root - st.u_cut),
                        flank: None,
                    }
                } else {
                    let u = if jj <= 2 * (ng + nf) {
                        match jj - 2 * ng {
                            0 => prof.u_root,
                            d if d == 2 * nf => prof.u_form,
                            d => prof.fillet_u(d as f64 / (2 * nf) as f64),
                        }
                    } else {
                        match jj - 2 * (ng + nf) {
                            d if d == 2 * ni => st.u_tip,
                            d => prof.flank_u(d as f64 / (2 * ni) as f64),
                        }
                    };
                    SectionPoint {
                        theta: prof.theta(u, v, st.theta_ref),
                        u,
                        flank: Some(prof.side),
                    }
                }
            })
            .collect()
    };
    let (lo, hi) = (side(false), side(true));

    // blend parameter: normalised chord length up each side, averaged
    let chord = |pts: &[SectionPoint]| -> Vec<f64> {
        let mut t = vec![0.0; pts.len()];
        for j in 1..pts.len() {
            let (a, b) = (pts[j - 1], pts[j]);
            let r = radius(0.5 * (a.u + b.u));
            t[j] = t[j - 1] + (r * (b.theta - a.theta)).hypot(b.u - a.u);
        }
        let total = t[pts.len() - 1];
        t.iter().map(|x| x / total).collect()
    };
    let (tl, th) = (chord(&lo), chord(&hi));
    let tau: Vec<f64> = tl.iter().zip(&th).map(|(a, b)| 0.5 * (a + b)).collect();
    let jform = 2 * (ng + nf);
    let tau_f = tau[jform];
    let alpha = |t: f64| {
        if t < tau_f {
            (1.0 - t / tau_f).powi(2)
        } else {
            0.0
        }
    };

    // across-row fractions: rows below the form line take the form row's
    let row_width = |jj: usize| {
        let j = jj.max(jform);
        let (a, b) = (lo[j], hi[j]);
        radius(0.5 * (a.u + b.u)) * (b.theta - a.theta)
    };
    let row_sig: Vec<Vec<f64>> = (0..=2 * nt)
        .map(|jj| row_fractions(row_width(jj), face.half_across, face.flank_size))
        .collect();
    let cell_widths = (0..=2 * nt)
        .map(|jj| {
            (0..na)
                .map(|d| row_width(jj) * (row_sig[jj][2 * d + 2] - row_sig[jj][2 * d]))
                .collect()
        })
        .collect();

    // the Π bottom (θ, u) at across index ii
    let sig = &face.across;
    let (s_c0, s_c1) = (sig[2 * nc], sig[2 * (na - nc)]);
    let u_i = st.u_cut - face.cut_depth;
    let bottom = |ii: usize| -> (f64, f64) {
        let s = sig[ii];
        if ii <= 2 * nc {
            (st.theta_cut, st.u_cut - face.cut_depth * s / s_c0)
        } else if ii >= 2 * (na - nc) {
            (
                st.theta_cut + pitch,
                st.u_cut - face.cut_depth * (1.0 - s) / (1.0 - s_c1),
            )
        } else {
            (st.theta_cut + pitch * (s - s_c0) / (s_c1 - s_c0), u_i)
        }
    };
    let top = |s: f64| -> (f64, f64) {
        (
            st.theta_tip[0] + s * (st.theta_tip[1] - st.theta_tip[0]),
            st.u_tip,
        )
    };
    let plain = |(theta, u): (f64, f64)| SectionPoint {
        theta,
        u,
        flank: None,
    };

    let h = 2 * nt + 1;
    let mut upper = Vec::with_capacity((2 * na + 1) * h);
    let (c00, c10) = ((lo[0].theta, lo[0].u), (hi[0].theta, hi[0].u));
    let (c01, c11) = (
        (lo[2 * nt].theta, lo[2 * nt].u),
        (hi[2 * nt].theta, hi[2 * nt].u),
    );
    for ii in 0..=2 * na {
        for jj in 0..=2 * nt {
            let p = if ii == 0 {
                lo[jj]
            } else if ii == 2 * na {
                hi[jj]
            } else if jj == 2 * nt {
                plain(top(row_sig[jj][ii]))
            } else if jj == 0 {
                plain(bottom(ii))
            } else {
                let s = row_sig[jj][ii];
                let t = tau[jj];
                let (b, tp) = (bottom(ii), top(s));
                let lerp = |a: (f64, f64), b: (f64, f64)| {
                    ((1.0 - s) * a.0 + s * b.0, (1.0 - s) * a.1 + s * b.1)
                };
                let ls = lerp((lo[jj].theta, lo[jj].u), (hi[jj].theta, hi[jj].u));
                let ls0 = lerp(c00, c10);
                let ls1 = lerp(c01, c11);
                let al = alpha(t);
                plain((
                    ls.0 + al * (b.0 - ls0.0) + t * (tp.0 - ls1.0),
                    ls.1 + al * (b.1 - ls0.1) + t * (tp.1 - ls1.1),
                ))
            };
            upper.push(p);
        }
    }

    // the rim: across the pitch from the Π bottom's middle, down to the mount
    let nr = c.rim;
    let nar = na - 2 * nc;
    let mut rim = Vec::with_capacity((2 * nar + 1) * (2 * nr + 1));
    for ir in 0..=2 * nar {
        let theta = bottom(ir + 2 * nc).0;
        for kk in 0..=2 * nr {
            let u = if kk == 2 * nr {
                u_i
            } else if kk == 0 {
                st.u_mount
            } else {
                u_i - (u_i - st.u_mount) * face.rim[2 * nr - kk]
            };
            rim.push(SectionPoint {
                theta,
                u,
                flank: None,
            });
        }
    }
    let row_heights = (0..=2 * nt)
        .map(|jj| {
            let j = 2 * (jj / 2).min(nt - 1);
            let (a, b) = (lo[j], lo[j + 2]);
            (radius(0.5 * (a.u + b.u)) * (b.theta - a.theta)).hypot(b.u - a.u)
        })
        .collect();
    SectionLattice {
        upper,
        rim,
        cell_widths,
        row_heights,
    }
}
