use glam::Vec3A;

use crate::accel::{Hit, Hits, PacketScratch, ShaftSet};
use crate::bsdf::{Bsdf, BsdfFlags, Lobes, MAX_LOBES};
use crate::emitter::{Emitter, LightSample, Reference};
use crate::integrator::clip::clip_camera_hits;
use crate::integrator::transmittance::transmittance;
use crate::math::Rgb;
use crate::math::{Aabb, Ray, Vec3};
use crate::sampling::{BranchKey, Distribution, EffectSpec, PointTable, Rng, SetPoint};
use crate::scene::Scene;

use super::config::Whitted;
use crate::integrator::metric::{Metric, RunningMean, ShadowTally};
use crate::integrator::shading::ShadingPoint;
use crate::integrator::stats::RayStats;
use crate::integrator::stopping::sets::{SetRule, SetTally};
use crate::integrator::streams;

/// Shadow rays stop this fraction short of their target, so that the surface
/// they aim at (or a surface touching it) does not count as a blocker.
const SHADOW_END: f32 = 1.0 - 1e-4;

/// Shadow sets of at least this many rays are traced through their shaft
/// (see [`crate::accel::Shaft`]). Building and gathering a shaft costs a few
/// rays' worth of work; on the bunny scene (instruction counts) it saved 16%
/// of a 64-ray render, 4% at 16 rays, and cost 28% at 4.
const SHAFT_MIN_RAYS: u32 = 16;

/// A shaft reaching more BVH leaves than this is not used: past it, testing
/// every ray against every leaf costs more than traversing the tree (16 and
/// 32 measured alike; 64 and more were slower).
const SHAFT_MAX_LEAVES: usize = 16;

/// One worker's tracer: reads the scene, counts its own rays, and keeps
/// pools of buffers so that tracing allocates nothing once warm.
pub struct Tracer<'a> {
    scene: &'a Scene,
    pub stats: RayStats,
    /// The integrator's settings this tracer reads.
    max_depth: u32,
    metric: Option<Metric>,
    /// The `custom` distribution's point sets.
    points: &'a PointTable,
    /// The sets of delta lobes that set none of their own.
    reflection: EffectSpec,
    refraction: EffectSpec,
    /// Point buffers of distribution sets.
    pool: Vec<Vec<Vec3>>,
    /// The buffers of each batch being traced (one per recursion level).
    levels: Vec<Level>,
    /// Ray and radiance buffers of the sets being traced.
    sets: Vec<(Vec<Ray>, Vec<Rgb>)>,
    /// What the current shadow set's shaft may cross.
    shaft: ShaftSet,
    packet: PacketScratch,
    light_samples: Vec<Option<LightSample>>,
    /// The lobes of each of the scene's BSDFs, and whether direct light is
    /// evaluated on them (a smooth lobe) and rays traced (a delta lobe).
    lobes: Vec<(Lobes, bool, bool)>,
    /// The set each of a material's lobes asks for, by material and slot
    /// (the integrator's [`RaySets::lobes`](crate::integrator::RaySets::lobes)).
    lobe_sets: &'a [[Option<EffectSpec>; MAX_LOBES]],
    /// The emitters direct light comes from (all but those at infinity,
    /// which rays that hit nothing see), by index in the scene.
    sampled: Vec<u32>,
    /// The branch of emitter `j`'s shadow sets (`streams::shadow`), hashed once,
    /// for each of `sampled`.
    shadow_keys: Vec<BranchKey>,
    /// The shadow set toward each of `sampled` (from
    /// [`RaySets::shadow`](crate::integrator::RaySets::shadow)).
    shadow_sets: Vec<EffectSpec>,
    /// The calibrated rule on sets, if on (see [`SetRule`]).
    set_rule: Option<SetRule>,
    /// Replica sums of the sets being traced, one per nesting level.
    tallies: Vec<SetTally>,
}

/// What tracing a batch of rays keeps between its steps (see
/// [`Tracer::radiance`]).
#[derive(Default)]
struct Level {
    /// The rays' hits, compact, then as records.
    found: Hits,
    hits: Vec<Option<Hit>>,
    /// The hits that receive direct light.
    lit: Vec<Lit>,
    /// The shadow sets of all lit hits toward one light, one after another
    /// (each as many rays as the light's sets have).
    rays: Vec<Option<ShadowRay>>,
    /// Direct light at lit hit `k` from light `j`, at `j * lit.len() + k`.
    direct: Vec<Rgb>,
}

/// A hit that receives direct light.
struct Lit {
    /// Its ray's index in the batch.
    ray: usize,
    material: u32,
    frame: Local,
    /// Where its shadow rays start: every ray of a set leaves on the side
    /// the geometric normal points to (others are not traced), so all start
    /// at the same offset point.
    origin: Vec3,
}

