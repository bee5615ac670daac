use std::collections::{HashMap, HashSet};
use std::path::Path;

use super::*;
use crate::fem::element::face_nodes;
use crate::geometry::gear_pair::{Flank, GearBody};
use crate::scene::{read_any_scene, AnyScene, BevelScene};

fn scene(seed: &str) -> BevelScene {
    let path = format!("{}/papers/{seed}/scene.toml", env!("CARGO_MANIFEST_DIR"));
    match read_any_scene(Path::new(&path)).unwrap() {
        AnyScene::Bevel(b) => b,
        _ => panic!("{seed} is not a bevel scene"),
    }
}

fn coarse() -> BevelSectorOptions {
    BevelSectorOptions {
        flank_size: 1.0,
        base_size: 4.0,
        ..Default::default()
    }
}

/// The body's flank of a flank set name ("FLANK_R2" → right flank, tooth 2).
fn set_flank<'a>(
    gear: &'a BevelGear,
    set: &str,
) -> Option<&'a dyn crate::geometry::surface::ToothSurface> {
    let side = match set.get(..7)? {
        "FLANK_L" => Flank::Left,
        "FLANK_R" => Flank::Right,
        _ => return None,
    };
    gear.flank(side, set[7..].parse().ok()?)
}

/// (largest distance of a flank node from its surface point,
/// [`flank_edge_deviation`]).
fn flank_deviation(gear: &BevelGear, r: &BevelSectorMesh) -> (f64, [f64; 2]) {
    let mesh = &r.mesh;
    let mut node_dist = 0.0f64;
    for (set, nodes) in &mesh.node_sets {
        let Some(surface) = set_flank(gear, set) else {
            continue;
        };
        for &n in nodes {
            let (u, v) = r.flank_uv[&n];
            let p = surface.point(u, v);
            let x = mesh.coords[n];
            node_dist = node_dist.max(
                ((p[0] - x[0]).powi(2) + (p[1] - x[1]).powi(2) + (p[2] - x[2]).powi(2)).sqrt(),
            );
        }
    }
    (node_dist, flank_edge_deviation(gear, r))
}

/// Conformity: no face is shared by more than two elements, and every
/// face used once (a free face) has all its corners on one boundary set,
/// so no crack lies inside the body where blocks or pitches meet.
fn assert_conforming(mesh: &crate::mesh::Mesh, m: usize) {
    let mut faces: HashMap<Vec<usize>, usize> = HashMap::new();
    for e in &mesh.elements {
        for f in 1..=6 {
            let nodes = face_nodes(e.kind, f).unwrap();
            let mut key: Vec<usize> = nodes[..4].iter().map(|&i| e.nodes[i]).collect();
            key.sort_unstable();
            *faces.entry(key).or_default() += 1;
        }
    }
    let boundary: HashSet<usize> = mesh
        .node_sets
        .iter()
        .filter(|(k, _)| !matches!(k.as_str(), "NALL"))
        .flat_map(|(_, v)| v.iter().copied())
        .collect();
    let mut free = 0;
    for (key, count) in &faces {
        assert!(*count <= 2, "a face shared by {count} elements");
        if *count == 1 {
            free += 1;
            // a boundary face has all its corners on one boundary set
            let on_one = mesh.node_sets.iter().any(|(k, v)| {
                k != "NALL"
                    && key
                        .iter()
                        .all(|n| v.binary_search(n).is_ok() || v.contains(n))
            });
            assert!(
                on_one,
                "member {m}: a free face inside the body (corners {:?}, on boundary sets: {:?})",
                key.iter().map(|n| mesh.coords[*n]).collect::<Vec<_>>(),
                key.iter().map(|n| boundary.contains(n)).collect::<Vec<_>>()
            );
        }
    }
    assert!(free > 0);
}

