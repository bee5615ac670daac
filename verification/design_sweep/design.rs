//! The seeded sample of ordinary spur and helical designs (README.md, "The
//! sample"): the ranges of issue 56, profile shifts drawn clear of
//! undercut and pointed tips by the closed forms of ISO 21771, the
//! backlash-free centre distance of the shifts, a line load of ordinary
//! size, and a tip relief or lead crowning on a third of the designs.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::f64::consts::PI;

/// Generating rack addendum h_fP* (flank's default, ×m_n).
const RACK_ADDENDUM: f64 = 1.25;
/// Smallest normal tip thickness the shifts may leave (×m_n), a common
/// design floor (0.25–0.4 m_n for case-hardened gears; the lower end here).
const MIN_TIP_THICKNESS: f64 = 0.25;
/// Margin of a shift above the undercut limit.
const UNDERCUT_MARGIN: f64 = 0.05;
const YOUNG_MPA: f64 = 206_000.0;
const POISSON: f64 = 0.3;

#[derive(Clone, Debug)]
pub enum Modification {
    None,
    /// On the pinion: amount (µm) and roll length from the tip (mm).
    TipRelief {
        amount_um: f64,
        length_mm: f64,
        parabolic: bool,
    },
    /// On the pinion: lead crowning (µm).
    LeadCrowning {
        amount_um: f64,
    },
}

impl Modification {
    pub fn label(&self) -> String {
        match self {
            Modification::None => "none".into(),
            Modification::TipRelief {
                amount_um,
                length_mm,
                parabolic,
            } => format!(
                "tip relief {amount_um:.1} um over {length_mm:.2} mm {}",
                if *parabolic { "parabolic" } else { "linear" }
            ),
            Modification::LeadCrowning { amount_um } => {
                format!("lead crowning {amount_um:.1} um")
            }
        }
    }
}

#[derive(Clone, Debug)]
pub struct Design {
    pub z1: u32,
    pub z2: u32,
    pub normal_module_mm: f64,
    pub pressure_angle_deg: f64,
    /// 0: spur.
    pub helix_angle_deg: f64,
    pub face_width_mm: f64,
    pub x1: f64,
    pub x2: f64,
    /// Pinion torque (N·m).
    pub torque_nm: f64,
    pub modification: Modification,
}

fn inv(a: f64) -> f64 {
    a.tan() - a
}

/// The angle whose involute function is `target` (Newton from 0.5 rad).
fn inv_inverse(target: f64) -> f64 {
    let mut a: f64 = 0.5;
    for _ in 0..60 {
        let step = (inv(a) - target) / a.tan().powi(2);
        a -= step;
        if step.abs() < 1e-15 {
            break;
        }
    }
    a
}

