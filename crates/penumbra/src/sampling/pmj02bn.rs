//! `pmj02bn`: progressive multi-jittered (0,2) sequences with blue noise
//! (Christensen, Kensler and Kilpatrick, "Progressive Multi-Jittered Sample
//! Sequences", EGSR 2018), drawn from a small pool of sequences built at
//! first use and randomised per set.
//!
//! # What it is
//!
//! A `pmj02bn` set has the guarantees of [`pmj02`](super::pmj02) (every
//! prefix of `2^m` points is a (0,m,2)-net in base 2) and, besides, its
//! points keep away from each other: fewer close pairs and larger gaps to
//! the nearest neighbour, the "blue noise" of best-candidate sampling.
//! Christensen et al. place each new point, among the sub-strata the (0,2)
//! constraints leave free, as the best of several random candidates (the
//! one farthest from the points so far). That is far too slow per set;
//! pbrt-v4 ships a few precomputed sequences and randomises them per pixel
//! by a random toroidal shift (Cranley–Patterson rotation). We build our
//! own pool at first use, and randomise it differently, for the reasons
//! below.
//!
//! # Where the freedom is
//!
//! Per-point best candidates shape the power-of-two sets little. Given the
//! first `2^m` points `P` of a progressive (0,2) sequence, the next `2^m`
//! points `Q` are fixed, to `m + 1` binary digits in each coordinate, by
//! `P` alone: `P ∪ Q` must be a (0,m+1,2)-net, so `Q` is a (0,m,2)-net
//! whose point in each elementary interval of `2^-m` area lies in the half
//! that `P`'s point there leaves free; taking the intervals from the rows
//! of height `2^-m` to the columns of width `2^-m`, each digit of a point
//! of `Q` is the complement of a digit of a point of `P`. A new point can
//! only choose *which* of those cells comes next (which shapes the sets of
//! other sizes) and where it sits in its cell of side `2^-(m+1)`, far
//! below the spacing of the set once there are more than a few points.
//! What shapes a set of `2^n` points is the choice, made earlier, of the
//! later digits of earlier points. Measured on sequences built that way
//! (ten candidates a point, not randomised): the mean nearest-neighbour
//! distance is 7% above `pmj02`'s at 16 and 64 points, 2% at 256, 1% at
//! 1024 (and 15 to 16% at 24 or 100 points).
//!
//! Those digit choices are what a nested (Owen) scramble of the Sobol'
//! sequence makes: each digit of a coordinate flipped or not according to
//! the digits above it. Each sequence of the pool is a *linearly*
//! scrambled Sobol' (0,2)-sequence, `x = Lx · C1 · i`, `y = Ly · C2 · i`
//! over GF(2) for point `i` (`C1`, `C2` the generator matrices of
//! [`sobol`](super::sobol); `Lx`, `Ly` lower triangular with a unit
//! diagonal: digit `d` flipped by a fixed parity of the digits above it),
//! with `Lx` and `Ly` chosen for blue noise.
//!
//! # Randomisation
//!
//! A toroidal shift keeps every distance but breaks the nets: a shift by a
//! multiple of `2^-k` maps elementary intervals of width `2^-k` or less
//! onto elementary intervals, but not wider ones (shifted by `1/4`, the
//! halves `[0, 1/2)` and `[1/2, 1)` straddle the cut). A nested scramble
//! keeps the nets but, in general, not the distances. Of the isometries of
//! the torus, only the translations by a half, the reflections of each
//! axis and the swap of the axes map every elementary interval onto one:
//! too few to make each point uniform over the square. Each set therefore
//! takes, from two 64-bit draws of its stream,
//!
//! * a random *digital shift*: `x xor cx`, `y xor cy` for uniform 32-bit
//!   `cx`, `cy` (a nested scramble that flips digit `d` of every point
//!   alike). Every point is then exactly uniform over the square (over the
//!   `2^32 x 2^32` fixed-point grid), and every elementary interval maps
//!   onto one of the same shape, so the nets stay nets;
//! * one of the [`POOL_SIZE`] sequences, and whether to swap the axes.
//!
//! A digital shift moves points by different amounts on either side of
//! the lines `x = a 2^-d`, so it changes distances; but after it, the
//! difference of two points depends only on the digits in which they
//! differ and on the shift, which gives each of those digits a random
//! sign. In a linear sequence the digits in which points `i` and `j`
//! differ are those of point `i xor j`. So the expected energy of a set
//! over all digital shifts is a sum over `k` of a function of point `k`,
//! cheap enough to optimise, and that expectation is what the pool's
//! sequences are optimised for, not the energy of one placement.
//!
//! # Construction of the pool
//!
//! The energy of a set of `N` points is `Σ exp(-|p - q|^2 / 2σ^2)` over its
//! pairs on the torus, `σ = 0.4 / sqrt(N)`; its expectation over digital
//! shifts is `Σ_k h(Lx C1 k) · h(Ly C2 k)` over `0 < k < N`, where
//! `h(D)` is the mean, over random signs, of the Gaussian of `Σ ±2^-d`
//! over the digits `d` set in `D`. `h` is tabulated over the first 9 to 14
//! digits of `D` by a recursion on the digits, from the last. Each
//! candidate sequence starts from random matrices; a coordinate descent
//! then flips one entry at a time when that lowers the summed energy per
//! point of the prefixes of 4, 8, ..., `2^POOL_LEVELS` points, in stages:
//! the prefixes of up to `2^s` points and digits 2 to `s/2 + 5` at stage
//! `s = 3, 4, ...`. Digits past the 10th stay random. The pool keeps the
//! [`POOL_SIZE`] of 8 candidates whose energy, counted up to
//! 4096 points, is least (the sequences best at 1024 points are often the
//! worst at 4096). Every decision is made in integers from tables built
//! with IEEE arithmetic only (no library `exp`), from fixed seeds, so
//! every machine builds the same pool.
//!
//! *Pool size.* 4 sequences of 2 x 4 x 256 words (8 KB each), chosen
//! among 8 and optimised for sets of up to 1024 points
//! ([`POOL_LEVELS`] = 10): the renderer's sets hold a few to a few hundred
//! points. The digital shift already makes 2^64 different sets of each
//! sequence; the pool only has to keep all pixels from sharing one
//! structure, and more candidates cost time at first use. Building it
//! takes about 20 ms of one core of a test machine, 30 to 45 ms when the
//! core is shared with other work (the test `the_pool_is_built_quickly`
//! prints it), once per process.
//!
//! *Beyond the optimised prefixes.* The sequences are infinite: sets of
//! any size keep their nets; past 1024 points their mean nearest-neighbour
//! distance falls to that of `pmj02`, though their closest pairs stay
//! farther apart (measured below).
//!
//! # Guarantees
//!
//! For every set: every prefix of `2^m` points is a (0,m,2)-net in base 2
//! (tested up to `2^13`); each point is exactly uniform over the square in
//! expectation. Measured, not guaranteed: the mean distance from a point to
//! its nearest neighbour on the torus, times `sqrt(N)`, over 64 sets (8 at
//! 4096), with the smallest in brackets, against `pmj02` (independent
//! uniform points give 0.50):
//!
//! | N | 16 | 64 | 256 | 1024 | 4096 | 24 | 100 |
//! |---|---:|---:|---:|---:|---:|---:|---:|
//! | `pmj02bn` | 0.78 (0.42) | 0.78 (0.37) | 0.75 (0.30) | 0.71 (0.24) | 0.65 (0.21) | 0.67 (0.37) | 0.68 (0.31) |
//! | `pmj02` | 0.65 (0.40) | 0.62 (0.29) | 0.66 (0.22) | 0.64 (0.13) | 0.65 (0.09) | 0.63 (0.31) | 0.63 (0.23) |
//!
//! The same pool without the digital shift gives 0.76 at 256 points, and
//! Owen-scrambled (also exact nets, also uniform) 0.64: a full nested
//! scramble erases the blue noise. Optimising one placement instead (an
//! Owen scramble of a 256-point net, in a prototype) reaches 0.90, but
//! keeps 0.72 once shifted.
//!
//! *Integration.* On the integrands of `penumbra reproduce --study
//! distributions`, edges converge as with `pmj02` (slopes −0.72 to −0.74,
//! slightly lower errors at small counts). On the smooth Gaussian the error
//! is erratic, as a fixed net's is: a digital shift makes the variance the
//! sum of the function's squared Walsh coefficients over the net's dual, so
//! it depends on the net (2.5 times `pmj02`'s RMSE at 128 points, 9 times
//! smaller at 256), where Owen's scramble averages over all nets and
//! guarantees `O(N^-3 log N)`. Blue noise, exact nets and exact uniformity
//! cost that: the structure that keeps points apart is the structure a
//! full scramble would average away.
//!
//! *Cost.* A point is eight table lookups and xors: a few ns.
//!
//! Sources: Christensen, Kensler and Kilpatrick 2018 (pmj02 and its
//! best-candidate variant); Owen 1995 (nested scrambles keep nets);
//! Matoušek 1998, "On the L2-discrepancy for anchored boxes" (linear
//! scrambles and digital shifts); pbrt-v4's `PMJ02BNSampler` (a pool of
//! precomputed sequences).

