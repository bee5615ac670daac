//! The `[analyses]` table: which analyses to run (`mesh`, `compliance`,
//! `contact`, `ltca`) and their options, range-checked.

use std::collections::BTreeMap;

use serde::Deserialize;
use toml::Spanned;

use super::location::{toml_message, Cx, Res};

/// Options of the `mesh` analysis (none yet: `mesh = {}`).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeshAnalysis {}

/// Options of the `compliance` analysis (nodal compliance tensors of both
/// bodies, [`crate::compliance`]), e.g.
/// `compliance = { clamp_cuts = false, flanks = "loaded", method = "schur" }`.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ComplianceAnalysis {
    /// Clamp the sector cut faces `CUT_A`, `CUT_B` as well as the bore
    /// (default false: the cut faces are free).
    #[serde(default)]
    pub clamp_cuts: bool,
    /// Flanks carrying tensors: `loaded` (default: `FLANK_R<k>`, the side the
    /// gear bodies load), `left`, `right` or `both`.
    #[serde(default)]
    pub flanks: crate::settings::FlankSelection,
    /// `full` (default here: `flank compliance` probes the fillet too) or
    /// `active`: the active flank plus a margin (spur/helical).
    #[serde(default)]
    pub flank_region: crate::settings::FlankRegion,
    /// `schur` (default) or `blocked`.
    #[serde(default)]
    pub method: crate::settings::Method,
    /// Memory for the right-hand-side blocks of the blocked method (MB, > 0).
    pub memory_budget_mb: Option<f64>,
}

/// Options of the `contact` analysis (FE contact over a mesh cycle,
/// [`crate::mesh_cycle`], run by `flank run`), e.g.
/// `contact = { roll_step_deg = 1.0, law = "hard" }`. Roll angles are in
/// flank's convention (0: the middle pair's kinematic contact at the pitch
/// point, positive in the drive direction); default: the middle pair's
/// kinematic engagement with two steps on each side.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactAnalysis {
    pub roll_start_deg: Option<f64>,
    pub roll_end_deg: Option<f64>,
    /// Step of the range (deg, > 0; default 1).
    pub roll_step_deg: Option<f64>,
    /// Explicit roll angles (deg); instead of the range.
    pub roll_angles_deg: Option<Vec<f64>>,
    /// A reference angle convention (e.g. a paper's): reference = roll −
    /// (kinematic start of single contact of the middle pair) + this value.
    pub reference_single_contact_start_deg: Option<f64>,
    /// Positions given in the reference convention (needs the key above).
    pub reference_angles_deg: Option<Vec<f64>>,
    /// `hard` (default) or `penalty`.
    pub law: Option<crate::settings::ContactLaw>,
    /// Penalty slope as a multiple of the automatic default (> 0, default 1).
    pub penalty_factor: Option<f64>,
    /// `auto` (default: the gear while a pair is before its kinematic start
    /// of contact, the pinion from then on), `pinion` or `gear`: the body
    /// whose flank nodes are slaves.
    pub slave: Option<crate::settings::SlaveBody>,
    /// Largest initial gap of a contact candidate (mm, > 0; default 0.2;
    /// doubled automatically, up to three times, at a position where nodes
    /// beyond it close under load).
    pub search_distance_mm: Option<f64>,
    /// Coulomb friction coefficient μ of the flanks (0…1; absent or 0:
    /// frictionless, no tangential terms at all). Stick is hard (no
    /// tangential penalty); each position is one static step, so the
    /// friction direction comes from the elastic tangential mismatch of the
    /// step, not from the kinematic sliding velocity.
    pub friction_mu: Option<f64>,
    /// Write one VTU file per position (default true).
    pub vtu: Option<bool>,
    /// Bisect the middle pair's first and last loaded angles to 0.01°
    /// for the contact ratio (default true).
    pub refine_contact_limits: Option<bool>,
}

