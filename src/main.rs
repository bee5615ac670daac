//! The `flank` command line: parses, calls the library, prints.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::{Parser, Subcommand};

use flank::fem::ordering::OrderingMethod;
use flank::fem::solver::Precision;
use flank::fem::static_analysis::{solve_static, SolveOptions};

#[derive(Parser)]
#[command(
    name = "flank",
    version,
    about = "Finite-element-first gear tooth contact: native 3D elasticity, FE contact, LTCA"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Solve a CalculiX/Abaqus linear static deck (C3D20, C3D20R, C3D15).
    Solve {
        /// The input deck (.inp).
        deck: PathBuf,
        /// Output directory (displacements.csv, stresses.csv, reactions.csv, result.vtu, summary.json).
        #[arg(long, default_value = "out")]
        out: PathBuf,
        /// Fill-reducing ordering for the Cholesky factorization.
        #[arg(long, value_enum, default_value_t = OrderingMethod::Metis)]
        ordering: OrderingMethod,
        /// Threads (0 = all cores).
        #[arg(long, default_value_t = 0)]
        threads: usize,
        /// Arithmetic of the factorization: double, or mixed (f32 factor,
        /// f64 iterative refinement, automatic fallback to double).
        #[arg(long, value_enum, default_value_t = Precision::Double)]
        precision: Precision,
        /// Skip stress recovery and reactions.
        #[arg(long)]
        no_stress: bool,
        /// No progress display.
        #[arg(long, short)]
        quiet: bool,
    },
    /// Read a gear-pair scene, check the pair (shifts vs centre distance,
    /// undercut, pointed tips, clearance, interference, contact ratio) and
    /// print the pair report (ε_α, ε_β, working pressure angle, W_k, …) as JSON.
    Check {
        /// The scene file (.toml).
        scene: PathBuf,
    },
    /// Mesh both bodies of a gear-pair scene (sector of N teeth, hex20 or
    /// wedge15, flank micro-geometry applied): writes pinion.inp and
    /// gear.inp (bore clamped, nominal single-pair
    /// normal force T/r_b1 at the working pitch point of the middle tooth),
    /// .vtu files, <body>_flank_uv.csv (flank node parameters) and
    /// mesh_report.json.
    Mesh {
        /// The scene file (.toml).
        scene: PathBuf,
        /// Output directory.
        #[arg(long, default_value = "out")]
        out: PathBuf,
        /// Flank element size (mm); overrides the scene's [mesh] flank_size_mm.
        #[arg(long)]
        flank_size: Option<f64>,
        /// Base element size (mm); overrides the scene's [mesh] base_size_mm.
        #[arg(long)]
        base_size: Option<f64>,
        /// Write the decks without the nominal load.
        #[arg(long)]
        no_load: bool,
        /// Element type; overrides the scene's [mesh] element.
        #[arg(long, value_enum)]
        element: Option<MeshElement>,
        /// Mesher: native (structured, graded to the flank) or gmsh
        /// (unstructured from a size field; needs a build with
        /// `--features gmsh` and libgmsh-dev).
        #[arg(long, value_enum, default_value_t = MesherChoice::Native)]
        mesher: MesherChoice,
    },
    /// Convert a gmsh mesh (.msh 4.1 ASCII; 20-node hexahedra and 15-node
    /// prisms, i.e. exported with Mesh.SecondOrderIncomplete = 1) into a
    /// CalculiX deck: physical groups of dimension 0–2 become node sets,
    /// volume groups element sets; one linear-elastic material, no boundary
    /// conditions or loads.
    Import {
        /// The gmsh mesh (.msh).
        mesh: PathBuf,
        /// Output deck (.inp).
        #[arg(long)]
        out: PathBuf,
        /// Young's modulus of the material (MPa).
        #[arg(long, default_value_t = 206000.0)]
        young_modulus: f64,
        /// Poisson's ratio of the material.
        #[arg(long, default_value_t = 0.3)]
        poisson_ratio: f64,
    },
    /// Nodal compliance tensors of a scene's gear bodies (bore clamped; the
    /// loaded flank FLANK_R<k> of every tooth by default) from one
    /// factorization each: writes <body>.inp (as `flank mesh`),
    /// <body>.compliance.h5 (built with --features hdf5) or
    /// <body>.compliance.bin, <body>_cnn.svg/.png (normal self-compliance over
    /// the middle tooth's flank) and summary.json.
    Compliance {
        /// The scene file (.toml).
        scene: PathBuf,
        /// Output directory.
        #[arg(long, default_value = "out")]
        out: PathBuf,
        #[command(flatten)]
        sizes: SectorArgs,
        /// Bodies, comma-separated.
        #[arg(long, value_delimiter = ',', default_values_t = ["pinion".to_string(), "gear".to_string()])]
        bodies: Vec<String>,
        /// Method (schur: flank DOFs ordered last, fastest; blocked:
        /// unit right-hand sides); overrides [analyses.compliance].
        #[arg(long, value_enum)]
        method: Option<flank::compliance::Method>,
        /// Flanks carrying tensors; overrides [analyses.compliance].
        #[arg(long, value_enum)]
        flanks: Option<flank::compliance::FlankSelection>,
        /// Clamp the sector cut faces CUT_A and CUT_B as well as the bore.
        #[arg(long)]
        clamp_cuts: bool,
        /// Threads (0 = all cores).
        #[arg(long, default_value_t = 0)]
        threads: usize,
        /// Memory for the blocked method's right-hand sides (MB).
        #[arg(long)]
        memory_budget_mb: Option<f64>,
        /// Right-hand sides per block (blocked method; 0 = from the budget).
        #[arg(long, default_value_t = 0)]
        block_size: usize,
        /// Campaign cache directory: tensors kept by key and reused.
        #[arg(long)]
        cache: Option<PathBuf>,
        /// File format (default: hdf5 with the feature, else native).
        #[arg(long, value_enum)]
        format: Option<flank::compliance::FileFormat>,
        /// Skip the condition-number estimate of C.
        #[arg(long)]
        no_condition: bool,
        /// Write the decks without the nominal load (as `flank mesh --no-load`).
        #[arg(long)]
        no_load: bool,
        /// Print nothing but errors.
        #[arg(long, short)]
        quiet: bool,
    },
    /// Compliance-matrix LTCA over a mesh cycle (the scene's [analyses.ltca]):
    /// both bodies' compliance tensors (computed once, cached beside the
    /// decks in --out), then per roll angle the unloaded TCA, the normal
    /// compliance of the candidate points and the contact QP. Writes
    /// ltca_cycle.csv, ltca_points.csv, summary.json and plots.
    Ltca {
        /// The scene file (.toml).
        scene: PathBuf,
        /// Output directory.
        #[arg(long, default_value = "out")]
        out: PathBuf,
        /// Compliance mesh (default m_n/8 flank, m_n/2 base).
        #[command(flatten)]
        sizes: SectorArgs,
        /// Roll angles (deg, flank's convention), comma-separated.
        #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
        roll_angles: Option<Vec<f64>>,
        /// K: candidate points per contact line.
        #[arg(long)]
        points_per_line: Option<usize>,
        /// QP solver: active-set or clarabel.
        #[arg(long)]
        solver: Option<String>,
        /// Local contact deformation model.
        #[arg(long, value_enum)]
        local: Option<flank::ltca::local::LocalModel>,
        /// FE cell half-width across the line in flank element sizes.
        #[arg(long)]
        fe_cell_factor: Option<f64>,
        /// A campaign cache of compliance tensors (directory).
        #[arg(long)]
        cache: Option<PathBuf>,
        /// Skip the condition number of F at every position (reported by
        /// default; not part of the timed solve).
        #[arg(long)]
        no_condition: bool,
        /// Threads (0 = all cores).
        #[arg(long, default_value_t = 0)]
        threads: usize,
        /// Print nothing but errors.
        #[arg(long, short)]
        quiet: bool,
    },
    /// LTCA against FE contact at the same roll angles: LTCA at several K,
    /// FE contact at several flank element sizes (the finest is the
    /// reference). Writes compare.json, compare.md and error_vs_time plots.
    Compare {
        /// The scene file (.toml).
        scene: PathBuf,
        /// Output directory.
        #[arg(long, default_value = "out")]
        out: PathBuf,
        /// K values of the LTCA runs.
        #[arg(long, value_delimiter = ',', default_value = "5,10,20,40")]
        points_per_line: Vec<usize>,
        /// FE-contact flank element sizes (mm); the smallest is the reference.
        #[arg(long, value_delimiter = ',', default_value = "1.0,0.5")]
        fe_flank_sizes: Vec<f64>,
        /// FE-contact base element size (mm); default the scene's [mesh].
        #[arg(long)]
        fe_base_size: Option<f64>,
        /// Roll angles (deg); default: the middle pair's engagement ± 2 steps.
        #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
        roll_angles: Option<Vec<f64>>,
        /// Step of the default roll angles (deg).
        #[arg(long, default_value_t = 1.0)]
        roll_step: f64,
        /// LTCA compliance mesh (default m_n/8 flank, m_n/2 base).
        #[command(flatten)]
        sizes: SectorArgs,
        /// Local contact deformation model of the LTCA.
        #[arg(long, value_enum)]
        local: Option<flank::ltca::local::LocalModel>,
        /// Threads (0 = all cores).
        #[arg(long, default_value_t = 0)]
        threads: usize,
        /// Print nothing but errors.
        #[arg(long, short)]
        quiet: bool,
    },
    /// FE contact over a mesh cycle (the scene's [analyses.contact]): both
    /// sectors meshed and placed in mesh, pinion hub coupled to a reference
    /// node loaded by the torque, gear hub clamped, one contact solve per
    /// roll angle with the stiffness factorized once. Writes
    /// mesh_cycle.csv, summary.json (contact_ratio, single_pair_force_n,
    /// positions, time_per_position_s, nodes, ...), force_per_tooth and
    /// transmission_error plots (SVG, PNG) and roll_<angle>deg.vtu.
    Run {
        /// The scene file (.toml).
        scene: PathBuf,
        /// Output directory.
        #[arg(long, default_value = "out")]
        out: PathBuf,
        #[command(flatten)]
        sizes: SectorArgs,
        /// Roll angles (deg, flank's convention: 0 = middle pair at the pitch
        /// point), comma-separated; overrides the scene's.
        #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
        roll_angles: Option<Vec<f64>>,
        /// Roll angles in the scene's reference convention
        /// (reference_single_contact_start_deg, e.g. the paper's angles).
        #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
        reference_angles: Option<Vec<f64>>,
        /// Normal contact law; overrides the scene's.
        #[arg(long, value_enum)]
        law: Option<flank::mesh_cycle::ContactLaw>,
        /// Penalty slope as a multiple of the automatic default.
        #[arg(long)]
        penalty_factor: Option<f64>,
        /// Body carrying the slave nodes (auto: the body whose tip edge can touch,
        /// per tooth pair and position); overrides the scene's.
        #[arg(long, value_enum)]
        slave: Option<flank::mesh_cycle::SlaveBody>,
        /// Coulomb friction coefficient of the flanks (0…1); overrides the
        /// scene's friction_mu.
        #[arg(long)]
        friction_mu: Option<f64>,
        /// Write no VTU files.
        #[arg(long)]
        no_vtu: bool,
        /// Also write a CalculiX deck per position (roll_<angle>deg.inp):
        /// the pair model at its placed coordinates, for ccx.
        #[arg(long)]
        decks: bool,
        /// Do not bisect the middle pair's contact limits.
        #[arg(long)]
        no_refine: bool,
        /// Threads (0 = all cores).
        #[arg(long, default_value_t = 0)]
        threads: usize,
        /// Print nothing but errors.
        #[arg(long, short)]
        quiet: bool,
    },
    /// Write the benchmark cantilever as a CalculiX deck: a box L × 10 × 10 mm
    /// (L = 10·nx/ny mm … so elements are cubes), clamped at x = 0, 1 kN tip
    /// load in −y spread over the tip face nodes.
    Cantilever {
        /// Elements along x, y, z.
        #[arg(long, value_delimiter = ',', default_values_t = [100, 10, 10])]
        cells: Vec<usize>,
        /// Element type.
        #[arg(long, value_enum, default_value_t = DeckElement::C3d20)]
        element: DeckElement,
        /// Output deck.
        #[arg(long, default_value = "cantilever.inp")]
        out: PathBuf,
    },
}

