//! The choices an analysis offers, as plain data: how compliance tensors
//! are computed and read, the FE contact law and slave body, the LTCA's QP
//! solver, local contact model, friction model and edge variants.
//!
//! Scenes (`[analyses.*]` keys), the command line and the engines
//! (compliance, mesh_cycle, ltca) all read these types, so they live below
//! all of them: this module imports nothing of flank but the error type,
//! and the scene no longer imports the engines it configures.

use crate::error::FlankError;

// ── Compliance tensors: how the LTCA reads them ──

/// Whether the LTCA reads its tensors dense or compressed: the scene key
/// `[analyses.ltca] compression = "none" | 1e-6` and `flank ltca
/// --compression none|1e-6`. `none` (default) reads the dense tensor;
/// a number ε in (0, 1) reads page pairs from the block low-rank form at
/// that relative accuracy per block ([`crate::compliance::compressed::BlrTensor`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Compression {
    #[default]
    None,
    Blr(f64),
}

impl Compression {
    /// The accuracy ε, if compressed.
    pub fn epsilon(self) -> Option<f64> {
        match self {
            Compression::None => None,
            Compression::Blr(e) => Some(e),
        }
    }
}

impl std::str::FromStr for Compression {
    type Err = FlankError;
    fn from_str(s: &str) -> Result<Self, FlankError> {
        let bad = || {
            FlankError::Model(format!(
                "compression: expected \"none\" or a relative accuracy in (0, 1) such as 1e-6, got {s:?}"
            ))
        };
        match s.trim() {
            "none" => Ok(Compression::None),
            x => {
                let e: f64 = x.parse().map_err(|_| bad())?;
                if e > 0.0 && e < 1.0 {
                    Ok(Compression::Blr(e))
                } else {
                    Err(bad())
                }
            }
        }
    }
}

impl serde::Serialize for Compression {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            Compression::None => s.serialize_str("none"),
            Compression::Blr(e) => s.serialize_f64(*e),
        }
    }
}

impl<'de> serde::Deserialize<'de> for Compression {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        #[derive(serde::Deserialize)]
        #[serde(untagged)]
        enum Raw {
            Name(String),
            Epsilon(f64),
        }
        let text = match Raw::deserialize(d)? {
            Raw::Name(s) => s,
            Raw::Epsilon(e) => format!("{e:e}"),
        };
        text.parse().map_err(serde::de::Error::custom)
    }
}

// ── Compliance tensors: how they are computed ──

/// How the flank block of K⁻¹ is computed.
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    serde::Serialize,
    serde::Deserialize,
    clap::ValueEnum,
)]
#[serde(rename_all = "lowercase")]
pub enum Method {
    /// Flank DOFs ordered last; C = (L₂₂L₂₂ᵀ)⁻¹ from the factor's trailing block (default: fastest).
    #[default]
    Schur,
    /// Unit right-hand sides solved in blocks, blocks in parallel.
    Blocked,
}

impl Method {
    pub fn name(self) -> &'static str {
        match self {
            Method::Schur => "schur",
            Method::Blocked => "blocked",
        }
    }
}

// ── Compliance tensors: which flank nodes carry them ──

/// Which flank node sets of a gear sector carry compliance tensors.
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    serde::Serialize,
    serde::Deserialize,
    clap::ValueEnum,
)]
#[serde(rename_all = "lowercase")]
pub enum FlankSelection {
    /// `FLANK_R<k>` of every tooth: the side [`crate::mesh::gear_body`] loads.
    #[default]
    Loaded,
    /// `FLANK_L<k>` of every tooth.
    Left,
    /// `FLANK_R<k>` of every tooth.
    Right,
    /// Both flanks of every tooth.
    Both,
}

impl FlankSelection {
    /// The node-set names for a sector of `teeth` teeth.
    pub fn set_names(self, teeth: usize) -> Vec<String> {
        let side = |s: &'static str| (1..=teeth).map(move |k| format!("FLANK_{s}{k}"));
        match self {
            FlankSelection::Loaded | FlankSelection::Right => side("R").collect(),
            FlankSelection::Left => side("L").collect(),
            FlankSelection::Both => side("L").chain(side("R")).collect(),
        }
    }
}

