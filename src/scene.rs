//! Scene files (TOML): which gear pair to analyse, with which materials,
//! under which load, and which analyses to run.
//!
//! The scene file is the unit boundary of flank: its keys carry their unit in
//! the name where it is not an internal one (`torque_nm`, `speed_rpm`,
//! `normal_pressure_angle_deg`, `tip_relief_um`, …) and everything is
//! converted here to mm, N, N·mm, MPa and rad. Nothing downstream converts.
//!
//! ```toml
//! [pair]
//! kind = "spur"                       # or "helical"
//! centre_distance_mm = 90.0
//!
//! [pinion]
//! teeth = 13
//! normal_module_mm = 3.8
//! normal_pressure_angle_deg = 20.0
//! helix_angle_deg = 0.0               # helical: 0 < β < 45; spur: 0 or absent
//! # hand = "right"                    # helical only; pinion and gear opposite
//! face_width_mm = 13.3
//! profile_shift = 0.3                 # optional, default 0
//! rack = { addendum = 1.25, dedendum = 1.0, tip_radius = 0.38 }  # optional (ISO 53, ×m_n)
//! tip_diameter_mm = 59.0              # optional; default d + 2 m_n (h_aP* + x)
//! bore_diameter_mm = 20.0
//! material = "steel"                  # a [materials.<name>] table
//!
//! [pinion.micro]                      # optional; parsed and validated only
//! tip_relief_um = 10.0
//! tip_relief_length_mm = 1.0
//! tip_relief_shape = "linear"         # or "parabolic"
//!
//! [gear]                              # the same keys as [pinion]
//! # …
//!
//! [materials.steel]
//! young_modulus_mpa = 206000.0
//! poisson_ratio = 0.3
//!
//! [load]
//! torque_nm = 312.0                   # on the pinion
//! speed_rpm = 11758.0                 # of the pinion
//!
//! [analyses]                          # optional: the analyses asked for
//! mesh = {}
//!
//! [mesh]                              # optional meshing options
//! teeth_in_sector = 3
//! element = "wedge15"                 # or "hex20"
//! flank_size_mm = 0.1
//! base_size_mm = 1.0
//! ```
//!
//! `[<gear>.micro]` keys (all optional): `tip_relief_um`/`_length_mm`/`_shape`,
//! `root_relief_um`/`_length_mm`/`_shape`, `end_relief_um`/`_length_mm`/`_shape`
//! (amount and length go together; shape `linear` by default),
//! `profile_crowning_um`, `lead_crowning_um` (≥ 0), `helix_slope_deviation_um`
//! (signed), `measured_profile_csv` (relative to the scene file; must exist).
//!
//! Every table rejects unknown keys; every error is a
//! [`FlankError::Parse`] with the file, the 1-based line and a message that
//! names the key. Beyond types and ranges (5 ≤ z ≤ 1000, m_n > 0,
//! 0 < α_n < 45°, spur β = 0 and no hand, helical 0 < β < 45° with opposite
//! hands, b > 0, |x| ≤ 2, E > 0, −1 < ν < 0.5, torque and speed ≥ 0) the
//! checks are geometric: both gears share m_n, α_n and β; the rack tooth tip
//! fits its fillets; the tip lies above the base and root circles and below
//! the pointed-tooth diameter; the bore is inside the root circle; the centre
//! distance exceeds r_b1 + r_b2 and is not too small for x1 + x2 (no
//! interference); no tip reaches into the mating root circle. Last, the pair
//! goes through [`crate::geometry::pair::check_pair`] (zero backlash: Σx within
//! 1e-6 of what the centre distance needs; clearances; interference with the
//! root fillet; ε_α ≥ 1), whose message is reported at the centre-distance line.

use std::collections::BTreeMap;
use std::f64::consts::PI;
use std::ops::Range;
use std::path::{Path, PathBuf};

use serde::Deserialize;
use toml::Spanned;

use crate::error::FlankError;
use crate::fem::material::Material;
use crate::geometry::micro::{roll_angle_at_radius, FlankModification};
use crate::geometry::rack::ToothProfile;
use crate::geometry::{GearSpec, Hand, PairSpec, RackProfile};

/// Flank modifications: defined in [`crate::geometry::micro`], re-exported here
/// because a scene is where they are read.
pub use crate::geometry::micro::{MicroGeometry, Relief, ReliefShape};

// ---------------------------------------------------------------------------
// Public types (internal units)
// ---------------------------------------------------------------------------

/// Kind of a cylindrical gear pair.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum PairKind {
    Spur,
    Helical,
}

/// Operating point, internal units.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Load {
    /// Torque on the pinion (N·mm); ≥ 0.
    pub torque_nmm: f64,
    /// Pinion speed (rev/min); ≥ 0.
    pub speed_rpm: f64,
}

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
    pub flanks: crate::compliance::FlankSelection,
    /// `schur` (default) or `blocked`.
    #[serde(default)]
    pub method: crate::compliance::Method,
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
    pub law: Option<crate::mesh_cycle::ContactLaw>,
    /// Penalty slope as a multiple of the automatic default (> 0, default 1).
    pub penalty_factor: Option<f64>,
    /// `auto` (default: the gear while a pair is before its kinematic start
    /// of contact, the pinion from then on), `pinion` or `gear`: the body
    /// whose flank nodes are slaves.
    pub slave: Option<crate::mesh_cycle::SlaveBody>,
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
    pub solver: Option<crate::ltca::qp::QpSolver>,
    /// Local contact deformation: `half-space` (default) or `none`.
    pub local: Option<crate::ltca::local::LocalModel>,
    /// FE cell half-width across the line in flank element sizes (> 0; default 1).
    pub fe_cell_factor: Option<f64>,
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
}

/// The analyses a scene asks for; an absent entry is not computed.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct Analyses {
    pub mesh: Option<MeshAnalysis>,
    pub compliance: Option<ComplianceAnalysis>,
    pub contact: Option<ContactAnalysis>,
    pub ltca: Option<LtcaAnalysis>,
}

impl Analyses {
    /// Names an `[analyses]` table accepts.
    pub const KNOWN: &'static [&'static str] = &["mesh", "compliance", "contact", "ltca"];
}

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

/// A parsed and validated scene, in internal units.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Scene {
    pub kind: PairKind,
    /// For spur pairs the helix angles are 0 and the hands `Right` (meaningless).
    pub pair: PairSpec,
    pub pinion_material: Material,
    pub gear_material: Material,
    pub load: Load,
    /// Flank modifications of `[pinion, gear]`.
    pub micro: [Option<MicroGeometry>; 2],
    pub analyses: Analyses,
    pub mesh: MeshOptions,
    /// The scene file (as given); relative paths inside it are resolved against its folder.
    pub source: PathBuf,
}

impl Scene {
    /// The flank modifications of `[pinion, gear]`, bound to their gears
    /// ([`FlankModification::new`]): tooth profiles, the start of active
    /// profile from [`crate::geometry::pair::check_pair`] and the face widths.
    /// `None` where the scene has no `[<gear>.micro]`; warnings (e.g. a
    /// measured range that does not cover the active profile) are in
    /// [`FlankModification::warnings`].
    pub fn flank_modifications(&self) -> Result<[Option<FlankModification>; 2], FlankError> {
        let report = crate::geometry::pair::check_pair(&self.pair)?;
        let mut out = [None, None];
        for (i, (spec, name, sap)) in [
            (
                &self.pair.pinion,
                "pinion",
                report.pinion.active_start_radius,
            ),
            (&self.pair.gear, "gear", report.gear.active_start_radius),
        ]
        .into_iter()
        .enumerate()
        {
            if let Some(micro) = &self.micro[i] {
                let profile = ToothProfile::new(spec, name)?;
                let u_sap = roll_angle_at_radius(profile.geometry.base_radius, sap)?;
                out[i] = Some(
                    FlankModification::new(micro, &profile, u_sap, spec.face_width).map_err(
                        |e| match e {
                            FlankError::Model(m) => FlankError::Model(format!("{name}: {m}")),
                            e => e,
                        },
                    )?,
                );
            }
        }
        Ok(out)
    }
}

