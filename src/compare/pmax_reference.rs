//! The p_max reference of `flank compare`: FE contact with **contact bands**
//! (`flank run … --contact-band SIZE`, `OUT/contact_band.json`,
//! [`crate::mesh_cycle::contact_band`]), whose rows resolve the Hertz width
//! where the uniform FE meshes of the comparison do not
//! (verification/contact_band).
//!
//! The band runs are grouped by roll angle; per roll angle and loaded tooth
//! pair, the FE p_max of the band sizes is extrapolated to h → 0 as the
//! load shares are in [`super::reference`]: with three sizes or more,
//! Richardson from the three finest with GCI_fine (Celik et al. 2008,
//! F_s = 1.25, [`crate::grid_convergence::gci`]); an observed order outside
//! [`ORDER_RANGE`] or no order keeps the finest value with 3 × the data
//! range as uncertainty (Eça & Hoekstra 2014). Here two more cases fall
//! back: a **non-monotone** sequence (changes of alternating sign give an
//! order but no asymptotic range) and changes that **grow** under
//! refinement, which Celik's eq. (2) turns into a positive order through
//! its absolute value ([`crate::grid_convergence::gci`] says
//! `Diverging` there). With fewer than
//! three sizes the finest value stands, its uncertainty the data range
//! (none with one size), flagged.
//!
//! The figure is the FE's largest face-averaged pressure **over the
//! flank** (`p_max_mpa`): the LTCA's p_max is its largest Hertz peak over
//! the pair's points, wherever along the face. The value at the node row
//! nearest mid face (`p_max_mid_face_mpa`) is extrapolated the same way
//! and reported beside it.
//!
//! Pairs are matched through the kinematic contact points: each band
//! run's contacts (pinion and gear radius, nominal Hertz half-width) must
//! be the compare scene's at that roll angle ([`band_contacts`]), which
//! maps the run's pinion tooth (a one-tooth sector numbers its tooth 1) to
//! the scene's, the LTCA's pair numbering; a run of another scene or load
//! is refused there.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use super::reference::{data_range, estimate, ORDER_RANGE};
use crate::error::FlankError;
use crate::grid_convergence::GciIssue;
use crate::ltca::model::PositionResult;
use crate::mesh_cycle::contact_band::{band_contacts, BandContact};
use crate::scene::Scene;

/// Relative tolerance on contact radii and half-widths when matching a
/// band run's contacts with the scene's (both from the same closed-form
/// involute geometry: only round-off differs).
const GEOMETRY_TOLERANCE: f64 = 1e-6;
/// Roll angles closer than this (deg) are one position.
const ROLL_TOLERANCE: f64 = 1e-6;

/// The fields of a `contact_band.json` position that are read.
#[derive(serde::Deserialize)]
struct BandRun {
    roll_deg: f64,
    band_size_mm: Option<f64>,
    contacts: Vec<BandContactIn>,
    pairs: Vec<BandPairIn>,
}

#[derive(serde::Deserialize)]
struct BandContactIn {
    pinion_tooth: usize,
    radius_mm: [f64; 2],
    nominal_half_width_mm: f64,
}

#[derive(serde::Deserialize)]
struct BandPairIn {
    pinion_tooth: usize,
    force_n: f64,
    load_share: f64,
    hertz_p0_mpa: Option<f64>,
    p_max_mpa: f64,
    p_max_mid_face_mpa: f64,
    elements_across_2b: Option<f64>,
}

/// One figure from the band sizes: reference value, relative uncertainty,
/// observed order (NaN where none was used) and how it was obtained.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Extrapolated {
    pub value_mpa: f64,
    #[serde(serialize_with = "nan_as_null")]
    pub uncertainty: f64,
    #[serde(serialize_with = "nan_as_null")]
    pub order: f64,
    /// `richardson`, `finest: order outside 0.5–4`, `finest: no order`,
    /// `finest: not monotone`, `finest: changes grow`, `finest: fewer than
    /// 3 bands`.
    pub method: String,
}

