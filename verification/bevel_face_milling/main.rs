//! # Face-milled (Gleason) generated bevel flanks
//!
//! The envelope engine (`geometry::bevel::generation`) on the cradle
//! machine (`cradle_machine`) with the face-milling cutter (`cutter`), for
//! the ISO 23509 Annex F.2 spiral bevel set (z 14/39, β_m 35°, r_c0
//! 114.3 mm) with settings from its blank (`machine_settings`): the gear
//! generated and formate, the pinion generated, both flanks each. Checks
//! (README.md gives the figures):
//!
//! 1. on a 21 × 11 grid of each flank (root → tip × toe → heel): the
//!    meshing residual and |n·r_u|/|r_u|, |n·r_v|/|r_v| ≤ 1e-10;
//! 2. r_u, r_v against central differences of the points;
//! 3. principal curvatures against a least-squares fit of the surface's
//!    height over its tangent plane;
//! 4. the formate gear lies on the cutter's cone (re-derived from the
//!    documented frames, not through the engine);
//! 5. the mean-point spiral and pressure angles and cone distance against
//!    the blank;
//! 6. straight-bevel reduction: zero offset, zero spiral, plane tool
//!    through the apex on a plane crown gear (infinite cutter radius): the
//!    generated flank is the octoid of the first kind, in closed form the
//!    cone of the characteristic lines n(ψ) × n′(ψ) of the tool planes;
//! 7. non-physical settings give errors naming the settings.

use std::f64::consts::PI;
use std::time::Instant;

use flank::geometry::bevel::cradle_machine::{CradleGeneration, CradleTool, MachineSettings};
use flank::geometry::bevel::generated_surface::{FlankKind, GeneratedFlank};
use flank::geometry::bevel::generation::{AxialSection, ConeLine, EnvelopeFlank, SolveOptions};
use flank::geometry::bevel::machine_settings::{
    check_mean_point, member_setup, refined_setup, CutterChoice, Member, MemberBlank,
};
use flank::geometry::bevel::{blank_design, BlankInputs};
use flank::geometry::surface::{principal_curvatures, ToothSurface};
use flank::geometry::Hand;
use nalgebra::{DMatrix, DVector};

type V3 = [f64; 3];

const F2: &str = r#"{"method": 0, "Sigma_deg": 90, "a_mm": 0, "z1": 14, "z2": 39, "de2_mm": 176.893, "b2_mm": 25.4, "beta_m2_deg": 35.0, "rc0_mm": 114.3, "data_type": "II", "alpha_dD_deg": 20, "alpha_dC_deg": 20, "f_alim": 0, "c_ham": 0.24737, "k_d": 2.0, "k_c": 0.125, "k_t": 0.0915, "backlash": "outer normal jen 0.127", "theta_a2_deg": 2.1342, "theta_f2_deg": 6.4934}"#;

fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn norm(a: V3) -> f64 {
    dot(a, a).sqrt()
}
fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn cutter() -> CutterChoice {
    CutterChoice {
        mean_radius: 114.3,
        edge_radius: 0.6,
        blade_height: None,
    }
}

fn blank(member: Member) -> MemberBlank {
    let design = blank_design(&BlankInputs::from_json(F2).unwrap()).unwrap();
    MemberBlank::from_design(&design, member).unwrap()
}

/// The five flanks: (name, flank).
fn flanks() -> Vec<(String, GeneratedFlank)> {
    let mut out = vec![];
    for (member, hand, generated) in [
        (Member::Gear, Hand::Left, true),
        (Member::Gear, Hand::Left, false),
        (Member::Pinion, Hand::Right, true),
    ] {
        let b = blank(member);
        let setup = member_setup(&b, hand, &cutter(), generated).unwrap();
        for kind in [FlankKind::Concave, FlankKind::Convex] {
            let name = format!(
                "{member:?} {} {kind:?}",
                if generated { "generated" } else { "formate" }
            );
            out.push((name, setup.flank(kind).unwrap()));
        }
    }
    out
}

