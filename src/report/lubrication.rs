//! The outputs of the wet–dry loop of seed 002, the same for the FE mesh
//! cycle ([`crate::mesh_cycle::lubricated`]) and the LTCA
//! ([`crate::ltca::lubricated`]): `lubrication.csv` (final pass: per
//! position and tooth pair W, P̄, R_x, R_y, u, v_s, slide-to-roll, h_c,
//! h_min, λ, μ, friction force, power loss, flags), `lubrication_passes.csv`
//! (μ used and μ from the EHL of every pass), plots of μ, h_c and power
//! loss against roll angle, and the `lubrication` object of summary.json.
//!
//! The mesh power loss is the mean over the positions within one angular
//! pitch around roll 0 (the cycle repeats every pitch) of Σ_pairs μ W |v_s|;
//! efficiency 1 − P_loss/(T ω₁). The subsurface change per position is the
//! largest principal shear below its contacts, last wet pass against the
//! dry pass (seed 002 Fig. 10): the Hertz line-contact peak
//! p₀ = √(w′ E′ / (2π R_x)) times the McEwen/Smith–Liu maximum for the μ
//! the pass used ([`crate::lubrication::subsurface`]).

use std::path::Path;

use serde::Serialize;

use crate::error::FlankError;
use crate::lubrication::{ContactEhl, LoopResult, LoopSettings, Lubricant};

/// What the loop's outputs are made of.
pub struct LoopOutputs<'a> {
    /// Output directory.
    pub out: &'a Path,
    /// Roll angle of every position (deg).
    pub angles: &'a [f64],
    pub result: &'a LoopResult,
    /// The contact solver's normal force per position and pair, per pass (N).
    pub pass_forces: &'a [Vec<Vec<f64>>],
    /// (pinion tooth, gear tooth) of every pair.
    pub teeth: &'a [(usize, usize)],
    pub settings: &'a LoopSettings,
    pub lubricant: &'a Lubricant,
    /// Angular pitch of the pinion (deg), its speed (rpm) and torque (N·mm).
    pub pitch_deg: f64,
    pub speed_rpm: f64,
    pub torque_nmm: f64,
    /// Poisson's ratio of the flanks (the mean of both bodies').
    pub poisson: f64,
    /// E′ (MPa) and the contact line length L (mm) of the operating points
    /// (`None` for point contacts, whose length is each contact's own).
    pub reduced_modulus_mpa: f64,
    pub contact_length_mm: Option<f64>,
    /// Bevel/hypoid point contacts (elliptical Hertz contacts).
    pub point_contact: bool,
}

/// The `lubrication` object of `summary.json` (`flank ltca` and `flank
/// run` with `[analyses.lubrication]`).
#[derive(Clone, Debug, Serialize)]
pub struct LubricationSummary {
    /// Wet passes run, and whether μ settled within the tolerance.
    pub iterations: usize,
    pub converged: bool,
    /// Largest and smallest μ of the final pass's contacts.
    pub mu_max: f64,
    pub mu_min: Option<f64>,
    /// Largest relative change of μ in the last pass.
    pub mu_last_change_rel: f64,
    /// Change of the largest subsurface shear, last wet pass against the
    /// dry one, over the positions (%).
    pub subsurface_change_max_pct: Option<f64>,
    pub subsurface_change_min_pct: Option<f64>,
    /// How the subsurface shear is computed.
    pub subsurface_stress: &'static str,
    /// Mesh power loss (W, mean over one pitch), efficiency 1 − P/(T ω₁),
    /// input power (W) and the positions of the mean.
    pub power_loss_w: f64,
    pub efficiency: f64,
    pub input_power_w: f64,
    pub power_loss_positions: usize,
    /// The loop's settings.
    pub initial_mu: f64,
    pub tolerance: f64,
    pub max_iterations: usize,
    pub film_model: &'static str,
    pub mean_pressure: &'static str,
    /// E′ (MPa) and the contact length L (mm) of the operating points
    /// (line contacts; `None` for point contacts).
    pub reduced_modulus_mpa: f64,
    pub contact_length_mm: Option<f64>,
    /// The lubricant, in internal units.
    pub lubricant: Lubricant,
    /// Contacts of the final pass, and how many carry each flag.
    pub flags: FlagCounts,
    /// Every pass.
    pub passes: Vec<PassSummary>,
    /// The files written.
    pub files: LoopFiles,
    pub notes: Vec<String>,
    pub warnings: Vec<String>,
    /// What the LTCA's loop adds (absent for the FE loop).
    #[serde(flatten, skip_serializing_if = "Option::is_none")]
    pub ltca: Option<LtcaLoopFigures>,
}

