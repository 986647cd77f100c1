//! The top of a bead across its width: the layer's surface, not the tool's face.
//!
//! ## The model
//! A bead printed from tip `p₀` to `p₁` (direction `d`, horizontal part `d_xy`) has its top
//! through the tip's path; across the bead, along the horizontal unit `h = ẑ × d_xy / |d_xy|`
//! (to the left of the path seen from above), it rises with the **cross slope** `σ` (mm of z
//! per mm along h). The cell at horizontal offset `λ = (c − on)·h` from the path (clamped to
//! `±w/2`) gets the height `z = on_z + λ·σ` ([`super::material::Material::deposit`]).
//!
//! Two slopes are candidates:
//! - the **tool face's**, `σ_tool = u_z / (u_xy·h)` with `u = n × d` (n the tool axis): the
//!   flat face pressing the bead. Right for a head that follows the layer's normal (the face
//!   is the layer), and flat (0) for a vertical nozzle.
//! - the **layer's**, `σ_layer`: the surface the bead is laid on, read from the material
//!   already printed beside the bead at `±w·h` from the middle of the piece
//!   ([`layer_slope`]): a side's surface is the top of a bead of the current layer there, or
//!   a layer height above a bead of an older layer; both sides known give
//!   `σ = (z₊ − z₋)/(2w)`, one side `(z_± − p_z)/(±w)`, none nothing.
//!
//! The bead's top is the **smaller of the two in magnitude when they agree in sign, and flat
//! when they do not** (the median of 0, σ_tool and σ_layer; σ_layer unknown counts as 0):
//! - a face steeper than the layer (the RTN's fixed 45° nozzle over a flat layer: σ_tool = ±1,
//!   σ_layer = 0) does not lift one side of the bead 0.225·sin 45° = 0.16 mm above the tip
//!   (issue 10, note 7: 16 false RTN/RotBot findings of 0.05–0.1 mm): the bead lies on the
//!   layer;
//! - a layer steeper than the face (a vertical nozzle on a 30° cone) keeps the flat top the
//!   face irons, as [`super::contact`] assumes (`(ρ + w/2)·tan β` beside the tip);
//! - where they agree (a 5-axis head on the layer's normal), both are the layer's slope.
//!
//! `|σ| ≤ |σ_tool|`: against the face-only model of the first version, a bead's rising edge is
//! lower by at most `(w/2)·(|σ_tool| − |σ|)` (0.16 mm for the RTN on a flat layer) and its
//! falling edge higher by as much; the centre line (the tip's path) is unchanged.

use glam::{DVec2, DVec3};

/// Below this horizontal length, mm, a piece is taken as vertical: no across direction (its
/// bead marks the cells along its centre).
pub const VERTICAL_PIECE_MM: f64 = 1e-9;

/// The horizontal unit across a piece of direction `d`: `ẑ × d_xy / |d_xy|` (None: a
/// vertical piece).
pub fn across(d: DVec3) -> Option<DVec2> {
    let dxy = d.truncate();
    let l = dxy.length();
    (l > VERTICAL_PIECE_MM).then(|| DVec2::new(-dxy.y, dxy.x) / l)
}

/// The tool face's cross slope along `h` (see the module documentation): `u_z / (u_xy·h)`,
/// `u = n × d`; None when the face is vertical across the bead (`u_xy·h` ≈ 0) or the tool
/// axis is along the move.
pub fn tool_slope(n: DVec3, d: DVec3, h: DVec2) -> Option<f64> {
    let u = n.cross(d);
    let run = u.truncate().dot(h);
    (run.abs() > 1e-9 * u.length().max(1e-300)).then(|| u.z / run)
}

/// The layer's surface on one side of a bead, as the material there tells it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Side {
    /// Nothing printed there (or nothing that tells).
    Unknown,
    /// The top of a bead of the current layer: the surface itself, mm.
    Current(f64),
    /// The top of a bead of an older layer: the surface is a layer height above it, mm.
    Older(f64),
}

impl Side {
    /// The layer's surface height on this side, mm.
    fn surface(self, layer_height: f64) -> Option<f64> {
        match self {
            Side::Unknown => None,
            Side::Current(z) => Some(z),
            Side::Older(z) => Some(z + layer_height),
        }
    }
}

/// The layer's cross slope at a tip of height `z` from the sides at `+w·h` (`plus`) and `−w·h`
/// (`minus`), layer height `layer_height` (see the module documentation).
pub fn layer_slope(z: f64, plus: Side, minus: Side, w: f64, layer_height: f64) -> Option<f64> {
    match (plus.surface(layer_height), minus.surface(layer_height)) {
        (Some(a), Some(b)) => Some((a - b) / (2.0 * w)),
        (Some(a), None) => Some((a - z) / w),
        (None, Some(b)) => Some((z - b) / w),
        (None, None) => None,
    }
}

/// The bead's cross slope: the median of 0, the tool face's and the layer's slope (unknown
/// ones count as 0; see the module documentation).
pub fn cross_slope(tool: Option<f64>, layer: Option<f64>) -> f64 {
    let (a, b) = (tool.unwrap_or(0.0), layer.unwrap_or(0.0));
    if a * b <= 0.0 {
        0.0
    } else if a > 0.0 {
        a.min(b)
    } else {
        a.max(b)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_45_degree_face_over_a_flat_layer_lays_a_flat_bead() {
        // the RTN nozzle leaning to −Y, printing along +X: n × d rises 45° towards +Y
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let (n, d) = (DVec3::new(0.0, -s, s), DVec3::X);
        let h = across(d).unwrap();
        assert_eq!(h, DVec2::new(0.0, 1.0));
        let tool = tool_slope(n, d, h).unwrap();
        assert!((tool.abs() - 1.0).abs() < 1e-12, "{tool}");
        // the older layer 0.2 mm under the tip on both sides: flat
        let layer = layer_slope(1.0, Side::Older(0.8), Side::Older(0.8), 0.45, 0.2);
        assert_eq!(layer, Some(0.0));
        assert_eq!(cross_slope(Some(tool), layer), 0.0);
    }

    #[test]
    fn a_face_flatter_than_the_layer_keeps_its_own_slope_and_opposite_signs_give_flat() {
        let t30 = 30f64.to_radians().tan();
        // a 5-axis head tilted 20° on a 30° layer: 20°
        let t20 = 20f64.to_radians().tan();
        assert!((cross_slope(Some(t20), Some(t30)) - t20).abs() < 1e-15);
        assert!((cross_slope(Some(-t20), Some(-t30)) + t20).abs() < 1e-15);
        // the layer flatter than the face: the layer's
        assert!((cross_slope(Some(t30), Some(t20)) - t20).abs() < 1e-15);
        assert_eq!(cross_slope(Some(t30), Some(-t20)), 0.0);
        assert_eq!(cross_slope(Some(t30), None), 0.0);
        // one side known: the slope from the tip to it
        let one = layer_slope(
            1.0,
            Side::Current(1.0 + 0.45 * t30),
            Side::Unknown,
            0.45,
            0.2,
        );
        assert!((one.unwrap() - t30).abs() < 1e-12);
        let other = layer_slope(1.0, Side::Unknown, Side::Older(0.8 - 0.45 * t30), 0.45, 0.2);
        assert!((other.unwrap() - t30).abs() < 1e-12);
    }
}
