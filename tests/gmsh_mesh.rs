#![cfg(feature = "gmsh")]
//! The gmsh gear-sector mesher (feature `gmsh`) on the seed 002 pinion, in
//! hex20 and in wedge15, at a coarse flank size: valid elements, the native
//! mesher's node sets, flank nodes on the exact involute/fillet, the clamped
//! and loaded body solves (and agrees with CalculiX if `ccx` is on the PATH),
//! and the mesh written by gmsh as `.msh` 4.1 reads back with the native
//! reader into the same mesh.

use std::path::{Path, PathBuf};
use std::time::Instant;

use flank::ccx::{ccx_executable, relative_difference, run_ccx};
use flank::fem::element::{check_jacobian, edges};
use flank::fem::mesh::{ElementKind, Mesh};
use flank::fem::static_analysis::{solve_static, SolveOptions};
use flank::geometry::rack::{Flank, ToothProfile};
use flank::geometry::GearSpec;
use flank::mesh::gear_body::{gear_body_with, Mesher};
use flank::mesh::gear_sector::{flank_segment, GearSectorMesh, SectorOptions};
use flank::mesh::gmsh::gmsh_sector_with_msh;
use flank::mesh::msh::read_msh;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn tmp(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("gmsh_mesh");
    std::fs::create_dir_all(&d).unwrap();
    d.join(name)
}

/// Clockwise rotation by `a` (the sector's tooth angle).
fn rot(p: [f64; 2], a: f64) -> [f64; 2] {
    let (s, c) = a.sin_cos();
    [c * p[0] + s * p[1], -s * p[0] + c * p[1]]
}

/// Distance of a transverse point (tooth 0) from the exact profile of one
/// flank, by sampling and golden-section search on u (independent of the
/// mesher's Newton projection).
fn profile_distance(p: &ToothProfile, f: Flank, q: [f64; 2], lo: f64, hi: f64) -> f64 {
    let d2 = |u: f64| {
        let e = p.point(f, flank_segment(p, u)).p;
        (e[0] - q[0]).powi(2) + (e[1] - q[1]).powi(2)
    };
    let n = 2000;
    let mut best = lo;
    for i in 0..=n {
        let u = lo + (hi - lo) * i as f64 / n as f64;
        if d2(u) < d2(best) {
            best = u;
        }
    }
    let step = (hi - lo) / n as f64;
    let (mut a, mut b) = ((best - step).max(lo), (best + step).min(hi));
    let gr = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..200 {
        let c = b - gr * (b - a);
        let d = a + gr * (b - a);
        if d2(c) < d2(d) {
            b = d;
        } else {
            a = c;
        }
    }
    d2(0.5 * (a + b)).sqrt()
}

/// Max distance of the flank nodes from the exact flank (spur: the normal
/// deviation) and max deviation of the quadratic flank edges at ξ = ±1/2.
fn flank_deviation(spec: &GearSpec, m: &GearSectorMesh, teeth: usize) -> (f64, f64) {
    let p = ToothProfile::new(spec, "pinion").unwrap();
    let (lo, hi) = (p.u_form - 1.0, p.u_tip);
    let pitch = p.angular_pitch();
    let to_tooth0 = |x: [f64; 3], k: usize| {
        let (s, c) = (p.twist_rate * x[2]).sin_cos();
        rot(
            [c * x[0] + s * x[1], -s * x[0] + c * x[1]],
            -((k - 1) as f64) * pitch,
        )
    };
    let mut node_dev = 0.0f64;
    let mut tooth_of = std::collections::HashMap::new();
    for k in 1..=teeth {
        for (f, nm) in [(Flank::Left, "FLANK_L"), (Flank::Right, "FLANK_R")] {
            for &n in &m.mesh.node_sets[&format!("{nm}{k}")] {
                tooth_of.insert(n, (k, f));
                let q = to_tooth0(m.mesh.coords[n], k);
                node_dev = node_dev.max(profile_distance(&p, f, q, lo, hi));
            }
        }
    }
    let mut edge_dev = 0.0f64;
    for el in &m.mesh.elements {
        for e in edges(el.kind) {
            let ns = [el.nodes[e[0]], el.nodes[e[1]], el.nodes[e[2]]];
            let Some(&(k, f)) = tooth_of.get(&ns[0]) else {
                continue;
            };
            if !ns.iter().all(|n| tooth_of.get(n) == Some(&(k, f))) {
                continue;
            }
            let x: Vec<[f64; 3]> = ns.iter().map(|&n| m.mesh.coords[n]).collect();
            for xi in [-0.5f64, 0.5] {
                let w = [0.5 * xi * (xi - 1.0), 0.5 * xi * (xi + 1.0), 1.0 - xi * xi];
                let y: Vec<f64> = (0..3)
                    .map(|c| w[0] * x[0][c] + w[1] * x[1][c] + w[2] * x[2][c])
                    .collect();
                let q = to_tooth0([y[0], y[1], y[2]], k);
                edge_dev = edge_dev.max(profile_distance(&p, f, q, lo, hi));
            }
        }
    }
    (node_dev, edge_dev)
}

