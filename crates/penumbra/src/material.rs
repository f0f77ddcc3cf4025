//! Surface materials: a Lambertian base with an energy-normalised Phong
//! highlight, plus mirror reflection and Fresnel-weighted refraction, each of
//! which the distributed integrator blurs by tracing several rays.
//!
//! Energy is conserved by construction: the local (diffuse + highlight) part is
//! weighted by `1 − reflectivity − transparency`, validation keeps that weight
//! non-negative and `albedo + specular ≤ 1` per channel, and the normalised
//! Phong lobe integrates to at most `specular`.

use std::f32::consts::PI;

use crate::math::Vec3;
use crate::sampling::Distribution;

/// Linear RGB radiance or reflectance.
pub type Rgb = Vec3;

/// How many rays an effect traces and how they are distributed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct EffectSpec {
    pub rays: u32,
    pub distribution: Distribution,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    pub albedo: Rgb,
    pub specular: f32,
    pub shininess: f32,
    pub reflectivity: f32,
    pub transparency: f32,
    pub ior: f32,
    pub emission: Rgb,
    /// Radius of the reflection distribution (thesis §3.3); 0 is a perfect mirror.
    pub glossiness: f32,
    /// Radius of the refraction distribution; 0 is clear glass.
    pub translucency: f32,
    pub reflection: EffectSpec,
    pub refraction: EffectSpec,
}

impl Material {
    /// Weight of the local (diffuse + highlight) shading.
    pub fn local_weight(&self) -> f32 {
        (1.0 - self.reflectivity - self.transparency).max(0.0)
    }

    /// True if direct lighting contributes at all.
    pub fn is_lit(&self) -> bool {
        self.local_weight() > 0.0 && (self.albedo.max_element() > 0.0 || self.specular > 0.0)
    }

    /// True if the material reflects or refracts rays (mirror, gloss, glass).
    pub fn scatters(&self) -> bool {
        self.reflectivity > 0.0 || self.transparency > 0.0
    }

    /// The local BRDF for unit vectors `wo` (toward the viewer) and `wi`
    /// (toward the light) around the unit normal `n`, including `local_weight`.
    /// Diffuse is albedo/π; the highlight is the normalised Phong lobe
    /// `specular · (s + 2)/(2π) · cos^s α`, α between `wo` and the mirrored `wi`.
    #[inline]
    pub fn local_brdf(&self, n: Vec3, wo: Vec3, wi: Vec3) -> Rgb {
        self.shading().local_brdf(n, wo, wi)
    }

    /// What shading a hit needs of this material, worked out once.
    pub fn shading(&self) -> Shading {
        Shading {
            lit: self.is_lit(),
            scatters: self.scatters(),
            diffuse: self.albedo * (1.0 / PI),
            specular: self.specular,
            shininess: self.shininess,
            weight: self.local_weight(),
        }
    }
}

/// The parts of a [`Material`] that shading a hit reads, with the
/// derived values computed once per tracer (a tile) instead of at every
/// hit (a lit sample of the bunny scene reads `is_lit` three times).
#[derive(Clone, Copy, Debug)]
pub struct Shading {
    /// [`Material::is_lit`].
    pub lit: bool,
    /// [`Material::scatters`].
    pub scatters: bool,
    /// `albedo / π`.
    diffuse: Rgb,
    specular: f32,
    shininess: f32,
    /// [`Material::local_weight`].
    weight: f32,
}

impl Shading {
    /// The local BRDF of [`Material::local_brdf`], which calls this.
    #[inline]
    pub fn local_brdf(&self, n: Vec3, wo: Vec3, wi: Vec3) -> Rgb {
        let mut f = self.diffuse;
        if self.specular > 0.0 {
            let r = 2.0 * wi.dot(n) * n - wi;
            let cos_a = r.dot(wo).max(0.0);
            let s = self.shininess;
            f += Vec3::splat(self.specular * (s + 2.0) / (2.0 * PI) * cos_a.powf(s));
        }
        f * self.weight
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

    #[test]
    fn fresnel_known_values() {
        // Normal incidence on glass: ((1 - 1.5) / (1 + 1.5))^2 = 0.04.
        assert!((fresnel_dielectric(1.0, 1.0 / 1.5) - 0.04).abs() < 1e-6);
        assert_eq!(fresnel_dielectric(0.1, 1.5), 1.0);
        assert!((fresnel_dielectric(0.0, 1.0 / 1.5) - 1.0).abs() < 1e-6);
    }

    #[test]
    fn phong_lobe_does_not_create_energy() {
        // Albedo (directional) of the normalised lobe at normal incidence, by quadrature.
        let n = Vec3::Z;
        let m = Material {
            albedo: Vec3::ZERO,
            specular: 1.0,
            shininess: 20.0,
            reflectivity: 0.0,
            transparency: 0.0,
            ior: 1.5,
            emission: Vec3::ZERO,
            glossiness: 0.0,
            translucency: 0.0,
            reflection: EffectSpec {
                rays: 1,
                distribution: Distribution::Grid,
            },
            refraction: EffectSpec {
                rays: 1,
                distribution: Distribution::Grid,
            },
        };
        let (nt, np) = (400, 400);
        let mut sum = 0.0;
        for i in 0..nt {
            let theta = (i as f32 + 0.5) / nt as f32 * PI / 2.0;
            for j in 0..np {
                let phi = (j as f32 + 0.5) / np as f32 * 2.0 * PI;
                let wi = Vec3::new(
                    theta.sin() * phi.cos(),
                    theta.sin() * phi.sin(),
                    theta.cos(),
                );
                let f = m.local_brdf(n, n, wi).x;
                sum +=
                    f * theta.cos() * theta.sin() * (PI / 2.0 / nt as f32) * (2.0 * PI / np as f32);
            }
        }
        assert!(sum <= 1.0 && sum > 0.85, "directional albedo {sum}");
    }
}
