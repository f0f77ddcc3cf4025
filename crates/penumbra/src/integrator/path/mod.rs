//! `path`: a unidirectional path tracer with next-event estimation,
//! multiple importance sampling and Russian roulette, as Mitsuba 3's
//! `path` integrator, run on a wavefront; `direct`, its first vertex
//! alone with counts of its own, as Mitsuba 3's `direct`; and
//! `distributed`, whose first vertices draw the thesis's sets.
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `max_depth` | integer ≥ −1 | `-1` | `path`: the longest path, in vertices from the camera (Mitsuba's count): 0 renders black, 1 only the emitters seen directly, 2 direct light, −1 no bound |
//! | `rr_depth` | integer ≥ 1 | `5` | `path`: the depth from which Russian roulette may end a path |
//! | `emitter_samples` | integer ≥ 0 | `1` | `direct`: emitter samples at the shading point |
//! | `bsdf_samples` | integer ≥ 0 | `1` | `direct`: BSDF samples at the shading point (not both 0) |
//! | `shading_samples` | integer ≥ 0 | `1` | `direct`: both counts at once (Mitsuba's name; the two above win) |
//! | `sets_depth` | integer 1–64 | `1` | `distributed`: the vertices from the camera that draw sets |
//! | `hide_emitters` | bool | `false` | emitters seen directly by camera rays are black |
//! | `path_sampler` | name | `independent` | where each bounce's numbers come from ([`PathSampler`](crate::sampling::PathSampler)) |
//! | `light_sampler` | name | `bvh` | how next-event estimation chooses its emitter: `uniform`, `power` or `bvh` ([`LightSampler`](crate::emitter::choice::LightSampler)) |
//!
//! `distributed` carries the thesis into global illumination: a vertex
//! below `sets_depth` traces a shadow set toward every emitter (its
//! `shadow_rays`, points of its `shadow_distribution`) and one set of BSDF
//! samples (the largest set the material's lobes ask for, else the
//! render's reflection set; points of its distribution), every BSDF ray
//! going on as a path of its own with the set's share of the throughput.
//! The distribution supplies the sample numbers of the light and the BSDF,
//! so the estimator converges to `path`'s image for random, uniform sets;
//! `grid`, whose sets are fixed points, and `fast-random`, which is not
//! uniform, bias it as they bias the thesis's sets.
//! Light and BSDF samples are weighed by the power heuristic on density
//! times count. The thesis's shadow metric may stop a shadow set after its
//! first `k` members (all reached the emitter, or all were blocked: their
//! mean is the set's value). Its reflection metric judges the first
//! vertex's BSDF set on its members' whole paths: α members are followed to
//! their ends, then one more of each set not yet converged, in rounds of the
//! wave from the second vertex, until every set is judged.
//! `direct` is this estimator with two vertices and no roulette: at the
//! first, `emitter_samples` emitter samples and `bsdf_samples` BSDF samples
//! (each going on as its own path, its throughput divided by the count),
//! weighed by the power heuristic on densities times counts, as Mitsuba
//! weighs them; at the second, the emission met.
//!
//! # The estimator
//!
//! A camera ray is followed from vertex to vertex. At each vertex the
//! radiance the surface emits toward the previous one is added; then, while
//! the next vertex would still be within `max_depth`, one emitter (chosen
//! by the scene's light sampler for the point and its shading normal) is
//! sampled for a shadow ray
//! (next-event estimation) on the BSDF's smooth lobes, and the BSDF is
//! sampled for the path's next direction. Emission reached by a BSDF
//! sample and an emitter sample of the same light are combined by the power
//! heuristic, the emitter sample's density being the light sampler's
//! probability of that emitter at the vertex the path left times the
//! emitter's own density; after a delta lobe (a mirror, clear glass, a lobe the thesis
//! blurs) the emission met counts whole. From `rr_depth` on, a path
//! survives with probability `min(max(throughput) · η², 0.95)` (η the
//! product of the relative indices crossed) and is divided by it.
//!
//! Emitters at infinity (`constant`) are sampled as Mitsuba samples them,
//! uniformly over the sphere, their shadow rays ending beyond the world.
//!
//! Where this differs from Mitsuba: shadow rays treat every surface as opaque
//! (the thesis's transparent shadows are a `whitted` model); an area light
//! under the thesis's penumbra model has no density over its surface, so it
//! is lit by its shadow rays alone (BSDF samples that meet it add nothing).
//!
//! # Volumetric paths (`volpath`)
//!
//! `volpath` is this estimator carried through participating media, as
//! Mitsuba 3's `volpath` (its stages in `volume.rs`): each path carries
//! the medium it is in (the camera's first), entering an object's
//! `interior` or `exterior` as it crosses its surface. In a medium, a
//! collision is drawn against the medium's majorant before the surface the
//! ray meets, by one colour channel chosen per path (Mitsuba's); with
//! `has_spectral_extinction` the throughput is weighed by the
//! transmittance over its density in that channel. A null collision moves
//! the path on unchanged; a real one scatters it by the phase function,
//! after next-event estimation toward an emitter (weighed against the
//! phase function's density by the power heuristic). Surfaces are
//! shaded as above; a pass-through (`null`, a thin sheet's transmission)
//! is not a scattering. `max_depth` and `rr_depth` count scatterings
//! (surface and medium alike), roulette playing from `rr_depth`
//! scatterings on at every step. Shadow rays cross pass-throughs, keeping
//! what they transmit, and take each medium's transmittance on the way
//! (exact in a homogeneous medium; Mitsuba's tracks it, with the same
//! mean). Null collisions and scatterings are counted in the ray
//! statistics (`media`).
//!
//! In a scene with media, `distributed` runs this volumetric wave, its
//! vertices within `sets_depth` drawing the thesis's sets (`volume_sets.rs`):
//! at a surface the sets above, their shadow rays tracked through media;
//! at a real collision a shadow set toward every emitter weighed by the
//! phase function and a set of phase directions of the render's reflection
//! set, each a path of its own. The metrics judge them as at surfaces: a
//! shadow ray "reaches" its emitter when it lets some light through, and
//! the first vertex's set of directions is judged on its members' paths,
//! the wave running again from the members still owed.
//!
//! # Spectral MIS (`volpathmis`)
//!
//! `volpathmis` is `volpath` weighed by multiple importance sampling, as
//! Mitsuba 3's `volpathmis` (Miller et al. 2019; its stages in
//! `volume_mis.rs`). A path keeps, instead of its throughput, the
//! densities with which it could have been drawn over its contribution,
//! per colour channel of the contribution: with `use_spectral_mis` (the
//! default) the densities of drawing its distances by each of the three
//! channels side by side, its contribution in channel `i` being `fᵢ` over
//! their mean (the balance heuristic over the channels: a distance drawn
//! by the red channel in a medium far denser in blue is not weighed by the
//! red density alone); without it, by the path's own channel, as `volpath`.
//! Next-event estimation from a scattering traces its shadow ray through
//! media by ratio tracking, drawn by the path's channel, and keeps the
//! densities of the path it makes under both strategies (next-event
//! estimation, and the path's own sampling choosing each null collision
//! with its probability); emission a path meets after a scattering is
//! weighed likewise against next-event estimation from that scattering.
//! Both are combined by the balance heuristic over strategies and
//! channels. `max_depth`, `rr_depth` and `hide_emitters` are `volpath`'s,
//! but roulette is not played right after a null collision (Mitsuba's).
//! Where a channel's contribution vanishes, `use_spectral_mis = false`
//! gives that channel 0 and keeps the others (Mitsuba's ends the path).
//!
//! # Random numbers
//!
//! Each path draws from the stream of its primary sample (the
//! [`Sampler`](crate::sampling::Sampler)'s, the same as `whitted`'s),
//! derived per bounce: bounce `b` reads `path.derive(b)` through the
//! [`PathSampler`](crate::sampling::PathSampler), in the order emitter
//! choice and point (dimensions 2j and 2j + 1) for each emitter sample j,
//! then BSDF point and roulette (2e + 2k, 2e + 2k + 1) for each BSDF
//! sample k (independent numbers are drawn in that order, a sequence's by
//! dimension); a vertex's BSDF samples
//! beyond one go on with the child streams of their index (a vertex drawing
//! the thesis's sets takes other branches, see [`streams`](crate::integrator::streams)). A
//! sample is a pure function of (seed, pixel, sample, bounce, dimension):
//! the same on any number of threads, tiles or passes.
//!
//! # The wavefront
//!
//! A worker keeps the paths of whole rows of its 64 × 64 tile (at least one
//! row, up to [`WAVE`] paths at the wave's widest bounce: a whole tile's
//! 4,096 at one sample, fewer rows where the thesis's sets or several BSDF
//! samples multiply the paths) in structure-of-arrays buffers, kept with
//! the worker across tiles and passes, and advances them
//! together, one stage at a time: one closest-hit call for all live paths
//! ([`World::intersect_all`](crate::accel::World::intersect_all)), one
//! shading pass that adds emission, prepares every shadow ray and samples
//! every BSDF, one occlusion pass over all shadow rays, then compaction of
//! the paths that ended. Radiance is kept per sample and added to the film
//! in each pixel's sample order once the wave is done.

mod config;
pub mod plugins;
mod sets;
mod vertex;
mod volume;
mod volume_mis;
mod volume_sets;
mod wavefront;

pub(crate) use config::max_depth;
pub use config::{PathSettings, PLUGINS};
pub use plugins::{DirectPlugin, DistributedPlugin, PathPlugin, VolpathPlugin, VolpathmisPlugin};

use super::film::FilmTile;
use super::interface::{BadSample, Integrator, PixelWorker, TileJob};
use super::ray_sets::RaySets;
use super::stats::{RayStats, StageBatches};
use crate::emitter::choice::LightSampler;
use crate::scene::Scene;

use wavefront::Wavefront;
pub use wavefront::WAVE;

/// The path tracer, with its settings, ready to render a scene.
#[derive(Clone, Debug)]
pub struct Path {
    pub settings: PathSettings,
    /// Camera rays per pixel.
    pub spp: u32,
    /// How next-event estimation chooses among the scene's emitters (the
    /// settings' `light_sampler`), built once per render and shared by
    /// every worker.
    pub lights: LightSampler,
    /// The shadow set of each emitter and the set of each material's
    /// lobes, which `distributed` draws.
    pub sets: RaySets,
}

impl Path {
    /// The integrator of `settings` for `scene`.
    pub fn new(scene: &Scene, mut settings: PathSettings) -> Path {
        // `distributed` tracks its paths through the scene's media.
        settings.volumetric |= settings.sets_depth > 0 && !scene.media.is_empty();
        // Emitters at infinity are measured through the world's bounding
        // sphere.
        let b = scene.world.bounds();
        let radius = 0.5 * (b.max - b.min).length();
        let sphere = if radius.is_finite() && radius > 0.0 {
            radius
        } else {
            1.0
        };
        Path {
            settings,
            spp: scene.settings.spp,
            lights: LightSampler::new(settings.light_sampler, &scene.emitters, sphere),
            sets: RaySets::new(scene),
        }
    }
}

impl Integrator for Path {
    type Worker<'s> = PathWorker<'s>;
    type TileState = ();

    fn worker<'s>(&'s self, scene: &'s Scene) -> PathWorker<'s> {
        PathWorker {
            wave: Wavefront::new(scene, self.settings, &self.lights, &self.sets),
        }
    }

    fn samples(&self) -> u32 {
        self.spp
    }

    fn passes(&self) -> u32 {
        self.settings.passes
    }

    fn whole_tiles(&self) -> bool {
        false
    }

    /// 64 pixels: a tile's 4,096 camera rays at one sample fill the first
    /// bounce's batches of a wave (see [`WAVE`]).
    fn tile(&self) -> u32 {
        64
    }
}

/// A [`Path`] worker: its wavefront's buffers and ray counts.
pub struct PathWorker<'s> {
    wave: Wavefront<'s>,
}

impl PixelWorker for PathWorker<'_> {
    type State = ();

    fn render(
        &mut self,
        tile: TileJob<'_>,
        _: &mut (),
        film: &mut FilmTile,
        bad: &mut Vec<BadSample>,
    ) -> bool {
        self.wave.render(tile, film, bad)
    }

    fn stats(&self) -> &RayStats {
        &self.wave.stats
    }

    fn clear_counts(&mut self) {
        self.wave.stats = RayStats::default();
        self.wave.batches = StageBatches::default();
    }

    fn batches(&self) -> StageBatches {
        self.wave.batches
    }
}
