//! # Conjugate hypoid / spiral bevel pinion and its ease-off
//!
//! A gear flank (here a **formate** gear: the cone surface of a face-mill
//! cutter placed at the gear's mean point, an exact surface with exact
//! second derivatives) and the assembly of an ISO 23509 blank (Annex F
//! samples F2, spiral bevel, and F4, hypoid with offset 31.75 mm) give the
//! conjugate pinion flank (`geometry::bevel::conjugate`). Checked here
//! (README.md gives the references and tolerances):
//!
//! (a) unloaded TCA: the conjugate pinion meshes with its gear at constant
//!     ratio, transmission error ≤ 1e-9 rad over the path of contact;
//! (b) the ease-off read back from the modified flank (closest-point
//!     projection on the conjugate flank) equals the specified one to
//!     ≤ 0.01 µm; the parabolic TE term alone gives the specified parabola;
//! (c) the meshing residual at every point ≤ 1e-12 and the derivatives
//!     (tangents, normal derivatives, roll angle, eased-flank tangents)
//!     against central differences;
//! (d) bad input gives errors.

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use flank::geometry::bevel::assembly::PairAssembly;
use flank::geometry::bevel::conjugate::ConjugatePinion;
use flank::geometry::bevel::ease_off::{
    deviation_grid, deviation_grid_at, write_grid_csv, EaseOffSpec, EasedPinion,
};
use flank::geometry::bevel::generated_surface::FlankKind;
use flank::geometry::bevel::machine_settings::{refined_setup, CutterChoice, Member, MemberBlank};
use flank::geometry::bevel::{blank_design, BlankDesign, BlankInputs};
use flank::geometry::rotated::RotatedSurface;
use flank::geometry::surface::ToothSurface;
use flank::geometry::Hand;

type V3 = [f64; 3];

fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn lin(a: V3, s: f64, b: V3) -> V3 {
    [a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2]]
}
fn sc(s: f64, a: V3) -> V3 {
    [s * a[0], s * a[1], s * a[2]]
}
fn norm(a: V3) -> f64 {
    dot(a, a).sqrt()
}
fn unit(a: V3) -> V3 {
    sc(1.0 / norm(a), a)
}

fn sample(name: &str) -> (BlankInputs, BlankDesign) {
    let path =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../shared/reference/iso23509_annexF.json");
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let v: serde_json::Value = serde_json::from_str(&text).expect("reference JSON");
    let inputs = BlankInputs::from_value(v[name]["inputs"].clone()).expect("inputs");
    let design = blank_design(&inputs).expect("blank design");
    (inputs, design)
}

/// A formate gear flank: the cone swept by a straight blade of pressure
/// angle α at point radius r_c about a cutter axis `a` (unit, along the
/// gear's pitch-cone normal at the mean point M, pointing to the tooth
/// tips) through the centre C. u = s, the height along `a` from the pitch
/// plane (root → tip); v = r_c θ, the arc length at the pitch plane
/// (toe → heel). Concave flank (outside blade): the radius grows with s,
/// r(s) = r_c + s tan α, outward normal n = −cos α e_r + sin α a.
#[derive(Debug, Clone)]
struct FormateFlank {
    centre: V3,
    e1: V3,
    e2: V3,
    axis: V3,
    rc: f64,
    alpha: f64,
    /// +1 concave (outside blade), −1 convex (inside blade).
    side: f64,
    u_box: (f64, f64),
    v_box: (f64, f64),
}

