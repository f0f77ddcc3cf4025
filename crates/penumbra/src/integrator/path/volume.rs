//! `volpath`: the path tracer's wavefront tracking paths through
//! participating media, as Mitsuba 3's `volpath` (see the
//! [module docs](super) for the estimator).
//!
//! Each path carries the medium it is in (the camera's to start with),
//! its scattering depth, its step (every event, null ones included, is a
//! step: its random numbers are those of `path.derive(step)`), the colour
//! channel its distances are drawn by, and what the emission it meets
//! next is weighed by. A step of the wave: one closest-hit call for every
//! live path; then for each, in a medium, a tentative collision drawn
//! against the medium's majorant before the surface met
//! ([`Medium::sample_interaction`]): a null one moves the path on
//! unchanged, a real one scatters it by the phase function, with
//! next-event estimation from the collision; otherwise (no medium, or no
//! collision before the surface) the surface: its emission, next-event
//! estimation on its smooth lobes, and a BSDF sample, a `null` surface's
//! pass-through changing the path's medium without counting as a
//! scattering. Then every shadow ray is traced through the surfaces that
//! let light through (their shadow transmittance: 1 for `null`) and the
//! media it crosses ([`Medium::transmittance`]).
//!
//! [`Medium::sample_interaction`]: crate::medium::Medium::sample_interaction
//! [`Medium::transmittance`]: crate::medium::Medium::transmittance

use super::vertex::{
    emission_weight, power_heuristic, sample_emitter, target_medium, Densities, Nee, Vertex,
    VolState, Volume, NO_SET,
};
use super::volume_sets::{medium_sets, surface_sets, SetsContext, VolOut};
use super::wavefront::Wavefront;
use crate::accel::Hit;
use crate::bsdf::BsdfFlags;
use crate::bsdf::{Bsdf, BsdfSample};
use crate::emitter::Reference;
use crate::integrator::clip::clip_camera_hits;
use crate::integrator::shading::ShadingPoint;
use crate::integrator::streams::{self, LOBE_DIMENSION};
use crate::math::{Ray, Rgb, Vec3};
use crate::medium::{channel_of, Interaction, Medium};
use crate::sampling::BounceNumbers;
use crate::sampling::{Distribution, EffectSpec, Rng, SetPoint};
use crate::scene::{Scene, NO_MEDIUM};

/// Where a shadow ray ends, as a fraction of the way to its target.
pub(super) const SHADOW_END: f32 = 1.0 - 1e-4;

/// The most surfaces a shadow ray crosses before it is taken as blocked.
pub(super) const MAX_CROSSINGS: u32 = 1024;

/// The most steps a path takes: a bound on null collisions and crossings
/// of `null` surfaces, which do not count toward `max_depth`.
pub(super) const MAX_STEPS: u32 = 1 << 20;

/// The largest probability with which Russian roulette keeps a path.
pub(super) const RR_MAX: f32 = 0.95;

/// The dimensions of a step's numbers.
pub(super) const ROULETTE: u64 = 0;
pub(super) const DISTANCE: u64 = 1;
pub(super) const NULL_CHOICE: u64 = 2;
pub(super) const EMITTER_CHOICE: u64 = 3;
pub(super) const EMITTER_POINT: u64 = 4;
pub(super) const DIRECTION: u64 = 6;

/// Per channel, the transmittance over the stretch `mi` covered and its
/// density of being drawn so: `T·σ̄` where a collision was drawn, `T` where
/// the stretch ends first (at `end`, from the ray's origin).
#[inline]
pub(super) fn free_flight(mi: &Interaction, end: f32) -> (Rgb, Rgb) {
    let t = mi.t.min(end) - mi.mint;
    let tr = mi
        .majorant
        .map(|m| if m > 0.0 { (-t * m).exp() } else { 1.0 });
    let pdf = if mi.is_valid() { tr * mi.majorant } else { tr };
    (tr, pdf)
}

