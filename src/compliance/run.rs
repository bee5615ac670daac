//! `flank compliance SCENE.toml`: the compliance tensors of a scene's gear
//! bodies, written beside their decks, with a summary and plots.

use std::path::{Path, PathBuf};
use std::time::Instant;

use nalgebra::{DMatrix, SymmetricEigen};

use crate::compliance::body::{
    active_flank_cut, active_margin_mm, any_scene_body, bevel_sector_options, flank_nodes_on,
    flank_uv_on, sector_options, BodyMeshOptions, SectorBody,
};
use crate::compliance::cache::{self, FileFormat};
use crate::compliance::contact_probe::{directional_matrices, retain_meshed, ProbePoint};
use crate::compliance::plot::plot_cnn;
use crate::compliance::summary::{
    BodySummary, ComplianceSummary, ContactLine, MeanContact, MeanContactProbe,
};
use crate::compliance::tensor_cache::{CacheOutcome, ComplianceCache};
use crate::compliance::{
    cache_key, clamp_sets, compliance_tensor, mesh_hash, region_cache_key, ComplianceOptions,
    ComplianceTensor, FlankInterpolator,
};
use crate::error::FlankError;
use crate::fem::static_analysis::peak_memory_mb;
use crate::scene::{read_scene, ComplianceAnalysis, Gears, Scene};
use crate::settings::{FlankRegion, FlankSelection, Method};
use crate::tca::major_axis::{major_axis_points, AxisPoint};
use crate::tca::point_contact::{point_tca, PointTcaSettings};

/// Options of [`run_scene`]; `None` fields fall back to the scene's
/// `[analyses.compliance]`, then to the defaults.
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    pub out: PathBuf,
    pub mesh: BodyMeshOptions,
    pub bodies: Vec<String>,
    pub method: Option<Method>,
    pub flanks: Option<FlankSelection>,
    pub clamp_cuts: bool,
    pub threads: usize,
    pub memory_budget_mb: Option<f64>,
    pub block_size: usize,
    /// A campaign cache directory (tensors by key), searched before computing.
    pub cache: Option<PathBuf>,
    pub format: Option<FileFormat>,
    pub condition: bool,
    /// The flank region (default: the scene's, else the full flank).
    pub region: Option<FlankRegion>,
}

/// [`BodyTensorOptions::region_u_min`] of body `name` of `scene` for
/// `region`: `None` for the full flank; for the active flank the cut of
/// [`crate::compliance::body::active_flank_cut`] with the margin of the
/// body's flank element size ([`active_margin_mm`]). The active region
/// needs the pair's start of active profile: spur/helical scenes only, for
/// now (a bevel/hypoid body's flank parameter u runs across the pitch
/// generatrix, and its active boundary is a curve in (u, v)).
pub fn region_cut(
    scene: &Scene,
    name: &str,
    region: FlankRegion,
    mesh: &BodyMeshOptions,
) -> Result<Option<f64>, FlankError> {
    match region {
        FlankRegion::Full => Ok(None),
        FlankRegion::Active if scene.is_bevel() => Err(FlankError::Model(
            "flank region `active` is implemented for spur/helical pairs only; a bevel/hypoid body takes `full`".into(),
        )),
        FlankRegion::Active => cylindrical_region_cut(scene, name, region, mesh),
    }
}

/// [`region_cut`] of a spur/helical scene.
pub fn cylindrical_region_cut(
    scene: &Scene,
    name: &str,
    region: FlankRegion,
    mesh: &BodyMeshOptions,
) -> Result<Option<f64>, FlankError> {
    match region {
        FlankRegion::Full => Ok(None),
        FlankRegion::Active => {
            let h = sector_options(scene, mesh)?.flank_size;
            active_flank_cut(scene, name, active_margin_mm(h)).map(Some)
        }
    }
}

