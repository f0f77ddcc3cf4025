//! `pmj02`: a progressive multi-jittered (0,2) sequence (Christensen,
//! Kensler and Kilpatrick, "Progressive Multi-Jittered Sample Sequences",
//! EGSR 2018).
//!
//! # Construction
//!
//! A pmj02 sequence is a (0,2)-sequence in base 2: every prefix of `2^m`
//! points is a (0,m,2)-net (one point in each elementary interval
//! `2^-j x 2^-k`, `j + k = m`), which makes it progressively stratified in
//! 2D and in both 1D projections at every power of two. Christensen et al.
//! build it by placing each new point at random in a stratum left free by
//! all earlier points. Helmer, Christensen and Kensler ("Stochastic
//! Generation of (t, s) Sample Sequences", EGSR 2021) generate pmj02
//! sequences far more cheaply as randomised (0,2)-sequences; in that spirit
//! we randomise the Sobol' (0,2)-sequence of [`sobol`](super::sobol) in two
//! ways, from three 32-bit seeds per set (rather than reproducing either
//! paper's algorithm):
//!
//! * the *order*: point `i` of the set is Sobol' point `owen(i)`, where
//!   `owen` is the same nested scramble applied to the bits of the index
//!   read from the least significant (Burley 2020's shuffling). Each index
//!   bit's flip depends only on the bits above it, so the first `2^m`
//!   indices map onto one aligned block of `2^m` Sobol' indices, which is a
//!   (0,m,2)-net as well: every prefix keeps the guarantee, but which block
//!   and in which order its points come is random per set;
//! * the *points*: each coordinate is Owen-scrambled as in `sobol`.
//!
//! For a power-of-two count a set is thus a scrambled Sobol' net, as for
//! `sobol` (a block's offset is a digital shift, which the scramble absorbs);
//! the two differ in the order of the points, which matters for other
//! counts and for sets stopped early. Christensen et al.'s best-candidate
//! blue-noise variant (`pmj02bn`) is not provided.
//!
//! # Guarantees
//!
//! For every seed: every prefix of `2^m` points is a (0,m,2)-net in base 2;
//! hence for `N = 2^m` each of the `N` columns and `N` rows of width `1/N`
//! holds exactly one point, and for `N = 4^k` each cell of the `2^k x 2^k`
//! grid does. Each point is uniform over the square in expectation.

use super::sobol::{owen_scramble, Sobol};
use super::Rng;
use crate::math::Vec2;

/// One randomised `pmj02` set: a scrambled Sobol' set and the seed of its
/// order.
#[derive(Clone, Copy, Debug)]
pub struct Pmj02 {
    points: Sobol,
    order: u32,
}

impl Pmj02 {
    /// A set drawn from its stream (two draws).
    pub fn new(rng: &mut Rng) -> Pmj02 {
        let points = Sobol::new(rng);
        Pmj02 {
            points,
            order: rng.next_u32(),
        }
    }

    /// The Sobol' index of the set's point `i`.
    #[inline]
    fn index(&self, i: u32) -> u32 {
        owen_scramble(i, self.order)
    }

    /// Point `i` in 32-bit fixed point.
    #[inline]
    pub fn bits(&self, i: u32) -> [u32; 2] {
        self.points.bits(self.index(i))
    }

    /// Point `i` in `[0, 1)^2`.
    #[inline]
    pub fn point(&self, i: u32) -> Vec2 {
        self.points.point(self.index(i))
    }

    /// Value `i` of the one-dimensional set (the first coordinate).
    #[inline]
    pub fn value(&self, i: u32) -> f32 {
        self.points.value(self.index(i))
    }
}

#[cfg(test)]
mod tests {
    use super::super::checks;
    use super::*;

    #[test]
    fn every_power_of_two_prefix_is_a_net() {
        checks::prefixes_are_nets("pmj02", |seed| {
            let s = Pmj02::new(&mut Rng::new(seed));
            move |i| s.bits(i)
        });
    }

    #[test]
    fn prefixes_are_stratified_in_1d_and_2d() {
        for seed in 0..checks::SEEDS {
            let s = Pmj02::new(&mut Rng::new(seed));
            let points: Vec<Vec2> = (0..1 << checks::MAX_M).map(|i| s.point(i)).collect();
            for m in 0..=checks::MAX_M {
                let prefix = &points[..1 << m];
                assert_eq!(checks::stratified(prefix), Ok(()), "seed {seed}, 2^{m}");
            }
        }
        // The check can fail: a prefix of 4 jittered points rarely is.
        let mut rng = Rng::new(3);
        let jittered: Vec<Vec2> = (0..4)
            .map(|_| Vec2::new(rng.next_f32(), rng.next_f32()))
            .collect();
        assert!(checks::stratified(&jittered).is_err());
    }

    #[test]
    fn the_order_is_random_per_set() {
        // The first point's Sobol' index is random, so sets do not all begin
        // with Sobol's first block.
        let firsts: std::collections::HashSet<u32> = (0..64)
            .map(|seed| Pmj02::new(&mut Rng::new(seed)).index(0))
            .collect();
        assert!(firsts.len() > 50, "{}", firsts.len());
        // Within a prefix of 4, the order of the block varies too.
        let orders: std::collections::HashSet<Vec<u32>> = (0..64)
            .map(|seed| {
                let s = Pmj02::new(&mut Rng::new(seed));
                (0..4).map(|i| s.index(i) % 4).collect()
            })
            .collect();
        assert!(orders.len() > 4, "{}", orders.len());
    }

    #[test]
    fn points_are_uniform_in_expectation() {
        checks::uniform_in_expectation("pmj02", |seed, count, out| {
            let s = Pmj02::new(&mut Rng::new(seed));
            out.extend((0..count).map(|i| s.point(i)));
        });
    }
}
