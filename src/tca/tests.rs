use super::*;
use crate::geometry::cylindrical::CylindricalPair;
use crate::geometry::involute::inv;
use crate::geometry::micro::test_gears::{gear, papers};
use crate::geometry::micro::FlankModification;
use crate::geometry::micro::{MicroGeometry, Relief, ReliefShape};
use crate::geometry::PairSpec;

const SPUR: &str = "seed002-spur";
const HELICAL: &str = "seed004-helical";

fn pair(scene: &str) -> PairSpec {
    crate::scene::read_scene(&papers().join(scene).join("scene.toml"))
        .unwrap()
        .cylindrical("this test")
        .unwrap()
        .pair
        .clone()
}

fn modification(scene: &str, which: usize, m: &MicroGeometry) -> FlankModification {
    let (tp, u_sap) = gear(scene, which);
    FlankModification::new(m, &tp, u_sap, tp.face_width).unwrap()
}

/// A test case's settings: the TCA's sampling and the cylindrical pair's
/// plane-of-action misalignment.
#[derive(Clone, Debug)]
struct Case {
    misalignment_rad: [f64; 2],
    centre_distance_error_mm: f64,
    points_per_line: usize,
    points_across: usize,
    across_spacing_mm: f64,
    extension_mm: f64,
}

impl Default for Case {
    fn default() -> Self {
        let d = TcaSettings::default();
        Case {
            misalignment_rad: [0.0; 2],
            centre_distance_error_mm: 0.0,
            points_per_line: d.points_per_line,
            points_across: d.points_across,
            across_spacing_mm: d.across_spacing_mm,
            extension_mm: d.extension_mm,
        }
    }
}

/// The TCA of a cylindrical pair with the pair's internals at hand.
#[derive(Debug)]
struct T {
    tca: Tca,
    cp: Arc<CylindricalPair>,
    t1: V3,
    n_t: V3,
    tilt_centre: V3,
    pinion: Vec<crate::geometry::flank::FlankSurface>,
    gear: Vec<crate::geometry::flank::FlankSurface>,
}

impl std::ops::Deref for T {
    type Target = Tca;
    fn deref(&self) -> &Tca {
        &self.tca
    }
}

impl T {
    fn kinematics(&self) -> &crate::geometry::cylindrical::MeshKinematics {
        self.cp.kinematics()
    }
}

impl Case {
    fn settings(&self) -> TcaSettings {
        TcaSettings {
            points_per_line: self.points_per_line,
            points_across: self.points_across,
            across_spacing_mm: self.across_spacing_mm,
            extension_mm: self.extension_mm,
            corner_spacing_mm: 0.0,
        }
    }
}

fn build(
    pr: &PairSpec,
    mods: [Option<FlankModification>; 2],
    teeth: usize,
    rpm: f64,
    s: Case,
) -> Result<T> {
    let settings = s.settings();
    settings.validate()?;
    let cp = Arc::new(
        CylindricalPair::new(pr, mods, teeth)?
            .with_plane_of_action_misalignment(s.misalignment_rad, s.centre_distance_error_mm)?,
    );
    let tca = Tca::new(cp.clone(), rpm, settings)?;
    let (t1, n_t) = cp.line_of_action();
    let side = |b: usize| {
        (1..=teeth)
            .map(|k| {
                cp.cylindrical(b)
                    .flank_surface(Flank::Right, k)
                    .unwrap()
                    .clone()
            })
            .collect()
    };
    Ok(T {
        tca,
        t1,
        n_t,
        tilt_centre: cp.tilt_centre(),
        pinion: side(0),
        gear: side(1),
        cp,
    })
}

fn tca(scene: &str, teeth: usize, mods: [Option<FlankModification>; 2], s: Case) -> T {
    build(&pair(scene), mods, teeth, 3000.0, s).unwrap()
}

fn flank_points(p: &TcaPosition) -> impl Iterator<Item = &ContactPoint> {
    p.lines
        .iter()
        .filter(|l| l.kind == LineKind::Flank)
        .flat_map(|l| &l.points)
}

/// Distance of a global point along the transverse line of action from T₁.
fn s_of(t: &T, x: V3) -> f64 {
    dot(t.n_t, sub(x, t.t1))
}

fn spread(v: impl Iterator<Item = f64>) -> f64 {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for x in v {
        lo = lo.min(x);
        hi = hi.max(x);
    }
    hi - lo
}

