//! The face stations of a bevel sector (module doc of [`super`]): on each
//! back cone v = v_s the profiles of the tooth's two flanks (fillet and
//! flank tabulated in arc length), the tip and gap lands, the sector cut
//! and the mounting surface; over all stations, the lattice counts and
//! the across-tooth, cut and rim gradings that every station shares.

use std::f64::consts::PI;

use rayon::prelude::*;

use super::{err, BevelSectorOptions, LatticeCounts, Mount};
use crate::error::FlankError;
use crate::geometry::bevel::body::{angle_from_y, facing, wrap_angle, BevelGear};
use crate::geometry::bevel::MemberBlank;
use crate::geometry::gear_pair::{Flank, GearBody};
use crate::geometry::surface::ToothSurface;
use crate::mesh::grading::{graded, half_lattice};

/// Samples of the fillet and of the flank tables (arc length ↔ u).
const FILLET_SAMPLES: usize = 32;
const FLANK_SAMPLES: usize = 64;
/// Growth of graded sizes away from the flank and into the rim.
pub(super) const GROWTH: f64 = 1.25;

/// `raw` unwrapped to within π of `reference`.
pub(super) fn unwrap(raw: f64, reference: f64) -> f64 {
    reference + wrap_angle(raw - reference)
}

/// One flank's profile on one station.
pub(super) struct Profile<'a> {
    pub(super) surface: &'a dyn ToothSurface,
    pub(super) side: Flank,
    pub(super) u_root: f64,
    pub(super) u_form: f64,
    /// (u, arc length from the root end) of the fillet, then of the flank
    /// (arc length from the form line).
    fillet: Vec<(f64, f64)>,
    flank: Vec<(f64, f64)>,
}

/// u at arc-length fraction `f` of a table.
fn u_at(table: &[(f64, f64)], f: f64) -> f64 {
    let total = table.last().unwrap().1;
    let target = f.clamp(0.0, 1.0) * total;
    let k = table
        .partition_point(|&(_, s)| s < target)
        .clamp(1, table.len() - 1);
    let ((u0, s0), (u1, s1)) = (table[k - 1], table[k]);
    let w = if s1 > s0 {
        (target - s0) / (s1 - s0)
    } else {
        0.0
    };
    u0 + w * (u1 - u0)
}

fn tabulate(surface: &dyn ToothSurface, v: f64, u0: f64, u1: f64, n: usize) -> Vec<(f64, f64)> {
    let mut out = Vec::with_capacity(n + 1);
    let mut prev = surface.point(u0, v);
    let mut s = 0.0;
    out.push((u0, 0.0));
    for k in 1..=n {
        let u = u0 + (u1 - u0) * k as f64 / n as f64;
        let p = surface.point(u, v);
        s +=
            ((p[0] - prev[0]).powi(2) + (p[1] - prev[1]).powi(2) + (p[2] - prev[2]).powi(2)).sqrt();
        out.push((u, s));
        prev = p;
    }
    out
}

impl<'a> Profile<'a> {
    fn new(surface: &'a dyn ToothSurface, side: Flank, v: f64, u_tip: f64) -> Self {
        let (u_root, u_form) = (surface.u_root(v), surface.u_form(v));
        Profile {
            surface,
            side,
            u_root,
            u_form,
            fillet: tabulate(surface, v, u_root, u_form, FILLET_SAMPLES),
            flank: tabulate(surface, v, u_form, u_tip, FLANK_SAMPLES),
        }
    }
    pub(super) fn fillet_length(&self) -> f64 {
        self.fillet.last().unwrap().1
    }
    pub(super) fn flank_length(&self) -> f64 {
        self.flank.last().unwrap().1
    }
    /// u at arc fraction f of the fillet (0 = root end, 1 = form line).
    pub(super) fn fillet_u(&self, f: f64) -> f64 {
        u_at(&self.fillet, f)
    }
    /// u at arc fraction f of the flank (0 = form line, 1 = tip).
    pub(super) fn flank_u(&self, f: f64) -> f64 {
        u_at(&self.flank, f)
    }
    /// θ of the flank point (u, v), unwrapped near `reference`.
    pub(super) fn theta(&self, u: f64, v: f64, reference: f64) -> f64 {
        unwrap(angle_from_y(self.surface.point(u, v)), reference)
    }
}

/// One station (back cone v = v_s) of tooth 1.
pub(super) struct Station<'a> {
    pub(super) v: f64,
    /// θ of the tooth's middle at the pitch cone (u = 0): every angle of
    /// the station is unwrapped near it.
    pub(super) theta_ref: f64,
    /// The flank at the lower θ, and the one at the higher θ.
    pub(super) lo: Profile<'a>,
    pub(super) hi: Profile<'a>,
    /// The face cone's u (tip land).
    pub(super) u_tip: f64,
    pub(super) theta_tip: [f64; 2],
    /// θ at the two fillet ends [lo, hi].
    pub(super) theta_root: [f64; 2],
    /// The cut on the low-θ side (gap centre): θ, and the land's u there.
    pub(super) theta_cut: f64,
    pub(super) u_cut: f64,
    /// u of the mounting surface on this back cone.
    pub(super) u_mount: f64,
}

