//! # Face-hobbed bevel and hypoid flanks (continuous indexing)
//!
//! The ISO 23509 Annex F sample F4 (method 2, Oerlikon face hobbing, hypoid
//! 9/34, z₀ = 13, r_c0 = 76 mm) gives the blank; `hobbing_settings` turns it
//! into face-hobbing machine settings and blades; `face_hobbing` is the
//! kinematic chain; the generic envelope engine solves the flanks. Checks
//! (README.md gives the references and the obtained figures):
//!
//! (a) equation of meshing and normal ⟂ r_u, r_v on 21 × 11 grids of both
//!     flanks of both members (generated; the pinion on the gear's crown
//!     gear) and of a formate gear;
//! (b) r_u, r_v against central differences of the points;
//! (c) the gear's pitch-cone tooth traces, developed into the crown-gear
//!     plane, against the closed-form extended epicycloid;
//! (d) the gear's spiral angle, lead angle ν and base radius ρ_b measured
//!     on the surface at the mean point against the blank design;
//! (e) bad input gives errors naming the setting;
//! (f)–(h) in `palloid.rs`: the pinion on the gear's crown gear (mean
//!     point, offset), a spiral bevel pair cut with one crown gear is
//!     conjugate, a formate gear and the pinion it generates are conjugate.

use std::f64::consts::{FRAC_PI_2, PI, TAU};
use std::time::Instant;

use flank::geometry::bevel::cutter::BladeSide;
use flank::geometry::bevel::hobbing_settings::{
    HobbedFlank, HobbingBlank, HobbingCutter, HobbingSetup, Member,
};
use flank::geometry::bevel::{blank_design, BlankDesign, BlankInputs};
use flank::geometry::surface::ToothSurface;
use flank::geometry::vec3::{dot, norm};

/// ISO 23509:2016 Annex F, sample F4 inputs (`../shared/reference/iso23509_annexF.json`).
pub(crate) const F4: &str = r#"{"method": 2, "Sigma_deg": 90, "a_mm": 31.75, "z1": 9, "z2": 34,
 "dm2_mm": 146.7, "b2_mm": 26.0, "beta_m2_deg": 21.009, "rc0_mm": 76.0, "z0": 13,
 "data_type": "II", "alpha_dD_deg": 20, "alpha_dC_deg": 20, "f_alim": 1.0,
 "c_ham": 0.275, "k_d": 2.0, "k_c": 0.125, "k_t": 0.1}"#;

fn design() -> BlankDesign {
    blank_design(&BlankInputs::from_json(F4).unwrap()).unwrap()
}

pub(crate) fn cutter() -> HobbingCutter {
    HobbingCutter {
        radius: 76.0,
        blade_groups: 13,
        edge_radius: 0.6,
    }
}

/// The gear on its own crown gear; the pinion on the gear's
/// (`HobbingSetup::pinion_from_gear`, the generated gear's crown gear).
fn setup(member: Member, generated: bool) -> HobbingSetup {
    let d = design();
    let g = HobbingSetup::new(
        HobbingBlank::from_design(&d, Member::Gear).unwrap(),
        cutter(),
        generated || member == Member::Pinion,
    )
    .unwrap();
    match member {
        Member::Gear => g,
        Member::Pinion => HobbingSetup::pinion_from_gear(
            &g,
            HobbingBlank::from_design(&d, Member::Pinion).unwrap(),
            generated,
        )
        .unwrap(),
    }
}

pub(crate) const SIDES: [BladeSide; 2] = [BladeSide::Outside, BladeSide::Inside];

