//! # Single-pair tooth stiffness of the seed 002 spur pair against ISO 6336-1
//!
//! Rung 5 of the verification ladder (a plausibility band, not an exact
//! reference). Both bodies of `papers/seed002-spur/scene.toml` are meshed as
//! 3-tooth hex20 sectors with the bore clamped. The middle tooth of each is
//! loaded by the single-pair normal force F_n = T₁/r_b1 spread uniformly along
//! the contact line at the working pitch radius (consistent quadratic
//! weights along the face width), along the inward flank normal. The
//! deflection δ of each tooth is the load-weighted mean displacement of the
//! loaded nodes along the load; the FE single stiffness of the pair is
//! c′_FE = F_n / (b (δ₁ + δ₂)) in N/(mm·µm), compared with ISO 6336-1
//! method B c′ (`flank check` reports it).
//!
//! What the comparison can and cannot say: the line load on FE nodes adds a
//! local indentation that grows as the mesh is refined (a line load is
//! log-singular in plane elasticity), while ISO's c′ is a calibrated figure
//! for real contact. The ratio is therefore reported for three flank sizes
//! and only asserted to lie in a wide plausibility band [0.5, 2].

#[path = "../common/mod.rs"]
mod common;

use std::time::Instant;

use flank::fem::model::NodalForce;
use flank::fem::static_analysis::{solve_static, SolveOptions};
use flank::geometry::involute::base_radius;
use flank::geometry::iso6336::tooth_stiffness;
use flank::geometry::pair::check_pair;
use flank::geometry::rack::{Flank, ToothProfile};
use flank::mesh::gear_body::gear_body;
use flank::mesh::gear_sector::{flank_segment, SectorOptions};
use flank::scene::{read_scene, Scene};

/// The spur/helical gears of a scene this case reads.
fn gears(s: &Scene) -> &flank::scene::CylindricalGears {
    s.cylindrical("this case").unwrap()
}

/// Deflection (mm) of one body's middle tooth under the line load `force` (N)
/// at radius `radius`, and the number of loaded nodes.
fn tooth_deflection(
    spec: &flank::geometry::GearSpec,
    name: &str,
    material: &flank::fem::material::Material,
    options: &SectorOptions,
    force: f64,
    radius: f64,
) -> (f64, usize, usize) {
    let mut body = gear_body(spec, name, material, options, None).unwrap();
    let profile = ToothProfile::new(spec, name).unwrap();
    let tooth = options.teeth.div_ceil(2);
    let set = body.model.mesh.node_sets[&format!("FLANK_R{tooth}")].clone();
    let coords = body.model.mesh.coords.clone();
    let r_of = |n: usize| (coords[n][0].powi(2) + coords[n][1].powi(2)).sqrt();
    // the profile rows (nodes of equal u) that carry a full quadratic line
    // across the face width (corner rows; midside rows hold corner-z nodes
    // only), and among them the one nearest to the radius
    let mut rows: std::collections::BTreeMap<u64, Vec<usize>> = Default::default();
    for &n in &set {
        rows.entry(body.sector.flank_uv[&n].0.to_bits())
            .or_default()
            .push(n);
    }
    let full = rows.values().map(Vec::len).max().unwrap();
    let target = rows
        .values()
        .filter(|r| r.len() == full)
        .map(|r| r[0])
        .min_by(|&a, &b| {
            (r_of(a) - radius)
                .abs()
                .total_cmp(&(r_of(b) - radius).abs())
        })
        .unwrap();
    let u0 = body.sector.flank_uv[&target].0;
    let mut line: Vec<(usize, f64)> = set
        .iter()
        .copied()
        .filter(|n| (body.sector.flank_uv[n].0 - u0).abs() < 1e-12)
        .map(|n| (n, body.sector.flank_uv[&n].1))
        .collect();
    line.sort_by(|a, b| a.1.total_cmp(&b.1));
    // consistent weights of a uniform line load on quadratic edges: h/6, 4h/6, h/6
    let mut w = vec![0.0; line.len()];
    for e in (0..line.len().saturating_sub(2)).step_by(2) {
        let h = line[e + 2].1 - line[e].1;
        w[e] += h / 6.0;
        w[e + 1] += 4.0 * h / 6.0;
        w[e + 2] += h / 6.0;
    }
    let total: f64 = w.iter().sum();
    let a = -((tooth - 1) as f64) * profile.angular_pitch();
    let (s, c) = a.sin_cos();
    let mut dirs = Vec::new();
    for (&(n, z), wi) in line.iter().zip(&w) {
        let u = body.sector.flank_uv[&n].0;
        let n0 = profile
            .surface(Flank::Right, flank_segment(&profile, u), z)
            .n;
        let d = [-(c * n0[0] - s * n0[1]), -(s * n0[0] + c * n0[1]), -n0[2]];
        for (k, dk) in d.iter().enumerate() {
            body.model.forces.push(NodalForce {
                node: n,
                component: k,
                value: force * wi / total * dk,
            });
        }
        dirs.push(d);
    }
    let sol = solve_static(
        &body.model,
        &SolveOptions {
            recover_stress: false,
            ..Default::default()
        },
    )
    .unwrap();
    let mut delta = 0.0;
    for ((&(n, _), wi), d) in line.iter().zip(&w).zip(&dirs) {
        let u = &sol.displacement[3 * n..3 * n + 3];
        delta += wi / total * (u[0] * d[0] + u[1] * d[1] + u[2] * d[2]);
    }
    (delta, line.len(), sol.stats.dofs)
}

