//! A four-wide BVH over triangles stored in leaf order, intersected four at a
//! time: the structure that static meshes live in.
//!
//! The generic [`Bvh`](super::Bvh) knows primitives only through a closure,
//! so each triangle test goes through the scene's indirections (primitive →
//! object → mesh → index buffer → three vertices). Here the triangles are
//! copied into the tree itself, in the order its leaves visit them, as
//! packets of four in structure-of-arrays form (`Pack`: per vertex and
//! axis, one 4-lane vector), and the traversal tests all four with the same
//! SIMD instructions.
//!
//! # Layout
//! A `Node4` (128 bytes, two cache lines) holds the boxes of up to four
//! children as one 4-lane vector per axis and side, and four child
//! references: an interior child by node index, a leaf as a range of packs
//! (`LEAF` bit, up to 7 packs, first pack). Unused lanes have the empty box,
//! which no ray hits, and an empty leaf. The tree is the binned-SAH binary
//! tree of `accel::build` (leaf cost per started packet of four)
//! collapsed to four children per node by repeatedly opening the child of
//! largest surface area. Packs take 160 bytes for four triangles (padding
//! lanes hold NaN vertices, which never hit); for the bunny, 95% of the lanes
//! are used and nodes and packs take 54 bytes per triangle.
//!
//! # Traversal
//! Closest hit visits the nearest child hit first and pushes the others,
//! farthest first, with their entry distances, so that popped subtrees
//! beyond the closest hit so far are skipped unread. Any hit visits children
//! in storage order, as Embree's occlusion traversal does: most shadow rays
//! are not blocked and enter every subtree they hit anyway. The stack keeps
//! 24 entries inline (initialised for every ray, so it is kept small) and
//! spills deeper ones to the heap, which real trees never need. Batches of
//! independent rays can be traced with their traversals interleaved
//! (`stream`), which overlaps the memory waits of incoherent rays; runs of
//! a batch's rays from one point go as packets.
//!
//! # Exactness
//! The triangle test is [`intersect_triangle`]'s watertight algorithm
//! computed lane-wise with the same operations in the same order (no fused
//! multiply-adds), so each lane gives bit for bit what the scalar routine
//! gives, including the double-precision recomputation of edge functions
//! that round to zero; the box test is the [`Bvh`](super::Bvh)'s robust one
//! (NaN-skipping slab reduction, far distance enlarged by `1 + 2γ₃`), so the
//! tree returns exactly what a loop over all triangles returns. Of
//! triangles hit at exactly the same distance (a shared edge can give equal
//! `t`), the lowest index wins, as in that loop, so a ray's closest hit does
//! not depend on the order the leaves are visited in: alone, interleaved
//! and in a packet it is the same. The tests below check this against the
//! loop.
//!
//! [`intersect_triangle`]: crate::geometry::triangle::intersect_triangle

use super::build::{self, Config, Node, MAX_DEPTH};
use super::bvh::{max_skip_nan, min_skip_nan};
use super::shaft::Shaft;
use crate::geometry::triangle::{edge_functions_f64, RayShear};
use crate::math::{Aabb, Ray, Vec3};
use glam::{Vec3A, Vec4};
use rayon::prelude::*;

mod stream;

/// `1 + 2γ₃`, as in [`Bvh`](super::Bvh): makes the far slab distance conservative.
const TFAR_SCALE: f32 = 1.0 + 2.0 * (3.0 * f32::EPSILON * 0.5) / (1.0 - 3.0 * f32::EPSILON * 0.5);

/// Child reference bit marking a leaf.
const LEAF: u32 = 1 << 31;
/// Bits of a leaf reference holding its first pack.
const FIRST_MASK: u32 = (1 << 28) - 1;
/// A leaf holds at most this many packs (3 bits).
const MAX_PACKS: usize = 7;

/// Builder settings: leaves of up to four triangles (one packet) always,
/// up to 16 (four packets) when the SAH prefers them, cost per packet.
const CONFIG: Config = Config {
    max_leaf: 4,
    max_sah_leaf: 16,
    block_shift: 2,
};

