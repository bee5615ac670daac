//! Reals for ccx, which reads a real from the first 20 characters of a
//! field only (`f20.0`).
//!
//! Every real is written in the shortest form that fits in 20 characters:
//! exact (bit-for-bit round trip) whenever such a form exists, otherwise
//! rounded to as many significant digits as fit: at least 15 (relative
//! error ≤ 5e-15) for 1e-9 ≤ |x| < 1e10, at least 13 anywhere. Every value
//! with 0.01 ≤ |x| < 1e26 (and 0) is exact; below that, values needing 16-17
//! significant digits (e.g. -0.0019289749616291370) may be rounded.

/// ccx reads reals from the first 20 characters of a field.
pub(super) const CCX_REAL_WIDTH: usize = 20;

/// Formats a finite real for ccx: at most [`CCX_REAL_WIDTH`] characters,
/// exact (shortest round-trip digits) whenever an exact form fits, otherwise
/// rounded to as many significant digits as fit.
pub(super) fn fmt_real(x: f64) -> String {
    // Fast path: Display is the shortest round-trip, positional; most fit.
    let plain = x.to_string();
    if plain.len() <= CCX_REAL_WIDTH {
        return plain;
    }
    let exact = compact_real(&format!("{x:e}"));
    if exact.len() <= CCX_REAL_WIDTH {
        return exact;
    }
    for digits in (1..17).rev() {
        let s = compact_real(&format!("{:.*e}", digits - 1, x));
        if s.len() <= CCX_REAL_WIDTH {
            return s;
        }
    }
    format!("{x:.0e}")
}

/// The shortest of scientific, integer-mantissa and positional notation for
/// a number given in Rust's `{:e}` form ("-1.25e-3"); all parse back to the
/// same value in Rust and Fortran.
fn compact_real(sci: &str) -> String {
    let (sign, rest) = match sci.strip_prefix('-') {
        Some(r) => ("-", r),
        None => ("", sci),
    };
    let Some((mantissa, exp)) = rest.split_once('e') else {
        return sci.to_string();
    };
    let Ok(exp) = exp.parse::<i64>() else {
        return sci.to_string();
    };
    let mut digits: String = mantissa.chars().filter(|c| *c != '.').collect();
    while digits.len() > 1 && digits.ends_with('0') {
        digits.pop();
    }
    let n = digits.len() as i64;
    // value = d1.d2d3... × 10^exp
    let scientific = {
        let mut s = digits[..1].to_string();
        if n > 1 {
            s.push('.');
            s.push_str(&digits[1..]);
        }
        if exp != 0 {
            s.push_str(&format!("e{exp}"));
        }
        s
    };
    let integer_mantissa = {
        let e = exp - (n - 1);
        if e == 0 {
            digits.clone()
        } else {
            format!("{digits}e{e}")
        }
    };
    let positional = if exp >= n - 1 {
        if exp - (n - 1) > 40 {
            None
        } else {
            Some(format!("{digits}{}", "0".repeat((exp - (n - 1)) as usize)))
        }
    } else if exp >= 0 {
        let k = (exp + 1) as usize;
        Some(format!("{}.{}", &digits[..k], &digits[k..]))
    } else if -exp > 40 {
        None
    } else {
        Some(format!(".{}{digits}", "0".repeat((-exp - 1) as usize)))
    };
    // Prefer positional notation on ties: it is the most readable.
    let mut best = positional.unwrap_or_else(|| scientific.clone());
    for cand in [scientific, integer_mantissa] {
        if cand.len() < best.len() {
            best = cand;
        }
    }
    format!("{sign}{best}")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::Rng;

    #[test]
    fn reals_fit_twenty_characters() {
        // Exact whenever an exact form fits.
        for x in [
            0.0,
            -0.0,
            1.0,
            -1.0,
            0.1,
            0.30000000000000004,
            1.0 / 3.0,
            -12.345678901234567,
            210000.0,
            1e300,
            -5e-324,
            6.123233995736766e-17,
            123456789012345680.0,
        ] {
            let s = fmt_real(x);
            assert!(s.len() <= CCX_REAL_WIDTH, "{s}");
            assert_eq!(s.parse::<f64>().unwrap().to_bits(), x.to_bits(), "{s}");
        }
        assert_eq!(fmt_real(1200.0), "1200");
        assert_eq!(fmt_real(-0.5), "-0.5");
        assert_eq!(fmt_real(2.5e-7), "0.00000025");
        assert_eq!(fmt_real(-2.5e-27), "-25e-28");
        // Needs 22 characters exactly; 15 significant digits fit.
        assert_eq!(fmt_real(-1.2345678901234567e-5), "-1.23456789012346e-5");
        // Random bit patterns: always short; exact or rounded to at least 15
        // significant digits in 1e-9..1e10, 13 anywhere.
        let mut rng = Rng::new(0x9e37_79b9_7f4a_7c15);
        let mut inexact = 0;
        for _ in 0..200_000 {
            let x = f64::from_bits(rng.next());
            if !x.is_finite() {
                continue;
            }
            let s = fmt_real(x);
            assert!(s.len() <= CCX_REAL_WIDTH, "{s}");
            let y: f64 = s.parse().unwrap();
            if y.to_bits() != x.to_bits() {
                inexact += 1;
                let tol = if (1e-9..1e10).contains(&x.abs()) {
                    5e-15
                } else {
                    5e-13
                };
                assert!(((y - x) / x).abs() <= tol, "{x:e} -> {s}");
            }
        }
        assert!(inexact > 0);
        // Everything with 0.01 <= |x| < 1e26 is exact.
        for i in 0..200_000u32 {
            let t = (f64::from(i) * 0.618_033_988_749_894_9).fract();
            for x in [
                t * 400.0 - 200.0,
                -0.01 - t * 0.09,
                10f64.powf(t * 28.0 - 2.0),
            ] {
                if x.abs() >= 0.01 && x.abs() < 1e26 {
                    let s = fmt_real(x);
                    assert_eq!(s.parse::<f64>().unwrap().to_bits(), x.to_bits(), "{s}");
                    let s = fmt_real(-x);
                    assert_eq!(s.parse::<f64>().unwrap().to_bits(), (-x).to_bits(), "{s}");
                }
            }
        }
    }
}
