//! # Verification: the stiff-and-extreme suite (issue 22, point 3)
//!
//! ## What
//!
//! Coarse spur scenes pushed to the edges the issue names — E ratio 70
//! and 10⁴ between the members, ν = 0.4999, torque 10⁻⁴× and 100×
//! nominal, penalty 10⁻³× and 10⁶× the default, element aspect ratio
//! 1 000, module 0.3 mm and 25 mm, a 6-tooth pinion against a 200-tooth
//! gear, 100 µm of lead crowning — each through FE contact (`flank run`'s
//! model at one roll angle) and through the LTCA (`flank ltca`: compliance
//! tensors, TCA, contact QP). Every row must be either an answer whose
//! residuals are within the limits below, or a clear error (a
//! `FlankError` whose message says why, asserted here by a fragment).
//!
//! ## Limits (fixed before the first run; README.md)
//!
//! FE contact, per position:
//! * backward error of the final sparse solve ≤ 1e-10 (flank refuses
//!   above it, `contact::solve`);
//! * equilibrium of the floating pinion ‖Dᵀλ − r‖/‖r‖ ≤ 1e-8;
//! * contact-law violation ≤ 1e-6 of the loaded approach δ = TE·r_b1;
//! * complementarity max |λᵢgᵢ| ≤ 1e-8 of F·δ (F = Σλ);
//! * condition estimate κ₁ ≤ 1e12 (κ·u ≤ 1e-4; above it flank writes a
//!   note to summary.json) — of the diagonally scaled K₀ since the second
//!   round (README: the error of a Cholesky solve depends on that one).
//!
//! LTCA, per position:
//! * relative KKT residual (stationarity, equilibrium rᵀp = T,
//!   feasibility, complementarity) ≤ 1e-9 (`qp::Kkt`, the solver's own);
//! * backward error of each body's compliance probe solve ≤ 1e-10 (flank
//!   refuses above it, `compliance::tensor`);
//! * κ₂(F) ≤ 1e12.
//!
//! Run: `cargo test --release --test extreme -- --nocapture` (CI part);
//! `-- --ignored --nocapture` for the reference row.

use std::path::{Path, PathBuf};
use std::time::Instant;

use flank::compliance::body::BodyMeshOptions;
use flank::ltca::cycle::{LtcaCycle, LtcaOptions};
use flank::mesh_cycle::cycle::MeshCycle;
use flank::mesh_cycle::run::{settings, RunOptions};
use flank::scene::{parse_scene, Scene};
use flank::settings::ContactLaw;

// ---- limits (README.md, fixed before the first run) ----
const FE_BACKWARD: f64 = 1e-10;
const FE_EQUILIBRIUM: f64 = 1e-8;
const FE_VIOLATION: f64 = 1e-6;
const FE_COMPLEMENTARITY: f64 = 1e-8;
const CONDITION: f64 = 1e12;
const LTCA_KKT: f64 = 1e-9;
const LTCA_BACKWARD: f64 = 1e-10;

/// One spur scene of the suite: seed 002's pair (z 13/35, m 3.8 mm,
/// b 13.3 mm, 312 N·m) with the keys a case changes.
#[derive(Clone, Debug)]
struct Pair {
    z: [u32; 2],
    module: f64,
    shift: [f64; 2],
    /// Tip and bore diameters, centre distance (mm); `None`: the default
    /// tip, bore 0.45 (pinion) / 0.8 (gear) of the pitch diameter and the
    /// standard centre distance (x₁ + x₂ = 0).
    tip: [Option<f64>; 2],
    bore: [Option<f64>; 2],
    centre: Option<f64>,
    face: f64,
    young: [f64; 2],
    poisson: [f64; 2],
    torque_nm: f64,
    lead_crowning_um: f64,
    element: &'static str,
    flank_size: f64,
    base_size: f64,
}

impl Pair {
    fn seed002() -> Pair {
        Pair {
            z: [13, 35],
            module: 3.8,
            shift: [0.30, -0.59931744],
            tip: [Some(58.7), Some(135.5)],
            bore: [Some(20.0), Some(80.0)],
            centre: Some(90.0),
            face: 13.3,
            young: [206000.0; 2],
            poisson: [0.3; 2],
            torque_nm: 312.0,
            lead_crowning_um: 0.0,
            element: "wedge15",
            flank_size: 1.0,
            base_size: 2.0,
        }
    }

