//! `flank check`: the pair report of a scene as JSON: for spur and helical
//! pairs the pair checks and ISO 6336 stiffness, for bevel and hypoid pairs
//! the ISO 23509 blank design (the standard's output keys, mm and degrees).

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
    let report = flank::scene::check::check(&scene)?;
    println!("{}", serde_json::to_string_pretty(&report)?);
    Ok(())
}
