//! What every distribution implements ([`DistributionModel`]), and the
//! pieces of sets they share: the shuffle into trace order, scaling to the
//! radius, the trace order of the low-discrepancy sequences.

use crate::math::{Vec2, Vec3};
use crate::sampling::custom::PointTable;
use crate::sampling::order::TraceOrder;
use crate::sampling::sobol::{owen_scramble, Sobol};
use crate::sampling::{mix64, Place, Rng};

/// Where the points of a distribution of radius `r` lie.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Domain {
    /// The square `[-r, r]^2`, `z = 0`: 2D points for a frame around the ray.
    Square,
    /// The disk of radius `r`, `z = 0` (`random`).
    Disk,
    /// The cube `[-r, r]^3`: 3D offsets added in world axes, without a
    /// frame (`fast-random`).
    Cube,
}

/// What every distribution answers (see the [module docs](super)). The
/// methods fill a set for [`Distribution`](super::Distribution), which clears the buffer and
/// handles a count of 0 before it asks.
pub trait DistributionModel {
    /// The kebab-case name users write (the serde name too).
    const NAME: &'static str;

    /// Other names it is selected by (after lower-casing and `_` → `-`).
    const ALIASES: &'static [&'static str] = &[];

    /// One of the thesis's six.
    const THESIS: bool = false;

    /// Its points come from the user's table (`custom`): not in
    /// [`Distribution::ALL`](super::Distribution::ALL).
    const NEEDS_TABLE: bool = false;

    /// Where its points lie: the square unless it says otherwise.
    const DOMAIN: Domain = Domain::Square;

    /// It is a sequence a [`PathSampler`](crate::sampling::PathSampler)
    /// may draw the numbers of a path's bounces from (see
    /// [`bounce_value`](Self::bounce_value)).
    const SEQUENCE: bool = false;

    /// It has one point per grid cell, and so fills its pattern for square
    /// counts only (grid, jitter, semi-jitter).
    const NEEDS_SQUARE_COUNT: bool = false;

    /// Appends `count ≥ 1` points to the empty `out`, in trace order (see
    /// [`Distribution::generate_in`](super::Distribution::generate_in)).
    fn generate(table: &PointTable, count: usize, radius: f32, rng: &mut Rng, out: &mut Vec<Vec3>);

    /// The one point of a set of one: the bits [`generate`](Self::generate)
    /// gives for `count = 1`, with the same draws.
    fn one(table: &PointTable, radius: f32, rng: &mut Rng) -> Vec3;

    /// Points `part` of the set [`generate_unordered`](Self::generate_unordered)
    /// makes of `count` (its points `part.start..part.end`, the same bits),
    /// into the empty `out`, without making the others; `false`, `out` and
    /// `rng` untouched, for a set whose points cannot be made apart.
    #[inline]
    fn generate_unordered_part(
        _table: &PointTable,
        _count: usize,
        _radius: f32,
        _rng: &mut Rng,
        _part: std::ops::Range<usize>,
        _out: &mut Vec<Vec3>,
    ) -> bool {
        false
    }

    /// [`generate`](Self::generate) for a set whose order cannot matter,
    /// into the empty `out` (`count` may be 0): by default the same.
    #[inline]
    fn generate_unordered(
        table: &PointTable,
        count: usize,
        radius: f32,
        rng: &mut Rng,
        out: &mut Vec<Vec3>,
    ) {
        if count > 0 {
            Self::generate(table, count, radius, rng, out);
        }
    }

    /// Appends `count ≥ 1` shutter times in `[0, 1)` to the empty `out`, in
    /// trace order (see [`Distribution::generate_1d_in`](super::Distribution::generate_1d_in)).
    fn generate_1d(table: &PointTable, count: usize, rng: &mut Rng, out: &mut Vec<f32>);

    /// As a path sampler ([`PathSampler`](crate::sampling::PathSampler)):
    /// the value of the dimension whose stream is at `place`. A sequence
    /// answers from its set scrambled for the pixel and the dimension, with
    /// the samples' order shuffled (pbrt-v4's padded samplers); the others,
    /// which a path sampler never holds, answer as `sobol`.
    #[inline]
    fn bounce_value(place: Place) -> f32 {
        let (set, i) = padded(place, Sobol::new);
        set.value(i)
    }

    /// As [`bounce_value`](Self::bounce_value), the point of a dimension
    /// pair.
    #[inline]
    fn bounce_point(place: Place) -> Vec2 {
        let (set, i) = padded(place, Sobol::new);
        set.point(i)
    }
}

