//! The path tracer's wavefront: the paths of whole rows of a tile in
//! structure-of-arrays buffers, advanced one stage at a time (see the
//! [module docs](super)).

use std::ops::Range;

use crate::accel::{Hit, PacketScratch};
use crate::bsdf::{Bsdf, BsdfFlags, BsdfSample};
use crate::emitter::{Emitter, LightSample};
use crate::integrator::film::FilmTile;
use crate::integrator::interface::{BadSample, TileJob};
use crate::integrator::stats::RayStats;
use crate::integrator::whitted::{guard, primary_rays};
use crate::math::{offset_origin, reach, Ray, Rgb, Vec2, Vec3};
use crate::sampling::points::unit_square;
use crate::sampling::{Distribution, EffectSpec, Rng, SetPoint};
use crate::scene::{PathSettings, Scene};

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

/// Shadow rays of a bounce, each with the sample it lights and what it
/// brings if nothing blocks it.
#[derive(Default)]
struct Shadows {
    ray: Vec<Ray>,
    slot: Vec<u32>,
    value: Vec<Rgb>,
}

/// A worker's wavefront: its buffers, kept from wave to wave.
pub(super) struct Wavefront<'s> {
    scene: &'s Scene,
    settings: PathSettings,
    pub(super) stats: RayStats,
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
    shadows: Shadows,
    /// Per sample of the wave, the radiance its path gathered.
    radiance: Vec<Rgb>,
    /// Per sample of the wave, its pixel-filter weight.
    weights: Vec<f32>,
    /// The points of a set being drawn.
    points: Vec<Vec3>,
}

