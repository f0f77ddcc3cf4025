//! The random streams of a render, fixed in one place: every value is a pure
//! function of (seed, pixel, sample index, dimension), so an image is the
//! same on any number of threads, tiles or machines, and one sample can be
//! replayed alone.
//!
//! | stream | derived as |
//! |---|---|
//! | pixel `p` | `Rng::new(seed).at_pixel(p, (x, y))`, `p = y · width + x` |
//! | film, lens, time sets of the pixel | `pixel.derive(0)`, `.derive(1)`, `.derive(2)` ([`Dimension`]) |
//! | path of primary sample `i` of `n` | `pixel.sibling(3 + i, i, ⌈log2 n⌉)` |
//! | replica `r` of the pixel (adaptive sampling's calibrated rule), all of whose streams derive from it as the pixel's do, with `⌈n / R⌉` paths | `pixel.derive(2^32 + r)` |
//!
//! `at_pixel` and `sibling` give the keys `derive(p)` and `derive(3 + i)`
//! would; they also record the stream's place in the frame (see
//! [`Rng`](super::Rng)'s docs), which `zsobol` reads.
//!
//! Below a path, the integrator derives the streams of each event's set of
//! rays from the path's stream (see the integrator's documentation).

use super::{index_bits, BranchKey, Distribution, PointTable, Rng};
use crate::math::Vec3;

/// The sets of a pixel drawn from its own streams, one per dimension of the
/// camera sample.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dimension {
    /// Positions on the film within the pixel (supersampling).
    Film = 0,
    /// Points of the lens (depth of field).
    Lens = 1,
    /// Times in the shutter interval (motion blur).
    Time = 2,
}

/// The first branch number of the primary samples' paths.
const FIRST_PATH: u64 = 3;

/// The branch number of a pixel's first replica (far above every path's).
const FIRST_REPLICA: u64 = 1 << 32;

/// The streams of a render with a given seed and image width, whose pixels
/// have (at most) `paths` primary samples.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Sampler {
    seed: u64,
    width: u32,
    paths: u32,
}

impl Sampler {
    pub fn new(seed: u64, width: u32, paths: u32) -> Sampler {
        Sampler { seed, width, paths }
    }

    /// The streams of pixel (x, y).
    pub fn pixel(&self, x: u32, y: u32) -> PixelSampler {
        let index = u64::from(y) * u64::from(self.width) + u64::from(x);
        PixelSampler {
            root: Rng::new(self.seed).at_pixel(index, (x, y)),
            path_bits: index_bits(self.paths as usize),
        }
    }
}

/// The streams of one pixel.
#[derive(Clone, Copy, Debug)]
pub struct PixelSampler {
    root: Rng,
    /// The bits of a primary sample's number.
    path_bits: u32,
}

impl PixelSampler {
    /// Replica `r` of `replicas` of the pixel: streams independent of the
    /// pixel's own and of every other replica's, each set an independent
    /// scrambling, with a share `⌈n / replicas⌉` of the pixel's paths.
    pub fn replica(&self, r: u32, replicas: u32) -> PixelSampler {
        let paths = (1usize << self.path_bits).div_ceil(replicas.max(1) as usize);
        PixelSampler {
            root: self.root.derive(FIRST_REPLICA + u64::from(r)),
            path_bits: index_bits(paths),
        }
    }

    /// The stream of a dimension's set.
    pub fn stream(&self, d: Dimension) -> Rng {
        self.root.derive(d as u64)
    }

    /// The `count` points of a dimension's set from `distribution` (with
    /// `custom`'s points from `table`) within `radius`, into `out`: in
    /// shuffled trace order if `ordered` (a metric may stop the set early),
    /// else in the distribution's own order.
    pub fn points(
        &self,
        d: Dimension,
        (distribution, table): (Distribution, &PointTable),
        count: usize,
        radius: f32,
        ordered: bool,
        out: &mut Vec<Vec3>,
    ) {
        let mut rng = self.stream(d);
        if ordered {
            distribution.generate_in(table, count, radius, &mut rng, out);
        } else {
            distribution.generate_unordered_in(table, count, radius, &mut rng, out);
        }
    }

    /// Points `part` of the unordered set [`points`](Self::points) makes,
    /// into `out`, made alone where the distribution can; `false`, `out`
    /// emptied, where it cannot (the caller then makes the whole set).
    pub fn points_part(
        &self,
        d: Dimension,
        (distribution, table): (Distribution, &PointTable),
        (count, radius): (usize, f32),
        part: std::ops::Range<usize>,
        out: &mut Vec<Vec3>,
    ) -> bool {
        let mut rng = self.stream(d);
        distribution.generate_unordered_part_in(table, (count, radius), &mut rng, part, out)
    }

    /// The `count` values in [0, 1) of a one-dimensional set (times).
    pub fn values(
        &self,
        d: Dimension,
        (distribution, table): (Distribution, &PointTable),
        count: usize,
        out: &mut Vec<f32>,
    ) {
        distribution.generate_1d_in(table, count, &mut self.stream(d), out);
    }

    /// The branch of primary sample `i`'s path; hashed once, it can be kept
    /// (see [`path_of`](Self::path_of)).
    pub fn path_key(i: usize) -> BranchKey {
        BranchKey::new(FIRST_PATH + i as u64)
    }

    /// The stream of the path of primary sample `i`.
    pub fn path(&self, i: usize) -> Rng {
        self.path_of(Self::path_key(i), i)
    }

    /// The stream of the path of primary sample `i`, whose branch is `key`
    /// (from [`path_key`](Self::path_key)).
    #[inline]
    pub fn path_of(&self, key: BranchKey, i: usize) -> Rng {
        self.root.sibling(key, i as u64, self.path_bits)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The streams are the documented derivations, and distinct pixels,
    /// dimensions and paths give distinct streams.
    #[test]
    fn streams_are_the_documented_ones() {
        let s = Sampler::new(7, 640, 16);
        let p = s.pixel(5, 3);
        let root = Rng::new(7).derive(3 * 640 + 5);
        assert_eq!(p.path(6).place().index(), 0b11011 << 4 | 0b0110);
        let first = |mut r: Rng| r.next_u64();
        assert_eq!(first(p.stream(Dimension::Film)), first(root.derive(0)));
        assert_eq!(first(p.stream(Dimension::Time)), first(root.derive(2)));
        assert_eq!(first(p.path(4)), first(root.derive(7)));
        assert_eq!(
            first(p.path_of(PixelSampler::path_key(4), 4)),
            first(p.path(4))
        );
        let replica = root.derive((1 << 32) + 2);
        assert_eq!(first(p.replica(2, 8).path(0)), first(replica.derive(3)));
        assert_eq!(p.replica(2, 8).path(1).place().index(), 0b11011 << 1 | 1);
        let mut seen = std::collections::HashSet::new();
        for (x, y) in [(0, 0), (1, 0), (0, 1)] {
            let p = s.pixel(x, y);
            for d in [Dimension::Film, Dimension::Lens, Dimension::Time] {
                assert!(seen.insert(first(p.stream(d))));
            }
            for i in 0..8 {
                assert!(seen.insert(first(p.path(i))));
                assert!(seen.insert(first(p.replica(i as u32, 8).path(0))));
            }
        }
    }
}
