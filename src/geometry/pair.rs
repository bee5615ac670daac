//! Relations of an external cylindrical gear pair (ISO 21771:2007 "gear pairs";
//! Niemann–Winter vol. II, gear pairs with profile shift): working pressure angle, the shift sum a centre
//! distance needs, contact and overlap ratios, clearances, interference.

use super::involute::{inv, inv_inverse, GearGeometry};
use super::PairSpec;
use crate::error::FlankError;
use std::f64::consts::PI;

type Result<T> = std::result::Result<T, FlankError>;

/// Tolerance on the shift sum Σx (module units) between the spec and the centre distance.
pub const SHIFT_SUM_TOL: f64 = 1e-6;

/// Per-gear figures in a [`PairReport`] (mm, rad).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct PairGearReport {
    #[serde(flatten)]
    pub geometry: GearGeometry,
    /// Start of the active profile: radius where the mating tip meets this flank (mm).
    pub active_start_radius: f64,
    /// Radial clearance between this gear's root and the mating tip, c = a − r_a,mate − r_f (mm).
    pub root_clearance: f64,
}

/// Figures of a checked pair.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct PairReport {
    pub centre_distance: f64,
    /// Reference centre distance a_0 = (r_1 + r_2) (mm).
    pub reference_centre_distance: f64,
    /// Working transverse pressure angle α_wt.
    pub working_pressure_angle_rad: f64,
    pub working_pressure_angle_deg: f64,
    /// Shift sum x_1 + x_2.
    pub shift_sum: f64,
    /// Transverse base pitch p_bt (mm).
    pub transverse_base_pitch: f64,
    /// Length of path of contact g_α (mm).
    pub path_of_contact: f64,
    /// Transverse contact ratio ε_α, overlap ratio ε_β, total ε_γ = ε_α + ε_β.
    pub contact_ratio: f64,
    pub overlap_ratio: f64,
    pub total_contact_ratio: f64,
    pub pinion: PairGearReport,
    pub gear: PairGearReport,
}

/// Working transverse pressure angle from the centre distance:
/// cos α_wt = (r_b1 + r_b2) / a (ISO 21771:2007).
pub fn working_pressure_angle(spec: &PairSpec) -> Result<f64> {
    let rb = super::involute::base_radius(&spec.pinion) + super::involute::base_radius(&spec.gear);
    let a = spec.centre_distance;
    if !(a.is_finite() && a > 0.0) {
        return Err(FlankError::Model(format!(
            "centre distance {a} mm: a finite positive value is needed"
        )));
    }
    let c = rb / a;
    if c >= 1.0 {
        return Err(FlankError::Model(format!(
            "centre distance {a} mm is not above the sum of the base radii {rb:.4} mm: the base circles overlap"
        )));
    }
    Ok(c.acos())
}

/// Shift sum a centre distance needs (zero backlash), from
/// inv α_wt = inv α_t + 2 (x_1 + x_2) tan α_n / (z_1 + z_2) (ISO 21771:2007).
pub fn shift_sum_for_centre_distance(spec: &PairSpec) -> Result<f64> {
    let awt = working_pressure_angle(spec)?;
    let g = &spec.pinion;
    let zs = (spec.pinion.teeth + spec.gear.teeth) as f64;
    let at = super::involute::transverse_pressure_angle(g);
    Ok((inv(awt) - inv(at)) * zs / (2.0 * g.normal_pressure_angle.tan()))
}

/// Centre distance the spec's shifts give (zero backlash): a = (r_b1 + r_b2) / cos α_wt,
/// α_wt = inv⁻¹(inv α_t + 2 Σx tan α_n / (z_1 + z_2)) (ISO 21771:2007).
pub fn centre_distance_for_shifts(spec: &PairSpec) -> Result<f64> {
    let g = &spec.pinion;
    let zs = (spec.pinion.teeth + spec.gear.teeth) as f64;
    let at = super::involute::transverse_pressure_angle(g);
    let xs = spec.pinion.profile_shift + spec.gear.profile_shift;
    let awt = inv_inverse(inv(at) + 2.0 * xs * g.normal_pressure_angle.tan() / zs)?;
    let rb = super::involute::base_radius(&spec.pinion) + super::involute::base_radius(&spec.gear);
    Ok(rb / awt.cos())
}

