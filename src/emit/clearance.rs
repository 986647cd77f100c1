//! What a lift must clear: the head as a **clearance profile** about its tool axis
//! ([`HeadProfile`]), and the printed material as something that answers "how high must the tip
//! be for the head to clear you here" ([`Printed`]).
//!
//! Both are plain data below the unwarp and the machines: a machine fills the profile from its
//! head solids (`crate::machine::head::clearance_profile`) and hands it over through its emitter
//! ([`super::Emitter::head_profile`]); the unwarp's height grid answers [`Printed`] for its
//! lifted travels and for the lifts a machine emitter makes on its own (a rotate-around, a
//! swing lift). The 3-axis emitter has no profile: its travels are planned for the tip only.
//!
//! ## The profile (tool frame, mm)
//! The tool frame has its origin at the tip and its axis `s` along the tool axis `n` (tip →
//! nozzle body). A [`ProfilePiece`] says: every point of the head with `from_mm ≤ s ≤ to_mm`
//! lies within the radius `r(s)` of the tool axis, and at most `δ(s)` from it **towards the
//! tilt's steepest descent** (the unit vector `e ⟂ n` in the vertical plane of `n`, `e_z =
//! −sin θ`); `r` and `δ` are linear in `s` between their values at the two ends, `δ ≤ r`. A
//! cone of half-angle α has `r(s) = r_tip + (s − from)·tan α = δ(s)`; a cylinder `r = δ = R`; a
//! box of a head that tilts in the vertical plane of its tool axis (its x axis is `±e`) has
//! `r` = its farthest corner from the axis and `δ = max(|x_min|, |x_max|)`; a box turned
//! arbitrarily about `n` has `δ = r`.
//!
//! With the tool axis tilted by θ from +Z (`n_z = cos θ`), a head point `q = s·n + v` (`v ⟂ n`,
//! `|v| ≤ r(s)`, `|v·e| ≤ δ(s)`) lies
//! - at most `g(s) = |s|·sin θ + r(s)` from the tip horizontally (|horizontal part of v| ≤ |v|),
//! - at least `h(s) = s·cos θ − δ(s)·sin θ` above the tip (`v_z = (v·e)·e_z`: the other
//!   direction ⟂ n is horizontal).
//!
//! [`HeadProfile::floor`]`(θ, d)` is the least `h(s)` over the pieces' `s` with `g(s) ≥ d`: no
//! head point at a horizontal distance ≥ d from the tip is lower than that above it. It is
//! exact for the cone's and cylinder's lowest generator and conservative elsewhere (a box's
//! corner is taken at its lowest `h` and its farthest `g` at once). For `s ≥ 0` and θ in
//! [0°, 90°] it does not increase with θ (`∂h/∂θ = −s sin θ − δ cos θ ≤ 0`, `g` grows), so a
//! move whose tilt stays at or below θ is bounded by the profile at θ.
//!
//! ## The lift
//! A head at tip height `z` over a printed cell of top `t` at least `d` away horizontally clears
//! it when `z + floor(θ, d) > t`. [`Printed::head_clear_z`] is the largest `t − floor(θ, d)`
//! over the cells in reach; a lift puts the tip [`HEAD_CLEARANCE_MM`] above that (and never
//! lower than the tip's own rule: the travel clearance above the printed top, or a
//! rotate-around's 1 mm).

use glam::DVec2;

/// Clearance of the head's profile above printed material in a lift, mm. Smaller than the
/// tip's 1 mm travel clearance: the profile already contains the head (boxes as their hulls,
/// the tilt at its largest) and the height grid holds each cell's highest bead top, so it is a
/// margin against the firmware's rounding and the bead's squish, not the only safety.
pub const HEAD_CLEARANCE_MM: f64 = 0.5;

/// One piece of a [`HeadProfile`] (see the module documentation), mm.
#[derive(Clone, Debug, PartialEq)]
pub struct ProfilePiece {
    /// The head part it bounds (`nozzle`, `heater-block`, …).
    pub name: String,
    /// Lowest `s` (along the tool axis from the tip).
    pub from_mm: f64,
    /// Highest `s`.
    pub to_mm: f64,
    /// Radius about the tool axis at `from_mm` and at `to_mm` (linear between).
    pub radius_mm: [f64; 2],
    /// Reach towards the tilt's steepest descent at `from_mm` and at `to_mm` (linear between;
    /// at most the radius).
    pub drop_mm: [f64; 2],
}

