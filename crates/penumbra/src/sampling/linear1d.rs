//! A distribution over an interval whose density is the piecewise-linear
//! interpolant of values at evenly spaced points (Mitsuba 3's
//! `ContinuousDistribution`): a tabulated phase function over the cosine of
//! the scattering angle. `n` values make `n − 1` segments; value `i` lies
//! at `lo + i (hi − lo) / (n − 1)`.
//!
//! A segment is chosen by its integral through [`Discrete`] (which reuses
//! the uniform number within the segment), and the point within it drawn
//! from the segment's linear density by inverting its cumulative
//! probability (`linear`, also the step of [`Bilinear2D`](super::Bilinear2D)).
//! The density of a point is the interpolant there over its integral,
//! sampled or looked up alike.

use super::Discrete;

/// A distribution over `[lo, hi]` proportional to the piecewise-linear
/// interpolant of evenly spaced values.
#[derive(Clone, Debug, PartialEq)]
pub struct Linear1D {
    lo: f32,
    hi: f32,
    /// The values scaled so that the interpolant integrates to 1.
    values: Vec<f32>,
    /// The segments by their integrals.
    segments: Discrete,
}

impl Linear1D {
    /// The distribution of `values` (at least 2, each finite and ≥ 0) over
    /// `[lo, hi]` (`lo < hi`). `None` if there are fewer than 2 values, a
    /// value is negative or not finite, or all are 0.
    pub fn new(values: &[f32], (lo, hi): (f32, f32)) -> Option<Linear1D> {
        if values.len() < 2 || lo.partial_cmp(&hi) != Some(std::cmp::Ordering::Less) {
            return None;
        }
        if values.iter().any(|v| !(v.is_finite() && *v >= 0.0)) {
            return None;
        }
        let width = f64::from(hi - lo) / (values.len() - 1) as f64;
        let integrals: Vec<f64> = values
            .windows(2)
            .map(|w| 0.5 * (f64::from(w[0]) + f64::from(w[1])) * width)
            .collect();
        let total: f64 = integrals.iter().sum();
        if !(total > 0.0 && total.is_finite()) {
            return None;
        }
        let segments = Discrete::new(integrals.iter().map(|&x| x as f32))?;
        let values = values
            .iter()
            .map(|&v| (f64::from(v) / total) as f32)
            .collect();
        Some(Linear1D {
            lo,
            hi,
            values,
            segments,
        })
    }

    /// The width of a segment.
    #[inline]
    fn width(&self) -> f32 {
        (self.hi - self.lo) / (self.values.len() - 1) as f32
    }

    /// The point of `[lo, hi]` for the uniform number `u` and its density.
    /// Segments of zero integral are never chosen.
    pub fn sample(&self, u: f32) -> (f32, f32) {
        let (i, _, s) = self.segments.sample(u.clamp(0.0, 1.0));
        let (a, b) = (self.values[i], self.values[i + 1]);
        let t = linear(a, b, s);
        let x = (self.lo + (i as f32 + t) * self.width()).clamp(self.lo, self.hi);
        (x, lerp(a, b, t))
    }

    /// The density at `x`: 0 outside `[lo, hi]`.
    pub fn pdf(&self, x: f32) -> f32 {
        if !(self.lo..=self.hi).contains(&x) {
            return 0.0;
        }
        let n = self.values.len() - 1;
        let at = (x - self.lo) / self.width();
        let i = (at as usize).min(n - 1);
        lerp(self.values[i], self.values[i + 1], at - i as f32)
    }
}

/// The point `(1 − t) a + t b`.
#[inline]
pub(super) fn lerp(a: f32, b: f32, t: f32) -> f32 {
    a + (b - a) * t
}

