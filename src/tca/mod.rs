//! Unloaded tooth contact analysis (TCA) of a gear pair given through the
//! gear-pair interface ([`LineContactPair`]): the geometric input of the
//! compliance-matrix LTCA.
//!
//! At a roll angle the TCA takes the pair's kinematic contact lines
//! ([`LineContactPair::contact_lines`]: the tooth pairs in mesh, each line as a
//! parameter range with seeds), samples each line with points, and gives
//! per point the flank parameters of both bodies (where the LTCA
//! interpolates the compliance tensors), the initial normal separation w
//! (micro-geometry, misalignment), the moment arm r of the pinion rotation,
//! the share of line length the point stands for, the surface velocities
//! and the curvature of both flanks across the line. Those are the w, r of
//! the LTCA's compatibility F p + w = θ r + d (seed `000_…`; seed `004_…`
//! §3.2).
//!
//! Methods: each sample point X₀ of a kinematic line (for spur and helical
//! pairs the closed-form line in the plane of action,
//! [`crate::geometry::cylindrical`]) is put through the real (modified,
//! misplaced) surfaces as in seed `004_…` §3.1: the normal line through X₀
//! is intersected with the pinion flank (M₁), and the line through M₁ along
//! the pinion's normal there with the gear flank (M₂); w is the signed
//! distance from M₁ to M₂ along the normal. Both intersections are Newton
//! iterations in (u, v, t) started from the pair's seeds (exact for
//! unmodified aligned flanks), so a position costs microseconds per point
//! (Litvin & Fuentes, *Gear Geometry and Applied Theory*, 2nd ed. 2004, TCA
//! by the tangency of surfaces; here the separation topology around the
//! contact line, as LTCA needs it). Nothing here depends on the gear type:
//! `verification/gear_pair_interface` runs it on a plane against a pin.
//!
//! # Conventions
//!
//! * **Global frame and roll angle** are the pair's ([`GearPair::frames`](crate::geometry::gear_pair::GearPair::frames));
//!   for spur and helical pairs: pinion axis = z axis, gear axis at (0, a);
//!   θ = pinion rotation in the drive direction (clockwise seen from +z), 0
//!   when the middle pair's kinematic contact is at the pitch point. The
//!   loaded flanks are the right flanks ([`Flank::Right`]) of both bodies;
//!   pinion sector tooth k meets gear tooth [`GearPair::mate`](crate::geometry::gear_pair::GearPair::mate)`(k)`.
//! * **Flank parameters** (u, v): those of each body's [`ToothSurface`] in
//!   its own (sector) frame (spur/helical: u the involute roll angle, v the
//!   body's own z in mm).
//! * **Normals** are unit vectors outward from the pinion flank (pointing
//!   from the pinion into the gear).
//! * **Separation** w (mm) > 0: a gap (the gear surface lies beyond the
//!   pinion surface along the normal); < 0: overlap (interference).
//! * **Moment arm** r = (ω̂₁ × (x − o₁))·n (mm), ω̂₁ the pinion's unit
//!   angular velocity for a drive rotation and o₁ its axis point: the normal
//!   approach of the pinion surface point x per unit pinion rotation,
//!   r_b1 cos β_b on an ideal involute contact line. Rotating the pinion by
//!   θ closes w by θ r.
//! * **Unloaded transmission error** θ₀ = min_i w_i / r_i (rad): the pinion
//!   rotation in the drive direction that brings the closest point into
//!   contact (> 0: the flanks are apart, the gear lags its ideal position;
//!   < 0: they overlap).
//! * **Misalignment** is the pair's ([`GearPair::misalignment`](crate::geometry::gear_pair::GearPair::misalignment)); spur and
//!   helical pairs take it as tilts in and normal to the plane of action
//!   and a centre-distance error
//!   ([`crate::geometry::cylindrical::CylindricalPair::with_plane_of_action_misalignment`], whose docs
//!   give the ISO 6336-1 f_Σβ / f_Σδ correspondence), or as the bevel
//!   set ΔE, ΔP, ΔG, ΔΣ ([`crate::geometry::cylindrical::CylindricalPair::with_misalignment`]).
//! * **Velocities** (m/s, from the pinion speed; the gear turns at
//!   ω₂ = ω₁ [`GearPair::ratio`](crate::geometry::gear_pair::GearPair::ratio)): v_ti = V_ti·e_roll, the tangential
//!   surface velocity of body i (seed `004_…` §2.2: V_ti = v_i − (v_i·n) n,
//!   v_i = ω_i × r_i) along the rolling direction e_roll = (n × a₁)/|n × a₁|
//!   (a₁ the pinion axis; across the contact line of a parallel-axis pair,
//!   in the tangent plane; e_roll·v_t1 > 0 on the active path).
//!   `sliding_velocity` v_s = v_t1 − v_t2 (seed 004's v_c, signed: > 0 where
//!   the pinion surface is the faster, in the recess beyond the pitch point
//!   for a driving pinion); `rolling_velocity` = the entraining speed
//!   u = (v_t1 + v_t2)/2 of seed `002_…` eq. 9; `sum_velocity` = v_t1 + v_t2.
//! * **Curvature**: `curvature_radius` = the radii of the two flanks (pinion,
//!   gear) in the normal section along e_roll, positive when convex (for an
//!   involute helicoid ρ_n = ρ_t / cos β_b with ρ_t the distance to the
//!   base tangent point), by a central difference of the normal over
//!   ±1e-3 mm. `equivalent_radius_mm` = ρ₁ρ₂/(ρ₁ + ρ₂) (seed `002_…`
//!   eqs. 6–7, in the normal plane).
//!
//! Flank points are sampled inside the kinematic path; with misplacement
//! or modifications the normal line may meet a mating flank a few µm beyond
//! its tip, where the involute is continued (the surfaces of
//! [`crate::geometry::flank::FlankSurface`] are defined there).
//!
//! # Corner contact
//!
//! FE contact shows loaded ideal involutes engaging early and leaving late
//! through the tip corner. Beyond the kinematic path ends the TCA therefore
//! also samples the tip edge of the tooth that would start (gear tip,
//! before the start of the path) or end (pinion tip, after its end) the
//! contact, over the pair's corner windows: the corner point is on the tip
//! edge ([`ToothSurface::tip_edge`]), its partner is
//! the closest point of the mating flank, the normal is the mating flank's
//! normal there, and a point is kept while its separation is ≤
//! `extension_mm`. A corner is a sharp edge (no tip rounding is modelled):
//! its curvature radius and the equivalent radius are reported as 0.

