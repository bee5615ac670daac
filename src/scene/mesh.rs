//! The `[mesh]` section: sector size, element family and element sizes.

use serde::Deserialize;
use toml::Spanned;

use super::location::{Cx, Res};

/// Solid element family for the tooth-sector mesh.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ElementKind {
    Hex20,
    Wedge15,
}

/// Meshing options (mm). `None` sizes are left to the mesher.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct MeshOptions {
    /// Teeth in each body's sector (1 ≤ n ≤ the smaller tooth count); default 3.
    pub teeth_in_sector: u32,
    /// Default `Hex20`.
    pub element: ElementKind,
    /// Element size on the flanks (mm), < the normal module and ≤ `base_size`.
    pub flank_size: Option<f64>,
    /// Element size away from the flanks (mm).
    pub base_size: Option<f64>,
}

impl Default for MeshOptions {
    fn default() -> Self {
        MeshOptions {
            teeth_in_sector: 3,
            element: ElementKind::Hex20,
            flank_size: None,
            base_size: None,
        }
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawMesh {
    teeth_in_sector: Option<Spanned<i64>>,
    element: Option<Spanned<ElementKind>>,
    flank_size_mm: Option<Spanned<f64>>,
    base_size_mm: Option<Spanned<f64>>,
}

pub(super) fn mesh_options(
    cx: &Cx,
    raw: Option<&RawMesh>,
    min_teeth: u32,
    min_module: f64,
) -> Res<MeshOptions> {
    let mut out = MeshOptions::default();
    let Some(m) = raw else {
        return Ok(out);
    };
    if let Some(n) = &m.teeth_in_sector {
        let v = *n.get_ref();
        if !(1..=i64::from(min_teeth)).contains(&v) {
            return Err(cx.err(
                n.span(),
                format!("`mesh.teeth_in_sector` = {v}: must lie in 1..={min_teeth} (the smaller tooth count)"),
            ));
        }
        out.teeth_in_sector = v as u32;
    }
    if let Some(e) = &m.element {
        out.element = *e.get_ref();
    }
    if let Some(v) = &m.flank_size_mm {
        let s = cx.positive(v, "mesh.flank_size_mm")?;
        if !(s < min_module) {
            return Err(cx.err(
                v.span(),
                format!(
                    "`mesh.flank_size_mm` = {s}: must be smaller than the normal module {min_module} mm to resolve a flank"
                ),
            ));
        }
        out.flank_size = Some(s);
    }
    if let Some(v) = &m.base_size_mm {
        let s = cx.positive(v, "mesh.base_size_mm")?;
        if let Some(f) = out.flank_size {
            if s < f {
                return Err(cx.err(
                    v.span(),
                    format!("`mesh.base_size_mm` = {s}: must not be smaller than `mesh.flank_size_mm` = {f}"),
                ));
            }
        }
        out.base_size = Some(s);
    }
    Ok(out)
}

/// Lines of `teeth_in_sector`, `flank_size_mm` and `base_size_mm` when given.
pub(super) fn key_lines(cx: &Cx, raw: Option<&RawMesh>) -> [Option<usize>; 3] {
    let Some(m) = raw else {
        return [None; 3];
    };
    [
        m.teeth_in_sector.as_ref().map(|v| cx.line(v.span().start)),
        m.flank_size_mm.as_ref().map(|v| cx.line(v.span().start)),
        m.base_size_mm.as_ref().map(|v| cx.line(v.span().start)),
    ]
}

/// A bevel/hypoid scene's element sizes against its members' teeth: the
/// flank size must fit each member's face width and mean whole depth twice
/// and the base size (the element length along the face) the face width
/// twice: with one element along the face or the depth the hex20 flank
/// faces cannot follow the spiral or the profile (a 50 mm flank size on
/// seed 003 meshed with scaled Jacobians of 0.12, a 60 mm base size with
/// one face layer and an aspect ratio of 71).
pub(super) fn check_bevel_sizes(
    cx: &Cx,
    raw: Option<&RawMesh>,
    bodies: &[std::sync::Arc<crate::geometry::bevel::body::BevelGear>; 2],
) -> Res<()> {
    let Some(m) = raw else {
        return Ok(());
    };
    for (name, body) in ["pinion", "gear"].iter().zip(bodies) {
        let c = body.cones();
        let depth = c.ham + c.hfm;
        if let Some(v) = &m.flank_size_mm {
            let limit = 0.5 * c.b.min(depth);
            if *v.get_ref() > limit {
                return Err(cx.err(
                    v.span(),
                    format!(
                        "`mesh.flank_size_mm` = {}: the flank elements do not fit the {name}'s teeth twice (face width {:.3} mm, mean whole depth {depth:.3} mm): at most {limit:.3} mm",
                        v.get_ref(),
                        c.b
                    ),
                ));
            }
        }
        if let Some(v) = &m.base_size_mm {
            let limit = 0.5 * c.b;
            if *v.get_ref() > limit {
                return Err(cx.err(
                    v.span(),
                    format!(
                        "`mesh.base_size_mm` = {}: the flank elements do not fit the {name}'s face width {:.3} mm twice along the face: at most {limit:.3} mm",
                        v.get_ref(),
                        c.b
                    ),
                ));
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use crate::scene::test_support::*;

    #[test]
    fn mesh_options_checked() {
        let t = edit(SPUR, "teeth_in_sector = 3", "teeth_in_sector = 0");
        expect_err(
            &t,
            line_of(&t, "teeth_in_sector"),
            &["mesh.teeth_in_sector"],
        );
        let t = edit(SPUR, "element = \"wedge15\"", "element = \"tet10\"");
        expect_err(&t, line_of(&t, "tet10"), &["tet10"]);
        let t = edit(SPUR, "base_size_mm = 1.0", "base_size_mm = 0.05");
        expect_err(&t, line_of(&t, "base_size_mm"), &["mesh.base_size_mm"]);
    }
}
