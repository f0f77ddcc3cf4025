//! Closest hits: one ray ([`World::intersect`]) and batches
//! ([`World::intersect_all`]), whose packets of rays from one point pass
//! the top level's objects one by one and the static triangles at once.

use super::{Candidate, Hit, HitRef, Hits, Item, World};
use crate::accel::bvh4::{Frustum, RayPacket};
use crate::accel::TriHit;
use crate::math::{nearest_lane, Ray};

impl World {
    /// The closest surface along the ray within (tmin, tmax).
    pub fn intersect(&self, ray: &Ray, tmin: f32, tmax: f32) -> Option<Hit> {
        self.kernels.run(
            #[inline(always)]
            || {
                let h = self.closest_kernel(ray, tmin, tmax)?;
                Some(self.surface_kernel(ray, h))
            },
        )
    }

    /// The closest hit along the ray within (tmin, tmax), in its compact
    /// form: [`intersect`](Self::intersect) without the record.
    pub fn closest(&self, ray: &Ray, tmin: f32, tmax: f32) -> Option<HitRef> {
        self.kernels.run(
            #[inline(always)]
            || self.closest_kernel(ray, tmin, tmax),
        )
    }

    /// [`closest`](Self::closest), compiled into each kernel set.
    #[inline(always)]
    fn closest_kernel(&self, ray: &Ray, tmin: f32, tmax: f32) -> Option<HitRef> {
        let mut best = None;
        self.top.traverse_items::<true>(
            self.kernels,
            ray,
            tmin,
            tmax,
            #[inline(always)]
            |items, r, tmax| {
                for &item in items {
                    match item {
                        Item::Object(_) | Item::Quads(_) => {
                            self.closest_item(item, ray, tmin, tmax, &mut best)
                        }
                        Item::Meshes => {
                            let h = match r {
                                Some(r) => self.tris.closest_hit_prepared(r, tmin, *tmax),
                                None => self.tris.closest_hit(ray, tmin, *tmax),
                            };
                            if let Some(h) = h {
                                *tmax = h.t;
                                best = Some(self.triangle_candidate(&h));
                            }
                        }
                    }
                }
                false
            },
        );
        best
    }

    /// [`closest_object`](Self::closest_object) or
    /// [`closest_quad`](Self::closest_quad) for a top-level item (nothing
    /// for the static triangles, which the caller traces).
    #[inline(always)]
    fn closest_item(&self, item: Item, ray: &Ray, tmin: f32, tmax: &mut f32, best: &mut Best) {
        match item {
            Item::Object(object) => self.closest_object(object, ray, tmin, tmax, best),
            Item::Quads(i) => self.closest_quad(i, ray, tmin, tmax, best),
            Item::Meshes => {}
        }
    }

    /// Tests one object for a hit nearer than `tmax`; on one, shrinks
    /// `tmax` to it and records it in `best`.
    #[inline]
    fn closest_object(&self, object: u32, ray: &Ray, tmin: f32, tmax: &mut f32, best: &mut Best) {
        if let Some((t, c)) = self.intersect_prim(object, ray, tmin, *tmax) {
            *tmax = t;
            *best = Some(HitRef::new(t, object, c));
        }
    }

    /// [`closest_object`](Self::closest_object) for the quads of
    /// `self.quads[i]`: the nearest lane, the first of equals (as testing
    /// them in order does).
    #[inline]
    fn closest_quad(&self, i: u32, ray: &Ray, tmin: f32, tmax: &mut f32, best: &mut Best) {
        let pack = &self.quads[i as usize];
        let h = pack.quads.intersect(ray, tmin, *tmax);
        if h.mask == 0 {
            return;
        }
        let lane = nearest_lane(h.mask, &h.t);
        let cand = Candidate {
            b1: h.s[lane],
            b2: h.tt[lane],
            inner: 0,
        };
        let object = pack.objects[lane];
        *tmax = h.t[lane];
        *best = Some(HitRef::new(h.t[lane], object, cand));
    }

