//! `distributed` through participating media: the thesis's sets at the
//! vertices of volumetric paths (see the [module docs](super)).
//!
//! A surface vertex below `sets_depth` draws its sets as the path tracer
//! draws them ([`thesis_sets`]); its shadow rays and the paths it starts
//! then take their media: each shadow ray the medium on its side of the
//! surface, tracked through media and pass-throughs to its emitter, each
//! path the medium it enters. A medium vertex (a real collision) below
//! `sets_depth` draws a shadow set toward every emitter, weighed by the
//! phase function, and a set of phase-function directions of the render's
//! reflection set, each going on as a path of its own with the set's
//! share of the throughput; light and phase samples are weighed by the
//! power heuristic on density times count, as at a surface.

use super::sets::{set_light_samples, thesis_sets, LightBuffers, Out, PendingSet};
use super::vertex::{
    power_heuristic, target_medium, Escape, Material, MediumPending, MediumVertex, Nee, Paths,
    ShadowRays, Shadows, Vertex, VolPaths, VolShadows, VolState, NO_SET,
};
use super::wavefront::Wavefront;
use crate::bsdf::Bsdf;
use crate::emitter::Reference;
use crate::integrator::metric::{Metric, RunningMean, ShadowTally};
use crate::integrator::stats::RayStats;
use crate::integrator::streams;
use crate::math::{Ray, Rgb, Vec3};
use crate::medium::Medium;
use crate::sampling::{EffectSpec, Rng};
use crate::scene::Scene;

/// Where a volumetric vertex's sets go: the paths they start, their
/// shadow rays (those traced first, and the members the shadow metric may
/// spare), the sets' tallies, and the buffers their points and emitter
/// samples are drawn into.
pub(super) struct VolOut<'a> {
    pub(super) next: &'a mut VolPaths,
    pub(super) shadows: &'a mut VolShadows,
    pub(super) later: &'a mut VolShadows,
    pub(super) tallies: &'a mut Vec<ShadowTally>,
    pub(super) stats: &'a mut RayStats,
    pub(super) points: &'a mut Vec<Vec3>,
    pub(super) lights: &'a mut LightBuffers,
    pub(super) escape: Escape,
    /// With the reflection metric on, at a first vertex: the members its
    /// set of directions always traces (α, at least 2).
    pub(super) judge: Option<u32>,
    /// The samples of the wave, which judged sets' members add to.
    pub(super) radiance: &'a mut Vec<Rgb>,
    /// The judged sets at surfaces, the state of their paths beside each,
    /// and the judged sets at medium collisions.
    pub(super) pending: &'a mut Vec<PendingSet>,
    pub(super) pending_state: &'a mut Vec<(VolState, Option<[u32; 2]>)>,
    pub(super) medium_pending: &'a mut Vec<MediumPending>,
}

/// What a volumetric vertex drawing sets reads of the render: the scene,
/// each emitter's shadow set, and the metric.
#[derive(Clone, Copy)]
pub(super) struct SetsContext<'s> {
    pub(super) scene: &'s Scene,
    pub(super) shadow: &'s [EffectSpec],
    pub(super) metric: Option<Metric>,
}

