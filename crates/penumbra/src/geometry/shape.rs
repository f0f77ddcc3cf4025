//! The shapes a scene is made of, and what every shape answers: its bounds,
//! where a ray meets it, its normals there, and its area.
//!
//! A closed set with one dispatch point (this file): the acceleration
//! structure asks a shape through these methods and never matches on the
//! kind itself. A triangle mesh is a shape too; its triangles are searched
//! by the acceleration structure, which tests them four at a time, so the
//! per-ray methods here answer for the analytic shapes and for one triangle
//! of a mesh.

use super::disk::intersect_disk;
use super::mesh::Mesh;
use super::quad::Quad;
use super::sphere::intersect_sphere;
use super::triangle::{intersect_triangle, RayShear};
use crate::math::{Aabb, Frame, Ray, Vec3};

/// A shape in its own space (world space for static objects).
#[derive(Clone, Debug)]
pub enum Shape {
    Sphere {
        center: Vec3,
        radius: f32,
    },
    /// A parallelogram (a rectangle for the scene format's `quad`).
    Quad(Quad),
    Disk {
        center: Vec3,
        frame: Frame,
        radius: f32,
    },
    /// A triangle mesh: the index of one of the scene's meshes.
    Mesh {
        mesh: u32,
    },
}

/// Where a ray meets a shape: the distance and the surface coordinates that
/// the normals are computed from (the barycentrics and triangle of a mesh,
/// the (s, t) of a quad; unused by spheres and disks).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ShapeHit {
    pub t: f32,
    pub b1: f32,
    pub b2: f32,
    /// The triangle of a mesh.
    pub inner: u32,
}

impl Shape {
    /// The box holding the shape (`meshes` resolves a mesh's index).
    pub fn bounds(&self, meshes: &[Mesh]) -> Aabb {
        match self {
            Shape::Sphere { center, radius } => Aabb::new(
                *center - Vec3::splat(*radius),
                *center + Vec3::splat(*radius),
            ),
            Shape::Quad(q) => Aabb::from_points([
                q.origin,
                q.point(1.0, 0.0),
                q.point(0.0, 1.0),
                q.point(1.0, 1.0),
            ]),
            Shape::Disk {
                center,
                frame,
                radius,
            } => {
                let e = Vec3::ONE - frame.n * frame.n;
                let r = *radius * Vec3::from_array(e.max(Vec3::ZERO).to_array().map(f32::sqrt));
                Aabb::new(*center - r, *center + r)
            }
            Shape::Mesh { mesh } => meshes[*mesh as usize].bounds(),
        }
    }

    /// The nearest point of an analytic shape along `ray` within
    /// (tmin, tmax). A mesh answers `None`: its triangles are searched by the
    /// acceleration structure ([`intersect_triangle_of`](Self::intersect_triangle_of)
    /// tests one of them).
    #[inline]
    pub fn intersect(&self, ray: &Ray, tmin: f32, tmax: f32) -> Option<ShapeHit> {
        let at = |t| ShapeHit {
            t,
            ..ShapeHit::default()
        };
        match self {
            Shape::Sphere { center, radius } => {
                intersect_sphere(ray, *center, *radius, tmin, tmax).map(at)
            }
            Shape::Quad(q) => q.intersect(ray, tmin, tmax).map(|(t, b1, b2)| ShapeHit {
                t,
                b1,
                b2,
                inner: 0,
            }),
            Shape::Disk {
                center,
                frame,
                radius,
            } => intersect_disk(ray, *center, frame.n, *radius, tmin, tmax).map(at),
            Shape::Mesh { .. } => None,
        }
    }

    /// Triangle `tri` of mesh `m` along `ray` within (tmin, tmax).
    #[inline]
    pub fn intersect_triangle_of(
        m: &Mesh,
        tri: u32,
        ray: &Ray,
        shear: &RayShear,
        tmin: f32,
        tmax: f32,
    ) -> Option<ShapeHit> {
        let [p0, p1, p2] = m.vertices(tri as usize);
        let (t, b1, b2) = intersect_triangle(ray, shear, p0, p1, p2, tmin, tmax)?;
        Some(ShapeHit {
            t,
            b1,
            b2,
            inner: tri,
        })
    }

    /// True if a segment can cross the shape twice (in and out): a sphere.
    #[inline]
    pub fn is_closed(&self) -> bool {
        matches!(self, Shape::Sphere { .. })
    }

