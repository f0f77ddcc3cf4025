//! Triangle meshes in the four-wide BVH, stored in leaf order and
//! intersected four at a time.
//!
//! A test through the scene's indirections (primitive → object → mesh →
//! index buffer → three vertices) would load scattered memory for every
//! triangle. Here the triangles are copied into the tree itself, in the order its leaves visit them, as
//! packets of four in structure-of-arrays form (`Pack`: per vertex and
//! axis, one 4-lane vector), and the traversal tests all four with the same
//! SIMD instructions.
//!
//! # Layout
//! The tree is a [`Bvh4`] whose leaf items are `Pack`s: its leaves hold up
//! to four packets (sixteen triangles) when the SAH prefers them, and the
//! builder charges a leaf per started packet. Packs take 160 bytes for four
//! triangles (padding lanes hold NaN vertices, which never hit); for the
//! bunny, 95% of the lanes are used and nodes and packs take 54 bytes per
//! triangle.
//!
//! # Traversal
//! Closest and any hit are [`Bvh4`]'s traversal with the packet test at the
//! leaves. Batches of independent rays can be traced with their traversals
//! interleaved (`stream`), which overlaps the memory waits of incoherent
//! rays; runs of a batch's rays from one point go as packets.
//!
//! # Exactness
//! The triangle test is [`intersect_triangle`]'s watertight algorithm
//! computed lane-wise with the same operations in the same order (no fused
//! multiply-adds), so each lane gives bit for bit what the scalar routine
//! gives, including the double-precision recomputation of edge functions
//! that round to zero; the box test is [`Bvh4`]'s robust one
//! (NaN-skipping slab reduction, far distance enlarged by `1 + 2γ₃`), so the
//! tree returns exactly what a loop over all triangles returns. Of
//! triangles hit at exactly the same distance (a shared edge can give equal
//! `t`), the lowest index wins, as in that loop, so a ray's closest hit does
//! not depend on the order the leaves are visited in: alone, interleaved
//! and in a packet it is the same. The tests below check this against the
//! loop.
//!
//! [`intersect_triangle`]: crate::geometry::triangle::intersect_triangle

use super::build::Config;
use super::bvh4::{any_of, reaches, Bvh4, Frustum, LeafSet, RayPacket, Run, TraversalRay};
use super::shaft::Shaft;
use crate::geometry::triangle::edge_functions_f64;
use crate::math::{Aabb, Ray, Vec3};
use glam::Vec4;
use rayon::prelude::*;

mod stream;

/// Builder settings: leaves of up to four triangles (one packet) always,
/// up to 16 (four packets) when the SAH prefers them, cost per packet.
const CONFIG: Config = Config {
    max_leaf: 4,
    max_sah_leaf: 16,
    block_shift: 2,
};

/// Four triangles, structure of arrays: `v[vertex][axis]` holds that
/// coordinate of the four triangles' vertex, and `id` their indices in the
/// build input. Unused lanes have NaN vertices and id `u32::MAX`.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(16))]
struct Pack {
    v: [[Vec4; 3]; 3],
    id: [u32; 4],
}

impl Pack {
    const EMPTY: Pack = Pack {
        v: [[Vec4::NAN; 3]; 3],
        id: [u32::MAX; 4],
    };

    /// The packet of triangles `ids` (at most four), whose vertices `tri` gives.
    #[inline(always)]
    fn of(ids: &[u32], tri: &impl Fn(usize) -> [Vec3; 3]) -> Pack {
        let mut p = Pack::EMPTY;
        for (lane, &id) in ids.iter().enumerate() {
            for (vertex, pos) in tri(id as usize).iter().enumerate() {
                for axis in 0..3 {
                    p.v[vertex][axis][lane] = pos[axis];
                }
            }
            p.id[lane] = id;
        }
        p
    }

    /// The watertight test on four triangles. Returns the mask of lanes hit
    /// within `(tmin, tmax)` (`(tmin, tmax]` if `CLOSED`) and, per lane,
    /// `t`, `b1`, `b2` (meaningful in the lanes of the mask).
    #[inline(always)]
    fn intersect<const CLOSED: bool>(
        &self,
        r: &TraversalRay,
        tmin: f32,
        tmax: f32,
    ) -> (u32, Vec4, Vec4, Vec4) {
        // `min(2)` lets the compiler drop the bounds checks (the permutation
        // entries are below 3 anyway).
        let (kx, ky, kz) = (r.k[0].min(2), r.k[1].min(2), r.k[2].min(2));
        let [ox, oy, oz] = r.ok;
        let [sx, sy, sz] = r.s;
        // The sheared frame of `RayShear::transform`, lane-wise.
        let sheared = |p: &[Vec4; 3]| {
            let x = p[kx] - ox;
            let y = p[ky] - oy;
            let z = p[kz] - oz;
            (x - sx * z, y - sy * z, z)
        };
        let (ax, ay, az) = sheared(&self.v[0]);
        let (bx, by, bz) = sheared(&self.v[1]);
        let (cx, cy, cz) = sheared(&self.v[2]);
        let mut u = cx * by - cy * bx;
        let mut v = ax * cy - ay * cx;
        let mut w = bx * ay - by * ax;
        let zero = Vec4::ZERO;
        let exact_zero = u.cmpeq(zero) | v.cmpeq(zero) | w.cmpeq(zero);
        if exact_zero.any() {
            (u, v, w) = recompute_f64(exact_zero.bitmask(), [ax, ay, bx, by, cx, cy], [u, v, w]);
        }
        let neg = u.cmplt(zero) | v.cmplt(zero) | w.cmplt(zero);
        let pos = u.cmpgt(zero) | v.cmpgt(zero) | w.cmpgt(zero);
        let det = u + v + w;
        let t = sz * (u * az + v * bz + w * cz) / det;
        let below = if CLOSED {
            t.cmple(Vec4::splat(tmax))
        } else {
            t.cmplt(Vec4::splat(tmax))
        };
        let ok = !(neg & pos) & det.cmpne(zero) & t.cmpgt(Vec4::splat(tmin)) & below;
        let mut mask = ok.bitmask();
        if mask == 0 {
            return (0, t, t, t);
        }
        let b1 = v / det;
        let b2 = w / det;
        mask &= (t.is_finite_mask() & b1.is_finite_mask() & b2.is_finite_mask()).bitmask();
        (mask, t, b1, b2)
    }
}

