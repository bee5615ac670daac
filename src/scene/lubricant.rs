//! The `[lubricant]` table: the oil at its bulk temperature and the solids'
//! thermal data, SI units in the key names, converted to internal units by
//! [`crate::lubrication::Lubricant::from_si`]; every range error points at
//! its key's line.
//!
//! ```toml
//! [lubricant]
//! name = "MIL-PRF-23699 turbine oil at 100 °C"   # optional
//! bulk_temperature_c = 100.0                      # optional, informative
//! viscosity_pa_s = 0.0045                         # η₀
//! pressure_viscosity_per_gpa = 11.0               # α
//! temperature_viscosity_per_k = 0.03              # β
//! eyring_stress_mpa = 4.0                         # τ₀
//! conductivity_w_per_m_k = 0.14                   # K_l
//! solid_density_kg_per_m3 = 7800.0                # ρ_g
//! solid_specific_heat_j_per_kg_k = 460.0          # c_g
//! solid_conductivity_w_per_m_k = 45.0             # K_g
//! ```

use serde::Deserialize;
use toml::Spanned;

use super::analyses::Analyses;
use super::load::Load;
use super::location::{Cx, Res};
use crate::lubrication::lubricant::{check_range, Lubricant, LubricantSi};

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawLubricant {
    name: Option<String>,
    bulk_temperature_c: Option<Spanned<f64>>,
    viscosity_pa_s: Spanned<f64>,
    pressure_viscosity_per_gpa: Spanned<f64>,
    temperature_viscosity_per_k: Spanned<f64>,
    eyring_stress_mpa: Spanned<f64>,
    conductivity_w_per_m_k: Spanned<f64>,
    solid_density_kg_per_m3: Spanned<f64>,
    solid_specific_heat_j_per_kg_k: Spanned<f64>,
    solid_conductivity_w_per_m_k: Spanned<f64>,
}

/// The scene's lubricant, checked against `[analyses.lubrication]`: the
/// loop needs a `[lubricant]` table and a pinion speed > 0 (both pair
/// kinds).
pub(super) fn scene_lubricant(
    cx: &Cx,
    raw: Option<&RawLubricant>,
    analyses: &Analyses,
    load: &Load,
) -> Res<Option<Lubricant>> {
    let lubricant = match raw {
        Some(l) => Some(lubricant(cx, l)?),
        None => None,
    };
    if let Some(span) = analyses.lubrication_span.clone() {
        if lubricant.is_none() {
            return Err(cx.err(
                span,
                "`analyses.lubrication` needs a [lubricant] table (viscosity_pa_s, pressure_viscosity_per_gpa, …)".into(),
            ));
        }
        if !(load.speed_rpm > 0.0) {
            return Err(cx.err(
                span,
                format!(
                    "`analyses.lubrication` needs `load.speed_rpm` > 0 (got {}): an EHL film needs an entraining speed",
                    load.speed_rpm
                ),
            ));
        }
    }
    Ok(lubricant)
}

fn lubricant(cx: &Cx, raw: &RawLubricant) -> Res<Lubricant> {
    let check = |v: &Spanned<f64>, key: &str| -> Res<f64> {
        check_range(key, *v.get_ref()).map_err(|m| cx.err(v.span(), format!("[lubricant] {m}")))
    };
    let bulk_temperature_c = match &raw.bulk_temperature_c {
        Some(t) => {
            let x = cx.finite(t, "lubricant.bulk_temperature_c")?;
            if !(-60.0..=400.0).contains(&x) {
                return Err(cx.err(
                    t.span(),
                    format!("`lubricant.bulk_temperature_c` = {x}: must lie in -60 … 400 °C"),
                ));
            }
            Some(x)
        }
        None => None,
    };
    let si = LubricantSi {
        name: raw.name.clone().unwrap_or_default(),
        bulk_temperature_c,
        viscosity_pa_s: check(&raw.viscosity_pa_s, "viscosity_pa_s")?,
        pressure_viscosity_per_gpa: check(
            &raw.pressure_viscosity_per_gpa,
            "pressure_viscosity_per_gpa",
        )?,
        temperature_viscosity_per_k: check(
            &raw.temperature_viscosity_per_k,
            "temperature_viscosity_per_k",
        )?,
        eyring_stress_mpa: check(&raw.eyring_stress_mpa, "eyring_stress_mpa")?,
        conductivity_w_per_m_k: check(&raw.conductivity_w_per_m_k, "conductivity_w_per_m_k")?,
        solid_density_kg_per_m3: check(&raw.solid_density_kg_per_m3, "solid_density_kg_per_m3")?,
        solid_specific_heat_j_per_kg_k: check(
            &raw.solid_specific_heat_j_per_kg_k,
            "solid_specific_heat_j_per_kg_k",
        )?,
        solid_conductivity_w_per_m_k: check(
            &raw.solid_conductivity_w_per_m_k,
            "solid_conductivity_w_per_m_k",
        )?,
    };
    Lubricant::from_si(&si).map_err(|e| cx.err(raw.viscosity_pa_s.span(), e.to_string()))
}