/// Which part of each selected flank carries compliance tensors.
///
/// The Schur-complement path costs m³ in the m = 3N flank DOFs
/// (`benches/README.md`, "Compliance tensors"), so DOFs the contact cannot
/// load are dear. The block of K⁻¹ on a subset of the flank DOFs is exactly
/// the sub-block of the full one (C = Eᵀ K⁻¹ E with fewer columns of E):
/// restricting the nodes drops rows and columns, it approximates nothing.
/// The active region's cut: [`crate::compliance::body::active_flank_cut`] with
/// [`crate::compliance::body::active_margin_mm`].
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    serde::Serialize,
    serde::Deserialize,
    clap::ValueEnum,
)]
#[serde(rename_all = "lowercase")]
pub enum FlankRegion {
    /// The whole flank node sets: involute and root fillet.
    #[default]
    Full,
    /// The active flank (start of active profile, from the pair, up to the
    /// tip) plus a margin of 2 flank elements + 1 mm down the profile; the
    /// default of the runs that know the mating gear (`flank ltca`,
    /// `flank compare`) on spur/helical pairs.
    Active,
}

impl FlankRegion {
    /// The lower-case name used in scenes, on the command line and in reports.
    pub fn name(self) -> &'static str {
        match self {
            FlankRegion::Full => "full",
            FlankRegion::Active => "active",
        }
    }
}

// ── FE contact over the mesh cycle ──

/// Which body carries the slave nodes (the other gives the master faces).
///
/// Node-to-surface contact is one-sided: slave nodes cannot pass through
/// master faces, but a master *corner* (a tooth tip edge) can cut between
/// slave nodes. At the start of engagement the gear's tip edge meets the
/// pinion's root flank, at the end the pinion's tip edge meets the gear's
/// root flank, so each tip edge must be on the slave side while it is in
/// play. `Auto` (the default) does that per tooth pair and position: the
/// gear is the slave while the pair is before its kinematic start of
/// contact (load-extended contact of the gear's tip edge), the pinion from
/// the kinematic start on. Inside the path both flanks are smooth and the
/// pinion as slave agreed better with the LTCA at 1° after the start
/// (verification/ltca: TE 2.6 % against 6.2 % with the gear as slave).
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    serde::Serialize,
    serde::Deserialize,
    clap::ValueEnum,
)]
#[serde(rename_all = "lowercase")]
pub enum SlaveBody {
    #[default]
    Auto,
    Pinion,
    Gear,
}

impl SlaveBody {
    pub fn name(self) -> &'static str {
        match self {
            SlaveBody::Auto => "auto",
            SlaveBody::Pinion => "pinion",
            SlaveBody::Gear => "gear",
        }
    }
}

/// Normal contact law of a gear run.
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    serde::Serialize,
    serde::Deserialize,
    clap::ValueEnum,
)]
#[serde(rename_all = "lowercase")]
pub enum ContactLaw {
    /// No penetration (Lagrange multipliers), as seed 002's Abaqus "hard".
    #[default]
    Hard,
    /// Linear penalty: slope × overclosure; slope = penalty_factor × the
    /// automatic default (10 × the flank elements' normal stiffness per area).
    Penalty,
}

// ── Compliance-matrix LTCA ──

/// How the LTCA treats the local contact deformation.
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    serde::Serialize,
    serde::Deserialize,
    clap::ValueEnum,
)]
#[serde(rename_all = "kebab-case")]
pub enum LocalModel {
    /// FE cells of half-width max(a, κ h) plus the half-space correction H.
    #[default]
    HalfSpace,
    /// FE cells of half-width max(a, κ h) only (near field below κ h missing).
    None,
}

impl LocalModel {
    pub fn name(self) -> &'static str {
        match self {
            LocalModel::HalfSpace => "half-space",
            LocalModel::None => "none",
        }
    }
}

