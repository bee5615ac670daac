//! The operating point of one loaded contact (one tooth pair at one
//! position) and its EHL evaluation: film, traction, friction force and
//! power loss.
//!
//! Geometry and kinematics of an involute contact are closed form (no
//! nodal finite differences): at the distance ρ_t1 from the pinion's base
//! tangent point T₁ along the transverse line of action, the transverse
//! radii of curvature are ρ_t1 = r_b1 tan α_y1 and ρ_t2 = T₁T₂ − ρ_t1
//! (T₁T₂ = a sin α_wt), the normal-section radii across the contact line
//! ρ_i = ρ_ti / cos β_b, and the rolling speeds normal to the contact line
//! v_i = ω_i ρ_ti cos β_b (ω₂ = ω₁ z₁/z₂). Then (seed 002 eqs. 7–9)
//! R_x = ρ₁ρ₂/(ρ₁ + ρ₂), u = (v₁ + v₂)/2, v_s = v₁ − v₂ (> 0 where the
//! pinion surface is faster, in the recess), slide-to-roll ratio v_s/u.
//! Side leakage: along the contact line an involute helicoid is straight;
//! lead crowning C_β over the face width b (parabolic,
//! [`crate::geometry::micro`]) bends each flank to R_c = b²/(8 C_β), and
//! 1/R_y = 1/R_c1 + 1/R_c2 (∞ without crowning: a line contact). For
//! helical pairs the crowning radius along the inclined line is taken
//! as this axial one (exact for spur).
//!
//! Load and pressure come from the contact solution (seed 002 eqs. 10–11):
//! W = Σ λ_i over the pair's closed slave nodes, A = Σ of their tributary
//! areas, P̄ = W/A.

use crate::error::FlankError;
use crate::geometry::cylindrical::MeshKinematics;
use crate::lubrication::film::{film_thickness, Film, FilmInput, FilmModel};
use crate::lubrication::lubricant::Lubricant;
use crate::lubrication::traction::{traction, Traction, TractionInput};

/// Closed-form involute contact geometry and kinematics at one position.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct InvoluteContact {
    /// Distance from T₁ along the transverse line of action (mm), after
    /// clamping to the path of contact.
    pub from_t1_mm: f64,
    /// Whether the given position was outside the kinematic path (load-
    /// extended contact at a tip corner): the values are those of the
    /// path's end, flagged.
    pub outside_path: bool,
    /// Normal-section radii of curvature [pinion, gear] (mm).
    pub curvature_radius_mm: [f64; 2],
    /// R_x, R_y (mm; R_y may be infinite).
    pub radius_x_mm: f64,
    pub radius_y_mm: f64,
    /// Rolling speeds [pinion, gear] normal to the contact line (mm/s).
    pub rolling_speed_mm_s: [f64; 2],
    pub entraining_speed_mm_s: f64,
    pub sliding_speed_mm_s: f64,
}

/// The involute contact of a spur/helical pair at `path_position_mm` from
/// the start of the path of contact (as [`crate::geometry::gear_pair::LineContactPair::path_position`]),
/// pinion speed `speed_rpm`, lead crowning [pinion, gear] (mm) over the
/// face widths of `kin`.
pub fn involute_contact(
    kin: &MeshKinematics,
    path_position_mm: f64,
    speed_rpm: f64,
    lead_crowning_mm: [f64; 2],
) -> Result<InvoluteContact, FlankError> {
    if !(path_position_mm.is_finite() && speed_rpm >= 0.0 && speed_rpm.is_finite()) {
        return Err(FlankError::Model(format!(
            "involute contact: position {path_position_mm} mm and speed {speed_rpm} rpm must be finite (speed ≥ 0)"
        )));
    }
    let s = kin.path_start + path_position_mm;
    let clamped = s.clamp(kin.path_start, kin.path_end);
    let outside_path = clamped != s;
    let cb = kin.base_helix_angle.cos();
    let rho_t = [clamped, kin.line_length - clamped];
    if !(rho_t[0] > 0.0 && rho_t[1] > 0.0) {
        return Err(FlankError::Model(format!(
            "involute contact: the path of contact reaches a base circle (ρ = {rho_t:?} mm): no convex contact there"
        )));
    }
    let rho = [rho_t[0] / cb, rho_t[1] / cb];
    let radius_x = rho[0] * rho[1] / (rho[0] + rho[1]);
    let crown = |c: f64, b: f64| {
        if c > 0.0 {
            1.0 / (b * b / (8.0 * c))
        } else {
            0.0
        }
    };
    let curv_y = crown(lead_crowning_mm[0], kin.face_width[0])
        + crown(lead_crowning_mm[1], kin.face_width[1]);
    let radius_y = if curv_y > 0.0 {
        1.0 / curv_y
    } else {
        f64::INFINITY
    };
    let w1 = speed_rpm * std::f64::consts::PI / 30.0;
    let w2 = w1 * kin.z1 / kin.z2;
    let v = [w1 * rho_t[0] * cb, w2 * rho_t[1] * cb];
    Ok(InvoluteContact {
        from_t1_mm: clamped,
        outside_path,
        curvature_radius_mm: rho,
        radius_x_mm: radius_x,
        radius_y_mm: radius_y,
        rolling_speed_mm_s: v,
        entraining_speed_mm_s: 0.5 * (v[0] + v[1]),
        sliding_speed_mm_s: v[0] - v[1],
    })
}

