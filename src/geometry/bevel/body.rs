//! A bevel or hypoid gear behind the gear-pair interface
//! ([`crate::geometry::gear_pair::GearBody`]): the generated flanks of one
//! tooth, turned to every tooth of the modelled sector, and the member's
//! blank (cones, bore).
//!
//! Own frame (shared with the generated surfaces): axis +z, origin at the
//! member's pitch-cone apex, +z from the apex toward the heel. In the axial
//! section a point at cone distance v along the pitch generatrix and at u
//! perpendicular to it (positive toward the tip) has
//! z = v cos δ − u sin δ, ρ = v sin δ + u cos δ (δ the pitch angle); the face
//! cone is u = h_a(v), the root cone u = −h_f(v), with
//! h_a(v) = h_am + (v − R_m) tan θ_a and h_f(v) = h_fm + (v − R_m) tan θ_f
//! (ISO 23509 clause 7.4: addendum and dedendum angles; zero for uniform
//! depth).

use std::f64::consts::PI;
use std::sync::Arc;

use super::MemberBlank;
use crate::error::{FlankError, Result};
use crate::geometry::gear_pair::{Blank, Flank, GearBody};
use crate::geometry::rotated::RotatedSurface;
use crate::geometry::surface::ToothSurface;
use crate::geometry::vec3::V3;

/// The cone lines of a member's axial section (module docs), from the
/// blank design's [`MemberBlank`] (ISO 23509 clauses 7.3, 7.4: the face and
/// root cones are the lines through the mean tip and root points at the
/// face and root angles δ_a, δ_f, whatever their apexes).
impl MemberBlank {
    /// h_a(v): addendum at cone distance v (θ_a = δ_a − δ).
    pub fn addendum(&self, v: f64) -> f64 {
        self.ham + (v - self.rm) * (self.delta_a - self.delta).tan()
    }

    /// h_f(v): dedendum at cone distance v (θ_f = δ − δ_f).
    pub fn dedendum(&self, v: f64) -> f64 {
        self.hfm + (v - self.rm) * (self.delta - self.delta_f).tan()
    }

    /// (z, ρ) of the axial-section point (u, v) (module docs).
    pub fn axial_point(&self, u: f64, v: f64) -> (f64, f64) {
        let (s, c) = self.delta.sin_cos();
        (v * c - u * s, v * s + u * c)
    }

    fn validate(&self, name: &str) -> Result<()> {
        let ok = self.delta > 0.0
            && self.delta < PI / 2.0
            && self.ri > 0.0
            && self.ri < self.rm
            && self.rm < self.re
            && self.ham.is_finite()
            && self.hfm > 0.0
            && self.addendum(self.ri) > -self.dedendum(self.ri)
            && self.addendum(self.re) > -self.dedendum(self.re);
        if ok {
            Ok(())
        } else {
            Err(FlankError::Model(format!(
                "{name}: inconsistent cones (0 < δ < 90°, 0 < R_i < R_m < R_e, positive depth): {self:?}"
            )))
        }
    }
}

/// Angle of a point about the member's axis, from +y toward +x (rad): the
/// placement angle of every bevel member's teeth (tooth 1 centred on +y).
pub fn angle_from_y(p: V3) -> f64 {
    p[0].atan2(p[1])
}

/// An angle difference wrapped into [−π, π).
pub fn wrap_angle(d: f64) -> f64 {
    (d + PI).rem_euclid(2.0 * PI) - PI
}

/// Component of the unit normal `n` at `p` along growing [`angle_from_y`]:
/// > 0 when the flank faces that way.
pub fn facing(p: V3, n: V3) -> f64 {
    (n[0] * p[1] - n[1] * p[0]) / p[0].hypot(p[1])
}

/// A bevel/hypoid member as a sector of teeth (module docs).
#[derive(Clone, Debug)]
pub struct BevelGear {
    name: String,
    teeth: u32,
    cones: MemberBlank,
    bore_radius: f64,
    /// Flanks of sector teeth 1..=n: [left, right].
    flanks: [Vec<RotatedSurface>; 2],
}

