//! Discretisation error from three grids: observed order of convergence,
//! Richardson extrapolation and the grid convergence index (GCI).
//!
//! Roache, "Verification and Validation in Computational Science and
//! Engineering", Hermosa 1998; ASME V&V 20-2009 §2.4; the procedure as
//! written out by Celik et al., "Procedure for estimation and reporting of
//! uncertainty due to discretization in CFD applications", J. Fluids Eng.
//! 130 (2008) 078001, eqs. (1)–(10), for non-constant refinement ratios:
//!
//! * h1 < h2 < h3 cell sizes, φ1, φ2, φ3 their results; r21 = h2/h1,
//!   r32 = h3/h2; ε21 = φ2 − φ1, ε32 = φ3 − φ2; s = sign(ε32/ε21);
//! * p = |ln|ε32/ε21| + q(p)| / ln r21, q(p) = ln((r21^p − s)/(r32^p − s)),
//!   solved by fixed-point iteration (q = 0 and one pass when r21 = r32);
//! * φ_ext = (r21^p φ1 − φ2)/(r21^p − 1);
//! * e_a = |(φ1 − φ2)/φ1|, e_ext = |(φ_ext − φ1)/φ_ext|;
//! * GCI_fine = F_s e_a/(r21^p − 1), F_s = 1.25 for three grids (Roache).

/// Bound on the fixed-point iterations for p.
const MAX_ITERATIONS: usize = 200;
const TOLERANCE: f64 = 1e-12;
/// Relative change below which two grids count as equal.
const ROUND_OFF: f64 = 1e-12;

/// The estimate from three grids.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Gci {
    /// Observed order p.
    pub order: f64,
    /// Richardson-extrapolated value φ_ext.
    pub extrapolated: f64,
    /// Relative change fine–medium e_a (None when φ1 = 0).
    pub approximate_error: Option<f64>,
    /// Relative error of the fine grid against φ_ext (None when φ_ext = 0).
    pub extrapolated_error: Option<f64>,
    /// GCI of the fine grid (relative; None when φ1 = 0).
    pub gci_fine: Option<f64>,
    /// The changes alternate in sign (oscillatory convergence: p is then
    /// less reliable, Celik et al. 2008).
    pub oscillatory: bool,
    /// Fixed-point iterations used.
    pub iterations: usize,
}

/// Why no estimate was made.
#[derive(Clone, Debug, PartialEq)]
pub enum GciIssue {
    /// The sizes are not strictly increasing and positive.
    BadSizes,
    /// φ1 = φ2 or φ2 = φ3: no change to measure the order from (converged
    /// to the last digit, or a figure independent of the mesh).
    NoChange,
    /// The order iteration did not settle within the bound.
    NotConverged,
    /// The changes grow under refinement (the signed order of eq. (2),
    /// without its absolute value, is ≤ 0; given here).
    Diverging(f64),
}

impl std::fmt::Display for GciIssue {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        match self {
            Self::BadSizes => write!(f, "cell sizes not increasing"),
            Self::NoChange => write!(f, "no change between grids"),
            Self::NotConverged => write!(f, "order iteration hit its bound ({MAX_ITERATIONS})"),
            Self::Diverging(p) => write!(f, "diverging (p = {p:.3})"),
        }
    }
}