impl Design {
    fn beta(&self) -> f64 {
        self.helix_angle_deg.to_radians()
    }
    fn alpha_n(&self) -> f64 {
        self.pressure_angle_deg.to_radians()
    }
    /// Transverse pressure angle α_t = atan(tan α_n / cos β).
    fn alpha_t(&self) -> f64 {
        (self.alpha_n().tan() / self.beta().cos()).atan()
    }
    fn pitch_radius(&self, z: u32) -> f64 {
        z as f64 * self.normal_module_mm / (2.0 * self.beta().cos())
    }
    /// Working transverse pressure angle of the shifts (ISO 21771, zero
    /// backlash): inv α_wt = inv α_t + 2 tan α_n (x1 + x2)/(z1 + z2).
    fn working_pressure_angle(&self) -> f64 {
        let z = (self.z1 + self.z2) as f64;
        inv_inverse(inv(self.alpha_t()) + 2.0 * self.alpha_n().tan() * (self.x1 + self.x2) / z)
    }
    pub fn centre_distance_mm(&self) -> f64 {
        (self.pitch_radius(self.z1) + self.pitch_radius(self.z2)) * self.alpha_t().cos()
            / self.working_pressure_angle().cos()
    }
    fn root_diameter(&self, z: u32, x: f64) -> f64 {
        2.0 * self.pitch_radius(z) - 2.0 * self.normal_module_mm * (RACK_ADDENDUM - x)
    }
    fn bore_mm(&self, z: u32, x: f64) -> f64 {
        let df = self.root_diameter(z, x);
        (df - 7.0 * self.normal_module_mm).max(0.35 * df)
    }
    /// Normal tooth thickness at the tip circle of the default tip
    /// (r_a = r + m_n (1 + x)), ×m_n.
    fn tip_thickness(&self, z: u32, x: f64) -> f64 {
        let m = self.normal_module_mm;
        let r = self.pitch_radius(z);
        let rb = r * self.alpha_t().cos();
        let ra = r + m * (1.0 + x);
        let mt = m / self.beta().cos();
        let st = mt * (PI / 2.0 + 2.0 * x * self.alpha_n().tan());
        let aa = (rb / ra).acos();
        let sa = 2.0 * ra * (st / (2.0 * r) + inv(self.alpha_t()) - inv(aa));
        let beta_a = (ra / r * self.beta().tan()).atan();
        sa * beta_a.cos() / m
    }
    /// Smallest shift without undercut by the default rack (h_fP* = 1.25,
    /// ρ_fP* = min(0.38, 0.99 ρ_max)): x_min = h_fP* − ρ(1 − sin α_n) −
    /// z sin²α_t / (2 cos β).
    fn undercut_limit(&self, z: u32) -> f64 {
        let a = self.alpha_n();
        let rho_max = (PI / 4.0 - RACK_ADDENDUM * a.tan()) * a.cos() / (1.0 - a.sin());
        let rho = (0.99 * rho_max).min(0.38);
        RACK_ADDENDUM
            - rho * (1.0 - a.sin())
            - z as f64 * self.alpha_t().sin().powi(2) / (2.0 * self.beta().cos())
    }
    /// Transverse contact ratio ε_α of the default tips.
    fn contact_ratio(&self) -> f64 {
        let m = self.normal_module_mm;
        let at = self.alpha_t();
        let a = self.centre_distance_mm();
        let aw = self.working_pressure_angle();
        let mut g = -a * aw.sin();
        for (z, x) in [(self.z1, self.x1), (self.z2, self.x2)] {
            let r = self.pitch_radius(z);
            let rb = r * at.cos();
            let ra = r + m * (1.0 + x);
            g += (ra * ra - rb * rb).sqrt();
        }
        g / (PI * m / self.beta().cos() * at.cos())
    }
    /// Nominal contact stress at the pitch point (MPa), ISO 6336-2's
    /// σ_H0 = Z_H Z_E √(F_t (u + 1) / (d_1 b u)) with Z_ε = Z_β = 1: the
    /// scale of the sweep's pressure ratio, not a rating.
    pub fn nominal_contact_stress_mpa(&self) -> f64 {
        let at = self.alpha_t();
        let aw = self.working_pressure_angle();
        let bb = (self.beta().sin() * self.alpha_n().cos()).asin();
        let zh = (2.0 * bb.cos() * aw.cos() / (at.cos().powi(2) * aw.sin())).sqrt();
        let ze = (1.0 / (PI * 2.0 * (1.0 - POISSON * POISSON) / YOUNG_MPA)).sqrt();
        let d1 = 2.0 * self.pitch_radius(self.z1);
        let u = self.z2 as f64 / self.z1 as f64;
        let ft = self.torque_nm * 1000.0 / (d1 / 2.0);
        zh * ze * (ft * (u + 1.0) / (d1 * self.face_width_mm * u)).sqrt()
    }