impl ProfilePiece {
    /// `(r(s), δ(s))` at `s` in `[from_mm, to_mm]`.
    fn at(&self, s: f64) -> (f64, f64) {
        let len = self.to_mm - self.from_mm;
        let t = if len > 0.0 {
            ((s - self.from_mm) / len).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let lerp = |v: [f64; 2]| v[0] + (v[1] - v[0]) * t;
        (lerp(self.radius_mm), lerp(self.drop_mm))
    }

    /// `g(s)`: the farthest horizontal distance from the tip at `s`, tilt with `sin θ = st`.
    fn reach_at(&self, s: f64, st: f64) -> f64 {
        s.abs() * st + self.at(s).0
    }

    /// `h(s)`: the least height above the tip at `s`, tilt `(sin θ, cos θ) = (st, ct)`.
    fn low_at(&self, s: f64, st: f64, ct: f64) -> f64 {
        s * ct - self.at(s).1 * st
    }

    /// `(g, h)` at both ends at one tilt: what [`ProfilePiece::floor`] needs whatever `d`.
    fn ends(&self, st: f64, ct: f64) -> PieceEnds {
        let (a, b) = (self.from_mm, self.to_mm);
        PieceEnds {
            ga: self.reach_at(a, st),
            gb: self.reach_at(b, st),
            ha: self.low_at(a, st, ct),
            hb: self.low_at(b, st, ct),
        }
    }

    /// The least `h(s)` over the `s` of this piece with `g(s) ≥ d` (+∞: none reaches `d`).
    /// `g` is linear in `s` where `s` keeps its sign, so the set is an interval found from
    /// the ends (a piece across `s = 0` is taken whole where either end reaches `d`).
    #[cfg(test)]
    fn floor(&self, st: f64, ct: f64, d: f64) -> f64 {
        self.floor_from(self.ends(st, ct), st, ct, d)
    }

    /// [`ProfilePiece::floor`] from the piece's [`PieceEnds`] at the tilt `(st, ct)`.
    fn floor_from(&self, e: PieceEnds, st: f64, ct: f64, d: f64) -> f64 {
        let (a, b) = (self.from_mm, self.to_mm);
        let PieceEnds { ga, gb, ha, hb } = e;
        if ga < d && gb < d {
            return f64::INFINITY;
        }
        if (ga >= d && gb >= d) || a < 0.0 {
            return ha.min(hb);
        }
        // one end reaches d: the crossing s_d of the linear g, and h there (h is linear too)
        let s_d = a + (b - a) * (d - ga) / (gb - ga);
        let h_d = self.low_at(s_d, st, ct);
        if ga >= d {
            ha.min(h_d)
        } else {
            hb.min(h_d)
        }
    }
}

/// The head as seen by a lift (see the module documentation).
#[derive(Clone, Debug, PartialEq)]
pub struct HeadProfile {
    /// The pieces, any order.
    pub pieces: Vec<ProfilePiece>,
    /// The tilts the machine realises (radians from +Z, lowest and highest): a tilt asked of
    /// [`HeadProfile::floor`] or [`HeadProfile::reach`] is taken into this range first (a 3-axis
    /// head stays vertical whatever the layer's normal, the RTN nozzle is always at 45°).
    pub tilt_range: [f64; 2],
}

impl Default for HeadProfile {
    fn default() -> Self {
        HeadProfile {
            pieces: Vec::new(),
            tilt_range: [0.0, std::f64::consts::PI],
        }
    }
}

impl HeadProfile {
    /// The tilt the machine realises for a requested tilt θ (radians).
    pub fn realised_tilt(&self, tilt: f64) -> f64 {
        tilt.clamp(
            self.tilt_range[0],
            self.tilt_range[1].max(self.tilt_range[0]),
        )
    }

    /// The farthest any head point gets from the tip horizontally at tilt θ (radians), mm.
    pub fn reach(&self, tilt: f64) -> f64 {
        let tilt = self.realised_tilt(tilt);
        let st = crate::num::sin(tilt).abs();
        self.pieces
            .iter()
            .map(|p| p.reach_at(p.from_mm, st).max(p.reach_at(p.to_mm, st)))
            .fold(0.0, f64::max)
    }

    /// No head point at a horizontal distance of `d` mm or more from the tip is lower than
    /// this above the tip, at tilt θ (radians from +Z); +∞ when none reaches `d`.
    pub fn floor(&self, tilt: f64, d: f64) -> f64 {
        self.at_tilt(tilt).floor(d)
    }

