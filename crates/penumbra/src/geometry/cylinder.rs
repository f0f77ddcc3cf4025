//! The cylinder (Mitsuba 3's `cylinder`): an open tube of radius `radius`
//! around the segment from `p0` to `p1`, without caps.
//!
//! In its frame (`frame.n` along the axis, `frame.u` and `frame.v` across
//! it, [`Frame::from_normal`] of the axis as Mitsuba's `Frame3f`) a point
//! is `base + r cos φ · u + r sin φ · v + z · n` with `z` in `[0, length]`.
//! Its surface coordinates are Mitsuba's: `u = φ / 2π` (φ in [0, 2π) from
//! the frame's `u` axis), `v = z / length`; `dp/du = 2π (−y u + x v)`,
//! `dp/dv = length · n`; the geometric normal points out of the axis
//! (`dp/du × dp/dv`).
//!
//! | parameter | type | default | meaning |
//! |---|---|---|---|
//! | `p0` | point | `[0, 0, 0]` | centre of the first end |
//! | `p1` | point | `[0, 0, 1]` | centre of the second end, ≠ `p0` |
//! | `radius` | number > 0 | `1` | radius |
//! | `flip_normals` | boolean | `false` | normals point into the axis |

use std::f32::consts::TAU;

use super::interaction::LocalGeometry;
use super::mesh::Mesh;
use super::model::{placed_frame, MeshTable, ShapeHit, ShapeModel, ShapeSample};
use crate::math::{Aabb, Frame, Mat4, Ray, Vec2, Vec3};
use crate::sampling::points::unit_square;
use crate::sampling::{Discrete, Distribution};

/// An open cylinder in world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cylinder {
    /// Centre of the first end (`p0`).
    pub base: Vec3,
    /// `n` along the axis, from `p0` to `p1`.
    pub frame: Frame,
    pub radius: f32,
    /// `|p1 − p0|`.
    pub length: f32,
}

impl Cylinder {
    /// The cylinder around `p0`–`p1`; `None` when the ends coincide or the
    /// radius is not positive and finite.
    pub fn new(p0: Vec3, p1: Vec3, radius: f32) -> Option<Cylinder> {
        let d = p1 - p0;
        let length = d.length();
        let ok = length > 0.0 && length.is_finite() && radius > 0.0 && radius.is_finite();
        ok.then(|| Cylinder {
            base: p0,
            frame: Frame::from_normal(d / length),
            radius,
            length,
        })
    }

    /// The box around both end circles.
    pub fn bounds(&self) -> Aabb {
        let n = self.frame.n;
        let e = Vec3::ONE - n * n;
        let r = self.radius * Vec3::from_array(e.max(Vec3::ZERO).to_array().map(f32::sqrt));
        let top = self.base + self.length * n;
        Aabb::new(self.base.min(top) - r, self.base.max(top) + r)
    }

    /// The surface area `2π r · length`.
    pub fn area(&self) -> f32 {
        TAU * self.radius * self.length
    }

    /// The point of surface coordinates `(u, v)` and its outward normal.
    pub fn point(&self, u: f32, v: f32) -> (Vec3, Vec3) {
        let (s, c) = (TAU * u).sin_cos();
        let out = c * self.frame.u + s * self.frame.v;
        (
            self.base + self.radius * out + v * self.length * self.frame.n,
            out,
        )
    }

    /// The nearest crossing of the tube within (tmin, tmax) whose point lies
    /// between the ends: the quadratic of the distance to the axis, solved
    /// in double precision in the cylinder's frame.
    pub fn intersect(&self, ray: &Ray, tmin: f32, tmax: f32) -> Option<f32> {
        let f = &self.frame;
        let o = ray.origin - self.base;
        let local = |w: Vec3| [f.u.dot(w), f.v.dot(w), f.n.dot(w)].map(f64::from);
        let ([ox, oy, oz], [dx, dy, dz]) = (local(o), local(ray.dir));
        let r = f64::from(self.radius);
        let a = dx * dx + dy * dy;
        if a == 0.0 {
            return None;
        }
        let b = 2.0 * (dx * ox + dy * oy);
        let c = ox * ox + oy * oy - r * r;
        let disc = b * b - 4.0 * a * c;
        if disc < 0.0 {
            return None;
        }
        // The stable pair of roots.
        let q = -0.5 * (b + disc.sqrt().copysign(b));
        let (mut t0, mut t1) = (q / a, if q != 0.0 { c / q } else { -q / a });
        if t0 > t1 {
            std::mem::swap(&mut t0, &mut t1);
        }
        let len = f64::from(self.length);
        [t0, t1].into_iter().find_map(|t| {
            let z = oz + t * dz;
            let t = t as f32;
            (t > tmin && t < tmax && (0.0..=len).contains(&z)).then_some(t)
        })
    }

