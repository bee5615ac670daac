//! The validated scene: what every analysis reads, in internal units (mm,
//! N, N·mm, MPa, rad), for every pair kind; [`Gears`] holds what only
//! one kind has.

use std::path::PathBuf;
use std::sync::Arc;

use serde::Deserialize;

use super::analyses::Analyses;
use super::load::Load;
use super::mesh::MeshOptions;
use crate::error::FlankError;
use crate::fem::material::Material;
use crate::geometry::bevel::body::BevelGear;
use crate::geometry::bevel::cutting::{MachineCut, PinionCut};
use crate::geometry::bevel::pair::BevelPair;
use crate::geometry::bevel::{BlankDesign, BlankInputs};
use crate::geometry::cylindrical::sector_size::{sector_for_rolls, SectorInMesh};
use crate::geometry::cylindrical::CylindricalPair;
use crate::geometry::gear_pair::{sector_teeth_holding, LineContactPair};
use crate::geometry::micro::{roll_angle_at_radius, FlankModification, MicroGeometry};
use crate::geometry::rack::ToothProfile;
use crate::geometry::{Hand, PairSpec};

/// A parsed and validated scene, in internal units: the pair, whose kind
/// is data ([`PairKind`], with the kind's own gear data in [`Gears`]), the
/// materials, the load, the analyses asked for and the meshing options.
/// Every analysis reads one of these, whatever the pair kind.
#[derive(Clone, Debug)]
pub struct Scene {
    pub kind: PairKind,
    /// The gears of the pair: what only one pair kind has.
    pub gears: Gears,
    pub pinion_material: Material,
    pub gear_material: Material,
    pub load: Load,
    pub analyses: Analyses,
    pub mesh: MeshOptions,
    /// `[lubricant]`: oil and solid thermal data (internal units), if given
    /// (spur and helical pairs: the bevel reader refuses the table).
    pub lubricant: Option<crate::lubrication::Lubricant>,
    /// The scene file (as given); relative paths inside it are resolved against its folder.
    pub source: PathBuf,
    /// 1-based line of `pair.kind` (where a kind an analysis does not
    /// handle is reported).
    pub kind_line: usize,
}

/// The gears of a pair, by pair kind.
#[derive(Clone, Debug)]
#[allow(clippy::large_enum_variant)]
pub enum Gears {
    /// Spur or helical: ISO 21771 gear data and flank modifications.
    Cylindrical(CylindricalGears),
    /// Spiral bevel or hypoid: the ISO 23509 blank and both members cut.
    Bevel(Box<BevelGears>),
}

/// The gears of a spur or helical pair.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct CylindricalGears {
    /// For spur pairs the helix angles are 0 and the hands `Right` (meaningless).
    pub pair: PairSpec,
    /// Flank modifications of `[pinion, gear]`.
    pub micro: [Option<MicroGeometry>; 2],
    /// Where the rack tip radius ρ_fP* of `[pinion, gear]` came from.
    pub rack_tip_radius_source: [RackTipRadiusSource; 2],
    /// The sector that holds every pair in mesh over the middle pair's
    /// whole engagement under the scene's load: the default of
    /// `[mesh] teeth_in_sector` (`None` if the pair could not be built).
    pub sector_in_mesh: Option<SectorInMesh>,
    /// Line of `[mesh] teeth_in_sector` when the scene gives it.
    pub teeth_in_sector_line: Option<usize>,
}

/// Where a generating rack's tip radius ρ_fP* came from (`flank check` reports it).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum RackTipRadiusSource {
    /// The scene's `rack.tip_radius`.
    Scene,
    /// The default where it fits: ISO 53:1998 profile A's 0.38.
    DefaultIso53,
    /// The default where 0.38 does not fit the rack tooth tip: 0.99 × the
    /// full root radius (`geometry::involute::default_rack_tip_radius`).
    DefaultNearFullRadius,
}

/// Kind of a gear pair (`[pair] kind`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PairKind {
    /// Parallel axes, straight teeth.
    Spur,
    /// Parallel axes, helical teeth.
    Helical,
    /// Intersecting axes (ISO 23509 method 0).
    SpiralBevel,
    /// Offset axes (ISO 23509 methods 1–3).
    Hypoid,
}

impl CylindricalGears {
    /// The flank modifications of `[pinion, gear]`, bound to their gears
    /// ([`FlankModification::new`]): tooth profiles, the start of active
    /// profile from [`crate::geometry::pair::check_pair`] and the face widths.
    /// `None` where the scene has no `[<gear>.micro]`; warnings (e.g. a
    /// measured range that does not cover the active profile) are in
    /// [`FlankModification::warnings`].
    pub fn flank_modifications(&self) -> Result<[Option<FlankModification>; 2], FlankError> {
        let bind = |i: usize, name: &str| {
            self.flank_modification(i).map_err(|e| match e {
                FlankError::Model(m) => FlankError::Model(format!("{name}: {m}")),
                e => e,
            })
        };
        Ok([bind(0, "pinion")?, bind(1, "gear")?])
    }

