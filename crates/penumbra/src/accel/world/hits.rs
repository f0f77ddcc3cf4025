//! Hits in two forms: the compact one the queries return ([`HitRef`],
//! and [`Hits`] for a batch, a structure of arrays) and the
//! surface-interaction record ([`Hit`]) built from it by
//! [`World::surface`] only where shading needs it.

use super::{Candidate, Hit, World};
use crate::geometry::{LocalGeometry, ShapeModel, SurfaceInteraction};
use crate::math::{Ray, Vec2, Vec3};

/// A hit as the queries find it (20 bytes): its distance along the ray,
/// the object, the primitive within the object and its two surface
/// coordinates (a triangle's index and barycentrics). [`World::surface`] makes the full record of it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HitRef {
    /// The distance along the ray, in units of its direction's length.
    pub t: f32,
    /// The object hit (an index into [`World::objects`]).
    pub object: u32,
    c: Candidate,
}

impl HitRef {
    pub(super) fn new(t: f32, object: u32, c: Candidate) -> HitRef {
        HitRef { t, object, c }
    }

    /// The parts [`Hits`] keeps of a ray's hit (`None`: a miss).
    #[inline(always)]
    fn parts(h: Option<HitRef>) -> (f32, u32, Candidate) {
        match h {
            Some(h) => (h.t, h.object, h.c),
            None => (f32::INFINITY, MISS, Candidate::default()),
        }
    }
}

/// The hits of a batch of rays, one entry per ray in order, as a
/// structure of arrays: distance, object (`u32::MAX` for a miss),
/// primitive and surface coordinates.
#[derive(Clone, Debug, Default)]
pub struct Hits {
    t: Vec<f32>,
    object: Vec<u32>,
    prim: Vec<u32>,
    bary: Vec<[f32; 2]>,
}

/// The object of a ray that hit nothing.
const MISS: u32 = u32::MAX;

impl Hits {
    pub fn len(&self) -> usize {
        self.t.len()
    }

    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }

    pub fn clear(&mut self) {
        self.t.clear();
        self.object.clear();
        self.prim.clear();
        self.bary.clear();
    }

    /// Appends the hit of the next ray (`None`: a miss).
    #[inline(always)]
    pub fn push(&mut self, h: Option<HitRef>) {
        let (t, object, c) = HitRef::parts(h);
        self.t.push(t);
        self.object.push(object);
        self.prim.push(c.inner);
        self.bary.push([c.b1, c.b2]);
    }

    /// The hit of ray `i`.
    #[inline(always)]
    pub fn get(&self, i: usize) -> Option<HitRef> {
        let object = self.object[i];
        (object != MISS).then(|| {
            let [b1, b2] = self.bary[i];
            let c = Candidate {
                b1,
                b2,
                inner: self.prim[i],
            };
            HitRef::new(self.t[i], object, c)
        })
    }

    /// Replaces the hit of ray `i`.
    pub fn set(&mut self, i: usize, h: Option<HitRef>) {
        let (t, object, c) = HitRef::parts(h);
        self.t[i] = t;
        self.object[i] = object;
        self.prim[i] = c.inner;
        self.bary[i] = [c.b1, c.b2];
    }

    /// The object ray `i` hit, if any.
    #[inline(always)]
    pub fn object(&self, i: usize) -> Option<u32> {
        let object = self.object[i];
        (object != MISS).then_some(object)
    }

    /// Every ray's distance to its hit (infinite for a miss).
    pub fn distances(&self) -> &[f32] {
        &self.t
    }
}

impl World {
    /// The surface-interaction record of hit `h` of `ray` (a hit the
    /// queries found for this ray): the point, normals, texture
    /// coordinates and tangents in world space, and what the object
    /// carries.
    pub fn surface(&self, ray: &Ray, h: HitRef) -> Hit {
        self.kernels.run(
            #[inline(always)]
            || self.surface_kernel(ray, h),
        )
    }

    /// [`surface`](Self::surface), compiled into each kernel set.
    #[inline(always)]
    pub(super) fn surface_kernel(&self, ray: &Ray, h: HitRef) -> Hit {
        let HitRef { t, object, c } = h;
        let o = &self.objects[object as usize];
        let shape_hit = c.at(t);
        // A static triangle's object neither moves nor is placed.
        match (o.motion.as_ref(), o.placement.as_deref()) {
            // The record of each case is made in place: merged with the
            // others' through memory, it would be read back with wider loads
            // than it was stored with, each waiting for the stores to drain
            // (a third of a hit's cost, for a triangle).
            (None, None) => {
                let p = ray.at(t);
                match o.shape.as_mesh() {
                    Some(m) => {
                        let g = ShapeModel::geometry(m, &self.meshes, &shape_hit, p);
                        self.record(object, ray, t, c, (p, g))
                    }
                    None => o.shape.with_geometry(
                        &self.meshes,
                        &shape_hit,
                        p,
                        #[inline(always)]
                        |g| self.record(object, ray, t, c, (p, g)),
                    ),
                }
            }
            (Some(m), _) => {
                let (local_ray, s) = m.to_object(ray);
                let p = local_ray.at(t);
                let g = o.shape.geometry(&self.meshes, &shape_hit, p);
                let g = g.transformed(|n| s.normal_to_world(n), |v| s.vector_to_world(v));
                self.record(object, ray, t, c, (s.point_to_world(p), g))
            }
            (None, Some(pl)) => {
                let p = pl.ray_to_object(ray).at(t);
                let g = o.shape.geometry(&self.meshes, &shape_hit, p);
                let g = g.transformed(|n| pl.normal_to_world(n), |v| pl.vector_to_world(v));
                self.record(object, ray, t, c, (pl.point_to_world(p), g))
            }
        }
    }

    /// The hit record of `object` at `point` with geometry `g` in world
    /// space: normals flipped if the object says so, the shading normal
    /// on the geometric normal's side.
    #[inline(always)]
    fn record(
        &self,
        object: u32,
        ray: &Ray,
        t: f32,
        c: Candidate,
        (point, g): (Vec3, LocalGeometry),
    ) -> Hit {
        let o = &self.objects[object as usize];
        let (ng, ns) = if o.flip_normals {
            (-g.ng, -g.ns)
        } else {
            (g.ng, g.ns)
        };
        let ns = if ns.dot(ng) < 0.0 { -ns } else { ns };
        SurfaceInteraction {
            t,
            p: point,
            time: ray.time,
            ng,
            n: ns,
            uv: g.uv,
            dpdu: g.dpdu,
            dpdv: g.dpdv,
            prim: c.inner,
            bary: if o.shape.as_mesh().is_some() {
                Vec2::new(c.b1, c.b2)
            } else {
                Vec2::ZERO
            },
            object,
            material: o.material,
            emitter: o.emitter,
        }
    }

    /// The records of all of `hits`, the hits of `rays`, into `out`.
    pub fn surfaces(&self, rays: &[Ray], hits: &Hits, out: &mut Vec<Option<Hit>>) {
        self.kernels.run(
            #[inline(always)]
            || {
                out.clear();
                // Zipped slices: one exact-size pass, no checks per item.
                let refs = (hits.t.iter().zip(&hits.object)).zip(hits.prim.iter().zip(&hits.bary));
                out.extend(rays.iter().zip(refs).map(
                    #[inline(always)]
                    |(ray, ((&t, &object), (&inner, &[b1, b2])))| {
                        let c = Candidate { b1, b2, inner };
                        (object != MISS)
                            .then(|| self.surface_kernel(ray, HitRef::new(t, object, c)))
                    },
                ));
            },
        )
    }
}