/// Options of the `ltca` analysis (compliance-matrix loaded tooth contact
/// analysis over a mesh cycle, [`crate::ltca`], run by `flank ltca`), e.g.
/// `ltca = { points_per_line = 20 }`. Roll angles as in
/// [`ContactAnalysis`]; default: the middle pair's kinematic engagement with
/// two 1° steps on each side, extended while it is loaded at an end.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LtcaAnalysis {
    pub roll_start_deg: Option<f64>,
    pub roll_end_deg: Option<f64>,
    /// Step of the range (deg, > 0; default 1).
    pub roll_step_deg: Option<f64>,
    /// Explicit roll angles (deg); instead of the range.
    pub roll_angles_deg: Option<Vec<f64>>,
    /// K: candidate points along each contact line (2 … 2000; default 20).
    pub points_per_line: Option<usize>,
    /// `active-set` (default) or `clarabel`.
    pub solver: Option<crate::settings::QpSolver>,
    /// Local contact deformation: `half-space` (default) or `none`.
    pub local: Option<crate::settings::LocalModel>,
    /// FE cell half-width across the line in flank element sizes (> 0; default 1).
    pub fe_cell_factor: Option<f64>,
    /// Limit on the fixed-point iterations on the Hertz half-widths of the
    /// half-space model (1 … 100; default 10). Reaching it without the 1 %
    /// tolerance is reported under `iteration_limits` in summary.json.
    pub local_iterations: Option<usize>,
    /// Misalignment of the gear axis (µrad): [in the plane of action, normal to it].
    pub misalignment_urad: Option<[f64; 2]>,
    /// Centre-distance error (µm, |Δa| < 1 mm).
    pub centre_distance_error_um: Option<f64>,
    /// Largest separation (mm) at which tip-corner points are candidates (> 0).
    pub extension_mm: Option<f64>,
    /// Compliance mesh: flank and base element sizes (mm); default m_n/8, m_n/2
    /// (not the FE-contact `[mesh]` sizes, which are meant for FE contact).
    pub flank_size_mm: Option<f64>,
    pub base_size_mm: Option<f64>,
    /// Flank nodes carrying the tensors: `active` (default: the active
    /// flank plus a margin, [`crate::settings::FlankRegion::Active`]) or
    /// `full` (involute and root fillet). Spur/helical only.
    pub flank_region: Option<crate::settings::FlankRegion>,
    /// `"none"` (default: dense tensors) or a relative accuracy ε in
    /// (0, 1), e.g. `1e-6`: the tensors are built in block low-rank
    /// form from the bodies' factors without the dense tensor
    /// ([`crate::compliance::compressed_build`]), each block within ε of
    /// its Frobenius norm, and the frictionless LTCA reads its page pairs
    /// from it ([`crate::compliance::compressed`]).
    /// Spur/helical, frictionless only.
    pub compression: Option<crate::settings::Compression>,
    /// Coulomb friction coefficient of the flanks (0…1; absent or 0:
    /// frictionless): the frictional LTCA of seeds 001/003
    /// ([`crate::ltca::friction`]), the friction force against the
    /// kinematic sliding. Needs `[load] speed_rpm` > 0.
    pub friction_mu: Option<f64>,
    /// Load increments of the frictional solve (1 … 10000; default 10).
    pub increments: Option<usize>,
    /// What the friction resists: `incremental` (default, seeds 001/003),
    /// `standstill` (the mate held, as one static FE step) or `sliding`
    /// (the running mesh), [`crate::settings::FrictionModel`].
    pub friction_model: Option<crate::settings::FrictionModel>,
    /// Bevel/hypoid pairs: the LTCA variants with respect to edge contact
    /// (seed 000): `without` (default: flank contacts only), `with` (the
    /// TCA's edge contacts are candidates too) or `both`
    /// ([`crate::settings::EdgeVariants`]).
    pub edges: Option<crate::settings::EdgeVariants>,
    /// Bevel/hypoid pairs: positions over one mesh cycle, on the point
    /// TCA's grid (4 … 400; default 20). Seed 003 asks for 20, seed 001
    /// for 30; the spur/helical LTCA takes its roll range instead.
    pub positions: Option<usize>,
    /// Pinion torques (N·m) of the map over torque (every pair kind): the
    /// LTCA over one mesh pitch at each, its TE peak-to-peak, mesh-order
    /// harmonics and mesh stiffness (`ltca_torque_map.csv`); 1 … 50
    /// values, each > 0.
    pub torques_nm: Option<Vec<f64>>,
}

