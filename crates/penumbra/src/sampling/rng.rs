//! A counter-based random generator.
//!
//! Every random value in a render is a pure function of (seed, pixel, sample
//! index, branch, draw number): a stream is identified by a 64-bit key derived by
//! hashing those identifiers ([`Rng::derive`]), and the n-th value of a stream is
//! a hash of (key, n). Nothing depends on which thread ran a tile or in which
//! order, so renders are reproducible bit for bit on any number of threads or
//! machines, and a single sample can be replayed.

/// Finaliser of SplitMix64: a bijective 64-bit mixer with
/// full avalanche, good enough to turn counters into independent-looking values.
#[inline]
pub const fn mix64(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

const GOLDEN: u64 = 0x9e37_79b9_7f4a_7c15;

/// A branch label of [`Rng::derive`], hashed (half of what deriving costs).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BranchKey(u64);

impl BranchKey {
    #[inline]
    pub const fn new(branch: u64) -> BranchKey {
        BranchKey(mix64(branch.wrapping_add(GOLDEN)))
    }
}

/// A stream of random numbers identified by a key; see the module docs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rng {
    key: u64,
    counter: u64,
}

impl Rng {
    /// The root stream of a seed.
    pub fn new(seed: u64) -> Self {
        Rng {
            key: mix64(seed ^ 0x5eed_0000_0000_0000),
            counter: 0,
        }
    }

    /// An independent sub-stream for `branch` (a pixel index, a sample index, a
    /// dimension, the k-th reflection ray...). Deriving does not advance `self`,
    /// so sub-streams do not shift each other.
    #[inline]
    pub fn derive(&self, branch: u64) -> Rng {
        self.derive_key(BranchKey::new(branch))
    }

    /// [`derive`](Self::derive) with the branch hashed beforehand: a loop
    /// that derives the same branches for every pixel (sample `i`'s path,
    /// light `j`'s shadow set) hashes them once instead of once a sample.
    #[inline]
    pub fn derive_key(&self, branch: BranchKey) -> Rng {
        Rng {
            key: mix64(self.key ^ branch.0),
            counter: 0,
        }
    }

    #[inline]
    pub fn next_u64(&mut self) -> u64 {
        self.counter = self.counter.wrapping_add(1);
        mix64(self.key.wrapping_add(self.counter.wrapping_mul(GOLDEN)))
    }

    #[inline]
    pub fn next_u32(&mut self) -> u32 {
        (self.next_u64() >> 32) as u32
    }

    /// Uniform in [0, 1): the top 24 bits, so every value is exactly
    /// representable and 1.0 is never returned.
    #[inline]
    pub fn next_f32(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 * (1.0 / (1u64 << 24) as f32)
    }

    /// Uniform in [a, b).
    #[inline]
    pub fn range(&mut self, a: f32, b: f32) -> f32 {
        a + (b - a) * self.next_f32()
    }

    /// Uniform integer in [0, n) without modulo bias (multiply-shift with rejection).
    #[inline]
    pub fn below(&mut self, n: u32) -> u32 {
        debug_assert!(n > 0);
        let mut m = u64::from(self.next_u32()) * u64::from(n);
        if (m as u32) < n {
            let threshold = n.wrapping_neg() % n;
            while (m as u32) < threshold {
                m = u64::from(self.next_u32()) * u64::from(n);
            }
        }
        (m >> 32) as u32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn streams_are_reproducible_and_distinct() {
        let a: Vec<u64> = (0..8)
            .map(|_| 0)
            .scan(Rng::new(7), |r, _| Some(r.next_u64()))
            .collect();
        let b: Vec<u64> = (0..8)
            .map(|_| 0)
            .scan(Rng::new(7), |r, _| Some(r.next_u64()))
            .collect();
        assert_eq!(a, b);
        let root = Rng::new(7);
        assert_ne!(root.derive(1).next_u64(), root.derive(2).next_u64());
        assert_ne!(Rng::new(7).next_u64(), Rng::new(8).next_u64());
    }

    #[test]
    fn floats_are_in_unit_interval_and_mean_half() {
        let mut r = Rng::new(1);
        let n = 200_000;
        let mut sum = 0.0f64;
        for _ in 0..n {
            let x = r.next_f32();
            assert!((0.0..1.0).contains(&x));
            sum += f64::from(x);
        }
        // Standard error of the mean is 1/sqrt(12 n) ≈ 6.5e-4; allow 5 sigma.
        assert!((sum / n as f64 - 0.5).abs() < 3.3e-3);
    }

    #[test]
    fn below_is_uniform() {
        let mut r = Rng::new(3);
        let mut counts = [0u32; 7];
        let n = 70_000;
        for _ in 0..n {
            counts[r.below(7) as usize] += 1;
        }
        // Chi-square with 6 degrees of freedom; the 99.9% quantile is 22.46.
        let expected = n as f64 / 7.0;
        let chi2: f64 = counts
            .iter()
            .map(|&c| (c as f64 - expected).powi(2) / expected)
            .sum();
        assert!(chi2 < 22.46, "chi2 = {chi2}");
    }
}