fn grid(f: &dyn ToothSurface, nu: usize, nv: usize) -> Vec<(f64, f64)> {
    let (v0, v1) = f.v_range();
    let mut g = vec![];
    for j in 0..nv {
        let v = v0 + (v1 - v0) * j as f64 / (nv - 1) as f64;
        let (ur, ut) = (f.u_root(v), f.u_tip(v));
        for i in 0..nu {
            g.push((ur + (ut - ur) * i as f64 / (nu - 1) as f64, v));
        }
    }
    g
}

#[test]
fn meshing_and_normal_on_every_grid_point() {
    let t = Instant::now();
    for (name, f) in flanks() {
        let (mut fmax, mut nu_max, mut nv_max) = (0.0f64, 0.0f64, 0.0f64);
        for (u, v) in grid(&f, 21, 11) {
            let (_, n, ru, rv) = f.try_evaluate(u, v).unwrap();
            fmax = fmax.max(f.meshing_residual(u, v).unwrap().abs());
            nu_max = nu_max.max(dot(n, ru).abs() / norm(ru));
            nv_max = nv_max.max(dot(n, rv).abs() / norm(rv));
            assert!((norm(n) - 1.0).abs() < 1e-14);
        }
        println!(
            "{name}: max |f| {fmax:.2e}, |n·r_u|/|r_u| {nu_max:.2e}, |n·r_v|/|r_v| {nv_max:.2e}"
        );
        assert!(
            fmax <= 1e-10 && nu_max <= 1e-10 && nv_max <= 1e-10,
            "{name}"
        );
    }
    println!("time {:.2} s", t.elapsed().as_secs_f64());
}

#[test]
fn derivatives_against_central_differences() {
    for (name, f) in flanks() {
        let mut worst = 0.0f64;
        for (u, v) in grid(&f, 21, 11) {
            let (ru, rv) = f.derivatives(u, v);
            // central differences with Richardson extrapolation (h, h/2):
            // truncation O(h⁴)
            let cd = |du: f64, dv: f64| {
                let d = |k: f64| {
                    sub(
                        f.point(u + k * du, v + k * dv),
                        f.point(u - k * du, v - k * dv),
                    )
                    .map(|x| x / (2.0 * k))
                };
                let (a, b) = (d(1e-5), d(0.5e-5));
                [0, 1, 2].map(|c| (4.0 * b[c] - a[c]) / 3.0)
            };
            let (fu, fv) = (cd(1.0, 0.0), cd(0.0, 1.0));
            let e = (norm(sub(fu, ru)) / norm(ru)).max(norm(sub(fv, rv)) / norm(rv));
            worst = worst.max(e);
        }
        println!("{name}: max relative |r_u − FD|, |r_v − FD| {worst:.2e}");
        assert!(worst < 1e-6, "{name}: {worst}");
    }
}

/// Principal curvatures of the fit w(x, y) = ½a x² + b xy + ½c y² + cubic
/// of the height over the tangent plane, 7 × 7 points of spacing h.
fn fitted_curvatures(f: &dyn ToothSurface, u: f64, v: f64, h: f64) -> [f64; 2] {
    let (p0, n, ru, _) = f.evaluate(u, v);
    let t1 = ru.map(|x| x / norm(ru));
    let t2 = cross(n, t1);
    let mut rows = vec![];
    let mut rhs = vec![];
    for i in -3..=3 {
        for j in -3..=3 {
            let d = sub(f.point(u + i as f64 * h, v + j as f64 * h), p0);
            let (x, y, w) = (dot(d, t1), dot(d, t2), dot(d, n));
            rows.push([
                0.5 * x * x,
                x * y,
                0.5 * y * y,
                x * x * x,
                x * x * y,
                x * y * y,
                y * y * y,
                x,
                y,
            ]);
            rhs.push(w);
        }
    }
    let a = DMatrix::from_fn(rows.len(), 9, |r, c| rows[r][c]);
    let b = DVector::from_vec(rhs);
    let sol = a.svd(true, true).solve(&b, 1e-14).unwrap();
    let (l, m, nn) = (-sol[0], -sol[1], -sol[2]);
    let hh = 0.5 * (l + nn);
    let disc = (0.25 * (l - nn) * (l - nn) + m * m).sqrt();
    [hh + disc, hh - disc]
}