/// GCI from sizes `h` (fine, medium, coarse) and results `phi`, F_s = `fs`.
pub fn gci(h: [f64; 3], phi: [f64; 3], fs: f64) -> Result<Gci, GciIssue> {
    let [h1, h2, h3] = h;
    if !(h1 > 0.0 && h2 > h1 && h3 > h2) {
        return Err(GciIssue::BadSizes);
    }
    let (r21, r32) = (h2 / h1, h3 / h2);
    let (e21, e32) = (phi[1] - phi[0], phi[2] - phi[1]);
    // changes at round-off level carry no order
    let noise = ROUND_OFF * phi.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    if e21.abs() <= noise || e32.abs() <= noise {
        return Err(GciIssue::NoChange);
    }
    let ratio = e32 / e21;
    let s = ratio.signum();
    let a = ratio.abs().ln();
    // Celik's start (q = 0); where that is 0 (equal changes on unequal
    // ratios) q(0) is 0/0, so start from first order instead
    let mut p = (a / r21.ln()).abs();
    if p < 1e-3 {
        p = 1.0;
    }
    let mut iterations = 0;
    let mut settled = false;
    for _ in 0..MAX_ITERATIONS {
        iterations += 1;
        let q = ((r21.powf(p) - s) / (r32.powf(p) - s)).ln();
        let next = ((a + q) / r21.ln()).abs();
        if !next.is_finite() {
            return Err(GciIssue::NotConverged);
        }
        let done = (next - p).abs() <= TOLERANCE * next.max(1.0);
        p = next;
        if done {
            settled = true;
            break;
        }
    }
    if !settled {
        return Err(GciIssue::NotConverged);
    }
    // eq. (2)'s absolute value also gives a positive p to changes that
    // grow under refinement (|ε21| > |ε32| at r21 = r32): the signed
    // value (ln|ε32/ε21| + q(p)) / ln r21 is > 0 only where they shrink
    let q = ((r21.powf(p) - s) / (r32.powf(p) - s)).ln();
    let signed = (a + q) / r21.ln();
    if !(p > 0.0) || !(signed > 0.0) {
        return Err(GciIssue::Diverging(signed));
    }
    let rp = r21.powf(p);
    let extrapolated = (rp * phi[0] - phi[1]) / (rp - 1.0);
    let approximate_error = (phi[0] != 0.0).then(|| ((phi[0] - phi[1]) / phi[0]).abs());
    let extrapolated_error =
        (extrapolated != 0.0).then(|| ((extrapolated - phi[0]) / extrapolated).abs());
    Ok(Gci {
        order: p,
        extrapolated,
        approximate_error,
        extrapolated_error,
        gci_fine: approximate_error.map(|e| fs * e / (rp - 1.0)),
        oscillatory: s < 0.0,
        iterations,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// φ(h) = φ0 + C h^p exactly: the observed order is p and the
    /// extrapolation φ0, for constant and non-constant ratios.
    #[test]
    fn recovers_a_power_law() {
        for (h, p) in [
            ([0.1, 0.2, 0.4], 2.0),
            ([0.1, 0.25, 0.5], 1.5),
            ([0.25, 0.5, 0.75], 3.0),
        ] {
            let phi = h.map(|x: f64| 7.0 + 0.8 * x.powf(p));
            let g = gci(h, phi, 1.25).unwrap();
            assert!((g.order - p).abs() < 1e-9, "{g:?}");
            assert!((g.extrapolated - 7.0).abs() < 1e-10, "{g:?}");
            // GCI = Fs |φ1 − φ2|/φ1/(r^p − 1) = Fs |φ1 − φ_ext|/φ1 for exact data
            let gci = g.gci_fine.unwrap();
            assert!(
                (gci - 1.25 * (phi[0] - 7.0) / phi[0]).abs() < 1e-12,
                "{gci}"
            );
            assert!(!g.oscillatory);
        }
    }

    /// Celik et al. (2008), Table 1, column φ = φ1 (reattachment length):
    /// N = 18 000 / 8 000 / 4 500 cells (2D, h = (A/N)^½: r21 = 1.5,
    /// r32 = 1.333), φ = 6.063 / 5.972 / 5.863 → p = 1.53, φ_ext = 6.1685,
    /// e_a = 1.5 %, e_ext = 1.7 %, GCI_fine = 2.17 %.
    #[test]
    fn celik_2008_table_1() {
        let h = [
            1.0 / 18000f64.sqrt(),
            1.0 / 8000f64.sqrt(),
            1.0 / 4500f64.sqrt(),
        ];
        let g = gci(h, [6.063, 5.972, 5.863], 1.25).unwrap();
        assert!((g.order - 1.53).abs() < 0.005, "{g:?}");
        assert!((g.extrapolated - 6.1685).abs() < 0.0005, "{g:?}");
        assert!(
            (g.approximate_error.unwrap() - 0.015).abs() < 0.0005,
            "{g:?}"
        );
        assert!(
            (g.extrapolated_error.unwrap() - 0.017).abs() < 0.0005,
            "{g:?}"
        );
        assert!((g.gci_fine.unwrap() - 0.0217).abs() < 0.0005, "{g:?}");
    }

    /// Growing changes (contact bands at −8.43°, pair 3 mid face:
    /// 1448.3 / 1482.6 / 1528.4 MPa on 0.1 / 0.0707 / 0.05 mm) are
    /// diverging, though eq. (2)'s absolute value gives them an order; a
    /// power law is not, and neither are equal ratios with shrinking
    /// changes.
    #[test]
    fn growing_changes_are_diverging() {
        let h = [0.05, 0.1 / 2f64.sqrt(), 0.1];
        let phi = [1528.3832812794735, 1482.6, 1448.3];
        assert!(matches!(gci(h, phi, 1.25), Err(GciIssue::Diverging(p)) if p < 0.0));
        // growing, equal ratios, both signs of the changes
        let h = [0.1, 0.2, 0.4];
        assert!(matches!(
            gci(h, [1.0, 1.4, 1.6], 1.25),
            Err(GciIssue::Diverging(_))
        ));
        assert!(matches!(
            gci(h, [1.0, 0.6, 0.8], 1.25),
            Err(GciIssue::Diverging(_))
        ));
        let h = [0.1, 0.25, 0.5];
        let phi = h.map(|x: f64| 7.0 + 0.8 * x.powf(1.5));
        let g = gci(h, phi, 1.25).unwrap();
        assert!((g.order - 1.5).abs() < 1e-9, "{g:?}");
    }

    #[test]
    fn degenerate_inputs_are_reported() {
        assert_eq!(
            gci([0.1, 0.1, 0.2], [1.0, 2.0, 3.0], 1.25),
            Err(GciIssue::BadSizes)
        );
        assert_eq!(
            gci([0.1, 0.2, 0.4], [1.0, 1.0, 3.0], 1.25),
            Err(GciIssue::NoChange)
        );
        // linear data on unequal ratios: p = 1 (the start q = 0 gives p = 0)
        let g = gci([1.0, 1.25, 1.5], [1.0, 1.25, 1.5], 1.25).unwrap();
        assert!((g.order - 1.0).abs() < 1e-9, "{g:?}");
        assert_eq!(
            gci([0.1, 0.2, 0.4], [1.0, 1.0 + 1e-15, 3.0], 1.25),
            Err(GciIssue::NoChange)
        );
        let g = gci([0.1, 0.2, 0.4], [1.0, 1.1, 0.9], 1.25).unwrap();
        assert!(g.oscillatory);
    }
}