/// A tentative collision in `medium` along `ray` before the surface at
/// `t_surface`, from `skip` on (a camera ray's near clip plane), drawn by
/// channel `channel` with the number `u`; and the distance to the surface
/// from where the drawing started.
#[inline]
pub(super) fn tentative_collision(
    medium: &Medium,
    ray: &Ray,
    (skip, t_surface): (f32, f32),
    u: f32,
    channel: usize,
) -> (Interaction, f32) {
    let skip = skip.min(t_surface);
    let t_surface = t_surface - skip;
    let from = (ray.origin + ray.dir * skip, ray.dir);
    (
        medium.sample_interaction(from, t_surface, u, channel),
        t_surface,
    )
}

/// The BSDF's direction at `hit` seen from `wo`, drawn with the step's
/// numbers `u`.
#[inline]
pub(super) fn bsdf_direction(
    bsdf: &Bsdf,
    hit: &Hit,
    wo: Vec3,
    u: &mut BounceNumbers,
) -> Option<BsdfSample> {
    let mut point = SetPoint::uniform(u.point(DIRECTION));
    if bsdf.wants_third() {
        point = point.with_third(u.value(LOBE_DIMENSION + DIRECTION));
    }
    bsdf.sample(hit, wo, None, point)
}

/// The mean of a colour's channels.
#[inline]
pub(super) fn mean(c: Rgb) -> f32 {
    c.element_sum() / 3.0
}

/// `a / b` channel by channel, 0 where `b` is 0.
#[inline]
pub(super) fn ratio(a: Rgb, b: Rgb) -> Rgb {
    let (a, b) = (a.to_array(), b.to_array());
    Rgb::from_array(std::array::from_fn(|i| {
        if b[i] != 0.0 {
            a[i] / b[i]
        } else {
            0.0
        }
    }))
}

