//! `r2` as a distribution: Roberts' R2 sequence, shifted, from
//! [`sampling::r2`](crate::sampling::r2), which holds its
//! construction, its guarantees and their tests; a set of `N` is its
//! first `N` points in the set's trace order (see
//! [Trace order](super#trace-order)).

use crate::math::{Vec2, Vec3};
pub(super) use crate::sampling::r2::R2;
use crate::sampling::{Place, PointTable, Rng};

use super::model::{padded, sequence, square, values, DistributionModel};

impl DistributionModel for R2 {
    const NAME: &'static str = "r2";
    const SEQUENCE: bool = true;

    fn generate(_: &PointTable, count: usize, radius: f32, rng: &mut Rng, out: &mut Vec<Vec3>) {
        sequence(count, radius, rng, out, R2::new, R2::point);
    }

    fn one(_: &PointTable, radius: f32, rng: &mut Rng) -> Vec3 {
        square(R2::new(rng).point(0), radius)
    }

    fn generate_1d(_: &PointTable, count: usize, rng: &mut Rng, out: &mut Vec<f32>) {
        values(count, rng, out, R2::new, R2::value);
    }

    #[inline]
    fn bounce_value(place: Place) -> f32 {
        let (set, i) = padded(place, R2::new);
        set.value(i)
    }

    #[inline]
    fn bounce_point(place: Place) -> Vec2 {
        let (set, i) = padded(place, R2::new);
        set.point(i)
    }
}
