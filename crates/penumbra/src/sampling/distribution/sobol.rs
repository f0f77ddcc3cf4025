//! `sobol` as a distribution: the first two dimensions of Owen-scrambled Sobol' points, from
//! [`sampling::sobol`](crate::sampling::sobol), which holds its
//! construction, its guarantees and their tests; a set of `N` is its
//! first `N` points in the set's trace order (see
//! [Trace order](super#trace-order)).

use crate::math::Vec3;
pub(super) use crate::sampling::sobol::Sobol;
use crate::sampling::{PointTable, Rng};

use super::model::{sequence, square, values, DistributionModel};

impl DistributionModel for Sobol {
    const NAME: &'static str = "sobol";
    const SEQUENCE: bool = true;
    const ALIASES: &'static [&'static str] = &["owen-sobol"];

    fn generate(_: &PointTable, count: usize, radius: f32, rng: &mut Rng, out: &mut Vec<Vec3>) {
        sequence(count, radius, rng, out, Sobol::new, Sobol::point);
    }

    fn one(_: &PointTable, radius: f32, rng: &mut Rng) -> Vec3 {
        square(Sobol::new(rng).point(0), radius)
    }

    fn generate_1d(_: &PointTable, count: usize, rng: &mut Rng, out: &mut Vec<f32>) {
        values(count, rng, out, Sobol::new, Sobol::value);
    }
}
