//! Pixel filters: how much a sample at an offset from a pixel's centre
//! counts toward that pixel.
//!
//! A filter is applied by importance sampling, as pbrt-v4 does: the film
//! points a pixel's distribution gives in `[-1/2, 1/2]²` are warped, axis by
//! axis, through the inverse of the filter's cumulative distribution, so
//! that samples land with a density proportional to the filter; the pixel
//! is then the plain mean of its samples (every filter here is separable
//! and non-negative, so each sample's weight is one). The warp is monotone,
//! so a stratified set stays stratified. The box filter of radius 1/2, the
//! thesis's supersampling over the pixel, leaves the points as they are.
//!
//! | name | profile `f(x)` on `|x| ≤ r` | radius `r` |
//! |---|---|---|
//! | `box` | 1 | 1/2 |
//! | `tent` | `r − |x|` | 1 |
//! | `gaussian` | `exp(−x²/2σ²) − exp(−r²/2σ²)`, σ = 1/2 | 3σ = 3/2 |

use std::sync::OnceLock;

/// A pixel filter; see the [module docs](self).
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Deserialize, serde::Serialize,
)]
#[serde(rename_all = "kebab-case")]
pub enum Filter {
    #[default]
    Box,
    Tent,
    Gaussian,
}

/// The Gaussian's standard deviation, in pixels.
const SIGMA: f32 = 0.5;

/// Cells of the tabulated inverse of the Gaussian's distribution.
const CELLS: usize = 1024;

impl Filter {
    pub const ALL: [Filter; 3] = [Filter::Box, Filter::Tent, Filter::Gaussian];

    /// The name users write (the serde name too).
    pub fn name(self) -> &'static str {
        match self {
            Filter::Box => "box",
            Filter::Tent => "tent",
            Filter::Gaussian => "gaussian",
        }
    }

    pub fn from_name(s: &str) -> Option<Filter> {
        Filter::ALL.into_iter().find(|f| f.name() == s)
    }

    /// How far from the pixel's centre a sample may land, in pixels.
    pub fn radius(self) -> f32 {
        match self {
            Filter::Box => 0.5,
            Filter::Tent => 1.0,
            Filter::Gaussian => 3.0 * SIGMA,
        }
    }

    /// The filter's profile along one axis (not normalised); 0 beyond the
    /// radius.
    pub fn eval(self, x: f32) -> f32 {
        let r = self.radius();
        if x.abs() > r {
            return 0.0;
        }
        match self {
            Filter::Box => 1.0,
            Filter::Tent => r - x.abs(),
            Filter::Gaussian => gaussian(x) - gaussian(r),
        }
    }

    /// The offset from the pixel's centre, along one axis, of the film point
    /// coordinate `p` in `[-1/2, 1/2]`: distributed in `[-r, r]` with a
    /// density proportional to [`eval`](Self::eval) when `p` is uniform, and
    /// increasing in `p`. The box filter returns `p` itself.
    #[inline]
    pub fn warp(self, p: f32) -> f32 {
        if self == Filter::Box {
            return p;
        }
        let u = (p + 0.5).clamp(0.0, 1.0);
        match self {
            Filter::Box => p,
            Filter::Tent => {
                if u < 0.5 {
                    (2.0 * u).sqrt() - 1.0
                } else {
                    1.0 - (2.0 * (1.0 - u)).sqrt()
                }
            }
            Filter::Gaussian => gaussian_inverse(u),
        }
    }
}

fn gaussian(x: f32) -> f32 {
    (-x * x / (2.0 * SIGMA * SIGMA)).exp()
}