impl Wavefront<'_> {
    /// Traces the camera rays in `self.paths` (their streams beside them)
    /// through surfaces and media to their ends, adding what they gather
    /// to `self.radiance`, sample by sample.
    pub(super) fn volume_wave(&mut self) {
        let scene = self.scene;
        let camera_medium = scene.camera_medium.unwrap_or(NO_MEDIUM);
        let vol = &mut self.volume;
        vol.paths.clear();
        for (k, (ray, &rng)) in self.paths.ray.iter().zip(&self.paths.rng).enumerate() {
            let channel = (rng.derive(streams::CHANNEL).next_f32() * 3.0).min(2.0) as u8;
            let ray = Ray::new(ray.origin, ray.dir.normalize(), ray.time);
            let skip = scene
                .camera
                .clip(&ray)
                .map_or(0.0, |(near, _)| near.max(0.0));
            let state = VolState {
                skip,
                medium: camera_medium,
                depth: 0,
                step: 0,
                channel,
                direct: !self.settings.hide_emitters,
                sets: false,
                eta: 1.0,
                last: (ray.origin, Vec3::ZERO),
                last_pdf: 1.0,
                last_null: false,
            };
            vol.paths.push(ray, k as u32, Rgb::ONE, rng, state);
            if self.settings.spectral_mis.is_some() {
                vol.paths.densities.push([Densities::ONE; 2]);
            }
        }
        self.pending.clear();
        self.volume.pending_state.clear();
        self.volume.medium_pending.clear();
        let mut first = true;
        loop {
            while !self.volume.paths.ray.is_empty() {
                self.batches.closest_hit.add(self.volume.paths.ray.len());
                scene.world.intersect_all(
                    &self.volume.paths.ray,
                    0.0,
                    &mut self.packet,
                    &mut self.hits,
                );
                if first {
                    clip_camera_hits(scene, &self.volume.paths.ray, &mut self.hits);
                    first = false;
                }
                if let Some(spectral) = self.settings.spectral_mis {
                    self.volume_mis_step(spectral);
                    self.volume_mis_occlude(spectral);
                } else {
                    self.volume_step();
                    self.volume_occlude();
                }
                let vol = &mut self.volume;
                std::mem::swap(&mut vol.paths, &mut vol.next);
            }
            // The judged sets' next members.
            if !self.volume_judge() {
                break;
            }
        }
    }

    /// One step of every live path (see the [module docs](self)): the
    /// paths that go on into `self.volume.next`, their shadow rays into
    /// `self.volume.shadows`.
    fn volume_step(&mut self) {
        let scene: &Scene = self.scene;
        let Wavefront {
            settings,
            lights: chooser,
            shadow_sets,
            stats,
            materials,
            escape,
            hits,
            radiance,
            points,
            set_lights,
            pending,
            volume,
            ..
        } = self;
        let Volume {
            paths,
            next,
            shadows,
            later,
            tallies,
            set_paths,
            set_shadows,
            pending_state,
            medium_pending,
            ..
        } = volume;
        next.clear();
        shadows.clear();
        later.clear();
        tallies.clear();
        let cx = SetsContext {
            scene,
            shadow: shadow_sets,
            metric: settings.metric,
        };
        // Where a vertex drawing sets writes; `first`: it is a path's first
        // vertex, whose set the reflection metric judges.
        macro_rules! sets_out {
            ($first:expr) => {
                VolOut {
                    next: &mut *next,
                    shadows: &mut *shadows,
                    later: &mut *later,
                    tallies: &mut *tallies,
                    stats: &mut *stats,
                    points: &mut *points,
                    lights: &mut *set_lights,
                    escape: *escape,
                    judge: settings
                        .metric
                        .filter(|m| m.reflections && $first)
                        .map(|m| m.min_rays.max(2)),
                    radiance: &mut *radiance,
                    pending: &mut *pending,
                    pending_state: &mut *pending_state,
                    medium_pending: &mut *medium_pending,
                }
            };
        }
        let max_depth = settings.max_depth.unwrap_or(u32::MAX);
        let lights = scene.emitters.len();
        // Emission met is weighed as `path`'s is, one emitter sample taken.
        let single = EffectSpec {
            rays: 1,
            distribution: Distribution::Jitter,
        };
        #[allow(clippy::needless_range_loop)]
        for i in 0..paths.ray.len() {
            let (ray, slot, mut beta, rng) =
                (paths.ray[i], paths.slot[i], paths.beta[i], paths.rng[i]);
            let mut st = paths.state[i];
            let skip = std::mem::take(&mut st.skip);
            if st.step >= MAX_STEPS || beta.max_element() <= 0.0 || beta.max_element().is_nan() {
                continue;
            }
            let mut u = settings
                .sampler
                .bounce(rng.derive(streams::bounce(st.step)));
            st.step += 1;
            // Russian roulette, as Mitsuba's volpath plays it: past
            // `rr_depth` scatterings, at every step.
            let r = u.value(ROULETTE);
            if st.depth > settings.rr_depth {
                let q = (beta.max_element() * st.eta * st.eta).min(RR_MAX);
                if r >= q || q.is_nan() {
                    continue;
                }
                beta /= q;
            }
            if st.depth >= max_depth {
                continue;
            }
            let hit = hits.get(i).map(|h| scene.world.surface(&ray, h));
            let t_surface = hit.map_or(f32::INFINITY, |h| h.t);
            let wo = -ray.dir;
            // The medium: a tentative collision before the surface.
            if st.medium != NO_MEDIUM {
                let medium = &scene.media[st.medium as usize];
                let channel = usize::from(st.channel);
                // From the near clip plane on, for a camera ray.
                let (mi, t_surface) = tentative_collision(
                    medium,
                    &ray,
                    (skip, t_surface),
                    u.value(DISTANCE),
                    channel,
                );
                let spectral = medium.has_spectral_extinction();
                if spectral {
                    // The transmittance over the stretch crossed, over the
                    // density of drawing it by the channel.
                    let (tr, pdf) = free_flight(&mi, t_surface);
                    let p = channel_of(pdf, channel);
                    beta = if p > 0.0 { beta * tr / p } else { Rgb::ZERO };
                }
                let choice = u.value(NULL_CHOICE);
                if mi.is_valid() {
                    let s = mi.sigma;
                    let null = mean(ratio(s.sigma_n, mi.majorant));
                    if choice < null {
                        // A null collision: on, unchanged.
                        stats.media.null_collisions += 1;
                        if spectral {
                            beta *= s.sigma_n / null;
                        }
                        let on = Ray::new(mi.p, ray.dir, ray.time);
                        next.push(on, slot, beta, rng, st);
                        continue;
                    }
                    stats.media.scatterings += 1;
                    st.depth += 1;
                    if st.depth >= max_depth {
                        continue;
                    }
                    beta *= if spectral {
                        s.sigma_s / mean(ratio(s.sigma_t, mi.majorant))
                    } else {
                        ratio(s.sigma_s, s.sigma_t)
                    };
                    let phase = &medium.phase;
                    if st.depth <= settings.sets_depth {
                        // The collision is vertex `depth − 1`: it draws sets.
                        let mut out = sets_out!(st.depth == 1);
                        let at = (mi.p, wo, ray.time);
                        medium_sets(cx, at, (st.medium, medium), (beta, slot, rng, st), &mut out);
                        continue;
                    }
                    // Next-event estimation from the collision.
                    if medium.sample_emitters && lights > 0 {
                        let pick = u.value(EMITTER_CHOICE);
                        let point = u.point(EMITTER_POINT);
                        if let Some((k, pmf)) = chooser.sample(mi.p, Vec3::ZERO, pick) {
                            let emitter = &scene.emitters[k as usize];
                            let p = SetPoint::uniform(point).native();
                            let r = Reference::new(mi.p, ray.time);
                            if let Some(ls) =
                                sample_emitter(emitter, r, (p, Distribution::Jitter), *escape)
                            {
                                let f = phase.eval(mi.p, wo, ls.dir);
                                let w = if ls.pdf > 0.0 {
                                    power_heuristic(pmf * ls.pdf, f)
                                } else {
                                    1.0
                                };
                                let value = beta * ls.weight * (f * w / pmf);
                                if value.max_element() > 0.0 {
                                    shadows.push(
                                        Ray::new(mi.p, ls.target - mi.p, ray.time),
                                        (slot, value),
                                        (st.medium, rng.derive(streams::tracking(st.step))),
                                        NO_SET,
                                    );
                                }
                            }
                        }
                    }
                    st.direct = !medium.sample_emitters;
                    st.sets = false;
                    // The phase function's direction.
                    let Some(ps) = phase.sample(mi.p, wo, u.point(DIRECTION)) else {
                        continue;
                    };
                    beta *= ps.weight;
                    stats.media.scattered += 1;
                    st.last = (mi.p, Vec3::ZERO);
                    st.last_pdf = ps.pdf;
                    next.push(Ray::new(mi.p, ps.wi, ray.time), slot, beta, rng, st);
                    continue;
                }
            }
            // The surface met, or what lies beyond everything.
            let seen = !(settings.hide_emitters && st.depth == 0);
            let prev = if st.direct {
                (0.0, Nee::None)
            } else if st.sets {
                (st.last_pdf, Nee::Sets)
            } else {
                (st.last_pdf, Nee::Choice(1.0))
            };
            // The emitter samples emission met is weighed against.
            let taken = |e: u32| {
                if st.sets {
                    shadow_sets[e as usize]
                } else {
                    single
                }
            };
            let (from, from_n) = st.last;
            let Some(hit) = hit else {
                if seen {
                    for &e in scene.far.iter() {
                        let emitter = &scene.emitters[e as usize];
                        let choice = || chooser.pmf(from, from_n, e);
                        let w = emission_weight(taken(e), prev, choice, || {
                            emitter.pdf_direction(ray.dir)
                        });
                        radiance[slot as usize] += beta * emitter.eval_miss(ray.dir) * w;
                    }
                }
                continue;
            };
            if let (Some(e), true) = (hit.emitter, seen) {
                let emitter = &scene.emitters[e as usize];
                let choice = || chooser.pmf(from, from_n, e);
                let density = || emitter.pdf(Reference::new(from, ray.time), hit.p, hit.ng);
                let w = emission_weight(taken(e), prev, choice, density);
                if w > 0.0 {
                    radiance[slot as usize] += beta * emitter.eval(hit.ng, hit.uv, ray.dir) * w;
                }
            }
            let bsdf = &scene.bsdfs[hit.material as usize];
            let at = ShadingPoint::new(&ray, hit.p, hit.ng);
            let media = scene.object_media.get(hit.object as usize);
            let material = &materials[hit.material as usize];
            if st.depth < settings.sets_depth && st.depth + 1 < max_depth && !material.pass {
                let v = Vertex {
                    hit: &hit,
                    at,
                    wo,
                    beta,
                    eta2: st.eta * st.eta,
                    slot,
                };
                let mut out = sets_out!(st.depth == 0);
                surface_sets(
                    cx,
                    &v,
                    (bsdf, material),
                    (rng, st, media),
                    (set_paths, set_shadows),
                    &mut out,
                );
                continue;
            }
            // Next-event estimation on the smooth lobes.
            let smooth = material.smooth;
            let pick = u.value(EMITTER_CHOICE);
            let point = u.point(EMITTER_POINT);
            if smooth && lights > 0 && st.depth + 1 < max_depth {
                if let Some((k, pmf)) = chooser.sample(hit.p, hit.n, pick) {
                    let emitter = &scene.emitters[k as usize];
                    let p = SetPoint::uniform(point).native();
                    let r = Reference::new(hit.p, ray.time);
                    if let Some(ls) = sample_emitter(emitter, r, (p, Distribution::Jitter), *escape)
                    {
                        let f = bsdf.eval(&hit, wo, ls.dir);
                        let cos = hit.n.dot(ls.dir).abs();
                        if f != Rgb::ZERO && cos > 0.0 {
                            let w = if ls.pdf > 0.0 {
                                power_heuristic(pmf * ls.pdf, bsdf.pdf(&hit, wo, ls.dir))
                            } else {
                                1.0
                            };
                            let origin = at.origin(ls.dir);
                            shadows.push(
                                at.spawn_ray_to(origin, ls.target),
                                (slot, beta * f * ls.weight * (cos * w / pmf)),
                                (
                                    target_medium(media, hit.ng, ls.dir, st.medium),
                                    rng.derive(streams::tracking(st.step)),
                                ),
                                NO_SET,
                            );
                        }
                    }
                }
            }
            // The BSDF's direction.
            let Some(s) = bsdf_direction(bsdf, &hit, wo, &mut u) else {
                continue;
            };
            if !s.flags.is_delta() && (s.pdf <= 0.0 || s.pdf.is_nan()) {
                continue;
            }
            beta *= s.weight;
            st.eta *= s.eta;
            if !s.flags.contains(BsdfFlags::NULL) {
                st.depth += 1;
                st.last = (hit.p, hit.n);
                st.last_pdf = s.pdf;
                st.sets = false;
                if s.flags.is_delta() {
                    st.direct = true;
                } else if s.flags.is_smooth() {
                    st.direct = false;
                }
                super::vertex::count_bounce(stats, s.flags);
            }
            st.medium = target_medium(media, hit.ng, s.wi, st.medium);
            next.push(at.spawn_ray(s.wi), slot, beta, rng, st);
        }
    }

    /// Traces every shadow ray of the step through the surfaces that let
    /// light through and the media it crosses, adding what arrives to its
    /// sample. A set the shadow metric judges whose first `k` members all
    /// let some light through, or were all blocked, stops there: their
    /// mean is its value (each of its rays counts `n / k` times) and the
    /// rest are never traced; the rest of the other sets are traced after.
    fn volume_occlude(&mut self) {
        let scene = self.scene;
        let Volume {
            shadows,
            later,
            tallies,
            passed,
            ..
        } = &mut self.volume;
        if !shadows.ray.is_empty() {
            self.stats.shadow += shadows.ray.len() as u64;
            self.batches.occlusion.add(shadows.ray.len());
            passed.clear();
            for k in 0..shadows.ray.len() {
                let mut rng = shadows.rng[k];
                let tr = shadow_transmittance(scene, shadows.ray[k], shadows.medium[k], &mut rng);
                if let Some(t) = tallies.get_mut(shadows.set[k] as usize) {
                    t.count(tr.max_element() > 0.0);
                }
                passed.push(tr);
            }
            for (k, &tr) in passed.iter().enumerate() {
                if tr.max_element() <= 0.0 {
                    continue;
                }
                let scale = match tallies.get(shadows.set[k] as usize) {
                    Some(t) if t.stops() => t.n as f32 / t.k as f32,
                    _ => 1.0,
                };
                self.radiance[shadows.slot[k] as usize] += shadows.value[k] * tr * scale;
            }
        }
        for t in tallies.iter().filter(|t| t.stops()) {
            self.stats.saved.shadow += u64::from(t.n - t.k);
        }
        for k in 0..later.ray.len() {
            if tallies[later.set[k] as usize].stops() {
                continue;
            }
            self.stats.shadow += 1;
            let mut rng = later.rng[k];
            let tr = shadow_transmittance(scene, later.ray[k], later.medium[k], &mut rng);
            if tr.max_element() > 0.0 {
                self.radiance[later.slot[k] as usize] += later.value[k] * tr;
            }
        }
    }
}