/// A path sampler's set of one dimension (`place`, the stream of the
/// dimension) drawn by `set`, and the index of this path's point in it.
#[inline]
pub(in crate::sampling) fn padded<S>(place: Place, set: impl FnOnce(&mut Rng) -> S) -> (S, u32) {
    // The scramble: the kind of branches and the pixel, with whatever
    // part of the index does not fit in 32 bits.
    let (index, high) = place.local_parts();
    let mut rng = Rng::new(mix64(place.dimension ^ mix64(place.pixel_code() ^ high)));
    let set = set(&mut rng);
    // The samples' order, shuffled per dimension (pbrt-v4's padded
    // samplers): the same index in every dimension would tie the
    // dimensions' points to one another. The shuffle maps the first
    // 2^m indices onto an aligned block of 2^m, which keeps a prefix
    // of a (0,2)-sequence a net.
    (set, owen_scramble(index, rng.next_u32()))
}

/// Shuffles `items` uniformly (Fisher–Yates): every permutation is equally
/// likely, so no position in a ray set is favoured by early termination.
pub fn shuffle<T>(items: &mut [T], rng: &mut Rng) {
    for i in (1..items.len()).rev() {
        let j = index_below(rng, i + 1);
        items.swap(i, j);
    }
}

/// The side `s = ceil(sqrt(count))` of the smallest square grid with at
/// least `count` cells (0 for 0), computed exactly in integers.
pub fn square_side(count: usize) -> usize {
    let s = count.isqrt();
    if s.checked_mul(s) == Some(count) {
        s
    } else {
        s + 1
    }
}

/// Uniform index in `[0, n)`, `n >= 1`; unbiased for `n < 2^32`, which covers
/// any realistic ray set.
pub(in crate::sampling) fn index_below(rng: &mut Rng, n: usize) -> usize {
    match u32::try_from(n) {
        Ok(n) => rng.below(n) as usize,
        Err(_) => (rng.next_u64() % n as u64) as usize,
    }
}

/// A point uniform in `[0, 1)^2`: two draws, x first.
pub(in crate::sampling) fn unit_square(rng: &mut Rng) -> Vec2 {
    let x = rng.next_f32();
    Vec2::new(x, rng.next_f32())
}

/// Maps `t` in `[0, 1]` to `[-r, r]`. Written as `r * (2t - 1)` because every
/// step is monotone under rounding, so the result never leaves `[-|r|, |r|]`.
#[inline]
pub(in crate::sampling) fn to_radius(t: f32, radius: f32) -> f32 {
    radius * (2.0 * t - 1.0)
}

/// A point of `[0, 1)^2` scaled to `[-r, r]^2`.
pub(in crate::sampling) fn square(p: Vec2, radius: f32) -> Vec3 {
    Vec3::new(to_radius(p.x, radius), to_radius(p.y, radius), 0.0)
}

/// The first `count` points of a low-discrepancy set (made from `rng` by
/// `set`), in its trace order ([`TraceOrder`], drawn from `rng` after the
/// set), scaled to `[-r, r]^2`.
pub(in crate::sampling) fn sequence<S>(
    count: usize,
    radius: f32,
    rng: &mut Rng,
    out: &mut Vec<Vec3>,
    set: impl FnOnce(&mut Rng) -> S,
    point: impl Fn(&S, u32) -> Vec2,
) {
    values(count, rng, out, set, |s, i| square(point(s, i), radius));
}

/// The first `count` values of a low-discrepancy set (its points, or its
/// one-dimensional sequence's values), in its trace order.
pub(in crate::sampling) fn values<S, T>(
    count: usize,
    rng: &mut Rng,
    out: &mut Vec<T>,
    set: impl FnOnce(&mut Rng) -> S,
    value: impl Fn(&S, u32) -> T,
) {
    let set = set(rng);
    let order = TraceOrder::new(count, rng);
    out.extend((0..count).map(|i| value(&set, order.index(i as u32))));
}

/// The largest `f32` below 1: keeps `[0, 1)` half-open under rounding.
pub(in crate::sampling) const ONE_BELOW: f32 = 1.0 - f32::EPSILON / 2.0;
