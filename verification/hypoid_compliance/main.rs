//! # Compliance tensors of hypoid flanks: against a direct solve, against CalculiX, and at the mean contact
//!
//! Issue 18 point 2 (see README.md beside this file). The compliance
//! machinery of the spur/helical bodies (`flank::compliance`, Schur
//! complement with the flank DOFs ordered last) runs unchanged on the
//! bevel sector meshes; the flank parameters are the surfaces' own
//! axial-section coordinates (u across the pitch generatrix, v the cone
//! distance). Checks:
//!
//! 1. the tensor's column at the loaded node, times the deck's nominal
//!    load, equals the displacement of every flank node in a direct solve
//!    of the same deck (flank's static solver, another ordering and
//!    factorization) to 1e-9, and in CalculiX to 1e-6 (the cross-code
//!    tolerance of `verification/ccx_crosscheck`);
//! 2. at the major axis of the middle pair's contact at roll 0 (point TCA),
//!    the directional compliances C_nn, C_nt, C_tn, C_tt (t the sliding
//!    direction) are reciprocal (C_nn, C_tt symmetric, C_tn = C_ntᵀ) to
//!    1e-12, C_nn is positive definite, and the interpolation reproduces
//!    the nodal tensors at the nodes;
//! 3. (ignored in CI, minutes) the compliance of a finite contact cell at
//!    the mean contact under mesh refinement.

#[path = "../common/mod.rs"]
mod common;

use std::path::Path;
use std::time::Instant;

use flank::compliance::body::{bevel_scene_body, BodyMeshOptions};
use flank::compliance::cache::FileFormat;
use flank::compliance::contact_probe::{directional_matrices, retain_meshed, ProbePoint};
use flank::compliance::interpolation::{CellShape, FlankInterpolator};
use flank::compliance::run::{
    body_tensor, mean_contact_axis, BodyTensorOptions, MEAN_CONTACT_POINTS,
};
use flank::compliance::{ComplianceOptions, ComplianceTensor};
use flank::deck::read_deck;
use flank::fem::static_analysis::{solve_static, SolveOptions};
use flank::scene::{read_scene, Scene};
use flank::settings::FlankSelection;
use flank::tca::major_axis::AxisPoint;

/// `papers/<seed>/<file>` (seed 003: `scene_eased.toml`, the pinion with a
/// bearing; its gear is the one of `scene.toml`).
fn scene(seed: &str, file: &str) -> Scene {
    let path = format!("{}/papers/{seed}/{file}", env!("CARGO_MANIFEST_DIR"));
    read_scene(Path::new(&path)).unwrap()
}

fn sizes(flank: f64, with_load: bool) -> BodyMeshOptions {
    BodyMeshOptions {
        flank_size: Some(flank),
        base_size: Some(4.0 * flank),
        with_load,
        element: None,
    }
}

fn tensor_of(
    sc: &Scene,
    name: &str,
    flank: f64,
    out: &Path,
) -> (std::sync::Arc<ComplianceTensor>, f64) {
    let body = bevel_scene_body(sc, name, &sizes(flank, true)).unwrap();
    let t = Instant::now();
    let bt = body_tensor(
        &body,
        &BodyTensorOptions {
            flanks: FlankSelection::Loaded,
            clamp_cuts: false,
            compliance: ComplianceOptions::default(),
            format: FileFormat::Native,
            campaign: None,
            region_u_min: None,
        },
        out,
    )
    .unwrap();
    (bt.tensor, t.elapsed().as_secs_f64())
}

/// Check 1 on the coarse seed 003 gear: C·f against a direct solve and ccx.
#[test]
fn seed003_gear_tensor_equals_direct_solve_and_ccx() {
    let sc = scene("seed003-hypoid", "scene_eased.toml");
    let work = common::scratch_dir("hypoid_compliance");
    let (tensor, t_tensor) = tensor_of(&sc, "gear", 1.5, &work);
    let deck = work.join("gear.inp");
    let parsed = read_deck(&deck).unwrap();
    let model = &parsed.model;
    // the deck's nominal load: one nodal force at the drive flank's mean point
    let mut force = std::collections::HashMap::<usize, [f64; 3]>::new();
    for f in &model.forces {
        force.entry(f.node).or_default()[f.component] += f.value;
    }
    assert_eq!(force.len(), 1, "one loaded node");
    let (&node, &f) = force.iter().next().unwrap();
    let label = model.mesh.node_labels[node];
    let j = tensor
        .flank
        .labels
        .iter()
        .position(|&l| l == label)
        .expect("the loaded node is a flank node");
    let t = Instant::now();
    let sol = solve_static(
        model,
        &SolveOptions {
            recover_stress: false,
            ..Default::default()
        },
    )
    .unwrap();
    let t_solve = t.elapsed().as_secs_f64();
    let index: Vec<usize> = tensor
        .flank
        .labels
        .iter()
        .map(|&l| model.mesh.node(l).unwrap())
        .collect();
    let predicted: Vec<[f64; 3]> = (0..tensor.node_count())
        .map(|i| {
            let c = tensor.block(i, j);
            [0, 1, 2].map(|a| c[a][0] * f[0] + c[a][1] * f[1] + c[a][2] * f[2])
        })
        .collect();
    let max_u = predicted
        .iter()
        .flat_map(|p| p.iter())
        .fold(0.0f64, |m, x| m.max(x.abs()));
    let diff = |u: &dyn Fn(usize) -> [f64; 3]| -> f64 {
        predicted
            .iter()
            .zip(&index)
            .flat_map(|(p, &n)| {
                let d = u(n);
                (0..3).map(move |a| (p[a] - d[a]).abs())
            })
            .fold(0.0f64, f64::max)
            / max_u
    };
    let direct = diff(&|n| {
        [
            sol.displacement[3 * n],
            sol.displacement[3 * n + 1],
            sol.displacement[3 * n + 2],
        ]
    });
    println!(
        "VERIFY hypoid_compliance seed003 gear: {} nodes, {} flank nodes (C {}×{}); tensor {t_tensor:.2} s, direct solve {t_solve:.2} s; max |C f − u| / max |u| over the flank = {direct:.2e} (tol 1e-9), max |u| = {max_u:.4e} mm",
        model.mesh.node_count(),
        tensor.node_count(),
        tensor.dim(),
        tensor.dim()
    );
    assert!(max_u > 0.0 && direct <= 1e-9, "{direct}");
    if !common::ccx_available() {
        return;
    }
    let ccx = common::run_ccx(&deck, &work.join("ccx"));
    let by_label = |n: usize| {
        ccx.displacements
            .get(&model.mesh.node_labels[n])
            .copied()
            .expect("ccx printed every node")
    };
    let cross = diff(&by_label);
    println!(
        "VERIFY hypoid_compliance seed003 gear vs ccx: max |C f − u_ccx| / max |u| over the flank = {cross:.2e} (tol 1e-6); ccx {:.2} s",
        ccx.wall_s
    );
    assert!(cross <= 1e-6, "{cross}");
}

