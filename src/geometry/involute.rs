//! Involute gear relations (ISO 21771:2007, DIN 3960, Niemann–Winter, Maschinenelemente vol. II, spur gear geometry).
//!
//! All functions take a [`GearSpec`] in internal units (mm, rad). For helical
//! gears the transverse quantities (index t) are those of the transverse
//! section; the normal quantities (index n) those of the generating rack.
//! The plain functions assume a validated spec; [`GearGeometry::new`] validates
//! first and is the entry point for user data.

use super::GearSpec;
use crate::error::FlankError;
use std::f64::consts::PI;

type Result<T> = std::result::Result<T, FlankError>;

/// Involute function inv α = tan α − α (ISO 21771:2007, "involute function").
pub fn inv(alpha: f64) -> f64 {
    alpha.tan() - alpha
}

/// Inverse of the involute function: α with tan α − α = y, for α ∈ [0, 1.5) rad.
///
/// Newton's method on f(α) = tan α − α − y (f′ = tan² α), started from the
/// series inversion α ≈ (3y)^{1/3} − 2y/5 (y < 0.5) or max(1, atan(y + 1)),
/// safeguarded by bisection on [0, 1.5).
pub fn inv_inverse(y: f64) -> Result<f64> {
    const HI: f64 = 1.5;
    if !y.is_finite() || y < 0.0 || y > inv(HI) {
        return Err(FlankError::Model(format!(
            "inverse involute function: inv α = {y} is outside [0, {:.3}] (α in [0, {HI}) rad)",
            inv(HI)
        )));
    }
    if y == 0.0 {
        return Ok(0.0);
    }
    let (mut lo, mut hi) = (0.0_f64, HI);
    // Start: three-term series α ≈ (3y)^{1/3} − (2/5) y for small y, else bracket midpoint.
    let mut a = if y < 0.5 {
        let c = (3.0 * y).cbrt();
        (c - 0.4 * y).clamp(1e-300, HI)
    } else {
        (y + 1.0).atan().max(1.0)
    };
    for _ in 0..100 {
        let f = inv(a) - y;
        if f > 0.0 {
            hi = a;
        } else {
            lo = a;
        }
        let t = a.tan();
        let fp = t * t;
        let mut next = a - f / fp;
        if !(next > lo && next < hi && next.is_finite()) {
            next = 0.5 * (lo + hi);
        }
        if (next - a).abs() <= 1e-15 * a.max(1e-300) {
            return Ok(next);
        }
        a = next;
    }
    Ok(a)
}

/// Transverse module m_t = m_n / cos β (ISO 21771:2007, transverse module).
pub fn transverse_module(g: &GearSpec) -> f64 {
    g.normal_module / g.helix_angle.cos()
}

/// Transverse pressure angle α_t = atan(tan α_n / cos β) (ISO 21771:2007).
pub fn transverse_pressure_angle(g: &GearSpec) -> f64 {
    (g.normal_pressure_angle.tan() / g.helix_angle.cos()).atan()
}

/// Reference radius r = z m_t / 2 (ISO 21771:2007, reference diameter d = z m_t).
pub fn reference_radius(g: &GearSpec) -> f64 {
    g.teeth as f64 * transverse_module(g) / 2.0
}

/// Base radius r_b = r cos α_t (ISO 21771:2007, base diameter d_b = d cos α_t).
pub fn base_radius(g: &GearSpec) -> f64 {
    reference_radius(g) * transverse_pressure_angle(g).cos()
}

/// Base helix angle β_b: sin β_b = sin β cos α_n (ISO 21771:2007).
pub fn base_helix_angle(g: &GearSpec) -> f64 {
    (g.helix_angle.sin() * g.normal_pressure_angle.cos()).asin()
}

/// Transverse base pitch p_bt = π m_t cos α_t (ISO 21771:2007).
pub fn transverse_base_pitch(g: &GearSpec) -> f64 {
    PI * transverse_module(g) * transverse_pressure_angle(g).cos()
}

