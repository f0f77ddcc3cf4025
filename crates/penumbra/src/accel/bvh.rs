//! A binary bounding volume hierarchy built with the binned surface area
//! heuristic (SAH), over arbitrary primitives.
//!
//! The BVH knows primitives only by their bounding boxes (at build time) and by
//! a closure that intersects primitive `i` (at traversal time), so one
//! implementation serves triangles, spheres, quads, instances, and moving
//! objects (whose boxes are the union over the shutter interval; the closure
//! then uses the ray time).
//!
//! # Layout
//! Siblings are stored together as a `NodePair` of 64 bytes, aligned to a
//! cache line: 32 bytes per node, holding the two boxes as three 4-lane
//! vectors `[lo_a, lo_b, hi_a, hi_b]` (one per axis) and the two nodes'
//! `(first, count)`. A leaf has `count >= 1` primitives at
//! `prims[first..first + count]`; an interior node has `count == 0` and its
//! children in pair `first`. The root is child 0 of pair 0, whose child 1 is an
//! empty box that no ray hits, so the root needs no special case. One cache
//! line thus brings both boxes that a traversal step tests, and the lane layout
//! lets one SIMD computation test both (the loads are plain vector loads, with
//! no gathering).
//!
//! # Traversal
//! At an interior node both child boxes are tested; the nearer (by entry
//! distance) is visited next and the farther pushed with its entry distance on
//! a fixed-size stack, so no allocation happens during traversal and popped
//! entries farther than the closest hit found meanwhile are skipped without
//! touching their nodes. Ordering by the actual entry distance rather than by
//! the sign of the ray direction along the split axis costs one comparison but
//! also orders children whose boxes overlap or were split on an axis the ray
//! barely moves along; and because children are tested before being pushed,
//! culled children are never pushed. A child's `(first, count)` is read from
//! the pair just tested, so whether it is a leaf is known without loading it.
//! The four outcomes of a pair test are dispatched with a `match`, which
//! compiles to a jump table; on incoherent rays that measured faster than a
//! chain of conditional branches or than branch-free pushes onto the stack.
//!
//! # Robust box test
//! Near and far planes are chosen by the sign of the reciprocal direction, so a
//! zero direction component (reciprocal ±inf) gives ±inf slab distances, except
//! when the origin lies exactly on a plane: then `0 * inf = NaN`. The slab
//! distances are reduced with a `max` that skips NaN (far distances negated, so
//! one reduction serves both), i.e. such a slab constrains nothing, which
//! treats a ray running along a face (or inside a flat box) as inside that
//! slab. Only false positives can result, never false misses. The far distance
//! is enlarged by `1 + 2γ₃` (γₙ = nε/(1 − nε)) as in "Robust BVH Ray Traversal"
//! (JCGT 2013), which bounds the rounding of the slab distances, so a box is
//! never missed by a ray that touches it; popped subtrees are culled against
//! the same enlarged bound, so the BVH returns exactly what a loop over all
//! primitives returns.

use super::build::{self, Config, Node, INTERSECT_COST, MAX_DEPTH, TRAVERSAL_COST};
#[cfg(test)]
use super::build::{MAX_LEAF, MAX_SAH_LEAF};
use super::bvh4::max_skip_nan;
use crate::math::{Aabb, Ray, Vec3};
use glam::{BVec4A, Vec4, Vec4Swizzles};

/// `1 + 2γ₃` with γ₃ = 3ε/(1 − 3ε), ε = 2⁻²⁴: the factor that makes the far
/// slab distance conservative under the rounding of `(plane - o) * inv_dir`.
const TFAR_SCALE: f32 = 1.0 + 2.0 * (3.0 * f32::EPSILON * 0.5) / (1.0 - 3.0 * f32::EPSILON * 0.5);

/// Two sibling nodes in one 64-byte cache line; see the module docs.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
struct NodePair {
    /// Per axis: `[lo_a, lo_b, hi_a, hi_b]`.
    x: Vec4,
    y: Vec4,
    z: Vec4,
    /// `[first_a, count_a, first_b, count_b]`.
    meta: [u32; 4],
}

/// A bounding volume hierarchy over primitives known by index.
#[derive(Clone, Debug, Default)]
pub struct Bvh {
    /// Pair 0 holds the root; empty when built over zero primitives.
    pairs: Vec<NodePair>,
    /// Primitive indices in leaf order; leaves refer to ranges of it.
    prims: Vec<u32>,
}

/// Shape statistics of a built tree.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BuildStats {
    /// Number of nodes, interior and leaves (`2 * leaves - 1` for a non-empty tree).
    pub nodes: usize,
    pub leaves: usize,
    /// Depth of the deepest leaf; the root has depth 0.
    pub max_depth: usize,
    /// SAH cost of the tree: the sum over nodes of (area / root area) times
    /// the traversal cost for interior nodes and times the intersection cost
    /// per primitive for leaves, in units of one primitive intersection.
    pub sah_cost: f32,
}