/// Traversal stack entries kept inline. Each of at most `MAX_DEPTH` levels
/// pushes at most three children; real trees stay far below this, and deeper
/// stacks spill to the heap. A smaller array than the worst case matters: it
/// is initialised for every ray, and at 32 entries that is a call to
/// `memset` costing 2.5% of a 16-sample render (24 costs no more than 16).
const STACK: usize = 24;

/// The traversal stack: `STACK` entries inline, the rest (never, in
/// practice) on the heap.
struct Stack {
    inline: [(u32, f32); STACK],
    len: usize,
    spill: Vec<(u32, f32)>,
}

impl Stack {
    #[inline(always)]
    fn new() -> Self {
        Stack {
            inline: [(0, 0.0); STACK],
            len: 0,
            spill: Vec::new(),
        }
    }

    #[inline(always)]
    fn push(&mut self, e: (u32, f32)) {
        if self.len < STACK {
            self.inline[self.len] = e;
            self.len += 1;
        } else {
            self.spill_push(e);
        }
    }

    #[cold]
    fn spill_push(&mut self, e: (u32, f32)) {
        debug_assert!(self.spill.len() < 3 * MAX_DEPTH);
        self.spill.push(e);
    }

    #[inline(always)]
    fn pop(&mut self) -> Option<(u32, f32)> {
        if !self.spill.is_empty() {
            return self.spill.pop();
        }
        if self.len == 0 {
            return None;
        }
        self.len -= 1;
        Some(self.inline[self.len])
    }

    /// Pops the next subtree that can still hold a hit nearer than `tmax`,
    /// dropping those that start beyond it.
    #[inline(always)]
    fn pop_within(&mut self, tmax: f32) -> Option<u32> {
        loop {
            let (c, t) = self.pop()?;
            if t <= tmax * TFAR_SCALE {
                return Some(c);
            }
        }
    }

    /// Empties the stack for the next ray.
    fn clear(&mut self) {
        self.len = 0;
        self.spill.clear();
    }
}

/// Vectors of four lanes per node side and axis: a node has `4 * HALVES`
/// children. Eight-wide nodes (two vectors) measured no faster than four-wide
/// ones on the bunny, for coherent or incoherent rays, and build slower.
const HALVES: usize = 1;
/// Children per node.
const WIDTH: usize = 4 * HALVES;
// Shaft gathering reads nodes as single four-lane vectors.
const _: () = assert!(HALVES == 1);

/// The children of an interior node (128 bytes when four-wide).
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
struct Node4 {
    /// Per axis, `[lo, hi]` of the children, four lanes per vector.
    b: [[[Vec4; HALVES]; 2]; 3],
    /// Per lane: node index, or `LEAF | packs << 28 | first pack`.
    child: [u32; WIDTH],
}

impl Node4 {
    const EMPTY: Node4 = Node4 {
        b: [[[Vec4::INFINITY; HALVES], [Vec4::NEG_INFINITY; HALVES]]; 3],
        child: [LEAF; WIDTH],
    };

    fn set(&mut self, lane: usize, b: &Aabb, child: u32) {
        for axis in 0..3 {
            self.b[axis][0][lane / 4][lane % 4] = b.min[axis];
            self.b[axis][1][lane / 4][lane % 4] = b.max[axis];
        }
        self.child[lane] = child;
    }

    /// Lower corners of the four children, one vector per axis.
    fn lo(&self) -> [Vec4; 3] {
        [self.b[0][0][0], self.b[1][0][0], self.b[2][0][0]]
    }

    /// Upper corners of the four children, one vector per axis.
    fn hi(&self) -> [Vec4; 3] {
        [self.b[0][1][0], self.b[1][1][0], self.b[2][1][0]]
    }

    fn lane_box(&self, lane: usize) -> Aabb {
        let (lo, hi) = (self.lo(), self.hi());
        Aabb {
            min: Vec3::new(lo[0][lane], lo[1][lane], lo[2][lane]),
            max: Vec3::new(hi[0][lane], hi[1][lane], hi[2][lane]),
        }
    }

