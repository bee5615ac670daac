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
    let gears = match &scene.gears {
        flank::scene::Gears::Cylindrical(c) => c,
        flank::scene::Gears::Bevel(b) => return bevel(&scene, b),
    };
    let report = flank::geometry::pair::check_pair(&gears.pair)?;
    let mut json = serde_json::to_value(&report)?;
    // ISO 6336-1 single and mesh stiffness: the plausibility band for FE stiffness
    let stiffness = flank::geometry::iso6336::tooth_stiffness(&gears.pair, report.contact_ratio);
    json["iso6336_stiffness_n_per_mm_um"] = match stiffness {
        Ok(s) => serde_json::to_value(s)?,
        Err(e) => serde_json::Value::String(format!("not applicable: {e}")),
    };
    println!("{}", serde_json::to_string_pretty(&json)?);
    Ok(())
}

/// The blank table of a bevel/hypoid scene and how each member is cut
/// (process, cutter, machine settings, mean-point figures measured on the
/// flanks).
fn bevel(scene: &flank::scene::Scene, gears: &flank::scene::BevelGears) -> Result<()> {
    let json = serde_json::json!({
        "kind": scene.kind,
        "method": gears.blank.method,
        "pinion_hand": gears.pinion_hand,
        "blank": gears.blank.outputs(),
        "pinion": gears.cutting_report[0],
        "gear": gears.cutting_report[1],
    });
    println!("{}", serde_json::to_string_pretty(&json)?);
    Ok(())
}