use std::sync::Arc;

use crate::error::FlankError;
use crate::geometry::frame::Frame;
pub use crate::geometry::gear_pair::LineKind;
use crate::geometry::gear_pair::{ContactSeed, Flank, KinematicLine, LineContactPair};
use crate::geometry::surface::ToothSurface;

pub mod candidates;
pub mod crossing;
pub mod edge_lines;
pub mod ellipse;
pub mod line_cycle;
pub mod major_axis;
pub mod point_candidates;
pub mod point_contact;
pub mod run;
#[cfg(test)]
mod tests;

type Result<T> = std::result::Result<T, FlankError>;
use crate::geometry::vec3::{add, cross, dot, sub, unit, V3};

/// Global point → a frame's own coordinates.
fn own(f: &Frame, x: V3) -> V3 {
    f.rotate_back(sub(x, f.translation))
}

/// Sampling settings of the TCA (mm). The misalignment belongs to the
/// pair ([`GearPair::misalignment`](crate::geometry::gear_pair::GearPair::misalignment); for spur and helical pairs
/// [`crate::geometry::cylindrical::CylindricalPair::with_plane_of_action_misalignment`]).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct TcaSettings {
    /// K ≥ 2 points along each contact line (midpoints of K equal cells).
    pub points_per_line: usize,
    /// Rows of points across each flank contact line (≥ 1; 1 = on the line
    /// only), `across_spacing_mm` apart in the plane of action, centred on
    /// the line. Corner lines are always one row.
    pub points_across: usize,
    pub across_spacing_mm: f64,
    /// Largest separation (mm) of a tip-corner point kept beyond the
    /// kinematic path ends; 0 switches corner contact off.
    pub extension_mm: f64,
    /// Least spacing of the points on a tip-corner line, in the lines'
    /// parameter ξ (axial mm for cylindrical pairs); 0 = no limit (K
    /// points). The LTCA sets
    /// it to the face length of the FE elements: a tip edge carries only
    /// 2n + 1 independent nodal load patterns over n quadratic elements,
    /// and corner points have no half-space term, so more points than
    /// that make the compliance F singular (`verification/extreme`).
    pub corner_spacing_mm: f64,
}

