//! How many teeth a spur/helical sector body needs: every tooth pair that
//! is in mesh while the middle pair is, over its whole engagement under
//! load.
//!
//! The LTCA and FE contact model the pairs of the sectors' teeth only; a
//! pair in mesh that the sectors do not hold takes no load, and its share
//! goes to the modelled pairs (a 3-tooth sector of a helical pair with
//! ε_γ = 6 carries a third of the load per pair where six share it). The
//! pairs in mesh ([`pairs_in_mesh`]) are those whose whole engagement
//! (transverse plus overlap, [`LineContactPair::face_engagement`]),
//! widened on both sides by the load's contact extension, contains a roll
//! angle of the analysis. The extension is the tip-corner reach
//! ([`CylindricalPair::corner_reach_mm`]) at the approach
//! δ = F_bn / (b c′): the deflection of a single pair under the whole
//! normal force F_bn = T₁ / (r_b1 cos β_b) at the single stiffness c′ of
//! ISO 6336-1:2006 9.3 ([`crate::geometry::iso6336`]), scaled by
//! E_r / 206 000 MPa for other materials than steel (9.3: c′ ∝ E). A
//! single pair under the whole load deflects the most, so δ bounds the
//! approach of any pair over the cycle. Seed 002 (312 N·m): δ ≈ 0.07 mm,
//! a contact extension of about 5° of roll per side against the 3° the
//! loaded contact ratio 1.70 shows: 3 teeth hold its pairs; seed 004
//! (ε_γ = 2.81) needs 5.
//!
//! Where ISO's formula does not apply (x₁ + x₂ outside [−0.5, 2]) c′ is
//! taken as 12 N/(mm·µm), below the formula's values for ordinary
//! proportions (12.7 for 20/40 teeth, x = 0), so the estimate errs towards
//! more teeth.

use super::CylindricalPair;
use crate::error::FlankError;
use crate::geometry::gear_pair::{pairs_in_mesh, sector_teeth_holding, GearPair, LineContactPair};
use crate::geometry::iso6336::tooth_stiffness;
use crate::geometry::PairSpec;

/// Young's modulus of ISO 6336-1's steel (MPa): c′ scales with E_r / this.
const ISO_STEEL_MODULUS_MPA: f64 = 206_000.0;

/// c′ (N/(mm·µm)) where ISO 6336-1's formula does not apply (module docs).
const FALLBACK_SINGLE_STIFFNESS: f64 = 12.0;

/// The sector a pair needs ([`sector_in_mesh`]).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct SectorInMesh {
    /// Teeth per sector that hold every pair in mesh (at most the smaller
    /// tooth count; `fits` says whether that is enough).
    pub teeth: usize,
    /// Offsets from the middle pair of the first and the last pair in mesh.
    pub pair_offsets: (i64, i64),
    /// The single-pair approach δ under the whole load (mm) and the
    /// contact extension it gives along the path (mm).
    pub approach_mm: f64,
    pub extension_mm: f64,
    /// Whether the smaller gear has enough teeth for such a sector.
    pub fits: bool,
}

/// The load's approach δ = F_bn / (b c′) of `spec` under pinion torque
/// `torque_nm` (N·m), for a reduced modulus `modulus_mpa`
/// (2 E₁E₂/(E₁+E₂); module docs).
pub fn load_approach_mm(
    spec: &PairSpec,
    pair: &CylindricalPair,
    torque_nm: f64,
    modulus_mpa: f64,
) -> f64 {
    let eps_alpha = pair.kinematic_contact_ratio();
    let single = tooth_stiffness(spec, eps_alpha)
        .map(|s| s.single)
        .unwrap_or(FALLBACK_SINGLE_STIFFNESS)
        * modulus_mpa
        / ISO_STEEL_MODULUS_MPA;
    let face = spec.pinion.face_width.min(spec.gear.face_width);
    let force = torque_nm.abs() * 1e3 / pair.nominal_moment_arm();
    // N/mm over N/(mm·µm) = µm
    force / face / single * 1e-3
}

