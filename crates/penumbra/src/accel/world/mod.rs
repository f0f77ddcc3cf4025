//! The scene's geometry in two levels of one kind of tree, a [`Bvh4`].
//!
//! The top level holds the scene's objects: spheres, quads, disks, moving
//! objects, and one item for the triangles of all static meshes. Those
//! triangles are baked into world space and copied, in leaf order, into a
//! [`TriangleBvh`] of their own (the fastest layout for rays: no
//! indirection per triangle, four triangles per SIMD test), which the top
//! level enters like an instance with the identity transform. A moving
//! object stays in its own space (a moving mesh with its own
//! [`TriangleBvh`]) and is intersected by transforming the ray to the
//! object at the ray's time; its top-level box bounds it over the whole
//! shutter interval. Every query, closest or any hit, one ray or a packet,
//! is the tree's one traversal step at both levels.
//!
//! Within a top-level leaf the objects come before the static triangles,
//! so that a ray that hits the ground in front of a mesh cuts its range
//! before entering the mesh's tree (which then often culls at its root).
//! A scene of at most four objects besides its static meshes (a ground and
//! a light) has a single top-level leaf.

use super::bvh4::ONE_PER_ITEM;
use super::{Bvh4, TriangleBvh};
use std::sync::Arc;

mod closest;
mod hits;
mod shadow;

pub use closest::PacketScratch;
pub use hits::{HitRef, Hits};
pub use shadow::{Crossing, ShaftSet};

use crate::geometry::instance::Placement;
use crate::geometry::motion::Motion;
use crate::geometry::quad::{Quad, Quad4};

use crate::geometry::{Mesh, Shape, ShapeHit, SurfaceInteraction};
use crate::math::{Aabb, Ray};
use crate::simd::{self, KernelSet, SimdError};

/// What a ray finds: the surface-interaction record of the nearest surface.
pub type Hit = SurfaceInteraction;

pub struct Object {
    pub shape: Shape,
    /// The object's BSDF (an index the world only passes on to its hits).
    pub material: u32,
    /// The emitter the object carries, if it emits.
    pub emitter: Option<u32>,
    /// Whether the object blocks shadow rays. A scene's lights are surfaces
    /// that do not (as the thesis's lights are seen but never in the way);
    /// everything else does.
    pub casts_shadows: bool,
    pub motion: Option<Motion>,
    /// The fixed transform of a shape of an instance (see
    /// [`instance`](crate::geometry::instance)): the shape is in its
    /// group's space. Never together with `motion`.
    pub placement: Option<Arc<Placement>>,
    /// The normals point the other way (`flip_normals`): into a sphere or
    /// cylinder, against a flat shape's or triangle's winding.
    pub flip_normals: bool,
    /// The mesh's triangles in its own space, for moving meshes and the
    /// meshes of instances (one tree shared by every instance of a group).
    pub mesh_bvh: Option<Arc<TriangleBvh>>,
}

impl Object {
    /// A still object of `shape` that casts shadows, does not emit and
    /// keeps its normals.
    pub fn new(shape: Shape, material: u32) -> Object {
        Object {
            shape,
            material,
            emitter: None,
            casts_shadows: true,
            motion: None,
            placement: None,
            flip_normals: false,
            mesh_bvh: None,
        }
    }

    /// True if the object is a static mesh in world space, whose triangles
    /// the world copies into its tree of static triangles.
    fn is_static_mesh(&self) -> bool {
        self.shape.as_mesh().is_some() && self.motion.is_none() && self.placement.is_none()
    }
}

/// What a top-level leaf holds.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Item {
    /// An object other than a static mesh, by index.
    Object(u32),
    /// Two to four static quads of one leaf, tested at once: an index into
    /// `World::quads`.
    Quads(u32),
    /// The triangles of the static meshes.
    Meshes,
}

/// Static quads of a top-level leaf, four lanes at once (a ground and a
/// light, the walls of a room), and their objects (`u32::MAX` in unused
/// lanes).
struct QuadPack {
    quads: Quad4,
    objects: [u32; 4],
}

pub struct World {
    pub objects: Vec<Object>,
    /// The scene's meshes, shared with the emitters of emitting ones.
    pub meshes: Arc<[Mesh]>,
    /// The top level; see the module docs.
    top: Bvh4<Item>,
    quads: Vec<QuadPack>,
    /// Triangles of the static meshes; a hit's id indexes `tri_refs`.
    tris: TriangleBvh,
    /// Object and triangle index of each triangle of `tris`.
    tri_refs: Vec<(u32, u32)>,
    /// Objects other than static meshes.
    others: usize,
    /// No object moves.
    is_static: bool,
    /// The instruction set every query runs its kernels with.
    kernels: KernelSet,
}