/// Edge functions of the lanes in `lanes` recomputed in `f64`, as
/// [`intersect_triangle`](crate::geometry::triangle::intersect_triangle) does
/// for a value that rounded to exactly zero. Rare: out of line.
#[cold]
#[inline(never)]
fn recompute_f64(lanes: u32, sheared: [Vec4; 6], uvw: [Vec4; 3]) -> (Vec4, Vec4, Vec4) {
    let s = sheared.map(|x| x.to_array());
    let [mut u, mut v, mut w] = uvw.map(|x| x.to_array());
    for i in 0..4 {
        if lanes & (1 << i) != 0 {
            (u[i], v[i], w[i]) =
                edge_functions_f64([s[0][i], s[1][i], s[2][i], s[3][i], s[4][i], s[5][i]]);
        }
    }
    (Vec4::from(u), Vec4::from(v), Vec4::from(w))
}

/// A ray–triangle hit: the triangle's index in the build input, the ray
/// parameter and the barycentrics of vertices 1 and 2.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriHit {
    pub id: u32,
    pub t: f32,
    pub b1: f32,
    pub b2: f32,
}

/// Shape and size of a built [`TriangleBvh`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriStats {
    pub triangles: usize,
    /// Four-wide interior nodes.
    pub nodes: usize,
    pub leaves: usize,
    /// Packets of four triangles (lanes in use: `triangles / (4 * packs)`).
    pub packs: usize,
    /// Memory of nodes and packets.
    pub bytes: usize,
}

/// A four-wide BVH over triangles; see the module docs.
#[derive(Clone, Debug, Default)]
pub struct TriangleBvh {
    tree: Bvh4<Pack>,
    len: usize,
}

impl TriangleBvh {
    /// Builds the tree over triangles `0..n`, whose vertices `tri(i)` gives
    /// (finite coordinates). Hits report `i` as their id.
    ///
    /// # Panics
    /// If there are 2²⁸ packets of triangles or more (about a billion triangles).
    pub fn build(n: usize, tri: impl Fn(usize) -> [Vec3; 3] + Sync) -> TriangleBvh {
        let bounds: Vec<Aabb> = (0..n)
            .into_par_iter()
            .with_min_len(4096)
            .map(|i| Aabb::from_points(tri(i)))
            .collect();
        let tree = Bvh4::build(&bounds, &CONFIG, |ids, packs| {
            packs.extend(ids.chunks(4).map(|chunk| Pack::of(chunk, &tri)));
        });
        TriangleBvh { tree, len: n }
    }

    /// Number of triangles.
    pub fn len(&self) -> usize {
        self.len
    }

    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Box around all triangles ([`Aabb::EMPTY`] when there are none).
    pub fn bounds(&self) -> Aabb {
        self.tree.bounds()
    }

    pub fn stats(&self) -> TriStats {
        let (nodes, leaves, packs) = self.tree.counts();
        TriStats {
            triangles: self.len,
            nodes,
            leaves,
            packs,
            bytes: self.tree.bytes(),
        }
    }

    /// The closest triangle hit within `(tmin, tmax)`, with the result of
    /// [`intersect_triangle`](crate::geometry::triangle::intersect_triangle)
    /// for it. A ray with a non-finite origin or direction hits nothing.
    #[inline(always)]
    pub fn closest_hit(&self, ray: &Ray, tmin: f32, tmax: f32) -> Option<TriHit> {
        let r = self.tree.prepare(ray)?;
        self.closest_hit_prepared(&r, tmin, tmax)
    }

    /// [`closest_hit`](Self::closest_hit) for a ray prepared by the level above.
    #[inline(always)]
    pub(super) fn closest_hit_prepared(
        &self,
        r: &TraversalRay,
        tmin: f32,
        tmax: f32,
    ) -> Option<TriHit> {
        let mut best = None;
        self.tree.traverse_prepared::<true>(
            r,
            tmin,
            tmax,
            #[inline(always)]
            |packs, r, tmax| {
                for p in packs {
                    closest_in_pack(p, r, tmin, tmax, &mut best);
                }
                false
            },
        );
        best
    }

    /// The closest hits of several rays from one origin, each within
    /// `(tmin, tmax[i])`, written to `out` in order: what
    /// [`closest_hit`](Self::closest_hit) gives each ray, bit for bit.
    ///
    /// Rays that leave one point with directions of the same signs (the
    /// camera rays of a pixel) are traced together: one interval box test
    /// per node for the whole packet (see `Frustum`) and every ray
    /// against the triangles of the leaves it reaches. Coherent rays visit
    /// nearly the same nodes, so the packet pays for about one ray's node
    /// tests. Other sets of rays are traced one by one.
    pub fn closest_hits(
        &self,
        rays: &[Ray],
        tmin: f32,
        tmax: &[f32],
        scratch: &mut RayPacket,
        out: &mut Vec<Option<TriHit>>,
    ) {
        match Frustum::new(rays) {
            Some(frustum) => self.closest_hits_in(&frustum, rays, tmin, tmax, scratch, out),
            None => {
                out.clear();
                let one = |(r, &t): (&Ray, &f32)| self.closest_hit(r, tmin, t);
                out.extend(rays.iter().zip(tmax).map(one));
            }
        }
    }

