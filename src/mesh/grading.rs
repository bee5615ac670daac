//! Graded element sizes along a line and their positions on the quadratic
//! half lattice (corner and midside points), shared by the structured gear
//! meshers ([`crate::mesh::gear_sector`], [`crate::mesh::bevel_sector`]).

/// Most sizes [`graded`] returns (far beyond any sector mesh).
const MAX_GRADED: usize = 100_000;

/// Sizes starting at h0, growing by q up to hmax, scaled to sum exactly to
/// len. `what` names the length in the error: a length or size that is not
/// positive and finite (a bore reaching the tooth section once looped
/// forever, allocating) or more than `MAX_GRADED` sizes.
pub fn graded(len: f64, h0: f64, q: f64, hmax: f64, what: &str) -> Result<Vec<f64>, String> {
    let ok = |x: f64| x > 0.0 && x.is_finite();
    if !(ok(len) && ok(h0) && ok(hmax) && q >= 1.0 && q.is_finite()) {
        return Err(format!(
            "{what}: length {len:.6} mm, first size {h0:.6} mm, largest {hmax:.6} mm: the length and sizes must be positive"
        ));
    }
    let mut v = Vec::new();
    let mut s = 0.0;
    let mut h = h0.min(hmax).min(len);
    while s + 0.5 * h < len || v.is_empty() {
        if v.len() == MAX_GRADED {
            return Err(format!(
                "{what}: more than {MAX_GRADED} elements of {h0:.3e} mm over {len:.6} mm"
            ));
        }
        v.push(h);
        s += h;
        h = (h * q).min(hmax);
    }
    let f = len / s;
    Ok(v.iter().map(|x| x * f).collect())
}

/// Cumulative fractions on the half lattice (2n + 1 values) from n sizes; odd
/// entries are the averages of their neighbours.
pub fn half_lattice(sizes: &[f64]) -> Vec<f64> {
    let tot: f64 = sizes.iter().sum();
    let mut out = vec![0.0];
    let mut s = 0.0;
    for h in sizes {
        out.push((s + 0.5 * h) / tot);
        s += h;
        out.push(s / tot);
    }
    *out.last_mut().unwrap() = 1.0;
    out
}

/// Half-lattice fractions across a tooth row of the given width with
/// 2·`half` elements: first layer `flank_size` at both flanks, geometric
/// growth q ∈ [1, 1.3] to the middle (q = 1.3 and a thicker first layer
/// where the row is too wide for its elements, uniform where it is too
/// narrow, e.g. near the tip). Bounded bisection for q (60 halvings).
pub fn row_fractions(width: f64, half: usize, flank_size: f64) -> Vec<f64> {
    let sum = |q: f64| (0..half).map(|k| q.powi(k as i32)).sum::<f64>();
    let target = 0.5 * width / flank_size;
    let q = if target <= half as f64 {
        1.0
    } else if target >= sum(1.3) {
        1.3
    } else {
        let (mut lo, mut hi) = (1.0, 1.3);
        for _ in 0..60 {
            let m = 0.5 * (lo + hi);
            if sum(m) < target {
                lo = m;
            } else {
                hi = m;
            }
        }
        0.5 * (lo + hi)
    };
    let h: Vec<f64> = (0..half).map(|k| q.powi(k as i32)).collect();
    let mut all = h.clone();
    all.extend(h.iter().rev());
    half_lattice(&all)
}

/// Largest growth ratio of [`banded_sizes`] between neighbouring elements
/// outside a band (the structured meshers' usual bound).
pub const BAND_GROWTH: f64 = 1.25;

