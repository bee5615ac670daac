//! FE contact of a spur/helical pair with **contact bands**: per roll
//! angle, both bodies are meshed with finer involute rows (and a finer
//! first layer across the tooth) around that position's kinematic contact
//! points ([`crate::mesh::gear_sector::ProfileBand`]), the pair model is
//! built and factorized for that position alone and solved. The point is a
//! contact pressure p_max from a mesh that resolves the Hertz width
//! (issue 23 item 1), without refining the whole flank.
//!
//! Per position and tooth pair in kinematic flank contact:
//! * the contact point on each flank from the TCA's kinematic line
//!   ([`LineContactPair::contact_lines`](crate::geometry::gear_pair::LineContactPair::contact_lines), [`LineContactPair::line_seed`](crate::geometry::gear_pair::LineContactPair::line_seed) at the middle
//!   of the line), as the involute roll angle u, radius r_b √(1 + u²) and
//!   radius of curvature ρ = r_b u (transverse; cylindrical involute);
//! * the Hertz half-width of the nominal single-pair load,
//!   b = √(4 w R / (π E*)) with w = T/(r_b1 cos β_b)/face width,
//!   1/R = 1/ρ₁ + 1/ρ₂ (spur pairs only), 1/E* = (1 − ν₁²)/E₁ + (1 − ν₂²)/E₂ (Johnson,
//!   *Contact Mechanics*, 1985, §4.2, eqs. 4.43–4.45; [`hertz_line`]);
//! * a band of `size_mm` rows over ±`half_width_b`·b on each body.
//!
//! The result per pair: normal force, share, the FE's own line load
//! w_FE = F/face width, Hertz p₀ = √(w_FE E*/(π R)) and b from w_FE, the
//! FE p_max (face-averaged pressure: largest over the flank and at the
//! node row nearest the middle of the face width; largest nodal λ/A), the
//! elements across 2b (2b / band size, and the closed nodes on the
//! mid-face row). Bands on every tooth of the sector (see
//! [`crate::mesh::gear_sector::gear_sector_banded`]): at a double-contact
//! position both pairs' bands lie on every tooth.

use std::time::Instant;

use crate::compliance::body::{sector_options, BodyMeshOptions};
use crate::contact::hertz_line::{contact_modulus, hertz_line};
use crate::contact::PressureOverclosure;
use crate::error::FlankError;
use crate::fem::static_analysis::peak_memory_mb;
use crate::geometry::gear_pair::LineKind;
use crate::mesh::gear_body::body_of_sector;
use crate::mesh::gear_sector::{gear_sector_banded, ProfileBand};
use crate::mesh_cycle::cycle::{MeshCycle, RunSettings};
use crate::mesh_cycle::pair_model::{combine, PairBody};

use crate::scene::Scene;
use crate::settings::{ContactLaw, SlaveBody};

/// Options of [`run_contact_band`].
#[derive(Clone, Debug)]
pub struct BandOptions {
    /// Row size inside the bands (mm); `None`: no band (the plain mesh of
    /// the same options, for comparison).
    pub size_mm: Option<f64>,
    /// Band half-width as a multiple of the Hertz half-width b of the
    /// nominal load (default 2.5: the contact ±b, and the contact point's
    /// shift under load, well inside).
    pub half_width_b: f64,
    /// Flank/base size and element overrides, as `flank run`.
    pub mesh: BodyMeshOptions,
    /// Quadratic layers over the face width; 0: the mesher's default
    /// (⌈b / base size⌉).
    pub face_layers: usize,
    pub threads: usize,
}

impl Default for BandOptions {
    fn default() -> Self {
        BandOptions {
            size_mm: None,
            half_width_b: 2.5,
            mesh: BodyMeshOptions::default(),
            face_layers: 0,
            threads: 0,
        }
    }
}

