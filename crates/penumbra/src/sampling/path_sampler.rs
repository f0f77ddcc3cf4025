//! Path samplers: where the random numbers of a path's bounces come from
//! (`path_sampler`), as pbrt-v4's samplers supply every dimension of a
//! path.
//!
//! | name | numbers of bounce `b`, dimension `d` of the `i`-th sample of a pixel |
//! |---|---|
//! | `independent` (default) | the path's own stream, derived by the bounce: independent uniform numbers, drawn in order |
//! | `sobol`, `pmj02`, `pmj02bn`, `halton`, `r2` | point `π(i)` of a set of that distribution scrambled for (pixel, bounce, dimension), `π` a shuffle of the samples' order drawn for the same (pbrt-v4's padded samplers): the pixel's samples are one stratified set in every pair of dimensions, and the dimensions are not tied to one another |
//! | `zsobol` | point `i` of the pixel's block of one Sobol' sequence shared by the frame, the blocks ordered along a Morton curve (pbrt-v4's `ZSobolSampler`) |
//!
//! Each dimension of a bounce is a 2D set of its own: the integrator asks
//! for a pair (a light's point, a BSDF's point) or a single value (the
//! emitter choice, Russian roulette: the set's first coordinate) by its
//! number `d`. A set's scramble is keyed by the stream's [place](Rng#its-place-in-the-frame)
//! below the sample (its kind of branches and its pixel) and indexed by the
//! sample's number in the pixel, followed by the numbers of the splits the
//! path took ([`Rng::child`]); so every value is still a pure function of
//! (seed, pixel, sample, bounce, branch, dimension).
//!
//! The thesis's distributions (grid, jitter, semi-jitter, Poisson, random,
//! fast random) are sets of a given size, not sequences one can index: they
//! serve the camera sample and the thesis's sets, not the bounces of paths.

use super::{Distribution, Rng};
use crate::math::Vec2;

/// Where a path's per-bounce numbers come from; see the [module docs](self).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum PathSampler {
    #[default]
    Independent,
    /// One of the low-discrepancy sequences (`sobol`, `zsobol`, `pmj02`,
    /// `pmj02bn`, `halton`, `r2`).
    Sequence(Distribution),
}

impl PathSampler {
    /// Every path sampler, in the order the reference lists them:
    /// `independent`, then [`Distribution::SEQUENCES`].
    pub const ALL: [PathSampler; Distribution::SEQUENCES.len() + 1] = {
        let mut all = [PathSampler::Independent; Distribution::SEQUENCES.len() + 1];
        let mut i = 0;
        while i < Distribution::SEQUENCES.len() {
            all[i + 1] = PathSampler::Sequence(Distribution::SEQUENCES[i]);
            i += 1;
        }
        all
    };

    /// The names users write, in the order of [`ALL`](Self::ALL).
    pub const NAMES: [&'static str; Self::ALL.len()] = {
        let mut names = [""; Self::ALL.len()];
        let mut i = 0;
        while i < Self::ALL.len() {
            names[i] = Self::ALL[i].name();
            i += 1;
        }
        names
    };

    pub const fn name(self) -> &'static str {
        match self {
            PathSampler::Independent => "independent",
            PathSampler::Sequence(d) => d.name(),
        }
    }

    /// The sampler a user-written name means (a distribution's aliases
    /// included); `None` for other names.
    pub fn from_name(s: &str) -> Option<PathSampler> {
        if s.trim().eq_ignore_ascii_case("independent") {
            return Some(PathSampler::Independent);
        }
        let d = Distribution::from_name(s)?;
        Self::ALL
            .into_iter()
            .find(|&p| p == PathSampler::Sequence(d))
    }

    /// The numbers of one bounce of a path whose stream, derived by the
    /// bounce, is `stream`.
    #[inline]
    pub fn bounce(self, stream: Rng) -> BounceNumbers {
        BounceNumbers {
            sampler: self,
            stream,
        }
    }
}

/// The numbers of one bounce of one path (see [`PathSampler::bounce`]).
#[derive(Clone, Debug)]
pub struct BounceNumbers {
    sampler: PathSampler,
    stream: Rng,
}

impl BounceNumbers {
    /// The value of dimension `d` in `[0, 1)`. `independent` ignores `d`
    /// and draws the stream's next number: ask in a fixed order.
    #[inline]
    pub fn value(&mut self, d: u64) -> f32 {
        match self.sampler {
            PathSampler::Independent => self.stream.next_f32(),
            PathSampler::Sequence(s) => s.bounce_value(self.stream.derive(d).place()),
        }
    }