#[cfg(test)]
mod tests {
    use crate::scene::test_support::*;

    pub(crate) const OIL: &str = "\n[lubricant]\nname = \"test\"\nviscosity_pa_s = 0.0045\npressure_viscosity_per_gpa = 11.0\ntemperature_viscosity_per_k = 0.03\neyring_stress_mpa = 4.0\nconductivity_w_per_m_k = 0.14\nsolid_density_kg_per_m3 = 7800.0\nsolid_specific_heat_j_per_kg_k = 460.0\nsolid_conductivity_w_per_m_k = 45.0\n";

    fn with_oil(analysis: &str) -> String {
        let t = edit(SPUR, "mesh = {}\n", &format!("mesh = {{}}\n{analysis}\n"));
        format!("{t}{OIL}")
    }

    #[test]
    fn lubricant_and_analysis_parse() {
        let t = with_oil("lubrication = { tolerance = 0.01, max_iterations = 4, initial_mu = 0.05, film = \"hamrock_dowson\", composite_roughness_um = 0.3 }");
        let s = parse(&t).unwrap();
        let l = s.lubricant.unwrap();
        assert!((l.viscosity_mpa_s - 4.5e-9).abs() < 1e-20);
        let a = s.analyses.lubrication.unwrap();
        assert_eq!(a.max_iterations, Some(4));
        assert_eq!(a.film, Some(crate::lubrication::FilmModel::HamrockDowson));
    }

    #[test]
    fn bad_lubricant_values_point_at_their_line() {
        for (from, to, words) in [
            (
                "viscosity_pa_s = 0.0045",
                "viscosity_pa_s = -0.0045",
                &["lubricant", "viscosity_pa_s", "-0.0045"][..],
            ),
            (
                "pressure_viscosity_per_gpa = 11.0",
                "pressure_viscosity_per_gpa = 1.1e-8",
                &["pressure_viscosity_per_gpa", "1/GPa"][..],
            ),
            (
                "eyring_stress_mpa = 4.0",
                "eyring_stress_mpa = nan",
                &["eyring_stress_mpa", "finite"][..],
            ),
        ] {
            let t = edit(&with_oil(""), from, to);
            expect_err(&t, line_of(&t, to), words);
        }
    }

    #[test]
    fn analysis_needs_lubricant_and_speed() {
        let t = edit(SPUR, "mesh = {}\n", "mesh = {}\nlubrication = {}\n");
        expect_err(
            &t,
            line_of(&t, "lubrication ="),
            &["analyses.lubrication", "[lubricant]"],
        );
        let t = edit(
            &with_oil("lubrication = {}"),
            "speed_rpm = 11758.0",
            "speed_rpm = 0.0",
        );
        expect_err(
            &t,
            line_of(&t, "lubrication ="),
            &["analyses.lubrication", "load.speed_rpm", "entraining"],
        );
        for (bad, words) in [
            ("lubrication = { tolerance = 0.0 }", &["tolerance"][..]),
            (
                "lubrication = { max_iterations = 0 }",
                &["max_iterations"][..],
            ),
            ("lubrication = { initial_mu = 0.0 }", &["initial_mu"][..]),
            ("lubrication = { film = \"grubin\" }", &["grubin"][..]),
        ] {
            let t = with_oil(bad);
            expect_err(&t, line_of(&t, "lubrication ="), words);
        }
    }
}