    /// The scene: both gears of steel, the default rack, sector and roll
    /// range; a coarse compliance mesh (flank 0.8 m_n, base 2 m_n, 10
    /// points per line) stepped at a tenth of a pitch, and the map over
    /// torque at the design torque alone (one pitch of equal steps: the
    /// mean mesh stiffness).
    pub fn scene_toml(&self) -> String {
        let m = self.normal_module_mm;
        let helical = self.helix_angle_deg > 0.0;
        let gear = |name: &str, z: u32, x: f64, hand: &str| {
            let mut s = format!(
                "[{name}]\nteeth = {z}\nnormal_module_mm = {m}\nnormal_pressure_angle_deg = {}\n",
                self.pressure_angle_deg
            );
            if helical {
                s += &format!(
                    "helix_angle_deg = {}\nhand = \"{hand}\"\n",
                    self.helix_angle_deg
                );
            }
            s += &format!(
                "face_width_mm = {}\nprofile_shift = {x}\nbore_diameter_mm = {:.3}\nmaterial = \"steel\"\n\n",
                self.face_width_mm,
                self.bore_mm(z, x)
            );
            s
        };
        let micro = match &self.modification {
            Modification::None => String::new(),
            Modification::TipRelief {
                amount_um,
                length_mm,
                parabolic,
            } => format!(
                "[pinion.micro]\ntip_relief_um = {amount_um}\ntip_relief_length_mm = {length_mm}\ntip_relief_shape = \"{}\"\n\n",
                if *parabolic { "parabolic" } else { "linear" }
            ),
            Modification::LeadCrowning { amount_um } => {
                format!("[pinion.micro]\nlead_crowning_um = {amount_um}\n\n")
            }
        };
        let pitch_deg = 360.0 / self.z1 as f64;
        format!(
            "# design sweep (verification/design_sweep)\n[pair]\nkind = \"{}\"\ncentre_distance_mm = {:.9}\n\n{}{}{}[materials.steel]\nyoung_modulus_mpa = {YOUNG_MPA}\npoisson_ratio = {POISSON}\n\n[load]\ntorque_nm = {}\nspeed_rpm = 1000.0\n\n[analyses]\nltca = {{ flank_size_mm = {}, base_size_mm = {}, points_per_line = 10, roll_step_deg = {:.6}, torques_nm = [{}] }}\n",
            if helical { "helical" } else { "spur" },
            self.centre_distance_mm(),
            gear("pinion", self.z1, self.x1, "right"),
            micro,
            gear("gear", self.z2, self.x2, "left"),
            self.torque_nm,
            0.8 * m,
            2.0 * m,
            pitch_deg / 10.0,
            self.torque_nm
        )
    }
}