#[derive(Clone, Copy, PartialEq, clap::ValueEnum)]
enum MesherChoice {
    Native,
    Gmsh,
}

/// Sector mesh sizes and element of the scene's bodies, overriding its [mesh].
#[derive(clap::Args, Clone, Copy)]
struct SectorArgs {
    /// Flank element size (mm); overrides the scene's [mesh] flank_size_mm.
    #[arg(long)]
    flank_size: Option<f64>,
    /// Base element size (mm); overrides the scene's [mesh] base_size_mm.
    #[arg(long)]
    base_size: Option<f64>,
    /// Element type; overrides the scene's [mesh] element.
    #[arg(long, value_enum)]
    element: Option<MeshElement>,
}

impl SectorArgs {
    fn body_options(self, with_load: bool) -> flank::compliance::body::BodyMeshOptions {
        flank::compliance::body::BodyMeshOptions {
            flank_size: self.flank_size,
            base_size: self.base_size,
            with_load,
            element: self.element.map(|e| match e {
                MeshElement::Hex20 => flank::scene::ElementKind::Hex20,
                MeshElement::Wedge15 => flank::scene::ElementKind::Wedge15,
            }),
        }
    }
}

#[derive(Clone, Copy, PartialEq, clap::ValueEnum)]
enum MeshElement {
    Hex20,
    Wedge15,
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum DeckElement {
    C3d20,
    C3d20r,
    C3d15,
}

fn main() -> std::process::ExitCode {
    match run(Cli::parse()) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            // the whole context chain, no backtrace: the message says what and where
            eprintln!("error: {e:#}");
            std::process::ExitCode::FAILURE
        }
    }
}

fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Solve {
            deck,
            out,
            ordering,
            threads,
            precision,
            no_stress,
            quiet,
        } => {
            let parsed = flank::mesh::inp::read_deck(&deck)?;
            for w in &parsed.warnings {
                eprintln!("warning: {}:{}: {}", deck.display(), w.line, w.message);
            }
            if !parsed.model.contact.is_empty() {
                return solve_contact_deck(
                    &deck, &out, &parsed, ordering, threads, !no_stress, quiet, precision,
                );
            }
            let options = SolveOptions {
                ordering,
                threads,
                recover_stress: !no_stress,
                progress: !quiet,
                precision,
            };
            let sol = solve_static(&parsed.model, &options)
                .with_context(|| format!("solving {}", deck.display()))?;
            let extra = serde_json::json!({
                "deck": deck.display().to_string(),
                "warnings": parsed.warnings.len(),
            });
            flank::report::solution::write_solution(&out, &parsed.model, &sol, extra)?;
            let s = &sol.stats;
            if !quiet {
                println!(
                    "{} nodes, {} elements, {} DOFs; nnz(L) = {} ({}); assembly {:.3} s, ordering {:.3} s, factorization {:.3} s ({:.1} GFLOP/s), solve {:.3} s; residual {:.1e}; peak memory {:.0} MB",
                    s.nodes, s.elements, s.dofs, s.nnz_factor, s.ordering, s.assembly_s, s.ordering_s, s.factorization_s, s.factorization_gflops, s.solve_s, s.relative_residual, s.peak_memory_mb
                );
                println!("results in {}", out.display());
            }
        }
        Command::Mesh {
            scene,
            out,
            flank_size,
            base_size,
            no_load,
            element,
            mesher,
        } => mesh_scene(
            &scene, &out, flank_size, base_size, !no_load, element, mesher,
        )?,
        Command::Import {
            mesh,
            out,
            young_modulus,
            poisson_ratio,
        } => {
            let m = flank::mesh::msh::read_msh(&mesh)?;
            let ne = m.elements.len();
            let model = flank::fem::model::Model {
                materials: vec![flank::fem::material::Material::new(
                    "MATERIAL",
                    young_modulus,
                    poisson_ratio,
                )?],
                element_material: vec![0; ne],
                mesh: m,
                ..Default::default()
            };
            flank::mesh::inp::write_deck(&model, &out)?;
            let mesh = &model.mesh;
            let hex = mesh.elements.iter().filter(|e| e.kind.node_count() == 20);
            let hex = hex.count();
            let sets: Vec<&str> = mesh.node_sets.keys().map(|k| k.as_str()).collect();
            println!(
                "wrote {} ({} nodes, {hex} C3D20 + {} C3D15 elements; node sets: {})",
                out.display(),
                mesh.node_count(),
                ne - hex,
                if sets.is_empty() {
                    "none".to_string()
                } else {
                    sets.join(", ")
                }
            );
        }
        Command::Check { scene } => {
            let scene = flank::scene::read_scene(&scene)?;
            let report = flank::geometry::pair::check_pair(&scene.pair)?;
            let mut json = serde_json::to_value(&report)?;
            // ISO 6336-1 single and mesh stiffness: the plausibility band for FE stiffness
            let stiffness =
                flank::geometry::iso6336::tooth_stiffness(&scene.pair, report.contact_ratio);
            json["iso6336_stiffness_n_per_mm_um"] = match stiffness {
                Ok(s) => serde_json::to_value(s)?,
                Err(e) => serde_json::Value::String(format!("not applicable: {e}")),
            };
            println!("{}", serde_json::to_string_pretty(&json)?);
        }
        Command::Compliance {
            scene,
            out,
            sizes,
            bodies,
            method,
            flanks,
            clamp_cuts,
            threads,
            memory_budget_mb,
            block_size,
            cache,
            format,
            no_condition,
            no_load,
            quiet,
        } => {
            use flank::compliance::run::{run_scene, RunOptions};
            let options = RunOptions {
                out: out.clone(),
                mesh: sizes.body_options(!no_load),
                bodies,
                method,
                flanks,
                clamp_cuts,
                threads,
                memory_budget_mb,
                block_size,
                cache,
                format,
                condition: !no_condition,
            };
            let summary = run_scene(&scene, &options)
                .with_context(|| format!("compliance of {}", scene.display()))?;
            if !quiet {
                if let Some(bodies) = summary["bodies"].as_object() {
                    for (name, b) in bodies {
                        let s = &b["stats"];
                        if s.is_null() {
                            println!(
                                "{name}: {} flank nodes, C {}×{} reused ({}, same cache key): {}",
                                b["flank_nodes"],
                                b["matrix_dim"],
                                b["matrix_dim"],
                                b["source"].as_str().unwrap_or(""),
                                b["file"].as_str().unwrap_or("")
                            );
                            continue;
                        }
                        println!(
                            "{name}: {} flank nodes, C {}×{} ({}); factorization {:.2} s, solve {:.2} s ({:.2}× its own factorization), κ(C) ≈ {:.3e}, C_nn on the pitch line κ = {:.3e}; {}",
                            b["flank_nodes"],
                            b["matrix_dim"],
                            b["matrix_dim"],
                            b["source"].as_str().unwrap_or(""),
                            s["factorization_s"].as_f64().unwrap_or(0.0),
                            s["solve_s"].as_f64().unwrap_or(0.0),
                            s["time_vs_factorization"].as_f64().unwrap_or(0.0),
                            s["condition"]["kappa"].as_f64().unwrap_or(f64::NAN),
                            b["contact_line"]["condition"].as_f64().unwrap_or(f64::NAN),
                            b["file"].as_str().unwrap_or("")
                        );
                    }
                }
                println!("wrote {}", out.display());
            }
        }
        Command::Run {
            scene,
            out,
            sizes,
            roll_angles,
            reference_angles,
            law,
            penalty_factor,
            slave,
            friction_mu,
            no_vtu,
            decks,
            no_refine,
            threads,
            quiet,
        } => {
            use flank::mesh_cycle::run::{run_scene, RunOptions};
            let options = RunOptions {
                out: out.clone(),
                mesh: sizes.body_options(false),
                threads,
                roll_angles_deg: roll_angles,
                reference_angles_deg: reference_angles,
                law,
                penalty_factor,
                slave,
                friction_mu,
                vtu: no_vtu.then_some(false),
                decks,
                refine_contact_limits: no_refine.then_some(false),
                quiet,
            };
            let s = run_scene(&scene, &options)
                .with_context(|| format!("FE contact mesh cycle of {}", scene.display()))?;
            if !quiet {
                let f = |k: &str| s[k].as_f64().unwrap_or(f64::NAN);
                println!(
                    "{} positions, {} nodes, {} DOFs; factorization {:.2} s once, {:.2} s per position; peak {:.0} MB",
                    s["positions"],
                    s["nodes"],
                    s["dofs"],
                    f("factorization_s"),
                    f("time_per_position_s"),
                    f("peak_memory_mb")
                );
                println!(
                    "contact ratio {:.4} (kinematic ε_α {:.4}); single-pair force {:.1} N vs T/(r_b1 cos β_b) = {:.1} N ({:+.2} %); TE peak-to-peak {:.2} µrad",
                    f("contact_ratio"),
                    f("contact_ratio_kinematic"),
                    f("single_pair_force_n"),
                    f("nominal_force_n"),
                    100.0 * f("single_pair_force_error"),
                    f("te_peak_to_peak_urad")
                );
                println!("contact law: {}", s["law"]);
                for n in s["notes"].as_array().into_iter().flatten() {
                    println!("note: {}", n.as_str().unwrap_or(""));
                }
                let w = s["warnings"].as_array().map_or(0, Vec::len);
                if w > 0 {
                    println!("{w} warning(s) in summary.json");
                }
                println!("wrote {}", out.display());
            }
        }
        Command::Ltca {
            scene,
            out,
            sizes,
            roll_angles,
            points_per_line,
            solver,
            local,
            fe_cell_factor,
            cache,
            no_condition,
            threads,
            quiet,
        } => {
            use flank::ltca::cycle::{run_scene, LtcaOptions};
            let solver = match solver {
                Some(s) => Some(
                    s.parse::<flank::ltca::qp::QpSolver>()
                        .map_err(|e| anyhow::anyhow!("--solver: {e}"))?,
                ),
                None => None,
            };
            let options = LtcaOptions {
                out: out.clone(),
                mesh: sizes.body_options(false),
                roll_angles_deg: roll_angles,
                points_per_line,
                solver,
                local,
                fe_cell_factor,
                cache,
                condition: !no_condition,
                threads,
                quiet,
            };
            let s = run_scene(&scene, &options)
                .with_context(|| format!("LTCA mesh cycle of {}", scene.display()))?;
            if !quiet {
                let f = |k: &str| s[k].as_f64().unwrap_or(f64::NAN);
                println!(
                    "{} positions, K = {}: {:.4} s for the cycle ({:.2} ms per position); compliance {:.1} s",
                    s["positions"],
                    s["points_per_line"],
                    f("cycle_s"),
                    1e3 * f("time_per_position_s"),
                    s["setup"]["compliance_s"].as_f64().unwrap_or(f64::NAN)
                );
                println!(
                    "contact ratio {:.4} (kinematic ε_α {:.4}); single-pair force {:.1} N vs T/(r_b1 cos β_b) = {:.1} N ({:+.2} %); max KKT residual {:.1e}",
                    f("contact_ratio"),
                    f("contact_ratio_kinematic"),
                    f("single_pair_force_n"),
                    f("nominal_force_n"),
                    100.0 * f("single_pair_force_error"),
                    f("max_kkt")
                );
                for n in s["notes"].as_array().into_iter().flatten() {
                    println!("note: {}", n.as_str().unwrap_or(""));
                }
                for n in s["kkt_flagged"].as_array().into_iter().flatten() {
                    println!("flagged: {}", n.as_str().unwrap_or(""));
                }
                println!("wrote {}", out.display());
            }
        }
        Command::Compare {
            scene,
            out,
            points_per_line,
            fe_flank_sizes,
            fe_base_size,
            roll_angles,
            roll_step,
            sizes,
            local,
            threads,
            quiet,
        } => {
            use flank::compare::{compare_scene, CompareOptions};
            let options = CompareOptions {
                out: out.clone(),
                points_per_line,
                fe_flank_sizes,
                fe_base_size,
                roll_angles_deg: roll_angles,
                roll_step_deg: roll_step,
                ltca: flank::ltca::cycle::LtcaOptions {
                    mesh: sizes.body_options(false),
                    local,
                    threads,
                    quiet: true,
                    ..Default::default()
                },
                threads,
                quiet,
            };
            let s = compare_scene(&scene, &options)
                .with_context(|| format!("LTCA against FE contact for {}", scene.display()))?;
            if !quiet {
                let f = |k: &str| s[k].as_f64().unwrap_or(f64::NAN);
                println!(
                    "best {} against {}: load sharing {:.4}, TE {:.4}, p_max {:.4}; LTCA cycle {:.4} s, FE cycle {:.1} s (+{:.1} s setup): {:.0}×",
                    s["best_ltca"].as_str().unwrap_or(""),
                    s["reference"].as_str().unwrap_or(""),
                    f("load_sharing_rel_err"),
                    f("te_rel_err"),
                    f("pmax_rel_err"),
                    f("ltca_cycle_s"),
                    f("fe_cycle_s"),
                    f("fe_setup_s"),
                    f("speedup")
                );
                println!("wrote {}", out.display());
            }
        }
        Command::Cantilever {
            cells,
            element,
            out,
        } => {
            let kind = match element {
                DeckElement::C3d20 => flank::mesh::structured::BoxElement::Hex20,
                DeckElement::C3d20r => flank::mesh::structured::BoxElement::Hex20R,
                DeckElement::C3d15 => flank::mesh::structured::BoxElement::Wedge15,
            };
            if cells.len() != 3 || cells.contains(&0) {
                anyhow::bail!("--cells needs three positive counts, e.g. --cells 100,10,10");
            }
            let model = flank::mesh::structured::cantilever_model(
                [cells[0], cells[1], cells[2]],
                kind,
                1000.0,
            )?;
            flank::mesh::inp::write_deck(&model, &out)?;
            println!(
                "wrote {} ({} nodes, {} elements)",
                out.display(),
                model.mesh.node_count(),
                model.mesh.elements.len()
            );
        }
    }
    Ok(())
}

