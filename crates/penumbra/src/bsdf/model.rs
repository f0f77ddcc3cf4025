//! The interface every scattering model implements.

use std::collections::HashMap;
use std::sync::Arc;

use super::sample::{BsdfSample, Lobes};
use super::Bsdf;
use crate::description::{Invalid, Props, Schema};
use crate::geometry::SurfaceInteraction;
use crate::math::{Rgb, Vec3};
use crate::sampling::{EffectSpec, SetPoint};
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
    /// holding others (`twosided`, `mask`, `blendbsdf`) names, built first.
    pub materials: &'a HashMap<String, Arc<Bsdf>>,
}

/// What every scattering model answers (see the [module docs](crate::bsdf)).
pub trait BsdfModel: Sized {
    /// The name scenes select the model by.
    const NAME: &'static str;

    /// Its parameters, their types and defaults (checked when a scene is
    /// loaded, listed in the scene-format reference).
    const SCHEMA: Schema;

    /// The model of a scene's parameters: read through `p` (type errors
    /// are the reader's), checked for range, defaulted.
    fn build(p: &Props, defaults: &Defaults) -> Result<Self, Invalid>;

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
