//! Bounded iterative loops, and how close each came to its bound.
//!
//! Every iterative loop in flank stops at a limit (Newton, fixed points,
//! active sets, pivoting; the list with each limit and what happens at it
//! is `docs/iteration_limits.md`). A loop that reaches its limit either
//! returns an error that gives its residual there, or returns its last
//! iterate, flagged. An analysis gathers one [`LoopEnd`] per call into an
//! [`IterationLimits`] tally and writes it under `iteration_limits` in its
//! `summary.json`: per loop its limit, the most iterations a call used, how
//! many calls reached the limit without converging and the largest residual
//! they left, so that a reader sees a bound that was hit next to the figure
//! it affects.

use std::collections::BTreeMap;

/// How one call of a bounded loop ended.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LoopEnd {
    /// Iterations the call used.
    pub iterations: usize,
    /// The loop's limit on iterations.
    pub limit: usize,
    /// The call met its tolerance (false: it stopped at its limit).
    pub converged: bool,
    /// The residual the call ended with (in the loop's own measure).
    pub residual: f64,
}

impl LoopEnd {
    /// A loop that met its tolerance.
    pub fn converged(iterations: usize, limit: usize, residual: f64) -> Self {
        LoopEnd {
            iterations,
            limit,
            converged: true,
            residual,
        }
    }

    /// A loop that stopped at its limit with `residual` left.
    pub fn at_limit(iterations: usize, limit: usize, residual: f64) -> Self {
        LoopEnd {
            iterations,
            limit,
            converged: false,
            residual,
        }
    }
}

/// The calls of one loop over an analysis.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct LoopTally {
    /// What the residual measures (and its unit or scale).
    pub residual: &'static str,
    /// The loop's tolerance on that residual.
    pub tolerance: f64,
    /// The limit on iterations (the largest, if calls differ).
    pub limit: usize,
    pub calls: usize,
    /// Most iterations of any call.
    pub most_iterations: usize,
    /// Calls that stopped at the limit without meeting the tolerance.
    pub limit_hits: usize,
    /// The largest residual such a call left (null if none hit).
    pub largest_residual_at_limit: Option<f64>,
    /// The largest residual of any call.
    pub largest_residual: f64,
}