/// (a): max |meshing residual|, max |n·r_u|, |n·r_v| above the root row,
/// max |n·r_u|/|r_u|, |n·r_v|/|r_v| over the whole grid.
pub(crate) fn grid_residuals(f: &HobbedFlank) -> (f64, f64, f64) {
    let (r0, r1) = f.v_range();
    let (mut mesh, mut orth, mut rel) = (0.0f64, 0.0f64, 0.0f64);
    for j in 0..11 {
        let v = r0 + (r1 - r0) * j as f64 / 10.0;
        let (ur, ut) = (f.u_root(v), f.u_tip(v));
        for i in 0..21 {
            let u = ur + (ut - ur) * i as f64 / 20.0;
            mesh = mesh.max(f.meshing_residual(u, v).unwrap().abs());
            let (_, n, ru, rv) = f.try_evaluate(u, v).unwrap();
            assert!((norm(n) - 1.0).abs() < 1e-12);
            // relative to |r_u|, |r_v| on every row (the root row's r_u is
            // ~1e6: the axial section is singular where the edge radius
            // touches the root cone), absolute above the root row
            rel = rel
                .max(dot(n, ru).abs() / norm(ru))
                .max(dot(n, rv).abs() / norm(rv));
            if i > 0 {
                orth = orth.max(dot(n, ru).abs()).max(dot(n, rv).abs());
            }
        }
    }
    (mesh, orth, rel)
}

#[test]
fn a_meshing_and_normals_on_grids() {
    let t = Instant::now();
    for member in [Member::Gear, Member::Pinion] {
        // formate: the gear only (a formate hypoid pinion is no practical
        // case; on the gear's crown gear its concave flank fails, see README)
        let kinds: &[bool] = match member {
            Member::Gear => &[true, false],
            Member::Pinion => &[true],
        };
        for &generated in kinds {
            let s = setup(member, generated);
            for side in SIDES {
                let f = s.flank(side).unwrap();
                let (mesh, orth, rel) = grid_residuals(&f);
                println!(
                    "(a) {member:?} {} {side:?} blade: max |f| {mesh:.2e}, max |n·r_u|,|n·r_v| {orth:.2e} (above the root row), relative {rel:.2e} (all rows)",
                    if generated { "generated" } else { "formate" }
                );
                assert!(
                    mesh <= 1e-10 && orth <= 1e-10 && rel <= 1e-10,
                    "{mesh} {orth} {rel}"
                );
            }
        }
    }
    // orientation and placement: both flanks of tooth 0 at the mean point;
    // each outward normal points away from the other flank (across the
    // tooth's material)
    for member in [Member::Gear, Member::Pinion] {
        let s = setup(member, true);
        let rm = s.blank.mean_cone_distance;
        let (pc, nc, _, _) = s
            .flank(BladeSide::Outside)
            .unwrap()
            .try_evaluate(0.0, rm)
            .unwrap();
        let (px, nx, _, _) = s
            .flank(BladeSide::Inside)
            .unwrap()
            .try_evaluate(0.0, rm)
            .unwrap();
        let d = [px[0] - pc[0], px[1] - pc[1], px[2] - pc[2]];
        let chord = norm(d);
        println!(
            "(a) {member:?}: tooth 0 at R_m: chord between the flanks {chord:.4} mm (design s_mn/cos β_m {:.4} mm), n_concave·d/|d| {:.4}, n_convex·d/|d| {:.4}",
            s.blank.normal_thickness / s.blank.spiral_angle.cos(),
            dot(nc, d) / chord,
            dot(nx, d) / chord
        );
        assert!(dot(nc, d) < 0.0 && dot(nx, d) > 0.0);
        // tooth 0 is centred on +y
        assert!(pc[1] > 0.0 && px[1] > 0.0 && pc[0] * px[0] < 0.0);
    }
    println!("(a) run time {:.2} s", t.elapsed().as_secs_f64());
}

