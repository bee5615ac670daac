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
    local: Option<flank::ltca::local::LocalModel>,
    /// Threads (0 = all cores).
    #[arg(long, default_value_t = 0)]
    threads: usize,
    /// Print nothing but errors.
    #[arg(long, short)]
    quiet: bool,
}

pub fn run(args: Args) -> Result<()> {
    use flank::compare::{compare_scene, CompareOptions};
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
        quiet,
    } = args;
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
    let s = match flank::scene::read_any_scene(&scene)? {
        flank::scene::AnyScene::Bevel(b) => {
            let mut ltca = flank::ltca::bevel::BevelLtcaOptions {
                mesh: sizes.body_options(false),
                threads,
                ..Default::default()
            };
            if let Some(l) = local {
                ltca.settings.local = l;
            }
            flank::compare::bevel::compare_bevel(&b, &options, &ltca)
        }
        flank::scene::AnyScene::Cylindrical(_) => compare_scene(&scene, &options),
    }
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
    Ok(())
}
