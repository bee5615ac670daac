//! Monte Carlo draws of tolerances: normal, uniform and truncated normal
//! distributions, sampled from a ChaCha8 stream per sample (seed, stream =
//! sample index), so sample i is the same whatever the number of samples
//! and on every platform (rand's `StdRng` promises neither).

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution as _, Normal};

/// Bound on the rejection loop of the truncated normal; the constructor
/// refuses truncations whose acceptance is below [`MIN_ACCEPTANCE`], so the
/// bound is reached with probability below (1 − 1e-3)^100 000 ≈ 4e-44.
const MAX_REJECTIONS: usize = 100_000;
const MIN_ACCEPTANCE: f64 = 1e-3;

/// A distribution of one scene key.
#[derive(Clone, Debug, PartialEq)]
pub enum Distribution {
    Normal {
        mean: f64,
        sd: f64,
    },
    Uniform {
        low: f64,
        high: f64,
    },
    /// Normal(mean, sd) restricted to [low, high] (rejection sampling).
    TruncatedNormal {
        mean: f64,
        sd: f64,
        low: f64,
        high: f64,
    },
}

impl Distribution {
    /// From the campaign file's `distribution = "normal" | "uniform" |
    /// "truncated_normal"` and its parameters; the message says what is wrong.
    pub fn new(
        kind: &str,
        mean: Option<f64>,
        sd: Option<f64>,
        low: Option<f64>,
        high: Option<f64>,
    ) -> Result<Self, String> {
        let need = |v: Option<f64>, name: &str| -> Result<f64, String> {
            let x = v.ok_or_else(|| format!("{kind} needs `{name}`"))?;
            if !x.is_finite() {
                return Err(format!("`{name}` = {x}: must be finite"));
            }
            Ok(x)
        };
        let none = |v: Option<f64>, name: &str| -> Result<(), String> {
            match v {
                Some(_) => Err(format!("`{name}` is not a parameter of {kind}")),
                None => Ok(()),
            }
        };
        let spread = |sd: f64| -> Result<f64, String> {
            if sd < 0.0 {
                Err(format!("`sd` = {sd}: a spread must not be negative"))
            } else {
                Ok(sd)
            }
        };
        match kind {
            "normal" => {
                none(low, "low")?;
                none(high, "high")?;
                Ok(Self::Normal {
                    mean: need(mean, "mean")?,
                    sd: spread(need(sd, "sd")?)?,
                })
            }
            "uniform" => {
                none(mean, "mean")?;
                none(sd, "sd")?;
                let (low, high) = (need(low, "low")?, need(high, "high")?);
                if !(low <= high) {
                    return Err(format!("`low` = {low} above `high` = {high}"));
                }
                Ok(Self::Uniform { low, high })
            }
            "truncated_normal" => {
                let (mean, sd) = (need(mean, "mean")?, spread(need(sd, "sd")?)?);
                let (low, high) = (need(low, "low")?, need(high, "high")?);
                if !(low <= high) {
                    return Err(format!("`low` = {low} above `high` = {high}"));
                }
                let p = if sd == 0.0 {
                    f64::from(u8::from((low..=high).contains(&mean)))
                } else {
                    normal_cdf((high - mean) / sd) - normal_cdf((low - mean) / sd)
                };
                if p < MIN_ACCEPTANCE {
                    return Err(format!(
                        "[{low}, {high}] holds {p:.1e} of Normal({mean}, {sd}): below {MIN_ACCEPTANCE:e}, move the bounds"
                    ));
                }
                Ok(Self::TruncatedNormal {
                    mean,
                    sd,
                    low,
                    high,
                })
            }
            other => Err(format!(
                "unknown distribution \"{other}\" (normal, uniform, truncated_normal)"
            )),
        }
    }

    /// One draw.
    fn draw(&self, rng: &mut ChaCha8Rng) -> f64 {
        match *self {
            Self::Normal { mean, sd } => normal(mean, sd, rng),
            Self::Uniform { low, high } => {
                if low == high {
                    low
                } else {
                    rng.random_range(low..=high)
                }
            }
            Self::TruncatedNormal {
                mean,
                sd,
                low,
                high,
            } => {
                for _ in 0..MAX_REJECTIONS {
                    let x = normal(mean, sd, rng);
                    if (low..=high).contains(&x) {
                        return x;
                    }
                }
                // unreachable in practice (see MAX_REJECTIONS); the clamp keeps
                // the value inside the declared range
                mean.clamp(low, high)
            }
        }
    }
}

fn normal(mean: f64, sd: f64, rng: &mut ChaCha8Rng) -> f64 {
    if sd == 0.0 {
        return mean;
    }
    // sd > 0 and finite: checked by Distribution::new
    Normal::new(mean, sd).map_or(mean, |n| n.sample(rng))
}

