//! Central (and minimum) EHL film thickness of a contact from analytical
//! fits, in the Hamrock–Dowson dimensionless groups
//!
//! ```text
//!   U = η₀ u / (E′ R_x),  G = α E′,  W = w / (E′ R_x²),  H = h / R_x
//!   E′ = 2 / [(1 − ν₁²)/E₁ + (1 − ν₂²)/E₂]
//! ```
//!
//! with u the entraining speed (u₁ + u₂)/2, w the contact load, R_x the
//! equivalent radius in the entraining direction and R_y the one across
//! (side leakage). Any coherent units give the same groups; flank uses
//! mm, N, s, MPa.
//!
//! * **Chittenden** (Chittenden, Dowson, Dunn & Taylor, Proc. R. Soc. Lond.
//!   A 397 (1985) 271–294, entrainment along a principal axis; seed 002
//!   eq. 2): H_c = 4.31 U^0.68 G^0.49 W^−0.073 [1 − exp(−1.23 (R_y/R_x)^(2/3))],
//!   H_min = 3.68 U^0.68 G^0.49 W^−0.073 [1 − exp(−0.67 (R_y/R_x)^(2/3))].
//! * **Hamrock–Dowson** (Hamrock & Dowson, ASME J. Lubr. Technol. 99 (1977)
//!   264–276): H_c = 2.69 U^0.67 G^0.53 W^−0.067 (1 − 0.61 e^(−0.73 k)),
//!   H_min = 3.63 U^0.68 G^0.49 W^−0.073 (1 − e^(−0.68 k)),
//!   k = 1.0339 (R_y/R_x)^0.636.
//! * **Dowson–Higginson** (line contact, load per length w′ = w/L,
//!   W′ = w′/(E′ R_x)): H_min = 2.65 U^0.70 G^0.54 W′^−0.13 (Dowson &
//!   Higginson, *Elasto-hydrodynamic Lubrication*, SI ed. 1977); central by
//!   the companion fit of Dowson & Toyoda (1979) H_c = 3.06 U^0.69 G^0.56 W′^−0.10.
//! * **Pan–Hamrock** (line contact; Pan & Hamrock, ASME J. Tribol. 111
//!   (1989) 246–251, fits to isothermal numerical solutions with Roelands
//!   viscosity and Dowson–Higginson density): H_c = 2.922 W′^−0.166 U^0.692
//!   G^0.470, H_min = 1.714 W′^−0.128 U^0.694 G^0.568. Constants as
//!   reproduced in Hamrock, Schmid & Jacobson, *Fundamentals of Fluid Film
//!   Lubrication* (2nd ed. 2004); the original was not reachable in this
//!   project's library. Within −4.8 … +0.3 % (h_c) of flank's numerical
//!   line-contact EHL solver over p_H 0.5–1.5 GPa × u 1–20 m/s
//!   (`verification/ehl_line_contact`), where Dowson–Toyoda's h_c misses
//!   by −26 … −10 %.
//!
//! **Seed 002's transcription** (eq. 3) writes the Chittenden groups as
//! U_e = πη₀u/(4E_r r), G_e = 2E_rα/π, W_e = πW/(2E_r r²). With E_r the
//! reduced modulus E* = E′/2 these are (π/2)U, G/π and πW, which lower h_c by
//! the factor (π/2)^0.68 π^−0.49 π^−0.073 = 0.714 against the same fit in
//! the Hamrock–Dowson groups; in those groups Chittenden's and
//! Hamrock–Dowson's fits agree within a few per cent for a circular contact
//! (`verification/ehl_formulas` checks both), with the π-groups they differ
//! by ≈ 30 %. flank uses the Hamrock–Dowson groups; [`seed_groups_ratio`]
//! gives the factor for comparisons with the seed.
//!
//! **Validity**: the point-contact fits were made for ellipticity
//! k ≤ 8 (Hamrock & Dowson), i.e. R_y/R_x ≤ 25; beyond (an uncrowned spur
//! line contact has R_y = ∞) the result is the fit's limit and is flagged
//! [`FilmFlag::OutsideEllipticityRange`], never silently extrapolated. The
//! line-contact fit is flagged when given a contact with R_y/R_x ≤ 25.

