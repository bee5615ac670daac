//! The wet–dry loop of a lubricated loaded tooth contact analysis (seed
//! 002 §2.9, §3.3): a "dry" contact pass at a constant μ₀, the EHL model
//! gives μ per contact (position × tooth pair), a "wet" pass runs again
//! with that μ, and so on until the largest relative change of μ between
//! two passes is below the tolerance, within a bounded number of wet
//! passes (hitting the bound is reported, not an error).
//!
//! The contact solver is a closure (FE mesh cycle or LTCA): given the μ of
//! every (position, pair), it returns the operating point of every loaded
//! contact. This module evaluates the EHL and keeps every pass's figures.

use crate::error::FlankError;
use crate::lubrication::film::FilmModel;
use crate::lubrication::lubricant::Lubricant;
use crate::lubrication::operating_point::{evaluate, ContactEhl, OperatingPoint};

/// Relative changes of μ are taken against max(μ_used, this): a contact
/// whose μ is (near) zero (pure rolling with the isothermal fallback of
/// [`crate::lubrication::traction`](mod@crate::lubrication::traction)) does not make the change infinite.
pub const MU_FLOOR: f64 = 1e-4;

/// Settings of the loop (`[analyses.lubrication]`).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct LoopSettings {
    pub film: FilmModel,
    /// Largest relative change of μ that ends the loop (default 0.005).
    pub tolerance: f64,
    /// Largest number of wet passes (default 10).
    pub max_iterations: usize,
    /// μ₀ of the dry pass.
    pub initial_mu: f64,
    /// Composite roughness σ = (R_q1² + R_q2²)^½ (mm) for the λ ratio.
    pub composite_roughness_mm: Option<f64>,
    /// Where P̄ comes from (used by the contact pass that builds the
    /// operating points).
    pub mean_pressure: crate::lubrication::operating_point::MeanPressure,
}

/// μ (or any value) per position and tooth pair.
pub type Table<T> = Vec<Vec<T>>;

/// One contact pass and the EHL evaluated on its solution.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Pass {
    /// 0: the dry pass.
    pub index: usize,
    /// μ the pass was solved with.
    pub mu_used: Table<f64>,
    /// EHL of every loaded contact of the pass (None: not loaded).
    pub contacts: Table<Option<ContactEhl>>,
    /// Largest relative change (μ_EHL − μ_used)/max(μ_used, [`MU_FLOOR`]) over the loaded
    /// contacts, signed (the entry of largest magnitude), and where.
    pub change_rel: f64,
    pub change_at: Option<(usize, usize)>,
}

/// The loop's answer.
#[derive(Clone, Debug, serde::Serialize)]
pub struct LoopResult {
    pub passes: Vec<Pass>,
    /// Wet passes run (passes − 1).
    pub iterations: usize,
    pub converged: bool,
    /// The change of the last pass (signed).
    pub mu_last_change_rel: f64,
    pub warnings: Vec<String>,
}

impl LoopResult {
    /// The last pass (its contacts are the final answer).
    pub fn last(&self) -> &Pass {
        self.passes.last().expect("at least the dry pass")
    }
}

/// Checks the settings.
pub fn check_settings(s: &LoopSettings) -> Result<(), FlankError> {
    if !(s.tolerance > 0.0 && s.tolerance < 1.0) {
        return Err(FlankError::Model(format!(
            "lubrication loop: tolerance {} must be in (0, 1) (relative change of μ)",
            s.tolerance
        )));
    }
    if !(1..=100).contains(&s.max_iterations) {
        return Err(FlankError::Model(format!(
            "lubrication loop: max_iterations {} must be in 1 … 100",
            s.max_iterations
        )));
    }
    if !(s.initial_mu > 0.0 && s.initial_mu <= 1.0) {
        return Err(FlankError::Model(format!(
            "lubrication loop: the dry pass needs μ₀ in (0, 1], got {}",
            s.initial_mu
        )));
    }
    if let Some(r) = s.composite_roughness_mm {
        if !(r > 0.0 && r.is_finite()) {
            return Err(FlankError::Model(format!(
                "lubrication loop: composite roughness {r} mm must be > 0"
            )));
        }
    }
    Ok(())
}

