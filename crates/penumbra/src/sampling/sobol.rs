//! `sobol`: the first two dimensions of Sobol's sequence, Owen-scrambled by
//! hashing (Burley, "Practical Hash-based Owen Scrambling", JCGT 2020).
//!
//! # The sequence
//!
//! Point `i` of the 2D Sobol' sequence, in 32-bit fixed point, is
//! `x = C1 · i` and `y = C2 · i` over the bits of `i` (arithmetic mod 2):
//! `C1` is the bit reversal (dimension 1 of Joe and Kuo's direction numbers,
//! the van der Corput sequence in base 2) and `C2` the upper-triangular
//! Pascal matrix mod 2 (dimension 2, primitive polynomial `x + 1`, `m1 = 1`:
//! direction numbers `v1 = 1/2`, `v(k+1) = v(k) xor v(k)/2`). Together they form
//! a (0,2)-sequence in base 2: every aligned block of `2^m` consecutive points
//! (in particular every power-of-two prefix) is a (0,m,2)-net, i.e. each
//! elementary interval `[a/2^j, (a+1)/2^j) x [b/2^k, (b+1)/2^k)` with
//! `j + k = m` holds exactly one point.
//!
//! # Randomisation
//!
//! Each set draws two 32-bit seeds from its stream and scrambles each
//! coordinate with a nested uniform (Owen) scramble: a digit of the binary
//! expansion is flipped or not according to a hash of the seed and all the
//! digits before it. We use Burley's construction: reverse the bits, apply a
//! Laine–Karras style hash in which every output bit depends only on the
//! input bits below it (an addition of the seed and multiplications by even
//! constants xor-ed in), and reverse back. Because each digit's flip depends
//! only on the more significant digits, the scramble maps elementary
//! intervals onto elementary intervals of the same shape bijectively:
//! scrambled nets stay nets, for every set. And because the top digit is
//! flipped by a random bit, the next by a hash of that one, and so on, each
//! point is uniform over the square (to the hash's quality).
//!
//! # Guarantees
//!
//! For every seed: every prefix of `2^m` points is a (0,m,2)-net in base 2
//! (so for `N = 4^k` exactly one point per cell of the `2^k x 2^k` grid, and
//! for every `N = 2^m` exactly one point per row and per column of `N`
//! strata); any prefix is progressive, so stopping a set early keeps its
//! spread. Each point is uniform over the square in expectation. A set
//! takes its points in the trace order of
//! [`Distribution`](super::Distribution), which keeps every power-of-two
//! prefix a net.

use super::Rng;
use crate::math::Vec2;

/// Direction numbers of the second Sobol' dimension in 32-bit fixed point:
/// `v[0] = 2^31`, `v[k] = v[k-1] xor (v[k-1] >> 1)`.
const SECOND: [u32; 32] = {
    let mut v = [0u32; 32];
    v[0] = 1 << 31;
    let mut k = 1;
    while k < 32 {
        v[k] = v[k - 1] ^ (v[k - 1] >> 1);
        k += 1;
    }
    v
};

/// The first Sobol' dimension (van der Corput in base 2), fixed point.
#[inline]
pub(super) fn first_dimension(i: u32) -> u32 {
    i.reverse_bits()
}

/// The second dimension's matrix applied to each byte of an index:
/// `BYTES[b][v]` is the xor of the direction numbers of the set bits of `v`
/// placed at byte `b`. Four lookups replace a loop over up to 32 bits (a
/// `pmj02` index has about 16 set bits).
const BYTES: [[u32; 256]; 4] = {
    let mut t = [[0u32; 256]; 4];
    let mut b = 0;
    while b < 4 {
        let mut v = 0;
        while v < 256 {
            let mut y = 0;
            let mut bit = 0;
            while bit < 8 {
                if v >> bit & 1 != 0 {
                    y ^= SECOND[8 * b + bit];
                }
                bit += 1;
            }
            t[b][v] = y;
            v += 1;
        }
        b += 1;
    }
    t
};

