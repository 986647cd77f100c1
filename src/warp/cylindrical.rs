//! Cylindrical layers (seed 002, "printed on a horizontal rotating rod, like a lathe"): layer k
//! is the cylinder of radius R + k·h about a horizontal axis parallel to X, for printing on a
//! rotating mandrel of radius R (pair it with the `lathe-a` machine).
//!
//! With the axis through (0, a_y, a_z) along +X and, for a model point p,
//! `d = (p_y − a_y, p_z − a_z)`, `ρ = |d|`, `θ = atan2(d_y, d_z)` (angle from +Z, radians):
//!
//! ```text
//! T(x, y, z) = (x,  R·θ,  ρ − R)            (mm; y' is the arc length on the mandrel surface)
//! T⁻¹(x', y', z') = (x,  a_y + (z' + R) sin(y'/R),  a_z + (z' + R) cos(y'/R))
//! J = [1 0 0; 0 R d_z/ρ² −R d_y/ρ²; 0 d_y/ρ d_z/ρ],   det J = R / ρ
//! ```
//!
//! The tool axis ∇T_z/|∇T_z| = (0, d_y, d_z)/ρ is radial. Not volume preserving: the core
//! scales E by 1/det J = ρ/R. Domain: ρ > 0 (the axis itself is excluded) and |θ| < π (the
//! half-plane below the axis, θ = ±π, is the seam of the unrolled surface). No `--base` blend.

use crate::schema::{Param, ParamType, WarpInfo};
use glam::{DMat3, DVec3};

use super::Warp;
use crate::num;

/// The cylindrical warp.
#[derive(Clone, Copy, Debug)]
pub struct Cylindrical {
    radius: f64,
    ay: f64,
    az: f64,
}

impl Cylindrical {
    /// Mandrel radius R (mm, > 0) and the axis position (y, z) in the model frame (mm).
    pub fn new(radius: f64, axis: [f64; 2]) -> Cylindrical {
        Cylindrical {
            radius,
            ay: axis[0],
            az: axis[1],
        }
    }
}

impl Warp for Cylindrical {
    fn forward(&self, p: DVec3) -> DVec3 {
        let (dy, dz) = (p.y - self.ay, p.z - self.az);
        let rho = (dy * dy + dz * dz).sqrt();
        DVec3::new(p.x, self.radius * num::atan2(dy, dz), rho - self.radius)
    }
    fn inverse(&self, q: DVec3) -> DVec3 {
        let rho = q.z + self.radius;
        let t = q.y / self.radius;
        DVec3::new(
            q.x,
            self.ay + rho * num::sin(t),
            self.az + rho * num::cos(t),
        )
    }
    fn jacobian(&self, p: DVec3) -> DMat3 {
        let (dy, dz) = (p.y - self.ay, p.z - self.az);
        let r2 = dy * dy + dz * dz;
        let rho = r2.sqrt();
        if rho <= 0.0 {
            return DMat3::IDENTITY;
        }
        let r = self.radius;
        DMat3::from_cols(
            DVec3::X,
            DVec3::new(0.0, r * dz / r2, dy / rho),
            DVec3::new(0.0, -r * dy / r2, dz / rho),
        )
    }
    fn jacobian_det(&self, p: DVec3) -> f64 {
        let (dy, dz) = (p.y - self.ay, p.z - self.az);
        let rho = (dy * dy + dz * dz).sqrt();
        if rho > 0.0 {
            self.radius / rho
        } else {
            1.0
        }
    }
}

/// What the cylindrical warp says of itself ([`crate::describe`]).
pub const INFO: WarpInfo = WarpInfo {
    name: "cylindrical",
    title: "Cylindrical (mandrel)",
    help: "coaxial cylinders about an axis parallel to X, for printing on a rotating mandrel (lathe-a)",
    formula: "T_z = ρ − R, ρ = distance to the axis ∥ X through (y, z)",
    seed: "002 (mandrel)",
    base: false,
    params: &[
        super::RADIUS,
        Param::number("axis", "--axis-yz", "Axis y,z")
            .of(ParamType::Pair)
            .unit("mm")
            .optional()
            .help("the mandrel axis (parallel to X) at y,z in the model frame; empty: 0,−radius (just under the part)"),
    ],
};

/// The axis when none is given: just under the part, `(0, −R)`.
pub fn default_axis(radius: f64) -> [f64; 2] {
    [0.0, -radius]
}