    /// The flank modification of member `i` (0 = pinion, 1 = gear) bound to
    /// its gear (see [`CylindricalGears::flank_modifications`]).
    pub(super) fn flank_modification(
        &self,
        i: usize,
    ) -> Result<Option<FlankModification>, FlankError> {
        let Some(micro) = &self.micro[i] else {
            return Ok(None);
        };
        let report = crate::geometry::pair::check_pair(&self.pair)?;
        let (spec, name, sap) = if i == 0 {
            (
                &self.pair.pinion,
                "pinion",
                report.pinion.active_start_radius,
            )
        } else {
            (&self.pair.gear, "gear", report.gear.active_start_radius)
        };
        let profile = ToothProfile::new(spec, name)?;
        let u_sap = roll_angle_at_radius(profile.geometry.base_radius, sap)?;
        FlankModification::new(micro, &profile, u_sap, spec.face_width).map(Some)
    }
}

impl Scene {
    /// The spur/helical gears, or the error that `what` (an analysis or
    /// option, e.g. "the contact-band study") handles spur and helical
    /// pairs only, at the scene's `pair.kind` line.
    pub fn cylindrical(&self, what: &str) -> Result<&CylindricalGears, FlankError> {
        match &self.gears {
            Gears::Cylindrical(c) => Ok(c),
            Gears::Bevel(_) => Err(self.kind_error(what, "spur and helical")),
        }
    }

    /// [`Scene::cylindrical`], to edit (a study that varies the gears of a
    /// scene it has read).
    pub fn cylindrical_mut(&mut self, what: &str) -> Result<&mut CylindricalGears, FlankError> {
        if self.is_bevel() {
            return Err(self.kind_error(what, "spur and helical"));
        }
        match &mut self.gears {
            Gears::Cylindrical(c) => Ok(c),
            Gears::Bevel(_) => unreachable!("checked above"),
        }
    }

    /// The bevel/hypoid gears, or the error that `what` handles spiral
    /// bevel and hypoid pairs only, at the scene's `pair.kind` line.
    pub fn bevel(&self, what: &str) -> Result<&BevelGears, FlankError> {
        match &self.gears {
            Gears::Bevel(b) => Ok(b),
            Gears::Cylindrical(_) => Err(self.kind_error(what, "spiral bevel and hypoid")),
        }
    }

    /// The pair's (mean) normal module m_n (mm): the gears' normal module
    /// of a cylindrical pair, ISO 23509's mean normal module m_mn of a
    /// bevel pair. The scale of the meshing defaults.
    pub fn normal_module(&self) -> f64 {
        match &self.gears {
            Gears::Cylindrical(c) => c.pair.pinion.normal_module,
            Gears::Bevel(b) => b.blank.cones.m_mn,
        }
    }

    /// Whether the pair is a spiral bevel or hypoid pair.
    pub fn is_bevel(&self) -> bool {
        matches!(self.gears, Gears::Bevel(_))
    }

    fn kind_error(&self, what: &str, kinds: &str) -> FlankError {
        FlankError::Parse {
            file: self.source.clone(),
            line: self.kind_line,
            message: format!(
                "`pair.kind` = \"{}\": {what} handles {kinds} pairs only",
                self.kind.name()
            ),
        }
    }

    /// `file:line` of a line of the scene.
    pub fn at(&self, line: usize) -> String {
        format!("{}:{line}", self.source.display())
    }

    /// The scene's spur/helical pair behind the gear-pair interface, as
    /// sectors of `[mesh] teeth_in_sector` teeth with the flank
    /// modifications, aligned.
    pub fn cylindrical_pair(&self) -> Result<CylindricalPair, FlankError> {
        let c = self.cylindrical("the cylindrical gear-pair model")?;
        CylindricalPair::new(
            &c.pair,
            c.flank_modifications()?,
            self.mesh.teeth_in_sector as usize,
        )
    }

    /// A warning when the sectors of `[mesh] teeth_in_sector` teeth do
    /// not hold every spur/helical tooth pair in mesh at the roll angles
    /// `rolls_deg` under the scene's load
    /// ([`crate::geometry::cylindrical::sector_size`]); `None` when they
    /// do, and for bevel pairs (their FE cycle checks its sector itself).
    pub fn sector_warning(&self, rolls_deg: &[f64]) -> Option<String> {
        let c = self.cylindrical("").ok()?;
        let approach = c.sector_in_mesh?.approach_mm;
        let teeth = self.mesh.teeth_in_sector as usize;
        let pair = CylindricalPair::new(&c.pair, [None, None], teeth).ok()?;
        self.sector_shortfall(sector_for_rolls(&pair, rolls_deg, approach))
    }

