//! Figures written twice, as SVG (for documents) and PNG (for viewers),
//! with `plotters`' pure-Rust backends. A plot implements [`Figure`] once,
//! generic over the backend; [`write_svg_png`] draws it on both.
//!
//! Text uses `ab_glyph` with a TrueType font found at run time
//! (`$FLANK_FONT` or a common system path, [`font_available`]); without one,
//! or with `FLANK_FONT` set empty, figures are drawn without text.

use std::path::Path;
use std::sync::OnceLock;

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::error::FlankError;

const FONT_PATHS: &[&str] = &[
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/TTF/DejaVuSans.ttf",
    "/usr/share/fonts/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/truetype/liberation/LiberationSans-Regular.ttf",
    "/usr/share/fonts/liberation/LiberationSans-Regular.ttf",
    "/usr/share/fonts/truetype/freefont/FreeSans.ttf",
    "/System/Library/Fonts/Supplemental/Arial.ttf",
    "C:\\Windows\\Fonts\\arial.ttf",
];

/// Registers a sans-serif font with plotters once; true if one was found.
pub fn font_available() -> bool {
    static FONT: OnceLock<bool> = OnceLock::new();
    *FONT.get_or_init(|| {
        let env = std::env::var_os("FLANK_FONT").map(std::path::PathBuf::from);
        if env.as_ref().is_some_and(|p| p.as_os_str().is_empty()) {
            return false; // FLANK_FONT= (empty): plots without text
        }
        let candidates = env
            .into_iter()
            .chain(FONT_PATHS.iter().map(std::path::PathBuf::from));
        for p in candidates {
            if let Ok(bytes) = std::fs::read(&p) {
                let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
                if plotters::style::register_font("sans-serif", FontStyle::Normal, bytes).is_ok() {
                    return true;
                }
            }
        }
        false
    })
}

/// A plot that can be drawn on any plotters backend.
pub trait Figure {
    /// Pixel size (width, height).
    fn size(&self) -> (u32, u32);
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), String>;
}

/// Draws `figure` into `DIR/STEM.svg` and `DIR/STEM.png`; returns the two
/// file names.
pub fn write_svg_png(
    dir: &Path,
    stem: &str,
    figure: &impl Figure,
) -> Result<Vec<String>, FlankError> {
    let svg = format!("{stem}.svg");
    let png = format!("{stem}.png");
    write_pair(&dir.join(&svg), &dir.join(&png), figure)?;
    Ok(vec![svg, png])
}

/// Draws `figure` into the two given paths (SVG, PNG).
pub fn write_pair(svg: &Path, png: &Path, figure: &impl Figure) -> Result<(), FlankError> {
    let err = |p: &Path, e: String| FlankError::Model(format!("plot {}: {e}", p.display()));
    let size = figure.size();
    // drawn to temporary names (same extension: plotters picks the image
    // format from it) and renamed: a killed run leaves no half plot
    crate::atomic_file::write_with(svg, |tmp| {
        let root = SVGBackend::new(tmp, size).into_drawing_area();
        figure.draw(&root).map_err(|e| err(svg, e))?;
        root.present().map_err(|e| err(svg, e.to_string()))
    })?;
    crate::atomic_file::write_with(png, |tmp| {
        let root = BitMapBackend::new(tmp, size).into_drawing_area();
        figure.draw(&root).map_err(|e| err(png, e))?;
        root.present().map_err(|e| err(png, e.to_string()))
    })
}
