//! `flank compare`: LTCA against FE contact at the same roll angles.

use std::path::PathBuf;

use anyhow::{Context, Result};

use crate::cli::common::SectorArgs;

#[derive(clap::Args)]
pub struct Args {
    /// The scene file (.toml).
    scene: PathBuf,
    /// Output directory.
    #[arg(long, default_value = "out")]
    out: PathBuf,
    /// K values of the LTCA runs (points per contact line; on hypoid
    /// pairs per major axis).
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
    local: Option<flank::settings::LocalModel>,
    /// Threads (0 = all cores).
    #[arg(long, default_value_t = 0)]
    threads: usize,
    /// Coulomb friction coefficient of both methods' flanks (0 =
    /// frictionless; default the scene's `[analyses.ltca] friction_mu`, on
    /// spur/helical scenes each method's own scene setting); with μ > 0
    /// the tangential force per pair is compared too.
    #[arg(long)]
    friction_mu: Option<f64>,
    /// Load increments of the LTCA's frictional solve (default 10).
    #[arg(long)]
    increments: Option<usize>,
    /// What the LTCA's friction resists (as `flank ltca`; default
    /// incremental). FE contact's is always the loading step's slip.
    #[arg(long, value_enum)]
    friction_model: Option<flank::settings::FrictionModel>,
    /// Compressed LTCA tensors (spur/helical, frictionless), as `flank
    /// ltca --compression`: `none` or ε in (0, 1), e.g. 1e-6; default
    /// the scene's `[analyses.ltca] compression`, else none.
    #[arg(long)]
    compression: Option<String>,
    /// p_max reference: contact-band FE runs (`flank run --roll-angles=X
    /// --contact-band SIZE`), their output directories or contact_band.json
    /// files, comma-separated. Grouped by roll angle; per angle and pair the
    /// FE p_max over the flank is Richardson-extrapolated from the three
    /// finest bands (GCI), else the finest band is used. The LTCA is solved
    /// at those angles too, and its p_max error is stated against this
    /// reference (spur pairs; the runs must be of this scene and load).
    #[arg(long, value_delimiter = ',')]
    pmax_reference: Vec<PathBuf>,
    /// Print nothing but errors.
    #[arg(long, short)]
    quiet: bool,
}

pub fn run(args: Args) -> Result<()> {
    use flank::compare::run::compare_scene;
    use flank::compare::CompareOptions;
    let Args {
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
        friction_mu,
        increments,
        friction_model,
        compression,
        pmax_reference,
        quiet,
    } = args;
    let compression = match compression {
        Some(c) => Some(
            c.parse::<flank::settings::Compression>()
                .map_err(|e| anyhow::anyhow!("--compression: {e}"))?,
        ),
        None => None,
    };
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
            increments,
            friction_model,
            compression,
            ..Default::default()
        },
        threads,
        quiet,
        friction_mu,
        pmax_reference,
    };
    let s = compare_scene(&scene, &options)
        .with_context(|| format!("LTCA against FE contact for {}", scene.display()))?;
    if !quiet {
        println!(
            "best {} against {}: load sharing {:.4}, TE {:.4}, p_max {:.4} (against {}); LTCA cycle {:.4} s, FE cycle {:.1} s (+{:.1} s setup): {:.0}×",
            s.best_ltca,
            s.reference,
            s.load_sharing_rel_err,
            s.te_rel_err,
            s.pmax_rel_err,
            s.pmax_reference,
            s.ltca_cycle_s,
            s.fe_cycle_s,
            s.fe_setup_s,
            s.speedup
        );
        if s.friction_mu > 0.0 {
            println!(
                "friction μ = {}: tangential force {:.4} (of the total normal force)",
                s.friction_mu, s.tangential_force_rel_err
            );
        }
        println!("wrote {}", out.display());
    }
    Ok(())
}
