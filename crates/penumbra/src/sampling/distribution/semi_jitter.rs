//! `semi-jitter`: one point per cell of an `s x s` grid, uniform in the
//! centred square of half the cell's side. A compromise between `grid`
//! (regular) and `jitter` (noisy): no two points come closer than half a
//! cell side. Guarantee: exactly one point per cell, inside its centred
//! half-size sub-square; with one point, one point uniform in
//! `[-r/2, r/2]^2`. Shutter times: `(i + 0.25 + 0.5 u) / n`.
//!
//! The thesis's Listing 3.3 adds `(RND()*2-1) * radius/(sqrtOfNumRays*4)`:
//! an offset in `[-r/(4s), r/(4s)]`, a square a *quarter* of the cell side.
//! The text says the square is "half the size of the jitter" one, with
//! values in `[-radius/2, radius/2]^2`. We use half the cell side: offset
//! in `[-r/(2s), r/(2s)]`. Both listings are thus a factor 2 narrower than
//! the text; the ratio of 2 between jitter and semi-jitter is kept.

use crate::math::{Vec2, Vec3};
use crate::sampling::{PointTable, Rng};

use super::cells::{cells, cells_unordered, cells_unordered_part, strata_1d};
use super::model::{square, unit_square, DistributionModel};

/// The `semi-jitter` distribution; see the [module docs](self).
#[derive(Clone, Copy, Debug)]
pub struct SemiJitter;

/// Semi-jitter's offset: uniform in the centred half-size square of the cell.
fn semi_jitter(rng: &mut Rng) -> Vec2 {
    Vec2::splat(0.25) + 0.5 * unit_square(rng)
}

impl DistributionModel for SemiJitter {
    const NAME: &'static str = "semi-jitter";
    const ALIASES: &'static [&'static str] = &["semijitter"];
    const THESIS: bool = true;
    const NEEDS_SQUARE_COUNT: bool = true;

    fn generate(_: &PointTable, count: usize, radius: f32, rng: &mut Rng, out: &mut Vec<Vec3>) {
        cells(count, radius, rng, out, semi_jitter);
    }

    fn one(_: &PointTable, radius: f32, rng: &mut Rng) -> Vec3 {
        square(semi_jitter(rng), radius)
    }

    fn generate_unordered(
        _: &PointTable,
        count: usize,
        radius: f32,
        rng: &mut Rng,
        out: &mut Vec<Vec3>,
    ) {
        cells_unordered(count, radius, rng, out, semi_jitter);
    }

    fn generate_unordered_part(
        _: &PointTable,
        count: usize,
        radius: f32,
        rng: &mut Rng,
        part: std::ops::Range<usize>,
        out: &mut Vec<Vec3>,
    ) -> bool {
        cells_unordered_part((count, radius), rng, part, out, (semi_jitter, 2))
    }

    fn generate_1d(_: &PointTable, count: usize, rng: &mut Rng, out: &mut Vec<f32>) {
        strata_1d(count, rng, out, |rng| 0.25 + 0.5 * rng.next_f32());
    }
}

#[cfg(test)]
mod tests {
    use super::super::testing::{within_cell_chi2, CHI2_999_DF15};
    use super::super::Distribution;

    #[test]
    fn semi_jitter_is_uniform_over_its_sub_square() {
        let c = within_cell_chi2(Distribution::SemiJitter, 0.25, 4);
        println!("semi-jitter within-sub-square chi2 (15 dof) = {c:.1}");
        assert!(c < CHI2_999_DF15, "chi2 = {c}");
    }
}