impl FormateFlank {
    /// At the gear's mean point M = (R_m2 sin δ2, 0, R_m2 cos δ2): the
    /// tooth trace t is the direction of the relative velocity at M (the
    /// kinematic condition of ISO 23509 clause 6.3) or, when it vanishes
    /// (E = 0), the direction at β_m2 from the generatrix; the cutter
    /// centre lies at r_c from M along a × t.
    fn at_mean_point(asm: &PairAssembly, d: &BlankDesign, rc: f64, alpha: f64, side: f64) -> Self {
        let c = &d.cones;
        let (s2, c2) = c.delta2.sin_cos();
        let m = [c.rm2 * s2, 0.0, c.rm2 * c2];
        let g = [s2, 0.0, c2];
        let h = [0.0, 1.0, 0.0];
        let a = [c2, 0.0, -s2];
        let [_, f2] = asm.nominal_frames(0.0, 0.0);
        let v = f2.rotate_back(asm.relative_velocity(f2.place(m)));
        let vp = lin(v, -dot(v, a), a);
        let mut t = if norm(vp) > 1e-9 * c.rm2 {
            unit(vp)
        } else {
            lin(sc(c.beta_m2.cos(), g), c.beta_m2.sin(), h)
        };
        if dot(t, g) < 0.0 {
            t = sc(-1.0, t);
        }
        let w = cross(a, t);
        let centre = lin(m, side * rc, w);
        let hm = d.depth.hm;
        let b = 0.8 * (c.re2 - c.rm2) * 2.0 / c.beta_m2.cos();
        FormateFlank {
            centre,
            e1: sc(-side, w),
            e2: sc(side, t),
            axis: a,
            rc,
            alpha,
            side,
            u_box: (-1.5 * hm, 1.5 * hm),
            v_box: (-b, b),
        }
    }
    fn radial(&self, th: f64) -> (V3, V3) {
        let (s, c) = th.sin_cos();
        (
            lin(sc(c, self.e1), s, self.e2),
            lin(sc(-s, self.e1), c, self.e2),
        )
    }
}

impl ToothSurface for FormateFlank {
    fn u_range(&self) -> (f64, f64) {
        self.u_box
    }
    fn v_range(&self) -> (f64, f64) {
        self.v_box
    }
    fn u_tip(&self, _v: f64) -> f64 {
        self.u_box.1
    }
    fn u_form(&self, _v: f64) -> f64 {
        self.u_box.0
    }
    fn u_root(&self, _v: f64) -> f64 {
        self.u_box.0
    }
    fn point(&self, u: f64, v: f64) -> V3 {
        let (er, _) = self.radial(self.side * v / self.rc);
        lin(
            lin(self.centre, self.rc + self.side * u * self.alpha.tan(), er),
            u,
            self.axis,
        )
    }
    fn normal(&self, _u: f64, v: f64) -> V3 {
        let (er, _) = self.radial(self.side * v / self.rc);
        lin(
            sc(-self.side * self.alpha.cos(), er),
            self.alpha.sin(),
            self.axis,
        )
    }
    fn derivatives(&self, u: f64, v: f64) -> (V3, V3) {
        let (er, et) = self.radial(self.side * v / self.rc);
        let r = self.rc + self.side * u * self.alpha.tan();
        (
            lin(sc(self.side * self.alpha.tan(), er), 1.0, self.axis),
            sc(self.side * r / self.rc, et),
        )
    }
    fn second_derivatives(&self, u: f64, v: f64) -> [V3; 3] {
        let (er, et) = self.radial(self.side * v / self.rc);
        let r = self.rc + self.side * u * self.alpha.tan();
        [
            [0.0; 3],
            sc(self.alpha.tan() / self.rc, et),
            sc(-r / (self.rc * self.rc), er),
        ]
    }
}

/// The lengthwise curvature radius of the gear's tooth trace at the mean
/// point the blank was designed for: the cutter radius r_c0 (face milling)
/// or the extended epicycloid's curvature radius (face hobbing).
fn trace_radius(inputs: &BlankInputs, design: &BlankDesign) -> f64 {
    let c = &design.cones;
    flank::geometry::bevel::hypoid_methods::lengthwise_curvature_radius(
        c.rm2,
        c.beta_m2,
        c.delta2,
        design.z2,
        inputs.rc0_mm,
        design.z0,
    )
    .unwrap()
}

struct Case {
    name: &'static str,
    inputs: BlankInputs,
    design: BlankDesign,
    asm: PairAssembly,
    gear: Arc<FormateFlank>,
    pinion: Arc<ConjugatePinion>,
}

/// The formate gear flank of each sample: (side, blade pressure angle).
/// With 20° the envelope folds (limit line of undercut) inside the
/// pinion's active flank near the toe for both blanks (see README), so the
/// cases use flanks whose conjugate covers the whole active flank.
fn flank_choice(name: &str) -> (f64, f64) {
    if name.starts_with("F2") {
        (1.0, 25.0)
    } else {
        (-1.0, 30.0)
    }
}

