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

/// Where a stream's sets sit in the frame's shared sequence; see [its
/// place in the frame](Rng#its-place-in-the-frame).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Place {
    /// The key of the kinds of branches taken (pixel- and index-free).
    pub dimension: u64,
    /// The pixel, `x` in the low 32 bits and `y` in the high ones.
    pixel: u64,
    /// The numbers of the siblings taken below the pixel.
    local: u64,
    /// How many bits `local` holds.
    pub local_bits: u32,
}

impl Place {
    /// The index: the pixel's Morton code followed by the `local_bits` bits
    /// of the siblings' numbers.
    pub fn index(&self) -> u128 {
        let morton = morton(self.pixel as u32, (self.pixel >> 32) as u32);
        u128::from(morton) << self.local_bits | u128::from(self.local)
    }

    /// The pixel, `x` in the low 32 bits and `y` in the high ones.
    pub fn pixel_code(&self) -> u64 {
        self.pixel
    }

    /// The siblings' numbers below the pixel: their low 32 bits, and the
    /// bits above.
    pub fn local_parts(&self) -> (u32, u64) {
        (self.local as u32, self.local >> 32)
    }
}

/// The Morton code of (x, y): the bits of `x` at the even positions, those
/// of `y` at the odd ones.
pub fn morton(x: u32, y: u32) -> u64 {
    fn spread(v: u32) -> u64 {
        let mut v = u64::from(v);
        v = (v | (v << 16)) & 0x0000_ffff_0000_ffff;
        v = (v | (v << 8)) & 0x00ff_00ff_00ff_00ff;
        v = (v | (v << 4)) & 0x0f0f_0f0f_0f0f_0f0f;
        v = (v | (v << 2)) & 0x3333_3333_3333_3333;
        (v | (v << 1)) & 0x5555_5555_5555_5555
    }
    spread(x) | spread(y) << 1
}

/// A stream of random numbers identified by a key: the n-th value is a
/// hash of (key, n), and [`derive`](Rng::derive) makes a sub-stream's key
/// from its parent's and a branch number.
///
/// # Its place in the frame
///
/// Beside its key, a stream keeps where its sets sit in a sequence shared by
/// the whole frame, for distributions whose sets are blocks of one sequence
/// rather than sets scrambled apart (`zsobol`, after pbrt-v4's sampler of
/// that name):
///
/// * its **dimension**: a key of the *kinds* of branches taken from the seed
///   ([`derive`](Rng::derive), [`derive_key`](Rng::derive_key): the film set,
///   light `j`'s shadow set, a glossy set), but not of pixels or numbered
///   siblings, so it is the same in every pixel and for every sample;
/// * its **index**: the pixel's Morton code ([`at_pixel`](Rng::at_pixel)),
///   followed by the numbers of the siblings taken below the pixel
///   ([`sibling`](Rng::sibling): sample `i` of the pixel, ray `k` of a set),
///   each in as many bits as its count needs; and how many of the index's
///   bits lie below the pixel's code.
///
/// Neither changes the stream's key, so the values drawn are the same with
/// or without them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rng {
    key: u64,
    counter: u64,
    place: Place,
}

impl Rng {
    /// The root stream of a seed.
    pub fn new(seed: u64) -> Self {
        let key = mix64(seed ^ 0x5eed_0000_0000_0000);
        Rng {
            key,
            counter: 0,
            place: Place {
                dimension: key,
                pixel: 0,
                local: 0,
                local_bits: 0,
            },
        }
    }

