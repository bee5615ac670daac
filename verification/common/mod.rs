//! Helpers shared by the verification programs (included with `#[path]`).
#![allow(dead_code)]

use std::collections::HashMap;
use std::path::Path;

use flank::fem::material::Material;
use flank::fem::mesh::Mesh;
use flank::fem::model::{Dirichlet, Model};

/// A model with one material on every element.
pub fn model_from_mesh(mesh: Mesh, young: f64, poisson: f64) -> Model {
    let ne = mesh.elements.len();
    Model {
        mesh,
        materials: vec![Material::new("material", young, poisson).expect("valid material")],
        element_material: vec![0; ne],
        ..Default::default()
    }
}

/// Prescribes `value` on components `comps` of every node of node set `set`.
pub fn fix_set(model: &mut Model, set: &str, comps: &[usize], value: f64) {
    let nodes = model
        .mesh
        .node_sets
        .get(set)
        .unwrap_or_else(|| panic!("node set {set}"))
        .clone();
    for n in nodes {
        for &k in comps {
            model.dirichlet.push(Dirichlet {
                node: n,
                component: k,
                value,
            });
        }
    }
}

/// Prints one verification figure in a fixed format (visible with `--nocapture`)
/// and asserts it is within tolerance.
pub fn check(
    case: &str,
    quantity: &str,
    obtained: f64,
    reference: f64,
    tolerance: f64,
    seconds: f64,
) {
    let err = if reference != 0.0 {
        ((obtained - reference) / reference).abs()
    } else {
        obtained.abs()
    };
    println!(
        "VERIFY {case:<16} {quantity:<40} obtained {obtained:>14.7e}  reference {reference:>14.7e}  rel.error {err:>9.2e}  tol {tolerance:>8.1e}  {seconds:>7.3} s"
    );
    assert!(err <= tolerance, "{case}: {quantity}: relative error {err:.3e} above tolerance {tolerance:.1e} (obtained {obtained}, reference {reference})");
}

/// Whether ccx can run here. On CI (env `CI` set) a missing ccx is a failure,
/// elsewhere the cross-code test is skipped with a message.
pub fn ccx_available() -> bool {
    if flank::ccx::ccx_executable().is_some() {
        return true;
    }
    if std::env::var_os("CI").is_some() {
        panic!("ccx not found on CI: .ci/run must install calculix-ccx");
    }
    eprintln!("ccx not found: cross-code comparison skipped (apt-get install calculix-ccx)");
    false
}

/// What ccx printed for one deck: the displacements by node label (the
/// deck's `*NODE PRINT` / `U`), the whole `.dat` text, and the wall time of
/// the ccx run.
pub struct CcxRun {
    pub displacements: HashMap<u64, [f64; 3]>,
    pub dat: String,
    pub wall_s: f64,
}

impl CcxRun {
    /// The `total force` blocks of the `.dat` (`*NODE PRINT, NSET=set,
    /// TOTALS=ONLY` / `RF`): set name → (fx, fy, fz).
    pub fn totals(&self) -> HashMap<String, [f64; 3]> {
        ccx_totals(&self.dat)
    }
}

/// Runs ccx (one thread) on the deck file `deck` in `workdir` (created; the
/// deck is copied there as `job.inp`) and reads what it printed to
/// `job.dat`. Panics if ccx fails; call [`ccx_available`] first.
pub fn run_ccx(deck: &Path, workdir: &Path) -> CcxRun {
    let run = flank::ccx::run_ccx(deck, workdir, 1).unwrap_or_else(|e| panic!("{e}"));
    let path = workdir.join("job.dat");
    let dat = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    CcxRun {
        displacements: run.displacements,
        dat,
        wall_s: run.wall_s,
    }
}

/// `total force` blocks of a ccx .dat file: set name → (fx, fy, fz).
pub fn ccx_totals(text: &str) -> HashMap<String, [f64; 3]> {
    let mut out = HashMap::new();
    let mut set: Option<String> = None;
    for line in text.lines() {
        let t = line.trim();
        if t.starts_with("total force") {
            set = t
                .split("for set ")
                .nth(1)
                .and_then(|s| s.split_whitespace().next())
                .map(str::to_string);
            continue;
        }
        if t.is_empty() {
            continue;
        }
        if let Some(name) = set.take() {
            let v: Vec<f64> = t
                .split_whitespace()
                .filter_map(|x| x.parse().ok())
                .collect();
            if v.len() == 3 {
                out.insert(name, [v[0], v[1], v[2]]);
            }
        }
    }
    out
}