fn case(name: &'static str) -> Case {
    let (inputs, design) = sample(name);
    let asm = PairAssembly::from_blank(&inputs, &design).expect("assembly");
    let (side, alpha) = flank_choice(name);
    let gear = Arc::new(FormateFlank::at_mean_point(
        &asm,
        &design,
        trace_radius(&inputs, &design),
        alpha.to_radians(),
        side,
    ));
    let pinion = Arc::new(
        ConjugatePinion::from_blank(gear.clone(), &asm, &inputs, &design).expect("conjugate"),
    );
    Case {
        name,
        inputs,
        design,
        asm,
        gear,
        pinion,
    }
}

const SAMPLES: [&str; 2] = [
    "F2_spiral_bevel_method0_face_milling",
    "F4_hypoid_method2_oerlikon_face_hobbing",
];

/// Dense solve (nalgebra's LU with partial pivoting); None if singular.
fn solve_dense(a: Vec<Vec<f64>>, b: Vec<f64>) -> Option<Vec<f64>> {
    let n = b.len();
    let m = nalgebra::DMatrix::from_fn(n, n, |i, j| a[i][j]);
    m.lu()
        .solve(&nalgebra::DVector::from_vec(b))
        .map(|x| x.iter().copied().collect())
}

/// Unloaded TCA at one pinion rotation φ₁ with the pinion's cone distance
/// v₁ held (a conjugate pair touches along a line): unknowns x = (u₁, u₂,
/// v₂, φ₂); residuals r₁ − r₂ (housing, 3) and n₂·r₁,u, n₂·r₁,v (the normals
/// are collinear). Gauss–Newton with central-difference Jacobian, at most
/// 60 steps; returns (x, residual norm, steps).
fn contact(
    asm: &PairAssembly,
    pinion: &dyn ToothSurface,
    gear: &dyn ToothSurface,
    phi1: f64,
    v1: f64,
    seed: [f64; 4],
) -> ([f64; 4], f64, usize) {
    let res = |x: &[f64; 4]| -> [f64; 5] {
        let [f1, f2] = asm.nominal_frames(phi1, x[3]);
        let (p1, _, r1u, r1v) = pinion.evaluate(x[0], v1);
        let (p2, n2, _, _) = gear.evaluate(x[1], x[2]);
        let d = sub(f1.place(p1), f2.place(p2));
        let n2h = f2.rotate(n2);
        [
            d[0],
            d[1],
            d[2],
            dot(n2h, f1.rotate(r1u)),
            dot(n2h, f1.rotate(r1v)),
        ]
    };
    let nrm = |r: &[f64; 5]| r.iter().map(|v| v * v).sum::<f64>().sqrt();
    let mut x = seed;
    let mut r = res(&x);
    for it in 0..60 {
        if nrm(&r) < 1e-13 {
            return (x, nrm(&r), it);
        }
        let hs = [1e-6, 1e-6, 1e-6, 1e-8];
        let mut jac = [[0.0; 4]; 5];
        for k in 0..4 {
            let (mut xp, mut xm) = (x, x);
            xp[k] += hs[k];
            xm[k] -= hs[k];
            let (rp, rm) = (res(&xp), res(&xm));
            for i in 0..5 {
                jac[i][k] = (rp[i] - rm[i]) / (2.0 * hs[k]);
            }
        }
        let mut a = vec![vec![0.0; 4]; 4];
        let mut g = vec![0.0; 4];
        for i in 0..5 {
            for k in 0..4 {
                g[k] -= jac[i][k] * r[i];
                for l in 0..4 {
                    a[k][l] += jac[i][k] * jac[i][l];
                }
            }
        }
        let Some(dx) = solve_dense(a, g) else {
            return (x, nrm(&r), it);
        };
        let xn = [x[0] + dx[0], x[1] + dx[1], x[2] + dx[2], x[3] + dx[3]];
        let rn = res(&xn);
        if nrm(&rn) >= nrm(&r) {
            return (x, nrm(&r), it);
        }
        x = xn;
        r = rn;
    }
    (x, nrm(&r), 60)
}

/// The pinion rotations of the path at cone distance v: from the contact
/// roll of the form point to that of the tip, 2 % inside.
fn path(p: &ConjugatePinion, v: f64, n: usize) -> Vec<(f64, [f64; 4])> {
    let (ua, ub) = (p.u_form(v), p.u_tip(v));
    (0..n)
        .map(|i| {
            let u = ua + (ub - ua) * (0.02 + 0.96 * i as f64 / (n - 1) as f64);
            let c = p.conjugate_point(u, v).expect("path point");
            // the seed is offset from the answer so that the solve finds it
            let seed = [
                u + 0.05,
                c.gear_q[0] - 0.03,
                c.gear_q[1] + 0.05,
                c.gear_q[2] + 1e-4,
            ];
            (c.roll, seed)
        })
        .collect()
}

