//! A deterministic stream of random numbers for the unit tests' generated cases, without a
//! dependency: Knuth's MMIX 64-bit linear congruential generator, its top 53 bits read as a
//! number in [0, 1). The same seed gives the same cases on every platform (native and wasm).

use glam::DVec3;

/// The generator; the field is its state (the seed).
pub(crate) struct Lcg(pub u64);

impl Lcg {
    /// The next number in [0, 1).
    pub fn unit(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }

    /// The next number in [a, b).
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.unit()
    }

    /// A point of the box `[lo, hi]`, its coordinates drawn in x, y, z order.
    pub fn within(&mut self, lo: DVec3, hi: DVec3) -> DVec3 {
        let x = self.range(lo.x, hi.x);
        let y = self.range(lo.y, hi.y);
        DVec3::new(x, y, self.range(lo.z, hi.z))
    }
}