    /// Tests the boxes against the ray clipped to `[tmin, tmax]`: a bit
    /// mask of the children hit and their entry distances.
    #[inline(always)]
    fn hit(&self, r: &TraversalRay, tmin: Vec4, tmax: Vec4) -> (u32, [f32; WIDTH]) {
        let mut mask = 0;
        let mut t = [0.0; WIDTH];
        for h in 0..HALVES {
            // The near plane is `lo` for a positive direction, `hi` for a
            // negative one: chosen by index, so without a branch or blend.
            let slab = |axis: usize| {
                let n = r.near[axis] & 1;
                let near = self.b[axis][n][h];
                let far = self.b[axis][n ^ 1][h];
                (
                    (near - r.o[axis]) * r.inv[axis],
                    (far - r.o[axis]) * r.inv[axis],
                )
            };
            let (nx, fx) = slab(0);
            let (ny, fy) = slab(1);
            let (nz, fz) = slab(2);
            let near = max_skip_nan(nx, max_skip_nan(ny, max_skip_nan(nz, tmin)));
            let far = min_skip_nan(fx, min_skip_nan(fy, min_skip_nan(fz, tmax)));
            mask |= near.cmple(far * TFAR_SCALE).bitmask() << (4 * h);
            t[4 * h..4 * h + 4].copy_from_slice(&near.to_array());
        }
        (mask, t)
    }
}

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

/// A ray prepared for node and packet tests.
struct TraversalRay {
    /// Origin and reciprocal direction, one splat per axis.
    o: [Vec4; 3],
    inv: [Vec4; 3],
    /// Per axis: 1 if the direction is negative (then the hi planes are
    /// near), else 0.
    near: [usize; 3],
    /// The watertight test's axis permutation, shear constants and permuted origin.
    k: [usize; 3],
    s: [Vec4; 3],
    ok: [Vec4; 3],
}