/// (a) Transmission error of the conjugate pair ≤ 1e-9 rad.
#[test]
fn conjugate_pinion_meshes_at_constant_ratio() {
    for name in SAMPLES {
        let t0 = Instant::now();
        let c = case(name);
        let m = c.pinion.roll_ratio();
        let mut worst: f64 = 0.0;
        let mut worst_res: f64 = 0.0;
        let mut count = 0;
        let (v0, v1) = c.pinion.v_range();
        for frac in [0.25, 0.5, 0.75] {
            let v = v0 + frac * (v1 - v0);
            for (phi1, seed) in path(&c.pinion, v, 21) {
                let (x, r, _) = contact(&c.asm, c.pinion.as_ref(), c.gear.as_ref(), phi1, v, seed);
                assert!(
                    r < 1e-9,
                    "{name}: contact not found at φ1 = {phi1} (residual {r:.2e})"
                );
                let te = m * x[3] - phi1;
                worst = worst.max(te.abs());
                worst_res = worst_res.max(r);
                count += 1;
            }
        }
        println!(
            "{}: {count} contacts, max |TE| = {worst:.2e} rad (pinion), residual {worst_res:.2e} mm, ratio m = {m:.6}, {:.2} s",
            c.name,
            t0.elapsed().as_secs_f64()
        );
        assert!(worst <= 1e-9, "{name}: TE {worst:.3e} rad");
        assert_eq!(c.pinion.failures(), 0);
    }
}

/// (c) Meshing residual, normal ⊥ tangents, and derivatives against
/// central differences.
#[test]
fn meshing_residual_and_derivatives() {
    for name in SAMPLES {
        let t0 = Instant::now();
        let c = case(name);
        let p = &c.pinion;
        let (v0, v1) = p.v_range();
        let mut worst = [0.0f64; 6];
        let h = 1e-4;
        for j in 0..5 {
            let v = v0 + (v1 - v0) * j as f64 / 4.0;
            for i in 0..7 {
                // the active flank (the envelope itself), clear of the form
                // line where the continuation below it joins with C¹ only
                let u = p.u_form(v) + (p.u_tip(v) - p.u_form(v)) * (0.02 + 0.96 * i as f64 / 6.0);
                let cp = p.conjugate_point(u, v).unwrap();
                worst[0] = worst[0].max(cp.meshing_residual.abs());
                worst[1] = worst[1].max(
                    (dot(cp.normal, cp.r_u) / norm(cp.r_u))
                        .abs()
                        .max((dot(cp.normal, cp.r_v) / norm(cp.r_v)).abs()),
                );
                let (pu, pv) = (
                    p.conjugate_point(u + h, v).unwrap(),
                    p.conjugate_point(u - h, v).unwrap(),
                );
                let (qu, qv) = (
                    p.conjugate_point(u, v + h).unwrap(),
                    p.conjugate_point(u, v - h).unwrap(),
                );
                let fd = |a: V3, b: V3| sc(0.5 / h, sub(a, b));
                worst[2] = worst[2]
                    .max(norm(sub(fd(pu.point, pv.point), cp.r_u)) / norm(cp.r_u))
                    .max(norm(sub(fd(qu.point, qv.point), cp.r_v)) / norm(cp.r_v));
                worst[3] = worst[3]
                    .max(norm(sub(fd(pu.normal, pv.normal), cp.n_u)))
                    .max(norm(sub(fd(qu.normal, qv.normal), cp.n_v)));
                worst[4] = worst[4]
                    .max(((pu.roll - pv.roll) / (2.0 * h) - cp.roll_u).abs())
                    .max(((qu.roll - qv.roll) / (2.0 * h) - cp.roll_v).abs());
                // the contact normal: pinion outward = − gear outward (housing)
                let [f1, f2] = c.asm.nominal_frames(cp.roll, cp.gear_q[2]);
                let n2 = f2.rotate(c.gear.normal(cp.gear_q[0], cp.gear_q[1]));
                worst[5] = worst[5].max(norm(lin(f1.rotate(cp.normal), 1.0, n2)));
            }
        }
        // the tangent continuation below the form line: tangents vs FD
        let mut fillet: f64 = 0.0;
        for j in 0..3 {
            let v = v0 + (v1 - v0) * (0.1 + 0.4 * j as f64);
            let u = 0.5 * (p.u_root(v) + p.u_form(v));
            let cp = p.conjugate_point(u, v).unwrap();
            assert!(!cp.conjugate);
            let fd = |a: V3, b: V3| sc(0.5 / h, sub(a, b));
            let (pu, pv) = (p.point(u + h, v), p.point(u - h, v));
            let (qu, qv) = (p.point(u, v + h), p.point(u, v - h));
            fillet = fillet
                .max(norm(sub(fd(pu, pv), cp.r_u)) / norm(cp.r_u))
                .max(norm(sub(fd(qu, qv), cp.r_v)) / norm(cp.r_v));
        }
        println!(
            "{}: below the form line: tangents vs FD {fillet:.2e} (rel)",
            c.name
        );
        assert!(fillet <= 1e-6, "fillet continuation tangents");
        println!(
            "{}: meshing residual {:.2e}, n·r_u {:.2e}, tangents vs FD {:.2e} (rel), n_u vs FD {:.2e} /mm, roll_u vs FD {:.2e} rad/mm, n1 + n2 {:.2e}; {:.2} s",
            c.name,
            worst[0],
            worst[1],
            worst[2],
            worst[3],
            worst[4],
            worst[5],
            t0.elapsed().as_secs_f64()
        );
        assert!(worst[0] <= 1e-12, "meshing residual");
        assert!(worst[1] <= 1e-12, "normal not normal");
        assert!(worst[2] <= 1e-7, "tangents");
        assert!(worst[3] <= 1e-7, "normal derivatives");
        assert!(worst[4] <= 1e-8, "roll derivatives");
        assert!(worst[5] <= 1e-12, "contact normals");
        // cost of a flank grid (100 × 50 points, each a Newton solve from
        // the seed table): reported, not asserted
        let t1 = Instant::now();
        for j in 0..50 {
            let v = v0 + (v1 - v0) * j as f64 / 49.0;
            for i in 0..100 {
                let u = p.u_form(v) + (p.u_tip(v) - p.u_form(v)) * i as f64 / 99.0;
                std::hint::black_box(p.evaluate(u, v));
            }
        }
        println!(
            "{}: 100 × 50 grid of point + normal + tangents: {:.1} ms",
            c.name,
            1e3 * t1.elapsed().as_secs_f64()
        );
        assert_eq!(p.failures(), 0);
    }
}

