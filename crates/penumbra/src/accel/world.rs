//! The scene's geometry: the triangles of static meshes in one four-wide
//! triangle BVH, every other object under a generic BVH.
//!
//! Static meshes are baked into world space and their triangles copied into a
//! [`TriangleBvh`] in leaf order (the fastest layout for rays: no indirection
//! per triangle, four triangles per SIMD test). Spheres, quads and disks, and
//! moving objects, are primitives of a generic [`Bvh`]; moving objects stay in
//! object space (a moving mesh with its own BVH) and are intersected by
//! transforming the ray to the object at the ray's time, bounded in the BVH
//! over the whole shutter interval. A ray is traced through the objects first
//! and then through the triangles with its range cut at the object hit (a
//! ground plane in front of a mesh spares the mesh's BVH).

use super::{brute_closest, Bvh, LeafSet, RayPacket, Shaft, TriHit, TriangleBvh};
use crate::geometry::motion::Motion;
use crate::geometry::quad::{Quad, Quad4};
use crate::geometry::triangle::RayShear;
use crate::geometry::{Mesh, Shape, ShapeHit};
use crate::math::{nearest_lane, Aabb, Ray, Vec3};

pub struct Object {
    pub shape: Shape,
    pub material: u32,
    /// The light this object is the visible surface of, if any.
    pub light: Option<u32>,
    pub motion: Option<Motion>,
    /// BVH over the mesh's triangles, for moving meshes only.
    pub mesh_bvh: Option<Bvh>,
}

/// Up to this many objects besides static triangles are simply tested one
/// after the other: cheaper than a BVH traversal (a ground quad and a light).
const FEW: usize = 4;

/// What the object BVH indexes.
#[derive(Clone, Copy, Debug)]
pub enum Prim {
    Triangle { object: u32, tri: u32 },
    Object { object: u32 },
}

/// A surface point found by a ray.
#[derive(Clone, Copy, Debug)]
pub struct Hit {
    pub t: f32,
    pub point: Vec3,
    /// Unit geometric normal, as the shape defines it (not flipped toward the ray).
    pub ng: Vec3,
    /// Unit shading normal, in the same hemisphere as `ng`.
    pub ns: Vec3,
    pub material: u32,
    pub light: Option<u32>,
}

pub struct World {
    pub objects: Vec<Object>,
    pub meshes: Vec<Mesh>,
    /// Triangles of the static meshes; a hit's id indexes `tri_refs`.
    tris: TriangleBvh,
    /// Object and triangle index of each triangle of `tris`.
    tri_refs: Vec<(u32, u32)>,
    /// The other objects, under `bvh`.
    prims: Vec<Prim>,
    /// Indices into `prims` of the objects that cast shadows (not lights).
    casters: Vec<u32>,
    bvh: Bvh,
    /// The other objects four lanes at once, when they are at most four
    /// static quads (a ground and a light): lane `i` is `prims[i]`.
    quads: Option<Quad4>,
    /// No object moves.
    is_static: bool,
}

/// Intersection details kept while the BVH search runs ([`ShapeHit`]
/// without its distance); turned into a [`Hit`] only once, for the closest
/// primitive.
#[derive(Clone, Copy, Default)]
struct Candidate {
    b1: f32,
    b2: f32,
    inner: u32,
}

impl Candidate {
    fn of(h: ShapeHit) -> (f32, Candidate) {
        let c = Candidate {
            b1: h.b1,
            b2: h.b2,
            inner: h.inner,
        };
        (h.t, c)
    }

    fn at(self, t: f32) -> ShapeHit {
        ShapeHit {
            t,
            b1: self.b1,
            b2: self.b2,
            inner: self.inner,
        }
    }
}