    /// Every length × s, the torque × s³: the same stresses, strains and
    /// rotations (TE in µrad) in linear elasticity.
    fn scaled(&self, s: f64) -> Pair {
        let m = |v: Option<f64>| v.map(|x| x * s);
        Pair {
            module: self.module * s,
            tip: self.tip.map(m),
            bore: self.bore.map(m),
            centre: m(self.centre),
            face: self.face * s,
            torque_nm: self.torque_nm * s * s * s,
            flank_size: self.flank_size * s,
            base_size: self.base_size * s,
            ..self.clone()
        }
    }

    fn toml(&self) -> String {
        let d = |k: usize| self.z[k] as f64 * self.module;
        let a = self
            .centre
            .unwrap_or(0.5 * self.module * (self.z[0] + self.z[1]) as f64);
        let member = |k: usize| {
            let mut s = format!(
                "teeth = {}\nnormal_module_mm = {}\nnormal_pressure_angle_deg = 20.0\nface_width_mm = {}\nprofile_shift = {}\nbore_diameter_mm = {}\nmaterial = \"m{k}\"\n",
                self.z[k],
                self.module,
                self.face,
                self.shift[k],
                self.bore[k].unwrap_or(d(k) * if k == 0 { 0.45 } else { 0.8 }),
            );
            if let Some(t) = self.tip[k] {
                s += &format!("tip_diameter_mm = {t}\n");
            }
            s
        };
        let mut t = format!(
            "[pair]\nkind = \"spur\"\ncentre_distance_mm = {a}\n\n[pinion]\n{}",
            member(0)
        );
        if self.lead_crowning_um > 0.0 {
            t += &format!(
                "\n[pinion.micro]\nlead_crowning_um = {}\n",
                self.lead_crowning_um
            );
        }
        t += &format!("\n[gear]\n{}", member(1));
        for k in 0..2 {
            t += &format!(
                "\n[materials.m{k}]\nyoung_modulus_mpa = {}\npoisson_ratio = {}\n",
                self.young[k], self.poisson[k]
            );
        }
        t += &format!(
            "\n[load]\ntorque_nm = {}\nspeed_rpm = 11758.0\n\n[analyses]\nmesh = {{}}\ncontact = {{}}\nltca = {{}}\n\n[mesh]\nteeth_in_sector = 3\nelement = \"{}\"\nflank_size_mm = {}\nbase_size_mm = {}\n",
            self.torque_nm, self.element, self.flank_size, self.base_size
        );
        t
    }
}

/// The FE contact law of a row.
#[derive(Clone, Copy, Debug)]
enum Fe {
    Hard,
    Penalty(f64),
}

/// The figures of one answer (both paths; FE-only fields NaN for LTCA).
#[derive(Clone, Debug, Default)]
struct Figures {
    te_urad: f64,
    shares: Vec<f64>,
    iterations: usize,
    /// FE: backward error; LTCA: the larger of the two tensor probes.
    backward: f64,
    equilibrium: f64,
    violation: f64,
    complementarity: f64,
    kkt: f64,
    /// FE: κ₁ of the diagonally scaled K₀; LTCA: κ₂ of F over every
    /// candidate (the limited figure).
    condition: f64,
    /// FE: κ₁ of K₀ unscaled; LTCA: κ₂ of F on the loaded points
    /// (reported beside it, README.md).
    other_condition: f64,
    /// LTCA: corner-contact extension finally used (mm).
    extension_mm: f64,
    max_pressure_mpa: f64,
    notes: Vec<String>,
}

