//! The path tracer's wavefront: the paths of whole rows of a tile in
//! structure-of-arrays buffers, advanced one stage at a time (see the
//! [module docs](super)).

use std::ops::Range;

use super::PathSettings;
use crate::accel::{Hit, PacketScratch};
use crate::bsdf::{Bsdf, BsdfFlags, BsdfSample};
use crate::emitter::choice::LightSampler;
use crate::emitter::{Emitter, LightSample};
use crate::integrator::film::FilmTile;
use crate::integrator::interface::{BadSample, TileJob};
use crate::integrator::metric::{Metric, RunningMean};
use crate::integrator::stats::{RayStats, StageBatches};
use crate::integrator::whitted::{guard, primary_rays};
use crate::math::{offset_origin, reach, Ray, Rgb, Vec2, Vec3};
use crate::sampling::points::unit_square;
use crate::sampling::{Distribution, EffectSpec, Rng, SetPoint};
use crate::scene::Scene;

/// The most paths a wave holds, unless one row of a tile's samples holds
/// more (a wave is whole rows).
pub const WAVE: usize = 8192;

/// Where a shadow ray ends, as a fraction of the way to its target: short
/// of the emitter's own surface.
const SHADOW_END: f32 = 1.0 - 1e-4;

/// The largest probability with which Russian roulette keeps a path.
const RR_MAX: f32 = 0.95;

/// The live paths of a wave, one entry per path in each buffer.
#[derive(Default)]
struct Paths {
    /// The ray each path follows next.
    ray: Vec<Ray>,
    /// The sample of the wave the path adds its radiance to.
    slot: Vec<u32>,
    /// Throughput: what the radiance found next is multiplied by.
    beta: Vec<Rgb>,
    /// The product of the `eta²` of the interfaces crossed (see
    /// [`BsdfSample::eta`](crate::bsdf::BsdfSample::eta)).
    eta2: Vec<f32>,
    /// The path's stream (its primary sample's).
    rng: Vec<Rng>,
    /// The vertex the ray left from, and its shading normal (zero for the
    /// camera): where the light sampler's probability of the emitter met is
    /// asked.
    from: Vec<(Vec3, Vec3)>,
    /// What the emission the ray meets is weighed by: the BSDF's
    /// solid-angle density times its samples at the vertex the ray left
    /// (0 after a delta lobe or from the camera: the emission then counts
    /// whole), and the emitter samples taken there.
    mis: Vec<(f32, Nee)>,
}

/// The emitter samples a vertex took (next-event estimation), as the
/// emission met from it is weighed against them.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Nee {
    /// None: the emission met counts whole.
    None,
    /// This many, each toward an emitter chosen by the light sampler.
    Choice(f32),
    /// A set toward every emitter, of the emitter's shadow rays (the
    /// thesis's shadow sets).
    Sets,
}

impl Paths {
    fn clear(&mut self) {
        self.ray.clear();
        self.slot.clear();
        self.beta.clear();
        self.eta2.clear();
        self.rng.clear();
        self.from.clear();
        self.mis.clear();
    }

    fn len(&self) -> usize {
        self.ray.len()
    }

