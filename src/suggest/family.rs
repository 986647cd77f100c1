//! The warp families `suggest` searches, their parameters as coordinates, and the flags that
//! give a warp back to `warpslice warp`.
//!
//! Every candidate is held as the [`WarpParams`] its rounded coordinates give (angles to
//! 0.1°, lengths to 0.1 mm, strengths to 0.001, directions to 1°), so the flags written for it
//! are exactly the warp that was measured.

use serde::Serialize;

use crate::mesh::Aabb;
use crate::num;
use crate::warp::{Direction, WarpParams, WarpSpec, MONOTONIC_MARGIN};

/// A family of warps the search covers.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "lowercase")]
#[non_exhaustive]
pub enum Family {
    /// Conic layers (seed 002): direction, angle, centre.
    Conic,
    /// Tilted planes (seed 002 `--axis=3`): direction, angle.
    Belt,
    /// Parabolic layers (seed 000 Eq. 1): direction, strength, offset.
    Curved,
    /// Roof layers (seed 000 Eq. 2): direction, strength, offset.
    Tilted,
    /// A bicubic B-spline height fitted from the best warp of the others ([`super::fit`]).
    Field,
}

/// Every family, in the order ties are broken.
pub const FAMILIES: &[Family] = &[
    Family::Conic,
    Family::Belt,
    Family::Curved,
    Family::Tilted,
    Family::Field,
];

/// Every family's name (the `--families` choices).
pub const FAMILY_NAMES: &[&str] = &["conic", "belt", "curved", "tilted", "field"];

impl Family {
    /// The warp's name (`--warp`).
    pub fn name(self) -> &'static str {
        match self {
            Family::Conic => "conic",
            Family::Belt => "belt",
            Family::Curved => "curved",
            Family::Tilted => "tilted",
            Family::Field => "field",
        }
    }

    /// The family of a warp spec (`None`: cylindrical, spherical).
    pub fn of(spec: &WarpSpec) -> Option<Family> {
        FAMILIES.iter().copied().find(|f| f.name() == spec.name())
    }
}

impl std::str::FromStr for Family {
    type Err = String;
    fn from_str(s: &str) -> Result<Family, String> {
        FAMILIES
            .iter()
            .copied()
            .find(|f| f.name() == s.trim())
            .ok_or_else(|| format!("'{s}' is not a family: one of {}", FAMILY_NAMES.join(", ")))
    }
}

/// The shortest base blend z1 (mm) the search gives a warp: the first 2 mm stay flat-ish,
/// enough for a first layer and a brim.
pub const BASE_MIN_SPAN_MM: f64 = 2.0;
/// The base blend's span is this factor above the least that keeps ∂z'/∂z > 0
/// (1.5·max(−g), [`crate::warp::base`]), so the search's warps are not at the fold's edge.
pub const BASE_SPAN_FACTOR: f64 = 1.1;

/// Round to `step` (the coordinates' resolution), `-0` as `0`.
pub(crate) fn round_to(v: f64, step: f64) -> f64 {
    let r = (v / step).round() * step;
    // one more rounding through text drops the binary tail of step multiples (0.30000000000000004)
    let r: f64 = format!("{r:.6}").parse().unwrap_or(r);
    if r == 0.0 {
        0.0
    } else {
        r
    }
}

/// A point of one family's parameter space: a direction (discrete) and continuous coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Point {
    /// The family.
    pub family: Family,
    /// Conic, curved, tilted: outward or inward (belt: unused).
    pub direction: Direction,
    /// Conic: (angle °, cx mm, cy mm); belt: (angle °, azimuth of `toward` °, −);
    /// curved: (strength, offset mm, −); tilted: (layer angle atan s °, offset mm, −).
    pub x: [f64; 3],
    /// Whether the warp gets the flat base blend.
    pub base: bool,
}

/// The resolution of each coordinate of a family (what [`Point::params`] rounds to).
pub fn resolution(family: Family) -> [f64; 3] {
    match family {
        Family::Conic => [0.1, 0.1, 0.1],
        Family::Belt => [0.1, 1.0, 1.0],
        Family::Curved => [0.001, 0.1, 1.0],
        Family::Tilted => [0.1, 0.1, 1.0],
        // no coordinates: the fit moves the grid's coefficients ([`super::fit`])
        Family::Field => [1.0, 1.0, 1.0],
    }
}

impl Point {
    /// The point with its coordinates rounded to their resolution.
    pub fn rounded(mut self) -> Point {
        let r = resolution(self.family);
        for (x, step) in self.x.iter_mut().zip(r) {
            *x = round_to(*x, step);
        }
        if self.family == Family::Belt {
            self.x[1] = self.x[1].rem_euclid(360.0);
            self.x[2] = 0.0;
        }
        if matches!(self.family, Family::Curved | Family::Tilted) {
            self.x[2] = 0.0;
        }
        self
    }