/// A scratch directory under the target dir for one case.
pub fn scratch_dir(case: &str) -> std::path::PathBuf {
    let d = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(case);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("scratch dir");
    d
}

/// What ccx printed: node displacements (U; rotations for a ROT NODE),
/// the contact pressure per slave node (CSTR) and the last total reaction
/// force of a set (`*NODE PRINT, TOTALS=ONLY` of RF).
#[derive(Default)]
pub struct CcxDat {
    pub u: HashMap<u64, [f64; 3]>,
    pub cstr: HashMap<u64, f64>,
    pub total_force: Option<[f64; 3]>,
}

pub fn parse_ccx_dat(text: &str) -> CcxDat {
    let mut out = CcxDat::default();
    // 1: displacements, 2: contact stress, 3: a set's total force
    let mut mode = 0;
    for line in text.lines() {
        let t = line.trim();
        if t.is_empty() {
            continue;
        }
        if t.starts_with("displacements") {
            mode = 1;
            continue;
        }
        if t.starts_with("contact stress") {
            mode = 2;
            out.cstr.clear();
            continue;
        }
        if t.starts_with("total force") {
            mode = 3;
            continue;
        }
        let v: Option<Vec<f64>> = t.split_whitespace().map(|x| x.parse().ok()).collect();
        match (mode, v) {
            (1, Some(v)) if v.len() == 4 => {
                out.u.insert(v[0] as u64, [v[1], v[2], v[3]]);
            }
            (2, Some(v)) if v.len() == 4 => {
                out.cstr.insert(v[0] as u64, v[1]);
            }
            (3, Some(v)) if v.len() == 3 => {
                out.total_force = Some([v[0], v[1], v[2]]);
            }
            _ => mode = 0,
        }
    }
    out
}

/// A cantilever of rectangular section under a tip load (mm, MPa, N):
/// the beam-theory references of `cantilever` and `substructuring`.
pub struct TipLoadedBeam {
    pub length: f64,
    /// Section height (in the load direction) and width.
    pub height: f64,
    pub width: f64,
    pub young: f64,
    pub poisson: f64,
    pub load: f64,
}

impl TipLoadedBeam {
    /// Timoshenko tip deflection P L³/(3 E I) + P L/(κ G A) for a shear
    /// coefficient κ (Timoshenko, Phil. Mag. 41, 1921).
    pub fn timoshenko(&self, kappa: f64) -> f64 {
        let (b, h) = (self.width, self.height);
        let i = b * h.powi(3) / 12.0;
        let a = b * h;
        let g = self.young / (2.0 * (1.0 + self.poisson));
        self.load * self.length.powi(3) / (3.0 * self.young * i)
            + self.load * self.length / (kappa * g * a)
    }

    /// Bending only (Euler–Bernoulli): P L³ / (3 E I).
    pub fn euler_bernoulli(&self) -> f64 {
        self.load * self.length.powi(3)
            / (3.0 * self.young * self.width * self.height.powi(3) / 12.0)
    }

    /// Cowper's shear coefficient of a rectangular section,
    /// 10 (1 + ν) / (12 + 11 ν).
    pub fn cowper_kappa(&self) -> f64 {
        10.0 * (1.0 + self.poisson) / (12.0 + 11.0 * self.poisson)
    }
}

/// Per node the weight ∫ N_a dA over the faces of box face set `set`
/// (`mesh::structured::box_faces`): the nodal loads of a unit uniform
/// traction, and the weights of the exact area mean of a nodal field.
pub fn face_weights(model: &Model, set: &str) -> Vec<f64> {
    use flank::fem::loads::traction_face_load;
    let mut weight = vec![0.0; model.mesh.node_count()];
    for (e, f) in flank::mesh::structured::box_faces(&model.mesh, set) {
        let el = &model.mesh.elements[e];
        let x = model.mesh.element_coords(e);
        let w = traction_face_load(el.kind, &x, f, [0.0, 1.0, 0.0]).expect("face exists");
        for (a, v) in w {
            weight[el.nodes[a]] += v[1];
        }
    }
    weight
}
