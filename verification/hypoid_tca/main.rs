//! Point-contact TCA of hypoid pairs (issue 17, point 8); see README.md.
//!
//! (a) a conjugate pair (pinion conjugate to the gear, no ease-off): TE
//!     ≤ 1e-9 rad and every flank contact flagged as line contact;
//! (b) the contact ellipse from the curvatures against the numerical search
//!     of seed 000 on flank points, at a small approach (≤ 1 %) and at the
//!     seed's δ = 0.00635 mm (figure printed);
//! (c) edge contacts of seed 000 with edges on: the point on the member's
//!     face cone to 1e-9 mm, t·n ≤ 1e-10, the mating flank resting on the
//!     edge (lean > 0);
//! (d) misalignment moves the pattern and changes the TE; the aligned pair
//!     reproduces itself;
//! (e) bad input: δ ≤ 0, a settings bound, a pair whose gear is the
//!     pinion's mirror (same hand) refused with the reason.

use std::path::{Path, PathBuf};

use flank::geometry::bevel::body::BevelGear;
use flank::geometry::bevel::pair::BevelPair;
use flank::geometry::gear_pair::{GearPair, Misalignment};
use flank::geometry::tangency::{ContactSystem, Edge};
use flank::scene::{read_scene, Scene};
use flank::tca::point_contact::{
    point_tca, point_tca_shared, EllipseMemo, PointTca, PointTcaSettings,
};

fn papers() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("papers")
}

fn bevel(path: &Path) -> Scene {
    read_scene(path).unwrap()
}

/// The bevel gears of a scene this case reads.
fn gears(s: &Scene) -> &flank::scene::BevelGears {
    s.bevel("this case").unwrap()
}

fn seed000() -> Scene {
    bevel(&papers().join("seed000-hypoid/scene.toml"))
}

