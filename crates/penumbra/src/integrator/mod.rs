//! The distributed (stochastic) ray tracer of the thesis, on top of Whitted
//! recursion.
//!
//! At every surface hit, each effect traces a *set* of rays distributed by its
//! own distribution (thesis §3.1): shadow rays toward every emitter
//! (penumbra), and a set around the perfect direction of each delta lobe of
//! the hit's BSDF (blurry reflection and transmission); each ray of a set
//! recurses, so counts grow exponentially between mutually reflecting
//! surfaces (Table 4.3). With one ray per effect and the grid distribution
//! every set is the single perfect ray, i.e. Whitted's algorithm.
//!
//! Integrators shade only through the interfaces: a hit's
//! [`SurfaceInteraction`](crate::geometry::SurfaceInteraction), its BSDF's
//! [`lobes`, `eval` and `sample`](crate::bsdf::Bsdf), the emitters'
//! [`sample`, `eval` and `eval_miss`](crate::emitter::Emitter). No file here
//! names a model.
//!
//! # Random streams
//!
//! Every random number is a pure function of (seed, pixel, sample, branch).
//! The pixel's streams come from the [`Sampler`](crate::sampling::Sampler);
//! below a primary sample's path they are fixed here and nowhere else:
//!
//! | stream | integrators | derived as |
//! |---|---|---|
//! | pixel `p`, its film, lens and time sets, path of primary sample `i` | all | see [`Sampler`](crate::sampling::Sampler) |
//! | shadow set toward emitter `j` at a hit | `whitted`, `distributed` | `path.derive(SHADOW + j)`, `SHADOW` = 2³² |
//! | set of lobe `k` of the hit's BSDF | `whitted` | `path.derive(2k + 1)` |
//! | path of the `i`-th ray of that set | `whitted` | `path.derive(2k + 2).child(i, n)` |
//! | bounce `b` of a path (read through the path sampler) | `path`, `direct`, `distributed` | `path.derive(b)` |
//! | the `k`-th of a first vertex's `n` BSDF samples, going on as a path | `path`, `direct`, `distributed` | `path.child(k, n)` |
//! | set of BSDF samples at a vertex drawing the thesis's sets | `distributed` | `path.derive(SHADOW − 1)`, its `i`-th path `path.child(i, n)` |
//! | Russian roulette of a path that set starts | `distributed` | `path.child(i, n).derive(SHADOW − 2)` |
//! | step `s` of a path (a scattering, a null collision or a crossing of a `null` surface; read through the path sampler) | `volpath`, `volpathmis` | `path.derive(s)` |
//! | the colour channel distances in media are drawn by | `volpath`, `volpathmis` | `path.derive(SHADOW − 3)` |
//! | ratio tracking of the shadow ray of step `s` through media | `volpath`, `volpathmis` | `path.derive(2³¹ + s)` |
//! | light path `(p, i)`: the path of primary sample `i` of pixel `p` | `ptracer` | the pixel's `path(i)`, as a camera sample's |
//! | its emission: time, emitter choice, origin point, direction point (in that order) | `ptracer` | `path.derive(0)` |
//! | its `b`-th surface (`b ≥ 1`): lens point, BSDF point, roulette, BSDF's third number | `ptracer` | `path.derive(b)` |
//! | the emitter seen directly: emitter choice, surface point (or direction), lens point | `ptracer` | `path.derive(SHADOW − 3)` |
//!
//! The keys are the constants and functions of [`streams`]. (The
//! thesis's material keeps its lobes in slots 0 to 2 — mirror, refraction,
//! Fresnel reflection — so its sets draw the streams 1 to 6.) Every value
//! is thus the same on any number of threads, tiles or machines.
//!
//! # Choices where the thesis is silent
//!
//! * A ray of a blurry reflection set that ends up below the surface is
//!   mirrored back above it across the tangent plane (and a blurred refracted
//!   ray that ends up on the incident side is mirrored to the transmitted
//!   side): the set keeps its size and its symmetry, and no energy is lost
//!   at grazing angles.
//! * A radius of 0 (a perfect mirror, clear glass) or a point light collapses
//!   the set to the single perfect ray: every ray would be identical.
//! * The Fresnel reflection of a transparent surface uses the material's
//!   refraction budget and `translucency` radius (a rough interface blurs both),
//!   and its rays are counted as reflection rays.

pub mod aov;
mod clip;
mod film;
mod interface;
mod metric;
mod model;
mod path;
pub mod plugins;
mod ptracer;
mod ray_sets;
mod shading;
mod sources;
pub mod splat;
mod stats;
pub mod stopping;
pub mod streams;
pub mod transmittance;
mod whitted;

pub use film::{srgb_to_xyz, Channels, ExtraFilm, FilmData, FilmTile};
pub use interface::{pass_samples, BadSample, Integrator, PixelWorker, TileJob};
pub use metric::{change, Metric, RunningMean};
pub use model::IntegratorModel;
pub use path::{
    DirectPlugin, DistributedPlugin, Path, PathPlugin, PathSettings, PathWorker, VolpathPlugin,
    VolpathmisPlugin, WAVE,
};
pub use plugins::{Config, RenderWith, SCHEMAS};
pub use ptracer::{Ptracer, PtracerPlugin, PtracerSettings, PtracerWorker};
pub use ray_sets::{RaySets, ONE_RAY};
pub use shading::ShadingPoint;
pub use splat::{SplatFilm, Splatting};
pub use stats::{Batches, MediumEvents, RayCounts, RayStats, StageBatches};
pub use stopping::Stopping;
pub use whitted::{Tracer, Whitted, WhittedPlugin, WhittedSettings, WhittedWorker};