    /// The cylinder's geometry at offset `d` from `base` (normals outward).
    pub fn geometry(&self, d: Vec3) -> LocalGeometry {
        let f = &self.frame;
        let (x, y, z) = (d.dot(f.u), d.dot(f.v), d.dot(f.n));
        let rxy = (x * x + y * y).sqrt();
        let (cos_phi, sin_phi) = if rxy > 0.0 {
            (x / rxy, y / rxy)
        } else {
            (1.0, 0.0)
        };
        let n = cos_phi * f.u + sin_phi * f.v;
        let phi = {
            let a = sin_phi.atan2(cos_phi);
            if a < 0.0 {
                a + TAU
            } else {
                a
            }
        };
        let r = self.radius;
        LocalGeometry {
            ng: n,
            ns: n,
            uv: Vec2::new(phi / TAU, z / self.length),
            dpdu: TAU * r * (cos_phi * f.v - sin_phi * f.u),
            dpdv: self.length * f.n,
        }
    }
}

impl ShapeModel for Cylinder {
    const NAME: &'static str = "cylinder";

    fn bounds(&self, _meshes: &[Mesh]) -> Aabb {
        Cylinder::bounds(self)
    }

    #[inline]
    fn intersect(&self, ray: &Ray, tmin: f32, tmax: f32) -> Option<ShapeHit> {
        Cylinder::intersect(self, ray, tmin, tmax).map(ShapeHit::at)
    }

    #[inline]
    fn geometry(&self, _meshes: &[Mesh], _hit: &ShapeHit, p: Vec3) -> LocalGeometry {
        Cylinder::geometry(self, p - self.base)
    }

    fn area(&self, _meshes: &[Mesh]) -> f32 {
        Cylinder::area(self)
    }

    #[inline]
    fn is_closed(&self) -> bool {
        true
    }

    fn center(&self, _meshes: &[Mesh]) -> Vec3 {
        self.base + 0.5 * self.length * self.frame.n
    }

    /// Those across its axis (whichever way it faces).
    fn normal_cone(
        &self,
        _meshes: &[Mesh],
        _triangles: Option<&Discrete>,
        _flip: bool,
    ) -> (Vec3, f32) {
        (self.frame.n, 0.0)
    }

    fn transformed(&self, m: &Mat4, scale: f32) -> Option<Cylinder> {
        Some(Cylinder {
            base: m.transform_point3(self.base),
            frame: placed_frame(m, &self.frame),
            radius: self.radius * scale,
            length: self.length * scale,
        })
    }

