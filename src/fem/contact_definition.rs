//! Contact data of a model, as a deck states it: surfaces, surface
//! interactions (pressure-overclosure law, friction) and contact pairs.
//!
//! Names are upper case (deck style). Element-face surfaces hold (element
//! index, CalculiX face number 1-based); node surfaces hold node indices.
//! [`ContactDefinition::validate`] checks the cross references so that the
//! solver can index without checks.

use crate::error::FlankError;
use crate::fem::mesh::Mesh;

/// What a surface is made of.
#[derive(Clone, Debug, PartialEq)]
pub enum SurfaceKind {
    /// Element faces `(element index, face 1..=6)`, CalculiX face numbering
    /// (`*SURFACE, TYPE=ELEMENT`, data `element or elset, Sn`).
    Element(Vec<(usize, usize)>),
    /// Nodes (`*SURFACE, TYPE=NODE`); usable as a slave surface only.
    Node(Vec<usize>),
}

/// A named surface.
#[derive(Clone, Debug, PartialEq)]
pub struct Surface {
    pub name: String,
    pub kind: SurfaceKind,
}

/// Normal contact law (`*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=...`).
#[derive(Clone, Debug, PartialEq)]
pub enum PressureOverclosure {
    /// No penetration: Lagrange multipliers (exact, active set).
    Hard,
    /// Penalty: pressure = slope × overclosure (MPa/mm); each slave node acts
    /// as a spring of stiffness slope × its tributary area. `slope = None`
    /// takes flank's automatic default (reported; see
    /// `contact::pairing::default_penalty_slope`). `tension` and
    /// `c0` are CalculiX's σ∞ and c₀ (kept for the deck round trip; flank
    /// has no tension at open contacts, which is their limit σ∞ → 0).
    Linear {
        slope: Option<f64>,
        tension: Option<f64>,
        c0: Option<f64>,
    },
}

/// Coulomb friction (`*FRICTION`: μ, stick slope).
#[derive(Clone, Debug, PartialEq)]
pub struct Friction {
    pub mu: f64,
    /// Tangential penalty (MPa/mm) of the stick state, if given.
    pub stick_slope: Option<f64>,
}

/// A named `*SURFACE INTERACTION`.
#[derive(Clone, Debug, PartialEq)]
pub struct SurfaceInteraction {
    pub name: String,
    /// `None` when the deck gives no `*SURFACE BEHAVIOR` (an error at solve
    /// time, as in CalculiX).
    pub behavior: Option<PressureOverclosure>,
    /// `None` (or μ = 0) is frictionless; friction terms are then left out.
    pub friction: Option<Friction>,
}

/// A `*CONTACT PAIR, TYPE=NODE TO SURFACE`: slave nodes against master faces.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactPair {
    pub interaction: String,
    pub slave: String,
    pub master: String,
    /// `SMALL SLIDING` given in the deck (flank always linearizes about the
    /// initial configuration; the flag is kept for the round trip).
    pub small_sliding: bool,
}

/// Everything a model says about contact. Empty for a model without contact.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ContactDefinition {
    pub surfaces: Vec<Surface>,
    pub interactions: Vec<SurfaceInteraction>,
    pub pairs: Vec<ContactPair>,
}

impl ContactDefinition {
    /// True when the model has no contact pair (the plain static path).
    pub fn is_empty(&self) -> bool {
        self.pairs.is_empty()
    }

    pub fn surface(&self, name: &str) -> Option<&Surface> {
        self.surfaces
            .iter()
            .find(|s| s.name.eq_ignore_ascii_case(name))
    }

    pub fn interaction(&self, name: &str) -> Option<&SurfaceInteraction> {
        self.interactions
            .iter()
            .find(|s| s.name.eq_ignore_ascii_case(name))
    }