/// Roll samples of [`sector_in_mesh`] at most (0.05° apart up to 25 000°).
const MAX_ROLL_SAMPLES: f64 = 500_000.0;

/// A contact reach (rad of roll) past which the sector no longer grows:
/// 2z + 1 tooth steps reach every pair a sector can hold
/// ([`pairs_in_mesh`] looks at offsets within ±z). Also the reach taken
/// where the load's is not a number (`f64::min` keeps the other operand),
/// so an absurd load errs towards more teeth.
fn saturated_reach(pair: &CylindricalPair) -> f64 {
    (2 * pair.pinion().teeth() + 1) as f64 * pair.tooth_roll_step().abs()
}

/// The pairs in mesh of `pair` at the roll angles `rolls_deg` widened by
/// the contact extension at approach `approach_mm`, and the sector that
/// holds them (module docs).
pub fn sector_for_rolls(
    pair: &CylindricalPair,
    rolls_deg: &[f64],
    approach_mm: f64,
) -> SectorInMesh {
    let extension_mm = pair.corner_reach_mm(approach_mm);
    let reach = (extension_mm / pair.transmission_error_radius()).min(saturated_reach(pair));
    // the positions at which the middle pair can be in contact: outside
    // them (the unloaded brackets of a default range) the pairs that are
    // in mesh do not share the middle pair's load
    let (a, e) = pair.face_engagement(pair.middle());
    let (from, to) = (a.min(e) - reach, a.max(e) + reach);
    let rolls: Vec<f64> = rolls_deg
        .iter()
        .map(|r| r.to_radians())
        .filter(|r| (from..=to).contains(r))
        .collect();
    let (lo, hi) = pairs_in_mesh(pair, &rolls, reach);
    let teeth = sector_teeth_holding(lo, hi);
    let most = pair.pinion().teeth().min(pair.gear().teeth()) as usize;
    SectorInMesh {
        teeth: teeth.min(most),
        pair_offsets: (lo, hi),
        approach_mm,
        extension_mm,
        fits: teeth <= most,
    }
}