    fn push(
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
struct ShadowRays {
    ray: Vec<Ray>,
    slot: Vec<u32>,
    value: Vec<Rgb>,
    set: Vec<u32>,
}

impl ShadowRays {
    fn clear(&mut self) {
        self.ray.clear();
        self.slot.clear();
        self.value.clear();
        self.set.clear();
    }

    fn push(&mut self, ray: Ray, slot: u32, value: Rgb, set: u32) {
        self.ray.push(ray);
        self.slot.push(slot);
        self.value.push(value);
        self.set.push(set);
    }
}

/// A shadow set the thesis's shadow metric judges: `n` members, of which
/// the first `k` are traced first; `reached` and `blocked` count how those
/// of them that are rays ended.
#[derive(Clone, Copy, Debug)]
struct ShadowTally {
    n: u32,
    k: u32,
    reached: u32,
    blocked: u32,
}

impl ShadowTally {
    /// The metric's verdict after the first `k` members: stop if they all
    /// reached the emitter or were all blocked (and one was a ray).
    fn stops(&self) -> bool {
        (self.reached == 0 || self.blocked == 0) && self.reached + self.blocked > 0
    }
}

/// No shadow set: a ray no metric judges.
const NO_SET: u32 = u32::MAX;

/// The shadow rays of a bounce: `now`, traced first, and `later`, the
/// members past the first `k` of the sets the shadow metric judges, traced
/// only for the sets it does not stop (see [`Wavefront::occlude`]).
#[derive(Default)]
struct Shadows {
    now: ShadowRays,
    later: ShadowRays,
    sets: Vec<ShadowTally>,
}

impl Shadows {
    fn clear(&mut self) {
        self.now.clear();
        self.later.clear();
        self.sets.clear();
    }
}

/// A worker's wavefront: its buffers, kept from wave to wave.
pub(super) struct Wavefront<'s> {
    scene: &'s Scene,
    settings: PathSettings,
    /// How next-event estimation chooses its emitter.
    lights: &'s LightSampler,
    pub(super) stats: RayStats,
    /// The calls of each stage and the items they took.
    pub(super) batches: StageBatches,
    /// Per material, what its vertices need of its lobes (found once).
    materials: Vec<Material>,
    /// The emitters at infinity, which rays that hit nothing see.
    far: Vec<u32>,
    /// How to reach the emitters at infinity from a point (see [`Escape`]).
    escape: Escape,
    /// Per material, the transparency shadow rays see: none.
    opaque: Vec<f32>,
    paths: Paths,
    next: Paths,
    hits: Vec<Option<Hit>>,
    packet: PacketScratch,
    /// The paths of a bounce grouped for shading: those that met nothing,
    /// then those on each material in turn (see [`group_by_material`]).
    order: Vec<u32>,
    /// Where each group of `order` starts, and its end.
    groups: Vec<u32>,
    shadows: Shadows,
    /// What each shadow ray of the bounce lets through (`None`: blocked).
    passed: Vec<Option<f32>>,
    /// Per sample of the wave, the radiance its path gathered.
    radiance: Vec<Rgb>,
    /// Per sample of the wave, its pixel-filter weight.
    weights: Vec<f32>,
    /// The points of a set being drawn.
    points: Vec<Vec3>,
    /// The sets the reflection metric judges, of the wave's first vertices.
    pending: Vec<PendingSet>,
}

impl<'s> Wavefront<'s> {
    pub(super) fn new(
        scene: &'s Scene,
        settings: PathSettings,
        lights: &'s LightSampler,
    ) -> Wavefront<'s> {
        let far = (0..scene.emitters.len() as u32)
            .filter(|&e| scene.emitters[e as usize].is_infinite())
            .collect();
        let materials = scene
            .bsdfs
            .iter()
            .map(|bsdf| Material::of(bsdf, scene.settings.reflection))
            .collect();
        let b = scene.world.bounds();
        let escape = Escape {
            center: 0.5 * (b.min + b.max),
            radius: 0.5 * (b.max - b.min).length(),
        };
        Wavefront {
            scene,
            settings,
            lights,
            stats: RayStats::default(),
            batches: StageBatches::default(),
            materials,
            far,
            escape,
            opaque: vec![0.0; scene.bsdfs.len()],
            paths: Paths::default(),
            next: Paths::default(),
            hits: Vec::new(),
            packet: PacketScratch::default(),
            order: Vec::new(),
            groups: Vec::new(),
            shadows: Shadows::default(),
            passed: Vec::new(),
            radiance: Vec::new(),
            weights: Vec::new(),
            points: Vec::new(),
            pending: Vec::new(),
        }
    }

    /// Adds samples `tile.samples` of the tile's pixels to `film`, a wave
    /// of whole rows at a time; `false` if the tile was cancelled (checked
    /// before every wave).
    pub(super) fn render(
        &mut self,
        tile: TileJob<'_>,
        film: &mut FilmTile,
        bad: &mut Vec<BadSample>,
    ) -> bool {
        let TileJob {
            xs,
            ys,
            samples,
            cancelled,
        } = tile;
        let m = samples.len();
        if m == 0 {
            return true;
        }
        let rows = (WAVE / (xs.len() * m)).max(1) as u32;
        let mut y0 = ys.start;
        while y0 < ys.end {
            if cancelled() {
                return false;
            }
            let y1 = (y0 + rows).min(ys.end);
            self.wave(&xs, y0..y1, &samples);
            let mut values = self.radiance.iter().zip(&self.weights);
            for y in y0..y1 {
                for x in xs.clone() {
                    let k = film.index(x, y);
                    for i in samples.clone() {
                        let (&l, &w) = values.next().expect("a value per sample");
                        film.add(k, guard(l, x, y, i as usize, bad), w);
                    }
                }
            }
            y0 = y1;
        }
        true
    }