impl World {
    pub fn new(objects: Vec<Object>, meshes: Vec<Mesh>) -> World {
        let mut tri_refs = Vec::new();
        let mut tri_meshes = Vec::new();
        let mut prims = Vec::new();
        let mut bounds = Vec::new();
        for (oi, o) in objects.iter().enumerate() {
            let object = oi as u32;
            match (&o.shape, o.motion) {
                (Shape::Mesh { mesh }, None) => {
                    let m = &meshes[*mesh as usize];
                    tri_refs.extend((0..m.triangles.len() as u32).map(|tri| (object, tri)));
                    tri_meshes.resize(tri_refs.len(), *mesh);
                }
                (shape, motion) => {
                    let b = shape.bounds(&meshes);
                    prims.push(Prim::Object { object });
                    bounds.push(motion.map_or(b, |m| m.bounds(b)));
                }
            }
        }
        let tris = TriangleBvh::build(tri_refs.len(), |i| {
            meshes[tri_meshes[i] as usize].vertices(tri_refs[i].1 as usize)
        });
        let bvh = Bvh::build(&bounds);
        let casters = (0..prims.len() as u32)
            .filter(|&i| {
                objects[prim_object(prims[i as usize]) as usize]
                    .light
                    .is_none()
            })
            .collect();
        let is_static = objects.iter().all(|o| o.motion.is_none());
        let quads = few_quads(&prims, &objects);
        World {
            objects,
            meshes,
            tris,
            tri_refs,
            prims,
            casters,
            bvh,
            quads,
            is_static,
        }
    }

    pub fn bounds(&self) -> Aabb {
        self.bvh.bounds().union(self.tris.bounds())
    }

    pub fn primitive_count(&self) -> usize {
        self.tri_refs.len() + self.prims.len()
    }

    /// True when no object moves (the camera may still).
    pub fn is_static(&self) -> bool {
        self.is_static
    }

    /// The closest surface along the ray within (tmin, tmax).
    pub fn intersect(&self, ray: &Ray, tmin: f32, tmax: f32) -> Option<Hit> {
        // The few other objects first (a ground, a light): their hit cuts the
        // ray before the triangle BVH, which then often culls at its root.
        let best = self.closest_object(ray, tmin, tmax);
        let tmax = best.map_or(tmax, |b| b.1);
        let tri = self.tris.closest_hit(ray, tmin, tmax);
        self.finish(ray, best, tri.as_ref())
    }

    /// The hit record of the nearer of an object hit and a triangle hit
    /// found within the object's distance (so the triangle, if any, wins).
    fn finish(
        &self,
        ray: &Ray,
        object: Option<(Prim, f32, Candidate)>,
        tri: Option<&TriHit>,
    ) -> Option<Hit> {
        let best = tri.map(|h| self.triangle_candidate(h)).or(object);
        best.map(|(prim, t, cand)| self.make_hit(prim, ray, t, cand))
    }

    /// [`intersect`](Self::intersect) for each of `rays`, written to `out` in
    /// order: the same hits (of static triangles hit at exactly the same
    /// distance, the lowest index on both paths). The static
    /// triangles are searched for all rays at once (see
    /// [`TriangleBvh::closest_hits`]), which pays off for rays from one
    /// point in nearly one direction: the camera rays of a pixel.
    pub fn intersect_all(
        &self,
        rays: &[Ray],
        tmin: f32,
        scratch: &mut PacketScratch,
        out: &mut Vec<Option<Hit>>,
    ) {
        let PacketScratch {
            objects,
            tmax,
            tris,
            packet,
        } = scratch;
        objects.clear();
        objects.extend(
            rays.iter()
                .map(|r| self.closest_object(r, tmin, f32::INFINITY)),
        );
        tmax.clear();
        tmax.extend(objects.iter().map(|b| b.map_or(f32::INFINITY, |b| b.1)));
        self.tris.closest_hits(rays, tmin, tmax, packet, tris);
        out.clear();
        let hits = rays.iter().zip(objects.iter()).zip(tris.iter());
        out.extend(hits.map(|((ray, best), tri)| self.finish(ray, *best, tri.as_ref())));
    }