fn probe(points: &[AxisPoint]) -> Vec<ProbePoint> {
    points
        .iter()
        .map(|p| ProbePoint {
            set: format!("FLANK_R{}", p.tooth),
            uv: p.uv,
            normal: p.normal,
            tangent: p.sliding,
        })
        .collect()
}

/// Check 2 on both coarse seed 003 members: directional compliances on the
/// major axis of the mean contact.
#[test]
fn seed003_directional_compliances_at_the_mean_contact() {
    let sc = scene("seed003-hypoid", "scene_eased.toml");
    let work = common::scratch_dir("hypoid_compliance_probe");
    let (a, axis) = mean_contact_axis(&sc).unwrap();
    println!("mean contact at roll 0: semi-major axis {a:.3} mm (δ = 0.00635 mm)");
    for (b, name) in ["pinion", "gear"].iter().enumerate() {
        let (tensor, t_tensor) = tensor_of(&sc, name, 1.5, &work);
        let (pts, outside) = retain_meshed(&tensor, probe(&axis[b])).unwrap();
        assert!(pts.len() >= 5, "{name}: {} points on the flank", pts.len());
        println!(
            "{name}: {} of {MEAN_CONTACT_POINTS} axis points on the active flank, {outside} of those beyond the meshed flank",
            axis[b].len()
        );
        // the interpolation reproduces the nodal tensors at the nodes
        let it = FlankInterpolator::new(&tensor).unwrap();
        let mut worst: f64 = 0.0;
        for i in (0..tensor.node_count()).step_by(97) {
            let set = &tensor.flank.sets[tensor.flank.set_of[i] as usize];
            let [u, v] = tensor.flank.uv[i];
            let w = it.point(set, u, v).unwrap();
            for &(a, wa) in &w.weights {
                let expect = if a as usize == i { 1.0 } else { 0.0 };
                worst = worst.max((wa - expect).abs());
            }
        }
        let m = directional_matrices(&tensor, &pts, None).unwrap();
        let r = m.report();
        println!(
            "VERIFY hypoid_compliance seed003 {name}: {} axis points; c_nn {:.4e}, c_tt {:.4e}, c_nt {:.4e}, c_tn {:.4e} mm/N; C_nn λ {:.3e}…{:.3e}, κ = {:.1}; reciprocity {:.1e} (tol 1e-12); nodal weights off by {worst:.1e}; tensor {t_tensor:.1} s",
            r.points, r.c_nn, r.c_tt, r.c_nt, r.c_tn, r.lambda_min, r.lambda_max, r.condition, r.reciprocity
        );
        assert!(r.reciprocity <= 1e-12, "{}", r.reciprocity);
        assert!(r.positive_definite);
        assert!(r.c_nn > 0.0 && r.c_tt > 0.0);
        // the cross terms exist on a tooth but are smaller than the direct ones
        assert!(r.c_nt.abs() < r.c_nn && r.c_tn.abs() < r.c_nn);
        assert!(worst < 1e-9, "{worst}");
    }
}

/// Check 3: the normal compliance of a 1 mm × 4 mm contact cell (u × v)
/// at the mean contact of the seed 003 gear, flank sizes 2 → 0.75 mm.
#[test]
#[ignore = "minutes: five tensors of the seed 003 gear down to 0.75 mm flank size"]
fn seed003_cell_compliance_under_refinement() {
    let sc = scene("seed003-hypoid", "scene_eased.toml");
    let (_, axis) = mean_contact_axis(&sc).unwrap();
    let centre = &axis[1][axis[1].len() / 2];
    let pts = probe(std::slice::from_ref(centre));
    let cell = CellShape::Rectangle { hu: 0.5, hv: 2.0 };
    println!(
        "| flank size (mm) | flank nodes | c_nn cell (mm/N) | c_nn point (mm/N) | tensor (s) |"
    );
    println!("|---|---|---|---|---|");
    for fs in [2.0, 1.5, 1.0, 0.75] {
        let work = common::scratch_dir(&format!("hypoid_compliance_{fs}"));
        let (tensor, t_tensor) = tensor_of(&sc, "gear", fs, &work);
        let c = directional_matrices(&tensor, &pts, Some((cell, 6))).unwrap();
        let p = directional_matrices(&tensor, &pts, None).unwrap();
        println!(
            "| {fs} | {} | {:.5e} | {:.5e} | {t_tensor:.1} |",
            tensor.node_count(),
            c.nn[0],
            p.nn[0]
        );
    }
}
