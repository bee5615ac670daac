//! Compliance tensors of the seed 002 pinion (3-tooth hex20 sector, bore
//! clamped, the loaded flank FLANK_R1..3): one plain factorization against
//! all flank tensors by the Schur complement and by blocked right-hand sides.
//!
//! * `cargo bench --bench compliance`: criterion medians on the coarse mesh
//!   (flank 1 mm, base 3 mm).
//! * `FLANK_COMPLIANCE_FIGURES=0.475,0.25 cargo bench --bench compliance`:
//!   the figures of benches/README.md, one child process per case (so that
//!   each peak memory is its own), base size m_n/2 = 1.9 mm; the blocked
//!   method is timed on a sample of `FLANK_COMPLIANCE_SAMPLE` right-hand
//!   sides (default 600) and its rate extrapolated to all of them.
//! * `FLANK_COMPLIANCE_CASES` (default `plain,schur,blocked`) picks and
//!   orders the cases of each size; `active` is the Schur complement on
//!   the active flank only (start of active profile from the pair, plus
//!   the LTCA's margin of 2 flank elements + 1 mm, the fillet below left
//!   out), `FLANK_COMPLIANCE_ROUNDS` repeats the list (alternating runs),
//!   and the load average is printed beside every case.

use std::process::Command;
use std::time::Instant;

use criterion::{criterion_group, Criterion};

use flank::compliance::body::{
    active_flank_cut, active_margin_mm, body_flank_nodes, scene_body, BodyMeshOptions,
};
use flank::compliance::{compute_compliance, ComplianceOptions, FlankNodes};
use flank::fem::assembly::Assembly;
use flank::fem::constraints::DofMap;
use flank::fem::model::Model;
use flank::fem::ordering::OrderingMethod;
use flank::fem::solver::{parallelism, Precision, SparseCholesky};
use flank::fem::static_analysis::peak_memory_mb;
use flank::settings::{FlankSelection, Method};

/// The seed 002 pinion and its loaded flank nodes; with `active`, only the
/// active flank plus the LTCA's margin ([`FlankNodes::restrict_u`]).
fn pinion(flank_size: f64, base_size: f64, active: bool) -> (Model, FlankNodes) {
    let scene = flank::scene::read_scene(std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/papers/seed002-spur/scene.toml"
    )))
    .unwrap();
    let o = BodyMeshOptions {
        flank_size: Some(flank_size),
        base_size: Some(base_size),
        with_load: false,
        element: Some(flank::scene::ElementKind::Hex20),
    };
    let body = scene_body(&scene, "pinion", &o).unwrap();
    let mut flank = body_flank_nodes(&body, FlankSelection::Loaded).unwrap();
    if active {
        let cut = active_flank_cut(&scene, "pinion", active_margin_mm(flank_size)).unwrap();
        flank = flank.restrict_u(&vec![cut; flank.sets.len()]).unwrap();
    }
    (body.model, flank)
}

/// The 1-minute load average (for the figures' rows).
fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .ok()
        .and_then(|s| s.split_whitespace().next().map(String::from))
        .unwrap_or_else(|| "?".into())
}

/// One plain (unconstrained METIS) factorization; returns (seconds, GFLOP, nnz(L)).
fn plain_factorization(model: &Model) -> (f64, f64, usize) {
    let mut dofs = DofMap::new(model).unwrap();
    let asm = Assembly::new(model, &mut dofs, OrderingMethod::Metis).unwrap();
    let sys = asm.assemble(model, &dofs).unwrap();
    let mut chol =
        SparseCholesky::analyze(&asm.pattern, OrderingMethod::Metis, 0.0, parallelism(0)).unwrap();
    let t = Instant::now();
    chol.factorize(&asm.pattern, &sys.values, Precision::Double, &|r| {
        format!("dof {r}")
    })
    .unwrap();
    (
        t.elapsed().as_secs_f64(),
        chol.stats.flops * 1e-9,
        chol.stats.nnz_factor,
    )
}

/// The first `n` nodes of the flank selection (for timing a sample of RHS).
fn subset(f: &FlankNodes, n: usize) -> FlankNodes {
    let n = n.min(f.len());
    FlankNodes {
        sets: f.sets.clone(),
        nodes: f.nodes[..n].to_vec(),
        labels: f.labels[..n].to_vec(),
        set_of: f.set_of[..n].to_vec(),
        uv: f.uv[..n].to_vec(),
        positions: f.positions[..n].to_vec(),
        normals: f.normals[..n].to_vec(),
        faces: Vec::new(),
    }
}

fn coarse(c: &mut Criterion) {
    let (model, flank) = pinion(1.0, 3.0, false);
    let mut g = c.benchmark_group("compliance_pinion_flank1mm");
    g.sample_size(10);
    g.bench_function("plain_factorization", |b| {
        b.iter(|| plain_factorization(&model))
    });
    for method in [Method::Schur, Method::Blocked] {
        let o = ComplianceOptions {
            method,
            condition: false,
            ..Default::default()
        };
        g.bench_function(format!("all_tensors_{}", method.name()), |b| {
            b.iter(|| compute_compliance(&model, &flank, &o).unwrap())
        });
    }
    g.finish();
}

