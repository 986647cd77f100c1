//! Tilted planar slices (belt printers; Slicer4RTN `--axis=3`), seed 002:
//!
//! T_z = z + (d·(x, y))·tan α
//!
//! d = the unit vector `toward` (default (0, 1)), α = slice angle. The layer planes
//! z = k·h − (d·(x, y))·tan α fall toward d, and the tool axis ∇T_z/|∇T_z| = (d·sin α, cos α)
//! tilts toward d by α.

use glam::DVec2;

use super::Height;

/// g(x, y) = (d·(x, y))·tan α.
#[derive(Clone, Copy, Debug)]
pub struct Belt {
    k: DVec2,
}

impl Belt {
    pub fn new(angle_deg: f64, toward: [f64; 2]) -> Belt {
        let d = DVec2::new(toward[0], toward[1]).normalize_or_zero();
        Belt {
            k: d * crate::num::tan(crate::num::rad(angle_deg)),
        }
    }
}

impl Height for Belt {
    fn g(&self, x: f64, y: f64) -> f64 {
        self.k.x * x + self.k.y * y
    }
    fn grad(&self, _x: f64, _y: f64) -> DVec2 {
        self.k
    }
}