/// The point `t` of [0, 1] where the density proportional to
/// `lerp(a, b, t)` (`a`, `b` ≥ 0) has the cumulative probability `s`: the
/// root of the quadratic written without dividing by `b − a`, so that it
/// holds for equal ends and for an end at 0. Uniform if both ends are 0.
#[inline]
pub(super) fn linear(a: f32, b: f32, s: f32) -> f32 {
    let denom = a + (a * a + s * (b * b - a * a)).max(0.0).sqrt();
    if denom > 0.0 {
        (s * (a + b) / denom).clamp(0.0, 1.0)
    } else {
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    /// Values with a zero segment, a rise and a fall over [−1, 1].
    const VALUES: [f32; 6] = [0.0, 0.0, 2.0, 0.5, 3.0, 1.0];

    /// The density is the interpolant over its integral: at the points the
    /// scaled values, linear between them, 0 outside, integrating to 1.
    #[test]
    fn the_density_is_the_normalised_interpolant() {
        let d = Linear1D::new(&VALUES, (-1.0, 1.0)).unwrap();
        // Segments of width 0.4: the integral is 0.4 times the sum of the
        // inner values plus half the ends.
        let total = 0.4 * (0.0 + 2.0 + 0.5 + 3.0 + 0.5 * (0.0 + 1.0));
        for (i, v) in VALUES.iter().enumerate() {
            let x = -1.0 + 0.4 * i as f32;
            assert!((d.pdf(x) - v / total).abs() < 1e-5, "value {i}");
        }
        assert!((d.pdf(-0.1) - 0.75 * 2.0 / total - 0.25 * 0.5 / total).abs() < 1e-5);
        assert_eq!(d.pdf(1.01), 0.0);
        assert_eq!(d.pdf(-1.01), 0.0);
        let n = 100_000;
        let integral: f64 = (0..n)
            .map(|k| f64::from(d.pdf(-1.0 + 2.0 * (k as f32 + 0.5) / n as f32)))
            .sum::<f64>()
            * 2.0
            / n as f64;
        assert!((integral - 1.0).abs() < 1e-4, "{integral}");
    }

    /// Pearson's χ² of 10⁶ samples in 50 bins against the density's
    /// integral over each (by the midpoint rule on sub-bins), below the
    /// 0.999 quantile; each sample's density is the one looked up. None
    /// lands on the zero segment.
    #[test]
    fn samples_follow_the_density() {
        use statrs::distribution::{ChiSquared, ContinuousCDF};
        let d = Linear1D::new(&VALUES, (-1.0, 1.0)).unwrap();
        let bins = 50;
        let mut counts = vec![0u32; bins];
        let mut rng = Rng::new(3);
        let n = 1_000_000;
        for _ in 0..n {
            let (x, pdf) = d.sample(rng.next_f32());
            assert!((-1.0..=1.0).contains(&x) && pdf > 0.0, "{x} {pdf}");
            assert!(x >= -0.6 - 1e-5, "{x} on the zero segment");
            assert!(
                (pdf - d.pdf(x)).abs() <= 1e-4 * pdf,
                "{pdf} vs {} at {x}",
                d.pdf(x)
            );
            counts[(((x + 1.0) / 2.0 * bins as f32) as usize).min(bins - 1)] += 1;
        }
        let sub = 64;
        let (mut stat, mut cells) = (0.0, 0usize);
        for (b, &c) in counts.iter().enumerate() {
            let e: f64 = (0..sub)
                .map(|k| {
                    let x = -1.0 + 2.0 * (b as f64 + (k as f64 + 0.5) / sub as f64) / bins as f64;
                    f64::from(d.pdf(x as f32))
                })
                .sum::<f64>()
                * 2.0
                / (bins * sub) as f64
                * n as f64;
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
        assert!(stat < q, "χ² {stat} (0.999 quantile {q})");
    }

    /// Too few values, a negative or NaN value, all zero, or an empty
    /// interval make no distribution.
    #[test]
    fn bad_tables_make_none() {
        assert!(Linear1D::new(&[1.0], (-1.0, 1.0)).is_none());
        assert!(Linear1D::new(&[1.0, -0.5], (-1.0, 1.0)).is_none());
        assert!(Linear1D::new(&[1.0, f32::NAN], (-1.0, 1.0)).is_none());
        assert!(Linear1D::new(&[0.0, 0.0, 0.0], (-1.0, 1.0)).is_none());
        assert!(Linear1D::new(&[1.0, 1.0], (1.0, 1.0)).is_none());
        assert!(Linear1D::new(&[0.0, 1.0], (-1.0, 1.0)).is_some());
    }
}
