//! The thesis's sets at a vertex of the distributed path tracer: a shadow
//! set toward every emitter and a set of BSDF samples, each going on as a
//! path, and the sets the reflection metric judges.

use super::vertex::{
    count_bounce, go_through, power_heuristic, sample_emitter, shadow_ray, Escape, Material, Nee,
    Paths, Shadows, Vertex, NO_SET,
};
use crate::accel::Hit;
use crate::bsdf::Bsdf;
use crate::emitter::{Emitter, LightSample, Reference};
use crate::integrator::metric::{Metric, RunningMean, ShadowTally};
use crate::integrator::shading::ShadingPoint;
use crate::integrator::stats::RayStats;
use crate::integrator::streams;
use crate::math::{Rgb, Vec3};
use crate::sampling::{Distribution, EffectSpec, Rng, SetPoint};
use crate::scene::Scene;

/// Where a vertex's work goes: its shadow rays, the paths it starts, the
/// ray counts, and a buffer for a set's points.
pub(super) struct Out<'a> {
    pub(super) shadows: &'a mut Shadows,
    pub(super) next: &'a mut Paths,
    pub(super) stats: &'a mut RayStats,
    pub(super) points: &'a mut Vec<Vec3>,
    pub(super) lights: &'a mut LightBuffers,
    pub(super) escape: Escape,
    /// With the reflection metric on, at a first vertex: the members its
    /// sets always trace (α, at least 2).
    pub(super) judge: Option<u32>,
    /// The samples of the wave, which judged sets' members add to.
    pub(super) radiance: &'a mut Vec<Rgb>,
    /// The sets the reflection metric judges.
    pub(super) pending: &'a mut Vec<PendingSet>,
}

/// A shadow set's emitter samples, the directions of those that give one,
/// and the BSDF toward each: kept between vertices.
#[derive(Default)]
pub(super) struct LightBuffers {
    samples: Vec<Option<LightSample>>,
    dirs: Vec<Vec3>,
    values: Vec<Rgb>,
}

/// A vertex that draws the thesis's sets (`distributed`): a set of shadow
/// rays toward every emitter, of its shadow set in `shadow` (by emitter,
/// see [`RaySets::shadow`](crate::integrator::RaySets::shadow)), and one
/// set of BSDF samples whose count and
/// distribution are the largest set the material's lobes ask for (the
/// render's reflection set for a material without sets), each sample
/// starting a path of its own with the set's share of the throughput. The
/// two are weighed by the power heuristic on density times count. `path`
/// is the vertex's stream; `rr` says whether the paths it starts face
/// Russian roulette.
#[inline]
pub(super) fn thesis_sets(
    (scene, shadow, metric): (&Scene, &[EffectSpec], Option<Metric>),
    v: &Vertex<'_>,
    (bsdf, material): (&Bsdf, &Material),
    (path, rr): (Rng, bool),
    out: &mut Out<'_>,
) {
    let table = &scene.settings.points;
    let set = material.set;
    let nb = set.rays as f32;
    if material.smooth {
        for (j, (emitter, set)) in scene.emitters.iter().zip(shadow).enumerate() {
            let (n, d) = (set.rays, set.distribution);
            // The shadow metric's tally, for the sets it judges.
            let tally = ShadowTally::of(metric, n);
            let k = tally.map(|t| t.k);
            let id = match tally {
                Some(tally) => {
                    out.shadows.sets.push(tally);
                    out.shadows.sets.len() as u32 - 1
                }
                None => NO_SET,
            };
            let mut rng = path.derive(streams::shadow(j as u64));
            d.generate_in(table, n as usize, 1.0, &mut rng, out.points);
            // The set's samples and the BSDF toward them, each a batch.
            let at = Reference::new(v.hit.p, v.hit.time);
            set_light_samples(emitter, at, (out.points, d), out.escape, out.lights);
            let LightBuffers {
                samples,
                dirs,
                values,
            } = &mut *out.lights;
            dirs.clear();
            dirs.extend(samples.iter().flatten().map(|ls| ls.dir));
            bsdf.eval_all(v.hit, v.wo, dirs, values);
            let mut f = values.iter();
            for (m, ls) in samples.iter().enumerate() {
                let Some(ls) = ls else {
                    continue;
                };
                let f = *f.next().expect("a value per sample");
                let ns = n as f32;
                let weigh = |pdf_b: f32| power_heuristic(ns * ls.pdf, nb * pdf_b);
                let rays = match k {
                    Some(k) if m as u32 >= k => &mut out.shadows.later,
                    _ => &mut out.shadows.now,
                };
                shadow_ray(v, bsdf, (ls, f), weigh, ns, (rays, id));
            }
        }
    }
    let mut rng = path.derive(streams::BSDF_SET);
    set.distribution
        .generate_in(table, set.rays as usize, 1.0, &mut rng, out.points);
    let first = out.judge.filter(|&a| set.rays > a);
    if let Some(alpha) = first {
        // The reflection metric judges the set: its first α members, each
        // adding to a sample of its own, and the rest one at a time
        // (see `Wavefront::judge_sets`).
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
            at: v.at,
            wo: v.wo,
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

/// The samples of `emitter` seen from `at` for the points `points` of
/// distribution `d` (a shadow set), drawn as one batch into `lights`.
#[inline]
pub(super) fn set_light_samples<'b>(
    emitter: &Emitter,
    at: Reference,
    (points, d): (&[Vec3], Distribution),
    escape: Escape,
    lights: &'b mut LightBuffers,
) -> &'b [Option<LightSample>] {
    let samples = &mut lights.samples;
    samples.clear();
    if emitter.is_infinite() {
        let each = |&point: &Vec3| sample_emitter(emitter, at, (point, d), escape);
        samples.extend(points.iter().map(each));
    } else {
        emitter.sample(|_| at, points, d, samples);
    }
    samples
}