/// (a) Ideal aligned spur pair: zero separation, moment arm r_b1, the pairs
/// in mesh are those of `engagement(k)`.
#[test]
fn ideal_spur() {
    let t = tca(SPUR, 3, [None, None], Case::default());
    let kin = t.kinematics().clone();
    let rb1 = kin.base_radius[0];
    let mut rolls = t.roll_angles_for_cycle(16);
    rolls.extend([-0.3, 0.0, 0.25]);
    let mut worst_w: f64 = 0.0;
    let mut worst_r: f64 = 0.0;
    for roll in rolls {
        let p = t.position(roll).unwrap();
        let mut in_mesh: Vec<usize> = p
            .lines
            .iter()
            .filter(|l| l.kind == LineKind::Flank)
            .map(|l| l.pinion_tooth)
            .collect();
        in_mesh.sort();
        let want: Vec<usize> = (1..=3)
            .filter(|&k| {
                let (a, e) = kin.engagement(k);
                a <= roll && roll <= e
            })
            .collect();
        assert_eq!(in_mesh, want, "roll {roll}");
        for l in &p.lines {
            assert_eq!(l.gear_tooth, kin.mate(l.pinion_tooth));
            if l.kind == LineKind::Flank {
                assert_eq!(l.points.len(), 20);
                assert!((l.length_mm - 13.3).abs() < 1e-12);
            } else {
                for q in &l.points {
                    assert!(
                        q.separation_mm > -1e-9,
                        "corner overlap {}",
                        q.separation_mm
                    );
                }
            }
        }
        for q in flank_points(&p) {
            worst_w = worst_w.max(q.separation_mm.abs());
            worst_r = worst_r.max((q.moment_arm_mm - rb1).abs());
            let n = q.normal;
            let a = kin.working_pressure_angle;
            assert!((n[0] - a.cos()).abs() < 1e-12 && (n[1] - a.sin()).abs() < 1e-12);
        }
        assert!(p.unloaded_te_rad.abs() < 1e-9 / rb1);
    }
    eprintln!("ideal spur: |w| ≤ {worst_w:.1e} mm, |r − r_b1| ≤ {worst_r:.1e} mm");
    assert!(worst_w < 1e-9 && worst_r < 1e-9);
    assert!((t.kinematic_contact_ratio() - 1.484).abs() < 2e-3);
    let (l, h) = t.single_contact();
    assert!(l < h);
}

/// Length of pair k's contact line by sampling the placed pinion flank
/// section by section (independent of the line-slope formula): at each z the
/// roll u whose point lies on the transverse line of action, inside the path.
fn sampled_length(t: &T, k: usize, roll: f64) -> f64 {
    let kin = t.kinematics();
    let f1 = kin.frames(roll)[0];
    let fs = &t.pinion[k - 1];
    let m = [-t.n_t[1], t.n_t[0], 0.0];
    let b = kin.face_width[0];
    let n = 20000;
    let mut inside = 0;
    for i in 0..n {
        let z = b * (i as f64 + 0.5) / n as f64;
        // m·(x(u) − T₁) = 0 by the secant method on u
        let g = |u: f64| dot(m, sub(f1.place(fs.point(u, z)), t.t1));
        let (mut a, mut c) = (0.1, 1.0);
        let (mut ga, mut gc) = (g(a), g(c));
        for _ in 0..60 {
            if gc == ga {
                break;
            }
            let d = c - (c - a) * gc / (gc - ga);
            a = c;
            ga = gc;
            c = d;
            gc = g(c);
            if gc.abs() < 1e-12 {
                break;
            }
        }
        let s = s_of(t, f1.place(fs.point(c, z)));
        let on_flank = c >= fs.u_form() && c <= fs.u_tip() + 1e-12 && gc.abs() < 1e-9;
        if on_flank && s >= kin.path_start && s <= kin.path_end {
            inside += 1;
        }
    }
    b / n as f64 * inside as f64 / kin.base_helix_angle.cos()
}

/// (b) Ideal helical pair: zero separation, moment arm r_b1 cos β_b, line
/// lengths against sections of the flank, and the mean total contact length
/// over a cycle = b ε_α / cos β_b (contact lines p_bt apart in s, inclined by
/// β_b in the plane of action: mean number of lines met at any z is ε_α).
#[test]
fn ideal_helical() {
    let t = tca(HELICAL, 5, [None, None], Case::default());
    let kin = t.kinematics().clone();
    let cb = kin.base_helix_angle.cos();
    let rb1 = kin.base_radius[0];
    let mut worst_w: f64 = 0.0;
    let mut worst_r: f64 = 0.0;
    let mut total = 0.0;
    let rolls = t.roll_angles_for_cycle(24);
    for &roll in &rolls {
        let p = t.position(roll).unwrap();
        for q in flank_points(&p) {
            worst_w = worst_w.max(q.separation_mm.abs());
            worst_r = worst_r.max((q.moment_arm_mm - rb1 * cb).abs());
        }
        total += p
            .lines
            .iter()
            .filter(|l| l.kind == LineKind::Flank)
            .map(|l| l.length_mm)
            .sum::<f64>();
    }
    eprintln!("ideal helical: |w| ≤ {worst_w:.1e} mm, |r − r_b1 cos β_b| ≤ {worst_r:.1e} mm");
    assert!(worst_w < 1e-9 && worst_r < 1e-9);
    let mean = total / rolls.len() as f64;
    let want = kin.face_width[0] * kin.contact_ratio / cb;
    eprintln!("mean total contact length {mean:.4} mm, b ε_α / cos β_b = {want:.4} mm");
    assert!((mean / want - 1.0).abs() < 1e-3, "{mean} vs {want}");
    // one position, every pair (including partly meshing ones)
    let roll = rolls[5];
    let p = t.position(roll).unwrap();
    let mut seen = 0;
    for k in 1..=5 {
        let want = sampled_length(&t, k, roll);
        let got = p
            .lines
            .iter()
            .find(|l| l.pinion_tooth == k && l.kind == LineKind::Flank)
            .map_or(0.0, |l| l.length_mm);
        eprintln!("pair {k}: line length {got:.4} mm, sampled {want:.4} mm");
        assert!((got - want).abs() < 0.02, "pair {k}: {got} vs {want}");
        if got > 0.0 {
            seen += 1;
        }
    }
    assert!(seen >= 3, "{seen} pairs in mesh");
}