impl Station<'_> {
    /// ρ of the axial-section point (u, v) of this station.
    pub(super) fn radius(&self, cones: &MemberBlank, u: f64) -> f64 {
        cones.axial_point(u, self.v).1
    }
    /// Length of the half gap land (mm, arc on the back cone).
    fn land_length(&self, cones: &MemberBlank) -> f64 {
        let r = self.radius(cones, self.u_cut);
        (r * (self.theta_root[0] - self.theta_cut)).hypot(self.lo.u_root - self.u_cut)
    }
    /// Tooth width at the higher form line (mm, arc).
    fn form_width(&self, cones: &MemberBlank) -> f64 {
        let u = self.lo.u_form.max(self.hi.u_form);
        let a = self.lo.theta(u, self.v, self.theta_ref);
        let b = self.hi.theta(u, self.v, self.theta_ref);
        self.radius(cones, u) * (b - a)
    }
}

/// Every station of the face and what they share.
pub(super) struct FaceLayout<'a> {
    pub(super) cones: MemberBlank,
    pub(super) pitch: f64,
    pub(super) stations: Vec<Station<'a>>,
    pub(super) counts: LatticeCounts,
    /// Across-tooth fractions of the Π bottom (2·across + 1), and the
    /// element sizes across the widest station's form line they come from.
    pub(super) across: Vec<f64>,
    pub(super) across_sizes: Vec<f64>,
    /// Half the elements across the tooth.
    pub(super) half_across: usize,
    /// Depth of the cut lines below the gap land (mm).
    pub(super) cut_depth: f64,
    /// Rim fractions from the Π bottom (0) to the mount (1), 2·rim + 1.
    pub(super) rim: Vec<f64>,
    pub(super) mount: Mount,
    pub(super) flank_size: f64,
    pub(super) shank: Option<ShankLayout>,
}

/// The shank's place in the lattice (module docs of [`super`]).
pub(super) struct ShankLayout {
    /// Half index kk of the rim row on ρ = r_s (the rows 0..=kk are extruded).
    pub(super) row: usize,
    pub(super) radius: f64,
    pub(super) bore: f64,
    /// z of the end plane and of the heel face at r_s (mm).
    pub(super) z_end: f64,
    pub(super) z_start: f64,
    /// Element layers along the shank.
    pub(super) layers: usize,
}

