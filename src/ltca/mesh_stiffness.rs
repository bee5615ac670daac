//! Mesh stiffness of the loaded pair per position, for dynamic models.
//!
//! Definition (the quasi-static one of Velex & Ajmi 2006, "On the
//! modelling of excitations in geared systems by transmission errors",
//! J. Sound Vib. 290: the loaded TE is the unloaded TE plus the
//! deflection F/k): at each position
//! k = F_n / δ, δ = r_n (θ − θ₀), with F_n the total normal force of all
//! tooth pairs (N), θ and θ₀ the loaded and unloaded TE (pinion rotation
//! beyond the rigid kinematics, rad) and r_n the moment arm of the normal
//! force ([`crate::ltca::model::PositionResult::mesh_stiffness_n_per_um`]):
//! r_b1 cos β_b for a spur/helical pair, so δ is the approach along the
//! normal to the flanks in the plane of action (spur: the line of action;
//! the transverse form F_bt/(r_b1 Δθ) is k cos²β_b), and for a bevel/hypoid
//! pair the middle pair's moment arm at roll 0 (there is no line of action:
//! δ is the pinion rotation at that arm). A secant stiffness at the
//! torque; the map over torque ([`crate::ltca::torque_map`]) shows how it
//! changes. Per unit face width (N/(mm·µm), as ISO 6336-1 states c′ and
//! c_γ) with the smaller face width of a cylindrical pair; a bevel pair's
//! is not defined (a point contact across a face of varying width).

use std::path::Path;

use serde::Serialize;

use crate::error::FlankError;
use crate::ltca::model::PositionResult;

/// Mean and variation of the mesh stiffness over positions equally spaced
/// over whole pitches (the mean is then the time average at a constant
/// speed).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MeshStiffness {
    pub positions: usize,
    /// Mean, smallest and largest k (N/µm), max − min (N/µm) and
    /// (max − min)/mean.
    pub mean_n_per_um: f64,
    pub min_n_per_um: f64,
    pub max_n_per_um: f64,
    pub peak_to_peak_n_per_um: f64,
    pub relative_variation: f64,
    /// The face width k is divided by (mm) and the mean per unit face
    /// width (N/(mm·µm)); `None` for a bevel/hypoid pair.
    pub face_width_mm: Option<f64>,
    pub mean_n_per_mm_um: Option<f64>,
    /// r_n of the definition (mm).
    pub moment_arm_mm: f64,
}

/// The mesh stiffness figures of `results` (a sample over whole pitches,
/// checked by the caller); the reason where a position has no stiffness
/// (its loaded TE not beyond the unloaded one).
pub fn mesh_stiffness(
    results: &[PositionResult],
    face_width_mm: Option<f64>,
    moment_arm_mm: f64,
) -> Result<MeshStiffness, String> {
    if results.is_empty() {
        return Err("no positions".into());
    }
    if let Some(r) = results
        .iter()
        .find(|r| !(r.mesh_stiffness_n_per_um.is_finite() && r.mesh_stiffness_n_per_um > 0.0))
    {
        return Err(format!(
            "at {:.4}° the loaded TE {:.3} µrad is not beyond the unloaded {:.3} µrad: no deflection to divide by",
            r.roll_deg, r.te_urad, r.unloaded_te_urad
        ));
    }
    let k: Vec<f64> = results.iter().map(|r| r.mesh_stiffness_n_per_um).collect();
    let mean = k.iter().sum::<f64>() / k.len() as f64;
    let min = k.iter().copied().fold(f64::INFINITY, f64::min);
    let max = k.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    Ok(MeshStiffness {
        positions: k.len(),
        mean_n_per_um: mean,
        min_n_per_um: min,
        max_n_per_um: max,
        peak_to_peak_n_per_um: max - min,
        relative_variation: (max - min) / mean,
        face_width_mm,
        mean_n_per_mm_um: face_width_mm.map(|b| mean / b),
        moment_arm_mm,
    })
}

/// One CSV row of a position: roll, fraction of a pitch from `first_deg`,
/// loaded and unloaded TE (µrad), the deflection δ (µm), F_n (N), k
/// (N/µm) and k/b (N/(mm·µm); empty without a face width); k and k/b
/// empty where not defined.
pub fn stiffness_row(
    r: &PositionResult,
    first_deg: f64,
    pitch_deg: f64,
    face_width_mm: Option<f64>,
) -> String {
    let force: f64 = r.line_force_n.iter().sum();
    let k = r.mesh_stiffness_n_per_um;
    let defined = k.is_finite() && k > 0.0;
    let cell = |x: Option<f64>| x.map_or(String::new(), |x| format!("{x:e}"));
    format!(
        "{},{:e},{:e},{:e},{:e},{:e},{},{}",
        r.roll_deg,
        (r.roll_deg - first_deg) / pitch_deg,
        r.te_urad,
        r.unloaded_te_urad,
        r.loaded_approach_mm * 1e3,
        force,
        cell(defined.then_some(k)),
        cell(face_width_mm.filter(|_| defined).map(|b| k / b)),
    )
}

/// The header of [`stiffness_row`].
pub const STIFFNESS_COLUMNS: &str = "roll_deg,pitch_fraction,te_urad,unloaded_te_urad,deflection_um,normal_force_n,mesh_stiffness_n_per_um,mesh_stiffness_n_per_mm_um";

/// `ltca_mesh_stiffness.csv`: one [`stiffness_row`] per position.
pub fn write_mesh_stiffness_csv(
    path: &Path,
    results: &[PositionResult],
    pitch_deg: f64,
    face_width_mm: Option<f64>,
) -> Result<(), FlankError> {
    let first = results.first().map_or(0.0, |r| r.roll_deg);
    let mut s = String::from(STIFFNESS_COLUMNS);
    s.push('\n');
    for r in results {
        s.push_str(&stiffness_row(r, first, pitch_deg, face_width_mm));
        s.push('\n');
    }
    crate::atomic_file::write(path, s)
}