/// The inverse of the truncated Gaussian's cumulative distribution at `u`,
/// by linear interpolation in a table of its values at the cells' ends
/// (the distribution integrated cell by cell in `f64`).
fn gaussian_inverse(u: f32) -> f32 {
    static CDF: OnceLock<Vec<f64>> = OnceLock::new();
    let r = f64::from(Filter::Gaussian.radius());
    let cdf = CDF.get_or_init(|| {
        let f = |x: f64| {
            let s = f64::from(SIGMA);
            (-x * x / (2.0 * s * s)).exp() - (-r * r / (2.0 * s * s)).exp()
        };
        let h = 2.0 * r / CELLS as f64;
        let mut cdf = Vec::with_capacity(CELLS + 1);
        let mut sum = 0.0;
        cdf.push(0.0);
        for i in 0..CELLS {
            // Simpson's rule over the cell.
            let x0 = -r + i as f64 * h;
            sum += h / 6.0 * (f(x0) + 4.0 * f(x0 + 0.5 * h) + f(x0 + h));
            cdf.push(sum);
        }
        cdf.iter().map(|c| c / sum).collect()
    });
    let u = f64::from(u);
    // The cell whose ends bracket u.
    let i = cdf.partition_point(|&c| c <= u).clamp(1, CELLS) - 1;
    let (c0, c1) = (cdf[i], cdf[i + 1]);
    let t = if c1 > c0 { (u - c0) / (c1 - c0) } else { 0.5 };
    let h = 2.0 * r / CELLS as f64;
    (-r + (i as f64 + t.clamp(0.0, 1.0)) * h) as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each warp is increasing, stays within the radius, maps the ends of
    /// the film square to the ends of the filter and its centre to 0.
    #[test]
    fn warps_are_monotone_within_the_radius() {
        for f in Filter::ALL {
            let r = f.radius();
            let mut last = f32::NEG_INFINITY;
            for k in 0..=10_000 {
                let x = f.warp(k as f32 / 10_000.0 - 0.5);
                assert!(x >= last && x.abs() <= r + 1e-6, "{f:?} at {k}: {x}");
                last = x;
            }
            assert!((f.warp(-0.5) + r).abs() < 1e-3 && (f.warp(0.5) - r).abs() < 1e-3);
            assert!(f.warp(0.0).abs() < 1e-3, "{f:?}");
        }
        // The box leaves film points as they are, bit for bit.
        for p in [-0.5, -0.123_456_7, 0.0, 1e-9, 0.499_999_9] {
            assert_eq!(Filter::Box.warp(p).to_bits(), f32::to_bits(p));
        }
    }

    /// Uniform points warped by each filter fall into 40 bins as often as
    /// the filter's integral over each bin says (χ² against the expected
    /// counts, 39 degrees of freedom, well below the 0.1% critical value).
    #[test]
    fn warped_points_follow_the_filter() {
        let n = 200_000;
        for f in Filter::ALL {
            let r = f.radius();
            let bins = 40;
            let width = 2.0 * r / bins as f32;
            let mut counts = vec![0u32; bins];
            for k in 0..n {
                let p = (k as f32 + 0.5) / n as f32 - 0.5;
                let x = f.warp(p);
                let b = (((x + r) / width) as usize).min(bins - 1);
                counts[b] += 1;
            }
            // Expected counts from the profile integrated by the midpoint rule.
            let mass: Vec<f64> = (0..bins)
                .map(|b| {
                    (0..100)
                        .map(|j| {
                            let x = -r + (b as f32 + (j as f32 + 0.5) / 100.0) * width;
                            f64::from(f.eval(x))
                        })
                        .sum::<f64>()
                })
                .collect();
            let total: f64 = mass.iter().sum();
            let chi2: f64 = counts
                .iter()
                .zip(&mass)
                .filter(|(_, m)| **m > 0.0)
                .map(|(&c, m)| {
                    let e = m / total * n as f64;
                    (f64::from(c) - e).powi(2) / e
                })
                .sum();
            assert!(chi2 < 72.0, "{f:?}: chi2 {chi2}");
        }
    }

    #[test]
    fn names_round_trip() {
        for f in Filter::ALL {
            assert_eq!(Filter::from_name(f.name()), Some(f));
        }
        assert_eq!(Filter::from_name("mitchell"), None);
    }
}
