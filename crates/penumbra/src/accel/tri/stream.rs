//! Independent rays traced together, their traversals interleaved.
//!
//! An incoherent ray spends most of its time waiting for memory: each step
//! of its traversal reads a node or a packet that the step before chose, and
//! the tree (3.6 MiB for the bunny) does not fit in the first- or
//! second-level cache. One ray alone gives the processor little to do
//! while it waits. Here up to `LANES` rays are in flight, each advanced by
//! one node or one leaf in turn, so the loads of different rays, which do
//! not depend on each other, overlap. Every ray follows exactly the path it
//! follows alone (the same node tests, children in the same order, the same
//! triangle tests), so the results are those of
//! [`closest_hit`](TriangleBvh::closest_hit) and
//! [`any_hit`](TriangleBvh::any_hit) bit for bit; only the order in which
//! different rays' work is done changes.
//!
//! On the harness's million incoherent rays over the bunny, interleaving
//! alone traced 1.3× as many rays per second as one ray after another;
//! camera rays, whose nodes stay in the cache, gained nothing and lost
//! nothing (see `docs/performance.md`, ninth round). Four, eight and sixteen rays in
//! flight measured alike; eight leaves room for slower memory.
//!
//! Interleaving alone leaves each load to be issued when its ray's turn
//! comes. So a step that chooses where its ray goes next also prefetches
//! it (through `safe_arch`'s safe wrapper of `prefetcht0`): the load then
//! has the other rays' steps to complete in. That added about 7% on the
//! incoherent rays (medians of interleaved series 1.00–1.15×; camera rays,
//! already in the cache, lost up to 6%: tenth round).

use super::{closest_in_pack, descend, pack_any_hit, Pack, Stack, TraversalRay, TriHit};
use super::{TriangleBvh, FIRST_MASK, LEAF};
use crate::math::Ray;
use glam::Vec4;

/// Rays in flight.
const LANES: usize = 8;

/// One ray's traversal between steps: where it is, what it deferred.
struct Walk {
    r: TraversalRay,
    /// Index of the ray in the batch.
    ray: usize,
    tmax: f32,
    /// The node or leaf to visit next.
    cur: u32,
    stack: Stack,
}

impl TriangleBvh {
    /// The closest hit of every ray within `(tmin, tmax[i])`, into `out`
    /// (cleared first): for each ray what
    /// [`closest_hit`](Self::closest_hit) gives it, bit for bit, computed
    /// with the traversals of several rays interleaved (see the module
    /// docs). For many independent rays: diffuse bounces, the harness's
    /// batch call. `tmax` must hold a limit per ray.
    pub fn closest_hit_each(
        &self,
        rays: &[Ray],
        tmin: f32,
        tmax: &[f32],
        out: &mut Vec<Option<TriHit>>,
    ) {
        out.clear();
        out.resize(rays.len(), None);
        self.interleave::<true>(
            rays,
            tmin,
            tmax,
            |i, p, r, tmax| {
                closest_in_pack(p, r, tmin, tmax, &mut out[i]);
                false
            },
            |_, _| {},
        );
    }

    /// [`any_hit`](Self::any_hit) for every ray within `(tmin, tmax[i])`,
    /// traversals interleaved: `hit(i, id)` hears of the triangles ray `i`
    /// crosses, in the order `any_hit` reports them, until it returns true.
    /// `out[i]` (cleared first) says whether it did.
    pub fn any_hit_each(
        &self,
        rays: &[Ray],
        tmin: f32,
        tmax: &[f32],
        mut hit: impl FnMut(usize, u32) -> bool,
        out: &mut Vec<bool>,
    ) {
        out.clear();
        out.resize(rays.len(), false);
        self.interleave::<false>(
            rays,
            tmin,
            tmax,
            |i, p, r, tmax| pack_any_hit(p, r, tmin, *tmax, &mut |id| hit(i, id)),
            |i, blocked| out[i] = blocked,
        );
    }

