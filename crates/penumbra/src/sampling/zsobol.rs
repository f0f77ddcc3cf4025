//! `zsobol`: Owen-scrambled Sobol' points whose sets are blocks of one
//! sequence laid over the frame in Morton order (Ahmed and Wonka, "Screen-
//! Space Blue-Noise Diffusion of Monte Carlo Sampling Error via Hierarchical
//! Ordering of Pixels", SIGGRAPH Asia 2020; the default sampler of pbrt-v4).
//!
//! # Construction
//!
//! Every other distribution scrambles each set apart, from the set's own
//! stream. `zsobol` instead reads the stream's [place](super::Place): a
//! *dimension* (a key of the kinds of branches that led to the set: the
//! film set, light `j`'s shadow set below a glossy set…, the same in every
//! pixel) and an *index* (the pixel's Morton code followed by the numbers of
//! the samples and rays above the set, each in `⌈log2 n⌉` bits). A set of
//! `N` points, `m = ⌈log2 N⌉`, is the Sobol' points of indices
//! `π(index) · 2^m + i`, `i < N`, scrambled with seeds of the dimension
//! alone:
//!
//! * `π` permutes the base-4 digits of the index, each by one of the 24
//!   permutations of four digits chosen by a hash of the dimension and the
//!   digits above it (and flips a lone lowest bit when the pixel's code
//!   starts at an odd bit, so that digits never straddle the pixel's code).
//!   Because a digit's permutation depends only on the digits above it, `π`
//!   maps every aligned block of indices onto an aligned block; and because
//!   it depends on the dimension, the order of a pixel's samples, and which
//!   block a pixel gets, differ between dimensions (the film set and the
//!   lens set of a sample are not paired by one index);
//! * the index's low 32 bits index the 32-bit Sobol' sequence; the bits
//!   above are hashed with the dimension into the two Owen-scramble seeds
//!   ([`sobol`](super::sobol)'s scramble), so sets far apart in the frame
//!   are scrambled independently.
//!
//! The 4 pixels of a 2x2 Morton quad thus hold together one aligned block
//! of `4 · 2^m` (times their samples') indices, a scrambled (0,2)-sequence
//! block, and so on up the quad tree: neighbouring pixels' points fill each
//! other's gaps, which spreads the error of a low sample count as blue noise
//! over the screen instead of white noise.
//!
//! # Guarantees
//!
//! For every place: every prefix of `2^k` points of a set is a
//! (0,k,2)-net in base 2 (an aligned Sobol' block, Owen-scrambled); the
//! sets of the 4 pixels of a Morton quad, with the same samples above them,
//! together form a (0,m+2,2)-net when each has `2^m` points; and all of a
//! pixel's sets of one dimension (over its samples and rays, each count a
//! power of two) together form a net. Each point is uniform over the square
//! in expectation.
//!
//! A set drawn from a stream with no pixel ([`Rng::new`](super::Rng::new),
//! as `penumbra samples` does) has index 0: the first block of the
//! sequence, scrambled by the seed.

use super::rng::{mix64, Place};
use super::sobol::{scrambled_first, unit, Sobol};
use crate::math::Vec2;

/// The 24 permutations of four digits, in lexicographic order.
const PERMUTATIONS: [[u8; 4]; 24] = {
    let mut table = [[0u8; 4]; 24];
    let mut n = 0;
    let mut a = 0;
    while a < 4 {
        let mut b = 0;
        while b < 4 {
            let mut c = 0;
            while c < 4 {
                let d = 6 - a - b - c;
                if a != b && a != c && b != c {
                    table[n] = [a as u8, b as u8, c as u8, d as u8];
                    n += 1;
                }
                c += 1;
            }
            b += 1;
        }
        a += 1;
    }
    table
};

/// The hash choosing the permutation of the digit at `shift` below the
/// digits `above`, in `dimension`.
#[inline]
fn node_hash(dimension: u64, above: u128, shift: u32) -> u64 {
    let high = (above >> 64) as u64;
    let above = above as u64 ^ if high == 0 { 0 } else { mix64(high) };
    // `above` fills the digits above `shift`: the multiplication spreads it
    // over the whole word before the one mixing step.
    let spread = above.wrapping_mul(0x9e37_79b9_7f4a_7c15) ^ u64::from(shift);
    mix64(dimension ^ spread)
}

/// `π(index)`: the base-4 digits of `index` permuted as the module docs say,
/// the digits aligned on bit `local_bits`. A digit with nothing but zeros
/// above it keeps its value (the identity is one of the permutations), so
/// the loop starts at the highest non-zero digit.
pub(super) fn permute(index: u128, local_bits: u32, dimension: u64) -> u128 {
    let lone = local_bits & 1;
    let mut out = 0;
    if index == 0 && lone == 0 {
        return 0;
    }
    let top = 128 - index.leading_zeros();
    // Digit shifts are lone + 2t; the highest one holding a set bit.
    let mut shift = if top > lone {
        lone + (top - 1 - lone) / 2 * 2
    } else {
        lone
    };
    loop {
        if shift < lone {
            break;
        }
        let above = index.checked_shr(shift + 2).unwrap_or(0);
        let digit = (index >> shift & 3) as usize;
        let mapped = if above == 0 {
            digit as u128
        } else {
            let p = (node_hash(dimension, above, shift) >> 40) % 24;
            u128::from(PERMUTATIONS[p as usize][digit])
        };
        out |= mapped << shift;
        if shift < 2 {
            break;
        }
        shift -= 2;
    }
    if lone == 1 {
        let flip = node_hash(dimension, index >> 1, 0) >> 63;
        out |= (index & 1) ^ u128::from(flip);
    }
    out
}