#[test]
fn b_derivatives_against_central_differences() {
    let h = 1e-5;
    let mut worst = 0.0f64;
    for member in [Member::Gear, Member::Pinion] {
        let s = setup(member, true);
        for side in SIDES {
            let f = s.flank(side).unwrap();
            let (r0, r1) = f.v_range();
            for j in 0..5 {
                let v = r0 + 0.5 + (r1 - r0 - 1.0) * j as f64 / 4.0;
                let (ur, ut) = (f.u_root(v), f.u_tip(v));
                for i in 0..5 {
                    let u = ur + 0.2 + (ut - ur - 0.4) * i as f64 / 4.0;
                    let (_, _, ru, rv) = f.try_evaluate(u, v).unwrap();
                    let p = |u: f64, v: f64| f.try_evaluate(u, v).unwrap().0;
                    let (a, b) = (p(u + h, v), p(u - h, v));
                    let (c, d) = (p(u, v + h), p(u, v - h));
                    for k in 0..3 {
                        worst = worst
                            .max(((a[k] - b[k]) / (2.0 * h) - ru[k]).abs())
                            .max(((c[k] - d[k]) / (2.0 * h) - rv[k]).abs());
                    }
                }
            }
        }
    }
    println!("(b) max |r_u, r_v − central difference (h = 1e-5)| = {worst:.2e}");
    assert!(worst < 1e-7, "{worst}");
}

fn wrap(a: f64) -> f64 {
    (a + PI).rem_euclid(TAU) - PI
}

#[test]
fn c_pitch_trace_is_the_extended_epicycloid() {
    // the gear: its pitch cone's apex is the crown gear's centre, so its
    // development is the crown plane (the pinion's apex is offset: (f))
    {
        let member = Member::Gear;
        let s = setup(member, true);
        let delta = s.blank.pitch_angle;
        for side in SIDES {
            let blade = s.blade(side);
            let f = s.flank(side).unwrap();
            let prof = f.map().profile();
            let x = prof.rho_h(prof.s_at_height(s.blank.mean_dedendum)).0;
            let epi = s.epicycloid(&blade, x);
            let (r0, r1) = f.v_range();
            let mut worst = 0.0f64;
            for j in 0..21 {
                let v = r0 + (r1 - r0) * j as f64 / 20.0;
                let p = f.envelope().solve(0.0, v).unwrap();
                let r = p.jet.r;
                let phi = r[1].atan2(r[0]);
                let theta = f.map().cutter_angle(p.q);
                let tau = epi.at_radius(v, theta).expect("closed form at radius");
                let (e, _) = epi.point(tau);
                // developed pitch cone: crown angle = −(Φ − π/2) sin δ
                let err = wrap(e[1].atan2(e[0]) + (phi - FRAC_PI_2) * delta.sin()).abs() * v;
                worst = worst.max(err);
                // and the closed form's parameter is the cutter angle θ
                assert!((tau - theta).abs() < 1e-9, "{tau} {:?}", p.q);
            }
            println!("(c) {member:?} {side:?} blade: max distance of the developed pitch trace from the epicycloid {worst:.2e} mm");
            assert!(worst < 1e-9, "{worst}");
        }
    }
}