/// Options of the `lubrication` analysis (the wet–dry loop of seed 002,
/// [`crate::lubrication::wet_dry`], run by `flank run` with the FE contact
/// cycle; needs a `[lubricant]` table and a pinion speed > 0), e.g.
/// `lubrication = { tolerance = 0.005, max_iterations = 10 }`.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LubricationAnalysis {
    /// Largest relative change of μ between passes that ends the loop
    /// (0 < tol < 1; default 0.005, i.e. 0.5 %).
    pub tolerance: Option<f64>,
    /// Largest number of wet passes (1 … 100; default 10).
    pub max_iterations: Option<usize>,
    /// μ₀ of the dry pass (0 < μ₀ ≤ 1; default `analyses.contact.friction_mu`
    /// if > 0, else 0.05 as seed 002).
    pub initial_mu: Option<f64>,
    /// Film fit: `chittenden` (default, seed 002 eq. 2), `hamrock_dowson`,
    /// or the line-contact fits `dowson_higginson` and `pan_hamrock`.
    pub film: Option<crate::lubrication::FilmModel>,
    /// Composite roughness σ = (R_q1² + R_q2²)^½ (µm, > 0) for the λ ratio.
    pub composite_roughness_um: Option<f64>,
    /// P̄: `contact_area` (default, W/A of the contact solution, seed 002
    /// eqs. 10–11) or `hertz` (line contact from W and R_x; for meshes that
    /// do not resolve the contact width).
    pub mean_pressure: Option<crate::lubrication::MeanPressure>,
}

/// The analyses a scene asks for; an absent entry is not computed.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct Analyses {
    pub mesh: Option<MeshAnalysis>,
    pub compliance: Option<ComplianceAnalysis>,
    pub contact: Option<ContactAnalysis>,
    pub ltca: Option<LtcaAnalysis>,
    pub lubrication: Option<LubricationAnalysis>,
    /// Where `lubrication` was given (byte span; for errors found later).
    #[serde(skip)]
    pub(super) lubrication_span: Option<std::ops::Range<usize>>,
    /// Where `ltca` was given (byte span; for errors found later).
    #[serde(skip)]
    pub(super) ltca_span: Option<std::ops::Range<usize>>,
}

impl Analyses {
    /// Names an `[analyses]` table accepts.
    pub const KNOWN: &'static [&'static str] =
        &["mesh", "compliance", "contact", "ltca", "lubrication"];
}

pub(super) type RawAnalyses = Spanned<BTreeMap<Spanned<String>, Spanned<toml::Value>>>;

pub(super) fn analyses(cx: &Cx, raw: Option<&RawAnalyses>) -> Res<Analyses> {
    let mut out = Analyses::default();
    let Some(raw) = raw else {
        return Ok(out);
    };
    for (name, value) in raw.get_ref() {
        match name.get_ref().as_str() {
            "mesh" => {
                let v: MeshAnalysis = value.get_ref().clone().try_into().map_err(|e| {
                    cx.err(
                        value.span(),
                        format!("`analyses.mesh`: {}", toml_message(&e)),
                    )
                })?;
                out.mesh = Some(v);
            }
            "compliance" => {
                let v: ComplianceAnalysis = value.get_ref().clone().try_into().map_err(|e| {
                    cx.err(
                        value.span(),
                        format!("`analyses.compliance`: {}", toml_message(&e)),
                    )
                })?;
                if let Some(mb) = v.memory_budget_mb {
                    if !(mb > 0.0 && mb.is_finite()) {
                        return Err(cx.err(
                            value.span(),
                            format!(
                                "`analyses.compliance`: memory_budget_mb must be > 0, got {mb}"
                            ),
                        ));
                    }
                }
                out.compliance = Some(v);
            }
            "contact" => {
                let v: ContactAnalysis = value.get_ref().clone().try_into().map_err(|e| {
                    cx.err(
                        value.span(),
                        format!("`analyses.contact`: {}", toml_message(&e)),
                    )
                })?;
                check_contact_analysis(&v)
                    .map_err(|m| cx.err(value.span(), format!("`analyses.contact`: {m}")))?;
                out.contact = Some(v);
            }
            "ltca" => {
                let v: LtcaAnalysis = value.get_ref().clone().try_into().map_err(|e| {
                    cx.err(
                        value.span(),
                        format!("`analyses.ltca`: {}", toml_message(&e)),
                    )
                })?;
                check_ltca_analysis(&v)
                    .map_err(|m| cx.err(value.span(), format!("`analyses.ltca`: {m}")))?;
                out.ltca = Some(v);
                out.ltca_span = Some(value.span());
            }
            "lubrication" => {
                let v: LubricationAnalysis = value.get_ref().clone().try_into().map_err(|e| {
                    cx.err(
                        value.span(),
                        format!("`analyses.lubrication`: {}", toml_message(&e)),
                    )
                })?;
                check_lubrication_analysis(&v)
                    .map_err(|m| cx.err(value.span(), format!("`analyses.lubrication`: {m}")))?;
                out.lubrication = Some(v);
                out.lubrication_span = Some(value.span());
            }
            other => {
                return Err(cx.err(
                    name.span(),
                    format!(
                        "unknown analysis `{other}` in [analyses]; known analyses: {}",
                        Analyses::KNOWN.join(", ")
                    ),
                ))
            }
        }
    }
    Ok(out)
}

