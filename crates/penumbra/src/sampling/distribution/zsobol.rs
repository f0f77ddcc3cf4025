//! `zsobol` as a distribution: Morton-ordered Sobol' points, blocks of one sequence over the frame, from
//! [`sampling::zsobol`](crate::sampling::zsobol), which holds its
//! construction, its guarantees and their tests; a set of `N` is its
//! first `N` points in the set's trace order (see
//! [Trace order](super#trace-order)).

use crate::math::{Vec2, Vec3};
pub(super) use crate::sampling::zsobol::ZSobol;
use crate::sampling::{Place, PointTable, Rng};

use super::model::{sequence, square, values, DistributionModel};

impl DistributionModel for ZSobol {
    const NAME: &'static str = "zsobol";
    const SEQUENCE: bool = true;
    const ALIASES: &'static [&'static str] = &["z-sobol"];

    fn generate(_: &PointTable, count: usize, radius: f32, rng: &mut Rng, out: &mut Vec<Vec3>) {
        let set = |rng: &mut Rng| ZSobol::new(rng.place(), count);
        sequence(count, radius, rng, out, set, ZSobol::point);
    }

    fn one(_: &PointTable, radius: f32, rng: &mut Rng) -> Vec3 {
        square(ZSobol::new(rng.place(), 1).point(0), radius)
    }

    fn generate_1d(_: &PointTable, count: usize, rng: &mut Rng, out: &mut Vec<f32>) {
        let set = |rng: &mut Rng| ZSobol::new(rng.place(), count);
        values(count, rng, out, set, ZSobol::value);
    }

    /// The pixel's block of the frame's sequence: point `i` of the set of
    /// one at the place of sample `i`.
    #[inline]
    fn bounce_value(place: Place) -> f32 {
        ZSobol::new(place, 1).value(0)
    }

    #[inline]
    fn bounce_point(place: Place) -> Vec2 {
        ZSobol::new(place, 1).point(0)
    }
}
