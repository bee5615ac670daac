//! Linear static analysis: constraints → assembly → Cholesky → solve → recovery.
//!
//! Before anything is factorized, every connected body is checked for rigid-
//! body modes its constraints leave free; a singular model is an error that
//! names the free modes, never a garbage answer. After the solve, the relative
//! residual ‖Kq − b‖/‖b‖ of the reduced system is measured and reported.

use std::time::Instant;

use indicatif::{ProgressBar, ProgressStyle};
use nalgebra::{DMatrix, SymmetricEigen};

use crate::error::FlankError;
use crate::fem::assembly::{Assembly, SparsePattern};
use crate::fem::constraints::{DofMap, DofTarget};
use crate::fem::loads::load_vector;
use crate::fem::model::Model;
use crate::fem::ordering::OrderingMethod;
use crate::fem::refinement::solve_refined;
use crate::fem::residual::sym_norm_inf;
use crate::fem::solver::{parallelism, FactorStats, Precision, SparseCholesky};
use crate::fem::stress::{recover, Recovery};
use crate::fem::substructuring::{
    Substructure, SubstructureStats, TwoDomainCholesky, SUBSTRUCTURE_MAX_SEPARATOR_DOFS,
};
use crate::fem::thermal::{has_thermal_strain, thermal_load_vector, validate_temperatures};

/// How to solve.
#[derive(Clone, Debug)]
pub struct SolveOptions {
    pub ordering: OrderingMethod,
    /// Threads for assembly and factorization (0 = all).
    pub threads: usize,
    /// Recover nodal stresses and reactions.
    pub recover_stress: bool,
    /// Show a progress spinner on stderr.
    pub progress: bool,
    /// Arithmetic of the factorization (default mixed = f32 factor + f64
    /// refinement with a backward-error check and fallback to double;
    /// `Double` forces the f64 factor).
    pub precision: Precision,
    /// The two-domain factorization ([`crate::fem::substructuring`]):
    /// `Auto` (default) with ≥ 2 threads and a large mixed-precision solve.
    pub substructure: Substructure,
}

impl Default for SolveOptions {
    fn default() -> Self {
        SolveOptions {
            ordering: OrderingMethod::Metis,
            threads: 0,
            recover_stress: true,
            progress: false,
            precision: Precision::Mixed,
            substructure: Substructure::Auto,
        }
    }
}

/// Figures of one solve (written to `summary.json`).
#[derive(Clone, Debug, Default, serde::Serialize)]
pub struct SolveStats {
    pub nodes: usize,
    pub elements: usize,
    /// Free (reduced) degrees of freedom.
    pub dofs: usize,
    pub nnz_matrix: usize,
    pub nnz_factor: usize,
    pub ordering: String,
    /// Precision of the factor actually used ("double" or "mixed").
    pub precision: String,
    /// Iterative-refinement steps (mixed precision only).
    pub refinement_steps: usize,
    /// True if mixed precision did not converge and the solve was redone in double.
    pub precision_fallback: bool,
    pub supernodal: bool,
    pub threads: usize,
    pub symbolic_assembly_s: f64,
    /// Wall time of the numeric assembly, which runs beside the symbolic
    /// factorization (`symbolic_factorization_s`, its own time, overlaps it).
    pub assembly_s: f64,
    pub ordering_s: f64,
    pub symbolic_factorization_s: f64,
    pub factorization_s: f64,
    pub factorization_gflop: f64,
    pub factorization_gflops: f64,
    pub solve_s: f64,
    pub recovery_s: f64,
    pub total_s: f64,
    /// ‖K q − b‖ / ‖b‖ of the reduced system.
    pub relative_residual: f64,
    /// Normwise backward error ‖r‖∞ / (‖K‖∞‖q‖∞ + ‖b‖∞): what the solver
    /// answers for, independent of conditioning (~1e-16 for a stable solve).
    pub backward_error: f64,
    pub min_pivot_ratio: f64,
    pub peak_memory_mb: f64,
    /// The memory guard's estimate of the peak (MB): the resident set before
    /// the numeric factorization plus its estimated extra memory.
    pub estimated_peak_mb: f64,
    /// Figures of the two-domain factorization, when used.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub substructure: Option<SubstructureStats>,
    /// Why the two-domain factorization was not used or abandoned.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub substructure_note: Option<String>,
}

/// Result of a linear static analysis.
#[derive(Clone, Debug)]
pub struct StaticSolution {
    /// Displacements (node-major, mm).
    pub displacement: Vec<f64>,
    /// Reaction forces f_int − f_ext (node-major, N); non-zero only at constrained DOFs.
    /// f_ext: the mechanical loads (forces, pressures, body loads); a thermal
    /// load enters through f_int = ∫ Bᵀ D (ε − ε_th) dV instead.
    pub reaction: Option<Vec<f64>>,
    pub recovery: Option<Recovery>,
    /// Motion (tx, ty, tz, rx, ry, rz) of each rigid coupling's reference point.
    pub coupling_motion: Vec<[f64; 6]>,
    pub stats: SolveStats,
}

/// Peak resident memory of this process in MB (Linux `VmHWM`; 0 elsewhere).
pub use crate::resources::peak_memory_mb;

/// Checks the model's data before assembly: materials, sections.
pub fn validate(model: &Model) -> Result<(), FlankError> {
    for m in &model.materials {
        m.validate()?;
    }
    if model.element_material.len() != model.mesh.elements.len() {
        return Err(FlankError::Model(format!(
            "{} elements but {} material assignments",
            model.mesh.elements.len(),
            model.element_material.len()
        )));
    }
    if model.mesh.elements.is_empty() {
        return Err(FlankError::Model("the model has no elements".into()));
    }
    validate_temperatures(model)?;
    for (e, &m) in model.element_material.iter().enumerate() {
        if m >= model.materials.len() {
            return Err(FlankError::Model(format!(
                "element {} has no valid material",
                model.mesh.elements[e].label
            )));
        }
    }
    for (i, x) in model.mesh.coords.iter().enumerate() {
        if x.iter().any(|v| !v.is_finite()) {
            return Err(FlankError::Model(format!(
                "node {} has non-finite coordinates",
                model.mesh.node_labels[i]
            )));
        }
    }
    Ok(())
}

fn find(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}