/// Seed 003's pinion (bore) and ring gear (mounting plane), coarse: every
/// element valid; the mesh is conforming (every face used once lies on a
/// boundary set: no crack where blocks or pitches meet); flank nodes are
/// the surfaces' points; the quadratic flank edges stay on the surface
/// (deviation of the edge's quarter points from the surface, by closest
/// point, converging at third order or faster); the mount set lies on its bore or plane.
#[test]
fn seed003_sectors_are_valid_conforming_and_exact_on_the_flanks() {
    let sc = scene("seed003-hypoid");
    for (m, gear) in sc.bodies.iter().enumerate() {
        let r = bevel_sector(gear, "body", &coarse()).unwrap();
        let mesh = &r.mesh;
        assert!(r.quality.min_scaled_jacobian > 0.2, "{:?}", r.quality);
        assert_conforming(mesh, m);
        // flank nodes and flank edges
        let (node_dist, dev) = flank_deviation(gear, &r);
        println!(
            "seed003 member {m}: {} nodes, {} elements, Jacobian {:.3}, aspect {:.1}, counts {:?}; flank node distance {node_dist:.2e} mm, flank edge deviation along the profile {:.2e} mm, along the face {:.2e} mm",
            mesh.node_count(),
            mesh.elements.len(),
            r.quality.min_scaled_jacobian,
            r.quality.max_aspect_ratio,
            r.counts,
            dev[0],
            dev[1]
        );
        assert!(node_dist < 1e-12 * gear.cones().re, "{node_dist}");
        // quadratic edges: the deviation falls as h³ or faster; twice the
        // face layers must divide the face edges' deviation by ≥ 6
        let finer = bevel_sector(
            gear,
            "body",
            &BevelSectorOptions {
                face_layers: 2 * r.counts.face,
                ..coarse()
            },
        )
        .unwrap();
        let (_, dev2) = flank_deviation(gear, &finer);
        println!(
            "  twice the face layers: along the face {:.2e} mm (ratio {:.1})",
            dev2[1],
            dev[1] / dev2[1]
        );
        assert!(dev[1] / dev2[1] >= 6.0, "{dev:?} {dev2:?}");
        // the mount
        let mount = &mesh.node_sets["MOUNT"];
        assert!(!mount.is_empty());
        for &n in mount {
            let x = mesh.coords[n];
            let off = match r.mount {
                Mount::Bore { radius } => x[0].hypot(x[1]) - radius,
                Mount::Plane { z } => x[2] - z,
            };
            assert!(off.abs() < 1e-9, "mount node off by {off}");
        }
        assert_eq!(mesh.node_sets.contains_key("BORE"), m == 0);
        for set in [
            "CUT_A", "CUT_B", "TOE", "HEEL", "TIP_LAND", "GAP_LAND", "FLANK_L1", "FLANK_R3",
        ] {
            assert!(!mesh.node_sets[set].is_empty(), "{set}");
        }
        let a: HashSet<_> = mesh.node_sets["CUT_A"].iter().collect();
        assert!(mesh.node_sets["CUT_B"].iter().all(|n| !a.contains(n)));
    }
}