use crate::error::FlankError;

/// Largest R_y/R_x covered by the point-contact fits (k ≤ 8, Hamrock & Dowson 1977).
pub const MAX_FITTED_RADIUS_RATIO: f64 = 25.0;

/// Which film-thickness fit.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FilmModel {
    /// Chittenden et al. (1985), seed 002 eq. 2.
    #[default]
    Chittenden,
    /// Hamrock & Dowson (1977), elliptical point contact.
    HamrockDowson,
    /// Dowson & Higginson (1977) line contact (central by Dowson & Toyoda 1979).
    DowsonHigginson,
    /// Pan & Hamrock (1989) line contact.
    PanHamrock,
}

impl FilmModel {
    pub fn name(self) -> &'static str {
        match self {
            FilmModel::Chittenden => "chittenden",
            FilmModel::HamrockDowson => "hamrock_dowson",
            FilmModel::DowsonHigginson => "dowson_higginson",
            FilmModel::PanHamrock => "pan_hamrock",
        }
    }
}

/// What a film formula needs (coherent units; flank: mm, N, s, MPa).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct FilmInput {
    /// η₀ (MPa·s), α (1/MPa).
    pub viscosity: f64,
    pub pressure_viscosity: f64,
    /// E′ = 2/[(1 − ν₁²)/E₁ + (1 − ν₂²)/E₂] (MPa).
    pub reduced_modulus: f64,
    /// R_x (entraining direction) and R_y (side leakage; may be ∞) (mm).
    pub radius_x: f64,
    pub radius_y: f64,
    /// Contact load w (N) and line length L (mm, for the line fit).
    pub load: f64,
    pub length: f64,
    /// Entraining speed u (mm/s).
    pub entraining_speed: f64,
}

/// A flag on a film result: the formula was used outside its data.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FilmFlag {
    /// A point-contact fit at R_y/R_x > [`MAX_FITTED_RADIUS_RATIO`] (line contact).
    OutsideEllipticityRange,
    /// The line-contact fit on a contact with R_y/R_x ≤ [`MAX_FITTED_RADIUS_RATIO`].
    PointContactInLineFit,
}

/// Film thickness and the groups it came from.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Film {
    pub model: FilmModel,
    /// Central and minimum film thickness (mm).
    pub central: f64,
    pub minimum: f64,
    /// U, G, W (W′ for the line fit).
    pub speed_group: f64,
    pub material_group: f64,
    pub load_group: f64,
    pub flags: Vec<FilmFlag>,
}

/// E′ = 2/[(1 − ν₁²)/E₁ + (1 − ν₂²)/E₂] (Hamrock–Dowson's reduced modulus).
pub fn reduced_modulus(e: [f64; 2], nu: [f64; 2]) -> f64 {
    2.0 / ((1.0 - nu[0] * nu[0]) / e[0] + (1.0 - nu[1] * nu[1]) / e[1])
}

