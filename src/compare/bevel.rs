//! What `flank compare` ([`super::run::compare`]) does only on a
//! bevel/hypoid scene: its FE contact cycle per flank size, built after
//! `flank run`'s input checks (hard contact, the pinion as slave), and the
//! kind's part of the summary. The TE is compared as the pinion's loaded
//! rotation (µrad; its relative error is the same at the gear).
//!
//! p_max is compared at every position; FE contact's p_max of a hypoid
//! contact converges only when the elements resolve the loaded ellipse's
//! width (≈ 1 mm here: `papers/seed003-hypoid/README.md`), so its error
//! says how far the reference is from resolving it as much as how far the
//! LTCA is off.
//!
//! With friction (μ > 0, `--friction-mu`) both methods use the same μ: the
//! LTCA's frictional solve in load increments (its friction model, default
//! `incremental`: friction against the kinematic sliding), FE contact's
//! static Coulomb law (friction against the slip of the loading step); the
//! tangential force per pair is compared besides the normal forces
//! (`super::errors`).

use std::time::Instant;

use crate::error::FlankError;
use crate::ltca::cycle::LtcaCycle;
use crate::mesh::bevel_sector::BevelSectorOptions;
use crate::mesh_cycle::bevel_checks::checked_cycle;
use crate::mesh_cycle::cycle::RunSettings;
use crate::scene::Scene;

use super::summary::BevelCompare;
use super::{fe_method_run, CompareOptions, MethodRun};

/// FE contact of a bevel/hypoid pair at flank size `h` over `angles`
/// (deg), Coulomb μ `mu`: the base size `--fe-base-size`, else the scene's,
/// else m_mn/2 (at least `h`); the inputs `flank run` refuses are refused
/// here too (a sector too small for the pairs in mesh at these angles,
/// interpenetrating unloaded bodies): FE numbers of such a model are not a
/// reference.
pub fn bevel_fe_run(
    scene: &Scene,
    options: &CompareOptions,
    h: f64,
    angles: &[f64],
    mu: f64,
) -> Result<MethodRun, FlankError> {
    let bevel = scene.bevel("the bevel/hypoid comparison")?;
    let t = Instant::now();
    let mesh = BevelSectorOptions {
        flank_size: h,
        base_size: options
            .fe_base_size
            .or(scene.mesh.base_size)
            .unwrap_or(bevel.blank.cones.m_mn / 2.0)
            .max(h),
        ..Default::default()
    };
    let settings = RunSettings {
        friction_mu: mu,
        roll_angles_deg: angles.to_vec(),
        ..RunSettings::default_for(scene)
    };
    let cycle = checked_cycle(scene, &mesh, settings, options.threads.max(1), angles)?.cycle;
    fe_method_run(h, &cycle, angles, t.elapsed().as_secs_f64())
}

/// The bevel/hypoid part of compare.json: the LTCA's friction model and
/// increments, its span of the major axis.
pub fn bevel_kind(base: &LtcaCycle) -> Result<BevelCompare, FlankError> {
    let friction = base.settings.friction.as_ref();
    Ok(BevelCompare {
        pair: "hypoid",
        ltca_friction_model: friction.map(|f| f.model),
        ltca_increments: friction.and_then(|f| f.increment_count()),
        ltca_span_approach_mm: base.point()?.span_approach_mm,
    })
}