/// A ray prepared for testing node pairs.
struct PairRay {
    /// Origin, one splat per axis.
    ox: Vec4,
    oy: Vec4,
    oz: Vec4,
    /// Reciprocal direction per axis as `[i, i, -i, -i]`: the far lanes come
    /// out negated, so one `max` reduces near and far distances alike.
    ix: Vec4,
    iy: Vec4,
    iz: Vec4,
    /// Per axis, all lanes set when the direction is negative (including
    /// -0.0, whose reciprocal is -inf): then the hi planes are the near ones.
    neg_x: BVec4A,
    neg_y: BVec4A,
    neg_z: BVec4A,
}

impl PairRay {
    #[inline(always)]
    fn new(ray: &Ray) -> Self {
        let inv = ray.dir.recip();
        let lanes = |i: f32| Vec4::new(i, i, -i, -i);
        let neg = |i: f32| BVec4A::splat(i < 0.0);
        PairRay {
            ox: Vec4::splat(ray.origin.x),
            oy: Vec4::splat(ray.origin.y),
            oz: Vec4::splat(ray.origin.z),
            ix: lanes(inv.x),
            iy: lanes(inv.y),
            iz: lanes(inv.z),
            neg_x: neg(inv.x),
            neg_y: neg(inv.y),
            neg_z: neg(inv.z),
        }
    }
}

/// Slab distances of one axis for both children: `[near_a, near_b, -far_a,
/// -far_b]`. A lane is NaN when the origin lies on that plane and the
/// direction is parallel to it; [`max_skip_nan`] then ignores it.
#[inline(always)]
fn slab(planes: Vec4, neg: BVec4A, o: Vec4, inv: Vec4) -> Vec4 {
    let planes = Vec4::select(neg, planes.zwxy(), planes);
    (planes - o) * inv
}

impl NodePair {
    /// Tests both boxes against the ray clipped to `[tmin, tmax]`. Returns a
    /// bit mask of the children hit (bit 0: a, bit 1: b) and their entry
    /// distances in lanes x and y.
    #[inline(always)]
    fn hit(&self, r: &PairRay, tmin: f32, tmax: f32) -> (u32, Vec4) {
        let tx = slab(self.x, r.neg_x, r.ox, r.ix);
        let ty = slab(self.y, r.neg_y, r.oy, r.iy);
        let tz = slab(self.z, r.neg_z, r.oz, r.iz);
        let clip = Vec4::new(tmin, tmin, -tmax, -tmax);
        // [near_a, near_b, -far_a, -far_b]
        let t = max_skip_nan(tx, max_skip_nan(ty, max_skip_nan(tz, clip)));
        let far = t.zwxy() * -TFAR_SCALE;
        (t.cmple(far).bitmask() & 3, t)
    }

    /// Box, first and count of child `side` (0 or 1).
    fn child(&self, side: usize) -> (Aabb, u32, u32) {
        let b = Aabb {
            min: Vec3::new(self.x[side], self.y[side], self.z[side]),
            max: Vec3::new(self.x[side + 2], self.y[side + 2], self.z[side + 2]),
        };
        (b, self.meta[2 * side], self.meta[2 * side + 1])
    }
}

/// A deferred subtree: the far child of a node whose children were both hit,
/// with its entry distance for culling when popped.
#[derive(Clone, Copy, Default)]
struct StackEntry {
    first: u32,
    count: u32,
    entry: f32,
}

impl Bvh {
    /// Binned SAH (e.g. 16 or 32 bins along the longest centroid axis, or all 3 axes if it pays), leaf when SAH says splitting costs more or count <= max_leaf (e.g. 4); robust to: zero primitives, one primitive, all centroids identical (fall back to a median split by index), zero-extent boxes, NaN-free but infinite-free inputs (the caller guarantees finite boxes).
    ///
    /// Here: 16 bins on each of the three axes, leaves of at most 4 primitives
    /// unless the SAH prefers a leaf of up to 16. Primitive references (box
    /// and index, 32 bytes) are partitioned in place, so each level is one
    /// linear pass and the build is O(n log n). When the centroids of a range
    /// coincide it is split in half by index; when the box has zero area (all
    /// primitives on a line or a point) or the depth budget runs low, at the
    /// object median of the longest centroid axis. Large ranges build their
    /// two subtrees in parallel (rayon).
    ///
    /// # Panics
    /// If there are `u32::MAX` primitives or more (indices are 32-bit).
    pub fn build(prim_bounds: &[Aabb]) -> Bvh {
        let (mut nodes, prims) = build::build_binary(prim_bounds, &Config::SINGLE);
        if nodes.is_empty() {
            return Bvh::default();
        }
        // The root's sibling: an empty box, which no finite ray hits. Should
        // one hit it anyway, it is a leaf holding slot 0, never a path back to
        // the root (an interior node here would make a cycle).
        nodes[1] = Node {
            bounds: Aabb::EMPTY,
            first: 0,
            count: 1,
        };
        Bvh {
            pairs: pack(&nodes),
            prims,
        }
    }