/// C_nn (row-major K × K) on the contact line of `set` nearest to roll
/// angle `u`: point loads at the nodes of that profile row, located through
/// the interpolator (so the row is also a check of it), normals interpolated.
pub fn contact_line(
    t: &ComplianceTensor,
    set: &str,
    u: f64,
) -> Result<(ContactLine, Vec<f64>), FlankError> {
    let it = FlankInterpolator::new(t)?;
    let s = t
        .flank
        .set_index(set)
        .ok_or_else(|| FlankError::Model(format!("no flank set {set}")))?;
    let mut rows: std::collections::BTreeMap<u64, Vec<f64>> = Default::default();
    for (p, &si) in t.flank.uv.iter().zip(&t.flank.set_of) {
        if si as usize == s {
            rows.entry(p[0].to_bits()).or_default().push(p[1]);
        }
    }
    let full = rows.values().map(Vec::len).max().unwrap_or(0);
    let (u_row, vs) = rows
        .iter()
        .filter(|(_, v)| v.len() == full)
        .map(|(k, v)| (f64::from_bits(*k), v.clone()))
        .min_by(|a, b| (a.0 - u).abs().total_cmp(&(b.0 - u).abs()))
        .ok_or_else(|| FlankError::Model(format!("flank set {set} has no nodes")))?;
    let k = vs.len();
    let mut pts = Vec::with_capacity(k);
    let mut normals = Vec::with_capacity(k);
    for &v in &vs {
        let p = it.point(set, u_row, v)?;
        normals.push(it.normal(&p));
        pts.push(p);
    }
    let c = it.normal_matrix(&pts, &normals);
    let eig = SymmetricEigen::new(DMatrix::from_row_slice(k, k, &c));
    let lmin = eig
        .eigenvalues
        .iter()
        .copied()
        .fold(f64::INFINITY, f64::min);
    let lmax = eig
        .eigenvalues
        .iter()
        .copied()
        .fold(f64::NEG_INFINITY, f64::max);
    Ok((
        ContactLine {
            set: set.to_string(),
            u: u_row,
            points: k,
            lambda_min: lmin,
            lambda_max: lmax,
            condition: lmax / lmin,
            positive_definite: lmin > 0.0,
            c_nn_first: c[0],
            c_nn_middle: c[(k / 2) * k + k / 2],
        },
        c,
    ))
}

/// How [`body_tensor`] computes a body's tensor.
#[derive(Clone)]
pub struct BodyTensorOptions<'c> {
    pub flanks: FlankSelection,
    pub clamp_cuts: bool,
    pub compliance: ComplianceOptions,
    pub format: FileFormat,
    /// A campaign cache searched before computing.
    pub campaign: Option<&'c ComplianceCache>,
    /// The lowest profile parameter u kept on every flank set (the active
    /// flank plus its margin, [`crate::compliance::body::active_flank_cut`]);
    /// `None`: the full flank ([`FlankRegion::Full`]).
    pub region_u_min: Option<f64>,
}

impl<'c> BodyTensorOptions<'c> {
    /// What the LTCA uses: the loaded flanks, the mount clamped, the
    /// default method and file format, `threads`, and a campaign cache.
    pub fn for_ltca(threads: usize, campaign: Option<&'c ComplianceCache>) -> Self {
        BodyTensorOptions {
            flanks: FlankSelection::Loaded,
            clamp_cuts: false,
            compliance: ComplianceOptions {
                threads,
                ..Default::default()
            },
            format: FileFormat::default_format(),
            campaign,
            region_u_min: None,
        }
    }
}

/// One body's tensor and where it came from.
pub struct BodyTensor {
    pub tensor: std::sync::Arc<ComplianceTensor>,
    pub outcome: CacheOutcome,
    /// Present when the tensor was computed here.
    pub stats: Option<crate::compliance::ComplianceStats>,
    /// The body's deck and tensor file in `out`.
    pub deck: PathBuf,
    pub file: PathBuf,
}

/// A body as its tensor is computed from: the model read back from its
/// deck (Dirichlet conditions only), the flank nodes, the region cut, the
/// cache key and the deck's path.
struct PreparedBody {
    model: crate::fem::model::Model,
    flank: crate::compliance::FlankNodes,
    region: Option<Vec<f64>>,
    key: String,
    deck: PathBuf,
}