/// The second Sobol' dimension, fixed point.
#[inline]
pub(super) fn second_dimension(i: u32) -> u32 {
    let [a, b, c, d] = i.to_le_bytes().map(usize::from);
    BYTES[0][a] ^ BYTES[1][b] ^ BYTES[2][c] ^ BYTES[3][d]
}

/// A hash of `x` in which every output bit depends only on the bits of `x`
/// at and below it (and on `seed`): Burley's improvement of Laine and
/// Karras's permutation. The constants are those of Burley's paper.
#[inline]
fn laine_karras(mut x: u32, seed: u32) -> u32 {
    x = x.wrapping_add(seed);
    x ^= x.wrapping_mul(0x6c50_b47c);
    x ^= x.wrapping_mul(0xb82f_1e52);
    x ^= x.wrapping_mul(0xc7af_e638);
    x ^= x.wrapping_mul(0x8d22_f6e6);
    x
}

/// Nested uniform (Owen) scramble of a 32-bit fixed-point value: the flip
/// of each bit depends only on the bits above it.
#[inline]
pub(super) fn owen_scramble(x: u32, seed: u32) -> u32 {
    laine_karras(x.reverse_bits(), seed).reverse_bits()
}

/// `owen_scramble(first_dimension(i), seed)`, without reversing the bits
/// twice (the first dimension is the reversal itself).
#[inline]
pub(super) fn scrambled_first(i: u32, seed: u32) -> u32 {
    laine_karras(i, seed).reverse_bits()
}