/// The local frame of a hit, oriented toward the viewer.
struct Local {
    /// Where its rays leave from, its geometric normal on the viewer's side.
    at: ShadingPoint,
    wo: Vec3,
    /// Shading normal on the viewer's side.
    n: Vec3,
}

impl Local {
    /// The frame of `hit`, seen along `ray`: normals flipped to the viewer's side.
    fn new(ray: &Ray, hit: &Hit) -> Local {
        let wo = -ray.dir.normalize();
        let front = hit.ng.dot(wo) >= 0.0;
        let flip = if front { 1.0 } else { -1.0 };
        Local {
            at: ShadingPoint::new(ray, hit.p, hit.ng * flip),
            wo,
            n: hit.n * flip,
        }
    }
}

impl<'a> Tracer<'a> {
    /// True if the pixel metric is on: a pixel's film points are traced
    /// in their shuffled order, since it may stop after any of them.
    pub(super) fn ordered(&self) -> bool {
        self.metric.is_some_and(|m| m.pixels)
    }

    pub fn new(scene: &'a Scene, config: &'a Whitted) -> Self {
        let s = &scene.settings;
        Tracer {
            max_depth: config.max_depth,
            metric: config.metric,
            points: &s.points,
            reflection: s.reflection,
            refraction: s.refraction,
            scene,
            stats: RayStats::default(),
            pool: Vec::new(),
            levels: Vec::new(),
            sets: Vec::new(),
            shaft: ShaftSet::default(),
            packet: PacketScratch::default(),
            light_samples: Vec::new(),
            lobes: scene
                .bsdfs
                .iter()
                .map(|b| {
                    let l = b.lobes();
                    (l, l.any_smooth(), l.any_delta())
                })
                .collect(),
            lobe_sets: &config.sets.lobes,
            sampled: (0..scene.emitters.len() as u32)
                .filter(|&j| !scene.emitters[j as usize].is_infinite())
                .collect(),
            shadow_sets: (0..scene.emitters.len())
                .filter(|&j| !scene.emitters[j].is_infinite())
                .map(|j| config.sets.shadow[j])
                .collect(),
            shadow_keys: (0..scene.emitters.len() as u64)
                .filter(|&j| !scene.emitters[j as usize].is_infinite())
                .map(|j| BranchKey::new(streams::shadow(j)))
                .collect(),
            set_rule: SetRule::new(config.stopping),
            tallies: Vec::new(),
        }
    }

    /// Radiance arriving along each of `rays`, appended to `out` in order;
    /// `depth` counts the reflection and refraction levels so far and
    /// `rng(i)` is ray `i`'s stream. The one way rays are traced, from a
    /// pixel's camera rays to a set of one mirror ray:
    ///
    /// 1. the hits of all rays are found together (see
    ///    [`World::intersect_all`](crate::accel::World::intersect_all));
    /// 2. the direct light of every lit hit, light by light, so that sets of
    ///    few shadow rays (one per camera ray, say) can share one shaft, as a
    ///    set of many rays does (see `direct_light`);
    /// 3. each hit is shaded (`shade`), its reflection and
    ///    refraction sets traced as batches a level deeper.
    ///
    /// A ray's radiance does not depend on the batch it is traced in (but
    /// for the rare tie noted at `intersect_all`).
    pub fn radiance(
        &mut self,
        rays: &[Ray],
        depth: u32,
        rng: impl Fn(usize) -> Rng,
        out: &mut Vec<Rgb>,
    ) {
        let scene = self.scene;
        let mut level = self.levels.pop().unwrap_or_default();
        let world = &scene.world;
        if depth == 0 && scene.camera.clips() {
            world.intersect_all(rays, 0.0, &mut self.packet, &mut level.found);
            clip_camera_hits(scene, rays, &mut level.found);
            world.surfaces(rays, &level.found, &mut level.hits);
        } else {
            // Every hit is shaded: each record made as it is found.
            world.intersect_all_records(rays, 0.0, &mut self.packet, &mut level.hits);
        }
        level.lit.clear();
        for (i, (ray, hit)) in rays.iter().zip(&level.hits).enumerate() {
            let Some(hit) = hit else { continue };
            if self.lobes[hit.material as usize].1 {
                let frame = Local::new(ray, hit);
                let origin = frame.at.origin(frame.at.ng);
                level.lit.push(Lit {
                    ray: i,
                    material: hit.material,
                    frame,
                    origin,
                });
            }
        }
        level.direct.clear();
        if !level.lit.is_empty() {
            for j in 0..self.sampled.len() {
                let (key, light) = (self.shadow_keys[j], self.sampled[j]);
                let light = (&scene.emitters[light as usize], self.shadow_sets[j]);
                self.direct_light(light, |i| rng(i).derive_key(key), &mut level);
            }
        }
        let Level {
            hits, lit, direct, ..
        } = &level;
        let mut k = 0;
        for (i, ray) in rays.iter().enumerate() {
            let Some(hit) = &hits[i] else {
                out.push(self.miss(ray));
                continue;
            };
            // A lit hit's frame and direct light were found above.
            let found = match lit.get(k) {
                Some(h) if h.ray == i => {
                    k += 1;
                    Some((&h.frame, k - 1))
                }
                _ => None,
            };
            let direct = |j: usize| match found {
                Some((_, k)) => direct[j * lit.len() + k],
                None => Rgb::ZERO,
            };
            let frame = found.map(|(s, _)| s);
            out.push(self.shade(ray, hit, frame, depth, rng(i), direct));
        }
        self.levels.push(level);
    }

