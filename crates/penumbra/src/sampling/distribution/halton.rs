//! `halton` as a distribution: the Halton sequence in bases 2 and 3, digit-permuted, from
//! [`sampling::halton`](crate::sampling::halton), which holds its
//! construction, its guarantees and their tests; a set of `N` is its
//! first `N` points in the set's trace order (see
//! [Trace order](super#trace-order)).

use crate::math::{Vec2, Vec3};
pub(super) use crate::sampling::halton::Halton;
use crate::sampling::{Place, PointTable, Rng};

use super::model::{padded, sequence, square, values, DistributionModel};

impl DistributionModel for Halton {
    const NAME: &'static str = "halton";
    const SEQUENCE: bool = true;

    fn generate(_: &PointTable, count: usize, radius: f32, rng: &mut Rng, out: &mut Vec<Vec3>) {
        sequence(count, radius, rng, out, Halton::new, Halton::point);
    }

    fn one(_: &PointTable, radius: f32, rng: &mut Rng) -> Vec3 {
        square(Halton::new(rng).point(0), radius)
    }

    fn generate_1d(_: &PointTable, count: usize, rng: &mut Rng, out: &mut Vec<f32>) {
        values(count, rng, out, Halton::new, Halton::value);
    }

    #[inline]
    fn bounce_value(place: Place) -> f32 {
        let (set, i) = padded(place, Halton::new);
        set.value(i)
    }

    #[inline]
    fn bounce_point(place: Place) -> Vec2 {
        let (set, i) = padded(place, Halton::new);
        set.point(i)
    }
}