fn work(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("extreme")
        .join(name);
    // tensors are read back from `out` when present: start clean so each
    // run computes (and checks) them
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn scene_of(p: &Pair, name: &str) -> Result<Scene, String> {
    let dir = work(&format!("{name}/scene"));
    let path = dir.join("scene.toml");
    let text = p.toml();
    std::fs::write(&path, &text).unwrap();
    parse_scene(&text, &path).map_err(|e| e.to_string())
}

fn mesh_of(p: &Pair) -> BodyMeshOptions {
    BodyMeshOptions {
        flank_size: Some(p.flank_size),
        base_size: Some(p.base_size),
        ..Default::default()
    }
}

/// Mid single contact (or mid engagement of the middle pair if the pair
/// has no single contact).
fn roll_deg(scene: &Scene) -> Result<f64, String> {
    let gp = scene.gear_pair().map_err(|e| e.to_string())?;
    let (l, h) = gp.single_contact();
    if h > l {
        Ok(0.5 * (l + h).to_degrees())
    } else {
        let (a, e) = gp.engagement(gp.middle());
        Ok(0.5 * (a + e).to_degrees())
    }
}

fn fe(p: &Pair, scene: &Scene, law: Fe, name: &str) -> Result<Figures, String> {
    let (law, factor) = match law {
        Fe::Hard => (ContactLaw::Hard, None),
        Fe::Penalty(f) => (ContactLaw::Penalty, Some(f)),
    };
    let roll = roll_deg(scene)?;
    let o = RunOptions {
        out: work(&format!("{name}/fe")),
        roll_angles_deg: Some(vec![roll]),
        law: Some(law),
        penalty_factor: factor,
        vtu: Some(false),
        refine_contact_limits: Some(false),
        quiet: true,
        ..Default::default()
    };
    let s = settings(scene, &o).map_err(|e| e.to_string())?;
    let c = MeshCycle::new(scene, &mesh_of(p), s, 0).map_err(|e| e.to_string())?;
    let r = c.solve(roll).map_err(|e| e.to_string())?.step;
    println!(
        "COST {name}: factorization {:.2} s, both κ estimates {:.2} s, one position {:.2} s ({} DOFs)",
        c.system.stats.factorization_s,
        c.system.stats.condition_s,
        r.time_s,
        c.system.stats.dofs
    );
    let total: f64 = r.pair_force_n.iter().sum();
    let delta = (r.te_um.unwrap_or(f64::NAN) * 1e-3).abs();
    Ok(Figures {
        te_urad: r.te_urad,
        shares: r.load_share.clone(),
        iterations: r.active_set_iterations,
        backward: r.backward_error,
        equilibrium: r.equilibrium,
        violation: r.max_violation_mm / delta,
        complementarity: r.complementarity / (total * delta),
        kkt: f64::NAN,
        condition: c.system.stats.scaled_condition_estimate,
        other_condition: c.system.stats.condition_estimate,
        extension_mm: f64::NAN,
        max_pressure_mpa: r.max_pressure_mpa.iter().fold(0.0, |a: f64, &b| a.max(b)),
        notes: r.warnings.clone(),
    })
}

fn ltca(p: &Pair, scene: &Scene, name: &str) -> Result<Figures, String> {
    let roll = roll_deg(scene)?;
    let o = LtcaOptions {
        out: work(&format!("{name}/ltca")),
        mesh: mesh_of(p),
        condition: true,
        quiet: true,
        // K override for the corner-point diagnosis (README): EXTREME_K=10
        points_per_line: std::env::var("EXTREME_K").ok().and_then(|k| k.parse().ok()),
        ..Default::default()
    };
    let c = LtcaCycle::new(scene, &o).map_err(|e| e.to_string())?;
    let r = c.solve(roll).map_err(|e| e.to_string())?;
    let f = c.pair_forces(&r);
    let t: f64 = f.iter().sum();
    Ok(Figures {
        te_urad: r.te_urad,
        shares: f.iter().map(|x| x / t).collect(),
        iterations: r.qp_iterations,
        backward: c
            .setup
            .backward_error
            .iter()
            .map(|b| b.unwrap_or(f64::NAN))
            .fold(0.0, f64::max),
        equilibrium: f64::NAN,
        violation: f64::NAN,
        complementarity: f64::NAN,
        kkt: r.kkt_max,
        condition: r.condition.unwrap_or(f64::NAN),
        other_condition: r.condition_loaded.unwrap_or(f64::NAN),
        extension_mm: r.corner_extension_mm,
        max_pressure_mpa: r.max_pressure_mpa,
        notes: r
            .warnings
            .iter()
            .cloned()
            .chain((!r.kkt_within_tolerance).then(|| "KKT flagged".to_string()))
            .collect(),
    })
}

/// Which primary limits an answer misses (one text each); empty:
/// within all.
fn misses(f: &Figures, path: &str) -> Vec<String> {
    let mut m = Vec::new();
    let mut lim = |what: &str, v: f64, l: f64| {
        if v.is_nan() || v > l {
            m.push(format!("{what} {v:.2e} > {l:.0e}"));
        }
    };
    if path == "FE" {
        lim("backward error", f.backward, FE_BACKWARD);
        lim("equilibrium", f.equilibrium, FE_EQUILIBRIUM);
        lim("violation/δ", f.violation, FE_VIOLATION);
        lim(
            "complementarity/(Fδ)",
            f.complementarity,
            FE_COMPLEMENTARITY,
        );
    } else {
        lim("KKT", f.kkt, LTCA_KKT);
        // NaN: both tensors read from the cache (checked when computed)
        if !f.backward.is_nan() {
            lim("tensor backward error", f.backward, LTCA_BACKWARD);
        }
    }
    lim("condition", f.condition, CONDITION);
    if !f.te_urad.is_finite() || f.shares.iter().any(|s| !s.is_finite()) {
        m.push("non-finite answer".into());
    }
    m
}

/// One row of the table: a path's answer or error.
struct Row {
    name: String,
    path: &'static str,
    result: Result<Figures, String>,
}

impl Row {
    fn answer(&self) -> &Figures {
        match &self.result {
            Ok(f) => f,
            Err(e) => panic!("{} {}: unexpected error: {e}", self.name, self.path),
        }
    }

    /// Within every primary limit (the second round has no exceptions).
    fn within(&self) -> &Self {
        let m = misses(self.answer(), self.path);
        assert!(
            m.is_empty(),
            "{} {}: {}",
            self.name,
            self.path,
            m.join(", ")
        );
        self
    }

    fn flagged(&self, fragment: &str) -> &Self {
        let f = self.answer();
        assert!(
            f.notes.iter().any(|n| n.contains(fragment)),
            "{} {}: no warning `{fragment}` in {:?}",
            self.name,
            self.path,
            f.notes
        );
        self
    }

    /// Within every primary limit but κ₂(F) over the candidates, which may
    /// miss only if flank says so ([`UNRESOLVED`]; third round, README).
    fn within_or_unresolved(&self) -> &Self {
        let f = self.answer();
        let m = misses(f, self.path);
        let (condition, other): (Vec<_>, Vec<_>) =
            m.iter().partition(|t| t.starts_with("condition"));
        assert!(
            other.is_empty(),
            "{} {}: {}",
            self.name,
            self.path,
            m.join(", ")
        );
        if !condition.is_empty() {
            self.flagged(UNRESOLVED);
        }
        self
    }

    fn not_flagged(&self, fragment: &str) -> &Self {
        let f = self.answer();
        assert!(
            !f.notes.iter().any(|n| n.contains(fragment)),
            "{} {}: unexpected warning {:?}",
            self.name,
            self.path,
            f.notes
        );
        self
    }

    fn error(&self, fragment: &str) {
        match &self.result {
            Err(e) => assert!(e.contains(fragment), "{} {}: {e}", self.name, self.path),
            Ok(_) => panic!(
                "{} {}: expected `{fragment}`, got an answer",
                self.name, self.path
            ),
        }
    }
}

/// Runs `name` through the paths asked for (FE with `law`, LTCA if `ltca`)
/// and prints each row (`ROW | …`, the README table's figures).
fn run_case(name: &str, p: &Pair, law: Option<Fe>, ltca_too: bool) -> Vec<Row> {
    let mut rows = Vec::new();
    let mut paths = Vec::new();
    if law.is_some() {
        paths.push("FE");
    }
    if ltca_too {
        paths.push("LTCA");
    }
    for path in paths {
        let t = Instant::now();
        let result = scene_of(p, name).and_then(|s| {
            if path == "FE" {
                fe(p, &s, law.unwrap_or(Fe::Hard), name)
            } else {
                ltca(p, &s, name)
            }
        });
        let secs = t.elapsed().as_secs_f64();
        match &result {
            Ok(f) => {
                let m = misses(f, path);
                println!(
                    "ROW | {name} | {path} | TE {:.1} µrad, shares {:.3?}, p_max {:.0} MPa | it {} | bwd {:.1e} | eq {:.1e} | viol {:.1e} | compl {:.1e} | KKT {:.1e} | κ {:.1e} (other {:.1e}) | ext {:.3} mm | {secs:.1} s | {} | notes {:?}",
                    f.te_urad, f.shares, f.max_pressure_mpa, f.iterations, f.backward, f.equilibrium, f.violation, f.complementarity, f.kkt, f.condition, f.other_condition, f.extension_mm,
                    if m.is_empty() { "pass".to_string() } else { format!("MISS: {}", m.join(", ")) },
                    f.notes
                );
            }
            Err(e) => println!("ROW | {name} | {path} | error: {e} | {secs:.1} s"),
        }
        rows.push(Row {
            name: name.to_string(),
            path,
            result,
        });
    }
    rows
}

const LARGE: &str = "small-displacement (linear) model";
const SINGULAR: &str = "the compliance F is singular on the";
const UNRESOLVED: &str = flank::ltca::model::UNRESOLVED_CANDIDATES;

// ---------------------------------------------------------------- cases

#[test]
fn nominal() {
    let r = run_case("nominal", &Pair::seed002(), Some(Fe::Hard), true);
    r[0].within().not_flagged(LARGE);
    r[1].within().not_flagged(LARGE);
}

/// A polymer gear at the steel pair's torque turns the pinion by 0.1 rad:
/// the answer meets its residuals and carries the large-rotation warning.
#[test]
fn e_ratio_70_steel_on_polymer() {
    let mut p = Pair::seed002();
    p.young[1] = p.young[0] / 70.0;
    let r = run_case("e_ratio_70", &p, Some(Fe::Hard), true);
    r[0].within().flagged(LARGE);
    r[1].within().flagged(LARGE).not_flagged(SINGULAR);
    // regression: the LTCA raised its corner extension and, as the FE
    // contact, loads a second pair (with 0.2 mm it put all on one pair)
    let (fe, lt) = (r[0].answer(), r[1].answer());
    assert!(lt.extension_mm > 1.0, "extension {}", lt.extension_mm);
    let second = |s: &[f64]| s.iter().filter(|&&x| x > 0.1).count();
    assert!(
        second(&fe.shares) == 2 && second(&lt.shares) == 2,
        "{:?} {:?}",
        fe.shares,
        lt.shares
    );
}

/// The torque scaled with the gear's modulus: the polymer gear's strains
/// as the steel gear's at nominal torque.
#[test]
fn e_ratio_70_polymer_torque() {
    let mut p = Pair::seed002();
    p.young[1] = p.young[0] / 70.0;
    p.torque_nm /= 70.0;
    let r = run_case("e_ratio_70_T/70", &p, Some(Fe::Hard), true);
    r[0].within().not_flagged(LARGE);
    r[1].within().not_flagged(LARGE);
}

#[test]
fn e_ratio_1e4_scaled_torque() {
    let mut p = Pair::seed002();
    p.young[1] = p.young[0] / 1e4;
    p.torque_nm /= 1e4;
    let r = run_case("e_ratio_1e4_T/1e4", &p, Some(Fe::Hard), true);
    r[0].within().not_flagged(LARGE);
    r[1].within().not_flagged(LARGE);
    // the unscaled κ₁(K₀) is 10⁴ × the nominal's and above the limit:
    // flank's ill-conditioning note follows the scaled figure (README)
    assert!(r[0].answer().other_condition > CONDITION);
}

#[test]
fn e_ratio_1e4() {
    let mut p = Pair::seed002();
    p.young[1] = p.young[0] / 1e4;
    let r = run_case("e_ratio_1e4", &p, Some(Fe::Hard), true);
    // the linear answer turns the pinion by 8 (FE) or 16 (LTCA) rad: more
    // than the angular pitch 2π/13, refused in both paths
    r[0].error("reaches the angular pitch 0.4833 rad");
    r[1].error("reaches the angular pitch 0.4833 rad");
}

#[test]
fn nearly_incompressible_wedge15() {
    let mut p = Pair::seed002();
    p.poisson = [0.4999; 2];
    // the scene's summaries carry the locking warning; the nominal's not
    let s = scene_of(&p, "nu_0.4999_scene").unwrap();
    assert!(s.material_warnings()[0].contains("lock volumetrically"));
    assert!(scene_of(&Pair::seed002(), "nu_0.3_scene")
        .unwrap()
        .material_warnings()
        .is_empty());
    let r = run_case("nu_0.4999_wedge15", &p, Some(Fe::Hard), true);
    r[0].within();
    r[1].within();
}

#[test]
fn nearly_incompressible_hex20() {
    let mut p = Pair::seed002();
    p.poisson = [0.4999; 2];
    p.element = "hex20";
    let r = run_case("nu_0.4999_hex20", &p, Some(Fe::Hard), true);
    r[0].within();
    r[1].within();
}

/// The reference of the ν = 0.4999 hex20 row: hex20 at ν = 0.3.
#[test]
#[ignore = "reference figure only (the nominal row's limits): keeps CI short"]
fn hex20_reference() {
    let mut p = Pair::seed002();
    p.element = "hex20";
    let r = run_case("nu_0.3_hex20", &p, Some(Fe::Hard), true);
    r[0].within();
    r[1].within();
}

#[test]
fn torque_1e_minus_4() {
    let mut p = Pair::seed002();
    p.torque_nm *= 1e-4;
    let r = run_case("torque_1e-4", &p, Some(Fe::Hard), true);
    r[0].within();
    r[1].within();
}

#[test]
fn torque_100() {
    let mut p = Pair::seed002();
    p.torque_nm *= 100.0;
    let r = run_case("torque_100", &p, Some(Fe::Hard), true);
    r[0].within().flagged(LARGE);
    // κ₂(F) over every candidate is finite or ∞ depending on the state
    // the half-width iteration settles on (README, third round): ∞ must be
    // said; the loaded points stay regular either way
    r[1].within_or_unresolved()
        .flagged(LARGE)
        .not_flagged(SINGULAR);
}

/// The penalty is an FE contact setting: the LTCA row is the nominal one.
#[test]
fn penalty_1e_minus_3() {
    let r = run_case(
        "penalty_1e-3",
        &Pair::seed002(),
        Some(Fe::Penalty(1e-3)),
        false,
    );
    r[0].within();
}

#[test]
fn penalty_1e6() {
    let r = run_case(
        "penalty_1e6",
        &Pair::seed002(),
        Some(Fe::Penalty(1e6)),
        false,
    );
    r[0].within();
}

#[test]
fn aspect_ratio_1000() {
    // one element layer across a 1 000 mm face, 1 mm flank elements; the
    // torque × 1000/13.3 keeps the load per face width
    let mut p = Pair::seed002();
    p.face = 1000.0;
    p.base_size = 1000.0;
    p.torque_nm *= 1000.0 / 13.3;
    let r = run_case("aspect_1000", &p, Some(Fe::Hard), true);
    r[0].within();
    r[1].within();
    // a 100 mm face in one layer: the largest aspect ratio ≈ 1 100
    let mut p = Pair::seed002();
    p.face = 100.0;
    p.base_size = 100.0;
    p.torque_nm *= 100.0 / 13.3;
    let r = run_case("aspect_100", &p, Some(Fe::Hard), true);
    r[0].within();
    r[1].within();
}

#[test]
fn module_0_3() {
    let p = Pair::seed002().scaled(0.3 / 3.8);
    let r = run_case("module_0.3", &p, Some(Fe::Hard), true);
    r[0].within();
    r[1].within().not_flagged(SINGULAR);
}

#[test]
fn module_25() {
    let p = Pair::seed002().scaled(25.0 / 3.8);
    let r = run_case("module_25", &p, Some(Fe::Hard), true);
    r[0].within();
    r[1].within();
}

#[test]
fn six_teeth_undercut() {
    let mut p = Pair::seed002();
    p.z = [6, 200];
    p.shift = [0.0, 0.0];
    p.tip = [None, None];
    p.bore = [None, None];
    p.centre = None;
    let r = run_case("z6_x0_z200", &p, Some(Fe::Hard), true);
    r[0].error("are undercut by the rack");
    r[1].error("are undercut by the rack");
}

#[test]
fn six_teeth_shifted() {
    let mut p = Pair::seed002();
    p.z = [6, 200];
    p.shift = [0.65, -0.65];
    p.tip = [None, None];
    p.bore = [None, None];
    p.centre = None;
    let r = run_case("z6_x0.65_z200_default_tip", &p, Some(Fe::Hard), true);
    r[0].error("the tooth is pointed below the tip diameter");
    r[1].error("the tooth is pointed below the tip diameter");
    // a tip diameter with 0.7 m of tooth thickness
    p.tip[0] = Some(32.0);
    let r = run_case("z6_x0.65_z200", &p, Some(Fe::Hard), true);
    r[0].within().flagged(LARGE);
    r[1].within().flagged(LARGE).not_flagged(SINGULAR);
}

#[test]
fn crowning_100_um() {
    let mut p = Pair::seed002();
    p.lead_crowning_um = 100.0;
    let r = run_case("crowning_100um", &p, Some(Fe::Hard), true);
    r[0].within();
    r[1].within();
}
