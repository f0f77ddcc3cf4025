//! Surface scattering models: what a surface does with light.
//!
//! Every model answers the same questions through [`BsdfModel`], taking its
//! random numbers as arguments: its lobes ([`Lobes`]: diffuse, glossy,
//! delta, reflection, transmission, by slot), its value for a pair of
//! directions (`eval`, without the cosine), a direction drawn from a
//! [`SetPoint`] (`sample`, with the weight `eval · |cos| / pdf`; one lobe
//! alone or a lobe chosen by the point), the density of drawing a
//! direction (`pdf`), and the fraction of light a shadow ray keeps
//! crossing it (the thesis's transparent shadows). Directions are world
//! vectors, `wo` toward the viewer and `wi` toward the light; the surface
//! is described by its [`SurfaceInteraction`].
//!
//! The models form a closed enum, [`Bsdf`], made by the `models!` list at
//! the end of this file: one dispatch point, inlined into the shading loops.
//! Adding a model is one file implementing [`BsdfModel`] and one line in
//! that list (which also declares the file's module).
//!
//! | model | what |
//! |---|---|
//! | [`thesis`](thesis::Thesis) | the thesis's layered material: Lambert + Phong, a mirror and a Fresnel dielectric, the last two blurred by distributed sets |
//! | [`diffuse`](diffuse::Diffuse) | an ideal Lambertian reflector (Mitsuba 3's `diffuse`) |
//! | [`conductor`](conductor::Conductor) | a smooth metal: delta reflection weighted by the conductor Fresnel reflectance (Mitsuba 3's `conductor`) |
//! | [`roughconductor`](roughconductor::RoughConductor) | a rough metal: Beckmann or GGX microfacet reflection (Mitsuba 3's `roughconductor`) |
//! | [`dielectric`](dielectric::Dielectric) | a smooth dielectric interface: Fresnel-weighted delta reflection and refraction (Mitsuba 3's `dielectric`) |
//! | [`roughdielectric`](roughdielectric::RoughDielectric) | a rough dielectric interface: microfacet reflection and transmission (Mitsuba 3's `roughdielectric`) |
//! | [`thindielectric`](thindielectric::ThinDielectric) | a thin dielectric sheet: reflection and straight transmission (Mitsuba 3's `thindielectric`) |
//! | [`plastic`](plastic::Plastic) | a smooth dielectric coating over a diffuse base, with the internal scattering (Mitsuba 3's `plastic`) |
//! | [`roughplastic`](roughplastic::RoughPlastic) | a rough coating over a diffuse base (Mitsuba 3's `roughplastic`) |
//! | [`twosided`](twosided::TwoSided) | one or two reflecting materials, one on each side (Mitsuba 3's `twosided`) |
//! | [`mask`](mask::Mask) | a material seen by a share `opacity` of the light, the rest passing through (Mitsuba 3's `mask`) |
//! | [`blendbsdf`](blendbsdf::BlendBsdf) | a linear blend of two materials (Mitsuba 3's `blendbsdf`) |
//! | [`normalmap`](normalmap::NormalMap) | a material seen through a normal read from a texture (Mitsuba 3's `normalmap`) |
//! | [`bumpmap`](bumpmap::BumpMap) | a material seen through the normal of a height field (Mitsuba 3's `bumpmap`) |
//! | [`principled`](principled::Principled) | Burley's principled (Disney) material: a diffuse base with sheen, GGX metal and dielectric reflection and transmission, a clearcoat (Mitsuba 3's `principled`) |
//! | [`principledthin`](principledthin::PrincipledThin) | the principled material of a thin sheet: diffuse reflection and transmission, GGX reflection and straight transmission (Mitsuba 3's `principledthin`) |
//! | [`null`](null::Null) | a surface light passes straight through: the boundary of a medium (Mitsuba 3's `null`) |
//!
//! Beside the models: [`microfacet`] (the Beckmann and GGX distributions
//! and their samplers), [`fresnel`] (dielectric and conductor
//! reflectance), [`ior`] (indices of refraction and conductor presets
//! by name), [`nested`] (what the models holding other models share:
//! a held model is a material of the scene named by a parameter) and
//! [`perturbed`] (a held model seen through a perturbed shading normal). The
//! models' tests hold every sampler to its density by a χ² test
//! (`chi2.rs`, Mitsuba 3's method).