fn spec(c: &Case) -> EaseOffSpec {
    spec_of(&c.pinion, c.design.cones.rm1)
}

/// The test's ease-off on a conjugate pinion with mean cone distance `rm`:
/// profile crowning 20 µm, lengthwise 30 µm, bias 10 µm, TE level 50 µrad
/// at ± half the roll span at the mean.
fn spec_of(p: &ConjugatePinion, rm: f64) -> EaseOffSpec {
    let (v0, v1) = p.v_range();
    let (ua, ub) = (p.u_form(rm), p.u_tip(rm));
    let roll_span =
        (p.conjugate_point(ub, rm).unwrap().roll - p.conjugate_point(ua, rm).unwrap().roll).abs();
    EaseOffSpec {
        centre: (0.0, rm),
        half_span: (0.5 * (ub - ua), 0.5 * (v1 - v0)),
        profile_crowning_mm: 0.020,
        lengthwise_crowning_mm: 0.030,
        bias_mm: 0.010,
        te_amplitude_rad: 50e-6,
        te_half_range_rad: 0.5 * roll_span,
    }
}

/// The ease-off read back on a 9 × 5 grid against the specified field
/// written out here: (largest |read − specified|, largest specified) in
/// mm. Also checks each grid point is the conjugate point moved by −e n.
fn read_back(pinion: &ConjugatePinion, eased: &EasedPinion) -> (f64, f64) {
    let s = *eased.spec();
    let grid = deviation_grid(eased, 9, 5).expect("grid");
    let k: V3 = [0.0, 0.0, 1.0];
    let c_te = s.te_amplitude_rad / s.te_half_range_rad.powi(2);
    let mut worst: f64 = 0.0;
    let mut largest: f64 = 0.0;
    for g in &grid {
        let cp = pinion.conjugate_point(g.u, g.v).unwrap();
        let xi = (g.u - s.centre.0) / s.half_span.0;
        let eta = (g.v - s.centre.1) / s.half_span.1;
        let arm = dot(cp.normal, cross(k, cp.point)).abs();
        let d = cp.roll - eased.roll_centre();
        let e = s.profile_crowning_mm * xi * xi
            + s.lengthwise_crowning_mm * eta * eta
            + s.bias_mm * xi * eta
            + c_te * d * d * arm;
        worst = worst.max((g.deviation_mm - e).abs());
        largest = largest.max(e.abs());
        assert!(norm(sub(g.point, lin(cp.point, -e, cp.normal))) < 1e-9);
    }
    (worst, largest)
}