/// Range checks of `[analyses.contact]` (types are serde's).
fn check_contact_analysis(v: &ContactAnalysis) -> Result<(), String> {
    let finite = |name: &str, x: Option<f64>| match x {
        Some(x) if !x.is_finite() => Err(format!("{name} must be finite, got {x}")),
        _ => Ok(()),
    };
    finite("roll_start_deg", v.roll_start_deg)?;
    finite("roll_end_deg", v.roll_end_deg)?;
    finite(
        "reference_single_contact_start_deg",
        v.reference_single_contact_start_deg,
    )?;
    if let Some(s) = v.roll_step_deg {
        if !(s > 0.0 && s.is_finite()) {
            return Err(format!("roll_step_deg must be > 0, got {s}"));
        }
    }
    match (v.roll_start_deg, v.roll_end_deg) {
        (Some(a), Some(b)) if b < a => {
            return Err(format!("roll_end_deg ({b}) is before roll_start_deg ({a})"))
        }
        (Some(_), None) | (None, Some(_)) => {
            return Err("give both roll_start_deg and roll_end_deg, or neither".into())
        }
        _ => {}
    }
    if let (Some(a), Some(b), Some(s)) = (v.roll_start_deg, v.roll_end_deg, v.roll_step_deg) {
        if (b - a) / s > 100_000.0 {
            return Err(format!(
                "{:.0} positions from roll_start_deg, roll_end_deg and roll_step_deg: too many",
                (b - a) / s
            ));
        }
    }
    let explicit = v.roll_angles_deg.is_some() as u8 + v.reference_angles_deg.is_some() as u8;
    if explicit > 1 || (explicit == 1 && v.roll_start_deg.is_some()) {
        return Err(
            "give one of roll_start_deg/roll_end_deg, roll_angles_deg and reference_angles_deg"
                .into(),
        );
    }
    for (name, list) in [
        ("roll_angles_deg", &v.roll_angles_deg),
        ("reference_angles_deg", &v.reference_angles_deg),
    ] {
        if let Some(l) = list {
            if l.is_empty() || l.iter().any(|x| !x.is_finite()) {
                return Err(format!("{name} must be a non-empty list of finite angles"));
            }
        }
    }
    if v.reference_angles_deg.is_some() && v.reference_single_contact_start_deg.is_none() {
        return Err("reference_angles_deg needs reference_single_contact_start_deg".into());
    }
    if let Some(f) = v.penalty_factor {
        if !(f > 0.0 && f.is_finite()) {
            return Err(format!("penalty_factor must be > 0, got {f}"));
        }
        if v.law != Some(crate::settings::ContactLaw::Penalty) {
            return Err("penalty_factor needs law = \"penalty\"".into());
        }
    }
    if let Some(d) = v.search_distance_mm {
        if !(d > 0.0 && d.is_finite()) {
            return Err(format!("search_distance_mm must be > 0, got {d}"));
        }
    }
    if let Some(mu) = v.friction_mu {
        if !(0.0..=1.0).contains(&mu) {
            return Err(format!(
                "friction_mu must be in 0…1 (lubricated steel flanks: 0.02–0.1), got {mu}"
            ));
        }
    }
    Ok(())
}

/// Range checks of `[analyses.lubrication]` (types are serde's).
fn check_lubrication_analysis(v: &LubricationAnalysis) -> Result<(), String> {
    if let Some(t) = v.tolerance {
        if !(t > 0.0 && t < 1.0) {
            return Err(format!(
                "tolerance must be in (0, 1) (relative change of μ; 0.005 = 0.5 %), got {t}"
            ));
        }
    }
    if let Some(n) = v.max_iterations {
        if !(1..=100).contains(&n) {
            return Err(format!("max_iterations must be in 1 … 100, got {n}"));
        }
    }
    if let Some(mu) = v.initial_mu {
        if !(mu > 0.0 && mu <= 1.0) {
            return Err(format!(
                "initial_mu (μ₀ of the dry pass) must be in (0, 1], got {mu}"
            ));
        }
    }
    if let Some(r) = v.composite_roughness_um {
        if !(r > 0.0 && r.is_finite() && r < 100.0) {
            return Err(format!(
                "composite_roughness_um must be in (0, 100) µm, got {r}"
            ));
        }
    }
    Ok(())
}

