//! # One hypoid mesh position in flank and in CalculiX
//!
//! Issue 18 point 6 (see README.md beside this file). The seed 003 pair
//! with the eased pinion (`papers/seed003-hypoid/scene_eased.toml`) as
//! `flank run` builds it (`MeshCycle`: both bevel sectors, pinion mount
//! coupled to a reference node turning about the pinion axis under the
//! torque, gear mount clamped, pinion drive flanks slave), with a LINEAR
//! penalty of flank's automatic slope, at roll 0 (the middle pair at the
//! mean point, its neighbours sharing the load). `MeshCycle::write_deck`
//! writes the position as a deck in the pinion's own frame (the gear
//! moved to its place). The same deck is solved
//!
//! * by flank: read back and solved by the plain `solve_contact` (no
//!   placement) — against `MeshCycle::solve` at that roll: the deck is the
//!   position's problem (test `deck_is_the_position`, in CI);
//! * by CalculiX 2.20, two steps as in `verification/gear_contact/ccx.rs`
//!   (the pinion turned by 0.8 × flank's rotation first, then released
//!   under the torque; frictionless and linear, the second step's answer
//!   does not depend on the first): force per tooth pair (CSTR × flank's
//!   tributary area of the slave node), total force, TE, and the total
//!   contact force as a vector without areas: ccx's reaction at the
//!   clamped gear mount (`RF`, `TOTALS=ONLY`) against flank's Σ λ n (test
//!   `position_flank_vs_ccx`, ignored: ccx takes minutes).
//!
//! Diagnostics (README, "Load scan"): `HYPOID_CCX_TORQUE_FACTOR` and
//! `HYPOID_CCX_PENALTY_FACTOR` scale the scene's torque and flank's
//! penalty slope (both codes) for that test; default 1.
//!
//! Tolerances, fixed before the first run: deck vs cycle 1e-8 (per-pair
//! force relative to the total, TE relative); flank vs ccx those of
//! `gear_contact_ccx` (from hertz_contact): total force 1e-3, each pair's
//! force 1e-3 of the total, TE 1e-3.

#[path = "../common/mod.rs"]
mod common;

use std::path::Path;
use std::time::Instant;

use flank::contact::{solve_contact, ContactOptions, PressureOverclosure};
use flank::mesh::bevel_sector::BevelSectorOptions;
use flank::mesh_cycle::cycle::{MeshCycle, RunSettings, StepResult};
use flank::mesh_cycle::pair_model::bevel_pair_model;
use flank::scene::read_scene;
use flank::settings::ContactLaw;
use flank::tca::point_contact::ARCSEC_PER_RAD;

const TOL_SAME_CODE: f64 = 1e-8;
const TOL_FORCE: f64 = 1e-3;
const TOL_TE: f64 = 1e-3;
/// ccx's σ∞ (MPa) and c₀ on the LINEAR law, as in gear_contact_ccx.
const TENSION: f64 = 0.01;
const C0: f64 = 0.3;
const ROLL_DEG: f64 = 0.0;

