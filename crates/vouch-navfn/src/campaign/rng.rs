//! Deterministic pseudo-random numbers for the map generators.
//!
//! A generated suite must be byte-identical for a given seed across vouch versions and
//! platforms, forever. `rand`'s `StdRng` explicitly reserves the right to change its algorithm
//! between releases, so the algorithm is pinned by name: SplitMix64 (Steele, Lea, Flood 2014),
//! 64-bit state, integer-only arithmetic, from `rand_xoshiro` (the reference outputs are
//! tested below). The reductions to a range are written here: they are part of what a seed
//! means, and `rand`'s own range sampling may change between releases.

use rand_xoshiro::rand_core::{Rng, SeedableRng};

use crate::core::numeric::Fnv1a;

/// SplitMix64 generator. Same seed → same sequence on every platform.
#[derive(Clone, Debug)]
pub struct SplitMix64 {
    inner: rand_xoshiro::SplitMix64,
}

impl SplitMix64 {
    /// The generator whose state is `seed`.
    pub fn new(seed: u64) -> Self {
        SplitMix64 { inner: rand_xoshiro::SplitMix64::seed_from_u64(seed) }
    }

    /// A generator for one sub-stream (e.g. one map of one category), derived from the suite
    /// seed and a label, so that selecting fewer categories does not shift the other maps.
    pub fn derive(seed: u64, label: &str, index: u64) -> Self {
        // FNV-1a over the label bytes, mixed with the seed and the index.
        let mut fnv = Fnv1a::default();
        fnv.bytes(label.as_bytes());
        let h = fnv.0;
        let mut g =
            SplitMix64::new(seed ^ h.rotate_left(17) ^ index.wrapping_mul(0x9e37_79b9_7f4a_7c15));
        // Discard one output so that nearby seeds decorrelate immediately.
        g.next_u64();
        g
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.inner.next_u64()
    }

    /// SplitMix64's output function alone (the finaliser of MurmurHash3's mixer): `z` with
    /// every input bit spread over every output bit.
    pub fn mix(z: u64) -> u64 {
        // one step from state `z − γ` outputs the finaliser of `z`
        SplitMix64::new(z.wrapping_sub(0x9e37_79b9_7f4a_7c15)).next_u64()
    }

    /// Uniform integer in `lo..=hi` (requires `lo <= hi`). Uses the widening-multiply reduction;
    /// its bias (< 2^-32 for our ranges) is irrelevant for test generation.
    pub fn range(&mut self, lo: u32, hi: u32) -> u32 {
        debug_assert!(lo <= hi);
        let span = u64::from(hi - lo) + 1;
        let r = (u128::from(self.next_u64()) * u128::from(span)) >> 64;
        lo + r as u32
    }

    /// Uniform index in `0..n` (requires `n > 0`).
    pub fn index(&mut self, n: usize) -> usize {
        debug_assert!(n > 0);
        let r = (u128::from(self.next_u64()) * n as u128) >> 64;
        r as usize
    }

    /// True with probability `num/den`.
    pub fn chance(&mut self, num: u32, den: u32) -> bool {
        self.range(0, den - 1) < num
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splitmix_reference_values() {
        // Reference outputs of SplitMix64 for seed 0 (published with the algorithm).
        let mut g = SplitMix64::new(0);
        assert_eq!(g.next_u64(), 0xe220_a839_7b1d_cdaf);
        assert_eq!(g.next_u64(), 0x6e78_9e6a_a1b9_65f4);
    }

    #[test]
    fn range_stays_in_bounds() {
        let mut g = SplitMix64::new(7);
        for _ in 0..10_000 {
            let v = g.range(50, 253);
            assert!((50..=253).contains(&v));
        }
    }
}
