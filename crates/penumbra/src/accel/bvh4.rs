//! The four-wide bounding volume hierarchy every ray query of the scene goes
//! through: one node layout and one traversal kernel, generic over what its
//! leaves hold (packets of four triangles for meshes, objects for the scene's
//! top level).
//!
//! # Layout
//! A `Node4` (128 bytes, two cache lines) holds the boxes of up to four
//! children as one 4-lane vector per axis and side, and four child
//! references: an interior child by node index, a leaf as a range of items
//! (`LEAF` bit, up to 7 items, first item). Unused lanes have the empty box,
//! which no ray hits, and an empty leaf. The tree is the binned-SAH binary
//! tree of `accel::build` collapsed to four children per node by repeatedly
//! opening the child of largest surface area.
//!
//! # Traversal
//! One step (`Bvh4::step`) either tests a node's four boxes and descends,
//! or hands a leaf's items to the caller, then pops the stack. Every query
//! is that step in a loop: a single ray, a packet of rays from one point
//! (the box test of the packet's frustum in place of the ray's), and the
//! interleaved walks of a batch of incoherent rays. Closest hit (`ORDERED`)
//! visits the nearest child hit first and pushes the others, farthest
//! first, with their entry distances, so that popped subtrees beyond the
//! closest hit so far are skipped unread. Any hit visits children in
//! storage order, as Embree's occlusion traversal does: most shadow rays
//! are not blocked and enter every subtree they hit anyway. The stack keeps
//! 24 entries inline (initialised for every ray, so it is kept small) and
//! spills deeper ones to the heap, which real trees never need.
//!
//! # Robust box test
//! Near and far planes are chosen by the sign of the reciprocal direction,
//! so a zero direction component (reciprocal ±inf) gives ±inf slab
//! distances, except when the origin lies exactly on a plane: then
//! `0 * inf = NaN`. The slab distances are reduced with a `max` that skips
//! NaN, so such a slab constrains nothing, which treats a ray running along
//! a face (or inside a flat box) as inside that slab. Only false positives
//! can result, never false misses. The far distance is enlarged by
//! `1 + 2γ₃` (γₙ = nε/(1 − nε)) as in "Robust BVH Ray Traversal" (JCGT
//! 2013), which bounds the rounding of the slab distances, so a box is
//! never missed by a ray that touches it; popped subtrees are culled against
//! the same enlarged bound, so the tree returns exactly what a loop over
//! all its items returns.

use super::build::{self, Config, Node, MAX_DEPTH};
use super::shaft::Shaft;
use crate::geometry::triangle::RayShear;
use crate::math::{Aabb, Ray, Vec3};
use crate::simd::KernelSet;
use glam::{Vec3A, Vec4};

/// `1 + 2γ₃` with γ₃ = 3ε/(1 − 3ε), ε = 2⁻²⁴: the factor that makes the far
/// slab distance conservative under the rounding of `(plane - o) * inv_dir`.
pub(super) const TFAR_SCALE: f32 =
    1.0 + 2.0 * (3.0 * f32::EPSILON * 0.5) / (1.0 - 3.0 * f32::EPSILON * 0.5);

/// Child reference bit marking a leaf.
pub(super) const LEAF: u32 = 1 << 31;
/// Bits of a leaf reference holding its first item.
pub(super) const FIRST_MASK: u32 = (1 << 28) - 1;
/// A leaf holds at most this many items (3 bits).
pub(super) const MAX_ITEMS: usize = 7;

/// Builder settings for one item per primitive (objects): leaves of up to
/// four always (the SAH cost model is too coarse to gain anything below
/// that), up to `MAX_ITEMS` when the SAH prefers them.
pub(super) const ONE_PER_ITEM: Config = Config {
    max_leaf: 4,
    max_sah_leaf: MAX_ITEMS,
    block_shift: 0,
};

/// Lane-wise `max(a, b)` for a `b` free of NaN, returning `b` where `a` is
/// NaN: such a slab constrains nothing.
///
/// On x86-64, glam's `max` is `MAXPS`, which returns its second operand when
/// either is NaN: exactly this, in one instruction (and glam's scalar fallback
/// uses `f32::max`, which ignores NaN as well). glam leaves NaN behaviour
/// unspecified, so the grazing-ray tests pin it down. Elsewhere (NEON's max
/// propagates NaN) the NaN lanes are selected away explicitly.
#[inline(always)]
pub(super) fn max_skip_nan(a: Vec4, b: Vec4) -> Vec4 {
    if cfg!(target_arch = "x86_64") {
        a.max(b)
    } else {
        Vec4::select(a.cmpeq(a), a.max(b), b)
    }
}

