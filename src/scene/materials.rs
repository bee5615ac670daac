//! The `[materials.<name>]` tables and the `material` key of each gear.

use std::collections::BTreeMap;

use serde::Deserialize;
use toml::Spanned;

use super::location::{Cx, Res};
use crate::fem::material::Material;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawMaterial {
    young_modulus_mpa: Spanned<f64>,
    poisson_ratio: Spanned<f64>,
}

pub(super) fn material(
    cx: &Cx,
    materials: &BTreeMap<String, RawMaterial>,
    name: &Spanned<String>,
    gear: &str,
) -> Res<Material> {
    let n = name.get_ref();
    let Some(m) = materials.get(n) else {
        let known: Vec<&str> = materials.keys().map(String::as_str).collect();
        return Err(cx.err(
            name.span(),
            format!(
                "`{gear}.material` = \"{n}\": no [materials.{n}] table (defined: {})",
                if known.is_empty() {
                    "none".to_string()
                } else {
                    known.join(", ")
                }
            ),
        ));
    };
    let e_key = format!("materials.{n}.young_modulus_mpa");
    let nu_key = format!("materials.{n}.poisson_ratio");
    let e = cx.positive(&m.young_modulus_mpa, &e_key)?;
    let nu = cx.finite(&m.poisson_ratio, &nu_key)?;
    if !(nu > -1.0 && nu < 0.5) {
        return Err(cx.err(
            m.poisson_ratio.span(),
            format!("`{nu_key}` = {nu}: must lie in (-1, 0.5)"),
        ));
    }
    Material::new(n, e, nu).map_err(|err| cx.err(m.young_modulus_mpa.span(), err.to_string()))
}

#[cfg(test)]
mod tests {
    use crate::scene::test_support::*;

    #[test]
    fn poisson_one_half() {
        let t = edit(SPUR, "poisson_ratio = 0.3", "poisson_ratio = 0.5");
        expect_err(
            &t,
            line_of(&t, "poisson_ratio"),
            &["materials.steel.poisson_ratio", "0.5"],
        );
        let t = edit(
            SPUR,
            "young_modulus_mpa = 206000.0",
            "young_modulus_mpa = 0.0",
        );
        expect_err(&t, line_of(&t, "young_modulus_mpa"), &["young_modulus_mpa"]);
    }

    #[test]
    fn unknown_material() {
        let t = edit(
            SPUR,
            "bore_diameter_mm = 80.0\nmaterial = \"steel\"",
            "bore_diameter_mm = 80.0\nmaterial = \"bronze\"",
        );
        expect_err(
            &t,
            line_of(&t, "\"bronze\""),
            &["gear.material", "bronze", "steel"],
        );
    }
}