/// The loops of one analysis, by name (`module.loop`).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
#[serde(transparent)]
pub struct IterationLimits(BTreeMap<&'static str, LoopTally>);

impl IterationLimits {
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds one call of loop `name`, whose residual is `residual` (a
    /// description) with tolerance `tolerance`.
    pub fn record(
        &mut self,
        name: &'static str,
        residual: &'static str,
        tolerance: f64,
        end: LoopEnd,
    ) {
        let t = self.0.entry(name).or_insert(LoopTally {
            residual,
            tolerance,
            limit: 0,
            calls: 0,
            most_iterations: 0,
            limit_hits: 0,
            largest_residual_at_limit: None,
            largest_residual: 0.0,
        });
        t.limit = t.limit.max(end.limit);
        t.calls += 1;
        t.most_iterations = t.most_iterations.max(end.iterations);
        t.largest_residual = max_nan(t.largest_residual, end.residual);
        if !end.converged {
            t.limit_hits += 1;
            t.largest_residual_at_limit = Some(match t.largest_residual_at_limit {
                Some(r) => max_nan(r, end.residual),
                None => end.residual,
            });
        }
    }

    /// Adds every call of `other`.
    pub fn merge(&mut self, other: &IterationLimits) {
        for (&name, o) in &other.0 {
            match self.0.get_mut(name) {
                None => {
                    self.0.insert(name, o.clone());
                }
                Some(t) => {
                    t.limit = t.limit.max(o.limit);
                    t.calls += o.calls;
                    t.most_iterations = t.most_iterations.max(o.most_iterations);
                    t.limit_hits += o.limit_hits;
                    t.largest_residual = max_nan(t.largest_residual, o.largest_residual);
                    t.largest_residual_at_limit =
                        match (t.largest_residual_at_limit, o.largest_residual_at_limit) {
                            (Some(a), Some(b)) => Some(max_nan(a, b)),
                            (a, b) => a.or(b),
                        };
                }
            }
        }
    }

    /// The tally of loop `name`, if it ran.
    pub fn get(&self, name: &str) -> Option<&LoopTally> {
        self.0.get(name)
    }

    /// Calls, over all loops, that stopped at their limit.
    pub fn limit_hits(&self) -> usize {
        self.0.values().map(|t| t.limit_hits).sum()
    }

    /// One line per loop that hit its limit, for the notes and warnings of
    /// an analysis.
    pub fn warnings(&self) -> Vec<String> {
        self.0
            .iter()
            .filter(|(_, t)| t.limit_hits > 0)
            .map(|(name, t)| {
                format!(
                    "{name}: {} of {} calls stopped at the iteration limit {} with {} up to {:.3e} (tolerance {:.1e})",
                    t.limit_hits,
                    t.calls,
                    t.limit,
                    t.residual,
                    t.largest_residual_at_limit.unwrap_or(f64::NAN),
                    t.tolerance
                )
            })
            .collect()
    }

    /// The tally as the `iteration_limits` object of a summary.
    pub fn to_json(&self) -> serde_json::Value {
        serde_json::to_value(self).unwrap_or(serde_json::Value::Null)
    }
}

/// max that keeps a NaN (a NaN residual is the worst there is).
fn max_nan(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() {
        f64::NAN
    } else {
        a.max(b)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tally_counts_calls_iterations_and_hits() {
        let mut l = IterationLimits::new();
        l.record(
            "a.newton",
            "|r| (mm)",
            1e-10,
            LoopEnd::converged(3, 30, 1e-12),
        );
        l.record(
            "a.newton",
            "|r| (mm)",
            1e-10,
            LoopEnd::at_limit(30, 30, 2e-6),
        );
        l.record(
            "a.newton",
            "|r| (mm)",
            1e-10,
            LoopEnd::at_limit(30, 30, 5e-7),
        );
        let t = l.get("a.newton").unwrap();
        assert_eq!(
            (t.calls, t.most_iterations, t.limit_hits, t.limit),
            (3, 30, 2, 30)
        );
        assert_eq!(t.largest_residual_at_limit, Some(2e-6));
        assert_eq!(l.limit_hits(), 2);
        let w = l.warnings();
        assert_eq!(w.len(), 1);
        assert!(
            w[0].contains("2 of 3 calls") && w[0].contains("2.000e-6"),
            "{}",
            w[0]
        );
        let j = l.to_json();
        assert_eq!(j["a.newton"]["limit_hits"], 2);
        assert_eq!(j["a.newton"]["most_iterations"], 30);
    }

    #[test]
    fn converged_calls_leave_no_residual_at_limit() {
        let mut l = IterationLimits::new();
        l.record(
            "b.fixed_point",
            "change",
            1e-2,
            LoopEnd::converged(2, 4, 3e-3),
        );
        let t = l.get("b.fixed_point").unwrap();
        assert_eq!(t.largest_residual_at_limit, None);
        assert_eq!(t.largest_residual, 3e-3);
        assert!(l.warnings().is_empty());
        assert!(l.to_json()["b.fixed_point"]["largest_residual_at_limit"].is_null());
    }

    #[test]
    fn merge_adds_calls_and_keeps_the_worst() {
        let mut a = IterationLimits::new();
        a.record("x", "r", 1e-9, LoopEnd::at_limit(5, 5, 1e-3));
        let mut b = IterationLimits::new();
        b.record("x", "r", 1e-9, LoopEnd::converged(2, 5, 1e-12));
        b.record("x", "r", 1e-9, LoopEnd::at_limit(5, 5, 4e-3));
        b.record("y", "s", 1e-9, LoopEnd::converged(1, 9, 0.0));
        a.merge(&b);
        let x = a.get("x").unwrap();
        assert_eq!((x.calls, x.limit_hits), (3, 2));
        assert_eq!(x.largest_residual_at_limit, Some(4e-3));
        assert_eq!(a.get("y").unwrap().limit, 9);
    }

    #[test]
    fn a_nan_residual_is_kept() {
        let mut l = IterationLimits::new();
        l.record("n", "r", 1e-9, LoopEnd::at_limit(5, 5, 1.0));
        l.record("n", "r", 1e-9, LoopEnd::at_limit(5, 5, f64::NAN));
        assert!(l
            .get("n")
            .unwrap()
            .largest_residual_at_limit
            .unwrap()
            .is_nan());
    }
}
