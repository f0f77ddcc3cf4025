//! The trace order of a low-discrepancy set: its points' indices, Owen-
//! scrambled.
//!
//! A camera sample pairs point `i` of its film set with point `i` of its
//! lens and time sets. Two independently randomised copies of one
//! low-discrepancy sequence taken in sequence order are not independent
//! when paired that way: point `i` of every `sobol` set has the same first
//! digit up to the set's scramble, so the film position's first half
//! decides the lens point's (and for `r2` the lens point is the film point
//! plus a constant). The pixel then integrates a different function, and
//! its error stops falling. pbrt-v4 meets this by permuting each
//! dimension's sample index; so does this.
//!
//! The permutation of a set of `N` points (`2^(m-1) < N ≤ 2^m`) is a
//! nested uniform (Owen) scramble of the index read as an `m`-digit binary
//! fraction: the flip of each digit depends on the digits above it and on
//! the set's seed. So the first `2^j` indices map onto one aligned block of
//! `2^j` indices, and every power-of-two prefix of the trace order is an
//! aligned block of the sequence: for `sobol`, `zsobol` and `pmj02bn`
//! still a `(0, j, 2)`-net, for `halton` and `r2` a run of
//! consecutive points. Indices that land at `N` or beyond are scrambled
//! again until they fall below it (cycle walking), which keeps the map a
//! permutation of `0..N`: the set is still its sequence's first `N` points.
//!
//! `pmj02` needs none: its sets already take the Sobol' sequence in an
//! order of their own, an Owen scramble of the whole 32-bit index.

use super::sobol::owen_scramble;
use super::Rng;

/// A permutation of the indices `0..count`.
#[derive(Clone, Copy, Debug)]
pub(super) struct TraceOrder {
    count: u32,
    /// `32 − m`: the index's `m` digits sit at the top of a fixed-point word.
    shift: u32,
    seed: u32,
}

impl TraceOrder {
    /// The order of a set of `count` points, drawn from its stream (one
    /// draw, none for a set of one: its order has no choice).
    pub(super) fn new(count: usize, rng: &mut Rng) -> TraceOrder {
        let count = u32::try_from(count).unwrap_or(u32::MAX);
        if count <= 1 {
            return TraceOrder {
                count,
                shift: 32,
                seed: 0,
            };
        }
        let digits = 32 - (count - 1).leading_zeros();
        TraceOrder {
            count,
            shift: 32 - digits,
            seed: rng.next_u32(),
        }
    }

    /// The sequence index of the set's `i`-th point in trace order.
    #[inline]
    pub(super) fn index(&self, i: u32) -> u32 {
        if self.shift == 32 {
            return i;
        }
        let mut j = i;
        loop {
            j = owen_scramble(j << self.shift, self.seed) >> self.shift;
            if j < self.count {
                return j;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn order(count: usize, seed: u64) -> Vec<u32> {
        let o = TraceOrder::new(count, &mut Rng::new(seed));
        (0..count as u32).map(|i| o.index(i)).collect()
    }

    #[test]
    fn it_is_a_permutation() {
        for count in [1, 2, 3, 5, 16, 17, 100, 255, 256, 1000] {
            for seed in 0..20 {
                let mut o = order(count, seed);
                o.sort_unstable();
                assert!(o.iter().copied().eq(0..count as u32), "{count} {seed}");
            }
        }
    }

    /// Every power-of-two prefix of a power-of-two set's order is one
    /// aligned block of indices.
    #[test]
    fn power_of_two_prefixes_are_aligned_blocks() {
        for seed in 0..50 {
            let o = order(256, seed);
            for j in 0..=8 {
                let size = 1u32 << j;
                let prefix = &o[..size as usize];
                let block = prefix[0] / size;
                assert!(prefix.iter().all(|&i| i / size == block), "{seed} {j}");
            }
        }
    }

    /// The orders of independent sets are independent: over many pairs of
    /// sets, the first index's lowest digit (which decides a `sobol`
    /// point's first coordinate's half) agrees about half the time, and
    /// each index is equally likely first.
    #[test]
    fn orders_are_random() {
        let sets = 4096;
        let mut first = [0u32; 16];
        let mut agree = 0;
        for s in 0..sets {
            let a = order(16, 2 * s);
            let b = order(16, 2 * s + 1);
            first[a[0] as usize] += 1;
            agree += (0..16).filter(|&i| a[i] & 1 == b[i] & 1).count();
        }
        let share = agree as f64 / (16 * sets) as f64;
        assert!((share - 0.5).abs() < 0.02, "{share}");
        let expected = sets as f64 / 16.0;
        let chi2: f64 = first
            .iter()
            .map(|&c| (c as f64 - expected).powi(2) / expected)
            .sum();
        // 15 degrees of freedom: 37.7 is the 0.999 quantile.
        assert!(chi2 < 37.7, "{chi2} {first:?}");
    }

    #[test]
    fn a_set_of_one_draws_nothing() {
        let mut rng = Rng::new(3);
        let before = rng.clone().next_u64();
        let o = TraceOrder::new(1, &mut rng);
        assert_eq!(o.index(0), 0);
        assert_eq!(rng.next_u64(), before);
    }
}
