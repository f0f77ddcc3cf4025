//! `volpathmis`: the volumetric wavefront weighed by multiple importance
//! sampling, as Mitsuba 3's `volpathmis` (Miller et al. 2019, "A null-
//! scattering path integral formulation of light transport"; see the
//! [module docs](super) for the estimator).
//!
//! A path does not carry its throughput but its [`Densities`]: for each
//! colour channel `i` of its contribution `f`, the densities `p` with which
//! it could have been drawn over `fᵢ`. Every event multiplies them by the
//! event's density over its contribution: a stretch crossed in a medium by
//! the transmittance's density under each channel's majorant (`T·σ̄` at a
//! collision, `T` past the end), a null collision by the probability of
//! taking it, a scattering by its direction's density. With spectral MIS
//! the densities of drawing distances by each channel are kept side by
//! side, and the contribution in channel `i` is `fᵢ` over their mean (the
//! balance heuristic over the channels, the one-sample model of choosing a
//! channel uniformly); without it, by the path's own channel alone.
//!
//! Next-event estimation traces its shadow ray through media by ratio
//! tracking, keeping two sets of densities for the path it makes: by
//! next-event estimation (the emitter's density at the end, the tracking's
//! tentative collisions passed without a choice) and by the path's own
//! sampling (the phase function's or BSDF's density at the start, each
//! null collision chosen with its probability). Emission that a path meets
//! after a scattering is weighed by its densities beside those of the same
//! path drawn by next-event estimation from its last scattering (kept
//! from there), by the balance heuristic over both strategies and, with
//! spectral MIS, over the channels.
//!
//! The step, its numbers and the rest are `volpath`'s (`volume.rs`), but
//! for Mitsuba's differences: Russian roulette is not played right after
//! a null collision, and paths end where a BSDF sample has no density.

use super::vertex::{sample_emitter, target_medium, Densities, VolShadows, NO_SET};
use super::volume::{
    bsdf_direction, free_flight, mean, ratio, tentative_collision, DIRECTION, DISTANCE,
    EMITTER_CHOICE, EMITTER_POINT, MAX_CROSSINGS, MAX_STEPS, NULL_CHOICE, ROULETTE, RR_MAX,
    SHADOW_END,
};
use super::wavefront::Wavefront;
use crate::bsdf::BsdfFlags;
use crate::emitter::{LightSample, Reference};
use crate::integrator::shading::ShadingPoint;
use crate::integrator::streams;
use crate::math::{Ray, Rgb, Vec3};
use crate::medium::{channel_of, Medium};
use crate::sampling::{Distribution, Rng, SetPoint};
use crate::scene::{Scene, NO_MEDIUM};

/// The most tentative collisions a shadow ray takes in one medium's
/// stretch.
const MAX_COLLISIONS: u32 = 100_000;

/// How a path's densities are kept: over every channel's distances
/// (spectral MIS) or by its own channel's.
#[derive(Clone, Copy, Debug)]
pub(super) struct Mode {
    pub(super) spectral: bool,
    pub(super) channel: usize,
}

impl Densities {
    /// Densities of a path that has drawn nothing yet.
    pub(super) const ONE: Densities = Densities([Rgb::ONE; 3]);

    /// Multiplies in an event of density `p` (per channel the distances
    /// may be drawn by) and contribution `f` (per channel of the
    /// contribution); what is not finite becomes 0 (Mitsuba's
    /// `update_weights`).
    #[inline]
    pub(super) fn update(&mut self, p: Rgb, f: Rgb, mode: Mode) {
        if mode.spectral {
            let (p, f) = (p.to_array(), f.to_array());
            for (row, fi) in self.0.iter_mut().zip(f) {
                let old = row.to_array();
                *row = Rgb::from_array(std::array::from_fn(|j| {
                    let r = p[j] / fi;
                    let r = if r.is_finite() { r } else { 0.0 } * old[j];
                    if r.is_nan() {
                        0.0
                    } else {
                        r
                    }
                }));
            }
        } else {
            let pdf = channel_of(p, mode.channel);
            let (old, f) = (self.0[0].to_array(), f.to_array());
            self.0[0] = Rgb::from_array(std::array::from_fn(|i| {
                let r = old[i] * (pdf / f[i]);
                if r.is_finite() {
                    r
                } else {
                    0.0
                }
            }));
        }
    }