    /// Traces samples `samples` of pixels `xs × ys` to their end, leaving
    /// their radiance in `self.radiance`, pixel by pixel.
    fn wave(&mut self, xs: &Range<u32>, ys: Range<u32>, samples: &Range<u32>) {
        let keep = samples.start as usize..samples.end as usize;
        let paths = &mut self.paths;
        paths.clear();
        self.weights.clear();
        let ordered = self.settings.metric.is_some_and(|m| m.pixels);
        for y in ys {
            primary_rays(
                (self.scene, ordered),
                (xs.clone(), y),
                keep.clone(),
                &mut paths.ray,
                &mut paths.rng,
                &mut self.weights,
            );
        }
        let n = paths.ray.len();
        paths.slot.extend(0..n as u32);
        paths.beta.resize(n, Rgb::ONE);
        paths.eta2.resize(n, 1.0);
        paths
            .from
            .extend(paths.ray.iter().map(|r| (r.origin, Vec3::ZERO)));
        paths.mis.resize(n, (0.0, Nee::None));
        self.radiance.clear();
        self.radiance.resize(n, Rgb::ZERO);
        self.stats.primary += n as u64;
        self.pending.clear();
        let max_depth = self.settings.max_depth.unwrap_or(u32::MAX);
        let mut depth = 0;
        loop {
            while self.paths.len() > 0 && depth < max_depth {
                let scene = self.scene;
                self.batches.closest_hit.add(self.paths.len());
                scene
                    .world
                    .intersect_all(&self.paths.ray, 0.0, &mut self.packet, &mut self.hits);
                self.shade(depth, max_depth);
                self.occlude();
                std::mem::swap(&mut self.paths, &mut self.next);
                depth += 1;
            }
            // The judged sets' next members, from the second vertex on.
            if !self.judge_sets() {
                break;
            }
            depth = 1;
        }
        self.radiance.truncate(n);
    }

    /// Judges the sets of BSDF samples pending at the wave's first
    /// vertices by the reflection metric (thesis §3.4), their latest
    /// members traced to their ends: a set whose running mean changed by
    /// less than the threshold, or that has traced all its members, adds
    /// its mean to its sample and counts the members left as saved; every
    /// other set starts the path of its next member. True if any did.
    fn judge_sets(&mut self) -> bool {
        let Some(metric) = self.settings.metric else {
            return false;
        };
        let scene = self.scene;
        self.paths.clear();
        let mut going = 0;
        for p in &mut self.pending {
            if p.batch == 0 {
                continue;
            }
            let n = p.set.rays;
            let mut stop = false;
            for a in p.acc..p.acc + p.batch {
                stop = p.mean.push(self.radiance[a as usize], Some(&metric), n);
            }
            let traced = p.mean.count();
            let v = p.vertex();
            let bsdf = &scene.bsdfs[p.material as usize];
            let table = &scene.settings.points;
            let mut rng = p.path.derive(BSDF_SET);
            (p.set.distribution).generate_in(table, n as usize, 1.0, &mut rng, &mut self.points);
            if stop || traced == n {
                self.radiance[p.slot as usize] += p.mean.mean();
                for &point in &self.points[traced as usize..] {
                    let u = SetPoint::new(point, p.set.distribution);
                    if let Some(s) = bsdf.sample(v.hit, v.wo, None, u) {
                        count_saved(&mut self.stats, s.flags);
                    }
                }
                p.batch = 0;
                continue;
            }
            let acc = self.radiance.len() as u32;
            self.radiance.push(Rgb::ZERO);
            let member = Member {
                k: traced,
                point: self.points[traced as usize],
                set: p.set,
                slot: acc,
                share: 1.0,
            };
            set_member(
                &v,
                bsdf,
                (p.path, p.rr),
                member,
                &mut self.paths,
                &mut self.stats,
            );
            (p.acc, p.batch) = (acc, 1);
            going += 1;
        }
        going > 0
    }