use std::fmt;
use std::sync::OnceLock;

use super::sobol::{second_dimension, unit};
use super::Rng;
use crate::math::Vec2;

/// Sequences in the pool.
pub const POOL_SIZE: usize = 4;
/// Sequences built, of which the pool keeps the [`POOL_SIZE`] of least
/// energy.
const CANDIDATES: usize = 8;
/// The pool's sequences are optimised for their prefixes of up to
/// `2^POOL_LEVELS` points...
pub const POOL_LEVELS: u32 = 10;
/// ...and chosen among `CANDIDATES` for those of up to `2^CHOICE_LEVELS`.
const CHOICE_LEVELS: u32 = 12;
/// Fixed-point scale of the energy tables.
const SCALE: f64 = (1u32 << 20) as f64;

/// One sequence of the pool: `bytes[axis][b][v]` is the coordinate of its
/// point `v << 8b` in 32-bit fixed point. The sequence is linear over
/// GF(2) (point `i xor j` is point `i` xor point `j`), so four lookups per
/// coordinate give any point.
struct Sequence {
    bytes: Box<[[[u32; 256]; 4]; 2]>,
}

impl Sequence {
    /// Point `i` of the sequence.
    #[inline]
    fn at(&self, i: u32) -> [u32; 2] {
        let [a, b, c, d] = i.to_le_bytes().map(usize::from);
        let t = &self.bytes;
        [
            t[0][0][a] ^ t[0][1][b] ^ t[0][2][c] ^ t[0][3][d],
            t[1][0][a] ^ t[1][1][b] ^ t[1][2][c] ^ t[1][3][d],
        ]
    }
}

