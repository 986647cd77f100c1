//! The z-shear shared by every seed warp: T(x, y, z) = (x, y, z + w(z)·g(x, y)).
//!
//! - Without a base blend w ≡ 1: T⁻¹(x, y, z') = (x, y, z' − g(x, y)), det J = 1.
//! - With the [`BaseBlend`] w(z) (0 below z0, 1 above z1, smoothstep between):
//!   J = [[1, 0, 0], [0, 1, 0], [w·g_x, w·g_y, 1 + w′(z)·g]], det J = 1 + w′(z)·g, and the
//!   inverse solves z + w(z)·g = z' for z with a safeguarded Newton iteration (the root is
//!   bracketed by z' − g and z' because 0 ≤ w ≤ 1).

use glam::{DMat3, DVec2, DVec3};

use super::{BaseBlend, Warp};
use crate::mesh::Aabb;
use crate::tolerance::INVERSE_SOLVE_TOLERANCE;

/// The height function g(x, y) of a z-shear, model frame, mm.
pub trait Height: Send + Sync + std::fmt::Debug {
    /// g(x, y), mm.
    fn g(&self, x: f64, y: f64) -> f64;
    /// ∇g = (∂g/∂x, ∂g/∂y). Where g has a kink (crease, cone apex) this is the mean of the
    /// one-sided gradients, which makes the tool axis there the mean of the adjacent normals.
    fn grad(&self, x: f64, y: f64) -> DVec2;

    /// The shear warp of this height, as a [`Shear`] of its own type: the warp's inverse and
    /// tool axis then call g and ∇g directly, not through `dyn Height` (one indirect call
    /// fewer per inverse, and g inlines into it; indirect calls cost more in wasm than
    /// natively). Every implementation is `Box::new(Shear::new(self, blend))`.
    fn into_shear(self: Box<Self>, blend: Option<BaseBlend>) -> Box<dyn Warp>;

    /// The smallest g over an XY box (sampled on a grid that includes corners and centre; every
    /// seed height is convex or concave along lines, so its extremes lie on that grid or are
    /// approached to well within the monotonicity margin) and where it is.
    fn min_over(&self, bbox: &Aabb) -> (f64, [f64; 2]) {
        const N: usize = 64;
        let mut best = (f64::INFINITY, [0.0, 0.0]);
        for i in 0..=N {
            for j in 0..=N {
                let x = bbox.min.x + (bbox.max.x - bbox.min.x) * (i as f64 / N as f64);
                let y = bbox.min.y + (bbox.max.y - bbox.min.y) * (j as f64 / N as f64);
                let v = self.g(x, y);
                if v < best.0 {
                    best = (v, [x, y]);
                }
            }
        }
        best
    }
}

/// A z-shear warp with an optional flat base; `H` is the height's own type where it is known
/// ([`Height::into_shear`]), `dyn Height` otherwise.
#[derive(Debug)]
pub struct Shear<H: Height + ?Sized = dyn Height> {
    height: Box<H>,
    blend: Option<BaseBlend>,
}

/// Most Newton/bisection steps of the base-blend inverse (it converges in < 10 in practice;
/// bisection alone needs ~60 for 1e-12 mm from a 100 mm bracket).
const MAX_INVERSE_STEPS: usize = 200;

impl<H: Height + ?Sized> Shear<H> {
    /// T = (x, y, z + w(z)·g(x, y)) with height `height` and optional blend (w ≡ 1 without).
    pub fn new(height: Box<H>, blend: Option<BaseBlend>) -> Shear<H> {
        Shear { height, blend }
    }
    /// The height function g(x, y).
    pub fn height(&self) -> &H {
        self.height.as_ref()
    }
    /// The flat-base blend w(z), if any.
    pub fn blend(&self) -> Option<BaseBlend> {
        self.blend
    }
    /// The z-offset z' − z at a model point.
    pub fn offset(&self, p: DVec3) -> f64 {
        let w = self.blend.map_or(1.0, |b| b.w(p.z));
        w * self.height.g(p.x, p.y)
    }

    fn solve_z(&self, b: BaseBlend, g: f64, zp: f64) -> f64 {
        // f(z) = z + w(z)·g − z', increasing (validated when built); root in [lo, hi].
        let (mut lo, mut hi) = if g >= 0.0 { (zp - g, zp) } else { (zp, zp - g) };
        if g == 0.0 {
            return zp;
        }
        let mut z = zp - g * b.w(zp - g).max(b.w(zp));
        z = z.clamp(lo, hi);
        for _ in 0..MAX_INVERSE_STEPS {
            let f = z + b.w(z) * g - zp;
            if f.abs() <= INVERSE_SOLVE_TOLERANCE {
                return z;
            }
            if f > 0.0 {
                hi = z;
            } else {
                lo = z;
            }
            let df = 1.0 + b.dw(z) * g;
            let mut next = if df > 0.0 { z - f / df } else { f64::NAN };
            if !(next > lo && next < hi) {
                next = 0.5 * (lo + hi);
            }
            if (hi - lo) <= INVERSE_SOLVE_TOLERANCE * 0.5 {
                return 0.5 * (lo + hi);
            }
            z = next;
        }
        z
    }
}

impl<H: Height + ?Sized> Warp for Shear<H> {
    fn forward(&self, p: DVec3) -> DVec3 {
        DVec3::new(p.x, p.y, p.z + self.offset(p))
    }

    fn inverse(&self, q: DVec3) -> DVec3 {
        let g = self.height.g(q.x, q.y);
        let z = match self.blend {
            None => q.z - g,
            Some(b) => self.solve_z(b, g, q.z),
        };
        DVec3::new(q.x, q.y, z)
    }

    fn jacobian(&self, p: DVec3) -> DMat3 {
        let g = self.height.g(p.x, p.y);
        let d = self.height.grad(p.x, p.y);
        let (w, dw) = self.blend.map_or((1.0, 0.0), |b| (b.w(p.z), b.dw(p.z)));
        DMat3::from_cols(
            DVec3::new(1.0, 0.0, w * d.x),
            DVec3::new(0.0, 1.0, w * d.y),
            DVec3::new(0.0, 0.0, 1.0 + dw * g),
        )
    }

    fn tool_axis(&self, p: DVec3) -> DVec3 {
        let d = self.height.grad(p.x, p.y);
        let v = match self.blend {
            None => DVec3::new(d.x, d.y, 1.0),
            Some(b) => {
                let w = b.w(p.z);
                DVec3::new(w * d.x, w * d.y, 1.0 + b.dw(p.z) * self.height.g(p.x, p.y))
            }
        };
        v / v.length()
    }

    fn jacobian_det(&self, p: DVec3) -> f64 {
        match self.blend {
            None => 1.0,
            Some(b) => 1.0 + b.dw(p.z) * self.height.g(p.x, p.y),
        }
    }
}
