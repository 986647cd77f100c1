//! The angle of a turn, bracketed without an arc cosine: the check compares head displacements
//! `|Δtip| + R·θ` against a step millions of times per file ([`super::sweep`]'s sampling and
//! `checked_poses`), and almost every comparison is far from the step, so bounds of θ that cost
//! a square root decide it; the arc cosine is computed only for the rare comparison the bounds
//! leave open (the answer is then the same as computing θ every time).
//!
//! ## The bounds
//! For `c = cos θ`, θ ∈ [0, π], let `u = 1 − c = 2 sin²(θ/2)` and `s = sin(θ/2) = √(u/2)`, so
//! `θ = 2 asin s`. On `t ∈ [0, π/2)`, `sin t ≤ t ≤ tan t`; with `t = asin s`:
//!
//! `s ≤ asin s ≤ s / √(1 − s²)`, so `2s ≤ θ ≤ 2s / √((1 + c)/2)` (and θ ≤ π).
//!
//! The gap is `θ³/6`-small for the small turns between samples (θ ≈ 0.004 rad for a 55 mm head
//! at a 0.2 mm step: a relative gap of 3·10⁻⁶). The float evaluation of `s` and of the quotient
//! is within a few ulps of the true values; [`BRACKET_MARGIN`] widens both bounds far beyond
//! that.

/// Relative widening of the bounds of [`acos_bracket`] and of the sums compared in
/// [`exceeds_bracketed`]: each is a handful of correctly rounded operations (relative error
/// under 10⁻¹⁵), and so is the library's `acos` (under an ulp), so 10⁻⁹ keeps every bound on its
/// side of the value the arc cosine path computes.
pub(crate) const BRACKET_MARGIN: f64 = 1e-9;

/// Bounds `(lo, hi)` with `lo ≤ acos(c) ≤ hi` for `c ∈ [−1, 1]` (see the module documentation:
/// `2s ≤ θ ≤ 2s/√((1 + c)/2)`, `s = √((1 − c)/2)`, each widened by [`BRACKET_MARGIN`];
/// `hi` at most π).
pub(crate) fn acos_bracket(c: f64) -> (f64, f64) {
    let c = c.clamp(-1.0, 1.0);
    let s = ((1.0 - c) * 0.5).sqrt();
    let lo = 2.0 * s * (1.0 - BRACKET_MARGIN);
    let half_cos = (1.0 + c) * 0.5;
    let hi = if half_cos > 0.0 {
        (2.0 * s / half_cos.sqrt() * (1.0 + BRACKET_MARGIN)).min(std::f64::consts::PI)
    } else {
        std::f64::consts::PI
    };
    (lo, hi)
}

/// Whether `d + reach · acos(c) > limit` as computed in f64 (`acos` the one of `exact`), deciding
/// from [`acos_bracket`] where it can: the sum with the upper bound at most the limit (less the
/// margin) answers no, the sum with the lower bound above it (plus the margin) answers yes, and
/// only in between is `exact(c)` called. `d ≥ 0`, `reach ≥ 0`.
pub(crate) fn exceeds_bracketed(
    d: f64,
    reach: f64,
    c: f64,
    limit: f64,
    exact: impl Fn(f64) -> f64,
) -> bool {
    let (lo, hi) = acos_bracket(c);
    if (d + reach * hi) * (1.0 + BRACKET_MARGIN) <= limit {
        return false;
    }
    if (d + reach * lo) * (1.0 - BRACKET_MARGIN) > limit {
        return true;
    }
    d + reach * exact(c.clamp(-1.0, 1.0)) > limit
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The bracket holds the arc cosine (the standard library's, not the check's `libm` one)
    /// over the whole range, densely near 1 where the turns between samples are, and its
    /// width is small there.
    #[test]
    fn the_bracket_holds_the_arc_cosine_and_is_tight_for_small_turns() {
        let mut cs: Vec<f64> = (0..=20_000).map(|i| -1.0 + i as f64 * 1e-4).collect();
        // small angles: θ from 1e-9 to 0.1 rad, and c one ulp either side
        for k in 0..2000 {
            let theta = 1e-9 * 1.01f64.powi(k);
            if theta > 0.1 {
                break;
            }
            let c = theta.cos();
            cs.extend([c, f64::from_bits(c.to_bits() - 1), c.next_up().min(1.0)]);
        }
        cs.extend([1.0, -1.0, 0.0, 1.0 - f64::EPSILON, -1.0 + f64::EPSILON]);
        for c in cs {
            let theta = c.acos();
            let (lo, hi) = acos_bracket(c);
            assert!(
                lo <= theta && theta <= hi,
                "c {c:e}: acos {theta:e} outside [{lo:e}, {hi:e}]"
            );
            assert!(
                libm::acos(c) >= lo && libm::acos(c) <= hi,
                "c {c:e}: libm acos outside"
            );
            if theta < 0.01 {
                assert!(
                    hi - lo <= theta * theta * theta + 3e-9 * theta,
                    "c {c:e}: bracket [{lo:e}, {hi:e}] too wide for θ {theta:e}"
                );
            }
        }
    }

    /// The bracketed decision equals the direct `d + reach·acos(c) > limit`, over sums near
    /// the limit (the cases the bracket leaves to the arc cosine) and far from it.
    #[test]
    fn the_bracketed_decision_equals_the_direct_comparison() {
        let mut x: u64 = 0x2545_f491_4f6c_dd1d;
        let mut unit = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            (x >> 11) as f64 / (1u64 << 53) as f64
        };
        let limit = 0.2;
        let mut near = 0;
        for _ in 0..200_000 {
            let reach = 60.0 * unit();
            let theta = 0.01 * unit();
            let c = theta.cos();
            let a = reach * libm::acos(c);
            // d chosen so the sum lands on, just under or just over the limit, or anywhere
            let d = match (unit() * 4.0) as u32 {
                0 => (limit - a).max(0.0),
                1 => (limit - a).max(0.0) * (1.0 - 1e-12),
                2 => (limit - a).max(0.0) * (1.0 + 1e-12),
                _ => 0.3 * unit(),
            };
            let direct = d + reach * libm::acos(c) > limit;
            let calls = std::cell::Cell::new(0);
            let got = exceeds_bracketed(d, reach, c, limit, |c| {
                calls.set(calls.get() + 1);
                libm::acos(c)
            });
            near += calls.get();
            assert_eq!(
                got, direct,
                "d {d:e} reach {reach} c {c:e}: bracketed {got}, direct {direct}"
            );
        }
        // most sums far from the limit are decided without the arc cosine
        assert!(near < 120_000, "the arc cosine was called {near} times");
    }
}
