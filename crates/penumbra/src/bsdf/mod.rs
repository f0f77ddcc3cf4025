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
//! The models form a closed enum, [`Bsdf`], made by the [`models!`] list at
//! the end of this file: one dispatch point, inlined into the shading loops.
//! Adding a model is one file implementing [`BsdfModel`] and one line in
//! that list.
//!
//! | model | what |
//! |---|---|
//! | [`thesis`](thesis::Thesis) | the thesis's layered material: Lambert + Phong, a mirror and a Fresnel dielectric, the last two blurred by distributed sets |
//! | [`diffuse`](diffuse::Diffuse) | an ideal Lambertian reflector (Mitsuba 3's `diffuse`) |

pub mod diffuse;
pub mod sample;
pub mod thesis;

pub use sample::{BsdfFlags, BsdfSample, Lobes, MAX_LOBES};

use crate::geometry::SurfaceInteraction;
use crate::math::{Rgb, Vec3};
use crate::sampling::SetPoint;

/// What every scattering model answers (see the [module docs](self)).
pub trait BsdfModel {
    /// The name scenes select the model by.
    const NAME: &'static str;

    /// The model's lobes by slot.
    fn lobes(&self) -> Lobes;

    /// The value for light arriving from `wi` and leaving toward `wo`,
    /// without the cosine; 0 for delta lobes.
    fn eval(&self, si: &SurfaceInteraction, wo: Vec3, wi: Vec3) -> Rgb;

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

    /// The solid-angle density of [`sample`](Self::sample) (no lobe asked)
    /// drawing `wi`; 0 for delta lobes.
    fn pdf(&self, si: &SurfaceInteraction, wo: Vec3, wi: Vec3) -> f32;

    /// The fraction of light a shadow ray keeps when it crosses the
    /// surface without bending (the thesis's transparent shadows); 0 for an
    /// opaque surface.
    fn shadow_transmittance(&self) -> f32 {
        0.0
    }
}

/// Makes [`Bsdf`], the enum of the models listed, and its dispatch.
macro_rules! models {
    ($($variant:ident($model:ty),)*) => {
        /// A scattering model: one of the models of this layer.
        #[derive(Clone, Copy, Debug)]
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
            pub fn shadow_transmittance(&self) -> f32 {
                match self {
                    $(Bsdf::$variant(m) => m.shadow_transmittance(),)*
                }
            }
        }
    };
}

models! {
    Thesis(thesis::Thesis),
    Diffuse(diffuse::Diffuse),
}