/// (c) Micro-geometry: w = o₁ + o₂ at the point, lead crowning a parabola.
#[test]
fn micro_geometry() {
    let r = |amount, length| {
        Some(Relief {
            amount,
            length,
            shape: ReliefShape::Parabolic,
        })
    };
    for (scene, teeth) in [(SPUR, 3), (HELICAL, 5)] {
        let m1 = MicroGeometry {
            profile_crowning: 0.004,
            tip_relief: r(0.008, 2.0),
            ..Default::default()
        };
        let m2 = MicroGeometry {
            tip_relief: r(0.010, 3.0),
            ..Default::default()
        };
        let t = tca(
            scene,
            teeth,
            [
                Some(modification(scene, 0, &m1)),
                Some(modification(scene, 1, &m2)),
            ],
            Case::default(),
        );
        let mut worst: f64 = 0.0;
        let mut largest: f64 = 0.0;
        for roll in t.roll_angles_for_cycle(8) {
            let p = t.position(roll).unwrap();
            for q in flank_points(&p) {
                let o1 = t.pinion[0].offset(q.pinion_uv[0], q.pinion_uv[1]);
                let o2 = t.gear[0].offset(q.gear_uv[0], q.gear_uv[1]);
                worst = worst.max((q.separation_mm - o1 - o2).abs());
                largest = largest.max(o1 + o2);
            }
        }
        eprintln!("{scene}: w vs o₁ + o₂: {worst:.2e} mm (largest sum {largest:.4} mm)");
        assert!(worst < 2e-6 && largest > 0.005);
    }
    // lead crowning C_β on the pinion: w = C_β ζ², ζ = (z − b/2)/(b/2)
    let cb = 0.012;
    let m = MicroGeometry {
        lead_crowning: cb,
        ..Default::default()
    };
    let t = tca(
        SPUR,
        3,
        [Some(modification(SPUR, 0, &m)), None],
        Case::default(),
    );
    let b = 13.3;
    let p = t.position(0.0).unwrap();
    let mut worst: f64 = 0.0;
    for q in flank_points(&p) {
        let zeta = (q.position[2] - 0.5 * b) / (0.5 * b);
        worst = worst.max((q.separation_mm - cb * zeta * zeta).abs());
    }
    eprintln!("lead crowning parabola: {worst:.2e} mm");
    assert!(worst < 1e-7);
    assert!(p.unloaded_te_rad > 0.0);
}

