//! `flank import`: a gmsh mesh (.msh 4.1) as a CalculiX deck.

use std::path::PathBuf;

use anyhow::{Context, Result};

#[derive(clap::Args)]
pub struct Args {
    /// The gmsh mesh (.msh).
    mesh: PathBuf,
    /// Output deck (.inp).
    #[arg(long)]
    out: PathBuf,
    /// Young's modulus of the material (MPa).
    #[arg(long, default_value_t = 206000.0)]
    young_modulus: f64,
    /// Poisson's ratio of the material.
    #[arg(long, default_value_t = 0.3)]
    poisson_ratio: f64,
}

pub fn run(args: Args) -> Result<()> {
    let Args {
        mesh,
        out,
        young_modulus,
        poisson_ratio,
    } = args;
    let m = flank::mesh::msh::read_msh(&mesh)?;
    let ne = m.elements.len();
    let model = flank::fem::model::Model {
        materials: vec![flank::fem::material::Material::new(
            "MATERIAL",
            young_modulus,
            poisson_ratio,
        )
        .context("--young-modulus / --poisson-ratio")?],
        element_material: vec![0; ne],
        mesh: m,
        ..Default::default()
    };
    flank::deck::write_deck(&model, &out)?;
    let mesh = &model.mesh;
    let hex = mesh.elements.iter().filter(|e| e.kind.node_count() == 20);
    let hex = hex.count();
    let sets: Vec<&str> = mesh.node_sets.keys().map(|k| k.as_str()).collect();
    println!(
        "wrote {} ({} nodes, {hex} C3D20 + {} C3D15 elements; node sets: {})",
        out.display(),
        mesh.node_count(),
        ne - hex,
        if sets.is_empty() {
            "none".to_string()
        } else {
            sets.join(", ")
        }
    );
    Ok(())
}