/// Reads and validates a scene file.
pub fn read_scene(path: &Path) -> Result<Scene, FlankError> {
    let text = std::fs::read_to_string(path).map_err(|e| FlankError::io(path, e))?;
    parse_scene(&text, path)
}

/// Parses and validates scene text; `path` names the file in errors and
/// anchors relative paths (measured profiles).
pub fn parse_scene(text: &str, path: &Path) -> Result<Scene, FlankError> {
    let cx = Cx { text, file: path };
    let raw: RawScene = toml::from_str(text).map_err(|e| cx.toml_error(&e))?;
    build(&cx, raw)
}

// ---------------------------------------------------------------------------
// Raw (file) schema
// ---------------------------------------------------------------------------

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawScene {
    pair: RawPair,
    pinion: RawGear,
    gear: RawGear,
    #[serde(default)]
    materials: BTreeMap<String, RawMaterial>,
    load: RawLoad,
    analyses: Option<Spanned<BTreeMap<Spanned<String>, Spanned<toml::Value>>>>,
    mesh: Option<RawMesh>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawPair {
    kind: Spanned<PairKind>,
    centre_distance_mm: Spanned<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawGear {
    teeth: Spanned<i64>,
    normal_module_mm: Spanned<f64>,
    normal_pressure_angle_deg: Spanned<f64>,
    helix_angle_deg: Option<Spanned<f64>>,
    hand: Option<Spanned<Hand>>,
    face_width_mm: Spanned<f64>,
    profile_shift: Option<Spanned<f64>>,
    rack: Option<RawRack>,
    tip_diameter_mm: Option<Spanned<f64>>,
    bore_diameter_mm: Spanned<f64>,
    material: Spanned<String>,
    micro: Option<RawMicro>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawRack {
    addendum: Option<Spanned<f64>>,
    dedendum: Option<Spanned<f64>>,
    tip_radius: Option<Spanned<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawMicro {
    tip_relief_um: Option<Spanned<f64>>,
    tip_relief_length_mm: Option<Spanned<f64>>,
    tip_relief_shape: Option<Spanned<ReliefShape>>,
    root_relief_um: Option<Spanned<f64>>,
    root_relief_length_mm: Option<Spanned<f64>>,
    root_relief_shape: Option<Spanned<ReliefShape>>,
    profile_crowning_um: Option<Spanned<f64>>,
    lead_crowning_um: Option<Spanned<f64>>,
    helix_slope_deviation_um: Option<Spanned<f64>>,
    end_relief_um: Option<Spanned<f64>>,
    end_relief_length_mm: Option<Spanned<f64>>,
    end_relief_shape: Option<Spanned<ReliefShape>>,
    measured_profile_csv: Option<Spanned<String>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawMaterial {
    young_modulus_mpa: Spanned<f64>,
    poisson_ratio: Spanned<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawLoad {
    torque_nm: Spanned<f64>,
    speed_rpm: Spanned<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawMesh {
    teeth_in_sector: Option<Spanned<i64>>,
    element: Option<Spanned<ElementKind>>,
    flank_size_mm: Option<Spanned<f64>>,
    base_size_mm: Option<Spanned<f64>>,
}

// ---------------------------------------------------------------------------
// Error context
// ---------------------------------------------------------------------------

type Res<T> = Result<T, FlankError>;

struct Cx<'a> {
    text: &'a str,
    file: &'a Path,
}

impl Cx<'_> {
    /// 1-based line of a byte offset.
    fn line(&self, offset: usize) -> usize {
        let end = offset.min(self.text.len());
        1 + self.text.as_bytes()[..end]
            .iter()
            .filter(|&&b| b == b'\n')
            .count()
    }

    fn err(&self, span: Range<usize>, message: String) -> FlankError {
        FlankError::Parse {
            file: self.file.to_path_buf(),
            line: self.line(span.start),
            message,
        }
    }

    fn toml_error(&self, e: &toml::de::Error) -> FlankError {
        let line = e.span().map(|s| self.line(s.start)).unwrap_or(1);
        let mut message = e.message().trim().to_string();
        if let Some(start) = e.span().map(|s| s.start) {
            if message.starts_with("missing field") {
                if let Some(table) = self.table_at(start) {
                    message = format!("[{table}]: {message}");
                }
            } else if message.starts_with("invalid") || message.starts_with("unknown variant") {
                // name the key: `table.key`
                if let Some(key) = self.key_at(start) {
                    let full = match self.table_at(start) {
                        Some(t) => format!("{t}.{key}"),
                        None => key,
                    };
                    message = format!("`{full}`: {message}");
                }
            }
        }
        if message.is_empty() {
            message = "invalid TOML".to_string();
        }
        FlankError::Parse {
            file: self.file.to_path_buf(),
            line,
            message,
        }
    }

    /// The key of a `key = value` line that contains a byte offset, if any.
    fn key_at(&self, offset: usize) -> Option<String> {
        let end = offset.min(self.text.len());
        let start = self.text.get(..end)?.rfind('\n').map_or(0, |i| i + 1);
        let line = self.text.get(start..)?.lines().next()?;
        let (key, _) = line.split_once('=')?;
        let key = key.trim();
        let simple = !key.is_empty()
            && key
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-' || c == '.');
        simple.then(|| key.to_string())
    }

    /// Name of the `[table]` header at or before a byte offset, if any.
    fn table_at(&self, offset: usize) -> Option<String> {
        let end = offset.min(self.text.len());
        // the header line that contains the offset, or the last one before it
        let line_end = self
            .text
            .get(end..)
            .and_then(|t| t.find('\n'))
            .map_or(self.text.len(), |i| end + i);
        let upto = self.text.get(..line_end)?;
        upto.lines().rev().find_map(|l| {
            let t = l.trim();
            let name = t.strip_prefix('[')?.split_once(']')?.0.trim();
            let plain = !t.starts_with("[[")
                && !name.is_empty()
                && name.chars().all(|c| {
                    c.is_alphanumeric() || matches!(c, '_' | '-' | '.' | '"' | '\'' | ' ')
                });
            plain.then(|| name.to_string())
        })
    }

    /// A finite value.
    fn finite(&self, v: &Spanned<f64>, key: &str) -> Res<f64> {
        let x = *v.get_ref();
        if !x.is_finite() {
            return Err(self.err(v.span(), format!("`{key}` = {x}: must be a finite number")));
        }
        Ok(x)
    }

    /// A finite value > 0.
    fn positive(&self, v: &Spanned<f64>, key: &str) -> Res<f64> {
        let x = self.finite(v, key)?;
        if !(x > 0.0) {
            return Err(self.err(v.span(), format!("`{key}` = {x}: must be positive")));
        }
        Ok(x)
    }

    /// A finite value ≥ 0.
    fn non_negative(&self, v: &Spanned<f64>, key: &str) -> Res<f64> {
        let x = self.finite(v, key)?;
        if !(x >= 0.0) {
            return Err(self.err(v.span(), format!("`{key}` = {x}: must not be negative")));
        }
        Ok(x)
    }
}

// ---------------------------------------------------------------------------
// Validation and conversion
// ---------------------------------------------------------------------------

/// What a converted gear still needs for the pair checks.
struct GearSpans {
    module: Range<usize>,
    alpha: Range<usize>,
    helix: Range<usize>,
    hand: Option<Range<usize>>,
    tip: Range<usize>,
    material: Spanned<String>,
}

fn build(cx: &Cx, raw: RawScene) -> Res<Scene> {
    let kind = *raw.pair.kind.get_ref();
    let (pinion, ps) = gear(cx, &raw.pinion, "pinion", kind)?;
    let (gear_spec, gs) = gear(cx, &raw.gear, "gear", kind)?;

    // the two gears must mesh: same normal module, pressure angle and helix angle
    let same = |a: f64, b: f64| (a - b).abs() <= 1e-9 * a.abs().max(b.abs()).max(1.0);
    if !same(pinion.normal_module, gear_spec.normal_module) {
        return Err(cx.err(
            gs.module.clone(),
            format!(
                "`gear.normal_module_mm` = {}: must equal `pinion.normal_module_mm` = {} (the gears must mesh)",
                gear_spec.normal_module, pinion.normal_module
            ),
        ));
    }
    if !same(
        pinion.normal_pressure_angle,
        gear_spec.normal_pressure_angle,
    ) {
        return Err(cx.err(
            gs.alpha.clone(),
            format!(
                "`gear.normal_pressure_angle_deg` = {}: must equal `pinion.normal_pressure_angle_deg` = {}",
                gear_spec.normal_pressure_angle.to_degrees(),
                pinion.normal_pressure_angle.to_degrees()
            ),
        ));
    }
    if !same(pinion.helix_angle, gear_spec.helix_angle) {
        return Err(cx.err(
            gs.helix.clone(),
            format!(
                "`gear.helix_angle_deg` = {}: must equal `pinion.helix_angle_deg` = {} (parallel axes)",
                gear_spec.helix_angle.to_degrees(),
                pinion.helix_angle.to_degrees()
            ),
        ));
    }
    if kind == PairKind::Helical && pinion.hand == gear_spec.hand {
        return Err(cx.err(
            gs.hand.clone().unwrap_or(gs.helix.clone()),
            format!(
                "`gear.hand` = \"{}\": an external helical pair needs opposite hands (pinion is \"{}\")",
                hand_name(gear_spec.hand),
                hand_name(pinion.hand)
            ),
        ));
    }
    // centre distance against the involutes
    let a_span = raw.pair.centre_distance_mm.span();
    let a = cx.positive(&raw.pair.centre_distance_mm, "pair.centre_distance_mm")?;
    let rb1 = base_diameter(&pinion) / 2.0;
    let rb2 = base_diameter(&gear_spec) / 2.0;
    if !(a > rb1 + rb2) {
        return Err(cx.err(
            a_span,
            format!(
                "`pair.centre_distance_mm` = {a}: must exceed the sum of the base radii {:.4} mm",
                rb1 + rb2
            ),
        ));
    }
    let x_sum_a = shift_sum_for_centre_distance(&pinion, &gear_spec, a);
    let x_sum = pinion.profile_shift + gear_spec.profile_shift;
    if x_sum > x_sum_a + 1e-4 {
        return Err(cx.err(
            a_span,
            format!(
                "`pair.centre_distance_mm` = {a}: too small for the profile shifts x1 + x2 = {x_sum:.4}; \
                 backlash-free meshing at this centre distance needs x1 + x2 = {x_sum_a:.4} (the teeth would interfere)"
            ),
        ));
    }
    for (g, s, name, other, other_name) in [
        (&pinion, &ps, "pinion", &gear_spec, "gear"),
        (&gear_spec, &gs, "gear", &pinion, "pinion"),
    ] {
        let clearance = a - tip_diameter(g) / 2.0 - root_diameter(other) / 2.0;
        if clearance < 0.0 {
            return Err(cx.err(
                s.tip.clone(),
                format!(
                    "{name} tip diameter {:.4} mm reaches {:.4} mm into the {other_name}'s root circle \
                     at centre distance {a} mm (reduce `{name}.tip_diameter_mm`)",
                    tip_diameter(g),
                    -clearance
                ),
            ));
        }
    }

    let pair = PairSpec {
        pinion,
        gear: gear_spec,
        centre_distance: a,
    };
    // the geometry module's pair check: zero backlash (Σx within 1e-6 of what
    // a needs), clearances, interference, ε_α ≥ 1
    crate::geometry::pair::check_pair(&pair).map_err(|e| {
        let m = match e {
            FlankError::Model(m) => m,
            other => other.to_string(),
        };
        cx.err(
            a_span.clone(),
            format!("`pair.centre_distance_mm` = {a}: {m}"),
        )
    })?;

    // materials
    let pinion_material = material(cx, &raw.materials, &ps.material, "pinion")?;
    let gear_material = material(cx, &raw.materials, &gs.material, "gear")?;

    // load
    let torque_nm = cx.non_negative(&raw.load.torque_nm, "load.torque_nm")?;
    let speed_rpm = cx.non_negative(&raw.load.speed_rpm, "load.speed_rpm")?;
    let load = Load {
        torque_nmm: torque_nm * 1000.0,
        speed_rpm,
    };

    // micro-geometry
    let micro = [
        match &raw.pinion.micro {
            Some(m) => Some(micro_geometry(cx, m, "pinion", pair.pinion.face_width)?),
            None => None,
        },
        match &raw.gear.micro {
            Some(m) => Some(micro_geometry(cx, m, "gear", pair.gear.face_width)?),
            None => None,
        },
    ];

    let analyses = analyses(cx, raw.analyses.as_ref())?;
    let min_teeth = pair.pinion.teeth.min(pair.gear.teeth);
    let min_module = pair.pinion.normal_module.min(pair.gear.normal_module);
    let mesh = mesh_options(cx, raw.mesh.as_ref(), min_teeth, min_module)?;

    Ok(Scene {
        kind,
        pair,
        pinion_material,
        gear_material,
        load,
        micro,
        analyses,
        mesh,
        source: cx.file.to_path_buf(),
    })
}

fn hand_name(h: Hand) -> &'static str {
    match h {
        Hand::Left => "left",
        Hand::Right => "right",
    }
}

fn gear(cx: &Cx, g: &RawGear, name: &str, kind: PairKind) -> Res<(GearSpec, GearSpans)> {
    let key = |k: &str| format!("{name}.{k}");

    let z = *g.teeth.get_ref();
    if !(5..=1000).contains(&z) {
        return Err(cx.err(
            g.teeth.span(),
            format!("`{}` = {z}: must lie in 5..=1000", key("teeth")),
        ));
    }
    let teeth = z as u32;

    let m = cx.positive(&g.normal_module_mm, &key("normal_module_mm"))?;

    let alpha_deg = cx.finite(
        &g.normal_pressure_angle_deg,
        &key("normal_pressure_angle_deg"),
    )?;
    if !(alpha_deg > 0.0 && alpha_deg < 45.0) {
        return Err(cx.err(
            g.normal_pressure_angle_deg.span(),
            format!(
                "`{}` = {alpha_deg}: must lie in (0, 45) degrees",
                key("normal_pressure_angle_deg")
            ),
        ));
    }

    let (beta_deg, helix_span) = match (&g.helix_angle_deg, kind) {
        (None, PairKind::Spur) => (0.0, g.teeth.span()),
        (Some(b), PairKind::Spur) => {
            let beta = cx.finite(b, &key("helix_angle_deg"))?;
            if beta != 0.0 {
                return Err(cx.err(
                    b.span(),
                    format!(
                        "`{}` = {beta}: a spur pair has no helix angle (0 or absent); use kind = \"helical\"",
                        key("helix_angle_deg")
                    ),
                ));
            }
            (0.0, b.span())
        }
        (None, PairKind::Helical) => {
            return Err(cx.err(
                g.teeth.span(),
                format!("[{name}]: missing field `helix_angle_deg` (required for a helical pair)"),
            ))
        }
        (Some(b), PairKind::Helical) => {
            let beta = cx.finite(b, &key("helix_angle_deg"))?;
            if !(beta > 0.0 && beta < 45.0) {
                return Err(cx.err(
                    b.span(),
                    format!(
                        "`{}` = {beta}: a helical gear needs 0 < β < 45 degrees (the direction is given by `hand`)",
                        key("helix_angle_deg")
                    ),
                ));
            }
            (beta, b.span())
        }
    };

    let hand = match (&g.hand, kind) {
        (None, PairKind::Spur) => Hand::Right,
        (Some(h), PairKind::Spur) => {
            return Err(cx.err(
                h.span(),
                format!("`{}`: a spur gear has no hand (helical only)", key("hand")),
            ))
        }
        (None, PairKind::Helical) => {
            return Err(cx.err(
                g.teeth.span(),
                format!("[{name}]: missing field `hand` (\"left\" or \"right\", required for a helical pair)"),
            ))
        }
        (Some(h), PairKind::Helical) => *h.get_ref(),
    };

    let b = cx.positive(&g.face_width_mm, &key("face_width_mm"))?;

    let x = match &g.profile_shift {
        Some(v) => {
            let x = cx.finite(v, &key("profile_shift"))?;
            if !(x.abs() <= 2.0) {
                return Err(cx.err(
                    v.span(),
                    format!("`{}` = {x}: must lie in [-2, 2]", key("profile_shift")),
                ));
            }
            x
        }
        None => 0.0,
    };

    let mut rack = RackProfile::default();
    if let Some(r) = &g.rack {
        if let Some(v) = &r.addendum {
            rack.addendum = cx.positive(v, &key("rack.addendum"))?;
        }
        if let Some(v) = &r.dedendum {
            rack.dedendum = cx.positive(v, &key("rack.dedendum"))?;
        }
        if let Some(v) = &r.tip_radius {
            rack.tip_radius = cx.non_negative(v, &key("rack.tip_radius"))?;
        }
        // the generating rack's tooth tip must be wide enough for both fillets
        let alpha = alpha_deg.to_radians();
        let half_tip = PI / 4.0 - rack.addendum * alpha.tan();
        let rho_max = half_tip * alpha.cos() / (1.0 - alpha.sin());
        let span = r
            .tip_radius
            .as_ref()
            .or(r.addendum.as_ref())
            .or(r.dedendum.as_ref())
            .map_or(g.teeth.span(), |v| v.span());
        if !(half_tip > 0.0) {
            return Err(cx.err(
                span,
                format!(
                    "`{}` = {}: the generating rack's tooth is pointed (addendum × tan α_n ≥ π/4)",
                    key("rack.addendum"),
                    rack.addendum
                ),
            ));
        }
        if rack.tip_radius > rho_max {
            return Err(cx.err(
                span,
                format!(
                    "`{}` = {}: larger than the {:.4} the rack tooth tip allows at addendum {} and α_n = {alpha_deg}°",
                    key("rack.tip_radius"),
                    rack.tip_radius,
                    rho_max,
                    rack.addendum
                ),
            ));
        }
    }

    let mut spec = GearSpec {
        teeth,
        normal_module: m,
        normal_pressure_angle: alpha_deg.to_radians(),
        helix_angle: beta_deg.to_radians(),
        hand,
        face_width: b,
        profile_shift: x,
        rack,
        tip_diameter: None,
        bore_diameter: 0.0,
    };

    let df = root_diameter(&spec);
    let db = base_diameter(&spec);
    let tip_span = match &g.tip_diameter_mm {
        Some(v) => {
            let da = cx.positive(v, &key("tip_diameter_mm"))?;
            if !(da > df) || !(da > db) {
                return Err(cx.err(
                    v.span(),
                    format!(
                        "`{}` = {da}: must exceed the root diameter {df:.4} mm and the base diameter {db:.4} mm",
                        key("tip_diameter_mm")
                    ),
                ));
            }
            spec.tip_diameter = Some(da);
            v.span()
        }
        None => g.teeth.span(),
    };
    let da = tip_diameter(&spec);
    if da > db {
        let s = tip_thickness(&spec, da);
        if !(s > 0.0) {
            let span = tip_span.clone();
            return Err(cx.err(
                span,
                format!(
                    "{name}: the tooth is pointed below the tip diameter {da:.4} mm \
                     (tooth thickness there {s:.4} mm); reduce `{}` or `{}`",
                    key("tip_diameter_mm"),
                    key("profile_shift")
                ),
            ));
        }
    } else {
        return Err(cx.err(
            tip_span,
            format!(
                "{name}: tip diameter {da:.4} mm does not exceed the base diameter {db:.4} mm (no involute flank)"
            ),
        ));
    }

    let bore = cx.positive(&g.bore_diameter_mm, &key("bore_diameter_mm"))?;
    if !(bore < df) || !(bore < da) {
        return Err(cx.err(
            g.bore_diameter_mm.span(),
            format!(
                "`{}` = {bore}: must be smaller than the root diameter {df:.4} mm (tip diameter {da:.4} mm)",
                key("bore_diameter_mm")
            ),
        ));
    }
    spec.bore_diameter = bore;

    Ok((
        spec,
        GearSpans {
            module: g.normal_module_mm.span(),
            alpha: g.normal_pressure_angle_deg.span(),
            helix: helix_span,
            hand: g.hand.as_ref().map(|h| h.span()),
            tip: tip_span,
            material: g.material.clone(),
        },
    ))
}

fn material(
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

fn micro_geometry(cx: &Cx, m: &RawMicro, name: &str, face_width: f64) -> Res<MicroGeometry> {
    let key = |k: &str| format!("{name}.micro.{k}");
    let um = |v: &Option<Spanned<f64>>, k: &str| -> Res<f64> {
        match v {
            Some(v) => Ok(cx.non_negative(v, &key(k))? * 1e-3),
            None => Ok(0.0),
        }
    };
    let relief = |amount: &Option<Spanned<f64>>,
                  length: &Option<Spanned<f64>>,
                  shape: &Option<Spanned<ReliefShape>>,
                  stem: &str|
     -> Res<Option<Relief>> {
        let a_key = format!("{stem}_um");
        let l_key = format!("{stem}_length_mm");
        let s_key = format!("{stem}_shape");
        match (amount, length) {
            (None, None) => {
                if let Some(s) = shape {
                    return Err(cx.err(
                        s.span(),
                        format!("`{}` given without `{}`", key(&s_key), key(&a_key)),
                    ));
                }
                Ok(None)
            }
            (Some(a), None) => Err(cx.err(
                a.span(),
                format!("`{}` needs `{}`", key(&a_key), key(&l_key)),
            )),
            (None, Some(l)) => Err(cx.err(
                l.span(),
                format!("`{}` needs `{}`", key(&l_key), key(&a_key)),
            )),
            (Some(a), Some(l)) => {
                let amount = cx.non_negative(a, &key(&a_key))? * 1e-3;
                let length = cx.positive(l, &key(&l_key))?;
                Ok(Some(Relief {
                    amount,
                    length,
                    shape: shape.as_ref().map_or(ReliefShape::Linear, |s| *s.get_ref()),
                }))
            }
        }
    };

    let tip_relief = relief(
        &m.tip_relief_um,
        &m.tip_relief_length_mm,
        &m.tip_relief_shape,
        "tip_relief",
    )?;
    let root_relief = relief(
        &m.root_relief_um,
        &m.root_relief_length_mm,
        &m.root_relief_shape,
        "root_relief",
    )?;
    let end_relief = relief(
        &m.end_relief_um,
        &m.end_relief_length_mm,
        &m.end_relief_shape,
        "end_relief",
    )?;
    if let (Some(r), Some(l)) = (&end_relief, &m.end_relief_length_mm) {
        if r.length > 0.5 * face_width {
            return Err(cx.err(
                l.span(),
                format!(
                    "`{}` = {}: end reliefs at both ends must fit the face width {face_width} mm (≤ b/2)",
                    key("end_relief_length_mm"),
                    r.length
                ),
            ));
        }
    }
    let helix_slope_deviation = match &m.helix_slope_deviation_um {
        Some(v) => cx.finite(v, &key("helix_slope_deviation_um"))? * 1e-3,
        None => 0.0,
    };
    let measured_profile = match &m.measured_profile_csv {
        Some(p) => {
            let rel = Path::new(p.get_ref());
            let base = cx.file.parent().unwrap_or(Path::new(""));
            let full = base.join(rel);
            if !full.is_file() {
                return Err(cx.err(
                    p.span(),
                    format!(
                        "`{}`: measured profile file not found: {}",
                        key("measured_profile_csv"),
                        full.display()
                    ),
                ));
            }
            Some(full)
        }
        None => None,
    };
    Ok(MicroGeometry {
        tip_relief,
        root_relief,
        profile_crowning: um(&m.profile_crowning_um, "profile_crowning_um")?,
        lead_crowning: um(&m.lead_crowning_um, "lead_crowning_um")?,
        helix_slope_deviation,
        end_relief,
        measured_profile,
    })
}

type RawAnalyses = Spanned<BTreeMap<Spanned<String>, Spanned<toml::Value>>>;

fn analyses(cx: &Cx, raw: Option<&RawAnalyses>) -> Res<Analyses> {
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
        if v.law != Some(crate::mesh_cycle::ContactLaw::Penalty) {
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
    Ok(())
}

fn toml_message(e: &toml::de::Error) -> String {
    e.message().trim().to_string()
}

fn mesh_options(
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

// ---------------------------------------------------------------------------
// Involute relations used by the checks (ISO 21771), internal units
// ---------------------------------------------------------------------------

fn inv(a: f64) -> f64 {
    a.tan() - a
}

fn transverse_pressure_angle(g: &GearSpec) -> f64 {
    (g.normal_pressure_angle.tan() / g.helix_angle.cos()).atan()
}

fn reference_diameter(g: &GearSpec) -> f64 {
    f64::from(g.teeth) * g.normal_module / g.helix_angle.cos()
}

fn base_diameter(g: &GearSpec) -> f64 {
    reference_diameter(g) * transverse_pressure_angle(g).cos()
}

/// d_a as given, else d + 2 m_n (h_aP* + x) (no tip shortening).
fn tip_diameter(g: &GearSpec) -> f64 {
    g.tip_diameter.unwrap_or(
        reference_diameter(g) + 2.0 * g.normal_module * (g.rack.dedendum + g.profile_shift),
    )
}

/// d_f = d − 2 m_n (h_fP* − x).
fn root_diameter(g: &GearSpec) -> f64 {
    reference_diameter(g) - 2.0 * g.normal_module * (g.rack.addendum - g.profile_shift)
}

/// Transverse tooth thickness (arc) at diameter `dy` (> d_b).
fn tip_thickness(g: &GearSpec, dy: f64) -> f64 {
    let d = reference_diameter(g);
    let at = transverse_pressure_angle(g);
    let mt = g.normal_module / g.helix_angle.cos();
    let st = mt * (PI / 2.0 + 2.0 * g.profile_shift * g.normal_pressure_angle.tan());
    let ay = (d * at.cos() / dy).acos();
    dy * (st / d + inv(at) - inv(ay))
}

/// Working transverse pressure angle at centre distance a: cos α_wt = (r_b1 + r_b2)/a.
fn working_pressure_angle(p: &GearSpec, g: &GearSpec, a: f64) -> f64 {
    ((base_diameter(p) + base_diameter(g)) / (2.0 * a)).acos()
}

/// x1 + x2 for backlash-free meshing at centre distance a:
/// inv α_wt = inv α_t + 2 (x1 + x2) tan α_n / (z1 + z2).
fn shift_sum_for_centre_distance(p: &GearSpec, g: &GearSpec, a: f64) -> f64 {
    let awt = working_pressure_angle(p, g, a);
    let at = transverse_pressure_angle(p);
    let z = f64::from(p.teeth + g.teeth);
    (inv(awt) - inv(at)) * z / (2.0 * p.normal_pressure_angle.tan())
}

/// Transverse contact ratio ε_α of a pair (used by the paper-scene tests).
#[cfg(test)]
fn transverse_contact_ratio(pair: &PairSpec) -> f64 {
    let (p, g, a) = (&pair.pinion, &pair.gear, pair.centre_distance);
    let (ra1, rb1) = (tip_diameter(p) / 2.0, base_diameter(p) / 2.0);
    let (ra2, rb2) = (tip_diameter(g) / 2.0, base_diameter(g) / 2.0);
    let awt = working_pressure_angle(p, g, a);
    let at = transverse_pressure_angle(p);
    let mt = p.normal_module / p.helix_angle.cos();
    ((ra1 * ra1 - rb1 * rb1).sqrt() + (ra2 * ra2 - rb2 * rb2).sqrt() - a * awt.sin())
        / (PI * mt * at.cos())
}

#[cfg(test)]
mod tests {
    use super::*;

    const SPUR: &str = r#"
[pair]
kind = "spur"
centre_distance_mm = 90.0

[pinion]
teeth = 13
normal_module_mm = 3.8
normal_pressure_angle_deg = 20.0
helix_angle_deg = 0.0
face_width_mm = 13.3
profile_shift = 0.3
rack = { addendum = 1.25, dedendum = 1.0, tip_radius = 0.38 }
tip_diameter_mm = 58.7
bore_diameter_mm = 20.0
material = "steel"

[pinion.micro]
tip_relief_um = 10.0
tip_relief_length_mm = 1.0
tip_relief_shape = "parabolic"
lead_crowning_um = 5.0
helix_slope_deviation_um = -3.0
end_relief_um = 20.0
end_relief_length_mm = 2.0

[gear]
teeth = 35
normal_module_mm = 3.8
normal_pressure_angle_deg = 20.0
face_width_mm = 13.3
profile_shift = -0.59931744
tip_diameter_mm = 135.5
bore_diameter_mm = 80.0
material = "steel"

[materials.steel]
young_modulus_mpa = 206000.0
poisson_ratio = 0.3

[load]
torque_nm = 312.0
speed_rpm = 11758.0

[analyses]
mesh = {}

[mesh]
teeth_in_sector = 3
element = "wedge15"
flank_size_mm = 0.1
base_size_mm = 1.0
"#;

    const HELICAL: &str = r#"
[pair]
kind = "helical"
centre_distance_mm = 462.917331

[pinion]
teeth = 21
normal_module_mm = 15
normal_pressure_angle_deg = 20.0
helix_angle_deg = 20.0
hand = "right"
face_width_mm = 180.0
bore_diameter_mm = 200.0
material = "a"

[gear]
teeth = 37
normal_module_mm = 15.0
normal_pressure_angle_deg = 20.0
helix_angle_deg = 20.0
hand = "left"
face_width_mm = 180.0
bore_diameter_mm = 400.0
material = "b"

[materials.a]
young_modulus_mpa = 207000.0
poisson_ratio = 0.3

[materials.b]
young_modulus_mpa = 210000.0
poisson_ratio = 0.29

[load]
torque_nm = 5000.0
speed_rpm = 3000.0
"#;

    fn parse(text: &str) -> Result<Scene, FlankError> {
        parse_scene(text, Path::new("/nonexistent/scene.toml"))
    }

    /// Replaces `from` (which must occur exactly once) by `to`.
    fn edit(text: &str, from: &str, to: &str) -> String {
        assert_eq!(text.matches(from).count(), 1, "edit anchor {from:?}");
        text.replacen(from, to, 1)
    }

    /// 1-based line of the first occurrence of `needle`.
    fn line_of(text: &str, needle: &str) -> usize {
        let i = text.find(needle).expect("needle");
        1 + text[..i].matches('\n').count()
    }

    /// Asserts a Parse error at `line` whose message contains every one of `words`.
    fn expect_err(text: &str, line: usize, words: &[&str]) {
        match parse(text) {
            Ok(_) => panic!("expected an error mentioning {words:?}"),
            Err(FlankError::Parse {
                file,
                line: l,
                message,
            }) => {
                assert_eq!(file, Path::new("/nonexistent/scene.toml"));
                for w in words {
                    assert!(message.contains(w), "message {message:?} lacks {w:?}");
                }
                assert_eq!(l, line, "line of {message:?}");
            }
            Err(e) => panic!("expected a parse error, got {e}"),
        }
    }

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-12 * a.abs().max(b.abs()).max(1.0)
    }

    #[test]
    fn spur_scene_in_internal_units() {
        let s = parse(SPUR).unwrap();
        assert_eq!(s.kind, PairKind::Spur);
        let p = &s.pair.pinion;
        let g = &s.pair.gear;
        assert_eq!((p.teeth, g.teeth), (13, 35));
        assert!(close(p.normal_module, 3.8));
        assert!(close(p.normal_pressure_angle, 20f64.to_radians()));
        assert_eq!(p.helix_angle, 0.0);
        assert_eq!(g.helix_angle, 0.0);
        assert!(close(p.face_width, 13.3));
        assert!(close(p.profile_shift, 0.3));
        assert!(close(g.profile_shift, -0.59931744));
        assert_eq!(p.rack, RackProfile::default());
        assert_eq!(p.tip_diameter, Some(58.7));
        assert_eq!(g.tip_diameter, Some(135.5));
        assert!(close(p.bore_diameter, 20.0));
        assert!(close(s.pair.centre_distance, 90.0));
        assert_eq!(
            s.pinion_material,
            Material::new("steel", 206000.0, 0.3).unwrap()
        );
        assert_eq!(s.gear_material, s.pinion_material);
        // N·m → N·mm
        assert!(close(s.load.torque_nmm, 312_000.0));
        assert!(close(s.load.speed_rpm, 11758.0));
        // µm → mm
        let m = s.micro[0].as_ref().unwrap();
        let tip = m.tip_relief.unwrap();
        assert!(close(tip.amount, 0.010));
        assert!(close(tip.length, 1.0));
        assert_eq!(tip.shape, ReliefShape::Parabolic);
        assert!(m.root_relief.is_none());
        assert!(close(m.lead_crowning, 0.005));
        assert!(close(m.helix_slope_deviation, -0.003));
        assert_eq!(m.profile_crowning, 0.0);
        let end = m.end_relief.unwrap();
        assert!(close(end.amount, 0.020));
        assert_eq!(end.shape, ReliefShape::Linear);
        assert!(s.micro[1].is_none());
        assert_eq!(s.analyses.mesh, Some(MeshAnalysis {}));
        assert_eq!(
            s.mesh,
            MeshOptions {
                teeth_in_sector: 3,
                element: ElementKind::Wedge15,
                flank_size: Some(0.1),
                base_size: Some(1.0),
            }
        );
        assert_eq!(s.source, Path::new("/nonexistent/scene.toml"));
        // a = 90 mm with x1 + x2 = -0.2993 is backlash-free to 1e-4
        let xs = shift_sum_for_centre_distance(p, g, 90.0);
        assert!((xs - (-0.29932)).abs() < 1e-5, "{xs}");
    }

    #[test]
    fn helical_scene_in_internal_units() {
        let s = parse(HELICAL).unwrap();
        assert_eq!(s.kind, PairKind::Helical);
        let p = &s.pair.pinion;
        let g = &s.pair.gear;
        assert!(close(p.normal_module, 15.0)); // integer in the file
        assert!(close(p.helix_angle, 20f64.to_radians()));
        assert!(close(g.helix_angle, 20f64.to_radians()));
        assert_eq!((p.hand, g.hand), (Hand::Right, Hand::Left));
        assert_eq!(p.profile_shift, 0.0);
        assert_eq!(p.tip_diameter, None);
        assert_eq!(p.rack, RackProfile::default());
        assert_eq!(s.pinion_material.name, "a");
        assert_eq!(s.gear_material, Material::new("b", 210000.0, 0.29).unwrap());
        assert!(close(s.load.torque_nmm, 5.0e6));
        assert_eq!(s.micro, [None, None]);
        assert_eq!(s.analyses, Analyses::default());
        assert_eq!(s.mesh, MeshOptions::default());
        // reference centre distance: (21 + 37) 15 / (2 cos 20°) = 462.9173 mm
        let a_ref = reference_diameter(p) / 2.0 + reference_diameter(g) / 2.0;
        assert!((a_ref - 462.9173).abs() < 1e-4, "{a_ref}");
    }

    #[test]
    fn unknown_key_top_level() {
        let t = edit(SPUR, "[load]\n", "[loads]\ntorque = 1\n\n[load]\n");
        expect_err(&t, line_of(&t, "[loads]"), &["loads"]);
    }

    #[test]
    fn unknown_key_in_pinion() {
        let t = edit(SPUR, "teeth = 13\n", "teeth = 13\ntooth_count = 13\n");
        expect_err(&t, line_of(&t, "tooth_count"), &["tooth_count"]);
    }

    #[test]
    fn unknown_key_in_rack() {
        let t = edit(
            SPUR,
            "tip_radius = 0.38 }",
            "tip_radius = 0.38, root_radius = 0.2 }",
        );
        expect_err(&t, line_of(&t, "rack = "), &["root_radius"]);
    }

    #[test]
    fn unknown_key_in_micro() {
        let t = edit(
            SPUR,
            "lead_crowning_um = 5.0\n",
            "lead_crowning_um = 5.0\nbarrelling_um = 2\n",
        );
        expect_err(&t, line_of(&t, "barrelling_um"), &["barrelling_um"]);
    }

    #[test]
    fn missing_required_key() {
        let t = edit(
            SPUR,
            "face_width_mm = 13.3\nprofile_shift = 0.3\n",
            "profile_shift = 0.3\n",
        );
        expect_err(
            &t,
            line_of(&t, "[pinion]"),
            &["[pinion]", "missing field `face_width_mm`"],
        );
        let t = edit(SPUR, "[load]\ntorque_nm = 312.0\n", "[load]\n");
        expect_err(&t, line_of(&t, "[load]"), &["[load]", "torque_nm"]);
        // a missing file is an I/O error naming the path
        let e = read_scene(Path::new("/nonexistent/scene.toml")).unwrap_err();
        assert!(matches!(e, FlankError::Io { .. }), "{e}");
        // helical-only keys are required for a helical pair
        let t = edit(HELICAL, "hand = \"left\"\n", "");
        expect_err(&t, line_of(&t, "teeth = 37"), &["hand", "gear"]);
        let t = edit(
            HELICAL,
            "helix_angle_deg = 20.0\nhand = \"right\"",
            "hand = \"right\"",
        );
        expect_err(
            &t,
            line_of(&t, "teeth = 21"),
            &["helix_angle_deg", "pinion"],
        );
    }

    #[test]
    fn wrong_type_names_key() {
        let t = edit(SPUR, "teeth = 13", "teeth = 13.0");
        expect_err(
            &t,
            line_of(&t, "teeth = 13.0"),
            &["`pinion.teeth`", "invalid type"],
        );
        let t = edit(SPUR, "kind = \"spur\"", "kind = \"bevel\"");
        expect_err(
            &t,
            line_of(&t, "bevel"),
            &["`pair.kind`", "bevel", "helical"],
        );
    }

    #[test]
    fn too_few_teeth() {
        let t = edit(SPUR, "teeth = 13", "teeth = 3");
        expect_err(&t, line_of(&t, "teeth = 3"), &["pinion.teeth", "3"]);
        let t = edit(SPUR, "teeth = 13", "teeth = -13");
        expect_err(&t, line_of(&t, "teeth = -13"), &["pinion.teeth"]);
    }

    #[test]
    fn spur_with_helix_angle() {
        let t = edit(SPUR, "helix_angle_deg = 0.0", "helix_angle_deg = 15.0");
        expect_err(
            &t,
            line_of(&t, "helix_angle_deg"),
            &["pinion.helix_angle_deg", "spur"],
        );
        let t = edit(SPUR, "helix_angle_deg = 0.0", "hand = \"left\"");
        expect_err(&t, line_of(&t, "hand ="), &["pinion.hand", "spur"]);
    }

    #[test]
    fn helical_with_same_hands() {
        let t = edit(HELICAL, "hand = \"left\"", "hand = \"right\"");
        expect_err(
            &t,
            line_of(
                &t,
                "hand = \"right\"\nface_width_mm = 180.0\nbore_diameter_mm = 400",
            ),
            &["gear.hand", "opposite"],
        );
    }

    #[test]
    fn helical_angles_must_match_and_be_in_range() {
        let t = edit(
            HELICAL,
            "helix_angle_deg = 20.0\nhand = \"left\"",
            "helix_angle_deg = 21.0\nhand = \"left\"",
        );
        expect_err(
            &t,
            line_of(&t, "helix_angle_deg = 21.0"),
            &["gear.helix_angle_deg"],
        );
        let t = edit(
            HELICAL,
            "helix_angle_deg = 20.0\nhand = \"left\"",
            "helix_angle_deg = 45.0\nhand = \"left\"",
        );
        expect_err(
            &t,
            line_of(&t, "helix_angle_deg = 45.0"),
            &["gear.helix_angle_deg"],
        );
    }

    #[test]
    fn contact_analysis_keys() {
        let ok = edit(
            SPUR,
            "mesh = {}\n",
            "mesh = {}\ncontact = { roll_start_deg = -20.0, roll_end_deg = 20.0, roll_step_deg = 0.5, law = \"penalty\", penalty_factor = 10.0, slave = \"gear\", friction_mu = 0.0 }\n",
        );
        let s = parse(&ok).unwrap();
        let c = s.analyses.contact.unwrap();
        assert_eq!(c.law, Some(crate::mesh_cycle::ContactLaw::Penalty));
        assert_eq!(c.slave, Some(crate::mesh_cycle::SlaveBody::Gear));
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
    fn negative_torque() {
        let t = edit(SPUR, "torque_nm = 312.0", "torque_nm = -312.0");
        expect_err(
            &t,
            line_of(&t, "torque_nm"),
            &["load.torque_nm", "negative"],
        );
    }

    #[test]
    fn negative_module() {
        let t = edit(
            SPUR,
            "normal_module_mm = 3.8\nnormal_pressure_angle_deg = 20.0\nhelix",
            "normal_module_mm = -3.8\nnormal_pressure_angle_deg = 20.0\nhelix",
        );
        expect_err(
            &t,
            line_of(&t, "-3.8"),
            &["pinion.normal_module_mm", "positive"],
        );
    }

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

    #[test]
    fn missing_measured_profile() {
        let t = edit(
            SPUR,
            "end_relief_length_mm = 2.0\n",
            "end_relief_length_mm = 2.0\nmeasured_profile_csv = \"cmm/pinion.csv\"\n",
        );
        expect_err(
            &t,
            line_of(&t, "measured_profile_csv"),
            &["measured_profile_csv", "/nonexistent/cmm/pinion.csv"],
        );
    }

    #[test]
    fn measured_profile_relative_to_scene() {
        let dir = std::env::temp_dir().join(format!("flank-scene-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("cmm")).unwrap();
        std::fs::write(dir.join("cmm/pinion.csv"), "x,y\n0,0\n").unwrap();
        let t = edit(
            SPUR,
            "end_relief_length_mm = 2.0\n",
            "end_relief_length_mm = 2.0\nmeasured_profile_csv = \"cmm/pinion.csv\"\n",
        );
        let s = parse_scene(&t, &dir.join("scene.toml")).unwrap();
        let m = s.micro[0].as_ref().unwrap();
        assert_eq!(
            m.measured_profile.as_deref(),
            Some(dir.join("cmm/pinion.csv").as_path())
        );
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn micro_values_checked() {
        let t = edit(SPUR, "tip_relief_um = 10.0", "tip_relief_um = -10.0");
        expect_err(
            &t,
            line_of(&t, "tip_relief_um"),
            &["pinion.micro.tip_relief_um"],
        );
        let t = edit(SPUR, "lead_crowning_um = 5.0", "lead_crowning_um = nan");
        expect_err(
            &t,
            line_of(&t, "lead_crowning_um"),
            &["pinion.micro.lead_crowning_um", "finite"],
        );
        let t = edit(SPUR, "tip_relief_length_mm = 1.0\n", "");
        expect_err(&t, line_of(&t, "tip_relief_um"), &["tip_relief_length_mm"]);
        let t = edit(
            SPUR,
            "end_relief_length_mm = 2.0",
            "end_relief_length_mm = 7.0",
        );
        expect_err(
            &t,
            line_of(&t, "end_relief_length_mm"),
            &["end_relief_length_mm"],
        );
        let t = edit(
            SPUR,
            "tip_relief_shape = \"parabolic\"",
            "tip_relief_shape = \"cubic\"",
        );
        expect_err(&t, line_of(&t, "tip_relief_shape"), &["cubic"]);
    }

    #[test]
    fn malformed_toml_reports_line() {
        let t = edit(
            SPUR,
            "face_width_mm = 13.3\nprofile_shift = 0.3",
            "face_width_mm = 13.3\nprofile_shift = = 0.3",
        );
        let err = parse(&t).unwrap_err();
        match err {
            FlankError::Parse { line, .. } => assert_eq!(line, line_of(&t, "= = 0.3")),
            e => panic!("{e}"),
        }
        let t = edit(SPUR, "[load]", "[load");
        match parse(&t).unwrap_err() {
            FlankError::Parse { line, .. } => assert_eq!(line, line_of(&t, "[load")),
            e => panic!("{e}"),
        }
    }

    #[test]
    fn unknown_analysis() {
        let t = edit(SPUR, "mesh = {}\n", "mesh = {}\nlubrication = {}\n");
        expect_err(
            &t,
            line_of(&t, "lubrication"),
            &["lubrication", "known analyses: mesh", "ltca"],
        );
        let t = edit(SPUR, "mesh = {}\n", "mesh = { order = 2 }\n");
        expect_err(&t, line_of(&t, "order"), &["analyses.mesh", "order"]);
    }

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

    #[test]
    fn pair_geometry_checked() {
        // bore at the root
        let t = edit(SPUR, "bore_diameter_mm = 20.0", "bore_diameter_mm = 50.0");
        expect_err(
            &t,
            line_of(&t, "bore_diameter_mm = 50"),
            &["pinion.bore_diameter_mm"],
        );
        // centre distance too small for the shifts
        let t = edit(
            SPUR,
            "centre_distance_mm = 90.0",
            "centre_distance_mm = 89.0",
        );
        expect_err(
            &t,
            line_of(&t, "centre_distance_mm"),
            &["pair.centre_distance_mm", "interfere"],
        );
        // pressure angle out of range, and different modules
        let t = edit(
            SPUR,
            "normal_pressure_angle_deg = 20.0\nhelix",
            "normal_pressure_angle_deg = 45.0\nhelix",
        );
        expect_err(
            &t,
            line_of(&t, "= 45.0"),
            &["pinion.normal_pressure_angle_deg"],
        );
        let t = edit(
            SPUR,
            "normal_module_mm = 3.8\nnormal_pressure_angle_deg = 20.0\nface",
            "normal_module_mm = 4.0\nnormal_pressure_angle_deg = 20.0\nface",
        );
        expect_err(&t, line_of(&t, "= 4.0"), &["gear.normal_module_mm"]);
        // negative speed, face width
        let t = edit(SPUR, "speed_rpm = 11758.0", "speed_rpm = -1.0");
        expect_err(&t, line_of(&t, "speed_rpm"), &["load.speed_rpm"]);
        let t = edit(
            SPUR,
            "face_width_mm = 13.3\nprofile_shift = 0.3",
            "face_width_mm = 0\nprofile_shift = 0.3",
        );
        expect_err(
            &t,
            line_of(&t, "face_width_mm = 0"),
            &["pinion.face_width_mm"],
        );
        // backlash: the centre distance does not match the shifts
        let t = edit(
            SPUR,
            "centre_distance_mm = 90.0",
            "centre_distance_mm = 90.1",
        );
        expect_err(
            &t,
            line_of(&t, "centre_distance_mm"),
            &["pair.centre_distance_mm", "profile shifts"],
        );
        // pointed pinion tooth
        let t = edit(SPUR, "tip_diameter_mm = 58.7", "tip_diameter_mm = 62.0");
        assert!(parse(&t).is_err());
    }

    #[test]
    fn no_panic_on_odd_input() {
        for text in [
            "",
            "[pair]",
            "\u{0}\u{ff}",
            "pair = 3",
            "[pair]\nkind = 7",
            "a = [",
            "[[pinion]]\nteeth = 1",
        ] {
            assert!(parse(text).is_err(), "{text:?}");
        }
        for (from, to) in [
            ("teeth = 13", "teeth = 99999999999999"),
            (
                "normal_module_mm = 3.8\nnormal_pressure_angle_deg = 20.0\nhelix",
                "normal_module_mm = inf\nnormal_pressure_angle_deg = 20.0\nhelix",
            ),
            ("centre_distance_mm = 90.0", "centre_distance_mm = nan"),
            ("torque_nm = 312.0", "torque_nm = \"lots\""),
            ("profile_shift = 0.3", "profile_shift = 1e308"),
        ] {
            assert!(parse(&edit(SPUR, from, to)).is_err(), "{to}");
        }
    }

    #[test]
    fn paper_scenes_parse() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("papers");
        let s2 = read_scene(&root.join("seed002-spur/scene.toml")).unwrap();
        assert_eq!(s2.kind, PairKind::Spur);
        assert_eq!((s2.pair.pinion.teeth, s2.pair.gear.teeth), (13, 35));
        assert!(close(s2.pair.centre_distance, 90.0));
        assert!(close(s2.load.torque_nmm, 312_000.0));
        assert!(close(s2.pinion_material.young, 206_000.0));
        let eps2 = transverse_contact_ratio(&s2.pair);
        assert!((1.45..=1.51).contains(&eps2), "seed 002 eps_alpha {eps2}");
        assert!((eps2 - 1.4844).abs() < 1e-4, "README value {eps2}");

        let s4 = read_scene(&root.join("seed004-helical/scene.toml")).unwrap();
        assert_eq!(s4.kind, PairKind::Helical);
        assert_eq!((s4.pair.pinion.teeth, s4.pair.gear.teeth), (21, 37));
        assert!(close(s4.pair.pinion.helix_angle, 20f64.to_radians()));
        assert!(close(s4.load.torque_nmm, 5.0e6));
        assert!(close(s4.gear_material.young, 207_000.0));
        let eps4 = transverse_contact_ratio(&s4.pair);
        assert!((eps4 - 1.5029).abs() < 1e-4, "README value {eps4}");

        // the geometry module's pair check accepts both and agrees on ε_α
        let r2 = crate::geometry::pair::check_pair(&s2.pair).unwrap();
        assert!(
            (r2.contact_ratio - eps2).abs() < 1e-9,
            "{}",
            r2.contact_ratio
        );
        let r4 = crate::geometry::pair::check_pair(&s4.pair).unwrap();
        assert!(
            (r4.contact_ratio - eps4).abs() < 1e-9,
            "{}",
            r4.contact_ratio
        );
        assert!(
            (r4.overlap_ratio - 1.3064).abs() < 1e-4,
            "{}",
            r4.overlap_ratio
        );
    }

    #[test]
    fn no_panic_on_mutated_scenes() {
        // deterministic mutations of a valid scene: every one parses or errors, none panics
        let base: Vec<char> = SPUR.chars().collect();
        let alphabet: Vec<char> = "=[]{}\"'.,-+0123456789eainf_\n #é".chars().collect();
        let mut state: u64 = 0x9e37_79b9_7f4a_7c15;
        let mut next = |n: usize| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state % n as u64) as usize
        };
        for _ in 0..3000 {
            let mut t = base.clone();
            for _ in 0..1 + next(3) {
                let at = next(t.len());
                match next(3) {
                    0 => {
                        t.remove(at);
                    }
                    1 => t.insert(at, alphabet[next(alphabet.len())]),
                    _ => t[at] = alphabet[next(alphabet.len())],
                }
            }
            let text: String = t.into_iter().collect();
            if let Err(e) = parse(&text) {
                assert!(matches!(e, FlankError::Parse { .. }), "{e}");
            }
        }
    }
}
