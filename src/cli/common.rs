//! Pieces shared by the subcommands: the sector mesh options of the scene
//! commands and the printing of a summary's notes and wet–dry loop.

/// Sector mesh sizes and element of the scene's bodies, overriding its [mesh].
#[derive(clap::Args, Clone, Copy)]
pub struct SectorArgs {
    /// Flank element size (mm); overrides the scene's [mesh] flank_size_mm.
    #[arg(long)]
    flank_size: Option<f64>,
    /// Base element size (mm); overrides the scene's [mesh] base_size_mm.
    #[arg(long)]
    base_size: Option<f64>,
    /// Element type; overrides the scene's [mesh] element.
    #[arg(long, value_enum)]
    element: Option<MeshElement>,
}

impl SectorArgs {
    pub fn body_options(self, with_load: bool) -> flank::compliance::body::BodyMeshOptions {
        flank::compliance::body::BodyMeshOptions {
            flank_size: self.flank_size,
            base_size: self.base_size,
            with_load,
            element: self.element.map(|e| match e {
                MeshElement::Hex20 => flank::scene::ElementKind::Hex20,
                MeshElement::Wedge15 => flank::scene::ElementKind::Wedge15,
            }),
        }
    }
}

#[derive(Clone, Copy, PartialEq, clap::ValueEnum)]
pub enum MeshElement {
    Hex20,
    Wedge15,
}

/// Prints the one-line summary of a wet–dry loop and its warnings.
pub fn print_wet_dry_loop(l: &flank::report::lubrication::LubricationSummary) {
    println!(
        "lubrication: {} wet pass(es), {}; last change of μ {:+.3} %; μ max {:.4}; mesh power loss {:.0} W, efficiency {:.3} %",
        l.iterations,
        if l.converged {
            "converged"
        } else {
            "NOT converged (iteration bound hit)"
        },
        100.0 * l.mu_last_change_rel,
        l.mu_max,
        l.power_loss_w,
        100.0 * l.efficiency
    );
    for w in &l.warnings {
        println!("warning: {w}");
    }
}
