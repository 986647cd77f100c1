//! Closed-form bounds of the firmware's interpolation error (issue 13): the lemmas the machines'
//! [`super::Machine::interpolation_bound`] are built from, so that a piece whose bound is small
//! enough needs none of the interpolation check's samples ([`super::tessellate`]).
//!
//! ## What is bounded
//! A piece goes from axes `a₀` (pose `(p₀, r₀) = forward(a₀)`) to `a₁`, with intended tool axes
//! `n₀, n₁` (unit). The firmware's path is `F(s) = forward((1 − s) a₀ + s a₁)`, the intended
//! one `E(s) = forward(inverse(p(s), slerp(n₀, n₁, s), a₀))`, `p(s) = (1 − s) p₀ + s p₁`
//! (seed 001 §4.5; [`super::tessellate`]). A bound `(β_p, β_a)` promises, for every s ∈ [0, 1],
//! `|F(s).tip − E(s).tip| ≤ β_p` (mm) and `∠(F(s).axis, E(s).axis) ≤ β_a` (degrees), and that
//! `inverse` succeeds all along (the sampling would otherwise report its error). The law
//! [`super::laws::check_interpolation_bound`] checks every machine's bound against dense
//! sampling.
//!
//! ## Lemma 1 (chord deviation)
//! A curve `f: [0, 1] → ℝ³` with `|f''| ≤ M` deviates from the chord at the same parameter,
//! `f(s) − ((1 − s) f(0) + s f(1))`, by at most `s(1 − s)/2 · M ≤ M/8` (the error of linear
//! interpolation, written with the non-negative Green's function of `d²/ds²` on [0, 1], whose
//! integral is `s(1 − s)/2`). [`chord_deviation`].
//!
//! ## Lemma 2 (rotations turned linearly)
//! A vector `R(θ(s)) v` rotated about a fixed unit axis by an angle linear in s (total `K`
//! radians) has `|d/ds| ≤ K|v|` and `|d²/ds²| ≤ K²|v|`. A unit vector `u(φ(s), t(s))` in
//! spherical coordinates with φ and t linear (totals `Δφ`, `Δt` radians) has
//! `|u''| ≤ Δt² + 2|Δt Δφ| + Δφ² = (|Δt| + |Δφ|)²` and length `≤ |Δt| + |Δφ|`.
//!
//! ## Lemma 3 (slerp against its chord)
//! `slerp(u₀, u₁, s)` runs along a great circle at constant speed w = ∠(u₀, u₁): `|f''| = w²`,
//! so it is within `w²/8` of the chord (Lemma 1).
//!
//! ## Lemma 4 (azimuth of a slerp)
//! The azimuth ψ(s) of the projection `m(s)` of `slerp(n₀, n₁, s)` onto a plane (xy for a
//! rotating nozzle, xz for a B head) against its linear interpolation: `|m'| ≤ w`, `|m''| ≤ w²`,
//! `ψ' = (m × m')/|m|²`, `ψ'' = (m × m'')/|m|² − 2 (m × m')(m · m')/|m|⁴`, so
//! `|ψ''| ≤ w²/ρ + 2 w²/ρ²` with ρ ≤ |m(s)|; and `ψ(s) − ((1 − s) ψ₀ + s ψ₁)` is within that
//! over 8 (Lemma 1). For w < π, `slerp(s) = (α + β)·((1 − λ) n₀ + λ n₁)` with α, β ≥ 0 and
//! `α + β = (sin((1 − s)w) + sin(sw))/sin w ≥ 1` (sin is concave), so ρ can be the distance
//! from the origin to the segment between the projections of n₀ and n₁ ([`segment_distance`]).
//!
//! ## Geodesic convexity
//! A great-circle arc shorter than π between two axes tilted at most T ≤ 90° from a pole stays
//! within T of it: `cos ∠(pole, slerp(s)) = R cos(ws − δ)` is a sinusoid, and on an interval
//! shorter than π whose ends are within π/2 of its crest it cannot reach its trough. So a
//! machine whose reachable axes are such a cap accepts every axis of the slerp
//! ([`arc_in_cap`]).

use glam::{DVec2, DVec3};

use super::PieceEnd;
use crate::num;

/// Slack added to a closed-form tip bound, mm: the intended pose is `forward(inverse(·))`,
/// equal to the asked tip within the round-trip law's 1e-9 mm (`laws::POSITION_TOLERANCE`),
/// plus the rounding of interpolating the axes (ulps of coordinates below 10⁴ mm); ten times
/// their sum.
pub const ROUND_TRIP_SLACK_MM: f64 = 1e-8;
/// Slack added to a closed-form tool-axis bound, degrees: the round trip's 1e-9 rad
/// (`laws::ANGLE_TOLERANCE`) at each end and along the path, and the slerp's rounding; about
/// ten times their sum (1e-7° ≈ 1.7e-9 rad … rounded up to 1e-6°).
pub const ROUND_TRIP_SLACK_DEG: f64 = 1e-6;
/// Smallest distance of an axis's projection from the origin (Lemma 4's ρ) for which a closed
/// form is given: nearer the pole the azimuth turns too fast to bound usefully (sample there).
pub const MIN_PROJECTION: f64 = 1e-3;
/// How far (degrees) an axis must stay from a clip, a hold zone or the end of a rotary range
/// for a closed form: it must not switch branch inside the piece.
pub const BRANCH_MARGIN_DEG: f64 = 1e-3;

