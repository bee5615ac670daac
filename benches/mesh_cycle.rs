//! FE contact mesh cycle of the seed 002 pair (wedge15 sectors, 3 teeth
//! each): the one-off setup (meshing, assembly, factorization) and the
//! time per roll angle with the factor reused (`flank::mesh_cycle`).
//!
//! `cargo bench --bench mesh_cycle`: criterion medians on a coarse mesh
//! (flank 0.75 mm, base 1.5 mm) at a double-contact and a single-contact
//! position. The paper-size figures (0.25 and 0.1 mm, time per position and
//! peak memory against the paper's 50 min per position) come from
//! `papers/seed002-spur/fe_contact_study.sh` and are in benches/README.md.

use std::time::Instant;

use criterion::{criterion_group, criterion_main, Criterion};

use flank::compliance::body::BodyMeshOptions;
use flank::mesh_cycle::cycle::{MeshCycle, RunSettings};
use flank::settings::{ContactLaw, SlaveBody};

fn cycle() -> MeshCycle {
    let scene = flank::scene::read_scene(std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/papers/seed002-spur/scene.toml"
    )))
    .unwrap();
    let mesh = BodyMeshOptions {
        flank_size: Some(0.75),
        base_size: Some(1.5),
        with_load: false,
        element: Some(flank::scene::ElementKind::Wedge15),
    };
    let settings = RunSettings {
        friction_mu: 0.0,
        law: ContactLaw::Hard,
        penalty_factor: 1.0,
        slave: SlaveBody::Pinion,
        search_distance_mm: 0.1,
        roll_angles_deg: vec![0.0],
        vtu: false,
        refine_contact_limits: false,
        reference_single_contact_start_deg: None,
        extend_step_deg: None,
        lubrication: None,
    };
    MeshCycle::new(&scene, &mesh, settings, 0).unwrap()
}

fn bench(c: &mut Criterion) {
    let t = Instant::now();
    let cyc = cycle();
    println!(
        "setup (mesh, assemble, factorize): {:.2} s, {} nodes, {} DOFs, factor nnz {}",
        t.elapsed().as_secs_f64(),
        cyc.pair.model.mesh.node_count(),
        cyc.system.stats.dofs,
        cyc.system.stats.nnz_factor
    );
    let (lpstc, hpstc) = cyc.line_pair().unwrap().single_contact();
    let single = 0.5 * (lpstc + hpstc).to_degrees();
    let mut g = c.benchmark_group("mesh_cycle_0.75mm");
    g.sample_size(10);
    g.bench_function("position_double_contact", |b| {
        b.iter(|| cyc.solve(-6.0).unwrap())
    });
    g.bench_function("position_single_contact", |b| {
        b.iter(|| cyc.solve(single).unwrap())
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
