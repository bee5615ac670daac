//! `flank cantilever`: the benchmark cantilever as a CalculiX deck.

use std::path::PathBuf;

use anyhow::Result;

#[derive(clap::Args)]
pub struct Args {
    /// Elements along x, y, z.
    #[arg(long, value_delimiter = ',', default_values_t = [100, 10, 10])]
    cells: Vec<usize>,
    /// Element type.
    #[arg(long, value_enum, default_value_t = DeckElement::C3d20)]
    element: DeckElement,
    /// Output deck.
    #[arg(long, default_value = "cantilever.inp")]
    out: PathBuf,
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum DeckElement {
    C3d20,
    C3d20r,
    C3d15,
}

pub fn run(args: Args) -> Result<()> {
    let Args {
        cells,
        element,
        out,
    } = args;
    let kind = match element {
        DeckElement::C3d20 => flank::mesh::structured::BoxElement::Hex20,
        DeckElement::C3d20r => flank::mesh::structured::BoxElement::Hex20R,
        DeckElement::C3d15 => flank::mesh::structured::BoxElement::Wedge15,
    };
    if cells.len() != 3 || cells.contains(&0) {
        anyhow::bail!("--cells needs three positive counts, e.g. --cells 100,10,10");
    }
    let model =
        flank::mesh::structured::cantilever_model([cells[0], cells[1], cells[2]], kind, 1000.0)?;
    flank::deck::write_deck(&model, &out)?;
    println!(
        "wrote {} ({} nodes, {} elements)",
        out.display(),
        model.mesh.node_count(),
        model.mesh.elements.len()
    );
    Ok(())
}
