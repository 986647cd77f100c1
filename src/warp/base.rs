//! The flat-base blend (CurviSlicer's idea): z' = z + w(z)·g(x, y).
//!
//! w(z) = 0 for z ≤ z0, 1 for z ≥ z1, and the smoothstep 3t² − 2t³ (t = (z − z0)/(z1 − z0))
//! between, so the first layers stay flat and the warp fades in. w′ peaks at 1.5/(z1 − z0)
//! (t = ½), so ∂z'/∂z = 1 + w′·g > 0 over the model needs −g < (z1 − z0)/1.5 everywhere: e.g.
//! belt 15° with `--base 0.6,10` holds for |y| < 9.4/1.5/tan 15° ≈ 23.4 mm.

/// The blend weight w(z) between `z0` and `z1` (mm, model frame).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BaseBlend {
    /// Top of the flat part: w = 0 for z ≤ z0, mm (model frame).
    pub z0: f64,
    /// Where the warp is complete: w = 1 for z ≥ z1, mm (model frame; z1 > z0).
    pub z1: f64,
}

impl BaseBlend {
    /// The blend from `z0` to `z1` (mm, model frame; callers check 0 ≤ z0 < z1).
    pub fn new(z0: f64, z1: f64) -> BaseBlend {
        BaseBlend { z0, z1 }
    }
    /// w(z) ∈ [0, 1].
    pub fn w(&self, z: f64) -> f64 {
        let t = ((z - self.z0) / (self.z1 - self.z0)).clamp(0.0, 1.0);
        t * t * (3.0 - 2.0 * t)
    }
    /// w′(z), 1/mm.
    pub fn dw(&self, z: f64) -> f64 {
        let span = self.z1 - self.z0;
        let t = (z - self.z0) / span;
        if !(0.0..=1.0).contains(&t) {
            return 0.0;
        }
        6.0 * t * (1.0 - t) / span
    }
    /// max w′ = 1.5/(z1 − z0), 1/mm.
    pub fn max_slope(&self) -> f64 {
        1.5 / (self.z1 - self.z0)
    }
}
