//! What the distributions' tests share: a set by seed, the chi-square
//! statistic and its quantiles, cells of the square.

use crate::math::{Vec2, Vec3};
use crate::sampling::Rng;

use super::Distribution;

// 99.9% quantiles of the chi-square distribution for the degrees of
// freedom used (standard tables; the tests use fixed seeds, so they are
// deterministic, and a correct generator fails one with p = 0.001).
pub const CHI2_999_DF6: f64 = 22.458;
pub const CHI2_999_DF9: f64 = 27.877;
pub const CHI2_999_DF11: f64 = 31.264;
pub const CHI2_999_DF15: f64 = 37.697;
pub const CHI2_999_DF63: f64 = 103.442;

/// The set of `count` points of `d` drawn from `Rng::new(seed)`.
pub fn gen(d: Distribution, count: usize, radius: f32, seed: u64) -> Vec<Vec3> {
    let mut out = vec![Vec3::ONE; 3]; // must be cleared
    d.generate(count, radius, &mut Rng::new(seed), &mut out);
    out
}

pub fn chi2(counts: &[u64]) -> f64 {
    let n: u64 = counts.iter().sum();
    let expected = n as f64 / counts.len() as f64;
    counts
        .iter()
        .map(|&c| (c as f64 - expected).powi(2) / expected)
        .sum()
}

/// Index of the grid cell (of `s x s` over `[-r, r]^2`) holding `x`.
pub fn cell_of(x: f32, r: f32, s: usize) -> usize {
    let t = (x / r + 1.0) * 0.5 * s as f32;
    (t.max(0.0) as usize).min(s - 1)
}

/// Checks one point per cell and returns the offsets from the cell
/// centres, in units of the cell side.
pub fn offsets_one_per_cell(d: Distribution, s: usize, r: f32, seed: u64) -> Vec<Vec2> {
    let points = gen(d, s * s, r, seed);
    let mut hits = vec![0; s * s];
    let side = 2.0 * r / s as f32;
    let mut offsets = Vec::new();
    for p in points {
        let (i, j) = (cell_of(p.x, r, s), cell_of(p.y, r, s));
        hits[j * s + i] += 1;
        let centre = Vec2::new(i as f32 + 0.5, j as f32 + 0.5) * side - Vec2::splat(r);
        offsets.push((p.truncate() - centre) / side);
    }
    assert!(hits.iter().all(|&h| h == 1), "{d} s={s}: {hits:?}");
    offsets
}

/// Chi-square of the offsets within the cell (or sub-square of half
/// `extent`) over a `bins x bins` sub-grid, pooled over many sets.
pub fn within_cell_chi2(d: Distribution, extent: f32, bins: usize) -> f64 {
    let mut counts = vec![0u64; bins * bins];
    for seed in 0..5000 {
        for o in offsets_one_per_cell(d, 4, 1.0, seed) {
            let t = (o / extent + Vec2::splat(1.0)) * 0.5 * bins as f32;
            let (i, j) = (t.x as usize, t.y as usize);
            counts[j.min(bins - 1) * bins + i.min(bins - 1)] += 1;
        }
    }
    chi2(&counts)
}