fn nan_as_null<S: serde::Serializer>(x: &f64, s: S) -> Result<S::Ok, S::Error> {
    if x.is_finite() {
        s.serialize_f64(*x)
    } else {
        s.serialize_none()
    }
}

/// The reference at one roll angle and tooth pair.
#[derive(Clone, Debug, serde::Serialize)]
pub struct PmaxReferencePair {
    pub roll_deg: f64,
    /// Pinion tooth of the scene's sector (the LTCA's pair numbering).
    pub pair: usize,
    /// Band sizes, finest first (mm), and the FE p_max at each (MPa): over
    /// the flank and at mid face (face-averaged).
    pub band_sizes_mm: Vec<f64>,
    pub p_max_mpa: Vec<f64>,
    pub p_max_mid_face_mpa: Vec<f64>,
    /// The reference: p_max over the flank extrapolated (uncertainty
    /// relative to the finest band's value, as GCI_fine); beside it the
    /// mid-face value extrapolated the same way.
    pub reference: Extrapolated,
    pub mid_face: Extrapolated,
    /// The finest band's load share, Hertz p₀ of its line load and
    /// elements across 2b.
    pub load_share: f64,
    #[serde(serialize_with = "nan_as_null")]
    pub hertz_p0_mpa: f64,
    #[serde(serialize_with = "nan_as_null")]
    pub elements_across_2b: f64,
    pub files: Vec<String>,
}

/// The contact-band reference: every (roll angle, pair) of the runs given.
#[derive(Clone, Debug, serde::Serialize)]
pub struct PmaxReference {
    pub pairs: Vec<PmaxReferencePair>,
}

impl PmaxReference {
    /// The roll angles (deg), ascending, once each.
    pub fn roll_angles(&self) -> Vec<f64> {
        let mut a: Vec<f64> = self.pairs.iter().map(|p| p.roll_deg).collect();
        a.dedup_by(|x, y| (*x - *y).abs() < ROLL_TOLERANCE);
        a
    }
}

/// `DIR` → `DIR/contact_band.json`; a file as it is.
fn band_file(p: &Path) -> PathBuf {
    if p.is_dir() {
        p.join("contact_band.json")
    } else {
        p.to_path_buf()
    }
}

fn err(file: &Path, m: impl std::fmt::Display) -> FlankError {
    FlankError::Model(format!("--pmax-reference {}: {m}", file.display()))
}

/// The scene's pinion tooth of `c`, a band run's contact: the scene
/// contact at the same pinion and gear radius and nominal half-width.
fn scene_tooth(
    file: &Path,
    roll: f64,
    c: &BandContactIn,
    scene: &[BandContact],
) -> Result<usize, FlankError> {
    let close = |a: f64, b: f64| (a - b).abs() <= GEOMETRY_TOLERANCE * a.abs().max(b.abs());
    scene
        .iter()
        .find(|s| {
            close(s.radius_mm[0], c.radius_mm[0])
                && close(s.radius_mm[1], c.radius_mm[1])
                && close(s.nominal_half_width_mm, c.nominal_half_width_mm)
        })
        .map(|s| s.pinion_tooth)
        .ok_or_else(|| {
            let have: Vec<String> = scene
                .iter()
                .map(|s| {
                    format!(
                        "tooth {}: r {:.4} / {:.4} mm, b {:.4} mm",
                        s.pinion_tooth, s.radius_mm[0], s.radius_mm[1], s.nominal_half_width_mm
                    )
                })
                .collect();
            err(
                file,
                format!(
                    "roll {roll}°: the run's contact of pinion tooth {} (r {:.4} / {:.4} mm, nominal b {:.4} mm) is none of the scene's kinematic contacts there ({}): a run of another scene, load or material",
                    c.pinion_tooth,
                    c.radius_mm[0],
                    c.radius_mm[1],
                    c.nominal_half_width_mm,
                    if have.is_empty() { "none".into() } else { have.join("; ") }
                ),
            )
        })
}

