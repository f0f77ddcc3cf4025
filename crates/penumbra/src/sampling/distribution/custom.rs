//! `custom`: the user's point sets, from a [`PointTable`] (see
//! [`sampling::custom`](crate::sampling::custom) for how a ray set is drawn
//! from them); without a table, independent uniform points.

use crate::math::{Vec2, Vec3};
use crate::sampling::{PointTable, Rng};

use super::model::{shuffle, square, DistributionModel};

/// The `custom` distribution: the user's own points, from a
/// [`PointTable`]; see the [module docs](crate::sampling::custom). Not in
/// [`Distribution::ALL`](super::Distribution::ALL), since it needs a table.
#[derive(Clone, Copy, Debug)]
pub struct Custom;

impl DistributionModel for Custom {
    const NAME: &'static str = "custom";
    const NEEDS_TABLE: bool = true;

    fn generate(table: &PointTable, count: usize, radius: f32, rng: &mut Rng, out: &mut Vec<Vec3>) {
        table.fill(count, rng, |p| out.push(square(p, radius)));
        shuffle(out, rng);
    }

    fn one(table: &PointTable, radius: f32, rng: &mut Rng) -> Vec3 {
        let mut point = Vec2::ZERO;
        table.fill(1, rng, |p| point = p);
        square(point, radius)
    }

    fn generate_1d(table: &PointTable, count: usize, rng: &mut Rng, out: &mut Vec<f32>) {
        table.fill(count, rng, |p| out.push(p.x));
        shuffle(out, rng);
    }
}