#[test]
fn curvatures_against_a_fit() {
    for (name, f) in flanks() {
        let mut worst = 0.0f64;
        let mut kmax = 0.0f64;
        for (u, v) in grid(&f, 5, 3) {
            // the fillet's junction has a jump in curvature: keep the
            // stencil (±3 × 0.02 mm) on one side, and inside the root
            if (u - f.u_form(v)).abs() < 0.1 || u - 0.06 < f.u_root(v) {
                continue;
            }
            let k = principal_curvatures(&f, u, v).principal;
            let fit = fitted_curvatures(&f, u, v, 0.01);
            worst = worst.max((k[0] - fit[0]).abs()).max((k[1] - fit[1]).abs());
            kmax = kmax.max(k[0].abs()).max(k[1].abs());
        }
        println!("{name}: max |κ − κ_fit| {worst:.2e} 1/mm (largest |κ| {kmax:.3e})");
        assert!(worst < 1e-5, "{name}: {worst}");
    }
}

/// The formate gear's flank points lie on the blade's cone: the point
/// taken back to the cutter frame by the documented frames
/// (`cradle_machine` docs) satisfies ρ_c = r_p + σ h tan α on the straight
/// blade (distance from the cone along its normal ≤ 1e-10 mm).
#[test]
fn formate_gear_is_the_cutter_surface() {
    let b = blank(Member::Gear);
    let setup = member_setup(&b, Hand::Left, &cutter(), false).unwrap();
    let s = setup.settings;
    let (sg, cg) = s.machine_root_angle.sin_cos();
    let (xw, yw, zw) = ([0.0, 1.0, 0.0], [sg, 0.0, cg], [cg, 0.0, -sg]);
    let apex = [0.0, 0.0, s.sliding_base];
    let centre = [
        s.radial_distance * s.cradle_angle.cos(),
        s.radial_distance * s.cradle_angle.sin(),
    ];
    let mut worst = 0.0f64;
    let mut count = 0;
    for kind in [FlankKind::Concave, FlankKind::Convex] {
        let f = setup.flank(kind).unwrap();
        let blade = *setup.head.blade(kind.blade_side());
        let sigma = if kind == FlankKind::Concave {
            1.0
        } else {
            -1.0
        };
        let rot = f.envelope().placement();
        for (u, v) in grid(&f, 21, 11) {
            if u < f.u_form(v) + 1e-6 {
                continue; // the edge radius: not the cone
            }
            let p = f.point(u, v);
            // undo the tooth placement, then work → machine (ψ = 0)
            let (sr, cr) = (-rot).sin_cos();
            let p = [cr * p[0] - sr * p[1], sr * p[0] + cr * p[1], p[2]];
            let m: V3 =
                std::array::from_fn(|k| apex[k] + p[0] * xw[k] + p[1] * yw[k] + p[2] * zw[k]);
            let rho = (m[0] - centre[0]).hypot(m[1] - centre[1]);
            let h = m[2];
            let a = blade.pressure_angle;
            let d = (rho - blade.point_radius - sigma * h * a.tan()) * a.cos();
            worst = worst.max(d.abs());
            count += 1;
        }
    }
    println!("formate gear: {count} points, max distance from the blade cone {worst:.2e} mm");
    assert!(count > 300 && worst < 1e-10);
}

