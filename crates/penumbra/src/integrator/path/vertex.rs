//! What the wavefront's stages share: the buffers of a wave's paths and
//! shadow rays, a vertex and what it needs of its material, and the
//! sampling and weighing of emitters at a vertex.

use crate::accel::Hit;
use crate::bsdf::{Bsdf, BsdfFlags, BsdfSample, MAX_LOBES};
use crate::emitter::{Emitter, LightSample, Reference};
use crate::integrator::metric::{RunningMean, ShadowTally};
use crate::integrator::shading::ShadingPoint;
use crate::integrator::stats::RayStats;
use crate::math::{Ray, Rgb, Vec2, Vec3};
use crate::medium::Phase;
use crate::sampling::points::unit_square;
use crate::sampling::{Distribution, EffectSpec, Rng, SetPoint};
use crate::scene::NO_MEDIUM;

/// The largest probability with which Russian roulette keeps a path.
const RR_MAX: f32 = 0.95;

/// The live paths of a wave, one entry per path in each buffer.
#[derive(Default)]
pub(super) struct Paths {
    /// The ray each path follows next.
    pub(super) ray: Vec<Ray>,
    /// The sample of the wave the path adds its radiance to.
    pub(super) slot: Vec<u32>,
    /// Throughput: what the radiance found next is multiplied by.
    pub(super) beta: Vec<Rgb>,
    /// The product of the `eta²` of the interfaces crossed (see
    /// [`BsdfSample::eta`](crate::bsdf::BsdfSample::eta)).
    pub(super) eta2: Vec<f32>,
    /// The path's stream (its primary sample's).
    pub(super) rng: Vec<Rng>,
    /// The vertex the ray left from, and its shading normal (zero for the
    /// camera): where the light sampler's probability of the emitter met is
    /// asked.
    pub(super) from: Vec<(Vec3, Vec3)>,
    /// What the emission the ray meets is weighed by: the BSDF's
    /// solid-angle density times its samples at the vertex the ray left
    /// (0 after a delta lobe or from the camera: the emission then counts
    /// whole), and the emitter samples taken there.
    pub(super) mis: Vec<(f32, Nee)>,
}

/// The emitter samples a vertex took (next-event estimation), as the
/// emission met from it is weighed against them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Nee {
    /// None: the emission met counts whole.
    None,
    /// This many, each toward an emitter chosen by the light sampler.
    Choice(f32),
    /// A set toward every emitter, of the emitter's shadow rays (the
    /// thesis's shadow sets).
    Sets,
}

impl Paths {
    #[inline]
    pub(super) fn clear(&mut self) {
        self.ray.clear();
        self.slot.clear();
        self.beta.clear();
        self.eta2.clear();
        self.rng.clear();
        self.from.clear();
        self.mis.clear();
    }

    #[inline]
    pub(super) fn len(&self) -> usize {
        self.ray.len()
    }

    #[inline]
    pub(super) fn push(
        &mut self,
        ray: Ray,
        slot: u32,
        (beta, eta2): (Rgb, f32),
        rng: Rng,
        (from, mis): ((Vec3, Vec3), (f32, Nee)),
    ) {
        self.ray.push(ray);
        self.slot.push(slot);
        self.beta.push(beta);
        self.eta2.push(eta2);
        self.rng.push(rng);
        self.from.push(from);
        self.mis.push(mis);
    }
}

/// Shadow rays, each with the sample it lights, what it brings if nothing
/// blocks it, and the shadow set whose metric judges it ([`NO_SET`]: none).
#[derive(Default)]
pub(super) struct ShadowRays {
    pub(super) ray: Vec<Ray>,
    pub(super) slot: Vec<u32>,
    pub(super) value: Vec<Rgb>,
    pub(super) set: Vec<u32>,
}

impl ShadowRays {
    #[inline]
    pub(super) fn clear(&mut self) {
        self.ray.clear();
        self.slot.clear();
        self.value.clear();
        self.set.clear();
    }

    #[inline]
    pub(super) fn push(&mut self, ray: Ray, slot: u32, value: Rgb, set: u32) {
        self.ray.push(ray);
        self.slot.push(slot);
        self.value.push(value);
        self.set.push(set);
    }
}

/// No shadow set: a ray no metric judges.
pub(super) const NO_SET: u32 = u32::MAX;

