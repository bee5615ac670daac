//! `flank blank INPUTS.json`: the ISO 23509 blank design of a spiral bevel
//! or hypoid pair; prints the outputs (Annex F key names, mm and degrees) as
//! JSON.

use std::path::PathBuf;

use anyhow::{Context, Result};

#[derive(clap::Args)]
pub struct Args {
    /// Input set as a JSON object with the key names of ISO 23509 Annex F
    /// (`method`, `Sigma_deg`, `a_mm`, `z1`, `z2`, `de2_mm` or `dm2_mm`, …).
    inputs: PathBuf,
}

pub fn run(args: Args) -> Result<()> {
    let text = flank::text_file::read_utf8(&args.inputs)?;
    let design = flank::api::blank(&text).with_context(|| args.inputs.display().to_string())?;
    println!("{}", serde_json::to_string_pretty(&design.outputs())?);
    Ok(())
}
