//! A distribution over the unit square whose density is the bilinear
//! interpolant of a grid of non-negative values at its vertices (Mitsuba 3's
//! `Hierarchical2D`, which samples an environment map so). A grid of
//! `nx` × `ny` values makes `(nx − 1)` × `(ny − 1)` patches; vertex `(i, j)`
//! lies at `(i / (nx − 1), j / (ny − 1))`.
//!
//! A patch is chosen by its integral (a marginal distribution over the rows
//! of patches, then a conditional one along the row, both through
//! [`Discrete`], which reuses the uniform number within the chosen item);
//! within the patch the point is drawn from the bilinear density by
//! inverting its marginal in `y` and then its conditional in `x`, each a
//! linear density. The density of a point is the interpolant there over its
//! integral, the same whichever way it is computed: sampled or looked up.

use super::linear1d::{lerp, linear};
use super::Discrete;
use crate::math::Vec2;

/// A distribution over [0, 1]² proportional to the bilinear interpolant of
/// a grid of vertex values; `x` runs along a row (`nx` values), `y` across
/// rows (`ny` rows).
#[derive(Clone, Debug)]
pub struct Bilinear2D {
    nx: usize,
    ny: usize,
    /// The vertex values scaled so that the interpolant integrates to 1.
    values: Vec<f32>,
    /// Per row of patches, the distribution over its patches by their
    /// integrals; `None` for a row of zero integral.
    rows: Vec<Option<Discrete>>,
    /// The distribution over the rows of patches.
    marginal: Discrete,
}

impl Bilinear2D {
    /// The distribution of the vertex values `values`, row by row (`nx` ×
    /// `ny` of them, each finite and ≥ 0). `None` if there are fewer than 2
    /// vertices along a side, the count is not `nx · ny`, a value is
    /// negative or not finite, or the interpolant is 0 everywhere.
    pub fn new(nx: usize, ny: usize, values: Vec<f32>) -> Option<Bilinear2D> {
        if nx < 2 || ny < 2 || values.len() != nx.checked_mul(ny)? {
            return None;
        }
        if values.iter().any(|v| !(v.is_finite() && *v >= 0.0)) {
            return None;
        }
        // The integral of each patch over its area: the mean of its corners.
        let patch = |i: usize, j: usize| {
            let at = |i: usize, j: usize| f64::from(values[j * nx + i]);
            0.25 * (at(i, j) + at(i + 1, j) + at(i, j + 1) + at(i + 1, j + 1))
        };
        let (px, py) = (nx - 1, ny - 1);
        let sums: Vec<Vec<f64>> = (0..py)
            .map(|j| (0..px).map(|i| patch(i, j)).collect())
            .collect();
        let total: f64 = sums.iter().flatten().sum();
        if !(total > 0.0 && total.is_finite()) {
            return None;
        }
        let rows: Vec<Option<Discrete>> = sums
            .iter()
            .map(|row| Discrete::new(row.iter().map(|&s| s as f32)))
            .collect();
        let marginal = Discrete::new(sums.iter().map(|row| row.iter().sum::<f64>() as f32))?;
        let scale = (px * py) as f64 / total;
        let values = values
            .iter()
            .map(|&v| (f64::from(v) * scale) as f32)
            .collect();
        Some(Bilinear2D {
            nx,
            ny,
            values,
            rows,
            marginal,
        })
    }

    /// The grid's size: vertices per row, rows of vertices.
    pub fn size(&self) -> (usize, usize) {
        (self.nx, self.ny)
    }

    /// The four corner values of patch `(i, j)`: `(v00, v10, v01, v11)`,
    /// the second index along `y`.
    #[inline]
    fn corners(&self, i: usize, j: usize) -> (f32, f32, f32, f32) {
        let k = j * self.nx + i;
        (
            self.values[k],
            self.values[k + 1],
            self.values[k + self.nx],
            self.values[k + self.nx + 1],
        )
    }

    /// The point of the square for the uniform pair `u` and its density
    /// (the interpolant there). Patches of zero integral are never chosen.
    pub fn sample(&self, u: Vec2) -> (Vec2, f32) {
        let (j, _, sy) = self.marginal.sample(u.y.clamp(0.0, 1.0));
        let Some(row) = &self.rows[j] else {
            // The marginal never chooses a row of zero integral.
            return (Vec2::ZERO, 0.0);
        };
        let (i, _, sx) = row.sample(u.x.clamp(0.0, 1.0));
        let (v00, v10, v01, v11) = self.corners(i, j);
        let ty = linear(v00 + v10, v01 + v11, sy);
        let (c0, c1) = (lerp(v00, v01, ty), lerp(v10, v11, ty));
        let tx = linear(c0, c1, sx);
        let p = Vec2::new(
            ((i as f32 + tx) / (self.nx - 1) as f32).min(1.0),
            ((j as f32 + ty) / (self.ny - 1) as f32).min(1.0),
        );
        (p, lerp(c0, c1, tx))
    }

