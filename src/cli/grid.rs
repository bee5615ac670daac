//! `flank grid SCENE`: one flank of one member of a scene (spur, helical,
//! spiral bevel or hypoid) as the measuring machine's grid (points and normals, `deviation_um` = 0) in CSV; a
//! measuring machine fills in the deviations and the file is read back as a
//! flank deviation (format: `flank::geometry::measurement_grid`).

use std::path::PathBuf;

use anyhow::{bail, Context, Result};
use flank::geometry::gear_pair::{Flank, GearBody};
use flank::geometry::measurement_grid::{measurement_grid, GridSpec};
use flank::scene::AnyScene;

#[derive(Clone, Copy, clap::ValueEnum)]
pub enum Member {
    Pinion,
    Gear,
}

#[derive(Clone, Copy, clap::ValueEnum)]
pub enum Side {
    Left,
    Right,
}

#[derive(clap::Args)]
pub struct Args {
    /// Gear-pair scene (TOML).
    scene: PathBuf,
    /// Which member.
    #[arg(long, value_enum, default_value = "gear")]
    member: Member,
    /// Which flank of the tooth (right = the drive flank of flank's scenes).
    #[arg(long, value_enum, default_value = "right")]
    flank: Side,
    /// Sector tooth (1-based).
    #[arg(long, default_value_t = 1)]
    tooth: usize,
    /// Grid size FACExPROFILE: points across the face × along the profile.
    #[arg(long, default_value = "9x5")]
    points: String,
    /// Margin at each face end and at tip and form, as a fraction of the
    /// flank's extent.
    #[arg(long, default_value_t = 0.1)]
    inset: f64,
    /// Output CSV file.
    #[arg(long)]
    out: PathBuf,
}

fn grid_size(s: &str) -> Result<(usize, usize)> {
    let parse = |t: &str| t.trim().parse::<usize>().ok();
    match s.split_once(['x', 'X', '×']) {
        Some((a, b)) => match (parse(a), parse(b)) {
            (Some(a), Some(b)) => Ok((a, b)),
            _ => bail!("--points '{s}': expected FACExPROFILE, e.g. 9x5"),
        },
        None => bail!("--points '{s}': expected FACExPROFILE, e.g. 9x5"),
    }
}

pub fn run(args: Args) -> Result<()> {
    let (face_points, profile_points) = grid_size(&args.points)?;
    if !(0.0..0.5).contains(&args.inset) {
        bail!("--inset {}: the margin must be in [0, 0.5)", args.inset);
    }
    let scene = flank::scene::read_any_scene(&args.scene)?;
    let (b, name) = match args.member {
        Member::Pinion => (0, "pinion"),
        Member::Gear => (1, "gear"),
    };
    let (side, side_name) = match args.flank {
        Side::Left => (Flank::Left, "left"),
        Side::Right => (Flank::Right, "right"),
    };
    // cylindrical pairs through their gear pair; bevel/hypoid members as
    // the scene cut them
    let cylindrical;
    let body: &dyn GearBody = match &scene {
        AnyScene::Cylindrical(s) => {
            cylindrical = s.gear_pair()?;
            cylindrical.body(b)
        }
        AnyScene::Bevel(s) => s.bodies[b].as_ref(),
    };
    let surface = body.flank(side, args.tooth).with_context(|| {
        format!(
            "--tooth {}: the {name} sector has teeth 1..={}",
            args.tooth,
            body.sector_teeth()
        )
    })?;
    let spec = GridSpec {
        face_points,
        profile_points,
        face_inset: args.inset,
        profile_inset: args.inset,
    };
    let grid = measurement_grid(surface, &spec)?;
    let description = format!(
        "{} {name} ({}), {side_name} flank of sector tooth {}",
        args.scene.display(),
        body.name(),
        args.tooth
    );
    grid.write(&args.out, &description)?;
    println!(
        "wrote {} ({face_points} × {profile_points} points)",
        args.out.display()
    );
    Ok(())
}
