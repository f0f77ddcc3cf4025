//! The shapes a scene is made of, and what every shape answers: its bounds,
//! where a ray meets it, its normals there, and its area.
//!
//! A closed set with one dispatch point (this file): the acceleration
//! structure asks a shape through these methods and never matches on the
//! kind itself. A triangle mesh is a shape too; its triangles are searched
//! by the acceleration structure, which tests them four at a time, so the
//! per-ray methods here answer for the analytic shapes and for one triangle
//! of a mesh.

use std::f32::consts::{PI, TAU};

use super::cylinder::Cylinder;
use super::disk::intersect_disk;
use super::interaction::LocalGeometry;
use super::mesh::Mesh;
use super::quad::Quad;
use super::sphere::intersect_sphere;
use super::triangle::{intersect_triangle, RayShear};
use crate::math::{Aabb, Frame, Ray, Vec2, Vec3};

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
    /// An open tube (Mitsuba's `cylinder`).
    Cylinder(Cylinder),
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
            Shape::Cylinder(c) => c.bounds(),
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
            Shape::Cylinder(c) => c.intersect(ray, tmin, tmax).map(at),
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

    /// What messages call the shape.
    pub fn name(&self) -> &'static str {
        match self {
            Shape::Sphere { .. } => "sphere",
            Shape::Quad(_) => "quad",
            Shape::Disk { .. } => "disk",
            Shape::Cylinder(_) => "cylinder",
            Shape::Mesh { .. } => "mesh",
        }
    }

    /// True if a segment can cross the shape twice (in and out): a sphere
    /// or a cylinder.
    #[inline]
    pub fn is_closed(&self) -> bool {
        matches!(self, Shape::Sphere { .. } | Shape::Cylinder(_))
    }

    /// The plane of a flat analytic shape: its unit normal and a point of it.
    #[inline]
    pub fn plane(&self) -> Option<(Vec3, Vec3)> {
        match self {
            Shape::Quad(q) => Some((q.normal, q.origin)),
            Shape::Disk { center, frame, .. } => Some((frame.n, *center)),
            Shape::Sphere { .. } | Shape::Cylinder(_) | Shape::Mesh { .. } => None,
        }
    }

    /// The geometric and shading normals at `p`, found by `hit` (unit; the
    /// geometric one as the shape defines it, not turned toward a ray).
    #[inline]
    pub fn normals(&self, meshes: &[Mesh], hit: &ShapeHit, p: Vec3) -> (Vec3, Vec3) {
        let g = self.geometry(meshes, hit, p);
        (g.ng, g.ns)
    }

    /// The shape's part of the surface-interaction record at `p`, found by
    /// `hit`: normals, surface coordinates and their derivatives, as the
    /// [interaction module](super::interaction) defines them.
    #[inline]
    pub fn geometry(&self, meshes: &[Mesh], hit: &ShapeHit, p: Vec3) -> LocalGeometry {
        match self {
            Shape::Sphere { center, .. } => sphere_geometry(p - *center),
            Shape::Quad(q) => LocalGeometry {
                ng: q.normal,
                ns: q.normal,
                uv: Vec2::new(hit.b1, hit.b2),
                dpdu: q.edge_u,
                dpdv: q.edge_v,
            },
            Shape::Disk {
                center,
                frame,
                radius,
            } => disk_geometry(p - *center, frame, *radius),
            Shape::Cylinder(c) => c.geometry(p - c.base),
            Shape::Mesh { mesh } => {
                let m = &meshes[*mesh as usize];
                let tri = hit.inner as usize;
                let corners = m.vertices(tri);
                let [p0, p1, p2] = corners;
                let ng = (p1 - p0).cross(p2 - p0).normalize_or_zero();
                let ns = m.shading_normal(tri, hit.b1, hit.b2).unwrap_or(ng);
                let (uv, (dpdu, dpdv)) = match m.triangle_uvs(tri) {
                    Some(uvs) => {
                        let b0 = 1.0 - hit.b1 - hit.b2;
                        let uv = b0 * uvs[0] + hit.b1 * uvs[1] + hit.b2 * uvs[2];
                        (uv, triangle_derivatives(corners, uvs))
                    }
                    None => (Vec2::new(hit.b1, hit.b2), (p1 - p0, p2 - p0)),
                };
                LocalGeometry {
                    ng,
                    ns,
                    uv,
                    dpdu,
                    dpdv,
                }
            }
        }
    }

    /// The surface area.
    pub fn area(&self, meshes: &[Mesh]) -> f32 {
        match self {
            Shape::Sphere { radius, .. } => 4.0 * PI * radius * radius,
            Shape::Quad(q) => q.area(),
            Shape::Disk { radius, .. } => PI * radius * radius,
            Shape::Cylinder(c) => c.area(),
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

/// The angle of `(x, y)` about the origin from +x, in [0, 2π).
#[inline]
fn angle(x: f32, y: f32) -> f32 {
    let phi = y.atan2(x);
    if phi < 0.0 {
        phi + TAU
    } else {
        phi
    }
}

/// A sphere's geometry at offset `d` from its centre (Mitsuba's
/// parameterisation: poles on the z axis).
fn sphere_geometry(d: Vec3) -> LocalGeometry {
    let n = d.normalize_or_zero();
    let rxy = (d.x * d.x + d.y * d.y).sqrt();
    let (cos_phi, sin_phi) = if rxy > 0.0 {
        (d.x / rxy, d.y / rxy)
    } else {
        (1.0, 0.0)
    };
    LocalGeometry {
        ng: n,
        ns: n,
        uv: Vec2::new(angle(d.x, d.y) / TAU, n.z.clamp(-1.0, 1.0).acos() / PI),
        dpdu: TAU * Vec3::new(-d.y, d.x, 0.0),
        dpdv: PI * Vec3::new(d.z * cos_phi, d.z * sin_phi, -rxy),
    }
}

/// A disk's geometry at offset `d` from its centre.
fn disk_geometry(d: Vec3, frame: &Frame, radius: f32) -> LocalGeometry {
    let (x, y) = (d.dot(frame.u), d.dot(frame.v));
    let r = (x * x + y * y).sqrt();
    let (cos_phi, sin_phi) = if r > 0.0 { (x / r, y / r) } else { (1.0, 0.0) };
    LocalGeometry {
        ng: frame.n,
        ns: frame.n,
        uv: Vec2::new(r / radius, angle(x, y) / TAU),
        dpdu: radius * (cos_phi * frame.u + sin_phi * frame.v),
        dpdv: TAU * r * (cos_phi * frame.v - sin_phi * frame.u),
    }
}

/// `dp/du` and `dp/dv` of the triangle `p` with texture coordinates `uv`
/// (pbrt's solution of the 2×2 system); the edges when the coordinates are
/// degenerate.
fn triangle_derivatives(p: [Vec3; 3], uv: [Vec2; 3]) -> (Vec3, Vec3) {
    let (d1, d2) = (uv[1] - uv[0], uv[2] - uv[0]);
    let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
    let det = d1.x * d2.y - d1.y * d2.x;
    if det.abs() < 1e-12 || !det.is_finite() {
        return (e1, e2);
    }
    let inv = 1.0 / det;
    ((d2.y * e1 - d1.y * e2) * inv, (d1.x * e2 - d2.x * e1) * inv)
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

    /// The surface coordinates' derivatives are tangent and agree with the
    /// coordinates: a small step along `dp/du` (or `dp/dv`), put back on
    /// the surface, changes `(u, v)` by that step in `u` (or `v`) alone
    /// (a finite difference), on a sphere, a disk and a cylinder.
    #[test]
    fn derivatives_agree_with_the_coordinates() {
        use crate::sampling::Rng;
        let frame = Frame::from_normal(Vec3::new(0.3, 1.0, -0.4).normalize());
        let (c, r) = (Vec3::new(0.5, -0.2, 0.1), 0.8);
        let tube = super::super::cylinder::Cylinder::new(c, c + 1.5 * frame.n, r).unwrap();
        let shapes = [
            Shape::Sphere {
                center: c,
                radius: r,
            },
            Shape::Disk {
                center: c,
                frame,
                radius: r,
            },
            Shape::Cylinder(tube),
        ];
        // The point of the surface nearest to `p`, and its coordinates.
        let project = |s: &Shape, p: Vec3| match s {
            Shape::Sphere { .. } => c + r * (p - c).normalize(),
            Shape::Cylinder(t) => {
                let along = t.frame.n * (p - t.base).dot(t.frame.n);
                t.base + along + r * (p - t.base - along).normalize()
            }
            _ => p - frame.n * (p - c).dot(frame.n),
        };
        let mut rng = Rng::new(3);
        let mut checked = 0;
        for s in &shapes {
            for _ in 0..500 {
                let dir = Vec3::new(
                    rng.range(-1.0, 1.0),
                    rng.range(-1.0, 1.0),
                    rng.range(-1.0, 1.0),
                );
                let p = match s {
                    Shape::Sphere { .. } => c + r * dir.normalize(),
                    Shape::Cylinder(t) => {
                        project(s, t.base + t.frame.n * (0.75 + 0.7 * dir.z) + dir)
                    }
                    _ => project(s, c + 0.9 * r * dir.clamp_length_max(1.0)),
                };
                let g = s.geometry(&[], &ShapeHit::default(), p);
                // Away from the sphere's poles and seam, the disk's centre and seam.
                if g.uv.x < 0.05 || g.uv.x > 0.95 || g.uv.y < 0.05 || g.uv.y > 0.95 {
                    continue;
                }
                let h = 1e-3;
                for (d, step) in [(g.dpdu, Vec2::new(h, 0.0)), (g.dpdv, Vec2::new(0.0, h))] {
                    assert!(d.dot(g.ng).abs() < 1e-4 * d.length(), "{s:?}: not tangent");
                    let q = project(s, p + h * d);
                    let moved = s.geometry(&[], &ShapeHit::default(), q).uv - g.uv;
                    assert!(
                        (moved - step).abs().max_element() < 2e-4,
                        "{s:?} at {:?}: {moved:?} for {step:?}",
                        g.uv
                    );
                }
                checked += 1;
            }
        }
        assert!(checked > 600, "{checked} points checked");
        // A quad's coordinates are the hit's (s, t), its derivatives its edges.
        let q = Quad::new(Vec3::ZERO, 2.0 * Vec3::X, 3.0 * Vec3::Z);
        let hit = ShapeHit {
            t: 1.0,
            b1: 0.25,
            b2: 0.5,
            inner: 0,
        };
        let g = Shape::Quad(q).geometry(&[], &hit, q.point(0.25, 0.5));
        assert_eq!(
            (g.uv, g.dpdu, g.dpdv),
            (Vec2::new(0.25, 0.5), q.edge_u, q.edge_v)
        );
    }

    /// A triangle's derivatives map texture-coordinate steps onto the
    /// triangle: `p(uv) = p0 + dpdu (u − u0) + dpdv (v − v0)` at every corner.
    #[test]
    fn triangle_derivatives_map_texture_coordinates() {
        let p = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(2.0, 0.0, 1.0),
            Vec3::new(0.5, 3.0, 0.0),
        ];
        let uv = [
            Vec2::new(0.1, 0.2),
            Vec2::new(0.9, 0.3),
            Vec2::new(0.2, 0.8),
        ];
        let (dpdu, dpdv) = triangle_derivatives(p, uv);
        for k in 0..3 {
            let d = uv[k] - uv[0];
            let q = p[0] + dpdu * d.x + dpdv * d.y;
            assert!((q - p[k]).length() < 1e-5, "corner {k}: {q:?}");
        }
        // Degenerate coordinates fall back to the edges.
        let (a, b) = triangle_derivatives(p, [Vec2::ZERO; 3]);
        assert_eq!((a, b), (p[1] - p[0], p[2] - p[0]));
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