    /// The mean radiance along a set of `n` rays, ray `k` being `ray(k)`,
    /// traced at `depth` (`rng(k)`: ray `k`'s stream) and stopped early by
    /// `metric` (see [`RunningMean`]), and how many rays were traced.
    /// Without a metric the set is one batch; with one, a batch of the rays
    /// the metric must see before it may stop, then batches of one, so that
    /// no ray is made or traced past the stop. With a set `rule` (whose
    /// replicas the rays must be), the batches are its passes, and the set
    /// stops after one when the rule judges it converged. `value(k, l)`
    /// gives what ray `k`'s radiance `l` adds to the mean.
    #[allow(clippy::too_many_arguments)]
    pub fn mean(
        &mut self,
        n: usize,
        ray: impl Fn(usize) -> Ray,
        depth: u32,
        rng: impl Fn(usize) -> Rng,
        metric: Option<&Metric>,
        rule: Option<SetRule>,
        value: impl FnMut(usize, Rgb) -> Rgb,
    ) -> (Rgb, usize) {
        let set = Continued {
            n,
            rays: 0..n,
            mean: RunningMean::default(),
        };
        let (mean, end, _) = self.continue_mean(set, ray, depth, rng, metric, rule, value);
        (mean.mean(), end)
    }

    /// [`mean`](Self::mean) for rays `set.rays` of a set of `set.n` whose
    /// earlier rays gave `set.mean`: the running mean after them, the index
    /// after the last ray traced, and whether the metric or the rule
    /// stopped the set. Continuing a set over `[a, b)` then `[b, c)` traces
    /// the rays, and stops where, continuing it over `[a, c)` does.
    #[allow(clippy::too_many_arguments)]
    pub fn continue_mean(
        &mut self,
        set: Continued,
        ray: impl Fn(usize) -> Ray,
        depth: u32,
        rng: impl Fn(usize) -> Rng,
        metric: Option<&Metric>,
        rule: Option<SetRule>,
        mut value: impl FnMut(usize, Rgb) -> Rgb,
    ) -> (RunningMean, usize, bool) {
        let Continued {
            n,
            rays: range,
            mut mean,
        } = set;
        let first = metric.map_or(n, |m| (m.min_rays.max(2) as usize).min(n));
        let (mut rays, mut values) = self.sets.pop().unwrap_or_default();
        let mut tally = rule.map(|r| {
            let mut t = self.tallies.pop().unwrap_or_default();
            t.reset(&r);
            (r, t)
        });
        let mut start = range.start;
        let mut stopped = false;
        'set: while start < range.end {
            let end = match (&tally, metric) {
                (Some((r, _)), _) => r.pass_end(start, n),
                (None, Some(_)) if start >= first => start + 1,
                _ => first,
            }
            .min(range.end);
            rays.clear();
            rays.extend((start..end).map(&ray));
            values.clear();
            self.radiance(&rays, depth, |k| rng(start + k), &mut values);
            for (k, &l) in (start..end).zip(values.iter()) {
                let l = value(k, l);
                if let Some((_, t)) = &mut tally {
                    t.push(k, l);
                }
                if mean.push(l, metric, n as u32) {
                    // The batch was traced whole when it is a rule's pass.
                    start = if tally.is_some() { end } else { k + 1 };
                    stopped = true;
                    break 'set;
                }
            }
            start = end;
            if tally.as_ref().is_some_and(|(r, t)| t.converged(r)) {
                stopped = start < n;
                break;
            }
        }
        self.sets.push((rays, values));
        if let Some((_, t)) = tally {
            self.tallies.push(t);
        }
        (mean, start, stopped)
    }

    /// Direct light from `light` (an emitter and its shadow set) at every
    /// lit hit of `level`, appended to `level.direct`: for each, the
    /// average over its shadow set (see [`trace_set`](Self::trace_set)).
    /// The rays of a set large enough are traced within its own shaft; sets
    /// too small for one share the batch's if all of them together are
    /// large enough.
    fn direct_light(
        &mut self,
        light: (&Emitter, EffectSpec),
        rng: impl Fn(usize) -> Rng,
        level: &mut Level,
    ) {
        let Level {
            hits,
            lit,
            rays,
            direct,
            ..
        } = level;
        rays.clear();
        self.shadow_rays(lit, light, &rng, rays);
        let n = light.1.rays as usize;
        let own = n >= SHAFT_MIN_RAYS as usize;
        let shared = !own
            && rays.iter().flatten().count() >= SHAFT_MIN_RAYS as usize
            && self.gather_shaft(rays);
        let scene = self.scene;
        for (h, set) in lit.iter().zip(rays.chunks_exact(n)) {
            let Some(si) = &hits[h.ray] else { continue };
            let bsdf = &scene.bsdfs[h.material as usize];
            let shaft = shared || (own && self.gather_shaft(set));
            direct.push(self.trace_set(&h.frame, si, bsdf, set, shaft));
        }
    }

    /// The radiance of rays that hit nothing: what the emitters at infinity
    /// send along them.
    fn miss(&self, ray: &Ray) -> Rgb {
        let eval = |j: &u32| self.scene.emitters[*j as usize].eval_miss(ray.dir);
        match self.scene.far.split_first() {
            None => Rgb::ZERO,
            Some((first, rest)) => rest.iter().fold(eval(first), |l, j| l + eval(j)),
        }
    }

    /// The radiance leaving `hit` along `ray`: the emitted radiance of its
    /// emitter, if it has one; then, if its BSDF has a smooth lobe, the
    /// direct light `direct(j)` of each emitter sampled, and if it has delta
    /// lobes, the light of their sets (see [`indirect`](Self::indirect)),
    /// summed in this order. `frame` is the hit's frame if the caller has it.
    #[inline]
    fn shade(
        &mut self,
        ray: &Ray,
        hit: &Hit,
        frame: Option<&Local>,
        depth: u32,
        rng: Rng,
        direct: impl Fn(usize) -> Rgb,
    ) -> Rgb {
        let emitted = |e: u32| self.scene.emitters[e as usize].eval(hit.ng, hit.uv, ray.dir);
        let mut l = hit.emitter.map_or(Rgb::ZERO, emitted);
        let (_, lit, scatters) = self.lobes[hit.material as usize];
        if !lit && !scatters {
            return l;
        }
        let fresh;
        let s = match frame {
            Some(s) => s,
            None => {
                fresh = Local::new(ray, hit);
                &fresh
            }
        };
        if lit {
            for j in 0..self.sampled.len() {
                l += direct(j);
            }
        }
        if scatters {
            // By value, not through a reference: `l` stays in registers
            // (a sum kept in memory is stored and reloaded in parts, and
            // each reload waits for the stores).
            l = self.indirect(s, hit, depth, rng, l);
        }
        l
    }

    /// `l` plus the light of each delta lobe of the hit's BSDF, added lobe
    /// by lobe in slot order: the mean radiance of the lobe's set times the
    /// lobe's weight.
    fn indirect(&mut self, s: &Local, hit: &Hit, depth: u32, rng: Rng, mut l: Rgb) -> Rgb {
        if depth >= self.max_depth {
            return l;
        }
        let (lobes, ..) = self.lobes[hit.material as usize];
        let sets = &self.lobe_sets[hit.material as usize];
        let bsdf = &self.scene.bsdfs[hit.material as usize];
        for (k, flags) in lobes.iter() {
            if !flags.is_delta() {
                continue;
            }
            let spec = sets[k].unwrap_or_else(|| self.default_set(flags));
            // A delta lobe weighs every ray of its set alike: its weight at
            // the perfect direction. `None`: the lobe sends nothing here
            // (total internal reflection, say).
            let zero = SetPoint::new(Vec3::ZERO, spec.distribution);
            let Some(perfect) = bsdf.sample(hit, s.wo, Some(k), zero) else {
                continue;
            };
            let mean = self.lobe_set(s, hit, bsdf, (k, flags, spec), perfect.wi, depth, rng);
            l += perfect.weight * mean;
        }
        l
    }

    /// The set a delta lobe without a budget of its own traces: the render's
    /// reflection or refraction rays and distribution.
    fn default_set(&self, flags: BsdfFlags) -> EffectSpec {
        if flags.contains(BsdfFlags::TRANSMISSION) {
            self.refraction
        } else {
            self.reflection
        }
    }

    /// The average over a prepared shadow set of `brdf · weight · cos θ ·
    /// transmittance`, its rays traced one by one, within the shaft last
    /// gathered if `shaft`, and stopped early by the shadow metric.
    fn trace_set(
        &mut self,
        s: &Local,
        si: &Hit,
        bsdf: &Bsdf,
        set: &[Option<ShadowRay>],
        shaft: bool,
    ) -> Rgb {
        let world = &self.scene.world;
        let clear = shaft && world.shaft_is_clear(&self.shaft);
        if let [one] = set {
            // No metric acts on one ray, and the average of one is its value
            // (`0 + x` as the loop sums, so even a -0 comes out alike).
            let term = one
                .as_ref()
                .and_then(|r| self.shadow_term(s, si, bsdf, r, shaft, clear));
            return Rgb::ZERO + term.unwrap_or(Rgb::ZERO);
        }
        let n = set.len() as u32;
        let mut shadow_metric = ShadowTally::of(self.metric, n).unwrap_or(ShadowTally::unjudged(n));
        let rule = SetRule::for_set(self.set_rule, set.len());
        let mut tally = rule.map(|r| {
            let mut t = self.tallies.pop().unwrap_or_default();
            t.reset(&r);
            (r, t, r.pass_end(0, set.len()))
        });
        let (mut sum, mut done) = (Rgb::ZERO, 0u32);
        for r in set {
            done += 1;
            let mut term = Rgb::ZERO;
            if let Some(r) = r {
                let t = self.shadow_term(s, si, bsdf, r, shaft, clear);
                if let Some(t) = t {
                    term = t;
                    sum += t;
                }
                shadow_metric.count(t.is_some());
            }
            // The calibrated rule, at the end of each of its passes.
            if let Some((rule, t, end)) = &mut tally {
                t.push(done as usize - 1, term);
                if done as usize == *end {
                    if t.converged(rule) {
                        self.stats.saved.shadow += u64::from(n - done);
                        break;
                    }
                    *end = rule.pass_end(*end, set.len());
                }
            }
            // The shadow metric: after k rays, all reached or all blocked.
            if done == shadow_metric.k && shadow_metric.stops() {
                self.stats.saved.shadow += u64::from(n - done);
                break;
            }
        }
        if let Some((_, t, _)) = tally {
            self.tallies.push(t);
        }
        sum / done.max(1) as f32
    }

    /// Traces one shadow ray (within the shaft last gathered if `shaft`; not
    /// at all if that shaft is `clear`): `brdf · weight · cos θ ·
    /// transmittance`, or `None` if it is blocked.
    #[inline(always)]
    fn shadow_term(
        &mut self,
        s: &Local,
        si: &Hit,
        bsdf: &Bsdf,
        r: &ShadowRay,
        shaft: bool,
        clear: bool,
    ) -> Option<Rgb> {
        self.stats.shadow += 1;
        let t = if clear {
            1.0
        } else {
            let (world, transparency) = (&self.scene.world, &self.scene.transparency);
            let within = shaft.then_some(&self.shaft);
            // A material whose transparency varies is read where it is crossed.
            let bsdfs = &self.scene.bsdfs;
            let at = |h: &Hit| bsdfs[h.material as usize].shadow_transmittance(h);
            transmittance(world, &r.ray, (0.0, SHADOW_END), transparency, within, &at)?
        };
        Some(bsdf.eval(si, s.wo, r.wi) * r.weight * (r.cos * t))
    }

    /// Appends to `set` the shadow sets toward `light` (an emitter and its
    /// shadow set) of the `lit` hits, one after another (`None` for points
    /// that give no ray): hit `h`'s distribution points drawn from
    /// `rng(h.ray)`.
    fn shadow_rays(
        &mut self,
        lit: &[Lit],
        (light, spec): (&Emitter, EffectSpec),
        rng: &impl Fn(usize) -> Rng,
        set: &mut Vec<Option<ShadowRay>>,
    ) {
        let (n, d) = (spec.rays as usize, spec.distribution);
        let mut points = self.pool.pop().unwrap_or_default();
        points.clear();
        if n == 1 {
            // A point light, or a Whitted shadow ray: no set buffer needed.
            let table = self.points;
            points.extend(lit.iter().map(|h| d.one_in(table, 1.0, &mut rng(h.ray))));
        } else {
            let mut one = self.pool.pop().unwrap_or_default();
            for h in lit {
                self.set_points(spec, &mut rng(h.ray), &mut one);
                points.extend_from_slice(&one);
            }
            self.pool.push(one);
        }
        let samples = &mut self.light_samples;
        samples.clear();
        let at = |k: usize| Reference::new(lit[k / n].frame.at.p, lit[k / n].frame.at.time);
        light.sample(at, &points, d, samples);
        for (h, samples) in lit.iter().zip(samples.chunks_exact(n)) {
            let ray = |ls: &Option<LightSample>| shadow_ray(&h.frame, h.origin, ls.as_ref()?);
            set.extend(samples.iter().map(ray));
        }
        self.pool.push(points);
    }

    /// The distribution points of a shadow set of `spec`, into `points`.
    fn set_points(&mut self, spec: EffectSpec, rng: &mut Rng, points: &mut Vec<Vec3>) {
        let (n, d) = (spec.rays as usize, spec.distribution);
        if let Some(rule) = SetRule::for_set(self.set_rule, n) {
            let mut scratch = self.pool.pop().unwrap_or_default();
            rule.points((d, self.points), n, rng, &mut scratch, points);
            self.pool.push(scratch);
            return;
        }
        // The rays are summed: their order matters only to the shadow
        // metric, which may stop the set early.
        if self.metric.is_some_and(|m| m.shadows) {
            d.generate_in(self.points, n, 1.0, rng, points);
        } else {
            d.generate_unordered_in(self.points, n, 1.0, rng, points);
        }
    }

    /// Gathers the static-triangle leaves of the shaft holding every ray of
    /// the set; false if the shaft reaches too many to be worth it.
    fn gather_shaft(&mut self, set: &[Option<ShadowRay>]) -> bool {
        // Four-wide min and max (glam's `Vec3A`): the same values as
        // `Aabb::grow`, without a compare and select per coordinate.
        let (mut lo, mut hi) = (Vec3A::INFINITY, Vec3A::NEG_INFINITY);
        let (mut o_lo, mut o_hi) = (lo, hi);
        for r in set.iter().flatten() {
            let (o, t) = (Vec3A::from(r.ray.origin), Vec3A::from(r.ray.at(1.0)));
            (o_lo, o_hi) = (o_lo.min(o), o_hi.max(o));
            (lo, hi) = (lo.min(t), hi.max(t));
        }
        let aabb = |lo: Vec3A, hi: Vec3A| Aabb {
            min: lo.into(),
            max: hi.into(),
        };
        let (origins, targets) = (aabb(o_lo, o_hi), aabb(lo, hi));
        let world = &self.scene.world;
        world.gather_shaft(origins, targets, SHAFT_MAX_LEAVES, &mut self.shaft)
    }

    /// Traces the set of lobe `k` (of `flags`, with budget `spec`) of
    /// `bsdf` at the hit, and averages it (see [`mean`](Self::mean)): a
    /// blurred (glossy) delta lobe's set has the budget's rays, each the
    /// lobe's sample for one point of the set; a sharp one is the single ray
    /// `perfect`.
    #[allow(clippy::too_many_arguments)]
    fn lobe_set(
        &mut self,
        s: &Local,
        hit: &Hit,
        bsdf: &Bsdf,
        (k, flags, spec): (usize, BsdfFlags, EffectSpec),
        perfect: Vec3,
        depth: u32,
        rng: Rng,
    ) -> Rgb {
        let blurred = flags.contains(BsdfFlags::GLOSSY);
        let (n, d) = (if blurred { spec.rays } else { 1 }, spec.distribution);
        let (set_tag, ray_tag) = streams::lobe(k);
        let rule = SetRule::for_set(self.set_rule, n as usize);
        let points = self.points(d, n, rule, rng.derive(set_tag));
        let transmit = flags.contains(BsdfFlags::TRANSMISSION);
        // The set's directions at once: what the points share is found once.
        let mut dirs = self.pool.pop().unwrap_or_default();
        if blurred {
            bsdf.sample_set(hit, s.wo, k, (&points, d), perfect, &mut dirs);
        } else {
            dirs.clear();
            dirs.resize(points.len(), perfect);
        }
        let ray = |j: usize| s.at.spawn_ray(dirs[j]);
        let children = rng.derive(ray_tag);
        let metric = self.metric.filter(|m| m.reflections);
        let n = points.len();
        let child = |k: usize| children.child(k, n);
        let (mean, traced) = self.mean(n, ray, depth + 1, child, metric.as_ref(), rule, |_, l| l);
        let (traced, saved) = (traced as u64, (n - traced) as u64);
        if transmit {
            self.stats.refraction += traced;
            self.stats.saved.refraction += saved;
        } else {
            self.stats.reflection += traced;
            self.stats.saved.reflection += saved;
        }
        self.pool.push(points);
        self.pool.push(dirs);
        mean
    }

    /// The points of a distribution set, in trace order (as `rule`'s
    /// replicas if it has one), from the buffer pool.
    fn points(
        &mut self,
        d: Distribution,
        n: u32,
        rule: Option<SetRule>,
        mut rng: Rng,
    ) -> Vec<Vec3> {
        let mut buf = self.pool.pop().unwrap_or_default();
        let table = self.points;
        match rule {
            Some(r) => {
                let mut scratch = self.pool.pop().unwrap_or_default();
                r.points((d, table), n as usize, &rng, &mut scratch, &mut buf);
                self.pool.push(scratch);
            }
            None => d.generate_in(table, n as usize, 1.0, &mut rng, &mut buf),
        }
        buf
    }
}