    /// The warning of [`Self::sector_warning`] for the sector `need` that
    /// holds the pairs in mesh; `None` when the scene's sectors are as large.
    pub fn sector_shortfall(&self, need: SectorInMesh) -> Option<String> {
        let c = self.cylindrical("").ok()?;
        let n = self.mesh.teeth_in_sector as usize;
        // a sector of the smaller tooth count is the whole gear
        if need.teeth <= n {
            return None;
        }
        let key = match c.teeth_in_sector_line {
            Some(l) => format!("{} `mesh.teeth_in_sector` = {n}", self.at(l)),
            None => format!("`mesh.teeth_in_sector` (default {n})"),
        };
        let (lo, hi) = need.pair_offsets;
        let what = if need.fits {
            format!("{} teeth hold them", need.teeth)
        } else {
            format!(
                "a sector of {} teeth would hold them, more than the smaller gear has: the whole gear ({} teeth) does",
                sector_teeth_holding(lo, hi),
                need.teeth
            )
        };
        Some(format!(
            "{key}: the sectors do not hold every tooth pair in mesh at these roll angles: pairs from {lo:+} to {hi:+} pitches from the middle one come within the single-pair approach δ = {:.4} mm under the load (ISO 6336-1 c′; contact extension {:.3} mm along the path); {what}; the missing pairs' load is carried by the modelled ones",
            need.approach_mm, need.extension_mm
        ))
    }

    /// Warnings about the members' materials (ν near ½:
    /// [`crate::fem::material::Material::locking_warning`]), one per
    /// material, for the analyses' summaries.
    pub fn material_warnings(&self) -> Vec<String> {
        let mut w: Vec<String> = [&self.pinion_material, &self.gear_material]
            .iter()
            .filter_map(|m| m.locking_warning())
            .collect();
        w.dedup();
        w
    }

    /// The keys every result of this scene opens with.
    pub fn summary_header(&self) -> crate::summary::Header {
        crate::summary::Header::new(&self.source, self.kind.name())
    }

    /// The scene's pair behind the gear-pair interface
    /// ([`crate::geometry::gear_pair::LineContactPair`]): what every analysis uses.
    pub fn gear_pair(&self) -> Result<Arc<dyn LineContactPair>, FlankError> {
        Ok(Arc::new(self.cylindrical_pair()?))
    }
}

impl PairKind {
    /// The name as in the scene file.
    pub fn name(self) -> &'static str {
        match self {
            PairKind::Spur => "spur",
            PairKind::Helical => "helical",
            PairKind::SpiralBevel => "spiral_bevel",
            PairKind::Hypoid => "hypoid",
        }
    }

    /// Spiral bevel or hypoid.
    pub fn is_bevel(self) -> bool {
        matches!(self, PairKind::SpiralBevel | PairKind::Hypoid)
    }
}

/// The gears of a spiral bevel or hypoid pair (internal units), with both
/// members cut (their flanks are built when the scene is read, so settings
/// that do not cut the blank are refused at load, at their key).
#[derive(Clone, Debug)]
pub struct BevelGears {
    pub pinion_hand: Hand,
    /// The `[blank]` input set as read, and its design.
    pub blank_inputs: BlankInputs,
    pub blank: BlankDesign,
    /// Bore diameters of `[pinion, gear]` (mm).
    pub bore_diameter: [f64; 2],
    /// How the gear and the pinion are cut.
    pub gear_cut: MachineCut,
    pub pinion_cut: PinionCut,
    /// The members as sectors of `mesh.teeth_in_sector` teeth:
    /// `[pinion, gear]`, drive flank = right.
    pub bodies: [Arc<BevelGear>; 2],
    /// The bodies in their assembly (no misalignment).
    pub pair: Arc<BevelPair>,
    /// Process, cutter, settings and mean-point figures of each member
    /// (JSON), `[pinion, gear]`.
    pub cutting_report: [serde_json::Value; 2],
    /// A conjugate pinion's eased flanks `[drive, coast]` (with an
    /// `[pinion.ease_off]`): the ease-off reads back against them.
    pub pinion_eased: Option<[Arc<crate::geometry::bevel::ease_off::EasedPinion>; 2]>,
    /// Lines of the keys the analyses' own checks point at.
    pub lines: BevelKeyLines,
    /// The pinion's shank (`[pinion] shank_length_mm`,
    /// `shank_diameter_mm`; `pinion_shank`), `None` when neither is given.
    pub pinion_shank: Option<crate::mesh::bevel_sector::Shank>,
}

/// 1-based lines in [`Scene::source`] of the tables and keys that
/// checks made after the scene is read (FE contact, meshing) point at.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BevelKeyLines {
    /// The `[pinion]` table (its cut: process, machine, ease-off).
    pub pinion: usize,
    /// `load.torque_nm`.
    pub torque: usize,
    /// `mesh.teeth_in_sector`, `mesh.flank_size_mm`, `mesh.base_size_mm`
    /// when given.
    pub teeth_in_sector: Option<usize>,
    pub flank_size: Option<usize>,
    pub base_size: Option<usize>,
    /// `analyses.lubrication` when given.
    pub lubrication: Option<usize>,
}