    fn triangle_candidate(&self, h: &TriHit) -> (Prim, f32, Candidate) {
        let (object, tri) = self.tri_refs[h.id as usize];
        let cand = Candidate {
            b1: h.b1,
            b2: h.b2,
            inner: tri,
        };
        (Prim::Triangle { object, tri }, h.t, cand)
    }

    /// The closest of the objects that are not static triangles.
    #[inline]
    fn closest_object(&self, ray: &Ray, tmin: f32, tmax: f32) -> Option<(Prim, f32, Candidate)> {
        match &self.quads {
            Some(q) => self.closest_quad(q, ray, tmin, tmax),
            None => self.closest_other(ray, tmin, tmax),
        }
    }

    /// The nearest lane of the few quads, the first of equals (as testing
    /// them in order does).
    #[inline]
    fn closest_quad(
        &self,
        q: &Quad4,
        ray: &Ray,
        tmin: f32,
        tmax: f32,
    ) -> Option<(Prim, f32, Candidate)> {
        let h = q.intersect(ray, tmin, tmax);
        if h.mask == 0 {
            return None;
        }
        let lane = nearest_lane(h.mask, &h.t);
        let cand = Candidate {
            b1: h.s[lane],
            b2: h.tt[lane],
            inner: 0,
        };
        Some((self.prims[lane], h.t[lane], cand))
    }

    /// [`closest_object`](Self::closest_object) one object at a time.
    #[inline(never)]
    fn closest_other(&self, ray: &Ray, tmin: f32, tmax: f32) -> Option<(Prim, f32, Candidate)> {
        let mut cand = Candidate::default();
        let test = |i: u32, tmax: f32| {
            let (t, c) = self.intersect_prim(self.prims[i as usize], ray, tmin, tmax)?;
            cand = c;
            Some(t)
        };
        let found = if self.prims.len() <= FEW {
            brute_closest(self.prims.len(), ray, tmin, tmax, test)
        } else {
            self.bvh.closest_hit(ray, tmin, tmax, test)
        };
        found.map(|(i, t)| (self.prims[i as usize], t, cand))
    }

    /// Prepares `out` for the segments from the box `origins` to the box
    /// `targets` (a shadow set, see [`Shaft`]): gathers the static-triangle
    /// leaves they may cross, and notes which of the few other shadow casters
    /// they may cross (a quad or disk with every end point on one side of its
    /// plane cannot be crossed: the ground a shadow set starts from, say;
    /// nor can a still object whose bounding box lies outside the shaft).
    /// Returns false if the boxes are not finite or the shaft reaches more
    /// than `limit` leaves: then the rays are better traced one by one.
    pub fn gather_shaft(
        &self,
        origins: Aabb,
        targets: Aabb,
        limit: usize,
        out: &mut ShaftSet,
    ) -> bool {
        let Some(shaft) = Shaft::new(origins, targets) else {
            return false;
        };
        if !self.tris.gather(&shaft, limit, &mut out.leaves) {
            return false;
        }
        out.casters = 0;
        for (bit, &i) in self.casters.iter().enumerate().take(FEW) {
            let o = &self.objects[prim_object(self.prims[i as usize]) as usize];
            let still = o.motion.is_none();
            let plane = o.shape.plane().filter(|_| still);
            let apart = plane.is_some_and(|(n, p)| one_side(n, p, &[origins, targets]));
            // Otherwise a still object whose box the shaft misses.
            let analytic = !matches!(o.shape, Shape::Mesh { .. });
            let outside = || still && analytic && !shaft.overlaps(&o.shape.bounds(&[]));
            if !apart && !outside() {
                out.casters |= 1 << bit;
            }
        }
        true
    }

    /// True if nothing can block a segment held by the shaft `set` was
    /// gathered for: no static-triangle leaf and no other caster is within
    /// it. [`transmittance`](Self::transmittance) within it is then 1 for
    /// every such segment, and a shadow set need not trace its rays.
    pub fn shaft_is_clear(&self, set: &ShaftSet) -> bool {
        let listed = self.casters.len().min(FEW);
        set.leaves.is_empty() && self.prims.len() <= FEW && set.casters & ((1 << listed) - 1) == 0
    }

