//! The FE reference extrapolated to h → 0: from the three finest FE-contact
//! runs of a comparison, per position the Richardson-extrapolated load
//! share of every tooth pair and TE, with their grid convergence index
//! (Celik et al. 2008, [`crate::grid_convergence`]), so that the LTCA's
//! error is stated against a converged reference and beside its
//! uncertainty (issue 23 point 1).
//!
//! Where a figure gives no estimate (no change between grids: a pair out of
//! mesh, a share of exactly 0 or 1; diverging or unsettled order), or an
//! observed order outside [`ORDER_RANGE`] (the extrapolation of a figure
//! that is not in its asymptotic range: with p = 0.02 it lands anywhere),
//! the finest run's value is kept and its uncertainty is the data range
//! 3 Δ_M, Δ_M the largest difference between the three grids (Eça &
//! Hoekstra, J. Comput. Phys. 262 (2014) 104–130, for anomalous
//! convergence); counted as a fallback. p_max is not extrapolated: an FE
//! nodal pressure that does not resolve the Hertz width has no asymptotic
//! range; the finest run's value stands in, as before.

use super::method_run::{shares, MethodRun};
use crate::grid_convergence::{gci, GciIssue};

/// Roache's safety factor for three grids.
const SAFETY_FACTOR: f64 = 1.25;
/// Observed orders trusted for extrapolation: from 0.5 to twice the
/// formal order of quadratic elements (2), the bounds of Eça & Hoekstra
/// (2014) for an order that is neither too low to extrapolate with nor
/// unrealistically high.
pub const ORDER_RANGE: (f64, f64) = (0.5, 4.0);
/// Safety factor on the data range where the order is not trusted.
const DATA_RANGE_FACTOR: f64 = 3.0;

/// The uncertainty of a figure without a trusted order: 3 × the largest
/// difference between the three grids (Eça & Hoekstra 2014).
pub(crate) fn data_range(phi: [f64; 3]) -> f64 {
    DATA_RANGE_FACTOR
        * (phi[0] - phi[1])
            .abs()
            .max((phi[1] - phi[2]).abs())
            .max((phi[0] - phi[2]).abs())
}

/// The extrapolated reference and its uncertainty.
#[derive(Clone, Debug, serde::Serialize)]
pub struct ExtrapolatedReference {
    /// The reference as a run (forces: extrapolated shares × the finest
    /// run's total; TE extrapolated; p_max the finest run's).
    #[serde(skip)]
    pub run: MethodRun,
    /// Flank sizes used, finest first (mm).
    pub flank_sizes_mm: [f64; 3],
    /// Per position and pair: the extrapolated share's absolute
    /// uncertainty (GCI_fine × |share|, or |φ1 − φ2| at a fallback).
    pub share_uncertainty: Vec<Vec<f64>>,
    /// Per position: the extrapolated TE's relative uncertainty (GCI_fine).
    pub te_uncertainty: Vec<f64>,
    /// Per position: the observed order of TE (NaN where none came out;
    /// outside [`ORDER_RANGE`] the finest value was kept).
    pub te_order: Vec<f64>,
    /// Largest share uncertainty over positions and pairs.
    pub max_share_uncertainty: f64,
    /// Largest relative TE uncertainty over positions.
    pub max_te_uncertainty: f64,
    /// Figures (shares and TEs) without a trusted estimate, the finest
    /// value kept.
    pub fallbacks: usize,
    /// Of those, figures that did not change between the grids.
    pub unchanged: usize,
}

/// One figure from three grids (values finest first): the extrapolated
/// value, its absolute uncertainty, its observed order (NaN where none came
/// out), whether it fell back, and why no order came out (none where one
/// did, trusted or not).
pub(crate) fn estimate(h: [f64; 3], phi: [f64; 3]) -> (f64, f64, f64, bool, Option<GciIssue>) {
    let range = data_range(phi);
    match gci(h, phi, SAFETY_FACTOR) {
        Ok(g) if g.order >= ORDER_RANGE.0 && g.order <= ORDER_RANGE.1 => {
            let u = g.gci_fine.map_or(range, |x| x * phi[0].abs());
            (g.extrapolated, u, g.order, false, None)
        }
        Ok(g) => (phi[0], range, g.order, true, None),
        Err(issue) => (phi[0], range, f64::NAN, true, Some(issue)),
    }
}

