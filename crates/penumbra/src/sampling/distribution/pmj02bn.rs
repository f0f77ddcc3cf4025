//! `pmj02bn` as a distribution: pmj02 with blue noise, from
//! [`sampling::pmj02bn`](crate::sampling::pmj02bn), which holds its
//! construction, its guarantees and their tests; a set of `N` is its
//! first `N` points in the set's trace order (see
//! [Trace order](super#trace-order)).

use crate::math::{Vec2, Vec3};
pub(super) use crate::sampling::pmj02bn::Pmj02bn;
use crate::sampling::{Place, PointTable, Rng};

use super::model::{padded, sequence, square, values, DistributionModel};

impl DistributionModel for Pmj02bn {
    const NAME: &'static str = "pmj02bn";
    const SEQUENCE: bool = true;

    fn generate(_: &PointTable, count: usize, radius: f32, rng: &mut Rng, out: &mut Vec<Vec3>) {
        sequence(count, radius, rng, out, Pmj02bn::new, Pmj02bn::point);
    }

    fn one(_: &PointTable, radius: f32, rng: &mut Rng) -> Vec3 {
        square(Pmj02bn::new(rng).point(0), radius)
    }

    fn generate_1d(_: &PointTable, count: usize, rng: &mut Rng, out: &mut Vec<f32>) {
        values(count, rng, out, Pmj02bn::new, Pmj02bn::value);
    }

    #[inline]
    fn bounce_value(place: Place) -> f32 {
        let (set, i) = padded(place, Pmj02bn::new);
        set.value(i)
    }

    #[inline]
    fn bounce_point(place: Place) -> Vec2 {
        let (set, i) = padded(place, Pmj02bn::new);
        set.point(i)
    }
}