    /// Fraction of light passing along the ray within (tmin, tmax): `None`
    /// when an opaque surface blocks it. Transparent surfaces let light
    /// through attenuated by their transparency at every crossing (without
    /// bending it); light surfaces cast no shadow. With `shaft`, what
    /// [`gather_shaft`](Self::gather_shaft) found for a shaft holding the
    /// segment, only its leaves are tested among the static triangles and
    /// only its casters among the other objects (the result is the same, bit
    /// for bit).
    pub fn transmittance(
        &self,
        ray: &Ray,
        (tmin, tmax): (f32, f32),
        transparency: &[f32],
        shaft: Option<&ShaftSet>,
    ) -> Option<f32> {
        let mut trans = 1.0f32;
        let hit = |id: u32| {
            let o = &self.objects[self.tri_refs[id as usize].0 as usize];
            if o.light.is_some() {
                return false;
            }
            trans *= transparency[o.material as usize];
            trans <= 0.0
        };
        let blocked = match shaft {
            None => self.tris.any_hit(ray, tmin, tmax, hit),
            Some(set) => self.tris.any_hit_in(&set.leaves, ray, tmin, tmax, hit),
        };
        if blocked {
            return None;
        }
        let test = |i: u32, tmax: f32| {
            let prim = self.prims[i as usize];
            let o = &self.objects[prim_object(prim) as usize];
            if o.light.is_some() {
                return false;
            }
            let crossings = self.count_crossings(prim, ray, tmin, tmax);
            if crossings == 0 {
                return false;
            }
            let kt = transparency[o.material as usize];
            trans *= kt.powi(crossings);
            trans <= 0.0
        };
        let blocked = if self.prims.len() <= FEW {
            // Only the objects that cast shadows (lights do not), and of
            // those only the ones the shaft may cross.
            let may_cross = shaft.map_or(u32::MAX, |s| s.casters);
            let mut casters = self.casters.iter().enumerate();
            if let Some(q) = &self.quads {
                // A quad is crossed at most once: its lane says whether.
                // (With a shaft, often no caster is left to test.)
                let listed = self.casters.len().min(FEW);
                if may_cross & ((1 << listed) - 1) == 0 {
                    return Some(trans);
                }
                let crossed = q.intersect(ray, tmin, tmax).mask;
                casters.any(|(bit, &i)| {
                    if may_cross >> bit & crossed >> i & 1 == 0 {
                        return false;
                    }
                    let o = &self.objects[prim_object(self.prims[i as usize]) as usize];
                    trans *= transparency[o.material as usize];
                    trans <= 0.0
                })
            } else {
                let mut test = test;
                casters.any(|(bit, &i)| may_cross >> bit & 1 != 0 && test(i, tmax))
            }
        } else {
            self.bvh.any_hit(ray, tmin, tmax, test)
        };
        (!blocked).then_some(trans)
    }

    fn count_crossings(&self, prim: Prim, ray: &Ray, tmin: f32, tmax: f32) -> i32 {
        let Some((t, _)) = self.intersect_prim(prim, ray, tmin, tmax) else {
            return 0;
        };
        // A closed shape (a sphere) can be crossed twice within the segment (in and out).
        let closed = self.objects[prim_object(prim) as usize].shape.is_closed();
        let second = matches!(prim, Prim::Object { .. })
            && closed
            && self.intersect_prim(prim, ray, t, tmax).is_some();
        1 + i32::from(second)
    }

    /// Intersects a primitive of the object BVH.
    fn intersect_prim(
        &self,
        prim: Prim,
        ray: &Ray,
        tmin: f32,
        tmax: f32,
    ) -> Option<(f32, Candidate)> {
        match prim {
            Prim::Triangle { object, tri } => {
                // Static triangles live in the triangle BVH; kept for completeness.
                let Shape::Mesh { mesh } = self.objects[object as usize].shape else {
                    return None;
                };
                let m = &self.meshes[mesh as usize];
                let shear = RayShear::new(ray);
                Shape::intersect_triangle_of(m, tri, ray, &shear, tmin, tmax).map(Candidate::of)
            }
            Prim::Object { object } => {
                let o = &self.objects[object as usize];
                match o.motion {
                    None => self.intersect_shape(o, ray, tmin, tmax),
                    Some(m) => {
                        let (local, _) = m.to_object(ray);
                        self.intersect_shape(o, &local, tmin, tmax)
                    }
                }
            }
        }
    }

