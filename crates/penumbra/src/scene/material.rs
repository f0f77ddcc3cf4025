//! A material as the scene describes it: validated parameters, no behaviour.
//! The bsdf layer turns each into the models that shade it.
//!
//! The thesis's material is a layered one: a local part (Lambertian base and
//! an energy-normalised Phong highlight) weighted by `1 − reflectivity −
//! transparency`, a mirror weighted by `reflectivity`, and a Fresnel
//! dielectric weighted by `transparency`; validation keeps the local weight
//! non-negative and `albedo + specular ≤ 1` per channel.

use crate::math::Rgb;
use crate::sampling::Distribution;

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
}