/// (d) Misalignment and centre-distance error.
#[test]
fn misalignment_and_centre_distance() {
    let g = 1e-4;
    for (scene, teeth) in [(SPUR, 3), (HELICAL, 5)] {
        let set = |m: [f64; 2], da: f64| Case {
            misalignment_rad: m,
            centre_distance_error_mm: da,
            ..Default::default()
        };
        // in the plane of action: w = γ (Δz n_t·n + ρ₂ n_z) to first order
        // (spur: γ Δz, slope γ); the ρ₂ n_z term is the axial shift of a
        // helical flank point by the tilt
        let t = tca(scene, teeth, [None, None], set([g, 0.0], 0.0));
        let kin = t.kinematics().clone();
        let zm = t.tilt_centre[2];
        let mut worst: f64 = 0.0;
        let mut spread_in: f64 = 0.0;
        let mut spread_out: f64 = 0.0;
        let t_out = tca(scene, teeth, [None, None], set([0.0, g], 0.0));
        for roll in t.roll_angles_for_cycle(6) {
            let p = t.position(roll).unwrap();
            for q in flank_points(&p) {
                let x = q.position;
                let rho2 = kin.line_length - s_of(&t, x);
                let n = q.normal;
                let pred = g * ((x[2] - zm) * dot(t.n_t, n) + rho2 * n[2]);
                worst = worst.max((q.separation_mm - pred).abs());
            }
            spread_in = spread_in.max(spread(flank_points(&p).map(|q| q.separation_mm)));
            let p = t_out.position(roll).unwrap();
            spread_out = spread_out.max(spread(flank_points(&p).map(|q| q.separation_mm)));
        }
        eprintln!(
            "{scene}: γ_β = {g}: |w − first order| ≤ {worst:.2e} mm, spread {spread_in:.3e} mm; γ_δ = {g}: spread {spread_out:.3e} mm"
        );
        assert!(worst < 2e-3 * spread_in);
        assert!(spread_out < 2e-3 * spread_in);
        // spur: slope exactly γ along the face
        if scene == SPUR {
            let p = t.position(0.0).unwrap();
            let l = &p
                .lines
                .iter()
                .find(|l| l.kind == LineKind::Flank)
                .unwrap()
                .points;
            let (a, b) = (&l[0], &l[l.len() - 1]);
            let slope = (b.separation_mm - a.separation_mm) / (b.position[2] - a.position[2]);
            assert!((slope / g - 1.0).abs() < 1e-3, "slope {slope}");
        }
        // centre-distance error: uniform separation (involute property) equal
        // to (r_b1 + r_b2)(inv α′ − inv α) along the new line of action; the
        // moment arm stays r_b1 cos β_b; w − r θ₀ = 0 everywhere
        let da = 0.1;
        let t = tca(scene, teeth, [None, None], set([0.0, 0.0], da));
        let rb = kin.base_radius;
        let a = kin.centre_distance;
        let alpha = kin.working_pressure_angle;
        let alpha2 = ((rb[0] + rb[1]) / (a + da)).acos();
        let cb = kin.base_helix_angle.cos();
        let want = (rb[0] + rb[1]) * (inv(alpha2) - inv(alpha)) * cb;
        let mut dev: f64 = 0.0;
        let mut worst_r: f64 = 0.0;
        let mut worst_te: f64 = 0.0;
        for roll in t.roll_angles_for_cycle(6) {
            let p = t.position(roll).unwrap();
            for q in flank_points(&p) {
                dev = dev.max((q.separation_mm - want).abs());
                worst_r = worst_r.max((q.moment_arm_mm - rb[0] * cb).abs());
                worst_te =
                    worst_te.max((q.separation_mm - q.moment_arm_mm * p.unloaded_te_rad).abs());
            }
        }
        eprintln!(
            "{scene}: Δa = {da} mm: w = {want:.6} mm ± {dev:.1e}, |r − r_b1 cos β_b| ≤ {worst_r:.1e}, |w − r θ₀| ≤ {worst_te:.1e} (α_wt {:.4}° → {:.4}°)",
            alpha.to_degrees(),
            alpha2.to_degrees()
        );
        assert!(dev < 1e-6 && worst_r < 1e-9 && worst_te < 1e-6);
    }
}

/// (e) Velocities and curvature: spur v_s = (ω₁ + ω₂)(s − s_C), the
/// entraining speed (ω₁ρ₁ + ω₂ρ₂)/2, ρ_eq = ρ₁ρ₂/(ρ₁ + ρ₂) with ρ_i the
/// distances to the base tangent points (helical: ρ_i/cos β_b).
#[test]
fn velocities_and_curvature() {
    for (scene, teeth) in [(SPUR, 3), (HELICAL, 5)] {
        let t = tca(scene, teeth, [None, None], Case::default());
        let kin = t.kinematics().clone();
        let [w1, w2] = t.omega;
        let sc = kin.base_radius[0] * kin.working_pressure_angle.tan();
        let cb = kin.base_helix_angle.cos();
        let (mut ev, mut er): (f64, f64) = (0.0, 0.0);
        let mut vmax: f64 = 0.0;
        for roll in t.roll_angles_for_cycle(8) {
            let p = t.position(roll).unwrap();
            for q in flank_points(&p) {
                let s = s_of(&t, q.position);
                let (r1, r2) = (s, kin.line_length - s);
                let vs = (w1 + w2) * (s - sc) * 1e-3;
                let u = 0.5 * (w1 * r1 + w2 * r2) * 1e-3;
                ev = ev
                    .max((q.sliding_velocity - vs).abs())
                    .max((q.rolling_velocity - u).abs())
                    .max((q.sum_velocity - 2.0 * u).abs());
                vmax = vmax.max(vs.abs());
                let want = [r1 / cb, r2 / cb];
                let eq = want[0] * want[1] / (want[0] + want[1]);
                for i in 0..2 {
                    er = er.max((q.curvature_radius[i] / want[i] - 1.0).abs());
                }
                er = er.max((q.equivalent_radius_mm / eq - 1.0).abs());
            }
        }
        eprintln!(
            "{scene}: velocities vs closed form {ev:.1e} m/s (largest |v_s| {vmax:.2} m/s), radii {er:.1e} relative"
        );
        assert!(ev < 1e-9 && er < 1e-6);
        // zero sliding at the pitch point: the middle pair at roll 0, z = 0 section
        let p = t.position(0.0).unwrap();
        let q = flank_points(&p)
            .min_by(|a, b| {
                (s_of(&t, a.position) - sc)
                    .abs()
                    .total_cmp(&(s_of(&t, b.position) - sc).abs())
            })
            .unwrap();
        let ds = s_of(&t, q.position) - sc;
        assert!((q.sliding_velocity - (w1 + w2) * ds * 1e-3).abs() < 1e-12);
        if scene == SPUR {
            assert!(q.sliding_velocity.abs() < 1e-12, "{}", q.sliding_velocity);
        }
    }
}