/// Element counts by CalculiX type name, e.g. {"C3D15": 1234}.
fn elements_by_type(mesh: &flank::mesh::Mesh) -> serde_json::Value {
    let mut counts = std::collections::BTreeMap::<String, usize>::new();
    for e in &mesh.elements {
        *counts.entry(e.kind.name().to_string()).or_default() += 1;
    }
    serde_json::json!(counts)
}

/// `flank mesh`: both bodies of a scene, decks, VTU, flank parameters, report.
fn mesh_scene(
    path: &std::path::Path,
    out: &std::path::Path,
    flank_size: Option<f64>,
    base_size: Option<f64>,
    with_load: bool,
    element: Option<MeshElement>,
    mesher: MesherChoice,
) -> Result<()> {
    use flank::geometry::involute::base_radius;
    use flank::mesh::gear_body::{gear_body_with, Mesher, GMSH_AVAILABLE, GMSH_MISSING};
    use flank::mesh::gear_sector::SectorOptions;
    use std::io::Write;
    let scene = flank::scene::read_scene(path)?;
    let report = flank::geometry::pair::check_pair(&scene.pair)?;
    let hex20 = match element {
        Some(e) => e == MeshElement::Hex20,
        None => scene.mesh.element == flank::scene::ElementKind::Hex20,
    };
    let element_kind = if hex20 {
        flank::mesh::ElementKind::C3D20
    } else {
        flank::mesh::ElementKind::C3D15
    };
    if mesher == MesherChoice::Gmsh && !GMSH_AVAILABLE {
        anyhow::bail!("--mesher gmsh: {GMSH_MISSING}");
    }
    let mn = scene.pair.pinion.normal_module;
    let flank_size = flank_size.or(scene.mesh.flank_size).unwrap_or(mn / 8.0);
    let base_size = base_size.or(scene.mesh.base_size).unwrap_or(mn / 2.0);
    if !(flank_size > 0.0 && base_size >= flank_size) {
        anyhow::bail!(
            "element sizes must satisfy 0 < flank size ({flank_size}) ≤ base size ({base_size})"
        );
    }
    let options = SectorOptions {
        teeth: scene.mesh.teeth_in_sector as usize,
        flank_size,
        base_size,
        face_layers: 0,
        element: element_kind,
    };
    std::fs::create_dir_all(out)?;
    let cos_aw = report.working_pressure_angle_rad.cos();
    let force = scene.load.torque_nmm / base_radius(&scene.pair.pinion);
    let modifications = scene.flank_modifications()?;
    let mut bodies = serde_json::Map::new();
    for (i, (name, spec, material)) in [
        ("pinion", &scene.pair.pinion, &scene.pinion_material),
        ("gear", &scene.pair.gear, &scene.gear_material),
    ]
    .into_iter()
    .enumerate()
    {
        let rb = base_radius(spec);
        let load = (with_load && force > 0.0).then_some((force, rb / cos_aw));
        let mesher = match mesher {
            MesherChoice::Native => Mesher::Native,
            MesherChoice::Gmsh => Mesher::Gmsh(element_kind),
        };
        let mut body = gear_body_with(spec, name, material, &options, mesher, load)?;
        let modified = match &modifications[i] {
            Some(m) => {
                for w in m.warnings() {
                    eprintln!("warning: {name}: {w}");
                }
                Some(body.modify_flanks(spec, m)?)
            }
            None => None,
        };
        let mesh = &body.model.mesh;
        flank::mesh::inp::write_deck(&body.model, &out.join(format!("{name}.inp")))?;
        flank::report::vtu::write_vtu(&out.join(format!("{name}.vtu")), mesh, &[], &[])?;
        let uv_path = out.join(format!("{name}_flank_uv.csv"));
        let mut w = std::io::BufWriter::new(std::fs::File::create(&uv_path)?);
        writeln!(w, "node,u,v_mm")?;
        let mut uv: Vec<(&usize, &(f64, f64))> = body.sector.flank_uv.iter().collect();
        uv.sort_by_key(|(n, _)| **n);
        for (&n, &(u, v)) in uv {
            writeln!(w, "{},{:e},{:e}", mesh.node_labels[n], u, v)?;
        }
        w.flush()?;
        let flank_nodes: usize = mesh
            .node_sets
            .iter()
            .filter(|(k, _)| k.starts_with("FLANK_"))
            .map(|(_, v)| v.len())
            .sum();
        bodies.insert(
            name.to_string(),
            serde_json::json!({
                "nodes": mesh.node_count(),
                "elements": elements_by_type(mesh),
                "flank_nodes": flank_nodes,
                "teeth_in_sector": options.teeth,
                "flank_size_mm": flank_size,
                "base_size_mm": base_size,
                "mesher": if mesher == Mesher::Native { "native" } else { "gmsh" },
                "min_scaled_jacobian": body.sector.quality.min_scaled_jacobian,
                "max_aspect_ratio": body.sector.quality.max_aspect_ratio,
                "flank_modification": modified,
                "base_radius_mm": rb,
                "nominal_load": body.load.map(|(n, f)| serde_json::json!({
                    "node": mesh.node_labels[n], "force_n": f, "normal_force_n": force
                })),
            }),
        );
        println!(
            "{name}: {} nodes, {} elements, min scaled Jacobian {:.3}",
            mesh.node_count(),
            mesh.elements.len(),
            body.sector.quality.min_scaled_jacobian
        );
    }
    let summary = serde_json::json!({
        "scene": path.display().to_string(),
        "bodies": bodies,
        "pair": {
            "contact_ratio": report.contact_ratio,
            "overlap_ratio": report.overlap_ratio,
            "working_pressure_angle_deg": report.working_pressure_angle_deg,
        },
    });
    std::fs::write(
        out.join("mesh_report.json"),
        serde_json::to_string_pretty(&summary)? + "\n",
    )?;
    println!("wrote {}", out.display());
    Ok(())
}

