//! How far an azimuth can move when a request turns a little: the pieces of
//! [`super::Machine::start_drift_deg`] (the bound that lets the tessellation skip its
//! held-axis probe; law 7, [`super::laws::check_start_drift`], checks every machine's).
//!
//! ## The azimuth's drift
//! Let ψ be the azimuth of a unit vector about a unit axis `a`, and ρ = sin θ the length of
//! its part perpendicular to `a` (θ the angle from `a`). Along a great-circle arc of length
//! `T` from `n` to `n'`, `|d sin θ| ≤ |dθ| ≤ ds`, so the arc keeps `sin θ ≥ ρ − T`, and
//! `ds² = dθ² + sin²θ dψ²` gives `|dψ| ≤ ds / sin θ`. Hence, with ψ followed continuously
//! along the arc,
//!
//! ```text
//! |ψ(n') − ψ(n)| ≤ T / (ρ − T)        (ρ > T)
//! ```
//!
//! [`azimuth_drift`] gives it where it is at most 1 rad (ρ ≥ 2T).
//!
//! ## Clear of a direction
//! An azimuth computed with `atan2` jumps by 2π at its cut, and a rotation taken into a range
//! may switch ends at a point of the circle (the rotating nozzle's shadow middle). A drift
//! of at most `d` (≤ 1 rad) cannot reach such a point `u` when the angle between the plane
//! vector `v` and `u` exceeds `d`: [`clear_of`] decides it without trigonometry, as
//! `v·u < 0` or `|v × u| > 2d (v·u)` (`tan x ≤ 2x` for `0 ≤ x ≤ 1`, so the angle's tangent
//! exceeds `tan d`).

use glam::DVec2;

/// Rounding slack of a drift bound, degrees: the azimuths come from `atan2`, a clamp and a
/// degree conversion (a few ulps of at most 360°, ≈ 1e-13°), far below this.
pub const DRIFT_SLACK_DEG: f64 = 1e-9;

/// The bound `T / (ρ − T)` (radians) on the azimuth's move for a turn of the request by at
/// most `turn` radians (the module's "The azimuth's drift"), `perp` the request's part
/// perpendicular to the azimuth's axis and `len` the request's length. `None` where
/// `ρ = |perp|/len < 2·turn` (near the pole, where the azimuth is held or the bound exceeds
/// 1 rad), or for a non-finite input.
pub fn azimuth_drift(perp: DVec2, len: f64, turn: f64) -> Option<f64> {
    let rho = perp.length() / len;
    // `!(… >= …)`: a NaN gives no bound
    if !(turn >= 0.0 && rho >= 2.0 * turn && rho > super::POLE_EPSILON) {
        return None;
    }
    Some(turn / (rho - turn))
}

/// Whether the direction of the plane vector `v` is more than `angle` radians (`0 ≤ angle ≤
/// 1`) from the unit direction `u` (the module's "Clear of a direction"). False for a zero
/// or non-finite `v` or an angle outside [0, 1].
pub fn clear_of(v: DVec2, u: DVec2, angle: f64) -> bool {
    if !(v.length() > super::POLE_EPSILON && (0.0..=1.0).contains(&angle)) {
        return false;
    }
    let (cross, dot) = (v.perp_dot(u).abs(), v.dot(u));
    dot < 0.0 || cross > 2.0 * angle * dot
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::num;

    /// The drift bound holds for random requests turned by at most `turn` (the azimuth
    /// difference measured with `atan2`, unwrapped), and is refused near the pole.
    #[test]
    fn an_azimuths_drift_stays_within_its_bound() {
        let mut rng = crate::test_rng::Lcg(17);
        let mut checked = 0;
        for _ in 0..20_000 {
            let n = crate::machine::laws::axis(rng.range(0.0, 180.0), rng.range(-180.0, 180.0));
            let turn = 10f64.powf(rng.range(-8.0, -1.0));
            let about = n.cross(glam::DVec3::new(rng.unit(), rng.unit(), rng.unit()) - 0.5);
            if about.length() < 1e-3 {
                continue;
            }
            let m = crate::machine::angles::rotate(n, about.normalize(), turn * rng.unit());
            let Some(d) = azimuth_drift(n.truncate(), n.length(), turn) else {
                assert!(n.truncate().length() < 2.0 * turn * (1.0 + 1e-12));
                continue;
            };
            let dpsi = crate::machine::angles::wrap180(num::deg(
                num::atan2(m.y, m.x) - num::atan2(n.y, n.x),
            ))
            .abs();
            assert!(
                num::rad(dpsi) <= d * (1.0 + 1e-9) + 1e-15,
                "{n} {m}: {dpsi}° > {d} rad"
            );
            checked += 1;
        }
        assert!(checked > 15_000, "{checked}");
        // the worst case: a turn of half of ρ in every direction (the azimuth then moves by up
        // to asin(sin T / ρ), above T/ρ and below T/(ρ − T))
        for theta in [0.001, 0.01, 0.1, 0.5, 1.0, 1.5] {
            let n = crate::machine::laws::axis(num::deg(theta), 30.0);
            let turn = num::sin(theta) / 2.0;
            let d = azimuth_drift(n.truncate(), n.length(), turn).unwrap();
            let side = n.any_orthonormal_vector();
            let mut worst = 0.0f64;
            for k in 0..3600 {
                let about = crate::machine::angles::rotate(side, n, num::rad(0.1 * k as f64));
                let m = crate::machine::angles::rotate(n, about, turn);
                let dpsi = crate::machine::angles::wrap180(num::deg(
                    num::atan2(m.y, m.x) - num::atan2(n.y, n.x),
                ));
                worst = worst.max(num::rad(dpsi.abs()));
            }
            assert!(worst <= d, "θ {theta}: {worst} > {d} rad");
            assert!(
                worst > turn / n.truncate().length(),
                "θ {theta}: {worst} rad"
            );
        }
        assert_eq!(azimuth_drift(DVec2::new(1e-7, 0.0), 1.0, 1e-7), None);
        assert_eq!(azimuth_drift(DVec2::new(f64::NAN, 0.0), 1.0, 1e-7), None);
    }

    /// `clear_of` agrees with the computed angle away from the factor 2 it gives away, and
    /// never says clear within the angle.
    #[test]
    fn clear_of_a_direction_is_the_computed_angle_or_safer() {
        let mut rng = crate::test_rng::Lcg(5);
        for _ in 0..20_000 {
            let a = rng.range(-180.0, 180.0);
            let v = DVec2::new(num::cos(num::rad(a)), num::sin(num::rad(a))) * rng.range(0.1, 3.0);
            let u = DVec2::new(1.0, 0.0);
            let angle = rng.unit();
            let between = num::atan2(v.perp_dot(u).abs(), v.dot(u));
            let clear = clear_of(v, u, angle);
            if between <= angle {
                assert!(!clear, "{a}° is within {angle} rad");
            }
            if between > 2.0 * angle * 1.000_001 {
                assert!(clear, "{a}° is beyond twice {angle} rad");
            }
        }
        assert!(!clear_of(DVec2::ZERO, DVec2::X, 0.1));
        assert!(!clear_of(DVec2::Y, DVec2::X, 1.5));
    }
}
