//! `flank grid SCENE`: one flank of one member of a scene (spur, helical,
//! spiral bevel or hypoid) as the measuring machine's grid (points and normals, `deviation_um` = 0) in CSV; a
//! measuring machine fills in the deviations and the file is read back as a
//! flank deviation (format: `flank::geometry::measurement_grid`).

use std::path::PathBuf;

use anyhow::{bail, Context, Result};
use flank::geometry::bevel::ease_off::deviation_grid_at;
use flank::geometry::gear_pair::{Flank, GearBody};
use flank::geometry::measurement_grid::{measurement_grid, GridSpec};
use flank::scene::Gears;

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
    /// Conjugate pinion with an `[pinion.ease_off]`: write in
    /// `deviation_um` the ease-off read back against the conjugate flank
    /// (closest-point distance; negative = material removed), the report of
    /// the pinion as deviations from the conjugate one.
    #[arg(long)]
    ease_off: bool,
    /// Output CSV file.
    #[arg(long)]
    out: PathBuf,
}

fn grid_size(s: &str) -> Result<(usize, usize)> {
    let parse = |t: &str| t.trim().parse::<usize>().ok();
    match s.split_once(['x', 'X', '×']) {
        Some((a, b)) => match (parse(a), parse(b)) {
            (Some(a), Some(b)) if a < 2 || b < 2 => {
                bail!("--points '{s}': a grid needs at least 2x2 points")
            }
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
    let scene = flank::scene::read_scene(&args.scene)?;
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
    let body: &dyn GearBody = match &scene.gears {
        Gears::Cylindrical(_) => {
            cylindrical = scene.gear_pair()?;
            cylindrical.body(b)
        }
        Gears::Bevel(s) => s.bodies[b].as_ref(),
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
    let mut grid = measurement_grid(surface, &spec)?;
    let mut description = format!(
        "{} {name} ({}), {side_name} flank of sector tooth {}",
        args.scene.display(),
        body.name(),
        args.tooth
    );
    if args.ease_off {
        let eased = match (&scene.gears, args.member) {
            (Gears::Bevel(s), Member::Pinion) => s.pinion_eased.as_ref(),
            _ => None,
        };
        let Some(eased) = eased else {
            bail!("--ease-off: only a conjugate pinion with an [pinion.ease_off] (bevel/hypoid scene, --member pinion) has an ease-off to report");
        };
        // Right = drive, Left = coast; (u, v) are those of the flank
        let e = &eased[if matches!(side, Flank::Right) { 0 } else { 1 }];
        let nodes: Vec<(f64, f64)> = grid.points.iter().map(|p| (p.u, p.v)).collect();
        let read = deviation_grid_at(e, &nodes)?;
        for (p, r) in grid.points.iter_mut().zip(&read) {
            p.deviation = -r.deviation_mm;
        }
        description.push_str(
            "; deviation_um = the ease-off read back against the conjugate flank (negative = material removed)",
        );
    }
    grid.write(&args.out, &description)?;
    println!(
        "wrote {} ({face_points} × {profile_points} points)",
        args.out.display()
    );
    Ok(())
}
