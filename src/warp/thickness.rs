//! Layer thickness along the tool axis, and the vertical layer height that gives it
//! (`--layer-thickness`, issue 15 item 4; Slicer4RTN's `--layer-height`, seed 002).
//!
//! Layer k is the level set `T_z(p) = z₁ + k·h` of the model frame (the planar slicer cuts the
//! warped mesh every `h`). Along the tool axis `n = ∇T_z/|∇T_z|`, `T_z(p + s n) = T_z(p) +
//! s·|∇T_z(p)| + O(s²)`, so the next layer is
//!
//! ```text
//! thickness(p) = h / |∇T_z(p)|            (to first order in h)
//! ```
//!
//! above p. For the shear warps (`T_z = z + g(x, y)`: curved, tilted, conic, belt) `∂T_z/∂z = 1`,
//! so `n_z = 1/|∇T_z| = cos(tilt)` and `thickness = h·cos(tilt)`: a 30° cone sliced at
//! `h = 0.2 mm` prints layers 0.173 mm thick. Seed 002 (Slicer4RTN, "layer-height"): the user
//! gives the conic layer height and "the layer height for the core slicer is calculated" —
//! `h = t / cos α`. For the radial warps (cylindrical, spherical: `T_z = ρ − R`)
//! `|∇T_z| = 1`: the layers are `h` thick at every tilt.
//!
//! [`vertical_layer_height`] gives `h = t·|∇T_z|` at the model's point of largest tilt (there
//! the layers of a shear warp are thinnest; everywhere else they are thicker), or
//! `h = t / cos θ` at a tilt θ the user names (shear warps only; exact where `∂T_z/∂z = 1`, i.e.
//! above a `--base` blend). `h` is rounded to [`LAYER_HEIGHT_STEP_MM`]: CuraEngine keeps layer
//! heights in whole micrometres and every slicer writes `;Z:` with three decimals, so a finer
//! `h` would drift from the warp's layer surfaces by up to `k·0.0005 mm` at layer k.

use glam::DVec3;

use super::Warp;

/// The vertical layer height is rounded to this, mm (see the module documentation): the
/// thickness along the tool axis then differs from the one asked by at most half of it.
pub const LAYER_HEIGHT_STEP_MM: f64 = 1.0 / STEPS_PER_MM;
/// Steps of [`LAYER_HEIGHT_STEP_MM`] per mm (dividing by it gives the nearest f64 to a whole
/// number of micrometres, e.g. 0.283, not 0.28300000000000003).
const STEPS_PER_MM: f64 = 1000.0;

/// The vertical layer height for a wanted layer thickness.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VerticalLayerHeight {
    /// The layer height to slice the warped mesh with, mm (rounded to
    /// [`LAYER_HEIGHT_STEP_MM`]).
    pub layer_height: f64,
    /// The tilt from vertical where the thickness is the one asked, degrees.
    pub at_tilt_deg: f64,
    /// `|∇T_z|` there: the factor from thickness to vertical height.
    pub factor: f64,
}

/// Why no vertical layer height can be given.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ThicknessError {
    /// The thickness is not a positive number.
    Thickness(f64),
    /// The tilt is not within `[0°, 90°)`.
    Tilt(f64),
    /// A tilt was named for a radial warp, whose layers have the same thickness at every tilt.
    TiltOfRadialWarp,
}

/// The vertical layer height `h` that makes the layers `thickness` mm thick along the tool
/// axis: at the vertex of `vertices` (model frame) with the largest tilt, or at `at_tilt_deg`
/// (`shear`: the warp is a shear in z; a tilt is refused for the others). See the module
/// documentation for the formula.
pub fn vertical_layer_height(
    warp: &dyn Warp,
    shear: bool,
    vertices: &[DVec3],
    thickness: f64,
    at_tilt_deg: Option<f64>,
) -> Result<VerticalLayerHeight, ThicknessError> {
    if !(thickness.is_finite() && thickness > 0.0) {
        return Err(ThicknessError::Thickness(thickness));
    }
    let (factor, tilt) = match at_tilt_deg {
        Some(t) if !(t.is_finite() && (0.0..90.0).contains(&t)) => {
            return Err(ThicknessError::Tilt(t))
        }
        Some(_) if !shear => return Err(ThicknessError::TiltOfRadialWarp),
        Some(t) => (1.0 / t.to_radians().cos(), t),
        None => {
            // the vertex of largest tilt (smallest n_z); |∇T_z| there
            let mut best: Option<(f64, f64)> = None;
            for &p in vertices {
                let j = warp.jacobian(p);
                let g = DVec3::new(j.x_axis.z, j.y_axis.z, j.z_axis.z);
                let len = g.length();
                if !(len.is_finite() && len > 0.0) {
                    continue;
                }
                let nz = g.z / len;
                if best.is_none_or(|(b, _)| nz < b) {
                    best = Some((nz, len));
                }
            }
            let (nz, len) = best.unwrap_or((1.0, 1.0));
            (len, crate::num::deg(crate::num::acos(nz.clamp(-1.0, 1.0))))
        }
    };
    let h = (thickness * factor * STEPS_PER_MM).round() / STEPS_PER_MM;
    Ok(VerticalLayerHeight {
        layer_height: h.max(LAYER_HEIGHT_STEP_MM),
        at_tilt_deg: tilt,
        factor,
    })
}
