//! Surface scattering models: what a surface does with light, built from
//! the scene's material records.
//!
//! Every model answers the same four questions, through [`Bsdf`]: its value
//! for a pair of directions (`eval`, without the cosine), a direction drawn
//! from uniform numbers the caller supplies (`sample`, with the weight
//! `eval · cos / pdf` and the pdf), the density of drawing a direction
//! (`pdf`), and what kind of lobe it is (`flags`: diffuse, glossy, delta,
//! reflection, transmission). Models never own random numbers.
//!
//! A closed enum with one dispatch point (this file) rather than trait
//! objects: the set is known at compile time, a match on a small enum is
//! inlined into the shading loop, and a batch of hits of one material runs
//! one arm. Adding a model is one file and one variant here.
//!
//! The thesis's material is layered: [`Surface`] holds its local part
//! ([`Phong`]), its mirror ([`Mirror`]) and its dielectric ([`Dielectric`]),
//! each weighted as the material says.

mod dielectric;
mod mirror;
mod phong;
mod sample;

pub use dielectric::{fresnel_dielectric, Dielectric, Split};
pub use mirror::Mirror;
pub use phong::Phong;
pub use sample::{BsdfFlags, BsdfSample};

use crate::math::{Rgb, Vec2, Vec3};
use crate::scene::Material;

/// A scattering model.
#[derive(Clone, Copy, Debug)]
pub enum Bsdf {
    Phong(Phong),
    Mirror(Mirror),
    Dielectric(Dielectric),
}

/// Where a BSDF is asked: the unit shading normal on the viewer's side, the
/// unit direction toward the viewer, and whether the viewer is on the side
/// the geometric normal points to.
#[derive(Clone, Copy, Debug)]
pub struct ShadingFrame {
    pub n: Vec3,
    pub wo: Vec3,
    pub front: bool,
}

impl Bsdf {
    /// The value for light arriving from `wi`, without the cosine.
    pub fn eval(&self, f: &ShadingFrame, wi: Vec3) -> Rgb {
        match self {
            Bsdf::Phong(p) => p.eval(f.n, f.wo, wi),
            Bsdf::Mirror(m) => m.eval(),
            Bsdf::Dielectric(d) => d.eval(),
        }
    }

    /// A direction from the uniform numbers `u` in [0, 1)².
    pub fn sample(&self, f: &ShadingFrame, u: Vec2) -> Option<BsdfSample> {
        match self {
            Bsdf::Phong(p) => p.sample(f.n, f.wo, u),
            Bsdf::Mirror(m) => m.sample(f.n, f.wo),
            Bsdf::Dielectric(d) => d.sample(f.n, f.wo, f.front, u.x),
        }
    }

    /// The density of [`sample`](Self::sample) drawing `wi`.
    pub fn pdf(&self, f: &ShadingFrame, wi: Vec3) -> f32 {
        match self {
            Bsdf::Phong(p) => p.pdf(f.n, f.wo, wi),
            Bsdf::Mirror(m) => m.pdf(),
            Bsdf::Dielectric(d) => d.pdf(),
        }
    }

    pub fn flags(&self) -> BsdfFlags {
        match self {
            Bsdf::Phong(p) => p.flags(),
            Bsdf::Mirror(m) => m.flags(),
            Bsdf::Dielectric(d) => d.flags(),
        }
    }
}

/// A material's models, built once per worker from its record.
#[derive(Clone, Copy, Debug)]
pub struct Surface {
    /// The local part receives direct light: it has a weight and reflects.
    pub lit: bool,
    /// The material reflects or refracts rays (mirror, gloss, glass).
    pub scatters: bool,
    pub local: Phong,
    pub mirror: Option<Mirror>,
    pub dielectric: Option<Dielectric>,
    pub emission: Rgb,
}

impl Surface {
    pub fn new(m: &Material) -> Surface {
        let local = Phong::new(m.albedo, m.specular, m.shininess, m.local_weight());
        let mirror = (m.reflectivity > 0.0).then_some(Mirror {
            reflectivity: m.reflectivity,
            glossiness: m.glossiness,
            effect: m.reflection,
        });
        let dielectric = (m.transparency > 0.0).then_some(Dielectric {
            transparency: m.transparency,
            ior: m.ior,
            translucency: m.translucency,
            effect: m.refraction,
        });
        Surface {
            lit: !local.is_black(),
            scatters: mirror.is_some() || dielectric.is_some(),
            local,
            mirror,
            dielectric,
            emission: m.emission,
        }
    }

    /// The models of the material, each as a [`Bsdf`].
    pub fn lobes(&self) -> impl Iterator<Item = Bsdf> + '_ {
        let local = self.lit.then_some(Bsdf::Phong(self.local));
        let mirror = self.mirror.map(Bsdf::Mirror);
        let dielectric = self.dielectric.map(Bsdf::Dielectric);
        local.into_iter().chain(mirror).chain(dielectric)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Distribution;
    use crate::scene::EffectSpec;

    fn material(reflectivity: f32, transparency: f32) -> Material {
        let effect = EffectSpec {
            rays: 4,
            distribution: Distribution::Jitter,
        };
        Material {
            albedo: Rgb::new(0.5, 0.5, 0.5),
            specular: 0.2,
            shininess: 10.0,
            reflectivity,
            transparency,
            ior: 1.5,
            emission: Rgb::ZERO,
            glossiness: 0.0,
            translucency: 0.1,
            reflection: effect,
            refraction: effect,
        }
    }

    /// A material is split into the lobes its weights ask for, and each
    /// lobe's flags say what it is.
    #[test]
    fn surfaces_hold_the_lobes_their_weights_ask_for() {
        let plain = Surface::new(&material(0.0, 0.0));
        assert!(plain.lit && !plain.scatters);
        assert_eq!(plain.lobes().count(), 1);
        let glass = Surface::new(&material(0.0, 1.0));
        assert!(!glass.lit && glass.scatters);
        let lobes: Vec<Bsdf> = glass.lobes().collect();
        assert_eq!(lobes.len(), 1);
        let flags = lobes[0].flags();
        assert!(flags.contains(BsdfFlags::DELTA | BsdfFlags::TRANSMISSION | BsdfFlags::GLOSSY));
        let mixed = Surface::new(&material(0.3, 0.3));
        assert_eq!(mixed.lobes().count(), 3);
        let f = ShadingFrame {
            n: Vec3::Z,
            wo: Vec3::Z,
            front: true,
        };
        for lobe in mixed.lobes() {
            let delta = lobe.flags().contains(BsdfFlags::DELTA);
            let value = lobe.eval(&f, Vec3::new(0.0, 0.6, 0.8)).max_element();
            assert_eq!(delta, value == 0.0, "{lobe:?}");
            assert_eq!(delta, lobe.pdf(&f, Vec3::new(0.0, 0.6, 0.8)) == 0.0);
        }
    }
}