    /// [`closest`](Self::closest) for each of `rays`, written to `out` in
    /// order in the compact form ([`World::surface`] makes the record of
    /// each where it is needed): the same hits (of static triangles hit at
    /// exactly the same distance, the lowest index on both paths). Rays
    /// from one point in nearly one direction (a packet: a pixel's camera
    /// rays, a span's, a narrow glossy set) pass the top level's objects
    /// one by one, then the static triangles all at once (see
    /// [`TriangleBvh::closest_hits`](crate::accel::TriangleBvh::closest_hits));
    /// other batches, and a batch of one, are traced ray by ray.
    pub fn intersect_all(
        &self,
        rays: &[Ray],
        tmin: f32,
        scratch: &mut PacketScratch,
        out: &mut Hits,
    ) {
        self.kernels.run(
            #[inline(always)]
            || {
                out.clear();
                self.closest_each(
                    rays,
                    tmin,
                    scratch,
                    #[inline(always)]
                    |_, h| out.push(h),
                );
            },
        )
    }

    /// [`intersect_all`](Self::intersect_all) with the record of every hit,
    /// made as each is found: for a caller that shades every hit.
    pub fn intersect_all_records(
        &self,
        rays: &[Ray],
        tmin: f32,
        scratch: &mut PacketScratch,
        out: &mut Vec<Option<Hit>>,
    ) {
        self.kernels.run(
            #[inline(always)]
            || {
                out.clear();
                self.closest_each(
                    rays,
                    tmin,
                    scratch,
                    #[inline(always)]
                    |ray, h| out.push(h.map(|h| self.surface_kernel(ray, h))),
                );
            },
        )
    }

    /// The body of the batch queries: the closest hit of each of `rays`,
    /// handed in order to `found` with its ray.
    #[inline(always)]
    fn closest_each(
        &self,
        rays: &[Ray],
        tmin: f32,
        scratch: &mut PacketScratch,
        mut found: impl FnMut(&Ray, Option<HitRef>),
    ) {
        // A batch of one, or of rays that are not a packet: each ray's own walk.
        let Some(frustum) = Frustum::packet(rays) else {
            // A loop, not `for_each`: kept inline in the kernel set's code.
            for r in rays {
                found(r, self.closest_kernel(r, tmin, f32::INFINITY));
            }
            return;
        };
        let PacketScratch {
            objects,
            tmax,
            tris,
            packet,
        } = scratch;
        objects.clear();
        objects.resize(rays.len(), None);
        tmax.clear();
        tmax.resize(rays.len(), f32::INFINITY);
        let rays_items = rays.iter().zip(objects.iter_mut()).zip(tmax.iter_mut());
        match self.top.single_leaf() {
            // A top level of one leaf: item by item, all rays (each item's
            // data loaded once), in the order a ray alone meets them.
            Some(items) => {
                for &item in items {
                    let rays_items = rays.iter().zip(objects.iter_mut()).zip(tmax.iter_mut());
                    match item {
                        Item::Object(object) => {
                            for ((ray, best), tmax) in rays_items {
                                self.closest_object(object, ray, tmin, tmax, best);
                            }
                        }
                        Item::Quads(i) => {
                            for ((ray, best), tmax) in rays_items {
                                self.closest_quad(i, ray, tmin, tmax, best);
                            }
                        }
                        Item::Meshes => {}
                    }
                }
            }
            None => {
                for ((ray, best), tmax) in rays_items {
                    self.top.traverse_items::<true>(
                        self.kernels,
                        ray,
                        tmin,
                        *tmax,
                        #[inline(always)]
                        |items, _, tmax| {
                            for &item in items {
                                self.closest_item(item, ray, tmin, tmax, best);
                            }
                            false
                        },
                    );
                    // The top level's traversal keeps its own limit.
                    *tmax = best.map_or(f32::INFINITY, |b| b.t);
                }
            }
        }
        (self.tris).closest_hits_in(&frustum, rays, tmin, tmax, packet, tris);
        let hits = rays.iter().zip(objects.iter()).zip(tris.iter());
        for ((ray, best), tri) in hits {
            found(ray, tri.map(|h| self.triangle_candidate(&h)).or(*best));
        }
    }

    fn triangle_candidate(&self, h: &TriHit) -> HitRef {
        let (object, tri) = self.tri_refs[h.id as usize];
        let cand = Candidate {
            b1: h.b1,
            b2: h.b2,
            inner: tri,
        };
        HitRef::new(h.t, object, cand)
    }
}

/// Per-worker buffers of [`World::intersect_all`].
#[derive(Default)]
pub struct PacketScratch {
    objects: Vec<Best>,
    tmax: Vec<f32>,
    tris: Vec<Option<TriHit>>,
    packet: RayPacket,
}

/// The closest hit found so far by a query.
type Best = Option<HitRef>;