#[test]
fn mean_point_matches_the_blank() {
    for (member, hand, generated) in [
        (Member::Gear, Hand::Left, true),
        (Member::Gear, Hand::Left, false),
        (Member::Pinion, Hand::Right, true),
    ] {
        let b = blank(member);
        let first =
            check_mean_point(&member_setup(&b, hand, &cutter(), generated).unwrap()).unwrap();
        let (setup, c) = refined_setup(&b, hand, &cutter(), generated, 1e-10, 40).unwrap();
        let d = |x: f64| x.to_degrees();
        println!(
            "{member:?} gen {generated}: first order β {:.4}/{:.4}° α {:.4}/{:.4}° (design β {:.4}°, α {:.4}/{:.4}°); \
             corrected β {:.10}/{:.10}° α {:.10}/{:.10}°, R {:.10} (design {:.10}), max error {:.2e} rad; \
             S_r {:.4} q {:.4}° γ_m {:.4}° ΔX_B {:.4} R_a {:.6}, blades {:.4}/{:.4}°",
            d(first.spiral_angle.0), d(first.spiral_angle.1), d(first.pressure_angle.0), d(first.pressure_angle.1),
            d(c.design_spiral_angle), d(c.design_pressure_angle.0), d(c.design_pressure_angle.1),
            d(c.spiral_angle.0), d(c.spiral_angle.1), d(c.pressure_angle.0), d(c.pressure_angle.1),
            c.cone_distance.0, c.design_cone_distance, c.max_angle_error(),
            setup.settings.radial_distance, d(setup.settings.cradle_angle), d(setup.settings.machine_root_angle),
            setup.settings.sliding_base, setup.settings.ratio_of_roll,
            d(setup.head.outside.pressure_angle), d(setup.head.inside.pressure_angle),
        );
        println!(
            "  s_mn first order {:.6} mm, corrected {:.9} mm, blank {:.9} mm",
            first.thickness, c.thickness, c.design_thickness
        );
        assert!(c.max_angle_error() <= 1e-10);
        assert!((c.thickness - c.design_thickness).abs() <= 1e-10 * b.mean_cone_distance);
        assert!((c.cone_distance.0 - b.mean_cone_distance).abs() <= 1e-9);
        assert!((c.cone_distance.1 - b.mean_cone_distance).abs() <= 1e-9);
    }
}

/// Rotation about z by a: (cos, sin) applied to p.
fn rz(a: f64, p: V3) -> V3 {
    let (s, c) = a.sin_cos();
    [c * p[0] - s * p[1], s * p[0] + c * p[1], p[2]]
}

#[test]
fn straight_bevel_reduction_is_the_octoid() {
    // a straight bevel gear on the F.2 gear's pitch cone, no dedendum
    // angle (the cradle plane is the pitch plane: a plane crown gear)
    let b = blank(Member::Gear);
    let delta = b.pitch_angle;
    let (z, rm) = (b.teeth as f64, b.mean_cone_distance);
    let settings = MachineSettings {
        radial_distance: 0.0,
        cradle_angle: 0.0,
        machine_root_angle: delta,
        sliding_base: 0.0,
        blank_offset: 0.0,
        machine_center_to_back: 0.0,
        ratio_of_roll: delta.sin(),
        modified_roll: (0.0, 0.0),
        tilt: 0.0,
        swivel: 0.0,
        generated: true,
    };
    let alpha = 20f64.to_radians();
    // crown-gear tooth space: half angle η = (π/z_c)/2, z_c = z / sin δ
    let eta = 0.5 * PI * delta.sin() / z;
    let mut worst = 0.0f64;
    let mut n_pts = 0;
    for sigma in [1.0f64, -1.0] {
        let e_l = [eta.cos(), sigma * eta.sin(), 0.0];
        let side = [-e_l[1], e_l[0], 0.0]; // e_z × e_L
        let t_b: V3 = std::array::from_fn(|k| {
            alpha.cos() * [0.0, 0.0, 1.0][k] + sigma * alpha.sin() * side[k]
        });
        let n0 = cross(t_b, e_l);
        let tool = CradleTool::Plane {
            origin: [0.0; 3],
            profile_dir: t_b,
            lengthwise_dir: e_l,
            orientation: -sigma,
        };
        let map = CradleGeneration::new(settings, tool).unwrap();
        let section = AxialSection {
            pitch_angle: delta,
            cone_distance: (b.inner_cone_distance, b.outer_cone_distance),
            mean_cone_distance: rm,
            tip: ConeLine {
                u_mean: b.mean_addendum,
                slope: 0.0,
            },
            root: ConeLine {
                u_mean: -0.8 * b.mean_dedendum,
                slope: 0.0,
            },
        };
        let f = EnvelopeFlank::new(
            map,
            section,
            0.0,
            None,
            [0.0, rm, 0.0],
            SolveOptions::default(),
        )
        .unwrap();
        // closed form: the tool plane's normal in the work frame,
        // n(ψ) = Rot_z(ψ/R_a) Bᵀ Rot_z(ψ) n₀, and its derivative
        let (sg, cg) = delta.sin_cos();
        let bt = |p: V3| [p[1], sg * p[0] + cg * p[2], cg * p[0] - sg * p[2]];
        let ra = settings.ratio_of_roll;
        let nrm = |psi: f64| rz(psi / ra, bt(rz(psi, n0)));
        let dn = |psi: f64| {
            let a = rz(psi / ra, bt(rz(psi, n0)));
            let kz = |p: V3| [-p[1], p[0], 0.0];
            let t1 = kz(a).map(|x| x / ra);
            let t2 = rz(psi / ra, bt(kz(rz(psi, n0))));
            [t1[0] + t2[0], t1[1] + t2[1], t1[2] + t2[2]]
        };
        for (u, v) in grid(&f, 21, 11) {
            let x = f.point(u, v);
            // ψ* with n′(ψ*)·x = 0, by bisection on a bracket around the
            // engine's ψ (closed-form function of ψ; 200 halvings max)
            let psi0 = f.solve(u, v).unwrap().q[2];
            let g = |psi: f64| dot(dn(psi), x);
            let (mut lo, mut hi) = (psi0 - 0.2, psi0 + 0.2);
            assert!(g(lo) * g(hi) < 0.0);
            for _ in 0..200 {
                let mid = 0.5 * (lo + hi);
                if g(lo) * g(mid) <= 0.0 {
                    hi = mid
                } else {
                    lo = mid
                }
                if hi - lo < 1e-16 {
                    break;
                }
            }
            let psi = 0.5 * (lo + hi);
            let e = {
                let c = cross(nrm(psi), dn(psi));
                c.map(|k| k / norm(c))
            };
            let on_ruling = e.map(|k| k * dot(x, e));
            worst = worst.max(norm(sub(x, on_ruling)));
            n_pts += 1;
        }
    }
    println!("straight bevel (octoid of the first kind): {n_pts} points, max distance from the closed-form octoid {worst:.2e} mm");
    assert!(worst < 1e-9);
}

