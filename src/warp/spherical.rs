//! Spherical layers (seed 002, for the 5-axis head): layer k is the sphere of radius R + k·h
//! about a centre c, for printing outward from a sphere of radius R (pair it with `pax-5axis`).
//!
//! With `v = p − c`, `ρ = |v|`, `s = |(v_x, v_y)|`, polar angle `φ = atan2(s, v_z)` (from +Z,
//! radians) and the azimuthal-equidistant map of the sphere of radius R about its top:
//!
//! ```text
//! T(p) = (f v_x,  f v_y,  ρ − R),   f = R φ / s   (f → R/ρ on the +Z axis, s → 0)
//! T⁻¹(x', y', z') = c + (z' + R)·(sin φ cos λ, sin φ sin λ, cos φ),
//!                   φ = |(x', y')| / R,  λ = atan2(y', x')
//! ```
//!
//! Lengths in mm. The Jacobian is analytic (below); det J = R² φ / (ρ² sin φ) (→ R²/ρ² at the
//! top). The tool axis ∇T_z/|∇T_z| = v/ρ is radial. Not volume preserving: the core scales E by
//! 1/det J. Domain: ρ > 0 and φ < π (the centre and the downward axis are excluded). No
//! `--base` blend.

use crate::schema::{Param, ParamType, WarpInfo};
use glam::{DMat3, DVec3};

use super::Warp;
use crate::num;

/// Below this s/ρ the top-pole limit of the Jacobian is used.
pub const POLE_RATIO: f64 = 1e-9;

/// The spherical warp.
#[derive(Clone, Copy, Debug)]
pub struct Spherical {
    radius: f64,
    c: DVec3,
}

impl Spherical {
    /// Inner radius R (mm, > 0) and the centre (model frame, mm).
    pub fn new(radius: f64, center: [f64; 3]) -> Spherical {
        Spherical {
            radius,
            c: DVec3::from_array(center),
        }
    }
}

impl Warp for Spherical {
    fn forward(&self, p: DVec3) -> DVec3 {
        let v = p - self.c;
        let rho = v.length();
        let s = (v.x * v.x + v.y * v.y).sqrt();
        let f = if s > POLE_RATIO * rho {
            self.radius * num::atan2(s, v.z) / s
        } else {
            self.radius / rho
        };
        DVec3::new(f * v.x, f * v.y, rho - self.radius)
    }
    fn inverse(&self, q: DVec3) -> DVec3 {
        let rho = q.z + self.radius;
        let w = (q.x * q.x + q.y * q.y).sqrt();
        let phi = w / self.radius;
        let (cl, sl) = if w > 0.0 {
            (q.x / w, q.y / w)
        } else {
            (1.0, 0.0)
        };
        let sp = num::sin(phi);
        self.c + DVec3::new(sp * cl, sp * sl, num::cos(phi)) * rho
    }
    fn jacobian(&self, p: DVec3) -> DMat3 {
        let v = p - self.c;
        let rho2 = v.length_squared();
        let rho = rho2.sqrt();
        if rho <= 0.0 {
            return DMat3::IDENTITY;
        }
        let r = self.radius;
        let s = (v.x * v.x + v.y * v.y).sqrt();
        let drho = v / rho;
        if s <= POLE_RATIO * rho {
            // top pole: x' ≈ R v_x / v_z, y' ≈ R v_y / v_z
            let k = r / v.z;
            return DMat3::from_cols(
                DVec3::new(k, 0.0, drho.x),
                DVec3::new(0.0, k, drho.y),
                DVec3::new(0.0, 0.0, drho.z),
            );
        }
        let phi = num::atan2(s, v.z);
        // ∂φ/∂v = (v_z v_x / s, v_z v_y / s, −s) / ρ²;  ∂s/∂v = (v_x, v_y, 0) / s
        let dphi = DVec3::new(v.z * v.x / s, v.z * v.y / s, -s) / rho2;
        let ds = DVec3::new(v.x / s, v.y / s, 0.0);
        // f = R φ / s,  ∂f = R (∂φ s − φ ∂s) / s²
        let f = r * phi / s;
        let df = (dphi * s - ds * phi) * (r / (s * s));
        // x' = f v_x: ∂x'/∂v = v_x ∂f + f e_x; likewise y'
        let dx = df * v.x + DVec3::X * f;
        let dy = df * v.y + DVec3::Y * f;
        // columns ∂T/∂x, ∂T/∂y, ∂T/∂z
        DMat3::from_cols(
            DVec3::new(dx.x, dy.x, drho.x),
            DVec3::new(dx.y, dy.y, drho.y),
            DVec3::new(dx.z, dy.z, drho.z),
        )
    }
}

/// What the spherical warp says of itself ([`crate::describe`]).
pub const INFO: WarpInfo = WarpInfo {
    name: "spherical",
    title: "Spherical (5-axis)",
    help: "concentric spheres about a centre, for a 5-axis head",
    formula: "T_z = ρ − R, ρ = distance to the centre",
    seed: "002 (5-axis)",
    base: false,
    params: &[
        super::RADIUS,
        Param::number("center", "--sphere-center", "Centre x,y,z")
            .of(ParamType::Triple)
            .unit("mm")
            .optional()
            .help(
                "the spheres' centre in the model frame; empty: 0,0,−radius (just under the part)",
            ),
    ],
};

/// The centre when none is given: just under the part, `(0, 0, −R)`.
pub fn default_center(radius: f64) -> [f64; 3] {
    [0.0, 0.0, -radius]
}