    fn intersect_shape(
        &self,
        o: &Object,
        ray: &Ray,
        tmin: f32,
        tmax: f32,
    ) -> Option<(f32, Candidate)> {
        let Shape::Mesh { mesh } = o.shape else {
            return o.shape.intersect(ray, tmin, tmax).map(Candidate::of);
        };
        // A moving mesh: its own BVH, in its own space.
        let m = &self.meshes[mesh as usize];
        let bvh = o.mesh_bvh.as_ref()?;
        let shear = RayShear::new(ray);
        let mut cand = Candidate::default();
        let (tri, t) = bvh.closest_hit(ray, tmin, tmax, |i, tmax| {
            let (t, c) =
                Candidate::of(Shape::intersect_triangle_of(m, i, ray, &shear, tmin, tmax)?);
            cand = c;
            Some(t)
        })?;
        cand.inner = tri;
        Some((t, cand))
    }

    fn make_hit(&self, prim: Prim, ray: &Ray, t: f32, c: Candidate) -> Hit {
        let object = prim_object(prim);
        let o = &self.objects[object as usize];
        let (local_ray, placement) = match (prim, o.motion) {
            (Prim::Object { .. }, Some(m)) => {
                let (r, s) = m.to_object(ray);
                (r, Some(s))
            }
            _ => (*ray, None),
        };
        let p = local_ray.at(t);
        let (ng, ns) = o.shape.normals(&self.meshes, &c.at(t), p);
        let (point, ng, ns) = match placement {
            None => (ray.at(t), ng, ns),
            Some(s) => (
                s.point_to_world(p),
                s.normal_to_world(ng),
                s.normal_to_world(ns),
            ),
        };
        let ns = if ns.dot(ng) < 0.0 { -ns } else { ns };
        Hit {
            t,
            point,
            ng,
            ns,
            material: o.material,
            light: o.light,
        }
    }
}

/// Per-worker buffers of [`World::intersect_all`].
#[derive(Default)]
pub struct PacketScratch {
    objects: Vec<Option<(Prim, f32, Candidate)>>,
    tmax: Vec<f32>,
    tris: Vec<Option<TriHit>>,
    packet: RayPacket,
}

/// What a shadow set may cross, gathered once by [`World::gather_shaft`] and
/// read by [`World::transmittance`] for each of its rays.
#[derive(Clone, Debug, Default)]
pub struct ShaftSet {
    leaves: LeafSet,
    /// Bit `i`: the `i`-th of the few non-triangle casters may be crossed.
    casters: u32,
}