#[test]
fn non_physical_settings_are_errors() {
    let b = blank(Member::Gear);
    let setup = member_setup(&b, Hand::Left, &cutter(), true).unwrap();
    // the cutter centre at a third of its radial distance: the blade
    // misses the blank
    let mut s = setup.settings;
    s.radial_distance *= 0.3;
    let kind = FlankKind::Concave;
    let e = GeneratedFlank::new(
        s,
        *setup.head.blade(kind.blade_side()),
        kind,
        b.section(),
        b.teeth,
        setup.start_guess(kind).unwrap(),
    );
    let msg = e.unwrap_err().to_string();
    println!("radial_distance × 0.3: {msg}");
    assert!(msg.contains("radial_distance"));
    // NaN setting
    let mut s = setup.settings;
    s.cradle_angle = f64::NAN;
    let e = GeneratedFlank::new(
        s,
        *setup.head.blade(kind.blade_side()),
        kind,
        b.section(),
        b.teeth,
        setup.start_guess(kind).unwrap(),
    );
    assert!(e.unwrap_err().to_string().contains("cradle_angle"));
    // a point far outside the generated region is an error, not a panic
    let f = setup.flank(kind).unwrap();
    let r = f.try_evaluate(40.0, b.mean_cone_distance);
    println!("u = 40 mm: {:?}", r.as_ref().err().map(|e| e.to_string()));
    assert!(r.is_err());
    // and the ToothSurface fallback is finite
    assert!(f
        .point(40.0, b.mean_cone_distance)
        .iter()
        .all(|x| x.is_finite()));
}

#[test]
fn grid_timing() {
    for (name, f) in flanks() {
        let t = Instant::now();
        let g = f.envelope().grid(100, 50).unwrap();
        let dt = t.elapsed().as_secs_f64();
        println!("{name}: 100 × 50 grid by continuation {:.2} ms", 1e3 * dt);
        assert_eq!(g.len(), 5000);
    }
}