/// A set of `n` rays continued over `rays`, after earlier ones gave `mean`
/// (see [`Tracer::continue_mean`]).
pub struct Continued {
    pub n: usize,
    pub rays: std::ops::Range<usize>,
    pub mean: RunningMean,
}

/// A shadow ray of a set, prepared before any ray of the set is traced.
#[derive(Clone, Copy)]
struct ShadowRay {
    /// From the offset shading point to the light sample (at parameter 1).
    ray: Ray,
    wi: Vec3,
    cos: f32,
    /// What the light brings along the ray if it is not blocked.
    weight: Rgb,
}

/// The shadow ray from `origin` (the shading point of `s` lifted off its
/// surface) toward the light sample `ls`; `None` if a cosine at the
/// receiver is at most 0 (the sample is below the horizon).
#[inline]
fn shadow_ray(s: &Local, origin: Vec3, ls: &LightSample) -> Option<ShadowRay> {
    let wi = ls.dir;
    let cos = s.n.dot(wi);
    if cos <= 0.0 || s.at.ng.dot(wi) <= 0.0 {
        return None;
    }
    Some(ShadowRay {
        ray: s.at.spawn_ray_to(origin, ls.target),
        wi,
        cos,
        weight: ls.weight,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Shadow rays from the ground near the world's origin, seen from a
    /// camera four units away, reach the light above: the hit points there
    /// are off by an ulp of the camera's coordinates (1e-7, often below the
    /// ground), so an offset scaled by the points' own tiny coordinates would
    /// leave them under the ground, which would then shadow them (a few dark
    /// samples in the bunny scene's ground).
    #[test]
    fn points_near_the_origin_are_not_shadowed_by_their_own_surface() {
        use crate::scene::{LoadOptions, SceneSource};
        let toml = "[[objects]]\ntype = \"quad\"\norigin = [-5.0, 0.0, -5.0]\n\
                    edge_u = [0.0, 0.0, 10.0]\nedge_v = [10.0, 0.0, 0.0]\n";
        let here = std::path::Path::new(".");
        let src = SceneSource::from_toml(toml, here, here, &LoadOptions::default());
        let scene = src
            .and_then(|s| s.build())
            .unwrap_or_else(|e| panic!("{e}"));
        let (world, eye, light) = (
            &scene.world,
            Vec3::new(0.0, 1.3, 4.2),
            Vec3::new(0.0, 4.0, 0.0),
        );
        let (mut r, mut below) = (Rng::new(5), 0);
        for _ in 0..20_000 {
            let aim = Vec3::new(r.range(-1e-3, 1e-3), 0.0, r.range(-1e-3, 1e-3));
            let ray = Ray::new(eye, (aim - eye).normalize(), 0.0);
            let hit = world
                .intersect(&ray, 0.0, f32::INFINITY)
                .expect("the ground");
            below += usize::from(hit.p.y < 0.0);
            let s = Local::new(&ray, &hit);
            let origin = s.at.origin(s.at.ng);
            let shadow = Ray::new(origin, light - origin, 0.0);
            let blocked = world.occluded(&shadow, (0.0, SHADOW_END));
            assert!(!blocked, "from {:?} (hit at {:?})", origin, hit.p);
        }
        // Not vacuous: many hit points are computed below the ground.
        assert!(below > 1_000, "{below} hit points below the ground");
    }

    /// A closed mesh (an octahedron split into 128 triangles) as OBJ text,
    /// centred at `c` with radius `r`.
    fn blob_obj(c: Vec3, r: f32) -> String {
        let mut obj = String::new();
        let (n, mut verts) = (4usize, 0);
        let corners = [Vec3::X, Vec3::Y, Vec3::Z, -Vec3::X, -Vec3::Y, -Vec3::Z];
        let faces = [(0, 1, 2), (1, 3, 2), (3, 4, 2), (4, 0, 2)];
        for (a, b, e) in faces
            .iter()
            .flat_map(|&(a, b, e)| [(a, b, e), (b, a, e + 3)])
        {
            let (a, b, e) = (corners[a], corners[b], corners[e]);
            for i in 0..n {
                for j in 0..n - i {
                    let p = |i: usize, j: usize| {
                        let (u, v) = (i as f32 / n as f32, j as f32 / n as f32);
                        let q = (a * u + b * v + e * (1.0 - u - v)).normalize();
                        c + q * r * (1.0 + 0.2 * (5.0 * q.x).sin())
                    };
                    let mut tri = |x: Vec3, y: Vec3, z: Vec3| {
                        for v in [x, y, z] {
                            obj += &format!("v {} {} {}\n", v.x, v.y, v.z);
                        }
                        obj += &format!("f {} {} {}\n", verts + 1, verts + 2, verts + 3);
                        verts += 3;
                    };
                    tri(p(i, j), p(i + 1, j), p(i, j + 1));
                    if i + j + 1 < n {
                        tri(p(i + 1, j), p(i + 1, j + 1), p(i, j + 1));
                    }
                }
            }
        }
        obj
    }

    /// A batch of 16 rays (direct light of all hits first, sets of one ray
    /// sampled four hits at a time, shared shafts) gives every ray the
    /// radiance and the ray counts that batches of one give, bit for bit:
    /// for one-ray sets on both penumbra models, sets too small for a shaft
    /// of their own, sets with one, a point light, a transparent caster, a
    /// mirror and packets hitting ground, mesh, lights and sky.
    #[test]
    fn radiance_does_not_depend_on_the_batch() {
        use crate::scene::{LoadOptions, SceneSource};
        let dir = tempfile::tempdir().unwrap();
        let obj = dir.path().join("blob.obj");
        std::fs::write(&obj, blob_obj(Vec3::new(0.0, 0.6, 0.0), 0.6)).unwrap();
        let lights = [
            ("surface", 1, "jitter"),
            ("thesis", 1, "grid"),
            ("surface", 1, "random"),
            ("surface", 4, "poisson"),
            ("surface", 16, "semi-jitter"),
        ];
        let mut compared = 0;
        for (k, (model, rays, dist)) in lights.into_iter().enumerate() {
            let toml = format!(
                "[render]\nmax_depth = 2\n\
                 [materials.m]\nalbedo = [0.6, 0.5, 0.4]\nspecular = 0.2\nshininess = 20\n\
                 [materials.mirror]\nreflectivity = 0.8\n\
                 [materials.clear]\ntransparency = 0.5\n\
                 [[objects]]\ntype = \"quad\"\nmaterial = \"m\"\norigin = [-5.0, 0.0, -5.0]\n\
                 edge_u = [0.0, 0.0, 10.0]\nedge_v = [10.0, 0.0, 0.0]\n\
                 [[objects]]\ntype = \"mesh\"\nmaterial = \"m\"\npath = {obj:?}\n\
                 [[objects]]\ntype = \"sphere\"\nmaterial = \"clear\"\ncenter = [1.2, 0.5, 0.3]\nradius = 0.4\n\
                 [[objects]]\ntype = \"sphere\"\nmaterial = \"mirror\"\ncenter = [-1.3, 0.5, 0.2]\nradius = 0.4\n\
                 [[lights]]\ntype = \"rect\"\norigin = [-0.5, 3.0, -0.5]\nedge_u = [1.0, 0.0, 0.0]\n\
                 edge_v = [0.0, 0.0, 1.0]\nradiance = [30.0, 30.0, 30.0]\nmodel = \"{model}\"\n\
                 shadow_rays = {rays}\nshadow_distribution = \"{dist}\"\n\
                 [[lights]]\ntype = \"point\"\nposition = [2.0, 2.5, 2.0]\nintensity = [3.0, 3.0, 3.0]\n"
            );
            let src = SceneSource::from_toml(
                &toml,
                std::path::Path::new("test.toml"),
                dir.path(),
                &LoadOptions::default(),
            );
            let scene = src
                .and_then(|s| s.build())
                .unwrap_or_else(|e| panic!("{e}"));
            let mut r = Rng::new(k as u64);
            let whitted = Whitted::of(&scene);
            let (mut wide, mut one) =
                (Tracer::new(&scene, &whitted), Tracer::new(&scene, &whitted));
            let mut out = Vec::new();
            for _ in 0..300 {
                // A pixel's rays: one origin, directions in a narrow cone
                // toward a point of the scene (or past the light, at the sky).
                let origin = Vec3::new(r.range(-3.0, 3.0), r.range(0.5, 4.0), 5.0);
                let aim = Vec3::new(r.range(-2.0, 2.0), r.range(-0.5, 3.5), r.range(-2.0, 2.0));
                let rays: Vec<Ray> = (0..16)
                    .map(|_| {
                        let jitter = Vec3::new(r.range(-0.05, 0.05), r.range(-0.05, 0.05), 0.0);
                        Ray::new(origin, (aim - origin).normalize() + jitter, 0.0)
                    })
                    .collect();
                let stream = |i: usize| Rng::new(99).derive(i as u64);
                out.clear();
                wide.radiance(&rays, 0, stream, &mut out);
                let mut alone = Vec::new();
                for (i, ray) in rays.iter().enumerate() {
                    one.radiance(std::slice::from_ref(ray), 0, |_| stream(i), &mut alone);
                    let l = alone[i];
                    let bits = |c: Rgb| c.to_array().map(f32::to_bits);
                    assert_eq!(bits(out[i]), bits(l), "light {k}, ray {ray:?}");
                    compared += usize::from(l != Rgb::ZERO);
                }
            }
            assert_eq!(wide.stats, one.stats, "light {k}");
            assert!(wide.stats.shadow > 2_000, "light {k}: {:?}", wide.stats);
        }
        assert!(compared > 8_000, "{compared} lit rays compared");
    }
}