/// The shadow rays of a bounce: `now`, traced first, and `later`, the
/// members past the first `k` of the sets the shadow metric judges, traced
/// only for the sets it does not stop (see `Wavefront::occlude`).
#[derive(Default)]
pub(super) struct Shadows {
    pub(super) now: ShadowRays,
    pub(super) later: ShadowRays,
    pub(super) sets: Vec<ShadowTally>,
}

impl Shadows {
    #[inline]
    pub(super) fn clear(&mut self) {
        self.now.clear();
        self.later.clear();
        self.sets.clear();
    }
}

/// The weight of the emission of an emitter that a path meets, having left
/// its last vertex with BSDF density `pdf` times the BSDF samples taken
/// there (0: from the camera or a delta lobe, which next-event estimation
/// could not have drawn) beside the emitter samples `nee`: the power
/// heuristic against the emitter samples' density (`density()` of one
/// sample toward where the path met it, times their count and, under a
/// choice among emitters, the probability `choice()` that the light
/// sampler chose this one from that vertex; a set has the size of the
/// emitter's shadow set `shadow`); 1 if the light sampler could not have
/// chosen it there; 0 for an emitter sampled without a density (the
/// thesis's penumbra model), whose light its shadow rays alone bring.
#[inline]
pub(super) fn emission_weight(
    shadow: EffectSpec,
    (pdf, nee): (f32, Nee),
    choice: impl FnOnce() -> f32,
    density: impl FnOnce() -> f32,
) -> f32 {
    if pdf == 0.0 {
        return 1.0;
    }
    let pdf_light = match nee {
        Nee::None => return 1.0,
        Nee::Choice(samples) => {
            let pmf = choice();
            if pmf <= 0.0 {
                return 1.0;
            }
            samples * pmf * density()
        }
        Nee::Sets => shadow.rays as f32 * density(),
    };
    if pdf_light > 0.0 {
        power_heuristic(pdf, pdf_light)
    } else {
        0.0
    }
}

/// The throughput and `eta²` product of the path the BSDF sample `s`
/// continues from `v`, one of `n` samples there; `None` if the sample has
/// no density where it needs one, carries nothing, or Russian roulette
/// (when `roulette` gives its number) ends it. Roulette keeps a path with
/// probability `min(max(throughput) · eta², 0.95)`, as Mitsuba 3 does, so
/// that the radiance scale of a crossing into a denser medium does not
/// end paths that will cross back out.
#[inline]
pub(super) fn go_through(
    v: &Vertex<'_>,
    s: &BsdfSample,
    n: f32,
    roulette: Option<f32>,
) -> Option<(Rgb, f32)> {
    if !s.flags.is_delta() && (s.pdf <= 0.0 || s.pdf.is_nan()) {
        return None;
    }
    let mut beta = v.beta * s.weight / n;
    let eta2 = v.eta2 * s.eta * s.eta;
    if let Some(u) = roulette {
        let q = (beta.max_element() * eta2).min(RR_MAX);
        if u >= q || q.is_nan() {
            return None;
        }
        beta /= q;
    }
    (beta.max_element() > 0.0).then_some((beta, eta2))
}

/// Counts a BSDF sample's ray as a reflection or a refraction ray.
#[inline]
pub(super) fn count_bounce(stats: &mut RayStats, flags: BsdfFlags) {
    if flags.contains(BsdfFlags::TRANSMISSION) {
        stats.refraction += 1;
    } else {
        stats.reflection += 1;
    }
}

/// Counts a BSDF sample's ray, left untraced by the metric, as a saved
/// reflection or refraction ray.
#[inline]
pub(super) fn count_saved(stats: &mut RayStats, flags: BsdfFlags) {
    if flags.contains(BsdfFlags::TRANSMISSION) {
        stats.saved.refraction += 1;
    } else {
        stats.saved.reflection += 1;
    }
}

/// A shading point, as next-event estimation reads it.
pub(super) struct Vertex<'h> {
    pub(super) hit: &'h Hit,
    /// Where its rays leave from (the hit's own geometric normal).
    pub(super) at: ShadingPoint,
    pub(super) wo: Vec3,
    pub(super) beta: Rgb,
    pub(super) eta2: f32,
    pub(super) slot: u32,
}