/// True if every box lies strictly on the same side of the plane through `p`
/// with normal `n`, by more than rounding of the plane test could blur; then
/// no segment between points of the boxes crosses the plane.
fn one_side(n: Vec3, p: Vec3, boxes: &[Aabb]) -> bool {
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

/// The four-lane form of the other objects if they are at most [`FEW`]
/// static quads.
fn few_quads(prims: &[Prim], objects: &[Object]) -> Option<Quad4> {
    if prims.len() > FEW {
        return None;
    }
    let quads: Option<Vec<Quad>> = prims
        .iter()
        .map(|&p| match &objects[prim_object(p) as usize] {
            Object {
                shape: Shape::Quad(q),
                motion: None,
                ..
            } => Some(*q),
            _ => None,
        })
        .collect();
    Quad4::new(&quads?)
}

fn prim_object(p: Prim) -> u32 {
    match p {
        Prim::Triangle { object, .. } | Prim::Object { object } => object,
    }
}

/// Builds the BVH of a mesh in its own space (moving meshes).
pub fn mesh_bvh(mesh: &Mesh) -> Bvh {
    let bounds: Vec<Aabb> = (0..mesh.triangles.len())
        .map(|i| mesh.triangle_bounds(i))
        .collect();
    Bvh::build(&bounds)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{self, offset_origin};

    fn point(x: f32, y: f32, z: f32) -> Aabb {
        Aabb::new(Vec3::new(x, y, z), Vec3::new(x, y, z))
    }

    /// Shadow sets leaving the ground upward never cross it; sets that reach
    /// the plane, or start within rounding distance of it, may.
    #[test]
    fn one_side_of_a_plane() {
        let (n, p) = (Vec3::Y, Vec3::new(3.0, 0.0, -2.0));
        let light = Aabb::new(Vec3::new(-0.5, 4.0, -0.5), Vec3::new(0.5, 4.0, 0.5));
        // An origin offset as `offset_origin` does at magnitude 4.
        let lifted = point(4.0, 4.0 / 65536.0, 1.0);
        assert!(one_side(n, p, &[lifted, light]));
        assert!(one_side(-n, p, &[lifted, light]));
        assert!(!one_side(n, p, &[point(4.0, 0.0, 1.0), light]));
        assert!(!one_side(n, p, &[point(4.0, 1e-7, 1.0), light]));
        assert!(!one_side(n, p, &[lifted, point(0.0, -1.0, 0.0)]));
        let below = Aabb::new(Vec3::new(-1.0, -3.0, -1.0), Vec3::new(1.0, -0.5, 1.0));
        assert!(one_side(n, p, &[below, point(0.0, -2.0, 7.0)]));
        assert!(!one_side(n, p, &[below, light]));
    }

    /// 600 small triangles (material 0) over a 10×10 ground quad
    /// (material 0) and one more object (material 1).
    fn soup_ground_and_sphere(other: Shape) -> World {
        use crate::sampling::Rng;
        let mut r = Rng::new(31);
        let mut v = || Vec3::new(r.range(-2.0, 2.0), r.range(0.0, 3.0), r.range(-2.0, 2.0));
        let mut positions = Vec::new();
        for _ in 0..600 {
            let c = v();
            let tri = [c, c + v() * 0.1, c + v() * 0.1];
            positions.extend(tri);
        }
        let triangles = (0..600u32).map(|i| [3 * i, 3 * i + 1, 3 * i + 2]).collect();
        let mesh = Mesh {
            positions,
            normals: None,
            triangles,
        };
        let object = |shape, material| Object {
            shape,
            material,
            light: None,
            motion: None,
            mesh_bvh: None,
        };
        let ground = Quad::new(Vec3::new(-5.0, 0.0, -5.0), Vec3::Z * 10.0, Vec3::X * 10.0);
        let objects = vec![
            object(Shape::Mesh { mesh: 0 }, 0),
            object(Shape::Quad(ground), 0),
            object(other, 1),
        ];
        World::new(objects, vec![mesh])
    }

    /// The camera rays of pixels, found together, hit what each finds
    /// alone: with the few objects as four quads at once (a second quad)
    /// and one by one (a sphere).
    #[test]
    fn packets_hit_what_single_rays_hit() {
        use crate::sampling::Rng;
        let light = Quad::new(Vec3::new(-0.5, 4.0, -0.5), Vec3::X, Vec3::Z);
        let sphere = Shape::Sphere {
            center: Vec3::new(0.5, 1.0, 0.0),
            radius: 0.4,
        };
        let (mut scratch, mut out, mut r) = (PacketScratch::default(), Vec::new(), Rng::new(41));
        for world in [
            soup_ground_and_sphere(Shape::Quad(light)),
            soup_ground_and_sphere(sphere),
        ] {
            let mut total = 0;
            for _ in 0..500 {
                let eye = Vec3::new(r.range(-6.0, 6.0), r.range(0.5, 6.0), r.range(-6.0, 6.0));
                let at = Vec3::new(r.range(-2.0, 2.0), r.range(0.0, 3.0), r.range(-2.0, 2.0));
                let rays: Vec<Ray> = (0..16)
                    .map(|_| {
                        let jitter = Vec3::new(r.range(-1.0, 1.0), r.range(-1.0, 1.0), 0.0);
                        Ray::new(eye, at - eye + jitter * 0.01, 0.0)
                    })
                    .collect();
                world.intersect_all(&rays, 0.0, &mut scratch, &mut out);
                for (ray, got) in rays.iter().zip(&out) {
                    let alone = world.intersect(ray, 0.0, f32::INFINITY);
                    assert_eq!(alone.map(|h| h.t.to_bits()), got.map(|h| h.t.to_bits()));
                    let key = |h: Option<Hit>| h.map(|h| (h.point, h.ng, h.ns, h.material));
                    assert_eq!(key(alone), key(*got), "{ray:?}");
                    total += usize::from(alone.is_some());
                }
            }
            assert!(total > 3000, "{total} hits");
        }
    }

    /// A soup of opaque and see-through triangles, a ground quad and a
    /// see-through sphere under a square light: every shadow ray gives the
    /// same transmittance, bit for bit, traced alone or through its set's
    /// shaft (leaves and casters); and the shafts found clear let every
    /// ray through.
    #[test]
    fn shaft_gives_what_single_rays_give() {
        use crate::sampling::Rng;
        let world = soup_ground_and_sphere(Shape::Sphere {
            center: Vec3::new(0.5, 1.0, 0.0),
            radius: 0.4,
        });
        let transparency = [0.0, 0.5];
        let (mut set, mut r) = (ShaftSet::default(), Rng::new(37));
        let (mut blocked, mut partial, mut culled, mut clear) = (0, 0, 0, 0);
        for i in 0..400 {
            // Every fourth set starts far out, where its shaft passes above
            // the soup and beside the sphere.
            let far = if i % 4 == 0 { 14.0 } else { 4.0 };
            let p = Vec3::new(r.range(-far, far), 0.0, r.range(-far, far));
            let origin = offset_origin(p, math::reach(p, p), Vec3::Y, Vec3::Y);
            let light = Aabb::new(Vec3::new(-0.5, 4.0, -0.5), Vec3::new(0.5, 4.0, 0.5));
            let targets: Vec<Vec3> = (0..16)
                .map(|_| Vec3::new(r.range(-0.5, 0.5), 4.0, r.range(-0.5, 0.5)))
                .collect();
            let origins = Aabb::new(origin, origin);
            assert!(world.gather_shaft(origins, light, usize::MAX, &mut set));
            // Casters are numbered in object order without the mesh: the ground is bit 0.
            culled += usize::from(set.casters & 1 == 0);
            let is_clear = world.shaft_is_clear(&set);
            clear += usize::from(is_clear);
            for t in targets {
                let ray = Ray::new(origin, t - origin, 0.0);
                let range = (0.0, 1.0 - 1e-4);
                let alone = world.transmittance(&ray, range, &transparency, None);
                let within = world.transmittance(&ray, range, &transparency, Some(&set));
                assert_eq!(alone.map(f32::to_bits), within.map(f32::to_bits), "{ray:?}");
                // A clear shaft lets every segment through whole.
                assert!(!is_clear || alone == Some(1.0), "{ray:?}");
                blocked += usize::from(alone.is_none());
                partial += usize::from(alone.is_some_and(|t| t < 1.0));
            }
        }
        // Not vacuous: some rays are blocked, some dimmed by the sphere, and
        // the ground is culled from the sets that start on it (except near
        // the origin, where the offset is below the test's rounding margin);
        // some shafts are clear only because the sphere's box is outside them.
        assert!(
            blocked > 100 && partial > 10,
            "{blocked} blocked, {partial} dimmed"
        );
        assert!(culled > 380, "ground culled from {culled} of 400 sets");
        assert!(clear > 20 && clear < 100, "{clear} of 400 shafts clear");
    }
}
