//! The short API of flank: load a scene (any pair kind), override its keys,
//! run an analysis, read its typed result. Everything here is also
//! reachable by its own module path; this page is where to start.
//!
//! | step | function | result |
//! |---|---|---|
//! | read a scene | [`load_scene`], [`load_scene_with`] (dotted keys overridden) | [`Scene`] |
//! | check the pair | [`check`] | [`PairCheck`] |
//! | ISO 23509 bevel/hypoid blank | [`blank`] | [`BlankDesign`] |
//! | unloaded TCA | [`tca`] | [`TcaSummary`] (in [`TcaRun`]) |
//! | compliance tensors | [`compliance`], [`compliance_of`], [`read_compliance_tensor`] | [`ComplianceSummary`]; [`ComplianceTensor`] |
//! | LTCA over the mesh cycle | [`ltca`] | [`LtcaResult`] |
//! | FE contact over the mesh cycle | [`fe_mesh_cycle`] | [`RunSummary`] |
//! | LTCA against FE contact | [`compare`] | [`CompareSummary`] |
//! | a campaign of variants | [`campaign`], [`campaign_collect`] | [`CampaignRun`] (the collected [`CampaignTable`]) |
//!
//! Each analysis takes the options of its command: a field left `None`
//! falls back to the scene's `[analyses.*]` key, else to the default
//! (docs/scene.md), and the files go to `options.out` (docs/outputs.md).
//!
//! ```
//! use flank::api::{load_scene, load_scene_with, PairKind};
//! use std::path::Path;
//!
//! let root = Path::new(env!("CARGO_MANIFEST_DIR"));
//! let spur = load_scene(root.join("papers/seed002-spur/scene.toml"))?;
//! assert_eq!(spur.kind, PairKind::Spur);
//! // the same scene at a third of its torque: the override passes the file's checks
//! let light = load_scene_with(
//!     root.join("papers/seed002-spur/scene.toml"),
//!     &[("load.torque_nm", toml::Value::Float(104.0))],
//! )?;
//! assert!((light.load.torque_nmm - 104_000.0).abs() < 1e-9);
//! // a value the scene refuses names the override
//! let refused = load_scene_with(
//!     root.join("papers/seed003-hypoid/scene_eased.toml"),
//!     &[("load.torque_nm", toml::Value::Float(-1.0))],
//! )
//! .unwrap_err();
//! assert!(refused.to_string().contains("with the overrides load.torque_nm"));
//! # Ok::<(), flank::error::FlankError>(())
//! ```
//!
//! An LTCA of any pair kind, read through its typed result (the same
//! fields for a spur and a hypoid pair; `examples/spur_ltca.rs` and
//! `examples/hypoid_ltca.rs` run it):
//!
//! ```no_run
//! use flank::api::{load_scene, ltca, LtcaOptions};
//!
//! let scene = load_scene("papers/seed003-hypoid/scene_eased.toml")?;
//! let result = ltca(&scene, &LtcaOptions { out: "out/ltca".into(), ..Default::default() })?;
//! let cycle = result.first();
//! println!(
//!     "{} positions, TE {:.2} arcsec at the gear ({:.1} µrad at the pinion) peak-to-peak",
//!     cycle.positions, cycle.te_peak_to_peak_arcsec, cycle.te_peak_to_peak_urad
//! );
//! for step in &cycle.steps {
//!     println!("{:+.2}°: load shares {:?}", step.position.roll_deg, step.load_share);
//! }
//! # Ok::<(), flank::error::FlankError>(())
//! ```
#![warn(missing_docs)]

use std::path::{Path, PathBuf};

use crate::error::FlankError;

pub use crate::campaign::local::LocalReport as CampaignReport;
pub use crate::campaign::table::Table as CampaignTable;

pub use crate::compare::summary::{CompareKind, CompareSummary};
pub use crate::compare::CompareOptions;
pub use crate::compliance::body::BodyMeshOptions;
pub use crate::compliance::cache::FileFormat;
pub use crate::compliance::run::RunOptions as ComplianceOptions;
pub use crate::compliance::summary::ComplianceSummary;
pub use crate::compliance::ComplianceTensor;
pub use crate::geometry::bevel::BlankDesign;
pub use crate::ltca::cycle::LtcaOptions;
pub use crate::ltca::summary::{
    BevelLtcaSummary, CylindricalLtcaSummary, KindSummary, LtcaResult, LtcaStep, LtcaSummary,
};
pub use crate::mesh_cycle::run::RunOptions as FeOptions;
pub use crate::mesh_cycle::summary::{RunKind, RunSummary};
pub use crate::scene::check::PairCheck;
pub use crate::scene::{Gears, PairKind, Scene};
pub use crate::summary::SCHEMA_VERSION;
pub use crate::tca::run::{TcaCycles, TcaKind, TcaOptions, TcaRun, TcaSummary};

/// Reads and validates the scene file at `path`, of any pair kind
/// ([`crate::scene::read_scene`]); a bad key is a Parse error with its
/// file and line.
pub fn load_scene(path: impl AsRef<Path>) -> Result<Scene, FlankError> {
    crate::scene::read_scene(path.as_ref())
}

