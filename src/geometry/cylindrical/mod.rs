//! Spur and helical gears behind the gear-pair interface
//! ([`crate::geometry::gear_pair`]): parallel axes, zero offset, exact
//! rack-generated involute helicoids ([`FlankSurface`]).
//!
//! * [`CylindricalGear`]: a [`GearBody`], both flanks of every tooth of the
//!   sector with the gear's flank modification;
//! * [`CylindricalPair`]: a [`LineContactPair`], the kinematics of
//!   [`MeshKinematics`] (line of action, path of contact, roll angle) and
//!   its misalignment in plane-of-action terms;
//! * [`sector_size`]: the teeth a sector body needs to hold every pair in
//!   mesh.
//!
//! # Kinematic contact lines
//!
//! The contact of unmodified aligned involute flanks is known in closed
//! form (ISO 21771:2007 path of contact; Litvin & Fuentes, *Gear Geometry
//! and Applied Theory*, 2nd ed. 2004: the contact line of a helical pair is
//! a straight generator of the base helicoid, inclined by β_b in the plane
//! of action). A line is parameterised by the global z (ξ = z): its point is
//! x₀ = T₁ + s(z) n_t + z e_z with s(z) = s₀ + c z the distance from T₁ along
//! the transverse line of action n_t, c = −r_b1 × (helix twist rate), s₀
//! the tooth's kinematic contact position. Seeds: u₁ = s/r_b1, v₁ = z on the
//! pinion, u₂ = (L′ − s)/r_b2, v₂ = z − (b₁ − b₂)/2 on the gear. Beyond the
//! path ends, windows of s for tip-corner contact: a convex pair separates
//! as Δ²/(2ρ) across the line, Δ = Δs cos β_b, ρ = ρ_t/cos β_b, ρ_t ≤ L/4,
//! so the window reaches 2 √(½ L e / cos³β_b) for a largest corner
//! separation e (twice its reach).
//!
//! # Misalignment (plane-of-action form)
//!
//! The gear axis is tilted about the point of its axis in the middle of the
//! common face width: γ_β in the plane of action (e_z → e_z + γ_β n_t,
//! n_t = (cos α_wt, sin α_wt, 0); γ_β > 0 opens the gap at large z), γ_δ
//! normal to it (e_z → e_z + γ_δ m, m = (−sin α_wt, cos α_wt, 0)).
//! A centre-distance error Δa > 0 moves the gear away along +y; the roll
//! angle and sample points stay those of the nominal centre distance, and
//! the flanks meet on the working line of action at cos α′ = (r_b1 + r_b2)/
//! (a + Δa) (ISO 21771), a pinion involute crossing it r_b1 (α′ − α) further
//! from the moved T₁′. Axial displacements ΔP, ΔG move the bodies along z;
//! the lines follow the pinion. [`Misalignment`] converts as its docs say.

pub mod kinematics;
pub mod sector_size;

use crate::error::FlankError;
use crate::geometry::flank::FlankSurface;
use crate::geometry::frame::Frame;
use crate::geometry::gear_pair::{
    Assembly, Blank, ContactSeed, Flank, GearBody, GearPair, KinematicLine, LineContactPair,
    LineKind, Misalignment,
};
use crate::geometry::involute::{root_radius, tip_radius};
use crate::geometry::micro::FlankModification;
use crate::geometry::rack::ToothProfile;
use crate::geometry::surface::ToothSurface;
use crate::geometry::vec3::{add, dot, sub, V3};
use crate::geometry::{GearSpec, PairSpec};

pub use kinematics::MeshKinematics;

type Result<T> = std::result::Result<T, FlankError>;

/// Rodrigues rotation by `angle` about the unit `axis`.
fn rotation(axis: V3, angle: f64) -> [[f64; 3]; 3] {
    let (s, c) = angle.sin_cos();
    let [x, y, z] = axis;
    let t = 1.0 - c;
    [
        [c + t * x * x, t * x * y - s * z, t * x * z + s * y],
        [t * x * y + s * z, c + t * y * y, t * y * z - s * x],
        [t * x * z - s * y, t * y * z + s * x, c + t * z * z],
    ]
}