    /// Whether each ray crosses a triangle within `(tmin, tmax[i])`: what
    /// [`occluded`](Self::occluded) says of it, traversals interleaved.
    pub fn occluded_each(&self, rays: &[Ray], tmin: f32, tmax: &[f32], out: &mut Vec<bool>) {
        self.any_hit_each(rays, tmin, tmax, |_, _| true, out);
    }

    /// Traces every ray with up to `LANES` in flight, one step each in
    /// turn. `leaf(i, packet, ray, tmax)` tests a packet for ray `i` and
    /// returns true to stop that ray; `done(i, stopped)` hears when ray `i`
    /// is finished (rays with a non-finite origin or direction at once).
    #[inline(always)]
    fn interleave<const ORDERED: bool>(
        &self,
        rays: &[Ray],
        tmin: f32,
        tmax: &[f32],
        mut leaf: impl FnMut(usize, &Pack, &TraversalRay, &mut f32) -> bool,
        mut done: impl FnMut(usize, bool),
    ) {
        assert!(tmax.len() >= rays.len(), "a tmax per ray");
        let mut next = 0;
        // The next ray worth tracing, or `None` when all have started.
        let mut start = |done: &mut dyn FnMut(usize, bool)| {
            while let Some(ray) = rays.get(next) {
                let i = next;
                next += 1;
                if !self.nodes.is_empty() && ray.origin.is_finite() && ray.dir.is_finite() {
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
            let (tmax, cur, stack) = (tmax[ray], 0, Stack::new());
            *slot = Some(Walk {
                r,
                ray,
                tmax,
                cur,
                stack,
            });
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
                        (w.r, w.ray, w.tmax, w.cur) = (r, ray, tmax[ray], 0);
                        w.stack.clear();
                    }
                    None => {
                        *slot = None;
                        live -= 1;
                    }
                }
            }
        }
    }

    /// Advances a ray by one node or one leaf: `Some(stopped)` once it is
    /// finished, with whether `leaf` stopped it. The loop body of
    /// [`traverse`](Self::traverse) for a single ray.
    #[inline(always)]
    fn step<const ORDERED: bool>(
        &self,
        w: &mut Walk,
        tmin4: Vec4,
        leaf: &mut impl FnMut(usize, &Pack, &TraversalRay, &mut f32) -> bool,
    ) -> Option<bool> {
        if w.cur & LEAF == 0 {
            let node = &self.nodes[w.cur as usize];
            let (mask, t) = node.hit(&w.r, tmin4, Vec4::splat(w.tmax));
            if mask != 0 {
                w.cur = descend::<ORDERED>(mask, &t, |i| node.child[i], &mut w.stack);
                self.prefetch(w.cur);
                return None;
            }
        } else {
            let (i, r, tmax) = (w.ray, &w.r, &mut w.tmax);
            if self.leaf_packs(w.cur).iter().any(|p| leaf(i, p, r, tmax)) {
                return Some(true);
            }
        }
        match w.stack.pop_within(w.tmax) {
            Some(c) => {
                w.cur = c;
                self.prefetch(c);
                None
            }
            None => Some(false),
        }
    }

    /// Asks the processor to start loading what a ray visits next (both
    /// cache lines of a node, or the first lines of a leaf's first packet),
    /// so that the load overlaps the other rays' steps instead of stalling
    /// this ray's next one. A hint only: no result depends on it.
    #[inline(always)]
    fn prefetch(&self, cur: u32) {
        if cur & LEAF == 0 {
            if let Some(n) = self.nodes.get(cur as usize) {
                // The two lines of a node (128 bytes, aligned to 64).
                fetch(&n.b[0][0]);
                fetch(&n.b[2][0]);
            }
        } else if let Some(p) = self.packs.get((cur & FIRST_MASK) as usize) {
            // The lines of its first 128 of 160 bytes (aligned to 16: a
            // packet starts anywhere in a line): all four lines measured
            // alike, the nodes alone slower than none.
            fetch(&p.v[0][0]);
            fetch(&p.v[1][1]);
        }
    }
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