    /// The density at the point `p` of the square (clamped into it).
    pub fn pdf(&self, p: Vec2) -> f32 {
        let (px, py) = (self.nx - 1, self.ny - 1);
        let x = p.x.clamp(0.0, 1.0) * px as f32;
        let y = p.y.clamp(0.0, 1.0) * py as f32;
        let (i, j) = ((x as usize).min(px - 1), (y as usize).min(py - 1));
        let (tx, ty) = (x - i as f32, y - j as f32);
        let (v00, v10, v01, v11) = self.corners(i, j);
        lerp(lerp(v00, v10, tx), lerp(v01, v11, tx), ty)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    /// A 5 × 4 grid with a zero corner, a zero row of vertices (whose
    /// patches above and below still weigh) and a steep peak.
    fn grid() -> Vec<f32> {
        vec![
            0.0, 2.0, 0.5, 4.0, 0.5, //
            1.0, 0.0, 3.0, 9.0, 1.0, //
            0.0, 0.0, 0.0, 0.0, 0.0, //
            0.25, 8.0, 1.0, 0.0, 2.0,
        ]
    }

    /// The linear warp: its cumulative probability at the drawn point is
    /// the uniform number, for equal, rising, falling and half-zero ends.
    #[test]
    fn the_linear_warp_inverts_its_cdf() {
        for (a, b) in [
            (1.0f32, 1.0f32),
            (0.0, 3.0),
            (2.0, 0.0),
            (0.3, 7.0),
            (5.0, 4.9),
        ] {
            for k in 0..=20 {
                let s = k as f32 / 20.0;
                let t = linear(a, b, s);
                let cdf = (a * t + 0.5 * (b - a) * t * t) / (0.5 * (a + b));
                assert!(
                    (cdf - s).abs() < 1e-5,
                    "({a}, {b}) at {s}: t {t}, cdf {cdf}"
                );
            }
        }
        assert_eq!(linear(0.0, 0.0, 0.3), 0.3);
    }

    /// The density is the interpolant: at the vertices the (scaled)
    /// values, between them linear along each axis, and it integrates to 1
    /// (the mean of the corners of each patch, summed).
    #[test]
    fn the_density_is_the_normalised_interpolant() {
        let g = grid();
        let d = Bilinear2D::new(5, 4, g.clone()).unwrap();
        // 4 patches along x, 3 along y, each of area 1/12: the values
        // scale by 12 over the sum of the patches' corner means.
        let mut sum = 0.0;
        for j in 0..3 {
            for i in 0..4 {
                let k = j * 5 + i;
                sum += 0.25 * (g[k] + g[k + 1] + g[k + 5] + g[k + 6]);
            }
        }
        let scale = 12.0 / sum;
        for j in 0..4 {
            for i in 0..5 {
                let p = Vec2::new(i as f32 / 4.0, j as f32 / 3.0);
                let want = g[j * 5 + i] * scale;
                assert!(
                    (d.pdf(p) - want).abs() < 1e-5 * want.max(1.0),
                    "vertex ({i}, {j})"
                );
            }
        }
        // A quarter of the way from vertex (2, 1) toward (3, 1), and a
        // third of the way from (2, 1) to (2, 2).
        let p = Vec2::new(2.25 / 4.0, 1.0 / 3.0);
        assert!((d.pdf(p) - (0.75 * 3.0 + 0.25 * 9.0) * scale).abs() < 1e-5);
        let p = Vec2::new(0.5, 4.0 / 9.0);
        assert!((d.pdf(p) - (2.0 / 3.0 * 3.0) * scale).abs() < 1e-5);
        // The integral by the midpoint rule on a fine grid (exact for a
        // bilinear function on cells inside the patches).
        let n = 240;
        let integral: f64 = (0..n * n)
            .map(|k| {
                let p = Vec2::new(
                    ((k % n) as f32 + 0.5) / n as f32,
                    ((k / n) as f32 + 0.5) / n as f32,
                );
                f64::from(d.pdf(p))
            })
            .sum::<f64>()
            / (n * n) as f64;
        assert!((integral - 1.0).abs() < 1e-5, "{integral}");
    }

    /// Pearson's χ² of 10⁶ samples binned by 4 × 4 sub-cells of every
    /// patch against the density integrated over each sub-cell (the area
    /// times the density at its centre: exact for a bilinear function),
    /// below the 0.999 quantile; every sample's density is the density
    /// looked up at its point (0 only on an edge of zero values, where
    /// rounding may land a draw). The same counts against the density with
    /// the expectations of the likeliest sub-cell's patch 5% higher fail.
    #[test]
    fn samples_follow_the_density() {
        use statrs::distribution::{ChiSquared, ContinuousCDF};
        let d = Bilinear2D::new(5, 4, grid()).unwrap();
        let (bx, by) = (4 * 4, 3 * 4);
        let mut counts = vec![0u32; bx * by];
        let mut rng = Rng::new(17);
        let n = 1_000_000;
        for _ in 0..n {
            let (p, pdf) = d.sample(Vec2::new(rng.next_f32(), rng.next_f32()));
            assert!((0.0..=1.0).contains(&p.x) && (0.0..=1.0).contains(&p.y));
            let looked = d.pdf(p);
            assert!(
                (pdf - looked).abs() <= 1e-4 * pdf,
                "{pdf} vs {looked} at {p:?}"
            );
            let x = ((p.x * bx as f32) as usize).min(bx - 1);
            let y = ((p.y * by as f32) as usize).min(by - 1);
            counts[y * bx + x] += 1;
        }
        let expected: Vec<f64> = (0..bx * by)
            .map(|k| {
                let c = Vec2::new(
                    ((k % bx) as f32 + 0.5) / bx as f32,
                    ((k / bx) as f32 + 0.5) / by as f32,
                );
                f64::from(d.pdf(c)) / (bx * by) as f64 * n as f64
            })
            .collect();
        let total: f64 = expected.iter().sum();
        assert!((total / n as f64 - 1.0).abs() < 1e-5, "{total}");
        let chi2 = |expected: &[f64]| {
            let (mut stat, mut cells) = (0.0, 0usize);
            for (&c, &e) in counts.iter().zip(expected) {
                if e >= 5.0 {
                    stat += (f64::from(c) - e).powi(2) / e;
                    cells += 1;
                } else {
                    assert!(c <= 20, "{c} samples where {e} were expected");
                }
            }
            let q = ChiSquared::new((cells - 1) as f64)
                .unwrap()
                .inverse_cdf(0.999);
            (stat, q)
        };
        let (good, q) = chi2(&expected);
        assert!(good < q, "χ² {good} (0.999 quantile {q})");
        let likeliest = (0..expected.len())
            .max_by(|&a, &b| expected[a].total_cmp(&expected[b]))
            .unwrap();
        let patch = |k: usize| ((k % bx) / 4, (k / bx) / 4);
        let off: Vec<f64> = (0..expected.len())
            .map(|k| {
                if patch(k) == patch(likeliest) {
                    1.05 * expected[k]
                } else {
                    expected[k]
                }
            })
            .collect();
        let (bad, _) = chi2(&off);
        eprintln!(
            "bilinear χ²: {good:.1} as drawn, {bad:.1} with a patch 5% off (0.999 quantile {q:.0})"
        );
        assert!(bad > q, "χ² {bad} with a 5% error");
    }

    /// Patches whose four corners are 0 are never drawn, even beside
    /// heavy ones.
    #[test]
    fn empty_patches_are_never_drawn() {
        // The left patch is 0; the right one rises to 1 at its far edge.
        let d = Bilinear2D::new(3, 2, vec![0.0, 0.0, 1.0, 0.0, 0.0, 1.0]).unwrap();
        let mut rng = Rng::new(3);
        for _ in 0..10_000 {
            let (p, pdf) = d.sample(Vec2::new(rng.next_f32(), rng.next_f32()));
            assert!(p.x >= 0.5 && pdf > 0.0, "{p:?} {pdf}");
        }
        // The density rises linearly across the right patch: 0 at x = 0.5,
        // 4 at x = 1 (the integral is 1/4 over the unit square).
        assert!((d.pdf(Vec2::new(1.0, 0.3)) - 4.0).abs() < 1e-6);
        assert!((d.pdf(Vec2::new(0.75, 0.9)) - 2.0).abs() < 1e-6);
        assert_eq!(d.pdf(Vec2::new(0.25, 0.5)), 0.0);
    }

    #[test]
    fn degenerate_grids_are_refused() {
        assert!(Bilinear2D::new(2, 2, vec![0.0; 4]).is_none());
        assert!(Bilinear2D::new(2, 2, vec![1.0; 3]).is_none());
        assert!(Bilinear2D::new(1, 2, vec![1.0; 2]).is_none());
        assert!(Bilinear2D::new(2, 1, vec![1.0; 2]).is_none());
        assert!(Bilinear2D::new(2, 2, vec![1.0, f32::NAN, 1.0, 1.0]).is_none());
        assert!(Bilinear2D::new(2, 2, vec![1.0, -1.0, 1.0, 1.0]).is_none());
    }
}
