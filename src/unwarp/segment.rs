//! Adaptive splitting of a straight slicing-frame move under T⁻¹.
//!
//! A straight move q(t) = q₀ + t·(q₁ − q₀), t ∈ [0, 1], of the slicer maps to the curve
//! c(t) = T⁻¹(q(t)) in the model frame. The move is split at parameters t₀ < t₁ < … until, on
//! every piece, the exact image stays within `tolerance` of the chord and no chord is longer
//! than `max_segment`. Splitting is by halving, so the result is deterministic.
//!
//! **The deviation bound.** On a piece, d(t) = distance of c(t) from the chord is sampled at
//! ¼, ½, ¾ (d = 0 at both ends). Along a straight slicer move every warp's image is the graph of
//! a convex or concave height (seed 000 Eq. 1's parabola, Eq. 2's |x + a| with its crease, the
//! cone r·tan α with its apex, circles for the mandrel and the sphere), so d is concave, and a
//! concave function lies below the extension of any of its chords outside that chord's
//! interval. On each quarter, d is bounded by the lower of the extensions of the neighbouring
//! sample chords ([`concave_bound`]): exact for a crease in the middle half of the piece (both
//! sides of a tent are lines), at most 4/3 of it in the outer quarters, 1.125 × the true
//! maximum for a parabola (so about 6 % more pieces than a midpoint test). Checking only the samples missed a crease between two of them by up to 4/3
//! (0.0114 mm chords for 0.01 mm at the tilted warp's crease with PrusaSlicer, issue 17).

use glam::DVec3;

use crate::num::{max, min};

/// Deepest halving (2⁻²⁴ of a move: far below any tolerance for a move of < 1 m).
pub const MAX_DEPTH: u32 = 24;

/// Distance from `p` to the segment a–b.
fn dist_to_segment(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let ab = b - a;
    let l2 = ab.length_squared();
    if l2 <= 0.0 {
        return (p - a).length();
    }
    let t = ((p - a).dot(ab) / l2).clamp(0.0, 1.0);
    (p - (a + ab * t)).length()
}

/// The largest value on [0, 1] of a concave d ≥ 0 with d(0) = d(1) = 0, given d at ¼, ½, ¾:
/// on each quarter the lower of the extensions of the neighbouring sample chords (see the
/// module doc), maximised at the quarter's ends or where the two lines cross.
pub fn concave_bound(d: [f64; 3]) -> f64 {
    const Q: f64 = 0.25;
    let f = [0.0, d[0], d[1], d[2], 0.0];
    // the line through samples i and i + 1, at parameter t
    let line = |i: usize, t: f64| f[i] + (f[i + 1] - f[i]) * (t / Q - i as f64);
    let mut bound = max(max(d[0], d[1]), d[2]);
    for q in 0usize..4 {
        let (lo, hi) = (q as f64 * Q, (q + 1) as f64 * Q);
        // the chord left of this quarter (samples q − 1, q) and right of it (q + 1, q + 2)
        let left = q.checked_sub(1);
        let right = (q + 2 <= 4).then_some(q + 1);
        let at = |t: f64| match (left, right) {
            (Some(l), Some(r)) => min(line(l, t), line(r, t)),
            (Some(l), None) => line(l, t),
            (None, Some(r)) => line(r, t),
            (None, None) => 0.0,
        };
        bound = max(max(bound, at(lo)), at(hi));
        if let (Some(l), Some(r)) = (left, right) {
            // slopes per unit t; the lines cross where they are equal
            let (sl, sr) = ((f[l + 1] - f[l]) / Q, (f[r + 1] - f[r]) / Q);
            if sl != sr {
                let t = (line(r, 0.0) - line(l, 0.0)) / (sl - sr);
                if t > lo && t < hi {
                    bound = max(bound, line(l, t));
                }
            }
        }
    }
    bound
}

/// Relative slack of [`concave_bound_exceeds`]'s quick "within" decision: [`concave_bound`]
/// is at most 2·max(d) exactly, and its computed value exceeds that by a few rounding errors
/// of numbers of that size (≈ 10⁻¹⁵ relative), far below this.
const QUICK_SLACK: f64 = 1e-9;

