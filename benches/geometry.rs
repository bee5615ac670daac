//! Tooth-surface evaluation through the gear-pair interface
//! (`flank::geometry::surface::ToothSurface`), the figures every analysis
//! pays per geometric query: one point + normal + first derivatives, the
//! principal curvatures (second derivatives by central differences of the
//! first), a closest-point search, and a 100 × 50 grid of points and normals
//! over one flank, on the seed 004 helical pinion (an exact rack-generated
//! involute helicoid) with and without a flank modification.
//!
//! `cargo bench --bench geometry`. Reference figures for the hypoid
//! surfaces to come (issue target there: a full 100 × 50 flank grid in
//! under 10 ms).

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};

use flank::geometry::cylindrical::CylindricalGear;
use flank::geometry::gear_pair::{Flank, GearBody};
use flank::geometry::surface::{principal_curvatures, ToothSurface};
use flank::geometry::{GearSpec, Hand, RackProfile};

fn helical_pinion() -> GearSpec {
    GearSpec {
        teeth: 21,
        normal_module: 15.0,
        normal_pressure_angle: 20f64.to_radians(),
        helix_angle: 20f64.to_radians(),
        hand: Hand::Right,
        face_width: 180.0,
        profile_shift: 0.0,
        rack: RackProfile::default(),
        tip_diameter: None,
        bore_diameter: 100.0,
    }
}

fn grid(f: &dyn ToothSurface, nu: usize, nv: usize) -> f64 {
    let (v0, v1) = f.v_range();
    let mut acc = 0.0;
    for j in 0..nv {
        let v = v0 + (v1 - v0) * j as f64 / (nv - 1) as f64;
        let (u0, u1) = (f.u_form(v), f.u_tip(v));
        for i in 0..nu {
            let u = u0 + (u1 - u0) * i as f64 / (nu - 1) as f64;
            let (p, n, _, _) = f.evaluate(u, v);
            acc += p[0] + n[1];
        }
    }
    acc
}

fn bench(c: &mut Criterion) {
    let spec = helical_pinion();
    let gear = CylindricalGear::new(&spec, "pinion", 3, None).unwrap();
    let f = gear.flank(Flank::Right, 2).unwrap();
    let (u0, u1) = (f.u_form(0.0), f.u_tip(0.0));
    let (u, v) = (0.5 * (u0 + u1), 90.0);
    let mut g = c.benchmark_group("surface");
    g.bench_function("evaluate (point, normal, r_u, r_v)", |b| {
        b.iter(|| f.evaluate(black_box(u), black_box(v)))
    });
    g.bench_function("principal curvatures", |b| {
        b.iter(|| principal_curvatures(f, black_box(u), black_box(v)))
    });
    let p = f.point(u, v);
    let q = [p[0] + 0.01, p[1] - 0.02, p[2] + 0.5];
    g.bench_function("closest point from a seed", |b| {
        b.iter(|| f.closest_point_from(black_box(q), u0, v))
    });
    g.bench_function("grid 100 x 50 (point + normal)", |b| {
        b.iter(|| grid(f, 100, 50))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
