//! Batches of rays: runs of rays from one point traced as packets, the
//! others together with their traversals interleaved.
//!
//! A batch's rays come in no known order. Consecutive rays that leave the
//! same point in nearly the same direction (a camera's, in pixel order)
//! form *runs* of up to `RUN` rays, traced as one packet, as
//! [`closest_hits`](TriangleBvh::closest_hits) traces a pixel's camera rays:
//! one interval box test per node for the run. On the harness's camera
//! rays the batch calls traced 1.3–1.5× as many rays per second with runs
//! as with interleaving alone. Finding runs costs an
//! incoherent batch one comparison per ray. The results do not
//! depend on which rays form runs: of triangles hit at exactly the same
//! distance, every path reports the lowest index.
//!
//! An incoherent ray spends most of its time waiting for memory: each step
//! of its traversal reads a node or a packet that the step before chose, and
//! the tree (3.6 MiB for the bunny) does not fit in the first- or
//! second-level cache. One ray alone gives the processor little to do
//! while it waits. Here up to `LANES` rays are in flight, each advanced by
//! one node or one leaf in turn, so the loads of different rays, which do
//! not depend on each other, overlap. Every ray follows exactly the path it
//! follows alone (the same node tests, children in the same order, the same
//! triangle tests); only the order in which different rays' work is done
//! changes. Interleaved or in a run, each ray gets what
//! [`closest_hit`](TriangleBvh::closest_hit) and
//! [`any_hit`](TriangleBvh::any_hit) give it, bit for bit.
//!
//! On the harness's million incoherent rays over the bunny, interleaving
//! alone traced 1.3× as many rays per second as one ray after another;
//! camera rays, whose nodes stay in the cache, gained nothing and lost
//! nothing (see `docs/performance.md`). Four, eight and sixteen rays in
//! flight measured alike; eight leaves room for slower memory.
//!
//! Interleaving alone leaves each load to be issued when its ray's turn
//! comes. So a step that chooses where its ray goes next also prefetches
//! it (through `safe_arch`'s safe wrapper of `prefetcht0`): the load then
//! has the other rays' steps to complete in. That adds about 7% on the
//! incoherent rays (medians of interleaved series 1.00–1.15×; camera rays,
//! already in the cache, lose up to 6%).

use super::super::bvh4::{any_of, Cursor, Frustum, Node4, RayPacket, Run, TraversalRay};
use super::{closest_in_pack, pack_any_hit, Pack, TriHit, TriangleBvh};
use crate::math::Ray;
use crate::simd;
use glam::{Vec3A, Vec4};
use std::ops::Range;

/// Rays in flight.
const LANES: usize = 8;

/// One ray's traversal between steps: where it is, what it deferred.
struct Walk {
    r: TraversalRay,
    /// Index of the ray in the batch.
    ray: usize,
    at: Cursor,
}

/// Most rays of a run traced as one packet. On the harness's camera rays
/// (800×600, in rows), packets of 8 consecutive rays took 0.68× the
/// instructions of interleaving them, of 16 0.74×, of 32 about as many.
pub(super) const RUN: usize = 8;
/// Fewest rays worth a packet (packets of 2 took as many instructions as
/// interleaving).
pub(super) const MIN_RUN: usize = 4;
/// Square of the cosine of 1°, the widest angle a run's rays may make with
/// its first: a packet enters every box any of its rays enters, so a wide
/// one tests each ray against leaves it never reaches (a glossy set of
/// 16 rays as a packet took 2.3× the instructions).
const RUN_COS2: f32 = 0.999_695;