/// Largest |axis value| (mm or degrees) for which [`ROUND_TRIP_SLACK_MM`] covers the
/// rounding of interpolating the axes (a few ulps of 10⁴ are ~10⁻¹² mm); beyond, sample.
pub const COORDINATE_LIMIT: f64 = 1e4;

/// Both ends of a piece have `count` axis values, all within [`COORDINATE_LIMIT`] (finite).
pub fn usable(from: PieceEnd, to: PieceEnd, count: usize) -> bool {
    [from.0, to.0]
        .iter()
        .all(|a| a.len() == count && a.iter().all(|v| v.abs() <= COORDINATE_LIMIT))
}

/// How far (degrees) an end's rotary value may differ from the azimuth of its asked axis for
/// the closed forms built on Lemma 4 (the rounding of the kinematics' degree/radian
/// conversions, ~10⁻¹³°, is far below): the end realises the asked azimuth, not a held or
/// clipped one.
pub const AZIMUTH_MATCH_DEG: f64 = 1e-7;

/// Lemma 1: largest deviation from the chord of a curve with `|f''| ≤ acceleration`.
pub fn chord_deviation(acceleration: f64) -> f64 {
    acceleration / 8.0
}

/// The angle (degrees) between two unit vectors at most `chord` apart: `2 asin(chord/2)`.
pub fn angle_of_chord(chord: f64) -> f64 {
    num::deg(2.0 * num::asin((chord / 2.0).min(1.0)))
}

/// Lemma 2 and 3 for a unit vector turned by rotations linear in s whose total angles sum to
/// `k` radians, against the slerp of its ends: its chord deviation `k²/8` plus the slerp's
/// `w²/8` (w ≤ k, the curve's length), as an angle, degrees.
pub fn turned_axis_deviation_deg(k: f64) -> f64 {
    angle_of_chord(chord_deviation(k * k) + chord_deviation(k * k))
}

/// Distance from the origin to the segment between `a` and `b` (Lemma 4's ρ).
pub fn segment_distance(a: DVec2, b: DVec2) -> f64 {
    let d = b - a;
    let l2 = d.length_squared();
    let t = if l2 > 0.0 {
        (-a.dot(d) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + d * t).length()
}

/// Lemma 4: the largest difference (radians) between the azimuth of the projection of
/// `slerp(n₀, n₁, s)` and the linear interpolation of its end azimuths, given the projections
/// `m0`, `m1` of the unit vectors n₀, n₁ and `w = ∠(n₀, n₁)` (radians). `None` when the
/// projection comes nearer the origin than [`MIN_PROJECTION`] or than w: with w ≤ ρ the
/// azimuth turns by at most `∫|ψ'| ≤ w/ρ ≤ 1` radian along the piece, so its continuous change
/// is the wrapped difference of the end azimuths.
pub fn azimuth_deviation(m0: DVec2, m1: DVec2, w: f64) -> Option<f64> {
    let rho = segment_distance(m0, m1);
    if !(rho >= MIN_PROJECTION && w <= rho) {
        return None;
    }
    Some(chord_deviation(w * w / rho + 2.0 * w * w / (rho * rho)))
}

/// Lemma 4 for the slerp from `n0` to `n1` projected by `project` onto a plane (its xy or xz
/// components): [`azimuth_deviation`] with w = ∠(n₀, n₁).
pub fn slerp_azimuth_deviation(n0: DVec3, n1: DVec3, project: fn(DVec3) -> DVec2) -> Option<f64> {
    azimuth_deviation(project(n0), project(n1), angle(n0, n1))
}

/// The angle between two unit vectors, radians (0 without trigonometry when equal).
pub fn angle(a: DVec3, b: DVec3) -> f64 {
    if a == b {
        0.0
    } else {
        num::angle_between(a, b)
    }
}

/// Geodesic convexity: every axis of the slerp from `n0` to `n1` (unit, w < π) lies within
/// `max_tilt_deg` (at most 90°) of `pole` when both ends do.
pub fn arc_in_cap(n0: DVec3, n1: DVec3, pole: DVec3, max_tilt_deg: f64) -> bool {
    max_tilt_deg <= 90.0
        && angle(n0, n1) < core::f64::consts::PI - 1e-6
        && [n0, n1]
            .iter()
            .all(|n| num::deg(angle(*n, pole)) <= max_tilt_deg)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn segment_distance_is_to_the_nearest_point() {
        let d = segment_distance(DVec2::new(-1.0, 1.0), DVec2::new(1.0, 1.0));
        assert!((d - 1.0).abs() < 1e-15);
        let d = segment_distance(DVec2::new(1.0, 1.0), DVec2::new(2.0, 1.0));
        assert!((d - 2f64.sqrt()).abs() < 1e-15);
    }

    #[test]
    fn the_chord_of_a_circle_arc_meets_lemma_1() {
        // unit circle turned by k radians: |f''| = k², the sagitta is 1 − cos(k/2) ≤ k²/8
        for k in [0.01f64, 0.1, 0.5, 1.0] {
            let sagitta = 1.0 - (k / 2.0).cos();
            assert!(sagitta <= chord_deviation(k * k) + 1e-15);
            assert!(
                sagitta > 0.9 * chord_deviation(k * k),
                "Lemma 1 is tight here"
            );
        }
    }
}