impl TraversalRay {
    #[inline(always)]
    fn new(ray: &Ray) -> Self {
        let inv = ray.dir.recip();
        let sh = RayShear::new(ray);
        let o = ray.origin.to_array();
        TraversalRay {
            o: o.map(Vec4::splat),
            inv: inv.to_array().map(Vec4::splat),
            near: inv.to_array().map(|i| usize::from(i < 0.0)),
            k: [sh.kx, sh.ky, sh.kz],
            s: [sh.sx, sh.sy, sh.sz].map(Vec4::splat),
            ok: [o[sh.kx], o[sh.ky], o[sh.kz]].map(Vec4::splat),
        }
    }
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
    /// Node 0 is the root; empty when built over zero triangles.
    nodes: Vec<Node4>,
    packs: Vec<Pack>,
    bounds: Aabb,
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
        let (nodes, prims) = build::build_binary(&bounds, &CONFIG);
        drop(bounds);
        let Some(root) = nodes.first() else {
            return TriangleBvh::default();
        };
        let mut out = TriangleBvh {
            nodes: Vec::with_capacity(nodes.len() / 3 + 1),
            packs: Vec::with_capacity(n / 3 + 1),
            bounds: root.bounds,
            len: n,
        };
        if root.count > 0 {
            // A single leaf: a root node with one child.
            out.nodes.push(Node4::EMPTY);
            let leaf = out.leaf(&prims[root.first as usize..][..root.count as usize], &tri);
            out.nodes[0].set(0, &root.bounds, leaf);
        } else {
            out.collapse(&nodes, &prims, 0, &tri);
        }
        out
    }

    /// Emits the four-wide node for binary interior node `idx` (and its
    /// subtree, depth first) and returns its index.
    fn collapse(
        &mut self,
        bin: &[Node],
        prims: &[u32],
        idx: usize,
        tri: &impl Fn(usize) -> [Vec3; 3],
    ) -> u32 {
        let slot = self.nodes.len();
        self.nodes.push(Node4::EMPTY);
        let first = bin[idx].first as usize;
        let mut kids = [0; WIDTH];
        (kids[0], kids[1]) = (first, first + 1);
        let mut k = 2;
        // Open the interior child of largest area until there are WIDTH.
        while k < WIDTH {
            let open = (0..k)
                .filter(|&j| bin[kids[j]].count == 0)
                .max_by(|&a, &b| {
                    let area = |j: usize| bin[kids[j]].bounds.surface_area();
                    area(a).total_cmp(&area(b))
                });
            let Some(j) = open else { break };
            let f = bin[kids[j]].first as usize;
            kids[j] = f;
            kids[k] = f + 1;
            k += 1;
        }
        for (lane, &kid) in kids[..k].iter().enumerate() {
            let c = bin[kid];
            let child = if c.count > 0 {
                self.leaf(&prims[c.first as usize..][..c.count as usize], tri)
            } else {
                self.collapse(bin, prims, kid, tri)
            };
            self.nodes[slot].set(lane, &c.bounds, child);
        }
        slot as u32
    }

    /// Appends the packets of a leaf's triangles and returns its reference.
    fn leaf(&mut self, ids: &[u32], tri: &impl Fn(usize) -> [Vec3; 3]) -> u32 {
        let first = self.packs.len();
        for chunk in ids.chunks(4) {
            let mut p = Pack::EMPTY;
            for (lane, &id) in chunk.iter().enumerate() {
                for (vertex, pos) in tri(id as usize).iter().enumerate() {
                    for axis in 0..3 {
                        p.v[vertex][axis][lane] = pos[axis];
                    }
                }
                p.id[lane] = id;
            }
            self.packs.push(p);
        }
        let count = self.packs.len() - first;
        assert!(count <= MAX_PACKS, "leaf of {} triangles", ids.len());
        assert!(
            self.packs.len() <= FIRST_MASK as usize,
            "too many triangles for 28-bit packet indices"
        );
        LEAF | (count as u32) << 28 | first as u32
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
        self.bounds
    }

    pub fn stats(&self) -> TriStats {
        let leaves = self
            .nodes
            .iter()
            .flat_map(|n| n.child)
            .filter(|&c| c & LEAF != 0 && (c >> 28) & 7 != 0)
            .count();
        TriStats {
            triangles: self.len,
            nodes: self.nodes.len(),
            leaves,
            packs: self.packs.len(),
            bytes: self.nodes.len() * std::mem::size_of::<Node4>()
                + self.packs.len() * std::mem::size_of::<Pack>(),
        }
    }

    /// The closest triangle hit within `(tmin, tmax)`, with the result of
    /// [`intersect_triangle`](crate::geometry::triangle::intersect_triangle)
    /// for it. A ray with a non-finite origin or direction hits nothing.
    #[inline]
    pub fn closest_hit(&self, ray: &Ray, tmin: f32, tmax: f32) -> Option<TriHit> {
        let mut best = None;
        self.traverse_ray::<true>(ray, tmin, tmax, |p, r, tmax| {
            closest_in_pack(p, r, tmin, tmax, &mut best);
            false
        });
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
        out.clear();
        match Frustum::new(rays).filter(|_| !self.nodes.is_empty()) {
            Some(frustum) => {
                out.resize(rays.len(), None);
                let run = Run {
                    frustum: &frustum,
                    rays,
                    tmin,
                    tmax,
                };
                self.closest_packet(&run, scratch, out);
            }
            None => {
                let one = |(r, &t): (&Ray, &f32)| self.closest_hit(r, tmin, t);
                out.extend(rays.iter().zip(tmax).map(one));
            }
        }
    }

    /// [`closest_hits`](Self::closest_hits) for a run (the tree not
    /// empty), into `out` (one entry per ray, `None` on entry).
    fn closest_packet(&self, run: &Run, scratch: &mut RayPacket, out: &mut [Option<TriHit>]) {
        let tmin = run.tmin;
        let tmin4 = Vec4::splat(tmin);
        self.traverse::<true, true>(
            scratch.reset(run.tmax),
            |node, tmax| run.frustum.hit(node, tmin4, Vec4::splat(tmax)),
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
    fn any_hit_packet(
        &self,
        run: &Run,
        scratch: &mut RayPacket,
        mut hit: impl FnMut(usize, u32) -> bool,
        out: &mut [bool],
    ) {
        let tmin = run.tmin;
        let tmin4 = Vec4::splat(tmin);
        self.traverse::<false, true>(
            scratch.reset(run.tmax),
            |node, tmax| run.frustum.hit(node, tmin4, Vec4::splat(tmax)),
            |at, packs, widest| {
                let (prepared, limits) = scratch.prepared(run.rays);
                let rays = prepared.iter().zip(limits.iter_mut()).zip(out.iter_mut());
                for (i, ((r, tmax), blocked)) in rays.enumerate() {
                    if *blocked || !reaches(at, r, tmin4, *tmax) {
                        continue;
                    }
                    if packs
                        .iter()
                        .any(|p| pack_any_hit(p, r, tmin, *tmax, &mut |id| hit(i, id)))
                    {
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
    #[inline]
    pub fn any_hit(
        &self,
        ray: &Ray,
        tmin: f32,
        tmax: f32,
        mut hit: impl FnMut(u32) -> bool,
    ) -> bool {
        self.traverse_ray::<false>(ray, tmin, tmax, |p, r, tmax| {
            pack_any_hit(p, r, tmin, *tmax, &mut hit)
        })
    }

    /// Collects into `out` the leaves whose boxes may overlap `shaft`, in
    /// the order [`any_hit`](Self::any_hit) visits leaves (depth first, children in
    /// storage order). Returns false, with `out` incomplete, once more than
    /// `limit` leaves are found.
    pub fn gather(&self, shaft: &Shaft, limit: usize, out: &mut LeafSet) -> bool {
        out.clear();
        if self.nodes.is_empty() {
            return true;
        }
        out.push_lanes(0, shaft.overlaps4(&self.nodes[0].lo(), &self.nodes[0].hi()));
        while let Some(e) = out.stack.pop() {
            let node = &self.nodes[(e >> 2) as usize];
            let lane = (e & 3) as usize;
            let child = node.child[lane];
            if child & LEAF == 0 {
                let n = &self.nodes[child as usize];
                out.push_lanes(child, shaft.overlaps4(&n.lo(), &n.hi()));
            } else if (child >> 28) & 7 != 0 {
                if out.len == limit {
                    return false;
                }
                out.push_leaf(node, lane);
            }
        }
        true
    }

    /// [`any_hit`](Self::any_hit) for a ray that lies in the shaft `set` was
    /// gathered for: tests only the leaves of `set` (four boxes at a time),
    /// and reports the same triangles in the same order as `any_hit`.
    pub fn any_hit_in(
        &self,
        set: &LeafSet,
        ray: &Ray,
        tmin: f32,
        tmax: f32,
        mut hit: impl FnMut(u32) -> bool,
    ) -> bool {
        if set.len == 0 || !(ray.origin.is_finite() && ray.dir.is_finite()) {
            return false;
        }
        let r = TraversalRay::new(ray);
        let (tmin4, tmax4) = (Vec4::splat(tmin), Vec4::splat(tmax));
        for group in &set.groups {
            let (mut mask, _) = group.hit(&r, tmin4, tmax4);
            while mask != 0 {
                let leaf = group.child[mask.trailing_zeros() as usize];
                mask &= mask - 1;
                for p in self.leaf_packs(leaf) {
                    if pack_any_hit(p, &r, tmin, tmax, &mut hit) {
                        return true;
                    }
                }
            }
        }
        false
    }

    /// Whether any triangle is crossed within `(tmin, tmax)`.
    #[inline]
    pub fn occluded(&self, ray: &Ray, tmin: f32, tmax: f32) -> bool {
        self.any_hit(ray, tmin, tmax, |_| true)
    }

    /// The packets of the leaf `child` refers to.
    #[inline(always)]
    fn leaf_packs(&self, child: u32) -> &[Pack] {
        let first = (child & FIRST_MASK) as usize;
        let count = ((child >> 28) & 7) as usize;
        &self.packs[first..first + count]
    }

    /// [`traverse`](Self::traverse) for one ray: `leaf` is called for each
    /// packet of the leaves it reaches, with the ray's current `tmax`.
    #[inline(always)]
    fn traverse_ray<const ORDERED: bool>(
        &self,
        ray: &Ray,
        tmin: f32,
        tmax: f32,
        mut leaf: impl FnMut(&Pack, &TraversalRay, &mut f32) -> bool,
    ) -> bool {
        if self.nodes.is_empty() || !(ray.origin.is_finite() && ray.dir.is_finite()) {
            return false;
        }
        let r = TraversalRay::new(ray);
        let tmin4 = Vec4::splat(tmin);
        self.traverse::<ORDERED, false>(
            tmax,
            |node, tmax| node.hit(&r, tmin4, Vec4::splat(tmax)),
            |_, packs, tmax| packs.iter().any(|p| leaf(p, &r, tmax)),
        )
    }

    /// Visits the leaves whose boxes `hit_node` reports hit, skipping subtrees
    /// that start beyond `tmax` (which `leaf` may shrink), nearer children
    /// first if `ORDERED`. `hit_node(node, tmax)` gives the mask of children
    /// hit and their entry distances; `leaf(parent, lane, packs, tmax)` gets
    /// a leaf's packets and where its box is. Stops and returns true when
    /// `leaf` returns true. The tree must not be empty.
    ///
    /// With `BOXED`, `cur` and stack entries name a leaf by its parent and
    /// lane (`LEAF | parent << 2 | lane`) rather than by its packets, so that
    /// the leaf's box is at hand for `leaf` (else it gets `None`): packets
    /// use it, single rays need not pay the extra load (10–19% on the
    /// Whitted and 64-shadow-ray frames). Interior nodes are fewer than packets, whose
    /// count `leaf` keeps below 2²⁸, so the parent fits in 29 bits.
    #[inline(always)]
    fn traverse<const ORDERED: bool, const BOXED: bool>(
        &self,
        tmax: f32,
        hit_node: impl Fn(&Node4, f32) -> (u32, [f32; WIDTH]),
        mut leaf: impl FnMut(Option<(&Node4, usize)>, &[Pack], &mut f32) -> bool,
    ) -> bool {
        let mut tmax = tmax;
        let mut stack = Stack::new();
        let mut cur = 0u32;
        loop {
            if cur & LEAF == 0 {
                let node = &self.nodes[cur as usize];
                let (mask, t) = hit_node(node, tmax);
                let at = |i: usize| {
                    let c = node.child[i];
                    if !BOXED || c & LEAF == 0 {
                        c
                    } else {
                        LEAF | cur << 2 | i as u32
                    }
                };
                if mask != 0 {
                    cur = descend::<ORDERED>(mask, &t, at, &mut stack);
                    continue;
                }
            } else {
                let (child, at) = if BOXED {
                    let parent = &self.nodes[((cur & !LEAF) >> 2) as usize];
                    let lane = (cur & 3) as usize;
                    (parent.child[lane], Some((parent, lane)))
                } else {
                    (cur, None)
                };
                if leaf(at, self.leaf_packs(child), &mut tmax) {
                    return true;
                }
            }
            match stack.pop_within(tmax) {
                Some(c) => cur = c,
                None => return false,
            }
        }
    }
}

/// The child to visit after an interior node whose children in `mask` (not
/// empty) were hit at entry distances `t`; the other children hit are
/// pushed on `stack`. `at(i)` is the reference of child `i`.
///
/// Unordered (any hit), the first child in storage order is next and the
/// others are pushed last first, with no distance (`tmax` never shrinks
/// there), so they pop in storage order: the order `gather` lists leaves
/// in, so that `any_hit_in` reports what `any_hit` does. Ordered, the
/// nearest is next and the others are pushed farthest first.
#[inline(always)]
fn descend<const ORDERED: bool>(
    mask: u32,
    t: &[f32; WIDTH],
    at: impl Fn(usize) -> u32,
    stack: &mut Stack,
) -> u32 {
    let i0 = mask.trailing_zeros() as usize;
    let rest = mask & (mask - 1);
    if rest == 0 {
        return at(i0);
    }
    if !ORDERED {
        let mut m = rest;
        while m != 0 {
            let i = 31 - m.leading_zeros() as usize;
            stack.push((at(i), f32::NEG_INFINITY));
            m &= !(1 << i);
        }
        return at(i0);
    }
    let i1 = rest.trailing_zeros() as usize;
    if rest & (rest - 1) == 0 {
        let (n, f) = if t[i1] < t[i0] { (i1, i0) } else { (i0, i1) };
        stack.push((at(f), t[f]));
        return at(n);
    }
    // More: insertion-sort by distance, farthest first.
    let mut e = [(0u32, 0f32); WIDTH];
    let mut k = 0;
    let mut m = mask;
    while m != 0 {
        let i = m.trailing_zeros() as usize;
        e[k] = (at(i), t[i]);
        let mut j = k;
        while j > 0 && e[j - 1].1 < e[j].1 {
            e.swap(j - 1, j);
            j -= 1;
        }
        k += 1;
        m &= m - 1;
    }
    for &entry in &e[..k - 1] {
        stack.push(entry);
    }
    e[k - 1].0
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

/// Whether ray `r` hits, within `[tmin, tmax]`, the box of the leaf a
/// packet reached at lane `lane` of `parent` (always, without one).
#[inline(always)]
fn reaches(at: Option<(&Node4, usize)>, r: &TraversalRay, tmin: Vec4, tmax: f32) -> bool {
    at.is_none_or(|(parent, lane)| parent.hit(r, tmin, Vec4::splat(tmax)).0 >> lane & 1 != 0)
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

/// Per-worker buffers of [`TriangleBvh::closest_hits`], kept by the caller
/// so that tracing a packet allocates nothing once warm.
#[derive(Default)]
pub struct RayPacket {
    rays: Vec<TraversalRay>,
    tmax: Vec<f32>,
}

impl RayPacket {
    /// Starts a packet of rays with limits `tmax`; returns the widest.
    fn reset(&mut self, tmax: &[f32]) -> f32 {
        self.rays.clear();
        self.tmax.clear();
        self.tmax.extend_from_slice(tmax);
        self.widest()
    }

    /// The largest limit of a ray of the packet.
    fn widest(&self) -> f32 {
        self.tmax.iter().fold(f32::NEG_INFINITY, |a, &b| a.max(b))
    }

    /// The packet's rays prepared for per-ray tests, and their limits. Rays
    /// are prepared when the packet first reaches a leaf: most packets that
    /// miss the mesh never do.
    fn prepared(&mut self, rays: &[Ray]) -> (&[TraversalRay], &mut [f32]) {
        if self.rays.is_empty() {
            self.rays.extend(rays.iter().map(TraversalRay::new));
        }
        (&self.rays, &mut self.tmax)
    }
}

/// Rays from one point traced as one packet: the frustum around them, the
/// rays and the interval each is traced over (`tmax` one per ray).
struct Run<'a> {
    frustum: &'a Frustum,
    rays: &'a [Ray],
    tmin: f32,
    tmax: &'a [f32],
}

/// Rays leaving one origin with directions of the same signs, bounded by the
/// range of their reciprocal directions per axis: interval arithmetic on the
/// slab test.
///
/// For a plane at signed offset `d` from the common origin, a ray's slab
/// distance is `d · inv`, rounded once. Rounding is monotone, so over the
/// packet it lies between `d · lo` and `d · hi` (in whichever order the
/// sign of `d` gives) exactly, not just approximately: the smallest near
/// distance and the largest far distance bound every ray's, and a box any
/// ray's robust test accepts is accepted here. The entry distance returned
/// is at most every ray's, so culling a subtree by it against the largest
/// `tmax` of the packet never drops a hit.
struct Frustum {
    o: [Vec4; 3],
    lo: [Vec4; 3],
    hi: [Vec4; 3],
    /// Per axis: 1 if the directions are negative, as in [`TraversalRay`].
    near: [usize; 3],
}

impl Frustum {
    /// `None` unless the rays share their origin (equal coordinates; a zero
    /// of either sign gives the same slab distances), and have finite
    /// directions with finite reciprocals of one sign per axis.
    fn new(rays: &[Ray]) -> Option<Frustum> {
        let first = rays.first()?;
        let o = Vec3A::from(first.origin);
        let (mut lo, mut hi) = (Vec3A::INFINITY, Vec3A::NEG_INFINITY);
        // Checked for all rays without a branch per ray, in SIMD registers
        // (`Vec3A`): sets are small and nearly always coherent (a pixel's
        // camera rays, a batch's run), and scalar checks cost 80
        // instructions a ray.
        let mut ok = o.is_finite_mask();
        for r in rays {
            let dir = Vec3A::from(r.dir);
            let inv = dir.recip();
            ok &= Vec3A::from(r.origin).cmpeq(o) & dir.is_finite_mask() & inv.is_finite_mask();
            (lo, hi) = (lo.min(inv), hi.max(inv));
        }
        // One sign per axis: the smallest and the largest reciprocal (all
        // finite, so none is zero) agree.
        let sign = lo.is_negative_bitmask();
        (ok.all() && sign == hi.is_negative_bitmask()).then(|| Frustum {
            o: o.to_array().map(Vec4::splat),
            lo: lo.to_array().map(Vec4::splat),
            hi: hi.to_array().map(Vec4::splat),
            near: [0, 1, 2].map(|axis| (sign >> axis & 1) as usize),
        })
    }

    /// [`Node4::hit`] for the whole packet: the children that some ray may
    /// hit within `[tmin, tmax]`, and entry distances no larger than any ray's.
    #[inline(always)]
    fn hit(&self, node: &Node4, tmin: Vec4, tmax: Vec4) -> (u32, [f32; WIDTH]) {
        let slab = |axis: usize| {
            let n = self.near[axis];
            let dn = node.b[axis][n][0] - self.o[axis];
            let df = node.b[axis][n ^ 1][0] - self.o[axis];
            let (lo, hi) = (self.lo[axis], self.hi[axis]);
            ((dn * lo).min(dn * hi), (df * lo).max(df * hi))
        };
        let (nx, fx) = slab(0);
        let (ny, fy) = slab(1);
        let (nz, fz) = slab(2);
        let near = max_skip_nan(nx, max_skip_nan(ny, max_skip_nan(nz, tmin)));
        let far = min_skip_nan(fx, min_skip_nan(fy, min_skip_nan(fz, tmax)));
        (near.cmple(far * TFAR_SCALE).bitmask(), near.to_array())
    }
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

/// The leaves of a [`TriangleBvh`] a [`Shaft`] may reach, in any-hit order,
/// with their boxes four to a node so that a ray tests four at once. Kept by
/// the caller and reused, so that gathering allocates nothing once warm.
#[derive(Clone, Debug, Default)]
pub struct LeafSet {
    groups: Vec<Node4>,
    len: usize,
    /// Work list of `gather`: `node << 2 | lane`.
    stack: Vec<u32>,
}

impl LeafSet {
    /// Number of leaves.
    pub fn len(&self) -> usize {
        self.len
    }

    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    fn clear(&mut self) {
        self.groups.clear();
        self.stack.clear();
        self.len = 0;
    }

    /// Schedules the lanes of `mask` of `node`, so that they pop in lane order.
    fn push_lanes(&mut self, node: u32, mask: u32) {
        for lane in (0..WIDTH as u32).rev() {
            if mask >> lane & 1 != 0 {
                self.stack.push(node << 2 | lane);
            }
        }
    }

    fn push_leaf(&mut self, node: &Node4, lane: usize) {
        if self.len == self.groups.len() * WIDTH {
            self.groups.push(Node4::EMPTY);
        }
        let b = node.lane_box(lane);
        if let Some(g) = self.groups.last_mut() {
            g.set(self.len % WIDTH, &b, node.child[lane]);
        }
        self.len += 1;
    }
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

    #[test]
    fn stack_spills_in_order() {
        let mut s = Stack::new();
        for i in 0..3 * MAX_DEPTH as u32 {
            s.push((i, i as f32));
        }
        for i in (0..3 * MAX_DEPTH as u32).rev() {
            assert_eq!(s.pop(), Some((i, i as f32)));
        }
        assert_eq!(s.pop(), None);
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