/// (f) Corner contact before the start and after the end of the path (spur).
#[test]
fn corner_contact() {
    let t = tca(SPUR, 3, [None, None], Case::default());
    let kin = t.kinematics().clone();
    // tooth 1 engages one pitch after the middle pair (tooth 2 still in
    // mesh before its start), tooth 3 leaves one pitch before it
    let start = kin.engagement(1).0;
    let end = kin.engagement(3).1;
    let corner = |roll: f64, kind: LineKind| -> Option<ContactLine> {
        let k = if kind == LineKind::GearTipCorner {
            1
        } else {
            3
        };
        t.position(roll)
            .unwrap()
            .lines
            .into_iter()
            .find(|l| l.pinion_tooth == k && l.kind == kind)
    };
    for (edge, kind, sign) in [
        (start, LineKind::GearTipCorner, -1.0),
        (end, LineKind::PinionTipCorner, 1.0),
    ] {
        let mut last = 0.0;
        let mut gone = false;
        let mut n_found = 0;
        for i in 1..=60 {
            let d = 0.002 * i as f64;
            let roll = edge + sign * d;
            match corner(roll, kind) {
                Some(l) => {
                    assert!(!gone, "{kind:?} came back at {d} rad");
                    n_found += 1;
                    let w = l.points[0].separation_mm;
                    assert!(w > last && w <= 0.2, "{kind:?} at {d}: w {w}");
                    for q in &l.points {
                        assert!((q.separation_mm - w).abs() < 1e-9);
                        assert!(q.moment_arm_mm > 0.0);
                        let uv = if kind == LineKind::GearTipCorner {
                            q.gear_uv
                        } else {
                            q.pinion_uv
                        };
                        let u_tip = if kind == LineKind::GearTipCorner {
                            t.gear[0].u_tip()
                        } else {
                            t.pinion[0].u_tip()
                        };
                        assert_eq!(uv[0], u_tip);
                    }
                    if i == 1 {
                        eprintln!(
                            "{kind:?} {d} rad beyond the path: w = {w:.3e} mm, r = {:.4} mm",
                            l.points[0].moment_arm_mm
                        );
                    }
                    last = w;
                }
                None => gone = true,
            }
        }
        eprintln!("{kind:?}: found at {n_found} of 60 steps of 0.002 rad, last w {last:.4} mm");
        assert!(gone && n_found >= 3 && last > 0.1);
    }
    // close to the path end the corner closes continuously
    let l = corner(start - 1e-5, LineKind::GearTipCorner).unwrap();
    assert!(l.points[0].separation_mm < 1e-6);
    // switched off
    let off = tca(
        SPUR,
        3,
        [None, None],
        Case {
            extension_mm: 0.0,
            ..Default::default()
        },
    );
    let p = off.position(start - 0.01).unwrap();
    assert!(p.lines.iter().all(|l| l.kind == LineKind::Flank));
}

#[test]
fn across_grid_and_speed() {
    let s = Case {
        points_per_line: 10,
        points_across: 3,
        across_spacing_mm: 0.2,
        ..Default::default()
    };
    let t = tca(SPUR, 3, [None, None], s);
    let p = t.position(0.0).unwrap();
    let l = p.lines.iter().find(|l| l.kind == LineKind::Flank).unwrap();
    assert_eq!(l.points.len(), 30);
    let across: Vec<f64> = l.points[..3].iter().map(|q| q.across_mm).collect();
    assert_eq!(across, vec![-0.2, 0.0, 0.2]);
    // timing: 50 points a line
    for (scene, teeth) in [(SPUR, 3), (HELICAL, 5)] {
        let m = MicroGeometry {
            profile_crowning: 0.004,
            lead_crowning: 0.01,
            ..Default::default()
        };
        let t = tca(
            scene,
            teeth,
            [Some(modification(scene, 0, &m)), None],
            Case {
                points_per_line: 50,
                misalignment_rad: [1e-4, 0.0],
                ..Default::default()
            },
        );
        let rolls = t.roll_angles_for_cycle(20);
        let t0 = std::time::Instant::now();
        let mut n = 0;
        for &r in &rolls {
            n += t
                .position(r)
                .unwrap()
                .lines
                .iter()
                .map(|l| l.points.len())
                .sum::<usize>();
        }
        let dt = t0.elapsed().as_secs_f64() / rolls.len() as f64;
        eprintln!(
            "{scene}: {:.0} µs a position, {:.1} points a position, {:.2} µs a point",
            dt * 1e6,
            n as f64 / rolls.len() as f64,
            dt * 1e6 * rolls.len() as f64 / n as f64
        );
    }
}