/// Intersection details kept while the search runs ([`ShapeHit`]
/// without its distance); turned into a [`Hit`] only once, for the closest
/// primitive.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
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
    pub fn new(objects: Vec<Object>, meshes: impl Into<Arc<[Mesh]>>) -> World {
        let meshes: Arc<[Mesh]> = meshes.into();
        let mut tri_refs = Vec::new();
        let mut tri_meshes = Vec::new();
        let mut items = Vec::new();
        let mut bounds = Vec::new();
        for (oi, o) in objects.iter().enumerate() {
            let object = oi as u32;
            match (o.shape.as_mesh(), o.motion) {
                (Some(mesh), None) if o.is_static_mesh() => {
                    let m = &meshes[mesh.mesh as usize];
                    tri_refs.extend((0..m.triangles.len() as u32).map(|tri| (object, tri)));
                    tri_meshes.resize(tri_refs.len(), mesh.mesh);
                }
                (_, motion) => {
                    let shape = &o.shape;
                    let b = match (&o.mesh_bvh, &o.placement) {
                        // An instance's mesh: the shared tree's box.
                        (Some(bvh), Some(_)) => bvh.bounds(),
                        _ => shape.bounds(&meshes),
                    };
                    items.push(Item::Object(object));
                    bounds.push(match (motion, &o.placement) {
                        (Some(m), _) => m.bounds(b),
                        (None, Some(pl)) => pl.bounds(b),
                        (None, None) => b,
                    });
                }
            }
        }
        let tris = TriangleBvh::build(tri_refs.len(), |i| {
            meshes[tri_meshes[i] as usize].vertices(tri_refs[i].1 as usize)
        });
        let others = items.len();
        if !tris.is_empty() {
            items.push(Item::Meshes);
            bounds.push(tris.bounds());
        }
        let mut quads = Vec::new();
        let top = Bvh4::build(&bounds, &ONE_PER_ITEM, |ids, out| {
            // The static quads of a leaf first (up to four at once), then
            // its other objects, then the triangles.
            let static_quad = |item: &Item| match *item {
                Item::Object(o) => {
                    let object = &objects[o as usize];
                    let still = object.motion.is_none() && object.placement.is_none();
                    let q = object.shape.as_quad().filter(|_| still)?;
                    Some((o, *q))
                }
                _ => None,
            };
            let leaf: Vec<Item> = ids.iter().map(|&i| items[i as usize]).collect();
            let (q, rest): (Vec<Item>, Vec<Item>) =
                leaf.iter().partition(|i| static_quad(i).is_some());
            let q: Vec<(u32, Quad)> = q.iter().filter_map(static_quad).collect();
            for chunk in q.chunks(4) {
                let (ids, q): (Vec<u32>, Vec<Quad>) = chunk.iter().copied().unzip();
                match Quad4::new(&q).filter(|_| q.len() >= 2) {
                    Some(quads4) => {
                        let mut objects = [u32::MAX; 4];
                        objects[..ids.len()].copy_from_slice(&ids);
                        out.push(Item::Quads(quads.len() as u32));
                        quads.push(QuadPack {
                            quads: quads4,
                            objects,
                        });
                    }
                    None => out.extend(ids.into_iter().map(Item::Object)),
                }
            }
            out.extend(rest.iter().filter(|&&i| i != Item::Meshes));
            out.extend(rest.iter().filter(|&&i| i == Item::Meshes));
        });
        let is_static = objects.iter().all(|o| o.motion.is_none());
        World {
            objects,
            meshes,
            top,
            quads,
            tris,
            tri_refs,
            others,
            is_static,
            kernels: simd::active(),
        }
    }

    /// The kernel set the queries run with: [`simd::active`] when the
    /// world was built.
    pub fn kernels(&self) -> KernelSet {
        self.kernels
    }

    /// Runs the queries with the kernel set `kernels` from now on.
    ///
    /// # Errors
    /// If this processor lacks the set (nothing changes then).
    pub fn set_kernels(&mut self, kernels: KernelSet) -> Result<(), SimdError> {
        self.kernels = kernels.require()?;
        Ok(())
    }

    pub fn bounds(&self) -> Aabb {
        self.top.bounds()
    }

    pub fn primitive_count(&self) -> usize {
        self.tri_refs.len() + self.others
    }

    /// True when no object moves (the camera may still).
    pub fn is_static(&self) -> bool {
        self.is_static
    }

    /// Intersects an object of the top level (a static triangle is found
    /// through the triangle tree instead).
    fn intersect_prim(
        &self,
        object: u32,
        ray: &Ray,
        tmin: f32,
        tmax: f32,
    ) -> Option<(f32, Candidate)> {
        let o = &self.objects[object as usize];
        match (o.motion, &o.placement) {
            (None, None) => self.intersect_shape(o, ray, tmin, tmax),
            (Some(m), _) => {
                let (local, _) = m.to_object(ray);
                self.intersect_shape(o, &local, tmin, tmax)
            }
            (None, Some(pl)) => self.intersect_shape(o, &pl.ray_to_object(ray), tmin, tmax),
        }
    }

    fn intersect_shape(
        &self,
        o: &Object,
        ray: &Ray,
        tmin: f32,
        tmax: f32,
    ) -> Option<(f32, Candidate)> {
        if o.shape.as_mesh().is_none() {
            return o.shape.intersect(ray, tmin, tmax).map(Candidate::of);
        }
        // A moving mesh or an instance's: its own tree, in its own space.
        let h = o.mesh_bvh.as_ref()?.closest_hit(ray, tmin, tmax)?;
        let cand = Candidate {
            b1: h.b1,
            b2: h.b2,
            inner: h.id,
        };
        Some((h.t, cand))
    }
}

