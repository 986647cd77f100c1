//! G2/G3 arcs in the XY plane (G17) → straight pieces within a chord tolerance.
//!
//! Geometry, XY plane, angles counter-clockwise from +X:
//! - I/J form: centre c = start + (I, J) (always relative to the start, Marlin/RRF).
//! - R form: with chord d = |end − start|, midpoint m and h = √(R² − (d/2)²), the centre lies at
//!   m ± h·u⊥ (u⊥ = the chord direction turned 90°); R > 0 takes the arc of at most 180°,
//!   R < 0 the longer one. |R| < d/2 (beyond [`ARC_RADIUS_SLACK`]) has no solution → error.
//! - Sweep: θ₀ = atan2(start − c), θ₁ = atan2(end − c); G3 (CCW) sweeps θ₁ − θ₀ wrapped into
//!   (0, 2π], G2 (CW) into [−2π, 0). An I/J arc that ends where it starts is a full circle.
//! - Pieces: a chord spanning angle φ on radius r stands off the arc by the sagitta
//!   s = r·(1 − cos(φ/2)); s ≤ tol ⇔ φ ≤ 2·acos(1 − tol/r). n = ⌈|sweep| / φ_max⌉ pieces of equal
//!   angle. Radius goes linearly from |start − c| to |end − c| (they differ by rounding in the
//!   file), Z (helix) linearly with the angle, and the last point is exactly the programmed end.
//!
//! Transcendentals go through [`crate::num`] so native and wasm agree bit for bit.

use glam::{DVec2, DVec3};

use crate::num;
use crate::tolerance::LENGTH_EPSILON;

/// How much |R| may fall short of half the chord and still be read as a half circle, mm
/// (files round R and the end point to 3 decimals).
pub const ARC_RADIUS_SLACK: f64 = 1e-3;
/// Largest accepted difference between the start radius and the end radius of an I/J arc, mm
/// (more means the centre does not fit the end point: the file is wrong).
pub const ARC_RADIUS_MISMATCH: f64 = 0.05;
/// Largest arc radius accepted, mm: 10 m, beyond any printer's bed (the unwarp's `--place` and
/// `--offset` are bounded alike). Arc fitters write large radii for gentle curves (ArcWelder
/// caps them at 9999 mm); `I-9000000` is no machine's arc, and expanding 3,000 of them took
/// 21 s. The number of pieces grows as the sweep × √(r / tolerance).
pub const MAX_ARC_RADIUS: f64 = 10_000.0;
/// Most pieces one arc may be split into (bounds memory per line; a 1 m radius full circle at a
/// 0.001 mm tolerance needs ~4 500).
pub const MAX_ARC_PIECES: usize = 100_000;

/// How the arc's centre is given.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Centre {
    /// I, J: centre offset from the start, mm.
    Offset(DVec2),
    /// R: signed radius, mm.
    Radius(f64),
}

/// Linearise an arc from `start` to `end`; `clockwise` for G2. Calls `piece(to)` with the end
/// point of every piece, in order; the last is `end` exactly. Returns the reason on a bad arc.
pub fn linearise(
    start: DVec3,
    end: DVec3,
    centre: Centre,
    clockwise: bool,
    tolerance: f64,
    mut piece: impl FnMut(DVec3),
) -> Result<(), String> {
    let s = start.truncate();
    let e = end.truncate();
    let c = match centre {
        Centre::Offset(o) => {
            if o.length() <= LENGTH_EPSILON {
                return Err("zero radius: I and J are both 0".into());
            }
            s + o
        }
        Centre::Radius(r) => r_centre(s, e, r, clockwise)?,
    };
    let r0 = (s - c).length();
    let r1 = (e - c).length();
    if !(r0.is_finite() && r1.is_finite() && c.is_finite()) {
        return Err("coordinates out of range".into());
    }
    if r0 <= LENGTH_EPSILON {
        return Err("zero radius".into());
    }
    if r0.max(r1) > MAX_ARC_RADIUS {
        return Err(format!(
            "radius {:.0} mm is larger than any machine ({MAX_ARC_RADIUS:.0} mm at most)",
            r0.max(r1)
        ));
    }
    if (r1 - r0).abs() > ARC_RADIUS_MISMATCH {
        return Err(format!(
            "the end point is {r1:.3} mm from the centre but the start is {r0:.3} mm from it"
        ));
    }
    let a0 = num::atan2(s.y - c.y, s.x - c.x);
    let a1 = num::atan2(e.y - c.y, e.x - c.x);
    let tau = 2.0 * core::f64::consts::PI;
    let full = matches!(centre, Centre::Offset(_)) && (e - s).length() <= LENGTH_EPSILON;
    let sweep = if full {
        if clockwise {
            -tau
        } else {
            tau
        }
    } else if clockwise {
        let mut d = a1 - a0;
        while d >= 0.0 {
            d -= tau;
        }
        while d < -tau {
            d += tau;
        }
        d
    } else {
        let mut d = a1 - a0;
        while d <= 0.0 {
            d += tau;
        }
        while d > tau {
            d -= tau;
        }
        d
    };
    let rmax = r0.max(r1);
    // an infinite tolerance (the reader outside the region): one piece
    let phi_max = if tolerance >= 2.0 * rmax {
        tau
    } else {
        2.0 * num::acos(1.0 - tolerance / rmax)
    };
    let n_f = (sweep.abs() / phi_max).ceil();
    if !(n_f.is_finite() && n_f >= 1.0) || n_f > MAX_ARC_PIECES as f64 {
        if n_f.is_finite() && n_f < 1.0 {
            // Cannot happen for sweep > 0, kept for safety.
            piece(end);
            return Ok(());
        }
        return Err(format!(
            "radius {rmax:.3} mm needs more than {MAX_ARC_PIECES} pieces at a {tolerance} mm tolerance"
        ));
    }
    let n = n_f as usize;
    for k in 1..n {
        let t = k as f64 / n as f64;
        let a = a0 + sweep * t;
        let r = r0 + (r1 - r0) * t;
        let z = start.z + (end.z - start.z) * t;
        piece(DVec3::new(c.x + r * num::cos(a), c.y + r * num::sin(a), z));
    }
    piece(end);
    Ok(())
}