/// A member of a vertex's set of BSDF samples: the `k`th of `set`, at
/// `point`, adding to sample `slot` with `1 / share` of the throughput.
#[derive(Clone, Copy)]
pub(super) struct Member {
    pub(super) k: u32,
    pub(super) point: Vec3,
    pub(super) set: EffectSpec,
    pub(super) slot: u32,
    pub(super) share: f32,
}

/// Starts the path of member `m` of the BSDF set at `v` (whose stream is
/// `path`; `rr`: the path faces Russian roulette), unless its sample has
/// no density, carries nothing or roulette ends it.
#[inline]
pub(super) fn set_member(
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
    let roulette = rr.then(|| stream.derive(streams::ROULETTE).next_f32());
    let Some(through) = go_through(v, &s, m.share, roulette) else {
        return;
    };
    let delta = s.flags.is_delta();
    // The emission met is weighed against the whole set's density.
    let mis = if delta {
        (0.0, Nee::None)
    } else {
        (n as f32 * s.pdf, Nee::Sets)
    };
    let ray = v.at.spawn_ray(s.wi);
    next.push(ray, m.slot, through, stream, ((v.hit.p, v.hit.n), mis));
    count_bounce(stats, s.flags);
}

/// A set of BSDF samples the reflection metric judges, at a first vertex:
/// the vertex, its set, the samples `acc..acc + batch` its latest members
/// add to, and the running mean of the members traced so far.
pub(super) struct PendingSet {
    pub(super) hit: Hit,
    pub(super) at: ShadingPoint,
    pub(super) wo: Vec3,
    pub(super) beta: Rgb,
    pub(super) eta2: f32,
    /// The sample the set's value goes to.
    pub(super) slot: u32,
    pub(super) path: Rng,
    pub(super) rr: bool,
    pub(super) material: u32,
    pub(super) set: EffectSpec,
    pub(super) acc: u32,
    pub(super) batch: u32,
    pub(super) mean: RunningMean,
}

impl PendingSet {
    #[inline]
    pub(super) fn vertex(&self) -> Vertex<'_> {
        Vertex {
            hit: &self.hit,
            at: self.at,
            wo: self.wo,
            beta: self.beta,
            eta2: self.eta2,
            slot: self.slot,
        }
    }
}