/// Normal base pitch p_bn = π m_n cos α_n = p_bt cos β_b (ISO 21771:2007).
pub fn normal_base_pitch(g: &GearSpec) -> f64 {
    PI * g.normal_module * g.normal_pressure_angle.cos()
}

/// Tip radius r_a: the given tip diameter / 2, else r + m_n (h_aP* + x)
/// (ISO 21771:2007, no tip shortening; h_aP* is the rack's dedendum).
pub fn tip_radius(g: &GearSpec) -> f64 {
    match g.tip_diameter {
        Some(d) => d / 2.0,
        None => reference_radius(g) + g.normal_module * (g.rack.dedendum + g.profile_shift),
    }
}

/// Root radius r_f = r − m_n (h_fP* − x) (ISO 21771:2007; h_fP* is the rack's addendum).
pub fn root_radius(g: &GearSpec) -> f64 {
    reference_radius(g) - g.normal_module * (g.rack.addendum - g.profile_shift)
}

/// Transverse tooth thickness (arc) at the reference circle,
/// s_t = m_t (π/2 + 2 x tan α_n) (ISO 21771:2007, zero backlash).
pub fn reference_thickness(g: &GearSpec) -> f64 {
    transverse_module(g) * (PI / 2.0 + 2.0 * g.profile_shift * g.normal_pressure_angle.tan())
}

/// Normal tooth thickness at the reference circle s_n = s_t cos β (ISO 21771:2007).
pub fn normal_reference_thickness(g: &GearSpec) -> f64 {
    reference_thickness(g) * g.helix_angle.cos()
}

/// Half the angular tooth thickness at the base circle,
/// ψ_b = s_t / (2 r) + inv α_t (ISO 21771:2007, thickness at any diameter).
pub fn base_half_angle(g: &GearSpec) -> f64 {
    reference_thickness(g) / (2.0 * reference_radius(g)) + inv(transverse_pressure_angle(g))
}

/// Transverse arc tooth thickness at radius r_y ≥ r_b,
/// s_yt = 2 r_y (s_t/(2r) + inv α_t − inv α_yt), cos α_yt = r_b / r_y (ISO 21771:2007).
pub fn thickness_at_radius(g: &GearSpec, r_y: f64) -> Result<f64> {
    let rb = base_radius(g);
    if !(r_y.is_finite() && r_y >= rb) {
        return Err(FlankError::Model(format!(
            "tooth thickness at radius {r_y} mm: the involute exists only at radii ≥ the base radius {rb:.6} mm"
        )));
    }
    let a_y = (rb / r_y).acos();
    Ok(2.0 * r_y * (base_half_angle(g) - inv(a_y)))
}

/// Helix angle at radius r_y: tan β_y = tan β · r_y / r (ISO 21771:2007).
pub fn helix_angle_at_radius(g: &GearSpec, r_y: f64) -> f64 {
    (g.helix_angle.tan() * r_y / reference_radius(g)).atan()
}

/// Transverse tip thickness s_at = s_yt at r_a (may be negative: pointed and cut).
pub fn tip_thickness(g: &GearSpec) -> Result<f64> {
    thickness_at_radius(g, tip_radius(g))
}

/// Normal tip thickness s_an = s_at cos β_a (ISO 21771:2007; DIN 3960).
pub fn normal_tip_thickness(g: &GearSpec) -> Result<f64> {
    Ok(tip_thickness(g)? * helix_angle_at_radius(g, tip_radius(g)).cos())
}

/// Span measurement over k teeth in the normal section (ISO 21771:2007; DIN 3960):
/// W_k = m_n cos α_n [(k − 0.5) π + z inv α_t] + 2 x m_n sin α_n.
pub fn span(g: &GearSpec, k: u32) -> f64 {
    let (mn, an) = (g.normal_module, g.normal_pressure_angle);
    mn * an.cos() * ((k as f64 - 0.5) * PI + g.teeth as f64 * inv(transverse_pressure_angle(g)))
        + 2.0 * g.profile_shift * mn * an.sin()
}

