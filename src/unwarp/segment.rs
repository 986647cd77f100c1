//! Adaptive splitting of a straight slicing-frame move under T⁻¹.
//!
//! A straight move q(t) = q₀ + t·(q₁ − q₀), t ∈ [0, 1], of the slicer maps to the curve
//! c(t) = T⁻¹(q(t)) in the model frame. The move is split at parameters t₀ < t₁ < … until, on
//! every piece, the exact image stays within `tolerance` of the chord (checked at ¼, ½ and ¾ of
//! the piece) and no chord is longer than `max_segment`. Splitting is by halving, so the result
//! is deterministic and exact for the quadratic curves of seed 000 Eq. 1 already at the
//! midpoint test; the quarter points catch creases (seed 000 Eq. 2, the cone apex).

use glam::DVec3;

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

/// Split [0, 1] for the curve `map` (t ↦ model point). Appends the end parameter of each
/// piece (in increasing order, the last being 1.0) and their mapped points to `out`.
/// `p0` = map(0). Reuses `stack` (no allocation in the steady state).
pub fn split(
    map: &dyn Fn(f64) -> DVec3,
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
                let mut worst = 0.0f64;
                for f in [0.25, 0.5, 0.75] {
                    let p = map(t0 + (t1 - t0) * f);
                    worst = worst.max(dist_to_segment(p, a, b));
                    if worst > tolerance {
                        break;
                    }
                }
                worst > tolerance
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