/// One of `e` emitter samples at `v` toward `emitter` (chosen with
/// probability `pmf`) with the point `point`, beside `b` BSDF samples
/// (`counts`): its shadow ray and what it brings,
/// `f · L · cos / (pdf · pmf · e)` weighed by the power heuristic, pushed
/// to `shadows` unless it brings nothing.
#[inline]
pub(super) fn light_sample(
    v: &Vertex<'_>,
    bsdf: &Bsdf,
    (emitter, escape): (&Emitter, Escape),
    point: Vec2,
    (e, b, pmf): (f32, f32, f32),
    shadows: &mut Shadows,
) {
    let p = SetPoint::uniform(point).native();
    let Some(ls) = sample_emitter(
        emitter,
        Reference::new(v.hit.p, v.hit.time),
        (p, Distribution::Jitter),
        escape,
    ) else {
        return;
    };
    let weigh = |pdf_b: f32| power_heuristic(e * pmf * ls.pdf, b * pdf_b);
    let f = bsdf.eval(v.hit, v.wo, ls.dir);
    shadow_ray(
        v,
        bsdf,
        (&ls, f),
        weigh,
        e * pmf,
        (&mut shadows.now, NO_SET),
    );
}

/// What a vertex needs of its material's lobes.
#[derive(Clone, Copy, Debug)]
pub(super) struct Material {
    /// It has a smooth lobe: emitter samples can light it.
    pub(super) smooth: bool,
    /// Its lobes are all pass-throughs (`null`): a volumetric path crosses
    /// it without a scattering.
    pub(super) pass: bool,
    /// The set of BSDF samples a vertex drawing the thesis's sets takes:
    /// the largest set its lobes ask for, else the render's reflection set.
    pub(super) set: EffectSpec,
}

impl Material {
    /// What a vertex needs of `bsdf`, whose lobes ask for `sets` (by slot).
    #[inline]
    pub(super) fn of(
        bsdf: &Bsdf,
        sets: &[Option<EffectSpec>; MAX_LOBES],
        reflection: EffectSpec,
    ) -> Material {
        let largest = sets.iter().flatten().max_by_key(|s| s.rays);
        Material {
            smooth: bsdf.lobes().any_smooth(),
            pass: bsdf
                .lobes()
                .iter()
                .all(|(_, f)| f.contains(BsdfFlags::NULL)),
            set: largest.copied().unwrap_or(reflection),
        }
    }
}

/// How far a shadow ray toward an emitter at infinity goes: past the
/// sphere around the world's bounds.
#[derive(Clone, Copy, Debug)]
pub(super) struct Escape {
    pub(super) center: Vec3,
    pub(super) radius: f32,
}

/// A sample of `emitter` seen from `r` for the distribution point `point`
/// of `d`: [`Emitter::sample_one`], or for an emitter at infinity a
/// direction with a target beyond the world (`escape`).
#[inline]
pub(super) fn sample_emitter(
    emitter: &Emitter,
    r: Reference,
    (point, d): (Vec3, Distribution),
    escape: Escape,
) -> Option<LightSample> {
    if !emitter.is_infinite() {
        return emitter.sample_one(r, point, d);
    }
    let p = r.p;
    let (dir, radiance, pdf) = emitter.sample_direction(unit_square(point, d))?;
    let far = 2.0 * (escape.radius + (p - escape.center).length()) + 1.0;
    Some(LightSample {
        target: p + dir * far,
        dir,
        weight: radiance / pdf,
        pdf,
    })
}

/// The shadow ray of the light sample `ls` at `v`, toward which the BSDF
/// is `f`, one of `n` (the
/// sample's share: divided by `n`), and what it brings if unblocked:
/// `f · weight · cos / n`, times `weigh` of the BSDF's density toward it
/// where the sample has a density (1 where it has none: a point light, the
/// thesis's penumbra model). Pushed to `rays`, judged with shadow set `set`,
/// unless it brings nothing.
#[inline]
pub(super) fn shadow_ray(
    v: &Vertex<'_>,
    bsdf: &Bsdf,
    (ls, f): (&LightSample, Rgb),
    weigh: impl Fn(f32) -> f32,
    n: f32,
    (rays, set): (&mut ShadowRays, u32),
) {
    let wi = ls.dir;
    let cos = v.hit.n.dot(wi).abs();
    if f == Rgb::ZERO || cos <= 0.0 {
        return;
    }
    let w = if ls.pdf > 0.0 {
        weigh(bsdf.pdf(v.hit, v.wo, wi))
    } else {
        1.0
    };
    let ray = v.at.spawn_ray_to(v.at.origin(wi), ls.target);
    rays.push(ray, v.slot, v.beta * f * ls.weight * (cos * w / n), set);
}