/// The usual number of teeth spanned (DIN 3960; Niemann–Winter vol. II):
/// k = round(z/π [tan α_M / cos² β_b − 2 x tan α_n / z − inv α_t] + 0.5),
/// cos α_M = r_b / (r + x m_n), clamped to 1..=z−1. Spur, x = 0: k = round(z α/π + 0.5).
pub fn span_teeth(g: &GearSpec) -> u32 {
    let z = g.teeth as f64;
    let rm = reference_radius(g) + g.profile_shift * g.normal_module;
    let c = (base_radius(g) / rm).clamp(-1.0, 1.0);
    let am = c.acos();
    let bb = base_helix_angle(g).cos();
    let k = z / PI
        * (am.tan() / (bb * bb)
            - 2.0 * g.profile_shift * g.normal_pressure_angle.tan() / z
            - inv(transverse_pressure_angle(g)))
        + 0.5;
    let k = if k.is_finite() { k.round() } else { 1.0 };
    (k.max(1.0) as u32).min(g.teeth.saturating_sub(1).max(1))
}

/// Height, in module units, of the end of the generating rack's straight flank
/// above its tip line: ρ_fP* (1 − sin α_n) (the rest of the rack tip is the rounding).
fn rack_rounding_height(g: &GearSpec) -> f64 {
    g.rack.tip_radius * (1.0 - g.normal_pressure_angle.sin())
}

/// Undercut limit (smallest shift without undercut) for a rack with tip rounding:
/// x_min = h_fP* − ρ_fP* (1 − sin α_n) − (z / (2 cos β)) sin² α_t
/// (Niemann–Winter vol. II, undercut limit; ISO 21771:2007 generating-rack relations: the end of
/// the rack's straight flank must not pass the interference point T of the line of action).
pub fn undercut_limit(g: &GearSpec) -> f64 {
    let at = transverse_pressure_angle(g);
    g.rack.addendum
        - rack_rounding_height(g)
        - g.teeth as f64 / (2.0 * g.helix_angle.cos()) * at.sin().powi(2)
}

/// Roll length r_b·u_F from the base tangent point to the start of the involute
/// (form point), generated by the end of the rack's straight flank:
/// g_F = r sin α_t − h_FfP / sin α_t, h_FfP = m_n (h_fP* − x − ρ_fP*(1 − sin α_n)).
/// Negative means undercut.
pub fn form_roll_length(g: &GearSpec) -> f64 {
    let at = transverse_pressure_angle(g);
    let h = g.normal_module * (g.rack.addendum - g.profile_shift - rack_rounding_height(g));
    reference_radius(g) * at.sin() - h / at.sin()
}

/// Form circle radius r_F (start of the involute, junction with the root fillet),
/// r_F = √(r_b² + g_F²) with g_F from [`form_roll_length`] (no undercut).
pub fn form_radius(g: &GearSpec) -> Result<f64> {
    let gf = form_roll_length(g);
    if gf < 0.0 {
        return Err(FlankError::Model(format!(
            "{} teeth, x = {}: the gear is undercut (x_min = {:.4}); a shift x ≥ x_min is needed",
            g.teeth,
            g.profile_shift,
            undercut_limit(g)
        )));
    }
    Ok(base_radius(g).hypot(gf))
}

/// Largest rack tip radius ρ_fP* that fits the rack tooth tip (the two roundings touch):
/// ρ_max* = (π/4 − h_fP* tan α_n) cos α_n / (1 − sin α_n).
pub fn max_rack_tip_radius(g: &GearSpec) -> f64 {
    rack_tip_radius_limit(g.rack.addendum, g.normal_pressure_angle)
}

/// [`max_rack_tip_radius`] of a rack of addendum h_fP* (×m_n) at α_n (rad).
///
/// The generating rack's tooth (s_P = e_P = π/2 m_n at the datum line) has the
/// half-width π/4 − h_fP* tan α_n at its tip line. A rounding tangent to the tip
/// line and to the flank (which meets the tip line at 90° + α_n inside the tooth)
/// touches the tip line ρ tan(45° − α_n/2) = ρ (1 − sin α_n)/cos α_n from the
/// corner; both roundings fit while that is at most the half-width, which gives
/// the formula (full root radius at equality). Negative: the rack tooth is pointed.
pub fn rack_tip_radius_limit(addendum: f64, alpha_n: f64) -> f64 {
    (PI / 4.0 - addendum * alpha_n.tan()) * alpha_n.cos() / (1.0 - alpha_n.sin())
}