#[cfg(test)]
pub(crate) mod chi2;
pub mod fresnel;
pub mod ior;
pub mod microfacet;
pub mod nested;
pub mod perturbed;
pub mod sample;
#[cfg(test)]
mod textured;

pub use sample::{BsdfFlags, BsdfSample, Lobes, MAX_LOBES};

use std::collections::HashMap;
use std::sync::Arc;

use crate::description::mitsuba::{Mitsuba, Plugin};
use crate::description::{Invalid, Props, Schema};
use crate::geometry::SurfaceInteraction;
use crate::math::{Rgb, Vec3};
use crate::sampling::{Distribution, EffectSpec, SetPoint};
use crate::texture::Textures;

/// What a model's parameters default to that the scene sets: the render's
/// sets of reflection and refraction rays; the scene's named textures and
/// folder, which its texture-typed parameters are read with; and the
/// scene's materials a model may hold by name.
#[derive(Clone, Copy, Debug)]
pub struct Defaults<'a> {
    pub reflection: EffectSpec,
    pub refraction: EffectSpec,
    pub textures: &'a Textures,
    /// The materials built before this one, by name: the ones a model
    /// holding others (`twosided`, `mask`, `blendbsdf`, `normalmap`,
    /// `bumpmap`) names, built first.
    pub materials: &'a HashMap<String, Arc<Bsdf>>,
}

/// What every scattering model answers (see the [module docs](crate::bsdf)).
pub trait BsdfModel: Sized {
    /// The name scenes select the model by.
    const NAME: &'static str;

    /// Its parameters, their types and defaults (checked when a scene is
    /// loaded, listed in the scene-format reference).
    const SCHEMA: Schema;

    /// How Mitsuba's plugin of its name maps onto it: through the schema
    /// alone unless the model says otherwise.
    const MITSUBA: Mitsuba = Mitsuba::SAME;

    /// The model of a scene's parameters: read through `p` (type errors
    /// are the reader's), checked for range, defaulted.
    fn build(p: &Props, defaults: &Defaults) -> Result<Self, Invalid>;

    /// The model's lobes by slot.
    fn lobes(&self) -> Lobes;

    /// The value for light arriving from `wi` and leaving toward `wo`,
    /// without the cosine; 0 for delta lobes.
    fn eval(&self, si: &SurfaceInteraction, wo: Vec3, wi: Vec3) -> Rgb;

    /// [`eval`](Self::eval) at one point for each direction of `wi`, into
    /// `out` (cleared first): the batch form, which a model's kernel may
    /// take several lanes at a time; by default, one by one.
    #[inline]
    fn eval_all(&self, si: &SurfaceInteraction, wo: Vec3, wi: &[Vec3], out: &mut Vec<Rgb>) {
        out.clear();
        out.extend(wi.iter().map(|&w| self.eval(si, wo, w)));
    }

    /// A direction drawn with the set point `u`: from lobe `lobe` alone
    /// (its weight not divided by a choice), or from a lobe the point
    /// chooses. `None` where the point gives no direction.
    fn sample(
        &self,
        si: &SurfaceInteraction,
        wo: Vec3,
        lobe: Option<usize>,
        u: SetPoint,
    ) -> Option<BsdfSample>;