/// Central and minimum film thickness of `input` by `model`.
pub fn film_thickness(model: FilmModel, input: &FilmInput) -> Result<Film, FlankError> {
    let FilmInput {
        viscosity,
        pressure_viscosity,
        reduced_modulus: e,
        radius_x: rx,
        radius_y: ry,
        load,
        length,
        entraining_speed: u,
    } = *input;
    let positive = |name: &str, v: f64| {
        if v > 0.0 && v.is_finite() {
            Ok(())
        } else {
            Err(FlankError::Model(format!(
                "film thickness: {name} = {v}: a finite value > 0 is needed"
            )))
        }
    };
    positive("viscosity η₀", viscosity)?;
    positive("pressure–viscosity coefficient α", pressure_viscosity)?;
    positive("reduced modulus E′", e)?;
    positive("equivalent radius R_x (mm)", rx)?;
    if !(ry > 0.0) || ry.is_nan() {
        return Err(FlankError::Model(format!(
            "film thickness: side-leakage radius R_y = {ry} mm: > 0 (or infinite) is needed"
        )));
    }
    positive("contact load w (N)", load)?;
    if !(u > 0.0 && u.is_finite()) {
        return Err(FlankError::Model(format!(
            "film thickness: entraining speed u = {} m/s: an EHL film needs u > 0 (a contact at rest, or one whose surfaces move apart, has no hydrodynamic film)",
            u * 1e-3
        )));
    }
    let big_u = viscosity * u / (e * rx);
    let big_g = pressure_viscosity * e;
    let ratio = ry / rx;
    let mut flags = Vec::new();
    let (hc, hm, wg) = match model {
        FilmModel::Chittenden | FilmModel::HamrockDowson => {
            let big_w = load / (e * rx * rx);
            if ratio > MAX_FITTED_RADIUS_RATIO {
                flags.push(FilmFlag::OutsideEllipticityRange);
            }
            let (c, m) = if model == FilmModel::Chittenden {
                let r23 = if ratio.is_finite() {
                    ratio.powf(2.0 / 3.0)
                } else {
                    f64::INFINITY
                };
                let base = big_u.powf(0.68) * big_g.powf(0.49) * big_w.powf(-0.073);
                (
                    4.31 * base * (1.0 - (-1.23 * r23).exp()),
                    3.68 * base * (1.0 - (-0.67 * r23).exp()),
                )
            } else {
                let k = if ratio.is_finite() {
                    1.0339 * ratio.powf(0.636)
                } else {
                    f64::INFINITY
                };
                (
                    2.69 * big_u.powf(0.67)
                        * big_g.powf(0.53)
                        * big_w.powf(-0.067)
                        * (1.0 - 0.61 * (-0.73 * k).exp()),
                    3.63 * big_u.powf(0.68)
                        * big_g.powf(0.49)
                        * big_w.powf(-0.073)
                        * (1.0 - (-0.68 * k).exp()),
                )
            };
            (c, m, big_w)
        }
        FilmModel::DowsonHigginson | FilmModel::PanHamrock => {
            positive("contact line length L (mm)", length)?;
            if ratio <= MAX_FITTED_RADIUS_RATIO {
                flags.push(FilmFlag::PointContactInLineFit);
            }
            let wl = load / (length * e * rx);
            if model == FilmModel::DowsonHigginson {
                (
                    3.06 * big_u.powf(0.69) * big_g.powf(0.56) * wl.powf(-0.10),
                    2.65 * big_u.powf(0.70) * big_g.powf(0.54) * wl.powf(-0.13),
                    wl,
                )
            } else {
                (
                    2.922 * wl.powf(-0.166) * big_u.powf(0.692) * big_g.powf(0.470),
                    1.714 * wl.powf(-0.128) * big_u.powf(0.694) * big_g.powf(0.568),
                    wl,
                )
            }
        }
    };
    let film = Film {
        model,
        central: hc * rx,
        minimum: hm * rx,
        speed_group: big_u,
        material_group: big_g,
        load_group: wg,
        flags,
    };
    if !(film.central > 0.0 && film.central.is_finite() && film.minimum.is_finite()) {
        return Err(FlankError::Model(format!(
            "film thickness: {} gave h_c = {} mm for U = {big_u:e}, G = {big_g}, W = {wg:e}",
            model.name(),
            film.central
        )));
    }
    Ok(film)
}