    /// Statistics of the tree, computed by walking it.
    pub fn stats(&self) -> BuildStats {
        let mut s = BuildStats {
            nodes: 0,
            leaves: 0,
            max_depth: 0,
            sah_cost: 0.0,
        };
        if self.pairs.is_empty() {
            return s;
        }
        let root_area = self.bounds().surface_area();
        let mut stack = vec![(0usize, 0usize, 0usize)];
        while let Some((pair, side, depth)) = stack.pop() {
            let (b, first, count) = self.pairs[pair].child(side);
            // A root of zero area (primitives on a point or a line) weighs every
            // node equally rather than dividing by zero.
            let rel = if root_area > 0.0 {
                b.surface_area() / root_area
            } else {
                1.0
            };
            s.nodes += 1;
            s.max_depth = s.max_depth.max(depth);
            if count > 0 {
                s.leaves += 1;
                s.sah_cost += rel * INTERSECT_COST * count as f32;
            } else {
                s.sah_cost += rel * TRAVERSAL_COST;
                stack.push((first as usize, 0, depth + 1));
                stack.push((first as usize, 1, depth + 1));
            }
        }
        s
    }

    /// Box around all primitives ([`Aabb::EMPTY`] when there are none).
    pub fn bounds(&self) -> Aabb {
        self.pairs.first().map_or(Aabb::EMPTY, |p| p.child(0).0)
    }

    /// Closest hit. `hit(prim, tmax) -> Option<f32>` tests primitive `prim` (an index into the slice given to build) and returns its hit distance if closer than tmax. Returns the closest (prim, t).
    ///
    /// The closure is responsible for `tmin` (and the ray time) itself; the BVH
    /// uses `[tmin, tmax]` only to cull boxes, and shrinks `tmax` to each hit.
    /// A ray with a non-finite origin or direction hits nothing (NaN slab
    /// distances would otherwise make every box look hit).
    #[inline]
    pub fn closest_hit(
        &self,
        ray: &Ray,
        tmin: f32,
        tmax: f32,
        mut hit: impl FnMut(u32, f32) -> Option<f32>,
    ) -> Option<(u32, f32)> {
        if self.pairs.is_empty() || !(ray.origin.is_finite() && ray.dir.is_finite()) {
            return None;
        }
        let r = PairRay::new(ray);
        let mut tmax = tmax;
        let mut best = None;
        let mut stack = [StackEntry::default(); MAX_DEPTH];
        let mut sp = 0usize;
        // Start as an interior node whose children are pair 0 (root, empty).
        let (mut first, mut count) = (0u32, 0u32);
        loop {
            if count == 0 {
                let pair = &self.pairs[first as usize];
                let (mask, t) = pair.hit(&r, tmin, tmax);
                let m = pair.meta;
                match mask {
                    3 => {
                        let (near, far, far_t) = if t.y < t.x { (1, 0, t.x) } else { (0, 1, t.y) };
                        stack[sp] = StackEntry {
                            first: m[2 * far],
                            count: m[2 * far + 1],
                            entry: far_t,
                        };
                        sp += 1;
                        (first, count) = (m[2 * near], m[2 * near + 1]);
                        continue;
                    }
                    1 => {
                        (first, count) = (m[0], m[1]);
                        continue;
                    }
                    2 => {
                        (first, count) = (m[2], m[3]);
                        continue;
                    }
                    _ => {}
                }
            } else {
                let start = first as usize;
                for &prim in &self.prims[start..start + count as usize] {
                    if let Some(t) = hit(prim, tmax) {
                        tmax = t;
                        best = Some((prim, t));
                    }
                }
            }
            // Pop the next subtree that can still hold a closer hit.
            loop {
                if sp == 0 {
                    return best;
                }
                sp -= 1;
                let e = stack[sp];
                if e.entry <= tmax * TFAR_SCALE {
                    (first, count) = (e.first, e.count);
                    break;
                }
            }
        }
    }

