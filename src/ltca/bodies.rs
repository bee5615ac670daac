//! The compliance tensors of both bodies of an LTCA, for any pair kind:
//! read from the run's folder or a campaign cache, else computed (dense),
//! or built and read in block low-rank form (spur/helical), with what the
//! setup cost ([`Setup`]).

use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

use rayon::prelude::*;

use crate::compliance::body::{any_scene_body, BodyMeshOptions, SectorBody};
use crate::compliance::cache::FileFormat;
use crate::compliance::compressed::{BlrOptions, BlrTensor};
use crate::compliance::interpolation::FlankGrids;
use crate::compliance::run::{
    body_tensor, build_compressed, open_compressed, region_cut, BodyTensorOptions, OpenedCompressed,
};
use crate::compliance::tensor_cache::ComplianceCache;
use crate::compliance::{ComplianceStats, ComplianceTensor};
use crate::error::FlankError;
use crate::scene::Scene;
use crate::settings::{Compression, FlankRegion};

/// What the setup cost and produced.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Setup {
    /// Flank nodes per body, compliance matrix dimension, whether it was
    /// computed here (else read), seconds.
    pub flank_nodes: [usize; 2],
    pub computed: [bool; 2],
    /// Backward error of each body's probe solve when its tensor was
    /// computed here (`None`: read from a file or the cache, checked when
    /// it was computed).
    pub backward_error: [Option<f64>; 2],
    pub compliance_s: f64,
    pub flank_size_mm: f64,
    pub base_size_mm: f64,
    /// Per body, the block low-rank compression the pages are read from
    /// (`None`: dense).
    pub compression: [Option<crate::compliance::compressed::BlrStats>; 2],
    /// Per body built compressed here: the panel build's figures and the
    /// factorization's time (s) and peak resident memory so far (MB).
    pub panel_build: [Option<PanelBuild>; 2],
}

/// A compressed body's build ([`Setup::panel_build`]).
#[derive(Clone, Debug, serde::Serialize)]
pub struct PanelBuild {
    #[serde(flatten)]
    pub panels: crate::compliance::compressed_build::PanelStats,
    pub factorization_s: f64,
    pub nnz_factor: usize,
    pub dofs: usize,
    pub peak_memory_mb: f64,
}

/// One body's tensor for the LTCA: dense, or flank and key only with its
/// block low-rank form.
struct Prepared {
    tensor: Arc<ComplianceTensor>,
    /// Present when computed here.
    stats: Option<ComplianceStats>,
    blr: Option<Arc<BlrTensor>>,
    panel: Option<PanelBuild>,
}

/// What [`tensors`] needs besides the scene.
pub struct TensorRequest<'a> {
    /// The compliance mesh (sizes already resolved where the kind does so).
    pub mesh: BodyMeshOptions,
    pub region: FlankRegion,
    pub compression: Compression,
    /// The run's folder (tensor files) and a campaign cache.
    pub out: &'a Path,
    pub cache: Option<&'a Path>,
    pub threads: usize,
    pub quiet: bool,
    /// What a body that cannot be meshed is told (the kind's hint).
    pub mesh_hint: &'a (dyn Fn(FlankError) -> FlankError + Sync),
}

/// Both bodies' compliance (pinion, gear) as [`tensors`] returns it.
pub struct BodyTensors {
    pub tensors: [Arc<ComplianceTensor>; 2],
    /// The flanks' face grids, paged from the compressed form if any.
    pub grids: [Arc<FlankGrids>; 2],
    pub setup: Setup,
}

/// Both bodies' tensors and face grids (pinion, gear), with the setup's
/// figures.
pub fn tensors(scene: &Scene, r: &TensorRequest) -> Result<BodyTensors, FlankError> {
    let t = Instant::now();
    let campaign = match r.cache {
        Some(d) => Some(ComplianceCache::shared(d, FileFormat::default_format())?),
        None => None,
    };
    let mut topts = BodyTensorOptions::for_ltca(r.threads, campaign.as_deref());
    let body = |name: &str| -> Result<SectorBody, FlankError> {
        any_scene_body(scene, name, &r.mesh).map_err(r.mesh_hint)
    };
    let mut bodies = Vec::with_capacity(2);
    match r.compression.epsilon() {
        // compressed: built panel by panel, the dense tensor never formed
        // (compliance::compressed_build); the two bodies are meshed and
        // their files read side by side, a missing tensor is then built
        // one body at a time (a factor and the panels' threads each)
        Some(epsilon) => {
            let blr = BlrOptions {
                epsilon,
                ..Default::default()
            };
            let mut per_body = Vec::with_capacity(2);
            for name in ["pinion", "gear"] {
                let mut o = topts.clone();
                o.region_u_min = region_cut(scene, name, r.region, &r.mesh)?;
                per_body.push((name, o));
            }
            let opened: Vec<OpenedCompressed> = per_body
                .par_iter()
                .map(|(name, o)| open_compressed(&body(name)?, o, &blr, r.cache, r.out))
                .collect::<Result<_, FlankError>>()?;
            for (opened, (_, o)) in opened.into_iter().zip(&per_body) {
                let c = match opened {
                    OpenedCompressed::Read(c) => *c,
                    OpenedCompressed::Missing(m) => build_compressed(m, o, &blr, !r.quiet)?,
                };
                bodies.push(Prepared {
                    tensor: c.tensor,
                    panel: c.stats.as_ref().map(|(s, p)| PanelBuild {
                        panels: p.clone(),
                        factorization_s: s.factorization_s,
                        nnz_factor: s.nnz_factor,
                        dofs: s.dofs,
                        peak_memory_mb: s.peak_memory_mb,
                    }),
                    stats: c.stats.map(|s| s.0),
                    blr: Some(c.blr),
                });
            }
        }
        None => {
            for name in ["pinion", "gear"] {
                topts.region_u_min = region_cut(scene, name, r.region, &r.mesh)?;
                let t = body_tensor(&body(name)?, &topts, r.out)?;
                bodies.push(Prepared {
                    tensor: t.tensor,
                    stats: t.stats,
                    blr: None,
                    panel: None,
                });
            }
        }
    }
    let gear = bodies.pop().expect("two bodies");
    let pinion = bodies.pop().expect("two bodies");
    let mut setup = Setup {
        flank_nodes: [pinion.tensor.node_count(), gear.tensor.node_count()],
        computed: [pinion.stats.is_some(), gear.stats.is_some()],
        backward_error: [
            pinion.stats.as_ref().map(|s| s.backward_error),
            gear.stats.as_ref().map(|s| s.backward_error),
        ],
        compliance_s: t.elapsed().as_secs_f64(),
        flank_size_mm: r.mesh.flank_size.unwrap_or(f64::NAN),
        base_size_mm: r.mesh.base_size.unwrap_or(f64::NAN),
        compression: [None, None],
        panel_build: [pinion.panel.clone(), gear.panel.clone()],
    };
    // the flanks' face grids (geometry only: a compressed tensor has no
    // dense matrix), the pages read from the compressed form if any
    let grids = [
        FlankGrids::of(&pinion.tensor)?,
        FlankGrids::of(&gear.tensor)?,
    ];
    for (b, body) in [&pinion, &gear].into_iter().enumerate() {
        if let Some(blr) = &body.blr {
            setup.compression[b] = Some(blr.stats.clone());
            grids[b].set_pages(crate::compliance::pages::TensorPages::compressed(
                &body.tensor,
                Arc::clone(blr),
            )?)?;
        }
    }
    Ok(BodyTensors {
        tensors: [pinion.tensor, gear.tensor],
        grids,
        setup,
    })
}
