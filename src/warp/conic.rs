//! Conic layers, seed 002 (Slicer4RTN):
//!
//! T_z = z + c·r·tan α,  r = |(x, y) − (cx, cy)|
//!
//! α = cone angle (0 < α < 90°), c = +1 outward / −1 inward. Outward: the layer surfaces
//! z = k·h − r·tan α fall away from the axis and the tool tilts outward by α, so outward
//! overhangs print (Slicer4RTN's "outside" mode, whose model mapping is z + d). Inward: the
//! surfaces rise away from the axis and the tool tilts inward by α.
//!
//! **At the apex** (r = 0) the gradient is undefined; the apex gets the mean of all adjacent
//! normals, the vertical axis (∇g := 0).

use crate::schema::{Param, ParamDefault, ParamType, WarpInfo};
use glam::DVec2;

use super::{Direction, Height};

/// g(x, y) = c·r·tan α.
#[derive(Clone, Copy, Debug)]
pub struct Conic {
    k: f64,
    cx: f64,
    cy: f64,
}

impl Conic {
    /// g from the cone angle `angle_deg` α (degrees), `direction` c and the axis' `center`, mm.
    pub fn new(angle_deg: f64, direction: Direction, center: [f64; 2]) -> Conic {
        Conic {
            k: direction.sign() * crate::num::tan(crate::num::rad(angle_deg)),
            cx: center[0],
            cy: center[1],
        }
    }
}

impl Height for Conic {
    fn into_shear(self: Box<Self>, blend: Option<super::BaseBlend>) -> Box<dyn super::Warp> {
        Box::new(super::Shear::new(self, blend))
    }

    fn g(&self, x: f64, y: f64) -> f64 {
        let (dx, dy) = (x - self.cx, y - self.cy);
        self.k * (dx * dx + dy * dy).sqrt()
    }
    fn grad(&self, x: f64, y: f64) -> DVec2 {
        let (dx, dy) = (x - self.cx, y - self.cy);
        let r = (dx * dx + dy * dy).sqrt();
        if r > 0.0 {
            DVec2::new(self.k * dx / r, self.k * dy / r)
        } else {
            DVec2::ZERO
        }
    }
}

/// What the conic warp says of itself ([`crate::describe`]).
pub const INFO: WarpInfo = WarpInfo {
    name: "conic",
    title: "Conic (Slicer4RTN)",
    help: "cone layers about a vertical axis: overhangs all round (outward) or a funnel (inward)",
    formula: "T_z = z + c·r·tan α, r = |(x, y) − centre|",
    seed: "002 (Slicer4RTN)",
    base: true,
    params: &[
        super::ANGLE,
        super::DIRECTION,
        Param::number("center", "--center", "Centre")
            .of(ParamType::Pair)
            .unit("mm")
            .default(ParamDefault::Pair([0.0, 0.0]))
            .help("the cone's axis cx,cy in the model frame (0,0 = the footprint's centre)"),
    ],
};