/// Lane-wise `min(a, b)` returning `b` where `a` is NaN (`MINPS` on x86-64):
/// the counterpart of [`max_skip_nan`] for far distances.
#[inline(always)]
pub(super) fn min_skip_nan(a: Vec4, b: Vec4) -> Vec4 {
    if cfg!(target_arch = "x86_64") {
        a.min(b)
    } else {
        Vec4::select(a.cmpeq(a), a.min(b), b)
    }
}

/// Whether `f` holds for an item of `items`, tried in order: `any` as a
/// loop that is always inlined, so that a kernel set's entry point
/// compiles the leaf tests with its own instructions (a call to
/// `Iterator::any` may be left out of line, compiled for the baseline).
#[inline(always)]
pub(super) fn any_of<T>(items: &[T], mut f: impl FnMut(&T) -> bool) -> bool {
    for x in items {
        if f(x) {
            return true;
        }
    }
    false
}

/// [`any_of`] trying the items last to first.
#[inline(always)]
pub(super) fn any_of_rev<T>(items: &[T], mut f: impl FnMut(&T) -> bool) -> bool {
    for x in items.iter().rev() {
        if f(x) {
            return true;
        }
    }
    false
}

/// Traversal stack entries kept inline. Each of at most `MAX_DEPTH` levels
/// pushes at most three children; real trees stay far below this, and deeper
/// stacks spill to the heap. A smaller array than the worst case matters: it
/// is initialised for every ray, and at 32 entries that is a call to
/// `memset` costing 2.5% of a 16-sample render (24 costs no more than 16).
pub(super) const STACK: usize = 24;

/// The traversal stack: `STACK` entries inline, the rest (never, in
/// practice) on the heap.
pub(super) struct Stack {
    inline: [(u32, f32); STACK],
    len: usize,
    spill: Vec<(u32, f32)>,
}

impl Stack {
    #[inline(always)]
    pub(super) fn new() -> Self {
        Stack {
            inline: [(0, 0.0); STACK],
            len: 0,
            spill: Vec::new(),
        }
    }

