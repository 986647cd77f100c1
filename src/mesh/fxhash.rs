//! A small, fast, deterministic hasher for integer keys (vertex welding).
//!
//! Words are folded in FxHash style, `h = (rotl(h, 5) ⊕ w) · K`, and [`Hasher::finish`]
//! applies the murmur3 64-bit finaliser so that the low bits hashbrown uses for bucket
//! selection depend on every input bit (float bit patterns of round numbers such as 1.0 have
//! all-zero low mantissa bits; plain Fx would put them all in one bucket chain). Not
//! DoS-resistant, which is irrelevant for a local file.

use std::hash::{BuildHasherDefault, Hasher};

/// FxHash multiplier (from Firefox / rustc).
const K: u64 = 0x517c_c1b7_2722_0a95;

#[derive(Default, Clone, Copy)]
pub(crate) struct FxHasher {
    hash: u64,
}

impl FxHasher {
    #[inline]
    fn add(&mut self, w: u64) {
        self.hash = (self.hash.rotate_left(5) ^ w).wrapping_mul(K);
    }
}

impl Hasher for FxHasher {
    #[inline]
    fn write(&mut self, bytes: &[u8]) {
        let mut chunks = bytes.chunks_exact(8);
        for c in &mut chunks {
            let mut w = [0u8; 8];
            w.copy_from_slice(c);
            self.add(u64::from_le_bytes(w));
        }
        let rest = chunks.remainder();
        if !rest.is_empty() {
            let mut w = [0u8; 8];
            w[..rest.len()].copy_from_slice(rest);
            self.add(u64::from_le_bytes(w));
        }
    }
    #[inline]
    fn write_u32(&mut self, i: u32) {
        self.add(u64::from(i));
    }
    #[inline]
    fn write_u64(&mut self, i: u64) {
        self.add(i);
    }
    #[inline]
    fn write_usize(&mut self, i: usize) {
        self.add(i as u64);
    }
    #[inline]
    fn finish(&self) -> u64 {
        // murmur3 fmix64
        let mut h = self.hash;
        h ^= h >> 33;
        h = h.wrapping_mul(0xff51_afd7_ed55_8ccd);
        h ^= h >> 33;
        h = h.wrapping_mul(0xc4ce_b9fe_1a85_ec53);
        h ^ (h >> 33)
    }
}

/// `HashMap<K, V, FxBuild>` uses [`FxHasher`].
pub(crate) type FxBuild = BuildHasherDefault<FxHasher>;

#[cfg(test)]
mod tests {
    use super::*;
    use std::hash::BuildHasher;

    #[test]
    fn round_floats_spread_over_low_bits() {
        // 1.0, 2.0, ... have zero low mantissa bits; the finaliser must still spread them.
        let b = FxBuild::default();
        let mut low = std::collections::HashSet::new();
        for i in 0..1024u32 {
            low.insert(b.hash_one((i as f32).to_bits()) & 1023);
        }
        assert!(
            low.len() > 500,
            "only {} distinct low-bit buckets",
            low.len()
        );
    }
}