/// Contacts of the final pass and the count of each flag.
#[derive(Clone, Debug, Serialize)]
pub struct FlagCounts {
    pub contacts: usize,
    pub outside_ellipticity_range: usize,
    pub point_contact_in_line_fit: usize,
    pub not_eyring: usize,
    pub isothermal_below_thermal: usize,
    pub thermal_formula_not_positive: usize,
    pub outside_path: usize,
}

/// One pass of the loop.
#[derive(Clone, Debug, Serialize)]
pub struct PassSummary {
    /// 0 is the dry pass.
    pub pass: usize,
    /// `dry` or `wet`.
    pub kind: &'static str,
    /// Largest μ used, and largest μ from the EHL of this pass.
    pub mu_used_max: f64,
    pub mu_ehl_max: f64,
    /// Largest relative change of μ against the pass before, and where.
    pub mu_change_rel: f64,
    pub mu_change_at: Option<MuChangeAt>,
    /// Normal force per position and tooth pair (N).
    pub pair_force_n: Vec<Vec<f64>>,
}

/// Where μ changed most.
#[derive(Clone, Debug, Serialize)]
pub struct MuChangeAt {
    pub roll_deg: f64,
    pub tooth_pair: usize,
}

/// The loop's files.
#[derive(Clone, Debug, Serialize)]
pub struct LoopFiles {
    pub csv: [&'static str; 2],
    pub plots: Vec<String>,
}

/// What the LTCA's loop adds to [`LubricationSummary`].
#[derive(Clone, Debug, Serialize)]
pub struct LtcaLoopFigures {
    /// `"ltca"`.
    pub solver: &'static str,
    /// The friction model of the passes.
    pub friction_model: crate::settings::FrictionModel,
    /// How the contact area A of P̄ = W/A is summed.
    pub contact_area: &'static str,
    /// Wall time of each wet pass and of the whole loop (s).
    pub wet_pass_s: Vec<f64>,
    pub loop_s: f64,
    /// Positions of the final pass whose KKT residual is above tolerance.
    pub final_pass_flagged: Vec<String>,
}

/// Writes the CSV files and plots and returns the `lubrication` object.
pub fn write_loop_outputs(o: &LoopOutputs) -> Result<LubricationSummary, FlankError> {
    let result = o.result;
    let angles = o.angles;
    let settings = o.settings;
    let np = o.teeth.len();
    let last = result.last();
    write_contacts_csv(&o.out.join("lubrication.csv"), angles, &last.contacts)?;
    write_passes_csv(&o.out.join("lubrication_passes.csv"), angles, result)?;

    // cycle power loss: mean over one angular pitch around roll 0
    let pitch = o.pitch_deg;
    let loss: Vec<f64> = last
        .contacts
        .iter()
        .map(|row| row.iter().flatten().map(|c| c.power_loss_w).sum())
        .collect();
    let window: Vec<usize> = (0..angles.len())
        .filter(|&i| angles[i] >= -0.5 * pitch && angles[i] < 0.5 * pitch)
        .collect();
    let mut notes = Vec::new();
    let used: Vec<usize> = if window.len() >= 2 {
        window
    } else {
        notes.push(format!(
            "fewer than two positions within one angular pitch ({pitch:.3}°) around roll 0: the power loss is the mean over all {} positions",
            angles.len()
        ));
        (0..angles.len()).collect()
    };
    let power_loss_w = used.iter().map(|&i| loss[i]).sum::<f64>() / used.len().max(1) as f64;
    let omega1 = o.speed_rpm * std::f64::consts::PI / 30.0;
    let input_power_w = o.torque_nmm * omega1 * 1e-3;
    let efficiency = 1.0 - power_loss_w / input_power_w;
    let all: Vec<&ContactEhl> = last.contacts.iter().flatten().flatten().collect();
    let mu_max = all.iter().map(|c| c.traction.mu).fold(0.0f64, f64::max);
    let mu_min = all
        .iter()
        .map(|c| c.traction.mu)
        .fold(f64::INFINITY, f64::min);
    // largest subsurface shear under each contact, dry pass against the
    // last wet pass (seed 002 Fig. 10): the Hertz peak p₀ of the operating
    // point (line: √(w′ E′ / (2π R_x)), Johnson eq. 4.45 with E′ = 2E*;
    // ellipse: 3W/(2πab); not the FE contact area, which one or two node
    // rows resolve) times the McEwen/Smith–Liu maximum for the μ the pass
    // used
    let nu = o.poisson;
    let tau_max = |pass: &crate::lubrication::wet_dry::Pass, i: usize, p: usize| -> Option<f64> {
        let c = pass.contacts[i][p].as_ref()?;
        let p0 = c.point.hertz_peak_mpa;
        if !(p0.is_finite() && p0 > 0.0) {
            return None;
        }
        let mu = pass.mu_used[i][p].abs();
        Some(p0 * crate::lubrication::subsurface::max_subsurface_shear(mu, nu))
    };
    let dry = &result.passes[0];
    // per position: the largest over its contacts (as the paper's Fig. 10)
    let position_max = |pass: &crate::lubrication::wet_dry::Pass, i: usize| -> Option<f64> {
        (0..np).filter_map(|p| tau_max(pass, i, p)).reduce(f64::max)
    };
    let subsurface_change_pct: Vec<f64> = (0..angles.len())
        .filter_map(|i| {
            let (d, w) = (position_max(dry, i)?, position_max(last, i)?);
            (d > 0.0).then(|| 100.0 * (w / d - 1.0))
        })
        .collect();
    let count = |f: &dyn Fn(&ContactEhl) -> bool| all.iter().filter(|c| f(c)).count();
    use crate::lubrication::{FilmFlag, TractionFlag};
    let flags = FlagCounts {
        contacts: all.len(),
        outside_ellipticity_range: count(&|c| {
            c.film.flags.contains(&FilmFlag::OutsideEllipticityRange)
        }),
        point_contact_in_line_fit: count(&|c| {
            c.film.flags.contains(&FilmFlag::PointContactInLineFit)
        }),
        not_eyring: count(&|c| c.traction.flags.contains(&TractionFlag::NotEyring)),
        isothermal_below_thermal: count(&|c| {
            c.traction
                .flags
                .contains(&TractionFlag::IsothermalBelowThermal)
        }),
        thermal_formula_not_positive: count(&|c| {
            c.traction
                .flags
                .contains(&TractionFlag::ThermalFormulaNotPositive)
        }),
        outside_path: count(&|c| c.point.outside_path),
    };
    // plots
    let series = |f: &dyn Fn(&ContactEhl) -> f64| -> Vec<(String, Vec<(f64, f64)>)> {
        (0..np)
            .map(|p| {
                let (k, m) = o.teeth[p];
                (
                    format!("pinion tooth {k} / gear tooth {m}"),
                    (0..angles.len())
                        .filter_map(|i| last.contacts[i][p].as_ref().map(|c| (angles[i], f(c))))
                        .collect(),
                )
            })
            .collect()
    };
    let mut files = Vec::new();
    for (stem, title, y, f) in [
        (
            "lubrication_mu",
            "Traction coefficient (Evans & Johnson), wet pass",
            "μ",
            (&|c: &ContactEhl| c.traction.mu) as &dyn Fn(&ContactEhl) -> f64,
        ),
        (
            "lubrication_film",
            "Central film thickness",
            "h_c (µm)",
            &|c: &ContactEhl| c.film.central * 1e3,
        ),
        (
            "lubrication_power_loss",
            "Sliding power loss μ W |v_s|",
            "power loss (W)",
            &|c: &ContactEhl| c.power_loss_w,
        ),
    ] {
        match crate::report::cycle_plot::plot_series(
            o.out,
            stem,
            title,
            "pinion roll angle (deg)",
            y,
            &series(f),
        ) {
            Ok(v) => files.extend(v),
            Err(e) => notes.push(format!("plot {stem} not written: {e}")),
        }
    }
    let passes: Vec<PassSummary> = result
        .passes
        .iter()
        .zip(o.pass_forces)
        .map(|(p, f)| PassSummary {
            pass: p.index,
            kind: if p.index == 0 { "dry" } else { "wet" },
            mu_used_max: p.mu_used.iter().flatten().fold(0.0f64, |a, &b| a.max(b)),
            mu_ehl_max: p
                .contacts
                .iter()
                .flatten()
                .flatten()
                .map(|c| c.traction.mu)
                .fold(0.0f64, f64::max),
            mu_change_rel: p.change_rel,
            mu_change_at: p.change_at.map(|(i, q)| MuChangeAt {
                roll_deg: angles[i],
                tooth_pair: q + 1,
            }),
            pair_force_n: f.clone(),
        })
        .collect();
    Ok(LubricationSummary {
        iterations: result.iterations,
        converged: result.converged,
        mu_max,
        mu_min: mu_min.is_finite().then_some(mu_min),
        mu_last_change_rel: result.mu_last_change_rel,
        subsurface_change_max_pct: subsurface_change_pct.iter().cloned().reduce(f64::max),
        subsurface_change_min_pct: subsurface_change_pct.iter().cloned().reduce(f64::min),
        subsurface_stress: if o.point_contact {
            "per position the largest principal shear below its contacts: the elliptical Hertz peak p₀ = 3W/(2πab) times the line-contact maximum for the pass's sliding friction (McEwen 1949, Smith & Liu 1953; lubrication::subsurface; an approximation for an ellipse), last wet pass against the dry pass"
        } else {
            "per position the largest principal shear below its contacts, Hertz line contacts with the pass's sliding friction (McEwen 1949, Smith & Liu 1953; lubrication::subsurface), last wet pass against the dry pass"
        },
        power_loss_w,
        efficiency,
        input_power_w,
        power_loss_positions: used.len(),
        initial_mu: settings.initial_mu,
        tolerance: settings.tolerance,
        max_iterations: settings.max_iterations,
        film_model: settings.film.name(),
        mean_pressure: settings.mean_pressure.name(),
        reduced_modulus_mpa: o.reduced_modulus_mpa,
        contact_length_mm: o.contact_length_mm,
        lubricant: o.lubricant.clone(),
        flags,
        passes,
        files: LoopFiles {
            csv: ["lubrication.csv", "lubrication_passes.csv"],
            plots: files,
        },
        notes,
        warnings: result.warnings.clone(),
        ltca: None,
    })
}

fn flag_text(c: &ContactEhl) -> String {
    let mut v: Vec<String> = c
        .film
        .flags
        .iter()
        .map(|f| format!("{f:?}"))
        .chain(c.traction.flags.iter().map(|f| format!("{f:?}")))
        .collect();
    if c.point.outside_path {
        v.push("OutsidePath".into());
    }
    v.join(" ")
}

fn write_contacts_csv(
    path: &Path,
    angles: &[f64],
    contacts: &[Vec<Option<ContactEhl>>],
) -> Result<(), FlankError> {
    use std::fmt::Write as _;
    let mut s = String::from("roll_deg,tooth_pair,load_n,mean_pressure_mpa,other_mean_pressure_mpa,radius_x_mm,radius_y_mm,entraining_speed_m_s,sliding_speed_m_s,slide_to_roll,central_film_um,minimum_film_um,lambda_ratio,zeta,mu,mu_thermal,friction_force_n,power_loss_w,flags\n");
    for (i, row) in contacts.iter().enumerate() {
        for (p, c) in row.iter().enumerate() {
            let Some(c) = c else { continue };
            let o = &c.point;
            let _ = writeln!(
                s,
                "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
                angles[i],
                p + 1,
                o.load_n,
                o.mean_pressure_mpa,
                o.other_mean_pressure_mpa,
                o.radius_x_mm,
                if o.radius_y_mm.is_finite() {
                    o.radius_y_mm.to_string()
                } else {
                    "line".into()
                },
                o.entraining_speed_mm_s * 1e-3,
                o.sliding_speed_mm_s * 1e-3,
                o.slide_to_roll(),
                c.film.central * 1e3,
                c.film.minimum * 1e3,
                c.lambda_ratio.map_or(String::new(), |l| l.to_string()),
                c.traction.zeta,
                c.traction.mu,
                c.traction.mu_thermal,
                c.friction_force_n,
                c.power_loss_w,
                flag_text(c)
            );
        }
    }
    crate::atomic_file::write(path, s)
}

fn write_passes_csv(path: &Path, angles: &[f64], r: &LoopResult) -> Result<(), FlankError> {
    use std::fmt::Write as _;
    let mut s = String::from("pass,roll_deg,tooth_pair,mu_used,mu_ehl,load_n,central_film_um\n");
    for pass in &r.passes {
        for (i, row) in pass.contacts.iter().enumerate() {
            for (p, c) in row.iter().enumerate() {
                let Some(c) = c else { continue };
                let _ = writeln!(
                    s,
                    "{},{},{},{},{},{},{}",
                    pass.index,
                    angles[i],
                    p + 1,
                    pass.mu_used[i][p],
                    c.traction.mu,
                    c.point.load_n,
                    c.film.central * 1e3
                );
            }
        }
    }
    crate::atomic_file::write(path, s)
}