/// Builds the tree of a mesh in its own space (moving meshes).
pub fn mesh_bvh(mesh: &Mesh) -> Arc<TriangleBvh> {
    Arc::new(TriangleBvh::build(mesh.triangles.len(), |i| {
        mesh.vertices(i)
    }))
}

#[cfg(test)]
pub(crate) mod tests {
    use super::shadow::one_side;
    use super::*;
    use crate::accel::bvh4::Frustum;
    use crate::geometry::{Disk, MeshShape, Sphere};
    use crate::math::Vec3;
    use crate::math::{self, offset_origin};
    use glam::Vec4;

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
    pub(crate) fn soup_ground_and_sphere(other: Shape) -> World {
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
            uvs: None,
            triangles,
        };
        let object = Object::new;
        let ground = Quad::new(Vec3::new(-5.0, 0.0, -5.0), Vec3::Z * 10.0, Vec3::X * 10.0);
        let objects = vec![
            object(Shape::MeshShape(MeshShape::new(0)), 0),
            object(Shape::Quad(ground), 0),
            object(other, 1),
        ];
        World::new(objects, vec![mesh])
    }

    /// The nearest hit over every object, one after the other, with the
    /// objects' own tests (a static mesh's triangles in world space, a moving
    /// object's in its space at the ray's time): the oracle of the tree.
    fn brute_nearest(w: &World, ray: &Ray) -> Option<(f32, u32)> {
        use crate::geometry::triangle::RayShear;
        let mut best: Option<(f32, u32)> = None;
        for (i, o) in w.objects.iter().enumerate() {
            let tmax = best.map_or(f32::INFINITY, |b| b.0);
            let local = match (o.motion, &o.placement) {
                (Some(m), _) => m.to_object(ray).0,
                (None, Some(pl)) => pl.ray_to_object(ray),
                (None, None) => *ray,
            };
            let t = match o.shape.as_mesh() {
                Some(mesh) => {
                    let m = &w.meshes[mesh.mesh as usize];
                    let shear = RayShear::new(&local);
                    let mut near = tmax;
                    for tri in 0..m.triangles.len() as u32 {
                        let hit =
                            mesh.intersect_triangle(&w.meshes, tri, &local, &shear, 0.0, near);
                        if let Some(h) = hit {
                            near = h.t;
                        }
                    }
                    (near < tmax).then_some(near)
                }
                None => o.shape.intersect(&local, 0.0, tmax).map(|h| h.t),
            };
            if let Some(t) = t {
                best = Some((t, i as u32));
            }
        }
        best
    }

    /// A scene of every kind of object: a static mesh, a moving mesh,
    /// sheared instances of a mesh sharing its tree, static and moving
    /// cylinders and spheres, quads (four of them packed together) and
    /// disks, over 300 objects so that the top level is a real tree. Each
    /// object has a material of its own, so a hit names its object.
    #[test]
    fn every_object_kind_matches_brute_force() {
        use crate::geometry::motion::{Motion, Similarity};
        use crate::geometry::quad::Quad;
        use crate::math::Frame;
        use crate::sampling::Rng;
        use glam::Quat;
        let mut r = Rng::new(53);
        let point =
            |r: &mut Rng| Vec3::new(r.range(-8.0, 8.0), r.range(-8.0, 8.0), r.range(-8.0, 8.0));
        let soup = |r: &mut Rng, n: u32, c: Vec3| {
            let positions = (0..3 * n)
                .map(|_| c + Vec3::new(r.range(-1.0, 1.0), r.range(-1.0, 1.0), r.range(-1.0, 1.0)))
                .collect();
            let triangles = (0..n).map(|i| [3 * i, 3 * i + 1, 3 * i + 2]).collect();
            Mesh {
                positions,
                normals: None,
                uvs: None,
                triangles,
            }
        };
        let meshes = vec![soup(&mut r, 400, Vec3::ZERO), soup(&mut r, 200, Vec3::ZERO)];
        let mut objects = Vec::new();
        let mut add = |shape, motion: Option<Motion>| {
            let material = objects.len() as u32;
            let mesh_bvh = match (Shape::as_mesh(&shape), motion) {
                (Some(mesh), Some(_)) => Some(mesh_bvh(&meshes[mesh.mesh as usize])),
                _ => None,
            };
            objects.push(Object {
                shape,
                material,
                emitter: None,
                casts_shadows: true,
                motion,
                placement: None,
                flip_normals: false,
                mesh_bvh,
            });
        };
        let slide = |r: &mut Rng| {
            let at = |t| Similarity {
                translation: t,
                ..Similarity::IDENTITY
            };
            let start = point(r);
            let end = Similarity {
                rotation: Quat::from_rotation_y(r.range(0.0, 1.0)),
                ..at(start + Vec3::new(r.range(-1.0, 1.0), 0.0, r.range(-1.0, 1.0)))
            };
            Some(Motion {
                start: at(start),
                end,
            })
        };
        add(Shape::MeshShape(MeshShape::new(0)), None);
        let m = slide(&mut r);
        add(Shape::MeshShape(MeshShape::new(1)), m);
        // Instances of the first mesh, sheared; cylinders, some moving.
        let shared = mesh_bvh(&meshes[0]);
        let mut placed = Vec::new();
        for _ in 0..40 {
            let mut m = glam::Mat4::from_translation(point(&mut r));
            m.y_axis.x = r.range(-0.5, 0.5);
            let mut o = Object::new(Shape::MeshShape(MeshShape::new(0)), 0);
            o.placement = Some(Arc::new(Placement::new(m).unwrap()));
            o.mesh_bvh = Some(Arc::clone(&shared));
            placed.push(o);
        }
        for i in 0..40 {
            let c = point(&mut r);
            let axis = Vec3::new(r.range(-1.0, 1.0), r.range(-1.0, 1.0), r.range(-1.0, 1.0));
            let cyl = crate::geometry::Cylinder::new(c, c + axis, r.range(0.1, 0.5)).unwrap();
            let m = if i % 2 == 0 { slide(&mut r) } else { None };
            add(Shape::Cylinder(cyl), m);
        }
        for i in 0..320 {
            let c = point(&mut r);
            match i % 4 {
                0 => add(Shape::Sphere(Sphere::new(c, r.range(0.1, 0.6))), None),
                1 => {
                    let m = slide(&mut r);
                    add(Shape::Sphere(Sphere::new(Vec3::ZERO, r.range(0.1, 0.6))), m)
                }
                2 => {
                    let (u, v) = (Vec3::X * r.range(0.2, 1.0), Vec3::Z * r.range(0.2, 1.0));
                    add(Shape::Quad(Quad::new(c, u, v)), None)
                }
                _ => {
                    let frame = Frame::from_normal(Vec3::new(0.3, 1.0, 0.2).normalize());
                    add(Shape::Disk(Disk::new(c, frame, r.range(0.1, 0.6))), None)
                }
            }
        }
        for mut o in placed {
            o.material = objects.len() as u32;
            objects.push(o);
        }
        let world = World::new(objects, meshes);
        assert!(world.top.single_leaf().is_none());
        assert!(!world.quads.is_empty(), "no quad packet was formed");
        let (mut hits, mut scratch, mut out) = (0, PacketScratch::default(), Hits::default());
        for _ in 0..4000 {
            let o = Vec3::new(
                r.range(-12.0, 12.0),
                r.range(-12.0, 12.0),
                r.range(-12.0, 12.0),
            );
            let ray = Ray::new(o, point(&mut r) - o, r.next_f32());
            let got = world.intersect(&ray, 0.0, f32::INFINITY);
            let want = brute_nearest(&world, &ray);
            let key = |h: Option<Hit>| h.map(|h| (h.t.to_bits(), h.material));
            assert_eq!(key(got), want.map(|(t, i)| (t.to_bits(), i)), "{ray:?}");
            // The same through a packet of one ray, and through any hit.
            world.intersect_all(&[ray], 0.0, &mut scratch, &mut out);
            assert_eq!(out.get(0), world.closest(&ray, 0.0, f32::INFINITY));
            assert_eq!(key(out.get(0).map(|h| world.surface(&ray, h))), key(got));
            let blocked = world.occluded(&ray, (0.0, f32::INFINITY));
            assert_eq!(blocked, got.is_some(), "{ray:?}");
            hits += usize::from(got.is_some());
        }
        assert!(hits > 1000 && hits < 3900, "{hits} hits");
    }

    /// Instancing against a second implementation: a group of a mesh, a
    /// cube, a sphere, a cylinder, a disk and a quad placed 60 times
    /// (shear and non-uniform scale on the meshes' placements, rotation,
    /// uniform scale and translation on the analytic shapes'), against the
    /// same scene flattened: every mesh copied into world space, every
    /// analytic shape moved there. Over many random rays the hits agree:
    /// the same object (by its material), distance, point, normals, surface
    /// coordinates and tangents, up to rounding; any hit agrees too; and
    /// flipped shapes turn their normals.
    #[test]
    fn instances_hit_what_their_flattened_copies_hit() {
        use crate::geometry::cube::cube;
        use crate::geometry::quad::Quad;
        use crate::geometry::Cylinder;
        use crate::math::{Frame, Mat4};
        use crate::sampling::Rng;
        use glam::Quat;
        let mut r = Rng::new(71);
        let soup = {
            let positions = (0..150)
                .map(|_| Vec3::new(r.range(-1.0, 1.0), r.range(-1.0, 1.0), r.range(-1.0, 1.0)))
                .collect();
            let uvs = Some(
                (0..150)
                    .map(|i| crate::math::Vec2::new(i as f32 / 150.0, 0.3))
                    .collect(),
            );
            let triangles = (0..50u32).map(|i| [3 * i, 3 * i + 1, 3 * i + 2]).collect();
            let mut m = Mesh {
                positions,
                normals: None,
                uvs,
                triangles,
            };
            m.compute_vertex_normals();
            m
        };
        // The group, in its own space: meshes 0 (soup) and 1 (cube).
        let group_meshes = vec![soup, cube()];
        let cyl = Cylinder::new(Vec3::new(0.0, -0.5, 0.0), Vec3::new(0.2, 0.6, 0.1), 0.3).unwrap();
        let disk_frame = Frame::from_normal(Vec3::new(0.3, 0.2, 1.0).normalize());
        let quad = Quad::new(
            Vec3::new(-0.5, -0.5, 0.8),
            Vec3::X,
            Vec3::new(0.0, 0.8, 0.3),
        );
        let group: Vec<(Shape, bool)> = vec![
            (Shape::MeshShape(MeshShape::new(0)), false),
            (Shape::MeshShape(MeshShape::new(1)), true),
            (
                Shape::Sphere(Sphere::new(Vec3::new(0.4, 0.1, -0.2), 0.35)),
                false,
            ),
            (Shape::Cylinder(cyl), true),
            (
                Shape::Disk(Disk::new(Vec3::new(-0.3, 0.4, 0.2), disk_frame, 0.4)),
                false,
            ),
            (Shape::Quad(quad), true),
        ];
        let k = group.len() as u32;
        let bvhs: Vec<Arc<TriangleBvh>> = group_meshes.iter().map(mesh_bvh).collect();
        let (mut inst, mut flat, mut flat_meshes) = (Vec::new(), Vec::new(), Vec::new());
        for i in 0..60u32 {
            let rot = Quat::from_axis_angle(
                Vec3::new(r.range(-1.0, 1.0), r.range(-1.0, 1.0), r.range(0.1, 1.0)).normalize(),
                r.range(0.0, 6.0),
            );
            let at = Vec3::new(r.range(-9.0, 9.0), r.range(-9.0, 9.0), r.range(-9.0, 9.0));
            let similar =
                Mat4::from_scale_rotation_translation(Vec3::splat(r.range(0.5, 1.5)), rot, at);
            let mut sheared = similar;
            sheared.y_axis += Vec4::new(r.range(-0.5, 0.5), 0.0, r.range(-0.5, 0.5), 0.0);
            sheared.x_axis *= r.range(0.6, 1.6);
            // Instance i is two instances: its meshes under the sheared
            // placement, its analytic shapes under the similar one.
            for (m, shapes) in [(sheared, 0..2), (similar, 2..group.len())] {
                let pl = Arc::new(Placement::new(m).unwrap());
                for j in shapes {
                    let (shape, flip) = &group[j];
                    let material = i * k + j as u32;
                    let mut o = Object::new(shape.clone(), material);
                    o.placement = Some(Arc::clone(&pl));
                    o.flip_normals = *flip;
                    if let Some(mesh) = shape.as_mesh() {
                        o.mesh_bvh = Some(Arc::clone(&bvhs[mesh.mesh as usize]));
                    }
                    inst.push(o);
                    // The flattened copy.
                    let scale = m.x_axis.truncate().length();
                    let world_shape = match shape.as_mesh() {
                        Some(mesh) => {
                            flat_meshes.push(group_meshes[mesh.mesh as usize].transformed(&m));
                            Shape::MeshShape(MeshShape::new(flat_meshes.len() as u32 - 1))
                        }
                        None => shape.transformed(&m, scale).expect("an analytic shape"),
                    };
                    let mut f = Object::new(world_shape, material);
                    f.flip_normals = *flip;
                    flat.push(f);
                }
            }
        }
        let inst = World::new(inst, group_meshes);
        let flat = World::new(flat, flat_meshes);
        let close = |a: Vec3, b: Vec3, scale: f32| (a - b).length() <= 2e-3 * scale.max(1.0);
        let (mut hits, mut flipped) = (0, 0);
        for _ in 0..6000 {
            let o = Vec3::new(
                r.range(-14.0, 14.0),
                r.range(-14.0, 14.0),
                r.range(-14.0, 14.0),
            );
            let to = Vec3::new(r.range(-9.0, 9.0), r.range(-9.0, 9.0), r.range(-9.0, 9.0));
            let ray = Ray::new(o, (to - o).normalize(), 0.0);
            let a = inst.intersect(&ray, 0.0, f32::INFINITY);
            let b = flat.intersect(&ray, 0.0, f32::INFINITY);
            let blocked = inst.occluded(&ray, (0.0, f32::INFINITY));
            assert_eq!(blocked, a.is_some(), "{ray:?}");
            let (Some(a), Some(b)) = (a, b) else {
                assert_eq!(a.is_some(), b.is_some(), "{ray:?}");
                continue;
            };
            // Grazing hits of two nearly equal surfaces may swap; they are rare.
            if a.material != b.material {
                assert!(
                    (a.t - b.t).abs() < 1e-3 * a.t,
                    "{ray:?}: {} vs {}",
                    a.t,
                    b.t
                );
                continue;
            }
            hits += 1;
            assert!(
                (a.t - b.t).abs() <= 1e-4 * a.t.max(1.0),
                "{ray:?}: t {} vs {}",
                a.t,
                b.t
            );
            assert!(close(a.p, b.p, a.t), "{ray:?}: {:?} vs {:?}", a.p, b.p);
            assert!(
                close(a.ng, b.ng, 1.0),
                "{ray:?}: ng {:?} vs {:?}",
                a.ng,
                b.ng
            );
            assert!(close(a.n, b.n, 1.0), "{ray:?}: n {:?} vs {:?}", a.n, b.n);
            let j = a.material % k;
            // A sphere in world space has no orientation: its coordinates
            // are about the world's axes, an instance's about its own.
            if group[j as usize].0.as_sphere().is_some() {
                continue;
            }
            let duv = (a.uv - b.uv).abs().max_element();
            // The seam of φ: 0 and 1 are one place.
            assert!(
                duv < 2e-3 || (duv - 1.0).abs() < 2e-3,
                "{ray:?}: uv {:?} vs {:?}",
                a.uv,
                b.uv
            );
            assert!(close(a.dpdu, b.dpdu, a.dpdu.length()), "{ray:?}");
            assert!(close(a.dpdv, b.dpdv, a.dpdv.length()), "{ray:?}");
            assert_eq!(a.prim, b.prim);
            if group[j as usize].1 {
                flipped += 1;
                // A flipped shape's normal is against its geometry's.
                let pl = inst.objects[a.object as usize]
                    .placement
                    .as_deref()
                    .unwrap();
                let local = pl.ray_to_object(&ray).at(a.t);
                let g = inst.objects[a.object as usize].shape.geometry(
                    &inst.meshes,
                    &ShapeHit {
                        t: a.t,
                        b1: 0.0,
                        b2: 0.0,
                        inner: a.prim,
                    },
                    local,
                );
                if inst.objects[a.object as usize].shape.as_mesh().is_none() {
                    assert!(pl.normal_to_world(g.ng).dot(a.ng) < -0.99, "{ray:?}");
                }
            }
        }
        assert!(
            hits > 1500 && flipped > 300,
            "{hits} hits, {flipped} on flipped shapes"
        );
    }

    /// Seven quads across one cube (identical boxes, so one leaf holds
    /// them all): packed four and three, every one is still found.
    #[test]
    fn a_leaf_of_many_quads_keeps_them_all() {
        use crate::geometry::quad::Quad;
        use crate::sampling::Rng;
        let v = Vec3::new;
        let quads = [
            (v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0), v(0.0, 1.0, 1.0)),
            (v(0.0, 0.0, 0.0), v(0.0, 1.0, 0.0), v(1.0, 0.0, 1.0)),
            (v(0.0, 0.0, 0.0), v(0.0, 0.0, 1.0), v(1.0, 1.0, 0.0)),
            (v(0.0, 1.0, 0.0), v(1.0, 0.0, 0.0), v(0.0, -1.0, 1.0)),
            (v(1.0, 0.0, 0.0), v(0.0, 1.0, 0.0), v(-1.0, 0.0, 1.0)),
            (v(0.0, 0.0, 1.0), v(0.0, 1.0, 0.0), v(1.0, 0.0, -1.0)),
            (v(0.0, 0.0, 1.0), v(1.0, 0.0, 0.0), v(0.0, 1.0, -1.0)),
        ];
        let objects = quads
            .iter()
            .enumerate()
            .map(|(i, &(o, a, b))| Object::new(Shape::Quad(Quad::new(o, a, b)), i as u32))
            .collect();
        let world = World::new(objects, Vec::new());
        assert_eq!(world.quads.len(), 2, "packs of 4 and 3");
        let (mut r, mut seen) = (Rng::new(59), [0; 7]);
        for _ in 0..3000 {
            let o = Vec3::new(r.range(-2.0, 3.0), r.range(-2.0, 3.0), r.range(-2.0, 3.0));
            let at = Vec3::new(r.range(0.0, 1.0), r.range(0.0, 1.0), r.range(0.0, 1.0));
            let ray = Ray::new(o, at - o, 0.0);
            let got = world.intersect(&ray, 0.0, f32::INFINITY);
            let want = brute_nearest(&world, &ray);
            let key = got.map(|h| (h.t.to_bits(), h.material));
            assert_eq!(key, want.map(|(t, i)| (t.to_bits(), i)), "{ray:?}");
            if let Some(h) = got {
                seen[h.material as usize] += 1;
            }
        }
        assert!(seen.iter().all(|&n| n > 50), "{seen:?}");
    }

    /// Batches that are not packets hit what each ray finds alone, bit for
    /// bit, with rays from inside the soup, from far away, grazing the
    /// ground and with non-finite parts; their records are those of
    /// single rays, and a batch of shadow rays is blocked where each alone
    /// is, also with the soup or an object passed by shadow rays (as a
    /// light is).
    #[test]
    fn incoherent_batches_hit_what_single_rays_hit() {
        use crate::sampling::Rng;
        let light = Quad::new(Vec3::new(-0.5, 4.0, -0.5), Vec3::X, Vec3::Z);
        let sphere = Shape::Sphere(Sphere::new(Vec3::new(0.5, 1.0, 0.0), 0.4));
        let (mut scratch, mut out, mut r) =
            (PacketScratch::default(), Hits::default(), Rng::new(47));
        let (mut records, mut blocked) = (Vec::new(), Vec::new());
        let mut light_soup = soup_ground_and_sphere(Shape::Quad(light));
        light_soup.objects[0].casts_shadows = false;
        let mut light_sphere = soup_ground_and_sphere(sphere.clone());
        light_sphere.objects[2].casts_shadows = false;
        for world in [
            soup_ground_and_sphere(Shape::Quad(light)),
            soup_ground_and_sphere(sphere),
            light_soup,
            light_sphere,
        ] {
            let mut hits = 0;
            for n in [1, 63, 300] {
                let mut rays: Vec<Ray> = (0..n)
                    .map(|_| {
                        let o =
                            Vec3::new(r.range(-3.0, 3.0), r.range(-0.5, 4.0), r.range(-3.0, 3.0));
                        let d =
                            Vec3::new(r.range(-1.0, 1.0), r.range(-1.0, 1.0), r.range(-1.0, 1.0));
                        Ray::new(o, d, 0.0)
                    })
                    .collect();
                if n == 300 {
                    rays[7] = Ray::new(Vec3::new(-9.0, 0.0, 0.3), Vec3::X, 0.0);
                    rays[8] = Ray::new(Vec3::new(f32::NAN, 1.0, 0.0), Vec3::X, 0.0);
                    rays[9] = Ray::new(
                        Vec3::new(0.0, 9.0, 0.0),
                        Vec3::new(0.0, f32::INFINITY, 0.0),
                        0.0,
                    );
                    rays[10] =
                        Ray::new(Vec3::new(0.0, 40.0, 0.0), Vec3::new(0.01, -1.0, 0.02), 0.0);
                }
                assert!(Frustum::packet(&rays).is_none() || n == 1);
                world.intersect_all(&rays, 1e-4, &mut scratch, &mut out);
                world.intersect_all_records(&rays, 1e-4, &mut scratch, &mut records);
                // Shadow rays to a point 3 units along.
                world.occluded_all(&rays, (1e-4, 3.0), &mut blocked);
                for (i, ray) in rays.iter().enumerate() {
                    let alone = world.closest(ray, 1e-4, f32::INFINITY);
                    assert_eq!(out.get(i), alone, "{n} rays, ray {i}: {ray:?}");
                    let t = |h: Option<Hit>| h.map(|h| (h.t.to_bits(), h.p, h.material));
                    assert_eq!(t(records[i]), t(world.intersect(ray, 1e-4, f32::INFINITY)));
                    assert_eq!(blocked[i], world.occluded(ray, (1e-4, 3.0)), "ray {i}");
                    hits += usize::from(alone.is_some());
                }
            }
            assert!(hits > 100, "{hits} hits");
            assert!(blocked.iter().any(|&b| b) && blocked.iter().any(|&b| !b));
        }
    }

    /// The camera rays of pixels, found together, hit what each finds
    /// alone: with the few objects as four quads at once (a second quad)
    /// and one by one (a sphere).
    #[test]
    fn packets_hit_what_single_rays_hit() {
        use crate::sampling::Rng;
        let light = Quad::new(Vec3::new(-0.5, 4.0, -0.5), Vec3::X, Vec3::Z);
        let sphere = Shape::Sphere(Sphere::new(Vec3::new(0.5, 1.0, 0.0), 0.4));
        let (mut scratch, mut out, mut r) =
            (PacketScratch::default(), Hits::default(), Rng::new(41));
        for world in [
            soup_ground_and_sphere(Shape::Quad(light)),
            soup_ground_and_sphere(sphere),
        ] {
            let (mut total, mut packets) = (0, 0);
            for _ in 0..500 {
                let eye = Vec3::new(r.range(-6.0, 6.0), r.range(0.5, 6.0), r.range(-6.0, 6.0));
                let at = Vec3::new(r.range(-2.0, 2.0), r.range(0.0, 3.0), r.range(-2.0, 2.0));
                let rays: Vec<Ray> = (0..16)
                    .map(|_| {
                        let jitter = Vec3::new(r.range(-1.0, 1.0), r.range(-1.0, 1.0), 0.0);
                        Ray::new(eye, at - eye + jitter * 0.01, 0.0)
                    })
                    .collect();
                packets += usize::from(Frustum::packet(&rays).is_some());
                world.intersect_all(&rays, 0.0, &mut scratch, &mut out);
                let (mut got, mut records) = (Vec::new(), Vec::new());
                world.surfaces(&rays, &out, &mut got);
                // The records made as the hits are found are the same.
                world.intersect_all_records(&rays, 0.0, &mut scratch, &mut records);
                let key = |h: Option<Hit>| h.map(|h| (h.p, h.ng, h.n, h.uv, h.dpdu, h.material));
                for (i, (ray, got)) in rays.iter().zip(&got).enumerate() {
                    let alone = world.intersect(ray, 0.0, f32::INFINITY);
                    assert_eq!(alone.map(|h| h.t.to_bits()), got.map(|h| h.t.to_bits()));
                    assert_eq!(out.distances()[i], got.map_or(f32::INFINITY, |h| h.t));
                    assert_eq!(out.get(i), world.closest(ray, 0.0, f32::INFINITY));
                    assert_eq!(key(records[i]), key(*got), "{ray:?}");
                    assert_eq!(key(alone), key(*got), "{ray:?}");
                    total += usize::from(alone.is_some());
                }
            }
            assert!(total > 3000, "{total} hits");
            assert!(packets > 450, "{packets} packets");
        }
    }

    /// A soup of opaque and see-through triangles, a ground quad and a
    /// see-through sphere under a square light: every shadow ray crosses
    /// the same surfaces in the same order (up to the first opaque one)
    /// traced alone or through its set's shaft (leaves and casters); and
    /// the shafts found clear hold no crossing.
    #[test]
    fn shaft_gives_what_single_rays_give() {
        use crate::sampling::Rng;
        let world =
            soup_ground_and_sphere(Shape::Sphere(Sphere::new(Vec3::new(0.5, 1.0, 0.0), 0.4)));
        // What a segment crosses, in order: (material, count) of each
        // surface, up to the first opaque one (material 0).
        fn crossed(
            world: &World,
            ray: &Ray,
            range: (f32, f32),
            shaft: Option<&ShaftSet>,
        ) -> Vec<(u32, i32)> {
            let mut out = Vec::new();
            world.crossings(ray, range, shaft, |c| {
                out.push((c.material(), c.count()));
                c.material() == 0
            });
            out
        }
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
            // The ground is object 1.
            culled += usize::from(!set.items.contains(&Item::Object(1)));
            let is_clear = world.shaft_is_clear(&set);
            clear += usize::from(is_clear);
            for t in targets {
                let ray = Ray::new(origin, t - origin, 0.0);
                let range = (0.0, 1.0 - 1e-4);
                let alone = crossed(&world, &ray, range, None);
                let within = crossed(&world, &ray, range, Some(&set));
                assert_eq!(alone, within, "{ray:?}");
                // A clear shaft lets every segment through whole.
                assert!(!is_clear || alone.is_empty(), "{ray:?}");
                blocked += usize::from(alone.iter().any(|c| c.0 == 0));
                partial += usize::from(!alone.is_empty() && alone.iter().all(|c| c.0 == 1));
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