    /// An independent sub-stream for `branch` (a sample index, a dimension,
    /// the k-th reflection ray...). Deriving does not advance `self`, so
    /// sub-streams do not shift each other. The branch counts as a kind of
    /// branch ([`Place::dimension`]); [`sibling`](Self::sibling) derives a
    /// numbered one.
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
            place: Place {
                // The branch key is a hash already: rotating and xor-ing
                // keeps the order of the kinds at the cost of two
                // instructions (it is hashed again where it is used).
                dimension: self.place.dimension.rotate_left(23) ^ branch.0,
                ..self.place
            },
        }
    }

    /// The stream of pixel (x, y), number `pixel` in row-major order: the
    /// key as [`derive`](Self::derive)`(pixel)` gives it, the dimension
    /// unchanged and the index the pixel's Morton code.
    pub fn at_pixel(&self, pixel: u64, (x, y): (u32, u32)) -> Rng {
        Rng {
            key: mix64(self.key ^ BranchKey::new(pixel).0),
            counter: 0,
            place: Place {
                dimension: self.place.dimension,
                pixel: u64::from(x) | u64::from(y) << 32,
                local: 0,
                local_bits: 0,
            },
        }
    }

    /// The sub-stream of sibling `index` of `2^bits` (sample `i` of a pixel,
    /// ray `k` of a set) whose branch is `key`: the key as
    /// [`derive_key`](Self::derive_key) gives it, the dimension unchanged
    /// and the index extended by `bits` bits holding `index`. Should the
    /// siblings' numbers outgrow 64 bits, those so far are hashed into the
    /// dimension and the count starts again, so distinct places stay
    /// distinct.
    #[inline]
    pub fn sibling(&self, key: BranchKey, index: u64, bits: u32) -> Rng {
        let mut place = self.place;
        if place.local_bits + bits > 64 {
            place.dimension = mix64(place.dimension ^ mix64(place.local));
            place.local = 0;
            place.local_bits = 0;
        }
        place.local = place.local.wrapping_shl(bits) | index;
        place.local_bits += bits;
        Rng {
            key: mix64(self.key ^ key.0),
            counter: 0,
            place,
        }
    }

    /// Sibling `k` of `count`, on branch `k`: ray `k` of a set of `count`.
    #[inline]
    pub fn child(&self, k: usize, count: usize) -> Rng {
        self.sibling(BranchKey::new(k as u64), k as u64, index_bits(count))
    }

    /// The stream's place in the frame's shared sequence.
    #[inline]
    pub fn place(&self) -> Place {
        self.place
    }

    /// Skips the next `n` values: the stream then gives what it would
    /// after `n` draws.
    #[inline]
    pub fn skip(&mut self, n: u64) {
        self.counter = self.counter.wrapping_add(n);
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

/// The bits an index below `count` needs: `⌈log2 count⌉` (0 for 0 and 1).
#[inline]
pub fn index_bits(count: usize) -> u32 {
    count.max(1).next_power_of_two().trailing_zeros()
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

    /// The place follows the documented rules, and never changes a key.
    #[test]
    fn places_follow_kinds_and_siblings() {
        let root = Rng::new(7);
        let p = root.at_pixel(41, (3, 2));
        assert_eq!(morton(3, 2), 0b1101);
        assert_eq!(p.key, root.derive(41).key);
        assert_eq!(p.place().dimension, root.place().dimension);
        let a = p.derive(2).child(3, 5).derive(9);
        assert_eq!(a.key, p.derive(2).derive(3).derive(9).key);
        let q = Rng::new(7)
            .at_pixel(12, (2, 1))
            .derive(2)
            .child(1, 8)
            .derive(9);
        // Same kinds, other pixel and sibling: same dimension, other index.
        assert_eq!(a.place().dimension, q.place().dimension);
        assert_eq!(a.place().index(), 0b1101 << 3 | 0b011);
        assert_eq!(a.place().local_bits, 3);
        assert_eq!(q.place().index(), 0b0110 << 3 | 0b001);
        assert_ne!(a.place().dimension, p.derive(3).place().dimension);
        assert_ne!(
            p.derive(2).derive(9).place().dimension,
            p.derive(9).derive(2).place().dimension
        );
        assert_eq!((index_bits(0), index_bits(1), index_bits(5)), (0, 0, 3));
        // Past 64 bits of siblings, their numbers go into the dimension.
        let deep = |k| {
            (0..9).fold(Rng::new(1).at_pixel(0, (0, 0)).child(k, 256), |r, _| {
                r.child(0, 256)
            })
        };
        assert_eq!(deep(1).place().index(), deep(2).place().index());
        assert_ne!(deep(1).place().dimension, deep(2).place().dimension);
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