/// ISO 53:1998 profile A's rack tip radius ρ_fP* = 0.38 (stated for α_P = 20°).
pub const ISO53_TIP_RADIUS: f64 = 0.38;

/// Share of [`rack_tip_radius_limit`] the default tip radius takes where 0.38
/// does not fit: a full-radius root less 1 %, leaving the root a short flat land
/// (the meshers need one). ISO 53 profile D is cut the same way at 20°:
/// ρ_fP* = 0.39 on h_fP* = 1.4, where the full radius is 0.394.
pub const FULL_ROOT_RADIUS_SHARE: f64 = 0.99;

/// Default rack tip radius ρ_fP* (×m_n) for a rack of addendum h_fP* at α_n (rad):
/// ρ_fP* = min(0.38, 0.99 ρ_max*) with ρ_max* from [`rack_tip_radius_limit`]:
/// ISO 53 profile A's 0.38 where it leaves the root its land, otherwise nearly the
/// full root radius. ISO 53 gives ρ_fP* for α_P = 20° only; at 20° and h_fP* = 1.25,
/// ρ_max* = 0.472 and the default is 0.38, as it is up to α_n = 23.04°. Zero where
/// the rack tooth is pointed (the scene refuses such a rack).
pub fn default_rack_tip_radius(addendum: f64, alpha_n: f64) -> f64 {
    let limit = rack_tip_radius_limit(addendum, alpha_n);
    ISO53_TIP_RADIUS
        .min(FULL_ROOT_RADIUS_SHARE * limit)
        .max(0.0)
}

/// Smallest normal tip thickness accepted, as a multiple of m_n (pointed-tip check).
pub const MIN_TIP_THICKNESS: f64 = 0.2;

/// Derived figures of one gear (mm, rad), computed after validation.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct GearGeometry {
    pub teeth: u32,
    pub profile_shift: f64,
    /// Transverse module m_t (mm).
    pub transverse_module: f64,
    /// Transverse pressure angle α_t (rad).
    pub transverse_pressure_angle: f64,
    /// Base helix angle β_b (rad).
    pub base_helix_angle: f64,
    pub reference_radius: f64,
    pub base_radius: f64,
    pub tip_radius: f64,
    pub root_radius: f64,
    /// Form circle radius r_F (start of the involute).
    pub form_radius: f64,
    /// Transverse base pitch p_bt (mm).
    pub transverse_base_pitch: f64,
    /// Transverse / normal arc tooth thickness at the reference circle (mm).
    pub reference_thickness_transverse: f64,
    pub reference_thickness_normal: f64,
    /// Transverse / normal tip thickness (mm).
    pub tip_thickness_transverse: f64,
    pub tip_thickness_normal: f64,
    /// Undercut limit x_min.
    pub undercut_limit: f64,
    /// Number of teeth spanned k and span W_k (mm).
    pub span_teeth: u32,
    pub span: f64,
}