/// Centre of an R-form arc (see the module doc).
fn r_centre(s: DVec2, e: DVec2, r: f64, clockwise: bool) -> Result<DVec2, String> {
    if r.abs() <= LENGTH_EPSILON {
        return Err("zero radius: R is 0".into());
    }
    let chord = e - s;
    let d = chord.length();
    if d <= LENGTH_EPSILON {
        return Err("an R arc cannot end where it starts (use I/J for a full circle)".into());
    }
    let half = d / 2.0;
    let ra = r.abs();
    if ra < half - ARC_RADIUS_SLACK {
        return Err(format!(
            "radius {ra:.3} mm is less than half the chord {half:.3} mm"
        ));
    }
    let h = (ra * ra - half * half).max(0.0).sqrt();
    let u = chord / d;
    // Left normal of the chord: for a CCW arc of ≤ 180° the centre is on the left.
    let left = DVec2::new(-u.y, u.x);
    let short = r > 0.0;
    let on_left = short != clockwise;
    let m = (s + e) / 2.0;
    Ok(if on_left { m + left * h } else { m - left * h })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pts(start: DVec3, end: DVec3, c: Centre, cw: bool, tol: f64) -> Vec<DVec3> {
        let mut v = vec![start];
        linearise(start, end, c, cw, tol, |p| v.push(p)).unwrap();
        v
    }

    #[test]
    fn r_form_picks_the_short_and_long_arcs() {
        let s = DVec3::new(10.0, 0.0, 0.0);
        let e = DVec3::new(0.0, 10.0, 0.0);
        // CCW, R=10: centre (0,0), quarter circle.
        let p = pts(s, e, Centre::Radius(10.0), false, 0.001);
        for q in &p {
            assert!((q.truncate().length() - 10.0).abs() < 1e-9);
        }
        // CCW, R=-10: centre (10,10), three quarters.
        let p2 = pts(s, e, Centre::Radius(-10.0), false, 0.001);
        for q in &p2 {
            assert!(((q.truncate() - DVec2::new(10.0, 10.0)).length() - 10.0).abs() < 1e-9);
        }
        assert!(p2.len() > 2 * p.len());
    }

    #[test]
    fn bad_arcs_are_refused() {
        let s = DVec3::ZERO;
        let e = DVec3::new(10.0, 0.0, 0.0);
        assert!(linearise(s, e, Centre::Radius(4.0), false, 0.01, |_| {}).is_err());
        assert!(linearise(s, e, Centre::Radius(0.0), false, 0.01, |_| {}).is_err());
        assert!(linearise(s, s, Centre::Radius(5.0), false, 0.01, |_| {}).is_err());
        assert!(linearise(s, e, Centre::Offset(DVec2::ZERO), false, 0.01, |_| {}).is_err());
        assert!(linearise(
            s,
            e,
            Centre::Offset(DVec2::new(1.0, 0.0)),
            false,
            0.01,
            |_| {}
        )
        .is_err());
    }
}