/// Names the rigid-body modes left free by the constraints, per connected
/// body; `Ok(())` if every body is held. Bodies joined by equations
/// (`*EQUATION`) are checked together: the unknowns are the rigid motions
/// of each body, and each equation is one row Σ cᵢ uᵢ = 0 between them (a
/// mechanism, two bodies joined at one node, is a free mode too).
pub fn check_rigid_body_modes(model: &Model, dofs: &DofMap) -> Result<(), FlankError> {
    let mesh = &model.mesh;
    let nn = mesh.node_count();
    let mut parent: Vec<usize> = (0..nn).collect();
    let union = |parent: &mut Vec<usize>, a: usize, b: usize| {
        let (ra, rb) = (find(parent, a), find(parent, b));
        if ra != rb {
            parent[ra.max(rb)] = ra.min(rb);
        }
    };
    for el in &mesh.elements {
        for &n in &el.nodes[1..] {
            union(&mut parent, el.nodes[0], n);
        }
    }
    for cp in &model.couplings {
        for w in cp.nodes.windows(2) {
            union(&mut parent, w[0], w[1]);
        }
    }
    let used = mesh.used_nodes();
    // per component: centroid, size, and constraint rows
    let mut comp_of = vec![usize::MAX; nn];
    let mut roots: Vec<usize> = Vec::new();
    for n in 0..nn {
        if used[n] {
            let r = find(&mut parent, n);
            if comp_of[r] == usize::MAX {
                comp_of[r] = roots.len();
                roots.push(r);
            }
            comp_of[n] = comp_of[r];
        }
    }
    let nc = roots.len();
    let mut centroid = vec![[0.0; 3]; nc];
    let mut count = vec![0usize; nc];
    let mut lo = vec![[f64::INFINITY; 3]; nc];
    let mut hi = vec![[f64::NEG_INFINITY; 3]; nc];
    for n in 0..nn {
        let c = comp_of[n];
        if c == usize::MAX {
            continue;
        }
        count[c] += 1;
        for k in 0..3 {
            centroid[c][k] += mesh.coords[n][k];
            lo[c][k] = lo[c][k].min(mesh.coords[n][k]);
            hi[c][k] = hi[c][k].max(mesh.coords[n][k]);
        }
    }
    let size: Vec<f64> = (0..nc)
        .map(|c| {
            for k in 0..3 {
                centroid[c][k] /= count[c] as f64;
            }
            ((hi[c][0] - lo[c][0]).powi(2)
                + (hi[c][1] - lo[c][1]).powi(2)
                + (hi[c][2] - lo[c][2]).powi(2))
            .sqrt()
            .max(f64::MIN_POSITIVE)
        })
        .collect();
    // displacement of component c's rigid mode k (3 translations, 3 rotations
    // scaled by the body size) at point x, component i
    let mode = |c: usize, x: [f64; 3]| -> [[f64; 6]; 3] {
        let r = [
            (x[0] - centroid[c][0]) / size[c],
            (x[1] - centroid[c][1]) / size[c],
            (x[2] - centroid[c][2]) / size[c],
        ];
        [
            [1.0, 0.0, 0.0, 0.0, r[2], -r[1]],
            [0.0, 1.0, 0.0, -r[2], 0.0, r[0]],
            [0.0, 0.0, 1.0, r[1], -r[0], 0.0],
        ]
    };
    // clusters: the bodies joined by equations (one body each without)
    let mut cparent: Vec<usize> = (0..nc).collect();
    for eq in &model.equations {
        let bodies: Vec<usize> = eq
            .terms
            .iter()
            .filter(|t| t.node < nn && comp_of[t.node] != usize::MAX)
            .map(|t| comp_of[t.node])
            .collect();
        for w in bodies.windows(2) {
            union(&mut cparent, w[0], w[1]);
        }
    }
    let mut cluster_of = vec![usize::MAX; nc];
    let mut clusters: Vec<Vec<usize>> = Vec::new();
    for c in 0..nc {
        let r = find(&mut cparent, c);
        if cluster_of[r] == usize::MAX {
            cluster_of[r] = clusters.len();
            clusters.push(Vec::new());
        }
        cluster_of[c] = cluster_of[r];
        clusters[cluster_of[c]].push(c);
    }
    let ncl = clusters.len();
    // Unknowns per cluster: the rigid motion (6) of each of its bodies and
    // the free reference DOFs of the couplings on them. Constraints: the
    // motion vanishes at Dirichlet DOFs, at every coupled node it equals the
    // motion the reference imposes, and every equation holds. A null vector
    // of these rows is a free mode (of a body, or of a reference DOF its
    // nodes do not feel, e.g. a rotation about the line of collinear
    // coupled nodes).
    let mut body_col = vec![0usize; nc];
    let mut width = vec![0usize; ncl];
    for (cl, bodies) in clusters.iter().enumerate() {
        for &c in bodies {
            body_col[c] = width[cl];
            width[cl] += 6;
        }
    }
    let mut comp_couplings: Vec<Vec<usize>> = vec![Vec::new(); nc];
    for (k, cp) in model.couplings.iter().enumerate() {
        if let Some(&n0) = cp.nodes.iter().find(|&&n| used[n]) {
            comp_couplings[comp_of[n0]].push(k);
        }
    }
    // column of each (coupling, reference DOF) within its cluster's unknowns
    let mut column = vec![[usize::MAX; 6]; model.couplings.len()];
    for c in 0..nc {
        let cl = cluster_of[c];
        for &k in &comp_couplings[c] {
            for j in 0..6 {
                if model.couplings[k].free[j] {
                    column[k][j] = width[cl];
                    width[cl] += 1;
                }
            }
        }
    }
    let mut gram: Vec<DMatrix<f64>> = (0..ncl)
        .map(|cl| DMatrix::zeros(width[cl], width[cl]))
        .collect();
    let add_row = |g: &mut DMatrix<f64>, row: &[(usize, f64)]| {
        for &(a, va) in row {
            for &(b, vb) in row {
                g[(a, b)] += va * vb;
            }
        }
    };
    let mut coupling_of = vec![usize::MAX; nn];
    for (k, cp) in model.couplings.iter().enumerate() {
        for &n in &cp.nodes {
            coupling_of[n] = k;
        }
    }
    for n in 0..nn {
        let c = comp_of[n];
        if c == usize::MAX {
            continue;
        }
        let m = mode(c, mesh.coords[n]);
        let b0 = body_col[c];
        for i in 0..3 {
            let mut row: Vec<(usize, f64)> = (0..6).map(|j| (b0 + j, m[i][j])).collect();
            match dofs.targets[3 * n + i] {
                DofTarget::Fixed(_) => {}
                // an equation's dependent DOF: its row is the equation's
                DofTarget::Coupled { .. } if dofs.is_dependent(3 * n + i) => continue,
                DofTarget::Coupled { .. } => {
                    let k = coupling_of[n];
                    let cp = &model.couplings[k];
                    let x = mesh.coords[n];
                    let r = [
                        (x[0] - cp.reference_point[0]) / size[c],
                        (x[1] - cp.reference_point[1]) / size[c],
                        (x[2] - cp.reference_point[2]) / size[c],
                    ];
                    // ∂u_i/∂(reference DOF j): translations δ_ij, rotations (e_j × r)_i
                    let rot = [[0.0, r[2], -r[1]], [-r[2], 0.0, r[0]], [r[1], -r[0], 0.0]];
                    for j in 0..6 {
                        let col = column[k][j];
                        if col == usize::MAX {
                            continue;
                        }
                        let v = if j < 3 {
                            if i == j {
                                1.0
                            } else {
                                0.0
                            }
                        } else {
                            rot[i][j - 3]
                        };
                        if v != 0.0 {
                            row.push((col, -v));
                        }
                    }
                }
                _ => continue,
            }
            add_row(&mut gram[cluster_of[c]], &row);
        }
    }
    // one row per equation, Σ cᵢ (mode of the body of node i)ᵢ, scaled to
    // a largest coefficient of 1
    for eq in &model.equations {
        let scale = eq
            .terms
            .iter()
            .fold(0.0f64, |a, t| a.max(t.coefficient.abs()));
        let mut row: Vec<(usize, f64)> = Vec::new();
        let mut cl = usize::MAX;
        for t in &eq.terms {
            if t.node >= nn || t.component > 2 || comp_of[t.node] == usize::MAX {
                continue;
            }
            let c = comp_of[t.node];
            cl = cluster_of[c];
            let m = mode(c, mesh.coords[t.node]);
            for j in 0..6 {
                row.push((body_col[c] + j, t.coefficient / scale * m[t.component][j]));
            }
        }
        if cl != usize::MAX && scale > 0.0 {
            add_row(&mut gram[cl], &row);
        }
    }
    let names = [
        "translation x",
        "translation y",
        "translation z",
        "rotation about x",
        "rotation about y",
        "rotation about z",
    ];
    let ref_names = ["ux", "uy", "uz", "rx", "ry", "rz"];
    // "translation x + rotation about z" for the 6 entries at `at` of v
    let describe = |v: &[f64], at: usize, norm: f64| -> String {
        let mut parts: Vec<(f64, usize)> = (0..6)
            .map(|j| (v[at + j].abs() / norm, j))
            .filter(|p| p.0 > 0.2)
            .collect();
        parts.sort_by(|a, b| b.0.partial_cmp(&a.0).unwrap_or(std::cmp::Ordering::Equal));
        let desc: Vec<&str> = parts.iter().map(|p| names[p.1]).collect();
        desc.join(" + ")
    };
    let mut problems = Vec::new();
    for (cl, bodies) in clusters.iter().enumerate() {
        let eig = SymmetricEigen::new(gram[cl].clone());
        let scale = eig.eigenvalues.iter().fold(1.0f64, |a, &b| a.max(b));
        let nb = 6 * bodies.len();
        let mut free = Vec::new();
        for k in 0..width[cl] {
            if eig.eigenvalues[k] <= 1e-10 * scale {
                let v: Vec<f64> = eig.eigenvectors.column(k).iter().copied().collect();
                let body: f64 = (0..nb).map(|j| v[j] * v[j]).sum::<f64>().sqrt();
                if body > 0.2 && bodies.len() == 1 {
                    free.push(describe(&v, 0, body));
                } else if body > 0.2 {
                    let mut desc = Vec::new();
                    for &c in bodies {
                        let at = body_col[c];
                        let norm: f64 = (0..6).map(|j| v[at + j] * v[at + j]).sum::<f64>().sqrt();
                        if norm > 0.2 * body {
                            desc.push(format!(
                                "body of node {}: {}",
                                mesh.node_labels[roots[c]],
                                describe(&v, at, norm)
                            ));
                        }
                    }
                    free.push(desc.join(" with "));
                } else {
                    let mut desc = Vec::new();
                    for &c in bodies {
                        for &kc in &comp_couplings[c] {
                            for j in 0..6 {
                                let col = column[kc][j];
                                if col != usize::MAX && v[col].abs() > 0.2 {
                                    desc.push(format!(
                                        "coupling '{}' reference {} (its nodes do not feel it)",
                                        model.couplings[kc].name, ref_names[j]
                                    ));
                                }
                            }
                        }
                    }
                    free.push(desc.join(" + "));
                }
            }
        }
        if free.is_empty() {
            continue;
        }
        if let [c] = bodies[..] {
            let label = mesh.node_labels[roots[c]];
            problems.push(format!(
                "body containing node {label} ({} nodes, centroid [{:.4}, {:.4}, {:.4}]) has {} free rigid-body mode(s): {}",
                count[c],
                centroid[c][0],
                centroid[c][1],
                centroid[c][2],
                free.len(),
                free.join("; ")
            ));
        } else {
            let labels: Vec<String> = bodies
                .iter()
                .map(|&c| mesh.node_labels[roots[c]].to_string())
                .collect();
            problems.push(format!(
                "the {} bodies containing nodes {} (joined by equations, {} nodes) have {} free rigid-body mode(s): {}",
                bodies.len(),
                labels.join(", "),
                bodies.iter().map(|&c| count[c]).sum::<usize>(),
                free.len(),
                free.join("; ")
            ));
        }
    }
    if problems.is_empty() {
        Ok(())
    } else {
        Err(FlankError::Singular(format!(
            "{}; add *BOUNDARY conditions that hold these modes",
            problems.join(". ")
        )))
    }
}