    /// The directions [`sample`](Self::sample) draws from lobe `lobe` for
    /// each point of a set (`points`, of distribution `d`), into `out`
    /// (cleared first); `fallback` where a point gives none. The batch
    /// form: a model may find what the points share once (the perfect
    /// direction, the frame around it), giving the same directions bit for
    /// bit; by default, one by one.
    #[inline]
    fn sample_set(
        &self,
        si: &SurfaceInteraction,
        wo: Vec3,
        lobe: usize,
        (points, d): (&[Vec3], Distribution),
        fallback: Vec3,
        out: &mut Vec<Vec3>,
    ) {
        sample_each(self, si, wo, lobe, (points, d), fallback, out);
    }

    /// The solid-angle density of [`sample`](Self::sample) (no lobe asked)
    /// drawing `wi`; 0 for delta lobes.
    fn pdf(&self, si: &SurfaceInteraction, wo: Vec3, wi: Vec3) -> f32;

    /// The reflectance of the surface at `si` seen from `wo` as a diffuse
    /// one (Mitsuba's `eval_diffuse_reflectance`, its `aov` integrator's
    /// `albedo`): a model with a diffuse reflectance or base colour gives
    /// it; any other, π times its value for light arriving along the
    /// shading normal (0 for a model of delta lobes alone).
    fn diffuse_reflectance(&self, si: &SurfaceInteraction, wo: Vec3) -> Rgb {
        self.eval(si, wo, si.n) * std::f32::consts::PI
    }

    /// The shading normal the model shades by at `si` seen from `wo` (the
    /// `aov` integrator's `sh_normal`): the interaction's own, but for a
    /// model that perturbs it (`normalmap`, `bumpmap`), as Mitsuba's
    /// `BSDF::sh_frame`.
    fn shading_normal(&self, si: &SurfaceInteraction, _wo: Vec3) -> Vec3 {
        si.n
    }

    /// The fraction of light a shadow ray keeps when it crosses the
    /// surface at `si` without bending (the thesis's transparent shadows);
    /// 0 for an opaque surface.
    fn shadow_transmittance(&self, _si: &SurfaceInteraction) -> f32 {
        0.0
    }

    /// The light a ray crossing the surface at `si` straight along `d`
    /// keeps, colour by colour, where the crossing is a pass-through
    /// (Mitsuba's `eval_null_transmission`): what the volumetric path
    /// tracer's shadow rays keep crossing it. By default the
    /// [`shadow_transmittance`](Self::shadow_transmittance); a thin sheet
    /// passes what it transmits.
    fn null_transmission(&self, si: &SurfaceInteraction, _d: Vec3) -> Rgb {
        Rgb::splat(self.shadow_transmittance(si))
    }

    /// [`shadow_transmittance`](Self::shadow_transmittance) where it is the
    /// same all over the surface; `None` where a texture makes it vary, so
    /// that a shadow ray must read it at each point it crosses.
    fn uniform_shadow_transmittance(&self) -> Option<f32> {
        Some(0.0)
    }

    /// The sets of rays the model's own parameters ask for, by lobe slot
    /// (the thesis material's `reflection_rays`, …); `None` for a model
    /// without such parameters.
    fn own_sets(&self) -> Option<[Option<EffectSpec>; MAX_LOBES]> {
        None
    }

    /// Whether [`sample`](Self::sample) reads a third number
    /// ([`SetPoint::third`]) to choose its lobe: a path sampler then draws
    /// one for it, a dimension of its own.
    fn wants_third(&self) -> bool {
        false
    }
}

/// [`BsdfModel::sample_set`] point by point: each point's own
/// [`sample`](BsdfModel::sample), `fallback` where it gives none.
#[inline]
pub fn sample_each<M: BsdfModel>(
    m: &M,
    si: &SurfaceInteraction,
    wo: Vec3,
    lobe: usize,
    (points, d): (&[Vec3], Distribution),
    fallback: Vec3,
    out: &mut Vec<Vec3>,
) {
    out.clear();
    out.extend(points.iter().map(|&p| {
        let u = SetPoint::new(p, d);
        m.sample(si, wo, Some(lobe), u).map_or(fallback, |b| b.wi)
    }));
}