/// Range checks of `[analyses.ltca]` (types are serde's).
fn check_ltca_analysis(v: &LtcaAnalysis) -> Result<(), String> {
    let range = ContactAnalysis {
        roll_start_deg: v.roll_start_deg,
        roll_end_deg: v.roll_end_deg,
        roll_step_deg: v.roll_step_deg,
        roll_angles_deg: v.roll_angles_deg.clone(),
        ..Default::default()
    };
    check_contact_analysis(&range)?;
    if let Some(k) = v.points_per_line {
        if !(2..=2000).contains(&k) {
            return Err(format!("points_per_line must be in 2 … 2000, got {k}"));
        }
    }
    if let Some(k) = v.local_iterations {
        if !(1..=100).contains(&k) {
            return Err(format!("local_iterations must be in 1 … 100, got {k}"));
        }
    }
    let positive = |name: &str, x: Option<f64>| match x {
        Some(x) if !(x > 0.0 && x.is_finite()) => Err(format!("{name} must be > 0, got {x}")),
        _ => Ok(()),
    };
    positive("fe_cell_factor", v.fe_cell_factor)?;
    positive("extension_mm", v.extension_mm)?;
    positive("flank_size_mm", v.flank_size_mm)?;
    positive("base_size_mm", v.base_size_mm)?;
    if let Some(m) = v.misalignment_urad {
        if m.iter().any(|x| !(x.is_finite() && x.abs() <= 1e5)) {
            return Err(format!(
                "misalignment_urad must be two finite angles of at most 1e5 µrad, got {m:?}"
            ));
        }
    }
    if let Some(d) = v.centre_distance_error_um {
        if !(d.is_finite() && d.abs() < 1000.0) {
            return Err(format!(
                "centre_distance_error_um must be finite and below 1000 µm in size, got {d}"
            ));
        }
    }
    if let Some(mu) = v.friction_mu {
        if !(0.0..=1.0).contains(&mu) {
            return Err(format!(
                "friction_mu must be in 0…1 (lubricated steel flanks: 0.02–0.1), got {mu}"
            ));
        }
    }
    if let Some(k) = v.increments {
        if !(1..=10_000).contains(&k) {
            return Err(format!("increments must be in 1 … 10000, got {k}"));
        }
    }
    if let Some(n) = v.positions {
        if !(4..=400).contains(&n) {
            return Err(format!(
                "positions must be in 4 … 400 per mesh cycle, got {n}"
            ));
        }
    }
    if let Some(t) = &v.torques_nm {
        if t.is_empty() || t.len() > 50 {
            return Err(format!(
                "torques_nm must hold 1 … 50 torques, got {}",
                t.len()
            ));
        }
        if let Some(x) = t.iter().find(|x| !(x.is_finite() && **x > 0.0)) {
            return Err(format!("torques_nm: every torque must be > 0 N·m, got {x}"));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use crate::scene::test_support::*;

    #[test]
    fn contact_analysis_keys() {
        let ok = edit(
            SPUR,
            "mesh = {}\n",
            "mesh = {}\ncontact = { roll_start_deg = -20.0, roll_end_deg = 20.0, roll_step_deg = 0.5, law = \"penalty\", penalty_factor = 10.0, slave = \"gear\", friction_mu = 0.0 }\n",
        );
        let s = parse(&ok).unwrap();
        let c = s.analyses.contact.unwrap();
        assert_eq!(c.law, Some(crate::settings::ContactLaw::Penalty));
        assert_eq!(c.slave, Some(crate::settings::SlaveBody::Gear));
        for (bad, words) in [
            (
                "contact = { friction_mu = -0.1 }",
                &["friction_mu", "0…1"][..],
            ),
            (
                "contact = { friction_mu = 1.5 }",
                &["friction_mu", "0…1"][..],
            ),
            (
                "contact = { roll_step_deg = 0.0 }",
                &["roll_step_deg", "> 0"][..],
            ),
            ("contact = { roll_start_deg = 5.0 }", &["roll_end_deg"][..]),
            (
                "contact = { roll_start_deg = 5.0, roll_end_deg = -5.0 }",
                &["before"][..],
            ),
            ("contact = { penalty_factor = 10.0 }", &["penalty"][..]),
            (
                "contact = { law = \"soft\" }",
                &["analyses.contact", "soft"][..],
            ),
            (
                "contact = { reference_angles_deg = [18.0] }",
                &["reference_single_contact_start_deg"][..],
            ),
            (
                "contact = { search_distance_mm = -1.0 }",
                &["search_distance_mm"][..],
            ),
            (
                "contact = { roll_angles_deg = [] }",
                &["roll_angles_deg"][..],
            ),
            ("contact = { rpm = 3 }", &["analyses.contact", "rpm"][..]),
        ] {
            let t = edit(SPUR, "mesh = {}\n", &format!("mesh = {{}}\n{bad}\n"));
            expect_err(&t, line_of(&t, "contact ="), words);
        }
    }

    #[test]
    fn ltca_friction_keys() {
        let ok = edit(
            SPUR,
            "mesh = {}\n",
                        "mesh = {}\nltca = { friction_mu = 0.05, increments = 20, friction_model = \"sliding\" }\n",
        );
        let l = parse(&ok).unwrap().analyses.ltca.unwrap();
        assert_eq!((l.friction_mu, l.increments), (Some(0.05), Some(20)));
        for (bad, words) in [
            (
                "ltca = { friction_mu = -0.01 }",
                &["friction_mu", "0…1"][..],
            ),
            ("ltca = { friction_mu = 2.0 }", &["friction_mu", "0…1"][..]),
            ("ltca = { increments = 0 }", &["increments", "10000"][..]),
            (
                "ltca = { increments = 20000 }",
                &["increments", "10000"][..],
            ),
            (
                "ltca = { friction_model = \"viscous\" }",
                &["analyses.ltca", "viscous"][..],
            ),
        ] {
            let t = edit(SPUR, "mesh = {}\n", &format!("mesh = {{}}\n{bad}\n"));
            expect_err(&t, line_of(&t, "ltca ="), words);
        }
    }

    #[test]
    fn ltca_positions_key() {
        for (bad, words) in [
            ("ltca = { positions = 3 }", &["positions", "4 … 400"][..]),
            ("ltca = { positions = 401 }", &["positions", "4 … 400"][..]),
            // in range, but the spur LTCA takes a roll range
            (
                "ltca = { positions = 30 }",
                &["positions = 30", "bevel and hypoid", "roll_step_deg"][..],
            ),
        ] {
            let t = edit(SPUR, "mesh = {}\n", &format!("mesh = {{}}\n{bad}\n"));
            expect_err(&t, line_of(&t, "ltca ="), words);
        }
    }

    /// `torques_nm`: read as given; an empty list or a torque ≤ 0 refused
    /// naming the file, the line and the key; a string naming the file,
    /// the line and the table.
    #[test]
    fn ltca_torques_key() {
        let ok = edit(
            SPUR,
            "mesh = {}\n",
            "mesh = {}\nltca = { torques_nm = [50.0, 100.0, 312.0] }\n",
        );
        let l = parse(&ok).unwrap().analyses.ltca.unwrap();
        assert_eq!(l.torques_nm, Some(vec![50.0, 100.0, 312.0]));
        for (bad, words) in [
            ("ltca = { torques_nm = [] }", &["torques_nm", "1 … 50"][..]),
            (
                "ltca = { torques_nm = [100.0, -5.0] }",
                &["torques_nm", "> 0 N·m", "-5"][..],
            ),
            (
                "ltca = { torques_nm = [100.0, 0.0] }",
                &["torques_nm", "> 0 N·m"][..],
            ),
            // a wrong type: serde's message names the table and the type
            // (as for every key of the table), the line points at it
            (
                "ltca = { torques_nm = \"100\" }",
                &["analyses.ltca", "expected a sequence"][..],
            ),
        ] {
            let t = edit(SPUR, "mesh = {}\n", &format!("mesh = {{}}\n{bad}\n"));
            expect_err(&t, line_of(&t, "ltca ="), words);
        }
    }

    #[test]
    fn unknown_analysis() {
        let t = edit(SPUR, "mesh = {}\n", "mesh = {}\nthermal = {}\n");
        expect_err(
            &t,
            line_of(&t, "thermal"),
            &["thermal", "known analyses: mesh", "ltca", "lubrication"],
        );
        let t = edit(SPUR, "mesh = {}\n", "mesh = { order = 2 }\n");
        expect_err(&t, line_of(&t, "order"), &["analyses.mesh", "order"]);
    }
}