/// Solves the linear static problem.
///
/// With `options.threads > 0` all parallel work (assembly, factorization,
/// recovery) runs in a rayon pool of that many threads; 0 uses the global pool.
pub fn solve_static(model: &Model, options: &SolveOptions) -> Result<StaticSolution, FlankError> {
    crate::fem::solver::with_threads(options.threads, || solve_static_in_pool(model, options))
}

fn solve_static_in_pool(
    model: &Model,
    options: &SolveOptions,
) -> Result<StaticSolution, FlankError> {
    let t_total = Instant::now();
    let pb = if options.progress {
        let pb = ProgressBar::new_spinner();
        pb.set_style(
            ProgressStyle::with_template("{spinner} [{elapsed_precise}] {msg}")
                .expect("valid template"),
        );
        pb.enable_steady_tick(std::time::Duration::from_millis(120));
        pb
    } else {
        ProgressBar::hidden()
    };
    validate(model)?;
    let mut dofs = DofMap::new(model)?;
    check_rigid_body_modes(model, &dofs)?;
    let par = parallelism(options.threads);
    let mut stats = SolveStats {
        nodes: model.mesh.node_count(),
        elements: model.mesh.elements.len(),
        dofs: dofs.reduced_count,
        threads: par.degree(),
        ..Default::default()
    };

    pb.set_message(format!(
        "ordering and symbolic assembly ({} DOFs)",
        dofs.reduced_count
    ));
    let t = Instant::now();
    let split = options
        .substructure
        .applies(dofs.reduced_count, par.degree(), options.precision);
    let assembly = if split {
        let max_separator = match options.substructure {
            Substructure::Auto => SUBSTRUCTURE_MAX_SEPARATOR_DOFS,
            _ => usize::MAX,
        };
        match Assembly::two_domain(model, &mut dofs, options.ordering, max_separator) {
            Ok(a) => a,
            Err(e) => {
                // refused before renumbering: the plain numbering instead
                stats.substructure_note = Some(format!("not substructured: {e}"));
                Assembly::new(model, &mut dofs, options.ordering)?
            }
        }
    } else {
        Assembly::new(model, &mut dofs, options.ordering)?
    };
    let dofs = dofs;
    stats.symbolic_assembly_s = t.elapsed().as_secs_f64();

    pb.set_message(format!(
        "assembly ({} elements) and symbolic factorization",
        model.mesh.elements.len()
    ));
    // The symbolic factorization (serial in faer) needs only the pattern:
    // it runs beside the numeric assembly, which takes the other threads.
    let t = Instant::now();
    let (analyzed, system) = rayon::join(
        || match assembly.split {
            Some(split) => TwoDomainCholesky::analyze(
                &assembly.pattern,
                split,
                options.ordering,
                assembly.ordering_s,
                par,
            )
            .map(Factor::TwoDomain),
            None => SparseCholesky::analyze(
                &assembly.pattern,
                options.ordering,
                assembly.ordering_s,
                par,
            )
            .map(Factor::Plain),
        },
        || assembly.assemble(model, &dofs),
    );
    let system = system?;
    let analyzed = analyzed?;
    stats.assembly_s = t.elapsed().as_secs_f64();
    let ordering_s = assembly.ordering_s;
    // keep the pattern, free the slot map and colouring before factorizing
    // (a partial move out of `assembly` would keep the rest to the end of
    // the function)
    let mut pattern = assembly.into_pattern();

    // reduced right-hand side: Tᵀ (f + f_th) + coupling loads − Tᵀ K u₀;
    // the reactions are f_int − f with f the mechanical loads (f_int holds
    // the thermal part: σ = D (ε − ε_th))
    let f_full = load_vector(model)?;
    let mut b = if has_thermal_strain(model) {
        let f_th = thermal_load_vector(model)?;
        let total: Vec<f64> = f_full.iter().zip(&f_th).map(|(a, b)| a + b).collect();
        dofs.restrict(&total)
    } else {
        dofs.restrict(&f_full)
    };
    for (c, cp) in model.couplings.iter().enumerate() {
        for k in 0..6 {
            if let Some(r) = dofs.coupling_dofs[c][k] {
                b[r] += cp.load[k];
            }
        }
    }
    for (bi, pi) in b.iter_mut().zip(&system.prescribed_load) {
        *bi += pi;
    }

    // the names are only needed for an error message: built on first use
    let dof_names = std::sync::OnceLock::new();
    let name_of = |r: usize| {
        dof_names
            .get_or_init(|| reduced_dof_names(model, &dofs))
            .get(r)
            .cloned()
            .unwrap_or_else(|| format!("reduced DOF {r}"))
    };
    let k_norm = sym_norm_inf(&pattern, &system.values);
    let mut chol = match analyzed {
        Factor::Plain(chol) => chol,
        Factor::TwoDomain(mut td) => {
            pb.set_message(format!(
                "two-domain factorization (nnz(L) = {})",
                td.nnz_factor()
            ));
            // K's pattern without the rows M_B's pattern repeats
            td.adopt(std::mem::replace(
                &mut pattern,
                SparsePattern {
                    n: 0,
                    col_ptr: Vec::new(),
                    row_idx: Vec::new(),
                },
            ));
            let factored = td.factorize(&system.values, Precision::Mixed, &name_of);
            let solved = match factored {
                Ok(()) => {
                    let t = Instant::now();
                    let r = solve_refined(
                        &|x: &mut [f64]| td.solve_in_place(x),
                        false,
                        &|x: &[f64]| td.sym_mul(&system.values, x),
                        k_norm,
                        &b,
                        &mut stats.refinement_steps,
                    );
                    stats.solve_s = t.elapsed().as_secs_f64();
                    r.ok_or_else(|| "the refinement did not converge".to_string())
                }
                // a refusal for memory is final: the f64 factor needs more
                Err(e @ FlankError::Memory(_)) => return Err(e),
                Err(e) => Err(e.to_string()),
            };
            let st = td.stats.clone();
            stats.nnz_matrix = td.nnz_matrix();
            stats.nnz_factor = td.nnz_factor();
            stats.factorization_s = st.factorization_s + st.schur_s;
            stats.factorization_gflop = td.flops() * 1e-9;
            stats.factorization_gflops =
                stats.factorization_gflop / stats.factorization_s.max(1e-12);
            stats.symbolic_factorization_s = st.halves[0].symbolic_s.max(st.halves[1].symbolic_s);
            stats.min_pivot_ratio = td.min_pivot_ratio();
            stats.estimated_peak_mb = st.resident_before_mb + st.factor_estimate_mb;
            stats.substructure = Some(st);
            match solved {
                Ok((q, rel, eta)) => {
                    drop(td);
                    stats.ordering = options.ordering.name().to_string();
                    stats.precision = "mixed".into();
                    stats.supernodal = true;
                    stats.ordering_s = ordering_s;
                    stats.relative_residual = rel;
                    stats.backward_error = eta;
                    return finish(model, options, &dofs, q, f_full, stats, t_total, pb);
                }
                Err(why) => {
                    // the plain double path, as a plain mixed solve falls back
                    pattern = td.into_pattern().expect("adopted above");
                    stats.precision_fallback = true;
                    // the figures above are the abandoned attempt's: the
                    // answer comes from the plain double factor below
                    stats.substructure = None;
                    stats.substructure_note = Some(format!(
                        "two-domain solve abandoned: {why}; solved in double"
                    ));
                    pb.set_message("factorization (double, after the two-domain solve failed)");
                    let mut chol =
                        SparseCholesky::analyze(&pattern, options.ordering, ordering_s, par)?;
                    chol.factorize(&pattern, &system.values, Precision::Double, &name_of)?;
                    chol
                }
            }
        }
    };
    if chol.stats.precision.is_empty() {
        pb.set_message(format!(
            "factorization (nnz(L) = {})",
            chol.stats.nnz_factor
        ));
        if let Err(e) = chol.factorize(&pattern, &system.values, options.precision, &name_of) {
            // a refusal for memory is final: the f64 factor needs more
            if options.precision != Precision::Mixed || matches!(e, FlankError::Memory(_)) {
                return Err(e);
            }
            // the f32 factor broke down (κ beyond single precision): factorize in f64
            stats.precision_fallback = true;
            chol.factorize(&pattern, &system.values, Precision::Double, &name_of)?;
        }
    }
    let t = Instant::now();
    let solve = |chol: &SparseCholesky, stats: &mut SolveStats| {
        let exact = chol.precision() == Precision::Double;
        solve_refined(
            &|x: &mut [f64]| chol.solve_in_place(x),
            exact,
            &|x: &[f64]| pattern.sym_mul(&system.values, x),
            k_norm,
            &b,
            &mut stats.refinement_steps,
        )
    };
    let solved = match solve(&chol, &mut stats) {
        Some(s) => s,
        None => {
            // refinement did not reach double-precision accuracy: redo in f64
            stats.precision_fallback = true;
            pb.set_message("factorization (double, after mixed precision did not converge)");
            chol.factorize(&pattern, &system.values, Precision::Double, &name_of)?;
            solve(&chol, &mut stats).expect("a double-precision solve always returns")
        }
    };
    let (q, rel, eta) = solved;
    stats.solve_s = t.elapsed().as_secs_f64();
    stats.relative_residual = rel;
    stats.backward_error = eta;
    let fs: FactorStats = chol.stats.clone();
    stats.nnz_matrix = fs.nnz_matrix;
    stats.nnz_factor = fs.nnz_factor;
    stats.estimated_peak_mb = fs.resident_before_mb + fs.factor_estimate_mb;
    stats.ordering = fs.ordering.clone();
    stats.precision = fs.precision.clone();
    stats.supernodal = fs.supernodal;
    stats.ordering_s = fs.ordering_s;
    stats.symbolic_factorization_s = fs.symbolic_s;
    stats.factorization_s = fs.factorization_s;
    stats.factorization_gflop = fs.flops * 1e-9;
    stats.factorization_gflops = if fs.factorization_s > 0.0 {
        fs.flops * 1e-9 / fs.factorization_s
    } else {
        0.0
    };
    stats.min_pivot_ratio = fs.min_pivot_ratio;
    drop(chol);
    finish(model, options, &dofs, q, f_full, stats, t_total, pb)
}