/// One `zsobol` set: its scramble and the first Sobol' index of its block.
#[derive(Clone, Copy, Debug)]
pub struct ZSobol {
    points: Sobol,
    base: u32,
    seed_x: u32,
}

impl ZSobol {
    /// The set of `count` points at `place`.
    pub fn new(place: Place, count: usize) -> ZSobol {
        let m = super::index_bits(count).min(32);
        let set = permute(place.index(), place.local_bits, place.dimension);
        // The block's first index is `set · 2^m`: its low 32 bits index the
        // sequence, the bits above choose the scramble.
        let (base, high) = (((set << m) as u32), set >> (32 - m));
        let high = high as u64 ^ mix64((high >> 64) as u64 ^ 0x2545_f491_4f6c_dd1d);
        let seeds = mix64(place.dimension ^ mix64(high));
        let (sx, sy) = (seeds as u32, (seeds >> 32) as u32);
        ZSobol {
            points: Sobol::from_seeds(sx, sy),
            base,
            seed_x: sx,
        }
    }

    /// Point `i` in 32-bit fixed point.
    #[inline]
    pub fn bits(&self, i: u32) -> [u32; 2] {
        self.points.bits(self.base | i)
    }

    /// Point `i` in `[0, 1)^2`.
    #[inline]
    pub fn point(&self, i: u32) -> Vec2 {
        self.points.point(self.base | i)
    }

    /// Value `i` of the one-dimensional set (the first coordinate).
    #[inline]
    pub fn value(&self, i: u32) -> f32 {
        unit(scrambled_first(self.base | i, self.seed_x))
    }
}

#[cfg(test)]
mod tests {
    use super::super::{checks, Rng, Sampler};
    use super::*;

    /// A place of the kind a render makes: some pixel, some samples above.
    fn place(seed: u64) -> Place {
        let mut r = Rng::new(seed ^ 0xabc);
        let pixel = Rng::new(seed).at_pixel(0, (r.next_u32() >> 20, r.next_u32() >> 20));
        pixel.child(r.below(7) as usize, 7).derive(5).place()
    }

    #[test]
    fn permute_is_a_bijection_on_aligned_blocks() {
        for local in [0, 1, 2, 3, 6] {
            for dimension in [1u64, 77, u64::MAX] {
                // Every aligned block of 2^b indices maps onto one.
                for b in [1u32, 2, 3, 4, 6] {
                    for start in [0u128, 64, 1 << 20, 5 << 30, 3 << 70] {
                        let block: Vec<u128> = (start..start + (1 << b))
                            .map(|i| permute(i, local, dimension))
                            .collect();
                        let mut sorted = block.clone();
                        sorted.sort_unstable();
                        sorted.dedup();
                        assert_eq!(sorted.len(), 1 << b, "not injective");
                        let first = sorted[0];
                        if b % 2 == local % 2 {
                            assert_eq!(first % (1 << b), 0, "block {start}+2^{b}");
                            assert_eq!(sorted[sorted.len() - 1], first + (1 << b) - 1);
                        }
                    }
                }
            }
        }
        // It does permute: not the identity for most dimensions.
        let moved = (0..64).filter(|&d| permute(0b1011_0110, 0, d) != 0b1011_0110);
        assert!(moved.count() > 40);
    }

    #[test]
    fn every_power_of_two_prefix_is_a_net() {
        checks::prefixes_are_nets("zsobol", |seed| {
            let s = ZSobol::new(place(seed), 1 << checks::MAX_M);
            move |i| s.bits(i)
        });
    }

    /// The film sets of the four pixels of a Morton quad form one net, and
    /// so do a pixel's shadow-like sets over all its samples.
    #[test]
    fn neighbours_and_samples_fill_one_net() {
        for seed in 0..checks::SEEDS {
            let sampler = Sampler::new(seed, 64, 4);
            let (qx, qy) = (2 * (seed as u32 % 8), 2 * (seed as u32 / 8));
            let mut union = Vec::new();
            for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                let pixel = sampler.pixel(qx + dx, qy + dy);
                let film = pixel.stream(super::super::Dimension::Film);
                let set = ZSobol::new(film.place(), 16);
                union.extend((0..16).map(|i| set.bits(i)));
            }
            assert_eq!(checks::first_non_net(64, |i| union[i as usize]), None);
            // Sample i's set of 8 rays below a kind of branch, i < 4.
            let pixel = sampler.pixel(qx, qy);
            let mut union = Vec::new();
            for i in 0..4 {
                let set = ZSobol::new(pixel.path(i).derive(9).place(), 8);
                union.extend((0..8).map(|k| set.bits(k)));
            }
            assert_eq!(checks::first_non_net(32, |i| union[i as usize]), None);
        }
    }

    #[test]
    fn dimensions_get_other_blocks_and_orders() {
        let pixel = Sampler::new(1, 64, 16).pixel(7, 5);
        let first = |d: u64| ZSobol::new(pixel.path(3).derive(d).place(), 1).bits(0);
        let firsts: std::collections::HashSet<[u32; 2]> = (0..32).map(first).collect();
        assert_eq!(firsts.len(), 32);
    }

    #[test]
    fn points_are_uniform_in_expectation() {
        checks::uniform_in_expectation("zsobol", |seed, count, out| {
            let s = ZSobol::new(place(seed), count as usize);
            out.extend((0..count).map(|i| s.point(i)));
        });
    }
}