/// The mounted gear under its nominal load deflects along the load; the
/// reaction at the mount balances it.
#[test]
fn loaded_ring_gear_solves() {
    use crate::fem::static_analysis::{solve_static, SolveOptions};
    use crate::mesh::bevel_body::bevel_body_model;
    let sc = scene("seed003-hypoid");
    let body = bevel_body_model(
        &sc.bodies[1],
        "gear",
        &sc.gear_material,
        &coarse(),
        Some(1.0e6),
    )
    .unwrap();
    let (node, f) = body.load.unwrap();
    let sol = solve_static(
        &body.model,
        &SolveOptions {
            threads: 2,
            ..Default::default()
        },
    )
    .unwrap();
    let d = &sol.displacement[3 * node..3 * node + 3];
    let fnorm = (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt();
    let along = (d[0] * f[0] + d[1] * f[1] + d[2] * f[2]) / fnorm;
    let dn = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    println!("gear: {} dofs, force {fnorm:.1} N, displacement {dn:.3e} mm, along the force {along:.3e} mm", sol.stats.dofs);
    assert!(along > 0.5 * dn && dn.is_finite(), "{along} {dn}");
    // moment of the load about the axis is the torque
    let x = body.model.mesh.coords[node];
    let moment = x[0] * f[1] - x[1] * f[0];
    assert!((moment.abs() - 1.0e6).abs() < 1e-6 * 1.0e6, "{moment}");
}

/// Bad input: a negative rim, wedge elements,
/// sizes out of order; and seed 000's pinion, whose fillets meet at the
/// toe (no gap land), is refused with that reason.
#[test]
fn bad_sectors_are_refused_with_the_reason() {
    let sc = scene("seed003-hypoid");
    let gear = &sc.bodies[0];
    let msg = |o: &BevelSectorOptions, g: &BevelGear| {
        bevel_sector(g, "pinion", o).unwrap_err().to_string()
    };
    let m = msg(
        &BevelSectorOptions {
            element: ElementKind::C3D15,
            ..coarse()
        },
        gear,
    );
    assert!(m.contains("C3D15"), "{m}");
    let m = msg(
        &BevelSectorOptions {
            flank_size: 2.0,
            base_size: 1.0,
            ..coarse()
        },
        gear,
    );
    assert!(m.contains("flank_size"), "{m}");
    let m = msg(
        &BevelSectorOptions {
            rim_thickness: Some(-1.0),
            ..coarse()
        },
        gear,
    );
    assert!(m.contains("rim thickness"), "{m}");
    let s0 = scene("seed000-hypoid");
    let m = msg(&coarse(), &s0.bodies[0]);
    assert!(m.contains("no gap land"), "{m}");
}

/// Seed 003's pinion with a shank (40 mm long, 30 mm diameter), coarse:
/// every element valid and no worse than without it, the mesh conforming;
/// the bearing seat (`MOUNT`) on the cylinder r_s from where it leaves the
/// heel face to the end plane 40 mm further, `BORE` on the bore through
/// teeth and shank, `SHANK_END` on the end plane, the cuts extended into
/// the shank; a shank wider than the rim, or on the ring gear, is refused.
#[test]
fn pinion_shank_is_an_exact_cylinder_on_the_heel_face() {
    let sc = scene("seed003-hypoid");
    let gear = &sc.bodies[0];
    let plain = bevel_sector(gear, "pinion", &coarse()).unwrap();
    let opts = BevelSectorOptions {
        shank: Some(Shank {
            length: 40.0,
            diameter: 30.0,
        }),
        ..coarse()
    };
    let r = bevel_sector(gear, "pinion", &opts).unwrap();
    let mesh = &r.mesh;
    let sh = r.shank.unwrap();
    println!(
        "pinion with shank: {} nodes ({} without), {} elements, Jacobian {:.3} ({:.3} without), aspect {:.1}; shank {sh:?}",
        mesh.node_count(),
        plain.mesh.node_count(),
        mesh.elements.len(),
        r.quality.min_scaled_jacobian,
        plain.quality.min_scaled_jacobian,
        r.quality.max_aspect_ratio
    );
    assert!(r.quality.min_scaled_jacobian >= plain.quality.min_scaled_jacobian - 1e-9);
    assert!(mesh.elements.len() > plain.mesh.elements.len());
    assert_conforming(mesh, 0);
    let tol = 1e-9 * gear.cones().re;
    assert!((sh.radius_mm - 15.0).abs() < tol && (sh.z_mm[1] - sh.z_mm[0] - 40.0).abs() < tol);
    let rho = |n: usize| mesh.coords[n][0].hypot(mesh.coords[n][1]);
    for &n in &mesh.node_sets["MOUNT"] {
        let z = mesh.coords[n][2];
        assert!((rho(n) - 15.0).abs() < 1e-9, "seat node at ρ = {}", rho(n));
        assert!(
            z > sh.z_mm[0] - tol && z < sh.z_mm[1] + tol,
            "seat node at z = {z}"
        );
    }
    let zs: Vec<f64> = mesh.node_sets["MOUNT"]
        .iter()
        .map(|&n| mesh.coords[n][2])
        .collect();
    let (zmin, zmax) = zs
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &z| {
            (a.min(z), b.max(z))
        });
    assert!(
        (zmin - sh.z_mm[0]).abs() < 1e-6 && (zmax - sh.z_mm[1]).abs() < 1e-6,
        "{zmin} {zmax}"
    );
    for &n in &mesh.node_sets["BORE"] {
        assert!(
            (rho(n) - sh.bore_radius_mm).abs() < 1e-9,
            "bore node at ρ = {}",
            rho(n)
        );
    }
    assert!(mesh.node_sets["BORE"].len() > plain.mesh.node_sets["BORE"].len());
    for &n in &mesh.node_sets["SHANK_END"] {
        assert!((mesh.coords[n][2] - sh.z_mm[1]).abs() < tol);
    }
    assert!(mesh.node_sets["CUT_A"].len() > plain.mesh.node_sets["CUT_A"].len());
    // refused: wider than the rim below the teeth, or on the ring gear
    let wide = BevelSectorOptions {
        shank: Some(Shank {
            length: 40.0,
            diameter: 200.0,
        }),
        ..coarse()
    };
    let m = bevel_sector(gear, "pinion", &wide).unwrap_err().to_string();
    assert!(
        m.contains("shank_diameter_mm") && m.contains("rim below the teeth"),
        "{m}"
    );
    let m = bevel_sector(&sc.bodies[1], "gear", &opts)
        .unwrap_err()
        .to_string();
    assert!(m.contains("mounting plane"), "{m}");
}