    /// [`update`](Self::update) by a density and a contribution the same
    /// in every channel's terms.
    #[inline]
    fn scale(&mut self, p: f32, f: Rgb, mode: Mode) {
        self.update(Rgb::splat(p), f, mode);
    }

    /// The sum, per channel of the contribution, of the densities of
    /// `self` and `other` (or of `self` alone).
    #[inline]
    fn sums(&self, other: Option<&Densities>, mode: Mode) -> Rgb {
        let rows = (0..if mode.spectral { 3 } else { 1 })
            .map(|i| self.0[i] + other.map_or(Rgb::ZERO, |o| o.0[i]));
        if mode.spectral {
            let mut sums = [0.0; 3];
            for (s, row) in sums.iter_mut().zip(rows) {
                *s = row.element_sum();
            }
            Rgb::from_array(sums)
        } else {
            rows.sum()
        }
    }

    /// The path's throughput: its contribution over its density, per
    /// channel (Mitsuba's `mis_weight`); with `other`, over the sum of
    /// both strategies' densities (the balance heuristic). 0 where the
    /// densities vanish.
    #[inline]
    pub(super) fn weight(&self, other: Option<&Densities>, mode: Mode) -> Rgb {
        let sums = self.sums(other, mode);
        let n = if mode.spectral { 3.0 } else { 1.0 };
        sums.map(|s| if s == 0.0 { 0.0 } else { n / s })
    }

    /// True while some density is left (what keeps a shadow ray tracked).
    #[inline]
    fn alive(&self, mode: Mode) -> bool {
        if mode.spectral {
            self.weight(None, mode).max_element() != 0.0
        } else {
            self.0[0] != Rgb::ZERO
        }
    }
}

/// The emitted radiance a light sample brings (its weight times its
/// density: a point light's and the thesis's area lights' weights are
/// their radiance), the density of next-event estimation having chosen it
/// (`pmf` times its density, 1 for a light without one) and whether it has
/// none (a delta light, which the path's own sampling cannot reach).
#[inline]
fn emitted(ls: &LightSample, pmf: f32) -> (Rgb, f32, bool) {
    if ls.pdf > 0.0 {
        (ls.weight * ls.pdf, pmf * ls.pdf, false)
    } else {
        (ls.weight, pmf, true)
    }
}