/// One tooth pair's kinematic contact at a position.
#[derive(Clone, Debug, serde::Serialize)]
pub struct BandContact {
    pub pinion_tooth: usize,
    pub gear_tooth: usize,
    /// Contact point radii (mm) and involute radii of curvature ρ = r_b u.
    pub radius_mm: [f64; 2],
    pub curvature_radius_mm: [f64; 2],
    /// Equivalent radius R (mm).
    pub equivalent_radius_mm: f64,
    /// Hertz half-width of the nominal single-pair load (mm).
    pub nominal_half_width_mm: f64,
}

/// Results of one tooth pair at one banded position.
#[derive(Clone, Debug, serde::Serialize)]
pub struct BandPair {
    pub pinion_tooth: usize,
    pub force_n: f64,
    pub load_share: f64,
    /// FE line load F/face width (N/mm).
    pub line_load_n_per_mm: f64,
    /// Hertz line contact of the FE's line load at the kinematic contact
    /// point: peak p₀ (MPa) and half-width b (mm); `None` without kinematic
    /// flank contact (no curvature radii).
    pub hertz_p0_mpa: Option<f64>,
    pub hertz_half_width_mm: Option<f64>,
    /// Largest face-averaged pressure over the slave flank (MPa), at the
    /// slave node row nearest the middle of the face width, largest nodal
    /// λ/A (MPa).
    pub p_max_mpa: f64,
    pub p_max_mid_face_mpa: f64,
    pub p_max_nodal_mpa: f64,
    /// Slave nodes with a positive face-averaged pressure on the node row
    /// nearest the middle of the face width (a mid-layer row, with an odd
    /// number of face layers, holds corner nodes only: n nodes span n − 1
    /// elements; a layer-boundary row holds corners and midsides).
    pub closed_nodes_mid_face: usize,
    /// 2b (Hertz, FE line load) / band row size.
    pub elements_across_2b: Option<f64>,
}

/// Results at one roll angle.
#[derive(Clone, Debug, serde::Serialize)]
pub struct BandPosition {
    pub roll_deg: f64,
    pub band_size_mm: Option<f64>,
    pub contacts: Vec<BandContact>,
    pub bands: [Vec<ProfileBand>; 2],
    pub pairs: Vec<BandPair>,
    pub te_urad: f64,
    pub nodes: usize,
    pub dofs: usize,
    /// Scaled Jacobian (min) and aspect ratio (max) of both bodies.
    pub min_scaled_jacobian: f64,
    pub max_aspect_ratio: f64,
    pub setup_s: f64,
    pub solve_s: f64,
    pub peak_memory_mb: f64,
}

/// The kinematic flank contacts of `pair` at `roll_deg` and their Hertz
/// half-width under the nominal single-pair load (module docs).
pub fn band_contacts(scene: &Scene, roll_deg: f64) -> Result<Vec<BandContact>, FlankError> {
    let cyl = scene.cylindrical("the contact-band study")?;
    let gp = scene.gear_pair()?;
    let rb = [
        crate::geometry::involute::base_radius(&cyl.pair.pinion),
        crate::geometry::involute::base_radius(&cyl.pair.gear),
    ];
    let e_star = e_star(scene);
    let w = scene.load.torque_nmm / gp.nominal_moment_arm() / cyl.pair.pinion.face_width;
    let mut out = Vec::new();
    for line in gp.contact_lines(roll_deg.to_radians(), 0.0) {
        if line.kind != LineKind::Flank {
            continue;
        }
        let seed = gp.line_seed(&line, 0.5 * (line.range.0 + line.range.1), 0.0);
        let u = [seed.pinion_uv[0], seed.gear_uv[0]];
        let rho = [rb[0] * u[0], rb[1] * u[1]];
        if !(rho[0] > 0.0 && rho[1] > 0.0) {
            continue;
        }
        let r_eq = rho[0] * rho[1] / (rho[0] + rho[1]);
        out.push(BandContact {
            pinion_tooth: line.pinion_tooth,
            gear_tooth: line.gear_tooth,
            radius_mm: [rb[0] * u[0].hypot(1.0), rb[1] * u[1].hypot(1.0)],
            curvature_radius_mm: rho,
            equivalent_radius_mm: r_eq,
            nominal_half_width_mm: hertz_line(w, r_eq, e_star).0,
        });
    }
    Ok(out)
}