/// `n` designs from `seed`: z1 12–40, ratio 1–4, m_n 1–12 mm, α_n
/// 17.5–25°, β 0 (half of them) or 8–35°, b/m_n 8–30; x1, x2 uniform above
/// the undercut limit (+0.05) up to 0.6 / 0.4, redrawn while a tip is
/// thinner than 0.25 m_n or ε_α < 1.1; load F_t/(b m_n) 30–120 N/mm²; a
/// third modified on the pinion (tip relief C_a = (0.5–1.5) F_t/(b c_γ)
/// with c_γ = 20 N/(mm·µm), over half the long relief (ε_α − 1) p_bt, linear
/// or parabolic; or lead crowning 5–20 µm).
pub fn sample(seed: u64, n: usize) -> Vec<Design> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..n)
        .map(|i| {
            let z1 = rng.random_range(12..=40u32);
            let ratio: f64 = rng.random_range(1.0..=4.0);
            let z2 = ((z1 as f64 * ratio).round() as u32).max(z1);
            let normal_module_mm = (rng.random_range(1.0..=12.0f64) * 4.0).round() / 4.0;
            let pressure_angle_deg = (rng.random_range(17.5..=25.0f64) * 10.0).round() / 10.0;
            let helix_angle_deg = if rng.random_bool(0.5) {
                0.0
            } else {
                (rng.random_range(8.0..=35.0f64) * 10.0).round() / 10.0
            };
            let face_width_mm =
                (rng.random_range(8.0..=30.0f64) * normal_module_mm * 10.0).round() / 10.0;
            let mut d = Design {
                z1,
                z2,
                normal_module_mm,
                pressure_angle_deg,
                helix_angle_deg,
                face_width_mm,
                x1: 0.0,
                x2: 0.0,
                torque_nm: 0.0,
                modification: Modification::None,
            };
            let mut drawn = false;
            for _ in 0..200 {
                let lo1 = d.undercut_limit(z1) + UNDERCUT_MARGIN;
                let lo2 = d.undercut_limit(z2) + UNDERCUT_MARGIN;
                d.x1 = (rng.random_range(lo1.clamp(-0.3, 0.55)..=0.6) * 1e4).round() / 1e4;
                d.x2 = (rng.random_range(lo2.clamp(-0.4, 0.35)..=0.4) * 1e4).round() / 1e4;
                if d.tip_thickness(z1, d.x1) >= MIN_TIP_THICKNESS
                    && d.tip_thickness(z2, d.x2) >= MIN_TIP_THICKNESS
                    && d.contact_ratio() >= 1.1
                {
                    drawn = true;
                    break;
                }
            }
            assert!(
                drawn,
                "design {i}: no shifts clear of undercut and pointed tips"
            );
            // F_t/(b m_n) of 30–120 N/mm²: light to heavy industrial loading
            let line_load = rng.random_range(30.0..=120.0f64) * normal_module_mm;
            let ft = line_load * face_width_mm;
            d.torque_nm = (ft * d.pitch_radius(z1) / 1000.0 * 10.0).round() / 10.0;
            d.modification = match rng.random_range(0..6u32) {
                0 => {
                    let mt = normal_module_mm / d.beta().cos();
                    let pbt = PI * mt * d.alpha_t().cos();
                    // the long relief runs from the tip to the single-contact point
                    let long_relief = (d.contact_ratio() - 1.0) * pbt;
                    Modification::TipRelief {
                        amount_um: (line_load / 20.0 * rng.random_range(0.5..=1.5) * 10.0).round()
                            / 10.0,
                        length_mm: (0.5 * long_relief * 100.0).round() / 100.0,
                        parabolic: rng.random_bool(0.5),
                    }
                }
                1 => Modification::LeadCrowning {
                    amount_um: (rng.random_range(5.0..=20.0f64) * 10.0).round() / 10.0,
                },
                _ => Modification::None,
            };
            d
        })
        .collect()
}

/// A flaw put into a design on purpose, which `flank check` must refuse.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Flaw {
    /// A shift 0.1 below the undercut limit.
    Undercut,
    /// A shift whose tip is thinner than 0.1 m_n (flank refuses below 0.2).
    PointedTip,
}

/// `n` designs of `sample(seed, n)` with a flaw in the pinion or the gear
/// (alternately undercut and pointed, pinion and gear), the other member
/// and the centre distance kept consistent with the new shift.
pub fn flawed(seed: u64, n: usize) -> Vec<(Design, Flaw, &'static str)> {
    sample(seed, n)
        .into_iter()
        .enumerate()
        .filter_map(|(i, mut d)| {
            let flaw = if i % 2 == 0 {
                Flaw::Undercut
            } else {
                Flaw::PointedTip
            };
            let member = if (i / 2) % 2 == 0 { "pinion" } else { "gear" };
            let z = if member == "pinion" { d.z1 } else { d.z2 };
            let x = match flaw {
                Flaw::Undercut => d.undercut_limit(z) - 0.1,
                // the shift at which the tip is 0.1 m_n thick (bisection on
                // the monotone tip thickness)
                Flaw::PointedTip => {
                    let (mut lo, mut hi) = (0.0, 3.0);
                    if d.tip_thickness(z, hi) > 0.1 {
                        return None;
                    }
                    for _ in 0..60 {
                        let mid = 0.5 * (lo + hi);
                        if d.tip_thickness(z, mid) > 0.1 {
                            lo = mid
                        } else {
                            hi = mid
                        }
                    }
                    hi
                }
            };
            let x = (x * 1e4).round() / 1e4;
            if !(-2.0..=2.0).contains(&x) {
                return None;
            }
            if member == "pinion" {
                d.x1 = x
            } else {
                d.x2 = x
            }
            d.modification = Modification::None;
            Some((d, flaw, member))
        })
        .collect()
}
