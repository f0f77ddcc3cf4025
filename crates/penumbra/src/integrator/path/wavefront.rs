//! The path tracer's wavefront: the paths of whole rows of a tile in
//! structure-of-arrays buffers, advanced one stage at a time (see the
//! [module docs](super)).

use std::ops::Range;

use super::PathSettings;
use crate::accel::{Hits, Object, PacketScratch};
use crate::emitter::choice::LightSampler;
use crate::emitter::Reference;
use crate::integrator::clip::clip_camera_hits;
use crate::integrator::film::FilmTile;
use crate::integrator::interface::{BadSample, TileJob};
use crate::integrator::ray_sets::RaySets;
use crate::integrator::shading::ShadingPoint;
use crate::integrator::stats::{RayStats, StageBatches};
use crate::integrator::streams;
use crate::integrator::whitted::{guard, primary_rays};
use crate::math::{Rgb, Vec2, Vec3};
use crate::sampling::{EffectSpec, SetPoint};
use crate::scene::Scene;

use super::sets::{set_member, thesis_sets, LightBuffers, Member, Out, PendingSet};
use super::vertex::{
    count_bounce, count_saved, emission_weight, go_through, light_sample, Escape, Material, Nee,
    Paths, Shadows, Vertex, Volume,
};

/// The most paths a wave holds, unless one row of a tile's samples holds
/// more (a wave is whole rows).
pub const WAVE: usize = 8192;

/// Where a shadow ray ends, as a fraction of the way to its target: short
/// of the emitter's own surface.
const SHADOW_END: f32 = 1.0 - 1e-4;

/// A worker's wavefront: its buffers, kept from wave to wave.
pub(super) struct Wavefront<'s> {
    pub(super) scene: &'s Scene,
    pub(super) settings: PathSettings,
    /// How next-event estimation chooses its emitter.
    pub(super) lights: &'s LightSampler,
    /// The shadow set of each emitter, for the vertices drawing the
    /// thesis's sets.
    pub(super) shadow_sets: &'s [EffectSpec],
    pub(super) stats: RayStats,
    /// The calls of each stage and the items they took.
    pub(super) batches: StageBatches,
    /// Per material, what its vertices need of its lobes (found once).
    pub(super) materials: Vec<Material>,
    /// How many paths, or shadow rays, a camera path may become at one
    /// bounce (see [`growth`]).
    growth: usize,
    /// How to reach the emitters at infinity from a point (see [`Escape`]).
    pub(super) escape: Escape,
    pub(super) paths: Paths,
    next: Paths,
    /// The hits of the bounce's rays, compact: a vertex's record is made
    /// when it is shaded.
    pub(super) hits: Hits,
    pub(super) packet: PacketScratch,
    /// The paths of a bounce grouped for shading: those that met nothing,
    /// then those on each material in turn (see [`group_by_material`]).
    order: Vec<u32>,
    /// Where each group of `order` starts, and its end.
    groups: Vec<u32>,
    shadows: Shadows,
    /// Whether each shadow ray of the bounce is blocked.
    blocked: Vec<bool>,
    /// Per sample of the wave, the radiance its path gathered.
    pub(super) radiance: Vec<Rgb>,
    /// Per sample of the wave, its pixel-filter weight.
    weights: Vec<f32>,
    /// Each primary sample's film offset from its pixel's centre.
    offsets: Vec<Vec2>,
    /// The points of a set being drawn.
    pub(super) points: Vec<Vec3>,
    /// A shadow set's emitter samples, their directions and the BSDF
    /// toward each.
    pub(super) set_lights: LightBuffers,
    /// The sets the reflection metric judges, of the wave's first vertices.
    pub(super) pending: Vec<PendingSet>,
    /// The buffers of volumetric paths (`volpath`).
    pub(super) volume: Volume,
}

