//! Face-milled bevel flank evaluation (`flank::geometry::bevel`): one
//! surface point + normal + principal curvatures per call (a Newton solve
//! of the equation of meshing from the flank's warm-start table, the
//! curvatures from the trait's default central differences of the exact
//! first derivatives), and a 100 × 50 grid of points and normals per
//! member by continuation ([`EnvelopeFlank::grid`]: implicit-function
//! predictor + Newton), on the ISO 23509 Annex F.2 spiral bevel set with
//! settings from its blank. Target (issue 16): a full grid under 10 ms.
//! The cradle map's jet is in closed form (`CradleGeneration::cutter_jet`,
//! ≈ 0.15–0.2 µs against ≈ 0.6 µs for the dual-number chain it replaced),
//! about 1.2 (gear) / 1.75 (pinion) Newton steps per grid point.
//! Criterion medians (1 thread, 2-core machine shared with other builds,
//! load average 3–5), before → after the closed-form jet: grid 9.8 → 4.4
//! ms (gear), 13.0 → 6.0 ms (pinion); point + normal + curvatures 15.0 →
//! 8.6 µs (gear), 18.5 → 10.0 µs (pinion).
//!
//! `cargo bench --bench bevel_geometry`.

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};

use flank::geometry::bevel::generated_surface::{FlankKind, GeneratedFlank};
use flank::geometry::bevel::machine_settings::{member_setup, CutterChoice, Member, MemberBlank};
use flank::geometry::bevel::{blank_design, BlankInputs};
use flank::geometry::surface::{principal_curvatures, ToothSurface};
use flank::geometry::Hand;

const F2: &str = r#"{"method": 0, "Sigma_deg": 90, "a_mm": 0, "z1": 14, "z2": 39, "de2_mm": 176.893, "b2_mm": 25.4, "beta_m2_deg": 35.0, "rc0_mm": 114.3, "data_type": "II", "alpha_dD_deg": 20, "alpha_dC_deg": 20, "f_alim": 0, "c_ham": 0.24737, "k_d": 2.0, "k_c": 0.125, "k_t": 0.0915, "backlash": "outer normal jen 0.127", "theta_a2_deg": 2.1342, "theta_f2_deg": 6.4934}"#;

fn flank(member: Member, hand: Hand) -> GeneratedFlank {
    let design = blank_design(&BlankInputs::from_json(F2).unwrap()).unwrap();
    let blank = MemberBlank::from_design(&design, member).unwrap();
    let cutter = CutterChoice {
        mean_radius: 114.3,
        edge_radius: 0.6,
        blade_height: None,
    };
    member_setup(&blank, hand, &cutter, true)
        .unwrap()
        .flank(FlankKind::Concave)
        .unwrap()
}

fn bench(c: &mut Criterion) {
    for (name, member, hand) in [
        ("gear", Member::Gear, Hand::Left),
        ("pinion", Member::Pinion, Hand::Right),
    ] {
        let f = flank(member, hand);
        let (v0, v1) = f.v_range();
        let v = 0.37 * v0 + 0.63 * v1;
        let u = 0.5 * (f.u_form(v) + f.u_tip(v));
        c.bench_function(&format!("bevel {name}: point + normal + curvatures"), |b| {
            b.iter(|| {
                let (p, n, _, _) = f.evaluate(black_box(u), black_box(v));
                let k = principal_curvatures(&f, u, v);
                black_box((p, n, k))
            })
        });
        c.bench_function(
            &format!("bevel {name}: 100 x 50 grid (continuation)"),
            |b| b.iter(|| black_box(f.envelope().grid(100, 50).unwrap().len())),
        );
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
