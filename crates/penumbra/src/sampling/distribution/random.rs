//! `random`: independent points uniform *per area* over the disk of radius
//! `r` (polar coordinates with radius `r * sqrt(u)`). No guarantee of
//! spread: a set may clump in one part of the disk. Points lie within `r`
//! up to a relative rounding error of about `1e-7`. Shutter times are
//! independent uniform values.
//!
//! The thesis's Listing 3.5 draws `rad = RND() * radius`, a radius uniform
//! in `[0, r]`. The density per unit area is then proportional to
//! `1 / rad`: half of the points fall within `r/2`, a quarter of the disk's
//! area, and the centre is heavily oversampled. The text (§2.4) wants "the
//! same probability for all locations", which needs `rad = r * sqrt(RND())`.
//! (The listing's `VECTOR_DOTPRODUCT(u, uCoord)` is meant as scaling the
//! vector `u` by `uCoord`; its angle in degrees is fine.)

use std::f32::consts::TAU;

use crate::math::Vec3;
use crate::sampling::{PointTable, Rng};

use super::model::{shuffle, DistributionModel, Domain};

/// The `random` distribution; see the [module docs](self).
#[derive(Clone, Copy, Debug)]
pub struct Random;

/// Uniform per area in the disk: radius `r * sqrt(u)` (not `r * u`, which
/// would crowd the centre; see the module docs).
fn disk(radius: f32, rng: &mut Rng) -> Vec3 {
    let rho = radius * rng.next_f32().sqrt();
    let (sin, cos) = (TAU * rng.next_f32()).sin_cos();
    Vec3::new(rho * cos, rho * sin, 0.0)
}

/// Independent uniform values in `[0, 1)`, shuffled (as the other
/// distributions' times are; the shuffle of independent values changes
/// nothing but the draws it takes).
pub(super) fn independent_1d(count: usize, rng: &mut Rng, out: &mut Vec<f32>) {
    out.extend((0..count).map(|_| rng.next_f32()));
    shuffle(out, rng);
}

impl DistributionModel for Random {
    const NAME: &'static str = "random";
    const THESIS: bool = true;
    const DOMAIN: Domain = Domain::Disk;

    fn generate(_: &PointTable, count: usize, radius: f32, rng: &mut Rng, out: &mut Vec<Vec3>) {
        out.extend((0..count).map(|_| disk(radius, rng)));
    }

    fn one(_: &PointTable, radius: f32, rng: &mut Rng) -> Vec3 {
        disk(radius, rng)
    }

    fn generate_1d(_: &PointTable, count: usize, rng: &mut Rng, out: &mut Vec<f32>) {
        independent_1d(count, rng, out);
    }
}

#[cfg(test)]
mod tests {
    use std::f32::consts::TAU;

    use super::super::testing::{chi2, gen, CHI2_999_DF11, CHI2_999_DF9};
    use super::super::Distribution;
    use crate::math::Vec3;
    use crate::sampling::Rng;

    /// Chi-square over 10 equal-area rings and over 12 angular sectors.
    fn disk_chi2(points: &[Vec3], r: f32) -> (f64, f64) {
        let (mut rings, mut sectors) = ([0u64; 10], [0u64; 12]);
        for p in points {
            // Ring k holds radii in [r sqrt(k/10), r sqrt((k+1)/10)).
            let ring = ((p.length() / r).powi(2) * 10.0) as usize;
            rings[ring.min(9)] += 1;
            let angle = p.y.atan2(p.x).rem_euclid(TAU);
            sectors[((angle / TAU * 12.0) as usize).min(11)] += 1;
        }
        (chi2(&rings), chi2(&sectors))
    }

    #[test]
    fn random_is_uniform_per_area() {
        let r = 2.0;
        let points: Vec<Vec3> = (0..6000)
            .flat_map(|seed| gen(Distribution::Random, 16, r, seed))
            .collect();
        let (rings, sectors) = disk_chi2(&points, r);
        println!("random: rings chi2 (9 dof) = {rings:.1}, sectors chi2 (11 dof) = {sectors:.1}");
        assert!(rings < CHI2_999_DF9, "rings chi2 = {rings}");
        assert!(sectors < CHI2_999_DF11, "sectors chi2 = {sectors}");
        // Power check: Listing 3.5's radius `RND() * radius` fails the rings.
        let mut rng = Rng::new(9);
        let listing: Vec<Vec3> = (0..points.len())
            .map(|_| {
                let (rho, phi) = (r * rng.next_f32(), TAU * rng.next_f32());
                Vec3::new(rho * phi.cos(), rho * phi.sin(), 0.0)
            })
            .collect();
        let (rings, _) = disk_chi2(&listing, r);
        assert!(rings > 100.0 * CHI2_999_DF9, "listing passed: {rings}");
    }
}