    /// The shading stage of the paths at vertex `depth`: adds the emission
    /// each path meets, prepares its shadow ray, samples its BSDF and keeps
    /// in `self.next` the paths that go on.
    fn shade(&mut self, depth: u32, max_depth: u32) {
        let scene = self.scene;
        let Wavefront {
            settings,
            lights: chooser,
            stats,
            materials,
            far,
            escape,
            paths,
            next,
            hits,
            order,
            groups,
            shadows,
            radiance,
            points,
            batches,
            pending,
            ..
        } = self;
        next.clear();
        shadows.clear();
        let seen = !(settings.hide_emitters && depth == 0);
        let go_on = depth.saturating_add(1) < max_depth;
        // Next-event estimation chooses among every emitter.
        let lights = scene.emitters.len();
        let shadow = scene.settings.shadow;
        group_by_material(hits, scene.bsdfs.len(), order, groups);
        for g in groups.windows(2).filter(|g| g[1] > g[0]) {
            batches.shading.add((g[1] - g[0]) as usize);
        }
        for &i in order.iter() {
            let i = i as usize;
            let hit = &hits[i];
            let (ray, slot, beta) = (&paths.ray[i], paths.slot[i], paths.beta[i]);
            let acc = &mut radiance[slot as usize];
            let prev = paths.mis[i];
            let Some(hit) = hit else {
                if seen {
                    for &e in far.iter() {
                        let emitter = &scene.emitters[e as usize];
                        let (from, from_n) = paths.from[i];
                        let choice = || chooser.pmf(from, from_n, e);
                        let w = emission_weight(emitter, shadow, prev, choice, || {
                            emitter.pdf_direction(ray.dir)
                        });
                        *acc += beta * emitter.eval_miss(ray.dir) * w;
                    }
                }
                continue;
            };
            if let (Some(e), true) = (hit.emitter, seen) {
                let emitter = &scene.emitters[e as usize];
                let (from, from_n) = paths.from[i];
                let choice = || chooser.pmf(from, from_n, e);
                let density = || emitter.pdf(from, hit.p, hit.ng);
                let w = emission_weight(emitter, shadow, prev, choice, density);
                if w > 0.0 {
                    let le = scene.emitters[e as usize].eval(hit.ng, ray.dir);
                    *acc += beta * le * w;
                }
            }
            if !go_on {
                continue;
            }
            let bsdf = &scene.bsdfs[hit.material as usize];
            let v = Vertex {
                hit,
                wo: -ray.dir.normalize(),
                reach: reach(hit.p, ray.origin),
                time: ray.time,
                beta,
                eta2: paths.eta2[i],
                slot,
            };
            let (e, b) = if depth == 0 {
                (settings.emitter_samples, settings.bsdf_samples)
            } else {
                (1, 1)
            };
            if depth < settings.sets_depth {
                let judge = settings.metric.filter(|m| m.reflections && depth == 0);
                let mut out = Out {
                    shadows,
                    next,
                    stats,
                    points: &mut *points,
                    escape: *escape,
                    judge: judge.map(|m| m.min_rays.max(2)),
                    radiance: &mut *radiance,
                    pending: &mut *pending,
                };
                let rr = depth + 1 >= settings.rr_depth;
                let m = &materials[hit.material as usize];
                thesis_sets(
                    (scene, settings.metric),
                    &v,
                    (bsdf, m),
                    (paths.rng[i], rr),
                    &mut out,
                );
                continue;
            }
            // The bounce's numbers: dimensions 2j and 2j + 1 for emitter
            // sample j, then 2e + 2k and 2e + 2k + 1 for BSDF sample k.
            let mut u = settings
                .sampler
                .bounce(paths.rng[i].derive(u64::from(depth)));
            // Next-event estimation on the smooth lobes.
            let smooth = materials[hit.material as usize].smooth;
            let nee = smooth && lights > 0 && e > 0;
            for j in 0..u64::from(e) {
                let choice = u.value(2 * j);
                let point = u.point(2 * j + 1);
                if nee {
                    let Some((k, pmf)) = chooser.sample(hit.p, hit.n, choice) else {
                        continue;
                    };
                    let emitter = &scene.emitters[k as usize];
                    let n = (e as f32, b as f32, pmf);
                    light_sample(&v, bsdf, (emitter, *escape), point, n, shadows);
                }
            }
            // The next directions.
            let taken = if nee {
                Nee::Choice(e as f32)
            } else {
                Nee::None
            };
            for k in 0..b {
                let d = 2 * u64::from(e + k);
                let point = SetPoint::uniform(u.point(d));
                let roulette = u.value(d + 1);
                let Some(s) = bsdf.sample(hit, v.wo, None, point) else {
                    continue;
                };
                let rr = (depth + 1 >= settings.rr_depth).then_some(roulette);
                let Some(through) = go_through(&v, &s, b as f32, rr) else {
                    continue;
                };
                let delta = s.flags.is_delta();
                let origin = offset_origin(hit.p, v.reach, hit.ng, s.wi);
                // The densities emission met next is weighed by.
                let mis = if delta {
                    (0.0, Nee::None)
                } else {
                    (b as f32 * s.pdf, taken)
                };
                let stream = if b == 1 {
                    paths.rng[i]
                } else {
                    paths.rng[i].child(k as usize, b as usize)
                };
                next.push(
                    Ray::new(origin, s.wi, ray.time),
                    slot,
                    through,
                    stream,
                    ((hit.p, hit.n), mis),
                );
                count_bounce(stats, s.flags);
            }
        }
    }