/// The thesis's sets at the surface vertex `v` of a volumetric path in
/// state `st` (its stream `rng`) on an object bounding `media`, drawn by
/// [`thesis_sets`] into `scratch` and then given their media.
pub(super) fn surface_sets(
    cx: SetsContext<'_>,
    v: &Vertex<'_>,
    (bsdf, material): (&Bsdf, &Material),
    (rng, st, media): (Rng, VolState, Option<&[u32; 2]>),
    (scratch, scratch_shadows): (&mut Paths, &mut Shadows),
    out: &mut VolOut<'_>,
) {
    scratch.clear();
    scratch_shadows.clear();
    let judged = out.pending.len();
    let mut o = Out {
        shadows: scratch_shadows,
        next: scratch,
        stats: out.stats,
        points: out.points,
        lights: out.lights,
        escape: out.escape,
        judge: out.judge,
        radiance: out.radiance,
        pending: out.pending,
    };
    // Roulette is the volumetric path's own, played at its next step.
    let sets = (cx.scene, cx.shadow, cx.metric);
    thesis_sets(sets, v, (bsdf, material), (rng, false), &mut o);
    if out.pending.len() > judged {
        out.pending_state.push((st, media.copied()));
    }
    let ng = v.hit.ng;
    for i in 0..scratch.len() {
        take_member(scratch, i, (st, media, ng), out.next);
    }
    let first = out.tallies.len() as u32;
    out.tallies.extend_from_slice(&scratch_shadows.sets);
    let tracking = rng.derive(streams::tracking(st.step));
    let moved = |from: &ShadowRays, to: &mut VolShadows, base: usize| {
        for k in 0..from.ray.len() {
            let ray = from.ray[k];
            let set = match from.set[k] {
                NO_SET => NO_SET,
                s => first + s,
            };
            let medium = target_medium(media, ng, ray.dir, st.medium);
            let stream = tracking.derive((base + k) as u64);
            to.push(ray, (from.slot[k], from.value[k]), (medium, stream), set);
        }
    };
    let now = &scratch_shadows.now;
    moved(now, out.shadows, 0);
    moved(&scratch_shadows.later, out.later, now.ray.len());
}

/// The path `i` of those a surface vertex's set started (`members`, in
/// the path tracer's buffers), pushed to `next` as a volumetric path going
/// on from the state `st` of the path at the vertex, in the medium it
/// enters across the surface of geometric normal `ng` bounding `media`.
fn take_member(
    members: &Paths,
    i: usize,
    (st, media, ng): (VolState, Option<&[u32; 2]>, Vec3),
    next: &mut VolPaths,
) {
    let ray = members.ray[i];
    let (pdf, nee) = members.mis[i];
    let state = VolState {
        medium: target_medium(media, ng, ray.dir, st.medium),
        depth: st.depth + 1,
        direct: nee == Nee::None,
        sets: nee == Nee::Sets,
        eta: members.eta2[i].sqrt(),
        last: members.from[i],
        last_pdf: pdf,
        skip: 0.0,
        ..st
    };
    next.push(ray, members.slot[i], members.beta[i], members.rng[i], state);
}

/// The thesis's sets at a real collision at `p` in `medium` of a path
/// arriving from `wo` with throughput `beta` (its scattering albedo
/// applied), in state `st` with stream `rng`, adding to sample `slot`.
pub(super) fn medium_sets(
    cx: SetsContext<'_>,
    (p, wo, time): (Vec3, Vec3, f32),
    (medium_index, medium): (u32, &Medium),
    (beta, slot, rng, st): (Rgb, u32, Rng, VolState),
    out: &mut VolOut<'_>,
) {
    let scene = cx.scene;
    let table = &scene.settings.points;
    let set = scene.settings.reflection;
    let nb = set.rays as f32;
    let phase = &medium.phase;
    let lit = medium.sample_emitters && !scene.emitters.is_empty();
    if lit {
        let at = Reference::new(p, time);
        let tracking = rng.derive(streams::tracking(st.step));
        let mut index = 0u64;
        for (j, (emitter, shadow)) in scene.emitters.iter().zip(cx.shadow).enumerate() {
            let (n, d) = (shadow.rays, shadow.distribution);
            let tally = ShadowTally::of(cx.metric, n);
            let k = tally.map(|t| t.k);
            let id = match tally {
                Some(t) => {
                    out.tallies.push(t);
                    out.tallies.len() as u32 - 1
                }
                None => NO_SET,
            };
            let mut r = rng.derive(streams::shadow(j as u64));
            d.generate_in(table, n as usize, 1.0, &mut r, out.points);
            let samples = set_light_samples(emitter, at, (out.points, d), out.escape, out.lights);
            let ns = n as f32;
            for (m, ls) in samples.iter().enumerate() {
                let Some(ls) = ls else {
                    continue;
                };
                let f = phase.eval(wo, ls.dir);
                if f <= 0.0 {
                    continue;
                }
                let w = if ls.pdf > 0.0 {
                    power_heuristic(ns * ls.pdf, nb * f)
                } else {
                    1.0
                };
                let value = beta * ls.weight * (f * w / ns);
                if value.max_element() <= 0.0 {
                    continue;
                }
                let rays = match k {
                    Some(k) if m as u32 >= k => &mut *out.later,
                    _ => &mut *out.shadows,
                };
                let ray = Ray::new(p, ls.target - p, time);
                rays.push(
                    ray,
                    (slot, value),
                    (medium_index, tracking.derive(index)),
                    id,
                );
                index += 1;
            }
        }
    }
    // The set of phase-function directions, each a path of its own.
    let mut r = rng.derive(streams::BSDF_SET);
    set.distribution
        .generate_in(table, set.rays as usize, 1.0, &mut r, out.points);
    let vertex = MediumVertex {
        p,
        wo,
        time,
        medium: medium_index,
        beta,
        slot,
        rng,
        st: VolState {
            direct: !lit,
            sets: lit,
            ..st
        },
        set,
    };
    if let Some(alpha) = out.judge.filter(|&a| set.rays > a) {
        // The reflection metric judges the set: its first α members, each
        // adding to a sample of its own, and the rest one at a time (see
        // `Wavefront::volume_judge`).
        let acc = out.radiance.len() as u32;
        out.radiance
            .resize(out.radiance.len() + alpha as usize, Rgb::ZERO);
        for k in 0..alpha {
            let point = out.points[k as usize];
            vertex.member(phase, (k, point), (acc + k, 1.0), out.next, out.stats);
        }
        out.medium_pending.push(MediumPending {
            vertex,
            acc,
            batch: alpha,
            mean: RunningMean::default(),
        });
        return;
    }
    for (k, &point) in out.points.iter().enumerate() {
        vertex.member(phase, (k as u32, point), (slot, nb), out.next, out.stats);
    }
}

