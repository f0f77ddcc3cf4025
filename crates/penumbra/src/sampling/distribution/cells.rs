//! What the grid family ([`grid`](super::grid), [`jitter`](super::jitter),
//! [`semi_jitter`](super::semi_jitter)) shares: one point per cell of an
//! `s x s` grid over the square, at an offset each of them chooses within
//! its cell; the one-dimensional strata of their shutter times. See
//! [Non-square counts](super#non-square-counts) for counts that are not
//! squares.

use crate::math::{Vec2, Vec3};
use crate::sampling::Rng;

use super::model::{shuffle, square_side, to_radius, ONE_BELOW};

/// One point per cell of the `s x s` grid, at `offset` (in `[0, 1)^2`, in
/// cell units) within its cell; then shuffled and cut to `count`.
pub(super) fn cells(
    count: usize,
    radius: f32,
    rng: &mut Rng,
    out: &mut Vec<Vec3>,
    offset: impl FnMut(&mut Rng) -> Vec2,
) {
    cell_points(square_side(count), radius, rng, out, offset);
    shuffle(out, rng);
    out.truncate(count);
}

/// The set of a square count in row order (its order cannot matter: every
/// cell is kept), or, for another count, the shuffled and cut set of
/// [`cells`]; into the empty `out`.
pub(super) fn cells_unordered(
    count: usize,
    radius: f32,
    rng: &mut Rng,
    out: &mut Vec<Vec3>,
    offset: impl FnMut(&mut Rng) -> Vec2,
) {
    let s = square_side(count);
    if s * s != count {
        cells(count, radius, rng, out, offset);
    } else {
        cell_points(s, radius, rng, out, offset);
    }
}

/// Points `part` of the set of a square count in row order
/// ([`cells_unordered`]), each offset taking `draws` values of `rng`;
/// `false` for another count.
pub(super) fn cells_unordered_part(
    (count, radius): (usize, f32),
    rng: &mut Rng,
    part: std::ops::Range<usize>,
    out: &mut Vec<Vec3>,
    (mut offset, draws): (impl FnMut(&mut Rng) -> Vec2, u64),
) -> bool {
    let s = square_side(count);
    if s * s != count || part.end > count {
        return false;
    }
    let side = s as f32;
    rng.skip(part.start as u64 * draws);
    out.reserve(part.len());
    for k in part {
        let o = offset(rng);
        let t = (Vec2::new((k % s) as f32, (k / s) as f32) + o) / side;
        out.push(Vec3::new(
            to_radius(t.x, radius),
            to_radius(t.y, radius),
            0.0,
        ));
    }
    true
}

/// One point per cell of the `s x s` grid, in row order, appended to `out`.
fn cell_points(
    s: usize,
    radius: f32,
    rng: &mut Rng,
    out: &mut Vec<Vec3>,
    mut offset: impl FnMut(&mut Rng) -> Vec2,
) {
    let side = s as f32;
    out.reserve(s.saturating_mul(s));
    for j in 0..s {
        for i in 0..s {
            let o = offset(rng);
            let t = (Vec2::new(i as f32, j as f32) + o) / side;
            out.push(Vec3::new(
                to_radius(t.x, radius),
                to_radius(t.y, radius),
                0.0,
            ));
        }
    }
}

/// One value per stratum `[i/n, (i+1)/n)` of `[0, 1)`, at `offset` within
/// it; then shuffled.
pub(super) fn strata_1d(
    count: usize,
    rng: &mut Rng,
    out: &mut Vec<f32>,
    mut offset: impl FnMut(&mut Rng) -> f32,
) {
    let n = count as f32;
    out.extend((0..count).map(|i| ((i as f32 + offset(rng)) / n).min(ONE_BELOW)));
    shuffle(out, rng);
}

#[cfg(test)]
mod tests {
    use super::super::testing::{cell_of, gen, offsets_one_per_cell};
    use super::super::Distribution;
    use crate::math::Vec3;

