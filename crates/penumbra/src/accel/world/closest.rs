//! Closest hits: one ray ([`World::intersect`]) and batches
//! ([`World::intersect_all`]), whose packets of rays from one point pass
//! the top level's objects one by one and the static triangles at once.

use super::{Candidate, Hit, Item, Prim, World};
use crate::accel::bvh4::{Frustum, RayPacket};
use crate::accel::TriHit;
use crate::math::{nearest_lane, Ray};

impl World {
    /// The closest surface along the ray within (tmin, tmax).
    pub fn intersect(&self, ray: &Ray, tmin: f32, tmax: f32) -> Option<Hit> {
        self.kernels.run(
            #[inline(always)]
            || self.intersect_kernel(ray, tmin, tmax),
        )
    }

    /// [`intersect`](Self::intersect), compiled into each kernel set.
    #[inline(always)]
    fn intersect_kernel(&self, ray: &Ray, tmin: f32, tmax: f32) -> Option<Hit> {
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
        best.map(|(prim, t, cand)| self.make_hit(prim, ray, t, cand))
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
        let prim = Prim::Object { object };
        if let Some((t, c)) = self.intersect_prim(prim, ray, tmin, *tmax) {
            *tmax = t;
            *best = Some((prim, t, c));
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
        *best = Some((Prim::Object { object }, h.t[lane], cand));
    }

    /// [`intersect`](Self::intersect) for each of `rays`, written to `out` in
    /// order: the same hits (of static triangles hit at exactly the same
    /// distance, the lowest index on both paths). Rays from one point in
    /// nearly one direction (a packet: a pixel's camera rays, a span's, a
    /// narrow glossy set) pass the top level's objects one by one, then the
    /// static triangles all at once (see [`TriangleBvh::closest_hits`](crate::accel::TriangleBvh::closest_hits));
    /// other batches, and a batch of one, are traced ray by ray.
    pub fn intersect_all(
        &self,
        rays: &[Ray],
        tmin: f32,
        scratch: &mut PacketScratch,
        out: &mut Vec<Option<Hit>>,
    ) {
        self.kernels.run(
            #[inline(always)]
            || {
                // A batch of one, or of rays that are not a packet: each ray's own walk.
                let Some(frustum) = Frustum::packet(rays) else {
                    out.clear();
                    // A loop, not `extend`: kept inline in the kernel set's code.
                    for r in rays {
                        out.push(self.intersect_kernel(r, tmin, f32::INFINITY));
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
                            let rays_items =
                                rays.iter().zip(objects.iter_mut()).zip(tmax.iter_mut());
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
                            *tmax = best.map_or(f32::INFINITY, |b| b.1);
                        }
                    }
                }
                (self.tris).closest_hits_in(&frustum, rays, tmin, tmax, packet, tris);
                out.clear();
                let hits = rays.iter().zip(objects.iter()).zip(tris.iter());
                out.extend(hits.map(|((ray, best), tri)| {
                    let best = tri.map(|h| self.triangle_candidate(&h)).or(*best);
                    best.map(|(prim, t, cand)| self.make_hit(prim, ray, t, cand))
                }));
            },
        )
    }

    fn triangle_candidate(&self, h: &TriHit) -> (Prim, f32, Candidate) {
        let (object, tri) = self.tri_refs[h.id as usize];
        let cand = Candidate {
            b1: h.b1,
            b2: h.b2,
            inner: tri,
        };
        (Prim::Triangle { object }, h.t, cand)
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
type Best = Option<(Prim, f32, Candidate)>;