    #[inline(always)]
    pub(super) fn push(&mut self, e: (u32, f32)) {
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
    pub(super) fn pop(&mut self) -> Option<(u32, f32)> {
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
    pub(super) fn pop_within(&mut self, tmax: f32) -> Option<u32> {
        loop {
            let (c, t) = self.pop()?;
            if t <= tmax * TFAR_SCALE {
                return Some(c);
            }
        }
    }

    /// Empties the stack for the next ray.
    pub(super) fn clear(&mut self) {
        self.len = 0;
        self.spill.clear();
    }
}

/// Vectors of four lanes per node side and axis: a node has `4 * HALVES`
/// children. Eight-wide nodes (two vectors) measured no faster than four-wide
/// ones on the bunny, for coherent or incoherent rays, and build slower.
pub(super) const HALVES: usize = 1;
/// Children per node.
pub(super) const WIDTH: usize = 4 * HALVES;
// Shaft gathering reads nodes as single four-lane vectors.
const _: () = assert!(HALVES == 1);

/// The children of an interior node (128 bytes when four-wide).
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
pub(super) struct Node4 {
    /// Per axis, `[lo, hi]` of the children, four lanes per vector.
    pub b: [[[Vec4; HALVES]; 2]; 3],
    /// Per lane: node index, or `LEAF | items << 28 | first item`.
    pub child: [u32; WIDTH],
}

impl Node4 {
    pub(super) const EMPTY: Node4 = Node4 {
        b: [[[Vec4::INFINITY; HALVES], [Vec4::NEG_INFINITY; HALVES]]; 3],
        child: [LEAF; WIDTH],
    };

    pub(super) fn set(&mut self, lane: usize, b: &Aabb, child: u32) {
        for axis in 0..3 {
            self.b[axis][0][lane / 4][lane % 4] = b.min[axis];
            self.b[axis][1][lane / 4][lane % 4] = b.max[axis];
        }
        self.child[lane] = child;
    }

    /// Lower corners of the four children, one vector per axis.
    pub(super) fn lo(&self) -> [Vec4; 3] {
        [self.b[0][0][0], self.b[1][0][0], self.b[2][0][0]]
    }

    /// Upper corners of the four children, one vector per axis.
    pub(super) fn hi(&self) -> [Vec4; 3] {
        [self.b[0][1][0], self.b[1][1][0], self.b[2][1][0]]
    }

    pub(super) fn lane_box(&self, lane: usize) -> Aabb {
        let (lo, hi) = (self.lo(), self.hi());
        Aabb {
            min: Vec3::new(lo[0][lane], lo[1][lane], lo[2][lane]),
            max: Vec3::new(hi[0][lane], hi[1][lane], hi[2][lane]),
        }
    }

    /// Tests the boxes against the ray clipped to `[tmin, tmax]`: a bit
    /// mask of the children hit and their entry distances.
    #[inline(always)]
    pub(super) fn hit(&self, r: &TraversalRay, tmin: Vec4, tmax: Vec4) -> (u32, [f32; WIDTH]) {
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

/// A ray prepared for node and packet tests.
pub(super) struct TraversalRay {
    /// Origin and reciprocal direction, one splat per axis.
    pub o: [Vec4; 3],
    pub inv: [Vec4; 3],
    /// Per axis: 1 if the direction is negative (then the hi planes are
    /// near), else 0.
    pub near: [usize; 3],
    /// The watertight test's axis permutation, shear constants and permuted origin.
    pub k: [usize; 3],
    pub s: [Vec4; 3],
    pub ok: [Vec4; 3],
}

impl TraversalRay {
    #[inline(always)]
    pub(super) fn new(ray: &Ray) -> Self {
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

/// A four-wide BVH whose leaves hold items of type `P`; see the module docs.
#[derive(Clone, Debug)]
pub struct Bvh4<P> {
    /// Node 0 is the root; empty when built over zero primitives.
    nodes: Vec<Node4>,
    /// Leaf items, in leaf order.
    items: Vec<P>,
    bounds: Aabb,
    /// The items of the only leaf, when the tree is one leaf.
    single: Option<Box<[P]>>,
}

impl<P> Default for Bvh4<P> {
    fn default() -> Self {
        Bvh4 {
            nodes: Vec::new(),
            items: Vec::new(),
            bounds: Aabb::EMPTY,
            single: None,
        }
    }
}

/// Where one traversal is: the node or leaf to visit next, the limit of
/// its interval, and the subtrees it deferred.
pub(super) struct Cursor {
    pub cur: u32,
    pub tmax: f32,
    pub stack: Stack,
}

impl Cursor {
    #[inline(always)]
    pub fn new(tmax: f32) -> Self {
        Cursor {
            cur: 0,
            tmax,
            stack: Stack::new(),
        }
    }

    /// Starts over at the root for another ray.
    pub fn restart(&mut self, tmax: f32) {
        (self.cur, self.tmax) = (0, tmax);
        self.stack.clear();
    }
}

impl<P: Copy> Bvh4<P> {
    /// Builds the tree over primitives with boxes `prim_bounds` (finite).
    /// `leaf(ids, items)` appends the items of a leaf holding primitives
    /// `ids` (at most `MAX_ITEMS` of them): one per primitive, or packets.
    ///
    /// # Panics
    /// If there are 2²⁸ items or more.
    pub(super) fn build(
        prim_bounds: &[Aabb],
        cfg: &Config,
        mut leaf: impl FnMut(&[u32], &mut Vec<P>),
    ) -> Self {
        let (nodes, prims) = build::build_binary(prim_bounds, cfg);
        let Some(root) = nodes.first() else {
            return Bvh4::default();
        };
        let mut out = Bvh4 {
            nodes: Vec::with_capacity(nodes.len() / 3 + 1),
            items: Vec::with_capacity(prims.len() / 3 + 1),
            bounds: root.bounds,
            single: None,
        };
        if root.count > 0 {
            // A single leaf: a root node with one child.
            out.nodes.push(Node4::EMPTY);
            let ids = &prims[root.first as usize..][..root.count as usize];
            let child = out.leaf(ids, &mut leaf);
            out.nodes[0].set(0, &root.bounds, child);
            out.single = Some(out.leaf_items(child).into());
        } else {
            out.collapse(&nodes, &prims, 0, &mut leaf);
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
        leaf: &mut impl FnMut(&[u32], &mut Vec<P>),
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
                self.leaf(&prims[c.first as usize..][..c.count as usize], leaf)
            } else {
                self.collapse(bin, prims, kid, leaf)
            };
            self.nodes[slot].set(lane, &c.bounds, child);
        }
        slot as u32
    }

    /// Appends the items of a leaf and returns its reference.
    fn leaf(&mut self, ids: &[u32], leaf: &mut impl FnMut(&[u32], &mut Vec<P>)) -> u32 {
        let first = self.items.len();
        leaf(ids, &mut self.items);
        let count = self.items.len() - first;
        assert!(count <= MAX_ITEMS, "leaf of {} items", count);
        assert!(
            self.items.len() <= FIRST_MASK as usize,
            "too many items for 28-bit indices"
        );
        LEAF | (count as u32) << 28 | first as u32
    }

    /// True for the tree over no primitives.
    #[inline(always)]
    pub(super) fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// Box around all primitives ([`Aabb::EMPTY`] when there are none).
    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    /// Interior nodes, leaves (that hold items) and items.
    pub(super) fn counts(&self) -> (usize, usize, usize) {
        let leaves = self
            .nodes
            .iter()
            .flat_map(|n| n.child)
            .filter(|&c| c & LEAF != 0 && (c >> 28) & 7 != 0)
            .count();
        (self.nodes.len(), leaves, self.items.len())
    }

    /// Memory of nodes and items.
    pub(super) fn bytes(&self) -> usize {
        self.nodes.len() * std::mem::size_of::<Node4>()
            + self.items.len() * std::mem::size_of::<P>()
    }

    /// The items of the leaf `child` refers to.
    #[inline(always)]
    pub(super) fn leaf_items(&self, child: u32) -> &[P] {
        let first = (child & FIRST_MASK) as usize;
        let count = ((child >> 28) & 7) as usize;
        &self.items[first..first + count]
    }

    /// The node `cur` refers to, when it is an interior node.
    #[inline(always)]
    pub(super) fn node(&self, cur: u32) -> Option<&Node4> {
        if cur & LEAF == 0 {
            self.nodes.get(cur as usize)
        } else {
            None
        }
    }

    /// The first item of the leaf `cur` refers to, when it is a leaf.
    #[inline(always)]
    pub(super) fn first_item(&self, cur: u32) -> Option<&P> {
        if cur & LEAF == 0 {
            None
        } else {
            self.items.get((cur & FIRST_MASK) as usize)
        }
    }

    /// One ray through the tree: `leaf` is called with the items of each
    /// leaf it reaches (in the order of [`step`](Self::step)), the ray
    /// prepared for tests, and its current `tmax`, which it may shrink; it
    /// returns true to stop. Returns whether it stopped. A ray with a
    /// non-finite origin or direction reaches nothing.
    #[inline(always)]
    pub(super) fn traverse_ray<const ORDERED: bool>(
        &self,
        ray: &Ray,
        tmin: f32,
        tmax: f32,
        leaf: impl FnMut(&[P], &TraversalRay, &mut f32) -> bool,
    ) -> bool {
        let r = self.prepare(ray);
        r.is_some_and(
            #[inline(always)]
            |r| self.traverse_prepared::<ORDERED>(&r, tmin, tmax, leaf),
        )
    }

    /// The ray prepared for the tree's tests; `None` when the tree is
    /// empty or the ray's origin or direction is not finite (it reaches
    /// nothing).
    #[inline(always)]
    pub(super) fn prepare(&self, ray: &Ray) -> Option<TraversalRay> {
        let finite = ray.origin.is_finite() && ray.dir.is_finite();
        (finite && !self.nodes.is_empty()).then(|| TraversalRay::new(ray))
    }

    /// [`traverse_ray`](Self::traverse_ray) for a tree whose items are
    /// tested with the ray itself: a tree of one leaf (a few objects) has
    /// its items tested directly, without preparing the ray for box tests
    /// (nearly every ray enters the box around them all), and `leaf` gets
    /// no prepared ray then; a ray with a non-finite origin or direction
    /// is given to the items' own tests, which then find no hit.
    #[inline(always)]
    pub(super) fn traverse_items<const ORDERED: bool>(
        &self,
        kernels: KernelSet,
        ray: &Ray,
        tmin: f32,
        tmax: f32,
        mut leaf: impl FnMut(&[P], Option<&TraversalRay>, &mut f32) -> bool,
    ) -> bool {
        if let Some(items) = self.single_leaf() {
            let mut tmax = tmax;
            return leaf(items, None, &mut tmax);
        }
        self.traverse_outlined::<ORDERED>(kernels, ray, tmin, tmax, leaf)
    }

    /// The traversal of [`traverse_items`](Self::traverse_items), kept out
    /// of line so that the callers' code for a tree of one leaf stays small,
    /// and so compiled again for the kernel set.
    #[inline(never)]
    fn traverse_outlined<const ORDERED: bool>(
        &self,
        kernels: KernelSet,
        ray: &Ray,
        tmin: f32,
        tmax: f32,
        mut leaf: impl FnMut(&[P], Option<&TraversalRay>, &mut f32) -> bool,
    ) -> bool {
        kernels.run(
            #[inline(always)]
            || {
                self.traverse_ray::<ORDERED>(
                    ray,
                    tmin,
                    tmax,
                    #[inline(always)]
                    |items, r, tmax| leaf(items, Some(r), tmax),
                )
            },
        )
    }

    /// [`traverse_ray`](Self::traverse_ray) for a ray already prepared
    /// (with a finite origin and direction): a level below another one
    /// that shares its space.
    #[inline(always)]
    pub(super) fn traverse_prepared<const ORDERED: bool>(
        &self,
        r: &TraversalRay,
        tmin: f32,
        tmax: f32,
        mut leaf: impl FnMut(&[P], &TraversalRay, &mut f32) -> bool,
    ) -> bool {
        if self.nodes.is_empty() {
            return false;
        }
        let tmin4 = Vec4::splat(tmin);
        self.traverse::<ORDERED, false>(
            tmax,
            #[inline(always)]
            |node, tmax| node.hit(r, tmin4, Vec4::splat(tmax)),
            #[inline(always)]
            |_, items, tmax| leaf(items, r, tmax),
        )
    }

    /// [`step`](Self::step) from the root until the traversal ends: returns
    /// true if `leaf` stopped it. The tree must not be empty.
    #[inline(always)]
    pub(super) fn traverse<const ORDERED: bool, const BOXED: bool>(
        &self,
        tmax: f32,
        hit_node: impl Fn(&Node4, f32) -> (u32, [f32; WIDTH]),
        mut leaf: impl FnMut(Option<(&Node4, usize)>, &[P], &mut f32) -> bool,
    ) -> bool {
        let (mut cur, mut tmax, mut stack) = (0, tmax, Stack::new());
        loop {
            let at = (&mut cur, &mut tmax, &mut stack);
            if let Some(stopped) = self.step::<ORDERED, BOXED>(at, &hit_node, &mut leaf) {
                return stopped;
            }
        }
    }

    /// The traversal kernel: advances a traversal (the node or leaf it
    /// visits next, its `tmax`, its stack) by one node or one leaf, and
    /// returns `Some(stopped)` once it is over. At an interior
    /// node, `hit_node(node, tmax)` gives the mask of children hit and their
    /// entry distances; the next child is chosen by [`descend`]. At a leaf,
    /// `leaf(at, items, tmax)` gets its items (and may shrink `tmax`);
    /// returning true ends the traversal. Then subtrees that start beyond
    /// `tmax` are popped and dropped.
    ///
    /// With `BOXED`, the next reference and stack entries name a leaf by its parent and
    /// lane (`LEAF | parent << 2 | lane`) rather than by its items, so that
    /// the leaf's box is at hand for `leaf` (else it gets `None`): packets
    /// use it, single rays need not pay the extra load (10–19% on the
    /// Whitted and 64-shadow-ray frames). Interior nodes are fewer than
    /// items, whose count `leaf` keeps below 2²⁸, so the parent fits in 29
    /// bits.
    #[inline(always)]
    pub(super) fn step<const ORDERED: bool, const BOXED: bool>(
        &self,
        (c_cur, c_tmax, stack): (&mut u32, &mut f32, &mut Stack),
        hit_node: &impl Fn(&Node4, f32) -> (u32, [f32; WIDTH]),
        leaf: &mut impl FnMut(Option<(&Node4, usize)>, &[P], &mut f32) -> bool,
    ) -> Option<bool> {
        let cur = *c_cur;
        if cur & LEAF == 0 {
            let node = &self.nodes[cur as usize];
            let (mask, t) = hit_node(node, *c_tmax);
            if mask != 0 {
                let at = |i: usize| {
                    let child = node.child[i];
                    if !BOXED || child & LEAF == 0 {
                        child
                    } else {
                        LEAF | cur << 2 | i as u32
                    }
                };
                *c_cur = descend::<ORDERED>(mask, &t, at, stack);
                return None;
            }
        } else {
            let (child, at) = if BOXED {
                let parent = &self.nodes[((cur & !LEAF) >> 2) as usize];
                let lane = (cur & 3) as usize;
                (parent.child[lane], Some((parent, lane)))
            } else {
                (cur, None)
            };
            if leaf(at, self.leaf_items(child), c_tmax) {
                return Some(true);
            }
        }
        match stack.pop_within(*c_tmax) {
            Some(next) => {
                *c_cur = next;
                None
            }
            None => Some(false),
        }
    }

    /// Collects into `out` the leaves whose boxes may overlap `shaft`, in
    /// the order an any-hit traversal visits leaves (depth first, children
    /// in storage order). Returns false, with `out` incomplete, once more
    /// than `limit` leaves are found.
    #[inline(always)]
    pub(super) fn gather(&self, shaft: &Shaft, limit: usize, out: &mut LeafSet) -> bool {
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

    /// The items of the tree when it is a single leaf.
    #[inline(always)]
    pub(super) fn single_leaf(&self) -> Option<&[P]> {
        self.single.as_deref()
    }

    /// Calls `leaf` with the items of each leaf of `set`, in order.
    pub(super) fn in_leaves(&self, set: &LeafSet, mut leaf: impl FnMut(&[P])) {
        for group in &set.groups {
            for &child in &group.child[..] {
                if child & LEAF != 0 && (child >> 28) & 7 != 0 {
                    leaf(self.leaf_items(child));
                }
            }
        }
    }

    /// An any-hit traversal restricted to the leaves of `set` (gathered for
    /// a shaft holding the ray): `leaf` gets the items of each leaf of
    /// `set` whose box the ray hits, four boxes tested at a time, in the
    /// order an any-hit traversal reaches them, until it returns true.
    pub(super) fn any_hit_in(
        &self,
        set: &LeafSet,
        ray: &Ray,
        tmin: f32,
        tmax: f32,
        mut leaf: impl FnMut(&[P], &TraversalRay) -> bool,
    ) -> bool {
        if set.len == 0 || !(ray.origin.is_finite() && ray.dir.is_finite()) {
            return false;
        }
        let r = TraversalRay::new(ray);
        let (tmin4, tmax4) = (Vec4::splat(tmin), Vec4::splat(tmax));
        for group in &set.groups {
            let (mut mask, _) = group.hit(&r, tmin4, tmax4);
            while mask != 0 {
                let child = group.child[mask.trailing_zeros() as usize];
                mask &= mask - 1;
                if leaf(self.leaf_items(child), &r) {
                    return true;
                }
            }
        }
        false
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
pub(super) fn descend<const ORDERED: bool>(
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

/// Whether ray `r` hits, within `[tmin, tmax]`, the box of the leaf a
/// packet reached at lane `lane` of `parent` (always, without one).
#[inline(always)]
pub(super) fn reaches(
    at: Option<(&Node4, usize)>,
    r: &TraversalRay,
    tmin: Vec4,
    tmax: f32,
) -> bool {
    at.is_none_or(
        #[inline(always)]
        |(parent, lane)| parent.hit(r, tmin, Vec4::splat(tmax)).0 >> lane & 1 != 0,
    )
}

/// Per-worker buffers of packet traversals ([`TriangleBvh::closest_hits`](super::TriangleBvh::closest_hits)), kept by the caller
/// so that tracing a packet allocates nothing once warm.
#[derive(Default)]
pub struct RayPacket {
    rays: Vec<TraversalRay>,
    tmax: Vec<f32>,
}

impl RayPacket {
    /// Starts a packet of rays with limits `tmax`; returns the widest.
    pub(super) fn reset(&mut self, tmax: &[f32]) -> f32 {
        self.rays.clear();
        self.tmax.clear();
        self.tmax.extend_from_slice(tmax);
        self.widest()
    }

    /// The largest limit of a ray of the packet.
    pub(super) fn widest(&self) -> f32 {
        self.tmax.iter().fold(f32::NEG_INFINITY, |a, &b| a.max(b))
    }

    /// The packet's rays prepared for per-ray tests, and their limits. Rays
    /// are prepared when the packet first reaches a leaf: most packets that
    /// miss the mesh never do.
    pub(super) fn prepared(&mut self, rays: &[Ray]) -> (&[TraversalRay], &mut [f32]) {
        if self.rays.is_empty() {
            self.rays.extend(rays.iter().map(TraversalRay::new));
        }
        (&self.rays, &mut self.tmax)
    }
}

/// Rays from one point traced as one packet: the frustum around them, the
/// rays and the interval each is traced over (`tmax` one per ray).
pub(super) struct Run<'a> {
    pub frustum: &'a Frustum,
    pub rays: &'a [Ray],
    pub tmin: f32,
    pub tmax: &'a [f32],
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
pub(super) struct Frustum {
    o: [Vec4; 3],
    lo: [Vec4; 3],
    hi: [Vec4; 3],
    /// Per axis: 1 if the directions are negative, as in [`TraversalRay`].
    near: [usize; 3],
}

impl Frustum {
    /// The frustum of `rays` if they are worth tracing as a packet: at least
    /// two, a frustum (see [`new`](Self::new)), and within a cone of 0.05
    /// radians around the first ray's direction (judged by two rays). A packet visits every node
    /// some ray may reach, so it pays only for nearly parallel rays: a
    /// pixel's camera rays, or a span's (0.01–0.02 radians at the bunny's
    /// field of view), not a glossy set, whose rays spread by its glossiness
    /// (on the glass bunny, instruction counts, tracing its sets as packets
    /// cost 7% more than ray by ray).
    pub(super) fn packet(rays: &[Ray]) -> Option<Frustum> {
        // sin² of the cone's half-angle.
        const SIN2: f32 = 0.0025;
        let [first, .., last] = rays else {
            return None;
        };
        // A set's spread is judged by its middle and last rays against its
        // first (no more is needed to tell a glossy set from a pixel's rays,
        // and a misjudged set costs time, not hits): |d × d0|² ≤ sin² · |d|²
        // |d0|², without a root or a division. Opposite directions fail the
        // frustum's sign check.
        let d0 = Vec3A::from(first.dir);
        let sin2 = SIN2 * d0.length_squared();
        let within = |r: &Ray| {
            let d = Vec3A::from(r.dir);
            d.cross(d0).length_squared() <= sin2 * d.length_squared()
        };
        if within(&rays[rays.len() / 2]) && within(last) {
            Frustum::new(rays)
        } else {
            None
        }
    }

    /// `None` unless the rays share their origin (equal coordinates; a zero
    /// of either sign gives the same slab distances), and have finite
    /// directions with finite reciprocals of one sign per axis.
    pub(super) fn new(rays: &[Ray]) -> Option<Frustum> {
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
    pub(super) fn hit(&self, node: &Node4, tmin: Vec4, tmax: Vec4) -> (u32, [f32; WIDTH]) {
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

/// The leaves of a [`Bvh4`] a [`Shaft`] may reach, in any-hit order,
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

    pub(super) fn clear(&mut self) {
        self.groups.clear();
        self.stack.clear();
        self.len = 0;
    }

    /// Schedules the lanes of `mask` of `node`, so that they pop in lane order.
    #[inline(always)]
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
const _: () = assert!(std::mem::size_of::<Node4>() == 128);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::brute::{brute_any, brute_closest};
    use crate::accel::testdata::{rand_dir, rand_in};
    use crate::sampling::Rng;

    /// Rays are a packet when they are at least two, leave one point and
    /// lie within 0.05 radians of the first: a pixel's camera rays (spread
    /// 0.002) and a span's (0.02) are; a glossy set (0.1) is not, nor rays
    /// spread by 0.06 (the last of them that far), nor a lone ray.
    #[test]
    fn packets_are_nearly_parallel_rays() {
        let mut r = Rng::new(3);
        let o = Vec3::new(0.3, 1.0, 4.0);
        let cone = |r: &mut Rng, axis: Vec3, angle: f32| -> Vec<Ray> {
            let f = crate::math::Frame::from_normal(axis);
            (0..16)
                .map(|k| {
                    let a = match k {
                        0 => 0.0,
                        15 => angle,
                        _ => r.range(0.0, angle),
                    };
                    let phi = r.range(0.0, std::f32::consts::TAU);
                    let d = axis * a.cos() + (f.u * phi.cos() + f.v * phi.sin()) * a.sin();
                    Ray::new(o, d * r.range(0.5, 2.0), 0.0)
                })
                .collect()
        };
        for _ in 0..200 {
            let axis = rand_dir(&mut r);
            if axis.abs().min_element() < 0.2 {
                continue; // a sign may flip within the cone: no frustum
            }
            for (angle, packet) in [(0.002, true), (0.02, true), (0.06, false), (0.1, false)] {
                let rays = cone(&mut r, axis, angle);
                assert_eq!(Frustum::packet(&rays).is_some(), packet, "{angle}");
            }
            assert!(Frustum::packet(&[Ray::new(o, axis, 0.0)]).is_none());
        }
    }

    /// A tree over `bounds` whose items are the primitives' indices.
    fn tree(bounds: &[Aabb]) -> Bvh4<u32> {
        Bvh4::build(bounds, &ONE_PER_ITEM, |ids, out| out.extend_from_slice(ids))
    }

    /// Depth of the deepest leaf below node `cur` (the root has depth 1).
    fn depth<P: Copy>(t: &Bvh4<P>, cur: u32) -> usize {
        match t.node(cur) {
            None => 0,
            Some(n) => 1 + n.child.iter().map(|&c| depth(t, c)).max().unwrap_or(0),
        }
    }

    /// Spheres moving during the shutter, intersected at the ray's time,
    /// under boxes around their whole sweep: the tree's closest and any hit
    /// against a loop over all of them, with the very same sphere test.
    #[test]
    fn moving_spheres_match_brute_force() {
        let mut r = Rng::new(6);
        let spheres: Vec<(Vec3, Vec3, f32)> = (0..3000)
            .map(|_| {
                let c = rand_in(&mut r, &Aabb::new(Vec3::splat(-10.0), Vec3::splat(10.0)));
                (c, rand_dir(&mut r) * r.range(0.0, 1.0), r.range(0.05, 0.5))
            })
            .collect();
        let bounds: Vec<Aabb> = spheres
            .iter()
            .map(|&(c, v, rad)| {
                let at = |p: Vec3| Aabb::new(p - Vec3::splat(rad), p + Vec3::splat(rad));
                at(c).union(at(c + v))
            })
            .collect();
        let t = tree(&bounds);
        assert!(depth(&t, 0) <= MAX_DEPTH);
        let all = t.bounds();
        let mut hits = 0;
        for _ in 0..20_000 {
            let o = rand_in(&mut r, &all);
            let ray = Ray::new(o, rand_dir(&mut r), r.next_f32());
            let (tmin, tmax) = (r.range(0.0, 0.5), r.range(1.0, 40.0));
            let f = |p: u32, tm: f32| {
                let (c0, v, rad) = spheres[p as usize];
                let oc = ray.origin - (c0 + ray.time * v);
                let a = ray.dir.length_squared();
                let hb = oc.dot(ray.dir);
                let disc = hb * hb - a * (oc.length_squared() - rad * rad);
                if disc < 0.0 {
                    return None;
                }
                let s = disc.sqrt();
                [(-hb - s) / a, (-hb + s) / a]
                    .into_iter()
                    .find(|&t| t > tmin && t < tm)
            };
            let mut got = None;
            t.traverse_ray::<true>(&ray, tmin, tmax, |items, _, tm| {
                for &p in items {
                    if let Some(h) = f(p, *tm) {
                        (*tm, got) = (h, Some(h));
                    }
                }
                false
            });
            let want = brute_closest(spheres.len(), &ray, tmin, tmax, f);
            assert_eq!(got.map(f32::to_bits), want.map(|h| h.1.to_bits()));
            let any = t.traverse_ray::<false>(&ray, tmin, tmax, |items, _, tm| {
                items.iter().any(|&p| f(p, *tm).is_some())
            });
            let some = |p, tm| f(p, tm).is_some();
            assert_eq!(any, brute_any(spheres.len(), &ray, tmin, tmax, some));
            hits += usize::from(got.is_some());
        }
        assert!(hits > 1000, "{hits} hits");
    }

    /// Rays with a NaN or infinite origin or direction reach no leaf (and
    /// end); a zero direction is finite and enters the boxes holding its
    /// origin.
    #[test]
    fn non_finite_rays_reach_nothing() {
        let mut r = Rng::new(8);
        let world = Aabb::new(Vec3::splat(-10.0), Vec3::splat(10.0));
        let bounds: Vec<Aabb> = (0..500)
            .map(|_| {
                let p = rand_in(&mut r, &world);
                Aabb::new(p, p + Vec3::splat(1.0))
            })
            .collect();
        let t = tree(&bounds);
        let (nan, inf) = (f32::NAN, f32::INFINITY);
        let rays = [
            Ray::new(Vec3::splat(nan), Vec3::X, 0.0),
            Ray::new(Vec3::ZERO, Vec3::splat(nan), 0.0),
            Ray::new(Vec3::ZERO, Vec3::new(nan, 1.0, 0.0), 0.0),
            Ray::new(Vec3::new(inf, 0.0, 0.0), -Vec3::X, 0.0),
            Ray::new(Vec3::ZERO, Vec3::splat(inf), 0.0),
            Ray::new(Vec3::ZERO, Vec3::new(-inf, 0.0, 0.0), 0.0),
        ];
        for ray in rays {
            let mut calls = 0;
            t.traverse_ray::<true>(&ray, 0.0, inf, |_, _, _| {
                calls += 1;
                false
            });
            assert_eq!(calls, 0, "{ray:?}");
            assert!(!t.traverse_ray::<false>(&ray, 0.0, inf, |_, _, _| true));
        }
        let inside = Ray::new(bounds[3].min + Vec3::splat(0.5), Vec3::ZERO, 0.0);
        let mut reached = Vec::new();
        t.traverse_ray::<false>(&inside, 0.0, inf, |items, _, _| {
            reached.extend_from_slice(items);
            false
        });
        assert!(reached.contains(&3), "{reached:?}");
    }

    /// Points on a line (boxes of zero area) still give a balanced tree,
    /// and every primitive lands in exactly one leaf.
    #[test]
    fn zero_area_boxes_give_a_balanced_tree() {
        let line: Vec<Aabb> = (0..1000)
            .map(|i| {
                let p = Vec3::new(i as f32, 0.0, 0.0);
                Aabb::new(p, p)
            })
            .collect();
        let t = tree(&line);
        assert!(depth(&t, 0) <= 10, "depth {}", depth(&t, 0));
        let mut items = t.items.clone();
        items.sort_unstable();
        assert_eq!(items, (0..1000).collect::<Vec<u32>>());
        let (_, leaves, n) = t.counts();
        assert_eq!(n, 1000);
        assert!(leaves >= 1000 / MAX_ITEMS, "{leaves} leaves");
        // One primitive, and none.
        assert_eq!(tree(&line[..1]).single_leaf(), Some(&[0u32][..]));
        assert!(tree(&[]).is_empty());
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
}