/// (g) Bad input.
#[test]
fn bad_input() {
    let pr = pair(SPUR);
    let ok = Case::default();
    let bad = [
        Case {
            misalignment_rad: [f64::NAN, 0.0],
            ..ok.clone()
        },
        Case {
            misalignment_rad: [0.0, 0.2],
            ..ok.clone()
        },
        Case {
            centre_distance_error_mm: f64::INFINITY,
            ..ok.clone()
        },
        Case {
            centre_distance_error_mm: 20.0,
            ..ok.clone()
        },
        Case {
            points_per_line: 1,
            ..ok.clone()
        },
        Case {
            points_across: 0,
            ..ok.clone()
        },
        Case {
            points_across: 3,
            across_spacing_mm: 0.0,
            ..ok.clone()
        },
        Case {
            extension_mm: -1.0,
            ..ok.clone()
        },
    ];
    for s in bad {
        let e = build(&pr, [None, None], 3, 1000.0, s.clone()).unwrap_err();
        eprintln!("{e}");
        assert!(matches!(e, FlankError::Model(_)), "{s:?}");
    }
    assert!(build(&pr, [None, None], 0, 1000.0, ok.clone()).is_err());
    assert!(build(&pr, [None, None], 14, 1000.0, ok.clone()).is_err());
    assert!(build(&pr, [None, None], 3, -1.0, ok.clone()).is_err());
    assert!(build(&pr, [None, None], 3, f64::NAN, ok.clone()).is_err());
    // a modification of the other gear
    let m = modification(SPUR, 1, &MicroGeometry::default());
    assert!(build(&pr, [Some(m), None], 3, 1000.0, ok.clone()).is_err());
    let t = build(&pr, [None, None], 3, 1000.0, ok).unwrap();
    assert!(t.position(f64::NAN).is_err());
    // far outside the sector's engagement: no pair in mesh
    let e = t.position(3.0).unwrap_err();
    assert!(e.to_string().contains("no tooth pair"), "{e}");
    // in degrees, as the scene's angles (issue 56), the radians in parentheses
    assert!(
        e.to_string().contains("at roll 171.8873° (3.0000 rad)"),
        "{e}"
    );
    assert!(t.roll_angles_for_cycle(0).is_empty());
}

/// (h) Axial displacements ΔP, ΔG through the generic misalignment set:
/// moving a helicoid along its axis by δ moves its surface along its normal
/// by δ sin β_b (|n_z| = sin β_b), so a helical pair's separation becomes
/// uniform ±(ΔG − ΔP) sin β_b; a spur pair's stays 0.
#[test]
fn axial_displacements() {
    for (scene, teeth) in [(SPUR, 3), (HELICAL, 5)] {
        let pr = pair(scene);
        let m = crate::geometry::gear_pair::Misalignment {
            pinion_axial_mm: -0.02,
            gear_axial_mm: 0.03,
            ..Default::default()
        };
        let cp = CylindricalPair::new(&pr, [None, None], teeth)
            .unwrap()
            .with_misalignment(m)
            .unwrap();
        let bb = cp.kinematics().base_helix_angle;
        let t = Tca::new(Arc::new(cp), 3000.0, Case::default().settings()).unwrap();
        let want = 0.05 * bb.sin();
        let mut n = 0;
        for roll in t.roll_angles_for_cycle(8) {
            let p = t.position(roll).unwrap();
            for q in flank_points(&p) {
                assert!(
                    (q.separation_mm.abs() - want).abs() < 1e-9,
                    "{scene} roll {roll}: w = {} vs ±{want}",
                    q.separation_mm
                );
                n += 1;
            }
        }
        assert!(n > 100, "{scene}: {n} points");
        eprintln!("{scene}: |w| = {want:.3e} mm at {n} points");
    }
}

