use std::collections::{HashMap, HashSet};
use std::path::Path;

use super::*;
use crate::fem::element::face_nodes;
use crate::geometry::gear_pair::{Flank, GearBody};
use crate::scene::{read_scene, BevelGears, Gears};

fn scene(seed: &str) -> BevelGears {
    let path = format!("{}/papers/{seed}/scene.toml", env!("CARGO_MANIFEST_DIR"));
    match read_scene(Path::new(&path)).unwrap().gears {
        Gears::Bevel(b) => *b,
        _ => panic!("{seed} is not a bevel scene"),
    }
}

/// The seeds' material (both members).
fn steel() -> crate::fem::material::Material {
    let path = format!(
        "{}/papers/seed003-hypoid/scene.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    read_scene(Path::new(&path)).unwrap().gear_material
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
fn assert_conforming(mesh: &crate::fem::mesh::Mesh, m: usize) {
    let mut faces: HashMap<Vec<usize>, usize> = HashMap::new();
    for e in &mesh.elements {
        for f in 1..=e.kind.face_count() {
            let nodes = face_nodes(e.kind, f).unwrap();
            let corners = nodes.len() / 2;
            let mut key: Vec<usize> = nodes[..corners].iter().map(|&i| e.nodes[i]).collect();
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

/// Seed 003's generated pinion (scene.toml) at `flank mesh`'s default sizes
/// (m/12 ≈ 0.486 mm on the flank, 4 × that in the rim): on the station at
/// cone distance 115.373 mm the form line's solve stalled at round-off
/// (meshing residual 1.07e-14 against 1e-14), the form line fell back to the
/// root line and the fillet's lattice points coincided ("a corner and a
/// midside node coincide"). Now the form line lies above the root line at
/// 401 cone distances across the face on both flanks, and the sector meshes.
#[test]
fn seed003_generated_pinion_meshes_at_the_default_sizes() {
    let sc = scene("seed003-hypoid");
    let pinion = &sc.bodies[0];
    for side in [Flank::Left, Flank::Right] {
        let f = pinion.flank(side, 1).unwrap();
        let (v0, v1) = f.v_range();
        let mut shortest = f64::INFINITY;
        for i in 0..=400 {
            let v = v0 + (v1 - v0) * i as f64 / 400.0;
            shortest = shortest.min(f.u_form(v) - f.u_root(v));
        }
        assert!(
            shortest > 0.1,
            "{side:?}: fillet height down to {shortest} mm"
        );
    }
    let h = 0.48605132617485347;
    let r = bevel_sector(
        pinion,
        "pinion",
        &BevelSectorOptions {
            flank_size: h,
            base_size: 4.0 * h,
            ..Default::default()
        },
    )
    .unwrap();
    assert!(r.quality.min_scaled_jacobian > 0.2, "{:?}", r.quality);
}

/// The mounted gear under its nominal load deflects along the load; the
/// reaction at the mount balances it.
#[test]
fn loaded_ring_gear_solves() {
    use crate::fem::static_analysis::{solve_static, SolveOptions};
    use crate::mesh::bevel_body::bevel_body_model;
    let sc = scene("seed003-hypoid");
    let body = bevel_body_model(&sc.bodies[1], "gear", &steel(), &coarse(), Some(1.0e6)).unwrap();
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

/// Bad input: a negative rim, sizes out of order; and seed 000's pinion, whose fillets meet at the
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

fn wedges() -> BevelSectorOptions {
    BevelSectorOptions {
        element: ElementKind::C3D15,
        ..coarse()
    }
}

/// Node coordinates of a set, sorted.
fn set_coords(mesh: &crate::fem::mesh::Mesh, set: &str) -> Vec<[f64; 3]> {
    let mut v: Vec<[f64; 3]> = mesh.node_sets[set]
        .iter()
        .map(|&n| mesh.coords[n])
        .collect();
    v.sort_by(|a, b| {
        a.iter()
            .zip(b)
            .fold(std::cmp::Ordering::Equal, |o, (x, y)| {
                o.then(x.total_cmp(y))
            })
    });
    v
}

/// Area (mm²) of the element faces on a node set.
fn set_area(mesh: &crate::fem::mesh::Mesh, set: &str) -> f64 {
    use crate::contact::surface::{face_area, faces_on_nodes, Face};
    faces_on_nodes(mesh, &mesh.node_sets[set])
        .into_iter()
        .map(|(e, f)| face_area(&Face::of_element(mesh, e, f).unwrap().coords(&mesh.coords)))
        .sum()
}

/// Wedge15 sectors of seed 003's pinion and ring gear and seed 000's ring
/// gear (its pinion has no gap land), coarse: every element a valid C3D15
/// (Jacobian checked while meshing, scaled Jacobian > 0.2), the mesh
/// conforming, flank nodes the surfaces' points (≤ 1e-9 mm), the node sets
/// of hex20's, the boundary ones on the flanks, lands, cuts and mount at
/// the same points (the flank faces are hex20's: FLANK_L1's area agrees
/// to 1e-9); at 0.5 mm, fewer nodes than hex20 (at 1 mm the teeth are
/// too few elements deep to coarsen much, and the split cells' centres
/// make the wedge mesh slightly larger: README of
/// verification/bevel_sector_mesh).
#[test]
fn wedge15_sectors_match_hex20() {
    let s3 = scene("seed003-hypoid");
    let s0 = scene("seed000-hypoid");
    let members = [
        ("seed003 pinion", &s3.bodies[0]),
        ("seed003 gear", &s3.bodies[1]),
        ("seed000 gear", &s0.bodies[1]),
    ];
    for (m, (what, gear)) in members.into_iter().enumerate() {
        let hex = bevel_sector(gear, "body", &coarse()).unwrap();
        let wed = bevel_sector(gear, "body", &wedges()).unwrap();
        let mesh = &wed.mesh;
        let (node_dist, dev) = flank_deviation(gear, &wed);
        let (a_hex, a_wed) = (set_area(&hex.mesh, "FLANK_L1"), set_area(mesh, "FLANK_L1"));
        println!(
            "{what}: hex20 {} nodes, {} elements, Jacobian {:.3}, aspect {:.1}; wedge15 {} nodes, {} elements, Jacobian {:.3}, aspect {:.1}; flank node distance {node_dist:.1e} mm, edge deviation {:.2e}/{:.2e} mm; FLANK_L1 area {a_hex:.6} / {a_wed:.6} mm²",
            hex.mesh.node_count(),
            hex.mesh.elements.len(),
            hex.quality.min_scaled_jacobian,
            hex.quality.max_aspect_ratio,
            mesh.node_count(),
            mesh.elements.len(),
            wed.quality.min_scaled_jacobian,
            wed.quality.max_aspect_ratio,
            dev[0],
            dev[1]
        );
        assert!(mesh.elements.iter().all(|e| e.kind == ElementKind::C3D15));
        assert!(wed.quality.min_scaled_jacobian > 0.2, "{:?}", wed.quality);
        assert_conforming(mesh, m);
        assert!(node_dist <= 1e-9, "{node_dist}");
        let names =
            |m: &crate::fem::mesh::Mesh| m.node_sets.keys().cloned().collect::<HashSet<_>>();
        assert_eq!(names(mesh), names(&hex.mesh));
        for set in mesh.node_sets.keys() {
            if matches!(set.as_str(), "NALL" | "TOE" | "HEEL") {
                // interior points differ (coarsened, split cells)
                assert!(!mesh.node_sets[set].is_empty());
                continue;
            }
            let (a, b) = (set_coords(mesh, set), set_coords(&hex.mesh, set));
            assert_eq!(a.len(), b.len(), "{what} {set}");
            let off = a
                .iter()
                .zip(&b)
                .flat_map(|(p, q)| (0..3).map(move |c| (p[c] - q[c]).abs()))
                .fold(0.0, f64::max);
            assert!(off < 1e-9, "{what} {set}: {off}");
        }
        assert!((a_wed - a_hex).abs() <= 1e-9 * a_hex, "{a_hex} {a_wed}");
        assert_eq!(wed.flank_uv.len(), hex.flank_uv.len());
    }
    for (m, gear) in s3.bodies.iter().enumerate() {
        let fine = |element| BevelSectorOptions {
            flank_size: 0.5,
            base_size: 2.0,
            element,
            ..Default::default()
        };
        let hex = bevel_sector(gear, "body", &fine(ElementKind::C3D20)).unwrap();
        let wed = bevel_sector(gear, "body", &fine(ElementKind::C3D15)).unwrap();
        let (nh, nw) = (hex.mesh.node_count(), wed.mesh.node_count());
        println!("seed003 member {m} at 0.5 mm: hex20 {nh} nodes, wedge15 {nw}");
        assert!(nw < nh, "{nw} {nh}");
    }
}

/// Seed 003's pinion with its shank in wedges: valid and conforming, the
/// bearing seat and the shank's end as hex20's.
#[test]
fn wedge15_pinion_shank() {
    let sc = scene("seed003-hypoid");
    let shank = Some(Shank {
        length: 40.0,
        diameter: 30.0,
    });
    let hex = bevel_sector(
        &sc.bodies[0],
        "pinion",
        &BevelSectorOptions { shank, ..coarse() },
    )
    .unwrap();
    let wed = bevel_sector(
        &sc.bodies[0],
        "pinion",
        &BevelSectorOptions { shank, ..wedges() },
    )
    .unwrap();
    println!(
        "pinion with shank: hex20 {} nodes, wedge15 {} nodes, Jacobian {:.3}",
        hex.mesh.node_count(),
        wed.mesh.node_count(),
        wed.quality.min_scaled_jacobian
    );
    assert!(wed.quality.min_scaled_jacobian > 0.2);
    assert_conforming(&wed.mesh, 0);
    for set in ["MOUNT", "BORE", "CUT_A", "CUT_B"] {
        assert_eq!(
            set_coords(&wed.mesh, set).len(),
            set_coords(&hex.mesh, set).len(),
            "{set}"
        );
    }
    assert!(!wed.mesh.node_sets["SHANK_END"].is_empty());
}

/// Seed 003's ring gear clamped at its mounting plane under the nominal
/// load (one nodal force at the drive flank's mean point): wedge15 and
/// hex20 at the same flank size (1 mm) move the tip land of the loaded
/// tooth alike. The tip node nearest the load lies a whole depth from it,
/// out of the point load's singular near field; both meshes are quadratic
/// with the same flank faces and flank-normal layers, the wedges coarser
/// inside the tooth only, so their difference is the bending
/// discretisation error of a coarse mesh: within 3 % (set before the run).
#[test]
fn wedge15_ring_gear_deflects_as_hex20() {
    use crate::fem::static_analysis::{solve_static, SolveOptions};
    use crate::mesh::bevel_body::bevel_body_model;
    let sc = scene("seed003-hypoid");
    let mut out = Vec::new();
    for opts in [coarse(), wedges()] {
        let body = bevel_body_model(&sc.bodies[1], "gear", &steel(), &opts, Some(1.0e6)).unwrap();
        let (node, f) = body.load.unwrap();
        let mesh = &body.model.mesh;
        let x = mesh.coords[node];
        let dist = |n: usize| {
            let y = mesh.coords[n];
            (0..3).map(|c| (y[c] - x[c]).powi(2)).sum::<f64>()
        };
        let tip = mesh.node_sets["TIP_LAND"]
            .iter()
            .copied()
            .min_by(|&a, &b| dist(a).total_cmp(&dist(b)))
            .unwrap();
        let t = std::time::Instant::now();
        let sol = solve_static(
            &body.model,
            &SolveOptions {
                threads: 2,
                ..Default::default()
            },
        )
        .unwrap();
        let fnorm = f.iter().map(|c| c * c).sum::<f64>().sqrt();
        let along = |n: usize| {
            let d = &sol.displacement[3 * n..3 * n + 3];
            (d[0] * f[0] + d[1] * f[1] + d[2] * f[2]) / fnorm
        };
        println!(
            "{}: {} nodes, {} dofs, solve {:.2} s; along the force: load node {:.4e} mm, tip node {:.4e} mm ({:.2} mm from the load)",
            opts.element.name(),
            mesh.node_count(),
            sol.stats.dofs,
            t.elapsed().as_secs_f64(),
            along(node),
            along(tip),
            dist(tip).sqrt()
        );
        out.push((mesh.coords[tip], along(tip), along(node)));
    }
    let ((x_hex, tip_hex, _), (x_wed, tip_wed, _)) = (out[0], out[1]);
    assert!((0..3).all(|c| (x_hex[c] - x_wed[c]).abs() < 1e-9));
    let rel = (tip_wed - tip_hex).abs() / tip_hex.abs();
    println!("tip displacement wedge15 vs hex20: {:.2} %", 100.0 * rel);
    assert!(tip_hex > 0.0 && rel < 0.03, "{tip_hex} {tip_wed}");
}