/// The native reader's mesh equals gmsh's: same labels, coordinates,
/// connectivity (so the permutation is the same) and node sets.
fn compare_round_trip(a: &Mesh, b: &Mesh) {
    assert_eq!(a.node_count(), b.node_count(), "node count");
    assert_eq!(a.elements.len(), b.elements.len(), "element count");
    for (i, &l) in a.node_labels.iter().enumerate() {
        let j = b.node(l).expect("node label");
        for c in 0..3 {
            let (x, y) = (a.coords[i][c], b.coords[j][c]);
            assert!(
                (x - y).abs() <= 1e-13 * x.abs().max(1.0),
                "node {l}: {x} vs {y}"
            );
        }
    }
    for el in &a.elements {
        let e = b.element(el.label).expect("element label");
        let other = &b.elements[e];
        assert_eq!(el.kind, other.kind);
        let la: Vec<u64> = el.nodes.iter().map(|&n| a.node_labels[n]).collect();
        let lb: Vec<u64> = other.nodes.iter().map(|&n| b.node_labels[n]).collect();
        assert_eq!(la, lb, "element {}", el.label);
        check_jacobian(other.kind, &b.element_coords(e)).unwrap();
    }
    for name in a.node_sets.keys().filter(|n| *n != "NALL") {
        let mut la: Vec<u64> = a.node_sets[name]
            .iter()
            .map(|&n| a.node_labels[n])
            .collect();
        let mut lb: Vec<u64> = b.node_sets[name]
            .iter()
            .map(|&n| b.node_labels[n])
            .collect();
        la.sort_unstable();
        lb.sort_unstable();
        assert_eq!(la, lb, "node set {name}");
    }
    assert_eq!(b.element_sets["EALL"].len(), b.elements.len());
}