/// (h) The point-contact TCA through the gear-pair interface on crowned
/// spur and helical pairs (pinion lead crowning 10 µm, profile crowning
/// 4 µm: a point contact), checked independently: with the gear turned to
/// the TCA's TE the active pair's flanks touch (gap at the contact ≤ 1e-9
/// mm) and overlap nowhere (the signed distance from the gear flank, where
/// its foot lies inside the flank's parameter box, of
/// 61 × 61 pinion points within ±2 % of the flank around the contact and
/// of 41 × 21 over the whole active flank ≥ −1e-9 mm). Beside it the
/// line-contact TCA's unloaded TE (θ₀ = min w/r, 200 points × 41 rows a
/// line, Δφ₂ = −(z₁/z₂) θ₀) is printed with the overlap it leaves: the
/// first-order w/r overestimates the lag by about 1 % (issue 17 note).
#[test]
fn point_contact_tca_of_crowned_cylindrical_pairs() {
    use crate::geometry::frame::Frame;
    use crate::geometry::gear_pair::GearPair;
    use crate::tca::point_contact::{point_tca, PointTcaSettings};
    for (scene, teeth) in [(SPUR, 3), (HELICAL, 3)] {
        let m = MicroGeometry {
            profile_crowning: 0.004,
            lead_crowning: 0.01,
            ..Default::default()
        };
        let t = tca(
            scene,
            teeth,
            [Some(modification(scene, 0, &m)), None],
            Case {
                points_per_line: 200,
                points_across: 41,
                across_spacing_mm: 0.05,
                extension_mm: 0.0,
                ..Default::default()
            },
        );
        let settings = PointTcaSettings {
            edges: false,
            search_directions: 0,
            ..Default::default()
        };
        let p = point_tca(t.cp.as_ref(), &settings).unwrap();
        let cp = t.cp.as_ref();
        let ratio = cp.ratio();
        let pitch = p.pitch_rad;
        let rb2 = t.kinematics().base_radius[1];
        let k = cp.middle();
        let (ps, gs) = (
            cp.pinion().flank(Flank::Right, k).unwrap(),
            cp.gear().flank(Flank::Right, cp.mate(k)).unwrap(),
        );
        // least signed distance of pinion points from the gear flank with
        // the gear lagging by `lag` (rad) at `roll`
        let gap = |lag: f64, roll: f64, points: &mut dyn Iterator<Item = (f64, f64)>| {
            let [f1, f2] = cp.frames(roll);
            let ax = f2.rotate(cp.rotation_axes()[1]);
            let f2t = Frame::about_axis(f2.translation, ax, lag).compose(&f2);
            points
                .filter_map(|(u, v)| {
                    let x = f1.place(ps.point(u, v));
                    let (gu, gv, d) = gs.closest_point(f2t.rotate_back(sub(x, f2t.translation)));
                    // a foot on the gear flank's boundary is no distance
                    // to the flank (the point lies beyond its face or tip)
                    let (a, b) = gs.u_range();
                    let (c, e) = gs.v_range();
                    let inside = gu > a && gu < b && gv > c && gv < e;
                    inside.then_some(d)
                })
                .fold(f64::INFINITY, f64::min)
        };
        let (mut worst_touch, mut worst_overlap, mut worst_line) = (0.0f64, 0.0f64, 0.0f64);
        let mut n = 0;
        for pos in p
            .positions
            .iter()
            .filter(|q| q.roll_rad.abs() <= 0.25 * pitch)
        {
            let c = pos.pairs.iter().find(|c| c.active).unwrap();
            // the active pair is the middle pair at the trace roll
            let roll = pos.roll_rad - c.offset as f64 * cp.tooth_roll_step();
            let [cu, cv] = c.pinion_uv;
            let touch = gap(pos.te_rad, roll, &mut std::iter::once((cu, cv)));
            let (du, dv) = (
                0.02 * (ps.u_tip(cv) - ps.u_form(cv)),
                0.02 * (ps.v_range().1 - ps.v_range().0),
            );
            let mut local = (0..=60).flat_map(|i| {
                (0..=60).map(move |j| {
                    (
                        cu + du * (i as f64 / 30.0 - 1.0),
                        cv + dv * (j as f64 / 30.0 - 1.0),
                    )
                })
            });
            let (v0, v1) = ps.v_range();
            let mut whole = (0..=40).flat_map(|i| {
                (0..=20).map(move |j| {
                    let v = v0 + (v1 - v0) * j as f64 / 20.0;
                    (
                        ps.u_form(v) + (ps.u_tip(v) - ps.u_form(v)) * i as f64 / 40.0,
                        v,
                    )
                })
            });
            let overlap = gap(pos.te_rad, roll, &mut local).min(gap(pos.te_rad, roll, &mut whole));
            worst_touch = worst_touch.max(touch.abs());
            worst_overlap = worst_overlap.min(overlap);
            let theta0 = t.position(pos.roll_rad).unwrap().unloaded_te_rad;
            worst_line = worst_line.max((pos.te_rad + ratio * theta0).abs() * rb2);
            n += 1;
        }
        eprintln!(
            "{scene}: {n} positions: gap at the contact ≤ {worst_touch:.1e} mm, least gap {worst_overlap:.1e} mm; line TCA TE differs by up to {worst_line:.2e} mm × r_b2 (TE p-p {:.3} µrad, {} Newton steps, residuals {:.1e} mm / {:.1e})",
            1e6 * p.te_peak_to_peak_rad,
            p.newton_steps,
            p.max_residual[0],
            p.max_residual[1]
        );
        assert!(n >= 10, "{scene}: {n} positions compared");
        assert!(worst_touch <= 1e-9, "{scene}: {worst_touch:.3e} mm");
        assert!(
            worst_overlap >= -1e-9,
            "{scene}: overlap {worst_overlap:.3e} mm"
        );
        assert!(p.max_residual[0] <= 1e-9 && p.max_residual[1] <= 1e-9);
    }
}

/// A plane patch z = 0 (u = x, v = y) whose own solve "fails" for u > 1:
/// there `evaluate` returns a fallback point off the plane that moves with
/// u, as a generated flank's last Newton iterate does; evaluations counted.
#[derive(Debug, Default)]
struct HalfPlane {
    evaluations: std::sync::atomic::AtomicUsize,
}