impl InvoluteContact {
    /// What an operating point needs of it.
    pub fn kinematics(&self) -> ContactKinematics {
        ContactKinematics {
            radius_x_mm: self.radius_x_mm,
            radius_y_mm: self.radius_y_mm,
            entraining_speed_mm_s: self.entraining_speed_mm_s,
            sliding_speed_mm_s: self.sliding_speed_mm_s,
            outside_path: self.outside_path,
        }
    }
}

/// The geometry and kinematics of one contact that the EHL formulas need,
/// of any pair kind: closed form for an involute line contact
/// ([`InvoluteContact::kinematics`]), from the point TCA's curvatures and
/// velocities for a bevel/hypoid point contact
/// (`crate::ltca::lubricated`).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct ContactKinematics {
    /// R_x (along the entrainment, the smaller) and R_y (mm; R_y may be
    /// infinite: a line contact).
    pub radius_x_mm: f64,
    pub radius_y_mm: f64,
    /// u and v_s (mm/s).
    pub entraining_speed_mm_s: f64,
    pub sliding_speed_mm_s: f64,
    /// The values are those of the path's end, the position lying beyond it.
    pub outside_path: bool,
}

/// The Hertz contact of an operating point's load: its area (mm²), mean
/// and peak pressure p₀ (MPa), for [`MeanPressure::Hertz`] and the
/// subsurface stress.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HertzContact {
    pub area_mm2: f64,
    pub mean_mpa: f64,
    pub peak_mpa: f64,
}

impl HertzContact {
    /// A line contact of `length` (mm): area 2bL, p₀ = √(w′E′/(2πR_x))
    /// (Johnson, *Contact Mechanics* 1985, eq. 4.45 with E′ = 2E*).
    pub fn line(load: f64, radius_x: f64, length: f64, reduced_modulus: f64) -> Self {
        let (mean, b) = hertz_line_contact(load, radius_x, length, reduced_modulus);
        HertzContact {
            area_mm2: 2.0 * b * length,
            mean_mpa: mean,
            peak_mpa: (load / length * reduced_modulus / (2.0 * std::f64::consts::PI * radius_x))
                .sqrt(),
        }
    }
}

/// Where P̄ comes from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MeanPressure {
    /// W/A with A the contact solution's area (seed 002 eqs. 10–11): needs
    /// a mesh that resolves the contact width (several nodes across it).
    #[default]
    ContactArea,
    /// Hertz line contact over the contact line length L from W and R_x:
    /// P̄ = w′/(2b), b = (8w′R_x/(πE′))^½, w′ = W/L (= π p₀/4; Johnson,
    /// *Contact Mechanics* 1985, §4.2). For meshes too coarse to resolve
    /// the Hertz width, where W/A jumps with the number of closed node rows.
    Hertz,
}

impl MeanPressure {
    pub fn name(self) -> &'static str {
        match self {
            MeanPressure::ContactArea => "contact_area",
            MeanPressure::Hertz => "hertz",
        }
    }
}

/// Hertz line contact under `load` (N) over `length` (mm) with R_x (mm)
/// and E′ (MPa): (P̄ (MPa), semi-width b (mm)) (see [`MeanPressure::Hertz`]).
pub fn hertz_line_contact(
    load: f64,
    radius_x: f64,
    length: f64,
    reduced_modulus: f64,
) -> (f64, f64) {
    let w = load / length;
    let b = (8.0 * w * radius_x / (std::f64::consts::PI * reduced_modulus)).sqrt();
    (w / (2.0 * b), b)
}