/// One band run at one position, its pairs in the scene's numbering:
/// (pair, p_max, p_max mid face, share, Hertz p₀, elements across 2b).
type RunPairs = Vec<(usize, f64, f64, f64, f64, f64)>;
/// Per roll angle (key: the angle in units of [`ROLL_TOLERANCE`]): the
/// angle and its runs (band size, file, pairs).
type Groups = BTreeMap<i64, (f64, Vec<(f64, PathBuf, RunPairs)>)>;

/// Reads the band runs `paths` (directories holding `contact_band.json`,
/// or the files) for `scene` and builds the reference (module docs).
pub fn load(paths: &[PathBuf], scene: &Scene) -> Result<PmaxReference, FlankError> {
    let mut groups = Groups::new();
    for p in paths {
        let file = band_file(p);
        let text = std::fs::read_to_string(&file).map_err(|e| {
            err(
                &file,
                format!(
                    "{e} (a contact_band.json of `flank run --contact-band`, or its directory)"
                ),
            )
        })?;
        let runs: Vec<BandRun> = serde_json::from_str(&text).map_err(|e| {
            err(
                &file,
                format!(
                    "not a contact-band output (`flank run --contact-band` writes a list of positions with roll_deg, band_size_mm, contacts, pairs): {e}"
                ),
            )
        })?;
        if runs.is_empty() {
            return Err(err(&file, "no position in it"));
        }
        for r in runs {
            let Some(h) = r.band_size_mm.filter(|h| *h > 0.0 && h.is_finite()) else {
                return Err(err(
                    &file,
                    format!(
                        "roll {}°: no contact band (band_size_mm {:?}): a plain mesh is no band size to extrapolate from",
                        r.roll_deg, r.band_size_mm
                    ),
                ));
            };
            let scene_contacts = band_contacts(scene, r.roll_deg)?;
            let mut pairs = RunPairs::new();
            for q in &r.pairs {
                // loaded pairs in kinematic flank contact (Hertz p₀ known)
                let Some(p0) = q.hertz_p0_mpa.filter(|_| q.force_n > 0.0) else {
                    continue;
                };
                let Some(c) = r.contacts.iter().find(|c| c.pinion_tooth == q.pinion_tooth) else {
                    return Err(err(
                        &file,
                        format!(
                            "roll {}°: pair of pinion tooth {} has a Hertz p₀ but no contact entry",
                            r.roll_deg, q.pinion_tooth
                        ),
                    ));
                };
                let k = scene_tooth(&file, r.roll_deg, c, &scene_contacts)?;
                pairs.push((
                    k,
                    q.p_max_mpa,
                    q.p_max_mid_face_mpa,
                    q.load_share,
                    p0,
                    q.elements_across_2b.unwrap_or(f64::NAN),
                ));
            }
            pairs.sort_by_key(|x| x.0);
            let key = (r.roll_deg / ROLL_TOLERANCE).round() as i64;
            let g = groups.entry(key).or_insert((r.roll_deg, Vec::new()));
            if let Some((_, other, _)) = g.1.iter().find(|(x, _, _)| (x - h).abs() < 1e-12) {
                return Err(err(
                    &file,
                    format!(
                        "roll {}°: band {h} mm given twice (also in {})",
                        r.roll_deg,
                        other.display()
                    ),
                ));
            }
            g.1.push((h, file.clone(), pairs));
        }
    }
    let mut out = Vec::new();
    for (_, (roll, mut runs)) in groups {
        runs.sort_by(|a, b| a.0.total_cmp(&b.0));
        let teeth: Vec<usize> = runs[0].2.iter().map(|x| x.0).collect();
        for (_, file, pairs) in &runs[1..] {
            let t: Vec<usize> = pairs.iter().map(|x| x.0).collect();
            if t != teeth {
                return Err(err(
                    file,
                    format!(
                        "roll {roll}°: loaded pairs {t:?} (scene numbering) differ from {:?} in {}",
                        teeth,
                        runs[0].1.display()
                    ),
                ));
            }
        }
        if teeth.is_empty() {
            return Err(err(
                &runs[0].1,
                format!("roll {roll}°: no loaded pair in kinematic flank contact"),
            ));
        }
        let h: Vec<f64> = runs.iter().map(|r| r.0).collect();
        for (i, &k) in teeth.iter().enumerate() {
            let over: Vec<f64> = runs.iter().map(|r| r.2[i].1).collect();
            let mid: Vec<f64> = runs.iter().map(|r| r.2[i].2).collect();
            let fine = &runs[0].2[i];
            out.push(PmaxReferencePair {
                roll_deg: roll,
                pair: k,
                band_sizes_mm: h.clone(),
                reference: extrapolate(&h, &over),
                mid_face: extrapolate(&h, &mid),
                p_max_mpa: over,
                p_max_mid_face_mpa: mid,
                load_share: fine.3,
                hertz_p0_mpa: fine.4,
                elements_across_2b: fine.5,
                files: runs.iter().map(|r| r.1.display().to_string()).collect(),
            });
        }
    }
    Ok(PmaxReference { pairs: out })
}