    /// [`closest_hits`](Self::closest_hits) for rays the caller has found
    /// to be a packet: `frustum` bounds them.
    #[inline(always)]
    pub(super) fn closest_hits_in(
        &self,
        frustum: &Frustum,
        rays: &[Ray],
        tmin: f32,
        tmax: &[f32],
        scratch: &mut RayPacket,
        out: &mut Vec<Option<TriHit>>,
    ) {
        out.clear();
        out.resize(rays.len(), None);
        if self.tree.is_empty() {
            return;
        }
        let run = Run {
            frustum,
            rays,
            tmin,
            tmax,
        };
        self.closest_packet(&run, scratch, out);
    }

    /// [`closest_hits`](Self::closest_hits) for a run (the tree not
    /// empty), into `out` (one entry per ray, `None` on entry).
    #[inline(always)]
    fn closest_packet(&self, run: &Run, scratch: &mut RayPacket, out: &mut [Option<TriHit>]) {
        let tmin = run.tmin;
        let tmin4 = Vec4::splat(tmin);
        self.tree.traverse::<true, true>(
            scratch.reset(run.tmax),
            #[inline(always)]
            |node, tmax| run.frustum.hit(node, tmin4, Vec4::splat(tmax)),
            #[inline(always)]
            |at, packs, widest| {
                let (prepared, limits) = scratch.prepared(run.rays);
                for ((r, tmax), best) in prepared.iter().zip(limits.iter_mut()).zip(out.iter_mut())
                {
                    // The packet reached the leaf; this ray may not have.
                    if !reaches(at, r, tmin4, *tmax) {
                        continue;
                    }
                    for p in packs {
                        closest_in_pack(p, r, tmin, tmax, best);
                    }
                }
                *widest = scratch.widest();
                false
            },
        );
    }

    /// [`any_hit`](Self::any_hit) for a run (the tree not empty), traced
    /// as one packet: `hit(i, id)` hears of the triangles ray `i` crosses,
    /// in the order `any_hit` reports them to it, until it returns true;
    /// then `out[i]` (false on entry) is set. Leaves are visited in storage
    /// order, as by `any_hit`, and a ray tests only those whose box it hits
    /// itself; the boxes of a node's subtree lie within its box, so these
    /// are exactly the leaves its own traversal reaches.
    #[inline(always)]
    fn any_hit_packet(
        &self,
        run: &Run,
        scratch: &mut RayPacket,
        mut hit: impl FnMut(usize, u32) -> bool,
        out: &mut [bool],
    ) {
        let tmin = run.tmin;
        let tmin4 = Vec4::splat(tmin);
        self.tree.traverse::<false, true>(
            scratch.reset(run.tmax),
            #[inline(always)]
            |node, tmax| run.frustum.hit(node, tmin4, Vec4::splat(tmax)),
            #[inline(always)]
            |at, packs, widest| {
                let (prepared, limits) = scratch.prepared(run.rays);
                let rays = prepared.iter().zip(limits.iter_mut()).zip(out.iter_mut());
                for (i, ((r, tmax), blocked)) in rays.enumerate() {
                    if *blocked || !reaches(at, r, tmin4, *tmax) {
                        continue;
                    }
                    if any_of(
                        packs,
                        #[inline(always)]
                        |p| pack_any_hit(p, r, tmin, *tmax, &mut |id| hit(i, id)),
                    ) {
                        // Done: a limit no box is entered before.
                        (*blocked, *tmax) = (true, f32::NEG_INFINITY);
                    }
                }
                *widest = scratch.widest();
                // All stopped: the packet is done.
                *widest == f32::NEG_INFINITY
            },
        );
    }

    /// Calls `hit(id)` for triangles crossed within `(tmin, tmax)` until it
    /// returns true (an occluder): then returns true. Each triangle is
    /// reported at most once. Children are visited in storage order, not by
    /// distance: most shadow rays are not blocked and must visit every
    /// subtree they enter anyway, so sorting would be wasted on them.
    #[inline(always)]
    pub fn any_hit(&self, ray: &Ray, tmin: f32, tmax: f32, hit: impl FnMut(u32) -> bool) -> bool {
        let r = self.tree.prepare(ray);
        r.is_some_and(
            #[inline(always)]
            |r| self.any_hit_prepared(&r, tmin, tmax, hit),
        )
    }

    /// [`any_hit`](Self::any_hit) for a ray prepared by the level above.
    #[inline(always)]
    pub(super) fn any_hit_prepared(
        &self,
        r: &TraversalRay,
        tmin: f32,
        tmax: f32,
        mut hit: impl FnMut(u32) -> bool,
    ) -> bool {
        self.tree.traverse_prepared::<false>(
            r,
            tmin,
            tmax,
            #[inline(always)]
            |packs, r, tmax| {
                any_of(
                    packs,
                    #[inline(always)]
                    |p| pack_any_hit(p, r, tmin, *tmax, &mut hit),
                )
            },
        )
    }