/// Everything the EHL formulas need of one contact (internal units).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct OperatingPoint {
    /// W (N), A (mm²), P̄ = W/A (MPa) (with [`MeanPressure::Hertz`] A is
    /// the Hertz area 2bL).
    pub load_n: f64,
    pub contact_area_mm2: f64,
    pub mean_pressure_mpa: f64,
    /// R_x, R_y (mm), contact line length L (mm, for line fits).
    pub radius_x_mm: f64,
    pub radius_y_mm: f64,
    pub length_mm: f64,
    /// u, v_s (mm/s).
    pub entraining_speed_mm_s: f64,
    pub sliding_speed_mm_s: f64,
    /// E′ (MPa).
    pub reduced_modulus_mpa: f64,
    /// The kinematics came from outside the path (clamped; see [`InvoluteContact`]).
    pub outside_path: bool,
    /// The other estimate of P̄, for comparison: Hertz when P̄ is W/A of
    /// the contact solution, W/A when P̄ is Hertz (MPa; 0 if unknown).
    pub other_mean_pressure_mpa: f64,
    /// The Hertz peak pressure p₀ of the load on these radii (MPa; line or
    /// elliptical contact), for the subsurface stress.
    pub hertz_peak_mpa: f64,
}

impl OperatingPoint {
    /// From the contact's kinematics, the contact solution's W and A and
    /// the Hertz contact of W, P̄ as `pressure` says; `length_mm` is the
    /// contact length of line fits.
    pub fn new(
        contact: &ContactKinematics,
        load_n: f64,
        contact_area_mm2: f64,
        hertz: HertzContact,
        length_mm: f64,
        reduced_modulus_mpa: f64,
        pressure: MeanPressure,
    ) -> Result<Self, FlankError> {
        if !(load_n > 0.0 && load_n.is_finite() && contact_area_mm2 > 0.0) {
            return Err(FlankError::Model(format!(
                "operating point: load {load_n} N on {contact_area_mm2} mm²: a loaded contact with an area is needed"
            )));
        }
        let p_hertz = hertz.mean_mpa;
        let p_area = load_n / contact_area_mm2;
        let (area, p, other) = match pressure {
            MeanPressure::ContactArea => (contact_area_mm2, p_area, p_hertz),
            MeanPressure::Hertz => (hertz.area_mm2, p_hertz, p_area),
        };
        Ok(OperatingPoint {
            load_n,
            contact_area_mm2: area,
            mean_pressure_mpa: p,
            other_mean_pressure_mpa: other,
            radius_x_mm: contact.radius_x_mm,
            radius_y_mm: contact.radius_y_mm,
            length_mm,
            entraining_speed_mm_s: contact.entraining_speed_mm_s,
            sliding_speed_mm_s: contact.sliding_speed_mm_s,
            reduced_modulus_mpa,
            outside_path: contact.outside_path,
            hertz_peak_mpa: hertz.peak_mpa,
        })
    }

    /// Slide-to-roll ratio v_s/u.
    pub fn slide_to_roll(&self) -> f64 {
        self.sliding_speed_mm_s / self.entraining_speed_mm_s
    }
}

/// The EHL answer of one contact.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct ContactEhl {
    pub point: OperatingPoint,
    pub film: Film,
    pub traction: Traction,
    /// h_min / σ (λ ratio) when a composite roughness is given.
    pub lambda_ratio: Option<f64>,
    /// μ W (N) and μ W |v_s| (W).
    pub friction_force_n: f64,
    pub power_loss_w: f64,
}