/// The factorization a static solve uses (one, short-lived).
#[allow(clippy::large_enum_variant)]
enum Factor {
    Plain(SparseCholesky),
    TwoDomain(TwoDomainCholesky),
}

/// Checks the reduced solution `q`, expands it and recovers stresses.
#[allow(clippy::too_many_arguments)]
fn finish(
    model: &Model,
    options: &SolveOptions,
    dofs: &DofMap,
    q: Vec<f64>,
    f_full: Vec<f64>,
    mut stats: SolveStats,
    t_total: Instant,
    pb: ProgressBar,
) -> Result<StaticSolution, FlankError> {
    if q.iter().any(|v| !v.is_finite()) {
        return Err(FlankError::Solver(
            "the solution contains non-finite values".into(),
        ));
    }
    if !(stats.backward_error <= BACKWARD_ERROR_LIMIT) {
        return Err(FlankError::Solver(format!(
            "backward error {:.2e} (relative residual {:.2e}) after the solve: the factorization is not trustworthy",
            stats.backward_error, stats.relative_residual
        )));
    }
    let displacement = dofs.expand(&q);
    let coupling_motion = dofs
        .coupling_dofs
        .iter()
        .map(|cd| {
            let mut m = [0.0; 6];
            for k in 0..6 {
                if let Some(r) = cd[k] {
                    m[k] = q[r];
                }
            }
            m
        })
        .collect();

    let (recovery, reaction) = if options.recover_stress {
        pb.set_message("stress recovery");
        let t = Instant::now();
        let rec = recover(model, &displacement)?;
        let reaction: Vec<f64> = rec
            .internal_force
            .iter()
            .zip(&f_full)
            .map(|(a, b)| a - b)
            .collect();
        stats.recovery_s = t.elapsed().as_secs_f64();
        (Some(rec), Some(reaction))
    } else {
        (None, None)
    };
    stats.total_s = t_total.elapsed().as_secs_f64();
    stats.peak_memory_mb = peak_memory_mb();
    pb.finish_and_clear();
    Ok(StaticSolution {
        displacement,
        reaction,
        recovery,
        coupling_motion,
        stats,
    })
}

