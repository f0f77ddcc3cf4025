//! A piecewise-constant distribution over the unit square, made of a grid
//! of non-negative cell weights: a marginal distribution over the rows and,
//! per row, a conditional one over its cells (pbrt-v4's
//! `PiecewiseConstant2D`, Mitsuba 3's distributions over an environment
//! map's pixels). A point lands in a cell with probability proportional to
//! its weight and uniformly within it, so the density over the square is
//! the cell's weight times the number of cells over the total weight.
//!
//! Both choices go through [`Discrete`], which reuses the uniform number
//! within the chosen item: a stratified pair of numbers stays stratified.

use super::Discrete;
use crate::math::Vec2;

/// A distribution over [0, 1)² proportional to a grid of weights; `x`
/// runs along a row (`width` cells), `y` across rows (`height` rows).
#[derive(Clone, Debug)]
pub struct Piecewise2D {
    width: usize,
    height: usize,
    /// Per row, the distribution over its cells; `None` for a row of zero weight.
    rows: Vec<Option<Discrete>>,
    /// The distribution over the rows (by their sums).
    marginal: Discrete,
    /// Cells over the total weight: density = weight · `norm`.
    norm: f64,
    weights: Vec<f32>,
}

impl Piecewise2D {
    /// The distribution of `weights`, row by row (`width` × `height` of
    /// them, each finite and ≥ 0). `None` if the grid is empty, the count
    /// is not `width · height`, a weight is negative or not finite, or all
    /// are 0.
    pub fn new(width: usize, height: usize, weights: Vec<f32>) -> Option<Piecewise2D> {
        if width == 0 || height == 0 || weights.len() != width.checked_mul(height)? {
            return None;
        }
        if weights.iter().any(|w| !(w.is_finite() && *w >= 0.0)) {
            return None;
        }
        let rows: Vec<Option<Discrete>> = weights
            .chunks_exact(width)
            .map(|row| Discrete::new(row.iter().copied()))
            .collect();
        let marginal = Discrete::new(
            rows.iter()
                .map(|r| r.as_ref().map_or(0.0, |d| d.total() as f32)),
        )?;
        let norm = (width * height) as f64 / marginal.total();
        Some(Piecewise2D {
            width,
            height,
            rows,
            marginal,
            norm,
            weights,
        })
    }

    /// The grid's size: cells per row, rows.
    pub fn size(&self) -> (usize, usize) {
        (self.width, self.height)
    }

    /// The point of the square for the uniform pair `u` and its density.
    /// Cells of zero weight are never chosen.
    pub fn sample(&self, u: Vec2) -> (Vec2, f32) {
        let (y, _, v) = self.marginal.sample(u.y);
        let Some(row) = &self.rows[y] else {
            // The marginal never chooses a row of zero weight.
            return (Vec2::ZERO, 0.0);
        };
        let (x, _, w) = row.sample(u.x);
        let p = Vec2::new(
            ((x as f32 + w) / self.width as f32).min(1.0 - f32::EPSILON / 2.0),
            ((y as f32 + v) / self.height as f32).min(1.0 - f32::EPSILON / 2.0),
        );
        (p, self.cell_pdf(x, y))
    }

    /// The density at the point `p` of the square.
    pub fn pdf(&self, p: Vec2) -> f32 {
        let x = ((p.x * self.width as f32) as usize).min(self.width - 1);
        let y = ((p.y * self.height as f32) as usize).min(self.height - 1);
        self.cell_pdf(x, y)
    }

    /// The density within the cell at column `x`, row `y`.
    #[inline]
    pub fn cell_pdf(&self, x: usize, y: usize) -> f32 {
        (f64::from(self.weights[y * self.width + x]) * self.norm) as f32
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    /// Pearson's χ² of samples binned by cell against the densities, on a
    /// 5 × 4 grid with empty cells and an empty row: below the 0.999
    /// quantile (31.3 for 14 degrees of freedom over 15 non-empty cells).
    /// The same counts against weights with one cell off by 5% fail.
    #[test]
    fn samples_follow_the_density() {
        let mut weights = vec![
            1.0, 2.0, 0.0, 4.0, 0.5, //
            0.0, 0.0, 0.0, 0.0, 0.0, //
            3.0, 1.0, 1.0, 6.0, 2.0, //
            0.25, 8.0, 1.0, 0.0, 2.0,
        ];
        let d = Piecewise2D::new(5, 4, weights.clone()).unwrap();
        let mut rng = Rng::new(11);
        let n = 400_000;
        let mut counts = [0u32; 20];
        for _ in 0..n {
            let (p, pdf) = d.sample(Vec2::new(rng.next_f32(), rng.next_f32()));
            assert!((0.0..1.0).contains(&p.x) && (0.0..1.0).contains(&p.y));
            assert!(
                (pdf - d.pdf(p)).abs() <= 1e-6 * pdf,
                "{pdf} vs {}",
                d.pdf(p)
            );
            counts[(p.y * 4.0) as usize * 5 + (p.x * 5.0) as usize] += 1;
        }
        let chi2 = |w: &[f32]| {
            let total: f32 = w.iter().sum();
            counts
                .iter()
                .zip(w)
                .filter(|(_, &w)| w > 0.0)
                .map(|(&c, &w)| {
                    let e = n as f32 * w / total;
                    (c as f32 - e).powi(2) / e
                })
                .sum::<f32>()
        };
        assert!(chi2(&weights) < 31.3, "{}", chi2(&weights));
        weights[13] *= 1.05;
        assert!(chi2(&weights) > 31.3, "a 5% error is detected");
    }

    /// The density integrates to 1 over the square, and is the weight
    /// times the cell count over the total.
    #[test]
    fn the_density_integrates_to_one() {
        let weights: Vec<f32> = (0..12).map(|i| (i % 5) as f32).collect();
        let d = Piecewise2D::new(4, 3, weights.clone()).unwrap();
        let integral: f32 = (0..12).map(|i| d.cell_pdf(i % 4, i / 4) / 12.0).sum();
        assert!((integral - 1.0).abs() < 1e-6);
        let total: f32 = weights.iter().sum();
        // (0.9, 0.5) is cell 3 of row 1, of weight 7 % 5 = 2.
        assert!((d.pdf(Vec2::new(0.9, 0.5)) - 2.0 * 12.0 / total).abs() < 1e-5);
    }

    #[test]
    fn degenerate_grids_are_refused() {
        assert!(Piecewise2D::new(2, 2, vec![0.0; 4]).is_none());
        assert!(Piecewise2D::new(2, 2, vec![1.0; 3]).is_none());
        assert!(Piecewise2D::new(0, 2, vec![]).is_none());
        assert!(Piecewise2D::new(2, 1, vec![1.0, f32::NAN]).is_none());
        assert!(Piecewise2D::new(2, 1, vec![1.0, -1.0]).is_none());
    }
}