    /// The occlusion stage: every shadow ray of the bounce tested in one
    /// call, and what the unblocked ones bring added to their samples. A
    /// set the shadow metric judges whose first `k` members all reached
    /// the emitter, or were all blocked, stops there: their mean is its
    /// value (each of its rays counts `n / k` times) and the rest are never
    /// traced; the rest of the other sets go in a second call.
    fn occlude(&mut self) {
        let world = &self.scene.world;
        let Shadows { now, later, sets } = &mut self.shadows;
        let passed = &mut self.passed;
        if !now.ray.is_empty() {
            self.stats.shadow += now.ray.len() as u64;
            self.batches.occlusion.add(now.ray.len());
            world.transmittance_all(&now.ray, (0.0, SHADOW_END), &self.opaque, passed);
            for (&set, pass) in now.set.iter().zip(passed.iter()) {
                if let Some(t) = sets.get_mut(set as usize) {
                    if pass.is_some() {
                        t.reached += 1;
                    } else {
                        t.blocked += 1;
                    }
                }
            }
            let rays = now.slot.iter().zip(&now.value).zip(&now.set);
            for (((&slot, &value), &set), pass) in rays.zip(passed.iter()) {
                if pass.is_none() {
                    continue;
                }
                let scale = match sets.get(set as usize) {
                    Some(t) if t.stops() => t.n as f32 / t.k as f32,
                    _ => 1.0,
                };
                self.radiance[slot as usize] += value * scale;
            }
        }
        for t in sets.iter().filter(|t| t.stops()) {
            self.stats.saved.shadow += u64::from(t.n - t.k);
        }
        // The rest of the sets the metric did not stop.
        let mut keep = 0;
        for i in 0..later.ray.len() {
            if !sets[later.set[i] as usize].stops() {
                later.ray[keep] = later.ray[i];
                later.slot[keep] = later.slot[i];
                later.value[keep] = later.value[i];
                keep += 1;
            }
        }
        if keep == 0 {
            return;
        }
        let rays = &later.ray[..keep];
        self.stats.shadow += keep as u64;
        self.batches.occlusion.add(keep);
        world.transmittance_all(rays, (0.0, SHADOW_END), &self.opaque, passed);
        for ((&slot, &value), pass) in later.slot.iter().zip(&later.value).zip(passed.iter()) {
            if pass.is_some() {
                self.radiance[slot as usize] += value;
            }
        }
    }
}

/// Groups the paths of a bounce for shading, keeping their order within a
/// group: `order` lists first those whose ray met nothing, then those on
/// material 0, 1, … of the `materials`; group `g` is
/// `order[groups[g]..groups[g + 1]]`. A path's contributions to its sample
/// keep their order whatever else shares the wave, so pixels do not depend
/// on how a frame is cut into tiles and waves.
fn group_by_material(
    hits: &[Option<Hit>],
    materials: usize,
    order: &mut Vec<u32>,
    groups: &mut Vec<u32>,
) {
    let key = |h: &Option<Hit>| h.as_ref().map_or(0, |h| h.material as usize + 1);
    groups.clear();
    groups.resize(materials + 2, 0);
    for h in hits {
        groups[key(h) + 1] += 1;
    }
    for g in 1..groups.len() {
        groups[g] += groups[g - 1];
    }
    order.clear();
    order.resize(hits.len(), 0);
    let mut next: Vec<u32> = groups[..materials + 1].to_vec();
    for (i, h) in hits.iter().enumerate() {
        let k = key(h);
        order[next[k] as usize] = i as u32;
        next[k] += 1;
    }
}

/// The weight of the emission of `emitter` that a path meets, having left
/// its last vertex with BSDF density `pdf` times the BSDF samples taken
/// there (0: from the camera or a delta lobe, which next-event estimation
/// could not have drawn) beside the emitter samples `nee`: the power
/// heuristic against the emitter samples' density (`density()` of one
/// sample toward where the path met it, times their count and, under a
/// choice among emitters, the probability `choice()` that the light
/// sampler chose this one from that vertex; a set has its emitter's size,
/// `shadow` for one at infinity); 1 if the light sampler could not have
/// chosen it there; 0 for an emitter sampled without a density (the
/// thesis's penumbra model), whose light its shadow rays alone bring.
fn emission_weight(
    emitter: &Emitter,
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
        Nee::Sets => shadow_set(emitter, shadow).rays as f32 * density(),
    };
    if pdf_light > 0.0 {
        power_heuristic(pdf, pdf_light)
    } else {
        0.0
    }
}