fn same(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * a.abs().max(b.abs()).max(1e-300)
}

/// Check that the gears mesh: same normal module, pressure angle and helix angle,
/// opposite hands (helical), the centre distance consistent with the shifts.
fn check_compatible(spec: &PairSpec) -> Result<()> {
    let (p, g) = (&spec.pinion, &spec.gear);
    let err = |m: String| Err(FlankError::Model(m));
    if !same(p.normal_module, g.normal_module) {
        return err(format!(
            "pinion normal module {} mm ≠ gear normal module {} mm: a pair needs the same module",
            p.normal_module, g.normal_module
        ));
    }
    if !same(p.normal_pressure_angle, g.normal_pressure_angle) {
        return err(format!(
            "pinion normal pressure angle {:.6}° ≠ gear {:.6}°: a pair needs the same pressure angle",
            p.normal_pressure_angle.to_degrees(),
            g.normal_pressure_angle.to_degrees()
        ));
    }
    if (p.helix_angle - g.helix_angle).abs() > 1e-9 {
        return err(format!(
            "pinion helix angle {:.6}° ≠ gear {:.6}°: an external parallel-axis pair needs equal helix angles",
            p.helix_angle.to_degrees(),
            g.helix_angle.to_degrees()
        ));
    }
    if p.helix_angle > 0.0 && p.hand == g.hand {
        return err(format!(
            "both gears are {:?}-handed: an external helical pair needs opposite hands",
            p.hand
        ));
    }
    Ok(())
}

