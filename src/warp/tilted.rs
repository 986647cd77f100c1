//! Tilted (angled straight) layers with a crease, seed 000 §4.2.2 Eq. 2:
//!
//! T_z = z + s·c·|x + a|
//!
//! s = strength (= tan of the layer tilt), c = +1 outward / −1 inward, a = offset (mm). The
//! layers are two planes meeting at the crease x = −a, tilted by ±atan(s) in XZ.
//!
//! **On the crease** the layer normal jumps from (−s·c, 0, 1)/√(1+s²) to (s·c, 0, 1)/√(1+s²).
//! A point exactly on it (|x + a| ≤ [`CREASE_HALF_WIDTH`]) gets the mean of the two normals,
//! the vertical axis (0, 0, 1): ∂|u|/∂u is taken as 0 there.

use crate::schema::WarpInfo;
use glam::DVec2;

use super::{Direction, Height};

/// Points closer than this to the crease (mm) count as on it and get the vertical tool axis.
pub const CREASE_HALF_WIDTH: f64 = 1e-12;

/// g(x, y) = s·c·|x + a|.
#[derive(Clone, Copy, Debug)]
pub struct Tilted {
    k: f64,
    a: f64,
}

impl Tilted {
    /// g from `strength` s (tan of the tilt), `direction` c and `offset` a (mm): crease at x = −a.
    pub fn new(strength: f64, direction: Direction, offset: f64) -> Tilted {
        Tilted {
            k: strength * direction.sign(),
            a: offset,
        }
    }
}

impl Height for Tilted {
    fn into_shear(self: Box<Self>, blend: Option<super::BaseBlend>) -> Box<dyn super::Warp> {
        Box::new(super::Shear::new(self, blend))
    }

    fn g(&self, x: f64, _y: f64) -> f64 {
        self.k * (x + self.a).abs()
    }
    fn grad(&self, x: f64, _y: f64) -> DVec2 {
        let u = x + self.a;
        let s = if u > CREASE_HALF_WIDTH {
            1.0
        } else if u < -CREASE_HALF_WIDTH {
            -1.0
        } else {
            0.0
        };
        DVec2::new(self.k * s, 0.0)
    }
}

/// What the tilted warp says of itself ([`crate::describe`]).
pub const INFO: WarpInfo = WarpInfo {
    name: "tilted",
    title: "Tilted (roof layers)",
    help: "two planes meeting at a crease at x = −a (a roof or a valley); the tool tilts in XZ",
    formula: "T_z = z + s·c·|x+a|",
    seed: "000 Eq. 2",
    base: true,
    params: &[super::STRENGTH, super::DIRECTION, super::OFFSET],
};