/// Seed 000's scene with `extra` lines after `[pinion]`, written to a
/// temporary file.
fn seed000_with(extra: &str, name: &str) -> Scene {
    let text = std::fs::read_to_string(papers().join("seed000-hypoid/scene.toml")).unwrap();
    let text = text.replace("[pinion]\n", &format!("[pinion]\n{extra}\n"));
    let dir = std::env::temp_dir().join(format!("flank_hypoid_tca_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    bevel(&p)
}

fn settings(edges: bool, search: usize, delta: f64) -> PointTcaSettings {
    PointTcaSettings {
        edges,
        search_directions: search,
        approach_mm: delta,
        ..Default::default()
    }
}

fn middle_contacts(t: &PointTca) -> impl Iterator<Item = &flank::tca::point_contact::PairContact> {
    t.positions
        .iter()
        .flat_map(|p| p.pairs.iter().filter(|c| c.offset == 0))
}

#[test]
fn a_conjugate_pair_has_no_te_and_line_contact() {
    let s = seed000_with("process = \"conjugate\"", "conjugate.toml");
    let t0 = std::time::Instant::now();
    let t = point_tca(gears(&s).pair.as_ref(), &settings(false, 0, 0.00635)).unwrap();
    let worst = middle_contacts(&t)
        .map(|c| c.gear_lag_rad.abs())
        .fold(0.0f64, f64::max);
    let flank: Vec<_> = middle_contacts(&t)
        .filter(|c| c.system == ContactSystem::Flank)
        .collect();
    let lines = flank
        .iter()
        .filter(|c| {
            c.ellipse
                .is_some_and(|e| e.line_contact && e.semi_major_mm.is_none())
        })
        .count();
    println!(
        "(a) conjugate pinion on seed 000's gear: {} positions, max |Δφ₂| = {worst:.2e} rad, TE p-p {:.2e} rad, {lines}/{} flank contacts flagged line contact, residuals {:.1e} mm / {:.1e}, {:.2} s",
        t.positions.len(),
        t.te_peak_to_peak_rad,
        flank.len(),
        t.max_residual[0],
        t.max_residual[1],
        t0.elapsed().as_secs_f64()
    );
    assert!(flank.len() >= 20);
    assert!(
        worst <= 1e-9 && t.te_peak_to_peak_rad <= 1e-9,
        "{worst:.3e}"
    );
    assert_eq!(lines, flank.len());
    // the crossing check: a conjugate pair's flanks touch along lines and
    // never interpenetrate
    assert!(t.crossing.is_none(), "{:?}", t.crossing);
}

/// The crossing check (`PointTca::crossing`): on seed 003's pair, whose
/// traced flank contact ends at −13.2° and +8.8° with no edge taking over,
/// the flanks of a neighbouring pair interpenetrate where the TE envelope
/// puts the gear; the check finds it, deeper than any approach δ, and the
/// FE pairing of `flank run` sees the same interference in the nominal
/// placement (0.65 mm, `mesh_cycle::cycle` tests).
#[test]
fn crossing_flanks_are_reported() {
    let path = format!(
        "{}/papers/seed003-hypoid/scene.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    let s = read_scene(Path::new(&path)).unwrap();
    let t = point_tca(gears(&s).pair.as_ref(), &settings(true, 0, 0.00635)).unwrap();
    let c = t.crossing.expect("seed 003's flanks cross");
    println!(
        "(e) seed 003: flanks cross by {:.4} mm at roll {:.3}°, pair offset {}, pinion (u, v) = ({:.3}, {:.3}) mm",
        c.depth_mm,
        c.roll_rad.to_degrees(),
        c.pair_offset,
        c.pinion_uv[0],
        c.pinion_uv[1]
    );
    assert!(c.depth_mm > 0.1, "{c:?}");
    let seed000 = point_tca(
        seed000().bevel("this case").unwrap().pair.as_ref(),
        &settings(true, 0, 0.00635),
    )
    .unwrap();
    assert!(seed000.crossing.is_none(), "{:?}", seed000.crossing);
}

/// The screened crossing check against the exhaustive one (every pinion
/// grid point tested by closest point, `crossing_exhaustive`): the same
/// deepest crossing (position, pair, grid point, depth to 1e-9 mm) and the
/// same number of (position × pair) checks that cross, on pairs whose
/// flanks cross deeply (seed 003 as milled, 0.71 mm), at a tip edge (seed
/// 000 tilted, 0.042 mm) and barely (seed 003 synthesised, 1.1 µm at the
/// pinion's heel tip), and on one whose flanks do not (seed 000); with the
/// share of grid points the screen sent to the exact test.
#[test]
fn the_screened_crossing_check_finds_what_every_point_finds() {
    let scene = |p: &str| bevel(&papers().join(p));
    for (name, s, edges) in [
        ("seed 003", scene("seed003-hypoid/scene.toml"), true),
        (
            "seed 003 synthesised",
            scene("seed003-hypoid/scene_synthesised.toml"),
            true,
        ),
        ("seed 000", seed000(), true),
        (
            "seed 000 tilted, without edges",
            scene("seed000-hypoid/scene_tilted.toml"),
            false,
        ),
    ] {
        let run = |exhaustive: bool| {
            let t0 = std::time::Instant::now();
            let t = point_tca(
                gears(&s).pair.as_ref(),
                &PointTcaSettings {
                    search_directions: 0,
                    edges,
                    crossing_exhaustive: exhaustive,
                    ..Default::default()
                },
            )
            .unwrap();
            (t, t0.elapsed().as_secs_f64())
        };
        let (screened, ts) = run(false);
        let (every, te) = run(true);
        let (a, b) = (screened.crossing_scan, every.crossing_scan);
        println!(
            "(f) {name}: crossing check screened {}/{} points exact, {} crossing checks, deepest {:?} mm, {ts:.2} s; every point: {}/{}, {} crossing, {:?} mm, {te:.2} s",
            a.exact,
            a.points,
            a.crossed,
            screened.crossing.map(|c| c.depth_mm),
            b.exact,
            b.points,
            b.crossed,
            every.crossing.map(|c| c.depth_mm),
        );
        assert_eq!(a.points, b.points);
        assert_eq!(b.exact, b.points);
        assert_eq!(a.crossed, b.crossed, "{name}");
        match (screened.crossing, every.crossing) {
            (None, None) => {}
            (Some(x), Some(y)) => {
                assert_eq!(
                    (x.roll_rad, x.pair_offset, x.pinion_uv),
                    (y.roll_rad, y.pair_offset, y.pinion_uv),
                    "{name}"
                );
                assert!((x.depth_mm - y.depth_mm).abs() <= 1e-9, "{x:?} {y:?}");
            }
            (x, y) => panic!("{name}: screened {x:?}, every point {y:?}"),
        }
        // the TCA itself does not depend on how the check is done
        assert_eq!(screened.positions, every.positions);
    }
}

/// Flank contacts of the middle pair whose ellipse lies on the flanks
/// (the search did not stop at a boundary: its axes are closed and the
/// curvature ellipse fits inside with a margin).
fn interior(t: &PointTca) -> Vec<(f64, f64, f64, f64)> {
    middle_contacts(t)
        .filter(|c| c.system == ContactSystem::Flank)
        .filter_map(|c| {
            let (e, s) = (c.ellipse?, c.searched_ellipse?);
            Some((
                e.semi_major_mm?,
                s.semi_major_mm?,
                e.semi_minor_mm,
                s.semi_minor_mm,
            ))
        })
        .collect()
}

#[test]
fn curvature_and_searched_ellipses_agree_on_the_flanks() {
    let s = seed000();
    for (delta, limit) in [(0.0001, Some(0.01)), (0.00635, None)] {
        let t = point_tca(gears(&s).pair.as_ref(), &settings(false, 36, delta)).unwrap();
        let pts = interior(&t);
        // compare over the middle half of the path (the ellipse away from
        // the toe and heel, where the search stops at the flank's end)
        let n = pts.len();
        let mid = &pts[n / 4..3 * n / 4];
        let rel = |a: f64, b: f64| (a - b).abs() / a;
        let (mut da, mut db) = (0.0f64, 0.0f64);
        for &(a, sa, b, sb) in mid {
            da = da.max(rel(a, sa));
            db = db.max(rel(b, sb));
        }
        let a_mean = mid.iter().map(|p| p.0).sum::<f64>() / mid.len() as f64;
        println!(
            "(b) δ = {delta} mm: {} flank points, mean semi-major {a_mean:.3} mm: searched vs curvature semi-major ≤ {:.2} %, semi-minor ≤ {:.3} %",
            mid.len(),
            100.0 * da,
            100.0 * db
        );
        assert!(mid.len() >= 10);
        if let Some(l) = limit {
            assert!(da <= l && db <= l, "δ = {delta}: {da:.3e} / {db:.3e}");
        }
    }
}

#[test]
fn shared_ellipse_searches_give_the_fresh_results() {
    // `flank tca` runs with and without edge contact on one memo: the
    // second run must equal a fresh one bit for bit and search only the
    // contacts the first did not
    let s = seed000();
    let pair = gears(&s).pair.as_ref();
    let memo = EllipseMemo::default();
    let with = point_tca_shared(pair, &settings(true, 8, 0.00635), &memo).unwrap();
    let after_with = memo.len();
    let shared = point_tca_shared(pair, &settings(false, 8, 0.00635), &memo).unwrap();
    let fresh = point_tca(pair, &settings(false, 8, 0.00635)).unwrap();
    let searched = |t: &PointTca| {
        t.positions
            .iter()
            .flat_map(|p| p.pairs.iter().filter_map(|c| c.searched_ellipse))
            .collect::<Vec<_>>()
    };
    let (a, b) = (searched(&shared), searched(&fresh));
    assert!(a.len() >= 10, "{} searched contacts", a.len());
    assert_eq!(a, b, "a shared search differs from the fresh one");
    assert_eq!(shared.te_peak_to_peak_rad, fresh.te_peak_to_peak_rad);
    let added = memo.len() - after_with;
    println!(
        "with edges {} searches ({} positions), without edges {} added ({} searched contacts)",
        after_with,
        with.positions.len(),
        added,
        b.len()
    );
    assert!(
        added < after_with,
        "{added} new searches: nothing was shared"
    );
}

#[test]
fn edge_contacts_lie_on_the_tip_cone_and_touch_the_flank() {
    let s = seed000();
    let t = point_tca(gears(&s).pair.as_ref(), &settings(true, 0, 0.00635)).unwrap();
    let pair = gears(&s).pair.as_ref();
    let mut n = 0;
    let (mut cone, mut tangency) = (0.0f64, 0.0f64);
    for c in middle_contacts(&t) {
        let (b, edge) = match c.system {
            ContactSystem::PinionEdge(e) => (0, e),
            ContactSystem::GearEdge(e) => (1, e),
            ContactSystem::Flank => continue,
        };
        assert!(c.edge_lean > 0.0);
        tangency = tangency.max(c.residual[1]);
        if edge == Edge::Tip {
            let body = pair.body(b).as_any().downcast_ref::<BevelGear>().unwrap();
            let m = body.cones();
            // projection: (v − R_m, u) in the axial section; face cone u = h_a(v)
            let [f, u] = c.projection_mm[b];
            cone = cone.max((u - m.addendum(f + m.rm)).abs());
        }
        n += 1;
    }
    println!(
        "(c) seed 000 with edges: {n} edge contacts of the middle pair, |t·n| ≤ {tangency:.1e}, face-cone residual ≤ {cone:.1e} mm; transitions {:?}",
        t.transitions
            .iter()
            .map(|x| format!("{:.3}° {} → {}", x.roll_rad.to_degrees(), x.from, x.to))
            .collect::<Vec<_>>()
    );
    assert!(n >= 2, "{n} edge contacts");
    assert!(
        tangency <= 1e-10 && cone <= 1e-9,
        "{tangency:.2e} {cone:.2e}"
    );
}

#[test]
fn misalignment_moves_the_pattern() {
    let s = seed000();
    let st = settings(false, 0, 0.00635);
    let base = point_tca(gears(&s).pair.as_ref(), &st).unwrap();
    let same = point_tca(
        &gears(&s).pair.with_misalignment(Misalignment::default()),
        &st,
    )
    .unwrap();
    assert_eq!(base, same);
    let at_zero = |t: &PointTca| {
        let p = t
            .positions
            .iter()
            .find(|p| p.roll_rad.abs() < 1e-12)
            .unwrap();
        p.pairs
            .iter()
            .find(|c| c.offset == 0)
            .unwrap()
            .projection_mm[1]
    };
    let p0 = at_zero(&base);
    for (name, m) in [
        (
            "ΔE = +0.1 mm",
            Misalignment {
                offset_error_mm: 0.1,
                ..Default::default()
            },
        ),
        (
            "ΔP = +0.1 mm",
            Misalignment {
                pinion_axial_mm: 0.1,
                ..Default::default()
            },
        ),
        (
            "ΔG = +0.1 mm",
            Misalignment {
                gear_axial_mm: 0.1,
                ..Default::default()
            },
        ),
        (
            "ΔΣ = 0.05°",
            Misalignment {
                shaft_angle_error_rad: 0.05f64.to_radians(),
                ..Default::default()
            },
        ),
    ] {
        let t = point_tca(&gears(&s).pair.with_misalignment(m), &st).unwrap();
        let p = at_zero(&t);
        let moved = (p[0] - p0[0]).hypot(p[1] - p0[1]);
        println!(
            "(d) {name}: mean contact on the gear moves {moved:.3} mm (face {:+.3}, profile {:+.3}), TE p-p {:.3} arcsec (aligned {:.3})",
            p[0] - p0[0],
            p[1] - p0[1],
            t.te_peak_to_peak_rad.to_degrees() * 3600.0,
            base.te_peak_to_peak_rad.to_degrees() * 3600.0
        );
        assert!(moved > 1e-3, "{name}: the pattern did not move");
    }
}

#[test]
fn bad_input_is_refused_with_the_reason() {
    let s = seed000();
    for (st, what) in [
        (settings(true, 0, 0.0), "approach"),
        (settings(true, 0, -1e-3), "approach"),
        (settings(true, 2, 0.00635), "search_directions"),
        (
            PointTcaSettings {
                positions_per_pitch: 2,
                ..Default::default()
            },
            "positions_per_pitch",
        ),
    ] {
        let e = point_tca(gears(&s).pair.as_ref(), &st)
            .unwrap_err()
            .to_string();
        assert!(e.contains(what), "{e}");
    }
    // a gear of the pinion's hand: the seed 000 gear mirrored (the pinion
    // hand flipped in the scene cuts the mirror pair; its gear put in the
    // original assembly does not mesh)
    let mirror = seed000_with("", "plain.toml");
    let text = std::fs::read_to_string(papers().join("seed000-hypoid/scene.toml"))
        .unwrap()
        .replace("pinion_hand = \"left\"", "pinion_hand = \"right\"");
    let p = std::env::temp_dir().join(format!(
        "flank_hypoid_tca_mirror_{}.toml",
        std::process::id()
    ));
    std::fs::write(&p, text).unwrap();
    let right = bevel(&p);
    let wrong = BevelPair::new(
        [
            gears(&mirror).bodies[0].clone(),
            gears(&right).bodies[1].clone(),
        ],
        *gears(&mirror).pair.pair_assembly(),
    );
    let e = wrong.unwrap_err().to_string();
    println!("(e) same-hand pair: {e}");
    assert!(e.contains("does not mesh"), "{e}");
}