/// Check an external pair and compute its figures (ISO 21771:2007; Niemann–Winter vol. II).
///
/// Errors (`FlankError::Model`, naming the figure and what is needed): invalid or
/// incompatible gears (see [`GearGeometry::new`]), a centre distance that does not
/// match the shift sum, ε_α < 1, negative tip/root clearance, interference (a mating
/// tip reaching below the form circle).
pub fn check_pair(spec: &PairSpec) -> Result<PairReport> {
    super::involute::validate(&spec.pinion, "pinion")?;
    super::involute::validate(&spec.gear, "gear")?;
    check_compatible(spec)?;
    let a = spec.centre_distance;
    let awt = working_pressure_angle(spec)?;
    let xs_needed = shift_sum_for_centre_distance(spec)?;
    let xs = spec.pinion.profile_shift + spec.gear.profile_shift;
    if (xs - xs_needed).abs() > SHIFT_SUM_TOL {
        let a_given = centre_distance_for_shifts(spec)
            .map(|v| format!("{v:.4} mm"))
            .unwrap_or_else(|_| "none (shift sum out of range)".into());
        let a0 = super::involute::reference_radius(&spec.pinion)
            + super::involute::reference_radius(&spec.gear);
        return Err(FlankError::Model(format!(
            "centre distance {a} mm does not match the profile shifts: it implies a working pressure angle α_wt = {:.4}° and needs a shift sum x1 + x2 = {xs_needed:.6} (reference centre distance {a0:.4} mm); the given shifts {} + {} = {xs:.6} give a centre distance of {a_given}",
            awt.to_degrees(),
            spec.pinion.profile_shift,
            spec.gear.profile_shift
        )));
    }
    let p = GearGeometry::new(&spec.pinion, "pinion")?;
    let g = GearGeometry::new(&spec.gear, "gear")?;

    // Path of contact along the line of action T1T2 (length a sin α_wt).
    let t1t2 = a * awt.sin();
    let ga1 = (p.tip_radius.powi(2) - p.base_radius.powi(2)).sqrt(); // T1 → tip of pinion
    let ga2 = (g.tip_radius.powi(2) - g.base_radius.powi(2)).sqrt(); // T2 → tip of gear
    let path = ga1 + ga2 - t1t2;
    let pbt = p.transverse_base_pitch;
    let eps_a = path / pbt;
    let b = spec.pinion.face_width.min(spec.gear.face_width);
    let eps_b = b * spec.pinion.helix_angle.sin() / (PI * spec.pinion.normal_module);

    // Clearances: c = a − r_a(mate) − r_f.
    let c_pinion_root = a - g.tip_radius - p.root_radius;
    let c_gear_root = a - p.tip_radius - g.root_radius;
    for (who, c, tip, root) in [
        (
            "gear tip to pinion root",
            c_pinion_root,
            g.tip_radius,
            p.root_radius,
        ),
        (
            "pinion tip to gear root",
            c_gear_root,
            p.tip_radius,
            g.root_radius,
        ),
    ] {
        if c < 0.0 {
            return Err(FlankError::Model(format!(
                "negative clearance {who}: c = a − r_a − r_f = {a} − {tip:.4} − {root:.4} = {c:.4} mm; a smaller tip diameter (tip shortening ≥ {:.4} mm in radius) is needed",
                -c
            )));
        }
    }

    // Interference: the mating tip meets this flank at roll length T_i → point = a sin α_wt − g_a(mate);
    // it must lie on the involute, i.e. not below the form circle.
    let start1 = t1t2 - ga2;
    let start2 = t1t2 - ga1;
    let mut active = [0.0; 2];
    for (i, (who, start, geo)) in [("pinion", start1, &p), ("gear", start2, &g)]
        .into_iter()
        .enumerate()
    {
        let gf = (geo.form_radius.powi(2) - geo.base_radius.powi(2)).sqrt();
        let r_start = geo.base_radius.hypot(start);
        if start < gf - 1e-9 * geo.base_radius {
            let other = if who == "pinion" { "gear" } else { "pinion" };
            let where_ = if start < 0.0 {
                format!(
                    "beyond the interference point T of the line of action by {:.4} mm",
                    -start
                )
            } else {
                format!("at radius {r_start:.4} mm")
            };
            return Err(FlankError::Model(format!(
                "interference: the {other} tip meets the {who} flank {where_}, below the {who} form radius {:.4} mm (into the root fillet); a smaller {other} tip diameter or a larger {who} profile shift is needed",
                geo.form_radius
            )));
        }
        active[i] = r_start;
    }

    if eps_a < 1.0 {
        return Err(FlankError::Model(format!(
            "transverse contact ratio ε_α = {eps_a:.4} < 1: the path of contact {path:.4} mm is shorter than the base pitch {pbt:.4} mm; larger tip diameters or a smaller working pressure angle are needed"
        )));
    }
    Ok(PairReport {
        centre_distance: a,
        reference_centre_distance: p.reference_radius + g.reference_radius,
        working_pressure_angle_rad: awt,
        working_pressure_angle_deg: awt.to_degrees(),
        shift_sum: xs,
        transverse_base_pitch: pbt,
        path_of_contact: path,
        contact_ratio: eps_a,
        overlap_ratio: eps_b,
        total_contact_ratio: eps_a + eps_b,
        pinion: PairGearReport {
            geometry: p,
            active_start_radius: active[0],
            root_clearance: c_pinion_root,
        },
        gear: PairGearReport {
            geometry: g,
            active_start_radius: active[1],
            root_clearance: c_gear_root,
        },
    })
}