/// One figure at band sizes `h` (finest first) with values `phi`.
fn extrapolate(h: &[f64], phi: &[f64]) -> Extrapolated {
    let range = phi.iter().copied().fold(f64::NEG_INFINITY, f64::max)
        - phi.iter().copied().fold(f64::INFINITY, f64::min);
    if h.len() < 3 {
        return Extrapolated {
            value_mpa: phi[0],
            uncertainty: if h.len() == 2 {
                range / phi[0].abs()
            } else {
                f64::NAN
            },
            order: f64::NAN,
            method: "finest: fewer than 3 bands".into(),
        };
    }
    let (h3, p3) = ([h[0], h[1], h[2]], [phi[0], phi[1], phi[2]]);
    let (x, u, order, fell, issue) = estimate(h3, p3);
    let oscillating = (p3[0] - p3[1]) * (p3[1] - p3[2]) < 0.0;
    let (value, u, method) = if oscillating {
        (p3[0], data_range(p3), "finest: not monotone".to_string())
    } else if matches!(issue, Some(GciIssue::Diverging(_))) {
        (x, u, "finest: changes grow".to_string())
    } else if fell && order.is_finite() {
        (
            x,
            u,
            format!("finest: order outside {}–{}", ORDER_RANGE.0, ORDER_RANGE.1),
        )
    } else if fell {
        (x, u, "finest: no order".to_string())
    } else {
        (x, u, "richardson".to_string())
    };
    // relative to the finest value, as GCI_fine is (Celik et al. 2008, eq. 10)
    Extrapolated {
        value_mpa: value,
        uncertainty: u / p3[0].abs(),
        order: if method == "richardson" {
            order
        } else {
            f64::NAN
        },
        method,
    }
}

/// The LTCA's p_max of `pair` (pinion tooth, 1-based): the largest Hertz
/// peak over the points of that pair's lines (MPa; 0 without any).
pub fn ltca_pair_pmax(r: &PositionResult, pair: usize) -> f64 {
    r.points
        .iter()
        .filter(|p| r.lines.get(p.line).is_some_and(|l| l.0 == pair))
        .map(|p| p.pressure_mpa)
        .fold(0.0, f64::max)
}

/// One LTCA run's p_max at the reference's entries and its error.
#[derive(Clone, Debug, serde::Serialize)]
pub struct PmaxRun {
    pub label: String,
    /// Per reference entry: the LTCA's p_max of that pair (MPa), its load
    /// share, and (p_L − p_ref)/p_ref.
    pub p_max_mpa: Vec<f64>,
    pub load_share: Vec<f64>,
    pub rel_err: Vec<f64>,
    /// max |rel_err|.
    pub max_rel_err: f64,
}