/// The pool, built at first use.
struct Pool {
    sequences: Vec<Sequence>,
}

fn pool() -> &'static Pool {
    static POOL: OnceLock<Pool> = OnceLock::new();
    POOL.get_or_init(Pool::build)
}

/// One randomised `pmj02bn` set: a sequence of the pool, whether its axes
/// are swapped, and its digital shift.
#[derive(Clone, Copy)]
pub struct Pmj02bn {
    sequence: &'static Sequence,
    index: u8,
    swap: bool,
    shift: [u32; 2],
}

impl fmt::Debug for Pmj02bn {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Pmj02bn")
            .field("sequence", &self.index)
            .field("swap", &self.swap)
            .field("shift", &self.shift)
            .finish()
    }
}

impl Pmj02bn {
    /// A set drawn from its stream (two draws). The first set ever drawn
    /// builds the pool.
    pub fn new(rng: &mut Rng) -> Pmj02bn {
        let s = rng.next_u64();
        let choice = rng.next_u64();
        let index = (choice >> 1) as usize % POOL_SIZE;
        Pmj02bn {
            sequence: &pool().sequences[index],
            index: index as u8,
            swap: choice & 1 == 1,
            shift: [s as u32, (s >> 32) as u32],
        }
    }

    /// Point `i` in 32-bit fixed point.
    #[inline]
    pub fn bits(&self, i: u32) -> [u32; 2] {
        let [x, y] = self.sequence.at(i);
        let [x, y] = if self.swap { [y, x] } else { [x, y] };
        [x ^ self.shift[0], y ^ self.shift[1]]
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
        unit(self.bits(i)[0])
    }
}

/// `exp(-z)` for `z >= 0` from additions, multiplications and divisions
/// only, which IEEE arithmetic gives the same on every machine (a
/// library's `exp` may differ in its last bit, and the pool must not).
fn exp_neg(z: f64) -> f64 {
    if z >= 40.0 {
        return 0.0;
    }
    // exp(-z) = exp(-z/64)^64, the inner one by its Taylor series (w < 0.63,
    // 14 terms: relative error below 1e-15, 1e-13 after squaring 6 times).
    let w = z / 64.0;
    let (mut term, mut sum) = (1.0, 1.0);
    for k in 1..=14 {
        term *= -w / f64::from(k);
        sum += term;
    }
    (0..6).fold(sum, |r, _| r * r)
}