/// Convenience: the gears' spec pair with the gear's shift chosen so the centre
/// distance is met (x_2 = Σx_needed − x_1); used to build consistent examples.
pub fn with_gear_shift_for_centre_distance(spec: &PairSpec) -> Result<PairSpec> {
    let xs = shift_sum_for_centre_distance(spec)?;
    let mut out = spec.clone();
    out.gear.profile_shift = xs - spec.pinion.profile_shift;
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::super::{GearSpec, Hand, RackProfile};
    use super::*;

    fn gear(z: u32, m: f64, x: f64, beta_deg: f64, hand: Hand, b: f64) -> GearSpec {
        GearSpec {
            teeth: z,
            normal_module: m,
            normal_pressure_angle: 20f64.to_radians(),
            helix_angle: beta_deg.to_radians(),
            hand,
            face_width: b,
            profile_shift: x,
            rack: RackProfile::default(),
            tip_diameter: None,
            bore_diameter: 0.0,
        }
    }

    /// Seed 002 pair 13/35, m = 3.8, a = 90 mm, α = 20°: a_0 = 91.2 mm, so the
    /// centre distance needs a negative shift sum.
    #[test]
    fn seed_13_35_needs_negative_shift_sum() {
        let spec = PairSpec {
            pinion: gear(13, 3.8, 0.0, 0.0, Hand::Right, 13.3),
            gear: gear(35, 3.8, 0.0, 0.0, Hand::Right, 13.3),
            centre_distance: 90.0,
        };
        let a = 20f64.to_radians();
        let awt = (91.2 * a.cos() / 90.0).acos();
        let xs = (inv(awt) - inv(a)) * 48.0 / (2.0 * a.tan());
        let got = shift_sum_for_centre_distance(&spec).unwrap();
        assert!((got - xs).abs() < 1e-12);
        assert!((xs + 0.299317443).abs() < 1e-8, "Σx = {xs}");
        let e = check_pair(&spec).unwrap_err().to_string();
        println!("{e}");
        assert!(e.contains(&format!("{xs:.6}")), "{e}");
        assert!(e.contains(&format!("{:.4}°", awt.to_degrees())), "{e}");
        assert!(e.contains("91.2000 mm"), "{e}");
        // With x1 = 0.25 (just above the pinion's x_min = 0.2396) and x2 = Σx − x1 it
        // meshes; x1 ≥ 0.3 lets the gear tip reach the pinion fillet (interference).
        let mut ok = spec.clone();
        ok.pinion.profile_shift = 0.25;
        let ok = with_gear_shift_for_centre_distance(&ok).unwrap();
        let r = check_pair(&ok).unwrap();
        println!("{}", serde_json::to_string_pretty(&r).unwrap());
        assert!((r.working_pressure_angle_rad - awt).abs() < 1e-12);
        assert!((centre_distance_for_shifts(&ok).unwrap() - 90.0).abs() < 1e-9);
        assert!(
            (r.contact_ratio - 1.6036532046).abs() < 1e-8,
            "{}",
            r.contact_ratio
        );
        assert!(r.overlap_ratio == 0.0);
        let mut worse = ok.clone();
        worse.pinion.profile_shift = 0.3;
        let worse = with_gear_shift_for_centre_distance(&worse).unwrap();
        let e = check_pair(&worse).unwrap_err().to_string();
        assert!(e.contains("interference"), "{e}");
        assert!(r.pinion.root_clearance > 0.0 && r.gear.root_clearance > 0.0);
        // same hand on a spur pair is fine; a = r_b1 + r_b2 is refused.
        let mut bad = ok.clone();
        bad.centre_distance = 0.5 * 48.0 * 3.8 * a.cos();
        assert!(check_pair(&bad).is_err());
    }

    /// A standard-consistent choice for seed 002 (a = 90 mm, ε_α near 1.45–1.51):
    /// x1 = 0.25, x2 = Σx − x1 = −0.549317, gear tip shortened to d_a2 = 135.5 mm.
    #[test]
    fn seed_13_35_candidate_with_shortened_gear_tip() {
        let mut spec = PairSpec {
            pinion: gear(13, 3.8, 0.25, 0.0, Hand::Right, 13.3),
            gear: gear(35, 3.8, 0.0, 0.0, Hand::Right, 13.3),
            centre_distance: 90.0,
        };
        spec = with_gear_shift_for_centre_distance(&spec).unwrap();
        spec.gear.tip_diameter = Some(135.5);
        let r = check_pair(&spec).unwrap();
        println!("{}", serde_json::to_string_pretty(&r).unwrap());
        // ε_α = (√(r_a1² − r_b1²) + √(r_a2² − r_b2²) − a sin α_wt) / p_bt
        let a = 20f64.to_radians();
        let awt = (91.2 * a.cos() / 90.0).acos();
        let (rb1, rb2) = (24.7 * a.cos(), 66.5 * a.cos());
        let e = ((29.45f64.powi(2) - rb1 * rb1).sqrt() + (67.75f64.powi(2) - rb2 * rb2).sqrt()
            - 90.0 * awt.sin())
            / (PI * 3.8 * a.cos());
        assert!((r.contact_ratio - e).abs() < 1e-12);
        assert!(
            (r.contact_ratio - 1.4989).abs() < 1e-4,
            "{}",
            r.contact_ratio
        );
        assert!(r.pinion.active_start_radius > r.pinion.geometry.form_radius + 0.03);
    }

    /// Reference pair 20/20 (a_0), closed-form contact ratio.
    #[test]
    fn spur_contact_ratio_closed_form() {
        let spec = PairSpec {
            pinion: gear(20, 4.0, 0.0, 0.0, Hand::Right, 10.0),
            gear: gear(40, 4.0, 0.0, 0.0, Hand::Right, 12.0),
            centre_distance: 120.0,
        };
        let r = check_pair(&spec).unwrap();
        let a = 20f64.to_radians();
        let (rb1, rb2) = (40.0 * a.cos(), 80.0 * a.cos());
        let e = ((44f64.powi(2) - rb1 * rb1).sqrt() + (84f64.powi(2) - rb2 * rb2).sqrt()
            - 120.0 * a.sin())
            / (4.0 * PI * a.cos());
        assert!((r.contact_ratio - e).abs() < 1e-12);
        assert!((r.working_pressure_angle_deg - 20.0).abs() < 1e-9);
        assert!((r.pinion.root_clearance - 1.0).abs() < 1e-12); // c = 0.25 m
        assert!((r.total_contact_ratio - r.contact_ratio).abs() < 1e-15);
        serde_json::to_string(&r).unwrap();
    }

    /// Seed 004 helical pair 21/37, m_n = 15, α_n = 20°, β = 20°, b = 180 mm, x = 0.
    #[test]
    fn seed_helical_21_37() {
        let mut spec = PairSpec {
            pinion: gear(21, 15.0, 0.0, 20.0, Hand::Right, 180.0),
            gear: gear(37, 15.0, 0.0, 20.0, Hand::Left, 180.0),
            centre_distance: 0.0,
        };
        let b = 20f64.to_radians();
        spec.centre_distance = 58.0 * 15.0 / (2.0 * b.cos());
        let r = check_pair(&spec).unwrap();
        println!("{}", serde_json::to_string_pretty(&r).unwrap());
        let at = (20f64.to_radians().tan() / b.cos()).atan();
        assert!((r.working_pressure_angle_rad - at).abs() < 1e-9);
        assert!((r.overlap_ratio - 180.0 * b.sin() / (PI * 15.0)).abs() < 1e-12);
        assert!(
            r.contact_ratio > 1.4 && r.contact_ratio < 1.7,
            "{}",
            r.contact_ratio
        );
        // same hand refused
        let mut bad = spec.clone();
        bad.gear.hand = Hand::Right;
        assert!(check_pair(&bad)
            .unwrap_err()
            .to_string()
            .contains("opposite hands"));
        // mismatched module refused
        let mut bad = spec.clone();
        bad.gear.normal_module = 14.0;
        assert!(check_pair(&bad)
            .unwrap_err()
            .to_string()
            .contains("same module"));
    }

    #[test]
    fn pair_errors() {
        // too-large tips: negative clearance
        let mut spec = PairSpec {
            pinion: gear(20, 4.0, 0.0, 0.0, Hand::Right, 10.0),
            gear: gear(40, 4.0, 0.0, 0.0, Hand::Right, 10.0),
            centre_distance: 120.0,
        };
        spec.pinion.tip_diameter = Some(2.0 * 45.5);
        let e = check_pair(&spec).unwrap_err().to_string();
        assert!(e.contains("clearance") || e.contains("interference"), "{e}");
        // short tips: contact ratio < 1
        spec.pinion.tip_diameter = Some(2.0 * 40.5);
        spec.gear.tip_diameter = Some(2.0 * 80.5);
        let e = check_pair(&spec).unwrap_err().to_string();
        assert!(e.contains("ε_α"), "{e}");
        // interference: big gear tip into a small pinion's fillet
        let spec = PairSpec {
            pinion: gear(18, 4.0, 0.0, 0.0, Hand::Right, 10.0),
            gear: GearSpec {
                tip_diameter: Some(2.0 * 204.8),
                ..gear(100, 4.0, 0.0, 0.0, Hand::Right, 10.0)
            },
            centre_distance: 236.0,
        };
        let e = check_pair(&spec).unwrap_err().to_string();
        assert!(
            e.contains("interference") && e.contains("pinion form radius"),
            "{e}"
        );
    }
}