    /// Checks names, indices and values against the mesh: every pair names
    /// an existing interaction with a surface behavior and two existing,
    /// non-empty surfaces; a master surface is made of element faces; μ ≥ 0;
    /// slopes positive and finite.
    pub fn validate(&self, mesh: &Mesh) -> Result<(), FlankError> {
        let bad = |m: String| Err(FlankError::Model(m));
        for (i, s) in self.surfaces.iter().enumerate() {
            if self.surfaces[..i]
                .iter()
                .any(|t| t.name.eq_ignore_ascii_case(&s.name))
            {
                return bad(format!("surface {} is defined twice", s.name));
            }
            match &s.kind {
                SurfaceKind::Element(faces) => {
                    if faces.is_empty() {
                        return bad(format!("surface {} names no element face", s.name));
                    }
                    for &(e, f) in faces {
                        let Some(el) = mesh.elements.get(e) else {
                            return bad(format!(
                                "surface {}: element index {e} beyond the mesh",
                                s.name
                            ));
                        };
                        if f == 0 || f > el.kind.face_count() {
                            return bad(format!(
                                "surface {}: element {} ({}) has no face S{f}",
                                s.name,
                                el.label,
                                el.kind.name()
                            ));
                        }
                    }
                }
                SurfaceKind::Node(nodes) => {
                    if nodes.is_empty() {
                        return bad(format!("surface {} names no node", s.name));
                    }
                    if let Some(&n) = nodes.iter().find(|&&n| n >= mesh.node_count()) {
                        return bad(format!(
                            "surface {}: node index {n} beyond the mesh",
                            s.name
                        ));
                    }
                }
            }
        }
        for (i, it) in self.interactions.iter().enumerate() {
            if self.interactions[..i]
                .iter()
                .any(|t| t.name.eq_ignore_ascii_case(&it.name))
            {
                return bad(format!("surface interaction {} is defined twice", it.name));
            }
            if let Some(PressureOverclosure::Linear { slope, tension, c0 }) = &it.behavior {
                for (what, v) in [("slope", slope), ("tension", tension), ("c0", c0)] {
                    if let Some(v) = v {
                        if !v.is_finite() || *v < 0.0 || (what == "slope" && *v == 0.0) {
                            return bad(format!(
                                "surface interaction {}: {what} {v} must be positive and finite",
                                it.name
                            ));
                        }
                    }
                }
            }
            if let Some(fr) = &it.friction {
                if !fr.mu.is_finite() || fr.mu < 0.0 {
                    return bad(format!(
                        "surface interaction {}: friction coefficient μ = {} must be ≥ 0",
                        it.name, fr.mu
                    ));
                }
                if let Some(k) = fr.stick_slope {
                    if !k.is_finite() || k <= 0.0 {
                        return bad(format!(
                            "surface interaction {}: stick slope {k} must be positive",
                            it.name
                        ));
                    }
                }
            }
        }
        for p in &self.pairs {
            let Some(it) = self.interaction(&p.interaction) else {
                return bad(format!(
                    "contact pair {} / {}: surface interaction {} is not defined",
                    p.slave, p.master, p.interaction
                ));
            };
            if it.behavior.is_none() {
                return bad(format!(
                    "surface interaction {} has no *SURFACE BEHAVIOR (pressure-overclosure law)",
                    it.name
                ));
            }
            let Some(slave) = self.surface(&p.slave) else {
                return bad(format!(
                    "contact pair: slave surface {} is not defined",
                    p.slave
                ));
            };
            let Some(master) = self.surface(&p.master) else {
                return bad(format!(
                    "contact pair: master surface {} is not defined",
                    p.master
                ));
            };
            if matches!(master.kind, SurfaceKind::Node(_)) {
                return bad(format!(
                    "contact pair {} / {}: the master surface must be made of element faces (TYPE=ELEMENT)",
                    slave.name, master.name
                ));
            }
            if slave.name.eq_ignore_ascii_case(&master.name) {
                return bad(format!(
                    "contact pair {0} / {0}: self contact is not supported",
                    slave.name
                ));
            }
        }
        Ok(())
    }
}