impl Default for TcaSettings {
    fn default() -> Self {
        TcaSettings {
            points_per_line: 20,
            points_across: 1,
            across_spacing_mm: 0.1,
            extension_mm: 0.2,
            corner_spacing_mm: 0.0,
        }
    }
}

impl TcaSettings {
    /// Checks the settings; errors name the field and the accepted range.
    pub fn validate(&self) -> Result<()> {
        let err = |m: String| Err(FlankError::Model(format!("TCA settings: {m}")));
        if !(2..=100_000).contains(&self.points_per_line) {
            return err(format!(
                "points_per_line = {}: between 2 and 100000 points along a contact line are needed",
                self.points_per_line
            ));
        }
        if !(1..=1000).contains(&self.points_across) {
            return err(format!(
                "points_across = {}: between 1 and 1000 rows are needed",
                self.points_across
            ));
        }
        if self.points_across > 1
            && !(self.across_spacing_mm.is_finite() && self.across_spacing_mm > 0.0)
        {
            return err(format!(
                "across_spacing_mm = {}: a finite positive spacing is needed with points_across > 1",
                self.across_spacing_mm
            ));
        }
        if !(self.extension_mm.is_finite() && self.extension_mm >= 0.0) {
            return err(format!(
                "extension_mm = {}: a finite value ≥ 0 is needed",
                self.extension_mm
            ));
        }
        if !(self.corner_spacing_mm.is_finite() && self.corner_spacing_mm >= 0.0) {
            return err(format!(
                "corner_spacing_mm = {}: a finite value ≥ 0 is needed",
                self.corner_spacing_mm
            ));
        }
        Ok(())
    }
}

/// Points on a corner line of span `span` (ξ): K, or fewer so that
/// their spacing span/n is at least `spacing` (never below 2; 0 = K).
fn corner_points(k: usize, span: f64, spacing: f64) -> usize {
    if spacing > 0.0 {
        let fit = (span / spacing).floor();
        // `fit` is finite and ≥ 0 here (span, spacing > 0 and finite)
        k.min((fit as usize).max(2))
    } else {
        k
    }
}

/// One sample point of a contact line (conventions in the module docs).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct ContactPoint {
    /// Pinion flank parameters (u, v) of its [`ToothSurface`] (own frame).
    pub pinion_uv: [f64; 2],
    /// Gear flank parameters (u, v) (its own frame).
    pub gear_uv: [f64; 2],
    /// Global position (mm): the midpoint of the two surface points.
    pub position: [f64; 3],
    /// Global unit normal, outward from the pinion flank.
    pub normal: [f64; 3],
    /// Initial normal separation w (mm), > 0 a gap.
    pub separation_mm: f64,
    /// r = ((−e_z) × x₁)·n (mm), r_b1 cos β_b on an ideal line.
    pub moment_arm_mm: f64,
    /// Length of contact line this point stands for (mm): line length / K.
    /// With `points_across` > 1 every row carries the same width; the load
    /// per unit length of a line section is the sum over its rows / width.
    pub width_mm: f64,
    /// Offset across the line in the plane of action (mm; 0 on the line).
    pub across_mm: f64,
    /// Unit tangent (global) along which the sliding velocity is
    /// measured: the LTCA's tangential (friction) direction. Spur and
    /// helical pairs: the rolling direction across the line; point
    /// contacts: the direction of v_t1 − v_t2.
    pub tangent: [f64; 3],
    /// v_t1 − v_t2 (m/s), signed, along `tangent`.
    pub sliding_velocity: f64,
    /// Entraining speed (v_t1 + v_t2)/2 (m/s), seed 002 eq. 9.
    pub rolling_velocity: f64,
    /// v_t1 + v_t2 (m/s).
    pub sum_velocity: f64,
    /// Radii of curvature of [pinion, gear] across the line, normal section
    /// (mm, > 0 convex; 0 for a tip edge).
    pub curvature_radius: [f64; 2],
    /// ρ₁ρ₂/(ρ₁ + ρ₂) (mm; 0 at a corner, infinite if not convex overall).
    pub equivalent_radius_mm: f64,
}

