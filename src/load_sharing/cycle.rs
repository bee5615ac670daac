//! Load sharing per tooth pair over a mesh cycle and the **functional
//! contact ratio** of seed `000_…`: the roll-angle span over which a tooth
//! pair carries load, divided by the angular pitch.
//!
//! The teeth are turned copies of one tooth, so a pair's loaded span over
//! its whole mesh equals the loaded spans of all pairs within one pitch of
//! roll summed: with N positions evenly spread over one pitch,
//!
//! ```text
//! ε_f = (1/N) Σ_positions #{pairs with P_k > ρ Σ_j P_j}
//! ```
//!
//! (the mean number of loaded pairs), ρ = [`LOADED_SHARE`]. The
//! **single-pair zone** is the part of the pitch where exactly one pair is
//! loaded. Only the sector's pairs are modelled: a pair beyond the sector
//! that would come within the loaded approach is reported by the caller.

/// Share of the position's total normal force above which a pair counts
/// as loaded: 1 %, above the QP's round-off by many orders, below any
/// share a pair entering or leaving mesh carries for more than a step or
/// two of a 20-position cycle.
pub const LOADED_SHARE: f64 = 0.01;

/// Load sharing over one cycle (module docs).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct CycleSharing {
    /// ε_f (pitches).
    pub functional_contact_ratio: f64,
    /// ρ of the module docs.
    pub loaded_share_threshold: f64,
    /// Loaded pairs per position, and their least and largest number.
    pub loaded_pairs: Vec<usize>,
    pub min_loaded_pairs: usize,
    pub max_loaded_pairs: usize,
    /// Fraction of the pitch with exactly one loaded pair (the single-pair
    /// zone) and its span (deg of pinion roll).
    pub single_pair_fraction: f64,
    pub single_pair_span_deg: f64,
    /// Largest share a single pair carries over the cycle.
    pub max_share: f64,
}

/// Sharing of `forces[position][pair]` (N) over positions spread evenly
/// over one pitch of `pitch_deg`; `None` without positions.
pub fn cycle_sharing(forces: &[Vec<f64>], pitch_deg: f64) -> Option<CycleSharing> {
    if forces.is_empty() {
        return None;
    }
    let mut loaded = Vec::with_capacity(forces.len());
    let mut max_share: f64 = 0.0;
    for f in forces {
        let total: f64 = f.iter().sum();
        let n = if total > 0.0 {
            f.iter().filter(|&&x| x > LOADED_SHARE * total).count()
        } else {
            0
        };
        if total > 0.0 {
            max_share = f.iter().fold(max_share, |m, &x| m.max(x / total));
        }
        loaded.push(n);
    }
    let n = forces.len() as f64;
    let single = loaded.iter().filter(|&&k| k == 1).count() as f64 / n;
    Some(CycleSharing {
        functional_contact_ratio: loaded.iter().sum::<usize>() as f64 / n,
        loaded_share_threshold: LOADED_SHARE,
        min_loaded_pairs: loaded.iter().copied().min().unwrap_or(0),
        max_loaded_pairs: loaded.iter().copied().max().unwrap_or(0),
        single_pair_fraction: single,
        single_pair_span_deg: single * pitch_deg,
        max_share,
        loaded_pairs: loaded,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pair_loaded_over_one_and_a_half_pitches_gives_ratio_one_and_a_half() {
        // 10 positions: two pairs loaded at 5, one at the other 5; a 0.5 %
        // share is below the threshold
        let f: Vec<Vec<f64>> = (0..10)
            .map(|i| {
                if i < 5 {
                    vec![600.0, 400.0, 0.0]
                } else {
                    vec![995.0, 5.0, 0.0]
                }
            })
            .collect();
        let s = cycle_sharing(&f, 30.0).unwrap();
        assert_eq!(s.functional_contact_ratio, 1.5);
        assert_eq!((s.min_loaded_pairs, s.max_loaded_pairs), (1, 2));
        assert_eq!(s.single_pair_fraction, 0.5);
        assert_eq!(s.single_pair_span_deg, 15.0);
        assert_eq!(s.max_share, 0.995);
        assert!(cycle_sharing(&[], 30.0).is_none());
    }
}