/// Writes the body's deck to `out/<name>.inp` and reads it back (the
/// tensor belongs to the deck as printed), selects the flank nodes (and
/// the region), clears the loads, clamps the cuts if asked and forms the
/// cache key.
fn prepare_body(
    body: &SectorBody,
    options: &BodyTensorOptions,
    out: &Path,
) -> Result<PreparedBody, FlankError> {
    std::fs::create_dir_all(out).map_err(|e| FlankError::io(out, e))?;
    let name = body.name.as_str();
    let deck = out.join(format!("{name}.inp"));
    crate::deck::write_deck(&body.model, &deck)?;
    // the tensors belong to the mesh of the deck as written (coordinates
    // as printed), so that the deck solved elsewhere is the same model
    let parsed = crate::deck::read_deck(&deck)?;
    let mut model = parsed.model;
    let uv = flank_uv_on(body, &model.mesh)?;
    let mut flank = flank_nodes_on(&model.mesh, &uv, body.surfaces.as_ref(), options.flanks)?;
    // the active flank: the faces reaching the cut, and where the tensor
    // stops (a restriction that keeps every node is the full flank)
    let mut region = None;
    if let Some(u) = options.region_u_min {
        let cut = vec![u; flank.sets.len()];
        let restricted = flank.restrict_u(&cut).map_err(|e| match e {
            FlankError::Model(m) => FlankError::Model(format!("{name}: {m}")),
            e => e,
        })?;
        if restricted.len() < flank.len() {
            flank = restricted;
            region = Some(cut);
        }
    }
    model.forces.clear();
    model.pressures.clear();
    if options.clamp_cuts {
        clamp_sets(&mut model, &["CUT_A", "CUT_B"])?;
    }
    let key = region_cache_key(
        &cache_key(&model, &mesh_hash(&model.mesh), &flank),
        region.as_deref(),
    );
    Ok(PreparedBody {
        model,
        flank,
        region,
        key,
        deck,
    })
}

/// One body's compressed tensor ([`open_compressed`], [`build_compressed`]).
pub struct BodyCompressed {
    /// The body's flank and key; no dense matrix
    /// ([`ComplianceTensor::has_matrix`] is false).
    pub tensor: std::sync::Arc<ComplianceTensor>,
    pub blr: std::sync::Arc<crate::compliance::compressed::BlrTensor>,
    /// Present when it was built here (else read from `file`).
    pub stats: Option<(
        crate::compliance::ComplianceStats,
        crate::compliance::compressed_build::PanelStats,
    )>,
    pub deck: PathBuf,
    pub file: PathBuf,
}

/// A body's compressed tensor as [`open_compressed`] found it.
pub enum OpenedCompressed {
    /// Read from its file.
    Read(Box<BodyCompressed>),
    /// No file holds it (none, stale or corrupt: named in a warning): to
    /// be built by [`build_compressed`].
    Missing(Box<MissingCompressed>),
}

/// A body prepared for [`build_compressed`]: its model, flank and key,
/// and the file to write.
pub struct MissingCompressed {
    model: crate::fem::model::Model,
    tensor: ComplianceTensor,
    deck: PathBuf,
    file: PathBuf,
}

/// The block low-rank tensor of a scene's body at `blr`, first half: the
/// body meshed and its deck written and read back, and its compressed
/// tensor read from `<cache>/<name>.<key16>.compression.bin` (a campaign
/// cache, `cache`) or `out/<name>.compression.bin` when that file holds
/// this body's tensor (key, node order) at this ε; else (a stale or
/// corrupt file named in a warning) [`build_compressed`] builds it panel
/// by panel from the body's factor
/// ([`crate::compliance::compressed_build`]: the dense tensor is never
/// formed, read or written) and writes it there. Two bodies can be opened
/// at once (reading is bound by copying the file, one core each);
/// building holds a factor and a thread per panel, so builds go one at a
/// time.
pub fn open_compressed(
    body: &SectorBody,
    options: &BodyTensorOptions,
    blr: &crate::compliance::compressed::BlrOptions,
    cache: Option<&Path>,
    out: &Path,
) -> Result<OpenedCompressed, FlankError> {
    use crate::compliance::compressed::BlrTensor;
    blr.validate()?;
    let PreparedBody {
        model,
        flank,
        region,
        key,
        deck,
    } = prepare_body(body, options, out)?;
    let name = body.name.as_str();
    let file = match cache {
        Some(d) => {
            std::fs::create_dir_all(d).map_err(|e| FlankError::io(d, e))?;
            // the short key (the full key is checked on reading)
            d.join(format!(
                "{name}.{}.compression.bin",
                &key[..key.len().min(16)]
            ))
        }
        None => out.join(format!("{name}.compression.bin")),
    };
    let mut tensor = ComplianceTensor {
        meta: crate::compliance::tensor_meta(name, &model, &flank, "panel"),
        flank,
        matrix: Vec::new(),
    };
    tensor.meta.cache_key = key;
    tensor.meta.region_u_min = region;
    if file.exists() {
        match BlrTensor::read(&file, &tensor, blr.epsilon) {
            Ok(c) => {
                return Ok(OpenedCompressed::Read(Box::new(BodyCompressed {
                    tensor: std::sync::Arc::new(tensor),
                    blr: std::sync::Arc::new(c),
                    stats: None,
                    deck,
                    file,
                })))
            }
            Err(e) => eprintln!("warning: {e}; building it again"),
        }
    }
    Ok(OpenedCompressed::Missing(Box::new(MissingCompressed {
        model,
        tensor,
        deck,
        file,
    })))
}