/// The power heuristic (β = 2) weight of a sample drawn with density `a`
/// against another strategy's density `b`.
#[inline]
pub(super) fn power_heuristic(a: f32, b: f32) -> f32 {
    let (a2, b2) = (a * a, b * b);
    if a2 + b2 > 0.0 {
        a2 / (a2 + b2)
    } else {
        0.0
    }
}

/// What a volumetric path (`volpath` and `volpathmis`, see `volume.rs`) carries besides its
/// ray, sample and throughput.
#[derive(Clone, Copy, Debug)]
pub(super) struct VolState {
    /// The medium the ray travels in ([`NO_MEDIUM`](crate::scene::NO_MEDIUM): none).
    pub(super) medium: u32,
    /// Scatterings so far (surfaces other than `null` and real collisions
    /// in media): Mitsuba's depth.
    pub(super) depth: u32,
    /// Steps so far (every event).
    pub(super) step: u32,
    /// The colour channel distances are drawn by.
    pub(super) channel: u8,
    /// The emission met next counts whole (Mitsuba's `specular_chain`,
    /// or the camera ray).
    pub(super) direct: bool,
    /// The last scattering drew the thesis's sets (`distributed`): the
    /// emission met next is weighed against its emitter's shadow set, and
    /// `last_pdf` is the density of the set of directions drawn there.
    pub(super) sets: bool,
    /// The product of the relative indices crossed (for roulette).
    pub(super) eta: f32,
    /// The last scattering point and its shading normal (zero in a
    /// medium), and the density of the direction drawn there.
    pub(super) last: (Vec3, Vec3),
    pub(super) last_pdf: f32,
    /// How far along the ray the medium begins: a camera ray's near clip
    /// plane (Mitsuba's camera rays start there), else 0.
    pub(super) skip: f32,
    /// The last step was a null collision (`volpathmis` plays no roulette
    /// after one).
    pub(super) last_null: bool,
}

/// A `volpathmis` path's densities over its contributions (Mitsuba's
/// `p_over_f`), per colour channel `i` of the contribution: with spectral
/// MIS, row `i` holds, for each channel `j`, the density of the path when
/// its distances are drawn by channel `j` over the contribution in channel
/// `i`; without it, row 0 alone holds, for each `i`, the density by the
/// path's channel over the contribution in `i`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Densities(pub(super) [Rgb; 3]);

/// The live volumetric paths of a wave.
#[derive(Default)]
pub(super) struct VolPaths {
    pub(super) ray: Vec<Ray>,
    pub(super) slot: Vec<u32>,
    pub(super) beta: Vec<Rgb>,
    pub(super) rng: Vec<Rng>,
    pub(super) state: Vec<VolState>,
    /// `volpathmis`: each path's densities, by the path's own sampling and
    /// by next-event estimation from its last scattering.
    pub(super) densities: Vec<[Densities; 2]>,
}

impl VolPaths {
    pub(super) fn clear(&mut self) {
        self.ray.clear();
        self.slot.clear();
        self.beta.clear();
        self.rng.clear();
        self.state.clear();
        self.densities.clear();
    }

    pub(super) fn push(&mut self, ray: Ray, slot: u32, beta: Rgb, rng: Rng, state: VolState) {
        self.ray.push(ray);
        self.slot.push(slot);
        self.beta.push(beta);
        self.rng.push(rng);
        self.state.push(state);
    }
}

/// Shadow rays through media: each from its origin to its target (the
/// ray's direction is the whole segment), the medium it starts in, the
/// stream its tracking reads, what it brings if it passes whole
/// (`volpathmis`: the emitted radiance, weighed by its densities), and the
/// shadow set whose metric judges it ([`NO_SET`]: none).
#[derive(Default)]
pub(super) struct VolShadows {
    pub(super) ray: Vec<Ray>,
    pub(super) slot: Vec<u32>,
    pub(super) value: Vec<Rgb>,
    pub(super) medium: Vec<u32>,
    pub(super) rng: Vec<Rng>,
    pub(super) set: Vec<u32>,
    /// `volpathmis`: the densities of the path ending at the emitter by
    /// next-event estimation and by the path's own sampling.
    pub(super) densities: Vec<[Densities; 2]>,
    /// `volpathmis`: the channel of the path, which its tracking draws
    /// distances by.
    pub(super) channel: Vec<u8>,
}

