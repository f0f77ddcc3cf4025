//! `jitter`: one point uniformly distributed over the whole of each cell of
//! an `s x s` grid (stratified sampling). Guarantee: exactly one point per
//! cell, and the union of all cells is covered uniformly; with one point,
//! one point uniform over the square. Shutter times: `(i + u) / n`.
//!
//! The thesis's Listing 3.4 adds `(RND()*2-1) * radius/(sqrtOfNumRays*2)`
//! to the cell centre: an offset in `[-r/(2s), r/(2s)]`, a square of side
//! `r/s`, which is *half* the cell side `2r/s`. Points never reach the
//! outer ring of their cell, so the listing's "jitter" is really what the
//! text calls semi-jitter. The text says the random values are "now
//! `[-radius, radius]^2`", i.e. the whole cell when `radius` is read as the
//! cell's half side (read as the full radius it would leave the cell), and
//! §2.4 says jitter moves points "within a subsquare". We jitter over the
//! whole cell: offset in `[-r/s, r/s]`.

use crate::math::Vec3;
use crate::sampling::{PointTable, Rng};

use super::cells::{cells, cells_unordered, cells_unordered_part, strata_1d};
use super::model::{square, unit_square, DistributionModel};

/// The `jitter` distribution; see the [module docs](self).
#[derive(Clone, Copy, Debug)]
pub struct Jitter;

impl DistributionModel for Jitter {
    const NAME: &'static str = "jitter";
    const THESIS: bool = true;
    const NEEDS_SQUARE_COUNT: bool = true;

    fn generate(_: &PointTable, count: usize, radius: f32, rng: &mut Rng, out: &mut Vec<Vec3>) {
        cells(count, radius, rng, out, unit_square);
    }

    fn one(_: &PointTable, radius: f32, rng: &mut Rng) -> Vec3 {
        square(unit_square(rng), radius)
    }

    fn generate_unordered(
        _: &PointTable,
        count: usize,
        radius: f32,
        rng: &mut Rng,
        out: &mut Vec<Vec3>,
    ) {
        cells_unordered(count, radius, rng, out, unit_square);
    }

    fn generate_unordered_part(
        _: &PointTable,
        count: usize,
        radius: f32,
        rng: &mut Rng,
        part: std::ops::Range<usize>,
        out: &mut Vec<Vec3>,
    ) -> bool {
        cells_unordered_part((count, radius), rng, part, out, (unit_square, 2))
    }

    fn generate_1d(_: &PointTable, count: usize, rng: &mut Rng, out: &mut Vec<f32>) {
        strata_1d(count, rng, out, Rng::next_f32);
    }
}

#[cfg(test)]
mod tests {
    use super::super::testing::{within_cell_chi2, CHI2_999_DF63};
    use super::super::Distribution;

    #[test]
    fn jitter_is_uniform_over_the_whole_cell() {
        let c = within_cell_chi2(Distribution::Jitter, 0.5, 8);
        println!("jitter within-cell chi2 (63 dof) = {c:.1}");
        assert!(c < CHI2_999_DF63, "chi2 = {c}");
        // Power check: the listing's jitter (half the cell) fails this test.
        let c = within_cell_chi2(Distribution::SemiJitter, 0.5, 8);
        assert!(
            c > 10.0 * CHI2_999_DF63,
            "semi-jitter passed as jitter: {c}"
        );
    }
}