/// `label`'s run at the reference entries from its position results
/// `results` at [`PmaxReference::roll_angles`] and its pair forces.
pub fn ltca_against(
    reference: &PmaxReference,
    label: &str,
    results: &[(f64, PositionResult, Vec<f64>)],
) -> PmaxRun {
    let mut p_max = Vec::new();
    let mut share = Vec::new();
    let mut rel = Vec::new();
    for e in &reference.pairs {
        let (p, s) = results
            .iter()
            .find(|(a, _, _)| (a - e.roll_deg).abs() < ROLL_TOLERANCE)
            .map_or((f64::NAN, f64::NAN), |(_, r, f)| {
                let total: f64 = f.iter().sum();
                let fp = f.get(e.pair - 1).copied().unwrap_or(0.0);
                (
                    ltca_pair_pmax(r, e.pair),
                    if total > 0.0 { fp / total } else { 0.0 },
                )
            });
        p_max.push(p);
        share.push(s);
        rel.push((p - e.reference.value_mpa) / e.reference.value_mpa);
    }
    PmaxRun {
        label: label.to_string(),
        max_rel_err: rel.iter().map(|x| x.abs()).fold(0.0, f64::max),
        p_max_mpa: p_max,
        load_share: share,
        rel_err: rel,
    }
}

