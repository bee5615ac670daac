//! Seed 004's Tables 1 and 3 in flank: the 21/37 helical pair (m_n 15 mm,
//! β 20°, b 180 mm).
//!
//! * Table 1 form: tangential surface velocities of both flanks and their
//!   difference (the sliding velocity, seed 004 §2.2) at −10, −5, 0, 5 and
//!   10 mm from the pitch point along the path of contact, at mid face
//!   width, 3000 rpm (unloaded TCA).
//! * Table 3 form: load per unit length of contact line along the path of
//!   contact (normalised 0 = start of meshing … 1 = end) for the middle tooth
//!   pair, at 5000 and 8000 N·m (LTCA, compliance tensors of both bodies):
//!   the mean over the pair's contact line (its force / its length) and the
//!   peak of the distribution along it.
//!
//! Run (writes papers/seed004-helical/results/):
//! `cargo run --release --example seed004_tables -- [FLANK_MM BASE_MM [half-space|none]]`

use std::fmt::Write;
use std::path::Path;

use flank::compliance::body::BodyMeshOptions;
use flank::ltca::cycle::{LtcaCycle, LtcaOptions};
use flank::scene::read_scene;

fn main() -> anyhow::Result<()> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("papers/seed004-helical");
    let out = root.join("results");
    std::fs::create_dir_all(&out)?;
    let words: Vec<String> = std::env::args().skip(1).collect();
    let local = match words.get(2).map(String::as_str) {
        None | Some("half-space") => flank::settings::LocalModel::HalfSpace,
        Some("none") => flank::settings::LocalModel::None,
        Some(o) => anyhow::bail!("local model {o}: half-space or none"),
    };
    let args: Vec<f64> = words
        .iter()
        .take(2)
        .map(|a| a.parse())
        .collect::<Result<_, _>>()?;
    let (flank_mm, base_mm) = match args.as_slice() {
        [] => (1.875, 7.5),
        [f, b] => (*f, *b),
        _ => anyhow::bail!("usage: seed004_tables [FLANK_MM BASE_MM [half-space|none]]"),
    };
    let mut scene = read_scene(&root.join("scene.toml"))?;
    let options = LtcaOptions {
        // decks and tensors (large) go to target/, not into the paper folder
        out: Path::new(env!("CARGO_MANIFEST_DIR")).join("target/seed004_bodies"),
        mesh: BodyMeshOptions {
            flank_size: Some(flank_mm),
            base_size: Some(base_mm),
            ..Default::default()
        },
        points_per_line: Some(40),
        local: Some(local),
        // block low-rank tensors built panel by panel from the factor:
        // within 1e-6 of the dense ones per block, LTCA answers within
        // ≈ 1e-7, and no dense 15 k × 15 k matrix (README)
        compression: Some(flank::settings::Compression::Blr(1e-6)),
        quiet: true,
        ..Default::default()
    };
    let t = std::time::Instant::now();
    let cycle = LtcaCycle::new(&scene, &options)?;
    eprintln!(
        "compliance tensors: {:?} flank nodes, {:.1} s",
        cycle.setup.flank_nodes,
        t.elapsed().as_secs_f64()
    );
    let kin = &flank::geometry::cylindrical::MeshKinematics::new(
        &scene.cylindrical("this test").unwrap().pair,
        cycle.pair.sector_teeth(),
    )?;
    let k = kin.middle;
    // the contact line of pair k runs s(z) = s0(roll) + slope·z across the
    // face (s the transverse position on the line of action, slope
    // −r_b1 dφ/dz of the pinion's helix): the roll at which it crosses
    // mid face at s
    let mid_face = 0.5 * kin.face_width[0];
    let twist = flank::geometry::rack::ToothProfile::new(
        &scene.cylindrical("this test").unwrap().pair.pinion,
        "pinion",
    )?
    .twist_rate;
    let slope = -kin.base_radius[0] * twist;
    let roll_at = |s: f64| -> anyhow::Result<f64> { Ok(kin.roll_at(k, s - slope * mid_face)) };
    // a dense TCA for the velocities at mid face
    let mut dense = cycle.line_tca()?.settings().clone();
    dense.points_per_line = 2001;
    let tca = cycle.line_tca()?.with_settings(dense)?;
    let s_pitch = kin.base_radius[0] * kin.working_pressure_angle.tan();
    // Table 1
    let paper1 = [
        (-10.0, 12.5, 8.2, 4.3),
        (-5.0, 11.8, 9.1, 2.7),
        (0.0, 10.0, 10.0, 0.0),
        (5.0, 8.5, 11.2, 2.7),
        (10.0, 7.1, 12.4, 5.3),
    ];
    let mut t1 = String::from("distance_from_pitch_point_mm,v_t1_m_s,v_t2_m_s,sliding_m_s,paper_v_t1,paper_v_t2,paper_sliding\n");
    let mut md = String::new();
    let _ = writeln!(
        md,
        "## Table 1 form: velocities along the path of contact (3000 rpm, mid face width)\n"
    );
    let _ = writeln!(md, "| distance from C (mm) | v_t1 (m/s) | v_t2 (m/s) | v_s = v_t1 − v_t2 (m/s) | paper v_t1 | paper v_t2 | paper v_s |");
    let _ = writeln!(md, "|---:|---:|---:|---:|---:|---:|---:|");
    for &(d, a, b, c) in &paper1 {
        let roll = roll_at(s_pitch + d)?;
        let p = tca.position(roll)?;
        let line = p
            .lines
            .iter()
            .find(|l| l.pinion_tooth == k && l.kind == flank::tca::LineKind::Flank)
            .expect("middle pair");
        let q = line
            .points
            .iter()
            .min_by(|a, b| {
                (a.position[2] - mid_face)
                    .abs()
                    .total_cmp(&(b.position[2] - mid_face).abs())
            })
            .expect("points");
        let v1 = 0.5 * (q.sum_velocity + q.sliding_velocity);
        let v2 = 0.5 * (q.sum_velocity - q.sliding_velocity);
        let _ = writeln!(t1, "{d},{v1},{v2},{},{a},{b},{c}", q.sliding_velocity);
        let _ = writeln!(
            md,
            "| {d:+.0} | {v1:.2} | {v2:.2} | {:+.2} | {a} | {b} | {c} |",
            q.sliding_velocity
        );
    }
    std::fs::write(out.join("table1_sliding_velocity.csv"), t1)?;
    // Table 3
    let paper3 = [
        1282.5, 1195.0, 1130.0, 1075.0, 1035.0, 1000.0, 1040.0, 1090.0, 1155.0, 1230.0, 1325.0,
    ];
    let mut t3 = String::from("path_position,torque_nm,roll_deg,mean_n_per_mm,peak_n_per_mm,pair_force_n,line_length_mm,share,te_urad,kkt,paper_5000nm_n_per_mm\n");
    let _ = writeln!(md, "\n## Table 3 form: load per unit length of the middle pair's contact line along the path of contact\n");
    let _ = writeln!(md, "| path position | 5000 N·m mean (N/mm) | 5000 N·m peak | 8000 N·m mean | 8000 N·m peak | paper (5000 N·m) |");
    let _ = writeln!(md, "|---:|---:|---:|---:|---:|---:|");
    let (ps, pe) = (kin.path_start, kin.path_end);
    let mut rows = vec![String::new(); 11];
    for torque_nm in [5000.0, 8000.0] {
        scene.load.torque_nmm = torque_nm * 1e3;
        let mut c = cycle.with_points_per_line(40)?;
        c.torque = scene.load.torque_nmm;
        for (i, row) in rows.iter_mut().enumerate() {
            let x = i as f64 / 10.0;
            // stay 0.5 % inside the path so the pair is on its flank
            let s = ps + (0.005 + 0.99 * x) * (pe - ps);
            let roll = roll_at(s)?;
            let r = c.solve(roll.to_degrees())?;
            let li = r
                .lines
                .iter()
                .position(|(p, _, kind)| *p == k && kind == "Flank")
                .expect("middle pair line");
            let length = c.line_tca()?.position(roll)?.lines[li].length_mm;
            let force = r.line_force_n[li];
            let peak = r
                .points
                .iter()
                .filter(|p| p.line == li)
                .map(|p| p.load_per_length)
                .fold(0.0, f64::max);
            let _ = writeln!(
                t3,
                "{x},{torque_nm},{},{},{peak},{force},{length},{},{},{:e},{}",
                roll.to_degrees(),
                force / length,
                r.line_share[li],
                r.te_urad,
                r.kkt_max,
                paper3[i]
            );
            if torque_nm == 5000.0 {
                let _ = write!(row, "| {x:.1} | {:.1} | {peak:.1} ", force / length);
            } else {
                let _ = write!(row, "| {:.1} | {peak:.1} | {} |", force / length, paper3[i]);
            }
        }
    }
    for r in rows {
        let _ = writeln!(md, "{r}");
    }
    let _ = writeln!(
        md,
        "\nCompliance mesh: flank {flank_mm} mm, base {base_mm} mm, K = 40, local model {}; flank nodes {:?}.",
        cycle.settings.local.name(),
        cycle.setup.flank_nodes
    );
    std::fs::write(out.join("table3_load_per_length.csv"), t3)?;
    std::fs::write(out.join("tables.md"), &md)?;
    println!("{md}");
    Ok(())
}
