//! `flank tca SCENE --out DIR`: unloaded tooth contact analysis over the
//! mesh cycle of any pair kind, with and without edge contact
//! ([`flank::api::tca`], [`flank::tca::run`]); prints the summary.

use std::path::PathBuf;

use anyhow::Result;
use flank::geometry::gear_pair::Misalignment;
use flank::tca::run::TcaOptions;

#[derive(clap::Args)]
pub struct Args {
    /// Gear-pair scene (TOML).
    scene: PathBuf,
    /// Output directory.
    #[arg(long)]
    out: PathBuf,
    /// Elastic approach δ of the contact ellipse (mm): 0.00635 finished
    /// teeth, 0.00381 lapped (seed 000).
    #[arg(long, default_value_t = 0.00635)]
    approach_mm: f64,
    /// Positions per angular pitch.
    #[arg(long, default_value_t = 30)]
    positions_per_pitch: usize,
    /// Planes of the numerical contact-ellipse search over 180° (0: off).
    #[arg(long, default_value_t = 18)]
    search_directions: usize,
    /// Offset error ΔE (mm, > 0: the axes apart).
    #[arg(long, default_value_t = 0.0)]
    offset_error_mm: f64,
    /// Pinion axial displacement ΔP (mm, along its own +z, toward its heel).
    #[arg(long, default_value_t = 0.0)]
    pinion_axial_mm: f64,
    /// Gear axial displacement ΔG (mm, along its own +z).
    #[arg(long, default_value_t = 0.0)]
    gear_axial_mm: f64,
    /// Shaft-angle error ΔΣ (degrees).
    #[arg(long, default_value_t = 0.0)]
    shaft_angle_error_deg: f64,
    /// V–H style sweep: ΔE and ΔP each over ±MM in 5 steps (25 TCA runs
    /// with edges, curvature ellipses, added to the misalignment above):
    /// writes vh_sweep.csv (bearing centre on the gear: the middle pair's
    /// contact where its TE curve peaks; TE peak-to-peak, contact ratio)
    /// and the V–H chart vh_chart.svg/png.
    #[arg(long)]
    sweep_mm: Option<f64>,
}

pub fn run(args: Args) -> Result<()> {
    let scene = flank::scene::read_scene(&args.scene)?;
    let options = TcaOptions {
        out: args.out,
        approach_mm: args.approach_mm,
        positions_per_pitch: args.positions_per_pitch,
        search_directions: args.search_directions,
        misalignment: Misalignment {
            offset_error_mm: args.offset_error_mm,
            pinion_axial_mm: args.pinion_axial_mm,
            gear_axial_mm: args.gear_axial_mm,
            shaft_angle_error_rad: args.shaft_angle_error_deg.to_radians(),
            out_of_plane_tilt_rad: 0.0,
        },
        sweep_mm: args.sweep_mm,
        quiet: false,
    };
    let run = flank::api::tca(&scene, &options)?;
    println!("{}", serde_json::to_string_pretty(&run.summary)?);
    for w in &run.warnings {
        eprintln!("warning: {w}");
    }
    Ok(())
}
