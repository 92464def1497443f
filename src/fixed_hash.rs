//! A fast fixed hash for small integer keys, and maps that use it.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

/// Maps with a fixed hash, so that iteration order (and with it the
/// rounding of the sums over strata) is the same on every run.
pub(crate) type FixedMap<K, V> = HashMap<K, V, BuildHasherDefault<GridHasher>>;

/// A fast fixed hash for small integer keys (grid cells and lattice
/// points): each word is folded in by a rotation, an exclusive or and a
/// multiplication by 2⁶⁴/φ (Fibonacci hashing). SipHash, the standard
/// default, resists adversarial keys, which these are not, at several
/// times the cost: the penumbra refinement hashes a few keys per shadow
/// ray, and the shadow boundaries an edge per occluder corner.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct GridHasher(u64);

impl GridHasher {
    fn fold(&mut self, word: u64) {
        self.0 = (self.0.rotate_left(5) ^ word).wrapping_mul(0x9e37_79b9_7f4a_7c15);
    }
}

impl Hasher for GridHasher {
    fn write(&mut self, bytes: &[u8]) {
        for &byte in bytes {
            self.fold(u64::from(byte));
        }
    }

    fn write_u8(&mut self, word: u8) {
        self.fold(u64::from(word));
    }

    fn write_u32(&mut self, word: u32) {
        self.fold(u64::from(word));
    }

    fn write_u64(&mut self, word: u64) {
        self.fold(word);
    }

    fn finish(&self) -> u64 {
        // The product's high bits are its best mixed; hash tables index by the low ones.
        self.0.rotate_left(26)
    }
}