/// h_c(seed 002's π-groups) / h_c(Hamrock–Dowson groups) for the
/// Chittenden fit with E_r = E′/2: (π/2)^0.68 π^−0.49 π^−0.073 (module docs).
pub fn seed_groups_ratio() -> f64 {
    use std::f64::consts::PI;
    (PI / 2.0).powf(0.68) * PI.powf(-0.49) * PI.powf(-0.073)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn input() -> FilmInput {
        FilmInput {
            viscosity: 0.01e-6,
            pressure_viscosity: 0.02,
            reduced_modulus: 226_000.0,
            radius_x: 10.0,
            radius_y: 10.0,
            load: 100.0,
            length: 10.0,
            entraining_speed: 5000.0,
        }
    }

    #[test]
    fn chittenden_and_hamrock_dowson_agree_for_a_circle() {
        let c = film_thickness(FilmModel::Chittenden, &input()).unwrap();
        let h = film_thickness(FilmModel::HamrockDowson, &input()).unwrap();
        let d = c.central / h.central - 1.0;
        assert!(d.abs() < 0.08, "{d}");
        assert!(c.flags.is_empty());
        // the seed's π-groups would be ≈ 29 % lower
        assert!((seed_groups_ratio() - 0.7137).abs() < 1e-3);
    }

    #[test]
    fn line_contact_is_flagged() {
        let mut i = input();
        i.radius_y = f64::INFINITY;
        let c = film_thickness(FilmModel::Chittenden, &i).unwrap();
        assert_eq!(c.flags, vec![FilmFlag::OutsideEllipticityRange]);
        let d = film_thickness(FilmModel::DowsonHigginson, &input()).unwrap();
        assert_eq!(d.flags, vec![FilmFlag::PointContactInLineFit]);
    }

    /// Pan & Hamrock (1989) at three line-contact points, against values
    /// computed by hand in SI (η₀ Pa·s, α 1/Pa, E′ = 226 GPa, R m, w′ N/m,
    /// u m/s → h µm, 6 digits): A (0.01, 2e-8, 10 mm, 1e6, 5) → h_c
    /// 0.232821, h_min 0.221202; B (0.00468, 1e-8, 8 mm, 3e5, 20) → 0.284994,
    /// 0.244148; C (0.05, 2.2e-8, 20 mm, 2e6, 1) → 0.301435, 0.288679.
    #[test]
    fn pan_hamrock_hand_values() {
        let points = [
            (1e-8, 0.02, 10.0, 1000.0, 5000.0, 0.232821, 0.221202),
            (4.68e-9, 0.01, 8.0, 300.0, 20_000.0, 0.284994, 0.244148),
            (5e-8, 0.022, 20.0, 2000.0, 1000.0, 0.301435, 0.288679),
        ];
        for (eta, alpha, r, w_per_mm, u, hc, hm) in points {
            let i = FilmInput {
                viscosity: eta,
                pressure_viscosity: alpha,
                reduced_modulus: 226_000.0,
                radius_x: r,
                radius_y: f64::INFINITY,
                load: w_per_mm * 10.0,
                length: 10.0,
                entraining_speed: u,
            };
            let f = film_thickness(FilmModel::PanHamrock, &i).unwrap();
            assert!((f.central * 1e3 / hc - 1.0).abs() < 1e-5, "{f:?} vs {hc}");
            assert!((f.minimum * 1e3 / hm - 1.0).abs() < 1e-5, "{f:?} vs {hm}");
            assert!(f.flags.is_empty(), "{f:?}");
            assert_eq!(f.model.name(), "pan_hamrock");
        }
        // a point contact in the line fit is flagged, as Dowson–Higginson
        let f = film_thickness(FilmModel::PanHamrock, &input()).unwrap();
        assert_eq!(f.flags, vec![FilmFlag::PointContactInLineFit]);
    }

    #[test]
    fn zero_speed_is_an_error() {
        let mut i = input();
        i.entraining_speed = 0.0;
        let e = film_thickness(FilmModel::Chittenden, &i).unwrap_err();
        assert!(e.to_string().contains("entraining speed"), "{e}");
    }
}