impl Wavefront<'_> {
    /// One step of every live `volpathmis` path (see the [module
    /// docs](self)): the paths that go on into `self.volume.next`, their
    /// shadow rays into `self.volume.shadows`.
    pub(super) fn volume_mis_step(&mut self, spectral: bool) {
        let scene: &Scene = self.scene;
        let Wavefront {
            settings,
            lights: chooser,
            stats,
            materials,
            escape,
            hits,
            radiance,
            volume,
            ..
        } = self;
        let (paths, next, shadows) = (&volume.paths, &mut volume.next, &mut volume.shadows);
        next.clear();
        shadows.clear();
        let max_depth = settings.max_depth.unwrap_or(u32::MAX);
        let lights = scene.emitters.len();
        #[allow(clippy::needless_range_loop)]
        for i in 0..paths.ray.len() {
            let (ray, slot, rng) = (paths.ray[i], paths.slot[i], paths.rng[i]);
            let [mut pf, mut pn] = paths.densities[i];
            let mut st = paths.state[i];
            let mode = Mode {
                spectral,
                channel: usize::from(st.channel),
            };
            let skip = std::mem::take(&mut st.skip);
            let acc = &mut radiance[slot as usize];
            if st.step >= MAX_STEPS {
                continue;
            }
            let mut u = settings
                .sampler
                .bounce(rng.derive(streams::bounce(st.step)));
            st.step += 1;
            // Russian roulette past `rr_depth` scatterings, but not
            // right after a null collision.
            let r = u.value(ROULETTE);
            if !st.last_null && st.depth > settings.rr_depth {
                let q = (pf.weight(None, mode).max_element() * st.eta * st.eta).min(RR_MAX);
                if r >= q || q.is_nan() {
                    continue;
                }
                pf.scale(q, Rgb::ONE, mode);
            }
            st.last_null = false;
            if st.depth >= max_depth || pf.weight(None, mode).max_element() == 0.0 {
                continue;
            }
            let hit = hits.get(i).map(|h| scene.world.surface(&ray, h));
            let t_surface = hit.map_or(f32::INFINITY, |h| h.t);
            let wo = -ray.dir;
            // The medium: a tentative collision before the surface.
            if st.medium != NO_MEDIUM {
                let medium = &scene.media[st.medium as usize];
                // From the near clip plane on, for a camera ray.
                let (mi, t_surface) = tentative_collision(
                    medium,
                    &ray,
                    (skip, t_surface),
                    u.value(DISTANCE),
                    mode.channel,
                );
                let is_spectral = medium.has_spectral_extinction();
                if is_spectral {
                    let (tr, pdf) = free_flight(&mi, t_surface);
                    pf.update(pdf, tr, mode);
                    pn.update(pdf, tr, mode);
                }
                let choice = u.value(NULL_CHOICE);
                if mi.is_valid() {
                    let s = mi.sigma;
                    let null = mean(ratio(s.sigma_n, mi.majorant));
                    if choice < null {
                        // A null collision: on, unchanged.
                        stats.media.null_collisions += 1;
                        st.last_null = true;
                        if is_spectral {
                            pf.scale(null, s.sigma_n, mode);
                            pn.scale(1.0, s.sigma_n, mode);
                        } else {
                            pf.update(s.sigma_n, s.sigma_n, mode);
                            pn.scale(1.0, Rgb::splat(null), mode);
                        }
                        let on = Ray::new(mi.p, ray.dir, ray.time);
                        next.push(on, slot, Rgb::ONE, rng, st);
                        next.densities.push([pf, pn]);
                        continue;
                    }
                    stats.media.scatterings += 1;
                    st.depth += 1;
                    if st.depth >= max_depth {
                        continue;
                    }
                    st.last = (mi.p, Vec3::ZERO);
                    st.direct = !medium.sample_emitters;
                    if is_spectral {
                        pf.scale(1.0 - null, s.sigma_s, mode);
                    } else {
                        pf.update(s.sigma_t, s.sigma_s, mode);
                    }
                    let phase = &medium.phase;
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
                                let f = Rgb::splat(phase.eval(mi.p, wo, ls.dir));
                                let (le, p_nee, delta) = emitted(&ls, pmf);
                                let (mut nee, mut uni) = (pf, pf);
                                nee.scale(p_nee, Rgb::ONE, mode);
                                nee.scale(1.0, f, mode);
                                uni.scale(if delta { 0.0 } else { f.r }, f, mode);
                                push_shadow(
                                    shadows,
                                    Ray::new(mi.p, ls.target - mi.p, ray.time),
                                    (slot, le, [nee, uni]),
                                    (st.medium, rng.derive(streams::tracking(st.step)), mode),
                                );
                            }
                        }
                    }
                    // The densities by next-event estimation start here.
                    pn = pf;
                    // The phase function's direction.
                    let Some(ps) = phase.sample(mi.p, wo, u.point(DIRECTION)) else {
                        continue;
                    };
                    stats.media.scattered += 1;
                    let f = Rgb::splat(ps.weight * ps.pdf);
                    pf.scale(ps.pdf, f, mode);
                    pn.scale(1.0, f, mode);
                    next.push(Ray::new(mi.p, ps.wi, ray.time), slot, Rgb::ONE, rng, st);
                    next.densities.push([pf, pn]);
                    continue;
                }
            }
            // The surface met, or what lies beyond everything.
            let seen = !(settings.hide_emitters && st.depth == 0);
            let whole = st.depth == 0 || st.direct;
            let (from, from_n) = st.last;
            // Emission met, weighed against next-event estimation from the
            // last scattering (density `nee`) unless that could not have
            // drawn it; nothing where it would have drawn it without a
            // density (the thesis's area lights).
            let mut add = |le: Rgb, pmf: f32, density: &dyn Fn() -> f32| {
                if whole {
                    *acc += pf.weight(None, mode) * le;
                    return;
                }
                let nee = if pmf > 0.0 { pmf * density() } else { 0.0 };
                if pmf > 0.0 && nee <= 0.0 {
                    return;
                }
                let mut n = pn;
                n.scale(nee, Rgb::ONE, mode);
                *acc += pf.weight(Some(&n), mode) * le;
            };
            let Some(hit) = hit else {
                if seen {
                    for &e in scene.far.iter() {
                        let emitter = &scene.emitters[e as usize];
                        let le = emitter.eval_miss(ray.dir);
                        if le != Rgb::ZERO {
                            let pmf = if whole {
                                0.0
                            } else {
                                chooser.pmf(from, from_n, e)
                            };
                            add(le, pmf, &|| emitter.pdf_direction(ray.dir));
                        }
                    }
                }
                continue;
            };
            if let (Some(e), true) = (hit.emitter, seen) {
                let emitter = &scene.emitters[e as usize];
                let le = emitter.eval(hit.ng, hit.uv, ray.dir);
                if le != Rgb::ZERO {
                    let pmf = if whole {
                        0.0
                    } else {
                        chooser.pmf(from, from_n, e)
                    };
                    add(le, pmf, &|| {
                        emitter.pdf(Reference::new(from, ray.time), hit.p, hit.ng)
                    });
                }
            }
            let bsdf = &scene.bsdfs[hit.material as usize];
            let at = ShadingPoint::new(&ray, hit.p, hit.ng);
            let media = scene.object_media.get(hit.object as usize);
            // Next-event estimation on the smooth lobes.
            let smooth = materials[hit.material as usize].smooth;
            let pick = u.value(EMITTER_CHOICE);
            let point = u.point(EMITTER_POINT);
            if smooth && lights > 0 && st.depth + 1 < max_depth {
                if let Some((k, pmf)) = chooser.sample(hit.p, hit.n, pick) {
                    let emitter = &scene.emitters[k as usize];
                    let p = SetPoint::uniform(point).native();
                    let r = Reference::new(hit.p, ray.time);
                    if let Some(ls) = sample_emitter(emitter, r, (p, Distribution::Jitter), *escape)
                    {
                        let f = bsdf.eval(&hit, wo, ls.dir) * hit.n.dot(ls.dir).abs();
                        if f.max_element() > 0.0 {
                            let (le, p_nee, delta) = emitted(&ls, pmf);
                            let pdf = if delta {
                                0.0
                            } else {
                                bsdf.pdf(&hit, wo, ls.dir)
                            };
                            let (mut nee, mut uni) = (pf, pf);
                            nee.scale(p_nee, Rgb::ONE, mode);
                            nee.scale(1.0, f, mode);
                            uni.scale(pdf, f, mode);
                            let origin = at.origin(ls.dir);
                            push_shadow(
                                shadows,
                                at.spawn_ray_to(origin, ls.target),
                                (slot, le, [nee, uni]),
                                (
                                    target_medium(media, hit.ng, ls.dir, st.medium),
                                    rng.derive(streams::tracking(st.step)),
                                    mode,
                                ),
                            );
                        }
                    }
                }
            }
            // The BSDF's direction.
            let Some(s) = bsdf_direction(bsdf, &hit, wo, &mut u) else {
                continue;
            };
            if s.pdf <= 0.0 || s.pdf.is_nan() {
                continue;
            }
            st.eta *= s.eta;
            let f = s.weight * s.pdf;
            if !s.flags.contains(BsdfFlags::NULL) {
                st.depth += 1;
                st.last = (hit.p, hit.n);
                if s.flags.is_delta() {
                    st.direct = true;
                } else if s.flags.is_smooth() {
                    st.direct = false;
                }
                super::vertex::count_bounce(stats, s.flags);
                pn = pf;
                pn.scale(1.0, f, mode);
            }
            pf.scale(s.pdf, f, mode);
            st.medium = target_medium(media, hit.ng, s.wi, st.medium);
            next.push(at.spawn_ray(s.wi), slot, Rgb::ONE, rng, st);
            next.densities.push([pf, pn]);
        }
    }

    /// Traces every shadow ray of the step through the surfaces that let
    /// light through and the media it crosses, adding what arrives to its
    /// sample, weighed by the densities of its path.
    pub(super) fn volume_mis_occlude(&mut self, spectral: bool) {
        let scene = self.scene;
        let sh = &self.volume.shadows;
        if sh.ray.is_empty() {
            return;
        }
        self.stats.shadow += sh.ray.len() as u64;
        self.batches.occlusion.add(sh.ray.len());
        for k in 0..sh.ray.len() {
            let mut rng = sh.rng[k];
            let mode = Mode {
                spectral,
                channel: usize::from(sh.channel[k]),
            };
            let [nee, uni] = sh.densities[k];
            if let Some((nee, uni)) =
                shadow_densities(scene, (sh.ray[k], sh.medium[k]), &mut rng, mode, (nee, uni))
            {
                let v = nee.weight(Some(&uni), mode) * sh.value[k];
                if v.max_element() > 0.0 {
                    self.radiance[sh.slot[k] as usize] += v;
                }
            }
        }
    }
}