    /// Collects into `out` the leaves whose boxes may overlap `shaft`, in
    /// the order [`any_hit`](Self::any_hit) visits leaves (depth first, children in
    /// storage order). Returns false, with `out` incomplete, once more than
    /// `limit` leaves are found.
    #[inline(always)]
    pub fn gather(&self, shaft: &Shaft, limit: usize, out: &mut LeafSet) -> bool {
        self.tree.gather(shaft, limit, out)
    }

    /// [`any_hit`](Self::any_hit) for a ray that lies in the shaft `set` was
    /// gathered for: tests only the leaves of `set` (four boxes at a time),
    /// and reports the same triangles in the same order as `any_hit`.
    #[inline(always)]
    pub fn any_hit_in(
        &self,
        set: &LeafSet,
        ray: &Ray,
        tmin: f32,
        tmax: f32,
        mut hit: impl FnMut(u32) -> bool,
    ) -> bool {
        self.tree.any_hit_in(
            set,
            ray,
            tmin,
            tmax,
            #[inline(always)]
            |packs, r| {
                any_of(
                    packs,
                    #[inline(always)]
                    |p| pack_any_hit(p, r, tmin, tmax, &mut hit),
                )
            },
        )
    }

    /// Whether any triangle is crossed within `(tmin, tmax)`.
    #[inline(always)]
    pub fn occluded(&self, ray: &Ray, tmin: f32, tmax: f32) -> bool {
        self.any_hit(ray, tmin, tmax, |_| true)
    }
}

/// Tests one packet for a hit nearer than `tmax`, or as near as `best` but
/// of a lower index; on one, shrinks `tmax` to it and records it in `best`.
///
/// Of triangles hit at exactly the same distance (a shared edge can give
/// equal `t`), the lowest index wins, as in a loop over all triangles in
/// index order. So the hit does not depend on the order leaves are visited
/// in: a ray traced alone, interleaved with others or in a packet finds
/// the same triangle.
#[inline(always)]
fn closest_in_pack(
    p: &Pack,
    r: &TraversalRay,
    tmin: f32,
    tmax: &mut f32,
    best: &mut Option<TriHit>,
) {
    let (mask, t, b1, b2) = p.intersect::<true>(r, tmin, *tmax);
    if mask == 0 {
        return;
    }
    let t = t.to_array();
    let lane = nearest_lane_by_id(mask, &t, &p.id);
    // At exactly `tmax`, only a lower index than the hit found there wins
    // (`tmax` is the caller's open limit until there is one).
    if t[lane] == *tmax && !best.is_some_and(|b| p.id[lane] < b.id) {
        return;
    }
    *tmax = t[lane];
    *best = Some(TriHit {
        id: p.id[lane],
        t: t[lane],
        b1: b1[lane],
        b2: b2[lane],
    });
}

/// The lane of `mask` (not empty) with the smallest `t`, of equals the one
/// with the lowest `id`.
#[inline(always)]
fn nearest_lane_by_id(mask: u32, t: &[f32; 4], id: &[u32; 4]) -> usize {
    let mut lane = mask.trailing_zeros() as usize;
    let mut rest = mask & (mask - 1);
    while rest != 0 {
        let i = rest.trailing_zeros() as usize;
        if t[i] < t[lane] || (t[i] == t[lane] && id[i] < id[lane]) {
            lane = i;
        }
        rest &= rest - 1;
    }
    lane
}

/// Reports the triangles of one packet the ray crosses, in lane order, until
/// `hit` returns true.
#[inline(always)]
fn pack_any_hit(
    p: &Pack,
    r: &TraversalRay,
    tmin: f32,
    tmax: f32,
    hit: &mut impl FnMut(u32) -> bool,
) -> bool {
    let (mut mask, ..) = p.intersect::<false>(r, tmin, tmax);
    while mask != 0 {
        if hit(p.id[mask.trailing_zeros() as usize]) {
            return true;
        }
        mask &= mask - 1;
    }
    false
}

// The sizes the module docs state.
const _: () = assert!(std::mem::size_of::<Pack>() == 160);

#[cfg(test)]
mod tests {
    use super::stream::{run_len, Stretches, MIN_RUN, RUN};
    use super::*;
    use crate::accel::brute::{brute_any, brute_closest};
    use crate::accel::testdata::*;
    use crate::geometry::triangle::intersect_triangle;
    use crate::geometry::triangle::RayShear;
    use crate::sampling::Rng;

    fn soup(r: &mut Rng, n: usize, size: f32) -> Vec<Tri> {
        let world = Aabb::new(Vec3::splat(-10.0), Vec3::splat(10.0));
        (0..n)
            .map(|_| {
                let a = rand_in(r, &world);
                [
                    a,
                    a + rand_dir(r) * r.range(0.0, size),
                    a + rand_dir(r) * r.range(0.0, size),
                ]
            })
            .collect()
    }