    /// The point of dimension pair `d` in `[0, 1)²` (for `independent`, the
    /// stream's next two numbers).
    #[inline]
    pub fn point(&mut self, d: u64) -> Vec2 {
        match self.sampler {
            PathSampler::Independent => {
                let x = self.stream.next_f32();
                Vec2::new(x, self.stream.next_f32())
            }
            PathSampler::Sequence(s) => s.bounce_point(self.stream.derive(d).place()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Sampler;

    #[test]
    fn names_round_trip() {
        for (p, name) in PathSampler::ALL.into_iter().zip(PathSampler::NAMES) {
            assert_eq!(p.name(), name);
            assert_eq!(PathSampler::from_name(name), Some(p));
        }
        assert_eq!(PathSampler::from_name("jitter"), None);
        assert_eq!(PathSampler::from_name("grid"), None);
        assert_eq!(PathSampler::from_name("nonsense"), None);
    }

    /// The stream of bounce `b` of sample `i` of pixel (x, y) of `n`.
    fn stream(seed: u64, (x, y): (u32, u32), i: usize, n: u32, b: u64) -> Rng {
        Sampler::new(seed, 64, n).pixel(x, y).path(i).derive(b)
    }

    /// The points of one dimension of a pixel's `n` samples.
    fn points(p: PathSampler, pixel: (u32, u32), n: u32, b: u64, d: u64) -> Vec<Vec2> {
        (0..n as usize)
            .map(|i| p.bounce(stream(7, pixel, i, n, b)).point(d))
            .collect()
    }

    /// Independent draws are the stream's own numbers, in order.
    #[test]
    fn independent_draws_the_streams_numbers_in_order() {
        let s = stream(3, (1, 2), 0, 4, 5);
        let mut n = PathSampler::Independent.bounce(s);
        let mut r = s;
        assert_eq!(n.value(9), r.next_f32());
        let p = n.point(0);
        assert_eq!((p.x, p.y), (r.next_f32(), r.next_f32()));
    }

    /// For each sequence and several pixels, bounces and dimensions, the
    /// 64 samples of a pixel put exactly one point in each of the 64
    /// columns and each of the 64 rows (a (0,6,2)-net in base 2; Halton's
    /// second coordinate is stratified in base 3, so only its first is
    /// checked). r2, a Kronecker sequence, spreads its points evenly
    /// without that guarantee: at least 40 columns hold exactly one, where
    /// independent numbers leave about 24 so.
    #[test]
    fn a_pixels_samples_are_stratified_in_every_dimension() {
        let n = 64;
        let columns = |pts: &[Vec2], axis: usize| {
            let mut seen = [0u32; 64];
            for p in pts {
                let v = if axis == 0 { p.x } else { p.y };
                seen[((v * 64.0) as usize).min(63)] += 1;
            }
            seen.iter().filter(|&&c| c == 1).count()
        };
        for p in PathSampler::ALL {
            for (pixel, b, d) in [((0, 0), 0, 0), ((5, 9), 3, 1), ((63, 2), 7, 4)] {
                let pts = points(p, pixel, n, b, d);
                match p {
                    PathSampler::Independent => assert!(columns(&pts, 0) < 40),
                    PathSampler::Sequence(Distribution::R2) => assert!(columns(&pts, 0) >= 40),
                    PathSampler::Sequence(Distribution::Halton) => {
                        assert_eq!(columns(&pts, 0), 64, "{}", p.name())
                    }
                    PathSampler::Sequence(_) => {
                        assert_eq!(columns(&pts, 0), 64, "{}", p.name());
                        assert_eq!(columns(&pts, 1), 64, "{}", p.name());
                    }
                }
            }
        }
    }

    /// Dimensions, bounces and pixels are scrambled apart: their points
    /// differ, and do not line up between two dimensions of one bounce.
    #[test]
    fn dimensions_bounces_and_pixels_are_decorrelated() {
        for p in &PathSampler::ALL[1..] {
            let a = points(*p, (1, 1), 16, 0, 0);
            for other in [
                points(*p, (1, 1), 16, 0, 1),
                points(*p, (1, 1), 16, 1, 0),
                points(*p, (2, 1), 16, 0, 0),
            ] {
                assert_ne!(a, other, "{}", p.name());
            }
            // The correlation of the x of dimension 0 and of dimension 1
            // over many samples is near 0.
            let n = 1024;
            let x0: Vec<f32> = points(*p, (3, 4), n, 2, 0).iter().map(|v| v.x).collect();
            let x1: Vec<f32> = points(*p, (3, 4), n, 2, 1).iter().map(|v| v.x).collect();
            let mean = |v: &[f32]| v.iter().sum::<f32>() / v.len() as f32;
            let (m0, m1) = (mean(&x0), mean(&x1));
            let cov: f32 = x0
                .iter()
                .zip(&x1)
                .map(|(a, b)| (a - m0) * (b - m1))
                .sum::<f32>()
                / n as f32;
            assert!((cov / (1.0 / 12.0)).abs() < 0.15, "{}: {cov}", p.name());
        }
    }

    /// Every value is in [0, 1) and uniform: the mean of many samples over
    /// many pixels is 1/2 within a few standard errors.
    #[test]
    fn values_are_uniform() {
        for p in PathSampler::ALL {
            let mut sum = 0.0f64;
            let mut count = 0;
            for x in 0..32 {
                for i in 0..16 {
                    let v = p.bounce(stream(11, (x, 0), i, 16, 1)).value(2);
                    assert!((0.0..1.0).contains(&v));
                    sum += f64::from(v);
                    count += 1;
                }
            }
            let mean = sum / count as f64;
            // Standard error of a uniform mean: sqrt(1/12 / 512) ≈ 0.0128.
            assert!((mean - 0.5).abs() < 0.05, "{}: {mean}", p.name());
        }
    }
}