/// Lower triangular GF(2) matrix with a unit diagonal: `rows[d]` holds the
/// digits above digit `d` (counted from the top, from 0) whose parity flips
/// it.
type Scramble = [u32; 32];

/// `L · u` for a scramble `L`.
fn scramble(rows: &Scramble, u: u32) -> u32 {
    let mut out = u;
    for (d, &row) in rows.iter().enumerate().skip(1) {
        if (row & u).count_ones() & 1 == 1 {
            out ^= 1 << (31 - d);
        }
    }
    out
}

/// The expected Gaussian of a coordinate difference over digital shifts:
/// `h[D >> (32 - bits)]` for the xor `D` of two coordinates, in units of
/// `1 / SCALE`, for sets of `n` points.
struct Kernel {
    bits: u32,
    h: Vec<u32>,
}

impl Kernel {
    /// For sets of `n` points: width `σ = 0.4 / sqrt(n)`, `bits =
    /// floor(log2 n) / 2 + 8` leading digits of `D` (the rest move a
    /// difference by under `σ / 50`).
    fn new(n: u32) -> Kernel {
        let bits = n.ilog2() / 2 + 8;
        let size = 1usize << bits;
        let two_sigma2 = 0.32 / f64::from(n);
        // The Gaussian of every offset t / 2^bits on the torus...
        let mut a: Vec<u32> = (0..size)
            .map(|v| {
                let c = v.min(size - v) as f64 / size as f64;
                (exp_neg(c * c / two_sigma2) * SCALE + 0.5) as u32
            })
            .collect();
        // ...then, digit by digit from the last, the mean over the sign of
        // digit `i` of D: entry (digits i.. of D, offset in units of
        // 2^-(i-1)), `bits` bits in all at every step.
        let mut b = vec![0u32; size];
        for i in (1..=bits).rev() {
            let (offset_bits, suffix_bits) = (i - 1, bits - i);
            let mask = (1usize << i) - 1;
            for s in 0..1usize << suffix_bits {
                let old = &a[s << i..(s + 1) << i];
                for t in 0..1usize << offset_bits {
                    b[s << offset_bits | t] = old[2 * t];
                    let avg = (u64::from(old[(2 * t + 1) & mask])
                        + u64::from(old[(2 * t + mask) & mask]))
                        / 2;
                    b[(1 << suffix_bits | s) << offset_bits | t] = avg as u32;
                }
            }
            std::mem::swap(&mut a, &mut b);
        }
        Kernel { bits, h: a }
    }

    #[inline]
    fn of(&self, d: u32) -> u64 {
        u64::from(self.h[(d >> (32 - self.bits)) as usize])
    }
}

/// The kernels of the prefixes of `2^m` points (index `m`, from 2 to
/// [`CHOICE_LEVELS`]) and the unscrambled Sobol' coordinates of the indices
/// below `2^CHOICE_LEVELS`.
struct Energy {
    kernels: Vec<Kernel>,
    u: [Vec<u32>; 2],
}

/// The smallest `m >= 2` with `k < 2^m`: the first prefix of `2^m` points
/// that holds pairs at index xor `k`.
#[inline]
fn first_level(k: usize) -> u32 {
    (usize::BITS - k.leading_zeros()).max(2)
}

impl Energy {
    fn new() -> Energy {
        let n = 1u32 << CHOICE_LEVELS;
        Energy {
            kernels: (0..=CHOICE_LEVELS).map(|m| Kernel::new(1 << m)).collect(),
            u: [
                (0..n).map(u32::reverse_bits).collect(),
                (0..n).map(second_dimension).collect(),
            ],
        }
    }

    /// The expected energy, per point of the prefixes of `2^m` points
    /// (`m <= top`) that hold them, of the pairs at index xor `k`, given
    /// the xors `dx`, `dy` of their coordinates.
    #[inline]
    fn pair(&self, k: usize, dx: u32, dy: u32, top: u32) -> u64 {
        self.kernels[first_level(k) as usize..=top as usize]
            .iter()
            .map(|kernel| kernel.of(dx) * kernel.of(dy))
            .sum()
    }

