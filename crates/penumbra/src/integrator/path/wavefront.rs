//! The path tracer's wavefront: the paths of whole rows of a tile in
//! structure-of-arrays buffers, advanced one stage at a time (see the
//! [module docs](super)).

use std::ops::Range;

use crate::accel::{Hit, PacketScratch};
use crate::integrator::film::FilmTile;
use crate::integrator::interface::{BadSample, TileJob};
use crate::integrator::stats::RayStats;
use crate::integrator::whitted::{guard, primary_rays};
use crate::math::{offset_origin, reach, Ray, Rgb, Vec2, Vec3};
use crate::sampling::{Distribution, Rng, SetPoint};
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
    /// The path's stream (its primary sample's).
    rng: Vec<Rng>,
    /// The vertex the ray left from.
    from: Vec<Vec3>,
    /// The solid-angle density the BSDF drew the ray with; 0 after a delta
    /// lobe or from the camera (the emission met then counts whole).
    pdf: Vec<f32>,
}

impl Paths {
    fn clear(&mut self) {
        self.ray.clear();
        self.slot.clear();
        self.beta.clear();
        self.rng.clear();
        self.from.clear();
        self.pdf.clear();
    }

    fn len(&self) -> usize {
        self.ray.len()
    }

    fn push(&mut self, ray: Ray, slot: u32, beta: Rgb, rng: Rng, (from, pdf): (Vec3, f32)) {
        self.ray.push(ray);
        self.slot.push(slot);
        self.beta.push(beta);
        self.rng.push(rng);
        self.from.push(from);
        self.pdf.push(pdf);
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
    /// The emitters next-event estimation chooses among (those with a
    /// position: not at infinity).
    lights: Vec<u32>,
    /// Per emitter, whether it is one of `lights`.
    sampled: Vec<bool>,
    /// The emitters at infinity, which rays that hit nothing see.
    far: Vec<u32>,
    /// Per material, the transparency shadow rays see: none.
    opaque: Vec<f32>,
    paths: Paths,
    next: Paths,
    hits: Vec<Option<Hit>>,
    packet: PacketScratch,
    shadows: Shadows,
    /// Per sample of the wave, the radiance its path gathered.
    radiance: Vec<Rgb>,
}

impl<'s> Wavefront<'s> {
    pub(super) fn new(scene: &'s Scene, settings: PathSettings) -> Wavefront<'s> {
        let (far, lights): (Vec<u32>, Vec<u32>) = (0..scene.emitters.len() as u32)
            .partition(|&e| scene.emitters[e as usize].is_infinite());
        let sampled = scene.emitters.iter().map(|e| !e.is_infinite()).collect();
        Wavefront {
            scene,
            settings,
            stats: RayStats::default(),
            lights,
            sampled,
            far,
            opaque: vec![0.0; scene.bsdfs.len()],
            paths: Paths::default(),
            next: Paths::default(),
            hits: Vec::new(),
            packet: PacketScratch::default(),
            shadows: Shadows::default(),
            radiance: Vec::new(),
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
            let mut values = self.radiance.iter();
            for y in y0..y1 {
                for x in xs.clone() {
                    let k = film.index(x, y);
                    for i in samples.clone() {
                        let l = *values.next().expect("a value per sample");
                        film.add(k, guard(l, x, y, i as usize, bad), 1.0);
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
        for y in ys {
            primary_rays(
                self.scene,
                (xs.clone(), y),
                keep.clone(),
                &mut paths.ray,
                &mut paths.rng,
            );
        }
        let n = paths.ray.len();
        paths.slot.extend(0..n as u32);
        paths.beta.resize(n, Rgb::ONE);
        paths.from.extend(paths.ray.iter().map(|r| r.origin));
        paths.pdf.resize(n, 0.0);
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
            lights,
            sampled,
            far,
            paths,
            next,
            hits,
            shadows,
            radiance,
            ..
        } = self;
        next.clear();
        shadows.ray.clear();
        shadows.slot.clear();
        shadows.value.clear();
        let seen = !(settings.hide_emitters && depth == 0);
        let go_on = depth.saturating_add(1) < max_depth;
        for (i, hit) in hits.iter().enumerate() {
            let (ray, slot, beta) = (&paths.ray[i], paths.slot[i], paths.beta[i]);
            let acc = &mut radiance[slot as usize];
            let Some(hit) = hit else {
                if seen {
                    for &e in far.iter() {
                        *acc += beta * scene.emitters[e as usize].eval_miss(ray.dir);
                    }
                }
                continue;
            };
            if let (Some(e), true) = (hit.emitter, seen) {
                let prev = (paths.from[i], paths.pdf[i]);
                let w = emission_weight(scene, (sampled, lights.len()), e, prev, hit);
                if w > 0.0 {
                    let le = scene.emitters[e as usize].eval(hit.ng, ray.dir);
                    *acc += beta * le * w;
                }
            }
            if !go_on {
                continue;
            }
            let bsdf = &scene.bsdfs[hit.material as usize];
            let wo = -ray.dir.normalize();
            let reach = reach(hit.p, ray.origin);
            let mut rng = paths.rng[i].derive(u64::from(depth));
            let mut u2 = || Vec2::new(rng.next_f32(), rng.next_f32());
            // Next-event estimation on the smooth lobes.
            let choice = u2();
            let point = u2();
            if bsdf.lobes().any_smooth() && !lights.is_empty() {
                let k = ((choice.x * lights.len() as f32) as usize).min(lights.len() - 1);
                let emitter = &scene.emitters[lights[k] as usize];
                let p = SetPoint::uniform(point).native();
                if let Some(ls) = emitter.sample_one(hit.p, p, Distribution::Jitter) {
                    let wi = ls.dir;
                    let f = bsdf.eval(hit, wo, wi);
                    let cos = hit.n.dot(wi).abs();
                    if f != Rgb::ZERO && cos > 0.0 {
                        let choose = lights.len() as f32;
                        let pdf_light = ls.pdf / choose;
                        let w = if ls.pdf > 0.0 {
                            power_heuristic(pdf_light, bsdf.pdf(hit, wo, wi))
                        } else {
                            1.0
                        };
                        let origin = offset_origin(hit.p, reach, hit.ng, wi);
                        shadows
                            .ray
                            .push(Ray::new(origin, ls.target - origin, ray.time));
                        shadows.slot.push(slot);
                        shadows
                            .value
                            .push(beta * f * ls.weight * (cos * choose * w));
                    }
                }
            }
            // The next direction.
            let u = SetPoint::uniform(u2());
            let roulette = rng.next_f32();
            let Some(b) = bsdf.sample(hit, wo, None, u) else {
                continue;
            };
            let delta = b.flags.is_delta();
            if !delta && (b.pdf <= 0.0 || b.pdf.is_nan()) {
                continue;
            }
            let mut beta = beta * b.weight;
            if depth + 1 >= settings.rr_depth {
                let q = beta.max_element().min(RR_MAX);
                if roulette >= q || q.is_nan() {
                    continue;
                }
                beta /= q;
            }
            if beta.max_element() <= 0.0 {
                continue;
            }
            let origin = offset_origin(hit.p, reach, hit.ng, b.wi);
            let pdf = if delta { 0.0 } else { b.pdf };
            next.push(
                Ray::new(origin, b.wi, ray.time),
                slot,
                beta,
                paths.rng[i],
                (hit.p, pdf),
            );
            if b.flags.contains(crate::bsdf::BsdfFlags::TRANSMISSION) {
                stats.refraction += 1;
            } else {
                stats.reflection += 1;
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

/// The weight of the emission of emitter `e` that a path meets at `hit`,
/// having left `from` with BSDF density `pdf` (0: from the camera or a
/// delta lobe, which next-event estimation could not have drawn): the power
/// heuristic against the emitter's own density, when next-event estimation
/// samples it; 0 for an emitter that it samples without a density (the
/// thesis's penumbra model), whose light its shadow rays alone bring.
fn emission_weight(
    scene: &Scene,
    (sampled, lights): (&[bool], usize),
    e: u32,
    (from, pdf): (Vec3, f32),
    hit: &Hit,
) -> f32 {
    if pdf == 0.0 || !sampled[e as usize] {
        return 1.0;
    }
    let emitter = &scene.emitters[e as usize];
    let pdf_light = emitter.pdf(from, hit.p, hit.ng) / lights as f32;
    if pdf_light > 0.0 {
        power_heuristic(pdf, pdf_light)
    } else {
        0.0
    }
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
