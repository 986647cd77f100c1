//! Tilted planar slices (belt printers; Slicer4RTN `--axis=3`), seed 002:
//!
//! T_z = z + (d·(x, y))·tan α
//!
//! d = the unit vector `toward` (default (0, 1)), α = slice angle. The layer planes
//! z = k·h − (d·(x, y))·tan α fall toward d, and the tool axis ∇T_z/|∇T_z| = (d·sin α, cos α)
//! tilts toward d by α.

use crate::schema::{Param, ParamDefault, ParamType, WarpInfo};
use glam::DVec2;

use super::Height;

/// g(x, y) = (d·(x, y))·tan α.
#[derive(Clone, Copy, Debug)]
pub struct Belt {
    k: DVec2,
}

impl Belt {
    /// g from the slice angle `angle_deg` α (degrees) and `toward` d (normalised here).
    pub fn new(angle_deg: f64, toward: [f64; 2]) -> Belt {
        let d = DVec2::new(toward[0], toward[1]).normalize_or_zero();
        Belt {
            k: d * crate::num::tan(crate::num::rad(angle_deg)),
        }
    }
}

impl Height for Belt {
    fn into_shear(self: Box<Self>, blend: Option<super::BaseBlend>) -> Box<dyn super::Warp> {
        Box::new(super::Shear::new(self, blend))
    }

    fn g(&self, x: f64, y: f64) -> f64 {
        self.k.x * x + self.k.y * y
    }
    fn grad(&self, _x: f64, _y: f64) -> DVec2 {
        self.k
    }
}

/// What the belt warp says of itself ([`crate::describe`]).
pub const INFO: WarpInfo = WarpInfo {
    name: "belt",
    title: "Belt (tilted planes)",
    help: "parallel planes falling toward a direction (belt printers, Slicer4RTN --axis=3)",
    formula: "T_z = z + (d·(x, y))·tan α",
    seed: "002 (--axis=3)",
    base: true,
    params: &[
        super::ANGLE,
        Param::number("toward", "--toward", "Toward")
            .of(ParamType::Pair)
            .default(ParamDefault::Pair([0.0, 1.0]))
            .help("the direction dx,dy the layers fall toward (any length but zero)"),
    ],
};
