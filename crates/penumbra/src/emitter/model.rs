//! What every emitter answers: [`EmitterModel`], whose defaults are those
//! of an emitter without the property (see the [module docs](super)).

use crate::texture::Textures;

use super::bounds::LightBounds;
use super::sample::{EmittedRay, LightSample, Reference, SurfacePoint};
use crate::description::{Invalid, Props};
use crate::math::{Rgb, Vec2, Vec3};
use crate::sampling::Distribution;

/// An emitter a scene names by itself (a `[[lights]]` entry, a Mitsuba
/// `<emitter>` at the top): its builder. Its schema and how Mitsuba's
/// plugin maps onto it are its `SCHEMA` and `MITSUBA`.
pub trait EmitterPlugin {
    /// What it builds: the emitter itself, or the one it is computed into
    /// (a sky: an environment map).
    type Built;

    /// The emitter of a scene's parameters: its files relative to
    /// `textures.base_dir`, the textures it takes read through `textures`.
    fn build(p: &Props, textures: &Textures) -> Result<Self::Built, Invalid>;
}

/// What every emitter answers (see the [module docs](crate::emitter)); the defaults
/// are those of an emitter without the property (no surface, not at
/// infinity, not a delta light).
pub trait EmitterModel {
    /// True for an emitter without extent (a point, spot or directional
    /// light): every shadow ray toward it would be the same.
    #[inline]
    fn is_delta(&self) -> bool {
        false
    }

    /// True for an emitter at infinity that rays that hit nothing see
    /// (`constant`, `envmap`; a directional light is at infinity but seen
    /// by no ray, sampled as a delta light).
    #[inline]
    fn is_infinite(&self) -> bool {
        false
    }

    /// Fits the emitter to the scene's bounding sphere.
    fn fit(&mut self, _center: Vec3, _radius: f32) {}

    /// The power it emits (W, mean over the colour channels); for an
    /// emitter at infinity the power it brings into the scene's bounding
    /// sphere of radius `radius`, as pbrt-v4 counts it.
    fn power(&self, radius: f32) -> f32;

    /// Its bounds for a light BVH; `None` for an emitter at infinity.
    fn bounds(&self) -> Option<LightBounds> {
        None
    }

    /// Radiance leaving the emitter's surface toward `-dir` at a point with
    /// geometric normal `n` and surface coordinates `uv`; zero for emitters
    /// without a surface.
    #[inline]
    fn eval(&self, _n: Vec3, _uv: Vec2, _dir: Vec3) -> Rgb {
        Rgb::ZERO
    }

    /// Radiance arriving along `dir` from infinity.
    #[inline]
    fn eval_miss(&self, _dir: Vec3) -> Rgb {
        Rgb::ZERO
    }

    /// Samples for a batch of distribution points (see
    /// [`Emitter::sample`](super::Emitter::sample)): one by one through
    /// [`sample_one`](Self::sample_one) unless the emitter has a kernel.
    #[inline]
    fn sample(
        &self,
        at: impl Fn(usize) -> Reference,
        points: &[Vec3],
        d: Distribution,
        out: &mut Vec<Option<LightSample>>,
    ) {
        out.extend((0..points.len()).map(|k| self.sample_one(at(k), points[k], d)));
    }

    /// One sample seen from `r` with the distribution point `point`, the
    /// portable form; `None` for an emitter at infinity, seen rather than
    /// sampled by the integrators that shade with this.
    #[inline]
    fn sample_one(&self, _r: Reference, _point: Vec3, _d: Distribution) -> Option<LightSample> {
        None
    }

    /// For an emitter at infinity, the direction toward it for the point
    /// `u` of the unit square, the radiance arriving from there and the
    /// solid-angle density of the direction; `None` for the others.
    fn sample_direction(&self, _u: Vec2) -> Option<(Vec3, Rgb, f32)> {
        None
    }

    /// The solid-angle density with which
    /// [`sample_direction`](Self::sample_direction) draws `dir`.
    fn pdf_direction(&self, _dir: Vec3) -> f32 {
        0.0
    }

    /// A ray leaving the emitter, for light tracing: its origin drawn with
    /// the point `u_pos` of the unit square, its direction with `u_dir`, at
    /// `time`; `sphere` is the scene's bounding sphere (centre, radius),
    /// which rays from infinity enter through. `None` where the numbers give
    /// no ray. Every emitter draws rays: the particle tracer needs them all.
    fn sample_ray(
        &self,
        u_pos: Vec2,
        u_dir: Vec2,
        time: f32,
        sphere: (Vec3, f32),
    ) -> Option<EmittedRay>;

    /// A point of the emitter's surface for the point `u` of the unit
    /// square, at `time`: how a particle tracer connects an emitter seen
    /// directly to the camera. `None` for an emitter without a surface.
    fn sample_position(&self, _u: Vec2, _time: f32) -> Option<SurfacePoint> {
        None
    }

    /// The solid-angle density with which [`sample`](Self::sample) draws
    /// `target` (a point of the emitter with outward normal `n`) from `r`;
    /// 0 for a delta light and for the thesis model, whose rays are not
    /// drawn from the light's surface.
    fn pdf(&self, _r: Reference, _target: Vec3, _n: Vec3) -> f32 {
        0.0
    }
}