/// Sizes along a line of length `len` that are `band.2` inside each band
/// `[band.0, band.1]` (positions from the start of the line, clipped to it)
/// and grow geometrically by about `q` per element away from the bands
/// back to `coarse`: a local refinement of a line otherwise cut into
/// elements of `coarse` (the contact band of
/// [`crate::mesh::gear_sector::ProfileBand`]).
///
/// Construction: the size field h(s) = min(coarse, minᵢ hᵢ + ln q · dᵢ(s))
/// (dᵢ the distance to band i; a field growing linearly with slope ln q
/// gives neighbouring elements of ratio ≈ q), N = ⌈∫ ds/h⌉ elements placed
/// at equal steps of ∫ ds/h (tabulated with steps of min h / 16, inverted
/// linearly). Every element spans ∫ ds/h ≤ 1 (N ≥ ∫ ds/h), so an element
/// inside a band is at most the band size: a band is at least as fine as
/// asked. Errors (naming `what`): a length, size or
/// band that is not positive and finite, a band entirely off the line, or
/// more than `MAX_GRADED` elements.
pub fn banded_sizes(
    len: f64,
    coarse: f64,
    bands: &[(f64, f64, f64)],
    q: f64,
    what: &str,
) -> Result<Vec<f64>, String> {
    let ok = |x: f64| x > 0.0 && x.is_finite();
    if !(ok(len) && ok(coarse) && q > 1.0 && q.is_finite()) {
        return Err(format!(
            "{what}: length {len:.6} mm, size {coarse:.6} mm, growth {q}: positive and finite values (growth > 1) are needed"
        ));
    }
    let mut clipped = Vec::with_capacity(bands.len());
    for &(a, b, h) in bands {
        if !(a.is_finite() && b.is_finite() && a <= b && ok(h)) {
            return Err(format!(
                "{what}: band [{a:.6}, {b:.6}] mm of size {h:.6} mm: a finite interval and a positive size are needed"
            ));
        }
        if b < 0.0 || a > len {
            return Err(format!(
                "{what}: band [{a:.6}, {b:.6}] mm lies off the line [0, {len:.6}] mm"
            ));
        }
        clipped.push((a.max(0.0), b.min(len), h.min(coarse)));
    }
    let slope = q.ln();
    let field = |s: f64| {
        clipped.iter().fold(coarse, |m, &(a, b, h)| {
            let d = if s < a {
                a - s
            } else if s > b {
                s - b
            } else {
                0.0
            };
            m.min(h + slope * d)
        })
    };
    let hmin = clipped.iter().fold(coarse, |m, b| m.min(b.2));
    let steps = ((16.0 * len / hmin).ceil() as usize).max(16);
    if steps > 64 * MAX_GRADED {
        return Err(format!(
            "{what}: more than {MAX_GRADED} elements of {hmin:.3e} mm over {len:.6} mm"
        ));
    }
    // cumulative ∫ ds/h, trapezoids
    let ds = len / steps as f64;
    let mut cum = vec![0.0; steps + 1];
    let mut prev = 1.0 / field(0.0);
    for k in 1..=steps {
        let cur = 1.0 / field(k as f64 * ds);
        cum[k] = cum[k - 1] + 0.5 * ds * (prev + cur);
        prev = cur;
    }
    let total = cum[steps];
    let n = (total.ceil() as usize).max(1);
    if n > MAX_GRADED {
        return Err(format!(
            "{what}: more than {MAX_GRADED} elements of {hmin:.3e} mm over {len:.6} mm"
        ));
    }
    let mut pos = Vec::with_capacity(n + 1);
    pos.push(0.0);
    let mut k = 0;
    for i in 1..n {
        let target = total * i as f64 / n as f64;
        while cum[k + 1] < target {
            k += 1;
        }
        let w = (target - cum[k]) / (cum[k + 1] - cum[k]);
        pos.push((k as f64 + w) * ds);
    }
    pos.push(len);
    Ok(pos.windows(2).map(|w| w[1] - w[0]).collect())
}

#[cfg(test)]
mod tests {
    use super::{graded, half_lattice};

    /// Sizes sum to the length and grow by at most q; a length that is not
    /// positive (a bore reaching the tooth section: it looped forever,
    /// allocating until the process was killed) is an error naming it.
    #[test]
    fn graded_sizes_and_bad_lengths() {
        let v = graded(10.0, 0.5, 1.25, 2.0, "t").unwrap();
        assert!((v.iter().sum::<f64>() - 10.0).abs() < 1e-12);
        assert!(v.windows(2).all(|w| w[1] <= 1.25 * w[0] * (1.0 + 1e-12)));
        for len in [-0.6, 0.0, f64::NAN, f64::INFINITY] {
            let e = graded(len, 0.5, 1.25, 2.0, "rim below the teeth").unwrap_err();
            assert!(e.contains("rim below the teeth"), "{e}");
        }
        assert!(graded(1.0, 1e-9, 1.0, 1e-9, "x").is_err());
    }

    /// Bands: the sizes sum to the length, are at most the band size inside
    /// it, grow by at most 1.3 between neighbours and reach the coarse size
    /// far from the band; bad bands are errors naming the line.
    #[test]
    fn banded_sizes_refine_locally() {
        let v = super::banded_sizes(10.0, 0.5, &[(4.0, 5.0, 0.025)], 1.25, "t").unwrap();
        assert!((v.iter().sum::<f64>() - 10.0).abs() < 1e-12);
        let mut s = 0.0;
        for (i, h) in v.iter().enumerate() {
            let mid = s + 0.5 * h;
            if s >= 4.0 && s + h <= 5.0 {
                assert!(*h <= 0.025 * (1.0 + 1e-9), "{h} at {mid}");
            }
            if i > 0 {
                let r = h / v[i - 1];
                assert!((1.0 / 1.3..=1.3).contains(&r), "ratio {r} at {mid}");
            }
            s += h;
        }
        assert!(
            v[0] > 0.45 && v[v.len() - 1] > 0.45,
            "{} {}",
            v[0],
            v[v.len() - 1]
        );
        for bad in [
            (4.0, 5.0, 0.0),
            (5.0, 4.0, 0.1),
            (11.0, 12.0, 0.1),
            (4.0, 5.0, f64::NAN),
        ] {
            let e = super::banded_sizes(10.0, 0.5, &[bad], 1.25, "involute").unwrap_err();
            assert!(e.contains("involute"), "{e}");
        }
    }

    /// Corner fractions are the cumulative sizes, midsides their averages.
    #[test]
    fn half_lattice_fractions() {
        let f = half_lattice(&[1.0, 3.0]);
        assert_eq!(f, vec![0.0, 0.125, 0.25, 0.625, 1.0]);
    }
}
