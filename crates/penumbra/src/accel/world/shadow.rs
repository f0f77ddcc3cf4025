//! Shadow segments: what a segment crosses ([`World::crossings`]), one
//! crossing at a time, and the shafts around shadow sets
//! ([`World::gather_shaft`]) that restrict a set's rays to the leaves and
//! casters they may meet.

use super::{Candidate, Hit, HitRef, Item, World};
use crate::accel::bvh4::{any_of, any_of_rev, TraversalRay};
use crate::accel::{LeafSet, Shaft};
use crate::geometry::triangle::{intersect_triangle, RayShear};
use crate::math::{Aabb, Ray, Vec3};

impl World {
    /// Prepares `out` for the segments from the box `origins` to the box
    /// `targets` (a shadow set, see [`Shaft`]): gathers the top-level
    /// leaves and the static-triangle leaves they may cross, and lists the
    /// shadow casters among the objects of those leaves that they may cross
    /// (a quad or disk with every end point on one side of its plane cannot
    /// be crossed: the ground a shadow set starts from, say; nor can a
    /// still object whose bounding box lies outside the shaft). Returns
    /// false if the boxes are not finite or the shaft reaches more than
    /// `limit` leaves or objects: then the rays are better traced one by one.
    pub fn gather_shaft(
        &self,
        origins: Aabb,
        targets: Aabb,
        limit: usize,
        out: &mut ShaftSet,
    ) -> bool {
        self.kernels.run(
            #[inline(always)]
            || {
                let Some(shaft) = Shaft::new(origins, targets) else {
                    return false;
                };
                out.items.clear();
                out.leaves.clear();
                let mut g = ShaftGather {
                    world: self,
                    shaft: &shaft,
                    ends: [origins, targets],
                    limit,
                    ok: true,
                };
                // A top level of one leaf (a few objects) is taken whole.
                if let Some(items) = self.top.single_leaf() {
                    g.leaf(items, out);
                } else {
                    let mut top = std::mem::take(&mut out.top);
                    if !self.top.gather(&shaft, limit, &mut top) {
                        out.top = top;
                        return false;
                    }
                    self.top.in_leaves(
                        &top,
                        #[inline(always)]
                        |items| g.leaf(items, out),
                    );
                    out.top = top;
                }
                g.ok && out.items.len() <= limit
            },
        )
    }

    /// True if nothing can block a segment held by the shaft `set` was
    /// gathered for: no static-triangle leaf and no caster is within it.
    /// Such a segment then [crosses](Self::crossings) nothing, and a shadow
    /// set need not trace its rays.
    pub fn shaft_is_clear(&self, set: &ShaftSet) -> bool {
        set.items.is_empty()
    }

    /// Visits the surfaces a segment of `ray` within `range` crosses, one
    /// [`Crossing`] at a time, until `cross` says to stop (true); true if
    /// it did. Objects that cast no shadow are passed. With `shaft`, what
    /// [`gather_shaft`](Self::gather_shaft) found for a shaft holding the
    /// segment, only its casters and static-triangle leaves are visited, in
    /// the order a traversal meets them (the same crossings in the same
    /// order). A leaf's items are visited last to first, the static
    /// triangles before the objects: an opaque mesh ends most of the
    /// shadow rays that meet it. Which crossings let light through, and
    /// how much, is the integrators' to say.
    pub fn crossings(
        &self,
        ray: &Ray,
        range: (f32, f32),
        shaft: Option<&ShaftSet>,
        mut cross: impl FnMut(&Crossing<'_>) -> bool,
    ) -> bool {
        // `cross` by reference: moved into the closure, it would be copied
        // with loads wider than the caller's stores, which wait for them.
        self.kernels.run(
            #[inline(always)]
            || self.crossings_kernel(ray, range, shaft, &mut cross),
        )
    }

    /// [`crossings`](Self::crossings), compiled into each kernel set.
    #[inline(always)]
    fn crossings_kernel(
        &self,
        ray: &Ray,
        (tmin, tmax): (f32, f32),
        shaft: Option<&ShaftSet>,
        mut cross: impl FnMut(&Crossing<'_>) -> bool,
    ) -> bool {
        let mut seg = Segment {
            world: self,
            ray,
            tmin,
            tmax,
            leaves: shaft.map(|s| &s.leaves),
            cross: &mut cross,
        };
        match shaft {
            Some(set) => any_of(
                &set.items,
                #[inline(always)]
                |&i| seg.blocked_by(i, None),
            ),
            None => self.top.traverse_items::<false>(
                self.kernels,
                ray,
                tmin,
                tmax,
                #[inline(always)]
                |items, r, _| {
                    any_of_rev(
                        items,
                        #[inline(always)]
                        |&i| seg.blocked_by(i, r),
                    )
                },
            ),
        }
    }

    /// [`occluded`](Self::occluded) for each of `rays` (the same fraction
    /// `range` of each direction), into `out` in order: a batch of shadow
    /// rays in one entry into the kernel set's code.
    pub fn occluded_all(&self, rays: &[Ray], range: (f32, f32), out: &mut Vec<bool>) {
        self.kernels.run(
            #[inline(always)]
            || {
                out.clear();
                // A loop, not `extend`: kept inline in the kernel set's code.
                for r in rays {
                    out.push(self.crossings_kernel(r, range, None, |_| true));
                }
            },
        )
    }

    /// True if a surface that casts shadows crosses the segment of `ray`
    /// within `range`.
    pub fn occluded(&self, ray: &Ray, range: (f32, f32)) -> bool {
        self.crossings(ray, range, None, |_| true)
    }

    /// How often the ray crosses the object within (tmin, tmax): a closed
    /// shape (a sphere) can be crossed twice (in and out).
    fn count_crossings(&self, object: u32, ray: &Ray, tmin: f32, tmax: f32) -> i32 {
        let Some((t, _)) = self.intersect_prim(object, ray, tmin, tmax) else {
            return 0;
        };
        let closed = self.objects[object as usize].shape.is_closed();
        let second = closed && self.intersect_prim(object, ray, t, tmax).is_some();
        1 + i32::from(second)
    }
}

/// What a shadow segment crosses (see [`World::crossings`]): an object of
/// the top level, crossed `count` times (a closed shape can be crossed
/// twice), or a static triangle, crossed once.
pub struct Crossing<'a> {
    world: &'a World,
    ray: &'a Ray,
    range: (f32, f32),
    what: Crossed,
}

#[derive(Clone, Copy)]
enum Crossed {
    Object { object: u32, count: i32 },
    Triangle { id: u32 },
}

impl Crossing<'_> {
    /// The material of the surface crossed.
    #[inline(always)]
    pub fn material(&self) -> u32 {
        let w = self.world;
        let object = match self.what {
            Crossed::Object { object, .. } => object,
            Crossed::Triangle { id } => w.tri_refs[id as usize].0,
        };
        w.objects[object as usize].material
    }

