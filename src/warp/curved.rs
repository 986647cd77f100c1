//! Curved layers, seed 000 §4.2.2 Eq. 1:
//!
//! T_z = z + s·c·(x + a)² / (w/2 + |a|)
//!
//! s = strength (dimensionless), c = +1 outward / −1 inward, a = offset (mm) shifting the
//! vertex of the parabola to x = −a, w = the model's width in x (mm). Layers are parabolic
//! cylinders along y; the tool axis tilts in the XZ plane only, by atan(2·s·c·(x+a)/(w/2+|a|)).

use crate::schema::WarpInfo;
use glam::DVec2;

use super::{Direction, Height};

/// g(x, y) = s·c·(x + a)² / (w/2 + |a|).
#[derive(Clone, Copy, Debug)]
pub struct Curved {
    k: f64,
    a: f64,
}

impl Curved {
    /// g from `strength` s, `direction` c, `offset` a (mm) and the model's `width` w in x (mm).
    pub fn new(strength: f64, direction: Direction, offset: f64, width: f64) -> Curved {
        Curved {
            k: strength * direction.sign() / (width / 2.0 + offset.abs()),
            a: offset,
        }
    }
}

impl Height for Curved {
    fn into_shear(self: Box<Self>, blend: Option<super::BaseBlend>) -> Box<dyn super::Warp> {
        Box::new(super::Shear::new(self, blend))
    }

    fn g(&self, x: f64, _y: f64) -> f64 {
        let u = x + self.a;
        self.k * u * u
    }
    fn grad(&self, x: f64, _y: f64) -> DVec2 {
        DVec2::new(2.0 * self.k * (x + self.a), 0.0)
    }
}

/// What the curved warp says of itself ([`crate::describe`]).
pub const INFO: WarpInfo = WarpInfo {
    name: "curved",
    title: "Curved (parabolic layers)",
    help:
        "parabolic cylinder layers along Y: domes (outward) or bowls (inward); the tool tilts in XZ",
    formula: "T_z = z + s·c·(x+a)² / (w/2 + |a|)",
    seed: "000 Eq. 1",
    base: true,
    params: &[super::STRENGTH, super::DIRECTION, super::OFFSET],
};