/// Whether [`concave_bound`]`(d) > tolerance`, decided from m = max(d) where that is enough.
/// The bound is at least m (it starts there), and for d ≥ 0 at most 2m: on an outer quarter
/// it is below the inner chord's extension, whose values there are d₀ and 2d₀ − d₁ ≤ 2d₀ (or
/// the mirror), and on a middle quarter below the outer chord's extension, d₀ and 2d₀ (or
/// the mirror). So m > tolerance says yes, 2m(1 + [`QUICK_SLACK`]) ≤ tolerance says no, and
/// only between them (and for NaN) is the bound computed: the same decision every time.
pub fn concave_bound_exceeds(d: [f64; 3], tolerance: f64) -> bool {
    let m = max(max(d[0], d[1]), d[2]);
    if m > tolerance {
        return true;
    }
    if 2.0 * m * (1.0 + QUICK_SLACK) <= tolerance {
        return false;
    }
    concave_bound(d) > tolerance
}

/// Split [0, 1] for the curve `map` (t ↦ model point). Appends the end parameter of each
/// piece (in increasing order, the last being 1.0) and their mapped points to `out`.
/// `p0` = map(0). Reuses `stack` (no allocation in the steady state). Generic over the map, so
/// that it is inlined (in wasm, a `&dyn Fn` is an indirect call per sample).
pub fn split(
    map: &impl Fn(f64) -> DVec3,
    p0: DVec3,
    tolerance: f64,
    max_segment: f64,
    stack: &mut Vec<(f64, DVec3, u32)>,
    out: &mut Vec<(f64, DVec3)>,
) {
    // Depth-first over [t0, t1] pieces, left first; stack holds right ends.
    stack.clear();
    let p1 = map(1.0);
    stack.push((1.0, p1, 0));
    let (mut t0, mut a) = (0.0f64, p0);
    while let Some(&(t1, b, depth)) = stack.last() {
        let needs = depth < MAX_DEPTH && {
            let chord = (b - a).length();
            chord > max_segment || {
                let d = [0.25, 0.5, 0.75].map(|f| dist_to_segment(map(t0 + (t1 - t0) * f), a, b));
                concave_bound_exceeds(d, tolerance)
            }
        };
        if needs {
            let tm = 0.5 * (t0 + t1);
            let pm = map(tm);
            stack.push((tm, pm, depth + 1));
            // The piece [t0, tm] is examined next; [tm, t1] stays below it with depth+1.
            if let Some(last) = stack.len().checked_sub(2).and_then(|i| stack.get_mut(i)) {
                last.2 = depth + 1;
            }
        } else {
            out.push((t1, b));
            stack.pop();
            t0 = t1;
            a = b;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn straight_map_is_split_only_by_length() {
        let map = |t: f64| DVec3::new(10.0 * t, 0.0, 0.0);
        let (mut st, mut out) = (Vec::new(), Vec::new());
        split(&map, map(0.0), 0.01, 1.0, &mut st, &mut out);
        assert_eq!(out.len(), 16); // 10 mm in halvings: 0.625 mm pieces
        assert_eq!(out.last().map(|o| o.0), Some(1.0));
        for w in out.windows(2) {
            assert!(w[0].0 < w[1].0);
        }
    }

    #[test]
    fn parabola_meets_tolerance() {
        // z = 0.03·x² over x ∈ [-10, 10]
        let map = |t: f64| {
            let x = -10.0 + 20.0 * t;
            DVec3::new(x, 0.0, 0.03 * x * x)
        };
        let (mut st, mut out) = (Vec::new(), Vec::new());
        split(&map, map(0.0), 0.01, 100.0, &mut st, &mut out);
        let mut t0 = 0.0;
        let mut a = map(0.0);
        for &(t1, b) in &out {
            for k in 1..100 {
                let t = t0 + (t1 - t0) * k as f64 / 100.0;
                assert!(dist_to_segment(map(t), a, b) <= 0.01 + 1e-12);
            }
            t0 = t1;
            a = b;
        }
    }

    #[test]
    fn concave_bound_holds_for_a_tent_and_is_9_8_for_a_parabola() {
        // a tent of height 1: exact with its apex in the middle quarters, at most 4/3 in the
        // outer ones (one chord extension only)
        for apex in [0.01, 0.2, 0.25, 0.3, 0.49, 0.6, 0.75, 0.8, 0.99] {
            let tent = |t: f64| {
                if t < apex {
                    t / apex
                } else {
                    (1.0 - t) / (1.0 - apex)
                }
            };
            let b = concave_bound([0.25, 0.5, 0.75].map(tent));
            let most = if apex > 0.25 && apex < 0.75 {
                1.0
            } else {
                4.0 / 3.0
            };
            assert!(
                b >= 1.0 - 1e-12 && b <= most + 1e-12,
                "apex {apex}: bound {b}"
            );
        }
        let parabola = |t: f64| 4.0 * t * (1.0 - t);
        let b = concave_bound([0.25, 0.5, 0.75].map(parabola));
        assert!((b - 1.125).abs() < 1e-12, "{b}");
    }

    /// The quick decision is the bound's own on random samples (d ≥ 0, a zero, equal values)
    /// against tolerances at, just off and between m and 2m, and the bound lies in [m, 2m].
    #[test]
    fn concave_bound_exceeds_decides_as_the_bound() {
        let mut rng = crate::test_rng::Lcg(0x9e37_79b9_7f4a_7c15);
        let mut unit = move || rng.unit();
        for k in 0..200_000 {
            let mut d = [unit(), unit(), unit()].map(|u| u * 10f64.powi((k % 7) as i32 - 4));
            match k % 5 {
                0 => d[k % 3] = 0.0,
                1 => d[(k + 1) % 3] = d[k % 3],
                2 => d = [0.0, d[1], 0.0],
                _ => {}
            }
            let m = d[0].max(d[1]).max(d[2]);
            let b = concave_bound(d);
            assert!(
                b >= m && b <= 2.0 * m * (1.0 + 1e-12),
                "{d:?}: bound {b}, max {m}"
            );
            for tol in [
                m,
                2.0 * m,
                b,
                m * (1.0 + unit()),
                b * (1.0 - 1e-16),
                b * (1.0 + 1e-16),
                2.0 * m * (1.0 + 2e-9),
                unit() * 3.0 * m,
            ] {
                assert_eq!(
                    concave_bound_exceeds(d, tol),
                    b > tol,
                    "{d:?} against {tol}: bound {b}"
                );
            }
        }
        assert!(
            concave_bound_exceeds([f64::NAN, 0.0, 0.0], 1.0)
                == (concave_bound([f64::NAN, 0.0, 0.0]) > 1.0)
        );
    }

    #[test]
    fn crease_between_quarter_samples_is_found() {
        // the worst case of the old quarter-point test: the crease at ⅛ of a piece, where the
        // samples see ¾·(1/(1 − ⅛))… of the peak
        for c in [0.3, 1.25, 3.3, 6.2] {
            let map = |t: f64| {
                let x = -10.0 + 20.0 * t;
                DVec3::new(x, 0.0, 0.2 * (x - c).abs())
            };
            let (mut st, mut out) = (Vec::new(), Vec::new());
            split(&map, map(0.0), 0.01, 1.0, &mut st, &mut out);
            let (mut t0, mut a) = (0.0, map(0.0));
            for &(t1, b) in &out {
                for k in 1..400 {
                    let t = t0 + (t1 - t0) * k as f64 / 400.0;
                    let d = dist_to_segment(map(t), a, b);
                    assert!(d <= 0.01 + 1e-9, "crease {c}: {d} on {t0}..{t1}");
                }
                t0 = t1;
                a = b;
            }
        }
    }

    #[test]
    fn crease_off_centre_is_found() {
        // |x − 3.3| over x ∈ [-10, 10], slope 0.5
        let map = |t: f64| {
            let x = -10.0 + 20.0 * t;
            DVec3::new(x, 0.0, 0.5 * (x - 3.3).abs())
        };
        let (mut st, mut out) = (Vec::new(), Vec::new());
        split(&map, map(0.0), 0.01, 100.0, &mut st, &mut out);
        let mut t0 = 0.0;
        let mut a = map(0.0);
        for &(t1, b) in &out {
            for k in 1..200 {
                let t = t0 + (t1 - t0) * k as f64 / 200.0;
                assert!(
                    dist_to_segment(map(t), a, b) <= 0.01 + 1e-9,
                    "piece {t0}..{t1}"
                );
            }
            t0 = t1;
            a = b;
        }
    }
}