fn matmul(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let mut r = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            r[i][j] = (0..3).map(|k| a[i][k] * b[k][j]).sum();
        }
    }
    r
}

fn matvec(a: &[[f64; 3]; 3], v: V3) -> V3 {
    [dot(a[0], v), dot(a[1], v), dot(a[2], v)]
}

/// A spur or helical gear modelled as a sector of teeth (module docs).
#[derive(Clone, Debug)]
pub struct CylindricalGear {
    name: String,
    spec: GearSpec,
    profile: ToothProfile,
    modification: Option<FlankModification>,
    /// Right and left flanks of sector teeth 1..=n.
    right: Vec<FlankSurface>,
    left: Vec<FlankSurface>,
}

impl CylindricalGear {
    /// Gear `spec` ("pinion"/"gear" in messages) as a sector of
    /// `sector_teeth` teeth, its flanks modified by `modification`.
    pub fn new(
        spec: &GearSpec,
        name: &str,
        sector_teeth: usize,
        modification: Option<FlankModification>,
    ) -> Result<Self> {
        let profile = ToothProfile::new(spec, name)?;
        if sector_teeth == 0 || sector_teeth > spec.teeth as usize {
            return Err(FlankError::Model(format!(
                "{name}: a sector of {sector_teeth} teeth does not fit a gear of {} teeth",
                spec.teeth
            )));
        }
        let mut right = Vec::with_capacity(sector_teeth);
        let mut left = Vec::with_capacity(sector_teeth);
        for k in 1..=sector_teeth {
            right.push(FlankSurface::new(
                profile.clone(),
                Flank::Right,
                k,
                modification.clone(),
            )?);
            left.push(FlankSurface::new(
                profile.clone(),
                Flank::Left,
                k,
                modification.clone(),
            )?);
        }
        Ok(CylindricalGear {
            name: name.to_string(),
            spec: spec.clone(),
            profile,
            modification,
            right,
            left,
        })
    }

    pub fn spec(&self) -> &GearSpec {
        &self.spec
    }

    /// The transverse section (rack-generated profile) of tooth 0.
    pub fn profile(&self) -> &ToothProfile {
        &self.profile
    }

    pub fn modification(&self) -> Option<&FlankModification> {
        self.modification.as_ref()
    }

    /// The involute flank surface `side` of sector tooth `tooth`.
    pub fn flank_surface(&self, side: Flank, tooth: usize) -> Option<&FlankSurface> {
        let v = match side {
            Flank::Right => &self.right,
            Flank::Left => &self.left,
        };
        tooth.checked_sub(1).and_then(|i| v.get(i))
    }
}

impl GearBody for CylindricalGear {
    fn name(&self) -> &str {
        &self.name
    }
    fn teeth(&self) -> u32 {
        self.spec.teeth
    }
    fn sector_teeth(&self) -> usize {
        self.right.len()
    }
    fn angular_pitch(&self) -> f64 {
        self.profile.angular_pitch()
    }
    fn flank(&self, side: Flank, tooth: usize) -> Option<&dyn ToothSurface> {
        self.flank_surface(side, tooth)
            .map(|s| s as &dyn ToothSurface)
    }
    fn blank(&self) -> Blank {
        Blank {
            bore_radius: 0.5 * self.spec.bore_diameter,
            root_radius: root_radius(&self.spec),
            tip_radius: tip_radius(&self.spec),
            axial_range: (0.0, self.spec.face_width),
        }
    }
    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}