impl Wavefront<'_> {
    /// Judges the sets pending at the wave's first vertices by the
    /// reflection metric, as [`judge_sets`](Wavefront::judge_sets) judges
    /// a surface's, and starts the next member of each set not yet judged
    /// in `self.volume.paths`. True if any set goes on.
    pub(super) fn volume_judge(&mut self) -> bool {
        let Some(metric) = self.settings.metric else {
            return false;
        };
        // The surfaces' sets: their members' paths from the path tracer's
        // buffers, each going on from its vertex's state.
        let mut going = self.judge_sets();
        let scene = self.scene;
        let vol = &mut self.volume;
        vol.paths.clear();
        let mut states = self.pending.iter().zip(&vol.pending_state);
        for i in 0..self.paths.len() {
            let slot = self.paths.slot[i];
            let (p, (st, media)) = states
                .find(|(p, _)| p.batch > 0 && p.acc == slot)
                .expect("a member's set");
            take_member(
                &self.paths,
                i,
                (*st, media.as_ref(), p.hit.ng),
                &mut vol.paths,
            );
        }
        // The media's sets.
        let table = &scene.settings.points;
        for m in &mut vol.medium_pending {
            if m.batch == 0 {
                continue;
            }
            let v = m.vertex;
            let n = v.set.rays;
            let mut stop = false;
            for a in m.acc..m.acc + m.batch {
                stop = m.mean.push(self.radiance[a as usize], Some(&metric), n);
            }
            let traced = m.mean.count();
            if stop || traced == n {
                self.radiance[v.slot as usize] += m.mean.mean();
                self.stats.media.saved += u64::from(n - traced);
                m.batch = 0;
                continue;
            }
            let mut rng = v.rng.derive(streams::BSDF_SET);
            let d = v.set.distribution;
            d.generate_in(table, n as usize, 1.0, &mut rng, &mut self.points);
            let acc = self.radiance.len() as u32;
            self.radiance.push(Rgb::ZERO);
            let phase = &scene.media[v.medium as usize].phase;
            let point = self.points[traced as usize];
            v.member(
                phase,
                (traced, point),
                (acc, 1.0),
                &mut vol.paths,
                &mut self.stats,
            );
            (m.acc, m.batch) = (acc, 1);
            going = true;
        }
        going
    }
}
