//! `fast-random`: independent points uniform in the cube `[-r, r]^3`, to be
//! added to a ray's end point in world axes, without building a frame (the
//! thesis's Listing 3.6, followed exactly, including its bias). Cheaper,
//! but the resulting *directions* are not uniform: the cube is aligned
//! with the world axes, not with the ray, so the spread depends on the
//! ray's direction, and seen along a ray its cross-section is a square or a
//! hexagon rather than a disk (more rays toward its corners). Only this
//! distribution returns a non-zero `z`; see
//! [`Distribution::is_3d`](super::Distribution::is_3d). Shutter times are
//! independent uniform values (time has no direction to bias).

use crate::math::Vec3;
use crate::sampling::{PointTable, Rng};

use super::model::{to_radius, DistributionModel, Domain};
use super::random::independent_1d;

/// The `fast-random` distribution; see the [module docs](self).
#[derive(Clone, Copy, Debug)]
pub struct FastRandom;

fn cube(radius: f32, rng: &mut Rng) -> Vec3 {
    let x = to_radius(rng.next_f32(), radius);
    let y = to_radius(rng.next_f32(), radius);
    Vec3::new(x, y, to_radius(rng.next_f32(), radius))
}

impl DistributionModel for FastRandom {
    const NAME: &'static str = "fast-random";
    const ALIASES: &'static [&'static str] = &["fastrandom"];
    const THESIS: bool = true;
    const DOMAIN: Domain = Domain::Cube;

    fn generate(_: &PointTable, count: usize, radius: f32, rng: &mut Rng, out: &mut Vec<Vec3>) {
        out.extend((0..count).map(|_| cube(radius, rng)));
    }

    fn one(_: &PointTable, radius: f32, rng: &mut Rng) -> Vec3 {
        cube(radius, rng)
    }

    fn generate_1d(_: &PointTable, count: usize, rng: &mut Rng, out: &mut Vec<f32>) {
        independent_1d(count, rng, out);
    }
}

#[cfg(test)]
mod tests {
    use super::super::testing::gen;
    use super::super::Distribution;
    use crate::math::{Frame, Vec3};

    /// Angles (polar from the ray, azimuth) of the directions `end + offset`
    /// for a ray along `axis`, in the ray's own frame.
    fn angles(axis: Vec3, offsets: &[Vec3]) -> Vec<(f32, f32)> {
        let frame = Frame::from_normal(axis);
        offsets
            .iter()
            .map(|&o| {
                let l = frame.to_local(axis + o);
                (l.truncate().length().atan2(l.z), l.y.atan2(l.x))
            })
            .collect()
    }

    fn mean_polar(a: &[(f32, f32)]) -> f64 {
        a.iter().map(|&(t, _)| f64::from(t)).sum::<f64>() / a.len() as f64
    }

    /// Fraction of azimuths within 22.5 degrees of a diagonal of the frame.
    fn diagonal_fraction(a: &[(f32, f32)]) -> f64 {
        let quarter = std::f32::consts::FRAC_PI_2;
        let near = |phi: f32| (phi.rem_euclid(quarter) - quarter / 2.0).abs() < quarter / 4.0;
        a.iter().filter(|&&(_, p)| near(p)).count() as f64 / a.len() as f64
    }

    #[test]
    fn fast_random_directions_are_biased() {
        let (r, sets) = (0.25, 12_500);
        let pool = |d: Distribution| -> Vec<Vec3> {
            (0..sets).flat_map(|seed| gen(d, 16, r, seed)).collect()
        };
        let (fast, disk) = (pool(Distribution::FastRandom), pool(Distribution::Random));
        let z = Vec3::Z;
        let diagonal = Vec3::ONE.normalize();
        // The 2D disk is applied in the ray's frame, the cube in world axes.
        let fast_z = angles(z, &fast);
        let fast_diag = angles(diagonal, &fast);
        let disk_z = angles(z, &disk);
        let within = |a: &[(f32, f32)]| {
            a.iter().filter(|&&(t, _)| t < (r / 2.0).atan()).count() as f64 / a.len() as f64
        };
        println!("n = {} directions, r = {r}, unit ray", fast.len());
        println!(
            "mean angle: random {:.4}, fast-random along z {:.4}, along diagonal {:.4}",
            mean_polar(&disk_z),
            mean_polar(&fast_z),
            mean_polar(&fast_diag)
        );
        println!(
            "within atan(r/2): random {:.4} (exact 0.25), fast-random along z {:.4}",
            within(&disk_z),
            within(&fast_z)
        );
        println!("azimuth near a diagonal: random {:.4} (exact 0.5), fast-random along z {:.4} (square: 0.586)",
            diagonal_fraction(&disk_z), diagonal_fraction(&fast_z));
        // Standard errors are ~0.0013 for the fractions and ~1e-4 for the means.
        assert!((within(&disk_z) - 0.25).abs() < 0.006);
        assert!((diagonal_fraction(&disk_z) - 0.5).abs() < 0.006);
        assert!(diagonal_fraction(&fast_z) > 0.56, "no azimuthal bias");
        assert!(within(&fast_z) < 0.22, "no radial bias");
        let (along_z, along_diag) = (mean_polar(&fast_z), mean_polar(&fast_diag));
        assert!(
            (along_z - along_diag).abs() > 0.005,
            "spread independent of direction"
        );
    }
}