    /// Any hit (shadow rays): stops at the first primitive for which `hit(prim, tmax)` is true.
    ///
    /// A ray with a non-finite origin or direction hits nothing.
    #[inline]
    pub fn any_hit(
        &self,
        ray: &Ray,
        tmin: f32,
        tmax: f32,
        mut hit: impl FnMut(u32, f32) -> bool,
    ) -> bool {
        if self.pairs.is_empty() || !(ray.origin.is_finite() && ray.dir.is_finite()) {
            return false;
        }
        let r = PairRay::new(ray);
        let mut stack = [(0u32, 0u32); MAX_DEPTH];
        let mut sp = 0usize;
        let (mut first, mut count) = (0u32, 0u32);
        loop {
            if count == 0 {
                let pair = &self.pairs[first as usize];
                let (mask, t) = pair.hit(&r, tmin, tmax);
                let m = pair.meta;
                // Any order finds an occluder; nearer first tends to find one
                // sooner and costs only a comparison.
                match mask {
                    3 => {
                        let (near, far) = if t.y < t.x { (1, 0) } else { (0, 1) };
                        stack[sp] = (m[2 * far], m[2 * far + 1]);
                        sp += 1;
                        (first, count) = (m[2 * near], m[2 * near + 1]);
                        continue;
                    }
                    1 => {
                        (first, count) = (m[0], m[1]);
                        continue;
                    }
                    2 => {
                        (first, count) = (m[2], m[3]);
                        continue;
                    }
                    _ => {}
                }
            } else {
                let start = first as usize;
                for &prim in &self.prims[start..start + count as usize] {
                    if hit(prim, tmax) {
                        return true;
                    }
                }
            }
            if sp == 0 {
                return false;
            }
            sp -= 1;
            (first, count) = stack[sp];
        }
    }
}