    /// What flipping digit `flip` of `d` (one coordinate's xor, `e` the
    /// other's) changes [`pair`](Self::pair) by.
    #[inline]
    fn flip_delta(&self, k: usize, d: u32, e: u32, flip: u32, top: u32) -> i64 {
        self.kernels[first_level(k) as usize..=top as usize]
            .iter()
            .map(|kernel| {
                let (new, old) = (kernel.of(d ^ flip) as i64, kernel.of(d) as i64);
                (new - old) * kernel.of(e) as i64
            })
            .sum()
    }

    /// The expected energy per point of scrambles `l`, summed over the
    /// optimised prefixes.
    fn total(&self, l: &[Scramble; 2]) -> u64 {
        let diff: [Vec<u32>; 2] = [0, 1].map(|axis| {
            self.u[axis]
                .iter()
                .map(|&u| scramble(&l[axis], u))
                .collect()
        });
        (1..1 << CHOICE_LEVELS)
            .map(|k| self.pair(k, diff[0][k], diff[1][k], CHOICE_LEVELS))
            .sum()
    }

    /// Scramble matrices from random ones by staged coordinate descent.
    fn matrices(&self, rng: &mut Rng) -> [Scramble; 2] {
        let mut l = [[0u32; 32]; 2];
        for rows in &mut l {
            for (d, row) in rows.iter_mut().enumerate().skip(1) {
                *row = rng.next_u32() & !(u32::MAX >> d);
            }
        }
        let mut diff: [Vec<u32>; 2] = [0, 1].map(|axis| {
            self.u[axis]
                .iter()
                .map(|&u| scramble(&l[axis], u))
                .collect()
        });
        for top in 3..=POOL_LEVELS {
            let n = 1usize << top;
            let rows = top as usize / 2 + 5;
            for _sweep in 0..8 {
                let mut changed = false;
                // Entry (d, b): digit b's part in the flip of digit d.
                let entries = (1..rows).flat_map(|d| (0..d).map(move |b| (d, b)));
                for ((d, b), axis) in entries.flat_map(|e| [(e, 0), (e, 1)]) {
                    let (select, flip) = (1u32 << (31 - b), 1u32 << (31 - d));
                    let (d_axis, other) = (&diff[axis], &diff[1 - axis]);
                    let delta: i64 = (1..n)
                        .filter(|&k| self.u[axis][k] & select != 0)
                        .map(|k| self.flip_delta(k, d_axis[k], other[k], flip, top))
                        .sum();
                    if delta < 0 {
                        changed = true;
                        l[axis][d] ^= select;
                        for (k, v) in diff[axis].iter_mut().enumerate() {
                            if self.u[axis][k] & select != 0 {
                                *v ^= flip;
                            }
                        }
                    }
                }
                if !changed {
                    break;
                }
            }
        }
        l
    }
}

/// The seed of the pool's random starting matrices.
const SEED: u64 = 0x706d_6a30_3262_6e00;

impl Pool {
    fn build() -> Pool {
        let energy = Energy::new();
        let mut candidates: Vec<(u64, usize, [Scramble; 2])> = (0..CANDIDATES)
            .map(|j| {
                let l = energy.matrices(&mut Rng::new(SEED).derive(j as u64));
                (energy.total(&l), j, l)
            })
            .collect();
        candidates.sort_unstable_by_key(|&(e, j, _)| (e, j));
        let sequences = candidates
            .iter()
            .take(POOL_SIZE)
            .map(|(_, _, l)| {
                let columns: [[u32; 32]; 2] = [
                    std::array::from_fn(|b| scramble(&l[0], 1 << (31 - b))),
                    std::array::from_fn(|b| scramble(&l[1], second_dimension(1 << b))),
                ];
                let mut bytes = Box::new([[[0u32; 256]; 4]; 2]);
                for (axis, table) in bytes.iter_mut().enumerate() {
                    for (byte, row) in table.iter_mut().enumerate() {
                        for (v, entry) in row.iter_mut().enumerate() {
                            *entry = (0..8)
                                .filter(|bit| v >> bit & 1 == 1)
                                .fold(0, |acc, bit| acc ^ columns[axis][8 * byte + bit]);
                        }
                    }
                }
                Sequence { bytes }
            })
            .collect();
        Pool { sequences }
    }
}