/// [`load_scene`] with dotted keys set first (`load.torque_nm`,
/// `pinion.micro.tip_relief_um`, `analyses.ltca.misalignment_urad.0`), as a
/// campaign's variants set them ([`crate::scene::overrides`]): the file is
/// checked as written, then with the overrides.
pub fn load_scene_with(
    path: impl AsRef<Path>,
    overrides: &[(&str, toml::Value)],
) -> Result<Scene, FlankError> {
    let path = path.as_ref();
    let text = crate::text_file::read_utf8(path)?;
    crate::scene::overrides::parse_scene_with(&text, path, overrides)
}

/// The check of the scene's pair ([`crate::scene::check::check`], `flank
/// check`): a cylindrical pair's contact ratios, working pressure angle and
/// ISO 6336-1 stiffness, or a bevel/hypoid pair's ISO 23509 blank and
/// cutting reports.
pub fn check(scene: &Scene) -> Result<PairCheck, FlankError> {
    crate::scene::check::check(scene)
}

/// The unloaded TCA over the mesh cycle with and without edge contact,
/// any pair kind ([`crate::tca::run::run`]): its tables, plots and
/// `summary.json` (and, with `options.sweep_mm`, the V–H sweep and chart)
/// in `options.out`. The result's `warnings` are for the user (the trace's
/// iteration limits, crossing flanks).
pub fn tca(scene: &Scene, options: &TcaOptions) -> Result<TcaRun, FlankError> {
    let mut run = crate::tca::run::run(scene, options)?;
    let out = &options.out;
    match &run.cycles {
        TcaCycles::Point {
            pair,
            with,
            without,
        } => {
            crate::report::tca_plot::plot_point_tca(out, pair.as_ref(), with, without)?;
        }
        TcaCycles::Line { with, without } => {
            let plots = crate::report::line_tca_plot::plot_line_tca(out, with, without)?;
            if let TcaKind::Line(l) = &mut run.summary.kind {
                l.plots = plots;
            }
        }
    }
    let text = serde_json::to_string_pretty(&run.summary)
        .map_err(|e| FlankError::Model(format!("summary: {e}")))?;
    crate::atomic_file::write(&out.join("summary.json"), text)?;
    let chart: Vec<crate::report::vh_plot::VhPoint> = crate::tca::run::vh_sweep(scene, options)?
        .into_iter()
        .map(|s| crate::report::vh_plot::VhPoint {
            offset_error_mm: s.offset_error_mm,
            pinion_axial_mm: s.pinion_axial_mm,
            centre_mm: s.centre_mm,
            te_peak_to_peak_arcsec: s.te_peak_to_peak_arcsec,
        })
        .collect();
    if options.sweep_mm.is_some() {
        crate::report::vh_plot::plot_vh_sweep(out, &chart)?;
    }
    Ok(run)
}

/// The compliance tensors of both bodies of the scene at `path`
/// ([`crate::compliance::run::run_scene`]): written into `options.out`,
/// their summary returned.
pub fn compliance(
    path: impl AsRef<Path>,
    options: &ComplianceOptions,
) -> Result<ComplianceSummary, FlankError> {
    crate::compliance::run::run_scene(path.as_ref(), options)
}

/// [`compliance`] of a parsed scene (one read with overrides,
/// [`load_scene_with`]; [`crate::compliance::run::run`]).
pub fn compliance_of(
    scene: &Scene,
    options: &ComplianceOptions,
) -> Result<ComplianceSummary, FlankError> {
    crate::compliance::run::run(scene, options)
}

/// Reads a compliance tensor file (`<body>.compliance.h5` or `.bin`, by
/// its extension; [`crate::compliance::cache::read`]): C, 3N × 3N, mm/N,
/// with its flank nodes and metadata.
pub fn read_compliance_tensor(path: impl AsRef<Path>) -> Result<ComplianceTensor, FlankError> {
    crate::compliance::cache::read(path.as_ref())
}

/// The compliance-matrix LTCA over the scene's mesh cycle, any pair kind
/// ([`crate::ltca::run::run`]); the files of docs/outputs.md in
/// `options.out`.
pub fn ltca(scene: &Scene, options: &LtcaOptions) -> Result<LtcaResult, FlankError> {
    crate::ltca::run::run(scene, options)
}

/// Quasi-static FE contact over the scene's mesh cycle, any pair kind
/// ([`crate::mesh_cycle::run::run`]); a spur/helical scene without
/// `[analyses] contact` is refused, as `flank run` refuses it.
pub fn fe_mesh_cycle(scene: &Scene, options: &FeOptions) -> Result<RunSummary, FlankError> {
    crate::mesh_cycle::run::asks_for_contact(scene)?;
    crate::mesh_cycle::run::run(scene, options)
}