/// Film, traction, friction force and power loss of `point`.
pub fn evaluate(
    lub: &Lubricant,
    model: FilmModel,
    point: &OperatingPoint,
    composite_roughness_mm: Option<f64>,
) -> Result<ContactEhl, FlankError> {
    let film = film_thickness(
        model,
        &FilmInput {
            viscosity: lub.viscosity_mpa_s,
            pressure_viscosity: lub.pressure_viscosity_per_mpa,
            reduced_modulus: point.reduced_modulus_mpa,
            radius_x: point.radius_x_mm,
            radius_y: point.radius_y_mm,
            load: point.load_n,
            length: point.length_mm,
            entraining_speed: point.entraining_speed_mm_s,
        },
    )?;
    let tr = traction(
        lub,
        &TractionInput {
            central_film: film.central,
            radius_x: point.radius_x_mm,
            reduced_modulus: point.reduced_modulus_mpa,
            mean_pressure: point.mean_pressure_mpa,
            entraining_speed: point.entraining_speed_mm_s,
            sliding_speed: point.sliding_speed_mm_s,
        },
    )?;
    let friction = tr.mu * point.load_n;
    Ok(ContactEhl {
        lambda_ratio: composite_roughness_mm.map(|s| film.minimum / s),
        friction_force_n: friction,
        // N · mm/s = 1e-3 W
        power_loss_w: friction * point.sliding_speed_mm_s.abs() * 1e-3,
        point: point.clone(),
        film,
        traction: tr,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The closed form against the TCA, whose speeds and curvatures come
    /// from the flank surfaces themselves (normal differences ±1e-3 mm).
    #[test]
    fn closed_form_matches_the_surface_tca() {
        use crate::geometry::gear_pair::LineKind;
        use crate::tca::{Tca, TcaSettings};
        let path =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("papers/seed002-spur/scene.toml");
        let scene = crate::scene::read_scene(&path).unwrap();
        let pair = scene.gear_pair().unwrap();
        let kin = MeshKinematics::new(
            &scene.cylindrical("this test").unwrap().pair,
            scene.mesh.teeth_in_sector as usize,
        )
        .unwrap();
        let tca = Tca::new(pair.clone(), 11758.0, TcaSettings::default()).unwrap();
        let mut checked = 0;
        for roll_deg in [-9.0, -2.5, 0.0, 4.0, 11.0] {
            let roll = f64::to_radians(roll_deg);
            for line in tca.position(roll).unwrap().lines {
                if line.kind != LineKind::Flank {
                    continue;
                }
                let pt = &line.points[line.points.len() / 2];
                let s = pair.path_position(line.pinion_tooth, roll);
                let c = involute_contact(&kin, s, 11758.0, [0.0; 2]).unwrap();
                assert!(!c.outside_path);
                let rel = |a: f64, b: f64| (a - b).abs() / b.abs().max(1e-9);
                assert!(
                    rel(c.entraining_speed_mm_s, pt.rolling_velocity * 1e3) < 1e-6,
                    "{roll_deg}°: u {} vs {}",
                    c.entraining_speed_mm_s,
                    pt.rolling_velocity * 1e3
                );
                assert!(
                    (c.sliding_speed_mm_s - pt.sliding_velocity * 1e3).abs()
                        < 1e-6 * c.entraining_speed_mm_s,
                    "{roll_deg}°: v_s {} vs {}",
                    c.sliding_speed_mm_s,
                    pt.sliding_velocity * 1e3
                );
                assert!(
                    rel(c.radius_x_mm, pt.equivalent_radius_mm) < 1e-4,
                    "{roll_deg}°: R_x {} vs {}",
                    c.radius_x_mm,
                    pt.equivalent_radius_mm
                );
                checked += 1;
            }
        }
        assert!(checked >= 5, "{checked}");
    }

    #[test]
    fn pitch_point_rolls_without_sliding() {
        let path =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("papers/seed002-spur/scene.toml");
        let scene = crate::scene::read_scene(&path).unwrap();
        let kin = MeshKinematics::new(&scene.cylindrical("this test").unwrap().pair, 3).unwrap();
        // the pitch point C: ρ_t1 = r_b1 tan α_wt
        let c = kin.base_radius[0] * kin.working_pressure_angle.tan();
        let ic = involute_contact(&kin, c - kin.path_start, 11758.0, [0.0; 2]).unwrap();
        assert!(ic.sliding_speed_mm_s.abs() < 1e-9 * ic.entraining_speed_mm_s);
        // u = ω₁ r_b1 tan α_wt = ω₁ r_w1 sin α_wt
        let w1 = 11758.0 * std::f64::consts::PI / 30.0;
        assert!((ic.entraining_speed_mm_s / (w1 * c) - 1.0).abs() < 1e-12);
        assert!(ic.radius_y_mm.is_infinite() && !ic.outside_path);
        // beyond the path: clamped and flagged
        let out = involute_contact(&kin, -1.0, 1000.0, [0.0; 2]).unwrap();
        assert!(out.outside_path && out.from_t1_mm == kin.path_start);
        // Hertz: P̄ = π p₀/4 with p₀ = (w′E′/(2πR))^½ (E′ = 2E*)
        let (p, b) = hertz_line_contact(1000.0, 10.0, 10.0, 226_000.0);
        let p0 = (100.0 * 226_000.0 / (2.0 * std::f64::consts::PI * 10.0)).sqrt();
        assert!((p / (std::f64::consts::PI * p0 / 4.0) - 1.0).abs() < 1e-12);
        assert!((100.0 / (2.0 * b) - p).abs() < 1e-9);
        // crowning 5 µm on 13.3 mm: R_c = b²/(8C) = 4422 mm each, R_y half
        let cr = involute_contact(&kin, 1.0, 1000.0, [0.005, 0.005]).unwrap();
        assert!((cr.radius_y_mm - 13.3f64.powi(2) / 0.04 / 2.0).abs() < 1e-9);
    }
}