#[cfg(test)]
mod tests {
    use super::super::checks;
    use super::super::pmj02::Pmj02;
    use super::super::sobol::owen_scramble;
    use super::*;

    fn set(seed: u64) -> Pmj02bn {
        Pmj02bn::new(&mut Rng::new(seed))
    }

    #[test]
    fn every_power_of_two_prefix_is_a_net() {
        checks::prefixes_are_nets("pmj02bn", |seed| {
            let s = set(seed);
            move |i| s.bits(i)
        });
    }

    /// The sets the renderer gets (scaled to `[-r, r]^2` and back, exactly)
    /// are the nets, and the shutter times are their first coordinates.
    #[test]
    fn generated_sets_are_nets() {
        use crate::sampling::Distribution;
        let (mut out, mut times) = (Vec::new(), Vec::new());
        for seed in 0..checks::SEEDS {
            let n = 1 << checks::MAX_M;
            Distribution::Pmj02bn.generate(n, 1.0, &mut Rng::new(seed), &mut out);
            let unit: Vec<Vec2> = out.iter().map(|p| 0.5 * (p.truncate() + 1.0)).collect();
            for m in 0..=checks::MAX_M {
                let bad = checks::first_non_net(1 << m, |i| checks::fixed(unit[i as usize]));
                assert_eq!(bad, None, "seed {seed}: 2^{m} points");
            }
            Distribution::Pmj02bn.generate_1d(n, &mut Rng::new(seed), &mut times);
            assert!(
                times.iter().zip(&unit).all(|(t, p)| *t == p.x),
                "seed {seed}"
            );
        }
    }

    /// The nets go on past the prefixes the pool is optimised for.
    #[test]
    fn nets_continue_past_the_optimised_prefixes() {
        for seed in 0..12 {
            let s = set(seed);
            for m in checks::MAX_M + 1..=13 {
                assert_eq!(
                    checks::first_non_net(1 << m, |i| s.bits(i)),
                    None,
                    "seed {seed}: 2^{m} points"
                );
            }
        }
    }

    #[test]
    fn prefixes_are_stratified_in_1d_and_2d() {
        for seed in 0..checks::SEEDS {
            let s = set(seed);
            let points: Vec<Vec2> = (0..1 << checks::MAX_M).map(|i| s.point(i)).collect();
            for m in 0..=checks::MAX_M {
                let prefix = &points[..1 << m];
                assert_eq!(checks::stratified(prefix), Ok(()), "seed {seed}, 2^{m}");
            }
            let values: Vec<f32> = (0..1 << checks::MAX_M).map(|i| s.value(i)).collect();
            assert!(values.iter().zip(&points).all(|(v, p)| *v == p.x));
        }
    }

    #[test]
    fn points_are_uniform_in_expectation() {
        checks::uniform_in_expectation("pmj02bn", |seed, count, out| {
            let s = set(seed);
            out.extend((0..count).map(|i| s.point(i)));
        });
    }

    #[test]
    fn sets_draw_every_sequence_both_ways() {
        let mut seen = std::collections::HashSet::new();
        for seed in 0..200 {
            let s = set(seed);
            seen.insert((s.index, s.swap));
        }
        assert_eq!(seen.len(), 2 * POOL_SIZE);
    }

    /// The sequences are digital: point `i xor j` is point `i` xor point
    /// `j`, so the difference of two points after a digital shift depends
    /// only on `i xor j` and the shift (what the construction relies on).
    #[test]
    fn sequences_are_linear() {
        let mut rng = Rng::new(3);
        for sequence in &pool().sequences {
            assert_eq!(sequence.at(0), [0, 0]);
            for _ in 0..1000 {
                let (i, j) = (rng.next_u32(), rng.next_u32());
                let [a, b] = [sequence.at(i), sequence.at(j)];
                assert_eq!(sequence.at(i ^ j), [a[0] ^ b[0], a[1] ^ b[1]]);
            }
        }
    }

