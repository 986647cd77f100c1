//! Deterministic floating-point helpers.
//!
//! Output must be byte-identical natively and in wasm, so every transcendental function goes
//! through the pure-Rust `libm` crate (the platform libm may differ in the last bit). `sqrt`,
//! `+ − × ÷` are IEEE-754 exact everywhere and are used directly.

/// Tangent (radians).
#[inline]
pub fn tan(x: f64) -> f64 {
    libm::tan(x)
}
/// Sine (radians).
#[inline]
pub fn sin(x: f64) -> f64 {
    libm::sin(x)
}
/// Cosine (radians).
#[inline]
pub fn cos(x: f64) -> f64 {
    libm::cos(x)
}
/// Arc tangent of y/x in (−π, π].
#[inline]
pub fn atan2(y: f64, x: f64) -> f64 {
    libm::atan2(y, x)
}
/// Arc sine.
#[inline]
pub fn asin(x: f64) -> f64 {
    libm::asin(x)
}
/// Arc cosine.
#[inline]
pub fn acos(x: f64) -> f64 {
    libm::acos(x)
}
/// Arc tangent.
#[inline]
pub fn atan(x: f64) -> f64 {
    libm::atan(x)
}
/// `x.round()` (to the nearest integer, halfway cases away from zero) from `trunc` and
/// comparisons: `f64::round` is a library call in wasm (and natively on x86-64 without SSE4.1),
/// `f64::trunc` one wasm instruction. Exact: for |x| < 2⁵², t = trunc(x) and x − t (the
/// fraction, exactly representable) are exact, and t ± 1 is exact; for |x| ≥ 2⁵² (already
/// integral), ±∞ and NaN, x − t is 0 or NaN and t = x is returned. The sign of a zero result is
/// x's, as `f64::round`'s.
#[inline]
pub fn round(x: f64) -> f64 {
    let t = x.trunc();
    if (x - t).abs() >= 0.5 {
        t + x.signum()
    } else {
        t
    }
}
/// `a.min(b)` by comparison: the smaller, and the other when one is NaN (`f64::min`'s rule;
/// of two equal values `a`). `f64::min` is a library call (`fmin`) in wasm, whose `f64.min`
/// instruction propagates NaN instead.
#[inline]
pub fn min(a: f64, b: f64) -> f64 {
    if b < a || a.is_nan() {
        b
    } else {
        a
    }
}
/// `a.max(b)` by comparison: the larger, and the other when one is NaN (`f64::max`'s rule;
/// of two equal values `a`); see [`min`].
#[inline]
pub fn max(a: f64, b: f64) -> f64 {
    if b > a || a.is_nan() {
        b
    } else {
        a
    }
}
/// Whether two lists of numbers are the same bit for bit (so −0 ≠ 0 and a NaN equals only
/// the same NaN): "this is the very value computed before", for reusing a result.
pub fn same_bits(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
}

/// Degrees to radians.
#[inline]
pub fn rad(deg: f64) -> f64 {
    deg * (core::f64::consts::PI / 180.0)
}
/// Radians to degrees.
#[inline]
pub fn deg(rad: f64) -> f64 {
    rad * (180.0 / core::f64::consts::PI)
}

/// Angle between two unit vectors in radians, accurate near 0 and π (uses atan2 of |a×b|, a·b).
#[inline]
pub fn angle_between(a: glam::DVec3, b: glam::DVec3) -> f64 {
    atan2(a.cross(b).length(), a.dot(b))
}

/// Full precision (shortest round-trip text), `-0` written as `0`: numbers in messages and
/// file headers that a user copies back into a file.
pub fn fmt_shortest(v: f64) -> String {
    if v == 0.0 {
        "0".into()
    } else {
        format!("{v}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::Lcg;

    /// Values where rounding and comparisons are delicate: halves, the largest double below
    /// ½, the edge of the integral range 2⁵², signed zeros, infinities, NaN.
    fn edge_values() -> Vec<f64> {
        let mut v = vec![
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.5,
            -1.5,
            2.5,
            -2.5,
            0.499_999_999_999_999_94,
            -0.499_999_999_999_999_94,
            4_503_599_627_370_495.5,
            -4_503_599_627_370_495.5,
            4_503_599_627_370_496.0,
            9.007_199_254_740_993e15,
            1e300,
            f64::MIN_POSITIVE,
            -f64::MIN_POSITIVE,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
        ];
        for k in -60i32..60 {
            let x = 2f64.powi(k);
            v.extend([x, -x, x + 0.5, x - 0.5, -x - 0.5]);
        }
        v
    }

    fn same(a: f64, b: f64) -> bool {
        a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
    }

    #[test]
    fn round_is_bit_identical_to_std_round() {
        let mut rng = Lcg(11);
        let mut xs = edge_values();
        for _ in 0..200_000 {
            // every magnitude from 10⁻³ to 10¹⁷, and the output formatter's scaled values
            let m = 10f64.powf(rng.range(-3.0, 17.0));
            xs.push(rng.range(-m, m));
            xs.push((rng.range(-500.0, 500.0) * 1e3).trunc() / 1e3 * 1e3);
        }
        for x in xs {
            assert!(
                same(round(x), x.round()),
                "round({x:e}) = {:e}, std {:e}",
                round(x),
                x.round()
            );
        }
    }

    #[test]
    fn min_max_follow_std_on_every_pair_but_equal_zeros() {
        let mut rng = Lcg(12);
        let mut xs = edge_values();
        for _ in 0..300 {
            xs.push(rng.range(-10.0, 10.0));
        }
        for &a in &xs {
            for &b in &xs {
                // std leaves the sign of min(0, −0) unspecified
                if a == 0.0 && b == 0.0 {
                    assert_eq!(min(a, b), 0.0);
                    assert_eq!(max(a, b), 0.0);
                    continue;
                }
                assert!(same(min(a, b), a.min(b)), "min({a}, {b}) = {}", min(a, b));
                assert!(same(max(a, b), a.max(b)), "max({a}, {b}) = {}", max(a, b));
            }
        }
    }
}