/// The branch of a path's stream that the shadow set toward light `j` of
/// a vertex drawing the thesis's sets takes (`SHADOW_SETS + j`); the
/// vertex's BSDF set takes `BSDF_SET`, and each path it starts the child
/// stream of its index. Far above the bounces' branches.
const SHADOW_SETS: u64 = 1 << 32;
const BSDF_SET: u64 = SHADOW_SETS - 1;
/// The branch of a set's path that its Russian roulette reads.
const ROULETTE: u64 = SHADOW_SETS - 2;

/// Where a vertex's work goes: its shadow rays, the paths it starts, the
/// ray counts, and a buffer for a set's points.
struct Out<'a> {
    shadows: &'a mut Shadows,
    next: &'a mut Paths,
    stats: &'a mut RayStats,
    points: &'a mut Vec<Vec3>,
    escape: Escape,
    /// With the reflection metric on, at a first vertex: the members its
    /// sets always trace (α, at least 2).
    judge: Option<u32>,
    /// The samples of the wave, which judged sets' members add to.
    radiance: &'a mut Vec<Rgb>,
    /// The sets the reflection metric judges.
    pending: &'a mut Vec<PendingSet>,
}

/// A vertex that draws the thesis's sets (`distributed`): a set of shadow
/// rays toward every emitter, of the emitter's `shadow_rays` from its
/// `shadow_distribution`, and one set of BSDF samples whose count and
/// distribution are the largest set the material's lobes ask for (the
/// render's reflection set for a material without sets), each sample
/// starting a path of its own with the set's share of the throughput. The
/// two are weighed by the power heuristic on density times count. `path`
/// is the vertex's stream; `rr` says whether the paths it starts face
/// Russian roulette.
fn thesis_sets(
    (scene, metric): (&Scene, Option<Metric>),
    v: &Vertex<'_>,
    (bsdf, material): (&Bsdf, &Material),
    (path, rr): (Rng, bool),
    out: &mut Out<'_>,
) {
    let table = &scene.settings.points;
    let set = material.set;
    let nb = set.rays as f32;
    if material.smooth {
        // The shadow metric's k, for the sets it judges.
        let metric = metric.filter(|m| m.shadows);
        for (j, emitter) in scene.emitters.iter().enumerate() {
            let set = shadow_set(emitter, scene.settings.shadow);
            let (n, d) = (set.rays, set.distribution);
            let k = metric.map(|m| m.shadow_rays).filter(|&k| k < n);
            let id = match k {
                Some(k) => {
                    let tally = ShadowTally {
                        n,
                        k,
                        reached: 0,
                        blocked: 0,
                    };
                    out.shadows.sets.push(tally);
                    out.shadows.sets.len() as u32 - 1
                }
                None => NO_SET,
            };
            let mut rng = path.derive(SHADOW_SETS + j as u64);
            d.generate_in(table, n as usize, 1.0, &mut rng, out.points);
            for (m, &point) in out.points.iter().enumerate() {
                let Some(ls) = sample_emitter(emitter, v.hit.p, (point, d), out.escape) else {
                    continue;
                };
                let ns = n as f32;
                let weigh = |pdf_b: f32| power_heuristic(ns * ls.pdf, nb * pdf_b);
                let rays = match k {
                    Some(k) if m as u32 >= k => &mut out.shadows.later,
                    _ => &mut out.shadows.now,
                };
                shadow_ray(v, bsdf, &ls, weigh, ns, (rays, id));
            }
        }
    }
    let mut rng = path.derive(BSDF_SET);
    set.distribution
        .generate_in(table, set.rays as usize, 1.0, &mut rng, out.points);
    let first = out.judge.filter(|&a| set.rays > a);
    if let Some(alpha) = first {
        // The reflection metric judges the set: its first α members, each
        // adding to a sample of its own, and the rest one at a time
        // (see [`Wavefront::judge_sets`]).
        let acc = out.radiance.len() as u32;
        out.radiance
            .resize(out.radiance.len() + alpha as usize, Rgb::ZERO);
        for k in 0..alpha {
            let member = Member {
                k,
                point: out.points[k as usize],
                set,
                slot: acc + k,
                share: 1.0,
            };
            set_member(v, bsdf, (path, rr), member, out.next, out.stats);
        }
        out.pending.push(PendingSet {
            hit: *v.hit,
            wo: v.wo,
            reach: v.reach,
            time: v.time,
            beta: v.beta,
            eta2: v.eta2,
            slot: v.slot,
            path,
            rr,
            material: v.hit.material,
            set,
            acc,
            batch: alpha,
            mean: RunningMean::default(),
        });
        return;
    }
    for (k, &point) in out.points.iter().enumerate() {
        let member = Member {
            k: k as u32,
            point,
            set,
            slot: v.slot,
            share: nb,
        };
        set_member(v, bsdf, (path, rr), member, out.next, out.stats);
    }
}