fn e_star(scene: &Scene) -> f64 {
    contact_modulus(
        [scene.pinion_material.young, scene.gear_material.young],
        [scene.pinion_material.poisson, scene.gear_material.poisson],
    )
}

/// FE contact at each of `roll_deg` with contact bands of `options`
/// (module docs): frictionless hard contact, slave body `auto`.
pub fn run_contact_band(
    scene: &Scene,
    roll_deg: &[f64],
    options: &BandOptions,
) -> Result<Vec<BandPosition>, FlankError> {
    let cyl = scene.cylindrical("the contact-band study")?;
    if let Some(s) = options.size_mm {
        if !(s > 0.0 && s.is_finite()) {
            return Err(FlankError::Model(format!(
                "--contact-band {s}: the band's row size (mm) must be positive and finite"
            )));
        }
    }
    if !(options.half_width_b > 0.0 && options.half_width_b.is_finite()) {
        return Err(FlankError::Model(format!(
            "--band-half-width {}: a positive multiple of the Hertz half-width is needed",
            options.half_width_b
        )));
    }
    if cyl.pair.pinion.helix_angle != 0.0 {
        return Err(FlankError::Model(
            "contact bands: spur pairs only (the band follows the transverse involute; a helical contact line crosses the profile)".into(),
        ));
    }
    if cyl.flank_modifications()?.iter().any(Option::is_some) {
        return Err(FlankError::Model(
            "contact bands: the scene's flank modifications are not applied to banded meshes yet"
                .into(),
        ));
    }
    let mut out = Vec::new();
    for &roll in roll_deg {
        out.push(position(scene, roll, options)?);
    }
    Ok(out)
}

