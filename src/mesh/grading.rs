//! Graded element sizes along a line and their positions on the quadratic
//! half lattice (corner and midside points), shared by the structured gear
//! meshers ([`crate::mesh::gear_sector`], [`crate::mesh::bevel_sector`]).

/// Most sizes [`graded`] returns (far beyond any sector mesh).
const MAX_GRADED: usize = 100_000;

/// Sizes starting at h0, growing by q up to hmax, scaled to sum exactly to
/// len. `what` names the length in the error: a length or size that is not
/// positive and finite (a bore reaching the tooth section once looped
/// forever, allocating) or more than [`MAX_GRADED`] sizes.
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

    /// Corner fractions are the cumulative sizes, midsides their averages.
    #[test]
    fn half_lattice_fractions() {
        let f = half_lattice(&[1.0, 3.0]);
        assert_eq!(f, vec![0.0, 0.125, 0.25, 0.625, 1.0]);
    }
}