/// A member of a vertex's set of BSDF samples: the `k`th of `set`, at
/// `point`, adding to sample `slot` with `1 / share` of the throughput.
#[derive(Clone, Copy)]
struct Member {
    k: u32,
    point: Vec3,
    set: EffectSpec,
    slot: u32,
    share: f32,
}

/// Starts the path of member `m` of the BSDF set at `v` (whose stream is
/// `path`; `rr`: the path faces Russian roulette), unless its sample has
/// no density, carries nothing or roulette ends it.
fn set_member(
    v: &Vertex<'_>,
    bsdf: &Bsdf,
    (path, rr): (Rng, bool),
    m: Member,
    next: &mut Paths,
    stats: &mut RayStats,
) {
    let n = m.set.rays;
    let u = SetPoint::new(m.point, m.set.distribution);
    let Some(s) = bsdf.sample(v.hit, v.wo, None, u) else {
        return;
    };
    let stream = path.child(m.k as usize, n as usize);
    let roulette = rr.then(|| stream.derive(ROULETTE).next_f32());
    let Some(through) = go_through(v, &s, m.share, roulette) else {
        return;
    };
    let delta = s.flags.is_delta();
    let origin = offset_origin(v.hit.p, v.reach, v.hit.ng, s.wi);
    // The emission met is weighed against the whole set's density.
    let mis = if delta {
        (0.0, Nee::None)
    } else {
        (n as f32 * s.pdf, Nee::Sets)
    };
    let ray = Ray::new(origin, s.wi, v.time);
    next.push(ray, m.slot, through, stream, ((v.hit.p, v.hit.n), mis));
    count_bounce(stats, s.flags);
}

/// A set of BSDF samples the reflection metric judges, at a first vertex:
/// the vertex, its set, the samples `acc..acc + batch` its latest members
/// add to, and the running mean of the members traced so far.
struct PendingSet {
    hit: Hit,
    wo: Vec3,
    reach: f32,
    time: f32,
    beta: Rgb,
    eta2: f32,
    /// The sample the set's value goes to.
    slot: u32,
    path: Rng,
    rr: bool,
    material: u32,
    set: EffectSpec,
    acc: u32,
    batch: u32,
    mean: RunningMean,
}

impl PendingSet {
    fn vertex(&self) -> Vertex<'_> {
        Vertex {
            hit: &self.hit,
            wo: self.wo,
            reach: self.reach,
            time: self.time,
            beta: self.beta,
            eta2: self.eta2,
            slot: self.slot,
        }
    }
}

/// The throughput and `eta²` product of the path the BSDF sample `s`
/// continues from `v`, one of `n` samples there; `None` if the sample has
/// no density where it needs one, carries nothing, or Russian roulette
/// (when `roulette` gives its number) ends it. Roulette keeps a path with
/// probability `min(max(throughput) · eta², 0.95)`, as Mitsuba 3 does, so
/// that the radiance scale of a crossing into a denser medium does not
/// end paths that will cross back out.
fn go_through(v: &Vertex<'_>, s: &BsdfSample, n: f32, roulette: Option<f32>) -> Option<(Rgb, f32)> {
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
fn count_bounce(stats: &mut RayStats, flags: BsdfFlags) {
    if flags.contains(BsdfFlags::TRANSMISSION) {
        stats.refraction += 1;
    } else {
        stats.reflection += 1;
    }
}

/// Counts a BSDF sample's ray, left untraced by the metric, as a saved
/// reflection or refraction ray.
fn count_saved(stats: &mut RayStats, flags: BsdfFlags) {
    if flags.contains(BsdfFlags::TRANSMISSION) {
        stats.saved.refraction += 1;
    } else {
        stats.saved.reflection += 1;
    }
}

/// A shading point, as next-event estimation reads it.
struct Vertex<'h> {
    hit: &'h Hit,
    wo: Vec3,
    reach: f32,
    time: f32,
    beta: Rgb,
    eta2: f32,
    slot: u32,
}