    /// How often the segment crosses the surface (1, or 2 through a
    /// closed shape).
    #[inline(always)]
    pub fn count(&self) -> i32 {
        match self.what {
            Crossed::Object { count, .. } => count,
            Crossed::Triangle { .. } => 1,
        }
    }

    /// Visits the record of each crossing (made as a closest hit's) in
    /// order along the ray, until `at` says to stop (true); true if it
    /// did.
    #[cold]
    pub fn each_hit(&self, mut at: impl FnMut(&Hit) -> bool) -> bool {
        let (w, ray, (tmin, tmax)) = (self.world, self.ray, self.range);
        match self.what {
            Crossed::Object { object, .. } => {
                let mut from = tmin;
                // A closed shape is crossed at most twice.
                for _ in 0..2 {
                    let Some((t, c)) = w.intersect_prim(object, ray, from, tmax) else {
                        break;
                    };
                    if at(&w.surface(ray, HitRef::new(t, object, c))) {
                        return true;
                    }
                    if !w.objects[object as usize].shape.is_closed() {
                        break;
                    }
                    from = t;
                }
                false
            }
            Crossed::Triangle { id } => {
                let (object, tri) = w.tri_refs[id as usize];
                let Some(mesh) = w.objects[object as usize].shape.as_mesh() else {
                    return false;
                };
                let [p0, p1, p2] = w.meshes[mesh.mesh as usize].vertices(tri as usize);
                let shear = RayShear::new(ray);
                let Some((t, b1, b2)) = intersect_triangle(ray, &shear, p0, p1, p2, tmin, tmax)
                else {
                    // The tree's test met it and the lone test, by rounding
                    // at an edge, does not: a graze, passed as a miss.
                    return false;
                };
                let c = Candidate { b1, b2, inner: tri };
                at(&w.surface(ray, HitRef::new(t, object, c)))
            }
        }
    }
}

/// A shadow segment being traced by [`World::crossings`], and what it
/// hands each crossing to.
struct Segment<'a, F> {
    world: &'a World,
    ray: &'a Ray,
    tmin: f32,
    tmax: f32,
    /// The static-triangle leaves of the shaft holding the segment, if any.
    leaves: Option<&'a LeafSet>,
    cross: &'a mut F,
}