/// A spur or helical pair on parallel axes (module docs).
#[derive(Clone, Debug)]
pub struct CylindricalPair {
    spec: PairSpec,
    kin: MeshKinematics,
    bodies: [CylindricalGear; 2],
    /// [γ_β, γ_δ] (rad), Δa (mm), [ΔP, ΔG] (mm).
    gamma: [f64; 2],
    centre_distance_error: f64,
    axial: [f64; 2],
    /// Common face in global z.
    z_range: (f64, f64),
    /// ds/dz of a contact line in the plane of action (−r_b1 × twist rate).
    slope: f64,
    cos_beta_b: f64,
    /// T₁ and the transverse line-of-action direction n_t.
    t1: V3,
    n_t: V3,
    /// Misalignment rotation and its centre.
    tilt: [[f64; 3]; 3],
    tilt_centre: V3,
    /// Working line of action with Δa: length L′, path [s_A, s_E] from T₁′,
    /// shift r_b1 (α′ − α) of a pinion involute's crossing.
    line_length: f64,
    path: (f64, f64),
    s_shift: f64,
}

impl CylindricalPair {
    /// `spec` meshed as sectors of `teeth` teeth, with the flank
    /// modifications of [pinion, gear], aligned.
    pub fn new(
        spec: &PairSpec,
        modifications: [Option<FlankModification>; 2],
        teeth: usize,
    ) -> Result<Self> {
        let kin = MeshKinematics::new(spec, teeth)?;
        let zmax = spec.pinion.teeth.min(spec.gear.teeth) as usize;
        if teeth > zmax {
            return Err(FlankError::Model(format!(
                "a sector of {teeth} teeth does not fit a gear of {zmax} teeth"
            )));
        }
        let [m1, m2] = modifications;
        let bodies = [
            CylindricalGear::new(&spec.pinion, "pinion", teeth, m1)?,
            CylindricalGear::new(&spec.gear, "gear", teeth, m2)?,
        ];
        let slope = -kin.base_radius[0] * bodies[0].profile.twist_rate;
        let cos_beta_b = kin.base_helix_angle.cos();
        let mut pair = CylindricalPair {
            spec: spec.clone(),
            kin,
            bodies,
            gamma: [0.0; 2],
            centre_distance_error: 0.0,
            axial: [0.0; 2],
            z_range: (0.0, 0.0),
            slope,
            cos_beta_b,
            t1: [0.0; 3],
            n_t: [0.0; 3],
            tilt: [[0.0; 3]; 3],
            tilt_centre: [0.0; 3],
            line_length: 0.0,
            path: (0.0, 0.0),
            s_shift: 0.0,
        };
        pair.place()?;
        Ok(pair)
    }

    /// The same pair with the gear axis tilted by [γ_β, γ_δ] (rad, in and
    /// normal to the plane of action) and the centre distance changed by
    /// Δa (mm) (module docs). |γ| ≤ 0.05 rad, |Δa| ≤ 5 % of a.
    pub fn with_plane_of_action_misalignment(
        mut self,
        gamma: [f64; 2],
        centre_distance_error_mm: f64,
    ) -> Result<Self> {
        let err = |m: String| Err(FlankError::Model(format!("misalignment: {m}")));
        for (i, g) in gamma.iter().enumerate() {
            if !(g.is_finite() && g.abs() <= 0.05) {
                let name = ["γ_β", "γ_δ"][i];
                return err(format!(
                    "{name} = {g} rad: a finite tilt of at most 0.05 rad is needed (small misalignment)"
                ));
            }
        }
        if !centre_distance_error_mm.is_finite() {
            return err(format!(
                "centre-distance error {centre_distance_error_mm} mm: a finite value is needed"
            ));
        }
        let a = self.spec.centre_distance;
        if centre_distance_error_mm.abs() > 0.05 * a {
            return err(format!(
                "centre-distance error {centre_distance_error_mm} mm exceeds 5 % of the centre distance {a} mm"
            ));
        }
        self.gamma = gamma;
        self.centre_distance_error = centre_distance_error_mm;
        self.place()?;
        Ok(self)
    }