/// The second half of [`open_compressed`]: the tensor built panel by
/// panel and written to its file.
pub fn build_compressed(
    m: Box<MissingCompressed>,
    options: &BodyTensorOptions,
    blr: &crate::compliance::compressed::BlrOptions,
    progress: bool,
) -> Result<BodyCompressed, FlankError> {
    let MissingCompressed {
        model,
        tensor,
        deck,
        file,
    } = *m;
    let (built, c, stats, panel) = crate::compliance::compressed_build::compressed_compliance(
        &tensor.meta.body,
        &model,
        &tensor.flank,
        &options.compliance,
        blr,
        progress,
    )?;
    debug_assert_eq!(built.flank.len(), tensor.flank.len());
    // the key of the region (the built tensor's is the full flank's)
    let c = c.with_cache_key(&tensor.meta.cache_key);
    c.write(&file)?;
    Ok(BodyCompressed {
        tensor: std::sync::Arc::new(tensor),
        blr: std::sync::Arc::new(c),
        stats: Some((stats, panel)),
        deck,
        file,
    })
}

/// The compliance tensor of a scene's body (meshed as `flank mesh` does,
/// [`crate::compliance::body`]): written to `out/<name>.inp`, read back (the
/// tensor belongs to the deck as printed), and computed unless
/// `out/<name>.compliance.*` or the campaign cache holds it under the same
/// key (mesh hash, constraints, material, flank nodes).
pub fn body_tensor(
    body: &SectorBody,
    options: &BodyTensorOptions,
    out: &Path,
) -> Result<BodyTensor, FlankError> {
    let PreparedBody {
        model,
        flank,
        region,
        key,
        deck,
    } = prepare_body(body, options, out)?;
    let name = body.name.as_str();
    let file = out.join(options.format.file_name(name));
    let mut stats = None;
    let mut compute = || -> Result<ComplianceTensor, FlankError> {
        let (mut t, s) = compliance_tensor(name, &model, &flank, &options.compliance)?;
        t.meta.cache_key = key.clone();
        t.meta.region_u_min = region.clone();
        stats = Some(s);
        Ok(t)
    };
    // a file in `out` is reused only when its key and checksum match; a
    // corrupt one is recomputed (with a warning) and replaced
    let (tensor, outcome) = if let Some(t) = cache::read_trusted(&file, &key) {
        (std::sync::Arc::new(t), CacheOutcome::Disk)
    } else {
        match options.campaign {
            Some(c) => {
                let (t, o) = c.get_or_compute(name, &key, compute)?;
                // the cache's file is the same bytes: linked, not rewritten
                if !c.link_into(name, &key, &file) {
                    cache::write(&file, &t)?;
                }
                (t, o)
            }
            None => {
                let t = std::sync::Arc::new(compute()?);
                cache::write(&file, &t)?;
                (t, CacheOutcome::Computed)
            }
        }
    };
    Ok(BodyTensor {
        tensor,
        outcome,
        stats,
        deck,
        file,
    })
}

/// Computes (or reuses) the tensors of the bodies of the scene file at
/// `path` ([`run`] of the scene read).
pub fn run_scene(path: &Path, options: &RunOptions) -> Result<ComplianceSummary, FlankError> {
    run(&read_scene(path)?, options)
}