/// The reference from `fe`, sorted coarse to fine, if it holds three runs
/// or more (the three finest are used); `None` otherwise.
pub fn extrapolate(fe: &[MethodRun]) -> Option<ExtrapolatedReference> {
    let n = fe.len();
    if n < 3 {
        return None;
    }
    let (f1, f2, f3) = (&fe[n - 1], &fe[n - 2], &fe[n - 3]);
    let h = [f1.flank_size_mm?, f2.flank_size_mm?, f3.flank_size_mm?];
    let positions = f1.te_urad.len();
    let mut run = f1.clone();
    run.method = "fe_extrapolated".into();
    run.label = format!("FE extrapolated from {} / {} / {} mm", h[2], h[1], h[0]);
    run.nodes = None;
    run.flank_size_mm = Some(0.0);
    let (mut share_u, mut te_u, mut te_p) = (Vec::new(), Vec::new(), Vec::new());
    let (mut fallbacks, mut unchanged) = (0, 0);
    for i in 0..positions {
        let s = [
            shares(&f1.pair_force_n[i]),
            shares(&f2.pair_force_n[i]),
            shares(&f3.pair_force_n[i]),
        ];
        let total: f64 = f1.pair_force_n[i].iter().sum();
        let mut forces = Vec::new();
        let mut u = Vec::new();
        for p in 0..s[0].len() {
            let (x, ux, _, fell, issue) = estimate(h, [s[0][p], s[1][p], s[2][p]]);
            fallbacks += usize::from(fell);
            unchanged += usize::from(issue == Some(GciIssue::NoChange));
            forces.push(x * total);
            u.push(ux);
        }
        run.pair_force_n[i] = forces;
        share_u.push(u);
        let (te, ute, p, fell, issue) = estimate(h, [f1.te_urad[i], f2.te_urad[i], f3.te_urad[i]]);
        fallbacks += usize::from(fell);
        unchanged += usize::from(issue == Some(GciIssue::NoChange));
        run.te_urad[i] = te;
        te_u.push(if te != 0.0 { ute / te.abs() } else { f64::NAN });
        te_p.push(p);
    }
    let max_share_uncertainty = share_u.iter().flatten().copied().fold(0.0, f64::max);
    let max_te_uncertainty = te_u.iter().copied().fold(0.0, f64::max);
    Some(ExtrapolatedReference {
        run,
        flank_sizes_mm: h,
        share_uncertainty: share_u,
        te_uncertainty: te_u,
        te_order: te_p,
        max_share_uncertainty,
        max_te_uncertainty,
        fallbacks,
        unchanged,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fe(h: f64, forces: Vec<Vec<f64>>, te: Vec<f64>) -> MethodRun {
        MethodRun {
            method: "fe_contact".into(),
            label: format!("FE flank {h} mm"),
            points_per_line: None,
            flank_size_mm: Some(h),
            nodes: Some(1),
            pmax_mpa: vec![1.0; te.len()],
            pair_force_n: forces,
            pair_tangential_n: Vec::new(),
            te_urad: te,
            cycle_s: 1.0,
            setup_s: 1.0,
            slave: Vec::new(),
            load_sharing_err: f64::NAN,
            te_rel_err: f64::NAN,
            pmax_rel_err: f64::NAN,
            pmax_uniform_fe_rel_err: f64::NAN,
            tangential_force_err: f64::NAN,
        }
    }

    /// Three FE runs at h = 1, ½, ¼: a position with shares s = 0.6 + 0.1 h²
    /// and TE = 100 (1 + h²), and a single-contact one (shares 0 / 1, TE
    /// 50 (1 + h)).
    fn quadratic_runs() -> Vec<MethodRun> {
        [1.0, 0.5, 0.25]
            .into_iter()
            .map(|h: f64| {
                let s = 0.6 + 0.1 * h * h;
                fe(
                    h,
                    vec![vec![1000.0 * s, 1000.0 * (1.0 - s)], vec![0.0, 700.0]],
                    vec![100.0 * (1.0 + h * h), 50.0 * (1.0 + h)],
                )
            })
            .collect()
    }

    /// Shares s = 0.6 + 0.1 h² and TE = 100 (1 + h²) at h = 1, ½, ¼, and a
    /// single-contact position (shares 0 / 1 on every grid: no change):
    /// the extrapolation recovers 0.6 and 100 with order 2; the unchanged
    /// shares fall back to their value with zero uncertainty.
    #[test]
    fn recovers_quadratic_convergence_and_keeps_unchanged_shares() {
        let runs = quadratic_runs();
        assert!(extrapolate(&runs[1..]).is_none());
        let r = extrapolate(&runs).unwrap();
        let s = shares(&r.run.pair_force_n[0]);
        assert!(
            (s[0] - 0.6).abs() < 1e-12 && (s[1] - 0.4).abs() < 1e-12,
            "{s:?}"
        );
        assert!((r.run.te_urad[0] - 100.0).abs() < 1e-10);
        assert!((r.te_order[0] - 2.0).abs() < 1e-9);
        assert!((r.run.te_urad[1] - 50.0).abs() < 1e-10, "first order TE");
        // GCI of the fine grid: F_s |φ1 − φ2| / (r^p − 1) / |φ1|
        let expected = 1.25 * (100.0 * 0.1875) / 3.0 / 106.25;
        assert!((r.te_uncertainty[0] - expected * 106.25 / 100.0).abs() < 1e-12);
        assert_eq!(r.share_uncertainty[1], [0.0, 0.0]);
        assert_eq!((r.fallbacks, r.unchanged), (2, 2));
        assert_eq!(r.run.pair_force_n[1], [0.0, 700.0]);
    }

    /// The per-position errors and their count within the targets: an
    /// LTCA 0.03 off in one share at the first position and 1 % high in TE
    /// at the second, against the quadratic reference above.
    #[test]
    fn per_position_errors_and_their_table() {
        let runs = quadratic_runs();
        let r = extrapolate(&runs).unwrap();
        let ltca = fe(
            0.5,
            vec![vec![630.0, 370.0], vec![0.0, 700.0]],
            vec![100.0, 1.01 * 50.0],
        );
        let rows = crate::compare::position_errors(&[-1.0, 2.0], &ltca, &r.run, Some(&r));
        assert!((rows[0].share_err - 0.03).abs() < 1e-12, "{:?}", rows[0]);
        assert!(rows[0].te_rel_err.abs() < 1e-12);
        assert_eq!(rows[1].share_err, 0.0);
        assert!((rows[1].te_rel_err - 0.01).abs() < 1e-12);
        assert_eq!(
            rows[0].share_uncertainty,
            r.share_uncertainty[0][0].max(r.share_uncertainty[0][1])
        );
        assert_eq!((rows[0].roll_deg, rows[1].roll_deg), (-1.0, 2.0));
        let mut md = String::new();
        crate::compare::position_table(&mut md, "LTCA K = 5", &rows, [0.02, 0.02]);
        assert!(md.contains("1 of 2 positions within both targets"), "{md}");
        assert!(md.contains("| -1.00 | 0.600 / 0.400 | 0.0300 |"), "{md}");
    }

    /// TE = 100 + 10 h^0.1 (observed order 0.1, below the trusted range):
    /// the finest value is kept, with 3 × the largest difference as its
    /// uncertainty; Richardson would have put it near 100.
    #[test]
    fn an_untrusted_order_keeps_the_finest_value() {
        let te = |h: f64| 100.0 + 10.0 * h.powf(0.1);
        let runs: Vec<MethodRun> = [1.0, 0.5, 0.25]
            .into_iter()
            .map(|h: f64| fe(h, vec![vec![500.0, 500.0]], vec![te(h)]))
            .collect();
        let r = extrapolate(&runs).unwrap();
        assert!((r.te_order[0] - 0.1).abs() < 1e-9, "{}", r.te_order[0]);
        assert_eq!(r.run.te_urad[0], te(0.25));
        let expected = 3.0 * (te(1.0) - te(0.25)) / te(0.25);
        assert!((r.te_uncertainty[0] - expected).abs() < 1e-12);
        assert_eq!(r.fallbacks, 3, "the TE and both (unchanged) shares");
    }
}
