//! Warps from the unit square `[0, 1)^2` to other domains, with their
//! densities.
//!
//! A warp turns a uniform 2D sample into a sample of a disk, sphere,
//! hemisphere, cone or triangle. Each `square_to_*` function comes with a
//! `*_pdf` giving the density of its output with respect to area (disk,
//! triangle) or solid angle (directions), which a Monte Carlo estimator
//! divides by. Directions are in a local frame whose `z` axis is the pole
//! (normal or cone axis); use [`Frame`](crate::math::Frame) to go to world
//! space. All warps are continuous and preserve stratification reasonably,
//! so they can be fed the stratified points of
//! [`Distribution`](super::Distribution) (mapped from `[-r, r]^2` to the unit
//! square).

use std::f32::consts::{FRAC_1_PI, FRAC_PI_2, FRAC_PI_4, PI, TAU};

use crate::math::{Vec2, Vec3};

/// The concentric map from the square to the unit disk: concentric squares
/// go to concentric circles. Uniform per area (pdf `1/π`), and unlike the
/// polar map `(sqrt(u), 2πv)` it keeps adjacent strata adjacent and compact,
/// so stratified samples stay well spread on the disk.
pub fn square_to_disk_concentric(p: Vec2) -> Vec2 {
    let a = 2.0 * p - Vec2::ONE;
    if a == Vec2::ZERO {
        return Vec2::ZERO;
    }
    let (r, theta) = if a.x.abs() > a.y.abs() {
        (a.x, FRAC_PI_4 * (a.y / a.x))
    } else {
        (a.y, FRAC_PI_2 - FRAC_PI_4 * (a.x / a.y))
    };
    let (sin, cos) = theta.sin_cos();
    r * Vec2::new(cos, sin)
}

/// Density per unit area of [`square_to_disk_concentric`]: `1/π` inside the
/// unit disk, 0 outside.
pub fn square_to_disk_concentric_pdf(p: Vec2) -> f32 {
    if p.length_squared() <= 1.0 {
        FRAC_1_PI
    } else {
        0.0
    }
}

/// Uniform direction on the unit sphere: `z` uniform in `[-1, 1]` (the band
/// of a sphere between two heights has an area proportional to their
/// difference, the hat-box theorem) and a uniform azimuth.
pub fn square_to_uniform_sphere(p: Vec2) -> Vec3 {
    let z = 1.0 - 2.0 * p.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let (sin, cos) = (TAU * p.y).sin_cos();
    Vec3::new(r * cos, r * sin, z)
}

/// Density per solid angle of [`square_to_uniform_sphere`]: `1 / (4π)`.
pub fn square_to_uniform_sphere_pdf(_v: Vec3) -> f32 {
    0.25 * FRAC_1_PI
}

/// Cosine-weighted direction on the hemisphere `z >= 0`: a uniform point on
/// the disk lifted to the hemisphere. The density `cos θ / π` cancels the
/// cosine of the rendering equation, which is why diffuse bounces use it.
pub fn square_to_cosine_hemisphere(p: Vec2) -> Vec3 {
    let d = square_to_disk_concentric(p);
    let z = (1.0 - d.length_squared()).max(0.0).sqrt();
    Vec3::new(d.x, d.y, z)
}

/// Density per solid angle of [`square_to_cosine_hemisphere`]: `cos θ / π`
/// for `z >= 0`, 0 below.
pub fn square_to_cosine_hemisphere_pdf(v: Vec3) -> f32 {
    v.z.max(0.0) * FRAC_1_PI
}

/// Uniform direction in the cone of half-angle `acos(cos_max)` around `z`:
/// `cos θ` uniform in `[cos_max, 1]` (the cap's area is linear in it). Used
/// for sampling a spherical light by the solid angle it subtends.
pub fn square_to_uniform_cone(p: Vec2, cos_max: f32) -> Vec3 {
    let cos = (1.0 - p.x) + p.x * cos_max;
    let sin = (1.0 - cos * cos).max(0.0).sqrt();
    let (s, c) = (TAU * p.y).sin_cos();
    Vec3::new(sin * c, sin * s, cos)
}