impl<'a> FaceLayout<'a> {
    pub(super) fn new(
        gear: &'a BevelGear,
        name: &str,
        opts: &BevelSectorOptions,
    ) -> Result<Self, FlankError> {
        let cones = *gear.cones();
        let pitch = gear.angular_pitch();
        let (left, right) = match (gear.flank(Flank::Left, 1), gear.flank(Flank::Right, 1)) {
            (Some(l), Some(r)) => (l, r),
            _ => return Err(err(format!("{name}: the body has no tooth 1"))),
        };
        let (lv, rv) = (left.v_range(), right.v_range());
        let (v0, v1) = (lv.0.max(rv.0), lv.1.min(rv.1));
        if !(v1 > v0) {
            return Err(err(format!(
                "{name}: the two flanks share no face (v ranges {lv:?} and {rv:?})"
            )));
        }
        // which flank lies at the lower θ (it faces −θ)
        let vm = 0.5 * (v0 + v1);
        let (pl, pr) = (left.point(0.0, vm), right.point(0.0, vm));
        let d = wrap_angle(angle_from_y(pr) - angle_from_y(pl));
        let (lo, hi) = if d > 0.0 {
            ((left, Flank::Left), (right, Flank::Right))
        } else {
            ((right, Flank::Right), (left, Flank::Left))
        };
        if facing(hi.0.point(0.0, vm), hi.0.normal(0.0, vm)) <= 0.0 {
            return Err(err(format!(
                "{name}: the flanks at the mean point do not bound a tooth (the flank at the higher angle faces inward)"
            )));
        }
        // face layers from the pitch line's length on the low flank
        let face_len: f64 = (0..32)
            .map(|k| {
                let a = lo.0.point(0.0, v0 + (v1 - v0) * k as f64 / 32.0);
                let b = lo.0.point(0.0, v0 + (v1 - v0) * (k + 1) as f64 / 32.0);
                ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
            })
            .sum();
        let nface = if opts.face_layers > 0 {
            opts.face_layers
        } else {
            ((face_len / opts.base_size).ceil() as usize).max(1)
        };
        let ns = 2 * nface;
        let vs: Vec<f64> = (0..=ns)
            .map(|s| {
                if s == ns {
                    v1
                } else {
                    v0 + (v1 - v0) * s as f64 / ns as f64
                }
            })
            .collect();
        // reference angles, marching from toe to heel (the tooth winds)
        let mut refs = Vec::with_capacity(vs.len());
        let mut prev = None;
        for &v in &vs {
            let raw = 0.5
                * (angle_from_y(lo.0.point(0.0, v))
                    + unwrap(
                        angle_from_y(hi.0.point(0.0, v)),
                        angle_from_y(lo.0.point(0.0, v)),
                    ));
            let t = match prev {
                None => wrap_angle(raw),
                Some(p) => unwrap(raw, p),
            };
            refs.push(t);
            prev = Some(t);
        }
        // the mounting surface
        let (sd, cd) = cones.delta.sin_cos();
        let whole_depth = cones.ham + cones.hfm;
        let bore = gear.blank().bore_radius;
        let stations: Vec<Station> = vs
            .par_iter()
            .zip(refs.par_iter())
            .map(|(&v, &theta_ref)| {
                let u_tip = lo.0.u_tip(v).min(hi.0.u_tip(v));
                let lp = Profile::new(lo.0, lo.1, v, u_tip);
                let hp = Profile::new(hi.0, hi.1, v, u_tip);
                let theta_root = [
                    lp.theta(lp.u_root, v, theta_ref),
                    hp.theta(hp.u_root, v, theta_ref),
                ];
                let theta_tip = [lp.theta(u_tip, v, theta_ref), hp.theta(u_tip, v, theta_ref)];
                Station {
                    v,
                    theta_ref,
                    u_tip,
                    theta_tip,
                    theta_root,
                    theta_cut: 0.5 * (theta_root[0] + theta_root[1] - pitch),
                    u_cut: 0.5 * (lp.u_root + hp.u_root),
                    u_mount: f64::NAN,
                    lo: lp,
                    hi: hp,
                }
            })
            .collect();
        let mut stations = stations;
        let mount = if cones.delta < 0.25 * PI {
            Mount::Bore { radius: bore }
        } else {
            let deepest = stations
                .iter()
                .map(|s| cones.axial_point(s.u_cut, s.v).0)
                .fold(f64::NEG_INFINITY, f64::max);
            Mount::Plane {
                z: deepest + opts.rim_thickness.unwrap_or(whole_depth),
            }
        };
        for s in &mut stations {
            s.u_mount = match mount {
                Mount::Bore { radius } => (radius - s.v * sd) / cd,
                Mount::Plane { z } => (s.v * cd - z) / sd,
            };
        }
        // checks on every station
        for s in &stations {
            let (tl, th) = (s.theta_tip[0], s.theta_tip[1]);
            if !(th > tl) {
                return Err(err(format!(
                    "{name}: pointed tooth at cone distance {:.3} mm: the flanks cross below the face cone",
                    s.v
                )));
            }
            for (p, which) in [(&s.lo, "low-θ"), (&s.hi, "high-θ")] {
                if !(p.fillet_length() > 1e-9 * cones.re) {
                    return Err(err(format!(
                        "{name}: the {which} flank has no fillet at cone distance {:.3} mm (its form line, u = {:.4} mm, is the root line, u = {:.4} mm): the surface's form line was not found there, and a fillet of zero length cannot be meshed",
                        s.v, p.u_form, p.u_root
                    )));
                }
            }
            if !(s.theta_root[0] > s.theta_cut) {
                return Err(err(format!(
                    "{name}: no gap land at cone distance {:.3} mm: the fillets of neighbouring teeth meet or overlap",
                    s.v
                )));
            }
            if !(s.u_cut - s.u_mount > 0.0) {
                return Err(err(format!(
                    "{name}: the mounting surface ({}) reaches the teeth at cone distance {:.3} mm: {}",
                    match mount {
                        Mount::Bore { radius } => format!("bore radius {radius:.3} mm"),
                        Mount::Plane { z } => format!("plane z = {z:.3} mm"),
                    },
                    s.v,
                    match mount {
                        Mount::Bore { .. } => "make the bore diameter smaller",
                        Mount::Plane { .. } => "make the rim thicker",
                    }
                )));
            }
        }
        let fs = opts.flank_size;
        let max = |f: &dyn Fn(&Station) -> f64| stations.iter().map(f).fold(0.0, f64::max);
        let min =
            |f: &dyn Fn(&Station) -> f64| stations.iter().map(f).fold(f64::INFINITY, f64::min);
        // across the tooth
        let width = max(&|s: &Station| s.form_width(&cones));
        let mut half = graded(0.5 * width, fs, GROWTH, opts.base_size, "half tooth width")
            .map_err(|e| err(format!("{name}: {e}")))?;
        if half.len() < 2 {
            let x = half[0] / 2.0;
            half = vec![x, x];
        }
        let nh = half.len();
        let mut sizes = half.clone();
        sizes.extend(half.iter().rev());
        let across = half_lattice(&sizes);
        // the cut lines: their steps match the first steps across the tooth
        let column = min(&|s: &Station| s.u_cut - s.u_mount);
        let target = (0.4 * column).min(0.22 * whole_depth);
        let mut nc = 1;
        for i in 1..nh {
            if across[2 * i] * width <= target {
                nc = i;
            }
        }
        let cut_depth = (across[2 * nc] * width).min(0.5 * column);
        // along the boundary
        let count = |len: f64| ((len / fs).ceil() as usize).max(1);
        let land = count(max(&|s: &Station| s.land_length(&cones)));
        let fillet = count(max(&|s: &Station| {
            s.lo.fillet_length().max(s.hi.fillet_length())
        }));
        let flank = count(max(&|s: &Station| {
            s.lo.flank_length().max(s.hi.flank_length())
        }));
        // the rim: graded from the cut's last step to base_size
        let cut_step = cut_depth * (across[2 * nc] - across[2 * nc - 2]) / across[2 * nc];
        let rim_len = max(&|s: &Station| s.u_cut - cut_depth - s.u_mount);
        let grade = |len: f64, first: f64, what: &str| {
            graded(len, first, GROWTH, opts.base_size, what)
                .map_err(|e| err(format!("{name}: {e}")))
        };
        let (rim_sizes, rim, shank) = match opts.shank {
            None => {
                let sizes = grade(rim_len, cut_step, "rim below the teeth")?;
                let rim = half_lattice(&sizes);
                (sizes, rim, None)
            }
            Some(sh) => {
                let Mount::Bore { radius: bore } = mount else {
                    return Err(err(format!(
                        "{name}: a shank is for a member held by its bore (a pinion, pitch angle below 45°); this one has a mounting plane"
                    )));
                };
                // the heel station's rim: from the Π bottom u_i down to the bore
                let heel = stations.last().expect("stations");
                let u_i = heel.u_cut - cut_depth;
                let rho_i = heel.radius(&cones, u_i);
                let r_s = 0.5 * sh.diameter;
                if !(r_s > bore && r_s < rho_i) {
                    return Err(err(format!(
                        "{name}: `pinion.shank_diameter_mm` = {}: the shank must lie between the bore (diameter {:.3} mm) and the rim below the teeth at the heel (diameter {:.3} mm)",
                        sh.diameter,
                        2.0 * bore,
                        2.0 * rho_i
                    )));
                }
                // fraction of the rim (from the Π bottom) where ρ = r_s at the heel
                let u_s = (r_s - heel.v * sd) / cd;
                let g = (u_i - u_s) / (u_i - heel.u_mount);
                let upper = grade(g * rim_len, cut_step, "rim above the shank")?;
                let last = *upper.last().expect("graded sizes");
                let lower = grade((1.0 - g) * rim_len, last, "rim over the shank")?;
                let mut rim: Vec<f64> = half_lattice(&upper).iter().map(|f| g * f).collect();
                rim.extend(
                    half_lattice(&lower)
                        .iter()
                        .skip(1)
                        .map(|f| g + (1.0 - g) * f),
                );
                // z on the heel cone at ρ (the back cone v = v₁)
                let z_heel = |rho: f64| cones.axial_point((rho - heel.v * sd) / cd, heel.v).0;
                let (z_start, z_bore) = (z_heel(r_s), z_heel(bore));
                let z_end = z_start + sh.length;
                if !(z_end > z_bore.max(z_start)) {
                    return Err(err(format!(
                        "{name}: `pinion.shank_length_mm` = {}: the shank must reach beyond the heel face at the bore ({:.3} mm behind where it leaves the face)",
                        sh.length,
                        z_bore - z_start
                    )));
                }
                let layers = ((z_end - z_start.min(z_bore)) / opts.base_size)
                    .ceil()
                    .max(1.0) as usize;
                let nr = upper.len() + lower.len();
                let shank = ShankLayout {
                    row: 2 * lower.len(),
                    radius: r_s,
                    bore,
                    z_end,
                    z_start,
                    layers,
                };
                debug_assert_eq!(rim.len(), 2 * nr + 1);
                let mut sizes = upper;
                sizes.extend(lower);
                (sizes, rim, Some(shank))
            }
        };
        Ok(FaceLayout {
            cones,
            pitch,
            counts: LatticeCounts {
                across: 2 * nh,
                land,
                fillet,
                flank,
                cut: nc,
                rim: rim_sizes.len(),
                face: nface,
            },
            stations,
            across,
            across_sizes: sizes,
            half_across: nh,
            cut_depth,
            rim,
            mount,
            flank_size: fs,
            shank,
        })
    }
}
