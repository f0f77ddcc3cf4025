//! The distributed (stochastic) ray tracer of the thesis, on top of Whitted
//! recursion.
//!
//! At every surface hit, each effect traces a *set* of rays distributed by its
//! own distribution (thesis §3.1): shadow rays toward every light (penumbra),
//! reflection rays around the mirror direction (blurry reflection) and
//! refraction rays around the refracted direction (blurry transmission); each
//! ray of a set recurses, so counts grow exponentially between mutually
//! reflecting surfaces (Table 4.3). With one ray per effect and the grid
//! distribution every set is the single perfect ray, i.e. Whitted's algorithm.
//!
//! # Random streams
//!
//! Every random number is a pure function of (seed, pixel, sample, branch).
//! The pixel's streams come from the [`Sampler`](crate::sampling::Sampler);
//! below a primary sample's path they are fixed here and nowhere else:
//!
//! | stream | derived as |
//! |---|---|
//! | pixel `p`, its film, lens and time sets, path of primary sample `i` | see [`Sampler`](crate::sampling::Sampler) |
//! | shadow set toward light `j` at a hit | `path.derive(SHADOW + j)` |
//! | reflection / refraction / Fresnel-reflection set | `path.derive(REFLECT_SET)` … |
//! | path of the k-th ray of such a set | `path.derive(REFLECT_RAY).derive(k)` … |
//!
//! so the image is identical on any number of threads, tiles or machines.
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

mod film;
mod interface;
mod metric;
mod stats;
pub mod stopping;
mod whitted;

pub use film::FilmTile;
pub use interface::{pass_samples, BadSample, Integrator, PixelWorker, TileJob};
pub use metric::{change, Metric, RunningMean};
pub use stats::{RayCounts, RayStats};
pub use whitted::{Tracer, Whitted, WhittedWorker};