/// Converts build nodes to the traversal layout.
fn pack(nodes: &[Node]) -> Vec<NodePair> {
    nodes
        .chunks_exact(2)
        .map(|c| {
            let (a, b) = (&c[0], &c[1]);
            let (la, lb, ha, hb) = (a.bounds.min, b.bounds.min, a.bounds.max, b.bounds.max);
            // Interior nodes refer to their children's pair.
            let first = |n: &Node| if n.count == 0 { n.first / 2 } else { n.first };
            NodePair {
                x: Vec4::new(la.x, lb.x, ha.x, hb.x),
                y: Vec4::new(la.y, lb.y, ha.y, hb.y),
                z: Vec4::new(la.z, lb.z, ha.z, hb.z),
                meta: [first(a), a.count, first(b), b.count],
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::brute::{brute_any, brute_closest};
    use crate::accel::testdata::*;
    use crate::geometry::triangle::{intersect_triangle, RayShear};
    use crate::sampling::Rng;

    fn tri_bounds(tris: &[Tri]) -> Vec<Aabb> {
        tris.iter().map(|t| Aabb::from_points(*t)).collect()
    }

    /// Directions with exact zeros (including -0.0) and axis directions mixed in.
    fn awkward_dir(r: &mut Rng) -> Vec3 {
        let axes = [
            Vec3::X,
            -Vec3::X,
            Vec3::Y,
            -Vec3::Y,
            Vec3::Z,
            -Vec3::Z,
            Vec3::new(1.0, -0.0, 1.0),
            Vec3::new(-0.0, 1.0, -1.0),
            Vec3::new(0.0, -0.0, -1.0),
        ];
        match r.below(3) {
            0 => axes[r.below(axes.len() as u32) as usize],
            _ => rand_dir(r),
        }
    }

    struct Outcome {
        hits: usize,
        rays: usize,
    }

    /// Checks closest and any hit of the BVH against brute force over `tris`
    /// for every ray, with the same intersection routine on both sides.
    fn check_triangles(tris: &[Tri], rays: &[(Ray, f32, f32)]) -> Outcome {
        let bvh = Bvh::build(&tri_bounds(tris));
        check_structure(&bvh, &tri_bounds(tris));
        let mut hits = 0;
        for (ray, tmin, tmax) in rays {
            let shear = RayShear::new(ray);
            let f = |p: u32, tm: f32| {
                let [a, b, c] = tris[p as usize];
                intersect_triangle(ray, &shear, a, b, c, *tmin, tm).map(|h| h.0)
            };
            let got = bvh.closest_hit(ray, *tmin, *tmax, f);
            let want = brute_closest(tris.len(), ray, *tmin, *tmax, f);
            match (got, want) {
                (None, None) => {}
                (Some((gp, gt)), Some((wp, wt))) => {
                    // Equal distances may come from different primitives
                    // (shared edges, duplicates); the distance must be identical.
                    assert_eq!(
                        gt.to_bits(),
                        wt.to_bits(),
                        "ray {ray:?}: bvh prim {gp} t {gt}, brute prim {wp} t {wt}"
                    );
                    hits += 1;
                }
                _ => panic!("ray {ray:?} [{tmin}, {tmax}]: bvh {got:?} vs brute {want:?}"),
            }
            let any = |p: u32, tm: f32| f(p, tm).is_some();
            let got_any = bvh.any_hit(ray, *tmin, *tmax, any);
            let want_any = brute_any(tris.len(), ray, *tmin, *tmax, any);
            assert_eq!(got_any, want_any, "any hit of ray {ray:?}");
            assert_eq!(got_any, want.is_some());
        }
        Outcome {
            hits,
            rays: rays.len(),
        }
    }

    /// Structural invariants: every primitive referenced exactly once, boxes
    /// nested, node count consistent with the leaf count, depth within bound.
    fn check_structure(bvh: &Bvh, bounds: &[Aabb]) {
        let s = bvh.stats();
        if bounds.is_empty() {
            assert_eq!(s.nodes, 0);
            assert!(bvh.bounds().is_empty());
            return;
        }
        assert_eq!(s.nodes, 2 * s.leaves - 1);
        assert_eq!(s.nodes, 2 * bvh.pairs.len() - 1);
        assert!(s.max_depth < MAX_DEPTH);
        assert!(s.sah_cost.is_finite() && s.sah_cost > 0.0);
        let contains = |outer: &Aabb, inner: &Aabb| {
            outer.min.cmple(inner.min).all() && inner.max.cmple(outer.max).all()
        };
        let all = bounds.iter().fold(Aabb::EMPTY, |a, b| a.union(*b));
        assert_eq!(bvh.bounds(), all);
        let mut seen = vec![0u32; bounds.len()];
        let mut leaves = 0;
        let mut stack = vec![(0usize, 0usize)];
        while let Some((pair, side)) = stack.pop() {
            let (b, first, count) = bvh.pairs[pair].child(side);
            if count > 0 {
                leaves += 1;
                let (a, c) = (first as usize, count as usize);
                assert!(c <= MAX_SAH_LEAF);
                for &p in &bvh.prims[a..a + c] {
                    seen[p as usize] += 1;
                    assert!(contains(&b, &bounds[p as usize]));
                }
            } else {
                for child in [0, 1] {
                    assert!(contains(&b, &bvh.pairs[first as usize].child(child).0));
                    stack.push((first as usize, child));
                }
            }
        }
        // The root's sibling is the empty box, never hit, and a leaf.
        let (b, _, count) = bvh.pairs[0].child(1);
        assert!(b.is_empty() && count == 1);
        assert_eq!(leaves, s.leaves);
        assert!(
            seen.iter().all(|&c| c == 1),
            "a primitive is not referenced exactly once"
        );
    }

    fn random_soup(r: &mut Rng, n: usize, degenerate: bool) -> Vec<Tri> {
        let mut tris = Vec::with_capacity(n);
        for i in 0..n {
            let c = Vec3::new(
                r.range(-10.0, 10.0),
                r.range(-10.0, 10.0),
                r.range(-10.0, 10.0),
            );
            // Sizes spread over three orders of magnitude.
            let size = 0.01 * 500.0f32.powf(r.next_f32());
            let tri = match i % 8 {
                // Long thin slivers across much of the scene.
                0 => {
                    let axis = rand_dir(r) * r.range(5.0, 20.0);
                    let side = rand_dir(r) * r.range(1e-4, 1e-2);
                    [c - axis, c + axis, c + 0.3 * axis + side]
                }
                1 if degenerate => {
                    // Collinear (rounded) or all three points equal.
                    if r.below(2) == 0 {
                        let d = rand_dir(r) * size;
                        [c, c + d, c + 2.5 * d]
                    } else {
                        [c, c, c]
                    }
                }
                _ => [
                    c + rand_dir(r) * size,
                    c + rand_dir(r) * size,
                    c + rand_dir(r) * size,
                ],
            };
            tris.push(tri);
        }
        tris
    }

    fn random_rays(r: &mut Rng, n: usize, b: &Aabb) -> Vec<(Ray, f32, f32)> {
        let centre = b.centroid();
        let radius = 1.5 * b.extent().length();
        (0..n)
            .map(|i| {
                let (o, d) = if i % 2 == 0 {
                    (rand_in(r, b), awkward_dir(r))
                } else {
                    // From outside, aimed at a point of the box.
                    let o = centre + rand_dir(r) * radius;
                    (o, rand_in(r, b) - o)
                };
                let tmax = if i % 5 == 0 {
                    r.range(0.0, 20.0)
                } else {
                    f32::INFINITY
                };
                let tmin = if i % 7 == 0 { r.range(0.0, 5.0) } else { 0.0 };
                (Ray::new(o, d, 0.0), tmin, tmax)
            })
            .collect()
    }

    #[test]
    fn random_soup_matches_brute_force() {
        let mut r = Rng::new(1);
        let tris = random_soup(&mut r, 2000, false);
        let b = tri_bounds(&tris)
            .iter()
            .fold(Aabb::EMPTY, |a, b| a.union(*b));
        let rays = random_rays(&mut r, 50_000, &b);
        let out = check_triangles(&tris, &rays);
        // The test must exercise both outcomes.
        assert!(
            out.hits > out.rays / 10 && out.hits < out.rays * 9 / 10,
            "{} hits",
            out.hits
        );
    }

    #[test]
    fn soup_with_degenerate_triangles_matches_brute_force() {
        let mut r = Rng::new(2);
        let tris = random_soup(&mut r, 2000, true);
        let b = tri_bounds(&tris)
            .iter()
            .fold(Aabb::EMPTY, |a, b| a.union(*b));
        // Aim a share of the rays exactly at points of degenerate triangles.
        let mut rays = random_rays(&mut r, 20_000, &b);
        for (k, t) in tris.iter().enumerate().filter(|(k, _)| k % 8 == 1) {
            let o = b.centroid() + rand_dir(&mut r) * 50.0;
            rays.push((Ray::new(o, t[k % 3] - o, 0.0), 0.0, f32::INFINITY));
        }
        let out = check_triangles(&tris, &rays);
        assert!(out.hits > 0);
    }

    /// All triangles in the plane y = 0 (flat boxes) plus triangles standing on
    /// it with an edge in the plane, hit by axis rays and rays exactly parallel
    /// to the plane, in it and just off it. Rays running in the plane along a
    /// box face are the case where slab distances are `0 * inf`.
    #[test]
    fn flat_scene_with_axis_and_parallel_rays() {
        let mut r = Rng::new(3);
        let tris = flat_triangles(&mut r, 3000);
        let rays = axis_and_parallel_rays(&mut r, 40_000);
        let out = check_triangles(&tris, &rays);
        assert!(out.hits > 1000);
        // In-plane rays do hit the bottom edges of standing triangles: that is
        // the grazing case that must not be culled by the box test.
        let in_plane: Vec<_> = rays
            .iter()
            .filter(|(ray, _, _)| ray.origin.y == 0.0 && ray.dir.y == 0.0)
            .copied()
            .collect();
        let out = check_triangles(&tris, &in_plane);
        assert!(out.hits > 100, "{} in-plane hits", out.hits);
    }

    #[test]
    fn zero_and_one_primitive() {
        let ray = Ray::new(Vec3::new(0.0, 0.0, -5.0), Vec3::Z, 0.0);
        let empty = Bvh::build(&[]);
        assert_eq!(
            empty.stats(),
            BuildStats {
                nodes: 0,
                leaves: 0,
                max_depth: 0,
                sah_cost: 0.0
            }
        );
        assert!(empty.bounds().is_empty());
        assert_eq!(
            empty.closest_hit(&ray, 0.0, f32::INFINITY, |_, _| Some(1.0)),
            None
        );
        assert!(!empty.any_hit(&ray, 0.0, f32::INFINITY, |_, _| true));

        let tri = [[
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(1.0, -1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        ]];
        let bvh = Bvh::build(&tri_bounds(&tri));
        let s = bvh.stats();
        assert_eq!((s.nodes, s.leaves, s.max_depth), (1, 1, 0));
        let rays = vec![
            (ray, 0.0, f32::INFINITY),
            (ray, 0.0, 4.0),
            (
                Ray::new(Vec3::new(3.0, 0.0, -5.0), Vec3::Z, 0.0),
                0.0,
                f32::INFINITY,
            ),
        ];
        let out = check_triangles(&tri, &rays);
        assert_eq!(out.hits, 1);
        // A zero-extent box (a point primitive) is still visited.
        let point = Bvh::build(&[Aabb::new(Vec3::ONE, Vec3::ONE)]);
        let to_point = Ray::new(Vec3::ZERO, Vec3::ONE, 0.0);
        assert_eq!(
            point.closest_hit(&to_point, 0.0, f32::INFINITY, |_, _| Some(1.0)),
            Some((0, 1.0))
        );
    }

    #[test]
    fn non_finite_rays_hit_nothing_and_terminate() {
        let mut r = Rng::new(8);
        let tris = random_soup(&mut r, 500, false);
        let bvh = Bvh::build(&tri_bounds(&tris));
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
            let got = bvh.closest_hit(&ray, 0.0, f32::INFINITY, |_, _| {
                calls += 1;
                Some(1.0)
            });
            assert_eq!((got, calls), (None, 0), "{ray:?}");
            assert!(!bvh.any_hit(&ray, 0.0, f32::INFINITY, |_, _| true));
        }
        // A zero direction is finite: boxes containing the origin are
        // entered, and the primitive test decides (the triangle test says no).
        let zero = Ray::new(tris[3][0], Vec3::ZERO, 0.0);
        let shear = RayShear::new(&zero);
        let got = bvh.closest_hit(&zero, 0.0, f32::INFINITY, |p, tm| {
            let [a, b, c] = tris[p as usize];
            intersect_triangle(&zero, &shear, a, b, c, 0.0, tm).map(|h| h.0)
        });
        assert_eq!(got, None);
    }

    #[test]
    fn identical_bounds_are_split_by_index() {
        // 10,000 triangles with the same box [0, 1]^3: two fixed corners and a
        // random third vertex.
        let mut r = Rng::new(4);
        let tris: Vec<Tri> = (0..10_000)
            .map(|_| {
                [
                    Vec3::ZERO,
                    Vec3::ONE,
                    rand_in(&mut r, &Aabb::new(Vec3::ZERO, Vec3::ONE)),
                ]
            })
            .collect();
        let bounds = tri_bounds(&tris);
        assert!(bounds.iter().all(|b| *b == bounds[0]));
        let bvh = Bvh::build(&bounds);
        let s = bvh.stats();
        assert!(s.leaves >= 10_000 / MAX_LEAF && s.max_depth <= 13, "{s:?}");
        let rays = random_rays(&mut r, 1500, &bounds[0]);
        let out = check_triangles(&tris, &rays);
        assert!(out.hits > 100);
    }

    /// A closed UV sphere: `nu` segments around, `nv` bands, fans at the poles,
    /// vertices shared through an index buffer.
    fn uv_sphere(radius: f32, nu: usize, nv: usize) -> (Vec<Vec3>, Vec<[usize; 3]>) {
        use std::f32::consts::{PI, TAU};
        let mut v = vec![Vec3::new(0.0, radius, 0.0)];
        for j in 1..nv {
            let theta = PI * j as f32 / nv as f32;
            for i in 0..nu {
                let phi = TAU * i as f32 / nu as f32;
                v.push(
                    radius
                        * Vec3::new(
                            theta.sin() * phi.cos(),
                            theta.cos(),
                            theta.sin() * phi.sin(),
                        ),
                );
            }
        }
        v.push(Vec3::new(0.0, -radius, 0.0));
        let south = v.len() - 1;
        let ring = |j: usize, i: usize| 1 + (j - 1) * nu + i % nu;
        let mut f = Vec::new();
        for i in 0..nu {
            f.push([0, ring(1, i + 1), ring(1, i)]);
            f.push([south, ring(nv - 1, i), ring(nv - 1, i + 1)]);
        }
        for j in 1..nv - 1 {
            for i in 0..nu {
                let (a, b, c, d) = (
                    ring(j, i),
                    ring(j, i + 1),
                    ring(j + 1, i),
                    ring(j + 1, i + 1),
                );
                f.push([a, b, d]);
                f.push([a, d, c]);
            }
        }
        (v, f)
    }

    #[test]
    fn closed_sphere_mesh_is_hit_and_watertight() {
        let radius = 2.0;
        let (verts, faces) = uv_sphere(radius, 200, 51);
        assert_eq!(faces.len(), 20_000);
        let tris: Vec<Tri> = faces.iter().map(|f| f.map(|i| verts[i])).collect();
        let bvh = Bvh::build(&tri_bounds(&tris));
        let closest = |ray: &Ray| {
            let shear = RayShear::new(ray);
            bvh.closest_hit(ray, 0.0, f32::INFINITY, |p, tm| {
                let [a, b, c] = tris[p as usize];
                intersect_triangle(ray, &shear, a, b, c, 0.0, tm).map(|h| h.0)
            })
        };
        let mut r = Rng::new(5);
        // Rays from outside aimed at the centre hit at |o| - R (up to the
        // tessellation's sag).
        for _ in 0..20_000 {
            let o = rand_dir(&mut r) * r.range(2.5, 10.0) * radius;
            let d = -o / o.length();
            let (_, t) = closest(&Ray::new(o, d, 0.0)).expect("ray at the centre missed");
            assert!((t - (o.length() - radius)).abs() < 0.01 * radius, "t = {t}");
        }
        // Rays aimed exactly at vertices and at edge midpoints, from outside
        // and from the exact centre, never slip through.
        let mut targets: Vec<Vec3> = verts.clone();
        for f in &faces {
            for k in 0..3 {
                targets.push(0.5 * (verts[f[k]] + verts[f[(k + 1) % 3]]));
            }
        }
        for (k, &p) in targets.iter().enumerate() {
            let o = if k % 2 == 0 {
                Vec3::ZERO
            } else {
                rand_dir(&mut r) * 3.0 * radius
            };
            let ray = Ray::new(o, p - o, 0.0);
            // Rays from outside that graze the sphere at the target (the
            // silhouette) touch the mesh only tangentially and may miss.
            let cos = p.dot(o - p) / (p.length() * (o - p).length());
            if o != Vec3::ZERO && cos.abs() < 0.05 {
                continue;
            }
            let (_, t) =
                closest(&ray).unwrap_or_else(|| panic!("ray to {p:?} from {o:?} slipped through"));
            if o == Vec3::ZERO || cos > 0.0 {
                assert!((t - 1.0).abs() < 1e-4, "t = {t} for target {p:?}");
            }
            let shear = RayShear::new(&ray);
            assert!(bvh.any_hit(&ray, 0.0, f32::INFINITY, |p, tm| {
                let [a, b, c] = tris[p as usize];
                intersect_triangle(&ray, &shear, a, b, c, 0.0, tm).is_some()
            }));
        }
    }

    /// The BVH is generic: moving spheres, boxed over the shutter interval, with
    /// an analytic intersection that uses the ray time.
    #[test]
    fn moving_spheres_match_brute_force() {
        let mut r = Rng::new(6);
        let spheres: Vec<(Vec3, Vec3, f32)> = (0..3000)
            .map(|_| {
                let c = Vec3::new(
                    r.range(-10.0, 10.0),
                    r.range(-10.0, 10.0),
                    r.range(-10.0, 10.0),
                );
                (c, rand_dir(&mut r) * r.range(0.0, 1.0), r.range(0.05, 0.5))
            })
            .collect();
        let bounds: Vec<Aabb> = spheres
            .iter()
            .map(|&(c, v, rad)| {
                Aabb::new(c - Vec3::splat(rad), c + Vec3::splat(rad)).union(Aabb::new(
                    c + v - Vec3::splat(rad),
                    c + v + Vec3::splat(rad),
                ))
            })
            .collect();
        let bvh = Bvh::build(&bounds);
        check_structure(&bvh, &bounds);
        let all = bvh.bounds();
        let mut hits = 0;
        for (ray, tmin, tmax) in random_rays(&mut r, 20_000, &all) {
            let ray = Ray {
                time: r.next_f32(),
                ..ray
            };
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
            let got = bvh.closest_hit(&ray, tmin, tmax, f);
            let want = brute_closest(spheres.len(), &ray, tmin, tmax, f);
            assert_eq!(got.map(|h| h.1.to_bits()), want.map(|h| h.1.to_bits()));
            let any = bvh.any_hit(&ray, tmin, tmax, |p, tm| f(p, tm).is_some());
            assert_eq!(
                any,
                brute_any(spheres.len(), &ray, tmin, tmax, |p, tm| f(p, tm).is_some())
            );
            hits += usize::from(got.is_some());
        }
        assert!(hits > 1000);
    }

    #[test]
    fn stats_are_sane_and_sah_beats_a_single_leaf() {
        let mut r = Rng::new(7);
        let tris = random_soup(&mut r, 5000, false);
        let bounds = tri_bounds(&tris);
        let bvh = Bvh::build(&bounds);
        check_structure(&bvh, &bounds);
        let s = bvh.stats();
        assert!(s.leaves >= 5000 / MAX_SAH_LEAF && s.leaves <= 5000);
        assert!(s.sah_cost < 0.05 * 5000.0, "{s:?}");
        assert!(s.max_depth >= 11, "{s:?}");
        // Points on a line (zero-area boxes) still get a balanced tree.
        let line: Vec<Aabb> = (0..1000)
            .map(|i| {
                let p = Vec3::new(i as f32, 0.0, 0.0);
                Aabb::new(p, p)
            })
            .collect();
        let bvh = Bvh::build(&line);
        check_structure(&bvh, &line);
        assert!(bvh.stats().max_depth <= 10);
    }

    #[test]
    fn any_hit_stops_at_first_occluder() {
        let bounds: Vec<Aabb> = (0..100)
            .map(|i| {
                Aabb::new(
                    Vec3::new(-1.0, -1.0, i as f32),
                    Vec3::new(1.0, 1.0, i as f32 + 0.5),
                )
            })
            .collect();
        let bvh = Bvh::build(&bounds);
        let ray = Ray::new(Vec3::new(0.0, 0.0, -1.0), Vec3::Z, 0.0);
        let mut calls = 0;
        assert!(bvh.any_hit(&ray, 0.0, f32::INFINITY, |_, _| {
            calls += 1;
            true
        }));
        assert_eq!(calls, 1);
        // tmax culls: nothing tested beyond it.
        let mut tested = Vec::new();
        bvh.closest_hit(&ray, 0.0, 10.0, |p, _| {
            tested.push(p);
            None
        });
        assert!(
            !tested.is_empty() && tested.iter().all(|&p| p <= 11),
            "{tested:?}"
        );
    }
}
