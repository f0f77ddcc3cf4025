//! A filter's profile tabulated for sampling: the inverse of the
//! cumulative distribution of `|f|` over `[-r, r]`, for offsets drawn with
//! a density proportional to `|f|`, and the normaliser `∫|f| / ∫f` that
//! turns the sign of `f` at an offset into its weight `f / pdf`.

/// The tabulated inverse distribution of `|f|` on `[-r, r]`, in cells of
/// equal width (the density is constant within a cell, its mass `|f|`
/// integrated over the cell by Simpson's rule in `f64`).
#[derive(Clone, Debug)]
pub(super) struct InverseCdf {
    radius: f64,
    /// The distribution at the cells' ends, from 0 to 1.
    cdf: Box<[f64]>,
    /// `∫|f| / ∫f`; exactly 1 when `f` has no negative value at any of the
    /// points the table integrates it at.
    pub(super) norm: f32,
}

impl InverseCdf {
    /// The table of `f` on `[-radius, radius]` in `cells` cells; `None` if
    /// `f` integrates to nothing or less (no filter here does).
    pub(super) fn new(radius: f32, cells: usize, f: impl Fn(f64) -> f64) -> Option<InverseCdf> {
        let r = f64::from(radius);
        let h = 2.0 * r / cells as f64;
        let mut cdf = Vec::with_capacity(cells + 1);
        let (mut abs, mut signed) = (0.0, 0.0);
        let mut negative = false;
        cdf.push(0.0);
        for i in 0..cells {
            let x0 = -r + i as f64 * h;
            let v = [f(x0), f(x0 + 0.5 * h), f(x0 + h)];
            negative |= v.iter().any(|&v| v < 0.0);
            abs += h / 6.0 * (v[0].abs() + 4.0 * v[1].abs() + v[2].abs());
            signed += h / 6.0 * (v[0] + 4.0 * v[1] + v[2]);
            cdf.push(abs);
        }
        if !(signed > 0.0 && abs.is_finite()) {
            return None;
        }
        Some(InverseCdf {
            radius: r,
            cdf: cdf.iter().map(|c| c / abs).collect(),
            norm: if negative { (abs / signed) as f32 } else { 1.0 },
        })
    }

    /// The offset in `[-r, r]` at `u` in `[0, 1]`: increasing in `u`, and
    /// distributed as the table's `|f|` when `u` is uniform.
    pub(super) fn sample(&self, u: f32) -> f32 {
        let cells = self.cdf.len() - 1;
        let u = f64::from(u.clamp(0.0, 1.0));
        // The cell whose ends bracket u.
        let i = self.cdf.partition_point(|&c| c <= u).clamp(1, cells) - 1;
        let (c0, c1) = (self.cdf[i], self.cdf[i + 1]);
        let t = if c1 > c0 { (u - c0) / (c1 - c0) } else { 0.5 };
        let h = 2.0 * self.radius / cells as f64;
        (-self.radius + (i as f64 + t.clamp(0.0, 1.0)) * h) as f32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A linear density's table inverts to its analytic inverse, and a
    /// profile with a negative part has `∫|f| / ∫f` as its normaliser.
    #[test]
    fn inverse_and_normaliser_are_analytic() {
        // f(x) = 1 + x/2 on [-1, 1]: F(x) = (x + 1 + (x² − 1)/4) / 2.
        let t = InverseCdf::new(1.0, 256, |x| 1.0 + 0.5 * x).unwrap();
        assert_eq!(t.norm, 1.0);
        for k in 0..=20 {
            let x = -1.0 + k as f64 / 10.0;
            let u = (x + 1.0 + (x * x - 1.0) / 4.0) / 2.0;
            assert!((f64::from(t.sample(u as f32)) - x).abs() < 1e-5, "{x}");
        }
        // f(x) = x + 1/2 on [-1, 1]: ∫f = 1, ∫|f| = 1/8 + 9/8 = 5/4.
        let t = InverseCdf::new(1.0, 1024, |x| x + 0.5).unwrap();
        assert!((t.norm - 1.25).abs() < 1e-5, "{}", t.norm);
        assert!(InverseCdf::new(1.0, 64, |x| -x * x).is_none());
        assert!(InverseCdf::new(1.0, 64, |x| x).is_none());
    }
}