    /// The plane of a flat analytic shape: its unit normal and a point of it.
    #[inline]
    pub fn plane(&self) -> Option<(Vec3, Vec3)> {
        match self {
            Shape::Quad(q) => Some((q.normal, q.origin)),
            Shape::Disk { center, frame, .. } => Some((frame.n, *center)),
            Shape::Sphere { .. } | Shape::Mesh { .. } => None,
        }
    }

    /// The geometric and shading normals at `p`, found by `hit` (unit; the
    /// geometric one as the shape defines it, not turned toward a ray).
    #[inline]
    pub fn normals(&self, meshes: &[Mesh], hit: &ShapeHit, p: Vec3) -> (Vec3, Vec3) {
        match self {
            Shape::Sphere { center, .. } => {
                let n = (p - *center).normalize_or_zero();
                (n, n)
            }
            Shape::Quad(q) => (q.normal, q.normal),
            Shape::Disk { frame, .. } => (frame.n, frame.n),
            Shape::Mesh { mesh } => {
                let m = &meshes[*mesh as usize];
                let [p0, p1, p2] = m.vertices(hit.inner as usize);
                let ng = (p1 - p0).cross(p2 - p0).normalize_or_zero();
                let ns = m
                    .shading_normal(hit.inner as usize, hit.b1, hit.b2)
                    .unwrap_or(ng);
                (ng, ns)
            }
        }
    }

    /// The surface area.
    pub fn area(&self, meshes: &[Mesh]) -> f32 {
        use std::f32::consts::PI;
        match self {
            Shape::Sphere { radius, .. } => 4.0 * PI * radius * radius,
            Shape::Quad(q) => q.area(),
            Shape::Disk { radius, .. } => PI * radius * radius,
            Shape::Mesh { mesh } => {
                let m = &meshes[*mesh as usize];
                (0..m.triangles.len())
                    .map(|i| {
                        let [a, b, c] = m.vertices(i);
                        0.5 * (b - a).cross(c - a).length()
                    })
                    .sum()
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every hit of an analytic shape lies inside its bounds, on its
    /// surface, and its normal is unit length.
    #[test]
    fn hits_lie_on_the_shape_inside_its_bounds() {
        use crate::sampling::Rng;
        let shapes = [
            Shape::Sphere {
                center: Vec3::new(0.2, 0.1, -0.3),
                radius: 0.7,
            },
            Shape::Quad(Quad::new(Vec3::splat(-0.5), Vec3::X, Vec3::Z)),
            Shape::Disk {
                center: Vec3::ZERO,
                frame: Frame::from_normal(Vec3::new(1.0, 2.0, 0.5).normalize()),
                radius: 0.8,
            },
        ];
        let mut r = Rng::new(5);
        for shape in &shapes {
            let b = shape.bounds(&[]);
            let grown = Aabb::new(b.min - Vec3::splat(1e-5), b.max + Vec3::splat(1e-5));
            let mut hits = 0;
            for _ in 0..2000 {
                let o = Vec3::new(r.range(-3.0, 3.0), r.range(-3.0, 3.0), r.range(-3.0, 3.0));
                let to = Vec3::new(r.range(-0.5, 0.5), r.range(-0.5, 0.5), r.range(-0.5, 0.5));
                let ray = Ray::new(o, to - o, 0.0);
                let Some(h) = shape.intersect(&ray, 0.0, f32::INFINITY) else {
                    continue;
                };
                hits += 1;
                let p = ray.at(h.t);
                assert!(
                    p.cmpge(grown.min).all() && p.cmple(grown.max).all(),
                    "{p:?} outside {b:?}"
                );
                let (ng, ns) = shape.normals(&[], &h, p);
                assert!((ng.length() - 1.0).abs() < 1e-4 && ns == ng);
            }
            assert!(hits > 200, "{hits} hits of {shape:?}");
        }
    }

    #[test]
    fn areas() {
        let q = Shape::Quad(Quad::new(Vec3::ZERO, 2.0 * Vec3::X, 3.0 * Vec3::Z));
        assert!((q.area(&[]) - 6.0).abs() < 1e-6);
        let s = Shape::Sphere {
            center: Vec3::ZERO,
            radius: 2.0,
        };
        assert!((s.area(&[]) - 16.0 * std::f32::consts::PI).abs() < 1e-4);
    }
}