/// The ISO 23509 blank design of a spiral bevel or hypoid pair from its
/// input set, a JSON object with the key names of the standard's Annex F
/// (`method`, `Sigma_deg`, `a_mm`, `z1`, `z2`, …; `flank blank`): the
/// design, whose [`BlankDesign::outputs`] are the printed outputs (Annex F
/// names, mm and degrees). Unknown keys and bad values are errors naming
/// the key.
pub fn blank(inputs_json: &str) -> Result<BlankDesign, FlankError> {
    let inputs = crate::geometry::bevel::BlankInputs::from_json(inputs_json)?;
    crate::geometry::bevel::blank_design(&inputs)
}

/// The LTCA against FE contact at the same positions, any pair kind
/// ([`crate::compare::run::compare`]): `compare.json`, `compare.md` and the
/// error-against-time plot in `options.out`.
pub fn compare(scene: &Scene, options: &CompareOptions) -> Result<CompareSummary, FlankError> {
    crate::compare::run::compare(scene, options)
}

/// Options of [`campaign`].
#[derive(Clone, Debug)]
pub struct CampaignOptions {
    /// The output folder (default: the campaign file's `out`, else beside
    /// it, as `flank campaign run`).
    pub out: Option<PathBuf>,
    /// The flank executable that runs the jobs: each block of jobs runs in
    /// a child process (`flank campaign run-task`), so that a crash or a
    /// kill loses only the job under way. A program of its own passes the
    /// path of the `flank` binary it ships with.
    pub exe: PathBuf,
    /// Parallel jobs (default: cores / threads per job).
    pub workers: Option<usize>,
    /// Memory budget (MB; default: the machine's available memory).
    pub memory_mb: Option<f64>,
    /// No progress output.
    pub quiet: bool,
}

/// What [`campaign`] did: the run's report (jobs done before, finished,
/// failed with their logs) and the collected table.
#[derive(Clone, Debug)]
pub struct CampaignRun {
    /// Jobs, workers, wall time, failures.
    pub report: CampaignReport,
    /// One row per job: inputs, figures (every number of its
    /// `summary.json`, flattened), run time, status.
    pub table: CampaignTable,
}

/// Runs the campaign file at `path` on this machine, any pair kind
/// ([`crate::campaign::local::run_local`], `flank campaign run`): the jobs
/// not done yet, in parallel, then the collected table (`table.csv`,
/// `table.parquet` and the plots in the output folder). Unlike `flank
/// campaign run`, an analysis option the command line would refuse is
/// not caught before the jobs start: the job fails with the message in
/// its log. An executable of another build than this library is refused
/// (job identities carry the build).
pub fn campaign(
    path: impl AsRef<Path>,
    options: &CampaignOptions,
) -> Result<CampaignRun, FlankError> {
    let c = crate::campaign::variants::Campaign::open(path.as_ref(), options.out.as_deref())?;
    same_build(&options.exe)?;
    let jobs = c.jobs()?;
    let report = crate::campaign::local::run_local(
        &c,
        &jobs,
        &crate::campaign::local::LocalOptions {
            exe: options.exe.clone(),
            workers: options.workers,
            memory_mb: options.memory_mb,
            batch: None,
            quiet: options.quiet,
        },
    )?;
    let table = crate::campaign::collect::collect(&c, &jobs)?;
    crate::campaign::collect::write_all(&c, &table)?;
    Ok(CampaignRun { report, table })
}

/// Refuses a `flank` executable of another build than this library: a
/// job's identity carries the build (its git commit), so the jobs it ran
/// would not be the ones this library looks for (every row "pending").
fn same_build(exe: &Path) -> Result<(), FlankError> {
    let ours = crate::campaign::variants::flank_version_static();
    let out = std::process::Command::new(exe)
        .arg("--version")
        .output()
        .map_err(|e| FlankError::Campaign(format!("cannot start {}: {e}", exe.display())))?;
    let theirs = String::from_utf8_lossy(&out.stdout);
    let theirs = theirs
        .trim()
        .strip_prefix("flank ")
        .unwrap_or(theirs.trim());
    if !out.status.success() || theirs != ours {
        return Err(FlankError::Campaign(format!(
            "{} is flank {theirs:?}, this library is flank {ours:?}: the jobs would run under another build's identities (their results would not be collected); pass the `flank` executable of the same build",
            exe.display()
        )));
    }
    Ok(())
}

/// Collects the campaign at `path` without running anything
/// ([`crate::campaign::collect::collect`], `flank campaign collect`): every
/// finished job's figures in the table (`table.csv`, `table.parquet`, the
/// convergence or Monte Carlo summaries and plots written to the output
/// folder, `out` or the campaign's own); jobs not done (pending, failed,
/// still queued on Slurm) are rows with their status.
pub fn campaign_collect(
    path: impl AsRef<Path>,
    out: Option<&Path>,
) -> Result<CampaignTable, FlankError> {
    let c = crate::campaign::variants::Campaign::open(path.as_ref(), out)?;
    let jobs = c.jobs()?;
    let table = crate::campaign::collect::collect(&c, &jobs)?;
    crate::campaign::collect::write_all(&c, &table)?;
    Ok(table)
}
