//! What `flank check` reports of a scene, typed: a cylindrical pair's
//! figures (contact ratios, working pressure angle, spans) with its ISO
//! 6336-1 stiffness, or a bevel/hypoid pair's ISO 23509 blank and how each
//! member is cut.

use serde::Serialize;

use super::validated::{Gears, PairKind, RackTipRadiusSource, Scene};
use crate::error::FlankError;
use crate::geometry::involute::rack_tip_radius_limit;
use crate::geometry::iso6336::ToothStiffness;
use crate::geometry::iso6336_3::NominalRootStress;
use crate::geometry::pair::PairReport;
use crate::geometry::{GearSpec, Hand};

/// The check of a scene's pair (`flank check` prints it as JSON).
#[derive(Clone, Debug, Serialize)]
#[serde(untagged)]
pub enum PairCheck {
    /// Spur and helical pairs.
    Cylindrical(Box<CylindricalCheck>),
    /// Spiral bevel and hypoid pairs.
    Bevel(Box<BevelCheck>),
}

/// A cylindrical pair's figures ([`crate::geometry::pair::check_pair`])
/// and the plausibility band of FE stiffness.
#[derive(Clone, Debug, Serialize)]
pub struct CylindricalCheck {
    #[serde(flatten)]
    pub report: PairReport,
    /// The generating racks the gears are cut with, and where each tip
    /// radius came from.
    pub racks: Racks,
    /// ISO 6336-1 single and mesh stiffness (N/(mm·µm)), or why the
    /// standard does not apply.
    pub iso6336_stiffness_n_per_mm_um: Iso6336Stiffness,
    /// ISO 6336-3 method B nominal root stress σ_F0 of both gears at the
    /// scene's torque, with Y_F, Y_S and the 30° tangent's geometry, or
    /// why the standard does not apply.
    pub iso6336_3_root_stress: Iso6336RootStress,
    /// The sector bodies: the teeth used, where the count came from, and
    /// the sector that holds every pair in mesh under the load.
    pub sector: SectorReport,
}

/// The sector bodies of a cylindrical pair
/// ([`crate::geometry::cylindrical::sector_size`]).
#[derive(Clone, Debug, Serialize)]
pub struct SectorReport {
    /// `[mesh] teeth_in_sector` as used.
    pub teeth: u32,
    /// `scene` or `default_pairs_in_mesh`.
    pub teeth_source: &'static str,
    /// Teeth that hold every pair in mesh over the middle pair's whole
    /// engagement, the pairs' offsets from the middle one, the single-pair
    /// approach δ and contact extension under the load (mm).
    pub in_mesh: Option<crate::geometry::cylindrical::sector_size::SectorInMesh>,
    /// Why the sectors used are too small, if they are.
    pub warning: Option<String>,
}

/// The generating racks of both gears.
#[derive(Clone, Debug, Serialize)]
pub struct Racks {
    pub pinion: RackReport,
    pub gear: RackReport,
}

/// One gear's generating rack as used (×m_n).
#[derive(Clone, Debug, Serialize)]
pub struct RackReport {
    /// h_fP*: cuts the gear's dedendum.
    pub addendum: f64,
    /// h_aP*: shapes the gear's addendum.
    pub dedendum: f64,
    /// ρ_fP*, the scene's or the default.
    pub tip_radius: f64,
    /// The largest ρ_fP* that fits the rack tooth tip at this addendum and
    /// α_n (a full root radius).
    pub tip_radius_limit: f64,
    pub tip_radius_source: RackTipRadiusSource,
}

impl RackReport {
    fn new(g: &GearSpec, source: RackTipRadiusSource) -> Self {
        RackReport {
            addendum: g.rack.addendum,
            dedendum: g.rack.dedendum,
            tip_radius: g.rack.tip_radius,
            tip_radius_limit: rack_tip_radius_limit(g.rack.addendum, g.normal_pressure_angle),
            tip_radius_source: source,
        }
    }
}

/// ISO 6336-3's nominal root stress, or the reason it does not apply.
#[derive(Clone, Debug, Serialize)]
#[serde(untagged)]
pub enum Iso6336RootStress {
    Figures(Box<NominalRootStress>),
    NotApplicable(String),
}

/// ISO 6336-1's stiffness, or the reason it does not apply.
#[derive(Clone, Debug, Serialize)]
#[serde(untagged)]
pub enum Iso6336Stiffness {
    Figures(ToothStiffness),
    NotApplicable(String),
}

/// A bevel/hypoid pair's blank table and cutting reports.
#[derive(Clone, Debug, Serialize)]
pub struct BevelCheck {
    pub kind: PairKind,
    /// ISO 23509 calculation method, 0–3.
    pub method: u8,
    pub pinion_hand: Hand,
    /// The standard's output keys (mm, degrees).
    pub blank: serde_json::Map<String, serde_json::Value>,
    /// Process, cutter, machine settings, mean-point figures measured on
    /// the flanks.
    pub pinion: serde_json::Value,
    pub gear: serde_json::Value,
}

/// Checks the scene's pair.
pub fn check(scene: &Scene) -> Result<PairCheck, FlankError> {
    match &scene.gears {
        Gears::Cylindrical(c) => {
            let report = crate::geometry::pair::check_pair(&c.pair)?;
            let iso = match crate::geometry::iso6336::tooth_stiffness(&c.pair, report.contact_ratio)
            {
                Ok(s) => Iso6336Stiffness::Figures(s),
                Err(e) => Iso6336Stiffness::NotApplicable(format!("not applicable: {e}")),
            };
            let torque = scene.load.torque_nmm;
            let root = if !(torque > 0.0) {
                Iso6336RootStress::NotApplicable(
                    "not applicable: the scene has no pinion torque ([load] torque_nm)".into(),
                )
            } else {
                match crate::geometry::iso6336_3::nominal_root_stress(
                    &c.pair,
                    report.contact_ratio,
                    report.overlap_ratio,
                    torque,
                ) {
                    Ok(s) => Iso6336RootStress::Figures(Box::new(s)),
                    Err(e) => Iso6336RootStress::NotApplicable(format!("not applicable: {e}")),
                }
            };
            let racks = Racks {
                pinion: RackReport::new(&c.pair.pinion, c.rack_tip_radius_source[0]),
                gear: RackReport::new(&c.pair.gear, c.rack_tip_radius_source[1]),
            };
            let sector = SectorReport {
                teeth: scene.mesh.teeth_in_sector,
                teeth_source: if c.teeth_in_sector_line.is_some() {
                    "scene"
                } else {
                    "default_pairs_in_mesh"
                },
                in_mesh: c.sector_in_mesh,
                warning: c.sector_in_mesh.and_then(|s| scene.sector_shortfall(s)),
            };
            Ok(PairCheck::Cylindrical(Box::new(CylindricalCheck {
                report,
                racks,
                iso6336_stiffness_n_per_mm_um: iso,
                iso6336_3_root_stress: root,
                sector,
            })))
        }
        Gears::Bevel(b) => Ok(PairCheck::Bevel(Box::new(BevelCheck {
            kind: scene.kind,
            method: b.blank.method,
            pinion_hand: b.pinion_hand,
            blank: b.blank.outputs(),
            pinion: b.cutting_report[0].clone(),
            gear: b.cutting_report[1].clone(),
        }))),
    }
}
