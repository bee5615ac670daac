//! Harmonics of the loaded transmission error at the mesh orders.
//!
//! The TE of a pair repeats with the mesh pitch, so its spectrum sits at
//! the mesh orders k = 1, 2, … (k cycles per angular pitch of the pinion).
//! Sampled at N positions equally spaced over M whole pitches, the
//! discrete Fourier transform X_j = Σ_n x_n e^{−2πi jn/N} gives the
//! amplitude of order k exactly (no leakage) as A_k = 2|X_{kM}|/N for
//! kM < N/2 (the DFT of a periodic sum of sines; e.g. Oppenheim & Schafer,
//! *Discrete-Time Signal Processing*, §8.1). [`pitch_sample`] checks that a
//! cycle's positions are such a sample and refuses them with the reason
//! otherwise: a leaky spectrum is not reported.

use serde::Serialize;

/// Mesh orders reported: 1 … 5.
pub const MESH_ORDERS: usize = 5;

/// Relative tolerance on the spacing of the positions and on a whole
/// number of pitches (of the spacing).
const SPACING_TOLERANCE: f64 = 1e-9;

/// A cycle's positions that are N equal steps over M whole pitches.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PitchSample {
    /// Positions of the sample (the first N of the cycle; a last position
    /// one period after the first is left out and kept as the closure).
    pub positions: usize,
    /// Whole pitches M they span.
    pub pitches: usize,
    /// The cycle has a position one period after the first (its TE
    /// repeats the first one's if the TE is periodic).
    pub closing_position: bool,
}

/// Checks that `roll_deg` (in order) are equally spaced over whole
/// pitches of `pitch_deg`: N positions with step h and N h = M p (the end
/// left out), or N + 1 with N h = M p (the end one period after the
/// first). Mesh order 5 must lie below the Nyquist order: N > 2·5·M.
pub fn pitch_sample(roll_deg: &[f64], pitch_deg: f64) -> Result<PitchSample, String> {
    let n = roll_deg.len();
    if n < 2 || !(pitch_deg > 0.0) {
        return Err(format!(
            "{n} positions: at least {} equally spaced positions over one pitch are needed",
            2 * MESH_ORDERS + 1
        ));
    }
    let h = (roll_deg[n - 1] - roll_deg[0]) / (n - 1) as f64;
    if !(h > 0.0) {
        return Err("the roll angles do not increase".into());
    }
    if let Some(w) = roll_deg.windows(2).find(|w| {
        let step = w[1] - w[0];
        (step - h).abs() > SPACING_TOLERANCE * h
    }) {
        return Err(format!(
            "the roll angles are not equally spaced ({:.6}° to {:.6}° against a mean step of {h:.6}°)",
            w[0], w[1]
        ));
    }
    let whole = |count: usize| {
        let m = count as f64 * h / pitch_deg;
        let r = m.round();
        (r >= 1.0 && (m - r).abs() * pitch_deg <= SPACING_TOLERANCE * h * count as f64)
            .then_some(r as usize)
    };
    let (positions, pitches, closing_position) = if let Some(m) = whole(n - 1) {
        (n - 1, m, true)
    } else if let Some(m) = whole(n) {
        (n, m, false)
    } else {
        return Err(format!(
            "{n} positions at {h:.6}° span {:.6} pitches of {pitch_deg:.6}°, not a whole number: the DFT would leak (give roll angles of N equal steps over whole pitches, or `torques_nm` for the map, which samples one pitch)",
            n as f64 * h / pitch_deg
        ));
    };
    if positions <= 2 * MESH_ORDERS * pitches {
        return Err(format!(
            "{positions} positions over {pitches} pitch(es): mesh order {MESH_ORDERS} needs more than {} (below the Nyquist order)",
            2 * MESH_ORDERS * pitches
        ));
    }
    Ok(PitchSample {
        positions,
        pitches,
        closing_position,
    })
}