impl<'s> Wavefront<'s> {
    pub(super) fn new(
        scene: &'s Scene,
        settings: PathSettings,
        lights: &'s LightSampler,
        sets: &'s RaySets,
    ) -> Wavefront<'s> {
        let materials: Vec<Material> = scene
            .bsdfs
            .iter()
            .zip(&sets.lobes)
            .map(|(bsdf, lobes)| Material::of(bsdf, lobes, scene.settings.reflection))
            .collect();
        let growth = growth(
            &settings,
            &materials,
            &sets.shadow,
            scene.settings.reflection,
        );
        let b = scene.world.bounds();
        let escape = Escape {
            center: 0.5 * (b.min + b.max),
            radius: 0.5 * (b.max - b.min).length(),
        };
        Wavefront {
            scene,
            settings,
            lights,
            shadow_sets: &sets.shadow,
            stats: RayStats::default(),
            batches: StageBatches::default(),
            materials,
            growth,
            escape,
            paths: Paths::default(),
            next: Paths::default(),
            hits: Hits::default(),
            packet: PacketScratch::default(),
            order: Vec::new(),
            groups: Vec::new(),
            shadows: Shadows::default(),
            blocked: Vec::new(),
            radiance: Vec::new(),
            weights: Vec::new(),
            offsets: Vec::new(),
            points: Vec::new(),
            set_lights: LightBuffers::default(),
            pending: Vec::new(),
            volume: Volume::default(),
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
        let (xs, samples) = (&tile.xs, &tile.samples);
        let m = samples.len();
        if m == 0 {
            return true;
        }
        // A wave's rows hold about `WAVE` paths at its widest bounce.
        let rows = (WAVE / (xs.len() * m).saturating_mul(self.growth)).max(1) as u32;
        tile.rows(rows, |ys| {
            self.wave(xs, ys.clone(), samples);
            let mut values = self.radiance.iter().zip(&self.weights).zip(&self.offsets);
            for y in ys {
                for x in xs.clone() {
                    let k = film.index(x, y);
                    for i in samples.clone() {
                        let ((&l, &w), &o) = values.next().expect("a value per sample");
                        film.add(k, guard(l, x, y, i as usize, bad), w, o);
                    }
                }
            }
        })
    }