impl ToothSurface for HalfPlane {
    fn u_range(&self) -> (f64, f64) {
        (-2.0, 2.0)
    }
    fn v_range(&self) -> (f64, f64) {
        (-2.0, 2.0)
    }
    fn u_tip(&self, _v: f64) -> f64 {
        1.0
    }
    fn u_form(&self, _v: f64) -> f64 {
        -1.0
    }
    fn u_root(&self, _v: f64) -> f64 {
        -2.0
    }
    fn point(&self, u: f64, v: f64) -> V3 {
        self.evaluate(u, v).0
    }
    fn normal(&self, u: f64, v: f64) -> V3 {
        self.evaluate(u, v).1
    }
    fn derivatives(&self, u: f64, v: f64) -> (V3, V3) {
        let (_, _, a, b) = self.evaluate(u, v);
        (a, b)
    }
    fn evaluate(&self, u: f64, v: f64) -> (V3, V3, V3, V3) {
        self.evaluations
            .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let x = if u > 1.0 { 1.0 - (u - 1.0) } else { u };
        (
            [x, v, 0.0],
            [0.0, 0.0, 1.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
        )
    }
    fn evaluate_checked(&self, u: f64, v: f64) -> Option<(V3, V3, V3, V3)> {
        (u <= 1.0).then(|| self.evaluate(u, v))
    }
}

/// `line_intersection` meets the surface where it is defined (Newton from
/// a neighbouring start, as before) and gives up at the first iterate
/// where it is not, instead of cycling on fallback points for 30 steps.
#[test]
fn line_intersection_stops_where_the_surface_is_undefined() {
    let s = HalfPlane::default();
    let down = [0.0, 0.0, -1.0];
    let (u, v, t, _) = line_intersection(
        &s,
        &Frame::IDENTITY,
        [0.5, 0.25, 3.0],
        down,
        [0.0, 0.0],
        1e-12,
    )
    .unwrap();
    assert!((u - 0.5).abs() < 1e-12 && (v - 0.25).abs() < 1e-12 && (t - 3.0).abs() < 1e-12);
    let before = s.evaluations.load(std::sync::atomic::Ordering::Relaxed);
    let miss = line_intersection(
        &s,
        &Frame::IDENTITY,
        [1.5, 0.0, 3.0],
        down,
        [0.9, 0.0],
        1e-12,
    );
    assert!(miss.is_none());
    let spent = s.evaluations.load(std::sync::atomic::Ordering::Relaxed) - before;
    assert!(spent <= 2, "{spent} evaluations");
}

/// The line TCA over a mesh cycle (`flank tca` on spur and helical
/// scenes): on unmodified aligned pairs with tip corners off, the contact
/// ratio at δ is the kinematic total ε_γ to within the position spacing and θ₀
/// is zero everywhere; tip corners only add contact; bad settings are
/// errors.
#[test]
fn line_cycle_of_spur_and_helical_pairs() {
    use crate::tca::line_cycle::line_tca_cycle;
    let n = 60;
    for scene in [SPUR, HELICAL] {
        // enough teeth for every pair in mesh (ε_γ up to 3)
        let off = tca(
            scene,
            5,
            [None, None],
            Case {
                extension_mm: 0.0,
                points_per_line: 8,
                ..Default::default()
            },
        );
        let c = line_tca_cycle(&off, n, 0.00635).unwrap();
        // total contact ratio ε_γ = ε_α + ε_β, ε_β = b sin β / (π m_n)
        // (ISO 21771), b the common face width
        let spec = pair(scene);
        let b = spec.pinion.face_width.min(spec.gear.face_width);
        let eps_beta =
            b * spec.pinion.helix_angle.sin() / (std::f64::consts::PI * spec.pinion.normal_module);
        let eps = off.kinematic_contact_ratio() + eps_beta;
        eprintln!(
            "{scene}: contact ratio at δ {:.4}, kinematic ε_γ {eps:.4}, TE p-p {:.2e} rad",
            c.contact_ratio, c.te_peak_to_peak_rad
        );
        assert_eq!(c.positions.len(), n);
        assert!(
            (c.contact_ratio - eps).abs() <= 1.0 / n as f64 + 1e-9,
            "{scene}"
        );
        assert!(c.te_peak_to_peak_rad.abs() < 1e-12, "{scene}");
        assert!(c.positions.iter().all(|p| p.unloaded_te_rad.abs() < 1e-12));
        assert_eq!(c.corner_contact_positions, 0);
        assert!(!c.corners);
        let on = tca(
            scene,
            5,
            [None, None],
            Case {
                points_per_line: 8,
                ..Default::default()
            },
        );
        let e = line_tca_cycle(&on, n, 0.00635).unwrap();
        assert!(e.corners);
        assert!(e.contact_ratio >= c.contact_ratio, "{scene}");
        // the corners close continuously at the path ends: some positions
        // next to them have a corner within δ
        assert!(e.corner_contact_positions > 0, "{scene}");
    }
    let t = tca(SPUR, 3, [None, None], Case::default());
    assert!(line_tca_cycle(&t, 1, 0.00635).is_err());
    assert!(line_tca_cycle(&t, 30, 0.0).is_err());
    assert!(line_tca_cycle(&t, 30, f64::NAN).is_err());
}

/// A corner line keeps K points unless a least spacing says fewer: then
/// ⌊span/spacing⌋, never below 2.
#[test]
fn corner_points_respect_the_least_spacing() {
    assert_eq!(super::corner_points(20, 13.3, 0.0), 20);
    assert_eq!(super::corner_points(20, 13.3, 1.9), 7);
    assert_eq!(super::corner_points(20, 13.3, 0.5), 20);
    assert_eq!(super::corner_points(20, 0.3, 1.9), 2);
    assert_eq!(super::corner_points(5, 13.3, 1.9), 5);
}