    /// The pool is a pure function of its seed: building it again, on
    /// another thread, gives the same points.
    #[test]
    fn the_pool_is_deterministic() {
        let again = std::thread::spawn(Pool::build).join().expect("build");
        for (a, b) in pool().sequences.iter().zip(&again.sequences) {
            assert_eq!(a.bytes, b.bytes);
        }
        // The first 1024 points of the first sequence, pinned: a change of
        // the construction, or a machine that computes it differently,
        // shows here (renders made elsewhere would differ).
        let first = &pool().sequences[0];
        let digest = (0..1 << POOL_LEVELS)
            .map(|i| first.at(i))
            .fold(0u64, |h, [x, y]| {
                crate::sampling::mix64(h ^ (u64::from(x) << 32 | u64::from(y)))
            });
        assert_eq!(digest, 0x278d_257f_b08f_f198, "{digest:#018x}");
    }

    #[test]
    fn the_pool_is_built_quickly() {
        let start = std::time::Instant::now();
        let built = Pool::build();
        let took = start.elapsed();
        println!("pmj02bn pool: {POOL_SIZE} sequences built in {took:?}");
        assert_eq!(built.sequences.len(), POOL_SIZE);
        // Generous (a shared machine, an unoptimised build): catches an
        // accidentally quadratic construction, not small regressions.
        let limit = if cfg!(debug_assertions) { 20_000 } else { 1000 };
        assert!(took.as_millis() < limit, "{took:?}");
    }

    #[test]
    fn exp_neg_is_exp() {
        for k in 0..4000 {
            let z = f64::from(k) * 0.01;
            let (ours, libm) = (exp_neg(z), (-z).exp());
            assert!(
                (ours - libm).abs() <= 1e-14 + 1e-12 * libm,
                "{z}: {ours} {libm}"
            );
        }
        assert_eq!(exp_neg(40.0), 0.0);
    }

    /// The kernel tables hold the mean, over the signs of the digits of D,
    /// of the Gaussian of the signed sum: checked by enumerating the signs.
    #[test]
    fn kernel_tables_are_the_mean_over_signs() {
        let mut rng = Rng::new(8);
        for m in [2, 5, 8] {
            let kernel = Kernel::new(1 << m);
            let two_sigma2 = 0.32 / f64::from(1u32 << m);
            for _ in 0..300 {
                // At most 12 digits set, so the signs can be enumerated.
                let d = rng.next_u32() & rng.next_u32() & !(u32::MAX >> kernel.bits);
                let digits: Vec<u32> = (1..=kernel.bits)
                    .filter(|&i| d >> (32 - i) & 1 == 1)
                    .collect();
                let patterns = 1u32 << digits.len();
                let mean = (0..patterns)
                    .map(|signs| {
                        let sum: f64 = digits
                            .iter()
                            .enumerate()
                            .map(|(j, &i)| {
                                let term = 0.5f64.powi(i as i32);
                                if signs >> j & 1 == 1 {
                                    -term
                                } else {
                                    term
                                }
                            })
                            .sum();
                        let c = (sum - sum.round()).abs();
                        exp_neg(c * c / two_sigma2)
                    })
                    .sum::<f64>()
                    / f64::from(patterns);
                let table = kernel.of(d) as f64 / SCALE;
                assert!(
                    (table - mean).abs() < 2e-5,
                    "m={m} d={d:#x}: {table} vs {mean}"
                );
            }
        }
    }

    /// Mean distance from each point to its nearest neighbour on the torus,
    /// times `sqrt(N)`, and the smallest, for a set in fixed point.
    fn nearest(points: &[[u32; 2]]) -> (f64, f64) {
        let axis = |a: u32, b: u32| f64::from(a.wrapping_sub(b) as i32) / 4_294_967_296.0;
        let (mut sum, mut least) = (0.0, f64::MAX);
        for (i, p) in points.iter().enumerate() {
            let d2 = points
                .iter()
                .enumerate()
                .filter(|&(j, _)| j != i)
                .map(|(_, q)| axis(p[0], q[0]).powi(2) + axis(p[1], q[1]).powi(2))
                .fold(f64::MAX, f64::min);
            sum += d2.sqrt();
            least = least.min(d2.sqrt());
        }
        let scale = (points.len() as f64).sqrt();
        (sum / points.len() as f64 * scale, least * scale)
    }

    /// Means of [`nearest`] over 64 sets of `n` points (8 past 1024).
    fn mean_nearest(n: u32, bits: impl Fn(u64, u32) -> [u32; 2]) -> (f64, f64) {
        let sets = if n > 1024 { 8 } else { 64 };
        let (mut mean, mut least) = (0.0, 0.0);
        for seed in 0..sets {
            let points: Vec<[u32; 2]> = (0..n).map(|i| bits(seed, i)).collect();
            let (a, b) = nearest(&points);
            mean += a / sets as f64;
            least += b / sets as f64;
        }
        (mean, least)
    }