/// Density per solid angle of [`square_to_uniform_cone`]:
/// `1 / (2π (1 - cos_max))` inside the cone, 0 outside. A degenerate cone
/// (`cos_max = 1`) gives infinity: it is a single direction, a delta.
pub fn square_to_uniform_cone_pdf(v: Vec3, cos_max: f32) -> f32 {
    if v.z >= cos_max {
        1.0 / (2.0 * PI * (1.0 - cos_max))
    } else {
        0.0
    }
}

/// Uniform barycentric coordinates `(b0, b1)` (with `b2 = 1 - b0 - b1`) on a
/// triangle: `b0 = 1 - sqrt(u)` makes the density of `b0` fall linearly
/// toward vertex 0, as the triangle's width does.
pub fn square_to_triangle(p: Vec2) -> (f32, f32) {
    let s = p.x.sqrt();
    (1.0 - s, p.y * s)
}

/// Density of [`square_to_triangle`] per unit area of the barycentric
/// triangle `b0, b1 >= 0, b0 + b1 <= 1` (area 1/2): 2 inside, 0 outside.
/// For a real triangle divide by its area over 1/2, i.e. use `1 / area`.
pub fn square_to_triangle_pdf(b: (f32, f32)) -> f32 {
    let (b0, b1) = b;
    if b0 >= 0.0 && b1 >= 0.0 && b0 + b1 <= 1.0 {
        2.0
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    // 99.9% quantiles of chi-square (standard tables) for the degrees of
    // freedom below; fixed seeds keep the tests deterministic.
    const CHI2_999_DF9: f64 = 27.877;
    const CHI2_999_DF11: f64 = 31.264;
    const CHI2_999_DF35: f64 = 66.619;

    const N: usize = 100_000;

    fn samples(seed: u64) -> impl Iterator<Item = Vec2> {
        let mut rng = Rng::new(seed);
        (0..N).map(move |_| {
            let x = rng.next_f32();
            Vec2::new(x, rng.next_f32())
        })
    }

    /// Chi-square of values in `[0, 1)` over `bins` equal bins.
    fn chi2_unit(values: impl Iterator<Item = f32>, bins: usize) -> f64 {
        let mut counts = vec![0u64; bins];
        for v in values {
            counts[((v * bins as f32) as usize).min(bins - 1)] += 1;
        }
        let expected = counts.iter().sum::<u64>() as f64 / bins as f64;
        let sq = |c: &u64| (*c as f64 - expected).powi(2) / expected;
        counts.iter().map(sq).sum()
    }

    fn azimuth01(x: f32, y: f32) -> f32 {
        y.atan2(x).rem_euclid(TAU) / TAU
    }

    #[test]
    fn concentric_disk_is_in_range_and_uniform() {
        for p in samples(1) {
            let d = square_to_disk_concentric(p);
            assert!(d.length() <= 1.0 + 1e-6, "{p:?} -> {d:?}");
            assert!(square_to_disk_concentric_pdf(d) > 0.0);
        }
        // Equal-area cells: 6 rings at radius sqrt(k/6) x 6 sectors.
        let cell = |d: Vec2| {
            let ring = ((d.length_squared() * 6.0) as usize).min(5);
            ring * 6 + ((azimuth01(d.x, d.y) * 6.0) as usize).min(5)
        };
        let values = samples(2).map(|p| (cell(square_to_disk_concentric(p)) as f32 + 0.5) / 36.0);
        let c = chi2_unit(values, 36);
        assert!(c < CHI2_999_DF35, "chi2 = {c}");
        assert_eq!(square_to_disk_concentric(Vec2::splat(0.5)), Vec2::ZERO);
        assert_eq!(square_to_disk_concentric_pdf(Vec2::new(1.0, 1.0)), 0.0);
    }

    #[test]
    fn sphere_is_unit_and_uniform() {
        let v: Vec<Vec3> = samples(3).map(square_to_uniform_sphere).collect();
        assert!(v.iter().all(|d| (d.length() - 1.0).abs() < 1e-5));
        let cz = chi2_unit(v.iter().map(|d| 0.5 * (d.z + 1.0)), 10);
        let cphi = chi2_unit(v.iter().map(|d| azimuth01(d.x, d.y)), 12);
        assert!(cz < CHI2_999_DF9 && cphi < CHI2_999_DF11, "{cz} {cphi}");
        assert!((square_to_uniform_sphere_pdf(Vec3::Z) * 4.0 * PI - 1.0).abs() < 1e-6);
    }

    #[test]
    fn cosine_hemisphere_is_unit_upper_and_cosine_weighted() {
        let v: Vec<Vec3> = samples(4).map(square_to_cosine_hemisphere).collect();
        assert!(v
            .iter()
            .all(|d| (d.length() - 1.0).abs() < 1e-5 && d.z >= 0.0));
        // With density cos θ / π, sin²θ = 1 - z² is uniform in [0, 1].
        let c = chi2_unit(v.iter().map(|d| 1.0 - d.z * d.z), 10);
        assert!(c < CHI2_999_DF9, "chi2 = {c}");
        assert_eq!(square_to_cosine_hemisphere_pdf(-Vec3::Z), 0.0);
    }

    #[test]
    fn cone_stays_inside_and_is_uniform() {
        for cos_max in [-0.5, 0.0, 0.5, 0.99] {
            let v: Vec<Vec3> = samples(5)
                .map(|p| square_to_uniform_cone(p, cos_max))
                .collect();
            assert!(v.iter().all(|d| (d.length() - 1.0).abs() < 1e-5));
            assert!(v.iter().all(|d| d.z >= cos_max - 1e-6 && d.z <= 1.0));
            let c = chi2_unit(v.iter().map(|d| (1.0 - d.z) / (1.0 - cos_max)), 10);
            assert!(c < CHI2_999_DF9, "cos_max {cos_max}: chi2 = {c}");
            let inside = square_to_uniform_cone_pdf(Vec3::Z, cos_max);
            assert!((inside * 2.0 * PI * (1.0 - cos_max) - 1.0).abs() < 1e-5);
        }
        assert_eq!(square_to_uniform_cone_pdf(-Vec3::Z, 0.5), 0.0);
    }

    /// Each pdf integrates to 1 over the sphere: the mean of `pdf(v) * 4π`
    /// over uniform directions is 1.
    #[test]
    fn direction_pdfs_integrate_to_one() {
        let v: Vec<Vec3> = samples(6).map(square_to_uniform_sphere).collect();
        let mean = |f: &dyn Fn(Vec3) -> f32| {
            v.iter().map(|&d| f64::from(f(d))).sum::<f64>() * 4.0 * f64::from(PI) / N as f64
        };
        assert!((mean(&square_to_cosine_hemisphere_pdf) - 1.0).abs() < 0.02);
        assert!((mean(&|d| square_to_uniform_cone_pdf(d, 0.3)) - 1.0).abs() < 0.02);
    }

    #[test]
    fn triangle_barycentrics_are_valid_and_uniform() {
        let b: Vec<(f32, f32)> = samples(7).map(square_to_triangle).collect();
        assert!(
            b.iter().all(|&t| square_to_triangle_pdf(t) == 2.0),
            "outside"
        );
        // Uniform on the triangle: (1 - b0)^2 is uniform, and so is
        // b1 / (1 - b0) (the position across the strip at height b0).
        let c0 = chi2_unit(b.iter().map(|&(b0, _)| (1.0 - b0).powi(2)), 10);
        let c1 = chi2_unit(b.iter().map(|&(b0, b1)| b1 / (1.0 - b0).max(1e-12)), 10);
        assert!(c0 < CHI2_999_DF9 && c1 < CHI2_999_DF9, "{c0} {c1}");
        assert_eq!(square_to_triangle_pdf((0.8, 0.8)), 0.0);
    }
}