/// Runs the loop over `positions` × `pairs` contacts. `solve(pass, μ)`
/// solves the contact problem with μ per (position, pair) and returns the
/// operating point of each loaded contact.
pub fn wet_dry_loop<F>(
    lub: &Lubricant,
    settings: &LoopSettings,
    positions: usize,
    pairs: usize,
    mut solve: F,
) -> Result<LoopResult, FlankError>
where
    F: FnMut(usize, &Table<f64>) -> Result<Table<Option<OperatingPoint>>, FlankError>,
{
    check_settings(settings)?;
    lub.validate()?;
    let mut mu = vec![vec![settings.initial_mu; pairs]; positions];
    let mut passes = Vec::new();
    let mut converged = false;
    for index in 0..=settings.max_iterations {
        let points = solve(index, &mu)?;
        if points.len() != positions || points.iter().any(|r| r.len() != pairs) {
            return Err(FlankError::Model(format!(
                "lubrication loop: the contact pass returned {} positions for {positions}",
                points.len()
            )));
        }
        let mut next = mu.clone();
        let mut contacts = vec![vec![None; pairs]; positions];
        let mut change = 0.0f64;
        let mut change_at = None;
        for i in 0..positions {
            for p in 0..pairs {
                let Some(op) = &points[i][p] else { continue };
                let c = evaluate(lub, settings.film, op, settings.composite_roughness_mm).map_err(
                    |e| match e {
                        FlankError::Model(m) => FlankError::Model(format!(
                            "lubrication pass {index}, position {}, tooth pair {}: {m}",
                            i + 1,
                            p + 1
                        )),
                        e => e,
                    },
                )?;
                let rel = (c.traction.mu - mu[i][p]) / mu[i][p].max(MU_FLOOR);
                if rel.abs() > change.abs() {
                    change = rel;
                    change_at = Some((i, p));
                }
                next[i][p] = c.traction.mu;
                contacts[i][p] = Some(c);
            }
        }
        if change_at.is_none() && contacts.iter().flatten().all(|c| c.is_none()) {
            return Err(FlankError::Model(format!(
                "lubrication pass {index}: no loaded contact at any position"
            )));
        }
        passes.push(Pass {
            index,
            mu_used: std::mem::replace(&mut mu, next),
            contacts,
            change_rel: change,
            change_at,
        });
        if change.abs() < settings.tolerance {
            converged = true;
            break;
        }
    }
    let last = passes.last().map_or(0.0, |p| p.change_rel);
    let mut warnings = Vec::new();
    if !converged {
        warnings.push(format!(
            "the wet–dry loop stopped at its bound of {} wet passes with a largest relative change of μ of {:+.3} % (tolerance {} %)",
            settings.max_iterations,
            100.0 * last,
            percent(settings.tolerance)
        ));
    }
    Ok(LoopResult {
        iterations: passes.len() - 1,
        converged,
        mu_last_change_rel: last,
        passes,
        warnings,
    })
}

/// A relative figure as a percentage for messages: up to three decimals
/// with the trailing zeros dropped ("0.5") from 0.001 % on, else in
/// exponent form ("1.0e-7"), never the float's full expansion.
fn percent(rel: f64) -> String {
    let p = 100.0 * rel;
    if p.abs() >= 1e-3 && p.abs() < 1e6 {
        let s = format!("{p:.3}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        format!("{p:.1e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lubrication::lubricant::test_oil;

    fn point(load: f64) -> OperatingPoint {
        OperatingPoint {
            load_n: load,
            contact_area_mm2: load / 1000.0,
            mean_pressure_mpa: 1000.0,
            radius_x_mm: 8.0,
            radius_y_mm: f64::INFINITY,
            length_mm: 13.3,
            entraining_speed_mm_s: 20_000.0,
            sliding_speed_mm_s: 5_000.0,
            reduced_modulus_mpa: 226_000.0,
            outside_path: false,
            other_mean_pressure_mpa: 0.0,
            hertz_peak_mpa: 0.0,
        }
    }

    fn settings() -> LoopSettings {
        LoopSettings {
            film: FilmModel::Chittenden,
            tolerance: 0.005,
            max_iterations: 5,
            initial_mu: 0.05,
            composite_roughness_mm: None,
            mean_pressure: Default::default(),
        }
    }

    #[test]
    fn fixed_load_converges_in_one_wet_pass() {
        let lub = Lubricant::from_si(&test_oil()).unwrap();
        // the load does not depend on μ: the first wet pass repeats the dry μ_EHL
        let r = wet_dry_loop(&lub, &settings(), 2, 2, |_, _| {
            Ok(vec![vec![Some(point(5000.0)), None]; 2])
        })
        .unwrap();
        assert!(r.converged);
        assert_eq!(r.iterations, 1);
        assert_eq!(r.mu_last_change_rel, 0.0);
        let mu = r.last().contacts[0][0].as_ref().unwrap().traction.mu;
        assert!(mu > 0.0 && mu < 0.1, "{mu}");
        assert!((r.passes[0].change_rel - (mu - 0.05) / 0.05).abs() < 1e-12);
    }

    #[test]
    fn the_bound_is_reported() {
        let lub = Lubricant::from_si(&test_oil()).unwrap();
        // a load that keeps moving with μ never settles within 1e-9
        let mut s = settings();
        s.tolerance = 1e-9;
        s.max_iterations = 3;
        let r = wet_dry_loop(&lub, &s, 1, 1, |pass, _| {
            Ok(vec![vec![Some(point(4000.0 + 100.0 * pass as f64))]])
        })
        .unwrap();
        assert!(!r.converged);
        assert_eq!(r.iterations, 3);
        assert!(r.warnings[0].contains("bound of 3"), "{:?}", r.warnings);
        // 1e-9 relative is 1e-7 % (it printed "0.00000010000000000000001 %")
        assert!(
            r.warnings[0].contains("(tolerance 1.0e-7 %)"),
            "{:?}",
            r.warnings
        );
    }

    #[test]
    fn tolerances_print_short() {
        assert_eq!(percent(0.005), "0.5");
        assert_eq!(percent(0.01), "1");
        assert_eq!(percent(0.0012345), "0.123");
        assert_eq!(percent(1e-9), "1.0e-7");
        assert_eq!(percent(1e-5), "0.001");
        assert_eq!(percent(2e-6), "2.0e-4");
    }
}