impl TriangleBvh {
    /// The closest hit of every ray within `(tmin, tmax[i])`, into `out`
    /// (cleared first): for each ray what
    /// [`closest_hit`](Self::closest_hit) gives it, bit for bit, whatever
    /// the batch. Runs of consecutive rays from one point in nearly the same
    /// direction (camera rays in pixel order) are traced as packets, as
    /// [`closest_hits`](Self::closest_hits) traces them; the other rays
    /// with their traversals interleaved (see the module docs). For many
    /// rays: diffuse bounces, the Python batch call. `tmax` must hold a
    /// limit per ray.
    pub fn closest_hit_each(
        &self,
        rays: &[Ray],
        tmin: f32,
        tmax: &[f32],
        out: &mut Vec<Option<TriHit>>,
    ) {
        simd::active().run(
            #[inline(always)]
            || {
                assert!(tmax.len() >= rays.len(), "a tmax per ray");
                out.clear();
                out.resize(rays.len(), None);
                let mut scratch = RayPacket::default();
                for (at, frustum) in Stretches::new(self, rays) {
                    let Some(f) = frustum else {
                        let leaf = |i, p: &Pack, r: &TraversalRay, tmax: &mut f32| {
                            closest_in_pack(p, r, tmin, tmax, &mut out[i]);
                            false
                        };
                        self.interleave::<true>(
                            rays,
                            at,
                            tmin,
                            tmax,
                            leaf,
                            #[inline(always)]
                            |_, _| {},
                        );
                        continue;
                    };
                    let run = Run::new(&f, rays, tmin, tmax, &at);
                    self.closest_packet(&run, &mut scratch, &mut out[at]);
                }
            },
        )
    }

    /// [`any_hit`](Self::any_hit) for every ray within `(tmin, tmax[i])`,
    /// runs as packets and the rest interleaved, as
    /// [`closest_hit_each`](Self::closest_hit_each): `hit(i, id)` hears of
    /// the triangles ray `i` crosses, in the order `any_hit` reports them,
    /// until it returns true. `out[i]` (cleared first) says whether it did.
    pub fn any_hit_each(
        &self,
        rays: &[Ray],
        tmin: f32,
        tmax: &[f32],
        mut hit: impl FnMut(usize, u32) -> bool,
        out: &mut Vec<bool>,
    ) {
        simd::active().run(
            #[inline(always)]
            || {
                assert!(tmax.len() >= rays.len(), "a tmax per ray");
                out.clear();
                out.resize(rays.len(), false);
                let mut scratch = RayPacket::default();
                for (at, frustum) in Stretches::new(self, rays) {
                    let Some(f) = frustum else {
                        let leaf = |i, p: &Pack, r: &TraversalRay, tmax: &mut f32| {
                            pack_any_hit(p, r, tmin, *tmax, &mut |id| hit(i, id))
                        };
                        self.interleave::<false>(
                            rays,
                            at,
                            tmin,
                            tmax,
                            leaf,
                            #[inline(always)]
                            |i, stop| out[i] = stop,
                        );
                        continue;
                    };
                    let run = Run::new(&f, rays, tmin, tmax, &at);
                    let first = at.start;
                    let hit = |i, id| hit(first + i, id);
                    self.any_hit_packet(&run, &mut scratch, hit, &mut out[at]);
                }
            },
        )
    }

    /// Whether each ray crosses a triangle within `(tmin, tmax[i])`: what
    /// [`occluded`](Self::occluded) says of it, as
    /// [`any_hit_each`](Self::any_hit_each) traces it.
    pub fn occluded_each(&self, rays: &[Ray], tmin: f32, tmax: &[f32], out: &mut Vec<bool>) {
        self.any_hit_each(rays, tmin, tmax, |_, _| true, out);
    }