/// (b) The ease-off read back equals the specified one (≤ 0.01 µm); the
/// eased flank's tangents against central differences; the TE term alone
/// gives the specified parabola.
#[test]
fn ease_off_read_back() {
    for name in SAMPLES {
        let t0 = Instant::now();
        let c = case(name);
        let s = spec(&c);
        let eased =
            EasedPinion::new(c.pinion.clone(), s, c.design.thickness.s_mn[0]).expect("eased");
        let (worst, largest) = read_back(&c.pinion, &eased);
        let grid = deviation_grid(&eased, 9, 5).expect("grid");
        let out = std::env::temp_dir().join(format!("bevel_conjugate_{}.csv", &c.name[..2]));
        write_grid_csv(&out, &grid).expect("csv");
        // tangents of the eased flank
        let h = 1e-4;
        let mut dworst: f64 = 0.0;
        let (v0, v1) = eased.v_range();
        for j in 0..3 {
            let v = v0 + (v1 - v0) * (0.1 + 0.4 * j as f64);
            for i in 0..3 {
                let u =
                    eased.u_form(v) + (eased.u_tip(v) - eased.u_form(v)) * (0.1 + 0.4 * i as f64);
                let (ru, rv) = eased.derivatives(u, v);
                let fu = sc(0.5 / h, sub(eased.point(u + h, v), eased.point(u - h, v)));
                let fv = sc(0.5 / h, sub(eased.point(u, v + h), eased.point(u, v - h)));
                dworst = dworst
                    .max(norm(sub(fu, ru)) / norm(ru))
                    .max(norm(sub(fv, rv)) / norm(rv));
                let n = eased.normal(u, v);
                assert!(dot(n, ru).abs() < 1e-12 * norm(ru) && dot(n, rv).abs() < 1e-12 * norm(rv));
            }
        }
        // the TE term alone: the eased pair's TE is the parabola to first
        // order in the amplitude (the term also crowns across the contact
        // lines, which moves the contact and lowers the TE by a relative
        // 2 c A (dφ/dξ)² / K, c = amplitude / half², K the relative curvature
        // across the line: README); checked as that linear scaling
        let m = c.pinion.roll_ratio();
        let mut rel = [0.0f64; 2];
        let mut eased_res: f64 = 0.0;
        for (k, amplitude) in [s.te_amplitude_rad, 0.1 * s.te_amplitude_rad]
            .into_iter()
            .enumerate()
        {
            let te_only = EaseOffSpec {
                profile_crowning_mm: 0.0,
                lengthwise_crowning_mm: 0.0,
                bias_mm: 0.0,
                te_amplitude_rad: amplitude,
                ..s
            };
            let te_pinion =
                EasedPinion::new(c.pinion.clone(), te_only, c.design.thickness.s_mn[0]).unwrap();
            let c_k = amplitude / s.te_half_range_rad.powi(2);
            let (mut dev, mut top) = (0.0f64, 0.0f64);
            for (phi1, seed) in path(&c.pinion, s.centre.1, 21) {
                let (x, r, _) =
                    contact(&c.asm, &te_pinion, c.gear.as_ref(), phi1, s.centre.1, seed);
                // not exactly a line contact any more: the mismatch along
                // the line is ≈ |r| Δφ² ≈ 30 mm × (1e-4)² ≈ 3e-7 mm
                assert!(r < 1e-6, "eased contact residual {r:.2e}");
                eased_res = eased_res.max(r);
                let te = m * x[3] - phi1;
                let expected = c_k * (phi1 - te_pinion.roll_centre()).powi(2);
                assert!(
                    te >= -1e-12,
                    "the eased pinion lags: TE {te:.3e} must be ≥ 0"
                );
                dev = dev.max((te - expected).abs());
                top = top.max(expected);
            }
            rel[k] = dev / top;
        }
        let te_worst = rel[0];
        println!(
            "{}: 9 × 5 grid, ease-off up to {:.2} µm, read-back error {:.2e} µm; eased tangents vs FD {:.2e} (rel); \
             TE-only ease-off: max |TE − c(φ−φc)²| / max c(φ−φc)² = {:.2e} at amplitude {:.0e} rad, {:.2e} at a tenth of it \
             (contact residual {eased_res:.1e} mm); {:.2} s",
            c.name,
            1e3 * largest,
            1e3 * worst,
            dworst,
            rel[0],
            s.te_amplitude_rad,
            rel[1],
            t0.elapsed().as_secs_f64()
        );
        assert!(worst <= 1e-5, "read-back {worst:.3e} mm");
        assert!(dworst <= 1e-7, "eased tangents");
        assert!(
            te_worst <= 1e-2,
            "TE parabola: relative deviation {te_worst:.3e}"
        );
        assert!(
            rel[1] <= 0.15 * rel[0],
            "TE deviation not first order in the amplitude: {rel:?}"
        );
    }
}