/// Amplitude and phase of the mesh orders 1 … `orders` of `x`, N samples
/// over `pitches` whole pitches: A_k = 2|X_{kM}|/N and
/// φ_k = arg X_{kM} (rad), so x_n = x̄ + Σ_k A_k cos(2πkMn/N + φ_k) for
/// a TE of these orders only (2πkMn/N = 2πk (φ_n − φ_0)/p); the caller
/// has checked the sample ([`pitch_sample`]).
pub fn mesh_order_amplitudes(x: &[f64], pitches: usize, orders: usize) -> Vec<(f64, f64)> {
    let n = x.len();
    // the mean taken out first: a TE of thousands of µrad would otherwise
    // leave its rounding in the small amplitudes
    let mean = x.iter().sum::<f64>() / n.max(1) as f64;
    (1..=orders)
        .map(|k| {
            let j = k * pitches;
            let (mut re, mut im) = (0.0, 0.0);
            for (i, v) in x.iter().map(|v| v - mean).enumerate() {
                // the angle reduced modulo N exactly, in integers
                let a = -2.0 * std::f64::consts::PI * ((j * i) % n) as f64 / n as f64;
                re += v * a.cos();
                im += v * a.sin();
            }
            (2.0 * re.hypot(im) / n as f64, im.atan2(re))
        })
        .collect()
}

/// One mesh order of the loaded TE.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Harmonic {
    /// k: cycles per mesh pitch.
    pub order: usize,
    /// Amplitude at the pinion (µrad), times the TE radius (µm; a
    /// cylindrical pair's r_b1: along the line of action) and at the gear
    /// (arcsec).
    pub amplitude_urad: f64,
    pub amplitude_um: f64,
    pub amplitude_arcsec: f64,
    /// Phase of cos(2πk φ/p + phase), φ from the sample's first position
    /// (deg).
    pub phase_deg: f64,
}

/// The loaded TE's mesh-order harmonics over one sample of whole pitches.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TeHarmonics {
    /// N positions over M pitches, from `first_roll_deg`.
    pub positions: usize,
    pub pitches: usize,
    pub first_roll_deg: f64,
    /// Mean loaded TE over the sample (µrad, pinion).
    pub mean_urad: f64,
    /// The radius (mm) that turns µrad into µm ([`Harmonic::amplitude_um`]).
    pub te_radius_mm: f64,
    /// |TE(first + M p) − TE(first)| (µrad) where the cycle has that
    /// position: how far the sampled TE is from periodic (a sector's
    /// outer teeth differ from its middle one). `None` without it.
    pub closure_urad: Option<f64>,
    /// Orders 1 … [`MESH_ORDERS`].
    pub harmonics: Vec<Harmonic>,
}