/// The sector of `spec` under pinion torque `torque_nm` that holds every
/// pair in mesh while the middle pair is, over its whole engagement
/// ([`crate::geometry::gear_pair::engagement_roll_angles`], sampled at 0.05°) and its extension under
/// load (the LTCA extends a default range while the middle pair is
/// loaded): the default of `[mesh] teeth_in_sector`.
pub fn sector_in_mesh(
    spec: &PairSpec,
    torque_nm: f64,
    modulus_mpa: f64,
) -> Result<SectorInMesh, FlankError> {
    let pair = CylindricalPair::new(spec, [None, None], 3)?;
    let approach = load_approach_mm(spec, &pair, torque_nm, modulus_mpa);
    if !approach.is_finite() {
        return Err(FlankError::Model(format!(
            "the load's approach F_bn / (b c′) is {approach} mm (pinion torque {torque_nm} N·m, \
             reduced modulus {modulus_mpa} MPa): no sector holds its pairs in mesh"
        )));
    }
    // the whole loaded engagement, finely: the default range and beyond
    // (the reach is bounded where the sector stops growing, see
    // `saturated_reach`)
    let ext_deg = (pair.corner_reach_mm(approach) / pair.transmission_error_radius())
        .min(saturated_reach(&pair))
        .to_degrees();
    let (a, e) = pair.face_engagement(pair.middle());
    // engagement_roll_angles' range at 0.05°, without building it
    let first = ((a.min(e).to_degrees() / 0.05).floor() - 2.0) * 0.05 - ext_deg;
    let last = ((a.max(e).to_degrees() / 0.05).ceil() + 2.0) * 0.05 + ext_deg;
    // 0.05° apart, or coarser where an absurd face engagement (thousands
    // of pitches) would need more than MAX_ROLL_SAMPLES of them
    let n = ((last - first) / 0.05).ceil().clamp(1.0, MAX_ROLL_SAMPLES);
    let step = if n < MAX_ROLL_SAMPLES {
        0.05
    } else {
        (last - first) / n
    };
    let n = n as usize;
    let rolls: Vec<f64> = (0..=n).map(|i| first + step * i as f64).collect();
    Ok(sector_for_rolls(&pair, &rolls, approach))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::read_scene;

    fn spec(path: &str) -> PairSpec {
        let s = read_scene(std::path::Path::new(&format!(
            "{}/{path}",
            env!("CARGO_MANIFEST_DIR")
        )))
        .unwrap();
        s.cylindrical("test").unwrap().pair.clone()
    }

    /// Seed 002 (ε_α 1.484, 312 N·m) needs its paper's 3 teeth; seed 004
    /// (ε_γ 2.809) 5: with ε_γ pitches of engagement and the middle pair
    /// in mesh throughout, pairs up to ⌈ε_γ⌉ − 1 pitches away share it.
    /// A helical pair's face engagement exceeds its transverse one by ε_β
    /// pitches.
    #[test]
    fn seed_sectors_hold_their_pairs() {
        let s2 = sector_in_mesh(&spec("papers/seed002-spur/scene.toml"), 312.0, 206_000.0).unwrap();
        assert_eq!(s2.teeth, 3, "{s2:?}");
        assert!(s2.approach_mm > 0.03 && s2.approach_mm < 0.15, "{s2:?}");
        let g4 = spec("papers/seed004-helical/scene.toml");
        let s4 = sector_in_mesh(&g4, 5000.0, 207_000.0).unwrap();
        assert_eq!(s4.teeth, 5, "{s4:?}");
        assert_eq!(s4.pair_offsets, (-2, 2));
        let pair = CylindricalPair::new(&g4, [None, None], 3).unwrap();
        let (a, e) = pair.engagement(2);
        let (fa, fe) = pair.face_engagement(2);
        let pitch = pair.pinion().angular_pitch();
        let eps_beta = 180.0 * 20f64.to_radians().sin() / (std::f64::consts::PI * 15.0);
        assert!(((fe - fa) - (e - a) - eps_beta * pitch).abs() < 1e-9 * pitch);
        // the transverse engagement lies inside the face engagement
        assert!(fa <= a.min(e) + 1e-12 && fe >= a.max(e) - 1e-12);
    }

    /// Spur pairs: face and transverse engagement are one; no roll, or
    /// one where no neighbour is near, needs only the middle pair.
    #[test]
    fn spur_engagement_and_lone_pair() {
        let g = spec("papers/seed002-spur/scene.toml");
        let pair = CylindricalPair::new(&g, [None, None], 3).unwrap();
        assert_eq!(pair.engagement(2), pair.face_engagement(2));
        assert_eq!(sector_teeth_holding(0, 0), 1);
        assert_eq!(sector_teeth_holding(-1, 1), 3);
        assert_eq!(sector_teeth_holding(-2, 1), 5);
        assert_eq!(sector_teeth_holding(-1, 2), 4);
        let s = sector_for_rolls(&pair, &[], 0.05);
        assert_eq!((s.teeth, s.pair_offsets), (1, (0, 0)));
    }

    /// An absurd (finite) load reaches every pair: the whole smaller gear
    /// (which cannot hold them all, `fits` false),
    /// found in bounded time (a fuzzed 1e300 N·m once asked for a roll
    /// vector of 10³⁰⁰ samples); a load whose approach overflows is
    /// refused with the figures.
    #[test]
    fn absurd_loads_are_bounded() {
        let g = spec("papers/seed002-spur/scene.toml");
        let most = g.pinion.teeth.min(g.gear.teeth) as usize;
        let s = sector_in_mesh(&g, 1e30, 206_000.0).unwrap();
        assert_eq!((s.teeth, s.fits), (most, false), "{s:?}");
        let e = sector_in_mesh(&g, 1e306, 206_000.0)
            .unwrap_err()
            .to_string();
        assert!(e.contains("approach") && e.contains("inf"), "{e}");
    }
}