/// (d) Bad input: a gear flank that does not mesh in the pinion blank, an
/// ease-off larger than the tooth allows, grids outside the flank.
#[test]
fn bad_input_is_an_error() {
    let c = case(SAMPLES[1]);
    // the gear flank moved 30 mm along the gear axis: no contact in the blank
    let mut moved = (*c.gear).clone();
    moved.centre[2] += 30.0;
    let err = ConjugatePinion::from_blank(Arc::new(moved), &c.asm, &c.inputs, &c.design)
        .expect_err("misplaced gear flank");
    println!("misplaced gear flank: {err}");
    assert!(err.to_string().contains("do not mesh"), "{err}");
    // a 20° concave formate flank: its envelope folds inside the active flank
    let folding = FormateFlank::at_mean_point(
        &c.asm,
        &c.design,
        trace_radius(&c.inputs, &c.design),
        20f64.to_radians(),
        1.0,
    );
    let err = ConjugatePinion::from_blank(Arc::new(folding), &c.asm, &c.inputs, &c.design)
        .expect_err("limit line");
    println!("envelope folds in the blank: {err}");
    assert!(err.to_string().contains("limit line"), "{err}");
    // an ease-off of 5 mm
    let big = EaseOffSpec {
        profile_crowning_mm: 5.0,
        ..spec(&c)
    };
    let err =
        EasedPinion::new(c.pinion.clone(), big, c.design.thickness.s_mn[0]).expect_err("too large");
    println!("ease-off too large: {err}");
    assert!(
        err.to_string().contains("half the tooth thickness"),
        "{err}"
    );
    let eased = EasedPinion::new(c.pinion.clone(), spec(&c), c.design.thickness.s_mn[0]).unwrap();
    let rm = c.design.cones.rm1;
    let err = deviation_grid_at(&eased, &[(0.0, rm), (c.pinion.u_tip(rm) + 0.5, rm)])
        .expect_err("outside");
    println!("grid outside the flank: {err}");
    assert!(err.to_string().contains("node 1") && err.to_string().contains("outside the flank"));
    let err = deviation_grid_at(&eased, &[(0.0, c.pinion.v_range().1 + 1.0)]).expect_err("heel");
    assert!(err.to_string().contains("outside the flank"));
    assert!(deviation_grid(&eased, 1, 5).is_err());
    let nan = EaseOffSpec {
        bias_mm: f64::NAN,
        ..spec(&c)
    };
    assert!(EasedPinion::new(c.pinion.clone(), nan, c.design.thickness.s_mn[0]).is_err());
}

/// The F2 gear flank generated on the cradle machine with the settings
/// derived from the blank (`machine_settings::refined_setup`: mean spiral
/// and pressure angles met to 1e-9 rad on the generated flank), left hand,
/// mean cutter radius r_c0 = 114.3 mm, edge radius 0.6 mm; `generated` =
/// false gives the formate gear (the cutter surface itself, no roll). The
/// flank's own frame has tooth 0 on +y; the assembly's gear frame has the
/// mean pitch point on +x, so the flank is turned by −90°.
fn refined_f2_gear(
    design: &BlankDesign,
    kind: FlankKind,
    generated: bool,
) -> Arc<dyn ToothSurface> {
    let blank = MemberBlank::from_design(design, Member::Gear).expect("gear blank");
    let cutter = CutterChoice {
        mean_radius: 114.3,
        edge_radius: 0.6,
        blade_height: None,
    };
    let (setup, check) =
        refined_setup(&blank, Hand::Left, &cutter, generated, 1e-9, 30).expect("refined settings");
    assert!(check.max_angle_error() <= 1e-9);
    let flank = setup.flank(kind).expect("gear flank");
    Arc::new(RotatedSurface::new(
        Arc::new(flank),
        -std::f64::consts::FRAC_PI_2,
    ))
}