    /// The same pair with the misalignment set `m` (ΔE = Δa; ΔΣ and the
    /// out-of-plane tilt turned into γ_β, γ_δ by α_wt; ΔP, ΔG along z).
    pub fn with_misalignment(self, m: Misalignment) -> Result<Self> {
        let (s, c) = self.kin.working_pressure_angle.sin_cos();
        let (t, sig) = (m.out_of_plane_tilt_rad, m.shaft_angle_error_rad);
        let gamma = [t * c + sig * s, -t * s + sig * c];
        for (name, x) in [("ΔP", m.pinion_axial_mm), ("ΔG", m.gear_axial_mm)] {
            let b = self.spec.pinion.face_width.min(self.spec.gear.face_width);
            if !(x.is_finite() && x.abs() < 0.5 * b) {
                return Err(FlankError::Model(format!(
                    "misalignment: {name} = {x} mm: a finite axial displacement below half the face width ({} mm) is needed",
                    0.5 * b
                )));
            }
        }
        let mut pair = self.with_plane_of_action_misalignment(gamma, m.offset_error_mm)?;
        pair.axial = [m.pinion_axial_mm, m.gear_axial_mm];
        pair.place()?;
        Ok(pair)
    }

    /// The derived placement data of the current misalignment.
    fn place(&mut self) -> Result<()> {
        let kin = &self.kin;
        let [dp, dg] = self.axial;
        let shift = kin.gear_z_shift;
        let z_range = if dp == 0.0 && dg == 0.0 {
            (
                0.0f64.max(shift),
                kin.face_width[0].min(shift + kin.face_width[1]),
            )
        } else {
            (
                dp.max(shift + dg),
                (dp + kin.face_width[0]).min(shift + dg + kin.face_width[1]),
            )
        };
        if !(z_range.1 > z_range.0) {
            return Err(FlankError::Model(
                "the face widths of pinion and gear do not overlap".into(),
            ));
        }
        let a = self.spec.centre_distance;
        let rb1 = kin.base_radius[0];
        let rbs = rb1 + kin.base_radius[1];
        let aw = a + self.centre_distance_error;
        if !(aw > rbs) {
            return Err(FlankError::Model(format!(
                "misalignment: centre-distance error {} mm leaves a centre distance {aw} mm at or below r_b1 + r_b2 = {rbs} mm",
                self.centre_distance_error
            )));
        }
        let alpha = (rbs / aw).acos();
        let line_length = aw * alpha.sin();
        self.path = (
            line_length - kin.base_radius[1] * kin.tip_roll[1],
            kin.path_end,
        );
        self.s_shift = rb1 * (alpha - kin.working_pressure_angle);
        let (sa, ca) = alpha.sin_cos();
        self.n_t = [ca, sa, 0.0];
        let m = [-sa, ca, 0.0];
        self.t1 = [-rb1 * sa, rb1 * ca, 0.0];
        let [gb, gd] = self.gamma;
        self.tilt = matmul(&rotation([-ca, -sa, 0.0], gd), &rotation(m, gb));
        self.tilt_centre = [0.0, a, 0.5 * (z_range.0 + z_range.1)];
        self.z_range = z_range;
        self.line_length = line_length;
        Ok(())
    }

    /// How far along the path of contact (mm) beyond its kinematic ends a
    /// tip corner comes within `separation_mm` of the mating flank: the
    /// corner windows of [`LineContactPair::contact_lines`],
    /// 2 √(L δ / (2 cos³β_b)) (the separation grows with the square of the
    /// distance from the path end, curvature 1/L of the relative involute
    /// motion).
    pub fn corner_reach_mm(&self, separation_mm: f64) -> f64 {
        2.0 * (0.5 * self.line_length * separation_mm / self.cos_beta_b.powi(3)).sqrt()
    }

    /// The involute kinematics of the aligned pair.
    pub fn kinematics(&self) -> &MeshKinematics {
        &self.kin
    }

    pub fn spec(&self) -> &PairSpec {
        &self.spec
    }

    pub fn cylindrical(&self, b: usize) -> &CylindricalGear {
        &self.bodies[b.min(1)]
    }

    /// [γ_β, γ_δ] (rad) and Δa (mm).
    pub fn plane_of_action_misalignment(&self) -> ([f64; 2], f64) {
        (self.gamma, self.centre_distance_error)
    }

    /// T₁′ (the pinion's base tangent point on the working line of action)
    /// and the transverse line-of-action direction n_t.
    pub fn line_of_action(&self) -> (V3, V3) {
        (self.t1, self.n_t)
    }