#[test]
fn seed002_pinion_gmsh_hex20_and_wedge15() {
    let scene = flank::scene::read_scene(&root().join("papers/seed002-spur/scene.toml")).unwrap();
    let spec = &scene.cylindrical("this test").unwrap().pair.pinion;
    let report =
        flank::geometry::pair::check_pair(&scene.cylindrical("this test").unwrap().pair).unwrap();
    let rb = flank::geometry::involute::base_radius(spec);
    let force = scene.load.torque_nmm / rb;
    let radius = rb / report.working_pressure_angle_rad.cos();
    let opts = SectorOptions {
        teeth: 3,
        flank_size: 1.0,
        base_size: 2.5,
        face_layers: 0,
        ..Default::default()
    };
    for kind in [ElementKind::C3D20, ElementKind::C3D15] {
        let tag = kind.name().to_ascii_lowercase();
        let msh = tmp(&format!("pinion_{tag}.msh"));
        let t = Instant::now();
        let (m, r) = gmsh_sector_with_msh(spec, "pinion", &opts, kind, Some(&msh)).unwrap();
        let t_mesh = t.elapsed().as_secs_f64();
        // every element valid, of the kind asked for
        for (e, el) in m.mesh.elements.iter().enumerate() {
            assert_eq!(el.kind, kind);
            check_jacobian(kind, &m.mesh.element_coords(e)).unwrap();
        }
        assert!(m.quality.min_scaled_jacobian > 0.1, "{:?}", m.quality);
        for set in [
            "BORE", "CUT_A", "CUT_B", "NALL", "FLANK_L1", "FLANK_R1", "FLANK_L2", "FLANK_R2",
            "FLANK_L3", "FLANK_R3",
        ] {
            assert!(!m.mesh.node_sets[set].is_empty(), "{tag}: {set}");
        }
        assert_eq!(m.mesh.element_sets["EALL"].len(), m.mesh.elements.len());
        let (node_dev, edge_dev) = flank_deviation(spec, &m, 3);
        println!(
            "{tag}: {} nodes, {} elements ({} layers), min scaled Jacobian {:.3}, max aspect ratio {:.1}; \
             meshed in {t_mesh:.2} s (gmsh {:.2} s); flank nodes moved ≤ {:.2e} mm onto the exact flank, \
             now off it by ≤ {node_dev:.2e} mm; flank edges at ξ = ±1/2 off by ≤ {edge_dev:.2e} mm",
            m.mesh.node_count(),
            m.mesh.elements.len(),
            r.layers,
            m.quality.min_scaled_jacobian,
            m.quality.max_aspect_ratio,
            r.gmsh_s,
            r.max_snap_mm,
        );
        assert!(
            node_dev < 1e-4,
            "flank node deviation {node_dev} mm ≥ 0.1 µm"
        );

        // round trip through gmsh's .msh 4.1 and the native reader
        let back = read_msh(&msh).unwrap();
        compare_round_trip(&m.mesh, &back);

        // the body: bore clamped, nominal normal force on the middle tooth
        let body = gear_body_with(
            spec,
            "pinion",
            &scene.pinion_material,
            &opts,
            Mesher::Gmsh(kind),
            Some((force, radius)),
        )
        .unwrap();
        let (node, f) = body.load.unwrap();
        let t = Instant::now();
        let sol = solve_static(
            &body.model,
            &SolveOptions {
                threads: 2,
                recover_stress: false,
                ..Default::default()
            },
        )
        .unwrap();
        let t_solve = t.elapsed().as_secs_f64();
        let d = &sol.displacement[3 * node..3 * node + 3];
        let along = (d[0] * f[0] + d[1] * f[1] + d[2] * f[2]) / force;
        println!(
            "{tag}: solve {} DOFs in {t_solve:.2} s, backward error {:.1e}; loaded node moves {along:.3e} mm along the force",
            sol.stats.dofs, sol.stats.backward_error
        );
        assert!(sol.stats.backward_error < 1e-14);
        assert!(along > 0.0);
        if ccx_executable().is_none() {
            assert!(std::env::var_os("CI").is_none(), "ccx missing on CI");
            println!("{tag}: ccx not found, cross-check skipped");
            continue;
        }
        let deck = tmp(&format!("pinion_{tag}.inp"));
        flank::deck::write_deck(&body.model, &deck).unwrap();
        let ccx = run_ccx(&deck, &tmp(&format!("ccx_{tag}")), 2).unwrap();
        let rel =
            relative_difference(&body.model.mesh, &sol.displacement, &ccx.displacements).unwrap();
        println!(
            "{tag}: ccx {:.2} s, max |u_flank − u_ccx| / max |u_ccx| = {rel:.2e}",
            ccx.wall_s
        );
        assert!(rel < 1e-6, "{tag}: flank vs ccx {rel}");
    }
}

/// `flank mesh --mesher gmsh` writes both bodies.
#[test]
fn cli_mesh_with_gmsh() {
    let out = tmp("cli_seed002");
    let _ = std::fs::remove_dir_all(&out);
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_flank"))
        .args([
            "mesh",
            "papers/seed002-spur/scene.toml",
            "--mesher",
            "gmsh",
            "--element",
            "wedge15",
            "--flank-size",
            "1.5",
            "--base-size",
            "4.0",
            "--no-load",
            "--out",
        ])
        .arg(&out)
        .current_dir(root())
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("mesh_report.json")).unwrap())
            .unwrap();
    for body in ["pinion", "gear"] {
        let b = &report["bodies"][body];
        assert_eq!(b["mesher"], "gmsh", "{b}");
        assert!(b["min_scaled_jacobian"].as_f64().unwrap() > 0.1, "{b}");
        let deck = flank::deck::read_deck(&out.join(format!("{body}.inp"))).unwrap();
        let mesh = &deck.model.mesh;
        assert!(mesh.elements.iter().all(|e| e.kind == ElementKind::C3D15));
        for set in ["BORE", "FLANK_L2", "FLANK_R2", "CUT_A", "CUT_B"] {
            assert!(mesh.node_sets.contains_key(set), "{body}: {set}");
        }
    }
}
