//! `flank check`: the pair report of a scene as JSON.

use std::path::PathBuf;

use anyhow::Result;

#[derive(clap::Args)]
pub struct Args {
    /// The scene file (.toml).
    scene: PathBuf,
}

pub fn run(args: Args) -> Result<()> {
    let Args { scene } = args;
    let scene = flank::scene::read_scene(&scene)?;
    let report = flank::geometry::pair::check_pair(&scene.pair)?;
    let mut json = serde_json::to_value(&report)?;
    // ISO 6336-1 single and mesh stiffness: the plausibility band for FE stiffness
    let stiffness = flank::geometry::iso6336::tooth_stiffness(&scene.pair, report.contact_ratio);
    json["iso6336_stiffness_n_per_mm_um"] = match stiffness {
        Ok(s) => serde_json::to_value(s)?,
        Err(e) => serde_json::Value::String(format!("not applicable: {e}")),
    };
    println!("{}", serde_json::to_string_pretty(&json)?);
    Ok(())
}