    /// The point of the gear axis about which the misalignment tilts it.
    pub fn tilt_centre(&self) -> V3 {
        self.tilt_centre
    }

    /// Global-z interval of the line s(z) = s0 + slope·z with s in [lo, hi],
    /// inside the common face.
    fn z_interval(&self, s0: f64, lo: f64, hi: f64) -> Option<(f64, f64)> {
        let (za, zb) = self.z_range;
        let c = self.slope;
        let (a, b) = if c.abs() < 1e-14 {
            if s0 >= lo && s0 <= hi {
                (za, zb)
            } else {
                return None;
            }
        } else {
            let (x, y) = ((lo - s0) / c, (hi - s0) / c);
            (x.min(y).max(za), x.max(y).min(zb))
        };
        (b - a > 1e-9 * (zb - za)).then_some((a, b))
    }

    fn line(
        &self,
        k: usize,
        kind: LineKind,
        range: (f64, f64),
        whole_window: bool,
        s0: f64,
    ) -> KinematicLine {
        KinematicLine {
            pinion_tooth: k,
            gear_tooth: self.kin.mate(k),
            kind,
            range,
            param_per_mm: self.cos_beta_b,
            whole_window,
            face_span: self.z_range.1 - self.z_range.0,
            origin: s0,
        }
    }

    /// A corner window in s ∈ [lo, hi], oriented so that its first end is
    /// next to the path end `edge`.
    fn corner(&self, k: usize, s0: f64, lo: f64, hi: f64, kind: LineKind) -> Option<KinematicLine> {
        let (za, zb) = self.z_interval(s0, lo, hi)?;
        let c = self.slope;
        if c.abs() < 1e-14 {
            return Some(self.line(k, kind, (za, zb), true, s0));
        }
        let (sa, sb) = (s0 + c * za, s0 + c * zb);
        let edge_first = match kind {
            LineKind::GearTipCorner => sa > sb,
            _ => sa < sb,
        };
        let range = if edge_first { (za, zb) } else { (zb, za) };
        Some(self.line(k, kind, range, false, s0))
    }
}

impl GearPair for CylindricalPair {
    fn pinion(&self) -> &dyn GearBody {
        &self.bodies[0]
    }
    fn gear(&self) -> &dyn GearBody {
        &self.bodies[1]
    }
    fn assembly(&self) -> Assembly {
        Assembly {
            shaft_angle_rad: 0.0,
            offset_mm: self.spec.centre_distance,
            mounting_distance_mm: [0.0, self.kin.gear_z_shift],
        }
    }
    fn misalignment(&self) -> Misalignment {
        // invert γ_β = t cos α + ΔΣ sin α, γ_δ = −t sin α + ΔΣ cos α
        let (s, c) = self.kin.working_pressure_angle.sin_cos();
        let [gb, gd] = self.gamma;
        Misalignment {
            offset_error_mm: self.centre_distance_error,
            pinion_axial_mm: self.axial[0],
            gear_axial_mm: self.axial[1],
            shaft_angle_error_rad: gb * s + gd * c,
            out_of_plane_tilt_rad: gb * c - gd * s,
        }
    }
    fn ratio(&self) -> f64 {
        self.kin.z1 / self.kin.z2
    }
    fn sector_teeth(&self) -> usize {
        self.kin.teeth
    }
    fn middle(&self) -> usize {
        self.kin.middle
    }
    fn mate(&self, k: usize) -> usize {
        self.kin.mate(k)
    }
    fn tooth_roll_step(&self) -> f64 {
        // tooth k + 1's contact lies a base pitch further along the line
        -self.kin.angular_pitch[0]
    }
    fn nominal_frames(&self, roll: f64) -> [Frame; 2] {
        self.kin.frames(roll)
    }
    fn frames(&self, roll: f64) -> [Frame; 2] {
        let [mut f1, f2] = self.kin.frames(roll);
        let c = self.tilt_centre;
        let mut t = add(
            add(matvec(&self.tilt, sub(f2.translation, c)), 1.0, c),
            self.centre_distance_error,
            [0.0, 1.0, 0.0],
        );
        let [dp, dg] = self.axial;
        if dp != 0.0 {
            f1.translation[2] += dp;
        }
        if dg != 0.0 {
            t = add(t, dg, matvec(&self.tilt, [0.0, 0.0, 1.0]));
        }
        [
            f1,
            Frame {
                rotation: matmul(&self.tilt, &f2.rotation),
                translation: t,
            },
        ]
    }
    fn rotation_axes(&self) -> [V3; 2] {
        // the pinion turns clockwise seen from +z, the gear counter-clockwise
        [[0.0, 0.0, -1.0], [0.0, 0.0, 1.0]]
    }
    fn describe(&self) -> serde_json::Value {
        serde_json::to_value(&self.kin).unwrap_or_default()
    }
}

