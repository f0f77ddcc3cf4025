//! `grid`: the centres of an `s x s` grid of equal cells over the square
//! (`s = sqrt(count)`), the thesis's Listing 3.2. Deterministic up to the
//! trace order: every set is the same pattern, which is why it can show
//! Moiré patterns and banded penumbras. Guarantee: the points are exactly
//! the cell centres, `r * ((2i + 1) / s - 1)` per axis; with one point,
//! the centre `(0, 0)`: the original ray of classic ray tracing. Shutter
//! times are the strata's centres, `(i + 0.5) / n`.
//!
//! The thesis's listing produces the same cell centres as we do (from `+r`
//! down to `-r`, row index `i / s` on `u`, column `i mod s` on `v`; the
//! order is irrelevant after shuffling). Its loop
//! `FOR i = 0 TO i = desiredNumOfRays` read literally runs `N + 1` times; we
//! generate exactly `N`.

use crate::math::{Vec2, Vec3};
use crate::sampling::{PointTable, Rng};

use super::cells::{cells, cells_unordered, cells_unordered_part, strata_1d};
use super::model::{square, DistributionModel};

/// The `grid` distribution; see the [module docs](self).
#[derive(Clone, Copy, Debug)]
pub struct Grid;

/// The grid's offset within its cell: the centre.
fn centre(_: &mut Rng) -> Vec2 {
    Vec2::splat(0.5)
}

impl DistributionModel for Grid {
    const NAME: &'static str = "grid";
    const THESIS: bool = true;
    const NEEDS_SQUARE_COUNT: bool = true;

    fn generate(_: &PointTable, count: usize, radius: f32, rng: &mut Rng, out: &mut Vec<Vec3>) {
        cells(count, radius, rng, out, centre);
    }

    fn one(_: &PointTable, radius: f32, rng: &mut Rng) -> Vec3 {
        // The one cell is the whole square: `(0 + offset) / 1 = offset`.
        square(centre(rng), radius)
    }

    fn generate_unordered(
        _: &PointTable,
        count: usize,
        radius: f32,
        rng: &mut Rng,
        out: &mut Vec<Vec3>,
    ) {
        cells_unordered(count, radius, rng, out, centre);
    }

    fn generate_unordered_part(
        _: &PointTable,
        count: usize,
        radius: f32,
        rng: &mut Rng,
        part: std::ops::Range<usize>,
        out: &mut Vec<Vec3>,
    ) -> bool {
        cells_unordered_part((count, radius), rng, part, out, (centre, 0))
    }

    fn generate_1d(_: &PointTable, count: usize, rng: &mut Rng, out: &mut Vec<f32>) {
        strata_1d(count, rng, out, |_| 0.5);
    }
}

#[cfg(test)]
mod tests {
    use super::super::testing::gen;
    use super::super::Distribution;
    use crate::math::Vec3;

    #[test]
    fn grid_of_one_is_the_centre() {
        for r in [0.1, 1.0, 3.7] {
            for seed in 0..5 {
                assert_eq!(gen(Distribution::Grid, 1, r, seed), vec![Vec3::ZERO]);
            }
        }
    }
}