    /// Closest and any hit of the tree against the scalar test over all
    /// triangles: identical hit/miss, the same triangle (of equally near
    /// ones the lowest index, as the loop finds) with bit-identical
    /// distance and barycentrics, and any-hit reporting exactly the crossed
    /// triangles, each once. Returns the number of hits.
    fn check(tris: &[Tri], rays: &[(Ray, f32, f32)]) -> usize {
        let bvh = TriangleBvh::build(tris.len(), |i| tris[i]);
        assert_eq!(bvh.len(), tris.len());
        let mut hits = 0;
        for &(ray, tmin, tmax) in rays {
            let shear = RayShear::new(&ray);
            let f = |p: u32, tm: f32| {
                let [a, b, c] = tris[p as usize];
                intersect_triangle(&ray, &shear, a, b, c, tmin, tm)
            };
            let got = bvh.closest_hit(&ray, tmin, tmax);
            let want = brute_closest(tris.len(), &ray, tmin, tmax, |p, tm| f(p, tm).map(|h| h.0));
            match (got, want) {
                (None, None) => {}
                (Some(g), Some((wid, wt))) => {
                    assert_eq!(g.t.to_bits(), wt.to_bits(), "ray {ray:?}: {g:?} vs t {wt}");
                    assert_eq!(g.id, wid, "ray {ray:?}: {g:?}");
                    // The reported triangle gives exactly the reported hit.
                    let (t, b1, b2) = f(g.id, tmax).expect("reported triangle is hit");
                    assert_eq!((t, b1, b2), (g.t, g.b1, g.b2));
                    hits += 1;
                }
                _ => panic!("ray {ray:?} [{tmin}, {tmax}]: tree {got:?} vs brute {want:?}"),
            }
            assert_eq!(bvh.occluded(&ray, tmin, tmax), got.is_some());
            assert_eq!(
                bvh.occluded(&ray, tmin, tmax),
                brute_any(tris.len(), &ray, tmin, tmax, |p, tm| f(p, tm).is_some())
            );
            let mut seen = Vec::new();
            assert!(!bvh.any_hit(&ray, tmin, tmax, |id| {
                seen.push(id);
                false
            }));
            seen.sort_unstable();
            let all: Vec<u32> = (0..tris.len() as u32)
                .filter(|&p| f(p, tmax).is_some())
                .collect();
            assert_eq!(seen, all, "crossings of {ray:?}");
        }
        hits
    }

    fn random_rays(r: &mut Rng, n: usize, b: &Aabb) -> Vec<(Ray, f32, f32)> {
        let grown = Aabb::new(b.min - Vec3::splat(2.0), b.max + Vec3::splat(2.0));
        (0..n)
            .map(|i| {
                let o = rand_in(r, &grown);
                let d = if i % 2 == 0 {
                    rand_dir(r)
                } else {
                    rand_in(r, b) - o
                };
                let (tmin, tmax) = match i % 5 {
                    0 => (0.0, r.range(0.5, 20.0)),
                    1 => (r.range(0.0, 3.0), f32::INFINITY),
                    _ => (0.0, f32::INFINITY),
                };
                (Ray::new(o, d, 0.0), tmin, tmax)
            })
            .collect()
    }

    #[test]
    fn random_soups_match_brute_force() {
        let mut r = Rng::new(21);
        for (n, size) in [
            (1, 3.0),
            (3, 3.0),
            (5, 3.0),
            (17, 2.0),
            (300, 1.0),
            (3000, 0.5),
        ] {
            let tris = soup(&mut r, n, size);
            let bounds = tris
                .iter()
                .fold(Aabb::EMPTY, |b, t| b.union(Aabb::from_points(*t)));
            let rays = random_rays(&mut r, 3000, &bounds);
            let hits = check(&tris, &rays);
            assert!(hits > 0 || n < 5, "{n} triangles: no hit");
        }
    }

    #[test]
    fn flat_scene_with_axis_and_parallel_rays() {
        // Triangles in the plane y = 0 (zero-height boxes) and standing on
        // it; rays along the axes, in the plane and exactly on box faces.
        let mut r = Rng::new(22);
        let tris = flat_triangles(&mut r, 2000);
        let rays = axis_and_parallel_rays(&mut r, 6000);
        assert!(check(&tris, &rays) > 300);
    }