/// Backward error above which a solution is rejected.
const BACKWARD_ERROR_LIMIT: f64 = 1e-10;

/// Human-readable name of every reduced DOF ("node 12 uy", "coupling 'HUB' rz").
pub(crate) fn reduced_dof_names(model: &Model, dofs: &DofMap) -> Vec<String> {
    let mut names = vec![String::new(); dofs.reduced_count];
    for (d, t) in dofs.targets.iter().enumerate() {
        if let DofTarget::Free(r) = t {
            names[*r] = format!(
                "node {} u{}",
                model.mesh.node_labels[d / 3],
                ["x", "y", "z"][d % 3]
            );
        }
    }
    for (c, cd) in dofs.coupling_dofs.iter().enumerate() {
        for (k, r) in cd.iter().enumerate() {
            if let Some(r) = r {
                names[*r] = format!(
                    "coupling '{}' {}",
                    model.couplings[c].name,
                    ["ux", "uy", "uz", "rx", "ry", "rz"][k]
                );
            }
        }
    }
    names
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fem::element::{HEX20_NODES, WEDGE15_NODES};
    use crate::fem::material::Material;
    use crate::fem::mesh::{ElementKind, Mesh};
    use crate::fem::model::{Dirichlet, Pressure};

    /// One element on [0,1]³ (or the unit wedge × [0,1]) under uniaxial pressure
    /// on the face x = 1: u_x = −p x / E, u_y = ν p y / E exactly.
    fn uniaxial(kind: ElementKind, face_x1: usize) {
        let nodes: Vec<[f64; 3]> = match kind {
            ElementKind::C3D15 => WEDGE15_NODES
                .iter()
                .map(|p| [p[0], p[1], 0.5 * (p[2] + 1.0)])
                .collect(),
            _ => HEX20_NODES
                .iter()
                .map(|p| [0.5 * (p[0] + 1.0), 0.5 * (p[1] + 1.0), 0.5 * (p[2] + 1.0)])
                .collect(),
        };
        let mut mesh = Mesh::new();
        for (i, x) in nodes.iter().enumerate() {
            mesh.add_node(i as u64 + 1, *x).unwrap();
        }
        mesh.add_element(1, kind, (0..nodes.len()).collect())
            .unwrap();
        let mut model = Model {
            mesh,
            materials: vec![Material::new("steel", 200e3, 0.3).unwrap()],
            element_material: vec![0],
            ..Default::default()
        };
        for (i, x) in nodes.iter().enumerate() {
            for k in 0..3 {
                if x[k] == 0.0 {
                    model.dirichlet.push(Dirichlet {
                        node: i,
                        component: k,
                        value: 0.0,
                    });
                }
            }
        }
        let p = 50.0;
        model.pressures.push(Pressure {
            element: 0,
            face: face_x1,
            value: p,
        });
        let sol = solve_static(&model, &SolveOptions::default()).unwrap();
        for (i, x) in nodes.iter().enumerate() {
            let ux = sol.displacement[3 * i];
            let uy = sol.displacement[3 * i + 1];
            assert!(
                (ux + p * x[0] / 200e3).abs() < 1e-14,
                "{kind:?} node {i}: ux = {ux}"
            );
            assert!(
                (uy - 0.3 * p * x[1] / 200e3).abs() < 1e-14,
                "{kind:?} node {i}: uy = {uy}"
            );
        }
        let rec = sol.recovery.unwrap();
        for s in &rec.stress {
            assert!((s[0] + p).abs() < 1e-9 && s[1].abs() < 1e-9, "{s:?}");
        }
        assert!(sol.stats.relative_residual < 1e-12 && sol.stats.backward_error < 1e-14);
    }

    #[test]
    fn uniaxial_single_elements() {
        uniaxial(ElementKind::C3D20, 4);
        uniaxial(ElementKind::C3D20R, 4);
        // wedge: the face through nodes 2,3,6,5 is not x = 1; use a hex-only check there
    }

    /// Mixed precision (f32 factor + CG on the f64 matrix) reproduces the
    /// double-precision answer, also on a nearly incompressible, slender body
    /// where the f32 factor is a poor preconditioner (it then refines longer
    /// or falls back to double).
    #[test]
    fn mixed_precision_matches_double() {
        use crate::mesh::structured::{cantilever_model, BoxElement};
        for nu in [0.3, 0.49999] {
            let mut model = cantilever_model([40, 2, 2], BoxElement::Hex20, 1000.0).unwrap();
            model.materials[0].poisson = nu;
            let d = solve_static(
                &model,
                &SolveOptions {
                    recover_stress: false,
                    precision: Precision::Double,
                    ..Default::default()
                },
            )
            .unwrap();
            let m = solve_static(
                &model,
                &SolveOptions {
                    recover_stress: false,
                    precision: Precision::Mixed,
                    ..Default::default()
                },
            )
            .unwrap();
            let umax = d.displacement.iter().fold(0.0f64, |a, b| a.max(b.abs()));
            let diff = d
                .displacement
                .iter()
                .zip(&m.displacement)
                .fold(0.0f64, |a, (x, y)| a.max((x - y).abs()));
            // Both answers are backward stable (η ≈ 1e-16); they may differ by
            // up to κ·η. At ν = 0.3 that is far below 1e-8; at ν = 0.49999
            // (λ/μ = 5·10⁴, slender beam; min pivot ratio 8.5e-8) κ is large and
            // the mixed and double answers were seen to differ by 1e-7 to 4e-7,
            // so there the check is 1e-5.
            let tol = if nu < 0.4 { 1e-8 } else { 1e-5 };
            assert!(
                diff <= tol * umax,
                "ν = {nu}: mixed differs from double by {:.2e}",
                diff / umax
            );
            assert!(m.stats.precision == "mixed" || m.stats.precision_fallback);
            for s in [&d.stats, &m.stats] {
                assert!(
                    s.backward_error < 1e-15,
                    "ν = {nu}: backward error {}",
                    s.backward_error
                );
            }
        }
    }

    /// One thread and two threads give the same answer (the colouring makes
    /// the assembly order-independent per slot; only the summation order of
    /// the parallel factorization may differ at round-off).
    #[test]
    fn one_and_two_threads_agree() {
        use crate::mesh::structured::{cantilever_model, BoxElement};
        let model = cantilever_model([12, 3, 3], BoxElement::Hex20, 1000.0).unwrap();
        let one = solve_static(
            &model,
            &SolveOptions {
                threads: 1,
                ..Default::default()
            },
        )
        .unwrap();
        let two = solve_static(
            &model,
            &SolveOptions {
                threads: 2,
                ..Default::default()
            },
        )
        .unwrap();
        assert_eq!(one.stats.threads, 1);
        assert_eq!(two.stats.threads, 2);
        let umax = one.displacement.iter().fold(0.0f64, |a, b| a.max(b.abs()));
        for (a, b) in one.displacement.iter().zip(&two.displacement) {
            assert!((a - b).abs() <= 1e-12 * umax);
        }
    }

    /// The two-domain solve (forced on, 1 and 2 threads) gives the plain
    /// solve's answer to the refinement's backward error, reports its
    /// halves, and on a nearly incompressible slender body (a poor f32
    /// preconditioner) still gives the double answer, refined or by the
    /// fallback to the plain double factorization.
    #[test]
    fn two_domain_solve_matches_plain_solve() {
        use crate::mesh::structured::{cantilever_model, BoxElement};
        for nu in [0.3, 0.49999] {
            let mut model = cantilever_model([24, 3, 3], BoxElement::Hex20, 1000.0).unwrap();
            model.materials[0].poisson = nu;
            let solve = |substructure, threads, precision| {
                solve_static(
                    &model,
                    &SolveOptions {
                        recover_stress: false,
                        substructure,
                        threads,
                        precision,
                        ..Default::default()
                    },
                )
                .unwrap()
            };
            let plain = solve(Substructure::Off, 2, Precision::Double);
            assert!(plain.stats.substructure.is_none());
            let umax = plain
                .displacement
                .iter()
                .fold(0.0f64, |a, b| a.max(b.abs()));
            let tol = if nu < 0.4 { 1e-8 } else { 1e-5 };
            for threads in [1, 2] {
                let split = solve(Substructure::On, threads, Precision::Mixed);
                // at ν = 0.3 the two-domain answer itself
                assert!(nu > 0.4 || !split.stats.precision_fallback);
                if split.stats.precision_fallback {
                    // abandoned for the plain double factor: its figures
                    // are not reported as the answer's
                    assert!(split.stats.substructure.is_none());
                    let note = split.stats.substructure_note.clone().unwrap_or_default();
                    assert!(note.contains("two-domain solve abandoned"), "{note}");
                } else {
                    let st = split.stats.substructure.as_ref().expect("two-domain stats");
                    assert!(st.separator_dofs > 0 && st.halves.iter().all(|h| h.dofs > 0));
                    assert_eq!(
                        st.halves[0].dofs + st.halves[1].dofs + st.separator_dofs,
                        split.stats.dofs
                    );
                }
                assert!(
                    split.stats.backward_error < 1e-15,
                    "{}",
                    split.stats.backward_error
                );
                assert!(split.stats.precision == "mixed" || split.stats.precision_fallback);
                let diff = plain
                    .displacement
                    .iter()
                    .zip(&split.displacement)
                    .fold(0.0f64, |a, (x, y)| a.max((x - y).abs()));
                assert!(
                    diff <= tol * umax,
                    "ν = {nu}, {threads} threads: {:.2e}",
                    diff / umax
                );
            }
            // auto: this model is below the size threshold
            let auto = solve(Substructure::Auto, 2, Precision::Mixed);
            assert!(auto.stats.substructure.is_none());
        }
    }

    /// When the two-domain factorization fails (here: a Young's modulus of
    /// 1e300 MPa overflows single precision) the solve falls back to the
    /// plain double factorization on K's rebuilt pattern and says so.
    #[test]
    fn two_domain_failure_falls_back_to_plain_double() {
        use crate::mesh::structured::{cantilever_model, BoxElement};
        let mut model = cantilever_model([12, 3, 3], BoxElement::Hex20, 1000.0).unwrap();
        model.materials[0].young = 1e300;
        let solve = |substructure, precision| {
            solve_static(
                &model,
                &SolveOptions {
                    recover_stress: false,
                    substructure,
                    threads: 2,
                    precision,
                    ..Default::default()
                },
            )
            .unwrap()
        };
        let split = solve(Substructure::On, Precision::Mixed);
        assert!(split.stats.precision_fallback);
        assert_eq!(split.stats.precision, "double");
        let note = split.stats.substructure_note.clone().unwrap_or_default();
        assert!(note.contains("two-domain solve abandoned"), "{note}");
        // the figures are the double solve's, not the abandoned attempt's
        assert!(split.stats.substructure.is_none());
        assert_eq!(split.stats.refinement_steps, 0);
        assert!(split.stats.backward_error < 1e-15);
        let plain = solve(Substructure::Off, Precision::Double);
        let umax = plain
            .displacement
            .iter()
            .fold(0.0f64, |a, b| a.max(b.abs()));
        assert!(umax > 0.0);
        for (a, b) in plain.displacement.iter().zip(&split.displacement) {
            assert!((a - b).abs() <= 1e-10 * umax);
        }
    }

    /// The symbolic analysis is reused for a new matrix with the same
    /// pattern: scaling K by 2 halves the solution.
    #[test]
    fn symbolic_factorization_is_reused() {
        use crate::fem::assembly::Assembly;
        use crate::fem::solver::parallelism;
        use crate::mesh::structured::{cantilever_model, BoxElement};
        let model = cantilever_model([6, 2, 2], BoxElement::Hex20, 1000.0).unwrap();
        let mut dofs = DofMap::new(&model).unwrap();
        let asm = Assembly::new(&model, &mut dofs, OrderingMethod::Metis).unwrap();
        let sys = asm.assemble(&model, &dofs).unwrap();
        let b = dofs.restrict(&load_vector(&model).unwrap());
        let mut chol =
            SparseCholesky::analyze(&asm.pattern, OrderingMethod::Metis, 0.0, parallelism(1))
                .unwrap();
        chol.factorize(&asm.pattern, &sys.values, Precision::Double, &|r| {
            r.to_string()
        })
        .unwrap();
        let mut x1 = b.clone();
        chol.solve_in_place(&mut x1);
        let doubled: Vec<f64> = sys.values.iter().map(|v| 2.0 * v).collect();
        chol.factorize(&asm.pattern, &doubled, Precision::Double, &|r| {
            r.to_string()
        })
        .unwrap();
        let mut x2 = b.clone();
        chol.solve_in_place(&mut x2);
        let m = x1.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        for (a, b) in x1.iter().zip(&x2) {
            assert!((a - 2.0 * b).abs() <= 1e-12 * m);
        }
    }

    /// A rigid coupling on one node (or collinear nodes) does not hold the
    /// rotations about that point (line), even with all reference DOFs fixed;
    /// a free reference rotation its nodes cannot feel is also named.
    #[test]
    fn coupling_on_too_few_nodes_is_caught() {
        use crate::fem::model::RigidCoupling;
        let mut mesh = Mesh::new();
        for (i, p) in HEX20_NODES.iter().enumerate() {
            mesh.add_node(i as u64 + 1, *p).unwrap();
        }
        mesh.add_element(1, ElementKind::C3D20, (0..20).collect())
            .unwrap();
        let base = Model {
            mesh,
            materials: vec![Material::new("steel", 200e3, 0.3).unwrap()],
            element_material: vec![0],
            ..Default::default()
        };
        let mut pin = base.clone();
        pin.couplings.push(RigidCoupling {
            name: "PIN".into(),
            reference_point: HEX20_NODES[0],
            nodes: vec![0],
            free: [false; 6],
            load: [0.0; 6],
        });
        let err = solve_static(&pin, &SolveOptions::default())
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("3 free rigid-body mode") && err.contains("rotation about"),
            "{err}"
        );
        // nodes 0 and 4 lie on the line x = y = −1 (parallel to z); the reference
        // on that line with rz free: the body is held by the face z = −1 in all
        // DOFs, so only the reference rotation is loose
        let mut axis = base.clone();
        for (i, p) in HEX20_NODES.iter().enumerate() {
            if p[2] == -1.0 && i != 0 {
                for k in 0..3 {
                    axis.dirichlet.push(Dirichlet {
                        node: i,
                        component: k,
                        value: 0.0,
                    });
                }
            }
        }
        let mut free = [false; 6];
        free[5] = true;
        axis.couplings.push(RigidCoupling {
            name: "AXIS".into(),
            reference_point: [-1.0, -1.0, 0.0],
            nodes: vec![0, 4, 16],
            free,
            load: [0.0; 6],
        });
        let err = solve_static(&axis, &SolveOptions::default())
            .unwrap_err()
            .to_string();
        assert!(err.contains("coupling 'AXIS' reference rz"), "{err}");
    }

    /// Two unit cubes side by side (x ∈ [−1, 1] and [1, 3], separate
    /// nodes on the shared face), the first clamped at z = −1: the second
    /// tied by equations u_b = u_a on every node pair of the face solves
    /// as one body (its face follows); tied at one node only, it keeps
    /// the three rotations about that node, named for the joined bodies.
    #[test]
    fn bodies_joined_by_equations() {
        use crate::fem::model::{Equation, EquationTerm, NodalForce};
        let mut mesh = Mesh::new();
        for (i, p) in HEX20_NODES.iter().enumerate() {
            mesh.add_node(i as u64 + 1, *p).unwrap();
        }
        for (i, p) in HEX20_NODES.iter().enumerate() {
            mesh.add_node(i as u64 + 101, [p[0] + 2.0, p[1], p[2]])
                .unwrap();
        }
        mesh.add_element(1, ElementKind::C3D20, (0..20).collect())
            .unwrap();
        mesh.add_element(2, ElementKind::C3D20, (20..40).collect())
            .unwrap();
        let mut model = Model {
            mesh,
            materials: vec![Material::new("steel", 200e3, 0.3).unwrap()],
            element_material: vec![0, 0],
            ..Default::default()
        };
        for (i, p) in HEX20_NODES.iter().enumerate() {
            if p[2] == -1.0 {
                for k in 0..3 {
                    model.dirichlet.push(Dirichlet {
                        node: i,
                        component: k,
                        value: 0.0,
                    });
                }
            }
        }
        // pairs (node of cube 2 at x = 1, node of cube 1 at x = 1)
        let pairs: Vec<(usize, usize)> = (0..20)
            .filter(|&i| HEX20_NODES[i][0] == -1.0)
            .map(|i| {
                let j = (0..20)
                    .find(|&j| {
                        HEX20_NODES[j][0] == 1.0
                            && HEX20_NODES[j][1] == HEX20_NODES[i][1]
                            && HEX20_NODES[j][2] == HEX20_NODES[i][2]
                    })
                    .unwrap();
                (20 + i, j)
            })
            .collect();
        let tie = |b: usize, a: usize, k: usize| Equation {
            terms: vec![
                EquationTerm {
                    node: b,
                    component: k,
                    coefficient: 1.0,
                },
                EquationTerm {
                    node: a,
                    component: k,
                    coefficient: -1.0,
                },
            ],
        };
        let mut tied = model.clone();
        for &(b, a) in &pairs {
            tied.equations.extend((0..3).map(|k| tie(b, a, k)));
        }
        tied.forces.push(NodalForce {
            node: 26,
            component: 2,
            value: -100.0,
        });
        let sol = solve_static(&tied, &SolveOptions::default()).unwrap();
        let u = &sol.displacement;
        assert!(u[3 * 26 + 2] < 0.0);
        for &(b, a) in &pairs {
            for k in 0..3 {
                assert!((u[3 * b + k] - u[3 * a + k]).abs() <= 1e-15 * u[3 * 26 + 2].abs());
            }
        }
        let mut pinned = model.clone();
        let (b, a) = pairs[0];
        pinned.equations.extend((0..3).map(|k| tie(b, a, k)));
        let err = solve_static(&pinned, &SolveOptions::default())
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("joined by equations") && err.contains("3 free rigid-body mode"),
            "{err}"
        );
    }

    #[test]
    fn missing_constraints_name_free_modes() {
        let mut mesh = Mesh::new();
        for (i, p) in HEX20_NODES.iter().enumerate() {
            mesh.add_node(i as u64 + 1, *p).unwrap();
        }
        mesh.add_element(1, ElementKind::C3D20, (0..20).collect())
            .unwrap();
        let mut model = Model {
            mesh,
            materials: vec![Material::new("steel", 200e3, 0.3).unwrap()],
            element_material: vec![0],
            ..Default::default()
        };
        let err = solve_static(&model, &SolveOptions::default())
            .unwrap_err()
            .to_string();
        assert!(err.contains("6 free rigid-body mode"), "{err}");
        // hold the face z = −1 in z only: x, y translations and rotation about z stay free
        for (i, p) in HEX20_NODES.iter().enumerate() {
            if p[2] == -1.0 {
                model.dirichlet.push(Dirichlet {
                    node: i,
                    component: 2,
                    value: 0.0,
                });
            }
        }
        let err = solve_static(&model, &SolveOptions::default())
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("3 free rigid-body mode") && err.contains("rotation about z"),
            "{err}"
        );
    }
}