    /// Traces samples `samples` of pixels `xs × ys` to their end, leaving
    /// their radiance in `self.radiance`, pixel by pixel.
    fn wave(&mut self, xs: &Range<u32>, ys: Range<u32>, samples: &Range<u32>) {
        let keep = samples.start as usize..samples.end as usize;
        let paths = &mut self.paths;
        paths.clear();
        self.weights.clear();
        self.offsets.clear();
        let ordered = self.settings.metric.is_some_and(|m| m.pixels);
        for y in ys {
            primary_rays(
                (self.scene, ordered),
                (xs.clone(), y),
                keep.clone(),
                &mut paths.ray,
                &mut paths.rng,
                (&mut self.weights, &mut self.offsets),
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
        if self.settings.volumetric {
            self.volume_wave();
            self.radiance.truncate(n);
            return;
        }
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
                if depth == 0 {
                    clip_camera_hits(scene, &self.paths.ray, &mut self.hits);
                }
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
    pub(super) fn judge_sets(&mut self) -> bool {
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
            let mut rng = p.path.derive(streams::BSDF_SET);
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
        let (scene, shadow_sets) = (self.scene, self.shadow_sets);
        let Wavefront {
            settings,
            lights: chooser,
            stats,
            materials,
            escape,
            paths,
            next,
            hits,
            order,
            groups,
            shadows,
            radiance,
            points,
            set_lights,
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
        group_by_material(hits, &scene.world.objects, scene.bsdfs.len(), order, groups);
        for g in groups.windows(2).filter(|g| g[1] > g[0]) {
            batches.shading.add((g[1] - g[0]) as usize);
        }
        for &i in order.iter() {
            let i = i as usize;
            let (ray, slot, beta) = (&paths.ray[i], paths.slot[i], paths.beta[i]);
            let acc = &mut radiance[slot as usize];
            let prev = paths.mis[i];
            let Some(found) = hits.get(i) else {
                if seen {
                    for &e in scene.far.iter() {
                        let emitter = &scene.emitters[e as usize];
                        let (from, from_n) = paths.from[i];
                        let choice = || chooser.pmf(from, from_n, e);
                        let w = emission_weight(shadow_sets[e as usize], prev, choice, || {
                            emitter.pdf_direction(ray.dir)
                        });
                        *acc += beta * emitter.eval_miss(ray.dir) * w;
                    }
                }
                continue;
            };
            // The record, only for emission met or a path that goes on.
            let emits = scene.world.objects[found.object as usize].emitter.is_some();
            if !(go_on || emits && seen) {
                continue;
            }
            let hit = &scene.world.surface(ray, found);
            if let (Some(e), true) = (hit.emitter, seen) {
                let emitter = &scene.emitters[e as usize];
                let (from, from_n) = paths.from[i];
                let choice = || chooser.pmf(from, from_n, e);
                let density = || emitter.pdf(Reference::new(from, ray.time), hit.p, hit.ng);
                let w = emission_weight(shadow_sets[e as usize], prev, choice, density);
                if w > 0.0 {
                    let le = scene.emitters[e as usize].eval(hit.ng, hit.uv, ray.dir);
                    *acc += beta * le * w;
                }
            }
            if !go_on {
                continue;
            }
            let bsdf = &scene.bsdfs[hit.material as usize];
            let v = Vertex {
                hit,
                at: ShadingPoint::new(ray, hit.p, hit.ng),
                wo: -ray.dir.normalize(),
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
                    lights: &mut *set_lights,
                    escape: *escape,
                    judge: judge.map(|m| m.min_rays.max(2)),
                    radiance: &mut *radiance,
                    pending: &mut *pending,
                };
                let rr = depth + 1 >= settings.rr_depth;
                let m = &materials[hit.material as usize];
                thesis_sets(
                    (scene, shadow_sets, settings.metric),
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
                .bounce(paths.rng[i].derive(streams::bounce(depth)));
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
                let mut point = SetPoint::uniform(u.point(d));
                let roulette = u.value(d + 1);
                if bsdf.wants_third() {
                    point = point.with_third(u.value(streams::LOBE_DIMENSION + d));
                }
                let Some(s) = bsdf.sample(hit, v.wo, None, point) else {
                    continue;
                };
                let rr = (depth + 1 >= settings.rr_depth).then_some(roulette);
                let Some(through) = go_through(&v, &s, b as f32, rr) else {
                    continue;
                };
                let delta = s.flags.is_delta();
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
                    v.at.spawn_ray(s.wi),
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
        let blocked = &mut self.blocked;
        if !now.ray.is_empty() {
            self.stats.shadow += now.ray.len() as u64;
            self.batches.occlusion.add(now.ray.len());
            world.occluded_all(&now.ray, (0.0, SHADOW_END), blocked);
            for (&set, &b) in now.set.iter().zip(blocked.iter()) {
                if let Some(t) = sets.get_mut(set as usize) {
                    t.count(!b);
                }
            }
            let rays = now.slot.iter().zip(&now.value).zip(&now.set);
            for (((&slot, &value), &set), &b) in rays.zip(blocked.iter()) {
                if b {
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
        world.occluded_all(rays, (0.0, SHADOW_END), blocked);
        for ((&slot, &value), &b) in later.slot.iter().zip(&later.value).zip(blocked.iter()) {
            if !b {
                self.radiance[slot as usize] += value;
            }
        }
    }
}

/// How many paths, or shadow rays, one camera path may become at one
/// bounce: the first vertex of a path tracer draws `bsdf_samples` and
/// `emitter_samples`; under `distributed` each of the first `sets_depth`
/// vertices draws a set of BSDF samples (its material's, or the render's
/// reflection set, which phase functions take too) and a shadow set toward
/// every emitter, and the sets of successive vertices multiply. A wave
/// takes fewer rows the more its paths grow, so that its buffers stay near
/// `WAVE` entries; the pixels do not depend on how rows are cut into
/// waves.
fn growth(
    settings: &PathSettings,
    materials: &[Material],
    shadow: &[EffectSpec],
    reflection: EffectSpec,
) -> usize {
    let first = settings.emitter_samples.max(settings.bsdf_samples).max(1) as usize;
    if settings.sets_depth == 0 {
        return first;
    }
    let set = materials
        .iter()
        .map(|m| m.set.rays)
        .fold(reflection.rays, u32::max);
    let shadows = shadow
        .iter()
        .map(|s| s.rays)
        .fold(0u32, u32::saturating_add);
    let each = set.max(shadows).max(1) as usize;
    each.saturating_pow(settings.sets_depth).max(first)
}

/// Groups the paths of a bounce for shading, keeping their order within a
/// group: `order` lists first those whose ray met nothing, then those on
/// material 0, 1, … of the `materials`; group `g` is
/// `order[groups[g]..groups[g + 1]]`. A path's contributions to its sample
/// keep their order whatever else shares the wave, so pixels do not depend
/// on how a frame is cut into tiles and waves.
fn group_by_material(
    hits: &Hits,
    objects: &[Object],
    materials: usize,
    order: &mut Vec<u32>,
    groups: &mut Vec<u32>,
) {
    let key = |i: usize| {
        hits.object(i)
            .map_or(0, |o| objects[o as usize].material as usize + 1)
    };
    group_by(hits.len(), key, materials + 1, order, groups);
}

/// Groups items `0..n` by `key` (below `keys`), keeping their order within
/// a group: group `k` is `order[groups[k]..groups[k + 1]]`.
fn group_by(
    n: usize,
    key: impl Fn(usize) -> usize,
    keys: usize,
    order: &mut Vec<u32>,
    groups: &mut Vec<u32>,
) {
    groups.clear();
    groups.resize(keys + 1, 0);
    for i in 0..n {
        groups[key(i) + 1] += 1;
    }
    for g in 1..groups.len() {
        groups[g] += groups[g - 1];
    }
    order.clear();
    order.resize(n, 0);
    // `groups[k]` serves as group k's cursor, ending at the start of
    // group k + 1; shifted back by one place after, with no buffer of
    // cursors allocated per bounce.
    for i in 0..n {
        let k = key(i);
        order[groups[k] as usize] = i as u32;
        groups[k] += 1;
    }
    groups.copy_within(..keys, 1);
    groups[0] = 0;
}

#[cfg(test)]
mod tests {
    use super::group_by;
    use crate::sampling::Rng;

    /// Grouping is a stable sort by key, and the groups' bounds are where
    /// each key's run starts and ends (empty groups included), with
    /// buffers reused from a larger grouping.
    #[test]
    fn grouping_is_a_stable_sort_by_key() {
        let mut r = Rng::new(5);
        let (mut order, mut groups) = (vec![7; 900], vec![3; 40]);
        for (n, keys) in [(0, 1), (1, 1), (300, 7), (1000, 3), (50, 30)] {
            let k: Vec<usize> = (0..n)
                .map(|_| (r.next_u32() as usize % keys) / 2 * 2)
                .collect();
            group_by(n, |i| k[i], keys, &mut order, &mut groups);
            let mut want: Vec<u32> = (0..n as u32).collect();
            want.sort_by_key(|&i| k[i as usize]);
            assert_eq!(order, want);
            assert_eq!(groups.len(), keys + 1);
            for key in 0..keys {
                let run = &order[groups[key] as usize..groups[key + 1] as usize];
                assert_eq!(run.len(), k.iter().filter(|&&x| x == key).count());
                assert!(run.iter().all(|&i| k[i as usize] == key));
            }
        }
    }
}
