//! Directional compliance matrices at a row of contact points (seed 001's
//! C_nn, C_nt, C_tn, C_tt), with the checks a contact solver needs of them.
//!
//! For K points k on one body's flank, each with its unit normal n_k and
//! unit tangent t_k (the sliding direction of the contact), and the
//! interpolated tensors C^{kl} ([`FlankInterpolator::tensor`]):
//!
//! ```text
//! C_nn[k][l] = n_kᵀ C^{kl} n_l    C_nt[k][l] = n_kᵀ C^{kl} t_l
//! C_tn[k][l] = t_kᵀ C^{kl} n_l    C_tt[k][l] = t_kᵀ C^{kl} t_l
//! ```
//!
//! (displacement along the first direction at k from a unit force along
//! the second at l, [`crate::compliance::interpolation`]). Reciprocity
//! (C^{kl} = (C^{lk})ᵀ) makes C_nn and C_tt symmetric and C_tn = C_ntᵀ; both
//! are measured, not assumed ([`ProbeReport::reciprocity`]), so the row is
//! also a check of the tensors and of the interpolation. Seed 003 expects
//! C_nn "symmetric and positive definite … condition number on the order
//! of 10³"; the report gives its eigenvalues and 2-norm condition number.

use nalgebra::{DMatrix, SymmetricEigen};

use crate::compliance::interpolation::{directional, CellShape, FlankInterpolator, SurfaceLoad};
use crate::compliance::ComplianceTensor;
use crate::error::FlankError;

/// One contact point on a body's flank, in that body's own frame.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct ProbePoint {
    /// Flank node set (`FLANK_R<k>`, …).
    pub set: String,
    /// Flank parameters (u, v) (mm).
    pub uv: [f64; 2],
    /// Unit normal and unit tangent (own frame).
    pub normal: [f64; 3],
    pub tangent: [f64; 3],
}

/// The four K × K directional compliance matrices (row-major, mm/N).
#[derive(Clone, Debug, PartialEq)]
pub struct DirectionalMatrices {
    pub points: usize,
    pub nn: Vec<f64>,
    pub nt: Vec<f64>,
    pub tn: Vec<f64>,
    pub tt: Vec<f64>,
}

/// What `probe` found (mm/N), for summaries.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct ProbeReport {
    pub points: usize,
    /// The middle point's own directional compliances.
    pub c_nn: f64,
    pub c_nt: f64,
    pub c_tn: f64,
    pub c_tt: f64,
    /// Eigenvalues of C_nn and λ_max/λ_min.
    pub lambda_min: f64,
    pub lambda_max: f64,
    pub condition: f64,
    pub positive_definite: bool,
    /// max |C_nn − C_nnᵀ|, |C_tt − C_ttᵀ|, |C_tn − C_ntᵀ| over max |C_nn|.
    pub reciprocity: f64,
}

/// `points` without those that lie outside the meshed flank of their set
/// (an axis point on the active flank can still fall beyond the quadratic
/// faces' boundary by the edge deviation); the count of those left out.
pub fn retain_meshed(
    tensor: &ComplianceTensor,
    points: Vec<ProbePoint>,
) -> Result<(Vec<ProbePoint>, usize), FlankError> {
    let it = FlankInterpolator::new(tensor)?;
    let n = points.len();
    let kept: Vec<ProbePoint> = points
        .into_iter()
        .filter(|p| it.point(&p.set, p.uv[0], p.uv[1]).is_ok())
        .collect();
    let dropped = n - kept.len();
    Ok((kept, dropped))
}

/// The directional matrices of `points` on `tensor`'s flank: point loads,
/// or loads spread over `cell` around each point.
pub fn directional_matrices(
    tensor: &ComplianceTensor,
    points: &[ProbePoint],
    cell: Option<(CellShape, usize)>,
) -> Result<DirectionalMatrices, FlankError> {
    let it = FlankInterpolator::new(tensor)?;
    let loads: Vec<SurfaceLoad> = points
        .iter()
        .map(|p| match cell {
            None => it.point(&p.set, p.uv[0], p.uv[1]),
            Some((shape, samples)) => it.cell(&p.set, p.uv[0], p.uv[1], shape, samples),
        })
        .collect::<Result<_, _>>()?;
    for p in points {
        let unit = |v: [f64; 3]| (v.iter().map(|x| x * x).sum::<f64>().sqrt() - 1.0).abs() < 1e-9;
        if !(unit(p.normal) && unit(p.tangent)) {
            return Err(FlankError::Model(format!(
                "probe point ({}, {}) of {}: normal and tangent must be unit vectors",
                p.uv[0], p.uv[1], p.set
            )));
        }
    }
    let k = points.len();
    let mut m = DirectionalMatrices {
        points: k,
        nn: vec![0.0; k * k],
        nt: vec![0.0; k * k],
        tn: vec![0.0; k * k],
        tt: vec![0.0; k * k],
    };
    for (i, (pi, li)) in points.iter().zip(&loads).enumerate() {
        for (j, (pj, lj)) in points.iter().zip(&loads).enumerate() {
            let d = directional(
                &it.tensor(li, lj),
                pi.normal,
                pi.tangent,
                pj.normal,
                pj.tangent,
            );
            m.nn[i * k + j] = d.nn;
            m.nt[i * k + j] = d.nt;
            m.tn[i * k + j] = d.tn;
            m.tt[i * k + j] = d.tt;
        }
    }
    Ok(m)
}

impl DirectionalMatrices {
    /// Eigenvalues, condition and reciprocity (module docs).
    pub fn report(&self) -> ProbeReport {
        let k = self.points;
        let mid = (k / 2) * k + k / 2;
        let scale = self.nn.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        let mut recip: f64 = 0.0;
        for i in 0..k {
            for j in 0..k {
                recip = recip
                    .max((self.nn[i * k + j] - self.nn[j * k + i]).abs())
                    .max((self.tt[i * k + j] - self.tt[j * k + i]).abs())
                    .max((self.tn[i * k + j] - self.nt[j * k + i]).abs());
            }
        }
        let sym = DMatrix::from_fn(k, k, |i, j| 0.5 * (self.nn[i * k + j] + self.nn[j * k + i]));
        let eig = SymmetricEigen::new(sym).eigenvalues;
        let lmin = eig.iter().copied().fold(f64::INFINITY, f64::min);
        let lmax = eig.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        ProbeReport {
            points: k,
            c_nn: self.nn[mid],
            c_nt: self.nt[mid],
            c_tn: self.tn[mid],
            c_tt: self.tt[mid],
            lambda_min: lmin,
            lambda_max: lmax,
            condition: lmax / lmin,
            positive_definite: lmin > 0.0,
            reciprocity: if scale > 0.0 { recip / scale } else { 0.0 },
        }
    }
}