/// The harmonics of the loaded TE `te_urad` at `roll_deg`, if those are a
/// [`pitch_sample`] of `pitch_deg`; `te_radius_mm` turns µrad into µm,
/// `ratio` = z₁/z₂ into arcsec at the gear. The reason otherwise.
pub fn te_harmonics(
    roll_deg: &[f64],
    te_urad: &[f64],
    pitch_deg: f64,
    te_radius_mm: f64,
    ratio: f64,
) -> Result<TeHarmonics, String> {
    if roll_deg.len() != te_urad.len() {
        return Err(format!(
            "{} roll angles for {} TE values",
            roll_deg.len(),
            te_urad.len()
        ));
    }
    if let Some(i) = te_urad.iter().position(|t| !t.is_finite()) {
        return Err(format!("the TE at {}° is not a number", roll_deg[i]));
    }
    let s = pitch_sample(roll_deg, pitch_deg)?;
    let x = &te_urad[..s.positions];
    let mean = x.iter().sum::<f64>() / s.positions as f64;
    let harmonics = mesh_order_amplitudes(x, s.pitches, MESH_ORDERS)
        .into_iter()
        .enumerate()
        .map(|(i, (a, phase))| Harmonic {
            order: i + 1,
            amplitude_urad: a,
            amplitude_um: a * te_radius_mm * 1e-3,
            amplitude_arcsec: crate::load_sharing::te_arcsec_at_gear(a, ratio).abs(),
            phase_deg: phase.to_degrees(),
        })
        .collect();
    Ok(TeHarmonics {
        positions: s.positions,
        pitches: s.pitches,
        first_roll_deg: roll_deg[0],
        mean_urad: mean,
        te_radius_mm,
        closure_urad: s
            .closing_position
            .then(|| (te_urad[s.positions] - te_urad[0]).abs()),
        harmonics,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// A synthetic TE of known mesh-order harmonics, sampled as a cycle's
    /// positions are, through the same function as the LTCA's TE: every
    /// amplitude back to 1e-12 µrad (of amplitudes up to 40 µrad), the
    /// phases to 1e-10 rad, µm and arcsec the same amplitudes scaled.
    #[test]
    fn synthetic_te_gives_its_harmonics_exactly() {
        let pitch = 360.0 / 13.0;
        let amps = [40.0, 12.5, 3.25, 0.8, 0.125];
        let phases = [0.3, -1.1, 2.0, -2.9, 0.7];
        for (n, pitches, closing) in [(24, 1, false), (24, 1, true), (37, 2, false), (11, 1, true)]
        {
            let start = -7.3;
            let count = n + usize::from(closing);
            let roll: Vec<f64> = (0..count)
                .map(|i| start + pitch * pitches as f64 * i as f64 / n as f64)
                .collect();
            let te: Vec<f64> = roll
                .iter()
                .map(|r| {
                    let t = 2.0 * PI * (r - start) / pitch;
                    4500.0
                        + amps
                            .iter()
                            .zip(&phases)
                            .enumerate()
                            .map(|(k, (a, p))| a * ((k + 1) as f64 * t + p).cos())
                            .sum::<f64>()
                })
                .collect();
            let h = te_harmonics(&roll, &te, pitch, 22.93, 13.0 / 35.0).unwrap();
            assert_eq!((h.positions, h.pitches), (n, pitches));
            assert!((h.mean_urad - 4500.0).abs() < 1e-9, "{}", h.mean_urad);
            assert_eq!(h.closure_urad.is_some(), closing);
            if let Some(c) = h.closure_urad {
                assert!(c < 1e-9, "closure {c}");
            }
            for (k, hk) in h.harmonics.iter().enumerate() {
                let err = (hk.amplitude_urad - amps[k]).abs();
                assert!(
                    err < 1e-12,
                    "N {n}, M {pitches}, order {}: error {err:e}",
                    k + 1
                );
                let dp = (hk.phase_deg.to_radians() - phases[k] + PI).rem_euclid(2.0 * PI) - PI;
                assert!(dp.abs() < 1e-10, "order {} phase error {dp:e}", k + 1);
                assert!((hk.amplitude_um - amps[k] * 22.93e-3).abs() < 1e-14);
                let arcsec = amps[k] * 1e-6 * 13.0 / 35.0 * 180.0 / PI * 3600.0;
                assert!((hk.amplitude_arcsec - arcsec).abs() < 1e-12 * arcsec.max(1.0));
            }
        }
    }

    /// Positions that are not equal steps over whole pitches, too few for
    /// order 5, or a TE that is not a number: refused with the reason.
    #[test]
    fn leaky_or_short_samples_are_refused() {
        let pitch = 27.0;
        // 1° steps over the engagement: 27.5 pitches' worth is no whole number
        let roll: Vec<f64> = (0..30).map(|i| i as f64).collect();
        let e = pitch_sample(&roll, 25.5).unwrap_err();
        assert!(e.contains("not a whole number"), "{e}");
        // unequal steps
        let mut bad: Vec<f64> = (0..24).map(|i| i as f64 * pitch / 24.0).collect();
        bad[5] += 0.01;
        assert!(pitch_sample(&bad, pitch)
            .unwrap_err()
            .contains("not equally spaced"));
        // ten positions over a pitch: order 5 is the Nyquist order
        let ten: Vec<f64> = (0..10).map(|i| i as f64 * pitch / 10.0).collect();
        assert!(pitch_sample(&ten, pitch).unwrap_err().contains("Nyquist"));
        let ok: Vec<f64> = (0..12).map(|i| i as f64 * pitch / 12.0).collect();
        let mut te = vec![1.0; 12];
        te[3] = f64::NAN;
        assert!(te_harmonics(&ok, &te, pitch, 1.0, 1.0)
            .unwrap_err()
            .contains("not a number"));
    }
}