/// The contact line of one tooth pair at one roll angle.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct ContactLine {
    /// Sector tooth numbers (1-based) of the pinion and of its mate.
    pub pinion_tooth: usize,
    pub gear_tooth: usize,
    pub kind: LineKind,
    /// Length of the sampled part of the line (mm): for a flank line the
    /// part inside the path and the face (Δz / cos β_b); for a corner line
    /// the part whose points were kept.
    pub length_mm: f64,
    /// Face parameter v per mm along the line (cos β_b on a cylindrical
    /// pair, where v = z): turns a length along the line into a v-extent.
    pub param_per_mm: f64,
    pub points: Vec<ContactPoint>,
}

/// The TCA at one roll angle.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct TcaPosition {
    pub roll: f64,
    /// θ₀ = min_i w_i / r_i (rad), > 0: the pinion must turn forward by θ₀
    /// to close the smallest separation.
    pub unloaded_te_rad: f64,
    pub lines: Vec<ContactLine>,
}

/// Unloaded tooth contact analysis of a gear pair (any type behind
/// [`LineContactPair`]).
#[derive(Clone, Debug)]
pub struct Tca {
    pair: Arc<dyn LineContactPair>,
    settings: TcaSettings,
    /// ω₁, ω₂ (rad/s).
    omega: [f64; 2],
}

impl Tca {
    /// The TCA of `pair` at the pinion speed `speed_rpm` (≥ 0; for the
    /// velocities) with `settings`.
    pub fn new(
        pair: Arc<dyn LineContactPair>,
        speed_rpm: f64,
        settings: TcaSettings,
    ) -> Result<Self> {
        settings.validate()?;
        if !(speed_rpm.is_finite() && speed_rpm >= 0.0) {
            return Err(FlankError::Model(format!(
                "TCA: pinion speed {speed_rpm} rpm: a finite value ≥ 0 is needed"
            )));
        }
        let w1 = speed_rpm * std::f64::consts::PI / 30.0;
        let omega = [w1, w1 * pair.ratio()];
        Ok(Tca {
            pair,
            settings,
            omega,
        })
    }

    /// The pair analysed.
    pub fn pair(&self) -> &Arc<dyn LineContactPair> {
        &self.pair
    }

    pub fn settings(&self) -> &TcaSettings {
        &self.settings
    }

    /// The same pair with other settings.
    pub fn with_settings(&self, settings: TcaSettings) -> Result<Self> {
        settings.validate()?;
        Ok(Tca {
            settings,
            ..self.clone()
        })
    }

    /// Kinematic contact ratio of the pair.
    pub fn kinematic_contact_ratio(&self) -> f64 {
        self.pair.kinematic_contact_ratio()
    }

    /// Kinematic single-tooth contact of the middle pair (roll angles).
    pub fn single_contact(&self) -> (f64, f64) {
        self.pair.single_contact()
    }