/// A fixed-point value in `[0, 2^32)` as an `f32` in `[0, 1)`: its top 24
/// bits, exactly.
#[inline]
pub(super) fn unit(x: u32) -> f32 {
    (x >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
}

/// Two independent 32-bit seeds from one draw of a set's stream.
pub(super) fn seeds(rng: &mut Rng) -> (u32, u32) {
    let s = rng.next_u64();
    (s as u32, (s >> 32) as u32)
}

/// One randomised `sobol` set: the scramble seeds of its two coordinates.
#[derive(Clone, Copy, Debug)]
pub struct Sobol {
    sx: u32,
    sy: u32,
}

impl Sobol {
    /// A set drawn from its stream (one 64-bit draw).
    pub fn new(rng: &mut Rng) -> Sobol {
        let (sx, sy) = seeds(rng);
        Sobol { sx, sy }
    }

    /// The set of two scramble seeds.
    pub(super) fn from_seeds(sx: u32, sy: u32) -> Sobol {
        Sobol { sx, sy }
    }

    /// Point `i` in 32-bit fixed point.
    #[inline]
    pub fn bits(&self, i: u32) -> [u32; 2] {
        [
            scrambled_first(i, self.sx),
            owen_scramble(second_dimension(i), self.sy),
        ]
    }

    /// Point `i` in `[0, 1)^2`.
    #[inline]
    pub fn point(&self, i: u32) -> Vec2 {
        let [x, y] = self.bits(i);
        Vec2::new(unit(x), unit(y))
    }

    /// Value `i` of the one-dimensional set (the first coordinate).
    #[inline]
    pub fn value(&self, i: u32) -> f32 {
        unit(scrambled_first(i, self.sx))
    }
}

#[cfg(test)]
mod tests {
    use super::super::checks;
    use super::*;

    #[test]
    fn the_sequence_is_sobols() {
        // The unscrambled start of the 2D Sobol' sequence.
        let expected = [
            (0.0, 0.0),
            (0.5, 0.5),
            (0.25, 0.75),
            (0.75, 0.25),
            (0.125, 0.625),
            (0.625, 0.125),
            (0.375, 0.375),
            (0.875, 0.875),
        ];
        for (i, &(x, y)) in expected.iter().enumerate() {
            let i = i as u32;
            assert_eq!(unit(first_dimension(i)), x, "x of {i}");
            assert_eq!(unit(second_dimension(i)), y, "y of {i}");
        }
    }

    #[test]
    fn the_byte_tables_are_the_direction_numbers() {
        let by_bits = |mut i: u32| {
            let mut y = 0;
            while i != 0 {
                y ^= SECOND[i.trailing_zeros() as usize];
                i &= i - 1;
            }
            y
        };
        let mut rng = Rng::new(4);
        for i in (0..4096).chain((0..4096).map(|_| rng.next_u32())) {
            assert_eq!(second_dimension(i), by_bits(i), "{i}");
        }
    }

    #[test]
    fn the_first_dimension_is_scrambled_directly() {
        let mut rng = Rng::new(6);
        for _ in 0..10_000 {
            let (i, seed) = (rng.next_u32(), rng.next_u32());
            let direct = scrambled_first(i, seed);
            assert_eq!(direct, owen_scramble(first_dimension(i), seed));
        }
    }

    #[test]
    fn the_scramble_is_nested() {
        // Values sharing their top k bits still share them after the scramble.
        let mut rng = Rng::new(1);
        for _ in 0..2000 {
            let (a, seed) = (rng.next_u32(), rng.next_u32());
            let k = rng.below(32);
            let b = a ^ (rng.next_u32() >> k);
            let (sa, sb) = (owen_scramble(a, seed), owen_scramble(b, seed));
            assert_eq!(sa.checked_shr(32 - k), sb.checked_shr(32 - k), "k={k}");
        }
    }

    #[test]
    fn every_power_of_two_prefix_is_a_net() {
        checks::prefixes_are_nets("sobol", |seed| {
            let s = Sobol::new(&mut Rng::new(seed));
            move |i| s.bits(i)
        });
        // The check can fail: the same hash applied without the reversals
        // (each bit's flip then depends on the bits *below* it) breaks the
        // nets, and so do independent second coordinates.
        for seed in [1, 2, 3] {
            let wrong_way = |i: u32| {
                [
                    scrambled_first(i, seed),
                    laine_karras(second_dimension(i), seed),
                ]
            };
            assert!(
                (1..=checks::MAX_M).any(|m| checks::first_non_net(1 << m, wrong_way).is_some()),
                "seed {seed}"
            );
        }
        let random = |i: u32| {
            [
                first_dimension(i),
                crate::sampling::mix64(u64::from(i)) as u32,
            ]
        };
        assert!(checks::first_non_net(64, random).is_some());
    }

    /// The sets the renderer gets (scaled to `[-r, r]^2` and back, exactly)
    /// are the nets in every power-of-two prefix of their trace order, for
    /// `sobol`, `zsobol`, `pmj02` and `pmj02bn`.
    #[test]
    fn generated_sets_are_nets() {
        use crate::sampling::Distribution;
        let mut out = Vec::new();
        for d in [
            Distribution::Sobol,
            Distribution::Zsobol,
            Distribution::Pmj02,
            Distribution::Pmj02bn,
        ] {
            for seed in 0..checks::SEEDS {
                d.generate(1 << checks::MAX_M, 1.0, &mut Rng::new(seed), &mut out);
                let unit: Vec<Vec2> = out.iter().map(|p| 0.5 * (p.truncate() + 1.0)).collect();
                for m in 0..=checks::MAX_M {
                    let bad = checks::first_non_net(1 << m, |i| checks::fixed(unit[i as usize]));
                    assert_eq!(bad, None, "{d} seed {seed}: 2^{m} points");
                }
            }
        }
    }

    #[test]
    fn points_are_uniform_in_expectation() {
        checks::uniform_in_expectation("sobol", |seed, count, out| {
            let s = Sobol::new(&mut Rng::new(seed));
            out.extend((0..count).map(|i| s.point(i)));
        });
    }
}
