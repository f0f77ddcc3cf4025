//! A smooth dielectric interface (glass, water) weighted by the material's
//! transparency: Fresnel-weighted perfect reflection and refraction. The
//! thesis blurs both by sets of rays around the perfect directions with
//! radius `translucency`, drawn by the integrator from `effect`.

use super::sample::{BsdfFlags, BsdfSample};
use crate::math::{reflect, refract, Rgb, Vec3};
use crate::scene::EffectSpec;

#[derive(Clone, Copy, Debug)]
pub struct Dielectric {
    pub transparency: f32,
    /// Index of refraction of the inside (the side the normal points away from).
    pub ior: f32,
    /// Radius of the distributions around the perfect directions; 0 is clear.
    pub translucency: f32,
    /// Rays per refraction (and Fresnel reflection) and their distribution.
    pub effect: EffectSpec,
}

/// The perfect directions at an interface and the Fresnel reflectance.
#[derive(Clone, Copy, Debug)]
pub struct Split {
    /// Fraction reflected (1 under total internal reflection).
    pub fresnel: f32,
    pub reflected: Vec3,
    /// `None` under total internal reflection.
    pub refracted: Option<Vec3>,
}

impl Dielectric {
    pub fn flags(&self) -> BsdfFlags {
        let blur = if self.translucency > 0.0 {
            BsdfFlags::GLOSSY
        } else {
            BsdfFlags::empty()
        };
        BsdfFlags::DELTA | BsdfFlags::REFLECTION | BsdfFlags::TRANSMISSION | blur
    }

    /// The interface seen along the unit direction `d` (toward the surface),
    /// with the unit normal `n` on the viewer's side; `front` if the viewer
    /// is outside.
    #[inline]
    pub fn split(&self, d: Vec3, n: Vec3, front: bool) -> Split {
        let eta = if front { 1.0 / self.ior } else { self.ior };
        let cos_i = n.dot(-d).max(0.0);
        Split {
            fresnel: fresnel_dielectric(cos_i, eta),
            reflected: reflect(d, n),
            refracted: refract(d, n, eta),
        }
    }

    /// A delta lobe has no value for any pair of directions.
    pub fn eval(&self) -> Rgb {
        Rgb::ZERO
    }

    /// A delta lobe has no density.
    pub fn pdf(&self) -> f32 {
        0.0
    }

    /// Reflection with probability F, else refraction; `u` uniform in [0, 1).
    /// The weight is the transparency (F and 1 − F cancel against their
    /// probabilities); radiance scaling by η² is left out, as in the
    /// thesis's Whitted model.
    pub fn sample(&self, n: Vec3, wo: Vec3, front: bool, u: f32) -> Option<BsdfSample> {
        if self.transparency <= 0.0 {
            return None;
        }
        let s = self.split(-wo, n, front);
        let (wi, flags, pdf) = match s.refracted {
            Some(t) if u >= s.fresnel => (t, BsdfFlags::TRANSMISSION, 1.0 - s.fresnel),
            _ => (s.reflected, BsdfFlags::REFLECTION, s.fresnel),
        };
        Some(BsdfSample {
            wi,
            weight: Rgb::splat(self.transparency),
            pdf,
            flags: flags | BsdfFlags::DELTA,
        })
    }
}

/// Unpolarised Fresnel reflectance of a dielectric interface, for the cosine
/// of the incident angle and the ratio `eta = n_incident / n_transmitted`.
/// Returns 1 under total internal reflection.
pub fn fresnel_dielectric(cos_i: f32, eta: f32) -> f32 {
    let cos_i = cos_i.clamp(0.0, 1.0);
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let r_par = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    let r_perp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    0.5 * (r_par * r_par + r_perp * r_perp)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::{Distribution, Rng};

    #[test]
    fn fresnel_known_values() {
        // Normal incidence on glass: ((1 - 1.5) / (1 + 1.5))^2 = 0.04.
        assert!((fresnel_dielectric(1.0, 1.0 / 1.5) - 0.04).abs() < 1e-6);
        assert_eq!(fresnel_dielectric(0.1, 1.5), 1.0);
        assert!((fresnel_dielectric(0.0, 1.0 / 1.5) - 1.0).abs() < 1e-6);
    }

    /// Sampling reflects a fraction F of the time (binomial, 5 sigma).
    #[test]
    fn sampling_reflects_the_fresnel_fraction() {
        let g = Dielectric {
            transparency: 1.0,
            ior: 1.5,
            translucency: 0.0,
            effect: EffectSpec {
                rays: 1,
                distribution: Distribution::Grid,
            },
        };
        let wo = Vec3::new(0.8, 0.6, 0.0);
        let f = g.split(-wo, Vec3::Y, true).fresnel;
        let mut rng = Rng::new(9);
        let n = 100_000;
        let reflected = (0..n)
            .filter(|_| {
                let s = g.sample(Vec3::Y, wo, true, rng.next_f32()).unwrap();
                s.flags.contains(BsdfFlags::REFLECTION)
            })
            .count() as f32;
        let sigma = (n as f32 * f * (1.0 - f)).sqrt();
        assert!(
            (reflected - n as f32 * f).abs() < 5.0 * sigma,
            "{reflected} of {n}, F = {f}"
        );
    }
}