criterion_group!(benches, coarse);

/// Child process: one case, printed as a JSON line.
fn run_case(spec: &str) {
    let parts: Vec<&str> = spec.split(':').collect();
    let (what, flank_size): (&str, f64) = (parts[0], parts[1].parse().unwrap());
    let (model, flank) = pinion(flank_size, 1.9, what == "active");
    let nodes = model.mesh.node_count();
    let m = 3 * flank.len();
    let out = match what {
        "plain" => {
            let (s, gflop, nnz) = plain_factorization(&model);
            serde_json::json!({"case": what, "flank_size": flank_size, "nodes": nodes, "rhs": m,
                "factorization_s": s, "gflop": gflop, "nnz_factor": nnz})
        }
        "schur" | "active" | "blocked" => {
            let sample: usize = std::env::var("FLANK_COMPLIANCE_SAMPLE")
                .ok()
                .and_then(|v| v.parse().ok())
                .unwrap_or(600);
            let (f, method) = if what != "blocked" {
                (flank.clone(), Method::Schur)
            } else {
                (subset(&flank, sample.div_ceil(3)), Method::Blocked)
            };
            let o = ComplianceOptions {
                method,
                condition: false,
                ..Default::default()
            };
            let t = Instant::now();
            let (_, s) = compute_compliance(&model, &f, &o).unwrap();
            let wall = t.elapsed().as_secs_f64();
            // blocked: the solve rate of the sample, extrapolated to every RHS
            let solve_all = s.solve_s * m as f64 / s.rhs as f64;
            serde_json::json!({"case": what, "flank_size": flank_size, "nodes": nodes, "rhs": m,
                "rhs_timed": s.rhs, "factorization_s": s.factorization_s, "gflop": s.factorization_gflop,
                "nnz_factor": s.nnz_factor, "solve_s": s.solve_s, "solve_all_s": solve_all,
                "symmetrize_s": s.symmetrize_s, "wall_s": wall, "block_size": s.block_size})
        }
        _ => panic!("unknown case {what}"),
    };
    let mut out = out;
    out["peak_memory_mb"] = serde_json::json!(peak_memory_mb());
    println!("CASE {out}");
}

fn figures(sizes: &str) {
    let exe = std::env::current_exe().unwrap();
    let cases =
        std::env::var("FLANK_COMPLIANCE_CASES").unwrap_or_else(|_| "plain,schur,blocked".into());
    let rounds: usize = std::env::var("FLANK_COMPLIANCE_ROUNDS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(1);
    println!("| flank size | case | load (1 min) | nodes | m = 3N | time (s) | GFLOP | / plain (same round) | RHS/s | peak MB |");
    println!("|---|---|---|---|---|---|---|---|---|---|");
    for fs in sizes.split(',') {
        for round in 0..rounds {
            let mut plain = f64::NAN;
            for case in cases.split(',') {
                let load = load_average();
                let o = Command::new(&exe)
                    .env("FLANK_COMPLIANCE_CASE", format!("{case}:{fs}"))
                    .output()
                    .unwrap();
                let text = String::from_utf8_lossy(&o.stdout);
                let line = text
                    .lines()
                    .find_map(|l| l.strip_prefix("CASE "))
                    .unwrap_or_else(|| panic!("{case}: {}", String::from_utf8_lossy(&o.stderr)));
                eprintln!("round {round} load {load}: {line}");
                let v: serde_json::Value = serde_json::from_str(line).unwrap();
                let f = |k: &str| v[k].as_f64().unwrap_or(f64::NAN);
                let time = match case {
                    "plain" => f("factorization_s"),
                    "blocked" => f("factorization_s") + f("solve_all_s"),
                    _ => f("factorization_s") + f("solve_s") + f("symmetrize_s"),
                };
                if case == "plain" {
                    plain = time;
                }
                let rate = match case {
                    "plain" => f64::NAN,
                    "blocked" => f("rhs_timed") / f("solve_s"),
                    _ => f("rhs") / time,
                };
                println!(
                    "| {fs} mm | {case} | {load} | {} | {} | {time:.2} | {:.0} | {:.2}× | {rate:.0} | {:.0} |",
                    v["nodes"], v["rhs"], f("gflop"), time / plain, f("peak_memory_mb"),
                );
            }
        }
    }
}

fn main() {
    if let Ok(spec) = std::env::var("FLANK_COMPLIANCE_CASE") {
        run_case(&spec);
        return;
    }
    if let Ok(sizes) = std::env::var("FLANK_COMPLIANCE_FIGURES") {
        figures(&sizes);
        return;
    }
    benches();
    Criterion::default().configure_from_args().final_summary();
}