/// (a), (b) and the meshing residual of (c) with a gear cut by machine
/// settings derived from the F2 blank: the generated and the formate gear,
/// both flanks (the formate convex flank's pinion is bounded by the line
/// its tip edge touches: README).
#[test]
fn generated_gear_conjugate() {
    let name = SAMPLES[0];
    let (inputs, design) = sample(name);
    let asm = PairAssembly::from_blank(&inputs, &design).expect("assembly");
    let rm = design.cones.rm1;
    for (generated, kind) in [
        (true, FlankKind::Convex),
        (true, FlankKind::Concave),
        (false, FlankKind::Concave),
        (false, FlankKind::Convex),
    ] {
        let t0 = Instant::now();
        let gear = refined_f2_gear(&design, kind, generated);
        let pinion = Arc::new(
            ConjugatePinion::from_blank(gear.clone(), &asm, &inputs, &design)
                .unwrap_or_else(|e| panic!("generated {generated}, {kind:?}: {e}")),
        );
        let m = pinion.roll_ratio();
        let (v0, v1) = pinion.v_range();
        let (mut worst, mut count, mut res) = (0.0f64, 0, 0.0f64);
        for frac in [0.25, 0.5, 0.75] {
            let v = v0 + frac * (v1 - v0);
            for (phi1, seed) in path(&pinion, v, 21) {
                let (x, r, _) = contact(&asm, pinion.as_ref(), gear.as_ref(), phi1, v, seed);
                assert!(r < 1e-9, "contact residual {r:.2e} at φ1 = {phi1}");
                worst = worst.max((m * x[3] - phi1).abs());
                res = res.max(r);
                count += 1;
            }
        }
        let mut mesh: f64 = 0.0;
        // the form line's contact lies on the gear flank, not beyond its
        // tip edge: u₂ − u_tip2(v₂) ≤ 1e-9 mm (= 0 where the tip edge
        // bounds the active flank)
        let mut beyond_tip = f64::NEG_INFINITY;
        for j in 0..5 {
            let v = v0 + (v1 - v0) * j as f64 / 4.0;
            for i in 0..7 {
                let u = pinion.u_form(v) + (pinion.u_tip(v) - pinion.u_form(v)) * i as f64 / 6.0;
                let cp = pinion.conjugate_point(u, v).unwrap();
                mesh = mesh.max(cp.meshing_residual.abs());
                if i == 0 {
                    beyond_tip = beyond_tip.max(cp.gear_q[0] - gear.u_tip(cp.gear_q[1]));
                }
            }
        }
        assert!(
            beyond_tip <= 1e-9,
            "form line meets the gear beyond its tip by {beyond_tip:.3e} mm"
        );
        let eased = EasedPinion::new(
            pinion.clone(),
            spec_of(&pinion, rm),
            design.thickness.s_mn[0],
        )
        .expect("eased");
        let (read, largest) = read_back(&pinion, &eased);
        println!(
            "{name}, {} gear, {kind:?} flank: {count} contacts, max |TE| = {worst:.2e} rad, \
             contact residual {res:.2e} mm, meshing residual {mesh:.2e}, form-line contact \
             u₂ − u_tip2 ≤ {beyond_tip:.2e} mm; ease-off up to {:.2} µm \
             read back to {:.2e} µm; failures {}; {:.2} s",
            if generated { "generated" } else { "formate" },
            1e3 * largest,
            1e3 * read,
            pinion.failures(),
            t0.elapsed().as_secs_f64()
        );
        assert!(worst <= 1e-9, "TE {worst:.3e} rad");
        assert!(mesh <= 1e-12, "meshing residual {mesh:.3e}");
        assert!(read <= 1e-5, "ease-off read back {read:.3e} mm");
        assert_eq!(pinion.failures(), 0);
    }
}