#[test]
fn seed002_single_pair_stiffness_vs_iso6336() {
    let scene = read_scene(std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/papers/seed002-spur/scene.toml"
    )))
    .unwrap();
    let report = check_pair(&gears(&scene).pair).unwrap();
    let iso = tooth_stiffness(&gears(&scene).pair, report.contact_ratio).unwrap();
    let force = scene.load.torque_nmm / base_radius(&gears(&scene).pair.pinion);
    let cos_aw = report.working_pressure_angle_rad.cos();
    let b = gears(&scene)
        .pair
        .pinion
        .face_width
        .min(gears(&scene).pair.gear.face_width);
    println!(
        "ISO 6336-1: c′ = {:.3} N/(mm·µm), c_γα = {:.3}; F_n = {force:.1} N",
        iso.single, iso.mesh
    );
    let mut ratios = Vec::new();
    for flank_size in [1.0, 0.5, 0.25] {
        let t = Instant::now();
        let options = SectorOptions {
            teeth: 3,
            flank_size,
            base_size: 2.0,
            face_layers: 0,
            ..Default::default()
        };
        let (d1, n1, dofs1) = tooth_deflection(
            &gears(&scene).pair.pinion,
            "pinion",
            &scene.pinion_material,
            &options,
            force,
            base_radius(&gears(&scene).pair.pinion) / cos_aw,
        );
        let (d2, _, dofs2) = tooth_deflection(
            &gears(&scene).pair.gear,
            "gear",
            &scene.gear_material,
            &options,
            force,
            base_radius(&gears(&scene).pair.gear) / cos_aw,
        );
        let c_fe = force / (b * (d1 + d2) * 1e3);
        let ratio = c_fe / iso.single;
        println!(
            "VERIFY gear_stiffness flank {flank_size:>5} mm: DOFs {dofs1}+{dofs2}, {n1} loaded nodes/tooth, δ1 = {:.3} µm, δ2 = {:.3} µm, c′_FE = {c_fe:.3} N/(mm·µm), c′_FE/c′_ISO = {ratio:.3}, {:.2} s",
            d1 * 1e3,
            d2 * 1e3,
            t.elapsed().as_secs_f64()
        );
        assert!(d1 > 0.0 && d2 > 0.0, "the teeth must yield along the load");
        ratios.push(ratio);
    }
    for r in &ratios {
        assert!(
            (0.5..=2.0).contains(r),
            "c′_FE/c′_ISO = {r} outside the plausibility band [0.5, 2]"
        );
    }
}
