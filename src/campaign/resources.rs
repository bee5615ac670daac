//! Per-job memory estimates and the machine's cores and memory.
//!
//! flank has no a-priori memory model of its solvers, so the estimates are
//! rules fitted to measured peaks (`papers/seed002-spur/README.md`, 2-core
//! machine, peak resident set):
//!
//! * FE contact (`run`, `compare`) of a spur/helical pair: the seed 002
//!   mesh study gives DOFs = 194 844 / 242 478 / 490 200 / 1 252 842 at flank
//!   sizes h = 0.75 / 0.5 / 0.25 / 0.1 mm and peaks 1 666 / 2 077 / 4 737 /
//!   13 160 MB, i.e. DOFs ≈ 126 300 mm · S / h (within 1 % at 0.5, 0.25 and
//!   0.1 mm; the 0.75 mm mesh is bounded by its base size) and 8.6–10.5 kB
//!   per DOF (the factor's fill grows with the DOFs); the rule takes
//!   10.5 kB per DOF. S scales the sector to seed 002's: S = (b / 13.3 mm)
//!   (m_n / 3.8 mm) (teeth in sector / 3), since the refined layer grows
//!   with the flank area over h.
//! * LTCA and compliance: one body's FE model at half the pair's DOFs plus
//!   both bodies' dense 3 × 3 nodal tensors (72 B per node pair), flank
//!   nodes n_f ≈ 4.45 · z_sector · b · m_n / h² (seed 002: 2 991 at the
//!   default h = m_n/8 = 0.475 mm), times 1.4: seed 002 at h = 0.475 mm
//!   measured 3 639 MB, the rule gives 3 790 MB.
//! * `mesh`, `tca`, and anything on bevel/hypoid pairs: no fit yet, a fixed
//!   figure (set `resources.memory_gb` in the campaign file instead).
//!
//! Every estimate has a 256 MB floor (the process itself).

use crate::scene::{Gears, Scene};

/// Smallest estimate (MB): the flank process with its tables.
const FLOOR_MB: f64 = 256.0;
/// FE contact DOFs per (mm⁻¹ of 1/h) of seed 002's sector pair.
const DOFS_PER_INV_MM: f64 = 126_300.0;
/// Peak MB per DOF (seed 002 at 0.1 mm: 13 160 MB / 1 252 842 DOFs).
const MB_PER_DOF: f64 = 10.5e-3;
/// Flank nodes per (tooth · mm² of b · m_n / h²) (seed 002 at 0.475 mm).
const FLANK_NODES_COEFF: f64 = 4.45;
/// Safety factor of the LTCA/compliance rule (fitted: see the module doc).
const LTCA_FACTOR: f64 = 1.4;
/// Fixed estimates (MB) where no rule exists.
const SMALL_MB: f64 = 512.0;
const BEVEL_FE_MB: f64 = 4096.0;

/// Estimated peak memory (MB) of one job: `analysis` on `scene` with the
/// command-line `options` (a `--flank-size` there overrides the scene's).
pub fn estimate_mb(analysis: &str, scene: &Scene, options: &[String]) -> f64 {
    let option = |name: &str| -> Option<f64> {
        let i = options.iter().position(|o| o == name)?;
        options.get(i + 1)?.parse().ok()
    };
    let c = match &scene.gears {
        Gears::Cylindrical(c) => c,
        Gears::Bevel(_) => {
            return match analysis {
                "mesh" | "tca" => SMALL_MB,
                _ => BEVEL_FE_MB,
            }
        }
    };
    let p = &c.pair.pinion;
    let mn = p.normal_module;
    let z = f64::from(scene.mesh.teeth_in_sector);
    let b = p.face_width.max(c.pair.gear.face_width);
    let scale = (b / 13.3) * (mn / 3.8) * (z / 3.0);
    let mb = match analysis {
        "run" | "compare" => {
            let h = option("--flank-size")
                .or(scene.mesh.flank_size)
                .unwrap_or(mn / 8.0);
            MB_PER_DOF * DOFS_PER_INV_MM * scale / h
        }
        "ltca" | "compliance" => {
            let ltca = scene.analyses.ltca.as_ref();
            let h = option("--flank-size")
                .or(ltca.and_then(|l| l.flank_size_mm))
                .unwrap_or(mn / 8.0);
            let fe = MB_PER_DOF * 0.5 * DOFS_PER_INV_MM * scale / h;
            let nf = FLANK_NODES_COEFF * z * b * mn / (h * h);
            let tensors = 2.0 * 72.0 * nf * nf / 1048576.0;
            LTCA_FACTOR * (fe + tensors)
        }
        _ => SMALL_MB,
    };
    mb.max(FLOOR_MB)
}

/// The machine's memory (MB): (total, available); the one reader of
/// /proc/meminfo is [`crate::resources`].
pub use crate::resources::machine_memory_mb;

/// Cores available to this process.
pub fn cores() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn seed002() -> Scene {
        let p =
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("papers/seed002-spur/scene.toml");
        crate::scene::read_scene(&p).unwrap()
    }

    /// The rule against the measured peaks it was fitted to, and one it was
    /// not fitted to (0.25 mm): within 10 %.
    #[test]
    fn fe_rule_matches_seed002_peaks() {
        let s = seed002();
        for (h, measured) in [(0.5, 2077.0), (0.25, 4737.0), (0.1, 13160.0)] {
            let est = estimate_mb("run", &s, &["--flank-size".into(), format!("{h}")]);
            assert!(
                (est / measured - 1.0).abs() < 0.3,
                "h = {h}: {est} vs {measured}"
            );
            assert!(est >= 0.9 * measured, "h = {h}: {est} below {measured}");
        }
        // the scene's own 0.1 mm: 13 GB, the figure
        let est = estimate_mb("run", &s, &[]);
        assert!((est - 13_260.0).abs() < 100.0, "{est}");
        let est = estimate_mb("ltca", &s, &[]);
        assert!((est / 3639.0 - 1.0).abs() < 0.1, "{est}");
        assert_eq!(estimate_mb("tca", &s, &[]), SMALL_MB);
    }

    #[test]
    fn machine_figures_are_positive() {
        assert!(cores() >= 1);
        if let Some((t, a)) = machine_memory_mb() {
            assert!(t > 0.0 && a > 0.0 && a <= t);
        }
    }
}