    #[inline(always)]
    fn sample(
        &self,
        _meshes: &[Mesh],
        _mesh: MeshTable,
        _from: Vec3,
        point: Vec3,
        d: Distribution,
    ) -> Option<ShapeSample> {
        let u = unit_square(point, d);
        let (p, n) = self.point(u.x, u.y);
        Some(ShapeSample::on_area(p, n, Cylinder::area(self)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    /// The cylinder of radius 2 along +z from z = 1 to z = 4: a ray toward
    /// the axis along −x meets it at x = 2, with the normal +x and the
    /// coordinates (0, (z − 1) / 3); from inside, at the far wall.
    #[test]
    fn hits_and_normals_of_an_axis_aligned_tube() {
        let c = Cylinder::new(Vec3::new(0.0, 0.0, 1.0), Vec3::new(0.0, 0.0, 4.0), 2.0).unwrap();
        assert_eq!(c.frame.u, Vec3::X, "Mitsuba's frame of +z");
        let ray = Ray::new(Vec3::new(5.0, 0.0, 2.5), -Vec3::X, 0.0);
        let t = c.intersect(&ray, 0.0, f32::INFINITY).unwrap();
        assert!((t - 3.0).abs() < 1e-6, "{t}");
        let g = c.geometry(ray.at(t) - c.base);
        assert!((g.ng - Vec3::X).length() < 1e-6);
        assert!((g.uv - Vec2::new(0.0, 0.5)).length() < 1e-6, "{:?}", g.uv);
        assert!(
            g.dpdu.cross(g.dpdv).dot(g.ng) > 0.0,
            "dp/du × dp/dv points out"
        );
        // From inside: the wall at x = −2, normal still +x outward there (−x).
        let inside = Ray::new(Vec3::new(0.0, 0.0, 2.5), -Vec3::X, 0.0);
        let t = c.intersect(&inside, 0.0, f32::INFINITY).unwrap();
        assert!((t - 2.0).abs() < 1e-6);
        let g = c.geometry(inside.at(t) - c.base);
        assert!((g.ng + Vec3::X).length() < 1e-6);
        assert!((g.uv.x - 0.5).abs() < 1e-6);
        // Beyond the ends, along the axis, and out of range: no hit.
        let above = Ray::new(Vec3::new(5.0, 0.0, 4.5), -Vec3::X, 0.0);
        assert_eq!(c.intersect(&above, 0.0, f32::INFINITY), None);
        let along = Ray::new(Vec3::new(0.0, 0.0, -3.0), Vec3::Z, 0.0);
        assert_eq!(c.intersect(&along, 0.0, f32::INFINITY), None);
        assert_eq!(c.intersect(&ray, 0.0, 2.9), None);
        // Through the open end: the inside of the far wall.
        let slant = Ray::new(Vec3::new(0.0, 0.0, 6.0), Vec3::new(1.0, 0.0, -1.0), 0.0);
        let t = c.intersect(&slant, 0.0, f32::INFINITY).unwrap();
        assert!((slant.at(t) - Vec3::new(2.0, 0.0, 4.0)).length() < 1e-5);
    }

    /// Random rays against a slanted tube: every hit lies on the surface at
    /// distance `radius` from the axis between the ends, inside the bounds,
    /// and the coordinates give the point back.
    #[test]
    fn random_hits_lie_on_the_surface() {
        let c = Cylinder::new(Vec3::new(0.3, -0.2, 0.1), Vec3::new(-0.5, 1.0, 0.7), 0.6).unwrap();
        let b = c.bounds();
        let mut r = Rng::new(11);
        let mut hits = 0;
        for _ in 0..4000 {
            let o = Vec3::new(r.range(-3.0, 3.0), r.range(-3.0, 3.0), r.range(-3.0, 3.0));
            let to = Vec3::new(r.range(-1.0, 1.0), r.range(-1.0, 1.0), r.range(-1.0, 1.0));
            let ray = Ray::new(o, to - o, 0.0);
            let Some(t) = c.intersect(&ray, 0.0, f32::INFINITY) else {
                continue;
            };
            hits += 1;
            let p = ray.at(t);
            let d = p - c.base;
            let z = d.dot(c.frame.n);
            let radial = (d - z * c.frame.n).length();
            assert!((radial - c.radius).abs() < 1e-4, "{radial}");
            assert!(z > -1e-4 && z < c.length + 1e-4, "{z}");
            let slack = Vec3::splat(1e-4);
            assert!(p.cmpge(b.min - slack).all() && p.cmple(b.max + slack).all());
            let g = c.geometry(d);
            let (q, n) = c.point(g.uv.x, g.uv.y);
            assert!((q - p).length() < 1e-4 && (n - g.ng).length() < 1e-4);
        }
        assert!(hits > 500, "{hits}");
    }

    #[test]
    fn degenerate_cylinders_are_refused() {
        assert!(Cylinder::new(Vec3::ONE, Vec3::ONE, 1.0).is_none());
        assert!(Cylinder::new(Vec3::ZERO, Vec3::Z, 0.0).is_none());
        assert!(Cylinder::new(Vec3::ZERO, Vec3::Z, f32::NAN).is_none());
        let c = Cylinder::new(Vec3::ZERO, Vec3::Z * 2.0, 0.5).unwrap();
        assert!((c.area() - TAU).abs() < 1e-5);
    }

    /// A tube's centre is the middle of its axis; carried by a similarity
    /// of scale 2 it is twice as long and wide around the carried axis.
    #[test]
    fn centre_and_similar_tubes() {
        let c = Cylinder::new(Vec3::ZERO, Vec3::new(0.0, 2.0, 0.0), 0.5).unwrap();
        assert_eq!(ShapeModel::center(&c, &[]), Vec3::Y);
        let m = Mat4::from_scale_rotation_translation(
            Vec3::splat(2.0),
            glam::Quat::from_rotation_z(0.3),
            Vec3::X,
        );
        let t = c.transformed(&m, 2.0).unwrap();
        assert_eq!((t.radius, t.length), (1.0, 4.0));
        let top = m.transform_point3(Vec3::new(0.0, 2.0, 0.0));
        assert!((t.base + t.length * t.frame.n - top).length() < 1e-5);
        assert!(c.is_closed() && c.projected_area(Vec3::Y).is_none());
    }
}