    #[test]
    fn empty_single_and_degenerate() {
        let ray = Ray::new(Vec3::new(0.0, 0.0, -5.0), Vec3::Z, 0.0);
        let empty = TriangleBvh::build(0, |_| unreachable!());
        assert!(empty.is_empty() && empty.bounds().is_empty());
        assert_eq!(empty.closest_hit(&ray, 0.0, f32::INFINITY), None);
        assert!(!empty.occluded(&ray, 0.0, f32::INFINITY));
        let tri = [
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(1.0, -1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        ];
        let one = TriangleBvh::build(1, |_| tri);
        let h = one.closest_hit(&ray, 0.0, f32::INFINITY).expect("hit");
        assert_eq!((h.id, h.t), (0, 5.0));
        assert_eq!(one.closest_hit(&ray, 0.0, 5.0), None);
        assert_eq!(one.stats().packs, 1);
        // Degenerate triangles (points, segments) among good ones, and rays
        // aimed at their points: never a hit from a degenerate one.
        let mut r = Rng::new(23);
        let mut tris = soup(&mut r, 500, 1.0);
        for i in 0..500 {
            let a = tris[i][0];
            tris.push(if i % 2 == 0 {
                [a, a, a]
            } else {
                [a, tris[i][1], a + 0.5 * (tris[i][1] - a)]
            });
        }
        let rays: Vec<_> = (0..3000)
            .map(|i| {
                let o = rand_dir(&mut r) * 15.0;
                let target = tris[500 + i % 500][i % 3];
                (Ray::new(o, target - o, 0.0), 0.0, f32::INFINITY)
            })
            .collect();
        check(&tris, &rays);
        // Non-finite rays hit nothing.
        let bvh = TriangleBvh::build(tris.len(), |i| tris[i]);
        for ray in [
            Ray::new(Vec3::splat(f32::NAN), Vec3::X, 0.0),
            Ray::new(Vec3::ZERO, Vec3::new(f32::INFINITY, 0.0, 0.0), 0.0),
        ] {
            assert_eq!(bvh.closest_hit(&ray, 0.0, f32::INFINITY), None);
            assert!(!bvh.occluded(&ray, 0.0, f32::INFINITY));
        }
    }

    /// Every crossing `any_hit` reports for `ray`, in its order, until
    /// `stop` of them (then also whether it stopped).
    fn crossings(
        bvh: &TriangleBvh,
        ray: &Ray,
        tmin: f32,
        tmax: f32,
        stop: usize,
    ) -> (bool, Vec<u32>) {
        let mut seen = Vec::new();
        let stopped = bvh.any_hit(ray, tmin, tmax, |id| {
            seen.push(id);
            seen.len() == stop
        });
        (stopped, seen)
    }

    /// Fans of 1 to 12 consecutive rays from one point, each fan's rays
    /// within an angle of 10⁻⁴ to 0.05 of its axis (runs of the batch calls
    /// below 1°, beyond it not), now and then one with a zero, infinite or
    /// negated direction component, mixed with single random rays.
    fn fans(r: &mut Rng, n: usize, b: &Aabb) -> Vec<(Ray, f32, f32)> {
        let grown = Aabb::new(b.min - Vec3::splat(2.0), b.max + Vec3::splat(2.0));
        let mut rays = Vec::new();
        while rays.len() < n {
            let o = rand_in(r, &grown);
            let axis = rand_in(r, b) - o;
            let spread = [1e-4, 1e-3, 5e-3, 0.05][rays.len() % 4];
            let k = 1 + (r.next_f32() * 12.0) as usize;
            for j in 0..k {
                let mut d = axis.normalize() + rand_dir(r) * r.range(0.0, spread);
                match (rays.len() + j) % 97 {
                    5 => d.x = 0.0,
                    6 => d.y = f32::INFINITY,
                    7 => d.z = -d.z,
                    _ => {}
                }
                let tmax = if r.next_f32() < 0.3 {
                    r.range(0.5, 20.0)
                } else {
                    f32::INFINITY
                };
                rays.push((Ray::new(o, d * r.range(0.5, 2.0), 0.0), 0.0, tmax));
            }
            if r.next_f32() < 0.3 {
                rays.extend(random_rays(r, 3, b));
            }
        }
        rays
    }

    /// The batch calls (runs as packets, the rest interleaved) against
    /// single rays: the same closest hit bit for bit, and the same
    /// crossings in the same order, with a limit per ray, rays stopped
    /// early, non-finite rays and an empty tree.
    #[test]
    fn interleaved_batches_match_single_rays() {
        let mut r = Rng::new(25);
        let mut cases = vec![(
            Vec::new(),
            random_rays(&mut r, 50, &Aabb::new(Vec3::ZERO, Vec3::ONE)),
        )];
        for (n, size) in [(1, 3.0), (17, 2.0), (3000, 0.5)] {
            let tris = soup(&mut r, n, size);
            let b = tris
                .iter()
                .fold(Aabb::EMPTY, |b, t| b.union(Aabb::from_points(*t)));
            let mut rays = random_rays(&mut r, 2000, &b);
            rays[7].0 = Ray::new(Vec3::splat(f32::NAN), Vec3::X, 0.0);
            rays[8].0 = Ray::new(Vec3::ZERO, Vec3::new(f32::INFINITY, 0.0, 0.0), 0.0);
            rays.extend(fans(&mut r, 3000, &b));
            cases.push((tris, rays));
        }
        cases.push((
            flat_triangles(&mut r, 2000),
            axis_and_parallel_rays(&mut r, 3000),
        ));
        // Triangle 3 again at ids 1000..1040 (leaves of at most 16): hits
        // on it are ties, which id 3 must win however leaves are visited.
        let mut copies = soup(&mut r, 1000, 1.0);
        copies.extend([copies[3]; 40]);
        let c = copies[3].iter().sum::<Vec3>() / 3.0;
        cases.push((copies, fans(&mut r, 2000, &Aabb::new(c, c))));
        let (mut closest, mut blocked) = (Vec::new(), Vec::new());
        for (tris, rays) in &cases {
            let bvh = TriangleBvh::build(tris.len(), |i| tris[i]);
            // One `tmin` per batch: the rays' own limits, and 0.5.
            for tmin in [0.0, 0.5] {
                let batch: Vec<Ray> = rays.iter().map(|r| r.0).collect();
                let tmax: Vec<f32> = rays.iter().map(|r| r.2).collect();
                bvh.closest_hit_each(&batch, tmin, &tmax, &mut closest);
                bvh.occluded_each(&batch, tmin, &tmax, &mut blocked);
                for (i, ray) in batch.iter().enumerate() {
                    let want = bvh.closest_hit(ray, tmin, tmax[i]);
                    let bits = |h: Option<TriHit>| {
                        h.map(|h| (h.id, h.t.to_bits(), h.b1.to_bits(), h.b2.to_bits()))
                    };
                    assert_eq!(bits(closest[i]), bits(want), "ray {i} {ray:?}");
                    if tris.len() == 1040 {
                        assert!(closest[i].is_none_or(|h| h.id < 1000), "ray {i}");
                    }
                    assert_eq!(blocked[i], bvh.occluded(ray, tmin, tmax[i]), "ray {i}");
                }
                for stop in [usize::MAX, 1, 2] {
                    let mut seen = vec![Vec::new(); batch.len()];
                    let hit = |i: usize, id: u32| {
                        seen[i].push(id);
                        seen[i].len() == stop
                    };
                    bvh.any_hit_each(&batch, tmin, &tmax, hit, &mut blocked);
                    for (i, ray) in batch.iter().enumerate() {
                        let want = crossings(&bvh, ray, tmin, tmax[i], stop);
                        assert_eq!((blocked[i], &seen[i]), (want.0, &want.1), "ray {i}");
                    }
                }
            }
        }
        assert!(cases.iter().any(|c| c.1.len() > 8), "more rays than lanes");
        let (mut runs, mut packed) = (0, 0);
        for (_, rays) in &cases[1..] {
            let batch: Vec<Ray> = rays.iter().map(|r| r.0).collect();
            let bvh = TriangleBvh::build(1, |_| [Vec3::ZERO, Vec3::X, Vec3::Y]);
            let mut next = 0;
            for (at, frustum) in Stretches::new(&bvh, &batch) {
                assert_eq!(at.start, next, "stretches in order, none left out");
                assert!(!at.is_empty());
                next = at.end;
                if frustum.is_some() {
                    assert!((MIN_RUN..=RUN).contains(&at.len()));
                    (runs, packed) = (runs + 1, packed + at.len());
                }
            }
            assert_eq!(next, batch.len());
        }
        assert!(runs > 300 && packed > 2000, "{runs} runs of {packed} rays");
    }

    /// Runs are rays from one origin with directions of the same signs
    /// within 1° of the first's, at most `RUN` of them.
    #[test]
    fn runs_of_coherent_rays() {
        let o = Vec3::new(1.0, 2.0, 3.0);
        let at = |deg: f32| {
            let a = deg.to_radians();
            // `deg` from (0, 0.6, 0.8), towards +x.
            Ray::new(o, Vec3::new(a.sin(), 0.6 * a.cos(), 0.8 * a.cos()), 0.0)
        };
        let fan: Vec<Ray> = (0..12).map(|i| at(0.09 * i as f32)).collect();
        assert_eq!(run_len(&fan), RUN);
        assert_eq!(run_len(&fan[..3]), 3);
        assert_eq!(run_len(&[at(0.0), at(0.9), at(1.1)]), 2);
        assert_eq!(run_len(&[at(1.5), at(0.6), at(0.4)]), 2);
        let mut moved = at(0.1);
        moved.origin.x = f32::from_bits(o.x.to_bits() + 1);
        assert_eq!(run_len(&[at(0.0), moved]), 1);
        // The x direction changes sign between these two.
        assert_eq!(run_len(&[at(0.05), at(-0.05)]), 1);
        assert_eq!(run_len(&[]), 0);
    }

    #[test]
    fn identical_boxes_and_large_leaves() {
        let mut r = Rng::new(24);
        let unit = Aabb::new(Vec3::ZERO, Vec3::ONE);
        let tris: Vec<Tri> = (0..5000)
            .map(|_| [Vec3::ZERO, Vec3::ONE, rand_in(&mut r, &unit)])
            .collect();
        let rays = random_rays(&mut r, 1000, &unit);
        assert!(check(&tris, &rays) > 100);
    }

    /// A closed UV sphere about the origin: `nu` segments, `nv` rings.
    fn uv_sphere(nu: usize, nv: usize, radius: f32) -> Vec<Tri> {
        crate::geometry::tessellate::uv_sphere(nu, nv, |_, _| radius)
    }

    #[test]
    fn closed_mesh_is_watertight() {
        // A UV sphere; rays aimed exactly at vertices and edge midpoints from
        // the centre never slip through.
        let tris = uv_sphere(60, 31, 2.0);
        let bvh = TriangleBvh::build(tris.len(), |i| tris[i]);
        let o = Vec3::ZERO;
        for t in &tris {
            for k in 0..3 {
                for p in [t[k], 0.5 * (t[k] + t[(k + 1) % 3])] {
                    let ray = Ray::new(o, p - o, 0.0);
                    let h = bvh.closest_hit(&ray, 0.0, f32::INFINITY);
                    let h = h.unwrap_or_else(|| panic!("ray to {p:?} slipped through"));
                    assert!((h.t - 1.0).abs() < 1e-4, "t = {}", h.t);
                    assert!(bvh.occluded(&ray, 0.0, f32::INFINITY));
                }
            }
        }
    }

    /// Packets of rays from one point give what each ray gives alone:
    /// narrow packets (the camera rays of a pixel), wide ones, ones with
    /// directions of mixed signs, a zero direction component or several
    /// origins (traced one by one), with per-ray limits.
    #[test]
    fn packets_match_single_rays() {
        let mut r = Rng::new(23);
        let tris = soup(&mut r, 3000, 0.5);
        let bvh = TriangleBvh::build(tris.len(), |i| tris[i]);
        let grown = Aabb::new(Vec3::splat(-12.0), Vec3::splat(12.0));
        let (mut scratch, mut out) = (RayPacket::default(), Vec::new());
        let (mut hits, mut coherent) = (0, 0);
        for k in 0..600 {
            let o = rand_in(&mut r, &grown);
            let axis = rand_in(&mut r, &Aabb::new(Vec3::splat(-8.0), Vec3::splat(8.0))) - o;
            let spread = [1e-3, 1e-2, 0.1, 1.0][k % 4] * axis.length();
            let mut rays: Vec<Ray> = (0..16)
                .map(|_| Ray::new(o, axis + rand_dir(&mut r) * r.range(0.0, spread), 0.0))
                .collect();
            match k % 10 {
                7 => rays[3].origin.x += 1.0,
                8 => rays[5].dir.y = 0.0,
                _ => {}
            }
            let tmin = if k % 3 == 0 { r.range(0.0, 5.0) } else { 0.0 };
            let tmax: Vec<f32> = rays
                .iter()
                .map(|_| {
                    if r.next_f32() < 0.3 {
                        r.range(1.0, 30.0)
                    } else {
                        f32::INFINITY
                    }
                })
                .collect();
            coherent += usize::from(Frustum::new(&rays).is_some());
            bvh.closest_hits(&rays, tmin, &tmax, &mut scratch, &mut out);
            assert_eq!(out.len(), rays.len());
            for ((ray, &tm), got) in rays.iter().zip(&tmax).zip(&out) {
                let bits = |h: Option<TriHit>| {
                    h.map(|h| (h.id, h.t.to_bits(), h.b1.to_bits(), h.b2.to_bits()))
                };
                assert_eq!(bits(*got), bits(bvh.closest_hit(ray, tmin, tm)), "{ray:?}");
                hits += usize::from(got.is_some());
            }
        }
        assert!(
            coherent > 300 && coherent < 600,
            "{coherent} packets traced together"
        );
        assert!(hits > 400, "{hits} hits");
    }

    /// A packet aimed from the centre of a closed sphere at a triangle's
    /// vertices and edge midpoints never slips through, as single rays don't.
    #[test]
    fn packets_are_watertight() {
        let tris = uv_sphere(48, 25, 1.0);
        let bvh = TriangleBvh::build(tris.len(), |i| tris[i]);
        let (mut scratch, mut out) = (RayPacket::default(), Vec::new());
        for t in &tris {
            let targets = [t[0], t[1], t[2], 0.5 * (t[0] + t[1]), 0.5 * (t[1] + t[2])];
            let rays: Vec<Ray> = targets
                .iter()
                .map(|&p| Ray::new(Vec3::ZERO, p, 0.0))
                .collect();
            bvh.closest_hits(&rays, 0.0, &[f32::INFINITY; 5], &mut scratch, &mut out);
            for (ray, h) in rays.iter().zip(&out) {
                let h = h.unwrap_or_else(|| panic!("{ray:?} slipped through"));
                assert_eq!(
                    Some(h.t),
                    bvh.closest_hit(ray, 0.0, f32::INFINITY).map(|a| a.t)
                );
            }
        }
    }

    /// Segments from a small box to a light-sized square, through a soup:
    /// testing only the gathered leaves reports the triangles full any-hit
    /// traversal reports, in the same order; a limit below the leaf count
    /// makes `gather` give up.
    #[test]
    fn gathered_leaves_report_what_traversal_reports() {
        let mut r = Rng::new(23);
        let mut set = LeafSet::default();
        let (mut crossed, mut gathered, mut leaves) = (0usize, 0usize, 0usize);
        for round in 0..30 {
            let tris = soup(&mut r, 300 + 40 * round, 1.5);
            let bvh = TriangleBvh::build(tris.len(), |i| tris[i]);
            let scene = Aabb::new(Vec3::splat(-12.0), Vec3::splat(12.0));
            let o = rand_in(&mut r, &scene);
            let origins = Aabb::new(o, o + Vec3::splat(r.range(0.0, 0.5)));
            let c = rand_in(&mut r, &scene);
            let half = Vec3::new(r.range(0.0, 3.0), 0.0, r.range(0.0, 3.0));
            let targets = Aabb::new(c - half, c + half);
            let shaft = Shaft::new(origins, targets).expect("finite boxes");
            assert!(bvh.gather(&shaft, usize::MAX, &mut set));
            gathered += set.len();
            leaves += bvh.stats().leaves;
            for _ in 0..200 {
                let (a, b) = (rand_in(&mut r, &origins), rand_in(&mut r, &targets));
                let ray = Ray::new(a, b - a, 0.0);
                let tmax = 1.0 - 1e-4;
                let mut full = Vec::new();
                bvh.any_hit(&ray, 0.0, tmax, |id| {
                    full.push(id);
                    false
                });
                let mut fast = Vec::new();
                bvh.any_hit_in(&set, &ray, 0.0, tmax, |id| {
                    fast.push(id);
                    false
                });
                assert_eq!(full, fast, "round {round}, ray {ray:?}");
                crossed += full.len();
                // Stopping at the first occluder agrees too.
                let first = |v: &Vec<u32>| v.first().copied();
                let mut stop = None;
                bvh.any_hit_in(&set, &ray, 0.0, tmax, |id| {
                    stop = Some(id);
                    true
                });
                assert_eq!(stop, first(&full));
            }
            if set.len() > 1 {
                assert!(!bvh.gather(&shaft, set.len() - 1, &mut set));
            }
        }
        // The case is not vacuous: segments cross triangles, and shafts
        // leave some leaves out.
        assert!(crossed > 1000, "{crossed} crossings");
        assert!(
            0 < gathered && gathered < leaves / 2,
            "{gathered} of {leaves}"
        );
    }

    /// A shaft far from every triangle gathers nothing.
    #[test]
    fn shaft_beside_the_soup_gathers_nothing() {
        let mut r = Rng::new(29);
        let tris = soup(&mut r, 500, 1.0);
        let bvh = TriangleBvh::build(tris.len(), |i| tris[i]);
        let far = Vec3::splat(100.0);
        let shaft = Shaft::new(
            Aabb::new(far, far),
            Aabb::new(far + Vec3::X, far + Vec3::ONE),
        )
        .expect("finite boxes");
        let mut set = LeafSet::default();
        assert!(bvh.gather(&shaft, 0, &mut set));
        assert!(set.is_empty());
        let ray = Ray::new(far, Vec3::ONE, 0.0);
        assert!(!bvh.any_hit_in(&set, &ray, 0.0, 1.0, |_| true));
    }
}