/// Queues a shadow ray: `ray` from its origin to its target, its sample,
/// the radiance it brings and its densities (by next-event estimation,
/// by the path's own sampling), the medium it starts in, the stream its
/// tracking reads and the path's channel.
fn push_shadow(
    shadows: &mut VolShadows,
    ray: Ray,
    (slot, value, densities): (u32, Rgb, [Densities; 2]),
    (medium, rng, mode): (u32, Rng, Mode),
) {
    if value.max_element() <= 0.0 {
        return;
    }
    shadows.push(ray, (slot, value), (medium, rng), NO_SET);
    shadows.densities.push(densities);
    shadows.channel.push(mode.channel as u8);
}

/// The densities `(nee, uni)` of a shadow path along the segment `ray`
/// (from its origin to `origin + dir`, short of the end by
/// [`SHADOW_END`]), starting in `medium`, multiplied by every event on
/// the way: in a medium, ratio tracking's tentative collisions drawn by
/// the path's channel (each stretch by its free-flight density, each
/// collision passed by next-event estimation without a choice and by the
/// path's own sampling with the probability of a null collision); each
/// surface crossed by what it lets through (0 for an opaque one). `None`
/// where no density is left (blocked).
fn shadow_densities(
    scene: &Scene,
    (ray, mut medium): (Ray, u32),
    rng: &mut Rng,
    mode: Mode,
    (mut nee, mut uni): (Densities, Densities),
) -> Option<(Densities, Densities)> {
    let target = ray.origin + ray.dir;
    let mut origin = ray.origin;
    for _ in 0..MAX_CROSSINGS {
        let to = target - origin;
        let length = to.length();
        if length.is_nan() || length <= 0.0 {
            return Some((nee, uni));
        }
        let dir = to / length;
        let end = length * SHADOW_END;
        let r = Ray::new(origin, dir, ray.time);
        let hit = scene.world.intersect(&r, 0.0, end);
        let t = hit.map_or(end, |h| h.t);
        if medium != NO_MEDIUM {
            let m = &scene.media[medium as usize];
            track(m, (origin, dir), t, rng, mode, (&mut nee, &mut uni))?;
        }
        let Some(h) = hit else {
            return Some((nee, uni));
        };
        let object = &scene.world.objects[h.object as usize];
        if object.casts_shadows {
            let f = scene.bsdfs[h.material as usize].null_transmission(&h, dir);
            nee.scale(1.0, f, mode);
            uni.scale(1.0, f, mode);
            if !(uni.alive(mode) || nee.alive(mode)) {
                return None;
            }
        }
        medium = target_medium(scene.object_media.get(h.object as usize), h.ng, dir, medium);
        origin = ShadingPoint::new(&r, h.p, h.ng).origin(dir);
    }
    None
}