    /// `positions` roll angles over one mesh cycle (one pinion angular pitch,
    /// half-open), centred on the middle of the middle pair's kinematic
    /// engagement.
    pub fn roll_angles_for_cycle(&self, positions: usize) -> Vec<f64> {
        let (a, e) = self.pair.engagement(self.pair.middle());
        let p = self.pair.pinion().angular_pitch();
        let start = 0.5 * (a + e) - 0.5 * p;
        (0..positions)
            .map(|i| start + p * i as f64 / positions as f64)
            .collect()
    }

    /// Frames (own → global) of the pinion and of the gear at `roll`, the
    /// gear misaligned as the pair says.
    pub fn frames(&self, roll: f64) -> [Frame; 2] {
        self.pair.frames(roll)
    }

    /// The right flank of sector tooth `k` of body `b`.
    fn flank(&self, b: usize, k: usize) -> Result<&dyn ToothSurface> {
        self.pair.body(b).flank(Flank::Right, k).ok_or_else(|| {
            FlankError::Model(format!(
                "TCA: the {} sector has no tooth {k}",
                self.pair.body(b).name()
            ))
        })
    }

    /// The TCA at `roll` (rad, the pair's convention).
    pub fn position(&self, roll: f64) -> Result<TcaPosition> {
        if !roll.is_finite() {
            return Err(FlankError::Model(format!(
                "TCA: roll angle {roll}: a finite value is needed"
            )));
        }
        let frames = self.frames(roll);
        let mut lines = Vec::new();
        for line in self.pair.contact_lines(roll, self.settings.extension_mm) {
            match line.kind {
                LineKind::Flank => lines.push(self.flank_line(&line, &frames)?),
                _ => {
                    if let Some(l) = self.corner_line(&line, &frames)? {
                        lines.push(l);
                    }
                }
            }
        }
        let mut te = f64::INFINITY;
        for p in lines.iter().flat_map(|l| &l.points) {
            if p.moment_arm_mm > 1e-9 {
                te = te.min(p.separation_mm / p.moment_arm_mm);
            }
        }
        if !te.is_finite() {
            // in degrees, as the scene gives roll angles
            let (a, e) = self.pair.engagement(self.pair.middle());
            return Err(FlankError::Model(format!(
                "TCA: no tooth pair of the {}-tooth sectors is in mesh at roll {:.4}° ({roll:.4} rad); the middle pair engages from {:.4}° to {:.4}°",
                self.pair.sector_teeth(),
                roll.to_degrees(),
                a.to_degrees(),
                e.to_degrees()
            )));
        }
        Ok(TcaPosition {
            roll,
            unloaded_te_rad: te,
            lines,
        })
    }

    fn flank_line(&self, line: &KinematicLine, frames: &[Frame; 2]) -> Result<ContactLine> {
        let n = self.settings.points_per_line;
        let rows = self.settings.points_across;
        let (za, zb) = line.range;
        let length = (zb - za) / line.param_per_mm;
        let width = length / n as f64;
        let mut points = Vec::with_capacity(n * rows);
        for i in 0..n {
            let z = za + (zb - za) * (i as f64 + 0.5) / n as f64;
            for j in 0..rows {
                let d = (j as f64 - 0.5 * (rows - 1) as f64) * self.settings.across_spacing_mm;
                let seed = self.pair.line_seed(line, z, d);
                if rows > 1 && !seed.inside {
                    continue;
                }
                let mut p = self.flank_point(line, &seed, frames)?;
                p.width_mm = width;
                p.across_mm = d;
                points.push(p);
            }
        }
        Ok(ContactLine {
            pinion_tooth: line.pinion_tooth,
            gear_tooth: line.gear_tooth,
            kind: LineKind::Flank,
            length_mm: length,
            param_per_mm: line.param_per_mm,
            points,
        })
    }