impl<'s> Wavefront<'s> {
    pub(super) fn new(scene: &'s Scene, settings: PathSettings) -> Wavefront<'s> {
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
            stats: RayStats::default(),
            materials,
            far,
            escape,
            opaque: vec![0.0; scene.bsdfs.len()],
            paths: Paths::default(),
            next: Paths::default(),
            hits: Vec::new(),
            packet: PacketScratch::default(),
            shadows: Shadows::default(),
            radiance: Vec::new(),
            weights: Vec::new(),
            points: Vec::new(),
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
        for y in ys {
            primary_rays(
                self.scene,
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
        let max_depth = self.settings.max_depth.unwrap_or(u32::MAX);
        let mut depth = 0;
        while self.paths.len() > 0 && depth < max_depth {
            let scene = self.scene;
            scene
                .world
                .intersect_all(&self.paths.ray, 0.0, &mut self.packet, &mut self.hits);
            self.shade(depth, max_depth);
            self.occlude();
            std::mem::swap(&mut self.paths, &mut self.next);
            depth += 1;
        }
    }

    /// The shading stage of the paths at vertex `depth`: adds the emission
    /// each path meets, prepares its shadow ray, samples its BSDF and keeps
    /// in `self.next` the paths that go on.
    fn shade(&mut self, depth: u32, max_depth: u32) {
        let scene = self.scene;
        let Wavefront {
            settings,
            stats,
            materials,
            far,
            escape,
            paths,
            next,
            hits,
            shadows,
            radiance,
            points,
            ..
        } = self;
        next.clear();
        shadows.ray.clear();
        shadows.slot.clear();
        shadows.value.clear();
        let seen = !(settings.hide_emitters && depth == 0);
        let go_on = depth.saturating_add(1) < max_depth;
        // Next-event estimation chooses among every emitter.
        let lights = scene.emitters.len();
        let shadow = scene.settings.shadow;
        for (i, hit) in hits.iter().enumerate() {
            let (ray, slot, beta) = (&paths.ray[i], paths.slot[i], paths.beta[i]);
            let acc = &mut radiance[slot as usize];
            let prev = paths.mis[i];
            let Some(hit) = hit else {
                if seen {
                    for &e in far.iter() {
                        let emitter = &scene.emitters[e as usize];
                        let (from, from_n) = paths.from[i];
                        let choice = || scene.lights.pmf(from, from_n, e);
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
                let choice = || scene.lights.pmf(from, from_n, e);
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
                let mut out = Out {
                    shadows,
                    next,
                    stats,
                    points: &mut *points,
                    escape: *escape,
                };
                let rr = depth + 1 >= settings.rr_depth;
                let m = &materials[hit.material as usize];
                thesis_sets(scene, &v, (bsdf, m), (paths.rng[i], rr), &mut out);
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
                    let Some((k, pmf)) = scene.lights.sample(hit.p, hit.n, choice) else {
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

    /// The occlusion stage: every shadow ray of the bounce tested, and what
    /// the unblocked ones bring added to their samples.
    fn occlude(&mut self) {
        let world = &self.scene.world;
        let s = &self.shadows;
        self.stats.shadow += s.ray.len() as u64;
        for ((ray, &slot), &value) in s.ray.iter().zip(&s.slot).zip(&s.value) {
            if world
                .transmittance(ray, (0.0, SHADOW_END), &self.opaque, None)
                .is_some()
            {
                self.radiance[slot as usize] += value;
            }
        }
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
    scene: &Scene,
    v: &Vertex<'_>,
    (bsdf, material): (&Bsdf, &Material),
    (path, rr): (Rng, bool),
    out: &mut Out<'_>,
) {
    let table = &scene.settings.points;
    let set = material.set;
    let nb = set.rays as f32;
    if material.smooth {
        for (j, emitter) in scene.emitters.iter().enumerate() {
            let set = shadow_set(emitter, scene.settings.shadow);
            let (n, d) = (set.rays, set.distribution);
            let mut rng = path.derive(SHADOW_SETS + j as u64);
            d.generate_in(table, n as usize, 1.0, &mut rng, out.points);
            for &point in out.points.iter() {
                let Some(ls) = sample_emitter(emitter, v.hit.p, (point, d), out.escape) else {
                    continue;
                };
                let ns = n as f32;
                let weigh = |pdf_b: f32| power_heuristic(ns * ls.pdf, nb * pdf_b);
                shadow_ray(v, bsdf, &ls, weigh, ns, out.shadows);
            }
        }
    }
    let mut rng = path.derive(BSDF_SET);
    set.distribution
        .generate_in(table, set.rays as usize, 1.0, &mut rng, out.points);
    for (k, &point) in out.points.iter().enumerate() {
        let u = SetPoint::new(point, set.distribution);
        let Some(s) = bsdf.sample(v.hit, v.wo, None, u) else {
            continue;
        };
        let stream = path.child(k, set.rays as usize);
        let roulette = rr.then(|| stream.derive(ROULETTE).next_f32());
        let Some(through) = go_through(v, &s, nb, roulette) else {
            continue;
        };
        let delta = s.flags.is_delta();
        let origin = offset_origin(v.hit.p, v.reach, v.hit.ng, s.wi);
        let mis = if delta {
            (0.0, Nee::None)
        } else {
            (nb * s.pdf, Nee::Sets)
        };
        let ray = Ray::new(origin, s.wi, v.time);
        out.next
            .push(ray, v.slot, through, stream, ((v.hit.p, v.hit.n), mis));
        count_bounce(out.stats, s.flags);
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
    shadow_ray(v, bsdf, &ls, weigh, e * pmf, shadows);
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
/// thesis's penumbra model). Pushed to `shadows` unless it brings nothing.
fn shadow_ray(
    v: &Vertex<'_>,
    bsdf: &Bsdf,
    ls: &LightSample,
    weigh: impl Fn(f32) -> f32,
    n: f32,
    shadows: &mut Shadows,
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
    shadows
        .ray
        .push(Ray::new(origin, ls.target - origin, v.time));
    shadows.slot.push(v.slot);
    shadows.value.push(v.beta * f * ls.weight * (cos * w / n));
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