    /// Traces the rays `rays[at]` with up to `LANES` in flight, one step
    /// each in turn (`i` below indexes `rays` and `tmax`, not the range).
    /// `leaf(i, packet, ray, tmax)` tests a packet for ray `i` and
    /// returns true to stop that ray; `done(i, stopped)` hears when ray `i`
    /// is finished (rays with a non-finite origin or direction at once).
    #[inline(always)]
    fn interleave<const ORDERED: bool>(
        &self,
        rays: &[Ray],
        at: Range<usize>,
        tmin: f32,
        tmax: &[f32],
        mut leaf: impl FnMut(usize, &Pack, &TraversalRay, &mut f32) -> bool,
        mut done: impl FnMut(usize, bool),
    ) {
        let (rays, mut next) = (&rays[..at.end], at.start);
        // The next ray worth tracing, or `None` when all have started.
        let mut start = |done: &mut dyn FnMut(usize, bool)| {
            while let Some(ray) = rays.get(next) {
                let i = next;
                next += 1;
                if !self.tree.is_empty() && ray.origin.is_finite() && ray.dir.is_finite() {
                    return Some((i, TraversalRay::new(ray)));
                }
                done(i, false);
            }
            None
        };
        let mut walks: [Option<Walk>; LANES] = Default::default();
        let mut live = 0;
        for slot in &mut walks {
            let Some((ray, r)) = start(&mut done) else {
                break;
            };
            let at = Cursor::new(tmax[ray]);
            *slot = Some(Walk { r, ray, at });
            live += 1;
        }
        let tmin4 = Vec4::splat(tmin);
        while live > 0 {
            for slot in &mut walks {
                let Some(w) = slot else {
                    continue;
                };
                let Some(stopped) = self.step::<ORDERED>(w, tmin4, &mut leaf) else {
                    continue;
                };
                done(w.ray, stopped);
                match start(&mut done) {
                    Some((ray, r)) => {
                        (w.r, w.ray) = (r, ray);
                        w.at.restart(tmax[ray]);
                    }
                    None => {
                        *slot = None;
                        live -= 1;
                    }
                }
            }
        }
    }

    /// Advances a ray by one node or one leaf (the tree's
    /// [`step`](super::Bvh4::step)): `Some(stopped)` once it is finished,
    /// with whether `leaf` stopped it. Prefetches what it visits next.
    #[inline(always)]
    fn step<const ORDERED: bool>(
        &self,
        w: &mut Walk,
        tmin4: Vec4,
        leaf: &mut impl FnMut(usize, &Pack, &TraversalRay, &mut f32) -> bool,
    ) -> Option<bool> {
        let (i, r) = (w.ray, &w.r);
        let hit_node = |node: &Node4, tmax| node.hit(r, tmin4, Vec4::splat(tmax));
        let mut packs = |_: Option<(&Node4, usize)>, packs: &[Pack], tmax: &mut f32| {
            any_of(
                packs,
                #[inline(always)]
                |p| leaf(i, p, r, tmax),
            )
        };
        let at = (&mut w.at.cur, &mut w.at.tmax, &mut w.at.stack);
        let done = self.tree.step::<ORDERED, false>(at, &hit_node, &mut packs);
        if done.is_none() {
            self.prefetch(w.at.cur);
        }
        done
    }

    /// Asks the processor to start loading what a ray visits next (both
    /// cache lines of a node, or the first lines of a leaf's first packet),
    /// so that the load overlaps the other rays' steps instead of stalling
    /// this ray's next one. A hint only: no result depends on it.
    #[inline(always)]
    fn prefetch(&self, cur: u32) {
        if let Some(n) = self.tree.node(cur) {
            // The two lines of a node (128 bytes, aligned to 64).
            fetch(&n.b[0][0]);
            fetch(&n.b[2][0]);
        } else if let Some(p) = self.tree.first_item(cur) {
            // The lines of its first 128 of 160 bytes (aligned to 16: a
            // packet starts anywhere in a line): all four lines measured
            // alike, the nodes alone slower than none.
            fetch(&p.v[0][0]);
            fetch(&p.v[1][1]);
        }
    }
}

/// Consecutive stretches of a batch, in order and covering it all: runs to
/// trace as a packet, with their frustum, and the rays between runs
/// (`None`), to interleave. With an empty tree, one stretch of all the rays
/// (interleaving handles it).
pub(super) struct Stretches<'a> {
    rays: &'a [Ray],
    /// The next ray to look at.
    i: usize,
    /// The first ray not yet given out in a stretch.
    loose: usize,
    /// A run found after loose rays, given out after them.
    run: Option<(Range<usize>, Frustum)>,
}