/// Φ(x) of the standard normal, from erfc (Numerical Recipes 3rd ed. §6.2.2,
/// Chebyshev fit, |error| < 1.2e-7): only for the acceptance check.
fn normal_cdf(x: f64) -> f64 {
    0.5 * erfc(-x / std::f64::consts::SQRT_2)
}

fn erfc(x: f64) -> f64 {
    let z = x.abs();
    let t = 1.0 / (1.0 + 0.5 * z);
    let r = t
        * (-z * z - 1.26551223
            + t * (1.00002368
                + t * (0.37409196
                    + t * (0.09678418
                        + t * (-0.18628806
                            + t * (0.27886807
                                + t * (-1.13520398
                                    + t * (1.48851587 + t * (-0.82215223 + t * 0.17087277)))))))))
            .exp();
    if x >= 0.0 {
        r
    } else {
        2.0 - r
    }
}

/// The values of sample `index` of every distribution, in order: a ChaCha8
/// stream with the campaign's seed and stream number `index`.
pub fn sample(seed: u64, index: usize, distributions: &[&Distribution]) -> Vec<f64> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(index as u64);
    distributions.iter().map(|d| d.draw(&mut rng)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn stats(d: &Distribution, n: usize) -> (f64, f64, f64, f64) {
        let xs: Vec<f64> = (0..n).map(|i| sample(7, i, &[d])[0]).collect();
        let mean = xs.iter().sum::<f64>() / n as f64;
        let var = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1) as f64;
        let lo = xs.iter().cloned().fold(f64::INFINITY, f64::min);
        let hi = xs.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
        (mean, var.sqrt(), lo, hi)
    }

    #[test]
    fn moments_match_the_distributions() {
        // n = 20 000: the standard error of the mean is sd/141, of the sd ≈ sd/200
        let n = 20_000;
        let (m, s, _, _) = stats(
            &Distribution::new("normal", Some(3.0), Some(2.0), None, None).unwrap(),
            n,
        );
        assert!((m - 3.0).abs() < 4.0 * 2.0 / (n as f64).sqrt(), "{m}");
        assert!((s - 2.0).abs() < 0.04, "{s}");
        // uniform [−1, 5]: mean 2, sd 6/√12
        let (m, s, lo, hi) = stats(
            &Distribution::new("uniform", None, None, Some(-1.0), Some(5.0)).unwrap(),
            n,
        );
        assert!((m - 2.0).abs() < 4.0 * 1.732 / (n as f64).sqrt(), "{m}");
        assert!((s - 6.0 / 12f64.sqrt()).abs() < 0.03, "{s}");
        assert!(lo >= -1.0 && hi <= 5.0);
        // half-normal truncation [0, ∞) of N(0, 1): mean √(2/π), sd √(1 − 2/π)
        let d = Distribution::new(
            "truncated_normal",
            Some(0.0),
            Some(1.0),
            Some(0.0),
            Some(1e9),
        )
        .unwrap();
        let (m, s, lo, _) = stats(&d, n);
        assert!(
            (m - (2.0 / std::f64::consts::PI).sqrt()).abs() < 0.02,
            "{m}"
        );
        assert!(
            (s - (1.0 - 2.0 / std::f64::consts::PI).sqrt()).abs() < 0.02,
            "{s}"
        );
        assert!(lo >= 0.0);
    }

    #[test]
    fn streams_are_reproducible_and_independent_of_n() {
        let d = Distribution::new("normal", Some(0.0), Some(1.0), None, None).unwrap();
        assert_eq!(sample(1, 5, &[&d, &d]), sample(1, 5, &[&d, &d]));
        assert_ne!(sample(1, 5, &[&d]), sample(1, 6, &[&d]));
        assert_ne!(sample(1, 5, &[&d]), sample(2, 5, &[&d]));
    }

    #[test]
    fn bad_parameters_are_refused() {
        let e = Distribution::new("normal", Some(0.0), Some(-1.0), None, None).unwrap_err();
        assert!(e.contains("must not be negative"), "{e}");
        let e = Distribution::new("uniform", None, None, Some(2.0), Some(1.0)).unwrap_err();
        assert!(e.contains("above"), "{e}");
        let e = Distribution::new("normal", Some(0.0), None, None, None).unwrap_err();
        assert!(e.contains("needs `sd`"), "{e}");
        let e = Distribution::new(
            "truncated_normal",
            Some(0.0),
            Some(1.0),
            Some(8.0),
            Some(9.0),
        )
        .unwrap_err();
        assert!(e.contains("move the bounds"), "{e}");
        let e = Distribution::new("lognormal", None, None, None, None).unwrap_err();
        assert!(e.contains("unknown distribution"), "{e}");
        // Φ(1.96) = 0.975 (table value)
        assert!((normal_cdf(1.96) - 0.9750021).abs() < 1e-6);
    }
}