/// The p_max section of `compare.md`.
pub fn markdown(s: &mut String, reference: &PmaxReference, runs: &[PmaxRun]) {
    use std::fmt::Write;
    let _ = writeln!(s, "\n## p_max against the contact-band FE reference\n");
    let _ = writeln!(
        s,
        "Reference: FE contact with contact bands (`flank run --contact-band`, verification/contact_band), the largest face-averaged pressure **over the flank** per pair, per roll angle Richardson-extrapolated from the three finest bands with GCI_fine (Celik et al. 2008, F_s = 1.25); an order outside {}–{}, no order, a non-monotone sequence or changes that grow under refinement keep the finest band's value with 3 × the data range as uncertainty; fewer than three bands: the finest value, uncertainty the data range. The mid-face value (node row nearest mid face width) is extrapolated the same way and shown beside it. The LTCA's p_max is the largest Hertz peak over the pair's points, solved at these roll angles. Pairs: pinion tooth of the scene's sector. The summary's p_max error of the LTCA runs is the largest |error| of this table.\n",
        ORDER_RANGE.0, ORDER_RANGE.1
    );
    let mut head = "| roll (°) | pair | FE share | bands (mm) | reference p_max (MPa) | GCI | order | how | mid face (MPa) | Hertz p₀ (MPa) | 2b/size |".to_string();
    let mut rule = "|---:|---:|---:|---|---:|---:|---:|---|---:|---:|---:|".to_string();
    for r in runs {
        head += &format!(" {} (MPa) | err |", r.label);
        rule += "---:|---:|";
    }
    let _ = writeln!(s, "{head}\n{rule}");
    let pct = |x: f64| {
        if x.is_finite() {
            format!("{:.1} %", 100.0 * x)
        } else {
            "—".into()
        }
    };
    for (i, e) in reference.pairs.iter().enumerate() {
        let bands: Vec<String> = e.band_sizes_mm.iter().map(|h| format!("{h}")).collect();
        let order = if e.reference.order.is_finite() {
            format!("{:.2}", e.reference.order)
        } else {
            "—".into()
        };
        let mut row = format!(
            "| {:.3} | {} | {:.3} | {} | {:.0} | {} | {} | {} | {:.0} ± {} | {:.0} | {:.1} |",
            e.roll_deg,
            e.pair,
            e.load_share,
            bands.join(" / "),
            e.reference.value_mpa,
            pct(e.reference.uncertainty),
            order,
            e.reference.method,
            e.mid_face.value_mpa,
            pct(e.mid_face.uncertainty),
            e.hertz_p0_mpa,
            e.elements_across_2b
        );
        for r in runs {
            row += &format!(" {:.0} | {:+.1} % |", r.p_max_mpa[i], 100.0 * r.rel_err[i]);
        }
        let _ = writeln!(s, "{row}");
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::read_scene;

    fn scene() -> Scene {
        read_scene(Path::new("papers/seed002-spur/scene.toml")).unwrap()
    }

    fn temp_dir(tag: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("flank_pmax_ref_{tag}_{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    /// A contact_band.json at `roll` with band `h`: the scene's contacts,
    /// renumbered from 1 when `one_tooth` (a one-tooth sector), pair
    /// pressures from `p(pinion tooth of the scene, h)`.
    fn band_json(
        s: &Scene,
        roll: f64,
        h: f64,
        one_tooth: bool,
        p: impl Fn(usize, f64) -> f64,
    ) -> String {
        let contacts = band_contacts(s, roll).unwrap();
        let number = |k: usize| if one_tooth { 1 } else { k };
        let c: Vec<_> = contacts
            .iter()
            .map(|c| {
                serde_json::json!({
                    "pinion_tooth": number(c.pinion_tooth), "gear_tooth": c.gear_tooth,
                    "radius_mm": c.radius_mm, "curvature_radius_mm": c.curvature_radius_mm,
                    "equivalent_radius_mm": c.equivalent_radius_mm,
                    "nominal_half_width_mm": c.nominal_half_width_mm,
                })
            })
            .collect();
        let share = 1.0 / contacts.len() as f64;
        let pairs: Vec<_> = contacts
            .iter()
            .map(|c| {
                serde_json::json!({
                    "pinion_tooth": number(c.pinion_tooth), "force_n": 1000.0, "load_share": share,
                    "line_load_n_per_mm": 75.0, "hertz_p0_mpa": 2000.0,
                    "hertz_half_width_mm": 0.2, "p_max_mpa": p(c.pinion_tooth, h),
                    "p_max_mid_face_mpa": p(c.pinion_tooth, h) - 10.0,
                    "p_max_nodal_mpa": 3000.0, "closed_nodes_mid_face": 5,
                    "elements_across_2b": 0.4 / h,
                })
            })
            .collect();
        serde_json::json!([{
            "roll_deg": roll, "band_size_mm": h, "contacts": c, "bands": [[], []],
            "pairs": pairs, "te_urad": 4000.0, "nodes": 1, "dofs": 3,
            "min_scaled_jacobian": 0.7, "max_aspect_ratio": 30.0,
            "setup_s": 1.0, "solve_s": 1.0, "peak_memory_mb": 100.0,
        }])
        .to_string()
    }

    /// p = P − C h^1.3 on bands 0.2 / 0.1 / 0.05 at a single-contact
    /// position written as one-tooth sectors (tooth 1), and two bands at a
    /// double-contact one: grouped per roll angle, the one-tooth run's
    /// pair mapped to the scene's middle tooth, P recovered with order 1.3;
    /// two bands keep the finest value with the data range.
    #[test]
    fn groups_by_roll_maps_pairs_and_extrapolates() {
        let s = scene();
        let d = temp_dir("ok");
        let p = |k: usize, h: f64| 2400.0 + 10.0 * k as f64 - 500.0 * h.powf(1.3);
        let mut paths = Vec::new();
        for h in [0.1, 0.05, 0.2] {
            let dir = d.join(format!("single_{h}"));
            std::fs::create_dir_all(&dir).unwrap();
            std::fs::write(
                dir.join("contact_band.json"),
                band_json(&s, 5.415, h, true, p),
            )
            .unwrap();
            paths.push(dir);
        }
        for h in [0.1, 0.05] {
            let f = d.join(format!("double_{h}.json"));
            std::fs::write(&f, band_json(&s, -8.43, h, false, p)).unwrap();
            paths.push(f);
        }
        let r = load(&paths, &s).unwrap();
        assert_eq!(r.roll_angles(), [-8.43, 5.415]);
        let pairs: Vec<(f64, usize)> = r.pairs.iter().map(|e| (e.roll_deg, e.pair)).collect();
        assert_eq!(pairs, [(-8.43, 2), (-8.43, 3), (5.415, 2)]);
        let single = &r.pairs[2];
        assert_eq!(single.band_sizes_mm, [0.05, 0.1, 0.2]);
        assert_eq!(single.reference.method, "richardson");
        assert!(
            (single.reference.value_mpa - 2420.0).abs() < 1e-6,
            "{single:?}"
        );
        assert!((single.reference.order - 1.3).abs() < 1e-6);
        assert!((single.mid_face.value_mpa - 2410.0).abs() < 1e-6);
        // GCI_fine = F_s |φ1 − φ2| / φ1 / (r^p − 1)
        let (f1, f2) = (p(2, 0.05), p(2, 0.1));
        let expected = 1.25 * (f1 - f2).abs() / (2f64.powf(1.3) - 1.0) / f1;
        assert!((single.reference.uncertainty - expected).abs() < 1e-9);
        let double = &r.pairs[0];
        assert_eq!(double.reference.method, "finest: fewer than 3 bands");
        assert_eq!(double.reference.value_mpa, p(2, 0.05));
        let range = (p(2, 0.05) - p(2, 0.1)) / p(2, 0.05);
        assert!((double.reference.uncertainty - range).abs() < 1e-12);
        // the LTCA's error against it
        let run = ltca_against(&r, "LTCA K = 5", &[]);
        assert!(run.p_max_mpa.iter().all(|x| x.is_nan()));
        let mut md = String::new();
        markdown(&mut md, &r, &[run]);
        assert!(md.contains("| 5.415 | 2 |"), "{md}");
        assert!(md.contains("richardson"), "{md}");
        let _ = std::fs::remove_dir_all(&d);
    }

    /// Non-monotone band values fall back to the finest with 3 × the range.
    #[test]
    fn a_non_monotone_sequence_keeps_the_finest_band() {
        let x = extrapolate(&[0.05, 0.0707, 0.1], &[2340.5, 2248.5, 2283.5]);
        assert_eq!(x.method, "finest: not monotone");
        assert_eq!(x.value_mpa, 2340.5);
        assert!((x.uncertainty - 3.0 * 92.0 / 2340.5).abs() < 1e-12);
        assert!(x.order.is_nan());
        // monotone but growing changes (pair 3 mid face there)
        let x = extrapolate(&[0.05, 0.0707, 0.1], &[1528.4, 1482.6, 1448.3]);
        assert_eq!(x.method, "finest: changes grow");
        assert_eq!(x.value_mpa, 1528.4);
        assert!((x.uncertainty - 3.0 * 80.1 / 1528.4).abs() < 1e-9);
    }

    /// Missing files, other JSON, another scene's contacts, differing pair
    /// sets and a repeated band are errors naming the file, not panics.
    #[test]
    fn bad_inputs_are_errors_naming_the_file() {
        let s = scene();
        let d = temp_dir("bad");
        let p = |_: usize, h: f64| 2400.0 - 500.0 * h;
        let e = load(&[d.join("nothing")], &s).unwrap_err().to_string();
        assert!(
            e.contains("nothing") && e.contains("--pmax-reference"),
            "{e}"
        );
        let f = d.join("summary.json");
        std::fs::write(&f, r#"{"positions": 3}"#).unwrap();
        let e = load(std::slice::from_ref(&f), &s).unwrap_err().to_string();
        assert!(
            e.contains("summary.json") && e.contains("not a contact-band output"),
            "{e}"
        );
        // another load: the nominal half-width differs
        let mut v: serde_json::Value =
            serde_json::from_str(&band_json(&s, 5.415, 0.1, true, p)).unwrap();
        v[0]["contacts"][0]["nominal_half_width_mm"] = serde_json::json!(0.5);
        let f = d.join("other_load.json");
        std::fs::write(&f, v.to_string()).unwrap();
        let e = load(std::slice::from_ref(&f), &s).unwrap_err().to_string();
        assert!(
            e.contains("other_load.json") && e.contains("another scene"),
            "{e}"
        );
        // a single-contact run at −8.43° beside a double-contact one
        let mut v: serde_json::Value =
            serde_json::from_str(&band_json(&s, -8.43, 0.1, false, p)).unwrap();
        v[0]["pairs"][1]["force_n"] = serde_json::json!(0.0);
        let (a, b) = (d.join("a.json"), d.join("b.json"));
        std::fs::write(&a, band_json(&s, -8.43, 0.05, false, p)).unwrap();
        std::fs::write(&b, v.to_string()).unwrap();
        let e = load(&[a.clone(), b], &s).unwrap_err().to_string();
        assert!(e.contains("b.json") && e.contains("differ"), "{e}");
        let e = load(&[a.clone(), a], &s).unwrap_err().to_string();
        assert!(e.contains("given twice"), "{e}");
        let _ = std::fs::remove_dir_all(&d);
    }
}
