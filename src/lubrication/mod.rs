//! Lubricated contact: EHL film thickness, traction and the wet–dry loop
//! of seed 002 (lubricated loaded tooth contact analysis).
//!
//! ```text
//! lubricant        oil and solid thermal data, range checks (internal units)
//! film             central/minimum film: Chittenden et al. 1985 (seed eq. 2–3),
//!                  Hamrock–Dowson 1977, Dowson–Higginson and Pan–Hamrock 1989
//!                  line contact
//! traction         Evans & Johnson 1986 thermal Eyring μ (seed eq. 4–5), regime flags
//! operating_point  closed-form involute R_x, R_y, u, v_s; W, P̄ from the contact
//!                  solution; film + traction + friction force + power loss
//! wet_dry          dry pass at μ₀ → μ per contact → wet passes until the
//!                  change of μ is below the tolerance (bounded)
//! subsurface       McEwen / Smith–Liu stresses below a Hertz line contact
//!                  with traction μp and their maxima (FE check:
//!                  `verification/subsurface_stress`)
//! ```
//!
//! Layers: uses geometry (involute kinematics) only; the analyses
//! (`mesh_cycle`) call it with their contact results, never the reverse.
//! Every discrepancy with the seed's transcription (π-groups in eq. 3,
//! the missing β in eq. 4) is stated in the module that implements the
//! formula and in `verification/ehl_formulas/README.md`.

pub mod film;
pub mod lubricant;
pub mod operating_point;
pub mod subsurface;
pub mod traction;
pub mod wet_dry;

pub use film::{film_thickness, reduced_modulus, Film, FilmFlag, FilmInput, FilmModel};
pub use lubricant::{Lubricant, LubricantSi};
pub use operating_point::{
    evaluate, hertz_line_contact, involute_contact, ContactEhl, ContactKinematics, HertzContact,
    InvoluteContact, MeanPressure, OperatingPoint,
};
pub use traction::{traction, Traction, TractionFlag, TractionInput};
pub use wet_dry::{wet_dry_loop, LoopResult, LoopSettings, Pass};