    /// One point of a flank line from its seed: the normal line through
    /// the seed point meets the pinion flank (M₁), the line through M₁
    /// along the pinion's normal meets the gear flank (M₂).
    fn flank_point(
        &self,
        line: &KinematicLine,
        seed: &ContactSeed,
        frames: &[Frame; 2],
    ) -> Result<ContactPoint> {
        let [f1, f2] = frames;
        let (k, g) = (line.pinion_tooth, line.gear_tooth);
        let fs1 = self.flank(0, k)?;
        let fs2 = self.flank(1, g)?;
        let x0 = seed.point;
        let [u1, v1] = seed.pinion_uv;
        let n0 = f1.rotate(fs1.normal(u1, v1));
        let (u1, v1, t1, [n1, pu1, pv1]) = intersect(fs1, f1, x0, n0, u1, v1)
            .ok_or_else(|| self.no_convergence("pinion", k, x0))?;
        let x1 = add(x0, t1, n0);
        let n = f1.rotate(n1);
        let [u2, v2] = seed.gear_uv;
        let (u2, v2, w, [_, pu2, pv2]) =
            intersect(fs2, f2, x1, n, u2, v2).ok_or_else(|| self.no_convergence("gear", g, x0))?;
        let x2 = add(x1, w, n);
        let e = self.rolling_direction(n, frames);
        let k1 = normal_curvature(fs1, f1, u1, v1, e, Some((pu1, pv1)));
        let k2 = normal_curvature(fs2, f2, u2, v2, e, Some((pu2, pv2)));
        let rho = [radius(k1), radius(k2)];
        let eq = if k1 + k2 > 0.0 {
            1.0 / (k1 + k2)
        } else {
            f64::INFINITY
        };
        Ok(self.point(x1, x2, n, w, [u1, v1], [u2, v2], rho, eq, frames))
    }

    /// e_roll = (n × a₁)/|n × a₁|, a₁ the pinion axis: across the contact
    /// line in the tangent plane.
    fn rolling_direction(&self, n: V3, frames: &[Frame; 2]) -> V3 {
        let (_, axis) = self.pair.pinion().axis();
        unit(cross(n, frames[0].rotate(axis)))
    }

    #[allow(clippy::too_many_arguments)]
    fn point(
        &self,
        x1: V3,
        x2: V3,
        n: V3,
        w: f64,
        uv1: [f64; 2],
        uv2: [f64; 2],
        rho: [f64; 2],
        eq: f64,
        frames: &[Frame; 2],
    ) -> ContactPoint {
        let [f1, f2] = frames;
        let [w1, w2] = self.pair.rotation_axes();
        let (a1, a2) = (f1.rotate(w1), f2.rotate(w2));
        let r1 = sub(x1, f1.translation);
        let arm = dot(cross(a1, r1), n);
        // surface velocities (mm/s) about the placed axes
        let v1 = cross(
            [
                self.omega[0] * a1[0],
                self.omega[0] * a1[1],
                self.omega[0] * a1[2],
            ],
            r1,
        );
        let v2 = cross(
            [
                self.omega[1] * a2[0],
                self.omega[1] * a2[1],
                self.omega[1] * a2[2],
            ],
            sub(x2, f2.translation),
        );
        let e = self.rolling_direction(n, frames);
        let vt = |v: V3| dot(add(v, -dot(v, n), n), e) * 1e-3;
        let (t1, t2) = (vt(v1), vt(v2));
        ContactPoint {
            pinion_uv: uv1,
            gear_uv: uv2,
            position: add(x1, 0.5, sub(x2, x1)),
            normal: n,
            separation_mm: w,
            moment_arm_mm: arm,
            width_mm: 0.0,
            across_mm: 0.0,
            tangent: e,
            sliding_velocity: t1 - t2,
            rolling_velocity: 0.5 * (t1 + t2),
            sum_velocity: t1 + t2,
            curvature_radius: rho,
            equivalent_radius_mm: eq,
        }
    }