    /// The blue noise the pool keeps through the per-set randomisation,
    /// against `pmj02`: the numbers of the module docs.
    #[test]
    fn blue_noise_survives_the_digital_shift() {
        let mut worse = Vec::new();
        for n in [16, 64, 256, 1024, 4096, 24, 100] {
            let bn = mean_nearest(n, |seed, i| set(seed).bits(i));
            let pmj = mean_nearest(n, |seed, i| Pmj02::new(&mut Rng::new(seed)).bits(i));
            println!(
                "N={n}: mean (smallest) nearest-neighbour distance x sqrt(N): \
                 pmj02bn {:.3} ({:.3}), pmj02 {:.3} ({:.3})",
                bn.0, bn.1, pmj.0, pmj.1
            );
            // Past the optimised prefixes, no worse than pmj02 (up to the
            // noise of 8 sets).
            let margin = match n {
                _ if n > 1 << POOL_LEVELS => -0.02,
                _ if n.is_power_of_two() => 0.05,
                _ => 0.02,
            };
            if bn.0 <= pmj.0 + margin {
                worse.push(n);
            }
        }
        assert!(worse.is_empty(), "not bluer than pmj02 at N = {worse:?}");
        // A full Owen scramble, which keeps nets and uniformity too, would
        // erase the blue noise the digital shift keeps.
        let unshifted = mean_nearest(256, |seed, i| {
            pool().sequences[seed as usize % POOL_SIZE].at(i)
        });
        let owen = mean_nearest(256, |seed, i| {
            let [x, y] = pool().sequences[seed as usize % POOL_SIZE].at(i);
            let s = seed as u32;
            [
                owen_scramble(x, s.wrapping_mul(0x9e37_79b9)),
                owen_scramble(y, !s),
            ]
        });
        let shifted = mean_nearest(256, |seed, i| set(seed).bits(i));
        println!(
            "N=256: pool unshifted {:.3} ({:.3}), digitally shifted {:.3} ({:.3}), \
             Owen-scrambled {:.3} ({:.3})",
            unshifted.0, unshifted.1, shifted.0, shifted.1, owen.0, owen.1
        );
        assert!(shifted.0 > owen.0 + 0.05, "{shifted:?} {owen:?}");
    }

    /// Why the randomisation is a digital shift and not a toroidal one: a
    /// translation by a multiple of `2^-k` (`k >= 2`) keeps every distance
    /// but breaks the nets, because elementary intervals wider than `2^-k`
    /// straddle the shifted cut; a translation by `1/2` (which is the xor
    /// of the first digit) keeps both; a digital shift keeps the nets.
    #[test]
    fn translations_break_the_nets_digital_shifts_keep_them() {
        let n = 1u32 << checks::MAX_M;
        let prefixes_are_nets = |bits: &dyn Fn(u32) -> [u32; 2]| {
            (0..=checks::MAX_M).all(|m| checks::first_non_net(1 << m, bits).is_none())
        };
        let mut rng = Rng::new(12);
        for seed in 0..8 {
            let s = set(seed);
            let base: Vec<[u32; 2]> = (0..n).map(|i| s.bits(i)).collect();
            for k in 2..=12 {
                let (a, b) = (rng.next_u32() >> k | 1, rng.next_u32() >> k);
                let shift = [a << (32 - k), b << (32 - k)];
                let moved = |i: u32| {
                    let [x, y] = base[i as usize];
                    [x.wrapping_add(shift[0]), y.wrapping_add(shift[1])]
                };
                assert!(
                    !prefixes_are_nets(&moved),
                    "seed {seed}: shift by {a}/2^{k} kept the nets"
                );
            }
            let half = |i: u32| {
                let [x, y] = base[i as usize];
                [x.wrapping_add(1 << 31), y]
            };
            assert!(prefixes_are_nets(&half));
            let (cx, cy) = (rng.next_u32(), rng.next_u32());
            let xored = |i: u32| {
                let [x, y] = base[i as usize];
                [x ^ cx, y ^ cy]
            };
            assert!(prefixes_are_nets(&xored));
        }
    }
}
