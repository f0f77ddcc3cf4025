//! A cylinder light (an `area` emitter on a `cylinder`), one-sided,
//! emitting outward from the axis (inward with `flip_normals`) with
//! uniform radiance; sampled uniformly over its area: `φ = 2π u₁`,
//! `z = length · u₂` for a point `(u₁, u₂)` of the unit square.

use crate::emitter::sample::{area_sample, LightSample};
use crate::geometry::Cylinder;
use crate::math::{Rgb, Vec3};
use crate::sampling::points::unit_square;
use crate::sampling::Distribution;

/// A uniform point of the tube for the distribution point `point`, and
/// its emitting side's normal.
#[inline]
pub(super) fn sample(
    power: Rgb,
    c: &Cylinder,
    inward: bool,
    p: Vec3,
    point: Vec3,
    d: Distribution,
) -> Option<LightSample> {
    let u = unit_square(point, d);
    let (target, out) = c.point(u.x, u.y);
    let n = if inward { -out } else { out };
    area_sample(power, p, target, n, c.area(), false)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    /// The light's samples fall uniformly in its (φ, z) parameters: a χ²
    /// test over a 16 × 8 grid of 64,000 samples drawn from the axis
    /// (inward, where every sample is seen), by `random` points (uniform
    /// in the unit disk). 127 degrees of freedom, bound at the 0.999
    /// quantile (181.9). Against counts expected 10% denser toward one end
    /// the same samples fail: the test can tell.
    #[test]
    fn samples_are_uniform_in_area() {
        let c = Cylinder::new(Vec3::new(0.2, -0.3, 0.1), Vec3::new(1.0, 1.5, -0.4), 0.7).unwrap();
        let (nphi, nz, n) = (16, 8, 64_000);
        let mid = c.base + 0.5 * c.length * c.frame.n;
        let mut counts = vec![0u32; nphi * nz];
        let mut rng = Rng::new(7);
        let mut drawn = 0;
        while drawn < n {
            let point = Vec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), 0.0);
            if point.length_squared() >= 1.0 {
                continue;
            }
            let s = sample(Rgb::ONE, &c, true, mid, point, Distribution::Random)
                .expect("seen from the axis");
            let g = c.geometry(s.target - c.base);
            let i = ((g.uv.x * nphi as f32) as usize).min(nphi - 1);
            let j = ((g.uv.y * nz as f32) as usize).min(nz - 1);
            counts[j * nphi + i] += 1;
            drawn += 1;
        }
        let chi2 = |expected: &dyn Fn(usize) -> f64| {
            (0..nphi * nz)
                .map(|k| (counts[k] as f64 - expected(k)).powi(2) / expected(k))
                .sum::<f64>()
        };
        let cell = n as f64 / (nphi * nz) as f64;
        let uniform = chi2(&|_| cell);
        assert!(uniform < 181.9, "χ² = {uniform}");
        // 1 ± 10% from one end to the other (the same total).
        let tilted = chi2(&|k| {
            let z = ((k / nphi) as f64 + 0.5) / nz as f64;
            cell * (1.0 + 0.2 * (z - 0.5))
        });
        assert!(tilted > 181.9, "a wrong density passes: χ² = {tilted}");
    }

    /// A sample's weight is `L cos θ A / r²`, its target on the surface;
    /// seen from outside, the inward side gives nothing.
    #[test]
    fn weights_follow_the_geometry_term() {
        let c = Cylinder::new(Vec3::ZERO, Vec3::new(0.0, 0.0, 2.0), 0.5).unwrap();
        let p = Vec3::new(3.0, 0.2, 1.0);
        let point = Vec3::new(-0.9, 0.1, 0.0);
        let s = sample(Rgb::ONE, &c, false, p, point, Distribution::Grid).unwrap();
        let u = unit_square(point, Distribution::Grid);
        let (q, n) = c.point(u.x, u.y);
        assert!((s.target - q).length() < 1e-6);
        let to = q - p;
        let want = n.dot(-to.normalize()) * c.area() / to.length_squared();
        assert!(
            (s.weight.r - want).abs() < 1e-4 * want,
            "{:?} vs {want}",
            s.weight
        );
        assert!(sample(Rgb::ONE, &c, true, p, point, Distribution::Grid).is_none());
    }
}