impl GearGeometry {
    /// Validate `g` and compute its figures; `name` (e.g. "pinion") goes into messages.
    ///
    /// Errors: non-finite or non-positive dimensions, fewer than 5 teeth, pressure
    /// angle outside (0°, 45°), helix angle outside [0°, 60°], a rack tip rounding that
    /// does not fit, undercut (x < x_min), pointed tip (s_an < 0.2 m_n), tip radius not
    /// above the form radius, bore ≥ root diameter.
    pub fn new(g: &GearSpec, name: &str) -> Result<Self> {
        validate(g, name)?;
        let err = |m: String| Err(FlankError::Model(format!("{name}: {m}")));
        let x_min = undercut_limit(g);
        if g.profile_shift < x_min - 1e-12 {
            return err(format!(
                "{} teeth with x = {} are undercut by the rack (x_min = h_fP* − ρ_fP*(1 − sin α_n) − z sin²α_t/(2 cos β) = {:.4}); a profile shift x ≥ {:.4} is needed",
                g.teeth, g.profile_shift, x_min, x_min
            ));
        }
        let rf_form = form_radius(g).map_err(|e| FlankError::Model(format!("{name}: {e}")))?;
        let ra = tip_radius(g);
        let rf = root_radius(g);
        if ra <= rf_form {
            return err(format!(
                "tip radius {ra:.4} mm is not above the form radius {rf_form:.4} mm: no involute is left; a larger tip diameter or profile shift is needed"
            ));
        }
        let sat = tip_thickness(g)?;
        let san = normal_tip_thickness(g)?;
        let mn = g.normal_module;
        if san < MIN_TIP_THICKNESS * mn {
            return err(format!(
                "pointed tip: normal tip thickness s_an = {san:.4} mm < {MIN_TIP_THICKNESS}·m_n = {:.4} mm; a smaller profile shift or tip diameter is needed",
                MIN_TIP_THICKNESS * mn
            ));
        }
        if g.bore_diameter >= 2.0 * rf {
            return err(format!(
                "bore diameter {} mm is not below the root diameter {:.4} mm",
                g.bore_diameter,
                2.0 * rf
            ));
        }
        let k = span_teeth(g);
        Ok(GearGeometry {
            teeth: g.teeth,
            profile_shift: g.profile_shift,
            transverse_module: transverse_module(g),
            transverse_pressure_angle: transverse_pressure_angle(g),
            base_helix_angle: base_helix_angle(g),
            reference_radius: reference_radius(g),
            base_radius: base_radius(g),
            tip_radius: ra,
            root_radius: rf,
            form_radius: rf_form,
            transverse_base_pitch: transverse_base_pitch(g),
            reference_thickness_transverse: reference_thickness(g),
            reference_thickness_normal: normal_reference_thickness(g),
            tip_thickness_transverse: sat,
            tip_thickness_normal: san,
            undercut_limit: x_min,
            span_teeth: k,
            span: span(g, k),
        })
    }
}