    /// The profile at one tilt θ (radians from +Z): [`TiltedProfile::floor`] for many `d`
    /// (a lift's height over many cells) without the tilt's sine, cosine and the pieces' ends
    /// computed again for each.
    pub fn at_tilt(&self, tilt: f64) -> TiltedProfile<'_> {
        let tilt = self.realised_tilt(tilt);
        let (st, ct) = (crate::num::sin(tilt).abs(), crate::num::cos(tilt));
        TiltedProfile {
            pieces: &self.pieces,
            ends: self.pieces.iter().map(|p| p.ends(st, ct)).collect(),
            st,
            ct,
        }
    }
}

/// `g` (reach) and `h` (height) at a piece's two ends, at one tilt.
#[derive(Clone, Copy, Debug)]
struct PieceEnds {
    ga: f64,
    gb: f64,
    ha: f64,
    hb: f64,
}

/// A [`HeadProfile`] at one tilt ([`HeadProfile::at_tilt`]).
#[derive(Clone, Debug)]
pub struct TiltedProfile<'a> {
    pieces: &'a [ProfilePiece],
    ends: Vec<PieceEnds>,
    st: f64,
    ct: f64,
}

impl TiltedProfile<'_> {
    /// [`HeadProfile::floor`] at this tilt: the same value.
    pub fn floor(&self, d: f64) -> f64 {
        self.pieces
            .iter()
            .zip(&self.ends)
            .map(|(p, e)| p.floor_from(*e, self.st, self.ct, d))
            .fold(f64::INFINITY, f64::min)
    }
}

/// Distance from `q` to the segment `a → b` (XY, mm).
pub fn segment_distance(q: DVec2, a: DVec2, b: DVec2) -> f64 {
    let ab = b - a;
    let len2 = ab.length_squared();
    let t = if len2 > 0.0 {
        ((q - a).dot(ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (q - (a + ab * t)).length()
}

/// Printed material as a lift sees it.
pub trait Printed {
    /// The lowest tip height at which the head (`profile`, tool axis tilted by at most `tilt`
    /// radians from +Z), with its tip anywhere within `pad` mm of the XY segment `a → b`, is
    /// above all printed material: the largest `top − profile.floor(tilt, d)` over what was
    /// printed, `d` a lower bound of its horizontal distance from the tip. −∞ when nothing
    /// printed is within the head's reach.
    fn head_clear_z(&self, profile: &HeadProfile, a: DVec2, b: DVec2, pad: f64, tilt: f64) -> f64;
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cone(half_angle_deg: f64) -> ProfilePiece {
        let r1 = 0.5 + 4.5 * half_angle_deg.to_radians().tan();
        ProfilePiece {
            name: "nozzle".into(),
            from_mm: 0.0,
            to_mm: 4.5,
            radius_mm: [0.5, r1],
            drop_mm: [0.5, r1],
        }
    }

    #[test]
    fn a_vertical_cone_is_as_high_as_its_generator_at_each_distance() {
        // θ = 0: g(s) = r(s) = 0.5 + s·tan α, h(s) = s, so floor(d) = (d − 0.5)/tan α
        let p = HeadProfile {
            pieces: vec![cone(40.0)],
            ..HeadProfile::default()
        };
        let k = 40f64.to_radians().tan();
        for d in [0.5, 1.0, 2.0, 4.0] {
            assert!((p.floor(0.0, d) - (d - 0.5) / k).abs() < 1e-12, "d = {d}");
        }
        assert_eq!(p.floor(0.0, 0.2), 0.0);
        assert_eq!(p.floor(0.0, 10.0), f64::INFINITY);
    }

    #[test]
    fn a_tilted_box_drops_by_its_reach_towards_the_descent() {
        // a block 4.5…16 mm up the axis reaching 14 mm towards the descent, tilted 45°: its
        // lowest corner is 4.5·cos 45° − 14·sin 45° below the tip (−6.72 mm)
        let p = HeadProfile {
            pieces: vec![ProfilePiece {
                name: "heater-block".into(),
                from_mm: 4.5,
                to_mm: 16.0,
                radius_mm: [16.12, 16.12],
                drop_mm: [14.0, 14.0],
            }],
            ..HeadProfile::default()
        };
        let t = 45f64.to_radians();
        let want = (4.5 - 14.0) * t.cos();
        assert!((p.floor(t, 0.0) - want).abs() < 1e-12);
        assert!((p.reach(t) - (16.0 * t.sin() + 16.12)).abs() < 1e-12);
    }
}