/// Declares the models' modules, and makes [`Bsdf`], the enum of the
/// models listed (each `module::Model`, its variant named as the model),
/// and its dispatch.
macro_rules! models {
    ($($module:ident::$variant:ident,)*) => {
        $(pub mod $module;)*
        models!(@enum $($variant($module::$variant),)*);
    };
    (@enum $($variant:ident($model:ty),)*) => {
        /// A scattering model: one of the models of this layer.
        #[derive(Clone, Debug)]
        pub enum Bsdf {
            $($variant($model),)*
        }

        $(impl From<$model> for Bsdf {
            fn from(m: $model) -> Bsdf {
                Bsdf::$variant(m)
            }
        })*

        impl Bsdf {
            /// The names of the models, as scenes select them.
            pub const NAMES: &'static [&'static str] = &[$(<$model as BsdfModel>::NAME,)*];

            /// The models' parameters.
            pub const SCHEMAS: &'static [&'static Schema] = &[$(&<$model as BsdfModel>::SCHEMA,)*];

            /// The models as the readers see them.
            pub const PLUGINS: &'static [Plugin] = &[$(Plugin::new(&<$model as BsdfModel>::SCHEMA, <$model as BsdfModel>::MITSUBA),)*];

            /// The model `name` of the parameters `p`; `None` for a name
            /// that is not a model's.
            pub fn build(name: &str, p: &Props, defaults: &Defaults) -> Option<Result<Bsdf, Invalid>> {
                match name {
                    $(<$model as BsdfModel>::NAME => Some(<$model>::build(p, defaults).map(Bsdf::from)),)*
                    _ => None,
                }
            }

            /// The model's name.
            pub fn name(&self) -> &'static str {
                match self {
                    $(Bsdf::$variant(_) => <$model as BsdfModel>::NAME,)*
                }
            }

            #[inline]
            pub fn lobes(&self) -> Lobes {
                match self {
                    $(Bsdf::$variant(m) => m.lobes(),)*
                }
            }

            /// The union of the lobes' flags.
            #[inline]
            pub fn flags(&self) -> BsdfFlags {
                self.lobes().union()
            }

            #[inline]
            pub fn eval(&self, si: &SurfaceInteraction, wo: Vec3, wi: Vec3) -> Rgb {
                match self {
                    $(Bsdf::$variant(m) => m.eval(si, wo, wi),)*
                }
            }

            /// See [`BsdfModel::diffuse_reflectance`].
            pub fn diffuse_reflectance(&self, si: &SurfaceInteraction, wo: Vec3) -> Rgb {
                match self {
                    $(Bsdf::$variant(m) => m.diffuse_reflectance(si, wo),)*
                }
            }

            /// See [`BsdfModel::shading_normal`].
            pub fn shading_normal(&self, si: &SurfaceInteraction, wo: Vec3) -> Vec3 {
                match self {
                    $(Bsdf::$variant(m) => m.shading_normal(si, wo),)*
                }
            }

            /// See [`BsdfModel::eval_all`].
            #[inline]
            pub fn eval_all(
                &self,
                si: &SurfaceInteraction,
                wo: Vec3,
                wi: &[Vec3],
                out: &mut Vec<Rgb>,
            ) {
                match self {
                    $(Bsdf::$variant(m) => m.eval_all(si, wo, wi, out),)*
                }
            }

            /// See [`BsdfModel::sample_set`].
            #[inline]
            pub fn sample_set(
                &self,
                si: &SurfaceInteraction,
                wo: Vec3,
                lobe: usize,
                set: (&[Vec3], Distribution),
                fallback: Vec3,
                out: &mut Vec<Vec3>,
            ) {
                match self {
                    $(Bsdf::$variant(m) => m.sample_set(si, wo, lobe, set, fallback, out),)*
                }
            }

            #[inline]
            pub fn sample(
                &self,
                si: &SurfaceInteraction,
                wo: Vec3,
                lobe: Option<usize>,
                u: SetPoint,
            ) -> Option<BsdfSample> {
                match self {
                    $(Bsdf::$variant(m) => m.sample(si, wo, lobe, u),)*
                }
            }

            #[inline]
            pub fn pdf(&self, si: &SurfaceInteraction, wo: Vec3, wi: Vec3) -> f32 {
                match self {
                    $(Bsdf::$variant(m) => m.pdf(si, wo, wi),)*
                }
            }

            #[inline]
            pub fn shadow_transmittance(&self, si: &SurfaceInteraction) -> f32 {
                match self {
                    $(Bsdf::$variant(m) => m.shadow_transmittance(si),)*
                }
            }

            /// See [`BsdfModel::null_transmission`].
            #[inline]
            pub fn null_transmission(&self, si: &SurfaceInteraction, d: Vec3) -> Rgb {
                match self {
                    $(Bsdf::$variant(m) => m.null_transmission(si, d),)*
                }
            }

            /// The shadow transmittance where it is the same all over the
            /// surface; `None` where it varies.
            #[inline]
            pub fn uniform_shadow_transmittance(&self) -> Option<f32> {
                match self {
                    $(Bsdf::$variant(m) => m.uniform_shadow_transmittance(),)*
                }
            }

            /// See [`BsdfModel::own_sets`].
            pub fn own_sets(&self) -> Option<[Option<EffectSpec>; MAX_LOBES]> {
                match self {
                    $(Bsdf::$variant(m) => m.own_sets(),)*
                }
            }

            /// See [`BsdfModel::wants_third`].
            #[inline]
            pub fn wants_third(&self) -> bool {
                match self {
                    $(Bsdf::$variant(m) => m.wants_third(),)*
                }
            }
        }
    };
}