/// Which LTCA variants to run: with the edge contacts as candidates, without
/// them (the flank axes only, today's LTCA), or both (seed 000's
/// comparison). Scene key `[analyses.ltca] edges`, option `--edges`.
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    serde::Serialize,
    serde::Deserialize,
    clap::ValueEnum,
)]
#[serde(rename_all = "kebab-case")]
pub enum EdgeVariants {
    #[default]
    Without,
    With,
    Both,
}

impl EdgeVariants {
    /// The variants to run, as (edges on, name) in the order written.
    pub fn runs(self) -> Vec<(bool, &'static str)> {
        match self {
            EdgeVariants::Without => vec![(false, "without_edges")],
            EdgeVariants::With => vec![(true, "with_edges")],
            EdgeVariants::Both => vec![(true, "with_edges"), (false, "without_edges")],
        }
    }
}

/// What sets the slip, hence the friction direction, of the frictional
/// LTCA (the physics behind each: [`crate::ltca::friction`]).
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    serde::Serialize,
    serde::Deserialize,
    clap::ValueEnum,
)]
#[serde(rename_all = "kebab-case")]
pub enum FrictionModel {
    /// Seeds 001/003: the torque in load increments, stick/slip/separation,
    /// the slip per unit rotation ρ = r_t + s r_n with the kinematic
    /// sliding coefficient s = v_s/(ω₁ r_n).
    #[default]
    Incremental,
    /// The same with s = 0: the torque taken up at a standing position
    /// against the held mate, what one static FE contact step with Coulomb
    /// friction models (`flank run --friction-mu`).
    Standstill,
    /// The running mesh: fully developed sliding, P_t = μ P_n against the
    /// kinematic sliding velocity at every loaded point
    /// ([`crate::ltca::friction::solve_sliding`]).
    Sliding,
}

/// The solver of the contact QP.
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    serde::Serialize,
    serde::Deserialize,
    clap::ValueEnum,
)]
#[serde(rename_all = "kebab-case")]
pub enum QpSolver {
    /// Dedicated primal active-set method (exact at termination, fast).
    #[default]
    ActiveSet,
    /// clarabel interior point, then polished on its loaded set.
    Clarabel,
}

impl QpSolver {
    /// All solvers, for sweeps and CLI help.
    pub const ALL: [QpSolver; 2] = [QpSolver::ActiveSet, QpSolver::Clarabel];

    /// The name used in scenes, the CLI and reports.
    pub fn name(self) -> &'static str {
        match self {
            QpSolver::ActiveSet => "active-set",
            QpSolver::Clarabel => "clarabel",
        }
    }
}

impl std::fmt::Display for QpSolver {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for QpSolver {
    type Err = FlankError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        QpSolver::ALL
            .into_iter()
            .find(|v| v.name() == s)
            .ok_or_else(|| {
                FlankError::Model(format!(
                    "unknown contact QP solver '{s}' (expected active-set or clarabel)"
                ))
            })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compression_setting_parses_or_names_the_error() {
        assert_eq!("none".parse::<Compression>().unwrap(), Compression::None);
        assert_eq!(
            "1e-6".parse::<Compression>().unwrap(),
            Compression::Blr(1e-6)
        );
        for bad in ["0", "1", "-1e-6", "dense", "nan", ""] {
            let e = bad.parse::<Compression>().unwrap_err().to_string();
            assert!(e.contains("compression"), "{bad}: {e}");
        }
        #[derive(serde::Deserialize)]
        struct S {
            compression: Compression,
        }
        let s: S = toml::from_str("compression = 1e-6").unwrap();
        assert_eq!(s.compression, Compression::Blr(1e-6));
        let s: S = toml::from_str("compression = \"none\"").unwrap();
        assert_eq!(s.compression, Compression::None);
        assert!(toml::from_str::<S>("compression = 2.0").is_err());
    }

    #[test]
    fn flank_selection_names_the_node_sets() {
        assert_eq!(
            FlankSelection::Both.set_names(2),
            ["FLANK_L1", "FLANK_L2", "FLANK_R1", "FLANK_R2"]
        );
        assert_eq!(FlankSelection::Loaded.set_names(1), ["FLANK_R1"]);
    }
}