/// Computes (or reuses) the tensors of the scene's bodies; writes
/// `<body>.inp`, `<body>.compliance.{h5,bin}`, `<body>_cnn.{svg,png}` and
/// `summary.json` into `options.out`; returns the summary. A parsed scene
/// (with overrides, [`crate::api::load_scene_with`]) as the other analyses
/// take it.
pub fn run(scene: &Scene, options: &RunOptions) -> Result<ComplianceSummary, FlankError> {
    let t_all = Instant::now();
    let (analyses, teeth) = (&scene.analyses, scene.mesh.teeth_in_sector as usize);
    let analysis: ComplianceAnalysis = analyses.compliance.clone().unwrap_or_default();
    let method = options.method.unwrap_or(analysis.method);
    let flanks = options.flanks.unwrap_or(analysis.flanks);
    let region = options.region.unwrap_or(analysis.flank_region);
    let clamp_cuts = options.clamp_cuts || analysis.clamp_cuts;
    let copts = ComplianceOptions {
        method,
        threads: options.threads,
        memory_budget_mb: options
            .memory_budget_mb
            .or(analysis.memory_budget_mb)
            .unwrap_or(ComplianceOptions::default().memory_budget_mb),
        block_size: options.block_size,
        condition: options.condition,
        ..Default::default()
    };
    // the region and the mesh options are checked before anything is written
    if region == FlankRegion::Active {
        region_cut(scene, "pinion", region, &options.mesh)?;
    }
    if scene.is_bevel() {
        bevel_sector_options(
            scene,
            &crate::compliance::body::compliance_sizes(scene, &options.mesh),
        )?;
    } else {
        sector_options(scene, &options.mesh)?;
    }
    let format = options.format.unwrap_or_else(FileFormat::default_format);
    let out = &options.out;
    std::fs::create_dir_all(out).map_err(|e| FlankError::io(out, e))?;
    let campaign = match &options.cache {
        Some(d) => Some(ComplianceCache::shared(d, format)?),
        None => None,
    };
    // where each body's tensors are probed: a spur/helical body along the
    // contact line through the working pitch point, a bevel/hypoid body
    // along the major axis of the middle pair's contact at roll 0
    let u_pitch = match &scene.gears {
        Gears::Cylindrical(c) => Some(
            crate::geometry::pair::check_pair(&c.pair)?
                .working_pressure_angle_rad
                .tan(),
        ),
        Gears::Bevel(_) => None,
    };
    let axis = scene.is_bevel().then(|| mean_contact_axis(scene));
    let bodies: Vec<String> = if options.bodies.is_empty() {
        vec!["pinion".into(), "gear".into()]
    } else {
        options.bodies.clone()
    };
    let mut summary = std::collections::BTreeMap::new();
    for name in &bodies {
        let t_body = Instant::now();
        let body = any_scene_body(scene, name, &options.mesh)?;
        let BodyTensor {
            tensor,
            outcome,
            stats,
            deck,
            file,
        } = body_tensor(
            &body,
            &BodyTensorOptions {
                flanks,
                clamp_cuts,
                compliance: copts.clone(),
                format,
                campaign: campaign.as_deref(),
                region_u_min: region_cut(scene, name, region, &options.mesh)?,
            },
            out,
        )?;
        let flank = &tensor.flank;
        let middle = teeth.div_ceil(2);
        let plot_set = flank
            .sets
            .iter()
            .find(|s| s.get(7..) == Some(middle.to_string().as_str()))
            .cloned()
            .unwrap_or_else(|| flank.sets[0].clone());
        let plot = plot_cnn(
            &tensor,
            &plot_set,
            &format!("{name} {plot_set}: normal self-compliance c_nn"),
            &out.join(format!("{name}_cnn.svg")),
            &out.join(format!("{name}_cnn.png")),
        )?;
        let line = match u_pitch {
            Some(u) if plot_set.starts_with("FLANK_") => {
                contact_line(&tensor, &plot_set, u).ok().map(|c| c.0)
            }
            _ => None,
        };
        let b = BodySummary {
            deck: deck.display().to_string(),
            file: file.display().to_string(),
            format,
            source: outcome,
            cache_key: tensor.meta.cache_key.clone(),
            mesh_hash: tensor.meta.mesh_hash.clone(),
            clamped_sets: tensor.meta.clamped_sets.clone(),
            flank_sets: tensor.meta.flank_sets.clone(),
            region_u_min: tensor.meta.region_u_min.clone(),
            flank_nodes: tensor.node_count(),
            matrix_dim: tensor.dim(),
            asymmetry: tensor.asymmetry(),
            plot,
            contact_line: line,
            body_s: t_body.elapsed().as_secs_f64(),
            mean_contact: axis.as_ref().map(|a| mean_contact_report(a, name, &tensor)),
            stats,
        };
        summary.insert(name.clone(), b);
    }
    let result = ComplianceSummary {
        header: scene.summary_header(),
        method,
        flanks,
        flank_region: region,
        clamp_cuts,
        threads: options.threads,
        bodies: summary,
        total_s: t_all.elapsed().as_secs_f64(),
        peak_memory_mb: peak_memory_mb(),
    };
    result.write(out)?;
    Ok(result)
}