    /// The warp of this point for a model whose model-frame box is `bbox` (`None` when the
    /// coordinates leave the family's range: an angle outside (0°, 90°), a negative strength,
    /// or a base blend the model is too low for; and for the field, which has no coordinates).
    pub fn params(&self, bbox: &Aabb) -> Option<WarpParams> {
        let p = self.rounded();
        let spec = match p.family {
            Family::Conic => {
                if !(p.x[0] > 0.0 && p.x[0] < 90.0) {
                    return None;
                }
                WarpSpec::Conic {
                    angle: p.x[0],
                    direction: p.direction,
                    center: [p.x[1], p.x[2]],
                }
            }
            Family::Belt => {
                if !(p.x[0] > 0.0 && p.x[0] < 90.0) {
                    return None;
                }
                let a = num::rad(p.x[1]);
                WarpSpec::Belt {
                    angle: p.x[0],
                    toward: [round_to(num::cos(a), 1e-4), round_to(num::sin(a), 1e-4)],
                }
            }
            Family::Curved => {
                if p.x[0].is_nan() || p.x[0] <= 0.0 {
                    return None;
                }
                WarpSpec::Curved {
                    strength: p.x[0],
                    direction: p.direction,
                    offset: p.x[1],
                    width: 0.0,
                }
            }
            Family::Tilted => {
                if !(p.x[0] > 0.0 && p.x[0] < 90.0) {
                    return None;
                }
                WarpSpec::Tilted {
                    strength: round_to(num::tan(num::rad(p.x[0])), 1e-4),
                    direction: p.direction,
                    offset: p.x[1],
                }
            }
            Family::Field => return None,
        };
        let base = if p.base {
            Some(base_for(&spec, bbox)?)
        } else {
            None
        };
        Some(WarpParams { spec, base })
    }
}

/// The base blend [0, z1] the search gives `spec` on a model with box `bbox`: z1 the larger
/// of [`BASE_MIN_SPAN_MM`] and [`BASE_SPAN_FACTOR`]·1.5·max(−g)/(1 − margin) over the box
/// (∂z'/∂z = 1 + w′·g > 0 with w′ ≤ 1.5/z1), rounded up to 0.1 mm; `None` when z1 would reach
/// half the model's height (no room to blend).
pub fn base_for(spec: &WarpSpec, bbox: &Aabb) -> Option<[f64; 2]> {
    let mut s = spec.clone();
    s.resolve(bbox);
    let height = s.height()?;
    let (min_g, _) = height.min_over(bbox);
    let need = BASE_SPAN_FACTOR * 1.5 * (-min_g).max(0.0) / (1.0 - MONOTONIC_MARGIN);
    let z1 = (need.max(BASE_MIN_SPAN_MM) * 10.0).ceil() / 10.0;
    (z1 < 0.5 * bbox.size().z).then_some([0.0, z1])
}

/// The flags `warpslice warp` takes for `params` (one string).
pub fn flags(params: &WarpParams) -> String {
    let f = num::fmt_shortest;
    let mut s = format!("--warp {}", params.spec.name());
    match &params.spec {
        WarpSpec::Conic {
            angle,
            direction,
            center,
        } => s.push_str(&format!(
            " --angle {} --direction {} --center {},{}",
            f(*angle),
            direction_name(*direction),
            f(center[0]),
            f(center[1])
        )),
        WarpSpec::Belt { angle, toward } => s.push_str(&format!(
            " --angle {} --toward {},{}",
            f(*angle),
            f(toward[0]),
            f(toward[1])
        )),
        WarpSpec::Curved {
            strength,
            direction,
            offset,
            ..
        }
        | WarpSpec::Tilted {
            strength,
            direction,
            offset,
        } => s.push_str(&format!(
            " --strength {} --direction {} --offset {}",
            f(*strength),
            direction_name(*direction),
            f(*offset)
        )),
        // the grid's text has no spaces; an expression is quoted as a shell takes it
        WarpSpec::Field { expr, grid, over } => {
            match grid {
                Some(text) => s.push_str(&format!(" --grid {text}")),
                None => s.push_str(&format!(" --expr '{}'", expr.replace('\'', r"'\''"))),
            }
            if let Some(text) = over {
                s.push_str(&format!(" --over {text}"));
            }
        }
        _ => {}
    }
    if let Some([z0, z1]) = params.base {
        s.push_str(&format!(" --base {},{}", f(z0), f(z1)));
    }
    s
}

fn direction_name(d: Direction) -> &'static str {
    match d {
        Direction::Outward => "outward",
        Direction::Inward => "inward",
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    #[test]
    fn rounded_points_write_the_flags_of_the_warp_they_measure() {
        let bbox = Aabb {
            min: DVec3::new(-10.0, -10.0, 0.0),
            max: DVec3::new(10.0, 10.0, 20.0),
        };
        let p = Point {
            family: Family::Conic,
            direction: Direction::Inward,
            x: [29.96, -2.5004, 0.04],
            base: false,
        };
        let w = p.params(&bbox).unwrap();
        assert_eq!(
            flags(&w),
            "--warp conic --angle 30 --direction inward --center -2.5,0"
        );
        let b = Point {
            family: Family::Belt,
            direction: Direction::Outward,
            x: [20.0, 90.0, 0.0],
            base: true,
        };
        let w = b.params(&bbox).unwrap();
        // g = 10·tan 20° = 3.64 at y = −10: z1 = 1.1·1.5·3.64/0.99 = 6.07 → 6.1
        assert_eq!(
            flags(&w),
            "--warp belt --angle 20 --toward 0,1 --base 0,6.1"
        );
        assert!(Point {
            x: [90.0, 0.0, 0.0],
            ..b
        }
        .params(&bbox)
        .is_none());
    }
}