/// Input checks that need no derived figure (finite, positive, in range).
pub fn validate(g: &GearSpec, name: &str) -> Result<()> {
    let err = |m: String| Err(FlankError::Model(format!("{name}: {m}")));
    if g.teeth < 5 {
        return err(format!("{} teeth: at least 5 teeth are needed", g.teeth));
    }
    let pos = [
        ("normal module", g.normal_module),
        ("face width", g.face_width),
        ("rack addendum h_fP*", g.rack.addendum),
        ("rack dedendum h_aP*", g.rack.dedendum),
    ];
    for (what, v) in pos {
        if !(v.is_finite() && v > 0.0) {
            return err(format!("{what} = {v}: a finite positive value is needed"));
        }
    }
    let nonneg = [
        ("rack tip radius ρ_fP*", g.rack.tip_radius),
        ("bore diameter", g.bore_diameter),
        ("helix angle", g.helix_angle),
    ];
    for (what, v) in nonneg {
        if !(v.is_finite() && v >= 0.0) {
            return err(format!("{what} = {v}: a finite value ≥ 0 is needed"));
        }
    }
    if !g.profile_shift.is_finite() {
        return err(format!(
            "profile shift x = {}: a finite value is needed",
            g.profile_shift
        ));
    }
    let an = g.normal_pressure_angle;
    if !(an.is_finite() && an > 0.0 && an < PI / 4.0) {
        return err(format!(
            "normal pressure angle {:.4}° is outside (0°, 45°)",
            an.to_degrees()
        ));
    }
    if g.helix_angle > PI / 3.0 {
        return err(format!(
            "helix angle {:.4}° is above 60° (the hand gives the direction; β ∈ [0°, 60°] is needed)",
            g.helix_angle.to_degrees()
        ));
    }
    if let Some(d) = g.tip_diameter {
        if !(d.is_finite() && d > 0.0) {
            return err(format!(
                "tip diameter {d} mm: a finite positive value is needed"
            ));
        }
    }
    let rho_max = max_rack_tip_radius(g);
    if g.rack.tip_radius > rho_max {
        return err(format!(
            "rack tip radius ρ_fP* = {} does not fit the rack tooth tip (h_fP* = {}, α_n = {:.3}°): ρ_fP* ≤ {:.4} is needed",
            g.rack.tip_radius,
            g.rack.addendum,
            an.to_degrees(),
            rho_max
        ));
    }
    if root_radius(g) <= 0.0 {
        return err(format!(
            "root radius {:.4} mm is not positive",
            root_radius(g)
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::super::{Hand, RackProfile};
    use super::*;

    pub(crate) fn spur(z: u32, m: f64, x: f64) -> GearSpec {
        GearSpec {
            teeth: z,
            normal_module: m,
            normal_pressure_angle: 20f64.to_radians(),
            helix_angle: 0.0,
            hand: Hand::Right,
            face_width: 10.0,
            profile_shift: x,
            rack: RackProfile::default(),
            tip_diameter: None,
            bore_diameter: 0.0,
        }
    }

    /// ρ_max from the geometry of the rack tooth (s_P = π/2, symmetric about
    /// X = 0, flank X = π/4 − Y tan α, tip line Y = h_fP*): the rounding centred on
    /// the axis at (0, h − ρ) is at distance ρ from the flank; at 24.7° the limit is
    /// the 0.3285 that refused the 20° default, and the default now fits.
    #[test]
    fn rack_tip_radius_limit_is_the_full_root_radius() {
        for deg in [14.5, 20.0, 24.7, 28.0, 31.0] {
            let a = f64::to_radians(deg);
            for h in [1.0, 1.25, 1.4] {
                let rho = rack_tip_radius_limit(h, a);
                // distance of (0, h − ρ) from the line X + Y tan α − π/4 = 0
                let d = (PI / 4.0 - (h - rho) * a.tan()) * a.cos();
                assert!((d - rho).abs() < 1e-14, "{deg}° h {h}: {d} vs {rho}");
                let rho_d = default_rack_tip_radius(h, a);
                if rho > 0.0 {
                    assert!(rho_d <= ISO53_TIP_RADIUS && rho_d < rho, "{deg}° h {h}");
                } else {
                    assert_eq!(rho_d, 0.0, "{deg}° h {h}: the rack tooth is pointed");
                }
            }
        }
        let mut g = spur(20, 4.0, 0.5);
        g.normal_pressure_angle = 24.7f64.to_radians();
        let e = validate(&g, "pinion").unwrap_err().to_string();
        assert!(e.contains("ρ_fP* ≤ 0.3285"), "{e}");
        g.rack.tip_radius = default_rack_tip_radius(g.rack.addendum, g.normal_pressure_angle);
        validate(&g, "pinion").unwrap();
        assert_eq!(default_rack_tip_radius(1.25, 20f64.to_radians()), 0.38);
        // ISO 53 profile D (h_fP* = 1.4, ρ_fP* = 0.39) is 0.99 of its full radius
        let d = rack_tip_radius_limit(1.4, 20f64.to_radians());
        assert!(
            (0.39 / d - FULL_ROOT_RADIUS_SHARE).abs() < 0.002,
            "{}",
            0.39 / d
        );
    }

    #[test]
    fn involute_inverse_roundtrip() {
        for i in 0..=280 {
            let a = i as f64 * 0.005;
            let back = inv_inverse(inv(a)).unwrap();
            assert!((back - a).abs() < 1e-13, "{a} -> {back}");
        }
        assert!(inv_inverse(-1.0).is_err());
        assert!(inv_inverse(f64::NAN).is_err());
        assert!(inv_inverse(1e6).is_err());
    }

    /// Worked example: z = 20, m = 4, α = 20°, x = 0 spur (closed forms evaluated by hand).
    #[test]
    fn worked_example_spur_20_4() {
        let g = spur(20, 4.0, 0.0);
        let a = 20f64.to_radians();
        assert!((reference_radius(&g) - 40.0).abs() < 1e-12);
        assert!((base_radius(&g) - 40.0 * a.cos()).abs() < 1e-12);
        assert!((base_radius(&g) - 37.587704831).abs() < 1e-8);
        assert!((reference_thickness(&g) - 2.0 * PI).abs() < 1e-12);
        assert!((tip_radius(&g) - 44.0).abs() < 1e-12);
        assert!((root_radius(&g) - 35.0).abs() < 1e-12);
        assert!((transverse_base_pitch(&g) - 4.0 * PI * a.cos()).abs() < 1e-12);
        // inv 20° = 0.014904383867336
        assert!((inv(a) - 0.014904383867336).abs() < 1e-14);
        assert_eq!(span_teeth(&g), 3);
        // W_3 = 4 cos20° (2.5 π + 20 inv 20°) = 30.64176
        let w3 = 4.0 * a.cos() * (2.5 * PI + 20.0 * inv(a));
        assert!((span(&g, 3) - w3).abs() < 1e-12);
        assert!((w3 - 30.641757504).abs() < 1e-8, "W3 = {w3}");
        // undercut limit with ISO 53 rack: 1.25 − 0.38(1 − sin20°) − 10 sin²20°
        let xm = 1.25 - 0.38 * (1.0 - a.sin()) - 10.0 * a.sin().powi(2);
        assert!((undercut_limit(&g) - xm).abs() < 1e-12);
        let geo = GearGeometry::new(&g, "gear").unwrap();
        assert!(geo.form_radius > geo.base_radius && geo.form_radius < geo.reference_radius);
        // the involute's thickness at the reference circle is s_t
        assert!((thickness_at_radius(&g, 40.0).unwrap() - 2.0 * PI).abs() < 1e-12);
    }

    #[test]
    fn helical_transverse_quantities() {
        let mut g = spur(21, 15.0, 0.0);
        g.helix_angle = 20f64.to_radians();
        let b = g.helix_angle;
        let an = g.normal_pressure_angle;
        let at = transverse_pressure_angle(&g);
        assert!((at.tan() - an.tan() / b.cos()).abs() < 1e-14);
        // sin β_b = sin β cos α_n  ⇔  tan β_b = tan β cos α_t
        let bb = base_helix_angle(&g);
        assert!((bb.tan() - b.tan() * at.cos()).abs() < 1e-14);
        // p_bn = p_bt cos β_b
        assert!((normal_base_pitch(&g) - transverse_base_pitch(&g) * bb.cos()).abs() < 1e-12);
        assert!((reference_radius(&g) - 21.0 * 15.0 / (2.0 * b.cos())).abs() < 1e-12);
        // normal thickness at reference: π m_n / 2 for x = 0
        assert!((normal_reference_thickness(&g) - PI * 7.5).abs() < 1e-12);
        GearGeometry::new(&g, "pinion").unwrap();
    }

    #[test]
    fn bad_inputs_give_errors() {
        let mut g = spur(4, 4.0, 0.0);
        assert!(GearGeometry::new(&g, "p")
            .unwrap_err()
            .to_string()
            .contains("5 teeth"));
        g = spur(20, -1.0, 0.0);
        assert!(GearGeometry::new(&g, "p").is_err());
        g = spur(20, f64::NAN, 0.0);
        assert!(GearGeometry::new(&g, "p").is_err());
        g = spur(10, 4.0, 0.0);
        let e = GearGeometry::new(&g, "pinion").unwrap_err().to_string();
        assert!(e.contains("undercut") && e.contains("x ≥"), "{e}");
        g = spur(12, 4.0, 1.2);
        let e = GearGeometry::new(&g, "pinion").unwrap_err().to_string();
        assert!(e.contains("pointed tip"), "{e}");
        g = spur(20, 4.0, 0.0);
        g.bore_diameter = 70.0;
        let e = GearGeometry::new(&g, "gear").unwrap_err().to_string();
        assert!(e.contains("bore"), "{e}");
        g = spur(20, 4.0, 0.0);
        g.rack.tip_radius = 0.6;
        assert!(GearGeometry::new(&g, "gear")
            .unwrap_err()
            .to_string()
            .contains("ρ_fP*"));
    }
}
