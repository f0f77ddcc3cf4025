//! `pmj02` as a distribution: a progressive multi-jittered (0,2) sequence, from
//! [`sampling::pmj02`](crate::sampling::pmj02), which holds its
//! construction, its guarantees and their tests; a set of `N` is its
//! first `N` points in its own order, an Owen scramble of the index per
//! set (see [Trace order](super#trace-order)).

use crate::math::{Vec2, Vec3};
pub(super) use crate::sampling::pmj02::Pmj02;
use crate::sampling::{Place, PointTable, Rng};

use super::model::{padded, square, DistributionModel};

impl DistributionModel for Pmj02 {
    const NAME: &'static str = "pmj02";
    const SEQUENCE: bool = true;
    const ALIASES: &'static [&'static str] = &["pmj"];

    fn generate(_: &PointTable, count: usize, radius: f32, rng: &mut Rng, out: &mut Vec<Vec3>) {
        // Its order is its own: an Owen scramble of the index per
        // set, which pairs sets independently already.
        let set = Pmj02::new(rng);
        out.extend((0..count).map(|i| square(set.point(i as u32), radius)));
    }

    fn one(_: &PointTable, radius: f32, rng: &mut Rng) -> Vec3 {
        square(Pmj02::new(rng).point(0), radius)
    }

    fn generate_1d(_: &PointTable, count: usize, rng: &mut Rng, out: &mut Vec<f32>) {
        let set = Pmj02::new(rng);
        out.extend((0..count).map(|i| set.value(i as u32)));
    }

    #[inline]
    fn bounce_value(place: Place) -> f32 {
        let (set, i) = padded(place, Pmj02::new);
        set.value(i)
    }

    #[inline]
    fn bounce_point(place: Place) -> Vec2 {
        let (set, i) = padded(place, Pmj02::new);
        set.point(i)
    }
}