fn position(scene: &Scene, roll: f64, options: &BandOptions) -> Result<BandPosition, FlankError> {
    let cyl = scene.cylindrical("the contact-band study")?;
    let t0 = Instant::now();
    let contacts = band_contacts(scene, roll)?;
    let mut bands: [Vec<ProfileBand>; 2] = [Vec::new(), Vec::new()];
    if let Some(size) = options.size_mm {
        if contacts.is_empty() {
            return Err(FlankError::Model(format!(
                "roll angle {roll}°: no tooth pair in kinematic flank contact, nowhere to put a contact band"
            )));
        }
        for c in &contacts {
            for (b, body) in bands.iter_mut().enumerate() {
                body.push(ProfileBand {
                    radius_mm: c.radius_mm[b],
                    half_width_mm: options.half_width_b * c.nominal_half_width_mm,
                    size_mm: size,
                });
            }
        }
    }
    let gp = scene.gear_pair()?;
    let mut sector = sector_options(scene, &options.mesh)?;
    sector.face_layers = options.face_layers;
    let mut models = Vec::new();
    let (mut min_j, mut max_a) = (f64::INFINITY, 0.0f64);
    for (b, (name, spec, material)) in [
        ("pinion", &cyl.pair.pinion, &scene.pinion_material),
        ("gear", &cyl.pair.gear, &scene.gear_material),
    ]
    .into_iter()
    .enumerate()
    {
        let m = gear_sector_banded(spec, name, &sector, &bands[b])
            .map_err(|e| FlankError::Model(format!("roll angle {roll}°, --contact-band: {e}")))?;
        min_j = min_j.min(m.quality.min_scaled_jacobian);
        max_a = max_a.max(m.quality.max_aspect_ratio);
        models.push(body_of_sector(spec, name, material, &sector, m, None)?);
    }
    let pair = combine(
        gp.as_ref(),
        [
            PairBody::of("pinion", &models[0].model, &models[0].sector.flank_uv),
            PairBody::of("gear", &models[1].model, &models[1].sector.flank_uv),
        ],
        scene.load.torque_nmm,
        PressureOverclosure::Hard,
        SlaveBody::Auto,
    )?;
    drop(models);
    let settings = RunSettings {
        law: ContactLaw::Hard,
        penalty_factor: 1.0,
        slave: SlaveBody::Auto,
        friction_mu: 0.0,
        search_distance_mm: scene
            .analyses
            .contact
            .as_ref()
            .and_then(|a| a.search_distance_mm)
            .unwrap_or(0.2),
        roll_angles_deg: vec![roll],
        vtu: false,
        refine_contact_limits: false,
        extend_step_deg: None,
        reference_single_contact_start_deg: None,
        lubrication: None,
    };
    let threads = if options.threads == 0 {
        std::thread::available_parallelism().map_or(1, |n| n.get())
    } else {
        options.threads
    };
    let cycle = MeshCycle::of_pair(scene, pair, settings, threads)?;
    let setup_s = t0.elapsed().as_secs_f64();
    let t1 = Instant::now();
    let solved = cycle.solve(roll)?;
    let solve_s = t1.elapsed().as_secs_f64();
    let step = &solved.step;
    let model = &cycle.pair.model;
    let face = cyl.pair.pinion.face_width;
    let e_star = e_star(scene);
    let mut pairs = Vec::new();
    for (p, &(k, _)) in cycle.pair.teeth.iter().enumerate() {
        // the slave flank's nodes of this pair at this position
        let (idx, _) = cycle.pairing_at(p, roll.to_radians());
        let slave_set = &model.contact.pairs[idx].slave;
        let set = format!(
            "{}_FLANK_{}",
            &slave_set[..slave_set.find('_').unwrap_or(0)],
            &slave_set[slave_set.find('_').map_or(0, |i| i + 1)..]
        );
        let nodes = model.mesh.node_sets.get(&set).cloned().unwrap_or_default();
        // the node row nearest the middle of the face width
        let zmid = nodes
            .iter()
            .map(|&n| model.mesh.coords[n][2])
            .min_by(|a, b| (a - 0.5 * face).abs().total_cmp(&(b - 0.5 * face).abs()))
            .unwrap_or(0.5 * face);
        let mid: Vec<usize> = nodes
            .iter()
            .copied()
            .filter(|&n| (model.mesh.coords[n][2] - zmid).abs() < 1e-9)
            .collect();
        let p_mid = mid.iter().map(|&n| solved.pressure[n]).fold(0.0, f64::max);
        let closed = mid.iter().filter(|&&n| solved.pressure[n] > 0.0).count();
        let force = step.pair_force_n[p];
        let w = force / face;
        let hz = contacts
            .iter()
            .find(|c| c.pinion_tooth == k)
            .filter(|_| force > 0.0)
            .map(|c| hertz_line(w, c.equivalent_radius_mm, e_star));
        pairs.push(BandPair {
            pinion_tooth: k,
            force_n: force,
            load_share: step.load_share[p],
            line_load_n_per_mm: w,
            hertz_p0_mpa: hz.map(|h| h.1),
            hertz_half_width_mm: hz.map(|h| h.0),
            p_max_mpa: step.max_pressure_mpa[p],
            p_max_mid_face_mpa: p_mid,
            p_max_nodal_mpa: step.max_nodal_pressure_mpa[p],
            closed_nodes_mid_face: closed,
            elements_across_2b: match (hz, options.size_mm) {
                (Some(h), Some(s)) => Some(2.0 * h.0 / s),
                _ => None,
            },
        });
    }
    Ok(BandPosition {
        roll_deg: roll,
        band_size_mm: options.size_mm,
        contacts,
        bands,
        pairs,
        te_urad: step.te_urad,
        nodes: model.mesh.node_count(),
        dofs: 3 * model.mesh.node_count(),
        min_scaled_jacobian: min_j,
        max_aspect_ratio: max_a,
        setup_s,
        solve_s,
        peak_memory_mb: peak_memory_mb(),
    })
}