/// The fraction of light passing along the shadow segment `ray` (from its
/// origin to `origin + dir`, short of the end by [`SHADOW_END`]), starting
/// in `medium`: each surface crossed multiplies it by what it lets through
/// (its [null transmission](crate::bsdf::BsdfModel::null_transmission): 1
/// for `null`, what a thin sheet transmits, 0 for an opaque surface, which
/// stops it) and
/// changes the medium where the surface bounds media; each stretch in a
/// medium multiplies it by the medium's transmittance (drawing from `rng`
/// where tracking needs numbers). Objects that cast no shadows are passed.
pub(super) fn shadow_transmittance(scene: &Scene, ray: Ray, mut medium: u32, rng: &mut Rng) -> Rgb {
    let target = ray.origin + ray.dir;
    let mut tr = Rgb::ONE;
    let mut origin = ray.origin;
    for _ in 0..MAX_CROSSINGS {
        let to = target - origin;
        let length = to.length();
        if length.is_nan() || length <= 0.0 {
            return tr;
        }
        let dir = to / length;
        let end = length * SHADOW_END;
        let r = Ray::new(origin, dir, ray.time);
        let hit = scene.world.intersect(&r, 0.0, end);
        let t = hit.map_or(end, |h| h.t);
        if medium != NO_MEDIUM {
            tr *= scene.media[medium as usize].transmittance((origin, dir), t, rng);
        }
        let Some(h) = hit else {
            return tr;
        };
        let object = &scene.world.objects[h.object as usize];
        if object.casts_shadows {
            tr *= scene.bsdfs[h.material as usize].null_transmission(&h, dir);
        }
        if tr.max_element() <= 0.0 {
            return Rgb::ZERO;
        }
        medium = target_medium(scene.object_media.get(h.object as usize), h.ng, dir, medium);
        origin = ShadingPoint::new(&r, h.p, h.ng).origin(dir);
    }
    Rgb::ZERO
}