/// `flank solve` on a deck with contact pairs: the contact solve, then the
/// usual outputs plus contact.csv, contact fields in result.vtu and the
/// contact figures in summary.json.
#[allow(clippy::too_many_arguments)]
fn solve_contact_deck(
    deck: &std::path::Path,
    out: &std::path::Path,
    parsed: &flank::mesh::inp::Deck,
    ordering: OrderingMethod,
    threads: usize,
    recover_stress: bool,
    quiet: bool,
    precision: Precision,
) -> Result<()> {
    if precision != Precision::Double {
        eprintln!("warning: contact solves factorize in double precision (--precision ignored)");
    }
    let options = flank::contact::ContactOptions {
        ordering,
        threads,
        recover_stress,
        ..Default::default()
    };
    let sol = flank::contact::solve_contact(&parsed.model, &options)
        .with_context(|| format!("solving {}", deck.display()))?;
    for w in &sol.summary.warnings {
        eprintln!("warning: {w}");
    }
    let extra = serde_json::json!({
        "deck": deck.display().to_string(),
        "warnings": parsed.warnings.len() + sol.summary.warnings.len(),
    });
    flank::report::solution::write_contact_solution(out, &parsed.model, &sol, extra)?;
    if !quiet {
        let s = &sol.solution.stats;
        let a = &sol.summary.active_set;
        println!(
            "{} nodes, {} elements, {} DOFs; factorization {:.3} s; contact: {} active-set iterations, {} closed, {} solves; law violation {:.1e} mm, complementarity {:.1e} N·mm; residual {:.1e}",
            s.nodes, s.elements, s.dofs, s.factorization_s, a.iterations, a.active, a.columns, a.max_violation, a.complementarity, s.relative_residual
        );
        for p in &sol.summary.pairs {
            let law = match p.law {
                flank::contact::pairing::NormalLaw::Hard => "hard".to_string(),
                flank::contact::pairing::NormalLaw::Penalty { slope, automatic } => format!(
                    "penalty {slope:.4e} MPa/mm{}",
                    if automatic { " (automatic)" } else { "" }
                ),
            };
            println!(
                "pair {} / {} ({law}): {} of {} candidates closed, total normal force {:.6e} N, max pressure {:.6e} MPa",
                p.slave, p.master, p.closed, p.candidates, p.total_normal_force, p.max_pressure
            );
            if let Some(f) = &p.friction {
                println!(
                    "  friction μ = {}{}: {} stick, {} slip; tangential force {:.6e} N ({:.6e}, {:.6e}, {:.6e}); max slip {:.3e} mm",
                    f.mu,
                    f.stick_slope
                        .map_or(" (hard stick)".to_string(), |k| format!(", stick slope {k:.4e} MPa/mm")),
                    f.stick,
                    f.slip,
                    f.total_tangential_force,
                    f.tangential_resultant[0],
                    f.tangential_resultant[1],
                    f.tangential_resultant[2],
                    f.max_slip
                );
            }
        }
        if let Some(f) = &sol.summary.friction {
            println!(
                "friction: {} fixed-point iterations ({}), polish {}; Coulomb residual {:.1e} N, stick/slip complementarity {:.1e} N·mm; {} stiffness solves",
                f.iterations,
                if f.converged { "converged" } else { "ITERATION LIMIT" },
                if f.polished { "exact" } else { "not applied" },
                f.coulomb_residual,
                f.stick_slip_complementarity,
                f.columns
            );
        }
        println!("results in {}", out.display());
    }
    Ok(())
}