impl BevelGear {
    /// `left` and `right` are the flanks of sector tooth 1; tooth k is
    /// tooth 1 turned by −(k − 1)·2π/z (the cylindrical gears' numbering).
    pub fn new(
        name: &str,
        teeth: u32,
        sector_teeth: usize,
        left: Arc<dyn ToothSurface>,
        right: Arc<dyn ToothSurface>,
        cones: MemberBlank,
        bore_radius: f64,
    ) -> Result<Self> {
        cones.validate(name)?;
        if teeth < 2 || sector_teeth < 1 || sector_teeth > teeth as usize {
            return Err(FlankError::Model(format!(
                "{name}: a sector of {sector_teeth} teeth of a gear of {teeth} teeth"
            )));
        }
        let toe_root = cones.axial_point(-cones.dedendum(cones.ri), cones.ri).1;
        if !(bore_radius > 0.0 && bore_radius < toe_root) {
            return Err(FlankError::Model(format!(
                "{name}: bore radius {bore_radius} mm must be positive and below the root cone at the toe ({toe_root:.3} mm)"
            )));
        }
        let pitch = 2.0 * PI / teeth as f64;
        let turned = |s: &Arc<dyn ToothSurface>| -> Vec<RotatedSurface> {
            (0..sector_teeth)
                .map(|k| RotatedSurface::new(s.clone(), -(k as f64) * pitch))
                .collect()
        };
        Ok(BevelGear {
            name: name.to_string(),
            teeth,
            cones,
            bore_radius,
            flanks: [turned(&left), turned(&right)],
        })
    }

    pub fn cones(&self) -> &MemberBlank {
        &self.cones
    }

    /// Checks that the two flanks of tooth 1 bound a tooth over the whole
    /// face (issue 16 point 5: pointed teeth, teeth that leave no space):
    /// at `TOOTH_CHECKS` cone distances from toe to heel, the flank whose
    /// outward normal points to growing angle θ about the axis must lie at
    /// the larger θ (the tooth's material between them), the angular
    /// thickness Δθ at the face cone must be positive (else the tooth is
    /// pointed: its flanks cross below the tip) and the space 2π/z − Δθ at
    /// the form line positive (else neighbouring teeth overlap). Returns
    /// the least top land ρ Δθ (mm) and its cone distance.
    pub fn check_tooth(&self) -> Result<(f64, f64)> {
        let (l, r) = (&self.flanks[0][0], &self.flanks[1][0]);
        let pitch = 2.0 * PI / self.teeth as f64;
        let c = &self.cones;
        let (pl, nl) = (l.point(0.0, c.rm), l.normal(0.0, c.rm));
        let (pr, nr) = (r.point(0.0, c.rm), r.normal(0.0, c.rm));
        let (sl, sr) = (facing(pl, nl), facing(pr, nr));
        if sl * sr >= 0.0 {
            return Err(FlankError::Model(format!(
                "{}: the left and right flanks face the same way at the mean point: they bound no tooth",
                self.name
            )));
        }
        // (flank facing +θ, flank facing −θ)
        let (a, b) = if sl > 0.0 { (l, r) } else { (r, l) };
        let mut least = (f64::INFINITY, c.rm);
        for k in 0..TOOTH_CHECKS {
            let v = c.ri + (c.re - c.ri) * k as f64 / (TOOTH_CHECKS - 1) as f64;
            let thickness = |u: f64| {
                let (pa, pb) = (a.point(u, v), b.point(u, v));
                wrap_angle(angle_from_y(pa) - angle_from_y(pb))
            };
            let ut = a.u_tip(v).min(b.u_tip(v));
            let tip = thickness(ut);
            let rho = c.axial_point(ut, v).1;
            if !(tip > 0.0) {
                return Err(FlankError::Model(format!(
                    "{}: pointed tooth: the flanks cross below the face cone at cone distance {v:.3} mm (angular thickness at the tip {:.4}°)",
                    self.name,
                    tip.to_degrees()
                )));
            }
            if rho * tip < least.0 {
                least = (rho * tip, v);
            }
            let uf = a.u_form(v).max(b.u_form(v));
            let space = pitch - thickness(uf);
            if !(space > 0.0) {
                return Err(FlankError::Model(format!(
                    "{}: no space between the teeth at the form line at cone distance {v:.3} mm (angular space {:.4}°): the tooth is thicker than the pitch",
                    self.name,
                    space.to_degrees()
                )));
            }
        }
        Ok(least)
    }
}