/// One of `e` emitter samples at `v` toward `emitter` (chosen with
/// probability `pmf`) with the point `point`, beside `b` BSDF samples
/// (`counts`): its shadow ray and what it brings,
/// `f · L · cos / (pdf · pmf · e)` weighed by the power heuristic, pushed
/// to `shadows` unless it brings nothing.
fn light_sample(
    v: &Vertex<'_>,
    bsdf: &Bsdf,
    (emitter, escape): (&Emitter, Escape),
    point: Vec2,
    (e, b, pmf): (f32, f32, f32),
    shadows: &mut Shadows,
) {
    let p = SetPoint::uniform(point).native();
    let Some(ls) = sample_emitter(emitter, v.hit.p, (p, Distribution::Jitter), escape) else {
        return;
    };
    let weigh = |pdf_b: f32| power_heuristic(e * pmf * ls.pdf, b * pdf_b);
    shadow_ray(v, bsdf, &ls, weigh, e * pmf, (&mut shadows.now, NO_SET));
}

/// What a vertex needs of its material's lobes.
#[derive(Clone, Copy, Debug)]
struct Material {
    /// It has a smooth lobe: emitter samples can light it.
    smooth: bool,
    /// The set of BSDF samples a vertex drawing the thesis's sets takes:
    /// the largest set its lobes ask for, else the render's reflection set.
    set: EffectSpec,
}

impl Material {
    fn of(bsdf: &Bsdf, reflection: EffectSpec) -> Material {
        let lobes = bsdf.lobes();
        let largest = lobes.sets.iter().flatten().max_by_key(|s| s.rays);
        Material {
            smooth: lobes.any_smooth(),
            set: largest.copied().unwrap_or(reflection),
        }
    }
}

/// How far a shadow ray toward an emitter at infinity goes: past the
/// sphere around the world's bounds.
#[derive(Clone, Copy, Debug)]
struct Escape {
    center: Vec3,
    radius: f32,
}

/// The shadow set of `emitter` at a vertex drawing the thesis's sets: its
/// own, but one at infinity takes the render's shadow set (`shadow`).
fn shadow_set(emitter: &Emitter, shadow: EffectSpec) -> EffectSpec {
    if emitter.is_infinite() {
        shadow
    } else {
        EffectSpec {
            rays: emitter.shadow_rays(),
            distribution: emitter.shadow().distribution,
        }
    }
}

/// A sample of `emitter` seen from `p` for the distribution point `point`
/// of `d`: [`Emitter::sample_one`], or for an emitter at infinity a
/// direction with a target beyond the world (`escape`).
fn sample_emitter(
    emitter: &Emitter,
    p: Vec3,
    (point, d): (Vec3, Distribution),
    escape: Escape,
) -> Option<LightSample> {
    if !emitter.is_infinite() {
        return emitter.sample_one(p, point, d);
    }
    let (dir, radiance, pdf) = emitter.sample_direction(unit_square(point, d))?;
    let far = 2.0 * (escape.radius + (p - escape.center).length()) + 1.0;
    Some(LightSample {
        target: p + dir * far,
        dir,
        weight: radiance / pdf,
        pdf,
    })
}

/// The shadow ray of the light sample `ls` at `v`, one of `n` (the
/// sample's share: divided by `n`), and what it brings if unblocked:
/// `f · weight · cos / n`, times `weigh` of the BSDF's density toward it
/// where the sample has a density (1 where it has none: a point light, the
/// thesis's penumbra model). Pushed to `rays`, judged with shadow set `set`,
/// unless it brings nothing.
fn shadow_ray(
    v: &Vertex<'_>,
    bsdf: &Bsdf,
    ls: &LightSample,
    weigh: impl Fn(f32) -> f32,
    n: f32,
    (rays, set): (&mut ShadowRays, u32),
) {
    let wi = ls.dir;
    let f = bsdf.eval(v.hit, v.wo, wi);
    let cos = v.hit.n.dot(wi).abs();
    if f == Rgb::ZERO || cos <= 0.0 {
        return;
    }
    let w = if ls.pdf > 0.0 {
        weigh(bsdf.pdf(v.hit, v.wo, wi))
    } else {
        1.0
    };
    let origin = offset_origin(v.hit.p, v.reach, v.hit.ng, wi);
    let ray = Ray::new(origin, ls.target - origin, v.time);
    rays.push(ray, v.slot, v.beta * f * ls.weight * (cos * w / n), set);
}

/// The power heuristic (β = 2) weight of a sample drawn with density `a`
/// against another strategy's density `b`.
#[inline]
fn power_heuristic(a: f32, b: f32) -> f32 {
    let (a2, b2) = (a * a, b * b);
    if a2 + b2 > 0.0 {
        a2 / (a2 + b2)
    } else {
        0.0
    }
}