// The models: one line each.
models! {
    thesis::Thesis,
    diffuse::Diffuse,
    conductor::Conductor,
    roughconductor::RoughConductor,
    dielectric::Dielectric,
    roughdielectric::RoughDielectric,
    thindielectric::ThinDielectric,
    plastic::Plastic,
    roughplastic::RoughPlastic,
    twosided::TwoSided,
    mask::Mask,
    blendbsdf::BlendBsdf,
    normalmap::NormalMap,
    bumpmap::BumpMap,
    principled::Principled,
    principledthin::PrincipledThin,
    null::Null,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::chi2::with_defaults;
    use crate::bsdf::thesis::tests::interaction;
    use crate::sampling::Rng;
    use std::collections::HashMap;

    /// Every model that builds from its defaults answers the batch form
    /// with the bits of its scalar form, direction by direction (so a
    /// kernel a model gives later is held to its portable form), at tilted
    /// shading normals and over both hemispheres.
    #[test]
    fn batch_evaluation_gives_the_scalar_bits() {
        let mut rng = Rng::new(3);
        let mut unit = || {
            let v = Vec3::new(
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
                rng.range(-1.0, 1.0),
            );
            v.normalize_or(Vec3::Z)
        };
        let (mut built, mut out) = (0, Vec::new());
        for schema in Bsdf::SCHEMAS {
            let text = format!("type = \"{}\"", schema.plugin);
            let none = HashMap::new();
            let m = with_defaults(&text, &none, |p, d| Bsdf::build(schema.plugin, p, d));
            // Models that need a held material or a texture are left out.
            let Some(Ok(m)) = m else {
                continue;
            };
            built += 1;
            for _ in 0..50 {
                let si = interaction((Vec3::Z + 0.3 * unit()).normalize());
                let wo = unit();
                let wi: Vec<Vec3> = (0..7).map(|_| unit()).collect();
                m.eval_all(&si, wo, &wi, &mut out);
                let bits = |c: Rgb| c.to_array().map(f32::to_bits);
                let want: Vec<_> = wi.iter().map(|&w| bits(m.eval(&si, wo, w))).collect();
                let got: Vec<_> = out.iter().map(|&c| bits(c)).collect();
                assert_eq!(got, want, "{}", schema.plugin);
            }
        }
        assert!(built >= 8, "{built} models built");
    }
}