impl<F: FnMut(&Crossing<'_>) -> bool> Segment<'_, F> {
    /// Hands the crossing `what` on; true once it says to stop.
    #[inline(always)]
    fn cross(&mut self, what: Crossed) -> bool {
        let crossing = Crossing {
            world: self.world,
            ray: self.ray,
            range: (self.tmin, self.tmax),
            what,
        };
        (self.cross)(&crossing)
    }

    /// Hands on what the segment crosses of a top-level item (objects
    /// that cast no shadow are passed); true once told to stop. `r` is the
    /// ray prepared by the top level, if it was.
    #[inline(always)]
    fn blocked_by(&mut self, item: Item, r: Option<&TraversalRay>) -> bool {
        let (w, ray, tmin, tmax) = (self.world, self.ray, self.tmin, self.tmax);
        match item {
            Item::Object(object) => {
                let o = &w.objects[object as usize];
                if !o.casts_shadows {
                    return false;
                }
                let count = w.count_crossings(object, ray, tmin, tmax);
                count > 0 && self.cross(Crossed::Object { object, count })
            }
            Item::Quads(i) => {
                // A quad is crossed at most once: its lane says whether.
                let pack = &w.quads[i as usize];
                let mut mask = pack.quads.intersect(ray, tmin, tmax).mask;
                while mask != 0 {
                    let object = pack.objects[mask.trailing_zeros() as usize];
                    mask &= mask - 1;
                    if !w.objects[object as usize].casts_shadows {
                        continue;
                    }
                    if self.cross(Crossed::Object { object, count: 1 }) {
                        return true;
                    }
                }
                false
            }
            Item::Meshes => {
                let leaves = self.leaves;
                let mut hit = |id: u32| {
                    let o = &w.objects[w.tri_refs[id as usize].0 as usize];
                    o.casts_shadows && self.cross(Crossed::Triangle { id })
                };
                match (leaves, r) {
                    (Some(set), _) => w.tris.any_hit_in(set, ray, tmin, tmax, &mut hit),
                    (None, Some(r)) => w.tris.any_hit_prepared(r, tmin, tmax, &mut hit),
                    (None, None) => w.tris.any_hit(ray, tmin, tmax, &mut hit),
                }
            }
        }
    }
}

/// What [`World::gather_shaft`] carries from leaf to leaf.
struct ShaftGather<'a> {
    world: &'a World,
    shaft: &'a Shaft,
    /// The boxes of the segments' origins and targets.
    ends: [Aabb; 2],
    limit: usize,
    /// False once the static triangles' leaves overflowed `limit`.
    ok: bool,
}

impl ShaftGather<'_> {
    /// Lists the object as a shadow caster unless it cannot be crossed: a
    /// quad or disk with every end on one side of its plane, or a still
    /// analytic object whose box the shaft misses.
    #[inline(always)]
    fn consider(&self, object: u32, out: &mut ShaftSet) {
        let o = &self.world.objects[object as usize];
        if !o.casts_shadows {
            return;
        }
        let still = o.motion.is_none() && o.placement.is_none();
        let plane = o.shape.plane().filter(|_| still);
        let apart = plane.is_some_and(|(n, p)| one_side(n, p, &self.ends));
        let analytic = o.shape.as_mesh().is_none();
        let outside = || still && analytic && !self.shaft.overlaps(&o.shape.bounds(&[]));
        if !apart && !outside() {
            out.items.push(Item::Object(object));
        }
    }

    /// Takes the items of a top-level leaf, in the order of an any-hit
    /// traversal (see `crossings`).
    #[inline(always)]
    fn leaf(&mut self, items: &[Item], out: &mut ShaftSet) {
        for &item in items.iter().rev() {
            match item {
                Item::Object(object) => self.consider(object, out),
                // Lane by lane: the crossings come in the same order.
                Item::Quads(i) => {
                    for object in self.world.quads[i as usize].objects {
                        if object != u32::MAX {
                            self.consider(object, out);
                        }
                    }
                }
                Item::Meshes => {
                    self.ok = (self.world.tris).gather(self.shaft, self.limit, &mut out.leaves);
                    if !out.leaves.is_empty() {
                        out.items.push(item);
                    }
                }
            }
        }
    }
}

/// What a shadow set may cross, gathered once by [`World::gather_shaft`] and
/// read by [`World::crossings`] for each of its rays.
#[derive(Clone, Debug, Default)]
pub struct ShaftSet {
    /// Top-level leaves the shaft may reach.
    top: LeafSet,
    /// Static-triangle leaves the shaft may reach.
    leaves: LeafSet,
    /// What its segments may cross, in the order a traversal meets it: the
    /// casters among the objects of `top` and, if `leaves` is not empty,
    /// the static triangles.
    pub(super) items: Vec<Item>,
}

/// True if every box lies strictly on the same side of the plane through `p`
/// with normal `n`, by more than rounding of the plane test could blur; then
/// no segment between points of the boxes crosses the plane.
pub(super) fn one_side(n: Vec3, p: Vec3, boxes: &[Aabb]) -> bool {
    let d = n.dot(p);
    let (mut lo, mut hi) = (f32::INFINITY, f32::NEG_INFINITY);
    let mut size = d.abs();
    for b in boxes {
        let near = (n * b.min).min(n * b.max).element_sum();
        let far = (n * b.min).max(n * b.max).element_sum();
        size = size.max(b.min.abs().max(b.max.abs()).max_element());
        (lo, hi) = (lo.min(near - d), hi.max(far - d));
    }
    let margin = 16.0 * f32::EPSILON * size;
    lo > margin || hi < -margin
}