#[test]
fn d_mean_point_spiral_angle_lead_angle_base_radius() {
    let d = design();
    let hob = d.hobbing.expect("F4 is face hobbing");
    // the gear (the pinion on the gear's crown gear: (f))
    {
        let member = Member::Gear;
        let s = setup(member, true);
        // the blade through the mean point itself (space width 0)
        let mut mean = s.outside;
        let alpha = mean.blade.pressure_angle;
        mean.blade.point_radius = s.mean_in_plane - s.blank.mean_dedendum * alpha.tan();
        let f = s.flank_with(mean).unwrap();
        let rm = s.blank.mean_cone_distance;
        let m = f.measure(0.0, rm).unwrap();
        let beta = m.spiral_angle;
        // developed trace tangent at P = (R_m, 0): t = (cos β, −hand sin β)
        let t = [beta.cos(), -m.hand_sign * beta.sin()];
        let n = [-t[1], t[0]];
        let ms = &s.settings.machine;
        let c = [
            ms.radial_distance * ms.cradle_angle.cos(),
            ms.radial_distance * ms.cradle_angle.sin(),
        ];
        // normal line P + k n meets the line O→C at I = μ C
        // rm + k n0 = μ c0, k n1 = μ c1
        let k = -rm * c[1] / (n[0] * c[1] - n[1] * c[0]);
        let i_pt = [rm + k * n[0], k * n[1]];
        let rho_b = i_pt[0].hypot(i_pt[1]);
        let pc = [c[0] - rm, c[1]];
        let pi = [i_pt[0] - rm, i_pt[1]];
        let nu = ((pc[0] * pi[0] + pc[1] * pi[1]) / (pc[0].hypot(pc[1]) * pi[0].hypot(pi[1])))
            .clamp(-1.0, 1.0)
            .acos();
        let nu = nu.min(PI - nu);
        let (beta_d, nu_d, rho_d) = match member {
            Member::Gear => (d.cones.beta_m2.abs(), hob.nu, hob.rho_b),
            Member::Pinion => (d.cones.beta_m1.abs(), s.lead_angle, s.base_radius),
        };
        println!(
            "(d) {member:?}: β measured {:.9}° design {:.9}° | ν {:.9}° design {:.9}° | ρ_b {:.9} mm design {:.9} mm | cone distance {:.12}",
            beta.to_degrees(),
            beta_d.to_degrees(),
            nu.to_degrees(),
            nu_d.to_degrees(),
            rho_b,
            rho_d,
            m.cone_distance
        );
        assert!((beta - beta_d).abs() < 1e-9);
        assert!((nu - nu_d).abs() < 1e-9);
        assert!((rho_b - rho_d).abs() < 1e-8);
        assert!((m.cone_distance - rm).abs() < 1e-10);
        // the blade offset |b| = z0 m_mn / 2 (ISO 23509 clause 6.3)
        assert!((mean.offset.abs() - 13.0 * d.cones.m_mn / 2.0).abs() < 1e-10);
        // the two flanks' spiral angles equal their own epicycloids'
        for side in SIDES {
            let blade = s.blade(side);
            let f = s.flank(side).unwrap();
            let prof = f.map().profile();
            let x = prof.rho_h(prof.s_at_height(s.blank.mean_dedendum)).0;
            let epi = s.epicycloid(&blade, x);
            let q = f.envelope().solve(0.0, rm).unwrap().q;
            let closed = epi.spiral_angle(epi.at_radius(rm, f.map().cutter_angle(q)).unwrap());
            let meas = f.measure(0.0, rm).unwrap();
            println!(
                "(d) {member:?} {side:?} blade: β at R_m measured {:.9}° epicycloid {:.9}°, normal pressure angle {:.6}° blade {:.6}°",
                meas.spiral_angle.to_degrees(),
                closed.to_degrees(),
                meas.pressure_angle.to_degrees(),
                blade.blade.pressure_angle.to_degrees()
            );
            assert!((meas.spiral_angle - closed).abs() < 1e-9);
        }
    }
}

#[test]
fn e_bad_input_names_the_setting() {
    let b = HobbingBlank::from_design(&design(), Member::Gear).unwrap();
    let msg = |c: HobbingCutter| HobbingSetup::new(b, c, true).unwrap_err().to_string();
    let e = msg(HobbingCutter {
        blade_groups: 0,
        ..cutter()
    });
    println!("(e) {e}");
    assert!(e.contains("blade_groups"));
    let e = msg(HobbingCutter {
        radius: 20.0,
        ..cutter()
    });
    println!("(e) {e}");
    assert!(e.contains("rc0"));
    let e = msg(HobbingCutter {
        radius: 10.0,
        blade_groups: 1,
        ..cutter()
    });
    println!("(e) {e}");
    assert!(e.contains("rc0") && e.contains("face width"));
    // settings that do not generate the flank: the Newton solve fails
    let mut s = HobbingSetup::new(b, cutter(), true).unwrap();
    s.settings.machine.radial_distance *= 3.0;
    let e = s.flank(BladeSide::Outside).unwrap_err().to_string();
    println!("(e) {e}");
    assert!(e.contains("radial_distance"));
}

mod palloid;
mod tilt;