impl VolShadows {
    pub(super) fn clear(&mut self) {
        self.ray.clear();
        self.slot.clear();
        self.value.clear();
        self.medium.clear();
        self.rng.clear();
        self.densities.clear();
        self.channel.clear();
        self.set.clear();
    }

    #[inline]
    pub(super) fn push(
        &mut self,
        ray: Ray,
        (slot, value): (u32, Rgb),
        (medium, rng): (u32, Rng),
        set: u32,
    ) {
        self.ray.push(ray);
        self.slot.push(slot);
        self.value.push(value);
        self.medium.push(medium);
        self.rng.push(rng);
        self.set.push(set);
    }
}

/// A worker's volumetric buffers, kept from wave to wave.
#[derive(Default)]
pub(super) struct Volume {
    pub(super) paths: VolPaths,
    pub(super) next: VolPaths,
    /// The step's shadow rays traced first, and the members past the first
    /// `k` of the sets the shadow metric judges (traced only for the sets
    /// it does not stop), with the sets' tallies.
    pub(super) shadows: VolShadows,
    pub(super) later: VolShadows,
    pub(super) tallies: Vec<ShadowTally>,
    /// What each shadow ray of `shadows` lets through.
    pub(super) passed: Vec<Rgb>,
    /// A surface vertex's sets as the path tracer draws them, before they
    /// take their media (see `volume_sets.rs`).
    pub(super) set_paths: Paths,
    pub(super) set_shadows: Shadows,
    /// Beside each of the wavefront's judged sets (at surfaces), the state
    /// of the path at its vertex and the media its object bounds.
    pub(super) pending_state: Vec<(VolState, Option<[u32; 2]>)>,
    /// The judged sets of phase directions (at medium collisions).
    pub(super) medium_pending: Vec<MediumPending>,
}

/// The medium a ray leaving a surface of `media` (`[interior, exterior]`)
/// in direction `d` enters, beside geometric normal `ng`; `current` where
/// the surface bounds none (Mitsuba's `target_medium`).
#[inline]
pub(super) fn target_medium(media: Option<&[u32; 2]>, ng: Vec3, d: Vec3, current: u32) -> u32 {
    match media {
        Some(&[interior, exterior]) if interior != NO_MEDIUM || exterior != NO_MEDIUM => {
            if d.dot(ng) > 0.0 {
                exterior
            } else {
                interior
            }
        }
        _ => current,
    }
}

/// A medium collision drawing a set of phase directions: where, in which
/// medium, the path arriving (its throughput with the albedo applied, its
/// sample, stream and state, that of the paths its set starts) and the set.
#[derive(Clone, Copy)]
pub(super) struct MediumVertex {
    pub(super) p: Vec3,
    pub(super) wo: Vec3,
    pub(super) time: f32,
    pub(super) medium: u32,
    pub(super) beta: Rgb,
    pub(super) slot: u32,
    pub(super) rng: Rng,
    pub(super) st: VolState,
    pub(super) set: EffectSpec,
}

impl MediumVertex {
    /// Starts the path of member `k` of the set, at `point`, adding to
    /// sample `slot` with `1 / share` of the throughput, unless its
    /// direction has no density or carries nothing.
    #[inline]
    pub(super) fn member(
        &self,
        phase: &Phase,
        (k, point): (u32, Vec3),
        (slot, share): (u32, f32),
        next: &mut VolPaths,
        stats: &mut RayStats,
    ) {
        let d = self.set.distribution;
        let Some(ps) = phase.sample(self.p, self.wo, unit_square(point, d)) else {
            return;
        };
        if ps.pdf <= 0.0 || ps.pdf.is_nan() {
            return;
        }
        let through = self.beta * (ps.weight / share);
        if through.max_element() <= 0.0 {
            return;
        }
        let n = self.set.rays;
        let state = VolState {
            last: (self.p, Vec3::ZERO),
            last_pdf: n as f32 * ps.pdf,
            ..self.st
        };
        let stream = self.rng.child(k as usize, n as usize);
        let ray = Ray::new(self.p, ps.wi, self.time);
        next.push(ray, slot, through, stream, state);
        stats.media.scattered += 1;
    }
}

/// A set of phase directions the reflection metric judges, at a first
/// collision: the vertex, the samples `acc..acc + batch` its latest members
/// add to, and the running mean of the members traced so far.
pub(super) struct MediumPending {
    pub(super) vertex: MediumVertex,
    pub(super) acc: u32,
    pub(super) batch: u32,
    pub(super) mean: RunningMean,
}