fn cycle(flank_size: f64) -> MeshCycle {
    let path = format!(
        "{}/papers/seed003-hypoid/scene_eased.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    let mut scene = read_scene(Path::new(&path)).unwrap();
    scene.load.torque_nmm *= std::env::var("HYPOID_CCX_TORQUE_FACTOR")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(1.0);
    let mesh = BevelSectorOptions {
        flank_size,
        base_size: 4.0 * flank_size,
        ..Default::default()
    };
    let settings = RunSettings {
        law: ContactLaw::Penalty,
        penalty_factor: std::env::var("HYPOID_CCX_PENALTY_FACTOR")
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or(1.0),
        ..RunSettings::default_for(&scene)
    };
    MeshCycle::of_pair(
        &scene,
        bevel_pair_model(&scene, &mesh).unwrap(),
        settings,
        2,
    )
    .unwrap()
}

/// TE at the gear (arcsec) from the pinion's rotation about its axis, as
/// `MeshCycle::solve` reports it.
fn te_of(c: &MeshCycle, rz: f64) -> f64 {
    let sense = c.gear_pair.rotation_axes()[0][2].signum();
    -rz * sense * c.gear_pair.ratio() * ARCSEC_PER_RAD
}

/// flank's answer on the deck read back: per-pair forces, pinion rotation,
/// the slave results (node label, pair, tributary area, λ/A).
struct DeckAnswer {
    forces: Vec<f64>,
    /// Σ λ n over the slave nodes: the contact force on the master (gear)
    /// side as a vector, no areas involved.
    force_vector: [f64; 3],
    rz: f64,
    slaves: Vec<(u64, usize, f64, f64)>,
    seconds: f64,
}

fn deck_answer(deck: &Path) -> DeckAnswer {
    let t = Instant::now();
    let parsed = flank::deck::read_deck(deck).expect("read the deck back");
    let options = ContactOptions {
        recover_stress: false,
        pairing: flank::contact::pairing::PairingOptions {
            search_distance: Some(0.1),
            max_initial_penetration: None,
        },
        ..Default::default()
    };
    let plain = solve_contact(&parsed.model, &options).expect("solve_contact on the deck");
    let labels = &parsed.model.mesh.node_labels;
    DeckAnswer {
        forces: plain
            .summary
            .pairs
            .iter()
            .map(|p| p.total_normal_force)
            .collect(),
        force_vector: plain.slaves.iter().fold([0.0; 3], |a, s| {
            [
                a[0] + s.force * s.normal[0],
                a[1] + s.force * s.normal[1],
                a[2] + s.force * s.normal[2],
            ]
        }),
        rz: plain.solution.coupling_motion[0][5],
        slaves: plain
            .slaves
            .iter()
            .map(|s| (labels[s.node], s.pair, s.area, s.nodal_pressure))
            .collect(),
        seconds: t.elapsed().as_secs_f64(),
    }
}

fn position(c: &MeshCycle, dir: &Path) -> (StepResult, DeckAnswer, std::path::PathBuf) {
    let step = c.solve(ROLL_DEG).unwrap().step;
    let deck = dir.join("roll_0.inp");
    c.write_deck(ROLL_DEG, &deck).unwrap();
    let answer = deck_answer(&deck);
    (step, answer, deck)
}

/// The written deck is this position's problem: solved plainly it gives
/// the cycle's forces and TE.
#[test]
fn deck_is_the_position() {
    let t = Instant::now();
    let c = cycle(2.0);
    let setup = t.elapsed().as_secs_f64();
    let dir = common::scratch_dir("hypoid_contact_deck");
    let (step, deck, _) = position(&c, &dir);
    let total: f64 = step.pair_force_n.iter().sum();
    let te_deck = te_of(&c, deck.rz);
    println!(
        "seed 003 eased, flank 2 mm, penalty: {} nodes; setup {setup:.1} s, cycle solve {:.2} s, deck read + solve {:.2} s",
        c.pair.model.mesh.node_count(),
        step.time_s,
        deck.seconds
    );
    println!(
        "cycle: forces {:?} N, TE {:.4}″; deck: forces {:?} N, TE {te_deck:.4}″",
        step.pair_force_n, step.te_arcsec, deck.forces
    );
    assert!(total > 0.0);
    let worst = step
        .pair_force_n
        .iter()
        .zip(&deck.forces)
        .map(|(a, b)| (a - b).abs() / total)
        .fold(0.0f64, f64::max);
    let te = (te_deck - step.te_arcsec).abs() / step.te_arcsec.abs();
    println!("VERIFY hypoid_contact_ccx deck vs cycle: forces {worst:.2e}, TE {te:.2e} (tol {TOL_SAME_CODE:.0e})");
    assert!(worst <= TOL_SAME_CODE, "{worst}");
    assert!(te <= TOL_SAME_CODE, "{te}");
}

/// flank against ccx at roll 0.
#[test]
#[ignore = "30-80 s of ccx; misses the force tolerance (1.5e-3 total, 2.1e-3 as reaction vectors, vs 1e-3), TE within 6e-4: a difference that grows with the load (README, load scan)"]
fn position_flank_vs_ccx() {
    let c = cycle(2.0);
    let dir = common::scratch_dir("hypoid_contact_ccx");
    let (step, deck, path) = position(&c, &dir);
    if !common::ccx_available() {
        return;
    }
    // the deck for ccx: the same model with ccx's σ∞ and c₀ on the law
    let mut model = c.deck_model(ROLL_DEG);
    let slope = match model.contact.interactions[0].behavior {
        Some(PressureOverclosure::Linear { slope: Some(s), .. }) => s,
        ref b => panic!("not an explicit penalty: {b:?}"),
    };
    model.contact.interactions[0].behavior = Some(PressureOverclosure::Linear {
        slope: Some(slope),
        tension: Some(TENSION),
        c0: Some(C0),
    });
    let written = flank::deck::format_deck(&model).expect("format_deck");
    let _ = path;
    let max = *c.pair.model.mesh.node_labels.iter().max().unwrap();
    let (r, q) = (max + 1, max + 2);
    assert!(written.contains(&format!(
        "*RIGID BODY, NSET=PINION_HUB, REF NODE={r}, ROT NODE={q}\n"
    )));
    let boundary =
        &written[written.find("*BOUNDARY\n").unwrap()..written.find("*CLOAD\n").unwrap()];
    // the clamped nodes (the gear's mount): their total reaction is the
    // whole contact force on the gear, as a vector
    let mut clamped: Vec<u64> = model
        .dirichlet
        .iter()
        .map(|d| model.mesh.node_labels[d.node])
        .collect();
    clamped.sort_unstable();
    clamped.dedup();
    let clamp = format!(
        "*NSET, NSET=GEAR_CLAMP\n{}\n",
        clamped
            .chunks(16)
            .map(|c| c.iter().map(u64::to_string).collect::<Vec<_>>().join(", "))
            .collect::<Vec<_>>()
            .join("\n")
    );
    let controls =
        "*STATIC\n*CONTROLS, PARAMETERS=TIME INCREMENTATION\n30, 30, 9, 200, 10, 4, 0, 5\n";
    let preload = format!(
        "{boundary}*BOUNDARY\n{q}, 3, 3, {}\n*END STEP\n*STEP\n{controls}{}*CLOAD\n",
        0.8 * deck.rz,
        boundary.replacen("*BOUNDARY\n", "*BOUNDARY, OP=NEW\n", 1)
    );
    let text = written
        .replacen(boundary, "", 1)
        .replace("*STATIC\n", controls)
        .replace(
            "*STEP\n",
            &format!("*NSET, NSET=PREF\n{r}, {q}\n{clamp}*STEP\n"),
        )
        .replace("*CLOAD\n", &preload)
        .replace(
            "*NODE PRINT, NSET=NALL\nU\n",
            "*NODE PRINT, NSET=PREF\nU\n*NODE PRINT, NSET=GEAR_CLAMP, TOTALS=ONLY\nRF\n",
        );
    assert_eq!(text.matches("*STEP\n").count(), 2);
    let ccx_path = dir.join("roll_0_ccx.inp");
    std::fs::write(&ccx_path, &text).unwrap();
    let run = flank::ccx::run_ccx(&ccx_path, &dir.join("ccx"), 2)
        .unwrap_or_else(|e| panic!("ccx did not solve the deck: {e}"));
    let dat = common::parse_ccx_dat(&std::fs::read_to_string(dir.join("ccx/job.dat")).unwrap());
    let rz_ccx = dat.u.get(&q).copied().expect("ccx printed the ROT NODE")[2];
    let mut forces_ccx = vec![0.0; deck.forces.len()];
    for &(label, pair, area, _) in &deck.slaves {
        if let Some(&p) = dat.cstr.get(&label) {
            forces_ccx[pair] += p.max(0.0) * area;
        }
    }
    let (fd, fc): (f64, f64) = (deck.forces.iter().sum(), forces_ccx.iter().sum());
    let (te_flank, te_ccx) = (te_of(&c, deck.rz), te_of(&c, rz_ccx));
    let max_pn_flank = deck.slaves.iter().map(|s| s.3).fold(0.0f64, f64::max);
    let max_pn_ccx = dat.cstr.values().fold(0.0f64, |a, &b| a.max(b));
    println!("| pair | flank cycle (N) | flank deck (N) | ccx (N) | flank − ccx (/ total) |");
    println!("|---|---|---|---|---|");
    for (k, (fd_k, fc_k)) in deck.forces.iter().zip(&forces_ccx).enumerate() {
        println!(
            "| {} | {:.3} | {fd_k:.3} | {fc_k:.3} | {:+.2e} |",
            k + 1,
            step.pair_force_n[k],
            (fd_k - fc_k) / fc
        );
    }
    println!(
        "total force flank {fd:.3} N, ccx {fc:.3} N; TE flank {te_flank:.4}″, ccx {te_ccx:.4}″; max λ/A flank {max_pn_flank:.1} MPa, max CSTR ccx {max_pn_ccx:.1} MPa; ccx {:.1} s",
        run.wall_s
    );
    // the benchmark side by side (issue 18): flank's factorization and
    // position against ccx's whole run on the same deck
    let st = &c.system.stats;
    println!(
        "flank: {} DOFs, nnz(L) {:.3e}, numeric factorization {:.2} GFLOP in {:.2} s ({:.1} GFLOP/s), this position {:.2} s; ccx: {:.1} s wall for the deck",
        st.dofs,
        st.nnz_factor as f64,
        st.flops / 1e9,
        st.factorization_s,
        st.flops / st.factorization_s.max(1e-9) / 1e9,
        step.time_s,
        run.wall_s
    );
    let mut misses = Vec::new();
    let mut check = |what: &str, err: f64, tol: f64| {
        let verdict = if err <= tol { "ok" } else { "MISS" };
        println!("VERIFY hypoid_contact_ccx {what:<32} {err:>9.2e}  tol {tol:>8.1e}  {verdict}");
        if err > tol {
            misses.push(format!("{what}: {err:.2e} > {tol:.1e}"));
        }
    };
    check("total force", (fd - fc).abs() / fc, TOL_FORCE);
    let worst = deck
        .forces
        .iter()
        .zip(&forces_ccx)
        .map(|(a, b)| (a - b).abs() / fc)
        .fold(0.0f64, f64::max);
    check("pair forces / total", worst, TOL_FORCE);
    check("TE", (te_flank - te_ccx).abs() / te_ccx.abs(), TOL_TE);
    // the total force without areas: ccx's reaction at the clamped gear
    // mount against flank's Σ λ n (n the gear's outward normal: the
    // contact pushes the gear by −Σ λ n, the clamp holds it by +Σ λ n)
    let rf = dat
        .total_force
        .expect("ccx printed the clamp's total force");
    let fv = deck.force_vector;
    let norm = |v: [f64; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    let diff = norm([rf[0] - fv[0], rf[1] - fv[1], rf[2] - fv[2]]) / norm(rf);
    println!(
        "gear clamp reaction: flank Σλn ({:.3}, {:.3}, {:.3}) N, |{:.3}|; ccx RF ({:.3}, {:.3}, {:.3}) N, |{:.3}|",
        fv[0], fv[1], fv[2], norm(fv), rf[0], rf[1], rf[2], norm(rf)
    );
    check("force vector (reaction)", diff, TOL_FORCE);
    assert!(misses.is_empty(), "{misses:?}");
}
