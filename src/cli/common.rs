//! Pieces shared by the subcommands: the sector mesh options of the scene
//! commands, the printing of a summary's notes and wet–dry loop, and the
//! contact-ratio line of a spur/helical cycle.

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

/// The contact ratio and single-pair force of a spur/helical cycle as
/// `flank ltca` and `flank run` print them; a figure that was not measured
/// is said in words (summary.json has null there), never printed as NaN.
pub fn contact_ratio_line(
    contact_ratio: Option<f64>,
    kinematic: f64,
    single_pair_force_n: Option<f64>,
    nominal_force_n: f64,
    single_pair_force_error: Option<f64>,
) -> String {
    let ratio = match contact_ratio.filter(|x| x.is_finite()) {
        Some(x) => format!("contact ratio {x:.4} (kinematic ε_α {kinematic:.4})"),
        None => format!(
            "contact ratio not measured: the roll angles do not cover the middle pair's whole engagement (kinematic ε_α {kinematic:.4})"
        ),
    };
    let force = match (
        single_pair_force_n.filter(|x| x.is_finite()),
        single_pair_force_error.filter(|x| x.is_finite()),
    ) {
        (Some(f), Some(e)) => format!(
            "single-pair force {f:.1} N vs T/(r_b1 cos β_b) = {nominal_force_n:.1} N ({:+.2} %)",
            100.0 * e
        ),
        _ => format!(
            "single-pair force not measured: no position has the middle pair loaded alone (T/(r_b1 cos β_b) = {nominal_force_n:.1} N)"
        ),
    };
    format!("{ratio}; {force}")
}

#[cfg(test)]
mod tests {
    use super::contact_ratio_line;

    /// Issue 56: an unmeasured contact ratio or single-pair force was printed
    /// as NaN; it is said in words, and measured figures print as before.
    #[test]
    fn unmeasured_figures_in_words() {
        let l = contact_ratio_line(None, 1.6191, None, 13065.2, None);
        assert!(!l.contains("NaN") && !l.contains("inf"), "{l}");
        assert!(l.contains("contact ratio not measured: the roll angles do not cover"));
        assert!(l.contains("kinematic ε_α 1.6191"));
        assert!(l.contains("single-pair force not measured"));
        assert!(l.contains("13065.2 N"));
        let l = contact_ratio_line(Some(1.5), 1.4844, Some(11000.0), 11218.1, Some(-0.0194));
        assert_eq!(
            l,
            "contact ratio 1.5000 (kinematic ε_α 1.4844); single-pair force 11000.0 N vs T/(r_b1 cos β_b) = 11218.1 N (-1.94 %)"
        );
        let l = contact_ratio_line(Some(f64::NAN), 1.2, Some(1.0), 1.0, Some(f64::INFINITY));
        assert!(!l.contains("NaN") && !l.contains("inf"), "{l}");
    }
}