/// Points on the contact-ellipse major axis that [`mean_contact_axis`]
/// probes (seed 001/003 place their M candidate points there).
pub const MEAN_CONTACT_POINTS: usize = 11;

/// The middle pair's contact of a bevel/hypoid scene at roll 0 (point TCA
/// with the default approach δ, flank contact only, curvature ellipse):
/// the roll angle, the ellipse's semi-major axis and its major-axis points
/// on [pinion, gear]; or why there is none.
pub fn mean_contact_axis(scene: &Scene) -> Result<(f64, [Vec<AxisPoint>; 2]), String> {
    let bevel = scene
        .bevel("the bevel/hypoid compliance")
        .map_err(|e| e.to_string())?;
    let settings = PointTcaSettings {
        edges: false,
        search_directions: 0,
        ..Default::default()
    };
    let tca = point_tca(bevel.pair.as_ref(), &settings).map_err(|e| e.to_string())?;
    let at_zero = tca
        .positions
        .iter()
        .min_by(|a, b| a.roll_rad.abs().total_cmp(&b.roll_rad.abs()))
        .ok_or("the TCA traced no position")?;
    let c = at_zero
        .pairs
        .iter()
        .find(|p| p.offset == 0)
        .ok_or("the middle pair is not in contact at roll 0")?;
    let a = c
        .ellipse
        .and_then(|e| e.semi_major_mm)
        .ok_or("the middle pair's contact at roll 0 has no finite contact ellipse")?;
    let points = major_axis_points(bevel.pair.as_ref(), c, MEAN_CONTACT_POINTS)
        .map_err(|e| e.to_string())?;
    Ok((a, points))
}

/// [`MeanContact::Missing`] for `error`.
fn missing(error: String) -> MeanContact {
    MeanContact::Missing { error }
}

/// `mean_contact` of a bevel body's summary: the directional compliances
/// (normal n outward from the body, tangent t the sliding direction from
/// the TCA) on the major axis of the middle pair's contact at roll 0.
fn mean_contact_report(
    axis: &Result<(f64, [Vec<AxisPoint>; 2]), String>,
    name: &str,
    tensor: &ComplianceTensor,
) -> MeanContact {
    let (a, points) = match axis {
        Ok(x) => x,
        Err(why) => return missing(why.clone()),
    };
    let b = usize::from(name == "gear");
    let probe: Vec<ProbePoint> = points[b]
        .iter()
        .filter(|p| p.sliding != [0.0; 3])
        .map(|p| ProbePoint {
            set: format!("FLANK_R{}", p.tooth),
            uv: p.uv,
            normal: p.normal,
            tangent: p.sliding,
        })
        .collect();
    let (probe, outside) = match retain_meshed(tensor, probe) {
        Ok(x) => x,
        Err(e) => return missing(e.to_string()),
    };
    if probe.is_empty() {
        return missing("no point of the major axis lies on the meshed flank".into());
    }
    match directional_matrices(tensor, &probe, None) {
        Ok(m) => MeanContact::Probed(Box::new(MeanContactProbe {
            semi_major_mm: *a,
            set: probe[0].set.clone(),
            uv_mm: probe[probe.len() / 2].uv,
            axis_points: MEAN_CONTACT_POINTS,
            off_the_active_flank: MEAN_CONTACT_POINTS - points[b].len(),
            off_the_meshed_flank: outside,
            report: m.report(),
        })),
        Err(e) => missing(e.to_string()),
    }
}