    /// A part of an unordered set made alone is that part of the whole
    /// set, bit for bit; a count that is not a square is refused.
    #[test]
    fn parts_of_unordered_sets_are_the_whole_sets_parts() {
        use crate::sampling::{PointTable, Rng};
        let table = PointTable::default();
        for d in [
            Distribution::Grid,
            Distribution::Jitter,
            Distribution::SemiJitter,
        ] {
            for count in [1, 4, 9, 16, 64] {
                let mut whole = Vec::new();
                d.generate_unordered_in(&table, count, 0.5, &mut Rng::new(7), &mut whole);
                for part in [0..count, 0..1, count / 2..count, count - 1..count] {
                    let mut got = Vec::new();
                    let made = d.generate_unordered_part_in(
                        &table,
                        (count, 0.5),
                        &mut Rng::new(7),
                        part.clone(),
                        &mut got,
                    );
                    assert!(made, "{d} {count}");
                    let bits = |v: &[Vec3]| -> Vec<[u32; 3]> {
                        v.iter().map(|p| p.to_array().map(f32::to_bits)).collect()
                    };
                    assert_eq!(
                        bits(&got),
                        bits(&whole[part.clone()]),
                        "{d} {count} {part:?}"
                    );
                }
            }
            let mut out = Vec::new();
            assert!(!d.generate_unordered_part_in(
                &table,
                (8, 0.5),
                &mut Rng::new(7),
                0..2,
                &mut out
            ));
        }
        let mut out = Vec::new();
        let random = Distribution::Random;
        assert!(!random.generate_unordered_part_in(
            &table,
            (4, 0.5),
            &mut Rng::new(7),
            0..2,
            &mut out
        ));
    }

    #[test]
    fn one_point_per_cell_for_square_counts() {
        for s in 1..=12 {
            for seed in 0..10 {
                let r = 1.5;
                for o in offsets_one_per_cell(Distribution::Grid, s, r, seed) {
                    assert!(o.abs().max_element() < 1e-5, "grid s={s}: {o:?}");
                }
                for o in offsets_one_per_cell(Distribution::SemiJitter, s, r, seed) {
                    assert!(o.abs().max_element() <= 0.25 + 1e-5, "semi s={s}: {o:?}");
                }
                for o in offsets_one_per_cell(Distribution::Jitter, s, r, seed) {
                    assert!(o.abs().max_element() <= 0.5 + 1e-5, "jitter s={s}: {o:?}");
                }
            }
        }
    }

    /// Position in the row-major enumeration of a 4 x 4 set (cell index).
    fn cell_key(p: Vec3) -> (usize, usize) {
        (cell_of(p.y, 1.0, 4), cell_of(p.x, 1.0, 4))
    }

    #[test]
    fn trace_order_is_a_shuffled_permutation() {
        let mut centres: Vec<(usize, usize)> = (0..16).map(|k| (k / 4, k % 4)).collect();
        centres.sort();
        for d in [
            Distribution::Grid,
            Distribution::Jitter,
            Distribution::SemiJitter,
        ] {
            let (mut sorted, mut same_row) = (0, 0);
            for seed in 0..2000 {
                let keys: Vec<_> = gen(d, 16, 1.0, seed).into_iter().map(cell_key).collect();
                let mut set = keys.clone();
                set.sort();
                assert_eq!(set, centres, "{d}: not one point per cell");
                let transposed: Vec<_> = keys.iter().map(|&(a, b)| (b, a)).collect();
                sorted += usize::from(keys.is_sorted() || transposed.is_sorted());
                sorted += usize::from(keys.iter().rev().is_sorted());
                same_row += usize::from(keys[..4].iter().all(|k| k.0 == keys[0].0));
            }
            // P(first 4 in one row) = 4 / C(16, 4) = 1/455: ~4.4 of 2000 by
            // chance, P(>= 16) < 1e-5; row-major order would give 2000.
            println!("{d}: sorted orders = {sorted}, first 4 in one row = {same_row} / 2000");
            assert_eq!(sorted, 0, "{d}");
            assert!(same_row < 16, "{d}: {same_row}");
        }
    }
}