    /// A corner line: the tip edge of one tooth against the mating flank,
    /// over the pair's corner window. A whole window (spur): K points over
    /// it. Otherwise the part from the path end to where w reaches
    /// `extension_mm` (bisection; w grows away from the path end), then K
    /// points in it. Points with w > `extension_mm` are dropped.
    fn corner_line(
        &self,
        line: &KinematicLine,
        frames: &[Frame; 2],
    ) -> Result<Option<ContactLine>> {
        let ext = self.settings.extension_mm;
        let at = |z: f64| self.corner_point(line, z, frames);
        let (ze, zf) = line.range;
        let (za, zb) = if line.whole_window {
            (ze, zf)
        } else {
            if at(ze)?.separation_mm > ext {
                return Ok(None);
            }
            let zs = if at(zf)?.separation_mm <= ext {
                zf
            } else {
                let (mut lo, mut hi) = (ze, zf);
                for _ in 0..25 {
                    let mid = 0.5 * (lo + hi);
                    if at(mid)?.separation_mm <= ext {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                lo
            };
            (ze.min(zs), ze.max(zs))
        };
        if !(zb - za > 1e-9 * line.face_span) {
            return Ok(None);
        }
        let n = corner_points(
            self.settings.points_per_line,
            zb - za,
            self.settings.corner_spacing_mm,
        );
        let width = (zb - za) / line.param_per_mm / n as f64;
        let mut points = Vec::new();
        for i in 0..n {
            let z = za + (zb - za) * (i as f64 + 0.5) / n as f64;
            let p = at(z)?;
            if p.separation_mm <= ext {
                points.push(ContactPoint {
                    width_mm: width,
                    ..p
                });
            }
        }
        if points.is_empty() {
            return Ok(None);
        }
        Ok(Some(ContactLine {
            pinion_tooth: line.pinion_tooth,
            gear_tooth: line.gear_tooth,
            kind: line.kind,
            length_mm: width * points.len() as f64,
            param_per_mm: line.param_per_mm,
            points,
        }))
    }

    /// The corner point of a corner line at ξ: the tip edge point of the
    /// edge body and the closest point of the mating flank.
    fn corner_point(
        &self,
        line: &KinematicLine,
        xi: f64,
        frames: &[Frame; 2],
    ) -> Result<ContactPoint> {
        let [f1, f2] = frames;
        let (k, g) = (line.pinion_tooth, line.gear_tooth);
        let fs1 = self.flank(0, k)?;
        let fs2 = self.flank(1, g)?;
        let seed = self.pair.line_seed(line, xi, 0.0);
        let p = match line.kind {
            LineKind::GearTipCorner => {
                let v = seed.gear_uv[1];
                let uv2 = [fs2.u_tip(v), v];
                let x2 = f2.place(fs2.tip_edge(v));
                let [u0, v0] = seed.pinion_uv;
                let (u, v, d) = fs1.closest_point_from(own(f1, x2), u0, v0);
                let nn = f1.rotate(fs1.normal(u, v));
                let x1 = f1.place(fs1.point(u, v));
                let r1 = radius(normal_curvature(
                    fs1,
                    f1,
                    u,
                    v,
                    self.rolling_direction(nn, frames),
                    None,
                ));
                self.point(x1, x2, nn, d, [u, v], uv2, [r1, 0.0], 0.0, frames)
            }
            _ => {
                let v = seed.pinion_uv[1];
                let uv1 = [fs1.u_tip(v), v];
                let x1 = f1.place(fs1.tip_edge(v));
                let [u0, v0] = seed.gear_uv;
                let (u, v, d) = fs2.closest_point_from(own(f2, x1), u0, v0);
                let ng = f2.rotate(fs2.normal(u, v));
                let nn = [-ng[0], -ng[1], -ng[2]];
                let x2 = f2.place(fs2.point(u, v));
                let r2 = radius(normal_curvature(
                    fs2,
                    f2,
                    u,
                    v,
                    self.rolling_direction(nn, frames),
                    None,
                ));
                self.point(x1, x2, nn, d, uv1, [u, v], [0.0, r2], 0.0, frames)
            }
        };
        if !p.separation_mm.is_finite() {
            return Err(FlankError::Model(format!(
                "TCA: corner separation not finite (pinion tooth {k}, line parameter {xi})"
            )));
        }
        Ok(p)
    }

    fn no_convergence(&self, body: &str, tooth: usize, x0: V3) -> FlankError {
        FlankError::Model(format!(
            "TCA: the normal line did not meet the {body} flank (tooth {tooth}) at ({:.6}, {:.6}, {:.6}) mm",
            x0[0], x0[1], x0[2]
        ))
    }
}

fn radius(kappa: f64) -> f64 {
    if kappa != 0.0 {
        1.0 / kappa
    } else {
        f64::INFINITY
    }
}

/// Intersection of the global line x0 + t d with the flank placed by `frame`:
/// Newton on P(u, v) − q0 − t d′ = 0 from (u, v, 0). Returns (u, v, t) and
/// the own-frame normal and derivatives (P_u, P_v) at the last evaluation
/// (within 1e-12 mm of the answer).
fn intersect(
    fs: &dyn ToothSurface,
    frame: &Frame,
    x0: V3,
    d: V3,
    u: f64,
    v: f64,
) -> Option<(f64, f64, f64, [V3; 3])> {
    line_intersection(fs, frame, x0, d, [u, v], 1e-12)
}

/// [`intersect`] to a step tolerance `tol` (mm): surfaces evaluated by an
/// inner Newton (generated bevel flanks) carry round-off above 1e-12 mm.
/// `None` also as soon as an iterate lands where the flank is not defined
/// ([`ToothSurface::evaluate_checked`]): the line has left the generated
/// surface (a candidate axis running past a conjugate pinion's tip), and
/// Newton on the fallback points there only cycles until its 30 steps run
/// out, each step a failed inner solve.
pub(crate) fn line_intersection(
    fs: &dyn ToothSurface,
    frame: &Frame,
    x0: V3,
    d: V3,
    [u, v]: [f64; 2],
    tol: f64,
) -> Option<(f64, f64, f64, [V3; 3])> {
    let q0 = own(frame, x0);
    let m = frame.rotate_back(d).map(|x| -x);
    let (mut u, mut v, mut t) = (u, v, 0.0);
    for _ in 0..30 {
        let (p, n, pu, pv) = fs.evaluate_checked(u, v)?;
        let r = add(sub(q0, p), -t, m);
        // [P_u P_v −d′] (du, dv, dt) = r by Cramer's rule
        let pvm = cross(pv, m);
        let det = dot(pu, pvm);
        if !(det.abs() > 0.0 && det.is_finite()) {
            return None;
        }
        let du = dot(r, pvm) / det;
        let dv = dot(pu, cross(r, m)) / det;
        let dt = dot(pu, cross(pv, r)) / det;
        u += du;
        v += dv;
        t += dt;
        let moved = add([du * pu[0], du * pu[1], du * pu[2]], dv, pv);
        let step = dot(moved, moved).sqrt() + dt.abs();
        if !step.is_finite() {
            return None;
        }
        if step < tol {
            return Some((u, v, t, [n, pu, pv]));
        }
    }
    None
}

/// Normal curvature (1/mm, > 0 convex) of the placed flank at (u, v) in the
/// global tangent direction `e`: (dn/ds)·e by a central difference of the
/// modified surface's normal over ±1e-3 mm; (P_u, P_v) own-frame derivatives at (u, v).
fn normal_curvature(
    fs: &dyn ToothSurface,
    frame: &Frame,
    u: f64,
    v: f64,
    e: V3,
    d: Option<(V3, V3)>,
) -> f64 {
    let (pu, pv) = d.unwrap_or_else(|| fs.derivatives(u, v));
    let t = frame.rotate_back(e);
    let (a, b, c) = (dot(pu, pu), dot(pu, pv), dot(pv, pv));
    let (ru, rv) = (dot(pu, t), dot(pv, t));
    let det = a * c - b * b;
    let du = (c * ru - b * rv) / det;
    let dv = (a * rv - b * ru) / det;
    let h = 1e-3;
    let np = fs.normal(u + h * du, v + h * dv);
    let nm = fs.normal(u - h * du, v - h * dv);
    dot(sub(np, nm), t) / (2.0 * h)
}