impl LineContactPair for CylindricalPair {
    fn engagement(&self, k: usize) -> (f64, f64) {
        self.kin.engagement(k)
    }
    /// Tooth `k`'s line s = s₀ + c z (s₀ = contact position + shift, less
    /// c ΔP with a pinion axial offset, as [`Self::contact_lines`]) meets
    /// the path [s_A, s_E] inside the common face z ∈ [z_a, z_b] while
    /// s₀ ∈ [s_A − max(c z), s_E − min(c z)]; s₀ grows with the roll at
    /// the rate r_b1.
    fn face_engagement(&self, k: usize) -> (f64, f64) {
        let c = self.slope;
        if c.abs() < 1e-14
            && self.s_shift == 0.0
            && self.path == (self.kin.path_start, self.kin.path_end)
        {
            return self.kin.engagement(k);
        }
        let (ps, pe) = self.path;
        let (za, zb) = self.z_range;
        let (cz_lo, cz_hi) = ((c * za).min(c * zb), (c * za).max(c * zb));
        let s0 = |s: f64| s - self.s_shift + c * self.axial[0];
        (
            self.kin.roll_at(k, s0(ps - cz_hi)),
            self.kin.roll_at(k, s0(pe - cz_lo)),
        )
    }
    fn single_contact(&self) -> (f64, f64) {
        self.kin.single_contact()
    }
    fn kinematic_contact_ratio(&self) -> f64 {
        self.kin.contact_ratio
    }
    fn path_position(&self, k: usize, roll: f64) -> f64 {
        self.kin.contact_position(k, roll) - self.kin.path_start
    }
    fn path_length(&self) -> f64 {
        self.kin.path_end - self.kin.path_start
    }
    fn path_pitch(&self) -> f64 {
        self.kin.base_pitch
    }
    fn nominal_moment_arm(&self) -> f64 {
        self.kin.base_radius[0] * self.kin.base_helix_angle.cos()
    }
    fn transmission_error_radius(&self) -> f64 {
        self.kin.base_radius[0]
    }
    fn contact_lines(&self, roll: f64, corner_separation_mm: f64) -> Vec<KinematicLine> {
        let (ps, pe) = self.path;
        let c = self.slope;
        let spur = c.abs() < 1e-14;
        let reach = self.corner_reach_mm(corner_separation_mm);
        let dp = self.axial[0];
        let mut lines = Vec::new();
        for k in 1..=self.kin.teeth {
            let mut s0 = self.kin.contact_position(k, roll) + self.s_shift;
            if dp != 0.0 {
                // the lines follow the pinion: s = s0 + c (z − ΔP)
                s0 -= c * dp;
            }
            if let Some((za, zb)) = self.z_interval(s0, ps, pe) {
                lines.push(self.line(k, LineKind::Flank, (za, zb), false, s0));
            }
            if corner_separation_mm > 0.0 {
                if !spur || s0 < ps {
                    lines.extend(self.corner(k, s0, ps - reach, ps, LineKind::GearTipCorner));
                }
                if !spur || s0 > pe {
                    lines.extend(self.corner(k, s0, pe, pe + reach, LineKind::PinionTipCorner));
                }
            }
        }
        lines
    }
    fn line_seed(&self, line: &KinematicLine, xi: f64, across: f64) -> ContactSeed {
        let c = self.slope;
        let z = xi;
        let s = line.origin + c * z;
        // across the line in the (s, z) plane: (1, −c)/q
        let q = (1.0 + c * c).sqrt();
        let (s, z) = (s + across / q, z - c * across / q);
        let (ps, pe) = self.path;
        let (z0, z1) = self.z_range;
        let rb = self.kin.base_radius;
        let [dp, dg] = self.axial;
        let v1 = if dp != 0.0 { z - dp } else { z };
        let v2 = if dg != 0.0 {
            z - self.kin.gear_z_shift - dg
        } else {
            z - self.kin.gear_z_shift
        };
        ContactSeed {
            point: add(add(self.t1, s, self.n_t), z, [0.0, 0.0, 1.0]),
            pinion_uv: [s / rb[0], v1],
            gear_uv: [(self.line_length - s) / rb[1], v2],
            inside: s >= ps && s <= pe && z >= z0 && z <= z1,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::involute::{base_helix_angle, reference_radius};
    use crate::geometry::surface::{normal_curvature, principal_curvatures};
    use crate::geometry::vec3::{cross, norm, unit};
    use crate::geometry::{Hand, RackProfile};

    /// Seed 004's helical pinion (z 21, m_n 15 mm, α_n 20°, β 20°).
    fn helical(teeth: u32) -> GearSpec {
        GearSpec {
            teeth,
            normal_module: 15.0,
            normal_pressure_angle: 20f64.to_radians(),
            helix_angle: 20f64.to_radians(),
            hand: Hand::Right,
            face_width: 180.0,
            profile_shift: 0.0,
            rack: RackProfile::default(),
            tip_diameter: None,
            bore_diameter: 100.0,
        }
    }

    /// The involute helicoid through the generic surface machinery: a
    /// developable surface whose principal curvatures are cos β_b/ρ_t, in
    /// the transverse direction e_roll = n × e_z, and 0 along the straight
    /// generator (the contact line, inclined by β_b to the axis), ρ_t = r_b u
    /// (Litvin & Fuentes, involute helical gears; the TCA's ρ_n = ρ_t/cos β_b).
    #[test]
    fn involute_curvatures_from_the_fundamental_forms() {
        let spec = helical(21);
        let g = CylindricalGear::new(&spec, "pinion", 3, None).unwrap();
        let bb = base_helix_angle(&spec);
        let rb = g.profile().geometry.base_radius;
        for k in [1, 2] {
            let f = g.flank(Flank::Right, k).unwrap();
            let (u0, u1) = (f.u_form(0.0), f.u_tip(0.0));
            for t in [0.2, 0.5, 0.9] {
                let u = u0 + t * (u1 - u0);
                let v = 60.0;
                let n = f.normal(u, v);
                let e = unit(cross(n, [0.0, 0.0, 1.0]));
                let rho_t = rb * u;
                let kn = normal_curvature(f, u, v, e);
                let want = bb.cos() / rho_t;
                assert!((kn - want).abs() < 1e-6 * want, "κ_n {kn} vs {want}");
                let c = principal_curvatures(f, u, v);
                let k1 = want;
                assert!((dot(c.directions[0], e).abs() - 1.0).abs() < 1e-6);
                assert!(
                    (c.principal[0] - k1).abs() < 1e-6 * k1,
                    "{:?} vs {k1}",
                    c.principal
                );
                assert!(c.principal[1].abs() < 1e-6 * k1, "{:?}", c.principal);
                let axial = c.directions[1][2].abs();
                assert!((axial - bb.cos()).abs() < 1e-6, "generator: {axial}");
            }
        }
    }

    /// The tip edge is the helix on the tip cylinder: its tangent makes the
    /// angle β_a with the axis, tan β_a = tan β r_a/r (ISO 21771).
    #[test]
    fn tip_edge_is_the_tip_helix() {
        let spec = helical(21);
        let g = CylindricalGear::new(&spec, "pinion", 1, None).unwrap();
        let f = g.flank(Flank::Right, 1).unwrap();
        let ra = tip_radius(&spec);
        let beta_a = (spec.helix_angle.tan() * ra / reference_radius(&spec)).atan();
        for v in [0.0, 45.0, 180.0] {
            let x = f.tip_edge(v);
            assert!(((x[0] * x[0] + x[1] * x[1]).sqrt() - ra).abs() < 1e-9);
            let t = f.tip_edge_tangent(v);
            assert!((norm(t) - 1.0).abs() < 1e-12);
            assert!(
                (t[2] - beta_a.cos()).abs() < 1e-9,
                "{t:?} vs cos β_a {}",
                beta_a.cos()
            );
        }
    }

    /// The misalignment set and the plane-of-action form convert both ways;
    /// out-of-range values are errors naming the value.
    #[test]
    fn misalignment_conversions() {
        let pinion = helical(21);
        let gear = helical(37);
        let gear = GearSpec {
            hand: Hand::Left,
            ..gear
        };
        let spec = PairSpec {
            pinion,
            gear,
            centre_distance: 0.5 * 15.0 * 58.0 / 20f64.to_radians().cos(),
        };
        let spec = crate::geometry::pair::with_gear_shift_for_centre_distance(&spec).unwrap();
        let m = Misalignment {
            offset_error_mm: 0.05,
            pinion_axial_mm: 0.0,
            gear_axial_mm: 0.3,
            shaft_angle_error_rad: 2e-4,
            out_of_plane_tilt_rad: -1e-4,
        };
        let p = CylindricalPair::new(&spec, [None, None], 3)
            .unwrap()
            .with_misalignment(m)
            .unwrap();
        let back = p.misalignment();
        assert!((back.shaft_angle_error_rad - m.shaft_angle_error_rad).abs() < 1e-18);
        assert!((back.out_of_plane_tilt_rad - m.out_of_plane_tilt_rad).abs() < 1e-18);
        assert_eq!(back.offset_error_mm, 0.05);
        assert_eq!(back.gear_axial_mm, 0.3);
        let ([gb, gd], da) = p.plane_of_action_misalignment();
        let a = p.kinematics().working_pressure_angle;
        assert!((gb - (-1e-4 * a.cos() + 2e-4 * a.sin())).abs() < 1e-18);
        assert!((gd - (1e-4 * a.sin() + 2e-4 * a.cos())).abs() < 1e-18);
        assert_eq!(da, 0.05);
        // ΔP, ΔG move the frames along the axes
        let aligned = CylindricalPair::new(&spec, [None, None], 3).unwrap();
        let shifted = aligned
            .clone()
            .with_misalignment(Misalignment {
                pinion_axial_mm: -0.2,
                gear_axial_mm: 0.3,
                ..Default::default()
            })
            .unwrap();
        let [a1, a2] = aligned.frames(0.1);
        let [s1, s2] = shifted.frames(0.1);
        assert_eq!(sub(s1.translation, a1.translation), [0.0, 0.0, -0.2]);
        let d = sub(s2.translation, a2.translation);
        assert!(norm(sub(d, [0.0, 0.0, 0.3])) < 1e-15, "{d:?}");
        for bad in [
            Misalignment {
                shaft_angle_error_rad: 0.1,
                ..Default::default()
            },
            Misalignment {
                gear_axial_mm: f64::NAN,
                ..Default::default()
            },
            Misalignment {
                offset_error_mm: 1e3,
                ..Default::default()
            },
        ] {
            let e = CylindricalPair::new(&spec, [None, None], 3)
                .unwrap()
                .with_misalignment(bad)
                .unwrap_err();
            assert!(e.to_string().contains("misalignment"), "{e}");
        }
        // the pair through the interface
        let q: &dyn LineContactPair = &p;
        assert_eq!(q.assembly().shaft_angle_rad, 0.0);
        assert_eq!(q.mate(1), 3);
        assert!((q.ratio() - 21.0 / 37.0).abs() < 1e-15);
        assert!((q.path_length() / q.path_pitch() - q.kinematic_contact_ratio()).abs() < 1e-12);
    }
}