impl<'a> Stretches<'a> {
    pub(super) fn new(bvh: &TriangleBvh, rays: &'a [Ray]) -> Self {
        // With an empty tree, all rays are loose.
        let i = if bvh.tree.is_empty() { rays.len() } else { 0 };
        Stretches {
            rays,
            i,
            loose: 0,
            run: None,
        }
    }
}

impl Iterator for Stretches<'_> {
    type Item = (Range<usize>, Option<Frustum>);

    fn next(&mut self) -> Option<Self::Item> {
        if let Some((at, frustum)) = self.run.take() {
            return Some((at, Some(frustum)));
        }
        let rays = self.rays;
        while self.i < rays.len() {
            // Most rays of an incoherent batch start nowhere near a run: skip
            // to the next ray whose successor starts at the same x.
            let ahead = &rays[self.i..];
            let same_x = |w: &[Ray]| w[1].origin.x == w[0].origin.x;
            self.i += ahead.windows(2).position(same_x).unwrap_or(ahead.len());
            let i = self.i;
            if i == rays.len() {
                break;
            }
            let n = run_len(&rays[i..]);
            self.i += n;
            if n < MIN_RUN {
                continue;
            }
            let Some(frustum) = Frustum::new(&rays[i..i + n]) else {
                continue;
            };
            let loose = std::mem::replace(&mut self.loose, i + n);
            if loose < i {
                self.run = Some((i..i + n, frustum));
                return Some((loose..i, None));
            }
            return Some((i..i + n, Some(frustum)));
        }
        let loose = std::mem::replace(&mut self.loose, rays.len());
        (loose < rays.len()).then_some((loose..rays.len(), None))
    }
}

impl<'a> Run<'a> {
    /// The run of rays `at` of a batch, inside `frustum`.
    fn new(
        frustum: &'a Frustum,
        rays: &'a [Ray],
        tmin: f32,
        tmax: &'a [f32],
        at: &Range<usize>,
    ) -> Self {
        Run {
            frustum,
            rays: &rays[at.clone()],
            tmin,
            tmax: &tmax[at.clone()],
        }
    }
}

/// How many rays at the start of `rays` (at least one, at most `RUN`) form
/// a run: the same origin, directions of the same signs, each
/// within 1° of the first's.
pub(super) fn run_len(rays: &[Ray]) -> usize {
    let [first, second, ..] = rays else {
        return rays.len();
    };
    // Rays from different points (with equal x) leave here.
    if second.origin != first.origin {
        return 1;
    }
    // In SIMD registers (`Vec3A`): scalar tests cost twice the instructions.
    let (o, d0) = (Vec3A::from(first.origin), Vec3A::from(first.dir));
    let (signs, len0) = (d0.is_negative_bitmask(), d0.length_squared());
    let close = |r: &Ray| {
        let d = Vec3A::from(r.dir);
        let dot = d.dot(d0);
        Vec3A::from(r.origin).cmpeq(o).all()
            & (d.is_negative_bitmask() == signs)
            & (dot > 0.0)
            & (dot * dot >= RUN_COS2 * d.length_squared() * len0)
    };
    1 + rays[1..rays.len().min(RUN)]
        .iter()
        .take_while(|r| close(r))
        .count()
}

/// Starts loading the cache line holding `x` (`prefetcht0`, through a safe
/// wrapper) where the target has the instruction; elsewhere does nothing.
#[inline(always)]
fn fetch<T>(x: &T) {
    #[cfg(all(
        any(target_arch = "x86", target_arch = "x86_64"),
        target_feature = "sse"
    ))]
    safe_arch::prefetch_t0(x);
    #[cfg(not(all(
        any(target_arch = "x86", target_arch = "x86_64"),
        target_feature = "sse"
    )))]
    let _ = x;
}