/// Ratio tracking of a shadow path in medium `m` along `(o, d)` over
/// `[0, tmax]` (see [`shadow_densities`]); `None` where no density is left.
fn track(
    m: &Medium,
    (o, d): (Vec3, Vec3),
    tmax: f32,
    rng: &mut Rng,
    mode: Mode,
    (nee, uni): (&mut Densities, &mut Densities),
) -> Option<()> {
    let spectral = m.has_spectral_extinction();
    let mut from = 0.0f32;
    for _ in 0..MAX_COLLISIONS {
        let left = tmax - from;
        let mi = m.sample_interaction((o + d * from, d), left, rng.next_f32(), mode.channel);
        if spectral {
            let (tr, pdf) = free_flight(&mi, left);
            nee.update(pdf, tr, mode);
            uni.update(pdf, tr, mode);
        }
        if !mi.is_valid() {
            return Some(());
        }
        from += mi.t;
        let s = mi.sigma;
        if spectral {
            nee.scale(1.0, s.sigma_n, mode);
            uni.scale(mean(ratio(s.sigma_n, mi.majorant)), s.sigma_n, mode);
        } else {
            nee.scale(1.0, ratio(s.sigma_n, mi.majorant), mode);
            uni.update(s.sigma_n, s.sigma_n, mode);
        }
        if !(uni.alive(mode) || nee.alive(mode)) {
            return None;
        }
    }
    None
}