impl BevelGear {
    /// Mean normal circular thickness measured on the flanks: the arc
    /// ρ_m Δθ between tooth 1's two flanks on the pitch cone at the mean
    /// cone distance (u = 0, v = R_m: both points lie on one circle of the
    /// pitch cone), times cos β_m — ISO 23509 clause 7.8's s_mn, whose
    /// transverse arc is s_mt = s_mn / cos β_m (mm).
    pub fn mean_normal_thickness(&self) -> f64 {
        let c = &self.cones;
        let (l, r) = (&self.flanks[0][0], &self.flanks[1][0]);
        let (pl, pr) = (l.point(0.0, c.rm), r.point(0.0, c.rm));
        let d = wrap_angle(angle_from_y(pl) - angle_from_y(pr)).abs();
        let rho = c.axial_point(0.0, c.rm).1;
        rho * d * c.beta_m.cos()
    }
}

/// Cone distances of [`BevelGear::check_tooth`] from toe to heel.
const TOOTH_CHECKS: usize = 9;

impl GearBody for BevelGear {
    fn name(&self) -> &str {
        &self.name
    }
    fn teeth(&self) -> u32 {
        self.teeth
    }
    fn sector_teeth(&self) -> usize {
        self.flanks[0].len()
    }
    fn angular_pitch(&self) -> f64 {
        2.0 * PI / self.teeth as f64
    }
    fn flank(&self, side: Flank, tooth: usize) -> Option<&dyn ToothSurface> {
        let k = match side {
            Flank::Left => 0,
            Flank::Right => 1,
        };
        if tooth == 0 {
            return None;
        }
        self.flanks[k]
            .get(tooth - 1)
            .map(|s| s as &dyn ToothSurface)
    }
    fn blank(&self) -> Blank {
        let c = &self.cones;
        let (ri, rm, re) = (c.ri, c.rm, c.re);
        let z: Vec<f64> = [
            c.axial_point(c.addendum(ri), ri),
            c.axial_point(-c.dedendum(ri), ri),
            c.axial_point(c.addendum(re), re),
            c.axial_point(-c.dedendum(re), re),
        ]
        .iter()
        .map(|p| p.0)
        .collect();
        Blank {
            bore_radius: self.bore_radius,
            root_radius: c.axial_point(-c.dedendum(rm), rm).1,
            tip_radius: c.axial_point(c.addendum(rm), rm).1,
            axial_range: (
                z.iter().cloned().fold(f64::INFINITY, f64::min),
                z.iter().cloned().fold(f64::NEG_INFINITY, f64::max),
            ),
        }
    }
    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::deviation::tests::Torus;

    fn cones() -> MemberBlank {
        let d = 70f64.to_radians();
        MemberBlank {
            z: 41.0,
            rm: 95.0,
            re: 110.0,
            ri: 80.0,
            b: 30.0,
            be: 15.0,
            bi: 15.0,
            delta: d,
            delta_a: d + 0.02,
            delta_f: d - 0.06,
            beta_m: 0.5,
            ham: 1.8,
            hfm: 6.7,
            smn: 4.0,
        }
    }

    #[test]
    fn sector_teeth_are_turned_copies_and_the_blank_follows_the_cones() {
        let g = BevelGear::new(
            "gear",
            41,
            3,
            Arc::new(Torus),
            Arc::new(Torus),
            cones(),
            40.0,
        )
        .unwrap();
        assert_eq!(g.sector_teeth(), 3);
        assert!(g.flank(Flank::Right, 0).is_none() && g.flank(Flank::Right, 4).is_none());
        let p1 = g.flank(Flank::Right, 1).unwrap().point(0.1, 0.1);
        let p3 = g.flank(Flank::Right, 3).unwrap().point(0.1, 0.1);
        let turn = p3[1].atan2(p3[0]) - p1[1].atan2(p1[0]);
        assert!((turn + 2.0 * g.angular_pitch()).abs() < 1e-12);
        let b = g.blank();
        let c = cones();
        let (s, co) = c.delta.sin_cos();
        assert!((b.root_radius - (95.0 * s - 6.7 * co)).abs() < 1e-12);
        assert!((b.tip_radius - (95.0 * s + 1.8 * co)).abs() < 1e-12);
        assert!(b.axial_range.0 < 80.0 * co && b.axial_range.1 > 110.0 * co);
        // A bore that cuts the root cone, or nonsense cones, are refused.
        assert!(BevelGear::new(
            "gear",
            41,
            3,
            Arc::new(Torus),
            Arc::new(Torus),
            cones(),
            80.0
        )
        .is_err());
        let mut bad = cones();
        bad.ri = 100.0;
        assert!(
            BevelGear::new("gear", 41, 3, Arc::new(Torus), Arc::new(Torus), bad, 40.0).is_err()
        );
    }
}
